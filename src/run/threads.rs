//! How many worker threads a run may ask for.
//!
//! A run gives the same bits on any number of threads, so threads beyond the machine's cores
//! only add hand-offs; thousands of them (`--threads 20000`) put the machine's load above 1000
//! for minutes (issue 41). Every command that takes `--threads` (and the Python module's
//! `threads=`) refuses more than [`PER_CORE`] × the cores: a little over-subscription is
//! harmless (and lets a test ask for 2 threads on one core), more is a mistake.

/// Threads per core accepted.
pub const PER_CORE: usize = 4;

/// The cores of this machine (as the standard library sees them: 1 when it cannot tell).
pub fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The most worker threads accepted here: [`PER_CORE`] × [`cores`].
pub fn max_threads() -> usize {
    PER_CORE * cores()
}

/// Checks a number of worker threads asked for; the error says what is accepted (the caller
/// puts the option's name before it).
pub fn check_threads(n: usize) -> Result<(), String> {
    let (max, cores) = (max_threads(), cores());
    if n == 0 {
        return Err("must be at least 1".into());
    }
    if n > max {
        return Err(format!(
            "{n} threads asked for, at most {max} accepted ({PER_CORE} × the {cores} cores of \
             this machine): a run gives the same bits on any number of threads, and threads \
             beyond the cores only slow it"
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn four_threads_per_core_are_accepted_and_no_more() {
        let cores = std::thread::available_parallelism().unwrap().get();
        assert!(check_threads(1).is_ok());
        assert!(check_threads(4 * cores).is_ok());
        let e = check_threads(4 * cores + 1).unwrap_err();
        assert!(e.contains(&format!("at most {}", 4 * cores)), "{e}");
        assert_eq!(check_threads(0).unwrap_err(), "must be at least 1");
    }
}
