//! The case file's `cell` section: a periodic cell, its pressure or stress control, its strain
//! rates and Lees–Edwards shear.

use super::fields::{FieldError, Obj, index, join, number, object, positive, scale, string, vec2};
use crate::dynamics::cell::{Cell, PRESSURE_RELAXATION, Periodic, Pressure, SideControl};
use crate::dynamics::neighbour_list::pair_reach;
use crate::dynamics::{BodyInit, Boundary};
use crate::geometry::Vec2;
use serde_json::Value;

/// The most a strain rate may stretch a cell's side in one step.
const MAX_STRAIN_PER_STEP: f64 = 0.01;

/// The periodic cell (see [`super::Case::cell`]): its size against the bodies' reach, no wall
/// across a periodic direction, shear and pressure only in a cell periodic in x and y, no gravity
/// there.
pub(super) fn parse_cell(
    v: &Value,
    walls: &[Boundary],
    bodies: &[BodyInit],
    gravity: Vec2,
    dt: f64,
) -> Result<Cell, FieldError> {
    let mut c = Obj::new(v, "cell")?;
    let size = Vec2::from(c.req_with("size", |v, p| {
        let [x, y] = vec2(v, p)?;
        for (k, z) in [x, y].into_iter().enumerate() {
            scale(&Value::from(z), &format!("{p}[{k}]"))?;
        }
        Ok([x, y])
    })?);
    let periodic = c.req_with("periodic", |v, p| match string(v, p)?.as_str() {
        "x" => Ok(Periodic::X),
        "xy" => Ok(Periodic::XY),
        other => Err(FieldError::new(
            p,
            format!("unknown periodicity `{other}` (expected `x` or `xy`)"),
        )),
    })?;
    let shear_rate = c.opt_with("shear_rate", number)?;
    let pressure = c.opt_with("pressure", positive)?;
    let gain = c.opt_with("pressure_gain", positive)?;
    // Per side: `{"xx": …, "yy": …}`, each optional.
    let sides = |f: fn(&Value, &str) -> Result<f64, FieldError>| {
        move |v: &Value, p: &str| {
            let s = object(v, p, |o| Ok([o.opt_with("xx", f)?, o.opt_with("yy", f)?]))?;
            if s == [None, None] {
                return Err(FieldError::new(p, "needs `xx`, `yy` or both"));
            }
            Ok(s)
        }
    };
    let stress = c.opt_with("stress", sides(positive))?;
    let strain_rate = c.opt_with("strain_rate", sides(number))?;
    let at = |k: &str| join("cell", k);
    if periodic == Periodic::X {
        for (k, given) in [
            ("shear_rate", shear_rate.is_some()),
            ("pressure", pressure.is_some()),
            ("stress", stress.is_some()),
            ("strain_rate", strain_rate.is_some()),
        ] {
            if given {
                return Err(FieldError::new(
                    at(k),
                    "needs a cell periodic in x and y (`\"periodic\": \"xy\"`)",
                ));
            }
        }
    }
    let mut stress = stress.unwrap_or([None, None]);
    if let Some(p) = pressure {
        if stress[1].is_some() {
            return Err(FieldError::new(
                at("pressure"),
                "and `stress.yy` both given: `pressure` is `stress.yy` (give one)",
            ));
        }
        stress[1] = Some(p);
    }
    let strain_rate = strain_rate.unwrap_or([None, None]);
    // A side strained by more than 1 % in one step moves every body affinely by that much
    // between two force evaluations: no contact law follows that (the stress control's stretch
    // is capped at 1e-4 per step).
    for (side, rate) in strain_rate.iter().enumerate() {
        if let Some(rate) = rate
            && (rate * dt).abs() > MAX_STRAIN_PER_STEP
        {
            let k = ["xx", "yy"][side];
            return Err(FieldError::new(
                format!("{}.{k}", at("strain_rate")),
                format!(
                    "{rate} /s strains the cell by {:.3e} per step of {dt} s: at most \
                     {MAX_STRAIN_PER_STEP} per step (|rate| ≤ {:.6e} /s at this dt)",
                    (rate * dt).abs(),
                    MAX_STRAIN_PER_STEP / dt
                ),
            ));
        }
    }
    for side in 0..2 {
        if stress[side].is_some() && strain_rate[side].is_some() {
            let k = ["xx", "yy"][side];
            return Err(FieldError::new(
                format!("{}.{k}", at("strain_rate")),
                format!(
                    "and a stress on the same side ({}): a side follows its stress or is \
                     strained at a rate, not both",
                    if side == 1 && pressure.is_some() {
                        at("pressure")
                    } else {
                        format!("{}.{k}", at("stress"))
                    }
                ),
            ));
        }
    }
    if let Some(g) = gain {
        if stress == [None, None] {
            return Err(FieldError::new(
                at("pressure_gain"),
                "needs `pressure` or `stress`",
            ));
        }
        if g > 1.0 {
            return Err(FieldError::new(
                at("pressure_gain"),
                format!(
                    "must be in (0, 1] (the fraction of the stress error corrected per step), got {g}"
                ),
            ));
        }
    }
    c.finish()?;
    let mut cell = Cell::new(size, periodic, shear_rate.unwrap_or(0.0), None);
    for side in 0..2 {
        cell.control[side] = match (stress[side], strain_rate[side]) {
            (Some(target), _) => Some(SideControl::Stress(Pressure {
                target,
                gain: gain.unwrap_or(PRESSURE_RELAXATION),
            })),
            (None, Some(rate)) => Some(SideControl::StrainRate(rate)),
            (None, None) => None,
        };
    }
    // At most one image of a pair within reach: every periodic side above twice the reach.
    let max_bound = bodies
        .iter()
        .map(|b| b.shape.bounding_radius())
        .fold(0.0f64, f64::max);
    let reach = pair_reach(max_bound);
    if let Err((k, least)) = cell.check_size(reach) {
        return Err(FieldError::new(
            format!("{}[{k}]", at("size")),
            format!(
                "{} cm is too small: a periodic side must exceed twice the reach of a pair \
                 ({least:.6e} cm: two largest bounding diameters and the neighbour list's skin), \
                 so that a pair meets at most one image of the other",
                [size.x, size.y][k]
            ),
        ));
    }
    for (k, w) in walls.iter().enumerate() {
        if w.drum().is_some() {
            return Err(FieldError::new(
                join(&index("walls", k), "drum"),
                "a drum is not supported in a periodic cell (a drum is not repeated across its \
                 seams)",
            ));
        }
        if w.turn.is_some() {
            return Err(FieldError::new(
                join(&index("walls", k), "angular_velocity"),
                "turning walls are not supported in a periodic cell",
            ));
        }
        if w.segment().is_some() {
            return Err(FieldError::new(
                format!("{}.segment", index("walls", k)),
                "segment walls are not supported in a periodic cell (a segment is not repeated \
                 across its seams)",
            ));
        }
        let n = w.line().normal;
        if periodic == Periodic::XY || n.x.abs() > 1e-12 {
            return Err(FieldError::new(
                format!("{}.normal", index("walls", k)),
                match periodic {
                    Periodic::XY => "a cell periodic in x and y has no walls".to_string(),
                    Periodic::X => format!(
                        "[{}, {}] crosses the cell's periodic x direction: a wall in a cell \
                         periodic in x must be horizontal (normal [0, 1] or [0, -1])",
                        n.x, n.y
                    ),
                },
            ));
        }
    }
    if periodic == Periodic::XY && gravity != Vec2::zeros() {
        return Err(FieldError::new(
            "gravity",
            "must be [0, 0] in a cell periodic in x and y (it has no floor: the bodies would \
             fall forever)",
        ));
    }
    Ok(cell)
}
