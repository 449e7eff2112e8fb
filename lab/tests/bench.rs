//! The throughput benchmark (`dem2d-lab bench`) on two small piles: its rows and its
//! identical-trajectory column.

/// `dem2d-lab bench` (what the user guide's throughput table comes from) times one world per size,
/// thread count and law, interleaved block by block: every row is there, each thread count's
/// final state is bit-identical to one thread's (the table's last column, computed from the
/// state's bits), and the two-thread row carries its speed-up.
#[test]
fn bench_times_every_size_and_thread_count_and_finds_the_same_trajectory() {
    let cache = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("bench-piles");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_dem2d-lab"))
        .args(["bench", "--shapes", "disks", "--sizes", "1000,2000"])
        .args([
            "--threads",
            "1,2",
            "--steps",
            "20",
            "--reps",
            "2",
            "--cache",
        ])
        .arg(&cache)
        .output()
        .expect("run dem2d-lab bench");
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let rows: Vec<Vec<&str>> = stdout
        .lines()
        .filter(|l| l.starts_with("| disks"))
        .map(|l| l.split('|').map(str::trim).collect())
        .collect();
    let keys: Vec<(&str, &str)> = rows.iter().map(|r| (r[2], r[4])).collect();
    assert_eq!(
        keys,
        [("1000", "1"), ("1000", "2"), ("2000", "1"), ("2000", "2")],
        "{stdout}"
    );
    for r in &rows {
        assert_eq!(r[r.len() - 2], "yes", "not the same trajectory: {r:?}");
        let speed_up = r[8].trim_end_matches('×').parse::<f64>().unwrap();
        assert!(speed_up.is_finite() && speed_up > 0.0, "{r:?}");
    }
}
