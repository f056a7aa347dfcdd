//! The constants of the contact law for every pair of contact kinds, built
//! once per scene: the Hertz law of each pair of kinds, and the scene's
//! restitution damping (one constant for body pairs, one for walls).
//!
//! A Hertz law depends on a body only through its material and its
//! diameter ([`HertzLaw`]), so bodies sharing both are one contact kind: a
//! bed of identical fibres has one kind, one fibre–fibre law and one
//! fibre–wall law. The laws are built by the same functions, from the same
//! numbers in the same order, as a law built for each pair would be:
//! bit-identical.

use crate::body::{Body, Material};
use crate::contact::damping::{damping_constant, Restitution};
use crate::contact::{HertzLaw, Walls};
use std::collections::HashMap;

/// Up to this many kinds the fibre–fibre laws are a dense `kinds²` table
/// (64 KiB at the limit); with more (a polydisperse bed) each touching pair
/// builds its law from its two kinds.
const MAX_TABLE_KINDS: usize = 64;

/// What a law needs of one contact kind.
#[derive(Clone, Copy, Debug)]
struct Kind {
    diameter: f64,
    young: f64,
    poisson: f64,
}

/// The law constants of a contact scene.
#[derive(Clone, Debug)]
pub(crate) struct LawTable {
    /// The damping constants `α(e)` of body pairs and of walls
    /// (`damping.rs`), if the scene declares a restitution.
    alpha: Option<[f64; 2]>,
    /// Contact kind of each body, by storage index.
    kind_of: Vec<u32>,
    /// The kinds, in order of first appearance.
    kinds: Vec<Kind>,
    /// Fibre–wall law of each kind (empty without walls).
    wall: Vec<HertzLaw>,
    /// Fibre–fibre law of kinds `(i, j)` at `i * kinds.len() + j`; empty
    /// above [`MAX_TABLE_KINDS`] kinds.
    pair: Vec<HertzLaw>,
}

impl LawTable {
    /// The laws of `bodies` (made of `materials`) with each other and with
    /// `walls`.
    pub(crate) fn new(bodies: &[Body], materials: &[Material], walls: Option<&Walls>) -> Self {
        let mut index: HashMap<(u32, u64), u32> = HashMap::new();
        let mut kinds = vec![];
        let kind_of = bodies
            .iter()
            .map(|b| {
                let diameter = b.shape.diameter();
                *index
                    .entry((b.material, diameter.to_bits()))
                    .or_insert_with(|| {
                        let m = &materials[b.material as usize];
                        kinds.push(Kind {
                            diameter,
                            young: m.young,
                            poisson: m.poisson,
                        });
                        (kinds.len() - 1) as u32
                    })
            })
            .collect();
        let wall = match walls {
            Some(w) => kinds
                .iter()
                .map(|k| HertzLaw::fibre_wall(k.diameter, k.young, k.poisson, w.young, w.poisson))
                .collect(),
            None => vec![],
        };
        let pair = if kinds.len() <= MAX_TABLE_KINDS {
            kinds
                .iter()
                .flat_map(|&a| kinds.iter().map(move |&b| pair_law(a, b)))
                .collect()
        } else {
            vec![]
        };
        LawTable {
            alpha: None,
            kind_of,
            kinds,
            wall,
            pair,
        }
    }

    /// The table with the restitution damping of `e` (`None`: elastic).
    pub(crate) fn with_restitution(mut self, e: Option<Restitution>) -> Self {
        self.alpha = e.map(|e| [damping_constant(e.fibre), damping_constant(e.wall)]);
        self
    }

    /// Whether the laws depend on the bodies' velocities (they have a
    /// non-conservative part).
    #[inline]
    pub(crate) fn reads_motion(&self) -> bool {
        self.alpha.is_some()
    }

    /// The damping constant of body pairs (0 when elastic).
    #[inline]
    pub(crate) fn alpha_pair(&self) -> f64 {
        self.alpha.map_or(0.0, |a| a[0])
    }

    /// The damping constant of walls (0 when elastic).
    #[inline]
    pub(crate) fn alpha_wall(&self) -> f64 {
        self.alpha.map_or(0.0, |a| a[1])
    }

    /// The Hertz law of body `a` against a wall.
    #[inline]
    pub(crate) fn wall(&self, a: usize) -> &HertzLaw {
        &self.wall[self.kind_of[a] as usize]
    }

    /// The Hertz law of body `a` (as the pair's first) against body `b`:
    /// the table's lookup (its untabled fallback out of line).
    #[inline(always)]
    pub(crate) fn pair(&self, a: usize, b: usize) -> HertzLaw {
        let (ka, kb) = (self.kind_of[a] as usize, self.kind_of[b] as usize);
        match self.pair.get(ka * self.kinds.len() + kb) {
            Some(&law) => law,
            None => self.computed(ka, kb),
        }
    }

    /// The law of kinds `ka` and `kb` when the table was not made.
    #[cold]
    #[inline(never)]
    fn computed(&self, ka: usize, kb: usize) -> HertzLaw {
        pair_law(self.kinds[ka], self.kinds[kb])
    }
}

/// Fibre–fibre law of kinds `a` and `b`, in the argument order of a pair
/// `(a, b)`.
#[inline]
fn pair_law(a: Kind, b: Kind) -> HertzLaw {
    HertzLaw::fibre_fibre(
        a.diameter, a.young, a.poisson, b.diameter, b.young, b.poisson,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::Shape;
    use glam::DVec3;

    fn material(young: f64, poisson: f64) -> Material {
        Material {
            name: String::new(),
            density: 1100.0,
            young,
            poisson,
        }
    }

    fn fibre(diameter: f64, material: u32) -> Body {
        Body::new(
            Shape::Fibre {
                diameter,
                length: 0.025,
            },
            material,
            1100.0,
        )
    }

    const WALLS: Walls = Walls {
        min: DVec3::ZERO,
        max: DVec3::ONE,
        young: 2e11,
        poisson: 0.3,
    };

    /// Reference: the laws built for each pair and each body (as the stage
    /// built them before the table), compared bit for bit.
    fn assert_matches_per_pair(bodies: &[Body], materials: &[Material]) {
        let t = LawTable::new(bodies, materials, Some(&WALLS));
        for (i, a) in bodies.iter().enumerate() {
            let ma = &materials[a.material as usize];
            let wall = HertzLaw::fibre_wall(
                a.shape.diameter(),
                ma.young,
                ma.poisson,
                WALLS.young,
                WALLS.poisson,
            );
            let bits = |l: &HertzLaw| (l.e_star.to_bits(), l.r_star.to_bits());
            assert_eq!(bits(t.wall(i)), bits(&wall), "wall, body {i}");
            for (j, b) in bodies.iter().enumerate() {
                let mb = &materials[b.material as usize];
                let law = HertzLaw::fibre_fibre(
                    a.shape.diameter(),
                    ma.young,
                    ma.poisson,
                    b.shape.diameter(),
                    mb.young,
                    mb.poisson,
                );
                assert_eq!(bits(&t.pair(i, j)), bits(&law), "pair {i} {j}");
            }
        }
    }

    #[test]
    fn a_bed_of_identical_fibres_has_one_law() {
        let materials = [material(5e7, 0.35)];
        let bodies = vec![fibre(0.01, 0); 9];
        let t = LawTable::new(&bodies, &materials, Some(&WALLS));
        assert_eq!((t.kinds.len(), t.wall.len(), t.pair.len()), (1, 1, 1));
        assert_matches_per_pair(&bodies, &materials);
    }

    #[test]
    fn tabled_laws_are_the_per_pair_laws() {
        // Two materials, three diameters (none exact in binary, so 1/R*
        // rounds differently for each pair of them).
        let materials = [material(5e7, 0.35), material(2.1e9, 0.23)];
        let bodies: Vec<Body> = [(0.01, 0), (0.003, 1), (0.01, 1), (0.01, 0), (0.001, 0)]
            .iter()
            .map(|&(d, m)| fibre(d, m))
            .collect();
        let t = LawTable::new(&bodies, &materials, Some(&WALLS));
        assert_eq!(t.kinds.len(), 4);
        assert_eq!(t.pair.len(), 16);
        assert_matches_per_pair(&bodies, &materials);
    }

    #[test]
    fn many_kinds_build_each_law_per_pair() {
        let materials = [material(5e7, 0.35)];
        let bodies: Vec<Body> = (0..MAX_TABLE_KINDS + 5)
            .map(|i| fibre(0.005 + 1e-4 * i as f64, 0))
            .collect();
        let t = LawTable::new(&bodies, &materials, Some(&WALLS));
        assert_eq!(t.kinds.len(), MAX_TABLE_KINDS + 5);
        assert!(t.pair.is_empty());
        assert_matches_per_pair(&bodies, &materials);
    }
}
