//! An orthographic camera (ParaView's parallel projection): a view
//! direction, an up vector, a zoom, fitted to what must be seen.

use crate::error::{Error, Result};
use glam::DVec3;

/// Where the camera looks from and how it fills the picture.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Unit vector from the scene toward the camera.
    pub toward: DVec3,
    /// Screen right, world.
    pub right: DVec3,
    /// Screen up, world.
    pub up: DVec3,
    /// World point at the centre of the drawing area.
    pub centre: DVec3,
    /// Pixels per metre.
    pub scale: f64,
    /// Pixel at the centre of the drawing area.
    pub origin: (f64, f64),
}

/// The view direction of a `--view` value (toward the camera).
pub fn view_direction(s: &str) -> Result<DVec3> {
    let named = match s {
        "front" => Some(DVec3::NEG_Y),
        "back" => Some(DVec3::Y),
        "left" => Some(DVec3::NEG_X),
        "right" => Some(DVec3::X),
        "top" => Some(DVec3::Z),
        "iso" => Some(DVec3::new(0.55, -1.0, 0.45)),
        _ => None,
    };
    let bad = |why: &str| {
        Error::bad(
            "command line",
            "--view",
            format!("{why}; give front, back, left, right, top, iso or X,Y,Z (toward the camera), e.g. 1,-2,1"),
        )
    };
    let v = match named {
        Some(v) => v,
        None => {
            let c: Vec<f64> = s
                .split(',')
                .map(|x| x.trim().parse::<f64>())
                .collect::<std::result::Result<_, _>>()
                .map_err(|_| bad(&format!("`{s}` is neither a view name nor three numbers")))?;
            if c.len() != 3 || !c.iter().all(|x| x.is_finite()) {
                return Err(bad(&format!("`{s}` is not three finite numbers")));
            }
            DVec3::new(c[0], c[1], c[2])
        }
    };
    if v.length() == 0.0 {
        return Err(bad("the direction is zero"));
    }
    Ok(v.normalize())
}

impl Camera {
    /// Look along `-toward` at the points `bounds` (lower, upper corner),
    /// fitting them into `area` (x, y, width, height in pixels), times `zoom`.
    pub fn fit(toward: DVec3, bounds: (DVec3, DVec3), area: [f64; 4], zoom: f64) -> Self {
        // World z is up on the screen unless we look along it.
        let up_hint = if toward.cross(DVec3::Z).length() < 1e-6 {
            DVec3::Y
        } else {
            DVec3::Z
        };
        let right = up_hint.cross(toward).normalize();
        let up = toward.cross(right);
        let (lo, hi) = bounds;
        let centre = 0.5 * (lo + hi);
        let (mut w, mut h) = (0.0f64, 0.0f64);
        for k in 0..8 {
            let p = DVec3::new(
                if k & 1 == 0 { lo.x } else { hi.x },
                if k & 2 == 0 { lo.y } else { hi.y },
                if k & 4 == 0 { lo.z } else { hi.z },
            ) - centre;
            w = w.max(2.0 * p.dot(right).abs());
            h = h.max(2.0 * p.dot(up).abs());
        }
        let [x, y, aw, ah] = area;
        let fit = (aw / w.max(1e-300)).min(ah / h.max(1e-300));
        Camera {
            toward,
            right,
            up,
            centre,
            scale: 0.95 * fit * zoom,
            origin: (x + 0.5 * aw, y + 0.5 * ah),
        }
    }

    /// Pixel coordinates of `p` and its depth (larger is nearer the camera).
    #[inline]
    pub fn project(&self, p: DVec3) -> (f64, f64, f64) {
        let d = p - self.centre;
        (
            self.origin.0 + self.scale * d.dot(self.right),
            self.origin.1 - self.scale * d.dot(self.up),
            d.dot(self.toward),
        )
    }
}
