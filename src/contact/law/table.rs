//! The constants of the contact law for every pair of contact kinds, built
//! once per scene: the Hertz law of each pair of kinds, and the scene's
//! restitution damping (one constant for body pairs, one for walls).
//!
//! A Hertz law depends on a body only through its collider kind (fibre,
//! sphere), its material and its diameter ([`HertzLaw`]), so bodies
//! sharing the three are one contact kind: a bed of identical fibres has
//! one kind, one fibre–fibre law and one fibre–wall law. The law of a
//! pair of kinds is the one of its collider kinds (`HertzLaw::fibre_fibre`,
//! `sphere_sphere`, `sphere_fibre`; `fibre_wall`, `sphere_wall`). The laws are built by the same functions, from the same
//! numbers in the same order, as a law built for each pair would be:
//! bit-identical.

use crate::body::{Bodies, Body, Material};
use crate::contact::damping::{damping_constant, Restitution};
use crate::contact::tangential::{Friction, Tangential};
use crate::contact::{ColliderKind, HertzLaw, Walls};
use std::collections::HashMap;

/// Up to this many kinds the body–body laws are a dense `kinds²` table
/// (64 KiB at the limit); with more (a polydisperse bed) each touching pair
/// builds its law from its two kinds.
const MAX_TABLE_KINDS: usize = 64;

/// What a law needs of one contact kind.
#[derive(Clone, Copy, Debug)]
struct Kind {
    shape: ColliderKind,
    diameter: f64,
    young: f64,
    poisson: f64,
    /// The material's own Coulomb coefficient, if it has one.
    friction: Option<f64>,
}

/// The law constants of a contact scene.
#[derive(Clone, Debug)]
pub(crate) struct LawTable {
    /// The damping constants `α(e)` of body pairs and of walls
    /// (`damping.rs`), if the scene declares a restitution.
    alpha: Option<[f64; 2]>,
    /// Contact kind of body `i` at `kind_of[i & mask]`: one entry (0) for
    /// all bodies when there is one kind (`mask` 0: a bed of identical
    /// fibres keeps nothing per body), else one per body (`mask` all ones).
    kind_of: Vec<u32>,
    mask: usize,
    /// The kinds, in order of first appearance.
    kinds: Vec<Kind>,
    /// Body–wall law of each kind (empty without walls).
    wall: Vec<HertzLaw>,
    /// Body–body law of kinds `(i, j)` at `i * kinds.len() + j`; empty
    /// above [`MAX_TABLE_KINDS`] kinds.
    pair: Vec<HertzLaw>,
    /// The walls' `(E, ν)`, if the scene has walls.
    wall_material: Option<(f64, f64)>,
    /// The scene's Coulomb coefficients and the time step its springs
    /// advance by, if it declares friction.
    friction: Option<(Friction, f64)>,
    /// The tangential laws (frictional scenes; `None` where μ = 0):
    /// body–wall of each kind (empty without walls), body–body of kinds
    /// `(i, j)` as [`LawTable::pair`] (empty above [`MAX_TABLE_KINDS`]
    /// kinds).
    tangential_wall: Vec<Option<TangentialLaw>>,
    tangential_pair: Vec<Option<TangentialLaw>>,
}

/// A frictional contact kind pair's tangential law as a contact point's
/// step reads it: the law, the ratio `√(G*/E*)` of its damping `η_t = 2
/// η_n √(G*/E*)` (`tangential.rs`) with `E*` the pair's Hertz law's, and
/// the time step its springs advance by. The ratio is a constant of the
/// kind pair: tabled, it is the same expression of the same numbers as
/// worked out per point, so the same bits, for one square root and one
/// division fewer per point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct TangentialLaw {
    pub law: Tangential,
    pub root_g_over_e: f64,
    pub dt: f64,
}

impl TangentialLaw {
    /// The law `t` of a contact whose Hertz law is `hertz`, its springs
    /// advanced by `dt`; `None` when `t` is frictionless (μ = 0).
    fn of(t: Tangential, hertz: &HertzLaw, dt: f64) -> Option<Self> {
        (t.mu > 0.0).then(|| TangentialLaw {
            law: t,
            root_g_over_e: (t.g_star / hertz.e_star).sqrt(),
            dt,
        })
    }
}

impl LawTable {
    /// The laws of `bodies` (made of `materials`) with each other and with
    /// `walls`.
    pub(crate) fn new(bodies: &Bodies, materials: &[Material], walls: Option<&Walls>) -> Self {
        let mut index: HashMap<(ColliderKind, u32, u64), u32> = HashMap::new();
        let mut kinds = vec![];
        // The contact kind of each distinct body value (`Bodies::kinds`, in
        // order of first appearance, so the contact kinds are too).
        let of_value: Vec<u32> = (bodies.kinds().iter())
            .map(|b| {
                let diameter = b.shape.diameter();
                let shape = ColliderKind::of(&b.shape)
                    .expect("scene validation admits no rigid body in contact scenes");
                *index
                    .entry((shape, b.material, diameter.to_bits()))
                    .or_insert_with(|| {
                        let m = &materials[b.material as usize];
                        kinds.push(Kind {
                            shape,
                            diameter,
                            young: m.young,
                            poisson: m.poisson,
                            friction: m.friction,
                        });
                        (kinds.len() - 1) as u32
                    })
            })
            .collect();
        let (kind_of, mask) = match kinds.len() {
            0 | 1 => (vec![0], 0),
            _ => (
                (0..bodies.len())
                    .map(|i| of_value[bodies.kind(i)])
                    .collect(),
                usize::MAX,
            ),
        };
        let wall = match walls {
            Some(w) => kinds.iter().map(|&k| wall_law(k, w)).collect(),
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
            mask,
            kinds,
            wall,
            pair,
            wall_material: walls.map(|w| (w.young, w.poisson)),
            friction: None,
            tangential_wall: vec![],
            tangential_pair: vec![],
        }
    }

    /// The table with the restitution damping of `e` (`None`: elastic).
    pub(crate) fn with_restitution(mut self, e: Option<Restitution>) -> Self {
        self.alpha = e.map(|e| [damping_constant(e.fibre), damping_constant(e.wall)]);
        self
    }

    /// The table with the Coulomb friction `f` (`None`: frictionless; the
    /// defaults of materials without their own, with the pair rule of
    /// [`Friction::pair`]), its springs advanced by `dt` per computation.
    pub(crate) fn with_friction(mut self, f: Option<Friction>, dt: f64) -> Self {
        self.friction = f.map(|f| (f, dt));
        self.tangential_wall = match (f, self.wall_material) {
            (Some(f), Some((young, poisson))) => (self.kinds.iter().zip(&self.wall))
                .map(|(k, hertz)| {
                    let mu = f.against_wall(k.friction);
                    let t = Tangential::new(mu, k.young, k.poisson, young, poisson);
                    TangentialLaw::of(t, hertz, dt)
                })
                .collect(),
            _ => vec![],
        };
        self.tangential_pair = match f {
            Some(f) if self.kinds.len() <= MAX_TABLE_KINDS => {
                let n = self.kinds.len();
                (0..n * n)
                    .map(|i| {
                        let (a, b) = (&self.kinds[i / n], &self.kinds[i % n]);
                        let mu = f.pair(a.friction, b.friction);
                        let t = Tangential::new(mu, a.young, a.poisson, b.young, b.poisson);
                        TangentialLaw::of(t, &self.pair[i], dt)
                    })
                    .collect()
            }
            _ => vec![],
        };
        self
    }

    /// The contact kind of body `a`.
    #[inline(always)]
    fn kind(&self, a: usize) -> usize {
        self.kind_of[a & self.mask] as usize
    }

    /// Whether the laws depend on the bodies' velocities (they have a
    /// non-conservative part).
    #[inline]
    pub(crate) fn reads_motion(&self) -> bool {
        self.alpha.is_some() || self.friction.is_some()
    }

    /// Whether the laws keep a record per contact (friction's spring).
    #[inline]
    pub(crate) fn keeps_history(&self) -> bool {
        self.friction.is_some()
    }

    /// The tangential law of body `a` against the walls, if that contact
    /// is frictional (the table has friction).
    #[inline(always)]
    pub(crate) fn tangential_wall(&self, a: usize) -> Option<TangentialLaw> {
        *self.tangential_wall.get(self.kind(a))?
    }

    /// The Hertz law of bodies `a` and `b` ([`LawTable::pair`]) and their
    /// tangential law if their contact is frictional (the table has
    /// friction): one lookup of their kinds for both.
    #[inline(always)]
    pub(crate) fn pair_with_tangential(
        &self,
        a: usize,
        b: usize,
    ) -> (HertzLaw, Option<TangentialLaw>) {
        let (ka, kb) = (self.kind(a), self.kind(b));
        let i = ka * self.kinds.len() + kb;
        match (self.pair.get(i), self.tangential_pair.get(i)) {
            (Some(&law), Some(&t)) => (law, t),
            _ => self.pair_with_tangential_computed(ka, kb),
        }
    }

    /// [`LawTable::pair_with_tangential`] of kinds `ka` and `kb` when the
    /// table was not made.
    #[cold]
    #[inline(never)]
    fn pair_with_tangential_computed(
        &self,
        ka: usize,
        kb: usize,
    ) -> (HertzLaw, Option<TangentialLaw>) {
        let (a, b) = (self.kinds[ka], self.kinds[kb]);
        let law = pair_law(a, b);
        let t = self.friction.and_then(|(f, dt)| {
            let mu = f.pair(a.friction, b.friction);
            let t = Tangential::new(mu, a.young, a.poisson, b.young, b.poisson);
            TangentialLaw::of(t, &law, dt)
        });
        (law, t)
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
        &self.wall[self.kind(a)]
    }

    /// The Hertz law of body `a` (as the pair's first) against body `b`:
    /// the table's lookup (its untabled fallback out of line).
    #[inline(always)]
    pub(crate) fn pair(&self, a: usize, b: usize) -> HertzLaw {
        let (ka, kb) = (self.kind(a), self.kind(b));
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

impl Kind {
    /// The contact kind of `body`, made of `m`.
    fn of(body: &Body, m: &Material) -> Self {
        Kind {
            shape: ColliderKind::of(&body.shape)
                .expect("scene validation admits no rigid body in contact scenes"),
            diameter: body.shape.diameter(),
            young: m.young,
            poisson: m.poisson,
            friction: m.friction,
        }
    }
}

/// The Hertz law of body `a` (made of `ma`) against body `b` (made of
/// `mb`): the law the table holds for their kinds (the time-step advice
/// reads it).
pub(crate) fn body_law(a: &Body, ma: &Material, b: &Body, mb: &Material) -> HertzLaw {
    pair_law(Kind::of(a, ma), Kind::of(b, mb))
}

/// The Hertz law of body `a` (made of `ma`) against the walls `w`.
pub(crate) fn body_wall_law(a: &Body, ma: &Material, w: &Walls) -> HertzLaw {
    wall_law(Kind::of(a, ma), w)
}

/// The law of kinds `a` and `b`, by their collider kinds, in the argument
/// order of a pair `(a, b)` (a sphere–fibre law takes the sphere first).
#[inline]
fn pair_law(a: Kind, b: Kind) -> HertzLaw {
    use ColliderKind::*;
    match (a.shape, b.shape) {
        (Fibre, Fibre) => HertzLaw::fibre_fibre(
            a.diameter, a.young, a.poisson, b.diameter, b.young, b.poisson,
        ),
        (Sphere, Sphere) => HertzLaw::sphere_sphere(
            a.diameter, a.young, a.poisson, b.diameter, b.young, b.poisson,
        ),
        (Sphere, Fibre) => HertzLaw::sphere_fibre(
            a.diameter, a.young, a.poisson, b.diameter, b.young, b.poisson,
        ),
        (Fibre, Sphere) => HertzLaw::sphere_fibre(
            b.diameter, b.young, b.poisson, a.diameter, a.young, a.poisson,
        ),
    }
}

/// The law of kind `k` against the walls `w`.
#[inline]
fn wall_law(k: Kind, w: &Walls) -> HertzLaw {
    match k.shape {
        ColliderKind::Fibre => {
            HertzLaw::fibre_wall(k.diameter, k.young, k.poisson, w.young, w.poisson)
        }
        ColliderKind::Sphere => {
            HertzLaw::sphere_wall(k.diameter, k.young, k.poisson, w.young, w.poisson)
        }
    }
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
            friction: None,
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

    /// The pair rule: two bodies take the smaller of their materials' μ, a
    /// material without its own takes `[contact] friction`; a body and a
    /// wall the smaller of its material's μ (else `wall_friction`) and
    /// `wall_friction`; a pair at μ = 0 is frictionless.
    #[test]
    fn a_pair_takes_the_smaller_mu() {
        let mut materials = vec![material(5e7, 0.35); 4];
        materials[0].friction = Some(0.2);
        materials[1].friction = Some(0.5);
        materials[3].friction = Some(0.0);
        let bodies: Bodies = (0..4).map(|m| fibre(0.01, m)).collect();
        let f = Friction {
            body: 0.3,
            wall: 0.4,
        };
        let t = LawTable::new(&bodies, &materials, Some(&WALLS)).with_friction(Some(f), 1e-6);
        let mu = |a, b| t.pair_with_tangential(a, b).1.map(|t| t.law.mu);
        assert_eq!(mu(0, 1), Some(0.2));
        assert_eq!(mu(1, 0), Some(0.2));
        assert_eq!(mu(1, 1), Some(0.5));
        assert_eq!(mu(1, 2), Some(0.3));
        assert_eq!(mu(2, 2), Some(0.3));
        assert_eq!(mu(0, 3), None);
        let wall = |a| t.tangential_wall(a).map(|t| t.law.mu);
        assert_eq!(
            [wall(0), wall(1), wall(2), wall(3)],
            [Some(0.2), Some(0.4), Some(0.4), None]
        );
    }

    /// Reference: the tangential law of each body pair and each body–wall
    /// contact built on its own (`Tangential::new` from the two materials,
    /// the Hertz law from the two bodies), and its damping ratio `√(G*/E*)`
    /// worked out as the law did per point, compared bit for bit: tabled
    /// (four kinds of two materials and three diameters, whose `E*` differ)
    /// and built per pair (more kinds than the table holds). (Mutant
    /// tried: the ratio tabled with the walls' `E*`.)
    #[test]
    fn tabled_tangential_laws_are_the_per_pair_laws() {
        let mut materials = vec![material(5e7, 0.35), material(2.1e9, 0.23)];
        materials[1].friction = Some(0.5);
        let few: Bodies = [(0.01, 0), (0.003, 1), (0.01, 1), (0.001, 0)]
            .iter()
            .map(|&(d, m)| fibre(d, m))
            .collect();
        let many: Bodies = (0..MAX_TABLE_KINDS + 3)
            .map(|i| fibre(0.005 + 1e-4 * i as f64, (i % 2) as u32))
            .collect();
        let f = Friction {
            body: 0.3,
            wall: 0.4,
        };
        let dt = 1e-6;
        for bodies in [few, many] {
            let t = LawTable::new(&bodies, &materials, Some(&WALLS)).with_friction(Some(f), dt);
            let bits = |t: &TangentialLaw| {
                let l = t.law;
                [l.mu, l.g_star, t.root_g_over_e, t.dt].map(f64::to_bits)
            };
            for (i, a) in bodies.iter().enumerate() {
                let ma = &materials[a.material as usize];
                let d = a.shape.diameter();
                let wall =
                    HertzLaw::fibre_wall(d, ma.young, ma.poisson, WALLS.young, WALLS.poisson);
                let mu = f.against_wall(ma.friction);
                let tan = Tangential::new(mu, ma.young, ma.poisson, WALLS.young, WALLS.poisson);
                let expected = TangentialLaw {
                    law: tan,
                    root_g_over_e: (tan.g_star / wall.e_star).sqrt(),
                    dt,
                };
                assert_eq!(
                    t.tangential_wall(i).map(|t| bits(&t)),
                    Some(bits(&expected))
                );
                for (j, b) in bodies.iter().enumerate() {
                    let mb = &materials[b.material as usize];
                    let db = b.shape.diameter();
                    let hertz =
                        HertzLaw::fibre_fibre(d, ma.young, ma.poisson, db, mb.young, mb.poisson);
                    let mu = f.pair(ma.friction, mb.friction);
                    let tan = Tangential::new(mu, ma.young, ma.poisson, mb.young, mb.poisson);
                    let expected = TangentialLaw {
                        law: tan,
                        root_g_over_e: (tan.g_star / hertz.e_star).sqrt(),
                        dt,
                    };
                    let (law, got) = t.pair_with_tangential(i, j);
                    assert_eq!(law.e_star.to_bits(), hertz.e_star.to_bits());
                    assert_eq!(got.map(|t| bits(&t)), Some(bits(&expected)), "{i} {j}");
                }
            }
        }
    }

    /// Reference: the laws built for each pair and each body (as the stage
    /// built them before the table), compared bit for bit.
    fn assert_matches_per_pair(bodies: &Bodies, materials: &[Material]) {
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

    fn sphere(diameter: f64, material: u32) -> Body {
        Body::new(Shape::Sphere { diameter }, material, 1100.0)
    }

    /// Reference: the law of each kind pair written out (Johnson's sphere
    /// laws, the fibre conventions; `hertz_spheres.rs`), for a mixed bed
    /// whose sphere and fibre share a diameter and a material (mutant
    /// tried: the kinds keyed without the collider kind, so the sphere
    /// takes the fibre's wall law).
    #[test]
    fn a_mixed_bed_has_the_law_of_each_kind_pair() {
        let materials = [material(5e7, 0.35), material(2.1e9, 0.23)];
        let bodies: Bodies = [
            fibre(0.01, 0),
            sphere(0.01, 0),
            sphere(0.003, 1),
            fibre(0.01, 0),
        ]
        .into_iter()
        .collect();
        let t = LawTable::new(&bodies, &materials, Some(&WALLS));
        assert_eq!(t.kinds.len(), 3);
        let bits = |l: &HertzLaw| (l.e_star.to_bits(), l.r_star.to_bits());
        let m = |i: usize| &materials[bodies[i].material as usize];
        let d = |i: usize| bodies[i].shape.diameter();
        for i in 0..bodies.len() {
            let wall = match bodies[i].shape {
                Shape::Sphere { .. } => HertzLaw::sphere_wall,
                _ => HertzLaw::fibre_wall,
            }(d(i), m(i).young, m(i).poisson, WALLS.young, WALLS.poisson);
            assert_eq!(bits(t.wall(i)), bits(&wall), "wall, body {i}");
            for j in 0..bodies.len() {
                let (si, sj) = (
                    matches!(bodies[i].shape, Shape::Sphere { .. }),
                    matches!(bodies[j].shape, Shape::Sphere { .. }),
                );
                let (a, b) = match (si, sj) {
                    (false, true) => (j, i),
                    _ => (i, j),
                };
                let law = match (si, sj) {
                    (true, true) => HertzLaw::sphere_sphere,
                    (false, false) => HertzLaw::fibre_fibre,
                    _ => HertzLaw::sphere_fibre,
                }(
                    d(a),
                    m(a).young,
                    m(a).poisson,
                    d(b),
                    m(b).young,
                    m(b).poisson,
                );
                assert_eq!(bits(&t.pair(i, j)), bits(&law), "pair {i} {j}");
            }
        }
        // The sphere–wall law is not the fibre–wall law of the same
        // diameter and material in general; here they agree in value (one
        // formula), so the kinds must still differ by collider kind.
        assert_ne!(t.kind_of[0], t.kind_of[1]);
    }

    #[test]
    fn a_bed_of_identical_fibres_has_one_law() {
        let materials = [material(5e7, 0.35)];
        let bodies = Bodies::uniform(fibre(0.01, 0), 9);
        let t = LawTable::new(&bodies, &materials, Some(&WALLS));
        assert_eq!((t.kinds.len(), t.wall.len(), t.pair.len()), (1, 1, 1));
        assert_eq!((t.kind_of.len(), t.mask), (1, 0), "nothing per body");
        assert_matches_per_pair(&bodies, &materials);
    }

    #[test]
    fn tabled_laws_are_the_per_pair_laws() {
        // Two materials, three diameters (none exact in binary, so 1/R*
        // rounds differently for each pair of them).
        let materials = [material(5e7, 0.35), material(2.1e9, 0.23)];
        let bodies: Bodies = [(0.01, 0), (0.003, 1), (0.01, 1), (0.01, 0), (0.001, 0)]
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
        let bodies: Bodies = (0..MAX_TABLE_KINDS + 5)
            .map(|i| fibre(0.005 + 1e-4 * i as f64, 0))
            .collect();
        let t = LawTable::new(&bodies, &materials, Some(&WALLS));
        assert_eq!(t.kinds.len(), MAX_TABLE_KINDS + 5);
        assert!(t.pair.is_empty());
        assert_matches_per_pair(&bodies, &materials);
    }
}
