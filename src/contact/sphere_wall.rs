//! Sphere–wall contact: exact, analytic, one contact.
//!
//! For the wall `n·x ≥ offset` (`n` into the box) the sphere's deepest
//! point is `c − r n`, so `δ = offset + r − n·c`; the force on the sphere
//! is along `n = −∂δ/∂c`, at the point midway between the sphere's deepest
//! point and the plane, `c − (r − δ/2) n`. Smooth everywhere.

use super::{ContactPoint, SphereGeom, Wall};
use glam::DVec3;

/// Contact of sphere `s` with wall `w`, appended to `out` if they overlap:
/// one point, weight 1, normal = the wall's (the force on the sphere).
pub fn contact_sphere_wall(s: &SphereGeom, w: &Wall, out: &mut Vec<ContactPoint>) {
    let n = w.normal;
    let overlap = w.offset + s.radius - n.dot(s.centre);
    if overlap > 0.0 {
        out.push(ContactPoint {
            point: s.centre - (s.radius - 0.5 * overlap) * n,
            normal: n,
            overlap,
            weight: 1.0,
            weight_grad: DVec3::ZERO,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::{box_walls, HertzLaw, Walls};

    fn the_box() -> Vec<Wall> {
        box_walls(&Walls {
            min: DVec3::new(-0.1, 0.0, 0.2),
            max: DVec3::new(0.3, 0.5, 0.7),
            young: 1e9,
            poisson: 0.3,
        })
    }

    /// Reference: the closed form for each wall of a box: a sphere whose
    /// centre is `r − δ0` inside the face along the inward normal has depth
    /// `δ0`, the force along the inward normal, and its point `δ0/2` outside
    /// the face, straight below the centre (mutant tried: `+ 0.5 * overlap`
    /// in the point).
    #[test]
    fn a_sphere_in_each_wall_matches_the_closed_form() {
        let (lo, hi) = (DVec3::new(-0.1, 0.0, 0.2), DVec3::new(0.3, 0.5, 0.7));
        let mid = 0.5 * (lo + hi);
        let (r, d0) = (0.004, 3e-6);
        for (i, w) in the_box().iter().enumerate() {
            let k = i / 2;
            let (face, inward) = if i % 2 == 0 {
                (lo[k], 1.0)
            } else {
                (hi[k], -1.0)
            };
            let mut centre = mid + DVec3::new(0.01, -0.02, 0.03);
            centre[k] = face + inward * (r - d0);
            let mut point = centre;
            point[k] = face - inward * 0.5 * d0;
            let mut out = vec![];
            contact_sphere_wall(&SphereGeom { centre, radius: r }, w, &mut out);
            assert_eq!(out.len(), 1, "wall {i}");
            let c = out[0];
            assert!((c.overlap - d0).abs() < 1e-16, "wall {i}: {}", c.overlap);
            assert_eq!(c.normal, inward * DVec3::AXES[k]);
            assert!(
                (c.point - point).length() < 1e-16,
                "wall {i}: {:?}",
                c.point
            );
            // Apart (and touching): no contact.
            for gap in [0.0, 1e-6] {
                let mut apart = centre;
                apart[k] = face + inward * (r + gap);
                let mut none = vec![];
                contact_sphere_wall(
                    &SphereGeom {
                        centre: apart,
                        radius: r,
                    },
                    w,
                    &mut none,
                );
                assert!(none.is_empty(), "wall {i}, gap {gap}");
            }
        }
    }

    /// Reference: the force is minus the gradient of the Hertz potential in
    /// the sphere's centre (central differences), tilted wall (mutant
    /// tried: normal `−n`).
    #[test]
    fn the_force_is_the_gradient_of_the_potential() {
        let law = HertzLaw::sphere_wall(0.01, 5e7, 0.23, 1e9, 0.3);
        let w = Wall {
            normal: DVec3::new(0.3, 1.0, -0.2).normalize(),
            offset: 0.01,
        };
        let s = SphereGeom {
            centre: w.normal * (w.offset + 0.005 - 2e-5) + DVec3::new(0.2, -0.06, 0.0),
            radius: 0.005,
        };
        let u = |c: DVec3| {
            let mut out = vec![];
            contact_sphere_wall(
                &SphereGeom {
                    centre: c,
                    radius: s.radius,
                },
                &w,
                &mut out,
            );
            out.iter().map(|p| law.energy(p.overlap)).sum::<f64>()
        };
        let mut out = vec![];
        contact_sphere_wall(&s, &w, &mut out);
        let force = law.force(out[0].overlap) * out[0].normal;
        let eps = 1e-9;
        for k in 0..3 {
            let e = eps * DVec3::AXES[k];
            let fd = -(u(s.centre + e) - u(s.centre - e)) / (2.0 * eps);
            assert!(
                (fd - force[k]).abs() < 1e-6 * force.length(),
                "{k}: {fd} vs {force}"
            );
        }
    }
}
