//! Field map of an axisymmetric magnetostatic solution: |B| as colour on the (r, z) triangles, flux
//! lines as contours of the flux function `ψ = r A_phi`, region outlines and region labels; and the
//! same drawing for any nodal scalar ([`ScalarMap`], e.g. a temperature with its isotherms).
//!
//! In axisymmetry the flux through the disc of radius r at height z is `Φ = 2π r A_phi`, so B is
//! tangent to the level lines of `ψ = r A_phi` and equally spaced levels of ψ give flux lines that
//! carry equal flux (their density shows |B|). Contours are traced triangle by triangle on the
//! piecewise-linear interpolant of ψ ("marching triangles") and joined into polylines
//! ([`lines`]). The triangles are drawn as one image ([`raster`]: no seams, small files), the
//! lines and labels ([`labels`]) as vectors. By default a field map shows the energised part of
//! the device ([`View::Energised`]), not the idle unit and the air box. The map knows no FEM
//! types: it takes plain node, triangle and value arrays. SVG by default, PNG when the file name
//! ends in `.png`.

pub mod labels;
pub mod lines;
pub mod raster;

use std::path::Path;

use mrbrake_design::analysis::FieldRegion;
use plotters::coord::Shift;
use plotters::prelude::*;

pub use labels::RegionKind;
pub use lines::{Window, contour_segments};
use raster::SvgImage;

use crate::ReportError;
use crate::chart::{Picture, save_picture};

/// Which part of the mesh a field map shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum View {
    /// The whole mesh, air box included.
    Whole,
    /// The part where the field is: the triangles with `|B|` at least [`ENERGISED_FRACTION`] of
    /// the largest, with a margin, from the axis outwards (see [`energised_window`]).
    #[default]
    Energised,
}

/// The data of a field map.
#[derive(Debug, Clone, Copy)]
pub struct FieldMap<'a> {
    /// Title drawn above the map.
    pub title: &'a str,
    /// Node coordinates `[r, z]` (m).
    pub nodes: &'a [[f64; 2]],
    /// Triangles (node indices).
    pub triangles: &'a [[usize; 3]],
    /// Region tag per triangle (outlines are drawn where it changes).
    pub region_tags: &'a [u32],
    /// |B| per triangle (T).
    pub b_abs_t: &'a [f64],
    /// Flux function `r A_phi` per node (Wb/rad).
    pub flux_function: &'a [f64],
    /// Number of flux lines.
    pub flux_lines: usize,
    /// The regions (tag, part name, material, role) for the labels; a region not listed, or of
    /// no known kind ([`RegionKind::of`]), is not labelled.
    pub regions: &'a [FieldRegion],
    /// The part of the mesh shown.
    pub view: View,
}

/// The share of the largest |B| above which a triangle counts as energised ([`View::Energised`]).
pub const ENERGISED_FRACTION: f64 = 0.05;

/// Pixel width of the map's plotting area.
const PLOT_WIDTH: f64 = 640.0;

/// Image size in pixels for a map of `window`: width fixed, height from the aspect ratio (plus
/// the colour bar and margins).
fn size_for(window: Window) -> (u32, u32) {
    let (lo, hi) = window;
    let aspect = ((hi[1] - lo[1]) / (hi[0] - lo[0]).max(1e-300)).clamp(0.2, 5.0);
    (PLOT_WIDTH as u32 + 170, (PLOT_WIDTH * aspect) as u32 + 110)
}

/// The bounding box of `nodes`.
pub fn bounds(nodes: &[[f64; 2]]) -> Window {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in nodes {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

/// The window of [`View::Energised`]: the bounding box of the triangles whose |B| is at least
/// [`ENERGISED_FRACTION`] of the largest, widened by 15 % of its larger side (so the parts around
/// the flux path show), reaching to the
/// mesh's smallest r (the axis), inside the mesh's bounds. The whole mesh if no field.
pub fn energised_window(nodes: &[[f64; 2]], triangles: &[[usize; 3]], b_abs_t: &[f64]) -> Window {
    window_above(nodes, triangles, b_abs_t, ENERGISED_FRACTION)
}

/// [`energised_window`] for any per-triangle magnitude and share `fraction` of its largest.
pub fn window_above(
    nodes: &[[f64; 2]],
    triangles: &[[usize; 3]],
    magnitude: &[f64],
    fraction: f64,
) -> Window {
    let whole = bounds(nodes);
    let b_max = magnitude.iter().copied().filter(|b| b.is_finite()).fold(0.0, f64::max);
    if b_max <= 0.0 {
        return whole;
    }
    let strong: Vec<[f64; 2]> = triangles
        .iter()
        .zip(magnitude)
        .filter(|(_, b)| **b >= fraction * b_max)
        .flat_map(|(t, _)| t.iter().map(|&v| nodes[v]))
        .collect();
    let (lo, hi) = bounds(&strong);
    let margin = 0.15 * (hi[0] - lo[0]).max(hi[1] - lo[1]);
    (
        [whole.0[0], (lo[1] - margin).max(whole.0[1])],
        [(hi[0] + margin).min(whole.1[0]), (hi[1] + margin).min(whole.1[1])],
    )
}

/// `window` with each side moved out to the device's edge (plus 3 % of the window) where that
/// edge lies within a quarter of the window's size beyond it, so a map does not cut the device a
/// few millimetres short of its end; inside `whole`.
pub fn snap_to_device(window: Window, device: Window, whole: Window) -> Window {
    let (mut lo, mut hi) = window;
    for k in 0..2 {
        let size = hi[k] - lo[k];
        let (reach, pad) = (0.25 * size, 0.03 * size);
        if device.0[k] < lo[k] && device.0[k] > lo[k] - reach {
            lo[k] = (device.0[k] - pad).max(whole.0[k]);
        }
        if device.1[k] > hi[k] && device.1[k] < hi[k] + reach {
            hi[k] = (device.1[k] + pad).min(whole.1[k]);
        }
    }
    (lo, hi)
}

/// Perceptually ordered colour map (an approximation of matplotlib's "viridis" by 5 anchors).
fn colour(t: f64) -> RGBColor {
    const ANCHORS: [(f64, f64, f64); 5] = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (253.0, 231.0, 37.0),
    ];
    let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.0 };
    let x = t * 4.0;
    let i = (x.floor() as usize).min(3);
    let f = x - i as f64;
    let (a, b) = (ANCHORS[i], ANCHORS[i + 1]);
    let mix = |u: f64, v: f64| (u + f * (v - u)).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

fn check(map: &FieldMap<'_>) -> Result<(), ReportError> {
    let n = map.nodes.len();
    if map.triangles.is_empty() || n == 0 {
        return Err(ReportError::Data("field map: empty mesh".into()));
    }
    if map.b_abs_t.len() != map.triangles.len()
        || map.region_tags.len() != map.triangles.len()
        || map.flux_function.len() != n
    {
        return Err(ReportError::Data(format!(
            "field map: {} triangles but {} |B| values and {} tags; {n} nodes but {} flux values",
            map.triangles.len(),
            map.b_abs_t.len(),
            map.region_tags.len(),
            map.flux_function.len()
        )));
    }
    if map.triangles.iter().any(|t| t.iter().any(|&v| v >= n)) {
        return Err(ReportError::Data("field map: a triangle references a missing node".into()));
    }
    Ok(())
}

impl FieldMap<'_> {
    /// The window the map shows.
    pub fn window(&self) -> Window {
        match self.view {
            View::Whole => bounds(self.nodes),
            View::Energised => {
                let window = energised_window(self.nodes, self.triangles, self.b_abs_t);
                match self.device_bounds() {
                    Some(device) => snap_to_device(window, device, bounds(self.nodes)),
                    None => window,
                }
            }
        }
    }

    /// The bounding box of the triangles of a known kind other than air (the device itself), if
    /// the regions say.
    fn device_bounds(&self) -> Option<Window> {
        let solid: std::collections::HashSet<u32> = self
            .regions
            .iter()
            .filter(|r| RegionKind::of(r.kind, &r.material).is_some_and(|k| k != RegionKind::Air))
            .map(|r| r.tag)
            .collect();
        let points: Vec<[f64; 2]> = self
            .triangles
            .iter()
            .zip(self.region_tags)
            .filter(|(_, tag)| solid.contains(tag))
            .flat_map(|(t, _)| t.iter().map(|&v| self.nodes[v]))
            .collect();
        (!points.is_empty()).then(|| bounds(&points))
    }

    /// Draws the map with its colour bar on `root`; see [`draw_with_bar`].
    fn draw_on<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        raster: Raster,
    ) -> Result<Option<SvgImage>, ReportError> {
        let b_max =
            self.b_abs_t.iter().cloned().filter(|b| b.is_finite()).fold(0.0, f64::max).max(1e-12);
        let layers = Layers {
            title: self.title,
            nodes: self.nodes,
            triangles: self.triangles,
            region_tags: self.region_tags,
            regions: self.regions,
            window: self.window(),
            fraction: &|t| self.b_abs_t[t] / b_max,
            contour_values: self.flux_function,
            // Flux lines where the field is: in the weak field of the air the few lines that
            // carry its small flux zig-zag across coarse triangles and say little.
            contour_in: &|t| self.b_abs_t[t] >= ENERGISED_FRACTION * b_max,
            contour_levels: flux_levels(self.flux_function, self.flux_lines),
        };
        draw_with_bar(root, &layers, (0.0, b_max), "|B| [T]", raster)
    }
}

impl Picture for FieldMap<'_> {
    fn size(&self) -> (u32, u32) {
        size_for(self.window())
    }

    /// The map on the left (|B| colours, flux lines, region outlines), its colour bar on the right.
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), ReportError> {
        self.draw_on(root, Raster::Blit).map(|_| ())
    }
}

/// How the coloured triangles reach the picture.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Raster {
    /// Drawn into the backend as a bitmap at its own resolution (PNG output).
    Blit,
    /// Returned as a PNG at this many pixels per picture pixel, for the caller to put into the
    /// SVG ([`raster::splice`]).
    Deferred(u32),
}

/// Resolution of the triangle image in an SVG, in image pixels per SVG pixel (sharp when zoomed
/// or printed).
const SVG_RASTER_SCALE: u32 = 2;

/// What one coloured triangle map draws: triangles coloured by a fraction in [0, 1], contour lines
/// of a nodal function at given levels, region outlines and labels, inside a window.
struct Layers<'a> {
    title: &'a str,
    nodes: &'a [[f64; 2]],
    triangles: &'a [[usize; 3]],
    region_tags: &'a [u32],
    regions: &'a [FieldRegion],
    window: Window,
    /// The colour-bar fraction of triangle `t`.
    fraction: &'a dyn Fn(usize) -> f64,
    /// Nodal values whose level lines are drawn.
    contour_values: &'a [f64],
    /// Whether the level lines are drawn through triangle `t`.
    contour_in: &'a dyn Fn(usize) -> bool,
    contour_levels: Vec<f64>,
}

/// The map on the left, its colour bar (from `range.0` to `range.1`, captioned `label`) on the
/// right; with [`Raster::Deferred`], the triangle image to put under it.
fn draw_with_bar<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    layers: &Layers<'_>,
    range: (f64, f64),
    label: &str,
    raster: Raster,
) -> Result<Option<SvgImage>, ReportError> {
    crate::chart::ensure_font();
    root.fill(&WHITE).map_err(backend)?;
    let (width, _) = root.dim_in_pixel();
    let (plot_area, bar_area) = root.split_horizontally(width.saturating_sub(150));
    let image = draw_map(layers, &plot_area, raster)?;
    draw_colour_bar(&bar_area, range, label)?;
    Ok(image)
}

/// A plotters drawing error as a [`ReportError`].
fn backend<E: std::error::Error + Send + Sync>(e: DrawingAreaErrorKind<E>) -> ReportError {
    ReportError::Backend(e.to_string())
}

/// Millimetres per metre: the map's axes are in mm.
const MM: f64 = 1e3;

/// The (r, z) map in mm: the triangles in the colour of their fraction, the contour lines in
/// white, the region outlines in black, the region labels on top.
fn draw_map<DB: DrawingBackend>(
    map: &Layers<'_>,
    area: &DrawingArea<DB, Shift>,
    raster: Raster,
) -> Result<Option<SvgImage>, ReportError> {
    let (lo, hi) = map.window;
    let (title, size) = crate::chart::fit_title(area, map.title, 18);
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", size))
        .margin(10)
        .margin_right(24)
        .x_label_area_size(40)
        .y_label_area_size(55)
        .build_cartesian_2d(lo[0] * MM..hi[0] * MM, lo[1] * MM..hi[1] * MM)
        .map_err(backend)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("r [mm]")
        .y_desc("z [mm]")
        .x_label_formatter(&|v| crate::chart::tick_label(*v))
        .y_label_formatter(&|v| crate::chart::tick_label(*v))
        .label_style(("sans-serif", 13))
        .draw()
        .map_err(backend)?;
    let (xs, ys) = chart.plotting_area().get_pixel_range();
    let place = (xs.start, ys.start, (xs.end - xs.start) as u32, (ys.end - ys.start) as u32);
    let colour_of = |t: usize| colour((map.fraction)(t));
    let image = match raster {
        Raster::Blit => {
            let rgb = raster::rasterise(
                map.nodes,
                map.triangles,
                &colour_of,
                map.window,
                (place.2, place.3),
            );
            let bitmap =
                BitMapElement::with_owned_buffer((xs.start, ys.start), (place.2, place.3), rgb)
                    .ok_or_else(|| ReportError::Backend("field map: bitmap size".into()))?;
            area.draw(&bitmap).map_err(backend)?;
            None
        }
        Raster::Deferred(scale) => {
            let size = (place.2 * scale, place.3 * scale);
            let rgb = raster::rasterise(map.nodes, map.triangles, &colour_of, map.window, size);
            Some(SvgImage { place, png: raster::encode_png(&rgb, size)? })
        }
    };
    let in_mm =
        |line: Vec<(f64, f64)>| line.into_iter().map(|p| (p.0 * MM, p.1 * MM)).collect::<Vec<_>>();
    let visible: Vec<[usize; 3]> = visible_triangles(map.nodes, map.triangles, map.window)
        .into_iter()
        .filter(|&t| (map.contour_in)(t))
        .map(|t| map.triangles[t])
        .collect();
    for &level in &map.contour_levels {
        let contours = lines::contour_lines(map.nodes, &visible, map.contour_values, level);
        let clipped = contours.iter().flat_map(|l| lines::clip_polyline(l, map.window));
        chart
            .draw_series(
                clipped.map(|l| PathElement::new(in_mm(l), WHITE.mix(0.9).stroke_width(1))),
            )
            .map_err(backend)?;
    }
    let outlines = lines::outline_lines(map.nodes, map.triangles, map.region_tags, map.window);
    chart
        .draw_series(
            outlines.into_iter().map(|l| PathElement::new(in_mm(l), BLACK.stroke_width(1))),
        )
        .map_err(backend)?;
    let px_per_m = f64::from(place.2) / (hi[0] - lo[0]);
    draw_labels(map, area, &chart, 14.0 / px_per_m, place)?;
    Ok(image)
}

/// The indices of the triangles with a node inside `window` or crossing it (their bounding box
/// meets it).
fn visible_triangles(nodes: &[[f64; 2]], triangles: &[[usize; 3]], window: Window) -> Vec<usize> {
    let (lo, hi) = window;
    (0..triangles.len())
        .filter(|&t| {
            let (a, b) = bounds(&triangles[t].map(|v| nodes[v]));
            a[0] <= hi[0] && b[0] >= lo[0] && a[1] <= hi[1] && b[1] >= lo[1]
        })
        .collect()
}

/// The region labels of `map`: text in a white box at its anchor, or beside it with a leader
/// line; `room_m` is the clearance a label needs to sit on its region. The boxes stay inside the
/// plotting area `plot` (left, top, width, height in pixels).
fn draw_labels<DB: DrawingBackend, CT: CoordTranslate<From = (f64, f64)>>(
    map: &Layers<'_>,
    area: &DrawingArea<DB, Shift>,
    chart: &ChartContext<'_, DB, CT>,
    room_m: f64,
    plot: (i32, i32, u32, u32),
) -> Result<(), ReportError> {
    let labels =
        labels::place(map.nodes, map.triangles, map.region_tags, map.regions, map.window, room_m);
    let font = ("sans-serif", 15).into_font();
    let style = TextStyle::from(font.clone());
    let to_px = |p: (f64, f64)| chart.plotting_area().map_coordinate(&(p.0 * MM, p.1 * MM));
    for label in &labels {
        let (w, h) = area.estimate_text_size(label.text, &style).map_err(backend)?;
        let (w, h) = (w as i32, h as i32);
        let anchor = to_px(label.anchor);
        let centre = label.moved_to.map_or(anchor, to_px);
        if label.moved_to.is_some() {
            let edge = (
                centre.0,
                if anchor.1 < centre.1 { centre.1 - h / 2 - 3 } else { centre.1 + h / 2 + 3 },
            );
            area.draw(&PathElement::new(vec![edge, anchor], BLACK.stroke_width(1)))
                .map_err(backend)?;
            area.draw(&Circle::new(anchor, 2, BLACK.filled())).map_err(backend)?;
        }
        let right = plot.0 + plot.2 as i32 - w - 10;
        let bottom = plot.1 + plot.3 as i32 - h - 8;
        let x0 = (centre.0 - w / 2 - 4).min(right).max(plot.0 + 2);
        let y0 = (centre.1 - h / 2 - 3).min(bottom).max(plot.1 + 2);
        area.draw(&Rectangle::new([(x0, y0), (x0 + w + 8, y0 + h + 6)], WHITE.mix(0.85).filled()))
            .map_err(backend)?;
        area.draw(&Rectangle::new(
            [(x0, y0), (x0 + w + 8, y0 + h + 6)],
            RGBColor(90, 90, 90).stroke_width(1),
        ))
        .map_err(backend)?;
        area.draw(&Text::new(label.text, (x0 + 4, y0 + 3), font.clone().color(&BLACK)))
            .map_err(backend)?;
    }
    Ok(())
}

/// `count` levels of the flux function, equally spaced and centred in its range, so that the
/// lines carry equal flux; none when the function is constant.
fn flux_levels(psi: &[f64], count: usize) -> Vec<f64> {
    let (psi_lo, psi_hi) =
        psi.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| (a.min(x), b.max(x)));
    if psi_hi > psi_lo && count > 0 {
        (1..=count).map(|k| psi_lo + (psi_hi - psi_lo) * (k as f64 - 0.5) / count as f64).collect()
    } else {
        Vec::new()
    }
}

/// The colour bar from `range.0` to `range.1`, in 64 steps, captioned `label`.
fn draw_colour_bar<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    range: (f64, f64),
    label: &str,
) -> Result<(), ReportError> {
    let (lo, hi) = range;
    let mut bar = ChartBuilder::on(area)
        .margin_top(40)
        .margin_bottom(50)
        .margin_right(60)
        .y_label_area_size(0)
        .right_y_label_area_size(50)
        .caption(label, ("sans-serif", 14))
        .build_cartesian_2d(0.0..1.0, lo..hi)
        .map_err(backend)?;
    bar.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_labels(6)
        .y_label_formatter(&|v| crate::chart::tick_label(*v))
        .label_style(("sans-serif", 12))
        .draw()
        .map_err(backend)?;
    let steps = 64;
    let at = |i: usize| lo + (hi - lo) * i as f64 / steps as f64;
    bar.draw_series((0..steps).map(|i| {
        Rectangle::new(
            [(0.0, at(i)), (1.0, at(i + 1))],
            colour((i as f64 + 0.5) / steps as f64).filled(),
        )
    }))
    .map_err(backend)?;
    Ok(())
}

/// The SVG document of a map drawn by `draw`, with the triangle image it returns put under the
/// lines.
fn map_svg(
    size: (u32, u32),
    draw: impl FnOnce(&DrawingArea<SVGBackend<'_>, Shift>) -> Result<Option<SvgImage>, ReportError>,
) -> Result<String, ReportError> {
    let mut buf = String::new();
    let image = {
        let root = SVGBackend::with_string(&mut buf, size).into_drawing_area();
        let image = draw(&root)?;
        root.present().map_err(|e| ReportError::Backend(e.to_string()))?;
        image
    };
    Ok(match image {
        Some(image) => raster::splice(&buf, &image),
        None => buf,
    })
}

/// Whether `path` names a PNG file (by its extension).
fn is_png(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("png"))
}

/// Renders the map as an SVG document.
pub fn field_map_svg(map: &FieldMap<'_>) -> Result<String, ReportError> {
    check(map)?;
    map_svg(map.size(), |root| map.draw_on(root, Raster::Deferred(SVG_RASTER_SCALE)))
}

/// Renders the map as a PNG image in memory, with its size in pixels.
pub fn field_map_png(map: &FieldMap<'_>) -> Result<(Vec<u8>, (u32, u32)), ReportError> {
    check(map)?;
    Ok((crate::chart::render_png(map)?, map.size()))
}

/// Writes the map to `path` atomically: PNG if the name ends in `.png`, SVG otherwise.
pub fn save_field_map(map: &FieldMap<'_>, path: &Path) -> Result<(), ReportError> {
    if is_png(path) {
        check(map)?;
        save_picture(map, path)
    } else {
        crate::write_atomic(path, field_map_svg(map)?.as_bytes())
    }
}

/// A nodal scalar field on the (r, z) triangles (e.g. a temperature): triangles coloured by the
/// mean of their nodes' values over the field's range, level lines (isotherms) equally spaced in
/// that range, region outlines, and a colour bar captioned `label`.
#[derive(Debug, Clone, Copy)]
pub struct ScalarMap<'a> {
    /// Title drawn above the map.
    pub title: &'a str,
    /// Node coordinates `[r, z]` (m).
    pub nodes: &'a [[f64; 2]],
    /// Triangles (node indices).
    pub triangles: &'a [[usize; 3]],
    /// Region tag per triangle.
    pub region_tags: &'a [u32],
    /// One value per node.
    pub values: &'a [f64],
    /// Caption of the colour bar, with the unit (e.g. `T [°C]`).
    pub label: &'a str,
    /// Number of level lines.
    pub levels: usize,
    /// The part of the section shown (clipped); `None`: the whole mesh.
    pub window: Option<Window>,
}

impl ScalarMap<'_> {
    fn shown(&self) -> Window {
        self.window.unwrap_or_else(|| bounds(self.nodes))
    }

    fn range(&self) -> (f64, f64) {
        let (lo, hi) = self
            .values
            .iter()
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)));
        if hi > lo { (lo, hi) } else { (lo - 0.5, lo + 0.5) }
    }

    fn check(&self) -> Result<(), ReportError> {
        let n = self.nodes.len();
        if self.triangles.is_empty() || n == 0 {
            return Err(ReportError::Data("scalar map: empty mesh".into()));
        }
        if self.values.len() != n || self.region_tags.len() != self.triangles.len() {
            return Err(ReportError::Data(format!(
                "scalar map: {n} nodes but {} values; {} triangles but {} tags",
                self.values.len(),
                self.triangles.len(),
                self.region_tags.len()
            )));
        }
        if self.triangles.iter().any(|t| t.iter().any(|&v| v >= n)) {
            return Err(ReportError::Data(
                "scalar map: a triangle references a missing node".into(),
            ));
        }
        if !self.values.iter().any(|v| v.is_finite()) {
            return Err(ReportError::Data("scalar map: no finite value".into()));
        }
        Ok(())
    }
}

impl ScalarMap<'_> {
    /// Draws the map with its colour bar on `root` (the whole mesh, no region labels).
    fn draw_on<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        raster: Raster,
    ) -> Result<Option<SvgImage>, ReportError> {
        let (lo, hi) = self.range();
        let mean = |t: usize| self.triangles[t].iter().map(|&v| self.values[v]).sum::<f64>() / 3.0;
        let layers = Layers {
            title: self.title,
            nodes: self.nodes,
            triangles: self.triangles,
            region_tags: self.region_tags,
            regions: &[],
            window: self.shown(),
            fraction: &|t| (mean(t) - lo) / (hi - lo),
            contour_values: self.values,
            contour_in: &|_| true,
            contour_levels: flux_levels(self.values, self.levels),
        };
        draw_with_bar(root, &layers, (lo, hi), self.label, raster)
    }
}

impl Picture for ScalarMap<'_> {
    fn size(&self) -> (u32, u32) {
        size_for(self.shown())
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), ReportError> {
        self.draw_on(root, Raster::Blit).map(|_| ())
    }
}

/// Renders a scalar map as an SVG document.
pub fn scalar_map_svg(map: &ScalarMap<'_>) -> Result<String, ReportError> {
    map.check()?;
    map_svg(map.size(), |root| map.draw_on(root, Raster::Deferred(SVG_RASTER_SCALE)))
}

/// Writes a scalar map to `path` atomically: PNG if the name ends in `.png`, SVG otherwise.
pub fn save_scalar_map(map: &ScalarMap<'_>, path: &Path) -> Result<(), ReportError> {
    if is_png(path) {
        map.check()?;
        save_picture(map, path)
    } else {
        crate::write_atomic(path, scalar_map_svg(map)?.as_bytes())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrbrake_design::geometry::PartKind;

    fn square() -> (Vec<[f64; 2]>, Vec<[usize; 3]>) {
        (vec![[0.0, 0.0], [0.01, 0.0], [0.01, 0.01], [0.0, 0.01]], vec![[0, 1, 2], [0, 2, 3]])
    }

    #[test]
    fn contour_of_a_linear_function_is_a_straight_line() {
        let (nodes, tris) = square();
        let psi: Vec<f64> = nodes.iter().map(|p| p[0]).collect();
        let segments = contour_segments(&nodes, &tris, &psi, 0.004);
        assert_eq!(segments.len(), 2);
        for s in segments {
            assert!((s[0].0 - 0.004).abs() < 1e-12 && (s[1].0 - 0.004).abs() < 1e-12);
        }
    }

    #[test]
    fn renders_svg_and_rejects_mismatched_data() {
        let (nodes, tris) = square();
        let psi = [0.0, 1.0, 2.0, 1.0];
        let map = FieldMap {
            title: "test",
            nodes: &nodes,
            triangles: &tris,
            region_tags: &[1, 2],
            b_abs_t: &[0.5, 1.0],
            flux_function: &psi,
            flux_lines: 5,
            regions: &[],
            view: View::Whole,
        };
        let svg = field_map_svg(&map).unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("|B| [T]"));
        let bad = FieldMap { b_abs_t: &[0.5], ..map };
        assert!(field_map_svg(&bad).is_err());
    }

    /// The outline (and so the SVG) does not depend on the hash map's per-run order.
    #[test]
    fn the_same_map_renders_the_same_svg() {
        let n = 6;
        let nodes: Vec<[f64; 2]> =
            (0..=n).flat_map(|j| (0..=n).map(move |i| [i as f64, j as f64])).collect();
        let id = |i: usize, j: usize| j * (n + 1) + i;
        let mut triangles = Vec::new();
        for j in 0..n {
            for i in 0..n {
                triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        let tags: Vec<u32> = (0..triangles.len()).map(|t| u32::from(t % 5 == 0)).collect();
        let b: Vec<f64> = (0..triangles.len()).map(|t| t as f64 / 10.0).collect();
        let psi: Vec<f64> = nodes.iter().map(|p| p[0] * p[0]).collect();
        let map = FieldMap {
            title: "grid",
            nodes: &nodes,
            triangles: &triangles,
            region_tags: &tags,
            b_abs_t: &b,
            flux_function: &psi,
            flux_lines: 4,
            regions: &[],
            view: View::Whole,
        };
        let outline = lines::outline_edges(map.triangles, map.region_tags);
        let boundary = &outline[outline.len() - 4 * n..];
        assert!(boundary.windows(2).all(|w| w[0] < w[1]), "{boundary:?}");
        let first = field_map_svg(&map).unwrap();
        for _ in 0..3 {
            assert!(field_map_svg(&map).unwrap() == first);
        }
    }

    /// A 10 x 10 grid of unit squares (two triangles each) with |B| = 1 in the squares with
    /// 2 <= i < 4 and 6 <= j < 8, 0.01 elsewhere.
    fn grid_with_a_hot_block() -> (Vec<[f64; 2]>, Vec<[usize; 3]>, Vec<f64>) {
        let n = 10;
        let nodes: Vec<[f64; 2]> =
            (0..=n).flat_map(|j| (0..=n).map(move |i| [i as f64, j as f64])).collect();
        let id = |i: usize, j: usize| j * (n + 1) + i;
        let (mut triangles, mut b) = (Vec::new(), Vec::new());
        for j in 0..n {
            for i in 0..n {
                let hot = (2..4).contains(&i) && (6..8).contains(&j);
                triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
                b.extend([if hot { 1.0 } else { 0.01 }; 2]);
            }
        }
        (nodes, triangles, b)
    }

    /// The energised window spans the strong field (r 2..4, z 6..8) with 15 % of its 2-unit size
    /// as margin, from the axis (r = 0).
    #[test]
    fn the_energised_window_crops_to_the_field() {
        let (nodes, triangles, b) = grid_with_a_hot_block();
        let (lo, hi) = energised_window(&nodes, &triangles, &b);
        let close = |a: f64, e: f64| (a - e).abs() < 1e-12;
        assert!(close(lo[0], 0.0) && close(hi[0], 4.3), "{lo:?} {hi:?}");
        assert!(close(lo[1], 5.7) && close(hi[1], 8.3), "{lo:?} {hi:?}");
        // A device edge just beyond the window is taken in; one far beyond is not.
        let device = ([0.0, 5.2], [4.5, 9.5]);
        let (lo, hi) = snap_to_device(([0.0, 5.7], [4.3, 8.3]), device, ([0.0, 0.0], [10.0, 10.0]));
        assert!(close(lo[1], 5.2 - 0.03 * 2.6) && close(hi[0], 4.5 + 0.03 * 4.3), "{lo:?} {hi:?}");
        assert!(close(hi[1], 8.3), "9.5 is more than a quarter of 2.6 above 8.3: {hi:?}");
        // No field: the whole mesh.
        let (lo, hi) = energised_window(&nodes, &triangles, &vec![0.0; b.len()]);
        assert!(close(lo[1], 0.0) && close(hi[0], 10.0) && close(hi[1], 10.0));
    }

    /// Known regions get their label, a region of unknown material none.
    #[test]
    fn labels_name_known_regions_only() {
        let (nodes, triangles, b) = grid_with_a_hot_block();
        let tags: Vec<u32> = (0..triangles.len()).map(|t| u32::from(t % 20 >= 10)).collect();
        let psi: Vec<f64> = nodes.iter().map(|p| p[0] * p[1]).collect();
        let region = |tag, name: &str, material: &str, kind| FieldRegion {
            tag,
            name: name.into(),
            material: material.into(),
            kind,
        };
        let regions = [
            region(0, "unit1.core", "steel-1008", PartKind::FluxPath),
            region(1, "part", "custom.csv", PartKind::NonMagnetic),
        ];
        let map = FieldMap {
            title: "grid",
            nodes: &nodes,
            triangles: &triangles,
            region_tags: &tags,
            b_abs_t: &b,
            flux_function: &psi,
            flux_lines: 6,
            regions: &regions,
            view: View::Whole,
        };
        let svg = field_map_svg(&map).unwrap();
        // plotters writes a text element's text on a line of its own.
        assert!(svg.contains("\nsteel\n"), "the steel region is labelled");
        for other in ["\nMR fluid gaps\n", "\ncoil\n", "\nnon-magnetic\n"] {
            assert!(!svg.contains(other), "{other} labelled without such a region");
        }
        let labels = labels::place(&nodes, &triangles, &tags, &regions, map.window(), 0.5);
        assert_eq!(labels.len(), 1, "{labels:?}");
        // The steel (the left half, r < 5) has room for its label: it stays on its region.
        assert!(labels[0].moved_to.is_none(), "{labels:?}");
    }

    #[test]
    fn scalar_map_renders_its_range_and_rejects_mismatched_data() {
        let (nodes, tris) = square();
        let values = [20.0, 40.0, 60.0, 40.0];
        let map = ScalarMap {
            title: "temperature",
            nodes: &nodes,
            triangles: &tris,
            region_tags: &[1, 2],
            values: &values,
            label: "T [°C]",
            levels: 3,
            window: None,
        };
        assert_eq!(map.range(), (20.0, 60.0));
        let svg = scalar_map_svg(&map).unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("T [°C]"));
        assert!(scalar_map_svg(&ScalarMap { values: &values[..3], ..map }).is_err());
    }
}
