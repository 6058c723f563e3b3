//! Identification workflows as one call each, for every front end: a characterisation of a
//! repeated-ramp log and, with the same brake's frequency-response data, the transfer function
//! fitted to them (what `mrbrake report --log LOG.csv --frd FRD.csv` shows: thesis §5.3.1 and
//! §5.3.2 on one page). The settings are the library's named defaults
//! ([`DEFAULT_ORDER`](crate::characterize::DEFAULT_ORDER), [`DEFAULT_BINS`](crate::characterize::DEFAULT_BINS),
//! [`DEFAULT_POLES`], [`DEFAULT_ZEROS`], the rig's column names) unless the caller changes them.

use std::path::{Path, PathBuf};

use crate::SysidError;
use crate::characterize::{Characterization, CharacterizeOptions, characterize};
use crate::frd::{Frd, read_frd};
use crate::log::{Log, read_log};
use crate::tfest::{TfestOptions, TfestResult, TfestSummary, tfest};

/// The time column of a characterisation log (as `mrbrake rig characterize` writes it), s.
pub const DEFAULT_TIME_COLUMN: &str = "time_s";
/// The current column, A.
pub const DEFAULT_CURRENT_COLUMN: &str = "current_A";
/// The torque column, N·m.
pub const DEFAULT_TORQUE_COLUMN: &str = "torque_Nm";
/// Poles of the fitted transfer function: two, as the thesis's identified lags (5.5), (5.6).
pub const DEFAULT_POLES: usize = 2;
/// Zeros of the fitted transfer function.
pub const DEFAULT_ZEROS: usize = 0;

/// A characterisation log, optionally with frequency-response data of the same brake.
#[derive(Debug, Clone)]
pub struct CharacterizationRequest {
    /// The repeated-ramp log (CSV).
    pub log: PathBuf,
    /// Its time, current and torque column names.
    pub columns: [String; 3],
    /// Branch order and averaging bins.
    pub options: CharacterizeOptions,
    /// Frequency-response data (FRD CSV, e.g. from `mrbrake freqresp`) to fit a transfer function
    /// to, if any.
    pub frd: Option<PathBuf>,
    /// The transfer function's poles and zeros (and the estimator's other settings).
    pub tfest: TfestOptions,
}

/// A transfer function fitted to frequency-response data read from a file.
#[derive(Debug, Clone)]
pub struct TransferFunctionFit {
    /// The FRD file.
    pub frd_path: PathBuf,
    /// Its data.
    pub frd: Frd,
    /// The fit.
    pub fit: TfestResult,
    /// The fit's summary (`mrbrake tfest --json`).
    pub summary: TfestSummary,
    /// Poles asked for.
    pub poles: usize,
    /// Zeros asked for.
    pub zeros: usize,
}

/// The outcome of a [`CharacterizationRequest`].
#[derive(Debug, Clone)]
pub struct Characterized {
    /// The log as read: channel 0 the current (A), channel 1 the torque (N·m).
    pub log: Log,
    /// The loop's branches and figures.
    pub characterization: Characterization,
    /// The transfer function, when frequency-response data were given.
    pub transfer_function: Option<TransferFunctionFit>,
}

impl CharacterizationRequest {
    /// The request for `log` with the default columns and settings, without frequency-response
    /// data.
    pub fn new(log: impl Into<PathBuf>) -> Self {
        Self {
            log: log.into(),
            columns: [DEFAULT_TIME_COLUMN, DEFAULT_CURRENT_COLUMN, DEFAULT_TORQUE_COLUMN]
                .map(String::from),
            options: CharacterizeOptions::default(),
            frd: None,
            tfest: TfestOptions::new(DEFAULT_POLES, DEFAULT_ZEROS),
        }
    }

    /// Reads the log, characterises it and, with frequency-response data, fits the transfer
    /// function; errors name the file.
    pub fn run(&self) -> Result<Characterized, SysidError> {
        self.options.check()?;
        self.tfest.check()?;
        let [time, current, torque] = &self.columns;
        let min_samples = 2 * (self.options.order + 1);
        let log = read_log(&self.log, time, &[current, torque], min_samples)?;
        let characterization = characterize(&log.channels[0], &log.channels[1], self.options)?;
        let transfer_function = self.frd.as_deref().map(|p| fit_frd(p, &self.tfest)).transpose()?;
        Ok(Characterized { log, characterization, transfer_function })
    }
}

/// The transfer function of `options` fitted to the FRD file `path`.
pub fn fit_frd(path: &Path, options: &TfestOptions) -> Result<TransferFunctionFit, SysidError> {
    let frd = read_frd(path, None)?;
    let fit = tfest(&frd, options)?;
    let summary = fit.summary()?;
    Ok(TransferFunctionFit {
        frd_path: path.to_path_buf(),
        frd,
        fit,
        summary,
        poles: options.poles,
        zeros: options.zeros,
    })
}

impl Characterized {
    /// The log's current samples, A.
    pub fn current_a(&self) -> &[f64] {
        &self.log.channels[0]
    }

    /// The log's torque samples, N·m.
    pub fn torque_nm(&self) -> &[f64] {
        &self.log.channels[1]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_the_thesis_settings_and_a_missing_log_is_named() {
        let r = CharacterizationRequest::new("missing.csv");
        assert_eq!((r.options.order, r.options.bins), (5, 200));
        assert_eq!((r.tfest.poles, r.tfest.zeros), (2, 0));
        let e = r.run().unwrap_err();
        assert!(e.to_string().contains("missing.csv"), "{e}");
    }
}
