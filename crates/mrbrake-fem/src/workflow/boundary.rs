//! Boundary integrals: bilinear forms on the tagged edges of a mesh, as local matrices to add to an
//! [`Assembly`] as constant couplings (Robin-type terms such as the
//! asymptotic open boundary of magnetostatics or a convective heat-transfer coefficient).
//!
//! On an edge from `x_a` to `x_b` with parameter `t ∈ [0, 1]`, the traces of the Lagrange bases
//! are the 1D Lagrange polynomials: P1 `φ = (1 − t, t)` at the two vertices; P2
//! `φ = ((1 − t)(1 − 2t), t(2t − 1), 4t(1 − t))` at the vertices and the midpoint (Zienkiewicz,
//! Taylor & Zhu, *The Finite Element Method: Its Basis and Fundamentals*, 7th ed., §6.2). The
//! integrals use Gauss–Legendre with 2 points for P1 and 3 for P2: exact for the `φ_a φ_b r`
//! integrands of degree 3 and 5 of an axisymmetric mass term on a straight edge.
//!
//! Non-linear boundary terms (radiation `εσ(T⁴ − T_∞⁴)`, any flux that depends on the unknown)
//! are an [`EdgeFlux`]: a normal flux `g(x, u)` through tagged edges with its derivative `∂g/∂u`,
//! whose residual `∫ g(x, u_h) φ_i` and Jacobian `∫ ∂g/∂u φ_i φ_j` (symmetric; positive
//! semi-definite when `g` increases with `u`, as an outflow does) are re-evaluated at every
//! iterate and added to an assembly's residual and Jacobian by the caller's
//! [`crate::workflow::newton::NonlinearSystem`].

use crate::FemError;
use crate::discretisation::basis::{Basis, Weighting};
use crate::discretisation::dofs::ElementOrder;
use crate::discretisation::quadrature::gauss_legendre_unit;
use crate::linalg::pattern::CONSTRAINED;
use crate::workflow::assemble::{Assembly, LocalMatrix};

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
    let edges = tagged_edges(basis, tag)?;
    Ok(edges
        .into_iter()
        .map(|edge| {
            let k = edge.dofs.len();
            let mut values = vec![vec![0.0; k]; k];
            for q in &edge.points {
                for (a, row) in values.iter_mut().enumerate() {
                    for (b, value) in row.iter_mut().enumerate() {
                        *value += kernel(edge.ends, q, a, b);
                    }
                }
            }
            LocalMatrix { dofs: edge.dofs, values }
        })
        .collect())
}

/// The end points, DOFs and quadrature points of the edges tagged `tag`, in the order of the
/// mesh's edge list (the one place both [`edge_matrices`] and [`EdgeFlux`] read them from).
fn tagged_edges(basis: &Basis, tag: u32) -> Result<Vec<FluxEdge>, FemError> {
    let mesh = basis.mesh();
    let quadratic = basis.order() == ElementOrder::P2;
    let (x, w) = gauss_legendre_unit(if quadratic { 3 } else { 2 });
    let mut edges = Vec::new();
    for (edge, _) in mesh.edges.iter().zip(&mesh.edge_tags).filter(|(_, t)| **t == tag) {
        let ends = [mesh.nodes[edge[0]], mesh.nodes[edge[1]]];
        let [pa, pb] = ends;
        let length = (pb[0] - pa[0]).hypot(pb[1] - pa[1]);
        let mut dofs = vec![edge[0], edge[1]];
        if quadratic {
            dofs.push(basis.dofs().edge_dof(edge[0], edge[1]).ok_or_else(|| {
                FemError::field(
                    "edges",
                    format!(
                        "boundary {tag}: edge ({}, {}) is not the side of a triangle",
                        edge[0], edge[1]
                    ),
                )
            })?);
        }
        let points = x
            .iter()
            .zip(&w)
            .map(|(&t, &wq)| {
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
                EdgePoint { point, weight, phi }
            })
            .collect();
        edges.push(FluxEdge { tag, ends, dofs, points, positions: Vec::new() });
    }
    Ok(edges)
}

/// One tagged edge: its end points, DOFs, quadrature points and, in an [`EdgeFlux`], for each
/// pair `(a, b)`, `a <= b`, of free DOFs, the position of the Jacobian entry on the assembly's
/// pattern.
#[derive(Debug, Clone)]
struct FluxEdge {
    tag: u32,
    ends: [[f64; 2]; 2],
    dofs: Vec<usize>,
    points: Vec<EdgePoint>,
    positions: Vec<(usize, usize, usize)>,
}

/// A non-linear normal flux `g(tag, x, u)` through tagged boundary edges: the physics-free seam
/// for boundary terms that depend on the unknown (radiation, a temperature-dependent heat-transfer
/// coefficient) and for linear Robin terms with a load (convection `h (u − u_∞)`).
///
/// Its contribution to the weak form is `R_i += ∫ g(x, u_h) φ_i w dl` and
/// `K_ij += ∫ ∂g/∂u (x, u_h) φ_i φ_j w dl` (`w` holds `r` for axisymmetric bases), integrated with
/// the Gauss–Legendre rules of [`edge_matrices`]. Built once per assembly (the pattern positions of
/// the edge couplings are looked up once), evaluated at every iterate.
#[derive(Debug, Clone)]
pub struct EdgeFlux {
    edges: Vec<FluxEdge>,
}

impl EdgeFlux {
    /// The edges of `tags` on the basis and constraints of `assembly`. Fails when a P2 edge is not
    /// the side of a triangle or two free DOFs of an edge share no element.
    pub fn new(assembly: &Assembly, tags: &[u32]) -> Result<Self, FemError> {
        let free = assembly.constraints().free_index();
        let mut edges = Vec::new();
        for &tag in tags {
            for mut edge in tagged_edges(assembly.basis(), tag)? {
                for a in 0..edge.dofs.len() {
                    for b in a..edge.dofs.len() {
                        let (fa, fb) = (free[edge.dofs[a]], free[edge.dofs[b]]);
                        if fa == CONSTRAINED || fb == CONSTRAINED {
                            continue;
                        }
                        let position = assembly.pattern().position(fa, fb).ok_or_else(|| {
                            FemError::field(
                                "edges",
                                format!(
                                    "boundary {tag}: DOFs {} and {} share no element",
                                    edge.dofs[a], edge.dofs[b]
                                ),
                            )
                        })?;
                        edge.positions.push((a, b, position));
                    }
                }
                edges.push(edge);
            }
        }
        Ok(Self { edges })
    }

    /// True when no edge carries the flux.
    pub fn is_empty(&self) -> bool {
        self.edges.is_empty()
    }

    /// The local residual `∫ g φ_a w` and Jacobian `∫ g_u φ_a φ_b w` of one edge at `u`.
    fn local(
        edge: &FluxEdge,
        u: &[f64],
        flux: &impl Fn(u32, [f64; 2], f64) -> (f64, f64),
    ) -> ([f64; 3], [[f64; 3]; 3]) {
        let (mut res, mut jac) = ([0.0; 3], [[0.0; 3]; 3]);
        let k = edge.dofs.len();
        for q in &edge.points {
            let uq: f64 = (0..k).map(|a| u[edge.dofs[a]] * q.phi[a]).sum();
            let (g, dg) = flux(edge.tag, q.point, uq);
            for a in 0..k {
                res[a] += q.weight * g * q.phi[a];
                for b in 0..k {
                    jac[a][b] += q.weight * dg * q.phi[a] * q.phi[b];
                }
            }
        }
        (res, jac)
    }

    /// Adds the flux's residual on the free DOFs (`residual`, indexed like the assembly's) and,
    /// when given, its Jacobian on the assembly's pattern (`jacobian`), at the DOF values `u`.
    /// `flux(tag, x, u)` returns `(g, ∂g/∂u)`.
    pub fn add(
        &self,
        free_index: &[usize],
        u: &[f64],
        flux: impl Fn(u32, [f64; 2], f64) -> (f64, f64),
        residual: &mut [f64],
        mut jacobian: Option<&mut [f64]>,
    ) {
        for edge in &self.edges {
            let (res, jac) = Self::local(edge, u, &flux);
            for (a, &dof) in edge.dofs.iter().enumerate() {
                let d = free_index[dof];
                if d != CONSTRAINED {
                    residual[d] += res[a];
                }
            }
            if let Some(values) = jacobian.as_deref_mut() {
                for &(a, b, position) in &edge.positions {
                    values[position] += jac[a][b];
                }
            }
        }
    }

    /// Adds the flux's residual at every DOF (constrained ones included: their reactions) into
    /// `residual` (one value per DOF).
    pub fn add_all_dofs(
        &self,
        u: &[f64],
        flux: impl Fn(u32, [f64; 2], f64) -> (f64, f64),
        residual: &mut [f64],
    ) {
        for edge in &self.edges {
            let (res, _) = Self::local(edge, u, &flux);
            for (a, &dof) in edge.dofs.iter().enumerate() {
                residual[dof] += res[a];
            }
        }
    }

    /// The integral `∫ g(x, u_h) w dl` over the edges tagged `tag` (the total flux through them,
    /// per radian for axisymmetric bases).
    pub fn total(
        &self,
        tag: u32,
        u: &[f64],
        flux: impl Fn(u32, [f64; 2], f64) -> (f64, f64),
    ) -> f64 {
        self.edges
            .iter()
            .filter(|e| e.tag == tag)
            .map(|edge| Self::local(edge, u, &flux).0.iter().sum::<f64>())
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::structured::{SideTags, graded_lines, rectangle_mesh};
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

    /// A flux `g = c u²` on the side `r = 2` of a P1/P2 mesh: the residual summed over all DOFs
    /// is `∫ c u² r dl` (for `u = z`: `c · 2 · 3³/3 = 18 c`), the total agrees, and the Jacobian
    /// matches central differences of the residual.
    #[test]
    fn edge_flux_residual_total_and_jacobian() {
        use crate::workflow::constraints::Constraints;
        let r = graded_lines(0.0, 2.0, 3, 1.0);
        let z = graded_lines(0.0, 3.0, 4, 1.2);
        let sides = SideTags { r_min: 1, r_max: 2, z_min: 3, z_max: 4 };
        let mesh = Arc::new(rectangle_mesh(&r, &z, |_, _| 1, sides).unwrap());
        let c = 0.7;
        let flux = |_: u32, _: [f64; 2], u: f64| (c * u * u, 2.0 * c * u);
        for order in [ElementOrder::P1, ElementOrder::P2] {
            let basis = Basis::new(mesh.clone(), order, 4, Weighting::Axisymmetric);
            let u: Vec<f64> = basis.dofs().coordinates().iter().map(|p| p[1]).collect();
            let constraints = Constraints::builder(basis.dofs()).build();
            let assembly = Assembly::new(basis, constraints).unwrap();
            let edges = EdgeFlux::new(&assembly, &[2]).unwrap();
            let free = assembly.constraints().free_index().to_vec();
            let n = assembly.n_free();
            let (mut res, mut jac) = (vec![0.0; n], vec![0.0; assembly.pattern().nnz()]);
            edges.add(&free, &u, flux, &mut res, Some(&mut jac));
            let sum: f64 = res.iter().sum();
            assert!((sum - 18.0 * c).abs() < 1e-12, "{order}: {sum}");
            assert!((edges.total(2, &u, flux) - 18.0 * c).abs() < 1e-12);
            let mut all = vec![0.0; u.len()];
            edges.add_all_dofs(&u, flux, &mut all);
            assert!((all.iter().sum::<f64>() - 18.0 * c).abs() < 1e-12);
            // Jacobian column of one DOF on the side against central differences.
            let dof = (0..u.len()).find(|&d| res[free[d]].abs() > 1e-3).unwrap();
            let h = 1e-6;
            let (mut up, mut down) = (u.clone(), u.clone());
            up[dof] += h;
            down[dof] -= h;
            let (mut rp, mut rm) = (vec![0.0; n], vec![0.0; n]);
            edges.add(&free, &up, flux, &mut rp, None);
            edges.add(&free, &down, flux, &mut rm, None);
            for i in 0..n {
                let fd = (rp[i] - rm[i]) / (2.0 * h);
                let exact = assembly.pattern().position(i, free[dof]).map_or(0.0, |p| jac[p]);
                assert!((fd - exact).abs() < 1e-7, "{order}: K[{i}][{dof}] {exact} vs {fd}");
            }
        }
    }
}
