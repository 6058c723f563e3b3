//! Mesher benchmark: a brake-like cross-section (steel, a 0.5 mm gap, a coil, air) meshed to about
//! 100 000 nodes with a graded size field.

use criterion::{Criterion, criterion_group, criterion_main};
use mrbrake_fem::mesh::mesher::{MeshOptions, Pslg, SizeField, triangulate};

fn geometry() -> Pslg {
    let mut g = Pslg::new();
    g.add_rectangle(0.0, 0.06, 0.0, 0.08).unwrap();
    g.add_rectangle(0.018, 0.025, 0.02, 0.05).unwrap();
    g.add_rectangle(0.025, 0.0255, 0.02, 0.03).unwrap();
    g.add_rectangle(0.0255, 0.04, 0.02, 0.03).unwrap();
    g.add_rectangle(0.026, 0.036, 0.031, 0.045).unwrap();
    g.add_segment([0.0, 0.0], [0.0, 0.08], Some(1)).unwrap();
    g.add_seed([0.02, 0.04], 1);
    g.add_seed([0.02525, 0.025], 2);
    g.add_seed([0.03, 0.025], 3);
    g.add_seed([0.03, 0.04], 4);
    g.add_seed([0.05, 0.07], 5);
    g
}

fn bench(c: &mut Criterion) {
    let g = geometry();
    // Uniform 0.3 mm plus a 0.0625 mm gap target gives about 100k nodes.
    let size = SizeField::uniform(0.3e-3).with_region(2, 0.0625e-3);
    let mesh = triangulate(&g, &size, &MeshOptions::default()).unwrap();
    eprintln!("mesher bench: {} nodes, {} triangles", mesh.nodes.len(), mesh.triangles.len());
    let mut group = c.benchmark_group("mesher");
    group.sample_size(10);
    group.bench_function("brake_section_100k_nodes", |b| {
        b.iter(|| triangulate(&g, &size, &MeshOptions::default()).unwrap())
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
