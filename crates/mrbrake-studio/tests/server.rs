//! The studio as a server, over real HTTP on 127.0.0.1: a test for each security rule (token,
//! Host, Origin, body and spec size, bounded sessions and solve queue, no file access), and that
//! a newer edit makes the older solve obsolete.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::time::{Duration, Instant};

use mrbrake_studio::{Config, Limits, Studio, TOKEN_HEADER};
use serde_json::{Value, json};

/// A started studio with its address and token.
struct Running {
    studio: Studio,
    host: String,
    token: String,
}

fn start(config: Config) -> Running {
    let studio = Studio::start(config).expect("the studio starts");
    let url = studio.url().to_string();
    let host = url.trim_start_matches("http://").split('/').next().unwrap().to_string();
    let token = url.split("token=").nth(1).unwrap().to_string();
    Running { studio, host, token }
}

/// One HTTP/1.1 request with `headers` (a Host is added unless given); the status and body.
fn request(
    host: &str,
    method: &str,
    path: &str,
    headers: &[(&str, &str)],
    body: &[u8],
) -> (u16, Vec<u8>) {
    let mut stream = TcpStream::connect(host).expect("connect to the studio");
    stream.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
    let mut head = format!("{method} {path} HTTP/1.1\r\nConnection: close\r\n");
    if !headers.iter().any(|(k, _)| k.eq_ignore_ascii_case("Host")) {
        head.push_str(&format!("Host: {host}\r\n"));
    }
    for (k, v) in headers {
        head.push_str(&format!("{k}: {v}\r\n"));
    }
    if !headers.iter().any(|(k, _)| k.eq_ignore_ascii_case("Transfer-Encoding")) {
        head.push_str(&format!("Content-Length: {}\r\n", body.len()));
    }
    head.push_str("\r\n");
    stream.write_all(head.as_bytes()).unwrap();
    let _ = stream.write_all(body);
    let mut response = Vec::new();
    let _ = stream.read_to_end(&mut response);
    let text = String::from_utf8_lossy(&response);
    let status = text.split(' ').nth(1).and_then(|s| s.parse().ok()).unwrap_or(0);
    let split =
        response.windows(4).position(|w| w == b"\r\n\r\n").map_or(response.len(), |p| p + 4);
    let head = text[..split.min(text.len())].to_ascii_lowercase();
    let body = &response[split..];
    let body =
        if head.contains("transfer-encoding: chunked") { dechunk(body) } else { body.to_vec() };
    (status, body)
}

/// A chunked body's data (large responses come chunked).
fn dechunk(mut body: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    while let Some(end) = body.windows(2).position(|w| w == b"\r\n") {
        let size =
            usize::from_str_radix(String::from_utf8_lossy(&body[..end]).trim(), 16).unwrap_or(0);
        if size == 0 {
            break;
        }
        out.extend_from_slice(&body[end + 2..end + 2 + size]);
        body = &body[end + 2 + size + 2..];
    }
    out
}

impl Running {
    fn api(&self, method: &str, path: &str, body: Option<Value>) -> (u16, Value) {
        let bytes = body.map(|b| serde_json::to_vec(&b).unwrap()).unwrap_or_default();
        let (status, body) =
            request(&self.host, method, path, &[(TOKEN_HEADER, &self.token)], &bytes);
        (status, serde_json::from_slice(&body).unwrap_or(Value::Null))
    }

    fn new_session(&self) -> Value {
        let (status, state) = self.api("POST", "/api/sessions", None);
        assert_eq!(status, 200, "{state}");
        state
    }
}

fn config(workers: usize) -> Config {
    Config { workers, ..Config::default() }
}

#[test]
fn it_binds_the_loopback_address_by_default() {
    assert!(Config::default().bind.is_loopback());
    let r = start(config(1));
    assert!(r.host.starts_with("127.0.0.1:"), "{}", r.host);
    r.studio.shut_down();
}

#[test]
fn every_request_needs_the_token() {
    let r = start(config(1));
    assert_eq!(request(&r.host, "GET", "/", &[], b"").0, 403);
    assert_eq!(request(&r.host, "GET", "/api/schema", &[], b"").0, 403);
    assert_eq!(request(&r.host, "GET", "/?token=0123", &[], b"").0, 403);
    assert_eq!(request(&r.host, "GET", "/api/schema", &[(TOKEN_HEADER, "wrong")], b"").0, 403);
    let (status, page) = request(&r.host, "GET", &format!("/?token={}", r.token), &[], b"");
    assert_eq!(status, 200);
    assert!(String::from_utf8_lossy(&page).contains("mrbrake studio"));
    assert_eq!(r.api("GET", "/api/schema", None).0, 200);
    r.studio.shut_down();
}

#[test]
fn a_foreign_host_or_origin_is_refused() {
    let r = start(config(1));
    let port = r.host.split(':').nth(1).unwrap().to_string();
    let token = r.token.clone();
    let rebinding = format!("attacker.example:{port}");
    let (status, body) = request(
        &r.host,
        "GET",
        "/api/schema",
        &[("Host", &rebinding), (TOKEN_HEADER, &token)],
        b"",
    );
    assert_eq!(status, 403, "DNS rebinding: {}", String::from_utf8_lossy(&body));
    let origin = [("Origin", "http://attacker.example"), (TOKEN_HEADER, token.as_str())];
    assert_eq!(request(&r.host, "POST", "/api/sessions", &origin, b"").0, 403, "cross-site");
    let own = format!("http://{}", r.host);
    let same = [("Origin", own.as_str()), (TOKEN_HEADER, token.as_str())];
    assert_eq!(request(&r.host, "POST", "/api/sessions", &same, b"").0, 200);
    let localhost = format!("localhost:{port}");
    assert_eq!(
        request(&r.host, "GET", "/api/info", &[("Host", &localhost), (TOKEN_HEADER, &token)], b"")
            .0,
        200
    );
    r.studio.shut_down();
}

#[test]
fn bodies_and_specs_are_bounded() {
    let limits = Limits { body_bytes: 4096, spec_bytes: 2048, ..Limits::default() };
    let r = start(Config { limits, ..config(1) });
    let id = r.new_session()["id"].as_str().unwrap().to_string();
    let path = format!("/api/sessions/{id}/edit");
    let big = vec![b'x'; 10_000];
    let (status, _) = request(&r.host, "POST", &path, &[(TOKEN_HEADER, &r.token)], &big);
    assert_eq!(status, 413, "a declared length over the limit");
    let chunked = format!("{:x}\r\n{}\r\n0\r\n\r\n", big.len(), "x".repeat(big.len()));
    let headers = [(TOKEN_HEADER, r.token.as_str()), ("Transfer-Encoding", "chunked")];
    assert_eq!(request(&r.host, "POST", &path, &headers, chunked.as_bytes()).0, 413, "chunked");
    // A huge declared length with no body, with or without the token, is refused and the server
    // lives (tiny_http once allocated the whole declared rest when dropping the request: abort).
    for token in [r.token.as_str(), "wrong"] {
        let mut stream = TcpStream::connect(&r.host).unwrap();
        stream.set_read_timeout(Some(Duration::from_secs(30))).unwrap();
        let head = format!(
            "POST {path} HTTP/1.1\r\nHost: {}\r\n{TOKEN_HEADER}: {token}\r\n\
             Content-Length: 999999999999\r\n\r\n{{}}",
            r.host
        );
        stream.write_all(head.as_bytes()).unwrap();
        stream.shutdown(std::net::Shutdown::Write).unwrap();
        let mut answer = String::new();
        let _ = stream.read_to_string(&mut answer);
        assert!(
            answer.starts_with("HTTP/1.1 413") || answer.starts_with("HTTP/1.1 403"),
            "{answer}"
        );
        assert_eq!(r.api("GET", "/api/info", None).0, 200, "the server still answers");
    }
    let (status, body) = r.api("POST", &path, Some(json!({ "text": "#".repeat(3000) })));
    assert_eq!(status, 413, "{body}");
    let (status, _) =
        r.api("POST", &path, Some(json!({ "path": "name", "value": "n".repeat(3000) })));
    assert_eq!(status, 413, "a form edit cannot grow the spec past the limit either");
    r.studio.shut_down();
}

#[test]
fn sessions_and_the_solve_queue_are_bounded() {
    let limits = Limits { sessions: 3, ..Limits::default() };
    let r = start(Config { limits, ..config(1) });
    let ids: Vec<String> =
        (0..5).map(|_| r.new_session()["id"].as_str().unwrap().to_string()).collect();
    assert_eq!(
        r.api("GET", &format!("/api/sessions/{}", ids[0]), None).0,
        404,
        "the oldest was closed"
    );
    assert_eq!(r.api("GET", &format!("/api/sessions/{}", ids[4]), None).0, 200);
    let path = format!("/api/sessions/{}/edit", ids[4]);
    for k in 0..200 {
        let value = format!("{}mm", 0.4 + 0.001 * f64::from(k % 50));
        let (status, _) = r.api("POST", &path, Some(json!({ "path": "drum.gap", "value": value })));
        assert_eq!(status, 200);
    }
    let stats = r.studio.queue_stats();
    assert!(stats.most_running <= 1, "one worker: {stats:?}");
    assert!(stats.most_waiting <= 3, "at most one entry per session: {stats:?}");
    r.studio.shut_down();
}

#[test]
fn no_request_reaches_a_file() {
    let dir = tempfile::tempdir().unwrap();
    let secret = dir.path().join("secret.txt");
    std::fs::write(&secret, "do not serve").unwrap();
    let r = start(config(1));
    let id = r.new_session()["id"].as_str().unwrap().to_string();
    let attempts = [
        "/../../etc/passwd".to_string(),
        format!("/studio.js/../../{}", secret.display()),
        format!("/api/sessions/{id}/download/..%2F..%2Fetc%2Fpasswd"),
        format!("/api/sessions/{id}/download/{}", secret.display()),
        "/api/study/spec?index=0".to_string(),
    ];
    for path in attempts {
        let (status, body) = request(&r.host, "GET", &path, &[(TOKEN_HEADER, &r.token)], b"");
        assert_eq!(status, 404, "{path}");
        assert!(
            !String::from_utf8_lossy(&body).contains("do not serve")
                && !String::from_utf8_lossy(&body).contains("root:")
        );
    }
    r.studio.shut_down();
}

/// A newer edit makes the older solve obsolete: nothing of the older spec is ever published,
/// and the newer one is solved (coarse mesh only, to keep it short: the default stage is
/// cancelled once the coarse result is in).
#[test]
fn a_newer_edit_cancels_the_older_solve() {
    let r = start(config(1));
    let state = r.new_session();
    let id = state["id"].as_str().unwrap().to_string();
    let edit = format!("/api/sessions/{id}/edit");
    let (_, first) = r.api("POST", &edit, Some(json!({ "path": "drum.gap", "value": "0.6mm" })));
    let (_, second) = r.api("POST", &edit, Some(json!({ "path": "drum.gap", "value": "0.7mm" })));
    let newest = second["version"].as_u64().unwrap();
    assert!(newest > first["version"].as_u64().unwrap());
    let deadline = Instant::now() + Duration::from_secs(300);
    let mut revision = 0;
    loop {
        let (status, s) = r.api("GET", &format!("/api/sessions/{id}?after={revision}"), None);
        revision = s["revision"].as_u64().unwrap_or_else(|| panic!("{status}: {s}"));
        for stage in s["stages"].as_array().unwrap() {
            if let Some(v) = stage["result"]["version"].as_u64() {
                assert_eq!(v, newest, "only the newest edit's results are published");
            }
        }
        if s["stages"][0]["status"] == "done" {
            let analysis = &s["stages"][0]["result"]["analysis"];
            assert!(analysis["torque"]["at_max_current_Nm"].as_f64().unwrap() > 0.5);
            r.api("POST", &format!("/api/sessions/{id}/cancel"), None);
            break;
        }
        assert!(Instant::now() < deadline, "no coarse result");
    }
    let (_, s) = r.api("GET", &format!("/api/sessions/{id}"), None);
    assert_eq!(s["stages"][1]["status"], "cancelled");
    r.studio.shut_down();
}

/// The analyses on request: an unknown one is refused; a cancel drops a waiting one at once and
/// it never publishes a result; an edit drops them too; a spec with errors has nothing to analyse.
#[test]
fn analyses_on_request_are_cancelled_by_a_cancel_or_an_edit() {
    let r = start(config(1));
    let state = r.new_session();
    let id = state["id"].as_str().unwrap().to_string();
    let session = format!("/api/sessions/{id}");
    let status_of = |s: &Value, k: usize| s["requests"][k]["status"].as_str().unwrap().to_string();
    assert_eq!(status_of(&state, 1), "idle");
    let (status, _) = r.api("POST", &format!("{session}/analyses/stress"), None);
    assert_eq!(status, 404);
    // The one worker is busy with the static solve: the thermal analysis waits, then is dropped.
    let (_, s) = r.api("POST", &format!("{session}/analyses/thermal"), None);
    assert_eq!(status_of(&s, 1), "queued");
    let (_, s) = r.api("POST", &format!("{session}/analyses/cancel"), None);
    assert_eq!(status_of(&s, 1), "cancelled");
    let (_, s) = r.api("POST", &format!("{session}/analyses/response"), None);
    assert_eq!(status_of(&s, 0), "queued");
    let edit = format!("{session}/edit");
    let (_, s) = r.api("POST", &edit, Some(json!({ "path": "drum.gap", "value": "0.6mm" })));
    assert_eq!(status_of(&s, 0), "cancelled", "an edit drops the analysis of the older design");
    r.api("POST", &format!("{session}/cancel"), None);
    let deadline = Instant::now() + Duration::from_secs(300);
    loop {
        let (_, s) = r.api("GET", &session, None);
        if s["queue"]["waiting"] == 0 && s["queue"]["running"] == 0 {
            for k in [0, 1] {
                assert_eq!(status_of(&s, k), "cancelled");
                assert!(s["requests"][k]["result"].is_null(), "no result of a dropped analysis");
            }
            break;
        }
        assert!(Instant::now() < deadline, "the queue did not drain");
        std::thread::sleep(Duration::from_millis(50));
    }
    let (_, s) = r.api("POST", &edit, Some(json!({ "text": "name = [" })));
    assert!(s["instant"]["valid"] == false, "{}", s["instant"]);
    let (status, body) = r.api("POST", &format!("{session}/analyses/haptic"), None);
    assert_eq!(status, 409, "{body}");
    assert!(body["error"].as_str().unwrap().contains("the spec has errors"), "{body}");
    r.studio.shut_down();
}

/// The thermal analysis on request answers `mrbrake thermal --json`'s numbers (the library call
/// with the command's defaults: the spec's maximum current, what heat does to the brake).
#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: a two-hour warm-up on the default mesh")]
fn the_thermal_analysis_on_request_is_the_commands() {
    use mrbrake_design::thermal::{ThermalOptions, analyze_thermal};
    let r = start(config(1));
    let id = r.new_session()["id"].as_str().unwrap().to_string();
    let session = format!("/api/sessions/{id}");
    r.api("POST", &format!("{session}/analyses/thermal"), None);
    let deadline = Instant::now() + Duration::from_secs(600);
    let answer = loop {
        let (_, s) = r.api("GET", &session, None);
        match s["requests"][1]["status"].as_str().unwrap() {
            "done" => break s["requests"][1]["result"].clone(),
            "failed" => panic!("{}", s["requests"][1]),
            _ => {}
        }
        assert!(Instant::now() < deadline, "no thermal result");
        std::thread::sleep(Duration::from_millis(100));
    };
    let spec = mrbrake_design::spec::default_spec();
    let options = ThermalOptions {
        current_a: spec.coil.max_current.a(),
        behaviour: true,
        ..ThermalOptions::default()
    };
    let expected = serde_json::to_value(analyze_thermal(&spec, &options).unwrap()).unwrap();
    // The heat solve's sums are not bit-reproducible across threads (parallel assembly): equal
    // to round-off.
    for pointer in [
        "/continuous_current_A",
        "/max_duty_at_max_current",
        "/time_to_limit_s",
        "/steady/coil_max_T_C",
        "/steady/fluid_mean_T_C",
        "/behaviour/torque_hot_current_drive_Nm",
    ] {
        let (got, want) = (&answer["result"].pointer(pointer), &expected.pointer(pointer));
        match (got.and_then(Value::as_f64), want.and_then(Value::as_f64)) {
            (Some(a), Some(b)) => assert!((a - b).abs() <= 1e-9 * b.abs(), "{pointer}: {a} vs {b}"),
            _ => assert_eq!(got, want, "{pointer}"),
        }
    }
    assert_eq!(answer["cli"], "mrbrake thermal SPEC --json");
    assert!(answer["figures"]["warmup"].as_str().unwrap().contains("<svg"));
    r.studio.shut_down();
}
