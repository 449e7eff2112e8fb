//! Output formats. Readers of results only: nothing here changes the world.

pub mod contacts;
pub mod summary;
pub mod trace;
