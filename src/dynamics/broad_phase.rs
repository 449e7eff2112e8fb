//! Broad phase: the pairs of bodies whose bounding circles overlap, from a uniform hash grid.
//!
//! The cell size is the largest bounding diameter, so two overlapping bounding circles always
//! have their centres in the same or neighbouring cells. Cells are hashed (not bounded), so
//! bodies anywhere — including ones that left the populated region — are found; hash collisions
//! only cost work, since each candidate's own cell is compared exactly. Cost per step is linear in
//! the number of bodies (a counting sort into buckets and a 3×3 cell scan per body).

use super::body::Bodies;

/// Reusable buffers of the grid (no allocation in the step once warmed up).
#[derive(Clone, Debug, Default)]
pub struct Grid {
    cell: Vec<(i64, i64)>,
    bucket: Vec<u32>,
    start: Vec<u32>,
    order: Vec<u32>,
}

#[inline]
fn hash(ix: i64, iy: i64, mask: u64) -> u32 {
    let h = (ix as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (iy as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F);
    ((h ^ (h >> 29)) & mask) as u32
}

impl Grid {
    /// Appends to `out` every pair `(i, j)`, `i < j`, whose bounding circles overlap, sorted.
    pub fn pairs(&mut self, bodies: &Bodies, out: &mut Vec<(u32, u32)>) {
        out.clear();
        let n = bodies.len();
        if n < 2 {
            return;
        }
        let size = 2.0 * bodies.bound.iter().copied().fold(0.0f64, f64::max);
        let inv = 1.0 / size;
        let buckets = (2 * n).next_power_of_two();
        let mask = (buckets - 1) as u64;
        self.cell.clear();
        self.bucket.clear();
        self.start.clear();
        self.start.resize(buckets + 1, 0);
        for p in &bodies.pose {
            // `as` saturates: far-away or non-finite coordinates still land in some cell.
            let c = (
                (p.position.x * inv).floor() as i64,
                (p.position.y * inv).floor() as i64,
            );
            let b = hash(c.0, c.1, mask);
            self.cell.push(c);
            self.bucket.push(b);
            self.start[b as usize + 1] += 1;
        }
        for k in 0..buckets {
            self.start[k + 1] += self.start[k];
        }
        self.order.clear();
        self.order.resize(n, 0);
        let mut fill = self.start.clone();
        for (k, &b) in self.bucket.iter().enumerate() {
            self.order[fill[b as usize] as usize] = k as u32;
            fill[b as usize] += 1;
        }
        for i in 0..n {
            let (cx, cy) = self.cell[i];
            let pi = bodies.pose[i].position;
            let ri = bodies.bound[i];
            for dx in -1..=1i64 {
                for dy in -1..=1i64 {
                    let (nx, ny) = (cx.saturating_add(dx), cy.saturating_add(dy));
                    let b = hash(nx, ny, mask) as usize;
                    for &j in &self.order[self.start[b] as usize..self.start[b + 1] as usize] {
                        let j = j as usize;
                        if j <= i || self.cell[j] != (nx, ny) {
                            continue;
                        }
                        let r = ri + bodies.bound[j];
                        if (bodies.pose[j].position - pi).norm_squared() <= r * r {
                            out.push((i as u32, j as u32));
                        }
                    }
                }
            }
        }
        out.sort_unstable();
        // Saturated cells (coordinates beyond ±9e18 cells) can list a pair twice.
        out.dedup();
    }
}
