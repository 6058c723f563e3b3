//! Operator-based hysteresis model of one brake and its exact inverse, as fixed-size tables: the
//! modified Prandtl–Ishlinskii model of Kuhnen (2003).
//!
//! **Forward model** (current `x` in A → torque `y` in N·m): `y = D⁻¹(Π[x])`, where
//!
//! - `Π[x] = Σᵢ aᵢ F_{rᵢ}[x]` is a Prandtl–Ishlinskii superposition of play (backlash) operators
//!   `F_r[x](t) = max(x(t) − r, min(x(t) + r, F_r[x](t⁻)))` with thresholds `0 = r₀ < r₁ < …` and
//!   weights `a₀ > 0, aᵢ ≥ 0` (Krasnosel'skii & Pokrovskii 1989, *Systems with Hysteresis*, §I.3;
//!   Brokate & Sprekels 1996, *Hysteresis and Phase Transitions*, §2.3). It is rate independent and
//!   has return-point memory and wiping-out (a Preisach model whose weight depends on `α − β` only).
//! - `D(y) = c + Σⱼ βⱼ ψⱼ(y)` is a strictly increasing piecewise-linear map of the torque with knots
//!   `d₀ < d₁ < …` and slopes `βⱼ > 0` (`ψⱼ` is the part of `y − dⱼ` inside segment `j`; the first
//!   and last segments extend without bound). This memoryless output operator is Kuhnen's
//!   superposition of dead-zone operators `S⁻¹` written with cumulative slopes; it makes the loops
//!   asymmetric (K. Kuhnen, "Modeling, identification and compensation of complex hysteretic
//!   nonlinearities: a modified Prandtl–Ishlinskii approach", European Journal of Control 9(4),
//!   407–418, 2003, eqs. (12)–(20)).
//!
//! **Inverse** (torque demand → current), exact and analytical: `x = Π⁻¹[D(y)]`, where the inverse of
//! a PI operator is again a PI operator with thresholds `r'ᵢ = Σ_{j≤i} aⱼ (rᵢ − rⱼ)` and weights
//! `a'₀ = 1/a₀`, `a'ᵢ = −aᵢ / (Aᵢ Aᵢ₋₁)` with `Aᵢ = Σ_{j≤i} aⱼ`, and initial states
//! `F'ᵢ(0) = Aᵢ F_{rᵢ}(0) + Σ_{j>i} aⱼ F_{rⱼ}(0)` (P. Krejčí and K. Kuhnen, "Inverse control of
//! systems with hysteresis and creep", IEE Proc. Control Theory Appl. 148(3), 185–192, 2001, Prop. 2;
//! Kuhnen 2003, eqs. (9)–(11)).
//!
//! **Rest state.** At `x = i_min` every play is pushed down to `i_min + rᵢ` (a descent to the lowest
//! current erases the memory, as in an MR brake, whose loops all close at 0 A). The inverse's plays
//! start in the matching state `z_rest + r'ᵢ`, and the inverse clamps the demand's image `D(y)` to the
//! range `[z_rest, z_top]` that currents in `[i_min, i_max]` reach, so its internal state never
//! drifts from the brake's.
//!
//! Everything is `no_std` with fixed capacity ([`MAX_PLAYS`], [`MAX_SEGMENTS`]); the step evaluates
//! `D` by a scan over the knots and updates the plays, with no iteration and no allocation.

use crate::error::{ControlError, check_range};
use crate::inverse::{Branch, CURRENT_LIMIT_A};

/// Most play operators a model may have (the controller's fixed capacity).
pub const MAX_PLAYS: usize = 32;

/// Most segments of the output map a model may have (the controller's fixed capacity).
pub const MAX_SEGMENTS: usize = 32;

/// The schema name of the operator-model file.
pub const OPERATOR_SCHEMA: &str = "mrbrake.operator-model";

/// The schema version this crate reads and writes.
pub const OPERATOR_SCHEMA_VERSION: u32 = 1;

/// The parameters of an [`OperatorModel`] before validation (slices; see the module docs).
#[derive(Debug, Clone, Copy)]
pub struct OperatorParts<'a> {
    /// Play thresholds `rᵢ`, A: `r₀ = 0`, strictly increasing.
    pub thresholds_a: &'a [f64],
    /// Play weights `aᵢ` (dimensionless): `a₀ > 0`, others `≥ 0`.
    pub weights: &'a [f64],
    /// Knots `dⱼ` of the output map, N·m, strictly increasing.
    pub knots_nm: &'a [f64],
    /// Slopes `βⱼ` of the output map, A per N·m, `> 0` (one per knot).
    pub slopes_a_per_nm: &'a [f64],
    /// Offset `c` of the output map, A.
    pub offset_a: f64,
    /// Lowest current (the rest state), A.
    pub current_min_a: f64,
    /// Highest current, A.
    pub current_max_a: f64,
}

/// A validated operator model with its precomputed inverse (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OperatorModel {
    plays: usize,
    thresholds_a: [f64; MAX_PLAYS],
    weights: [f64; MAX_PLAYS],
    segments: usize,
    knots_nm: [f64; MAX_SEGMENTS],
    slopes: [f64; MAX_SEGMENTS],
    /// `D(dⱼ)`, A.
    knot_levels: [f64; MAX_SEGMENTS],
    offset_a: f64,
    current_min_a: f64,
    current_max_a: f64,
    inverse_thresholds: [f64; MAX_PLAYS],
    inverse_weights: [f64; MAX_PLAYS],
    /// `Π` at rest and fully ascended to `i_max`, A.
    z_range: (f64, f64),
}

/// The state of the forward model (the plays of `Π`); the default is the rest state.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct OperatorState {
    plays: [f64; MAX_PLAYS],
    started: bool,
}

/// What the inverse carries from one demand to the next (the plays of `Π⁻¹`, the last demand's
/// image and the direction it last moved); the default is the rest state.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct OperatorCompensation {
    plays: [f64; MAX_PLAYS],
    z: f64,
    branch: Branch,
    started: bool,
    /// The plays are in the rest state (after a zero demand): another zero demand changes nothing.
    at_rest: bool,
}

impl OperatorCompensation {
    /// The direction in which the demand's image last moved (rising or falling).
    pub fn branch(&self) -> Branch {
        self.branch
    }
}

impl OperatorModel {
    /// Builds and validates a model; errors name the field and the allowed range.
    pub fn new(parts: &OperatorParts<'_>) -> Result<Self, ControlError> {
        let (i_min, i_max) = check_current_range(parts.current_min_a, parts.current_max_a)?;
        let plays = check_count("plays", parts.thresholds_a.len(), MAX_PLAYS)?;
        if parts.weights.len() != plays {
            return Err(ControlError::CountMismatch {
                field: "weights",
                count: parts.weights.len(),
                expected: plays,
            });
        }
        let segments = check_count("segments", parts.knots_nm.len(), MAX_SEGMENTS)?;
        if parts.slopes_a_per_nm.len() != segments {
            return Err(ControlError::CountMismatch {
                field: "slopes",
                count: parts.slopes_a_per_nm.len(),
                expected: segments,
            });
        }
        check_increasing("thresholds", parts.thresholds_a, true)?;
        check_increasing("knots", parts.knots_nm, false)?;
        check_range("weights[0]", parts.weights[0], f64::MIN_POSITIVE, f64::MAX)?;
        for &w in &parts.weights[1..] {
            check_range("weights", w, 0.0, f64::MAX)?;
        }
        for &s in parts.slopes_a_per_nm {
            check_range("slopes", s, f64::MIN_POSITIVE, f64::MAX)?;
        }
        check_range("offset", parts.offset_a, -f64::MAX, f64::MAX)?;
        let mut model = Self {
            plays,
            thresholds_a: [0.0; MAX_PLAYS],
            weights: [0.0; MAX_PLAYS],
            segments,
            knots_nm: [0.0; MAX_SEGMENTS],
            slopes: [0.0; MAX_SEGMENTS],
            knot_levels: [0.0; MAX_SEGMENTS],
            offset_a: parts.offset_a,
            current_min_a: i_min,
            current_max_a: i_max,
            inverse_thresholds: [0.0; MAX_PLAYS],
            inverse_weights: [0.0; MAX_PLAYS],
            z_range: (0.0, 0.0),
        };
        model.thresholds_a[..plays].copy_from_slice(parts.thresholds_a);
        model.weights[..plays].copy_from_slice(parts.weights);
        model.knots_nm[..segments].copy_from_slice(parts.knots_nm);
        model.slopes[..segments].copy_from_slice(parts.slopes_a_per_nm);
        model.precompute();
        Ok(model)
    }

    /// Knot levels of `D`, the inverse PI's thresholds and weights (Krejčí & Kuhnen 2001), and the
    /// reachable range of `Π`.
    fn precompute(&mut self) {
        let mut level = self.offset_a;
        for j in 0..self.segments {
            self.knot_levels[j] = level;
            if j + 1 < self.segments {
                level += self.slopes[j] * (self.knots_nm[j + 1] - self.knots_nm[j]);
            }
        }
        let (r, a) = (&self.thresholds_a, &self.weights);
        let mut cumulative = 0.0;
        for i in 0..self.plays {
            let previous = cumulative;
            cumulative += a[i];
            self.inverse_thresholds[i] = (0..=i).map(|j| a[j] * (r[i] - r[j])).sum();
            self.inverse_weights[i] =
                if i == 0 { 1.0 / a[0] } else { -a[i] / (cumulative * previous) };
        }
        let (lo, hi) = (self.current_min_a, self.current_max_a);
        let rest: f64 = (0..self.plays).map(|i| a[i] * (lo + r[i])).sum();
        let top: f64 = (0..self.plays).map(|i| a[i] * (hi - r[i]).max(lo + r[i])).sum();
        self.z_range = (rest, top);
    }

    /// Number of play operators.
    pub fn plays(&self) -> usize {
        self.plays
    }

    /// Number of segments of the output map.
    pub fn segments(&self) -> usize {
        self.segments
    }

    /// Lowest current (the rest state), A.
    pub fn current_min_a(&self) -> f64 {
        self.current_min_a
    }

    /// Highest current, A.
    pub fn current_max_a(&self) -> f64 {
        self.current_max_a
    }

    /// The parameters (slices into the model).
    pub fn parts(&self) -> OperatorParts<'_> {
        OperatorParts {
            thresholds_a: &self.thresholds_a[..self.plays],
            weights: &self.weights[..self.plays],
            knots_nm: &self.knots_nm[..self.segments],
            slopes_a_per_nm: &self.slopes[..self.segments],
            offset_a: self.offset_a,
            current_min_a: self.current_min_a,
            current_max_a: self.current_max_a,
        }
    }

    /// The output map `D(y)`: torque (N·m) → internal variable (A).
    #[inline]
    pub fn output_map(&self, torque_nm: f64) -> f64 {
        let mut j = 0;
        while j + 1 < self.segments && torque_nm >= self.knots_nm[j + 1] {
            j += 1;
        }
        self.knot_levels[j] + self.slopes[j] * (torque_nm - self.knots_nm[j])
    }

    /// `D⁻¹(z)`: internal variable (A) → torque (N·m).
    pub fn output_map_inverse(&self, z: f64) -> f64 {
        let mut j = 0;
        while j + 1 < self.segments && z >= self.knot_levels[j + 1] {
            j += 1;
        }
        self.knots_nm[j] + (z - self.knot_levels[j]) / self.slopes[j]
    }

    /// Forward model: the torque after the current moves to `current_a` (clamped to the range).
    pub fn torque_nm(&self, state: &mut OperatorState, current_a: f64) -> f64 {
        if !state.started {
            for i in 0..self.plays {
                state.plays[i] = self.current_min_a + self.thresholds_a[i];
            }
            state.started = true;
        }
        let x = if current_a.is_finite() { current_a } else { self.current_min_a };
        let x = x.clamp(self.current_min_a, self.current_max_a);
        let z = play_update(&mut state.plays, &self.thresholds_a, &self.weights, self.plays, x);
        self.output_map_inverse(z)
    }

    /// Hysteresis compensation of one demand: the current in `[0, min(limit_a, i_max)]` at which the
    /// model gives `demand_nm`, following the history in `state`. A non-positive or non-finite demand
    /// gives 0 A (and moves the inverse to its rest state, as the brake's current goes to rest).
    #[inline]
    pub fn compensate(
        &self,
        state: &mut OperatorCompensation,
        demand_nm: f64,
        limit_a: f64,
    ) -> f64 {
        let (z_rest, z_top) = self.z_range;
        if !state.started {
            for i in 0..self.plays {
                state.plays[i] = z_rest + self.inverse_thresholds[i];
            }
            state.z = z_rest;
            state.started = true;
        }
        let active = demand_nm.is_finite() && demand_nm > 0.0;
        if !active && state.at_rest {
            return 0.0; // the idle brake of a bidirectional pair costs nothing
        }
        state.at_rest = !active;
        let z = if active { self.output_map(demand_nm).clamp(z_rest, z_top) } else { z_rest };
        if z > state.z {
            state.branch = Branch::Rising;
        } else if z < state.z {
            state.branch = Branch::Falling;
        }
        state.z = z;
        let (r, a) = (&self.inverse_thresholds, &self.inverse_weights);
        let x = play_update(&mut state.plays, r, a, self.plays, z);
        let upper = limit_a.min(self.current_max_a).max(0.0);
        if active && x.is_finite() { x.clamp(0.0, upper) } else { 0.0 }
    }
}

/// Moves the plays (thresholds `r`, weights `a`, first `n`) to input `x`; returns `Σ aᵢ Fᵢ`.
#[inline]
fn play_update(
    plays: &mut [f64; MAX_PLAYS],
    r: &[f64; MAX_PLAYS],
    a: &[f64; MAX_PLAYS],
    n: usize,
    x: f64,
) -> f64 {
    let mut sum = 0.0;
    for i in 0..n.min(MAX_PLAYS) {
        let p = (x - r[i]).max((x + r[i]).min(plays[i]));
        plays[i] = p;
        sum += a[i] * p;
    }
    sum
}

/// `0 ≤ i_min < i_max ≤ CURRENT_LIMIT_A`.
fn check_current_range(lo: f64, hi: f64) -> Result<(f64, f64), ControlError> {
    let lo = check_range("current_min_a", lo, 0.0, CURRENT_LIMIT_A)?;
    let hi = check_range("current_max_a", hi, lo, CURRENT_LIMIT_A)?;
    if hi - lo <= 0.0 {
        return Err(ControlError::OutOfRange {
            field: "current_max_a",
            value: hi,
            min: lo,
            max: CURRENT_LIMIT_A,
        });
    }
    Ok((lo, hi))
}

/// `1 ≤ count ≤ limit`.
fn check_count(field: &'static str, count: usize, limit: usize) -> Result<usize, ControlError> {
    if count == 0 || count > limit {
        return Err(ControlError::Capacity { field, count, limit });
    }
    Ok(count)
}

/// Finite and strictly increasing; with `zero_first` the first value must be 0.
fn check_increasing(
    field: &'static str,
    values: &[f64],
    zero_first: bool,
) -> Result<(), ControlError> {
    let bad = |value| Err(ControlError::NotIncreasing { field, value });
    if zero_first && values[0].abs() > 0.0 {
        return bad(values[0]);
    }
    let mut previous = f64::NEG_INFINITY;
    for &v in values {
        if !v.is_finite() || v <= previous {
            return bad(v);
        }
        previous = v;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn model() -> OperatorModel {
        OperatorModel::new(&OperatorParts {
            thresholds_a: &[0.0, 0.1, 0.25, 0.5],
            weights: &[1.0, 0.3, 0.2, 0.1],
            knots_nm: &[0.15, 1.0, 2.5],
            slopes_a_per_nm: &[0.8, 1.0, 1.4],
            offset_a: 0.2,
            current_min_a: 0.0,
            current_max_a: 2.0,
        })
        .unwrap()
    }

    #[test]
    fn the_inverse_is_exact_along_any_path() {
        let m = model();
        let (mut forward, mut inverse) =
            (OperatorState::default(), OperatorCompensation::default());
        let path = [0.3, 1.2, 0.8, 1.9, 0.4, 1.0, 0.95, 1.5, 0.05, 1.99];
        for (k, &i) in path.iter().enumerate() {
            let t = m.torque_nm(&mut forward, i);
            let back = m.compensate(&mut inverse, t, 2.0);
            assert!((back - i).abs() < 1e-12, "step {k}: {i} → {t} → {back}");
        }
    }

    #[test]
    fn output_map_round_trips() {
        let m = model();
        for k in 0..100 {
            let y = -0.5 + 0.05 * k as f64;
            assert!((m.output_map_inverse(m.output_map(y)) - y).abs() < 1e-12);
        }
    }

    #[test]
    fn bad_parts_name_field_and_limit() {
        let m = model();
        let thresholds = [0.0; 40];
        let parts = OperatorParts { thresholds_a: &thresholds, ..m.parts() };
        assert_eq!(
            OperatorModel::new(&parts),
            Err(ControlError::Capacity { field: "plays", count: 40, limit: MAX_PLAYS })
        );
        let parts = OperatorParts { thresholds_a: &[0.0, 0.2, 0.1, 0.5], ..m.parts() };
        assert!(matches!(OperatorModel::new(&parts), Err(ControlError::NotIncreasing { .. })));
        let parts = OperatorParts { slopes_a_per_nm: &[0.8, 0.0, 1.4], ..m.parts() };
        assert!(OperatorModel::new(&parts).is_err());
    }

    #[test]
    fn no_demand_gives_zero_and_the_limit_caps() {
        let m = model();
        let mut s = OperatorCompensation::default();
        assert!((m.compensate(&mut s, 50.0, 1.5) - 1.5).abs() < 1e-12);
        assert!(m.compensate(&mut s, f64::NAN, 1.5).abs() < 1e-300);
        assert!(m.compensate(&mut s, -1.0, 1.5).abs() < 1e-300);
    }
}

/// The operator-model file (feature `serde`), schema `mrbrake.operator-model` version 1:
///
/// ```json
/// { "schema": "mrbrake.operator-model", "version": 1,
///   "current_min_A": 0.0, "current_max_A": 2.0,
///   "plays":  { "thresholds_A": [0.0, ...], "weights": [1.0, ...] },
///   "output": { "knots_Nm": [...], "slopes_A_per_Nm": [...], "offset_A": 0.0 } }
/// ```
///
/// Lists hold 1 to [`MAX_PLAYS`] (plays) or [`MAX_SEGMENTS`] (output) finite numbers; a longer list
/// is refused while reading, naming its length and the capacity. Other fields (fit statistics) are
/// ignored; another schema name or version is refused. The values are then checked by
/// [`OperatorModel::new`].
#[cfg(feature = "serde")]
mod serde_impl {
    use core::fmt;

    use serde::de::{self, Deserialize, Deserializer, SeqAccess, Visitor};
    use serde::ser::{Serialize, SerializeStruct, Serializer};

    use super::*;

    /// A list of at most `N` finite numbers, read without allocating.
    struct List<const N: usize> {
        values: [f64; N],
        len: usize,
    }

    impl<const N: usize> List<N> {
        fn as_slice(&self) -> &[f64] {
            &self.values[..self.len]
        }
    }

    struct ListVisitor<const N: usize>;

    impl<'de, const N: usize> Visitor<'de> for ListVisitor<N> {
        type Value = List<N>;

        fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            write!(f, "a list of 1 to {N} finite numbers (the controller's fixed capacity)")
        }

        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<List<N>, A::Error> {
            let mut list = List { values: [0.0; N], len: 0 };
            while let Some(v) = seq.next_element::<f64>()? {
                if list.len == N {
                    let mut total = N + 1;
                    while seq.next_element::<de::IgnoredAny>()?.is_some() {
                        total += 1;
                    }
                    return Err(de::Error::invalid_length(total, &self));
                }
                if !v.is_finite() {
                    return Err(de::Error::invalid_value(de::Unexpected::Float(v), &self));
                }
                list.values[list.len] = v;
                list.len += 1;
            }
            if list.len == 0 {
                return Err(de::Error::invalid_length(0, &self));
            }
            Ok(list)
        }
    }

    impl<'de, const N: usize> Deserialize<'de> for List<N> {
        fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
            d.deserialize_seq(ListVisitor::<N>)
        }
    }

    /// The schema name, checked while reading.
    struct SchemaName;

    struct SchemaVisitor;

    impl Visitor<'_> for SchemaVisitor {
        type Value = SchemaName;

        fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            write!(f, "the schema name \"{OPERATOR_SCHEMA}\"")
        }

        fn visit_str<E: de::Error>(self, v: &str) -> Result<SchemaName, E> {
            if v == OPERATOR_SCHEMA {
                Ok(SchemaName)
            } else {
                Err(E::invalid_value(de::Unexpected::Str(v), &self))
            }
        }
    }

    impl<'de> Deserialize<'de> for SchemaName {
        fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
            d.deserialize_str(SchemaVisitor)
        }
    }

    #[derive(serde::Deserialize)]
    struct PlaysObject {
        #[serde(rename = "thresholds_A")]
        thresholds: List<MAX_PLAYS>,
        weights: List<MAX_PLAYS>,
    }

    #[derive(serde::Deserialize)]
    struct OutputObject {
        #[serde(rename = "knots_Nm")]
        knots: List<MAX_SEGMENTS>,
        #[serde(rename = "slopes_A_per_Nm")]
        slopes: List<MAX_SEGMENTS>,
        #[serde(rename = "offset_A")]
        offset: f64,
    }

    #[derive(serde::Deserialize)]
    struct FileObject {
        #[allow(dead_code)]
        schema: SchemaName,
        version: u32,
        #[serde(rename = "current_min_A")]
        current_min: f64,
        #[serde(rename = "current_max_A")]
        current_max: f64,
        plays: PlaysObject,
        output: OutputObject,
    }

    impl<'de> Deserialize<'de> for OperatorModel {
        fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
            let file = FileObject::deserialize(d)?;
            if file.version != OPERATOR_SCHEMA_VERSION {
                return Err(de::Error::custom(format_args!(
                    "{OPERATOR_SCHEMA} version {} is not supported (this mrbrake reads version {})",
                    file.version, OPERATOR_SCHEMA_VERSION
                )));
            }
            OperatorModel::new(&OperatorParts {
                thresholds_a: file.plays.thresholds.as_slice(),
                weights: file.plays.weights.as_slice(),
                knots_nm: file.output.knots.as_slice(),
                slopes_a_per_nm: file.output.slopes.as_slice(),
                offset_a: file.output.offset,
                current_min_a: file.current_min,
                current_max_a: file.current_max,
            })
            .map_err(de::Error::custom)
        }
    }

    /// The `plays` object.
    struct Plays<'a>(&'a OperatorModel);

    impl Serialize for Plays<'_> {
        fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
            let parts = self.0.parts();
            let mut o = s.serialize_struct("Plays", 2)?;
            o.serialize_field("thresholds_A", parts.thresholds_a)?;
            o.serialize_field("weights", parts.weights)?;
            o.end()
        }
    }

    /// The `output` object.
    struct Output<'a>(&'a OperatorModel);

    impl Serialize for Output<'_> {
        fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
            let parts = self.0.parts();
            let mut o = s.serialize_struct("Output", 3)?;
            o.serialize_field("knots_Nm", parts.knots_nm)?;
            o.serialize_field("slopes_A_per_Nm", parts.slopes_a_per_nm)?;
            o.serialize_field("offset_A", &parts.offset_a)?;
            o.end()
        }
    }

    impl Serialize for OperatorModel {
        fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
            let mut o = s.serialize_struct("OperatorModel", 6)?;
            o.serialize_field("schema", OPERATOR_SCHEMA)?;
            o.serialize_field("version", &OPERATOR_SCHEMA_VERSION)?;
            o.serialize_field("current_min_A", &self.current_min_a)?;
            o.serialize_field("current_max_A", &self.current_max_a)?;
            o.serialize_field("plays", &Plays(self))?;
            o.serialize_field("output", &Output(self))?;
            o.end()
        }
    }
}
