//! Contact laws: the force between two bodies from the contact record, the relative velocity at
//! the contact point, the pair's effective mass and radius, and the contact's history.
//! A law never sees a shape.
//!
//! # A law is composed of parts
//! As LAMMPS's granular model, a [`Law`] is assembled from parts, each in its own file, each
//! returning its force or couple and its stiffness (the critical-step estimate asks the parts,
//! [`Law::modes`]):
//! - [`normal`]: the spring (linear on δ, or Hertz), on the overlap the [`NormalForce`] choice
//!   gives it (the depth, or the area potential's equivalent overlap);
//! - [`damping`]: the normal and shear dashpots (given, or from a restitution coefficient);
//! - [`tangential`]: the shear spring and Coulomb's slider, written once for every spring;
//! - [`rolling`] (optional): the rolling-resistance couple (Ai et al. 2011's CDT or EPSD);
//! - [`cohesion`] (optional): a pull `c ℓ` on the overlap chord, the gradient of `−c A`.
//!
//! Each part owns its parameters and its per-contact history, as LAMMPS's granular sub-models
//! do: it reads its own keys from the case's contact object through [`Keys`] (the core never
//! sees JSON: the scene implements it), resolves them for a pair, and declares the history
//! values its contacts carry (their names in a restart file): the [`Part`] trait. This file is
//! the one place where the parts are registered: [`ContactSpec`] lists them once (its keys,
//! `given`, `mix`, `mixed_keys` and the history's layout, [`History`], are generated from the
//! list), [`ContactSpec::parse`], [`ContactSpec::resolve`], [`Law`] and [`Law::force`] (the
//! parts in order). Every reader of a spec or a law destructures it, so adding a part touches
//! its file and this one, and the compiler names every place here that must handle it.
//! A case names a model (`linear`, `hertz_mindlin`: the normal part's key, which the damping
//! and tangential parts follow) with its parameters, plus the optional rolling keys.
//!
//! Conventions: `n` points from i to j; `t = (−n_y, n_x)` (n turned a quarter counter-clockwise);
//! the relative velocity is that of j's material point minus i's, at the contact point, with
//! components `v_n` (negative when approaching) and `v_t`. The force on j is `F_n n + F_t t`, on
//! i its opposite; `F_n ≥ 0` always (a contact pushes, never pulls) but for the [`cohesion`]
//! part's pull.
//!
//! T writes the Voigt element for the force on i with `n_ij` pointing from j to i and the overlap
//! negative (T6–T9); with our n (i → j) and δ > 0 the same law reads `F_n = k_n δ − η_n v_n` for
//! the force on j.
//!
//! # What the normal spring acts on ([`NormalForce`])
//! - **Depth** (P's model): the spring acts on the depth δ along the chord normal, at the chord
//!   midpoint. For non-circular bodies this force is not the gradient of any potential: a
//!   closed loop of configurations gains or loses work (of order δ/a per collision).
//! - **Area** (the energy-conserving contact of Feng, Han & Owen 2012): the normal force derives
//!   from a potential `W(A)` of the overlap area A. Moving j changes A by `−L n·du` (L the chord
//!   length), so `−∇W` is the force `W′(A) L` along P's chord normal at P's chord midpoint — the
//!   same geometry, another magnitude. `W` keeps the stiffness parameters' meaning: with
//!   `δ_eq(A)` the overlap of two disks of the bodies' equal-area radii whose lens has area A
//!   (and `L_eq = dA/dδ_eq` that lens's chord), `W = ∫F_s(δ_eq) dδ_eq` with `F_s` the law's
//!   spring (`k_n δ`, or Hertz), so two disks get exactly the spring on their depth. Then
//!   `F_n = ρ F_s(δ_eq) + η δ̇_eq` with `ρ = L/L_eq` and `δ̇_eq = Ȧ/L_eq = −ρ v_n`: the law
//!   evaluated at the equivalent overlap, scaled by ρ. The dashpot acts on the same overlap's
//!   rate with the coefficient η/ρ, so that the damping ratio, and hence a requested
//!   restitution, is that of the spring on the depth for any ρ (a smooth contact whose true
//!   radius of curvature is R*_t has ρ ≈ (R*_t/R*_eq)^{1/3} and stiffness `k_n ρ²` against its
//!   depth). See [`EquivalentOverlap`] for two flat faces.

pub mod cohesion;
pub mod damping;
pub mod force;
pub mod keys;
pub mod kinematics;
pub mod mixing;
pub mod normal;
pub mod overlap;
pub mod params;
pub mod part;
pub mod rolling;
pub mod tangential;

pub use cohesion::{CohesionKinematics, CohesionPart};
pub use damping::{
    DampingPart, DampingSpec, LinearDamping, damping_factor_hertz, damping_ratio_linear,
};
pub use force::ContactForce;
pub use keys::{Check, Given, Keys, ParamError};
pub use kinematics::{AreaKinematics, EquivalentOverlap, Kinematics, SpringOverlap};
pub use mixing::MixError;
pub use normal::{NormalForce, NormalPart, NormalSpec, NormalSpring, SpringSpec};
pub use overlap::{PairFacts, SpringOn};
pub use params::Scaled;
pub use part::Part;
pub use rolling::{RollingKinematics, RollingModel, RollingPart};
pub use tangential::{ShearSpec, ShearStiffness, TangentialPart, TangentialSpec};

/// Where each part's history values sit in a contact's [`History`]: the parts' in the order of
/// [`ContactSpec`]'s fields (each part declares how many, and their names: [`Part::HISTORY`]),
/// so the tangential part's first, then the rolling part's.
const AT_TANGENTIAL: usize = history_at(PartField::tangential as usize);
const AT_ROLLING: usize = history_at(PartField::rolling as usize);

/// How many history values a contact can carry: every part's.
pub const HISTORY_LEN: usize = history_at(PART_HISTORIES.len());

/// Where the history of the `k`-th part of [`ContactSpec`] starts: the count of every earlier
/// part's values.
const fn history_at(k: usize) -> usize {
    let mut at = 0;
    let mut p = 0;
    while p < k {
        at += PART_HISTORIES[p].len();
        p += 1;
    }
    at
}

/// The per-contact state carried from step to step while the contact lasts (T16), every part's
/// values at its place (dropped when the contact ends): the shear spring's elongation along the
/// current tangent `t` (in 2D the tangent plane is a line, so a scalar along `t` is the
/// displacement "kept in the current tangent direction as the contact rotates"), then EPSD's
/// rolling spring moment.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct History(pub [f64; HISTORY_LEN]);

/// How many leading [`History`] values a law with these parts keeps: the tangential part's
/// always (the slot holds it), the rolling part's where it keeps a spring.
fn history_kept(rolling: Option<RollingPart>) -> usize {
    match rolling {
        Some(r) if r.keeps_history() => HISTORY_LEN,
        Some(_) | None => AT_ROLLING,
    }
}

impl History {
    /// The name of each value, as a restart file writes it: every part's [`Part::HISTORY`], in
    /// order.
    pub const NAMES: [&str; HISTORY_LEN] = {
        let mut names = [""; HISTORY_LEN];
        let (mut k, mut p) = (0, 0);
        while p < PART_HISTORIES.len() {
            let mut i = 0;
            while i < PART_HISTORIES[p].len() {
                names[k] = PART_HISTORIES[p][i];
                k += 1;
                i += 1;
            }
            p += 1;
        }
        names
    };
}

/// Declares [`ContactSpec`] from its list of parts (each a field of a type that implements
/// [`Part`]) and everything that visits every part.
macro_rules! parts {
    ($(#[$meta:meta])* pub struct ContactSpec { $($(#[$doc:meta])* $field:ident: $part:ty,)* }) => {
        $(#[$meta])*
        pub struct ContactSpec {
            $($(#[$doc])* pub $field: $part,)*
        }

        /// The parts by their field's name, numbered in order (for the history's layout).
        #[allow(non_camel_case_types, dead_code)]
        enum PartField {
            $($field),*
        }

        /// Each part's [`Part::HISTORY`], in the order of [`ContactSpec`]'s fields.
        const PART_HISTORIES: &[&[&str]] = &[$(<$part as Part>::HISTORY),*];

        impl ContactSpec {
            /// Every key of a contact object, each part's.
            pub fn keys() -> impl Iterator<Item = &'static str> {
                [$(<$part as Part>::KEYS),*].into_iter().flatten().copied()
            }

            /// The keys a wall's override `key` replaces in the scene's contact object it
            /// inherits: every key for `model` (a wall naming a model starts afresh), else each
            /// part's rule ([`Part::replaced_by`]).
            pub fn replaced_by(key: &str) -> Vec<&'static str> {
                if key == "model" {
                    return Self::keys().collect();
                }
                [$(<$part as Part>::replaced_by(key)),*].into_iter().flatten().copied().collect()
            }

            /// Every key of the spec as a case file gives it (what [`ContactSpec::parse`] reads
            /// back to the same spec), each part's.
            pub fn given(&self) -> Vec<(&'static str, Given)> {
                let mut keys = Vec::new();
                $(keys.extend(self.$field.given());)*
                keys
            }

            /// The parameters of contacts between the materials `self` and `other` by each
            /// part's rule ([`mixing`]; the model and the normal force are `self`'s: a case's
            /// materials share the scene's). A material with itself keeps its own spec.
            pub fn mix(&self, other: &ContactSpec) -> Result<ContactSpec, MixError> {
                if self == other {
                    return Ok(*self);
                }
                Ok(ContactSpec {
                    $($field: self.$field.mix(&other.$field)?,)*
                })
            }

            /// The keys of contacts between the materials `self` and `other`, part by part: each
            /// part's mixed keys, or where a part's two values have no rule, `self`'s with the
            /// error (a pair given in a case must then give that key itself).
            pub fn mixed_keys(&self, other: &ContactSpec) -> (Vec<(&'static str, Given)>, Vec<MixError>) {
                let (mut keys, mut errors) = (Vec::new(), Vec::new());
                $(match self.$field.mix(&other.$field) {
                    Ok(p) => keys.extend(p.given()),
                    Err(e) => {
                        errors.push(e);
                        keys.extend(self.$field.given());
                    }
                })*
                (keys, errors)
            }
        }
    };
}

parts! {
    /// A contact law as a case gives it: its parts' parameters. The parts are listed here once
    /// (see [`Part`]); their order is the history's.
    #[derive(Clone, Copy, Debug, PartialEq)]
    pub struct ContactSpec {
        normal: NormalSpec,
        damping: DampingSpec,
        tangential: TangentialSpec,
        rolling: Option<RollingPart>,
        cohesion: Option<CohesionPart>,
    }
}

impl ContactSpec {
    /// Every part read from a contact object (the normal part first: the damping and the
    /// tangential part follow its model).
    pub fn parse(k: &impl Keys) -> Result<Self, ParamError> {
        let normal = NormalSpec::parse(k)?;
        let tangential = TangentialSpec::parse(k, &normal)?;
        let rolling = RollingPart::parse(k)?;
        let damping = DampingSpec::parse(k, &normal)?;
        let cohesion = CohesionPart::parse(k)?;
        Ok(ContactSpec {
            normal,
            damping,
            tangential,
            rolling,
            cohesion,
        })
    }

    /// P's linear spring–dashpot with Coulomb friction (`"model": "linear"`), under the area
    /// law and without rolling resistance.
    pub fn linear(kn: Scaled, ks: Scaled, damping: LinearDamping, friction: f64) -> Self {
        ContactSpec {
            normal: NormalSpec {
                spring: SpringSpec::Linear { kn },
                normal_force: NormalForce::default(),
            },
            damping: DampingSpec::Linear(damping),
            tangential: TangentialSpec {
                stiffness: ShearSpec::Constant(ks),
                friction,
            },
            rolling: None,
            cohesion: None,
        }
    }

    /// Hertz–Mindlin (`"model": "hertz_mindlin"`; T10–T19), under the area law and without
    /// rolling resistance.
    pub fn hertz_mindlin(young: f64, poisson: f64, restitution: f64, friction: f64) -> Self {
        ContactSpec {
            normal: NormalSpec {
                spring: SpringSpec::Hertz { young, poisson },
                normal_force: NormalForce::default(),
            },
            damping: DampingSpec::Hertz { restitution },
            tangential: TangentialSpec {
                stiffness: ShearSpec::Mindlin,
                friction,
            },
            rolling: None,
            cohesion: None,
        }
    }

    /// What the normal spring acts on.
    pub fn normal_force(&self) -> NormalForce {
        self.normal.normal_force
    }

    /// The same spec with the normal spring acting on `normal_force`.
    pub fn with_normal_force(mut self, normal_force: NormalForce) -> Self {
        self.normal.normal_force = normal_force;
        self
    }

    /// Rolling resistance, if any.
    pub fn rolling(&self) -> Option<RollingPart> {
        self.rolling
    }

    /// The same spec with rolling resistance `rolling`.
    pub fn with_rolling(mut self, rolling: Option<RollingPart>) -> Self {
        self.rolling = rolling;
        self
    }

    /// Cohesion, if any.
    pub fn cohesion(&self) -> Option<CohesionPart> {
        self.cohesion
    }

    /// The same spec with cohesion `cohesion`.
    pub fn with_cohesion(mut self, cohesion: Option<CohesionPart>) -> Self {
        self.cohesion = cohesion;
        self
    }

    /// Whether a contact's force depends on its path, not on the configuration alone (a
    /// Coulomb slider, rolling resistance): no energy to minimise.
    pub fn path_dependent(&self) -> bool {
        let ContactSpec {
            normal: _,
            damping: _,
            tangential,
            rolling,
            cohesion: _, // a potential's gradient
        } = self;
        tangential.friction > 0.0 || rolling.is_some()
    }

    /// Whether the law reads each body's number of contacts (the CDT rolling limiter's share:
    /// [`rolling`]).
    pub fn counts_contacts(&self) -> bool {
        self.rolling.is_some()
    }

    /// Coulomb friction coefficient.
    pub fn friction(&self) -> f64 {
        self.tangential.friction
    }

    /// How many of the [`History`] values the contacts of this law carry (the leading ones;
    /// the parts' after the last that keeps any are left out).
    pub fn history_kept(&self) -> usize {
        history_kept(self.rolling)
    }

    /// The law for a pair: `self` is the spec that governs the pair (a wall's own, when it
    /// overrides), `other_material` the spec of the other side's material (Hertz–Mindlin mixes
    /// the two materials, T11, T19); `rho` the pair's density, `g` = |gravity|. (The effective
    /// mass is not needed here: a dashpot that depends on it reads it at each contact.)
    pub fn resolve(&self, other_material: &ContactSpec, rho: f64, g: f64) -> Law {
        Law {
            normal: self.normal.resolve(&other_material.normal, rho, g),
            damping: self.damping.resolve(rho, g),
            tangential: self
                .tangential
                .resolve(&self.normal, &other_material.normal, rho, g),
            rolling: self.rolling,
            cohesion: self.cohesion,
        }
    }

    /// True when the resolved law's dashpots depend on the pair's effective mass
    /// (restitution-tuned linear dashpots).
    pub fn depends_on_mass(&self) -> bool {
        self.damping.depends_on_mass()
    }
}

/// A contact law with its parameters resolved for one pair: the parts it is composed of.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Law {
    pub normal: NormalPart,
    pub damping: DampingPart,
    pub tangential: TangentialPart,
    pub rolling: Option<RollingPart>,
    pub cohesion: Option<CohesionPart>,
}

/// The stiffness and damping of a contact's modes, for the critical time step: along the
/// normal, the tangent, and in relative rotation (the couple's spring: the rolling part's).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Modes {
    pub normal: (f64, f64),
    pub tangential: (f64, f64),
    pub rotation: (f64, f64),
}

/// What a law reads of a contact besides its overlap, velocities and step: the contact pass
/// computes these only for a law that asks ([`Law::needs`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Needs {
    /// The effective mass m* (T13): a Hertz dashpot (T14), a rolling part (its damping ratio).
    pub m_eff: bool,
    /// The effective radius R* (T11): the Hertz spring (and Mindlin's shear spring with it).
    pub r_eff: bool,
    /// The rolling radius and inertias ([`RollingKinematics`]): a rolling part.
    pub rolling: bool,
    /// The overlap chord and area ([`CohesionKinematics`]): a cohesion part.
    pub cohesion: bool,
}

impl Law {
    /// What the law reads of a contact (see [`Needs`]).
    #[inline(always)]
    pub fn needs(&self) -> Needs {
        let Law {
            normal,
            damping,
            tangential: _, // reads the normal spring's stiffness and the relative velocity only
            rolling,
            cohesion,
        } = self;
        Needs {
            m_eff: !matches!(damping, DampingPart::Dashpots { .. }) || rolling.is_some(),
            r_eff: matches!(normal, NormalPart::Hertz { .. }),
            rolling: rolling.is_some(),
            cohesion: cohesion.is_some(),
        }
    }

    /// The force for these kinematics, updating the history. The parts in order:
    /// the normal spring on its overlap ([`Kinematics::spring_overlap`]: the depth, or the
    /// area law's δ_eq with `F_n = ρ F_s(δ_eq) + η δ̇_eq`), `F_n = max(0, ρ F_s + η_n δ̇)` (T6,
    /// clamped so that the contact never pulls); the tangential part (T15–T20) with the
    /// damping part's shear dashpot; the rolling part, if any; last the cohesion part's pull
    /// `c ℓ` (after the slider and the rolling cap, which read the repulsive part only).
    /// Elastic energy `e k δ²` (with
    /// `δ²` → `δ·energy_depth`) plus the history springs'.
    #[inline(always)]
    pub fn force(&self, k: &Kinematics, h: &mut History) -> ContactForce {
        let Law {
            normal,
            damping,
            tangential,
            rolling,
            cohesion,
        } = self;
        let o = k.spring_overlap();
        let s = normal.spring(o.depth, k.r_eff);
        let eta_n = damping.normal(&s, k.m_eff);
        let spring = o.rho * (s.k * o.depth);
        let fn_ = (spring + eta_n * o.rate).max(0.0); // T(6)
        let (couple, couple_non_elastic) = o.couple(s.k * o.depth, eta_n);
        let mut out = ContactForce {
            normal: fn_,
            tangential: 0.0,
            elastic_energy: s.energy * s.k * o.depth * o.energy_depth,
            kn: s.tangent * s.k * o.rho * o.rho,
            eta_n: eta_n * o.rho,
            kt: 0.0,
            eta_t: 0.0,
            kr: 0.0,
            cr: 0.0,
            normal_non_elastic: fn_ - spring,
            history_energy: 0.0,
            history_energy_change: 0.0,
            couple,
            couple_non_elastic,
        };
        if tangential.friction > 0.0 || rolling.is_some() {
            let kt = tangential.stiffness(&s);
            let (shear_history, rolling_history) = h.0.split_at_mut(AT_ROLLING);
            tangential.apply(
                kt,
                damping.tangential(eta_n),
                k.vt,
                k.dt,
                &mut shear_history[AT_TANGENTIAL..],
                &mut out,
            );
            if let Some(r) = rolling {
                let zeta = damping.ratio(&s, k.m_eff);
                r.apply(
                    &k.rolling,
                    k.spin,
                    kt,
                    zeta,
                    k.dt,
                    rolling_history,
                    &mut out,
                );
            }
        }
        if let Some(c) = cohesion {
            // The pass gives the chord to every contact whose law has cohesion (`needs`).
            debug_assert!(k.cohesion.is_some(), "a cohesive contact without its chord");
            if let Some(ck) = &k.cohesion {
                c.apply(ck, &mut out);
            }
        }
        out
    }

    /// The modes of a contact with the kinematics `k` (its spring overlap `k.depth`, R*, m* and
    /// rolling kinematics), each part's stiffness and dashpot as [`Law::force`] reports them
    /// (`ρ = 1`: the caller scales the normal mode for the geometry it assumes).
    pub fn modes(&self, k: &Kinematics) -> Modes {
        let Law {
            normal,
            damping,
            tangential,
            rolling,
            cohesion: _, // stiffens nothing: its pull's derivative in δ is not a spring's
        } = self;
        let s = normal.spring(k.depth, k.r_eff);
        let eta_n = damping.normal(&s, k.m_eff);
        let kt = tangential.stiffness(&s);
        let shear = if tangential.friction > 0.0 {
            (kt, damping.tangential(eta_n))
        } else {
            (0.0, 0.0)
        };
        let rotation = match rolling {
            Some(r) => r.mode(&k.rolling, kt, damping.ratio(&s, k.m_eff)),
            None => (0.0, 0.0),
        };
        Modes {
            normal: (s.tangent * s.k, eta_n),
            tangential: shear,
            rotation,
        }
    }

    /// Coulomb friction coefficient μ.
    pub fn friction(&self) -> f64 {
        self.tangential.friction
    }

    /// How many of the [`History`] values its contacts carry (see
    /// [`ContactSpec::history_kept`]).
    pub fn history_kept(&self) -> usize {
        history_kept(self.rolling)
    }
}

/// A [`Law`] of the commonest kind — a linear spring, constant dashpots, a constant shear
/// spring with its slider, no rolling part — held as its numbers alone. [`LinearDashpots::law`]
/// rebuilds the [`Law`] with its kinds written out, so that where it is inlined the compiler
/// knows every part and [`Law::force`] compiles to that law's arithmetic alone: the same code
/// and the same bits as the general law, without its dispatch (the step compiles its slot
/// updates for such laws: every slot of a scene whose laws are all of this kind).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearDashpots {
    pub kn: f64,
    pub eta_n: f64,
    pub eta_s: f64,
    pub ks: f64,
    pub friction: f64,
}

impl LinearDashpots {
    /// The law's numbers, when it is of this kind. Every part is read and every kind of each
    /// named: a part added to [`Law`] is a compile error here until it says whether it is of
    /// this kind (`deny(unused_variables)`: a part bound and not read is an error too). A law
    /// with cohesion is not (its contacts need the chord, which this kind's copies never ask
    /// for). `tests/law_parts.rs` checks that [`LinearDashpots::law`] rebuilds every law this
    /// accepts exactly, so no part is dropped on the fast path.
    #[deny(unused_variables)]
    pub fn of(law: &Law) -> Option<Self> {
        let Law {
            normal,
            damping,
            tangential,
            rolling,
            cohesion,
        } = *law;
        match cohesion {
            None => {}
            Some(CohesionPart { .. }) => return None,
        }
        match rolling {
            None => {}
            Some(RollingPart { .. }) => return None,
        }
        let kn = match normal {
            NormalPart::Linear { kn } => kn,
            NormalPart::Hertz { .. } => return None,
        };
        let (eta_n, eta_s) = match damping {
            DampingPart::Dashpots { eta_n, eta_s } => (eta_n, eta_s),
            DampingPart::Restitution { .. } | DampingPart::Hertz { .. } => return None,
        };
        let TangentialPart {
            stiffness,
            friction,
        } = tangential;
        let ks = match stiffness {
            ShearStiffness::Constant(ks) => ks,
            ShearStiffness::Mindlin { .. } => return None,
        };
        Some(LinearDashpots {
            kn,
            eta_n,
            eta_s,
            ks,
            friction,
        })
    }

    /// The law itself.
    #[inline(always)]
    pub fn law(&self) -> Law {
        Law {
            normal: NormalPart::Linear { kn: self.kn },
            damping: DampingPart::Dashpots {
                eta_n: self.eta_n,
                eta_s: self.eta_s,
            },
            tangential: TangentialPart {
                stiffness: ShearStiffness::Constant(self.ks),
                friction: self.friction,
            },
            rolling: None,
            cohesion: None,
        }
    }
}

/// The parameters of contacts between two materials: the law that governs them (`spec`) and
/// the other side's material (`other`: Hertz–Mindlin forms E* and G* from both, T11, T19).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairSpec {
    pub spec: ContactSpec,
    pub other: ContactSpec,
}

impl PairSpec {
    /// A material with itself, or a law that governs every contact of a wall (`other` the
    /// body's material).
    pub fn new(spec: ContactSpec, other: ContactSpec) -> Self {
        PairSpec { spec, other }
    }

    /// The law for a pair of density `rho` under |g| `g`.
    #[inline]
    pub fn resolve(&self, rho: f64, g: f64) -> Law {
        self.spec.resolve(&self.other, rho, g)
    }
}
