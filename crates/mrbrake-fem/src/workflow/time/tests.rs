//! Orders of convergence in time against closed forms, on a small system of independent scalar
//! ODEs (one per DOF of a 4-node mesh, so the step systems go through the core's pattern,
//! Cholesky factor and Newton solver like a field's):
//!
//! - linear, `u̇ = −λ_i u + sin t`, `u(0) = 1`: `u(t) = (1 + 1/(1+λ²)) e^{−λt} + (λ sin t −
//!   cos t)/(1+λ²)` (the linear fast path);
//! - non-linear, `u̇ = −c u³`, `u(0) = u₀`: `u(t) = u₀/√(1 + 2 c u₀² t)` (Newton in every step).

use std::sync::Arc;

use mrbrake_observe::{Flow, Silent};

use super::run::Run;
use super::*;
use crate::discretisation::basis::{Basis, Weighting};
use crate::discretisation::dofs::ElementOrder;
use crate::mesh::structured::{SideTags, rectangle_mesh};
use crate::workflow::assemble::Assembly;

/// `u̇_i = −λ_i u_i − c u_i³ + f sin t` on the DOFs of a 4-node mesh.
struct Decay {
    newton: NewtonSolver,
    data: DecayData,
}

/// What the step systems read.
struct DecayData {
    assembly: Assembly,
    lambda: Vec<f64>,
    cubic: f64,
    forcing: f64,
    /// Breakpoints the adaptive steps must land on.
    corners: Vec<f64>,
    /// Pattern position of every free DOF's diagonal entry.
    diagonal: Vec<usize>,
}

impl Decay {
    fn new(lambda: [f64; 4], cubic: f64, forcing: f64) -> Self {
        let lines = [0.0, 1.0];
        let sides = SideTags { r_min: 1, r_max: 2, z_min: 3, z_max: 4 };
        let mesh = Arc::new(rectangle_mesh(&lines, &lines, |_, _| 1, sides).unwrap());
        let basis = Basis::new(mesh, ElementOrder::P1, 2, Weighting::Planar);
        let constraints = Constraints::builder(basis.dofs()).build();
        let assembly = Assembly::new(basis, constraints).unwrap();
        let newton = NewtonSolver::for_assembly(&assembly, 1).unwrap();
        let diagonal = (0..assembly.n_free())
            .map(|i| assembly.pattern().position(i, i).expect("a diagonal entry"))
            .collect();
        let lambda = lambda.to_vec();
        let data = DecayData { assembly, lambda, cubic, forcing, corners: Vec::new(), diagonal };
        Self { newton, data }
    }

    /// The closed form at `t` from `u(0) = u0`.
    fn exact(&self, t: f64, u0: f64) -> Vec<f64> {
        let d = &self.data;
        if d.cubic > 0.0 {
            return vec![u0 / (1.0 + 2.0 * d.cubic * u0 * u0 * t).sqrt(); 4];
        }
        let term = |l: f64| {
            let q = 1.0 + l * l;
            (u0 + d.forcing / q) * (-l * t).exp() + d.forcing * (l * t.sin() - t.cos()) / q
        };
        d.lambda.iter().map(|&l| term(l)).collect()
    }
}

struct DecayStep<'a> {
    decay: &'a DecayData,
    step: &'a Step,
}

impl NonlinearSystem for DecayStep<'_> {
    fn constraints(&self) -> &Constraints {
        self.decay.assembly.constraints()
    }

    fn evaluate(&mut self, u: &[f64], residual: &mut [f64], jacobian: Option<&mut [f64]>) {
        let (d, s) = (self.decay, self.step);
        for (i, r) in residual.iter_mut().enumerate() {
            *r = d.lambda[i] * u[i] + d.cubic * u[i].powi(3) + s.rate * (u[i] - s.history[i])
                - d.forcing * s.t.sin();
        }
        if let Some(jacobian) = jacobian {
            jacobian.iter_mut().for_each(|j| *j = 0.0);
            for (i, &p) in d.diagonal.iter().enumerate() {
                jacobian[p] = d.lambda[i] + 3.0 * d.cubic * u[i] * u[i] + s.rate;
            }
        }
    }

    fn is_linear(&self) -> bool {
        self.decay.cubic <= 0.0
    }
}

impl TransientProblem for Decay {
    type Error = TimeError;
    type System<'a> = DecayStep<'a>;

    fn constraints(&self) -> &Constraints {
        self.data.assembly.constraints()
    }

    fn newton(&mut self) -> &mut NewtonSolver {
        &mut self.newton
    }

    fn newton_options(&self) -> NewtonOptions {
        NewtonOptions { residual_tolerance: 1e-13, ..NewtonOptions::default() }
    }

    fn residual_scale(&mut self) -> f64 {
        1.0
    }

    fn prepare(&mut self, _step: &Step) {}

    fn step_system<'a>(&'a mut self, step: &'a Step) -> (&'a mut NewtonSolver, DecayStep<'a>) {
        (&mut self.newton, DecayStep { decay: &self.data, step })
    }

    fn is_linear(&self) -> bool {
        self.data.cubic <= 0.0
    }

    fn static_residual(&mut self, u: &[f64]) -> Vec<f64> {
        let d = &self.data;
        (0..4).map(|i| d.lambda[i] * u[i] + d.cubic * u[i].powi(3)).collect()
    }

    fn mass_product(&self, x: &[f64]) -> Vec<f64> {
        x.to_vec()
    }

    fn add_step_loads(&self, step: &Step, _u: &[f64], residual: &mut [f64]) {
        residual.iter_mut().for_each(|r| *r -= self.data.forcing * step.t.sin());
    }

    fn breakpoints(&self, t_end: f64) -> Vec<f64> {
        self.data.corners.iter().copied().filter(|&t| t < t_end).collect()
    }
}

/// A linear forced decay (the fast path) and a cubic one (Newton), both from `u(0) = 1`.
fn linear() -> Decay {
    Decay::new([0.5, 1.0, 1.5, 2.0], 0.0, 1.0)
}

fn cubic() -> Decay {
    Decay::new([0.0; 4], 0.5, 0.0)
}

fn max_error(u: &[f64], exact: &[f64]) -> f64 {
    u.iter().zip(exact).fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()))
}

/// The largest error over the levels in `[1, 2]` of a run to `t_end = 2` in `steps` uniform steps
/// (past the first second the error is in its asymptotic regime; at one instant it may cross
/// zero).
fn fixed_error(problem: &mut Decay, scheme: Scheme, steps: usize) -> (f64, Outcome) {
    let options = TimeOptions::new(2.0, scheme, TimeStep::Fixed { dt_s: 2.0 / steps as f64 });
    let mut worst = 0.0_f64;
    let outcome = integrate(problem, vec![1.0; 4], &options, |e: &Event<'_, Decay>| {
        if e.level.t >= 1.0 {
            worst = worst.max(max_error(e.level.u, &e.problem.exact(e.level.t, 1.0)));
        }
        Flow::Continue
    })
    .unwrap();
    assert_eq!((outcome.steps, outcome.stopped), (steps, false));
    assert!((outcome.t - 2.0).abs() < f64::EPSILON);
    (worst, outcome)
}

/// The largest error over the levels in `[1, 2]` of a non-uniform grid: the steps `h · [1, 1.6, 0.7]` repeated `cycles`
/// times (step ratios ω = 1.6, 0.4375, 1.43), driven through the run's own step and commit.
fn variable_error(problem: &mut Decay, scheme: Scheme, cycles: usize) -> f64 {
    let pattern = [1.0, 1.6, 0.7];
    let h = 2.0 / (3.3 * cycles as f64);
    let options = TimeOptions::new(2.0, scheme, TimeStep::Fixed { dt_s: h });
    let mut run = Run::new(problem, vec![1.0; 4], &options);
    let (mut t, mut worst) = (0.0, 0.0_f64);
    for k in 0..3 * cycles {
        let dt = h * pattern[k % 3];
        t += dt;
        let attempt = run.attempt(problem, t, dt).unwrap();
        run.commit(problem, &mut Silent, Some(attempt)).unwrap();
        if t >= 1.0 {
            worst = worst.max(max_error(run.state(), &problem.exact(t, 1.0)));
        }
    }
    worst
}

/// Observed orders `log(e_k/e_{k+1}) / log 2` of errors at halved steps.
fn orders(errors: &[f64]) -> Vec<f64> {
    errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect()
}

fn assert_order(name: &str, errors: &[f64], expected: usize) {
    let o = orders(errors);
    println!("{name}: errors {errors:?}, orders {o:.3?}");
    let p = expected as f64;
    assert!(o.iter().all(|&o| (o - p).abs() < 0.15 * p), "{name}: orders {o:?}, expected {p}");
}

#[test]
fn fixed_steps_converge_at_the_schemes_orders() {
    for (scheme, p) in [(Scheme::ImplicitEuler, 1), (Scheme::Bdf2, 2)] {
        for (name, mut problem) in [("linear", linear()), ("cubic", cubic())] {
            let errors: Vec<f64> = [40, 80, 160, 320]
                .iter()
                .map(|&n| fixed_error(&mut problem, scheme, n).0)
                .collect();
            assert_order(&format!("{scheme}, {name}, fixed steps"), &errors, p);
        }
    }
}

#[test]
fn variable_steps_converge_at_the_schemes_orders() {
    for (scheme, p) in [(Scheme::ImplicitEuler, 1), (Scheme::Bdf2, 2)] {
        for (name, mut problem) in [("linear", linear()), ("cubic", cubic())] {
            let errors: Vec<f64> = [16, 32, 64, 128]
                .iter()
                .map(|&n| variable_error(&mut problem, scheme, n))
                .collect();
            assert_order(&format!("{scheme}, {name}, variable steps"), &errors, p);
        }
    }
}

#[test]
fn the_linear_path_factorises_once_per_rate_and_newton_iterates() {
    let (_, outcome) = fixed_error(&mut linear(), Scheme::Bdf2, 50);
    // BDF2's Euler start and the rest: two rates, two factorisations, one solve per step.
    assert_eq!((outcome.factorizations, outcome.newton_iterations), (2, 50));
    let (_, outcome) = fixed_error(&mut linear(), Scheme::ImplicitEuler, 50);
    assert_eq!(outcome.factorizations, 1);
    let (_, outcome) = fixed_error(&mut cubic(), Scheme::Bdf2, 50);
    assert!(outcome.newton_iterations > 50, "Newton iterates: {outcome:?}");
}

/// The largest error over every level of a run of the fast cubic decay `u̇ = −20 u³` (most of
/// the change in the first hundredth of the run), and the run's outcome.
fn fast_decay_error(step: TimeStep, scheme: Scheme) -> (f64, Outcome) {
    let mut problem = Decay::new([0.0; 4], 20.0, 0.0);
    let mut worst = 0.0_f64;
    let options = TimeOptions::new(2.0, scheme, step);
    let outcome = integrate(&mut problem, vec![1.0; 4], &options, |e: &Event<'_, Decay>| {
        worst = worst.max(max_error(e.level.u, &e.problem.exact(e.level.t, 1.0)));
        Flow::Continue
    })
    .unwrap();
    (worst, outcome)
}

#[test]
fn adaptive_steps_meet_their_tolerance_in_fewer_steps() {
    for scheme in [Scheme::ImplicitEuler, Scheme::Bdf2] {
        let mut previous = f64::INFINITY;
        for rtol in [1e-2, 1e-3, 1e-4] {
            let (error, outcome) =
                fast_decay_error(TimeStep::Adaptive { rtol, dt_initial_s: 1e-4 }, scheme);
            let steps = outcome.steps;
            let (fixed, _) = fast_decay_error(TimeStep::Fixed { dt_s: 2.0 / steps as f64 }, scheme);
            println!(
                "{scheme} rtol {rtol:e}: {steps} steps ({} rejected), error {error:.2e}; as many \
                 fixed steps: {fixed:.2e}",
                outcome.rejected_steps
            );
            assert!((outcome.t - 2.0).abs() < 1e-12, "lands on t_end");
            assert!(error < previous, "{scheme}: a tighter tolerance, a smaller error");
            assert!(error < 0.5 * fixed, "{scheme}: steps where the solution changes");
            previous = error;
        }
    }
}

#[test]
fn adaptive_steps_land_on_breakpoints_and_t_end() {
    let mut times = Vec::new();
    let mut problem = linear();
    problem.data.corners = vec![1.5, 0.7];
    let step = TimeStep::Adaptive { rtol: 1e-2, dt_initial_s: 0.3 };
    let options = TimeOptions::new(2.0, Scheme::Bdf2, step);
    integrate(&mut problem, vec![1.0; 4], &options, |e: &Event<'_, Decay>| {
        times.push(e.level.t);
        Flow::Continue
    })
    .unwrap();
    assert!(times.windows(2).all(|w| w[1] > w[0]), "{times:?}");
    for stop in [0.7, 1.5, 2.0] {
        assert!(times.iter().any(|t| (t - stop).abs() < 1e-12), "{stop} not in {times:?}");
    }
}

#[test]
fn an_observer_stop_ends_the_run_after_its_level() {
    let mut seen = Vec::new();
    let options = TimeOptions::new(1.0, Scheme::Bdf2, TimeStep::Fixed { dt_s: 0.1 });
    let outcome = integrate(&mut linear(), vec![1.0; 4], &options, |e: &Event<'_, Decay>| {
        seen.push(e.level.index);
        Flow::stop_if(e.level.index == 3)
    })
    .unwrap();
    assert_eq!(seen, [0, 1, 2, 3]);
    assert!(outcome.stopped && outcome.steps == 3 && (outcome.t - 0.3).abs() < 1e-12);
}

#[test]
fn levels_carry_the_schemes_derivative() {
    // At every level the scheme's u̇ = ρ (u − h) approaches the equation's right-hand side.
    let mut worst = 0.0_f64;
    let options = TimeOptions::new(1.0, Scheme::Bdf2, TimeStep::Fixed { dt_s: 1e-3 });
    integrate(&mut linear(), vec![1.0; 4], &options, |e: &Event<'_, Decay>| {
        let derivative = e.level.derivative();
        if e.level.index == 0 {
            assert!(derivative.iter().all(|d| d.abs() < f64::MIN_POSITIVE));
        }
        for (i, d) in derivative.iter().enumerate().filter(|_| e.level.index > 0) {
            let rhs = -e.problem.data.lambda[i] * e.level.u[i] + e.level.t.sin();
            worst = worst.max((d - rhs).abs());
        }
        Flow::Continue
    })
    .unwrap();
    assert!(worst < 1e-10, "{worst:e}");
}

#[test]
fn invalid_options_and_keys_name_the_key() {
    let fixed = |t_end: f64, dt_s: f64| {
        TimeOptions::new(t_end, Scheme::Bdf2, TimeStep::Fixed { dt_s }).validate().unwrap_err()
    };
    assert!(fixed(1e-3, 1e-2).to_string().contains("t_end: = 0.001 s is shorter than dt"));
    assert!(fixed(1.0, f64::NAN).to_string().contains("dt: = NaN s must be finite and > 0"));
    assert!(fixed(1.0, 1e-9).to_string().contains("exceeds the limit"));
    let keys =
        StepKeys { t_end: 1.0, dt: Some(0.1), scheme: Some("trapezoid"), ..StepKeys::default() };
    let e = TimeOptions::from_keys(&keys).unwrap_err();
    assert_eq!(e.errors()[0].field, "scheme");
    assert!(e.to_string().contains("\"trapezoid\" is not known"), "{e}");
    let both = StepKeys {
        t_end: 1.0,
        dt: Some(0.1),
        adaptive: Some(AdaptiveKeys { rtol: 1e-3, dt_initial: 1e-3 }),
        ..StepKeys::default()
    };
    assert_eq!(TimeOptions::from_keys(&both).unwrap_err().errors()[0].field, "adaptive");
    let neither = StepKeys { t_end: 1.0, ..StepKeys::default() };
    assert_eq!(TimeOptions::from_keys(&neither).unwrap_err().errors()[0].field, "dt");
    let bad = StepKeys {
        t_end: -1.0,
        adaptive: Some(AdaptiveKeys { rtol: 2.0, dt_initial: 0.0 }),
        ..StepKeys::default()
    };
    let fields: Vec<String> = TimeOptions::from_keys(&bad)
        .unwrap_err()
        .errors()
        .iter()
        .map(|e| e.field.clone())
        .collect();
    assert_eq!(fields, ["t_end", "adaptive.rtol", "adaptive.dt_initial"]);
    assert_eq!("euler".parse::<Scheme>(), Ok(Scheme::ImplicitEuler));
    assert_eq!("bdf2".parse::<Scheme>(), Ok(Scheme::Bdf2));
}
