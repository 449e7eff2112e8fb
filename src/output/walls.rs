//! `walls.csv`: every wall's line, velocity and load at each output frame (written by every run
//! whose case has walls), and its reader.
//!
//! `step,t,wall,x,y,nx,ny,vx,vy,fn,ft,contacts,span,sn,st,fx,fy,angle,omega,torque,power`:
//! - `x,y` a point of the wall's line now (a segment's first end; a drum's centre), `nx,ny` its
//!   unit normal (into the free side; a drum: `0,1`), `vx,vy` its velocity over the step that
//!   ended here (cm/s; zero for a fixed wall; a turning wall's pivot's);
//! - `fn,ft` its **load**: the sum `F` of the forces its contacts exert on the bodies (dyn per
//!   cm of thickness), `fn = F·n` (positive: the wall pushes the bodies, compression) and
//!   `ft = F·t` with `t = (−n_y, n_x)`; `contacts` their number;
//! - `span` the length the load is spread over (cm): a servo wall's loaded span (see
//!   [`crate::dynamics::boundary`]), else the length of the wall's line that lies on the free
//!   side of every other wall (the side of a box: its current width or height); empty when the
//!   other walls do not bound the line (a lone floor);
//! - `sn,st` the wall's normal and shear stress, `fn/span` and `ft/span` (dyn/cm²; empty
//!   without a span). A biaxial test's stress–strain curve is `sn` of its walls against the
//!   change of their positions.
//!
//! - `fx,fy` the load `F` itself (dyn/cm; a drum's in particular, whose `fn,ft` refer to the
//!   line `0,1` through its centre); `angle` the angle it has turned (rad, counter-clockwise; 0
//!   for a wall that does not turn), `omega` its angular velocity over the step (rad/s),
//!   `torque` a turning wall's moment about its pivot (a drum's centre) of the forces and
//!   couples its contacts exert on the bodies, `Σ ℓ_c × F_c + M_c` (dyn·cm/cm; 0 for a wall
//!   that does not turn; see `Boundary::lever`), and
//!   `power` the work per unit time it does on the bodies, `F·v + ω torque` (erg/s per cm: what
//!   the energy account's wall work integrates).
//!
//! Runs written before these columns have `step,t,wall,x,y,nx,ny` only, or end at `st`;
//! [`read_walls`] reads all three.

use super::run_data::ReadError;
use super::trace::{FrameRows, LineFile, Written};
use crate::dynamics::World;
use crate::dynamics::boundary::{Boundary, span_length};
use crate::geometry::Vec2;
use std::path::Path;

pub const WALLS_HEADER: &str =
    "step,t,wall,x,y,nx,ny,vx,vy,fn,ft,contacts,span,sn,st,fx,fy,angle,omega,torque,power";
/// The header of runs written before the turning walls' columns.
pub const WALLS_HEADER_BEFORE_TURNING: &str =
    "step,t,wall,x,y,nx,ny,vx,vy,fn,ft,contacts,span,sn,st";
/// The header of runs written before the walls' loads were recorded.
pub const WALLS_HEADER_LINES_ONLY: &str = "step,t,wall,x,y,nx,ny";

/// The length of wall `k`'s line over which its load is spread (see the module documentation);
/// `None` when no other wall bounds it.
pub fn loaded_span(k: usize, walls: &[Boundary]) -> Option<f64> {
    let me = &walls[k];
    if let Some(s) = me.servo() {
        return Some(span_length(me.line(), &s.span, walls));
    }
    if let Some(seg) = me.segment() {
        // A segment wall's load is spread over the segment.
        return Some(seg.length);
    }
    if let Some(d) = me.drum() {
        // A drum's over its circumference.
        return Some(std::f64::consts::TAU * d.radius);
    }
    let (p, t) = (
        me.line().point,
        Vec2::new(-me.line().normal.y, me.line().normal.x),
    );
    // The line p + s t on the free side of wall j: s (n_j·t) ≥ n_j·(p_j − p).
    let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
    for (j, o) in walls.iter().enumerate() {
        if j == k || !o.is_half_plane() {
            // (A segment or a drum bounds no half-plane wall's line.)
            continue;
        }
        let (nt, gap) = (
            o.line().normal.dot(&t),
            o.line().normal.dot(&(o.line().point - p)),
        );
        if nt.abs() < 1e-12 {
            // Parallel: the whole line is free of it, or solid (then nothing is loaded).
            if gap > 0.0 {
                return None;
            }
        } else if nt > 0.0 {
            lo = lo.max(gap / nt);
        } else {
            hi = hi.min(gap / nt);
        }
    }
    (lo.is_finite() && hi.is_finite() && hi > lo).then_some(hi - lo)
}

/// A number, or nothing for NaN.
fn num(x: f64) -> String {
    if x.is_nan() {
        String::new()
    } else {
        format!("{x}")
    }
}

/// The rows of `walls.csv`, one per wall ([`WALLS_HEADER`]).
pub struct Walls;

impl FrameRows for Walls {
    const FILE: &str = "walls.csv";
    const HEADER: &str = WALLS_HEADER;
    fn rows(&self, out: &mut LineFile, world: &World, step: u64, t: &str) -> Written {
        for (k, w) in world.walls.iter().enumerate() {
            let (p, n, v) = (w.line().point, w.line().normal, w.velocity);
            let f = w.load.force;
            let (fn_, ft) = (f.dot(&n), f.x * -n.y + f.y * n.x);
            let span = loaded_span(k, &world.walls).unwrap_or(f64::NAN);
            let omega = w.omega();
            let power = f.dot(&v) + omega * w.load.torque;
            out.line(format_args!(
                "{step},{t},{k},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
                p.x,
                p.y,
                n.x,
                n.y,
                v.x,
                v.y,
                fn_,
                ft,
                w.load.contacts,
                num(span),
                num(fn_ / span),
                num(ft / span),
                f.x,
                f.y,
                w.angle(),
                omega,
                w.load.torque,
                power
            ))?;
        }
        Ok(())
    }
}

/// One wall at one output frame, as `walls.csv` holds it (NaN for what a row does not carry).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallRow {
    pub point: Vec2,
    pub normal: Vec2,
    pub velocity: Vec2,
    pub fn_: f64,
    pub ft: f64,
    pub contacts: f64,
    pub span: f64,
    pub sn: f64,
    pub st: f64,
    /// The angle the wall has turned (0 in a file written before the column).
    pub angle: f64,
}

/// The walls of one output frame.
#[derive(Clone, Debug, PartialEq)]
pub struct WallFrame {
    pub step: u64,
    pub t: f64,
    pub walls: Vec<WallRow>,
}

/// What [`read_walls`] found: the frames, and a note when the file's last frame was left out
/// (a run killed mid-write leaves a partial line or a partial frame).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WallFrames {
    pub frames: Vec<WallFrame>,
    pub incomplete: Option<String>,
}

/// Reads `dir/walls.csv` (`Ok(None)` when there is none) for a case of `n_walls` walls. Errors
/// name the file and the line. A last line without its newline and a last frame without every
/// wall are left out, with a note.
pub fn read_walls(dir: &Path, n_walls: usize) -> Result<Option<WallFrames>, ReadError> {
    let file = dir.join("walls.csv");
    let text = match std::fs::read_to_string(&file) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => {
            return Err(ReadError {
                file,
                message: format!("cannot read: {e}"),
            });
        }
    };
    let bad = |n: usize, m: &str| ReadError {
        file: file.clone(),
        message: format!("line {n}: {m}"),
    };
    let (whole, partial) = super::run_data::whole_lines(&text);
    let mut lines = whole.lines();
    let width = match lines.next() {
        Some(WALLS_HEADER) => 21,
        Some(WALLS_HEADER_BEFORE_TURNING) => 15,
        Some(WALLS_HEADER_LINES_ONLY) => 7,
        _ => return Err(bad(1, &format!("expected the header `{WALLS_HEADER}`"))),
    };
    let mut out = WallFrames::default();
    for (k, line) in lines.enumerate() {
        let f =
            super::run_data::fields(line).map_err(|e| bad(k + 2, &format!("not a number: {e}")))?;
        if f.len() != width {
            return Err(bad(k + 2, &format!("{} fields, expected {width}", f.len())));
        }
        let step = f[0] as u64;
        if out.frames.last().is_none_or(|w| w.step != step) {
            if let Some(last) = out.frames.last()
                && last.walls.len() != n_walls
            {
                return Err(bad(
                    k + 2,
                    &format!(
                        "step {}: {} walls, but case.json has {n_walls}",
                        last.step,
                        last.walls.len()
                    ),
                ));
            }
            out.frames.push(WallFrame {
                step,
                t: f[1],
                walls: Vec::new(),
            });
        }
        let g = |i: usize| f.get(i).copied().unwrap_or(f64::NAN);
        out.frames.last_mut().expect("pushed").walls.push(WallRow {
            point: Vec2::new(f[3], f[4]),
            normal: Vec2::new(f[5], f[6]),
            velocity: Vec2::new(g(7), g(8)),
            fn_: g(9),
            ft: g(10),
            contacts: g(11),
            span: g(12),
            sn: g(13),
            st: g(14),
            angle: f.get(17).copied().unwrap_or(0.0),
        });
    }
    let cut_frame = out.frames.last().is_some_and(|w| w.walls.len() != n_walls);
    if cut_frame {
        let last = out.frames.pop().expect("a frame");
        out.incomplete = Some(format!(
            "{}: the last frame (step {}) has {} of the {n_walls} walls (the run was stopped \
             while writing it): left out",
            file.display(),
            last.step,
            last.walls.len()
        ));
    } else if partial {
        out.incomplete = Some(format!(
            "{}: the last line is incomplete (the run was stopped while writing it): left out",
            file.display()
        ));
    }
    Ok(Some(out))
}
