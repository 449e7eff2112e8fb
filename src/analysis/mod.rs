//! Measures of a granular state: the Love–Weber stress and the boundary stress from wall
//! forces, the packing fraction of a window (exact clipped areas), the coordination number with
//! and without rattlers, the fabric anisotropies `a_c`, `a_n`, `a_t` (second-order Fourier fits,
//! Rothenburg & Bathurst 1989), and the orientation order of non-circular bodies.
//!
//! Everything here is a pure function of a [`Frame`] — the bodies' shapes and poses and the
//! contacts' points, normals and forces — so that the same code serves a running world
//! ([`Frame::from_world`]) and a run already written (`dem2d analyze` rebuilds frames from
//! `trajectory.csv` and `contacts.csv`). No I/O.
//!
//! # Conventions
//! - A contact keeps the world's convention: the normal `n` points from the giver `i` (a body or
//!   a wall) to the receiver `j` (a body); the force on j is `+F`, on i `−F`. `F_n = F·n > 0` in
//!   compression, `F_t = F·t` with `t = (−n_y, n_x)`.
//! - Stresses are **compression positive** (the soil-mechanics sign): σ = −(1/V) Σ f ⊗ ℓ with f
//!   the force *on* a body at a contact and ℓ its branch vector, centroid → contact point.
//! - The **region** is an axis-aligned rectangle ([`Window`]): the box of four axis-aligned
//!   walls when the scene has one, or a window given by the caller.

pub mod fabric;
pub mod fields;
pub mod forces;
pub mod packing;
pub mod statistics;
pub mod stress;

use crate::dynamics::cell::Cell;
use crate::dynamics::{Partner, World};
use crate::geometry::{Shape, Vec2};

/// An axis-aligned rectangle `[x0, x1] × [y0, y1]` (cm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Window {
    pub x0: f64,
    pub x1: f64,
    pub y0: f64,
    pub y1: f64,
}

impl Window {
    /// Its area (cm²).
    pub fn area(&self) -> f64 {
        (self.x1 - self.x0) * (self.y1 - self.y0)
    }

    /// True when `p` lies inside (boundary included).
    pub fn contains(&self, p: Vec2) -> bool {
        p.x >= self.x0 && p.x <= self.x1 && p.y >= self.y0 && p.y <= self.y1
    }

    /// Its centre.
    pub fn centre(&self) -> Vec2 {
        Vec2::new(0.5 * (self.x0 + self.x1), 0.5 * (self.y0 + self.y1))
    }

    /// The window shrunk by `margin` on every side.
    pub fn inset(&self, margin: f64) -> Window {
        Window {
            x0: self.x0 + margin,
            x1: self.x1 - margin,
            y0: self.y0 + margin,
            y1: self.y1 - margin,
        }
    }
}

/// A body as the analysis sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameBody {
    pub shape: Shape,
    pub position: Vec2,
    pub angle: f64,
    /// g/cm³ (read by the inertial number of a periodic cell).
    pub density: f64,
}

/// A contact as the analysis sees it (see the module conventions).
#[derive(Clone, Debug, PartialEq)]
pub struct FrameContact {
    /// The giver: a body (the pair's lower index) or a wall.
    pub i: Partner,
    /// The receiver, a body.
    pub j: usize,
    pub point: Vec2,
    /// Unit normal from i to j.
    pub normal: Vec2,
    /// Force on j.
    pub force: Vec2,
    /// A couple on j (its opposite on i): zero but for the area law's deep, four-crossing
    /// overlaps, whose force acts at the crossings' mean together with this couple.
    pub couple: f64,
    pub depth: f64,
    pub state: String,
}

impl FrameContact {
    /// `F_n = F·n`.
    pub fn normal_force(&self) -> f64 {
        self.force.dot(&self.normal)
    }

    /// `F_t = F·t`, `t = (−n_y, n_x)`.
    pub fn tangential_force(&self) -> f64 {
        self.force.dot(&Vec2::new(-self.normal.y, self.normal.x))
    }

    /// The giving body, if it is one.
    pub fn giver_body(&self) -> Option<usize> {
        self.i.body()
    }

    /// Where the force acts when it carries the couple itself: the point of its line of action
    /// nearest to `point`, `point + M (F_y, −F_x)/|F|²` (the moment of `F` there about `point`
    /// is `M`). `point` for a contact without a couple, or without a force to carry it.
    pub fn action_point(&self) -> Vec2 {
        let f2 = self.force.norm_squared();
        if self.couple == 0.0 || f2 == 0.0 {
            return self.point;
        }
        self.point + Vec2::new(self.force.y, -self.force.x) * (self.couple / f2)
    }
}

/// The bodies and contacts of one instant.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Frame {
    pub time: f64,
    pub bodies: Vec<FrameBody>,
    pub contacts: Vec<FrameContact>,
    /// The box of four axis-aligned walls, if the scene has one.
    pub wall_box: Option<Window>,
    /// The periodic cell the bodies repeat in, as it was at this instant (its size, shift and
    /// stress), if the scene has one: the region is then the cell, a lever arm across a seam
    /// is taken to the contact point's nearest image, and the cell's own measures are added.
    pub cell: Option<Cell>,
}

impl Frame {
    /// The frame of a world. The contacts' normals and depths are read from the contact extras:
    /// call [`World::refresh_contact_extras`] first (the step does not keep them).
    pub fn from_world(world: &World) -> Frame {
        let b = &world.bodies;
        let bodies = (0..b.len())
            .map(|k| FrameBody {
                shape: b.shape[k],
                position: b.state[k].pose.position,
                angle: b.state[k].pose.angle(),
                density: b.density[k],
            })
            .collect();
        let contacts = world
            .contacts
            .active()
            .map(|c| {
                let s = c.sides();
                FrameContact {
                    i: s.giver,
                    j: s.receiver,
                    point: c.data.point,
                    normal: c.extra.normal,
                    force: c.data.force,
                    couple: c.data.couple,
                    depth: c.extra.depth,
                    state: c.slot.state.as_str().to_string(),
                }
            })
            .collect();
        let walls: Vec<(Vec2, Vec2)> = world
            .walls
            .iter()
            // (The box of four half-plane walls: segment walls and drums bound no box.)
            .filter(|w| w.is_half_plane())
            .map(|w| (w.line().point, w.line().normal))
            .collect();
        Frame {
            time: world.time,
            bodies,
            contacts,
            wall_box: wall_box(&walls),
            cell: world.cell,
        }
    }
}

/// The box bounded by four axis-aligned walls — one facing each of +x, −x, +y, −y, given as
/// (point, inward unit normal) — or `None` when the walls are not such a set (extra walls are
/// ignored only if the four faces are found exactly once each).
pub fn wall_box(walls: &[(Vec2, Vec2)]) -> Option<Window> {
    let (mut x0, mut x1, mut y0, mut y1) = (None, None, None, None);
    for &(p, n) in walls {
        let slot = if n.x > 1.0 - 1e-12 {
            &mut x0
        } else if n.x < -1.0 + 1e-12 {
            &mut x1
        } else if n.y > 1.0 - 1e-12 {
            &mut y0
        } else if n.y < -1.0 + 1e-12 {
            &mut y1
        } else {
            return None;
        };
        if slot.is_some() {
            return None;
        }
        *slot = Some(if n.x.abs() > 0.5 { p.x } else { p.y });
    }
    let w = Window {
        x0: x0?,
        x1: x1?,
        y0: y0?,
        y1: y1?,
    };
    (w.x1 > w.x0 && w.y1 > w.y0).then_some(w)
}

/// Everything written to one row of `analysis.csv`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Measures {
    pub time: f64,
    /// The region's area (cm²).
    pub area: f64,
    /// Love–Weber stress of the bodies whose centre lies in the region (compression positive,
    /// dyn/cm²), symmetric part.
    pub stress: [f64; 3],
    /// Boundary stress from the wall contacts (NaN without a wall box).
    pub boundary_stress: [f64; 3],
    pub packing_fraction: f64,
    pub coordination: f64,
    pub coordination_no_rattlers: f64,
    pub rattler_fraction: f64,
    pub fabric: fabric::Anisotropy,
    /// Orientation order of the non-circular bodies (NaN without any).
    pub orientation_order: f64,
    pub bodies: usize,
    pub contacts: usize,
    /// In a periodic cell, the cell's measures.
    pub cell: Option<CellMeasures>,
}

/// A periodic cell's measures (see `dynamics::cell`): its normal stress σ_yy (the pressure a
/// shear cell holds), its shear stress `(σ_xy + σ_yx)/2`, the effective friction
/// `μ = −τ/σ_yy` (positive when the cell resists a positive shear rate), the inertial number
/// `I = γ̇ d/√(P/ρ)` (GDR MiDi 2004; d the mean equal-area diameter, ρ the bodies' mean
/// density, P = σ_yy) and the cell's height.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CellMeasures {
    pub pressure: f64,
    pub shear_stress: f64,
    pub mu_eff: f64,
    pub inertial_number: f64,
    pub ly: f64,
}

impl CellMeasures {
    /// The measures of `cell` holding `bodies`.
    pub fn of(cell: &Cell, bodies: &[FrameBody]) -> Self {
        let n = bodies.len().max(1) as f64;
        let d = bodies
            .iter()
            .map(|b| 2.0 * b.shape.equal_area_radius())
            .sum::<f64>()
            / n;
        let rho = bodies.iter().map(|b| b.density).sum::<f64>() / n;
        let (p, tau) = (cell.normal_stress(), cell.shear_stress());
        CellMeasures {
            pressure: p,
            shear_stress: tau,
            mu_eff: if p > 0.0 { -tau / p } else { f64::NAN },
            inertial_number: if p > 0.0 {
                cell.shear_rate.abs() * d / (p / rho).sqrt()
            } else {
                f64::NAN
            },
            ly: cell.size.y,
        }
    }
}

/// The measures of `frame` over `region` (the wall box when `None`; without a wall box, the
/// bounding box of the bodies' outlines).
pub fn measure(frame: &Frame, region: Option<Window>) -> Measures {
    let cell_box = frame.cell.map(|c| Window {
        x0: 0.0,
        x1: c.size.x,
        y0: 0.0,
        y1: c.size.y,
    });
    let region = region
        .or(cell_box)
        .or(frame.wall_box)
        .unwrap_or_else(|| packing::bounding_window(&frame.bodies));
    let inside: Vec<bool> = frame
        .bodies
        .iter()
        .map(|b| region.contains(b.position))
        .collect();
    let stress = stress::love_weber(frame, &inside, region.area());
    let boundary_stress = match frame.wall_box {
        Some(b) => stress::boundary(frame, b).symmetric(),
        None => [f64::NAN; 3],
    };
    let coord = packing::coordination(frame, &inside);
    let fab = fabric::anisotropy(frame, &inside);
    Measures {
        time: frame.time,
        area: region.area(),
        stress: stress.symmetric(),
        boundary_stress,
        // A cell holds each body once (a body across a seam is there in two pieces).
        packing_fraction: match frame.cell {
            Some(c) => frame.bodies.iter().map(|b| b.shape.area()).sum::<f64>() / c.area(),
            None => packing::packing_fraction(&frame.bodies, region),
        },
        coordination: coord.with_rattlers,
        coordination_no_rattlers: coord.without_rattlers,
        rattler_fraction: coord.rattler_fraction,
        fabric: fab,
        orientation_order: fabric::orientation_order(frame, &inside).0,
        bodies: inside.iter().filter(|&&b| b).count(),
        contacts: frame.contacts.len(),
        cell: frame.cell.map(|c| CellMeasures::of(&c, &frame.bodies)),
    }
}
