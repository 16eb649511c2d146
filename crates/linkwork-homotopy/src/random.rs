//! A small deterministic generator (splitmix64) for gamma, patches and start systems:
//! results are reproducible from the seed, and no dependency is needed for it.

use num_complex::Complex64 as C64;

pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed ^ 0x9e37_79b9_7f4a_7c15)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in (0, 1).
    pub fn uniform(&mut self) -> f64 {
        ((self.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    /// Standard complex normal (Box-Muller).
    pub fn complex_normal(&mut self) -> C64 {
        let r = (-2.0 * self.uniform().ln()).sqrt() / std::f64::consts::SQRT_2;
        let a = std::f64::consts::TAU * self.uniform();
        C64::from_polar(r, a)
    }

    /// Uniform on the unit circle.
    pub fn unit_complex(&mut self) -> C64 {
        C64::from_polar(1.0, std::f64::consts::TAU * self.uniform())
    }
}
