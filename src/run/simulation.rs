//! The run driver: [`Simulation`].

use super::observer::{End, Moment, Observer, Plan, StepInfo};
use super::outcome::{RunError, Stop};
use super::progress::RunProgress;
use super::quiescence::Quiescence;
use super::watch::{self, BlowupReport, BlowupWatch};
use crate::dynamics::{StepReport, World};
use std::sync::atomic::{AtomicI32, Ordering};
use std::time::Instant;

/// Steps a world until a stop condition holds, feeding its observers (see the module
/// documentation of [`super`]). Built with the conditions and observers, then run once or in
/// several calls ([`Simulation::run`]: each call takes its own step budget); the world is
/// borrowed, and can be read between calls ([`Simulation::world`]).
pub struct Simulation<'a> {
    world: &'a mut World,
    /// The last step of the run's duration (counted from t = 0 of the whole run).
    last_step: Option<u64>,
    /// The run's end in time: no step is taken once the world's time has reached it.
    end_time: Option<f64>,
    /// The most steps one call of [`Simulation::run`] takes.
    max_steps: Option<u64>,
    quiescence: Option<Quiescence>,
    flag: Option<&'a AtomicI32>,
    watching: bool,
    observers: Vec<&'a mut dyn Observer>,
    /// Every how many steps the contact network's critical step is sampled.
    critical_dt_every: Option<u64>,
    progress: RunProgress,
    quiescent_step: Option<u64>,
    start_step: u64,
    wall_seconds: f64,
}

impl<'a> Simulation<'a> {
    /// A run of `world` from its current state, with no stop condition but a blow-up (the
    /// watch is on: [`Simulation::without_watch`]) and no observer. The watch's reference and the
    /// initial energy are the world's state now: its account starts closed, `E₀ = K + P + E_el +
    /// D − W` with the work `W` the state already holds (a state continued without its run's
    /// progress, such as `dem2d relax`'s, keeps the walls' work of the run that made it; booking
    /// it as created energy put the work of a compression into the `unaccounted` of the shear
    /// that followed: issue 41).
    pub fn new(world: &'a mut World) -> Self {
        let progress = RunProgress {
            initial_total: world.energies.total() - world.energies.boundary_work,
            quiescence_streak: 0,
            first_contact_step: None,
            contact_sum: 0,
            watch: BlowupWatch::new(world),
        };
        let start_step = world.step;
        Simulation {
            world,
            last_step: None,
            end_time: None,
            max_steps: None,
            quiescence: None,
            flag: None,
            watching: true,
            observers: Vec::new(),
            critical_dt_every: None,
            progress,
            quiescent_step: None,
            start_step,
            wall_seconds: 0.0,
        }
    }

    /// Continues a run whose progress was saved with the world's state (the world resumed from
    /// that state): its counters, its watch's reference and its quiescence streak (a run that
    /// stopped at rest asks for rest anew: its streak starts again when it reaches the window).
    pub fn resume(mut self, progress: RunProgress) -> Self {
        self.progress = progress;
        self
    }

    /// Stops with [`Stop::Completed`] after the world's step `last` (a case's duration:
    /// [`crate::scene::Case::steps`]; a continued run counts on from its state's step).
    pub fn until_step(mut self, last: u64) -> Self {
        self.last_step = Some(last);
        self
    }

    /// Stops with [`Stop::Completed`] once the world's time has reached `time` (no step is taken
    /// from a time at or past it).
    pub fn until_time(mut self, time: f64) -> Self {
        self.end_time = Some(time);
        self
    }

    /// Stops with [`Stop::MaxSteps`] after `n` steps of each call of [`Simulation::run`], unless
    /// the run's last step ([`Simulation::until_step`]) comes first.
    pub fn for_steps(mut self, n: u64) -> Self {
        self.max_steps = Some(n);
        self
    }

    /// Stops with [`Stop::AtRest`] when P's criterion has held for its window (`None`: never).
    pub fn quiescence(mut self, criterion: Option<Quiescence>) -> Self {
        self.quiescence = criterion;
        self
    }

    /// Stops with [`Stop::Interrupted`] after the step during which `flag` became non-zero (a
    /// signal handler sets it to the signal's number).
    pub fn stop_flag(mut self, flag: &'a AtomicI32) -> Self {
        self.flag = Some(flag);
        self
    }

    /// Without the blow-up watch (a non-finite state still ends the run): for runs meant to
    /// leave the stable range, or to create energy.
    pub fn without_watch(mut self) -> Self {
        self.watching = false;
        self
    }

    /// Adds an observer (called in the order added).
    pub fn observe(mut self, observer: &'a mut dyn Observer) -> Self {
        self.observers.push(observer);
        self
    }

    /// Samples the contact network's critical time step ([`World::network_critical_dt`], its
    /// smallest kept in the world's diagnostics) after every `every`-th step (not after a
    /// blow-up).
    pub fn sample_critical_dt(mut self, every: u64) -> Self {
        self.critical_dt_every = Some(every.max(1));
        self
    }

    pub fn world(&self) -> &World {
        self.world
    }

    pub fn world_mut(&mut self) -> &mut World {
        self.world
    }

    /// The run's progress (to save with the world's state).
    pub fn progress(&self) -> &RunProgress {
        &self.progress
    }

    /// The step at which rest began, once the run stopped at rest.
    pub fn quiescent_step(&self) -> Option<u64> {
        self.quiescent_step
    }

    /// The world's step when the simulation was made (0, or a saved state's).
    pub fn start_step(&self) -> u64 {
        self.start_step
    }

    /// Wall time of the steps of the last call of [`Simulation::run`] (the observers' first
    /// and last words not included), in seconds.
    pub fn wall_seconds(&self) -> f64 {
        self.wall_seconds
    }

    /// Steps until a stop condition holds; returns why it stopped, or the blow-up (the world
    /// is left in the state it was found in) or the observer's failure that ended it. The
    /// observers have had their last word either way.
    pub fn run(&mut self) -> Result<Stop, RunError> {
        self.drive(|_, _| false)
    }

    /// [`Simulation::run`], calling `each` after every step taken (with the world and the
    /// step's report), before the observers.
    pub fn run_each(
        &mut self,
        mut each: impl FnMut(&mut World, &StepReport),
    ) -> Result<Stop, RunError> {
        self.drive(|w, r| {
            each(w, r);
            false
        })
    }

    /// [`Simulation::run`], also stopping with [`Stop::Asked`] after the first step at which
    /// `stop` (called after every step taken, before the observers) returns true.
    pub fn run_until(
        &mut self,
        stop: impl FnMut(&mut World, &StepReport) -> bool,
    ) -> Result<Stop, RunError> {
        self.drive(stop)
    }

    fn drive(
        &mut self,
        mut asked: impl FnMut(&mut World, &StepReport) -> bool,
    ) -> Result<Stop, RunError> {
        let first = self.world.step;
        let budget = self.max_steps.map(|m| first.saturating_add(m));
        let last = match (self.last_step, budget) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
        // Reaching `last` completes the run unless the step budget cut it short.
        let at_last = match (last, self.last_step) {
            (Some(l), Some(d)) if l < d => Stop::MaxSteps,
            (Some(_), None) => Stop::MaxSteps,
            _ => Stop::Completed,
        };
        if let Some(q) = self.quiescence
            && self.progress.quiescence_streak >= q.window
        {
            self.progress.quiescence_streak = 0;
        }
        // Insertion and outflow at the start (at most once a step: see `dynamics::flow`).
        self.world.apply_flow();
        let plan = Plan { first, last };
        if asks_extras(&self.observers, Moment::Start(&plan)) {
            self.world.refresh_contact_extras();
        }
        let started = self
            .observers
            .iter_mut()
            .try_for_each(|o| o.start(self.world, &plan));
        let clock = Instant::now();
        let mut outcome = match started {
            Ok(()) => self.steps(last, at_last, &mut asked),
            Err(e) => Err(RunError::Observer(e)),
        };
        self.wall_seconds = clock.elapsed().as_secs_f64();
        // The observers' last word: the state the loop left, labelled with the step it belongs
        // to (a step that stopped part-way: that step).
        let (step, finite) = match &outcome {
            Err(RunError::Blowup(b)) => (b.step, !b.within_step),
            _ => (self.world.step, true),
        };
        let end = End {
            step,
            finite,
            outcome: &outcome,
            progress: &self.progress,
        };
        // Not on a state a step stopped part-way on: its contacts are not those of a whole step.
        if finite && asks_extras(&self.observers, Moment::Finish(&end)) {
            self.world.refresh_contact_extras();
        }
        for o in self.observers.iter_mut() {
            let end = End {
                step,
                finite,
                outcome: &outcome,
                progress: &self.progress,
            };
            if let Err(e) = o.finish(self.world, &end)
                && !matches!(outcome, Err(RunError::Observer(_)))
            {
                // The files are incomplete: that is how the run ended, even after a blow-up.
                outcome = Err(RunError::Observer(e));
            }
        }
        outcome
    }

    /// The step loop.
    fn steps(
        &mut self,
        last: Option<u64>,
        at_last: Stop,
        asked: &mut impl FnMut(&mut World, &StepReport) -> bool,
    ) -> Result<Stop, RunError> {
        let world = &mut *self.world;
        let progress = &mut self.progress;
        let ended = |w: &World| self.end_time.is_some_and(|t| w.time >= t);
        loop {
            if last.is_some_and(|l| world.step >= l) {
                return Ok(at_last);
            }
            if ended(world) {
                return Ok(Stop::Completed);
            }
            let report = match world.step() {
                Ok(r) => r,
                Err(b) => return Err(RunError::Blowup(BlowupReport::within_step(&b, world))),
            };
            // Bodies in and out between steps (a world without a flow: nothing).
            if world.flow.is_some() {
                world.apply_flow();
            }
            let s = world.step;
            progress.contact_sum += report.contacts as u64;
            if progress.first_contact_step.is_none() && report.contacts > 0 {
                progress.first_contact_step = Some(s);
            }
            let trigger = match self.watching {
                true => progress.watch.check(world),
                false => None,
            }
            .or_else(|| watch::cell_limit(world));
            let blowup = trigger.map(|t| BlowupReport::of_trigger(t, world));
            // The stop conditions, in order of precedence; the streak is kept before the
            // observers take the step (a checkpoint saves it with the state).
            let mut stop = None;
            let mut streak = progress.quiescence_streak;
            if blowup.is_none() {
                let caller = asked(world, &report);
                if let Some(q) = self.quiescence {
                    let (after, rest) = q.observe(streak, s, &report.increments);
                    streak = after;
                    stop = rest.map(|since| Stop::AtRest { since });
                }
                if stop.is_none()
                    && let Some(sig) = self.flag.map(|f| f.load(Ordering::Relaxed))
                    && sig != 0
                {
                    stop = Some(Stop::Interrupted(sig));
                }
                if stop.is_none() && caller {
                    stop = Some(Stop::Asked);
                }
                if stop.is_none() && last == Some(s) {
                    stop = Some(at_last);
                }
                if stop.is_none() && ended(world) {
                    stop = Some(Stop::Completed);
                }
            }
            if blowup.is_none() {
                progress.quiescence_streak = streak;
            }
            let info = StepInfo {
                step: s,
                report,
                last,
                stopping: blowup.is_some() || stop.is_some(),
                blowup: blowup.is_some(),
                progress: *progress,
            };
            let sampled = info
                .step
                .is_multiple_of(self.critical_dt_every.unwrap_or(u64::MAX))
                && !info.blowup;
            if sampled {
                world.network_critical_dt(); // (it refreshes the extras)
            } else if asks_extras(&self.observers, Moment::Step(&info)) {
                world.refresh_contact_extras();
            }
            for o in self.observers.iter_mut() {
                o.after_step(world, &info).map_err(RunError::Observer)?;
            }
            if let Some(b) = blowup {
                return Err(RunError::Blowup(b));
            }
            if let Some(stop) = stop {
                if let Stop::AtRest { since } = stop {
                    self.quiescent_step = Some(since);
                }
                return Ok(stop);
            }
        }
    }
}

/// Whether some observer reads the contacts' extras at `moment`.
fn asks_extras(observers: &[&mut dyn Observer], moment: Moment) -> bool {
    observers.iter().any(|o| o.reads_extras(moment))
}
