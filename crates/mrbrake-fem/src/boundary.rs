//! Boundary integrals: bilinear forms on the tagged edges of a mesh, as local matrices to add to an
//! [`Assembly`](crate::assemble::Assembly) as constant couplings (Robin-type terms such as the
//! asymptotic open boundary of magnetostatics or a convective heat-transfer coefficient).
//!
//! On an edge from `x_a` to `x_b` with parameter `t ∈ [0, 1]`, the traces of the Lagrange bases
//! are the 1D Lagrange polynomials: P1 `φ = (1 − t, t)` at the two vertices; P2
//! `φ = ((1 − t)(1 − 2t), t(2t − 1), 4t(1 − t))` at the vertices and the midpoint (Zienkiewicz,
//! Taylor & Zhu, *The Finite Element Method: Its Basis and Fundamentals*, 7th ed., §6.2). The
//! integrals use Gauss–Legendre with 2 points for P1 and 3 for P2: exact for the `φ_a φ_b r`
//! integrands of degree 3 and 5 of an axisymmetric mass term on a straight edge.

use crate::FemError;
use crate::assemble::LocalMatrix;
use crate::basis::{Basis, Weighting};
use crate::dofs::ElementOrder;
use crate::quadrature::gauss_legendre_unit;

/// The values a boundary form needs at one quadrature point of an edge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgePoint {
    /// `[r, z]` of the point (m).
    pub point: [f64; 2],
    /// Quadrature weight times the edge length, times `r` for [`Weighting::Axisymmetric`].
    pub weight: f64,
    /// Trace values of the edge's basis functions (the last is 0 for P1).
    pub phi: [f64; 3],
}

/// The local matrices `m_ab = Σ_q kernel(ends, q, a, b)` of every edge tagged `tag`, over the edge's
/// DOFs (its two vertices and, for P2, its midpoint), in the order of the mesh's edge list.
/// `ends` are the edge's end points; `kernel` returns the contribution of point `q` to the pair
/// `(a, b)` (e.g. `q.weight * q.phi[a] * q.phi[b] * c` for a mass term with coefficient `c`).
/// Fails when a P2 edge is not the side of a triangle (it has no midpoint DOF).
pub fn edge_matrices(
    basis: &Basis,
    tag: u32,
    kernel: impl Fn([[f64; 2]; 2], &EdgePoint, usize, usize) -> f64,
) -> Result<Vec<LocalMatrix>, FemError> {
    let mesh = basis.mesh();
    let quadratic = basis.order() == ElementOrder::P2;
    let (x, w) = gauss_legendre_unit(if quadratic { 3 } else { 2 });
    let mut matrices = Vec::new();
    for (edge, _) in mesh.edges.iter().zip(&mesh.edge_tags).filter(|(_, t)| **t == tag) {
        let ends = [mesh.nodes[edge[0]], mesh.nodes[edge[1]]];
        let [pa, pb] = ends;
        let length = (pb[0] - pa[0]).hypot(pb[1] - pa[1]);
        let mut dofs = vec![edge[0], edge[1]];
        if quadratic {
            dofs.push(basis.dofs().edge_dof(edge[0], edge[1]).ok_or_else(|| {
                FemError::Input(format!(
                    "boundary {tag}: edge ({}, {}) is not the side of a triangle",
                    edge[0], edge[1]
                ))
            })?);
        }
        let k = dofs.len();
        let mut values = vec![vec![0.0; k]; k];
        for (&t, &wq) in x.iter().zip(&w) {
            let phi = if quadratic {
                [(1.0 - t) * (1.0 - 2.0 * t), t * (2.0 * t - 1.0), 4.0 * t * (1.0 - t)]
            } else {
                [1.0 - t, t, 0.0]
            };
            let point = [pa[0] * (1.0 - t) + pb[0] * t, pa[1] * (1.0 - t) + pb[1] * t];
            let weight = match basis.weighting() {
                Weighting::Planar => wq * length,
                Weighting::Axisymmetric => wq * length * point[0],
            };
            let q = EdgePoint { point, weight, phi };
            for (a, row) in values.iter_mut().enumerate() {
                for (b, value) in row.iter_mut().enumerate() {
                    *value += kernel(ends, &q, a, b);
                }
            }
        }
        matrices.push(LocalMatrix { dofs, values });
    }
    Ok(matrices)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::structured::{SideTags, graded_lines, rectangle_mesh};
    use std::sync::Arc;

    /// The axisymmetric "mass" `∫ φ_a φ_b r dl` summed over all pairs is `∫ r dl`: on the side
    /// `r = 2` of height 3 that is 6, on the bottom `z = 0` from r = 0 to 2 it is 2; both orders.
    #[test]
    fn edge_mass_sums_to_the_weighted_length() {
        let r = graded_lines(0.0, 2.0, 5, 1.4);
        let z = graded_lines(0.0, 3.0, 4, 1.0);
        let sides = SideTags { r_min: 1, r_max: 2, z_min: 3, z_max: 4 };
        let mesh = Arc::new(rectangle_mesh(&r, &z, |_, _| 1, sides).unwrap());
        for order in [ElementOrder::P1, ElementOrder::P2] {
            let basis = Basis::new(mesh.clone(), order, 2, Weighting::Axisymmetric);
            for (tag, exact) in [(2, 6.0), (3, 2.0)] {
                let m = edge_matrices(&basis, tag, |_, q, a, b| q.weight * q.phi[a] * q.phi[b])
                    .unwrap();
                let total: f64 = m.iter().flat_map(|l| l.values.iter().flatten()).sum();
                assert!((total - exact).abs() < 1e-12, "{order} tag {tag}: {total}");
                assert!(m.iter().all(|l| l.dofs.len() == order.degree() + 1));
            }
        }
    }
}
