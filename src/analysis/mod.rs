//! Measures of a granular state: the Love–Weber stress and the boundary stress from wall
//! forces, the packing fraction of a window (exact clipped areas), the coordination number with
//! and without rattlers, the fabric anisotropies `a_c`, `a_n`, `a_t` (second-order Fourier fits,
//! Rothenburg & Bathurst 1989), and the orientation order of non-circular bodies.
//!
//! Everything here is a pure function of a [`Frame`] — the bodies' shapes and poses and the
//! contacts' points, normals and forces — so that the same code serves a running world
//! ([`Frame::from_world`]) and a run already written (`dem2d analyze` rebuilds frames from
//! `trajectory.csv` and `contacts.csv`). No I/O.
//!
//! # Conventions
//! - A contact keeps the world's convention: the normal `n` points from the giver `i` (a body or
//!   a wall) to the receiver `j` (a body); the force on j is `+F`, on i `−F`. `F_n = F·n > 0` in
//!   compression, `F_t = F·t` with `t = (−n_y, n_x)`.
//! - Stresses are **compression positive** (the soil-mechanics sign): σ = −(1/V) Σ f ⊗ ℓ with f
//!   the force *on* a body at a contact and ℓ its branch vector, centroid → contact point.
//! - The **region** is an axis-aligned rectangle ([`Window`]): the box of four axis-aligned
//!   walls when the scene has one, or a window given by the caller.

pub mod fabric;
pub mod fields;
pub mod forces;
pub mod frame;
pub mod packing;
pub mod statistics;
pub mod stress;

pub use frame::{Frame, FrameBody, FrameContact, Window, wall_box};

use crate::dynamics::cell::Cell;

/// Everything written to one row of `analysis.csv`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Measures {
    pub time: f64,
    /// The region's area (cm²).
    pub area: f64,
    /// Love–Weber stress of the bodies whose centre lies in the region (compression positive,
    /// dyn/cm²), symmetric part.
    pub stress: [f64; 3],
    /// Boundary stress from the wall contacts (NaN without a wall box).
    pub boundary_stress: [f64; 3],
    pub packing_fraction: f64,
    pub coordination: f64,
    pub coordination_no_rattlers: f64,
    pub rattler_fraction: f64,
    pub fabric: fabric::Anisotropy,
    /// Orientation order of the non-circular bodies (NaN without any).
    pub orientation_order: f64,
    pub bodies: usize,
    pub contacts: usize,
    /// In a periodic cell, the cell's measures.
    pub cell: Option<CellMeasures>,
}

/// A periodic cell's measures (see `dynamics::cell`): its normal stress σ_yy (the pressure a
/// shear cell holds), its shear stress `(σ_xy + σ_yx)/2`, the effective friction
/// `μ = −τ/σ_yy` (positive when the cell resists a positive shear rate), the inertial number
/// `I = γ̇ d/√(P/ρ)` (GDR MiDi 2004; d the mean equal-area diameter, ρ the bodies' mean
/// density, P = σ_yy) and the cell's height.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CellMeasures {
    pub pressure: f64,
    pub shear_stress: f64,
    pub mu_eff: f64,
    pub inertial_number: f64,
    pub ly: f64,
}

impl CellMeasures {
    /// The measures of `cell` holding `bodies`.
    pub fn of(cell: &Cell, bodies: &[FrameBody]) -> Self {
        let n = bodies.len().max(1) as f64;
        let d = bodies
            .iter()
            .map(|b| 2.0 * b.shape.equal_area_radius())
            .sum::<f64>()
            / n;
        let rho = bodies.iter().map(|b| b.density).sum::<f64>() / n;
        let (p, tau) = (cell.normal_stress(), cell.shear_stress());
        CellMeasures {
            pressure: p,
            shear_stress: tau,
            mu_eff: if p > 0.0 { -tau / p } else { f64::NAN },
            inertial_number: if p > 0.0 {
                cell.shear_rate.abs() * d / (p / rho).sqrt()
            } else {
                f64::NAN
            },
            ly: cell.size.y,
        }
    }
}

/// The measures of `frame` over `region` (the wall box when `None`; without a wall box, the
/// bounding box of the bodies' outlines).
pub fn measure(frame: &Frame, region: Option<Window>) -> Measures {
    let cell_box = frame.cell.map(|c| Window {
        x0: 0.0,
        x1: c.size.x,
        y0: 0.0,
        y1: c.size.y,
    });
    let region = region
        .or(cell_box)
        .or(frame.wall_box)
        .unwrap_or_else(|| packing::bounding_window(&frame.bodies));
    let inside: Vec<bool> = frame
        .bodies
        .iter()
        .map(|b| region.contains(b.position))
        .collect();
    let stress = stress::love_weber(frame, &inside, region.area());
    let boundary_stress = match frame.wall_box {
        Some(b) => stress::boundary(frame, b).symmetric(),
        None => [f64::NAN; 3],
    };
    let coord = packing::coordination(frame, &inside);
    let fab = fabric::anisotropy(frame, &inside);
    Measures {
        time: frame.time,
        area: region.area(),
        stress: stress.symmetric(),
        boundary_stress,
        // A cell holds each body once (a body across a seam is there in two pieces).
        packing_fraction: match frame.cell {
            Some(c) => frame.bodies.iter().map(|b| b.shape.area()).sum::<f64>() / c.area(),
            None => packing::packing_fraction(&frame.bodies, region),
        },
        coordination: coord.with_rattlers,
        coordination_no_rattlers: coord.without_rattlers,
        rattler_fraction: coord.rattler_fraction,
        fabric: fab,
        orientation_order: fabric::orientation_order(frame, &inside).0,
        bodies: inside.iter().filter(|&&b| b).count(),
        contacts: frame.contacts.len(),
        cell: frame.cell.map(|c| CellMeasures::of(&c, &frame.bodies)),
    }
}
