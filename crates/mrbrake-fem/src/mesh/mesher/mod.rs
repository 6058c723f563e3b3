//! In-process quality mesher for axisymmetric (r, z) cross-sections.
//!
//! Brief overview: describe the geometry as a [`Pslg`] (vertices, segments with optional physical
//! tags, one [`RegionSeed`] per region), choose a [`SizeField`] (global maximum edge length,
//! per-region targets, growth rate) and [`MeshOptions`] (angle limit, budgets), and call
//! [`triangulate`] to get a [`crate::mesh::Mesh`]: counter-clockwise triangles tagged by region and
//! the edges lying on tagged segments.
//!
//! The triangulation is spade's constrained Delaunay triangulation with Ruppert/Chew refinement
//! (minimum angle, default 28°); grading comes from subdividing the input segments at the local
//! size and from centroid insertion in triangles larger than the size field, each pass followed by a
//! quality refinement. No external mesher is needed.
//!
//! ```
//! use mrbrake_fem::mesh::mesher::{triangulate, MeshOptions, Pslg, SizeField};
//! let mut g = Pslg::new();
//! g.add_rectangle(0.0, 0.01, 0.0, 0.01).unwrap();
//! g.add_rectangle(0.01, 0.0105, 0.0, 0.01).unwrap(); // a 0.5 mm gap beside a 10 mm square
//! g.add_seed([0.005, 0.005], 1);
//! g.add_seed([0.01025, 0.005], 2);
//! let size = SizeField::uniform(0.002).with_region(2, 0.000125);
//! let mesh = triangulate(&g, &size, &MeshOptions::default()).unwrap();
//! assert!(mesh.triangle_tags.iter().any(|&t| t == 2));
//! ```

mod pslg;
pub mod quality;
mod size_field;
mod triangulate;

pub use pslg::{NormalizedPslg, Pslg, RegionSeed, Segment};
pub use size_field::SizeField;
pub use triangulate::{MeshOptions, triangulate};

#[cfg(test)]
mod tests;
