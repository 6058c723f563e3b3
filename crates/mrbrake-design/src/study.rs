//! Design studies. [`thesis_tables`] re-runs the thesis's configuration comparisons (Tables 4.1–4.4:
//! disc thickness, gap width, coil location, drum vs single vs multi-disc) on mrbrake's own
//! geometries with its own field solver, and sets each row beside the thesis's printed values.
//!
//! The thesis does not give the full geometry of these comparison models (4.2.1), only the varied
//! parameter, the current (2 A for Tables 4.1–4.3, 1 A for Table 4.4) and, for Tables 4.3 and 4.4, the
//! disc radii R1/R2. Every row here starts from one documented base design
//! (`examples/specs/study-single-disc.toml`, embedded) and changes only what the thesis varies, so the
//! trends are comparable while the absolute values depend on the base (coil window, case, steel).
//! The drum of Table 4.4 uses R0 = 25 mm and h = 9 mm, the sizes that reproduce its printed torque
//! through (3.9) (see `tests/it/thesis_tables.rs`).

use serde::Serialize;

use crate::DesignError;
use crate::analysis::{AnalysisOptions, AnalysisRequest};
use crate::spec::{BrakeSpec, CoilPlacement, Configuration, Current, Disc, Drum, Length};

/// The base design of the thesis-table study (single disc, outer coil).
pub const STUDY_BASE_TOML: &str = include_str!("../../../examples/specs/study-single-disc.toml");

/// One row of a study table: ours beside the thesis's.
#[derive(Debug, Clone, Serialize)]
pub struct StudyRow {
    /// What this row is (e.g. `d = 1.5 mm`).
    pub label: String,
    /// Mean |B| over the fluid gaps, ours (T).
    #[serde(rename = "mean_B_T")]
    pub mean_b_t: f64,
    /// τ_y at that mean |B|, ours (kPa).
    #[serde(rename = "tau_y_kPa")]
    pub tau_y_kpa: f64,
    /// Torque by the thesis's method (mean B → τ_y → formula), ours (N·m).
    #[serde(rename = "thesis_method_Nm")]
    pub thesis_method_nm: f64,
    /// Torque from the local |B| along the gaps, ours (N·m).
    #[serde(rename = "local_Nm")]
    pub local_nm: f64,
    /// The thesis's printed B (T).
    #[serde(rename = "thesis_B_T")]
    pub thesis_b_t: f64,
    /// The thesis's printed τ_y (kPa).
    #[serde(rename = "thesis_tau_y_kPa")]
    pub thesis_tau_y_kpa: f64,
    /// The thesis's printed torque (N·m).
    #[serde(rename = "thesis_torque_Nm")]
    pub thesis_torque_nm: f64,
}

/// One study table.
#[derive(Debug, Clone, Serialize)]
pub struct StudyTable {
    /// Which thesis table (e.g. `Table 4.1`).
    pub table: &'static str,
    /// What it compares.
    pub title: &'static str,
    /// Current used (A).
    #[serde(rename = "current_A")]
    pub current_a: f64,
    /// The rows.
    pub rows: Vec<StudyRow>,
}

/// The base design of the study.
pub fn study_base() -> Result<BrakeSpec, DesignError> {
    BrakeSpec::from_toml_str(STUDY_BASE_TOML, "study-single-disc.toml (embedded)")
}

fn mm(v: f64) -> Length {
    Length(v * 1e-3)
}

fn run_row(
    spec: &BrakeSpec,
    options: &AnalysisOptions,
    label: String,
    thesis: (f64, f64, f64),
) -> Result<StudyRow, DesignError> {
    let a = match AnalysisRequest::of(spec).options(*options).run() {
        Ok(a) => a,
        Err(e) => return Err(DesignError::StudyRow { label, source: Box::new(e) }),
    };
    let last = a.torque_current_curve.last().expect("at least two points");
    // τ_y at the mean B of all direction-1 gaps, as the thesis method uses it.
    let material = mrbrake_materials::library::fluid(&spec.materials.fluid)?;
    let tau_y_kpa = material.tau_y_of_b(last.mean_b_t) / 1e3;
    Ok(StudyRow {
        label,
        mean_b_t: last.mean_b_t,
        tau_y_kpa,
        thesis_method_nm: last.thesis_formula_nm,
        local_nm: last.yield_torque_nm,
        thesis_b_t: thesis.0,
        thesis_tau_y_kpa: thesis.1,
        thesis_torque_nm: thesis.2,
    })
}

/// The base at `amps`, with its disc changed by `edit` (the base is a single-disc brake).
fn disc_variant(base: &BrakeSpec, amps: f64, edit: impl FnOnce(&mut Disc)) -> BrakeSpec {
    let mut spec = base.clone();
    spec.coil.max_current = Current(amps);
    edit(spec.configuration.disc_mut().expect("the study base is a disc brake"));
    spec
}

/// Re-runs Tables 4.1–4.4 of the thesis on mrbrake's geometries (see the module docs).
pub fn thesis_tables(options: &AnalysisOptions) -> Result<Vec<StudyTable>, DesignError> {
    let base = study_base()?;
    let options = AnalysisOptions { points: 2, speed_rad_s: 0.0, ..*options };
    Ok(vec![
        table_4_1(&base, &options)?,
        table_4_2(&base, &options)?,
        table_4_3(&base, &options)?,
        table_4_4(&base, &options)?,
    ])
}

/// Table 4.1: disc thickness at 2 A, single disc.
fn table_4_1(base: &BrakeSpec, options: &AnalysisOptions) -> Result<StudyTable, DesignError> {
    let mut rows = Vec::new();
    for (d, thesis) in [
        (1.0, (0.0565, 1.4773, 0.09)),
        (1.5, (0.0590, 1.6166, 0.09)),
        (2.0, (0.0604, 1.6924, 0.10)),
    ] {
        let s = disc_variant(base, 2.0, |disc| disc.thickness = mm(d));
        rows.push(run_row(&s, options, format!("d = {d} mm"), thesis)?);
    }
    Ok(StudyTable {
        table: "Table 4.1",
        title: "disc thickness (single disc, 2 A)",
        current_a: 2.0,
        rows,
    })
}

/// Table 4.2: gap width at 2 A.
fn table_4_2(base: &BrakeSpec, options: &AnalysisOptions) -> Result<StudyTable, DesignError> {
    let mut rows = Vec::new();
    for (g, thesis) in [
        (1.0, (0.0604, 1.6924, 0.10)),
        (0.75, (0.0749, 2.2559, 0.13)),
        (0.5, (0.0866, 2.6457, 0.15)),
    ] {
        let s = disc_variant(base, 2.0, |disc| disc.gap = mm(g));
        rows.push(run_row(&s, options, format!("g = {g} mm"), thesis)?);
    }
    Ok(StudyTable {
        table: "Table 4.2",
        title: "fluid gap width (single disc, 2 A)",
        current_a: 2.0,
        rows,
    })
}

/// Table 4.3: coil location, radii as printed.
fn table_4_3(base: &BrakeSpec, options: &AnalysisOptions) -> Result<StudyTable, DesignError> {
    let mut rows = Vec::new();
    for (placement, name, r1, r2, thesis) in [
        (CoilPlacement::Inner, "inner", 10.0, 30.0, (0.0156, 0.4394, 0.05)),
        (CoilPlacement::Outer, "outer", 4.0, 24.0, (0.0604, 1.6924, 0.10)),
        (CoilPlacement::TwoSided, "two sided", 10.0, 24.0, (0.0646, 1.8924, 0.10)),
    ] {
        let mut s = disc_variant(base, 2.0, |disc| {
            disc.inner_radius = mm(r1);
            disc.outer_radius = mm(r2);
        });
        s.coil.placement = placement;
        rows.push(run_row(&s, options, format!("{name} (R1 {r1} mm, R2 {r2} mm)"), thesis)?);
    }
    Ok(StudyTable {
        table: "Table 4.3",
        title: "coil location (single disc, 2 A)",
        current_a: 2.0,
        rows,
    })
}

/// Table 4.4: configurations at 1 A, discs R1 = 4 mm, R2 = 24 mm.
fn table_4_4(base: &BrakeSpec, options: &AnalysisOptions) -> Result<StudyTable, DesignError> {
    let mut rows = Vec::new();
    let mut drum = base.clone();
    drum.coil.max_current = Current(1.0);
    drum.configuration = Configuration::Drum(Drum {
        r0: mm(25.0),
        height: mm(9.0),
        cylinder_thickness: mm(1.0),
        gap: mm(0.5),
        rotating_cylinders: 1,
    });
    rows.push(run_row(&drum, options, "drum (R 25 mm, h 9 mm)".into(), (0.1100, 3.5517, 0.25))?);
    for (n, thesis) in [
        (1, (0.1475, 5.3654, 0.31)),
        (3, (0.1535, 5.5918, 0.97)),
        (5, (0.1692, 6.3388, 1.83)),
        (7, (0.1679, 6.2785, 2.53)),
    ] {
        let mut s = disc_variant(base, 1.0, |disc| {
            disc.inner_radius = mm(4.0);
            disc.outer_radius = mm(24.0);
            disc.count = n;
        });
        if n > 1 {
            let disc = s.configuration.disc().expect("the study base is a disc brake").clone();
            s.configuration = Configuration::MultiDisc(disc);
        }
        let label = if n == 1 { "single disc".to_string() } else { format!("multi {n} disc") };
        rows.push(run_row(&s, options, label, thesis)?);
    }
    Ok(StudyTable {
        table: "Table 4.4",
        title: "configurations (1 A, R1 4 mm, R2 24 mm)",
        current_a: 1.0,
        rows,
    })
}
