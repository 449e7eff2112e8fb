//! Materials: which material each body and wall is of, and the contact parameters of every
//! pair of materials ([`PairTable`]), formed once when the world is made.
//!
//! Material 0 is the scene's own contact law (a case's `contact`): the material of every body
//! that names none. A case's further materials are 1, 2, …, each a contact law (the scene's
//! keys with the material's own in their place). Contacts between two materials take the
//! parameters the rules of [`crate::contact_law::mixing`] give, or the pair's own where the case
//! gives them (`pairs`). A wall is of a material (the scene's unless it names one), or has its
//! own law (a wall that gives contact keys of its own): that law then governs its contacts with
//! every body, whatever the body's material (the other side's moduli still enter a
//! Hertz–Mindlin E*).

use super::boundary::Boundary;
use crate::contact_law::{ContactSpec, MixError, PairSpec};

/// The materials of a scene as a case gives them, beside the scene's law (material 0).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Materials {
    /// The contact law of materials 1, 2, … (index k is material k + 1).
    pub specs: Vec<ContactSpec>,
    /// Pairs of materials given their own contact law: `(a, b, law)`, a ≤ b.
    pub pairs: Vec<(u16, u16, ContactSpec)>,
}

impl Materials {
    /// How many materials a scene with these has: the scene's and the named ones.
    pub fn count(&self) -> usize {
        1 + self.specs.len()
    }

    /// The contact law of material `m` (`scene`: material 0's).
    pub fn spec<'a>(&'a self, scene: &'a ContactSpec, m: u16) -> &'a ContactSpec {
        match m {
            0 => scene,
            _ => &self.specs[m as usize - 1],
        }
    }

    /// The law of contacts between materials `a` and `b`: the pair's own if given, else by the
    /// mixing rules (an error names the key no rule combines).
    pub fn pair(&self, scene: &ContactSpec, a: u16, b: u16) -> Result<PairSpec, MixError> {
        let (lo, hi) = (a.min(b), a.max(b));
        let (sa, sb) = (self.spec(scene, lo), self.spec(scene, hi));
        if let Some((_, _, own)) = self.pairs.iter().find(|p| (p.0, p.1) == (lo, hi)) {
            return Ok(PairSpec::new(*own, *sb));
        }
        Ok(PairSpec::new(sa.mix(sb)?, *sb))
    }
}

/// The contact law of every pair a scene can have: between two materials, and between each
/// wall and each material.
#[derive(Clone, Debug, PartialEq)]
pub struct PairTable {
    /// Number of materials M.
    count: usize,
    /// Material pairs, `a · M + b` (symmetric).
    bodies: Vec<PairSpec>,
    /// Walls against materials, `w · M + m`.
    walls: Vec<PairSpec>,
}

impl PairTable {
    /// The table of a scene whose law is `scene`, with `materials` and `walls`.
    ///
    /// # Panics
    /// If a pair of materials has no law (a case's reader refuses such a case first, naming
    /// the key: see [`Materials::pair`]).
    pub fn new(scene: &ContactSpec, materials: &Materials, walls: &[Boundary]) -> Self {
        let m = materials.count();
        let pair = |a: usize, b: usize| {
            materials
                .pair(scene, a as u16, b as u16)
                .unwrap_or_else(|e| panic!("materials {a} and {b}: `{}` {}", e.key, e.message))
        };
        let bodies = (0..m * m).map(|k| pair(k / m, k % m)).collect();
        let mut table = PairTable {
            count: m,
            bodies,
            walls: Vec::with_capacity(walls.len() * m),
        };
        for w in walls {
            for b in 0..m {
                let pair = match w.material {
                    Some(a) => *table.body_pair(a, b as u16),
                    None => PairSpec::new(w.spec, *materials.spec(scene, b as u16)),
                };
                table.walls.push(pair);
            }
        }
        table
    }

    /// Number of materials.
    #[inline]
    pub fn count(&self) -> usize {
        self.count
    }

    /// The law of contacts between materials `a` and `b`.
    #[inline]
    pub fn body_pair(&self, a: u16, b: u16) -> &PairSpec {
        &self.bodies[a as usize * self.count + b as usize]
    }

    /// The law of contacts between wall `w` and material `m`.
    #[inline]
    pub fn wall(&self, w: usize, m: u16) -> &PairSpec {
        &self.walls[w * self.count + m as usize]
    }

    /// Every law of the table: the material pairs' (`a · M + b`), then each wall's against each
    /// material (`M² + w · M + m`).
    pub fn all(&self) -> impl Iterator<Item = &PairSpec> {
        self.bodies.iter().chain(&self.walls)
    }
}
