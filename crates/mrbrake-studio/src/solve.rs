//! The bounded solve queue: at most one waiting entry per session (a newer edit replaces the
//! older one in place, so a flood of edits cannot grow it), served by a fixed number of workers
//! (at most one running solve per core). A worker solves the latest edit of a session on the
//! coarse mesh, then on the default mesh; an edit or a cancel made meanwhile makes the running
//! solve obsolete, and it stops at the next cancellation point without publishing anything.
//!
//! The cancellation points are before each stage and after each current of the sweep: the
//! analysis's observer (`mrbrake_observe::Observer<Count>`) answers `Flow::Stop` once the solve is
//! obsolete, and the sweep ends there (`DesignError::Stopped`) instead of finishing its stage.

use std::collections::VecDeque;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::time::Instant;

use mrbrake_design::analysis::{AnalysisOptions, AnalysisRequest};
use mrbrake_design::geometry;
use mrbrake_design::mesh_build::MeshLevel;
use mrbrake_design::spec::BrakeSpec;
use mrbrake_observe::{Count, Flow};
use mrbrake_report::analysis::{
    field_map, field_map_title, gap_flux_density_figure, torque_current_figure,
};
use mrbrake_report::field_map::field_map_svg;
use mrbrake_report::html::inline_svg;
use serde_json::{Value, json};

use crate::on_request::{self, Kind};
use crate::session::{Session, Solved, chain};

/// A solve stage: the coarse mesh answers first, the default mesh replaces it.
#[derive(Debug, Clone, Copy)]
pub struct StageSettings {
    /// `coarse` or `default`.
    pub name: &'static str,
    /// Mesh density.
    pub mesh: MeshLevel,
    /// Currents of the sweep.
    pub points: usize,
}

/// The two stages, in order: the coarse one with a short sweep (torque at the maximum current,
/// mean B and the field map at once), then `analyze`'s defaults.
pub const STAGES: [StageSettings; 2] = [
    StageSettings { name: "coarse", mesh: MeshLevel::Coarse, points: 6 },
    StageSettings { name: "default", mesh: MeshLevel::Default, points: 21 },
];

impl StageSettings {
    /// The analysis options: `analyze`'s defaults with this mesh and sweep.
    pub fn options(self) -> AnalysisOptions {
        AnalysisOptions { mesh: self.mesh, points: self.points, ..AnalysisOptions::default() }
    }

    /// The CLI command that prints the same numbers.
    pub fn command(self) -> String {
        format!("mrbrake analyze SPEC --mesh {} --points {} --json", self.name, self.points)
    }
}

/// Whether a solve started at `generation` is still wanted.
pub struct Cancel<'a> {
    session: &'a Session,
    generation: u64,
}

impl Cancel<'_> {
    /// True once an edit or a cancel made the solve obsolete.
    pub fn is_cancelled(&self) -> bool {
        self.session.generation() != self.generation
    }
}

/// What a worker does for a session: the static solves of its latest edit, or an analysis on
/// request.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Job {
    /// The coarse then the default-mesh solve.
    Solve,
    /// One analysis on request.
    Request(Kind),
}

/// The queue of sessions waiting for a solve or an analysis, and its workers' counters.
#[derive(Debug, Default)]
pub struct Queue {
    waiting: Mutex<VecDeque<(Arc<Session>, Job)>>,
    ready: Condvar,
    running: AtomicUsize,
    most_running: AtomicUsize,
    most_waiting: AtomicUsize,
    stop: AtomicBool,
}

/// What the queue has done (for tests and the status line).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct QueueStats {
    /// Sessions waiting now.
    pub waiting: usize,
    /// Solves running now.
    pub running: usize,
    /// The most solves that ever ran at once.
    pub most_running: usize,
    /// The most sessions that ever waited at once.
    pub most_waiting: usize,
}

impl Queue {
    /// Asks for a solve of `session`'s latest edit; a session already waiting keeps its place.
    pub fn submit(&self, session: &Arc<Session>) {
        self.submit_job(session, Job::Solve);
    }

    /// Asks for `job` of `session`; a job already waiting keeps its place (so the queue holds at
    /// most one entry per session and job: four).
    pub fn submit_job(&self, session: &Arc<Session>, job: Job) {
        let mut waiting = self.waiting.lock().unwrap_or_else(|p| p.into_inner());
        if !waiting.iter().any(|(s, j)| s.id == session.id && *j == job) {
            waiting.push_back((Arc::clone(session), job));
            self.most_waiting.fetch_max(waiting.len(), Ordering::SeqCst);
        }
        self.ready.notify_one();
    }

    /// Forgets a closed session.
    pub fn remove(&self, id: &str) {
        self.waiting.lock().unwrap_or_else(|p| p.into_inner()).retain(|(s, _)| s.id != id);
    }

    /// The counters.
    pub fn stats(&self) -> QueueStats {
        QueueStats {
            waiting: self.waiting.lock().unwrap_or_else(|p| p.into_inner()).len(),
            running: self.running.load(Ordering::SeqCst),
            most_running: self.most_running.load(Ordering::SeqCst),
            most_waiting: self.most_waiting.load(Ordering::SeqCst),
        }
    }

    /// Stops the workers after their current solve.
    pub fn shut_down(&self) {
        self.stop.store(true, Ordering::SeqCst);
        self.ready.notify_all();
    }

    /// The next session and job, or `None` when shutting down.
    fn next(&self) -> Option<(Arc<Session>, Job)> {
        let mut waiting = self.waiting.lock().unwrap_or_else(|p| p.into_inner());
        loop {
            if self.stop.load(Ordering::SeqCst) {
                return None;
            }
            if let Some(entry) = waiting.pop_front() {
                return Some(entry);
            }
            waiting = self.ready.wait(waiting).unwrap_or_else(|p| p.into_inner());
        }
    }

    /// A worker's loop: solve sessions until shut down.
    pub fn work(&self) {
        while let Some((session, job)) = self.next() {
            let now = self.running.fetch_add(1, Ordering::SeqCst) + 1;
            self.most_running.fetch_max(now, Ordering::SeqCst);
            match job {
                Job::Solve => solve_latest(&session),
                Job::Request(kind) => run_request(&session, kind),
            }
            self.running.fetch_sub(1, Ordering::SeqCst);
        }
    }
}

/// Solves the latest edit of `session`, stage by stage, unless it becomes obsolete.
fn solve_latest(session: &Session) {
    let (generation, version, spec, text) = {
        let state = session.lock();
        (session.generation(), state.version, state.spec.clone(), state.text.clone())
    };
    let Some(spec) = spec else { return };
    let cancel = Cancel { session, generation };
    for (k, stage) in STAGES.iter().enumerate() {
        if cancel.is_cancelled() {
            return;
        }
        set_stage(session, &cancel, k, |s| s.status = "running");
        let outcome = run_stage(session, &cancel, k, *stage, &spec, &text);
        let outcome = outcome.map(|(mut result, solved)| {
            result["version"] = json!(version);
            (result, solved)
        });
        let mut state = session.lock();
        if cancel.is_cancelled() {
            return;
        }
        match outcome {
            Ok((result, solved)) => {
                state.stages[k].status = "done";
                state.stages[k].result = result;
                if k + 1 == STAGES.len() {
                    state.solved = Some(Arc::new(solved));
                }
            }
            Err(message) => {
                state.stages[k].status = "failed";
                state.stages[k].result = json!({ "error": message });
                session.notify(&mut state);
                return;
            }
        }
        session.notify(&mut state);
    }
}

/// Runs the analysis `kind` of the latest edit, unless a cancel or an edit makes it obsolete
/// (its result is then dropped: see [`crate::on_request`]).
fn run_request(session: &Session, kind: Kind) {
    let k = kind as usize;
    let (generation, version, spec, solved) = {
        let mut state = session.lock();
        let generation = session.request_generation();
        if state.requests[k].status != "queued" {
            return;
        }
        state.requests[k].status = "running";
        session.notify(&mut state);
        let solved = state.solved.clone().filter(|s| s.text == state.text);
        (generation, state.version, state.spec.clone(), solved)
    };
    let outcome = match &spec {
        Some(spec) => on_request::run(kind, spec, solved.as_deref()),
        None => Err("the spec has errors: nothing to analyse".to_string()),
    };
    let mut state = session.lock();
    if session.request_generation() != generation {
        return;
    }
    let request = &mut state.requests[k];
    match outcome {
        Ok(mut result) => {
            result["version"] = json!(version);
            request.status = "done";
            request.result = result;
        }
        Err(message) => {
            request.status = "failed";
            request.result = json!({ "error": message, "version": version });
        }
    }
    session.notify(&mut state);
}

/// Changes stage `k` of a session that is still at `cancel`'s generation.
fn set_stage(
    session: &Session,
    cancel: &Cancel<'_>,
    k: usize,
    change: impl FnOnce(&mut crate::session::Stage),
) {
    let mut state = session.lock();
    if !cancel.is_cancelled() {
        change(&mut state.stages[k]);
        session.notify(&mut state);
    }
}

/// One stage: the analysis with its field (the library's, as `analyze` runs it), the figures the
/// report draws, and what the downloads need.
fn run_stage(
    session: &Session,
    cancel: &Cancel<'_>,
    k: usize,
    stage: StageSettings,
    spec: &BrakeSpec,
    text: &str,
) -> Result<(Value, Solved), String> {
    let start = Instant::now();
    let options = stage.options();
    // The sweep's observer: progress for the page, and a stop between currents once an edit made
    // this solve obsolete (the sweep then ends with `DesignError::Stopped`).
    let progress = |count: &Count| {
        if cancel.is_cancelled() {
            return Flow::Stop;
        }
        set_stage(session, cancel, k, |s| s.progress = (count.done, count.total));
        Flow::Continue
    };
    let (analysis, field) = AnalysisRequest::of(spec)
        .options(options)
        .observe(progress)
        .run_with_field()
        .map_err(|e| chain(&e))?;
    let geometry = geometry::build(spec).map_err(|e| chain(&e))?;
    let title = field_map_title(&analysis);
    let figure = |svg: Result<String, mrbrake_report::ReportError>, label: &str| {
        svg.and_then(|s| inline_svg(&s, label)).map_err(|e| chain(&e))
    };
    let figures = json!({
        "torque_current": figure(torque_current_figure(&analysis).to_svg(), "torque–current curve")?,
        "gap_flux_density": figure(gap_flux_density_figure(&analysis).to_svg(), "|B| along the gaps")?,
        "field_map": figure(field_map_svg(&field_map(&title, &field)), &title)?,
    });
    let result = json!({
        "stage": stage.name,
        "settings": { "mesh": stage.name, "points": stage.points, "order": 1,
                      "speed": "1rad/s", "temperature": "20C" },
        "cli": stage.command(),
        "analysis": serde_json::to_value(&analysis).map_err(|e| e.to_string())?,
        "figures": figures,
        "elapsed_s": start.elapsed().as_secs_f64(),
    });
    let solved =
        Solved { text: text.to_string(), spec: spec.clone(), geometry, options, analysis, field };
    Ok((result, solved))
}
