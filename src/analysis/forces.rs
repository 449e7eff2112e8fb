//! The statistics of contact forces (`dem2d forces`): the distribution of the normal forces
//! normalised by their mean, and the stress–fabric relation of Rothenburg & Bathurst
//! (Géotechnique 39, 1989) and Azéma & Radjaï: for coaxial directions
//! `sin φ = (σ₁ − σ₃)/(σ₁ + σ₃) ≈ ½(a_c + a_n + a_t)` ([`super::fabric`]; disks; non-circular
//! bodies add a branch-length anisotropy, which this leaves out and shows as the difference).

use super::fabric::{Anisotropy, anisotropy};
use super::frame::Frame;
use super::stress::{love_weber, principal};

/// A histogram of `f/⟨f⟩`: bins of equal width from 0 to the largest force.
#[derive(Clone, Debug, PartialEq)]
pub struct Distribution {
    /// The mean normal force ⟨f⟩ (dyn/cm).
    pub mean: f64,
    /// Each bin's centre `f/⟨f⟩`, its probability density (`count / (n Δ)`, so that
    /// `Σ pdf Δ = 1`) and its count.
    pub rows: Vec<(f64, f64, usize)>,
    /// The forces counted (those > 0).
    pub count: usize,
}

/// The distribution of the positive values of `forces` in `bins` bins.
pub fn distribution(forces: &[f64], bins: usize) -> Distribution {
    let f: Vec<f64> = forces.iter().copied().filter(|&x| x > 0.0).collect();
    let n = f.len();
    if n == 0 || bins == 0 {
        return Distribution {
            mean: f64::NAN,
            rows: Vec::new(),
            count: 0,
        };
    }
    let mean = f.iter().sum::<f64>() / n as f64;
    let top = f.iter().copied().fold(0.0, f64::max) / mean;
    let width = top / bins as f64;
    let mut count = vec![0usize; bins];
    for x in &f {
        let k = ((x / mean / width) as usize).min(bins - 1);
        count[k] += 1;
    }
    Distribution {
        mean,
        rows: (0..bins)
            .map(|k| {
                (
                    (k as f64 + 0.5) * width,
                    count[k] as f64 / (n as f64 * width),
                    count[k],
                )
            })
            .collect(),
        count: n,
    }
}

/// The stress–fabric check of frames taken together.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StressFabric {
    /// The anisotropies of all the frames' body–body contacts together.
    pub fabric: Anisotropy,
    /// `(σ₁ − σ₃)/(σ₁ + σ₃)` of the mean Love–Weber stress over the frames.
    pub sin_phi: f64,
    /// `½(a_c + a_n + a_t)`.
    pub half_sum: f64,
}

/// The check over `frames` (each over its region `area`, every body inside).
pub fn stress_fabric(frames: &[(Frame, f64)]) -> StressFabric {
    let mut all = Frame::default();
    let mut s = [0.0; 3];
    for (f, area) in frames {
        let inside = vec![true; f.bodies.len()];
        let st = love_weber(f, &inside, *area).symmetric();
        for k in 0..3 {
            s[k] += st[k] / frames.len() as f64;
        }
        // The contacts pooled: the anisotropy reads only their normals and forces (its
        // `inside` test keeps every contact here).
        all.contacts.extend(f.contacts.iter().cloned().map(|mut c| {
            c.j = 0;
            if c.giver_body().is_some() {
                c.i = crate::dynamics::Partner::Body(0);
            }
            c
        }));
    }
    let fabric = anisotropy(&all, &[true]);
    let (s1, s3, _) = principal(s);
    StressFabric {
        fabric,
        sin_phi: (s1 - s3) / (s1 + s3),
        half_sum: 0.5 * (fabric.a_c + fabric.a_n + fabric.a_t),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The histogram's density integrates to one and each count is where the value lies.
    #[test]
    fn the_density_integrates_to_one_and_counts_fall_where_they_lie() {
        // Forces 0.5, 1.5, …, 9.5 (mean 5), and a zero that is not counted: bins of width 1.9
        // in force hold two each (the largest in the last).
        let mut f: Vec<f64> = (0..10).map(|k| k as f64 + 0.5).collect();
        f.push(0.0);
        let d = distribution(&f, 5);
        assert_eq!(d.count, 10);
        assert!((d.mean - 5.0).abs() < 1e-15);
        let width = 9.5 / 5.0 / 5.0;
        let total: f64 = d.rows.iter().map(|r| r.1 * width).sum();
        assert!((total - 1.0).abs() < 1e-14, "{total}");
        let counts: Vec<usize> = d.rows.iter().map(|r| r.2).collect();
        assert_eq!(counts, vec![2; 5]);
        assert!((d.rows[0].1 - 2.0 / (10.0 * width)).abs() < 1e-14);
    }
}
