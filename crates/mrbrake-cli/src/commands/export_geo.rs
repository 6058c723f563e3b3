//! `mrbrake export-geo`: the brake geometry and physical groups as a Gmsh `.geo` file, so the model
//! can be meshed and solved in another tool for a cross-check.

use std::path::PathBuf;

use anyhow::Context;
use clap::Args;

use mrbrake_design::mesh_build::MeshLevel;
use mrbrake_design::spec::{BrakeSpec, default_spec};

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
pub fn run(args: ExportGeoArgs) -> anyhow::Result<()> {
    let spec = match &args.spec {
        Some(path) => BrakeSpec::from_path(path)?,
        None => default_spec(),
    };
    let level = MeshLevel::parse(&args.mesh)?;
    // The spec's errors name its file and lines.
    let validated = spec.validate()?;
    let warnings = validated.warnings;
    for w in &warnings {
        eprintln!("{w}");
    }
    let geometry = validated.geometry;
    let settings = level.settings(geometry.device.r1);
    let text = mrbrake_design::geo_export::to_geo(&geometry, &settings, &spec.name)?;
    mrbrake_report::write_atomic(&args.output, text.as_bytes())
        .with_context(|| format!("writing {}", args.output.display()))?;
    if args.json {
        let regions: Vec<_> = geometry
            .regions
            .iter()
            .map(|r| serde_json::json!({ "tag": r.tag, "name": r.name, "material": r.material, "area_m2": r.area_m2() }))
            .collect();
        let gaps: Vec<_> = geometry
            .gaps
            .iter()
            .map(|g| {
                serde_json::json!({
                    "index": g.index, "unit": g.unit + 1, "index_in_unit": g.index_in_unit, "tag": g.tag,
                    "r_m": g.shear_radius_m, "height_m": g.height_m, "width_m": g.width_m,
                    "inner_wall_tag": g.inner_wall_tag, "outer_wall_tag": g.outer_wall_tag,
                })
            })
            .collect();
        let coils: Vec<_> = geometry
            .coils
            .iter()
            .map(|c| serde_json::json!({ "tag": c.tag, "unit": c.unit + 1, "turns": c.turns, "current_sign": c.current_sign }))
            .collect();
        crate::output::print_json(&serde_json::json!({
            "output": args.output.display().to_string(),
            "spec": spec.name,
            "axis_tag": geometry.axis_tag,
            "outer_tag": geometry.outer_tag,
            "regions": regions,
            "gaps": gaps,
            "coils": coils,
            "warnings": warnings.iter().map(ToString::to_string).collect::<Vec<_>>(),
        }))
    } else {
        crate::outln!(
            "wrote {} ({} regions, {} fluid gaps, {} coils; mesh it with: gmsh -2 {})",
            args.output.display(),
            geometry.regions.len(),
            geometry.gaps.len(),
            geometry.coils.len(),
            args.output.display()
        );
        Ok(())
    }
}
