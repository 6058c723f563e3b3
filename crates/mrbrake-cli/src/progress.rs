//! Progress of long work on stderr: a bar with rate and ETA when stderr is a terminal, and plain
//! lines when it is not (a pipe, a Slurm or Kubernetes log), so a batch job's log shows life.
//!
//! The lines follow one rule for every command: nothing for work that ends within
//! [`QUIET_FOR`] (short runs stay quiet), then one line per completed design (`sweep`,
//! `optimize`) or per completed step, at most one a second for fast steps (`analyze`'s
//! currents, `haptic zwidth`'s stiffness rows), and a last line when the work is done. The
//! environment variable `MRBRAKE_PROGRESS` overrides the choice: `lines` prints every line from
//! the start (also on a terminal), `off` prints nothing, `auto` (or unset) is the rule above.
//! A command's `quiet` (its `--json`) hides the terminal bar only: lines go to stderr, never
//! into the JSON on stdout, and a batch job that keeps the JSON still shows life in its log.

use std::io::{IsTerminal, Write};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};
use mrbrake::explore::Progress;
use mrbrake::explore::optimize::{OptimizeProgress, Stage};
use mrbrake::explore::surrogate::IterationStatus;

/// Work that ends sooner than this prints no progress lines.
pub const QUIET_FOR: Duration = Duration::from_secs(2);

/// The shortest interval between two lines for fast steps.
const STEP_INTERVAL: Duration = Duration::from_secs(1);

/// How progress is shown, from `MRBRAKE_PROGRESS` and whether stderr is a terminal.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Mode {
    /// A bar on the terminal.
    Bar,
    /// Lines after [`QUIET_FOR`] (stderr is not a terminal).
    Lines,
    /// Every line from the start (`MRBRAKE_PROGRESS=lines`).
    AllLines,
    /// Nothing.
    Off,
}

fn mode(quiet: bool) -> Mode {
    match std::env::var("MRBRAKE_PROGRESS").as_deref().map(str::trim) {
        Ok("off") => Mode::Off,
        Ok("lines") => Mode::AllLines,
        _ if !std::io::stderr().is_terminal() => Mode::Lines,
        _ if quiet => Mode::Off,
        _ => Mode::Bar,
    }
}

/// When a line is due: the rule of the module overview, with the clock passed in (testable).
#[derive(Debug, Clone)]
struct LineRule {
    start: Instant,
    quiet_for: Duration,
    interval: Duration,
    last: Option<Instant>,
}

impl LineRule {
    /// Whether to print a line at `now`, `done` of `total` complete; records the line.
    fn due(&mut self, now: Instant, done: usize, total: usize) -> bool {
        let started = now.duration_since(self.start) >= self.quiet_for;
        let finished = total > 0 && done >= total;
        let spaced = self.last.is_none_or(|last| now.duration_since(last) >= self.interval);
        // The last line is printed once lines have started (or the work has taken long).
        let due = started && (spaced || finished) || (finished && self.last.is_some());
        if due {
            self.last = Some(now);
        }
        due
    }
}

/// Shows the progress of one piece of work on stderr (see the module overview).
pub struct ProgressDisplay {
    bar: ProgressBar,
    what: String,
    unit: &'static str,
    lines: Option<LineRule>,
    /// The `done` of the last optimisation line printed: a line is printed only when it grew.
    last_done: usize,
}

impl ProgressDisplay {
    /// Progress of `what` over designs, one line per completed design; `quiet` hides the bar.
    pub fn new(what: &str, quiet: bool) -> Self {
        Self::with_unit(what, "designs", Duration::ZERO, quiet)
    }

    /// Progress of `what` over fast steps counted in `unit` (at most a line a second).
    pub fn steps(what: &str, unit: &'static str, quiet: bool) -> Self {
        Self::with_unit(what, unit, STEP_INTERVAL, quiet)
    }

    fn with_unit(what: &str, unit: &'static str, interval: Duration, quiet: bool) -> Self {
        let mode = mode(quiet);
        let bar = if mode == Mode::Bar { visible_bar(what, unit) } else { ProgressBar::hidden() };
        let quiet_for = if mode == Mode::AllLines { Duration::ZERO } else { QUIET_FOR };
        let lines = matches!(mode, Mode::Lines | Mode::AllLines).then(|| LineRule {
            start: Instant::now(),
            quiet_for,
            interval: if mode == Mode::AllLines { Duration::ZERO } else { interval },
            last: None,
        });
        Self { bar, what: what.to_string(), unit, lines, last_done: 0 }
    }

    /// Reports a run of designs.
    pub fn update(&mut self, p: &Progress) {
        let detail =
            format!("({} reused, {} infeasible, {} failed)", p.reused, p.infeasible, p.failed);
        self.bar.set_length(p.to_compute as u64);
        self.bar.set_position(p.computed as u64);
        self.bar.set_message(detail.clone());
        self.line(p.computed, p.to_compute, &detail);
    }

    /// Reports an optimisation, counted over the whole run with its generation (or poll): the
    /// lines never restart at a new batch, and none says "0/N" (nothing done yet).
    pub fn update_optimize(&mut self, p: &OptimizeProgress) {
        let stage = match p.stage {
            Stage::Reference => "reference design".to_string(),
            Stage::Generation { index: 0, .. } => "initial population".to_string(),
            Stage::Generation { index, of } => format!("generation {index}/{of}"),
            Stage::Poll { index: 0 } => "start point".to_string(),
            Stage::Poll { index } => format!("poll {index}"),
            Stage::Iteration { index: 0 } => "initial design".to_string(),
            Stage::Iteration { index } => format!("iteration {index}"),
            Stage::FrontDesigns => "front designs, rounded".to_string(),
        };
        if let Some(status) = &p.iteration {
            let line = iteration_line(status);
            // Kept above the bar on a terminal: one line per iteration is the run's history.
            self.bar.println(format!("{}: {stage}: {line}", self.what));
            let Some(rule) = &mut self.lines else { return };
            let now = Instant::now();
            if rule.due(now, p.done, p.total) {
                let elapsed = now.duration_since(rule.start).as_secs_f64();
                let text = format!("{}: {stage}: {line} ({elapsed:.0} s elapsed)", self.what);
                let _ = writeln!(std::io::stderr().lock(), "{text}");
            }
            return;
        }
        let r = &p.run;
        let detail =
            format!("({} reused, {} infeasible, {} failed)", r.reused, r.infeasible, r.failed);
        self.bar.set_length(p.total as u64);
        self.bar.set_position(p.done as u64);
        self.bar.set_message(format!("{stage} {detail}"));
        if p.done <= self.last_done {
            return;
        }
        // Pattern search may converge, and the surrogate stall, before the budget: the total is
        // an upper bound there.
        let of = match p.stage {
            Stage::Poll { .. } | Stage::Iteration { .. } => {
                format!("{} of at most {}", p.done, p.total)
            }
            _ => format!("{}/{}", p.done, p.total),
        };
        let what = format!("{}: {stage}, {of}", self.what);
        if self.line_with(p.done, p.total, &what, &detail) {
            self.last_done = p.done;
        }
    }

    /// Reports `done` of `total` steps.
    pub fn step(&mut self, done: usize, total: usize) {
        self.bar.set_length(total as u64);
        self.bar.set_position(done as u64);
        self.line(done, total, "");
    }

    fn line(&mut self, done: usize, total: usize, detail: &str) {
        let what = format!("{}: {done}/{total}", self.what);
        self.line_with(done, total, &what, detail);
    }

    /// Prints `{what} {unit} done, {elapsed} s elapsed {detail}` when a line is due; returns
    /// whether it did.
    fn line_with(&mut self, done: usize, total: usize, what: &str, detail: &str) -> bool {
        let Some(rule) = &mut self.lines else { return false };
        let now = Instant::now();
        let due = rule.due(now, done, total);
        if due {
            let elapsed = now.duration_since(rule.start).as_secs_f64();
            let text = format!("{what} {} done, {elapsed:.0} s elapsed {detail}", self.unit);
            // A closed stderr must not stop the work.
            let _ = writeln!(std::io::stderr().lock(), "{}", text.trim_end());
        }
        due
    }

    /// Removes the bar.
    pub fn finish(&mut self) {
        self.bar.finish_and_clear();
    }
}

/// A surrogate iteration in words: its batch, the evaluations, the hypervolume and each model's
/// leave-one-out error (or the fallback), and the time the models took.
fn iteration_line(s: &IterationStatus) -> String {
    let models = if let Some(fallback) = &s.fallback {
        fallback.clone()
    } else if s.models.is_empty() {
        "no models yet".to_string()
    } else {
        let fits: Vec<String> =
            s.models.iter().map(|m| format!("{} {:.3}", m.model, m.loo_error)).collect();
        format!("leave-one-out error {}", fits.join(", "))
    };
    format!(
        "batch of {}, {} evaluations, hypervolume {:.6e}; {models}; fit {:.2} s, acquisition {:.2} s",
        s.batch, s.evaluations, s.hypervolume, s.fit_s, s.acquisition_s
    )
}

fn visible_bar(what: &str, unit: &str) -> ProgressBar {
    let bar = ProgressBar::new(0);
    // The template is a constant known to be valid; fall back to the default style if not.
    let template =
        format!("{{prefix}} [{{bar:30}}] {{pos}}/{{len}} {unit}, {{per_sec}}, ETA {{eta}} {{msg}}");
    if let Ok(style) = ProgressStyle::with_template(&template) {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_prefix(what.to_string());
    bar
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rule(interval_s: u64) -> (LineRule, Instant) {
        let start = Instant::now();
        let rule = LineRule {
            start,
            quiet_for: QUIET_FOR,
            interval: Duration::from_secs(interval_s),
            last: None,
        };
        (rule, start)
    }

    #[test]
    fn short_work_is_quiet() {
        let (mut r, t0) = rule(0);
        let at = |ms| t0 + Duration::from_millis(ms);
        assert!(!r.due(at(100), 1, 3));
        assert!(!r.due(at(500), 2, 3));
        assert!(!r.due(at(1900), 3, 3), "done within the quiet time: no line at all");
    }

    #[test]
    fn one_line_per_design_after_the_quiet_time() {
        let (mut r, t0) = rule(0);
        let at = |ms| t0 + Duration::from_millis(ms);
        assert!(!r.due(at(1000), 1, 4));
        assert!(r.due(at(2100), 2, 4));
        assert!(r.due(at(2200), 3, 4));
        assert!(r.due(at(2300), 4, 4));
    }

    #[test]
    fn fast_steps_are_spaced_and_the_last_is_printed() {
        let (mut r, t0) = rule(1);
        let at = |ms| t0 + Duration::from_millis(ms);
        assert!(r.due(at(2000), 10, 100));
        assert!(!r.due(at(2500), 20, 100), "half a second after the last line");
        assert!(r.due(at(3000), 30, 100));
        assert!(r.due(at(3100), 100, 100), "the last step always has its line");
    }
}
