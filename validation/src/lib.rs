//! dem2d-validation: an independent high-precision reference for the contact geometry and the
//! families of hard cases it is compared on. Never used by a simulation, and not part of the
//! `dem2d` library: the tests (a dev-dependency), `dem2d-lab figures` and the contact-kernel
//! benchmark use it. Only [`families`] calls the library (the kernels it checks); the references
//! themselves share no code with it.
//!
//! The reference computes in double-double arithmetic (≈ 106 bits) from the exact double inputs,
//! by methods deliberately different from the kernel's: the boundary of one body in parametric
//! form substituted into the other's implicit form (a quartic in tan(t/2)) instead of the pencil
//! of conics, segment intersections for rectangles. [`overlap_reference`] adds the overlap
//! area of a pair (and the boundary pieces it is made of) by Green's theorem in closed form on
//! the same crossings, for the tests of the overlap-area contact law.

pub mod dd;
pub mod families;
pub mod overlap_reference;
pub mod pairs;
pub mod polygon_reference;
pub mod reference;
pub mod rng;
