use dem2d::geometry::overlap_area::DiskLens;
fn main() {
    let l = DiskLens::new(1.0, 1.0);
    let a = 3.0023309563442195;
    let (d, c) = l.depth_for_area(a);
    println!("{d:e} {c:e} {:?}", l.at_depth(d));
    for k in -3..=3 {
        let dd = d + k as f64 * 1e-12;
        println!("{dd:e} {:?}", l.at_depth(dd));
    }
}
