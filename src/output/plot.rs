//! SVG figures (plotters, SVG backend): scenes like P's Figs. 2–4 (walls, body outlines at
//! regular times fading from old to new, centroid paths, orientation marks, equal aspect), and
//! line panels (time series, log–log reports).

use super::run_data::RunData;
use crate::dynamics::cell::Cell;
use crate::geometry::{Shape, Vec2};
use plotters::coord::Shift;
use plotters::coord::ranged1d::ValueFormatter;
use plotters::coord::types::RangedCoordf64;
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

/// Writes a drawing of `size` units, as plotters left it in `svg`, to `path` (errors do not
/// repeat the file name: the caller names it): the header rewritten
/// to display it at `size / S` pixels; as SVG, or rendered to PNG when the name ends in `.png`
/// (at the drawing's own resolution, `S` pixels per displayed pixel, fit for print).
fn save(path: &Path, svg: &str, size: (u32, u32)) -> Result<(), PlotError> {
    let from = format!("width=\"{}\" height=\"{}\"", size.0, size.1);
    let to = format!("width=\"{}\" height=\"{}\"", size.0 / S, size.1 / S);
    if !svg.contains(&from) {
        return Err(PlotError("unexpected SVG header".into()));
    }
    let svg = svg.replacen(&from, &to, 1);
    let bytes = if is_png(path) {
        png_of_svg(&svg, S as f32).map_err(PlotError)?
    } else {
        svg.into_bytes()
    };
    std::fs::write(path, bytes).map_err(|e| PlotError(format!("cannot write: {e}")))
}

/// True when `path` names a PNG file (`.png`, any case).
pub fn is_png(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"))
}

/// Renders an SVG to PNG bytes at `zoom` pixels per SVG pixel (resvg), on white, with the
/// system's fonts (the SVG's `sans-serif` is the first of DejaVu Sans, Liberation Sans, Arial,
/// Noto Sans that is installed). No font at all is an error: the picture would have no text.
pub fn png_of_svg(svg: &str, zoom: f32) -> Result<Vec<u8>, String> {
    use resvg::{tiny_skia, usvg};
    let mut opt = usvg::Options::default();
    let db = opt.fontdb_mut();
    db.load_system_fonts();
    if db.is_empty() {
        return Err(
            "no font found to render the text (install one, e.g. Debian's fonts-dejavu-core)"
                .into(),
        );
    }
    let families: Vec<String> = db
        .faces()
        .flat_map(|f| f.families.iter().map(|(name, _)| name.clone()))
        .collect();
    if let Some(sans) = ["DejaVu Sans", "Liberation Sans", "Arial", "Noto Sans"]
        .into_iter()
        .find(|want| families.iter().any(|f| f == want))
        .or_else(|| families.first().map(String::as_str))
    {
        let sans = sans.to_string();
        db.set_sans_serif_family(sans);
    }
    let tree = usvg::Tree::from_str(svg, &opt).map_err(|e| format!("cannot read the SVG: {e}"))?;
    let size = tree.size();
    let (w, h) = (
        (size.width() * zoom).ceil() as u32,
        (size.height() * zoom).ceil() as u32,
    );
    let mut pixmap =
        tiny_skia::Pixmap::new(w, h).ok_or_else(|| format!("cannot make a {w}×{h} image"))?;
    pixmap.fill(tiny_skia::Color::WHITE);
    resvg::render(
        &tree,
        tiny_skia::Transform::from_scale(zoom, zoom),
        &mut pixmap.as_mut(),
    );
    pixmap
        .encode_png()
        .map_err(|e| format!("cannot encode the PNG: {e}"))
}

/// The outline of a shape placed at `(x, y)` with angle `angle`, as a closed polygon (vertices
/// as [`super::outline`] places them).
pub fn outline(shape: &Shape, x: f64, y: f64, angle: f64) -> Vec<(f64, f64)> {
    let mut pts = super::outline::polygon(shape, x, y, angle);
    pts.push(pts[0]);
    pts
}

/// One panel of a scene figure: runs drawn on the same axes.
pub struct ScenePanel<'a> {
    pub title: String,
    /// Each run with its legend label (empty: no legend entry).
    pub runs: Vec<(&'a RunData, String)>,
}

/// What colours the bodies of a scene.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ColorBy {
    /// One colour per body when a panel shows one run of few bodies, one per run when it shows
    /// several, and the normal contact force for a snapshot of many bodies.
    #[default]
    Auto,
    /// One colour per body.
    Body,
    /// One colour per run.
    Run,
    /// Speed |v| (a colour scale with its bar).
    Speed,
    /// Angular velocity ω, signed (a diverging scale).
    Omega,
    /// Rotation since the run's first frame, θ − θ₀, signed (a diverging scale).
    Rotation,
    /// The normal contact force on the body, Σ F_n over its contacts, recomputed from the
    /// frame's state ([`super::forces::normal_force_per_body`]).
    Force,
}

impl ColorBy {
    /// The colour-bar label, and whether the quantity is signed (diverging scale); `None` for
    /// the categorical colourings.
    fn quantity(self, units: &str) -> Option<(String, bool)> {
        let speed = if units.is_empty() {
            "speed |v|".to_string()
        } else {
            format!("speed |v| ({units}/s)")
        };
        match self {
            ColorBy::Auto | ColorBy::Body | ColorBy::Run => None,
            ColorBy::Speed => Some((speed, false)),
            ColorBy::Omega => Some(("angular velocity ω (rad/s)".into(), true)),
            ColorBy::Rotation => Some(("rotation θ − θ₀ (rad)".into(), true)),
            // Per unit thickness; dyn when the case is in cgs.
            ColorBy::Force => Some((
                if units == "cm" {
                    "normal contact force ΣFₙ (dyn)".into()
                } else {
                    "normal contact force ΣFₙ".into()
                },
                false,
            )),
        }
    }
}

/// Options of a scene figure.
#[derive(Clone, Debug)]
pub struct SceneOptions {
    /// Draw from this time on (default: the start).
    pub t_min: Option<f64>,
    /// Draw up to this time (default: the whole run).
    pub t_max: Option<f64>,
    /// Number of outlines per body over the time shown (unless `outline_every` is given).
    pub outlines: usize,
    /// Time between outlines (overrides `outlines`).
    pub outline_every: Option<f64>,
    /// Only the last frame of the time shown: outlines, no paths.
    pub last_only: bool,
    /// Figure width in pixels; `None`: 1000, or wider for a snapshot of many small bodies (about
    /// 8 pixels across the smallest body, at most 3000).
    pub width: Option<u32>,
    /// What colours the bodies.
    pub color: ColorBy,
    /// Runs with more bodies than this are drawn as a snapshot: each body's outline at the last
    /// time shown, without paths or earlier outlines (which would bury a pile and make the file
    /// hundreds of megabytes).
    pub snapshot_above: usize,
    /// In a periodic cell, also draw the periodic images of the bodies that a seam cuts (those
    /// that overlap the cell), so that grains at a seam look whole.
    pub images: bool,
    /// The region drawn, `(x0, x1, y0, y1)` (default: what the outlines and walls need): the
    /// frames of a movie share one.
    pub bounds: Option<(f64, f64, f64, f64)>,
    /// The colour scale's range (default: the values drawn): the frames of a movie share one.
    pub color_range: Option<(f64, f64)>,
}

impl Default for SceneOptions {
    fn default() -> Self {
        SceneOptions {
            t_min: None,
            t_max: None,
            outlines: 24,
            outline_every: None,
            last_only: false,
            width: None,
            color: ColorBy::Auto,
            snapshot_above: 100,
            images: false,
            bounds: None,
            color_range: None,
        }
    }
}

/// What is drawn of one run: the frames whose outlines are drawn, the frames its centroid paths
/// run through (empty for a snapshot), and each outline's colour value.
struct Drawn<'a> {
    run: &'a RunData,
    label: String,
    outlines: Vec<usize>,
    path: Vec<usize>,
    /// Per outline frame, per body (empty for categorical colours).
    values: Vec<Vec<f64>>,
    snapshot: bool,
    /// Draw the periodic images of bodies cut by a seam.
    images: bool,
}

/// The offsets of the periodic images of a body of bounding radius `r` at `(x, y)` that
/// overlap `cell` (its bounding box meets the cell's rectangle), the body itself left out: the
/// image `(k_x, k_y)` cells over lies at `(x + k_x L_x + k_y s, y + k_y L_y)`, s the Lees–Edwards
/// offset of the image above (in a cell periodic in x only, k_y = 0 and the rectangle spans
/// every y).
fn image_offsets(cell: &Cell, x: f64, y: f64, r: f64) -> Vec<Vec2> {
    let (lx, ly) = (cell.size.x, cell.size.y);
    let ky_range: &[f64] = if cell.periodic_y() {
        &[-1.0, 0.0, 1.0]
    } else {
        &[0.0]
    };
    let mut out = Vec::new();
    for &ky in ky_range {
        for kx in [-1.0, 0.0, 1.0] {
            if kx == 0.0 && ky == 0.0 {
                continue;
            }
            let o = Vec2::new(kx * lx + ky * cell.offset, ky * ly);
            let (cx, cy) = (x + o.x, y + o.y);
            let meets_x = cx + r > 0.0 && cx - r < lx;
            let meets_y = !cell.periodic_y() || (cy + r > 0.0 && cy - r < ly);
            if meets_x && meets_y {
                out.push(o);
            }
        }
    }
    out
}

/// The part of the plane a cell's outline covers: its rectangle (`"xy"`), or its two seams
/// `x = 0`, `x = L_x` (`"x"`: y unbounded).
fn cell_lines(cell: &Cell, (_, _, y0, y1): (f64, f64, f64, f64)) -> Vec<Vec<(f64, f64)>> {
    let (lx, ly) = (cell.size.x, cell.size.y);
    if cell.periodic_y() {
        vec![vec![(0.0, 0.0), (lx, 0.0), (lx, ly), (0.0, ly), (0.0, 0.0)]]
    } else {
        vec![vec![(0.0, y0), (0.0, y1)], vec![(lx, y0), (lx, y1)]]
    }
}

/// The frames of `run` to draw under `opts`.
fn select<'a>(
    run: &'a RunData,
    label: &str,
    opts: &SceneOptions,
    color: ColorBy,
) -> Result<Drawn<'a>, PlotError> {
    let (t0, t1) = (
        opts.t_min.unwrap_or(f64::NEG_INFINITY),
        opts.t_max.unwrap_or(f64::INFINITY),
    );
    let window: Vec<usize> = (0..run.frames.len())
        .filter(|&i| (t0..=t1).contains(&run.frames[i].t))
        .collect();
    let (Some(&first), Some(&last)) = (window.first(), window.last()) else {
        let (a, b) = (run.frames[0].t, run.frames[run.frames.len() - 1].t);
        return Err(PlotError(format!(
            "{}: no frame between t = {t0} and t = {t1} s (the run's frames are from {a} to {b} s)",
            run.dir.display()
        )));
    };
    let snapshot = opts.last_only || run.most_bodies() > opts.snapshot_above;
    let outlines = if snapshot {
        vec![last]
    } else {
        // Outlines at regular times from the window's first frame, and always its last.
        let span = run.frames[last].t - run.frames[first].t;
        let every = opts
            .outline_every
            .unwrap_or(span / (opts.outlines.max(2) - 1) as f64);
        let mut chosen = Vec::new();
        let mut next = run.frames[first].t;
        for &i in &window {
            if run.frames[i].t + 1e-12 * span.max(1e-300) >= next {
                chosen.push(i);
                next += every.max(1e-300);
            }
        }
        if chosen.last() != Some(&last) {
            chosen.push(last);
        }
        chosen
    };
    let values = match color {
        ColorBy::Speed => outlines
            .iter()
            .map(|&i| {
                run.frames[i]
                    .bodies
                    .iter()
                    .map(|b| b.vx.hypot(b.vy))
                    .collect()
            })
            .collect(),
        ColorBy::Omega => outlines
            .iter()
            .map(|&i| run.frames[i].bodies.iter().map(|b| b.omega).collect())
            .collect(),
        ColorBy::Rotation => outlines
            .iter()
            .map(|&i| {
                // Since the first frame that holds the body (the run's first, but for a body
                // inserted later).
                let f = &run.frames[i];
                f.ids
                    .iter()
                    .zip(&f.bodies)
                    .map(|(&id, b)| {
                        let start = (0..=i)
                            .find_map(|j| run.place(j, id).map(|k| run.frames[j].bodies[k]))
                            .unwrap_or(*b);
                        b.angle - start.angle
                    })
                    .collect()
            })
            .collect(),
        ColorBy::Force => {
            // The run's own forces where it recorded them (`--contacts`).
            let recorded = match run.dir.join("contacts.csv").exists() {
                true => Some(super::analysis::read_contact_frames(&run.dir).map_err(PlotError)?),
                false => None,
            };
            outlines
                .iter()
                .map(|&i| super::forces::normal_force_per_body(run, i, recorded.as_ref()))
                .collect()
        }
        ColorBy::Auto | ColorBy::Body | ColorBy::Run => Vec::new(),
    };
    Ok(Drawn {
        run,
        label: label.to_string(),
        outlines,
        path: if snapshot { Vec::new() } else { window },
        values,
        snapshot,
        images: opts.images && run.case.cell.is_some(),
    })
}

/// The box that holds every outline drawn, extended to axis-aligned walls nearby; equal aspect
/// is applied later.
fn scene_bounds(panels: &[Vec<(Drawn, ColorBy)>]) -> (f64, f64, f64, f64) {
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for (d, _) in panels.iter().flatten() {
        for &i in d.outlines.iter().chain(&d.path) {
            // (With the periodic images drawn at the outlines.)
            let cell = d.run.cell_at(i).filter(|_| d.images);
            for (b, init) in d.run.frames[i].bodies.iter().zip(d.run.inits(i)) {
                let shifts = match &cell {
                    Some(c) => image_offsets(c, b.x, b.y, init.shape.bounding_radius()),
                    None => Vec::new(),
                };
                for s in std::iter::once(Vec2::zeros()).chain(shifts) {
                    for (x, y) in
                        super::outline::polygon(&init.shape, b.x + s.x, b.y + s.y, b.angle)
                    {
                        x0 = x0.min(x);
                        x1 = x1.max(x);
                        y0 = y0.min(y);
                        y1 = y1.max(y);
                    }
                }
            }
        }
    }
    // A periodic cell's rectangle (its x extent in a cell periodic in x only) at every outline.
    for (d, _) in panels.iter().flatten() {
        for &i in &d.outlines {
            if let Some(c) = d.run.cell_at(i) {
                x0 = x0.min(0.0);
                x1 = x1.max(c.size.x);
                if c.periodic_y() {
                    y0 = y0.min(0.0);
                    y1 = y1.max(c.size.y);
                }
            }
        }
    }
    let (w, h) = (x1 - x0, y1 - y0);
    for (d, _) in panels.iter().flatten() {
        let Some(&last) = d.outlines.last() else {
            continue;
        };
        for wall in &d.run.walls_at(last).0 {
            if let Some(dr) = wall.drum() {
                // A drum: the box holds its circle.
                let (c, r) = (dr.center, dr.radius);
                (x0, x1, y0, y1) = (
                    x0.min(c.x - r),
                    x1.max(c.x + r),
                    y0.min(c.y - r),
                    y1.max(c.y + r),
                );
                continue;
            }
            if let Some(seg) = wall.segment() {
                // A segment wall: the box holds it whole.
                for p in [seg.a, seg.b] {
                    (x0, x1, y0, y1) = (x0.min(p.x), x1.max(p.x), y0.min(p.y), y1.max(p.y));
                }
                continue;
            }
            let (pt, n) = (wall.line().point, wall.line().normal);
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
    let (mx, my) = (0.03 * (x1 - x0), 0.05 * (y1 - y0));
    (x0 - mx, x1 + mx, y0 - my, y1 + my)
}

/// The part of the line through `p` with direction `d` inside the box, if any (Liang–Barsky).
pub fn clip_line(p: Vec2, d: Vec2, b: (f64, f64, f64, f64)) -> Option<(Vec2, Vec2)> {
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

/// The fixed parts of a scene panel's layout, in drawing units.
#[derive(Clone, Copy)]
struct SceneLayout {
    left: u32,
    bottom: u32,
    margin: u32,
    /// Width of the colour bar's area on the right (0: none).
    bar: u32,
}

/// The chart of a scene panel on `area` (its left part when there is a colour bar).
fn scene_chart<'a, DB: DrawingBackend + 'a>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    l: SceneLayout,
    (x0, x1, y0, y1): (f64, f64, f64, f64),
) -> Result<ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>, PlotError>
where
    DB::ErrorType: 'static,
{
    let (w, _) = area.dim_in_pixel();
    let chart_area = if l.bar > 0 {
        area.split_horizontally(w.saturating_sub(l.bar)).0
    } else {
        area.clone()
    };
    ChartBuilder::on(&chart_area)
        .caption(title, ("sans-serif", 17 * S))
        .margin(l.margin)
        .x_label_area_size(l.bottom)
        .y_label_area_size(l.left)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(err)
}

/// A panel's plotting area: its pixel spans (x, y) and its top and bottom rows.
type Measured = ((f64, f64), (i32, i32));

/// The plotting area of a scene panel of `size` drawing units: its pixel spans (the number of
/// units from the first to the last pixel, as plotters maps a range) and its top and bottom
/// rows. Measured by laying the panel out on a throw-away SVG: plotters places the caption and
/// label areas itself, so computing them would be a guess (it was: circles came out 6–9 %
/// taller than wide).
fn measure(size: (u32, u32), title: &str, l: SceneLayout) -> Result<Measured, PlotError> {
    let mut sink = String::new();
    let root = SVGBackend::with_string(&mut sink, size).into_drawing_area();
    let chart = scene_chart(&root, title, l, (0.0, 1.0, 0.0, 1.0))?;
    let (xr, yr) = chart.plotting_area().get_pixel_range();
    Ok((
        (
            (xr.end - xr.start - 1) as f64,
            (yr.end - yr.start - 1) as f64,
        ),
        (yr.start, yr.end),
    ))
}

/// Draws a scene figure: panels stacked vertically on common axes at equal scale (a unit of x
/// is as long as a unit of y, to the pixel), into `path` (SVG, or PNG for a `.png` name).
pub fn scene(path: &Path, panels: &[ScenePanel], opts: &SceneOptions) -> Result<(), PlotError> {
    // What is drawn, and how it is coloured.
    let mut drawn = Vec::new();
    for p in panels {
        let mut runs = Vec::new();
        for (run, label) in &p.runs {
            let snapshot = opts.last_only || run.most_bodies() > opts.snapshot_above;
            let color = match opts.color {
                ColorBy::Auto if snapshot && run.most_bodies() > opts.snapshot_above => {
                    ColorBy::Force
                }
                ColorBy::Auto if p.runs.len() > 1 => ColorBy::Run,
                ColorBy::Auto => ColorBy::Body,
                c => c,
            };
            runs.push((select(run, label, opts, color)?, color));
        }
        drawn.push(runs);
    }
    let color = drawn
        .iter()
        .flatten()
        .map(|d: &(Drawn, ColorBy)| d.1)
        .find(|c| c.quantity("").is_some())
        .unwrap_or(ColorBy::Body);
    let units = panels
        .iter()
        .flat_map(|p| p.runs.first())
        .map(|(r, _)| r.case.units.clone())
        .next()
        .unwrap_or_default();
    let scale = color
        .quantity(&units)
        .map(|(label, signed)| match opts.color_range {
            Some((lo, hi)) => ColorScale::new(label, signed, [lo, hi].into_iter()),
            None => {
                let vals = drawn
                    .iter()
                    .flatten()
                    .flat_map(|d| d.0.values.iter().flatten().copied());
                ColorScale::new(label, signed, vals)
            }
        });

    let (mut x0, mut x1, mut y0, mut y1) = opts.bounds.unwrap_or_else(|| scene_bounds(&drawn));
    check_range("the scene's x", x0, x1)?;
    check_range("the scene's y", y0, y1)?;
    let layout = SceneLayout {
        left: 60 * S,
        bottom: 45 * S,
        margin: 12 * S,
        bar: scale
            .as_ref()
            .map_or(0, |s| (10 + 40 + 16) * S + s.label_area()),
    };
    let width = S * opts.width.unwrap_or_else(|| {
        // A snapshot: about 8 pixels across the smallest body.
        let smallest = drawn
            .iter()
            .flatten()
            .filter(|d| d.0.snapshot)
            .flat_map(|d| d.0.outlines.iter().flat_map(|&i| d.0.run.inits(i)))
            .map(|b| 2.0 * b.shape.inscribed_radius())
            .fold(f64::INFINITY, f64::min);
        let want = 8.0 * (x1 - x0) / smallest + 100.0;
        if want.is_finite() {
            want.clamp(1000.0, 3000.0) as u32
        } else {
            1000
        }
    });
    let title0 = panels.first().map_or("", |p| p.title.as_str());
    // The panel height that gives the plotting area the data's aspect: measure the layout's
    // fixed parts once, then size the panel so the plot fits, within sensible heights.
    let guess = 600 * S;
    let ((pw, ph), _) = measure((width, guess), title0, layout)?;
    let fixed_h = guess as f64 - ph;
    let mut want_h = pw * (y1 - y0) / (x1 - x0);
    let (min_h, max_h) = (150.0 * S as f64, 900.0 * S as f64);
    if want_h < min_h {
        // Grow upwards mostly: scenes usually stand on a floor.
        let grow = (min_h / want_h - 1.0) * (y1 - y0);
        (y0, y1) = (y0 - 0.1 * grow, y1 + 0.9 * grow);
        want_h = min_h;
    } else if want_h > max_h {
        let grow = (want_h / max_h - 1.0) * (x1 - x0) / 2.0;
        (x0, x1) = (x0 - grow, x1 + grow);
        want_h = max_h;
    }
    let panel_h = (want_h + fixed_h).round() as u32;
    // Equal scale to the pixel: the plotting area as it will be, and the ranges widened (x
    // about its centre, y upwards) until both axes have the same units per pixel.
    let ((pw, ph), _) = measure((width, panel_h), title0, layout)?;
    let per_px = ((x1 - x0) / pw).max((y1 - y0) / ph);
    let xc = 0.5 * (x0 + x1);
    (x0, x1) = (xc - 0.5 * per_px * pw, xc + 0.5 * per_px * pw);
    y1 = y0 + per_px * ph;
    let bounds = (x0, x1, y0, y1);

    let height = panel_h * panels.len() as u32;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let areas = root.split_evenly((panels.len(), 1));
        for ((area, panel), runs) in areas.iter().zip(panels).zip(&drawn) {
            let (_, (top, bottom)) = measure((width, panel_h), &panel.title, layout)?;
            let mut chart = scene_chart(area, &panel.title, layout, bounds)?;
            draw_scene_panel(&mut chart, runs, scale.as_ref(), &units, bounds)?;
            if let Some(scale) = &scale {
                let (w, _) = area.dim_in_pixel();
                let bar_area = area.split_horizontally(w - layout.bar).1;
                draw_color_bar(&bar_area, scale, (top, bottom))?;
            }
        }
        root.present().map_err(err)?;
    }
    save(path, &svg, (width, height))
}

/// A colour scale: sequential (viridis, from the smallest value to the largest) or, for a
/// signed quantity, diverging (blue–white–red, symmetric about zero).
struct ColorScale {
    label: String,
    signed: bool,
    lo: f64,
    hi: f64,
}

impl ColorScale {
    fn new(label: String, signed: bool, values: impl Iterator<Item = f64>) -> ColorScale {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for v in values.filter(|v| v.is_finite()) {
            lo = lo.min(v);
            hi = hi.max(v);
        }
        if !lo.is_finite() {
            (lo, hi) = (0.0, 1.0);
        }
        if signed {
            let m = lo.abs().max(hi.abs());
            (lo, hi) = (-m, m);
        }
        if hi - lo <= 1e-12 * hi.abs().max(lo.abs()) {
            // A constant (e.g. no contact at all): a unit-wide scale around it.
            (lo, hi) = (lo - 0.5, hi + 0.5);
        }
        ColorScale {
            label,
            signed,
            lo,
            hi,
        }
    }

    /// Width of the bar's label area: its widest tick label (13-point digits are about 8 units
    /// wide) and the rotated title beside it, so that the two never overlap.
    fn label_area(&self) -> u32 {
        let span = self.hi - self.lo;
        let widest = (0..=20)
            .map(|k| {
                tick_label(self.lo + span * k as f64 / 20.0, false, span)
                    .chars()
                    .count()
            })
            .max()
            .unwrap_or(1) as u32;
        (widest * 8 + 34) * S
    }

    fn color(&self, v: f64) -> RGBColor {
        let f = ((v - self.lo) / (self.hi - self.lo)).clamp(0.0, 1.0);
        let stops: &[(f64, (u8, u8, u8))] = if self.signed {
            // Moreland's cool–warm diverging map (blue, light grey, red).
            &[
                (0.0, (59, 76, 192)),
                (0.25, (141, 176, 254)),
                (0.5, (221, 221, 221)),
                (0.75, (244, 154, 123)),
                (1.0, (180, 4, 38)),
            ]
        } else {
            // Viridis at eight stops.
            &[
                (0.0, (68, 1, 84)),
                (0.143, (70, 50, 127)),
                (0.286, (54, 92, 141)),
                (0.429, (39, 127, 142)),
                (0.571, (31, 161, 135)),
                (0.714, (74, 193, 109)),
                (0.857, (160, 218, 57)),
                (1.0, (253, 231, 37)),
            ]
        };
        let k = stops
            .windows(2)
            .position(|w| f <= w[1].0)
            .unwrap_or(stops.len() - 2);
        let ((fa, a), (fb, b)) = (stops[k], stops[k + 1]);
        let t = ((f - fa) / (fb - fa)).clamp(0.0, 1.0);
        let mix = |p: u8, q: u8| (p as f64 + t * (q as f64 - p as f64)).round() as u8;
        RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
    }
}

/// A vertical colour bar with its ticks and label, spanning the rows `top..bottom` of `area`.
fn draw_color_bar<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    scale: &ColorScale,
    (top, bottom): (i32, i32),
) -> Result<(), PlotError>
where
    DB::ErrorType: 'static,
{
    let (_, h) = area.dim_in_pixel();
    let mut chart = ChartBuilder::on(area)
        .margin_top(top.max(0) as u32)
        .margin_bottom((h as i32 - bottom).max(0) as u32)
        .margin_left(10 * S)
        .margin_right(16 * S)
        .set_label_area_size(LabelAreaPosition::Right, scale.label_area())
        .build_cartesian_2d(0f64..1f64, scale.lo..scale.hi)
        .map_err(err)?;
    let span = scale.hi - scale.lo;
    let fy = move |v: &f64| tick_label(*v, false, span);
    chart
        .configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_label_formatter(&fy)
        .y_desc(scale.label.as_str())
        .label_style(("sans-serif", 13 * S))
        .axis_desc_style(("sans-serif", 14 * S))
        .draw()
        .map_err(err)?;
    let steps = 128;
    chart
        .draw_series((0..steps).map(|k| {
            let (a, b) = (
                scale.lo + span * k as f64 / steps as f64,
                scale.lo + span * (k + 1) as f64 / steps as f64,
            );
            Rectangle::new([(0.0, a), (0.45, b)], scale.color(0.5 * (a + b)).filled())
        }))
        .map_err(err)?;
    Ok(())
}

type SceneChart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

fn draw_scene_panel<'a, DB: DrawingBackend + 'a>(
    chart: &mut SceneChart<'a, DB>,
    runs: &[(Drawn, ColorBy)],
    scale: Option<&ColorScale>,
    units: &str,
    (x0, x1, y0, y1): (f64, f64, f64, f64),
) -> Result<(), PlotError>
where
    DB::ErrorType: 'static,
{
    let unit = |axis: &str| {
        if units.is_empty() {
            axis.to_string()
        } else {
            format!("{axis} ({units})")
        }
    };
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
    // Walls where they are at the last outline drawn: a thick line with hatching on the solid
    // side; a moving wall also thin and faint where it was at the earlier outlines.
    if let Some((d, _)) = runs.first()
        && let Some(&last) = d.outlines.last()
    {
        let now = d.run.walls_at(last).0;
        for &o in &d.outlines[..d.outlines.len() - 1] {
            for (w, then) in now.iter().zip(d.run.walls_at(o).0) {
                if (then.line().point == w.line().point && then.angle() == w.angle())
                    || then.drum().is_some()
                {
                    continue;
                }
                let t = Vec2::new(-then.line().normal.y, then.line().normal.x);
                let drawn = match then.segment() {
                    Some(seg) => Some((seg.a, seg.b)),
                    None => clip_line(then.line().point, t, bounds),
                };
                if let Some((a, b)) = drawn {
                    chart
                        .draw_series(std::iter::once(PathElement::new(
                            vec![(a.x, a.y), (b.x, b.y)],
                            BLACK.mix(0.25).stroke_width(S),
                        )))
                        .map_err(err)?;
                }
            }
        }
        for w in &now {
            if let Some(dr) = w.drum() {
                // A drum: its circle, thick, with a radius marking how far it has turned.
                let (c, r) = (dr.center, dr.radius);
                let circle: Vec<(f64, f64)> = (0..=256)
                    .map(|i| {
                        let a = std::f64::consts::TAU * i as f64 / 256.0;
                        (c.x + r * a.cos(), c.y + r * a.sin())
                    })
                    .collect();
                chart
                    .draw_series(std::iter::once(PathElement::new(
                        circle,
                        BLACK.stroke_width(2 * S),
                    )))
                    .map_err(err)?;
                let (sn, cs) = (w.angle() - std::f64::consts::FRAC_PI_2).sin_cos();
                chart
                    .draw_series(std::iter::once(PathElement::new(
                        vec![
                            (c.x + 0.9 * r * cs, c.y + 0.9 * r * sn),
                            (c.x + r * cs, c.y + r * sn),
                        ],
                        BLACK.stroke_width(2 * S),
                    )))
                    .map_err(err)?;
                continue;
            }
            if let Some(seg) = w.segment() {
                // A segment wall: both sides solid, a thick line without hatching.
                chart
                    .draw_series(std::iter::once(PathElement::new(
                        vec![(seg.a.x, seg.a.y), (seg.b.x, seg.b.y)],
                        BLACK.stroke_width(2 * S),
                    )))
                    .map_err(err)?;
                continue;
            }
            let (n, t) = (
                w.line().normal,
                Vec2::new(-w.line().normal.y, w.line().normal.x),
            );
            if let Some((a, b)) = clip_line(w.line().point, t, bounds) {
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
    let several = runs.len() > 1;
    let mut legend = false;
    for (ri, (d, by)) in runs.iter().enumerate() {
        let run = d.run;
        // The colour of body k's outline number `o`, where it is the frame's body `at`.
        let pick = |k: usize, at: usize, o: usize| match (scale, d.values.get(o)) {
            (Some(s), Some(v)) => s.color(v[at]),
            _ if *by == ColorBy::Body => color(k),
            _ => color(ri),
        };
        let key = if d.values.is_empty() && *by != ColorBy::Body {
            Some(color(ri))
        } else {
            None
        };
        let (Some(&first), Some(&last)) = (d.outlines.first(), d.outlines.last()) else {
            continue;
        };
        if d.snapshot {
            let f = &run.frames[last];
            let o = d.outlines.len() - 1;
            let cell = run.cell_at(last).filter(|_| d.images);
            let polygons = run.inits(last).enumerate().flat_map(|(k, init)| {
                let b = f.bodies[k];
                let shifts = match &cell {
                    Some(c) => image_offsets(c, b.x, b.y, init.shape.bounding_radius()),
                    None => Vec::new(),
                };
                std::iter::once(Vec2::zeros())
                    .chain(shifts)
                    .map(move |s| (k, outline(&init.shape, b.x + s.x, b.y + s.y, b.angle)))
            });
            if d.values.is_empty() {
                chart
                    .draw_series(
                        polygons.map(|(k, p)| PathElement::new(p, pick(k, k, o).stroke_width(S))),
                    )
                    .map_err(err)?;
            } else {
                // Filled by the value, each with a thin dark rim so that neighbours of one
                // colour stay apart.
                let polygons: Vec<_> = polygons.collect();
                chart
                    .draw_series(
                        polygons.iter().map(|(k, p)| {
                            Polygon::new(&p[..p.len() - 1], pick(*k, *k, o).filled())
                        }),
                    )
                    .map_err(err)?;
                chart
                    .draw_series(polygons.into_iter().map(|(_, p)| {
                        PathElement::new(p, RGBColor(40, 40, 40).mix(0.7).stroke_width(1))
                    }))
                    .map_err(err)?;
            }
            if let (true, Some(col)) = (several && !d.label.is_empty(), key) {
                chart
                    .draw_series(std::iter::empty::<PathElement<(f64, f64)>>())
                    .map_err(err)?
                    .label(d.label.clone())
                    .legend(move |(x, y)| {
                        PathElement::new(
                            vec![(x, y), (x + 18 * S as i32, y)],
                            col.stroke_width(2 * S),
                        )
                    });
                legend = true;
            }
            continue;
        }
        let (t_first, t_last) = (run.frames[first].t, run.frames[last].t);
        let span = (t_last - t_first).max(1e-300);
        // Each body drawn, by identity (`0 … n − 1` in a case whose bodies stay; else those of
        // the frames drawn, each over the frames that hold it).
        for (nth, id) in run.ids_in(&d.path).into_iter().enumerate() {
            let k = id as usize;
            let init = run.init(id);
            // Centroid path: the body's or run's colour; dark grey under a colour scale.
            let path_col = if d.values.is_empty() {
                pick(k, k, 0)
            } else {
                RGBColor(90, 90, 90)
            };
            // In a periodic cell the path breaks where the body re-entered the cell (its image
            // counts changed), instead of crossing it.
            // It breaks too where the body is not in a frame (inserted later, or removed).
            let mut pieces: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
            let mut images_before = None;
            for &i in &d.path {
                let f = &run.frames[i];
                let Some(at) = run.place(i, id) else {
                    if pieces.last().is_some_and(|p| !p.is_empty()) {
                        pieces.push(Vec::new());
                    }
                    continue;
                };
                let images = f.images.get(at).copied();
                if images_before.is_some() && images != images_before {
                    pieces.push(Vec::new());
                }
                images_before = images;
                pieces
                    .last_mut()
                    .expect("a piece")
                    .push((f.bodies[at].x, f.bodies[at].y));
            }
            pieces.retain(|p| !p.is_empty());
            let mut series = None;
            for piece in pieces {
                series = Some(
                    chart
                        .draw_series(LineSeries::new(piece, path_col.mix(0.9).stroke_width(S)))
                        .map_err(err)?,
                );
            }
            let series = series.expect("one piece at least");
            if let (true, 0, Some(col)) = (several && !d.label.is_empty(), nth, key) {
                series.label(d.label.clone()).legend(move |(x, y)| {
                    PathElement::new(
                        vec![(x, y), (x + 18 * S as i32, y)],
                        col.stroke_width(2 * S),
                    )
                });
                legend = true;
            }
            // Outlines at the chosen times, older ones fainter, with an orientation mark.
            let r = init.shape.bounding_radius();
            for (o, &fi) in d.outlines.iter().enumerate() {
                let f = &run.frames[fi];
                let Some(at) = run.place(fi, id) else {
                    continue;
                };
                let b = f.bodies[at];
                let age = (f.t - t_first) / span;
                let alpha = if d.values.is_empty() {
                    0.15 + 0.85 * age
                } else {
                    // The colour carries the value: fading would change it.
                    1.0
                };
                let style =
                    pick(k, at, o)
                        .mix(alpha)
                        .stroke_width(if fi == last { 2 * S } else { S });
                // The body, and its images across the seams that cut it.
                let shifts = match run.cell_at(fi).filter(|_| d.images) {
                    Some(c) => image_offsets(&c, b.x, b.y, r),
                    None => Vec::new(),
                };
                for s in std::iter::once(Vec2::zeros()).chain(shifts) {
                    let (x, y) = (b.x + s.x, b.y + s.y);
                    chart
                        .draw_series(std::iter::once(PathElement::new(
                            outline(&init.shape, x, y, b.angle),
                            style,
                        )))
                        .map_err(err)?;
                    let tip = (x + 0.8 * r * b.angle.cos(), y + 0.8 * r * b.angle.sin());
                    chart
                        .draw_series(std::iter::once(PathElement::new(vec![(x, y), tip], style)))
                        .map_err(err)?;
                }
            }
        }
    }
    // A periodic cell's outline at the last outline drawn (blue, over the bodies), and faint where it was at the
    // earlier ones when its size changed (an imposed pressure).
    if let Some((d, _)) = runs.first()
        && let Some(&last) = d.outlines.last()
        && let Some(now) = d.run.cell_at(last)
    {
        let cell_colour = RGBColor(40, 90, 200);
        for &o in &d.outlines[..d.outlines.len() - 1] {
            if let Some(then) = d.run.cell_at(o)
                && then.size != now.size
            {
                chart
                    .draw_series(
                        cell_lines(&then, bounds)
                            .into_iter()
                            .map(|l| PathElement::new(l, cell_colour.mix(0.25).stroke_width(S))),
                    )
                    .map_err(err)?;
            }
        }
        chart
            .draw_series(
                cell_lines(&now, bounds)
                    .into_iter()
                    .map(|l| PathElement::new(l, cell_colour.stroke_width(2 * S))),
            )
            .map_err(err)?;
    }
    if legend {
        draw_legend(chart, SeriesLabelPosition::UpperRight)?;
    }
    Ok(())
}

/// A box in pixels: left, top, width, height.
#[derive(Clone, Copy, Debug, PartialEq)]
struct LabelBox {
    x: i32,
    y: i32,
    w: i32,
    h: i32,
}

impl LabelBox {
    fn new(x: i32, y: i32, w: i32, h: i32) -> Self {
        LabelBox { x, y, w, h }
    }

    fn overlaps(&self, o: &LabelBox) -> bool {
        self.x < o.x + o.w && o.x < self.x + self.w && self.y < o.y + o.h && o.y < self.y + self.h
    }
}

/// Where the label `text` of the point at pixel `at` goes, as the offset of its top-left corner
/// from the point: the first of eight places around it (upper right first) whose box overlaps
/// none of `boxes` (the markers and the labels placed so far), which it then joins; `None`
/// when every place overlaps something. 12-point text: about 7 units per character, 12 high.
fn place_label(at: (i32, i32), text: &str, boxes: &mut Vec<LabelBox>) -> Option<(i32, i32)> {
    let s = S as i32;
    let (w, h) = (7 * s * text.chars().count() as i32, 12 * s);
    let gap = 5 * s;
    let candidates = [
        (gap, -h - gap / 2),
        (gap, gap / 2),
        (-gap - w, -h - gap / 2),
        (-gap - w, gap / 2),
        (gap + s, -h / 2),
        (-gap - s - w, -h / 2),
        (-w / 2, -h - gap - s),
        (-w / 2, gap + s),
    ];
    for (dx, dy) in candidates {
        let b = LabelBox::new(at.0 + dx, at.1 + dy, w, h);
        if !boxes.iter().any(|o| o.overlaps(&b)) {
            boxes.push(b);
            return Some((dx, dy));
        }
    }
    None
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
    /// Text drawn beside each point (empty: none); index k labels `points[k]`.
    pub point_labels: Vec<String>,
    /// Vertical error bars (empty: none): `points[k]` ± `y_errors[k]`.
    pub y_errors: Vec<f64>,
}

impl Series {
    /// A line of `points` in colour `color` (no markers).
    pub fn line(label: impl Into<String>, points: Vec<(f64, f64)>, color: usize) -> Series {
        Series {
            label: label.into(),
            points,
            color,
            line: true,
            ..Default::default()
        }
    }
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
    let decimals = (1.0 - (span / 10.0).log10().floor()).clamp(0.0, 12.0) as usize;
    if span >= 1e5 {
        // Large values in exponent form too: `4.5e5`, not `450000` (long labels run into the
        // axis title); rounded to the ticks' step.
        let unit = 10f64.powf((span / 10.0).log10().floor());
        let r = (v / unit).round() * unit;
        let digits = (r.abs().log10().floor() - unit.log10()).max(0.0) as usize;
        let text = format!("{r:.digits$e}");
        let (mantissa, exp) = text.split_once('e').unwrap_or((&text, "0"));
        let mantissa = match mantissa.contains('.') {
            true => mantissa.trim_end_matches('0').trim_end_matches('.'),
            false => mantissa,
        };
        return format!("{mantissa}e{exp}");
    }
    if decimals > 4 {
        // Small values in exponent form: `4e-6`, `1.2e-5`, not `0.000004`.
        let scale = 10f64.powi(decimals as i32);
        return format!("{:e}", (v * scale).round() / scale);
    }
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
        let far = lo.abs().max(hi.abs());
        // One value (or a spread too small to draw, see `check_range`): a band of ±5 % of its
        // magnitude about it (±0.05 about 0). A study over one aspect ratio drew such a series
        // and panicked (issue 41).
        let pad = if hi - lo > 1e-9 * far {
            0.05 * (hi - lo).max(1e-12 * hi.abs().max(1.0))
        } else if far > 0.0 {
            0.05 * far
        } else {
            0.05
        };
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
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        for (area, panel) in root.split_evenly((rows, cols)).iter().zip(panels) {
            draw_line_panel(area, panel)?;
        }
        root.present().map_err(err)?;
    }
    save(path, &svg, size)
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
    // (Each point's error bar included.)
    let ys = p
        .series
        .iter()
        .flat_map(|s| {
            s.points.iter().enumerate().flat_map(|(k, q)| {
                let e = s.y_errors.get(k).copied().unwrap_or(0.0);
                [q.1 - e, q.1 + e]
            })
        })
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
    let shown = |&(x, y): &(f64, f64)| {
        x.is_finite() && y.is_finite() && (!p.log_x || x > 0.0) && (!p.log_y || y > 0.0)
    };
    // Point labels are placed beside their points where they overlap no other label and no
    // marker of any series (a label that fits nowhere is left out rather than drawn over
    // another).
    let mut boxes: Vec<LabelBox> = p
        .series
        .iter()
        .filter(|s| s.markers)
        .flat_map(|s| s.points.iter().filter(|q| shown(q)))
        .map(|q| {
            let (x, y) = chart.backend_coord(q);
            let r = 4 * S as i32;
            LabelBox::new(x - r, y - r, 2 * r, 2 * r)
        })
        .collect();
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
        if !s.y_errors.is_empty() {
            chart
                .draw_series(
                    s.points
                        .iter()
                        .zip(&s.y_errors)
                        .filter(|(q, e)| shown(q) && e.is_finite())
                        .map(|(&(x, y), &e)| {
                            ErrorBar::new_vertical(
                                x,
                                y - e,
                                y,
                                y + e,
                                col.stroke_width(2 * S),
                                10 * S,
                            )
                        }),
                )
                .map_err(err)?;
        }
        if !s.point_labels.is_empty() {
            let font = ("sans-serif", 12 * S).into_font().color(&col);
            let mut placed = Vec::new();
            for (&q, l) in s
                .points
                .iter()
                .zip(&s.point_labels)
                .filter(|(q, _)| shown(q))
            {
                let at = chart.backend_coord(&q);
                if let Some(offset) = place_label(at, l, &mut boxes) {
                    placed.push((q, l.clone(), offset));
                }
            }
            chart
                .draw_series(
                    placed.into_iter().map(|(q, l, offset)| {
                        EmptyElement::at(q) + Text::new(l, offset, font.clone())
                    }),
                )
                .map_err(err)?;
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 29, item 13: the representation figure's point labels (`3d`, `5d`, `16`, `17d` of
    /// points a few pixels apart) were drawn over each other. Labels are now placed where they
    /// overlap no other label and no marker, or left out.
    #[test]
    fn periodic_images_are_those_that_overlap_the_cell_with_the_lees_edwards_offset() {
        use crate::dynamics::cell::{Cell, Periodic};
        let mut c = Cell::new(Vec2::new(10.0, 8.0), Periodic::XY, 1.0, None);
        c.offset = 3.0;
        // Near the top-right corner: its image one cell left, and the one below (shifted back
        // by the offset: (9.5 − 3, 7.6 − 8)); the one below-left lies outside.
        let mut got = image_offsets(&c, 9.5, 7.6, 1.0);
        got.sort_by(|a, b| a.x.total_cmp(&b.x));
        assert_eq!(got, vec![Vec2::new(-10.0, 0.0), Vec2::new(-3.0, -8.0)]);
        // In the middle: none.
        assert!(image_offsets(&c, 5.0, 4.0, 1.0).is_empty());
        // Periodic in x only: no image in y.
        let x = Cell::new(Vec2::new(10.0, 8.0), Periodic::X, 0.0, None);
        assert_eq!(
            image_offsets(&x, 9.5, 7.6, 1.0),
            vec![Vec2::new(-10.0, 0.0)]
        );
    }

    #[test]
    fn bug_point_labels_were_drawn_over_each_other() {
        // A tight cluster of 12 points (3 pixels apart) and a few apart from it.
        let points: Vec<(i32, i32)> = (0..12)
            .map(|k| (400 + 3 * (k % 4), 300 + 3 * (k / 4)))
            .chain([(100, 100), (700, 500), (130, 100)])
            .collect();
        let r = 4 * S as i32;
        let mut boxes: Vec<LabelBox> = points
            .iter()
            .map(|&(x, y)| LabelBox::new(x - r, y - r, 2 * r, 2 * r))
            .collect();
        let markers = boxes.len();
        let mut placed = 0;
        for (k, &at) in points.iter().enumerate() {
            if place_label(at, &format!("{k}d"), &mut boxes).is_some() {
                placed += 1;
            }
        }
        // No two boxes (markers and labels) overlap but marker with marker.
        for (i, a) in boxes.iter().enumerate() {
            for b in &boxes[(i + 1).max(markers)..] {
                assert!(!a.overlaps(b), "{a:?} and {b:?}");
            }
        }
        // The lone points all get theirs; the cluster gets several (a place on each side).
        assert!(placed >= 3 + 4, "{placed} placed");
        assert_eq!(boxes.len(), markers + placed);
    }

    /// Issue 29, item 5: the force colour bar's tick labels (`900000000`) ran into its title.
    /// Large values are written in exponent form, and the label area is as wide as the widest
    /// label plus the title.
    #[test]
    fn bug_colour_bar_tick_labels_ran_into_its_title() {
        let span = 9e8;
        for (v, want) in [
            (9e8, "9e8"),
            (4.5e8, "4.5e8"),
            (1e8, "1e8"),
            (5e7, "5e7"),
            (0.0, "0"),
        ] {
            assert_eq!(tick_label(v, false, span), want);
        }
        let scale = ColorScale::new("force".into(), false, [1e3, 9e8].into_iter());
        let widest = (0..=20)
            .map(|k| {
                tick_label(
                    scale.lo + (scale.hi - scale.lo) * k as f64 / 20.0,
                    false,
                    9e8,
                )
            })
            .map(|s| s.chars().count() as u32)
            .max()
            .unwrap();
        // 13-point digits are under 8 units wide; the rotated title needs about 20 more.
        assert!(scale.label_area() >= (widest * 8 + 20) * S);
        // Small spans keep their plain decimals.
        assert_eq!(tick_label(2.5, false, 10.0), "2.5");
        assert_eq!(tick_label(45000.0, false, 5e4), "45000");
    }
}
