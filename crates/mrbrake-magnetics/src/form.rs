//! The axisymmetric A_phi weak form of magnetostatics, as an element form on the FEM core.
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
//! Newton systems are solved by sparse Cholesky ([`mrbrake_fem::workflow::newton`]).
//!
//! The `A/r` term makes the integrand non-polynomial on elements touching the axis; the quadrature
//! rules have interior points only (no evaluation at r = 0) and the default degree-2 rule gives the
//! optimal O(h²) L2 convergence of linear (P1) elements observed in the validation tests. DOFs on
//! the axis carry `A = 0`.
//!
//! Element order: the form is written once, generic over the Lagrange basis
//! ([`mrbrake_fem::discretisation::element::TriangleBasis`]: `ElementTriP1` with 3 DOFs, `ElementTriP2` with 6),
//! and the FEM core compiles it for each order. For quadratic elements `B` is linear in each
//! element (plus the `A/r` term) and the polynomial part of the r-weighted integrands has degree 3,
//! so they take the degree-4 rule (Dunavant 1985, 6 interior points) or higher.
//!
//! Linear materials (air, coils, non-magnetic steel: most of a mesh) have a constant element
//! Jacobian `ν G` with the geometric stiffness `G_ij = Σ_q w_q curl φ_i · curl φ_j`, and a residual
//! `ν G a − J f` with the unit load `f_i = Σ_q w_q φ_i`: both are integrated once
//! (when the form is built), so those elements need no quadrature loop during the Newton iterations,
//! and the core assembles their Jacobians once.

use mrbrake_fem::by_order;
use mrbrake_fem::discretisation::basis::{Basis, Element, QuadraturePoint};
use mrbrake_fem::discretisation::element::TriangleBasis;
use mrbrake_fem::workflow::assemble::{
    ElementForm, MAX_PACKED_LEN, element_matrices, element_vectors, packed_len, unpack_symmetric,
};
use mrbrake_materials::Magnetic;

/// `curl φ_i = (−∂φ_i/∂z, ∂φ_i/∂r + φ_i/r)` of the basis functions at a quadrature point.
#[inline(always)]
pub(crate) fn curls<const N: usize>(q: &QuadraturePoint<N>) -> [[f64; 2]; N] {
    let inv_r = 1.0 / q.point[0];
    let mut curl = [[0.0; 2]; N];
    for i in 0..N {
        curl[i] = [-q.grad[i][1], q.grad[i][0] + q.phi[i] * inv_r];
    }
    curl
}

/// Flux density `B = Σ A_i curl φ_i` from the curls at a point and the element's DOF values.
#[inline(always)]
pub(crate) fn flux_density<const N: usize>(curl: &[[f64; 2]; N], a: [f64; N]) -> [f64; 2] {
    let mut b = [0.0; 2];
    for i in 0..N {
        b[0] += a[i] * curl[i][0];
        b[1] += a[i] * curl[i][1];
    }
    b
}

/// The A_phi form of one problem: the material and source current density of every element, and
/// the integrated linear-element matrices.
#[derive(Debug, Clone)]
pub(crate) struct AphiForm {
    /// The materials, by region index.
    pub materials: Vec<Magnetic>,
    /// Region index of every element (into `materials`).
    pub element_region: Vec<u32>,
    /// Source current density J_phi (A/m²) of every element.
    pub current_density: Vec<f64>,
    /// Geometric stiffness `G` of every element, packed upper triangles.
    pub geometric_stiffness: Vec<f64>,
    /// Load per unit current density `f` of every element.
    pub unit_load: Vec<f64>,
    /// The hysteretic regions' law and per-point state, when a quasi-static hysteretic solve is
    /// set up ([`crate::hysteresis`]); `None`: every element takes its region's `Magnetic`.
    pub hysteresis: Option<Box<crate::hysteresis::HysteresisField>>,
}

impl AphiForm {
    /// The form with zero sources, integrating `G` and `f` on `basis`.
    pub fn new(basis: &Basis, materials: Vec<Magnetic>, element_region: Vec<u32>) -> Self {
        let (geometric_stiffness, unit_load) = by_order!(basis.order(), linear_matrices(basis));
        let current_density = vec![0.0; basis.n_elements()];
        Self {
            materials,
            element_region,
            current_density,
            geometric_stiffness,
            unit_load,
            hysteresis: None,
        }
    }

    /// The material of element `t`.
    #[inline(always)]
    pub fn material(&self, t: usize) -> &Magnetic {
        &self.materials[self.element_region[t] as usize]
    }
}

/// `G` and `f` of every element (module docs).
fn linear_matrices<E: TriangleBasis<N>, const N: usize>(basis: &Basis) -> (Vec<f64>, Vec<f64>) {
    let stiffness = element_matrices::<E, N>(basis, |_, q, g| {
        let curl = curls(q);
        let mut p = 0;
        for i in 0..N {
            for j in i..N {
                g[p] += q.weight * (curl[i][0] * curl[j][0] + curl[i][1] * curl[j][1]);
                p += 1;
            }
        }
    });
    let load = element_vectors::<E, N>(basis, |_, q, f| {
        for i in 0..N {
            f[i] += q.weight * q.phi[i];
        }
    });
    (stiffness, load)
}

impl ElementForm for AphiForm {
    #[inline]
    fn element<E: TriangleBasis<N>, const N: usize>(
        &self,
        element: &Element<'_, E, N>,
        local: [f64; N],
        residual: &mut [f64],
        jacobian: Option<&mut [f64]>,
    ) {
        let t = element.index;
        if let Some(field) = &self.hysteresis
            && let Some(params) = field.law(t)
        {
            let current_density = self.current_density[t];
            field.element_kernel(element, params, current_density, local, residual, jacobian);
            return;
        }
        let material = self.material(t);
        if let Magnetic::Linear { .. } = material {
            let nu = material.nu_and_dnu_db2(0.0).0;
            let g = &self.geometric_stiffness[packed_len(N) * t..packed_len(N) * (t + 1)];
            let f = &self.unit_load[N * t..N * (t + 1)];
            linear_element(nu, g, f, self.current_density[t], local, residual);
            return;
        }
        let current_density = self.current_density[t];
        element_kernel(element, material, current_density, local, residual, jacobian);
    }

    fn has_constant_jacobian(&self, index: usize) -> bool {
        let hysteretic = self.hysteresis.as_ref().is_some_and(|h| h.law(index).is_some());
        !hysteretic && !self.material(index).is_nonlinear()
    }

    fn constant_jacobian<E: TriangleBasis<N>, const N: usize>(
        &self,
        element: &Element<'_, E, N>,
        jacobian: &mut [f64],
    ) {
        let t = element.index;
        let nu = self.material(t).nu_and_dnu_db2(0.0).0;
        let g = &self.geometric_stiffness[packed_len(N) * t..packed_len(N) * (t + 1)];
        for (j, g) in jacobian.iter_mut().zip(g) {
            *j = nu * g;
        }
    }
}

/// Residual `ν G a − J f` of an element with a linear material (`g`: the packed upper triangle
/// of `G`; its Jacobian `ν G` is assembled once by the core).
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
    let (f, residual) = (&f[..N], &mut residual[..N]);
    let full = unpack_symmetric::<N>(&g[..packed_len(N)]);
    for i in 0..N {
        let mut ga = 0.0;
        for j in 0..N {
            ga += full[i][j] * a[j];
        }
        residual[i] = nu * ga - current_density * f[i];
    }
}

/// Element residual (`N` values) and, if `jacobian` is given, the packed upper triangle of the
/// element Jacobian, by quadrature (non-linear materials).
#[inline]
pub(crate) fn element_kernel<E: TriangleBasis<N>, const N: usize>(
    element: &Element<'_, E, N>,
    material: &Magnetic,
    current_density: f64,
    a: [f64; N],
    residual: &mut [f64],
    jacobian: Option<&mut [f64]>,
) {
    let mut res = [0.0; N];
    // Packed upper triangle (the first N(N+1)/2 entries are used).
    let mut jac = [0.0; MAX_PACKED_LEN];
    let want_jacobian = jacobian.is_some();
    let geometry = element.geometry();
    for q in element.points(&geometry) {
        let curl = curls(&q);
        let b = flux_density(&curl, a);
        let b2 = b[0] * b[0] + b[1] * b[1];
        let (nu, dnu) = material.nu_and_dnu_db2(b2);
        let mut b_dot_curl = [0.0; N];
        for i in 0..N {
            b_dot_curl[i] = b[0] * curl[i][0] + b[1] * curl[i][1];
            res[i] += q.weight * (nu * b_dot_curl[i] - current_density * q.phi[i]);
        }
        if want_jacobian {
            let mut p = 0;
            for i in 0..N {
                for j in i..N {
                    let curl_dot = curl[i][0] * curl[j][0] + curl[i][1] * curl[j][1];
                    jac[p] +=
                        q.weight * (nu * curl_dot + 2.0 * dnu * b_dot_curl[i] * b_dot_curl[j]);
                    p += 1;
                }
            }
        }
    }
    residual.copy_from_slice(&res);
    if let Some(out) = jacobian {
        out.copy_from_slice(&jac[..packed_len(N)]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::MarroccoCurve;
    use mrbrake_fem::discretisation::basis::Weighting;
    use mrbrake_fem::discretisation::dofs::ElementOrder;
    use mrbrake_fem::discretisation::element::{ElementTriP1, ElementTriP2};
    use mrbrake_fem::mesh::Mesh;
    use std::sync::Arc;

    /// One triangle near the knee of the iron curve.
    fn one_triangle(order: ElementOrder, degree: usize) -> Basis {
        let mesh = Mesh {
            nodes: vec![[0.01, 0.0], [0.02, 0.001], [0.012, 0.012]],
            triangles: vec![[0, 1, 2]],
            triangle_tags: vec![1],
            ..Mesh::default()
        };
        Basis::new(Arc::new(mesh), order, degree, Weighting::Axisymmetric)
    }

    /// The element Jacobian is the derivative of the element residual: central differences agree
    /// for every column, in saturated iron (where `dν/dB²` matters).
    fn check_jacobian<E: TriangleBasis<N>, const N: usize>(
        order: ElementOrder,
        degree: usize,
        a: [f64; N],
    ) {
        let basis = one_triangle(order, degree);
        let element = basis.element::<E, N>(0);
        let iron = Magnetic::NonLinear(Arc::new(MarroccoCurve::soft_iron()));
        let mut res = [0.0; N];
        let mut jac = vec![0.0; packed_len(N)];
        element_kernel(&element, &iron, 1e6, a, &mut res, Some(&mut jac));
        let full = unpack_symmetric::<N>(&jac);
        // The field is at the knee of the curve, where the `2 dν/dB² B⊗B` term matters.
        let geometry = element.geometry();
        let q = element.points(&geometry).next().unwrap();
        let b = flux_density(&curls(&q), a);
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
            element_kernel(&element, &iron, 1e6, ap, &mut rp, None);
            element_kernel(&element, &iron, 1e6, am, &mut rm, None);
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
        check_jacobian::<ElementTriP1, 3>(ElementOrder::P1, 2, [0.008, 0.022, 0.014]);
    }

    #[test]
    fn p2_jacobian_matches_finite_differences() {
        let a = [0.008, 0.022, 0.014, 0.017, 0.019, 0.0104];
        check_jacobian::<ElementTriP2, 6>(ElementOrder::P2, 4, a);
    }

    /// Uniform `B = B0 e_z` is `A = B0 r / 2`, in both spaces: B is exact at every point.
    fn check_uniform_field<E: TriangleBasis<N>, const N: usize>(
        order: ElementOrder,
        degree: usize,
    ) {
        let basis = one_triangle(order, degree);
        let element = basis.element::<E, N>(0);
        let geometry = element.geometry();
        let b0 = 0.3;
        let a = E::nodes().map(|l| 0.5 * b0 * geometry.point(l)[0]);
        for q in element.points(&geometry) {
            let b = flux_density(&curls(&q), a);
            assert!(b[0].abs() < 1e-12 && (b[1] - b0).abs() < 1e-12, "{b:?}");
        }
    }

    #[test]
    fn uniform_field_is_exact() {
        check_uniform_field::<ElementTriP1, 3>(ElementOrder::P1, 2);
        check_uniform_field::<ElementTriP2, 6>(ElementOrder::P2, 4);
    }

    /// The packed linear-element matrices give the same residual as the quadrature kernel.
    #[test]
    fn precomputed_linear_matrices_match_the_kernel() {
        let basis = one_triangle(ElementOrder::P2, 4);
        let material = Magnetic::Linear { mu_r: 3.0 };
        let mut form = AphiForm::new(&basis, vec![material.clone()], vec![0]);
        form.current_density[0] = 2e6;
        let a = [0.004, 0.011, 0.007, 0.0085, 0.0095, 0.0052];
        let (mut from_matrices, mut from_kernel) = ([0.0; 6], [0.0; 6]);
        let element = basis.element::<ElementTriP2, 6>(0);
        form.element(&element, a, &mut from_matrices, None);
        element_kernel(&element, &material, 2e6, a, &mut from_kernel, None);
        for i in 0..6 {
            assert!(
                (from_matrices[i] - from_kernel[i]).abs() <= 1e-12 * from_kernel[i].abs().max(1.0),
                "{from_matrices:?} vs {from_kernel:?}"
            );
        }
    }
}
