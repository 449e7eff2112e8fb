//! Reading a state file (`state.json`, written by `output::state` at the end of a run): a case
//! file with a `"state"` block, from which `dem2d run` continues the run exactly. A case file
//! without the block reads as a case.
//!
//! The case part is read as any case (every check applies; the bodies' positions, angles and
//! velocities are the state's). The block's numbers are read as written — finite, of any
//! magnitude — and every error names the field (`state.contacts[3].shear`). The block must fit
//! the case: one entry per body and per wall, contacts between the case's bodies and walls,
//! listed once each in key order, and the time `step × dt` (a continued run keeps the time step).

use super::case::Case;
use super::fields::{FieldError, Obj, index, join, object, parse_json, type_of};
use crate::contact_law::{HISTORY_LEN, History};
use crate::dynamics::Motion;
use crate::dynamics::World;
use crate::dynamics::account::{Diagnostics, Energies};
use crate::dynamics::boundary::WallLoad;
use crate::dynamics::cell::LatticeMark;
use crate::dynamics::contacts::{ContactData, Slot};
use crate::dynamics::flow::{FlowRestart, InserterState};
use crate::dynamics::partner::{MAX_INDEX, Partner};
use crate::dynamics::restart::{
    BodyRestart, ProgramRestart, RestartState, SlotRestart, TurnRestart, WallRestart,
    state_from_name,
};
use crate::geometry::Vec2;
use crate::narrow_phase::PairCache;
use crate::run::{BlowupWatch, RunProgress};
use serde_json::Value;

/// A case file, and the state it continues from when it is a state file.
#[derive(Clone, Debug)]
pub struct CaseFile {
    pub case: Case,
    /// The state block's world state (`None` for a case that starts at t = 0).
    pub restart: Option<RestartState>,
    /// The state block's run progress (`"run"`: the run that wrote the state), saved beside
    /// the world's state.
    pub run: Option<RunProgress>,
    /// The file as parsed (a state file written at the end of the run repeats its fields).
    pub value: Value,
    /// What the state's reader found worth telling (an edited state's new overlaps).
    pub warnings: Vec<String>,
}

impl CaseFile {
    /// Reads a case or state file from its text.
    pub fn from_json(text: &str) -> Result<CaseFile, FieldError> {
        let value = parse_json(text, "")?;
        let mut case = Case::from_value(&value)?;
        let mut warnings = case.warnings();
        let (restart, run) = match value.get("state") {
            None => (None, None),
            Some(s) => {
                let (mut state, mut run) = parse_state(s, &case)?;
                continue_walls(&mut case, &mut state);
                if let Some(w) = wrap_into_cell(&case, &mut state) {
                    warnings.push(w);
                }
                // The same check as the world's when it resumes, named in the file's terms.
                let world = case
                    .resume_world(&state)
                    .map_err(|e| FieldError::new(join("state", &e.path), e.message))?;
                check_account(&world, &state, run.as_ref())?;
                if let Some((warning, fresh)) = check_contact_list(&case, &state)? {
                    warnings.push(warning);
                    if let Some(run) = &mut run {
                        watch_from_here(run, &state.energies, &fresh);
                    }
                }
                (Some(state), run)
            }
        };
        Ok(CaseFile {
            case,
            restart,
            run,
            value,
            warnings,
        })
    }

    /// The world at the start of the run: the case's at t = 0, or the state's.
    pub fn build_world(&self) -> World {
        match &self.restart {
            None => self.case.build_world(),
            Some(state) => self.case.resume_world(state).expect("checked when read"),
        }
    }
}

/// A wall given a constant velocity continues from where the state has it: its motion
/// `p = p₀ + v (t − t₀)` is anchored at the state's point and time unless the state's point is
/// where the case's motion puts it (`p₀ + v t` from the case's point, to the bit: an unchanged
/// continuation, which then steps exactly as the uninterrupted run); its velocity is the case's
/// (a wall given a velocity in an edited state had 0). Without this, a wall given a velocity in
/// a state file jumped to `p₀ + v t` at its first step (issue 29).
fn continue_walls(case: &mut Case, state: &mut RestartState) {
    for (w, r) in case.walls.iter_mut().zip(&mut state.walls) {
        if let Motion::Velocity(v) = w.motion {
            // A turning one's angle too: θ = ω t from the case's, unless the state's differs;
            // its angular velocity is the case's.
            let turned = match (&w.turn, &mut r.turn) {
                (Some(t), Some(rt)) => {
                    rt.omega = t.rate;
                    rt.angle != t.rate * state.time
                }
                _ => false,
            };
            if r.point != w.start + v * state.time || turned {
                w.start = r.point;
                w.start_time = state.time;
                if let (Some(t), Some(rt)) = (&mut w.turn, &mut r.turn) {
                    t.start_angle = rt.angle;
                    rt.start_angle = rt.angle;
                }
            }
            r.velocity = v;
        }
    }
}

/// Brings the state's bodies that lie outside its periodic cell into it, as a crossing would
/// (their image counts, and across a sheared seam their velocities, changed; the kinetic energy
/// a velocity change gives booked as the seam's work, as the step books it), and says how many.
/// A run never writes such a state: it was edited (a body moved by whole periods). Without this,
/// the first frame had y outside [0, L) and the run created 15× its initial energy without a
/// word (issue 41); a case file's bodies are wrapped the same way.
fn wrap_into_cell(case: &Case, state: &mut RestartState) -> Option<String> {
    let cell = state.cell?;
    let mut moved = Vec::new();
    for (k, (r, b)) in state.bodies.iter_mut().zip(&case.bodies).enumerate() {
        if let Some(w) = cell.wrap(r.position, r.velocity) {
            let m = b.density * b.shape.area();
            state.energies.boundary_work +=
                0.5 * m * (w.velocity.norm_squared() - r.velocity.norm_squared());
            r.position = w.position;
            r.velocity = w.velocity;
            r.image[0] += w.images[0];
            r.image[1] += w.images[1];
            moved.push(k.to_string());
        }
    }
    if moved.is_empty() {
        return None;
    }
    let n = moved.len();
    moved.truncate(10);
    Some(format!(
        "{n} bod{} of the state lie{} outside the periodic cell (an edited state?): brought into \
         it through the seams as crossings, image counts{} changed (bodies {}{})",
        if n == 1 { "y" } else { "ies" },
        if n == 1 { "s" } else { "" },
        if cell.shear_rate != 0.0 {
            " and velocities across the sheared seam"
        } else {
            ""
        },
        moved.join(", "),
        if n > 10 { ", …" } else { "" }
    ))
}

/// Refuses a state whose energy account no run can have reached: an energy of motion or of the
/// springs below zero, dissipation below zero (it only grows from 0), or an account the blow-up
/// watch would stop at once (energy created far beyond what the start, gravity and the walls
/// supply — `dissipated: 1e300`). Named at `state.energies`.
fn check_account(
    world: &World,
    state: &RestartState,
    run: Option<&RunProgress>,
) -> Result<(), FieldError> {
    let e = &state.energies;
    let at = |k: &str| join("state.energies", k);
    for (k, v) in [("kinetic", e.kinetic), ("elastic", e.elastic)] {
        if v < 0.0 {
            return Err(FieldError::new(
                at(k),
                format!("must be zero or positive, got {v} (an energy of motion or of springs)"),
            ));
        }
    }
    // Dissipation only grows from 0; a run's rounding leaves it at most this far below.
    let scale = e.kinetic + e.potential.abs() + e.elastic + e.boundary_work.abs();
    if e.dissipated < -1e-6 * scale {
        return Err(FieldError::new(
            at("dissipated"),
            format!(
                "{:e} is below zero: the energy the contacts took out only ever grows from 0",
                e.dissipated
            ),
        ));
    }
    if let Some(run) = run {
        let mut watch = run.watch;
        use crate::run::watch::{ENERGY_GROWTH, Trigger};
        let why = match watch.check(world) {
            None => return check_closure(e, run),
            Some(Trigger::Energy { created, available }) => format!(
                "{created:.3e} erg created since the start, more than {ENERGY_GROWTH} × the \
                 {available:.3e} erg that the start, gravity and the walls supply"
            ),
            Some(Trigger::Depth { ratio }) => {
                format!("an overlap of {ratio:.3} × the smaller inscribed radius")
            }
            Some(Trigger::NonFinite(what)) => format!("a non-finite {what}"),
            Some(Trigger::CellLimit { side, size, least }) => {
                format!("a cell side ({side}) of {size:e} cm, below its least {least:e} cm")
            }
            // The positions are the reader's own range check.
            Some(Trigger::Escaped { .. }) => return check_closure(e, run),
        };
        return Err(FieldError::new(
            "state.energies",
            format!(
                "the account is that of a blow-up ({why}): no run writes such a state (was it \
                 edited?)"
            ),
        ));
    }
    Ok(())
}

/// Refuses a state whose account does not close, either way, by more than the blow-up watch
/// allows a run (energy created or lost beyond [`ENERGY_GROWTH`] × the energy the run has had in
/// motion: the start's, gravity's, what the bodies and springs hold and what the contacts took
/// out), or whose watch could no longer see a blow-up: one number edited alone —
/// `boundary_work: 1e300`, `initial_total_energy: -1e300`, the watch's `total0` — leaves the
/// others to disagree with it by its whole size (issue 41: such states were accepted, the
/// first two silently, the last switching the watch off).
/// The scale leaves out the numbers checked, so that none can widen its own tolerance; a run's
/// rounding is allowed for.
///
/// [`ENERGY_GROWTH`]: crate::run::watch::ENERGY_GROWTH
fn check_closure(e: &Energies, run: &RunProgress) -> Result<(), FieldError> {
    use crate::run::watch::ENERGY_GROWTH;
    let w = &run.watch;
    // (Sizes: a cohesive contact stores a negative energy, −c A.)
    let moved = w.kinetic0
        + w.elastic0.abs()
        + (w.potential0 - e.potential).abs()
        + e.kinetic
        + e.elastic.abs()
        + e.dissipated.abs();
    let rounding = 1e-9
        * (moved
            + e.potential.abs()
            + w.potential0.abs()
            + e.boundary_work.abs()
            + run.initial_total.abs()
            + w.total0.abs()
            + w.boundary_supplied.abs()
            + w.dissipated_max.abs());
    let limit = ENERGY_GROWTH * moved + rounding;
    let unaccounted = e.total() - run.initial_total - e.boundary_work;
    let created = e.total() - w.total0 - e.boundary_work + (w.dissipated_max - e.dissipated);
    let (field, value, what) = if unaccounted.abs() > limit {
        (
            "state.run.initial_total_energy",
            unaccounted,
            "the account K + P + E_el + D − E₀ − W (energies, walls' work and the run's initial \
             total) is off by",
        )
    } else if created.abs() > limit {
        (
            "state.run.watch.total0",
            created,
            "the blow-up watch's account (its total0 and dissipated_max against the energies) \
             is off by",
        )
    } else {
        return Ok(());
    };
    Err(FieldError::new(
        field,
        format!(
            "{what} {value:.3e} erg, beyond {ENERGY_GROWTH} × the {moved:.3e} erg the run has had \
             in motion: no run writes such a state (was it edited? `energies.boundary_work` and \
             the `run` block's figures must agree with the energies)"
        ),
    ))
}

/// Refuses a state whose contact list lacks a pair that overlaps (the list was emptied, or a
/// body was moved by an edit out of its neighbours' reach): the continued run would not see that
/// contact until its list is next rebuilt, by which time the bodies have passed into each other
/// (an emptied list blew up 1019 steps later). Warns of pairs the list holds that overlap where
/// the state's contacts did not (an edit that created an overlap: its spring acts from the first
/// step). Returns that warning and the energies of the state's configuration evaluated afresh.
fn check_contact_list(
    case: &Case,
    state: &RestartState,
) -> Result<Option<(String, crate::dynamics::account::Energies)>, FieldError> {
    use crate::dynamics::BodyInit;
    let bodies: Vec<BodyInit> = case
        .bodies
        .iter()
        .zip(&state.bodies)
        .map(|(b, r)| BodyInit {
            position: r.position,
            angle: r.angle,
            velocity: r.velocity,
            omega: r.omega,
            ..*b
        })
        .collect();
    let mut walls = case.walls.clone();
    for (w, r) in walls.iter_mut().zip(&state.walls) {
        w.place(r.point, r.turn.map_or(0.0, |t| t.angle));
    }
    let mut fresh = Case {
        bodies,
        walls,
        ..case.clone()
    }
    .build_world();
    fresh.refresh_contact_extras();
    let listed = |i: u32, j: u32| {
        state
            .slots
            .iter()
            .filter(move |s| (s.slot.i, s.slot.j) == (i, j))
    };
    let name = |i: u32, j: u32| match Partner::from_key(j) {
        Partner::Wall(w) => format!("body {i} and wall {w}"),
        Partner::Body(j) => format!("bodies {i} and {j}"),
    };
    let mut new_overlaps = Vec::new();
    for c in fresh.contacts.active().filter(|c| c.extra.depth > 0.0) {
        let (i, j) = (c.slot.i, c.slot.j);
        if listed(i, j).next().is_none() {
            return Err(FieldError::new(
                "state.contacts",
                format!(
                    "{} overlap (by δ = {:.3e}) but the contact list does not hold their pair \
                     (emptied, or a body moved by an edit): the continued run would miss their \
                     contact; remove the `state` block to run these positions as a case from \
                     t = 0",
                    name(i, j),
                    c.extra.depth
                ),
            ));
        }
        if !listed(i, j).any(|s| s.slot.active) {
            new_overlaps.push((name(i, j), c.extra.depth));
        }
    }
    if new_overlaps.is_empty() {
        return Ok(None);
    }
    new_overlaps.sort_by(|a, b| b.1.total_cmp(&a.1));
    let named: Vec<String> = new_overlaps
        .iter()
        .take(5)
        .map(|(n, d)| format!("{n} by δ = {d:.3e}"))
        .collect();
    Ok(Some((
        format!(
            "{} pair{} overlap where the state's contacts did not (an edited state?): {}{}; their \
         springs act from the first step, and the blow-up watch starts from this state",
            new_overlaps.len(),
            if new_overlaps.len() == 1 { "" } else { "s" },
            named.join("; "),
            match new_overlaps.len().saturating_sub(5) {
                0 => String::new(),
                more => format!("; and {more} more"),
            }
        ),
        fresh.energies,
    )))
}

/// The blow-up watch of an edited state starts from it: the energy its edit put into springs
/// (or motion) is the state's own, not energy created by the step. `fresh` are the energies of
/// the state's configuration evaluated afresh (no history springs); the dissipation and the
/// walls' work so far are the state's.
fn watch_from_here(run: &mut RunProgress, e: &Energies, fresh: &Energies) {
    let w = &mut run.watch;
    w.kinetic0 = fresh.kinetic;
    w.elastic0 = fresh.elastic.max(e.elastic);
    w.potential0 = fresh.potential;
    // (The account `E − E₀ − W` starts at zero: the work so far is the state's.)
    w.total0 = fresh.kinetic + fresh.potential + w.elastic0 + e.dissipated - e.boundary_work;
    w.gravity_supplied = 0.0;
    w.boundary_supplied = 0.0;
    w.dissipated_max = e.dissipated;
}

/// Any finite number (the state's numbers are what a run computed: no range applies).
fn float(v: &Value, path: &str) -> Result<f64, FieldError> {
    match v.as_f64() {
        Some(x) if x.is_finite() => Ok(x),
        _ => Err(FieldError::new(
            path,
            format!("must be a finite number, got {}", shown(v)),
        )),
    }
}

/// A number, or `null` for ∞ (a critical time step never sampled).
fn float_or_infinity(v: &Value, path: &str) -> Result<f64, FieldError> {
    match v {
        Value::Null => Ok(f64::INFINITY),
        _ => float(v, path),
    }
}

fn whole(v: &Value, path: &str) -> Result<u64, FieldError> {
    v.as_u64().ok_or_else(|| {
        FieldError::new(
            path,
            format!("must be a whole number ≥ 0, got {}", shown(v)),
        )
    })
}

fn shown(v: &Value) -> String {
    match v {
        Value::Number(n) => n.to_string(),
        Value::String(s) if s.starts_with('\u{1}') => s.rsplit(':').next().unwrap_or("").into(),
        other => type_of(other).to_string(),
    }
}

fn pair(v: &Value, path: &str) -> Result<Vec2, FieldError> {
    let [x, y] = floats::<2>(v, path)?;
    Ok(Vec2::new(x, y))
}

fn floats<const N: usize>(v: &Value, path: &str) -> Result<[f64; N], FieldError> {
    match v.as_array() {
        Some(a) if a.len() == N => {
            let mut out = [0.0; N];
            for (k, x) in a.iter().enumerate() {
                out[k] = float(x, &index(path, k))?;
            }
            Ok(out)
        }
        _ => Err(FieldError::new(
            path,
            format!("must be an array of {N} numbers, got {}", shown_array(v)),
        )),
    }
}

fn shown_array(v: &Value) -> String {
    match v {
        Value::Array(a) => format!("an array of {} elements", a.len()),
        other => type_of(other).to_string(),
    }
}

fn array<'a>(v: &'a Value, path: &str) -> Result<&'a Vec<Value>, FieldError> {
    v.as_array()
        .ok_or_else(|| FieldError::new(path, format!("must be an array, got {}", type_of(v))))
}

/// A warm start: four single-precision numbers, `null` for NaN.
fn warm(v: &Value, path: &str) -> Result<PairCache, FieldError> {
    let items = match v.as_array() {
        Some(a) if a.len() == 4 => a,
        _ => {
            return Err(FieldError::new(
                path,
                format!(
                    "must be an array of 4 single-precision numbers or null, got {}",
                    shown_array(v)
                ),
            ));
        }
    };
    let mut w = [f32::NAN; 4];
    for (k, x) in items.iter().enumerate() {
        if x.is_null() {
            continue;
        }
        let p = index(path, k);
        let d = float(x, &p)?;
        let f = d as f32;
        if f64::from(f) != d {
            return Err(FieldError::new(
                p,
                format!("{d} is not a single-precision number (a warm start is kept in f32)"),
            ));
        }
        w[k] = f;
    }
    Ok(PairCache::from_saved(w))
}

/// Reads the state block of a state file whose case part is `case`: the world's state, and the
/// run's progress when the block has it.
pub fn parse_state(
    v: &Value,
    case: &Case,
) -> Result<(RestartState, Option<RunProgress>), FieldError> {
    let mut o = Obj::new(v, "state")?;
    o.opt_with("status", |v, p| {
        v.as_str()
            .map(|_| ())
            .ok_or_else(|| FieldError::new(p, format!("must be a string, got {}", type_of(v))))
    })?;
    let step = o.req_with("step", whole)?;
    let time = o.req_with("time", float)?;
    let energies = o.req_with("energies", |v, p| {
        object(v, p, |e| {
            Ok(Energies {
                kinetic: e.req_with("kinetic", float)?,
                potential: e.req_with("potential", float)?,
                elastic: e.req_with("elastic", float)?,
                dissipated: e.req_with("dissipated", float)?,
                boundary_work: e.req_with("boundary_work", float)?,
            })
        })
    })?;
    let diagnostics = o.req_with("diagnostics", |v, p| {
        object(v, p, |d| {
            Ok(Diagnostics {
                max_depth_ratio: d.req_with("max_depth_ratio", float)?,
                deep_contacts: d.req_with("deep_contacts", whole)?,
                contained_contacts: d.req_with("contained_contacts", whole)?,
                dt_critical_observed: d.req_with("dt_critical_observed", float_or_infinity)?,
            })
        })
    })?;
    let last_increments = o.req_with("last_increments", floats::<3>)?;
    let mut run = o.opt_with("run", parse_run)?;
    if let Some(r) = &mut run
        && r.watch.dissipated_max.is_nan()
    {
        r.watch.dissipated_max = energies.dissipated;
    }
    let walls = o.req_with("walls", |v, p| {
        array(v, p)?
            .iter()
            .enumerate()
            .map(|(k, w)| {
                let mut w = Obj::new(w, &index(p, k))?;
                let point = w.req_with("point", pair)?;
                let velocity = w.req_with("velocity", pair)?;
                let mut load = w.req_with("load", |v, p| {
                    object(v, p, |l| {
                        Ok(WallLoad {
                            force: l.req_with("force", pair)?,
                            force_non_elastic: l.req_with("force_non_elastic", pair)?,
                            torque: 0.0,
                            torque_non_elastic: 0.0,
                            stiffness: l.req_with("stiffness", float)?,
                            contacts: l.req_with("contacts", |v, p| {
                                u32::try_from(whole(v, p)?).map_err(|_| {
                                    FieldError::new(p, "must be a whole number below 2³²")
                                })
                            })?,
                        })
                    })
                })?;
                let program = w.opt_with("program", |v, p| {
                    object(v, p, |o| {
                        Ok(ProgramRestart {
                            stage: o.req_with("stage", |v, p| {
                                usize::try_from(whole(v, p)?)
                                    .map_err(|_| FieldError::new(p, "is beyond the largest stage"))
                            })?,
                            start: o.req_with("start", pair)?,
                            start_time: o.req_with("start_time", float)?,
                        })
                    })
                })?;
                let turn = w.opt_with("turn", |v, p| {
                    object(v, p, |o| {
                        load.torque = o.req_with("torque", float)?;
                        load.torque_non_elastic = o.req_with("torque_non_elastic", float)?;
                        Ok(TurnRestart {
                            angle: o.req_with("angle", float)?,
                            start_angle: o.req_with("start_angle", float)?,
                            omega: o.req_with("omega", float)?,
                        })
                    })
                })?;
                let at = index(p, k);
                match (case.walls.get(k).map(|w| w.turn.is_some()), &turn) {
                    (Some(true), None) => {
                        return Err(FieldError::new(
                            at,
                            "`turn` is missing: a drum or a turning wall keeps its angle",
                        ));
                    }
                    (Some(false), Some(_)) => {
                        return Err(FieldError::new(
                            format!("{at}.turn"),
                            "only a drum or a turning wall (`angular_velocity`) has one",
                        ));
                    }
                    _ => {}
                }
                match (case.walls.get(k).map(|w| &w.motion), &program) {
                    (Some(Motion::Program(prog)), Some(r)) if r.stage > prog.stages.len() => {
                        return Err(FieldError::new(
                            format!("{at}.program.stage"),
                            format!(
                                "stage {} does not exist (the wall's program has {} stages)",
                                r.stage,
                                prog.stages.len()
                            ),
                        ));
                    }
                    (Some(Motion::Program(_)), None) => {
                        return Err(FieldError::new(
                            at,
                            "`program` is missing: a wall with a motion program keeps its stage",
                        ));
                    }
                    (Some(m), Some(_)) if !matches!(m, Motion::Program(_)) => {
                        return Err(FieldError::new(
                            format!("{at}.program"),
                            "only a wall with a motion program (`motion` in the case) has one",
                        ));
                    }
                    _ => {}
                }
                w.finish()?;
                Ok(WallRestart {
                    point,
                    velocity,
                    load,
                    program,
                    turn,
                })
            })
            .collect::<Result<Vec<_>, _>>()
    })?;
    let cell = match (case.cell, o.get("cell")) {
        (None, None) => None,
        (None, Some(_)) => {
            return Err(FieldError::new(
                "state.cell",
                "the case has no periodic cell (`cell`) for this state's",
            ));
        }
        (Some(_), None) => {
            return Err(FieldError::new(
                "state.cell",
                "is missing: the case's periodic cell needs the state's (its height, shift and \
                 stress)",
            ));
        }
        (Some(mut c), Some(v)) => {
            let mut k = Obj::new(v, "state.cell")?;
            let size = k.req_with("size", pair)?;
            // The sides are where the run left them (a side that followed a stress or a strain
            // rate moved; the case's may since have fixed it, to shear at constant volume), and
            // must leave a pair one image within reach, as a case's must.
            for (side, got) in [size.x, size.y].into_iter().enumerate() {
                if got.is_nan() || got <= 0.0 {
                    return Err(FieldError::new(
                        format!("state.cell.size[{side}]"),
                        "must be positive",
                    ));
                }
            }
            c.size = size;
            let max_bound = case
                .bodies
                .iter()
                .map(|b| b.shape.bounding_radius())
                .fold(0.0f64, f64::max);
            if let Err((side, least)) =
                c.check_size(crate::dynamics::neighbour_list::pair_reach(max_bound))
            {
                return Err(FieldError::new(
                    format!("state.cell.size[{side}]"),
                    format!(
                        "{} cm is too small: a periodic side must exceed twice the reach of a \
                         pair ({least:.6e} cm)",
                        [size.x, size.y][side]
                    ),
                ));
            }
            c.offset = k.req_with("offset", float)?;
            c.shift = k.req_with("shift", float)?;
            c.stress = k.req_with("stress", floats::<4>)?;
            c.stiffness[1] = k.req_with("stiffness_yy", float)?;
            // (Absent from state files written before it was kept: the first step's stretch
            // then books half its work from zero, as those runs did.)
            c.elastic[1] = k.opt_with("elastic_yy", float)?.unwrap_or(0.0);
            c.stiffness[0] = k.opt_with("stiffness_xx", float)?.unwrap_or(0.0);
            c.elastic[0] = k.opt_with("elastic_xx", float)?.unwrap_or(0.0);
            k.finish()?;
            if !(0.0..c.size.x).contains(&c.offset) {
                return Err(FieldError::new(
                    "state.cell.offset",
                    format!(
                        "must be in [0, {}) (the shift modulo the cell's width)",
                        c.size.x
                    ),
                ));
            }
            Some(c)
        }
    };
    let bodies_value = o.req("bodies")?;
    let listed = array(bodies_value, "state.bodies")?;
    if listed.len() != case.bodies.len() {
        return Err(FieldError::new(
            "state.bodies",
            format!(
                "has {} entries, but the case has {} bodies",
                listed.len(),
                case.bodies.len()
            ),
        ));
    }
    let mut bodies = Vec::with_capacity(listed.len());
    for (k, (b, init)) in listed.iter().zip(&case.bodies).enumerate() {
        let path = index("state.bodies", k);
        let mut b = Obj::new(b, &path)?;
        let force = b.req_with("force", pair)?;
        let torque = b.req_with("torque", float)?;
        let frame = match b.opt_with("frame", floats::<2>)? {
            Some([c, s]) if init.shape.is_circle() => (c, s),
            Some(_) => {
                return Err(FieldError::new(
                    join(&path, "frame"),
                    "only a circle keeps a frame apart from its angle",
                ));
            }
            None => {
                let (s, c) = init.angle.sin_cos();
                (c, s)
            }
        };
        let image = match cell {
            Some(_) => b.req_with("image", |v, p| {
                let [x, y] = floats::<2>(v, p)?;
                let whole = |z: f64| z.fract() == 0.0 && z.abs() < i32::MAX as f64;
                if !(whole(x) && whole(y)) {
                    return Err(FieldError::new(
                        p,
                        "must be two whole numbers (image counts)",
                    ));
                }
                Ok([x as i32, y as i32])
            })?,
            None => [0, 0],
        };
        b.finish()?;
        bodies.push(BodyRestart {
            image,
            position: init.position,
            angle: init.angle,
            frame,
            velocity: init.velocity,
            omega: init.omega,
            force,
            torque,
        });
    }
    let slots = o.req_with("contacts", |v, p| {
        array(v, p)?
            .iter()
            .enumerate()
            .map(|(k, c)| parse_contact(c, &index(p, k)))
            .collect::<Result<Vec<_>, _>>()
    })?;
    let (builds, wall_built_at, lattice_built_at, built_at) =
        o.req_with("neighbour_list", |v, p| {
            object(v, p, |l| {
                let builds = l.req_with("builds", whole)?;
                let points = |v: &Value, p: &str| -> Result<Vec<Vec2>, FieldError> {
                    array(v, p)?
                        .iter()
                        .enumerate()
                        .map(|(k, x)| pair(x, &index(p, k)))
                        .collect()
                };
                let wall_built_at = l.req_with("wall_built_at", points)?;
                let lattice = l.opt_with("lattice_built_at", |v, p| {
                    object(v, p, |m| {
                        Ok(LatticeMark {
                            shift: m.req_with("shift", float)?,
                            size: m.req_with("size", pair)?,
                        })
                    })
                })?;
                let built_at = l.req_with("built_at", points)?;
                Ok((builds, wall_built_at, lattice, built_at))
            })
        })?;
    let n = bodies.len();
    let ids = o
        .opt_with("ids", |v, p| {
            array(v, p)?
                .iter()
                .enumerate()
                .map(|(k, x)| whole(x, &index(p, k)))
                .collect::<Result<Vec<_>, _>>()
        })?
        .unwrap_or_else(|| (0..n as u64).collect());
    let next_id = o.opt_with("next_id", whole)?.unwrap_or(n as u64);
    let flow = o.opt_with("flow", |v, p| parse_flow(v, p, case))?;
    o.finish()?;
    if case.flow.is_some() != flow.is_some() {
        return Err(FieldError::new(
            "state.flow",
            if flow.is_some() {
                "the state has a flow, but the case has no `insert` or `outflow`"
            } else {
                "is missing: the case has `insert` or `outflow`, and a continued run needs where \
                 they stood"
            },
        ));
    }
    let state = RestartState {
        step,
        time,
        bodies,
        walls,
        slots,
        built_at,
        wall_built_at,
        // (A state file written before the lattice was kept: the cell's now, as those runs
        // had it.)
        lattice_built_at: match cell {
            Some(c) => lattice_built_at.or(Some(c.lattice())),
            None => None,
        },
        builds,
        energies,
        diagnostics,
        last_increments,
        cell,
        ids,
        next_id,
        flow,
    };
    Ok((state, run))
}

/// A state's `flow` block: where each inserter of the case stands (its generator, count and
/// next try), the step of the last application and the bodies removed so far.
fn parse_flow(v: &Value, path: &str, case: &Case) -> Result<FlowRestart, FieldError> {
    let mut o = Obj::new(v, path)?;
    let inserters = o.req_with("inserters", |v, p| {
        array(v, p)?
            .iter()
            .enumerate()
            .map(|(k, x)| {
                let at = index(p, k);
                let mut i = Obj::new(x, &at)?;
                let rng = i.req_with("rng", |v, p| {
                    v.as_str()
                        .and_then(|t| t.strip_prefix("0x"))
                        .and_then(|t| u64::from_str_radix(t, 16).ok())
                        .ok_or_else(|| {
                            FieldError::new(p, "must be a generator state such as \"0x1f\"")
                        })
                })?;
                let inserted = i.req_with("inserted", whole)?;
                let next_try = i.opt_with("next_try", float)?.unwrap_or(f64::NEG_INFINITY);
                i.finish()?;
                Ok(InserterState {
                    rng,
                    inserted,
                    next_try,
                })
            })
            .collect::<Result<Vec<_>, FieldError>>()
    })?;
    let want = case.flow.as_ref().map_or(0, |f| f.inserters.len());
    if inserters.len() != want {
        return Err(FieldError::new(
            join(path, "inserters"),
            format!(
                "has {} entries, but the case has {want} inserters",
                inserters.len()
            ),
        ));
    }
    let applied_step = o.opt_with("applied_step", whole)?;
    let discharged = o.req_with("discharged", whole)?;
    let discharged_mass = o.req_with("discharged_mass", float)?;
    o.finish()?;
    Ok(FlowRestart {
        inserters,
        applied_step,
        discharged,
        discharged_mass,
    })
}

fn parse_contact(v: &Value, path: &str) -> Result<SlotRestart, FieldError> {
    let mut c = Obj::new(v, path)?;
    let index_of = |v: &Value, p: &str| {
        u32::try_from(whole(v, p)?)
            .ok()
            .filter(|&x| x < MAX_INDEX)
            .ok_or_else(|| FieldError::new(p, "is beyond the largest index"))
    };
    let i = c.req_with("i", index_of)?;
    let j = match (c.has("j"), c.has("wall")) {
        (true, false) => c.req_with("j", index_of)?,
        (false, true) => Partner::Wall(c.req_with("wall", index_of)? as usize).key(),
        _ => {
            return Err(FieldError::new(
                path,
                "must give either `j` (a body) or `wall` (a wall index)",
            ));
        }
    };
    let active = c
        .opt_with("active", |v, p| {
            v.as_bool().ok_or_else(|| {
                FieldError::new(p, format!("must be true or false, got {}", type_of(v)))
            })
        })?
        .unwrap_or(false);
    let sub = c
        .opt_with("members", |v, p| {
            let m = v.as_array().filter(|a| a.len() == 2).ok_or_else(|| {
                FieldError::new(
                    p,
                    format!("must be [member of i, member of j], got {}", shown(v)),
                )
            })?;
            let member = |k: usize| {
                let at = format!("{p}[{k}]");
                whole(&m[k], &at).and_then(|x| {
                    usize::try_from(x)
                        .ok()
                        .filter(|&x| x < crate::geometry::clump::MAX_MEMBERS)
                        .ok_or_else(|| FieldError::new(at, "is beyond the largest member index"))
                })
            };
            Ok(Slot::sub_of(member(0)?, member(1)?))
        })?
        .unwrap_or(0);
    let mut slot = Slot::with_sub(i, j, sub);
    let mut more = [0.0; HISTORY_LEN - 1];
    let mut data = ContactData::default();
    if active {
        let state = c.req_with("state", |v, p| {
            v.as_str().and_then(state_from_name).ok_or_else(|| {
                FieldError::new(
                    p,
                    format!(
                        "must be one of `overlap`, `deep`, `contained`, `touching`, `separated`, got {}",
                        shown(v)
                    ),
                )
            })
        })?;
        slot.active = true;
        slot.state = state;
        // The history, each part's values by their names (the first is the slot's).
        slot.shear = c.req_with(History::NAMES[0], float)?;
        for (v, name) in more.iter_mut().zip(&History::NAMES[1..]) {
            *v = c.req_with(name, float)?;
        }
        slot.history_energy = c.req_with("history_energy", float)?;
        data = ContactData {
            point: c.req_with("point", pair)?,
            force: c.req_with("force", pair)?,
            force_non_elastic: c.req_with("force_non_elastic", pair)?,
            couple: c.req_with("couple", float)?,
            couple_non_elastic: c.req_with("couple_non_elastic", float)?,
        };
    }
    let cache = c.opt_with("warm", warm)?.unwrap_or(PairCache::EMPTY);
    c.finish()?;
    Ok(SlotRestart {
        slot,
        more,
        cache,
        data,
    })
}

fn parse_run(v: &Value, path: &str) -> Result<RunProgress, FieldError> {
    let mut r = Obj::new(v, path)?;
    let initial_total = r.req_with("initial_total_energy", float)?;
    let quiescence_streak = r.req_with("quiescence_streak", whole)?;
    let first_contact_step = r.req_with("first_contact_step", |v, p| match v {
        Value::Null => Ok(None),
        _ => whole(v, p).map(Some),
    })?;
    let contact_sum = r.req_with("contact_sum", whole)?;
    let watch = r.req_with("watch", |v, p| {
        object(v, p, |w| {
            Ok(BlowupWatch {
                kinetic0: w.req_with("kinetic0", float)?,
                elastic0: w.req_with("elastic0", float)?,
                potential0: w.req_with("potential0", float)?,
                total0: w.req_with("total0", float)?,
                gravity_supplied: w.req_with("gravity_supplied", float)?,
                boundary_supplied: w.req_with("boundary_supplied", float)?,
                // Absent from states written before it was kept: the state's own dissipation
                // (set by the caller, which has it).
                dissipated_max: w.opt_with("dissipated_max", float)?.unwrap_or(f64::NAN),
                depth_limit: w.req_with("depth_limit", float)?,
            })
        })
    })?;
    r.finish()?;
    Ok(RunProgress {
        initial_total,
        quiescence_streak,
        first_contact_step,
        contact_sum,
        watch,
    })
}
