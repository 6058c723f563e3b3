//! `mrbrake export-geo`: the brake geometry and physical groups as a Gmsh `.geo` file, so the model
//! can be meshed and solved in another tool for a cross-check.

use std::path::PathBuf;

use crate::error::Context;
use crate::output::print_text;
use clap::Args;

use crate::error::CommandResult;
use mrbrake::design::mesh_build::MeshLevel;
use mrbrake::design::spec::{BrakeSpec, default_spec};
use mrbrake::report::geometry as geometry_report;

/// Arguments of `mrbrake export-geo`.
#[derive(Debug, Args)]
pub struct ExportGeoArgs {
    /// Brake specification (TOML). Without it, the embedded thesis bidirectional brake is exported.
    pub spec: Option<PathBuf>,
    /// Output `.geo` file (written atomically).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Mesh density for the characteristic lengths: coarse, default or fine.
    #[arg(long, default_value = "default")]
    pub mesh: String,
    /// Print a JSON summary (regions, gaps, coils, output path) instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Runs `mrbrake export-geo`.
pub fn run(args: ExportGeoArgs) -> CommandResult {
    let spec = match &args.spec {
        Some(path) => BrakeSpec::from_path(path)?,
        None => default_spec(),
    };
    let level = MeshLevel::parse(&args.mesh).map_err(super::field_flags::design)?;
    // The spec's errors name its file and lines.
    let validated = spec.validate()?;
    let warnings = validated.warnings;
    for w in &warnings {
        eprintln!("{w}");
    }
    let geometry = validated.geometry;
    let settings = level.settings(geometry.device.r1);
    let text = mrbrake::design::geo_export::to_geo(&geometry, &settings, &spec.name)?;
    mrbrake::report::write_atomic(&args.output, text.as_bytes())
        .with_context(|| format!("writing {}", args.output.display()))?;
    if args.json {
        let warnings: Vec<String> = warnings.iter().map(ToString::to_string).collect();
        let report = geometry_report::export_json(&geometry, &spec.name, &args.output, &warnings);
        return crate::output::print_json(&report);
    }
    print_text(&geometry_report::export_text(&geometry, &args.output))
}
