//! Output formats. Readers of results only: nothing here changes the world.

pub mod analysis;
pub mod cell;
pub mod contacts;
pub mod discharge;
pub mod docs_tables;
pub mod dump;
pub mod fields;
pub mod force_statistics;
pub mod forces;
pub mod outline;
pub mod panels;
pub mod player;
pub mod plot;
pub mod progress;
pub mod reactions;
pub mod run_data;
pub mod run_dir;
pub mod state;
pub mod summary;
pub mod trace;
pub mod vtk;
pub mod walls;

/// Writes `text` to `dir/name` atomically: into `name.tmp`, synced, then renamed over it, so that
/// a reader sees the old file or the new one, never a torn one (a failed write removes the
/// temporary file and leaves the old one).
pub fn write_atomically(dir: &std::path::Path, name: &str, text: &str) -> std::io::Result<()> {
    use std::io::Write;
    let tmp = dir.join(format!("{name}.tmp"));
    let result = std::fs::File::create(&tmp).and_then(|mut f| {
        f.write_all(text.as_bytes())?;
        f.sync_all()
    });
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(e);
    }
    std::fs::rename(&tmp, dir.join(name))
}
