//! What the integration tests share: running the `dem2d` binary, scratch directories, and the
//! small scenes the dynamics tests build (a body at rest, a floor, P's linear law, the energy
//! error of a run). Each test file includes it (`mod common;`) and uses part of it.
#![allow(dead_code)]

use dem2d::contact_law::{ContactSpec, LinearDamping, NormalForce, Scaled};
use dem2d::dynamics::{BodyInit, Boundary};
use dem2d::geometry::{Shape, Vec2, Wall};
use dem2d::run::Simulation;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

/// The `dem2d` binary under test.
pub fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_dem2d")
}

fn exit(out: Output) -> (i32, String, String) {
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
}

/// Runs `dem2d ARGS` in the repository's root; its exit code (−1 when killed by a signal),
/// standard output and standard error.
pub fn dem2d(args: &[&str]) -> (i32, String, String) {
    exit(
        Command::new(bin())
            .args(args)
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .output()
            .expect("run dem2d"),
    )
}

/// [`dem2d`] with `stdin` as its standard input.
pub fn dem2d_with_input(args: &[&str], stdin: &str) -> (i32, String, String) {
    let mut child = Command::new(bin())
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run dem2d");
    child
        .stdin
        .take()
        .unwrap()
        .write_all(stdin.as_bytes())
        .unwrap();
    exit(child.wait_with_output().unwrap())
}

/// A path of this test file's scratch space (`TARGET_TMPDIR/<test file>/<name>`), emptied:
/// whatever an earlier run left there is removed, and nothing is created.
pub fn scratch_path(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(env!("CARGO_CRATE_NAME"))
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// [`scratch_path`], created as an empty directory.
pub fn scratch(name: &str) -> PathBuf {
    let d = scratch_path(name);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A shipped case file's path (`cases/NAME`).
pub fn case_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("cases")
        .join(name)
}

/// A body of `shape` at `position` and `angle`, at rest, of density 1.
pub fn body(shape: Shape, position: Vec2, angle: f64) -> BodyInit {
    BodyInit {
        material: 0,
        prescribed: false,
        shape,
        position,
        angle,
        velocity: Vec2::zeros(),
        omega: 0.0,
        density: 1.0,
    }
}

/// The floor `y = 0` (free side up) under the law `spec`.
pub fn floor(spec: ContactSpec) -> Boundary {
    Boundary::new(Wall::new(Vec2::zeros(), Vec2::y()).unwrap(), spec)
}

/// The linear law with normal and tangential stiffness `kn`, both dashpots `eta`, Coulomb
/// friction `friction`, on the depth (absolute values: no ρg scaling).
pub fn linear(kn: f64, eta: f64, friction: f64) -> ContactSpec {
    ContactSpec::linear(
        Scaled::Absolute(kn),
        Scaled::Absolute(kn),
        LinearDamping::Dashpots {
            eta_n: Scaled::Absolute(eta),
            eta_s: Scaled::Absolute(eta),
        },
        friction,
    )
    .with_normal_force(NormalForce::Depth)
}

/// The largest `|E − E₀|/E₀` over the steps of `sim`'s run (`E = K + P + E_el + D`, `E₀` the
/// world's at the start): what an undamped, frictionless scene must keep small.
pub fn worst_energy_error(mut sim: Simulation) -> f64 {
    let e0 = sim.world().energies.total();
    let mut worst = 0.0f64;
    sim.run_each(|w, _| worst = worst.max(((w.energies.total() - e0) / e0).abs()))
        .unwrap();
    worst
}

/// A small deterministic generator (xorshift), uniform in [0, 1): the tests' random scenes.
pub struct Rng(pub u64);
impl Rng {
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The arrays of a `.vtu` frame as dem2d writes it (inline base64, a UInt64 byte count first),
/// decoded here without VTK: name → raw little-endian bytes.
pub fn vtu_arrays(text: &str) -> std::collections::HashMap<String, Vec<u8>> {
    fn decode(s: &str) -> Vec<u8> {
        let val = |c: u8| match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => panic!("not base64: {c}"),
        };
        let s: Vec<u8> = s.bytes().filter(|c| !c.is_ascii_whitespace()).collect();
        let mut out = Vec::new();
        for q in s.chunks(4) {
            let pad = q.iter().filter(|&&c| c == b'=').count();
            let v = q
                .iter()
                .map(|&c| if c == b'=' { 0 } else { u32::from(val(c)) })
                .fold(0u32, |acc, x| (acc << 6) | x);
            out.extend(&[(v >> 16) as u8, (v >> 8) as u8, v as u8][..3 - pad]);
        }
        out
    }
    let mut arrays = std::collections::HashMap::new();
    for part in text.split("<DataArray ").skip(1) {
        let name = part
            .split("Name=\"")
            .nth(1)
            .unwrap()
            .split('"')
            .next()
            .unwrap();
        let body = part.split('>').nth(1).unwrap().split('<').next().unwrap();
        let raw = decode(body);
        let n = u64::from_le_bytes(raw[..8].try_into().unwrap()) as usize;
        assert_eq!(raw.len(), 8 + n, "{name}: byte count");
        arrays.insert(name.to_string(), raw[8..].to_vec());
    }
    arrays
}

pub fn f64s(b: &[u8]) -> Vec<f64> {
    b.chunks(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

pub fn i64s(b: &[u8]) -> Vec<i64> {
    b.chunks(8)
        .map(|c| i64::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

/// Little-endian `Int32`s.
pub fn i32s(b: &[u8]) -> Vec<i32> {
    b.chunks(4)
        .map(|c| i32::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

/// Ellipses, disks, a rectangle and a polygon on a floor between two walls, moving and
/// turning, in contact by the end.
pub const MIXED_SCENE: &str = r#"{ "version": 1, "name": "mixed_scene", "units": "cm",
  "gravity": [0, -980], "dt": 1e-5, "duration": 0.1, "output_every": 1000,
  "contact": { "model": "linear", "kn_over_rho_g": 36400, "restitution": 0.5, "friction": 0.5 },
  "walls": [ { "point": [0, 0], "normal": [0, 1] }, { "point": [0, 0], "normal": [1, 0] },
             { "point": [30, 0], "normal": [-1, 0] } ],
  "bodies": [
    { "shape": {"type": "circle", "r": 1}, "position": [2, 1.05], "velocity": [-5, 0], "omega": 3 },
    { "shape": {"type": "ellipse", "a": 3, "b": 1}, "position": [7, 2.0], "angle": 0.4, "omega": 2 },
    { "shape": {"type": "polygon", "vertices": [[0,0],[2,0],[2.5,1.5],[1,2.5],[-0.5,1.2]]},
      "position": [12, 1.6], "angle": 0.3 },
    { "shape": {"type": "ellipse", "a": 1.5, "b": 0.8}, "position": [16, 1.2], "angle": 2.5,
      "omega": -40 },
    { "shape": {"type": "rectangle", "w": 2, "h": 1}, "position": [12, 5], "angle": -1 },
    { "shape": {"type": "ellipse", "a": 2, "b": 0.4}, "position": [20, 3.5], "angle": -0.7,
      "omega": 100 },
    { "shape": {"type": "circle", "r": 0.8}, "position": [26, 3], "velocity": [30, 0] }
  ] }"#;

/// Disks and ellipses in a periodic cell 8 × 6 cm under Lees–Edwards shear (γ̇ = 3/s), no
/// gravity, 0.5 s, frames every 0.05 s.
pub fn sheared_cell() -> String {
    let bodies: Vec<String> = (0..12)
        .map(|k| {
            let (i, j) = (k % 4, k / 4);
            let shape = if k % 2 == 0 {
                r#"{"type": "circle", "r": 0.5}"#
            } else {
                r#"{"type": "ellipse", "a": 0.7, "b": 0.4}"#
            };
            format!(
                r#"{{"shape": {shape}, "position": [{}, {}], "angle": {}, "velocity": [{}, 0]}}"#,
                2.0 * i as f64 + 1.0,
                2.0 * j as f64 + 1.0,
                0.3 * k as f64,
                2.0 * j as f64 - 2.0
            )
        })
        .collect();
    format!(
        r#"{{"version": 1, "name": "sheared_cell", "gravity": [0, 0], "dt": 5e-5, "duration": 0.5,
        "output_every": 1000,
        "cell": {{"size": [8, 6], "periodic": "xy", "shear_rate": 3}},
        "contact": {{"model": "linear", "kn": 1e6, "restitution": 0.5, "friction": 0.4}},
        "bodies": [{}]}}"#,
        bodies.join(", ")
    )
}

/// Sends `sig` (`-INT`, `-TERM`, `-KILL`) to `child` with `kill`, which must succeed.
pub fn signal(child: &std::process::Child, sig: &str) {
    let ok = Command::new("kill")
        .args([sig, &child.id().to_string()])
        .status()
        .unwrap()
        .success();
    assert!(ok, "kill {sig}");
}
