//! Validation of the input laws: quantiles against closed forms and 40-digit references
//! (mpmath), moments of truncated laws against closed forms and numerical integration of the
//! density, and property tests (quantile ∘ CDF = identity, CDF ∘ quantile = identity, monotone).

use mrbrake_uq::distribution::Distribution;
use proptest::prelude::*;

fn close(a: f64, b: f64, tolerance: f64) -> bool {
    (a - b).abs() <= tolerance * (1.0 + b.abs())
}

#[test]
fn quantiles_against_known_values() {
    let z975 = 1.959_963_984_540_054;
    let cases: Vec<(Distribution, f64, f64)> = vec![
        (Distribution::normal(10.0, 2.0).unwrap(), 0.975, 10.0 + 2.0 * z975),
        (Distribution::uniform(2.0, 6.0).unwrap(), 0.25, 3.0),
        // Triangular (0, 1, 3): F(1) = 1/3; above, x = 3 − √((1 − p)·3·2).
        (Distribution::triangular(0.0, 1.0, 3.0).unwrap(), 1.0 / 3.0, 1.0),
        (Distribution::triangular(0.0, 1.0, 3.0).unwrap(), 0.5, 3.0 - 3f64.sqrt()),
        (Distribution::log_normal(0.0, 1.0).unwrap(), 0.5, 1.0),
        (Distribution::log_normal(0.0, 1.0).unwrap(), 0.975, 7.099_071_384_231_336),
        // Half-normal: Q(p) = Φ⁻¹((1 + p)/2).
        (
            Distribution::normal(0.0, 1.0).unwrap().truncated(0.0, f64::INFINITY).unwrap(),
            0.5,
            0.674_489_750_196_081_7,
        ),
        // Doubly truncated and upper-tail truncated normals (mpmath, 40 digits).
        (
            Distribution::normal(0.0, 1.0).unwrap().truncated(-1.0, 2.0).unwrap(),
            0.1,
            -0.704_647_821_094_745_2,
        ),
        (
            Distribution::normal(0.0, 1.0).unwrap().truncated(-1.0, 2.0).unwrap(),
            0.5,
            0.171_163_918_017_824_77,
        ),
        (
            Distribution::normal(0.0, 1.0).unwrap().truncated(-1.0, 2.0).unwrap(),
            0.9,
            1.255_715_364_150_215_2,
        ),
        (
            Distribution::normal(0.0, 1.0).unwrap().truncated(3.0, f64::INFINITY).unwrap(),
            0.5,
            3.205_154_920_598_933,
        ),
        (
            Distribution::normal(0.0, 1.0).unwrap().truncated(3.0, f64::INFINITY).unwrap(),
            0.99,
            4.197_414_437_605_671,
        ),
        // Truncated uniform: uniform on the intersection.
        (Distribution::uniform(0.0, 10.0).unwrap().truncated(2.0, 4.0).unwrap(), 0.25, 2.5),
    ];
    for (law, p, expected) in cases {
        let x = law.quantile(p).unwrap();
        assert!(close(x, expected, 1e-13), "{law:?} at {p}: {x} vs {expected}");
        assert!(close(law.cdf(x), p, 1e-13), "{law:?}: cdf({x}) = {} vs {p}", law.cdf(x));
    }
}

#[test]
fn truncated_normal_moments_match_the_closed_form() {
    // N(0, 1) on [−1, 2] (mpmath): mean 0.229637179091329, sd 0.720945586859046.
    let law = Distribution::normal(5.0, 0.5).unwrap().truncated(4.5, 6.0).unwrap();
    assert!(close(law.mean(), 5.0 + 0.5 * 0.229_637_179_091_328_97, 1e-14));
    assert!(close(law.std_dev(), 0.5 * 0.720_945_586_859_045_8, 1e-13));
}

/// `(E[X], sd X)` by numerical integration in probability space, independent of the closed forms:
/// `E[g(X)] = ∫₀¹ g(Q(p)) dp` with `p = Φ(z)`, i.e. `∫ g(Q(Φ(z))) φ(z) dz` over `|z| ≤ 8`
/// (dropped mass 1.2e-15), composite Simpson with 20 000 intervals.
fn integrated_moments(law: &Distribution) -> (f64, f64) {
    let standard = Distribution::normal(0.0, 1.0).unwrap();
    let n = 20_000;
    let h = 16.0 / n as f64;
    let mut m = [0.0; 3];
    for k in 0..=n {
        let z = -8.0 + k as f64 * h;
        let w = if k == 0 || k == n {
            1.0
        } else if k % 2 == 1 {
            4.0
        } else {
            2.0
        };
        let x = law.quantile(standard.cdf(z)).unwrap();
        let f = w * standard.pdf(z) * h / 3.0;
        m[0] += f;
        m[1] += f * x;
        m[2] += f * x * x;
    }
    let mean = m[1] / m[0];
    (mean, (m[2] / m[0] - mean * mean).max(0.0).sqrt())
}

/// A law of each kind, its untruncated quantile levels giving an optional truncation.
fn any_law() -> impl Strategy<Value = Distribution> {
    let base =
        prop_oneof![
            (-5.0..5.0f64, 0.01..3.0f64).prop_map(|(m, s)| Distribution::normal(m, s).unwrap()),
            (-5.0..5.0f64, 0.01..5.0f64)
                .prop_map(|(a, w)| Distribution::uniform(a, a + w).unwrap()),
            (-5.0..5.0f64, 0.01..5.0f64, 0.0..=1.0f64)
                .prop_map(|(a, w, c)| Distribution::triangular(a, a + c * w, a + w).unwrap()),
            (-2.0..2.0f64, 0.05..1.0f64).prop_map(|(m, s)| Distribution::log_normal(m, s).unwrap()),
        ];
    (base, 0.0..0.9f64, 0.05..1.0f64, 0..4usize).prop_map(|(law, low, width, sides)| {
        let (lower_p, upper_p) = (low, (low + width).min(1.0));
        let lower = if sides & 1 == 1 { law.quantile(lower_p).unwrap() } else { f64::NEG_INFINITY };
        let upper = if sides & 2 == 2 { law.quantile(upper_p).unwrap() } else { f64::INFINITY };
        if lower < upper { law.truncated(lower, upper).unwrap_or(law) } else { law }
    })
}

proptest! {
    #[test]
    fn quantile_inverts_the_cdf(law in any_law(), p in 0.001..0.999f64) {
        let x = law.quantile(p).unwrap();
        prop_assert!(x.is_finite());
        prop_assert!((law.cdf(x) - p).abs() < 1e-9, "{law:?}: cdf(q({p})) = {}", law.cdf(x));
        let (a, b) = law.support();
        prop_assert!(a <= x && x <= b);
    }

    #[test]
    fn cdf_then_quantile_returns_the_point(law in any_law(), p in 0.01..0.99f64) {
        let x = law.quantile(p).unwrap();
        let back = law.quantile(law.cdf(x)).unwrap();
        let scale = law.std_dev().max(1e-300);
        prop_assert!((back - x).abs() < 1e-7 * scale, "{law:?}: {x} -> {back}");
    }

    #[test]
    fn quantile_is_monotone(law in any_law(), p in 0.0..1.0f64, dp in 0.0..0.5f64) {
        let q = (p + dp).min(1.0);
        prop_assert!(law.quantile(p).unwrap() <= law.quantile(q).unwrap());
    }

    #[test]
    fn moments_match_integration(law in any_law()) {
        let (mean, sd) = integrated_moments(&law);
        prop_assert!((law.mean() - mean).abs() < 1e-6 * (sd + mean.abs()), "{law:?}: mean {} vs {mean}", law.mean());
        prop_assert!((law.std_dev() - sd).abs() < 1e-5 * sd, "{law:?}: sd {} vs {sd}", law.std_dev());
    }
}
