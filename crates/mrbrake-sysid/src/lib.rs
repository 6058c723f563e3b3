//! System identification from MR-brake test-rig logs (thesis chapter 5).
//!
//! Brief overview:
//! - [`log`] reads CSV logs (columns by name, any sample rate) with errors naming file and line.
//! - [`characterize`] finds the repeated current ramps of the characterisation protocol (§5.3.1),
//!   averages them and fits polynomial rising/falling branches → [`characterize::Characterization`].
//! - [`model_file`] reads the inverse-model file those branches are saved as, into the one model type
//!   every later stage runs: the controller's [`mrbrake_control::InverseModel`]
//!   ([`characterize::Characterization::model`] converts a fit directly).
//! - [`operator_fit`] identifies the operator hysteresis model (modified Prandtl–Ishlinskii, minor
//!   loops, exact inverse) from a log with minor loops, and reads its file.
//! - [`outliers`] screens a logged channel for corrupted samples before a fit.
//! - [`tracking`] computes the torque-tracking RMSE (5.2).
//! - [`freqresp`] turns sinusoidal tests (a manifest of logs) into frequency-response points by sine
//!   fits (5.3), (5.4), each a [`freqresp::MeasuredPoint`] wrapping the one frequency-response
//!   type, [`frd::FrequencyPoint`] (G(jω) at ω); [`frd::Frd`] is such data (measured, predicted by
//!   `mrbrake-design`, or a model's), with the one FRD CSV writer and reader and the one −3 dB
//!   bandwidth search.
//! - [`tfest`] estimates a continuous-time [`transfer_function::TransferFunction`] from them
//!   (Levy / Sanathanan–Koerner, then Levenberg–Marquardt).
//! - [`request`]: the front ends' workflows as one call (a characterisation with a fitted transfer
//!   function), settings as named defaults.
//!
//! ```
//! use mrbrake_sysid::{frd::Frd, tfest::{logspace, tfest, TfestOptions}, transfer_function::TransferFunction};
//! // The thesis's brake 1 (5.5) sampled at 41 log-spaced frequencies and estimated back.
//! let g = TransferFunction::new(vec![1.0], vec![1.791e-5, 0.01702, 1.0]).unwrap();
//! let frd = Frd::sample(&logspace(0.1, 1000.0, 41), |w| g.response(w));
//! let fit = tfest(&frd, &TfestOptions::new(2, 0)).unwrap();
//! let corners = fit.model.corner_frequencies_rad_s().unwrap();
//! assert!((corners[0] - 62.93).abs() < 0.01 && (corners[1] - 887.38).abs() < 0.01);
//! ```

pub mod characterize;
mod complex;
mod error;
pub mod frd;
pub mod freqresp;
pub mod linalg;
pub mod log;
pub mod model_file;
pub mod operator_fit;
pub mod outliers;
pub mod polynomial;
pub mod request;
pub mod tfest;
pub mod tracking;
pub mod transfer_function;

pub use error::SysidError;
