//! `mrbrake studio`: design a brake in the browser. A local web application served by the
//! `mrbrake` binary: a form built from the spec's schema beside its TOML text, the cross-section
//! and the parts at once, a coarse-mesh solve then the default-mesh solve of every edit (a newer
//! edit cancels the older solve), the response, thermal and haptic-wall analyses on request,
//! pinned designs to compare, undo and redo, a results store's Pareto front, and downloads (spec,
//! HTML report, brake model, curves).
//!
//! Brief overview: [`Studio::start`] binds the server ([`Config`]: address, port, the spec or
//! store the user opened, [`Limits`]) and returns at once with its [`Studio::url`] (token
//! included); [`Studio::wait`] serves until the process ends, [`Studio::shut_down`] stops it.
//! Modules: `security` (token, Host and Origin checks), `server` (HTTP on `tiny_http`, body
//! limits, routes), `session` (a tab's spec, history, results), `solve` (the bounded queue and
//! its workers), `on_request` (the response, thermal and haptic analyses the page asks for),
//! `study` (the store's records and front), `downloads`, `assets` (the page:
//! plain HTML, CSS and JavaScript embedded with `include_str!`, no build step).
//!
//! # No numerics here
//! Every number the page shows comes from the library functions the CLI calls
//! (`mrbrake_design::analysis::analyze_with_field_and_progress`, `instant_figures`,
//! `mrbrake_report`'s figures, cross-section and HTML report): the page's figures for a spec and
//! settings are those of `mrbrake analyze SPEC --mesh M --points N --json`, which each result
//! names.
//!
//! # Security (it is a server)
//! - It binds 127.0.0.1 unless told otherwise ([`Config::bind`]; the CLI warns).
//! - Every request needs the session token (128 random bits from the operating system, in the
//!   printed URL; the page sends it in a header), a `Host` naming this server (DNS rebinding) and,
//!   when present, an `Origin` of this server (cross-site requests); otherwise 403.
//! - Request bodies are bounded ([`Limits::body_bytes`], 413), specs too ([`Limits::spec_bytes`]).
//! - The solve queue holds at most one entry per session and job (the static solves, each
//!   analysis on request) and sessions are bounded
//!   ([`Limits::sessions`], the least recently used is closed); [`Config::workers`] solves run at
//!   once, at most one per core.
//! - No request names a file: the server reads only the spec and the store given on its command
//!   line, and writes nothing (downloads are responses the browser saves).
//!
//! # Measured (release binary, thesis brake, 2 shared cores)
//! The server answers 4–29 ms after start and the page is ready 0.35 s after the browser opens it;
//! edit → cross-section 2 ms (in the edit's response); edit → coarse torque 0.58 s, → default
//! torque 2.17 s (medians of 6 edits); peak RSS after 6 solved and 100 quick edits 81 MB.
//!
//! # Why `tiny_http` (build time, issue 34)
//! Cold release builds of a hello-world server on this 2-core machine (shared, so wall times
//! vary): axum 0.8 on tokio 1 (http1, json, query; rt-multi-thread, net, macros, sync, signal):
//! 56 crates, 95 s wall, 43 s CPU; `tiny_http` 0.12: 11 crates, 18 s wall, 10 s CPU. The studio's
//! work is CPU-bound solves on worker threads and a handful of local connections, which plain
//! threads serve well; the async stack would cost a third of the 5-minute cold-build budget.

mod assets;
mod downloads;
mod on_request;
mod security;
mod server;
mod session;
mod solve;
mod study;

use std::net::{IpAddr, Ipv4Addr, SocketAddr};
use std::path::PathBuf;

pub use security::TOKEN_HEADER;
pub use server::Studio;
pub use solve::{QueueStats, STAGES};

/// What a studio serves and how.
#[derive(Debug, Clone)]
pub struct Config {
    /// The address to bind; 127.0.0.1 unless the user asks otherwise.
    pub bind: IpAddr,
    /// The port; 0 picks a free one.
    pub port: u16,
    /// The spec file the user opened (read once at start), or the embedded thesis brake.
    pub spec: Option<PathBuf>,
    /// A results store to show (read once at start).
    pub store: Option<PathBuf>,
    /// Solve workers (solves running at once); at most the number of cores.
    pub workers: usize,
    /// Size limits.
    pub limits: Limits,
}

impl Default for Config {
    fn default() -> Self {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        Self {
            bind: IpAddr::V4(Ipv4Addr::LOCALHOST),
            port: 0,
            spec: None,
            store: None,
            workers: cores.min(8),
            limits: Limits::default(),
        }
    }
}

impl Config {
    /// The socket address to bind.
    pub fn address(&self) -> SocketAddr {
        SocketAddr::new(self.bind, self.port)
    }
}

/// Bounds on what clients can make the server hold.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limits {
    /// The largest request body (bytes).
    pub body_bytes: usize,
    /// The largest spec text (bytes).
    pub spec_bytes: usize,
    /// Sessions open at once (tabs); the least recently used is closed beyond it.
    pub sessions: usize,
    /// Undo steps kept per session.
    pub history: usize,
    /// Pinned designs per session.
    pub pins: usize,
    /// HTTP threads (long polls use at most all but two).
    pub http_threads: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            body_bytes: 256 * 1024,
            spec_bytes: 64 * 1024,
            sessions: 8,
            history: 50,
            pins: 8,
            http_threads: 8,
        }
    }
}

/// Why the studio could not start.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum StudioError {
    /// The address could not be bound (in use, not allowed), or no random source.
    #[error("cannot start the studio: {0}")]
    Start(String),
    /// The spec or store the user opened could not be read.
    #[error("{0}")]
    Open(String),
}

impl mrbrake_error::Kind for StudioError {
    fn kind(&self) -> mrbrake_error::ErrorKind {
        match self {
            Self::Start(_) => mrbrake_error::ErrorKind::Io,
            Self::Open(_) => mrbrake_error::ErrorKind::Input,
        }
    }
}
