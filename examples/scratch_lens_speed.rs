use dem2d::geometry::overlap_area::DiskLens;
use std::time::Instant;
fn main() {
    let mut areas = vec![];
    let mut lenses = vec![];
    for k in 0..1000 {
        let r1 = 0.8 + 0.4 * ((k * 7919) % 1000) as f64 / 1000.0;
        let r2 = 0.8 + 0.4 * ((k * 104729) % 1000) as f64 / 1000.0;
        let l = DiskLens::new(r1, r2);
        let d = 10f64.powf(-4.0 + 2.0 * ((k * 31) % 1000) as f64 / 1000.0);
        areas.push(l.at_depth(d).0);
        lenses.push(l);
    }
    let t = Instant::now();
    let mut acc = 0.0;
    for _ in 0..1000 {
        for (l, a) in lenses.iter().zip(&areas) {
            acc += l.depth_for_area(std::hint::black_box(*a)).0;
        }
    }
    println!(
        "{:.1} ns per inverse ({acc})",
        t.elapsed().as_nanos() as f64 / 1e6
    );
}
