//! `dem2d study NAME`: the studies behind the README's tables that are not a single case — each
//! runs its cases through the library and prints a Markdown table (run from the repository: the
//! studies read `cases/`).

use dem2d::run::RunError;

pub mod biaxial;
pub mod biaxial_shape;
pub mod impacts;
pub mod packing;
pub mod repose;
pub mod representation;
pub mod rolling_fig3;

/// The studies `dem2d study` runs.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum Study {
    /// P Fig. 3's thrown circle and ellipse with rolling resistance: when they come to rest.
    RollingFig3,
    /// The angle of repose of a 2D heap of disks against μ_r (CDT and EPSD).
    Repose,
    /// Servo compaction of 400 disks, then a biaxial test with servo side walls.
    Biaxial,
    /// Impact benchmarks (Chung & Ooi 2011) of a disk on a wall against closed forms; writes
    /// figures/impacts.svg and figures/impacts.md.
    Impacts,
    /// Biaxial tests of 400 (`--grains`) ellipses per aspect ratio (1, 1.5, 2, 2.5): stress ratio and
    /// volumetric strain, friction and dilatancy angles, fabric at the peak; writes
    /// figures/biaxial_shape.svg and figures/biaxial_shape.md.
    BiaxialShape,
    /// Packing fraction and coordination of bidisperse grains poured into a box against the
    /// aspect ratio (1–3), frictionless and μ = 0.5; writes figures/packing.svg and .md.
    Packing,
    /// The ellipse as the exact conic against equal-area 8–128-gons: P Fig. 2's drop (α = 1.5,
    /// 2, 3), P Fig. 4's settling and a poured pile of 300 (`--grains`) grains; error against
    /// cost; writes figures/representation_pareto.svg and figures/representation.md.
    Representation,
}

/// Runs `study`; `write_cases` also writes its case files into `cases/`; `grains` sets the
/// sample size of the studies that take one (the others ignore it). A run that blows up ends
/// the study with its report.
pub fn run(study: Study, write_cases: bool, grains: Option<usize>) -> Result<(), RunError> {
    match study {
        Study::RollingFig3 => rolling_fig3::run(),
        Study::Repose => repose::run(write_cases),
        Study::Biaxial => biaxial::run(write_cases),
        Study::Impacts => impacts::run(),
        Study::BiaxialShape => biaxial_shape::run(grains.unwrap_or(400), write_cases),
        Study::Packing => packing::run(grains.unwrap_or(packing::N), write_cases),
        Study::Representation => representation::run(grains.unwrap_or(packing::N)),
    }
}
