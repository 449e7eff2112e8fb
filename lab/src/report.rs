//! `dem2d-lab figures`: every figure and table of the user guide, regenerated from the code.
//!
//! Runs the paper's cases through the `dem2d` binary (into a work directory), draws their figures, sweeps the time step for
//! the speed-vs-error and stability reports, tabulates the contact kernel's accuracy against the
//! independent reference with its time per pair, and writes SVG, CSV and Markdown into the
//! output directory. With `--docs`, the user guide's regions between `<!-- figures:NAME -->` and
//! `<!-- /figures:NAME -->` (in `README.md` and `docs/src`) are replaced by the Markdown of the
//! same name, so its tables are never edited by hand either; with `--docs --check` they are
//! compared instead, and a difference is an error (CI). Without `--docs` the guide is left alone.
//!
//! Everything written into the output directory is a function of the code and the cases only,
//! the same bits on every machine and every run, so that regenerating leaves a clean tree.
//! Machine-dependent timings (wall time of the runs and of the sweeps, the contact kernel's time
//! per pair, the error against wall time) go to `timings.md` and `speed_vs_error_time.svg` in
//! the work directory, which is not tracked.

use dem2d::contact_law::NormalForce;
use dem2d::dynamics::timestep::estimate_critical_dt;
use dem2d::narrow_phase::contact;
use dem2d::output::panels;
use dem2d::output::plot::{self, LinePanel, SceneOptions, ScenePanel, Series};
use dem2d::output::run_data::RunData;
use dem2d::run::{RunError, Simulation};
use dem2d::scene::Case;
use dem2d_validation::families::{markdown_table, run_families};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// An error of the figures command, as text (the file and what went wrong).
#[derive(Debug)]
pub struct ReportError(pub String);

impl std::fmt::Display for ReportError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ReportError {}

/// A progress line on stderr (a closed stderr must not stop the figures).
fn note(text: &str) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "{text}");
}

fn e<E: std::fmt::Display>(what: &str) -> impl Fn(E) -> ReportError + '_ {
    move |err| ReportError(format!("{what}: {err}"))
}

/// Where the figures command reads and writes.
pub struct FigureOptions {
    /// The case files (`cases/`).
    pub cases: PathBuf,
    /// Where figures and tables go (`figures/`).
    pub out: PathBuf,
    /// Where the runs go (their trajectories are not figures).
    pub work: PathBuf,
    /// Refresh (or check) the user guide's marked tables, in the repository at the current
    /// directory (None: leave the guide alone).
    pub docs: Option<dem2d::output::docs_tables::Mode>,
    /// Fewer repetitions and sweep points (for a quick look; the guide's numbers use the full set).
    pub quick: bool,
    /// Where each SVG is also rendered as PNG (None: `WORK/png`). Not in `out`: the rendering
    /// depends on the machine's fonts, and `out` holds the same bits on every machine.
    pub png: Option<PathBuf>,
}

fn load_case(path: &Path) -> Result<(Case, String), ReportError> {
    let text = std::fs::read_to_string(path).map_err(e(&path.display().to_string()))?;
    let case = Case::from_json(&text).map_err(e(&path.display().to_string()))?;
    Ok((case, text))
}

fn run(opts: &FigureOptions, name: &str) -> Result<RunData, ReportError> {
    run_law(opts, name, None)
}

/// Runs case `name` as its file gives it (`law` None), or with every contact under `law` (the
/// run, and the case name in its `case.json`, then carry the law's name as a suffix).
fn run_law(
    opts: &FigureOptions,
    name: &str,
    law: Option<NormalForce>,
) -> Result<RunData, ReportError> {
    let path = opts.cases.join(format!("{name}.json"));
    let (mut case, mut text) = load_case(&path)?;
    let mut label = name.to_string();
    if let Some(law) = law {
        label = format!("{name}_{}", law.as_str());
        case = case.with_normal_force(law);
        case.name = label.clone();
        let mut v: serde_json::Value =
            serde_json::from_str(&text).map_err(e(&path.display().to_string()))?;
        v["name"] = label.clone().into();
        v["contact"]["normal_force"] = law.as_str().into();
        if let Some(walls) = v["walls"].as_array_mut() {
            for w in walls {
                if w.get("normal_force").is_some() {
                    w["normal_force"] = law.as_str().into();
                }
            }
        }
        text = serde_json::to_string_pretty(&v).map_err(e(&label))?;
    }
    let _ = case;
    let dir = opts.work.join(&label);
    // The case as it is run, beside its output (`dem2d run` reads a file); the work directory
    // holds the previous figures' runs: replace them.
    std::fs::create_dir_all(&opts.work).map_err(e(&opts.work.display().to_string()))?;
    let file = opts.work.join(format!("{label}.json"));
    std::fs::write(&file, &text).map_err(e(&file.display().to_string()))?;
    let out = std::process::Command::new(crate::dem2d_exe().map_err(ReportError)?)
        .arg("run")
        .arg(&file)
        .arg("--out")
        .arg(&dir)
        .args(["--overwrite", "--quiet"])
        .output()
        .map_err(e(&format!("{label}: dem2d run")))?;
    if !out.status.success() {
        return Err(ReportError(format!(
            "{label}: dem2d run failed: {}",
            String::from_utf8_lossy(&out.stderr).trim()
        )));
    }
    RunData::load(&dir).map_err(e(&label))
}

/// Regenerates everything; returns the files written.
pub fn figures(opts: &FigureOptions) -> Result<Vec<PathBuf>, ReportError> {
    std::fs::create_dir_all(&opts.out).map_err(e(&opts.out.display().to_string()))?;
    let mut written = Vec::new();
    let mut tables: Vec<(&str, String)> = Vec::new();
    let out = |f: &str| opts.out.join(f);

    // The paper's cases.
    let names = [
        "drop_rebound_mu01",
        "drop_rebound_mu05",
        "throw_circle",
        "throw_ellipse",
        "throw_square",
        "settle3_dt1e-5",
        "settle3_dt1e-4",
    ];
    // Each as its file gives it (P's spring on the depth), and under the area law.
    let mut runs = Vec::new();
    let mut area_runs = Vec::new();
    for n in names {
        note(&format!(
            "figures: running {n}, with the depth law and with the area law"
        ));
        runs.push(run(opts, n)?);
        area_runs.push(run_law(opts, n, Some(NormalForce::Area))?);
    }
    let by = |n: &str| &runs[names.iter().position(|m| *m == n).expect("known case")];
    let by_area = |n: &str| &area_runs[names.iter().position(|m| *m == n).expect("known case")];
    let both: Vec<RunData> = runs
        .iter()
        .zip(&area_runs)
        .flat_map(|(d, a)| [d.clone(), a.clone()])
        .collect();
    tables.push(("paper_cases", paper_cases_table(&both)));
    let mut timings = String::from(
        "# Timings of `dem2d figures` (machine-dependent)\n\nMeasured on this machine by the run that wrote this file; they change from run to run and \
         from machine to machine, which is why they are kept out of `figures/`.\n\n## The paper's cases\n\n| case | steps | wall time (s) |\n|---|---:|---:|\n",
    );
    for r in &both {
        writeln!(
            timings,
            "| `{}` | {} | {:.3} |",
            r.case.name,
            r.summary["steps"],
            r.summary["wall_seconds"].as_f64().unwrap_or(f64::NAN)
        )
        .expect("string");
    }

    // P's Figs. 2–4: the depth law as the case files give it, and the area law.
    written.extend(paper_figures(opts, &by, Law::Depth)?);
    written.extend(paper_figures(opts, &by_area, Law::Area)?);
    let (tc, te, ts) = (by("throw_circle"), by("throw_ellipse"), by("throw_square"));
    let (ae, as_) = (by_area("throw_ellipse"), by_area("throw_square"));
    tables.push((
        "fig3_comparison",
        comparison_table(&[
            (tc, "circle (either law: central)"),
            (te, "ellipse, depth law"),
            (ae, "ellipse, area law"),
            (ts, "square, depth law"),
            (as_, "square, area law (Winkler on a wall: the same)"),
        ]),
    ));

    // Speed vs error, and stability.
    let sve = speed_vs_error(opts)?;
    std::fs::write(out("speed_vs_error.csv"), sve.csv).map_err(e("speed_vs_error.csv"))?;
    written.push(out("speed_vs_error.csv"));
    let f = out("speed_vs_error.svg");
    plot::line_panels(&f, (800, 520), (1, 1), &[sve.by_dt]).map_err(e("speed vs error"))?;
    written.push(f);
    tables.push(("speed_vs_error", sve.md));
    timings.push_str(&sve.timings);
    std::fs::create_dir_all(&opts.work).map_err(e(&opts.work.display().to_string()))?;
    let f = opts.work.join("speed_vs_error_time.svg");
    plot::line_panels(&f, (800, 520), (1, 1), &[sve.by_wall]).map_err(e("speed vs error"))?;
    written.push(f);
    let (st_md, st_csv, st_panels) = stability(opts)?;
    std::fs::write(out("stability.csv"), st_csv).map_err(e("stability.csv"))?;
    written.push(out("stability.csv"));
    let f = out("stability.svg");
    plot::line_panels(&f, (900, 900), (2, 1), &st_panels).map_err(e("stability"))?;
    written.push(f);
    tables.push(("stability", st_md));

    // The area law: force against the depth spring, restitution, energy.
    eprintln!("figures: area law tables");
    tables.push(("area_force", crate::area_law_report::force_overlap_table()));
    tables.push((
        "area_restitution",
        crate::area_law_report::restitution_table(),
    ));
    tables.push(("area_energy", crate::area_law_report::energy_table()));

    // The contact kernel: accuracy against the reference and time per pair.
    note("figures: contact kernel families");
    let (kernel_md, kernel_times) = kernel_report(opts.quick);
    tables.push(("kernel_report", kernel_md));
    timings.push_str(&kernel_times);

    for (name, md) in &tables {
        let f = out(&format!("{name}.md"));
        std::fs::write(&f, md).map_err(e(&f.display().to_string()))?;
        written.push(f);
    }
    let f = opts.work.join("timings.md");
    std::fs::write(&f, timings).map_err(e(&f.display().to_string()))?;
    written.push(f);
    let stale = match opts.docs {
        Some(mode) => Some((
            mode,
            dem2d::output::docs_tables::refresh(Path::new("."), &tables, mode)
                .map_err(ReportError)?,
        )),
        None => None,
    };
    // Every SVG also as PNG, at twice its displayed size (print resolution).
    let png_dir = opts.png.clone().unwrap_or_else(|| opts.work.join("png"));
    std::fs::create_dir_all(&png_dir).map_err(e(&png_dir.display().to_string()))?;
    let svgs: Vec<PathBuf> = written
        .iter()
        .filter(|f| f.extension().is_some_and(|x| x == "svg"))
        .cloned()
        .collect();
    for svg in svgs {
        let name = svg
            .file_stem()
            .unwrap_or_default()
            .to_string_lossy()
            .to_string();
        let png = png_dir.join(format!("{name}.png"));
        let text = std::fs::read_to_string(&svg).map_err(e(&svg.display().to_string()))?;
        let bytes = plot::png_of_svg(&text, 2.0).map_err(e(&png.display().to_string()))?;
        std::fs::write(&png, bytes).map_err(e(&png.display().to_string()))?;
        written.push(png);
    }
    if let Some((mode, stale)) = stale {
        note(&dem2d::output::docs_tables::report(&stale, mode).map_err(ReportError)?);
    }
    Ok(written)
}

fn paper_cases_table(runs: &[RunData]) -> String {
    let mut t = String::from(
        "| case | normal force | steps | at rest at step | first contact at step | dt | dt_critical (a priori) | max δ / inscribed radius |\n|---|---|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in runs {
        let s = &r.summary;
        let q = s["quiescent_step"]
            .as_u64()
            .map_or("never".to_string(), |v| v.to_string());
        let fc = s["first_contact_step"]
            .as_u64()
            .map_or("–".to_string(), |v| v.to_string());
        writeln!(
            t,
            "| `{}` | {} | {} | {q} | {fc} | {:e} | {:.3e} | {:.4} |",
            r.case.name,
            r.case.contact.normal_force().as_str(),
            s["steps"],
            s["dt"].as_f64().unwrap_or(f64::NAN),
            s["dt_critical"].as_f64().unwrap_or(f64::NAN),
            s["max_depth_ratio"].as_f64().unwrap_or(f64::NAN),
        )
        .expect("string");
    }
    t
}

/// Which law a set of paper figures shows: the file names' suffix and the titles' note.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Law {
    Depth,
    Area,
}

impl Law {
    fn suffix(self) -> &'static str {
        match self {
            Law::Depth => "",
            Law::Area => "_area",
        }
    }

    /// Inserted after "P Fig. N" in titles.
    fn note(self) -> &'static str {
        match self {
            Law::Depth => "",
            Law::Area => ", area law",
        }
    }
}

/// P's Figs. 2–4 from the runs `by` gives (`*.svg`, or `*_area.svg` under the area law).
fn paper_figures<'a>(
    opts: &FigureOptions,
    by: &dyn Fn(&str) -> &'a RunData,
    law: Law,
) -> Result<Vec<PathBuf>, ReportError> {
    let file = |name: &str| opts.out.join(format!("{name}{}.svg", law.suffix()));
    let note = law.note();
    let mut written = Vec::new();

    // P Fig. 2: the drop at two frictions.
    let (d1, d5) = (by("drop_rebound_mu01"), by("drop_rebound_mu05"));
    let f = file("fig2_drop_rebound");
    plot::scene(
        &f,
        &[
            ScenePanel {
                title: format!(
                    "P Fig. 2 (a){note}: ellipse a/b = 1.5 dropped tilted, floor friction μ = 0.1"
                ),
                runs: vec![(d1, String::new())],
            },
            ScenePanel {
                title: format!("P Fig. 2 (b){note}: the same, floor friction μ = 0.5"),
                runs: vec![(d5, String::new())],
            },
        ],
        &SceneOptions {
            t_max: Some(0.6),
            outlines: 25,
            ..Default::default()
        },
    )
    .map_err(e("fig2"))?;
    written.push(f);
    let f = file("fig2_drop_rebound_series");
    plot::line_panels(
        &f,
        (1000, 700),
        (2, 1),
        &panels::time_series(
            &[(d1, "μ = 0.1"), (d5, "μ = 0.5")],
            &format!("P Fig. 2{note}: centroid height and angle"),
        ),
    )
    .map_err(e("fig2 series"))?;
    written.push(f);

    // P Fig. 3: circle, ellipse and square, one panel each on common axes, as P draws them.
    let (tc, te, ts) = (by("throw_circle"), by("throw_ellipse"), by("throw_square"));
    let f = file("fig3_throw_comparison");
    let panel = |run: &'a RunData, what: &str| ScenePanel {
        title: format!(
            "P Fig. 3{note}: {what} thrown sideways at {} cm/s, first 0.8 s",
            run.frames[0].bodies[0].vx
        ),
        runs: vec![(run, String::new())],
    };
    plot::scene(
        &f,
        &[
            panel(tc, "(a) circle"),
            panel(te, "(b) ellipse a/b = 1.5 of the same area"),
            panel(ts, "(c) square of the same area"),
        ],
        &SceneOptions {
            t_max: Some(0.8),
            outlines: 14,
            ..Default::default()
        },
    )
    .map_err(e("fig3"))?;
    written.push(f);
    let f = file("fig3_throw_series");
    plot::line_panels(
        &f,
        (1000, 700),
        (2, 1),
        &panels::time_series(
            &[(tc, "circle"), (te, "ellipse"), (ts, "square")],
            &format!("P Fig. 3{note}: centroid height and angle"),
        ),
    )
    .map_err(e("fig3 series"))?;
    written.push(f);

    // P Fig. 4: the three ellipses at Δt = 1e-5 s; at 1e-4 s the scene looks the same, so
    // what differs — the rotation that never stops — gets its own figure.
    let (s5, s4) = (by("settle3_dt1e-5"), by("settle3_dt1e-4"));
    let rest = |r: &RunData| {
        r.summary["quiescent_step"]
            .as_u64()
            .map_or("never at rest".to_string(), |s| {
                format!("at rest at step {s}")
            })
    };
    let f = file("fig4_settle3");
    plot::scene(
        &f,
        &[ScenePanel {
            title: format!(
                "P Fig. 4{note}: three ellipses from first contact, Δt = 1e-5 s: {}",
                rest(s5)
            ),
            runs: vec![(s5, String::new())],
        }],
        &SceneOptions {
            outlines: 12,
            width: Some(800),
            ..Default::default()
        },
    )
    .map_err(e("fig4"))?;
    written.push(f);
    let f = file("fig4_dt1e-4");
    plot::line_panels(
        &f,
        (1200, 520),
        (1, 2),
        &panels::rotation_against_dt(&[(s5, "Δt = 1e-5 s"), (s4, "Δt = 1e-4 s")], note),
    )
    .map_err(e("fig4 rotation"))?;
    written.push(f);
    let f = file("fig4_quiescence");
    plot::line_panels(
        &f,
        (1200, 500),
        (1, 2),
        &[
            panels::quiescence(
                s5,
                &format!("P's quiescence measures{note}, Δt = 1e-5 s: {}", rest(s5)),
                Some((1e-12, 1e-3)),
            ),
            panels::quiescence(
                s4,
                &format!("P's quiescence measures{note}, Δt = 1e-4 s: {}", rest(s4)),
                Some((1e-12, 1e-3)),
            ),
        ],
    )
    .map_err(e("fig4 quiescence"))?;
    written.push(f);
    Ok(written)
}

/// Rebound heights, impacts, distance travelled at 1 s, final rotation and time to rest.
fn comparison_table(runs: &[(&RunData, &str)]) -> String {
    let mut t = String::from(
        "| shape | first rebound apex (cm) | apex above lowest resting height (cm) | impacts | x at t = 1 s (cm) | x over the last 1 s of the run (cm) | final rotation (rad) | time to rest (s) |\n|---|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for (run, label) in runs {
        // Contact onsets from the per-step contact counts.
        let incs = &run.increments;
        let mut onsets = Vec::new();
        let mut ends = Vec::new();
        let mut prev = 0;
        for i in incs {
            if prev == 0 && i.contacts > 0 {
                onsets.push(i.t);
            }
            if prev > 0 && i.contacts == 0 {
                ends.push(i.t);
            }
            prev = i.contacts;
        }
        let apex = match (ends.first(), onsets.get(1)) {
            (Some(&t0), next) => {
                let t1 = next.copied().unwrap_or(f64::INFINITY);
                run.frames
                    .iter()
                    .filter(|f| f.t > t0 && f.t < t1)
                    .map(|f| f.bodies[0].y)
                    .fold(f64::NEG_INFINITY, f64::max)
            }
            _ => f64::NAN,
        };
        let x1 = run
            .frames
            .iter()
            .min_by(|a, b| (a.t - 1.0).abs().total_cmp(&(b.t - 1.0).abs()))
            .map_or(f64::NAN, |f| f.bodies[0].x);
        let last = run.frames.last().expect("frames");
        // A rocking body's x at one instant is a phase of the rocking: give the range too.
        let (xl, xh) = run
            .frames
            .iter()
            .filter(|f| f.t >= last.t - 1.0)
            .map(|f| f.bodies[0].x)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| {
                (l.min(x), h.max(x))
            });
        let range = if run.summary["quiescent"].as_bool() == Some(true) {
            format!("{:.2} (at rest)", last.bodies[0].x)
        } else {
            format!("{xl:.2} – {xh:.2}")
        };
        let rest = run.summary["quiescent_step"]
            .as_u64()
            .map_or("never (in 3 s)".to_string(), |s| {
                format!("{:.3}", s as f64 * run.case.dt)
            });
        // The centroid of a body lying on its flattest side is its inscribed radius above the
        // floor: the apex above that height compares rebounds of shapes of unequal heights.
        let (apex_s, above_s) = if apex.is_finite() {
            let rest_h = run.case.bodies[0].shape.inscribed_radius();
            (format!("{apex:.3}"), format!("{:.3}", apex - rest_h))
        } else {
            ("no rebound".into(), String::new())
        };
        writeln!(
            t,
            "| {label} | {apex_s} | {above_s} | {} | {x1:.2} | {range} | {:.3} | {rest} |",
            onsets.len(),
            last.bodies[0].angle
        )
        .expect("string");
    }
    t
}

/// State of a single-body drop run: apex of the first rebound and the state at the end.
struct DropResult {
    wall: f64,
    apex: f64,
    x: f64,
    y: f64,
    angle: f64,
}

/// A drop run at `dt` to `t_end`. Without the blow-up watch: the sweep approaches the stability
/// limit on purpose, where the energy swings widely in a stable run; a non-finite state is the
/// error.
fn drop_run(case: &Case, dt: f64, t_end: f64) -> Result<DropResult, ReportError> {
    let mut w = case.clone().with_dt(dt).build_world();
    let steps = (t_end / dt).round() as u64;
    let start = Instant::now();
    let (mut phase, mut apex) = (0u8, f64::NEG_INFINITY);
    Simulation::new(&mut w)
        .without_watch()
        .for_steps(steps)
        .run_each(|w, _| {
            let touching = !w.contacts.is_empty();
            let y = w.bodies.state[0].pose.position.y;
            phase = match (phase, touching) {
                (0, true) => 1,
                (1, false) => 2,
                (2, true) => 3,
                (p, _) => p,
            };
            if phase == 2 {
                apex = apex.max(y);
            }
        })
        .map_err(e(&format!("the drop of {} at dt = {dt:e}", case.name)))?;
    let wall = start.elapsed().as_secs_f64();
    let p = w.bodies.state[0].pose;
    Ok(DropResult {
        wall,
        apex,
        x: p.position.x,
        y: p.position.y,
        angle: p.angle(),
    })
}

/// Errors of a drop at one Δt, each the mean over release heights (see [`drop_sweep`]).
struct DropErrors {
    dt: f64,
    /// Median wall time of one run (s).
    wall: f64,
    apex: f64,
    position: f64,
    /// a·|Δθ| (cm).
    angle: f64,
}

/// Number of release heights the drop errors are averaged over.
const RELEASE_HEIGHTS: usize = 8;

/// Time-step sweep of a single-body drop. The impact falls at a different phase within a step for
/// every Δt, which scatters the error of a single run by an order of magnitude; each error is
/// therefore the mean over [`RELEASE_HEIGHTS`] release heights (shifted by 0.0137 cm apart, several
/// step lengths of the impact speed at the largest Δt), each against its own reference run at
/// `dt_ref`.
fn drop_sweep(
    case: &Case,
    dts: &[f64],
    dt_ref: f64,
    t_end: f64,
    reps: usize,
    a: f64,
) -> Result<Vec<DropErrors>, ReportError> {
    let variants: Vec<Case> = (0..RELEASE_HEIGHTS)
        .map(|k| {
            let mut c = case.clone();
            c.bodies[0].position.y += 0.0137 * k as f64;
            c
        })
        .collect();
    let refs: Vec<DropResult> = variants
        .iter()
        .map(|c| drop_run(c, dt_ref, t_end))
        .collect::<Result<_, _>>()?;
    dts.iter()
        .map(|&dt| {
            let (mut apex, mut position, mut angle) = (0.0, 0.0, 0.0);
            let mut walls = Vec::new();
            for (c, r) in variants.iter().zip(&refs) {
                let s = drop_run(c, dt, t_end)?;
                walls.push(s.wall);
                apex += (s.apex - r.apex).abs();
                position += (s.x - r.x).hypot(s.y - r.y);
                angle += a * (s.angle - r.angle).abs();
            }
            // Extra repetitions of the first height for the timing only.
            for _ in 1..reps {
                walls.push(drop_run(&variants[0], dt, t_end)?.wall);
            }
            let n = RELEASE_HEIGHTS as f64;
            Ok(DropErrors {
                dt,
                wall: median(walls),
                apex: apex / n,
                position: position / n,
                angle: angle / n,
            })
        })
        .collect()
}

/// Steps to rest (P's criterion, one step; `to_rest`) or the state at `t_max` (not `to_rest`).
struct SettleResult {
    dt: f64,
    wall: f64,
    rest_step: Option<u64>,
    state: Vec<(f64, f64, f64)>,
    /// Smallest critical step of the contact network, sampled every 1e-5 s.
    dt_network: f64,
    /// The largest of P's three measures over the last step run.
    final_increment: f64,
}

/// Without the blow-up watch: the stability sweep runs past the stability limit on purpose, and
/// a run that blows up ends where its state became non-finite (its last increments are the
/// figure's).
fn settle_run(case: &Case, dt: f64, t_max: f64, to_rest: bool) -> SettleResult {
    let mut w = case.clone().with_dt(dt).build_world();
    let q = case.quiescence.unwrap_or(1e-10);
    let steps = (t_max / dt).round() as u64;
    // The network's critical step every 1e-5 s of simulated time (every step at coarser Δt),
    // before the step.
    let sample = ((1e-5 / dt).round() as u64).max(1);
    let start = Instant::now();
    let mut rest_step = None;
    if sample == 1 {
        w.network_critical_dt();
    }
    let ended = Simulation::new(&mut w)
        .without_watch()
        .for_steps(steps)
        .run_until(|w, r| {
            if r.increments.iter().all(|&d| d <= q) {
                rest_step.get_or_insert(w.step);
                if to_rest {
                    return true;
                }
            }
            if (w.step + 1).is_multiple_of(sample) {
                w.network_critical_dt();
            }
            false
        });
    // A blow-up ends the run: that is what the sweep measures.
    let _: Result<_, RunError> = ended;
    let wall = start.elapsed().as_secs_f64();
    let state = w
        .bodies
        .state
        .iter()
        .map(|s| (s.pose.position.x, s.pose.position.y, s.pose.angle()))
        .collect();
    w.network_critical_dt();
    SettleResult {
        dt,
        wall,
        rest_step,
        state,
        dt_network: w.diagnostics.dt_critical_observed,
        final_increment: w.last_increments.iter().copied().fold(0.0, f64::max),
    }
}

/// Median wall time of `n` runs (the machines are shared; medians, in one run of the command).
fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Least-squares slope of log(err) against log(dt): the observed order.
fn order(points: &[(f64, f64)]) -> f64 {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|p| p.1 > 0.0 && p.1.is_finite())
        .map(|p| (p.0.ln(), p.1.ln()))
        .collect();
    let n = pts.len() as f64;
    if n < 2.0 {
        return f64::NAN;
    }
    let (sx, sy) = (
        pts.iter().map(|p| p.0).sum::<f64>(),
        pts.iter().map(|p| p.1).sum::<f64>(),
    );
    let (sxx, sxy) = (
        pts.iter().map(|p| p.0 * p.0).sum::<f64>(),
        pts.iter().map(|p| p.0 * p.1).sum::<f64>(),
    );
    (n * sxy - sx * sy) / (n * sxx - sx * sx)
}

/// The speed-vs-error report: the table, the CSV, the panel of error against Δt (all
/// deterministic), and the machine-dependent part: wall times and the panel of error against
/// wall time.
struct SpeedVsError {
    md: String,
    csv: String,
    by_dt: LinePanel,
    timings: String,
    by_wall: LinePanel,
}

fn speed_vs_error(opts: &FigureOptions) -> Result<SpeedVsError, ReportError> {
    note("figures: speed vs error sweeps");
    let reps = if opts.quick { 1 } else { 3 };
    let a = 1.5; // the ellipse's semi-axis: angle errors are shown as a·|Δθ| (cm)
    // Drop and rebound: apex of the first rebound and the state at t = 0.4 s; the paper's damped
    // case and the same drop elastic and frictionless (no dashpot: the force does not jump at
    // impact).
    let (drop, _) = load_case(&opts.cases.join("drop_rebound_mu05.json"))?;
    let mut elastic = drop.clone();
    elastic.contact = dem2d::contact_law::ContactSpec::linear(
        dem2d::contact_law::Scaled::OverRhoG(36400.0),
        dem2d::contact_law::Scaled::OverRhoG(36400.0),
        dem2d::contact_law::LinearDamping::Restitution(1.0),
        0.0,
    )
    .with_normal_force(drop.contact.normal_force());
    for w in &mut elastic.walls {
        w.spec = elastic.contact;
    }
    let drop_dts: Vec<f64> = if opts.quick {
        vec![2e-6, 1e-5, 5e-5]
    } else {
        vec![5e-7, 1e-6, 2e-6, 5e-6, 1e-5, 2e-5, 5e-5, 1e-4, 2e-4]
    };
    let dt_crit_drop = estimate_critical_dt(
        &dem2d::dynamics::Bodies::new(&drop.bodies),
        &drop.contact,
        &drop.walls,
        drop.gravity.norm(),
    );
    // Just after the first impact (it ends near 0.10 s): later states add the amplification of
    // repeated impacts to the error of each.
    let t_end = 0.12;
    let drop_rows = drop_sweep(&drop, &drop_dts, drop_dts[0] / 4.0, t_end, reps, a)?;
    let elastic_rows = drop_sweep(&elastic, &drop_dts, drop_dts[0] / 4.0, t_end, 1, a)?;
    // Settling: the state at t = 0.15 s, after the scene has settled. (The state at P's rest is
    // not comparable across Δt: P's criterion |Δx| ≤ 1e-10 per step is |v| ≤ 1e-10/Δt, so a smaller
    // step declares rest earlier, while the scene still creeps.)
    let (settle, _) = load_case(&opts.cases.join("settle3_dt1e-5.json"))?;
    let settle_dts: Vec<f64> = if opts.quick {
        vec![2e-6, 1e-5, 4e-5]
    } else {
        vec![1e-6, 2e-6, 5e-6, 1e-5, 2e-5, 4e-5]
    };
    let t_settled = 0.15;
    let sref = settle_run(&settle, settle_dts[0] / 4.0, t_settled, false);
    let mut settle_rows = Vec::new();
    for &dt in &settle_dts {
        let mut r = settle_run(&settle, dt, t_settled, false);
        r.wall = median(
            (0..reps)
                .map(|_| settle_run(&settle, dt, t_settled, false).wall)
                .chain([r.wall])
                .collect(),
        );
        settle_rows.push(r);
    }
    let state_err = |s: &[(f64, f64, f64)], r: &[(f64, f64, f64)]| {
        s.iter()
            .zip(r)
            .map(|(p, q)| (p.0 - q.0).hypot(p.1 - q.1) + a * (p.2 - q.2).abs())
            .fold(0.0, f64::max)
    };
    let mut csv = String::from(
        "case,dt,apex_error_cm,final_position_error_cm,final_angle_error_times_a_cm,rest_step,settled_state_error_cm\n",
    );
    let mut apex_pts = Vec::new();
    let mut pos_pts = Vec::new();
    let mut ang_pts = Vec::new();
    for r in &drop_rows {
        writeln!(
            csv,
            "drop_rebound_mu05,{:e},{:e},{:e},{:e},,",
            r.dt, r.apex, r.position, r.angle
        )
        .expect("string");
        apex_pts.push((r.dt, r.apex, r.wall));
        pos_pts.push((r.dt, r.position, r.wall));
        ang_pts.push((r.dt, r.angle, r.wall));
    }
    let mut el_pts = Vec::new();
    for r in &elastic_rows {
        writeln!(
            csv,
            "drop_elastic_frictionless,{:e},{:e},{:e},{:e},,",
            r.dt, r.apex, r.position, r.angle
        )
        .expect("string");
        el_pts.push((r.dt, r.position, r.wall));
    }
    let mut rest_pts = Vec::new();
    for r in &settle_rows {
        let er = state_err(&r.state, &sref.state);
        writeln!(
            csv,
            "settle3,{:e},,,,{},{:e}",
            r.dt,
            r.rest_step.map_or(String::new(), |s| s.to_string()),
            er
        )
        .expect("string");
        rest_pts.push((r.dt, er, r.wall));
    }
    // Observed orders over the smaller steps (the asymptotic range, Δt ≤ 1e-5).
    let small = |v: &[(f64, f64, f64)]| {
        v.iter()
            .filter(|p| p.0 <= 1e-5 + 1e-18)
            .map(|p| (p.0, p.1))
            .collect::<Vec<_>>()
    };
    let (o_apex, o_pos, o_ang, o_rest) = (
        order(&small(&apex_pts)),
        order(&small(&pos_pts)),
        order(&small(&ang_pts)),
        order(&small(&rest_pts)),
    );
    let o_el = order(&small(&el_pts));
    let mut md = format!(
        "Reference: the same run at Δt/4 of the smallest step shown (drop: Δt = {:e} s, state at t = {t_end} s, just after the first rebound; settling: Δt = {:e} s, state at t = {t_settled} s, after rest). \
         Drop errors are means over {RELEASE_HEIGHTS} release heights 0.0137 cm apart (the phase of the impact within a step scatters single runs by an order of magnitude). \
         Errors of angles are shown as a·|Δθ| with a = 1.5 cm. Observed order (least-squares slope of log error against log Δt for Δt ≤ 1e-5 s): \
         paper drop (damped, friction): apex {o_apex:.2}, final position {o_pos:.2}, final angle {o_ang:.2}; the same drop elastic and frictionless: final position {o_el:.2}; \
         settled state {o_rest:.2}. A-priori critical step: drop {:.2e} s, settling {:.2e} s.\n\n",
        drop_dts[0] / 4.0,
        settle_dts[0] / 4.0,
        dt_crit_drop,
        estimate_critical_dt(
            &dem2d::dynamics::Bodies::new(&settle.bodies),
            &settle.contact,
            &settle.walls,
            settle.gravity.norm()
        )
    );
    md.push_str("| case | Δt (s) | steps per run | apex error (cm) | final position error (cm) | final a·angle error (cm) | rest step (P) | settled-state error (cm) |\n|---|---:|---:|---:|---:|---:|---:|---:|\n");
    let mut timings = String::from(
        "\n## Speed against error\n\nWall time per run (s; median of the repetitions).\n\n| case | Δt (s) | steps per run | wall time (s) |\n|---|---:|---:|---:|\n",
    );
    let steps = |t: f64, dt: f64| (t / dt).round() as u64;
    for (r, ((a_, p_), t_)) in drop_rows
        .iter()
        .zip(apex_pts.iter().zip(&pos_pts).zip(&ang_pts))
    {
        let n = steps(t_end, r.dt);
        writeln!(
            md,
            "| drop, μ = 0.5 | {:e} | {n} | {:.2e} | {:.2e} | {:.2e} | | |",
            r.dt, a_.1, p_.1, t_.1
        )
        .expect("string");
        writeln!(
            timings,
            "| drop, μ = 0.5 | {:e} | {n} | {:.4} |",
            r.dt, r.wall
        )
        .expect("string");
    }
    for (r, p) in elastic_rows.iter().zip(&el_pts) {
        let n = steps(t_end, r.dt);
        writeln!(
            md,
            "| drop, elastic, frictionless | {:e} | {n} | | {:.2e} | | | |",
            r.dt, p.1
        )
        .expect("string");
        writeln!(
            timings,
            "| drop, elastic, frictionless | {:e} | {n} | {:.4} |",
            r.dt, r.wall
        )
        .expect("string");
    }
    for (r, p) in settle_rows.iter().zip(&rest_pts) {
        let rest = r.rest_step.map_or("never".to_string(), |s| s.to_string());
        let n = steps(t_settled, r.dt);
        writeln!(
            md,
            "| settle3 | {:e} | {n} | | | | {rest} | {:.2e} |",
            r.dt, p.1
        )
        .expect("string");
        writeln!(timings, "| settle3 | {:e} | {n} | {:.4} |", r.dt, r.wall).expect("string");
    }
    let as_series = |pts: &[(f64, f64, f64)], label: &str, color: usize, by_wall: bool| Series {
        label: label.into(),
        points: pts
            .iter()
            .map(|p| (if by_wall { p.2 } else { p.0 }, p.1))
            .collect(),
        color,
        line: true,
        markers: true,
        hollow: false,
        point_labels: Vec::new(),
        y_errors: Vec::new(),
    };
    // Two decades of headroom above the data for the legends.
    let all = apex_pts
        .iter()
        .chain(&pos_pts)
        .chain(&ang_pts)
        .chain(&el_pts)
        .chain(&rest_pts);
    let (lo, hi) = all
        .map(|p| p.1)
        .filter(|v| *v > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(l, h), v| (l.min(v), h.max(v)));
    let y_range = (
        10f64.powf(lo.log10().floor()),
        10f64.powf(hi.log10().ceil() + 2.0),
    );
    let by_wall = LinePanel {
        title: "error against wall time (velocity Verlet; this machine)".into(),
        x_label: "wall time per run (s)".into(),
        y_label: "error (cm)".into(),
        log_x: true,
        log_y: true,
        y_range: Some(y_range),
        series: vec![
            as_series(&apex_pts, "drop: apex of first rebound", 0, true),
            as_series(&pos_pts, "drop: position at 0.12 s", 1, true),
            as_series(&ang_pts, "drop: a·angle at 0.12 s", 2, true),
            as_series(&el_pts, "drop, elastic frictionless: position", 4, true),
            as_series(&rest_pts, "settle3: state at 0.15 s", 3, true),
        ],
        ..Default::default()
    };
    let by_dt = LinePanel {
        title: format!(
            "error against Δt; order {o_pos:.1} damped, {o_el:.1} elastic, {o_rest:.1} settling"
        ),
        x_label: "Δt (s)".into(),
        y_label: "error (cm)".into(),
        log_x: true,
        log_y: true,
        y_range: Some(y_range),
        series: vec![
            as_series(&apex_pts, "drop: apex", 0, false),
            as_series(&pos_pts, "drop: position", 1, false),
            as_series(&ang_pts, "drop: a·angle", 2, false),
            as_series(&el_pts, "drop, elastic: position", 4, false),
            as_series(&rest_pts, "settle3: state at 0.15 s", 3, false),
        ],
        vlines: vec![(dt_crit_drop, "drop: a-priori critical Δt".into())],
        ..Default::default()
    };
    Ok(SpeedVsError {
        md,
        csv,
        by_dt,
        timings,
        by_wall,
    })
}

fn stability(opts: &FigureOptions) -> Result<(String, String, Vec<LinePanel>), ReportError> {
    note("figures: stability sweep");
    let (settle, _) = load_case(&opts.cases.join("settle3_dt1e-5.json"))?;
    let bodies = dem2d::dynamics::Bodies::new(&settle.bodies);
    let dt_crit = estimate_critical_dt(
        &bodies,
        &settle.contact,
        &settle.walls,
        settle.gravity.norm(),
    );
    let dts: Vec<f64> = if opts.quick {
        vec![1e-6, 1e-5, 4e-5, 6e-5, 1e-4]
    } else {
        vec![
            1e-6, 2e-6, 5e-6, 1e-5, 2e-5, 3e-5, 4e-5, 4.5e-5, 5e-5, 5.5e-5, 6e-5, 7e-5, 8e-5, 9e-5,
            1e-4, 1.5e-4, 2e-4,
        ]
    };
    let runs: Vec<SettleResult> = dts
        .iter()
        .map(|&dt| settle_run(&settle, dt, 0.5, true))
        .collect();
    // The network's stiffest mode: the smallest seen along the runs that reached rest (a run that
    // declares rest early, at a turning point, sees fewer configurations; unstable runs visit
    // configurations the physical motion does not).
    let dt_net = runs
        .iter()
        .filter(|r| r.rest_step.is_some())
        .map(|r| r.dt_network)
        .fold(f64::INFINITY, f64::min);
    let mut csv = String::from("dt,rest_step,time_to_rest_s,network_dt_critical_s\n");
    let mut md = format!(
        "Critical time step of the scene: a priori, from the stiffest single contact it can have (damping and lever arms included), {dt_crit:.3e} s; \
         from the stiffest mode of the actual contact network (the smallest seen along the runs that reached rest, sampled every 1e-5 s), {dt_net:.3e} s. Runs of at most 0.5 s.\n\n\
         | Δt (s) | Δt / Δt_crit (single contact) | Δt / Δt_crit (network) | network Δt_crit seen in this run (s) | steps to rest | time to rest (s) |\n|---:|---:|---:|---:|---:|---:|\n"
    );
    let (mut rest, mut final_rest, mut final_never) = (Vec::new(), Vec::new(), Vec::new());
    let (mut last_rest, mut first_failure) = (None, None);
    for r in &runs {
        let dt = r.dt;
        match r.rest_step {
            Some(s) => {
                rest.push((dt, s as f64));
                final_rest.push((dt, r.final_increment));
                last_rest = Some(dt);
                writeln!(
                    md,
                    "| {dt:e} | {:.2} | {:.2} | {:.3e} | {s} | {:.4} |",
                    dt / dt_crit,
                    dt / dt_net,
                    r.dt_network,
                    s as f64 * dt
                )
                .expect("string");
            }
            None => {
                final_never.push((dt, r.final_increment));
                first_failure.get_or_insert(dt);
                writeln!(
                    md,
                    "| {dt:e} | {:.2} | {:.2} | {:.3e} | never | never |",
                    dt / dt_crit,
                    dt / dt_net,
                    r.dt_network
                )
                .expect("string");
            }
        }
        let rest_s = r.rest_step.map_or(String::new(), |s| s.to_string());
        let time_s = r
            .rest_step
            .map_or(String::new(), |s| format!("{:e}", s as f64 * dt));
        writeln!(csv, "{dt:e},{rest_s},{time_s},{:e}", r.dt_network).expect("string");
    }
    if let Some(d) = first_failure {
        writeln!(md, "\nSmallest Δt that never reached rest: {d:e} s = {:.2} × the network estimate = {:.2} × the single-contact estimate.", d / dt_net, d / dt_crit).expect("string");
    }
    if let Some(d) = last_rest {
        writeln!(md, "Largest Δt that reached rest: {d:e} s (near the limit the outcome is not monotone in Δt: a weakly unstable mode may or may not lock into a sustained oscillation before the scene settles).").expect("string");
    }
    let vlines = vec![
        (dt_net, format!("network critical Δt = {dt_net:.2e} s")),
        (
            dt_crit,
            format!("single-contact critical Δt = {dt_crit:.2e} s"),
        ),
    ];
    // Two quantities, two panels: the steps to rest of the runs that rested, and for every
    // run where its increments ended (the runs that never rested stop at 0.5 s).
    let x_range = Some((dts[0] / 2.0, dts[dts.len() - 1] * 2.0));
    let steps = LinePanel {
        title: "(a) P Fig. 4 scene: steps to rest against Δt (runs that reached rest)".into(),
        x_label: "Δt (s)".into(),
        y_label: "steps to rest".into(),
        log_x: true,
        log_y: true,
        x_range,
        series: vec![Series {
            label: "at rest (P's criterion)".into(),
            points: rest,
            color: 0,
            line: true,
            markers: true,
            hollow: false,
            point_labels: Vec::new(),
            y_errors: Vec::new(),
        }],
        vlines: vlines.clone(),
        ..Default::default()
    };
    let q = settle.quiescence.unwrap_or(1e-10);
    let ends = LinePanel {
        title: "(b) the largest of P's three measures at the last step (at rest, or after 0.5 s)"
            .into(),
        x_label: "Δt (s)".into(),
        y_label: "max(|Δx|, |Δy|, |Δθ|) per step (cm; rad)".into(),
        log_x: true,
        log_y: true,
        x_range,
        series: vec![
            Series {
                label: "reached rest".into(),
                points: final_rest,
                color: 0,
                line: false,
                markers: true,
                hollow: false,
                point_labels: Vec::new(),
                y_errors: Vec::new(),
            },
            Series {
                label: "never at rest in 0.5 s".into(),
                points: final_never,
                color: 1,
                line: false,
                markers: true,
                hollow: true,
                point_labels: Vec::new(),
                y_errors: Vec::new(),
            },
        ],
        hlines: vec![(q, format!("threshold {q:e}"))],
        ..Default::default()
    };
    let panel = vec![steps, ends];
    Ok((md, csv, panel))
}

/// The hard-case families with their worst errors (deterministic), and the kernel's median time
/// per pair of each family (machine-dependent).
fn kernel_report(quick: bool) -> (String, String) {
    let reports = run_families();
    let reps = if quick { 3 } else { 15 };
    let ns: Vec<f64> = reports
        .iter()
        .map(|r| {
            let passes = (20_000 / r.pairs.len().max(1)).max(1);
            let times: Vec<f64> = (0..reps)
                .map(|_| {
                    let start = Instant::now();
                    let mut acc = 0.0;
                    for _ in 0..passes {
                        for (i, j) in &r.pairs {
                            if let Some(g) =
                                contact(std::hint::black_box(i), std::hint::black_box(j))
                            {
                                acc += g.depth;
                            }
                        }
                    }
                    std::hint::black_box(acc);
                    start.elapsed().as_secs_f64() * 1e9 / (passes * r.pairs.len()) as f64
                })
                .collect();
            median(times)
        })
        .collect();
    let failures: usize = reports.iter().map(|r| r.failures.len()).sum();
    let table = format!(
        "{}\nBars: depth 1e-12·a_max, normal 1e-8 rad (corner-on-corner rectangles: the conditioning of their chord), point 1e-9·a_max; rigid motion and swap in units of those bars. Failures: {failures}.\n",
        markdown_table(&reports, None)
    );
    let mut times = format!(
        "\n## Contact kernel, time per pair\n\nMedian of {reps} timings of each family's own pairs (mixed states: overlapping, separated, deep, contained).\n\n| family | ns/pair |\n|---|---:|\n"
    );
    for (r, t) in reports.iter().zip(&ns) {
        writeln!(times, "| {} | {t:.0} |", r.name).expect("string");
    }
    (table, times)
}
