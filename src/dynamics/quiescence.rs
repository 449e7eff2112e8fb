//! P's quiescence criterion: the mean over bodies of `|Δx|, |Δy|, |Δθ|` over one step, each at
//! most a threshold — held for a window of consecutive steps (a window of one is P's own
//! criterion; a rocking or bouncing body passes through zero velocity at its turning points,
//! where one step can satisfy it).

/// The criterion and how long it has held.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quiescence {
    threshold: f64,
    window: u64,
    streak: u64,
}

impl Quiescence {
    /// At rest when every mean increment is at most `threshold` for `window` (≥ 1) steps.
    pub fn new(threshold: f64, window: u64) -> Self {
        Quiescence {
            threshold,
            window: window.max(1),
            streak: 0,
        }
    }

    /// Takes the increments of step `step` (the world's step count after it); returns the step
    /// at which rest began (the first step of the streak: P's count for a window of one) once
    /// the criterion has held for the window.
    pub fn observe(&mut self, step: u64, increments: &[f64; 3]) -> Option<u64> {
        if increments.iter().all(|&d| d <= self.threshold) {
            self.streak += 1;
        } else {
            self.streak = 0;
        }
        (self.streak >= self.window).then(|| step + 1 - self.streak)
    }

    /// Steps for which the criterion has held so far.
    pub fn streak(&self) -> u64 {
        self.streak
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rest_begins_at_the_first_step_of_the_streak() {
        let mut q = Quiescence::new(1e-3, 3);
        let (lo, hi) = ([1e-4; 3], [1e-4, 1e-2, 0.0]);
        assert_eq!(q.observe(1, &lo), None);
        assert_eq!(q.observe(2, &hi), None);
        assert_eq!(q.observe(3, &lo), None);
        assert_eq!(q.observe(4, &lo), None);
        assert_eq!(q.observe(5, &lo), Some(3));
        let mut p = Quiescence::new(1e-3, 1);
        assert_eq!(p.observe(7, &lo), Some(7));
    }
}
