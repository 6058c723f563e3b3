//! The virtual test rig: simulates the thesis's experiments (§3.2, §5.3) and writes logs in exactly the
//! form a real rig would, so the identification pipeline can be tested end to end and an experiment
//! rehearsed before a brake exists.
//!
//! Signal chain, one update per output sample (zero-order-hold current, [`crate::lti`] exact
//! discretisation):
//!
//! ```text
//! current I ──► static hysteresis T_s (play-type switch between polynomial branches)
//!           ──► brake dynamics G_b(s) (default (5.5)) ──► + viscous c·ω ──► torque sensor
//! motor voltage ──► DC motor (5.1) ──► ÷ belt ratio ──► shaft speed ω
//! torque sensor: T·(V_fs/T_fs) + Gaussian noise ──► 16-bit ADC over ±V_fs ──► logged torque
//! ```
//!
//! The static hysteresis is a play-type (clamp) model: T_s\[k\] = clamp(T_s\[k−1\], T_up(I\[k\]),
//! T_down(I\[k\])) with T_down ≥ T_up. On a full ramp it follows the rising branch up and the falling
//! branch down, exactly the loop the characterisation fits; on a reversal inside the loop the torque
//! holds until the other branch is reached, so the loop stays continuous.
//!
//! Protocols: [`characterization_log`] (§5.3.1) and [`frequency_response_logs`] (§5.3.2: the current
//! is shaped through the inverse model so that the torque demand is sinusoidal). The inverse model is
//! the controller's ([`mrbrake_control::InverseModel`]), and the current is shaped by the controller's
//! own hysteresis compensation ([`InverseModel::compensate`], no deadband): the rig drives the brake
//! exactly as the controller would.

pub mod config;
pub mod everett;
pub mod minor_loops;
pub mod noise;
pub mod preisach;
pub mod tracking;

use mrbrake_control::{Branch, CompensationState, InverseModel};
use mrbrake_sysid::polynomial::Polynomial;
use mrbrake_sysid::transfer_function::TransferFunction;

use crate::SimError;
use crate::lti::DiscreteStateSpace;
pub use config::RigConfig;
use noise::GaussianNoise;
use preisach::{HysteresisKind, PreisachHysteresis};

/// The simulated plant: brake, motor and sensor, advanced one output sample at a time.
#[derive(Debug, Clone)]
pub struct Plant {
    rising: Polynomial,
    falling: Polynomial,
    static_torque_nm: f64,
    brake_dynamics: DiscreteStateSpace,
    motor: DiscreteStateSpace,
    viscous: f64,
    belt_ratio: f64,
    motor_voltage_v: f64,
    volts_per_nm: f64,
    noise_std_v: f64,
    lsb_v: f64,
    full_scale_v: f64,
    stiffness: f64,
    noise: GaussianNoise,
    /// The Preisach hysteresis when the configuration selects it (else the play-type clamp).
    preisach: Option<PreisachHysteresis>,
}

/// One output sample of the plant.
#[derive(Debug, Clone, Copy)]
pub struct PlantSample {
    /// True brake torque, N·m.
    pub torque_nm: f64,
    /// Torque as logged by the sensor chain (noise, quantisation), N·m.
    pub measured_torque_nm: f64,
    /// Brake shaft speed, rad/s.
    pub speed_rad_s: f64,
}

impl Plant {
    /// Builds the plant at output step `dt_s` with noise seed `seed`.
    pub fn new(config: &RigConfig, dt_s: f64, seed: u64) -> Result<Self, SimError> {
        let b = &config.brake;
        let g = TransferFunction::new(b.dynamics_numerator.clone(), b.dynamics_denominator.clone())
            .map_err(|source| SimError::Model { what: "brake dynamics", source })?;
        let m =
            TransferFunction::new(config.motor.numerator.clone(), config.motor.denominator.clone())
                .map_err(|source| SimError::Model { what: "motor", source })?;
        let s = &config.sensor;
        Ok(Self {
            rising: Polynomial::new(b.rising.clone()),
            falling: Polynomial::new(b.falling.clone()),
            static_torque_nm: Polynomial::new(b.rising.clone()).eval(0.0),
            brake_dynamics: DiscreteStateSpace::zoh(&g, dt_s)?,
            motor: DiscreteStateSpace::zoh(&m, dt_s)?,
            viscous: b.viscous_nm_s_per_rad,
            belt_ratio: config.motor.belt_ratio,
            motor_voltage_v: config.motor.voltage_v,
            volts_per_nm: s.full_scale_v / s.full_scale_nm,
            noise_std_v: s.noise_std_v,
            lsb_v: 2.0 * s.full_scale_v / 2f64.powi(s.adc_bits as i32),
            full_scale_v: s.full_scale_v,
            stiffness: s.stiffness_nm_per_rad,
            noise: GaussianNoise::new(seed),
            preisach: match (&b.everett, config.hysteresis.model) {
                (Some(table), _) => Some(PreisachHysteresis::from_everett(table, 0.0)?),
                (None, HysteresisKind::Clamp) => None,
                (None, HysteresisKind::Preisach) => Some(PreisachHysteresis::new(
                    &config.hysteresis,
                    &b.rising,
                    &b.falling,
                    b.current_max_a,
                )?),
            },
        })
    }

    /// Starts in equilibrium at current `current_a` on the rising branch, motor at steady speed.
    pub fn settle(&mut self, current_a: f64) {
        self.static_torque_nm = match &mut self.preisach {
            Some(p) => p.settle(current_a),
            None => self.rising.eval(current_a),
        };
        self.brake_dynamics.set_steady_state(self.static_torque_nm);
        self.motor.set_steady_state(self.motor_voltage_v);
    }

    /// Static (quasi-steady) torque of the play-type hysteresis model for the next current.
    fn static_torque(&mut self, current_a: f64) -> f64 {
        if let Some(p) = &mut self.preisach {
            self.static_torque_nm = p.torque_nm(current_a);
            return self.static_torque_nm;
        }
        let up = self.rising.eval(current_a);
        let down = self.falling.eval(current_a);
        let (lo, hi) = if up <= down { (up, down) } else { (down, up) };
        self.static_torque_nm = self.static_torque_nm.clamp(lo, hi);
        self.static_torque_nm
    }

    /// Advances one output step with current `current_a`; `measure` adds the sensor chain.
    pub fn step(&mut self, current_a: f64, measure: bool) -> PlantSample {
        let ts = self.static_torque(current_a);
        let motor_speed = self.motor.step(self.motor_voltage_v);
        let speed_rad_s = motor_speed / self.belt_ratio;
        let torque_nm = self.brake_dynamics.step(ts) + self.viscous * speed_rad_s;
        let measured_torque_nm = if measure { self.measure(torque_nm) } else { torque_nm };
        PlantSample { torque_nm, measured_torque_nm, speed_rad_s }
    }

    /// Sensor chain: volts, noise, clipping at ±full scale, quantisation, back to N·m.
    fn measure(&mut self, torque_nm: f64) -> f64 {
        let v = torque_nm * self.volts_per_nm + self.noise_std_v * self.noise.standard_normal();
        let v = v.clamp(-self.full_scale_v, self.full_scale_v - self.lsb_v);
        let code = (v / self.lsb_v).round();
        code * self.lsb_v / self.volts_per_nm
    }

    /// Sensor shaft twist for a torque, rad (torque / torsional stiffness).
    pub fn twist_rad(&self, torque_nm: f64) -> f64 {
        torque_nm / self.stiffness
    }
}

/// A log produced by the rig: its file name and CSV text.
#[derive(Debug, Clone)]
pub struct RigFile {
    /// File name (no directory).
    pub name: String,
    /// CSV content with a header row.
    pub csv: String,
}

/// The current command of the characterisation protocol at output step `k` (§5.3.1).
fn protocol_current(config: &RigConfig, t_s: f64) -> Option<f64> {
    let c = &config.characterization;
    let steps = (config.brake.current_max_a / c.step_a).round() as i64;
    let sequence_s = (2 * steps + 1) as f64 * c.step_s + c.pause_s;
    let rep = (t_s / sequence_s).floor();
    if rep >= c.repetitions as f64 {
        return None;
    }
    let local = t_s - rep * sequence_s;
    let index = (local / c.step_s + 1e-9).floor() as i64;
    let level = if index <= steps {
        index
    } else if index <= 2 * steps {
        2 * steps - index
    } else {
        0
    };
    Some((level as f64 * c.step_a).min(config.brake.current_max_a))
}

/// The most output steps one protocol may simulate (characterisation, or all the sine tests
/// together): 50 million, 110 times the thesis characterisation (450 s at 1 kHz) and 2.6 times
/// its frequency-response protocol at a 20 kHz output rate (1.9e7 steps, the validation's). Each
/// step is kept as a logged sample, so this bounds the memory of a run (~32 bytes a sample plus
/// its CSV text, ~3 GB at the limit) as well as its time; a configuration asking for more is an
/// input error naming the fields to change.
pub const MAX_RUN_STEPS: f64 = 5e7;

/// The most test frequencies of the frequency-response protocol.
pub const MAX_TEST_FREQUENCIES: f64 = 10_000.0;

/// The largest accepted full-scale sensor voltage, V (the thesis amplifier gives ±10 V; a larger
/// value overflows the ADC step).
pub const MAX_FULL_SCALE_V: f64 = 1e3;

/// A plant model of the rig must be stable (every pole in the open left half-plane): an
/// unstable motor or brake model grows without bound and fills the log with NaN (found by the
/// fuzzer: a motor denominator `[2e-5, 1e-300, -1]`).
fn check_stable(g: &TransferFunction) -> Result<(), String> {
    let poles = g.poles().map_err(|e| e.to_string())?;
    match poles.iter().find(|p| p.re.is_nan() || p.re >= 0.0) {
        Some(p) => Err(format!(
            "the model is not stable: a pole at {:.4e}{:+.4e}j (every pole must have a negative \
             real part)",
            p.re, p.im
        )),
        None => Ok(()),
    }
}

/// Checks that the brake and motor models discretise at the output rate (degenerate
/// coefficients overflow) and that both protocols fit [`MAX_RUN_STEPS`] (and the sine tests
/// [`MAX_TEST_FREQUENCIES`]) before anything is allocated; `Err((field, message))` otherwise.
fn check_run_size(config: &RigConfig) -> Result<(), (&'static str, String)> {
    let rate = config.daq.output_rate_hz;
    let models = [
        (
            "brake.dynamics_denominator",
            &config.brake.dynamics_numerator,
            &config.brake.dynamics_denominator,
        ),
        ("motor.denominator", &config.motor.numerator, &config.motor.denominator),
    ];
    for (field, num, den) in models {
        TransferFunction::new(num.clone(), den.clone())
            .map_err(|e| e.to_string())
            .and_then(|g| check_stable(&g).map(|()| g))
            .and_then(|g| DiscreteStateSpace::zoh(&g, 1.0 / rate).map_err(|e| e.to_string()))
            .map_err(|e| (field, e))?;
    }
    let steps = characterization_duration_s(config) * rate;
    if steps.is_nan() || steps > MAX_RUN_STEPS {
        return Err((
            "characterization",
            format!(
                "the protocol would simulate {steps:.3e} output steps ({:.3e} s at {rate} Hz), more \
                 than the limit of {MAX_RUN_STEPS:.0e}: reduce repetitions, pause_s, step_s or \
                 current_max_A / step_A",
                characterization_duration_s(config)
            ),
        ));
    }
    let f = &config.frequency_response;
    let count = (f.omega_max_rad_s / f.omega_min_rad_s).log10() * f.points_per_decade as f64 + 1.0;
    if count.is_nan() || count > MAX_TEST_FREQUENCIES {
        return Err((
            "frequency_response.points_per_decade",
            format!(
                "{count:.3e} test frequencies, more than the limit of {MAX_TEST_FREQUENCIES}: reduce \
                 points_per_decade or the range omega_min_rad_s..omega_max_rad_s"
            ),
        ));
    }
    let total: f64 =
        test_frequencies(config).iter().map(|&w| sine_test_duration_s(config, w)).sum();
    if (total * rate).is_nan() || total * rate > MAX_RUN_STEPS {
        return Err((
            "frequency_response",
            format!(
                "the sine tests would simulate {:.3e} output steps ({total:.3e} s at {rate} Hz), more \
                 than the limit of {MAX_RUN_STEPS:.0e}: raise omega_min_rad_s or reduce the periods \
                 and durations",
                total * rate
            ),
        ));
    }
    Ok(())
}

/// Recorded duration of one sine test at `omega_rad_s`, s: the discarded start-up and the
/// measured part.
fn sine_test_duration_s(config: &RigConfig, omega_rad_s: f64) -> f64 {
    let f = &config.frequency_response;
    let period = 2.0 * std::f64::consts::PI / omega_rad_s;
    (f.periods_discarded * period).max(f.settle_s)
        + (f.periods_measured * period).max(f.min_measure_s)
}

/// Duration of the characterisation protocol, s.
pub fn characterization_duration_s(config: &RigConfig) -> f64 {
    let c = &config.characterization;
    let steps = (config.brake.current_max_a / c.step_a).round();
    ((2.0 * steps + 1.0) * c.step_s + c.pause_s) * c.repetitions as f64
}

fn rates(config: &RigConfig) -> (f64, usize) {
    let dt = 1.0 / config.daq.output_rate_hz;
    let sub = (config.daq.output_rate_hz / config.daq.sample_rate_hz).round() as usize;
    (dt, sub.max(1))
}

/// Samples (time s, current A, torque N·m, speed rad/s) of the characterisation run.
pub fn characterization_samples(config: &RigConfig) -> Result<Vec<[f64; 4]>, SimError> {
    config.validate("rig configuration")?;
    let (dt, sub) = rates(config);
    let mut plant = Plant::new(config, dt, config.seed)?;
    plant.settle(0.0);
    let total = characterization_duration_s(config);
    let n = (total * config.daq.output_rate_hz).round() as usize;
    let mut out = Vec::with_capacity(n / sub + 1);
    for k in 0..n {
        let t = k as f64 * dt;
        let current = protocol_current(config, t).unwrap_or(0.0);
        let logged = k % sub == 0;
        let s = plant.step(current, logged);
        if logged {
            out.push([t, current, s.measured_torque_nm, s.speed_rad_s]);
        }
    }
    Ok(out)
}

/// The characterisation log (`time_s, current_A, torque_Nm, speed_rad_s`), as `mrbrake characterize`
/// reads it.
pub fn characterization_log(config: &RigConfig) -> Result<RigFile, SimError> {
    let samples = characterization_samples(config)?;
    let mut csv = String::with_capacity(samples.len() * 40);
    csv.push_str("time_s,current_A,torque_Nm,speed_rad_s\n");
    for [t, i, tq, w] in samples {
        push_row(&mut csv, &[t, i, tq, w]);
    }
    Ok(RigFile { name: "characterization.csv".into(), csv })
}

/// Appends one CSV row with enough digits for the 16-bit sensor and microsecond time stamps.
fn push_row(out: &mut String, values: &[f64]) {
    use std::fmt::Write;
    for (k, v) in values.iter().enumerate() {
        if k > 0 {
            out.push(',');
        }
        let _ = write!(out, "{v:.7}");
    }
    out.push('\n');
}

/// The test frequencies of §5.3.2: `points_per_decade` per decade from ω_min to ω_max inclusive.
pub fn test_frequencies(config: &RigConfig) -> Vec<f64> {
    let f = &config.frequency_response;
    let decades = (f.omega_max_rad_s / f.omega_min_rad_s).log10();
    let count = (decades * f.points_per_decade as f64).round() as usize + 1;
    (0..count)
        .map(|k| f.omega_min_rad_s * 10f64.powf(k as f64 / f.points_per_decade as f64))
        .collect()
}

/// One sinusoidal test: (time s, demanded torque N·m, measured torque N·m, current A) per sample.
pub fn sine_test_samples(
    config: &RigConfig,
    omega_rad_s: f64,
    inverse: &InverseModel,
    seed: u64,
) -> Result<Vec<[f64; 4]>, SimError> {
    let f = &config.frequency_response;
    let (dt, sub) = rates(config);
    let mid = 0.5 * (f.torque_min_nm + f.torque_max_nm);
    let amp = 0.5 * (f.torque_max_nm - f.torque_min_nm);
    let mut plant = Plant::new(config, dt, seed)?;
    let limit_a = inverse.current_max_a();
    // No deadband: the demand is exact, so every change of its direction switches the branch.
    let mut compensation = CompensationState::default();
    let i0 = inverse.compensate(&mut compensation, mid, limit_a, 0.0);
    plant.settle(i0);
    let n = (sine_test_duration_s(config, omega_rad_s) / dt).ceil() as usize;
    let mut out = Vec::with_capacity(n / sub + 1);
    for k in 0..n {
        let t = k as f64 * dt;
        let demand = mid + amp * (omega_rad_s * t).sin();
        let current = inverse.compensate(&mut compensation, demand, limit_a, 0.0);
        let logged = k % sub == 0;
        let s = plant.step(current, logged);
        if logged {
            out.push([t, demand, s.measured_torque_nm, current]);
        }
    }
    Ok(out)
}

/// The inverse model of the configured branches (what a perfectly characterised brake would use).
/// Fails when a branch has more coefficients than the controller holds or decreases on
/// `[0, current_max_A]`.
pub fn configured_model(config: &RigConfig) -> Result<InverseModel, SimError> {
    InverseModel::new(&config.brake.rising, &config.brake.falling, 0.0, config.brake.current_max_a)
        .map_err(|source| SimError::Control { what: "brake branches (rig configuration)", source })
}

/// One sinusoidal test's frequency (rad/s) and samples (see [`sine_test_samples`]).
pub type SineRun = (f64, Vec<[f64; 4]>);

/// The frequency-response protocol's runs: for each test frequency (rad/s), its samples (time s,
/// demanded torque N·m, measured torque N·m, current A). `model` is the inverse model that shapes
/// the current (default: the configured branches).
pub fn frequency_response_runs(
    config: &RigConfig,
    model: Option<&InverseModel>,
) -> Result<Vec<SineRun>, SimError> {
    config.validate("rig configuration")?;
    let inverse = match model {
        Some(model) => *model,
        None => configured_model(config)?,
    };
    // Each branch is non-decreasing, so its torque range runs from i_min to i_max.
    let range = |branch| {
        (
            inverse.torque_nm(branch, inverse.current_min_a()),
            inverse.torque_nm(branch, inverse.current_max_a()),
        )
    };
    let (lo, hi) = (range(Branch::Rising), range(Branch::Falling));
    let f = &config.frequency_response;
    if f.torque_min_nm < lo.0.max(hi.0) || f.torque_max_nm > lo.1.min(hi.1) {
        return Err(mrbrake_error::FieldError::new(
            "frequency_response.torque_min_Nm",
            "the torque demand leaves the range both branches reach",
        )
        .with_value(format!("{}..{} N·m", f.torque_min_nm, f.torque_max_nm))
        .with_allowed(format!("{:.4}..{:.4} N·m", lo.0.max(hi.0), lo.1.min(hi.1)))
        .into());
    }
    test_frequencies(config)
        .into_iter()
        .enumerate()
        .map(|(k, w)| {
            let seed = config.seed.wrapping_add(1 + k as u64);
            Ok((w, sine_test_samples(config, w, &inverse, seed)?))
        })
        .collect()
}

/// The frequency-response protocol: one log per test frequency (`time_s, input, output, current_A`)
/// and the manifest `frequency_rad_s,file` (the runs of [`frequency_response_runs`]).
pub fn frequency_response_logs(
    config: &RigConfig,
    model: Option<&InverseModel>,
) -> Result<Vec<RigFile>, SimError> {
    let mut files = Vec::new();
    let mut manifest = String::from("frequency_rad_s,file\n");
    for (k, (w, samples)) in frequency_response_runs(config, model)?.into_iter().enumerate() {
        let mut csv = String::with_capacity(samples.len() * 40);
        csv.push_str("time_s,input,output,current_A\n");
        for row in samples {
            push_row(&mut csv, &row);
        }
        let name = format!("sine_{k:02}.csv");
        manifest.push_str(&format!("{w},{name}\n"));
        files.push(RigFile { name, csv });
    }
    files.push(RigFile { name: "manifest.csv".into(), csv: manifest });
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn protocol_matches_thesis_timing() {
        let c = RigConfig::default();
        // (2·2000 + 1) steps of 10 ms + 5 s pause = 45.01 s per sequence, ten sequences.
        assert!((characterization_duration_s(&c) - 450.1).abs() < 1e-9);
        assert!((protocol_current(&c, 0.005).unwrap() - 0.0).abs() < 1e-15);
        assert!((protocol_current(&c, 10.0).unwrap() - 1.0).abs() < 1e-12);
        assert!((protocol_current(&c, 20.005).unwrap() - 2.0).abs() < 1e-12);
        assert!((protocol_current(&c, 30.0).unwrap() - 1.0).abs() < 1e-12);
        assert!((protocol_current(&c, 42.0).unwrap()).abs() < 1e-15);
        assert!(protocol_current(&c, 451.0).is_none());
    }

    #[test]
    fn play_model_follows_branches_and_holds_on_reversal() {
        let mut cfg = RigConfig::default();
        cfg.sensor.noise_std_v = 0.0;
        let mut p = Plant::new(&cfg, 1e-3, 0).unwrap();
        p.settle(0.0);
        let up = Polynomial::new(cfg.brake.rising.clone());
        let down = Polynomial::new(cfg.brake.falling.clone());
        for k in 0..=100 {
            p.static_torque(k as f64 * 0.01);
        }
        assert!((p.static_torque_nm - up.eval(1.0)).abs() < 1e-12);
        // Reversal: the torque holds until the falling branch comes down to it.
        let held = p.static_torque(0.99);
        assert!((held - up.eval(1.0)).abs() < 1e-12);
        let low = p.static_torque(0.2);
        assert!((low - down.eval(0.2)).abs() < 1e-12);
    }

    #[test]
    fn sensor_quantises_to_the_adc_step() {
        let mut cfg = RigConfig::default();
        cfg.sensor.noise_std_v = 0.0;
        let mut p = Plant::new(&cfg, 1e-3, 0).unwrap();
        let lsb_nm = 20.0 / 65536.0;
        let m = p.measure(1.23456);
        assert!((m - 1.23456).abs() <= 0.5 * lsb_nm + 1e-15);
        assert!(((m / lsb_nm) - (m / lsb_nm).round()).abs() < 1e-9);
    }

    /// The hostile configurations of issue 18 (each used to abort on a huge allocation or panic)
    /// are input errors naming the field, before any sample is simulated.
    #[test]
    fn oversized_protocols_are_refused_before_allocating() {
        let cases = [
            ("[characterization]\nrepetitions = 1000000\n", "characterization"),
            ("[characterization]\npause_s = 1e308\n", "characterization"),
            ("[brake]\ncurrent_max_A = 2147483647\n", "characterization"),
            ("[sensor]\nfull_scale_V = 1e308\n", "sensor.full_scale_V"),
            ("[frequency_response]\npoints_per_decade = 1000000000\n", "points_per_decade"),
            ("[frequency_response]\nomega_min_rad_s = 1e-300\n", "frequency_response"),
            (
                "[brake]\ndynamics_denominator = [5e-324, 0.01702, 1.0]\n",
                "brake.dynamics_denominator",
            ),
            ("[motor]\ndenominator = [2e-5, 0.000368, 1e307]\n", "motor.denominator"),
        ];
        for (text, field) in cases {
            let e = RigConfig::from_toml("rig.toml", text).unwrap_err();
            assert!(mrbrake_error::Kind::is_input_error(&e), "{text}: {e}");
            let message = e.to_string();
            assert!(message.contains("rig.toml") && message.contains(field), "{text}: {message}");
        }
        // The defaults and the largest sensor voltage still run.
        let mut c = RigConfig::default();
        c.sensor.full_scale_v = MAX_FULL_SCALE_V;
        c.characterization.repetitions = 1;
        assert!(characterization_samples(&c).unwrap().len() > 1000);
    }

    #[test]
    fn thesis_frequency_grid_has_41_points() {
        let w = test_frequencies(&RigConfig::default());
        assert_eq!(w.len(), 41);
        assert!((w[0] - 0.1).abs() < 1e-15 && (w[40] - 1000.0).abs() < 1e-9);
    }
}
