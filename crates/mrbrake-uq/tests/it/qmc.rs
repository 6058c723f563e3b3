//! Validation of the scrambled Sobol' points: still a (t, m, s)-net after scrambling (one point per
//! stratum of every dimension for n = 2^m, and the (0, m, 2)-net of the first two dimensions),
//! unbiased, and far more accurate than plain Monte Carlo on a smooth integrand; mapped samples
//! follow their laws.

use mrbrake_optim::rng::Rng;
use mrbrake_uq::distribution::Distribution;
use mrbrake_uq::qmc::{ScrambledSobol, sample};

#[test]
fn every_dimension_is_stratified_for_powers_of_two() {
    for seed in [1, 2, 3] {
        let n = 1 << 10;
        let points = ScrambledSobol::new(8, seed).unwrap().points(n).unwrap();
        for d in 0..8 {
            let mut counts = vec![0usize; n];
            for p in &points {
                assert!(p[d] > 0.0 && p[d] < 1.0);
                counts[(p[d] * n as f64) as usize] += 1;
            }
            assert!(counts.iter().all(|&c| c == 1), "seed {seed}, dimension {d}");
        }
    }
}

#[test]
fn first_two_dimensions_form_a_0_m_2_net() {
    // Sobol' dimensions 1 and 2 are a (0, m, 2)-net: every elementary box of volume 2^-m, of any
    // shape 2^-a × 2^-(m-a), holds exactly one point; linear matrix scrambling keeps this.
    let m = 8;
    let n = 1usize << m;
    for seed in [5, 6] {
        let points = ScrambledSobol::new(2, seed).unwrap().points(n).unwrap();
        for a in 0..=m {
            let (cols, rows) = (1usize << a, 1usize << (m - a));
            let mut counts = vec![0usize; n];
            for p in &points {
                let i = (p[0] * cols as f64) as usize;
                let j = (p[1] * rows as f64) as usize;
                counts[i * rows + j] += 1;
            }
            assert!(counts.iter().all(|&c| c == 1), "seed {seed}, boxes {cols}×{rows}");
        }
    }
}

/// `Π exp(u_i)/(e − 1)` over 6 dimensions: mean 1, variance ((e + 1)/(2(e − 1)))^6 − 1 ≈ 0.605.
fn integrand(u: &[f64]) -> f64 {
    let e = std::f64::consts::E;
    u.iter().map(|x| x.exp() / (e - 1.0)).product()
}

#[test]
fn scrambled_estimates_are_unbiased_and_beat_monte_carlo() {
    let (n, replicates) = (1024, 32);
    let e = std::f64::consts::E;
    let variance = ((e + 1.0) / (2.0 * (e - 1.0))).powi(6) - 1.0;
    let mut qmc = Vec::new();
    let mut mc = Vec::new();
    for seed in 0..replicates {
        let points = ScrambledSobol::new(6, seed).unwrap().points(n).unwrap();
        qmc.push(points.iter().map(|u| integrand(u)).sum::<f64>() / n as f64);
        let mut rng = Rng::new(1000 + seed);
        let plain: f64 =
            (0..n).map(|_| integrand(&(0..6).map(|_| rng.uniform()).collect::<Vec<_>>())).sum();
        mc.push(plain / n as f64);
    }
    let rmse =
        |v: &[f64]| (v.iter().map(|x| (x - 1.0).powi(2)).sum::<f64>() / v.len() as f64).sqrt();
    let (qmc_rmse, mc_rmse) = (rmse(&qmc), rmse(&mc));
    let theoretical_mc = (variance / n as f64).sqrt();
    // Plain MC behaves as theory says; scrambled Sobol' is at least 20 times more accurate.
    assert!((mc_rmse / theoretical_mc - 1.0).abs() < 0.4, "MC {mc_rmse} vs {theoretical_mc}");
    assert!(qmc_rmse < theoretical_mc / 20.0, "QMC {qmc_rmse} vs MC {theoretical_mc}");
    // Unbiased: the mean of the replicates is within 4 standard errors of the exact value.
    let mean = qmc.iter().sum::<f64>() / replicates as f64;
    assert!((mean - 1.0).abs() < 4.0 * qmc_rmse / (replicates as f64).sqrt() + 1e-12);
}

#[test]
fn mapped_samples_follow_their_laws() {
    let inputs = [
        Distribution::normal(1.0, 0.1).unwrap(),
        Distribution::triangular(0.0, 0.2, 1.0).unwrap(),
        Distribution::log_normal(0.0, 0.5).unwrap().truncated(0.5, 3.0).unwrap(),
    ];
    let n = 1024;
    let s = sample(&inputs, n, 9).unwrap();
    assert_eq!(s.len(), n);
    for (i, law) in inputs.iter().enumerate() {
        for p in [0.05, 0.1, 0.5, 0.9, 0.95] {
            let q = law.quantile(p).unwrap();
            let below = s.values.iter().filter(|x| x[i] < q).count() as f64 / n as f64;
            // Stratification: the empirical CDF is within 1/n of the law's at every quantile.
            assert!((below - p).abs() <= 1.0 / n as f64 + 1e-12, "input {i}, p {p}: {below}");
        }
        let (lo, hi) = law.support();
        assert!(s.values.iter().all(|x| x[i] > lo && x[i] < hi));
    }
}
