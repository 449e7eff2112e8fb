//! The case file's `walls` section beyond each wall's geometry ([`super::body`]): the checks of
//! the walls against the bodies, a wall's motion, turning, servo and programmed stages.

use super::fields::{FieldError, Obj, index, number, positive, scale, type_of, vec2};
use crate::dynamics::boundary::{Program, Stage, StageMotion};
use crate::dynamics::{BodyInit, Boundary, Motion, Servo, Span};
use crate::geometry::Vec2;
use serde_json::Value;

/// Refuses walls that cannot be meant:
/// - **coincident walls**: two walls with the same free side (normals within 1e-6 rad) whose
///   lines are closer than the smallest body's inscribed radius. A body touching one touches
///   the other (or could reach it only through the first): a wall given twice doubles the
///   contact stiffness, and given 300 times it made the step unstable with its energy appearing
///   as negative dissipation (issue 29);
/// - **a flipped normal**: a wall with most bodies (more than half) starting on its solid side
///   (`n·(x − p) < 0` for the centroid x): its normal, which points into the free side, is
///   most likely reversed (`[0, -1]` for a floor: a run then "completes" with the bodies falling
///   forever).
pub(super) fn check_walls(walls: &[Boundary], bodies: &[BodyInit]) -> Result<(), FieldError> {
    let smallest = bodies
        .iter()
        .map(|b| b.shape.inscribed_radius())
        .fold(f64::INFINITY, f64::min);
    // (Segment walls: both sides solid, no free side to check; two may well share a line.)
    // A drum holds its bodies inside: one whose centroid lies on or beyond its circle starts
    // in its solid.
    for (w, d) in walls
        .iter()
        .enumerate()
        .filter_map(|(w, b)| b.drum().map(|d| (w, d)))
    {
        if let Some((k, b)) = bodies
            .iter()
            .enumerate()
            .find(|(_, b)| (b.position - d.center).norm() >= d.radius)
        {
            return Err(FieldError::new(
                format!("{}.position", index("bodies", k)),
                format!(
                    "[{}, {}] lies outside the drum walls[{w}] (centre [{}, {}], radius {}): a \
                     drum holds its bodies inside its circle",
                    b.position.x, b.position.y, d.center.x, d.center.y, d.radius
                ),
            ));
        }
    }
    let half_plane = |w: &Boundary| w.is_half_plane();
    for (j, b) in walls.iter().enumerate().filter(|(_, b)| half_plane(b)) {
        for (i, a) in walls[..j].iter().enumerate().filter(|(_, a)| half_plane(a)) {
            let (na, nb) = (a.line().normal, b.line().normal);
            let parallel = na.dot(&nb) > 0.0 && (na.x * nb.y - na.y * nb.x).abs() < 1e-6;
            let gap = na.dot(&(b.point() - a.point())).abs();
            if parallel && gap < smallest {
                return Err(FieldError::new(
                    index("walls", j),
                    format!(
                        "coincides with walls[{i}]: the same free side and lines {gap:.3e} cm \
                         apart, less than the smallest body's inscribed radius ({smallest:.3e} \
                         cm), so a body touching one touches both, with the stiffness doubled; \
                         give each wall once"
                    ),
                ));
            }
        }
    }
    for (k, w) in walls.iter().enumerate().filter(|(_, w)| half_plane(w)) {
        let solid = bodies
            .iter()
            .filter(|b| w.line().normal.dot(&(b.position - w.point())) < 0.0)
            .count();
        if 2 * solid > bodies.len() {
            let n = w.line().normal;
            return Err(FieldError::new(
                format!("{}.normal", index("walls", k)),
                format!(
                    "{solid} of the {} bodies start on the wall's solid side: the normal may be \
                     flipped (it points from the wall into the free side, where the bodies are: \
                     [{}, {}] rather than [{}, {}]?)",
                    bodies.len(),
                    // (+ 0.0: no `-0` in the message)
                    -n.x + 0.0,
                    -n.y + 0.0,
                    n.x,
                    n.y
                ),
            ));
        }
    }
    Ok(())
}

/// A wall's motion: `"velocity": [vx, vy]` (cm/s), or `"servo": {"stress": σ, "span": S or
/// [a, b], "max_speed": v, "gain": G}`, or `"motion": [stage, …]` (a program, each stage
/// `{"until": t, "velocity": [vx, vy]}` or `{"until": t, "servo": {…}}`, the last may omit
/// `until`; see `dynamics::boundary`); fixed without any. `dt` places the stages' ends on steps.
pub(super) fn wall_motion(w: &mut Obj, dt: f64) -> Result<Motion, FieldError> {
    let velocity = w.opt_with("velocity", vec2)?;
    let servo = w.get("servo");
    if let Some(p) = w.get("motion") {
        if let Some(key) = [("velocity", velocity.is_some()), ("servo", servo.is_some())]
            .into_iter()
            .find_map(|(k, given)| given.then_some(k))
        {
            return Err(FieldError::new(
                w.field_path(key),
                "give `motion` (a program of stages, each with its velocity or servo) or the \
                 wall's own `velocity` or `servo`, not both",
            ));
        }
        return program(p, &w.field_path("motion"), dt).map(Motion::Program);
    }
    let Some(v) = servo else {
        return Ok(velocity.map_or(Motion::Fixed, |v| Motion::Velocity(Vec2::from(v))));
    };
    if velocity.is_some() {
        return Err(FieldError::new(
            w.field_path("velocity"),
            "give `velocity` or `servo`, not both (a servo sets the wall's velocity)",
        ));
    }
    servo_of(v, &w.field_path("servo")).map(Motion::Servo)
}

/// A wall's turning keys: `"angular_velocity": ω` (rad/s, counter-clockwise) and
/// `"pivot": [x, y]` (a half-plane's or a segment's; a drum turns about its centre).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Turning {
    pub(super) rate: Option<f64>,
    pub(super) pivot: Option<[f64; 2]>,
}

/// Reads a wall's [`Turning`] keys.
pub(super) fn wall_turning(w: &mut Obj) -> Result<Turning, FieldError> {
    Ok(Turning {
        rate: w.opt_with("angular_velocity", number)?,
        pivot: w.opt_with("pivot", vec2)?,
    })
}

/// A servo object `{"stress": σ, "span": S or [a, b], "max_speed": v, "gain": G}` at `at`.
pub(super) fn servo_of(v: &Value, at: &str) -> Result<Servo, FieldError> {
    let mut o = Obj::new(v, at)?;
    let stress = o.req_with("stress", positive)?;
    let span = o.req_with("span", |v, p| match v {
        Value::Array(_) => {
            let err = || {
                FieldError::new(
                    p,
                    "must be a length or two wall indices [a, b] (the span between walls a and b)",
                )
            };
            let a = v.as_array().expect("array");
            if a.len() != 2 {
                return Err(err());
            }
            let idx = |x: &Value| x.as_u64().map(|k| k as usize).ok_or_else(err);
            Ok(Span::Between(idx(&a[0])?, idx(&a[1])?))
        }
        _ => Ok(Span::Length(scale(v, p)?)),
    })?;
    let max_speed = o.req_with("max_speed", positive)?;
    let gain = o.opt_with("gain", positive)?;
    o.finish()?;
    Ok(Servo {
        stress,
        span,
        gain,
        max_speed,
    })
}

/// A wall's program at `path`: its stages in time order, each ending at a later step than the
/// one before (the stage ends at the step nearest its `until`, so stages closer than a step
/// are refused), every one but the last with its `until`.
pub(super) fn program(v: &Value, path: &str, dt: f64) -> Result<Program, FieldError> {
    let items = match v.as_array() {
        Some(a) if !a.is_empty() => a,
        _ => {
            return Err(FieldError::new(
                path,
                format!(
                    "must be a non-empty array of stages ({{\"until\": t, \"velocity\": [vx, \
                     vy]}} or {{\"until\": t, \"servo\": {{…}}}}; the last may omit `until`), \
                     got {}",
                    if v.is_array() {
                        "an empty array"
                    } else {
                        type_of(v)
                    }
                ),
            ));
        }
    };
    let mut stages = Vec::with_capacity(items.len());
    let mut previous: Option<(f64, f64)> = None;
    for (i, item) in items.iter().enumerate() {
        let at = index(path, i);
        let mut o = Obj::new(item, &at)?;
        let until = o.opt_with("until", scale)?;
        let velocity = o.opt_with("velocity", vec2)?;
        let angular_velocity = o.opt_with("angular_velocity", number)?;
        let servo = match o.get("servo") {
            Some(s) => Some(servo_of(s, &o.field_path("servo"))?),
            None => None,
        };
        if servo.is_some() && angular_velocity.is_some() {
            return Err(FieldError::new(
                o.field_path("angular_velocity"),
                "a servo stage moves a half-plane along its normal: give it no \
                 `angular_velocity`",
            ));
        }
        let motion = match (velocity, servo) {
            (Some(v), None) => StageMotion::Velocity(Vec2::from(v)),
            (None, Some(s)) => StageMotion::Servo(s),
            (None, None) if angular_velocity.is_some() => StageMotion::Velocity(Vec2::zeros()),
            (Some(_), Some(_)) => {
                return Err(FieldError::new(
                    o.field_path("servo"),
                    "give the stage a `velocity` or a `servo`, not both",
                ));
            }
            (None, None) => {
                return Err(FieldError::new(
                    &at,
                    "a stage moves the wall at a `velocity` ([0, 0]: at rest), turns it at an \
                     `angular_velocity` or moves it by a `servo`: give one",
                ));
            }
        };
        let until_at = o.field_path("until");
        o.finish()?;
        match until {
            None if i + 1 < items.len() => {
                return Err(FieldError::new(
                    until_at,
                    "is missing: every stage but the last ends at a time (s)",
                ));
            }
            None => {}
            Some(t) => {
                let step = (t / dt).round();
                match previous {
                    Some((t0, _)) if t <= t0 => {
                        return Err(FieldError::new(
                            until_at,
                            format!(
                                "{t} is not after the previous stage's end ({t0}): the stages \
                                 are listed in time order"
                            ),
                        ));
                    }
                    Some((t0, s0)) if step <= s0 => {
                        return Err(FieldError::new(
                            until_at,
                            format!(
                                "{t} is within a step of the previous stage's end ({t0}; dt = \
                                 {dt}): a stage lasts at least one step"
                            ),
                        ));
                    }
                    None if step < 1.0 => {
                        return Err(FieldError::new(
                            until_at,
                            format!("{t} is before the first step ends (dt = {dt})"),
                        ));
                    }
                    _ => {}
                }
                previous = Some((t, step));
            }
        }
        stages.push(Stage {
            until,
            motion,
            angular_velocity: angular_velocity.unwrap_or(0.0),
        });
    }
    Ok(Program { stages })
}

/// A servo span between two walls must name two other walls that cross the servo wall's line
/// (`at` the span's path).
pub(super) fn check_span(
    walls: &[Boundary],
    k: usize,
    span: &Span,
    at: &str,
) -> Result<(), FieldError> {
    let Span::Between(a, b) = *span else {
        return Ok(());
    };
    let me = walls[k].line();
    let t = Vec2::new(-me.normal.y, me.normal.x);
    if a == b {
        return Err(FieldError::new(at, "must name two different walls"));
    }
    for w in [a, b] {
        if w >= walls.len() {
            return Err(FieldError::new(
                at,
                format!(
                    "wall {w} does not exist (the case has {} walls)",
                    walls.len()
                ),
            ));
        }
        if w == k {
            return Err(FieldError::new(
                at,
                "must name two other walls, not this one",
            ));
        }
        if !walls[w].is_half_plane() {
            return Err(FieldError::new(
                at,
                format!("wall {w} is not a half-plane (`point`, `normal`): it bounds no span"),
            ));
        }
        if walls[w].line().normal.dot(&t).abs() < 1e-6 {
            return Err(FieldError::new(
                at,
                format!("wall {w} is parallel to this wall: their lines do not cross"),
            ));
        }
    }
    Ok(())
}
