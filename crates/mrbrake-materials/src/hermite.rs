//! Monotone piecewise cubic Hermite interpolation with a continuous first derivative (C¹).
//!
//! A [`PiecewiseCubic`] stores, on each piece `[x_k, x_{k+1}]`, the polynomial
//! `y = c0 + c1 t + c2 t² + c3 t³` with `t = x − x_k`. The pieces are built from the data values and
//! one slope per knot (cubic Hermite form), so the curve passes through every data point exactly and
//! its derivative is continuous at every knot.
//!
//! Knot slopes follow **M. Steffen, "A simple method for monotonic interpolation in one dimension",
//! Astron. Astrophys. 239 (1990) 443–450**: eq. (11) at interior knots,
//! `y'_i = (sign s_{i−1} + sign s_i) · min(|s_{i−1}|, |s_i|, ½|p_i|)` with the secants `s` and the
//! parabola slope `p_i = (s_{i−1} h_i + s_i h_{i−1}) / (h_{i−1} + h_i)`, and eqs. (26)–(27) at the ends.
//! Steffen proves that these slopes make every piece monotone: in the notation of
//! **F. N. Fritsch and R. E. Carlson, "Monotone piecewise cubic interpolation", SIAM J. Numer. Anal.
//! 17 (1980) 238–246**, the normalised end slopes `α = y'_i/s_i`, `β = y'_{i+1}/s_i` stay in `[0, 2]`,
//! inside the Fritsch–Carlson monotonicity region (which contains the square `[0, 3]²`).
//!
//! When a caller imposes an end slope outside that region (the `μ0` slope at the end of a B-H curve),
//! a single cubic can overshoot; [`monotone_piece`] then splits the interval into two quadratics with
//! one extra knot, after **L. L. Schumaker, "On shape preserving quadratic spline interpolation",
//! SIAM J. Numer. Anal. 20 (1983) 854–864** (Lemma 2.3), which is monotone for any positive end slopes
//! as long as the left slope is below twice the secant.

/// A piecewise cubic polynomial on increasing knots.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct PiecewiseCubic {
    /// Piece boundaries `x_0 < x_1 < … < x_m`.
    knots: Vec<f64>,
    /// Values at the knots (used to locate a piece when inverting).
    values: Vec<f64>,
    /// Coefficients `[c0, c1, c2, c3]` of each of the `m` pieces, in `t = x − x_k`.
    coeffs: Vec<[f64; 4]>,
    /// Piece-location accelerator: `x_0 + i·cell` lies in piece `cell_start[i]` (uniform cells).
    cell_start: Vec<u32>,
    /// `1/cell` of the uniform cells over `[x_0, x_m]`.
    inverse_cell: f64,
}

/// Coefficients of one or two polynomial pieces covering one data interval.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Piece {
    /// One cubic on the whole interval.
    Cubic([f64; 4]),
    /// Two quadratics split at the interior knot `x_split` (Schumaker).
    Split { x_split: f64, left: [f64; 4], right: [f64; 4] },
}

impl PiecewiseCubic {
    /// Assembles a curve from the data knots `x` and one [`Piece`] per interval.
    pub fn from_pieces(x: &[f64], pieces: &[Piece]) -> Self {
        let mut knots = Vec::with_capacity(x.len() + 2);
        let mut coeffs = Vec::with_capacity(pieces.len() + 2);
        for (k, piece) in pieces.iter().enumerate() {
            knots.push(x[k]);
            match *piece {
                Piece::Cubic(c) => coeffs.push(c),
                Piece::Split { x_split, left, right } => {
                    coeffs.push(left);
                    knots.push(x_split);
                    coeffs.push(right);
                }
            }
        }
        if let Some(&last) = x.last() {
            knots.push(last);
        }
        let mut values: Vec<f64> = coeffs.iter().map(|c| c[0]).collect();
        if let (Some(c), Some(w)) = (coeffs.last(), knots.windows(2).last()) {
            values.push(eval_poly(c, w[1] - w[0]));
        }
        let (cell_start, inverse_cell) = build_cells(&knots);
        Self { knots, values, coeffs, cell_start, inverse_cell }
    }

    /// The piece boundaries (data knots plus any split knots).
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// The coefficients of every piece.
    pub fn coefficients(&self) -> &[[f64; 4]] {
        &self.coeffs
    }

    /// Index of the piece holding `x`, clamped to the first/last piece outside the knot range.
    ///
    /// O(1): a uniform cell table gives the piece at the cell's start, then a short forward scan
    /// (cells are several times narrower than the average piece). This replaces a binary search whose
    /// unpredictable branches dominated the cost of `ν(B²)`.
    #[inline]
    pub fn piece_index(&self, x: f64) -> usize {
        let last_piece = self.coeffs.len() - 1;
        let offset = (x - self.knots[0]) * self.inverse_cell;
        if offset.is_nan() || offset < 0.0 {
            return 0; // below the first knot (or NaN)
        }
        // Truncation is the floor for offset >= 0; `as` saturates for huge values.
        let cell = (offset as usize).min(self.cell_start.len() - 1);
        let mut k = self.cell_start[cell] as usize;
        while k < last_piece && self.knots[k + 1] <= x {
            k += 1;
        }
        k
    }

    /// Value and first derivative at `x` (the end pieces are continued as polynomials outside).
    #[inline]
    pub fn value_and_slope(&self, x: f64) -> (f64, f64) {
        let k = self.piece_index(x);
        let c = &self.coeffs[k];
        let t = x - self.knots[k];
        let value = c[0] + t * (c[1] + t * (c[2] + t * c[3]));
        let slope = c[1] + t * (2.0 * c[2] + t * 3.0 * c[3]);
        (value, slope)
    }

    /// Value at `x`.
    #[inline]
    pub fn value(&self, x: f64) -> f64 {
        self.value_and_slope(x).0
    }

    /// The `x` in `[x_0, x_m]` where the (increasing) curve takes the value `y`; `y` must lie within the
    /// values at the first and last knots (callers handle the outside). Safeguarded Newton on the
    /// monotone piece, converged to a relative tolerance of a few ulps.
    pub fn inverse(&self, y: f64) -> f64 {
        let above = self.values.partition_point(|&v| v <= y);
        let k = above.saturating_sub(1).min(self.coeffs.len() - 1);
        let c = &self.coeffs[k];
        let width = self.knots[k + 1] - self.knots[k];
        let target = y - c[0];
        // Bracket [lo, hi] in t; the piece is increasing, so f(t) = p(t) − y changes sign once.
        let (mut lo, mut hi) = (0.0_f64, width);
        let span = self.values[k + 1] - self.values[k];
        let mut t = if span > 0.0 { (target / span * width).clamp(0.0, width) } else { 0.0 };
        for _ in 0..100 {
            let f = t * (c[1] + t * (c[2] + t * c[3])) - target;
            if f == 0.0 {
                break;
            }
            if f > 0.0 {
                hi = t;
            } else {
                lo = t;
            }
            let df = c[1] + t * (2.0 * c[2] + t * 3.0 * c[3]);
            let newton = if df > 0.0 { t - f / df } else { f64::NAN };
            let next = if newton >= lo && newton <= hi { newton } else { 0.5 * (lo + hi) };
            if (next - t).abs() <= 4.0 * f64::EPSILON * width.max(t.abs())
                || hi - lo <= f64::EPSILON * width
            {
                t = next;
                break;
            }
            t = next;
        }
        self.knots[k] + t
    }
}

/// The uniform cell table of [`PiecewiseCubic::piece_index`]: 8 cells per piece (64 to 4096 cells).
fn build_cells(knots: &[f64]) -> (Vec<u32>, f64) {
    let pieces = knots.len().saturating_sub(1).max(1);
    let cells = (8 * pieces).clamp(64, 4096);
    let span = knots[knots.len() - 1] - knots[0];
    let inverse_cell = if span > 0.0 { cells as f64 / span } else { 0.0 };
    let cell_start = (0..cells)
        .map(|i| {
            // Start a hair before the cell so that rounding of the cell index at run time can never
            // skip a piece (the forward scan moves on from here).
            let x = knots[0] + i as f64 / inverse_cell.max(f64::MIN_POSITIVE) - 1e-9 * span;
            let above = knots.partition_point(|&k| k <= x);
            above.saturating_sub(1).min(pieces - 1) as u32
        })
        .collect();
    (cell_start, inverse_cell)
}

/// `c0 + c1 t + c2 t² + c3 t³`.
#[inline]
pub(crate) fn eval_poly(c: &[f64; 4], t: f64) -> f64 {
    c[0] + t * (c[1] + t * (c[2] + t * c[3]))
}

/// Secant slopes `s_i = (y_{i+1} − y_i)/(x_{i+1} − x_i)`.
pub(crate) fn secants(x: &[f64], y: &[f64]) -> Vec<f64> {
    x.windows(2).zip(y.windows(2)).map(|(xw, yw)| (yw[1] - yw[0]) / (xw[1] - xw[0])).collect()
}

/// Steffen (1990) knot slopes: eq. (11) inside, eqs. (26)–(27) at both ends. Needs at least 3 points.
pub(crate) fn steffen_slopes(x: &[f64], y: &[f64]) -> Vec<f64> {
    let n = x.len();
    let h: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
    let s = secants(x, y);
    let mut d = vec![0.0; n];
    for i in 1..n - 1 {
        let p = (s[i - 1] * h[i] + s[i] * h[i - 1]) / (h[i - 1] + h[i]);
        d[i] =
            (s[i - 1].signum() + s[i].signum()) * s[i - 1].abs().min(s[i].abs()).min(0.5 * p.abs());
        if s[i - 1] * s[i] <= 0.0 {
            d[i] = 0.0;
        }
    }
    // Eq. (26)–(27): a parabola through the first (last) three points, limited to keep monotonicity.
    let end_slope = |s_near: f64, s_far: f64, h_near: f64, h_far: f64| {
        let p = s_near * (1.0 + h_near / (h_near + h_far)) - s_far * h_near / (h_near + h_far);
        if p * s_near <= 0.0 {
            0.0
        } else if p.abs() > 2.0 * s_near.abs() {
            2.0 * s_near
        } else {
            p
        }
    };
    d[0] = end_slope(s[0], s[1], h[0], h[1]);
    d[n - 1] = end_slope(s[n - 2], s[n - 3], h[n - 2], h[n - 3]);
    d
}

/// The cubic Hermite piece on `[x0, x1]` with values `y0, y1` and end slopes `d0, d1`.
pub(crate) fn hermite_cubic(x0: f64, x1: f64, y0: f64, y1: f64, d0: f64, d1: f64) -> [f64; 4] {
    let h = x1 - x0;
    let secant = (y1 - y0) / h;
    [y0, d0, (3.0 * secant - 2.0 * d0 - d1) / h, (d0 + d1 - 2.0 * secant) / (h * h)]
}

/// Smallest derivative of the polynomial `c` over `t ∈ [0, width]` (the derivative is a quadratic).
pub(crate) fn min_slope(c: &[f64; 4], width: f64) -> f64 {
    let slope = |t: f64| c[1] + t * (2.0 * c[2] + t * 3.0 * c[3]);
    let mut lowest = slope(0.0).min(slope(width));
    if c[3].abs() > 0.0 {
        let vertex = -c[2] / (3.0 * c[3]);
        if vertex > 0.0 && vertex < width {
            lowest = lowest.min(slope(vertex));
        }
    }
    lowest
}

/// A cubic piece is accepted when its smallest slope exceeds this fraction of its secant; the margin
/// keeps the derivative clearly positive (the inverse and the Newton Jacobian rely on it).
pub(crate) const MIN_SLOPE_FRACTION: f64 = 1e-6;

/// A strictly increasing C¹ piece on `[x0, x1]` matching values and the end slopes `d0, d1 > 0`.
///
/// The cubic Hermite piece is used when its derivative stays positive (the interior of the
/// Fritsch–Carlson region). Otherwise the interval is split into two quadratics (Schumaker 1983,
/// Lemma 2.3): with the split at `x0 + λh`, the slope there is `m = 2Δ − λ d0 − (1 − λ) d1` (so that the
/// integral of the slope equals the rise), and `λ` is chosen halfway inside the range where `m > 0`.
/// This requires `d0 < 2Δ`; the caller guarantees it (returns `None` otherwise).
pub(crate) fn monotone_piece(
    x0: f64,
    x1: f64,
    y0: f64,
    y1: f64,
    d0: f64,
    d1: f64,
) -> Option<Piece> {
    let h = x1 - x0;
    let cubic = hermite_cubic(x0, x1, y0, y1, d0, d1);
    let secant = (y1 - y0) / h;
    if min_slope(&cubic, h) > MIN_SLOPE_FRACTION * secant {
        return Some(Piece::Cubic(cubic));
    }
    if d0 >= 2.0 * secant || d0 <= 0.0 || d1 <= 0.0 {
        return None;
    }
    let lambda = if d1 < 2.0 * secant {
        0.5
    } else {
        // m(λ) is increasing in λ and vanishes at λ0; take the middle of (λ0, 1).
        let lambda0 = (d1 - 2.0 * secant) / (d1 - d0);
        0.5 * (lambda0 + 1.0)
    };
    // Widths from the rounded split knot, so that evaluation (t = x − knot) matches construction.
    let x_split = x0 + lambda * h;
    let left_width = x_split - x0;
    let right_width = x1 - x_split;
    let total = left_width + right_width;
    let m = 2.0 * (y1 - y0) / total - (left_width * d0 + right_width * d1) / total;
    let y_split = y0 + left_width * (d0 + m) / 2.0;
    Some(Piece::Split {
        x_split,
        left: [y0, d0, (m - d0) / (2.0 * left_width), 0.0],
        right: [y_split, m, (d1 - m) / (2.0 * right_width), 0.0],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hermite_cubic_matches_values_and_slopes() {
        let c = hermite_cubic(1.0, 3.0, 2.0, 5.0, 0.5, 4.0);
        assert!((eval_poly(&c, 0.0) - 2.0).abs() < 1e-14);
        assert!((eval_poly(&c, 2.0) - 5.0).abs() < 1e-14);
        assert!((c[1] - 0.5).abs() < 1e-14);
        let slope_end = c[1] + 2.0 * 2.0 * c[2] + 3.0 * 4.0 * c[3];
        assert!((slope_end - 4.0).abs() < 1e-13);
    }

    #[test]
    fn schumaker_split_is_c1_monotone_and_exact_for_a_steep_end_slope() {
        // Secant 1, end slope 20: far outside the Fritsch–Carlson region, a cubic would overshoot.
        let piece = monotone_piece(0.0, 1.0, 0.0, 1.0, 0.8, 20.0).unwrap();
        let Piece::Split { x_split, left, right } = piece else { panic!("expected a split") };
        let pc = PiecewiseCubic::from_pieces(&[0.0, 1.0], &[piece]);
        assert!(x_split > 0.0 && x_split < 1.0);
        // Continuity of value and slope at the split knot.
        let lw = x_split;
        assert!((eval_poly(&left, lw) - right[0]).abs() < 1e-14);
        assert!((left[1] + 2.0 * left[2] * lw - right[1]).abs() < 1e-12);
        assert!((pc.value(1.0) - 1.0).abs() < 1e-13);
        let (_, end_slope) = pc.value_and_slope(1.0);
        assert!((end_slope - 20.0).abs() < 1e-10);
        for i in 0..=1000 {
            let x = f64::from(i) / 1000.0;
            assert!(pc.value_and_slope(x).1 > 0.0, "slope not positive at {x}");
        }
    }

    #[test]
    fn piece_index_agrees_with_a_binary_search() {
        let x = [0.0, 0.001, 0.5, 0.5001, 1.2, 3.0, 3.0000001, 10.0];
        let y: Vec<f64> = x.iter().map(|v| v * 2.0).collect();
        let d = steffen_slopes(&x, &y);
        let pieces: Vec<Piece> = (0..x.len() - 1)
            .map(|k| Piece::Cubic(hermite_cubic(x[k], x[k + 1], y[k], y[k + 1], d[k], d[k + 1])))
            .collect();
        let pc = PiecewiseCubic::from_pieces(&x, &pieces);
        let mut probes: Vec<f64> =
            (0..=20_000).map(|i| -1.0 + 12.0 * f64::from(i) / 20_000.0).collect();
        for &k in &x {
            probes.extend([k, k - 1e-12, k + 1e-12, f64::from_bits(k.to_bits().saturating_sub(1))]);
        }
        for p in probes {
            let reference = x.partition_point(|&k| k <= p).saturating_sub(1).min(x.len() - 2);
            assert_eq!(pc.piece_index(p), reference, "x = {p}");
        }
        assert_eq!(pc.piece_index(f64::NAN), 0);
        assert_eq!(pc.piece_index(f64::INFINITY), x.len() - 2);
    }

    #[test]
    fn inverse_recovers_x() {
        let x = [0.0, 1.0, 2.5, 4.0];
        let y = [0.0, 2.0, 2.5, 7.0];
        let d = steffen_slopes(&x, &y);
        let pieces: Vec<Piece> = (0..3)
            .map(|k| Piece::Cubic(hermite_cubic(x[k], x[k + 1], y[k], y[k + 1], d[k], d[k + 1])))
            .collect();
        let pc = PiecewiseCubic::from_pieces(&x, &pieces);
        for i in 0..=400 {
            let xi = 4.0 * f64::from(i) / 400.0;
            let back = pc.inverse(pc.value(xi));
            assert!((back - xi).abs() < 1e-12, "x = {xi}, back = {back}");
        }
    }
}
