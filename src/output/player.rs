//! `dem2d animate`: a run as one self-contained HTML file that plays in any browser
//! ([`write_player`]), or as a movie through ffmpeg ([`write_movie`]).
//!
//! # The player
//! One file: the page (`player.html`, compiled in), its script inline and the run's frames as
//! data inside it — no network, no external script (a Content-Security-Policy of
//! `default-src 'none'` forbids the page any load). It draws every output frame (or every N-th,
//! `--every`) with true outlines: circles and ellipses as the canvas's arcs and ellipses, the
//! other shapes as their outlines' vertices ([`super::outline::body_frame_vertices`]: a
//! rectangle's or polygon's corners, a clump's exposed arcs); the walls where `walls.csv` put
//! them at each frame (a half-plane as a line across the view, hatched on its solid side; a
//! segment as itself); a periodic cell's outline and the images of the bodies its seams cut; and,
//! when the run recorded `contacts.csv`, the contact network (a line per contact, from centroid to
//! centroid across the seams, or to the point of a wall contact, as wide as its normal force).
//! Controls: play/pause (space), a time slider (← → step a frame), speed (frames per second),
//! colour by speed, spin, angle (mod π for ellipses and rectangles, mod 2π otherwise), material,
//! body identity or — with `contacts.csv` — the normal contact force on the body `ΣF_n`;
//! zoom (wheel, + −) and pan (drag); `f` or a double click fits the scene. A click shows the
//! body under it (its identity, shape, material, state) and follows it by identity.
//!
//! A sequential colour scale runs from 0 to the 99th percentile of the run's values (of the
//! frame's, with "scale per frame"), a signed one symmetrically about 0 to the 99th percentile
//! of |value|: a few grains flung out at the start do not turn every other one the bottom colour.
//!
//! The page opens at the first frame and plays; `#frame=K` in the address opens it paused at
//! frame K (0-based; `last` the last), `#color=NAME` chooses the colouring, `#network` shows
//! the contact forces, `#size=WxH` draws on a canvas of that size whatever the window
//! (screenshots). The canvas says where it draws (`data-view="s,x0,y0"`: a point (x, y) in cm
//! is at page pixel `(x0 + s x, y0 − s y)`) and which frame (`data-frame`), for tests.
//!
//! # The data
//! Each body is drawn by identity (`trajectory.csv`'s `body`), never by its place in a frame,
//! so that a body removed by an outflow or inserted later keeps its shape. Positions, angles and
//! velocities are stored as 32-bit floats (7 significant digits: a few 1e-5 cm on a 500 cm
//! scene), base64-encoded: about 32 bytes per body per frame (a pile of 10⁴ bodies over 100
//! frames: 32 MB), and 20 bytes per contact per frame.

use super::plot::{self, ColorBy, SceneOptions, ScenePanel};
use super::run_data::RunData;
use super::trace::WriteError;
use super::vtk::base64;
use serde_json::{Value, json};
use std::path::Path;

/// The page; `/*DATA*/` and `__TITLE__` are filled in.
const PAGE: &str = include_str!("player.html");

/// The frames of `run` kept with every `every`-th: 0, every, 2·every, … and always the last.
pub fn thin(run: &RunData, every: usize) -> Vec<usize> {
    let n = run.frames.len();
    let mut out: Vec<usize> = (0..n).step_by(every.max(1)).collect();
    if out.last() != Some(&(n - 1)) {
        out.push(n - 1);
    }
    out
}

fn f32s(v: &[f32]) -> String {
    let bytes: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
    let mut s = String::new();
    base64(&bytes, &mut s);
    s
}

fn u32s(v: &[u32]) -> String {
    let bytes: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
    let mut s = String::new();
    base64(&bytes, &mut s);
    s
}

/// The player's data for frames `frames` of `run`: the JSON object the page reads (see the
/// module documentation; its script names each field).
pub fn player_data(run: &RunData, frames: &[usize]) -> Result<Value, String> {
    // The body table: every identity shown, increasing; each with its shape (a table of the
    // distinct outlines), material and bounding radius.
    let ids = run.ids_in(frames);
    let mut shapes: Vec<Value> = Vec::new();
    let mut shape_keys: std::collections::HashMap<String, usize> = Default::default();
    let (mut body_shape, mut material, mut radius, mut kind) = (vec![], vec![], vec![], vec![]);
    for &id in &ids {
        let init = run.init(id);
        let s = &init.shape;
        let entry = match s.ellipse_semi_axes() {
            Some((a, b)) => json!({ "e": [a, b] }),
            None => {
                let v: Vec<f64> = super::outline::body_frame_vertices(s)
                    .into_iter()
                    .flat_map(|(x, y)| [x, y])
                    .collect();
                json!({ "p": v })
            }
        };
        // Bodies of one shape share its outline (a pile of one polygon, one clump).
        let key = entry.to_string();
        let n = shapes.len();
        let at = *shape_keys.entry(key).or_insert(n);
        if at == n {
            shapes.push(entry);
        }
        body_shape.push(at);
        material.push(init.material);
        radius.push(s.bounding_radius());
        kind.push(s.type_name());
    }
    // Where each identity sits in the body table.
    let table = |id: u64| ids.binary_search(&id).expect("every identity shown") as u32;
    let flows = run.case.flow.is_some();
    let (mut state, mut index, mut count) = (Vec::new(), Vec::new(), Vec::new());
    let (mut times, mut walls, mut cells) = (Vec::new(), Vec::new(), Vec::new());
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for &k in frames {
        let f = &run.frames[k];
        count.push(f.bodies.len());
        times.push(json!({ "step": f.step, "t": f.t }));
        for (&id, b) in f.ids.iter().zip(&f.bodies) {
            state.extend([b.x, b.y, b.angle, b.vx, b.vy, b.omega].map(|v| v as f32));
            if flows {
                index.push(table(id));
            }
        }
        let (ws, _) = run.walls_at(k);
        let mut w: Vec<f64> = Vec::new();
        for wall in &ws {
            if let Some(d) = wall.drum() {
                w.extend([2.0, d.center.x, d.center.y, d.radius, wall.angle()]);
                continue;
            }
            match wall.segment() {
                Some(s) => w.extend([1.0, s.a.x, s.a.y, s.b.x, s.b.y]),
                None => {
                    let (p, n) = (wall.line().point, wall.line().normal);
                    w.extend([0.0, p.x, p.y, n.x, n.y]);
                }
            }
        }
        walls.push(w);
        let cell = run.cell_at(k);
        if let Some(c) = &cell {
            cells.push(json!([
                c.size.x,
                c.size.y,
                c.offset,
                u8::from(c.periodic_y())
            ]));
        }
        // The view fits what the LAMMPS dump's box holds at every frame.
        let bodies = super::dump::run_bodies(run, k);
        let bx = super::dump::dump_box(&bodies, &ws, cell.as_ref());
        x0 = x0.min(bx.x[0]);
        x1 = x1.max(bx.x[1]);
        y0 = y0.min(bx.y[0]);
        y1 = y1.max(bx.y[1]);
    }
    let contacts = match run.dir.join("contacts.csv").exists() {
        false => Value::Null,
        true => {
            let recorded = super::analysis::read_contact_frames(&run.dir)?;
            let (mut data, mut per) = (Vec::new(), Vec::new());
            for &k in frames {
                let step = run.frames[k].step;
                let at = recorded
                    .contacts
                    .binary_search_by_key(&step, |(s, _)| *s)
                    .ok();
                let list = at.map_or(&[][..], |i| &recorded.contacts[i].1[..]);
                per.push(list.len());
                for c in list {
                    let i = match c.i {
                        crate::dynamics::Partner::Body(b) => b as f32,
                        crate::dynamics::Partner::Wall(w) => -1.0 - w as f32,
                    };
                    data.extend([
                        i,
                        c.j as f32,
                        c.normal_force() as f32,
                        c.point.x as f32,
                        c.point.y as f32,
                    ]);
                }
            }
            json!({ "count": per, "data": f32s(&data) })
        }
    };
    Ok(json!({
        "name": run.case.name,
        "units": if run.case.units.is_empty() { "cm" } else { run.case.units.as_str() },
        "frames": times,
        "count": count,
        "state": f32s(&state),
        "index": if flows { Value::from(u32s(&index)) } else { Value::Null },
        "ids": ids,
        "shapes": shapes,
        "body_shape": body_shape,
        "material": material,
        "radius": radius,
        "kind": kind,
        "walls": walls,
        "cells": if cells.is_empty() { Value::Null } else { Value::from(cells) },
        "contacts": contacts,
        "bounds": [x0, x1, y0, y1],
        "status": run.summary["status"],
    }))
}

/// `text` with `& < > "` written as HTML entities.
fn escape_html(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The page for frames `frames` of `run`.
pub fn player_html(run: &RunData, frames: &[usize]) -> Result<String, String> {
    let data = player_data(run, frames)?.to_string();
    // Inside a <script> element nothing may read as its end tag: `</` is written `<\/`, which
    // JSON reads as the same two characters.
    let data = data.replace("</", "<\\/");
    Ok(PAGE
        .replace("__TITLE__", &escape_html(&run.case.name))
        .replacen("/*DATA*/", &data, 1))
}

/// Writes the player of frames `frames` of `run` to `out` (atomically: a temporary file renamed
/// over it); returns its size in bytes.
pub fn write_player(run: &RunData, frames: &[usize], out: &Path) -> Result<u64, WriteError> {
    let html = player_html(run, frames).map_err(|e| WriteError {
        file: run.dir.join("contacts.csv"),
        error: std::io::Error::other(e),
    })?;
    let dir = match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let name = out
        .file_name()
        .and_then(|n| n.to_str())
        .ok_or_else(|| WriteError {
            file: out.to_path_buf(),
            error: std::io::Error::other("not a file name"),
        })?;
    super::write_atomically(dir, name, &html).map_err(|error| WriteError {
        file: out.to_path_buf(),
        error,
    })?;
    Ok(html.len() as u64)
}

/// A movie's container.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Movie {
    Mp4,
    Gif,
}

/// Why a movie was not made.
#[derive(Debug)]
pub enum MovieError {
    /// ffmpeg is not installed (or does not run).
    NoFfmpeg(String),
    /// Drawing a frame, or ffmpeg, failed.
    Failed(String),
}

/// The range of `color` over frames `frames` of `run` (`None` for a colouring without a
/// scale): the movie's frames share it, so a colour means the same value throughout.
fn movie_range(run: &RunData, frames: &[usize], color: ColorBy) -> Option<(f64, f64)> {
    let mut vals: Vec<f64> = Vec::new();
    match color {
        ColorBy::Speed => {
            for &k in frames {
                vals.extend(run.frames[k].bodies.iter().map(|b| b.vx.hypot(b.vy)));
            }
        }
        ColorBy::Omega => {
            for &k in frames {
                vals.extend(run.frames[k].bodies.iter().map(|b| b.omega));
            }
        }
        ColorBy::Rotation => {
            // Since the first frame holding each body, by identity.
            let mut first: std::collections::HashMap<u64, f64> = Default::default();
            for (k, f) in run.frames.iter().enumerate() {
                for (&id, b) in f.ids.iter().zip(&f.bodies) {
                    let a0 = *first.entry(id).or_insert(b.angle);
                    if frames.binary_search(&k).is_ok() {
                        vals.push(b.angle - a0);
                    }
                }
            }
        }
        ColorBy::Force => {
            let recorded = run
                .dir
                .join("contacts.csv")
                .exists()
                .then(|| super::analysis::read_contact_frames(&run.dir).ok())
                .flatten();
            for &k in frames {
                vals.extend(super::forces::normal_force_per_body(
                    run,
                    k,
                    recorded.as_ref(),
                ));
            }
        }
        ColorBy::Auto | ColorBy::Body | ColorBy::Run => return None,
    }
    let (lo, hi) = vals
        .iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    // Speeds and forces from zero.
    let lo = if matches!(color, ColorBy::Speed | ColorBy::Force) {
        lo.min(0.0)
    } else {
        lo
    };
    lo.is_finite().then_some((lo, hi))
}

/// Writes frames `frames` of `run` as a movie `out` through ffmpeg: each frame drawn as
/// `dem2d plot --last` draws it (outlines, walls, the cell and its seams' images, a colour bar),
/// at `width` pixels, all frames on the same region and colour scale, `fps` frames per second.
pub fn write_movie(
    run: &RunData,
    frames: &[usize],
    out: &Path,
    kind: Movie,
    color: ColorBy,
    (fps, width): (u32, u32),
) -> Result<(), MovieError> {
    use std::process::{Command, Stdio};
    match Command::new("ffmpeg")
        .arg("-version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
    {
        Ok(s) if s.success() => {}
        Ok(s) => {
            return Err(MovieError::NoFfmpeg(format!(
                "ffmpeg -version failed ({s}): a movie needs a working ffmpeg; `dem2d animate \
                 {}` writes the HTML player without it",
                run.dir.display()
            )));
        }
        Err(e) => {
            return Err(MovieError::NoFfmpeg(format!(
                "ffmpeg not found ({e}): a movie (.mp4, .gif) is made through ffmpeg — install \
                 it (Debian: apt-get install ffmpeg), or write the HTML player, `dem2d animate \
                 {}`, which needs nothing",
                run.dir.display()
            )));
        }
    }
    // One region for every frame: the union of what each frame needs.
    let mut bounds: Option<(f64, f64, f64, f64)> = None;
    for &k in frames {
        let bodies = super::dump::run_bodies(run, k);
        let (walls, _) = run.walls_at(k);
        let bx = super::dump::dump_box(&bodies, &walls, run.cell_at(k).as_ref());
        let b = (bx.x[0], bx.x[1], bx.y[0], bx.y[1]);
        bounds = Some(match bounds {
            None => b,
            Some(a) => (a.0.min(b.0), a.1.max(b.1), a.2.min(b.2), a.3.max(b.3)),
        });
    }
    let (x0, x1, y0, y1) = bounds.expect("a run has a frame");
    let (mx, my) = (0.03 * (x1 - x0), 0.05 * (y1 - y0));
    let bounds = (x0 - mx, x1 + mx, y0 - my, y1 + my);
    let color_range = movie_range(run, frames, color);
    let name = out
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or("movie")
        .to_string();
    let dir = out
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let tmp = dir.join(format!(".{name}.frames-{}", std::process::id()));
    let fail = |m: String| MovieError::Failed(m);
    std::fs::create_dir_all(&tmp).map_err(|e| fail(format!("{}: {e}", tmp.display())))?;
    let result = (|| {
        for (n, &k) in frames.iter().enumerate() {
            let f = &run.frames[k];
            let png = tmp.join(format!("frame_{n:05}.png"));
            plot::scene(
                &png,
                &[ScenePanel {
                    title: format!("{} · t = {} s (step {})", run.case.name, f.t, f.step),
                    runs: vec![(run, String::new())],
                }],
                &SceneOptions {
                    t_min: Some(f.t),
                    t_max: Some(f.t),
                    last_only: true,
                    width: Some(width),
                    color,
                    images: run.case.cell.is_some(),
                    bounds: Some(bounds),
                    color_range,
                    ..SceneOptions::default()
                },
            )
            .map_err(|e| fail(format!("frame {n} (step {}): {e}", f.step)))?;
        }
        let pattern = tmp.join("frame_%05d.png");
        let mut cmd = Command::new("ffmpeg");
        cmd.args(["-hide_banner", "-loglevel", "error", "-y", "-framerate"])
            .arg(fps.to_string())
            .arg("-i")
            .arg(&pattern);
        // The frames are drawn at twice their width (as `dem2d plot` writes PNG): scaled down
        // to `width`.
        match kind {
            // H.264 wants even sizes and 4:2:0 colour for players to open it.
            Movie::Mp4 => cmd
                .arg("-vf")
                .arg(format!("scale={width}:-2:flags=lanczos"))
                .args(["-pix_fmt", "yuv420p", "-movflags", "+faststart"]),
            // One palette made from the frames themselves.
            Movie::Gif => cmd.arg("-vf").arg(format!(
                "scale={width}:-1:flags=lanczos,split[a][b];[a]palettegen=stats_mode=diff[p];\
                 [b][p]paletteuse"
            )),
        };
        let output = cmd
            .arg(out)
            .stdin(Stdio::null())
            .output()
            .map_err(|e| fail(format!("ffmpeg: {e}")))?;
        if !output.status.success() {
            return Err(fail(format!(
                "ffmpeg failed ({}) writing {}: {}",
                output.status,
                out.display(),
                String::from_utf8_lossy(&output.stderr).trim()
            )));
        }
        Ok(())
    })();
    let _ = std::fs::remove_dir_all(&tmp);
    result
}
