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
