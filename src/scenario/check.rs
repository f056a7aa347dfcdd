//! Checks of single values, with messages that name the key and the fix.

use crate::error::{Error, Result};
use glam::DVec3;

/// Where the values come from (the scenario file, or `command line`).
pub(super) struct Ctx<'a> {
    pub(super) src: &'a str,
}

impl Ctx<'_> {
    pub(super) fn err(&self, key: &str, msg: impl Into<String>) -> Error {
        Error::bad(self.src, key, msg)
    }

    pub(super) fn positive(&self, key: &str, v: f64) -> Result<f64> {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(self.err(
                key,
                format!("must be a finite number > 0, got {v}; give a positive value"),
            ))
        }
    }

    pub(super) fn finite3(&self, key: &str, v: [f64; 3]) -> Result<DVec3> {
        if v.iter().all(|x| x.is_finite()) {
            Ok(DVec3::from_array(v))
        } else {
            Err(self.err(
                key,
                format!(
                    "must be three finite numbers, got {v:?}; give [x, y, z] with finite entries"
                ),
            ))
        }
    }

    pub(super) fn poisson(&self, key: &str, v: f64) -> Result<f64> {
        if v.is_finite() && v > -1.0 && v < 0.5 {
            Ok(v)
        } else {
            Err(self.err(
                key,
                format!("Poisson's ratio must lie in (-1, 0.5), got {v}; give e.g. 0.3"),
            ))
        }
    }
}
