//! Sampling plans for design studies: full factorial grids, Latin hypercubes and Sobol' sequences.
//!
//! * [`full_factorial`]: every combination of given levels (the plan of a sweep over lists).
//! * [`latin_hypercube`]: McKay, Beckman & Conover (1979), "A comparison of three methods for selecting
//!   values of input variables in the analysis of output from a computer code", Technometrics 21(2),
//!   239–245. Each variable's range is cut into `n` equal strata and every stratum holds exactly one
//!   point; strata are paired across variables by independent random permutations.
//! * [`sobol`]: the Sobol' low-discrepancy sequence (Sobol', USSR Comput. Math. Math. Phys. 7(4), 1967)
//!   generated in Gray-code order (Antonov & Saleev 1979; Bratley & Fox, ACM TOMS 14(1), 1988) with
//!   the direction numbers of Joe & Kuo (2008), "Constructing Sobol sequences with better
//!   two-dimensional projections", SIAM J. Sci. Comput. 30(5), 2635–2654 (file
//!   `new-joe-kuo-6.21201`, first [`MAX_SOBOL_DIMENSION`] dimensions).
//!
//! All plans map unit-cube samples onto the bounds with [`Bounds::from_unit`], so integer variables
//! come out integral with every integer equally represented.

use crate::OptimError;
use crate::rng::Rng;
use crate::space::Bounds;

/// Every combination of the given levels, one `Vec` per design, the **first** variable varying
/// slowest (row-major order, like nested loops with the first variable outermost).
///
/// Returns an empty plan when there are no variables or any variable has no levels.
///
/// ```
/// use mrbrake_optim::sampling::full_factorial;
/// let plan = full_factorial(&[vec![1.0, 2.0], vec![10.0, 20.0, 30.0]]);
/// assert_eq!(plan.len(), 6);
/// assert_eq!(plan[1], vec![1.0, 20.0]);
/// assert_eq!(plan[3], vec![2.0, 10.0]);
/// ```
pub fn full_factorial(levels: &[Vec<f64>]) -> Vec<Vec<f64>> {
    if levels.is_empty() || levels.iter().any(Vec::is_empty) {
        return Vec::new();
    }
    let total: usize = levels.iter().map(Vec::len).product();
    let mut plan = Vec::with_capacity(total);
    // A mixed-radix counter whose last digit turns fastest.
    let mut digits = vec![0usize; levels.len()];
    for _ in 0..total {
        plan.push(digits.iter().zip(levels).map(|(&d, values)| values[d]).collect());
        for position in (0..levels.len()).rev() {
            digits[position] += 1;
            if digits[position] < levels[position].len() {
                break;
            }
            digits[position] = 0;
        }
    }
    plan
}

/// A Latin hypercube of `n` designs over `bounds` (McKay, Beckman & Conover 1979).
///
/// For every variable the unit interval is cut into `n` strata `[k/n, (k+1)/n)`; a random permutation
/// assigns one stratum to each design and the point is placed uniformly inside its stratum, then
/// mapped onto the bounds ([`Bounds::from_unit`]; integers repaired). The bounds should have been
/// checked with [`Bounds::validate`]; `n == 0` gives an empty plan.
pub fn latin_hypercube(n: usize, bounds: &[Bounds], rng: &mut Rng) -> Vec<Vec<f64>> {
    let mut plan = vec![Vec::with_capacity(bounds.len()); n];
    if n == 0 {
        return plan;
    }
    let mut strata: Vec<usize> = (0..n).collect();
    for b in bounds {
        rng.shuffle(&mut strata);
        for (design, &stratum) in plan.iter_mut().zip(&strata) {
            let u = (stratum as f64 + rng.uniform()) / n as f64;
            design.push(b.from_unit(u));
        }
    }
    plan
}

/// The largest dimension [`sobol`] supports (rows of the built-in Joe–Kuo table plus dimension 1).
pub const MAX_SOBOL_DIMENSION: usize = JOE_KUO_2008.len() + 1;

/// Bits of the direction numbers: at most 2^32 − 1 points can be generated.
pub const SOBOL_BITS: usize = 32;

/// Joe & Kuo (2008) direction numbers, file `new-joe-kuo-6.21201`, dimensions 2 to 32: for each
/// dimension `(s, a, [m_1 .. m_s])`, where `s` is the degree of the primitive polynomial, `a` encodes
/// its interior coefficients (most significant bit first) and `m_i` are the initial direction
/// integers (odd, `m_i < 2^i`). Dimension 1 is the van der Corput sequence (all `m_i = 1`).
const JOE_KUO_2008: [(u32, u32, &[u32]); 31] = [
    (1, 0, &[1]),
    (2, 1, &[1, 3]),
    (3, 1, &[1, 3, 1]),
    (3, 2, &[1, 1, 1]),
    (4, 1, &[1, 1, 3, 3]),
    (4, 4, &[1, 3, 5, 13]),
    (5, 2, &[1, 1, 5, 5, 17]),
    (5, 4, &[1, 1, 5, 5, 5]),
    (5, 7, &[1, 1, 7, 11, 19]),
    (5, 11, &[1, 1, 5, 1, 1]),
    (5, 13, &[1, 1, 1, 3, 11]),
    (5, 14, &[1, 3, 5, 5, 31]),
    (6, 1, &[1, 3, 3, 9, 7, 49]),
    (6, 13, &[1, 1, 1, 15, 21, 21]),
    (6, 16, &[1, 3, 1, 13, 27, 49]),
    (6, 19, &[1, 1, 1, 15, 7, 5]),
    (6, 22, &[1, 3, 1, 15, 13, 25]),
    (6, 25, &[1, 1, 5, 5, 19, 61]),
    (7, 1, &[1, 3, 7, 11, 23, 15, 103]),
    (7, 4, &[1, 3, 7, 13, 13, 15, 69]),
    (7, 7, &[1, 1, 3, 13, 7, 35, 63]),
    (7, 8, &[1, 3, 5, 9, 1, 25, 53]),
    (7, 14, &[1, 3, 1, 13, 9, 35, 107]),
    (7, 19, &[1, 3, 1, 5, 27, 61, 31]),
    (7, 21, &[1, 1, 5, 11, 19, 41, 61]),
    (7, 28, &[1, 3, 5, 3, 3, 13, 69]),
    (7, 31, &[1, 1, 7, 13, 1, 19, 1]),
    (7, 32, &[1, 3, 7, 5, 13, 19, 59]),
    (7, 37, &[1, 1, 3, 9, 25, 29, 41]),
    (7, 41, &[1, 3, 5, 13, 23, 1, 55]),
    (7, 42, &[1, 3, 7, 3, 13, 59, 17]),
];

/// The 32 direction numbers `V_1 .. V_32` (as 32-bit fractions) of one Sobol' dimension (0-based
/// `dimension`; 0 is van der Corput).
///
/// `V_i = m_i 2^(32-i)` for `i <= s`; beyond, the recurrence of Bratley & Fox (1988), eq. (2):
/// `V_i = a_1 V_(i-1) ^ a_2 V_(i-2) ^ ... ^ a_(s-1) V_(i-s+1) ^ V_(i-s) ^ (V_(i-s) >> s)`.
fn direction_numbers(dimension: usize) -> [u32; SOBOL_BITS] {
    let mut v = [0u32; SOBOL_BITS];
    if dimension == 0 {
        for (i, vi) in v.iter_mut().enumerate() {
            *vi = 1u32 << (SOBOL_BITS - 1 - i);
        }
        return v;
    }
    let (s, a, m) = JOE_KUO_2008[dimension - 1];
    let s = s as usize;
    for i in 0..SOBOL_BITS {
        if i < s {
            v[i] = m[i] << (SOBOL_BITS - 1 - i);
        } else {
            let mut value = v[i - s] ^ (v[i - s] >> s);
            for k in 1..s {
                if (a >> (s - 1 - k)) & 1 == 1 {
                    value ^= v[i - k];
                }
            }
            v[i] = value;
        }
    }
    v
}

/// The 32 direction numbers `V_1 .. V_32` of Sobol' dimension `dimension` (0-based, below
/// [`MAX_SOBOL_DIMENSION`]; 0 is van der Corput), as 32-bit binary fractions: bit `31 − k` of
/// `V_j` is entry `(k, j)` of the dimension's generator matrix `C` over GF(2) (row `k` = output
/// digit `2^-(k+1)`, column `j` = digit `j` of the point index). These are the numbers
/// [`sobol_unit`] uses; a scrambler (e.g. Matoušek's linear matrix scrambling, which multiplies
/// `C` on the left by a random lower-triangular matrix) needs them to build its own points.
pub fn sobol_direction_numbers(dimension: usize) -> Result<[u32; SOBOL_BITS], OptimError> {
    if dimension >= MAX_SOBOL_DIMENSION {
        return Err(OptimError::SobolDimension {
            requested: dimension + 1,
            max: MAX_SOBOL_DIMENSION,
        });
    }
    Ok(direction_numbers(dimension))
}

/// The first `n` points of the `dimension`-dimensional Sobol' sequence in the unit cube, **skipping**
/// the initial all-zero point (which sits on a corner of the design space).
///
/// Gray-code order (Antonov & Saleev 1979): `X_k = X_(k-1) ^ V_c`, `c` the position of the lowest zero
/// bit of `k − 1`. The first points in two dimensions are `(0.5, 0.5)`, `(0.75, 0.25)`,
/// `(0.25, 0.75)`, `(0.375, 0.375)`, ... as in Joe & Kuo's reference generator.
pub fn sobol_unit(n: usize, dimension: usize) -> Result<Vec<Vec<f64>>, OptimError> {
    if dimension == 0 || dimension > MAX_SOBOL_DIMENSION {
        return Err(OptimError::SobolDimension { requested: dimension, max: MAX_SOBOL_DIMENSION });
    }
    let max_points = u32::MAX as usize;
    if n > max_points {
        return Err(OptimError::SobolPoints { requested: n, max: max_points });
    }
    let directions: Vec<[u32; SOBOL_BITS]> = (0..dimension).map(direction_numbers).collect();
    const SCALE: f64 = 1.0 / 4_294_967_296.0; // 2^-32
    let mut state = vec![0u32; dimension];
    let mut points = Vec::with_capacity(n);
    for k in 1..=n {
        let c = (k - 1).trailing_ones() as usize;
        let point = state
            .iter_mut()
            .zip(&directions)
            .map(|(x, v)| {
                *x ^= v[c];
                f64::from(*x) * SCALE
            })
            .collect();
        points.push(point);
    }
    Ok(points)
}

/// The first `n` Sobol' points (zero point skipped, see [`sobol_unit`]) mapped onto `bounds`
/// ([`Bounds::from_unit`]; integers repaired). Errors for invalid bounds, more than
/// [`MAX_SOBOL_DIMENSION`] variables, or more than 2^32 − 1 points.
pub fn sobol(n: usize, bounds: &[Bounds]) -> Result<Vec<Vec<f64>>, OptimError> {
    crate::space::validate_bounds(bounds)?;
    let unit = sobol_unit(n, bounds.len())?;
    Ok(unit
        .into_iter()
        .map(|u| u.iter().zip(bounds).map(|(&ui, b)| b.from_unit(ui)).collect())
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn joe_kuo_rows_are_well_formed() {
        for (row, &(s, a, m)) in JOE_KUO_2008.iter().enumerate() {
            assert_eq!(m.len(), s as usize, "row {row}");
            assert!(a < (1 << (s - 1)).max(1), "row {row}: a = {a}");
            for (i, &mi) in m.iter().enumerate() {
                assert_eq!(mi % 2, 1, "row {row}: m_{} even", i + 1);
                assert!(mi < (1 << (i + 1)), "row {row}: m_{} too large", i + 1);
            }
        }
        // Polynomials of equal degree must be distinct.
        for i in 0..JOE_KUO_2008.len() {
            for j in 0..i {
                assert!(
                    JOE_KUO_2008[i].0 != JOE_KUO_2008[j].0
                        || JOE_KUO_2008[i].1 != JOE_KUO_2008[j].1
                );
            }
        }
    }

    #[test]
    fn full_factorial_edge_cases() {
        assert!(full_factorial(&[]).is_empty());
        assert!(full_factorial(&[vec![1.0], vec![]]).is_empty());
        assert_eq!(full_factorial(&[vec![3.0]]), vec![vec![3.0]]);
        let plan = full_factorial(&[vec![0.0, 1.0], vec![0.0, 1.0], vec![5.0, 6.0]]);
        assert_eq!(plan.len(), 8);
        assert_eq!(plan[0], vec![0.0, 0.0, 5.0]);
        assert_eq!(plan[1], vec![0.0, 0.0, 6.0]);
        assert_eq!(plan[2], vec![0.0, 1.0, 5.0]);
        assert_eq!(plan[7], vec![1.0, 1.0, 6.0]);
    }

    #[test]
    fn sobol_rejects_bad_dimension_and_bounds() {
        assert!(matches!(sobol_unit(4, 0), Err(OptimError::SobolDimension { .. })));
        assert!(matches!(
            sobol_unit(4, MAX_SOBOL_DIMENSION + 1),
            Err(OptimError::SobolDimension { .. })
        ));
        assert!(sobol_unit(4, MAX_SOBOL_DIMENSION).is_ok());
        assert!(sobol(4, &[Bounds::continuous(1.0, 0.0)]).is_err());
        assert!(sobol_direction_numbers(MAX_SOBOL_DIMENSION - 1).is_ok());
        assert!(matches!(
            sobol_direction_numbers(MAX_SOBOL_DIMENSION),
            Err(OptimError::SobolDimension { .. })
        ));
    }

    #[test]
    fn direction_numbers_rebuild_the_sequence() {
        // Point k (Gray-code order, zero point skipped) is the XOR of the direction numbers
        // selected by the bits of the Gray code of k, as the generator matrices say.
        let points = sobol_unit(64, 5).unwrap();
        for dimension in 0..5 {
            let v = sobol_direction_numbers(dimension).unwrap();
            for (k, point) in points.iter().enumerate() {
                let gray = (k + 1) ^ ((k + 1) >> 1);
                let x = (0..SOBOL_BITS)
                    .filter(|bit| (gray >> bit) & 1 == 1)
                    .fold(0u32, |acc, bit| acc ^ v[bit]);
                assert!((f64::from(x) / 4_294_967_296.0 - point[dimension]).abs() < 1e-15);
            }
        }
    }
}
