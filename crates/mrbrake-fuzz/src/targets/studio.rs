//! The studio's HTTP endpoints as an input (issue 33, "Keep it found"): raw request bytes —
//! request lines, headers, bodies, tokens — mutated and sent to one running studio on 127.0.0.1.
//! Properties checked on every execution (a violation panics: a finding):
//! - without the session token anywhere in the request, nothing is answered with a 2xx;
//! - after any request the server still answers a valid one (no handler thread lost, no lock
//!   poisoned for good, no queue grown without bound).
//!
//! Seeds are valid requests with placeholders (`{{TOKEN}}`, `{{HOST}}`, `{{SESSION}}`) filled in
//! at run time, so mutations of a placeholder give wrong tokens, hosts and session ids. No seed
//! long-polls (`?after=`): a poll waits up to 20 s by design, which is not a finding.

use std::io::{Read, Write};
use std::net::{Shutdown, TcpStream};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use mrbrake_studio::{Config, Studio, TOKEN_HEADER};

use super::Target;
use crate::Outcome;

/// The target of this module.
pub fn targets() -> Vec<Target> {
    vec![Target { name: "studio-http", seeds: seeds(), run: run_request }]
}

/// One studio for the whole fuzzing run, with its address, token and a session.
struct Harness {
    _studio: Studio,
    host: String,
    token: String,
    session: String,
}

fn harness() -> &'static Harness {
    static HARNESS: OnceLock<Harness> = OnceLock::new();
    HARNESS.get_or_init(|| {
        let studio = Studio::start(Config { workers: 1, ..Config::default() })
            .expect("the studio starts on 127.0.0.1");
        let url = studio.url().to_string();
        let host = url.trim_start_matches("http://").split('/').next().unwrap_or("").to_string();
        let token = url.split("token=").nth(1).unwrap_or("").to_string();
        let mut h = Harness { _studio: studio, host, token, session: String::new() };
        let request = fill(b"POST /api/sessions HTTP/1.1\r\nHost: {{HOST}}\r\nX-Mrbrake-Token: {{TOKEN}}\r\nContent-Length: 0\r\n\r\n", &h);
        let (_, body) = send(&h.host, &request);
        let text = String::from_utf8_lossy(&body);
        h.session = text.split("\"id\":\"").nth(1).and_then(|s| s.split('"').next()).unwrap_or("").to_string();
        h
    })
}

const GETS: &[&str] = &[
    "GET /api/info HTTP/1.1\r\nHost: {{HOST}}\r\nX-Mrbrake-Token: {{TOKEN}}\r\n\r\n",
    "GET /?token={{TOKEN}} HTTP/1.1\r\nHost: {{HOST}}\r\n\r\n",
    "GET /studio.js?token={{TOKEN}} HTTP/1.1\r\nHost: {{HOST}}\r\nOrigin: http://{{HOST}}\r\n\r\n",
    "GET /api/schema HTTP/1.1\r\nHost: {{HOST}}\r\nX-Mrbrake-Token: {{TOKEN}}\r\n\r\n",
    "GET /api/sessions/{{SESSION}} HTTP/1.1\r\nHost: {{HOST}}\r\nX-Mrbrake-Token: {{TOKEN}}\r\n\r\n",
    "GET /api/sessions/{{SESSION}}/download/spec.toml?token={{TOKEN}} HTTP/1.1\r\nHost: {{HOST}}\r\n\r\n",
];

/// Requests with a body: the path after `/api/sessions/{{SESSION}}/` and the JSON body (each
/// answered 200 whatever ran before, as the seeds must be accepted).
const POSTS: &[(&str, &str)] = &[
    ("edit", r#"{"path":"name","value":"fuzz"}"#),
    ("edit", r#"{"path":"coil.max_current","value":"2A"}"#),
    ("solve", ""),
    ("analyses/cancel", ""),
];

fn seeds() -> Vec<Vec<u8>> {
    let posts = POSTS.iter().map(|(path, body)| {
        format!(
            "POST /api/sessions/{{{{SESSION}}}}/{path} HTTP/1.1\r\nHost: {{{{HOST}}}}\r\n\
             X-Mrbrake-Token: {{{{TOKEN}}}}\r\nContent-Type: application/json\r\n\
             Content-Length: {}\r\n\r\n{body}",
            body.len()
        )
    });
    let chunked = "POST /api/sessions/{{SESSION}}/edit HTTP/1.1\r\nHost: {{HOST}}\r\n\
                   X-Mrbrake-Token: {{TOKEN}}\r\nTransfer-Encoding: chunked\r\n\r\n\
                   1e\r\n{\"path\":\"name\",\"value\":\"fuzz\"}\r\n0\r\n\r\n";
    GETS.iter()
        .map(|s| s.to_string())
        .chain(posts)
        .chain([chunked.to_string()])
        .map(String::into_bytes)
        .collect()
}

/// `template` with the placeholders filled in.
fn fill(template: &[u8], h: &Harness) -> Vec<u8> {
    let text = String::from_utf8_lossy(template);
    if !text.contains("{{") {
        return template.to_vec();
    }
    text.replace("{{TOKEN}}", &h.token)
        .replace("{{HOST}}", &h.host)
        .replace("{{SESSION}}", &h.session)
        .into_bytes()
}

/// Sends `request` (then closes the writing side) and reads the answer for at most 3 s: the
/// status (0 for none) and the body.
fn send(host: &str, request: &[u8]) -> (u16, Vec<u8>) {
    let Ok(mut stream) = TcpStream::connect(host) else { return (0, Vec::new()) };
    let _ = stream.set_read_timeout(Some(Duration::from_secs(3)));
    let _ = stream.set_write_timeout(Some(Duration::from_secs(3)));
    let _ = stream.write_all(request);
    let _ = stream.shutdown(Shutdown::Write);
    let mut answer = Vec::new();
    let _ = stream.read_to_end(&mut answer);
    let head_end = answer.windows(4).position(|w| w == b"\r\n\r\n").map_or(answer.len(), |p| p + 4);
    let head = String::from_utf8_lossy(&answer[..head_end]);
    let status = head.split(' ').nth(1).and_then(|s| s.parse().ok()).unwrap_or(0);
    (status, answer[head_end..].to_vec())
}

fn run_request(input: &[u8]) -> Outcome {
    let h = harness();
    let request = fill(input, h);
    let (status, _) = send(&h.host, &request);
    let has_token = request.windows(h.token.len()).any(|w| w == h.token.as_bytes());
    assert!(
        has_token || !(200..300).contains(&status),
        "answered {status} to a request without the token: {}",
        String::from_utf8_lossy(&request)
    );
    check_alive(h);
    match status {
        200..=299 => Outcome::Ok,
        s => Outcome::Refused(format!("HTTP {}", s / 100 * 100)),
    }
}

/// Panics unless the server answers a valid request within 5 s.
fn check_alive(h: &Harness) {
    let probe = format!(
        "GET /api/info HTTP/1.1\r\nHost: {}\r\n{TOKEN_HEADER}: {}\r\n\r\n",
        h.host, h.token
    );
    let start = Instant::now();
    loop {
        if send(&h.host, probe.as_bytes()).0 == 200 {
            return;
        }
        assert!(start.elapsed() < Duration::from_secs(5), "the studio stopped answering");
        std::thread::sleep(Duration::from_millis(50));
    }
}
