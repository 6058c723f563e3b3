//! Interaction scenarios: what the user intends and where the wall is, as functions of time.
//!
//! The wall occupies positive angles above its position (brake 1 resists motion into it).
//! - **Press and withdraw**: from −0.1 rad the hand moves to +0.3 rad (well inside the wall at 0) in
//!   0.8 s, holds 1 s, then withdraws to −0.6 rad in 0.8 s and rests (the hand then pulls with up to
//!   K_h·0.6 ≈ 1.8 Nm). The sticky-wall test.
//! - **Slide / hold**: the hand presses toward +0.2 rad, then its intention swings between +0.2 and
//!   −0.1 rad at 1 Hz: each outward swing asks the device to let go while the handle is in contact.
//! - **Moving wall**: the wall surface moves between 0 and 0.1 rad at 0.5 Hz while the hand keeps
//!   pressing 0.2 rad beyond it: the device must follow a retreating and an advancing surface.
//!
//! Point-to-point moves are minimum-jerk (Flash & Hogan 1985): `θ = θ₀ + Δ(10σ³ − 15σ⁴ + 6σ⁵)`.

/// A scenario.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Scenario {
    /// Press into the wall and withdraw.
    PressWithdraw,
    /// Press, then move in and out while staying in contact.
    SlideHold,
    /// Keep pressing against an oscillating wall.
    MovingWall,
}

/// Minimum-jerk position and velocity from `from` to `to` over `[t0, t1]`.
fn minimum_jerk(t: f64, t0: f64, t1: f64, from: f64, to: f64) -> (f64, f64) {
    let duration = t1 - t0;
    let sigma = ((t - t0) / duration).clamp(0.0, 1.0);
    let s2 = sigma * sigma;
    let shape = s2 * sigma * (10.0 - 15.0 * sigma + 6.0 * s2);
    let rate = if (0.0..1.0).contains(&sigma) {
        30.0 * s2 * (1.0 - sigma) * (1.0 - sigma) / duration
    } else {
        0.0
    };
    (from + (to - from) * shape, (to - from) * rate)
}

impl Scenario {
    /// Every scenario, in the order the CLI lists them.
    pub const ALL: [Self; 3] = [Self::PressWithdraw, Self::SlideHold, Self::MovingWall];

    /// The scenario called `name` (as [`Scenario::name`] gives it), if there is one.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.name() == name)
    }

    /// The name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::PressWithdraw => "press-withdraw",
            Self::SlideHold => "slide-hold",
            Self::MovingWall => "moving-wall",
        }
    }

    /// Default duration, s.
    pub fn default_duration_s(self) -> f64 {
        4.0
    }

    /// Initial handle angle, rad (outside the wall, at rest).
    pub fn start_angle_rad(self) -> f64 {
        -0.1
    }

    /// The moment the user starts to withdraw, s (press-and-withdraw only).
    pub fn withdraw_start_s(self) -> Option<f64> {
        match self {
            Self::PressWithdraw => Some(2.0),
            _ => None,
        }
    }

    /// Intended angle and velocity at time `t_s`.
    #[inline]
    pub fn intended(self, t_s: f64) -> (f64, f64) {
        match self {
            Self::PressWithdraw => {
                if t_s < 2.0 {
                    minimum_jerk(t_s, 0.2, 1.0, -0.1, 0.3)
                } else {
                    minimum_jerk(t_s, 2.0, 2.8, 0.3, -0.6)
                }
            }
            Self::SlideHold => {
                if t_s < 1.0 {
                    minimum_jerk(t_s, 0.2, 1.0, -0.1, 0.2)
                } else {
                    let w = core::f64::consts::TAU;
                    let phase = w * (t_s - 1.0);
                    (0.2 - 0.15 * (1.0 - phase.cos()), -0.15 * w * phase.sin())
                }
            }
            Self::MovingWall => {
                let (wall, wall_rate) = self.wall_position_and_rate(t_s);
                let (approach, approach_rate) = minimum_jerk(t_s, 0.2, 1.0, -0.1, 0.2);
                if t_s < 1.0 { (approach, approach_rate) } else { (wall + 0.2, wall_rate) }
            }
        }
    }

    /// Wall position and its rate at time `t_s`, rad and rad/s.
    #[inline]
    pub fn wall_position_and_rate(self, t_s: f64) -> (f64, f64) {
        match self {
            Self::MovingWall if t_s >= 1.0 => {
                let w = core::f64::consts::PI;
                let phase = w * (t_s - 1.0);
                (0.05 * (1.0 - phase.cos()), 0.05 * w * phase.sin())
            }
            _ => (0.0, 0.0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn minimum_jerk_velocity_is_the_derivative_of_the_position() {
        for scenario in [Scenario::PressWithdraw, Scenario::SlideHold, Scenario::MovingWall] {
            for k in 1..400 {
                let t = k as f64 * 0.01;
                let h = 1e-6;
                let numeric = (scenario.intended(t + h).0 - scenario.intended(t - h).0) / (2.0 * h);
                assert!((numeric - scenario.intended(t).1).abs() < 1e-4, "{scenario:?} t = {t}");
            }
        }
        let (end, _) = Scenario::PressWithdraw.intended(3.5);
        assert!((end + 0.6).abs() < 1e-12);
    }
}
