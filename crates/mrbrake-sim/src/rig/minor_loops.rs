//! The minor-loop protocol (`mrbrake rig minor-loops`): current ramps between turning points inside
//! the range, so the log shows the brake's minor loops, for the identification of a hysteresis model
//! that reproduces them ([`mrbrake_sysid::operator_fit`]).
//!
//! The current ramps at a constant rate (quasi-static, like the characterisation's 0.1 A/s) through
//! three parts, each starting from rest at 0 A:
//!
//! 1. **First-order reversal curves from below**: 0 → `αₖ` → 0 for `αₖ = k·I_max/n`, `k = 1…n`
//!    (the descending reversal curves of FORC analysis: Mayergoyz 1986, IEEE Trans. Magn. 22(5),
//!    603–608; Pike, Roberts & Verosub 1999, J. Appl. Phys. 85, 6660).
//! 2. **First-order reversal curves from above**: 0 → I_max → `βₖ` → I_max for
//!    `βₖ = (k−1)·I_max/n`, then back to 0.
//! 3. **Decaying triangles** about mid-range: `I_max/2 ± Aₖ`, `Aₖ = (I_max/2)·dᵏ`, alternating above
//!    and below, `m` half-cycles (the nested loops of an AC demagnetisation), then back to 0.
//!
//! A rest of `pause_s` at 0 A separates the parts. The log has the characterisation's columns
//! (`time_s, current_A, torque_Nm, speed_rad_s`), so a lab can run the same current program on a real
//! brake and feed `mrbrake characterize --operators`; `manifest.csv` lists every ramp.

use serde::{Deserialize, Serialize};

use super::{Plant, RigConfig, RigFile, push_row, rates};
use crate::SimError;
use mrbrake_error::FieldError;

/// `[minor_loops]` of the rig configuration.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MinorLoopProtocol {
    /// Ramp rate of the current, A/s.
    #[serde(rename = "ramp_rate_A_per_s")]
    pub ramp_rate_a_per_s: f64,
    /// Reversal points per family of first-order reversal curves, 1..=50.
    pub reversal_points: usize,
    /// Half-cycles of the decaying triangles, 0..=50.
    pub triangle_half_cycles: usize,
    /// Amplitude ratio between successive half-cycles, in (0, 1).
    pub triangle_decay: f64,
    /// Rest at 0 A between the parts (and at the start), s.
    pub pause_s: f64,
}

impl Default for MinorLoopProtocol {
    /// 0.2 A/s, five reversal points per family, twelve half-cycles decaying by 0.8, 2 s rests.
    fn default() -> Self {
        Self {
            ramp_rate_a_per_s: 0.2,
            reversal_points: 5,
            triangle_half_cycles: 12,
            triangle_decay: 0.8,
            pause_s: 2.0,
        }
    }
}

impl MinorLoopProtocol {
    /// Checks ranges; `Err((field, message))` for the first bad field.
    pub fn check(&self, _current_max_a: f64) -> Result<(), (&'static str, String)> {
        let r = self.ramp_rate_a_per_s;
        if !(r.is_finite() && r > 0.0) {
            return Err(("minor_loops.ramp_rate_A_per_s", format!("{r} must be > 0")));
        }
        if !(1..=50).contains(&self.reversal_points) {
            let msg = format!("{} is outside 1..=50", self.reversal_points);
            return Err(("minor_loops.reversal_points", msg));
        }
        if self.triangle_half_cycles > 50 {
            let msg = format!("{} is outside 0..=50", self.triangle_half_cycles);
            return Err(("minor_loops.triangle_half_cycles", msg));
        }
        let d = self.triangle_decay;
        if !(d.is_finite() && d > 0.0 && d < 1.0) {
            return Err(("minor_loops.triangle_decay", format!("{d} is outside (0, 1)")));
        }
        if !(self.pause_s.is_finite() && self.pause_s >= 0.0) {
            return Err(("minor_loops.pause_s", format!("{} must be ≥ 0", self.pause_s)));
        }
        Ok(())
    }
}

/// One ramp of the program: its part, start and end current.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ramp {
    /// `forc_from_below`, `forc_from_above`, `decaying_triangles` or `rest`.
    pub part: &'static str,
    /// Current at the start, A.
    pub from_a: f64,
    /// Current at the end, A (equal to `from_a` for a rest).
    pub to_a: f64,
    /// Duration, s.
    pub duration_s: f64,
}

/// The current program as ramps (module docs).
pub fn program(config: &RigConfig) -> Vec<Ramp> {
    let p = &config.minor_loops;
    let i_max = config.brake.current_max_a;
    let n = p.reversal_points;
    let mut points: Vec<(&'static str, f64)> = Vec::new();
    for k in 1..=n {
        let alpha = i_max * k as f64 / n as f64;
        points.extend([("forc_from_below", alpha), ("forc_from_below", 0.0), ("rest", 0.0)]);
    }
    points.push(("forc_from_above", i_max));
    for k in 1..=n {
        let beta = i_max * (k - 1) as f64 / n as f64;
        points.extend([("forc_from_above", beta), ("forc_from_above", i_max)]);
    }
    points.extend([("forc_from_above", 0.0), ("rest", 0.0)]);
    let mid = 0.5 * i_max;
    for k in 0..p.triangle_half_cycles {
        let amplitude = mid * p.triangle_decay.powi(k as i32);
        let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
        points.push(("decaying_triangles", mid + sign * amplitude));
    }
    points.extend([("decaying_triangles", 0.0), ("rest", 0.0)]);
    let mut ramps = vec![Ramp { part: "rest", from_a: 0.0, to_a: 0.0, duration_s: p.pause_s }];
    let mut at = 0.0;
    for (part, to) in points {
        let duration_s =
            if part == "rest" { p.pause_s } else { (to - at).abs() / p.ramp_rate_a_per_s };
        if duration_s > 0.0 {
            ramps.push(Ramp { part, from_a: at, to_a: to, duration_s });
        }
        at = to;
    }
    ramps
}

/// A ramp with its start and end time, s.
pub type TimedRamp = (Ramp, f64, f64);

/// Samples (time s, current A, torque N·m, speed rad/s) of the minor-loop program, and the ramps with
/// their start and end times.
pub fn minor_loop_samples(config: &RigConfig) -> Result<(Vec<[f64; 4]>, Vec<TimedRamp>), SimError> {
    config.validate("rig configuration")?;
    let (dt, sub) = rates(config);
    let mut plant = Plant::new(config, dt, config.seed)?;
    plant.settle(0.0);
    let ramps = program(config);
    let total_s: f64 = ramps.iter().map(|r| r.duration_s).sum();
    let steps = total_s * config.daq.output_rate_hz;
    if steps.is_nan() || steps > super::MAX_RUN_STEPS {
        return Err(FieldError::new(
            "minor_loops",
            format!(
                "rig configuration: the program is too long ({total_s:.3e} s): raise \
                 ramp_rate_A_per_s or lower pause_s, reversal_points or triangle_half_cycles"
            ),
        )
        .with_value(format!("{steps:.3e} output steps"))
        .with_allowed(format!("<= {:.0e} output steps", super::MAX_RUN_STEPS))
        .into());
    }
    let mut timed = Vec::with_capacity(ramps.len());
    let mut samples = Vec::new();
    let (mut t0, mut k) = (0.0, 0usize);
    for ramp in ramps {
        let t1 = t0 + ramp.duration_s;
        timed.push((ramp, t0, t1));
        while (k as f64) * dt < t1 {
            let t = k as f64 * dt;
            let f = ((t - t0) / ramp.duration_s).clamp(0.0, 1.0);
            let current = ramp.from_a + f * (ramp.to_a - ramp.from_a);
            let logged = k % sub == 0;
            let s = plant.step(current, logged);
            if logged {
                samples.push([t, current, s.measured_torque_nm, s.speed_rad_s]);
            }
            k += 1;
        }
        t0 = t1;
    }
    Ok((samples, timed))
}

/// The minor-loop log `minor_loops.csv` (characterisation columns) and `manifest.csv`
/// (`ramp,part,start_s,end_s,from_A,to_A`).
pub fn minor_loop_logs(config: &RigConfig) -> Result<Vec<RigFile>, SimError> {
    let (samples, ramps) = minor_loop_samples(config)?;
    let mut csv = String::with_capacity(samples.len() * 40);
    csv.push_str("time_s,current_A,torque_Nm,speed_rad_s\n");
    for row in &samples {
        push_row(&mut csv, row);
    }
    let mut manifest = String::from("ramp,part,start_s,end_s,from_A,to_A\n");
    for (k, (r, t0, t1)) in ramps.iter().enumerate() {
        manifest.push_str(&format!("{k},{},{t0:.6},{t1:.6},{},{}\n", r.part, r.from_a, r.to_a));
    }
    Ok(vec![
        RigFile { name: "minor_loops.csv".into(), csv },
        RigFile { name: "manifest.csv".into(), csv: manifest },
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn program_visits_inner_turning_points_and_ends_at_rest() {
        let config = RigConfig::default();
        let ramps = program(&config);
        let last = ramps.last().unwrap();
        assert!(last.to_a.abs() < 1e-15 && last.part == "rest");
        // Reversals strictly inside (0, I_max): 4 + 4 FORC points and the triangle tips 1..=10 (tip 0
        // is I_max, after tip 11 the current keeps falling to 0).
        let inner = ramps
            .windows(2)
            .filter(|w| w[0].to_a > 1e-9 && w[0].to_a < 2.0 - 1e-9)
            .filter(|w| (w[0].to_a - w[0].from_a) * (w[1].to_a - w[1].from_a) < 0.0)
            .count();
        assert_eq!(inner, 4 + 4 + 10, "{ramps:?}");
        // Every ramp is at the configured rate.
        for r in ramps.iter().filter(|r| r.part != "rest") {
            assert!(((r.to_a - r.from_a).abs() / r.duration_s - 0.2).abs() < 1e-12);
        }
    }

    /// A program longer than the run limit is an input error before anything is simulated.
    #[test]
    fn an_endless_program_is_refused_before_simulating() {
        let mut config = RigConfig::default();
        config.minor_loops.pause_s = 1e300;
        let error = minor_loop_samples(&config).unwrap_err();
        let SimError::Input(field) = &error else { panic!("{error:?}") };
        assert_eq!(field.field, "minor_loops", "{error}");
        assert!(field.allowed.as_deref().is_some_and(|a| a.contains("output steps")), "{error}");
    }
}
