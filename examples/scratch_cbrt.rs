use std::time::Instant;
fn main() {
    let xs: Vec<f64> = (0..1000).map(|k| 1e-6 + k as f64 * 1e-5).collect();
    let t = Instant::now();
    let mut acc = 0.0;
    for _ in 0..10000 {
        for x in &xs {
            acc += std::hint::black_box(*x).cbrt();
        }
    }
    println!("cbrt {:.1} ns ({acc})", t.elapsed().as_nanos() as f64 / 1e7);
    let t = Instant::now();
    let mut acc = 0.0;
    for _ in 0..10000 {
        for x in &xs {
            acc += dem2d::geometry::overlap_area::unit_cap(std::hint::black_box(*x));
        }
    }
    println!(
        "unit_cap {:.1} ns ({acc})",
        t.elapsed().as_nanos() as f64 / 1e7
    );
    let t = Instant::now();
    let mut acc = 0.0;
    for _ in 0..10000 {
        for x in &xs {
            acc += std::hint::black_box(*x).sqrt();
        }
    }
    println!("sqrt {:.1} ns ({acc})", t.elapsed().as_nanos() as f64 / 1e7);
}
