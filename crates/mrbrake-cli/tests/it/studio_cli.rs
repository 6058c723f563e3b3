//! `mrbrake studio` in a real browser (Debian's Chromium, headless, over the DevTools pipe of
//! `browser/mod.rs`): the page loads, a change of the gap shows the cross-section at once and
//! then the default-mesh torque, which equals `analyze --json` of the same edited spec; an invalid
//! value shows the field's error and starts no solve; pin and compare; two tabs at once; a study
//! store's front point loads into the editor; keyboard navigation and labelled controls; no
//! console error, no request leaving the server, screenshots not blank. Skipped with a note
//! without Chromium, unless `MRBRAKE_REQUIRE_BROWSER=1` (CI).
//!
//! `MRBRAKE_STUDIO_SCREENSHOT=docs/img/studio.png` also writes the README's screenshot.

#[allow(dead_code)]
use crate::browser;
use crate::common;

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};

use browser::{Browser, Tab};
use common::{json, mrbrake, path_str};

/// A running `mrbrake studio` child and its printed address.
struct Server {
    child: Child,
    url: String,
}

impl Server {
    fn start(args: &[&str]) -> Server {
        let mut child = Command::new(env!("CARGO_BIN_EXE_mrbrake"))
            .arg("studio")
            .args(["--port", "0"])
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("mrbrake studio starts");
        let mut line = String::new();
        BufReader::new(child.stdout.take().unwrap()).read_line(&mut line).unwrap();
        let url = line.trim().to_string();
        assert!(url.starts_with("http://127.0.0.1:") && url.contains("/?token="), "{url}");
        Server { child, url }
    }

    /// `http://127.0.0.1:PORT/`: every request of the page must start with it.
    fn origin(&self) -> String {
        let end = self.url.find("/?").unwrap();
        format!("{}/", &self.url[..end])
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Waits until the page's stage `name` is done for the latest edit and returns its torque at
/// the maximum current as shown (`data-value`, the exact JSON number).
fn solved_torque(b: &mut Browser, tab: &Tab, name: &str) -> f64 {
    let done = format!(
        "(() => {{ const c = document.querySelector('[data-stage={name}]'); \
         return c && c.dataset.status === 'done'; }})()"
    );
    b.wait_until(tab, &done, 600, &format!("the {name}-mesh solve"));
    let cell = "document.querySelector('#figures td[data-pointer=\"/torque/at_max_current_Nm\"]').dataset.value";
    let text = b.eval(tab, cell);
    text.as_str().and_then(|t| t.parse().ok()).expect("a torque on the page")
}

/// Sets the form field `path` to `value` as a user would (typing, then leaving the field).
fn set_field(b: &mut Browser, tab: &Tab, path: &str, value: &str) {
    let id = format!("f-{}", path.replace('.', "-"));
    b.eval(
        tab,
        &format!(
            "(() => {{ const i = document.getElementById('{id}'); i.focus(); i.value = '{value}'; \
             i.dispatchEvent(new Event('change')); i.blur(); return true; }})()"
        ),
    );
}

/// `analyze --json` of the spec text the tab shows.
fn analyze_shown_spec(b: &mut Browser, tab: &Tab, dir: &std::path::Path) -> serde_json::Value {
    let text = b.eval(tab, "document.getElementById('toml').value");
    let path = dir.join("edited.toml");
    std::fs::write(&path, text.as_str().unwrap()).unwrap();
    json(&["analyze", path_str(&path), "--json"])
}

#[test]
fn the_studio_edits_solves_and_matches_the_cli() {
    let Some(chromium) = browser::find() else { return };
    let dir = tempfile::tempdir().unwrap();
    let server = Server::start(&[]);
    let mut b = Browser::start(&chromium);
    let tab = b.open(&server.url, 1500, 1000);
    b.wait_until(&tab, "document.body.dataset.ready === '1'", 60, "the page to be ready");
    let first = solved_torque(&mut b, &tab, "default");
    let cli = json(&["analyze", "--json"]);
    let cli_torque = cli["torque"]["at_max_current_Nm"].as_f64().unwrap();
    assert_eq!(first.to_bits(), cli_torque.to_bits(), "the thesis brake: {first} vs {cli_torque}");
    if let Ok(path) = std::env::var("MRBRAKE_STUDIO_SCREENSHOT") {
        std::fs::write(path, b.screenshot(&tab)).unwrap();
    }

    // An edit: the cross-section changes at once, then the default-mesh torque equals the CLI's.
    let section = "document.querySelector('#cross-section .svg').innerHTML";
    let before = b.eval(&tab, section);
    set_field(&mut b, &tab, "drum.gap", "0.6mm");
    b.wait_until(&tab, &format!("{section} !== {before}"), 30, "the new cross-section");
    let torque = solved_torque(&mut b, &tab, "default");
    let expected = analyze_shown_spec(&mut b, &tab, dir.path());
    let expected = expected["torque"]["at_max_current_Nm"].as_f64().unwrap();
    assert_eq!(torque.to_bits(), expected.to_bits(), "the edited spec: {torque} vs {expected}");
    assert!(torque < first, "a wider gap brakes less: {torque} vs {first}");

    // Pin, then compare with a second design.
    b.eval(&tab, "document.getElementById('pin').click(), true");
    b.wait_until(&tab, "!document.getElementById('compare').hidden", 30, "the comparison");
    set_field(&mut b, &tab, "coil.max_current", "1.5A");
    // Right after the pin the table already holds the pinned design and the current one (the
    // same design, solved): wait until the page shows the edit (its TOML text, rendered in the
    // same call as the table), then for the table's row of the edited design on the default mesh.
    let rows = "document.querySelectorAll('#compare-table tbody tr')";
    let current_default = format!(
        "(() => {{ const r = {rows}; \
         return document.getElementById('toml').value.includes('\"1.5A\"') && r.length === 2 && \
         r[1].querySelector('th').textContent === 'current (default)'; }})()"
    );
    b.wait_until(&tab, &current_default, 600, "the pinned design and the current one");
    let torque_cells =
        format!("[...{rows}].map(r => Number(JSON.parse(r.querySelector('td').dataset.value)))");
    let torques = b.eval(&tab, &torque_cells);
    let torques: Vec<f64> = torques.as_array().unwrap().iter().filter_map(|t| t.as_f64()).collect();
    assert_eq!(torques.len(), 2, "the pinned design and the current one: {torques:?}");
    assert!(torques[1] < torques[0], "less current brakes less: {torques:?}");

    // An invalid value: the field's error in the CLI's words, no solve.
    set_field(&mut b, &tab, "drum.gap", "-1mm");
    let error = b.wait_until(
        &tab,
        "document.getElementById('f-drum-gap-error').textContent",
        30,
        "the field error",
    );
    assert!(error.as_str().unwrap().contains("must be a fluid gap in (0, 10 mm]"), "{error}");
    let invalid =
        b.eval(&tab, "document.getElementById('f-drum-gap').getAttribute('aria-invalid')");
    assert_eq!(invalid, "true");
    let stages = b.eval(
        &tab,
        "[...document.querySelectorAll('[data-stage]')].map(c => c.dataset.status).join()",
    );
    assert_eq!(stages, "idle,idle", "no solve of an invalid spec");
    b.eval(&tab, "document.getElementById('undo').click(), true");
    b.wait_until(&tab, "document.getElementById('f-drum-gap').value === '0.6mm'", 30, "undo");

    // Two tabs at once: an edit in the second leaves the first alone.
    let second = b.open(&server.url, 1200, 900);
    b.wait_until(&second, "document.body.dataset.ready === '1'", 60, "the second tab");
    set_field(&mut b, &second, "drum.height", "10mm");
    solved_torque(&mut b, &second, "default");
    let first_height = b.eval(&tab, "document.getElementById('f-drum-height').value");
    assert_eq!(first_height, "9mm", "sessions are separate");

    check_accessibility(&mut b, &tab);
    let shot = b.screenshot(&tab);
    let (share, colours) = browser::ink(&shot);
    assert!(share > 0.05 && colours > 50, "blank screenshot ({share}, {colours} colours)");
    for t in [&tab, &second] {
        let (errors, requests) = b.tab_problems(t, &server.origin());
        assert!(errors.is_empty(), "console errors: {errors:?}");
        assert!(requests.is_empty(), "requests leaving the server: {requests:?}");
    }
}

/// Waits until the page's analysis on request `name` is done and returns the exact value of its
/// key figure at `pointer` (`data-value`).
fn requested_value(b: &mut Browser, tab: &Tab, name: &str, pointer: &str) -> serde_json::Value {
    let done = format!(
        "(() => {{ const c = document.querySelector('.chip[data-request={name}]'); \
         if (c && c.dataset.status === 'failed') throw new Error(c.textContent); \
         return c && c.dataset.status === 'done'; }})()"
    );
    b.wait_until(tab, &done, 900, &format!("the {name} analysis"));
    let cell = format!(
        "document.querySelector('section.request[data-request={name}] td[data-pointer=\"{pointer}\"]').dataset.value"
    );
    let text = b.eval(tab, &cell);
    serde_json::from_str(text.as_str().expect("a value on the page")).unwrap()
}

/// The analyses on request (step/frequency response, haptic wall with the design's brake model)
/// show the numbers of the CLI commands they name, with their figures; an edit drops a running
/// one.
#[test]
fn the_studio_runs_response_and_haptic_wall_on_request_as_the_cli() {
    let Some(chromium) = browser::find() else { return };
    let dir = tempfile::tempdir().unwrap();
    let server = Server::start(&[]);
    let mut b = Browser::start(&chromium);
    let tab = b.open(&server.url, 1500, 1000);
    b.wait_until(&tab, "document.body.dataset.ready === '1'", 60, "the page to be ready");
    solved_torque(&mut b, &tab, "default");
    b.eval(&tab, "document.querySelector('[data-analysis=haptic]').click(), true");
    b.eval(&tab, "document.querySelector('[data-analysis=response]').click(), true");
    let stiffness = requested_value(&mut b, &tab, "haptic", "/displayed_stiffness_Nm_per_rad");
    let free = requested_value(&mut b, &tab, "haptic", "/free_motion_torque_Nm");
    let model = dir.path().join("model.json");
    json(&["analyze", "--save-model", path_str(&model), "--json"]);
    let wall = json(&[
        "haptic",
        "wall",
        "--device",
        "bidirectional",
        "--brake-model",
        path_str(&model),
        "--json",
    ]);
    // Equal to round-off (a parallel sum's order may differ between two processes).
    let same = |shown: &serde_json::Value, cli: &serde_json::Value, what: &str| {
        let (a, b) = (shown.as_f64().unwrap(), cli.as_f64().unwrap());
        assert!((a - b).abs() <= 1e-9 * b.abs(), "{what}: {a} on the page, {b} from the CLI");
    };
    same(&stiffness, &wall["displayed_stiffness_Nm_per_rad"], "displayed stiffness");
    same(&free, &wall["free_motion_torque_Nm"], "free-motion torque");
    let bandwidth = requested_value(&mut b, &tab, "response", "/bandwidth_rad_s");
    same(&bandwidth, &json(&["response", "--json"])["bandwidth_rad_s"], "bandwidth");
    let figures =
        b.eval(&tab, "[...document.querySelectorAll('section.request figure .svg svg')].length");
    assert_eq!(figures, 3, "step, Bode and wall figures");

    // An edit drops the analysis that is running and marks the shown ones as of an earlier edit.
    b.eval(&tab, "document.querySelector('[data-analysis=response]').click(), true");
    set_field(&mut b, &tab, "drum.gap", "0.6mm");
    let chip = "document.querySelector('.chip[data-request=response]')";
    b.wait_until(
        &tab,
        &format!("{chip}.dataset.status === 'cancelled'"),
        60,
        "the dropped analysis",
    );
    let haptic = b.eval(&tab, "document.querySelector('.chip[data-request=haptic]').textContent");
    assert!(haptic.as_str().unwrap().contains("of an earlier edit"), "{haptic}");
    let (errors, requests) = b.tab_problems(&tab, &server.origin());
    assert!(errors.is_empty(), "console errors: {errors:?}");
    assert!(requests.is_empty(), "requests leaving the server: {requests:?}");
}

/// Every control has an accessible name, figures are labelled, and Tab moves through the form.
fn check_accessibility(b: &mut Browser, tab: &Tab) {
    let unnamed = b.eval(
        tab,
        "[...document.querySelectorAll('input, select, textarea, button')].filter(e => { \
           if (e.closest('[hidden]')) return false; \
           const label = e.id && document.querySelector(`label[for=\"${e.id}\"]`); \
           return !(label && label.textContent.trim()) && !e.getAttribute('aria-label') \
             && !e.textContent.trim(); }).map(e => e.outerHTML.slice(0, 80))",
    );
    assert_eq!(unnamed, serde_json::json!([]), "controls without a name");
    let unlabelled = b.eval(
        tab,
        "[...document.querySelectorAll('svg[role=img]')].filter(s => !s.getAttribute('aria-label')).length",
    );
    assert_eq!(unlabelled, 0, "figures without a name");
    b.eval(tab, "document.getElementById('f-name').focus(), true");
    let mut visited = Vec::new();
    for _ in 0..3 {
        b.press(tab, "Tab", 9);
        visited.push(b.eval(tab, "document.activeElement.id"));
    }
    assert_eq!(visited, ["f-configuration", "f-materials-flux_path", "f-materials-non_magnetic"]);
}

/// A study store: the front is plotted, hovering names a design, a click loads it.
#[test]
fn a_study_front_point_loads_into_the_editor() {
    let Some(chromium) = browser::find() else { return };
    let dir = tempfile::tempdir().unwrap();
    let store = dir.path().join("study.sqlite");
    let out = mrbrake(&[
        "sweep",
        "--vary",
        "g=0.4mm,0.5mm,0.7mm",
        "--mesh",
        "coarse",
        "--store",
        path_str(&store),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let server = Server::start(&["--store", path_str(&store)]);
    let mut b = Browser::start(&chromium);
    let tab = b.open(&server.url, 1400, 1000);
    b.wait_until(&tab, "!document.getElementById('study').hidden", 60, "the study");
    let points = b.eval(&tab, "document.querySelectorAll('#study-plot circle').length");
    assert_eq!(points, 3);
    let front = "document.querySelector('#study-plot circle[data-front=\"1\"]')";
    b.eval(&tab, &format!("{front}.dispatchEvent(new Event('mouseenter')), true"));
    let hover = b.eval(&tab, "document.getElementById('study-hover').textContent");
    let index = b.eval(&tab, &format!("{front}.dataset.index"));
    let stored = mrbrake::store::Store::open_read_only(&store).unwrap().records().unwrap();
    let wanted = &stored[index.as_str().unwrap().parse::<usize>().unwrap()];
    let (variable, gap) = wanted.variables[0].clone();
    assert!(hover.as_str().unwrap().contains(&format!("{variable} = ")), "{hover}");
    b.eval(&tab, &format!("{front}.dispatchEvent(new Event('click')), true"));
    let shown = format!("document.getElementById('toml').value.includes('gap = {gap}')");
    b.wait_until(&tab, &shown, 30, "the front design in the editor");
    let (errors, requests) = b.tab_problems(&tab, &server.origin());
    assert!(errors.is_empty(), "console errors: {errors:?}");
    assert!(requests.is_empty(), "requests leaving the server: {requests:?}");
}
