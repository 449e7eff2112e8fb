//! What dem2d accepts: the ranges of every input quantity, and the size of input files.
//!
//! The step forms products of up to seven input magnitudes (the rotational energy `½Iω²` is
//! `ρ·L⁴·ω²`; the critical step `1/m + r²/I` divides by `ρ·L⁴`). With every magnitude within
//! 1e-40 … 1e40, every such product stays within 1e±280, far from float64's overflow (1.8e308)
//! and underflow (2.2e-308): the dynamics never meets an overflow or a subnormal because of the
//! input alone. Ratios matter as well as magnitudes: positions must resolve the smallest body
//! (a coordinate of 1e9 × the smallest size is resolved to 2e-7 of it), and the contact kernels
//! are accurate to rounding relative to the larger body of a pair, so the spread of sizes is
//! bounded. Everything outside is refused at load, naming the field; everything inside runs, and
//! what then explodes through the physics (Δt far above the critical step, say) is caught by the
//! run as a blow-up.
//!
//! | quantity | accepted |
//! |---|---|
//! | every number | finite, magnitude ≤ [`MAX_MAGNITUDE`] (1e40) |
//! | sizes `r`, `a`, `b`, `w`, `h`; `density`; `dt`; `duration`; stiffnesses `kn`, `ks` (and `…_over_rho_g`), `young` | [`MIN_SCALE`] … [`MAX_MAGNITUDE`] (1e-40 … 1e40) |
//! | a stiffness or modulus as the law sees it (`kn_over_rho_g·ρ·|g|`, E*, G*) | 1e-40 … 1e40, for every density of the scene |
//! | largest / smallest size in a scene (or a `contact` pair) | ≤ [`MAX_SIZE_RATIO`] (1e6) |
//! | a coordinate of a position or a wall point | ≤ [`MAX_EXTENT_RATIO`] (1e9) × the smallest size |
//! | steps, `duration / dt` | ≤ [`MAX_STEPS`] (1e10) |
//! | an input file | ≤ [`MAX_INPUT_BYTES`] (256 MiB) |

use super::fields::FieldError;
pub use super::fields::{MAX_MAGNITUDE, MIN_SCALE};
use crate::contact_law::{ContactSpec, DampingSpec, LinearDamping, Scaled, ShearSpec, SpringSpec};
use crate::geometry::{Shape, Vec2};
use std::io::Read;

/// Largest ratio of the largest to the smallest size in a scene (or a pair).
pub const MAX_SIZE_RATIO: f64 = 1e6;
/// Largest coordinate, in units of the smallest size.
pub const MAX_EXTENT_RATIO: f64 = crate::run::watch::MAX_EXTENT_RATIO;
/// Ceiling on the number of steps of a run.
pub const MAX_STEPS: u64 = 10_000_000_000;
/// Largest input file (a case of a million bodies is about 200 MB).
pub const MAX_INPUT_BYTES: u64 = 256 * 1024 * 1024;

/// Reads an input file as text (`-`: standard input), refusing more than [`MAX_INPUT_BYTES`]
/// (reading `/dev/zero` must end). A leading byte-order mark is kept (the JSON reader skips it).
/// The error says what went wrong, without the file's name.
pub fn read_input(file: &str) -> Result<String, String> {
    let mut bytes = Vec::new();
    let limit = MAX_INPUT_BYTES + 1;
    let read = if file == "-" {
        std::io::stdin().lock().take(limit).read_to_end(&mut bytes)
    } else {
        std::fs::File::open(file).and_then(|f| f.take(limit).read_to_end(&mut bytes))
    };
    read.map_err(|e| format!("cannot read: {e}"))?;
    if bytes.len() as u64 > MAX_INPUT_BYTES {
        return Err(format!(
            "larger than {} MiB, the limit for an input file",
            MAX_INPUT_BYTES >> 20
        ));
    }
    String::from_utf8(bytes).map_err(|e| {
        format!(
            "not UTF-8 text (invalid byte at offset {})",
            e.utf8_error().valid_up_to()
        )
    })
}

/// The sizes of a shape with their field names.
fn sizes(shape: &Shape) -> [(&'static str, f64); 2] {
    match *shape {
        Shape::Circle { r } => [("r", r), ("r", r)],
        Shape::Ellipse { a, b } => [("a", a), ("b", b)],
        Shape::Rectangle { w, h } => [("w", w), ("h", h)],
        // Its smallest width is at least twice the inscribed radius, its largest at most twice
        // the bounding radius.
        Shape::Polygon(p) => [
            ("vertices", 2.0 * p.inscribed_radius),
            ("vertices", 2.0 * p.bounding_radius),
        ],
        // Its members' sizes: the smallest member's diameter, the bounding diameter.
        Shape::Clump(c) => [
            ("disks", 2.0 * c.smallest_radius),
            ("disks", 2.0 * c.bounding_radius),
        ],
    }
}

/// A body or a wall as far as the ranges are concerned: its path (`bodies[3]`, `pairs[2].i`)
/// and what it holds.
pub enum Placed<'a> {
    Body {
        path: String,
        shape: &'a Shape,
        position: Vec2,
    },
    Wall {
        path: String,
        point: Vec2,
    },
    /// A point named by its own path (a periodic cell's far corner, `cell.size`).
    Point {
        path: String,
        point: Vec2,
    },
}

/// Checks the size spread and the coordinates of a scene (or a pair): the largest size at most
/// [`MAX_SIZE_RATIO`] × the smallest, every coordinate at most [`MAX_EXTENT_RATIO`] × the
/// smallest size.
pub fn check_extent(items: &[Placed]) -> Result<(), FieldError> {
    let mut smallest: Option<(String, f64)> = None;
    let mut largest: Option<(String, f64)> = None;
    for item in items {
        if let Placed::Body { path, shape, .. } = item {
            for (field, s) in sizes(shape) {
                if smallest.as_ref().is_none_or(|m| s < m.1) {
                    smallest = Some((format!("{path}.shape.{field}"), s));
                }
                if largest.as_ref().is_none_or(|m| s > m.1) {
                    largest = Some((format!("{path}.shape.{field}"), s));
                }
            }
        }
    }
    let (Some((small_at, small)), Some((large_at, large))) = (smallest, largest) else {
        return Ok(());
    };
    if large > MAX_SIZE_RATIO * small {
        return Err(FieldError::new(
            large_at,
            format!(
                "{large:e} is {:.1e} × the smallest size ({small_at} = {small:e}); sizes may \
                 differ by a factor of at most {MAX_SIZE_RATIO:e}",
                large / small
            ),
        ));
    }
    for item in items {
        let (at, p) = match item {
            Placed::Body { path, position, .. } => (format!("{path}.position"), *position),
            Placed::Wall { path, point } => (format!("{path}.point"), *point),
            Placed::Point { path, point } => (path.clone(), *point),
        };
        let c = p.x.abs().max(p.y.abs());
        if c > MAX_EXTENT_RATIO * small {
            return Err(FieldError::new(
                at,
                format!(
                    "a coordinate of {c:e} is {:.1e} × the smallest size ({small_at} = {small:e}); \
                     at most {MAX_EXTENT_RATIO:e} is accepted (farther out, positions no longer \
                     resolve the bodies)",
                    c / small
                ),
            ));
        }
    }
    Ok(())
}

/// The number of steps `duration / dt`, refused above [`MAX_STEPS`] (named at `dt`).
pub fn check_steps(duration: f64, dt: f64) -> Result<(), FieldError> {
    let steps = (duration / dt).round();
    if steps > MAX_STEPS as f64 {
        return Err(FieldError::new(
            "dt",
            format!(
                "duration / dt = {steps:.3e} steps, above the ceiling of {:e} steps per run",
                MAX_STEPS as f64
            ),
        ));
    }
    Ok(())
}

/// Where a contact specification's fields are (`contact`, `walls[2]`), the densities the law
/// will be resolved for, and |g|.
pub struct SpecContext<'a> {
    pub at: &'a str,
    /// Smallest and largest body density, with the path of each.
    pub rho: [(f64, String); 2],
    pub g: f64,
}

fn in_window(x: f64) -> bool {
    (MIN_SCALE..=MAX_MAGNITUDE).contains(&x)
}

/// Checks that every stiffness and modulus of `spec` resolves to a value within
/// [`MIN_SCALE`] … [`MAX_MAGNITUDE`] for every density of the scene (a zero, subnormal or
/// infinite stiffness lets bodies pass through each other or overflows), and that nothing is
/// given per ρg in a scene without gravity. `other` is the material on the other side (for
/// Hertz–Mindlin walls: the scene's; T11, T19).
pub fn check_spec(
    spec: &ContactSpec,
    other: &ContactSpec,
    ctx: &SpecContext,
) -> Result<(), FieldError> {
    let field = |k: &str| super::fields::join(ctx.at, k);
    let scaled = |s: Scaled, abs: &str, rel: &str, stiffness: bool| -> Result<(), FieldError> {
        let (name, v) = match s {
            Scaled::Absolute(v) => (abs, v),
            Scaled::OverRhoG(v) => (rel, v),
        };
        if let Scaled::OverRhoG(v) = s
            && ctx.g == 0.0
            && (stiffness || v > 0.0)
        {
            return Err(FieldError::new(
                field(rel),
                format!(
                    "{rel} needs non-zero gravity: it is multiplied by ρ|g|, and gravity is zero \
                     here (give `{abs}` instead)"
                ),
            ));
        }
        for (rho, rho_at) in &ctx.rho {
            let r = s.value(*rho, ctx.g);
            let bad = if stiffness {
                !in_window(r)
            } else {
                r > MAX_MAGNITUDE
            };
            if bad {
                let how = match s {
                    Scaled::Absolute(_) => String::new(),
                    Scaled::OverRhoG(_) => {
                        format!(" ({v:e} × ρ × |g| for ρ = {rho:e} at {rho_at})")
                    }
                };
                let range = if stiffness {
                    format!("{MIN_SCALE:e} … {MAX_MAGNITUDE:e}")
                } else {
                    format!("up to {MAX_MAGNITUDE:e}")
                };
                return Err(FieldError::new(
                    field(name),
                    format!("resolves to {abs} = {r:e}{how}, outside the accepted range {range}"),
                ));
            }
        }
        Ok(())
    };
    if let SpringSpec::Linear { kn } = spec.normal.spring {
        scaled(kn, "kn", "kn_over_rho_g", true)?;
    }
    if let ShearSpec::Constant(ks) = spec.tangential.stiffness {
        scaled(ks, "ks", "ks_over_rho_g", true)?;
    }
    if let DampingSpec::Linear(LinearDamping::Dashpots { eta_n, eta_s }) = spec.damping {
        scaled(eta_n, "eta_n", "eta_n_over_rho_g", false)?;
        scaled(eta_s, "eta_s", "eta_s_over_rho_g", false)?;
    }
    if let Some((young, poisson)) = spec.normal.moduli() {
        let (e2, nu2) = other.normal.moduli().unwrap_or((young, poisson));
        let e_star = 1.0 / ((1.0 - poisson * poisson) / young + (1.0 - nu2 * nu2) / e2); // T(11)
        let g_star = 1.0
            / (2.0 * (2.0 - poisson) * (1.0 + poisson) / young
                + 2.0 * (2.0 - nu2) * (1.0 + nu2) / e2); // T(19)
        for (name, v) in [("E*", e_star), ("G*", g_star)] {
            if !in_window(v) {
                return Err(FieldError::new(
                    field("young"),
                    format!(
                        "with this `poisson`, the contact modulus {name} = {v:e}, outside \
                         the accepted range {MIN_SCALE:e} … {MAX_MAGNITUDE:e}"
                    ),
                ));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn products_of_seven_accepted_magnitudes_stay_normal() {
        // The premise of the ranges: ρ·L⁴·ω² and its reciprocal at the extremes.
        let (lo, hi) = (MIN_SCALE, MAX_MAGNITUDE);
        let big = hi * hi.powi(4) * hi * hi;
        let small = lo * lo.powi(4) * lo * lo;
        assert!(big.is_finite() && big < 1e281, "{big:e}");
        assert!(small.is_normal() && small > 1e-281, "{small:e}");
        assert!((1.0 / small).is_finite());
    }
}
