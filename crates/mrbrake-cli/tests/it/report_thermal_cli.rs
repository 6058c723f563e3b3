//! `mrbrake report --thermal`: the design report with the heat section — its anchor, two more
//! figures (temperature map, warm-up curve), the numbers of `mrbrake thermal --json`, and a clean
//! load in Chromium when there is one (release only: the thermal analysis with its bisection,
//! warm-up and magnetic analysis).

use crate::browser;
use crate::common;

use common::{json, mrbrake, path_str};

/// The number of `svg` elements of the well-formed (polyglot XML) page, which has no script.
fn svg_count(page: &str) -> usize {
    let options = roxmltree::ParsingOptions { allow_dtd: true, ..Default::default() };
    let doc = roxmltree::Document::parse_with_options(page, options)
        .unwrap_or_else(|e| panic!("the page is not well-formed: {e}"));
    assert_eq!(doc.descendants().filter(|n| n.has_tag_name("script")).count(), 0);
    doc.descendants().filter(|n| n.has_tag_name("svg")).count()
}

#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: the brake's thermal and magnetic analyses")]
fn design_report_with_the_heat_section() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("heat.html");
    let args = ["report", "-o", path_str(&path), "--mesh", "coarse", "--points", "3"];
    let plain = mrbrake(&args);
    assert!(plain.status.success(), "{}", String::from_utf8_lossy(&plain.stderr));
    let without = svg_count(&std::fs::read_to_string(&path).unwrap());
    let mut with_heat = args.to_vec();
    with_heat.push("--thermal");
    let out = mrbrake(&with_heat);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let page = std::fs::read_to_string(&path).unwrap();
    assert_eq!(svg_count(&page), without + 2, "temperature map and warm-up curve");
    assert!(page.contains("id=\"heat\""));
    assert!(!page.contains("the temperature map and warm-up curve (thermal analysis)"));
    let thermal = json(&["thermal", "--mesh", "coarse", "--json"]);
    let rating = thermal["continuous_current_A"].as_f64().unwrap();
    let hot = thermal["steady"]["coil_max_T_C"].as_f64().unwrap();
    let current_hot = thermal["behaviour"]["voltage_drive"]["current_hot_A"].as_f64().unwrap();
    for shown in [format!("{rating:.3}"), format!("{hot:.1}"), format!("{current_hot:.3}")] {
        assert!(page.contains(&format!(">{shown}<")), "the page shows {shown}");
    }
    if let Some(chromium) = browser::find() {
        let visit = browser::Browser::start(&chromium).visit(&path);
        assert!(visit.errors.is_empty(), "console errors {:?}", visit.errors);
        assert!(visit.requests.is_empty(), "network requests {:?}", visit.requests);
        for (tag, w, h, loaded) in &visit.figures {
            assert!(*w > 10.0 && *h > 10.0 && *loaded, "{tag} rendered {w} × {h}");
        }
        let (share, colours) = browser::ink(&visit.screenshot_png);
        assert!(share > 0.02 && colours > 20, "blank screenshot ({share}, {colours} colours)");
        assert!(visit.pdf.starts_with(b"%PDF"), "no PDF print");
    }
}
