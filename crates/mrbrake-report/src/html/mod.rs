//! Self-contained HTML reports: one file a researcher can open offline, print on A4 and mail.
//!
//! Brief overview: [`writer`] writes escaped, well-formed HTML and tables whose numeric cells name
//! the JSON value they show (`data-json` pointer, `data-scale`), so a table can never disagree with
//! the command's `--json`; [`Page`] assembles sections under a title with a table of contents, the
//! inline style sheet (screen and A4 print) and a Content-Security-Policy that forbids scripts and
//! every network fetch; figures are inline SVG ([`crate::chart`] via plotters' SVG backend, the
//! [`cross_section`] drawing) or, for the field map with its thousands of triangles, an inline
//! base64 PNG (`data:` URL, no request).
//!
//! The reports:
//! * [`design`]: a brake design (cross-section with parts and materials, field map, torque–current
//!   curve, |B| along each gap, gap/coil/mechanics tables, the thesis comparison for the embedded
//!   default, the spec's assumptions, the provenance of every material curve);
//! * [`study`]: a results store (variables and objectives, Pareto front and constraint plots, the
//!   front's designs with a section each);
//! * [`uncertainty`]: the section of an uncertainty propagation (bands, tornado chart, Sobol'
//!   indices) added to a design report;
//! * [`characterization`]: a test-rig characterisation (hysteresis loop, branch fits, inverse model,
//!   and with frequency-response data the Bode diagram with the fitted transfer function);
//! * [`request`]: each of those pages from what a front end parsed (the analyses a page needs run
//!   there), the one composition of `mrbrake report` and Python's `mrbrake.report`.
//!
//! Each report type has a `json()` document (the same values as the corresponding `--json`
//! output) and an `html()` page whose numeric cells point into it.
//!
//! **Adding a section** (e.g. the step response and Bode diagram of a dynamics analysis, or the
//! temperature map and warm-up curve of a heat analysis, once those analyses exist): write a
//! function in a module beside these that turns the analysis's result type into a [`Section`]
//! (figures with [`Figure::to_svg`](crate::chart::Figure::to_svg) through [`inline_svg`], tables
//! with [`writer::Table`]) and hand it to the report's `extra_sections`
//! ([`design::DesignReport::extra_sections`]); the page lists it in its contents.

pub mod characterization;
pub mod check;
pub mod cross_section;
pub mod design;
pub mod request;
pub mod response;
pub mod spec_notes;
pub mod study;
pub mod thermal;
pub mod uncertainty;
pub mod writer;

mod style;

pub use writer::{Cell, Html, Table, escape, fixed};

use crate::ReportError;

/// One section of a page: an anchor, a heading and its content.
#[derive(Debug)]
pub struct Section {
    /// The anchor (`id`), unique on the page.
    pub id: String,
    /// The heading.
    pub title: String,
    /// The content.
    pub body: Html,
}

impl Section {
    /// A section with empty content.
    pub fn new(id: impl Into<String>, title: impl Into<String>) -> Self {
        Self { id: id.into(), title: title.into(), body: Html::new() }
    }
}

/// A whole page: title, a line of facts under it, sections.
#[derive(Debug)]
pub struct Page {
    /// The page title (also the document's `<title>`).
    pub title: String,
    /// Lines under the title (what was analysed, by which version, with which settings).
    pub facts: Vec<String>,
    /// The sections, in order.
    pub sections: Vec<Section>,
}

/// What the page may load: nothing from anywhere but itself (inline style, `data:` images); no
/// script at all.
const CONTENT_SECURITY_POLICY: &str =
    "default-src 'none'; style-src 'unsafe-inline'; img-src data:; font-src data:";

impl Page {
    /// The HTML document.
    pub fn render(self) -> String {
        let mut h = Html::new();
        h.trusted_markup("<!DOCTYPE html>\n");
        h.open("html", &[("lang", "en"), ("xmlns", "http://www.w3.org/1999/xhtml")]);
        h.open("head", &[]);
        h.void("meta", &[("charset", "utf-8")]);
        h.void(
            "meta",
            &[("http-equiv", "Content-Security-Policy"), ("content", CONTENT_SECURITY_POLICY)],
        );
        h.void("meta", &[("name", "viewport"), ("content", "width=device-width, initial-scale=1")]);
        let generator = format!("mrbrake {}", env!("CARGO_PKG_VERSION"));
        h.void("meta", &[("name", "generator"), ("content", &generator)]);
        h.element("title", &[], &self.title);
        h.open("style", &[]).text(style::CSS).close();
        h.close();
        h.open("body", &[]).open("header", &[]);
        h.element("h1", &[], &self.title);
        for fact in &self.facts {
            h.element("p", &[("class", "facts")], fact);
        }
        h.open("nav", &[("aria-label", "contents")]).open("ol", &[]);
        for s in &self.sections {
            let href = format!("#{}", s.id);
            h.open("li", &[]).element("a", &[("href", &href)], &s.title).close();
        }
        h.close().close().close();
        h.open("main", &[]);
        for s in self.sections {
            h.open("section", &[("id", &s.id)]);
            h.element("h2", &[], &s.title);
            h.append(s.body);
            h.close();
        }
        h.close();
        h.open("footer", &[]).text(&format!(
            "Written by {generator}. Self-contained: no script, nothing loaded from the network."
        ));
        h.close().close().close();
        h.finish()
    }
}

/// An SVG document from mrbrake's renderers made fit for inlining: the XML declaration dropped,
/// the fixed pixel size replaced by a `viewBox` and a relative width so it scales with the page,
/// and an accessible name.
pub fn inline_svg(svg: &str, label: &str) -> Result<String, ReportError> {
    let start = svg
        .find("<svg")
        .ok_or_else(|| ReportError::Backend("the renderer returned no <svg> element".into()))?;
    let body = &svg[start..];
    let tag_end =
        body.find('>').ok_or_else(|| ReportError::Backend("unterminated <svg> tag".into()))?;
    let (tag, rest) = body.split_at(tag_end);
    let number = |name: &str| -> Option<f64> {
        let key = format!(" {name}=\"");
        let from = tag.find(&key)? + key.len();
        tag[from..].split('"').next()?.parse().ok()
    };
    let (w, h) = number("width")
        .zip(number("height"))
        .ok_or_else(|| ReportError::Backend("<svg> without width and height".into()))?;
    let open = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 {w} {h}\" width=\"{w}\" height=\"{h}\" \
         class=\"figure\" role=\"img\" aria-label=\"{}\"",
        escape(label)
    );
    Ok(format!("{open}{}", rest.trim_end()))
}

/// A `<figure>` holding inline markup (an SVG from [`inline_svg`]) and a caption.
pub fn figure(h: &mut Html, markup: &str, caption: &str) {
    h.open("figure", &[]).trusted_markup(markup).element("figcaption", &[], caption).close();
}

/// A `<figure>` with a PNG image inlined as a `data:` URL, its pixel size and a caption.
pub fn png_figure(h: &mut Html, png: &[u8], size: (u32, u32), alt: &str, caption: &str) {
    let src = format!("data:image/png;base64,{}", base64(png));
    let (w, hh) = (size.0.to_string(), size.1.to_string());
    h.open("figure", &[]);
    h.void(
        "img",
        &[("src", &src), ("width", &w), ("height", &hh), ("alt", alt), ("class", "figure")],
    );
    h.element("figcaption", &[], caption).close();
}

/// Standard base64 (RFC 4648 §4, with padding).
pub fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [chunk[0], *chunk.get(1).unwrap_or(&0), *chunk.get(2).unwrap_or(&0)];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ALPHABET[((n >> (18 - 6 * k)) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_matches_rfc_4648_vectors() {
        let cases = [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ];
        for (input, expected) in cases {
            assert_eq!(base64(input.as_bytes()), expected);
        }
    }

    #[test]
    fn inlined_svg_scales_and_is_labelled() {
        let svg = "<?xml version=\"1.0\"?>\n<svg width=\"900\" height=\"600\" viewBox=\"0 0 900 600\" \
                   xmlns=\"http://www.w3.org/2000/svg\">\n<rect/>\n</svg>\n";
        let out = inline_svg(svg, "a \"chart\"").unwrap();
        assert!(
            out.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 900 600\"")
        );
        assert!(out.contains("aria-label=\"a &quot;chart&quot;\">\n<rect/>"), "{out}");
        assert!(out.ends_with("</svg>"));
        assert!(inline_svg("<p>", "x").is_err());
    }

    #[test]
    fn a_page_has_contents_policy_and_sections() {
        let mut s = Section::new("one", "First & only");
        s.body.paragraph("text");
        let page =
            Page { title: "T <1>".into(), facts: vec!["fact".into()], sections: vec![s] }.render();
        assert!(page.starts_with("<!DOCTYPE html>\n<html lang=\"en\""));
        assert!(page.contains("<title>T &lt;1&gt;</title>"));
        assert!(page.contains("<a href=\"#one\">First &amp; only</a>"));
        assert!(page.contains("<section id=\"one\"><h2>First &amp; only</h2><p>text</p>"));
        assert!(page.contains("default-src &#39;none&#39;"));
    }
}
