//! A small seeded pseudo-random generator, written here so that optimisation results are
//! reproducible bit for bit whatever happens to the dependency tree.
//!
//! [`Rng`] is xoshiro256** (Blackman & Vigna, "Scrambled linear pseudorandom number generators",
//! ACM Trans. Math. Softw. 47(4), 2021; preprint arXiv:1805.01407, 2018), whose 256-bit state is
//! filled from the 64-bit seed by splitmix64 (Steele, Lea & Flood, "Fast splittable pseudorandom
//! number generators", OOPSLA 2014), as the xoshiro authors recommend. Integers below a bound are
//! drawn without bias by Lemire's multiply-and-reject method (Lemire, "Fast random integer generation
//! in an interval", ACM Trans. Model. Comput. Simul. 29(1), 2019).
//!
//! [`SplitMix64`] is also public: the one SplitMix64 stream of mrbrake, which the virtual rig's
//! sensor noise draws from as well (a counter stream is all a noise generator needs, and the rig's
//! logs stay the same for a given seed).
//!
//! ```
//! use mrbrake_optim::rng::Rng;
//! let mut a = Rng::new(42);
//! let mut b = Rng::new(42);
//! assert_eq!(a.next_u64(), b.next_u64());
//! let u = a.uniform();
//! assert!((0.0..1.0).contains(&u));
//! ```

/// The splitmix64 generator (Steele, Lea & Flood 2014; constants from Vigna's reference
/// `splitmix64.c`): a 64-bit counter advanced by the golden-ratio increment, each value mixed into
/// the output. Period 2^64; every seed is valid. Seeds [`Rng`], and serves on its own where a
/// small, fast stream is enough (the virtual rig's sensor noise).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    /// A stream determined entirely by `seed` (its first output mixes `seed + 0x9E37…7C15`).
    pub const fn new(seed: u64) -> Self {
        Self { state: seed }
    }

    /// The next 64 random bits.
    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
}

/// The xoshiro256** generator (Blackman & Vigna 2018), seeded by splitmix64.
///
/// Period 2^256 − 1; passes BigCrush. Not cryptographic. The stream for a given seed is fixed by this
/// file alone, so runs are reproducible across platforms and dependency updates.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Rng {
    state: [u64; 4],
}

impl Rng {
    /// A generator whose state is four successive splitmix64 outputs from `seed`.
    ///
    /// splitmix64 is a bijection of its counter, so the four outputs are distinct and the state can
    /// never be all zero (the one state xoshiro must avoid).
    pub fn new(seed: u64) -> Self {
        let mut sm = SplitMix64::new(seed);
        let state = [sm.next_u64(), sm.next_u64(), sm.next_u64(), sm.next_u64()];
        Self { state }
    }

    /// The next 64 random bits (xoshiro256**: output `rotl(s1 * 5, 7) * 9`, then the linear state
    /// update of Blackman & Vigna 2018, Fig. 1).
    pub fn next_u64(&mut self) -> u64 {
        let s = &mut self.state;
        let result = s[1].wrapping_mul(5).rotate_left(7).wrapping_mul(9);
        let t = s[1] << 17;
        s[2] ^= s[0];
        s[3] ^= s[1];
        s[1] ^= s[2];
        s[0] ^= s[3];
        s[2] ^= t;
        s[3] = s[3].rotate_left(45);
        result
    }

    /// A uniform double in `[0, 1)`: the top 53 bits times 2^-53 (every representable multiple of
    /// 2^-53 equally likely).
    pub fn uniform(&mut self) -> f64 {
        const SCALE: f64 = 1.0 / (1u64 << 53) as f64;
        (self.next_u64() >> 11) as f64 * SCALE
    }

    /// A uniform double in `[lower, upper)` (or exactly `lower` when the interval is empty).
    pub fn uniform_in(&mut self, lower: f64, upper: f64) -> f64 {
        lower + (upper - lower) * self.uniform()
    }

    /// A uniform integer in `0..n`, without modulo bias (Lemire 2019, Algorithm 5). Returns 0 when
    /// `n == 0`, the only value a caller asking for "an index into nothing" could use.
    pub fn below(&mut self, n: u64) -> u64 {
        if n == 0 {
            return 0;
        }
        let mut product = u128::from(self.next_u64()) * u128::from(n);
        let mut low = product as u64;
        if low < n {
            // 2^64 mod n values of the low word would over-represent some results: reject them.
            let threshold = n.wrapping_neg() % n;
            while low < threshold {
                product = u128::from(self.next_u64()) * u128::from(n);
                low = product as u64;
            }
        }
        (product >> 64) as u64
    }

    /// A uniform index in `0..n` (see [`Rng::below`]).
    pub fn index(&mut self, n: usize) -> usize {
        // usize is at most 64 bits on every supported platform, so both conversions are lossless.
        self.below(n as u64) as usize
    }

    /// True with probability `p` (false for `p <= 0`, true for `p >= 1`).
    pub fn bernoulli(&mut self, p: f64) -> bool {
        self.uniform() < p
    }

    /// Shuffles `items` uniformly in place (Fisher–Yates / Durstenfeld, Knuth TAOCP vol. 2,
    /// Algorithm 3.4.2P).
    pub fn shuffle<T>(&mut self, items: &mut [T]) {
        for i in (1..items.len()).rev() {
            let j = self.index(i + 1);
            items.swap(i, j);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splitmix64_matches_the_published_sequence() {
        // Reference outputs for seed 1234567 from the splitmix64 reference implementation
        // (as reproduced on Rosetta Code, "Pseudo-random numbers/Splitmix64").
        let mut s = SplitMix64::new(1_234_567);
        let expected = [
            6_457_827_717_110_365_317u64,
            3_203_168_211_198_807_973,
            9_817_491_932_198_370_423,
            4_593_380_528_125_082_431,
            16_408_922_859_458_223_821,
        ];
        for e in expected {
            assert_eq!(s.next_u64(), e);
        }
    }

    #[test]
    fn xoshiro256starstar_matches_hand_computed_outputs_from_state_1_2_3_4() {
        // Worked by hand from the algorithm: s1 = 2 -> rotl(10, 7) * 9 = 11520; after one update
        // s1 = 0 -> 0; after two updates s1 = 262149 -> rotl(1310745, 7) * 9 = 1509978240.
        let mut rng = Rng { state: [1, 2, 3, 4] };
        assert_eq!(rng.next_u64(), 11_520);
        assert_eq!(rng.next_u64(), 0);
        assert_eq!(rng.next_u64(), 1_509_978_240);
    }

    #[test]
    fn same_seed_same_stream_different_seed_different_stream() {
        let a: Vec<u64> = {
            let mut r = Rng::new(7);
            (0..8).map(|_| r.next_u64()).collect()
        };
        let b: Vec<u64> = {
            let mut r = Rng::new(7);
            (0..8).map(|_| r.next_u64()).collect()
        };
        let c: Vec<u64> = {
            let mut r = Rng::new(8);
            (0..8).map(|_| r.next_u64()).collect()
        };
        assert_eq!(a, b);
        assert_ne!(a, c);
    }

    #[test]
    fn uniform_is_in_unit_interval_with_mean_near_one_half() {
        let mut rng = Rng::new(1);
        let n = 100_000;
        let mut sum = 0.0;
        for _ in 0..n {
            let u = rng.uniform();
            assert!((0.0..1.0).contains(&u));
            sum += u;
        }
        let mean = sum / f64::from(n);
        // Standard error of the mean is sqrt(1/12 / n) = 9.1e-4; allow 5 sigma.
        assert!((mean - 0.5).abs() < 5.0 * 9.13e-4, "mean {mean}");
    }

    #[test]
    fn below_is_unbiased_over_a_small_range() {
        let mut rng = Rng::new(99);
        let n = 7u64;
        let draws = 70_000;
        let mut counts = [0u32; 7];
        for _ in 0..draws {
            let k = rng.below(n);
            assert!(k < n);
            counts[k as usize] += 1;
        }
        // Chi-square with 6 degrees of freedom: the 99.9 % quantile is 22.46.
        let expected = f64::from(draws) / 7.0;
        let chi2: f64 = counts.iter().map(|&c| (f64::from(c) - expected).powi(2) / expected).sum();
        assert!(chi2 < 22.46, "chi2 {chi2}, counts {counts:?}");
        assert_eq!(rng.below(0), 0);
        assert_eq!(rng.below(1), 0);
    }

    #[test]
    fn shuffle_is_a_permutation() {
        let mut rng = Rng::new(3);
        let mut v: Vec<usize> = (0..50).collect();
        rng.shuffle(&mut v);
        let mut sorted = v.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..50).collect::<Vec<_>>());
        assert_ne!(v, sorted);
    }
}
