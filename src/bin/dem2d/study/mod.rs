//! `dem2d study NAME`: the studies behind the README's tables that are not a single case — each
//! runs its cases through the library and prints a Markdown table (run from the repository: the
//! studies read `cases/`).

pub mod biaxial;
pub mod repose;
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
}

/// Runs `study`; `write_cases` also writes its case files into `cases/`.
pub fn run(study: Study, write_cases: bool) {
    match study {
        Study::RollingFig3 => rolling_fig3::run(),
        Study::Repose => repose::run(write_cases),
        Study::Biaxial => biaxial::run(write_cases),
    }
}
