//! A small deterministic generator (xorshift*) shared by the validation families, the tests and
//! the kernel benchmarks, so every run draws the same pairs. Not for simulations (the pile
//! generator has its own, seeded from the case).

/// xorshift* state; seed with any non-zero value.
pub struct Rng(pub u64);

impl Rng {
    /// Uniform in [0, 1), 53 random bits.
    pub fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [a, b).
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.uniform()
    }

    /// Uniform angle in [−π, π).
    pub fn angle(&mut self) -> f64 {
        self.range(-std::f64::consts::PI, std::f64::consts::PI)
    }
}
