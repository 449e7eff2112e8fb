//! `dem2d animate`: the HTML player.
//!
//! - Always: the file is self-contained (a Content-Security-Policy of `default-src 'none'`, no
//!   address, no external script, style or font, no fetch), and its data — decoded here from
//!   the page — holds every frame of `trajectory.csv` (positions, angles, velocities to 32-bit
//!   precision), each body's outline by its identity (an inserted body's shape as
//!   `inserted.csv` records it, in every frame until `discharge.csv` removes it), the walls, the
//!   cell and `contacts.csv`'s contacts per frame.
//! - In a real browser: headless Chromium opens the page with no console message (an error, an
//!   uncaught exception or a blocked load would each print one: a planted page shows that the
//!   check sees them), and its screenshot has the bodies where `trajectory.csv` puts them: for
//!   every body, points inside it (off its axis mark) have its fill colour, and for every
//!   elongated ellipse a point 0.9 a along its own axis is filled while a point 1.15 a along it
//!   is not — at the first frame and the last, and after bodies were inserted and removed. The
//!   page says where it draws (`data-view`, read from the DOM Chromium dumps).
//!
//! The browser part needs Chromium (Debian: `chromium`; `DEM2D_CHROMIUM` names another):
//! without it the test says so and passes, unless `DEM2D_REQUIRE_CHROMIUM` is set — as `.ci/run`
//! sets it after installing the package, so that CI never skips it. The screenshots are left in
//! `TARGET_TMPDIR/player/`.

use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

mod common;
use common::{MIXED_SCENE, dem2d, scratch, sheared_cell};

/// Standard base64 (RFC 4648) decoded, for the page's arrays.
fn unbase64(s: &str) -> Vec<u8> {
    let val = |c: u8| -> u32 {
        match c {
            b'A'..=b'Z' => (c - b'A') as u32,
            b'a'..=b'z' => (c - b'a' + 26) as u32,
            b'0'..=b'9' => (c - b'0' + 52) as u32,
            b'+' => 62,
            b'/' => 63,
            _ => panic!("not base64: {c}"),
        }
    };
    let mut out = Vec::new();
    for chunk in s.as_bytes().chunks(4) {
        let pad = chunk.iter().filter(|&&c| c == b'=').count();
        let mut v = 0u32;
        for &c in chunk {
            v = (v << 6) | if c == b'=' { 0 } else { val(c) };
        }
        let bytes = [(v >> 16) as u8, (v >> 8) as u8, v as u8];
        out.extend_from_slice(&bytes[..3 - pad]);
    }
    out
}

fn f32s(s: &str) -> Vec<f32> {
    unbase64(s)
        .chunks(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect()
}

fn u32s(s: &str) -> Vec<u32> {
    unbase64(s)
        .chunks(4)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect()
}

/// `trajectory.csv` as text: per step, the rows (body, x, y, angle, vx, vy, omega).
fn trajectory(dir: &Path) -> Vec<(u64, Vec<[f64; 7]>)> {
    let text = std::fs::read_to_string(dir.join("trajectory.csv")).unwrap();
    let mut out: Vec<(u64, Vec<[f64; 7]>)> = Vec::new();
    for line in text.lines().skip(1) {
        let f: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        let step = f[0] as u64;
        if out.last().is_none_or(|l| l.0 != step) {
            out.push((step, Vec::new()));
        }
        out.last_mut()
            .unwrap()
            .1
            .push([f[2], f[3], f[4], f[5], f[6], f[7], f[8]]);
    }
    out
}

fn run(dir: &Path, name: &str, case: &str, extra: &[&str]) -> PathBuf {
    let file = dir.join(format!("{name}.json"));
    std::fs::write(&file, case).unwrap();
    let out = dir.join(name);
    let mut args = vec![
        "run",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ];
    args.extend(extra);
    let (code, _, err) = dem2d(&args);
    assert_eq!(code, 0, "{err}");
    out
}

/// Writes the player of `run` (its default place, RUN/animation.html) and returns its text.
fn animate(run: &Path) -> String {
    let (code, stdout, err) = dem2d(&["animate", run.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("animation.html"), "{stdout}");
    std::fs::read_to_string(run.join("animation.html")).unwrap()
}

/// The page's data object.
fn page_data(html: &str) -> Value {
    let open = "<script id=\"data\" type=\"application/json\">";
    let a = html.find(open).unwrap() + open.len();
    let b = a + html[a..].find("</script>").unwrap();
    serde_json::from_str(&html[a..b]).unwrap()
}

/// Nothing in the page can load anything: the policy forbids it, and nothing tries.
fn assert_self_contained(html: &str) {
    assert!(html.contains(
        "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; \
         script-src 'unsafe-inline'; style-src 'unsafe-inline'\">"
    ));
    let lower = html.to_lowercase();
    for bad in [
        "http:",
        "https:",
        "//cdn",
        " src=",
        " href=",
        "<link",
        "@import",
        "url(",
        "fetch(",
        "xmlhttprequest",
        "websocket",
        "import(",
        "<iframe",
        "<img",
    ] {
        assert!(!lower.contains(bad), "the page holds `{bad}`");
    }
    assert_eq!(
        lower.matches("<script").count(),
        2,
        "the data and the code, both inline"
    );
}

/// The page's frames against the trajectory: every row, by identity.
fn assert_frames_match(d: &Value, traj: &[(u64, Vec<[f64; 7]>)]) {
    let frames = d["frames"].as_array().unwrap();
    assert_eq!(frames.len(), traj.len());
    let state = f32s(d["state"].as_str().unwrap());
    let ids: Vec<u64> = d["ids"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_u64().unwrap())
        .collect();
    let index = d["index"].as_str().map(u32s);
    let mut row = 0;
    for (k, (step, rows)) in traj.iter().enumerate() {
        assert_eq!(frames[k]["step"].as_u64(), Some(*step));
        assert_eq!(d["count"][k].as_u64(), Some(rows.len() as u64));
        for (m, r) in rows.iter().enumerate() {
            let table = index.as_ref().map_or(m, |ix| ix[row] as usize);
            assert_eq!(ids[table], r[0] as u64, "frame {k}: row {m}'s identity");
            for c in 0..6 {
                assert_eq!(
                    state[6 * row + c],
                    r[c + 1] as f32,
                    "frame {k}, body {}",
                    r[0]
                );
            }
            row += 1;
        }
    }
    assert_eq!(row * 6, state.len());
}

/// A body's outline as the page has it, by identity: `(a, b)` for an ellipse or disk, the
/// vertex count otherwise.
fn page_shape(d: &Value, id: u64) -> Value {
    let ids = d["ids"].as_array().unwrap();
    let t = ids.iter().position(|v| v.as_u64() == Some(id)).unwrap();
    let s = d["body_shape"][t].as_u64().unwrap() as usize;
    d["shapes"][s].clone()
}

fn f(v: &Value, k: &str) -> f64 {
    v[k].as_f64().unwrap()
}

fn num2(v: &Value) -> (f64, f64) {
    (v[0].as_f64().unwrap(), v[1].as_f64().unwrap())
}

/// Bodies poured into a small box and drained through an outflow below it.
const FLOW: &str = r#"{
  "version": 1, "name": "player_flow", "units": "cm", "gravity": [0, -981], "dt": 1e-4,
  "duration": 0.25, "output_every": 250,
  "contact": {"model": "linear", "kn_over_rho_g": 2000, "restitution": 0.5, "friction": 0.3},
  "bodies": [{"shape": {"type": "circle", "r": 0.6}, "position": [0, -2], "velocity": [0, -20]}],
  "insert": [{"region": [-5, 5, 0, 3], "rate": 120, "shape": "ellipse",
              "size": {"uniform": [0.4, 0.6]}, "aspect": {"choice": [1.6, 2.5, 3]},
              "velocity": [0, -40], "seed": 5}],
  "outflow": [{"region": [-20, 20, -100, -5]}]
}"#;

#[test]
fn the_page_is_self_contained_and_holds_every_frame_by_identity() {
    let dir = scratch("data");
    // The mixed scene, with its contacts.
    let mix = run(&dir, "mix", MIXED_SCENE, &["--contacts"]);
    let html = animate(&mix);
    assert_self_contained(&html);
    let d = page_data(&html);
    let traj = trajectory(&mix);
    assert_frames_match(&d, &traj);
    let case: Value = serde_json::from_str(MIXED_SCENE).unwrap();
    for (k, b) in case["bodies"].as_array().unwrap().iter().enumerate() {
        let s = page_shape(&d, k as u64);
        let sh = &b["shape"];
        match sh["type"].as_str().unwrap() {
            "circle" => assert_eq!(num2(&s["e"]), (f(sh, "r"), f(sh, "r"))),
            "ellipse" => assert_eq!(num2(&s["e"]), (f(sh, "a"), f(sh, "b"))),
            // Corners about the centroid: a rectangle's four, the polygon's five.
            "rectangle" => assert_eq!(s["p"].as_array().unwrap().len(), 8),
            "polygon" => assert_eq!(s["p"].as_array().unwrap().len(), 10),
            t => panic!("{t}"),
        }
    }
    // Three walls at every frame; the contacts of contacts.csv, frame by frame.
    let contacts = std::fs::read_to_string(mix.join("contacts.csv")).unwrap();
    let mut per_step: BTreeMap<u64, u64> = BTreeMap::new();
    for line in contacts.lines().skip(1) {
        *per_step
            .entry(line.split(',').next().unwrap().parse().unwrap())
            .or_default() += 1;
    }
    for (k, (step, _)) in traj.iter().enumerate() {
        assert_eq!(d["walls"][k].as_array().unwrap().len(), 15);
        assert_eq!(
            d["contacts"]["count"][k].as_u64(),
            Some(per_step.get(step).copied().unwrap_or(0))
        );
    }
    assert!(per_step.values().sum::<u64>() > 20);

    // Bodies inserted and removed: each identity's outline is the one inserted.csv records.
    let flow = run(&dir, "flow", FLOW, &[]);
    let d = page_data(&animate(&flow));
    let traj = trajectory(&flow);
    assert_frames_match(&d, &traj);
    let inserted = std::fs::read_to_string(flow.join("inserted.csv")).unwrap();
    let mut n = 0;
    for line in inserted.lines().skip(1) {
        let f: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        let (id, r, alpha) = (f[2] as u64, f[4], f[5]);
        let e = page_shape(&d, id)["e"].clone();
        let (a, b) = (e[0].as_f64().unwrap(), e[1].as_f64().unwrap());
        assert!((a - r * alpha.sqrt()).abs() < 1e-12 && (b - r / alpha.sqrt()).abs() < 1e-12);
        n += 1;
    }
    let discharged = std::fs::read_to_string(flow.join("discharge.csv")).unwrap();
    assert!(n >= 20 && discharged.lines().count() > 5, "{n} inserted");

    // A sheared periodic cell: the cell at every frame, as cell.csv has it.
    let cell = run(&dir, "cell", &sheared_cell(), &[]);
    let d = page_data(&animate(&cell));
    let rows = std::fs::read_to_string(cell.join("cell.csv")).unwrap();
    for (k, line) in rows.lines().skip(1).enumerate() {
        let f: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        let c: Vec<f64> = d["cells"][k]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        assert_eq!(c, [f[2], f[3], f[4], 1.0]);
    }

    // --every keeps every N-th frame and the last; a bad --out or --every is refused.
    let (code, _, err) = dem2d(&[
        "animate",
        mix.to_str().unwrap(),
        "--every",
        "4",
        "--out",
        dir.join("thin.html").to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let d = page_data(&std::fs::read_to_string(dir.join("thin.html")).unwrap());
    let steps: Vec<u64> = d["frames"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["step"].as_u64().unwrap())
        .collect();
    assert_eq!(steps, [0, 4000, 8000, 10000]);
    for (args, want) in [
        (vec!["--out", "x.svg"], ".html (the player), .mp4 or .gif"),
        (vec!["--every", "0"], "--every: must be at least 1"),
    ] {
        let mut a = vec!["animate", mix.to_str().unwrap()];
        a.extend(args);
        let (code, _, err) = dem2d(&a);
        assert_eq!(code, 2, "{err}");
        assert!(err.contains(want), "{err}");
    }
    let (code, _, err) = dem2d(&["animate", dir.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("case.json"), "{err}");
}

/// Chromium, if there is one.
fn chromium() -> Option<String> {
    let candidates: Vec<String> = std::env::var("DEM2D_CHROMIUM")
        .into_iter()
        .chain(["chromium", "chromium-browser", "google-chrome"].map(String::from))
        .collect();
    candidates.into_iter().find(|c| {
        Command::new(c)
            .arg("--version")
            .output()
            .is_ok_and(|o| o.status.success())
    })
}

/// Runs headless Chromium on `page` (`file://` address with `hash`) with a fresh profile, its
/// console written to stderr; `what` is `--dump-dom` or `--screenshot=FILE`. Returns stdout
/// and the console lines.
fn browse(
    chrome: &str,
    profile: &Path,
    page: &Path,
    hash: &str,
    what: &str,
) -> (String, Vec<String>) {
    let _ = std::fs::remove_dir_all(profile);
    let url = format!("file://{}{hash}", page.display());
    let out = Command::new(chrome)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--no-first-run",
            "--hide-scrollbars",
            "--force-device-scale-factor=1",
            "--window-size=1000,700",
            "--enable-logging=stderr",
            "--v=0",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(what)
        .arg(url)
        .output()
        .expect("run chromium");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "chromium failed: {stderr}");
    // Every console message, of any level (Chromium logs them all as INFO:CONSOLE).
    let console = stderr
        .lines()
        .filter(|l| l.contains(":CONSOLE"))
        .map(String::from)
        .collect();
    (String::from_utf8_lossy(&out.stdout).into_owned(), console)
}

/// The screenshot's pixel at page point (x, y), as RGB.
struct Shot {
    pixmap: resvg::tiny_skia::Pixmap,
}

impl Shot {
    fn at(&self, x: f64, y: f64) -> [u8; 3] {
        let (i, j) = (x.round() as u32, y.round() as u32);
        let p = self
            .pixmap
            .pixel(i, j)
            .unwrap_or_else(|| panic!("({x}, {y}) off the screenshot"));
        [p.red(), p.green(), p.blue()]
    }
}

fn near(a: [u8; 3], b: [u8; 3], tol: i32) -> bool {
    (0..3).all(|c| (a[c] as i32 - b[c] as i32).abs() <= tol)
}

/// The page's first categorical colour (material 0).
const FILL: [u8; 3] = [0x4e, 0x79, 0xa7];

/// Opens the player of `run` at frame `k` coloured by material, checks the console and the
/// pixels of the trajectory's bodies; `axes` gives each identity's semi-axes (an ellipse's a, b;
/// for another shape its inscribed radius as both and `false`). Returns the bodies checked.
fn check_frame(
    chrome: &str,
    dir: &Path,
    run: &Path,
    k: usize,
    axes: &dyn Fn(u64) -> (f64, f64, bool),
) -> usize {
    let page = run.join("animation.html");
    let traj = trajectory(run);
    // A canvas of a fixed size: Chromium's window differs between --dump-dom and --screenshot.
    let hash = format!("#frame={k}&color=material&size=1000x600");
    let (dom, console) = browse(chrome, &dir.join("profile"), &page, &hash, "--dump-dom");
    assert!(console.is_empty(), "console: {console:?}");
    let view = dom
        .split("data-view=\"")
        .nth(1)
        .and_then(|s| s.split('"').next())
        .unwrap_or_else(|| panic!("no data-view in the DOM"));
    let v: Vec<f64> = view.split(',').map(|x| x.parse().unwrap()).collect();
    assert!(dom.contains(&format!("data-frame=\"{k}\"")), "frame {k}");
    let (s, x0, y0) = (v[0], v[1], v[2]);
    let png = dir.join(format!(
        "{}_frame{k}.png",
        run.file_name().unwrap().to_str().unwrap()
    ));
    let (_, console) = browse(
        chrome,
        &dir.join("profile"),
        &page,
        &hash,
        &format!("--screenshot={}", png.display()),
    );
    assert!(console.is_empty(), "console: {console:?}");
    let shot = Shot {
        pixmap: resvg::tiny_skia::Pixmap::decode_png(&std::fs::read(&png).unwrap()).unwrap(),
    };
    let px = |x: f64, y: f64| (x0 + s * x, y0 - s * y);
    let rows = &traj[k].1;
    let mut checked = 0;
    for r in rows {
        let (id, x, y, th) = (r[0] as u64, r[1], r[2], r[3]);
        let (a, b, ellipse) = axes(id);
        let (c, sn) = (th.cos(), th.sin());
        // Off the axis mark (drawn from the centre along x): half way along the body's y axis.
        let inside = (x - 0.5 * b * sn, y + 0.5 * b * c);
        let (ix, iy) = px(inside.0, inside.1);
        if !(0.0..1000.0).contains(&ix) || !(80.0..650.0).contains(&iy) {
            continue;
        }
        let got = shot.at(ix, iy);
        assert!(
            near(got, FILL, 12),
            "frame {k}, body {id} at ({x}, {y}): {got:?} at its inside point, not its fill"
        );
        if ellipse && a >= 1.4 * b && s * a > 20.0 {
            // Along the body's own axis: filled at 0.9 a (past the axis mark's 0.8 R), not at
            // 1.15 a — where nothing else is.
            let (fx, fy) = px(x + 0.9 * a * c, y + 0.9 * a * sn);
            assert!(
                near(shot.at(fx, fy), FILL, 12),
                "frame {k}, ellipse {id}: not along its axis"
            );
            let out = (x + 1.15 * a * c, y + 1.15 * a * sn);
            let clear = rows.iter().all(|o| {
                o[0] == r[0] || (o[1] - out.0).hypot(o[2] - out.1) > 1.05 * axes(o[0] as u64).0
            });
            if clear {
                let (ox, oy) = px(out.0, out.1);
                assert!(
                    !near(shot.at(ox, oy), FILL, 40),
                    "frame {k}, ellipse {id}: too long"
                );
            }
        }
        checked += 1;
    }
    checked
}

#[test]
fn chromium_opens_the_player_without_errors_and_draws_the_bodies_where_they_are() {
    let dir = scratch("browser");
    let Some(chrome) = chromium() else {
        assert!(
            std::env::var_os("DEM2D_REQUIRE_CHROMIUM").is_none(),
            "DEM2D_REQUIRE_CHROMIUM is set but no Chromium was found (apt-get install chromium)"
        );
        eprintln!(
            "SKIPPED the browser check: no Chromium (Debian: apt-get install chromium; .ci/run \
             installs it)"
        );
        return;
    };
    // The console check sees errors: a planted page's error and exception are both caught.
    let planted = dir.join("planted.html");
    std::fs::write(
        &planted,
        "<!DOCTYPE html><html><body><script>console.error('planted error');\
         throw new Error('planted throw');</script></body></html>",
    )
    .unwrap();
    let (_, console) = browse(&chrome, &dir.join("profile"), &planted, "", "--dump-dom");
    assert!(
        console.iter().any(|l| l.contains("planted error"))
            && console
                .iter()
                .any(|l| l.contains("Uncaught Error: planted throw")),
        "{console:?}"
    );

    let mix = run(&dir, "mix", MIXED_SCENE, &["--contacts"]);
    animate(&mix);
    let case: Value = serde_json::from_str(MIXED_SCENE).unwrap();
    let bodies = case["bodies"].as_array().unwrap().clone();
    let mix_axes = move |id: u64| -> (f64, f64, bool) {
        let sh = &bodies[id as usize]["shape"];
        let f = |k: &str| sh[k].as_f64().unwrap();
        match sh["type"].as_str().unwrap() {
            "circle" => (f("r"), f("r"), true),
            "ellipse" => (f("a"), f("b"), true),
            // A safe inside distance: well within the rectangle (h = 1) and the polygon.
            _ => (0.5, 0.5, false),
        }
    };
    let n = check_frame(&chrome, &dir, &mix, 0, &mix_axes);
    assert_eq!(n, 7, "every body of the first frame");
    let last = trajectory(&mix).len() - 1;
    let n = check_frame(&chrome, &dir, &mix, last, &mix_axes);
    assert_eq!(n, 7, "every body of the last frame");

    // After insertion and outflow: each body drawn with its own shape.
    let flow = run(&dir, "flow", FLOW, &[]);
    animate(&flow);
    let mut shapes: BTreeMap<u64, (f64, f64, bool)> = BTreeMap::new();
    shapes.insert(0, (0.6, 0.6, true));
    let inserted = std::fs::read_to_string(flow.join("inserted.csv")).unwrap();
    for line in inserted.lines().skip(1) {
        let f: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        shapes.insert(f[2] as u64, (f[4] * f[5].sqrt(), f[4] / f[5].sqrt(), true));
    }
    let frames = trajectory(&flow).len();
    let removed = std::fs::read_to_string(flow.join("discharge.csv"))
        .unwrap()
        .lines()
        .count()
        - 1;
    assert!(removed >= 3, "{removed} removed");
    let present = trajectory(&flow)[frames - 1].1.len();
    let n = check_frame(&chrome, &dir, &flow, frames - 1, &|id| shapes[&id]);
    assert!(n == present && n >= 8, "{n} of {present} bodies checked");
}

/// `--out FILE.gif` / `.mp4` go through ffmpeg: without it the command says so (exit 2) and
/// writes nothing; with it (where installed: CI does not install it) the movie has one picture
/// per frame at the width asked, as ffprobe counts them.
#[test]
fn movies_go_through_ffmpeg_or_say_that_it_is_missing() {
    let dir = scratch("movie");
    let mix = run(&dir, "mix", MIXED_SCENE, &[]);
    let gif = dir.join("m.gif");
    let empty = dir.join("no-programs");
    std::fs::create_dir_all(&empty).unwrap();
    let out = Command::new(common::bin())
        .args([
            "animate",
            mix.to_str().unwrap(),
            "--out",
            gif.to_str().unwrap(),
        ])
        .env("PATH", &empty)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("ffmpeg not found") && err.contains("apt-get install ffmpeg"),
        "{err}"
    );
    assert!(!gif.exists());
    let has = |p: &str| {
        Command::new(p)
            .arg("-version")
            .output()
            .is_ok_and(|o| o.status.success())
    };
    if !(has("ffmpeg") && has("ffprobe")) {
        eprintln!(
            "SKIPPED the movie check: no ffmpeg and ffprobe (Debian: apt-get install ffmpeg)"
        );
        return;
    }
    for (name, width) in [("m.gif", 500), ("m.mp4", 640)] {
        let file = dir.join(name);
        let w = width.to_string();
        let (code, _, err) = dem2d(&[
            "animate",
            mix.to_str().unwrap(),
            "--out",
            file.to_str().unwrap(),
            "--width",
            &w,
            "--color",
            "spin",
        ]);
        assert_eq!(code, 0, "{err}");
        let probe = Command::new("ffprobe")
            .args([
                "-v",
                "error",
                "-count_frames",
                "-show_entries",
                "stream=nb_read_frames,width",
                "-of",
                "csv=p=0",
            ])
            .arg(&file)
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&probe.stdout);
        assert_eq!(text.trim(), format!("{width},11"), "{name}");
    }
}
