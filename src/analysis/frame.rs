//! One frame of a run as the measures read it ([`Frame`]: bodies, contacts, the cell), and the
//! region they average over ([`Window`]).

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
