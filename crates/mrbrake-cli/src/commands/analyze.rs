//! `mrbrake analyze [SPEC.toml]`: the main job — field, torque–current curve, coil and mechanics of a
//! brake design; with no spec, the thesis's bidirectional brake (embedded default).

use std::path::{Path, PathBuf};

use clap::Args;
use mrbrake_design::analysis::{self, Analysis, AnalysisOptions, ElementOrder, FieldAtMaxCurrent};
use mrbrake_design::mesh_build::MeshLevel;
use mrbrake_design::spec::{BrakeSpec, default_spec};
use mrbrake_report::chart::{Figure, Panel, Series, SeriesLabelPosition};
use mrbrake_report::field_map::{FieldMap, save_field_map};
use mrbrake_units::{Dimension, parse};

use crate::exit::InputError;
use crate::output::print_json;

/// Arguments of `mrbrake analyze`.
#[derive(Debug, Args)]
pub struct AnalyzeArgs {
    /// Brake specification (TOML). Omitted: the embedded thesis bidirectional brake
    /// (examples/specs/thesis-bidirectional.toml).
    spec: Option<PathBuf>,
    /// Mesh density: coarse, default or fine.
    #[arg(long, default_value = "default")]
    mesh: String,
    /// Element order of the field solution: 1 (linear triangles) or 2 (quadratic, 6-node
    /// triangles on the same mesh: about four times the unknowns, B one order more accurate).
    #[arg(long, value_name = "1|2", default_value_t = 1, value_parser = clap::value_parser!(u8).range(1..=2))]
    order: u8,
    /// Number of currents in the torque–current sweep (0 to the maximum current).
    #[arg(long, default_value_t = 21)]
    points: usize,
    /// Relative speed for the viscous torque (e.g. 1rad/s, 60rpm).
    #[arg(long, default_value = "1rad/s", allow_hyphen_values = true)]
    speed: String,
    /// Seal and bearing friction added to every torque (e.g. 0.05Nm).
    #[arg(long, default_value = "0Nm", allow_hyphen_values = true)]
    seal_friction: String,
    /// Copper temperature for the coil resistance (e.g. 20C, 75C).
    #[arg(long, default_value = "20C", allow_hyphen_values = true)]
    temperature: String,
    /// Write plots here: field map, torque–current curve, |B| along the gaps (SVG).
    #[arg(long, value_name = "DIR")]
    plot_dir: Option<PathBuf>,
    /// Also write PNG versions of the plots.
    #[arg(long)]
    png: bool,
    /// Print a JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// Runs `mrbrake analyze`.
pub fn run(a: AnalyzeArgs) -> anyhow::Result<()> {
    let spec = match &a.spec {
        Some(path) => BrakeSpec::from_path(path)?,
        None => default_spec(),
    };
    let options = AnalysisOptions {
        mesh: MeshLevel::parse(&a.mesh)?,
        points: a.points,
        speed_rad_s: parse(&a.speed, Dimension::AngularVelocity)
            .map_err(|e| InputError(format!("--speed: {e}")))?,
        seal_friction_nm: parse(&a.seal_friction, Dimension::Torque)
            .map_err(|e| InputError(format!("--seal-friction: {e}")))?,
        temperature_c: parse(&a.temperature, Dimension::TemperatureCelsius)
            .map_err(|e| InputError(format!("--temperature: {e}")))?,
        order: ElementOrder::from_degree(a.order.into()).expect("clap accepts only 1 and 2"),
    };
    if a.points < 2 {
        return Err(InputError(format!("--points must be at least 2, got {}", a.points)).into());
    }
    let (analysis, field) = analysis::analyze_with_field(&spec, &options)?;
    for w in &analysis.warnings {
        eprintln!("warning: {w}");
    }
    if let Some(dir) = &a.plot_dir {
        std::fs::create_dir_all(dir).map_err(|e| {
            InputError(format!("--plot-dir {}: cannot create it: {e}", dir.display()))
        })?;
        write_plots(&analysis, &field, dir, a.png)?;
    }
    if a.json {
        return print_json(&analysis);
    }
    print_text(&analysis, a.spec.as_deref());
    Ok(())
}

fn print_text(a: &Analysis, spec: Option<&Path>) {
    let source = spec.map_or("embedded default".to_string(), |p| p.display().to_string());
    crate::outln!("{} ({}, {source})", a.name, a.configuration);
    crate::outln!(
        "mesh: {} nodes, {} triangles (P{} elements, {} unknowns)",
        a.mesh.nodes,
        a.mesh.elements,
        a.mesh.order,
        a.mesh.unknowns
    );
    crate::outln!();
    crate::outln!("torque–current curve (direction 1, speed {} rad/s):", a.speed_rad_s);
    crate::outln!("  current [A]  torque [N·m]  thesis method [N·m]  mean B [T]  Newton its");
    for p in &a.torque_current_curve {
        crate::outln!(
            "  {:>10.3}  {:>12.4}  {:>19.4}  {:>10.4}  {:>10}",
            p.current_a,
            p.torque_nm,
            p.thesis_formula_nm,
            p.mean_b_t,
            p.newton_iterations
        );
    }
    let t = &a.torque;
    crate::outln!();
    crate::outln!("at {:.3} A:", a.max_current_a);
    crate::outln!("  torque (local Bingham + viscous) {:.4} N·m", t.at_max_current_nm);
    crate::outln!(
        "  thesis method (mean B -> tau_y)  {:.4} N·m at mean B = {:.4} T",
        t.thesis_formula_nm,
        t.mean_b_t
    );
    crate::outln!("  off-state torque                 {:.4} N·m", t.off_state_nm);
    if let Some(t2) = t.direction2_at_max_current_nm {
        crate::outln!("  direction 2 (own coil)           {t2:.4} N·m");
    }
    if let Some(c) = t.cross_coupling {
        crate::outln!(
            "  cross-coupling into idle unit    {:.2} % of the active unit's yield torque",
            100.0 * c
        );
    }
    crate::outln!();
    crate::outln!("gaps at the maximum current:");
    crate::outln!(
        "  gap unit  R [mm]  h [mm]  g [mm]  mean B [T]  max B [T]  tau_y(mean B) [kPa]  torque [N·m]"
    );
    for g in &a.gaps {
        crate::outln!(
            "  {:>3} {:>4} {:>7.2} {:>7.2} {:>7.2} {:>11.4} {:>10.4} {:>20.3} {:>13.4}",
            g.index,
            g.unit + 1,
            g.r_m * 1e3,
            g.height_m * 1e3,
            g.width_m * 1e3,
            g.mean_b_t,
            g.max_b_t,
            g.tau_y_pa / 1e3,
            g.torque_nm
        );
    }
    let c = &a.coil;
    crate::outln!();
    crate::outln!(
        "coil: {} turns of {:.3} mm wire, {:.1} m, {:.3} Ω at 20 °C ({:.3} Ω hot), J = {:.2} A/mm² (4.1), {:.2} W",
        c.turns,
        c.wire_diameter_m * 1e3,
        c.wire_length_m,
        c.resistance_20c_ohm,
        c.resistance_ohm,
        c.current_density_a_per_mm2,
        c.power_w
    );
    crate::outln!(
        "      L = {:.2} mH (secant), {:.2} mH (incremental) at max current; L/R = {:.2} ms",
        c.inductance_h * 1e3,
        c.incremental_inductance_h * 1e3,
        c.time_constant_s * 1e3
    );
    let m = &a.mechanics;
    crate::out!(
        "mechanics: mass {:.3} kg, envelope {:.1} cm³, rotor inertia {:.1} kg·mm²",
        m.mass_kg,
        m.volume_m3 * 1e6,
        m.rotor_inertia_kg_m2 * 1e6
    );
    if let Some(j2) = m.rotor_inertia_direction2_kg_m2 {
        crate::out!(" (direction 2: {:.1} kg·mm²)", j2 * 1e6);
    }
    crate::outln!();
    crate::outln!(
        "           torque density {:.1} kN·m/m³, {:.3} N·m/kg",
        m.torque_density_nm_per_m3 / 1e3,
        m.torque_density_nm_per_kg
    );
    let tm = &a.timings_s;
    crate::outln!();
    crate::outln!(
        "time: {:.3} s (mesh {:.3}, setup {:.3}, solve {:.3}, post {:.3})",
        tm.total,
        tm.mesh,
        tm.setup,
        tm.solve,
        tm.post
    );
}

fn write_plots(
    a: &Analysis,
    field: &FieldAtMaxCurrent,
    dir: &Path,
    png: bool,
) -> anyhow::Result<()> {
    let extensions: &[&str] = if png { &["svg", "png"] } else { &["svg"] };
    // Torque–current curve.
    let pts = |f: fn(&analysis::CurvePoint) -> f64| -> Vec<(f64, f64)> {
        a.torque_current_curve.iter().map(|p| (p.current_a, f(p))).collect()
    };
    let curve = Figure::new(format!("{}: torque–current curve", a.name)).panel(
        Panel::new("current [A]", "torque [N·m]")
            .series(Series::line_points("local Bingham + viscous", pts(|p| p.torque_nm)))
            .series(Series::dashed("thesis method (mean B)", pts(|p| p.thesis_formula_nm))),
    );
    // |B| along each gap at the maximum current.
    let mut gaps = Panel::new("position along the gap [mm]", "|B| [T]")
        .legend(SeriesLabelPosition::LowerRight);
    for g in &a.gaps {
        let profile = g.profile.iter().map(|&(s, b)| (s * 1e3, b)).collect();
        gaps = gaps.series(Series::line(format!("gap {} (unit {})", g.index, g.unit + 1), profile));
    }
    let gap_fig =
        Figure::new(format!("{}: |B| along the fluid gaps at {} A", a.name, a.max_current_a))
            .panel(gaps);
    // Field map.
    let mesh = field.solver.mesh();
    let element_b = field.solver.element_b(&field.solution);
    let b_abs: Vec<f64> = element_b.iter().map(|b| b[0].hypot(b[1])).collect();
    let psi = field.solver.flux_function(&field.solution);
    let title = format!("{}: |B| and flux lines at {} A", a.name, a.max_current_a);
    let map = FieldMap {
        title: &title,
        nodes: &mesh.nodes,
        triangles: &mesh.triangles,
        region_tags: &mesh.triangle_tags,
        b_abs_t: &b_abs,
        flux_function: &psi,
        flux_lines: 24,
    };
    for ext in extensions {
        curve.save(&dir.join(format!("torque_current.{ext}")))?;
        gap_fig.save(&dir.join(format!("gap_flux_density.{ext}")))?;
        save_field_map(&map, &dir.join(format!("field_map.{ext}")))?;
    }
    Ok(())
}
