//! Error bars: the standard error of a mean, from one correlated time series (blocking, with
//! the block length chosen from the integrated autocorrelation time) or from independent
//! repetitions (seeds). Every `± se` a study prints comes from here.
//!
//! # Method
//! - **Independent values** (one per seed, per packing): `se = s/√m`, `s` the sample standard
//!   deviation (divisor `m − 1`) of the `m` values ([`mean_se`]).
//! - **One correlated series** `x_1 … x_n` (a stress sampled along a run): its mean's variance is
//!   `σ² g / n` for large `n`, with the *statistical inefficiency* `g = 1 + 2 Σ_{k≥1} ρ_k`
//!   (ρ_k the autocorrelation at lag k; Sokal 1997, eq. 2.19, `g = 2 τ_int`). For an AR(1)
//!   series `x_t = φ x_{t−1} + ε_t`, `ρ_k = φ^k` and `g = (1 + φ)/(1 − φ)`.
//!   - [`inefficiency`] estimates `g` by Sokal's automatic window: the smallest `M` with
//!     `M ≥ c · g(M)/2`, `c` = [`SOKAL_C`] (Sokal 1997, §3, "automatic windowing").
//!   - [`blocking`] is Flyvbjerg & Petersen's transformation (J. Chem. Phys. 91 (1989) 461):
//!     halve the series again and again by averaging neighbours; at each level with `m`
//!     blocks of length `B` the estimate `se_B² = Σ (x̄_i − x̄)² / (m (m − 1))` (their eq. 26–28)
//!     and its own standard error `se_B / √(2 (m − 1))` (eq. 28's error bar). `se_B` grows with
//!     `B` to the true se and stays there (the plateau).
//!   - [`series_se`] reads the plateau at a block length chosen from `g` rather than by eye:
//!     the blocked variance at block length `B` falls short of the true one by the relative
//!     bias `2 Σ_k k ρ_k / (g B)` (from `Var(block mean) = (σ²/B²) Σ_{|k|<B} (B − |k|) ρ_k`);
//!     for an AR(1) series of the same `g` that is `(g² − 1)/(2 g B)`. The chosen `B` is the
//!     smallest power of two that keeps it below [`BIAS`] (2 %): `B ≥ (g² − 1)/(2 g · BIAS)`.
//!     With fewer than [`MIN_BLOCKS`] blocks there, the level with [`MIN_BLOCKS`] blocks is used
//!     and the estimate says it is not [`Estimate::converged`] (the series is too short for its
//!     correlation time: its se is then biased low).
//! - A **ratio of means** `r = ⟨a⟩/⟨b⟩` (μ = −⟨σ_xy⟩/⟨σ_yy⟩) takes the se of the mean of the
//!   linearised series `u_t = (a_t − r b_t)/⟨b⟩` (the delta method; e.g. Allen & Tildesley,
//!   *Computer Simulation of Liquids*, 2nd ed., §8.4): [`ratio_se`].
//! - Two estimates agree when `|x₁ − x₂| < 3 √(se₁² + se₂²)` ([`consistent`]).

/// Sokal's window constant `c` (Sokal 1997 recommends 4–10 for roughly exponential decay).
pub const SOKAL_C: f64 = 6.0;

/// The largest relative bias of the blocked variance [`series_se`] accepts (see the module
/// documentation).
pub const BIAS: f64 = 0.02;

/// A series shorter than this many times its estimated `g` gives a se from `g` that is not
/// [`Estimate::converged`]: too short a series also underestimates `g` itself (an AR(1) series
/// with g = 199 and 512 values reads g ≈ 40, its window closing early), and the se's own
/// relative error, about `√(SOKAL_C g / n)`, is then above one half.
pub const MIN_LENGTH: f64 = 20.0;

/// The fewest blocks a blocked se is read from: its relative error is then `1/√(2·15)` ≈ 18 %.
pub const MIN_BLOCKS: usize = 16;

/// A mean with its standard error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    /// The mean.
    pub mean: f64,
    /// Its standard error.
    pub se: f64,
    /// The values (samples of a series, or repetitions) it is made of.
    pub n: usize,
    /// The block length the se was read at (1 for independent values; 0 where it came from the
    /// inefficiency, the series being shorter than [`MIN_BLOCKS`] blocks).
    pub block: usize,
    /// The statistical inefficiency `g` of the series (1 for independent values).
    pub inefficiency: f64,
    /// Whether the se can be trusted: blocked with at least [`MIN_BLOCKS`] blocks of the
    /// chosen length, or (shorter series) Sokal's window closed; for independent values, at
    /// least two of them.
    pub converged: bool,
}

impl Estimate {
    /// `mean ± se` with `digits` decimals, marked `†` when not [`Estimate::converged`].
    pub fn pm(&self, digits: usize) -> String {
        format!(
            "{:.*} ± {:.*}{}",
            digits,
            self.mean,
            digits,
            self.se,
            if self.converged { "" } else { " †" }
        )
    }
}

/// The mean of `x` (NaN for none).
pub fn mean(x: &[f64]) -> f64 {
    x.iter().sum::<f64>() / x.len() as f64
}

/// The mean and the sample standard deviation (divisor `n − 1`; 0 for one value) of `x`.
pub fn mean_sd(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let m = mean(x);
    let v = x.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / (n - 1.0).max(1.0);
    (m, v.sqrt())
}

/// The mean of independent values `x` (one per seed) and its standard error `s/√m`; for one
/// value the se is NaN and the estimate is not converged.
pub fn mean_se(x: &[f64]) -> Estimate {
    let (m, s) = mean_sd(x);
    let n = x.len();
    Estimate {
        mean: m,
        se: if n > 1 {
            s / (n as f64).sqrt()
        } else {
            f64::NAN
        },
        n,
        block: 1,
        inefficiency: 1.0,
        converged: n > 1,
    }
}

/// One level of [`blocking`]: block length, number of blocks, the se estimate and its error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Level {
    pub block: usize,
    pub blocks: usize,
    pub se: f64,
    pub se_error: f64,
}

/// The se of the mean of `x` read from blocks of length `block` (the last `n mod block` values
/// are left out of the blocks): `√(Σ (x̄_i − x̄)² / (m (m − 1)))` over the `m` block means.
pub fn blocked_se(x: &[f64], block: usize) -> Level {
    let m = x.len() / block.max(1);
    let means: Vec<f64> = (0..m)
        .map(|i| mean(&x[i * block..(i + 1) * block]))
        .collect();
    let (_, s) = mean_sd(&means);
    let se = s / (m as f64).sqrt();
    Level {
        block,
        blocks: m,
        se,
        se_error: se / (2.0 * (m as f64 - 1.0)).sqrt(),
    }
}

/// Flyvbjerg–Petersen blocking (see the module documentation): the levels of block length 1,
/// 2, 4, … while at least two blocks remain.
pub fn blocking(x: &[f64]) -> Vec<Level> {
    let mut out = Vec::new();
    let mut b = 1;
    while x.len() / b >= 2 {
        out.push(blocked_se(x, b));
        b *= 2;
    }
    out
}

/// The autocorrelation of `x` at lag `k` (the biased estimator `Σ (x_t − x̄)(x_{t+k} − x̄)/n`
/// over the variance, as Sokal 1997, eq. 3.5).
fn autocorrelation(x: &[f64], m: f64, c0: f64, k: usize) -> f64 {
    let n = x.len();
    let ck: f64 = (0..n - k).map(|t| (x[t] - m) * (x[t + k] - m)).sum::<f64>() / n as f64;
    ck / c0
}

/// The statistical inefficiency `g = 1 + 2 Σ_{k=1}^{M} ρ_k` of `x` with Sokal's automatic
/// window `M` (the smallest with `M ≥ SOKAL_C · g(M)/2`, at most n/4); 1 for a constant series,
/// and at least 1 (anticorrelation does not shrink the blocks below one value).
pub fn inefficiency(x: &[f64]) -> f64 {
    window(x).0
}

/// [`inefficiency`], and whether the window closed (`M ≥ SOKAL_C · g(M)/2` within n/4: the
/// series is at least about `2 SOKAL_C` times its correlation time `g` long).
pub fn window(x: &[f64]) -> (f64, bool) {
    let n = x.len();
    if n < 2 {
        return (1.0, false);
    }
    let m = mean(x);
    let c0 = x.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / n as f64;
    if c0 <= 0.0 || !c0.is_finite() {
        return (1.0, true);
    }
    let mut g = 1.0;
    // A window past a quarter of the series reads mostly noise: the loop stops there too.
    for k in 1..=(n / 4).max(1) {
        g += 2.0 * autocorrelation(x, m, c0, k);
        if k as f64 >= SOKAL_C * g / 2.0 {
            return (g.max(1.0), true);
        }
    }
    (g.max(1.0), false)
}

/// The block length [`series_se`] uses for a series of inefficiency `g`: the smallest power of
/// two with `(g² − 1)/(2 g B) ≤ BIAS`.
pub fn block_length(g: f64) -> usize {
    let need = (g * g - 1.0) / (2.0 * g * BIAS);
    let mut b = 1usize;
    while (b as f64) < need {
        b *= 2;
    }
    b
}

/// The mean of the correlated series `x` and its standard error (see the module
/// documentation): blocked at the length chosen from its inefficiency `g` where the series holds
/// [`MIN_BLOCKS`] blocks of it; else, from `g` itself, `se² = g s²/n` (Sokal 1997, eq. 2.20),
/// converged when Sokal's window closed and the series is [`MIN_LENGTH`] times `g` long.
pub fn series_se(x: &[f64]) -> Estimate {
    let n = x.len();
    let (g, closed) = window(x);
    let want = block_length(g);
    if want * MIN_BLOCKS <= n {
        let level = blocked_se(x, want);
        return Estimate {
            mean: mean(x),
            se: level.se,
            n,
            block: want,
            inefficiency: g,
            converged: true,
        };
    }
    let (m, s) = mean_sd(x);
    Estimate {
        mean: m,
        se: (g * s * s / n as f64).sqrt(),
        n,
        block: 0,
        inefficiency: g,
        converged: closed && n as f64 >= MIN_LENGTH * g,
    }
}

/// The ratio of means `r = ⟨a⟩/⟨b⟩` of two series sampled together, and its se from the
/// linearised series `(a_t − r b_t)/⟨b⟩` (the delta method), blocked as [`series_se`].
pub fn ratio_se(a: &[f64], b: &[f64]) -> Estimate {
    let (ma, mb) = (mean(a), mean(b));
    let r = ma / mb;
    let u: Vec<f64> = a.iter().zip(b).map(|(x, y)| (x - r * y) / mb).collect();
    Estimate {
        mean: r,
        ..series_se(&u)
    }
}

/// Whether two estimates of the same quantity agree: `|x₁ − x₂| < 3 √(se₁² + se₂²)`.
pub fn consistent(a: &Estimate, b: &Estimate) -> bool {
    (a.mean - b.mean).abs() < 3.0 * a.se.hypot(b.se)
}
