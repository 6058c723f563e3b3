//! Drive waveforms `w(t)`: the coil's current or voltage is `amplitude · w(t)`.
//!
//! The time origin is the start of the transient: the solve begins from the static (DC) state at
//! `w(0)` and integrates over `(0, t_end]`. A step is `w = initial` at `t <= 0` and `1` for
//! `t > 0` (a Heaviside step from `initial`), a release 1 at `t <= 0` and 0 after; a ramp rises linearly from 0 to 1 over `rise_s`;
//! a sine is `offset + sin(2π f t)`; a table is interpolated linearly (held constant outside).

use crate::MagneticsError;
use mrbrake_error::FieldError;

/// A drive waveform (dimensionless: it scales the drive's amplitude).
#[derive(Debug, Clone, PartialEq)]
pub enum Waveform {
    /// `initial` for `t <= 0`, 1 afterwards.
    Step {
        /// Value before the step (0 for a step from rest).
        initial: f64,
    },
    /// 1 for `t <= 0`, 0 afterwards: a step down to rest (a release), which a [`Self::Step`]
    /// scaled by its final value cannot express.
    Release,
    /// 0 at `t <= 0`, `t / rise_s` while rising, 1 afterwards.
    Ramp {
        /// Rise time (s), > 0.
        rise_s: f64,
    },
    /// `offset + sin(2π f t)`.
    Sine {
        /// Frequency (Hz), > 0.
        frequency_hz: f64,
        /// Constant offset.
        offset: f64,
    },
    /// Piecewise-linear `(time_s, value)` points, strictly increasing in time.
    Table {
        /// The points.
        points: Vec<(f64, f64)>,
    },
}

impl Waveform {
    /// Checks the parameters (finite, positive rise time and frequency, increasing table).
    pub fn validate(&self) -> Result<(), MagneticsError> {
        let bad = |field: &str, value: f64, allowed: &str| {
            Err(FieldError::out_of_range(field, value, allowed).into())
        };
        match self {
            Self::Step { initial } if !initial.is_finite() => bad("initial", *initial, "finite"),
            Self::Ramp { rise_s } if !(*rise_s > 0.0 && rise_s.is_finite()) => {
                bad("rise_s", *rise_s, "finite, > 0 s")
            }
            Self::Sine { frequency_hz, .. }
                if !(*frequency_hz > 0.0 && frequency_hz.is_finite()) =>
            {
                bad("frequency_Hz", *frequency_hz, "finite, > 0 Hz")
            }
            Self::Sine { offset, .. } if !offset.is_finite() => bad("offset", *offset, "finite"),
            Self::Table { points } => check_table(points),
            _ => Ok(()),
        }
    }

    /// `w(t)`.
    pub fn value(&self, t: f64) -> f64 {
        match self {
            Self::Step { initial } => {
                if t <= 0.0 {
                    *initial
                } else {
                    1.0
                }
            }
            Self::Release => {
                if t <= 0.0 {
                    1.0
                } else {
                    0.0
                }
            }
            Self::Ramp { rise_s } => (t / rise_s).clamp(0.0, 1.0),
            Self::Sine { frequency_hz, offset } => {
                offset + (2.0 * std::f64::consts::PI * frequency_hz * t).sin()
            }
            Self::Table { points } => interpolate(points, t),
        }
    }

    /// Times in `(0, t_end)` where `w` has a kink or a jump (a variable step lands on them).
    pub fn breakpoints(&self, t_end: f64) -> Vec<f64> {
        let inside = |t: f64| t > 0.0 && t < t_end;
        match self {
            Self::Ramp { rise_s } if inside(*rise_s) => vec![*rise_s],
            Self::Table { points } => points.iter().map(|p| p.0).filter(|&t| inside(t)).collect(),
            _ => Vec::new(),
        }
    }
}

fn check_table(points: &[(f64, f64)]) -> Result<(), MagneticsError> {
    if points.is_empty() {
        return Err(MagneticsError::field("points", "table waveform: no points"));
    }
    for (k, p) in points.iter().enumerate() {
        if !(p.0.is_finite() && p.1.is_finite()) {
            return Err(MagneticsError::field(
                format!("points[{k}]"),
                format!("table waveform: point {} ({}, {}) is not finite", k + 1, p.0, p.1),
            ));
        }
        if k > 0 && p.0 <= points[k - 1].0 {
            return Err(MagneticsError::field(
                format!("points[{k}]"),
                format!(
                    "table waveform: time must increase strictly (point {} at t = {} s follows t = {} s)",
                    k + 1,
                    p.0,
                    points[k - 1].0
                ),
            ));
        }
    }
    Ok(())
}

fn interpolate(points: &[(f64, f64)], t: f64) -> f64 {
    let k = points.partition_point(|p| p.0 <= t);
    if k == 0 {
        return points[0].1;
    }
    if k == points.len() {
        return points[k - 1].1;
    }
    let (a, b) = (points[k - 1], points[k]);
    a.1 + (b.1 - a.1) * (t - a.0) / (b.0 - a.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bad_parameter_is_a_field_error_with_its_value_and_range() {
        let e = Waveform::Ramp { rise_s: -1.0 }.validate().unwrap_err();
        let MagneticsError::Input(f) = &e else { panic!("{e:?}") };
        assert_eq!((f.field.as_str(), f.value.as_deref()), ("rise_s", Some("-1")));
        assert_eq!(f.allowed.as_deref(), Some("finite, > 0 s"));
        let e = Waveform::Sine { frequency_hz: 50.0, offset: f64::NAN }.validate().unwrap_err();
        assert!(e.to_string().starts_with("offset: got NaN"), "{e}");
    }

    #[test]
    fn values_and_breakpoints() {
        let step = Waveform::Step { initial: 0.25 };
        assert!((step.value(0.0) - 0.25).abs() < 1e-15 && (step.value(1e-9) - 1.0).abs() < 1e-15);
        let release = Waveform::Release;
        assert!((release.value(0.0) - 1.0).abs() < 1e-15 && release.value(1e-9).abs() < 1e-15);
        let ramp = Waveform::Ramp { rise_s: 2.0 };
        assert!((ramp.value(1.0) - 0.5).abs() < 1e-15 && (ramp.value(5.0) - 1.0).abs() < 1e-15);
        assert_eq!(ramp.breakpoints(3.0), vec![2.0]);
        let table = Waveform::Table { points: vec![(0.0, 0.0), (1.0, 2.0), (3.0, 0.0)] };
        assert!((table.value(0.5) - 1.0).abs() < 1e-15 && (table.value(2.0) - 1.0).abs() < 1e-15);
        assert!((table.value(9.0)).abs() < 1e-15);
    }

    #[test]
    fn bad_waveforms_are_refused() {
        assert!(Waveform::Ramp { rise_s: 0.0 }.validate().is_err());
        assert!(Waveform::Sine { frequency_hz: -1.0, offset: 0.0 }.validate().is_err());
        let not_increasing = Waveform::Table { points: vec![(0.0, 0.0), (0.0, 1.0)] };
        let message = not_increasing.validate().unwrap_err().to_string();
        assert!(message.contains("increase"), "{message}");
    }
}
