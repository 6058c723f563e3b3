//! Validation of the B-H interpolation on every built-in curve and on random curves (proptest):
//! exactness at the data points, C¹ continuity, monotonicity, the μ0 extrapolation, and the
//! consistency of `ν(B²)` with `dν/dB²` (finite differences over the whole range).

use mrbrake_materials::{BhCurve, MU_0, Provenance, Trust, library};
use proptest::prelude::*;

fn library_curves() -> Vec<(&'static str, std::sync::Arc<BhCurve>)> {
    library::names()
        .into_iter()
        .filter_map(|(name, _)| {
            let curve = library::get(name).unwrap().magnetic.bh_curve()?.clone();
            Some((name, std::sync::Arc::new(curve)))
        })
        .collect()
}

fn rel_close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * b.abs().max(1e-300)
}

/// Checks exactness at knots, C¹ at piece boundaries, positive slope, inverse consistency.
fn check_curve(name: &str, c: &BhCurve) {
    for &(h, b) in c.points() {
        if b > 0.0 {
            assert!(rel_close(c.h_of_b(b), h, 1e-12), "{name}: H({b}) = {} != {h}", c.h_of_b(b));
            assert!(rel_close(c.b_of_h(h), b, 1e-12), "{name}: B({h}) = {} != {b}", c.b_of_h(h));
        } else {
            assert!(c.h_of_b(0.0).abs() < 1e-300 && c.b_of_h(0.0).abs() < 1e-300, "{name}: origin");
        }
    }
    // C¹: value and slope of adjacent pieces agree at every boundary (data and split knots).
    let (knots, coeffs) = c.pieces();
    for k in 1..coeffs.len() {
        let w = knots[k] - knots[k - 1];
        let p = coeffs[k - 1];
        let left_value = p[0] + w * (p[1] + w * (p[2] + w * p[3]));
        let left_slope = p[1] + w * (2.0 * p[2] + 3.0 * w * p[3]);
        assert!(rel_close(left_value, coeffs[k][0], 1e-11), "{name}: value jump at knot {k}");
        // Rounding is relative to the size of the terms that cancel, not to the (possibly tiny) slope.
        let terms = p[1].abs() + (2.0 * w * p[2]).abs() + (3.0 * w * w * p[3]).abs();
        assert!(
            (left_slope - coeffs[k][1]).abs() <= 1e-12 * terms,
            "{name}: slope jump at knot {k}"
        );
    }
    // The slope at the last point equals 1/μ0 from both sides.
    let (h_last, b_last) = c.last_point();
    let last = coeffs[coeffs.len() - 1];
    let w = knots[knots.len() - 1] - knots[knots.len() - 2];
    let end_slope = last[1] + w * (2.0 * last[2] + 3.0 * w * last[3]);
    assert!(
        rel_close(end_slope, 1.0 / MU_0, 1e-9),
        "{name}: slope at the end of the last piece {end_slope}"
    );
    assert!(
        rel_close(c.dh_db(b_last * (1.0 + 1e-12)), 1.0 / MU_0, 1e-12),
        "{name}: slope above last point"
    );
    // Monotone, Jacobian positive and inverse consistent on a dense grid up to 1.5× the last B.
    let mut previous_h = -1.0;
    for i in 0..=6000 {
        let b = 1.5 * b_last * f64::from(i) / 6000.0;
        let h = c.h_of_b(b);
        assert!(h > previous_h, "{name}: H not increasing at B = {b}");
        previous_h = h;
        let b2 = b * b;
        let (nu, dnu) = c.nu_and_dnu_db2(b2);
        let jacobian = nu + 2.0 * b2 * dnu;
        assert!(c.dh_db(b) > 0.0, "{name}: dH/dB <= 0 at B = {b}");
        // ν + 2B² dν/dB² = dH/dB up to the rounding of the sum (relative to its terms).
        let terms = nu.abs() + (2.0 * b2 * dnu).abs();
        assert!(
            (jacobian - c.dh_db(b)).abs() <= 1e-12 * terms,
            "{name}: Jacobian != dH/dB at B = {b}"
        );
        if b > 0.0 {
            // Conditioning: H is known to a few ulps, which moves B by ulps(H)/(dH/dB).
            let tolerance = 1e-11 * b + 8.0 * f64::EPSILON * h / c.dh_db(b);
            assert!((c.b_of_h(h) - b).abs() <= tolerance, "{name}: B(H(B)) != B at B = {b}");
            assert!(rel_close(c.nu_of_b2(b2) * b, h, 1e-12), "{name}: nu B != H at B = {b}");
        }
    }
    assert!(h_last > 0.0);
}

/// `dν/dB²` against a finite difference of `ν(B²)` at `b2`: central, or one-sided (second order) when a
/// piece boundary lies inside the central stencil (ν is only C¹ there, so a stencil across a boundary
/// measures the jump of the second derivative, not an inconsistency).
fn check_fd(name: &str, c: &BhCurve, b2: f64) {
    let step = 1e-6 * b2.max(1e-4);
    let (knots, _) = c.pieces();
    let boundary = knots.iter().map(|k| k * k).find(|&k2| k2 > 0.0 && (k2 - b2).abs() < 2.0 * step);
    let nu = |x: f64| c.nu_of_b2(x);
    let difference = |step: f64| match boundary {
        None => {
            let lo = (b2 - step).max(0.0);
            let hi = b2 + step;
            (nu(hi) - nu(lo)) / (hi - lo)
        }
        // Boundary at or above b2: differentiate from the left; below: from the right.
        Some(k2) if k2 >= b2 => {
            (3.0 * nu(b2) - 4.0 * nu(b2 - step) + nu(b2 - 2.0 * step)) / (2.0 * step)
        }
        Some(_) => (-3.0 * nu(b2) + 4.0 * nu(b2 + step) - nu(b2 + 2.0 * step)) / (2.0 * step),
    };
    // Richardson extrapolation of the second-order differences: strongly curved random pieces would
    // otherwise show truncation error of the difference itself.
    let fd = (4.0 * difference(0.5 * step) - difference(step)) / 3.0;
    let exact = c.dnu_db2(b2);
    // Scale: ν/B² bounds the size of dν/dB² away from 0; rounding of the difference is ~1e-10 of it.
    let scale = c.nu_of_b2(b2) / b2.max(1e-4);
    assert!(
        (fd - exact).abs() <= 1e-5 * exact.abs() + 1e-6 * scale,
        "{name}: dnu/dB2 at B2 = {b2}: exact {exact}, finite difference {fd}"
    );
}

#[test]
fn library_curves_are_exact_c1_monotone_and_invertible() {
    for (name, c) in library_curves() {
        check_curve(name, &c);
        // The Newton Jacobian coefficient, as a solver computes it, is positive everywhere.
        let (_, b_last) = c.last_point();
        for i in 0..=20_000 {
            let b2 = (2.0 * b_last * f64::from(i) / 20_000.0).powi(2);
            let jacobian = c.nu_of_b2(b2) + 2.0 * b2 * c.dnu_db2(b2);
            assert!(jacobian > 0.0, "{name}: Newton Jacobian {jacobian} <= 0 at B² = {b2}");
        }
    }
}

#[test]
fn nu_and_dnu_agree_with_finite_differences_over_the_whole_range() {
    for (name, c) in library_curves() {
        let (_, b_last) = c.last_point();
        let mut samples = vec![0.0, 1e-12, 1e-8, 1e-6, 1e-4];
        // Dense sweep in B, including the extrapolation up to 3× the last point.
        samples.extend((1..=2000).map(|i| (3.0 * b_last * f64::from(i) / 2000.0).powi(2)));
        // Just around every piece boundary (data knots and split knots).
        let (knots, _) = c.pieces();
        for &k in knots.iter().skip(1) {
            for f in [1.0 - 1e-3, 1.0 - 1e-7, 1.0, 1.0 + 1e-7, 1.0 + 1e-3] {
                samples.push((k * f).powi(2));
            }
        }
        for b2 in samples {
            check_fd(name, &c, b2);
        }
        // At B = 0, ν is the initial slope dH/dB and dν/dB² is finite.
        assert!(rel_close(c.nu_of_b2(0.0), c.dh_db(0.0), 1e-12), "{name}");
        assert!(c.dnu_db2(0.0).is_finite(), "{name}");
    }
}

#[test]
fn extrapolation_has_slope_mu0() {
    for (name, c) in library_curves() {
        let (h_last, b_last) = c.last_point();
        for dh in [1.0, 1e3, 1e6, 1e8] {
            let db = c.b_of_h(h_last + dh) - b_last;
            assert!(rel_close(db, MU_0 * dh, 1e-9), "{name}: dB = {db} for dH = {dh}");
        }
        // Far in saturation, ν → 1/μ0.
        assert!(rel_close(c.nu_of_b2(1e6), 1.0 / MU_0, 0.01), "{name}");
    }
}

#[test]
fn odd_symmetry_and_special_arguments() {
    let c = library::bh_curve("steel-1008").unwrap();
    for h in [10.0, 1e3, 1e5, 1e7] {
        assert!(rel_close(c.b_of_h(-h), -c.b_of_h(h), 1e-15));
    }
    assert!(rel_close(c.nu_of_b2(-1.0), c.nu_of_b2(0.0), 1e-15));
    assert!(c.nu_of_b2(f64::NAN).is_nan() && c.dnu_db2(f64::NAN).is_nan());
}

/// Random valid curves: positive increments in H and B, 4–30 points, spanning several decades.
fn random_points() -> impl Strategy<Value = Vec<(f64, f64)>> {
    proptest::collection::vec((0.01f64..10.0, 0.01f64..10.0, -3.0f64..3.0), 3..30).prop_map(
        |steps| {
            let mut points = vec![(0.0, 0.0)];
            let (mut h, mut b) = (0.0, 0.0);
            for (dh, db, decade) in steps {
                h += dh * 10f64.powf(decade + 2.0);
                b += db * 0.05;
                points.push((h, b));
            }
            points
        },
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn random_curves_are_exact_monotone_and_c1(points in random_points()) {
        let c = BhCurve::from_points(&points, Provenance::new("proptest", "random", Trust::User)).unwrap();
        check_curve("random", &c);
        let (_, b_last) = c.last_point();
        for i in 0..=200 {
            check_fd("random", &c, (1.2 * b_last * f64::from(i) / 200.0).powi(2));
        }
    }

    #[test]
    fn b_of_h_is_monotone_for_random_curves(points in random_points(), fractions in proptest::collection::vec(0.0f64..1.5, 2..50)) {
        let c = BhCurve::from_points(&points, Provenance::new("proptest", "random", Trust::User)).unwrap();
        let (h_last, _) = c.last_point();
        let mut hs: Vec<f64> = fractions.iter().map(|f| f * h_last).collect();
        hs.sort_by(f64::total_cmp);
        for w in hs.windows(2) {
            prop_assert!(c.b_of_h(w[1]) >= c.b_of_h(w[0]));
        }
    }
}
