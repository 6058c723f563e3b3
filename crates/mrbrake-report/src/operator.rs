//! Report of an operator-model identification (`mrbrake characterize --operators`): the modified
//! Prandtl–Ishlinskii model of [`mrbrake_sysid::operator_fit`], as text and JSON.

use std::fmt::Write as _;
use std::path::Path;

use mrbrake_sim::rig::tracking::TrackingScore;
use mrbrake_sysid::operator_fit::OperatorFit;
use serde_json::{Value, json};

use crate::ReportError;

/// The text report: the log, the operator counts, the forward model's fit to the log.
pub fn operator_fit_text(fit: &OperatorFit, log: &Path, samples: usize) -> String {
    let model = &fit.model.0;
    let mut out = String::new();
    let _ = writeln!(out, "log: {} ({samples} samples)", log.display());
    let _ = writeln!(
        out,
        "operator model (modified Prandtl–Ishlinskii): {} play operators, {} output segments",
        model.plays(),
        model.segments()
    );
    let _ = writeln!(
        out,
        "current range: {:.4} .. {:.4} A; reversals inside the range: {}",
        model.current_min_a(),
        model.current_max_a(),
        fit.fit.inner_reversals
    );
    let _ = writeln!(
        out,
        "forward model on the log ({} samples): RMSE {:.4} N·m, fit {:.2} %",
        fit.fit.samples, fit.fit.rmse_nm, fit.fit.fit_percent
    );
    out
}

/// The JSON report: the log and the fit (model in the operator-model file schema, statistics).
pub fn operator_fit_json(fit: &OperatorFit, log: &Path) -> Result<Value, ReportError> {
    let value = serde_json::to_value(fit).map_err(ReportError::from)?;
    Ok(json!({ "log": log.display().to_string(), "operator_model": value }))
}

/// The tracking scores of `mrbrake rig track` as a table.
pub fn tracking_text(scores: &[TrackingScore]) -> String {
    let mut out = String::from("demand                 RMSE (5.2)\n");
    for s in scores {
        let _ = writeln!(
            out,
            "{:22} {:.4} N·m = {:.2} % of the demand's range ({})",
            s.demand, s.rmse_nm, s.rmse_percent_of_range, s.file
        );
    }
    out
}
