//! CSV traces of a run: the trajectory (every `output_every` steps and the last step) and the
//! per-step quiescence measures. Writers only read the world.
//!
//! Rows are buffered and written in whole lines: when a write fails (a full disk), the file is
//! cut back to the last whole line written, so a trace never ends mid-line, and the error names
//! the file. Times are written as `step × dt` computed in decimal from `dt` as written
//! ([`time_text`]): `0.009`, not the float product `0.009000000000000001`.

use crate::dynamics::World;
use crate::dynamics::step::StepReport;
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

/// The time `step × dt` as the exact decimal product of `step` and `dt`'s shortest decimal form
/// (the double nearest to it, when read back). `dt = 1e-3`, step 9: `0.009`.
pub fn time_text(step: u64, dt: f64) -> String {
    let s = format!("{dt:e}");
    let decimal = s.split_once('e').and_then(|(mantissa, exp)| {
        let exp: i32 = exp.parse().ok()?;
        let (int, frac) = mantissa.split_once('.').unwrap_or((mantissa, ""));
        let digits: u128 = format!("{int}{frac}").parse().ok()?;
        let product = digits.checked_mul(u128::from(step))?;
        Some((product, exp - frac.len() as i32))
    });
    let Some((product, e10)) = decimal else {
        return format!("{}", step as f64 * dt);
    };
    if product == 0 {
        return "0".into();
    }
    let p = product.to_string();
    let len = p.len() as i32;
    let trim = |s: String| -> String {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    };
    if (0..=6).contains(&e10) {
        format!("{p}{}", "0".repeat(e10 as usize))
    } else if e10 < 0 && len + e10 > 0 {
        let cut = (len + e10) as usize;
        trim(format!("{}.{}", &p[..cut], &p[cut..]))
    } else if e10 < 0 && len + e10 > -6 {
        trim(format!("0.{}{p}", "0".repeat((-(len + e10)) as usize)))
    } else {
        let mantissa = trim(format!("{}.{}", &p[..1], &p[1..]));
        format!("{mantissa}e{}", e10 + len - 1)
    }
}

/// The time `step × dt` as a number (the double nearest to [`time_text`]).
pub fn time_value(step: u64, dt: f64) -> f64 {
    time_text(step, dt).parse().unwrap_or(step as f64 * dt)
}

/// A text file written in whole lines (see the module documentation).
pub(crate) struct LineFile {
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

/// The header of `trajectory.csv`.
pub const TRAJECTORY_HEADER: &str = "step,t,body,x,y,angle,vx,vy,omega";
/// The header of `trajectory.csv` in a periodic cell: the image counts after the rest (see
/// `dynamics::cell`).
pub const TRAJECTORY_HEADER_CELL: &str = "step,t,body,x,y,angle,vx,vy,omega,ix,iy";

/// `trajectory.csv`: `step,t,body,x,y,angle,vx,vy,omega` ([`TRAJECTORY_HEADER`]), full
/// round-trip precision; in a periodic cell the positions are the wrapped ones and each row
/// ends with the body's image counts `ix,iy` ([`TRAJECTORY_HEADER_CELL`]: the unwrapped
/// position is `x + ix L_x + iy S`, `y + iy L_y`, with S the cell's total Lees–Edwards shift).
pub struct TrajectoryWriter {
    out: LineFile,
    last_step: Option<u64>,
}

impl TrajectoryWriter {
    /// A new `trajectory.csv` at `path`, with the image counts when `cell` (a periodic cell).
    pub fn create(path: &Path, cell: bool) -> Result<Self, WriteError> {
        let mut out = LineFile::create(path)?;
        let header = if cell {
            TRAJECTORY_HEADER_CELL
        } else {
            TRAJECTORY_HEADER
        };
        out.line(format_args!("{header}"))?;
        // A run killed before its first full buffer still leaves a readable (empty) table.
        out.flush()?;
        Ok(TrajectoryWriter {
            out,
            last_step: None,
        })
    }

    /// One row per body for the world's current state (once per step).
    pub fn write(&mut self, world: &World) -> Result<(), WriteError> {
        self.write_labelled(world, world.step)
    }

    /// One row per body for the world's current state, labelled as step `step` (once per
    /// label). A step that failed part-way leaves the world at a state of that step, not of the
    /// last completed one.
    pub fn write_labelled(&mut self, world: &World, step: u64) -> Result<(), WriteError> {
        if self.last_step == Some(step) {
            return Ok(());
        }
        self.last_step = Some(step);
        let t = time_text(step, world.dt);
        let b = &world.bodies;
        for k in 0..b.len() {
            let p = &b.state[k].pose;
            let images = match b.image.get(k) {
                Some([ix, iy]) => format!(",{ix},{iy}"),
                None => String::new(),
            };
            self.out.line(format_args!(
                "{},{},{},{},{},{},{},{},{}{}",
                step,
                t,
                k,
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

    pub fn flush(&mut self) -> Result<(), WriteError> {
        self.out.flush()
    }
}

/// `increments.csv`: `step,t,mean_dx,mean_dy,mean_dtheta,unbalanced_force_ratio,contacts` —
/// P's quiescence measure (mean over bodies of the displacement increments of one step). The
/// unbalanced-force ratio costs a pass over every contact and body, which only output needs:
/// it is written on the rows the caller asks for (`dem2d run`: the output steps and the last
/// row) and left empty on the others.
pub struct IncrementsWriter {
    out: LineFile,
}

impl IncrementsWriter {
    pub fn create(path: &Path) -> Result<Self, WriteError> {
        let mut out = LineFile::create(path)?;
        out.line(format_args!(
            "step,t,mean_dx,mean_dy,mean_dtheta,unbalanced_force_ratio,contacts"
        ))?;
        out.flush()?;
        Ok(IncrementsWriter { out })
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_are_the_decimal_products_of_step_and_dt() {
        // Against the decimal text written by hand, and against the float product where that
        // is exact.
        assert_eq!(time_text(9, 1e-3), "0.009");
        assert_eq!(9.0 * 1e-3, 0.009000000000000001); // what the float product gives
        assert_eq!(time_value(9, 1e-3), 0.009);
        assert_eq!(time_text(0, 1e-5), "0");
        assert_eq!(time_text(7493, 1e-5), "0.07493");
        assert_eq!(time_text(120000, 1e-5), "1.2");
        assert_eq!(time_text(3, 2.5e-6), "0.0000075");
        assert_eq!(time_text(4, 2.5), "10");
        assert_eq!(time_text(3, 1e10), "3e10");
        assert_eq!(time_text(12, 1e-30), "1.2e-29");
        assert_eq!(time_text(1, 0.1), "0.1");
        assert_eq!(time_text(3, 0.1), "0.3");
        assert_eq!(time_text(1_000_000, 1e-6), "1");
        // Against the exact rational product, for dt's with long decimal forms.
        for (step, dt) in [(12345u64, 1.0 / 3.0), (987, std::f64::consts::PI * 1e-7)] {
            let v = time_value(step, dt);
            assert!(
                (v - step as f64 * dt).abs() <= 2.0 * f64::EPSILON * v,
                "{v}"
            );
        }
    }
}
