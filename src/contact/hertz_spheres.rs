//! The Hertz laws of the sphere contacts: one law per pair of contact kinds,
//! with the conventions of the fibre laws ([`HertzLaw`]), so that every law
//! in a mixed bed is a sphere-on-sphere or sphere-on-plane Hertz law.
//!
//! - Sphere–sphere: `1/R* = 2/D1 + 2/D2`, exact Hertz.
//! - Sphere–wall: `R* = D/2`, exact Hertz (sphere on a half-space).
//! - Sphere–fibre: `1/R* = 2/D_s + 2/D_f`, the fibre–fibre convention (the
//!   fibre's side treated as a sphere of the fibre's radius), the same law
//!   on the side, the end faces and the rims. A per-feature law would make
//!   the potential jump where the feature changes at a nonzero depth; one
//!   law keeps it continuous. Against the true Hertz geometry it is exact
//!   nowhere: on a face (a sphere on a plane, `R* = R_s`) it is softer by
//!   `√(R_f/(R_s + R_f))` (0.71 for equal radii); on the side (crossed
//!   sphere and cylinder, equivalent radius `√(R_s · R_sR_f/(R_s + R_f))`)
//!   by `(R_f/(R_s + R_f))^{1/4}` (0.84), ignoring the ellipticity of the
//!   contact; on a rim (an edge) Hertz does not apply at all. Details:
//!   docs/contacts.md, "Sphere contacts".
//!
//! Each is the fibre law of the same formula, called with the same numbers
//! in the same order: the formulas are written once, in `hertz.rs`.

use super::HertzLaw;

impl HertzLaw {
    /// Sphere–sphere: `1/R* = 2/D1 + 2/D2`, `1/E* = (1−ν1²)/E1 + (1−ν2²)/E2`
    /// (Hertz's law of two spheres, exact).
    pub fn sphere_sphere(d1: f64, e1: f64, nu1: f64, d2: f64, e2: f64, nu2: f64) -> Self {
        Self::fibre_fibre(d1, e1, nu1, d2, e2, nu2)
    }

    /// Sphere–wall: `R* = D/2` (Hertz's law of a sphere on a half-space,
    /// exact).
    pub fn sphere_wall(d: f64, e: f64, nu: f64, e_wall: f64, nu_wall: f64) -> Self {
        Self::fibre_wall(d, e, nu, e_wall, nu_wall)
    }

    /// Sphere (diameter `d_sphere`) – fibre (diameter `d_fibre`):
    /// `1/R* = 2/D_s + 2/D_f` on every feature (side, face, rim), the
    /// fibre–fibre convention; its limits are in the module documentation.
    pub fn sphere_fibre(
        d_sphere: f64,
        e_sphere: f64,
        nu_sphere: f64,
        d_fibre: f64,
        e_fibre: f64,
        nu_fibre: f64,
    ) -> Self {
        Self::fibre_fibre(d_sphere, e_sphere, nu_sphere, d_fibre, e_fibre, nu_fibre)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `1/E*` of Hertz theory, written out: `(1−ν1²)/E1 + (1−ν2²)/E2`.
    fn inv_e_star(e1: f64, nu1: f64, e2: f64, nu2: f64) -> f64 {
        (1.0 - nu1 * nu1) / e1 + (1.0 - nu2 * nu2) / e2
    }

    /// Reference: Hertz's closed forms (Johnson, Contact Mechanics, §4.2):
    /// two spheres `R* = R1 R2/(R1 + R2)`, a sphere on a plane `R* = R`;
    /// the sphere–fibre convention `R* = R_s R_f/(R_s + R_f)`. Different
    /// materials on each side, so that a swapped argument is caught
    /// (mutants tried: `sphere_fibre` with `R* = D_s/2`, the face's true law;
    /// the two materials swapped).
    #[test]
    fn the_laws_have_the_closed_form_constants() {
        let (ds, es, nus) = (0.012, 5e7, 0.23);
        let (d2, e2, nu2) = (0.008, 2e9, 0.35);
        let (rs, r2) = (ds / 2.0, d2 / 2.0);
        let rel = |x: f64, y: f64| (x - y).abs() <= 1e-15 * y.abs();
        for law in [
            HertzLaw::sphere_sphere(ds, es, nus, d2, e2, nu2),
            HertzLaw::sphere_fibre(ds, es, nus, d2, e2, nu2),
        ] {
            assert!(rel(law.r_star, rs * r2 / (rs + r2)), "{law:?}");
            assert!(
                rel(1.0 / law.e_star, inv_e_star(es, nus, e2, nu2)),
                "{law:?}"
            );
        }
        let wall = HertzLaw::sphere_wall(ds, es, nus, e2, nu2);
        assert!(rel(wall.r_star, rs), "{wall:?}");
        assert!(
            rel(1.0 / wall.e_star, inv_e_star(es, nus, e2, nu2)),
            "{wall:?}"
        );
    }

    /// Reference: the convention's promise; a sphere and a fibre of the
    /// same diameter and material have the fibre–fibre law of that pair,
    /// bit for bit, in either order of the kinds (mutant tried: the face's
    /// law, as above).
    #[test]
    fn a_sphere_fibre_law_is_the_fibre_fibre_law_of_the_same_diameters() {
        let (d1, e1, nu1, d2, e2, nu2) = (0.01, 5e7, 0.23, 0.004, 1e8, 0.4);
        let sf = HertzLaw::sphere_fibre(d1, e1, nu1, d2, e2, nu2);
        assert_eq!(sf, HertzLaw::fibre_fibre(d1, e1, nu1, d2, e2, nu2));
        assert_eq!(sf, HertzLaw::sphere_fibre(d2, e2, nu2, d1, e1, nu1));
    }
}
