//! Sphere–sphere contact: exact, analytic, one contact.
//!
//! `δ = r_A + r_B − d`, `d = |c_A − c_B|`; the force on A acts along
//! `n = (c_A − c_B)/d = −∂δ/∂c_A` at the point midway between the two
//! surfaces on the line of centres, `c_B + (r_B − δ/2) n`. The depth is
//! smooth except where the centres coincide (a cone point of `d`): there the
//! normal is `+x` (any unit vector is an element of the subgradient; parry
//! makes the same choice), measure zero.

use super::{ContactPoint, SphereGeom};
use glam::DVec3;

/// Contact of sphere `a` with sphere `b`, appended to `out` if they overlap:
/// one point, weight 1, normal = the direction of the force on `a`.
#[inline]
pub fn contact_sphere_sphere(a: &SphereGeom, b: &SphereGeom, out: &mut Vec<ContactPoint>) {
    if let Some(p) = sphere_sphere_point(a, b) {
        out.push(p);
    }
}

/// The contact point of sphere `a` with sphere `b`, if they overlap (the
/// one point [`contact_sphere_sphere`] appends): returned by value, so a
/// loop over sphere pairs keeps it out of the kernels' buffer.
#[inline(always)]
pub fn sphere_sphere_point(a: &SphereGeom, b: &SphereGeom) -> Option<ContactPoint> {
    let reach = a.radius + b.radius;
    let w = a.centre - b.centre;
    let d2 = w.length_squared();
    if d2 >= reach * reach {
        return None;
    }
    let d = d2.sqrt();
    let normal = if d > 0.0 { w / d } else { DVec3::X };
    let overlap = reach - d;
    Some(ContactPoint {
        point: b.centre + (b.radius - 0.5 * overlap) * normal,
        normal,
        overlap,
        weight: 1.0,
        weight_grad: DVec3::ZERO,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::HertzLaw;

    fn sphere(centre: DVec3, radius: f64) -> SphereGeom {
        SphereGeom { centre, radius }
    }

    fn contacts(a: &SphereGeom, b: &SphereGeom) -> Vec<ContactPoint> {
        let mut out = vec![];
        contact_sphere_sphere(a, b, &mut out);
        out
    }

    /// Reference: the closed form of two overlapping spheres placed at
    /// centre distance `r_A + r_B − δ0` along `u`: depth `δ0`, force on A
    /// along `u`, point midway between A's surface point `c_A − r_A u` and
    /// B's `c_B + r_B u`. Unequal radii, so that a point placed from the
    /// wrong sphere is caught (mutant tried: `a.radius` for `b.radius` in
    /// the point).
    #[test]
    fn overlapping_spheres_match_the_closed_form() {
        let b = sphere(DVec3::new(0.1, -0.2, 0.3), 0.004);
        for (u, ra, d0) in [
            (DVec3::X, 0.006, 1e-5),
            (DVec3::new(1.0, -2.0, 0.5).normalize(), 0.002, 3e-4),
            (DVec3::new(-0.3, 0.1, -1.0).normalize(), 0.01, 2e-6),
        ] {
            let a = sphere(b.centre + (ra + b.radius - d0) * u, ra);
            let c = contacts(&a, &b);
            assert_eq!(c.len(), 1);
            let c = c[0];
            let mid = 0.5 * ((a.centre - ra * u) + (b.centre + b.radius * u));
            assert!((c.overlap - d0).abs() < 1e-15, "{} vs {d0}", c.overlap);
            assert!((c.normal - u).length() < 1e-13, "{:?}", c.normal);
            assert!((c.point - mid).length() < 1e-15, "{:?} vs {mid:?}", c.point);
            assert_eq!((c.weight, c.weight_grad), (1.0, DVec3::ZERO));
        }
    }

    /// Reference: the definition of contact; spheres apart or just
    /// touching (`d = r_A + r_B`) have none (mutant tried: `>` for `>=` in
    /// the reject).
    #[test]
    fn apart_or_touching_spheres_have_no_contact() {
        let b = sphere(DVec3::ZERO, 0.5);
        for gap in [0.0, 1e-9, 0.3] {
            let a = sphere(DVec3::new(0.0, 0.0, 1.25 + gap), 0.75);
            assert!(contacts(&a, &b).is_empty(), "gap {gap}");
        }
    }

    /// Reference: the force on A is minus the gradient of the Hertz
    /// potential `U(δ)` in A's centre (central differences), and on B the
    /// opposite (mutant tried: normal `b − a`).
    #[test]
    fn the_force_is_the_gradient_of_the_potential() {
        let law = HertzLaw::sphere_sphere(0.012, 5e7, 0.23, 0.008, 2e8, 0.3);
        let b = sphere(DVec3::new(0.01, 0.02, -0.03), 0.004);
        let a = sphere(b.centre + DVec3::new(0.003, -0.0075, 0.002), 0.006);
        let u = |a: &SphereGeom, b: &SphereGeom| {
            contacts(a, b)
                .iter()
                .map(|c| law.energy(c.overlap))
                .sum::<f64>()
        };
        let c = contacts(&a, &b)[0];
        let force = law.force(c.overlap) * c.normal;
        let eps = 1e-9;
        for k in 0..3 {
            let e = eps * DVec3::AXES[k];
            let moved = |s: &SphereGeom, sign: f64| sphere(s.centre + sign * e, s.radius);
            let fd_a = -(u(&moved(&a, 1.0), &b) - u(&moved(&a, -1.0), &b)) / (2.0 * eps);
            let fd_b = -(u(&a, &moved(&b, 1.0)) - u(&a, &moved(&b, -1.0))) / (2.0 * eps);
            assert!(
                (fd_a - force[k]).abs() < 1e-6 * force.length(),
                "{k}: {fd_a} vs {force}"
            );
            assert!(
                (fd_b + force[k]).abs() < 1e-6 * force.length(),
                "{k}: {fd_b} vs {force}"
            );
        }
    }

    /// Reference: Newton's third law; B first gives the same point and depth
    /// with the force reversed. Coincident centres (the cone point) give a
    /// unit normal and the full depth `r_A + r_B`, no NaN. (Mutant tried:
    /// the normal `b − a`, which moves the point.)
    #[test]
    fn swapped_spheres_reverse_the_force_and_coincident_centres_are_finite() {
        let a = sphere(DVec3::new(0.001, 0.002, 0.003), 0.006);
        let b = sphere(DVec3::new(0.004, -0.002, 0.007), 0.003);
        let (ab, ba) = (contacts(&a, &b)[0], contacts(&b, &a)[0]);
        assert!((ab.point - ba.point).length() < 1e-15);
        assert_eq!(ab.overlap, ba.overlap);
        assert_eq!(ab.normal, -ba.normal);
        let c = contacts(&a, &sphere(a.centre, 0.002))[0];
        assert_eq!((c.overlap, c.normal), (0.008, DVec3::X));
        assert!(c.point.is_finite());
    }
}
