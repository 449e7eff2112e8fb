//! What every part of a contact law declares ([`Part`]).

use super::keys::Given;
use super::mixing::MixError;

/// One part of a contact law as a case gives it, in its own file: its keys, its history, how a
/// wall's override replaces inherited keys, how two materials' parts combine
/// ([`super::mixing`]). [`super::ContactSpec`] lists the parts once (its `parts!` declaration); what
/// reads every part (the keys, the history's layout, [`super::ContactSpec::given`],
/// [`super::ContactSpec::mix`], [`super::ContactSpec::mixed_keys`]) is generated from that list, so a new
/// part cannot be left out of any of them.
pub trait Part: Copy + Sized {
    /// The keys this part reads in a contact object.
    const KEYS: &'static [&'static str];
    /// The names of the values its contacts carry from step to step (a restart file's), if
    /// any.
    const HISTORY: &'static [&'static str] = &[];

    /// The inherited keys a wall's override `key` replaces ([`super::ContactSpec::replaced_by`]):
    /// keys that give the same parameter another way, and what depends on the key.
    fn replaced_by(key: &str) -> &'static [&'static str] {
        let _ = key;
        &[]
    }

    /// Its keys as a case file gives them (what its parser reads back).
    fn given(&self) -> Vec<(&'static str, Given)>;

    /// The part of contacts between the materials `self` and `other` by its rule
    /// ([`super::mixing`]), or the key whose two values no rule combines.
    fn mix(&self, other: &Self) -> Result<Self, MixError>;
}
