//! A LAMMPS-style text dump of a run (`dump.lammpstrj`) for OVITO, and for any tool that reads
//! LAMMPS dumps: `dem2d export RUN --format lammps-dump` writes it from a run directory
//! ([`export_run`]), `dem2d run --dump` while the run goes ([`Dump`], an observer at the
//! trajectory's frames). Both write the same bytes for the same frames: a frame is made of the
//! same numbers either way ([`DumpBody`], [`dump_box`], [`write_frame`]), and the trajectory holds
//! every double exactly.
//!
//! # A frame
//! ```text
//! ITEM: TIME
//! 0.01
//! ITEM: TIMESTEP
//! 1000
//! ITEM: NUMBER OF ATOMS
//! 3
//! ITEM: BOX BOUNDS ff ff ff
//! -1.5 4.5
//! 0 3.2
//! -1.5 1.5
//! ITEM: ATOMS id type x y z vx vy omegaz shapex shapey shapez quatw quati quatj quatk angle shape material
//! 1 1 0.5 1.02 0 …
//! ```
//! LAMMPS's own order (`dump_modify time yes` puts `ITEM: TIME` first). Per body, one row:
//! - `id`: the body's identity plus one (LAMMPS numbers atoms from 1): `trajectory.csv`'s `body`
//!   plus one, stable across insertion and outflow (an inserted body gets the next identity; a
//!   removed one's is never reused), so OVITO follows each grain from frame to frame;
//! - `type`: its material plus one (`materials[k]` of the case is type k + 1; type 1 the scene's
//!   law), as LIGGGHTS maps atom types to materials;
//! - `x y z`: its centroid (cm), z = 0; `vx vy` (cm/s); `omegaz` (rad/s, counter-clockwise);
//! - `shapex shapey shapez`: **diameters** (cm), as LAMMPS writes ellipsoids since 2020 and OVITO
//!   halves into its Aspherical Shape: an ellipse `2a 2b`, a disk `2r 2r`, and — not being
//!   ellipses — a rectangle, polygon or clump its bounding circle's `2R 2R`; `shapez` a thin
//!   z extent, [`THIN`] × the smaller of the two (a flat ellipsoid, drawn from above as the
//!   ellipse);
//! - `quatw quati quatj quatk`: the rotation by the body's angle θ about z,
//!   `(cos θ/2, 0, 0, sin θ/2)` (it turns the body's x axis, the ellipse's `a`, onto the lab's);
//! - and after LAMMPS's columns: `angle` θ (rad, as the trajectory writes it: not reduced),
//!   `shape` (0 circle, 1 ellipse, 2 rectangle, 3 polygon, 4 clump: [`Shape::type_code`]) and
//!   `material`.
//!
//! Numbers are written with full round-trip precision (the shortest text that reads back to the
//! same double).
//!
//! # The box
//! In a periodic cell (`ITEM: BOX BOUNDS pp pp ff`): the cell `[0, L_x] × [0, L_y]` at the
//! frame's size; under Lees–Edwards shear a triclinic box (`ITEM: BOX BOUNDS xy xz yz pp pp
//! ff`) whose tilt `xy` is the shift of the image above, brought into `[−L_x/2, L_x/2)` (the same
//! lattice of images), so that OVITO's periodic analyses see the right neighbours across the
//! top and bottom; in a cell periodic in x only, `pp ff ff` with y spanning the bodies. Without a
//! cell (`ff ff ff`): the box holding every body's bounding circle, the segment walls and the
//! axis-aligned walls (a floor, a side wall). z spans ± the largest bounding radius: a slab, not
//! periodic, so that no analysis meets a body's own image through z. A frame with no body and
//! nothing else to span gets the box `[0, 1]` in x and y.

use super::run_data::RunData;
use super::trace::{FrameRows, LineFile, WriteError, Written};
use crate::dynamics::cell::Cell;
use crate::dynamics::{Boundary, World};
use crate::geometry::Shape;
use std::fmt;
use std::path::Path;

/// The dump's file name in a run directory (`dem2d run --dump`, `dem2d export`'s default).
pub const FILE: &str = "dump.lammpstrj";

/// The columns of a body's row (`ITEM: ATOMS …`).
pub const COLUMNS: &str = "id type x y z vx vy omegaz shapex shapey shapez quatw quati quatj \
quatk angle shape material";

/// The thin z extent of a body's ellipsoid, as a fraction of its smaller in-plane diameter.
pub const THIN: f64 = 0.1;

/// One body of a frame, as the dump writes it (see the module documentation).
#[derive(Clone, Copy, Debug)]
pub struct DumpBody<'a> {
    /// Its identity (`trajectory.csv`'s `body`; the dump writes it plus one).
    pub id: u64,
    pub shape: &'a Shape,
    pub material: u16,
    pub x: f64,
    pub y: f64,
    pub angle: f64,
    pub vx: f64,
    pub vy: f64,
    pub omega: f64,
}

impl DumpBody<'_> {
    /// `shapex, shapey, shapez`: diameters (see the module documentation).
    pub fn diameters(&self) -> [f64; 3] {
        let (a, b) = self.shape.ellipse_semi_axes().unwrap_or_else(|| {
            let r = self.shape.bounding_radius();
            (r, r)
        });
        [2.0 * a, 2.0 * b, THIN * 2.0 * a.min(b)]
    }

    /// `quatw, quati, quatj, quatk`: the rotation by the angle about z.
    pub fn quaternion(&self) -> [f64; 4] {
        let (s, c) = (0.5 * self.angle).sin_cos();
        [c, 0.0, 0.0, s]
    }
}

/// A frame's box (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DumpBox {
    pub x: [f64; 2],
    pub y: [f64; 2],
    pub z: [f64; 2],
    /// The triclinic tilt `xy` (Lees–Edwards shear), if any.
    pub tilt: Option<f64>,
    /// Periodic in x, in y.
    pub periodic: [bool; 2],
}

/// The box of a frame of `bodies`, with the walls and the periodic cell where they are then.
pub fn dump_box(bodies: &[DumpBody], walls: &[Boundary], cell: Option<&Cell>) -> DumpBox {
    let inf = f64::INFINITY;
    let (mut x, mut y) = ([inf, -inf], [inf, -inf]);
    let grow = |a: &mut [f64; 2], v: f64| {
        a[0] = a[0].min(v);
        a[1] = a[1].max(v);
    };
    let mut reach: f64 = 0.0;
    for b in bodies {
        let r = b.shape.bounding_radius();
        reach = reach.max(r);
        grow(&mut x, b.x - r);
        grow(&mut x, b.x + r);
        grow(&mut y, b.y - r);
        grow(&mut y, b.y + r);
    }
    for w in walls {
        if let Some(d) = w.drum() {
            for o in [-d.radius, d.radius] {
                grow(&mut x, d.center.x + o);
                grow(&mut y, d.center.y + o);
            }
            continue;
        }
        if let Some(s) = w.segment() {
            for p in [s.a, s.b] {
                grow(&mut x, p.x);
                grow(&mut y, p.y);
            }
            continue;
        }
        let (p, n) = (w.line().point, w.line().normal);
        if n.x == 0.0 {
            grow(&mut y, p.y);
        } else if n.y == 0.0 {
            grow(&mut x, p.x);
        }
    }
    let mut periodic = [false, false];
    let mut tilt = None;
    if let Some(c) = cell {
        x = [0.0, c.size.x];
        periodic[0] = true;
        if c.periodic_y() {
            y = [0.0, c.size.y];
            periodic[1] = true;
            if c.shear_rate != 0.0 || c.offset != 0.0 {
                // The same lattice of images, the least tilted cell.
                let lx = c.size.x;
                tilt = Some(c.offset - lx * (c.offset / lx + 0.5).floor());
            }
        }
    }
    // Nothing to span (no body left, no wall): a unit box, so that readers get a cell.
    for a in [&mut x, &mut y] {
        if a[0] > a[1] || a[0].is_nan() || a[1].is_nan() {
            *a = [0.0, 1.0];
        }
    }
    let h = if reach > 0.0 { reach } else { 0.5 };
    DumpBox {
        x,
        y,
        z: [-h, h],
        tilt,
        periodic,
    }
}

/// Writes one frame through `line` (called once per line, the text without its newline).
pub fn write_frame<E>(
    line: &mut impl FnMut(fmt::Arguments) -> Result<(), E>,
    (step, t): (u64, &str),
    bx: &DumpBox,
    bodies: &[DumpBody],
) -> Result<(), E> {
    line(format_args!("ITEM: TIME"))?;
    line(format_args!("{t}"))?;
    line(format_args!("ITEM: TIMESTEP"))?;
    line(format_args!("{step}"))?;
    line(format_args!("ITEM: NUMBER OF ATOMS"))?;
    line(format_args!("{}", bodies.len()))?;
    let pf = |p: bool| if p { "pp" } else { "ff" };
    let (px, py) = (pf(bx.periodic[0]), pf(bx.periodic[1]));
    match bx.tilt {
        None => {
            line(format_args!("ITEM: BOX BOUNDS {px} {py} ff"))?;
            line(format_args!("{} {}", bx.x[0], bx.x[1]))?;
            line(format_args!("{} {}", bx.y[0], bx.y[1]))?;
            line(format_args!("{} {}", bx.z[0], bx.z[1]))?;
        }
        Some(xy) => {
            // LAMMPS's triclinic bounds: the x range of the tilted cell's corners, then the
            // tilt factors xy, xz, yz.
            line(format_args!("ITEM: BOX BOUNDS xy xz yz {px} {py} ff"))?;
            line(format_args!(
                "{} {} {xy}",
                bx.x[0] + xy.min(0.0),
                bx.x[1] + xy.max(0.0)
            ))?;
            line(format_args!("{} {} 0", bx.y[0], bx.y[1]))?;
            line(format_args!("{} {} 0", bx.z[0], bx.z[1]))?;
        }
    }
    line(format_args!("ITEM: ATOMS {COLUMNS}"))?;
    for b in bodies {
        let [sx, sy, sz] = b.diameters();
        let [qw, qi, qj, qk] = b.quaternion();
        line(format_args!(
            "{} {} {} {} 0 {} {} {} {sx} {sy} {sz} {qw} {qi} {qj} {qk} {} {} {}",
            b.id + 1,
            u32::from(b.material) + 1,
            b.x,
            b.y,
            b.vx,
            b.vy,
            b.omega,
            b.angle,
            b.shape.type_code(),
            b.material
        ))?;
    }
    Ok(())
}

/// The bodies of the world as they stand.
pub fn world_bodies(world: &World) -> Vec<DumpBody<'_>> {
    let b = &world.bodies;
    (0..b.len())
        .map(|k| {
            let s = &b.state[k];
            DumpBody {
                id: b.id[k],
                shape: &b.shape[k],
                material: b.material[k],
                x: s.pose.position.x,
                y: s.pose.position.y,
                angle: s.pose.angle(),
                vx: s.vel.x,
                vy: s.vel.y,
                omega: s.omega,
            }
        })
        .collect()
}

/// The bodies of frame `k` of `run`.
pub fn run_bodies(run: &RunData, k: usize) -> Vec<DumpBody<'_>> {
    let f = &run.frames[k];
    f.ids
        .iter()
        .zip(&f.bodies)
        .map(|(&id, s)| {
            let init = run.init(id);
            DumpBody {
                id,
                shape: &init.shape,
                material: init.material,
                x: s.x,
                y: s.y,
                angle: s.angle,
                vx: s.vx,
                vy: s.vy,
                omega: s.omega,
            }
        })
        .collect()
}

/// The rows of `dump.lammpstrj` for a run's observer ([`super::trace::Frames`]): the dump
/// written at the trajectory's frames while the run goes (`dem2d run --dump`).
pub struct Dump;

/// The writer of `dump.lammpstrj` during a run.
pub type DumpWriter = super::trace::Frames<Dump>;

impl FrameRows for Dump {
    const FILE: &str = FILE;
    /// None: a dump has no file header, each frame its own.
    const HEADER: &str = "";
    fn rows(&self, out: &mut LineFile, world: &World, step: u64, t: &str) -> Written {
        let bodies = world_bodies(world);
        let bx = dump_box(&bodies, &world.walls, world.cell.as_ref());
        write_frame(&mut |a| out.line(a), (step, t), &bx, &bodies)
    }
}

/// Writes the dump of the run read back in `run` to `out`: into `out.tmp`, renamed over `out`
/// when whole (a failed write leaves no torn dump). Returns the number of frames.
pub fn export_run(run: &RunData, out: &Path) -> Result<usize, WriteError> {
    let mut tmp = out.as_os_str().to_owned();
    tmp.push(".tmp");
    let tmp = std::path::PathBuf::from(tmp);
    let result = (|| {
        let mut file = LineFile::create(&tmp)?;
        for k in 0..run.frames.len() {
            let bodies = run_bodies(run, k);
            let (walls, _) = run.walls_at(k);
            let cell = run.cell_at(k);
            let bx = dump_box(&bodies, &walls, cell.as_ref());
            let f = &run.frames[k];
            let t = crate::run::time::time_text(f.step, run.case.dt);
            write_frame(&mut |a| file.line(a), (f.step, &t), &bx, &bodies)?;
        }
        file.flush()
    })();
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(e);
    }
    std::fs::rename(&tmp, out).map_err(|error| WriteError {
        file: out.to_path_buf(),
        error,
    })?;
    Ok(run.frames.len())
}
