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
//! Shapes (`bodies[].shape`, [`super::body`]): `{"type": "circle", "r"}`, `{"type": "ellipse",
//! "a", "b"}`, `{"type": "rectangle", "w", "h"}`, `{"type": "polygon", "vertices": [[x, y], …]}`
//! (convex, counter-clockwise, at most 1000) and `{"type": "clump", "disks": [{"center": [x, y],
//! "r"}, …]}`. Unknown fields are errors (naming what was likely meant and the valid keys); a
//! state file's `"state"` block is read by [`super::state`]. `contact.model` is `linear`
//! (stiffness `kn` or `kn_over_rho_g`;
//! `ks`/`ks_over_rho_g`, default equal to the normal one as in P; damping `eta_n`/
//! `eta_n_over_rho_g` with `eta_s`/`eta_s_over_rho_g` defaulting to it (T: η_t = η_n), or
//! `restitution` instead (T12); `friction`) or `hertz_mindlin` (`young`, `poisson`,
//! `restitution`, `friction`; T10–T20). A wall may override any contact parameter.

use super::body::{WallGeometry, parse_body_with, parse_wall_or_segment_with};
use super::cell::parse_cell;
use super::contact::{parse_contact, wall_overrides};
use super::fields::{FieldError, Obj, count, index, join, number, positive, scale, type_of, vec2};
use super::fields::{boolean, string};
use super::law_checks::{check_cohesion_boundaries, check_contact_ranges};
use super::materials::{body_density, check_mixing, meeting, read_materials, read_pairs};
use super::ranges::{Placed, check_extent, check_steps};
use super::walls::{Turning, check_span, check_walls, wall_motion, wall_turning};
use crate::contact_law::{ContactSpec, NormalForce};
use crate::dynamics::boundary::{BoundaryKind, StageMotion};
use crate::dynamics::cell::Cell;
use crate::dynamics::{BodyInit, Boundary, Flow, Materials, Motion};
use crate::geometry::Vec2;
use serde_json::Value;

/// The densest material, in g/cm³ (osmium, 22.6, rounded up): a denser body is most likely given
/// in kg/m³ ([`Case::warnings`]).
pub const DENSEST_MATERIAL: f64 = 30.0;

/// A scene as a case file describes it.
#[derive(Clone, Debug, PartialEq)]
pub struct Case {
    pub name: String,
    pub description: String,
    /// The length unit, for the plots' labels only: `"cm"` or empty (absent). dem2d works in
    /// cgs; any other unit is refused, since nothing would convert it (issue 41: `"m"` was
    /// accepted and ignored).
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
    /// The case's named materials (`materials`, material k + 1 named `material_names[k]`) and
    /// the pairs given their own law (`pairs`); material 0 is `contact`.
    pub materials: Materials,
    pub material_names: Vec<String>,
    pub walls: Vec<Boundary>,
    pub bodies: Vec<BodyInit>,
    /// The periodic cell the scene repeats in (`"cell": {"size": [L_x, L_y], "periodic": "x" |
    /// "xy", "shear_rate": γ̇, "pressure": P, "pressure_gain": α}`; see `dynamics::cell`).
    pub cell: Option<Cell>,
    /// Insertion and outflow regions (`insert`, `outflow`; see [`crate::dynamics::flow`]).
    pub flow: Option<Flow>,
    /// Cundall's local non-viscous damping coefficient α (`"damping": {"local": α}`, in [0, 1);
    /// 0, the default: off; see `dynamics::local_damping`).
    pub local_damping: f64,
    /// The energy audit's threshold (`"energy_audit"`, a fraction of the energy the run has had
    /// in motion; [`crate::run::audit`]).
    pub energy_audit: f64,
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
        if !units.is_empty() && units != "cm" {
            return Err(FieldError::new(
                "units",
                format!(
                    "dem2d works in cgs (lengths in cm, masses in g, times in s) and converts \
                     nothing: `units` may only be \"cm\" (or left out), got {units:?}; give every \
                     length in cm, densities in g/cm³ and gravity in cm/s² ([0, -980])"
                ),
            ));
        }
        let gravity = Vec2::from(o.req_with("gravity", vec2)?);
        let dt = o.req_with("dt", scale)?;
        let duration = o.req_with("duration", scale)?;
        let quiescence = o.opt_with("quiescence", positive)?;
        let quiescence_window = o.opt_with("quiescence_window", count)?.unwrap_or(1);
        let output_every = o.opt_with("output_every", count)?.unwrap_or(100);
        let energy_audit = o
            .opt_with("energy_audit", positive)?
            .unwrap_or(crate::run::audit::DEFAULT_THRESHOLD);
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
        let contact = parse_contact(&contact_map, "contact", "contact", true)?;
        let mut named = read_materials(o.get("materials"), &contact_map)?;
        read_pairs(o.get("pairs"), &mut named, (&contact, &contact_map))?;
        let mut walls = Vec::new();
        let wall_items = o.get("walls");
        if let Some(list) = wall_items {
            let items = list.as_array().ok_or_else(|| {
                FieldError::new("walls", format!("must be an array, got {}", type_of(list)))
            })?;
            let mut spans = Vec::new();
            for (k, item) in items.iter().enumerate() {
                let path = index("walls", k);
                let (wall, (spec, motion, material, turning)) =
                    parse_wall_or_segment_with(item, &path, |w| {
                        let material = w.opt_with("material", |v, p| named.index_of(v, p))?;
                        let spec = wall_overrides(w, &contact_map)?;
                        if material.is_some() && spec.is_some() {
                            return Err(FieldError::new(
                                w.field_path("material"),
                                "give the wall a `material` or contact keys of its own, not both",
                            ));
                        }
                        let turning = wall_turning(w)?;
                        Ok((spec, wall_motion(w, dt)?, material, turning))
                    })?;
                match &motion {
                    Motion::Servo(s) => spans.push((k, s.span, format!("{path}.servo.span"))),
                    Motion::Program(p) => {
                        for (i, st) in p.stages.iter().enumerate() {
                            if let StageMotion::Servo(s) = st.motion {
                                spans.push((k, s.span, format!("{path}.motion[{i}].servo.span")));
                            }
                        }
                    }
                    Motion::Fixed | Motion::Velocity(_) => {}
                }
                let kind = match wall {
                    WallGeometry::HalfPlane(w) => BoundaryKind::Wall(w),
                    WallGeometry::Segment(s) => {
                        if let Some((_, _, at)) = spans.iter().find(|(w, ..)| *w == k) {
                            return Err(FieldError::new(
                                at.trim_end_matches(".span").to_string(),
                                "a servo moves a half-plane wall (`point`, `normal`); a segment \
                                 wall moves at a `velocity` or by a `motion` program of velocity \
                                 stages",
                            ));
                        }
                        BoundaryKind::Segment(s)
                    }
                    WallGeometry::Drum(d) => {
                        if let Some((_, _, at)) = spans.iter().find(|(w, ..)| *w == k) {
                            return Err(FieldError::new(
                                at.trim_end_matches(".span").to_string(),
                                "a servo moves a half-plane wall (`point`, `normal`); a drum \
                                 turns at an `angular_velocity` (or by a `motion` program)",
                            ));
                        }
                        BoundaryKind::drum(d)
                    }
                };
                let stages_turn = match &motion {
                    Motion::Program(p) => p.stages.iter().any(|s| s.angular_velocity != 0.0),
                    _ => false,
                };
                let drum = matches!(kind, BoundaryKind::Drum(..));
                match (turning, drum) {
                    (Turning { pivot: Some(_), .. }, true) => {
                        return Err(FieldError::new(
                            join(&path, "pivot"),
                            "a drum turns about its centre: give it no `pivot`",
                        ));
                    }
                    (Turning { rate, pivot: None }, false) if rate.is_some() || stages_turn => {
                        return Err(FieldError::new(
                            join(&path, "pivot"),
                            "is missing: a turning wall or segment turns about its `pivot` \
                             [x, y]",
                        ));
                    }
                    (
                        Turning {
                            rate: None,
                            pivot: Some(_),
                        },
                        false,
                    ) if !stages_turn => {
                        return Err(FieldError::new(
                            join(&path, "pivot"),
                            "is given, but the wall does not turn: give its \
                             `angular_velocity` (or stages with one in `motion`)",
                        ));
                    }
                    _ => {}
                }
                if turning.rate.is_some() && matches!(motion, Motion::Program(_)) {
                    return Err(FieldError::new(
                        join(&path, "angular_velocity"),
                        "give `motion` (its stages with their `angular_velocity`) or the wall's \
                         own `angular_velocity`, not both",
                    ));
                }
                if turning.rate.is_some() && matches!(motion, Motion::Servo(_)) {
                    return Err(FieldError::new(
                        join(&path, "angular_velocity"),
                        "a servo moves a half-plane along its normal: give `servo` or \
                         `angular_velocity`, not both",
                    ));
                }
                let turns = drum || turning.rate.is_some() || stages_turn;
                let mut boundary = Boundary::of_kind(kind, spec.unwrap_or(contact), motion);
                if turns {
                    boundary = boundary.turning(
                        turning.pivot.map_or(Vec2::zeros(), Vec2::from),
                        turning.rate.unwrap_or(0.0),
                    );
                }
                walls.push(match (spec, material) {
                    // A wall of its own law.
                    (Some(_), _) => boundary,
                    (None, m) => {
                        let m = m.unwrap_or(0);
                        boundary.of_material(m, *named.materials.spec(&contact, m))
                    }
                });
            }
            for (k, span, at) in spans {
                check_span(&walls, k, &span, &at)?;
            }
        }
        let list = o.req("bodies")?;
        let items = list.as_array().ok_or_else(|| {
            FieldError::new("bodies", format!("must be an array, got {}", type_of(list)))
        })?;
        if items.is_empty() && !o.has("insert") {
            return Err(FieldError::new(
                "bodies",
                "must list at least one body (or the case must `insert` some)",
            ));
        }
        let mut bodies = Vec::with_capacity(items.len());
        for (k, item) in items.iter().enumerate() {
            let path = index("bodies", k);
            let mut b = Obj::new(item, &path)?;
            let (shape, pose, (velocity, omega, density, material, prescribed)) =
                parse_body_with(&mut b, |b| {
                    let velocity = b.opt_with("velocity", vec2)?.unwrap_or([0.0, 0.0]);
                    let omega = b.opt_with("omega", number)?.unwrap_or(0.0);
                    let density = b.opt_with("density", scale)?;
                    let material = b
                        .opt_with("material", |v, p| named.index_of(v, p))?
                        .unwrap_or(0);
                    let prescribed = prescribed_motion(b, velocity, omega)?;
                    Ok((velocity, omega, density, material, prescribed))
                })?;
            b.finish()?;
            let density = body_density(&named, material, density, &path)?;
            bodies.push(BodyInit {
                material,
                prescribed,
                shape,
                position: pose.position,
                angle: pose.angle(),
                velocity: Vec2::from(velocity),
                omega,
                density,
            });
        }
        let cell = match o.get("cell") {
            None => None,
            Some(v) => Some(parse_cell(v, &walls, &bodies, gravity, dt)?),
        };
        let (insert, outflow) = (o.get("insert"), o.get("outflow"));
        let flow = super::flow::parse_flow(insert, outflow, &named, &bodies)?;
        if let Some(f) = &flow {
            super::flow::check_regions_clear_of_walls(f, &walls)?;
            super::flow::check_bodies_per_step(f, dt)?;
        }
        let local_damping = match o.get("damping") {
            None => 0.0,
            Some(v) => parse_damping(v)?,
        };
        // A state file's block (read by `scene::state`, which continues the run from it).
        let _ = o.get("state");
        o.finish()?;
        // The inserters' bodies are checked as the case's are (sizes, materials, ranges).
        let templates = flow
            .as_ref()
            .map(super::flow::templates)
            .unwrap_or_default();
        let checked: Vec<BodyInit> = bodies.iter().chain(&templates).copied().collect();
        check_steps(duration, dt)?;
        let mut placed: Vec<Placed> = checked
            .iter()
            .enumerate()
            .map(|(k, b)| Placed::Body {
                path: match k.checked_sub(bodies.len()) {
                    None => index("bodies", k),
                    Some(i) => join(&index("insert", i), "size"),
                },
                shape: &b.shape,
                position: b.position,
            })
            .collect();
        for (w, ws) in walls.iter().enumerate() {
            if let Some(d) = ws.drum() {
                placed.extend(super::body::drum_extent(
                    d,
                    &join(&index("walls", w), "drum"),
                ));
                continue;
            }
            match ws.segment() {
                None => placed.push(Placed::Wall {
                    path: index("walls", w),
                    point: ws.line().point,
                }),
                Some(s) => {
                    placed.extend(
                        [s.a, s.b]
                            .iter()
                            .enumerate()
                            .map(|(k, &point)| Placed::Wall {
                                path: format!("{}.segment[{k}]", index("walls", w)),
                                point,
                            }),
                    )
                }
            }
        }
        if let Some(c) = &cell {
            // The cell's far corner, as far out as a body may be.
            placed.push(Placed::Point {
                path: "cell.size".into(),
                point: c.size,
            });
        }
        check_extent(&placed)?;
        check_walls(&walls, &bodies)?;
        let meets = meeting(&checked, &walls);
        check_mixing(&named, (&contact, &contact_map), &meets)?;
        check_cohesion_boundaries(
            &walls,
            &checked,
            &named,
            (&contact, &contact_map),
            wall_items,
        )?;
        check_contact_ranges(&contact, &named, &meets, &walls, &checked, gravity)?;
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
            materials: named.materials,
            material_names: named.names,
            walls,
            bodies,
            cell,
            flow,
            local_damping,
            energy_audit,
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
            materials: Materials::default(),
            material_names: Vec::new(),
            walls,
            bodies,
            cell: None,
            flow: None,
            local_damping: 0.0,
            energy_audit: crate::run::audit::DEFAULT_THRESHOLD,
        }
    }

    /// The same case in the periodic cell `cell` (unchecked, as [`Case::new`]).
    pub fn with_cell(mut self, cell: Cell) -> Case {
        self.cell = Some(cell);
        self
    }

    /// The world this case describes, at t = 0 (the forces of the initial configuration
    /// evaluated).
    pub fn build_world(&self) -> crate::dynamics::World {
        let world = crate::dynamics::World::of_scene(self.scene());
        let mut world = match self.cell {
            Some(cell) => world.with_cell(cell).0,
            None => world,
        };
        world.local_damping = self.local_damping;
        match &self.flow {
            Some(flow) => world.with_flow(flow.clone(), None),
            None => world,
        }
    }

    /// How many bodies lie outside the case's periodic cell (they are brought into it when the
    /// world is built: see `dynamics::World::with_cell`).
    pub fn bodies_outside_cell(&self) -> usize {
        self.cell.map_or(0, |c| {
            self.bodies
                .iter()
                .filter(|b| c.wrap(b.position, b.velocity).is_some())
                .count()
        })
    }

    /// The world of this case resumed from `state` (a state file's, taken of a world of this
    /// case): it steps on to the same bits as the world the state was taken from. Refused when
    /// the state does not fit the case.
    pub fn resume_world(
        &self,
        state: &crate::dynamics::RestartState,
    ) -> Result<crate::dynamics::World, crate::dynamics::RestartError> {
        let mut world = crate::dynamics::World::resume(self.scene(), state)?;
        world.local_damping = self.local_damping;
        Ok(match &self.flow {
            Some(flow) => world.with_flow(flow.clone(), state.flow.as_ref()),
            None => world,
        })
    }

    /// What the case's world is made of.
    pub fn scene(&self) -> crate::dynamics::Scene<'_> {
        crate::dynamics::Scene {
            bodies: &self.bodies,
            walls: self.walls.clone(),
            gravity: self.gravity,
            spec: self.contact,
            materials: self.materials.clone(),
            dt: self.dt,
        }
    }

    /// The same case stepped with `dt`.
    pub fn with_dt(mut self, dt: f64) -> Case {
        self.dt = dt;
        self
    }

    /// The same case with every contact law (the scene's, each material's, each pair's and
    /// each wall's) changed by `f`.
    pub fn map_contacts(mut self, f: impl Fn(ContactSpec) -> ContactSpec) -> Case {
        self.contact = f(self.contact);
        for s in &mut self.materials.specs {
            *s = f(*s);
        }
        for p in &mut self.materials.pairs {
            p.2 = f(p.2);
        }
        for w in &mut self.walls {
            w.spec = f(w.spec);
        }
        self
    }

    /// The same case with every contact (the scene's and each wall's) under `normal_force`.
    pub fn with_normal_force(self, normal_force: NormalForce) -> Case {
        self.map_contacts(|c| c.with_normal_force(normal_force))
    }

    /// P's quiescence criterion as the case states it (None: no stop at rest).
    pub fn quiescence_criterion(&self) -> Option<crate::run::Quiescence> {
        self.quiescence
            .map(|q| crate::run::Quiescence::new(q, self.quiescence_window))
    }

    /// The a-priori critical time step of the scene ([`estimate_critical_dt_of`]): of the
    /// case's bodies and of the bodies its inserters can make (each inserter's smallest and
    /// largest size at its smallest and largest aspect ratio: [`super::flow::extremes`]), so
    /// that a scene filled by insertion gets an estimate (it was `inf`, and the Δt warning never
    /// came: issue 41).
    ///
    /// [`estimate_critical_dt_of`]: crate::dynamics::timestep::estimate_critical_dt_of
    pub fn critical_dt(&self) -> f64 {
        use crate::dynamics::body::Bodies;
        use crate::dynamics::materials::PairTable;
        let extra = self
            .flow
            .as_ref()
            .map(super::flow::extremes)
            .unwrap_or_default();
        let inits: Vec<BodyInit> = self.bodies.iter().chain(&extra).copied().collect();
        let pairs = PairTable::new(&self.contact, &self.materials, &self.walls);
        crate::dynamics::timestep::estimate_critical_dt_of(
            &Bodies::new(&inits),
            &pairs,
            &self.walls,
            self.gravity.norm(),
        )
    }

    /// What is worth telling about the case before it runs (every command that runs it prints
    /// these, and `summary.json` lists them; the Python module's `Case.warnings`):
    /// - `dt` above the a-priori critical step ([`Case::critical_dt`]);
    /// - gravity of Earth's magnitude in m/s² (|g| in 9–11: dem2d is cgs, where it is 980
    ///   cm/s²), or a body denser than any material (above [`DENSEST_MATERIAL`] g/cm³: a density
    ///   in kg/m³?), each naming the largest size too (in cm). A size alone cannot tell SI from
    ///   cgs (0.005 is a 50 µm powder grain in cm): it is named beside these.
    pub fn warnings(&self) -> Vec<String> {
        let mut out = Vec::new();
        let dt_critical = self.critical_dt();
        if self.dt > dt_critical {
            out.push(format!(
                "dt = {:e} exceeds the critical time step estimated from the stiffest possible contact, {:.3e} \
                 (damping, rotational inertia and lever arms included): the explicit scheme may oscillate or blow up",
                self.dt, dt_critical
            ));
        }
        let extra = self
            .flow
            .as_ref()
            .map(super::flow::extremes)
            .unwrap_or_default();
        let all: Vec<(String, &BodyInit)> = self
            .bodies
            .iter()
            .enumerate()
            .map(|(k, b)| (index("bodies", k), b))
            .chain(
                extra
                    .iter()
                    .enumerate()
                    .map(|(k, b)| (index("insert", k / 4), b)),
            )
            .collect();
        let largest = all
            .iter()
            .map(|(_, b)| b.shape.bounding_radius())
            .fold(0.0, f64::max);
        // (Three significant digits, written plainly: 1.5, 0.424, 2e-5.)
        let largest: f64 = format!("{largest:.2e}").parse().unwrap_or(largest);
        let sizes = format!(
            "sizes and positions are read in cm too (the largest body here reaches {largest} cm \
             from its centre)"
        );
        let g = self.gravity.norm();
        if (9.0..=11.0).contains(&g) {
            out.push(format!(
                "gravity of magnitude {g} cm/s² is Earth's in m/s²: dem2d works in cgs, where \
                 it is about 980 cm/s² (\"gravity\": [0, -980]); {sizes}"
            ));
        }
        if let Some((at, b)) = all
            .iter()
            .filter(|(_, b)| b.density > DENSEST_MATERIAL)
            .max_by(|x, y| x.1.density.total_cmp(&y.1.density))
        {
            out.push(format!(
                "{at} has a density of {} g/cm³, denser than any material (osmium: 22.6 \
                 g/cm³): a density in kg/m³? dem2d works in cgs, where {} kg/m³ is {} g/cm³; \
                 {sizes}",
                b.density,
                b.density,
                b.density / 1000.0
            ));
        }
        out
    }

    /// Number of steps the duration takes (rounded to the nearest step).
    pub fn steps(&self) -> u64 {
        (self.duration / self.dt).round().max(1.0) as u64
    }
}

/// Cundall's local damping (`"damping": {"local": α}`, see [`Case::local_damping`]): α in
/// [0, 1) (at 1 a body moving away from rest would feel no force; above, a force pushing it on).
fn parse_damping(v: &Value) -> Result<f64, FieldError> {
    let mut d = Obj::new(v, "damping")?;
    let alpha = d.req_with("local", number)?;
    d.finish()?;
    if !(0.0..1.0).contains(&alpha) {
        return Err(FieldError::new(
            "damping.local",
            format!(
                "must be in [0, 1) (Cundall's local damping: the fraction of a body's unbalanced \
                 force turned against its motion), got {alpha}"
            ),
        ));
    }
    Ok(alpha)
}

/// Whether a body's motion is prescribed: `"fixed": true` (at rest: a velocity or spin given
/// with it must be zero) or `"prescribed": true` (at its `velocity` and `omega`), not both.
fn prescribed_motion(b: &mut Obj, velocity: [f64; 2], omega: f64) -> Result<bool, FieldError> {
    let fixed = b.opt_with("fixed", boolean)?.unwrap_or(false);
    let prescribed = b.opt_with("prescribed", boolean)?.unwrap_or(false);
    if fixed && prescribed {
        return Err(FieldError::new(
            b.field_path("prescribed"),
            "give `fixed` (at rest) or `prescribed` (at its `velocity` and `omega`), not both",
        ));
    }
    if fixed && (velocity != [0.0, 0.0] || omega != 0.0) {
        let key = if omega != 0.0 { "omega" } else { "velocity" };
        return Err(FieldError::new(
            b.field_path(key),
            "a fixed body does not move: give `\"prescribed\": true` instead of `fixed` to move \
             it at its `velocity` and `omega`",
        ));
    }
    Ok(fixed || prescribed)
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
