//! One module per subcommand; each defines its clap arguments and a `run` function.
//! To add a subcommand: a `mod` line, an enum variant and a match arm.

use crate::error::CommandResult;
use clap::Subcommand;

mod analyze;
mod calibrate;
mod characterize;
mod export_geo;
mod fem;
mod field_flags;
mod formula;
mod freqresp;
mod haptic;
mod materials;
mod optimize;
mod report;
mod response;
mod rig;
mod schema;
mod studio;
mod study;
mod sweep;
mod tfest;
mod thermal;
mod uncertainty;

/// The subcommands of `mrbrake`.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Analyse a brake design: field in every gap, torque–current curve, coil, mechanics, plots.
    /// With no SPEC, the thesis's bidirectional brake.
    Analyze(analyze::AnalyzeArgs),
    /// Closed-form thesis models: brake torque (single disc, multi-disc, drum, multi-drum) and coil.
    #[command(subcommand)]
    Formula(formula::FormulaCommand),
    /// The built-in material library: list names, show curves, derived values and provenance.
    #[command(subcommand)]
    Materials(materials::MaterialsCommand),
    /// Haptic simulation: virtual wall with a conventional brake, the bidirectional brake or a motor; Z-width map.
    #[command(subcommand)]
    Haptic(haptic::HapticCommand),
    /// Hysteresis branches, inverse model and loop plot from a repeated-ramp test-rig log (§5.3.1).
    Characterize(characterize::CharacterizeArgs),
    /// Gain, phase and tracking RMSE per frequency from sinusoidal test logs listed in a manifest (§5.3.2).
    Freqresp(freqresp::FreqRespArgs),
    /// Continuous-time transfer function from frequency-response data.
    Tfest(tfest::TfestArgs),
    /// Predicted dynamics of a brake design: torque step response and small-signal frequency
    /// response (eddy currents in the flux path, the coil circuit, the fluid's lag).
    Response(response::ResponseArgs),
    /// Temperatures of a brake design: steady hot spot, warm-up, time to the insulation limit,
    /// continuous current rating and duty cycle, and what heat does to the brake.
    Thermal(thermal::ThermalArgs),
    /// Axisymmetric non-linear magnetostatic finite elements (problem files, Gmsh meshes).
    #[command(subcommand)]
    Fem(fem::FemCommand),
    /// Virtual test rig: simulate the thesis's experiments and write their logs.
    #[command(subcommand)]
    Rig(rig::RigCommand),
    /// Design studies: the thesis's comparison tables on mrbrake's geometries.
    #[command(subcommand)]
    Study(study::StudyCommand),
    /// Write the brake geometry and its physical groups as a Gmsh .geo file (cross-check in other solvers).
    ExportGeo(export_geo::ExportGeoArgs),
    /// Parameter sweep over spec fields (grid, Latin hypercube, Sobol'), every design analysed by the
    /// FEA and kept in a resumable SQLite store; shardable over processes.
    Sweep(sweep::SweepArgs),
    /// Constrained single- or multi-objective design optimisation (NSGA-II, pattern search) from a
    /// problem file: Pareto front, plots and ready-to-analyse spec files.
    Optimize(optimize::OptimizeArgs),
    /// Merge results stores (e.g. one per shard) into one, without duplicates.
    Merge(sweep::MergeArgs),
    /// Export a results store as CSV or JSON.
    Export(sweep::ExportArgs),
    /// Uncertainty bands and global sensitivities: declared uncertain inputs (--inputs FILE)
    /// sampled by scrambled Sobol' points through the FEA, each sample kept in a resumable store.
    Uncertainty(uncertainty::UncertaintyArgs),
    /// Calibration against a rig: fit spec fields (--parameter) so the predicted torque–current
    /// curve matches a characterisation log's loop; estimates, standard errors, correlations,
    /// unidentifiable groups, a calibrated spec (-o) and brake model (--save-model).
    Calibrate(calibrate::CalibrateArgs),
    /// One self-contained HTML report (offline, printable on A4): a design ([SPEC]; default the
    /// thesis brake), a study (--store) or a characterisation (--log, --frd).
    Report(report::ReportArgs),
    /// The JSON Schema of an input format (spec, magnetics, heat, study) for editors (taplo, Even
    /// Better TOML), or with --markdown its reference page (docs/reference/).
    Schema(schema::SchemaArgs),
    /// Design a brake in the browser: a local web application with the spec's form, the
    /// cross-section, and torque and field solved as you type. Prints its address (with a session
    /// token) on the first line and serves until interrupted.
    Studio(studio::StudioArgs),
}

/// Runs one subcommand.
pub fn run(command: Command) -> CommandResult {
    match command {
        Command::Analyze(a) => analyze::run(a),
        Command::Formula(c) => formula::run(c),
        Command::Materials(c) => materials::run(c),
        Command::Haptic(c) => haptic::run(c),
        Command::Characterize(a) => characterize::run(a),
        Command::Freqresp(a) => freqresp::run(a),
        Command::Tfest(a) => tfest::run(a),
        Command::Rig(c) => rig::run(c),
        Command::Response(a) => response::run(a),
        Command::Thermal(a) => thermal::run(a),
        Command::Fem(c) => fem::run(c),
        Command::Study(c) => study::run(c),
        Command::ExportGeo(a) => export_geo::run(a),
        Command::Sweep(a) => sweep::run_sweep(a),
        Command::Optimize(a) => optimize::run(a),
        Command::Merge(a) => sweep::run_merge(a),
        Command::Export(a) => sweep::run_export(a),
        Command::Uncertainty(a) => uncertainty::run(a),
        Command::Calibrate(a) => calibrate::run(a),
        Command::Report(a) => report::run(a),
        Command::Schema(a) => schema::run(a),
        Command::Studio(a) => studio::run(a),
    }
}
