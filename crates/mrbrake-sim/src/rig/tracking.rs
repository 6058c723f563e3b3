//! Torque tracking on the virtual rig: a torque demand is turned into current by an inverse model
//! ([`mrbrake_control::TorqueInverse`]: the polynomial branches or the operator model) and the
//! measured torque is scored by the RMSE of thesis (5.2) ([`mrbrake_sysid::tracking`]).
//!
//! The demands: sinusoids (thesis §5.3.2 at 0.1 rad/s) and a band-limited random demand, a multisine
//! of log-spaced components with random phases (Pintelon & Schoukens 2012, *System Identification: A
//! Frequency Domain Approach*, 2nd ed., §5.2: a random-phase multisine is a band-limited random
//! signal), scaled to the requested torque interval.

use mrbrake_control::{TorqueInverse, TorqueInverseState};

use super::noise::GaussianNoise;
use super::{Plant, RigConfig, rates};
use crate::SimError;

/// A torque demand, N·m, as a function of time.
#[derive(Debug, Clone, PartialEq)]
pub enum Demand {
    /// `mid + amplitude·sin(ω t)`.
    Sine {
        /// Centre, N·m.
        mid_nm: f64,
        /// Amplitude, N·m.
        amplitude_nm: f64,
        /// Angular frequency, rad/s.
        omega_rad_s: f64,
    },
    /// `mid + Σₖ gₖ sin(ωₖ t + φₖ)` with log-spaced `ωₖ`, random `φₖ` and a common gain chosen so that the
    /// demand spans `mid ± amplitude` over the run.
    Multisine {
        /// Centre, N·m.
        mid_nm: f64,
        /// Components: (ω rad/s, phase rad, gain N·m).
        components: Vec<(f64, f64, f64)>,
    },
}

impl Demand {
    /// The demand at time `t_s`.
    pub fn at(&self, t_s: f64) -> f64 {
        match self {
            Self::Sine { mid_nm, amplitude_nm, omega_rad_s } => {
                mid_nm + amplitude_nm * (omega_rad_s * t_s).sin()
            }
            Self::Multisine { mid_nm, components } => {
                mid_nm + components.iter().map(|(w, p, g)| g * (w * t_s + p).sin()).sum::<f64>()
            }
        }
    }

    /// A random-phase multisine of `count` components log-spaced over `[ω_lo, ω_hi]` rad/s, scaled so
    /// that it spans exactly `mid ± amplitude` over `[0, duration_s]` (sampled at 1 kHz).
    pub fn band_limited(
        mid_nm: f64,
        amplitude_nm: f64,
        band_rad_s: (f64, f64),
        count: usize,
        duration_s: f64,
        seed: u64,
    ) -> Self {
        let mut noise = GaussianNoise::new(seed);
        let ratio = band_rad_s.1 / band_rad_s.0;
        let components: Vec<(f64, f64, f64)> = (0..count)
            .map(|k| {
                let w = band_rad_s.0 * ratio.powf(k as f64 / (count.max(2) - 1) as f64);
                let phase = noise.standard_normal().atan2(noise.standard_normal());
                (w, phase, 1.0)
            })
            .collect();
        let unscaled = Self::Multisine { mid_nm: 0.0, components: components.clone() };
        let n = (duration_s * 1000.0) as usize;
        let peak = (0..=n).map(|k| unscaled.at(k as f64 * 1e-3).abs()).fold(1e-300, f64::max);
        let gain = amplitude_nm / peak;
        Self::Multisine {
            mid_nm,
            components: components.into_iter().map(|(w, p, _)| (w, p, gain)).collect(),
        }
    }
}

/// Runs `demand` for `duration_s` through `inverse` on the rig's plant (both start at rest, 0 A) and
/// returns (time s, demand N·m, measured torque N·m, current A) per logged sample.
pub fn track(
    config: &RigConfig,
    demand: &Demand,
    duration_s: f64,
    inverse: &TorqueInverse,
    seed: u64,
) -> Result<Vec<[f64; 4]>, SimError> {
    config.validate("rig configuration")?;
    let (dt, sub) = rates(config);
    let mut plant = Plant::new(config, dt, seed)?;
    plant.settle(0.0);
    let mut state = TorqueInverseState::default();
    let limit_a = config.brake.current_max_a;
    let n = (duration_s / dt).ceil() as usize;
    let mut out = Vec::with_capacity(n / sub + 1);
    for k in 0..n {
        let t = k as f64 * dt;
        let d = demand.at(t);
        let current = inverse.compensate(&mut state, d, limit_a, 0.0);
        let logged = k % sub == 0;
        let s = plant.step(current, logged);
        if logged {
            out.push([t, d, s.measured_torque_nm, current]);
        }
    }
    Ok(out)
}

/// One demand of the tracking suite: name, demand, run length (s), start of the scored part (s).
pub type TrackingCase = (&'static str, Demand, f64, f64);

/// The tracking suite over the frequency-response torque interval `[T_lo, T_hi]` of the configuration
/// (default 0.5–3.5 N·m): (a) the full interval at 0.1 rad/s (thesis Fig. 5.8), (b) 50 % and 25 % of
/// it about its middle at 0.1 rad/s, (c) a band-limited random demand (16 components, 0.1–2 rad/s)
/// over the full interval. Sinusoids run 1.25 periods and are scored over the last period; the random
/// demand runs 120 s and is scored after 5 s.
pub fn tracking_suite(config: &RigConfig) -> Vec<TrackingCase> {
    let f = &config.frequency_response;
    let mid = 0.5 * (f.torque_min_nm + f.torque_max_nm);
    let half = 0.5 * (f.torque_max_nm - f.torque_min_nm);
    let period = 2.0 * std::f64::consts::PI / 0.1;
    let sine =
        |share: f64| Demand::Sine { mid_nm: mid, amplitude_nm: share * half, omega_rad_s: 0.1 };
    let random =
        Demand::band_limited(mid, half, (0.1, 2.0), 16, 120.0, config.seed.wrapping_add(7));
    vec![
        ("sine_full_range", sine(1.0), 1.25 * period, 0.25 * period),
        ("sine_50_percent", sine(0.5), 1.25 * period, 0.25 * period),
        ("sine_25_percent", sine(0.25), 1.25 * period, 0.25 * period),
        ("band_limited_random", random, 120.0, 5.0),
    ]
}

/// The score of one tracking run: RMSE (5.2) over the scored part.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct TrackingScore {
    /// The demand's name in the suite.
    pub demand: &'static str,
    /// The log written for it.
    pub file: String,
    /// RMSE, N·m.
    #[serde(rename = "rmse_Nm")]
    pub rmse_nm: f64,
    /// RMSE in % of the scored demand's range.
    pub rmse_percent_of_range: f64,
}

/// Runs the suite through `inverse` (noise seeds `seed + 101 …`, none shared with the identification
/// protocols): one log per demand (`time_s, input, output, current_A`), `manifest.csv` with the scores,
/// and the scores.
pub fn tracking_logs(
    config: &RigConfig,
    inverse: &TorqueInverse,
) -> Result<(Vec<super::RigFile>, Vec<TrackingScore>), SimError> {
    let mut files = Vec::new();
    let mut scores = Vec::new();
    let mut manifest = String::from("demand,file,rmse_Nm,rmse_percent_of_range\n");
    for (k, (name, demand, duration, skip)) in tracking_suite(config).into_iter().enumerate() {
        let run =
            track(config, &demand, duration, inverse, config.seed.wrapping_add(101 + k as u64))?;
        let scored: Vec<&[f64; 4]> = run.iter().filter(|s| s[0] >= skip).collect();
        let d: Vec<f64> = scored.iter().map(|s| s[1]).collect();
        let m: Vec<f64> = scored.iter().map(|s| s[2]).collect();
        let e = mrbrake_sysid::tracking::tracking_error(&d, &m)?;
        let file = format!("track_{name}.csv");
        let mut csv = String::from("time_s,input,output,current_A\n");
        for row in &run {
            super::push_row(&mut csv, row);
        }
        manifest.push_str(&format!("{name},{file},{},{}\n", e.rmse_nm, e.rmse_percent_of_range));
        scores.push(TrackingScore {
            demand: name,
            file: file.clone(),
            rmse_nm: e.rmse_nm,
            rmse_percent_of_range: e.rmse_percent_of_range,
        });
        files.push(super::RigFile { name: file, csv });
    }
    files.push(super::RigFile { name: "manifest.csv".into(), csv: manifest });
    Ok((files, scores))
}
