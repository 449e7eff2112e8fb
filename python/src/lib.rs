//! `dem2d._core`: the extension module behind the Python package `dem2d` (python/dem2d/).
//!
//! A thin layer over the library: a case is read by `dem2d::scene` (the one JSON reader, with
//! its messages), a run is `dem2d::run::Simulation` with the writers of
//! `dem2d::output::run_dir` (the same code path as `dem2d run`), the measures are
//! `dem2d::analysis`'s, and a run directory is read back by `dem2d::output::run_data`. Nothing
//! here computes physics.
//!
//! # Threads, the GIL and Ctrl-C
//! A run steps on a worker thread inside the simulation's own rayon pool, with the GIL released;
//! the calling thread waits for it, taking the GIL back every 50 ms to let Python handle its
//! signals (`PyErr_CheckSignals`, effective on the main thread). A signal handler that raises
//! (Ctrl-C: `KeyboardInterrupt`) raises the run's stop flag: the run stops after its current
//! step, its observers have their last word (the last frame, `state.json`, the summary with
//! status `interrupted`), and the exception is raised again. `Simulation.interrupt()` raises
//! the same flag from any thread.

use dem2d::analysis::{self, Frame, Window};
use dem2d::dynamics::{Partner, World};
use dem2d::geometry::Shape;
use dem2d::output::run_dir::{Counts, RunDir, RunError as DirError, RunOptions, continued};
use dem2d::output::summary::Status;
use dem2d::run::{RunError as RunFailure, RunProgress, Simulation as Driver, Stop};
use dem2d::scene::{CaseFile, FieldError};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::IntoPyObjectExt;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::PathBuf;
use std::sync::Mutex;
use std::sync::atomic::{AtomicI32, Ordering};
use std::time::Duration;

/// The allocator of the `dem2d` binary (huge pages for large blocks: [`dem2d::alloc`]), so that
/// a world steps here as fast as there; it serves the extension's own Rust allocations only.
#[global_allocator]
static GLOBAL: dem2d::alloc::HugePageAllocator = dem2d::alloc::HugePageAllocator;

/// SIGINT's number: what Ctrl-C and `Simulation.interrupt()` put in the stop flag.
const SIGINT: i32 = 2;

/// An exception of `dem2d` (the classes are in python/dem2d/_errors.py, so that they can derive
/// from both `dem2d.Error` and the built-in they stand for) with `message` and attributes.
fn error(py: Python<'_>, class: &str, message: String, attrs: &[(&str, Py<PyAny>)]) -> PyErr {
    let made = (|| -> PyResult<PyErr> {
        let cls = py.import("dem2d._errors")?.getattr(class)?;
        let e = cls.call1((message.clone(),))?;
        for (k, v) in attrs {
            e.setattr(*k, v)?;
        }
        Ok(PyErr::from_value(e))
    })();
    made.unwrap_or_else(|e| e)
}

/// `dem2d.InputError` for a field error (the message as `dem2d` prints it, after `prefix`).
fn field_error(py: Python<'_>, prefix: Option<&str>, e: &FieldError) -> PyErr {
    let message = match prefix {
        Some(p) => format!("{p}: {e}"),
        None => e.to_string(),
    };
    let field = e.path.clone().into_py_any(py).expect("a string");
    error(py, "InputError", message, &[("field", field)])
}

fn input_error(py: Python<'_>, message: String) -> PyErr {
    error(py, "InputError", message, &[("field", py.None())])
}

/// A whole number ≥ 0 given for the argument `name` (a Python int, or a numpy integer), else
/// `dem2d.InputError` naming it and what is accepted: a negative number, a float or a string
/// is refused by name (not as an `OverflowError` or a `TypeError` from the conversion).
fn whole(py: Python<'_>, name: &str, v: &Bound<'_, PyAny>) -> PyResult<u64> {
    let refuse = || {
        input_error(
            py,
            format!(
                "{name}: must be a whole number ≥ 1, got {}",
                v.repr().map_or_else(|_| "?".to_string(), |r| r.to_string())
            ),
        )
    };
    if v.is_instance_of::<pyo3::types::PyBool>() {
        return Err(refuse());
    }
    let i = v
        .call_method0("__index__")
        .map_err(|_| refuse())?
        .extract::<i128>()
        .map_err(|_| refuse())?;
    u64::try_from(i).map_err(|_| refuse())
}

/// A scene: the case file's keys (docs/src/reference/case-file.md), read by dem2d's own reader.
///
/// `Case(d)` from a dict (numpy values allowed), `Case.load(path)` from a case file or a run's
/// `state.json` (a Simulation of it continues that run), `Case.from_json(text)`. Bad input raises
/// `dem2d.InputError` with the command line's message; its `field` names the field.
/// `to_json()`, `save(path)` and `to_dict()` give the case back exactly.
#[pyclass(frozen, module = "dem2d")]
struct Case {
    file: CaseFile,
    /// The JSON text (a file's, or the one made from a dict): what `case.json` and
    /// [`Case::to_json`] give back.
    text: String,
    /// The file it was read from.
    source: Option<PathBuf>,
}

impl Case {
    fn parse(py: Python<'_>, text: String, source: Option<PathBuf>) -> PyResult<Case> {
        let prefix = source.as_ref().map(|p| p.display().to_string());
        let file =
            CaseFile::from_json(&text).map_err(|e| field_error(py, prefix.as_deref(), &e))?;
        Ok(Case { file, text, source })
    }

    fn scene(&self) -> &dem2d::scene::Case {
        &self.file.case
    }
}

#[pymethods]
impl Case {
    /// A case from a dict of the case file's keys (numpy arrays and numbers allowed): its JSON
    /// text is made by `dem2d._json.dumps` (exact: floats written by `repr`).
    #[new]
    fn new(py: Python<'_>, spec: &Bound<'_, PyAny>) -> PyResult<Case> {
        if !spec.is_instance_of::<PyDict>() {
            return Err(error(
                py,
                "InputError",
                format!(
                    "a case is a dict of the case file's keys, got {}; read a file with \
                     dem2d.Case.load(path), JSON text with dem2d.Case.from_json(text)",
                    spec.get_type().name()?
                ),
                &[("field", py.None())],
            ));
        }
        let text: String = py
            .import("dem2d._json")?
            .getattr("dumps")?
            .call1((spec,))?
            .extract()?;
        Case::parse(py, text, None)
    }

    /// A case from its JSON text (`source`: the file it came from, for messages).
    #[staticmethod]
    #[pyo3(signature = (text, source=None))]
    fn from_json(py: Python<'_>, text: String, source: Option<PathBuf>) -> PyResult<Case> {
        Case::parse(py, text, source)
    }

    /// A case or state file, read as `dem2d run` reads it (size limit, messages).
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Case> {
        let name = path.display().to_string();
        let text = dem2d::scene::ranges::read_input(&name)
            .map_err(|e| input_error(py, format!("{name}: {e}")))?;
        Case::parse(py, text, Some(path))
    }

    /// The JSON text, exactly as given (a file's bytes; for a dict, the text made from it).
    fn to_json(&self) -> String {
        self.text.clone()
    }

    /// The case's keys as a dict (the JSON text read back: every number bit for bit).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        py.import("json")?
            .getattr("loads")?
            .call1((self.text.as_str(),))
    }

    /// Writes the JSON text to `path`, byte for byte what `to_json()` gives.
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        std::fs::write(&path, &self.text).map_err(|e| {
            error(
                py,
                "OutputError",
                format!("{}: cannot write: {e}", path.display()),
                &[],
            )
        })
    }

    #[getter]
    fn source(&self) -> Option<PathBuf> {
        self.source.clone()
    }

    #[getter]
    fn name(&self) -> String {
        self.scene().name.clone()
    }

    #[getter]
    fn dt(&self) -> f64 {
        self.scene().dt
    }

    #[getter]
    fn duration(&self) -> f64 {
        self.scene().duration
    }

    /// The steps of the case's duration.
    #[getter]
    fn steps(&self) -> u64 {
        self.scene().steps()
    }

    #[getter]
    fn gravity(&self) -> (f64, f64) {
        let g = self.scene().gravity;
        (g.x, g.y)
    }

    #[getter]
    fn n_bodies(&self) -> usize {
        self.scene().bodies.len()
    }

    #[getter]
    fn n_walls(&self) -> usize {
        self.scene().walls.len()
    }

    /// The step a state file continues from (None for a case that starts at t = 0).
    #[getter]
    fn state_step(&self) -> Option<u64> {
        self.file.restart.as_ref().map(|s| s.step)
    }

    /// What reading the file found worth telling (as `dem2d run` prints them).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.file.warnings.clone()
    }

    fn __eq__(&self, other: &Case) -> bool {
        self.text == other.text
    }

    fn __repr__(&self) -> String {
        let c = self.scene();
        format!(
            "dem2d.Case(name={:?}, bodies={}, walls={}, dt={:e}, duration={}{})",
            c.name,
            c.bodies.len(),
            c.walls.len(),
            c.dt,
            c.duration,
            match &self.file.restart {
                Some(s) => format!(", state at step {}", s.step),
                None => String::new(),
            }
        )
    }
}

/// What a simulation holds between calls.
struct Inner {
    world: World,
    case: Py<Case>,
    /// The run's progress (carried from call to call, as one run's).
    progress: RunProgress,
    /// The counts of the run so far (wall time summed over the calls).
    counts: Counts,
    files: Option<RunDir>,
    pool: rayon::ThreadPool,
    /// Wall time of the last call's steps (s).
    last_wall: f64,
    /// `close()` released the output directory (runs are then refused).
    closed: bool,
}

/// A run of a case: `Simulation(case, *, threads=None, out=None, overwrite=False, vtk=None,
/// analysis=False, contacts=False, progress=False)`.
///
/// `case`: a `dem2d.Case`, a dict of the case file's keys or a file's path. `threads`: the
/// simulation's worker threads (default: one per core; the same bits for any number). `out`:
/// a directory to write the files of `dem2d run --out` into (refused when it holds an earlier
/// run's, unless `overwrite`); `analysis`, `contacts`, `vtk` (True, or the steps between frames)
/// as `dem2d run --analysis`, `--contacts`, `--vtk-every`; `progress`: its progress line on
/// stderr. Step it with `run()`; read its state as numpy arrays (`positions`, `angles`,
/// `velocities`, `spins`, `forces`, `torques`, `masses`, `shapes()`, `contacts()`,
/// `analysis()`, `energies()`).
#[pyclass(frozen, module = "dem2d")]
struct Simulation {
    inner: Mutex<Inner>,
    /// Raised (to a signal number) to stop the run after its current step.
    stop: AtomicI32,
    threads: usize,
}

impl Simulation {
    /// The inner state, or an error when a run holds it (in another thread).
    fn lock<'s>(&'s self, py: Python<'_>) -> PyResult<std::sync::MutexGuard<'s, Inner>> {
        self.inner.try_lock().map_err(|_| {
            error(
                py,
                "RunError",
                "the simulation is running (in another thread): wait for its run to end, or \
                 call interrupt()"
                    .into(),
                &[],
            )
        })
    }
}

/// What a run was asked to do.
struct Ask {
    steps: Option<u64>,
    until_step: Option<u64>,
    rest: Option<dem2d::run::Quiescence>,
}

/// How one call's run ended, with its counts and progress.
type Ran = (Result<Stop, RunFailure>, Counts, RunProgress);

#[pymethods]
impl Simulation {
    #[new]
    #[pyo3(signature = (case, *, threads=None, out=None, overwrite=false, vtk=None,
                        analysis=false, contacts=false, dump=false, progress=false,
                        checkpoint_every=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        case: &Bound<'_, PyAny>,
        threads: Option<&Bound<'_, PyAny>>,
        out: Option<PathBuf>,
        overwrite: bool,
        vtk: Option<&Bound<'_, PyAny>>,
        analysis: bool,
        contacts: bool,
        dump: bool,
        progress: bool,
        checkpoint_every: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Simulation> {
        let case: Py<Case> = if let Ok(c) = case.cast::<Case>() {
            c.clone().unbind()
        } else if case.is_instance_of::<PyDict>() {
            Py::new(py, Case::new(py, case)?)?
        } else if let Ok(path) = case.extract::<PathBuf>() {
            Py::new(py, Case::load(py, path)?)?
        } else {
            return Err(input_error(
                py,
                format!(
                    "case: give a dem2d.Case, a dict of the case file's keys or a file's path, \
                     got {}",
                    case.get_type().name()?
                ),
            ));
        };
        let c = case.get();
        let scene = c.scene();
        // Any whole number is read (a negative one is refused by name, not as an OverflowError),
        // then held to the command line's limit (`dem2d::run::threads`).
        let threads = threads
            .map(|v| whole(py, "threads", v))
            .transpose()?
            .map(|n| {
                let n = usize::try_from(n).unwrap_or(usize::MAX);
                dem2d::run::threads::check_threads(n)
                    .map(|()| n)
                    .map_err(|e| input_error(py, format!("threads: {e}")))
            })
            .transpose()?;
        // What the case's reader found worth telling (Δt above the critical step, units, …),
        // as `dem2d run` prints them: Python's warnings (`UserWarning`), once each.
        for w in &c.file.warnings {
            PyErr::warn(
                py,
                &py.get_type::<pyo3::exceptions::PyUserWarning>(),
                &std::ffi::CString::new(format!("dem2d: {w}")).unwrap_or_default(),
                1,
            )?;
        }
        // `vtk=True`: the case's `output.vtk_every`, else its `output_every`; a number: the
        // steps between frames; False or None: as the case says (`output.vtk`).
        let case_vtk = scene.output.vtk_every.unwrap_or(scene.output_every);
        let vtk: Option<u64> = match vtk {
            None => scene.output.vtk.then_some(case_vtk),
            Some(v) if v.is_instance_of::<pyo3::types::PyBool>() => {
                (v.extract::<bool>()? || scene.output.vtk).then_some(case_vtk)
            }
            Some(v) => match v.extract::<u64>() {
                Ok(n) if n >= 1 => Some(n),
                _ => {
                    return Err(input_error(
                        py,
                        format!("vtk: True, or the steps between frames (at least 1), got {v}"),
                    ));
                }
            },
        };
        // `checkpoint_every=N`: `dem2d run --checkpoint-every N` (state.json every N steps).
        let checkpoint_every = match checkpoint_every {
            None => None,
            Some(v) => match whole(py, "checkpoint_every", v)? {
                0 => {
                    return Err(input_error(
                        py,
                        "checkpoint_every: at least 1 step, got 0".to_string(),
                    ));
                }
                n => Some(n),
            },
        };
        let mut builder = rayon::ThreadPoolBuilder::new();
        if let Some(n) = threads {
            builder = builder.num_threads(n);
        }
        let pool = builder
            .build()
            .map_err(|e| error(py, "RunError", format!("thread pool: {e}"), &[]))?;
        let mut world = c.file.build_world();
        let resumed = c.file.run.as_ref().map(|p| continued(p, scene));
        let progress_now = match &resumed {
            Some(p) => *p,
            None => *Driver::new(&mut world).progress(),
        };
        let files = match out {
            None => None,
            Some(dir) => {
                let opts = RunOptions {
                    out_dir: dir,
                    progress,
                    max_steps: None,
                    overwrite,
                    stop: None,
                    vtk_every: vtk,
                    dump,
                    analysis: analysis || scene.output.analysis,
                    checkpoint_every,
                    contacts: contacts || scene.output.contacts,
                    analysis_window: scene.output.analysis_window,
                    restart: c.file.restart.clone(),
                    run: c.file.run,
                    input: c.source.clone(),
                    warnings: c.file.warnings.clone(),
                };
                let files =
                    RunDir::open(scene, &c.text, &mut world, &opts).map_err(|e| match e {
                        DirError::Occupied { .. } | DirError::Locked { .. } => {
                            input_error(py, e.to_string())
                        }
                        DirError::State(_) => input_error(py, e.to_string()),
                        DirError::Io(_) => error(py, "OutputError", e.to_string(), &[]),
                    })?;
                Some(files)
            }
        };
        let counts = Counts {
            quiescent_step: None,
            first_contact_step: progress_now.first_contact_step,
            contact_sum: progress_now.contact_sum,
            wall_seconds: 0.0,
            start_step: world.step,
        };
        let threads = pool.current_num_threads();
        Ok(Simulation {
            inner: Mutex::new(Inner {
                world,
                case,
                progress: progress_now,
                counts,
                files,
                pool,
                last_wall: 0.0,
                closed: false,
            }),
            stop: AtomicI32::new(0),
            threads,
        })
    }

    /// Steps the world and returns how the run stopped: `"completed"` (the steps asked for by
    /// `duration`, or to the case's duration), `"max_steps"` (the `steps` asked for),
    /// `"at_rest"` (the case's quiescence criterion held for its window) or `"interrupted"`
    /// (`interrupt()` from another thread).
    ///
    /// - `run()`: to the end of the case's duration, as `dem2d run` (the same frames and files).
    /// - `run(steps)`: `steps` more steps, as `dem2d run --max-steps`.
    /// - `run(duration=d)`: `d` seconds more (rounded to whole steps).
    /// - `until_rest`: None (default) stops at rest when the case gives `quiescence`, as
    ///   `dem2d run` does; True requires it; False never stops at rest.
    ///
    /// The GIL is released while stepping. Ctrl-C stops the run after its current step, writes
    /// its files as an interrupted `dem2d run` does, and raises `KeyboardInterrupt`. A blow-up
    /// raises `dem2d.BlowupError` naming the step and the body (attributes `step`, `body`,
    /// `time`, `reason`); a failed write, `dem2d.OutputError`. With an output directory each
    /// call ends with a trajectory frame, `state.json` and `summary.json`.
    #[pyo3(signature = (steps=None, *, duration=None, until_rest=None))]
    fn run(
        &self,
        py: Python<'_>,
        steps: Option<&Bound<'_, PyAny>>,
        duration: Option<f64>,
        until_rest: Option<bool>,
    ) -> PyResult<String> {
        // Any whole number is read: `run(-5)` is refused by name (it was an OverflowError).
        let steps = steps.map(|v| whole(py, "steps", v)).transpose()?;
        let mut guard = self.lock(py)?;
        let inner = &mut *guard;
        if inner.closed {
            return Err(error(
                py,
                "RunError",
                "the simulation was closed (its output directory released): make a new one, from \
                 its state.json to continue"
                    .into(),
                &[],
            ));
        }
        let case_obj = inner.case.clone_ref(py);
        let case = case_obj.get().scene();
        if steps.is_some() && duration.is_some() {
            return Err(input_error(
                py,
                "run: give steps or duration, not both".into(),
            ));
        }
        if steps == Some(0) {
            return Err(input_error(py, "steps: must be at least 1, got 0".into()));
        }
        let world_step = inner.world.step;
        let until_step = match duration {
            Some(d) => {
                if !(d.is_finite() && d > 0.0) {
                    return Err(input_error(
                        py,
                        format!("duration: must be a positive time (s), got {d}"),
                    ));
                }
                dem2d::scene::ranges::check_steps(d, case.dt)
                    .map_err(|e| input_error(py, format!("duration: {}", e.message)))?;
                Some(world_step + (d / case.dt).round().max(1.0) as u64)
            }
            None if steps.is_none() => {
                if world_step >= case.steps() {
                    return Err(input_error(
                        py,
                        format!(
                            "the simulation is at step {world_step} (t = {} s), already at the end \
                             of the case's duration ({} s, {} steps): give steps= or duration= to \
                             run further",
                            dem2d::run::time::time_text(world_step, case.dt),
                            case.duration,
                            case.steps()
                        ),
                    ));
                }
                Some(case.steps())
            }
            None => None,
        };
        let rest = match until_rest {
            None => case.quiescence_criterion(),
            Some(false) => None,
            Some(true) => Some(case.quiescence_criterion().ok_or_else(|| {
                input_error(
                    py,
                    "until_rest: the case has no `quiescence` (the rest criterion): give it in the \
                     case (and `quiescence_window`)"
                        .into(),
                )
            })?),
        };
        let ask = Ask {
            steps,
            until_step,
            rest,
        };
        self.stop.store(0, Ordering::Relaxed);
        let (ran, pending) = self.drive(py, inner, &ask);
        let (outcome, counts, progress) = ran;
        inner.progress = progress;
        let acc = &mut inner.counts;
        acc.quiescent_step = counts.quiescent_step;
        acc.first_contact_step = counts.first_contact_step;
        acc.contact_sum = counts.contact_sum;
        acc.wall_seconds += counts.wall_seconds;
        inner.last_wall = counts.wall_seconds;
        let acc = *acc;
        let (status, blowup, io_error) = match inner.files.as_mut() {
            Some(files) => {
                let o = files.finish(case, &mut inner.world, outcome, &acc);
                let io = match (o.io_error, o.summary_error) {
                    (Some(a), Some(b)) => Some(format!("{a}; then {b}")),
                    (a, b) => a.or(b),
                };
                (o.summary.status, o.blowup, io)
            }
            None => {
                let status = Status::of(&outcome);
                match outcome {
                    Err(RunFailure::Blowup(b)) => (status, Some(b), None),
                    Err(RunFailure::Observer(e)) => (status, None, Some(e.to_string())),
                    Ok(_) => (status, None, None),
                }
            }
        };
        let kept = inner
            .files
            .as_ref()
            .map(|f| format!("; output so far kept in {}", f.dir().display()))
            .unwrap_or_default();
        if let Some(e) = io_error {
            return Err(error(py, "OutputError", e, &[]));
        }
        if let Some(b) = blowup {
            let attrs = [
                ("step", b.step.into_py_any(py)?),
                ("body", b.body.into_py_any(py)?),
                ("time", b.time.into_py_any(py)?),
                ("reason", b.reason.clone().into_py_any(py)?),
            ];
            return Err(error(py, "BlowupError", format!("{b}{kept}"), &attrs));
        }
        if let Some(e) = pending {
            return Err(e);
        }
        Ok(status.as_str().to_string())
    }

    /// Releases the output directory (its lock; every file was written at the end of the last
    /// run) and refuses further runs. A simulation without one is only marked closed. Also what
    /// leaving a `with` block does.
    fn close(&self, py: Python<'_>) -> PyResult<()> {
        let mut g = self.lock(py)?;
        g.files = None;
        g.closed = true;
        Ok(())
    }

    fn __enter__(slf: Py<Self>) -> Py<Self> {
        slf
    }

    #[pyo3(signature = (*_args))]
    fn __exit__(&self, py: Python<'_>, _args: &Bound<'_, pyo3::types::PyTuple>) -> PyResult<bool> {
        self.close(py)?;
        Ok(false)
    }

    /// Asks a run of this simulation (in another thread) to stop after its current step, as
    /// Ctrl-C does: it returns `"interrupted"`.
    fn interrupt(&self) {
        self.stop.store(SIGINT, Ordering::Relaxed);
    }

    /// Wall time of the last run's steps (s): the run driver's step loop, without what comes
    /// before the first step and after the last (the observers' first and last words, the
    /// summary, this module's thread and GIL handling).
    #[getter]
    fn wall_seconds(&self, py: Python<'_>) -> PyResult<f64> {
        Ok(self.lock(py)?.last_wall)
    }

    /// The worker threads of the simulation's pool.
    #[getter]
    fn threads(&self) -> usize {
        self.threads
    }

    #[getter]
    fn case(&self, py: Python<'_>) -> PyResult<Py<Case>> {
        Ok(self.lock(py)?.case.clone_ref(py))
    }

    /// The output directory (None when the simulation writes none).
    #[getter]
    fn out(&self, py: Python<'_>) -> PyResult<Option<PathBuf>> {
        Ok(self.lock(py)?.files.as_ref().map(|f| f.dir().to_path_buf()))
    }

    #[getter]
    fn step(&self, py: Python<'_>) -> PyResult<u64> {
        Ok(self.lock(py)?.world.step)
    }

    /// The time, `step × dt` (s).
    #[getter]
    fn time(&self, py: Python<'_>) -> PyResult<f64> {
        let g = self.lock(py)?;
        Ok(dem2d::run::time::time_value(g.world.step, g.world.dt))
    }

    #[getter]
    fn dt(&self, py: Python<'_>) -> PyResult<f64> {
        Ok(self.lock(py)?.world.dt)
    }

    #[getter]
    fn n_bodies(&self, py: Python<'_>) -> PyResult<usize> {
        Ok(self.lock(py)?.world.bodies.len())
    }

    /// Centroids, shape (n, 2), cm.
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let g = self.lock(py)?;
        let b = &g.world.bodies;
        pairs(py, b.state.iter().map(|s| s.pose.position))
    }

    /// Angles of the bodies' x axes (rad, counter-clockwise), shape (n,).
    #[getter]
    fn angles<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let g = self.lock(py)?;
        vector(py, g.world.bodies.state.iter().map(|s| s.pose.angle()))
    }

    /// Centroid velocities, shape (n, 2), cm/s.
    #[getter]
    fn velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let g = self.lock(py)?;
        pairs(py, g.world.bodies.state.iter().map(|s| s.vel))
    }

    /// Angular velocities, shape (n,), rad/s.
    #[getter]
    fn spins<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let g = self.lock(py)?;
        vector(py, g.world.bodies.state.iter().map(|s| s.omega))
    }

    /// Forces of the last evaluation (contacts and gravity), shape (n, 2), dyn per cm of
    /// thickness.
    #[getter]
    fn forces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let g = self.lock(py)?;
        pairs(py, g.world.bodies.force.iter().copied())
    }

    /// Moments of the last evaluation about the centroids, shape (n,), dyn·cm per cm.
    #[getter]
    fn torques<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let g = self.lock(py)?;
        vector(py, g.world.bodies.torque.iter().copied())
    }

    /// Masses per unit thickness, shape (n,), g per cm.
    #[getter]
    fn masses<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let g = self.lock(py)?;
        vector(py, g.world.bodies.mass.iter().copied())
    }

    /// The shapes: `type` (a list of names) and their parameters as arrays of shape (n,), NaN
    /// where a shape has no such parameter: `r` (circle), `a`, `b` (ellipse semi-axes), `w`,
    /// `h` (rectangle widths); `vertices` (a polygon's, about its centroid, (k, 2)) and `disks`
    /// (a clump's centres and radii, (k, 3)) as lists with None for other shapes; `area`,
    /// `bounding_radius` and `inscribed_radius` for every shape.
    fn shapes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let g = self.lock(py)?;
        let shapes = &g.world.bodies.shape;
        let d = PyDict::new(py);
        let names: Vec<&str> = shapes.iter().map(|s| s.type_name()).collect();
        d.set_item("type", names)?;
        let nan = f64::NAN;
        let param = |f: &dyn Fn(&Shape) -> f64| shapes.iter().map(f).collect::<Vec<f64>>();
        let r = param(&|s| match s {
            Shape::Circle { r } => *r,
            _ => nan,
        });
        let a = param(&|s| match s {
            Shape::Ellipse { a, .. } => *a,
            _ => nan,
        });
        let b = param(&|s| match s {
            Shape::Ellipse { b, .. } => *b,
            _ => nan,
        });
        let w = param(&|s| match s {
            Shape::Rectangle { w, .. } => *w,
            _ => nan,
        });
        let h = param(&|s| match s {
            Shape::Rectangle { h, .. } => *h,
            _ => nan,
        });
        for (k, v) in [("r", r), ("a", a), ("b", b), ("w", w), ("h", h)] {
            d.set_item(k, PyArray1::from_vec(py, v))?;
        }
        d.set_item("area", PyArray1::from_vec(py, param(&|s| s.area())))?;
        d.set_item(
            "bounding_radius",
            PyArray1::from_vec(py, param(&|s| s.bounding_radius())),
        )?;
        d.set_item(
            "inscribed_radius",
            PyArray1::from_vec(py, param(&|s| s.inscribed_radius())),
        )?;
        let vertices = PyList::empty(py);
        let disks = PyList::empty(py);
        for s in shapes {
            match s {
                Shape::Polygon(p) => {
                    vertices.append(pairs(py, p.vertices.iter().copied())?)?;
                    disks.append(py.None())?;
                }
                Shape::Clump(c) => {
                    let rows: Vec<f64> = c
                        .centres
                        .iter()
                        .zip(c.radii.iter())
                        .flat_map(|(p, r)| [p.x, p.y, *r])
                        .collect();
                    let n = c.radii.len();
                    disks.append(PyArray1::from_vec(py, rows).reshape([n, 3])?)?;
                    vertices.append(py.None())?;
                }
                Shape::Circle { .. } | Shape::Ellipse { .. } | Shape::Rectangle { .. } => {
                    vertices.append(py.None())?;
                    disks.append(py.None())?;
                }
            }
        }
        d.set_item("vertices", vertices)?;
        d.set_item("disks", disks)?;
        Ok(d)
    }

    /// The contacts now, as `contacts.csv` lists them: arrays `i` (the giving body, -1 for a
    /// wall), `wall` (the wall's index, -1 for a body), `j` (the receiving body), `point`
    /// (m, 2), `normal` (m, 2, from i to j), `depth`, `force` (m, 2, on j), `fn`, `ft`
    /// (`F·n`, `F·t` with `t = (−n_y, n_x)`), `couple` (on j), and `state` (a list of names).
    fn contacts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let mut g = self.lock(py)?;
        g.world.refresh_contact_extras();
        let frame = Frame::from_world(&g.world);
        let c = &frame.contacts;
        let d = PyDict::new(py);
        let ints = |f: &dyn Fn(&analysis::FrameContact) -> i64| {
            PyArray1::from_vec(py, c.iter().map(f).collect::<Vec<i64>>())
        };
        d.set_item(
            "i",
            ints(&|k| match k.i {
                Partner::Body(b) => b as i64,
                Partner::Wall(_) => -1,
            }),
        )?;
        d.set_item(
            "wall",
            ints(&|k| match k.i {
                Partner::Body(_) => -1,
                Partner::Wall(w) => w as i64,
            }),
        )?;
        d.set_item("j", ints(&|k| k.j as i64))?;
        d.set_item("point", pairs(py, c.iter().map(|k| k.point))?)?;
        d.set_item("normal", pairs(py, c.iter().map(|k| k.normal))?)?;
        d.set_item("depth", vector(py, c.iter().map(|k| k.depth))?)?;
        d.set_item("force", pairs(py, c.iter().map(|k| k.force))?)?;
        d.set_item("fn", vector(py, c.iter().map(|k| k.normal_force()))?)?;
        d.set_item("ft", vector(py, c.iter().map(|k| k.tangential_force()))?)?;
        d.set_item("couple", vector(py, c.iter().map(|k| k.couple))?)?;
        let states: Vec<&str> = c.iter().map(|k| k.state.as_str()).collect();
        d.set_item("state", states)?;
        Ok(d)
    }

    /// The measures of `analysis.csv` now (dem2d::analysis), over `window` = (x0, x1, y0, y1)
    /// (default: the case's `output.analysis_window`, else the box of four walls, else the
    /// bodies' extent). Stresses compression positive, dyn/cm²; fabric angles in radians.
    #[pyo3(signature = (window=None))]
    fn analysis<'py>(
        &self,
        py: Python<'py>,
        window: Option<[f64; 4]>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let mut g = self.lock(py)?;
        let case_window = g.case.get().scene().output.analysis_window;
        let window = match window.or(case_window) {
            None => None,
            Some([x0, x1, y0, y1]) => {
                if !(x0 < x1 && y0 < y1 && [x0, x1, y0, y1].iter().all(|v| v.is_finite())) {
                    return Err(input_error(
                        py,
                        format!(
                            "window: must be finite with x0 < x1 and y0 < y1, got \
                             [{x0}, {x1}, {y0}, {y1}]"
                        ),
                    ));
                }
                Some(Window { x0, x1, y0, y1 })
            }
        };
        g.world.refresh_contact_extras();
        let frame = Frame::from_world(&g.world);
        let m = analysis::measure(&frame, window);
        let d = PyDict::new(py);
        let tensor = |s: [f64; 3]| -> PyResult<Bound<'py, PyAny>> {
            let [xx, yy, xy] = s;
            Ok(PyArray1::from_vec(py, vec![xx, xy, xy, yy])
                .reshape([2, 2])?
                .into_any())
        };
        d.set_item("time", m.time)?;
        d.set_item("area", m.area)?;
        d.set_item("stress", tensor(m.stress)?)?;
        d.set_item("boundary_stress", tensor(m.boundary_stress)?)?;
        let (s1, s3, _) = analysis::stress::principal(m.stress);
        d.set_item("p", 0.5 * (s1 + s3))?;
        d.set_item("q", 0.5 * (s1 - s3))?;
        d.set_item("packing_fraction", m.packing_fraction)?;
        d.set_item("coordination", m.coordination)?;
        d.set_item("coordination_no_rattlers", m.coordination_no_rattlers)?;
        d.set_item("rattler_fraction", m.rattler_fraction)?;
        let f = &m.fabric;
        let fabric = PyDict::new(py);
        for (k, v) in [
            ("a_c", f.a_c),
            ("theta_c", f.theta_c),
            ("a_n", f.a_n),
            ("theta_n", f.theta_n),
            ("a_t", f.a_t),
            ("theta_t", f.theta_t),
        ] {
            fabric.set_item(k, v)?;
        }
        d.set_item("fabric", fabric)?;
        d.set_item("orientation_order", m.orientation_order)?;
        d.set_item("bodies", m.bodies)?;
        d.set_item("contacts", m.contacts)?;
        // In a periodic cell, `analysis.csv`'s cell columns.
        if let Some(c) = m.cell {
            let cell = PyDict::new(py);
            for (k, v) in [
                ("pressure", c.pressure),
                ("shear_stress", c.shear_stress),
                ("mu_eff", c.mu_eff),
                ("inertial_number", c.inertial_number),
                ("ly", c.ly),
            ] {
                cell.set_item(k, v)?;
            }
            d.set_item("cell", cell)?;
        } else {
            d.set_item("cell", py.None())?;
        }
        Ok(d)
    }

    /// The periodic cell now (None without one): `size` (Lx, Ly, cm), `periodic` ("x" or
    /// "xy"), `shear_rate` (1/s), `offset` (the Lees–Edwards shift of the image above modulo
    /// Lx) and `shift` (its total, cm), `pressure` (the imposed σ_yy, or None), `stress_xx`,
    /// `stress_yy`, `strain_rate_xx`, `strain_rate_yy` (each side's control, or None), `stress` (the
    /// cell's mean stress of the last evaluation, 2×2, compression positive, kinetic part
    /// included; NaN in an "x" cell), `normal_stress` (σ_yy), `shear_stress` ((σ_xy + σ_yx)/2),
    /// `stiffness_yy`, `stiffness_xx` and `area` (cm²), as `cell.csv` writes them.
    #[getter]
    fn cell<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let g = self.lock(py)?;
        let Some(c) = g.world.cell.as_ref() else {
            return Ok(None);
        };
        let d = PyDict::new(py);
        d.set_item("size", (c.size.x, c.size.y))?;
        d.set_item("periodic", c.periodic.as_str())?;
        d.set_item("shear_rate", c.shear_rate)?;
        d.set_item("offset", c.offset)?;
        d.set_item("shift", c.shift)?;
        d.set_item("pressure", c.pressure().map(|p| p.target))?;
        // Each side's target: a stress (dyn/cm) or a strain rate (1/s), None for a fixed side.
        for (side, key) in ["xx", "yy"].into_iter().enumerate() {
            use dem2d::dynamics::cell::SideControl;
            let (stress, rate) = match c.control[side] {
                Some(SideControl::Stress(p)) => (Some(p.target), None),
                Some(SideControl::StrainRate(e)) => (None, Some(e)),
                None => (None, None),
            };
            d.set_item(format!("stress_{key}"), stress)?;
            d.set_item(format!("strain_rate_{key}"), rate)?;
        }
        let measured = c.measures_stress();
        let stress = if measured { c.stress } else { [f64::NAN; 4] };
        d.set_item(
            "stress",
            PyArray1::from_vec(py, stress.to_vec()).reshape([2, 2])?,
        )?;
        d.set_item("normal_stress", c.normal_stress())?;
        d.set_item("shear_stress", c.shear_stress())?;
        d.set_item(
            "stiffness_yy",
            if measured { c.stiffness[1] } else { f64::NAN },
        )?;
        d.set_item(
            "stiffness_xx",
            if measured { c.stiffness[0] } else { f64::NAN },
        )?;
        d.set_item("area", c.area())?;
        Ok(Some(d))
    }

    /// In a periodic cell, how often each body crossed its seams (ix, iy), shape (n, 2); None
    /// without a cell.
    #[getter]
    fn images<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        let g = self.lock(py)?;
        if g.world.cell.is_none() {
            return Ok(None);
        }
        let flat: Vec<i64> = g
            .world
            .bodies
            .image
            .iter()
            .flat_map(|i| [i[0] as i64, i[1] as i64])
            .collect();
        let n = flat.len() / 2;
        Ok(Some(
            PyArray1::from_vec(py, flat).reshape([n, 2])?.into_any(),
        ))
    }

    /// The positions unwrapped through the seams (`x + ix Lx + iy S`, `y + iy Ly`: the cell's
    /// `Cell::unwrapped`), shape (n, 2); the positions themselves without a cell.
    #[getter]
    fn unwrapped_positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let g = self.lock(py)?;
        let b = &g.world.bodies;
        match g.world.cell.as_ref() {
            None => pairs(py, b.state.iter().map(|s| s.pose.position)),
            Some(c) => pairs(
                py,
                b.state
                    .iter()
                    .zip(&b.image)
                    .map(|(s, i)| c.unwrapped(s.pose.position, *i)),
            ),
        }
    }

    /// Brings the bodies to rest at a minimum of their potential energy: FIRE on positions and
    /// angles under the law's conservative part (`dem2d::dynamics::minimise`, what `dem2d
    /// relax` does; frictionless laws only, else `dem2d.InputError` naming the field). Stops
    /// when the residual force (the largest out-of-balance force on a body, |F| + |M|/r, over
    /// the mean magnitude of the forces on a body) is below `tolerance`, or after
    /// `max_iterations` force evaluations, or when the residual stops falling at the round-off
    /// level of the forces. Returns a dict: `status` ("relaxed", "round_off" or
    /// "max_iterations"), `iterations`, `residual`, `potential` (erg), `converged`. The step
    /// count does not change; the GIL is released while it works (it is not interrupted by
    /// Ctrl-C: give `max_iterations`).
    #[pyo3(signature = (tolerance=1e-9, max_iterations=1_000_000))]
    fn relax<'py>(
        &self,
        py: Python<'py>,
        tolerance: f64,
        max_iterations: u64,
    ) -> PyResult<Bound<'py, PyDict>> {
        use dem2d::dynamics::minimise::{Fire, RelaxError, Tolerance, check_frictionless, relax};
        if !(tolerance.is_finite() && tolerance > 0.0) {
            return Err(input_error(
                py,
                format!("tolerance: must be a positive number, got {tolerance}"),
            ));
        }
        let mut guard = self.lock(py)?;
        let inner = &mut *guard;
        let prefix = inner
            .case
            .get()
            .source
            .as_ref()
            .map(|p| format!("{}: ", p.display()))
            .unwrap_or_default();
        if let Err(e) = check_frictionless(&inner.world) {
            return Err(match &e {
                // Named as the case file names the law, as `dem2d relax` does.
                RelaxError::Friction(whose) => {
                    let field = format!("{whose}.friction").into_py_any(py)?;
                    error(
                        py,
                        "InputError",
                        format!("{prefix}field {e}"),
                        &[("field", field)],
                    )
                }
                other => input_error(py, format!("{prefix}{other}")),
            });
        }
        let tol = Tolerance {
            force: tolerance,
            max_iterations,
            energy: 0.0,
            stall: 0.0,
        };
        let Inner { world, pool, .. } = inner;
        let relaxed = py
            .detach(|| pool.install(|| relax(world, &Fire::default(), &tol)))
            .map_err(|e| error(py, "RunError", format!("{prefix}{e}"), &[]))?;
        let d = PyDict::new(py);
        d.set_item(
            "status",
            if relaxed.converged {
                "relaxed"
            } else if relaxed.round_off {
                "round_off"
            } else {
                "max_iterations"
            },
        )?;
        d.set_item("iterations", relaxed.iterations)?;
        d.set_item("residual", relaxed.residual)?;
        d.set_item("potential", relaxed.potential)?;
        d.set_item("converged", relaxed.converged)?;
        Ok(d)
    }

    /// The energy account (erg per cm of thickness): kinetic, potential, elastic, dissipated,
    /// walls_work, total.
    fn energies<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let g = self.lock(py)?;
        let e = g.world.energies;
        let d = PyDict::new(py);
        for (k, v) in [
            ("kinetic", e.kinetic),
            ("potential", e.potential),
            ("elastic", e.elastic),
            ("dissipated", e.dissipated),
            ("walls_work", e.boundary_work),
            ("total", e.total()),
        ] {
            d.set_item(k, v)?;
        }
        Ok(d)
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        match self.inner.try_lock() {
            Ok(g) => format!(
                "dem2d.Simulation({:?}, bodies={}, step={}, threads={}{})",
                g.case.get().scene().name,
                g.world.bodies.len(),
                g.world.step,
                self.threads,
                g.files
                    .as_ref()
                    .map(|f| format!(", out={:?}", f.dir().display().to_string()))
                    .unwrap_or_default()
            ),
            Err(_) => {
                let _ = py;
                "dem2d.Simulation(running)".into()
            }
        }
    }
}

impl Simulation {
    /// Runs on a worker thread in the pool with the GIL released, checking Python's signals
    /// every 50 ms on the calling thread; returns how the run ended and the first exception a
    /// signal handler raised (the run stopped for it).
    fn drive(&self, py: Python<'_>, inner: &mut Inner, ask: &Ask) -> (Ran, Option<PyErr>) {
        let Inner {
            world,
            files,
            pool,
            progress,
            ..
        } = inner;
        let stop = &self.stop;
        let progress = *progress;
        let before = (progress, world.step);
        let work = move || -> Ran {
            let mut sim = Driver::new(world)
                .resume(progress)
                .quiescence(ask.rest)
                .stop_flag(stop);
            if let Some(n) = ask.steps {
                sim = sim.for_steps(n);
            }
            if let Some(l) = ask.until_step {
                sim = sim.until_step(l);
            }
            match files.as_mut() {
                Some(f) => {
                    let e = f.run(sim);
                    (e.outcome, e.counts, e.progress)
                }
                None => {
                    let outcome = sim.run();
                    (outcome, Counts::of(&sim), *sim.progress())
                }
            }
        };
        let (tx, rx) = std::sync::mpsc::channel();
        // Only this thread receives; the mutex makes the receiver shareable with `detach`.
        let rx = Mutex::new(rx);
        let mut pending = None;
        let ran = std::thread::scope(|s| {
            s.spawn(move || {
                // A panic is a bug in dem2d: it reaches Python as `dem2d.RunError` naming it,
                // not as a `PanicException` (the world is left where the panic found it).
                let ran =
                    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| pool.install(work)))
                        .unwrap_or_else(|payload| {
                            let what = payload
                                .downcast_ref::<&str>()
                                .map(|s| s.to_string())
                                .or_else(|| payload.downcast_ref::<String>().cloned())
                                .unwrap_or_default();
                            let (progress, start_step) = before;
                            let counts = Counts {
                                quiescent_step: None,
                                first_contact_step: progress.first_contact_step,
                                contact_sum: progress.contact_sum,
                                wall_seconds: 0.0,
                                start_step,
                            };
                            let e = format!(
                                "internal error (a bug in dem2d, please report it): {what}"
                            );
                            (Err(RunFailure::Observer(e.into())), counts, progress)
                        });
                let _ = tx.send(ran);
            });
            loop {
                let wait = || {
                    let rx = rx.lock().unwrap_or_else(|e| e.into_inner());
                    rx.recv_timeout(Duration::from_millis(50))
                };
                match py.detach(wait) {
                    Ok(ran) => break ran,
                    Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {
                        if pending.is_none()
                            && let Err(e) = py.check_signals()
                        {
                            stop.store(SIGINT, Ordering::Relaxed);
                            pending = Some(e);
                        }
                    }
                    Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => {
                        panic!("the run's thread ended without a result")
                    }
                }
            }
        });
        (ran, pending)
    }
}

/// A (n, 2) float array of vectors.
fn pairs<'py>(
    py: Python<'py>,
    v: impl Iterator<Item = dem2d::geometry::Vec2>,
) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<f64> = v.flat_map(|p| [p.x, p.y]).collect();
    let n = flat.len() / 2;
    Ok(PyArray1::from_vec(py, flat).reshape([n, 2])?.into_any())
}

/// A (n,) float array.
fn vector<'py>(py: Python<'py>, v: impl Iterator<Item = f64>) -> PyResult<Bound<'py, PyAny>> {
    Ok(PyArray1::from_vec(py, v.collect::<Vec<f64>>()).into_any())
}

/// A run directory read back (`dem2d::output::run_data::RunData`, and `contacts.csv` when the
/// run wrote it), as a dict of arrays; analysis.csv and state.json are read by the Python side.
#[pyfunction]
fn load_run<'py>(py: Python<'py>, dir: PathBuf) -> PyResult<Bound<'py, PyDict>> {
    let run =
        dem2d::output::run_data::RunData::load(&dir).map_err(|e| input_error(py, e.to_string()))?;
    let d = PyDict::new(py);
    let frames = &run.frames;
    // Columns are the identities present in any frame (`trajectory.csv`'s `body`), increasing:
    // `0 … n − 1` for a case that neither inserts nor removes bodies; where it does, a body's
    // entries are NaN (images 0) in the frames it is absent from, and `present` says which.
    let ids = run.ids_in(&(0..frames.len()).collect::<Vec<_>>());
    let n = ids.len();
    let f = frames.len();
    // For each frame, the column of each of its bodies.
    let columns: Vec<Vec<usize>> = frames
        .iter()
        .map(|fr| {
            fr.ids
                .iter()
                .map(|id| {
                    ids.binary_search(id)
                        .expect("ids_in holds every frame's ids")
                })
                .collect()
        })
        .collect();
    let padded = |width: usize, g: &dyn Fn(&dem2d::output::run_data::BodyState) -> [f64; 2]| {
        let mut out = vec![f64::NAN; f * n * width];
        for (k, fr) in frames.iter().enumerate() {
            for (b, &c) in fr.bodies.iter().zip(&columns[k]) {
                let v = g(b);
                out[(k * n + c) * width..(k * n + c + 1) * width].copy_from_slice(&v[..width]);
            }
        }
        out
    };
    let steps: Vec<u64> = frames.iter().map(|fr| fr.step).collect();
    d.set_item("step", PyArray1::from_vec(py, steps))?;
    d.set_item("t", vector(py, frames.iter().map(|fr| fr.t))?)?;
    d.set_item("ids", PyArray1::from_vec(py, ids.clone()))?;
    let mut present = vec![false; f * n];
    for (k, cols) in columns.iter().enumerate() {
        for &c in cols {
            present[k * n + c] = true;
        }
    }
    d.set_item("present", PyArray1::from_vec(py, present).reshape([f, n])?)?;
    d.set_item(
        "positions",
        PyArray1::from_vec(py, padded(2, &|b| [b.x, b.y])).reshape([f, n, 2])?,
    )?;
    d.set_item(
        "angles",
        PyArray1::from_vec(py, padded(1, &|b| [b.angle, 0.0])).reshape([f, n])?,
    )?;
    d.set_item(
        "velocities",
        PyArray1::from_vec(py, padded(2, &|b| [b.vx, b.vy])).reshape([f, n, 2])?,
    )?;
    d.set_item(
        "spins",
        PyArray1::from_vec(py, padded(1, &|b| [b.omega, 0.0])).reshape([f, n])?,
    )?;
    if run.case.cell.is_some() {
        let mut images = vec![0i64; f * n * 2];
        for (k, fr) in frames.iter().enumerate() {
            for (i, &c) in fr.images.iter().zip(&columns[k]) {
                images[(k * n + c) * 2] = i[0] as i64;
                images[(k * n + c) * 2 + 1] = i[1] as i64;
            }
        }
        d.set_item("images", PyArray1::from_vec(py, images).reshape([f, n, 2])?)?;
    }
    let inc = PyDict::new(py);
    let i = &run.increments;
    inc.set_item(
        "step",
        PyArray1::from_vec(py, i.iter().map(|r| r.step).collect::<Vec<u64>>()),
    )?;
    inc.set_item("t", vector(py, i.iter().map(|r| r.t))?)?;
    inc.set_item("mean_dx", vector(py, i.iter().map(|r| r.mean_dx))?)?;
    inc.set_item("mean_dy", vector(py, i.iter().map(|r| r.mean_dy))?)?;
    inc.set_item("mean_dtheta", vector(py, i.iter().map(|r| r.mean_dtheta))?)?;
    inc.set_item(
        "unbalanced_force_ratio",
        vector(py, i.iter().map(|r| r.unbalanced_force_ratio))?,
    )?;
    inc.set_item(
        "contacts",
        PyArray1::from_vec(py, i.iter().map(|r| r.contacts).collect::<Vec<u64>>()),
    )?;
    d.set_item("increments", inc)?;
    d.set_item("summary", run.summary.to_string())?;
    d.set_item("incomplete", run.incomplete.clone())?;
    if dir.join("contacts.csv").exists() {
        let frames =
            dem2d::output::analysis::read_contact_frames(&dir).map_err(|e| input_error(py, e))?;
        let all: Vec<(u64, &analysis::FrameContact)> = frames
            .contacts
            .iter()
            .flat_map(|(s, cs)| cs.iter().map(move |c| (*s, c)))
            .collect();
        let c = PyDict::new(py);
        c.set_item(
            "step",
            PyArray1::from_vec(py, all.iter().map(|(s, _)| *s).collect::<Vec<u64>>()),
        )?;
        let ints = |f: &dyn Fn(&analysis::FrameContact) -> i64| {
            PyArray1::from_vec(py, all.iter().map(|(_, k)| f(k)).collect::<Vec<i64>>())
        };
        c.set_item(
            "i",
            ints(&|k| match k.i {
                Partner::Body(b) => b as i64,
                Partner::Wall(_) => -1,
            }),
        )?;
        c.set_item(
            "wall",
            ints(&|k| match k.i {
                Partner::Body(_) => -1,
                Partner::Wall(w) => w as i64,
            }),
        )?;
        c.set_item("j", ints(&|k| k.j as i64))?;
        c.set_item("point", pairs(py, all.iter().map(|(_, k)| k.point))?)?;
        c.set_item("normal", pairs(py, all.iter().map(|(_, k)| k.normal))?)?;
        c.set_item("depth", vector(py, all.iter().map(|(_, k)| k.depth))?)?;
        c.set_item("force", pairs(py, all.iter().map(|(_, k)| k.force))?)?;
        // `fn` and `ft` as written (the reader keeps the force vector, `fn n + ft t`, whose
        // projections are those numbers only to rounding).
        let text = std::fs::read_to_string(dir.join("contacts.csv"))
            .map_err(|e| input_error(py, format!("{}: {e}", dir.join("contacts.csv").display())))?;
        let (whole, _) = dem2d::output::run_data::whole_lines(&text);
        let mut fn_ = Vec::with_capacity(all.len());
        let mut ft = Vec::with_capacity(all.len());
        for line in whole.lines().skip(1) {
            let mut f = line.split(',').skip(8);
            let mut next = || {
                f.next()
                    .and_then(|v| v.parse::<f64>().ok())
                    .unwrap_or(f64::NAN)
            };
            fn_.push(next());
            ft.push(next());
        }
        c.set_item("fn", PyArray1::from_vec(py, fn_))?;
        c.set_item("ft", PyArray1::from_vec(py, ft))?;
        c.set_item("couple", vector(py, all.iter().map(|(_, k)| k.couple))?)?;
        let states: Vec<&str> = all.iter().map(|(_, k)| k.state.as_str()).collect();
        c.set_item("state", states)?;
        d.set_item("contacts", c)?;
    }
    Ok(d)
}

/// Reads the run directory `dir` for `export` and `animate` (`dem2d.InputError` naming the
/// file when it is not a whole run).
fn read_run(py: Python<'_>, dir: &std::path::Path) -> PyResult<dem2d::output::run_data::RunData> {
    dem2d::output::run_data::RunData::load(dir).map_err(|e| input_error(py, e.to_string()))
}

/// `dem2d export RUN --format lammps-dump [--out FILE]`: writes the run's LAMMPS-style dump
/// (for OVITO; `dem2d::output::dump`) and returns its path.
#[pyfunction]
#[pyo3(signature = (dir, format="lammps-dump", out=None))]
fn export(py: Python<'_>, dir: PathBuf, format: &str, out: Option<PathBuf>) -> PyResult<PathBuf> {
    if format != "lammps-dump" {
        return Err(input_error(
            py,
            format!("format: the formats are \"lammps-dump\", got {format:?}"),
        ));
    }
    let run = read_run(py, &dir)?;
    let out = out.unwrap_or_else(|| dir.join(dem2d::output::dump::FILE));
    py.detach(|| dem2d::output::dump::export_run(&run, &out))
        .map_err(|e| error(py, "OutputError", e.to_string(), &[]))?;
    Ok(out)
}

/// `dem2d fields RUN --axis AXIS --bins N [--from T0] [--to T1] [--range LO,HI] [--relative]`:
/// writes the run's coarse-grained fields (`fields.csv`, `dem2d::output::fields`) and returns
/// its path; the notes (no contacts.csv, the range chosen) as Python warnings.
#[pyfunction]
#[pyo3(signature = (dir, *, axis="y", bins, start=None, end=None, range=None, relative=false, out=None))]
#[allow(clippy::too_many_arguments)]
fn fields(
    py: Python<'_>,
    dir: PathBuf,
    axis: &str,
    bins: usize,
    start: Option<f64>,
    end: Option<f64>,
    range: Option<(f64, f64)>,
    relative: bool,
    out: Option<PathBuf>,
) -> PyResult<PathBuf> {
    use dem2d::analysis::fields::Axis;
    let axis = match axis {
        "x" => Axis::X,
        "y" => Axis::Y,
        other => {
            return Err(input_error(
                py,
                format!("axis: \"x\" or \"y\", got {other:?}"),
            ));
        }
    };
    let request = dem2d::output::fields::FieldRequest {
        axis,
        bins,
        from: start,
        to: end,
        range,
        relative,
    };
    let f = py
        .detach(|| dem2d::output::fields::run_fields(&dir, &request))
        .map_err(|m| input_error(py, m))?;
    for note in &f.notes {
        PyErr::warn(
            py,
            &py.get_type::<pyo3::exceptions::PyUserWarning>(),
            &std::ffi::CString::new(format!("dem2d fields: {note}")).unwrap_or_default(),
            1,
        )?;
    }
    let out = out.unwrap_or_else(|| dir.join("fields.csv"));
    std::fs::write(&out, dem2d::output::fields::fields_csv(&f)).map_err(|e| {
        error(
            py,
            "OutputError",
            format!("{}: cannot write: {e}", out.display()),
            &[],
        )
    })?;
    Ok(out)
}

/// `dem2d forces RUN [--frame K] [--from T] [--bins N]`: writes `forces.csv` and `forces.json`
/// (`dem2d::output::force_statistics`) and returns the directory they are in.
#[pyfunction]
#[pyo3(signature = (dir, *, frame=None, start=None, bins=40))]
fn forces(
    py: Python<'_>,
    dir: PathBuf,
    frame: Option<i64>,
    start: Option<f64>,
    bins: usize,
) -> PyResult<PathBuf> {
    use dem2d::output::force_statistics::{ForcesRequest, forces_csv, forces_json, run_forces};
    let request = ForcesRequest {
        frame,
        from: start,
        bins,
    };
    let r = py
        .detach(|| run_forces(&dir, &request))
        .map_err(|m| input_error(py, m))?;
    for (name, text) in [
        ("forces.csv", forces_csv(&r)),
        ("forces.json", forces_json(&r)),
    ] {
        let out = dir.join(name);
        std::fs::write(&out, text).map_err(|e| {
            error(
                py,
                "OutputError",
                format!("{}: cannot write: {e}", out.display()),
                &[],
            )
        })?;
    }
    Ok(dir)
}

/// `dem2d animate RUN [--out FILE] [--every N]`: the run as a self-contained HTML player
/// (`.html`, the default `RUN/animation.html`) or a movie through ffmpeg (`.mp4`, `.gif`:
/// coloured by `color`, one of speed, spin, rotation, force, body, at `fps` frames per second
/// and `width` pixels); returns its path.
#[pyfunction]
#[pyo3(signature = (dir, out=None, *, every=1, color="speed", fps=20, width=800))]
fn animate(
    py: Python<'_>,
    dir: PathBuf,
    out: Option<PathBuf>,
    every: usize,
    color: &str,
    fps: u32,
    width: u32,
) -> PyResult<PathBuf> {
    use dem2d::output::player::{self, Movie, MovieError};
    use dem2d::output::plot::ColorBy;
    if every == 0 {
        return Err(input_error(py, "every: must be at least 1".into()));
    }
    let out = out.unwrap_or_else(|| dir.join("animation.html"));
    let ext = out
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let movie = match ext.as_deref() {
        Some("html" | "htm") => None,
        Some("mp4") => Some(Movie::Mp4),
        Some("gif") => Some(Movie::Gif),
        _ => {
            return Err(input_error(
                py,
                format!(
                    "out {}: animate writes .html (the player), .mp4 or .gif (through ffmpeg)",
                    out.display()
                ),
            ));
        }
    };
    let by = match color {
        "speed" => ColorBy::Speed,
        "spin" => ColorBy::Omega,
        "rotation" => ColorBy::Rotation,
        "force" => ColorBy::Force,
        "body" => ColorBy::Body,
        other => {
            return Err(input_error(
                py,
                format!(
                    "color: one of \"speed\", \"spin\", \"rotation\", \"force\", \"body\", \
                     got {other:?}"
                ),
            ));
        }
    };
    if movie.is_some() && !((1..=120).contains(&fps) && (100..=8000).contains(&width)) {
        return Err(input_error(
            py,
            format!("fps must be 1 … 120 and width 100 … 8000 pixels, got {fps} and {width}"),
        ));
    }
    let run = read_run(py, &dir)?;
    let frames = player::thin(&run, every);
    match movie {
        None => {
            py.detach(|| player::write_player(&run, &frames, &out))
                .map_err(|e| error(py, "OutputError", e.to_string(), &[]))?;
        }
        Some(kind) => {
            py.detach(|| player::write_movie(&run, &frames, &out, kind, by, (fps, width)))
                .map_err(|e| match e {
                    MovieError::NoFfmpeg(m) => input_error(py, m),
                    MovieError::Failed(m) => error(py, "OutputError", m, &[]),
                })?;
        }
    }
    Ok(out)
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Case>()?;
    m.add_class::<Simulation>()?;
    m.add_function(wrap_pyfunction!(load_run, m)?)?;
    m.add_function(wrap_pyfunction!(export, m)?)?;
    m.add_function(wrap_pyfunction!(fields, m)?)?;
    m.add_function(wrap_pyfunction!(forces, m)?)?;
    m.add_function(wrap_pyfunction!(animate, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
