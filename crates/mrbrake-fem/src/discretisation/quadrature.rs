//! Quadrature rules on the reference triangle and on the interval.
//!
//! Triangle rules are given in barycentric coordinates `(l1, l2, l3)` with weights that sum to one,
//! so `∫_T f dA ≈ |T| Σ w_q f(x(l_q))`. They are symmetric rules with interior points only, which
//! matters for the axisymmetric forms: integrands such as `A²/r` are never sampled on the axis.
//! The r-weighted forms of quadratic (P2) elements have polynomial parts of degree 3 (plus the
//! `A/r` terms), so they use the degree-4 rule or higher.
//!
//! - degree 1: centroid;
//! - degree 2: Strang & Fix, 3 points `(2/3, 1/6, 1/6)`;
//! - degree 4: Dunavant (1985), "High degree efficient symmetrical Gaussian quadrature rules for the
//!   triangle", Int. J. Numer. Meth. Eng. 21, Table of n = 6 points;
//! - degree 5: Dunavant (1985), 7 points (Radon's rule).
//!
//! The interval rule is Gauss–Legendre of any order, nodes found by Newton's method on the Legendre
//! polynomial from the Chebyshev-like start `cos(π (i + 3/4) / (n + 1/2))` (Abramowitz & Stegun 25.4.29).

/// A quadrature point on the reference triangle: barycentric coordinates and weight (weights sum to 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrianglePoint {
    /// Barycentric coordinates `(l1, l2, l3)`, summing to one.
    pub bary: [f64; 3],
    /// Weight relative to the triangle area.
    pub weight: f64,
}

/// Symmetric quadrature rule on triangles exact for polynomials up to `degree` (1, 2, 4 or 5; other
/// requests get the next available degree, capped at 5).
pub fn triangle_rule(degree: usize) -> Vec<TrianglePoint> {
    let p = |a: f64, b: f64, c: f64, w: f64| TrianglePoint { bary: [a, b, c], weight: w };
    match degree {
        0 | 1 => vec![p(1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0, 1.0)],
        2 => {
            let (a, b) = (2.0 / 3.0, 1.0 / 6.0);
            vec![p(a, b, b, 1.0 / 3.0), p(b, a, b, 1.0 / 3.0), p(b, b, a, 1.0 / 3.0)]
        }
        3 | 4 => {
            let (a1, b1, w1) =
                (0.108_103_018_168_070, 0.445_948_490_915_965, 0.223_381_589_678_011);
            let (a2, b2, w2) =
                (0.816_847_572_980_459, 0.091_576_213_509_771, 0.109_951_743_655_322);
            vec![
                p(a1, b1, b1, w1),
                p(b1, a1, b1, w1),
                p(b1, b1, a1, w1),
                p(a2, b2, b2, w2),
                p(b2, a2, b2, w2),
                p(b2, b2, a2, w2),
            ]
        }
        _ => {
            let (a1, b1, w1) =
                (0.059_715_871_789_770, 0.470_142_064_105_115, 0.132_394_152_788_506);
            let (a2, b2, w2) =
                (0.797_426_985_353_087, 0.101_286_507_323_456, 0.125_939_180_544_827);
            vec![
                p(1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0, 0.225),
                p(a1, b1, b1, w1),
                p(b1, a1, b1, w1),
                p(b1, b1, a1, w1),
                p(a2, b2, b2, w2),
                p(b2, a2, b2, w2),
                p(b2, b2, a2, w2),
            ]
        }
    }
}

/// Gauss–Legendre rule with `n >= 1` points on `[0, 1]`: `(nodes, weights)`, weights summing to one.
pub fn gauss_legendre_unit(n: usize) -> (Vec<f64>, Vec<f64>) {
    let n = n.max(1);
    let mut nodes = vec![0.0; n];
    let mut weights = vec![0.0; n];
    for i in 0..n {
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut derivative = 1.0;
        for _ in 0..100 {
            // Legendre recurrence (k+1) P_{k+1} = (2k+1) x P_k - k P_{k-1}.
            let (mut p0, mut p1) = (1.0, x);
            for k in 1..n {
                let p2 = ((2 * k + 1) as f64 * x * p1 - k as f64 * p0) / (k + 1) as f64;
                p0 = p1;
                p1 = p2;
            }
            let pn = if n == 1 { x } else { p1 };
            let pn_minus_1 = if n == 1 { 1.0 } else { p0 };
            derivative = n as f64 * (x * pn - pn_minus_1) / (x * x - 1.0);
            let step = pn / derivative;
            x -= step;
            if step.abs() < 1e-16 {
                break;
            }
        }
        nodes[i] = 0.5 * (1.0 - x);
        weights[i] = 1.0 / ((1.0 - x * x) * derivative * derivative);
    }
    (nodes, weights)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫_T x^a y^b over the unit right triangle = a! b! / (a + b + 2)!.
    fn exact_monomial(a: u32, b: u32) -> f64 {
        let f = |k: u32| (1..=k).map(f64::from).product::<f64>();
        f(a) * f(b) / f(a + b + 2)
    }

    #[test]
    fn triangle_rules_are_exact_to_their_degree() {
        for (degree, rule_degree) in [(1, 1), (2, 2), (4, 4), (5, 5)] {
            let rule = triangle_rule(degree);
            let weight_sum: f64 = rule.iter().map(|q| q.weight).sum();
            assert!((weight_sum - 1.0).abs() < 1e-12);
            for a in 0..=rule_degree {
                for b in 0..=(rule_degree - a) {
                    // Reference triangle (0,0), (1,0), (0,1): x = l2, y = l3, area 1/2.
                    let approx: f64 = rule
                        .iter()
                        .map(|q| {
                            0.5 * q.weight * q.bary[1].powi(a as i32) * q.bary[2].powi(b as i32)
                        })
                        .sum();
                    let exact = exact_monomial(a, b);
                    assert!(
                        (approx - exact).abs() < 1e-12,
                        "degree {degree} x^{a} y^{b}: {approx} vs {exact}"
                    );
                }
            }
        }
    }

    #[test]
    fn gauss_legendre_integrates_degree_2n_minus_1() {
        for n in 1..12 {
            let (x, w) = gauss_legendre_unit(n);
            for k in 0..(2 * n) {
                let approx: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(k as i32)).sum();
                assert!((approx - 1.0 / (k as f64 + 1.0)).abs() < 1e-13, "n={n} k={k}");
            }
        }
    }
}
