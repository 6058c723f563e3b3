//! Hysteresis parameter sets for the library's low-carbon steels, with provenance.
//!
//! # What was found, what is assumed
//! No published major loop, coercivity or remanence of AISI 1008, 1010 or 1018 could be found in the
//! stored corpora searched for this work (code, documentation, pages and issues; queries listed in
//! `data/SOURCES.md`, section "Hysteresis"). A set is therefore built from two inputs:
//! * the library's B–H curve of the steel, taken as the model's **normal magnetisation curve** (the
//!   first-magnetisation curve from the demagnetised state, which in this model is also the locus of
//!   the tips of symmetric loops). It keeps the curve's own source and trust;
//! * a **coercivity** `H_c` of the major loop (tip at [`TIP_FIELD_A_PER_M`]). The default is the
//!   *curve-consistent* coercivity ([`curve_consistent_coercivity`]): the value for which the model,
//!   fitted to the library curve as its normal curve, reproduces that curve best. In this model a cell
//!   with pinning field `κ` adds nothing to the normal curve below `H = κ`, so the knee of the normal
//!   curve bounds where the pinning fields, and with them `H_c`, can lie: a steep curve (FEMM 1006,
//!   Ansys 1008) is only reproduced with a small `H_c`, a soft one (FEMM 1018) with a larger one. It is
//!   a model-based estimate from sourced data, trust **low**, not a measurement.
//!   [`steel_with_coercivity`] builds the set for any other value (a datasheet value, a spread study),
//!   and [`super::identify`] fits a measured loop.
//!
//! The fit ([`super::identify::fit`]) puts the normal curve (points up to [`FIT_FIELD_A_PER_M`]) and
//! the coercivity point in one non-negative least-squares problem; the coercivity point carries the
//! weight of all curve points together, so it is met closely. The remanence then follows from the
//! model; it is reported, not imposed.

use std::sync::{Arc, OnceLock};

use super::identify::{IdentifyOptions, Observation, PathStart, fit};
use super::{HysteresisParams, loop_measures, major_loop};
use crate::{MaterialError, MaterialKind, Provenance, Sourced, Trust};

/// Tip field of the major loop on which the coercivity is defined, A/m.
pub const TIP_FIELD_A_PER_M: f64 = 20_000.0;

/// Largest field of the library curve points used in the fit, A/m.
pub const FIT_FIELD_A_PER_M: f64 = 320_000.0;

/// The pinning fields of the fit as multiples of the coercivity: a reversible cell, then cells
/// around `H_c`, where the descending branch crosses zero.
const PINNING_GRID: [f64; 8] = [0.0, 0.5, 0.75, 1.0, 1.25, 1.5, 2.0, 3.0];

/// A steel's hysteresis parameter set with where it comes from.
#[derive(Debug, Clone, PartialEq)]
pub struct SteelHysteresis {
    /// Library name of the steel (`steel-1008`, …).
    pub name: String,
    /// The parameter set.
    pub params: Arc<HysteresisParams>,
    /// Source, method and trust of the set as a whole (the lower of its inputs' trusts).
    pub provenance: Provenance,
    /// The coercivity the set was fitted to, A/m, with its source.
    pub coercivity_a_per_m: Sourced<f64>,
    /// Remanence of the fitted major loop (tip [`TIP_FIELD_A_PER_M`]), T: a result, not an input.
    pub remanence_t: f64,
    /// Coercivity of the fitted major loop, A/m (close to the input).
    pub fitted_coercivity_a_per_m: f64,
    /// RMS deviation of the model's normal curve from the library curve points, T.
    pub normal_curve_rms_t: f64,
    /// Warnings of the fit.
    pub warnings: Vec<String>,
}

/// The default set of library steel `name` (coercivity from [`curve_consistent_coercivity`]), built
/// on its first use.
pub fn steel(name: &str) -> Result<Arc<SteelHysteresis>, MaterialError> {
    type Slot = OnceLock<Result<Arc<SteelHysteresis>, MaterialError>>;
    static SETS: OnceLock<Result<Vec<(String, Slot)>, MaterialError>> = OnceLock::new();
    let sets = SETS
        .get_or_init(|| Ok(steel_names()?.into_iter().map(|n| (n, OnceLock::new())).collect()))
        .as_ref()
        .map_err(Clone::clone)?;
    let wanted = name.trim().to_ascii_lowercase();
    let (steel, slot) = sets.iter().find(|s| s.0 == wanted).ok_or_else(|| no_model(name))?;
    // Each steel is fitted on its first use only (a coercivity search of about 40 small fits).
    slot.get_or_init(|| {
        curve_consistent_coercivity(steel)
            .and_then(|hc| steel_with_coercivity(steel, hc))
            .map(Arc::new)
            .map_err(MaterialError::builtin)
    })
    .clone()
}

/// The hysteresis law of library material `name`, for an FEA region: the steel's default set, an
/// error naming the material for a material without a model (air, aluminium, a fluid) and the
/// library's error for an unknown name.
pub fn for_material(name: &str) -> Result<Arc<SteelHysteresis>, MaterialError> {
    crate::library::get(name)?;
    steel(name)
}

/// The error for a material without a hysteresis model.
fn no_model(name: &str) -> MaterialError {
    MaterialError::NoHysteresisModel {
        name: name.to_string(),
        known: steel_names().unwrap_or_default(),
    }
}

/// The library's steels (every material of kind steel has a set).
pub fn steel_names() -> Result<Vec<String>, MaterialError> {
    Ok(crate::library::all()?
        .iter()
        .filter(|m| m.kind == MaterialKind::Steel)
        .map(|m| m.name.clone())
        .collect())
}

/// Searched range of the curve-consistent coercivity, A/m.
pub const COERCIVITY_SEARCH_A_PER_M: (f64, f64) = (25.0, 1000.0);

/// The coercivity for which the model best reproduces the library curve of steel `name` as its normal
/// curve (see the module docs), with its provenance (trust low: a model-based estimate).
pub fn curve_consistent_coercivity(name: &str) -> Result<Sourced<f64>, MaterialError> {
    let user = |hc: f64| Sourced::new(hc, Provenance::new("search", "search", Trust::User));
    let rms = |hc: f64| steel_with_coercivity(name, user(hc)).map(|s| s.normal_curve_rms_t);
    // A log grid of 25 points, then golden-section refinement around the best one.
    let (low, high) = COERCIVITY_SEARCH_A_PER_M;
    let grid: Vec<f64> = (0..25).map(|i| low * (high / low).powf(i as f64 / 24.0)).collect();
    let mut best = (0usize, f64::INFINITY);
    for (i, &hc) in grid.iter().enumerate() {
        let r = rms(hc)?;
        if r < best.1 {
            best = (i, r);
        }
    }
    // Golden-section search in ln H_c, one new fit per iteration (the bracket shrinks to 0.2 %).
    let (mut a, mut b) = (grid[best.0.saturating_sub(1)].ln(), grid[(best.0 + 1).min(24)].ln());
    let ratio = 0.5 * (5f64.sqrt() - 1.0);
    let (mut c, mut d) = (b - ratio * (b - a), a + ratio * (b - a));
    let (mut fc, mut fd) = (rms(c.exp())?, rms(d.exp())?);
    for _ in 0..14 {
        if fc < fd {
            (b, d, fd) = (d, c, fc);
            c = b - ratio * (b - a);
            fc = rms(c.exp())?;
        } else {
            (a, c, fc) = (c, d, fd);
            d = a + ratio * (b - a);
            fd = rms(d.exp())?;
        }
    }
    let hc = (0.5 * (a + b)).exp();
    Ok(Sourced::new(
        hc,
        Provenance::new(
            format!(
                "derived from the library B-H curve of {name}; no published coercivity of AISI 1008/1010/1018 was found"
            ),
            format!(
                "the coercivity (searched over {low}..{high} A/m) for which the energy-based model, fitted to the \
                 library curve as its normal magnetisation curve, reproduces that curve best; a model-based estimate"
            ),
            Trust::Low,
        ),
    ))
}

/// The set of library steel `name` fitted to its library curve and the given coercivity (A/m,
/// `0 < H_c < 5000`).
pub fn steel_with_coercivity(
    name: &str,
    coercivity: Sourced<f64>,
) -> Result<SteelHysteresis, MaterialError> {
    let hc = coercivity.value;
    if !(hc.is_finite() && hc > 0.0 && hc < 5000.0) {
        return Err(MaterialError::OutOfRange {
            quantity: "coercivity_A_per_m".into(),
            value: hc,
            allowed: "finite, 0 < Hc < 5000 A/m (soft steel)".into(),
        });
    }
    let material = crate::library::get(name)?;
    if material.kind != MaterialKind::Steel {
        return Err(no_model(name));
    }
    let curve = material.magnetic.bh_curve().ok_or_else(|| no_model(name))?;
    let points: Vec<(f64, f64)> =
        curve.points().iter().copied().filter(|p| p.0 > 0.0 && p.0 <= FIT_FIELD_A_PER_M).collect();
    let normal = Observation::first_magnetisation(&format!("{name} library curve"), &points);
    let coercive = Observation {
        name: format!("{name} coercivity"),
        h_a_per_m: vec![TIP_FIELD_A_PER_M, 0.0, -hc],
        b_t: vec![None, None, Some(0.0)],
        start: PathStart::Demagnetised,
        weight: points.len() as f64,
    };
    let options = IdentifyOptions {
        pinning_a_per_m: PINNING_GRID.iter().map(|f| f * hc).collect(),
        term_fields_a_per_m: (0..6)
            .map(|i| 0.125 * hc * (2.0 * FIT_FIELD_A_PER_M / hc).powf(i as f64 / 5.0))
            .collect(),
    };
    let fitted = fit(&[normal.clone(), coercive], &options)?;
    let measures = loop_measures(&major_loop(&fitted.params, TIP_FIELD_A_PER_M, 2000));
    let normal_rms = normal_curve_rms(&fitted.params, &points);
    let trust = material.provenance.trust.min(coercivity.provenance.trust);
    let provenance = Provenance::new(
        format!(
            "normal curve: {} ({}); coercivity: {}",
            material.provenance.source, material.provenance.trust, coercivity.provenance.source
        ),
        format!(
            "energy-based model fitted by NNLS to the library curve as the normal magnetisation curve \
             (H <= {FIT_FIELD_A_PER_M} A/m) and to B = 0 at H = -{hc} A/m after a tip at {TIP_FIELD_A_PER_M} A/m"
        ),
        trust,
    );
    Ok(SteelHysteresis {
        name: material.name.clone(),
        params: Arc::new(fitted.params),
        provenance,
        coercivity_a_per_m: coercivity,
        remanence_t: measures.remanence_t.unwrap_or(0.0),
        fitted_coercivity_a_per_m: measures.coercivity_a_per_m.unwrap_or(0.0),
        normal_curve_rms_t: normal_rms,
        warnings: fitted.warnings,
    })
}

/// RMS deviation of the model's first-magnetisation curve from `points`, T.
fn normal_curve_rms(params: &HysteresisParams, points: &[(f64, f64)]) -> f64 {
    let mut state = super::HysteresisState::demagnetised();
    let sum: f64 = points
        .iter()
        .map(|&(h, b)| {
            let r = state.step_h(params, h);
            (r.b - b).powi(2)
        })
        .sum();
    (sum / points.len().max(1) as f64).sqrt()
}
