//! # dem2d — two-dimensional discrete element method with circles, ellipses and rectangles
//!
//! Ellipses are handled as conics, following Kawasaki, Kiyama, Fujimura and Nishimura's
//! elliptical-element DEM (P in the citations `// P(9)`); contact laws follow the DEM theory
//! note T (`// T(14)`). Full references are in the user guide (docs/src/references.md).
//!
//! # Pipeline
//! `scene JSON → World → broad phase → narrow phase (Contact) → contact law → forces and
//! moments → integrator → quiescence check → output`.
//!
//! # Conventions
//! - Units: cgs (cm, g, s; forces in dyn, energies in erg); the equations are unit-agnostic, the
//!   documentation, the cases and the accepted ranges are cgs. Bodies have unit thickness.
//! - Angles in radians, counter-clockwise; a body's angle is that of its own x axis.
//! - For a contact between i and j the unit normal points from i to j; the overlap `δ > 0` when
//!   penetrating; the force on j is `+F` and on i `−F`.
//! - Pair geometry is computed in a frame centred on a body, never in world coordinates.

pub mod alloc;
pub mod analysis;
pub mod contact_law;
pub mod dynamics;
pub mod geometry;
pub mod narrow_phase;
pub mod output;
pub mod run;
pub mod scene;
