//! Case files: one JSON file describes one scene completely (`"version": 1`).
//!
//! ```json
//! { "version": 1, "name": "settle3", "description": "…", "units": "cm",
//!   "gravity": [0, -980], "dt": 1e-5, "duration": 0.5,
//!   "quiescence": 1e-10, "quiescence_window": 1, "output_every": 100,
//!   "contact": { "model": "linear", "kn_over_rho_g": 36400, "ks_over_rho_g": 36400,
//!                "eta_n_over_rho_g": 25.925, "eta_s_over_rho_g": 25.925, "friction": 0.5 },
//!   "walls": [ { "point": [0, 0], "normal": [0, 1], "friction": 0.3 } ],
//!   "bodies": [ { "shape": {"type": "ellipse", "a": 1.5, "b": 1.0}, "position": [0, 5],
//!                 "angle": 0.5, "velocity": [20, 0], "omega": 0, "density": 1.0 } ] }
//! ```
//! Unknown fields are errors; a state file's `"state"` block is read by [`super::state`]. `contact.model` is `linear` (stiffness `kn` or `kn_over_rho_g`;
//! `ks`/`ks_over_rho_g`, default equal to the normal one as in P; damping `eta_n`/
//! `eta_n_over_rho_g` with `eta_s`/`eta_s_over_rho_g` defaulting to it (T: η_t = η_n), or
//! `restitution` instead (T12); `friction`) or `hertz_mindlin` (`young`, `poisson`,
//! `restitution`, `friction`; T10–T20). A wall may override any contact parameter.

use super::body::{parse_body_with, parse_wall_with};
use super::fields::{
    FieldError, Obj, index, join, non_negative, number, positive, scale, type_of, unknown_field,
    vec2,
};
use super::ranges::{Placed, SpecContext, check_extent, check_spec, check_steps};
use crate::contact_law::{
    ContactSpec, LinearDamping, NormalForce, RollingModel, RollingPart, Scaled,
};
use crate::dynamics::{BodyInit, Boundary, Motion, Servo, Span};
use crate::geometry::Vec2;
use serde_json::{Map, Value};

/// A scene as a case file describes it.
#[derive(Clone, Debug, PartialEq)]
pub struct Case {
    pub name: String,
    pub description: String,
    /// The length unit, for the plots' labels only (`"cm"` in every shipped case: dem2d works in
    /// cgs; default empty).
    pub units: String,
    pub gravity: Vec2,
    pub dt: f64,
    pub duration: f64,
    /// P's quiescence threshold on the mean displacement increments per step (stop at rest).
    pub quiescence: Option<f64>,
    /// Consecutive steps the quiescence criterion must hold (1: P's criterion, one step). A body
    /// rocking or bouncing passes through zero velocity at its turning points, where one step
    /// can satisfy the criterion; a window of a few hundred steps tells that from rest.
    pub quiescence_window: u64,
    pub output_every: u64,
    /// Optional outputs (`"output": {"vtk": true, "vtk_every": N, "analysis": true,
    /// "contacts": true, "analysis_window": [x0, x1, y0, y1]}`).
    pub output: OutputSpec,
    pub contact: ContactSpec,
    pub walls: Vec<Boundary>,
    pub bodies: Vec<BodyInit>,
}

/// The case's optional outputs.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct OutputSpec {
    /// Write VTK frames and `run.pvd` for ParaView (as `dem2d run --vtk`).
    pub vtk: bool,
    /// Steps between VTK frames (default: `output_every`).
    pub vtk_every: Option<u64>,
    /// Write `analysis.csv` at the output frames (as `dem2d run --analysis`).
    pub analysis: bool,
    /// Write `contacts.csv` and `walls.csv` at the output frames (as `dem2d run --contacts`).
    pub contacts: bool,
    /// The region of `analysis.csv`'s measures, `[x0, x1, y0, y1]` (cm; default: the box of four
    /// axis-aligned walls, else the bodies' extent).
    pub analysis_window: Option<[f64; 4]>,
}

const CONTACT_KEYS: [&str; 17] = [
    "model",
    "normal_force",
    "kn",
    "kn_over_rho_g",
    "ks",
    "ks_over_rho_g",
    "eta_n",
    "eta_n_over_rho_g",
    "eta_s",
    "eta_s_over_rho_g",
    "restitution",
    "friction",
    "young",
    "poisson",
    "rolling_model",
    "rolling_friction",
    "rolling_damping",
];

/// Keys that replace each other when a wall overrides one of them.
const GROUPS: [&[&str]; 3] = [
    &["kn", "kn_over_rho_g"],
    &["ks", "ks_over_rho_g"],
    &[
        "eta_n",
        "eta_n_over_rho_g",
        "eta_s",
        "eta_s_over_rho_g",
        "restitution",
    ],
];

impl Case {
    /// Reads a case from its JSON text. Errors name the field (`bodies[2].shape.a`, …).
    pub fn from_json(text: &str) -> Result<Case, FieldError> {
        let v = super::fields::parse_json(text, "")?;
        Case::from_value(&v)
    }

    /// Reads a case from a parsed JSON value.
    pub fn from_value(v: &Value) -> Result<Case, FieldError> {
        if let Some(items) = v.as_array()
            && items
                .iter()
                .any(|p| p.get("i").is_some() && p.get("j").is_some())
        {
            return Err(FieldError::new(
                "",
                "this is a `dem2d contact` input (an array of {\"i\": BODY, \"j\": BODY} pairs), \
                 not a case: give it to `dem2d contact FILE`; a case is an object with \
                 `version`, `name`, `gravity`, `dt`, `duration`, `contact` and `bodies`",
            ));
        }
        let mut o = Obj::new(v, "")?;
        let version = o.req_with("version", number)?;
        if version != 1.0 {
            return Err(FieldError::new(
                "version",
                format!("unsupported version {version} (this dem2d reads version 1)"),
            ));
        }
        let name = o.req_with("name", string)?;
        let description = o.opt_with("description", string)?.unwrap_or_default();
        let units = o.opt_with("units", string)?.unwrap_or_default();
        let gravity = Vec2::from(o.req_with("gravity", vec2)?);
        let dt = o.req_with("dt", scale)?;
        let duration = o.req_with("duration", scale)?;
        let quiescence = o.opt_with("quiescence", positive)?;
        let quiescence_window = o.opt_with("quiescence_window", count)?.unwrap_or(1);
        let output_every = o.opt_with("output_every", count)?.unwrap_or(100);
        let output = match o.get("output") {
            None => OutputSpec::default(),
            Some(v) => {
                let mut out = Obj::new(v, "output")?;
                let vtk = out.opt_with("vtk", boolean)?.unwrap_or(false);
                let vtk_every = out.opt_with("vtk_every", count)?;
                let analysis = out.opt_with("analysis", boolean)?.unwrap_or(false);
                let contacts = out.opt_with("contacts", boolean)?.unwrap_or(false);
                let analysis_window = match out.get("analysis_window") {
                    None => None,
                    Some(w) => Some(analysis_window(w)?),
                };
                out.finish()?;
                OutputSpec {
                    vtk,
                    vtk_every,
                    analysis,
                    contacts,
                    analysis_window,
                }
            }
        };
        let contact_value = o.req("contact")?;
        let contact_map = contact_value
            .as_object()
            .ok_or_else(|| {
                FieldError::new(
                    "contact",
                    format!("must be an object, got {}", type_of(contact_value)),
                )
            })?
            .clone();
        let contact = parse_contact(&contact_map, "contact", "contact")?;
        let mut walls = Vec::new();
        if let Some(list) = o.get("walls") {
            let items = list.as_array().ok_or_else(|| {
                FieldError::new("walls", format!("must be an array, got {}", type_of(list)))
            })?;
            let mut spans = Vec::new();
            for (k, item) in items.iter().enumerate() {
                let path = index("walls", k);
                let (wall, (spec, motion)) = parse_wall_with(item, &path, |w| {
                    Ok((wall_overrides(w, &contact_map)?, wall_motion(w)?))
                })?;
                if let Motion::Servo(s) = motion {
                    spans.push((k, s.span));
                }
                walls.push(Boundary::moving(wall, spec.unwrap_or(contact), motion));
            }
            for (k, span) in spans {
                check_span(&walls, k, &span)?;
            }
        }
        let list = o.req("bodies")?;
        let items = list.as_array().ok_or_else(|| {
            FieldError::new("bodies", format!("must be an array, got {}", type_of(list)))
        })?;
        if items.is_empty() {
            return Err(FieldError::new("bodies", "must list at least one body"));
        }
        let mut bodies = Vec::with_capacity(items.len());
        for (k, item) in items.iter().enumerate() {
            let path = index("bodies", k);
            let mut b = Obj::new(item, &path)?;
            let (shape, pose, (velocity, omega, density)) = parse_body_with(&mut b, |b| {
                let velocity = b.opt_with("velocity", vec2)?.unwrap_or([0.0, 0.0]);
                let omega = b.opt_with("omega", number)?.unwrap_or(0.0);
                let density = b.opt_with("density", scale)?.unwrap_or(1.0);
                Ok((velocity, omega, density))
            })?;
            b.finish()?;
            bodies.push(BodyInit {
                shape,
                position: pose.position,
                angle: pose.angle(),
                velocity: Vec2::from(velocity),
                omega,
                density,
            });
        }
        // A state file's block (read by `scene::state`, which continues the run from it).
        let _ = o.get("state");
        o.finish()?;
        check_steps(duration, dt)?;
        let mut placed: Vec<Placed> = bodies
            .iter()
            .enumerate()
            .map(|(k, b)| Placed::Body {
                path: index("bodies", k),
                shape: &b.shape,
                position: b.position,
            })
            .collect();
        placed.extend(walls.iter().enumerate().map(|(w, ws)| Placed::Wall {
            path: index("walls", w),
            point: ws.line().point,
        }));
        check_extent(&placed)?;
        check_walls(&walls, &bodies)?;
        check_contact_ranges(&contact, &walls, &bodies, gravity)?;
        Ok(Case {
            name,
            description,
            units,
            gravity,
            dt,
            duration,
            quiescence,
            quiescence_window,
            output_every,
            output,
            contact,
            walls,
            bodies,
        })
    }

    /// A scene made in code rather than read from a file (no name or description, its duration
    /// one step, no quiescence criterion, the default outputs): its world is
    /// [`Case::build_world`]'s. Nothing is checked, as a file's case is.
    pub fn new(
        bodies: Vec<BodyInit>,
        walls: Vec<Boundary>,
        gravity: Vec2,
        contact: ContactSpec,
        dt: f64,
    ) -> Case {
        Case {
            name: String::new(),
            description: String::new(),
            units: String::new(),
            gravity,
            dt,
            duration: dt,
            quiescence: None,
            quiescence_window: 1,
            output_every: 100,
            output: OutputSpec::default(),
            contact,
            walls,
            bodies,
        }
    }

    /// The world this case describes, at t = 0 (the forces of the initial configuration
    /// evaluated).
    pub fn build_world(&self) -> crate::dynamics::World {
        crate::dynamics::World::new(
            &self.bodies,
            self.walls.clone(),
            self.gravity,
            self.contact,
            self.dt,
        )
    }

    /// The world of this case resumed from `state` (a state file's, taken of a world of this
    /// case): it steps on to the same bits as the world the state was taken from. Refused when
    /// the state does not fit the case.
    pub fn resume_world(
        &self,
        state: &crate::dynamics::RestartState,
    ) -> Result<crate::dynamics::World, crate::dynamics::RestartError> {
        crate::dynamics::World::resume(
            &self.bodies,
            self.walls.clone(),
            self.gravity,
            self.contact,
            self.dt,
            state,
        )
    }

    /// The same case stepped with `dt`.
    pub fn with_dt(mut self, dt: f64) -> Case {
        self.dt = dt;
        self
    }

    /// The same case with every contact (the scene's and each wall's) with the rolling
    /// resistance `rolling`.
    pub fn with_rolling(mut self, rolling: Option<RollingPart>) -> Case {
        self.contact = self.contact.with_rolling(rolling);
        for w in &mut self.walls {
            w.spec = w.spec.with_rolling(rolling);
        }
        self
    }

    /// The same case with every contact (the scene's and each wall's) under `normal_force`.
    pub fn with_normal_force(mut self, normal_force: NormalForce) -> Case {
        self.contact = self.contact.with_normal_force(normal_force);
        for w in &mut self.walls {
            w.spec = w.spec.with_normal_force(normal_force);
        }
        self
    }

    /// P's quiescence criterion as the case states it (None: no stop at rest).
    pub fn quiescence_criterion(&self) -> Option<crate::run::Quiescence> {
        self.quiescence
            .map(|q| crate::run::Quiescence::new(q, self.quiescence_window))
    }

    /// Number of steps the duration takes (rounded to the nearest step).
    pub fn steps(&self) -> u64 {
        (self.duration / self.dt).round().max(1.0) as u64
    }
}

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
fn check_walls(walls: &[Boundary], bodies: &[BodyInit]) -> Result<(), FieldError> {
    let smallest = bodies
        .iter()
        .map(|b| b.shape.inscribed_radius())
        .fold(f64::INFINITY, f64::min);
    for (j, b) in walls.iter().enumerate() {
        for (i, a) in walls[..j].iter().enumerate() {
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
    for (k, w) in walls.iter().enumerate() {
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

/// Checks every contact law a pair that can meet will use: the scene's (between bodies, and with
/// walls that do not override it) and each wall's own, for every density of the scene.
fn check_contact_ranges(
    contact: &ContactSpec,
    walls: &[Boundary],
    bodies: &[BodyInit],
    gravity: Vec2,
) -> Result<(), FieldError> {
    let by_density = |pick: fn(f64, f64) -> bool| {
        let (k, b) = bodies
            .iter()
            .enumerate()
            .reduce(|a, b| if pick(b.1.density, a.1.density) { b } else { a })
            .expect("at least one body");
        (b.density, format!("bodies[{k}].density"))
    };
    let rho = [by_density(|a, b| a < b), by_density(|a, b| a > b)];
    let g = gravity.norm();
    let scene_used = bodies.len() >= 2 || walls.iter().any(|w| w.spec == *contact);
    if scene_used {
        let ctx = SpecContext {
            at: "contact",
            rho: rho.clone(),
            g,
        };
        check_spec(contact, contact, &ctx)?;
    }
    for (w, ws) in walls.iter().enumerate() {
        if ws.spec != *contact {
            let at = index("walls", w);
            let ctx = SpecContext {
                at: &at,
                rho: rho.clone(),
                g,
            };
            check_spec(&ws.spec, contact, &ctx)?;
        }
    }
    Ok(())
}

fn string(v: &Value, path: &str) -> Result<String, FieldError> {
    v.as_str()
        .map(str::to_string)
        .ok_or_else(|| FieldError::new(path, format!("must be a string, got {}", type_of(v))))
}

fn boolean(v: &Value, path: &str) -> Result<bool, FieldError> {
    v.as_bool()
        .ok_or_else(|| FieldError::new(path, format!("must be true or false, got {}", type_of(v))))
}

fn count(v: &Value, path: &str) -> Result<u64, FieldError> {
    match v.as_u64() {
        Some(n) if n >= 1 => Ok(n),
        _ => Err(FieldError::new(
            path,
            format!("must be a whole number ≥ 1, got {v}"),
        )),
    }
}

/// A wall's contact overrides: every known contact key given on the wall replaces the scene's
/// (with the keys of its group); `None` when the wall overrides nothing.
fn wall_overrides(
    w: &mut Obj,
    defaults: &Map<String, Value>,
) -> Result<Option<ContactSpec>, FieldError> {
    let mut merged = defaults.clone();
    let mut any = false;
    let mut given: Vec<String> = Vec::new();
    for key in CONTACT_KEYS.iter() {
        if let Some(v) = w.get(key) {
            any = true;
            if *key == "model" {
                merged.clear();
            }
            // Another rolling model does not inherit the scene's model's damping.
            if *key == "rolling_model" && !w.has("rolling_damping") {
                merged.remove("rolling_damping");
            }
            for group in GROUPS {
                if group.contains(key) && !given.iter().any(|g| group.contains(&g.as_str())) {
                    for k in group.iter() {
                        merged.remove(*k);
                    }
                }
            }
            merged.insert(key.to_string(), v.clone());
            given.push(key.to_string());
        }
    }
    if !any {
        return Ok(None);
    }
    let path = w.path().to_string();
    parse_contact(&merged, &path, &path).map(Some)
}

/// The contact object. `path` prefixes field paths; `missing_at` is where a missing field is
/// reported.
fn parse_contact(
    map: &Map<String, Value>,
    path: &str,
    missing_at: &str,
) -> Result<ContactSpec, FieldError> {
    let field = |k: &str| join(path, k);
    let get = |k: &str| map.get(k);
    for k in CONTACT_KEYS {
        super::fields::note_key(path, k);
    }
    for k in map.keys() {
        if !CONTACT_KEYS.contains(&k.as_str()) {
            return Err(FieldError::new(field(k), unknown_field(k, &CONTACT_KEYS)));
        }
    }
    let model = match get("model") {
        Some(v) => string(v, &field("model"))?,
        None => return Err(FieldError::new(join(missing_at, "model"), "is missing")),
    };
    let friction = match get("friction") {
        Some(v) => non_negative(v, &field("friction"))?,
        None => return Err(FieldError::new(join(missing_at, "friction"), "is missing")),
    };
    let normal_force = match get("normal_force") {
        None => NormalForce::default(),
        Some(v) => match string(v, &field("normal_force"))?.as_str() {
            "area" => NormalForce::Area,
            "depth" => NormalForce::Depth,
            other => {
                return Err(FieldError::new(
                    field("normal_force"),
                    format!("unknown normal force `{other}` (expected `area` or `depth`)"),
                ));
            }
        },
    };
    let rolling = parse_rolling(map, path, missing_at)?;
    // A stiffness is a scale (zero would let bodies pass through each other); a damping may be
    // zero.
    type Reader = fn(&Value, &str) -> Result<f64, FieldError>;
    let scaled = |abs: &str, rel: &str| -> Result<Option<Scaled>, FieldError> {
        let read: Reader = if abs.starts_with('k') {
            scale
        } else {
            non_negative
        };
        match (get(abs), get(rel)) {
            (Some(_), Some(_)) => Err(FieldError::new(
                field(rel),
                format!("give `{abs}` or `{rel}`, not both"),
            )),
            (Some(v), None) => Ok(Some(Scaled::Absolute(read(v, &field(abs))?))),
            (None, Some(v)) => Ok(Some(Scaled::OverRhoG(read(v, &field(rel))?))),
            (None, None) => Ok(None),
        }
    };
    let restitution = |required: bool| -> Result<Option<f64>, FieldError> {
        match get("restitution") {
            Some(v) => {
                let e = positive(v, &field("restitution"))?;
                if e > 1.0 {
                    return Err(FieldError::new(
                        field("restitution"),
                        format!("must be in (0, 1], got {e}"),
                    ));
                }
                Ok(Some(e))
            }
            None if required => Err(FieldError::new(
                join(missing_at, "restitution"),
                "is missing",
            )),
            None => Ok(None),
        }
    };
    let refuse = |keys: &[&str], model: &str| -> Result<(), FieldError> {
        for k in keys {
            if get(k).is_some() {
                return Err(FieldError::new(
                    field(k),
                    format!("is not a parameter of the `{model}` model"),
                ));
            }
        }
        Ok(())
    };
    match model.as_str() {
        "linear" => {
            refuse(&["young", "poisson"], "linear")?;
            let kn = scaled("kn", "kn_over_rho_g")?.ok_or_else(|| {
                FieldError::new(
                    join(missing_at, "kn_over_rho_g"),
                    "is missing (or give `kn`)",
                )
            })?;
            let ks = scaled("ks", "ks_over_rho_g")?.unwrap_or(kn);
            let eta_n = scaled("eta_n", "eta_n_over_rho_g")?;
            let eta_s = scaled("eta_s", "eta_s_over_rho_g")?;
            let e = restitution(false)?;
            let damping = match (eta_n, e) {
                (Some(_), Some(_)) => {
                    return Err(FieldError::new(
                        field("restitution"),
                        "give dashpots (`eta_n…`) or `restitution`, not both",
                    ));
                }
                (Some(eta_n), None) => LinearDamping::Dashpots {
                    eta_n,
                    eta_s: eta_s.unwrap_or(eta_n),
                },
                (None, Some(e)) => {
                    if eta_s.is_some() {
                        return Err(FieldError::new(
                            field("eta_s"),
                            "with `restitution`, η_s = η_n (T); do not give `eta_s`",
                        ));
                    }
                    LinearDamping::Restitution(e)
                }
                (None, None) => {
                    return Err(FieldError::new(
                        join(missing_at, "eta_n_over_rho_g"),
                        "is missing (or give `eta_n` or `restitution`)",
                    ));
                }
            };
            Ok(ContactSpec::Linear {
                kn,
                ks,
                damping,
                friction,
                normal_force,
                rolling,
            })
        }
        "hertz_mindlin" => {
            refuse(
                &[
                    "kn",
                    "kn_over_rho_g",
                    "ks",
                    "ks_over_rho_g",
                    "eta_n",
                    "eta_n_over_rho_g",
                    "eta_s",
                    "eta_s_over_rho_g",
                ],
                "hertz_mindlin",
            )?;
            let young = match get("young") {
                Some(v) => scale(v, &field("young"))?,
                None => return Err(FieldError::new(join(missing_at, "young"), "is missing")),
            };
            let poisson = match get("poisson") {
                Some(v) => {
                    let nu = number(v, &field("poisson"))?;
                    // At ν = −1 the contact moduli E* and G* (T11, T19) are infinite.
                    if !(nu > -1.0 && nu < 0.5) {
                        return Err(FieldError::new(
                            field("poisson"),
                            format!("must be in (-1, 0.5), got {nu}"),
                        ));
                    }
                    nu
                }
                None => return Err(FieldError::new(join(missing_at, "poisson"), "is missing")),
            };
            let restitution = restitution(true)?.expect("required");
            Ok(ContactSpec::HertzMindlin {
                young,
                poisson,
                restitution,
                friction,
                normal_force,
                rolling,
            })
        }
        other => Err(FieldError::new(
            field("model"),
            format!("unknown contact model `{other}` (expected `linear` or `hertz_mindlin`)"),
        )),
    }
}

/// The rolling-resistance keys of a contact object (Ai et al. 2011): `rolling_model` (`cdt` or
/// `epsd`) with `rolling_friction` μ_r ≥ 0, and for EPSD an optional `rolling_damping` η_r ≥ 0.
/// None when not given, or when μ_r = 0 (no couple at all).
fn parse_rolling(
    map: &Map<String, Value>,
    path: &str,
    missing_at: &str,
) -> Result<Option<RollingPart>, FieldError> {
    let field = |k: &str| join(path, k);
    let (model, friction, damping) = (
        map.get("rolling_model"),
        map.get("rolling_friction"),
        map.get("rolling_damping"),
    );
    let Some(model) = model else {
        for (k, v) in [("rolling_friction", friction), ("rolling_damping", damping)] {
            if v.is_some() {
                return Err(FieldError::new(
                    field(k),
                    "needs `rolling_model` (`cdt` or `epsd`)",
                ));
            }
        }
        return Ok(None);
    };
    let model = match string(model, &field("rolling_model"))?.as_str() {
        "cdt" => RollingModel::Cdt,
        "epsd" => RollingModel::Epsd,
        other => {
            return Err(FieldError::new(
                field("rolling_model"),
                format!("unknown rolling model `{other}` (expected `cdt` or `epsd`)"),
            ));
        }
    };
    let friction = match friction {
        Some(v) => non_negative(v, &field("rolling_friction"))?,
        None => {
            return Err(FieldError::new(
                join(missing_at, "rolling_friction"),
                "is missing (the coefficient of rolling friction μ_r that `rolling_model` needs)",
            ));
        }
    };
    let damping = match (damping, model) {
        (None, _) => None,
        (Some(_), RollingModel::Cdt) => {
            return Err(FieldError::new(
                field("rolling_damping"),
                "is not a parameter of the `cdt` rolling model (only `epsd` has a rolling dashpot)",
            ));
        }
        (Some(v), RollingModel::Epsd) => Some(non_negative(v, &field("rolling_damping"))?),
    };
    if friction == 0.0 {
        return Ok(None);
    }
    Ok(Some(RollingPart {
        model,
        friction,
        damping,
    }))
}

/// A wall's motion: `"velocity": [vx, vy]` (cm/s), or `"servo": {"stress": σ, "span": S or
/// [a, b], "max_speed": v, "gain": G}` (see `dynamics::boundary`); fixed without either.
fn wall_motion(w: &mut Obj) -> Result<Motion, FieldError> {
    let velocity = w.opt_with("velocity", vec2)?;
    let Some(v) = w.get("servo") else {
        return Ok(velocity.map_or(Motion::Fixed, |v| Motion::Velocity(Vec2::from(v))));
    };
    let at = w.field_path("servo");
    if velocity.is_some() {
        return Err(FieldError::new(
            w.field_path("velocity"),
            "give `velocity` or `servo`, not both (a servo sets the wall's velocity)",
        ));
    }
    let mut o = Obj::new(v, &at)?;
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
    Ok(Motion::Servo(Servo {
        stress,
        span,
        gain,
        max_speed,
    }))
}

/// A servo span between two walls must name two other walls that cross the servo wall's line.
fn check_span(walls: &[Boundary], k: usize, span: &Span) -> Result<(), FieldError> {
    let Span::Between(a, b) = *span else {
        return Ok(());
    };
    let at = format!("{}.servo.span", index("walls", k));
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
        if walls[w].line().normal.dot(&t).abs() < 1e-6 {
            return Err(FieldError::new(
                at,
                format!("wall {w} is parallel to this wall: their lines do not cross"),
            ));
        }
    }
    Ok(())
}

/// `output.analysis_window`: four finite numbers `[x0, x1, y0, y1]` with `x0 < x1`, `y0 < y1`.
fn analysis_window(v: &Value) -> Result<[f64; 4], FieldError> {
    let field = "output.analysis_window";
    let bad = || {
        FieldError::new(
            field,
            format!("must be [x0, x1, y0, y1] (cm) with x0 < x1 and y0 < y1, got {v}"),
        )
    };
    let a = v.as_array().ok_or_else(bad)?;
    if a.len() != 4 {
        return Err(bad());
    }
    let x: Vec<f64> = a.iter().filter_map(Value::as_f64).collect();
    if x.len() != 4 || x.iter().any(|x| !x.is_finite()) || x[0] >= x[1] || x[2] >= x[3] {
        return Err(bad());
    }
    Ok([x[0], x[1], x[2], x[3]])
}
