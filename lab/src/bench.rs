//! `dem2d bench`: throughput of settled piles of disks and ellipses at several sizes and thread
//! counts — particle-steps per second, nanoseconds per contact, heap bytes per body — and a check
//! that every thread count gives the same trajectory bit for bit.
//!
//! # How a settled pile is made
//! A pile of n ≤ 10⁴ bodies is generated ([`PileSpec`]) and settled under gravity at a larger
//! step (0.4 × the a-priori critical step, at most 5 × the case's) until its mean speed falls
//! below [`SETTLED_SPEED`] or [`SETTLE_TIME_MAX`] has passed; bigger piles are that many settled
//! 10⁴ piles side by side in one wide box. Settled piles are cached as case files (they are
//! ordinary cases: `dem2d run` runs them). The timed steps then run at the case's Δt = 1e-5 s,
//! every size, thread count and law of a shape interleaved block by block (see [`run`]).

use dem2d::contact_law::NormalForce;
use dem2d::dynamics::timestep::estimate_critical_dt;
use dem2d::dynamics::{BodyInit, StageTimes, World};
use dem2d::output::progress::CommandProgress;
use dem2d::run::Simulation;
use dem2d::scene::Case;
use dem2d::scene::generate::{PileShape, PileSpec, WIDTH_10K};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Mean speed (cm/s) below which a pile counts as settled for the benchmark.
pub const SETTLED_SPEED: f64 = 0.5;
/// Longest settling time (s of simulated time).
pub const SETTLE_TIME_MAX: f64 = 3.0;

/// What to measure.
#[derive(Clone, Debug)]
pub struct BenchOptions {
    pub shapes: Vec<PileShape>,
    pub sizes: Vec<usize>,
    /// Timed steps per repetition.
    pub steps: u64,
    /// Repetitions (the median is reported).
    pub reps: usize,
    /// Thread counts; the first is the reference for the identical-trajectory check.
    pub threads: Vec<usize>,
    /// The normal-force laws to time each pile under (the same settled state for each).
    pub normal_forces: Vec<NormalForce>,
    /// Where settled piles are cached (None: always settle).
    pub cache: Option<PathBuf>,
    /// Progress on stderr.
    pub progress: bool,
}

/// One measurement.
#[derive(Clone, Debug)]
pub struct BenchRow {
    pub shape: PileShape,
    pub n: usize,
    pub normal_force: NormalForce,
    pub threads: usize,
    pub steps: u64,
    /// Median wall time of one repetition (s).
    pub wall: f64,
    pub particle_steps_per_second: f64,
    /// Particle-steps per CPU-second of the process (all its threads), median over the
    /// repetitions: on a shared machine, steadier than the wall-clock rate.
    pub particle_steps_per_cpu_second: f64,
    /// Contacts (body–body and body–wall) per step, mean over the timed steps.
    pub contacts_per_step: f64,
    /// Wall time per contact-step (ns): the whole step's cost divided by its contacts.
    pub ns_per_contact: f64,
    /// Heap bytes held by the world (bodies, contacts, broad phase, buffers) per body: the
    /// larger of the allocator's count after the warm-up and the world's own account after
    /// the timed steps (so that a buffer first grown at a later list build counts).
    pub bytes_per_body: f64,
    /// Neighbour-list slots (candidate pairs) per body, and list builds per 1000 steps.
    pub slots_per_body: f64,
    pub builds_per_1000_steps: f64,
    /// Heap allocations per step during the timed steps.
    pub allocations_per_step: f64,
    /// The world's own account of its heap, by part (bytes per body).
    pub breakdown: Vec<(&'static str, f64)>,
    /// The final state is bit-identical to the first thread count's.
    pub identical: bool,
    /// Shares of the timed steps' wall time spent in neighbour-list builds and in the rest of
    /// the step's serial code (see `dem2d::dynamics::StageTimes`), summed over the blocks.
    pub list_share: f64,
    pub rest_share: f64,
}

/// An error of the bench command, as text.
#[derive(Debug)]
pub struct BenchError(pub String);

impl std::fmt::Display for BenchError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for BenchError {}

/// Mean speed of the bodies (cm/s).
fn mean_speed(w: &World) -> f64 {
    let b = &w.bodies;
    b.state.iter().map(|s| s.vel.norm()).sum::<f64>() / b.len().max(1) as f64
}

/// The bodies of `world` as case bodies (shape, pose, velocities).
fn bodies_of(w: &World) -> Vec<BodyInit> {
    let b = &w.bodies;
    (0..b.len())
        .map(|k| BodyInit {
            material: 0,
            prescribed: false,
            shape: b.shape[k],
            position: b.state[k].pose.position,
            angle: b.state[k].pose.angle(),
            velocity: b.state[k].vel,
            omega: b.state[k].omega,
            density: b.density[k],
        })
        .collect()
}

/// Settles a generated pile of n bodies; returns its case-file text.
fn settle(spec: &PileSpec, progress: bool) -> Result<String, BenchError> {
    let case = Case::from_json(&spec.case_json()).map_err(|e| BenchError(e.to_string()))?;
    let dt_crit = estimate_critical_dt(
        &dem2d::dynamics::Bodies::new(&case.bodies),
        &case.contact,
        &case.walls,
        case.gravity.norm(),
    );
    let dt = (0.4 * dt_crit).min(5.0 * case.dt);
    let mut w = case.clone().with_dt(dt).build_world();
    let start = Instant::now();
    let check = ((0.01 / dt).round() as u64).max(1);
    let mut speed = mean_speed(&w);
    // `dem2d run`'s line (the step's contacts, not the neighbour list's pairs).
    let mut lines = CommandProgress::new(format!("settling {}", spec.name()));
    let mut sim = Simulation::new(&mut w).until_time(SETTLE_TIME_MAX);
    if progress {
        sim = sim.observe(&mut lines);
    }
    sim.run_until(|w, _| {
        if !w.step.is_multiple_of(check) {
            return false;
        }
        speed = mean_speed(w);
        w.time > 0.2 && speed < SETTLED_SPEED
    })
    .map_err(|e| BenchError(format!("settling {}: {e}", spec.name())))?;
    drop(sim);
    let description = format!(
        "{} settled at Δt = {dt:.3e} s for {:.2} s (mean speed {speed:.3} cm/s; {:.0} s of wall time) by `dem2d bench`, from: {}",
        spec.name(),
        w.time,
        start.elapsed().as_secs_f64(),
        case.description
    );
    Ok(spec.case_text(
        &format!("{}_settled", spec.name()),
        &description,
        spec.width(),
        &bodies_of(&w),
    ))
}

/// The settled pile of `shape` with `n` bodies (from the cache when there).
pub fn settled_pile(
    shape: PileShape,
    n: usize,
    cache: Option<&Path>,
    progress: bool,
) -> Result<Case, BenchError> {
    let text = settled_pile_text(shape, n, cache, progress)?;
    Case::from_json(&text).map_err(|e| BenchError(e.to_string()))
}

/// The settled pile of `shape` with `n` bodies as case-file text (from the cache when there;
/// settled and cached otherwise).
pub fn settled_pile_text(
    shape: PileShape,
    n: usize,
    cache: Option<&Path>,
    progress: bool,
) -> Result<String, BenchError> {
    let spec = PileSpec::new(shape, n, 1);
    let file = cache.map(|d| d.join(format!("{}_settled.json", spec.name())));
    if let Some(f) = &file
        && let Ok(text) = std::fs::read_to_string(f)
    {
        Case::from_json(&text).map_err(|e| BenchError(format!("{}: {e}", f.display())))?;
        return Ok(text);
    }
    let text = if n > 10_000 && n.is_multiple_of(10_000) {
        // Tiles of the settled 10⁴ pile, side by side.
        let tile = settled_pile(shape, 10_000, cache, progress)?;
        let copies = n / 10_000;
        let mut bodies = Vec::with_capacity(n);
        for k in 0..copies {
            for b in &tile.bodies {
                let mut b = *b;
                b.position.x += WIDTH_10K * k as f64;
                bodies.push(b);
            }
        }
        let description = format!(
            "{copies} copies of the settled 10 000-body pile side by side in one box {} cm wide (by `dem2d bench`): {}",
            WIDTH_10K * copies as f64,
            tile.description
        );
        spec.case_text(
            &format!("{}_settled", spec.name()),
            &description,
            WIDTH_10K * copies as f64,
            &bodies,
        )
    } else {
        settle(&spec, progress)?
    };
    if let Some(f) = &file {
        if let Some(d) = f.parent() {
            std::fs::create_dir_all(d).map_err(|e| BenchError(format!("{}: {e}", d.display())))?;
        }
        std::fs::write(f, &text).map_err(|e| BenchError(format!("{}: {e}", f.display())))?;
    }
    Ok(text)
}

/// The bits of every body's state, hashed (FNV-1a): equal hashes ⇔ (with overwhelming
/// probability) bit-identical states.
fn state_hash(w: &World) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let b = &w.bodies;
    for k in 0..b.len() {
        let p = b.state[k].pose;
        for v in [
            p.position.x,
            p.position.y,
            p.angle(),
            b.state[k].vel.x,
            b.state[k].vel.y,
            b.state[k].omega,
        ] {
            for byte in v.to_bits().to_le_bytes() {
                h = (h ^ byte as u64).wrapping_mul(0x0100_0000_01b3);
            }
        }
    }
    h
}

/// Runs the benchmark; `heap` reports the bytes currently allocated (the binary's counting
/// allocator), so that the world's own footprint can be measured.
///
/// Every timed block of a shape — each size, thread count and law, each with its own world —
/// runs once per repetition, in turn (interleaved), so that a change of the machine's load hits
/// them alike: the ratios the table is read for (two threads over one, 10⁶ bodies against 10⁴,
/// one law against another) come from blocks timed side by side, not minutes apart.
pub fn run(
    opts: &BenchOptions,
    heap: &(dyn Fn() -> usize + Sync),
    allocations: &(dyn Fn() -> usize + Sync),
) -> Result<Vec<BenchRow>, BenchError> {
    let pools = opts
        .threads
        .iter()
        .map(|&threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .map_err(|e| BenchError(format!("thread pool of {threads}: {e}")))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let reps = opts.reps.max(1);
    let mut rows = Vec::new();
    for &shape in &opts.shapes {
        let mut runs = Vec::new();
        for &n in &opts.sizes {
            let settled = settled_pile(shape, n, opts.cache.as_deref(), opts.progress)?;
            for (p, (&threads, pool)) in opts.threads.iter().zip(&pools).enumerate() {
                for &normal_force in &opts.normal_forces {
                    let case = settled.clone().with_normal_force(normal_force);
                    let before = heap();
                    let mut w = case.build_world();
                    // Warm-up: contact histories, buffers at their working sizes.
                    pool.install(|| {
                        Simulation::new(&mut w)
                            .for_steps(opts.steps.min(200))
                            .run()
                            .map_err(|e| BenchError(e.to_string()))
                    })?;
                    let bytes = heap().saturating_sub(before);
                    let builds = w.contacts.builds;
                    runs.push(LawRun {
                        n,
                        threads,
                        pool: p,
                        normal_force,
                        w,
                        bytes,
                        builds,
                        walls: Vec::with_capacity(reps),
                        cpus: Vec::with_capacity(reps),
                        contacts: 0,
                        allocations: 0,
                        times: StageTimes::default(),
                    });
                }
            }
        }
        for _ in 0..reps {
            for run in &mut runs {
                pools[run.pool].install(|| -> Result<(), BenchError> {
                    let allocs = allocations();
                    let (start, cpu) = (Instant::now(), process_cpu_seconds());
                    let times = run.w.stage_times();
                    let contacts = &mut run.contacts;
                    Simulation::new(&mut run.w)
                        .for_steps(opts.steps)
                        .run_each(|_, r| *contacts += r.contacts as u64)
                        .map_err(|e| BenchError(e.to_string()))?;
                    run.walls.push(start.elapsed().as_secs_f64());
                    run.cpus.push(process_cpu_seconds() - cpu);
                    let now = run.w.stage_times();
                    let t = &mut run.times;
                    t.list_builds += now.list_builds - times.list_builds;
                    t.rest += now.rest - times.rest;
                    t.drift += now.total() - times.total();
                    run.allocations += allocations() - allocs;
                    Ok(())
                })?;
            }
        }
        // The identical-trajectory reference of each size and law: its first thread count's
        // final state (every world of one size and law has run the same steps).
        let mut reference: Vec<((usize, NormalForce), u64)> = Vec::new();
        for run in runs {
            let key = (run.n, run.normal_force);
            let row = run.row(shape, opts.steps, &mut reference, key);
            if opts.progress {
                let parts: Vec<String> = row
                    .breakdown
                    .iter()
                    .map(|(p, b)| format!("{p} {b:.0}"))
                    .collect();
                eprintln!(
                    "{:?} n = {}, {} law, {} thread(s): {:.2} M particle-steps/s ({:.2} M per CPU-second, {:.0} ns per contact); heap {:.0} B/body ({})",
                    shape,
                    row.n,
                    row.normal_force.as_str(),
                    row.threads,
                    row.particle_steps_per_second / 1e6,
                    row.particle_steps_per_cpu_second / 1e6,
                    row.ns_per_contact,
                    row.bytes_per_body,
                    parts.join(", ")
                );
            }
            rows.push(row);
        }
    }
    rows.sort_by_key(|r| (r.shape as u8, r.n, r.normal_force as u8, r.threads));
    Ok(rows)
}

/// One world (size, thread count, law) during an interleaved timing, and what its blocks
/// measured.
struct LawRun {
    n: usize,
    threads: usize,
    /// Its thread pool (an index into the run's pools).
    pool: usize,
    normal_force: NormalForce,
    w: World,
    bytes: usize,
    builds: u64,
    walls: Vec<f64>,
    cpus: Vec<f64>,
    contacts: u64,
    allocations: usize,
    /// The timed blocks' stage times (list builds, rest; all stages in `drift`).
    times: StageTimes,
}

impl LawRun {
    /// The table row: medians of the blocks; `references` holds, for each `key` (size, law),
    /// the hash of the final state's bits at the first thread count timed (set by its row).
    fn row(
        mut self,
        shape: PileShape,
        steps: u64,
        references: &mut Vec<((usize, NormalForce), u64)>,
        key: (usize, NormalForce),
    ) -> BenchRow {
        let (n, threads) = (self.n, self.threads);
        self.walls.sort_by(f64::total_cmp);
        self.cpus.sort_by(f64::total_cmp);
        let (wall, cpu) = (
            self.walls[self.walls.len() / 2],
            self.cpus[self.cpus.len() / 2],
        );
        let total_steps = steps * self.walls.len() as u64;
        let contacts_per_step = self.contacts as f64 / total_steps as f64;
        let w = &self.w;
        let breakdown = w.heap_breakdown();
        let held: usize = breakdown.iter().map(|&(_, bytes)| bytes).sum();
        BenchRow {
            shape,
            n,
            normal_force: self.normal_force,
            threads,
            steps,
            wall,
            particle_steps_per_second: n as f64 * steps as f64 / wall,
            particle_steps_per_cpu_second: n as f64 * steps as f64 / cpu,
            contacts_per_step,
            ns_per_contact: wall * 1e9 / (steps as f64 * contacts_per_step).max(1.0),
            bytes_per_body: self.bytes.max(held) as f64 / n as f64,
            slots_per_body: w.contacts.slots.len() as f64 / n as f64,
            builds_per_1000_steps: 1000.0 * (w.contacts.builds - self.builds) as f64
                / total_steps as f64,
            allocations_per_step: self.allocations as f64 / total_steps as f64,
            breakdown: breakdown
                .iter()
                .map(|&(part, bytes)| (part, bytes as f64 / n as f64))
                .collect(),
            list_share: self.times.list_builds / self.times.drift,
            rest_share: self.times.rest / self.times.drift,
            identical: {
                let hash = state_hash(w);
                match references.iter().find(|(k, _)| *k == key) {
                    Some(&(_, h)) => h == hash,
                    None => {
                        references.push((key, hash));
                        true
                    }
                }
            },
        }
    }
}

/// CPU seconds used by this process so far (all threads).
fn process_cpu_seconds() -> f64 {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes into the timespec we own; the clock id is valid.
    unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut t) };
    t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9
}

/// The rows as a Markdown table, with the speed-up over one thread where measured.
pub fn markdown(rows: &[BenchRow]) -> String {
    let mut t = String::from(
        "| pile | bodies | normal force | threads | steps × median wall (s) | particle-steps/s (M) | per CPU-second (M) | speed-up | contacts per body | slots per body | list builds per 1000 steps | ns per contact | heap bytes per body | allocations per step | list builds (% of step) | other serial (% of step) | same trajectory as 1 thread |\n|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n",
    );
    for r in rows {
        let one = rows
            .iter()
            .find(|o| {
                o.shape == r.shape
                    && o.n == r.n
                    && o.normal_force == r.normal_force
                    && o.threads == 1
            })
            .map(|o| o.particle_steps_per_second);
        let speedup = one.map_or(String::new(), |o| {
            format!("{:.2}×", r.particle_steps_per_second / o)
        });
        let kind = match r.shape {
            PileShape::Disks => "disks",
            PileShape::Ellipses => "ellipses",
        };
        writeln!(
            t,
            "| {kind} | {} | {} | {} | {} × {:.2} | {:.2} | {:.2} | {speedup} | {:.2} | {:.2} | {:.1} | {:.0} | {:.0} | {:.2} | {:.1} | {:.1} | {} |",
            r.n,
            r.normal_force.as_str(),
            r.threads,
            r.steps,
            r.wall,
            r.particle_steps_per_second / 1e6,
            r.particle_steps_per_cpu_second / 1e6,
            r.contacts_per_step / r.n as f64,
            r.slots_per_body,
            r.builds_per_1000_steps,
            r.ns_per_contact,
            r.bytes_per_body,
            r.allocations_per_step,
            100.0 * r.list_share,
            100.0 * r.rest_share,
            if r.identical { "yes" } else { "**no**" }
        )
        .expect("string");
    }
    t
}
