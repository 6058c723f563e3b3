//! Seeded, reproducible Gaussian noise: the Box–Muller transform of uniforms drawn from mrbrake's
//! one SplitMix64 stream ([`mrbrake_optim::rng::SplitMix64`], Steele, Lea & Flood 2014), whose
//! sequence is fixed by mrbrake's own code, so a given seed gives the same logs on every platform and
//! for every version of the dependencies.

use mrbrake_optim::rng::SplitMix64;

/// A standard-normal random stream.
#[derive(Debug, Clone)]
pub struct GaussianNoise {
    bits: SplitMix64,
    spare: Option<f64>,
}

impl GaussianNoise {
    /// A stream determined entirely by `seed`.
    pub fn new(seed: u64) -> Self {
        Self { bits: SplitMix64::new(seed), spare: None }
    }

    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.bits.next_u64()
    }

    /// Uniform in the open interval (0, 1): the top 53 bits, offset by half a step.
    pub fn uniform(&mut self) -> f64 {
        ((self.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    /// A standard normal sample (Box–Muller, both outputs used).
    pub fn standard_normal(&mut self) -> f64 {
        if let Some(s) = self.spare.take() {
            return s;
        }
        let (u1, u2) = (self.uniform(), self.uniform());
        let r = (-2.0 * u1.ln()).sqrt();
        let phi = 2.0 * std::f64::consts::PI * u2;
        self.spare = Some(r * phi.sin());
        r * phi.cos()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moments_are_standard_normal_and_seed_reproduces() {
        let mut g = GaussianNoise::new(7);
        let n = 200_000;
        let xs: Vec<f64> = (0..n).map(|_| g.standard_normal()).collect();
        let mean = xs.iter().sum::<f64>() / n as f64;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64;
        assert!(mean.abs() < 0.01 && (var - 1.0).abs() < 0.01, "{mean} {var}");
        let mut h = GaussianNoise::new(7);
        assert!((h.standard_normal() - xs[0]).abs() < 1e-300);
    }

    #[test]
    fn the_stream_is_the_published_splitmix64_sequence() {
        // The rig's logs depend on this sequence: seed 1234567 gives the reference outputs of
        // `splitmix64.c` (as reproduced on Rosetta Code, "Pseudo-random numbers/Splitmix64").
        let mut g = GaussianNoise::new(1_234_567);
        assert_eq!(g.next_u64(), 6_457_827_717_110_365_317);
        assert_eq!(g.next_u64(), 3_203_168_211_198_807_973);
    }
}
