//! Generic XY charts: line and scatter series on linear or logarithmic axes, in one or several stacked
//! panels, rendered to SVG (or PNG when the file name ends in `.png`).
//!
//! The domain plots (Bode diagram, hysteresis loop, torque–current curve, haptic time histories) are
//! built from a [`Figure`] of [`Panel`]s so they all look alike.
//!
//! ```
//! use mrbrake_report::chart::{Figure, Panel, Series};
//! let fig = Figure::new("Torque–current").panel(
//!     Panel::new("current [A]", "torque [N·m]")
//!         .series(Series::line("T(I)", vec![(0.0, 0.15), (1.0, 2.1), (2.0, 3.84)])),
//! );
//! let svg = fig.to_svg().unwrap();
//! assert!(svg.starts_with("<svg"));
//! ```

use std::path::Path;
use std::sync::Once;

use plotters::coord::Shift;
use plotters::element::ComposedElement;
pub use plotters::prelude::SeriesLabelPosition;
use plotters::prelude::*;

use crate::ReportError;

/// The font used for all text: DejaVu Sans (Bitstream Vera licence, see `fonts/LICENSE-DejaVu.txt`),
/// embedded so that a plot renders the same on any machine without system fonts.
static FONT: &[u8] = include_bytes!("../fonts/DejaVuSans.ttf");
static REGISTER_FONT: Once = Once::new();

/// Registers the embedded font with plotters once per process (every plot module calls this).
pub(crate) fn ensure_font() {
    REGISTER_FONT.call_once(|| {
        // The embedded font is a valid TrueType file; failing here would be a build defect.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mark {
    /// A polyline through the points in order.
    Line,
    /// A dashed polyline (reference curves, limits).
    Dashed,
    /// A circle at each point.
    Points,
    /// A polyline with a circle at each point.
    LinePoints,
    /// A translucent filled polygon through the points, closed back to the first (a band: its
    /// upper edge left to right, then its lower edge right to left).
    Area,
}

/// A named set of (x, y) points.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend label (empty: no legend entry).
    pub label: String,
    /// The points, in drawing order.
    pub points: Vec<(f64, f64)>,
    /// How the points are drawn.
    pub mark: Mark,
    /// Colour index into the palette (None: the series' position in the panel).
    pub color: Option<usize>,
    /// Marker shape of [`Mark::Points`] and [`Mark::LinePoints`].
    pub shape: Shape,
    /// Marker radius in pixels.
    pub marker_size: u32,
    /// Line width in pixels.
    pub line_width: u32,
}

/// The marker drawn at each point of a point series: shapes that stay apart in grey print and for
/// colour-blind readers, not only colours.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Shape {
    /// A filled circle.
    #[default]
    Circle,
    /// An open circle (the points under it stay visible).
    Ring,
    /// A filled triangle.
    Triangle,
    /// A diagonal cross.
    Cross,
}

impl Series {
    /// A solid line.
    pub fn line(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::with_mark(label.into(), points, Mark::Line)
    }
    /// A dashed line.
    pub fn dashed(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::with_mark(label.into(), points, Mark::Dashed)
    }
    /// Markers only.
    pub fn points(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::with_mark(label.into(), points, Mark::Points)
    }
    /// A translucent filled polygon (see [`Mark::Area`]).
    pub fn area(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::with_mark(label.into(), points, Mark::Area)
    }
    /// A line with markers.
    pub fn line_points(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::with_mark(label.into(), points, Mark::LinePoints)
    }
    fn with_mark(label: String, points: Vec<(f64, f64)>, mark: Mark) -> Self {
        Self {
            label,
            points,
            mark,
            color: None,
            shape: Shape::Circle,
            marker_size: 3,
            line_width: 2,
        }
    }
    /// Sets the palette colour index.
    pub fn color(mut self, index: usize) -> Self {
        self.color = Some(index);
        self
    }
    /// Sets the marker shape.
    pub fn shape(mut self, shape: Shape) -> Self {
        self.shape = shape;
        self
    }
    /// Sets the marker radius in pixels.
    pub fn marker_size(mut self, pixels: u32) -> Self {
        self.marker_size = pixels;
        self
    }
    /// Sets the line width in pixels.
    pub fn line_width(mut self, pixels: u32) -> Self {
        self.line_width = pixels;
        self
    }
}

/// Axis scale.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Scale {
    /// Linear axis.
    #[default]
    Linear,
    /// Base-10 logarithmic axis (all values must be positive).
    Log,
}

/// One plotting area with its axes and series.
#[derive(Clone)]
pub struct Panel {
    /// Optional panel caption.
    pub caption: String,
    /// X-axis label with unit.
    pub x_label: String,
    /// Y-axis label with unit.
    pub y_label: String,
    /// X scale.
    pub x_scale: Scale,
    /// Y scale.
    pub y_scale: Scale,
    /// Fixed x range (None: from the data).
    pub x_range: Option<(f64, f64)>,
    /// Fixed y range (None: from the data, with a margin).
    pub y_range: Option<(f64, f64)>,
    /// The series drawn in this panel.
    pub series: Vec<Series>,
    /// Where the legend box goes.
    pub legend: SeriesLabelPosition,
    /// A panel without axes that only shows this text (e.g. why a device has no such trace).
    pub note: Option<String>,
}

impl Panel {
    /// A panel with axis labels and no series yet.
    pub fn new(x_label: impl Into<String>, y_label: impl Into<String>) -> Self {
        Self {
            caption: String::new(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            x_range: None,
            y_range: None,
            series: Vec::new(),
            legend: SeriesLabelPosition::UpperLeft,
            note: None,
        }
    }
    /// A panel with a caption and a centred note instead of axes (keeps a grid of panels aligned
    /// where one cell has nothing to plot).
    pub fn note(caption: impl Into<String>, text: impl Into<String>) -> Self {
        let mut panel = Self::new("", "").caption(caption);
        panel.note = Some(text.into());
        panel
    }
    /// Moves the legend (e.g. `SeriesLabelPosition::LowerRight`) away from the data.
    pub fn legend(mut self, position: SeriesLabelPosition) -> Self {
        self.legend = position;
        self
    }
    /// Sets the caption.
    pub fn caption(mut self, caption: impl Into<String>) -> Self {
        self.caption = caption.into();
        self
    }
    /// Adds a series.
    pub fn series(mut self, series: Series) -> Self {
        self.series.push(series);
        self
    }
    /// Logarithmic x axis.
    pub fn log_x(mut self) -> Self {
        self.x_scale = Scale::Log;
        self
    }
    /// Logarithmic y axis.
    pub fn log_y(mut self) -> Self {
        self.y_scale = Scale::Log;
        self
    }
    /// Fixes the x range.
    pub fn x_range(mut self, lo: f64, hi: f64) -> Self {
        self.x_range = Some((lo, hi));
        self
    }
    /// Fixes the y range.
    pub fn y_range(mut self, lo: f64, hi: f64) -> Self {
        self.y_range = Some((lo, hi));
        self
    }

    /// The points of `series` that can be drawn on this panel's axes: finite, and positive on a
    /// logarithmic axis.
    fn drawable_points(&self, series: &Series) -> Vec<(f64, f64)> {
        series
            .points
            .iter()
            .copied()
            .filter(|(x, y)| {
                x.is_finite()
                    && y.is_finite()
                    && (self.x_scale == Scale::Linear || *x > 0.0)
                    && (self.y_scale == Scale::Linear || *y > 0.0)
            })
            .collect()
    }

    fn data_range(&self, axis: usize, scale: Scale) -> Result<(f64, f64), ReportError> {
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for s in &self.series {
            for p in &s.points {
                let v = if axis == 0 { p.0 } else { p.1 };
                if !v.is_finite() || (scale == Scale::Log && v <= 0.0) {
                    continue;
                }
                lo = lo.min(v);
                hi = hi.max(v);
            }
        }
        if !lo.is_finite() || !hi.is_finite() {
            return Err(ReportError::Data(format!(
                "panel '{}' has no finite{} {} values",
                if self.caption.is_empty() { &self.y_label } else { &self.caption },
                if scale == Scale::Log { " positive" } else { "" },
                if axis == 0 { "x" } else { "y" }
            )));
        }
        Ok(pad_range(lo, hi, scale, axis == 1))
    }
}

/// Widens a data range so that the curve does not touch the frame, and a flat range gets a height.
fn pad_range(lo: f64, hi: f64, scale: Scale, pad: bool) -> (f64, f64) {
    match scale {
        Scale::Log => {
            if hi / lo < 1.0 + 1e-9 {
                (lo / 2.0, hi * 2.0)
            } else if pad {
                (lo / 1.2, hi * 1.2)
            } else {
                (lo, hi)
            }
        }
        Scale::Linear => {
            let span = hi - lo;
            if span <= 1e-12 * (1.0 + hi.abs()) {
                let d = if hi.abs() > 0.0 { 0.1 * hi.abs() } else { 1.0 };
                (lo - d, hi + d)
            } else if pad {
                (lo - 0.05 * span, hi + 0.05 * span)
            } else {
                (lo, hi)
            }
        }
    }
}

/// A whole picture: a title and panels laid out in a grid.
#[derive(Clone)]
pub struct Figure {
    /// Title over the figure.
    pub title: String,
    /// Panels, filled row by row.
    pub panels: Vec<Panel>,
    /// Number of panel columns (rows follow from the panel count).
    pub columns: usize,
    /// Pixel size (width, height).
    pub size: (u32, u32),
    /// Relative heights of the panel rows (empty: equal rows).
    pub row_weights: Vec<f64>,
}

impl Figure {
    /// An empty figure, 900 × 600 pixels, one column.
    pub fn new(title: impl Into<String>) -> Self {
        Self {
            title: title.into(),
            panels: Vec::new(),
            columns: 1,
            size: (900, 600),
            row_weights: Vec::new(),
        }
    }
    /// Adds a panel.
    pub fn panel(mut self, panel: Panel) -> Self {
        self.panels.push(panel);
        self
    }
    /// Sets the number of panel columns.
    pub fn columns(mut self, columns: usize) -> Self {
        self.columns = columns.max(1);
        self
    }
    /// Sets the size in pixels.
    pub fn size(mut self, width: u32, height: u32) -> Self {
        self.size = (width, height);
        self
    }
    /// Sets the relative heights of the panel rows (e.g. `[3.0, 1.0]`: a main panel over a
    /// residual panel a third as tall).
    pub fn row_weights(mut self, weights: Vec<f64>) -> Self {
        self.row_weights = weights;
        self
    }

    /// Renders the figure as an SVG document.
    pub fn to_svg(&self) -> Result<String, ReportError> {
        render_svg(self)
    }

    /// Renders the figure as a PNG image in memory (for figures with too many points to inline
    /// as SVG, such as a log's raw samples).
    pub fn to_png(&self) -> Result<Vec<u8>, ReportError> {
        render_png(self)
    }

    /// Writes the figure to `path` atomically: PNG for a `.png` name, SVG for `.svg`; any other
    /// extension is [`ReportError::PlotFormat`].
    pub fn save(&self, path: &Path) -> Result<(), ReportError> {
        save_picture(self, path)
    }
}

impl Picture for Figure {
    fn size(&self) -> (u32, u32) {
        self.size
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), ReportError> {
        ensure_font();
        let be = |e: DrawingAreaErrorKind<DB::ErrorType>| ReportError::Backend(e.to_string());
        if self.panels.is_empty() {
            return Err(ReportError::Data(format!("figure '{}' has no panel", self.title)));
        }
        root.fill(&WHITE).map_err(be)?;
        let area = if self.title.is_empty() {
            root.clone()
        } else {
            let (title, size) = fit_title(root, &self.title, 22);
            root.titled(&title, ("sans-serif", size)).map_err(be)?
        };
        let rows = self.panels.len().div_ceil(self.columns);
        let row_areas = area.split_by_breakpoints(
            Vec::<i32>::new(),
            row_breakpoints(&self.row_weights, rows, area.dim_in_pixel().1),
        );
        let areas = row_areas.iter().flat_map(|row| row.split_evenly((1, self.columns)));
        for (panel, sub) in self.panels.iter().zip(areas) {
            draw_panel(panel, &sub)?;
        }
        Ok(())
    }
}

/// A title that fits the width of `area`, and its font size: at `size` px if it fits, else smaller
/// (down to 60 % of `size`), else at that size shortened in the middle with `…` (a design's name
/// can be long; plotters centres a title and would clip it on both sides).
pub(crate) fn fit_title<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    size: u32,
) -> (String, u32) {
    ensure_font();
    let room = area.dim_in_pixel().0.saturating_sub(16);
    let width = |text: &str, size: u32| {
        area.estimate_text_size(text, &TextStyle::from(("sans-serif", size).into_font()))
            .map_or(u32::MAX, |s| s.0)
    };
    let smallest = (size * 3).div_ceil(5).max(1);
    for s in (smallest..=size).rev() {
        if width(title, s) <= room {
            return (title.to_string(), s);
        }
    }
    let chars: Vec<char> = title.chars().collect();
    let mut keep = chars.len();
    while keep > 2 {
        keep -= 1;
        let head: String = chars[..keep.div_ceil(2)].iter().collect();
        let tail: String = chars[chars.len() - keep / 2..].iter().collect();
        let shortened = format!("{}…{}", head.trim_end(), tail.trim_start());
        if width(&shortened, smallest) <= room {
            return (shortened, smallest);
        }
    }
    ("…".to_string(), smallest)
}

/// The pixel rows at which `rows` panel rows of `height` pixels split, in proportion to `weights`
/// (equal rows where a weight is missing or not positive).
fn row_breakpoints(weights: &[f64], rows: usize, height: u32) -> Vec<i32> {
    let weight = |k: usize| weights.get(k).copied().filter(|w| *w > 0.0).unwrap_or(1.0);
    let total: f64 = (0..rows).map(weight).sum();
    let mut at = 0.0;
    (0..rows.saturating_sub(1))
        .map(|k| {
            at += weight(k) / total;
            (at * f64::from(height)).round() as i32
        })
        .collect()
}

/// Something drawn on any plotters backend at a fixed pixel size (a [`Figure`], a field map), so
/// that one function renders it as SVG and one saves it as SVG or PNG.
pub(crate) trait Picture {
    /// Width and height in pixels.
    fn size(&self) -> (u32, u32);
    /// Draws the whole picture on `root`.
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), ReportError>;
}

/// The SVG document of `picture`.
pub(crate) fn render_svg(picture: &impl Picture) -> Result<String, ReportError> {
    let mut buf = String::new();
    {
        let root = SVGBackend::with_string(&mut buf, picture.size()).into_drawing_area();
        picture.draw(&root)?;
        root.present().map_err(|e| ReportError::Backend(e.to_string()))?;
    }
    Ok(buf)
}

/// The PNG image (8-bit RGB) of `picture`, in memory (for `data:` URLs in the HTML reports).
pub(crate) fn render_png(picture: &impl Picture) -> Result<Vec<u8>, ReportError> {
    let (w, h) = picture.size();
    let mut rgb = vec![0u8; w as usize * h as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        picture.draw(&root)?;
        root.present().map_err(|e| ReportError::Backend(e.to_string()))?;
    }
    let backend = |e: png::EncodingError| ReportError::Backend(format!("PNG encoding: {e}"));
    let mut out = Vec::new();
    let mut encoder = png::Encoder::new(&mut out, w, h);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().map_err(backend)?;
    writer.write_image_data(&rgb).map_err(backend)?;
    writer.finish().map_err(backend)?;
    Ok(out)
}

/// Writes `picture` to `path` atomically: PNG for a `.png` name, SVG for `.svg`; any other
/// extension is [`ReportError::PlotFormat`].
pub(crate) fn save_picture(picture: &impl Picture, path: &Path) -> Result<(), ReportError> {
    let is_png =
        crate::plot_format::PlotFormat::from_path(path)? == crate::plot_format::PlotFormat::Png;
    if !is_png {
        return crate::write_atomic(path, render_svg(picture)?.as_bytes());
    }
    // The bitmap backend encodes by file name, so it renders into the temporary .png that
    // `write_atomic_with` puts in place (renamed beside the target, or copied into a FIFO/device).
    let mut drawing_error = None;
    let written = crate::atomic::write_atomic_with(path, |tmp| {
        let root = BitMapBackend::new(tmp, picture.size()).into_drawing_area();
        let drawn = picture
            .draw(&root)
            .and_then(|()| root.present().map_err(|e| ReportError::Backend(e.to_string())));
        drawn.map_err(|e| {
            let message = e.to_string();
            drawing_error = Some(e);
            std::io::Error::other(message)
        })
    });
    match drawing_error {
        Some(e) => Err(e),
        None => written,
    }
}

/// Opacity of a [`Mark::Area`] fill: the lines and grid under a band stay visible.
const AREA_ALPHA: f64 = 0.25;

/// The palette index of a neutral grey (context data drawn under the series that matter).
pub const GREY: usize = 8;

/// Palette: distinguishable colours (Okabe–Ito, colour-blind safe), a neutral grey ([`GREY`]),
/// then plotters' Palette99.
pub fn palette(index: usize) -> RGBColor {
    const OKABE_ITO: [RGBColor; 8] = [
        RGBColor(0, 114, 178),
        RGBColor(213, 94, 0),
        RGBColor(0, 158, 115),
        RGBColor(204, 121, 167),
        RGBColor(230, 159, 0),
        RGBColor(86, 180, 233),
        RGBColor(0, 0, 0),
        RGBColor(240, 228, 66),
    ];
    if index < OKABE_ITO.len() {
        OKABE_ITO[index]
    } else if index == GREY {
        RGBColor(150, 150, 150)
    } else {
        let c = Palette99::pick(index).to_rgba();
        RGBColor(c.0, c.1, c.2)
    }
}

fn draw_panel<DB: DrawingBackend>(
    panel: &Panel,
    area: &DrawingArea<DB, Shift>,
) -> Result<(), ReportError> {
    let be = |e: DrawingAreaErrorKind<DB::ErrorType>| ReportError::Backend(e.to_string());
    if let Some(note) = &panel.note {
        return draw_note(panel, note, area).map_err(be);
    }
    let (x0, x1) = match panel.x_range {
        Some(r) => r,
        None => panel.data_range(0, panel.x_scale)?,
    };
    let (y0, y1) = match panel.y_range {
        Some(r) => r,
        None => panel.data_range(1, panel.y_scale)?,
    };
    let span = |lo: f64, hi: f64, scale: Scale| if scale == Scale::Linear { hi - lo } else { 0.0 };
    let (x_span, y_span) = (span(x0, x1, panel.x_scale), span(y0, y1, panel.y_scale));
    // The four scale combinations are four chart types in plotters; a macro keeps the axes one body.
    macro_rules! with_chart {
        ($xr:expr, $yr:expr) => {{
            let mut builder = ChartBuilder::on(area);
            // The right margin leaves room for the last x tick label, centred on the frame's edge.
            builder.margin(12).margin_right(30).x_label_area_size(42).y_label_area_size(64);
            if !panel.caption.is_empty() {
                builder.caption(&panel.caption, ("sans-serif", 17));
            }
            let mut chart = builder.build_cartesian_2d($xr, $yr).map_err(be)?;
            chart
                .configure_mesh()
                .x_desc(panel.x_label.as_str())
                .y_desc(panel.y_label.as_str())
                .x_label_formatter(&|v| tick_label(snap_zero(*v, x_span)))
                .y_label_formatter(&|v| tick_label(snap_zero(*v, y_span)))
                .label_style(("sans-serif", 13))
                .light_line_style(RGBColor(235, 235, 235))
                .draw()
                .map_err(be)?;
            draw_series(&mut chart, panel)
        }};
    }
    let log = |lo: f64, hi: f64| {
        let (major, minor) = log_ticks(lo, hi);
        (lo..hi).log_scale().with_key_points(major).with_light_points(minor)
    };
    match (panel.x_scale, panel.y_scale) {
        (Scale::Linear, Scale::Linear) => with_chart!(x0..x1, y0..y1),
        (Scale::Log, Scale::Linear) => with_chart!(log(x0, x1), y0..y1),
        (Scale::Linear, Scale::Log) => with_chart!(x0..x1, log(y0, y1)),
        (Scale::Log, Scale::Log) => with_chart!(log(x0, x1), log(y0, y1)),
    }
}

/// A panel that shows only its caption and a centred note.
fn draw_note<DB: DrawingBackend>(
    panel: &Panel,
    note: &str,
    area: &DrawingArea<DB, Shift>,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let area = if panel.caption.is_empty() {
        area.clone()
    } else {
        area.titled(&panel.caption, ("sans-serif", 17))?
    };
    let (w, h) = area.dim_in_pixel();
    let style = TextStyle::from(("sans-serif", 14).into_font())
        .color(&RGBColor(110, 110, 110))
        .pos(plotters::style::text_anchor::Pos::new(
            plotters::style::text_anchor::HPos::Center,
            plotters::style::text_anchor::VPos::Center,
        ));
    area.draw_text(note, &style, (w as i32 / 2, h as i32 / 2))
}

/// `v`, or 0 where it is rounding noise on an axis spanning `span` (a tick at -1e-17 is a 0).
fn snap_zero(v: f64, span: f64) -> f64 {
    if v.abs() < 1e-9 * span.abs() { 0.0 } else { v }
}

/// A tick label without float noise or a needless `.0` (`1000`, `0.1`, `-0.25`, `1e-5`).
pub fn tick_label(v: f64) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    if v.abs() < 1e-300 {
        return "0".into();
    }
    let magnitude = v.abs().log10().floor();
    if !(-4.0..6.0).contains(&magnitude) {
        return format!("{v:.1e}").replace(".0e", "e");
    }
    // Ten significant digits remove the noise of 0.1 + 0.2; Display drops trailing zeros.
    let scale = 10f64.powi(9 - magnitude as i32);
    format!("{}", (v * scale).round() / scale)
}

/// Tick values of a logarithmic axis from `lo` to `hi`: a labelled tick at every decade (and at
/// 2 and 5 times each decade when the range spans less than two decades), a light grid line at
/// every other integer multiple of a decade.
pub fn log_ticks(lo: f64, hi: f64) -> (Vec<f64>, Vec<f64>) {
    let (first, last) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    let inside = |v: &f64| *v >= lo * (1.0 - 1e-9) && *v <= hi * (1.0 + 1e-9);
    let decades: Vec<f64> = (first..=last).map(|d| 10f64.powi(d)).collect();
    let multiples = |ks: &[f64]| -> Vec<f64> {
        decades.iter().flat_map(|&d| ks.iter().map(move |k| k * d)).filter(inside).collect()
    };
    let major_decades: Vec<f64> = decades.iter().copied().filter(inside).collect();
    if major_decades.len() >= 3 {
        (major_decades, multiples(&[2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]))
    } else {
        (multiples(&[1.0, 2.0, 5.0]), multiples(&[3.0, 4.0, 6.0, 7.0, 8.0, 9.0]))
    }
}

/// Draws the panel's series on `chart` (axes already drawn), then the legend of the labelled ones.
fn draw_series<'a, DB: DrawingBackend + 'a, CT: CoordTranslate<From = (f64, f64)>>(
    chart: &mut ChartContext<'a, DB, CT>,
    panel: &Panel,
) -> Result<(), ReportError> {
    let be = |e: DrawingAreaErrorKind<DB::ErrorType>| ReportError::Backend(e.to_string());
    let mut any_label = false;
    for (i, s) in panel.series.iter().enumerate() {
        let color = palette(s.color.unwrap_or(i));
        let pts = panel.drawable_points(s);
        let style = ShapeStyle::from(&color).stroke_width(s.line_width);
        let (shape, size) = (s.shape, s.marker_size);
        let anno = match s.mark {
            Mark::Line => {
                chart.draw_series(LineSeries::new(pts.iter().copied(), style)).map_err(be)?
            }
            Mark::LinePoints => {
                draw_markers(chart, &pts, shape, size, color).map_err(be)?;
                chart.draw_series(LineSeries::new(pts.iter().copied(), style)).map_err(be)?
            }
            Mark::Dashed => chart
                .draw_series(DashedLineSeries::new(pts.iter().copied(), 6, 4, style))
                .map_err(be)?,
            Mark::Points => draw_markers(chart, &pts, shape, size, color).map_err(be)?,
            Mark::Area => chart
                .draw_series(std::iter::once(Polygon::new(
                    pts.clone(),
                    color.mix(AREA_ALPHA).filled(),
                )))
                .map_err(be)?,
        };
        if !s.label.is_empty() {
            any_label = true;
            let mark = s.mark;
            anno.label(s.label.as_str()).legend(move |(x, y)| legend_key(mark, shape, color, x, y));
        }
    }
    if any_label {
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.9))
            .border_style(RGBColor(180, 180, 180))
            .label_font(("sans-serif", 13))
            .position(panel.legend.clone())
            .draw()
            .map_err(be)?;
    }
    Ok(())
}

/// Markers of `shape` and radius `size` at `pts`.
fn draw_markers<'a, 'c, DB: DrawingBackend + 'a, CT: CoordTranslate<From = (f64, f64)>>(
    chart: &'c mut ChartContext<'a, DB, CT>,
    pts: &[(f64, f64)],
    shape: Shape,
    size: u32,
    color: RGBColor,
) -> Result<&'c mut plotters::chart::SeriesAnno<'a, DB>, DrawingAreaErrorKind<DB::ErrorType>> {
    let r = size as i32;
    let at = |p: (f64, f64)| EmptyElement::at(p);
    let cross = |p| {
        at(p)
            + PathElement::new(vec![(-r, -r), (r, r)], color.stroke_width(2))
            + PathElement::new(vec![(-r, r), (r, -r)], color.stroke_width(2))
    };
    let triangle = |p| at(p) + Polygon::new(vec![(0, -r - 1), (r + 1, r), (-r - 1, r)], color);
    match shape {
        Shape::Circle => {
            chart.draw_series(pts.iter().map(|&p| Circle::new(p, size, color.filled())))
        }
        Shape::Ring => {
            chart.draw_series(pts.iter().map(|&p| Circle::new(p, size, color.stroke_width(1))))
        }
        Shape::Triangle => chart.draw_series(pts.iter().map(|&p| triangle(p))),
        Shape::Cross => chart.draw_series(pts.iter().map(|&p| cross(p))),
    }
}

/// An element of two parts in pixel coordinates.
type Composed<DB, A, B> = ComposedElement<(i32, i32), DB, A, B>;
/// A polyline in pixel coordinates.
type PixelPath = PathElement<(i32, i32)>;
/// A line and a circle marker (the inner parts of [`LegendKey`], in the order they are added).
type LineAndCircle<DB> = Composed<DB, PixelPath, Circle<(i32, i32), u32>>;
/// A legend key: two line pieces, a circle, a triangle and the two strokes of a cross.
type LegendKey<DB> = Composed<
    DB,
    PixelPath,
    Composed<
        DB,
        Composed<DB, Composed<DB, LineAndCircle<DB>, Polygon<(i32, i32)>>, PixelPath>,
        PixelPath,
    >,
>;

/// The legend key of a series at `(x, y)`: its marker for points, a line (with its marker)
/// otherwise. One element type for every kind (plotters' legend wants a concrete element): the
/// parts a kind does not use are transparent.
fn legend_key<DB: DrawingBackend>(
    mark: Mark,
    shape: Shape,
    color: RGBColor,
    x: i32,
    y: i32,
) -> LegendKey<DB> {
    let none = ShapeStyle::from(&TRANSPARENT);
    let stroke = color.stroke_width(2);
    let (first, second) = match mark {
        // A band's key: a thick stroke of its translucent fill.
        Mark::Area => ((9, color.mix(AREA_ALPHA).stroke_width(8)), none),
        Mark::Line | Mark::LinePoints => ((9, stroke), none),
        Mark::Dashed => ((-3, stroke), stroke),
        Mark::Points => ((9, none), none),
    };
    let glyph = matches!(mark, Mark::Points | Mark::LinePoints);
    let pick =
        |wanted: Shape, style: ShapeStyle| if glyph && shape == wanted { style } else { none };
    let circle = match shape {
        Shape::Ring => pick(Shape::Ring, color.stroke_width(1)),
        _ => pick(Shape::Circle, color.filled()),
    };
    let r = 4;
    EmptyElement::at((x + 9, y))
        + PathElement::new(vec![(-9, 0), (first.0, 0)], first.1)
        + PathElement::new(vec![(2, 0), (9, 0)], second)
        + Circle::new((0, 0), r as u32, circle)
        + Polygon::new(
            vec![(0, -r - 1), (r + 1, r), (-r - 1, r)],
            pick(Shape::Triangle, color.filled()),
        )
        + PathElement::new(vec![(-r, -r), (r, r)], pick(Shape::Cross, stroke))
        + PathElement::new(vec![(-r, r), (r, -r)], pick(Shape::Cross, stroke))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A title too long for its figure is shrunk, then shortened in the middle, never clipped;
    /// a short one is left alone.
    #[test]
    fn long_titles_fit_their_figure() {
        let long = format!(
            "{}: torque–current curve",
            "front design 17 of the thesis requirement study ".repeat(3)
        );
        let figure = Figure::new(long.clone())
            .panel(Panel::new("x", "y").series(Series::line("a", vec![(0.0, 0.0), (1.0, 1.0)])));
        let svg = figure.to_svg().unwrap();
        assert!(svg.contains('…') && svg.contains("torque–current curve"), "the end is kept");
        let mut buf = String::new();
        let root = SVGBackend::with_string(&mut buf, (900, 600)).into_drawing_area();
        let (title, size) = fit_title(&root, &long, 22);
        let width = root
            .estimate_text_size(&title, &TextStyle::from(("sans-serif", size).into_font()))
            .unwrap()
            .0;
        assert!(width <= 900 && size < 22, "{width} px at {size}");
        assert_eq!(fit_title(&root, "short", 22), ("short".to_string(), 22));
    }

    fn sample() -> Figure {
        Figure::new("test")
            .panel(
                Panel::new("ω [rad/s]", "gain [dB]")
                    .log_x()
                    .series(Series::points(
                        "measured",
                        vec![(0.1, 0.0), (10.0, -1.0), (1000.0, -40.0)],
                    ))
                    .series(Series::line("model", vec![(0.1, 0.0), (10.0, -1.2), (1000.0, -41.0)])),
            )
            .panel(
                Panel::new("ω [rad/s]", "phase [°]")
                    .log_x()
                    .series(Series::dashed("", vec![(0.1, 0.0), (1000.0, -170.0)])),
            )
    }

    #[test]
    fn renders_svg_with_labels() {
        let svg = sample().to_svg().unwrap();
        assert!(svg.contains("gain [dB]"));
        assert!(svg.contains("measured"));
    }

    #[test]
    fn saves_png_and_svg_atomically() {
        let dir = tempfile::tempdir().unwrap();
        for name in ["fig.png", "fig.svg"] {
            let p = dir.path().join(name);
            sample().save(&p).unwrap();
            let bytes = std::fs::read(&p).unwrap();
            assert!(bytes.len() > 1000, "{name} too small");
        }
        let png = std::fs::read(dir.path().join("fig.png")).unwrap();
        assert_eq!(&png[1..4], b"PNG");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2, "no temporary files left");
    }

    #[test]
    fn tick_labels_and_log_ticks() {
        assert_eq!(tick_label(1000.0), "1000");
        assert_eq!(tick_label(0.1 + 0.2), "0.3");
        assert_eq!(tick_label(-0.25), "-0.25");
        assert_eq!(tick_label(snap_zero(-1e-17, 1.0)), "0");
        assert_eq!(tick_label(2.5e-6), "2.5e-6");
        // A label at every decade of a Bode axis, 0.1 to 1000 rad/s.
        let (major, minor) = log_ticks(0.1, 1000.0);
        let expected = [0.1, 1.0, 10.0, 100.0, 1000.0];
        assert_eq!(major.len(), expected.len());
        assert!(major.iter().zip(expected).all(|(a, b)| (a / b - 1.0).abs() < 1e-12), "{major:?}");
        assert_eq!(minor.len(), 4 * 8);
        // Less than two decades: 1-2-5 steps.
        let (major, _) = log_ticks(3.0, 60.0);
        assert_eq!(
            major.iter().map(|v| tick_label(*v)).collect::<Vec<_>>(),
            ["5", "10", "20", "50"]
        );
    }

    #[test]
    fn row_weights_split_the_height() {
        assert_eq!(row_breakpoints(&[3.0, 1.0], 2, 800), vec![600]);
        assert_eq!(row_breakpoints(&[], 3, 900), vec![300, 600]);
    }

    #[test]
    fn markers_and_notes_render() {
        let fig = Figure::new("shapes")
            .columns(2)
            .panel(
                Panel::new("x", "y")
                    .series(Series::points("ring", vec![(0.0, 1.0)]).shape(Shape::Ring))
                    .series(Series::points("triangle", vec![(1.0, 2.0)]).shape(Shape::Triangle))
                    .series(Series::points("cross", vec![(2.0, 3.0)]).shape(Shape::Cross)),
            )
            .panel(Panel::note("motor", "nothing to plot"));
        let svg = fig.to_svg().unwrap();
        assert!(svg.contains("nothing to plot") && svg.contains("cross"));
    }

    #[test]
    fn empty_panel_is_a_data_error() {
        let fig = Figure::new("x").panel(Panel::new("a", "b"));
        assert!(matches!(fig.to_svg(), Err(ReportError::Data(_))));
    }
}
