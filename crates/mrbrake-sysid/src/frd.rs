//! Frequency-response data (FRD): the complex response G(jω) at a set of angular frequencies, the
//! one shape of every frequency response in mrbrake, and its CSV file.
//!
//! - [`FrequencyPoint`]: G(jω) at one ω, with the whole turns that put its phase on the branch of
//!   its neighbours ([`unwrap_phase`]). A predicted response (`mrbrake_design::response`), a
//!   measured one (each [`crate::freqresp::MeasuredPoint`] wraps one with its quality, tracking
//!   error and log file) and a model's ([`Frd::sample`] of
//!   [`crate::transfer_function::TransferFunction::response`]) are all made of them, so a
//!   prediction and a measurement are plotted on one Bode diagram and fitted by
//!   [`crate::tfest`] as they are.
//! - [`Frd`]: the points in increasing frequency, with optional per-point weights of the estimator.
//! - [`bandwidth_rad_s`]: the one −3 dB bandwidth search, of data (log–log interpolated between the
//!   points, [`Frd::bandwidth_rad_s`]) and of models
//!   ([`crate::transfer_function::TransferFunction::bandwidth_rad_s`]).
//!
//! # The FRD CSV file
//!
//! A header row, then one row per test frequency; columns by name, in any order. The reader
//! ([`read_frd`]) needs `omega_rad_s` (positive, strictly increasing) and either `re, im` (read
//! when present) or `magnitude_dB, phase_deg` (20·log10|G|, thesis (5.4), and degrees), optionally a
//! weight column named by the caller; other columns are ignored. A file with both forms must say
//! the same thing in both. The one writer ([`write_csv`]) writes
//!
//! ```text
//! omega_rad_s,magnitude_dB,phase_deg,re,im[,more columns]
//! ```
//!
//! with the phase unwrapped along frequency, then the columns it is given: a measurement's
//! `quality_percent,rmse_Nm,rmse_percent` (`mrbrake freqresp`), an FRD's `weight`. Files of
//! earlier versions, whose predicted responses (`mrbrake response --frd`) had the columns
//! `omega_rad_s,re,im,magnitude_dB,phase_deg`, read the same: the reader goes by names.

use std::path::Path;

use num_complex::Complex64;
use serde::ser::{Serialize, SerializeSeq, SerializeStruct, Serializer};

use crate::SysidError;
use crate::log::read_columns_from;

/// The magnitude ratio of the half-power point, 1/√2 (−3.01 dB): the level of a model's −3 dB
/// bandwidth relative to its DC gain
/// ([`crate::transfer_function::TransferFunction::bandwidth_rad_s`]).
pub const HALF_POWER: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// The magnitude ratio of exactly −3 dB, 10^(−3/20) = 0.70795: the level of a predicted response's
/// bandwidth (`mrbrake_design::response`, whose points are normalised by their DC gain). 0.1 %
/// above [`HALF_POWER`]; kept as each result was defined (results unchanged).
pub const MINUS_3_DB: f64 = 0.707_945_784_384_137_9;

/// G(jω) at one angular frequency.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrequencyPoint {
    /// Angular frequency, rad/s.
    pub omega_rad_s: f64,
    /// The complex response G(jω).
    pub response: Complex64,
    /// Whole turns (360° each) added to the principal phase of `response`, so that the phase is
    /// continuous along the data the point belongs to ([`unwrap_phase`]); 0 for a lone point.
    pub phase_turns: i32,
}

impl FrequencyPoint {
    /// G(jω) = `response` at `omega_rad_s`, phase on the principal branch.
    pub fn new(omega_rad_s: f64, response: Complex64) -> Self {
        Self { omega_rad_s, response, phase_turns: 0 }
    }

    /// 20·log10|G| (thesis (5.4)), dB.
    pub fn magnitude_db(&self) -> f64 {
        20.0 * self.response.norm().log10()
    }

    /// The phase of G in degrees: the principal value (−180°, 180°] plus the point's turns.
    pub fn phase_deg(&self) -> f64 {
        self.response.arg().to_degrees() + 360.0 * f64::from(self.phase_turns)
    }
}

/// A point in JSON: `{omega_rad_s, magnitude_dB, phase_deg, re, im}` (units in the names; the
/// phase on its branch), the keys of every frequency response `--json` prints.
impl Serialize for FrequencyPoint {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut s = serializer.serialize_struct("FrequencyPoint", 5)?;
        s.serialize_field("omega_rad_s", &self.omega_rad_s)?;
        s.serialize_field("magnitude_dB", &self.magnitude_db())?;
        s.serialize_field("phase_deg", &self.phase_deg())?;
        s.serialize_field("re", &self.response.re)?;
        s.serialize_field("im", &self.response.im)?;
        s.end()
    }
}

/// Sets each point's [`FrequencyPoint::phase_turns`] so that consecutive phases differ by less
/// than 180° (the first keeps its principal value): removes the ±360° jumps of the principal
/// phase along frequency.
pub fn unwrap_phase<'a>(points: impl IntoIterator<Item = &'a mut FrequencyPoint>) {
    let mut turns = 0_i32;
    let mut previous: Option<f64> = None;
    for p in points {
        let principal = p.response.arg().to_degrees();
        if let Some(before) = previous {
            turns -= ((principal - before) / 360.0).round() as i32;
        }
        p.phase_turns = turns;
        previous = Some(principal);
    }
}

/// Frequency-response data: points in strictly increasing frequency.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Frd {
    /// The points, frequency increasing, phases unwrapped along them.
    pub points: Vec<FrequencyPoint>,
    /// Optional per-point weights of the estimator ([`crate::tfest`]), one per point.
    pub weight: Option<Vec<f64>>,
}

impl Frd {
    /// The data of `points` (in increasing frequency), phases unwrapped along them, no weights.
    pub fn new(mut points: Vec<FrequencyPoint>) -> Self {
        unwrap_phase(&mut points);
        Self { points, weight: None }
    }

    /// `response(ω)` at each of `omegas_rad_s` (increasing): a model's frequency response, e.g.
    /// `Frd::sample(&omegas, |w| g.response(w))`.
    pub fn sample(omegas_rad_s: &[f64], mut response: impl FnMut(f64) -> Complex64) -> Self {
        Self::new(omegas_rad_s.iter().map(|&w| FrequencyPoint::new(w, response(w))).collect())
    }

    /// Moves every phase by the same whole turns so that the first point's phase lies within
    /// 180° of `phase_deg`: puts a model's curve on the branch of the data it is drawn with.
    pub fn align_phase(&mut self, phase_deg: f64) {
        let Some(first) = self.points.first() else { return };
        let turns = ((phase_deg - first.phase_deg()) / 360.0).round() as i32;
        self.points.iter_mut().for_each(|p| p.phase_turns += turns);
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// True without points.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// The frequencies, rad/s.
    pub fn omegas(&self) -> impl ExactSizeIterator<Item = f64> + '_ {
        self.points.iter().map(|p| p.omega_rad_s)
    }

    /// The responses G(jω).
    pub fn responses(&self) -> impl ExactSizeIterator<Item = Complex64> + '_ {
        self.points.iter().map(|p| p.response)
    }

    /// |G| at `omega_rad_s` inside the data's range, interpolated linearly in log ω – log |G|
    /// between the neighbouring points (a Bode plot's straight lines); `None` outside the range.
    pub fn magnitude_at(&self, omega_rad_s: f64) -> Option<f64> {
        // The first point at or above the frequency, and the one before it.
        let k = self.points.partition_point(|p| p.omega_rad_s < omega_rad_s);
        let b = self.points.get(k)?;
        if b.omega_rad_s <= omega_rad_s {
            return Some(b.response.norm());
        }
        let a = self.points.get(k.checked_sub(1)?)?;
        let s = (omega_rad_s.ln() - a.omega_rad_s.ln()) / (b.omega_rad_s.ln() - a.omega_rad_s.ln());
        let (ga, gb) = (a.response.norm().ln(), b.response.norm().ln());
        Some((ga + s * (gb - ga)).exp())
    }

    /// The −3 dB bandwidth of the data ([`bandwidth_rad_s`]): the first frequency at which the
    /// magnitude, log–log interpolated between the points ([`Frd::magnitude_at`]), falls to
    /// `level` (an absolute |G|, e.g. [`MINUS_3_DB`] for data normalised by its DC gain); the first
    /// point's frequency if it is already below, `None` if the data never fall that low.
    pub fn bandwidth_rad_s(&self, level: f64) -> Option<f64> {
        let samples = self.points.iter().map(|p| (p.omega_rad_s, p.response.norm()));
        bandwidth_rad_s(samples, |w| self.magnitude_at(w).unwrap_or(f64::NAN), level)
    }

    /// The data as FRD CSV text ([`write_csv`]), with a `weight` column when weighted.
    pub fn to_csv(&self) -> String {
        let weight: Vec<Column<'_>> =
            self.weight.iter().map(|w| ("weight", w.as_slice())).collect();
        write_csv(&self.points, &weight)
    }
}

/// The data in JSON: the list of its points ([`FrequencyPoint`]'s keys), each with its `weight`
/// when the data are weighted.
impl Serialize for Frd {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        #[derive(serde::Serialize)]
        struct Weighted<'a> {
            #[serde(flatten)]
            point: &'a FrequencyPoint,
            weight: f64,
        }
        let mut seq = serializer.serialize_seq(Some(self.points.len()))?;
        for (k, point) in self.points.iter().enumerate() {
            match &self.weight {
                Some(w) => seq.serialize_element(&Weighted { point, weight: w[k] })?,
                None => seq.serialize_element(point)?,
            }
        }
        seq.end()
    }
}

/// The one −3 dB bandwidth search: the first frequency at which a magnitude falls to `level`.
/// `samples` are `(ω, |G(jω)|)` in increasing ω (a model's on a fine grid, or the data's points);
/// at the first sample at or below `level` the crossing is bisected in log ω between it and the
/// sample before, on `magnitude` (the model itself, or the data's interpolation). Returns the
/// first sample's ω if it is already below, `None` if no sample is.
pub fn bandwidth_rad_s(
    samples: impl IntoIterator<Item = (f64, f64)>,
    magnitude: impl Fn(f64) -> f64,
    level: f64,
) -> Option<f64> {
    let mut before: Option<f64> = None;
    for (omega, g) in samples {
        if g <= level {
            let Some(lower) = before else { return Some(omega) };
            // Bisection in log ω: 100 halvings reach the rounding of log ω.
            let (mut a, mut b) = (lower.ln(), omega.ln());
            for _ in 0..100 {
                let m = 0.5 * (a + b);
                if magnitude(m.exp()) <= level {
                    b = m;
                } else {
                    a = m;
                }
            }
            return Some((0.5 * (a + b)).exp());
        }
        before = Some(omega);
    }
    None
}

/// One more column of an FRD CSV file: its header name and one value per point.
pub type Column<'a> = (&'a str, &'a [f64]);

/// The FRD CSV text of `points` (module docs): `omega_rad_s,magnitude_dB,phase_deg,re,im`, then
/// the `extra` columns (each with one value per point), numbers in Rust's shortest round-trip
/// form. The one writer of FRD files; [`read_frd`] reads them back.
pub fn write_csv<'a>(
    points: impl IntoIterator<Item = &'a FrequencyPoint>,
    extra: &[Column<'_>],
) -> String {
    let mut s = String::from("omega_rad_s,magnitude_dB,phase_deg,re,im");
    for (name, _) in extra {
        s.push(',');
        s.push_str(name);
    }
    s.push('\n');
    for (k, p) in points.into_iter().enumerate() {
        let (db, deg) = (p.magnitude_db(), p.phase_deg());
        s.push_str(&format!("{},{db},{deg},{},{}", p.omega_rad_s, p.response.re, p.response.im));
        for (_, values) in extra {
            s.push_str(&format!(",{}", values[k]));
        }
        s.push('\n');
    }
    s
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
    let text = mrbrake_error::read::text(path, mrbrake_error::read::MODEL)
        .map_err(|source| SysidError::Io { path: path.to_path_buf(), source })?;
    read_frd_from(path, &text, weight_col)
}

/// Which form of the response a header offers: `Ok(true)` polar (`magnitude_dB, phase_deg` only),
/// `Ok(false)` Cartesian (`re, im`), and whether it has both.
fn response_form(source: &Path, header: &[String]) -> Result<(bool, bool), SysidError> {
    let has = |n: &str| header.iter().any(|h| h == n);
    let cartesian = has("re") && has("im");
    let polar = has("magnitude_dB") && has("phase_deg");
    if !(cartesian || polar) {
        return Err(crate::log::file_error(source)(
            Some(1),
            format!(
                "needs columns omega_rad_s and either re, im or magnitude_dB, phase_deg (found: {})",
                header.join(", ")
            ),
        ));
    }
    Ok((!cartesian, cartesian && polar))
}

/// The weight column `name` (`cols[3]`), non-negative.
fn weights(source: &Path, name: &str, values: &[f64]) -> Result<Vec<f64>, SysidError> {
    if let Some(k) = values.iter().position(|v| *v < 0.0) {
        return Err(crate::log::file_error(source)(
            Some(k as u64 + 2),
            format!("weight column '{name}' must be non-negative"),
        ));
    }
    Ok(values.to_vec())
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
    let (polar, both) = response_form(source, &header)?;
    let mut names = vec![
        "omega_rad_s",
        if polar { "magnitude_dB" } else { "re" },
        if polar { "phase_deg" } else { "im" },
    ];
    names.extend(weight_col);
    let cols = read_columns_from(source, text.as_bytes(), &names)?;
    let omega = &cols[0];
    check_frequencies(omega).map_err(|(line, message)| file_err(Some(line), message))?;
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
    let weight = weight_col.map(|w| weights(source, w, &cols[3])).transpose()?;
    if omega.is_empty() {
        return Err(file_err(None, "no data rows".into()));
    }
    let points = omega.iter().zip(response).map(|(w, g)| FrequencyPoint::new(*w, g)).collect();
    Ok(Frd { weight, ..Frd::new(points) })
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
        assert!((a.points[0].response - Complex64::new(0.0, -1.0)).norm() < 1e-15);
        assert!((a.points[1].response - Complex64::new(-0.1, 0.0)).norm() < 1e-15);
        let cart = "omega_rad_s,re,im,w\n1,0,-1,1\n10,-0.1,0,2\n";
        let b = read_frd_from(Path::new("b.csv"), cart, Some("w")).unwrap();
        assert!((b.points[1].response - a.points[1].response).norm() < 1e-15);
        assert_eq!(b.weight.unwrap(), vec![1.0, 2.0]);
    }

    #[test]
    fn bad_frequency_names_line() {
        let err = read_frd_from(Path::new("f.csv"), "omega_rad_s,re,im\n1,1,0\n1,1,0\n", None)
            .unwrap_err()
            .to_string();
        assert!(err.contains("f.csv, line 3"), "{err}");
    }

    /// A phase that passes −180° continues below it (−185°, −200°) instead of jumping to +175°.
    #[test]
    fn unwrapping_removes_the_jumps_of_the_principal_phase() {
        let deg = [-170.0_f64, 175.0, 160.0];
        let frd = Frd::new(
            deg.iter()
                .enumerate()
                .map(|(k, d)| {
                    FrequencyPoint::new(k as f64 + 1.0, Complex64::from_polar(1.0, d.to_radians()))
                })
                .collect(),
        );
        let phase: Vec<f64> = frd.points.iter().map(FrequencyPoint::phase_deg).collect();
        assert!((phase[0] + 170.0).abs() < 1e-12, "{phase:?}");
        assert!((phase[1] + 185.0).abs() < 1e-12 && (phase[2] + 200.0).abs() < 1e-12, "{phase:?}");
    }

    /// The writer's file reads back to the same data, weights included, and the columns of the
    /// earlier predicted-response writer (re, im before the polar pair) still read.
    #[test]
    fn written_files_read_back_and_the_earlier_column_order_reads() {
        let g = |w: f64| Complex64::new(1.0, 0.0) / Complex64::new(1.0 - w * w / 1e4, w / 50.0);
        let mut frd = Frd::sample(&[1.0, 10.0, 100.0, 1000.0], g);
        frd.weight = Some(vec![1.0, 0.5, 2.0, 0.0]);
        let text = frd.to_csv();
        assert!(text.starts_with("omega_rad_s,magnitude_dB,phase_deg,re,im,weight\n"), "{text}");
        let back = read_frd_from(Path::new("w.csv"), &text, Some("weight")).unwrap();
        assert_eq!(back, frd);
        let earlier =
            "omega_rad_s,re,im,magnitude_dB,phase_deg\n1,0,-1,0,-90\n10,-0.1,0,-20,-180\n";
        let old = read_frd_from(Path::new("old.csv"), earlier, None).unwrap();
        assert!((old.points[1].response - Complex64::new(-0.1, 0.0)).norm() < 1e-15);
    }

    /// The data's bandwidth of a first-order lag sampled 20 a decade is its corner within the
    /// interpolation's error, and the search returns the first point when it is already below.
    #[test]
    fn bandwidth_of_data_interpolates_between_points() {
        let omegas: Vec<f64> = (0..=60).map(|k| 10f64.powf(k as f64 / 20.0)).collect();
        let frd =
            Frd::sample(&omegas, |w| Complex64::new(1.0, 0.0) / Complex64::new(1.0, w / 50.0));
        let bw = frd.bandwidth_rad_s(HALF_POWER).unwrap();
        assert!((bw / 50.0 - 1.0).abs() < 1e-3, "bandwidth {bw}");
        assert!(frd.bandwidth_rad_s(MINUS_3_DB).unwrap() < bw);
        assert!((frd.bandwidth_rad_s(2.0).unwrap() - 1.0).abs() < 1e-15);
        assert!(frd.bandwidth_rad_s(1e-9).is_none());
        assert!((MINUS_3_DB - 10f64.powf(-3.0 / 20.0)).abs() < 2e-16);
        // The interpolant passes through the points and is None outside them.
        assert!(
            (frd.magnitude_at(omegas[7]).unwrap() - frd.points[7].response.norm()).abs() < 1e-15
        );
        assert!(frd.magnitude_at(0.5).is_none() && frd.magnitude_at(2000.0).is_none());
    }

    #[test]
    fn points_serialise_with_the_keys_of_every_response() {
        let mut p = FrequencyPoint::new(2.0, Complex64::new(0.0, -0.5));
        p.phase_turns = -1;
        let v = serde_json::to_value(p).unwrap();
        assert!((v["magnitude_dB"].as_f64().unwrap() - 20.0 * 0.5f64.log10()).abs() < 1e-15);
        assert!((v["phase_deg"].as_f64().unwrap() + 450.0).abs() < 1e-12, "{v}");
        assert!((v["omega_rad_s"].as_f64().unwrap() - 2.0).abs() < 1e-15);
        assert!((v["im"].as_f64().unwrap() + 0.5).abs() < 1e-15);
    }
}
