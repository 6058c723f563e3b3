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
//! optimal O(h²) L2 convergence observed in the validation tests. Nodes on the axis carry `A = 0`.
//!
//! Open boundary (first-order asymptotic boundary condition): far from the sources `A_phi` is a
//! dipole field, `A ∝ sin θ / ρ²` in spherical coordinates centred on the axis, so on a sphere of
//! radius `ρ = R`, `(n × B)_phi = −∂A/∂n − n_r A/r = 2A/R − A/R = A/R`, and the natural boundary
//! term becomes `∮ ν0 (A/R) φ_i r dl` added to the left-hand side. This is the axisymmetric form of
//! the asymptotic boundary condition of Chen & Konrad, IEEE Trans. Magn. 33(1) 1997, §III, and the
//! coefficient FEMM uses for axisymmetric open boundaries (`c0 = 1/(μ0 R)`).

use rayon::prelude::*;

use mrbrake_fem::element::P1Triangle;
use mrbrake_fem::mesh::Mesh;
use mrbrake_fem::quadrature::TrianglePoint;

use crate::material::MagneticMaterial;

/// Per-element data the form needs: node coordinates come from the mesh, the rest from here.
#[derive(Debug, Clone)]
pub(crate) struct ElementData {
    /// Index into the material list, per triangle.
    pub material: Vec<u32>,
    /// Source current density J_phi (A/m²), per triangle.
    pub current_density: Vec<f64>,
    /// Geometric stiffness `G_ij = Σ_q w_q curl φ_i · curl φ_j` (upper triangle, same pair order as
    /// the Jacobian) per triangle, with the same quadrature as [`element_kernel`]: for a linear
    /// material the element residual is `ν G a − J f` and the Jacobian `ν G`, so those elements
    /// (air, coils: most of a mesh) need no quadrature loop during the Newton iterations.
    pub geometric_stiffness: Vec<[f64; 6]>,
    /// Load per unit current density `f_i = Σ_q w_q φ_i` per triangle.
    pub unit_load: Vec<[f64; 3]>,
}

impl ElementData {
    /// Material indices per triangle, zero sources, and the precomputed linear element matrices.
    pub fn new(mesh: &Mesh, rule: &[TrianglePoint], material: Vec<u32>) -> Self {
        let n = mesh.triangles.len();
        let mut geometric_stiffness = vec![[0.0; 6]; n];
        let mut unit_load = vec![[0.0; 3]; n];
        geometric_stiffness
            .par_iter_mut()
            .zip(unit_load.par_iter_mut())
            .enumerate()
            .with_min_len(2048)
            .for_each(|(t, (g, f))| {
                let tri = triangle(mesh, t);
                for q in rule {
                    let v = point_values(&tri, q);
                    let mut p = 0;
                    for i in 0..3 {
                        f[i] += v.weight * v.basis[i];
                        for j in i..3 {
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

/// Residual `ν G a − J f` and Jacobian `ν G` of an element with a linear material.
#[inline]
fn linear_element(
    nu: f64,
    g: &[f64; 6],
    f: &[f64; 3],
    current_density: f64,
    a: [f64; 3],
    residual: &mut [f64],
    jacobian: Option<&mut [f64]>,
) {
    let full = [[g[0], g[1], g[2]], [g[1], g[3], g[4]], [g[2], g[4], g[5]]];
    for i in 0..3 {
        let ga = full[i][0] * a[0] + full[i][1] * a[1] + full[i][2] * a[2];
        residual[i] = nu * ga - current_density * f[i];
    }
    if let Some(out) = jacobian {
        for (o, gp) in out.iter_mut().zip(g) {
            *o = nu * gp;
        }
    }
}

/// Values of the form at one quadrature point of one element.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PointValues {
    /// Quadrature weight times area times r (m³ per radian).
    pub weight: f64,
    /// `curl φ_i` of the three basis functions.
    pub curl: [[f64; 2]; 3],
    /// Barycentric coordinates (the P1 basis values).
    pub basis: [f64; 3],
}

/// Geometry of triangle `t` and the form's basis values at quadrature point `q`.
#[inline]
pub(crate) fn point_values(tri: &P1Triangle, q: &TrianglePoint) -> PointValues {
    let point = tri.point(q.bary);
    let r = point[0];
    let inv_r = 1.0 / r;
    let mut curl = [[0.0; 2]; 3];
    for i in 0..3 {
        curl[i] = [-tri.grad[i][1], tri.grad[i][0] + q.bary[i] * inv_r];
    }
    PointValues { weight: q.weight * tri.area * r, curl, basis: q.bary }
}

/// The P1 triangle of mesh triangle `t`.
#[inline]
pub(crate) fn triangle(mesh: &Mesh, t: usize) -> P1Triangle {
    let [a, b, c] = mesh.triangles[t];
    P1Triangle::new([mesh.nodes[a], mesh.nodes[b], mesh.nodes[c]])
}

/// Flux density `B = Σ A_i curl φ_i` at a quadrature point.
#[inline]
pub(crate) fn flux_density(values: &PointValues, a: [f64; 3]) -> [f64; 2] {
    let mut b = [0.0; 2];
    for i in 0..3 {
        b[0] += a[i] * values.curl[i][0];
        b[1] += a[i] * values.curl[i][1];
    }
    b
}

/// Element residual (3 values) and, if `jacobian` is given, the upper triangle of the element
/// Jacobian (6 values, pairs (0,0) (0,1) (0,2) (1,1) (1,2) (2,2)).
#[inline]
pub(crate) fn element_kernel(
    tri: &P1Triangle,
    rule: &[TrianglePoint],
    material: &MagneticMaterial,
    current_density: f64,
    a: [f64; 3],
    residual: &mut [f64],
    jacobian: Option<&mut [f64]>,
) {
    let mut res = [0.0; 3];
    let mut jac = [0.0; 6];
    let want_jacobian = jacobian.is_some();
    for q in rule {
        let v = point_values(tri, q);
        let b = flux_density(&v, a);
        let b2 = b[0] * b[0] + b[1] * b[1];
        let (nu, dnu) = material.nu_and_dnu_db2(b2);
        let mut b_dot_curl = [0.0; 3];
        for i in 0..3 {
            b_dot_curl[i] = b[0] * v.curl[i][0] + b[1] * v.curl[i][1];
            res[i] += v.weight * (nu * b_dot_curl[i] - current_density * v.basis[i]);
        }
        if want_jacobian {
            let mut p = 0;
            for i in 0..3 {
                for j in i..3 {
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
        out.copy_from_slice(&jac);
    }
}

/// Computes all element residuals in parallel into `element_residual` (3 per triangle) and, when
/// `element_jacobian` is `Some` (6 per triangle), the Jacobians of the elements with a
/// *non-linear* material. A linear element's Jacobian `ν G` never changes: the solver assembles
/// those once ([`linear_jacobians`]) and adds only the non-linear ones per Newton iteration.
pub(crate) fn assemble_elements(
    mesh: &Mesh,
    rule: &[TrianglePoint],
    materials: &[MagneticMaterial],
    data: &ElementData,
    a: &[f64],
    element_residual: &mut [f64],
    element_jacobian: Option<&mut [f64]>,
) {
    const MIN_LEN: usize = 2048;
    let kernel = |t: usize, res: &mut [f64], jac: Option<&mut [f64]>| {
        // (`jac` is left untouched for linear elements.)
        let [n0, n1, n2] = mesh.triangles[t];
        let material = &materials[data.material[t] as usize];
        if let MagneticMaterial::Linear { .. } = material {
            let nu = material.nu_and_dnu_db2(0.0).0;
            let (g, f) = (&data.geometric_stiffness[t], &data.unit_load[t]);
            linear_element(nu, g, f, data.current_density[t], [a[n0], a[n1], a[n2]], res, None);
            return;
        }
        let tri = P1Triangle::new([mesh.nodes[n0], mesh.nodes[n1], mesh.nodes[n2]]);
        element_kernel(
            &tri,
            rule,
            material,
            data.current_density[t],
            [a[n0], a[n1], a[n2]],
            res,
            jac,
        );
    };
    match element_jacobian {
        Some(jac) => element_residual
            .par_chunks_mut(3)
            .zip(jac.par_chunks_mut(6))
            .enumerate()
            .with_min_len(MIN_LEN)
            .for_each(|(t, (res, jac))| kernel(t, res, Some(jac))),
        None => element_residual
            .par_chunks_mut(3)
            .enumerate()
            .with_min_len(MIN_LEN)
            .for_each(|(t, res)| kernel(t, res, None)),
    }
}

/// The constant element Jacobians `ν G` of the linear-material elements (6 per triangle, upper
/// pairs), zero for the non-linear ones.
pub(crate) fn linear_jacobians(
    materials: &[MagneticMaterial],
    data: &ElementData,
    element_jacobian: &mut [f64],
) {
    element_jacobian.par_chunks_mut(6).enumerate().with_min_len(2048).for_each(|(t, jac)| {
        let material = &materials[data.material[t] as usize];
        if let MagneticMaterial::Linear { .. } = material {
            let nu = material.nu_and_dnu_db2(0.0).0;
            for (j, g) in jac.iter_mut().zip(&data.geometric_stiffness[t]) {
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
    use crate::material::{MU_0, MarroccoCurve};
    use mrbrake_fem::quadrature::triangle_rule;
    use std::sync::Arc;

    /// The Jacobian is the derivative of the residual: central differences agree.
    #[test]
    fn jacobian_matches_finite_differences() {
        let tri = P1Triangle::new([[0.01, 0.0], [0.02, 0.001], [0.012, 0.012]]);
        let rule = triangle_rule(2);
        let iron = MagneticMaterial::NonLinear(Arc::new(MarroccoCurve::soft_iron()));
        let a = [0.004, 0.011, 0.007];
        let mut res = [0.0; 3];
        let mut jac = [0.0; 6];
        element_kernel(&tri, &rule, &iron, 1e6, a, &mut res, Some(&mut jac));
        let full = |i: usize, j: usize| {
            let (i, j) = if i <= j { (i, j) } else { (j, i) };
            jac[[0, 1, 2, 0, 3, 4, 0, 0, 5][i * 3 + j]]
        };
        for j in 0..3 {
            let h = 1e-7;
            let (mut ap, mut am) = (a, a);
            ap[j] += h;
            am[j] -= h;
            let (mut rp, mut rm) = ([0.0; 3], [0.0; 3]);
            element_kernel(&tri, &rule, &iron, 1e6, ap, &mut rp, None);
            element_kernel(&tri, &rule, &iron, 1e6, am, &mut rm, None);
            for i in 0..3 {
                let fd = (rp[i] - rm[i]) / (2.0 * h);
                assert!(
                    (fd - full(i, j)).abs() <= 1e-5 * full(i, i).abs(),
                    "({i},{j}): {fd} vs {}",
                    full(i, j)
                );
            }
        }
        // Uniform B = B0 e_z is A = B0 r / 2: the air residual without source is the boundary flux only,
        // and B at any point equals B0.
        let air = MagneticMaterial::air();
        let b0 = 0.3;
        let a_uniform = tri.nodes.map(|p| 0.5 * b0 * p[0]);
        for q in &rule {
            let b = flux_density(&point_values(&tri, q), a_uniform);
            // A linear in r is exactly represented, so B is exact at every point.
            assert!(b[0].abs() < 1e-12 && (b[1] - b0).abs() < 1e-12);
        }
        element_kernel(&tri, &rule, &air, 0.0, a_uniform, &mut res, None);
        assert!(res.iter().all(|r| r.is_finite()));
        let _ = MU_0;
    }
}
