//! The HTML report of a brake design (`mrbrake report [SPEC]`): what `mrbrake analyze` computes,
//! drawn and tabulated on one page, with the spec's assumptions and the provenance of every
//! material curve.
//!
//! Every number in its tables is a value of [`DesignReport::json`], which is the analysis as
//! `mrbrake analyze --json` prints it; each numeric cell names its JSON pointer (`data-json`).

use mrbrake_design::analysis::{Analysis, CoilResult, FieldAtMaxCurrent};
use mrbrake_design::geometry::BrakeGeometry;
use mrbrake_materials::{Magnetic, library};
use serde_json::Value;

use super::spec_notes::notes;
use super::writer::{Cell, Table};
use super::{Page, Section, cross_section, figure, inline_svg, png_figure};
use crate::ReportError;
use crate::analysis::{field_map, field_map_title, gap_flux_density_figure, torque_current_figure};
use crate::chart::{Figure, Panel, Series};
use crate::field_map::field_map_png;

/// A design to report.
#[derive(Debug)]
pub struct DesignReport<'a> {
    /// The analysis (as `mrbrake analyze` computes it).
    pub analysis: &'a Analysis,
    /// Its field at the maximum current.
    pub field: &'a FieldAtMaxCurrent,
    /// The geometry the analysis meshed.
    pub geometry: &'a BrakeGeometry,
    /// The spec file as written (its comments hold its assumptions).
    pub spec_text: &'a str,
    /// Where the spec came from (its path, or `embedded default`).
    pub source: &'a str,
    /// Compare with the thesis's published values (for the embedded thesis brake).
    pub thesis_comparison: bool,
    /// Further sections, after the design's own and before the spec and materials: the place for
    /// analyses composed elsewhere (step response and Bode diagram, temperature map and warm-up
    /// curve, when those analyses exist).
    pub extra_sections: Vec<Section>,
}

/// A value the thesis publishes for its final bidirectional brake, with where it says so.
struct ThesisValue {
    what: &'static str,
    unit: &'static str,
    thesis: f64,
    source: &'static str,
    /// JSON pointer of mrbrake's value and its display scale.
    pointer: &'static str,
    scale: f64,
}

/// Karabulut (2017)'s published values for the final design (section and table in the thesis).
const THESIS_VALUES: [ThesisValue; 7] = [
    ThesisValue {
        what: "mean |B| in the fluid at 2 A",
        unit: "T",
        thesis: 0.492,
        source: "§4.4.1 (ANSYS, simplified 3-D model)",
        pointer: "/torque/mean_B_T",
        scale: 1.0,
    },
    ThesisValue {
        what: "torque at 2 A, model",
        unit: "N·m",
        thesis: 4.33,
        source: "§4.4.2 (4.4), Table 4.7",
        pointer: "/torque/at_max_current_Nm",
        scale: 1.0,
    },
    ThesisValue {
        what: "torque at 2 A, measured on the prototype",
        unit: "N·m",
        thesis: 3.84,
        source: "§5.3.1, Table 5.1",
        pointer: "/torque/at_max_current_Nm",
        scale: 1.0,
    },
    ThesisValue {
        what: "rotor inertia (one direction)",
        unit: "kg·mm²",
        thesis: 54.8,
        source: "§4.3, Table 4.7",
        pointer: "/mechanics/rotor_inertia_kg_m2",
        scale: 1e6,
    },
    ThesisValue {
        what: "mass",
        unit: "kg",
        thesis: 3.5,
        source: "Table 4.7",
        pointer: "/mechanics/mass_kg",
        scale: 1.0,
    },
    ThesisValue {
        what: "outer diameter",
        unit: "mm",
        thesis: 80.0,
        source: "§4.5, Table 5.1",
        pointer: "/mechanics/outer_diameter_m",
        scale: 1e3,
    },
    ThesisValue {
        what: "length",
        unit: "mm",
        thesis: 124.0,
        source: "§4.5, Table 5.1",
        pointer: "/mechanics/length_m",
        scale: 1e3,
    },
];

impl DesignReport<'_> {
    /// The JSON document the page's numbers point into: the analysis, exactly as
    /// `mrbrake analyze --json` prints it.
    pub fn json(&self) -> Result<Value, ReportError> {
        Ok(serde_json::to_value(self.analysis)?)
    }

    /// The HTML page.
    pub fn html(self) -> Result<String, ReportError> {
        let json = self.json()?;
        let a = self.analysis;
        let m = &a.mesh;
        let facts = vec![
            format!("{} brake; spec: {}", a.configuration, self.source),
            format!(
                "Finite-element analysis: {} nodes, {} triangles, P{} elements ({} unknowns); \
                 maximum current {} A; viscous torque at {} rad/s.",
                m.nodes, m.elements, m.order, m.unknowns, a.max_current_a, a.speed_rad_s
            ),
        ];
        let mut sections = vec![
            self.summary(),
            self.cross_section(),
            self.field_map()?,
            self.torque_current()?,
            self.gaps()?,
            self.coil_and_mechanics(),
        ];
        if self.thesis_comparison {
            sections.push(thesis_section(&json));
        }
        let extra_ids: Vec<String> = self.extra_sections.iter().map(|s| s.id.clone()).collect();
        sections.extend(self.extra_sections);
        sections.push(not_included(&extra_ids));
        sections.push(spec_section(self.spec_text, &a.warnings));
        sections.push(materials_section(self.geometry)?);
        Ok(Page { title: a.name.clone(), facts, sections }.render())
    }

    fn summary(&self) -> Section {
        let a = self.analysis;
        let t = &a.torque;
        let mut s = Section::new("summary", "Summary");
        let mut table = Table::new("Key figures", &["quantity", "value", "unit"]);
        let mut row =
            |what: &str, value: f64, decimals: usize, pointer: &str, scale: f64, unit: &str| {
                table.row(vec![
                    Cell::text(what),
                    Cell::json(value, decimals, pointer, scale),
                    Cell::text(unit),
                ]);
            };
        let at = format!("torque at {} A (local Bingham + viscous)", a.max_current_a);
        row(&at, t.at_max_current_nm, 4, "/torque/at_max_current_Nm", 1.0, "N·m");
        row(
            "torque by the thesis's method (mean B → τy → formula)",
            t.thesis_formula_nm,
            4,
            "/torque/thesis_formula_Nm",
            1.0,
            "N·m",
        );
        row("off-state torque", t.off_state_nm, 4, "/torque/off_state_Nm", 1.0, "N·m");
        for (name, key, value, source) in a.torque_off.terms() {
            let what = format!("  off-state: {name} ({source})");
            row(&what, value, 5, &format!("/torque_off/{key}"), 1.0, "N·m");
        }
        row("dynamic range (on/off)", t.dynamic_range, 1, "/torque/dynamic_range", 1.0, "–");
        row("mean |B| in the fluid gaps", t.mean_b_t, 4, "/torque/mean_B_T", 1.0, "T");
        if let Some(t2) = t.direction2_at_max_current_nm {
            row(
                "direction 2 torque (own coil)",
                t2,
                4,
                "/torque/direction2_at_max_current_Nm",
                1.0,
                "N·m",
            );
        }
        if let Some(c) = t.cross_coupling {
            row("cross-coupling into the idle unit", c, 2, "/torque/cross_coupling", 100.0, "%");
        }
        row("coil power at the maximum current", a.coil.power_w, 2, "/coil/power_W", 1.0, "W");
        row(
            "electrical time constant L/R",
            a.coil.time_constant_s,
            2,
            "/coil/time_constant_s",
            1e3,
            "ms",
        );
        row(
            "rotor inertia",
            a.mechanics.rotor_inertia_kg_m2,
            1,
            "/mechanics/rotor_inertia_kg_m2",
            1e6,
            "kg·mm²",
        );
        row("mass (modelled parts)", a.mechanics.mass_kg, 3, "/mechanics/mass_kg", 1.0, "kg");
        s.body.table(&table);
        s
    }

    fn cross_section(&self) -> Section {
        let mut s = Section::new("cross-section", "Cross-section");
        let title = format!("{}: half cross-section in the r–z plane", self.analysis.name);
        let svg = cross_section::svg(self.geometry, "design", &title);
        figure(
            &mut s.body,
            &svg,
            "Half cross-section (axis of symmetry on the left, z along the shaft). Numbers refer to \
             the parts table; hatched parts rotate with the shaft; MR fluid in blue, coil copper, \
             steel grey, non-magnetic parts light.",
        );
        s.body.table(&cross_section::legend(self.geometry));
        s
    }

    fn field_map(&self) -> Result<Section, ReportError> {
        let mut s = Section::new("field-map", "Field map");
        let title = field_map_title(self.analysis);
        let (png, size) = field_map_png(&field_map(&title, self.field))?;
        let caption = format!(
            "|B| (colour) and flux lines at {} A, unit 1 energised, from the finite-element solution.",
            self.field.current_a
        );
        png_figure(&mut s.body, &png, size, &title, &caption);
        Ok(s)
    }

    fn torque_current(&self) -> Result<Section, ReportError> {
        let a = self.analysis;
        let mut s = Section::new("torque-current", "Torque–current curve");
        let svg = inline_svg(&torque_current_figure(a).to_svg()?, "torque–current curve")?;
        figure(
            &mut s.body,
            &svg,
            "Torque against coil current (direction 1): the local Bingham torque with the viscous term, \
             and the thesis's method (mean |B| over the gaps → τy → (4.4)).",
        );
        let mut t = Table::new(
            "Torque–current curve (direction 1)",
            &[
                "current [A]",
                "torque [N·m]",
                "yield torque [N·m]",
                "thesis method [N·m]",
                "mean |B| [T]",
                "flux linkage [mWb]",
                "Newton iterations",
            ],
        );
        for (k, p) in a.torque_current_curve.iter().enumerate() {
            let at = |field: &str| format!("/torque_current_curve/{k}/{field}");
            t.row(vec![
                Cell::json(p.current_a, 3, at("current_A"), 1.0),
                Cell::json(p.torque_nm, 4, at("torque_Nm"), 1.0),
                Cell::json(p.yield_torque_nm, 4, at("yield_torque_Nm"), 1.0),
                Cell::json(p.thesis_formula_nm, 4, at("thesis_formula_Nm"), 1.0),
                Cell::json(p.mean_b_t, 4, at("mean_B_T"), 1.0),
                Cell::json(p.flux_linkage_wb, 3, at("flux_linkage_Wb"), 1e3),
                Cell::json(p.newton_iterations as f64, 0, at("newton_iterations"), 1.0),
            ]);
        }
        s.body.table(&t);
        Ok(s)
    }

    fn gaps(&self) -> Result<Section, ReportError> {
        let a = self.analysis;
        let mut s = Section::new("gaps", "Fluid gaps");
        let svg = inline_svg(&gap_flux_density_figure(a).to_svg()?, "|B| along the gaps")?;
        figure(
            &mut s.body,
            &svg,
            "|B| along the mid-line of every fluid gap at the maximum current.",
        );
        let mut t = Table::new(
            format!("Gaps at {} A", a.max_current_a),
            &[
                "gap",
                "unit",
                "orientation",
                "R [mm]",
                "h [mm]",
                "g [mm]",
                "mean |B| [T]",
                "max |B| [T]",
                "τy(mean B) [kPa]",
                "torque [N·m]",
                "viscous [N·m]",
            ],
        );
        for (k, g) in a.gaps.iter().enumerate() {
            let at = |field: &str| format!("/gaps/{k}/{field}");
            t.row(vec![
                Cell::json((g.index + 1) as f64, 0, at("index"), 1.0),
                Cell::json((g.unit + 1) as f64, 0, at("unit"), 1.0),
                Cell::text(g.orientation),
                Cell::json(g.r_m, 2, at("r_m"), 1e3),
                Cell::json(g.height_m, 2, at("height_m"), 1e3),
                Cell::json(g.width_m, 2, at("width_m"), 1e3),
                Cell::json(g.mean_b_t, 4, at("mean_B_T"), 1.0),
                Cell::json(g.max_b_t, 4, at("max_B_T"), 1.0),
                Cell::json(g.tau_y_pa, 3, at("tau_y_Pa"), 1e-3),
                Cell::json(g.torque_nm, 4, at("torque_Nm"), 1.0),
                Cell::json(g.viscous_torque_nm, 5, at("viscous_torque_Nm"), 1.0),
            ]);
        }
        s.body.table(&t);
        Ok(s)
    }

    fn coil_and_mechanics(&self) -> Section {
        let mut s = Section::new("coil-mechanics", "Coil, mechanics and flux path");
        s.body.table(&coil_table(&self.analysis.coil));
        s.body.table(&mechanics_table(self.analysis));
        s
    }
}

/// The coil's table.
fn coil_table(c: &CoilResult) -> Table {
    let mut coil = Table::new("Coil", &["quantity", "value", "unit"]);
    for (what, v, d, p, scale, unit) in [
        ("turns", f64::from(c.turns), 0, "/coil/turns", 1.0, "–"),
        ("wire diameter", c.wire_diameter_m, 3, "/coil/wire_diameter_m", 1e3, "mm"),
        ("wire length", c.wire_length_m, 1, "/coil/wire_length_m", 1.0, "m"),
        ("resistance at 20 °C", c.resistance_20c_ohm, 3, "/coil/resistance_20C_ohm", 1.0, "Ω"),
        (
            "resistance at the analysis temperature",
            c.resistance_ohm,
            3,
            "/coil/resistance_ohm",
            1.0,
            "Ω",
        ),
        (
            "current density (4.1)",
            c.current_density_a_per_mm2,
            2,
            "/coil/current_density_A_per_mm2",
            1.0,
            "A/mm²",
        ),
        ("power at the maximum current", c.power_w, 2, "/coil/power_W", 1.0, "W"),
        ("inductance (secant)", c.inductance_h, 2, "/coil/inductance_H", 1e3, "mH"),
        (
            "inductance (incremental)",
            c.incremental_inductance_h,
            2,
            "/coil/incremental_inductance_H",
            1e3,
            "mH",
        ),
        ("time constant L/R", c.time_constant_s, 2, "/coil/time_constant_s", 1e3, "ms"),
        ("copper fill factor", c.fill_factor, 3, "/coil/fill_factor", 1.0, "–"),
    ] {
        coil.row(vec![Cell::text(what), Cell::json(v, d, p, scale), Cell::text(unit)]);
    }
    coil
}

/// The mechanics and flux-path table.
fn mechanics_table(a: &Analysis) -> Table {
    let (m, f) = (&a.mechanics, &a.flux_path);
    let mut mech = Table::new("Mechanics (modelled parts)", &["quantity", "value", "unit"]);
    let mut rows = vec![
        ("mass", m.mass_kg, 3, "/mechanics/mass_kg", 1.0, "kg"),
        ("envelope volume", m.volume_m3, 1, "/mechanics/volume_m3", 1e6, "cm³"),
        ("outer diameter", m.outer_diameter_m, 1, "/mechanics/outer_diameter_m", 1e3, "mm"),
        ("length", m.length_m, 1, "/mechanics/length_m", 1e3, "mm"),
        (
            "rotor inertia",
            m.rotor_inertia_kg_m2,
            1,
            "/mechanics/rotor_inertia_kg_m2",
            1e6,
            "kg·mm²",
        ),
    ];
    if let Some(j2) = m.rotor_inertia_direction2_kg_m2 {
        rows.push((
            "rotor inertia, direction 2",
            j2,
            1,
            "/mechanics/rotor_inertia_direction2_kg_m2",
            1e6,
            "kg·mm²",
        ));
    }
    rows.push((
        "torque density (volume)",
        m.torque_density_nm_per_m3,
        1,
        "/mechanics/torque_density_Nm_per_m3",
        1e-3,
        "kN·m/m³",
    ));
    rows.push((
        "torque density (mass)",
        m.torque_density_nm_per_kg,
        3,
        "/mechanics/torque_density_Nm_per_kg",
        1.0,
        "N·m/kg",
    ));
    rows.push(("flux path: max |B|", f.max_b_t, 3, "/flux_path/max_B_T", 1.0, "T"));
    rows.push(("flux path: 90 % quantile of |B|", f.q90_b_t, 3, "/flux_path/q90_B_T", 1.0, "T"));
    rows.push(("flux path: mean |B|", f.mean_b_t, 3, "/flux_path/mean_B_T", 1.0, "T"));
    for (what, v, d, p, scale, unit) in rows {
        mech.row(vec![Cell::text(what), Cell::json(v, d, p, scale), Cell::text(unit)]);
    }
    mech
}

/// The thesis's published values beside mrbrake's.
fn thesis_section(json: &Value) -> Section {
    let mut s = Section::new("thesis", "Against the thesis");
    s.body.paragraph(
        "The embedded default is the thesis's final bidirectional brake (Karabulut 2017), \
         reconstructed from what the thesis states; the geometry it does not give is assumed \
         (see the spec's assumptions below) and was not tuned to reach these values. Differences \
         are part of the result.",
    );
    let mut t = Table::new(
        "Published values of the thesis and mrbrake's",
        &["quantity", "thesis", "mrbrake", "mrbrake / thesis", "unit", "thesis source"],
    );
    for v in &THESIS_VALUES {
        let ours = json.pointer(v.pointer).and_then(Value::as_f64).unwrap_or(f64::NAN);
        t.row(vec![
            Cell::text(v.what),
            Cell::number(v.thesis, 3),
            Cell::json(ours, 3, v.pointer, v.scale),
            Cell::number(ours * v.scale / v.thesis, 3),
            Cell::text(v.unit),
            Cell::text(v.source),
        ]);
    }
    s.body.table(&t);
    s.body.paragraph(
        "mrbrake models neither bearings, seals and bolts nor the device's full 124 mm length, so \
         its mass and inertia are lower; the prototype's measured torque was limited by air left \
         in the gaps (thesis §5.3.1).",
    );
    s
}

/// What this report does not show yet, named so that a reader does not look for it.
fn not_included(extra_ids: &[String]) -> Section {
    let mut s = Section::new("scope", "Not in this report");
    let missing: Vec<&str> = [
        ("dynamics", "the step response and Bode diagram of the brake (dynamics analysis)"),
        ("heat", "the temperature map and warm-up curve (thermal analysis)"),
    ]
    .iter()
    .filter(|(id, _)| !extra_ids.iter().any(|e| e == id))
    .map(|(_, what)| *what)
    .collect();
    if missing.is_empty() {
        s.body.paragraph("Every analysis mrbrake has for a design is included.");
    } else {
        s.body.open("ul", &[]);
        for what in missing {
            s.body.element("li", &[], &format!("{what}: not computed by this version of mrbrake."));
        }
        s.body.close();
    }
    s
}

/// The spec's header notes, every field as written with its comment, and the analysis's warnings.
fn spec_section(spec_text: &str, warnings: &[String]) -> Section {
    let n = notes(spec_text);
    let mut s = Section::new("spec", "The spec and its assumptions");
    if !n.header.is_empty() {
        s.body.element("h3", &[], "Notes of the spec file");
        s.body.element("pre", &[], &n.header.join("\n"));
    }
    let mut t = Table::new(
        "Every field as written, with the note beside it (its source or assumption)",
        &["field", "value", "note", "line"],
    );
    for l in &n.lines {
        let note = if l.comment.is_empty() { "—".to_string() } else { l.comment.clone() };
        t.row(vec![
            Cell::text(l.key.clone()),
            Cell::text(l.value.clone()),
            Cell::text(note),
            Cell::text(l.line.to_string()),
        ]);
    }
    s.body.table(&t);
    s.body.paragraph(
        "Fields the spec leaves out take their defaults: every key with its unit, allowed range, \
         default and meaning is in the spec reference (docs/reference/spec.md in the source, or \
         `mrbrake schema spec --markdown`).",
    );
    if !warnings.is_empty() {
        s.body.element("h3", &[], "Warnings of the analysis");
        s.body.open("ul", &[]);
        for w in warnings {
            s.body.element("li", &[], w);
        }
        s.body.close();
    }
    s
}

/// Every material of the geometry: which parts use it, its magnetic law and the provenance of
/// each curve; and a figure of the non-linear B–H curves and the fluid's yield stress.
fn materials_section(geometry: &BrakeGeometry) -> Result<Section, ReportError> {
    let mut names: Vec<&str> = Vec::new();
    for r in &geometry.regions {
        if !names.contains(&r.material.as_str()) {
            names.push(&r.material);
        }
    }
    let mut s = Section::new("materials", "Materials and the provenance of their curves");
    let mut t = Table::new(
        "Materials (library data; `mrbrake materials show NAME` for the curves' points)",
        &["material", "used by", "curve or value", "source", "method", "trust"],
    );
    let mut bh = Panel::new("H [A/m]", "B [T]").log_x();
    let mut tau = Panel::new("|B| [T]", "τy [kPa]");
    for name in names {
        let m =
            library::get(name).map_err(|e| ReportError::Data(format!("material {name}: {e}")))?;
        let parts: Vec<&str> = geometry
            .regions
            .iter()
            .filter(|r| r.material == name)
            .map(|r| r.name.as_str())
            .collect();
        let used = parts.join(", ");
        let mut provenance_row = |what: String, p: &mrbrake_materials::Provenance| {
            t.row(vec![
                Cell::text(name),
                Cell::text(used.clone()),
                Cell::text(what),
                Cell::text(p.source.clone()),
                Cell::text(p.method.clone()),
                Cell::text(p.trust.as_str()),
            ]);
        };
        match (&m.magnetic, m.magnetic.bh_curve()) {
            (Magnetic::Linear { mu_r }, _) => {
                provenance_row(format!("linear, μr = {mu_r}"), &m.provenance)
            }
            (_, Some(curve)) => {
                provenance_row(
                    format!("B–H curve ({} points)", curve.points().len()),
                    curve.provenance(),
                );
                let pts = log_grid(10.0, 1e6, 120).map(|h| (h, curve.b_of_h(h))).collect();
                bh = bh.series(Series::line(name, pts));
            }
            (Magnetic::NonLinear(_), None) => {
                provenance_row("non-linear (analytic law)".into(), &m.provenance)
            }
        }
        if let Some(fluid) = &m.fluid {
            let ys = fluid.yield_stress();
            provenance_row(
                format!("yield stress τy ({} points)", ys.points().len()),
                ys.provenance(),
            );
            let pts = (0..=100)
                .map(|k| 0.01 * f64::from(k))
                .map(|b| (b, fluid.tau_y_of_b(b) / 1e3))
                .collect();
            tau = tau.series(Series::line(name, pts));
        }
    }
    s.body.table(&t);
    if !bh.series.is_empty() {
        let mut fig = Figure::new("Material curves used by the analysis").panel(bh);
        if !tau.series.is_empty() {
            fig = fig.panel(tau).columns(2).size(1100, 480);
        }
        figure(
            &mut s.body,
            &inline_svg(&fig.to_svg()?, "material curves")?,
            "B–H curves of the non-linear materials (left) and the MR fluid's yield stress against |B| \
             (right), as the library evaluates them.",
        );
    }
    Ok(s)
}

/// `n` points from `lo` to `hi`, equally spaced in log.
fn log_grid(lo: f64, hi: f64, n: usize) -> impl Iterator<Item = f64> {
    let step = (hi / lo).ln() / (n - 1) as f64;
    (0..n).map(move |k| lo * (step * k as f64).exp())
}
