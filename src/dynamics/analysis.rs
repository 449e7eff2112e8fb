//! Measures of a state: the angle of repose of a heap.

use super::world::World;

/// The surface of a heap standing on the floor y = 0 at x ≥ 0: the slope angle (degrees) of its
/// surface, its height and its toe (the farthest x any body reaches).
///
/// The surface is the top of the highest body in each bin of width `bin` along x (from x = 0);
/// the angle is that of the least-squares line through the bins' tops where they lie between
/// 20 % and 80 % of the heap's height (away from the crest and the toe, where the surface
/// curves). A heap falling towards +x gives a positive angle.
pub fn heap_surface(world: &World, bin: f64) -> (f64, f64, f64) {
    let b = &world.bodies;
    let mut tops: Vec<f64> = Vec::new();
    let mut toe: f64 = 0.0;
    for k in 0..b.len() {
        let p = b.state[k].pose.position;
        if p.x < 0.0 {
            continue;
        }
        let i = (p.x / bin) as usize;
        if tops.len() <= i {
            tops.resize(i + 1, 0.0);
        }
        tops[i] = tops[i].max(p.y + b.bound[k]);
        toe = toe.max(p.x + b.bound[k]);
    }
    let height = tops.iter().copied().fold(0.0, f64::max);
    let (mut xs, mut ys) = (Vec::new(), Vec::new());
    for (i, &t) in tops.iter().enumerate() {
        if t > 0.2 * height && t < 0.8 * height {
            xs.push((i as f64 + 0.5) * bin);
            ys.push(t);
        }
    }
    if xs.len() < 2 {
        return (f64::NAN, height, toe);
    }
    let n = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    ((-sxy / sxx).atan().to_degrees(), height, toe)
}
