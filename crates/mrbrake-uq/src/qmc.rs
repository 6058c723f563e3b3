//! Quasi-Monte Carlo samples: scrambled Sobol' points in the unit cube, mapped onto the inputs'
//! laws by their quantile functions, and the model evaluated on them in parallel.
//!
//! # Scrambling
//!
//! The Sobol' points of dimension `j` are `x = C_j a` over GF(2): `a` the binary digits of the
//! point's index, `C_j` the generator matrix whose columns are the direction numbers of
//! [`mrbrake_optim::sampling::sobol_direction_numbers`] (Joe & Kuo 2008). Scrambling applies
//! Matoušek's **linear matrix scrambling with a random digital shift** (J. Matoušek, "On the
//! L2-discrepancy for anchored boxes", J. Complexity 14(4), 527–556, 1998; the scheme of
//! SciPy's `qmc.Sobol(scramble=True)`): `x' = L_j C_j a ⊕ e_j`, with `L_j` a random
//! lower-triangular binary matrix with unit diagonal and `e_j` a random 32-bit shift. Because `L_j`
//! is lower triangular and invertible, the first `k` output digits are a bijection of the first
//! `k` digits of `C_j a`: every elementary interval keeps its number of points, so a
//! `(t, m, s)`-net stays a `(t, m, s)`-net, while each point becomes uniformly distributed on the
//! unit cube (Owen, "Randomly permuted (t,m,s)-nets and (t,s)-sequences", 1995, and Matoušek 1998)
//! and the mean of any integrand over the points an unbiased estimate.
//!
//! Points are produced in Gray-code order (Antonov & Saleev 1979) **starting from index 0**: the
//! first `2^m` points are a scrambled `(t, m, s)`-net, so sample sizes should be powers of two. A
//! point's 32-bit value `x` maps to `(x + ½) 2^-32`, the centre of its finest cell, which lies
//! strictly inside `(0, 1)` (quantiles of unbounded laws stay finite) and inside the same elementary
//! intervals as `x`.

use crate::distribution::Distribution;
use crate::{RunError, UqError};
use mrbrake_optim::rng::Rng;
use mrbrake_optim::sampling::{MAX_SOBOL_DIMENSION, SOBOL_BITS, sobol_direction_numbers};
use rayon::prelude::*;

/// The largest number of coordinates (points × dimension) [`ScrambledSobol::points`] and
/// [`sample`] produce (2^24, 128 MiB of `f64`): far beyond what a propagation through an expensive
/// model needs (2 million points of 8 inputs), and small enough that the points fit in memory.
pub const MAX_COORDINATES: usize = 1 << 24;

/// A scrambled Sobol' sequence (module docs): the scrambled direction numbers and the digital
/// shift of each dimension, fixed by the seed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ScrambledSobol {
    directions: Vec<[u32; SOBOL_BITS]>,
    shifts: Vec<u32>,
}

impl ScrambledSobol {
    /// The sequence in `dimension` dimensions (1 to [`MAX_SOBOL_DIMENSION`]) scrambled by a
    /// generator seeded with `seed`: the same seed gives the same points on every platform.
    pub fn new(dimension: usize, seed: u64) -> Result<Self, UqError> {
        if dimension == 0 || dimension > MAX_SOBOL_DIMENSION {
            return Err(mrbrake_optim::OptimError::SobolDimension {
                requested: dimension,
                max: MAX_SOBOL_DIMENSION,
            }
            .into());
        }
        let mut rng = Rng::new(seed);
        let mut directions = Vec::with_capacity(dimension);
        let mut shifts = Vec::with_capacity(dimension);
        for j in 0..dimension {
            let v = sobol_direction_numbers(j)?;
            directions.push(scramble_matrix(&v, &mut rng));
            shifts.push(rng.next_u64() as u32);
        }
        Ok(Self { directions, shifts })
    }

    /// The number of dimensions.
    pub fn dimension(&self) -> usize {
        self.directions.len()
    }

    /// The first `n` points (index 0 included), each a `Vec` of `dimension` coordinates in
    /// `(0, 1)`. Errors when `n × dimension` exceeds [`MAX_COORDINATES`].
    pub fn points(&self, n: usize) -> Result<Vec<Vec<f64>>, UqError> {
        if n.saturating_mul(self.dimension()) > MAX_COORDINATES {
            return Err(UqError::InvalidOption {
                name: "samples",
                value: n as f64,
                allowed: "at most 2^24 = 16 777 216 samples × inputs",
            });
        }
        const SCALE: f64 = 1.0 / 4_294_967_296.0; // 2^-32
        let to_unit = |x: u32| (f64::from(x) + 0.5) * SCALE;
        let mut state = self.shifts.clone();
        let mut points = Vec::with_capacity(n);
        for k in 0..n {
            if k > 0 {
                // Gray code: going from index k − 1 to k flips digit `trailing_zeros(k)`.
                let c = k.trailing_zeros() as usize;
                for (x, v) in state.iter_mut().zip(&self.directions) {
                    *x ^= v[c];
                }
            }
            points.push(state.iter().map(|&x| to_unit(x)).collect());
        }
        Ok(points)
    }
}

/// Multiplies the generator matrix given by its columns `v` (32-bit binary fractions, most
/// significant bit = first digit) on the left by a random lower-triangular binary matrix with unit
/// diagonal: output digit `i` is digit `i` plus (mod 2) a random subset of digits `0..i`.
fn scramble_matrix(v: &[u32; SOBOL_BITS], rng: &mut Rng) -> [u32; SOBOL_BITS] {
    // Row i of L below the diagonal: a random mask over the i more significant digits.
    let rows: Vec<u32> = (0..SOBOL_BITS)
        .map(|i| if i == 0 { 0 } else { (rng.next_u64() as u32) & (u32::MAX << (SOBOL_BITS - i)) })
        .collect();
    let mut scrambled = [0u32; SOBOL_BITS];
    for (out, &column) in scrambled.iter_mut().zip(v) {
        for (i, &row) in rows.iter().enumerate() {
            let position = SOBOL_BITS - 1 - i;
            let digit = ((column >> position) & 1) ^ ((row & column).count_ones() & 1);
            *out |= digit << position;
        }
    }
    scrambled
}

/// A quasi-Monte Carlo sample of the inputs: the unit-cube points and the input values they map
/// to (`values[k][i] = F_i⁻¹(unit[k][i])`).
#[derive(Debug, Clone, PartialEq)]
pub struct Sample {
    /// The scrambled Sobol' points, one row per sample: the inputs' CDF values `u = F(x)`, which is
    /// what the polynomial-chaos fit of [`crate::pce`] takes.
    pub unit: Vec<Vec<f64>>,
    /// The input values, one row per sample, one column per input, in the inputs' SI units.
    pub values: Vec<Vec<f64>>,
}

/// `n` scrambled Sobol' samples (seeded by `seed`) of independent inputs with the given laws,
/// each coordinate mapped by its input's quantile function. `n` should be a power of two (module
/// docs).
///
/// ```
/// use mrbrake_uq::{distribution::Distribution, qmc::sample};
/// let inputs = [Distribution::normal(1.0, 0.1)?, Distribution::uniform(0.8, 1.0)?];
/// let s = sample(&inputs, 256, 7)?;
/// assert_eq!(s.values.len(), 256);
/// let mean: f64 = s.values.iter().map(|x| x[0]).sum::<f64>() / 256.0;
/// assert!((mean - 1.0).abs() < 1e-3);
/// # Ok::<(), mrbrake_uq::UqError>(())
/// ```
pub fn sample(inputs: &[Distribution], n: usize, seed: u64) -> Result<Sample, UqError> {
    let unit = ScrambledSobol::new(inputs.len(), seed)?.points(n)?;
    let values = unit
        .iter()
        .map(|u| u.iter().zip(inputs).map(|(&p, law)| law.quantile(p)).collect())
        .collect::<Result<Vec<Vec<f64>>, UqError>>()?;
    Ok(Sample { unit, values })
}

impl Sample {
    /// The number of samples.
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// True when there are no samples.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// Evaluates `model` on every sample's input values in parallel (rayon), returning one output
    /// vector per sample in sample order. The first model error (in sample order) is returned
    /// unchanged as [`RunError::Model`]; outputs of different lengths are a broken contract.
    pub fn evaluate<F, E>(&self, model: F) -> Result<Vec<Vec<f64>>, RunError<E>>
    where
        F: Fn(&[f64]) -> Result<Vec<f64>, E> + Sync,
        E: Send,
    {
        let outputs: Vec<Vec<f64>> = self
            .values
            .par_iter()
            .map(|x| model(x))
            .collect::<Result<_, E>>()
            .map_err(RunError::Model)?;
        let width = outputs.first().map_or(0, Vec::len);
        if let Some(k) = outputs.iter().position(|y| y.len() != width) {
            return Err(UqError::ModelContract(format!(
                "sample {k} has {} outputs, sample 0 has {width}",
                outputs[k].len()
            ))
            .into());
        }
        Ok(outputs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_seed_same_points_other_seed_other_points() {
        let a = ScrambledSobol::new(3, 1).unwrap().points(16).unwrap();
        let b = ScrambledSobol::new(3, 1).unwrap().points(16).unwrap();
        let c = ScrambledSobol::new(3, 2).unwrap().points(16).unwrap();
        assert_eq!(a, b);
        assert_ne!(a, c);
    }

    #[test]
    fn bad_dimension_and_count_are_input_errors() {
        assert!(ScrambledSobol::new(0, 1).is_err());
        assert!(ScrambledSobol::new(MAX_SOBOL_DIMENSION + 1, 1).is_err());
        let s = ScrambledSobol::new(1, 1).unwrap();
        assert!(matches!(s.points(MAX_COORDINATES + 1), Err(UqError::InvalidOption { .. })));
        let wide = ScrambledSobol::new(8, 1).unwrap();
        assert!(matches!(wide.points(usize::MAX), Err(UqError::InvalidOption { .. })));
    }

    #[test]
    fn scrambling_keeps_the_matrix_invertible_digit_by_digit() {
        // The unscrambled van der Corput matrix is the identity; after scrambling, column j must
        // keep digit j set and have no digit above j (L lower triangular, unit diagonal).
        let v = sobol_direction_numbers(0).unwrap();
        let scrambled = scramble_matrix(&v, &mut Rng::new(3));
        for (j, &column) in scrambled.iter().enumerate() {
            let top = SOBOL_BITS - 1 - j;
            assert_eq!((column >> top) & 1, 1, "digit {j} lost");
            assert_eq!(column >> top, 1, "column {j} has digits above the diagonal");
        }
    }

    #[test]
    fn evaluate_passes_model_errors_and_checks_lengths() {
        let inputs = [Distribution::uniform(0.0, 1.0).unwrap()];
        let s = sample(&inputs, 8, 1).unwrap();
        let out = s.evaluate(|x| Ok::<_, String>(vec![2.0 * x[0]])).unwrap();
        assert!((out[3][0] - 2.0 * s.values[3][0]).abs() < 1e-15);
        let failed = s.evaluate(|_| Err::<Vec<f64>, _>("fea".to_string()));
        assert!(matches!(failed, Err(RunError::Model(ref m)) if m == "fea"));
        let ragged = s.evaluate(|x| Ok::<_, String>(vec![0.0; 1 + usize::from(x[0] > 0.5)]));
        assert!(matches!(ragged, Err(RunError::Uq(UqError::ModelContract(_)))));
    }
}
