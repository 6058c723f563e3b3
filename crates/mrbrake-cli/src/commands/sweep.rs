//! `mrbrake sweep`, `mrbrake merge` and `mrbrake export`: parameter sweeps over brake-spec fields
//! into a results store, combining the stores of shards, and exporting a store to CSV / JSON.

use std::path::PathBuf;

use super::field_flags;
use crate::error::Context;
use clap::Args;
use mrbrake::design::mesh_build::MeshLevel;
use mrbrake::design::spec::DEFAULT_SPEC_TOML;
use mrbrake::explore::metrics::StudyMetrics;
use mrbrake::explore::plan::{self, Sampling, Shard, SweepPlan, SweepRequest};
use mrbrake::explore::variable::parse_sets;
use mrbrake::explore::{EvaluationSettings, Progress, Runner, runner, stored};
use mrbrake::observe::Flow;
use mrbrake::report::study::{self as study_report, SweepReport};
use mrbrake::store::Store;
use mrbrake::units::{Dimension, parse};

use crate::error::CommandResult;
use crate::output::{print_json, print_text};
use crate::progress::ProgressDisplay;

/// Arguments of `mrbrake sweep`.
#[derive(Debug, Args)]
pub struct SweepArgs {
    /// Base brake specification (TOML). Omitted: the embedded thesis bidirectional brake.
    spec: Option<PathBuf>,
    /// A variable and its values: a list `g=0.5mm,0.75mm,1mm`, a range with a count
    /// `h=5mm..10mm:6`, or bounds `R0=20mm..30mm` for --sample; for a part's material the
    /// materials by name, `materials.bobbin=aluminium,stainless-304,pom`. Names: a spec field
    /// (drum.gap, coil.turns, materials.bobbin, …) or a thesis symbol (g, h, d, R0, R1, R2, n, N,
    /// I, AWG). Repeat for several.
    #[arg(long = "vary", value_name = "NAME=VALUES", required = true)]
    vary: Vec<String>,
    /// A fixed change to the base spec, e.g. `coil.turns=fill` (turns fill the window),
    /// `housing.case_thickness=4mm` or `materials.bobbin=pom`. Repeatable.
    #[arg(long = "set", value_name = "PATH=VALUE")]
    set: Vec<String>,
    /// Sample instead of a full-factorial grid: `lhs:N` (Latin hypercube) or `sobol:N`.
    #[arg(long, value_name = "KIND:N")]
    sample: Option<String>,
    /// Seed of the Latin hypercube.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Results store (SQLite file). Created if missing; an existing store needs --resume.
    #[arg(long, value_name = "FILE")]
    store: PathBuf,
    /// Continue an existing store: designs already in it are not recomputed.
    #[arg(long)]
    resume: bool,
    /// Analyses run at the same time (0: one per core).
    #[arg(long, default_value_t = 0)]
    jobs: usize,
    /// Evaluate only shard K of N of the plan (0-based, e.g. `$SLURM_ARRAY_TASK_ID/4`); each shard
    /// fills its own store, `mrbrake merge` combines them.
    #[arg(long, value_name = "K/N")]
    shard: Option<String>,
    #[command(flatten)]
    analysis: AnalysisSettingsArgs,
    /// Also compute and store a dynamics or heat metric (e.g. t63_s, continuous_current_A; the
    /// list: `mrbrake optimize --list-metrics`), with `mrbrake response`'s and `mrbrake
    /// thermal`'s default settings (a problem file's [response]/[thermal] set them). Repeatable.
    #[arg(long = "record", value_name = "METRIC")]
    record: Vec<String>,
    /// Also write this sweep's designs as CSV.
    #[arg(long, value_name = "FILE")]
    csv: Option<PathBuf>,
    /// Print a JSON object (designs and run summary) instead of text.
    #[arg(long)]
    json: bool,
}

/// Arguments of `mrbrake merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// The store to merge into (created if missing).
    output: PathBuf,
    /// Stores to merge (e.g. one per shard).
    #[arg(required = true)]
    inputs: Vec<PathBuf>,
}

/// Arguments of `mrbrake export`.
#[derive(Debug, Args)]
pub struct ExportArgs {
    /// The store.
    store: PathBuf,
    /// Write every design as CSV to this file.
    #[arg(long, value_name = "FILE")]
    csv: Option<PathBuf>,
    /// Print every design as JSON.
    #[arg(long)]
    json: bool,
}

/// The evaluation settings from the common flags.
pub fn settings_from(mesh: &str, speed: &str, order: u8) -> CommandResult<EvaluationSettings> {
    Ok(EvaluationSettings {
        mesh: MeshLevel::parse(mesh).map_err(super::field_flags::design)?,
        speed_rad_s: parse(speed, Dimension::AngularVelocity).context("--speed")?,
        order: field_flags::order(order)?,
        ..EvaluationSettings::default()
    })
}

/// The settings every analysis of a study shares (`sweep`, `uncertainty`, `calibrate`).
#[derive(Debug, clap::Args)]
pub(crate) struct AnalysisSettingsArgs {
    /// Mesh density of every analysis: coarse, default or fine.
    #[arg(long, default_value = "default")]
    mesh: String,
    /// Element order of every analysis: 1 (linear) or 2 (quadratic triangles).
    #[arg(long, value_name = "1|2", default_value_t = 1)]
    order: u8,
    /// Relative speed for the viscous (off-state) torque (e.g. 1rad/s, 60rpm).
    #[arg(long, default_value = "1rad/s", allow_hyphen_values = true)]
    speed: String,
}

impl AnalysisSettingsArgs {
    /// The evaluation settings they give (static: no study metrics).
    pub(crate) fn settings(&self) -> CommandResult<EvaluationSettings> {
        settings_from(&self.mesh, &self.speed, self.order)
    }
}

/// The base spec's text and where it came from.
pub(crate) fn base_spec(spec: Option<&PathBuf>) -> CommandResult<(String, String)> {
    Ok(match spec {
        Some(path) => (
            mrbrake::error::read::text(path, mrbrake::error::read::SETTINGS)
                .with_context(|| format!("cannot read the spec {}", path.display()))?,
            path.display().to_string(),
        ),
        None => (DEFAULT_SPEC_TOML.to_string(), "thesis-bidirectional.toml (embedded)".into()),
    })
}

/// The sweep's plan and shard, from the arguments.
fn plan_from(a: &SweepArgs) -> CommandResult<(SweepPlan, Shard)> {
    let (spec_text, origin) = base_spec(a.spec.as_ref())?;
    let overrides = parse_sets(&a.set).map_err(field_flags::study)?;
    let sampling = match &a.sample {
        Some(text) => Sampling::parse(text, a.seed).map_err(field_flags::study)?,
        None => Sampling::FullFactorial,
    };
    let shard = match &a.shard {
        Some(text) => Shard::parse(text).map_err(field_flags::study)?,
        None => Shard::ALL,
    };
    let request = SweepRequest {
        spec_text: &spec_text,
        origin: &origin,
        overrides: &overrides,
        vary: &a.vary,
        sampling,
        shard,
        settings: EvaluationSettings {
            study: recorded_metrics(&a.record)?,
            ..a.analysis.settings()?
        },
    };
    let plan = plan::sweep_plan(&request).map_err(field_flags::study)?;
    mrbrake::explore::metrics::check_space(&plan.space, std::path::Path::new(&origin))?;
    Ok((plan, shard))
}

/// The metrics of `--record`, each a known metric (a static one is computed anyway).
pub(crate) fn recorded_metrics(names: &[String]) -> CommandResult<StudyMetrics> {
    let mut asked = Vec::with_capacity(names.len());
    for name in names {
        // The library's rule (a current or legacy name), named by the flag.
        let info = mrbrake::explore::problem::known_metric(name)
            .map_err(|e| e.with_field_names(&[("metric", "--record")]))?;
        asked.push(info.name);
    }
    Ok(StudyMetrics::new(asked, &[], Default::default(), Default::default()))
}

/// Runs `mrbrake sweep`.
pub fn run_sweep(a: SweepArgs) -> CommandResult {
    let (SweepPlan { space, plan_points, designs }, shard) = plan_from(&a)?;
    let created_by = format!("mrbrake {}", env!("CARGO_PKG_VERSION"));
    let mut store = runner::open_sweep_store(&a.store, a.resume, &created_by)?;
    let mut display = ProgressDisplay::new("sweep", a.json);
    let mut runner = Runner::new(&mut store, space.settings().clone(), a.jobs);
    let (records, summary) = runner.run(&designs, &mut |p: &Progress| {
        display.update(p);
        Flow::Continue
    })?;
    display.finish();

    if let Some(path) = &a.csv {
        mrbrake::report::write_atomic(path, &mrbrake::store::to_csv(&records)?)?;
    }
    let name = if a.json { None } else { space.base_design()?.spec.map(|s| s.name).ok() };
    let report = SweepReport {
        name: name.as_deref().unwrap_or_default(),
        variables: space.variables(),
        records: &records,
        summary: &summary,
        plan_points,
        shard,
        store: &a.store,
    };
    if a.json {
        return print_json(&report.json());
    }
    print_text(&report.text())
}

/// Runs `mrbrake merge`.
pub fn run_merge(a: MergeArgs) -> CommandResult {
    // Every input is checked (read-only) before the output is created, so a bad input leaves no
    // empty output store behind.
    for input in &a.inputs {
        let store = Store::open_read_only(input)?;
        warn_unverified(&store)?;
        store.close()?;
    }
    let created = !a.output.exists();
    let mut store = Store::open_or_create(&a.output, true)?;
    let mut total = 0;
    for input in &a.inputs {
        // A store written before the unit convention merges under the current metric names.
        let summary = match stored::merge_into(&mut store, input) {
            Ok(summary) => summary,
            Err(error) => {
                // A store this command created and could not fill is removed again.
                if created && total == 0 && store.is_empty().unwrap_or(false) {
                    store.close()?;
                    let _ = std::fs::remove_file(&a.output);
                }
                return Err(error.into());
            }
        };
        total += summary.inserted;
        // A line per input as it is merged (each ends with one newline, as every output).
        print_text(&study_report::merge_text(input, &summary))?;
    }
    let designs = mrbrake::report::wording::count(store.len()?, "design", "designs");
    print_text(&format!("{}: {designs} ({total} added)", a.output.display()))
}

/// Runs `mrbrake export`.
pub fn run_export(a: ExportArgs) -> CommandResult {
    // Read-only: an export never changes the store (nor migrates an old one).
    let store = Store::open_read_only(&a.store)?;
    warn_unverified(&store)?;
    // A store written before the unit convention exports under the current metric names.
    let records = stored::read_records(&store)?;
    if let Some(path) = &a.csv {
        mrbrake::report::write_atomic(path, &mrbrake::store::to_csv(&records)?)?;
    }
    if a.json {
        return print_json(&mrbrake::store::to_json(&records));
    }
    if a.csv.is_none() {
        print_text(&study_report::store_summary_text(&a.store, &records))?;
    }
    Ok(())
}

/// Says once, on stderr, that a store holds records written before checksums (read unverified).
fn warn_unverified(store: &Store) -> CommandResult {
    let unverified = store.unverified_len()?;
    if unverified > 0 {
        eprintln!(
            "warning: {}: {unverified} of {} records were written before per-record checksums \
             (mrbrake store schema 1) and are read unverified",
            store.path().display(),
            store.len()?
        );
    }
    Ok(())
}
