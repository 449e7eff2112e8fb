//! Regressions of issue 29 ("Nothing silent, nothing stale") in the lab's commands; the rest are
//! in the tool's `tests/regressions.rs`. One module per bug, named after it; its doc says what
//! went wrong and what happens now.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("regressions")
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// `dem2d-lab bench` on one pile size of disks, one thread, a few steps, piles cached in `cache`.
fn bench(size: &str, cache: &Path) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_dem2d-lab"));
    c.args(["bench", "--shapes", "disks", "--sizes", size])
        .args(["--steps", "10", "--reps", "1", "--threads", "1", "--cache"])
        .arg(cache);
    c
}

/// Issue 29, item 13 (the lab's part). `bench`'s settling printed nothing while it worked, and
/// its "settled" 1000-disk pile was reported with 0 contacts (the neighbour list's count at the
/// one line a log received, while the pile was still falling). Now the settling shows
/// `dem2d run`'s progress line with the step's contacts, and the settled pile touches.
mod bug_bench_settling_printed_nothing_and_its_settled_pile_had_no_contacts {
    use super::*;

    #[test]
    fn settling_shows_the_progress_line_of_dem2d_run() {
        let cache = scratch("bench_progress");
        let mut child = bench("10000", &cache)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut seen = String::new();
        let mut line = None;
        for l in BufReader::new(child.stderr.take().unwrap()).lines() {
            let l = l.unwrap();
            seen.push_str(&l);
            seen.push('\n');
            if l.starts_with("settling settle_disks_10k: step ") {
                line = Some(l);
                break;
            }
        }
        let _ = child.kill();
        let _ = child.wait();
        let line = line.unwrap_or_else(|| panic!("no progress line in:\n{seen}"));
        // `NAME: step N/M (P %), t = T s, R steps/s, L left (at most), C contacts, unbalanced
        // force ratio U`.
        let fields: Vec<&str> = line.split(", ").collect();
        assert_eq!(fields.len(), 6, "{line}");
        assert!(fields[4].ends_with(" contacts"), "{line}");
        assert!(fields[5].starts_with("unbalanced force ratio "), "{line}");
    }

    #[test]
    fn the_settled_thousand_disk_pile_touches_and_is_at_rest() {
        use dem2d::scene::Case;
        let cache = scratch("bench_1k");
        let out = bench("1000", &cache).output().unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        // The cached pile is an ordinary case: one step of it, and its contacts counted. A
        // settled 2D pile of disks has a coordination of 3 to 4 (1.5 to 2 contacts per body);
        // its mean speed is below bench's 0.5 cm/s (free fall reaches 200 cm/s in the 0.2 s
        // bench waits at least).
        let text = std::fs::read_to_string(cache.join("settle_disks_1k_settled.json")).unwrap();
        let case = Case::from_json(&text).unwrap();
        let mut w = case.build_world();
        let mut contacts = 0;
        dem2d::run::Simulation::new(&mut w)
            .for_steps(1)
            .run_each(|_, r| contacts = r.contacts)
            .unwrap();
        let n = w.bodies.len() as f64;
        assert!(
            contacts as f64 >= 1.5 * n,
            "{contacts} contacts among {n} disks"
        );
        let speed = w.bodies.state.iter().map(|s| s.vel.norm()).sum::<f64>() / n;
        assert!(speed < 1.0, "mean speed {speed} cm/s");
    }
}
