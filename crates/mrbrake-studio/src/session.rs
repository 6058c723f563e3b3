//! One browser tab's design session: the spec text (the one truth the form and the TOML editor
//! both show), its undo and redo history, what an edit shows at once (field errors, the
//! cross-section, the parts, mass, inertia and coil), the coarse and default solves of the latest
//! edit, and the pinned designs. A long poll waits on [`Session::wait_newer`] for the next change.

use std::collections::VecDeque;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::Duration;

use mrbrake_design::DesignError;
use mrbrake_design::analysis::{Analysis, AnalysisOptions, FieldAtMaxCurrent, instant_figures};
use mrbrake_design::geometry::BrakeGeometry;
use mrbrake_design::spec::BrakeSpec;
use mrbrake_report::html::{Html, cross_section};
use serde_json::{Value, json};

use crate::Limits;
use crate::on_request::Kind;

/// What a client asks of the spec.
#[derive(Debug, Clone)]
pub enum Edit {
    /// The whole TOML text (the editor).
    Text(String),
    /// One key set to a value (the form): a JSON number or string, `null` to remove the key.
    Field {
        /// Dotted path, e.g. `drum.gap`.
        path: String,
        /// The new value.
        value: Value,
    },
    /// Back to the text before the last edit.
    Undo,
    /// Forward again.
    Redo,
}

/// A finished solve of the latest design with what the downloads need.
#[derive(Debug)]
pub struct Solved {
    /// The spec text solved.
    pub text: String,
    /// The spec.
    pub spec: BrakeSpec,
    /// Its geometry.
    pub geometry: BrakeGeometry,
    /// The settings.
    pub options: AnalysisOptions,
    /// The analysis (as `analyze --json` prints it).
    pub analysis: Analysis,
    /// The field at the maximum current.
    pub field: FieldAtMaxCurrent,
}

/// The progress of one solve stage (coarse or default) of the latest edit.
#[derive(Debug, Clone, Default)]
pub struct Stage {
    /// `idle`, `queued`, `running`, `done`, `failed`, `cancelled`.
    pub status: &'static str,
    /// Currents done and in all, while running.
    pub progress: (usize, usize),
    /// The result (analysis, figures, settings) once done, or the error.
    pub result: Value,
}

/// The mutable state of a session.
#[derive(Debug)]
pub struct State {
    /// Where the spec came from, as error messages name it (`spec.toml`, a file's name).
    pub origin: String,
    /// The spec text.
    pub text: String,
    undo: VecDeque<String>,
    redo: Vec<String>,
    /// Number of the latest edit.
    pub version: u64,
    /// Number of the latest change of anything (long polls wait for it to grow).
    pub revision: u64,
    /// What the latest edit showed at once.
    pub instant: Value,
    /// The latest edit's spec when it is valid (what the solves take).
    pub spec: Option<BrakeSpec>,
    /// The coarse and the default solve of the latest edit.
    pub stages: [Stage; 2],
    /// Pinned designs (name, settings, analysis), oldest first.
    pub pins: Vec<Value>,
    /// The latest default-mesh solve, for the downloads.
    pub solved: Option<Arc<Solved>>,
    /// The analyses run on request (response, thermal, haptic: [`Kind::ALL`]'s order); a result
    /// names the version of the spec it is of.
    pub requests: [Stage; 3],
    history_limit: usize,
}

/// A session: its state, a condition variable for long polls, and its solve generation (bumped
/// by every edit and cancel; a running solve of an older generation is obsolete).
#[derive(Debug)]
pub struct Session {
    /// Its id (random, in the page's requests).
    pub id: String,
    state: Mutex<State>,
    changed: Condvar,
    generation: AtomicU64,
    request_generation: AtomicU64,
}

impl Session {
    /// A session on `text` read from `origin`.
    pub fn new(id: String, origin: &str, text: String, limits: &Limits) -> Arc<Self> {
        let mut state = State {
            origin: origin.to_string(),
            text: String::new(),
            undo: VecDeque::new(),
            redo: Vec::new(),
            version: 0,
            revision: 0,
            instant: Value::Null,
            spec: None,
            stages: Default::default(),
            pins: Vec::new(),
            solved: None,
            requests: Kind::ALL.map(|_| Stage { status: "idle", ..Stage::default() }),
            history_limit: limits.history,
        };
        state.set_text_only(text);
        Arc::new(Self {
            id,
            state: Mutex::new(state),
            changed: Condvar::new(),
            generation: AtomicU64::new(1),
            request_generation: AtomicU64::new(1),
        })
    }

    /// The state, locked (a poisoned lock still holds a consistent state: every change is made
    /// under one lock and completes or panics before any field is half-written).
    pub fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// The solve generation: a solve started at another one is obsolete.
    pub fn generation(&self) -> u64 {
        self.generation.load(Ordering::SeqCst)
    }

    /// Cancels the running and waiting solves of the latest edit.
    pub fn cancel(&self) {
        let mut state = self.lock();
        self.generation.fetch_add(1, Ordering::SeqCst);
        for stage in &mut state.stages {
            if matches!(stage.status, "queued" | "running") {
                stage.status = "cancelled";
            }
        }
        self.notify(&mut state);
    }

    /// The generation of the analyses on request: one started at another is obsolete.
    pub fn request_generation(&self) -> u64 {
        self.request_generation.load(Ordering::SeqCst)
    }

    /// Queues the analysis `kind` of the latest edit; false when the spec has errors (nothing
    /// to analyse) or `kind` is already waiting or running.
    pub fn request(&self, kind: Kind) -> bool {
        let mut state = self.lock();
        let valid = state.spec.is_some();
        let request = &mut state.requests[kind as usize];
        if !valid || matches!(request.status, "queued" | "running") {
            return false;
        }
        *request = Stage { status: "queued", ..Stage::default() };
        self.notify(&mut state);
        true
    }

    /// Cancels the waiting and running analyses on request (their results are dropped).
    pub fn cancel_requests(&self) {
        let mut state = self.lock();
        self.drop_requests(&mut state);
        self.notify(&mut state);
    }

    fn drop_requests(&self, state: &mut State) {
        self.request_generation.fetch_add(1, Ordering::SeqCst);
        for request in &mut state.requests {
            if matches!(request.status, "queued" | "running") {
                request.status = "cancelled";
            }
        }
    }

    /// Asks for the solves of the latest edit again (after a cancel or a failure); true when the
    /// spec is valid and a solve should be queued.
    pub fn resolve(&self) -> bool {
        let mut state = self.lock();
        self.generation.fetch_add(1, Ordering::SeqCst);
        let valid = state.spec.is_some();
        if valid {
            for stage in &mut state.stages {
                *stage = Stage { status: "queued", ..Stage::default() };
            }
        }
        self.notify(&mut state);
        valid
    }

    /// Applies `edit`; returns the new version, or an error message for an edit that cannot be
    /// applied (a form edit while the TOML text does not parse, nothing to undo).
    pub fn edit(&self, edit: Edit) -> Result<u64, String> {
        let mut state = self.lock();
        let text = match edit {
            Edit::Text(text) => text,
            Edit::Field { path, value } => set_key(&state.text, &path, &value)?,
            Edit::Undo => {
                let previous = state.undo.pop_back().ok_or("nothing to undo")?;
                let current = std::mem::replace(&mut state.text, previous.clone());
                state.redo.push(current);
                state.set_text_only(previous);
                return Ok(self.changed_version(&mut state));
            }
            Edit::Redo => {
                let next = state.redo.pop().ok_or("nothing to redo")?;
                let current = std::mem::replace(&mut state.text, next.clone());
                state.push_undo(current);
                state.set_text_only(next);
                return Ok(self.changed_version(&mut state));
            }
        };
        if text == state.text {
            return Ok(state.version);
        }
        let current = std::mem::take(&mut state.text);
        state.push_undo(current);
        state.redo.clear();
        state.set_text_only(text);
        Ok(self.changed_version(&mut state))
    }

    fn changed_version(&self, state: &mut State) -> u64 {
        self.generation.fetch_add(1, Ordering::SeqCst);
        // The analyses on request describe the design they started on: an edit drops them.
        self.drop_requests(state);
        self.notify(state);
        state.version
    }

    /// Records a change (bumps the revision and wakes the long polls).
    pub fn notify(&self, state: &mut State) {
        state.revision += 1;
        self.changed.notify_all();
    }

    /// Waits up to `timeout` for a revision newer than `after`; returns the state then.
    pub fn wait_newer(&self, after: u64, timeout: Duration) -> MutexGuard<'_, State> {
        let state = self.lock();
        let (state, _) = self
            .changed
            .wait_timeout_while(state, timeout, |s| s.revision <= after)
            .unwrap_or_else(|p| p.into_inner());
        state
    }
}

impl State {
    /// Takes `text` as the spec: what it shows at once, its stages reset.
    fn set_text_only(&mut self, text: String) {
        self.version += 1;
        let (instant, spec) = instant(&text, &self.origin);
        self.instant = instant;
        let queued = if spec.is_some() { "queued" } else { "idle" };
        self.stages = [0, 1].map(|_| Stage { status: queued, ..Stage::default() });
        self.spec = spec;
        self.text = text;
    }

    fn push_undo(&mut self, text: String) {
        self.undo.push_back(text);
        while self.undo.len() > self.history_limit {
            self.undo.pop_front();
        }
    }

    /// Whether undo and redo have something to do.
    pub fn history(&self) -> (bool, bool) {
        (!self.undo.is_empty(), !self.redo.is_empty())
    }
}

/// `text` with the key `path` set to `value` (a number or string; `null` removes it), its
/// comments and layout kept.
pub fn set_key(text: &str, path: &str, value: &Value) -> Result<String, String> {
    let mut doc: toml_edit::DocumentMut =
        text.parse().map_err(|e| format!("the TOML text does not parse; fix it first: {e}"))?;
    let keys: Vec<&str> = path.split('.').collect();
    let (last, tables) = keys.split_last().ok_or("an empty key")?;
    let mut item = doc.as_item_mut();
    for key in tables {
        if item.get(key).is_none() {
            item.as_table_like_mut()
                .ok_or_else(|| format!("{path}: not inside a table"))?
                .insert(key, toml_edit::table());
        }
        item = item.get_mut(key).ok_or_else(|| format!("{path}: no table {key}"))?;
    }
    let table = item.as_table_like_mut().ok_or_else(|| format!("{path}: not inside a table"))?;
    let new = match value {
        Value::Null => {
            table.remove(last);
            return Ok(doc.to_string());
        }
        Value::String(s) => toml_edit::value(s.as_str()),
        Value::Bool(b) => toml_edit::value(*b),
        Value::Number(n) => match n.as_i64() {
            Some(i) => toml_edit::value(i),
            None => toml_edit::value(n.as_f64().unwrap_or(f64::NAN)),
        },
        _ => return Err(format!("{path}: a value must be a number or a string")),
    };
    match table.get_mut(last) {
        Some(existing) if existing.is_value() => {
            // Keep the key's comment (its decor) and replace only the value.
            let decor = existing.as_value().map(|v| v.decor().clone());
            *existing = new;
            if let (Some(decor), Some(v)) = (decor, existing.as_value_mut()) {
                *v.decor_mut() = decor;
            }
        }
        _ => {
            table.insert(last, new);
        }
    }
    Ok(doc.to_string())
}

/// What an edit shows at once: the field errors in the CLI's words (or the cross-section, the
/// parts, the mechanics and the coil of a valid spec), the form's values; and the spec if valid.
pub fn instant(text: &str, origin: &str) -> (Value, Option<BrakeSpec>) {
    let values = form_values(text);
    let spec = match BrakeSpec::from_toml_str(text, origin) {
        Ok(spec) => spec,
        Err(e) => {
            return (json!({ "valid": false, "errors": errors(&e, text), "values": values }), None);
        }
    };
    let validated = match spec.validate() {
        Ok(v) => v,
        Err(e) => {
            return (json!({ "valid": false, "errors": errors(&e, text), "values": values }), None);
        }
    };
    let geometry = validated.geometry;
    let figures = instant_figures(&spec, &geometry, AnalysisOptions::default().temperature_c);
    let (mechanics, coil) = match figures {
        Ok(f) => f,
        Err(e) => {
            return (json!({ "valid": false, "errors": errors(&e, text), "values": values }), None);
        }
    };
    let mut parts = Html::new();
    parts.table(&cross_section::legend(&geometry));
    let warnings: Vec<Value> = validated
        .warnings
        .iter()
        .map(|w| json!({ "field": w.field, "message": w.message, "text": w.to_string() }))
        .collect();
    let shown = json!({
        "valid": true,
        "errors": [],
        "warnings": warnings,
        "values": values,
        "name": spec.name,
        "configuration": spec.configuration.name(),
        "cross_section": cross_section::svg(&geometry, "xs", &format!("{}: cross-section", spec.name)),
        "parts": parts.finish(),
        "mechanics": mechanics,
        "coil": coil,
    });
    (shown, Some(spec))
}

/// Every invalid field of `e` as `{field, line, message, text}`: the CLI's words (`text` is the
/// line `mrbrake analyze` prints).
fn errors(e: &DesignError, text: &str) -> Vec<Value> {
    match e {
        DesignError::Spec { errors, .. } => errors
            .errors()
            .iter()
            .map(|f| json!({ "field": f.field, "line": f.line, "message": f.message, "text": f.to_string() }))
            .collect(),
        DesignError::Parse { origin, error } => {
            let line = error.span().map(|s| text[..s.start.min(text.len())].matches('\n').count() + 1);
            let message = error.message().trim().to_string();
            let field = parse_error_field(&message);
            let shown = match line {
                Some(l) => format!("{origin}:{l}: {message}"),
                None => format!("{origin}: {message}"),
            };
            vec![json!({ "field": field, "line": line, "message": message, "text": shown })]
        }
        other => vec![json!({ "field": "", "line": null, "message": chain(other), "text": chain(other) })],
    }
}

/// The field a TOML parse error names (`unknown field `x``), when it says; else empty.
fn parse_error_field(message: &str) -> String {
    message
        .split('`')
        .nth(1)
        .filter(|_| message.starts_with("unknown field") || message.starts_with("missing field"))
        .unwrap_or("")
        .to_string()
}

/// An error with its causes, as the CLI prints them (`a: b: c`).
pub fn chain(e: &dyn std::error::Error) -> String {
    let mut text = e.to_string();
    let mut source = e.source();
    while let Some(s) = source {
        text.push_str(": ");
        text.push_str(&s.to_string());
        source = s.source();
    }
    text
}

/// The spec's keys as the form shows them: dotted path → value as written (strings with their
/// units, numbers as numbers). Empty for text that is not TOML.
pub fn form_values(text: &str) -> Value {
    let mut out = serde_json::Map::new();
    if let Ok(table) = toml::from_str::<toml::Table>(text) {
        flatten(&table, "", &mut out);
    }
    Value::Object(out)
}

fn flatten(table: &toml::Table, prefix: &str, out: &mut serde_json::Map<String, Value>) {
    for (key, value) in table {
        let path = if prefix.is_empty() { key.clone() } else { format!("{prefix}.{key}") };
        match value {
            toml::Value::Table(inner) => flatten(inner, &path, out),
            toml::Value::String(s) => {
                out.insert(path, json!(s));
            }
            toml::Value::Integer(i) => {
                out.insert(path, json!(i));
            }
            toml::Value::Float(f) => {
                out.insert(path, json!(f));
            }
            toml::Value::Boolean(b) => {
                out.insert(path, json!(b));
            }
            other => {
                out.insert(path, json!(other.to_string()));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrbrake_design::spec::DEFAULT_SPEC_TOML;

    fn limits() -> Limits {
        Limits::default()
    }

    #[test]
    fn a_form_edit_changes_one_value_and_keeps_the_comments() {
        let text = set_key(DEFAULT_SPEC_TOML, "drum.gap", &json!("0.6mm")).unwrap();
        assert!(text.contains("gap = \"0.6mm\"                   # 4.4.2"), "the comment stays");
        assert_eq!(text.lines().count(), DEFAULT_SPEC_TOML.lines().count());
        let removed = set_key(&text, "coil.turns", &Value::Null).unwrap();
        assert!(!removed.contains("turns = 450"));
        let added = set_key(&removed, "coil.turns", &json!(300)).unwrap();
        assert!(added.contains("turns = 300"));
        assert!(set_key("x = [", "a", &json!(1)).unwrap_err().contains("does not parse"));
    }

    #[test]
    fn an_edit_shows_errors_in_the_cli_words_or_the_drawing() {
        let (shown, spec) = instant(DEFAULT_SPEC_TOML, "spec.toml");
        assert!(spec.is_some() && shown["valid"] == true);
        assert!(shown["cross_section"].as_str().unwrap().starts_with("<svg"));
        assert!(shown["mechanics"]["mass_kg"].as_f64().unwrap() > 0.1);
        assert!(shown["coil"]["resistance_20C_ohm"].as_f64().unwrap() > 1.0);
        let bad = DEFAULT_SPEC_TOML.replace("gap = \"0.5mm\"", "gap = \"-1mm\"");
        let (shown, spec) = instant(&bad, "spec.toml");
        assert!(spec.is_none());
        let error = &shown["errors"][0];
        assert_eq!(error["field"], "drum.gap");
        let cli = BrakeSpec::from_toml_str(&bad, "spec.toml").unwrap().validate().unwrap_err();
        assert!(cli.to_string().contains(error["text"].as_str().unwrap()), "{cli}");
        let (shown, _) = instant("name = \"x\"\nbogus = 1\n", "spec.toml");
        assert!(shown["errors"][0]["text"].as_str().unwrap().starts_with("spec.toml:"));
    }

    #[test]
    fn undo_and_redo_walk_the_history() {
        let s = Session::new("s".into(), "spec.toml", DEFAULT_SPEC_TOML.into(), &limits());
        let (v1, g1) = (s.lock().version, s.generation());
        let v2 = s.edit(Edit::Field { path: "drum.gap".into(), value: json!("0.6mm") }).unwrap();
        assert!(v2 > v1 && s.generation() > g1);
        assert!(s.lock().text.contains("0.6mm"));
        s.edit(Edit::Undo).unwrap();
        assert_eq!(s.lock().text, DEFAULT_SPEC_TOML);
        s.edit(Edit::Redo).unwrap();
        assert!(s.lock().text.contains("0.6mm"));
        assert!(s.edit(Edit::Redo).is_err());
        for k in 0..(limits().history + 10) {
            s.edit(Edit::Text(format!("name = \"{k}\""))).unwrap();
        }
        assert_eq!(s.lock().undo.len(), limits().history, "the history is bounded");
    }
}
