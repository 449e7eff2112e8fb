//! P's quiescence criterion: the mean over bodies of `|Δx|, |Δy|, |Δθ|` over one step, each at
//! most a threshold — held for a window of consecutive steps (a window of one is P's own
//! criterion; a rocking or bouncing body passes through zero velocity at its turning points,
//! where one step can satisfy it). How long it has held (the streak) is the run's progress
//! ([`super::RunProgress`]), kept by the [`super::Simulation`].

/// The criterion: a threshold and a window.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quiescence {
    pub threshold: f64,
    /// Consecutive steps the criterion must hold (≥ 1).
    pub window: u64,
}

impl Quiescence {
    /// At rest when every mean increment is at most `threshold` for `window` (≥ 1) steps.
    pub fn new(threshold: f64, window: u64) -> Self {
        Quiescence {
            threshold,
            window: window.max(1),
        }
    }

    /// Whether one step's increments meet the threshold.
    pub fn holds(&self, increments: &[f64; 3]) -> bool {
        increments.iter().all(|&d| d <= self.threshold)
    }

    /// Takes the increments of step `step` (the world's step count after it) and the streak
    /// before it; returns the streak after it, and the step at which rest began (the first
    /// step of the streak: P's count for a window of one) once the criterion has held for the
    /// window.
    pub fn observe(&self, streak: u64, step: u64, increments: &[f64; 3]) -> (u64, Option<u64>) {
        let streak = if self.holds(increments) {
            streak + 1
        } else {
            0
        };
        (streak, (streak >= self.window).then(|| step + 1 - streak))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rest_begins_at_the_first_step_of_the_streak() {
        let q = Quiescence::new(1e-3, 3);
        let (lo, hi) = ([1e-4; 3], [1e-4, 1e-2, 0.0]);
        let mut streak = 0;
        let mut at = Vec::new();
        for (step, inc) in [(1, lo), (2, hi), (3, lo), (4, lo), (5, lo)] {
            let (s, rest) = q.observe(streak, step, &inc);
            streak = s;
            at.push(rest);
        }
        assert_eq!(at, [None, None, None, None, Some(3)]);
        assert_eq!(Quiescence::new(1e-3, 1).observe(0, 7, &lo), (1, Some(7)));
        assert_eq!(Quiescence::new(1e-3, 0).window, 1);
    }
}
