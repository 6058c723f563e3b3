//! Field-dependent yield stress `τ_y` of an MR fluid, as a function of B or of H.
//!
//! An MR fluid in a field behaves as a Bingham plastic, `τ = τ_y(H) + η γ̇` (thesis eqs. 2.5, 3.3);
//! the brake torque integrates `τ_y` over the fluid surfaces (eqs. 3.5–3.9). A [`YieldStressCurve`]
//! holds `τ_y` of one field variable (B in T or H in A/m) as:
//! * a monotone C¹ interpolant of the data points (Steffen 1990, see [`crate::hermite`]), which passes
//!   through every point **by construction**;
//! * above the last point, a saturating exponential matched in value and slope,
//!   `τ(x) = τ_sat − (τ_sat − τ_n) · exp(−k (x − x_n))` with `k = τ'_n / (τ_sat − τ_n)`,
//!   so the curve stays C¹, increases monotonically and tends to the ceiling `τ_sat` without reaching
//!   it. The ceiling is a stated material property (e.g. the ~35 kPa the thesis gives for MRF-122EG,
//!   or the asymptote of Carlson's fit), not a fitted parameter.
//!
//! `τ_y` is even in the field (the sign of B does not matter), so negative arguments use `|x|`.

use crate::bh_curve::validate_increasing_from_origin;
use crate::hermite::{self, Piece, PiecewiseCubic};
use crate::{MaterialError, Provenance};

/// Minimum number of points of a yield-stress curve (the origin and two more).
pub const MIN_YIELD_POINTS: usize = 3;

/// The field variable a yield-stress table is given in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum FieldVariable {
    /// Flux density B in T (CSV header `B_T,tau_y_Pa`).
    FluxDensity,
    /// Field strength H in A/m (CSV header `H_A_per_m,tau_y_Pa`).
    FieldStrength,
}

impl FieldVariable {
    /// The CSV header of a table in this variable.
    pub fn header(self) -> [&'static str; 2] {
        match self {
            FieldVariable::FluxDensity => ["B_T", "tau_y_Pa"],
            FieldVariable::FieldStrength => ["H_A_per_m", "tau_y_Pa"],
        }
    }

    fn name_and_unit(self) -> (&'static str, &'static str) {
        match self {
            FieldVariable::FluxDensity => ("B", "T"),
            FieldVariable::FieldStrength => ("H", "A/m"),
        }
    }
}

/// Yield stress `τ_y` \[Pa\] of one field variable, monotone C¹, saturating above the data.
#[derive(Debug, Clone, PartialEq)]
pub struct YieldStressCurve {
    variable: FieldVariable,
    points: Vec<(f64, f64)>,
    curve: PiecewiseCubic,
    x_last: f64,
    tau_last: f64,
    /// Ceiling the tail tends to \[Pa\].
    tau_ceiling_pa: f64,
    /// Decay rate `k` of the tail \[1/unit of x\].
    tail_rate: f64,
    provenance: Provenance,
}

impl YieldStressCurve {
    /// Builds a curve from `(x, τ_y [Pa])` points starting at the origin; `tau_ceiling_pa` must exceed
    /// the last `τ_y`. Errors name the point (1-based) and the rule.
    pub fn from_points(
        points: &[(f64, f64)],
        variable: FieldVariable,
        tau_ceiling_pa: f64,
        provenance: Provenance,
    ) -> Result<Self, MaterialError> {
        let numbered: Vec<(u64, f64, f64)> =
            points.iter().enumerate().map(|(i, &(x, t))| (i as u64 + 1, x, t)).collect();
        Self::from_numbered(&numbered, "points", variable, tau_ceiling_pa, provenance)
    }

    /// Parses CSV text with the header of `variable` (`B_T,tau_y_Pa` or `H_A_per_m,tau_y_Pa`).
    pub fn from_csv_str(
        text: &str,
        file: &str,
        variable: FieldVariable,
        tau_ceiling_pa: f64,
        provenance: Provenance,
    ) -> Result<Self, MaterialError> {
        let rows = crate::table::read_xy(text, file, variable.header())?;
        Self::from_numbered(&rows, file, variable, tau_ceiling_pa, provenance)
    }

    fn from_numbered(
        rows: &[(u64, f64, f64)],
        file: &str,
        variable: FieldVariable,
        tau_ceiling_pa: f64,
        provenance: Provenance,
    ) -> Result<Self, MaterialError> {
        validate_increasing_from_origin(
            rows,
            file,
            variable.name_and_unit(),
            ("tau_y", "Pa"),
            MIN_YIELD_POINTS,
        )?;
        let x: Vec<f64> = rows.iter().map(|r| r.1).collect();
        let tau: Vec<f64> = rows.iter().map(|r| r.2).collect();
        let n = x.len();
        let (last_line, tau_last) = (rows[n - 1].0, tau[n - 1]);
        if !(tau_ceiling_pa.is_finite() && tau_ceiling_pa > tau_last) {
            return Err(MaterialError::InvalidCurve {
                file: file.to_string(),
                line: last_line,
                rule: format!(
                    "rule `ceiling above data`: the saturation ceiling {tau_ceiling_pa} Pa must be finite and \
                     exceed the last tau_y = {tau_last} Pa"
                ),
            });
        }
        let d = hermite::steffen_slopes(&x, &tau);
        let pieces: Vec<Piece> = (0..n - 1)
            .map(|k| {
                Piece::Cubic(hermite::hermite_cubic(
                    x[k],
                    x[k + 1],
                    tau[k],
                    tau[k + 1],
                    d[k],
                    d[k + 1],
                ))
            })
            .collect();
        let curve = PiecewiseCubic::from_pieces(&x, &pieces);
        Ok(Self {
            variable,
            points: rows.iter().map(|r| (r.1, r.2)).collect(),
            curve,
            x_last: x[n - 1],
            tau_last,
            tau_ceiling_pa,
            tail_rate: d[n - 1] / (tau_ceiling_pa - tau_last),
            provenance,
        })
    }

    /// `τ_y` \[Pa\] at field value `x` (T or A/m, see [`YieldStressCurve::variable`]); even in `x`.
    pub fn tau_y(&self, x: f64) -> f64 {
        self.tau_y_and_slope(x).0
    }

    /// `τ_y` \[Pa\] and `dτ_y/dx` at `|x|`.
    pub fn tau_y_and_slope(&self, x: f64) -> (f64, f64) {
        let x = x.abs();
        if x >= self.x_last {
            let gap =
                (self.tau_ceiling_pa - self.tau_last) * (-self.tail_rate * (x - self.x_last)).exp();
            (self.tau_ceiling_pa - gap, self.tail_rate * gap)
        } else {
            self.curve.value_and_slope(x)
        }
    }

    /// The field variable of the table.
    pub fn variable(&self) -> FieldVariable {
        self.variable
    }

    /// The data points `(x, τ_y [Pa])`, starting at the origin.
    pub fn points(&self) -> &[(f64, f64)] {
        &self.points
    }

    /// The ceiling \[Pa\] the curve tends to above the data.
    pub fn ceiling_pa(&self) -> f64 {
        self.tau_ceiling_pa
    }

    /// The last data point `(x, τ_y)`, where the saturating tail starts.
    pub fn last_point(&self) -> (f64, f64) {
        (self.x_last, self.tau_last)
    }

    /// Where the curve comes from and how it was built.
    pub fn provenance(&self) -> &Provenance {
        &self.provenance
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Trust;

    fn curve() -> YieldStressCurve {
        YieldStressCurve::from_points(
            &[(0.0, 0.0), (0.1, 3000.0), (0.3, 12000.0), (0.5, 25000.0)],
            FieldVariable::FluxDensity,
            35000.0,
            Provenance::new("test", "test", Trust::User),
        )
        .unwrap()
    }

    #[test]
    fn tail_is_c1_monotone_and_below_the_ceiling() {
        let c = curve();
        let (below, slope_below) = c.tau_y_and_slope(0.5 - 1e-9);
        let (at, slope_at) = c.tau_y_and_slope(0.5);
        assert!((below - at).abs() < 1e-3);
        assert!((slope_below - slope_at).abs() < 1e-3 * slope_at);
        let mut prev = at;
        for i in 1..200 {
            let tau = c.tau_y(0.5 + 0.05 * f64::from(i));
            assert!(tau >= prev && tau <= 35000.0);
            prev = tau;
        }
        assert!(35000.0 - c.tau_y(10.0) < 1.0);
    }

    #[test]
    fn ceiling_below_the_data_is_rejected() {
        let err = YieldStressCurve::from_points(
            &[(0.0, 0.0), (0.1, 3000.0), (0.3, 12000.0)],
            FieldVariable::FluxDensity,
            10000.0,
            Provenance::new("test", "test", Trust::User),
        )
        .unwrap_err();
        assert!(err.to_string().contains("ceiling"), "{err}");
        assert!(err.to_string().starts_with("points:3:"), "{err}");
    }

    #[test]
    fn even_in_the_field() {
        let c = curve();
        assert!((c.tau_y(-0.2) - c.tau_y(0.2)).abs() < 1e-9);
    }
}
