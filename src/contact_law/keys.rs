//! How a part reads its keys: from a contact object given by the case reader through [`Keys`]
//! (the core never sees JSON; the scene's reader implements it, names every field in its
//! errors, and refuses a key no part reads).

/// A parameter error: the field's path and what is wrong with it.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamError {
    pub field: String,
    pub message: String,
}

/// What a number must be.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Check {
    /// Any finite number.
    Any,
    /// `≥ 0`.
    NonNegative,
    /// `> 0`.
    Positive,
    /// A scale (a stiffness, a modulus, a length): positive and within the accepted range.
    Scale,
}

/// A contact object's keys, as the law's parts read them.
pub trait Keys {
    /// Whether `key` is given.
    fn has(&self, key: &str) -> bool;
    /// The string at `key`, if given.
    fn string(&self, key: &str) -> Result<Option<String>, ParamError>;
    /// The number at `key`, if given, checked.
    fn number(&self, key: &str, check: Check) -> Result<Option<f64>, ParamError>;
    /// An error about the given key `key`.
    fn error(&self, key: &str, message: String) -> ParamError;
    /// An error about the missing key `key` (reported where a missing key is: a wall's override
    /// names the scene's contact object).
    fn missing(&self, key: &str, message: String) -> ParamError;

    /// Refuses the keys of `keys` that are given: they are not parameters of `model`.
    fn refuse(&self, keys: &[&str], model: &str) -> Result<(), ParamError> {
        match keys.iter().find(|k| self.has(k)) {
            Some(k) => Err(self.error(k, format!("is not a parameter of the `{model}` model"))),
            None => Ok(()),
        }
    }

    /// A value given absolutely (`abs`) or per ρg (`rel`), not both; `check` for either.
    fn scaled(&self, abs: &str, rel: &str, check: Check) -> Result<Option<Scaled>, ParamError> {
        match (self.has(abs), self.has(rel)) {
            (true, true) => Err(self.error(rel, format!("give `{abs}` or `{rel}`, not both"))),
            (true, false) => Ok(self.number(abs, check)?.map(Scaled::Absolute)),
            (false, true) => Ok(self.number(rel, check)?.map(Scaled::OverRhoG)),
            (false, false) => Ok(None),
        }
    }
}

pub use super::params::Given;
use super::params::Scaled;
