//! Validation of the calibration: known parameters of a synthetic non-linear model recovered from
//! noisy data (within 2 % always, within 2 standard errors about 95 % of the time, as standard
//! errors must be), a product-only pair reported unidentifiable, bounds, failing models.

use mrbrake_error::{ErrorKind, Kind};
use mrbrake_optim::rng::Rng;
use mrbrake_uq::calibration::{CalibrationOptions, Parameter, calibrate};
use mrbrake_uq::special::std_normal_quantile;
use mrbrake_uq::{RunError, UqError};
use std::convert::Infallible;

/// A saturating torque–current curve with an off-state torque: `T(I) = τ tanh(I/I0) + T_off`
/// (N·m, A; parameters `[τ, I0, T_off]`).
fn torque(p: &[f64], current: f64) -> f64 {
    p[0] * (current / p[1]).tanh() + p[2]
}

const TRUE: [f64; 3] = [3.0, 0.8, 1.0];
const NOISE: f64 = 0.01;

/// A "rig log": 61 currents 0–3 A, Gaussian noise of `NOISE` N·m drawn from seed `seed`.
fn log(seed: u64) -> (Vec<f64>, Vec<f64>) {
    let mut rng = Rng::new(seed);
    let currents: Vec<f64> = (0..=60).map(|k| 0.05 * f64::from(k)).collect();
    let measured = currents
        .iter()
        .map(|&i| torque(&TRUE, i) + NOISE * std_normal_quantile(rng.uniform().max(1e-300)))
        .collect();
    (currents, measured)
}

fn parameters() -> [Parameter; 3] {
    [
        Parameter { start: 2.0, lower: 0.5, upper: 10.0 },
        Parameter { start: 0.3, lower: 0.05, upper: 5.0 },
        Parameter { start: 0.0, lower: -1.0, upper: 3.0 },
    ]
}

#[test]
fn known_parameters_are_recovered_with_honest_standard_errors() {
    let (mut within, mut total) = (0, 0);
    for seed in 0..200 {
        let (currents, measured) = log(seed);
        let residual = |p: &[f64]| -> Result<Vec<f64>, Infallible> {
            Ok(currents.iter().zip(&measured).map(|(&i, m)| torque(p, i) - m).collect())
        };
        let fit = calibrate(residual, &parameters(), &CalibrationOptions::default()).unwrap();
        assert!(fit.termination.converged(), "seed {seed}: {:?}", fit.termination);
        assert!(
            fit.identifiability.unidentifiable.is_empty(),
            "seed {seed}: {:?}",
            fit.correlation
        );
        // The noise estimate is close to the truth (s/σ scatters by 1/√(2·58) = 9 % with 58
        // degrees of freedom); the fit brings the RMS down to it.
        assert!((fit.noise / NOISE - 1.0).abs() < 0.4, "seed {seed}: noise {}", fit.noise);
        assert!(fit.residual_rms_after < fit.residual_rms_before);
        for j in 0..3 {
            let error = fit.estimate[j] - TRUE[j];
            assert!(
                error.abs() < 0.02 * TRUE[j],
                "seed {seed}, parameter {j}: {}",
                fit.estimate[j]
            );
            total += 1;
            within += usize::from(error.abs() < 2.0 * fit.standard_error[j]);
        }
    }
    // 2-SE intervals of a correct covariance hold ~95 % of the time (94.9 % over 1000 seeds;
    // binomial sd over 600: 0.9 %): a covariance too small by 20 % would give ~89 %.
    let share = within as f64 / total as f64;
    assert!(share > 0.92 && share < 0.98, "{within} of {total} within 2 standard errors");
}

#[test]
fn a_product_only_pair_is_reported_unidentifiable() {
    // r = a·b·t + c − y: only the product a·b is determined.
    let t: Vec<f64> = (0..30).map(|k| 0.1 * f64::from(k)).collect();
    let mut rng = Rng::new(4);
    let y: Vec<f64> =
        t.iter().map(|t| 6.0 * t + 0.5 + 0.01 * std_normal_quantile(rng.uniform())).collect();
    let residual = |p: &[f64]| -> Result<Vec<f64>, Infallible> {
        Ok(t.iter().zip(&y).map(|(t, y)| p[0] * p[1] * t + p[2] - y).collect())
    };
    let parameters = [
        Parameter { start: 1.0, lower: 0.5, upper: 10.0 },
        Parameter { start: 1.0, lower: 0.5, upper: 10.0 },
        Parameter { start: 0.0, lower: -2.0, upper: 2.0 },
    ];
    let fit = calibrate(residual, &parameters, &CalibrationOptions::default()).unwrap();
    assert_eq!(fit.identifiability.unidentifiable, vec![vec![0, 1]]);
    let weak = &fit.identifiability.weak_directions;
    assert_eq!(weak.len(), 1);
    assert_eq!(weak[0].parameters, vec![0, 1]);
    assert!(weak[0].collinearity_index() > 1e3, "{}", weak[0].collinearity_index());
    // The product and the offset are still fitted; the pair's correlation is −1, nothing is NaN.
    assert!((fit.estimate[0] * fit.estimate[1] - 6.0).abs() < 0.05);
    assert!((fit.estimate[2] - 0.5).abs() < 0.05);
    assert!(fit.correlation[0][1] < -0.99, "{}", fit.correlation[0][1]);
    assert!(fit.correlation.iter().flatten().all(|x| x.is_finite()));
    assert!(fit.standard_error.iter().all(|x| !x.is_nan()));
    assert!(fit.standard_error[0] > 100.0 * fit.standard_error[2]);
}

#[test]
fn a_parameter_whose_truth_lies_outside_its_bounds_ends_on_the_bound() {
    let (currents, measured) = log(7);
    let residual = |p: &[f64]| -> Result<Vec<f64>, Infallible> {
        Ok(currents.iter().zip(&measured).map(|(&i, m)| torque(p, i) - m).collect())
    };
    let mut bounded = parameters();
    bounded[0].upper = 2.5; // τ = 3 lies outside
    let fit = calibrate(residual, &bounded, &CalibrationOptions::default()).unwrap();
    assert!(fit.termination.converged(), "{:?}", fit.termination);
    assert!(fit.at_bound[0] && !fit.at_bound[1] && !fit.at_bound[2], "{:?}", fit.at_bound);
    assert!((fit.estimate[0] - 2.5).abs() < 1e-12);
}

#[test]
fn bounds_narrow_against_the_value_keep_the_steps_inside() {
    // T_off in [0.999, 1.001]: a step relative to |θ| = 1 would be twice the range.
    let (currents, measured) = log(2);
    let inside = |p: &[f64]| -> Result<Vec<f64>, Infallible> {
        assert!((0.999..=1.001).contains(&p[2]), "step left the bounds: {}", p[2]);
        Ok(currents.iter().zip(&measured).map(|(&i, m)| torque(p, i) - m).collect())
    };
    let mut narrow = parameters();
    narrow[2] = Parameter { start: 1.0005, lower: 0.999, upper: 1.001 };
    let options = CalibrationOptions { relative_step: 0.1, ..Default::default() };
    let fit = calibrate(inside, &narrow, &options).unwrap();
    assert!((fit.estimate[0] - TRUE[0]).abs() < 0.02 * TRUE[0]);
}

#[test]
fn central_differences_and_a_given_noise() {
    let (currents, measured) = log(3);
    let residual = |p: &[f64]| -> Result<Vec<f64>, Infallible> {
        Ok(currents.iter().zip(&measured).map(|(&i, m)| torque(p, i) - m).collect())
    };
    let options =
        CalibrationOptions { central_differences: true, noise: Some(NOISE), ..Default::default() };
    let fit = calibrate(residual, &parameters(), &options).unwrap();
    assert!(!fit.noise_estimated && (fit.noise - NOISE).abs() < 1e-15);
    let forward = calibrate(residual, &parameters(), &CalibrationOptions::default()).unwrap();
    for j in 0..3 {
        assert!((fit.estimate[j] - forward.estimate[j]).abs() < 1e-4 * TRUE[j]);
    }
}

#[test]
fn failing_and_non_finite_models() {
    // A model undefined (NaN) for τ above 4: the iteration must steer around it.
    let (currents, measured) = log(1);
    let partial = |p: &[f64]| -> Result<Vec<f64>, Infallible> {
        Ok(currents
            .iter()
            .zip(&measured)
            .map(|(&i, m)| if p[0] > 4.0 { f64::NAN } else { torque(p, i) - m })
            .collect())
    };
    let mut from_above = parameters();
    from_above[0].start = 3.9;
    let fit = calibrate(partial, &from_above, &CalibrationOptions::default()).unwrap();
    assert!((fit.estimate[0] - TRUE[0]).abs() < 0.02 * TRUE[0]);
    // A model error passes through unchanged, with its own kind.
    let failing = |_: &[f64]| -> Result<Vec<f64>, UqError> {
        Err(UqError::Numerical { message: "FEA diverged".into(), history: vec![] })
    };
    let error = calibrate(failing, &parameters(), &CalibrationOptions::default()).unwrap_err();
    assert!(matches!(error, RunError::Model(_)) && error.kind() == ErrorKind::Numerical);
    assert_eq!(error.to_string(), "FEA diverged");
}

#[test]
fn bad_parameters_and_options_are_input_errors() {
    let residual = |p: &[f64]| -> Result<Vec<f64>, Infallible> { Ok(vec![p[0], p[0] - 1.0]) };
    let cases = [
        Parameter { start: 2.0, lower: 0.0, upper: 1.0 },
        Parameter { start: 0.5, lower: 1.0, upper: 0.0 },
        Parameter { start: 0.5, lower: 0.0, upper: f64::INFINITY },
        Parameter { start: f64::NAN, lower: 0.0, upper: 1.0 },
    ];
    for p in cases {
        let e = calibrate(residual, &[p], &CalibrationOptions::default()).unwrap_err();
        assert!(matches!(e, RunError::Uq(UqError::InvalidCalibrationParameter { index: 0, .. })));
        assert_eq!(e.kind(), ErrorKind::Input);
    }
    let ok = [Parameter { start: 0.5, lower: 0.0, upper: 1.0 }];
    let bad = CalibrationOptions { relative_step: 0.0, ..Default::default() };
    assert!(calibrate(residual, &ok, &bad).unwrap_err().kind() == ErrorKind::Input);
    // Two residuals and two parameters: no noise estimate is possible without a given noise.
    let two = [ok[0], ok[0]];
    let square = |p: &[f64]| -> Result<Vec<f64>, Infallible> { Ok(vec![p[0], p[1]]) };
    let e = calibrate(square, &two, &CalibrationOptions::default()).unwrap_err();
    assert!(matches!(e, RunError::Uq(UqError::InvalidOption { name: "noise", .. })));
    let given = CalibrationOptions { noise: Some(0.1), ..Default::default() };
    assert!(calibrate(square, &two, &given).is_ok());
}
