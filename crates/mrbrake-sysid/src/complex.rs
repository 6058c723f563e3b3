//! Complex division by Smith's algorithm, for the frequency responses, the estimator and the
//! polynomial roots.
//!
//! The complex type is `num_complex::Complex64` (the one faer and the rest of the ecosystem use). Its
//! `/` is the textbook formula `(a c + b d, b c − a d) / (c² + d²)`, which overflows once
//! `|c|, |d| > 1e154` and rounds differently from the scaled form; the Levenberg–Marquardt
//! iterations of [`crate::tfest`] amplify such last-bit differences (up to 1e-9 relative in a
//! three-pole fit), so every complex quotient here goes through [`div`] instead (Smith 1962,
//! Comm. ACM 5(8):435).

use num_complex::Complex64;

/// `numerator / denominator` by Smith's algorithm: divides by the larger of the denominator's parts
/// first, so no intermediate squares the denominator.
#[inline]
pub fn div(numerator: Complex64, denominator: Complex64) -> Complex64 {
    let (a, b) = (numerator.re, numerator.im);
    let (c, d) = (denominator.re, denominator.im);
    if c.abs() >= d.abs() {
        let r = d / c;
        let t = c + d * r;
        Complex64::new((a + b * r) / t, (b - a * r) / t)
    } else {
        let r = c / d;
        let t = c * r + d;
        Complex64::new((a * r + b) / t, (b * r - a) / t)
    }
}

/// `1 / z` by Smith's algorithm.
#[inline]
pub fn recip(z: Complex64) -> Complex64 {
    div(Complex64::new(1.0, 0.0), z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn division_inverts_multiplication_even_for_huge_denominators() {
        let a = Complex64::new(1.5, -2.0);
        for b in
            [Complex64::new(-0.3, 4.0), Complex64::new(7.0, 0.5), Complex64::new(3e200, -4e200)]
        {
            assert!((div(a * b, b) - a).norm() < 1e-14 * a.norm());
        }
        // The textbook formula squares the denominator and overflows here.
        let big = Complex64::new(3e200, 4e200);
        assert!((div(big, big) - Complex64::new(1.0, 0.0)).norm() < 1e-15);
        assert!((recip(Complex64::new(0.0, 2.0)) - Complex64::new(0.0, -0.5)).norm() < 1e-16);
    }
}
