//! Plots of an optimisation: the objective scatter with the Pareto front and a reference design, and
//! the constraint activity of the front's designs.
//!
//! Built on [`crate::chart`]: every evaluated design is a grey point, infeasible ones a light point,
//! the front a line with markers, and the reference design (the thesis's) a highlighted marker with
//! its own legend entry.

use crate::chart::{Figure, Panel, Series};

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
        panel =
            panel.series(Series::points("violates a constraint", plot.infeasible.clone()).color(7));
    }
    if !plot.feasible.is_empty() {
        panel = panel.series(Series::points("feasible design", plot.feasible.clone()).color(2));
    }
    if !plot.front.is_empty() {
        panel = panel.series(Series::line_points("Pareto front", plot.front.clone()).color(0));
    }
    for (k, (label, point)) in plot.references.iter().enumerate() {
        panel = panel.series(Series::points(label.clone(), vec![*point]).color(1 + 2 * k));
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
    let mut x_range = (f64::INFINITY, f64::NEG_INFINITY);
    for (k, (label, points)) in activity.constraints.iter().enumerate() {
        for &(x, _) in points {
            x_range = (x_range.0.min(x), x_range.1.max(x));
        }
        panel = panel.series(Series::line_points(label.clone(), points.clone()).color(k));
    }
    if x_range.0.is_finite() {
        panel = panel.series(
            Series::dashed("active (limit)", vec![(x_range.0, 0.0), (x_range.1, 0.0)]).color(7),
        );
    }
    let margins = activity.constraints.iter().flat_map(|(_, points)| points.iter().map(|p| p.1));
    panel.y_range = legend_headroom(margins, Some(0.0));
    Figure::new(activity.title.clone()).panel(panel)
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn the_legend_headroom_covers_the_data_and_the_limit() {
        let (lo, hi) = legend_headroom([0.1, 0.3].into_iter(), Some(0.0)).unwrap();
        assert!(lo < 0.0 && (hi - (0.3 + 0.35 * 0.3)).abs() < 1e-12);
        assert!(legend_headroom([f64::NAN].into_iter(), None).is_none());
        let (lo, hi) = legend_headroom([2.0].into_iter(), None).unwrap();
        assert!(lo < 2.0 && hi > 2.0);
    }
}
