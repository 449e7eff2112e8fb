//! The BODY and wall forms:
//! `{"shape": {"type": "ellipse", "a": 1.5, "b": 1.0}, "position": [x, y], "angle": θ}`
//! (types `circle` with `r`, `ellipse` with `a`, `b`, `rectangle` with `w`, `h`, `polygon` with
//! `vertices`: `[[x, y], …]`, counter-clockwise and convex, shifted to their centroid — the
//! body's `position` is the centroid's, `clump` with `disks`: `[{"center": [x, y], "r": r}, …]`,
//! shifted to the centroid of their union — the body's `position` is that centroid's) and
//! `{"wall": {"point": [x, y], "normal": [nx, ny]}}` or a segment wall
//! `{"wall": {"segment": [[x0, y0], [x1, y1]]}}` or a drum
//! `{"wall": {"drum": {"center": [x, y], "radius": R}}}`.

use super::fields::{FieldError, Obj, index, number, scale, type_of, vec2};
use super::ranges::{Placed, check_extent};
use crate::geometry::{Clump, ClumpError, Polygon, PolygonError, Pose, Segment, SegmentError};
use crate::geometry::{Drum, Shape, Vec2, Wall};
use crate::narrow_phase::Object;
use serde_json::Value;

/// Most vertices a polygon may have.
pub const MAX_POLYGON_VERTICES: usize = 1000;

/// A shape object `{"type": …, sizes…}`.
pub fn parse_shape(v: &Value, path: &str) -> Result<Shape, FieldError> {
    let mut o = Obj::new(v, path)?;
    let ty = o.req_with("type", |v, p| {
        v.as_str()
            .map(str::to_string)
            .ok_or_else(|| FieldError::new(p, format!("must be a string, got {}", type_of(v))))
    })?;
    let shape = match ty.as_str() {
        "circle" => Shape::Circle {
            r: o.req_with("r", scale)?,
        },
        "ellipse" => Shape::Ellipse {
            a: o.req_with("a", scale)?,
            b: o.req_with("b", scale)?,
        },
        "rectangle" => Shape::Rectangle {
            w: o.req_with("w", scale)?,
            h: o.req_with("h", scale)?,
        },
        "polygon" => Shape::Polygon(o.req_with("vertices", polygon)?),
        "clump" => Shape::Clump(o.req_with("disks", clump)?),
        other => {
            return Err(FieldError::new(
                o.field_path("type"),
                format!(
                    "unknown shape type `{other}` (expected `circle`, `ellipse`, `rectangle`, \
                     `polygon` or `clump`)"
                ),
            ));
        }
    };
    o.finish()?;
    Ok(shape)
}

/// A polygon's `vertices`: an array of at least three `[x, y]`, counter-clockwise, convex, with
/// no two consecutive vertices equal and no straight angle (see [`Polygon::new`]); errors name
/// the vertex (`vertices[k]`) where one is at fault.
fn polygon(v: &Value, path: &str) -> Result<Polygon, FieldError> {
    let Some(items) = v.as_array() else {
        return Err(FieldError::new(
            path,
            format!("must be an array of [x, y] vertices, got {}", type_of(v)),
        ));
    };
    if items.len() > MAX_POLYGON_VERTICES {
        return Err(FieldError::new(
            path,
            format!(
                "{} vertices: at most {MAX_POLYGON_VERTICES} are accepted (a polygon's contact \
                 tests walk its vertices: at 100 000, 200 steps of one body took 1.5 s); \
                 describe a smooth body as an ellipse, a circle or a clump of disks",
                items.len()
            ),
        ));
    }
    let vertices = items
        .iter()
        .enumerate()
        .map(|(k, p)| vec2(p, &index(path, k)))
        .collect::<Result<Vec<_>, _>>()?;
    Polygon::new(&vertices).map_err(|e| {
        let at = match e {
            PolygonError::NonFinite(k)
            | PolygonError::Duplicate(k)
            | PolygonError::Collinear(k)
            | PolygonError::NonConvex(k) => index(path, k),
            PolygonError::TooFew(_) | PolygonError::Clockwise | PolygonError::ZeroArea => {
                path.to_string()
            }
        };
        FieldError::new(at, e.to_string())
    })
}

/// A clump's `disks`: a non-empty array of `{"center": [x, y], "r": r}` (finite centres, `r`
/// positive and finite; see [`Clump::new`]); errors name the disk's field (`disks[k].r`).
fn clump(v: &Value, path: &str) -> Result<Clump, FieldError> {
    let Some(items) = v.as_array() else {
        return Err(FieldError::new(
            path,
            format!(
                "must be an array of {{\"center\": [x, y], \"r\": r}} disks, got {}",
                type_of(v)
            ),
        ));
    };
    let disks = items
        .iter()
        .enumerate()
        .map(|(k, d)| {
            let at = index(path, k);
            let mut o = Obj::new(d, &at)?;
            let center = o.req_with("center", vec2)?;
            let r = o.req_with("r", number)?;
            o.finish()?;
            Ok((center, r))
        })
        .collect::<Result<Vec<_>, FieldError>>()?;
    Clump::new(&disks).map_err(|e| {
        let at = match e {
            ClumpError::NonFiniteCentre(k) => format!("{}.center", index(path, k)),
            ClumpError::BadRadius(k, _) => format!("{}.r", index(path, k)),
            ClumpError::Empty | ClumpError::TooMany(_) => path.to_string(),
        };
        FieldError::new(at, e.to_string())
    })
}

/// What a wall object describes: a half-plane or a segment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum WallGeometry {
    HalfPlane(Wall),
    Segment(Segment),
    Drum(Drum),
}

/// A wall's inner object: a half-plane `{"point": [x, y], "normal": [nx, ny]}` (the normal need
/// not be unit; it points into the free side) or a segment `{"segment": [[x0, y0], [x1, y1]]}`
/// (its two ends, cm; not both). `extra` reads any further fields (case files add contact
/// parameters) before unknown ones are rejected.
pub fn parse_wall_or_segment_with<T>(
    v: &Value,
    path: &str,
    extra: impl FnOnce(&mut Obj) -> Result<T, FieldError>,
) -> Result<(WallGeometry, T), FieldError> {
    let mut o = Obj::new(v, path)?;
    let geometry = if o.has("drum") {
        for key in ["point", "normal", "segment"] {
            if o.has(key) {
                return Err(FieldError::new(
                    o.field_path(key),
                    "give a wall's `drum` (its centre and radius), its `segment` or its `point` \
                     and `normal` (a half-plane): one of them",
                ));
            }
        }
        WallGeometry::Drum(o.req_with("drum", parse_drum)?)
    } else if o.has("segment") {
        for key in ["point", "normal"] {
            if o.has(key) {
                return Err(FieldError::new(
                    o.field_path(key),
                    "give a wall's `segment` (its two ends) or its `point` and `normal` (a \
                     half-plane), not both",
                ));
            }
        }
        WallGeometry::Segment(o.req_with("segment", parse_segment)?)
    } else {
        let point = o.req_with("point", vec2)?;
        let normal = Vec2::from(o.req_with("normal", vec2)?);
        // `Wall::new` takes a normal of any non-zero length (a tiny one such as [1e-200, 1e-200],
        // whose squared length underflows, too) and keeps its direction exactly.
        let wall = Wall::new(Vec2::from(point), normal)
            .ok_or_else(|| FieldError::new(o.field_path("normal"), "must be a non-zero vector"))?;
        WallGeometry::HalfPlane(wall)
    };
    let t = extra(&mut o)?;
    o.finish()?;
    Ok((geometry, t))
}

/// A drum `{"center": [x, y], "radius": R}` (R a positive scale).
pub fn parse_drum(v: &Value, path: &str) -> Result<Drum, FieldError> {
    let mut o = Obj::new(v, path)?;
    let center = o.req_with("center", vec2)?;
    let radius = o.req_with("radius", scale)?;
    o.finish()?;
    Drum::new(Vec2::from(center), radius)
        .ok_or_else(|| FieldError::new(path, "must have a finite centre and a positive radius"))
}

/// A segment's two ends `[[x0, y0], [x1, y1]]` (finite, distinct).
pub fn parse_segment(v: &Value, path: &str) -> Result<Segment, FieldError> {
    let ends = match v.as_array() {
        Some(a) if a.len() == 2 => [vec2(&a[0], &index(path, 0))?, vec2(&a[1], &index(path, 1))?],
        _ => {
            return Err(FieldError::new(
                path,
                format!(
                    "must be two points [[x0, y0], [x1, y1]], got {}",
                    match v {
                        Value::Array(a) => format!("an array of {} elements", a.len()),
                        other => type_of(other).to_string(),
                    }
                ),
            ));
        }
    };
    Segment::new(Vec2::from(ends[0]), Vec2::from(ends[1])).map_err(|e| {
        FieldError::new(
            path,
            match e {
                SegmentError::ZeroLength => format!(
                    "has zero length: both ends are [{}, {}] (a segment wall needs two distinct \
                     ends)",
                    ends[0][0], ends[0][1]
                ),
                SegmentError::NonFinite => {
                    "its ends are too far apart: b − a overflows".to_string()
                }
            },
        )
    })
}

/// A placed body `{"shape": …, "position": [x, y], "angle": θ}` (`angle` defaults to 0), with
/// `extra` reading any further fields before unknown ones are rejected.
pub fn parse_body_with<T>(
    o: &mut Obj,
    extra: impl FnOnce(&mut Obj) -> Result<T, FieldError>,
) -> Result<(Shape, Pose, T), FieldError> {
    let shape = o.req_with("shape", parse_shape)?;
    let position = o.req_with("position", vec2)?;
    let angle = o.opt_with("angle", number)?.unwrap_or(0.0);
    let t = extra(o)?;
    Ok((shape, Pose::new(Vec2::from(position), angle), t))
}

/// A BODY or a wall.
pub fn parse_object(v: &Value, path: &str) -> Result<Object, FieldError> {
    let mut o = Obj::new(v, path)?;
    if o.has("wall") {
        let (wall, ()) = o.req_with("wall", |v, p| parse_wall_or_segment_with(v, p, |_| Ok(())))?;
        o.finish()?;
        return Ok(match wall {
            WallGeometry::HalfPlane(w) => Object::Wall(w),
            WallGeometry::Segment(s) => Object::Segment(s),
            WallGeometry::Drum(d) => Object::Drum(d),
        });
    }
    let (shape, pose, ()) = parse_body_with(&mut o, |_| Ok(()))?;
    o.finish()?;
    Ok(Object::Body { shape, pose })
}

/// The `dem2d contact` input: an array of `{"i": BODY, "j": BODY}` (at most one of them a wall).
pub fn parse_pairs(v: &Value) -> Result<Vec<(Object, Object)>, FieldError> {
    let Some(items) = v.as_array() else {
        return Err(FieldError::new(
            "",
            format!("expected an array of pairs, got {}", type_of(v)),
        ));
    };
    let mut pairs = Vec::with_capacity(items.len());
    for (k, item) in items.iter().enumerate() {
        let path = index("pairs", k);
        let mut o = Obj::new(item, &path)?;
        let i = o.req_with("i", parse_object)?;
        let j = o.req_with("j", parse_object)?;
        o.finish()?;
        if matches!(
            (i, j),
            (
                Object::Wall(_) | Object::Segment(_) | Object::Drum(_),
                Object::Wall(_) | Object::Segment(_) | Object::Drum(_)
            )
        ) {
            return Err(FieldError::new(path, "a pair of two walls has no contact"));
        }
        let placed: Vec<Placed> = [(&i, "i"), (&j, "j")]
            .into_iter()
            .flat_map(|(o, side)| match o {
                Object::Body { shape, pose } => vec![Placed::Body {
                    path: format!("{path}.{side}"),
                    shape,
                    position: pose.position,
                }],
                Object::Wall(w) => vec![Placed::Wall {
                    path: format!("{path}.{side}.wall"),
                    point: w.point,
                }],
                Object::Segment(s) => [s.a, s.b]
                    .iter()
                    .enumerate()
                    .map(|(k, &point)| Placed::Wall {
                        path: format!("{path}.{side}.wall.segment[{k}]"),
                        point,
                    })
                    .collect(),
                Object::Drum(d) => drum_extent(d, &format!("{path}.{side}.wall.drum")),
            })
            .collect();
        check_extent(&placed)?;
        pairs.push((i, j));
    }
    Ok(pairs)
}

/// The points that bound a drum's extent (its centre and its box's corners), for
/// [`check_extent`].
pub fn drum_extent(d: &Drum, path: &str) -> Vec<Placed<'static>> {
    let r = d.radius;
    [[0.0, 0.0], [r, r], [-r, -r]]
        .iter()
        .map(|o| Placed::Wall {
            path: format!("{path}.center"),
            point: d.center + Vec2::new(o[0], o[1]),
        })
        .collect()
}
