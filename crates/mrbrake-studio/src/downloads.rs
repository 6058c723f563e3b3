//! What the page offers to keep: the spec as written, and of the latest default-mesh solve the
//! HTML report, the brake model, the torque–current curve (CSV) and the analysis (JSON, as
//! `analyze --json` prints it). Each is a response the browser saves; nothing is written here.

use mrbrake_report::html::design::DesignReport;

use crate::server::Reply;
use crate::session::{Session, chain};

/// The downloads there are.
const NAMES: [&str; 5] = ["spec.toml", "analysis.json", "curve.csv", "report.html", "model.json"];

/// The download `name` of `session`.
pub(crate) fn download(session: &Session, name: &str) -> Reply {
    let (text, solved) = {
        let state = session.lock();
        (state.text.clone(), state.solved.clone())
    };
    if !NAMES.contains(&name) {
        return Reply::error(404, &format!("no download '{name}'"));
    }
    let stem = file_stem(&text);
    let body = match name {
        "spec.toml" => Ok(("application/toml", text.into_bytes())),
        _ => match &solved {
            None => return Reply::error(409, "the default-mesh solve has not finished yet"),
            Some(s) => solved_file(s, name),
        },
    };
    match body {
        Ok((content_type, bytes)) => {
            let mut reply = Reply::with(200, content_type, bytes);
            reply.file_name = Some(format!("{stem}-{name}"));
            reply
        }
        Err((status, message)) => Reply::error(status, &message),
    }
}

/// A file made from the latest default solve.
fn solved_file(
    s: &crate::session::Solved,
    name: &str,
) -> Result<(&'static str, Vec<u8>), (u16, String)> {
    let failed = |e: &dyn std::error::Error| (500, chain(e));
    match name {
        "analysis.json" => {
            let mut text = serde_json::to_string_pretty(&s.analysis).map_err(|e| failed(&e))?;
            text.push('\n');
            Ok(("application/json", text.into_bytes()))
        }
        "curve.csv" => {
            Ok(("text/csv", mrbrake_report::analysis::torque_current_csv(&s.analysis).into_bytes()))
        }
        "report.html" => {
            let report = DesignReport {
                analysis: &s.analysis,
                field: &s.field,
                geometry: &s.geometry,
                spec_text: &s.text,
                source: "mrbrake studio",
                thesis_comparison: false,
                extra_sections: Vec::new(),
            };
            Ok(("text/html; charset=utf-8", report.html().map_err(|e| failed(&e))?.into_bytes()))
        }
        "model.json" => {
            let how = format!(
                "mrbrake studio (as mrbrake analyze SPEC --mesh {} --points {})",
                s.options.mesh.name(),
                s.options.points
            );
            let identity = mrbrake_explore::design::analysis_identity(&s.spec, &s.options)
                .map_err(|e| failed(&e))?;
            let model = mrbrake_device::brake_model::from_analysis(
                &s.analysis,
                &s.options,
                Some(identity),
                &how,
            )
            .map_err(|e| failed(&e))?;
            Ok(("application/json", model.to_json().into_bytes()))
        }
        _ => Err((404, format!("no download '{name}'"))),
    }
}

/// A file-name stem from the spec's name (letters, digits and dashes; `design` when none).
fn file_stem(text: &str) -> String {
    let name = toml::from_str::<toml::Table>(text)
        .ok()
        .and_then(|t| t.get("name").and_then(|n| n.as_str().map(String::from)))
        .unwrap_or_default();
    let stem: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c.to_ascii_lowercase() } else { '-' })
        .collect::<String>()
        .split('-')
        .filter(|w| !w.is_empty())
        .take(6)
        .collect::<Vec<_>>()
        .join("-");
    if stem.is_empty() { "design".into() } else { stem }
}
