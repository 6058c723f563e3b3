//! Magnetic materials as the solver sees them: the material library's [`Magnetic`] law (linear, or
//! a non-linear [`Reluctivity`] `ν(B²) = H/B` with its derivative, which the Newton solver needs at
//! every quadrature point: the Jacobian coefficient is `ν I + 2 dν/dB² B⊗B`), re-exported here, and
//! the analytic [`MarroccoCurve`] the validation tests use because its inverse `B(H)` is an
//! independent bisection, not the same interpolation the solver uses.

pub use mrbrake_materials::{MU_0, Magnetic, Reluctivity};

/// Marrocco's analytic reluctivity (A. Marrocco, "Analyse numérique de problèmes d'électrotechnique",
/// Ann. Sc. Math. Québec 1 (1977) 271–296; also Hecht, Marrocco et al., IEEE Trans. Magn. 1990):
/// `ν(B²) = ν0 [ε + (c − ε) B^{2α} / (B^{2α} + τ)]`.
/// With `0 < ε < c` and `α >= 1` ν increases with B² so `H(B) = ν B` is strictly monotone.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MarroccoCurve {
    /// `ε = 1/μr` at low field.
    pub epsilon: f64,
    /// `c`, the saturated value of `ν/ν0` (1 for iron: μr → 1).
    pub c: f64,
    /// Exponent `α` (on B², so B^{2α}).
    pub alpha: i32,
    /// `τ` (T^{2α}): the knee sits where `B^{2α} ≈ τ`.
    pub tau: f64,
}

impl MarroccoCurve {
    /// A soft-iron-like test curve: μr = 2000 at low field, knee near 1.6–2 T, μr → 1 when saturated.
    pub fn soft_iron() -> Self {
        Self { epsilon: 1.0 / 2000.0, c: 1.0, alpha: 5, tau: 1024.0 }
    }

    /// `B(H)` by bisection of the monotone `H(B) = ν(B²) B` (T, for `H >= 0` in A/m).
    pub fn b_of_h(&self, h: f64) -> f64 {
        let (mut lo, mut hi) = (0.0, MU_0 * h.abs() / self.epsilon.min(self.c) + 1e-12);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if self.h_of_b(mid) < h.abs() { lo = mid } else { hi = mid }
        }
        0.5 * (lo + hi)
    }
}

impl Reluctivity for MarroccoCurve {
    fn b_of_h(&self, h: f64) -> f64 {
        MarroccoCurve::b_of_h(self, h)
    }

    fn nu_and_dnu_db2(&self, b2: f64) -> (f64, f64) {
        let nu0 = 1.0 / MU_0;
        let s = b2.max(0.0);
        let sa = s.powi(self.alpha);
        let denominator = sa + self.tau;
        let nu = nu0 * (self.epsilon + (self.c - self.epsilon) * sa / denominator);
        let dsa =
            if self.alpha == 0 { 0.0 } else { f64::from(self.alpha) * s.powi(self.alpha - 1) };
        let dnu = nu0 * (self.c - self.epsilon) * dsa * self.tau / (denominator * denominator);
        (nu, dnu)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn marrocco_derivative_matches_finite_difference() {
        let curve = MarroccoCurve::soft_iron();
        for b in [0.1, 0.8, 1.5, 2.0, 3.0] {
            let b2: f64 = b * b;
            let h = 1e-6 * b2;
            let fd = (curve.nu_and_dnu_db2(b2 + h).0 - curve.nu_and_dnu_db2(b2 - h).0) / (2.0 * h);
            let exact = curve.nu_and_dnu_db2(b2).1;
            assert!((fd - exact).abs() <= 1e-6 * exact.abs().max(1.0), "B={b}: {fd} vs {exact}");
        }
    }

    #[test]
    fn marrocco_inverse_round_trips() {
        let curve = MarroccoCurve::soft_iron();
        for b in [0.01, 0.5, 1.2, 1.9, 2.6] {
            let h = curve.h_of_b(b);
            assert!((curve.b_of_h(h) - b).abs() < 1e-10);
        }
    }

    #[test]
    fn energy_density_matches_closed_form_for_linear_and_fine_sum() {
        let air = Magnetic::air();
        assert!((air.energy_density(1.0) - 0.5 / MU_0).abs() < 1e-6);
        let iron = Magnetic::NonLinear(std::sync::Arc::new(MarroccoCurve::soft_iron()));
        // Reference: fine midpoint sum of H(B).
        let b = 2.2;
        let n = 200_000;
        let curve = MarroccoCurve::soft_iron();
        let fine: f64 = (0..n).map(|i| curve.h_of_b(b * (i as f64 + 0.5) / n as f64)).sum::<f64>()
            * b
            / n as f64;
        assert!((iron.energy_density(b) - fine).abs() < 1e-6 * fine);
    }
}
