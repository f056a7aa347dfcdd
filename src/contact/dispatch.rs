//! Kernels by shape pair: the one place that maps two colliders to the
//! kernel computing their contacts (parry's contact dispatcher, reduced to
//! a match). The contact stage and the start-overlap check both call
//! [`contacts`]. A new kernel is one file and one arm here (its Hertz law
//! goes in `laws.rs`).

use super::{
    contact_fibre_fibre_remembering, contact_fibre_wall, ContactPoint, FibreGeom, KernelCounters,
    PairMemory, Wall,
};

/// One side of a candidate pair, as the kernels see it. Every body of a
/// contact scene is a fibre (scene validation admits no sphere there).
#[derive(Clone, Copy, Debug)]
pub enum Collider<'a> {
    /// A fibre at its current pose.
    Fibre(&'a FibreGeom),
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
/// the sum of both bodies' motion bounds since (fibre pairs only; the
/// contact stage's candidates, `fibre_fibre/coherence.rs`).
#[inline]
pub fn contacts_remembering(
    a: Collider,
    b: Collider,
    out: &mut Vec<ContactPoint>,
    counters: &mut KernelCounters,
    memory: Option<(&mut PairMemory, f64)>,
) {
    match (a, b) {
        (Collider::Fibre(a), Collider::Fibre(b)) => {
            contact_fibre_fibre_remembering(a, b, out, counters, memory)
        }
        (Collider::Fibre(f), Collider::Wall(w)) => contact_fibre_wall(f, w, out),
        (Collider::Wall(w), Collider::Fibre(f)) => {
            // The same contacts seen from the wall: forces and the weights'
            // couples (zero for walls) act the other way.
            let from = out.len();
            contact_fibre_wall(f, w, out);
            for c in &mut out[from..] {
                c.normal = -c.normal;
                c.weight_grad = -c.weight_grad;
            }
        }
        // Walls do not move: they never meet.
        (Collider::Wall(_), Collider::Wall(_)) => {}
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
        contacts(Collider::Fibre(&f), Collider::Wall(&w), &mut ab, &mut k);
        contacts(Collider::Wall(&w), Collider::Fibre(&f), &mut ba, &mut k);
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
}
