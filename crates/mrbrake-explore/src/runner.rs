//! Evaluates batches of designs in parallel and stores each result the moment it completes.
//!
//! Brief overview: [`Runner::run`] takes a batch of [`Design`]s, skips those whose key the store
//! already holds (and duplicates within the batch), records invalid designs as `infeasible`
//! without analysis, and analyses the rest on a pool of `jobs` worker threads (rayon). Workers send
//! each outcome over a channel to the calling thread, the store's single writer, which inserts it
//! in its own durable transaction before showing the caller's [`Observer`] the [`Progress`]. A
//! run that is killed at any point therefore loses at most the evaluations in flight; re-running
//! the same batch recomputes only those. The records of the whole batch are returned in batch
//! order. An observer's [`Flow::Stop`] stops the workers from taking new designs; the designs in
//! flight finish and are stored, and the run ends with [`ExploreError::Stopped`].
//!
//! A stored design that lacks metrics the study asks for (a study resumed with a longer metric
//! list, see [`crate::metrics::StudyMetrics::needs_completion`]) is *completed*: only its missing
//! metrics are computed ([`crate::evaluate::complete`], no static analysis) and the record is
//! extended in place ([`Store::complete`]); it counts as computed, not reused, and as
//! [`Progress::completed`] (the summaries say "completed" for it).
//!
//! [`Flow::Stop`]: mrbrake_observe::Flow::Stop

use std::collections::HashSet;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Instant;

use mrbrake_observe::Observer;
use mrbrake_store::{Record, Status, Store};
use rayon::prelude::*;

use crate::ExploreError;
use crate::design::{Design, solver_version};
use crate::evaluate::{EvaluationSettings, Outcome, complete, evaluate};

/// One evaluation to compute: a new design, or a stored record to complete with the metrics it
/// lacks.
struct Job<'d> {
    design: &'d Design,
    stored: Option<Record>,
}

/// Where a run stands, reported after every stored evaluation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress {
    /// Evaluations to compute in this run (designs not yet in the store, and stored designs to
    /// complete with the metrics they lack).
    pub to_compute: usize,
    /// Evaluations computed and stored so far.
    pub computed: usize,
    /// Of the computed: stored designs completed with the metrics they lacked (no static
    /// analysis again).
    pub completed: usize,
    /// Designs of the batch found in the store with every metric asked for (not recomputed).
    pub reused: usize,
    /// Of the computed: infeasible designs.
    pub infeasible: usize,
    /// Of the computed: numerical failures.
    pub failed: usize,
    /// Wall time since the run started (s).
    pub elapsed_s: f64,
}

impl Progress {
    /// Adds the counts and time of `other` (a later run's) to these.
    pub fn add(&mut self, other: &Progress) {
        self.to_compute += other.to_compute;
        self.computed += other.computed;
        self.completed += other.completed;
        self.reused += other.reused;
        self.infeasible += other.infeasible;
        self.failed += other.failed;
        self.elapsed_s += other.elapsed_s;
    }
}

/// What a run did.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSummary {
    /// The final progress.
    pub progress: Progress,
    /// Sum of the analyses' own wall times (s) (exceeds the elapsed time with several jobs).
    pub evaluation_s: f64,
    /// Wall time spent inserting into the store (s), on the writer thread.
    pub store_s: f64,
}

/// Evaluates designs into a store.
pub struct Runner<'a> {
    store: &'a mut Store,
    settings: EvaluationSettings,
    jobs: usize,
}

/// Opens the results store of a sweep at `path` (created if missing; an existing store only with
/// `resume`) and records `created_by` (e.g. `mrbrake 0.1.0`) in a new one.
pub fn open_sweep_store(
    path: &std::path::Path,
    resume: bool,
    created_by: &str,
) -> Result<Store, ExploreError> {
    let mut store = Store::open_or_create(path, resume)?;
    if store.meta("created_by")?.is_none() {
        store.set_meta("created_by", created_by)?;
    }
    Ok(store)
}

impl<'a> Runner<'a> {
    /// A runner writing to `store`, analysing with `settings` on `jobs` threads (0: one per core).
    pub fn new(store: &'a mut Store, settings: EvaluationSettings, jobs: usize) -> Self {
        Self { store, settings, jobs }
    }

    /// The store.
    pub fn store(&self) -> &Store {
        self.store
    }

    /// The store, to record a study's meta data between batches (e.g. the hypervolume's
    /// reference point an optimisation fixed).
    pub fn store_mut(&mut self) -> &mut Store {
        self.store
    }

    /// Evaluates `designs` (see the module docs), showing `observer` the [`Progress`] before the
    /// first evaluation and after each stored result, and returns every design's record, in
    /// order, with the run's summary. A stop asked for before every design is stored ends the
    /// run with [`ExploreError::Stopped`] once the designs in flight are stored.
    pub fn run(
        &mut self,
        designs: &[Design],
        observer: &mut impl Observer<Progress>,
    ) -> Result<(Vec<Record>, RunSummary), ExploreError> {
        let start = Instant::now();
        let (todo, reused) = self.to_compute(designs)?;
        let mut progress = Progress {
            to_compute: todo.len(),
            computed: 0,
            completed: 0,
            reused,
            infeasible: 0,
            failed: 0,
            elapsed_s: 0.0,
        };
        let mut timing = Timing { start, evaluation_s: 0.0, store_s: 0.0 };
        if !observer.observe(&progress).is_stop() {
            self.evaluate_into_store(&todo, &mut timing, &mut progress, observer)?;
        }
        progress.elapsed_s = start.elapsed().as_secs_f64();
        if progress.computed < progress.to_compute {
            return Err(ExploreError::Stopped { progress });
        }
        let mut records = Vec::with_capacity(designs.len());
        for design in designs {
            // A record reused from a store written before the unit convention reads under the
            // current metric names.
            let record = crate::stored::read_record(self.store, &design.key)?.ok_or_else(|| {
                ExploreError::Internal(format!("design {} missing from the store", design.key))
            })?;
            records.push(record);
        }
        let summary =
            RunSummary { progress, evaluation_s: timing.evaluation_s, store_s: timing.store_s };
        Ok((records, summary))
    }

    /// The evaluations of the batch to compute (designs not stored, and stored ones lacking
    /// asked-for metrics; first of their key) and how many designs are stored already, complete.
    fn to_compute<'d>(&self, designs: &'d [Design]) -> Result<(Vec<Job<'d>>, usize), ExploreError> {
        let stored = self.store.keys()?;
        let study = &self.settings.study;
        let mut seen = HashSet::new();
        let mut todo: Vec<Job<'d>> = Vec::new();
        let mut reused = 0;
        for design in designs {
            if !seen.insert(design.key.as_str()) {
                if stored.contains(&design.key) {
                    reused += 1;
                }
                continue;
            }
            if !stored.contains(&design.key) {
                todo.push(Job { design, stored: None });
                continue;
            }
            let record = if study.is_static() {
                None
            } else {
                crate::stored::read_record(self.store, &design.key)?
            };
            match record.filter(|r| design.spec.is_ok() && study.needs_completion(r)) {
                Some(record) => todo.push(Job { design, stored: Some(record) }),
                None => reused += 1,
            }
        }
        Ok((todo, reused))
    }

    /// Analyses `todo` on the worker pool while this thread stores each outcome as it arrives;
    /// after a store error the workers stop taking new designs and the error is returned. After
    /// the observer asks to stop they stop taking new designs too, and the ones in flight are
    /// still stored.
    fn evaluate_into_store(
        &mut self,
        todo: &[Job<'_>],
        timing: &mut Timing,
        progress: &mut Progress,
        observer: &mut impl Observer<Progress>,
    ) -> Result<(), ExploreError> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(self.jobs)
            .thread_name(|i| format!("mrbrake-eval-{i}"))
            .build()
            .map_err(|e| ExploreError::Internal(format!("cannot start worker threads: {e}")))?;
        let stop = AtomicBool::new(false);
        // One copy for the workers and the writer (a study's settings hold its metric list).
        let settings = &self.settings.clone();
        // A rendezvous channel: a worker hands its result to the writer before it starts another
        // design, so a stop leaves at most one design per worker in flight (an unbounded queue let
        // a worker run ahead of a slow durable write: CI saw three designs computed with one
        // worker after a stop at the first), and finished results never pile up in memory.
        let (sender, receiver) = mpsc::sync_channel::<(usize, Outcome, f64)>(0);
        let mut first_error: Option<ExploreError> = None;
        std::thread::scope(|scope| {
            let stop = &stop;
            scope.spawn(move || {
                pool.install(|| {
                    todo.par_iter().enumerate().for_each_with(sender, |sender, (i, job)| {
                        if stop.load(Ordering::Relaxed) {
                            return;
                        }
                        let t0 = Instant::now();
                        let outcome = match (&job.design.spec, &job.stored) {
                            (Ok(spec), Some(stored)) => complete(spec, settings, &stored.metrics),
                            (Ok(spec), None) => evaluate(spec, settings),
                            (Err(reason), _) => Outcome::infeasible(reason.to_string()),
                        };
                        // The receiver only hangs up after an error; then the result is moot.
                        let _ = sender.send((i, outcome, t0.elapsed().as_secs_f64()));
                    });
                });
            });
            // This thread is the store's single writer.
            for (i, outcome, seconds) in receiver {
                if first_error.is_some() {
                    continue;
                }
                let job = &todo[i];
                let mut record = record_of(job.design, outcome, seconds, settings);
                if let Some(stored) = &job.stored {
                    record.eval_seconds += stored.eval_seconds;
                }
                let completes = job.stored.is_some();
                if let Err(e) = self.store_record(&record, completes, seconds, timing, progress) {
                    stop.store(true, Ordering::Relaxed);
                    first_error = Some(e);
                    continue;
                }
                if observer.observe(progress).is_stop() {
                    stop.store(true, Ordering::Relaxed);
                }
            }
        });
        first_error.map_or(Ok(()), Err)
    }

    /// Inserts one record, or completes the stored one (its own durable transaction), and
    /// counts it.
    fn store_record(
        &mut self,
        record: &Record,
        completes: bool,
        evaluation_s: f64,
        timing: &mut Timing,
        progress: &mut Progress,
    ) -> Result<(), ExploreError> {
        let t0 = Instant::now();
        if completes {
            let upgrade = crate::evaluate::upgrade_metric_list;
            self.store.complete_upgrading(record, &|metrics| upgrade(metrics))?;
        } else {
            self.store.insert(record)?;
        }
        timing.store_s += t0.elapsed().as_secs_f64();
        timing.evaluation_s += evaluation_s;
        progress.computed += 1;
        progress.completed += usize::from(completes);
        match record.status {
            Status::Infeasible => progress.infeasible += 1,
            Status::Failed => progress.failed += 1,
            Status::Ok => {}
        }
        progress.elapsed_s = timing.start.elapsed().as_secs_f64();
        Ok(())
    }
}

/// When the run started and the time spent in analyses and in the store.
struct Timing {
    start: Instant,
    evaluation_s: f64,
    store_s: f64,
}

fn record_of(
    design: &Design,
    outcome: Outcome,
    seconds: f64,
    settings: &EvaluationSettings,
) -> Record {
    Record {
        key: design.key.clone(),
        status: outcome.status,
        reason: outcome.reason,
        variables: design.variables.clone(),
        metrics: outcome.metrics,
        spec_toml: design.spec_toml.clone(),
        eval_seconds: seconds,
        solver_version: solver_version(),
        settings: settings.recorded(),
    }
}
