//! A sphere as the kernels see it.

use glam::DVec3;

/// A solid sphere: centre and radius. A sphere's contacts do not depend on
/// its orientation (every contact normal passes through its centre), so the
/// kernels need no more.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SphereGeom {
    /// Centre (world).
    pub centre: DVec3,
    /// D/2.
    pub radius: f64,
}
