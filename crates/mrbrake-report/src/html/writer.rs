//! A small HTML writer: elements with escaped text and attribute values, tables whose numeric
//! cells name the JSON value they show, and trusted inline SVG from mrbrake's own renderers.
//!
//! The output is polyglot HTML5: every element is closed, void elements are self-closed (`<br />`)
//! and only the five XML entities are used, so the page is also well-formed XML (the tests parse
//! it with an XML parser) while browsers read it as ordinary HTML.

use std::fmt::Write as _;

/// Escapes `text` for element content and double-quoted attribute values.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            // Control characters other than tab and newline are not allowed in XML 1.0.
            c if c.is_control() && c != '\n' && c != '\t' => out.push('\u{FFFD}'),
            c => out.push(c),
        }
    }
    out
}

/// `value` with `decimals` digits after the point; a non-finite value as [`UNDEFINED`].
pub fn fixed(value: f64, decimals: usize) -> String {
    if value.is_finite() { format!("{value:.decimals$}") } else { UNDEFINED.into() }
}

/// What a page shows for a number that is undefined (NaN or infinite, e.g. the dynamic range of
/// a brake whose off-state torque is zero): the JSON has `null` there (docs/CONVENTIONS.md), and
/// no page prints "inf" or "NaN" as if it were a value.
pub const UNDEFINED: &str = "—";

/// HTML being written: a string and the stack of open elements.
#[derive(Debug, Default)]
pub struct Html {
    out: String,
    open: Vec<&'static str>,
}

impl Html {
    /// An empty fragment.
    pub fn new() -> Self {
        Self::default()
    }

    /// Opens `<tag attrs…>`; attribute values are escaped.
    pub fn open(&mut self, tag: &'static str, attrs: &[(&str, &str)]) -> &mut Self {
        self.start_tag(tag, attrs, false);
        self.open.push(tag);
        self
    }

    /// Closes the innermost open element.
    pub fn close(&mut self) -> &mut Self {
        let tag = self.open.pop().expect("close() without a matching open()");
        let _ = write!(self.out, "</{tag}>");
        if matches!(tag, "section" | "table" | "tr" | "ul" | "li" | "p" | "figure" | "div") {
            self.out.push('\n');
        }
        self
    }

    /// Escaped text.
    pub fn text(&mut self, text: &str) -> &mut Self {
        self.out.push_str(&escape(text));
        self
    }

    /// `<tag attrs…>text</tag>`.
    pub fn element(&mut self, tag: &'static str, attrs: &[(&str, &str)], text: &str) -> &mut Self {
        self.open(tag, attrs).text(text).close()
    }

    /// A void element, self-closed: `<tag attrs… />`.
    pub fn void(&mut self, tag: &'static str, attrs: &[(&str, &str)]) -> &mut Self {
        self.start_tag(tag, attrs, true);
        self
    }

    /// Markup produced by mrbrake's own renderers (SVG documents of [`crate::chart`],
    /// [`crate::field_map`] and this module), inserted as is. Never pass user text here.
    pub fn trusted_markup(&mut self, markup: &str) -> &mut Self {
        self.out.push_str(markup);
        self
    }

    /// Appends another fragment (which must have closed all its elements).
    pub fn append(&mut self, other: Html) -> &mut Self {
        self.out.push_str(&other.finish());
        self
    }

    /// A paragraph of escaped text.
    pub fn paragraph(&mut self, text: &str) -> &mut Self {
        self.element("p", &[], text)
    }

    /// A table (see [`Table`]).
    pub fn table(&mut self, table: &Table) -> &mut Self {
        table.write(self);
        self
    }

    /// The markup written; every opened element must be closed.
    pub fn finish(self) -> String {
        assert!(self.open.is_empty(), "unclosed elements: {:?}", self.open);
        self.out
    }

    fn start_tag(&mut self, tag: &str, attrs: &[(&str, &str)], void: bool) {
        let _ = write!(self.out, "<{tag}");
        for (name, value) in attrs {
            let _ = write!(self.out, " {name}=\"{}\"", escape(value));
        }
        self.out.push_str(if void { " />" } else { ">" });
    }
}

/// A table cell: text, or a number tied to the JSON value it shows.
#[derive(Debug, Clone, PartialEq)]
pub enum Cell {
    /// Plain text (escaped).
    Text(String),
    /// A number: the displayed text and, when the number is a value of the report's JSON, the
    /// JSON pointer to it and the display scale (displayed = JSON value × scale, e.g. 1000 for a
    /// length in metres shown in mm). Written as `data-json` and `data-scale` attributes so that a
    /// test can check every displayed number against the JSON.
    Number {
        /// The displayed number.
        text: String,
        /// JSON pointer (RFC 6901) into the report's JSON document.
        pointer: Option<String>,
        /// Display scale.
        scale: f64,
    },
    /// A link to an anchor or a file (the text is escaped).
    Link {
        /// The link text.
        text: String,
        /// The target, e.g. `#front-01`.
        href: String,
    },
}

impl Cell {
    /// A text cell.
    pub fn text(text: impl Into<String>) -> Self {
        Cell::Text(text.into())
    }

    /// A number not taken from the JSON (a thesis value, a ratio computed for the page).
    pub fn number(value: f64, decimals: usize) -> Self {
        Cell::Number { text: fixed(value, decimals), pointer: None, scale: 1.0 }
    }

    /// `value × scale` with `decimals` digits; `value` is the JSON value at `pointer`.
    pub fn json(value: f64, decimals: usize, pointer: impl Into<String>, scale: f64) -> Self {
        Cell::Number { text: fixed(value * scale, decimals), pointer: Some(pointer.into()), scale }
    }

    /// A link.
    pub fn link(text: impl Into<String>, href: impl Into<String>) -> Self {
        Cell::Link { text: text.into(), href: href.into() }
    }

    fn write(&self, html: &mut Html, tag: &'static str) {
        match self {
            Cell::Text(t) => _ = html.element(tag, &[], t),
            Cell::Number { text, pointer: Some(p), scale } => {
                let scale = format!("{scale}");
                html.element(
                    tag,
                    &[("class", "num"), ("data-json", p), ("data-scale", &scale)],
                    text,
                );
            }
            Cell::Number { text, pointer: None, .. } => {
                html.element(tag, &[("class", "num")], text);
            }
            Cell::Link { text, href } => {
                html.open(tag, &[]).element("a", &[("href", href)], text).close();
            }
        }
    }
}

/// A table with a caption, a header row and rows of cells.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Table {
    /// Caption above the table.
    pub caption: String,
    /// Column titles (with units).
    pub headers: Vec<String>,
    /// Rows; the first cell of a row is written as its header (`<th scope="row">`).
    pub rows: Vec<Vec<Cell>>,
}

impl Table {
    /// An empty table with a caption and column titles.
    pub fn new(caption: impl Into<String>, headers: &[&str]) -> Self {
        Self {
            caption: caption.into(),
            headers: headers.iter().map(|h| h.to_string()).collect(),
            rows: Vec::new(),
        }
    }

    /// Adds a row.
    pub fn row(&mut self, cells: Vec<Cell>) -> &mut Self {
        self.rows.push(cells);
        self
    }

    fn write(&self, html: &mut Html) {
        html.open("table", &[]);
        if !self.caption.is_empty() {
            html.element("caption", &[], &self.caption);
        }
        html.open("thead", &[]).open("tr", &[]);
        for h in &self.headers {
            html.element("th", &[("scope", "col")], h);
        }
        html.close().close().open("tbody", &[]);
        for row in &self.rows {
            html.open("tr", &[]);
            for (k, cell) in row.iter().enumerate() {
                cell.write(html, if k == 0 { "th" } else { "td" });
            }
            html.close();
        }
        html.close().close();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_and_attributes_are_escaped() {
        let mut h = Html::new();
        h.open("p", &[("title", "a \"b\" <c> & 'd'")]).text("x < y && z > 1").close();
        assert_eq!(
            h.finish(),
            "<p title=\"a &quot;b&quot; &lt;c&gt; &amp; &#39;d&#39;\">x &lt; y &amp;&amp; z &gt; 1</p>\n"
        );
        assert_eq!(escape("bell\u{7}"), "bell\u{FFFD}");
    }

    #[test]
    fn numbers_name_their_json_value() {
        assert_eq!(fixed(f64::NAN, 2), UNDEFINED);
        assert_eq!(fixed(f64::NEG_INFINITY, 2), UNDEFINED);
        assert_eq!(fixed(0.123456, 3), "0.123");
        let mut t = Table::new("c", &["what", "r [mm]"]);
        t.row(vec![Cell::text("gap"), Cell::json(0.0255, 2, "/gaps/0/r_m", 1e3)]);
        let mut h = Html::new();
        h.table(&t);
        let out = h.finish();
        assert!(
            out.contains(
                "<th>gap</th><td class=\"num\" data-json=\"/gaps/0/r_m\" data-scale=\"1000\">25.50</td>"
            ),
            "{out}"
        );
    }

    #[test]
    #[should_panic(expected = "unclosed elements")]
    fn an_unclosed_element_is_a_bug() {
        let mut h = Html::new();
        h.open("div", &[]);
        let _ = h.finish();
    }
}
