//! `dem2d export RUN --format lammps-dump` and `dem2d run --dump`: the LAMMPS-style dump read
//! back by a strict parser written here from LAMMPS's format (every `ITEM:` in LAMMPS's order,
//! the counts, the box lines, the fixed column list, every field a number), against the run's
//! own files read as text — `trajectory.csv` (positions, velocities and angles to the bit, the
//! time as written), `case.json` (each shape's size, measured here: a polygon's bounding radius
//! from its vertices about its area centroid), `inserted.csv` and `discharge.csv` (identities
//! across insertion and outflow), `cell.csv` (the periodic box and its Lees–Edwards tilt). The
//! dump written while running equals the export of the same run byte for byte, and writing it
//! changes nothing else. Bad requests are refused naming the file.
//!
//! OVITO's own reader and renderer read the same dumps in `tests/ovito.rs`.

use std::collections::BTreeMap;
use std::path::Path;

mod common;
use common::{MIXED_SCENE as MIX, dem2d, scratch, sheared_cell};

/// The dump's columns, fixed by the issue that asked for it (LAMMPS's names).
const COLUMNS: &str = "id type x y z vx vy omegaz shapex shapey shapez quatw quati quatj quatk \
                       angle shape material";

/// One frame as the parser reads it.
#[derive(Debug)]
struct Frame {
    time: String,
    step: u64,
    /// `ITEM: BOX BOUNDS`'s words after `BOUNDS`.
    bounds: Vec<String>,
    /// The three box lines.
    lines: [Vec<f64>; 3],
    /// Each atom's fields (the integer columns as numbers too).
    atoms: Vec<Vec<f64>>,
}

/// Parses a dump strictly: anything out of LAMMPS's order or shape fails, naming the line.
fn parse_dump(text: &str) -> Vec<Frame> {
    assert!(text.ends_with('\n'), "the dump ends with a whole line");
    let lines: Vec<&str> = text.lines().collect();
    let k = std::cell::Cell::new(0);
    let next = |what: &str| -> &str {
        let l = *lines
            .get(k.get())
            .unwrap_or_else(|| panic!("line {}: end of file, expected {what}", k.get() + 1));
        k.set(k.get() + 1);
        l
    };
    let mut frames = Vec::new();
    let width = COLUMNS.split(' ').count();
    loop {
        assert_eq!(next("ITEM: TIME"), "ITEM: TIME");
        let time = next("the time").to_string();
        time.parse::<f64>().expect("a time");
        assert_eq!(next("ITEM: TIMESTEP"), "ITEM: TIMESTEP");
        let step: u64 = next("the step").parse().expect("a step");
        assert_eq!(next("ITEM: NUMBER OF ATOMS"), "ITEM: NUMBER OF ATOMS");
        let n: usize = next("the count").parse().expect("a count");
        let b = next("ITEM: BOX BOUNDS");
        let bounds: Vec<String> = b
            .strip_prefix("ITEM: BOX BOUNDS ")
            .unwrap_or_else(|| panic!("{b}"))
            .split(' ')
            .map(String::from)
            .collect();
        let tilted = bounds.len() == 6;
        assert!(
            bounds.len() == 3 || (tilted && bounds[..3] == ["xy", "xz", "yz"]),
            "{b}"
        );
        for f in &bounds[bounds.len() - 3..] {
            assert!(f == "pp" || f == "ff", "{b}");
        }
        let box_line = || -> Vec<f64> {
            let v: Vec<f64> = next("a box line")
                .split(' ')
                .map(|x| x.parse().unwrap())
                .collect();
            assert_eq!(v.len(), if tilted { 3 } else { 2 });
            assert!(v[0] <= v[1], "{v:?}");
            v
        };
        let lines3 = [box_line(), box_line(), box_line()];
        assert_eq!(next("ITEM: ATOMS"), format!("ITEM: ATOMS {COLUMNS}"));
        let mut atoms = Vec::with_capacity(n);
        for _ in 0..n {
            let row: Vec<&str> = next("an atom").split(' ').collect();
            assert_eq!(row.len(), width, "{row:?}");
            // id, type, shape and material are integers.
            for i in [0, 1, 16, 17] {
                row[i].parse::<u64>().expect("an integer column");
            }
            atoms.push(row.iter().map(|x| x.parse::<f64>().unwrap()).collect());
        }
        frames.push(Frame {
            time,
            step,
            bounds,
            lines: lines3,
            atoms,
        });
        if k.get() == lines.len() {
            return frames;
        }
    }
}

/// `trajectory.csv` read as text: per step (in order), the time as written and the rows'
/// fields (body, x, y, angle, vx, vy, omega).
type Traj = Vec<(u64, String, Vec<[f64; 7]>)>;

fn read_trajectory(dir: &Path) -> Traj {
    let text = std::fs::read_to_string(dir.join("trajectory.csv")).unwrap();
    let mut out: Traj = Vec::new();
    for line in text.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let step: u64 = f[0].parse().unwrap();
        let v: Vec<f64> = f[2..9].iter().map(|x| x.parse().unwrap()).collect();
        if out.last().is_none_or(|l| l.0 != step) {
            out.push((step, f[1].to_string(), Vec::new()));
        }
        out.last_mut()
            .unwrap()
            .2
            .push([v[0], v[1], v[2], v[3], v[4], v[5], v[6]]);
    }
    out
}

/// The semi-axes an exact viewer draws (a, b), or for a shape that is not an ellipse its
/// bounding radius (R, R), measured here from the case's shape (`shape` of case.json).
fn expected_axes(shape: &serde_json::Value) -> (f64, f64, u64) {
    let f = |k: &str| shape[k].as_f64().unwrap();
    match shape["type"].as_str().unwrap() {
        "circle" => (f("r"), f("r"), 0),
        "ellipse" => (f("a"), f("b"), 1),
        "rectangle" => {
            let r = 0.5 * f("w").hypot(f("h"));
            (r, r, 2)
        }
        "polygon" => {
            // The area centroid (shoelace), then the farthest vertex from it.
            let v: Vec<(f64, f64)> = shape["vertices"]
                .as_array()
                .unwrap()
                .iter()
                .map(|p| (p[0].as_f64().unwrap(), p[1].as_f64().unwrap()))
                .collect();
            let (mut a, mut cx, mut cy) = (0.0, 0.0, 0.0);
            for i in 0..v.len() {
                let (p, q) = (v[i], v[(i + 1) % v.len()]);
                let cross = p.0 * q.1 - q.0 * p.1;
                a += cross / 2.0;
                cx += (p.0 + q.0) * cross;
                cy += (p.1 + q.1) * cross;
            }
            let (cx, cy) = (cx / (6.0 * a), cy / (6.0 * a));
            let r = v
                .iter()
                .map(|p| (p.0 - cx).hypot(p.1 - cy))
                .fold(0.0, f64::max);
            (r, r, 3)
        }
        other => panic!("no expectation for {other}"),
    }
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs())
}

/// Checks one atom row against the trajectory row `t` and the body's expected axes; returns
/// nothing, panics naming the body.
fn check_atom(atom: &[f64], t: &[f64; 7], (a, b, code): (f64, f64, u64), material: u64) {
    let body = t[0];
    assert_eq!(atom[0], body + 1.0, "id = identity + 1");
    assert_eq!(atom[1], (material + 1) as f64, "body {body}: type");
    // Positions, velocities, spin and angle to the bit.
    for (col, tcol) in [(2, 1), (3, 2), (5, 4), (6, 5), (7, 6), (15, 3)] {
        assert_eq!(
            atom[col].to_bits(),
            t[tcol].to_bits(),
            "body {body}: column {col}"
        );
    }
    assert_eq!(atom[4], 0.0, "z");
    // Diameters, the thin z a tenth of the smaller.
    assert!(
        close(atom[8], 2.0 * a, 1e-15),
        "body {body}: shapex {}",
        atom[8]
    );
    assert!(
        close(atom[9], 2.0 * b, 1e-15),
        "body {body}: shapey {}",
        atom[9]
    );
    assert!(
        close(atom[10], 0.2 * a.min(b), 1e-15),
        "body {body}: shapez"
    );
    // A unit quaternion about z whose angle is the body's (mod 2π).
    let (w, i, j, k) = (atom[11], atom[12], atom[13], atom[14]);
    assert_eq!((i, j), (0.0, 0.0));
    assert!((w * w + k * k - 1.0).abs() < 1e-15, "body {body}: |q|");
    let turn = 2.0 * k.atan2(w) - t[3];
    let off = turn - std::f64::consts::TAU * (turn / std::f64::consts::TAU).round();
    assert!(
        off.abs() < 1e-12 * t[3].abs().max(1.0),
        "body {body}: angle {} vs {}",
        2.0 * k.atan2(w),
        t[3]
    );
    assert_eq!(atom[16], code as f64, "body {body}: shape code");
    assert_eq!(atom[17], material as f64);
}

fn run(case_text: &str, dir: &Path, name: &str, extra: &[&str]) -> std::path::PathBuf {
    let case = dir.join(format!("{name}.json"));
    std::fs::write(&case, case_text).unwrap();
    let out = dir.join(name);
    let mut args = vec![
        "run",
        case.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ];
    args.extend(extra);
    let (code, _, err) = dem2d(&args);
    assert_eq!(code, 0, "{err}");
    out
}

fn export(run: &Path, out: &Path) {
    let (code, stdout, err) = dem2d(&[
        "export",
        run.to_str().unwrap(),
        "--format",
        "lammps-dump",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("frames"), "{stdout}");
}

#[test]
fn the_dump_of_a_mixed_scene_holds_the_trajectory_shapes_and_orientations() {
    let dir = scratch("mix");
    let out = run(MIX, &dir, "mix", &["--dump"]);
    let dumped = std::fs::read_to_string(out.join("dump.lammpstrj")).unwrap();
    // The export of the run is the same file, byte for byte; its default place is RUN/.
    let exported = dir.join("exported.lammpstrj");
    export(&out, &exported);
    assert!(dumped == std::fs::read_to_string(&exported).unwrap());
    let (code, _, err) = dem2d(&["export", out.to_str().unwrap(), "--format", "lammps-dump"]);
    assert_eq!(code, 0, "{err}");
    assert!(dumped == std::fs::read_to_string(out.join("dump.lammpstrj")).unwrap());
    // Writing it changed nothing else.
    let plain = run(MIX, &dir, "plain", &[]);
    for f in ["trajectory.csv", "increments.csv", "walls.csv"] {
        assert!(
            std::fs::read(out.join(f)).unwrap() == std::fs::read(plain.join(f)).unwrap(),
            "{f}"
        );
    }
    assert!(!plain.join("dump.lammpstrj").exists());

    let frames = parse_dump(&dumped);
    let traj = read_trajectory(&out);
    let case: serde_json::Value = serde_json::from_str(MIX).unwrap();
    let axes: Vec<(f64, f64, u64)> = case["bodies"]
        .as_array()
        .unwrap()
        .iter()
        .map(|b| expected_axes(&b["shape"]))
        .collect();
    assert_eq!(frames.len(), traj.len());
    assert_eq!(frames.len(), 11, "steps 0, 1000, …, 10000");
    let mut turned = 0;
    for (f, (step, t, rows)) in frames.iter().zip(&traj) {
        assert_eq!((f.step, &f.time), (*step, t));
        assert_eq!(f.atoms.len(), rows.len());
        assert_eq!(f.bounds, ["ff", "ff", "ff"]);
        // The box: the walls at x = 0 and 30 and y = 0, and every body's bounding circle.
        let (mut x0, mut x1, mut y0, mut y1) = (0.0f64, 30.0f64, 0.0f64, 0.0f64);
        let mut reach: f64 = 0.0;
        for (atom, row) in f.atoms.iter().zip(rows) {
            let ax = axes[row[0] as usize];
            check_atom(atom, row, ax, 0);
            let r = if ax.2 <= 1 { ax.0.max(ax.1) } else { ax.0 };
            reach = reach.max(r);
            (x0, x1) = (x0.min(row[1] - r), x1.max(row[1] + r));
            (y0, y1) = (y0.min(row[2] - r), y1.max(row[2] + r));
            if row[3].abs() > std::f64::consts::PI {
                turned += 1;
            }
        }
        assert_eq!(f.lines[0], [x0, x1]);
        assert_eq!(f.lines[1], [y0, y1]);
        assert_eq!(f.lines[2], [-reach, reach]);
    }
    // Some angles went past ±π (the spinning ellipse): the quaternion still holds them.
    assert!(turned > 0);
}

/// Bodies inserted and removed: every identity keeps its shape (the one inserted.csv records
/// for it) from the frame it appears in to the frame it leaves, and is never given to another.
#[test]
fn identities_and_shapes_stay_with_their_bodies_across_insertion_and_outflow() {
    let dir = scratch("flow");
    let case = r#"{
  "version": 1, "name": "dump_flow", "units": "cm", "gravity": [0, -981], "dt": 1e-4,
  "duration": 0.3, "output_every": 100,
  "contact": {"model": "linear", "kn_over_rho_g": 2000, "restitution": 0.5, "friction": 0.3},
  "bodies": [{"shape": {"type": "circle", "r": 0.7}, "position": [30, 0], "velocity": [0, -30]}],
  "insert": [{"region": [-10, 10, 0, 4], "rate": 400, "shape": "ellipse",
              "size": {"uniform": [0.3, 0.5]}, "aspect": {"choice": [1.5, 2, 3]},
              "velocity": [0, -100], "seed": 11}],
  "outflow": [{"region": [-20, 40, -1000, -20]}]
}"#;
    let out = run(case, &dir, "flow", &["--dump"]);
    let dumped = std::fs::read_to_string(out.join("dump.lammpstrj")).unwrap();
    let exported = dir.join("exported.lammpstrj");
    export(&out, &exported);
    assert!(dumped == std::fs::read_to_string(&exported).unwrap());
    // What each identity is: body 0 the case's disk, the others inserted.csv's ellipses.
    let mut axes: BTreeMap<u64, (f64, f64, u64)> = BTreeMap::new();
    axes.insert(0, (0.7, 0.7, 0));
    let inserted = std::fs::read_to_string(out.join("inserted.csv")).unwrap();
    for line in inserted.lines().skip(1) {
        let f: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        let (r, alpha) = (f[4], f[5]);
        axes.insert(f[2] as u64, (r * alpha.sqrt(), r / alpha.sqrt(), 1));
    }
    let mut removed: BTreeMap<u64, u64> = BTreeMap::new();
    let discharge = std::fs::read_to_string(out.join("discharge.csv")).unwrap();
    for line in discharge.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        removed.insert(f[2].parse().unwrap(), f[0].parse().unwrap());
    }
    assert!(removed.len() >= 10, "{} removed", removed.len());
    assert!(removed.contains_key(&0), "the case's own disk leaves too");
    let frames = parse_dump(&dumped);
    let traj = read_trajectory(&out);
    assert_eq!(frames.len(), traj.len());
    let mut seen: BTreeMap<u64, (f64, f64)> = BTreeMap::new();
    for (f, (step, _, rows)) in frames.iter().zip(&traj) {
        assert_eq!(f.step, *step);
        assert_eq!(f.atoms.len(), rows.len());
        for (atom, row) in f.atoms.iter().zip(rows) {
            let id = row[0] as u64;
            check_atom(atom, row, axes[&id], 0);
            assert!(
                removed.get(&id).is_none_or(|&s| s >= *step),
                "body {id} after removal"
            );
            let sh = (atom[8], atom[9]);
            assert_eq!(*seen.entry(id).or_insert(sh), sh, "body {id} changed shape");
        }
    }
    // Many more bodies passed through than a frame ever holds.
    let most = frames.iter().map(|f| f.atoms.len()).max().unwrap();
    assert!(
        seen.len() > most + 10,
        "{} seen, at most {most} at once",
        seen.len()
    );
}

/// A periodic cell: `pp pp` over the cell as `cell.csv` has it; under Lees–Edwards shear a
/// triclinic box whose tilt is the image above's shift (mod L_x, in [−L_x/2, L_x/2)); a cell
/// periodic in x only, `pp ff`.
#[test]
fn a_periodic_cell_is_the_dump_box_with_the_lees_edwards_tilt() {
    let dir = scratch("cell");
    let case = sheared_cell();
    let out = run(&case, &dir, "le", &["--dump"]);
    let dumped = std::fs::read_to_string(out.join("dump.lammpstrj")).unwrap();
    let exported = dir.join("exported.lammpstrj");
    export(&out, &exported);
    assert!(dumped == std::fs::read_to_string(&exported).unwrap());
    let frames = parse_dump(&dumped);
    let cells = std::fs::read_to_string(out.join("cell.csv")).unwrap();
    let cells: Vec<Vec<f64>> = cells
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(frames.len(), cells.len());
    let traj = read_trajectory(&out);
    let mut tilted = 0;
    for ((f, c), (_, _, rows)) in frames.iter().zip(&cells).zip(&traj) {
        assert_eq!(f.step as f64, c[0]);
        let (lx, ly, offset) = (c[2], c[3], c[4]);
        assert_eq!(f.bounds, ["xy", "xz", "yz", "pp", "pp", "ff"]);
        let xy = f.lines[0][2];
        assert!((-lx / 2.0..lx / 2.0).contains(&xy), "tilt {xy}");
        let k = ((offset - xy) / lx).round();
        assert!(
            (offset - xy - k * lx).abs() < 1e-12 * lx,
            "{offset} vs {xy}"
        );
        assert_eq!(f.lines[0][..2], [xy.min(0.0), lx + xy.max(0.0)]);
        assert_eq!(f.lines[1], [0.0, ly, 0.0]);
        if xy != 0.0 {
            tilted += 1;
        }
        for (atom, row) in f.atoms.iter().zip(rows) {
            let k = row[0] as usize;
            let ax = if k.is_multiple_of(2) {
                (0.5, 0.5, 0)
            } else {
                (0.7, 0.4, 1)
            };
            check_atom(atom, row, ax, 0);
        }
    }
    assert!(tilted >= 9, "{tilted} tilted frames");

    // Periodic in x only, between a floor and a lid: `pp ff ff`, x over the cell.
    let case = r#"{ "version": 1, "name": "dump_x", "units": "cm",
  "gravity": [0, -980], "dt": 1e-5, "duration": 0.02, "output_every": 1000,
  "cell": { "size": [8, 10], "periodic": "x" },
  "contact": { "model": "linear", "kn_over_rho_g": 36400, "restitution": 0.5, "friction": 0.5 },
  "walls": [ { "point": [0, 0], "normal": [0, 1] }, { "point": [0, 10], "normal": [0, -1] } ],
  "bodies": [ { "shape": {"type": "ellipse", "a": 1.0, "b": 0.5}, "position": [7.5, 1] },
              { "shape": {"type": "circle", "r": 0.6}, "position": [0.2, 1] } ] }"#;
    let out = run(case, &dir, "x", &["--dump"]);
    let frames = parse_dump(&std::fs::read_to_string(out.join("dump.lammpstrj")).unwrap());
    let traj = read_trajectory(&out);
    assert_eq!(frames.len(), 3);
    for (f, (_, _, rows)) in frames.iter().zip(&traj) {
        assert_eq!(f.bounds, ["pp", "ff", "ff"]);
        assert_eq!(f.lines[0], [0.0, 8.0]);
        // The floor, the lid and the bodies' bounding circles (R = 1 and 0.6).
        let (mut y0, mut y1) = (0.0f64, 10.0f64);
        for (row, r) in rows.iter().zip([1.0, 0.6]) {
            (y0, y1) = (y0.min(row[2] - r), y1.max(row[2] + r));
        }
        assert_eq!(f.lines[1], [y0, y1]);
    }
}

#[test]
fn bad_exports_are_refused_naming_what_is_wrong() {
    let dir = scratch("bad");
    // Not a run directory: exit 2, naming the file it needs.
    let (code, _, err) = dem2d(&["export", dir.to_str().unwrap(), "--format", "lammps-dump"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("case.json") && err.contains("cannot read"),
        "{err}"
    );
    // An unknown format, or none: the argument parser's refusal (exit 2), listing the formats.
    let (code, _, err) = dem2d(&["export", dir.to_str().unwrap(), "--format", "vtk"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("lammps-dump"), "{err}");
    let (code, _, err) = dem2d(&["export", dir.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--format"), "{err}");
    // An unwritable output: exit 1, naming the file; nothing left behind.
    let out = run(MIX, &dir, "run", &["--max-steps", "2000"]);
    let nowhere = dir.join("no/such/dir/d.lammpstrj");
    let (code, _, err) = dem2d(&[
        "export",
        out.to_str().unwrap(),
        "--format",
        "lammps-dump",
        "--out",
        nowhere.to_str().unwrap(),
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("d.lammpstrj.tmp") && err.contains("cannot write"),
        "{err}"
    );
    // A run stopped while writing its last frame: the frames before it, and a warning.
    let traj = out.join("trajectory.csv");
    let text = std::fs::read_to_string(&traj).unwrap();
    std::fs::write(&traj, &text[..text.len() - 20]).unwrap();
    let (code, _, err) = dem2d(&["export", out.to_str().unwrap(), "--format", "lammps-dump"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("warning") && err.contains("trajectory.csv"),
        "{err}"
    );
    let frames = parse_dump(&std::fs::read_to_string(out.join("dump.lammpstrj")).unwrap());
    assert_eq!(frames.len(), 2, "steps 0 and 1000, not the cut 2000");
    // A second run into the directory is refused while the dump is there (it is the earlier
    // run's); --overwrite removes it with the rest.
    let case = dir.join("run.json");
    let (code, _, err) = dem2d(&[
        "run",
        case.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--max-steps",
        "10",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("dump.lammpstrj"), "{err}");
    let (code, _, err) = dem2d(&[
        "run",
        case.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--max-steps",
        "10",
        "--quiet",
        "--overwrite",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(!out.join("dump.lammpstrj").exists());
}
