//! `state.json`: the state a run ended in, as a case file that continues the run
//! (`dem2d run RUN/state.json`).
//!
//! The file is the run's case — every field as the case gave it, the bodies listed with their
//! current positions, angles and velocities — plus a `"state"` block holding the rest of the
//! state ([`crate::dynamics::restart`]): the step and time, each body's last force and moment
//! (and a circle's frame), each wall's current point, velocity and load, every pair of the
//! neighbour list with its contact history and warm start, the energy account, the counters —
//! and beside the world's state the run's progress ([`RunProgress`], `"run"`). `scene::state`
//! reads it back.
//!
//! Every number is written in the shortest form that reads back as the same double (ryu, as
//! serde_json writes floats; `-0.0` stays negative, subnormals keep their bits). A warm start is
//! single precision: its numbers are written as the doubles equal to them (read back exactly)
//! and `null` for its NaN. One body, one contact or one position per line. The file is written
//! atomically (a temporary file renamed over it), like `summary.json`.

use super::summary::Status;
use super::trace::WriteError;
use crate::contact_law::History;
use crate::dynamics::restart::{RestartState, state_name};
use crate::dynamics::{BodyInit, World};
use crate::geometry::{Shape, Vec2};
use crate::run::{End, Observer, ObserverError, RunError, RunProgress, StepInfo};
use serde_json::{Value, json};
use std::fmt::Write as _;
use std::io;
use std::path::{Path, PathBuf};

/// The case's top-level fields in the order a state file lists them (the bodies and the state
/// come last).
const CASE_ORDER: [&str; 17] = [
    "version",
    "name",
    "description",
    "units",
    "gravity",
    "dt",
    "duration",
    "quiescence",
    "quiescence_window",
    "output_every",
    "output",
    "contact",
    "materials",
    "pairs",
    "walls",
    "cell",
    "damping",
];

/// A double in its shortest round-trip form (`null` if not finite).
fn num(x: f64) -> String {
    serde_json::to_string(&x).expect("a float serialises")
}

fn vec2(v: Vec2) -> String {
    format!("[{}, {}]", num(v.x), num(v.y))
}

fn compact(v: &Value) -> String {
    serde_json::to_string(v).expect("a JSON value serialises")
}

/// The text of a state file: `case` the run's case as read (its JSON), `duration` the run's
/// duration (the case's, or the one the command line gave), `state` the world's state, `run`
/// the run's progress, `bodies` the world's bodies as they are (for which of them are circles:
/// a circle's frame is written; and the fields of a body inserted during the run), `status`
/// how the run ended.
///
/// Each body is listed with the fields the case gave it, found by its identity
/// ([`crate::dynamics::Bodies::id`]: the case's `bodies[id]`, or where a state file's `ids`
/// put it); a body inserted during the run ([`crate::dynamics::flow`]) with its shape, its
/// material's name and its density (unless its material gives it).
pub fn state_text(
    case: &Value,
    duration: f64,
    state: &RestartState,
    run: Option<&RunProgress>,
    bodies: &[BodyInit],
    status: &str,
) -> String {
    let mut out = String::with_capacity(256 + 200 * (state.bodies.len() + state.slots.len()));
    out.push_str("{\n");
    for key in CASE_ORDER {
        let value = match key {
            "duration" => Some(num(duration)),
            _ => case.get(key).map(compact),
        };
        if let Some(v) = value {
            let _ = writeln!(out, "  {}: {v},", compact(&Value::from(key)));
        }
    }
    // Keys this list does not know yet still travel with the state (a restart reads the case
    // from it): after the known ones, in the case's order.
    if let Some(obj) = case.as_object() {
        for (key, v) in obj {
            if !CASE_ORDER.contains(&key.as_str()) && key != "bodies" && key != "state" {
                let _ = writeln!(out, "  {},", member(key, v));
            }
        }
    }
    // The bodies: the case's, at their current pose and velocity.
    out.push_str("  \"bodies\": [\n");
    let listed = case.get("bodies").and_then(Value::as_array);
    // Where each identity is listed in the case (a state file's `ids`; else its index).
    let listed_ids: Option<Vec<u64>> = case
        .get("state")
        .and_then(|s| s.get("ids"))
        .and_then(Value::as_array)
        .map(|a| a.iter().filter_map(Value::as_u64).collect());
    let place: std::collections::HashMap<u64, usize> = match &listed_ids {
        Some(ids) => ids.iter().enumerate().map(|(k, &id)| (id, k)).collect(),
        None => (0..listed.map_or(0, Vec::len))
            .map(|k| (k as u64, k))
            .collect(),
    };
    for (k, b) in state.bodies.iter().enumerate() {
        let id = state.ids.get(k).copied().unwrap_or(k as u64);
        let given = match place
            .get(&id)
            .and_then(|&at| listed.and_then(|l| l.get(at)))
        {
            Some(v) => v.clone(),
            None => bodies
                .get(k)
                .map_or(Value::Null, |b| inserted_body(case, b)),
        };
        let mut line = String::from("{");
        if let Some(shape) = given.get("shape") {
            let _ = write!(line, "\"shape\": {}, ", compact(shape));
        }
        let _ = write!(
            line,
            "\"position\": {}, \"angle\": {}, \"velocity\": {}, \"omega\": {}",
            vec2(b.position),
            num(b.angle),
            vec2(b.velocity),
            num(b.omega)
        );
        if let Some(obj) = given.as_object() {
            for (key, v) in obj {
                if !["shape", "position", "angle", "velocity", "omega"].contains(&key.as_str()) {
                    let _ = write!(line, ", {}", member(key, v));
                }
            }
        }
        line.push('}');
        let sep = if k + 1 < state.bodies.len() { "," } else { "" };
        let _ = writeln!(out, "    {line}{sep}");
    }
    out.push_str("  ],\n");
    out.push_str("  \"state\": {\n");
    let circles: Vec<bool> = bodies.iter().map(|b| b.shape.is_circle()).collect();
    write_state_block(&mut out, state, run, &circles, status);
    out.push_str("  }\n}\n");
    out
}

/// One member of an object, `"key": value`, in compact JSON.
fn member(key: &str, v: &Value) -> String {
    format!("{}: {}", compact(&Value::from(key)), compact(v))
}

/// The fields of a body inserted during the run: its shape, its material (by name: material
/// k is the case's k-th in `materials`, as the reader numbers them) and its density unless its
/// material gives one.
fn inserted_body(case: &Value, b: &BodyInit) -> Value {
    let shape = match b.shape {
        Shape::Circle { r } => json!({"type": "circle", "r": r}),
        Shape::Ellipse { a, b } => json!({"type": "ellipse", "a": a, "b": b}),
        Shape::Rectangle { w, h } => json!({"type": "rectangle", "w": w, "h": h}),
        // (Inserters make none of these.)
        Shape::Polygon(_) | Shape::Clump(_) => Value::Null,
    };
    let mut fields = serde_json::Map::new();
    fields.insert("shape".into(), shape);
    let material = match b.material {
        0 => None,
        m => case
            .get("materials")
            .and_then(Value::as_object)
            .and_then(|o| o.iter().nth(m as usize - 1)),
    };
    if let Some((name, given)) = material {
        fields.insert("material".into(), Value::from(name.as_str()));
        if given.get("density").is_none() {
            fields.insert("density".into(), json!(b.density));
        }
    } else {
        fields.insert("density".into(), json!(b.density));
    }
    Value::Object(fields)
}

fn write_state_block(
    out: &mut String,
    s: &RestartState,
    run: Option<&RunProgress>,
    circles: &[bool],
    status: &str,
) {
    let _ = writeln!(out, "    \"status\": {},", compact(&Value::from(status)));
    let _ = writeln!(out, "    \"step\": {},", s.step);
    let _ = writeln!(out, "    \"time\": {},", num(s.time));
    let e = &s.energies;
    let _ = writeln!(
        out,
        "    \"energies\": {{\"kinetic\": {}, \"potential\": {}, \"elastic\": {}, \"dissipated\": {}, \"boundary_work\": {}}},",
        num(e.kinetic),
        num(e.potential),
        num(e.elastic),
        num(e.dissipated),
        num(e.boundary_work)
    );
    let d = &s.diagnostics;
    let _ = writeln!(
        out,
        "    \"diagnostics\": {{\"max_depth_ratio\": {}, \"deep_contacts\": {}, \"contained_contacts\": {}, \"dt_critical_observed\": {}}},",
        num(d.max_depth_ratio),
        d.deep_contacts,
        d.contained_contacts,
        num(d.dt_critical_observed)
    );
    let [a, b, c] = s.last_increments;
    let _ = writeln!(
        out,
        "    \"last_increments\": [{}, {}, {}],",
        num(a),
        num(b),
        num(c)
    );
    if let Some(run) = run {
        write_run(out, run);
    }
    if let Some(c) = &s.cell {
        let _ = writeln!(
            out,
            "    \"cell\": {{\"size\": {}, \"offset\": {}, \"shift\": {}, \"stress\": [{}], \"stiffness_yy\": {}, \"elastic_yy\": {}, \"stiffness_xx\": {}, \"elastic_xx\": {}}},",
            vec2(c.size),
            num(c.offset),
            num(c.shift),
            c.stress.map(num).join(", "),
            num(c.stiffness[1]),
            num(c.elastic[1]),
            num(c.stiffness[0]),
            num(c.elastic[0])
        );
    }
    if s.flow.is_some() || s.ids.iter().enumerate().any(|(k, &id)| id != k as u64) {
        let ids: Vec<String> = s.ids.iter().map(u64::to_string).collect();
        let _ = writeln!(out, "    \"next_id\": {},", s.next_id);
        let _ = writeln!(out, "    \"ids\": [{}],", ids.join(", "));
    }
    if let Some(f) = &s.flow {
        let inserters: Vec<String> = f
            .inserters
            .iter()
            .map(|i| {
                let next = if i.next_try.is_finite() {
                    format!(", \"next_try\": {}", num(i.next_try))
                } else {
                    String::new()
                };
                format!(
                    "{{\"rng\": \"{:#x}\", \"inserted\": {}{next}}}",
                    i.rng, i.inserted
                )
            })
            .collect();
        let applied = f
            .applied_step
            .map_or(String::new(), |s| format!("\"applied_step\": {s}, "));
        let _ = writeln!(
            out,
            "    \"flow\": {{{applied}\"discharged\": {}, \"discharged_mass\": {}, \"inserters\": [{}]}},",
            f.discharged,
            num(f.discharged_mass),
            inserters.join(", ")
        );
    }
    out.push_str("    \"walls\": [");
    write_lines(out, &s.walls, |out, _, w| {
        let l = &w.load;
        let _ = write!(
            out,
            "{{\"point\": {}, \"velocity\": {}, \"load\": {{\"force\": {}, \"force_non_elastic\": {}, \"stiffness\": {}, \"contacts\": {}}}",
            vec2(w.point),
            vec2(w.velocity),
            vec2(l.force),
            vec2(l.force_non_elastic),
            num(l.stiffness),
            l.contacts
        );
        if let Some(p) = &w.program {
            let _ = write!(
                out,
                ", \"program\": {{\"stage\": {}, \"start\": {}, \"start_time\": {}}}",
                p.stage,
                vec2(p.start),
                num(p.start_time)
            );
        }
        if let Some(t) = &w.turn {
            let _ = write!(
                out,
                ", \"turn\": {{\"angle\": {}, \"start_angle\": {}, \"omega\": {}, \"torque\": {}, \"torque_non_elastic\": {}}}",
                num(t.angle),
                num(t.start_angle),
                num(t.omega),
                num(l.torque),
                num(l.torque_non_elastic)
            );
        }
        out.push('}');
    });
    out.push_str(",\n    \"bodies\": [");
    write_lines(out, &s.bodies, |out, k, b| {
        let _ = write!(
            out,
            "{{\"force\": {}, \"torque\": {}",
            vec2(b.force),
            num(b.torque)
        );
        if circles.get(k) == Some(&true) {
            let _ = write!(out, ", \"frame\": [{}, {}]", num(b.frame.0), num(b.frame.1));
        }
        if s.cell.is_some() {
            let _ = write!(out, ", \"image\": [{}, {}]", b.image[0], b.image[1]);
        }
        out.push('}');
    });
    out.push_str(",\n    \"contacts\": [");
    write_lines(out, &s.slots, |out, _, c| {
        let slot = &c.slot;
        let _ = write!(out, "{{\"i\": {}, ", slot.i);
        match slot.sides().wall() {
            Some(w) => {
                let _ = write!(out, "\"wall\": {w}");
            }
            None => {
                let _ = write!(out, "\"j\": {}", slot.j);
            }
        }
        if slot.sub != 0 {
            // A clump pair's member pair (absent for other pairs).
            let (a, b) = slot.members();
            let _ = write!(out, ", \"members\": [{a}, {b}]");
        }
        if slot.active {
            let d = &c.data;
            let _ = write!(
                out,
                ", \"active\": true, \"state\": \"{}\"",
                state_name(slot.state)
            );
            // The history, each part's values by their names (the first is the slot's).
            for (name, v) in History::NAMES
                .iter()
                .zip(std::iter::once(slot.shear).chain(c.more))
            {
                let _ = write!(out, ", \"{name}\": {}", num(v));
            }
            let _ = write!(
                out,
                ", \"history_energy\": {}, \"point\": {}, \"force\": {}, \"force_non_elastic\": {}, \"couple\": {}, \"couple_non_elastic\": {}",
                num(slot.history_energy),
                vec2(d.point),
                vec2(d.force),
                vec2(d.force_non_elastic),
                num(d.couple),
                num(d.couple_non_elastic)
            );
        }
        if !c.cache.is_empty() {
            let w = c.cache.saved().map(|v| num(f64::from(v)));
            let _ = write!(out, ", \"warm\": [{}, {}, {}, {}]", w[0], w[1], w[2], w[3]);
        }
        out.push('}');
    });
    out.push_str(",\n");
    let _ = write!(
        out,
        "    \"neighbour_list\": {{\"builds\": {}, \"wall_built_at\": [{}], ",
        s.builds,
        s.wall_built_at
            .iter()
            .map(|p| vec2(*p))
            .collect::<Vec<_>>()
            .join(", ")
    );
    if let Some(m) = &s.lattice_built_at {
        let _ = write!(
            out,
            "\"lattice_built_at\": {{\"shift\": {}, \"size\": {}}}, ",
            num(m.shift),
            vec2(m.size)
        );
    }
    out.push_str("\"built_at\": [");
    write_lines(out, &s.built_at, |out, _, p| out.push_str(&vec2(*p)));
    out.push_str("}\n");
}

/// The items of an array of the state block (its `[` written), one a line (`item` writes
/// the k-th), and its `]`.
fn write_lines<T>(out: &mut String, items: &[T], mut item: impl FnMut(&mut String, usize, &T)) {
    for (k, x) in items.iter().enumerate() {
        out.push_str(if k > 0 { ",\n      " } else { "\n      " });
        item(out, k, x);
    }
    out.push_str(if items.is_empty() { "]" } else { "\n    ]" });
}

fn write_run(out: &mut String, r: &RunProgress) {
    let w = &r.watch;
    let _ = writeln!(
        out,
        "    \"run\": {{\"initial_total_energy\": {}, \"quiescence_streak\": {}, \"first_contact_step\": {}, \"contact_sum\": {}, \"watch\": {{\"kinetic0\": {}, \"elastic0\": {}, \"potential0\": {}, \"total0\": {}, \"gravity_supplied\": {}, \"boundary_supplied\": {}, \"dissipated_max\": {}, \"depth_limit\": {}}}}},",
        num(r.initial_total),
        r.quiescence_streak,
        r.first_contact_step
            .map_or("null".to_string(), |s| s.to_string()),
        r.contact_sum,
        num(w.kinetic0),
        num(w.elastic0),
        num(w.potential0),
        num(w.total0),
        num(w.gravity_supplied),
        num(w.boundary_supplied),
        num(w.dissipated_max),
        num(w.depth_limit)
    );
}

/// Writes `state.json` into `dir` atomically (`state.json.tmp`, synced, renamed over it): the
/// world's state with the run's progress `run` (see [`state_text`]).
pub fn write_state(
    dir: &Path,
    case: &Value,
    duration: f64,
    world: &World,
    run: &RunProgress,
    status: &str,
) -> io::Result<()> {
    let text = state_text(
        case,
        duration,
        &world.restart_state(),
        Some(run),
        &current_bodies(world),
        status,
    );
    super::write_atomically(dir, "state.json", &text)
}

/// The world's bodies as they are now (shape, material, density: what a state file lists).
pub fn current_bodies(world: &World) -> Vec<BodyInit> {
    let b = &world.bodies;
    (0..b.len())
        .map(|k| BodyInit {
            shape: b.shape[k],
            position: b.state[k].pose.position,
            angle: b.state[k].pose.angle(),
            velocity: b.state[k].vel,
            omega: b.state[k].omega,
            density: b.density[k],
            material: b.material[k],
            prescribed: b.is_prescribed(k),
        })
        .collect()
}

/// The writer of a run's `state.json` (an observer): when the run ends, however it ends but by a
/// blow-up (a non-finite or unphysical state is nothing to continue from), with the status of
/// its end; with checkpoints ([`StateWriter::checkpoint_every`]), also every so many steps, with
/// the status `checkpoint`, each replacing the last atomically — a run killed outright (SIGKILL,
/// a node lost) continues from the last, and the continued run's rows are the uninterrupted
/// run's.
pub struct StateWriter {
    dir: PathBuf,
    case: Value,
    duration: f64,
    checkpoint_every: Option<u64>,
}

impl StateWriter {
    /// Into `dir`, for the run of `case` (its JSON) of `duration`.
    pub fn new(dir: &Path, case: &Value, duration: f64) -> Self {
        StateWriter {
            dir: dir.to_path_buf(),
            case: case.clone(),
            duration,
            checkpoint_every: None,
        }
    }

    /// Also writes the state every `every` steps (`None` or 0: only at the end).
    pub fn checkpoint_every(mut self, every: Option<u64>) -> Self {
        self.checkpoint_every = every.filter(|&n| n > 0);
        self
    }

    /// Writes the state now, with the run's progress `run` and the status `status`.
    pub fn write(
        &self,
        world: &World,
        run: &RunProgress,
        status: Status,
    ) -> Result<(), WriteError> {
        self.write_status(world, run, status.as_str())
    }

    fn write_status(
        &self,
        world: &World,
        run: &RunProgress,
        status: &str,
    ) -> Result<(), WriteError> {
        write_state(&self.dir, &self.case, self.duration, world, run, status).map_err(|error| {
            WriteError {
                file: self.dir.join("state.json"),
                error,
            }
        })
    }
}

impl Observer for StateWriter {
    fn after_step(&mut self, world: &World, info: &StepInfo) -> Result<(), ObserverError> {
        // (Not at the last step: the run's end writes it with how it ended.)
        if let Some(n) = self.checkpoint_every
            && info.step.is_multiple_of(n)
            && !info.stopping
        {
            self.write_status(world, &info.progress, "checkpoint")?;
        }
        Ok(())
    }

    fn finish(&mut self, world: &World, end: &End) -> Result<(), ObserverError> {
        if matches!(end.outcome, Err(RunError::Blowup(_))) {
            return Ok(());
        }
        Ok(self.write(world, end.progress, Status::of(end.outcome))?)
    }
}
