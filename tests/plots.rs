//! `dem2d plot`: every kind of plot is written as a well-formed SVG carrying
//! its title, axis labels with units and legend; a directory that is not a run is refused with
//! the file named (`dem2d-lab figures` is tested in lab/tests/figures.rs).
//! (Whether the pictures read well is checked by eye on PNGs: `bash .ci/figures`.)

use std::process::Command;

mod common;
use common::{dem2d, scratch};

/// The SVG's texts, unescaped (`&lt;` etc. are not used in our labels).
fn texts(svg: &str) -> Vec<String> {
    svg.split("<text")
        .skip(1)
        .filter_map(|t| {
            let start = t.find('>')? + 1;
            let end = t.find("</text>")?;
            Some(t[start..end].to_string())
        })
        .collect()
}

#[test]
fn every_plot_kind_writes_an_svg_with_title_axes_and_units() {
    let dir = scratch("settle3");
    let (code, _, err) = dem2d(&[
        "run",
        "cases/settle3_dt1e-5.json",
        "--out",
        dir.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    let expect: [(&str, &[&str]); 3] = [
        ("scene", &["settle3", "x (cm)", "y (cm)"]),
        (
            "series",
            &[
                "settle3",
                "t (s)",
                "centroid height y (cm)",
                "angle θ (rad)",
                "body 2",
            ],
        ),
        (
            "quiescence",
            &[
                "settle3",
                "step",
                "mean increment per step (|Δx|, |Δy| in cm; |Δθ| in rad)",
                "threshold 1e-10",
                "mean |Δθ| (rad)",
            ],
        ),
    ];
    for (kind, wanted) in expect {
        let out = dir.join(format!("{kind}-plot.svg"));
        let (code, stdout, err) = dem2d(&[
            "plot",
            dir.to_str().unwrap(),
            "--kind",
            kind,
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{kind}: {err}");
        assert!(stdout.contains(out.to_str().unwrap()));
        let svg = std::fs::read_to_string(&out).unwrap();
        assert!(
            svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"),
            "{kind}: not a whole SVG"
        );
        let t = texts(&svg);
        for w in wanted {
            assert!(
                t.iter().any(|s| s.contains(w)),
                "{kind}: no text {w:?} in {t:?}"
            );
        }
        // Something is drawn besides the axes: outlines or series as paths/polylines.
        assert!(
            svg.matches("<polyline").count() + svg.matches("<path").count() >= 3,
            "{kind}: nothing drawn"
        );
    }
}

/// The polylines of an SVG with exactly `points` points (outlines of circles and ellipses are
/// closed 72-gons: 73 points; axes, ticks and wall hatching have 2).
fn polylines_with(svg: &str, points: usize) -> usize {
    svg.split("<polyline")
        .skip(1)
        .filter(|p| {
            let Some(start) = p.find("points=\"") else {
                return false;
            };
            let rest = &p[start + 8..];
            rest[..rest.find('"').unwrap_or(0)]
                .split_whitespace()
                .count()
                == points
        })
        .count()
}

/// The point lists of every element starting with `tag` (`<polygon`, `<polyline`).
fn shapes_points(svg: &str, tag: &str) -> Vec<Vec<(f64, f64)>> {
    svg.split(tag)
        .skip(1)
        .filter_map(|p| {
            let start = p.find("points=\"")? + 8;
            let rest = &p[start..];
            let list = &rest[..rest.find('"')?];
            Some(
                list.split_whitespace()
                    .map(|xy| {
                        let (x, y) = xy.split_once(',').unwrap();
                        (x.parse().unwrap(), y.parse().unwrap())
                    })
                    .collect(),
            )
        })
        .collect()
}

/// Width and height of a point set.
fn extent(pts: &[(f64, f64)]) -> (f64, f64) {
    let f = |g: fn(&(f64, f64)) -> f64| {
        let (lo, hi) = pts
            .iter()
            .map(g)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
                (l.min(v), h.max(v))
            });
        hi - lo
    };
    (f(|p| p.0), f(|p| p.1))
}

/// Least-squares line `v = s·u + c` through `(u, v)` pairs: `(s, c, worst residual)`.
fn fit(pts: &[(f64, f64)]) -> (f64, f64, f64) {
    let n = pts.len() as f64;
    let (mu, mv) = (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let suv: f64 = pts.iter().map(|p| (p.0 - mu) * (p.1 - mv)).sum();
    let suu: f64 = pts.iter().map(|p| (p.0 - mu).powi(2)).sum();
    let s = suv / suu;
    let c = mv - s * mu;
    let worst = pts
        .iter()
        .map(|p| (p.1 - s * p.0 - c).abs())
        .fold(0.0, f64::max);
    (s, c, worst)
}

#[test]
fn a_many_body_run_plots_as_a_snapshot_and_summarised_series() {
    let dir = scratch("pile300");
    let case = dir.join("pile.json");
    let (code, _, err) = dem2d(&[
        "generate",
        "--shape",
        "disks",
        "--n",
        "300",
        "--seed",
        "7",
        "--out",
        case.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let run = dir.join("run");
    let (code, _, err) = dem2d(&[
        "run",
        case.to_str().unwrap(),
        "--out",
        run.to_str().unwrap(),
        "--max-steps",
        "20000",
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    // Scene: one outline per body (at the last frame), none of the earlier outlines or paths.
    let scene = dir.join("scene.svg");
    let (code, _, err) = dem2d(&[
        "plot",
        run.to_str().unwrap(),
        "--out",
        scene.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let svg = std::fs::read_to_string(&scene).unwrap();
    assert_eq!(polylines_with(&svg, 73), 300);
    // Equal scale: a unit of x is as long as a unit of y. The filled outlines are drawn in body
    // order; fit drawing = s·world + c on each axis by least squares over every vertex (against
    // the body's outline computed from the trajectory, independently of the drawing) and
    // compare the two scales. Before the fix the plot area's height was guessed, and circles
    // came out 6–9 % taller than wide.
    let data = dem2d::output::run_data::RunData::load(&run).unwrap();
    let last = data.frames.last().unwrap();
    let drawn = shapes_points(&svg, "<polygon");
    assert_eq!(drawn.len(), 300);
    let (mut px, mut py) = (Vec::new(), Vec::new());
    for (k, pts) in drawn.iter().enumerate() {
        let b = last.bodies[k];
        let world = dem2d::output::plot::outline(&data.case.bodies[k].shape, b.x, b.y, b.angle);
        assert_eq!(pts.len() + 1, world.len(), "body {k}");
        for (p, w) in pts.iter().zip(&world) {
            px.push((w.0, p.0));
            py.push((w.1, p.1));
        }
        // Each circle's drawn width and height agree to the pixel (coordinates are whole
        // drawing units, each extreme within one).
        let (w, h) = extent(pts);
        assert!((w - h).abs() <= 2.0, "body {k}: {w} × {h}");
    }
    let ((sx, _, rx), (sy, _, ry)) = (fit(&px), fit(&py));
    assert!(
        (sy / sx + 1.0).abs() < 2e-3,
        "x scale {sx}, y scale {sy} units per cm"
    );
    // The fit is good to the rounding of the drawing's integer coordinates.
    assert!(rx <= 1.0 && ry <= 1.0, "worst residuals {rx}, {ry}");
    // Series: the summary lines, not 300 legend entries.
    let series = dir.join("series.svg");
    let (code, _, err) = dem2d(&[
        "plot",
        run.to_str().unwrap(),
        "--kind",
        "series",
        "--out",
        series.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let t = texts(&std::fs::read_to_string(&series).unwrap());
    for w in [
        "mean of 300 bodies",
        "lowest",
        "highest",
        "largest",
        "rotation |θ − θ₀|",
    ] {
        assert!(t.iter().any(|s| s.contains(w)), "no text {w:?} in {t:?}");
    }
    assert!(!t.iter().any(|s| s.contains("body 0")), "{t:?}");
    // The summary lines bracket every body, and the mean is the mean, read back from the
    // trajectory file (heights) at every frame.
    let data = dem2d::output::run_data::RunData::load(&run).unwrap();
    let panels = dem2d::output::panels::time_series(&[(&data, "")], "pile");
    let [mean, low, high] = [0, 1, 2].map(|s| &panels[0].series[s].points);
    assert_eq!(mean.len(), data.frames.len());
    for (k, f) in data.frames.iter().enumerate() {
        let ys: Vec<f64> = f.bodies.iter().map(|b| b.y).collect();
        let m = ys.iter().sum::<f64>() / ys.len() as f64;
        assert!((mean[k].1 - m).abs() <= 1e-12 * m.abs().max(1.0));
        assert_eq!(low[k].1, ys.iter().cloned().fold(f64::INFINITY, f64::min));
        assert_eq!(
            high[k].1,
            ys.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
        );
    }
}

#[test]
fn plotting_a_directory_that_is_not_a_run_names_the_missing_file() {
    let dir = scratch("not_a_run");
    let (code, _, err) = dem2d(&["plot", dir.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("case.json") || err.contains("trajectory.csv"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    // A truncated trajectory is refused with the file and line.
    let run = scratch("truncated");
    let (code, _, err) = dem2d(&[
        "run",
        "cases/settle3_dt1e-5.json",
        "--out",
        run.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    let traj = run.join("trajectory.csv");
    let text = std::fs::read_to_string(&traj).unwrap();
    std::fs::write(&traj, format!("{text}1,2,x\n")).unwrap();
    let (code, _, err) = dem2d(&["plot", run.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("trajectory.csv") && err.contains("line"),
        "{err}"
    );
}

/// Width and height of a PNG, from its IHDR chunk (after checking the signature).
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "not a PNG");
    assert_eq!(&bytes[12..16], b"IHDR");
    let be = |k: usize| u32::from_be_bytes(bytes[k..k + 4].try_into().unwrap());
    (be(16), be(20))
}

/// The displayed size an SVG declares.
fn svg_size(svg: &str) -> (u32, u32) {
    let num = |key: &str| {
        let start = svg.find(key).unwrap() + key.len();
        svg[start..].split('"').next().unwrap().parse().unwrap()
    };
    (num("width=\""), num("height=\""))
}

#[test]
fn plot_options_png_output_and_bad_options() {
    let run = scratch("options");
    let (code, _, err) = dem2d(&[
        "run",
        "cases/settle3_dt1e-5.json",
        "--out",
        run.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    let r = run.to_str().unwrap();
    // `--out x.png` writes a real PNG, at twice the SVG's displayed size.
    let (svg, png) = (run.join("s.svg"), run.join("s.png"));
    for out in [&svg, &png] {
        let (code, _, err) = dem2d(&["plot", r, "--out", out.to_str().unwrap()]);
        assert_eq!(code, 0, "{err}");
    }
    let (w, h) = svg_size(&std::fs::read_to_string(&svg).unwrap());
    assert_eq!(png_size(&std::fs::read(&png).unwrap()), (2 * w, 2 * h));
    // Colour by a quantity: a colour bar with its label and units; the last frame only: one
    // outline per body (ellipses a/b = 1.5: 84 vertices, closed).
    let out = run.join("force.svg");
    let (code, _, err) = dem2d(&[
        "plot",
        r,
        "--out",
        out.to_str().unwrap(),
        "--color",
        "speed",
        "--last",
    ]);
    assert_eq!(code, 0, "{err}");
    let s = std::fs::read_to_string(&out).unwrap();
    assert!(
        texts(&s).iter().any(|t| t.trim() == "speed |v| (cm/s)"),
        "{:?}",
        texts(&s)
    );
    assert_eq!(polylines_with(&s, 85), 3);
    // An outline every 0.01 s over 0.02–0.05 s: 4 outlines per body.
    let (code, _, err) = dem2d(&[
        "plot",
        r,
        "--out",
        out.to_str().unwrap(),
        "--from",
        "0.02",
        "--to",
        "0.05",
        "--every",
        "0.01",
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        polylines_with(&std::fs::read_to_string(&out).unwrap(), 85),
        12
    );
    // Bad options: refused naming the option, exit code 2, nothing written.
    let gone = run.join("never.svg");
    let g = gone.to_str().unwrap();
    for (args, want) in [
        (vec!["--out", "x.pdf"], "dem2d plot writes SVG or PNG"),
        (
            vec!["--out", g, "--from", "0.05", "--to", "0.01"],
            "--from 0.05 is after --to 0.01",
        ),
        (
            vec!["--out", g, "--every", "0"],
            "--every: must be a positive time",
        ),
        (
            vec!["--out", g, "--every=-1"],
            "--every: must be a positive time",
        ),
        (vec!["--out", g, "--from", "7"], "no frame of"),
        (vec!["--out", g, "--width", "5"], "--width: must be 200"),
        (
            vec!["--out", g, "--kind", "series", "--last"],
            "apply to --kind scene only",
        ),
        (vec!["--out", g, "--color", "heat"], "invalid value 'heat'"),
    ] {
        let mut all = vec!["plot", r];
        all.extend(args);
        let (code, _, err) = dem2d(&all);
        assert_eq!(code, 2, "{all:?}: {err}");
        assert!(err.contains(want), "{all:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    assert!(!gone.exists());
    // An unwritable output: exit code 1, the file named.
    let bad = run.join("no/such/dir/x.png");
    let (code, _, err) = dem2d(&["plot", r, "--out", bad.to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains(&format!("{}: cannot write", bad.display())),
        "{err}"
    );
}

#[test]
fn plot_refuses_what_it_cannot_draw() {
    let run = scratch("huge");
    let (code, _, err) = dem2d(&[
        "run",
        "cases/settle3_dt1e-5.json",
        "--out",
        run.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    // A coordinate of 1e155 (a run that blew up) made the scene plot grow without end: it must
    // return, promptly, with the range named.
    let traj = run.join("trajectory.csv");
    let text = std::fs::read_to_string(&traj).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let last = lines.pop().unwrap();
    let mut fields: Vec<&str> = last.split(',').collect();
    fields[3] = "1e155";
    lines.push(fields.join(","));
    std::fs::write(&traj, lines.join("\n") + "\n").unwrap();
    let mut child = Command::new(common::bin())
        .args(["plot", run.to_str().unwrap()])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if start.elapsed().as_secs() > 60 {
            child.kill().unwrap();
            panic!("plot did not return in 60 s");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    };
    let mut err = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
    assert_eq!(status.code(), Some(1), "{err}");
    assert!(
        err.contains("cannot be drawn") && err.contains("1.03e155"),
        "{err}"
    );
}

#[test]
fn a_periodic_cell_is_drawn_at_its_size_with_the_images_of_the_bodies_a_seam_cuts() {
    // The shear tutorial's cell, 6000 steps (its height has shrunk under the imposed pressure):
    // a snapshot (150 bodies), each body a filled polygon followed by its images. Which images
    // overlap the cell, and where they lie — `(x + kx Lx + ky s, y + ky Ly)` with s the
    // Lees–Edwards offset of the image above — is worked out here from trajectory.csv and
    // cell.csv, and the polygons' centres are fitted against it.
    let dir = scratch("cell");
    let run = dir.join("run");
    let (code, _, err) = dem2d(&[
        "run",
        "cases/shear_cell.json",
        "--out",
        run.to_str().unwrap(),
        "--quiet",
        "--max-steps",
        "6000",
    ]);
    assert_eq!(code, 0, "{err}");
    let svg_path = dir.join("scene.svg");
    let (code, _, err) = dem2d(&[
        "plot",
        run.to_str().unwrap(),
        "--out",
        svg_path.to_str().unwrap(),
        "--images",
    ]);
    assert_eq!(code, 0, "{err}");
    let svg = std::fs::read_to_string(&svg_path).unwrap();
    let cell = std::fs::read_to_string(run.join("cell.csv")).unwrap();
    let last: Vec<f64> = cell
        .lines()
        .last()
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    let (step, lx, ly, offset) = (last[0], last[2], last[3], last[4]);
    assert!(ly < 19.0, "the cell should have shrunk: {ly}");
    let case: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(run.join("case.json")).unwrap()).unwrap();
    let radii: Vec<f64> = case["bodies"]
        .as_array()
        .unwrap()
        .iter()
        .map(|b| b["shape"]["r"].as_f64().unwrap())
        .collect();
    let traj = std::fs::read_to_string(run.join("trajectory.csv")).unwrap();
    let mut want = Vec::new();
    for row in traj.lines().skip(1) {
        let v: Vec<f64> = row.split(',').map(|v| v.parse().unwrap()).collect();
        if v[0] != step {
            continue;
        }
        let (x, y, r) = (v[3], v[4], radii[v[2] as usize]);
        want.push((x, y));
        for ky in [-1.0, 0.0, 1.0] {
            for kx in [-1.0, 0.0, 1.0] {
                let (cx, cy) = (x + kx * lx + ky * offset, y + ky * ly);
                if (kx, ky) != (0.0, 0.0)
                    && cx + r > 0.0
                    && cx - r < lx
                    && cy + r > 0.0
                    && cy - r < ly
                {
                    want.push((cx, cy));
                }
            }
        }
    }
    assert!(want.len() > radii.len() + 5, "few images: {}", want.len());
    let polygons = shapes_points(&svg, "<polygon");
    assert_eq!(polygons.len(), want.len(), "bodies and their images");
    let centres: Vec<(f64, f64)> = polygons
        .iter()
        .map(|p| {
            let n = p.len() as f64;
            (
                p.iter().map(|q| q.0).sum::<f64>() / n,
                p.iter().map(|q| q.1).sum::<f64>() / n,
            )
        })
        .collect();
    let (sx, _, wx) = fit(&want
        .iter()
        .zip(&centres)
        .map(|(w, c)| (w.0, c.0))
        .collect::<Vec<_>>());
    let (sy, _, wy) = fit(&want
        .iter()
        .zip(&centres)
        .map(|(w, c)| (w.1, c.1))
        .collect::<Vec<_>>());
    // Within a pixel; at equal scale (y drawn upwards).
    assert!(wx < 1.0 && wy < 1.0, "centres off by {wx}, {wy} px");
    assert!((sx + sy).abs() < 0.002 * sx, "scales {sx}, {sy}");
    // The cell's rectangle at the last frame's size: a closed 5-point polyline whose extent is
    // Lx × Ly at that scale.
    let rect = shapes_points(&svg, "<polyline")
        .into_iter()
        .filter(|p| p.len() == 5 && p[0] == p[4])
        .map(|p| extent(&p))
        .find(|&(w, h)| (w / sx - lx).abs() < 0.05 && (h / sx - ly).abs() < 0.05);
    assert!(
        rect.is_some(),
        "no rectangle of the cell's size {lx} × {ly}"
    );
    // --images on a run without a cell is refused.
    let plain = dir.join("plain");
    let (code, _, _) = dem2d(&[
        "run",
        "cases/settle3_dt1e-5.json",
        "--out",
        plain.to_str().unwrap(),
        "--quiet",
        "--max-steps",
        "10",
    ]);
    assert_eq!(code, 0);
    let (code, _, err) = dem2d(&["plot", plain.to_str().unwrap(), "--images"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--images") && err.contains("no periodic cell"),
        "{err}"
    );
}
