//! A deterministic stream of numbers for the shadow room's tests (no dependency, the same
//! numbers on every machine).

use glam::Vec3;

/// A 64-bit linear congruential generator (Knuth's MMIX constants).
pub(super) struct Lcg(pub u64);

impl Lcg {
    /// The next number in [0, 1).
    pub fn next(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }

    /// A point in the box [lo, hi)³.
    pub fn in_box(&mut self, lo: f32, hi: f32) -> Vec3 {
        Vec3::new(self.next(), self.next(), self.next()) * (hi - lo) + lo
    }

    /// An integer in [0, n).
    pub fn below(&mut self, n: i32) -> i32 {
        (self.next() * n as f32) as i32
    }
}
