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
    for (k, w) in omega.iter().enumerate() {
        if w.is_nan() || *w <= 0.0 {
            return Err(file_err(
                Some(k as u64 + 2),
                format!("omega_rad_s must be positive, got {w}"),
            ));
        }
        if k > 0 && omega[k] <= omega[k - 1] {
            return Err(file_err(Some(k as u64 + 2), "omega_rad_s must strictly increase".into()));
        }
    }
    let response: Vec<Complex64> = if polar {
        cols[1]
            .iter()
            .zip(&cols[2])
            .map(|(db, deg)| Complex64::from_polar(10f64.powf(db / 20.0), deg.to_radians()))
            .collect()
    } else {
        cols[1].iter().zip(&cols[2]).map(|(re, im)| Complex64::new(*re, *im)).collect()
    };
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
