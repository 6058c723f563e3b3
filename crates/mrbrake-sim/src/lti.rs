//! Linear time-invariant models: a continuous-time transfer function
//! ([`TransferFunction`], owned by `mrbrake-sysid`), discretised **exactly** for a piecewise-constant
//! (zero-order-hold) input and simulated sample by sample.
//!
//! For ẋ = A x + B u, y = C x + D u and an input held constant over each step Δt, the exact update is
//! (Franklin, Powell & Workman, *Digital Control of Dynamic Systems*, §4.3.3)
//!
//! ```text
//! x\[k+1\] = Φ x\[k\] + Γ u\[k\],  Φ = e^{AΔt},  Γ = ∫₀^Δt e^{Aσ} dσ B,
//! ```
//!
//! both read off one matrix exponential exp([[A, B], [0, 0]]·Δt) (Van Loan 1978). The realisation is the
//! controllable canonical form of G in a frequency-scaled variable p = s/ω_s with
//! ω_s = |d₀/d_n|^{1/n}, which keeps the companion matrix's entries near 1 even for the thesis's widely
//! spread poles (63 and 887 rad/s); the exponential is computed by scaling and squaring a Taylor series
//! (Moler & Van Loan 2003, method 3).
//!
//! ```
//! use mrbrake_sim::lti::DiscreteStateSpace;
//! use mrbrake_sysid::transfer_function::TransferFunction;
//! // First-order lag 1/(0.01 s + 1) stepped at 1 kHz: y(t) = 1 − e^{−t/0.01}.
//! let g = TransferFunction::new(vec![1.0], vec![0.01, 1.0]).unwrap();
//! let mut sys = DiscreteStateSpace::zoh(&g, 1e-3).unwrap();
//! let y: Vec<f64> = (0..=10).map(|_| sys.step(1.0)).collect();
//! assert!((y[10] - (1.0 - (-1.0f64).exp())).abs() < 1e-12);
//! ```
//! (`step` returns the output at the start of the step, then advances the state: `y[k] = C x[k] + D u[k]`.)

use mrbrake_sysid::transfer_function::TransferFunction;

use crate::SimError;

/// The exactly discretised (zero-order-hold) state-space model of a [`TransferFunction`], with its
/// state.
///
/// `step` allocates nothing, so the model can run inside a real-time or haptic loop.
#[derive(Debug, Clone)]
pub struct DiscreteStateSpace {
    n: usize,
    dt_s: f64,
    /// Φ, row-major n×n.
    phi: Vec<f64>,
    gamma: Vec<f64>,
    c: Vec<f64>,
    d: f64,
    /// Lowest coefficient of the monic scaled denominator (for the steady state).
    alpha0: f64,
    x: Vec<f64>,
    scratch: Vec<f64>,
}

impl DiscreteStateSpace {
    /// Discretises `tf` exactly for a zero-order-hold input with step `dt_s`.
    pub fn zoh(tf: &TransferFunction, dt_s: f64) -> Result<Self, SimError> {
        if !(dt_s > 0.0 && dt_s.is_finite()) {
            let e =
                mrbrake_error::FieldError::out_of_range("dt", format!("{dt_s} s"), "finite, > 0 s");
            return Err(e.into());
        }
        let n = tf.order();
        let den_asc: Vec<f64> = tf.denominator.iter().rev().copied().collect();
        let mut num_asc: Vec<f64> = tf.numerator.iter().rev().copied().collect();
        num_asc.resize(n + 1, 0.0);
        if n == 0 {
            return Ok(Self {
                n,
                dt_s,
                phi: vec![],
                gamma: vec![],
                c: vec![],
                d: num_asc[0] / den_asc[0],
                alpha0: 1.0,
                x: vec![],
                scratch: vec![],
            });
        }
        // Frequency scale from the lowest non-zero denominator coefficient.
        let k0 = den_asc.iter().position(|c| c.abs() > 0.0).unwrap_or(0);
        let omega_s =
            if k0 < n { (den_asc[k0] / den_asc[n]).abs().powf(1.0 / (n - k0) as f64) } else { 1.0 };
        let omega_s = if omega_s.is_finite() && omega_s > 0.0 { omega_s } else { 1.0 };
        // Coefficients of p: d_i ω_sⁱ, made monic.
        let lead = den_asc[n] * omega_s.powi(n as i32);
        let alpha: Vec<f64> = (0..=n).map(|i| den_asc[i] * omega_s.powi(i as i32) / lead).collect();
        let beta: Vec<f64> = (0..=n).map(|i| num_asc[i] * omega_s.powi(i as i32) / lead).collect();
        let d = beta[n];
        let r: Vec<f64> = (0..n).map(|i| beta[i] - d * alpha[i]).collect();
        // Augmented matrix [[A', B'], [0, 0]]·ω_s Δt, size n+1, row-major.
        let size = n + 1;
        let h = omega_s * dt_s;
        let mut m = vec![0.0; size * size];
        for i in 0..n - 1 {
            m[i * size + i + 1] = h;
        }
        for j in 0..n {
            m[(n - 1) * size + j] = -alpha[j] * h;
        }
        m[(n - 1) * size + n] = h;
        let e = expm(&m, size);
        let mut phi = vec![0.0; n * n];
        let mut gamma = vec![0.0; n];
        for i in 0..n {
            for j in 0..n {
                phi[i * n + j] = e[i * size + j];
            }
            gamma[i] = e[i * size + n];
        }
        if phi.iter().chain(&gamma).any(|v| !v.is_finite()) {
            return Err(mrbrake_error::FieldError::new(
                "tf",
                "the discretisation overflowed (unstable or badly scaled model)",
            )
            .into());
        }
        Ok(Self {
            n,
            dt_s,
            phi,
            gamma,
            c: r,
            d,
            alpha0: alpha[0],
            x: vec![0.0; n],
            scratch: vec![0.0; n],
        })
    }

    /// Output for input `u` at the current state, then advances one step: `y[k] = C x[k] + D u[k]`,
    /// x\[k+1\] = Φ x\[k\] + Γ u\[k\].
    pub fn step(&mut self, u: f64) -> f64 {
        let y = self.output(u);
        let n = self.n;
        for i in 0..n {
            let row = &self.phi[i * n..(i + 1) * n];
            let mut s = self.gamma[i] * u;
            for j in 0..n {
                s += row[j] * self.x[j];
            }
            self.scratch[i] = s;
        }
        std::mem::swap(&mut self.x, &mut self.scratch);
        y
    }

    /// Output C x + D u at the current state (no state change).
    pub fn output(&self, u: f64) -> f64 {
        self.c.iter().zip(&self.x).map(|(c, x)| c * x).sum::<f64>() + self.d * u
    }

    /// Sets the state to the equilibrium for a constant input `u` (so a simulation starts without a
    /// transient); does nothing for a model with a pole at the origin.
    pub fn set_steady_state(&mut self, u: f64) {
        self.x.iter_mut().for_each(|v| *v = 0.0);
        if self.n > 0 && self.alpha0.abs() > 0.0 {
            // Controllable canonical form: x₁ = u/α₀, the derivatives x₂…x_n vanish.
            self.x[0] = u / self.alpha0;
        }
    }

    /// Zero state.
    pub fn reset(&mut self) {
        self.x.iter_mut().for_each(|v| *v = 0.0);
    }

    /// Model order.
    pub fn order(&self) -> usize {
        self.n
    }

    /// Time step, s.
    pub fn dt_s(&self) -> f64 {
        self.dt_s
    }

    /// The state (scaled controllable canonical coordinates).
    pub fn state(&self) -> &[f64] {
        &self.x
    }
}

/// Matrix exponential of a small row-major `size × size` matrix: scaling and squaring of a Taylor
/// series (Moler & Van Loan 2003, method 3). The matrix is scaled by 2^−s until its 1-norm is ≤ 1/2,
/// so 20 terms reach machine precision (the series stops once a term's largest entry is below
/// 1e-18, at most 30 terms), then squared s times. The one matrix exponential of mrbrake: the
/// transfer-function discretisation here and the haptic brakes' torque lag
/// ([`crate::haptic::TorqueLag::discretise`]) both use it. A matrix with a non-finite entry or
/// norm gives a matrix of NaN (no finite answer exists), never an endless squaring loop.
pub fn expm(m: &[f64], size: usize) -> Vec<f64> {
    let norm = (0..size)
        .map(|j| (0..size).map(|i| m[i * size + j].abs()).sum::<f64>())
        .fold(0.0, f64::max);
    if !norm.is_finite() {
        // An overflowed (or NaN) matrix: no finite exponential; callers refuse non-finite
        // results. Without this the squaring count below would saturate at i32::MAX.
        return vec![f64::NAN; size * size];
    }
    // At most ~1026 squarings for a finite norm (≤ 1.8e308 = 2^1024).
    let squarings = if norm > 0.5 { (norm / 0.5).log2().ceil() as i32 } else { 0 };
    let scale = 0.5f64.powi(squarings);
    let a: Vec<f64> = m.iter().map(|v| v * scale).collect();
    let mul = |x: &[f64], y: &[f64]| {
        let mut z = vec![0.0; size * size];
        for i in 0..size {
            for k in 0..size {
                let xik = x[i * size + k];
                for j in 0..size {
                    z[i * size + j] += xik * y[k * size + j];
                }
            }
        }
        z
    };
    let mut result = vec![0.0; size * size];
    let mut term = vec![0.0; size * size];
    for i in 0..size {
        result[i * size + i] = 1.0;
        term[i * size + i] = 1.0;
    }
    for k in 1..=30 {
        term = mul(&term, &a).into_iter().map(|v| v / k as f64).collect();
        let tn = term.iter().fold(0.0_f64, |acc, v| acc.max(v.abs()));
        for (r, t) in result.iter_mut().zip(&term) {
            *r += t;
        }
        if tn < 1e-18 {
            break;
        }
    }
    for _ in 0..squarings {
        result = mul(&result, &result);
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrbrake_error::Kind as _;

    #[test]
    fn second_order_step_matches_closed_form() {
        // Thesis brake 1 (5.5), real poles p1, p2: y(t) = 1 − (p2 e^{−p1 t} − p1 e^{−p2 t})/(p2 − p1).
        let (a2, a1): (f64, f64) = (1.791e-5, 0.01702);
        let disc = (a1 * a1 - 4.0 * a2).sqrt();
        let p1 = (a1 - disc) / (2.0 * a2);
        let p2 = (a1 + disc) / (2.0 * a2);
        let g = TransferFunction::new(vec![1.0], vec![a2, a1, 1.0]).unwrap();
        let mut sys = DiscreteStateSpace::zoh(&g, 1e-3).unwrap();
        for k in 0..200 {
            let y = sys.step(1.0);
            let t = k as f64 * 1e-3;
            let exact = 1.0 - (p2 * (-p1 * t).exp() - p1 * (-p2 * t).exp()) / (p2 - p1);
            assert!((y - exact).abs() < 1e-12, "t = {t}: {y} vs {exact}");
        }
    }

    #[test]
    fn feedthrough_and_steady_state() {
        // (s + 2)/(s + 1): step response 2 − e^{−t}; steady state for u = 3 is 6.
        let g = TransferFunction::new(vec![1.0, 2.0], vec![1.0, 1.0]).unwrap();
        let mut sys = DiscreteStateSpace::zoh(&g, 0.01).unwrap();
        for k in 0..300 {
            let y = sys.step(1.0);
            let t = k as f64 * 0.01;
            assert!((y - (2.0 - (-t).exp())).abs() < 1e-12);
        }
        sys.set_steady_state(3.0);
        for _ in 0..10 {
            assert!((sys.step(3.0) - 6.0).abs() < 1e-12);
        }
    }

    #[test]
    fn integrator_ramps() {
        let g = TransferFunction::new(vec![2.0], vec![1.0, 0.0]).unwrap();
        let mut sys = DiscreteStateSpace::zoh(&g, 0.1).unwrap();
        for k in 0..50 {
            let y = sys.step(1.0);
            assert!((y - 2.0 * k as f64 * 0.1).abs() < 1e-12);
        }
    }

    #[test]
    fn dc_motor_model_is_stable_and_reaches_its_gain() {
        // (5.1): 10.35/(2e-5 s² + 0.000368 s + 1), lightly damped at 224 rad/s.
        let g = TransferFunction::new(vec![10.35], vec![2e-5, 0.000368, 1.0]).unwrap();
        let mut sys = DiscreteStateSpace::zoh(&g, 1e-3).unwrap();
        let mut y = 0.0;
        for _ in 0..5000 {
            y = sys.step(1.0);
        }
        assert!((y - 10.35).abs() < 1e-9);
    }

    #[test]
    fn bad_time_step_is_an_input_error() {
        let g = TransferFunction::new(vec![1.0], vec![1.0, 1.0]).unwrap();
        assert!(DiscreteStateSpace::zoh(&g, 0.0).unwrap_err().is_input_error());
    }

    /// Hostile coefficients (a subnormal leading coefficient, a huge constant term) overflow the
    /// scaled matrix: refused as input at once, where the squaring count used to saturate and spin.
    #[test]
    fn degenerate_denominators_are_refused_not_spun_on() {
        for den in [vec![5e-324, 0.01702, 1.0], vec![2e-5, 0.000368, 1e307], vec![1e-300, 1e300]] {
            let g = TransferFunction::new(vec![1.0], den.clone()).unwrap();
            let e = DiscreteStateSpace::zoh(&g, 1e-3).unwrap_err();
            assert!(e.is_input_error(), "{den:?}: {e}");
        }
        assert!(expm(&[f64::INFINITY, 0.0, 0.0, 1.0], 2).iter().all(|v| v.is_nan()));
    }

    #[test]
    fn exponential_of_a_rotation_generator_is_the_rotation() {
        // exp([[0, θ], [−θ, 0]]) = [[cos θ, sin θ], [−sin θ, cos θ]], with θ large enough to square.
        let theta: f64 = 3.0;
        let e = expm(&[0.0, theta, -theta, 0.0], 2);
        let expected = [theta.cos(), theta.sin(), -theta.sin(), theta.cos()];
        for (a, b) in e.iter().zip(expected) {
            assert!((a - b).abs() < 1e-14, "{e:?}");
        }
    }
}
