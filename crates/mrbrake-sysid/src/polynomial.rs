//! Real polynomials: evaluation, well-conditioned least-squares fits and complex roots.
//!
//! Fits scale the abscissa to [−1, 1] before building the Vandermonde matrix (its condition number then
//! grows like a few times 2ⁿ instead of (x_max)ⁿ·…), solve by Householder QR, and only at the end expand
//! the result back to ascending powers of the physical variable, which is the form the JSON files carry.

use mrbrake_error::FieldError;
use num_complex::Complex64;

use crate::SysidError;
use crate::complex::{div, recip};
use crate::linalg::{Matrix, least_squares};

/// A real polynomial `c₀ + c₁ x + … + cₙ xⁿ` (coefficients in ascending powers).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Polynomial {
    /// Coefficients in ascending powers of x.
    pub coefficients: Vec<f64>,
}

impl Polynomial {
    /// A polynomial from coefficients in ascending powers.
    pub fn new(coefficients: Vec<f64>) -> Self {
        Self { coefficients }
    }

    /// Value at `x` (Horner's scheme).
    pub fn eval(&self, x: f64) -> f64 {
        self.coefficients.iter().rev().fold(0.0, |acc, c| acc * x + c)
    }

    /// Value at a complex argument.
    pub fn eval_complex(&self, z: Complex64) -> Complex64 {
        self.coefficients
            .iter()
            .rev()
            .fold(Complex64::default(), |acc, c| acc * z + Complex64::new(*c, 0.0))
    }

    /// The derivative polynomial.
    pub fn derivative(&self) -> Self {
        Self::new(self.coefficients.iter().enumerate().skip(1).map(|(k, c)| k as f64 * c).collect())
    }

    /// Degree (number of coefficients − 1; 0 for an empty polynomial).
    pub fn degree(&self) -> usize {
        self.coefficients.len().saturating_sub(1)
    }

    /// `p(α x + β)` expanded in ascending powers of x.
    fn compose_affine(&self, alpha: f64, beta: f64) -> Self {
        let mut result: Vec<f64> = Vec::with_capacity(self.coefficients.len());
        for c in self.coefficients.iter().rev() {
            // result ← result·(α x + β) + c
            let mut next = vec![0.0; result.len() + 1];
            for (k, r) in result.iter().enumerate() {
                next[k] += r * beta;
                next[k + 1] += r * alpha;
            }
            next[0] += c;
            result = next;
        }
        Self::new(result)
    }
}

/// Least-squares polynomial of degree `order` through `(x, y)`, returned in ascending powers of x.
///
/// The abscissa is mapped to u = (2x − (a + b))/(b − a) ∈ [−1, 1] for the solve (see module docs).
pub fn fit(x: &[f64], y: &[f64], order: usize) -> Result<Polynomial, SysidError> {
    if x.len() != y.len() {
        return Err(FieldError::new("y", "polynomial fit: one value per abscissa")
            .with_value(format!("{} values", y.len()))
            .with_allowed(format!("{} values", x.len()))
            .into());
    }
    if x.len() < order + 1 {
        return Err(FieldError::new(
            "x",
            format!("polynomial fit of order {order}: too few points"),
        )
        .with_value(x.len())
        .with_allowed(format!(">= {} points", order + 1))
        .into());
    }
    let (lo, hi) =
        x.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| (l.min(*v), h.max(*v)));
    if (hi - lo).is_nan() || hi - lo <= 0.0 {
        return Err(FieldError::new("x", "polynomial fit: the abscissae span no interval").into());
    }
    let alpha = 2.0 / (hi - lo);
    let beta = -(hi + lo) / (hi - lo);
    let mut a = Matrix::zeros(x.len(), order + 1);
    for (i, xi) in x.iter().enumerate() {
        let u = alpha * xi + beta;
        let mut p = 1.0;
        for k in 0..=order {
            a.set(i, k, p);
            p *= u;
        }
    }
    let c = least_squares(&a, y)?;
    Ok(Polynomial::new(c).compose_affine(alpha, beta))
}

/// Complex64 roots of the polynomial with coefficients in **descending** powers (`c[0] sⁿ + … + c[n]`).
///
/// Degree 1 and 2 use closed forms (the quadratic in its cancellation-free form); higher degrees use the
/// Aberth–Ehrlich simultaneous iteration (Aberth 1973, Math. Comp. 27:339) followed by a Newton polish.
pub fn roots_descending(c: &[f64]) -> Result<Vec<Complex64>, SysidError> {
    let first = c.iter().position(|v| v.abs() > 0.0).unwrap_or(c.len());
    let c = &c[first..];
    if c.len() <= 1 {
        return Ok(vec![]);
    }
    let n = c.len() - 1;
    if n == 1 {
        return Ok(vec![Complex64::new(-c[1] / c[0], 0.0)]);
    }
    if n == 2 {
        let (a, b, cc) = (c[0], c[1], c[2]);
        let disc = b * b - 4.0 * a * cc;
        if disc >= 0.0 {
            let q = -0.5 * (b + b.signum() * disc.sqrt());
            let q = if q.abs() > 0.0 { q } else { -0.5 * disc.sqrt() };
            let r1 = q / a;
            let r2 = if q.abs() > 0.0 { cc / q } else { 0.0 };
            let (lo, hi) = if r1.abs() <= r2.abs() { (r1, r2) } else { (r2, r1) };
            return Ok(vec![Complex64::new(lo, 0.0), Complex64::new(hi, 0.0)]);
        }
        let re = -b / (2.0 * a);
        let im = (-disc).sqrt() / (2.0 * a.abs());
        return Ok(vec![Complex64::new(re, im), Complex64::new(re, -im)]);
    }
    let ascending = Polynomial::new(c.iter().rev().copied().collect());
    let deriv = ascending.derivative();
    // Initial guesses on a circle of the geometric-mean root radius, at irregular angles.
    let radius = (c[n].abs() / c[0].abs()).powf(1.0 / n as f64).max(1e-12);
    let mut z: Vec<Complex64> = (0..n)
        .map(|k| {
            Complex64::from_polar(
                radius,
                2.0 * std::f64::consts::PI * (k as f64 + 0.25) / n as f64 + 0.4,
            )
        })
        .collect();
    let mut history = Vec::new();
    for _ in 0..500 {
        let mut max_step = 0.0_f64;
        for i in 0..n {
            let ratio = div(ascending.eval_complex(z[i]), deriv.eval_complex(z[i]));
            let mut sum = Complex64::default();
            for j in 0..n {
                if j != i {
                    sum += recip(z[i] - z[j]);
                }
            }
            let step = div(ratio, Complex64::new(1.0, 0.0) - ratio * sum);
            if step.is_finite() {
                z[i] -= step;
                max_step = max_step.max(step.norm() / z[i].norm().max(1e-300));
            }
        }
        history.push(max_step);
        if max_step < 1e-15 {
            break;
        }
    }
    if z.iter().any(|r| !r.is_finite()) || history.last().is_none_or(|s| *s > 1e-8) {
        return Err(SysidError::numerical(
            "polynomial roots: the Aberth iteration did not converge",
            history,
        ));
    }
    for r in &mut z {
        let step = div(ascending.eval_complex(*r), deriv.eval_complex(*r));
        if step.is_finite() {
            *r -= step;
        }
        if r.im.abs() <= 1e-12 * r.norm() {
            r.im = 0.0;
        }
    }
    z.sort_by(|a, b| a.norm().total_cmp(&b.norm()));
    Ok(z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fit_recovers_exact_quintic_in_ascending_powers() {
        let truth = Polynomial::new(vec![0.15, 3.2, -1.1, 0.4, -0.05, 0.003]);
        let x: Vec<f64> = (0..=200).map(|i| i as f64 * 0.01).collect();
        let y: Vec<f64> = x.iter().map(|v| truth.eval(*v)).collect();
        let p = fit(&x, &y, 5).unwrap();
        for (a, b) in p.coefficients.iter().zip(&truth.coefficients) {
            assert!((a - b).abs() < 1e-9, "{a} vs {b}");
        }
    }

    #[test]
    fn quadratic_roots_of_thesis_brake_1() {
        // (5.5): 1.791e-5 s² + 0.01702 s + 1.
        let r = roots_descending(&[1.791e-5, 0.01702, 1.0]).unwrap();
        assert!((r[0].re + 62.93).abs() < 0.01 && (r[1].re + 887.38).abs() < 0.01, "{r:?}");
    }

    #[test]
    fn aberth_finds_roots_of_product() {
        // (s+1)(s+10)(s²+2s+5) = s⁴ + 13 s³ + 37 s² + 75 s + 50
        let r = roots_descending(&[1.0, 13.0, 37.0, 75.0, 50.0]).unwrap();
        let expect = [
            Complex64::new(-1.0, 0.0),
            Complex64::new(-1.0, 2.0),
            Complex64::new(-1.0, -2.0),
            Complex64::new(-10.0, 0.0),
        ];
        for e in expect {
            assert!(r.iter().any(|z| (*z - e).norm() < 1e-10), "{e:?} not in {r:?}");
        }
    }
}
