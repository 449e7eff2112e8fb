//! The case's `insert` and `outflow` lists (see [`crate::dynamics::flow`]):
//!
//! ```json
//! "insert": [{"region": [x0, x1, y0, y1], "rate": 200, "count": 1000, "start": 0,
//!             "shape": "ellipse", "size": {"uniform": [0.4, 0.6]}, "aspect": 2,
//!             "angle": "random", "velocity": [0, -20], "seed": 7}],
//! "outflow": [{"region": [x0, x1, y0, y1]}]
//! ```
//!
//! A distribution (`size`, `aspect`) is a number, `{"uniform": [lo, hi]}` or
//! `{"choice": [v, …], "weights": [w, …]}` (weights optional: equal).

use super::fields::{FieldError, Obj, count, index, join, number, positive, scale, type_of, vec2};
use super::materials::{Named, body_density};
use crate::dynamics::BodyInit;
use crate::dynamics::flow::{Distribution, Flow, InsertShape, Inserter, Region, Target};
use crate::geometry::Vec2;
use serde_json::Value;

/// Positions tried per body unless `attempts` says otherwise.
pub const ATTEMPTS: u32 = 100;
/// The most positions a body may try (`attempts`): each try tests every body, so a body that
/// finds no place costs `attempts` × bodies tests at every retry; at 1e9 tries a full region
/// stalled the run for good (issue 41's fuzzing round).
pub const MAX_ATTEMPTS: u64 = 1_000_000;
/// Wait after a body found no place, unless `retry` says otherwise (s).
pub const RETRY: f64 = 0.01;
/// The densest packing of equal disks in a convex region covers at most π/√12 of it (Fejes
/// Tóth); random sequential placement stops near 0.547 (the jamming limit of random sequential
/// adsorption of disks, Hinrichsen, Feder and Jøssang 1986).
const DENSEST: f64 = 0.906_899_682_117_108_9;
const RANDOM: f64 = 0.547;

/// `[x0, x1, y0, y1]` with `x0 < x1`, `y0 < y1`.
fn region(v: &Value, path: &str) -> Result<Region, FieldError> {
    let items = v.as_array().filter(|a| a.len() == 4).ok_or_else(|| {
        FieldError::new(
            path,
            format!("must be [x0, x1, y0, y1], got {}", type_of(v)),
        )
    })?;
    let mut x = [0.0; 4];
    for (k, item) in items.iter().enumerate() {
        x[k] = number(item, &index(path, k))?;
    }
    if !(x[0] < x[1] && x[2] < x[3]) {
        return Err(FieldError::new(
            path,
            format!(
                "must be [x0, x1, y0, y1] with x0 < x1 and y0 < y1, got [{}, {}, {}, {}]",
                x[0], x[1], x[2], x[3]
            ),
        ));
    }
    Ok(Region {
        x0: x[0],
        x1: x[1],
        y0: x[2],
        y1: x[3],
    })
}

/// A distribution of positive values: a number, `{"uniform": [lo, hi]}` or
/// `{"choice": [...], "weights": [...]}`.
fn distribution(v: &Value, path: &str) -> Result<Distribution, FieldError> {
    if v.is_number() {
        return Ok(Distribution::Fixed(scale(v, path)?));
    }
    let expected = "expected a number, {\"uniform\": [lo, hi]} or {\"choice\": [v, …], \
                    \"weights\": [w, …]}";
    let Some(map) = v.as_object() else {
        return Err(FieldError::new(
            path,
            format!("must be a distribution ({expected}), got {}", type_of(v)),
        ));
    };
    let mut o = Obj::new(v, path)?;
    let d = if map.contains_key("uniform") {
        o.req_with("uniform", |v, p| {
            let [lo, hi] = vec2(v, p)?;
            for (k, x) in [lo, hi].into_iter().enumerate() {
                scale(&Value::from(x), &index(p, k))?;
            }
            if lo > hi {
                return Err(FieldError::new(
                    p,
                    format!("must be [lo, hi] with lo ≤ hi, got [{lo}, {hi}]"),
                ));
            }
            Ok(Distribution::Uniform(lo, hi))
        })?
    } else if map.contains_key("choice") {
        let values = o.req_with("choice", |v, p| list(v, p, scale))?;
        let weights = match o.opt_with("weights", |v, p| list(v, p, positive))? {
            Some(w) if w.len() != values.len() => {
                return Err(FieldError::new(
                    join(path, "weights"),
                    format!(
                        "has {} entries for {} values in `choice`",
                        w.len(),
                        values.len()
                    ),
                ));
            }
            Some(w) => w,
            None => vec![1.0; values.len()],
        };
        Distribution::Choice { values, weights }
    } else {
        let name = map.keys().next().map_or("", String::as_str);
        return Err(FieldError::new(
            path,
            format!("unknown distribution `{name}` ({expected})"),
        ));
    };
    o.finish()?;
    Ok(d)
}

/// A non-empty array of numbers read with `each`.
fn list(
    v: &Value,
    path: &str,
    each: fn(&Value, &str) -> Result<f64, FieldError>,
) -> Result<Vec<f64>, FieldError> {
    let items = v
        .as_array()
        .filter(|a| !a.is_empty())
        .ok_or_else(|| FieldError::new(path, "must be a non-empty array of numbers"))?;
    items
        .iter()
        .enumerate()
        .map(|(k, x)| each(x, &index(path, k)))
        .collect()
}

/// One inserter `insert[k]` (at `path`).
fn inserter(v: &Value, path: &str, named: &Named) -> Result<Inserter, FieldError> {
    let mut o = Obj::new(v, path)?;
    let region = o.req_with("region", region)?;
    let rate = o.opt_with("rate", positive)?;
    let given = o.opt_with("count", count)?;
    let keep = o.opt_with("keep", count)?;
    let target = match (rate, given, keep) {
        (Some(_), _, Some(_)) => {
            return Err(FieldError::new(
                join(path, "keep"),
                "give a `rate` or a number to `keep`, not both",
            ));
        }
        (Some(rate), count, None) => Target::Rate { rate, count },
        (None, count, Some(keep)) => Target::Keep { keep, count },
        (None, Some(c), None) => Target::Count(c),
        (None, None, None) => {
            return Err(FieldError::new(
                path,
                "must say how many bodies to insert: `rate` (bodies/s), `count` (all at once, \
                 or the total with a rate) or `keep` (the number of free bodies to hold)",
            ));
        }
    };
    let start = o
        .opt_with("start", super::fields::non_negative)?
        .unwrap_or(0.0);
    let shape = o
        .opt_with("shape", |v, p| match v.as_str() {
            Some("circle") => Ok(InsertShape::Circle),
            Some("ellipse") => Ok(InsertShape::Ellipse),
            Some("rectangle") => Ok(InsertShape::Rectangle),
            _ => Err(FieldError::new(
                p,
                format!("unknown shape {v} (an inserter makes `circle`, `ellipse` or `rectangle`)"),
            )),
        })?
        .unwrap_or(InsertShape::Circle);
    let size = o.req_with("size", distribution)?;
    let aspect = o
        .opt_with("aspect", distribution)?
        .unwrap_or(Distribution::Fixed(1.0));
    if aspect.range().0 < 1.0 {
        return Err(FieldError::new(
            join(path, "aspect"),
            format!(
                "the aspect ratio (long over short side) must be at least 1, got {}",
                aspect.range().0
            ),
        ));
    }
    if shape == InsertShape::Circle && aspect != Distribution::Fixed(1.0) {
        return Err(FieldError::new(
            join(path, "aspect"),
            "a circle has no aspect ratio (give `shape`: `ellipse` or `rectangle`)",
        ));
    }
    let angle = o.opt_with("angle", |v, p| match v.as_str() {
        Some("random") => Ok(None),
        _ => number(v, p).map(Some),
    })?;
    let velocity = Vec2::from(o.opt_with("velocity", vec2)?.unwrap_or([0.0, 0.0]));
    let omega = o.opt_with("omega", number)?.unwrap_or(0.0);
    let own_density = o.opt_with("density", scale)?;
    let material = o
        .opt_with("material", |v, p| named.index_of(v, p))?
        .unwrap_or(0);
    let density = body_density(named, material, own_density, path)?;
    let attempts = o
        .opt_with("attempts", |v, p| {
            let a = count(v, p)?;
            if a > MAX_ATTEMPTS {
                return Err(FieldError::new(
                    p,
                    format!(
                        "{a} tries per body is more than the {MAX_ATTEMPTS} accepted (each try \
                         tests every body: a region with no place left would stall the run; a \
                         body that finds none waits `retry` and tries again)"
                    ),
                ));
            }
            Ok(a as u32)
        })?
        .unwrap_or(ATTEMPTS);
    let retry = o.opt_with("retry", positive)?.unwrap_or(RETRY);
    let seed = o.opt_with("seed", |v, p| {
        v.as_u64()
            .ok_or_else(|| FieldError::new(p, format!("must be a whole number ≥ 0, got {v}")))
    })?;
    o.finish()?;
    let ins = Inserter {
        region,
        target,
        start,
        shape,
        size,
        aspect,
        angle: angle.flatten(),
        velocity,
        omega,
        density,
        material,
        attempts,
        retry,
        seed: seed.unwrap_or(0),
    };
    let big = ins.largest_bound();
    if 2.0 * big >= region.width().min(region.height()) {
        return Err(FieldError::new(
            join(path, "region"),
            format!(
                "is {} × {}: too small for its largest body (bounding diameter {})",
                region.width(),
                region.height(),
                2.0 * big
            ),
        ));
    }
    if let Target::Count(n) = ins.target {
        // All at once: the bodies must fit in the region together.
        let r = ins.smallest_bound();
        let disk = std::f64::consts::PI * r * r;
        let area = region.width() * region.height();
        let densest = (DENSEST * area / disk).floor() as u64;
        let random = (RANDOM * area / disk).floor() as u64;
        if n > random {
            return Err(FieldError::new(
                join(path, "count"),
                format!(
                    "{n} bodies cannot be placed at once in `{}` ({} × {} cm): it holds about \
                     {random} placed at random without overlap (and no packing holds more than \
                     {densest}) of bounding radius {r}; give a larger region, fewer bodies, or a \
                     `rate`",
                    join(path, "region"),
                    region.width(),
                    region.height()
                ),
            ));
        }
    }
    Ok(ins)
}

/// The case's `insert` and `outflow` lists (either may be absent); `bodies` the case's bodies
/// (an outflow region holding all of them is refused). `None` when neither is given.
/// The most bodies an inserter may place in one step, or at once: each body placed is tested
/// against every other, so a rate of 1e12 /s asked for 2e7 bodies per step and never finished
/// its first step (issue 41's fuzzing; a SIGTERM could not stop it between steps).
pub const MAX_INSERTED_PER_STEP: f64 = 1e5;

/// Refuses an inserter that asks for more than [`MAX_INSERTED_PER_STEP`] bodies in one step of
/// `dt`, naming its `rate` or `count`.
pub fn check_bodies_per_step(flow: &Flow, dt: f64) -> Result<(), FieldError> {
    for (k, ins) in flow.inserters.iter().enumerate() {
        let (key, per_step) = match ins.target {
            Target::Rate { rate, .. } => ("rate", rate * dt),
            Target::Count(n) => ("count", n as f64),
            Target::Keep { keep, .. } => ("keep", keep as f64),
        };
        if per_step > MAX_INSERTED_PER_STEP {
            return Err(FieldError::new(
                join(&index("insert", k), key),
                format!(
                    "asks for {per_step:.4e} bodies in one step (of {dt} s): at most \
                     {MAX_INSERTED_PER_STEP} per step (each is tested against every other)"
                ),
            ));
        }
    }
    Ok(())
}

pub fn parse_flow(
    insert: Option<&Value>,
    outflow: Option<&Value>,
    named: &Named,
    bodies: &[BodyInit],
) -> Result<Option<Flow>, FieldError> {
    if insert.is_none() && outflow.is_none() {
        return Ok(None);
    }
    let items = |v: Option<&Value>, name: &str| -> Result<Vec<Value>, FieldError> {
        match v {
            None => Ok(Vec::new()),
            Some(v) => v.as_array().cloned().ok_or_else(|| {
                FieldError::new(name, format!("must be an array, got {}", type_of(v)))
            }),
        }
    };
    let inserters = items(insert, "insert")?
        .iter()
        .enumerate()
        .map(|(k, v)| inserter(v, &index("insert", k), named))
        .collect::<Result<Vec<_>, _>>()?;
    let mut outflows = Vec::new();
    for (k, v) in items(outflow, "outflow")?.iter().enumerate() {
        let path = index("outflow", k);
        let mut o = Obj::new(v, &path)?;
        let r = o.req_with("region", region)?;
        o.finish()?;
        let at = join(&path, "region");
        let free: Vec<&BodyInit> = bodies.iter().filter(|b| !b.prescribed).collect();
        if !free.is_empty() && free.iter().all(|b| r.contains(b.position)) {
            return Err(FieldError::new(
                at,
                format!(
                    "contains the whole scene (all {} free bodies): every body would be removed \
                     at the first step",
                    free.len()
                ),
            ));
        }
        if let Some(i) = inserters.iter().position(|i| r.covers(&i.region)) {
            return Err(FieldError::new(
                at,
                format!(
                    "contains the whole of insert[{i}].region: every body inserted there would \
                     be removed at once"
                ),
            ));
        }
        outflows.push(r);
    }
    Ok(Some(Flow::new(inserters, outflows)))
}

/// A body of each inserter's largest size (for the checks a case's bodies get: the materials
/// that meet, the ranges of sizes, the critical time step).
pub fn templates(flow: &Flow) -> Vec<BodyInit> {
    flow.inserters
        .iter()
        .map(|i| {
            let (_, r) = i.size.range();
            let (_, a) = i.aspect.range();
            BodyInit {
                shape: i.shape.make(r, a),
                position: Vec2::new(
                    0.5 * (i.region.x0 + i.region.x1),
                    0.5 * (i.region.y0 + i.region.y1),
                ),
                angle: 0.0,
                velocity: i.velocity,
                omega: i.omega,
                density: i.density,
                material: i.material,
                prescribed: false,
            }
        })
        .collect()
}

/// Bodies of each inserter's extreme sizes and shapes: the smallest and the largest size, each
/// at the smallest and the largest aspect ratio (the lightest body and the longest lever
/// bound the critical time step; see [`super::Case::critical_dt`]). Their positions are the
/// region's centre (only their shapes and masses are read).
pub fn extremes(flow: &Flow) -> Vec<BodyInit> {
    flow.inserters
        .iter()
        .flat_map(|i| {
            let (r0, r1) = i.size.range();
            let (a0, a1) = i.aspect.range();
            [(r0, a0), (r0, a1), (r1, a0), (r1, a1)].map(|(r, a)| BodyInit {
                shape: i.shape.make(r, a),
                position: Vec2::new(
                    0.5 * (i.region.x0 + i.region.x1),
                    0.5 * (i.region.y0 + i.region.y1),
                ),
                angle: 0.0,
                velocity: i.velocity,
                omega: i.omega,
                density: i.density,
                material: i.material,
                prescribed: false,
            })
        })
        .collect()
}

/// Refuses an insertion region in which no body can be placed because a fixed half-plane wall
/// covers it: every position an inserter may draw (the region less its smallest body's
/// bounding radius on each side) is on the wall's solid side or within that radius of it, so
/// the inserter (which places a body only clear of every wall) would place none, and the run
/// end with exit 0 and an empty scene (issue 41). The signed distance is linear, so its
/// largest value over the rectangle of positions is at a corner.
pub fn check_regions_clear_of_walls(
    flow: &Flow,
    walls: &[crate::dynamics::Boundary],
) -> Result<(), FieldError> {
    use crate::dynamics::Motion;
    for (k, ins) in flow.inserters.iter().enumerate() {
        let b = ins.smallest_bound();
        let r = &ins.region;
        let corners = [
            Vec2::new(r.x0 + b, r.y0 + b),
            Vec2::new(r.x1 - b, r.y0 + b),
            Vec2::new(r.x0 + b, r.y1 - b),
            Vec2::new(r.x1 - b, r.y1 - b),
        ];
        for (w, wall) in walls.iter().enumerate() {
            if let Some(d) = wall.drum() {
                // A drum that does not translate: the region's point nearest its centre must
                // lie farther than b inside its circle.
                let still = match &wall.motion {
                    Motion::Fixed => true,
                    Motion::Velocity(v) => *v == Vec2::zeros(),
                    Motion::Servo(_) | Motion::Program(_) => false,
                };
                let (lo, hi) = (corners[0], corners[3]);
                let nearest = Vec2::new(
                    d.center.x.clamp(lo.x.min(hi.x), lo.x.max(hi.x)),
                    d.center.y.clamp(lo.y.min(hi.y), lo.y.max(hi.y)),
                );
                if still && d.signed_distance(nearest) <= b {
                    return Err(FieldError::new(
                        join(&index("insert", k), "region"),
                        format!(
                            "[{}, {}, {}, {}] lies outside the drum walls[{w}] (centre [{}, {}], \
                             radius {}; or closer to its circle than its smallest body's \
                             bounding radius, {b}): no body can be placed there; move the \
                             region inside the drum",
                            r.x0, r.x1, r.y0, r.y1, d.center.x, d.center.y, d.radius
                        ),
                    ));
                }
                continue;
            }
            if !wall.is_half_plane() || !matches!(wall.motion, Motion::Fixed) {
                continue;
            }
            let clearest = corners
                .iter()
                .map(|&c| wall.signed_distance(c))
                .fold(f64::NEG_INFINITY, f64::max);
            if clearest <= b {
                return Err(FieldError::new(
                    join(&index("insert", k), "region"),
                    format!(
                        "[{}, {}, {}, {}] lies behind walls[{w}] (on its solid side, or closer \
                         to it than its smallest body's bounding radius, {b}): no body can be \
                         placed there; move the region to the wall's free side (the side its \
                         normal points to)",
                        r.x0, r.x1, r.y0, r.y1
                    ),
                ));
            }
        }
    }
    Ok(())
}
