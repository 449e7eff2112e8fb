//! Coarse-grained fields across a flow (`dem2d fields`): profiles along one axis of the packing
//! fraction, the mean velocity, the granular temperature, the stress and the nematic order, in
//! bins (slabs across the whole width), averaged over a window of frames.
//!
//! # Definitions (bin k of area `A_k`, a frame's bodies b)
//! - **Packing fraction** `φ_k = (1/A_k) Σ_b a_bk`, `a_bk` the exact area of body b inside the
//!   slab ([`super::packing::clipped_area`]: closed forms for disks and ellipses, polygon
//!   clipping for flat-faced shapes, the clumps' 512² midpoint rule where a slab cuts one): each
//!   body's area is shared exactly between the bins it overlaps, so `Σ_k φ_k A_k` is the
//!   bodies' area.
//! - **Velocity** `v̄_k = Σ m_bk v_b / Σ m_bk`, `m_bk = ρ_b a_bk` the mass of b in the slab,
//!   summed over the window's frames (a mass-weighted, Favre average, as Goldhirsch's and
//!   MercuryCG's coarse-grained momentum over density).
//! - **Granular temperature** `T_k = Σ m_bk |v_b − v̄_k|²/2 / Σ m_bk` (cm²/s²: the translational
//!   fluctuation per unit mass about the bin's mean over the window).
//! - **Stress** (compression positive, the [module](super)'s convention): the contact part
//!   `−(1/A_k) Σ_contacts Σ_{body sides} w_k F ⊗ ℓ`, ℓ the branch vector from a body's centroid to
//!   the contact's point of action and `w_k` the fraction of that branch vector's length inside
//!   slab k (Weinhart, Thornton, Luding & Bokhove 2012, Granular Matter 14:289, the contact
//!   stress spread along the branch vector; a branch vector along the slabs falls in one), plus
//!   the kinetic part `(1/A_k) Σ m_bk (v_b − v̄_k) ⊗ (v_b − v̄_k)`. Summed over the bins with
//!   their areas it is the whole sample's Love–Weber stress ([`super::stress::love_weber`]), the
//!   kinetic part aside; `sxy` is the symmetric part.
//! - **Nematic order** `S_k = |Σ a_bk e^{2iθ_b}| / Σ a_bk` over the bodies with a long axis θ_b
//!   ([`super::fabric::long_axis`]); none where the bin saw only disks.
//!
//! # Domains
//! In a periodic cell the bins divide the cell's side along the axis as it is at each frame
//! (its size may follow a stress), a body or branch vector across that side's seam is shared
//! between the bins at both ends (across a Lees–Edwards seam the part beyond it moves as the
//! body's image, at `v ∓ γ̇ L_y`), and a contact across a seam is counted once, through the
//! nearest image. Elsewhere the caller gives the range `[lo, hi)` and the width across, and
//! what lies outside the range is not binned. (Bins along x in a cell periodic in y: a body
//! across the horizontal seam is binned at its own x, not at its Lees–Edwards image's.)

use super::fabric::long_axis;
use super::frame::FrameContact;
use super::frame::Window;
use super::packing::clipped_area;
use crate::dynamics::cell::Cell;
use crate::geometry::{Shape, Vec2};

/// The axis the bins follow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    X,
    Y,
}

impl Axis {
    fn along(self, p: Vec2) -> f64 {
        match self {
            Axis::X => p.x,
            Axis::Y => p.y,
        }
    }

    fn index(self) -> usize {
        match self {
            Axis::X => 0,
            Axis::Y => 1,
        }
    }

    /// The column name: `x` or `y`.
    pub fn name(self) -> &'static str {
        ["x", "y"][self.index()]
    }
}

/// A body as the fields see it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FieldBody {
    pub shape: Shape,
    pub position: Vec2,
    pub angle: f64,
    pub velocity: Vec2,
    /// g/cm³.
    pub density: f64,
}

/// One frame: its bodies, its contacts (empty when the run wrote none) and its cell.
#[derive(Clone, Debug, Default)]
pub struct FieldFrame {
    pub bodies: Vec<FieldBody>,
    pub contacts: Vec<FrameContact>,
    pub cell: Option<Cell>,
}

/// Where the bins lie outside a periodic cell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Span {
    /// The range `[lo, hi)` along the axis (cm).
    pub lo: f64,
    pub hi: f64,
    /// The width across it (cm): a bin's area is its height times this.
    pub across: f64,
}

/// How to bin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Binning {
    pub axis: Axis,
    pub bins: usize,
    /// The range and width where the frames have no cell (ignored in a cell).
    pub span: Span,
    /// In a Lees–Edwards cell, `vx` about the imposed profile `γ̇ (y − L_y/2)`.
    pub relative: bool,
}

/// One bin's averages over the frames (see the module documentation; NaN where a bin held no
/// mass, `nematic` None where it held no body with a long axis).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bin {
    /// The bin's centre along the axis (cm; in a cell whose side changes, the mean over the
    /// frames).
    pub at: f64,
    pub phi: f64,
    pub vx: f64,
    pub vy: f64,
    pub temperature: f64,
    pub sxx: f64,
    pub syy: f64,
    pub sxy: f64,
    pub nematic: Option<f64>,
    /// How many frames the averages are over.
    pub frames: usize,
}

/// The bins of a frame: the range along the axis, the width across, and whether the range is a
/// period.
fn frame_span(frame: &FieldFrame, b: &Binning) -> (f64, f64, f64, bool) {
    match &frame.cell {
        Some(c) => {
            let (along, across) = match b.axis {
                Axis::X => (c.size.x, c.size.y),
                Axis::Y => (c.size.y, c.size.x),
            };
            let periodic = b.axis == Axis::X || c.periodic_y();
            (0.0, along, across, periodic)
        }
        None => (b.span.lo, b.span.hi, b.span.across, false),
    }
}

/// Calls `f(k, overlap)` for each bin k that `[s0, s1]` overlaps, with the length of the overlap
/// (bins of height `h` from `lo`, `n` of them; a periodic range wraps).
fn overlaps(
    s0: f64,
    s1: f64,
    lo: f64,
    h: f64,
    n: usize,
    periodic: bool,
    mut f: impl FnMut(usize, f64),
) {
    let first = ((s0 - lo) / h).floor() as i64;
    let last = ((s1 - lo) / h).floor() as i64;
    for u in first..=last {
        let (b0, b1) = (lo + u as f64 * h, lo + (u + 1) as f64 * h);
        let len = s1.min(b1) - s0.max(b0);
        if len <= 0.0 {
            continue;
        }
        if let Some(k) = bin_index(u, n, periodic) {
            f(k, len);
        }
    }
}

/// The bin of the `u`-th slab from `lo` (any whole number): itself, or wrapped in a period
/// (None outside a range that is not a period).
fn bin_index(u: i64, n: usize, periodic: bool) -> Option<usize> {
    if periodic {
        Some(u.rem_euclid(n as i64) as usize)
    } else {
        (0..n as i64).contains(&u).then_some(u as usize)
    }
}

/// The bin holding the coordinate `s`.
fn bin_of(s: f64, lo: f64, h: f64, n: usize, periodic: bool) -> Option<usize> {
    bin_index(((s - lo) / h).floor() as i64, n, periodic)
}

/// The area of `body` inside each bin it overlaps: `f(k, area, wraps)`, `wraps` the number of
/// periods the slab lies above the range (−1: the part of a body below a periodic range's
/// bottom, binned at the top; 0 inside).
fn body_areas(
    body: &FieldBody,
    axis: Axis,
    lo: f64,
    h: f64,
    n: usize,
    periodic: bool,
    mut f: impl FnMut(usize, f64, i64),
) {
    let fb = super::frame::FrameBody {
        shape: body.shape,
        position: body.position,
        angle: body.angle,
        density: body.density,
    };
    let r = body.shape.bounding_radius();
    let (p, q) = (
        axis.along(body.position),
        match axis {
            Axis::X => body.position.y,
            Axis::Y => body.position.x,
        },
    );
    // Slabs unbounded across (wider than the body).
    let (c0, c1) = (q - 2.0 * r - 1.0, q + 2.0 * r + 1.0);
    let first = ((p - r - lo) / h).floor() as i64;
    let last = ((p + r - lo) / h).floor() as i64;
    for u in first..=last {
        let (b0, b1) = (lo + u as f64 * h, lo + (u + 1) as f64 * h);
        let w = match axis {
            Axis::X => Window {
                x0: b0,
                x1: b1,
                y0: c0,
                y1: c1,
            },
            Axis::Y => Window {
                x0: c0,
                x1: c1,
                y0: b0,
                y1: b1,
            },
        };
        let a = clipped_area(&fb, w);
        if a <= 0.0 {
            continue;
        }
        if let Some(k) = bin_index(u, n, periodic) {
            f(k, a, u.div_euclid(n as i64));
        }
    }
}

/// The fields of `frames` in the bins of `binning` (see the module documentation). Two passes:
/// the mean velocities first, then the fluctuations about them.
pub fn fields(frames: &[FieldFrame], binning: &Binning) -> Vec<Bin> {
    let n = binning.bins;
    let axis = binning.axis;
    let mut mass = vec![0.0; n];
    let mut momentum = vec![Vec2::zeros(); n];
    let mut phi = vec![0.0; n];
    let mut contact = vec![[0.0; 3]; n];
    let mut order = vec![(0.0, 0.0, 0.0); n];
    let mut centre = vec![0.0; n];
    // The velocity of the part of body b in a slab `wraps` periods above the range: across the
    // horizontal seam of a Lees–Edwards cell that part is the body's image, which moves at
    // `v − wraps γ̇ L_y` (the image at y − L_y of a body above the top, at y + L_y of one below
    // the bottom: Lees & Edwards 1972); about the imposed profile it is the body's own.
    let relative_to = |frame: &FieldFrame, b: &FieldBody, wraps: i64| -> Vec2 {
        match &frame.cell {
            Some(c) if binning.relative => b.velocity - Vec2::new(c.mean_flow(b.position.y), 0.0),
            Some(c) if axis == Axis::Y && wraps != 0 => {
                let jump = c.mean_flow(c.size.y) - c.mean_flow(0.0);
                b.velocity - Vec2::new(wraps as f64 * jump, 0.0)
            }
            _ => b.velocity,
        }
    };
    for frame in frames {
        let (lo, hi, across, periodic) = frame_span(frame, binning);
        let h = (hi - lo) / n as f64;
        let area = h * across;
        for (k, c) in centre.iter_mut().enumerate() {
            *c += lo + (k as f64 + 0.5) * h;
        }
        for b in &frame.bodies {
            let axis_of = long_axis(&b.shape, b.angle);
            body_areas(b, axis, lo, h, n, periodic, |k, a, wraps| {
                let v = relative_to(frame, b, wraps);
                phi[k] += a / area;
                let m = b.density * a;
                mass[k] += m;
                momentum[k] += m * v;
                if let Some(t) = axis_of {
                    let o = &mut order[k];
                    o.0 += a * (2.0 * t).cos();
                    o.1 += a * (2.0 * t).sin();
                    o.2 += a;
                }
            });
        }
        // The contact part: each body side's branch vector shared between the bins it crosses.
        for c in &frame.contacts {
            let at = c.action_point();
            let mut side = |k: usize, f: Vec2| {
                let Some(body) = frame.bodies.get(k) else {
                    return;
                };
                let l = {
                    let r = at - body.position;
                    frame.cell.map_or(r, |cell| cell.shortest(r))
                };
                let (s0, s1) = {
                    let (a, e) = (axis.along(body.position), axis.along(body.position + l));
                    (a.min(e), a.max(e))
                };
                let mut add = |k: usize, w: f64| {
                    let s = &mut contact[k];
                    s[0] -= w * f.x * l.x / area;
                    s[1] -= w * f.y * l.y / area;
                    s[2] -= w * 0.5 * (f.x * l.y + f.y * l.x) / area;
                };
                if s1 > s0 {
                    overlaps(s0, s1, lo, h, n, periodic, |k, len| add(k, len / (s1 - s0)));
                } else if let Some(k) = bin_of(s0, lo, h, n, periodic) {
                    add(k, 1.0);
                }
            };
            side(c.j, c.force);
            if let Some(i) = c.giver_body() {
                side(i, -c.force);
            }
        }
    }
    let count = frames.len();
    let mean: Vec<Vec2> = (0..n).map(|k| momentum[k] / mass[k]).collect();
    // Second pass: the fluctuations about each bin's mean over the window.
    let mut fluct = vec![0.0; n];
    let mut kinetic = vec![[0.0; 3]; n];
    for frame in frames {
        let (lo, hi, across, periodic) = frame_span(frame, binning);
        let h = (hi - lo) / n as f64;
        let area = h * across;
        for b in &frame.bodies {
            body_areas(b, axis, lo, h, n, periodic, |k, a, wraps| {
                let v = relative_to(frame, b, wraps);
                let m = b.density * a;
                let d = v - mean[k];
                fluct[k] += 0.5 * m * d.norm_squared();
                let s = &mut kinetic[k];
                s[0] += m * d.x * d.x / area;
                s[1] += m * d.y * d.y / area;
                s[2] += m * d.x * d.y / area;
            });
        }
    }
    let per = |x: f64| x / count as f64;
    (0..n)
        .map(|k| Bin {
            at: per(centre[k]),
            phi: per(phi[k]),
            vx: mean[k].x,
            vy: mean[k].y,
            temperature: fluct[k] / mass[k],
            sxx: per(contact[k][0] + kinetic[k][0]),
            syy: per(contact[k][1] + kinetic[k][1]),
            sxy: per(contact[k][2] + kinetic[k][2]),
            nematic: (order[k].2 > 0.0).then(|| order[k].0.hypot(order[k].1) / order[k].2),
            frames: count,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::Partner;
    use crate::dynamics::cell::Periodic;

    fn disk(x: f64, y: f64, r: f64, v: Vec2) -> FieldBody {
        FieldBody {
            shape: Shape::Circle { r },
            position: Vec2::new(x, y),
            angle: 0.0,
            velocity: v,
            density: 1.0,
        }
    }

    fn binning(axis: Axis, bins: usize, lo: f64, hi: f64, across: f64) -> Binning {
        Binning {
            axis,
            bins,
            span: Span { lo, hi, across },
            relative: false,
        }
    }

    /// A square lattice of touching disks packs at π/4 in every bin that holds whole rows, and
    /// in bins that cut rows the exact shares sum to the disks' area.
    #[test]
    fn a_lattice_packs_at_pi_over_4_and_the_shares_sum_to_the_area() {
        let r = 0.5;
        let bodies: Vec<FieldBody> = (0..100)
            .map(|k| {
                disk(
                    0.5 + (k % 10) as f64,
                    0.5 + (k / 10) as f64,
                    r,
                    Vec2::zeros(),
                )
            })
            .collect();
        let frame = FieldFrame {
            bodies,
            ..Default::default()
        };
        // 5 bins of two rows each.
        let out = fields(
            std::slice::from_ref(&frame),
            &binning(Axis::Y, 5, 0.0, 10.0, 10.0),
        );
        for b in &out {
            assert!((b.phi - std::f64::consts::FRAC_PI_4).abs() < 1e-12, "{b:?}");
        }
        // 7 bins: each cuts rows; what each bin holds is the integral of the chord length.
        let out = fields(
            std::slice::from_ref(&frame),
            &binning(Axis::Y, 7, 0.0, 10.0, 10.0),
        );
        let total: f64 = out.iter().map(|b| b.phi * 10.0 / 7.0 * 10.0).sum();
        assert!(
            (total - 100.0 * std::f64::consts::PI * r * r).abs() < 1e-9,
            "{total}"
        );
        // A disk's share in a slab [y0, y1] against the closed form of the circular segment.
        let seg = |d: f64| {
            // The area of the disk below the line at height d above its centre.
            let d = (d / r).clamp(-1.0, 1.0);
            r * r * (d * (1.0 - d * d).sqrt() + d.asin() + std::f64::consts::FRAC_PI_2)
        };
        let h = 10.0 / 7.0;
        let want: f64 = (0..10)
            .map(|row| {
                let y = 0.5 + row as f64;
                10.0 * (seg(h - y) - seg(0.0 - y))
            })
            .sum::<f64>()
            / (h * 10.0);
        assert!(
            (out[0].phi - want).abs() < 1e-12,
            "{} against {want}",
            out[0].phi
        );
    }

    /// A column of disks pressed between a floor and a lid by a force F carries σ_yy = F/W in
    /// every bin between them (each bin crossed by the whole chain), and nothing across.
    #[test]
    fn a_loaded_column_carries_f_over_w_in_every_bin() {
        let (r, f, w) = (0.5, 40.0, 4.0);
        let bodies: Vec<FieldBody> = (0..6)
            .map(|k| disk(2.0, r + 2.0 * r * k as f64, r, Vec2::zeros()))
            .collect();
        let mut contacts = Vec::new();
        let up = Vec2::new(0.0, 1.0);
        // The floor under the first, each disk on the one below, the lid on the last.
        contacts.push(FrameContact {
            i: Partner::Wall(0),
            j: 0,
            point: Vec2::new(2.0, 0.0),
            normal: up,
            force: up * f,
            couple: 0.0,
            depth: 0.0,
            state: String::new(),
        });
        for k in 1..6 {
            contacts.push(FrameContact {
                i: Partner::Body(k - 1),
                j: k,
                point: Vec2::new(2.0, 2.0 * r * k as f64),
                normal: up,
                force: up * f,
                couple: 0.0,
                depth: 0.0,
                state: String::new(),
            });
        }
        contacts.push(FrameContact {
            i: Partner::Wall(1),
            j: 5,
            point: Vec2::new(2.0, 6.0),
            normal: -up,
            force: -up * f,
            couple: 0.0,
            depth: 0.0,
            state: String::new(),
        });
        let frame = FieldFrame {
            bodies,
            contacts,
            cell: None,
        };
        let out = fields(&[frame], &binning(Axis::Y, 8, 0.0, 6.0, w));
        for b in &out {
            assert!((b.syy - f / w).abs() < 1e-12 * f / w, "{b:?}");
            assert!(b.sxx.abs() < 1e-12 && b.sxy.abs() < 1e-12, "{b:?}");
        }
    }

    /// Velocities: a plug flow U with fluctuations ±u in x and y within each bin gives v̄ = U
    /// and T = u²/2 (the fluctuation per unit mass of two components, u² each, halved), and the
    /// kinetic stress ρ_bin u² on the diagonal.
    #[test]
    fn a_plug_flow_with_known_fluctuations_gives_its_mean_and_temperature() {
        let (u0, u) = (3.0, 0.2);
        let mut bodies = Vec::new();
        for row in 0..4 {
            for (k, s) in [(0, 1.0), (1, -1.0)] {
                let v = Vec2::new(u0 + s * u, s * u);
                bodies.push(disk(1.0 + 2.0 * k as f64, 1.0 + 2.0 * row as f64, 0.4, v));
            }
        }
        let frame = FieldFrame {
            bodies,
            ..Default::default()
        };
        let out = fields(&[frame], &binning(Axis::Y, 4, 0.0, 8.0, 4.0));
        let rho = 2.0 * std::f64::consts::PI * 0.16 / 8.0;
        for b in &out {
            assert!((b.vx - u0).abs() < 1e-12 && b.vy.abs() < 1e-12, "{b:?}");
            assert!((b.temperature - u * u).abs() < 1e-12, "{b:?}");
            assert!((b.sxx - rho * u * u).abs() < 1e-12, "{b:?}");
            assert!((b.sxy - rho * u * u).abs() < 1e-12, "{b:?}");
            assert_eq!(b.nematic, None);
        }
    }

    /// In a periodic cell a body across the seam is shared between the first and the last bin,
    /// and a contact across it is counted once: the bins' stresses times their areas sum to
    /// the whole cell's Love–Weber stress.
    #[test]
    fn across_the_seam_areas_and_stresses_are_shared_and_sum_to_the_whole() {
        let cell = Cell::new(Vec2::new(4.0, 4.0), Periodic::XY, 0.0, None);
        let (r, f) = (0.5, 10.0);
        let bodies = vec![
            disk(2.0, 3.8, r, Vec2::zeros()),
            disk(2.0, 0.6 + 1e-3, r, Vec2::zeros()),
        ];
        // The pair touches across the horizontal seam (through the image of the second above).
        let n = Vec2::new(0.0, 1.0);
        let contacts = vec![FrameContact {
            i: Partner::Body(0),
            j: 1,
            point: Vec2::new(2.0, 4.3),
            normal: n,
            force: n * f,
            couple: 0.0,
            depth: 1e-3,
            state: String::new(),
        }];
        let frame = FieldFrame {
            bodies,
            contacts,
            cell: Some(cell),
        };
        let out = fields(
            std::slice::from_ref(&frame),
            &binning(Axis::Y, 8, 0.0, 0.0, 0.0),
        );
        let h = 0.5;
        let total: f64 = out.iter().map(|b| b.phi * h * 4.0).sum();
        assert!(
            (total - 2.0 * std::f64::consts::PI * r * r).abs() < 1e-12,
            "{total}"
        );
        // The chain between the centres (y 3.8 → 4.601, wrapped): σ_yy A = F (0.801) in all.
        let syy: f64 = out.iter().map(|b| b.syy * h * 4.0).sum();
        assert!((syy - f * 0.801).abs() < 1e-9, "{syy}");
        // The bins the branch vectors cross: 7 (3.5–4) and 0 (0–0.5) and 1 (0.5–0.601).
        assert!(
            out[7].syy > 0.0 && out[0].syy > 0.0 && out[1].syy > 0.0,
            "{out:?}"
        );
        assert!(out[2..7].iter().all(|b| b.syy == 0.0), "{out:?}");
    }

    /// In a Lees–Edwards cell the part of a body beyond the horizontal seam is its image, which
    /// moves at `v ∓ γ̇ L_y` (Lees & Edwards 1972): a disk at rest in the flow's frame at the
    /// top, half across the seam, gives the bottom bin the image's velocity and no temperature.
    #[test]
    fn across_a_lees_edwards_seam_a_body_moves_as_its_image() {
        let (rate, l) = (3.0, 4.0);
        let cell = Cell::new(Vec2::new(l, l), Periodic::XY, rate, None);
        // Centred on the top edge: half of it above, binned at the bottom as its image.
        let v = Vec2::new(rate * (l - 0.5 * l), 0.0);
        let frame = FieldFrame {
            bodies: vec![disk(2.0, l, 0.4, v)],
            contacts: Vec::new(),
            cell: Some(cell),
        };
        let out = fields(
            std::slice::from_ref(&frame),
            &binning(Axis::Y, 4, 0.0, 0.0, 0.0),
        );
        // Top bin: the body itself, at +γ̇ L_y/2; bottom bin: its image, at −γ̇ L_y/2.
        assert!((out[3].vx - 0.5 * rate * l).abs() < 1e-12, "{out:?}");
        assert!((out[0].vx + 0.5 * rate * l).abs() < 1e-12, "{out:?}");
        assert!(out[0].temperature.abs() < 1e-12 && out[3].temperature.abs() < 1e-12);
        // About the imposed profile both halves are at rest.
        let mut relative = binning(Axis::Y, 4, 0.0, 0.0, 0.0);
        relative.relative = true;
        let out = fields(std::slice::from_ref(&frame), &relative);
        assert!(
            out[0].vx.abs() < 1e-12 && out[3].vx.abs() < 1e-12,
            "{out:?}"
        );
    }
}
