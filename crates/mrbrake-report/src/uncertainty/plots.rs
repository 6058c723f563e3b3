//! The two figures of `mrbrake uncertainty --plots DIR` and of the report's uncertainty section:
//! the torque–current band (the samples' 5–95 % torque shaded, the median, the nominal design, and
//! optionally measured points) and the tornado chart of one metric's Sobol' indices (per input
//! its first-order and total index with their bootstrap 95 % intervals, the inputs ranked by the
//! total index). Both are drawn from an [`UncertaintyDocument`], so a saved run draws the same.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor;

use super::document::{IndexEntry, UncertaintyDocument};
use crate::ReportError;
use crate::chart::{Figure, Panel, Picture, Series, SeriesLabelPosition, Shape, palette};

/// File name (without extension) of the torque band plot.
pub const BAND_FILE: &str = "torque_band";
/// File name (without extension) of the tornado chart.
pub const TORNADO_FILE: &str = "tornado";

/// Measured torque–current points to draw over the band, with what they are.
#[derive(Debug, Clone, PartialEq)]
pub struct Measured {
    /// The legend's words (e.g. the prototype and the source).
    pub label: String,
    /// `(current A, torque N·m)`.
    pub points: Vec<(f64, f64)>,
}

/// The thesis prototype's measured torques: 0.15 N·m at 0 A (off state, mostly seals) and
/// 3.84 N·m at 2 A (Karabulut 2017, §5.3.1, Table 5.1), for the band of the embedded thesis brake.
pub fn thesis_prototype() -> Measured {
    use mrbrake_sim::haptic::prototype::{CURRENT_MAX_A, FULL_TORQUE_NM, OFF_STATE_TORQUE_NM};
    Measured {
        label: "prototype, measured (thesis §5.3.1)".into(),
        points: vec![(0.0, OFF_STATE_TORQUE_NM), (CURRENT_MAX_A, FULL_TORQUE_NM)],
    }
}

/// The torque–current band of `doc` titled `title`, with `measured` points when given. A data
/// error when the band is empty.
pub fn band_figure(
    doc: &UncertaintyDocument,
    title: &str,
    measured: Option<&Measured>,
) -> Result<Figure, ReportError> {
    let band = &doc.torque_band;
    if band.is_empty() {
        return Err(ReportError::Data("the propagation has no torque band".into()));
    }
    let mut outline: Vec<(f64, f64)> = band.iter().map(|p| (p.current_a, p.p95_nm)).collect();
    outline.extend(band.iter().rev().map(|p| (p.current_a, p.p5_nm)));
    let median: Vec<(f64, f64)> = band.iter().map(|p| (p.current_a, p.p50_nm)).collect();
    let nominal: Vec<(f64, f64)> =
        band.iter().filter_map(|p| p.nominal_nm.map(|t| (p.current_a, t))).collect();
    let mut panel = Panel::new("current [A]", "torque [N·m]")
        .legend(SeriesLabelPosition::UpperLeft)
        .series(Series::area("5–95 % of the samples", outline).color(0))
        .series(Series::line_points("median", median).color(0).marker_size(3));
    if !nominal.is_empty() {
        panel = panel.series(Series::dashed("nominal design", nominal).color(1));
    }
    if let Some(m) = measured.filter(|m| !m.points.is_empty()) {
        let series = Series::points(m.label.as_str(), m.points.clone());
        panel = panel.series(series.color(6).shape(Shape::Triangle).marker_size(6));
    }
    let caption = format!("{} of {} samples", doc.evaluated, doc.samples);
    Ok(Figure::new(title).panel(panel.caption(caption)))
}

/// The tornado chart of `metric`'s Sobol' indices in `doc`.
#[derive(Debug, Clone)]
pub struct Tornado {
    title: String,
    /// Per input, ranked by the total index (largest first): name, first, total and intervals.
    bars: Vec<(String, IndexEntry)>,
}

impl Tornado {
    /// The chart of `metric`, or a data error naming the metrics that have indices.
    pub fn new(doc: &UncertaintyDocument, metric: &str) -> Result<Self, ReportError> {
        let Some(indices) = doc.indices(metric) else {
            let known: Vec<&str> = doc.sobol.keys().map(String::as_str).collect();
            return Err(ReportError::Data(format!(
                "no Sobol' indices of {metric} (the metrics with indices: {})",
                if known.is_empty() { "none".to_string() } else { known.join(", ") }
            )));
        };
        if indices.is_empty() {
            return Err(ReportError::Data(format!("no declared input has indices of {metric}")));
        }
        let mut bars: Vec<_> = indices.into_iter().map(|(n, ix)| (n.to_string(), ix)).collect();
        bars.sort_by(|a, b| b.1.total.total_cmp(&a.1.total));
        let surrogate = doc.surrogates.get(metric).map_or(String::new(), |s| {
            format!(" (polynomial chaos, leave-one-out error {:.3})", s.loo_error)
        });
        Ok(Self { title: format!("Sobol' indices of {metric}{surrogate}"), bars })
    }

    /// The SVG document.
    pub fn to_svg(&self) -> Result<String, ReportError> {
        crate::chart::render_svg(self)
    }

    /// Writes the chart to `path` atomically (SVG or PNG by its extension).
    pub fn save(&self, path: &Path) -> Result<(), ReportError> {
        crate::chart::save_picture(self, path)
    }
}

/// Half-heights of the bars (in rows): the total index wide and light, the first-order index
/// narrow and dark inside it.
const TOTAL_HALF: f64 = 0.34;
const FIRST_HALF: f64 = 0.17;

impl Picture for Tornado {
    fn size(&self) -> (u32, u32) {
        (900, 150 + 56 * self.bars.len().max(1) as u32)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), ReportError> {
        crate::chart::ensure_font();
        let be = |e: DrawingAreaErrorKind<DB::ErrorType>| ReportError::Backend(e.to_string());
        root.fill(&WHITE).map_err(be)?;
        let (title, size) = crate::chart::fit_title(root, &self.title, 20);
        let area = root.titled(&title, ("sans-serif", size)).map_err(be)?;
        let rows = self.bars.len();
        let label_style = TextStyle::from(("sans-serif", 14).into_font());
        let widest = self
            .bars
            .iter()
            .filter_map(|(name, _)| area.estimate_text_size(name, &label_style).ok())
            .map(|s| s.0)
            .max()
            .unwrap_or(40);
        let mut chart = ChartBuilder::on(&area)
            .margin(12)
            .margin_right(30)
            .x_label_area_size(42)
            .y_label_area_size(widest + 16)
            .build_cartesian_2d(0.0..1.0, -0.5..rows as f64 - 0.5)
            .map_err(be)?;
        chart
            .configure_mesh()
            .disable_y_mesh()
            .y_labels(0)
            .x_desc("Sobol' index (share of the variance)")
            .x_label_formatter(&|v| crate::chart::tick_label(*v))
            .label_style(("sans-serif", 14))
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(be)?;
        // The inputs' names left of their bars, right-aligned on the axis (plotters' own labels
        // sit at "nice" values, not at the rows).
        let anchor = label_style
            .pos(text_anchor::Pos::new(text_anchor::HPos::Right, text_anchor::VPos::Center));
        for (k, (name, _)) in self.bars.iter().enumerate() {
            let (x, y) = chart.backend_coord(&(0.0, row_y(rows, k)));
            root.draw_text(name, &anchor, (x - 8, y)).map_err(be)?;
        }
        self.draw_bars(&mut chart).map_err(be)?;
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.9))
            .border_style(RGBColor(180, 180, 180))
            .label_font(("sans-serif", 13))
            .position(SeriesLabelPosition::LowerRight)
            .draw()
            .map_err(be)
    }
}

impl Tornado {
    /// The bars (total, then first-order inside it) and their intervals as whiskers.
    fn draw_bars<'a, DB: DrawingBackend + 'a, CT: CoordTranslate<From = (f64, f64)>>(
        &self,
        chart: &mut ChartContext<'a, DB, CT>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        let rows = self.bars.len();
        let clamp = |x: f64| x.clamp(0.0, 1.0);
        let (light, dark) = (palette(5), palette(0));
        let bar = |y: f64, half: f64, x: f64, color: RGBColor| {
            Rectangle::new([(0.0, y - half), (clamp(x), y + half)], color.filled())
        };
        let whisker = |y: f64, ci: [f64; 2]| {
            PathElement::new(vec![(clamp(ci[0]), y), (clamp(ci[1]), y)], BLACK.stroke_width(2))
        };
        let y_of = |k: usize| row_y(rows, k);
        type Index = fn(&IndexEntry) -> f64;
        let kinds: [(&str, f64, Index, RGBColor); 2] = [
            ("total index", TOTAL_HALF, |ix| ix.total, light),
            ("first-order index", FIRST_HALF, |ix| ix.first, dark),
        ];
        for (label, half, index, color) in kinds {
            let bars = self.bars.iter().enumerate();
            let key = (half * 18.0).round() as i32;
            chart
                .draw_series(bars.map(|(k, (_, ix))| bar(y_of(k), half, index(ix), color)))?
                .label(label)
                .legend(move |(x, y)| {
                    Rectangle::new([(x, y - key), (x + 14, y + key)], color.filled())
                });
        }
        let whiskers = self.bars.iter().enumerate().flat_map(|(k, (_, ix))| {
            let y = y_of(k);
            [whisker(y + FIRST_HALF + 0.06, ix.total_ci), whisker(y, ix.first_ci)]
        });
        chart
            .draw_series(whiskers)?
            .label("bootstrap 95 % interval")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 14, y)], BLACK.stroke_width(2)));
        // Each bar's numbers right of it, so the small ones are read too.
        let anchor = text_anchor::Pos::new(text_anchor::HPos::Left, text_anchor::VPos::Center);
        let style = TextStyle::from(("sans-serif", 13).into_font()).pos(anchor);
        let values = self.bars.iter().enumerate().map(|(k, (_, ix))| {
            let x = (ix.total.max(ix.total_ci[1]) + 0.015).clamp(0.015, 0.82);
            let text = format!("first {:.3}, total {:.3}", ix.first, ix.total);
            Text::new(text, (x, y_of(k)), style.clone())
        });
        chart.draw_series(values)?;
        Ok(())
    }
}

/// The chart's y of the `k`-th input of the ranking among `rows`: the largest total on top.
fn row_y(rows: usize, k: usize) -> f64 {
    (rows - 1 - k) as f64
}

/// Writes the band plot (`torque_band.svg`) and the tornado chart of `metric` (`tornado.svg`,
/// skipped when `metric` is `None`) into `dir`, and PNG copies with `png`.
pub fn write_plots(
    doc: &UncertaintyDocument,
    dir: &Path,
    band_title: &str,
    measured: Option<&Measured>,
    metric: Option<&str>,
    png: bool,
) -> Result<(), ReportError> {
    let band = band_figure(doc, band_title, measured)?;
    let tornado = metric.map(|m| Tornado::new(doc, m)).transpose()?;
    for ext in if png { &["svg", "png"][..] } else { &["svg"][..] } {
        band.save(&dir.join(format!("{BAND_FILE}.{ext}")))?;
        if let Some(t) = &tornado {
            t.save(&dir.join(format!("{TORNADO_FILE}.{ext}")))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::uncertainty::document::SAMPLE;

    fn doc() -> UncertaintyDocument {
        serde_json::from_str(SAMPLE).unwrap()
    }

    #[test]
    fn band_and_tornado_are_written_as_non_empty_pictures() {
        let dir = tempfile::tempdir().unwrap();
        let measured = thesis_prototype();
        write_plots(&doc(), dir.path(), "band", Some(&measured), Some("torque_max_Nm"), true)
            .unwrap();
        for name in ["torque_band.svg", "torque_band.png", "tornado.svg", "tornado.png"] {
            let bytes = std::fs::read(dir.path().join(name)).unwrap();
            assert!(bytes.len() > 1000, "{name}: {} bytes", bytes.len());
        }
        let band = std::fs::read_to_string(dir.path().join("torque_band.svg")).unwrap();
        assert!(band.contains("5–95 % of the samples") && band.contains("nominal design"));
        assert!(band.contains("prototype, measured"), "the measured points have a legend entry");
        let tornado = std::fs::read_to_string(dir.path().join("tornado.svg")).unwrap();
        // Inputs ranked by the total index: b (0.8) above a (0.2), both named.
        assert!(tornado.contains("\nb\n") && tornado.contains("\na\n"), "input names on the axis");
        assert!(tornado.contains("leave-one-out error 0.010"));
    }

    #[test]
    fn a_metric_without_indices_and_an_empty_band_are_data_errors() {
        let e = Tornado::new(&doc(), "volume_m3").unwrap_err().to_string();
        assert!(e.contains("volume_m3") && e.contains("torque_max_Nm"), "{e}");
        let mut empty = doc();
        empty.inputs.clear();
        assert!(matches!(Tornado::new(&empty, "torque_max_Nm"), Err(ReportError::Data(_))));
        empty.torque_band.clear();
        assert!(matches!(band_figure(&empty, "t", None), Err(ReportError::Data(_))));
    }
}
