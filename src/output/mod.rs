//! Output formats. Readers of results only: nothing here changes the world.

pub mod analysis;
pub mod contacts;
pub mod docs_tables;
pub mod forces;
pub mod outline;
pub mod panels;
pub mod plot;
pub mod progress;
pub mod run_data;
pub mod state;
pub mod summary;
pub mod trace;
pub mod vtk;
pub mod walls;
