//! The HTTP side: `tiny_http` on a few threads, every request checked (`security`), bodies
//! bounded, then routed to the page, the JSON API or a download.

use std::io::Read;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use serde_json::{Value, json};

use crate::on_request::Kind;
use crate::security::{Guard, TOKEN_HEADER, Token, query_value};
use crate::session::{Edit, Session};
use crate::solve::{Job, Queue, QueueStats, STAGES};
use crate::study::Study;
use crate::{Config, Limits, StudioError, assets, downloads};

/// How long a long poll waits for a change.
const POLL: Duration = Duration::from_secs(20);

/// A running studio.
pub struct Studio {
    app: Arc<App>,
    server: Arc<tiny_http::Server>,
    threads: Vec<JoinHandle<()>>,
}

impl std::fmt::Debug for Studio {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Studio").field("url", &self.url()).finish()
    }
}

/// What the request handlers share.
pub(crate) struct App {
    pub guard: Guard,
    pub url: String,
    pub limits: Limits,
    pub origin: String,
    pub spec_text: String,
    pub sessions: Mutex<Vec<(Arc<Session>, Instant)>>,
    pub queue: Arc<Queue>,
    pub study: Option<Study>,
    polls: AtomicUsize,
    next_session: AtomicUsize,
}

/// A response.
pub(crate) struct Reply {
    pub status: u16,
    pub content_type: &'static str,
    pub body: Vec<u8>,
    /// A download's file name.
    pub file_name: Option<String>,
}

impl Reply {
    pub fn json(value: &Value) -> Self {
        Self::with(200, "application/json", serde_json::to_vec(value).unwrap_or_default())
    }

    pub fn error(status: u16, message: &str) -> Self {
        let body = serde_json::to_vec(&json!({ "error": message })).unwrap_or_default();
        Self::with(status, "application/json", body)
    }

    pub fn with(status: u16, content_type: &'static str, body: Vec<u8>) -> Self {
        Self { status, content_type, body, file_name: None }
    }
}

impl Studio {
    /// Binds the server, reads what the user opened, starts the workers; returns at once.
    pub fn start(config: Config) -> Result<Studio, StudioError> {
        let (origin, spec_text) = opened_spec(&config)?;
        let study = config.store.as_deref().map(Study::open).transpose()?;
        let server = tiny_http::Server::http(config.address())
            .map_err(|e| StudioError::Start(format!("{}: {e}", config.address())))?;
        let address = server
            .server_addr()
            .to_ip()
            .ok_or_else(|| StudioError::Start("not an IP socket".into()))?;
        let token = Token::random()?;
        let host = if address.ip().is_loopback() {
            address.to_string()
        } else {
            format!("127.0.0.1:{}", address.port())
        };
        let url = format!("http://{host}/?token={}", token.as_str());
        let app = Arc::new(App {
            guard: Guard::new(token, address),
            url,
            limits: config.limits,
            origin,
            spec_text,
            sessions: Mutex::new(Vec::new()),
            queue: Arc::new(Queue::default()),
            study,
            polls: AtomicUsize::new(0),
            next_session: AtomicUsize::new(1),
        });
        let server = Arc::new(server);
        let mut threads = Vec::new();
        for _ in 0..config.workers.max(1) {
            let queue = Arc::clone(&app.queue);
            threads.push(std::thread::spawn(move || queue.work()));
        }
        for _ in 0..config.limits.http_threads.max(3) {
            let (app, server) = (Arc::clone(&app), Arc::clone(&server));
            threads.push(std::thread::spawn(move || {
                while let Ok(request) = server.recv() {
                    handle(&app, request);
                }
            }));
        }
        Ok(Studio { app, server, threads })
    }

    /// The page's address with its token.
    pub fn url(&self) -> &str {
        &self.app.url
    }

    /// The solve queue's counters.
    pub fn queue_stats(&self) -> QueueStats {
        self.app.queue.stats()
    }

    /// Serves until the process ends.
    pub fn wait(self) {
        for thread in self.threads {
            let _ = thread.join();
        }
    }

    /// Stops serving and solving (the running solves stop at their next cancellation point).
    pub fn shut_down(self) {
        self.app.queue.shut_down();
        for (session, _) in self.app.sessions.lock().unwrap_or_else(|p| p.into_inner()).iter() {
            session.cancel();
        }
        for _ in 0..self.threads.len() {
            self.server.unblock();
        }
        for thread in self.threads {
            let _ = thread.join();
        }
    }
}

/// The spec text the sessions start from and its name in messages.
fn opened_spec(config: &Config) -> Result<(String, String), StudioError> {
    match &config.spec {
        None => Ok(("spec.toml".into(), mrbrake_design::spec::DEFAULT_SPEC_TOML.to_string())),
        Some(path) => {
            let text = mrbrake_error::read::text(path, mrbrake_error::read::SETTINGS)
                .map_err(|e| StudioError::Open(format!("{}: cannot read: {e}", path.display())))?;
            if text.len() > config.limits.spec_bytes {
                return Err(StudioError::Open(format!(
                    "{}: {} bytes; a spec may have at most {}",
                    path.display(),
                    text.len(),
                    config.limits.spec_bytes
                )));
            }
            let name =
                path.file_name().map_or("spec.toml".into(), |n| n.to_string_lossy().into_owned());
            Ok((name, text))
        }
    }
}

/// One request: checks, body, route, response.
fn handle(app: &App, mut request: tiny_http::Request) {
    let header = |name: &str| {
        let found =
            request.headers().iter().find(|h| h.field.as_str().as_str().eq_ignore_ascii_case(name));
        found.map(|h| h.value.as_str().to_string())
    };
    let (host, origin, token) = (header("Host"), header("Origin"), header(TOKEN_HEADER));
    let url = request.url().to_string();
    let reply = match app.guard.check(host.as_deref(), origin.as_deref(), token.as_deref(), &url) {
        Err(refusal) => Reply::error(403, &refusal.to_string()),
        Ok(()) => match read_body(&mut request, app.limits.body_bytes) {
            Err(reply) => reply,
            Ok(body) => route(app, request.method().as_str(), &url, &body),
        },
    };
    respond(request, reply);
}

/// The body, at most `limit` bytes (413 beyond).
fn read_body(request: &mut tiny_http::Request, limit: usize) -> Result<Vec<u8>, Reply> {
    let too_large = || Reply::error(413, &format!("a request body may have at most {limit} bytes"));
    if request.body_length().is_some_and(|n| n > limit) {
        return Err(too_large());
    }
    let mut body = Vec::new();
    request
        .as_reader()
        .take(limit as u64 + 1)
        .read_to_end(&mut body)
        .map_err(|e| Reply::error(400, &format!("cannot read the body: {e}")))?;
    if body.len() > limit { Err(too_large()) } else { Ok(body) }
}

fn respond(request: tiny_http::Request, reply: Reply) {
    let mut response = tiny_http::Response::from_data(reply.body).with_status_code(reply.status);
    let mut headers = vec![
        ("Content-Type", reply.content_type.to_string()),
        ("Cache-Control", "no-store".into()),
        ("X-Content-Type-Options", "nosniff".into()),
        ("Referrer-Policy", "no-referrer".into()),
        ("X-Frame-Options", "DENY".into()),
        ("Content-Security-Policy", assets::CSP.into()),
    ];
    if let Some(name) = reply.file_name {
        headers.push(("Content-Disposition", format!("attachment; filename=\"{name}\"")));
    }
    for (field, value) in headers {
        if let Ok(h) = tiny_http::Header::from_bytes(field.as_bytes(), value.as_bytes()) {
            response.add_header(h);
        }
    }
    let _ = request.respond(response);
}

/// The route of `method` `url`.
fn route(app: &App, method: &str, url: &str, body: &[u8]) -> Reply {
    let path = url.split('?').next().unwrap_or("");
    let parts: Vec<&str> = path.trim_start_matches('/').split('/').collect();
    match (method, parts.as_slice()) {
        ("GET", [""]) => Reply::with(
            200,
            "text/html; charset=utf-8",
            assets::page(app.guard.token().as_str()).into_bytes(),
        ),
        ("GET", ["studio.js"]) => {
            Reply::with(200, "text/javascript; charset=utf-8", assets::SCRIPT.as_bytes().to_vec())
        }
        ("GET", ["studio.css"]) => {
            Reply::with(200, "text/css; charset=utf-8", assets::STYLE.as_bytes().to_vec())
        }
        ("GET", ["api", "schema"]) => Reply::json(&mrbrake_design::spec::schema()),
        ("GET", ["api", "info"]) => Reply::json(&info(app)),
        ("GET", ["api", "study"]) => match &app.study {
            Some(study) => Reply::json(&study.json),
            None => Reply::error(
                404,
                "no results store was opened (mrbrake studio --store STUDY.sqlite)",
            ),
        },
        ("GET", ["api", "study", "spec"]) => study_spec(app, url),
        ("POST", ["api", "sessions"]) => new_session(app),
        (_, ["api", "sessions", id, rest @ ..]) => match find_session(app, id) {
            None => Reply::error(404, "no such session (it was closed; reload the page)"),
            Some(session) => session_route(app, &session, method, rest, url, body),
        },
        _ => Reply::error(404, "not found"),
    }
}

fn info(app: &App) -> Value {
    let stages: Vec<Value> = STAGES
        .iter()
        .map(|s| json!({ "name": s.name, "points": s.points, "cli": s.command() }))
        .collect();
    json!({
        "version": env!("CARGO_PKG_VERSION"),
        "stages": stages,
        "study": app.study.is_some(),
        "limits": { "spec_bytes": app.limits.spec_bytes, "pins": app.limits.pins },
    })
}

fn study_spec(app: &App, url: &str) -> Reply {
    let Some(study) = &app.study else { return Reply::error(404, "no results store was opened") };
    let index = query_value(url, "index").and_then(|i| i.parse::<usize>().ok());
    match index.and_then(|i| study.spec_of(i)) {
        Some(text) => Reply::json(&json!({ "text": text })),
        None => Reply::error(404, "no such record"),
    }
}

/// A new session on the opened spec; beyond the limit the least recently used one is closed.
fn new_session(app: &App) -> Reply {
    let n = app.next_session.fetch_add(1, Ordering::SeqCst);
    let mut suffix = [0u8; 8];
    let _ = getrandom::fill(&mut suffix);
    let id = format!("s{n}-{}", suffix.iter().map(|b| format!("{b:02x}")).collect::<String>());
    let session = Session::new(id, &app.origin, app.spec_text.clone(), &app.limits);
    {
        let mut sessions = app.sessions.lock().unwrap_or_else(|p| p.into_inner());
        while sessions.len() >= app.limits.sessions {
            let oldest = sessions.iter().enumerate().min_by_key(|(_, (_, t))| *t).map(|(k, _)| k);
            let Some(k) = oldest else { break };
            let (closed, _) = sessions.remove(k);
            closed.cancel();
            app.queue.remove(&closed.id);
        }
        sessions.push((Arc::clone(&session), Instant::now()));
    }
    app.queue.submit(&session);
    Reply::json(&state_json(app, &session))
}

fn find_session(app: &App, id: &str) -> Option<Arc<Session>> {
    let mut sessions = app.sessions.lock().unwrap_or_else(|p| p.into_inner());
    let entry = sessions.iter_mut().find(|(s, _)| s.id == id)?;
    entry.1 = Instant::now();
    Some(Arc::clone(&entry.0))
}

fn session_route(
    app: &App,
    session: &Arc<Session>,
    method: &str,
    rest: &[&str],
    url: &str,
    body: &[u8],
) -> Reply {
    match (method, rest) {
        ("GET", []) => {
            let after = query_value(url, "after").and_then(|a| a.parse::<u64>().ok());
            match after {
                Some(after) => long_poll(app, session, after),
                None => Reply::json(&state_json(app, session)),
            }
        }
        ("POST", ["edit"]) => edit(app, session, body),
        ("POST", ["cancel"]) => {
            session.cancel();
            Reply::json(&state_json(app, session))
        }
        ("POST", ["solve"]) => {
            if session.resolve() {
                app.queue.submit(session);
            }
            Reply::json(&state_json(app, session))
        }
        ("POST", ["analyses", "cancel"]) => {
            session.cancel_requests();
            Reply::json(&state_json(app, session))
        }
        ("POST", ["analyses", name]) => request(app, session, name),
        ("POST", ["pin"]) => pin(app, session, body),
        ("GET", ["download", name]) => downloads::download(session, name),
        ("DELETE", []) => {
            session.cancel();
            app.queue.remove(&session.id);
            app.sessions
                .lock()
                .unwrap_or_else(|p| p.into_inner())
                .retain(|(s, _)| s.id != session.id);
            Reply::json(&json!({ "closed": session.id }))
        }
        _ => Reply::error(404, "not found"),
    }
}

/// Waits for a change after revision `after` (bounded: beyond the poll threads it answers now).
fn long_poll(app: &App, session: &Session, after: u64) -> Reply {
    let allowed = app.limits.http_threads.max(3) - 2;
    if app.polls.fetch_add(1, Ordering::SeqCst) >= allowed {
        app.polls.fetch_sub(1, Ordering::SeqCst);
        return Reply::json(&state_json(app, session));
    }
    drop(session.wait_newer(after, POLL));
    app.polls.fetch_sub(1, Ordering::SeqCst);
    Reply::json(&state_json(app, session))
}

/// An edit: `{"text": …}`, `{"path": …, "value": …}` or `{"action": "undo" | "redo"}`.
fn edit(app: &App, session: &Arc<Session>, body: &[u8]) -> Reply {
    let Ok(request) = serde_json::from_slice::<Value>(body) else {
        return Reply::error(400, "the body must be a JSON object");
    };
    let edit = if let Some(text) = request["text"].as_str() {
        if text.len() > app.limits.spec_bytes {
            return Reply::error(
                413,
                &format!("a spec may have at most {} bytes", app.limits.spec_bytes),
            );
        }
        Edit::Text(text.to_string())
    } else if let Some(path) = request["path"].as_str() {
        Edit::Field { path: path.to_string(), value: request["value"].clone() }
    } else {
        match request["action"].as_str() {
            Some("undo") => Edit::Undo,
            Some("redo") => Edit::Redo,
            _ => return Reply::error(400, "give text, path and value, or action"),
        }
    };
    if let Err(message) = session.edit(edit) {
        return Reply::error(409, &message);
    }
    if session.lock().text.len() > app.limits.spec_bytes {
        let _ = session.edit(Edit::Undo);
        return Reply::error(
            413,
            &format!("a spec may have at most {} bytes", app.limits.spec_bytes),
        );
    }
    if session.lock().spec.is_some() {
        app.queue.submit(session);
    }
    Reply::json(&state_json(app, session))
}

/// Asks for the analysis `name` (`response`, `thermal`, `haptic`) of the latest edit.
fn request(app: &App, session: &Arc<Session>, name: &str) -> Reply {
    let Some(kind) = Kind::from_name(name) else {
        return Reply::error(404, "no such analysis: response, thermal or haptic");
    };
    if session.lock().spec.is_none() {
        return Reply::error(409, "the spec has errors: fix them to analyse the design");
    }
    if session.request(kind) {
        app.queue.submit_job(session, Job::Request(kind));
    }
    Reply::json(&state_json(app, session))
}

/// Pins the latest finished solve (`{"stage": "default"}`), or removes pin `{"remove": k}`.
fn pin(app: &App, session: &Session, body: &[u8]) -> Reply {
    let request: Value = serde_json::from_slice(body).unwrap_or(Value::Null);
    let mut state = session.lock();
    if let Some(k) = request["remove"].as_u64() {
        if (k as usize) < state.pins.len() {
            state.pins.remove(k as usize);
        }
    } else {
        let done = state.stages.iter().rev().find(|s| s.status == "done").map(|s| s.result.clone());
        let Some(result) = done else { return Reply::error(409, "nothing solved to pin yet") };
        if state.pins.len() >= app.limits.pins {
            state.pins.remove(0);
        }
        let pinned = json!({
            "version": state.version,
            "stage": result["stage"],
            "cli": result["cli"],
            "analysis": result["analysis"],
            "text": state.text,
        });
        state.pins.push(pinned);
    }
    session.notify(&mut state);
    drop(state);
    Reply::json(&state_json(app, session))
}

/// The session as the page sees it.
pub(crate) fn state_json(app: &App, session: &Session) -> Value {
    let state = session.lock();
    let (undo, redo) = state.history();
    let stages: Vec<Value> = STAGES
        .iter()
        .zip(&state.stages)
        .map(|(settings, stage)| {
            json!({
                "name": settings.name,
                "status": stage.status,
                "progress": [stage.progress.0, stage.progress.1],
                "result": stage.result,
            })
        })
        .collect();
    let requests: Vec<Value> = Kind::ALL
        .iter()
        .zip(&state.requests)
        .map(|(kind, r)| json!({ "name": kind.name(), "status": r.status, "result": r.result }))
        .collect();
    let stats = app.queue.stats();
    json!({
        "id": session.id,
        "revision": state.revision,
        "version": state.version,
        "origin": state.origin,
        "text": state.text,
        "instant": state.instant,
        "stages": stages,
        "pins": state.pins,
        "requests": requests,
        "undo": undo,
        "redo": redo,
        "queue": { "waiting": stats.waiting, "running": stats.running },
    })
}
