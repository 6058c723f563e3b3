//! Identification of a parameter set from measured `(H, B)` paths by non-negative least squares.
//!
//! # Why the problem is linear
//! For a given H history, the reversible field of every cell depends only on H and on its pinning field
//! `κ_k` (the play rule), not on the cell's polarisation law. So with the pinning fields fixed on a grid
//! `κ_0 = 0 < κ_1 < …` and the term fields on a grid `a_1 < a_2 < …`, every sample gives one linear
//! equation in the term amplitudes `J_{k,m} ≥ 0`:
//! `B_i − μ0 H_i = Σ_{k,m} J_{k,m} g(h_k(i) / a_m)`, `g(x) = x/(1 + |x|)`.
//! The least-squares fit with `J_{k,m} ≥ 0` is convex (Lawson–Hanson NNLS: C. L. Lawson, R. J. Hanson, *Solving Least Squares Problems*, 1974, ch. 23), has no
//! local minima and needs no starting guess; the grid is the only choice (defaults from the data:
//! [`IdentifyOptions::from_data`]). Non-negative amplitudes make every fitted set a valid, passive model.
//!
//! # What a loop does not determine
//! The fit reports, as warnings: pinning fields the data never exercise (their cells never move, so
//! their amplitudes are set to zero); amplitudes whose standard error exceeds half their value (the
//! data cannot tell them from their neighbours on the grid — harmless for the fitted curves, but the
//! split is not a material property); and the saturation polarisation `J_s = Σ J_{k,m}` when its
//! relative standard error exceeds 5 % (a loop that stops short of saturation). Standard errors use
//! the residual's standard deviation, but at least [`RESIDUAL_FLOOR_T`] (noise-free synthetic data
//! would otherwise make every amplitude look determined). The weighted residual variance is used
//! as it is (weights are not normalised).
//!
//! # Paths
//! An [`Observation`] is one H sequence with measured B at some of its samples, starting from the
//! demagnetised state (a first-magnetisation curve) or periodic (a loop: the sequence is run once to
//! set the cells' state, then fitted on the second pass).

use std::path::Path;

use super::nnls::{nnls, solve_spd};
use super::params::{HysteresisParams, MAX_CELLS, MAX_TERMS, Term};
use super::{HysteresisState, loop_measures};
use crate::{MU_0, MaterialError};

/// The CSV header of a loop file: `H_A_per_m,B_T`, samples in traversal order.
pub const LOOP_HEADER: [&str; 2] = ["H_A_per_m", "B_T"];

/// Most samples of a loop file, and of all observations of one fit together.
pub const MAX_LOOP_POINTS: usize = 100_000;

/// Largest loop file read, bytes (about 40 bytes a sample).
pub const MAX_LOOP_FILE_BYTES: u64 = 4_000_000;

/// Fewest samples of a loop.
pub const MIN_LOOP_POINTS: usize = 8;

/// The smallest residual standard deviation assumed when judging what the data determine, T (the
/// resolution of a good B–H tracer, 0.1 mT).
pub const RESIDUAL_FLOOR_T: f64 = 1e-4;

/// Where an observed path starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PathStart {
    /// From the demagnetised state (a first-magnetisation / normal curve).
    Demagnetised,
    /// A periodic path (a loop): run once to set the state, fitted on the second pass.
    Periodic,
}

/// One measured path: H samples in order, the measured B at some of them.
#[derive(Debug, Clone, PartialEq)]
pub struct Observation {
    /// What the path is (for warnings), e.g. the file name.
    pub name: String,
    /// Applied field samples in traversal order, A/m.
    pub h_a_per_m: Vec<f64>,
    /// Measured flux density at each sample, T (`None`: the sample only drives the state).
    pub b_t: Vec<Option<f64>>,
    /// Where the path starts.
    pub start: PathStart,
    /// Weight of its samples in the least-squares sum (`> 0`).
    pub weight: f64,
}

impl Observation {
    /// A measured loop (periodic), every sample fitted.
    pub fn major_loop(name: &str, samples: &[(f64, f64)]) -> Self {
        Self {
            name: name.to_string(),
            h_a_per_m: samples.iter().map(|s| s.0).collect(),
            b_t: samples.iter().map(|s| Some(s.1)).collect(),
            start: PathStart::Periodic,
            weight: 1.0,
        }
    }

    /// A first-magnetisation (normal) curve from the demagnetised state, every sample fitted.
    pub fn first_magnetisation(name: &str, samples: &[(f64, f64)]) -> Self {
        Self { start: PathStart::Demagnetised, ..Self::major_loop(name, samples) }
    }
}

/// The grids of the fit: pinning fields (one cell each) and term fields (one term per cell each).
#[derive(Debug, Clone, PartialEq)]
pub struct IdentifyOptions {
    /// Pinning fields `κ_k`, A/m (at most [`MAX_CELLS`], each `≥ 0`).
    pub pinning_a_per_m: Vec<f64>,
    /// Term fields `a_m`, A/m (each `> 0`; cells × fields at most [`MAX_TERMS`]).
    pub term_fields_a_per_m: Vec<f64>,
}

impl IdentifyOptions {
    /// Default grids from the data: `κ = 0` plus 5 pinning fields spaced geometrically from
    /// `H_c/4` to `min(4 H_c, H_peak/2)`, and 6 term fields from `H_c/2` to `H_peak`, where `H_c`
    /// is the coercivity of the first loop among the observations (`H_peak/100` without one) and
    /// `H_peak` the largest |H| of the data.
    pub fn from_data(observations: &[Observation]) -> Self {
        let peak = observations
            .iter()
            .flat_map(|o| o.h_a_per_m.iter())
            .fold(0.0_f64, |m, h| m.max(h.abs()))
            .max(1.0);
        let coercivity = observations
            .iter()
            .filter(|o| o.start == PathStart::Periodic)
            .find_map(|o| {
                let samples: Vec<(f64, f64)> = o
                    .h_a_per_m
                    .iter()
                    .zip(&o.b_t)
                    .filter_map(|(&h, b)| b.map(|b| (h, b)))
                    .collect();
                loop_measures(&samples).coercivity_a_per_m
            })
            .filter(|hc| *hc > 0.0)
            .unwrap_or(peak / 100.0);
        let high = (4.0 * coercivity).min(0.5 * peak).max(0.25 * coercivity * 1.01);
        let mut pinning = vec![0.0];
        pinning.extend(geometric(0.25 * coercivity, high, 5));
        Self { pinning_a_per_m: pinning, term_fields_a_per_m: geometric(0.5 * coercivity, peak, 6) }
    }
}

/// `count` values spaced geometrically from `low` to `high`.
fn geometric(low: f64, high: f64, count: usize) -> Vec<f64> {
    let ratio = (high / low).powf(1.0 / (count.max(2) - 1) as f64);
    (0..count).map(|i| low * ratio.powi(i as i32)).collect()
}

/// The result of a fit.
#[derive(Debug, Clone, PartialEq)]
pub struct Identified {
    /// The fitted parameter set (terms with zero amplitude dropped).
    pub params: HysteresisParams,
    /// Root-mean-square residual of B over the fitted samples (unweighted), T.
    pub rms_residual_t: f64,
    /// Largest |residual| of B, T.
    pub max_residual_t: f64,
    /// Number of fitted samples.
    pub samples: usize,
    /// Standard error of the saturation polarisation `J_s`, T (`None`: fewer samples than amplitudes).
    pub saturation_polarisation_error_t: Option<f64>,
    /// What the data do not determine (see the module docs).
    pub warnings: Vec<String>,
}

/// Fits a parameter set to the observations on the grids of `options` (see the module docs).
pub fn fit(
    observations: &[Observation],
    options: &IdentifyOptions,
) -> Result<Identified, MaterialError> {
    check_observations(observations)?;
    let grid = Grid::new(options)?;
    let (g, c, samples) = normal_equations(observations, &grid);
    let p = grid.columns();
    let norms: Vec<f64> = (0..p).map(|i| g[i * p + i].sqrt()).collect();
    let largest = norms.iter().fold(0.0_f64, |m, &v| m.max(v));
    let usable: Vec<bool> = norms.iter().map(|&v| v > 1e-9 * largest).collect();
    let mut scaled = vec![0.0; p * p];
    let mut rhs = vec![0.0; p];
    for i in (0..p).filter(|&i| usable[i]) {
        rhs[i] = c[i] / norms[i];
        for j in (0..p).filter(|&j| usable[j]) {
            scaled[i * p + j] = g[i * p + j] / (norms[i] * norms[j]);
        }
    }
    let x: Vec<f64> = nnls(&scaled, &rhs)
        .iter()
        .enumerate()
        .map(|(i, &v)| if usable[i] { v / norms[i] } else { 0.0 })
        .collect();
    let (rms, max, sum_squares) = residuals(observations, &grid, &x);
    let mut warnings = unexercised_cells(&grid, &usable);
    let js_error = uncertainty(&scaled, &norms, &x, sum_squares, samples, &grid, &mut warnings);
    let params = grid.params(&x)?;
    Ok(Identified {
        params,
        rms_residual_t: rms,
        max_residual_t: max,
        samples,
        saturation_polarisation_error_t: js_error,
        warnings,
    })
}

/// Fits a measured major loop alone (`options`: the grids; `None` for [`IdentifyOptions::from_data`]).
pub fn fit_major_loop(
    samples: &[(f64, f64)],
    options: Option<&IdentifyOptions>,
) -> Result<Identified, MaterialError> {
    let observations = [Observation::major_loop("loop", samples)];
    let defaults;
    let options = match options {
        Some(o) => o,
        None => {
            defaults = IdentifyOptions::from_data(&observations);
            &defaults
        }
    };
    fit(&observations, options)
}

/// The grid of columns: column `k·M + m` is cell `k` with term field `a_m`.
struct Grid {
    pinning: Vec<f64>,
    fields: Vec<f64>,
}

impl Grid {
    fn new(options: &IdentifyOptions) -> Result<Self, MaterialError> {
        let (cells, fields) = (options.pinning_a_per_m.len(), options.term_fields_a_per_m.len());
        if cells == 0 || fields == 0 || cells > MAX_CELLS || cells * fields > MAX_TERMS {
            return Err(MaterialError::OutOfRange {
                quantity: "identification grid (pinning fields x term fields)".into(),
                value: (cells * fields) as f64,
                allowed: format!(
                    "1..={MAX_CELLS} pinning fields, at most {MAX_TERMS} columns in all"
                ),
            });
        }
        // Validates every grid value through the parameter rules.
        let terms: Vec<Term> = (0..cells)
            .flat_map(|k| options.term_fields_a_per_m.iter().map(move |&a| (k, a)))
            .map(|(cell, a)| Term { cell, polarisation_t: 1.0, field_a_per_m: a })
            .collect();
        HysteresisParams::new(&options.pinning_a_per_m, &terms)?;
        Ok(Self {
            pinning: options.pinning_a_per_m.clone(),
            fields: options.term_fields_a_per_m.clone(),
        })
    }

    fn columns(&self) -> usize {
        self.pinning.len() * self.fields.len()
    }

    /// The row of one sample: `g(h_k / a_m)` for every column.
    fn row(&self, reversible: &[f64; MAX_CELLS], row: &mut [f64]) {
        let m = self.fields.len();
        for k in 0..self.pinning.len() {
            for (j, &a) in self.fields.iter().enumerate() {
                let x = reversible[k] / a;
                row[k * m + j] = x / (1.0 + x.abs());
            }
        }
    }

    /// The parameter set of amplitudes `x`: zero amplitudes dropped, and with them the cells left
    /// without a term (they would contribute nothing but cost time at every step).
    fn params(&self, x: &[f64]) -> Result<HysteresisParams, MaterialError> {
        let m = self.fields.len();
        let kept: Vec<(usize, usize, f64)> = x
            .iter()
            .enumerate()
            .filter(|(_, v)| **v > 1e-9)
            .map(|(i, &v)| (i / m, i % m, v))
            .collect();
        if kept.is_empty() {
            return Err(MaterialError::OutOfRange {
                quantity: "fitted saturation polarisation (no positive amplitude)".into(),
                value: 0.0,
                allowed: "data with B − mu0 H increasing with H".into(),
            });
        }
        let mut cells: Vec<usize> = kept.iter().map(|t| t.0).collect();
        cells.dedup();
        let pinning: Vec<f64> = cells.iter().map(|&k| self.pinning[k]).collect();
        let terms: Vec<Term> = kept
            .iter()
            .map(|&(k, j, v)| Term {
                cell: cells
                    .iter()
                    .position(|&c| c == k)
                    .expect("kept cells include every term's cell"),
                polarisation_t: v,
                field_a_per_m: self.fields[j],
            })
            .collect();
        HysteresisParams::new(&pinning, &terms)
    }
}

/// Visits every fitted sample: its row of the design matrix, `B − μ0 H`, its weight.
fn for_each_sample(
    observations: &[Observation],
    grid: &Grid,
    mut visit: impl FnMut(&[f64], f64, f64),
) {
    // Zero amplitudes: only the cells' reversible fields matter here.
    let probe = HysteresisParams::new(
        &grid.pinning,
        &[Term { cell: 0, polarisation_t: 1.0, field_a_per_m: 1.0 }],
    )
    .expect("the grid was validated");
    let mut row = vec![0.0; grid.columns()];
    for observation in observations {
        let mut state = HysteresisState::demagnetised();
        if observation.start == PathStart::Periodic {
            for &h in &observation.h_a_per_m {
                state.step_h(&probe, h);
            }
        }
        for (&h, b) in observation.h_a_per_m.iter().zip(&observation.b_t) {
            state.step_h(&probe, h);
            if let Some(b) = b {
                grid.row(state.reversible_a_per_m(), &mut row);
                visit(&row, b - MU_0 * h, observation.weight);
            }
        }
    }
}

/// `G = AᵀWA`, `c = AᵀWy` and the number of fitted samples.
fn normal_equations(observations: &[Observation], grid: &Grid) -> (Vec<f64>, Vec<f64>, usize) {
    let p = grid.columns();
    let (mut g, mut c, mut samples) = (vec![0.0; p * p], vec![0.0; p], 0);
    for_each_sample(observations, grid, |row, y, w| {
        samples += 1;
        for i in 0..p {
            c[i] += w * row[i] * y;
            for j in 0..p {
                g[i * p + j] += w * row[i] * row[j];
            }
        }
    });
    (g, c, samples)
}

/// RMS and largest |residual| (unweighted) and the weighted sum of squares.
fn residuals(observations: &[Observation], grid: &Grid, x: &[f64]) -> (f64, f64, f64) {
    let (mut sum, mut weighted, mut max, mut n) = (0.0, 0.0, 0.0_f64, 0usize);
    for_each_sample(observations, grid, |row, y, w| {
        let r = row.iter().zip(x).map(|(a, b)| a * b).sum::<f64>() - y;
        sum += r * r;
        weighted += w * r * r;
        max = max.max(r.abs());
        n += 1;
    });
    ((sum / n.max(1) as f64).sqrt(), max, weighted)
}

/// Warnings for cells whose columns vanish on the data.
fn unexercised_cells(grid: &Grid, usable: &[bool]) -> Vec<String> {
    let m = grid.fields.len();
    (0..grid.pinning.len())
        .filter(|&k| (0..m).all(|j| !usable[k * m + j]))
        .map(|k| {
            format!(
                "pinning field {:.4} A/m is not exercised by the data (its cell never moves): its weight is not determined and is set to zero",
                grid.pinning[k]
            )
        })
        .collect()
}

/// Standard errors on the active set; pushes warnings and returns the error of `J_s`.
fn uncertainty(
    scaled: &[f64],
    norms: &[f64],
    x: &[f64],
    sum_squares: f64,
    samples: usize,
    grid: &Grid,
    warnings: &mut Vec<String>,
) -> Option<f64> {
    let p = x.len();
    let active: Vec<usize> = (0..p).filter(|&i| x[i] > 0.0).collect();
    let n = active.len();
    if n == 0 || samples <= n {
        return None;
    }
    // A floor on the residual variance: exact (synthetic) data must not make everything look
    // determined.
    let variance = (sum_squares / (samples - n) as f64).max(RESIDUAL_FLOOR_T * RESIDUAL_FLOOR_T);
    let sub: Vec<f64> =
        active.iter().flat_map(|&i| active.iter().map(move |&j| scaled[i * p + j])).collect();
    let (mut js_variance, mut poor) = (0.0, Vec::new());
    for (a, &i) in active.iter().enumerate() {
        let mut unit = vec![0.0; n];
        unit[a] = 1.0;
        let column = solve_spd(&sub, &unit);
        js_variance +=
            column.iter().zip(&active).map(|(v, &j)| v / (norms[i] * norms[j])).sum::<f64>();
        let error = (variance * column[a]).sqrt() / norms[i];
        if error > 0.5 * x[i] {
            let m = grid.fields.len();
            poor.push(format!(
                "(kappa {:.4} A/m, a {:.4} A/m)",
                grid.pinning[i / m],
                grid.fields[i % m]
            ));
        }
    }
    if !poor.is_empty() {
        warnings.push(format!(
            "{} of {n} amplitudes are poorly determined (standard error > 50 %): {}; the fitted curves are not affected, their split between cells is not a material property",
            poor.len(),
            poor.join(", ")
        ));
    }
    let js: f64 = x.iter().sum();
    let js_error = (variance * js_variance.max(0.0)).sqrt();
    if js_error > 0.05 * js {
        warnings.push(format!(
            "the data do not determine the saturation polarisation: J_s = {js:.4} T +- {js_error:.4} T; extend the loop towards saturation"
        ));
    }
    Some(js_error)
}

/// Checks sizes, finiteness and weights of the observations.
fn check_observations(observations: &[Observation]) -> Result<(), MaterialError> {
    let total: usize = observations.iter().map(|o| o.h_a_per_m.len()).sum();
    if observations.is_empty() || total > 2 * MAX_LOOP_POINTS {
        return Err(MaterialError::OutOfRange {
            quantity: "samples of all observations".into(),
            value: total as f64,
            allowed: format!("1..={}", 2 * MAX_LOOP_POINTS),
        });
    }
    for o in observations {
        let bad = |line: usize, message: String| MaterialError::Parse {
            file: o.name.clone(),
            line: line as u64 + 1,
            message,
        };
        if o.h_a_per_m.len() != o.b_t.len() || o.h_a_per_m.is_empty() {
            return Err(bad(0, "H and B must have the same, non-zero number of samples".into()));
        }
        if !(o.weight.is_finite() && o.weight > 0.0) {
            return Err(bad(0, format!("weight {} must be finite and > 0", o.weight)));
        }
        for (i, (h, b)) in o.h_a_per_m.iter().zip(&o.b_t).enumerate() {
            if !h.is_finite()
                || h.abs() > 1e8
                || b.is_some_and(|b| !b.is_finite() || b.abs() > 100.0)
            {
                return Err(bad(
                    i,
                    format!(
                        "sample ({h}, {b:?}) out of range: finite, |H| <= 1e8 A/m, |B| <= 100 T"
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Reads a loop from CSV text (header `H_A_per_m,B_T`, samples in traversal order); `file` names
/// the source in errors (file, line, column).
pub fn read_loop_csv(text: &str, file: &str) -> Result<Vec<(f64, f64)>, MaterialError> {
    if text.len() as u64 > MAX_LOOP_FILE_BYTES {
        return Err(MaterialError::Parse {
            file: file.to_string(),
            line: 1,
            message: format!(
                "the file has {} bytes; at most {MAX_LOOP_FILE_BYTES} are read",
                text.len()
            ),
        });
    }
    let rows = crate::table::read_xy(text, file, LOOP_HEADER)?;
    if rows.len() > MAX_LOOP_POINTS || rows.len() < MIN_LOOP_POINTS {
        return Err(MaterialError::Parse {
            file: file.to_string(),
            line: rows.last().map_or(1, |r| r.0),
            message: format!(
                "{} samples; a loop needs {MIN_LOOP_POINTS}..={MAX_LOOP_POINTS}",
                rows.len()
            ),
        });
    }
    for &(line, h, b) in &rows {
        for (column, value, limit) in [(LOOP_HEADER[0], h, 1e8), (LOOP_HEADER[1], b, 100.0)] {
            if !(value.is_finite() && value.abs() <= limit) {
                return Err(MaterialError::InvalidCurve {
                    file: file.to_string(),
                    line,
                    rule: format!(
                        "field `{column}` is {value}; allowed: finite, |value| <= {limit:e}"
                    ),
                });
            }
        }
    }
    Ok(rows.into_iter().map(|(_, h, b)| (h, b)).collect())
}

/// Reads a loop file (see [`read_loop_csv`]); a file over [`MAX_LOOP_FILE_BYTES`] is refused unread.
pub fn read_loop_file(path: &Path) -> Result<Vec<(f64, f64)>, MaterialError> {
    let file = path.display().to_string();
    let size = std::fs::metadata(path).map_err(|e| MaterialError::io(&file, e))?.len();
    if size > MAX_LOOP_FILE_BYTES {
        return Err(MaterialError::Parse {
            file,
            line: 1,
            message: format!("the file has {size} bytes; at most {MAX_LOOP_FILE_BYTES} are read"),
        });
    }
    let text = mrbrake_error::read::text(path, mrbrake_error::read::LOG)
        .map_err(|e| MaterialError::io(&file, e))?;
    read_loop_csv(&text, &file)
}
