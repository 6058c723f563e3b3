//! Uncertainty quantification: how sure a prediction is, which uncertain input it depends on, and
//! which parameter values a measurement implies. The numerical core only: it knows nothing about
//! brakes; the caller supplies the model (an FEA, a closed form) as a function of plain SI numbers.
//!
//! # Brief overview
//!
//! * [`distribution`]: the inputs' laws — normal, uniform, triangular, log-normal, each optionally
//!   truncated — with CDF, quantile, density, mean and standard deviation, and typed errors naming
//!   a bad parameter.
//! * [`qmc`]: scrambled Sobol' points (Matoušek's linear matrix scrambling + digital shift, on the
//!   Joe–Kuo generator of `mrbrake-optim`), mapped onto the inputs by their quantiles, seeded and
//!   reproducible; the model evaluated on them in parallel.
//! * [`statistics`]: mean, standard deviation and 5/50/95 % percentiles of an output, and the
//!   per-point band of a curve.
//! * [`pce`] and [`sensitivity`]: a polynomial-chaos expansion in the inputs' CDF variables, fitted
//!   by least squares on the same samples, degree chosen by the leave-one-out error; first-order and
//!   total Sobol' indices from its coefficients with bootstrap confidence intervals.
//! * [`calibration`] and [`identifiability`]: bounded Levenberg–Marquardt on a caller's residual
//!   with a parallel finite-difference Jacobian; estimates, standard errors, correlations, and the
//!   parameter groups the data cannot separate.
//! * [`special`]: the standard normal CDF and quantile to full precision.
//!
//! Errors: [`UqError`] (its [`mrbrake_error::Kind`] says input, numerical or internal); runs that
//! call the caller's model return [`RunError`], which carries the model's own error unchanged.
//!
//! # A propagation, its sensitivities, a calibration
//!
//! ```
//! use mrbrake_uq::{distribution::Distribution, qmc, sensitivity, statistics};
//! use mrbrake_uq::calibration::{calibrate, CalibrationOptions, Parameter};
//! // Two uncertain factors of a torque T = 2 N·m × k_tau × (1 − 2 (g − 0.5 mm)/mm).
//! let inputs = [
//!     Distribution::normal(1.0, 0.1)?.truncated(0.6, 1.4)?, // yield-stress scale
//!     Distribution::uniform(0.45e-3, 0.55e-3)?,             // gap (m)
//! ];
//! let sample = qmc::sample(&inputs, 256, 42)?;
//! let torque = |x: &[f64]| 2.0 * x[0] * (1.0 - 2.0 * (x[1] - 0.5e-3) / 1e-3);
//! let outputs = sample
//!     .evaluate(|x| Ok::<_, std::convert::Infallible>(vec![torque(x)]))
//!     .map_err(|_| "the model cannot fail")?;
//! let y: Vec<f64> = outputs.iter().map(|o| o[0]).collect();
//! let band = statistics::summarize(&y)?;
//! assert!(band.p5 < 2.0 && 2.0 < band.p95);
//! let options = sensitivity::SensitivityOptions { bootstrap: 20, ..Default::default() };
//! let indices = sensitivity::sobol_indices(&sample.unit, &y, &options)?;
//! assert!(indices.inputs[0].total > indices.inputs[1].total); // the scale matters most
//!
//! // Calibrate the scale back from "measured" torques at three gaps.
//! let gaps = [0.46e-3, 0.5e-3, 0.54e-3];
//! let measured: Vec<f64> = gaps.iter().map(|&g| torque(&[0.85, g])).collect();
//! let residual = |p: &[f64]| -> Result<Vec<f64>, std::convert::Infallible> {
//!     Ok(gaps.iter().zip(&measured).map(|(&g, m)| torque(&[p[0], g]) - m).collect())
//! };
//! let fit = calibrate(residual, &[Parameter { start: 1.0, lower: 0.5, upper: 1.5 }],
//!     &CalibrationOptions::default()).map_err(|e| e.to_string())?;
//! assert!((fit.estimate[0] - 0.85).abs() < 1e-6);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod calibration;
pub mod distribution;
mod error;
pub mod identifiability;
pub mod pce;
pub mod qmc;
pub mod sensitivity;
pub mod special;
pub mod statistics;

pub use error::{RunError, UqError};
