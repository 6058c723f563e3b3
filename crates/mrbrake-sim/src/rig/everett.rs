//! A tabulated Everett function: the Preisach model of a brake identified directly from
//! first-order reversal curves (FORCs), e.g. the design-predicted ones of
//! `mrbrake_design::forc`.
//!
//! **Identification** (Mayergoyz 1991, *Mathematical Models of Hysteresis*, Springer, §1.3, the
//! identification theorem). A FORC rises from the reference state (every relay off) to `α` and
//! falls to `β < α`; `f_α` is its top and `f_αβ` its value at `β`. In Mayergoyz's ±1 relays the
//! Everett function is `F(α, β) = ½ (f_α − f_αβ)` and the density `μ(α, β) = ½ ∂²f_αβ/∂α∂β`; with
//! the 0/1 relays of [`super::preisach`] the factor ½ drops:
//!
//! ```text
//! E(α, β) = T(α) − T(α, β),        μ(α, β) = ∂²T(α, β)/∂α∂β
//! ```
//!
//! and every state of the model follows from `E` at its turning points ([`super::preisach`]). On
//! the grid `α_a = a I_max/n` the table holds `E(α_a, α_b)` for `b ≤ a` (`E(α, α) = 0`), exact at
//! the FORCs' nodes; between nodes the model interpolates bilinearly (on the diagonal cells
//! linearly on the triangle below the diagonal, so that `E(u, u) = 0` everywhere).
//!
//! **The β = 0 row.** In a Preisach system a FORC that falls back to the lowest input returns to
//! the reference state (wiping-out, Mayergoyz's theorem 1.1): `T(α, 0) = T(0)`. A brake's field
//! solution or a rig only approximates it, and a model cannot be exact at every node if it does
//! not hold (the data exceed the model's unknowns by one per FORC). The table takes
//! `E(α_a, 0) = T(α_a) − T(0)`: the rising branch is exact and every FORC node with `β > 0`; at
//! `β = 0` the model gives `T(0)` for every FORC (the identification reports the largest
//! difference, [`Identified::wiping_out_defect_nm`]).
//!
//! **Non-negative density.** The cells' weights are the mixed second differences of the table,
//! `w(a, b) = E(a+1, b) − E(a, b) − E(a+1, b+1) + E(a, b+1)` (`b < a`) and, on the diagonal,
//! `w(a, a) = E(a+1, a)`; they must not be negative (a negative relay weight makes a minor loop
//! turn the wrong way and the torque leave the major loop). [`EverettTable::check`] refuses a
//! table with a weight below `−`[`WEIGHT_TOLERANCE`] × the largest. Data that are not exactly
//! of a Preisach system (a torque that is a non-linear function of a Preisach-like magnetisation
//! breaks the congruency of minor loops, Mayergoyz 1991, theorem 1.2) give negative weights;
//! [`EverettTable::from_forcs`] then projects them onto the closest table with non-negative
//! weights in the least-squares sense over the nodes, `min Σ c_ab (E'(a,b) − E(a,b))²` over
//! `w' ≥ 0` (non-negative least squares, Lawson & Hanson 1974, ch. 23), with the major loop's
//! nodes (the rising branch `b = 0` and the falling branch `a = n`) weighted
//! [`MAJOR_LOOP_WEIGHT`] times the others so that the loop the controller compensates is kept;
//! the rising branch follows from the wiping-out relation `T(α) = T(0) + E(α, 0)`. The change is
//! reported ([`Identified::projection_nm`]).

use serde::{Deserialize, Serialize};

/// Most levels `n` of a table (the design's FORC grid; the projection's normal equations have
/// `(n(n+1)/2)²` entries).
pub const MAX_LEVELS: usize = 64;
/// Negative cell weight tolerated, as a fraction of the largest weight (rounding).
pub const WEIGHT_TOLERANCE: f64 = 1e-9;
/// Weight of the major loop's nodes in the projection onto a non-negative density (module docs).
pub const MAJOR_LOOP_WEIGHT: f64 = 100.0;

/// A Preisach model as a tabulated Everett function on a uniform grid of `[0, I_max]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EverettTable {
    /// The levels `α_0 = 0 < … < α_n = I_max`, evenly spaced, A.
    #[serde(rename = "levels_A")]
    pub levels_a: Vec<f64>,
    /// The rising branch from the reference state at each level, N·m.
    #[serde(rename = "rising_Nm")]
    pub rising_nm: Vec<f64>,
    /// `everett[a][b] = E(α_a, α_b)`, `b = 0 … a` (`everett[a][a] = 0`), N·m.
    #[serde(rename = "everett_Nm")]
    pub everett_nm: Vec<Vec<f64>>,
}

/// A table identified from FORCs, with what the identification changed.
#[derive(Debug, Clone, PartialEq)]
pub struct Identified {
    /// The table.
    pub table: EverettTable,
    /// Largest `|T(α_k, 0) − T(0)|` of the FORCs (module docs), N·m.
    pub wiping_out_defect_nm: f64,
    /// Sum of the negative cell weights set to zero, N·m (0: none).
    pub projected_weight_nm: f64,
    /// Largest change of a node's torque the projection made, N·m.
    pub projection_nm: f64,
}

impl EverettTable {
    /// Identifies the table from FORCs on the grid `levels_a`: `forcs_nm[k][j] = T(α_k, β_j)`,
    /// `j = 0 … k`, with `forcs_nm[k][k] = T(α_k)` (module docs), projected onto a non-negative
    /// density. `Err((field, message))` for a bad shape or value.
    pub fn from_forcs(
        levels_a: &[f64],
        forcs_nm: &[Vec<f64>],
    ) -> Result<Identified, (String, String)> {
        let n = levels_a.len().saturating_sub(1);
        check_levels(levels_a)?;
        check_rows("forcs_Nm", forcs_nm, n)?;
        let rising_nm: Vec<f64> = forcs_nm.iter().enumerate().map(|(k, f)| f[k]).collect();
        let reference = rising_nm[0];
        let everett_nm = forcs_nm
            .iter()
            .enumerate()
            .map(|(a, forc)| {
                (0..=a)
                    .map(|b| match b {
                        _ if b == a => 0.0,
                        0 => rising_nm[a] - reference,
                        _ => rising_nm[a] - forc[b],
                    })
                    .collect()
            })
            .collect();
        let wiping_out_defect_nm =
            forcs_nm[1..].iter().map(|f| (f[0] - reference).abs()).fold(0.0, f64::max);
        let raw = Self { levels_a: levels_a.to_vec(), rising_nm, everett_nm };
        let weights = raw.weights();
        let projected_weight_nm: f64 = weights.iter().flatten().filter(|w| **w < 0.0).sum::<f64>();
        let largest = weights.iter().flatten().fold(0.0_f64, |m, w| m.max(*w));
        let negative = weights.iter().flatten().any(|w| *w < -WEIGHT_TOLERANCE * largest);
        let everett_nm = if negative {
            sum_weights(&project(&raw.everett_nm).map_err(|e| ("forcs_Nm".to_string(), e))?)
        } else {
            raw.everett_nm.clone()
        };
        let rising_nm: Vec<f64> = everett_nm.iter().map(|row| reference + row[0]).collect();
        let projection_nm = raw
            .everett_nm
            .iter()
            .flatten()
            .zip(everett_nm.iter().flatten())
            .map(|(a, b)| (a - b).abs())
            .chain(raw.rising_nm.iter().zip(&rising_nm).map(|(a, b)| (a - b).abs()))
            .fold(0.0, f64::max);
        Ok(Identified {
            table: Self { levels_a: raw.levels_a, rising_nm, everett_nm },
            wiping_out_defect_nm,
            projected_weight_nm: -projected_weight_nm,
            projection_nm,
        })
    }

    /// Levels `n` (cells per side).
    pub fn levels(&self) -> usize {
        self.levels_a.len() - 1
    }

    /// Checks shape, values and the non-negative density against a unit whose maximum current is
    /// `current_max_a`; `Err((field, message))` names the first bad field.
    pub fn check(&self, current_max_a: f64) -> Result<(), (String, String)> {
        check_levels(&self.levels_a)?;
        let n = self.levels();
        let last = self.levels_a[n];
        if (last - current_max_a).abs() > 1e-9 * current_max_a {
            return Err((
                "levels_A".into(),
                format!("must end at current_max_A = {current_max_a} A, ends at {last} A"),
            ));
        }
        if self.rising_nm.len() != n + 1 {
            let msg =
                format!("{} values for {} levels; need one per level", self.rising_nm.len(), n + 1);
            return Err(("rising_Nm".into(), msg));
        }
        if let Some(k) = self.rising_nm.iter().position(|v| !v.is_finite() || *v < 0.0) {
            return Err((format!("rising_Nm[{k}]"), "must be a finite torque ≥ 0".into()));
        }
        check_rows("everett_Nm", &self.everett_nm, n)?;
        let scale = self.everett_nm.iter().flatten().fold(0.0_f64, |m, v| m.max(v.abs()));
        for (a, row) in self.everett_nm.iter().enumerate() {
            if row[a].abs() > 1e-12 * scale.max(f64::MIN_POSITIVE) {
                return Err((format!("everett_Nm[{a}][{a}]"), "E(α, α) must be 0".into()));
            }
        }
        let weights = self.weights();
        let largest = weights.iter().flatten().fold(0.0_f64, |m, w| m.max(*w));
        for (a, row) in weights.iter().enumerate() {
            if let Some(b) = row.iter().position(|w| *w < -WEIGHT_TOLERANCE * largest.max(1e-300)) {
                return Err((
                    format!("everett_Nm[{}][{b}]", a + 1),
                    format!(
                        "the Preisach weight of cell ({a}, {b}) is {:.3e} N·m < 0: the Everett \
                         function must increase with α and decrease with β, its mixed second \
                         differences ≥ 0",
                        row[b]
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The cells' weights `w[a][b]`, `b ≤ a < n` (module docs).
    pub fn weights(&self) -> Vec<Vec<f64>> {
        let e = |a: usize, b: usize| if b >= a { 0.0 } else { self.everett_nm[a][b] };
        (0..self.levels())
            .map(|a| {
                (0..=a).map(|b| e(a + 1, b) - e(a, b) - e(a + 1, b + 1) + e(a, b + 1)).collect()
            })
            .collect()
    }

    /// The falling major branch `T(I_max, α_b)`, `b = 0 … n`, N·m (the model's torque after the
    /// peak: `T(α_n) − E(α_n, α_b)`, with the β = 0 row's `T(0)`).
    pub fn falling_nm(&self) -> Vec<f64> {
        let n = self.levels();
        (0..=n).map(|b| self.rising_nm[n] - self.everett_nm[n][b]).collect()
    }

    /// The table with `offset_nm` added to the rising branch (a constant friction).
    pub fn with_offset(&self, offset_nm: f64) -> Self {
        let mut t = self.clone();
        t.rising_nm.iter_mut().for_each(|v| *v += offset_nm);
        t
    }

    /// The table with every torque times `factor` (a unit whose curve is another's scaled).
    pub fn scaled(&self, factor: f64) -> Self {
        let mut t = self.clone();
        t.rising_nm.iter_mut().for_each(|v| *v *= factor);
        t.everett_nm.iter_mut().flatten().for_each(|v| *v *= factor);
        t
    }
}

/// The non-negative cell weights whose table is closest to `everett` (module docs): NNLS on the
/// normal equations. Node `(a, b)`, `b < a`, sums the cells `(i, j)` with `b ≤ j ≤ i < a`, so
/// `G[c, d] = Σ c_ab` over the nodes with `a > max(i_c, i_d)` and `b ≤ min(j_c, j_d)`.
fn project(everett: &[Vec<f64>]) -> Result<Vec<Vec<f64>>, String> {
    let n = everett.len() - 1;
    let cells: Vec<(usize, usize)> = (0..n).flat_map(|i| (0..=i).map(move |j| (i, j))).collect();
    let weight = |a: usize, b: usize| if b == 0 || a == n { MAJOR_LOOP_WEIGHT } else { 1.0 };
    // sum_w[a][b] = Σ c_a'b' over a' ≥ a, b' ≤ b (nodes b' < a'), and the same of c·E.
    let mut sum_w = vec![vec![0.0; n + 1]; n + 2];
    let mut sum_we = vec![vec![0.0; n + 1]; n + 2];
    for a in (1..=n).rev() {
        for b in 0..=n {
            let (node_w, node_we) =
                if b < a { (weight(a, b), weight(a, b) * everett[a][b]) } else { (0.0, 0.0) };
            let left_w = if b > 0 { sum_w[a][b - 1] } else { 0.0 };
            let left_we = if b > 0 { sum_we[a][b - 1] } else { 0.0 };
            let below_w = sum_w[a + 1][b] - if b > 0 { sum_w[a + 1][b - 1] } else { 0.0 };
            let below_we = sum_we[a + 1][b] - if b > 0 { sum_we[a + 1][b - 1] } else { 0.0 };
            sum_w[a][b] = left_w + below_w + node_w;
            sum_we[a][b] = left_we + below_we + node_we;
        }
    }
    let m = cells.len();
    let mut gram = vec![0.0; m * m];
    for (c, &(ic, jc)) in cells.iter().enumerate() {
        for (d, &(id, jd)) in cells.iter().enumerate() {
            gram[c * m + d] = sum_w[ic.max(id) + 1][jc.min(jd)];
        }
    }
    let rhs: Vec<f64> = cells.iter().map(|&(i, j)| sum_we[i + 1][j]).collect();
    let solution =
        mrbrake_sysid::operator_fit::nnls_gram(&gram, &rhs, m).map_err(|e| e.to_string())?;
    let mut out: Vec<Vec<f64>> = (0..n).map(|i| vec![0.0; i + 1]).collect();
    for (&(i, j), w) in cells.iter().zip(solution) {
        out[i][j] = w.max(0.0);
    }
    Ok(out)
}

/// The table `E[a][b] = Σ w(i, j)` over the cells with `b ≤ j ≤ i < a`.
fn sum_weights(weights: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let n = weights.len();
    let mut e = vec![vec![0.0]; n + 1];
    for a in 1..=n {
        let mut row = vec![0.0; a + 1];
        // Column sums of row a−1 of the cells from b up, plus the table of the rows below.
        let mut tail = 0.0;
        for b in (0..a).rev() {
            tail += weights[a - 1][b];
            row[b] = tail + if b < a - 1 { e[a - 1][b] } else { 0.0 };
        }
        e[a] = row;
    }
    e
}

/// Levels: 2 ..= MAX_LEVELS + 1 values, finite, from 0, evenly spaced.
fn check_levels(levels_a: &[f64]) -> Result<(), (String, String)> {
    let count = levels_a.len();
    if !(3..=MAX_LEVELS + 1).contains(&count) {
        let msg = format!("{count} levels; need 3..={} (2..={MAX_LEVELS} cells)", MAX_LEVELS + 1);
        return Err(("levels_A".into(), msg));
    }
    if let Some(k) = levels_a.iter().position(|v| !v.is_finite()) {
        return Err((format!("levels_A[{k}]"), "must be a finite current".into()));
    }
    let n = count - 1;
    let top = levels_a[n];
    if top <= 0.0 || levels_a[0].abs() > 1e-12 * top {
        return Err((
            "levels_A".into(),
            format!("must run from 0 to a positive current, runs {}..{top}", levels_a[0]),
        ));
    }
    for (k, v) in levels_a.iter().enumerate() {
        if (v - top * k as f64 / n as f64).abs() > 1e-9 * top {
            return Err((
                format!("levels_A[{k}]"),
                format!(
                    "{v} A: the levels must be evenly spaced ({} A)",
                    top * k as f64 / n as f64
                ),
            ));
        }
    }
    Ok(())
}

/// Row `a` of a triangular table has `a + 1` finite values.
fn check_rows(field: &str, rows: &[Vec<f64>], n: usize) -> Result<(), (String, String)> {
    if rows.len() != n + 1 {
        return Err((
            field.into(),
            format!("{} rows for {} levels; need one per level", rows.len(), n + 1),
        ));
    }
    for (a, row) in rows.iter().enumerate() {
        if row.len() != a + 1 {
            return Err((
                format!("{field}[{a}]"),
                format!("{} values; row {a} has {} (β = α_0 … α_{a})", row.len(), a + 1),
            ));
        }
        if let Some(b) = row.iter().position(|v| !v.is_finite()) {
            return Err((format!("{field}[{a}][{b}]"), "must be a finite torque".into()));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rig::preisach::{HysteresisConfig, HysteresisKind, PreisachHysteresis};
    use proptest::prelude::*;

    /// The FORCs of `model` on the grid of `n` levels of `[0, i_max]`: from the state at 0 A,
    /// rise to `α_k`, fall through every lower level.
    fn forcs_of(model: &PreisachHysteresis, n: usize, i_max: f64) -> Vec<Vec<f64>> {
        (0..=n)
            .map(|k| {
                let mut m = model.clone();
                m.settle(0.0);
                let mut forc = vec![0.0; k + 1];
                for a in 0..=k {
                    forc[k] = m.torque_nm(i_max * a as f64 / n as f64);
                }
                for j in (0..k).rev() {
                    forc[j] = m.torque_nm(i_max * j as f64 / n as f64);
                }
                forc
            })
            .collect()
    }

    /// A table from cell weights, its rising branch `t0 + E(α, 0)` (a Preisach system).
    fn table_of(weights: &[Vec<f64>], t0: f64, i_max: f64) -> EverettTable {
        let n = weights.len();
        let everett_nm = sum_weights(weights);
        EverettTable {
            levels_a: (0..=n).map(|k| i_max * k as f64 / n as f64).collect(),
            rising_nm: everett_nm.iter().map(|row| t0 + row[0]).collect(),
            everett_nm,
        }
    }

    /// Random non-negative cell weights of an `n`-level table.
    fn weights(n: usize) -> impl Strategy<Value = Vec<Vec<f64>>> {
        let rows: Vec<_> = (0..n).map(|a| proptest::collection::vec(0.0..0.2f64, a + 1)).collect();
        rows
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(32))]

        /// A Preisach model's FORCs give back its Everett function, and the model identified from
        /// them reproduces every FORC at the nodes (here exactly: the system wipes out).
        #[test]
        fn a_preisach_models_forcs_give_back_its_everett_function(
            w in weights(7), t0 in 0.0..0.5f64, i_max in 0.5..3.0f64,
        ) {
            let table = table_of(&w, t0, i_max);
            table.check(i_max).unwrap();
            let model = PreisachHysteresis::from_everett(&table, 0.0).unwrap();
            let forcs = forcs_of(&model, 7, i_max);
            let identified = EverettTable::from_forcs(&table.levels_a, &forcs).unwrap();
            prop_assert!(identified.wiping_out_defect_nm < 1e-12);
            prop_assert!(identified.projection_nm < 1e-12 && identified.projected_weight_nm < 1e-12);
            for (a, row) in identified.table.everett_nm.iter().enumerate() {
                for (b, e) in row.iter().enumerate() {
                    prop_assert!((e - table.everett_nm[a][b]).abs() < 1e-12, "E({a}, {b})");
                }
            }
            let again = PreisachHysteresis::from_everett(&identified.table, 0.0).unwrap();
            let forcs_again = forcs_of(&again, 7, i_max);
            for (f, g) in forcs.iter().flatten().zip(forcs_again.iter().flatten()) {
                prop_assert!((f - g).abs() < 1e-12);
            }
        }
    }

    /// FORCs that no Preisach model has (a node pushed up makes a cell weight negative) are
    /// projected onto a valid table, the major loop kept closer than the rest.
    #[test]
    fn forcs_of_no_preisach_model_are_projected_onto_a_valid_table() {
        let w: Vec<Vec<f64>> = (0..6).map(|a| vec![0.05; a + 1]).collect();
        let table = table_of(&w, 0.1, 2.0);
        let model = PreisachHysteresis::from_everett(&table, 0.0).unwrap();
        let mut forcs = forcs_of(&model, 6, 2.0);
        forcs[4][2] -= 0.2;
        let identified = EverettTable::from_forcs(&table.levels_a, &forcs).unwrap();
        identified.table.check(2.0).unwrap();
        assert!(identified.projected_weight_nm > 0.1, "{identified:?}");
        assert!(identified.projection_nm > 0.0 && identified.projection_nm < 0.2);
        let major = |t: &EverettTable| {
            let mut v: Vec<f64> = t.everett_nm.iter().skip(1).map(|r| r[0]).collect();
            v.extend(t.everett_nm[6].iter().copied());
            v
        };
        let change = major(&identified.table)
            .iter()
            .zip(major(&table))
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(change < 0.01 * identified.projection_nm.max(1e-3) + 2e-3, "{change}");
    }

    /// The branch + prior model has a reversible part; identified from its FORCs on a coarser grid
    /// (every 4th of its 64 levels), the table model gives the same torque along any history whose
    /// turning points are grid levels (the reversible part becomes relays one cell wide).
    #[test]
    fn the_identified_model_follows_the_branch_and_prior_model_on_the_grid() {
        let config = HysteresisConfig { model: HysteresisKind::Preisach, ..Default::default() };
        let rising = [0.15, 3.69, -1.38375, 0.230625];
        let falling = [0.15, 4.29, -1.68375, 0.230625];
        let model = PreisachHysteresis::new(&config, &rising, &falling, 2.0).unwrap();
        let n = 16;
        let forcs = forcs_of(&model, n, 2.0);
        let levels: Vec<f64> = (0..=n).map(|k| 2.0 * k as f64 / n as f64).collect();
        let identified = EverettTable::from_forcs(&levels, &forcs).unwrap();
        assert!(identified.wiping_out_defect_nm < 1e-12 && identified.projection_nm < 1e-12);
        let (mut a, mut b) =
            (model, PreisachHysteresis::from_everett(&identified.table, 0.0).unwrap());
        a.settle(0.0);
        b.settle(0.0);
        for level in [3u32, 12, 5, 9, 7, 16, 1, 10, 4, 8, 0, 13, 11, 14, 2] {
            let i = 2.0 * f64::from(level) / n as f64;
            let (ta, tb) = (a.torque_nm(i), b.torque_nm(i));
            assert!((ta - tb).abs() < 1e-12, "{ta} vs {tb} at {i} A");
        }
    }

    #[test]
    fn weights_sum_back_to_the_table() {
        let w = vec![vec![0.5], vec![0.2, 0.3], vec![0.0, 0.1, 0.4]];
        let e = sum_weights(&w);
        let t = EverettTable {
            levels_a: vec![0.0, 1.0, 2.0, 3.0],
            rising_nm: vec![0.0; 4],
            everett_nm: e.clone(),
        };
        assert_eq!(e[1], vec![0.5, 0.0]);
        // E(3, 0): every cell.
        assert!((e[3][0] - 1.5).abs() < 1e-15 && (e[3][2] - 0.4).abs() < 1e-15);
        for (a, row) in t.weights().iter().enumerate() {
            for (b, v) in row.iter().enumerate() {
                assert!((v - w[a][b]).abs() < 1e-15, "{a} {b}");
            }
        }
    }

    #[test]
    fn bad_tables_are_refused_naming_the_field() {
        let good = EverettTable {
            levels_a: vec![0.0, 1.0, 2.0],
            rising_nm: vec![0.1, 0.6, 1.2],
            everett_nm: vec![vec![0.0], vec![0.5, 0.0], vec![1.1, 0.4, 0.0]],
        };
        assert!(good.check(2.0).is_ok());
        let field = |t: &EverettTable| t.check(2.0).unwrap_err().0;
        let mut t = good.clone();
        t.everett_nm[2][1] = f64::NAN;
        assert_eq!(field(&t), "everett_Nm[2][1]");
        let mut t = good.clone();
        t.everett_nm[2].pop();
        assert_eq!(field(&t), "everett_Nm[2]");
        let mut t = good.clone();
        t.levels_a[1] = 0.7;
        assert_eq!(field(&t), "levels_A[1]");
        let mut t = good.clone();
        t.rising_nm.pop();
        assert_eq!(field(&t), "rising_Nm");
        // E(2, 0) < E(1, 0) + E(2, 1): a negative cell (1, 0).
        let mut t = good.clone();
        t.everett_nm[2][0] = 0.8;
        assert_eq!(field(&t), "everett_Nm[2][0]");
        assert!(good.check(3.0).unwrap_err().0 == "levels_A");
    }
}
