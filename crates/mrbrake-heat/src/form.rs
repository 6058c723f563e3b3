//! The weak form of axisymmetric heat conduction as an [`ElementForm`] on the FEM core.
//!
//! Multiplying `ρc ∂T/∂t − ∇·(k ∇T) − q(T) = 0` by a test function `φ_i`, integrating over the
//! ring swept by each triangle (the core's axisymmetric weight carries `r`; the common factor 2π
//! is dropped) and integrating the conduction term by parts (e.g. Lewis, Nithiarasu and Seetharamu,
//! *Fundamentals of the Finite Element Method for Heat and Fluid Flow*, Wiley 2004, §3.2 and §6.3):
//!
//! `R_i(T) = ∫ [k_r ∂_rT ∂_rφ_i + k_z ∂_zT ∂_zφ_i − (q0 + q1 T) φ_i + ρc ρ (T − h) φ_i] r dr dz`
//!
//! plus the boundary fluxes (added by the solver through the core's `EdgeFlux`). The source is
//! affine in `T` (a Joule loss at the local temperature, see [`crate::problem::Source::affine`]),
//! the last term is the time derivative of a step of the core's integrator,
//! `Ṫ ≈ ρ (T − h)` with the scheme's rate `ρ` and history `h` (`mrbrake_fem::workflow::time`:
//! implicit Euler `ρ = 1/Δt, h = T_n`; BDF2 `ρ = 3/(2Δt), h = (4 T_n − T_{n−1})/3` at a constant
//! step; Hairer & Wanner, *Solving ODEs II*, §III.1). The Jacobian
//! `∫ [k ∇φ_j·∇φ_i − q1 φ_j φ_i + ρc ρ φ_j φ_i] r dr dz` does not depend on `T`: every element
//! is linear and the core sums it once. It is symmetric, and positive definite unless the Joule
//! feedback `q1` outweighs conduction and cooling (thermal runaway).

use mrbrake_fem::discretisation::basis::{Element, QuadraturePoint};
use mrbrake_fem::discretisation::element::TriangleBasis;
use mrbrake_fem::workflow::assemble::{ElementForm, MAX_PACKED_LEN, packed_len};

/// The coefficients of one region.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coefficients {
    /// Radial conductivity \[W/(m·K)\].
    pub k_radial: f64,
    /// Axial conductivity \[W/(m·K)\].
    pub k_axial: f64,
    /// Heat capacity per volume \[J/(m³·K)\].
    pub rho_c: f64,
    /// Constant part of the source \[W/m³\].
    pub q0: f64,
    /// Temperature coefficient of the source \[W/(m³·K)\].
    pub q1: f64,
}

/// The time-derivative term of a step: `ρc ρ (T − h)`.
#[derive(Debug, Clone, PartialEq)]
pub struct Capacity {
    /// The scheme's rate `ρ` \[1/s\].
    pub rate: f64,
    /// The history `h` at every DOF \[K\].
    pub history: Vec<f64>,
}

/// The heat form: per-element coefficients and, for a time step, the capacity term.
#[derive(Debug, Clone)]
pub struct HeatForm {
    /// Coefficients per region, indexed by `element_region`.
    pub coefficients: Vec<Coefficients>,
    /// For each element, its index in `coefficients`.
    pub element_region: Vec<usize>,
    /// The time-derivative term, or `None` for a steady problem.
    pub capacity: Option<Capacity>,
}

/// `T` and `∇T` at a quadrature point from the element's DOF values.
#[inline(always)]
pub fn value_and_gradient<const N: usize>(
    q: &QuadraturePoint<N>,
    local: &[f64; N],
) -> (f64, [f64; 2]) {
    let mut t = 0.0;
    let mut grad = [0.0; 2];
    for i in 0..N {
        t += local[i] * q.phi[i];
        grad[0] += local[i] * q.grad[i][0];
        grad[1] += local[i] * q.grad[i][1];
    }
    (t, grad)
}

impl HeatForm {
    /// The coefficients of element `index`.
    #[inline(always)]
    pub fn coefficients_of(&self, index: usize) -> &Coefficients {
        &self.coefficients[self.element_region[index]]
    }

    /// The capacity term's rate `ρ (T − h)` at a point (0 for a steady problem).
    #[inline(always)]
    pub fn rate<const N: usize>(&self, q: &QuadraturePoint<N>, t: f64, history: &[f64; N]) -> f64 {
        match &self.capacity {
            None => 0.0,
            Some(c) => {
                let h: f64 = (0..N).map(|i| history[i] * q.phi[i]).sum();
                c.rate * (t - h)
            }
        }
    }

    /// The history values of an element's DOFs (zeros for a steady problem).
    #[inline(always)]
    pub fn history_of<const N: usize>(&self, dofs: &[usize; N]) -> [f64; N] {
        match &self.capacity {
            None => [0.0; N],
            Some(c) => dofs.map(|d| c.history[d]),
        }
    }
}

impl ElementForm for HeatForm {
    fn element<E: TriangleBasis<N>, const N: usize>(
        &self,
        element: &Element<'_, E, N>,
        local: [f64; N],
        residual: &mut [f64],
        jacobian: Option<&mut [f64]>,
    ) {
        let c = *self.coefficients_of(element.index);
        let history = self.history_of(element.dofs());
        let rate = self.capacity.as_ref().map_or(0.0, |cap| cap.rate);
        let (mut res, mut jac) = ([0.0; N], [0.0; MAX_PACKED_LEN]);
        let want_jacobian = jacobian.is_some();
        let geometry = element.geometry();
        for q in element.points(&geometry) {
            let (t, grad) = value_and_gradient(&q, &local);
            let flux = [c.k_radial * grad[0], c.k_axial * grad[1]];
            let volumetric = c.rho_c * self.rate(&q, t, &history) - (c.q0 + c.q1 * t);
            for i in 0..N {
                res[i] += q.weight
                    * (flux[0] * q.grad[i][0] + flux[1] * q.grad[i][1] + volumetric * q.phi[i]);
            }
            if want_jacobian {
                let mass = c.rho_c * rate - c.q1;
                let mut p = 0;
                for i in 0..N {
                    for j in i..N {
                        let stiffness = c.k_radial * q.grad[i][0] * q.grad[j][0]
                            + c.k_axial * q.grad[i][1] * q.grad[j][1];
                        jac[p] += q.weight * (stiffness + mass * q.phi[i] * q.phi[j]);
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

    fn has_constant_jacobian(&self, _index: usize) -> bool {
        true
    }

    fn constant_jacobian<E: TriangleBasis<N>, const N: usize>(
        &self,
        element: &Element<'_, E, N>,
        jacobian: &mut [f64],
    ) {
        let mut residual = [0.0; N];
        self.element(element, [0.0; N], &mut residual, Some(jacobian));
    }
}
