//! Progress lines on stderr for long runs: rewritten in place about once a second on a terminal;
//! in a log (stderr not a terminal) one full line every 30 s, so logs stay readable. A line
//! ([`line`]) gives the step, the simulated time, steps per second, the estimated time left (to
//! the end of the duration: a run that comes to rest stops sooner) and the unbalanced-force
//! ratio, PFC's and Yade's measure of how far the pile is from equilibrium.

use crate::dynamics::World;
use crate::run::{End, Observer, ObserverError, Plan, StepInfo};
use std::io::{IsTerminal, Write};
use std::time::{Duration, Instant};

/// Prints a progress line on stderr: rewritten in place on a terminal (`tty`), a whole line in
/// a log. Progress is a courtesy: a closed or full stderr must not stop the run.
fn print_line(tty: bool, text: &str) {
    let mut err = std::io::stderr().lock();
    let _ = if tty {
        write!(err, "\r{text}   ")
    } else {
        writeln!(err, "{text}")
    };
}

/// Throttled progress reporting; silent until `quiet_for` has passed since creation.
pub struct Progress {
    enabled: bool,
    tty: bool,
    start: Instant,
    last: Instant,
    quiet_for: Duration,
    shown: bool,
}

impl Progress {
    /// `enabled` false: never prints. `quiet_for`: nothing before this much wall time (short runs
    /// print nothing).
    pub fn new(enabled: bool, quiet_for: Duration) -> Progress {
        let now = Instant::now();
        Progress {
            enabled,
            tty: std::io::stderr().is_terminal(),
            start: now,
            last: now,
            quiet_for,
            shown: false,
        }
    }

    /// Whether a line is due now (then the caller formats it and calls [`Progress::show`]). One
    /// clock read.
    pub fn due(&self) -> bool {
        if !self.enabled {
            return false;
        }
        let now = Instant::now();
        let every = Duration::from_secs(if self.tty { 1 } else { 30 });
        now.duration_since(self.start) >= self.quiet_for
            && (!self.shown || now.duration_since(self.last) >= every)
    }

    /// Prints one progress line.
    pub fn show(&mut self, line: &str) {
        self.last = Instant::now();
        self.shown = true;
        print_line(self.tty, line);
    }

    /// Ends the in-place line on a terminal, if one was shown.
    pub fn finish(&self) {
        if self.shown && self.tty {
            let _ = writeln!(std::io::stderr());
        }
    }
}

/// Progress lines of a run (an observer): silent for its first two seconds, then a [`line`] when
/// one is due, not on the step the run stops at.
pub struct ProgressLines {
    name: String,
    enabled: bool,
    shown: Option<(Progress, Instant)>,
}

impl ProgressLines {
    /// Lines naming the run `name`; none unless `enabled`.
    pub fn new(name: &str, enabled: bool) -> Self {
        ProgressLines {
            name: name.to_string(),
            enabled,
            shown: None,
        }
    }
}

impl Observer for ProgressLines {
    fn start(&mut self, _: &World, _: &Plan) -> Result<(), ObserverError> {
        self.shown = Some((
            Progress::new(self.enabled, Duration::from_secs(2)),
            Instant::now(),
        ));
        Ok(())
    }

    fn after_step(&mut self, world: &World, info: &StepInfo) -> Result<(), ObserverError> {
        if let Some((progress, start)) = &mut self.shown
            && !info.stopping
            && progress.due()
        {
            // The unbalanced ratio costs a pass over the contacts: only when a line is due.
            progress.show(&line(&Fields {
                name: &self.name,
                step: info.step,
                steps: info.last.unwrap_or(info.step),
                time: world.time,
                elapsed: start.elapsed().as_secs_f64(),
                contacts: info.report.contacts,
                unbalanced: world.unbalanced_ratios().0,
            }));
        }
        Ok(())
    }

    fn finish(&mut self, _: &World, _: &End) -> Result<(), ObserverError> {
        if let Some((progress, _)) = &self.shown {
            progress.finish();
        }
        Ok(())
    }
}

/// What a progress line reports.
#[derive(Clone, Debug, PartialEq)]
pub struct Fields<'a> {
    pub name: &'a str,
    pub step: u64,
    pub steps: u64,
    /// Simulated time (s).
    pub time: f64,
    /// Wall time since the first step (s).
    pub elapsed: f64,
    pub contacts: usize,
    /// Mean net force on a body over the mean contact force (0 without contacts).
    pub unbalanced: f64,
}

/// One progress line, e.g. `pile: step 12000/400000 (3 %), t = 0.1200 s, 5210 steps/s, 1:14 left
/// (at most), 1803 contacts, unbalanced force ratio 2.1e-2`.
pub fn line(f: &Fields) -> String {
    let rate = if f.elapsed > 0.0 {
        f.step as f64 / f.elapsed
    } else {
        0.0
    };
    let left = if rate > 0.0 {
        format!(
            "{} left (at most)",
            duration((f.steps - f.step.min(f.steps)) as f64 / rate)
        )
    } else {
        "time left unknown".into()
    };
    format!(
        "{}: step {}/{} ({:.0} %), t = {:.4} s, {:.0} steps/s, {left}, {} contacts, unbalanced force ratio {:.1e}",
        f.name,
        f.step,
        f.steps,
        100.0 * f.step as f64 / f.steps.max(1) as f64,
        f.time,
        rate,
        f.contacts,
        f.unbalanced
    )
}

/// Progress lines of the runs of a longer command — a study, `dem2d verify`, `dem2d-lab
/// bench`'s settling — as `run` shows them ([`line`]), an observer of each run. The pace is the
/// process's, not the run's (a study of many short runs is one long command): nothing for its
/// first two seconds, then one line per second on a terminal, one per 30 s in a log, whichever
/// run is going. One clock read per step; the unbalanced ratio (a pass over the contacts) only
/// when a line is due.
pub struct CommandProgress {
    name: String,
    /// The run's first step and its last, if it has one.
    first: u64,
    last: Option<u64>,
    start: Instant,
    tty: bool,
    /// Whether this run showed a line (a terminal's in-place line then needs its newline).
    shown: bool,
}

/// When the process's first [`CommandProgress`] was made, and its last line (nanoseconds after
/// that; `u64::MAX`: none yet).
static PROCESS_START: std::sync::OnceLock<Instant> = std::sync::OnceLock::new();
static LAST_LINE: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(u64::MAX);

impl CommandProgress {
    /// Lines naming the run `name` (the study and its sample).
    pub fn new(name: impl Into<String>) -> Self {
        PROCESS_START.get_or_init(Instant::now);
        CommandProgress {
            name: name.into(),
            first: 0,
            last: None,
            start: Instant::now(),
            tty: std::io::stderr().is_terminal(),
            shown: false,
        }
    }

    /// Whether a line is due now (and, if so, it is counted as shown).
    fn due(&self) -> bool {
        use std::sync::atomic::Ordering;
        let origin = *PROCESS_START.get_or_init(Instant::now);
        let now = Instant::now().duration_since(origin).as_nanos() as u64;
        let every = if self.tty {
            1_000_000_000
        } else {
            30_000_000_000
        };
        let last = LAST_LINE.load(Ordering::Relaxed);
        let due = now >= 2_000_000_000 && (last == u64::MAX || now >= last.saturating_add(every));
        due && LAST_LINE
            .compare_exchange(last, now, Ordering::Relaxed, Ordering::Relaxed)
            .is_ok()
    }
}

impl Observer for CommandProgress {
    fn start(&mut self, world: &World, plan: &Plan) -> Result<(), ObserverError> {
        (self.first, self.last, self.start) = (world.step, plan.last, Instant::now());
        Ok(())
    }

    fn after_step(&mut self, world: &World, info: &StepInfo) -> Result<(), ObserverError> {
        if !info.stopping && self.due() {
            let text = line(&Fields {
                name: &self.name,
                step: info.step - self.first,
                steps: info.last.unwrap_or(info.step) - self.first,
                time: world.time,
                elapsed: self.start.elapsed().as_secs_f64(),
                contacts: info.report.contacts,
                unbalanced: world.unbalanced_ratios().0,
            });
            self.shown = true;
            print_line(self.tty, &text);
        }
        Ok(())
    }

    fn finish(&mut self, _: &World, _: &End) -> Result<(), ObserverError> {
        if std::mem::take(&mut self.shown) && self.tty {
            let _ = writeln!(std::io::stderr());
        }
        Ok(())
    }
}

/// A wall-clock duration as `m:ss` or `h:mm:ss` (rounded to the second).
pub fn duration(seconds: f64) -> String {
    let s = if seconds.is_finite() {
        seconds.max(0.0).round() as u64
    } else {
        u64::MAX / 2
    };
    let (h, m, s) = (s / 3600, s / 60 % 60, s % 60);
    if h > 0 {
        format!("{h}:{m:02}:{s:02}")
    } else {
        format!("{m}:{s:02}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_progress_line_gives_rate_time_left_and_the_unbalanced_ratio() {
        assert_eq!(duration(0.4), "0:00");
        assert_eq!(duration(74.0), "1:14");
        assert_eq!(duration(3725.0), "1:02:05");
        let l = line(&Fields {
            name: "pile",
            step: 12_000,
            steps: 400_000,
            time: 0.12,
            elapsed: 2.0,
            contacts: 1803,
            unbalanced: 0.0213,
        });
        // 6000 steps/s; 388 000 steps left take 64.7 s.
        assert_eq!(
            l,
            "pile: step 12000/400000 (3 %), t = 0.1200 s, 6000 steps/s, 1:05 left (at most), \
             1803 contacts, unbalanced force ratio 2.1e-2"
        );
    }
}
