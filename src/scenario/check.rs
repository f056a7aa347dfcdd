//! Checks of single values, with messages that name the key and the fix.
//! The messages are shared by the pre-check (every problem of a file at
//! once) and the build (the checks that need the whole scene), so a value
//! is described the same way by both.

use crate::error::{Error, Result};
use crate::integrate::rotate::RotatorKind;
use glam::DVec3;

/// Where the values come from (the scenario file, or `command line`).
pub(super) struct Ctx<'a> {
    pub(super) src: &'a str,
}

/// Why `v` is not a finite number > 0, if it is not.
pub(super) fn not_positive(v: f64) -> Option<String> {
    (!(v.is_finite() && v > 0.0))
        .then(|| format!("must be a finite number > 0, got {v}; give a positive value"))
}

/// Why `v` is not a Poisson ratio, if it is not.
pub(super) fn not_poisson(v: f64) -> Option<String> {
    (!(v.is_finite() && v > -1.0 && v < 0.5))
        .then(|| format!("Poisson's ratio must lie in (-1, 0.5), got {v}; give e.g. 0.3"))
}

/// Why `v` is not three finite numbers, if it is not.
pub(super) fn not_finite3(v: [f64; 3]) -> Option<String> {
    (!v.iter().all(|x| x.is_finite())).then(|| {
        format!("must be three finite numbers, got {v:?}; give [x, y, z] with finite entries")
    })
}

/// Why a quaternion of norm `n` is refused.
pub(super) fn not_unit_quaternion(n: f64) -> Option<String> {
    (!(n.is_finite() && (n - 1.0).abs() <= 1e-6))
        .then(|| format!("must be a unit quaternion [w, x, y, z] (norm {n}); normalise it"))
}

/// An unknown rotator name.
pub(super) fn unknown_rotator(name: &str) -> String {
    let names: Vec<&str> = RotatorKind::SELECTABLE.iter().map(|k| k.name()).collect();
    format!(
        "unknown rotator `{name}`; choose one of {}",
        names.join(", ")
    )
}

/// An unknown material name, with the defined ones.
pub(super) fn unknown_material(name: &str, known: &[&str]) -> String {
    format!("unknown material `{name}`; defined: {known:?}")
}

/// An axis of length zero.
pub(super) const ZERO_AXIS: &str = "the axis direction must be non-zero";
/// `every = 0`.
pub(super) const EVERY_ZERO: &str = "must be >= 1 (one output row per `every` steps)";
/// A scene without `[[body]]`.
pub(super) const NO_BODIES: &str =
    "the scene has no bodies; add at least one [[body]] table or a [bodies] file";
/// A sphere with a length.
pub(super) const SPHERE_LENGTH: &str =
    "a sphere has no `length`; remove it or use shape = \"fibre\"";
/// A sphere that can touch something.
pub(super) const SPHERE_CONTACTS: &str =
    "spheres are supported only in contact-free scenes (one body, no [box]); use fibres";
/// Both a material name and inline values.
pub(super) const MATERIAL_AND_INLINE: &str =
    "give either `material` or inline density/young/poisson, not both";
/// Both an axis and a quaternion.
pub(super) const AXIS_AND_QUATERNION: &str = "give either `axis` or `quaternion`, not both";

impl Ctx<'_> {
    pub(super) fn err(&self, key: &str, msg: impl Into<String>) -> Error {
        Error::bad(self.src, key, msg)
    }

    pub(super) fn positive(&self, key: &str, v: f64) -> Result<f64> {
        match not_positive(v) {
            None => Ok(v),
            Some(m) => Err(self.err(key, m)),
        }
    }

    pub(super) fn finite3(&self, key: &str, v: [f64; 3]) -> Result<DVec3> {
        match not_finite3(v) {
            None => Ok(DVec3::from_array(v)),
            Some(m) => Err(self.err(key, m)),
        }
    }

    pub(super) fn poisson(&self, key: &str, v: f64) -> Result<f64> {
        match not_poisson(v) {
            None => Ok(v),
            Some(m) => Err(self.err(key, m)),
        }
    }
}
