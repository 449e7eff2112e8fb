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
use super::fields::{
    FieldError, Obj, count, index, join, non_negative, number, object, positive, scale, type_of,
    unknown_field, vec2,
};
use super::materials::{Named, body_density, check_mixing, meeting, read_materials, read_pairs};
use super::ranges::{Placed, SpecContext, check_extent, check_spec, check_steps};
use crate::contact_law::{Check, ContactSpec, Keys, NormalForce, ParamError};
use crate::dynamics::boundary::{BoundaryKind, Program, Stage, StageMotion};
use crate::dynamics::cell::{Cell, PRESSURE_RELAXATION, Periodic, Pressure, SideControl};
use crate::dynamics::neighbour_list::pair_reach;
use crate::dynamics::{BodyInit, Boundary, Flow, Materials, Motion, Servo, Span};
use crate::geometry::{Shape, Vec2};
use serde_json::{Map, Value};

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

/// Checks every contact law a pair that can meet will use: each two materials' that meet
/// (`meets`; the scene's at `contact`, a pair given its own at `pairs[k]`, else at the later
/// material's `materials.<name>`), and each wall's own law against every material of a body,
/// for every density of the scene.
fn check_contact_ranges(
    contact: &ContactSpec,
    named: &Named,
    meets: &[(u16, u16)],
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
    let m = &named.materials;
    // Two bodies of material 0 meet, or one meets a wall of material 0.
    let scene_used = bodies.len() >= 2 && meets.contains(&(0, 0))
        || walls.iter().any(|w| w.material == Some(0)) && bodies.iter().any(|b| b.material == 0);
    for &(a, b) in meets {
        if (a, b) == (0, 0) && !scene_used {
            continue;
        }
        let pair = m.pair(contact, a, b).expect("checked: the pair mixes");
        let at = match m.pairs.iter().position(|p| (p.0, p.1) == (a, b)) {
            Some(k) => index("pairs", k),
            None if b == 0 => "contact".to_string(),
            None => join("materials", &named.names[b as usize - 1]),
        };
        let ctx = SpecContext {
            at: &at,
            rho: rho.clone(),
            g,
        };
        check_spec(&pair.spec, &pair.other, &ctx)?;
    }
    let mut used: Vec<u16> = bodies.iter().map(|b| b.material).collect();
    used.sort_unstable();
    used.dedup();
    for (w, ws) in walls.iter().enumerate() {
        if ws.material.is_some() {
            continue;
        }
        let at = index("walls", w);
        let ctx = SpecContext {
            at: &at,
            rho: rho.clone(),
            g,
        };
        for &b in &used {
            check_spec(&ws.spec, m.spec(contact, b), &ctx)?;
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

/// A wall's contact overrides: every contact key given on the wall replaces the scene's, with
/// the inherited keys it replaces ([`ContactSpec::replaced_by`]); `None` when the wall overrides
/// nothing.
fn wall_overrides(
    w: &mut Obj,
    defaults: &Map<String, Value>,
) -> Result<Option<ContactSpec>, FieldError> {
    let given: Vec<(&str, Value)> = ContactSpec::keys()
        .filter_map(|key| w.get(key).map(|v| (key, v.clone())))
        .collect();
    if given.is_empty() {
        return Ok(None);
    }
    let merged = layered(defaults, given);
    let path = w.path().to_string();
    parse_contact(&merged, &path, &path, true).map(Some)
}

/// The contact object `base` with the keys `given` in place of its own: each given key
/// replaces the keys of `base` it replaces ([`ContactSpec::replaced_by`]).
pub(crate) fn layered(base: &Map<String, Value>, given: Vec<(&str, Value)>) -> Map<String, Value> {
    let mut merged = base.clone();
    for (key, _) in &given {
        for k in ContactSpec::replaced_by(key) {
            merged.remove(k);
        }
    }
    for (key, v) in given {
        merged.insert(key.to_string(), v);
    }
    merged
}

/// The contact object, each part reading its keys ([`ContactSpec::parse`]). `path` prefixes
/// field paths; `missing_at` is where a missing field is reported; `note`: record every
/// contact key as one this object takes (see `fields::keys_asked_during`; a material's and a
/// pair's reader records the keys they take).
pub(crate) fn parse_contact(
    map: &Map<String, Value>,
    path: &str,
    missing_at: &str,
    note: bool,
) -> Result<ContactSpec, FieldError> {
    let keys: Vec<&str> = ContactSpec::keys().collect();
    if note {
        for k in &keys {
            super::fields::note_key(path, k);
        }
    }
    for k in map.keys() {
        if !keys.contains(&k.as_str()) {
            return Err(FieldError::new(join(path, k), unknown_field(k, &keys)));
        }
    }
    let keys = ContactKeys {
        map,
        path,
        missing_at,
    };
    ContactSpec::parse(&keys).map_err(|e| FieldError::new(e.field, e.message))
}

/// A contact object's keys as the law's parts read them ([`Keys`]).
struct ContactKeys<'a> {
    map: &'a Map<String, Value>,
    path: &'a str,
    missing_at: &'a str,
}

impl Keys for ContactKeys<'_> {
    fn has(&self, key: &str) -> bool {
        self.map.contains_key(key)
    }

    fn string(&self, key: &str) -> Result<Option<String>, ParamError> {
        self.map
            .get(key)
            .map(|v| string(v, &join(self.path, key)))
            .transpose()
            .map_err(param_error)
    }

    fn number(&self, key: &str, check: Check) -> Result<Option<f64>, ParamError> {
        let read: fn(&Value, &str) -> Result<f64, FieldError> = match check {
            Check::Any => number,
            Check::NonNegative => non_negative,
            Check::Positive => positive,
            Check::Scale => scale,
        };
        self.map
            .get(key)
            .map(|v| read(v, &join(self.path, key)))
            .transpose()
            .map_err(param_error)
    }

    fn error(&self, key: &str, message: String) -> ParamError {
        ParamError {
            field: join(self.path, key),
            message,
        }
    }

    fn missing(&self, key: &str, message: String) -> ParamError {
        ParamError {
            field: join(self.missing_at, key),
            message,
        }
    }
}

fn param_error(e: FieldError) -> ParamError {
    ParamError {
        field: e.path,
        message: e.message,
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

/// The periodic cell (see [`Case::cell`]): its size against the bodies' reach, no wall across a
/// periodic direction, shear and pressure only in a cell periodic in x and y, no gravity there.
/// The most a strain rate may stretch a cell's side in one step.
const MAX_STRAIN_PER_STEP: f64 = 0.01;

fn parse_cell(
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

/// A wall's motion: `"velocity": [vx, vy]` (cm/s), or `"servo": {"stress": σ, "span": S or
/// [a, b], "max_speed": v, "gain": G}`, or `"motion": [stage, …]` (a program, each stage
/// `{"until": t, "velocity": [vx, vy]}` or `{"until": t, "servo": {…}}`, the last may omit
/// `until`; see `dynamics::boundary`); fixed without any. `dt` places the stages' ends on steps.
fn wall_motion(w: &mut Obj, dt: f64) -> Result<Motion, FieldError> {
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
struct Turning {
    rate: Option<f64>,
    pivot: Option<[f64; 2]>,
}

/// Reads a wall's [`Turning`] keys.
fn wall_turning(w: &mut Obj) -> Result<Turning, FieldError> {
    Ok(Turning {
        rate: w.opt_with("angular_velocity", number)?,
        pivot: w.opt_with("pivot", vec2)?,
    })
}

/// A servo object `{"stress": σ, "span": S or [a, b], "max_speed": v, "gain": G}` at `at`.
fn servo_of(v: &Value, at: &str) -> Result<Servo, FieldError> {
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
fn program(v: &Value, path: &str, dt: f64) -> Result<Program, FieldError> {
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
fn check_span(walls: &[Boundary], k: usize, span: &Span, at: &str) -> Result<(), FieldError> {
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

/// Refuses cohesion against a drum or a segment wall for a body that is not a disk (nor a
/// clump, whose members are disks): a disk's overlap with them has a closed form (a drum: the
/// disk's part beyond the circle, `πr² − lens`; a segment: the half-plane's cap over the face,
/// the cap at the same depth at an end), an ellipse's or a polygon's has none that the kernels
/// give for every contact, so the pull `c ℓ` and its energy `−c A` would have no chord to act on
/// (see `contact_law::cohesion`). The error names the key that gives the pair its cohesion: the
/// wall's own `cohesion`, its material's, or the scene's.
fn check_cohesion_boundaries(
    walls: &[Boundary],
    bodies: &[BodyInit],
    named: &Named,
    (contact, contact_map): (&ContactSpec, &Map<String, Value>),
    items: Option<&Value>,
) -> Result<(), FieldError> {
    for (k, w) in walls.iter().enumerate() {
        let kind = match (w.drum(), w.segment()) {
            (Some(_), _) => "a drum",
            (None, Some(_)) => "a segment wall",
            (None, None) => continue,
        };
        let own = items
            .and_then(|v| v.get(k))
            .is_some_and(|item| item.get("cohesion").is_some());
        // The first body that is not made of disks and meets this wall with cohesion.
        let offending = bodies.iter().enumerate().find(|(_, b)| {
            !matches!(b.shape, Shape::Circle { .. } | Shape::Clump(_))
                && match w.material {
                    None => w.spec.cohesion.is_some(),
                    Some(a) => named
                        .materials
                        .pair(contact, a, b.material)
                        .is_ok_and(|p| p.spec.cohesion.is_some()),
                }
        });
        let Some((i, body)) = offending else {
            continue;
        };
        let at = if own {
            join(&index("walls", k), "cohesion")
        } else {
            match w.material {
                Some(m) if m != 0 && named.map(contact_map, m).contains_key("cohesion") => {
                    join(&named.path(m), "cohesion")
                }
                _ => "contact.cohesion".to_string(),
            }
        };
        return Err(FieldError::new(
            at,
            format!(
                "cohesion is not available against {kind} (walls[{k}]) for bodies[{i}], of shape \
                 `{}`: only disks and clumps have a closed-form overlap area with it to pull on; give \
                 that wall a law without it (its own `\"cohesion\": 0`, or a material without \
                 cohesion)",
                body.shape.type_name()
            ),
        ));
    }
    Ok(())
}
