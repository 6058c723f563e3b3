//! The axisymmetric A_phi form, element by element, and its parallel assembly.
//!
//! With `A = A_phi(r, z) e_phi`, `B = curl A = (−∂A/∂z, ∂A/∂r + A/r)` in (r, z) components, and the
//! magnetostatic equation `curl(ν(|B|²) curl A) = J_phi` has the weak form (Galerkin, 2π dropped from
//! both sides)
//!
//! `R_i(A) = ∫_Ω ν(|B|²) B · curl(φ_i) r dr dz − ∫_Ω J_phi φ_i r dr dz = 0`,
//!
//! with `curl(φ_i) = (−∂φ_i/∂z, ∂φ_i/∂r + φ_i/r)`. This is the stationarity condition of the convex
//! energy `W(A) = ∫ w(B) r dr dz − ∫ J A r dr dz`, `w(B) = ∫_0^B H db` (e.g. Meunier (ed.), The
//! Finite Element Method for Electromagnetic Modeling, ch. 4; Silvester & Ferrari, Finite Elements
//! for Electrical Engineers, 3rd ed., §7.4 for the axisymmetric r-weighting). Its Jacobian is
//!
//! `K_ij = ∫ [ν curl φ_i · curl φ_j + 2 dν/dB² (B · curl φ_i)(B · curl φ_j)] r dr dz`,
//!
//! symmetric, and positive definite when `H(B) = ν B` is increasing (`ν + 2 B² dν/dB² > 0`), so the
//! Newton systems are solved by sparse Cholesky.
//!
//! The `A/r` term makes the integrand non-polynomial on elements touching the axis; the quadrature
//! rules have interior points only (no evaluation at r = 0) and the default degree-2 rule gives the
//! optimal O(h²) L2 convergence of linear (P1) elements observed in the validation tests. DOFs on
//! the axis carry `A = 0`.
//!
//! Element order: the form is written once, generic over the Lagrange basis
//! ([`mrbrake_fem::element::TriangleBasis`]: `ElementTriP1` with 3 DOFs, `ElementTriP2` with 6),
//! and compiled for each order (the `by_order!` macro picks the instance at run time). For
//! quadratic elements `B` is linear in each element (plus the `A/r` term) and the polynomial part
//! of the r-weighted integrands has degree 3, so they take the degree-4 rule (Dunavant 1985,
//! 6 interior points) or higher.
//!
//! Open boundary (first-order asymptotic boundary condition): far from the sources `A_phi` is a
//! dipole field, `A ∝ sin θ / ρ²` in spherical coordinates centred on the axis, so on a sphere of
//! radius `ρ = R`, `(n × B)_phi = −∂A/∂n − n_r A/r = 2A/R − A/R = A/R`, and the natural boundary
//! term becomes `∮ ν0 (A/R) φ_i r dl` added to the left-hand side. This is the axisymmetric form of
//! the asymptotic boundary condition of Chen & Konrad, IEEE Trans. Magn. 33(1) 1997, §III, and the
//! coefficient FEMM uses for axisymmetric open boundaries (`c0 = 1/(μ0 R)`).

use rayon::prelude::*;

use mrbrake_fem::element::{P1Triangle, TriangleBasis};
use mrbrake_fem::mesh::Mesh;
use mrbrake_fem::quadrature::TrianglePoint;

use crate::material::MagneticMaterial;

/// Calls the generic function `f::<Basis, N>(args)` instantiated for the element order `order`
/// (a [`mrbrake_fem::dofs::ElementOrder`]): `ElementTriP1, 3` or `ElementTriP2, 6`.
macro_rules! by_order {
    ($order:expr, $($f:ident)::+ ( $($arg:expr),* $(,)? )) => {
        match $order {
            mrbrake_fem::dofs::ElementOrder::P1 => {
                $($f)::+::<mrbrake_fem::element::ElementTriP1, 3>($($arg),*)
            }
            mrbrake_fem::dofs::ElementOrder::P2 => {
                $($f)::+::<mrbrake_fem::element::ElementTriP2, 6>($($arg),*)
            }
        }
    };
}
pub(crate) use by_order;

/// The full symmetric `N × N` matrix of its upper triangle packed row by row (pairs `(i, j)`,
/// `i <= j`, in the order of the element Jacobians).
#[inline(always)]
pub(crate) fn unpack_symmetric<const N: usize>(packed: &[f64]) -> [[f64; N]; N] {
    let mut full = [[0.0; N]; N];
    let mut p = 0;
    for i in 0..N {
        for j in i..N {
            full[i][j] = packed[p];
            full[j][i] = packed[p];
            p += 1;
        }
    }
    full
}

/// Number of upper-triangle pairs `(i, j)`, `i <= j`, of an element with `k` DOFs.
pub(crate) const fn pairs(k: usize) -> usize {
    k * (k + 1) / 2
}

/// Upper-triangle pairs of the largest element (P2: 6 DOFs, 21 pairs).
const MAX_PAIRS: usize = pairs(6);

/// Triangles per parallel task in the element loops.
const MIN_LEN: usize = 2048;

/// Per-element data the form needs: node coordinates come from the mesh, the rest from here.
#[derive(Debug, Clone)]
pub(crate) struct ElementData {
    /// Index into the material list, per triangle.
    pub material: Vec<u32>,
    /// Source current density J_phi (A/m²), per triangle.
    pub current_density: Vec<f64>,
    /// Geometric stiffness `G_ij = Σ_q w_q curl φ_i · curl φ_j` (upper triangle, same pair order as
    /// the Jacobian, `k(k+1)/2` values per triangle for `k` DOFs) with the same quadrature as
    /// [`element_kernel`]: for a linear material the element residual is `ν G a − J f` and the
    /// Jacobian `ν G`, so those elements (air, coils: most of a mesh) need no quadrature loop
    /// during the Newton iterations.
    pub geometric_stiffness: Vec<f64>,
    /// Load per unit current density `f_i = Σ_q w_q φ_i`, `k` values per triangle.
    pub unit_load: Vec<f64>,
}

impl ElementData {
    /// Material indices per triangle, zero sources, and the precomputed linear element matrices of
    /// the basis `E` with `N` DOFs.
    pub fn new<E: TriangleBasis<N>, const N: usize>(
        mesh: &Mesh,
        rule: &[TrianglePoint],
        material: Vec<u32>,
    ) -> Self {
        let n = mesh.triangles.len();
        let mut geometric_stiffness = vec![0.0; pairs(N) * n];
        let mut unit_load = vec![0.0; N * n];
        geometric_stiffness
            .par_chunks_mut(pairs(N))
            .zip(unit_load.par_chunks_mut(N))
            .enumerate()
            .with_min_len(MIN_LEN)
            .for_each(|(t, (g, f))| {
                let tri = triangle(mesh, t);
                for q in rule {
                    let v = point_values::<E, N>(&tri, q);
                    let mut p = 0;
                    for i in 0..N {
                        f[i] += v.weight * v.basis[i];
                        for j in i..N {
                            g[p] += v.weight
                                * (v.curl[i][0] * v.curl[j][0] + v.curl[i][1] * v.curl[j][1]);
                            p += 1;
                        }
                    }
                }
            });
        Self { material, current_density: vec![0.0; n], geometric_stiffness, unit_load }
    }
}

/// Residual `ν G a − J f` of an element with a linear material (`g`: the packed upper triangle
/// of `G`; its Jacobian `ν G` is assembled once, [`linear_jacobians`]).
#[inline]
fn linear_element<const N: usize>(
    nu: f64,
    g: &[f64],
    f: &[f64],
    current_density: f64,
    a: [f64; N],
    residual: &mut [f64],
) {
    // Slices of the known lengths: the indexing below needs no further bounds checks.
    let (g, f, residual) = (&g[..pairs(N)], &f[..N], &mut residual[..N]);
    let full = unpack_symmetric::<N>(g);
    for i in 0..N {
        let mut ga = 0.0;
        for j in 0..N {
            ga += full[i][j] * a[j];
        }
        residual[i] = nu * ga - current_density * f[i];
    }
}

/// Values of the form at one quadrature point of one element with `N` DOFs.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PointValues<const N: usize> {
    /// `[r, z]` of the point (m).
    pub point: [f64; 2],
    /// Quadrature weight times area times r (m³ per radian).
    pub weight: f64,
    /// `curl φ_i` of the basis functions.
    pub curl: [[f64; 2]; N],
    /// The basis values `φ_i`.
    pub basis: [f64; N],
}

/// The basis `E`'s values and curls at quadrature point `q` of the triangle `tri`.
#[inline]
pub(crate) fn point_values<E: TriangleBasis<N>, const N: usize>(
    tri: &P1Triangle,
    q: &TrianglePoint,
) -> PointValues<N> {
    let point = tri.point(q.bary);
    let r = point[0];
    let inv_r = 1.0 / r;
    let basis = E::values(q.bary);
    let grad = E::gradients(q.bary, &tri.grad);
    let mut curl = [[0.0; 2]; N];
    for i in 0..N {
        curl[i] = [-grad[i][1], grad[i][0] + basis[i] * inv_r];
    }
    PointValues { point, weight: q.weight * tri.area * r, curl, basis }
}

/// The (straight-sided) triangle geometry of mesh triangle `t` (always inlined: in the element
/// loops a call costs as much as the geometry).
#[inline(always)]
pub(crate) fn triangle(mesh: &Mesh, t: usize) -> P1Triangle {
    let [a, b, c] = mesh.triangles[t];
    P1Triangle::new([mesh.nodes[a], mesh.nodes[b], mesh.nodes[c]])
}

/// The values of `a` at the `N` DOFs of triangle `t` (`element_dofs`: `N` global DOFs per triangle).
#[inline(always)]
pub(crate) fn local_values<const N: usize>(
    element_dofs: &[usize],
    t: usize,
    a: &[f64],
) -> [f64; N] {
    let dofs = &element_dofs[N * t..N * (t + 1)];
    std::array::from_fn(|i| a[dofs[i]])
}

/// Flux density `B = Σ A_i curl φ_i` at a quadrature point.
#[inline]
pub(crate) fn flux_density<const N: usize>(values: &PointValues<N>, a: [f64; N]) -> [f64; 2] {
    let mut b = [0.0; 2];
    for i in 0..N {
        b[0] += a[i] * values.curl[i][0];
        b[1] += a[i] * values.curl[i][1];
    }
    b
}

/// Element residual (`N` values) and, if `jacobian` is given, the upper triangle of the element
/// Jacobian (`N(N+1)/2` values, pairs in row-major upper order: (0,0) (0,1) … (0,N−1) (1,1) …).
#[inline]
pub(crate) fn element_kernel<E: TriangleBasis<N>, const N: usize>(
    tri: &P1Triangle,
    rule: &[TrianglePoint],
    material: &MagneticMaterial,
    current_density: f64,
    a: [f64; N],
    residual: &mut [f64],
    jacobian: Option<&mut [f64]>,
) {
    let mut res = [0.0; N];
    // Packed upper triangle (the first N(N+1)/2 entries are used).
    let mut jac = [0.0; MAX_PAIRS];
    let want_jacobian = jacobian.is_some();
    for q in rule {
        let v = point_values::<E, N>(tri, q);
        let b = flux_density(&v, a);
        let b2 = b[0] * b[0] + b[1] * b[1];
        let (nu, dnu) = material.nu_and_dnu_db2(b2);
        let mut b_dot_curl = [0.0; N];
        for i in 0..N {
            b_dot_curl[i] = b[0] * v.curl[i][0] + b[1] * v.curl[i][1];
            res[i] += v.weight * (nu * b_dot_curl[i] - current_density * v.basis[i]);
        }
        if want_jacobian {
            let mut p = 0;
            for i in 0..N {
                for j in i..N {
                    let curl_dot = v.curl[i][0] * v.curl[j][0] + v.curl[i][1] * v.curl[j][1];
                    jac[p] +=
                        v.weight * (nu * curl_dot + 2.0 * dnu * b_dot_curl[i] * b_dot_curl[j]);
                    p += 1;
                }
            }
        }
    }
    residual.copy_from_slice(&res);
    if let Some(out) = jacobian {
        out.copy_from_slice(&jac[..pairs(N)]);
    }
}

/// Computes all element residuals in parallel into `element_residual` (`N` per triangle) and, when
/// `element_jacobian` is `Some` (`N(N+1)/2` per triangle), the Jacobians of the elements with a
/// *non-linear* material. A linear element's Jacobian `ν G` never changes: the solver assembles
/// those once ([`linear_jacobians`]) and adds only the non-linear ones per Newton iteration.
/// `element_dofs` holds the `N` global DOFs of each triangle, `a` the value of every DOF.
pub(crate) fn assemble_elements<E: TriangleBasis<N>, const N: usize>(
    mesh: &Mesh,
    element_dofs: &[usize],
    rule: &[TrianglePoint],
    materials: &[MagneticMaterial],
    data: &ElementData,
    a: &[f64],
    element_residual: &mut [f64],
    element_jacobian: Option<&mut [f64]>,
) {
    // Per-element inputs as chunks zipped with the outputs: no index arithmetic per element.
    let inputs = element_dofs
        .par_chunks(N)
        .zip(data.geometric_stiffness.par_chunks(pairs(N)))
        .zip(data.unit_load.par_chunks(N));
    let kernel = |t: usize, ((dofs, g), f): ((&[usize], &[f64]), &[f64]), res: &mut [f64], jac| {
        // (`jac` is left untouched for linear elements.)
        let dofs: &[usize; N] = dofs.try_into().expect("N DOFs per triangle");
        let a_local = dofs.map(|d| a[d]);
        let material = &materials[data.material[t] as usize];
        if let MagneticMaterial::Linear { .. } = material {
            let nu = material.nu_and_dnu_db2(0.0).0;
            linear_element(nu, g, f, data.current_density[t], a_local, res);
            return;
        }
        let tri = triangle(mesh, t);
        element_kernel::<E, N>(&tri, rule, material, data.current_density[t], a_local, res, jac);
    };
    match element_jacobian {
        Some(jac) => element_residual
            .par_chunks_mut(N)
            .zip(jac.par_chunks_mut(pairs(N)))
            .zip(inputs)
            .enumerate()
            .with_min_len(MIN_LEN)
            .for_each(|(t, ((res, jac), input))| kernel(t, input, res, Some(jac))),
        None => element_residual
            .par_chunks_mut(N)
            .zip(inputs)
            .enumerate()
            .with_min_len(MIN_LEN)
            .for_each(|(t, (res, input))| kernel(t, input, res, None)),
    }
}

/// Adds the element residuals (`N` per triangle) into the free-DOF residual `residual_free`
/// (zeroed first), through `dof` (the free index of every global DOF, or `CONSTRAINED`).
pub(crate) fn scatter_residual<const N: usize>(
    element_dofs: &[usize],
    dof: &[usize],
    element_residual: &[f64],
    residual_free: &mut [f64],
) {
    residual_free.iter_mut().for_each(|r| *r = 0.0);
    for (dofs, res) in element_dofs.chunks_exact(N).zip(element_residual.chunks_exact(N)) {
        for k in 0..N {
            let d = dof[dofs[k]];
            if d != mrbrake_fem::pattern::CONSTRAINED {
                residual_free[d] += res[k];
            }
        }
    }
}

/// The constant element Jacobians `ν G` of the linear-material elements (`p` = `k(k+1)/2` values
/// per triangle, upper pairs), zero for the non-linear ones.
pub(crate) fn linear_jacobians(
    materials: &[MagneticMaterial],
    data: &ElementData,
    p: usize,
    element_jacobian: &mut [f64],
) {
    element_jacobian
        .par_chunks_mut(p)
        .zip(data.geometric_stiffness.par_chunks(p))
        .enumerate()
        .with_min_len(MIN_LEN)
        .for_each(|(t, (jac, g))| {
            let material = &materials[data.material[t] as usize];
            if let MagneticMaterial::Linear { .. } = material {
                let nu = material.nu_and_dnu_db2(0.0).0;
                for (j, g) in jac.iter_mut().zip(g) {
                    *j = nu * g;
                }
            } else {
                jac.iter_mut().for_each(|j| *j = 0.0);
            }
        });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::MarroccoCurve;
    use mrbrake_fem::element::{ElementTriP1, ElementTriP2};
    use mrbrake_fem::quadrature::triangle_rule;
    use std::sync::Arc;

    /// The element Jacobian is the derivative of the element residual: central differences agree
    /// for every column, in saturated iron (where `dν/dB²` matters).
    fn check_jacobian<E: TriangleBasis<N>, const N: usize>(degree: usize, a: [f64; N]) {
        let tri = P1Triangle::new([[0.01, 0.0], [0.02, 0.001], [0.012, 0.012]]);
        let rule = triangle_rule(degree);
        let iron = MagneticMaterial::NonLinear(Arc::new(MarroccoCurve::soft_iron()));
        let mut res = [0.0; N];
        let mut jac = vec![0.0; pairs(N)];
        element_kernel::<E, N>(&tri, &rule, &iron, 1e6, a, &mut res, Some(&mut jac));
        let full = unpack_symmetric::<N>(&jac);
        // The field is at the knee of the curve, where the `2 dν/dB² B⊗B` term matters.
        let b = flux_density(&point_values::<E, N>(&tri, &rule[0]), a);
        let b2 = b[0] * b[0] + b[1] * b[1];
        let (nu, dnu) = iron.nu_and_dnu_db2(b2);
        assert!(
            2.0 * dnu * b2 > 0.5 * nu,
            "|B| = {}: ν {nu}, 2 B² dν/dB² {}",
            b2.sqrt(),
            2.0 * dnu * b2
        );
        for j in 0..N {
            let h = 1e-7;
            let (mut ap, mut am) = (a, a);
            ap[j] += h;
            am[j] -= h;
            let (mut rp, mut rm) = ([0.0; N], [0.0; N]);
            element_kernel::<E, N>(&tri, &rule, &iron, 1e6, ap, &mut rp, None);
            element_kernel::<E, N>(&tri, &rule, &iron, 1e6, am, &mut rm, None);
            for i in 0..N {
                let fd = (rp[i] - rm[i]) / (2.0 * h);
                assert!(
                    (fd - full[i][j]).abs() <= 1e-5 * full[i][i].abs(),
                    "({i},{j}): {fd} vs {}",
                    full[i][j]
                );
            }
        }
    }

    #[test]
    fn p1_jacobian_matches_finite_differences() {
        check_jacobian::<ElementTriP1, 3>(2, [0.008, 0.022, 0.014]);
    }

    #[test]
    fn p2_jacobian_matches_finite_differences() {
        check_jacobian::<ElementTriP2, 6>(4, [0.008, 0.022, 0.014, 0.017, 0.019, 0.0104]);
    }

    /// Uniform `B = B0 e_z` is `A = B0 r / 2`, in both spaces: B is exact at every point.
    fn check_uniform_field<E: TriangleBasis<N>, const N: usize>(degree: usize) {
        let tri = P1Triangle::new([[0.01, 0.0], [0.02, 0.001], [0.012, 0.012]]);
        let b0 = 0.3;
        let a = E::nodes().map(|l| 0.5 * b0 * tri.point(l)[0]);
        for q in &triangle_rule(degree) {
            let b = flux_density(&point_values::<E, N>(&tri, q), a);
            assert!(b[0].abs() < 1e-12 && (b[1] - b0).abs() < 1e-12, "{b:?}");
        }
    }

    #[test]
    fn uniform_field_is_exact() {
        check_uniform_field::<ElementTriP1, 3>(2);
        check_uniform_field::<ElementTriP2, 6>(4);
    }

    /// The packed linear-element matrices give the same residual as the quadrature kernel.
    #[test]
    fn precomputed_linear_matrices_match_the_kernel() {
        let mesh = Mesh {
            nodes: vec![[0.01, 0.0], [0.02, 0.001], [0.012, 0.012]],
            triangles: vec![[0, 1, 2]],
            triangle_tags: vec![1],
            ..Mesh::default()
        };
        let rule = triangle_rule(4);
        let data = ElementData::new::<ElementTriP2, 6>(&mesh, &rule, vec![0]);
        let air = MagneticMaterial::Linear { mu_r: 3.0 };
        let a = [0.004, 0.011, 0.007, 0.0085, 0.0095, 0.0052];
        let (mut from_matrices, mut from_kernel) = ([0.0; 6], [0.0; 6]);
        let nu = air.nu_and_dnu_db2(0.0).0;
        linear_element(nu, &data.geometric_stiffness, &data.unit_load, 2e6, a, &mut from_matrices);
        element_kernel::<ElementTriP2, 6>(
            &triangle(&mesh, 0),
            &rule,
            &air,
            2e6,
            a,
            &mut from_kernel,
            None,
        );
        for i in 0..6 {
            assert!(
                (from_matrices[i] - from_kernel[i]).abs() <= 1e-12 * from_kernel[i].abs().max(1.0),
                "{from_matrices:?} vs {from_kernel:?}"
            );
        }
    }
}
