//! Magnetodynamics in problem files: the `[transient]` and `[harmonic]` tables, region
//! conductivities, voltage-driven coils, and their part of the report.
//!
//! ```toml
//! [[region]]
//! physical = 1
//! material = "steel-1010"              # library materials bring their sourced conductivity
//! conductivity_S_per_m = 5.0e6         # optional; overrides the library value (S/m, finite, >= 0)
//! [[region]]
//! physical = 2
//! material = "air"
//! source = { turns = 1000, current_A = 1.0 }   # the amplitude the waveform scales
//! # or: source = { turns = 450, drive = { voltage_V = 15.0, series_resistance_ohm = 7.6 } }
//! [transient]
//! t_end = 0.05                         # s
//! dt = 1e-4                            # s; or adaptive = { rtol = 1e-4, dt_initial = 1e-5 }
//! scheme = "bdf2"                      # or "euler" (implicit Euler); default "bdf2"
//! waveform = { kind = "step" }         # default; 0 at t <= 0, 1 after
//!                                      # { kind = "ramp", rise_s = 1e-3 } (0 to 1 over rise_s)
//!                                      # { kind = "sine", frequency_Hz = 50.0, offset = 0.0 }
//!                                      # { kind = "csv", file = "w.csv" } (time_s,value rows,
//!                                      #   strictly increasing time; path relative to this file)
//! vtu_times = [0.01, 0.05]             # optional: `fem solve --vtu` writes these instants
//! max_steps = 1000000                  # optional bound on the number of steps
//! [harmonic]                           # instead of [transient]
//! frequencies_Hz = [1.0, 10.0, 100.0]
//! bias = { current_A = 1.0 }           # optional: small-signal about the DC state at this current
//! # or per coil (unlisted coils at 0 A):
//! # bias = { coils = [{ physical = 2, current_A = 1.0 }, { physical = 5, current_A = -0.5 }] }
//! vtu_frequencies_Hz = [100.0]         # optional: `fem solve --vtu` writes these phasors
//!                                      # (default: every frequency)
//! ```
//!
//! Times are in seconds and frequencies in hertz whatever the file's `length_unit` (which scales
//! coordinates only). The waveform scales every coil's amplitude (`current_A`, or `voltage_V` of a
//! voltage drive in series with `series_resistance_ohm`, the circuit `v = R i + dλ/dt` solved with
//! the field). The solve starts from the DC state at `w(0)`. Harmonic solves use peak phasors and
//! the time factor `exp(+jωt)` (a quantity is `Re(x̂ e^{jωt})`); they drive coils by current and
//! are linear about `a = 0` (initial permeability) or, with `bias`, about the DC state at the bias
//! current (the small-signal response of a saturated device).
//!
//! Conductivity: an explicit `conductivity_S_per_m` wins; otherwise a library material's sourced
//! value (FEMM's 5.8 MS/m for its 1006-1020 steels, the ANSYS steel-1008 curve's 2 MS/m: the spread
//! is real); MR fluids, air and `{ mu_r }` / `{ bh_csv }` materials have none and do not conduct.
//! A coil is a stranded winding: an explicit conductivity > 0 on a coil region is refused, a
//! library material's conductivity there is not used (the report says so). A
//! `current_density_A_per_m2` source stays a constant (DC) load. The static part of the report
//! (probes, regions, coils with their inductances) is the DC state at the drives' amplitudes
//! (`current_A`, or `voltage_V / series_resistance_ohm`).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::Serialize;

use mrbrake_fem::workflow::time::{Scheme, StepKeys, TimeOptions};

use super::raw::{RawBias, RawFile, RawHarmonic, RawRegion, RawTransient, RawWaveform};
use super::{ProblemFile, SolveReport};
use crate::MagneticsError;
use crate::dynamics::harmonic::{HarmonicPoint, HarmonicPotential};
use crate::dynamics::transient::{TransientOptions, TransientResult};
use crate::dynamics::{Coil, Conductor, Drive, Dynamics, Waveform};
use crate::field::{Solution, phasor_vtu};
use crate::problem::{Problem, Source};
use crate::solver::Solver;
use mrbrake_error::FieldError;

/// The conductivity a region is solved with, and where it comes from.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConductorReport {
    /// Physical tag of the region.
    pub physical: u32,
    /// σ (S/m).
    #[serde(rename = "conductivity_S_per_m")]
    pub conductivity_s_per_m: f64,
    /// Where the value comes from (the file, a library material and its source, or none).
    pub source: String,
}

/// The dynamic solve a problem file asks for beyond the static one.
#[derive(Debug, Clone, PartialEq)]
pub enum DynamicSolve {
    /// A transient; its `snapshot_times_s` are the file's `vtu_times` (default: `t_end`).
    Transient(TransientOptions),
    /// Harmonic solves at these frequencies, about the DC state at `bias_a` if given.
    Harmonic {
        /// Frequencies (Hz).
        frequencies_hz: Vec<f64>,
        /// Bias current of each coil (A), in the order of [`DynamicsSpec::coils`].
        bias_a: Option<Vec<f64>>,
        /// The frequencies whose phasors `fem solve --vtu` writes, as indices into
        /// `frequencies_hz` (the file's `vtu_frequencies_Hz`; default every frequency).
        vtu_frequencies: Vec<usize>,
    },
}

/// The dynamic part of a problem file, read and checked.
#[derive(Debug, Clone, PartialEq)]
pub struct DynamicsSpec {
    /// Conductivity of every region.
    pub conductors: Vec<ConductorReport>,
    /// The driven coils.
    pub coils: Vec<Coil>,
    /// Transient or harmonic.
    pub analysis: DynamicSolve,
}

/// A transient in the report: the scheme and the traces (JSON keys of [`TransientResult`]).
#[derive(Debug, Clone, Serialize)]
pub struct TransientReport {
    /// Time scheme.
    pub scheme: Scheme,
    /// The traces over time.
    #[serde(flatten)]
    pub result: TransientResult,
}

/// The dynamic part of the report (flattened into the `--json` object).
#[derive(Debug, Clone, Serialize)]
pub struct DynamicsReport {
    /// Conductivity of every region and its source.
    pub conductors: Vec<ConductorReport>,
    /// Transient traces.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub transient: Option<TransientReport>,
    /// Harmonic response per frequency (peak phasors `[re, im]`, time factor `exp(+jωt)`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub harmonic: Option<Vec<HarmonicPoint>>,
    /// The DC bias of a small-signal harmonic solve (A) when every coil has the same.
    #[serde(rename = "harmonic_bias_A", skip_serializing_if = "Option::is_none")]
    pub harmonic_bias_a: Option<f64>,
    /// The DC bias of each coil (A) when they differ (a per-coil `bias.coils` table).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub harmonic_bias_coils: Vec<CoilBias>,
    /// The potentials of the harmonic solve at `vtu_frequencies_Hz` (for `--vtu`).
    #[serde(skip)]
    pub harmonic_potentials: Vec<HarmonicPotential>,
    /// Wall time of the transient or harmonic solve (s).
    pub dynamics_s: f64,
}

/// A coil's DC bias current.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CoilBias {
    /// Physical tag of the coil region.
    pub physical: u32,
    /// Bias current (A).
    #[serde(rename = "current_A")]
    pub current_a: f64,
}

/// An input error about `field` (a problem-file key such as `region[2].source.drive`).
fn input(field: impl Into<String>, message: String) -> MagneticsError {
    FieldError::new(field, message).into()
}

/// An input error about `field` of the problem file `file`.
fn input_in(file: &str, field: impl Into<String>, message: String) -> MagneticsError {
    FieldError::new(field, message).in_file(file, None).into()
}

/// An input error at a line of a waveform CSV file (`at`: the field, the file and the line).
fn input_at(at: &(&str, String, usize), message: String) -> MagneticsError {
    let (field, file, line) = at;
    FieldError::new(*field, message).in_file(file.as_str(), Some(*line)).into()
}

/// The voltage drive of a coil `source = { turns, drive = { voltage_V, series_resistance_ohm } }`.
pub(super) fn voltage_drive(value: &toml::Value, field: &str) -> Result<Drive, MagneticsError> {
    let table = value.as_table().ok_or_else(|| {
        input(
            field,
            "source.drive must be a table { voltage_V = ..., series_resistance_ohm = ... }"
                .to_string(),
        )
    })?;
    for key in table.keys() {
        if !["voltage_V", "series_resistance_ohm"].contains(&key.as_str()) {
            return Err(input(
                field,
                format!(
                    "unknown source.drive field `{key}`; allowed: voltage_V, series_resistance_ohm"
                ),
            ));
        }
    }
    let number = |key: &str| -> Result<Option<f64>, MagneticsError> {
        table
            .get(key)
            .map(|v| {
                v.as_float()
                    .or_else(|| v.as_integer().map(|i| i as f64))
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| {
                        input(field, format!("source.drive.{key} must be a finite number"))
                    })
            })
            .transpose()
    };
    let amplitude_v = number("voltage_V")?
        .ok_or_else(|| input(field, "source.drive needs `voltage_V` (V)".to_string()))?;
    let resistance = number("series_resistance_ohm")?.ok_or_else(|| {
        input(
            field,
            "a voltage drive needs `series_resistance_ohm` (Ω, > 0: the winding's \
             resistance plus the source's)"
                .to_string(),
        )
    })?;
    if !super::raw::SERIES_RESISTANCE.contains(resistance) {
        let allowed = super::raw::SERIES_RESISTANCE.describe("Ω");
        let e = FieldError::out_of_range("source.drive.series_resistance_ohm", resistance, allowed);
        return Err(e.under(field).into());
    }
    Ok(Drive::Voltage { amplitude_v, series_resistance_ohm: resistance })
}

/// The dynamic part of a problem file (`None` for a static file).
pub(super) fn spec_of(
    raw: &RawFile,
    problem: &Problem,
    dir: &Path,
    file: &str,
) -> Result<Option<DynamicsSpec>, MagneticsError> {
    let (analysis, waveform) = match (&raw.transient, &raw.harmonic) {
        (Some(_), Some(_)) => {
            return Err(input_in(
                file,
                "transient",
                "[transient] and [harmonic] cannot be solved together; give one of them"
                    .to_string(),
            ));
        }
        (Some(t), None) => (
            DynamicSolve::Transient(transient_of(t, file)?),
            waveform_of(t.waveform.as_ref(), dir, file)?,
        ),
        // The waveform of a harmonic solve is the phasor's `exp(+jωt)`; the coils' is unused.
        (None, Some(h)) => (
            harmonic_of(h, &coil_tags(&raw.region, problem), file)?,
            Waveform::Step { initial: 0.0 },
        ),
        (None, None) => {
            if let Some(k) = raw.region.iter().position(has_drive) {
                return Err(input_in(
                    file,
                    format!("region[{k}].source.drive"),
                    format!(
                        "region[{k}] (physical = {}): a voltage drive (source.drive) needs a \
                     [transient] table; a static solve takes current_A",
                        raw.region[k].physical
                    ),
                ));
            }
            // A static solve does not use conductivities; a bad one is still refused.
            for (k, r) in raw.region.iter().enumerate() {
                if let Some(s) = r.conductivity
                    && !super::raw::CONDUCTIVITY.contains(s)
                {
                    let e = FieldError::new(
                        format!("region[{k}].conductivity_S_per_m"),
                        format!("region physical = {}", r.physical),
                    );
                    let e = e.with_value(s).with_allowed("finite, >= 0 S/m");
                    return Err(e.in_file(file, None).into());
                }
            }
            return Ok(None);
        }
    };
    let conductors = conductors_of(&raw.region, problem, file)?;
    let coils = coils_of(&raw.region, problem, &waveform, file)?;
    Ok(Some(DynamicsSpec { conductors, coils, analysis }))
}

fn has_drive(region: &RawRegion) -> bool {
    region.source.as_ref().and_then(|s| s.as_table()).is_some_and(|t| t.contains_key("drive"))
}

/// The conductivity of every region: the file's value, else the library material's, else 0.
fn conductors_of(
    raw: &[RawRegion],
    problem: &Problem,
    file: &str,
) -> Result<Vec<ConductorReport>, MagneticsError> {
    let mut out = Vec::with_capacity(raw.len());
    for (k, r) in raw.iter().enumerate() {
        let field = format!("region[{k}]");
        let located = |e| super::located(e, file, r.physical);
        let coil = is_coil(problem, r.physical);
        let (sigma, source) = match r.conductivity {
            Some(s) if !super::raw::CONDUCTIVITY.contains(s) => {
                let e = FieldError::out_of_range("conductivity_S_per_m", s, "finite, >= 0 S/m");
                return Err(located(e.under(&field).into()));
            }
            Some(s) if s > 0.0 && coil => {
                let e = FieldError::new(
                    "conductivity_S_per_m",
                    "a coil region is a stranded winding (no eddy currents); it cannot conduct \
                     (remove the key or set 0)",
                );
                return Err(located(e.with_value(s).with_allowed("0").under(&field).into()));
            }
            Some(s) => (s, "given in the problem file".to_string()),
            None => library_conductivity(r.material.as_ref(), coil)?,
        };
        out.push(ConductorReport { physical: r.physical, conductivity_s_per_m: sigma, source });
    }
    Ok(out)
}

/// A library material's sourced conductivity (0 for other materials, and in a coil region).
fn library_conductivity(
    material: Option<&toml::Value>,
    is_coil: bool,
) -> Result<(f64, String), MagneticsError> {
    let Some(name) = material.and_then(|m| m.as_str()) else {
        return Ok((0.0, "none given: not conducting".to_string()));
    };
    let material = mrbrake_materials::library::get(name)?;
    Ok(match (&material.conductivity_s_per_m, is_coil) {
        (Some(s), true) if s.value > 0.0 => (
            0.0,
            format!("stranded coil: the {:.3e} S/m of library \"{name}\" is not used", s.value),
        ),
        (Some(s), _) => (
            s.value,
            format!(
                "library \"{name}\": {} ({}; trust {})",
                s.provenance.source, s.provenance.method, s.provenance.trust
            ),
        ),
        (None, _) => (0.0, format!("library \"{name}\" gives none: not conducting")),
    })
}

/// Every coil region's drive, scaled by `waveform`.
fn coils_of(
    raw: &[RawRegion],
    problem: &Problem,
    waveform: &Waveform,
    file: &str,
) -> Result<Vec<Coil>, MagneticsError> {
    let mut coils = Vec::new();
    for (k, r) in raw.iter().enumerate() {
        let Some(Source::Coil { turns, current_a }) =
            problem.region(r.physical).and_then(|x| x.source)
        else {
            continue;
        };
        let field = format!("region[{k}]");
        let drive = match r.source.as_ref().and_then(|s| s.get("drive")) {
            Some(value) => {
                voltage_drive(value, &field).map_err(|e| super::located(e, file, r.physical))?
            }
            None => Drive::Current { amplitude_a: current_a },
        };
        coils.push(Coil { tag: r.physical, turns, drive, waveform: waveform.clone() });
    }
    if coils.is_empty() {
        return Err(input_in(
            file,
            "region",
            "a [transient] or [harmonic] solve needs a coil: a region with source = \
             { turns, current_A } or { turns, drive = { voltage_V, series_resistance_ohm } }"
                .to_string(),
        ));
    }
    Ok(coils)
}

/// The `[transient]` table as solver options (the waveform goes to the coils separately).
fn transient_of(raw: &RawTransient, file: &str) -> Result<TransientOptions, MagneticsError> {
    let keys = StepKeys {
        t_end: raw.t_end,
        dt: raw.dt,
        adaptive: raw.adaptive,
        scheme: raw.scheme.as_deref(),
        max_steps: raw.max_steps,
    };
    // Every bad step key at once, as the heat reader reports them.
    let time = TimeOptions::from_keys(&keys).map_err(|errors| {
        let mut all = mrbrake_error::FieldErrors::new();
        for e in errors {
            all.push(e.under("transient").in_file(file, None));
        }
        MagneticsError::from(all)
    })?;
    Ok(TransientOptions {
        time,
        probes: Vec::new(),
        energy: true,
        snapshot_times_s: vtu_times_of(raw.vtu_times.as_deref(), raw.t_end, file)?,
        force_regions: Vec::new(),
    })
}

/// `vtu_times` (default: the final state), checked to lie in `[0, t_end]` and increase.
fn vtu_times_of(times: Option<&[f64]>, t_end: f64, file: &str) -> Result<Vec<f64>, MagneticsError> {
    let Some(times) = times else { return Ok(vec![t_end]) };
    if times.is_empty() {
        return Err(input_in(file, "transient.vtu_times", "empty (omit it for t_end)".into()));
    }
    for (k, &t) in times.iter().enumerate() {
        if !(0.0..=t_end).contains(&t) || (k > 0 && t <= times[k - 1]) {
            let e = FieldError::new(format!("transient.vtu_times[{k}]"), "times increase strictly")
                .with_value(format!("{t} s"))
                .with_allowed(format!("[0, t_end = {t_end} s], after the time before it"));
            return Err(e.in_file(file, None).into());
        }
    }
    Ok(times.to_vec())
}

/// The `waveform` of `[transient]` (default: a step from 0).
fn waveform_of(
    raw: Option<&RawWaveform>,
    dir: &Path,
    file: &str,
) -> Result<Waveform, MagneticsError> {
    let Some(w) = raw else { return Ok(Waveform::Step { initial: 0.0 }) };
    let field = "transient.waveform";
    let allowed: &[&str] = match w.kind.as_str() {
        "step" => &[],
        "ramp" => &["rise_s"],
        "sine" => &["frequency_Hz", "offset"],
        "csv" => &["file"],
        other => {
            let allowed =
                "\"step\", \"ramp\" (rise_s), \"sine\" (frequency_Hz, offset), \"csv\" (file)";
            let e = FieldError::out_of_range("kind", format!("\"{other}\""), allowed);
            return Err(e.under(field).in_file(file, None).into());
        }
    };
    let given = [
        ("rise_s", w.rise_s.is_some()),
        ("frequency_Hz", w.frequency_hz.is_some()),
        ("offset", w.offset.is_some()),
        ("file", w.file.is_some()),
    ];
    if let Some((key, _)) = given.iter().find(|(key, set)| *set && !allowed.contains(key)) {
        return Err(input_in(
            file,
            field,
            format!(
                "`{key}` is not a parameter of kind = \"{}\" (its parameters: {allowed:?})",
                w.kind
            ),
        ));
    }
    let missing = |key: &str| input_in(file, field, format!("kind = \"{}\" needs `{key}`", w.kind));
    let waveform = match w.kind.as_str() {
        "step" => Waveform::Step { initial: 0.0 },
        "ramp" => {
            let rise_s = w.rise_s.ok_or_else(|| missing("rise_s"))?;
            if !super::raw::RISE.contains(rise_s) {
                let allowed = super::raw::RISE.describe("s");
                let e = FieldError::out_of_range("waveform.rise_s", rise_s, allowed);
                return Err(e.under("transient").in_file(file, None).into());
            }
            Waveform::Ramp { rise_s }
        }
        "sine" => Waveform::Sine {
            frequency_hz: w.frequency_hz.ok_or_else(|| missing("frequency_Hz"))?,
            offset: w.offset.unwrap_or(0.0),
        },
        _ => {
            let name = w.file.as_deref().ok_or_else(|| missing("file"))?;
            // The CSV's errors are located in the CSV; its problem file is said in the message.
            let points = read_waveform_csv(&dir.join(name), field, name).map_err(|e| match e {
                MagneticsError::Input(mut e) => {
                    e.message = format!("{} (the waveform file of {file})", e.message);
                    MagneticsError::Input(e)
                }
                other => other,
            })?;
            Waveform::Table { points }
        }
    };
    waveform.validate().map_err(|e| match e {
        MagneticsError::Input(e) => MagneticsError::from(e.under(field).in_file(file, None)),
        other => other,
    })?;
    Ok(waveform)
}

/// `time_s,value` rows (an optional header line, `#` comments), time strictly increasing.
fn read_waveform_csv(
    path: &Path,
    field: &str,
    name: &str,
) -> Result<Vec<(f64, f64)>, MagneticsError> {
    let text = mrbrake_error::read::text(path, mrbrake_error::read::MODEL).map_err(|e| {
        input(field, format!("file = \"{name}\": cannot read {}: {e}", path.display()))
    })?;
    let mut points: Vec<(f64, f64)> = Vec::new();
    for (line_no, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let cells: Vec<&str> = line.split(',').map(str::trim).collect();
        let parsed = match cells.as_slice() {
            [t, v] => t.parse::<f64>().ok().zip(v.parse::<f64>().ok()),
            _ => None,
        };
        let at = (field, path.display().to_string(), line_no + 1);
        match parsed {
            None if points.is_empty() && line_no == 0 => continue, // the header
            None => {
                return Err(input_at(
                    &at,
                    format!("expected `time_s,value` numbers, got `{line}`"),
                ));
            }
            Some((t, v)) => {
                if let Some(&(previous, _)) = points.last()
                    && t <= previous
                {
                    return Err(input_at(
                        &at,
                        format!(
                            "time_s must increase strictly (t = {t} s follows t = {previous} s)"
                        ),
                    ));
                }
                points.push((t, v));
            }
        }
    }
    if points.is_empty() {
        return Err(input(field, format!("{} has no `time_s,value` rows", path.display())));
    }
    Ok(points)
}

/// The physical tags of the driven coils, in the order [`coils_of`] builds them.
fn coil_tags(raw: &[RawRegion], problem: &Problem) -> Vec<u32> {
    raw.iter().filter(|r| is_coil(problem, r.physical)).map(|r| r.physical).collect()
}

/// True for a region with a coil (turns) source: a stranded winding.
fn is_coil(problem: &Problem, physical: u32) -> bool {
    matches!(problem.region(physical).and_then(|x| x.source), Some(Source::Coil { .. }))
}

fn harmonic_of(
    raw: &RawHarmonic,
    coils: &[u32],
    file: &str,
) -> Result<DynamicSolve, MagneticsError> {
    if raw.frequencies_hz.is_empty() {
        return Err(input_in(file, "harmonic.frequencies_Hz", "is empty".into()));
    }
    if let Some(f) = raw.frequencies_hz.iter().find(|f| !super::raw::FREQUENCY.contains(**f)) {
        let e = FieldError::out_of_range(
            "harmonic.frequencies_Hz",
            format!("{f} Hz"),
            "finite, >= 0 Hz",
        );
        return Err(e.in_file(file, None).into());
    }
    if raw.frequencies_hz.len() > MAX_FREQUENCIES {
        let count = format!("{} frequencies", raw.frequencies_hz.len());
        let e = FieldError::out_of_range(
            "harmonic.frequencies_Hz",
            count,
            format!("<= {MAX_FREQUENCIES}"),
        );
        return Err(e.in_file(file, None).into());
    }
    let bias_a = raw.bias.as_ref().map(|b| bias_of(b, coils, file)).transpose()?;
    let vtu_frequencies = match &raw.vtu_frequencies_hz {
        None => (0..raw.frequencies_hz.len()).collect(),
        Some(chosen) if chosen.is_empty() => {
            return Err(input_in(
                file,
                "harmonic.vtu_frequencies_Hz",
                "is empty (omit it for every frequency)".to_string(),
            ));
        }
        Some(chosen) => {
            let index_of = |(k, f): (usize, &f64)| {
                raw.frequencies_hz
                    .iter()
                    .position(|g| (g - f).abs() <= 1e-12 * g.abs().max(1.0))
                    .ok_or_else(|| {
                        input_in(
                            file,
                            format!("harmonic.vtu_frequencies_Hz[{k}]"),
                            format!("{f} Hz is not one of frequencies_Hz"),
                        )
                    })
            };
            chosen.iter().enumerate().map(index_of).collect::<Result<Vec<_>, _>>()?
        }
    };
    Ok(DynamicSolve::Harmonic {
        frequencies_hz: raw.frequencies_hz.clone(),
        bias_a,
        vtu_frequencies,
    })
}

/// The most frequencies one `[harmonic]` table may list (every one's potential is kept while the
/// sweep runs: a bound on memory for hostile files).
pub const MAX_FREQUENCIES: usize = 10_000;

/// The bias current of each coil: `current_A` for every coil, or the `coils` table (unlisted
/// coils at 0 A).
fn bias_of(raw: &RawBias, coils: &[u32], file: &str) -> Result<Vec<f64>, MagneticsError> {
    let finite = |b: f64, field: String| {
        if b.is_finite() {
            Ok(b)
        } else {
            Err(MagneticsError::from(
                FieldError::out_of_range(field, b, "finite").in_file(file, None),
            ))
        }
    };
    match (raw.current_a, &raw.coils) {
        (Some(b), None) => Ok(vec![finite(b, "harmonic.bias.current_A".into())?; coils.len()]),
        (None, Some(list)) => {
            let mut bias = vec![0.0; coils.len()];
            for (k, entry) in list.iter().enumerate() {
                let field = format!("harmonic.bias.coils[{k}]");
                let index = coils.iter().position(|&t| t == entry.physical).ok_or_else(|| {
                    input_in(
                        file,
                        format!("{field}.physical"),
                        format!(
                            "{field}.physical = {}: not a coil region (coils: {coils:?})",
                            entry.physical
                        ),
                    )
                })?;
                if list[..k].iter().any(|e| e.physical == entry.physical) {
                    return Err(input_in(
                        file,
                        format!("{field}.physical"),
                        format!("{field}.physical = {}: listed twice", entry.physical),
                    ));
                }
                bias[index] = finite(entry.current_a, format!("{field}.current_A"))?;
            }
            Ok(bias)
        }
        _ => Err(input_in(
            file,
            "harmonic.bias",
            "harmonic.bias takes either current_A (every coil) or coils = [{ physical, \
             current_A }, ...], not both or neither"
                .to_string(),
        )),
    }
}

/// An input error of the library gets the problem file's name in front.
fn named(error: MagneticsError, file: &str) -> MagneticsError {
    use mrbrake_fem::workflow::time::TimeError;
    match error {
        MagneticsError::Input(e) => MagneticsError::from(e.in_file(file, None)),
        // The options' keys are the `[transient]` table's (the first invalid one is named).
        MagneticsError::Time(TimeError::Options(errors)) if !errors.is_empty() => {
            let first = errors.errors()[0].clone().under("transient");
            MagneticsError::from(first.in_file(file, None))
        }
        other => other,
    }
}

/// Runs the transient or harmonic solve of `problem_file` (its problem, options and probes).
pub(super) fn run(
    spec: &DynamicsSpec,
    problem_file: &ProblemFile,
    path: &Path,
) -> Result<DynamicsReport, MagneticsError> {
    let file = path.display().to_string();
    let start = Instant::now();
    let solver = Solver::new(problem_file.problem.clone(), problem_file.options)?;
    let conductors: Vec<Conductor> = spec
        .conductors
        .iter()
        .map(|c| Conductor { tag: c.physical, conductivity_s_per_m: c.conductivity_s_per_m })
        .collect();
    let mut dynamics =
        Dynamics::new(solver, &conductors, spec.coils.clone()).map_err(|e| named(e, &file))?;
    let probes = problem_file.probes.clone();
    let mut report = DynamicsReport {
        conductors: spec.conductors.clone(),
        transient: None,
        harmonic: None,
        harmonic_bias_a: None,
        harmonic_bias_coils: Vec::new(),
        harmonic_potentials: Vec::new(),
        dynamics_s: 0.0,
    };
    match &spec.analysis {
        DynamicSolve::Transient(options) => {
            let force_regions = dynamics.solver().mesh().region_tags();
            let options = TransientOptions { probes, force_regions, ..options.clone() };
            let result = dynamics.transient(&options).map_err(|e| named(e, &file))?;
            report.transient = Some(TransientReport { scheme: options.time.scheme, result });
        }
        DynamicSolve::Harmonic { frequencies_hz, bias_a, vtu_frequencies } => {
            let potentials = dynamics
                .harmonic_potentials(frequencies_hz, bias_a.as_deref())
                .map_err(|e| named(e, &file))?;
            let points = potentials
                .iter()
                .map(|p| dynamics.harmonic_point(p, &probes))
                .collect::<Result<Vec<_>, _>>()
                .map_err(|e| named(e, &file))?;
            report.harmonic = Some(points);
            let mut keep = vec![false; potentials.len()];
            vtu_frequencies.iter().for_each(|&k| keep[k] = true);
            report.harmonic_potentials =
                potentials.into_iter().zip(keep).filter_map(|(p, k)| k.then_some(p)).collect();
            if let Some(bias) = bias_a {
                match bias.split_first() {
                    Some((first, rest)) if rest.iter().all(|b| b.to_bits() == first.to_bits()) => {
                        report.harmonic_bias_a = Some(*first);
                    }
                    _ => {
                        report.harmonic_bias_coils = spec
                            .coils
                            .iter()
                            .zip(bias)
                            .map(|(c, &b)| CoilBias { physical: c.tag, current_a: b })
                            .collect();
                    }
                }
            }
        }
    }
    report.dynamics_s = start.elapsed().as_secs_f64();
    Ok(report)
}

/// The `.vtu` files `fem solve --vtu PATH` writes, with their contents: the static field at
/// `PATH`; for a transient the kept instants (`vtu_times`, default the final state); for a
/// harmonic solve the phasors at `vtu_frequencies_Hz` (default every frequency; real and
/// imaginary parts, [`crate::field::phasor_vtu`]). One file goes to `PATH`, several to
/// `STEM_000.vtu`, `STEM_001.vtu`, … beside `PATH` with a ParaView collection `STEM.pvd` giving
/// their times (s) or frequencies (Hz) as its time steps.
pub fn vtu_files(
    report: &SolveReport,
    solver: &Solver,
    solution: &Solution,
    path: &Path,
) -> Vec<(PathBuf, String)> {
    let state = |a: &[f64]| {
        let s = Solution::from_potential(a.to_vec(), solver.basis().dofs().n_vertices());
        solver.field_snapshot(&s)
    };
    let dynamics = report.dynamics.as_ref();
    let files: Vec<(f64, String)> = match (
        dynamics.and_then(|d| d.transient.as_ref()),
        dynamics.filter(|d| d.harmonic.is_some()),
    ) {
        (Some(t), _) => {
            t.result.snapshots.iter().map(|(t, a)| (*t, state(a).to_vtu(solver.mesh()))).collect()
        }
        (None, Some(d)) => d
            .harmonic_potentials
            .iter()
            .map(|p| {
                let vtu = phasor_vtu(&state(&p.re), &state(&p.im), solver.mesh());
                (p.frequency_hz, vtu)
            })
            .collect(),
        (None, None) => {
            return vec![(
                path.to_path_buf(),
                solver.field_snapshot(solution).to_vtu(solver.mesh()),
            )];
        }
    };
    if files.len() == 1 {
        return files.into_iter().map(|(_, text)| (path.to_path_buf(), text)).collect();
    }
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let mut out = Vec::with_capacity(files.len() + 1);
    let mut pvd = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n",
    );
    for (k, (step, text)) in files.into_iter().enumerate() {
        let name = format!("{stem}_{k:03}.vtu");
        let _ = writeln!(pvd, "<DataSet timestep=\"{step:e}\" file=\"{name}\"/>");
        out.push((path.with_file_name(&name), text));
    }
    pvd.push_str("</Collection>\n</VTKFile>\n");
    out.push((path.with_file_name(format!("{stem}.pvd")), pvd));
    out
}
