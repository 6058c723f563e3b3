//! Structured mutation fuzzing of every mrbrake parser and loader, on the stable toolchain
//! (issue 18: CI machines have no nightly, so no libFuzzer; AFL++ needs its own compiler pass).
//!
//! Brief overview:
//! - [`mod@targets`] lists one [`Target`] per input format — brake spec, magnetic and heat problem
//!   files, MSH 2.2 and 4.1, optimisation problem, rig configuration, CSV logs (characterisation),
//!   sine-test manifest, FRD, inverse-model JSON, results store, and (issue 33) magnetodynamic
//!   problem files, brake-model files, Preisach rigs with their minor-loop programs and the
//!   `response`/`thermal` options, and the studio's HTTP endpoints (`targets::studio`: raw
//!   requests to a running studio) — each with its seed corpus (the
//!   files of `examples/` and the test fixtures, plus files the library writes itself) and a
//!   function that feeds one input through the loader and, where cheap, the next stage.
//! - [`mutate`] derives a new input from a corpus entry: byte flips, deletions, duplications,
//!   splices with another entry, and *structured* edits that replace a number with a hostile one
//!   (0, −1, 5e-324, 1e308, NaN, inf, 999999999999, …), cut or repeat whole lines.
//! - [`fuzz`] runs a target for a time or execution budget: each input runs under
//!   `catch_unwind` (a panic is a crash, kept with its message), an execution slower than the
//!   limit is a finding too, and an input whose outcome (ok, or the error's kind and its first
//!   words with digits removed) has not been seen joins the corpus — outcome diversity stands in
//!   for the coverage feedback a compiler-instrumented fuzzer would have.
//!
//! The issue 33 targets check its properties on every execution (`targets::hardening`): an
//! accepted input gives only finite numbers, a refused file names its file; a violation panics and
//! is recorded as a crash like any other.
//!
//! Every crash found becomes a file under `crates/mrbrake-fuzz/regressions/<target>/` that
//! `tests/regressions.rs` replays. `mrbrake-fuzz --seconds N` is the bounded CI run (`.ci/run`);
//! longer runs are documented in the crate's README.

pub mod targets;

use std::collections::HashSet;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::time::{Duration, Instant};

use mrbrake_optim::rng::Rng;

pub use targets::{Target, targets};

/// What one execution of a target gave.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Outcome {
    /// The input was accepted.
    Ok,
    /// The input was refused with an error: its kind and message, normalised (digits removed,
    /// cut to a few words) so that the signature names the check that fired, not the values.
    Refused(String),
}

impl Outcome {
    /// The outcome of a library result: `Ok`, or the error's kind and normalised message.
    pub fn of<T, E: mrbrake_error::Kind + std::fmt::Display>(result: Result<T, E>) -> Self {
        match result {
            Ok(_) => Self::Ok,
            Err(e) => Self::Refused(format!("{:?}: {}", e.kind(), normalise(&e.to_string()))),
        }
    }
}

/// The first 60 characters of `message` without digits or file paths (signature of a check).
pub(crate) fn normalise(message: &str) -> String {
    let without_paths = message.rsplit(".toml").next().unwrap_or(message);
    without_paths
        .chars()
        .filter(|c| !c.is_ascii_digit() && *c != '.' && *c != '-')
        .take(60)
        .collect()
}

/// A crash: the input and the panic message.
#[derive(Debug, Clone)]
pub struct Crash {
    /// The input that panicked.
    pub input: Vec<u8>,
    /// The panic's message.
    pub message: String,
}

/// What a run of one target found.
#[derive(Debug, Clone, Default)]
pub struct Report {
    /// The target's name.
    pub target: String,
    /// Inputs executed.
    pub executions: u64,
    /// Wall time, s.
    pub seconds: f64,
    /// Corpus size at the end (seeds plus inputs with a new outcome).
    pub corpus: usize,
    /// Distinct outcomes seen.
    pub outcomes: usize,
    /// Inputs that panicked (each distinct panic message once).
    pub crashes: Vec<Crash>,
    /// Inputs slower than the limit, with their time in seconds.
    pub slow: Vec<(Vec<u8>, f64)>,
}

/// Budget and limits of a run.
#[derive(Debug, Clone, Copy)]
pub struct Budget {
    /// Wall time for the target.
    pub time: Duration,
    /// At most this many executions.
    pub max_executions: u64,
    /// An execution slower than this is reported as slow.
    pub slow_after: Duration,
    /// Seed of the mutation generator.
    pub seed: u64,
}

/// Runs `target` within `budget` (module docs). `on_input` sees each input before it runs (the
/// binary keeps it on disk, so an abort or a hang leaves the culprit behind).
pub fn fuzz(target: &Target, budget: Budget, mut on_input: impl FnMut(&[u8])) -> Report {
    let start = Instant::now();
    let mut rng = Rng::new(budget.seed);
    let mut corpus: Vec<Vec<u8>> = target.seeds.clone();
    let mut seen = HashSet::new();
    let mut crash_messages = HashSet::new();
    let mut report = Report { target: target.name.to_string(), ..Report::default() };
    let mut next_seed = 0;
    while start.elapsed() < budget.time && report.executions < budget.max_executions {
        // Seeds first, unmutated; then mutations of the corpus.
        let input = if next_seed < target.seeds.len() {
            next_seed += 1;
            target.seeds[next_seed - 1].clone()
        } else {
            let base = &corpus[rng.index(corpus.len())];
            let other = &corpus[rng.index(corpus.len())];
            mutate(&mut rng, base, other)
        };
        on_input(&input);
        let t0 = Instant::now();
        let result = catch_unwind(AssertUnwindSafe(|| (target.run)(&input)));
        let took = t0.elapsed();
        report.executions += 1;
        if took > budget.slow_after {
            report.slow.push((input.clone(), took.as_secs_f64()));
        }
        match result {
            Ok(outcome) => {
                if seen.insert(outcome) {
                    corpus.push(input);
                }
            }
            Err(payload) => {
                let message = panic_message(payload.as_ref());
                if crash_messages.insert(message.clone()) {
                    report.crashes.push(Crash { input, message });
                }
            }
        }
    }
    report.seconds = start.elapsed().as_secs_f64();
    report.corpus = corpus.len();
    report.outcomes = seen.len();
    report
}

fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<String>()
        .cloned()
        .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_else(|| "a panic without a message".into())
}

/// Numbers a hostile user (or a flaky rig) writes: zero, signs, subnormals, overflow, non-finite
/// values, counts near the integer limits.
const HOSTILE_NUMBERS: &[&str] = &[
    "0",
    "-0",
    "-1",
    "1",
    "2",
    "0.0",
    "1e-9",
    "5e-324",
    "1e-300",
    "1e300",
    "1e308",
    "-1e308",
    "1.8e308",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "999999999999",
    "2147483647",
    "4294967296",
    "9223372036854775807",
    "18446744073709551615",
    "1000000000",
    "65",
    "3",
    "0.5um",
    "1e-9mm",
    "1e9mm",
    "\"0mm\"",
    "\"-1mm\"",
    "\"1e308m\"",
    "\"nanmm\"",
    "[]",
    "\"\"",
];

/// A new input derived from `base` (and `other`, for splices); module docs list the edits.
pub fn mutate(rng: &mut Rng, base: &[u8], other: &[u8]) -> Vec<u8> {
    let mut out = base.to_vec();
    let edits = 1 + rng.index(3);
    for _ in 0..edits {
        match rng.index(8) {
            0 => flip_byte(rng, &mut out),
            1 => delete_range(rng, &mut out),
            2 => duplicate_range(rng, &mut out),
            3 => splice(rng, &mut out, other),
            4 | 5 => replace_number(rng, &mut out),
            6 => edit_line(rng, &mut out),
            _ => insert_hostile(rng, &mut out),
        }
    }
    out
}

fn flip_byte(rng: &mut Rng, data: &mut [u8]) {
    if !data.is_empty() {
        let i = rng.index(data.len());
        data[i] ^= 1 << rng.index(8);
    }
}

fn range(rng: &mut Rng, len: usize) -> (usize, usize) {
    if len == 0 {
        return (0, 0);
    }
    let a = rng.index(len);
    let b = (a + 1 + rng.index(64.min(len - a))).min(len);
    (a, b)
}

fn delete_range(rng: &mut Rng, data: &mut Vec<u8>) {
    let (a, b) = range(rng, data.len());
    data.drain(a..b);
}

fn duplicate_range(rng: &mut Rng, data: &mut Vec<u8>) {
    if data.len() > 1 << 20 {
        return;
    }
    let (a, b) = range(rng, data.len());
    let piece: Vec<u8> = data[a..b].to_vec();
    let at = rng.index(data.len() + 1);
    data.splice(at..at, piece);
}

fn splice(rng: &mut Rng, data: &mut Vec<u8>, other: &[u8]) {
    if other.is_empty() {
        return;
    }
    let (a, b) = range(rng, other.len());
    let at = rng.index(data.len() + 1);
    let end = (at + rng.index(64)).min(data.len());
    data.splice(at..end, other[a..b].iter().copied());
}

/// Replaces one numeric token (digits with an optional sign, point and exponent) by a hostile
/// number.
fn replace_number(rng: &mut Rng, data: &mut Vec<u8>) {
    let starts: Vec<usize> = (0..data.len())
        .filter(|&i| data[i].is_ascii_digit() && (i == 0 || !is_number_byte(data[i - 1])))
        .collect();
    if starts.is_empty() {
        return insert_hostile(rng, data);
    }
    let a = starts[rng.index(starts.len())];
    let b = (a..data.len()).find(|&i| !is_number_byte(data[i])).unwrap_or(data.len());
    let with = HOSTILE_NUMBERS[rng.index(HOSTILE_NUMBERS.len())].as_bytes();
    data.splice(a..b, with.iter().copied());
}

fn is_number_byte(b: u8) -> bool {
    b.is_ascii_digit() || matches!(b, b'.' | b'e' | b'E' | b'+' | b'-')
}

fn insert_hostile(rng: &mut Rng, data: &mut Vec<u8>) {
    let with = HOSTILE_NUMBERS[rng.index(HOSTILE_NUMBERS.len())].as_bytes();
    let at = rng.index(data.len() + 1);
    data.splice(at..at, with.iter().copied());
}

/// Deletes, repeats or swaps whole lines (a truncated section, a duplicated manifest row).
fn edit_line(rng: &mut Rng, data: &mut Vec<u8>) {
    let text = String::from_utf8_lossy(data).into_owned();
    let mut lines: Vec<&str> = text.split('\n').collect();
    if lines.len() < 2 {
        return;
    }
    let i = rng.index(lines.len());
    match rng.index(3) {
        0 => {
            lines.remove(i);
        }
        1 => lines.insert(i, lines[i]),
        _ => {
            let j = rng.index(lines.len());
            lines.swap(i, j);
        }
    }
    *data = lines.join("\n").into_bytes();
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mutations_are_reproducible_and_change_the_input() {
        let base = b"[drum]\ngap = \"0.5mm\"\nheight = 14\n".to_vec();
        let run = |seed| {
            let mut rng = Rng::new(seed);
            (0..50).map(|_| mutate(&mut rng, &base, b"x = 1\n")).collect::<Vec<_>>()
        };
        assert_eq!(run(3), run(3));
        assert!(run(3).iter().filter(|m| **m != base).count() > 40);
    }

    #[test]
    fn outcomes_ignore_the_values_in_messages() {
        let a = normalise("f.msh:12: the number of nodes is 999");
        let b = normalise("f.msh:7: the number of nodes is 12");
        assert_eq!(a, b);
    }
}
