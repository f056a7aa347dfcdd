//! A fibre's `axis` as an orientation: the minimal rotation that takes body
//! x to the axis, exact for every tilt from 0 to π.

use glam::{DQuat, DVec3};

/// The minimal rotation taking body x to the unit vector `b`.
///
/// Half-angle form: for unit `a`, `b` at angle θ, `q ∝ (1 + a·b, a × b)`
/// (`|a × b| = sin θ`, `1 + a·b = 1 + cos θ`, so `q = (cos θ/2, sin θ/2 n)`
/// after normalising). `a × b` carries a tiny tilt to full relative
/// accuracy, so no tilt is snapped to zero (glam's `from_rotation_arc`
/// returns the identity within ~3e-8 rad of x). Near −x, `1 + a·b` cancels;
/// for a unit `b` it equals `|a × b|² / (1 − a·b)`, which does not. For
/// `a·b ≥ 0` the operations are glam's own, so those axes give the same
/// bits as before. Exactly −x: a half turn about world z.
pub fn rotation_from_x(b: DVec3) -> DQuat {
    let c = DVec3::X.cross(b);
    let dot = DVec3::X.dot(b);
    let w = if dot >= 0.0 {
        1.0 + dot
    } else {
        c.length_squared() / (1.0 - dot)
    };
    if w == 0.0 && c == DVec3::ZERO {
        return DQuat::from_xyzw(0.0, 0.0, 1.0, 0.0);
    }
    // Normalising the half-angle form is its definition, not a correction.
    DQuat::from_xyzw(c.x, c.y, c.z, w).normalize()
}

#[cfg(test)]
mod tests {
    use super::rotation_from_x;
    use glam::{DQuat, DVec3};

    /// Tilts from 1e-12 to π, in several azimuths, against the closed form
    /// `q = (cos θ/2, sin θ/2 n)`, `n = (0, −sin φ, cos φ)`: the half angle's
    /// cosine and sine each to a relative 4 ulp (so a tilt of 1e-12 rad, or
    /// 1e-12 rad short of a half turn, keeps its digits), and `q x q* = b`.
    #[test]
    fn tilts_from_1e_12_to_pi_match_the_closed_form() {
        let pi = std::f64::consts::PI;
        let mut tilts = vec![1e-12, 1e-10, 1e-9, 2.9e-8, 3.1e-8, 1e-6, 1e-3, 0.5, 1.0];
        tilts.extend([
            pi / 2.0,
            2.0,
            3.0,
            pi - 1e-3,
            pi - 1e-6,
            pi - 1e-9,
            pi - 1e-12,
        ]);
        for &theta in &tilts {
            for &phi in &[0.0, 0.3, 2.0, -1.2] {
                let (s, c) = (f64::sin(theta), f64::cos(theta));
                let b = DVec3::new(c, s * f64::cos(phi), s * f64::sin(phi));
                let q = rotation_from_x(b);
                // The exact tilt of the f64 vector b, and its half-angle parts
                // (sin and cos of θ/2 from the components, without cancellation).
                let perp = (b.y * b.y + b.z * b.z).sqrt();
                let (sh, ch) = if b.x >= 0.0 {
                    let tilt = perp.atan2(b.x);
                    ((tilt / 2.0).sin(), (tilt / 2.0).cos())
                } else {
                    // From −x: cos θ/2 = sin((π − θ)/2), no cancellation.
                    let short_of_half_turn = perp.atan2(-b.x);
                    (
                        (short_of_half_turn / 2.0).cos(),
                        (short_of_half_turn / 2.0).sin(),
                    )
                };
                let n = DVec3::new(0.0, -b.z, b.y) / perp;
                let want = DQuat::from_xyzw(sh * n.x, sh * n.y, sh * n.z, ch);
                let rel =
                    |got: f64, want: f64| (got - want).abs() <= 4.0 * f64::EPSILON * want.abs();
                assert!(
                    rel(q.w, want.w),
                    "θ {theta:e} φ {phi}: w {} vs {}",
                    q.w,
                    want.w
                );
                let v = DVec3::new(q.x, q.y, q.z);
                assert!(
                    rel(v.length(), sh),
                    "θ {theta:e} φ {phi}: |v| {} vs {sh}",
                    v.length()
                );
                assert!(
                    (v.normalize() - n).length() < 4.0 * f64::EPSILON,
                    "θ {theta:e}"
                );
                let image = q * DVec3::X;
                assert!(
                    (image - b).length() < 4.0 * f64::EPSILON,
                    "θ {theta:e}: {image}"
                );
            }
        }
    }

    /// glam snaps tilts below ~3e-8 rad to the identity; we do not, and we
    /// agree with glam's bits where it does not snap and the axis is within
    /// 90° of x (every shipped scene's axis).
    #[test]
    fn same_bits_as_glam_where_glam_is_exact() {
        let tiny = DVec3::new(1.0, 1e-9, 0.0).normalize();
        assert_eq!(DQuat::from_rotation_arc(DVec3::X, tiny), DQuat::IDENTITY);
        assert!(rotation_from_x(tiny).z > 4.9e-10);
        for a in [
            DVec3::X,
            DVec3::Z,
            DVec3::new(0.8660254037844387, 0.0, 0.5),
            DVec3::new(0.25881904510252074, 0.0, 0.9659258262890683),
            DVec3::new(0.9999995000000417, 0.0, 0.0009999998333333417),
            DVec3::new(0.9961946980917455, 0.0, 0.08715574274765817),
        ] {
            let b = a.normalize();
            let (ours, glam) = (rotation_from_x(b), DQuat::from_rotation_arc(DVec3::X, b));
            assert_eq!(
                ours.to_array().map(f64::to_bits),
                glam.to_array().map(f64::to_bits)
            );
        }
        let half_turn = rotation_from_x(-DVec3::X);
        assert!((half_turn * DVec3::X + DVec3::X).length() < 1e-15);
    }
}
