//! The time-discrete form of one step: the magnetostatic A_phi form plus the eddy-current term.
//!
//! A step of a backward-differentiation scheme replaces `ȧ` by `ρ (a − h)`, with the rate
//! `ρ = γ/Δt` and the history `h` of the scheme (implicit Euler: `γ = 1`, `h = a_n`; BDF2, see
//! [`super::transient`]). Element by element the residual gains `ρ σ_e M_e (a_e − h_e)` and the
//! Jacobian `ρ σ_e M_e`, constant for a fixed step: elements of linear materials keep a constant
//! Jacobian, so a linear problem at a fixed step is factorised once.

use mrbrake_fem::discretisation::basis::Element;
use mrbrake_fem::discretisation::element::TriangleBasis;
use mrbrake_fem::workflow::assemble::{ElementForm, packed_len, unpack_symmetric};

use crate::form::AphiForm;

/// The form of one time step.
pub(crate) struct TransientForm<'a> {
    pub statics: &'a AphiForm,
    /// σ of every element.
    pub sigma: &'a [f64],
    /// Packed `∫ φ_i φ_j r` of every element.
    pub mass: &'a [f64],
    /// The history `h` at every DOF.
    pub history: &'a [f64],
    /// The rate `ρ = γ/Δt` (1/s).
    pub rate: f64,
}

impl TransientForm<'_> {
    fn mass_of<const N: usize>(&self, t: usize) -> [[f64; N]; N] {
        unpack_symmetric::<N>(&self.mass[packed_len(N) * t..packed_len(N) * (t + 1)])
    }
}

impl ElementForm for TransientForm<'_> {
    #[inline]
    fn element<E: TriangleBasis<N>, const N: usize>(
        &self,
        element: &Element<'_, E, N>,
        local: [f64; N],
        residual: &mut [f64],
        mut jacobian: Option<&mut [f64]>,
    ) {
        let t = element.index;
        self.statics.element(element, local, residual, jacobian.as_deref_mut());
        let sigma = self.sigma[t];
        if sigma <= 0.0 {
            return;
        }
        let coefficient = self.rate * sigma;
        let m = self.mass_of::<N>(t);
        let history = element.dofs().map(|d| self.history[d]);
        for i in 0..N {
            let mut mv = 0.0;
            for j in 0..N {
                mv += m[i][j] * (local[j] - history[j]);
            }
            residual[i] += coefficient * mv;
        }
        if self.statics.has_constant_jacobian(t) {
            return;
        }
        if let Some(jacobian) = jacobian {
            add_packed(jacobian, coefficient, &m);
        }
    }

    fn has_constant_jacobian(&self, index: usize) -> bool {
        self.statics.has_constant_jacobian(index)
    }

    fn constant_jacobian<E: TriangleBasis<N>, const N: usize>(
        &self,
        element: &Element<'_, E, N>,
        jacobian: &mut [f64],
    ) {
        self.statics.constant_jacobian(element, jacobian);
        let sigma = self.sigma[element.index];
        if sigma > 0.0 {
            add_packed(jacobian, self.rate * sigma, &self.mass_of::<N>(element.index));
        }
    }
}

/// `packed += c · m` on the upper triangle.
fn add_packed<const N: usize>(packed: &mut [f64], c: f64, m: &[[f64; N]; N]) {
    let mut p = 0;
    for i in 0..N {
        for j in i..N {
            packed[p] += c * m[i][j];
            p += 1;
        }
    }
}
