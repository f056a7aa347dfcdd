//! Checks of single values, with messages that name the key and the fix.
//! The messages are shared by the pre-check (every problem of a file at
//! once) and the build (the checks that need the whole scene), so a value
//! is described the same way by both.

use super::keys::Kind;
use super::spell;
use crate::error::{Error, Result};
use crate::fmt::{short, short3};
use glam::DVec3;

/// Where the values come from (the scenario file, or `command line`).
pub(super) struct Ctx<'a> {
    pub(super) src: &'a str,
}

/// Why `v` is not a finite number > 0, if it is not.
pub(super) fn not_positive(v: f64) -> Option<String> {
    (!(v.is_finite() && v > 0.0)).then(|| {
        format!(
            "must be a finite number > 0, got {}; give a positive value",
            short(v)
        )
    })
}

/// Why `v` is not a finite number ≥ 0, if it is not.
pub(super) fn not_non_negative(v: f64) -> Option<String> {
    (!(v.is_finite() && v >= 0.0)).then(|| {
        format!(
            "must be a finite number >= 0, got {}; give e.g. 0.3 (0 is frictionless)",
            short(v)
        )
    })
}

/// Why `v` is not a Poisson ratio, if it is not.
pub(super) fn not_poisson(v: f64) -> Option<String> {
    (!(v.is_finite() && v > -1.0 && v < 0.5)).then(|| {
        format!(
            "Poisson's ratio must lie in (-1, 0.5), got {}; give e.g. 0.3",
            short(v)
        )
    })
}

/// Why `v` is not three finite numbers, if it is not.
pub(super) fn not_finite3(v: [f64; 3]) -> Option<String> {
    (!v.iter().all(|x| x.is_finite())).then(|| {
        format!(
            "must be three finite numbers, got {}; give [x, y, z] with finite entries",
            short3(v)
        )
    })
}

/// Why a quaternion of norm `n` is refused.
pub(super) fn not_unit_quaternion(n: f64) -> Option<String> {
    (!(n.is_finite() && (n - 1.0).abs() <= 1e-6)).then(|| {
        format!(
            "must be a unit quaternion [w, x, y, z] (norm {}); normalise it",
            short(n)
        )
    })
}

/// A value of an enumerated key (`rotator`, `shape`, `closed_form`,
/// `orientation`) that is not one of its names: the closest name, if one is
/// close, and all.
pub(super) fn unknown_name(kind: Kind, name: &str) -> String {
    let what = match kind {
        Kind::Rotator => "rotator",
        Kind::Shape => "shape",
        Kind::OrientationBodies => "orientation.csv selection",
        _ => "closed form",
    };
    let names = kind.names();
    format!(
        "unknown {what} `{name}`; {}choose one of {}",
        spell::did_you_mean(name, names.iter().copied()),
        names.join(", ")
    )
}

/// An unknown rotator name.
pub(super) fn unknown_rotator(name: &str) -> String {
    unknown_name(Kind::Rotator, name)
}

/// An unknown material name, with the defined ones.
pub(super) fn unknown_material(name: &str, known: &[&str]) -> String {
    format!(
        "unknown material `{name}`; {}defined: {known:?}",
        spell::did_you_mean(name, known.iter().copied())
    )
}

/// How far, relative to the largest moment, a triangle inequality of the
/// principal moments may fail and still be taken as met. A lamina
/// (`I1 + I2 = I3` exactly, in decimal) meets it with equality, which the
/// doubles read from its decimals only approximate: each moment is rounded
/// to half an ulp when read and their sum to half an ulp again, so the sum
/// may fall short by a few ulps (`2e-6 + 3e-6 = 4.999999999999999e-6`).
/// Eight units of rounding (4 ε, about 9e-16) cover that; any triple a body
/// cannot have misses by far more.
pub(super) const INERTIA_TOLERANCE: f64 = 4.0 * f64::EPSILON;

/// Why positive principal moments `[I1, I2, I3]` cannot be those of a
/// rigid body, if they cannot: each is at most the sum of the other two
/// (to [`INERTIA_TOLERANCE`]).
pub(super) fn not_inertia(m: [f64; 3]) -> Option<String> {
    let [a, b, c] = m;
    [
        (b + c, a, "I2 + I3 >= I1"),
        (a + c, b, "I1 + I3 >= I2"),
        (a + b, c, "I1 + I2 >= I3"),
    ]
    .into_iter()
    .find(|&(sum, alone, _)| alone - sum > INERTIA_TOLERANCE * alone)
    .map(|(_, _, text)| {
        format!(
            "{} violates {text}: the principal moments of a rigid body satisfy the triangle inequalities (e.g. a solid box of sides a, b, c has I1 = m (b^2 + c^2)/12 and cyclically; a flat plate has I1 + I2 = I3); check the values and their order",
            short3(m)
        )
    })
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
/// Both a material name and inline values.
pub(super) const MATERIAL_AND_INLINE: &str =
    "give either `material` or inline density/young/poisson, not both";
/// A rigid body in a scene where bodies can touch.
pub(super) const RIGID_CONTACTS: &str = "rigid bodies have no contact geometry, so they are supported only in contact-free scenes (one body, no [box]); remove the [box] and the other bodies, or use fibres";
/// The keys a `rigid` body does not take: its size and material are its
/// `mass` and `inertia`.
pub(super) const NOT_FOR_RIGID: [&str; 6] = [
    "diameter", "length", "material", "density", "young", "poisson",
];

/// A key of [`NOT_FOR_RIGID`] on a rigid body.
pub(super) fn not_for_rigid(key: &str) -> String {
    format!("a rigid body is given by `mass` and `inertia` only; remove `{key}`")
}

/// `mass` or `inertia` on a fibre or a sphere.
pub(super) fn rigid_only(key: &str) -> String {
    format!("`{key}` is for shape = \"rigid\" only; a fibre's or a sphere's mass properties come from its size and density: remove `{key}`, or use shape = \"rigid\"")
}

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

    pub(super) fn non_negative(&self, key: &str, v: f64) -> Result<f64> {
        match not_non_negative(v) {
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
