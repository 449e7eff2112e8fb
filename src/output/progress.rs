//! Progress lines on stderr for long runs: rewritten in place about once a second on a terminal;
//! in a log (stderr not a terminal) one full line every 30 s, so logs stay readable.

use std::io::{IsTerminal, Write};
use std::time::{Duration, Instant};

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
        // Progress is a courtesy: a closed or full stderr must not stop the run.
        let mut err = std::io::stderr().lock();
        let _ = if self.tty {
            write!(err, "\r{line}   ")
        } else {
            writeln!(err, "{line}")
        };
    }

    /// Ends the in-place line on a terminal, if one was shown.
    pub fn finish(&self) {
        if self.shown && self.tty {
            let _ = writeln!(std::io::stderr());
        }
    }
}
