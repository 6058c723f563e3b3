//! A headless Chromium driven over the DevTools protocol through a pipe
//! (`--remote-debugging-pipe`: commands on the browser's fd 3, answers on fd 4, NUL-terminated
//! JSON), so the tests need no websocket client and no browser-automation package: only
//! Debian's `chromium`. `sh` maps the child's stdin/stdout to fds 3/4, since the standard library
//! cannot hand a child extra descriptors without `unsafe`.
//!
//! [`Browser::find`] looks for `$MRBRAKE_CHROMIUM`, then `chromium`, `chromium-browser`,
//! `google-chrome` on the `PATH`. With `MRBRAKE_REQUIRE_BROWSER=1` (set by `.ci/run`) a missing
//! browser fails the test; otherwise the test prints a note and skips the browser checks.

use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc::{Receiver, RecvTimeoutError, channel};
use std::time::{Duration, Instant};

use serde_json::{Value, json};

/// How long one protocol answer or the page load may take.
const TIMEOUT: Duration = Duration::from_secs(90);

/// The Chromium executable, or `None` (after the note) when it is absent and not required.
pub fn find() -> Option<PathBuf> {
    let candidates = std::env::var_os("MRBRAKE_CHROMIUM").map(PathBuf::from).into_iter().chain(
        ["chromium", "chromium-browser", "google-chrome"].iter().filter_map(|name| {
            std::env::var_os("PATH").and_then(|paths| {
                std::env::split_paths(&paths).map(|d| d.join(name)).find(|p| p.is_file())
            })
        }),
    );
    let found = candidates.into_iter().find(|p| p.is_file());
    if found.is_none() {
        let required = std::env::var("MRBRAKE_REQUIRE_BROWSER").is_ok_and(|v| v == "1");
        assert!(
            !required,
            "MRBRAKE_REQUIRE_BROWSER=1 but no Chromium found (apt-get install chromium)"
        );
        eprintln!(
            "note: no Chromium found; the browser checks are skipped (apt-get install chromium)"
        );
    }
    found
}

/// What loading a page showed.
#[derive(Debug)]
pub struct PageVisit {
    /// Console errors, uncaught exceptions and browser log errors (e.g. a blocked resource).
    pub errors: Vec<String>,
    /// Every URL the page requested other than itself (`data:` URLs excluded).
    pub requests: Vec<String>,
    /// Every top-level `img` and `svg`: tag, rendered width and height (CSS px), loaded.
    pub figures: Vec<(String, f64, f64, bool)>,
    /// A PNG screenshot of the first 1200 × 900 px.
    pub screenshot_png: Vec<u8>,
    /// The page printed to A4 (PDF bytes).
    pub pdf: Vec<u8>,
}

/// A running browser and its protocol pipe.
pub struct Browser {
    child: Child,
    to_browser: ChildStdin,
    from_browser: Receiver<Value>,
    next_id: u64,
    events: Vec<Value>,
    _profile: tempfile::TempDir,
}

impl Browser {
    /// Starts `chromium` headless with a fresh profile and no background networking.
    pub fn start(chromium: &Path) -> Browser {
        let profile = tempfile::tempdir().expect("profile folder");
        let flags = [
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--disable-dev-shm-usage",
            "--hide-scrollbars",
            "--remote-debugging-pipe",
        ];
        let script = format!(
            "exec \"$0\" {} --user-data-dir=\"$1\" 3<&0 4>&1 0</dev/null 1>/dev/null",
            flags.join(" ")
        );
        let mut child = Command::new("sh")
            .args(["-c", &script])
            .arg(chromium)
            .arg(profile.path())
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("chromium starts");
        let to_browser = child.stdin.take().expect("pipe to the browser");
        let mut reader = BufReader::new(child.stdout.take().expect("pipe from the browser"));
        let (tx, rx) = channel();
        std::thread::spawn(move || {
            let mut message = Vec::new();
            while reader.read_until(0, &mut message).is_ok_and(|n| n > 0) {
                if message.last() == Some(&0) {
                    message.pop();
                }
                if let Ok(v) = serde_json::from_slice::<Value>(&message) {
                    if tx.send(v).is_err() {
                        break;
                    }
                }
                message.clear();
            }
        });
        Browser {
            child,
            to_browser,
            from_browser: rx,
            next_id: 0,
            events: Vec::new(),
            _profile: profile,
        }
    }

    /// Sends `method` (to the page `session`, or the browser) and returns its result; events that
    /// arrive meanwhile are kept.
    fn call(&mut self, session: Option<&str>, method: &str, params: Value) -> Value {
        self.next_id += 1;
        let id = self.next_id;
        let mut message = json!({ "id": id, "method": method, "params": params });
        if let Some(s) = session {
            message["sessionId"] = json!(s);
        }
        let mut bytes = serde_json::to_vec(&message).unwrap();
        bytes.push(0);
        self.to_browser.write_all(&bytes).expect("write to the browser");
        self.to_browser.flush().unwrap();
        let deadline = Instant::now() + TIMEOUT;
        loop {
            let v = self.receive(deadline, method);
            if v["id"].as_u64() == Some(id) {
                assert!(v.get("error").is_none(), "{method} failed: {}", v["error"]);
                return v["result"].clone();
            }
            self.events.push(v);
        }
    }

    fn receive(&mut self, deadline: Instant, waiting_for: &str) -> Value {
        let left = deadline.saturating_duration_since(Instant::now());
        match self.from_browser.recv_timeout(left) {
            Ok(v) => v,
            Err(RecvTimeoutError::Timeout) => panic!("no answer from the browser to {waiting_for}"),
            Err(RecvTimeoutError::Disconnected) => {
                panic!("the browser exited during {waiting_for}")
            }
        }
    }

    /// Waits until the event `method` of `session` has arrived (or had already).
    fn wait_for(&mut self, session: &str, method: &str) {
        let seen = |e: &Value| e["method"] == method && e["sessionId"] == session;
        let deadline = Instant::now() + TIMEOUT;
        while !self.events.iter().any(seen) {
            let v = self.receive(deadline, method);
            self.events.push(v);
        }
    }

    /// Opens `file` in a new tab, waits for its load event and collects what the page did.
    pub fn visit(&mut self, file: &Path) -> PageVisit {
        let url = format!("file://{}", file.canonicalize().expect("page exists").display());
        let session = self.new_tab(1200, 900);
        let s = Some(session.as_str());
        self.events.clear();
        self.call(s, "Page.navigate", json!({ "url": url }));
        self.wait_for(&session, "Page.loadEventFired");
        let figures = self.figures(&session);
        let shot = self.call(s, "Page.captureScreenshot", json!({ "format": "png" }));
        let pdf = self.call(
            s,
            "Page.printToPDF",
            json!({ "paperWidth": 8.27, "paperHeight": 11.69, "printBackground": true }),
        );
        let (errors, requests) = self.page_problems(&session, &url);
        PageVisit {
            errors,
            requests,
            figures,
            screenshot_png: base64_decode(shot["data"].as_str().expect("screenshot data")),
            pdf: base64_decode(pdf["data"].as_str().expect("PDF data")),
        }
    }

    /// The rendered size of every top-level image and SVG (not SVGs nested in an SVG).
    fn figures(&mut self, session: &str) -> Vec<(String, f64, f64, bool)> {
        let expression = "JSON.stringify(Array.from(document.querySelectorAll('img, svg'))\
            .filter(e => !(e.parentElement && e.parentElement.closest('svg')))\
            .map(e => { const r = e.getBoundingClientRect(); \
              return [e.tagName, r.width, r.height, e.tagName !== 'IMG' || (e.complete && e.naturalWidth > 0)]; }))";
        let v = self.call(
            Some(session),
            "Runtime.evaluate",
            json!({ "expression": expression, "returnByValue": true }),
        );
        let list: Vec<(String, f64, f64, bool)> =
            serde_json::from_str(v["result"]["value"].as_str().expect("figures as JSON")).unwrap();
        list
    }

    /// Console errors and requests other than the page itself, from the events of `session`.
    fn page_problems(&self, session: &str, url: &str) -> (Vec<String>, Vec<String>) {
        let mut errors = Vec::new();
        let mut requests = Vec::new();
        for e in self.events.iter().filter(|e| e["sessionId"] == session) {
            let p = &e["params"];
            match e["method"].as_str().unwrap_or("") {
                "Runtime.consoleAPICalled" if p["type"] == "error" || p["type"] == "warning" => {
                    errors.push(format!("console {}: {}", p["type"], p["args"]))
                }
                "Runtime.exceptionThrown" => {
                    errors.push(format!("exception: {}", p["exceptionDetails"]))
                }
                "Log.entryAdded"
                    if p["entry"]["level"] == "error" || p["entry"]["level"] == "warning" =>
                {
                    errors.push(format!("log: {}", p["entry"]["text"]))
                }
                "Network.requestWillBeSent" => {
                    let requested = p["request"]["url"].as_str().unwrap_or("").to_string();
                    if requested != url && !requested.starts_with("data:") {
                        requests.push(requested);
                    }
                }
                _ => {}
            }
        }
        (errors, requests)
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        let _ = self.call_quietly();
        let deadline = Instant::now() + Duration::from_secs(10);
        while Instant::now() < deadline {
            if let Ok(Some(_)) = self.child.try_wait() {
                return;
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Browser {
    /// Asks the browser to close, ignoring a browser that is already gone.
    fn call_quietly(&mut self) -> std::io::Result<()> {
        self.next_id += 1;
        let message = json!({ "id": self.next_id, "method": "Browser.close", "params": {} });
        let mut bytes = serde_json::to_vec(&message).unwrap();
        bytes.push(0);
        self.to_browser.write_all(&bytes)
    }
}

/// Standard base64 (RFC 4648) to bytes.
pub fn base64_decode(text: &str) -> Vec<u8> {
    let value = |c: u8| -> u32 {
        match c {
            b'A'..=b'Z' => u32::from(c - b'A'),
            b'a'..=b'z' => u32::from(c - b'a') + 26,
            b'0'..=b'9' => u32::from(c - b'0') + 52,
            b'+' => 62,
            b'/' => 63,
            _ => panic!("not base64: {c}"),
        }
    };
    let clean: Vec<u8> = text.bytes().filter(|c| !c.is_ascii_whitespace()).collect();
    let mut out = Vec::with_capacity(clean.len() / 4 * 3);
    for chunk in clean.chunks(4) {
        let digits: Vec<u8> = chunk.iter().copied().filter(|&c| c != b'=').collect();
        let n = digits.iter().enumerate().fold(0u32, |n, (k, &c)| n | (value(c) << (18 - 6 * k)));
        for k in 0..digits.len().saturating_sub(1) {
            out.push((n >> (16 - 8 * k)) as u8);
        }
    }
    out
}

/// The share of pixels that are not (near) white and the number of distinct colours of a PNG.
pub fn ink(png_bytes: &[u8]) -> (f64, usize) {
    let decoder = png::Decoder::new(std::io::Cursor::new(png_bytes));
    let mut reader = decoder.read_info().expect("a PNG");
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).expect("PNG pixels");
    let channels = info.color_type.samples();
    let pixels = &buf[..info.buffer_size()];
    let mut colours = std::collections::HashSet::new();
    let mut inked = 0usize;
    let count = pixels.len() / channels;
    for p in pixels.chunks(channels) {
        if p[..3].iter().any(|&c| c < 240) {
            inked += 1;
        }
        if colours.len() < 100_000 {
            colours.insert([p[0], p[1], p[2]]);
        }
    }
    (inked as f64 / count as f64, colours.len())
}

/// A tab open on a web application (`Browser::open`), driven by script evaluation and keys.
#[allow(dead_code)]
pub struct Tab {
    session: String,
}

#[allow(dead_code)]
impl Browser {
    /// A new blank `width` × `height` tab with its events on; its protocol session.
    fn new_tab(&mut self, width: u32, height: u32) -> String {
        let target = self.call(None, "Target.createTarget", json!({ "url": "about:blank" }));
        let attached = self.call(
            None,
            "Target.attachToTarget",
            json!({ "targetId": target["targetId"], "flatten": true }),
        );
        let session = attached["sessionId"].as_str().expect("session id").to_string();
        let s = Some(session.as_str());
        for domain in ["Page.enable", "Runtime.enable", "Log.enable", "Network.enable"] {
            self.call(s, domain, json!({}));
        }
        let metrics =
            json!({ "width": width, "height": height, "deviceScaleFactor": 1, "mobile": false });
        self.call(s, "Emulation.setDeviceMetricsOverride", metrics);
        session
    }

    /// Opens `url` in a new `width` × `height` tab and waits for its load event.
    pub fn open(&mut self, url: &str, width: u32, height: u32) -> Tab {
        let session = self.new_tab(width, height);
        self.call(Some(&session), "Page.navigate", json!({ "url": url }));
        self.wait_for(&session, "Page.loadEventFired");
        Tab { session }
    }

    /// The value of `expression` in `tab` (promises awaited; an exception fails the test).
    pub fn eval(&mut self, tab: &Tab, expression: &str) -> Value {
        let v = self.call(
            Some(&tab.session),
            "Runtime.evaluate",
            json!({ "expression": expression, "returnByValue": true, "awaitPromise": true }),
        );
        assert!(v.get("exceptionDetails").is_none(), "{expression}: {}", v["exceptionDetails"]);
        v["result"]["value"].clone()
    }

    /// Waits until `expression` is truthy in `tab` (polling), returns its value; fails after
    /// `seconds` with `what`.
    pub fn wait_until(&mut self, tab: &Tab, expression: &str, seconds: u64, what: &str) -> Value {
        let deadline = Instant::now() + Duration::from_secs(seconds);
        loop {
            let v = self.eval(tab, expression);
            if !(v.is_null() || v == json!(false) || v == json!(0) || v == json!("")) {
                return v;
            }
            assert!(Instant::now() < deadline, "timed out waiting for {what}");
            std::thread::sleep(Duration::from_millis(100));
        }
    }

    /// Presses `key` (e.g. `Tab`) in `tab`, as the keyboard would.
    pub fn press(&mut self, tab: &Tab, key: &str, code: u32) {
        for kind in ["rawKeyDown", "keyUp"] {
            self.call(
                Some(&tab.session),
                "Input.dispatchKeyEvent",
                json!({ "type": kind, "key": key, "code": key, "windowsVirtualKeyCode": code }),
            );
        }
    }

    /// A PNG screenshot of `tab`'s viewport.
    pub fn screenshot(&mut self, tab: &Tab) -> Vec<u8> {
        let shot =
            self.call(Some(&tab.session), "Page.captureScreenshot", json!({ "format": "png" }));
        base64_decode(shot["data"].as_str().expect("screenshot data"))
    }

    /// Console errors and warnings, exceptions, and every requested URL not starting with `own`.
    pub fn tab_problems(&mut self, tab: &Tab, own: &str) -> (Vec<String>, Vec<String>) {
        // Collect what arrived meanwhile.
        self.call(Some(&tab.session), "Runtime.evaluate", json!({ "expression": "1" }));
        let (errors, requests) = self.page_problems(&tab.session, own);
        (errors, requests.into_iter().filter(|r| !r.starts_with(own)).collect())
    }
}
