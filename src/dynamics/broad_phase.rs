//! Broad phase: the pairs of bodies whose bounding circles come within a margin of each other,
//! from a uniform hash grid.
//!
//! The cell size is the largest bounding diameter plus the margin, so two such circles always
//! have their centres in the same or neighbouring cells. Cells are hashed (not bounded), so
//! bodies anywhere — including ones that left the populated region — are found; hash collisions
//! only cost work, since each candidate's own cell is compared exactly. Cost is linear in the
//! number of bodies (a counting sort into buckets and a 3×3 cell scan per body). A size spread
//! makes the cells as large as the largest body: small bodies then share cells, which costs
//! time in proportion to the spread but misses nothing.

use super::body::Bodies;

/// Reusable buffers of the grid (no allocation once warmed up).
#[derive(Clone, Debug, Default)]
pub struct Grid {
    cell: Vec<(i64, i64)>,
    bucket: Vec<u32>,
    start: Vec<u32>,
    fill: Vec<u32>,
    order: Vec<u32>,
}

#[inline]
fn hash(ix: i64, iy: i64, mask: u64) -> u32 {
    let h = (ix as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (iy as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F);
    ((h ^ (h >> 29)) & mask) as u32
}

impl Grid {
    /// Heap bytes held (capacities).
    pub fn heap_bytes(&self) -> usize {
        self.cell.capacity() * 16
            + (self.bucket.capacity()
                + self.start.capacity()
                + self.fill.capacity()
                + self.order.capacity())
                * 4
    }

    /// Appends to `out` (after clearing it) every pair `(i, j)`, `i < j`, with
    /// `|x_i − x_j| ≤ R_i + R_j + margin` (R the bounding radii), sorted.
    pub fn pairs(&mut self, bodies: &Bodies, margin: f64, out: &mut Vec<(u32, u32)>) {
        out.clear();
        let n = bodies.len();
        if n < 2 {
            return;
        }
        for v in [&mut self.bucket, &mut self.order] {
            super::contacts::reserve_for(v, n);
        }
        super::contacts::reserve_for(&mut self.cell, n);
        let size = 2.0 * bodies.bound.iter().copied().fold(0.0f64, f64::max) + margin;
        let inv = 1.0 / size;
        let buckets = (2 * n).next_power_of_two();
        let mask = (buckets - 1) as u64;
        self.cell.clear();
        self.bucket.clear();
        self.start.clear();
        self.start.resize(buckets + 1, 0);
        for p in bodies.state.iter().map(|s| &s.pose) {
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
        self.fill.clear();
        self.fill.extend_from_slice(&self.start[..buckets]);
        for (k, &b) in self.bucket.iter().enumerate() {
            self.order[self.fill[b as usize] as usize] = k as u32;
            self.fill[b as usize] += 1;
        }
        for i in 0..n {
            let (cx, cy) = self.cell[i];
            let pi = bodies.state[i].pose.position;
            let ri = bodies.bound[i] + margin;
            let first = out.len();
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
                        if (bodies.state[j].pose.position - pi).norm_squared() <= r * r {
                            out.push((i as u32, j as u32));
                        }
                    }
                }
            }
            // Each body's partners in increasing order: the whole list is then sorted.
            out[first..].sort_unstable();
        }
        // Saturated cells (coordinates beyond ±9e18 cells) can list a pair twice.
        out.dedup();
    }
}
