//! `mrbrake schema`: every format's JSON Schema and reference page, and the copies in
//! `docs/reference/` are up to date (CI fails when a format changes and its reference does not;
//! `MRBRAKE_UPDATE_REFERENCE=1 cargo test -p mrbrake-cli --test it schema_cli::` rewrites them).

use crate::common;

use common::{expect_input_error, mrbrake};

const FORMATS: [&str; 4] = ["spec", "magnetics", "heat", "study"];

fn stdout(args: &[&str]) -> String {
    let out = mrbrake(args);
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).expect("UTF-8")
}

#[test]
fn the_reference_in_docs_is_what_mrbrake_schema_prints() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/reference");
    let update = std::env::var("MRBRAKE_UPDATE_REFERENCE").is_ok_and(|v| v == "1");
    for format in FORMATS {
        let schema = stdout(&["schema", format]);
        let page = stdout(&["schema", format, "--markdown"]);
        let parsed: serde_json::Value = serde_json::from_str(&schema).expect("JSON");
        assert_eq!(parsed["$schema"], "http://json-schema.org/draft-07/schema#");
        for (name, text) in
            [(format!("{format}.schema.json"), &schema), (format!("{format}.md"), &page)]
        {
            let path = std::path::Path::new(root).join(&name);
            if update {
                std::fs::write(&path, text).unwrap();
            }
            let written = std::fs::read_to_string(&path).unwrap_or_default();
            assert!(
                written == *text,
                "docs/reference/{name} is out of date: run \
                 MRBRAKE_UPDATE_REFERENCE=1 cargo test -p mrbrake-cli --test it schema_cli::"
            );
        }
    }
}

#[test]
fn an_unknown_format_is_a_usage_error() {
    let out = mrbrake(&["schema", "nonsense"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("spec"));
    let _ = expect_input_error;
}
