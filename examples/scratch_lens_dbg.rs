use dem2d::geometry::overlap_area::DiskLens;
fn main() {
    for (r1, r2, d) in [
        (1.0, 1.0, 1e-4),
        (0.8, 1.2, 1e-3),
        (1.0, 1.1, 1e-2),
        (0.9, f64::INFINITY, 1e-3),
    ] {
        let l = DiskLens::new(r1, r2);
        let (a, _) = l.at_depth(d);
        println!("{r1} {r2} {d}: {:?}", l.depth_for_area(a));
    }
}
