//! The case file's `contact` section and what depends on it: a wall's overrides of the scene's
//! contact keys, the keys a law part reads ([`ContactKeys`]), the range checks of every law a
//! pair that can meet will use, and the boundaries cohesion cannot act on.

use super::fields::{
    FieldError, Obj, join, non_negative, number, positive, scale, string, unknown_field,
};
use crate::contact_law::{Check, ContactSpec, Keys, ParamError};
use serde_json::{Map, Value};

/// A wall's contact overrides: every contact key given on the wall replaces the scene's, with
/// the inherited keys it replaces ([`ContactSpec::replaced_by`]); `None` when the wall overrides
/// nothing.
pub(super) fn wall_overrides(
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

/// A contact object's keys as the law's parts read them ([`Keys`]).
pub(super) struct ContactKeys<'a> {
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

pub(super) fn param_error(e: FieldError) -> ParamError {
    ParamError {
        field: e.path,
        message: e.message,
    }
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
