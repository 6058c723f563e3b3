//! `mrbrake report`: the three kinds of page are well-formed, show the numbers of the matching
//! `--json`, and load in a real headless Chromium from a `file://` URL with no console error, no
//! network request, every figure rendered with a non-zero size, a non-blank screenshot and an A4
//! print. Without Chromium the browser checks are skipped with a note, unless
//! `MRBRAKE_REQUIRE_BROWSER=1` (CI), where its absence fails.

use crate::browser;
use crate::common;

use std::path::Path;

use common::{expect_input_error, json, mrbrake, path_str};
use mrbrake::report::html::check::numbers_agree;

/// Parses the page as XML (the pages are polyglot HTML5) and returns the number of `svg` and
/// `img` elements.
fn well_formed(page: &str) -> (usize, usize) {
    let options = roxmltree::ParsingOptions { allow_dtd: true, ..Default::default() };
    let doc = roxmltree::Document::parse_with_options(page, options)
        .unwrap_or_else(|e| panic!("the page is not well-formed: {e}"));
    let count = |tag: &str| doc.descendants().filter(|n| n.has_tag_name(tag)).count();
    assert_eq!(count("script"), 0);
    (count("svg"), count("img"))
}

/// Writes a report with `args` to `dir/name` and returns the page.
fn report(dir: &Path, name: &str, args: &[&str]) -> String {
    let out_path = dir.join(name);
    let mut all = vec!["report", "-o", path_str(&out_path)];
    all.extend_from_slice(args);
    let out = mrbrake(&all);
    assert!(out.status.success(), "{all:?}: {}", String::from_utf8_lossy(&out.stderr));
    std::fs::read_to_string(&out_path).expect("report written")
}

/// Loads each page in Chromium (when there is one) and checks what a reader would see.
fn check_in_browser(pages: &[&Path]) {
    let Some(chromium) = browser::find() else { return };
    let mut b = browser::Browser::start(&chromium);
    for page in pages {
        let visit = b.visit(page);
        let name = page.display();
        assert!(visit.errors.is_empty(), "{name}: console errors {:?}", visit.errors);
        assert!(visit.requests.is_empty(), "{name}: network requests {:?}", visit.requests);
        assert!(!visit.figures.is_empty(), "{name}: no figure");
        for (tag, w, h, loaded) in &visit.figures {
            assert!(
                *w > 10.0 && *h > 10.0 && *loaded,
                "{name}: {tag} rendered {w} × {h}, loaded {loaded}"
            );
        }
        let (share, colours) = browser::ink(&visit.screenshot_png);
        assert!(
            share > 0.02 && colours > 20,
            "{name}: blank screenshot ({share}, {colours} colours)"
        );
        assert!(visit.pdf.starts_with(b"%PDF"), "{name}: no PDF print");
        let pages = visit.pdf.windows(10).filter(|w| w == b"/Type /Pag").count();
        assert!(pages >= 2, "{name}: {pages} printed pages");
        eprintln!(
            "{name}: {} figures, screenshot {:.0} % ink, {} colours",
            visit.figures.len(),
            100.0 * share,
            colours
        );
    }
}

#[test]
fn design_report_matches_analyze_json_and_renders() {
    let dir = tempfile::tempdir().unwrap();
    let settings = ["--mesh", "coarse", "--points", "3"];
    let page = report(dir.path(), "design.html", &settings);
    let (svgs, imgs) = well_formed(&page);
    assert_eq!((svgs, imgs), (4, 1));
    let mut analyze = vec!["analyze", "--json"];
    analyze.extend_from_slice(&settings);
    let expected = json(&analyze);
    let checked = numbers_agree(&page, &expected).unwrap();
    assert!(checked > 100, "{checked} numbers checked");
    assert!(page.contains("Against the thesis"));
    check_in_browser(&[&dir.path().join("design.html")]);
}

/// `--response` adds the predicted dynamics: its section, table and three more figures (step
/// response, Bode diagram, eddy-current map), the numbers of `response --json`, and the page still loads cleanly (release only: a non-linear
/// transient of the whole brake).
#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: the brake's transient and frequency sweep")]
fn design_report_with_the_predicted_dynamics() {
    let dir = tempfile::tempdir().unwrap();
    let page =
        report(dir.path(), "dynamics.html", &["--mesh", "coarse", "--points", "3", "--response"]);
    let (svgs, imgs) = well_formed(&page);
    assert_eq!((svgs, imgs), (7, 1), "three more figures: step response, Bode, eddy currents");
    assert!(page.contains("id=\"dynamics\""));
    assert!(page.contains("J_φ = −σ ∂A/∂t"), "the eddy-current map's caption");
    let response = json(&["response", "--mesh", "coarse", "--json"]);
    let bandwidth = response["bandwidth_rad_s"].as_f64().expect("a bandwidth below 1000 rad/s");
    let t63 = response["step"][0]["t63_s"].as_f64().expect("t63") * 1e3;
    for shown in [format!("{bandwidth:.1}"), format!("{t63:.2}")] {
        assert!(page.contains(&format!(">{shown}<")), "the page shows {shown}");
    }
    check_in_browser(&[&dir.path().join("dynamics.html")]);
}

#[test]
fn bad_input_is_exit_code_2_with_a_clear_message() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.html");
    let out = path_str(&out);
    expect_input_error(&["report", "missing.toml", "-o", out], &["missing.toml"]);
    expect_input_error(&["report", "--frd", "f.csv", "-o", out], &["--log"]);
    expect_input_error(&["report", "--store", "missing.sqlite", "-o", out], &["missing.sqlite"]);
    expect_input_error(&["report", "--log", "missing.csv", "-o", out], &["missing.csv"]);
    expect_input_error(&["report", "--points", "1", "-o", out], &["--points", "got 1", ">= 2"]);
    let nowhere = dir.path().join("no-such-folder").join("r.html");
    expect_input_error(
        &["report", "--points", "2", "--mesh", "coarse", "-o", path_str(&nowhere)],
        &["no-such-folder"],
    );
    assert!(!Path::new(out).exists(), "no partial output on failure");
}

/// The browser checks can fail: a page with a script error and a request to a loopback port
/// (nothing listens there; no traffic leaves the machine) is caught.
#[test]
fn the_browser_check_sees_console_errors_and_requests() {
    let Some(chromium) = browser::find() else { return };
    let dir = tempfile::tempdir().unwrap();
    let page = dir.path().join("bad.html");
    std::fs::write(
        &page,
        "<!DOCTYPE html><html><body><p>x</p><img src=\"http://127.0.0.1:9/x.png\" />\
         <script>console.error('broken');</script></body></html>",
    )
    .unwrap();
    let visit = browser::Browser::start(&chromium).visit(&page);
    assert!(visit.errors.iter().any(|e| e.contains("broken")), "{:?}", visit.errors);
    assert_eq!(visit.requests, ["http://127.0.0.1:9/x.png"]);
    assert!(visit.figures.iter().any(|(tag, _, _, loaded)| tag == "IMG" && !loaded));
}

const SINGLE_DISC: &str =
    concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/specs/single-disc.toml");

/// A small two-objective optimisation; the study report's front is the optimiser's front, its
/// numbers those of `mrbrake export --json`, every front design has its own section, and the
/// hypervolume is shown with the reference point the run recorded.
#[test]
fn study_report_of_a_small_optimisation() {
    let dir = tempfile::tempdir().unwrap();
    let problem = dir.path().join("problem.toml");
    std::fs::write(
        &problem,
        format!(
            // Written as evaluated: rounded front designs would join the store, and the store's
            // front (the page's) would no longer be the optimiser's.
            "spec = \"{SINGLE_DISC}\"\nmesh = \"coarse\"\nmanufacturing_resolution = 0\n\
             [[variable]]\nname = \"g\"\nmin = \"0.3mm\"\nmax = \"1mm\"\n\
             [[variable]]\nname = \"d\"\nmin = \"1mm\"\nmax = \"2mm\"\n\
             [[constraint]]\nmetric = \"torque_max_Nm\"\nmin = \"0.5Nm\"\n\
             [[objective]]\nmetric = \"rotor_inertia_kg_m2\"\n\
             [[objective]]\nmetric = \"torque_max_Nm\"\ngoal = \"maximize\"\n\
             [algorithm]\nkind = \"nsga2\"\npopulation = 4\ngenerations = 1\nseed = 7\n"
        ),
    )
    .unwrap();
    let store = dir.path().join("opt.sqlite");
    let optimized = json(&["optimize", path_str(&problem), "--store", path_str(&store), "--json"]);
    let page = report(dir.path(), "study.html", &["--store", path_str(&store)]);
    let (svgs, _) = well_formed(&page);
    let exported = json(&["export", path_str(&store), "--json"]);
    let checked = numbers_agree(&page, &exported).unwrap();
    let front = optimized["front"].as_array().unwrap();
    assert!(!front.is_empty());
    assert!(checked >= front.len() * 4, "{checked} numbers checked");
    for (k, design) in front.iter().enumerate() {
        let key = design["key"].as_str().unwrap();
        assert!(page.contains(key), "front design {key} missing");
        assert!(page.contains(&format!("<a href=\"#front-{:02}\">", k + 1)));
        assert!(page.contains(&format!("<section id=\"front-{:02}\">", k + 1)));
    }
    assert_eq!(page.matches("<section id=\"front-0").count(), front.len(), "the same front");
    // Objective and constraint plots, the hypervolume against evaluations, and one cross-section
    // per front design.
    assert_eq!(svgs, 3 + front.len());
    // The hypervolume against the reference point the run fixed and recorded in the store.
    assert!(optimized["hypervolume"]["value"].as_f64().is_some_and(|v| v > 0.0), "{optimized}");
    assert!(page.contains("<section id=\"hypervolume\">"), "no hypervolume section");
    assert!(page.contains("recorded in the store by the run that fixed it"), "reference source");
    check_in_browser(&[&dir.path().join("study.html")]);
}

/// The rig's characterisation and frequency-response experiments: the page's numbers are those of
/// `characterize --json` and `tfest --json`.
#[test]
fn characterization_report_of_the_virtual_rig() {
    let dir = tempfile::tempdir().unwrap();
    let (char_dir, freq_dir) = (dir.path().join("char"), dir.path().join("freq"));
    assert!(mrbrake(&["rig", "characterize", "--out", path_str(&char_dir)]).status.success());
    assert!(mrbrake(&["rig", "freqresp", "--out", path_str(&freq_dir)]).status.success());
    let manifest = freq_dir.join("manifest.csv");
    assert!(mrbrake(&["freqresp", path_str(&manifest)]).status.success());
    let (log, frd) = (char_dir.join("characterization.csv"), freq_dir.join("frd.csv"));
    let page = report(dir.path(), "char.html", &["--log", path_str(&log), "--frd", path_str(&frd)]);
    let (svgs, imgs) = well_formed(&page);
    assert_eq!((svgs, imgs), (2, 1), "inverse model and Bode (SVG), loop (PNG)");
    let expected = serde_json::json!({
        "characterization": json(&["characterize", path_str(&log), "--json"]),
        "transfer_function": json(&["tfest", path_str(&frd), "--poles", "2", "--json"]),
    });
    let checked = numbers_agree(&page, &expected).unwrap();
    assert!(checked >= 7 + 2 * 9 + 8, "{checked} numbers checked");
    let only_log = report(dir.path(), "loop.html", &["--log", path_str(&log)]);
    assert!(!only_log.contains("id=\"bode\"") && only_log.contains("id=\"inverse\""));
    check_in_browser(&[&dir.path().join("char.html")]);
}
