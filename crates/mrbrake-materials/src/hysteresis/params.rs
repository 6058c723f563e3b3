//! The parameters of the energy-based model: pinning fields of the cells and the anhysteretic law
//! of each cell as a non-negative sum of Fröhlich–Kennelly terms.
//!
//! Cell `k` has a pinning field `κ_k ≥ 0` (A/m) and a reversible polarisation law
//! `J_k(h) = Σ_{terms of k} J_t · g(h / a_t)`, `g(x) = x / (1 + |x|)`, with `J_t > 0` (T) and
//! `a_t > 0` (A/m). `g` is the Fröhlich–Kennelly law `M = M_s H / (a + |H|)` (O. Fröhlich,
//! Elektrotech. Z. 2 (1881) 134; A. E. Kennelly, Trans. AIEE 8 (1891) 485; in R. M. Bozorth,
//! *Ferromagnetism*, Van Nostrand 1951; citations as usually given): odd, strictly increasing, bounded by `J_t`, and it
//! approaches saturation as `1 − a/H`, the law of approach of polycrystalline iron at high field.
//! A sum of such terms with different `a_t` describes both the steep low-field part of a steel's curve
//! and its slow approach to saturation; it costs one division per term (no `exp`, no `coth`).
//!
//! The saturation polarisation of the material is `J_s = Σ_t J_t`.

use serde::Serialize;

use crate::{MU_0, MaterialError};

/// Most cells (pinning fields) of a parameter set: the per-point state holds one reversible field per
/// cell, so this bounds the state's size (a `Copy` array).
pub const MAX_CELLS: usize = 8;

/// Most anhysteretic terms of a parameter set (all cells together).
pub const MAX_TERMS: usize = 48;

/// Largest pinning field or term field accepted, A/m (10 MA/m: far beyond any soft steel; it keeps
/// every intermediate product finite).
pub const MAX_FIELD_A_PER_M: f64 = 1e7;

/// Largest term polarisation accepted, T (iron-cobalt saturates at 2.4 T).
pub const MAX_POLARISATION_T: f64 = 3.0;

/// One anhysteretic term: `J_t · g(h/a_t)` added to the law of cell `cell`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Term {
    /// Index of the cell the term belongs to.
    pub cell: usize,
    /// Polarisation amplitude `J_t`, T (`> 0`).
    #[serde(rename = "polarisation_T")]
    pub polarisation_t: f64,
    /// Field scale `a_t`, A/m (`> 0`).
    #[serde(rename = "field_A_per_m")]
    pub field_a_per_m: f64,
}

/// A validated parameter set of the energy-based hysteresis model (configuration, shared by every
/// quadrature point of a region; the per-point state is [`super::HysteresisState`]).
#[derive(Debug, Clone, PartialEq)]
pub struct HysteresisParams {
    cells: usize,
    pinning: [f64; MAX_CELLS],
    terms: usize,
    /// Terms are stored grouped by cell: cell `k` owns `cell_start[k]..cell_start[k + 1]`.
    cell_start: [usize; MAX_CELLS + 1],
    term_cell: [usize; MAX_TERMS],
    term_js: [f64; MAX_TERMS],
    /// `1/a_t`, so that a term costs one division (`1/(1+|x|)`).
    term_inv_a: [f64; MAX_TERMS],
}

impl HysteresisParams {
    /// Builds and validates a parameter set: `pinning_a_per_m[k]` is `κ_k` (finite, `0 ≤ κ_k ≤ 10 MA/m`),
    /// each term names an existing cell and has `0 < J_t ≤ 3 T`, `0 < a_t ≤ 10 MA/m`; at least one
    /// term; at most [`MAX_CELLS`] cells and [`MAX_TERMS`] terms. Errors name the field and the range.
    pub fn new(pinning_a_per_m: &[f64], terms: &[Term]) -> Result<Self, MaterialError> {
        let out_of_range = |quantity: String, value: f64, allowed: &str| {
            MaterialError::OutOfRange { quantity, value, allowed: allowed.to_string() }
        };
        let cells = pinning_a_per_m.len();
        if cells == 0 || cells > MAX_CELLS {
            let allowed = format!("1..={MAX_CELLS}");
            return Err(out_of_range("number of hysteresis cells".into(), cells as f64, &allowed));
        }
        if terms.is_empty() || terms.len() > MAX_TERMS {
            let allowed = format!("1..={MAX_TERMS}");
            return Err(out_of_range(
                "number of anhysteretic terms".into(),
                terms.len() as f64,
                &allowed,
            ));
        }
        let mut pinning = [0.0; MAX_CELLS];
        for (k, &kappa) in pinning_a_per_m.iter().enumerate() {
            if !(kappa.is_finite() && (0.0..=MAX_FIELD_A_PER_M).contains(&kappa)) {
                return Err(out_of_range(
                    format!("hysteresis cell {k}: pinning field kappa_A_per_m"),
                    kappa,
                    "finite, 0 <= kappa <= 1e7 A/m",
                ));
            }
            pinning[k] = kappa;
        }
        let mut params = Self {
            cells,
            pinning,
            terms: terms.len(),
            cell_start: [0; MAX_CELLS + 1],
            term_cell: [0; MAX_TERMS],
            term_js: [0.0; MAX_TERMS],
            term_inv_a: [0.0; MAX_TERMS],
        };
        for (t, term) in terms.iter().enumerate() {
            check_term(t, term, cells)?;
        }
        // Group the terms by cell (stable), so that an evaluation visits each cell once.
        let mut ordered: Vec<&Term> = terms.iter().collect();
        ordered.sort_by_key(|term| term.cell);
        for (t, term) in ordered.iter().enumerate() {
            params.term_cell[t] = term.cell;
            params.term_js[t] = term.polarisation_t;
            params.term_inv_a[t] = 1.0 / term.field_a_per_m;
            params.cell_start[term.cell + 1] = t + 1;
        }
        for k in 1..=MAX_CELLS {
            params.cell_start[k] = params.cell_start[k].max(params.cell_start[k - 1]);
        }
        Ok(params)
    }

    /// Number of cells.
    pub fn cells(&self) -> usize {
        self.cells
    }

    /// Pinning fields `κ_k`, A/m.
    pub fn pinning_a_per_m(&self) -> &[f64] {
        &self.pinning[..self.cells]
    }

    /// The anhysteretic terms, grouped by cell (in the order given within a cell).
    pub fn terms(&self) -> Vec<Term> {
        (0..self.terms)
            .map(|t| Term {
                cell: self.term_cell[t],
                polarisation_t: self.term_js[t],
                field_a_per_m: 1.0 / self.term_inv_a[t],
            })
            .collect()
    }

    /// Saturation polarisation `J_s = Σ J_t`, T.
    pub fn saturation_polarisation_t(&self) -> f64 {
        self.term_js[..self.terms].iter().sum()
    }

    /// The same set with every pinning field multiplied by `factor ≥ 0` (`0` gives the anhysteretic
    /// limit: a single-valued curve).
    pub fn with_pinning_scaled(&self, factor: f64) -> Result<Self, MaterialError> {
        let pinning: Vec<f64> = self.pinning_a_per_m().iter().map(|k| k * factor).collect();
        Self::new(&pinning, &self.terms())
    }

    /// Polarisation `J = Σ_k J_k(h_k)` of the cells at reversible fields `reversible[k]` and its
    /// derivative with respect to the field of the cells flagged in `moving` (the cells whose
    /// reversible field follows the applied field), T and T·m/A.
    #[inline]
    pub(crate) fn polarisation(&self, reversible: &[f64; MAX_CELLS], moving: u32) -> (f64, f64) {
        let (j, dj, _) = self.polarisation_and_curvature(reversible, moving);
        (j, dj)
    }

    /// [`HysteresisParams::polarisation`] and the second derivative `d²J/dH²` of the moving cells
    /// (`g''(x) = −2 sign(x) / (1 + |x|)³`), for the root search's Halley steps.
    #[inline]
    pub(crate) fn polarisation_and_curvature(
        &self,
        reversible: &[f64; MAX_CELLS],
        moving: u32,
    ) -> (f64, f64, f64) {
        let (mut j, mut dj, mut d2j) = (0.0, 0.0, 0.0);
        for (k, &h) in reversible.iter().enumerate().take(self.cells) {
            let terms = self.cell_start[k]..self.cell_start[k + 1];
            let js = &self.term_js[terms.clone()];
            let inv_a = &self.term_inv_a[terms];
            let slopes = (moving & (1 << k) != 0).then_some((&mut dj, &mut d2j));
            add_cell_terms(js, inv_a, h, &mut j, slopes);
        }
        (j, dj, d2j)
    }

    /// The polarisation of every cell, `J_k(h_k)` (T), with `dJ/dH` of the cells flagged in
    /// `moving` and its second derivative (as [`Self::polarisation_and_curvature`]); a cell flagged
    /// in `known` (and not in `moving`) takes its polarisation from `cached[k]` instead of its
    /// terms: a cell whose reversible field did not change since `cached` was evaluated costs
    /// nothing. The total `J` is the sum of the cells'.
    #[inline]
    pub(crate) fn cell_polarisations(
        &self,
        reversible: &[f64; MAX_CELLS],
        moving: u32,
        known: u32,
        cached: &[f64; MAX_CELLS],
    ) -> ([f64; MAX_CELLS], f64, f64) {
        let mut cells = [0.0; MAX_CELLS];
        let (mut dj, mut d2j) = (0.0, 0.0);
        for (k, &h) in reversible.iter().enumerate().take(self.cells) {
            let bit = 1 << k;
            if moving & bit == 0 && known & bit != 0 {
                cells[k] = cached[k];
                continue;
            }
            let terms = self.cell_terms(k);
            let js = &self.term_js[terms.clone()];
            let inv_a = &self.term_inv_a[terms];
            let mut j = 0.0;
            let slopes = (moving & bit != 0).then_some((&mut dj, &mut d2j));
            add_cell_terms(js, inv_a, h, &mut j, slopes);
            cells[k] = j;
        }
        (cells, dj, d2j)
    }

    /// The terms of cell `cell` (stored together, in their order).
    fn cell_terms(&self, cell: usize) -> std::ops::Range<usize> {
        self.cell_start[cell]..self.cell_start[cell + 1]
    }

    /// Polarisation of cell `cell` alone at reversible field `h`, T (states keep theirs:
    /// [`Self::cell_polarisations`]).
    #[cfg(test)]
    pub(crate) fn cell_polarisation(&self, cell: usize, h: f64) -> f64 {
        self.cell_terms(cell)
            .map(|t| {
                let x = h * self.term_inv_a[t];
                self.term_js[t] * x / (1.0 + x.abs())
            })
            .sum()
    }

    /// Free energy of cell `cell` at reversible field `h`: `U_k = h J_k(h) − ∫_0^h J_k`, J/m³, with
    /// `∫_0^h J_t g(s/a) ds = J_t a (|x| − ln(1 + |x|))`, `x = h/a`. Convex in `J_k`.
    pub(crate) fn cell_free_energy(&self, cell: usize, h: f64) -> f64 {
        self.cell_terms(cell)
            .map(|t| {
                let a = 1.0 / self.term_inv_a[t];
                let x = (h * self.term_inv_a[t]).abs();
                let js = self.term_js[t];
                h.abs() * js * x / (1.0 + x) - js * a * (x - x.ln_1p())
            })
            .sum()
    }

    /// The anhysteretic curve `B(H) = μ0 H + Σ_k J_k(H)` (every cell at the applied field), T.
    pub fn anhysteretic_b(&self, h: f64) -> f64 {
        let reversible = [h; MAX_CELLS];
        MU_0 * h + self.polarisation(&reversible, 0).0
    }
}

impl Serialize for HysteresisParams {
    /// `{ "model": "energy-based (play)", "pinning_A_per_m": [...], "terms": [...],
    /// "saturation_polarisation_T": ... }` (for reports).
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let mut out = serializer.serialize_struct("HysteresisParams", 4)?;
        out.serialize_field("model", "energy-based (play), Henrotte et al. 2006")?;
        out.serialize_field("pinning_A_per_m", self.pinning_a_per_m())?;
        out.serialize_field("terms", &self.terms())?;
        out.serialize_field("saturation_polarisation_T", &self.saturation_polarisation_t())?;
        out.end()
    }
}

fn check_term(t: usize, term: &Term, cells: usize) -> Result<(), MaterialError> {
    let out_of_range = |field: &str, value: f64, allowed: String| MaterialError::OutOfRange {
        quantity: format!("anhysteretic term {t}: {field}"),
        value,
        allowed,
    };
    if term.cell >= cells {
        return Err(out_of_range("cell", term.cell as f64, format!("0..{cells}")));
    }
    let js = term.polarisation_t;
    if !(js.is_finite() && js > 0.0 && js <= MAX_POLARISATION_T) {
        return Err(out_of_range("polarisation_T", js, "finite, 0 < J <= 3 T".into()));
    }
    let a = term.field_a_per_m;
    if !(a.is_finite() && a > 0.0 && a <= MAX_FIELD_A_PER_M) {
        return Err(out_of_range("field_A_per_m", a, "finite, 0 < a <= 1e7 A/m".into()));
    }
    Ok(())
}

/// Adds one cell's terms at its reversible field `h` (A/m) to `j`: `Σ J_s x/(1 + |x|)` with
/// `x = h/a` (T); with `slopes`, also their first and second derivatives in `h` (the cell is
/// moving). One loop for [`HysteresisParams::polarisation_and_curvature`] and
/// [`HysteresisParams::cell_polarisations`], the same operations in the same order as before.
#[inline]
fn add_cell_terms(
    js: &[f64],
    inv_a: &[f64],
    h: f64,
    j: &mut f64,
    slopes: Option<(&mut f64, &mut f64)>,
) {
    match slopes {
        None => {
            for (&js, &inv_a) in js.iter().zip(inv_a) {
                let x = h * inv_a;
                *j += js * x / (1.0 + x.abs());
            }
        }
        Some((dj, d2j)) => {
            for (&js, &inv_a) in js.iter().zip(inv_a) {
                let x = h * inv_a;
                let inv = 1.0 / (1.0 + x.abs());
                *j += js * x * inv;
                let slope = js * inv_a * inv * inv;
                *dj += slope;
                *d2j -= 2.0 * slope * inv_a * inv * x.signum();
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn term(cell: usize, js: f64, a: f64) -> Term {
        Term { cell, polarisation_t: js, field_a_per_m: a }
    }

    #[test]
    fn rejects_out_of_range_values_naming_the_field() {
        let bad_kappa = HysteresisParams::new(&[-1.0], &[term(0, 1.0, 100.0)]).unwrap_err();
        assert!(bad_kappa.to_string().contains("cell 0: pinning field"), "{bad_kappa}");
        let nan = HysteresisParams::new(&[f64::NAN], &[term(0, 1.0, 100.0)]).unwrap_err();
        assert!(nan.to_string().contains("pinning"), "{nan}");
        let bad_js = HysteresisParams::new(&[10.0], &[term(0, 0.0, 100.0)]).unwrap_err();
        assert!(bad_js.to_string().contains("term 0: polarisation_T"), "{bad_js}");
        let bad_cell = HysteresisParams::new(&[10.0], &[term(1, 1.0, 100.0)]).unwrap_err();
        assert!(bad_cell.to_string().contains("term 0: cell"), "{bad_cell}");
        let too_many = HysteresisParams::new(&[1.0; MAX_CELLS + 1], &[term(0, 1.0, 1.0)]);
        assert!(too_many.is_err());
        assert!(HysteresisParams::new(&[1.0], &[]).is_err());
    }

    #[test]
    fn free_energy_derivative_is_the_reversible_field() {
        // dU/dJ = h  <=>  dU/dh = h dJ/dh.
        let p =
            HysteresisParams::new(&[50.0], &[term(0, 1.2, 300.0), term(0, 0.8, 5000.0)]).unwrap();
        for h in [-4000.0_f64, -150.0, 20.0, 900.0, 30000.0] {
            let step = 1e-3 * (1.0 + h.abs());
            let du =
                (p.cell_free_energy(0, h + step) - p.cell_free_energy(0, h - step)) / (2.0 * step);
            let dj = (p.cell_polarisation(0, h + step) - p.cell_polarisation(0, h - step))
                / (2.0 * step);
            assert!(
                (du - h * dj).abs() <= 1e-6 * (h * dj).abs().max(1e-9),
                "h={h}: {du} vs {}",
                h * dj
            );
        }
    }
}
