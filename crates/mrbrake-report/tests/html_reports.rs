//! The HTML reports are well-formed (parsed by an XML parser: the pages are polyglot HTML5), hold
//! every section they promise, load nothing from outside, and show the numbers of their JSON.

use mrbrake_design::analysis::{AnalysisOptions, AnalysisRequest};
use mrbrake_design::geometry::build;
use mrbrake_design::mesh_build::MeshLevel;
use mrbrake_design::spec::{DEFAULT_SPEC_TOML, default_spec};
use mrbrake_report::html::check::numbers_agree;
use mrbrake_report::html::design::DesignReport;

/// Parses `page` as XML and checks what every report must hold: a title, sections with unique
/// ids that the contents link to, no script, no external reference, sized figures.
fn check_page(page: &str) -> roxmltree::Document<'_> {
    let options = roxmltree::ParsingOptions { allow_dtd: true, ..Default::default() };
    let doc = roxmltree::Document::parse_with_options(page, options)
        .unwrap_or_else(|e| panic!("the page is not well-formed: {e}"));
    let elements: Vec<roxmltree::Node<'_, '_>> =
        doc.descendants().filter(|n| n.is_element()).collect();
    assert!(elements.iter().all(|n| n.tag_name().name() != "script"), "a script element");
    let ids: Vec<&str> = elements.iter().filter_map(|n| n.attribute("id")).collect();
    let mut unique = ids.clone();
    unique.sort_unstable();
    unique.dedup();
    assert_eq!(unique.len(), ids.len(), "duplicate ids");
    for n in &elements {
        for attr in ["href", "src"] {
            if let Some(target) = n.attribute(attr) {
                let inside = target.starts_with('#') || target.starts_with("data:");
                assert!(inside, "{attr}={target} points outside the page");
                if let Some(anchor) = target.strip_prefix('#') {
                    assert!(ids.contains(&anchor), "link to a missing anchor #{anchor}");
                }
            }
        }
        if n.tag_name().name() == "img" {
            assert!(n.attribute("width").is_some() && n.attribute("height").is_some());
        }
    }
    doc
}

#[test]
fn design_report_of_the_thesis_brake() {
    let spec = default_spec();
    let options = AnalysisOptions { mesh: MeshLevel::Coarse, points: 3, ..Default::default() };
    let (analysis, field) = AnalysisRequest::of(&spec).options(options).run_with_field().unwrap();
    let geometry = build(&spec).unwrap();
    let report = DesignReport {
        analysis: &analysis,
        field: &field,
        geometry: &geometry,
        spec_text: DEFAULT_SPEC_TOML,
        source: "embedded default",
        thesis_comparison: true,
        extra_sections: Vec::new(),
    };
    let json = report.json().unwrap();
    assert_eq!(json, serde_json::to_value(&analysis).unwrap(), "the JSON is the analysis");
    let page = report.html().unwrap();
    let doc = check_page(&page);
    let sections: Vec<&str> = doc
        .descendants()
        .filter(|n| n.has_tag_name("section"))
        .filter_map(|n| n.attribute("id"))
        .collect();
    assert_eq!(
        sections,
        [
            "summary",
            "cross-section",
            "field-map",
            "torque-current",
            "gaps",
            "coil-mechanics",
            "thesis",
            "scope",
            "spec",
            "materials"
        ]
    );
    // Every numeric cell tied to the JSON agrees with it: 3 curve points × 7, 8 gaps × 9, …
    let checked = numbers_agree(&page, &json).unwrap();
    assert!(checked >= 3 * 7 + 8 * 9 + 10 + 10, "only {checked} numbers checked");
    // The figures: cross-section, torque–current, gaps, material curves (SVG); field map (PNG).
    let svgs = doc.descendants().filter(|n| n.has_tag_name("svg")).count();
    let imgs = doc.descendants().filter(|n| n.has_tag_name("img")).count();
    assert_eq!((svgs, imgs), (4, 1));
    // Every assumption of the spec (A1–A6 in its notes) and every field with its note is shown.
    for a in ["A1.", "A2.", "A3.", "A4.", "A5.", "A6."] {
        assert!(page.contains(a), "assumption {a} missing");
    }
    assert!(page.contains("<th>drum.r0</th><td>&quot;25mm&quot;</td><td>4.4.2</td>"));
    // The provenance of every material of the spec.
    for m in ["steel-1008", "aluminium", "stainless-304", "mrf-122eg", "copper", "air"] {
        assert!(page.contains(&format!("<th>{m}</th>")), "material {m} missing");
    }
    let out = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("design-report.html");
    std::fs::write(&out, &page).unwrap();
}
