//! The report of a brake analysis (`mrbrake_design::analysis`): the text summary (torque–current
//! curve, gaps, coil, mechanics, timings) and the plots (torque–current curve, |B| along the fluid
//! gaps, the field map with flux lines at the maximum current).

use std::fmt::Write as _;
use std::path::Path;

use mrbrake_design::analysis::{Analysis, CurvePoint, FieldAtMaxCurrent};

use crate::ReportError;
use crate::chart::{Figure, Panel, Series, SeriesLabelPosition};
use crate::field_map::{FieldMap, View, save_field_map};

/// Flux lines drawn on the field map.
const FLUX_LINES: usize = 24;

/// The text report of `a`; `source` says where the spec came from (its path, or
/// `"embedded default"`).
pub fn text(a: &Analysis, source: &str) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "{} ({}, {source})", a.name, a.configuration);
    let _ = writeln!(
        out,
        "mesh: {} nodes, {} triangles (P{} elements, {} unknowns)",
        a.mesh.nodes, a.mesh.elements, a.mesh.order, a.mesh.unknowns
    );
    let _ = writeln!(out);
    curve_text(&mut out, a);
    torque_text(&mut out, a);
    gaps_text(&mut out, a);
    coil_and_mechanics_text(&mut out, a);
    let tm = &a.timings_s;
    let _ = writeln!(out);
    let _ = writeln!(
        out,
        "time: {:.3} s (mesh {:.3}, setup {:.3}, solve {:.3}, post {:.3})",
        tm.total, tm.mesh, tm.setup, tm.solve, tm.post
    );
    out
}

/// The torque–current table.
fn curve_text(out: &mut String, a: &Analysis) {
    let _ = writeln!(out, "torque–current curve (direction 1, speed {} rad/s):", a.speed_rad_s);
    let _ =
        writeln!(out, "  current [A]  torque [N·m]  thesis method [N·m]  mean B [T]  Newton its");
    for p in &a.torque_current_curve {
        let _ = writeln!(
            out,
            "  {:>10.3}  {:>12.4}  {:>19.4}  {:>10.4}  {:>10}",
            p.current_a, p.torque_nm, p.thesis_formula_nm, p.mean_b_t, p.newton_iterations
        );
    }
}

/// The torques at the maximum current (both directions, cross-coupling).
fn torque_text(out: &mut String, a: &Analysis) {
    let t = &a.torque;
    let _ = writeln!(out);
    let _ = writeln!(out, "at {:.3} A:", a.max_current_a);
    let _ = writeln!(out, "  torque (local Bingham + viscous) {:.4} N·m", t.at_max_current_nm);
    let _ = writeln!(
        out,
        "  thesis method (mean B -> tau_y)  {:.4} N·m at mean B = {:.4} T",
        t.thesis_formula_nm, t.mean_b_t
    );
    let _ = writeln!(out, "  off-state torque                 {:.4} N·m", t.off_state_nm);
    off_state_text(out, a);
    if let Some(t2) = t.direction2_at_max_current_nm {
        let _ = writeln!(out, "  direction 2 (own coil)           {t2:.4} N·m");
    }
    if let Some(c) = t.cross_coupling {
        let _ = writeln!(
            out,
            "  cross-coupling into idle unit    {:.2} % of the active unit's yield torque",
            100.0 * c
        );
    }
}

/// The off-state torque's terms, each with its source, and the rotors' magnetic pull.
fn off_state_text(out: &mut String, a: &Analysis) {
    for (name, _, value, source) in a.torque_off.terms() {
        let _ = writeln!(out, "    {name:<10} {value:>9.5} N·m  {source}");
    }
    let f = &a.rotor_forces;
    for u in &f.units {
        let _ = writeln!(
            out,
            "  axial pull on unit {}'s rotor     {:.3} N at {:.3} A",
            u.unit + 1,
            u.axial_force_n,
            f.current_a
        );
    }
    if f.bearing_friction_nm > 0.0 {
        let _ =
            writeln!(out, "  bearing friction with that pull  {:.5} N·m", f.bearing_friction_nm);
    }
}

/// One line per fluid gap at the maximum current.
fn gaps_text(out: &mut String, a: &Analysis) {
    let _ = writeln!(out);
    let _ = writeln!(out, "gaps at the maximum current:");
    let _ = writeln!(
        out,
        "  gap unit  R [mm]  h [mm]  g [mm]  mean B [T]  max B [T]  tau_y(mean B) [kPa]  torque [N·m]"
    );
    for g in &a.gaps {
        let _ = writeln!(
            out,
            "  {:>3} {:>4} {:>7.2} {:>7.2} {:>7.2} {:>11.4} {:>10.4} {:>20.3} {:>13.4}",
            g.index + 1,
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
}

/// The coil's electrical figures and the mechanics.
fn coil_and_mechanics_text(out: &mut String, a: &Analysis) {
    let c = &a.coil;
    let _ = writeln!(out);
    // At the 20 °C reference the hot resistance is the same number: say it once (compared as
    // printed, so a temperature a hair above 20 °C does not repeat it either).
    let (cold, hot) = (format!("{:.3}", c.resistance_20c_ohm), format!("{:.3}", c.resistance_ohm));
    let hot = if hot == cold { String::new() } else { format!(" ({hot} Ω hot)") };
    let _ = writeln!(
        out,
        "coil: {} turns of {:.3} mm wire, {:.1} m, {cold} Ω at 20 °C{hot}, J = {:.2} A/mm² (4.1), {:.2} W",
        c.turns,
        c.wire_diameter_m * 1e3,
        c.wire_length_m,
        c.current_density_a_per_mm2,
        c.power_w
    );
    let _ =
        writeln!(out, "      copper fill factor {:.3} (copper area / window area)", c.fill_factor);
    let _ = writeln!(
        out,
        "      L = {:.2} mH (secant), {:.2} mH (incremental) at max current; L/R = {:.2} ms",
        c.inductance_h * 1e3,
        c.incremental_inductance_h * 1e3,
        c.time_constant_s * 1e3
    );
    let m = &a.mechanics;
    let _ = write!(
        out,
        "mechanics: mass {:.3} kg, envelope {:.1} cm³, rotor inertia {:.1} kg·mm²",
        m.mass_kg,
        m.volume_m3 * 1e6,
        m.rotor_inertia_kg_m2 * 1e6
    );
    if let Some(j2) = m.rotor_inertia_direction2_kg_m2 {
        let _ = write!(out, " (direction 2: {:.1} kg·mm²)", j2 * 1e6);
    }
    let _ = writeln!(out);
    let _ = writeln!(
        out,
        "           torque density {:.1} kN·m/m³, {:.3} N·m/kg",
        m.torque_density_nm_per_m3 / 1e3,
        m.torque_density_nm_per_kg
    );
}

/// The torque–current curve: the local Bingham torque (with the viscous term) and the thesis's
/// mean-B method.
pub fn torque_current_figure(a: &Analysis) -> Figure {
    let pts = |f: fn(&CurvePoint) -> f64| -> Vec<(f64, f64)> {
        a.torque_current_curve.iter().map(|p| (p.current_a, f(p))).collect()
    };
    Figure::new(format!("{}: torque–current curve", a.name)).panel(
        Panel::new("current [A]", "torque [N·m]")
            .legend(SeriesLabelPosition::LowerRight)
            .series(Series::line_points("local Bingham + viscous", pts(|p| p.torque_nm)))
            .series(Series::dashed("thesis method (mean B)", pts(|p| p.thesis_formula_nm))),
    )
}

/// |B| along the mid-line of every fluid gap at the maximum current: one panel per unit (each
/// solved with its own coil energised), gaps and units numbered from 1, the y axis from 0 and
/// shared by the panels, neighbouring gaps told apart by colour and by solid/dashed lines.
pub fn gap_flux_density_figure(a: &Analysis) -> Figure {
    let units = a.gaps.iter().map(|g| g.unit + 1).max().unwrap_or(1);
    let b_top = a
        .gaps
        .iter()
        .flat_map(|g| g.profile.iter().map(|p| p.1))
        .filter(|b| b.is_finite())
        .fold(0.0, f64::max);
    // Every gap's whole height, the same in every panel (the mirrored unit's sample positions
    // can end a rounding error short of it).
    let s_end = a.gaps.iter().map(|g| g.height_m * 1e3).fold(0.0, f64::max);
    let mut figure =
        Figure::new(format!("{}: |B| along the fluid gaps at {} A", a.name, a.max_current_a))
            .columns(units)
            .size(if units > 1 { 1100 } else { 900 }, 560);
    for unit in 0..units {
        let caption = if units > 1 {
            format!("unit {}, its coil energised", unit + 1)
        } else {
            String::new()
        };
        let mut panel = Panel::new("position along the gap [mm]", "|B| [T]")
            .caption(caption)
            .y_range(0.0, (1.1 * b_top).max(1e-3))
            .legend(SeriesLabelPosition::LowerMiddle);
        if s_end > 0.0 {
            panel = panel.x_range(0.0, s_end);
        }
        for (k, g) in a.gaps.iter().filter(|g| g.unit == unit).enumerate() {
            let profile = g.profile.iter().map(|&(s, b)| (s * 1e3, b)).collect();
            let label = format!("gap {}", g.index + 1);
            let series = if k % 2 == 0 {
                Series::line(label, profile)
            } else {
                Series::dashed(label, profile)
            };
            panel = panel.series(series.color(GAP_COLOURS[k % GAP_COLOURS.len()]));
        }
        figure = figure.panel(panel);
    }
    figure
}

/// The torque–current curve as CSV: one row per current, the columns named as `analyze --json`
/// names the curve's keys.
pub fn torque_current_csv(a: &Analysis) -> String {
    let mut out = String::from(
        "current_A,torque_Nm,yield_torque_Nm,thesis_formula_Nm,mean_B_T,flux_linkage_Wb,newton_iterations\n",
    );
    for p in &a.torque_current_curve {
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{}",
            p.current_a,
            p.torque_nm,
            p.yield_torque_nm,
            p.thesis_formula_nm,
            p.mean_b_t,
            p.flux_linkage_wb,
            p.newton_iterations
        );
    }
    out
}

/// Palette indices of the gaps of one unit: blue, vermilion, bluish green, reddish purple (the
/// Okabe–Ito colours that stay dark enough on white; no yellow).
const GAP_COLOURS: [usize; 4] = [0, 1, 2, 3];

/// The title of the field map of `a`.
pub fn field_map_title(a: &Analysis) -> String {
    format!("{}: |B| and flux lines at {} A", a.name, a.max_current_a)
}

/// The field map (|B| and flux lines) of `field`, under `title`.
pub fn field_map<'a>(title: &'a str, field: &'a FieldAtMaxCurrent) -> FieldMap<'a> {
    FieldMap {
        title,
        nodes: &field.nodes,
        triangles: &field.triangles,
        region_tags: &field.region_tags,
        b_abs_t: &field.b_abs_t,
        flux_function: &field.flux_function_wb,
        flux_lines: FLUX_LINES,
        regions: &field.regions,
        view: View::Energised,
    }
}

/// Writes the plots of an analysis into the existing folder `dir`: `torque_current`,
/// `gap_flux_density` and `field_map`, as SVG and, with `png`, also as PNG.
pub fn write_plots(
    a: &Analysis,
    field: &FieldAtMaxCurrent,
    dir: &Path,
    png: bool,
) -> Result<(), ReportError> {
    let extensions: &[&str] = if png { &["svg", "png"] } else { &["svg"] };
    let curve = torque_current_figure(a);
    let gaps = gap_flux_density_figure(a);
    let title = field_map_title(a);
    let map = field_map(&title, field);
    for ext in extensions {
        curve.save(&dir.join(format!("torque_current.{ext}")))?;
        gaps.save(&dir.join(format!("gap_flux_density.{ext}")))?;
        save_field_map(&map, &dir.join(format!("field_map.{ext}")))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrbrake_design::analysis::{AnalysisOptions, AnalysisRequest};
    use mrbrake_design::mesh_build::MeshLevel;
    use mrbrake_design::spec::default_spec;

    /// The text has one line per current and per gap between fixed sections, and the plots are the
    /// three figures in each format.
    #[test]
    fn text_and_plots_of_the_thesis_brake() {
        let options = AnalysisOptions { mesh: MeshLevel::Coarse, points: 3, ..Default::default() };
        let (analysis, field) =
            AnalysisRequest::of(&default_spec()).options(options).run_with_field().unwrap();
        let text = text(&analysis, "embedded default");
        let lines: Vec<&str> = text.lines().collect();
        assert!(lines[0].ends_with("(bidirectional, embedded default)"), "{}", lines[0]);
        // Title, mesh, blank, curve title and header; 3 points; blank, "at", 5 torque lines (both
        // directions), 5 off-state terms, 2 rotor pulls; blank, 2 gap titles, 8 gaps; blank, 3
        // coil (the last its fill factor), 2 mechanics; blank, time.
        assert_eq!(lines.len(), 5 + 3 + 14 + 11 + 6 + 2, "{text}");
        assert!(lines[10].starts_with("  torque (local Bingham + viscous) "), "{}", lines[10]);
        assert!(lines[13].starts_with("    viscous ") && lines[17].starts_with("    remanent "));
        assert!(lines[18].starts_with("  axial pull on unit 1's rotor "), "{}", lines[18]);
        assert_eq!(lines[23], "gaps at the maximum current:");
        assert!(lines[35].starts_with("      copper fill factor 0."), "{}", lines[35]);
        assert!(lines[37].starts_with("mechanics: mass ") && lines[37].contains("(direction 2: "));
        assert!(lines[lines.len() - 1].starts_with("time: ") && text.ends_with(")\n"));
        // At the default 20 °C the resistance is said once; a hot coil adds its hot value.
        let coil = lines.iter().find(|l| l.starts_with("coil: ")).expect("a coil line");
        assert_eq!(coil.matches('Ω').count(), 1, "{coil}");
        assert!(coil.contains(" Ω at 20 °C, J = ") && !coil.contains("hot"), "{coil}");
        let mut hot = analysis.clone();
        hot.coil.resistance_ohm = 1.2 * hot.coil.resistance_20c_ohm;
        let text_hot = super::text(&hot, "embedded default");
        let coil = text_hot.lines().find(|l| l.starts_with("coil: ")).expect("a coil line");
        let expected = format!("({:.3} Ω hot), J = ", hot.coil.resistance_ohm);
        assert!(coil.contains(&expected), "{coil}");

        let dir = tempfile::tempdir().unwrap();
        write_plots(&analysis, &field, dir.path(), true).unwrap();
        for name in ["torque_current", "gap_flux_density", "field_map"] {
            for ext in ["svg", "png"] {
                let path = dir.path().join(format!("{name}.{ext}"));
                assert!(std::fs::metadata(&path).unwrap().len() > 1000, "{}", path.display());
            }
        }
        assert!(field_map_title(&analysis).ends_with("|B| and flux lines at 2 A"));

        // The field map shows the energised unit 1 (z from below 0 to its spacer, not unit 2),
        // labels its regions, and stays small (it was 3.2 MB of SVG polygons).
        let title = field_map_title(&analysis);
        let map = field_map(&title, &field);
        let (lo, hi) = map.window();
        let (_, whole_hi) = crate::field_map::bounds(&field.nodes);
        assert!(lo[0].abs() < 1e-12 && hi[1] < 0.6 * whole_hi[1], "{lo:?} {hi:?} of {whole_hi:?}");
        let svg = crate::field_map::field_map_svg(&map).unwrap();
        assert!(svg.len() < 900_000, "field map SVG of {} bytes", svg.len());
        assert!(!svg.contains("<polygon"), "triangles are one image, not polygons");
        for label in ["steel", "MR fluid gaps", "coil", "non-magnetic"] {
            assert!(svg.contains(&format!("\n{label}\n")), "no label {label}");
        }
        let gaps = gap_flux_density_figure(&analysis);
        assert_eq!(gaps.panels.len(), 2, "one panel per unit");
        let svg = gaps.to_svg().unwrap();
        assert!(svg.contains("gap 1") && svg.contains("gap 8") && !svg.contains("gap 0"));
    }
}
