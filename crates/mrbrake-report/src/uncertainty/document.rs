//! The JSON of `mrbrake uncertainty --json` read back, typed: what the plots and the report's
//! section need of a propagation, the same whether it was just run ([`UncertaintyDocument::of`])
//! or saved by an earlier run ([`UncertaintyDocument::read`]), so a report of a saved run shows
//! exactly what that run printed.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Deserialize;

use mrbrake_explore::uncertainty::Uncertainty;

use crate::ReportError;

/// A propagation as its JSON holds it (keys as in the JSON; unknown keys ignored).
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct UncertaintyDocument {
    /// Samples drawn.
    pub samples: usize,
    /// Samples in the statistics.
    pub evaluated: usize,
    /// Samples left out (not a valid brake, or a failed analysis).
    pub left_out: usize,
    /// The first left-out sample's reason.
    #[serde(default)]
    pub left_out_reason: Option<String>,
    /// The declared inputs.
    pub inputs: Vec<InputEntry>,
    /// Per metric: its statistics.
    pub outputs: BTreeMap<String, OutputEntry>,
    /// The torque–current band, in increasing current.
    pub torque_band: Vec<BandEntry>,
    /// Per metric, per input: the Sobol' indices.
    pub sobol: BTreeMap<String, BTreeMap<String, IndexEntry>>,
    /// Per metric: the surrogate behind its indices.
    #[serde(default)]
    pub surrogates: BTreeMap<String, SurrogateEntry>,
    /// Wall times.
    pub timings_s: Timings,
}

/// One declared input.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct InputEntry {
    /// The spec path.
    pub name: String,
    /// The law's name.
    pub distribution: String,
    /// The field's SI unit (empty for factors).
    #[serde(default)]
    pub unit: String,
    /// The law's mean and standard deviation after truncation.
    pub moments: Moments,
}

/// Mean and standard deviation.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
pub struct Moments {
    /// Mean.
    pub mean: f64,
    /// Standard deviation.
    pub std: f64,
}

/// The statistics of one output metric (in its unit).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
pub struct OutputEntry {
    /// Mean.
    pub mean: f64,
    /// Standard deviation.
    pub std: f64,
    /// 5th percentile.
    pub p5: f64,
    /// Median.
    pub p50: f64,
    /// 95th percentile.
    pub p95: f64,
    /// The nominal design's value.
    #[serde(default)]
    pub nominal: Option<f64>,
}

/// One current of the torque band.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
pub struct BandEntry {
    /// The current (A).
    #[serde(rename = "current_A")]
    pub current_a: f64,
    /// 5th percentile of the torque (N·m).
    #[serde(rename = "p5_Nm")]
    pub p5_nm: f64,
    /// Median torque (N·m).
    #[serde(rename = "p50_Nm")]
    pub p50_nm: f64,
    /// 95th percentile (N·m).
    #[serde(rename = "p95_Nm")]
    pub p95_nm: f64,
    /// Mean (N·m).
    #[serde(rename = "mean_Nm")]
    pub mean_nm: f64,
    /// Standard deviation (N·m).
    #[serde(rename = "std_Nm")]
    pub std_nm: f64,
    /// The nominal design's torque (N·m).
    #[serde(rename = "nominal_Nm", default)]
    pub nominal_nm: Option<f64>,
    /// Samples reaching this current.
    pub samples: usize,
}

/// First-order and total Sobol' indices of one input, with their bootstrap 95 % intervals.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
pub struct IndexEntry {
    /// First-order index.
    pub first: f64,
    /// Total index.
    pub total: f64,
    /// Interval of the first-order index.
    pub first_ci: [f64; 2],
    /// Interval of the total index.
    pub total_ci: [f64; 2],
}

/// The surrogate behind one metric's indices.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct SurrogateEntry {
    /// Its kind (`polynomial_chaos`).
    pub kind: String,
    /// Its leave-one-out error (relative).
    pub loo_error: f64,
}

/// Wall times (s).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
pub struct Timings {
    /// Of the whole propagation.
    pub total: f64,
}

impl UncertaintyDocument {
    /// The document of a propagation just run (through its JSON, so it equals a saved one).
    pub fn of(u: &Uncertainty) -> Result<Self, ReportError> {
        Ok(serde_json::from_value(super::json(u))?)
    }

    /// Reads the document saved by `mrbrake uncertainty --json > FILE`; an unreadable file, JSON
    /// that is not such a document or a band that is not a band is an error naming the file.
    pub fn read(path: &Path) -> Result<Self, ReportError> {
        let text = mrbrake_error::read::text(path, mrbrake_error::read::MODEL).map_err(|e| {
            ReportError::Document {
                path: path.to_path_buf(),
                detail: format!("cannot read: {e}"),
                source: Some(e),
            }
        })?;
        let invalid = |detail: String| ReportError::Document {
            path: path.to_path_buf(),
            detail,
            source: None,
        };
        let document: Self = serde_json::from_str(&text)
            .map_err(|e| invalid(format!("not the JSON of `mrbrake uncertainty --json` ({e})")))?;
        document.check().map_err(invalid)?;
        Ok(document)
    }

    /// The band's currents increase and each point's percentiles are ordered.
    fn check(&self) -> Result<(), String> {
        for (k, p) in self.torque_band.iter().enumerate() {
            let ordered = p.p5_nm <= p.p50_nm && p.p50_nm <= p.p95_nm;
            let increasing = k == 0 || self.torque_band[k - 1].current_a < p.current_a;
            if !(ordered && increasing && p.current_a.is_finite()) {
                return Err(format!(
                    "torque_band[{k}] (current_A {}): the currents must increase and p5_Nm ≤ \
                     p50_Nm ≤ p95_Nm",
                    p.current_a
                ));
            }
        }
        Ok(())
    }

    /// The metric whose Sobol' indices a report shows first: `torque_max_Nm` when it has them,
    /// else the first that has.
    pub fn main_metric(&self) -> Option<&str> {
        let main = "torque_max_Nm";
        if self.sobol.contains_key(main) {
            return Some(main);
        }
        self.sobol.keys().next().map(String::as_str)
    }

    /// The indices of `metric`, inputs in declaration order.
    pub fn indices(&self, metric: &str) -> Option<Vec<(&str, IndexEntry)>> {
        let per_input = self.sobol.get(metric)?;
        let ordered = self
            .inputs
            .iter()
            .filter_map(|i| per_input.get(&i.name).map(|ix| (i.name.as_str(), *ix)));
        Some(ordered.collect())
    }
}

/// A small document for the tests of the plots and the report section.
#[cfg(test)]
pub(crate) const SAMPLE: &str = r#"{"samples": 4, "evaluated": 4, "left_out": 0, "inputs": [
        {"name": "b", "distribution": "uniform", "unit": "", "moments": {"mean": 1, "std": 0.1}},
        {"name": "a", "distribution": "normal", "unit": "m", "moments": {"mean": 2, "std": 0.2}}],
      "outputs": {"torque_max_Nm": {"mean": 4, "std": 1, "p5": 3, "p50": 4, "p95": 5, "nominal": 5}},
      "torque_band": [{"current_A": 0, "p5_Nm": 0.1, "p50_Nm": 0.1, "p95_Nm": 0.1, "mean_Nm": 0.1,
        "std_Nm": 0, "nominal_Nm": 0.1, "samples": 4},
        {"current_A": 2, "p5_Nm": 3, "p50_Nm": 4, "p95_Nm": 5, "mean_Nm": 4, "std_Nm": 1,
        "nominal_Nm": null, "samples": 4}],
      "sobol": {"torque_max_Nm": {"a": {"first": 0.1, "total": 0.2, "first_ci": [0, 0.2],
        "total_ci": [0.1, 0.3]}, "b": {"first": 0.7, "total": 0.8, "first_ci": [0.6, 0.8],
        "total_ci": [0.7, 0.9]}}},
      "surrogates": {"torque_max_Nm": {"kind": "polynomial_chaos", "loo_error": 0.01}},
      "timings_s": {"total": 1.5}}"#;

#[cfg(test)]
mod tests {
    use super::*;

    const DOC: &str = SAMPLE;

    #[test]
    fn a_saved_document_reads_back_and_a_foreign_one_is_named() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("u.json");
        std::fs::write(&path, DOC).unwrap();
        let d = UncertaintyDocument::read(&path).unwrap();
        assert_eq!(d.torque_band.len(), 2);
        assert_eq!(d.torque_band[1].nominal_nm, None);
        assert_eq!(d.main_metric(), Some("torque_max_Nm"));
        let names: Vec<&str> = d.indices("torque_max_Nm").unwrap().iter().map(|x| x.0).collect();
        assert_eq!(names, ["b", "a"], "declaration order");
        let bad = dir.path().join("bad.json");
        std::fs::write(&bad, DOC.replace("\"p95_Nm\": 5", "\"p95_Nm\": 3.5")).unwrap();
        let e = UncertaintyDocument::read(&bad).unwrap_err().to_string();
        assert!(e.contains("bad.json") && e.contains("torque_band[1]"), "{e}");
        std::fs::write(&bad, "{\"samples\": 3}").unwrap();
        let e = UncertaintyDocument::read(&bad).unwrap_err();
        assert!(e.to_string().contains("mrbrake uncertainty --json"), "{e}");
        assert_eq!(mrbrake_error::Kind::kind(&e), mrbrake_error::ErrorKind::Input);
        let missing = UncertaintyDocument::read(&dir.path().join("none.json")).unwrap_err();
        assert!(missing.to_string().contains("none.json"), "{missing}");
    }
}
