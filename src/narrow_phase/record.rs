//! The narrow phase's records: the one contact record every pair kind produces ([`Contact`], its
//! [`ContactState`], [`OverlapArea`], [`FlatOverlap`]), the two sides of a pair ([`Object`],
//! [`Side`]) and what a query asks ([`Request`]). The conventions are the module's (see
//! [`super`]).

use crate::geometry::{Drum, Pose, Segment, Shape, Vec2, Wall};
use std::cell::Cell;

/// How two objects relate.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ContactState {
    /// No common point.
    Separated,
    /// Boundaries touch at one point (within rounding); depth ≈ 0.
    Touching,
    /// Boundaries cross at two points: the chord definition applies exactly.
    Overlap,
    /// Boundaries cross four (or more) times: fallback geometry, flagged.
    Deep,
    /// One solid lies inside the other (boundaries do not cross): fallback geometry, flagged.
    Contained,
}

impl ContactState {
    /// The name used in the JSON output.
    pub fn as_str(&self) -> &'static str {
        match self {
            ContactState::Separated => "separated",
            ContactState::Touching => "touching",
            ContactState::Overlap => "overlap",
            ContactState::Deep => "deep",
            ContactState::Contained => "contained",
        }
    }

    /// True for the fallback geometries ([`Deep`](Self::Deep), [`Contained`](Self::Contained)).
    pub fn is_deep(&self) -> bool {
        matches!(self, ContactState::Deep | ContactState::Contained)
    }

    /// The state of a query's result: [`Separated`](Self::Separated) for none.
    #[inline]
    pub fn of(c: Option<&Contact>) -> ContactState {
        c.map_or(ContactState::Separated, |c| c.state)
    }
}

/// The one contact record every pair kind produces (world coordinates), for two objects that
/// touch; a query's `None` is "apart".
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// Relation of the pair (never [`ContactState::Separated`]).
    pub state: ContactState,
    /// Chord midpoint (contact point).
    pub point: Vec2,
    /// Unit normal from i towards j, perpendicular to the chord.
    pub normal: Vec2,
    /// Overlap along `normal` (positive when penetrating).
    pub depth: f64,
    /// Half the chord's length ([`Contact::chord`]): 0 for touching and for the fallbacks'
    /// degenerate chords, and when the [`Request`] did not ask for the chord (the dynamics
    /// reads none; two circles, say, would pay a square root for it).
    pub half_chord: f64,
    /// The overlap area and its gradient, when asked for (see [`OverlapArea`]); `None`
    /// otherwise, and for touching pairs.
    pub area: Option<OverlapArea>,
    /// The overlap polygon's area and centroid where both sides are flat (a flat-sided body —
    /// `Shape::is_flat_sided`, a rectangle — against a wall or another); `None` otherwise. See
    /// [`FlatOverlap`].
    pub flat: Option<FlatOverlap>,
}

impl Contact {
    /// The chord's two ends, `point ∓ half_chord · t` with `t = (−n_y, n_x)` (the same two
    /// points, exchanged, for the pair seen the other way round).
    #[inline]
    pub fn chord(&self) -> (Vec2, Vec2) {
        let t = Vec2::new(-self.normal.y, self.normal.x) * self.half_chord;
        (self.point - t, self.point + t)
    }

    /// The same contact seen from the other body (i ↔ j): normal flipped (and the area
    /// gradient's normal and couple), all else kept.
    #[inline(always)]
    pub fn swapped(mut self) -> Contact {
        self.turn();
        self
    }

    /// Turns this contact round in place ([`Contact::swapped`]).
    #[inline(always)]
    pub(super) fn turn(&mut self) {
        self.normal = -self.normal;
        if let Some(a) = &mut self.area {
            // The other body's gradient: the opposite force and the opposite couple.
            a.normal = -a.normal;
            a.couple = -a.couple;
        }
    }
}

/// The overlap area `A` of a pair and how it changes with j's rigid motion: the geometry of the
/// energy-conserving normal force, which derives from a potential `W(A)` (Feng, Han & Owen
/// 2012). Moving j by `du` and turning it by `dθ` about its centroid `c_j` changes the area by
///
/// `dA = −length · n·du − (length · (point − c_j) × n + couple) dθ`,
///
/// so the force `W′(A) · length · n` at `point` plus the couple `W′(A) · couple` on j (their
/// opposites on i) is exactly `−∇W`. For two crossings (divergence theorem over the part of j
/// inside i) `length` is the chord length L, `n` and `point` are the chord's normal and
/// midpoint — P's chord, so only the magnitude differs from a spring on the depth — and the
/// couple is zero. For four or more crossings the gradient is the sum, over the arcs of j's
/// boundary inside i, of each arc's closing chord `L_k n_k` at its midpoint; `point` is then the
/// crossings' mean and `couple` what the sum leaves about it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OverlapArea {
    /// Area of the overlap.
    pub area: f64,
    /// `|∂A/∂x_j|`: the chord length for two crossings.
    pub length: f64,
    /// Unit vector along `−∂A/∂x_j` (from i towards j).
    pub normal: Vec2,
    /// Where the force acts (world coordinates).
    pub point: Vec2,
    /// The gradient's couple about `point`, see above (zero for two crossings).
    pub couple: f64,
}

/// The overlap of two flat-sided objects (a polygon), for a contact that acts like a Winkler
/// foundation: pressure `k′ × local penetration`, so a resultant `k′ A` at the overlap's
/// centroid (the centre of pressure) along the chord normal, and stored energy `k′ A ȳ` with ȳ
/// the centroid's distance from the chord — the area-based polygon contact of Tillemans &
/// Herrmann. Against a flat line this is exactly the gradient of that energy. With one contact
/// point, a spring on `depth` (the deepest corner's penetration) at the chord midpoint is not
/// the gradient of any potential when a face lies on a face: a rectangle resting on a floor then
/// rocks forever, fed by its own contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlatOverlap {
    /// Area of the overlap polygon.
    pub area: f64,
    /// Its centroid (world coordinates).
    pub centroid: Vec2,
}

/// One side of a pair: a placed body, a wall (a half-plane) or a segment wall.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Object {
    Body {
        shape: Shape,
        pose: Pose,
    },
    Wall(Wall),
    Segment(Segment),
    /// A drum: a circle with the bodies inside it (see [`drum`]).
    Drum(Drum),
}

/// One side of a pair, borrowed: what a caller that keeps its bodies elsewhere (the dynamics)
/// hands the dispatcher, without copying shapes and poses into [`Object`]s.
#[derive(Clone, Copy, Debug)]
pub enum Side<'a> {
    Body(&'a Shape, &'a Pose),
    Wall(&'a Wall),
    Segment(&'a Segment),
    Drum(&'a Drum),
}

impl Object {
    /// True for a clump.
    #[inline]
    pub fn is_clump(&self) -> bool {
        matches!(
            self,
            Object::Body {
                shape: Shape::Clump(_),
                ..
            }
        )
    }
}

impl<'a> From<&'a Object> for Side<'a> {
    #[inline(always)]
    fn from(o: &'a Object) -> Self {
        match o {
            Object::Body { shape, pose } => Side::Body(shape, pose),
            Object::Wall(w) => Side::Wall(w),
            Object::Segment(s) => Side::Segment(s),
            Object::Drum(d) => Side::Drum(d),
        }
    }
}

/// What a query computes besides the contact's state, point, normal and depth (which it always
/// gives), and whether to report how it got them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Request<'a> {
    /// The overlap area and its gradient ([`Contact::area`]).
    pub area: bool,
    /// The chord's half-length ([`Contact::half_chord`]; 0 without it).
    pub chord: bool,
    /// Where to record whether the pair cache's warm start gave the result (rather than the
    /// computation from scratch): for the tests that hold the warm path to the same bars.
    pub trace: Option<&'a Cell<bool>>,
}

impl Request<'static> {
    /// Everything: the chord and the overlap area (one-off queries, the `contact` command).
    pub const FULL: Request<'static> = Request {
        area: true,
        chord: true,
        trace: None,
    };
    /// The chord geometry without the overlap area.
    pub const CHORD: Request<'static> = Request {
        area: false,
        chord: true,
        trace: None,
    };
    /// The state, point, normal and depth alone (what a spring on the depth reads).
    pub const LEAN: Request<'static> = Request {
        area: false,
        chord: false,
        trace: None,
    };
}

/// Relative tolerance (of the pair's size) below which a depth counts as touching.
pub const TOUCH_TOL: f64 = 1e-14;
