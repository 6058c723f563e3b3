//! Identification of the operator hysteresis model ([`mrbrake_control::OperatorModel`], Kuhnen's
//! modified Prandtl–Ishlinskii model) from a log that contains minor loops, and the reader of its
//! file.
//!
//! **Method** (Kuhnen 2003, European Journal of Control 9(4), 407–418, §4: identification in the
//! "implicit" form). The model is `D(y) = Π[x]` with current `x`, torque `y`. With the play thresholds
//! and the knots of `D` fixed on uniform grids (plays `rᵢ = i·(x_max − x_min)/(2n)`, `i = 0…n−1`;
//! knots over the logged torque range), both sides are linear in the unknowns, so with `a₀ = 1`
//! (which fixes the common scale of `Π` and `D`)
//!
//! ```text
//! x(t) = −Σ_{i≥1} aᵢ F_{rᵢ}[x](t) + c + Σⱼ βⱼ ψⱼ(y(t)),     aᵢ ≥ 0,  βⱼ ≥ β_min > 0
//! ```
//!
//! is a linear least-squares problem with bounds. The free offset `c` is removed by centring every
//! column, `βⱼ = β_min + β'ⱼ` turns the lower bounds into non-negativity, and the problem is solved by
//! the active-set NNLS algorithm of Lawson & Hanson (*Solving Least Squares Problems*, 1974, ch. 23)
//! on the normal equations (a few dozen unknowns). The plays start in the rest state, so the fit uses
//! the samples from the first visit of the lowest current on (a descent to the lowest current erases
//! the brake's memory).
//!
//! **Quality** is reported as an output error: the identified forward model is run on the log's
//! current and its torque compared with the measured one (RMSE, fit percentage).
//!
//! **Bad input.** A minor-loop identification needs reversals of the current inside its range; a log
//! whose current turns only at its extremes (the characterisation's full ramps) is refused.

use mrbrake_error::FieldError;
use std::path::Path;

use mrbrake_control::{OperatorModel, OperatorParts, OperatorState};

use crate::SysidError;
use crate::characterize::fit_percent;

/// Settings of the operator identification.
#[derive(Debug, Clone, Copy)]
pub struct OperatorOptions {
    /// Number of play operators (including the `r = 0` one), 1..=[`mrbrake_control::MAX_PLAYS`].
    pub plays: usize,
    /// Segments of the output map, 1..=[`mrbrake_control::MAX_SEGMENTS`].
    pub segments: usize,
}

impl Default for OperatorOptions {
    fn default() -> Self {
        Self { plays: 12, segments: 12 }
    }
}

/// The identified model and how well it reproduces the log.
#[derive(Debug, Clone, serde::Serialize)]
pub struct OperatorFit {
    /// The model (serialised in the operator-model file schema).
    #[serde(flatten)]
    pub model: OperatorModelJson,
    /// Fit statistics (ignored by the file reader).
    pub fit: OperatorFitStats,
}

/// The model as JSON (the operator-model file's fields).
#[derive(Debug, Clone, serde::Serialize)]
#[serde(transparent)]
pub struct OperatorModelJson(pub OperatorModel);

/// How well the identified forward model reproduces the log.
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct OperatorFitStats {
    /// Torque RMSE of the forward model over the samples used, N·m.
    #[serde(rename = "rmse_Nm")]
    pub rmse_nm: f64,
    /// 100·(1 − ‖T − T̂‖/‖T − mean T‖) over the samples used.
    pub fit_percent: f64,
    /// Reversals of the current strictly inside its range.
    pub inner_reversals: usize,
    /// Samples used (from the first visit of the lowest current on).
    pub samples: usize,
}

/// Identifies the operator model from current (A) and torque (N·m) samples (module docs).
pub fn fit_operator_model(
    current_a: &[f64],
    torque_nm: &[f64],
    options: OperatorOptions,
) -> Result<OperatorFit, SysidError> {
    check_inputs(current_a, torque_nm, options)?;
    let (lo, hi) = range(current_a);
    let inner_reversals = inner_reversals(current_a, lo, hi);
    if inner_reversals < 2 {
        return Err(FieldError::new(
            "current",
            format!(
                "characterize --operators: too few reversals inside its range {lo:.4}..{hi:.4} A \
                 (turning points at the extremes do not count); a minor-loop identification needs \
                 minor loops: record them with `mrbrake rig minor-loops` or the same current \
                 program on the real brake"
            ),
        )
        .with_value(format!("{inner_reversals} reversal(s)"))
        .with_allowed(">= 2 reversals")
        .into());
    }
    // From the first visit of the lowest current on, the plays' rest state is known.
    let start = current_a.iter().position(|&i| i <= lo + 1e-3 * (hi - lo)).unwrap_or(0);
    let (x, y) = (&current_a[start..], &torque_nm[start..]);
    let (y_lo, y_hi) = range(y);
    let thresholds: Vec<f64> =
        (0..options.plays).map(|i| i as f64 * (hi - lo) / (2 * options.plays) as f64).collect();
    let knots: Vec<f64> = (0..options.segments)
        .map(|j| y_lo + j as f64 * (y_hi - y_lo) / options.segments as f64)
        .collect();
    let (weights, slopes, offset) = solve_weights(x, y, &thresholds, &knots, lo)?;
    let model = OperatorModel::new(&OperatorParts {
        thresholds_a: &thresholds,
        weights: &weights,
        knots_nm: &knots,
        slopes_a_per_nm: &slopes,
        offset_a: offset,
        current_min_a: lo,
        current_max_a: hi,
    })
    .map_err(|e| {
        SysidError::from(FieldError::new(
            "current",
            format!("characterize --operators: identified model refused: {e}"),
        ))
    })?;
    let predicted = simulate(&model, x);
    let n = y.len() as f64;
    let rmse_nm =
        (y.iter().zip(&predicted).map(|(a, b)| (a - b) * (a - b)).sum::<f64>() / n).sqrt();
    let stats = OperatorFitStats {
        rmse_nm,
        fit_percent: fit_percent(y, &predicted),
        inner_reversals,
        samples: y.len(),
    };
    Ok(OperatorFit { model: OperatorModelJson(model), fit: stats })
}

/// The forward model's torque along a current history starting at rest.
pub fn simulate(model: &OperatorModel, current_a: &[f64]) -> Vec<f64> {
    let mut state = OperatorState::default();
    current_a.iter().map(|&i| model.torque_nm(&mut state, i)).collect()
}

fn check_inputs(
    current_a: &[f64],
    torque_nm: &[f64],
    o: OperatorOptions,
) -> Result<(), SysidError> {
    if current_a.len() != torque_nm.len() || current_a.len() < 10 {
        return Err(FieldError::new(
            "torque",
            "characterize --operators: need equally long current and torque signals",
        )
        .with_value(format!("{} and {} samples", current_a.len(), torque_nm.len()))
        .with_allowed(">= 10 samples each, equally many")
        .into());
    }
    let (p, s) = (mrbrake_control::MAX_PLAYS, mrbrake_control::MAX_SEGMENTS);
    let capacity = "the controller's fixed capacity";
    if !(1..=p).contains(&o.plays) {
        let e = FieldError::new("plays", capacity).with_value(o.plays);
        return Err(e.with_allowed(format!("1..={p}")).into());
    }
    if !(1..=s).contains(&o.segments) {
        let e = FieldError::new("segments", capacity).with_value(o.segments);
        return Err(e.with_allowed(format!("1..={s}")).into());
    }
    if current_a.iter().chain(torque_nm).any(|v| !v.is_finite()) {
        return Err(FieldError::new("current", "characterize --operators: non-finite sample")
            .with_allowed("finite samples")
            .into());
    }
    Ok(())
}

/// Smallest and largest value.
fn range(v: &[f64]) -> (f64, f64) {
    v.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| (l.min(*x), h.max(*x)))
}

/// Turning points of the current (moves smaller than 1 % of the range are ignored, so sensor or
/// DAC steps do not count) that lie more than 5 % of the range inside both extremes.
pub fn inner_reversals(current_a: &[f64], lo: f64, hi: f64) -> usize {
    let span = hi - lo;
    if span.is_nan() || span <= 0.0 {
        return 0;
    }
    let step = 0.01 * span;
    let (mut extreme, mut direction, mut count) = (current_a[0], 0i8, 0usize);
    for &i in current_a {
        let turned = match direction {
            1 if i < extreme - step => Some(-1),
            -1 if i > extreme + step => Some(1),
            0 if (i - extreme).abs() > step => Some(if i > extreme { 1 } else { -1 }),
            _ => None,
        };
        match turned {
            Some(d) => {
                if direction != 0 && extreme > lo + 0.05 * span && extreme < hi - 0.05 * span {
                    count += 1;
                }
                direction = d;
                extreme = i;
            }
            None if (direction == 1 && i > extreme) || (direction == -1 && i < extreme) => {
                extreme = i;
            }
            None => {}
        }
    }
    count
}

/// The weights `(a, β, c)` of the module docs by NNLS.
fn solve_weights(
    x: &[f64],
    y: &[f64],
    thresholds: &[f64],
    knots: &[f64],
    rest_a: f64,
) -> Result<(Vec<f64>, Vec<f64>, f64), SysidError> {
    let (n, m) = (thresholds.len(), knots.len());
    let (y_lo, y_hi) = range(y);
    let (x_lo, x_hi) = range(x);
    let beta_min = 1e-3 * (x_hi - x_lo) / (y_hi - y_lo).max(1e-12);
    let columns = n - 1 + m;
    let mut gram = vec![0.0; columns * columns];
    let mut rhs = vec![0.0; columns];
    let mut sums = vec![0.0; columns + 1];
    let mut plays: Vec<f64> = thresholds.iter().map(|r| rest_a + r).collect();
    let mut row = vec![0.0; columns];
    // Two passes would store every row; instead accumulate raw moments and centre afterwards.
    let mut target_sq_cross = vec![0.0; columns];
    let count = x.len() as f64;
    for (&xi, &yi) in x.iter().zip(y) {
        for (k, r) in thresholds.iter().enumerate() {
            plays[k] = (xi - r).max((xi + r).min(plays[k]));
        }
        for k in 1..n {
            row[k - 1] = -plays[k];
        }
        let mut psi_sum = 0.0;
        for j in 0..m {
            let upper = if j + 1 < m { knots[j + 1] - knots[j] } else { f64::INFINITY };
            let lower = if j == 0 { f64::NEG_INFINITY } else { 0.0 };
            let psi = (yi - knots[j]).clamp(lower, upper);
            row[n - 1 + j] = psi;
            psi_sum += psi;
        }
        let target = xi - beta_min * psi_sum;
        for a in 0..columns {
            sums[a] += row[a];
            target_sq_cross[a] += row[a] * target;
            for b in a..columns {
                gram[a * columns + b] += row[a] * row[b];
            }
        }
        sums[columns] += target;
    }
    // Centring removes the free offset: G ← G − s sᵀ/N, h ← h − s·t̄.
    for a in 0..columns {
        rhs[a] = target_sq_cross[a] - sums[a] * sums[columns] / count;
        for b in a..columns {
            let v = gram[a * columns + b] - sums[a] * sums[b] / count;
            gram[a * columns + b] = v;
            gram[b * columns + a] = v;
        }
    }
    let solution = nnls_gram(&gram, &rhs, columns)?;
    let mut weights = vec![1.0];
    weights.extend_from_slice(&solution[..n - 1]);
    let slopes: Vec<f64> = solution[n - 1..].iter().map(|b| b + beta_min).collect();
    // c = mean(target) − Σ θ·mean(column).
    let offset = sums[columns] / count
        - solution.iter().zip(&sums[..columns]).map(|(t, s)| t * s / count).sum::<f64>();
    Ok((weights, slopes, offset))
}

/// Lawson–Hanson NNLS on the normal equations: minimises `½θᵀGθ − hᵀθ` with `θ ≥ 0`.
pub fn nnls_gram(gram: &[f64], rhs: &[f64], n: usize) -> Result<Vec<f64>, SysidError> {
    let scale: Vec<f64> = (0..n).map(|k| gram[k * n + k].max(1e-300).sqrt()).collect();
    let g = |a: usize, b: usize| gram[a * n + b] / (scale[a] * scale[b]);
    let h: Vec<f64> = (0..n).map(|k| rhs[k] / scale[k]).collect();
    let mut x = vec![0.0; n];
    let mut passive = vec![false; n];
    let tolerance = 1e-12 * h.iter().fold(0.0_f64, |m, v| m.max(v.abs())).max(1e-300);
    for _ in 0..3 * n + 10 {
        let w: Vec<f64> =
            (0..n).map(|a| h[a] - (0..n).map(|b| g(a, b) * x[b]).sum::<f64>()).collect();
        let candidate = (0..n).filter(|&k| !passive[k]).max_by(|&a, &b| w[a].total_cmp(&w[b]));
        let Some(j) = candidate.filter(|&j| w[j] > tolerance) else {
            return Ok((0..n).map(|k| x[k] / scale[k]).collect());
        };
        passive[j] = true;
        for _ in 0..3 * n + 10 {
            let s = solve_passive(&g, &h, &passive, n)?;
            if (0..n).filter(|&k| passive[k]).all(|k| s[k] > 0.0) {
                x = s;
                break;
            }
            let alpha = (0..n)
                .filter(|&k| passive[k] && s[k] <= 0.0)
                .map(|k| x[k] / (x[k] - s[k]))
                .fold(f64::INFINITY, f64::min);
            for k in 0..n {
                x[k] += alpha * (s[k] - x[k]);
                if passive[k] && x[k] <= 1e-15 {
                    passive[k] = false;
                    x[k] = 0.0;
                }
            }
        }
    }
    Err(SysidError::Numerical {
        message: "characterize --operators: NNLS did not converge".into(),
        history: Vec::new(),
    })
}

/// Solves `G_PP s_P = h_P` (Cholesky with a ridge of 10⁻¹⁴ on the unit diagonal), `s = 0` outside the passive set.
fn solve_passive(
    g: &dyn Fn(usize, usize) -> f64,
    h: &[f64],
    passive: &[bool],
    n: usize,
) -> Result<Vec<f64>, SysidError> {
    let idx: Vec<usize> = (0..n).filter(|&k| passive[k]).collect();
    let p = idx.len();
    let mut l = vec![0.0; p * p];
    for a in 0..p {
        for b in 0..=a {
            let mut v = g(idx[a], idx[b]) + if a == b { 1e-14 } else { 0.0 };
            for k in 0..b {
                v -= l[a * p + k] * l[b * p + k];
            }
            if a == b {
                if v <= 0.0 {
                    return Err(SysidError::Numerical {
                        message: "characterize --operators: the regressors are linearly dependent"
                            .into(),
                        history: Vec::new(),
                    });
                }
                l[a * p + a] = v.sqrt();
            } else {
                l[a * p + b] = v / l[b * p + b];
            }
        }
    }
    let mut z: Vec<f64> = idx.iter().map(|&k| h[k]).collect();
    for a in 0..p {
        z[a] = (z[a] - (0..a).map(|k| l[a * p + k] * z[k]).sum::<f64>()) / l[a * p + a];
    }
    for a in (0..p).rev() {
        z[a] = (z[a] - (a + 1..p).map(|k| l[k * p + a] * z[k]).sum::<f64>()) / l[a * p + a];
    }
    let mut s = vec![0.0; n];
    for (a, &k) in idx.iter().enumerate() {
        s[k] = z[a];
    }
    Ok(s)
}

/// Reads an operator-model file (schema [`mrbrake_control::OPERATOR_SCHEMA`]); errors name the file
/// and the field (a list beyond the controller's capacity names its length and the capacity).
pub fn read_operator_model(path: &Path) -> Result<OperatorModel, SysidError> {
    parse_operator_model(path, &crate::model_file::read_text(path)?)
}

/// Parses operator-model JSON text; `source` names it in errors.
pub fn parse_operator_model(source: &Path, text: &str) -> Result<OperatorModel, SysidError> {
    crate::model_file::deserialize_json(source, text)
}

/// Reads either model file: an operator-model file (it has a `schema` field) or the polynomial-branch
/// inverse-model file ([`crate::model_file`]), as the controller's [`mrbrake_control::TorqueInverse`].
pub fn read_torque_inverse(path: &Path) -> Result<mrbrake_control::TorqueInverse, SysidError> {
    let text = crate::model_file::read_text(path)?;
    let has_schema = serde_json::from_str::<serde_json::Value>(&text)
        .map(|v| v.get("schema").is_some())
        .unwrap_or(false);
    if has_schema {
        parse_operator_model(path, &text).map(Into::into)
    } else {
        crate::model_file::parse_inverse_model(path, &text).map(Into::into)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrbrake_error::Kind as _;

    /// Nested triangles 0 → 2 → 0.4 → 1.6 → 0.8 → 1.2 → 0 A in 1 mA steps.
    fn nested_current() -> Vec<f64> {
        let turning: [f64; 9] = [0.0, 2.0, 0.4, 1.6, 0.8, 1.2, 0.0, 1.0, 0.0];
        let mut i = Vec::new();
        for w in turning.windows(2) {
            let steps = ((w[1] - w[0]).abs() / 1e-3).round() as usize;
            i.extend((0..steps).map(|k| w[0] + (w[1] - w[0]) * k as f64 / steps as f64));
        }
        i
    }

    #[test]
    fn a_model_in_the_class_is_recovered() {
        // Same play grid as the fit (2 A / (2·4) apart) and a linear output map, so the truth is in the
        // model class and the equation error is zero.
        let truth = OperatorModel::new(&OperatorParts {
            thresholds_a: &[0.0, 0.25, 0.5, 0.75],
            weights: &[1.0, 0.4, 0.0, 0.1],
            knots_nm: &[0.15],
            slopes_a_per_nm: &[0.6],
            offset_a: 0.4,
            current_min_a: 0.0,
            current_max_a: 2.0,
        })
        .unwrap();
        let current = nested_current();
        let torque = simulate(&truth, &current);
        let fit = fit_operator_model(&current, &torque, OperatorOptions { plays: 4, segments: 1 })
            .unwrap();
        assert!(fit.fit.rmse_nm < 1e-9, "{:?}", fit.fit);
        let parts = fit.model.0.parts();
        for (a, b) in parts.weights.iter().zip([1.0, 0.4, 0.0, 0.1]) {
            assert!((a - b).abs() < 1e-9, "{:?}", parts.weights);
        }
        assert!(fit.fit.inner_reversals >= 4);
    }

    #[test]
    fn full_ramps_without_minor_loops_are_refused() {
        let mut current = Vec::new();
        for _ in 0..3 {
            current.extend((0..=2000).map(|k| k as f64 * 1e-3));
            current.extend((0..2000).rev().map(|k| k as f64 * 1e-3));
        }
        let torque: Vec<f64> = current.iter().map(|i| 0.15 + 1.8 * i).collect();
        let e = fit_operator_model(&current, &torque, OperatorOptions::default()).unwrap_err();
        assert!(e.is_input_error());
        assert!(e.to_string().contains("rig minor-loops"), "{e}");
    }

    #[test]
    fn nnls_matches_a_hand_solution() {
        // min ‖Aθ − b‖ with A = I₂, b = (1, −2): θ = (1, 0).
        let s = nnls_gram(&[1.0, 0.0, 0.0, 1.0], &[1.0, -2.0], 2).unwrap();
        assert!((s[0] - 1.0).abs() < 1e-10 && s[1].abs() < 1e-15, "{s:?}");
    }

    #[test]
    fn files_beyond_the_capacity_name_count_and_limit() {
        let thresholds: Vec<String> = (0..40).map(|k| format!("{}", k as f64 * 0.01)).collect();
        let text = format!(
            r#"{{"schema": "mrbrake.operator-model", "version": 1, "current_min_A": 0.0, "current_max_A": 2.0,
                "plays": {{"thresholds_A": [{}], "weights": [1.0]}},
                "output": {{"knots_Nm": [0.1], "slopes_A_per_Nm": [1.0], "offset_A": 0.0}}}}"#,
            thresholds.join(",")
        );
        let e = parse_operator_model(Path::new("op.json"), &text).unwrap_err();
        assert!(e.is_input_error());
        let chain = format!("{e}: {}", std::error::Error::source(&e).unwrap());
        assert!(
            chain.contains("plays.thresholds_A") && chain.contains("invalid length 40"),
            "{chain}"
        );
        assert!(chain.contains("1 to 32"), "{chain}");
        let foreign = text.replace("mrbrake.operator-model", "other");
        let e = parse_operator_model(Path::new("op.json"), &foreign).unwrap_err();
        assert!(
            std::error::Error::source(&e).unwrap().to_string().contains("mrbrake.operator-model")
        );
    }
}
