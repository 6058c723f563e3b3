//! Non-linear B-H curves and the reluctivity `ν(B²)` a Newton magnetostatic solver needs.
//!
//! # Representation (why H as a function of B)
//! The curve is stored as a monotone C¹ piecewise cubic **H(B)** (see [`crate::hermite`]), built once
//! from the data points:
//! * the interpolant passes through every data point exactly (it is a Hermite interpolant);
//! * knot slopes follow Steffen (1990), so every piece is monotone and `dH/dB > 0` everywhere;
//! * the **first piece is odd**, `H = a1 B + a3 B³` (no constant, no `B²` term). The material is
//!   isotropic and free of hysteresis in this model, so `H(−B) = −H(B)`: an odd curve continued
//!   through the origin is C² there. It also makes the reluctivity a polynomial in `B²` on the first
//!   piece, `ν = H/B = a1 + a3 B²`, so `ν(0) = a1 = dH/dB(0)` (the initial slope) and
//!   `dν/dB² = a3` are finite at `B = 0`. (A `B²` term would make `dν/dB²` blow up like `B^{-1}`.)
//!   With `a1 = (3 s0 − d1)/2`, `a3 = (d1 − s0)/(2 B1²)` the piece matches `H1` and the Steffen slope
//!   `d1 ≤ 2 s0` at the first data point, so `a1 ≥ s0/2 > 0`;
//! * beyond the last point the curve is the straight line of slope `dB/dH = μ0` (the material is
//!   saturated: `B = μ0 (H + M_s)`), and the interpolant's slope at the last data point is set to
//!   `dH/dB = 1/μ0`, so the derivative is continuous there. If a cubic cannot take that slope and stay
//!   monotone, the last interval is split into two quadratics (Schumaker 1983).
//!
//! The Newton solver evaluates `ν(B²)` and `dν/dB²` about a million times per iteration. With `H(B)`
//! stored as a cubic, each call is one binary search over a few dozen knots, one square root and one
//! polynomial — no root finding. `B(H)` (not needed by the solver) inverts the cubic by safeguarded
//! Newton. Tabulating `ν(B²)` on a fine grid would be faster still but no longer exact at the data.
//!
//! # Reluctivity
//! `ν(B²) = H(B)/B` and, by the chain rule, `dν/dB² = (dν/dB)/(2B) = (B H'(B) − H(B)) / (2 B³)`.
//! The Newton Jacobian of the magnetostatic problem contains `ν + 2 B² dν/dB² = dH/dB`, which is
//! positive everywhere by construction ([`BhCurve::dh_db`]).

use std::path::Path;

use crate::hermite::{self, Piece, PiecewiseCubic};
use crate::{MU_0, MaterialError, Provenance};

/// Minimum number of points in a B-H curve (the origin and three more).
pub const MIN_BH_POINTS: usize = 4;

/// The CSV header of a B-H file.
pub const BH_HEADER: [&str; 2] = ["H_A_per_m", "B_T"];

/// A validated, non-linear, single-valued B-H curve (H in A/m, B in T) with provenance.
#[derive(Debug, Clone, PartialEq)]
pub struct BhCurve {
    /// The data points `(H, B)`, starting at the origin.
    points: Vec<(f64, f64)>,
    /// `H(B)` on `[0, B_last]`.
    h_of_b: PiecewiseCubic,
    /// `a1` of the odd first piece: `dH/dB` at the origin, in A/(m·T).
    nu_initial: f64,
    /// `a3` of the odd first piece: `dν/dB²` on the first piece.
    dnu_db2_first: f64,
    /// `B1²`: the first piece covers `B² ≤ b2_first`.
    b2_first: f64,
    /// Last data point.
    h_last: f64,
    b_last: f64,
    b2_last: f64,
    provenance: Provenance,
}

impl BhCurve {
    /// Builds a curve from `(H [A/m], B [T])` points. Errors name the point (1-based) and the rule.
    pub fn from_points(
        points: &[(f64, f64)],
        provenance: Provenance,
    ) -> Result<Self, MaterialError> {
        let numbered: Vec<(u64, f64, f64)> =
            points.iter().enumerate().map(|(i, &(h, b))| (i as u64 + 1, h, b)).collect();
        Self::from_numbered(&numbered, "points", provenance)
    }

    /// Parses CSV text (header `H_A_per_m,B_T`); `file` names the source in error messages.
    pub fn from_csv_str(
        text: &str,
        file: &str,
        provenance: Provenance,
    ) -> Result<Self, MaterialError> {
        let rows = crate::table::read_xy(text, file, BH_HEADER)?;
        Self::from_numbered(&rows, file, provenance)
    }

    /// Reads and validates a user CSV file (header `H_A_per_m,B_T`); its provenance is the path.
    pub fn from_csv_file(path: &Path) -> Result<Self, MaterialError> {
        let file = path.display().to_string();
        let text = mrbrake_error::read::text(path, mrbrake_error::read::MODEL)
            .map_err(|source| MaterialError::io(&file, source))?;
        Self::from_csv_str(&text, &file, Provenance::user_file(&file))
    }

    fn from_numbered(
        rows: &[(u64, f64, f64)],
        file: &str,
        provenance: Provenance,
    ) -> Result<Self, MaterialError> {
        validate_increasing_from_origin(rows, file, ("H", "A/m"), ("B", "T"), MIN_BH_POINTS)?;
        let h: Vec<f64> = rows.iter().map(|r| r.1).collect();
        let b: Vec<f64> = rows.iter().map(|r| r.2).collect();
        let n = b.len();
        // H as a function of B: x = B, y = H.
        let s = hermite::secants(&b, &h);
        let mut d = hermite::steffen_slopes(&b, &h);
        d[n - 1] = 1.0 / MU_0;
        // The last interval must reach slope 1/μ0 monotonically; if the cubic cannot, the Schumaker
        // split needs d_{n-2} < 2·secant. Lowering d_{n-2} keeps the neighbouring piece monotone
        // (its normalised slope only decreases within [0, 2]).
        let last_secant = s[n - 2];
        let (b0, b_end, h0, h_end) = (b[n - 2], b[n - 1], h[n - 2], h[n - 1]);
        let cubic = hermite::hermite_cubic(b0, b_end, h0, h_end, d[n - 2], d[n - 1]);
        if hermite::min_slope(&cubic, b_end - b0) <= hermite::MIN_SLOPE_FRACTION * last_secant {
            // The cubic cannot reach 1/μ0 monotonically: cap the left slope so that the Schumaker
            // split keeps a slope of at least secant/4 at its inner knot.
            d[n - 2] = d[n - 2].min(1.5 * last_secant);
        }
        let last_piece = hermite::monotone_piece(b0, b_end, h0, h_end, d[n - 2], d[n - 1]).expect(
            "a left slope <= 1.5 secant and positive slopes always admit a Schumaker split",
        );
        // First piece: odd cubic H = a1 B + a3 B³ through (B1, H1) with slope d1 at B1.
        let (b1, d1, s0) = (b[1], d[1], s[0]);
        let a1 = 0.5 * (3.0 * s0 - d1);
        let a3 = (d1 - s0) / (2.0 * b1 * b1);
        let mut pieces = Vec::with_capacity(n - 1);
        pieces.push(Piece::Cubic([0.0, a1, 0.0, a3]));
        for k in 1..n - 2 {
            pieces.push(Piece::Cubic(hermite::hermite_cubic(
                b[k],
                b[k + 1],
                h[k],
                h[k + 1],
                d[k],
                d[k + 1],
            )));
        }
        pieces.push(last_piece);
        let h_of_b = PiecewiseCubic::from_pieces(&b, &pieces);
        Ok(Self {
            points: rows.iter().map(|r| (r.1, r.2)).collect(),
            h_of_b,
            nu_initial: a1,
            dnu_db2_first: a3,
            b2_first: b1 * b1,
            h_last: h[n - 1],
            b_last: b[n - 1],
            b2_last: b[n - 1] * b[n - 1],
            provenance,
        })
    }

    /// The data points `(H [A/m], B [T])`, starting at the origin.
    pub fn points(&self) -> &[(f64, f64)] {
        &self.points
    }

    /// Where the curve comes from and how far to trust it.
    pub fn provenance(&self) -> &Provenance {
        &self.provenance
    }

    /// The last data point `(H, B)`; beyond it the curve continues with slope `dB/dH = μ0`.
    pub fn last_point(&self) -> (f64, f64) {
        (self.h_last, self.b_last)
    }

    /// Field strength H \[A/m\] at flux density `b` \[T\]. Odd: `h_of_b(−b) = −h_of_b(b)`.
    pub fn h_of_b(&self, b: f64) -> f64 {
        let magnitude = b.abs();
        let h = if magnitude >= self.b_last {
            self.h_last + (magnitude - self.b_last) / MU_0
        } else {
            self.h_of_b.value(magnitude)
        };
        h.copysign(b)
    }

    /// Flux density B \[T\] at field strength `h` \[A/m\]: the inverse of [`BhCurve::h_of_b`]. Odd.
    pub fn b_of_h(&self, h: f64) -> f64 {
        let magnitude = h.abs();
        let b = if magnitude >= self.h_last {
            self.b_last + MU_0 * (magnitude - self.h_last)
        } else {
            self.h_of_b.inverse(magnitude)
        };
        b.copysign(h)
    }

    /// Differential reluctivity `dH/dB` \[A/(m·T)\] at flux density `b` \[T\]: positive everywhere. This is
    /// the Newton Jacobian coefficient `ν + 2 B² dν/dB²`.
    pub fn dh_db(&self, b: f64) -> f64 {
        let magnitude = b.abs();
        if magnitude >= self.b_last { 1.0 / MU_0 } else { self.h_of_b.value_and_slope(magnitude).1 }
    }

    /// Reluctivity `ν = H/B` \[m/H\] as a function of `b2 = B²` \[T²\]. At `B = 0` it is the initial slope
    /// `dH/dB(0)`. Negative `b2` is treated as 0; NaN gives NaN.
    #[inline]
    pub fn nu_of_b2(&self, b2: f64) -> f64 {
        self.nu_and_dnu_db2(b2).0
    }

    /// `dν/dB²` \[m/(H·T²)\] at `b2 = B²`, the exact derivative of [`BhCurve::nu_of_b2`]:
    /// `(B H'(B) − H(B)) / (2 B³)`, or the constant `a3` on the first (odd) piece.
    #[inline]
    pub fn dnu_db2(&self, b2: f64) -> f64 {
        self.nu_and_dnu_db2(b2).1
    }

    /// `ν(B²)` and `dν/dB²` together, with one piece lookup (what an assembly loop should call).
    #[inline]
    pub fn nu_and_dnu_db2(&self, b2: f64) -> (f64, f64) {
        if b2.is_nan() {
            return (f64::NAN, f64::NAN);
        }
        let b2 = b2.max(0.0);
        if b2 <= self.b2_first {
            // Odd first piece: ν = a1 + a3 B², exact polynomial in B² (no division near 0).
            return (self.nu_initial + self.dnu_db2_first * b2, self.dnu_db2_first);
        }
        let b = b2.sqrt();
        if b2 >= self.b2_last {
            // H = H_n + (B − B_n)/μ0, so B H' − H = B_n/μ0 − H_n.
            let h = self.h_last + (b - self.b_last) / MU_0;
            return (h / b, (self.b_last / MU_0 - self.h_last) / (2.0 * b * b2));
        }
        let (h, dh) = self.h_of_b.value_and_slope(b);
        (h / b, (b * dh - h) / (2.0 * b * b2))
    }

    /// Initial relative permeability `μr = 1/(μ0 · dH/dB(0))`.
    pub fn initial_relative_permeability(&self) -> f64 {
        1.0 / (MU_0 * self.nu_initial)
    }

    /// The polynomial pieces of `H(B)`: knots and coefficients (for plots and tests).
    pub fn pieces(&self) -> (&[f64], &[[f64; 4]]) {
        (self.h_of_b.knots(), self.h_of_b.coefficients())
    }
}

/// Shared validation of a curve given as numbered `(line, x, y)` rows: every value finite, the first
/// point at the origin, x and y strictly increasing, at least `min_points` points.
pub(crate) fn validate_increasing_from_origin(
    rows: &[(u64, f64, f64)],
    file: &str,
    (x_name, x_unit): (&str, &str),
    (y_name, y_unit): (&str, &str),
    min_points: usize,
) -> Result<(), MaterialError> {
    let fail = |line: u64, rule: String| {
        Err(MaterialError::InvalidCurve { file: file.to_string(), line, rule })
    };
    for &(line, x, y) in rows {
        if !x.is_finite() || !y.is_finite() {
            return fail(
                line,
                format!(
                    "rule `finite`: {x_name} = {x}, {y_name} = {y}; every value must be a finite number"
                ),
            );
        }
    }
    match rows.first() {
        None => {
            return fail(
                1,
                format!("rule `enough points`: no data points; at least {min_points} are needed"),
            );
        }
        Some(&(line, x, y)) => {
            if x.abs() > 0.0 || y.abs() > 0.0 {
                return fail(
                    line,
                    format!(
                        "rule `starts at origin`: the first point must be {x_name} = 0, {y_name} = 0, \
                         found {x_name} = {x} {x_unit}, {y_name} = {y} {y_unit}"
                    ),
                );
            }
        }
    }
    for pair in rows.windows(2) {
        let (prev_line, px, py) = pair[0];
        let (line, x, y) = pair[1];
        for (name, unit, value, previous) in [(x_name, x_unit, x, px), (y_name, y_unit, y, py)] {
            if value <= previous {
                return fail(
                    line,
                    format!(
                        "rule `strictly increasing {name}`: {name} = {value} {unit} must exceed the \
                         previous {name} = {previous} {unit} (line {prev_line})"
                    ),
                );
            }
        }
    }
    if rows.len() < min_points {
        let line = rows.last().map(|r| r.0).unwrap_or(1);
        return fail(
            line,
            format!(
                "rule `enough points`: {} points found, at least {min_points} are needed (the origin and {} more)",
                rows.len(),
                min_points - 1
            ),
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Trust;

    fn curve(points: &[(f64, f64)]) -> BhCurve {
        BhCurve::from_points(points, Provenance::new("test", "test", Trust::User)).unwrap()
    }

    #[test]
    fn odd_first_piece_gives_finite_nu_and_dnu_at_zero() {
        let c = curve(&[(0.0, 0.0), (100.0, 0.5), (300.0, 1.0), (2000.0, 1.5), (20000.0, 1.8)]);
        let (nu0, dnu0) = c.nu_and_dnu_db2(0.0);
        assert!(nu0.is_finite() && nu0 > 0.0);
        assert!(dnu0.is_finite());
        // ν(0) is the initial slope dH/dB.
        assert!((nu0 - c.dh_db(0.0)).abs() < 1e-9 * nu0);
    }

    #[test]
    fn extrapolates_with_mu0_beyond_the_last_point() {
        let c = curve(&[(0.0, 0.0), (100.0, 0.5), (300.0, 1.0), (2000.0, 1.5), (20000.0, 1.8)]);
        let b1 = c.b_of_h(1e5);
        let b2 = c.b_of_h(2e5);
        assert!(((b2 - b1) / 1e5 / MU_0 - 1.0).abs() < 1e-12);
        assert!((c.dh_db(1.8 - 1e-9) * MU_0 - 1.0).abs() < 1e-5);
    }
}
