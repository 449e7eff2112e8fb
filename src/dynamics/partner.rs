//! The two sides of a contact, and the one rule that says which receives `+F`.
//!
//! A slot pairs a body `i` with a partner: another body `j > i`, or a boundary (a wall of the
//! case's `walls`). The partner is packed into the slot's key `j` ([`Partner::key`]) and read
//! back from it ([`Partner::from_key`]) here and nowhere else. The contact law speaks of "i" and "j" with the normal from i to j and
//! the force `+F` on j. Which body plays the law's j:
//! - two bodies: the slot's `j` receives `+F`, its `i` receives `−F` (the narrow phase's normal
//!   points from i to j);
//! - a body and a wall: the wall is the law's i (the contact normal is the wall's normal,
//!   pointing into its free side) and the body receives `+F`.
//!
//! Everything that needs the rule — the contact pass, the force gather's adjacency, the
//! critical step's Jacobian, reports of overlaps — asks [`Sides`].

use crate::geometry::Vec2;

/// Boundary `w` is keyed as `WALL_BASE + w`, above every body index.
const WALL_BASE: u32 = u32::MAX / 2;

/// The number of bodies (and of boundaries) a key can name.
pub const MAX_INDEX: u32 = WALL_BASE;

/// A body or a boundary.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Partner {
    /// Body index.
    Body(usize),
    /// Wall index.
    Wall(usize),
}

impl Partner {
    /// The partner a slot's `j` stands for.
    #[inline]
    pub fn from_key(j: u32) -> Self {
        if j >= WALL_BASE {
            Partner::Wall((j - WALL_BASE) as usize)
        } else {
            Partner::Body(j as usize)
        }
    }

    /// The key a slot's `j` holds for this partner (the inverse of [`Partner::from_key`]).
    #[inline]
    pub fn key(self) -> u32 {
        match self {
            Partner::Body(k) => k as u32,
            Partner::Wall(w) => WALL_BASE + w as u32,
        }
    }

    /// The body, if the partner is one.
    #[inline]
    pub fn body(self) -> Option<usize> {
        match self {
            Partner::Body(k) => Some(k),
            Partner::Wall(_) => None,
        }
    }
}

/// Where a contact's giver is seen from its receiver when it is not where it is: a periodic
/// image of a body (a periodic cell's seam), shifted by `offset` and, under Lees–Edwards
/// shear, moving at `velocity` relative to the body itself. The narrow phase and the law never
/// know a cell exists: the shift is applied where the pair's sides are built.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageShift {
    pub offset: Vec2,
    pub velocity: Vec2,
}

/// A contact's two sides as the law sees them: `receiver` (the law's j, always a body) receives
/// `+F` and the couple `+M`; `giver` (the law's i) receives `−F`, `−M`; `image`: the giver's
/// periodic image the receiver touches, if it is not the giver itself.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sides {
    pub receiver: usize,
    pub giver: Partner,
    pub image: Option<ImageShift>,
}

impl Sides {
    /// The sides of the slot `(i, j)` (see the module documentation).
    #[inline]
    pub fn of_slot(i: u32, j: u32) -> Self {
        match Partner::from_key(j) {
            Partner::Body(j) => Sides {
                receiver: j,
                giver: Partner::Body(i as usize),
                image: None,
            },
            wall @ Partner::Wall(_) => Sides {
                receiver: i as usize,
                giver: wall,
                image: None,
            },
        }
    }

    /// The wall of a body–wall contact.
    #[inline]
    pub fn wall(&self) -> Option<usize> {
        match self.giver {
            Partner::Wall(w) => Some(w),
            Partner::Body(_) => None,
        }
    }

    /// The giving body of a body pair.
    #[inline]
    pub fn giving_body(&self) -> Option<usize> {
        self.giver.body()
    }
}
