//! CSV traces of a run: the trajectory (every `output_every` steps and the last step) and the
//! per-step quiescence measures. Writers only read the world; as observers of a run
//! ([`crate::run::Observer`]) they write at their cadences.
//!
//! Rows are buffered and written in whole lines: when a write fails (a full disk), the file is
//! cut back to the last whole line written, so a trace never ends mid-line, and the error names
//! the file. Times are written as `step × dt` computed in decimal from `dt` as written
//! ([`time_text`]): `0.009`, not the float product `0.009000000000000001`.

use crate::dynamics::StepReport;
use crate::dynamics::World;
use crate::run::time::time_text;
use crate::run::{End, Observer, ObserverError, Plan, StepInfo};
use std::fmt;
use std::fs::File;
use std::io::{self, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

/// A failed write: the file and the error.
#[derive(Debug)]
pub struct WriteError {
    pub file: PathBuf,
    pub error: io::Error,
}

impl fmt::Display for WriteError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: cannot write: {}", self.file.display(), self.error)
    }
}

impl std::error::Error for WriteError {}

/// What a write returns: nothing, or the write that failed.
pub type Written = Result<(), WriteError>;

/// A text file written in whole lines (see the module documentation).
pub struct LineFile {
    file: File,
    path: PathBuf,
    buf: Vec<u8>,
    /// Bytes of whole lines known to be in the file.
    committed: u64,
}

/// Buffered bytes that trigger a write.
const BUFFER: usize = 1 << 16;

impl LineFile {
    pub(crate) fn create(path: &Path) -> Result<Self, WriteError> {
        let file = File::create(path).map_err(|error| WriteError {
            file: path.to_path_buf(),
            error,
        })?;
        Ok(LineFile {
            file,
            path: path.to_path_buf(),
            buf: Vec::with_capacity(BUFFER + 1024),
            committed: 0,
        })
    }

    /// Appends one line (the text without its newline).
    pub(crate) fn line(&mut self, args: fmt::Arguments) -> Result<(), WriteError> {
        // Writing into a Vec cannot fail.
        let _ = self.buf.write_fmt(args);
        self.buf.push(b'\n');
        if self.buf.len() >= BUFFER {
            self.flush()?;
        }
        Ok(())
    }

    /// Writes the buffered lines; on failure cuts the file back to its last whole line.
    pub(crate) fn flush(&mut self) -> Result<(), WriteError> {
        let result = self
            .file
            .write_all(&self.buf)
            .and_then(|()| self.file.flush());
        match result {
            Ok(()) => {
                self.committed += self.buf.len() as u64;
                self.buf.clear();
                Ok(())
            }
            Err(error) => {
                // Shrinking needs no space; if even that fails, the write's error is the news.
                let _ = self.file.set_len(self.committed);
                let _ = self.file.seek(SeekFrom::Start(self.committed));
                self.buf.clear();
                Err(WriteError {
                    file: self.path.clone(),
                    error,
                })
            }
        }
    }
}

/// What one frame of a [`Frames`] file holds.
pub trait FrameRows {
    /// The file's name in the run's directory.
    const FILE: &'static str;
    /// The file's header line (empty: none).
    const HEADER: &'static str;
    /// The header line of this writer's file ([`FrameRows::HEADER`] unless it depends on the
    /// run).
    fn header(&self) -> &'static str {
        Self::HEADER
    }
    /// Writes the rows of `world` for the frame labelled `step`, at time `t` (as written).
    fn rows(&self, out: &mut LineFile, world: &World, step: u64, t: &str)
    -> Result<(), WriteError>;
}

/// A file with one block of rows per output frame, `R`'s — as an observer of a run, the start
/// (on disk at once, so that a run killed at any later moment leaves a whole frame), every
/// `every` steps (a blown-up state excepted: it is written once, as the last frame) and the
/// state the run ended in (`trajectory.csv`, `walls.csv`, `cell.csv`, `reactions.csv`).
pub struct Frames<R> {
    out: LineFile,
    last_step: Option<u64>,
    every: u64,
    rows: R,
}

impl<R: FrameRows> Frames<R> {
    /// Creates `R`'s file in `dir` with its header line, on disk at once (a run killed before
    /// its first full buffer still leaves a readable, empty table); as an observer it writes
    /// every `every` steps.
    pub fn create(dir: &Path, every: u64, rows: R) -> Result<Self, WriteError> {
        let mut out = LineFile::create(&dir.join(R::FILE))?;
        // (A file without a header line, such as a LAMMPS dump, has an empty one.)
        if !rows.header().is_empty() {
            out.line(format_args!("{}", rows.header()))?;
        }
        out.flush()?;
        Ok(Frames {
            out,
            last_step: None,
            every: every.max(1),
            rows,
        })
    }

    /// The frame of the world's current state (once per step).
    pub fn write(&mut self, world: &World) -> Result<(), WriteError> {
        self.write_labelled(world, world.step)
    }

    /// The frame of the world's current state, labelled as step `step` (once per label). A step
    /// that failed part-way leaves the world at a state of that step, not of the last completed
    /// one.
    pub fn write_labelled(&mut self, world: &World, step: u64) -> Result<(), WriteError> {
        if self.last_step == Some(step) {
            return Ok(());
        }
        self.last_step = Some(step);
        let t = time_text(step, world.dt);
        self.rows.rows(&mut self.out, world, step, &t)
    }

    pub fn flush(&mut self) -> Result<(), WriteError> {
        self.out.flush()
    }
}

impl<R: FrameRows> Observer for Frames<R> {
    fn start(&mut self, world: &World, _: &Plan) -> Result<(), ObserverError> {
        self.write(world)?;
        Ok(self.flush()?)
    }

    fn after_step(&mut self, world: &World, info: &StepInfo) -> Result<(), ObserverError> {
        if !info.blowup && info.step.is_multiple_of(self.every) {
            self.write_labelled(world, info.step)?;
        }
        Ok(())
    }

    fn finish(&mut self, world: &World, end: &End) -> Result<(), ObserverError> {
        self.write_labelled(world, end.step)?;
        Ok(self.flush()?)
    }
}

/// The header of `trajectory.csv`.
pub const TRAJECTORY_HEADER: &str = "step,t,body,x,y,angle,vx,vy,omega";
/// The header of `trajectory.csv` in a periodic cell: the image counts after the rest (see
/// `dynamics::cell`).
pub const TRAJECTORY_HEADER_CELL: &str = "step,t,body,x,y,angle,vx,vy,omega,ix,iy";

/// The rows of `trajectory.csv`: `step,t,body,x,y,angle,vx,vy,omega` ([`TRAJECTORY_HEADER`]),
/// one per body, full round-trip precision; in a periodic cell (`cell`) the positions are the
/// wrapped ones and each row ends with the body's image counts `ix,iy`
/// ([`TRAJECTORY_HEADER_CELL`]: the unwrapped position is `x + ix L_x + iy S`, `y + iy L_y`,
/// with S the cell's total Lees–Edwards shift).
pub struct Trajectory {
    pub cell: bool,
}

/// The writer of `trajectory.csv` (see [`Trajectory`] and [`Frames`]).
pub type TrajectoryWriter = Frames<Trajectory>;

impl FrameRows for Trajectory {
    const FILE: &str = "trajectory.csv";
    const HEADER: &str = TRAJECTORY_HEADER;
    fn header(&self) -> &'static str {
        match self.cell {
            true => TRAJECTORY_HEADER_CELL,
            false => TRAJECTORY_HEADER,
        }
    }
    fn rows(&self, out: &mut LineFile, world: &World, step: u64, t: &str) -> Written {
        let b = &world.bodies;
        for k in 0..b.len() {
            let p = &b.state[k].pose;
            let images = match b.image.get(k) {
                Some([ix, iy]) => format!(",{ix},{iy}"),
                None => String::new(),
            };
            out.line(format_args!(
                "{},{},{},{},{},{},{},{},{}{}",
                step,
                t,
                b.id[k],
                p.position.x,
                p.position.y,
                p.angle(),
                b.state[k].vel.x,
                b.state[k].vel.y,
                b.state[k].omega,
                images
            ))?;
        }
        Ok(())
    }
}

/// Per-step increments are written for runs of up to this many steps, thinned beyond.
pub const MAX_INCREMENT_ROWS: u64 = 200_000;

/// `increments.csv`: `step,t,mean_dx,mean_dy,mean_dtheta,unbalanced_force_ratio,contacts` —
/// P's quiescence measure (mean over bodies of the displacement increments of one step). The
/// unbalanced-force ratio costs a pass over every contact and body, which only output needs:
/// it is written on the rows the caller asks for and left empty on the others. As an observer:
/// every step of a run of up to [`MAX_INCREMENT_ROWS`] steps (thinned to about that many
/// beyond), the run's last step and the step it stopped at, with the ratio on the rows of the
/// output steps (every `ratio_every`) and the last.
pub struct IncrementsWriter {
    out: LineFile,
    ratio_every: u64,
    /// Steps between rows (from the run's plan).
    thin: u64,
}

impl IncrementsWriter {
    /// Creates the file (with its header); as an observer it gives the unbalanced-force ratio
    /// every `ratio_every` steps.
    pub fn create(path: &Path, ratio_every: u64) -> Result<Self, WriteError> {
        let mut out = LineFile::create(path)?;
        out.line(format_args!(
            "step,t,mean_dx,mean_dy,mean_dtheta,unbalanced_force_ratio,contacts"
        ))?;
        out.flush()?;
        Ok(IncrementsWriter {
            out,
            ratio_every: ratio_every.max(1),
            thin: 1,
        })
    }

    /// One row; the unbalanced-force ratio when `with_ratio`, else an empty field.
    pub fn write(
        &mut self,
        world: &World,
        r: &StepReport,
        with_ratio: bool,
    ) -> Result<(), WriteError> {
        let ratio = with_ratio.then(|| world.unbalanced_ratios().0);
        self.out.line(format_args!(
            "{},{},{:e},{:e},{:e},{},{}",
            world.step,
            time_text(world.step, world.dt),
            r.increments[0],
            r.increments[1],
            r.increments[2],
            Ratio(ratio),
            r.contacts
        ))
    }

    pub fn flush(&mut self) -> Result<(), WriteError> {
        self.out.flush()
    }
}

impl Observer for IncrementsWriter {
    fn start(&mut self, _: &World, plan: &Plan) -> Result<(), ObserverError> {
        self.thin = plan
            .last
            .map_or(1, |last| last.div_ceil(MAX_INCREMENT_ROWS).max(1));
        Ok(())
    }

    fn after_step(&mut self, world: &World, info: &StepInfo) -> Result<(), ObserverError> {
        let s = info.step;
        let last = info.last == Some(s);
        if info.blowup {
            self.write(world, &info.report, true)?;
        } else if s.is_multiple_of(self.thin) || last {
            // The unbalanced ratio (a pass over every contact) only on output steps.
            let ratio = s.is_multiple_of(self.ratio_every) || last;
            self.write(world, &info.report, ratio)?;
        } else if info.stopping {
            self.write(world, &info.report, true)?;
        }
        Ok(())
    }

    fn finish(&mut self, _: &World, _: &End) -> Result<(), ObserverError> {
        Ok(self.flush()?)
    }
}

/// An optional number as a CSV field: `{:e}`, or empty.
struct Ratio(Option<f64>);

impl std::fmt::Display for Ratio {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.0 {
            Some(v) => write!(f, "{v:e}"),
            None => Ok(()),
        }
    }
}
