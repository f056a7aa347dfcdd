//! A deterministic stream of uniforms for the kernels' randomized tests
//! (xorshift64*: reproducible scenes without a dependency).

use crate::contact::FibreGeom;
use glam::DVec3;

pub(super) struct Uniform(pub(super) u64);

impl Uniform {
    /// The next uniform in [0, 1).
    pub(super) fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A vector with components uniform in [−scale/2, scale/2).
    pub(super) fn vec(&mut self, scale: f64) -> DVec3 {
        scale * DVec3::new(self.next() - 0.5, self.next() - 0.5, self.next() - 0.5)
    }

    /// Test case 1's fibre (D = 0.01 m, L = 0.025 m) near the origin,
    /// centre within `spread`, axis random.
    pub(super) fn fibre(&mut self, spread: f64) -> FibreGeom {
        FibreGeom {
            centre: self.vec(spread),
            axis: self.vec(1.0).normalize(),
            radius: 0.005,
            half_length: 0.0125,
        }
    }
}
