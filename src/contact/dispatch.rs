//! Kernels by shape pair: the one place that maps two colliders to the
//! kernel computing their contacts (parry's contact dispatcher, reduced to
//! a match on the pair's kinds, one arm per kind pair). The candidate loop,
//! the start-up overlap check and the frames' contact counts all call
//! [`contacts`]. A new kernel is one file and one arm here (its Hertz law
//! goes in `law/table.rs`; a new shape also gets a [`Collider`] variant and
//! a `shape.rs` kind).

use super::{
    contact_fibre_fibre_remembering, contact_fibre_sphere, contact_fibre_wall,
    contact_sphere_fibre, contact_sphere_wall, sphere_sphere_point, ContactPoint, FibreGeom,
    KernelCounters, PairMemory, SphereGeom, Wall,
};

/// One side of a candidate pair, as the kernels see it.
#[derive(Clone, Copy, Debug)]
pub enum Collider<'a> {
    /// A fibre at its current pose.
    Fibre(FibreGeom),
    /// A sphere at its current position.
    Sphere(SphereGeom),
    /// A wall of the box.
    Wall(&'a Wall),
}

/// The contacts of `a` with `b`, appended to `out`: each point's normal is
/// the direction of the force on `a` (see [`ContactPoint`]). `counters`
/// collects the kernels' diagnostics.
#[inline]
pub fn contacts(
    a: Collider,
    b: Collider,
    out: &mut Vec<ContactPoint>,
    counters: &mut KernelCounters,
) {
    contacts_remembering(a, b, out, counters, None);
}

/// [`contacts`] with the pair's memory of its last end-involved scan and
/// the sum of both bodies' motion bounds since (read by fibre pairs only,
/// `fibre_fibre/coherence.rs`; the other kernels keep no memory). Always
/// inlined: a caller's colliders, made at the pair by value, then go to
/// their kernel without being built.
#[inline(always)]
pub fn contacts_remembering(
    a: Collider,
    b: Collider,
    out: &mut Vec<ContactPoint>,
    counters: &mut KernelCounters,
    memory: Option<(&mut PairMemory, f64)>,
) {
    match (a, b) {
        (Collider::Fibre(a), Collider::Fibre(b)) => {
            contact_fibre_fibre_remembering(&a, &b, out, counters, memory)
        }
        (Collider::Fibre(f), Collider::Sphere(s)) => {
            contact_fibre_sphere(&f, &s, out);
        }
        (Collider::Sphere(s), Collider::Fibre(f)) => {
            contact_sphere_fibre(&s, &f, out);
        }
        (Collider::Sphere(a), Collider::Sphere(b)) => {
            if let Some(p) = sphere_pair(&a, &b) {
                out.push(p);
            }
        }
        (Collider::Fibre(f), Collider::Wall(w)) => contact_fibre_wall(&f, w, out),
        (Collider::Sphere(s), Collider::Wall(w)) => contact_sphere_wall(&s, w, out),
        // The same contacts seen from the wall: forces and the weights'
        // couples (zero for walls) act the other way.
        (Collider::Wall(w), Collider::Fibre(f)) => {
            let from = out.len();
            contact_fibre_wall(&f, w, out);
            reverse(&mut out[from..]);
        }
        (Collider::Wall(w), Collider::Sphere(s)) => {
            let from = out.len();
            contact_sphere_wall(&s, w, out);
            reverse(&mut out[from..]);
        }
        // Walls do not move: they never meet.
        (Collider::Wall(_), Collider::Wall(_)) => {}
    }
}

/// The sphere–sphere arm's point, if the spheres overlap: also called
/// directly by a candidate list known to hold sphere pairs only (the
/// candidate loop's `Spheres`), where the match is decided once for the
/// whole list and the point is taken by value.
#[inline(always)]
pub fn sphere_pair(a: &SphereGeom, b: &SphereGeom) -> Option<ContactPoint> {
    sphere_sphere_point(a, b)
}

/// Contacts seen from the other side: every force and weight couple
/// reversed (Newton's third law).
#[inline]
fn reverse(points: &mut [ContactPoint]) {
    for c in points {
        c.normal = -c.normal;
        c.weight_grad = -c.weight_grad;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    /// Reference: Newton's third law; the wall-first arm must be the
    /// fibre-first one with every force reversed, at the same points.
    #[test]
    fn a_wall_first_pair_is_the_fibre_first_pair_reversed() {
        let f = FibreGeom {
            centre: DVec3::new(0.0, 0.0, 0.004),
            axis: DVec3::new(1.0, 0.0, 0.01).normalize(),
            radius: 0.005,
            half_length: 0.0125,
        };
        let w = Wall {
            normal: DVec3::Z,
            offset: 0.0,
        };
        let mut k = KernelCounters::default();
        let (mut ab, mut ba) = (vec![], vec![]);
        contacts(Collider::Fibre(f), Collider::Wall(&w), &mut ab, &mut k);
        contacts(Collider::Wall(&w), Collider::Fibre(f), &mut ba, &mut k);
        assert_eq!(ab.len(), 2, "both ends below the floor: {ab:?}");
        assert_eq!(ab.len(), ba.len());
        for (x, y) in ab.iter().zip(&ba) {
            assert_eq!(
                (x.point, x.overlap, x.weight),
                (y.point, y.overlap, y.weight)
            );
            assert_eq!(x.normal, -y.normal);
        }
        let mut none = vec![];
        contacts(Collider::Wall(&w), Collider::Wall(&w), &mut none, &mut k);
        assert!(none.is_empty());
    }

    /// Reference: the kernels themselves, called directly. Every kind pair
    /// reaches its own kernel, in either order of the pair (the reversed
    /// one with every force reversed), a sphere's wall-first arm too
    /// (mutants tried: the sphere–fibre arm calling the sphere–sphere
    /// kernel of the fibre's bounding sphere; the wall-first sphere arm
    /// not reversed).
    #[test]
    fn every_kind_pair_reaches_its_kernel_in_either_order() {
        let f = FibreGeom {
            centre: DVec3::new(0.0, 0.0, 0.0),
            axis: DVec3::X,
            radius: 0.005,
            half_length: 0.0125,
        };
        // Over the fibre's side, near its end: its bounding sphere (radius
        // 0.0135) would reach it from much farther.
        let s = SphereGeom {
            centre: DVec3::new(0.01, 0.0, 0.0089),
            radius: 0.004,
        };
        let t = SphereGeom {
            centre: DVec3::new(0.01, 0.0, 0.0165),
            radius: 0.004,
        };
        let w = Wall {
            normal: -DVec3::Z,
            offset: -0.02,
        };
        let mut k = KernelCounters::default();
        let call = |a: Collider, b: Collider, k: &mut KernelCounters| {
            let mut out = vec![];
            contacts(a, b, &mut out, k);
            out
        };
        let (mut sf, mut ss, mut sw) = (vec![], vec![], vec![]);
        crate::contact::contact_sphere_fibre(&s, &f, &mut sf);
        crate::contact::contact_sphere_sphere(&s, &t, &mut ss);
        crate::contact::contact_sphere_wall(&t, &w, &mut sw);
        assert!(sf.len() == 1 && ss.len() == 1 && sw.len() == 1);
        for (ab, ba, direct) in [
            (
                call(Collider::Sphere(s), Collider::Fibre(f), &mut k),
                call(Collider::Fibre(f), Collider::Sphere(s), &mut k),
                &sf,
            ),
            (
                call(Collider::Sphere(s), Collider::Sphere(t), &mut k),
                call(Collider::Sphere(t), Collider::Sphere(s), &mut k),
                &ss,
            ),
            (
                call(Collider::Sphere(t), Collider::Wall(&w), &mut k),
                call(Collider::Wall(&w), Collider::Sphere(t), &mut k),
                &sw,
            ),
        ] {
            assert_eq!(&ab, direct);
            assert_eq!(ba.len(), 1);
            assert_eq!(
                (ba[0].overlap, ba[0].normal),
                (ab[0].overlap, -ab[0].normal)
            );
            assert!(ba[0].point.distance(ab[0].point) < 1e-15);
        }
        // 0.5 mm off the side, inside the fibre's bounding sphere: apart.
        let apart = SphereGeom {
            centre: DVec3::new(0.0, 0.0, 0.0095),
            radius: 0.004,
        };
        assert!(call(Collider::Sphere(apart), Collider::Fibre(f), &mut k).is_empty());
        assert!(call(Collider::Fibre(f), Collider::Sphere(apart), &mut k).is_empty());
    }
}
