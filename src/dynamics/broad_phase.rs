//! Broad phase: the pairs of bodies whose bounding circles come within a margin of each other,
//! from a uniform hash grid.
//!
//! The cell size is the largest bounding diameter plus the margin, so two such circles always
//! have their centres in the same or neighbouring cells. Cells are hashed (not bounded), so
//! bodies anywhere — including ones that left the populated region — are found; hash collisions
//! only cost work, since each candidate's own cell is compared exactly. When the bodies' cells
//! span no more cells than there are buckets (a pile, a packing: the usual scene), the "hash" is
//! the cell's row-major index in their bounding box, so that neighbouring cells are neighbouring
//! buckets and a body's 3×3 scan reads three short runs of memory rather than nine random
//! places (at 10⁶ bodies the grid's arrays are far larger than the cache); otherwise (a body
//! flung far away) a mixing hash, which no layout of the cells can make collide in bulk. Cost
//! is linear in the number of bodies (a counting sort into buckets and a 3×3 cell scan per
//! body). A size spread makes the cells as large as the largest body: small bodies then share
//! cells, which costs time in proportion to the spread but misses nothing.

use super::body::Bodies;
use super::cell::Cell;
use crate::geometry::Vec2;
use rayon::prelude::*;

/// Bodies per parallel chunk of a list build's per-body loops (each chunk lists its bodies'
/// entries apart; the lists are joined in body order, so the result does not depend on the
/// chunks).
const SCAN_CHUNK: usize = 4096;

/// A pair of bodies `(i, j)`, `i < j`.
type Pair = (u32, u32);

/// Runs `each(bodies, list)` (which appends the entries of a range of bodies, in order) over
/// the bodies `0..n` chunk by chunk in parallel, each chunk into its own list of `parts`, and
/// joins the lists in body order into `out` (after what it holds): the same list as one loop
/// over the bodies would make.
pub(crate) fn in_body_chunks<T: Copy + Send>(
    n: usize,
    parts: &mut Vec<Vec<T>>,
    out: &mut Vec<T>,
    each: impl Fn(std::ops::Range<usize>, &mut Vec<T>) + Sync,
) {
    let chunks = n.div_ceil(SCAN_CHUNK);
    if parts.len() < chunks {
        parts.resize(chunks, Vec::new());
    }
    parts[..chunks]
        .par_iter_mut()
        .enumerate()
        .for_each(|(c, part)| {
            part.clear();
            each(c * SCAN_CHUNK..((c + 1) * SCAN_CHUNK).min(n), part);
        });
    let total = out.len() + parts[..chunks].iter().map(Vec::len).sum::<usize>();
    super::contacts::reserve_for(out, total);
    for part in &parts[..chunks] {
        out.extend_from_slice(part);
    }
}

/// Reusable buffers of the grid (no allocation once warmed up).
#[derive(Clone, Debug, Default)]
pub struct Grid {
    cell: Vec<(i64, i64)>,
    bucket: Vec<u32>,
    start: Vec<u32>,
    fill: Vec<u32>,
    order: Vec<u32>,
    /// Each scan chunk's pairs (see [`in_body_chunks`]).
    parts: Vec<Vec<Pair>>,
}

/// How a cell maps to its bucket (see the module documentation).
#[derive(Clone, Copy, Debug)]
enum Buckets {
    /// Row-major in the bounding box of the occupied cells: `(iy − y0)·nx + (ix − x0)`.
    Dense { x0: i64, y0: i64, nx: i64 },
    /// A mixing hash.
    Hashed,
}

impl Buckets {
    #[inline]
    fn of(self, ix: i64, iy: i64, mask: u64) -> u32 {
        let h = match self {
            Buckets::Dense { x0, y0, nx } => {
                (iy.wrapping_sub(y0).wrapping_mul(nx)).wrapping_add(ix.wrapping_sub(x0)) as u64
            }
            Buckets::Hashed => {
                let h = (ix as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
                    ^ (iy as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F);
                h ^ (h >> 29)
            }
        };
        (h & mask) as u32
    }
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
            + self.parts.iter().map(|p| p.capacity() * 8).sum::<usize>()
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
        let (mut lo, mut hi) = ((i64::MAX, i64::MAX), (i64::MIN, i64::MIN));
        for p in bodies.state.iter().map(|s| &s.pose) {
            // `as` saturates: far-away or non-finite coordinates still land in some cell.
            let c = (
                (p.position.x * inv).floor() as i64,
                (p.position.y * inv).floor() as i64,
            );
            lo = (lo.0.min(c.0), lo.1.min(c.1));
            hi = (hi.0.max(c.0), hi.1.max(c.1));
            self.cell.push(c);
        }
        // The occupied cells' bounding box, in cells (i128: saturated coordinates span 2^64).
        let (nx, ny) = (
            i128::from(hi.0) - i128::from(lo.0) + 1,
            i128::from(hi.1) - i128::from(lo.1) + 1,
        );
        let layout = if nx * ny <= buckets as i128 {
            Buckets::Dense {
                x0: lo.0,
                y0: lo.1,
                nx: nx as i64,
            }
        } else {
            Buckets::Hashed
        };
        self.bucket
            .extend(self.cell.iter().map(|&(cx, cy)| layout.of(cx, cy, mask)));
        self.sort_by_bucket(buckets);
        let (cell, order, start) = (&self.cell, &self.order, &self.start);
        in_body_chunks(n, &mut self.parts, out, |range, out| {
            range.for_each(|i| {
                let (cx, cy) = cell[i];
                let pi = bodies.state[i].pose.position;
                let ri = bodies.bound[i] + margin;
                let first = out.len();
                for dx in -1..=1i64 {
                    for dy in -1..=1i64 {
                        let (nx, ny) = (cx.saturating_add(dx), cy.saturating_add(dy));
                        let b = layout.of(nx, ny, mask) as usize;
                        for &j in &order[start[b] as usize..start[b + 1] as usize] {
                            let j = j as usize;
                            if j <= i || cell[j] != (nx, ny) {
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
            })
        });
        // Saturated cells (coordinates beyond ±9e18 cells) can list a pair twice.
        out.dedup();
    }
}

impl Grid {
    /// Sorts the bodies by their `bucket` (a counting sort): `order[start[b]..start[b + 1]]`
    /// are the bodies of bucket `b`, in increasing number.
    fn sort_by_bucket(&mut self, buckets: usize) {
        self.start.clear();
        self.start.resize(buckets + 1, 0);
        for &b in &self.bucket {
            self.start[b as usize + 1] += 1;
        }
        for k in 0..buckets {
            self.start[k + 1] += self.start[k];
        }
        self.order.clear();
        self.order.resize(self.bucket.len(), 0);
        self.fill.clear();
        self.fill.extend_from_slice(&self.start[..buckets]);
        for (k, &b) in self.bucket.iter().enumerate() {
            self.order[self.fill[b as usize] as usize] = k as u32;
            self.fill[b as usize] += 1;
        }
    }

    /// [`Grid::pairs`] in a periodic cell: the pairs whose bounding circles come within
    /// `margin` through the giver's nearest image (every body inside the cell). The cell is
    /// tiled by `n_x × n_y` cells at least as large as the reach, and a body's neighbours are in
    /// the 3 × 3 cells around it with the indices taken modulo the tiling; across the y seam of
    /// a Lees–Edwards cell, the row beyond is shifted by the image's offset, so the search there
    /// covers the four cells around the shifted column. Each pair once, `i < j`, sorted.
    pub fn pairs_periodic(
        &mut self,
        bodies: &Bodies,
        margin: f64,
        cell: &Cell,
        out: &mut Vec<(u32, u32)>,
    ) {
        out.clear();
        let n = bodies.len();
        if n < 2 {
            return;
        }
        let size = 2.0 * bodies.bound.iter().copied().fold(0.0f64, f64::max) + margin;
        let (lx, ly) = (cell.size.x, cell.size.y);
        let fx = (lx / size).floor().max(1.0);
        // Not periodic in y: the bodies' extent in y, tiled from its bottom.
        let (y0, fy) = if cell.periodic_y() {
            (0.0, (ly / size).floor().max(1.0))
        } else {
            let (lo, hi) = bodies
                .state
                .iter()
                .map(|s| s.pose.position.y)
                .fold((f64::MAX, f64::MIN), |(l, h), y| (l.min(y), h.max(y)));
            (lo, ((hi - lo) / size).floor() + 1.0)
        };
        // A sparse cell (far larger than its bodies' reach) gets at most a few tiles per body,
        // each larger than the reach: the same pairs, without a tiling larger than memory. The
        // cap holds for the product, whatever the shape of the tiling: a cell one tile wide
        // whose bodies span 1e25 cm in y (a body thrown up at 1e30 cm/s) would otherwise split
        // the excess evenly, keep nx at 1 and ask for 1e16 rows (issue 41, item 6).
        let cap = (4 * n).max(64) as f64;
        let f = (fx * fy / cap).sqrt().max(1.0);
        let whole = |v: f64| {
            if v.is_finite() {
                v.clamp(1.0, cap)
            } else {
                1.0
            }
        };
        let nx = whole((fx / f).floor());
        let ny = whole((fy / f).floor()).min((cap / nx).floor()).max(1.0);
        let (nx, ny) = (nx as i64, ny as i64);
        let (wx, wy) = (
            lx / nx as f64,
            if cell.periodic_y() {
                ly / ny as f64
            } else {
                // Rows cover the bodies' extent (wider than the reach when it is capped), so
                // two bodies within reach are in the same row or neighbouring rows.
                if ny as f64 == fy {
                    size
                } else {
                    size.max(fy * size / ny as f64)
                }
            },
        );
        let cells = (nx * ny) as usize;
        self.cell.clear();
        self.bucket.clear();
        let index = |ix: i64, iy: i64| (iy * nx + ix) as usize;
        for s in &bodies.state {
            let p = s.pose.position;
            let ix = ((p.x / wx).floor() as i64).clamp(0, nx - 1);
            let iy = (((p.y - y0) / wy).floor() as i64).clamp(0, ny - 1);
            self.cell.push((ix, iy));
            self.bucket.push(index(ix, iy) as u32);
        }
        self.sort_by_bucket(cells);
        let wrap = |i: i64, m: i64| i.rem_euclid(m);
        let (cells, order, start) = (&self.cell, &self.order, &self.start);
        in_body_chunks(n, &mut self.parts, out, |range, out| {
            range.for_each(|i| {
                let (cx, cy) = cells[i];
                let pi = bodies.state[i].pose.position;
                let ri = bodies.bound[i] + margin;
                let first = out.len();
                // (At most 4 cells in each of the three rows.)
                let mut seen = [(0i64, 0i64); 12];
                let mut seen_len = 0;
                for dy in -1..=1i64 {
                    let mut ty = cy + dy;
                    // The columns to scan in the row `ty`: around cx, or (across a Lees–Edwards
                    // seam) around the column of the shifted position.
                    let mut columns = [cx - 1, cx, cx + 1, cx + 1];
                    let mut count = 3;
                    if cell.periodic_y() && (ty < 0 || ty >= ny) {
                        // The row beyond the top is the bottom row of the image above, shifted by
                        // +offset: its bodies at x are seen at x + offset, so this body at x looks
                        // at x − offset there (and + offset across the bottom).
                        let shift = if ty >= ny { -cell.offset } else { cell.offset };
                        let x = pi.x + shift;
                        let c = (x / wx).floor() as i64;
                        columns = [c - 1, c, c + 1, c + 2];
                        count = 4;
                        ty = wrap(ty, ny);
                    } else if ty < 0 || ty >= ny {
                        continue;
                    }
                    for &tx in &columns[..count] {
                        let key = (wrap(tx, nx), ty);
                        if seen[..seen_len].contains(&key) {
                            continue;
                        }
                        seen[seen_len] = key;
                        seen_len += 1;
                        let b = index(key.0, key.1);
                        for &j in &order[start[b] as usize..start[b + 1] as usize] {
                            let j = j as usize;
                            if j <= i {
                                continue;
                            }
                            let pj = bodies.state[j].pose.position;
                            let at = pj
                                + cell
                                    .nearest_image(pj, pi)
                                    .map_or(Vec2::zeros(), |m| m.offset);
                            let r = ri + bodies.bound[j];
                            if (at - pi).norm_squared() <= r * r {
                                out.push((i as u32, j as u32));
                            }
                        }
                    }
                }
                out[first..].sort_unstable();
                // (A tiling of two rows reaches the other row from both sides, shifted apart
                // across a Lees–Edwards seam: a body there may be found twice.)
                let mut kept = first;
                for r in first..out.len() {
                    if r == first || out[r] != out[kept - 1] {
                        out[kept] = out[r];
                        kept += 1;
                    }
                }
                out.truncate(kept);
            })
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::body::BodyInit;
    use crate::geometry::{Shape, Vec2};

    /// A small deterministic generator (no dependency).
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    fn bodies(at: &[(f64, f64, f64)]) -> Bodies {
        let inits: Vec<BodyInit> = at
            .iter()
            .map(|&(x, y, r)| BodyInit {
                material: 0,
                prescribed: false,
                shape: Shape::Circle { r },
                position: Vec2::new(x, y),
                angle: 0.0,
                velocity: Vec2::zeros(),
                omega: 0.0,
                density: 1.0,
            })
            .collect();
        Bodies::new(&inits)
    }

    /// Every pair within reach, by testing all of them.
    fn brute(at: &[(f64, f64, f64)], margin: f64) -> Vec<(u32, u32)> {
        let mut out = Vec::new();
        for i in 0..at.len() {
            for j in i + 1..at.len() {
                let (dx, dy) = (at[j].0 - at[i].0, at[j].1 - at[i].1);
                let r = at[i].2 + margin + at[j].2;
                if dx * dx + dy * dy <= r * r {
                    out.push((i as u32, j as u32));
                }
            }
        }
        out
    }

    /// The grid against all pairs: a jittered pile (the row-major buckets), the same pile with
    /// one body flung a million cells away (the mixing hash), a pile spanning the origin
    /// (negative cells), and a polydisperse scatter; the same grid reused throughout.
    #[test]
    fn the_grid_finds_exactly_the_pairs_within_reach() {
        let mut rng = Lcg(7);
        let mut grid = Grid::default();
        let mut out = Vec::new();
        let pile: Vec<(f64, f64, f64)> = (0..600)
            .map(|k| {
                let (col, row) = ((k % 30) as f64, (k / 30) as f64);
                let r = 0.8 + 0.4 * rng.next();
                (
                    2.1 * col + 0.3 * rng.next(),
                    2.1 * row + 0.3 * rng.next(),
                    r,
                )
            })
            .collect();
        let mut flung = pile.clone();
        flung[17] = (3.0e6, -2.0e6, 1.0);
        let shifted: Vec<_> = pile
            .iter()
            .map(|&(x, y, r)| (x - 31.0, y - 20.0, r))
            .collect();
        let scatter: Vec<_> = (0..400)
            .map(|_| (60.0 * rng.next(), 60.0 * rng.next(), 0.1 + 2.0 * rng.next()))
            .collect();
        let mut dense_seen = 0;
        for (name, at) in [
            ("pile", &pile),
            ("flung", &flung),
            ("shifted", &shifted),
            ("scatter", &scatter),
        ] {
            for margin in [0.0, 0.12, 0.5] {
                grid.pairs(&bodies(at), margin, &mut out);
                assert_eq!(out, brute(at, margin), "{name}, margin {margin}");
            }
            let b = bodies(at);
            let size = 2.0 * b.bound.iter().copied().fold(0.0f64, f64::max);
            let cells = |k: usize| at.iter().map(move |p| [p.0, p.1][k]);
            let span = |k: usize| {
                let (lo, hi) =
                    cells(k).fold((f64::MAX, f64::MIN), |(l, h), v| (l.min(v), h.max(v)));
                ((hi / size).floor() - (lo / size).floor() + 1.0) as usize
            };
            if span(0) * span(1) <= (2 * at.len()).next_power_of_two() {
                dense_seen += 1;
            }
        }
        // Both bucket layouts were exercised.
        assert!(
            (1..4).contains(&dense_seen),
            "dense layouts: {dense_seen} of 4"
        );
    }

    /// Issue 41, item 6: a cell periodic in x, 8 cm wide (one tile across), whose bodies span
    /// 1e25 cm in y (one thrown up at 1e30 cm/s) or 1e14 cm: the tiling asked for 1e16 rows (a
    /// hang, 37 TB). The tiles are now at most `4 n` (the cap), the buffers a few kB, and the
    /// pairs those of all pairs through the nearest image in x, by brute force.
    #[test]
    fn a_cell_periodic_in_x_tiles_a_huge_vertical_extent_within_its_cap() {
        use crate::dynamics::cell::{Cell, Periodic};
        let cell = Cell::new(Vec2::new(8.0, 10.0), Periodic::X, 0.0, None);
        for far in [1e14, 1e25, f64::MAX] {
            let at = [
                (7.5, 1.0, 0.6),
                (0.2, 1.0, 0.6),
                (4.2, 1.0, 0.6),
                (4.0, 2.1, 0.5),
                (2.2, far, 0.6),
                (2.4, far, 0.6),
            ];
            let b = bodies(&at);
            let mut grid = Grid::default();
            let mut out = Vec::new();
            grid.pairs_periodic(&b, 0.1, &cell, &mut out);
            assert!(grid.heap_bytes() < 1 << 16, "{} bytes", grid.heap_bytes());
            let mut want = Vec::new();
            for i in 0..at.len() {
                for j in i + 1..at.len() {
                    let d = cell.shortest(Vec2::new(at[j].0 - at[i].0, at[j].1 - at[i].1));
                    let r = at[i].2 + 0.1 + at[j].2;
                    if d.norm_squared() <= r * r {
                        want.push((i as u32, j as u32));
                    }
                }
            }
            assert_eq!(out, want, "bodies up to y = {far:e}");
        }
    }
}
