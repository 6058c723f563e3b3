//! `mrbrake uncertainty`: propagates declared uncertain inputs (a `--inputs` TOML file) through
//! the FEA by scrambled Sobol' samples, each stored in a resumable results store, and prints the
//! band of every output and the torque–current band with its Sobol' sensitivities
//! (`mrbrake_explore::uncertainty`); `--plots DIR` writes the band plot and the tornado chart
//! (`mrbrake_report::uncertainty::plots`).

use std::path::PathBuf;

use clap::Args;
use mrbrake::design::spec::BrakeSpec;
use mrbrake::explore::uncertainty::{self, Declarations, UncertaintyRequest};
use mrbrake::explore::{Progress, runner};
use mrbrake::observe::Flow;
use mrbrake::report::atomic::StagedDir;
use mrbrake::report::uncertainty::document::UncertaintyDocument;
use mrbrake::report::uncertainty::plots;

use super::sweep::{AnalysisSettingsArgs, base_spec, recorded_metrics};
use crate::error::CommandResult;
use crate::output::{print_json, print_text};
use crate::progress::ProgressDisplay;

/// Arguments of `mrbrake uncertainty`.
#[derive(Debug, Args)]
pub struct UncertaintyArgs {
    /// Brake specification (TOML). Omitted: the embedded thesis bidirectional brake.
    spec: Option<PathBuf>,
    /// The uncertain inputs: a TOML file of `[[input]]` tables (`path`, `distribution` =
    /// normal | uniform | triangular | log-normal, its parameters, optional `truncate`).
    #[arg(long, value_name = "FILE")]
    inputs: PathBuf,
    /// Number of scrambled Sobol' samples (a power of two keeps them balanced).
    #[arg(long, default_value_t = 64)]
    samples: usize,
    /// Seed of the scrambling and of the bootstrap.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Bootstrap replicates of the Sobol' indices' confidence intervals.
    #[arg(long, default_value_t = 200)]
    bootstrap: usize,
    /// Metric to summarise (default: the static torques, mean gap B, inductance, time constant,
    /// and every --record metric). Repeatable.
    #[arg(long = "metric", value_name = "METRIC")]
    metric: Vec<String>,
    /// Also compute a dynamics or heat metric per sample (e.g. bandwidth_rad_s). Repeatable.
    #[arg(long = "record", value_name = "METRIC")]
    record: Vec<String>,
    /// Results store (SQLite file); an existing store needs --resume. Default: a file beside the
    /// inputs (`INPUTS.store`).
    #[arg(long, value_name = "FILE")]
    store: Option<PathBuf>,
    /// Continue an existing store: samples already in it are not recomputed.
    #[arg(long)]
    resume: bool,
    /// Analyses run at the same time (0: one per core).
    #[arg(long, default_value_t = 0)]
    jobs: usize,
    #[command(flatten)]
    analysis: AnalysisSettingsArgs,
    /// Currents of each sample's torque–current curve, evenly from 0 A to the maximum current
    /// (2 to 41): the torque band's currents. Each is a field solve per sample; part of the
    /// design keys, so a resumed run needs the same count.
    #[arg(long, default_value_t = uncertainty::DEFAULT_CURVE_POINTS)]
    curve_points: usize,
    /// Write plots here: the torque–current band (torque_band.svg) and the tornado chart of the
    /// Sobol' indices (tornado.svg).
    #[arg(long, value_name = "DIR")]
    plots: Option<PathBuf>,
    /// Also write PNG versions of the plots.
    #[arg(long, requires = "plots")]
    png: bool,
    /// The metric of the tornado chart (default: torque_max_Nm).
    #[arg(long, value_name = "METRIC", requires = "plots")]
    tornado: Option<String>,
    /// Print a JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// Runs `mrbrake uncertainty`.
pub fn run(a: UncertaintyArgs) -> CommandResult {
    let (spec_text, origin) = base_spec(a.spec.as_ref())?;
    let spec = BrakeSpec::from_toml_str(&spec_text, &origin)?;
    let declarations = Declarations::from_path(&a.inputs, spec.configuration.is_drum())?;
    let settings = mrbrake::explore::EvaluationSettings {
        study: recorded_metrics(&a.record)?,
        curve_points: a.curve_points,
        ..a.analysis.settings()?
    };
    let request = UncertaintyRequest {
        spec_toml: &spec_text,
        spec_origin: &origin,
        declarations: &declarations,
        samples: a.samples,
        seed: a.seed,
        settings,
        metrics: a.metric.clone(),
        bootstrap: a.bootstrap,
        jobs: a.jobs,
    };
    let store_path = a.store.clone().unwrap_or_else(|| a.inputs.with_extension("store"));
    let created_by = format!("mrbrake {}", env!("CARGO_PKG_VERSION"));
    let mut store = runner::open_sweep_store(&store_path, a.resume, &created_by)?;
    let mut display = ProgressDisplay::new("uncertainty", a.json);
    let result = uncertainty::propagate(&mut store, &request, &mut |p: &Progress| {
        display.update(p);
        Flow::Continue
    })
    .map_err(|e| e.with_field_names(&[("points", "--curve-points"), ("samples", "--samples")]))?;
    display.finish();
    if let Some(dir) = &a.plots {
        let doc = UncertaintyDocument::of(&result)?;
        let metric = a.tornado.as_deref().or(doc.main_metric());
        let title = format!("{}: torque–current band", spec.name);
        let measured = a.spec.is_none().then(plots::thesis_prototype);
        StagedDir::write(dir, |staging| {
            plots::write_plots(&doc, staging, &title, measured.as_ref(), metric, a.png)
        })?
        .commit()?;
    }
    if a.json {
        return print_json(&mrbrake::report::uncertainty::json(&result));
    }
    print_text(&mrbrake::report::uncertainty::text(&result, &spec.name))
}
