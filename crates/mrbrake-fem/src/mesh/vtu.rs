//! VTK XML unstructured-grid (.vtu) text for ParaView: the (r, z) mesh as points `(r, z, 0)`,
//! triangles as VTK cell type 5, plus named point and cell fields (scalars or vectors).
//!
//! The format is ASCII "UnstructuredGrid" version 0.1 (VTK User's Guide, "VTK XML file formats").
//! This module only builds the text; callers write it (atomically) where they want.

use std::fmt::Write;

use crate::mesh::Mesh;

/// A named field: `components` values per point (or cell), 1 for scalars, 3 for vectors.
#[derive(Debug, Clone, Copy)]
pub struct Field<'a> {
    /// Name shown in ParaView.
    pub name: &'a str,
    /// Values per point or cell (1 or 3).
    pub components: usize,
    /// `components × count` values.
    pub values: &'a [f64],
}

/// Builds the .vtu text. Cell field `region` (the triangle tags) is always included.
pub fn to_vtu(mesh: &Mesh, point_fields: &[Field<'_>], cell_fields: &[Field<'_>]) -> String {
    let n_points = mesh.nodes.len();
    let n_cells = mesh.triangles.len();
    let mut s = String::with_capacity(64 * (n_points + n_cells));
    s.push_str("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n<UnstructuredGrid>\n");
    let _ = writeln!(s, "<Piece NumberOfPoints=\"{n_points}\" NumberOfCells=\"{n_cells}\">");
    s.push_str(
        "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n",
    );
    for p in &mesh.nodes {
        let _ = writeln!(s, "{:e} {:e} 0", p[0], p[1]);
    }
    s.push_str("</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    for t in &mesh.triangles {
        let _ = writeln!(s, "{} {} {}", t[0], t[1], t[2]);
    }
    s.push_str("</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    for i in 0..n_cells {
        let _ = writeln!(s, "{}", 3 * (i + 1));
    }
    s.push_str("</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for _ in 0..n_cells {
        s.push_str("5\n");
    }
    s.push_str("</DataArray>\n</Cells>\n<PointData>\n");
    for f in point_fields {
        data_array(&mut s, f);
    }
    s.push_str(
        "</PointData>\n<CellData>\n<DataArray type=\"Int64\" Name=\"region\" format=\"ascii\">\n",
    );
    for t in &mesh.triangle_tags {
        let _ = writeln!(s, "{t}");
    }
    s.push_str("</DataArray>\n");
    for f in cell_fields {
        data_array(&mut s, f);
    }
    s.push_str("</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    s
}

fn data_array(s: &mut String, field: &Field<'_>) {
    let _ = writeln!(
        s,
        "<DataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"ascii\">",
        field.name, field.components
    );
    for chunk in field.values.chunks(field.components.max(1)) {
        let line: Vec<String> = chunk.iter().map(|v| format!("{v:e}")).collect();
        let _ = writeln!(s, "{}", line.join(" "));
    }
    s.push_str("</DataArray>\n");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vtu_has_counts_and_fields() {
        let mesh = Mesh {
            nodes: vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
            triangles: vec![[0, 1, 2]],
            triangle_tags: vec![4],
            ..Mesh::default()
        };
        let a = [0.0, 1.0, 2.0];
        let text = to_vtu(&mesh, &[Field { name: "A_phi", components: 1, values: &a }], &[]);
        assert!(text.contains("NumberOfPoints=\"3\" NumberOfCells=\"1\""));
        assert!(text.contains("Name=\"A_phi\""));
        assert!(text.contains("\n5\n"));
    }
}
