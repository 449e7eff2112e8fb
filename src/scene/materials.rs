//! A case's materials: `"materials": {"glass": {"density": 2.5, "friction": 0.3, …}, …}`,
//! `"material": "glass"` on a body or a wall, and `"pairs": [{"materials": ["glass",
//! "steel"], "friction": 0.2, …}]` (see `dynamics::materials` and `contact_law::mixing`).
//!
//! A material is the scene's `contact` object with the material's own keys in their place (as a
//! wall's overrides: a key replaces the keys that give the same parameter another way); it may
//! give every contact key but `model` and `normal_force` (the scene's), and a `density` for its
//! bodies. A pair entry gives keys of contacts between two materials in place of those the
//! mixing rules give (every contact key but `model`, `normal_force`, `young` and `poisson`:
//! E* and G* are always formed from the two materials' moduli). Every error names its field.

use super::contact::{layered, parse_contact};
use super::fields::unknown_field;
use super::fields::{FieldError, Obj, index, join, note_key, scale, suggest, type_of};
use crate::contact_law::{ContactSpec, Given, MixError};
use crate::dynamics::{BodyInit, Boundary, Materials};
use serde_json::{Map, Value};

/// The contact keys a material may not give: the scene's choices.
const SCENE_ONLY: [&str; 2] = ["model", "normal_force"];

/// The contact keys a pair may not give besides [`SCENE_ONLY`]: its moduli are the materials'.
const MODULI: [&str; 2] = ["young", "poisson"];

/// A case's materials as read: their names (material k + 1 is `names[k]`), each one's contact
/// object and density, and [`Materials`] (its pairs filled by [`read_pairs`]).
#[derive(Clone, Debug, Default)]
pub struct Named {
    pub names: Vec<String>,
    maps: Vec<Map<String, Value>>,
    pub densities: Vec<Option<f64>>,
    pub materials: Materials,
}

impl Named {
    /// The name of material `m` as a message gives it (material 0: the scene's `contact`).
    pub fn describe(&self, m: u16) -> String {
        match m {
            0 => "the scene's `contact`".to_string(),
            _ => format!("`{}`", self.names[m as usize - 1]),
        }
    }

    /// The path of material `m`'s object (`contact` for material 0).
    pub(crate) fn path(&self, m: u16) -> String {
        match m {
            0 => "contact".to_string(),
            _ => join("materials", &self.names[m as usize - 1]),
        }
    }

    /// Material `m`'s contact object (`scene` for material 0).
    pub(crate) fn map<'a>(
        &'a self,
        scene: &'a Map<String, Value>,
        m: u16,
    ) -> &'a Map<String, Value> {
        match m {
            0 => scene,
            _ => &self.maps[m as usize - 1],
        }
    }

    /// The index of the material named by the string at `path` (a body's or a wall's
    /// `material`).
    pub fn index_of(&self, v: &Value, path: &str) -> Result<u16, FieldError> {
        let name = v.as_str().ok_or_else(|| {
            FieldError::new(
                path,
                format!("must be a material's name (a string), got {}", type_of(v)),
            )
        })?;
        match self.names.iter().position(|n| n == name) {
            Some(k) => Ok(k as u16 + 1),
            None => Err(FieldError::new(path, self.unknown(name))),
        }
    }

    /// The message for an unknown material name.
    fn unknown(&self, name: &str) -> String {
        if self.names.is_empty() {
            return format!(
                "unknown material `{name}`: the case defines no materials (give them in \
                 `materials`)"
            );
        }
        let names: Vec<&str> = self.names.iter().map(String::as_str).collect();
        let what = format!("unknown material `{name}`");
        suggest(&what, name, &names, "the case's materials")
    }
}

/// The keys a material's object takes: `density`, and every contact key but the scene's own.
fn material_keys() -> Vec<&'static str> {
    std::iter::once("density")
        .chain(ContactSpec::keys().filter(|k| !SCENE_ONLY.contains(k)))
        .collect()
}

/// The keys a pair's object takes: `materials`, and every contact key but the scene's own and
/// the moduli.
fn pair_keys() -> Vec<&'static str> {
    std::iter::once("materials")
        .chain(ContactSpec::keys().filter(|k| !SCENE_ONLY.contains(k) && !MODULI.contains(k)))
        .collect()
}

/// Reads `materials` (absent: none), each over the scene's contact object `scene`.
pub fn read_materials(v: Option<&Value>, scene: &Map<String, Value>) -> Result<Named, FieldError> {
    let mut named = Named::default();
    for k in material_keys() {
        note_key("materials.<name>", k);
    }
    let Some(v) = v else {
        return Ok(named);
    };
    let items = v.as_object().ok_or_else(|| {
        FieldError::new(
            "materials",
            format!(
                "must be an object of named materials ({{\"glass\": {{\"density\": 2.5, \
                 \"friction\": 0.3}}}}), got {}",
                type_of(v)
            ),
        )
    })?;
    if items.len() >= u16::MAX as usize {
        return Err(FieldError::new(
            "materials",
            format!(
                "{} materials: at most {} are accepted",
                items.len(),
                u16::MAX - 1
            ),
        ));
    }
    let keys = material_keys();
    for (name, m) in items {
        let path = join("materials", name);
        if name.is_empty() {
            return Err(FieldError::new(path, "a material needs a name"));
        }
        let o = m.as_object().ok_or_else(|| {
            FieldError::new(&path, format!("must be an object, got {}", type_of(m)))
        })?;
        let mut density = None;
        let mut given = Vec::new();
        for (key, value) in o {
            let at = join(&path, key);
            if key == "density" {
                density = Some(scale(value, &at)?);
            } else if SCENE_ONLY.contains(&key.as_str()) {
                return Err(FieldError::new(
                    at,
                    format!(
                        "is the scene's (`contact.{key}`): a material gives parameters of the \
                         scene's model"
                    ),
                ));
            } else if let Some(k) = keys.iter().find(|k| **k == key.as_str()) {
                given.push((*k, value.clone()));
            } else {
                return Err(FieldError::new(at, unknown_field(key, &keys)));
            }
        }
        let map = layered(scene, given);
        let spec = parse_contact(&map, &path, &path, false)?;
        named.names.push(name.clone());
        named.maps.push(map);
        named.densities.push(density);
        named.materials.specs.push(spec);
    }
    Ok(named)
}

/// The JSON value of a key as a part gives it back.
fn value_of(g: Given) -> Value {
    match g {
        Given::Number(x) => serde_json::Number::from_f64(x).map_or(Value::Null, Value::Number),
        Given::Text(t) => Value::from(t),
    }
}

/// Reads `pairs` (absent: none): each entry's keys in place of those the mixing rules give its
/// two materials. `scene` is the scene's law and contact object.
pub fn read_pairs(
    v: Option<&Value>,
    named: &mut Named,
    scene: (&ContactSpec, &Map<String, Value>),
) -> Result<(), FieldError> {
    for k in pair_keys() {
        note_key("pairs[]", k);
    }
    let Some(v) = v else {
        return Ok(());
    };
    let items = v
        .as_array()
        .ok_or_else(|| FieldError::new("pairs", format!("must be an array, got {}", type_of(v))))?;
    let keys = pair_keys();
    for (k, item) in items.iter().enumerate() {
        let path = index("pairs", k);
        let mut o = Obj::new(item, &path)?;
        let at = o.field_path("materials");
        let names = o.req("materials")?;
        let list = names
            .as_array()
            .filter(|a| a.len() == 2)
            .ok_or_else(|| FieldError::new(&at, "must name two materials: [\"a\", \"b\"]"))?;
        let a = named.index_of(&list[0], &index(&at, 0))?;
        let b = named.index_of(&list[1], &index(&at, 1))?;
        let (lo, hi) = (a.min(b), a.max(b));
        if named.materials.pairs.iter().any(|p| (p.0, p.1) == (lo, hi)) {
            return Err(FieldError::new(
                at,
                format!(
                    "the pair of {} and {} is given twice",
                    named.describe(a),
                    named.describe(b)
                ),
            ));
        }
        let mut given = Vec::new();
        for key in item.as_object().expect("an object").keys() {
            if key == "materials" {
                continue;
            }
            let field = join(&path, key);
            if SCENE_ONLY.contains(&key.as_str()) || MODULI.contains(&key.as_str()) {
                return Err(FieldError::new(
                    field,
                    format!(
                        "is not a pair's: {}",
                        if MODULI.contains(&key.as_str()) {
                            "the contact moduli E* and G* are formed from the two materials' \
                             `young` and `poisson` (T11, T19)"
                        } else {
                            "it is the scene's (`contact`)"
                        }
                    ),
                ));
            }
            match keys.iter().find(|k| **k == key.as_str()) {
                Some(k) => given.push((*k, o.get(k).expect("present").clone())),
                None => return Err(FieldError::new(field, unknown_field(key, &keys))),
            }
        }
        o.finish()?;
        let (sa, sb) = (
            named.materials.spec(scene.0, lo),
            named.materials.spec(scene.0, hi),
        );
        let (base, errors) = sa.mixed_keys(sb);
        for e in errors {
            let covered = given
                .iter()
                .any(|(g, _)| *g == e.key || ContactSpec::replaced_by(g).contains(&e.key));
            if !covered {
                return Err(FieldError::new(
                    join(&path, e.key),
                    format!(
                        "is missing: {} and {} have no common rule for it ({}): give it here",
                        named.describe(lo),
                        named.describe(hi),
                        e.message
                    ),
                ));
            }
        }
        let base: Map<String, Value> = base
            .into_iter()
            .map(|(k, g)| (k.to_string(), value_of(g)))
            .collect();
        let spec = parse_contact(&layered(&base, given), &path, &path, false)?;
        named.materials.pairs.push((lo, hi, spec));
    }
    Ok(())
}

/// The pairs of materials that can meet: every two materials of bodies, and each wall's with
/// every material of a body (a wall of its own law meets none: its law governs).
pub fn meeting(bodies: &[BodyInit], walls: &[Boundary]) -> Vec<(u16, u16)> {
    let mut used: Vec<u16> = bodies.iter().map(|b| b.material).collect();
    used.sort_unstable();
    used.dedup();
    let mut out = Vec::new();
    for (i, &a) in used.iter().enumerate() {
        for &b in &used[i..] {
            out.push((a, b));
        }
    }
    for w in walls {
        if let Some(a) = w.material {
            for &b in &used {
                out.push((a.min(b), a.max(b)));
            }
        }
    }
    out.sort_unstable();
    out.dedup();
    out
}

/// Checks that every two materials that can meet ([`meeting`]) without a pair of their own
/// mix by the rules; the error names the key at the material that gives it
/// (`materials.steel.restitution`).
pub fn check_mixing(
    named: &Named,
    scene: (&ContactSpec, &Map<String, Value>),
    meeting: &[(u16, u16)],
) -> Result<(), FieldError> {
    for &(a, b) in meeting {
        let Err(MixError { key, message }) = named.materials.pair(scene.0, a, b) else {
            continue;
        };
        let at = [b, a]
            .into_iter()
            .find(|&m| named.map(scene.1, m).contains_key(key))
            .map_or_else(|| named.path(b), |m| join(&named.path(m), key));
        return Err(FieldError::new(
            at,
            format!(
                "{} and {} meet in this scene but have no common rule for `{key}` ({message}): \
                 give it both the same way, or give the pair its own in `pairs`",
                named.describe(a),
                named.describe(b)
            ),
        ));
    }
    Ok(())
}

/// A body's density: its own `density`, else its material's, else 1; refused when both give
/// one (`path` the body's).
pub fn body_density(
    named: &Named,
    material: u16,
    own: Option<f64>,
    path: &str,
) -> Result<f64, FieldError> {
    let of_material = match material {
        0 => None,
        m => named.densities[m as usize - 1],
    };
    match (own, of_material) {
        (Some(_), Some(d)) => Err(FieldError::new(
            join(path, "density"),
            format!(
                "material {} gives the density ({d}): give it in one place",
                named.describe(material)
            ),
        )),
        (Some(d), None) | (None, Some(d)) => Ok(d),
        (None, None) => Ok(1.0),
    }
}
