//! VTK output for ParaView: `vtk/frame_NNNNN.vtu` (an unstructured grid per output frame) and
//! `run.pvd` (the time series that ParaView opens), written from the world as it stands.
//!
//! # What a frame holds
//! One piece, three kinds of cell (cell array `kind`):
//! - **0, a body**: its true outline as a polygon (`VTK_POLYGON`), vertices on the boundary as
//!   [`super::outline`] places them (an ellipse of a/b = 10 gets 128, every chord within 1e-3 b
//!   of the boundary);
//! - **1, a contact**: a line (`VTK_LINE`) from the centroid of i to the centroid of j, or from
//!   the body's centroid to the contact point for a body–wall contact (force chains);
//! - **2, a wall**: its line, clipped to the box holding every body and wall point seen so far
//!   (padded by 5 %), so that it does not change length from frame to frame;
//! - **3, the periodic cell's outline** (a case with `"cell"`): in a cell periodic in x and y,
//!   its rectangle `[0, L_x] × [0, L_y]` at the frame's size as a closed poly-line
//!   (`VTK_POLY_LINE`, five points, the last the first: a line, not a filled face, so that it
//!   hides no body); in a cell periodic in x only, its two seams `x = 0` and `x = L_x` as lines
//!   across the walls' box. (The Lees–Edwards shift moves the image above along the top edge,
//!   which stays where it is: the shift is in the field data.)
//!
//! A body's outline is drawn once, where its centroid is (inside the cell), so a body cut by a
//! seam sticks out of it; a contact across a seam is drawn from the receiver's centroid to the
//! giver's image nearest to it (a new point), not across the cell.
//!
//! Cell data (zero where an array does not apply to a kind): `id` (a body's identity — the
//! `body` of `trajectory.csv`, its index until an outflow removes a body —, a contact's ordinal,
//! a wall's index), `pair` (a contact's i and j by identity, a wall w given as j = −1 − w),
//! `shape` (0 circle, 1
//! ellipse, 2 rectangle, 3 polygon, 4 clump, −1 not a body), `semi_axes` (a, b: an ellipse's semi-axes,
//! (r, r) for a circle, (w/2, h/2) for a rectangle, for a polygon those of the ellipse with its
//! second moments of area, whose a lies along the polygon's long axis — the tensor below is
//! turned by that axis), `angle` (rad), `velocity` (cm/s, 3 components, z = 0),
//! `angular_velocity` (rad/s), `shape_tensor` — `R diag(a², b²) Rᵀ` with **semi-axes** a, b
//! (not diameters) and R the rotation by the body's angle, as a 3 × 3 tensor with zero z row and
//! column; the body is `{x : (x − c)ᵀ T⁻¹ (x − c) ≤ 1}` for ellipses and circles —,
//! `body_normal_force` (a body's Σ F_n over its contacts, dyn), and for contacts
//! `normal_force` (F·n ≥ 0, dyn), `tangential_force` (F·t with t = (−n_y, n_x), dyn), `force`
//! (the force on j, or on the body for a wall contact), `normal` (unit, from i towards j, or from
//! the wall) and `depth` (δ, cm). Field data `TIME` (s) and `STEP`, and with a periodic cell
//! `CELL_SIZE` (L_x, L_y: cm, L_y following an imposed pressure), `CELL_OFFSET` (the
//! Lees–Edwards shift of the image above modulo L_x, cm) and `CELL_SHIFT` (the total shift S,
//! cm), as in `cell.csv`. Forces are per unit thickness, as everywhere in dem2d.
//!
//! # Format
//! VTK XML, `UnstructuredGrid` version 1.0, every array inline in base64 (`format="binary"`,
//! little-endian, a `UInt64` byte count before each array): exact doubles, a third above their
//! raw size, no compression library needed. Written here rather than through a crate: the
//! format is a page of XML around arrays, the crates that write it (`vtkio`) have had only
//! release candidates since 2021, and the test that matters reads the files with VTK's own
//! reader (`tests/vtk.rs`).

use super::plot::clip_line;
use super::trace::WriteError;
use crate::dynamics::{Partner, World};
use crate::geometry::{Shape, Vec2};
use crate::run::time::{time_text, time_value};
use crate::run::{End, Moment, Observer, ObserverError, Plan, StepInfo};
use std::collections::HashMap;
use std::fmt::Write as _;
use std::io;
use std::path::{Path, PathBuf};

/// The VTK cell types used.
const VTK_LINE: u8 = 3;
const VTK_POLY_LINE: u8 = 4;
const VTK_POLYGON: u8 = 7;

/// Writes the frames of one run and keeps its `run.pvd` up to date.
pub struct VtkWriter {
    run_dir: PathBuf,
    /// Each frame's time (decimal text) and file, relative to the run directory.
    frames: Vec<(String, String)>,
    last_step: Option<u64>,
    /// Body-frame outline of each body, by its identity ([`crate::dynamics::Bodies::id`]):
    /// computed once per body, when it is first drawn. Keyed by identity, not by index: an
    /// outflow removes rows and shifts every later body's index, an insertion appends bodies
    /// the writer has not seen (issue 41, items 4 and 5).
    outlines: HashMap<u64, Vec<(f64, f64)>>,
    /// Box that walls are clipped to: every body and wall point seen so far.
    bbox: Option<(f64, f64, f64, f64)>,
    /// Steps between frames, as an observer of a run.
    every: u64,
}

/// The files of an earlier run's VTK output in `run_dir`: `run.pvd` and `vtk/frame_*.vtu`.
pub fn existing_outputs(run_dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for f in ["run.pvd", "run.pvd.tmp"] {
        let p = run_dir.join(f);
        if p.symlink_metadata().is_ok() {
            out.push(p);
        }
    }
    if let Ok(entries) = std::fs::read_dir(run_dir.join("vtk")) {
        let mut frames: Vec<PathBuf> = entries
            .filter_map(Result::ok)
            .map(|e| e.path())
            .filter(|p| {
                p.file_name()
                    .and_then(|n| n.to_str())
                    .is_some_and(|n| n.starts_with("frame_") && n.ends_with(".vtu"))
            })
            .collect();
        frames.sort();
        out.extend(frames);
    }
    out
}

/// The body-frame outline of every body now in `world`, by identity: those in `known` kept
/// (a body's shape never changes), the others computed, the removed bodies' dropped.
fn outlines_by_id(
    world: &World,
    mut known: HashMap<u64, Vec<(f64, f64)>>,
) -> HashMap<u64, Vec<(f64, f64)>> {
    let b = &world.bodies;
    b.id.iter()
        .zip(&b.shape)
        .map(|(&id, shape)| {
            let outline = known
                .remove(&id)
                .unwrap_or_else(|| super::outline::body_frame_vertices(shape));
            (id, outline)
        })
        .collect()
}

fn io_err(file: &Path) -> impl FnOnce(io::Error) -> WriteError + '_ {
    move |error| WriteError {
        file: file.to_path_buf(),
        error,
    }
}

impl VtkWriter {
    /// A writer for the run in `run_dir` (creates `run_dir/vtk`); as an observer of a run it
    /// writes the first state, every `every` steps and the last (finite) state.
    pub fn create(run_dir: &Path, world: &World, every: u64) -> Result<VtkWriter, WriteError> {
        let dir = run_dir.join("vtk");
        std::fs::create_dir_all(&dir).map_err(io_err(&dir))?;
        Ok(VtkWriter {
            run_dir: run_dir.to_path_buf(),
            frames: Vec::new(),
            last_step: None,
            outlines: outlines_by_id(world, HashMap::new()),
            bbox: None,
            every: every.max(1),
        })
    }

    /// Writes the world's current state as the next frame (once per step).
    pub fn write(&mut self, world: &World) -> Result<(), WriteError> {
        let step = world.step;
        self.write_labelled(world, step)
    }

    /// Writes the world's current state labelled as step `step` (once per label; see
    /// [`super::trace::TrajectoryWriter::write_labelled`]), then rewrites `run.pvd`. Reads the
    /// contact extras (normals, depths), which the step does not keep: the caller refreshes them
    /// ([`World::refresh_contact_extras`]; a run's driver does when [`Observer::reads_extras`]
    /// asks).
    pub fn write_labelled(&mut self, world: &World, step: u64) -> Result<(), WriteError> {
        if self.last_step == Some(step) {
            return Ok(());
        }
        self.last_step = Some(step);
        self.outlines = outlines_by_id(world, std::mem::take(&mut self.outlines));
        self.grow_bbox(world);
        let name = format!("vtk/frame_{:05}.vtu", self.frames.len());
        let path = self.run_dir.join(&name);
        let text = self.frame_xml(world, step);
        std::fs::write(&path, text).map_err(io_err(&path))?;
        self.frames.push((time_text(step, world.dt), name));
        self.write_pvd()
    }

    /// `run.pvd`, written to a temporary file and renamed over the old one, so that ParaView
    /// never reads a torn one and an interrupted run leaves a valid series.
    fn write_pvd(&self) -> Result<(), WriteError> {
        let mut s = String::from(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n",
        );
        for (t, file) in &self.frames {
            writeln!(
                s,
                "    <DataSet timestep=\"{t}\" group=\"\" part=\"0\" file=\"{file}\"/>"
            )
            .expect("string");
        }
        s.push_str("  </Collection>\n</VTKFile>\n");
        let (tmp, path) = (
            self.run_dir.join("run.pvd.tmp"),
            self.run_dir.join("run.pvd"),
        );
        std::fs::write(&tmp, s).map_err(io_err(&tmp))?;
        std::fs::rename(&tmp, &path).map_err(io_err(&path))
    }

    fn grow_bbox(&mut self, world: &World) {
        let (mut x0, mut x1, mut y0, mut y1) = self.bbox.unwrap_or((
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ));
        let b = &world.bodies;
        let points = (0..b.len())
            .map(|k| (b.state[k].pose.position, b.bound[k]))
            .chain(
                world
                    .walls
                    .iter()
                    .flat_map(|w| match (w.segment(), w.drum()) {
                        (Some(s), _) => vec![(s.a, 0.0), (s.b, 0.0)],
                        (None, Some(d)) => vec![(d.center, d.radius)],
                        (None, None) => vec![(w.line().point, 0.0)],
                    }),
            );
        for (p, r) in points {
            x0 = x0.min(p.x - r);
            x1 = x1.max(p.x + r);
            y0 = y0.min(p.y - r);
            y1 = y1.max(p.y + r);
        }
        self.bbox = Some((x0, x1, y0, y1));
    }

    /// The frame as VTK XML.
    fn frame_xml(&self, world: &World, step: u64) -> String {
        let b = &world.bodies;
        let n = b.len();
        let mut points: Vec<f64> = Vec::new();
        let mut connectivity: Vec<i64> = Vec::new();
        let mut offsets: Vec<i64> = Vec::new();
        let mut types: Vec<u8> = Vec::new();
        let mut cells: Vec<Cell> = Vec::new();
        let push_point = |points: &mut Vec<f64>, p: (f64, f64)| -> i64 {
            points.extend([p.0, p.1, 0.0]);
            (points.len() / 3 - 1) as i64
        };
        // Bodies: outline polygons.
        let mut body_fn = vec![0.0; n];
        let contacts: Vec<_> = world.contacts.active().collect();
        for c in &contacts {
            let f_n = c.data.force.dot(&c.extra.normal);
            body_fn[c.slot.i as usize] += f_n;
            if !c.is_wall() {
                body_fn[c.slot.j as usize] += f_n;
            }
        }
        for (k, &fn_sum) in body_fn.iter().enumerate() {
            let s = &b.state[k];
            let angle = s.pose.angle();
            let (x, y) = (s.pose.position.x, s.pose.position.y);
            for p in super::outline::place(&self.outlines[&b.id[k]], x, y, angle) {
                connectivity.push(push_point(&mut points, p));
            }
            offsets.push(connectivity.len() as i64);
            types.push(VTK_POLYGON);
            let (kind, (sa, sb), turn) = match b.shape[k] {
                Shape::Circle { r } => (0, (r, r), 0.0),
                Shape::Ellipse { a, b } => (1, (a, b), 0.0),
                Shape::Rectangle { w, h } => (2, (0.5 * w, 0.5 * h), 0.0),
                Shape::Polygon(p) => (
                    3,
                    (p.moment_ellipse[0], p.moment_ellipse[1]),
                    p.long_axis.unwrap_or(0.0),
                ),
                Shape::Clump(c) => (4, (c.moment_ellipse[0], c.moment_ellipse[1]), c.long_axis),
            };
            let (sn, cs) = (angle + turn).sin_cos();
            let (a2, b2) = (sa * sa, sb * sb);
            let (txx, tyy, txy) = (
                a2 * cs * cs + b2 * sn * sn,
                a2 * sn * sn + b2 * cs * cs,
                (a2 - b2) * cs * sn,
            );
            cells.push(Cell {
                kind: 0,
                id: b.id[k] as i64,
                pair: [-1, -1],
                shape: kind,
                semi_axes: [sa, sb],
                angle,
                velocity: [s.vel.x, s.vel.y, 0.0],
                angular_velocity: s.omega,
                shape_tensor: [txx, txy, 0.0, txy, tyy, 0.0, 0.0, 0.0, 0.0],
                body_normal_force: fn_sum,
                ..Cell::default()
            });
        }
        // Centroids, for the contact lines.
        let centroid0 = points.len() as i64 / 3;
        for k in 0..n {
            let p = b.state[k].pose.position;
            push_point(&mut points, (p.x, p.y));
        }
        // Contacts.
        for (ordinal, c) in contacts.iter().enumerate() {
            let i = c.slot.i as i64;
            let (from, to, j) = match c.slot.partner() {
                Partner::Wall(w) => {
                    let p = c.data.point;
                    (
                        centroid0 + i,
                        push_point(&mut points, (p.x, p.y)),
                        -1 - w as i64,
                    )
                }
                Partner::Body(j) => {
                    let (pi, pj) = (b.state[i as usize].pose.position, b.state[j].pose.position);
                    // Across a seam: to the giver's image nearest the receiver.
                    let to = match &world.cell {
                        Some(cell) if cell.shortest(pj - pi) != pj - pi => {
                            let q = pi + cell.shortest(pj - pi);
                            push_point(&mut points, (q.x, q.y))
                        }
                        _ => centroid0 + j as i64,
                    };
                    (centroid0 + i, to, j as i64)
                }
            };
            connectivity.extend([from, to]);
            offsets.push(connectivity.len() as i64);
            types.push(VTK_LINE);
            let (nrm, f) = (c.extra.normal, c.data.force);
            let t = Vec2::new(-nrm.y, nrm.x);
            // The pair by identity, as trajectory.csv names bodies.
            let j = if j >= 0 { b.id[j as usize] as i64 } else { j };
            cells.push(Cell {
                kind: 1,
                id: ordinal as i64,
                pair: [b.id[i as usize] as i64, j],
                normal_force: f.dot(&nrm),
                tangential_force: f.dot(&t),
                force: [f.x, f.y, 0.0],
                normal: [nrm.x, nrm.y, 0.0],
                depth: c.extra.depth,
                ..Cell::default()
            });
        }
        // Walls, clipped to the padded box.
        if let Some((x0, x1, y0, y1)) = self.bbox {
            let pad = 0.05 * (x1 - x0).max(y1 - y0);
            let bx = (x0 - pad, x1 + pad, y0 - pad, y1 + pad);
            for (w, ws) in world.walls.iter().enumerate() {
                if let Some(d) = ws.drum() {
                    // A drum: its circle as 128 lines, each with its inward normal.
                    const SIDES: usize = 128;
                    let at = |i: usize| {
                        let a = std::f64::consts::TAU * i as f64 / SIDES as f64;
                        d.center + Vec2::new(a.cos(), a.sin()) * d.radius
                    };
                    for i in 0..SIDES {
                        let (a, e) = (at(i), at(i + 1));
                        let ia = push_point(&mut points, (a.x, a.y));
                        let ie = push_point(&mut points, (e.x, e.y));
                        connectivity.extend([ia, ie]);
                        offsets.push(connectivity.len() as i64);
                        types.push(VTK_LINE);
                        let inward = (d.center - (a + e) * 0.5).normalize();
                        cells.push(Cell {
                            kind: 2,
                            id: w as i64,
                            normal: [inward.x, inward.y, 0.0],
                            ..Cell::default()
                        });
                    }
                    continue;
                }
                let (p, nrm) = (ws.line().point, ws.line().normal);
                let drawn = match ws.segment() {
                    Some(s) => Some((s.a, s.b)),
                    None => clip_line(p, Vec2::new(-nrm.y, nrm.x), bx),
                };
                if let Some((a, e)) = drawn {
                    let ia = push_point(&mut points, (a.x, a.y));
                    let ie = push_point(&mut points, (e.x, e.y));
                    connectivity.extend([ia, ie]);
                    offsets.push(connectivity.len() as i64);
                    types.push(VTK_LINE);
                    cells.push(Cell {
                        kind: 2,
                        id: w as i64,
                        normal: [nrm.x, nrm.y, 0.0],
                        ..Cell::default()
                    });
                }
            }
        }
        // The periodic cell: its rectangle, or its two seams across the walls' box.
        if let Some(cell) = &world.cell {
            let (lx, ly) = (cell.size.x, cell.size.y);
            let lines: Vec<(u8, Vec<(f64, f64)>)> = if cell.periodic_y() {
                let corners = [(0.0, 0.0), (lx, 0.0), (lx, ly), (0.0, ly)];
                vec![(VTK_POLY_LINE, corners.to_vec())]
            } else {
                let (_, _, y0, y1) = self.bbox.unwrap_or((0.0, lx, 0.0, ly));
                let pad = 0.05 * (y1 - y0);
                [0.0, lx]
                    .iter()
                    .map(|&x| (VTK_LINE, vec![(x, y0 - pad), (x, y1 + pad)]))
                    .collect()
            };
            for (ty, pts) in lines {
                let ids: Vec<i64> = pts.iter().map(|&p| push_point(&mut points, p)).collect();
                connectivity.extend(&ids);
                if ty == VTK_POLY_LINE {
                    connectivity.push(ids[0]); // closed
                }
                offsets.push(connectivity.len() as i64);
                types.push(ty);
                cells.push(Cell {
                    kind: 3,
                    ..Cell::default()
                });
            }
        }

        let (np, nc) = (points.len() / 3, types.len());
        let mut x = String::with_capacity(points.len() * 12 + nc * 200);
        x.push_str(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <UnstructuredGrid>\n    <FieldData>\n",
        );
        array(
            &mut x,
            "Float64",
            "TIME",
            1,
            &f64s(&[time_value(step, world.dt)]),
        );
        array(&mut x, "Int64", "STEP", 1, &i64s(&[step as i64]));
        if let Some(cell) = &world.cell {
            let size = [cell.size.x, cell.size.y];
            array(&mut x, "Float64", "CELL_SIZE", 2, &f64s(&size));
            array(&mut x, "Float64", "CELL_OFFSET", 1, &f64s(&[cell.offset]));
            array(&mut x, "Float64", "CELL_SHIFT", 1, &f64s(&[cell.shift]));
        }
        writeln!(
            x,
            "    </FieldData>\n    <Piece NumberOfPoints=\"{np}\" NumberOfCells=\"{nc}\">\n      <Points>"
        )
        .expect("string");
        array(&mut x, "Float64", "Points", 3, &f64s(&points));
        x.push_str("      </Points>\n      <Cells>\n");
        array(&mut x, "Int64", "connectivity", 1, &i64s(&connectivity));
        array(&mut x, "Int64", "offsets", 1, &i64s(&offsets));
        array(&mut x, "UInt8", "types", 1, &types);
        x.push_str("      </Cells>\n      <CellData Scalars=\"kind\">\n");
        let c = &cells;
        let ints = |f: fn(&Cell) -> i64| i64s(&c.iter().map(f).collect::<Vec<_>>());
        let floats = |f: fn(&Cell) -> f64| f64s(&c.iter().map(f).collect::<Vec<_>>());
        let vecs =
            |f: fn(&Cell) -> &[f64]| f64s(&c.iter().flat_map(f).copied().collect::<Vec<_>>());
        array(&mut x, "Int32", "kind", 1, &i32s(c.iter().map(|c| c.kind)));
        array(&mut x, "Int64", "id", 1, &ints(|c| c.id));
        array(
            &mut x,
            "Int64",
            "pair",
            2,
            &i64s(&c.iter().flat_map(|c| c.pair).collect::<Vec<_>>()),
        );
        array(
            &mut x,
            "Int32",
            "shape",
            1,
            &i32s(c.iter().map(|c| c.shape)),
        );
        array(&mut x, "Float64", "semi_axes", 2, &vecs(|c| &c.semi_axes));
        array(&mut x, "Float64", "angle", 1, &floats(|c| c.angle));
        array(&mut x, "Float64", "velocity", 3, &vecs(|c| &c.velocity));
        array(
            &mut x,
            "Float64",
            "angular_velocity",
            1,
            &floats(|c| c.angular_velocity),
        );
        array(
            &mut x,
            "Float64",
            "shape_tensor",
            9,
            &vecs(|c| &c.shape_tensor),
        );
        array(
            &mut x,
            "Float64",
            "body_normal_force",
            1,
            &floats(|c| c.body_normal_force),
        );
        array(
            &mut x,
            "Float64",
            "normal_force",
            1,
            &floats(|c| c.normal_force),
        );
        array(
            &mut x,
            "Float64",
            "tangential_force",
            1,
            &floats(|c| c.tangential_force),
        );
        array(&mut x, "Float64", "force", 3, &vecs(|c| &c.force));
        array(&mut x, "Float64", "normal", 3, &vecs(|c| &c.normal));
        array(&mut x, "Float64", "depth", 1, &floats(|c| c.depth));
        x.push_str("      </CellData>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
        x
    }
}

/// The cell data of one cell (see the module documentation).
#[derive(Clone, Debug)]
struct Cell {
    kind: i32,
    id: i64,
    pair: [i64; 2],
    shape: i32,
    semi_axes: [f64; 2],
    angle: f64,
    velocity: [f64; 3],
    angular_velocity: f64,
    shape_tensor: [f64; 9],
    body_normal_force: f64,
    normal_force: f64,
    tangential_force: f64,
    force: [f64; 3],
    normal: [f64; 3],
    depth: f64,
}

impl Default for Cell {
    fn default() -> Self {
        Cell {
            kind: 0,
            id: 0,
            pair: [-1, -1],
            shape: -1,
            semi_axes: [0.0; 2],
            angle: 0.0,
            velocity: [0.0; 3],
            angular_velocity: 0.0,
            shape_tensor: [0.0; 9],
            body_normal_force: 0.0,
            normal_force: 0.0,
            tangential_force: 0.0,
            force: [0.0; 3],
            normal: [0.0; 3],
            depth: 0.0,
        }
    }
}

fn f64s(v: &[f64]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

fn i64s(v: &[i64]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

fn i32s(v: impl Iterator<Item = i32>) -> Vec<u8> {
    v.flat_map(|x| x.to_le_bytes()).collect()
}

/// One `DataArray` in VTK's inline binary form: base64 of (the byte count as a little-endian
/// UInt64, then the bytes).
fn array(x: &mut String, ty: &str, name: &str, components: usize, bytes: &[u8]) {
    let size = match ty {
        "Float64" | "Int64" => 8,
        "Int32" => 4,
        _ => 1,
    };
    // Field data needs the tuple count (a reader takes none without it).
    let tuples = bytes.len() / (size * components);
    write!(
        x,
        "        <DataArray type=\"{ty}\" Name=\"{name}\" NumberOfComponents=\"{components}\" NumberOfTuples=\"{tuples}\" format=\"binary\">\n          "
    )
    .expect("string");
    let mut raw = Vec::with_capacity(8 + bytes.len());
    raw.extend((bytes.len() as u64).to_le_bytes());
    raw.extend_from_slice(bytes);
    base64(&raw, x);
    x.push_str("\n        </DataArray>\n");
}

/// Standard base64 (RFC 4648, with padding), appended to `out`.
pub fn base64(bytes: &[u8], out: &mut String) {
    const ABC: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    out.reserve(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            chunk.get(1).copied().unwrap_or(0),
            chunk.get(2).copied().unwrap_or(0),
        ];
        let v = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for (k, shift) in [18, 12, 6, 0].into_iter().enumerate() {
            if k <= chunk.len() {
                out.push(ABC[((v >> shift) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
}

impl Observer for VtkWriter {
    fn reads_extras(&self, moment: Moment) -> bool {
        moment.writes_frame(self.every, self.last_step)
    }

    fn start(&mut self, world: &World, _: &Plan) -> Result<(), ObserverError> {
        Ok(self.write(world)?)
    }

    fn after_step(&mut self, world: &World, info: &StepInfo) -> Result<(), ObserverError> {
        if !info.blowup && info.step.is_multiple_of(self.every) {
            self.write(world)?;
        }
        Ok(())
    }

    fn finish(&mut self, world: &World, end: &End) -> Result<(), ObserverError> {
        // A non-finite state is not drawn (VTK readers choke on it); the trajectory has it.
        if end.finite {
            self.write_labelled(world, end.step)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_matches_the_rfc_4648_test_vectors() {
        for (input, want) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            let mut s = String::new();
            base64(input.as_bytes(), &mut s);
            assert_eq!(s, want, "{input:?}");
        }
    }
}
