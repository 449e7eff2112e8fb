//! A small reader over `serde_json::Value` objects that knows its path, so that every error says
//! which field is wrong, and that rejects fields it was not asked for.

use serde::de::{self, DeserializeSeed, Deserializer, MapAccess, SeqAccess, Visitor};
use serde_json::{Map, Value};
use std::cell::RefCell;
use std::collections::BTreeSet;
use std::fmt;

/// Largest magnitude of any number read.
pub const MAX_MAGNITUDE: f64 = 1e40;

/// Smallest value of a scale (a size, density, time step, stiffness or modulus).
pub const MIN_SCALE: f64 = 1e-40;

/// An input error located at a field.
#[derive(Clone, Debug, PartialEq)]
pub struct FieldError {
    /// Where: a path like `pairs[3].i.shape.a` (empty for the whole document).
    pub path: String,
    /// What is wrong with it.
    pub message: String,
}

impl FieldError {
    pub fn new(path: impl Into<String>, message: impl Into<String>) -> Self {
        FieldError {
            path: path.into(),
            message: message.into(),
        }
    }
}

impl fmt::Display for FieldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.path.is_empty() {
            write!(f, "{}", self.message)
        } else {
            write!(f, "field `{}`: {}", self.path, self.message)
        }
    }
}

impl std::error::Error for FieldError {}

/// `parent.key`, or `key` at the top; an empty key is written `""` so that it can be seen.
pub fn join(parent: &str, key: &str) -> String {
    let key = if key.is_empty() { "\"\"" } else { key };
    if parent.is_empty() {
        key.to_string()
    } else {
        format!("{parent}.{key}")
    }
}

/// `parent[index]`.
pub fn index(parent: &str, i: usize) -> String {
    format!("{parent}[{i}]")
}

/// A short description of a JSON value's type, for messages.
pub fn type_of(v: &Value) -> &'static str {
    match v {
        Value::Null => "null",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    }
}

/// Marks a non-finite literal (`NaN`, `Infinity`) that [`parse_json`] turned into a string.
const NON_FINITE: &str = "\u{1}non-finite:";

/// Parses JSON, accepting the non-JSON literals `NaN`, `Infinity` and `-Infinity` outside strings
/// (as some writers emit them) so that they can be refused with the field they stand in
/// (`must be a finite number, got NaN`) rather than as a syntax error at a column. A leading
/// UTF-8 byte-order mark is skipped. A key given twice in one object is refused with its path
/// (`serde_json::Value` would silently keep the last value). `root` names the document in paths
/// (`""` for a case file, `"pairs"` for a `dem2d contact` input). Numbers are read exactly (the
/// double nearest to the decimal text: serde_json's `float_roundtrip`).
pub fn parse_json(text: &str, root: &str) -> Result<Value, FieldError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let marked = mark_non_finite(text);
    let duplicate = RefCell::new(None);
    let mut de = serde_json::Deserializer::from_str(&marked);
    let parsed = ValueSeed {
        path: root,
        duplicate: &duplicate,
    }
    .deserialize(&mut de)
    .and_then(|v| de.end().map(|()| v));
    parsed.map_err(|e| match duplicate.into_inner() {
        Some(path) => FieldError::new(
            path,
            format!(
                "duplicate key: given more than once in the same object (line {}, column {})",
                e.line(),
                e.column()
            ),
        ),
        None => FieldError::new("", format!("malformed JSON: {e}")),
    })
}

/// Replaces the literals `NaN`, `Infinity`, `+Infinity` and `-Infinity` outside strings by marked
/// strings (see [`number`]).
fn mark_non_finite(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut in_string = false;
    let mut escaped = false;
    let mut rest = text;
    while let Some(c) = rest.chars().next() {
        if in_string {
            out.push(c);
            if escaped {
                escaped = false;
            } else if c == '\\' {
                escaped = true;
            } else if c == '"' {
                in_string = false;
            }
            rest = &rest[c.len_utf8()..];
            continue;
        }
        let literal = ["-Infinity", "+Infinity", "Infinity", "NaN"]
            .into_iter()
            .find(|l| rest.starts_with(l));
        match (c, literal) {
            ('"', _) => {
                in_string = true;
                out.push(c);
                rest = &rest[1..];
            }
            (_, Some(l)) => {
                // The marker's control character must be escaped inside a JSON string.
                out.push_str("\"\\u0001non-finite:");
                out.push_str(l);
                out.push('"');
                rest = &rest[l.len()..];
            }
            _ => {
                out.push(c);
                rest = &rest[c.len_utf8()..];
            }
        }
    }
    out
}

/// Builds a [`Value`] like serde_json's own deserializer, but knows the path of what it reads and
/// records the path of the first key it sees twice in one object (then fails).
struct ValueSeed<'a> {
    path: &'a str,
    duplicate: &'a RefCell<Option<String>>,
}

impl<'de> DeserializeSeed<'de> for ValueSeed<'_> {
    type Value = Value;

    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Value, D::Error> {
        d.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for ValueSeed<'_> {
    type Value = Value;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a JSON value")
    }

    fn visit_bool<E>(self, v: bool) -> Result<Value, E> {
        Ok(Value::Bool(v))
    }

    fn visit_i64<E>(self, v: i64) -> Result<Value, E> {
        Ok(Value::from(v))
    }

    fn visit_u64<E>(self, v: u64) -> Result<Value, E> {
        Ok(Value::from(v))
    }

    fn visit_f64<E>(self, v: f64) -> Result<Value, E> {
        // JSON text cannot spell a non-finite number (they arrive as marked strings).
        Ok(serde_json::Number::from_f64(v).map_or(Value::Null, Value::Number))
    }

    fn visit_str<E>(self, v: &str) -> Result<Value, E> {
        Ok(Value::String(v.to_string()))
    }

    fn visit_string<E>(self, v: String) -> Result<Value, E> {
        Ok(Value::String(v))
    }

    fn visit_unit<E>(self) -> Result<Value, E> {
        Ok(Value::Null)
    }

    fn visit_none<E>(self) -> Result<Value, E> {
        Ok(Value::Null)
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Value, A::Error> {
        let mut items = Vec::new();
        loop {
            let path = index(self.path, items.len());
            let seed = ValueSeed {
                path: &path,
                duplicate: self.duplicate,
            };
            match seq.next_element_seed(seed)? {
                Some(v) => items.push(v),
                None => return Ok(Value::Array(items)),
            }
        }
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Value, A::Error> {
        let mut out = Map::new();
        while let Some(key) = map.next_key::<String>()? {
            let path = join(self.path, &key);
            if out.contains_key(&key) {
                *self.duplicate.borrow_mut() = Some(path);
                return Err(de::Error::custom(format!("duplicate key `{key}`")));
            }
            let seed = ValueSeed {
                path: &path,
                duplicate: self.duplicate,
            };
            let value = map.next_value_seed(seed)?;
            out.insert(key, value);
        }
        Ok(Value::Object(out))
    }
}

/// A finite number of magnitude at most [`MAX_MAGNITUDE`] (every number a case gives: see
/// [`super::ranges`]).
pub fn number(v: &Value, path: &str) -> Result<f64, FieldError> {
    if let Value::String(s) = v
        && let Some(literal) = s.strip_prefix(NON_FINITE)
    {
        return Err(FieldError::new(
            path,
            format!("must be a finite number, got {literal}"),
        ));
    }
    match v.as_f64() {
        Some(x) if x.abs() <= MAX_MAGNITUDE => Ok(x),
        Some(x) if x.is_finite() => Err(FieldError::new(
            path,
            format!("{x:e} is outside the accepted range: magnitudes up to {MAX_MAGNITUDE:e}"),
        )),
        Some(_) => Err(FieldError::new(path, "must be a finite number")),
        None => Err(FieldError::new(
            path,
            format!("must be a number, got {}", type_of(v)),
        )),
    }
}

/// A positive number (at most [`MAX_MAGNITUDE`]).
pub fn positive(v: &Value, path: &str) -> Result<f64, FieldError> {
    let x = number(v, path)?;
    if x > 0.0 {
        Ok(x)
    } else {
        Err(FieldError::new(path, format!("must be positive, got {x}")))
    }
}

/// A count: a whole number ≥ 1.
pub fn count(v: &Value, path: &str) -> Result<u64, FieldError> {
    match v.as_u64() {
        Some(n) if n >= 1 => Ok(n),
        _ => Err(FieldError::new(
            path,
            format!("must be a whole number ≥ 1, got {v}"),
        )),
    }
}

/// A scale — a size, density, time step, stiffness or modulus: positive, within
/// [`MIN_SCALE`] … [`MAX_MAGNITUDE`].
pub fn scale(v: &Value, path: &str) -> Result<f64, FieldError> {
    let x = positive(v, path)?;
    if x >= MIN_SCALE {
        Ok(x)
    } else {
        Err(FieldError::new(
            path,
            format!("{x:e} is outside the accepted range {MIN_SCALE:e} … {MAX_MAGNITUDE:e}"),
        ))
    }
}

/// A non-negative number (at most [`MAX_MAGNITUDE`]).
pub fn non_negative(v: &Value, path: &str) -> Result<f64, FieldError> {
    let x = number(v, path)?;
    if x >= 0.0 {
        Ok(x)
    } else {
        Err(FieldError::new(
            path,
            format!("must be zero or positive, got {x}"),
        ))
    }
}

/// A pair `[x, y]` of finite numbers.
pub fn vec2(v: &Value, path: &str) -> Result<[f64; 2], FieldError> {
    match v.as_array() {
        Some(a) if a.len() == 2 => Ok([
            number(&a[0], &index(path, 0))?,
            number(&a[1], &index(path, 1))?,
        ]),
        _ => Err(FieldError::new(
            path,
            format!(
                "must be an array of two numbers [x, y], got {}",
                describe(v)
            ),
        )),
    }
}

fn describe(v: &Value) -> String {
    match v {
        Value::Array(a) => format!("an array of {} elements", a.len()),
        other => type_of(other).to_string(),
    }
}

/// Other names users give a field, and the field meant.
const ALIASES: [(&str, &str); 16] = [
    ("radius", "r"),
    ("width", "w"),
    ("height", "h"),
    ("semi_major", "a"),
    ("semi_minor", "b"),
    ("mu", "friction"),
    ("friction_coefficient", "friction"),
    ("pos", "position"),
    ("center", "position"),
    ("vel", "velocity"),
    ("v", "velocity"),
    ("angular_velocity", "omega"),
    ("theta", "angle"),
    ("rho", "density"),
    ("timestep", "dt"),
    ("g", "gravity"),
];

/// Edit distance between `a` and `b` (insertions, deletions, substitutions and swaps of two
/// neighbours: `frction` is 1 from `friction`, `firction` 1).
fn edit_distance(a: &str, b: &str) -> usize {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    let mut d = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    for (i, row) in d.iter_mut().enumerate() {
        row[0] = i;
    }
    for (j, x) in d[0].iter_mut().enumerate() {
        *x = j;
    }
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut v = (d[i - 1][j] + 1)
                .min(d[i][j - 1] + 1)
                .min(d[i - 1][j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                v = v.min(d[i - 2][j - 2] + 1);
            }
            d[i][j] = v;
        }
    }
    d[a.len()][b.len()]
}

/// The valid key a user most likely meant by `given`: a known other name of it, else the
/// closest by spelling (within a third of its length, at least one edit), else the key it is
/// the start or the plural of.
pub fn did_you_mean<'k>(given: &str, valid: &[&'k str]) -> Option<&'k str> {
    let lower = given.to_ascii_lowercase();
    if let Some(&k) = valid.iter().find(|k| **k == lower) {
        return Some(k);
    }
    if let Some((_, meant)) = ALIASES.iter().find(|(alias, _)| *alias == lower)
        && let Some(&k) = valid.iter().find(|k| *k == meant)
    {
        return Some(k);
    }
    let (best, d) = valid
        .iter()
        .map(|k| (*k, edit_distance(&lower, k)))
        .min_by_key(|&(_, d)| d)?;
    if d <= (lower.chars().count() / 3).max(1) {
        return Some(best);
    }
    valid
        .iter()
        .find(|k| k.len() >= 3 && (lower.starts_with(*k) || k.starts_with(lower.as_str())))
        .copied()
}

/// The message for an unknown key: what it may have meant and the keys this object takes.
pub fn unknown_field(given: &str, valid: &[&str]) -> String {
    let mut valid: Vec<&str> = valid.to_vec();
    valid.sort_unstable();
    valid.dedup();
    let what = if given.is_empty() {
        "unknown field (an empty key)".to_string()
    } else {
        "unknown field".to_string()
    };
    suggest(&what, given, &valid, "the valid keys here")
}

/// The message `what` about the unknown name `given`, with the name of `valid` it may have
/// meant and the list of them (`whose`: what they are); `what` alone when there are none.
pub fn suggest(what: &str, given: &str, valid: &[&str], whose: &str) -> String {
    if valid.is_empty() {
        return what.to_string();
    }
    let list = valid
        .iter()
        .map(|k| format!("`{k}`"))
        .collect::<Vec<_>>()
        .join(", ");
    match did_you_mean(given, valid) {
        Some(k) => format!("{what}: did you mean `{k}`? ({whose}: {list})"),
        None => format!("{what} ({whose}: {list})"),
    }
}

thread_local! {
    /// The keys asked for while [`keys_asked_during`] runs (None otherwise: nothing recorded).
    static ASKED: RefCell<Option<BTreeSet<String>>> = const { RefCell::new(None) };
}

/// Runs `f` and returns, beside its result, every key a reader asked for while it ran (present
/// or not), as schema paths with the array indices left out (`bodies[].shape.r`,
/// `walls[].servo.gain`). The readers' own requests are thus the list of the keys they accept:
/// `tests/docs.rs` holds the case-file reference to it, both ways.
pub fn keys_asked_during<T>(f: impl FnOnce() -> T) -> (T, BTreeSet<String>) {
    let outer = ASKED.with(|a| a.replace(Some(BTreeSet::new())));
    let result = f();
    let asked = ASKED.with(|a| a.replace(outer)).unwrap_or_default();
    (result, asked)
}

/// Records that the reader at `parent` asked for `key` (see [`keys_asked_during`]).
pub(crate) fn note_key(parent: &str, key: &str) {
    ASKED.with(|a| {
        if let Some(set) = a.borrow_mut().as_mut() {
            set.insert(schema_path(&join(parent, key)));
        }
    });
}

/// `bodies[3].shape.disks[0].r` → `bodies[].shape.disks[].r`.
fn schema_path(path: &str) -> String {
    let mut out = String::with_capacity(path.len());
    let mut chars = path.chars().peekable();
    while let Some(c) = chars.next() {
        out.push(c);
        if c == '[' {
            while chars.peek().is_some_and(char::is_ascii_digit) {
                chars.next();
            }
        }
    }
    out
}

/// Reads the object `v` at `path` with `f`, then rejects the fields `f` did not take
/// ([`Obj::finish`]).
pub fn object<T>(
    v: &Value,
    path: &str,
    f: impl FnOnce(&mut Obj) -> Result<T, FieldError>,
) -> Result<T, FieldError> {
    let mut o = Obj::new(v, path)?;
    let r = f(&mut o)?;
    o.finish()?;
    Ok(r)
}

/// An object being read: fields are taken one by one, and [`Obj::finish`] rejects the rest.
pub struct Obj<'a> {
    map: &'a Map<String, Value>,
    path: String,
    taken: Vec<&'a str>,
    /// Every key asked for, present or not: the keys this object takes.
    asked: Vec<String>,
}

impl<'a> Obj<'a> {
    /// The object at `path`, or an error if `v` is not an object.
    pub fn new(v: &'a Value, path: &str) -> Result<Self, FieldError> {
        match v.as_object() {
            Some(map) => Ok(Obj {
                map,
                path: path.to_string(),
                taken: Vec::new(),
                asked: Vec::new(),
            }),
            None => Err(FieldError::new(
                path,
                format!("must be an object, got {}", type_of(v)),
            )),
        }
    }

    /// This object's path.
    pub fn path(&self) -> &str {
        &self.path
    }

    /// The path of one of its fields.
    pub fn field_path(&self, key: &str) -> String {
        join(&self.path, key)
    }

    /// True if the field is present.
    pub fn has(&self, key: &str) -> bool {
        note_key(&self.path, key);
        self.map.contains_key(key)
    }

    /// An optional field (marked as read).
    pub fn get(&mut self, key: &str) -> Option<&'a Value> {
        note_key(&self.path, key);
        if !self.asked.iter().any(|a| a == key) {
            self.asked.push(key.to_string());
        }
        let (k, v) = self.map.get_key_value(key)?;
        self.taken.push(k.as_str());
        Some(v)
    }

    /// A required field. When it is missing and a key nobody asked for looks like it
    /// (`radius` for `r`, `frction` for `friction`), the message says so.
    pub fn req(&mut self, key: &str) -> Result<&'a Value, FieldError> {
        let path = self.field_path(key);
        if let Some(v) = self.get(key) {
            return Ok(v);
        }
        let lookalike = self
            .map
            .keys()
            .find(|k| !self.asked.iter().any(|a| a == *k) && did_you_mean(k, &[key]).is_some());
        Err(FieldError::new(
            path,
            match lookalike {
                Some(k) => format!("is missing (`{k}` is given: did you mean `{key}`?)"),
                None => "is missing".to_string(),
            },
        ))
    }

    /// Applies `f` to a required field with its path.
    pub fn req_with<T>(
        &mut self,
        key: &str,
        f: impl FnOnce(&Value, &str) -> Result<T, FieldError>,
    ) -> Result<T, FieldError> {
        let v = self.req(key)?;
        f(v, &self.field_path(key))
    }

    /// Applies `f` to an optional field with its path.
    pub fn opt_with<T>(
        &mut self,
        key: &str,
        f: impl FnOnce(&Value, &str) -> Result<T, FieldError>,
    ) -> Result<Option<T>, FieldError> {
        match self.get(key) {
            Some(v) => f(v, &self.field_path(key)).map(Some),
            None => Ok(None),
        }
    }

    /// Errors on the first field that was never read (unknown fields are mistakes, not comments).
    pub fn finish(self) -> Result<(), FieldError> {
        let mut keys: Vec<&String> = self.map.keys().collect();
        keys.sort();
        for k in keys {
            if !self.taken.contains(&k.as_str()) {
                let valid: Vec<&str> = self.asked.iter().map(String::as_str).collect();
                return Err(FieldError::new(
                    join(&self.path, k),
                    unknown_field(k, &valid),
                ));
            }
        }
        Ok(())
    }
}

/// A string field at `path`.
pub fn string(v: &Value, path: &str) -> Result<String, FieldError> {
    v.as_str()
        .map(str::to_string)
        .ok_or_else(|| FieldError::new(path, format!("must be a string, got {}", type_of(v))))
}

/// A boolean field at `path`.
pub fn boolean(v: &Value, path: &str) -> Result<bool, FieldError> {
    v.as_bool()
        .ok_or_else(|| FieldError::new(path, format!("must be true or false, got {}", type_of(v))))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_read_exactly() {
        // Against Rust's own parse (correctly rounded): 17-digit decimals of random doubles of
        // every magnitude the ranges accept, and the issue's example.
        let mut state = 0x2545_F491_4F6C_DD1Du64;
        let mut texts = vec!["933.1286246343909".to_string()];
        while texts.len() < 3000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let x = f64::from_bits(state);
            if x.is_finite() && x.abs() <= 1e40 && x.abs() >= 1e-40 {
                texts.push(format!("{x:.16e}"));
                texts.push(format!("{}", x));
            }
        }
        let json = format!("[{}]", texts.join(","));
        let v = parse_json(&json, "").unwrap();
        for (t, v) in texts.iter().zip(v.as_array().unwrap()) {
            let want: f64 = t.parse().unwrap();
            assert_eq!(v.as_f64().unwrap().to_bits(), want.to_bits(), "{t}");
        }
    }

    #[test]
    fn a_key_given_twice_is_named_with_its_path() {
        let e = parse_json(r#"{"a": [{"b": {"c": 1, "c": 2}}]}"#, "top").unwrap_err();
        assert_eq!(e.path, "top.a[0].b.c");
        assert!(e.message.starts_with("duplicate key"), "{}", e.message);
        let e = parse_json(r#"{"dt": -1, "dt": 1e-5}"#, "").unwrap_err();
        assert_eq!(e.path, "dt");
        // The same key in two objects is no duplicate.
        assert!(parse_json(r#"[{"c": 1}, {"c": 2}]"#, "").is_ok());
    }

    #[test]
    fn a_byte_order_mark_is_skipped_and_non_finite_literals_are_marked() {
        let v = parse_json("\u{feff}{\"x\": NaN, \"s\": \"NaN\"}", "").unwrap();
        let e = number(&v["x"], "x").unwrap_err();
        assert_eq!(e.message, "must be a finite number, got NaN");
        assert_eq!(v["s"], "NaN");
    }
}
