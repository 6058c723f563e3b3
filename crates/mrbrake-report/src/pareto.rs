//! Plots of an optimisation: the objective scatter with the Pareto front and a reference design, the
//! constraint activity of the front's designs, and the hypervolume against evaluations.
//!
//! Built on [`crate::chart`]: feasible designs are green points, infeasible ones grey crosses under
//! them, the front a line with markers, and the reference design (the thesis's) a large triangle
//! with its own legend entry; axes and legends in the displayed units ([`metric_plot_axis`]).

use crate::chart::{Figure, GREY, Panel, Series, Shape, tick_label};
use crate::study::metric_axis;

/// Unit endings of metric names (case-insensitive, longest first), dropped from axis labels that
/// carry the displayed unit in brackets instead.
const UNIT_SUFFIXES: [&str; 15] = [
    "_nm_per_m3",
    "_nm_per_kg",
    "_a_per_mm2",
    "_kg_m2",
    "_m3",
    "_nm",
    "_ohm",
    "_kg",
    "_m",
    "_t",
    "_a",
    "_w",
    "_k",
    "_h",
    "_s",
];

/// A metric's name in words, without its SI unit ending: `rotor_inertia_kg_m2` → `rotor inertia`,
/// `mean_B_fluid_T` → `mean |B| fluid`.
pub fn metric_words(name: &str) -> String {
    let lower = name.to_ascii_lowercase();
    let stem = UNIT_SUFFIXES
        .iter()
        .find(|suffix| lower.len() > suffix.len() && lower.ends_with(*suffix))
        .map_or(name, |suffix| &name[..name.len() - suffix.len()]);
    stem.split('_')
        .map(|word| if word.eq_ignore_ascii_case("b") { "|B|" } else { word })
        .collect::<Vec<_>>()
        .join(" ")
}

/// The display scale of a metric and its axis label in the displayed unit, e.g.
/// `(1e6, "rotor inertia [kg·mm²]")` for `rotor_inertia_kg_m2`.
pub fn metric_plot_axis(name: &str) -> (f64, String) {
    let (scale, label) = metric_axis(name);
    let unit = label.rsplit_once('[').and_then(|(_, u)| u.strip_suffix(']')).unwrap_or("");
    let unit = if unit.is_empty() || unit == "1" { "–" } else { unit };
    (scale, format!("{} [{unit}]", metric_words(name)))
}

/// A constraint as a legend label in displayed units, e.g. `outer diameter ≤ 80 mm`.
pub fn constraint_legend(metric: &str, min: Option<f64>, max: Option<f64>) -> String {
    let (scale, label) = metric_plot_axis(metric);
    let unit = label.rsplit_once('[').and_then(|(_, u)| u.strip_suffix(']')).unwrap_or("");
    let unit = if unit == "–" { String::new() } else { format!(" {unit}") };
    let bound = |sign: &str, v: Option<f64>| {
        v.map_or(String::new(), |v| format!(" {sign} {}{unit}", tick_label(v * scale)))
    };
    format!("{}{}{}", metric_words(metric), bound("≥", min), bound("≤", max))
}

/// The data of an objective-space plot (values already in display units).
#[derive(Debug, Clone, Default)]
pub struct ObjectivePlot {
    /// Figure title.
    pub title: String,
    /// X-axis label with unit.
    pub x_label: String,
    /// Y-axis label with unit.
    pub y_label: String,
    /// Feasible designs.
    pub feasible: Vec<(f64, f64)>,
    /// Designs that break a constraint (evaluated, but not allowed).
    pub infeasible: Vec<(f64, f64)>,
    /// The Pareto front, sorted along x.
    pub front: Vec<(f64, f64)>,
    /// Reference designs: label and point.
    pub references: Vec<(String, (f64, f64))>,
}

/// The objective scatter with the front and the references.
pub fn objective_figure(plot: &ObjectivePlot) -> Figure {
    let mut panel = Panel::new(plot.x_label.clone(), plot.y_label.clone());
    if !plot.infeasible.is_empty() {
        panel = panel.series(
            Series::points("violates a constraint", plot.infeasible.clone())
                .color(GREY)
                .shape(Shape::Cross)
                .marker_size(3),
        );
    }
    if !plot.feasible.is_empty() {
        panel = panel.series(Series::points("feasible design", plot.feasible.clone()).color(2));
    }
    if !plot.front.is_empty() {
        panel = panel.series(Series::line_points("Pareto front", plot.front.clone()).color(0));
    }
    for (k, (label, point)) in plot.references.iter().enumerate() {
        panel = panel.series(
            Series::points(label.clone(), vec![*point])
                .color(1 + 2 * k)
                .shape(Shape::Triangle)
                .marker_size(7),
        );
    }
    let ys = plot.infeasible.iter().chain(&plot.feasible).chain(&plot.front).map(|p| p.1);
    let references = plot.references.iter().map(|(_, p)| p.1);
    panel.y_range = legend_headroom(ys.chain(references), None);
    Figure::new(plot.title.clone()).panel(panel)
}

/// A y range over `values` (and `include`, if given) with 35 % of the span added above, so that
/// the legend in the upper-left corner sits above the data instead of on it.
fn legend_headroom(values: impl Iterator<Item = f64>, include: Option<f64>) -> Option<(f64, f64)> {
    let (lo, hi) = values
        .chain(include)
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if !lo.is_finite() {
        return None;
    }
    let span = if hi > lo { hi - lo } else { lo.abs().max(1.0) };
    Some((lo - 0.05 * span, hi + 0.35 * span))
}

/// Constraint activity: for each front design (x: its position along the front), the relative
/// margin to each constraint's limit; 0 is an active constraint, below 0 a violation.
#[derive(Debug, Clone, Default)]
pub struct ConstraintActivity {
    /// Figure title.
    pub title: String,
    /// X-axis label (e.g. the first objective with unit).
    pub x_label: String,
    /// One series per constraint: its label and `(x, margin)` points.
    pub constraints: Vec<(String, Vec<(f64, f64)>)>,
}

/// The constraint-activity chart.
pub fn constraint_activity_figure(activity: &ConstraintActivity) -> Figure {
    let mut panel = Panel::new(activity.x_label.clone(), "relative margin to the limit [–]");
    let points = activity.constraints.iter().flat_map(|(_, points)| points.iter());
    let (x0, x1) = points
        .map(|p| p.0)
        .filter(|x| x.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| (lo.min(x), hi.max(x)));
    // The limit first, in black, so the constraints that sit on it are drawn over it.
    if x0.is_finite() {
        let (x0, x1) = if x1 > x0 { (x0, x1) } else { (x0 - 1.0, x1 + 1.0) };
        panel = panel
            .series(Series::dashed("active (limit)", vec![(x0, 0.0), (x1, 0.0)]).color(6))
            .x_range(x0, x1);
    }
    for (k, (label, points)) in activity.constraints.iter().enumerate() {
        panel = panel.series(Series::line_points(label.clone(), points.clone()).color(k));
    }
    let margins = activity.constraints.iter().flat_map(|(_, points)| points.iter().map(|p| p.1));
    panel.y_range = legend_headroom(margins, Some(0.0));
    Figure::new(activity.title.clone()).panel(panel)
}

/// One curve of hypervolume against evaluations: its label and `(evaluations, hypervolume)` points
/// (in the displayed unit).
pub type HypervolumeCurve = (String, Vec<(f64, f64)>);

/// The hypervolume against evaluations, one line per curve (a run, or the median of several), as a
/// step function: the hypervolume holds until the next evaluation that changes it.
pub fn hypervolume_figure(title: &str, y_label: &str, curves: &[HypervolumeCurve]) -> Figure {
    let mut panel = Panel::new("evaluations (designs analysed)", y_label.to_string());
    for (k, (label, points)) in curves.iter().enumerate() {
        panel = panel.series(Series::line(label.clone(), steps(points)).color(k));
    }
    let values = curves.iter().flat_map(|(_, p)| p.iter().map(|q| q.1));
    panel.y_range = legend_headroom(values, Some(0.0));
    Figure::new(title.to_string()).panel(panel)
}

/// The points of a step function through `points` (sorted by x): each value held until the next x.
fn steps(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(2 * points.len());
    for (k, &(x, y)) in points.iter().enumerate() {
        if k > 0 {
            out.push((x, points[k - 1].1));
        }
        out.push((x, y));
    }
    out
}

/// The display scale and unit of a hypervolume of these objective metrics: the product of their
/// displayed units (`kg·mm² × cm³`).
pub fn hypervolume_axis(metrics: &[&str]) -> (f64, String) {
    let mut scale = 1.0;
    let mut units = Vec::with_capacity(metrics.len());
    for metric in metrics {
        let (s, label) = metric_plot_axis(metric);
        scale *= s;
        let unit = label.rsplit_once('[').and_then(|(_, u)| u.strip_suffix(']')).unwrap_or("–");
        units.push(unit.to_string());
    }
    (scale, format!("hypervolume [{}]", units.join(" × ")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hypervolume_curve_is_a_step_function_in_display_units() {
        assert_eq!(steps(&[(1.0, 0.0), (3.0, 2.0)]), vec![(1.0, 0.0), (3.0, 0.0), (3.0, 2.0)]);
        let (scale, label) = hypervolume_axis(&["rotor_inertia_kg_m2", "volume_m3"]);
        assert!((scale - 1e12).abs() < 1.0, "{scale}");
        assert_eq!(label, "hypervolume [kg·mm² × cm³]");
        let figure =
            hypervolume_figure("t", &label, &[("run".into(), vec![(1.0, 0.0), (5.0, 3.0)])]);
        let dir = tempfile::tempdir().unwrap();
        figure.save(&dir.path().join("hv.svg")).unwrap();
    }

    #[test]
    fn both_figures_render() {
        let plot = ObjectivePlot {
            title: "front".into(),
            x_label: "J [kg·mm²]".into(),
            y_label: "V [cm³]".into(),
            feasible: vec![(1.0, 5.0), (2.0, 3.0), (3.0, 3.5)],
            infeasible: vec![(0.5, 1.0)],
            front: vec![(1.0, 5.0), (2.0, 3.0)],
            references: vec![("thesis design".into(), (2.5, 4.0))],
        };
        let svg = objective_figure(&plot).to_svg().unwrap();
        assert!(svg.contains("Pareto front") && svg.contains("thesis design"));
        let activity = ConstraintActivity {
            title: "constraints".into(),
            x_label: "J".into(),
            constraints: vec![("T ≥ 3 N·m".into(), vec![(1.0, 0.0), (2.0, 0.2)])],
        };
        assert!(constraint_activity_figure(&activity).to_svg().unwrap().contains("active"));
    }

    #[test]
    fn axis_and_legend_labels_are_in_the_displayed_unit() {
        assert_eq!(metric_plot_axis("rotor_inertia_kg_m2"), (1e6, "rotor inertia [kg·mm²]".into()));
        assert_eq!(metric_plot_axis("volume_m3").1, "volume [cm³]");
        assert_eq!(metric_plot_axis("mean_B_fluid_T").1, "mean |B| fluid [T]");
        assert_eq!(metric_plot_axis("current_to_rating").1, "current to rating [–]");
        assert_eq!(metric_words("torque_max_Nm"), "torque max");
        assert_eq!(
            constraint_legend("outer_diameter_m", None, Some(0.08)),
            "outer diameter ≤ 80 mm"
        );
        assert_eq!(constraint_legend("torque_max_Nm", Some(3.0), None), "torque max ≥ 3 N·m");
        assert_eq!(
            constraint_legend("current_to_rating", None, Some(1.0)),
            "current to rating ≤ 1"
        );
    }

    #[test]
    fn the_legend_headroom_covers_the_data_and_the_limit() {
        let (lo, hi) = legend_headroom([0.1, 0.3].into_iter(), Some(0.0)).unwrap();
        assert!(lo < 0.0 && (hi - (0.3 + 0.35 * 0.3)).abs() < 1e-12);
        assert!(legend_headroom([f64::NAN].into_iter(), None).is_none());
        let (lo, hi) = legend_headroom([2.0].into_iter(), None).unwrap();
        assert!(lo < 2.0 && hi > 2.0);
    }
}
