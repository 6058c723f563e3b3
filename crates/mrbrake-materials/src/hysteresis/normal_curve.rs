//! The model's normal magnetisation curve as a single-valued [`Reluctivity`], so that the existing
//! anhysteretic solvers can run on the same material law as a hysteretic solve (the first
//! magnetisation from the demagnetised state) without any change: wrap it in
//! [`crate::Magnetic::NonLinear`].
//!
//! From the demagnetised state the B-driven step gives `H(B)` and `dH/dB` on the first-magnetisation
//! curve, which in this model is also the locus of the tips of symmetric loops. The reluctivity is
//! `ν = H/B` and, by the chain rule, `dν/dB² = (B dH/dB − H) / (2 B³)`. The Fröhlich–Kennelly terms
//! have an `x|x|` part at the origin, so `dν/dB²` grows like `1/|B|` as `B → 0`; it only enters the
//! Newton Jacobian as `2 dν/dB² B⊗B`, which stays bounded. Below [`SMALL_B_T`] the values at
//! [`SMALL_B_T`] are used (ν is continuous there; its change below 1 µT is negligible).

use std::sync::Arc;

use super::{HysteresisParams, HysteresisState};
use crate::Reluctivity;

/// Below this |B| (T) the reluctivity takes its values at this |B|.
pub const SMALL_B_T: f64 = 1e-6;

/// The normal magnetisation curve of a hysteresis parameter set (see the module docs).
#[derive(Debug, Clone)]
pub struct NormalCurve {
    params: Arc<HysteresisParams>,
}

impl NormalCurve {
    /// The normal curve of `params`.
    pub fn new(params: Arc<HysteresisParams>) -> Self {
        Self { params }
    }

    /// The parameter set.
    pub fn params(&self) -> &Arc<HysteresisParams> {
        &self.params
    }

    /// `(H, dH/dB)` on the curve at flux density `b ≥ 0` (T).
    fn field_and_slope(&self, b: f64) -> (f64, f64) {
        let (response, _) = HysteresisState::demagnetised().trial(&self.params, b);
        (response.h, response.dh_db)
    }
}

impl Reluctivity for NormalCurve {
    fn nu_and_dnu_db2(&self, b2: f64) -> (f64, f64) {
        let b = b2.max(0.0).sqrt().max(SMALL_B_T);
        let (h, slope) = self.field_and_slope(b);
        (h / b, (b * slope - h) / (2.0 * b * b * b))
    }

    fn h_of_b(&self, b: f64) -> f64 {
        self.field_and_slope(b.abs()).0.copysign(b)
    }
}
