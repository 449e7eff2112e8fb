//! SVG figures (plotters, SVG backend): scenes like P's Figs. 2–4 (walls, body outlines at
//! regular times fading from old to new, centroid paths, orientation marks, equal aspect), and
//! line panels (time series, log–log reports).

use super::run_data::RunData;
use crate::geometry::{Shape, Vec2};
use plotters::coord::Shift;
use plotters::coord::ranged1d::ValueFormatter;
use plotters::prelude::*;
use std::path::Path;

/// A plotting error (file or drawing), as text.
#[derive(Debug)]
pub struct PlotError(pub String);

impl std::fmt::Display for PlotError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for PlotError {}

fn err<E: std::fmt::Debug>(e: E) -> PlotError {
    PlotError(format!("{e:?}"))
}

/// Largest magnitude of a coordinate or value that is drawn. plotters forms squares of
/// coordinates: a scene with a coordinate of 1e155 never finished drawing (its memory grew
/// without bound), so a plot reaching beyond this is refused with the range it holds.
pub const PLOT_LIMIT: f64 = 1e100;

/// Refuses an axis range that cannot be drawn: not finite, beyond [`PLOT_LIMIT`], or too narrow
/// for its distance from zero to be resolved.
fn check_range(what: &str, lo: f64, hi: f64) -> Result<(), PlotError> {
    let far = lo.abs().max(hi.abs());
    let drawable = lo.is_finite() && hi.is_finite() && far <= PLOT_LIMIT && hi - lo > 1e-9 * far;
    if drawable {
        Ok(())
    } else {
        Err(PlotError(format!(
            "{what} from {lo:e} to {hi:e} cannot be drawn: values must be finite, at most \
             {PLOT_LIMIT:e} in magnitude, and spread over more than 1e-9 of their magnitude (a \
             run that blew up?)"
        )))
    }
}

/// The colours of series and bodies (colour-blind-safe order).
pub const COLORS: [RGBColor; 6] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(86, 180, 233),
    RGBColor(230, 159, 0),
];

fn color(k: usize) -> RGBColor {
    COLORS[k % COLORS.len()]
}

/// Drawing units per displayed pixel. plotters' SVG backend writes integer coordinates; drawing at
/// `S`× the size and declaring the displayed size in the header keeps curves smooth (no pixel
/// staircase) while text and lines keep their displayed sizes.
const S: u32 = 2;

/// Rewrites the SVG header to display the `size`-unit drawing at `size / S` pixels.
fn downscale_header(path: &Path, size: (u32, u32)) -> Result<(), PlotError> {
    let text = std::fs::read_to_string(path).map_err(err)?;
    let from = format!("width=\"{}\" height=\"{}\"", size.0, size.1);
    let to = format!("width=\"{}\" height=\"{}\"", size.0 / S, size.1 / S);
    if !text.contains(&from) {
        return Err(PlotError(format!(
            "{}: unexpected SVG header",
            path.display()
        )));
    }
    std::fs::write(path, text.replacen(&from, &to, 1)).map_err(err)
}

/// The outline of a shape placed at `(x, y)` with angle `angle`, as a closed polygon.
pub fn outline(shape: &Shape, x: f64, y: f64, angle: f64) -> Vec<(f64, f64)> {
    let (s, c) = angle.sin_cos();
    let place = |u: f64, v: f64| (x + c * u - s * v, y + s * u + c * v);
    let mut pts: Vec<(f64, f64)> = match *shape {
        Shape::Circle { r } => (0..72)
            .map(|k| k as f64 * std::f64::consts::TAU / 72.0)
            .map(|t| place(r * t.cos(), r * t.sin()))
            .collect(),
        Shape::Ellipse { a, b } => (0..72)
            .map(|k| k as f64 * std::f64::consts::TAU / 72.0)
            .map(|t| place(a * t.cos(), b * t.sin()))
            .collect(),
        Shape::Rectangle { w, h } => {
            let (u, v) = (0.5 * w, 0.5 * h);
            vec![place(-u, -v), place(u, -v), place(u, v), place(-u, v)]
        }
    };
    pts.push(pts[0]);
    pts
}

/// One panel of a scene figure: runs drawn on the same axes.
pub struct ScenePanel<'a> {
    pub title: String,
    /// Each run with its legend label (empty: no legend entry).
    pub runs: Vec<(&'a RunData, String)>,
}

/// Options of a scene figure.
pub struct SceneOptions {
    /// Draw up to this time (default: the whole run).
    pub t_max: Option<f64>,
    /// Number of outlines per body over the time shown.
    pub outlines: usize,
    /// Figure width in pixels.
    pub width: u32,
    /// Colour by body (one run per panel) rather than by run.
    pub color_by_body: bool,
    /// Runs with more bodies than this are drawn as a snapshot: each body's outline at the last
    /// time shown, without paths or earlier outlines (which would bury a pile and make the file
    /// hundreds of megabytes).
    pub snapshot_above: usize,
}

impl Default for SceneOptions {
    fn default() -> Self {
        SceneOptions {
            t_max: None,
            outlines: 24,
            width: 1000,
            color_by_body: true,
            snapshot_above: 100,
        }
    }
}

/// The box that holds every body of every panel over the time shown (at its last time only for a
/// snapshot run), extended to axis-aligned walls nearby; equal aspect is applied later.
fn scene_bounds(panels: &[ScenePanel], opts: &SceneOptions, t_max: f64) -> (f64, f64, f64, f64) {
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for p in panels {
        for (run, _) in &p.runs {
            let shown: Vec<_> = run.frames.iter().filter(|f| f.t <= t_max).collect();
            let snapshot = run.case.bodies.len() > opts.snapshot_above;
            let from = if snapshot {
                shown.len().saturating_sub(1)
            } else {
                0
            };
            for f in &shown[from..] {
                for (b, init) in f.bodies.iter().zip(&run.case.bodies) {
                    for (x, y) in outline(&init.shape, b.x, b.y, b.angle) {
                        x0 = x0.min(x);
                        x1 = x1.max(x);
                        y0 = y0.min(y);
                        y1 = y1.max(y);
                    }
                }
            }
        }
    }
    let (w, h) = (x1 - x0, y1 - y0);
    for p in panels {
        for (run, _) in &p.runs {
            for wall in &run.case.walls {
                let (pt, n) = (wall.wall.point, wall.wall.normal);
                if n.x.abs() < 1e-12 && (pt.y - y0).abs() < 0.5 * h.max(w) {
                    y0 = y0.min(pt.y);
                    y1 = y1.max(pt.y);
                }
                if n.y.abs() < 1e-12 && (pt.x - x0).abs().min((pt.x - x1).abs()) < 0.5 * w.max(h) {
                    x0 = x0.min(pt.x);
                    x1 = x1.max(pt.x);
                }
            }
        }
    }
    let (mx, my) = (0.03 * (x1 - x0), 0.05 * (y1 - y0));
    (x0 - mx, x1 + mx, y0 - my, y1 + my)
}

/// The part of the line through `p` with direction `d` inside the box, if any (Liang–Barsky).
fn clip_line(p: Vec2, d: Vec2, b: (f64, f64, f64, f64)) -> Option<(Vec2, Vec2)> {
    let (mut t0, mut t1) = (f64::NEG_INFINITY, f64::INFINITY);
    for (pv, dv, lo, hi) in [(p.x, d.x, b.0, b.1), (p.y, d.y, b.2, b.3)] {
        if dv.abs() < 1e-300 {
            if pv < lo || pv > hi {
                return None;
            }
        } else {
            let (a, c) = ((lo - pv) / dv, (hi - pv) / dv);
            t0 = t0.max(a.min(c));
            t1 = t1.min(a.max(c));
        }
    }
    (t0 < t1).then(|| (p + d * t0, p + d * t1))
}

/// Draws a scene figure: panels stacked vertically on common, equal-aspect axes.
pub fn scene(path: &Path, panels: &[ScenePanel], opts: &SceneOptions) -> Result<(), PlotError> {
    let t_max = opts.t_max.unwrap_or(f64::INFINITY);
    let (mut x0, mut x1, mut y0, mut y1) = scene_bounds(panels, opts, t_max);
    check_range("the scene's x", x0, x1)?;
    check_range("the scene's y", y0, y1)?;
    let (left, bottom, title_h, margin) = (60 * S, 45 * S, 30 * S, 12 * S);
    let width = opts.width * S;
    let plot_w = (width - left - 2 * margin) as f64;
    // Equal aspect: pixels per unit the same on both axes, within sensible panel heights.
    let mut plot_h = plot_w * (y1 - y0) / (x1 - x0);
    let (min_h, max_h) = (150.0 * S as f64, 600.0 * S as f64);
    if plot_h < min_h {
        // Grow upwards mostly: scenes usually stand on a floor.
        let grow = (min_h / plot_h - 1.0) * (y1 - y0);
        (y0, y1) = (y0 - 0.1 * grow, y1 + 0.9 * grow);
        plot_h = min_h;
    } else if plot_h > max_h {
        let grow = (plot_h / max_h - 1.0) * (x1 - x0) / 2.0;
        (x0, x1) = (x0 - grow, x1 + grow);
        plot_h = max_h;
    }
    let panel_h = plot_h as u32 + bottom + title_h + 2 * margin;
    let height = panel_h * panels.len() as u32;
    let root = SVGBackend::new(path, (width, height)).into_drawing_area();
    root.fill(&WHITE).map_err(err)?;
    let areas = root.split_evenly((panels.len(), 1));
    let bounds = (x0, x1, y0, y1);
    for (area, panel) in areas.iter().zip(panels) {
        draw_scene_panel(area, panel, opts, bounds, t_max, (left, bottom, margin))?;
    }
    root.present().map_err(err)?;
    drop(root);
    downscale_header(path, (width, height))
}

fn draw_scene_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    panel: &ScenePanel,
    opts: &SceneOptions,
    (x0, x1, y0, y1): (f64, f64, f64, f64),
    t_max: f64,
    (left, bottom, margin): (u32, u32, u32),
) -> Result<(), PlotError>
where
    DB::ErrorType: 'static,
{
    let units = panel
        .runs
        .first()
        .map(|(r, _)| r.case.units.clone())
        .unwrap_or_default();
    let unit = |axis: &str| {
        if units.is_empty() {
            axis.to_string()
        } else {
            format!("{axis} ({units})")
        }
    };
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, ("sans-serif", 17 * S))
        .margin(margin)
        .x_label_area_size(bottom)
        .y_label_area_size(left)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(err)?;
    let (sx, sy) = (x1 - x0, y1 - y0);
    let fx = move |v: &f64| tick_label(*v, false, sx);
    let fy = move |v: &f64| tick_label(*v, false, sy);
    chart
        .configure_mesh()
        .disable_mesh()
        .x_label_formatter(&fx)
        .y_label_formatter(&fy)
        .x_desc(unit("x"))
        .y_desc(unit("y"))
        .label_style(("sans-serif", 13 * S))
        .axis_desc_style(("sans-serif", 14 * S))
        .draw()
        .map_err(err)?;
    let bounds = (x0, x1, y0, y1);
    let size = (x1 - x0).max(y1 - y0);
    // Walls: a thick line with hatching on the solid side.
    if let Some((run, _)) = panel.runs.first() {
        for w in &run.case.walls {
            let (n, t) = (w.wall.normal, Vec2::new(-w.wall.normal.y, w.wall.normal.x));
            if let Some((a, b)) = clip_line(w.wall.point, t, bounds) {
                chart
                    .draw_series(std::iter::once(PathElement::new(
                        vec![(a.x, a.y), (b.x, b.y)],
                        BLACK.stroke_width(2 * S),
                    )))
                    .map_err(err)?;
                let len = (b - a).norm();
                let hatch = size / 70.0;
                let k = (len / hatch).floor() as usize;
                let into = (t - n) * (hatch / 2f64.sqrt());
                chart
                    .draw_series((0..=k).map(|i| {
                        let p = a + (b - a) * (i as f64 / k.max(1) as f64);
                        let q = p + into;
                        PathElement::new(
                            vec![(p.x, p.y), (q.x, q.y)],
                            BLACK.mix(0.6).stroke_width(S),
                        )
                    }))
                    .map_err(err)?;
            }
        }
    }
    let several = panel.runs.len() > 1;
    for (ri, (run, label)) in panel.runs.iter().enumerate() {
        let frames: Vec<_> = run.frames.iter().filter(|f| f.t <= t_max).collect();
        let (Some(first), Some(last)) = (frames.first(), frames.last()) else {
            continue;
        };
        let span = (last.t - first.t).max(1e-300);
        if run.case.bodies.len() > opts.snapshot_above {
            let col = color(ri);
            chart
                .draw_series(run.case.bodies.iter().enumerate().map(|(k, init)| {
                    let b = last.bodies[k];
                    PathElement::new(outline(&init.shape, b.x, b.y, b.angle), col.stroke_width(S))
                }))
                .map_err(err)?;
            continue;
        }
        for (k, init) in run.case.bodies.iter().enumerate() {
            let col = if opts.color_by_body && !several {
                color(k)
            } else {
                color(ri)
            };
            // Centroid path.
            let path: Vec<(f64, f64)> = frames
                .iter()
                .map(|f| (f.bodies[k].x, f.bodies[k].y))
                .collect();
            let series = chart
                .draw_series(LineSeries::new(path, col.mix(0.9).stroke_width(S)))
                .map_err(err)?;
            if several && k == 0 && !label.is_empty() {
                series.label(label.clone()).legend(move |(x, y)| {
                    PathElement::new(
                        vec![(x, y), (x + 18 * S as i32, y)],
                        col.stroke_width(2 * S),
                    )
                });
            }
            // Outlines at regular times, older ones fainter, with an orientation mark.
            let count = opts.outlines.max(2);
            let mut next = first.t;
            let mut chosen = Vec::new();
            for f in &frames {
                if f.t + 1e-12 >= next {
                    chosen.push(*f);
                    next += span / (count - 1) as f64;
                }
            }
            if chosen.last().map(|f| f.step) != Some(last.step) {
                chosen.push(last);
            }
            let r = init.shape.bounding_radius();
            for f in chosen {
                let b = f.bodies[k];
                let age = (f.t - first.t) / span;
                let alpha = 0.15 + 0.85 * age;
                let style =
                    col.mix(alpha)
                        .stroke_width(if f.step == last.step { 2 * S } else { S });
                chart
                    .draw_series(std::iter::once(PathElement::new(
                        outline(&init.shape, b.x, b.y, b.angle),
                        style,
                    )))
                    .map_err(err)?;
                let tip = (b.x + 0.8 * r * b.angle.cos(), b.y + 0.8 * r * b.angle.sin());
                chart
                    .draw_series(std::iter::once(PathElement::new(
                        vec![(b.x, b.y), tip],
                        style,
                    )))
                    .map_err(err)?;
            }
        }
    }
    if several {
        draw_legend(&mut chart, SeriesLabelPosition::UpperRight)?;
    }
    Ok(())
}

/// The legend box, in the house style, at `position`.
fn draw_legend<'a, DB, CT>(
    chart: &mut ChartContext<'a, DB, CT>,
    position: SeriesLabelPosition,
) -> Result<(), PlotError>
where
    DB: DrawingBackend + 'a,
    DB::ErrorType: 'static,
    CT: CoordTranslate,
{
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.4))
        .label_font(("sans-serif", 13 * S))
        .legend_area_size(26 * S)
        .margin(8 * S)
        .draw()
        .map_err(err)
}

/// One series of a line panel.
#[derive(Clone, Debug, Default)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub color: usize,
    pub line: bool,
    pub markers: bool,
    /// Hollow markers (e.g. "did not converge").
    pub hollow: bool,
}

/// A panel of line series.
#[derive(Clone, Debug, Default)]
pub struct LinePanel {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub log_x: bool,
    pub log_y: bool,
    pub series: Vec<Series>,
    /// Vertical and horizontal reference lines with labels.
    pub vlines: Vec<(f64, String)>,
    pub hlines: Vec<(f64, String)>,
    pub x_range: Option<(f64, f64)>,
    pub y_range: Option<(f64, f64)>,
    /// Where the legend goes.
    pub legend: Legend,
}

/// Legend corner of a line panel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Legend {
    /// The corner where the legend box covers the fewest drawn points.
    #[default]
    Auto,
    UpperRight,
    UpperLeft,
    LowerRight,
    LowerLeft,
}

impl Legend {
    fn position(self) -> SeriesLabelPosition {
        match self {
            Legend::Auto | Legend::UpperRight => SeriesLabelPosition::UpperRight,
            Legend::UpperLeft => SeriesLabelPosition::UpperLeft,
            Legend::LowerRight => SeriesLabelPosition::LowerRight,
            Legend::LowerLeft => SeriesLabelPosition::LowerLeft,
        }
    }
}

/// Tick labels: powers of ten on log axes (`1e-6`), and on linear axes as many decimals as the
/// tick spacing needs (no `20000.0`, no repeated labels).
fn tick_label(v: f64, log: bool, span: f64) -> String {
    if log {
        return format!("{v:.0e}");
    }
    if v == 0.0 {
        return "0".into();
    }
    // One digit finer than a tenth of the span (plotters puts up to ~10 ticks at 1-2-5 or
    // 2.5 steps), trailing zeros dropped: `2.25`, `2.5`, `3`, never `2` twice.
    let decimals = (1.0 - (span / 10.0).log10().floor()).clamp(0.0, 8.0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

fn data_range(vals: impl Iterator<Item = f64>, log: bool) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in vals.filter(|v| v.is_finite() && (!log || *v > 0.0)) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return if log { (1e-3, 1.0) } else { (0.0, 1.0) };
    }
    if log {
        let (l, h) = (lo.log10(), hi.log10());
        // Whole decades: both ends get a tick label, and short ranges get enough of them.
        (
            10f64.powf((l - 0.01).floor()),
            10f64.powf((h + 0.01).ceil()),
        )
    } else {
        let pad = 0.05 * (hi - lo).max(1e-12 * hi.abs().max(1.0));
        (lo - pad, hi + pad)
    }
}

/// The corner for an automatic legend: the one whose legend-sized box (estimated from the
/// labels' lengths and the plotting area of `px` drawing units) covers the fewest points of the
/// series, sampled along their segments.
fn auto_legend(p: &LinePanel, (x0, x1, y0, y1): (f64, f64, f64, f64), px: (u32, u32)) -> Legend {
    let norm = |v: f64, lo: f64, hi: f64, log: bool| {
        if log {
            (v.ln() - lo.ln()) / (hi.ln() - lo.ln())
        } else {
            (v - lo) / (hi - lo)
        }
    };
    let labels: Vec<&str> = p
        .series
        .iter()
        .map(|s| s.label.as_str())
        .chain(p.vlines.iter().chain(&p.hlines).map(|l| l.1.as_str()))
        .filter(|l| !l.is_empty())
        .collect();
    let chars = labels.iter().map(|l| l.chars().count()).max().unwrap_or(0) as f64;
    // About 7 px per character at the 13 px legend font, the key and margins; 19 px per row.
    let s = S as f64;
    let w = ((7.0 * chars + 50.0) * s / px.0.max(1) as f64).min(0.95);
    let h = ((19.0 * labels.len() as f64 + 20.0) * s / px.1.max(1) as f64).min(0.95);
    let corners = [
        (Legend::UpperRight, (1.0 - w, 1.0), (1.0 - h, 1.0)),
        (Legend::UpperLeft, (0.0, w), (1.0 - h, 1.0)),
        (Legend::LowerRight, (1.0 - w, 1.0), (0.0, h)),
        (Legend::LowerLeft, (0.0, w), (0.0, h)),
    ];
    let mut counts = [0usize; 4];
    for s in &p.series {
        let pts: Vec<(f64, f64)> = s
            .points
            .iter()
            .filter(|(x, y)| {
                x.is_finite() && y.is_finite() && (!p.log_x || *x > 0.0) && (!p.log_y || *y > 0.0)
            })
            .map(|&(x, y)| (norm(x, x0, x1, p.log_x), norm(y, y0, y1, p.log_y)))
            .collect();
        let mut visit = |(u, v): (f64, f64)| {
            for (k, (_, (ua, ub), (va, vb))) in corners.iter().enumerate() {
                if (*ua..=*ub).contains(&u) && (*va..=*vb).contains(&v) {
                    counts[k] += 1;
                }
            }
        };
        for (k, &q) in pts.iter().enumerate() {
            visit(q);
            if s.line && k + 1 < pts.len() {
                let r = pts[k + 1];
                for i in 1..8 {
                    let f = i as f64 / 8.0;
                    visit((q.0 + f * (r.0 - q.0), q.1 + f * (r.1 - q.1)));
                }
            }
        }
    }
    // Vertical and horizontal reference lines cross the boxes they pass through.
    for &(v, _) in &p.vlines {
        let u = norm(v, x0, x1, p.log_x);
        for (k, (_, (ua, ub), _)) in corners.iter().enumerate() {
            if (*ua..=*ub).contains(&u) {
                counts[k] += 50;
            }
        }
    }
    for &(v, _) in &p.hlines {
        let u = norm(v, y0, y1, p.log_y);
        for (k, (_, _, (va, vb))) in corners.iter().enumerate() {
            if (*va..=*vb).contains(&u) {
                counts[k] += 50;
            }
        }
    }
    let best = (0..4).min_by_key(|&k| counts[k]).unwrap_or(0);
    corners[best].0
}

/// Draws panels in a `rows × cols` grid into an SVG of `size` pixels.
pub fn line_panels(
    path: &Path,
    size: (u32, u32),
    (rows, cols): (usize, usize),
    panels: &[LinePanel],
) -> Result<(), PlotError> {
    let size = (size.0 * S, size.1 * S);
    let root = SVGBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE).map_err(err)?;
    for (area, panel) in root.split_evenly((rows, cols)).iter().zip(panels) {
        draw_line_panel(area, panel)?;
    }
    root.present().map_err(err)?;
    drop(root);
    downscale_header(path, size)
}

fn draw_line_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    p: &LinePanel,
) -> Result<(), PlotError>
where
    DB::ErrorType: 'static,
{
    let xs = p
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(|q| q.0))
        .chain(p.vlines.iter().map(|v| v.0));
    let ys = p
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(|q| q.1))
        .chain(p.hlines.iter().map(|h| h.0));
    let (x0, x1) = p.x_range.unwrap_or_else(|| data_range(xs, p.log_x));
    let (y0, y1) = p.y_range.unwrap_or_else(|| data_range(ys, p.log_y));
    check_range(&format!("`{}`: x", p.title), x0, x1)?;
    check_range(&format!("`{}`: y", p.title), y0, y1)?;
    let mut builder = ChartBuilder::on(area);
    builder
        .caption(&p.title, ("sans-serif", 16 * S))
        .margin(12 * S)
        .x_label_area_size(45 * S)
        .y_label_area_size(70 * S);
    match (p.log_x, p.log_y) {
        (false, false) => fill(
            builder.build_cartesian_2d(x0..x1, y0..y1).map_err(err)?,
            p,
            (x0, x1, y0, y1),
        ),
        (true, false) => fill(
            builder
                .build_cartesian_2d((x0..x1).log_scale(), y0..y1)
                .map_err(err)?,
            p,
            (x0, x1, y0, y1),
        ),
        (false, true) => fill(
            builder
                .build_cartesian_2d(x0..x1, (y0..y1).log_scale())
                .map_err(err)?,
            p,
            (x0, x1, y0, y1),
        ),
        (true, true) => fill(
            builder
                .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
                .map_err(err)?,
            p,
            (x0, x1, y0, y1),
        ),
    }
}

fn fill<'a, DB, X, Y>(
    mut chart: ChartContext<'a, DB, Cartesian2d<X, Y>>,
    p: &LinePanel,
    (x0, x1, y0, y1): (f64, f64, f64, f64),
) -> Result<(), PlotError>
where
    DB: DrawingBackend + 'a,
    DB::ErrorType: 'static,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let (lx, ly, sx, sy) = (p.log_x, p.log_y, x1 - x0, y1 - y0);
    let fx = move |v: &f64| tick_label(*v, lx, sx);
    let fy = move |v: &f64| tick_label(*v, ly, sy);
    chart
        .configure_mesh()
        .light_line_style(WHITE.mix(0.0))
        .bold_line_style(BLACK.mix(0.08))
        .x_label_formatter(&fx)
        .y_label_formatter(&fy)
        .x_desc(p.x_label.as_str())
        .y_desc(p.y_label.as_str())
        .label_style(("sans-serif", 13 * S))
        .axis_desc_style(("sans-serif", 14 * S))
        .draw()
        .map_err(err)?;
    // Reference lines: grey, then dashed-looking darker tones, so that two are told apart.
    let ref_colors = [
        RGBColor(110, 110, 110),
        RGBColor(170, 51, 119),
        RGBColor(34, 136, 51),
    ];
    let lines = p
        .vlines
        .iter()
        .map(|(v, l)| (vec![(*v, y0), (*v, y1)], l))
        .chain(p.hlines.iter().map(|(h, l)| (vec![(x0, *h), (x1, *h)], l)));
    for (k, (pts, label)) in lines.enumerate() {
        let col = ref_colors[k % ref_colors.len()];
        let s = chart
            .draw_series(std::iter::once(PathElement::new(
                pts,
                col.stroke_width(2 * S),
            )))
            .map_err(err)?;
        if !label.is_empty() {
            s.label(label.clone()).legend(move |(x, y)| {
                PathElement::new(
                    vec![(x, y), (x + 18 * S as i32, y)],
                    col.stroke_width(2 * S),
                )
            });
        }
    }
    let mut labelled = !p.vlines.iter().chain(&p.hlines).all(|(_, l)| l.is_empty());
    for s in &p.series {
        let col = color(s.color);
        let pts: Vec<(f64, f64)> = s
            .points
            .iter()
            .copied()
            .filter(|(x, y)| {
                x.is_finite() && y.is_finite() && (!p.log_x || *x > 0.0) && (!p.log_y || *y > 0.0)
            })
            .collect();
        let mut legend_drawn = false;
        if s.line && pts.len() > 1 {
            let series = chart
                .draw_series(LineSeries::new(pts.clone(), col.stroke_width(2 * S)))
                .map_err(err)?;
            if !s.label.is_empty() {
                let marker = s.markers;
                series.label(s.label.clone()).legend(move |(x, y)| {
                    EmptyElement::at((x, y))
                        + PathElement::new(
                            vec![(0, 0), (18 * S as i32, 0)],
                            col.stroke_width(2 * S),
                        )
                        + Circle::new(
                            (9 * S as i32, 0),
                            if marker { 3 * S } else { 0 },
                            col.filled(),
                        )
                });
                legend_drawn = true;
            }
        }
        if s.markers {
            let style = if s.hollow {
                col.stroke_width(2 * S)
            } else {
                col.filled()
            };
            let series = chart
                .draw_series(pts.iter().map(|&q| Circle::new(q, 4 * S, style)))
                .map_err(err)?;
            if !legend_drawn && !s.label.is_empty() {
                series
                    .label(s.label.clone())
                    .legend(move |(x, y)| Circle::new((x + 9 * S as i32, y), 4 * S, style));
            }
        }
        labelled |= !s.label.is_empty();
    }
    if labelled {
        let px = chart.plotting_area().dim_in_pixel();
        let position = match p.legend {
            Legend::Auto => auto_legend(p, (x0, x1, y0, y1), px),
            fixed => fixed,
        };
        draw_legend(&mut chart, position.position())?;
    }
    Ok(())
}
