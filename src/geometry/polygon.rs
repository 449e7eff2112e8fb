//! Convex polygons: the vertex list of a [`Shape::Polygon`](super::Shape::Polygon), checked
//! once, shifted to its centroid, with its area, inertia and radii computed once.
//!
//! # Sharing (why `Shape` stays `Copy`)
//! Every per-shape fact is a method of `Shape`, which is `Copy` and travels by value through the
//! whole code (the body arrays, the narrow phase's `Object`, the analysis frames). A polygon's
//! vertex list cannot be copied cheaply, so a [`Polygon`] is a reference into a process-wide
//! shape table: each distinct vertex list (as given, bit for bit) is stored there once, for the
//! life of the process, and every grain of that shape points at it. The table only grows with
//! the number of *distinct* polygons a process loads (a case file's few shapes), never with the
//! number of grains or of loads of the same case. This keeps `Shape: Copy` (no clone, no
//! reference count in the contact loop) — the least invasive design; an `Arc<[Vec2]>` would have
//! made `Shape` non-`Copy` and touched every place a shape is passed.
//!
//! # The body frame
//! A body's frame has its origin at the centroid (the dynamics integrates the centroid and turns
//! the body about it). The vertices as given may be anywhere: they are **shifted by minus their
//! centroid** at load ([`PolygonData::shift`] keeps what was subtracted, so a case's `position`
//! is the centroid's position, not that of the vertices' origin). Mass and inertia then follow
//! from the exact polygon formulas (the shoelace area and the polar second moment of area; e.g.
//! Bourke, "Calculating the area and centroid of a polygon", 1988, and Eberly, "Polygon moments"
//! in *Geometric Tools*):
//! - `A = ½ Σ (x_k y_{k+1} − x_{k+1} y_k)`,
//! - `c = (1/6A) Σ (v_k + v_{k+1}) (x_k y_{k+1} − x_{k+1} y_k)`,
//! - `J = (1/12) Σ (x_k y_{k+1} − x_{k+1} y_k)(v_k·v_k + v_k·v_{k+1} + v_{k+1}·v_{k+1})` about the
//!   origin of the (centred) vertices, so `I/m = J/A`.

use super::pose::Vec2;
use std::collections::HashMap;
use std::fmt;
use std::sync::{Mutex, OnceLock};

/// A convex polygon's data (body frame: centroid at the origin, counter-clockwise).
#[derive(Debug, PartialEq)]
pub struct PolygonData {
    /// Vertices relative to the centroid, counter-clockwise.
    pub vertices: Box<[Vec2]>,
    /// Outward unit normals of the edges (edge k from vertex k to k + 1).
    pub normals: Box<[Vec2]>,
    /// The centroid of the vertices as given (subtracted from them).
    pub shift: Vec2,
    /// Area.
    pub area: f64,
    /// Polar moment of inertia about the centroid divided by mass, `J/A`.
    pub inertia_per_mass: f64,
    /// Largest distance from the centroid to a vertex.
    pub bounding_radius: f64,
    /// Smallest distance from the centroid to an edge's line.
    pub inscribed_radius: f64,
    /// Length of the longest edge.
    pub longest_edge: f64,
    /// The long axis (body frame, radians in (−π/2, π/2]): the principal direction of the
    /// largest second moment of area; `None` when the two are equal (regular polygons).
    pub long_axis: Option<f64>,
    /// Semi-axes `(a, b)`, `a ≥ b`, of the ellipse with the same second moments of area (a
    /// along the long axis: `a² = 4 I₁/A`, `b² = 4 I₂/A` with I₁ ≥ I₂ the principal moments),
    /// for outputs that describe a body by an ellipse (VTK's shape tensor).
    pub moment_ellipse: [f64; 2],
}

/// A convex polygon shape: a shared reference into the process-wide shape table (see the
/// module documentation). Two `Polygon`s are equal exactly when their vertex lists as given are
/// (the table stores each list once, so this compares pointers).
#[derive(Clone, Copy)]
pub struct Polygon(&'static PolygonData);

impl PartialEq for Polygon {
    fn eq(&self, other: &Self) -> bool {
        std::ptr::eq(self.0, other.0)
    }
}

impl fmt::Debug for Polygon {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list()
            .entries(self.0.vertices.iter().map(|v| [v.x, v.y]))
            .finish()
    }
}

impl std::ops::Deref for Polygon {
    type Target = PolygonData;
    fn deref(&self) -> &PolygonData {
        self.0
    }
}

/// Why a vertex list is not a usable convex polygon. `vertex` indices are those of the list as
/// given.
#[derive(Clone, Debug, PartialEq)]
pub enum PolygonError {
    /// Fewer than three vertices.
    TooFew(usize),
    /// A coordinate is NaN or infinite.
    NonFinite(usize),
    /// Vertex `k` equals the next one.
    Duplicate(usize),
    /// Vertex `k` lies on the line through its neighbours (a straight angle).
    Collinear(usize),
    /// The vertices run clockwise.
    Clockwise,
    /// The polygon turns the wrong way at vertex `k` (or winds round more than once).
    NonConvex(usize),
    /// All vertices on one line.
    ZeroArea,
}

impl fmt::Display for PolygonError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PolygonError::TooFew(n) => write!(f, "a polygon needs at least 3 vertices, got {n}"),
            PolygonError::NonFinite(k) => write!(f, "vertex {k} is not finite"),
            PolygonError::Duplicate(k) => {
                write!(f, "vertex {k} repeats the next vertex (duplicate vertices)")
            }
            PolygonError::Collinear(k) => write!(
                f,
                "vertex {k} lies on the line through its neighbours (collinear vertices)"
            ),
            PolygonError::Clockwise => {
                write!(f, "the vertices run clockwise; give them counter-clockwise")
            }
            PolygonError::NonConvex(k) => {
                write!(
                    f,
                    "the polygon is not convex (it turns clockwise at vertex {k})"
                )
            }
            PolygonError::ZeroArea => write!(f, "the polygon has zero area"),
        }
    }
}

impl std::error::Error for PolygonError {}

/// Relative size of `e_prev × e_next` (against `|e_prev||e_next|`, the sine of the turn) below
/// which a vertex counts as a straight angle.
const COLLINEAR_SINE: f64 = 1e-12;

type Table = Mutex<HashMap<Vec<[u64; 2]>, &'static PolygonData>>;

fn table() -> &'static Table {
    static TABLE: OnceLock<Table> = OnceLock::new();
    TABLE.get_or_init(|| Mutex::new(HashMap::new()))
}

impl Polygon {
    /// The convex polygon with these vertices (counter-clockwise, in any frame: they are shifted
    /// to their centroid), from the shape table; checked, see [`PolygonError`].
    pub fn new(given: &[[f64; 2]]) -> Result<Polygon, PolygonError> {
        let key: Vec<[u64; 2]> = given
            .iter()
            .map(|p| [p[0].to_bits(), p[1].to_bits()])
            .collect();
        if let Some(&d) = table().lock().expect("shape table").get(&key) {
            return Ok(Polygon(d));
        }
        let data = PolygonData::new(given)?;
        let mut t = table().lock().expect("shape table");
        let d: &'static PolygonData = t.entry(key).or_insert_with(|| Box::leak(Box::new(data)));
        Ok(Polygon(d))
    }

    /// The regular `n`-gon inscribed in the circle of radius `r`, its first vertex at angle
    /// `phase` (radians).
    pub fn regular(n: usize, r: f64, phase: f64) -> Result<Polygon, PolygonError> {
        let v: Vec<[f64; 2]> = (0..n)
            .map(|k| {
                let t = phase + 2.0 * std::f64::consts::PI * k as f64 / n as f64;
                [r * t.cos(), r * t.sin()]
            })
            .collect();
        Polygon::new(&v)
    }

    /// The `n`-gon with vertices on the ellipse `x²/a² + y²/b² = 1` at equally spaced eccentric
    /// angles (first at `phase`), scaled about the centre so that its area is the ellipse's `πab`.
    pub fn equal_area_ellipse(
        n: usize,
        a: f64,
        b: f64,
        phase: f64,
    ) -> Result<Polygon, PolygonError> {
        // The inscribed n-gon has area (n/2) ab sin(2π/n).
        let t = 2.0 * std::f64::consts::PI / n as f64;
        let s = (std::f64::consts::PI / (0.5 * n as f64 * t.sin())).sqrt();
        let v: Vec<[f64; 2]> = (0..n)
            .map(|k| {
                let u = phase + t * k as f64;
                [s * a * u.cos(), s * b * u.sin()]
            })
            .collect();
        Polygon::new(&v)
    }

    /// Support `max over vertices of u·v` (u in the body frame, any length).
    #[inline]
    pub fn support(&self, u: Vec2) -> f64 {
        vertex_support(&self.0.vertices, u)
    }

    /// The data's address (a stable key for canonical orders within one process).
    pub fn data(&self) -> &'static PolygonData {
        self.0
    }
}

/// `max over the vertices of u·v` (u any length): a convex polygon's support along `u`.
#[inline]
pub fn vertex_support(vertices: &[Vec2], u: Vec2) -> f64 {
    vertices
        .iter()
        .map(|v| u.x * v.x + u.y * v.y)
        .fold(f64::NEG_INFINITY, f64::max)
}

/// The corners of a `w × h` rectangle centred at the origin (its sides along the axes),
/// counter-clockwise from `(−w/2, −h/2)`.
#[inline]
pub fn rectangle_corners(w: f64, h: f64) -> [Vec2; 4] {
    let (x, y) = (0.5 * w, 0.5 * h);
    [
        Vec2::new(-x, -y),
        Vec2::new(x, -y),
        Vec2::new(x, y),
        Vec2::new(-x, y),
    ]
}

/// The outward normals of [`rectangle_corners`]' edges (edge k from corner k to k + 1).
pub const RECTANGLE_NORMALS: [Vec2; 4] = [
    Vec2::new(0.0, -1.0),
    Vec2::new(1.0, 0.0),
    Vec2::new(0.0, 1.0),
    Vec2::new(-1.0, 0.0),
];

impl PolygonData {
    fn new(given: &[[f64; 2]]) -> Result<PolygonData, PolygonError> {
        let n = given.len();
        if n < 3 {
            return Err(PolygonError::TooFew(n));
        }
        if let Some(k) = given
            .iter()
            .position(|p| !(p[0].is_finite() && p[1].is_finite()))
        {
            return Err(PolygonError::NonFinite(k));
        }
        let at = |k: usize| Vec2::new(given[k % n][0], given[k % n][1]);
        for k in 0..n {
            if at(k) == at(k + 1) {
                return Err(PolygonError::Duplicate(k));
            }
        }
        // Shoelace about the first vertex (small numbers for a polygon far from the origin).
        let o = at(0);
        let (mut twice, mut cx, mut cy) = (0.0, 0.0, 0.0);
        for k in 1..n - 1 {
            let (p, q) = (at(k) - o, at(k + 1) - o);
            let cr = p.x * q.y - p.y * q.x;
            twice += cr;
            cx += (p.x + q.x) * cr;
            cy += (p.y + q.y) * cr;
        }
        let scale = given
            .iter()
            .map(|p| (p[0] - o.x).hypot(p[1] - o.y))
            .fold(0.0, f64::max);
        if twice.abs() <= COLLINEAR_SINE * scale * scale {
            return Err(PolygonError::ZeroArea);
        }
        if twice < 0.0 {
            return Err(PolygonError::Clockwise);
        }
        // Every turn left, and once round in all (a star polygon also turns left everywhere).
        let mut turning = 0.0;
        for k in 0..n {
            let (e0, e1) = (at(k + n) - at(k + n - 1), at(k + 1) - at(k));
            let cr = e0.x * e1.y - e0.y * e1.x;
            if cr.abs() <= COLLINEAR_SINE * e0.norm() * e1.norm() {
                return Err(PolygonError::Collinear(k));
            }
            if cr < 0.0 {
                return Err(PolygonError::NonConvex(k));
            }
            turning += cr.atan2(e0.dot(&e1));
        }
        if turning > 3.0 * std::f64::consts::PI {
            return Err(PolygonError::NonConvex(0));
        }
        let shift = o + Vec2::new(cx, cy) / (3.0 * twice);
        let vertices: Box<[Vec2]> = (0..n).map(|k| at(k) - shift).collect();
        let v = |k: usize| vertices[k % n];
        let (mut a2, mut j12, mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0, 0.0, 0.0);
        let mut normals = Vec::with_capacity(n);
        let (mut inscribed, mut longest) = (f64::INFINITY, 0.0f64);
        for k in 0..n {
            let (p, q) = (v(k), v(k + 1));
            let cr = p.x * q.y - p.y * q.x;
            a2 += cr;
            // Second moments of area about the centroid (Eberly): ∫x² = Σ cr (x_p² + x_p x_q +
            // x_q²)/12, likewise y², and ∫xy = Σ cr (2x_p y_p + x_p y_q + x_q y_p + 2x_q y_q)/24.
            sxx += cr * (p.x * p.x + p.x * q.x + q.x * q.x);
            syy += cr * (p.y * p.y + p.y * q.y + q.y * q.y);
            sxy += cr * (2.0 * p.x * p.y + p.x * q.y + q.x * p.y + 2.0 * q.x * q.y);
            j12 += cr * (p.dot(&p) + p.dot(&q) + q.dot(&q));
            let e = q - p;
            let len = e.norm();
            longest = longest.max(len);
            let u = Vec2::new(e.y / len, -e.x / len);
            normals.push(u);
            inscribed = inscribed.min(u.dot(&p));
        }
        let area = 0.5 * a2;
        let (ixx, iyy, ixy) = (sxx / 12.0, syy / 12.0, sxy / 24.0);
        // Principal axes of the second moment tensor [[∫x², ∫xy], [∫xy, ∫y²]].
        let spread = (0.5 * (ixx - iyy)).hypot(ixy);
        let long_axis = (spread > 1e-12 * (ixx + iyy)).then(|| 0.5 * (2.0 * ixy).atan2(ixx - iyy));
        let mean = 0.5 * (ixx + iyy);
        let moment_ellipse = [
            (4.0 * (mean + spread) / area).sqrt(),
            (4.0 * (mean - spread).max(0.0) / area).sqrt(),
        ];
        let bounding_radius = vertices.iter().map(|p| p.norm()).fold(0.0, f64::max);
        Ok(PolygonData {
            vertices,
            normals: normals.into_boxed_slice(),
            shift,
            area,
            inertia_per_mass: j12 / 12.0 / area,
            bounding_radius,
            inscribed_radius: inscribed,
            longest_edge: longest,
            long_axis,
            moment_ellipse,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_shifted_square_is_centred_with_the_rectangle_formulas() {
        let p = Polygon::new(&[[1.0, 1.0], [3.0, 1.0], [3.0, 2.0], [1.0, 2.0]]).unwrap();
        assert_eq!(p.shift, Vec2::new(2.0, 1.5));
        assert!((p.area - 2.0).abs() < 1e-15);
        assert!((p.inertia_per_mass - (4.0 + 1.0) / 12.0).abs() < 1e-15);
        assert_eq!(p.long_axis, Some(0.0));
        assert!((p.inscribed_radius - 0.5).abs() < 1e-15);
        // The same list gives the same table entry.
        let q = Polygon::new(&[[1.0, 1.0], [3.0, 1.0], [3.0, 2.0], [1.0, 2.0]]).unwrap();
        assert_eq!(p, q);
    }

    #[test]
    fn bad_lists_are_named() {
        use PolygonError::*;
        let sq = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert_eq!(Polygon::new(&sq[..2]).unwrap_err(), TooFew(2));
        let mut cw = sq;
        cw.reverse();
        assert_eq!(Polygon::new(&cw).unwrap_err(), Clockwise);
        let dart = [[0.0, 0.0], [2.0, 0.0], [1.0, 0.5], [1.0, 2.0]];
        assert_eq!(Polygon::new(&dart).unwrap_err(), NonConvex(2));
        let col = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [1.0, 1.0]];
        assert_eq!(Polygon::new(&col).unwrap_err(), Collinear(1));
        let dup = [[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [1.0, 1.0]];
        assert_eq!(Polygon::new(&dup).unwrap_err(), Duplicate(1));
        let flat = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]];
        assert_eq!(Polygon::new(&flat).unwrap_err(), ZeroArea);
        let star: Vec<[f64; 2]> = (0..5)
            .map(|k| {
                let t = 4.0 * std::f64::consts::PI * k as f64 / 5.0;
                [t.cos(), t.sin()]
            })
            .collect();
        assert!(matches!(Polygon::new(&star).unwrap_err(), NonConvex(_)));
        assert_eq!(
            Polygon::new(&[[0.0, 0.0], [f64::NAN, 0.0], [0.0, 1.0]]).unwrap_err(),
            NonFinite(1)
        );
    }

    #[test]
    fn regular_polygons_have_the_closed_form_inertia() {
        // A regular n-gon of circumradius R: I/m = R²(1 + 2cos²(π/n))/12·... = (R²/6)(2 + cos(2π/n)).
        for n in [3usize, 4, 6, 64] {
            let p = Polygon::regular(n, 1.3, 0.2).unwrap();
            let want = 1.3f64.powi(2) / 6.0 * (2.0 + (2.0 * std::f64::consts::PI / n as f64).cos());
            assert!((p.inertia_per_mass - want).abs() < 1e-14, "{n}");
            assert!(p.long_axis.is_none(), "{n}");
        }
    }
}
