//! Frequency-response data (FRD) files: one row per test frequency.
//!
//! Accepted columns (by name, header row): `omega_rad_s` and either `re, im` (preferred when present) or
//! `magnitude_dB, phase_deg`, optionally a weight column. Written files carry all of them plus the
//! measurement quality, so they can be read back by [`read_frd`] or by any spreadsheet.

use std::path::Path;

use num_complex::Complex64;

use crate::SysidError;
use crate::log::read_columns_from;

/// Frequency-response data.
#[derive(Debug, Clone, Default)]
pub struct Frd {
    /// Test frequencies in rad/s, strictly increasing.
    pub omega_rad_s: Vec<f64>,
    /// Complex64 response G(jω) at each frequency.
    pub response: Vec<Complex64>,
    /// Optional per-point weights for the estimator.
    pub weight: Option<Vec<f64>>,
}

impl Frd {
    /// Magnitude in dB, 20·log10|G| (thesis (5.4)).
    pub fn magnitude_db(&self) -> Vec<f64> {
        self.response.iter().map(|g| 20.0 * g.norm().log10()).collect()
    }

    /// Phase in degrees, unwrapped along frequency (starting in (−180°, 180°]).
    pub fn phase_deg_unwrapped(&self) -> Vec<f64> {
        unwrap_deg(&self.response.iter().map(|g| g.arg().to_degrees()).collect::<Vec<_>>())
    }
}

/// Removes ±360° jumps between consecutive phases.
pub fn unwrap_deg(phase_deg: &[f64]) -> Vec<f64> {
    let mut out = Vec::with_capacity(phase_deg.len());
    let mut offset = 0.0;
    for (k, p) in phase_deg.iter().enumerate() {
        if k > 0 {
            let prev = phase_deg[k - 1];
            let d = p - prev;
            offset -= 360.0 * (d / 360.0).round();
        }
        out.push(p + offset);
    }
    out
}

/// Positive, finite, strictly increasing frequencies; `Err((line, message))` for the first bad one.
fn check_frequencies(omega: &[f64]) -> Result<(), (u64, String)> {
    for (k, w) in omega.iter().enumerate() {
        let line = k as u64 + 2;
        if !(w.is_finite() && *w > 0.0) {
            return Err((line, format!("omega_rad_s must be a positive finite number, got {w}")));
        }
        if k > 0 && omega[k] <= omega[k - 1] {
            return Err((line, "omega_rad_s must strictly increase".into()));
        }
    }
    Ok(())
}

/// A file with both `re, im` and `magnitude_dB, phase_deg` must say the same thing in both
/// (within 0.1 % of |G|, room for a spreadsheet's rounding): the estimator reads re/im, so a
/// disagreement would otherwise go unnoticed.
fn check_polar_agrees(source: &Path, text: &str, response: &[Complex64]) -> Result<(), SysidError> {
    let cols = read_columns_from(source, text.as_bytes(), &["magnitude_dB", "phase_deg"])?;
    for (k, ((db, deg), g)) in cols[0].iter().zip(&cols[1]).zip(response).enumerate() {
        let polar = Complex64::from_polar(10f64.powf(db / 20.0), deg.to_radians());
        let distance = (polar - g).norm();
        if distance.is_nan() || distance > 1e-3 * g.norm().max(polar.norm()) {
            return Err(crate::log::file_error(source)(
                Some(k as u64 + 2),
                format!(
                    "re, im = {}, {} and magnitude_dB, phase_deg = {db}, {deg} disagree ({:.4} dB, \
                     {:.2}° from re/im): fix or delete one pair",
                    g.re,
                    g.im,
                    20.0 * g.norm().log10(),
                    g.arg().to_degrees()
                ),
            ));
        }
    }
    Ok(())
}

/// Reads an FRD CSV file; `weight_col` names an optional weight column.
pub fn read_frd(path: &Path, weight_col: Option<&str>) -> Result<Frd, SysidError> {
    let text = std::fs::read_to_string(path)
        .map_err(|source| SysidError::Io { path: path.to_path_buf(), source })?;
    read_frd_from(path, &text, weight_col)
}

/// As [`read_frd`], from text; `source` names it in errors.
pub fn read_frd_from(
    source: &Path,
    text: &str,
    weight_col: Option<&str>,
) -> Result<Frd, SysidError> {
    let file_err = crate::log::file_error(source);
    let mut rdr = crate::log::csv_reader(text.as_bytes(), false);
    let header: Vec<String> = rdr
        .headers()
        .map_err(|e| crate::log::csv_error(source, Some(1), "cannot read the header row", e))?
        .iter()
        .map(str::to_string)
        .collect();
    let has = |n: &str| header.iter().any(|h| h == n);
    let both = has("re") && has("im") && has("magnitude_dB") && has("phase_deg");
    let polar = if has("re") && has("im") {
        false
    } else if has("magnitude_dB") && has("phase_deg") {
        true
    } else {
        return Err(file_err(
            Some(1),
            format!(
                "needs columns omega_rad_s and either re, im or magnitude_dB, phase_deg (found: {})",
                header.join(", ")
            ),
        ));
    };
    let mut names = vec![
        "omega_rad_s",
        if polar { "magnitude_dB" } else { "re" },
        if polar { "phase_deg" } else { "im" },
    ];
    if let Some(w) = weight_col {
        names.push(w);
    }
    let cols = read_columns_from(source, text.as_bytes(), &names)?;
    let omega = cols[0].clone();
    check_frequencies(&omega).map_err(|(line, message)| file_err(Some(line), message))?;
    let response: Vec<Complex64> = if polar {
        cols[1]
            .iter()
            .zip(&cols[2])
            .map(|(db, deg)| Complex64::from_polar(10f64.powf(db / 20.0), deg.to_radians()))
            .collect()
    } else {
        cols[1].iter().zip(&cols[2]).map(|(re, im)| Complex64::new(*re, *im)).collect()
    };
    if let Some(k) = response.iter().position(|g| !(g.re.is_finite() && g.im.is_finite())) {
        return Err(file_err(
            Some(k as u64 + 2),
            format!("the response {} is not a finite number", response[k]),
        ));
    }
    if both {
        check_polar_agrees(source, text, &response)?;
    }
    let weight = match weight_col {
        Some(w) => {
            let ws = cols[3].clone();
            if let Some(k) = ws.iter().position(|v| *v < 0.0) {
                return Err(file_err(
                    Some(k as u64 + 2),
                    format!("weight column '{w}' must be non-negative"),
                ));
            }
            Some(ws)
        }
        None => None,
    };
    if omega.is_empty() {
        return Err(file_err(None, "no data rows".into()));
    }
    Ok(Frd { omega_rad_s: omega, response, weight })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 18: an FRD whose two forms disagree was fitted from re/im without a word.
    #[test]
    fn disagreeing_forms_and_non_finite_values_are_refused() {
        let same = "omega_rad_s,magnitude_dB,phase_deg,re,im\n1,0,-90,0,-1\n10,-20,-180,-0.1,0\n";
        assert!(read_frd_from(Path::new("f.csv"), same, None).is_ok());
        let differ = "omega_rad_s,magnitude_dB,phase_deg,re,im\n1,0,-90,0,-1\n10,-20,-90,-0.1,0\n";
        let e = read_frd_from(Path::new("f.csv"), differ, None).unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains("f.csv") && text.contains("disagree") && text.contains('3'),
            "{text}"
        );
        let inf = "omega_rad_s,re,im\n1,0,-1\ninf,1,0\n";
        assert!(read_frd_from(Path::new("f.csv"), inf, None).is_err());
    }

    #[test]
    fn polar_and_cartesian_forms_agree() {
        let polar = "omega_rad_s,magnitude_dB,phase_deg\n1,0,-90\n10,-20,-180\n";
        let a = read_frd_from(Path::new("a.csv"), polar, None).unwrap();
        assert!((a.response[0] - Complex64::new(0.0, -1.0)).norm() < 1e-15);
        assert!((a.response[1] - Complex64::new(-0.1, 0.0)).norm() < 1e-15);
        let cart = "omega_rad_s,re,im,w\n1,0,-1,1\n10,-0.1,0,2\n";
        let b = read_frd_from(Path::new("b.csv"), cart, Some("w")).unwrap();
        assert!((b.response[1] - a.response[1]).norm() < 1e-15);
        assert_eq!(b.weight.unwrap(), vec![1.0, 2.0]);
    }

    #[test]
    fn bad_frequency_names_line() {
        let err = read_frd_from(Path::new("f.csv"), "omega_rad_s,re,im\n1,1,0\n1,1,0\n", None)
            .unwrap_err()
            .to_string();
        assert!(err.contains("f.csv, line 3"), "{err}");
    }

    #[test]
    fn unwrap_removes_jumps() {
        let u = unwrap_deg(&[-170.0, 175.0, 160.0]);
        assert!((u[1] + 185.0).abs() < 1e-12 && (u[2] + 200.0).abs() < 1e-12);
    }
}
