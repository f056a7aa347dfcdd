//! The iterative penetration search, now the fallback of the feature-pair
//! kernels (end_involved.rs) where their scan is unsure: the depth
//! `min_n h̃_B(n) + h̃_A(−n)` of the two domed cylinders (support.rs),
//! found by local searches over the feature manifolds of that function from
//! seeds (parry's checked normal, the closest-point normal, competitive face
//! normals), with two tied local minima blended. The feature minimisers
//! [`circle_min`] and [`sphere_min`] also serve the parry check. How the
//! searches were made reliable: docs/contacts.md, "Penetration search".

use super::blend::{smooth_min_c2, Blend, END_TIE_BAND};
use super::end_involved::contact_along;
use super::support::{dome_sag, domed_projection_overlap as pov, sig, support, support_branch};
use super::Cand;
use crate::contact::FibreGeom;
use glam::DVec3;

/// The end-involved depth: `min_n` of the domed projection overlap
/// (`support::domed_projection_overlap`), the penetration depth of the two
/// domed cylinders (separating-axis theorem): equal to the flat cylinders' depth when the
/// minimiser is more than θc from every face normal, at most `σ_A + σ_B`
/// deeper otherwise. The function is smooth except on each cylinder's side
/// great circle (`n ⊥ axis`, the support jumps between end rims) and C¹ at
/// the caps' edges. The minimum is therefore searched on each feature
/// manifold: the face normals and common normal (points), the two side
/// circles (1-D Newton), and each smooth branch on the sphere (2-D Newton:
/// rim on rim, a rim or generator on a cap), seeded by parry's normal / the
/// closest-point normal and, when a face normal is competitive, by that
/// face normal. Every value is an upper bound of the minimum; the least
/// one is returned.
///
/// Gradient: at a smooth minimum the two support points differ along `n`
/// only, and the force at either is the exact gradient (envelope theorem).
/// On one body's side circle that body's support is a whole generator, and
/// the force at the *other* body's support point is the gradient
/// (parametrise `n` in the degenerate body's frame; Danskin). On both side
/// circles (common normal, generators crossing) the force acts at the
/// crossing of the two generators.
pub(super) fn penetration(a: &FibreGeom, b: &FibreGeom, seeds: [DVec3; 2]) -> Cand {
    let m = depth_minima(a, b, seeds, false);
    contact_along(a, b, m.best_n, m.best)
}

/// The end-involved depth with its ties smoothed: [`penetration`]'s
/// minimum `δ1`, and, when the lowest *other* local minimum `δ2` of the
/// domed projection overlap (a different escape direction) is within
/// [`END_TIE_BAND`] of it, their C² smooth minimum `m(δ1, δ2)`
/// ([`smooth_min_c2`]), pushed as two contacts (one per minimum, its own
/// normal and point) at depth `m` with weights `∂m/∂δ_i` (summing to 1):
/// energy `U(m)`, forces `F(m) Σ ∂m/∂δ_i ∇δ_i`, its exact gradient (each
/// minimum's gradient by the envelope theorem, as for `δ1` alone). The
/// weights depend on the pose only through `δ1, δ2`, and sum to 1, so they
/// carry no `ContactPoint::weight_grad`. C², not C¹: leap-frog's energy
/// error follows the curvature of the potential (docs/contacts.md, "Ties").
pub(super) fn penetration_smoothed(a: &FibreGeom, b: &FibreGeom, seeds: [DVec3; 2]) -> Blend {
    let m = depth_minima(a, b, seeds, true);
    let best = Blend::single(contact_along(a, b, m.best_n, m.best));
    match m.runner_up {
        Some((v, n)) if v - m.best < END_TIE_BAND => {
            let other = Blend::single(contact_along(a, b, n, v));
            best.smin_by(other, |x, y| smooth_min_c2(x, y, END_TIE_BAND))
        }
        _ => best,
    }
}

/// Two local minima of the depth whose normals are closer than this
/// (cos 1e-4 rad) are one minimum found twice (different searches agree
/// to ~1e-9 rad; a smooth minimum of a minimum with itself would
/// under-estimate it by 3ε/16).
pub(super) const SAME_MINIMUM_COS: f64 = 1.0 - 5e-9;

/// Result of [`depth_minima`]: the least value found (and its direction),
/// and the least *local minimum* in another direction, if any was found.
struct Minima {
    best: f64,
    best_n: DVec3,
    runner_up: Option<(f64, DVec3)>,
}

/// The searches of [`penetration`], with a record of the local minima they
/// reach: a side-circle minimum that is a local minimum on the sphere, a
/// smooth-branch minimum inside its own branch, both stationary (a search
/// stopped short is not a minimum, and the force at it is not the
/// gradient of its value).
struct Search<'g> {
    a: &'g FibreGeom,
    b: &'g FibreGeom,
    best: f64,
    best_n: DVec3,
    minima: [(f64, DVec3); 16],
    count: usize,
    /// Stationarity tolerance of a local minimum: the tangential offset of
    /// the two support points (m).
    tol: f64,
}

impl Search<'_> {
    fn consider(&mut self, n: DVec3) {
        let l = n.length();
        if !(l > 1e-12 && l.is_finite()) {
            return;
        }
        for m in [n / l, -n / l] {
            let v = pov(self.a, self.b, m);
            if v < self.best {
                self.best = v;
                self.best_n = m;
            }
        }
    }

    fn record(&mut self, v: f64, n: DVec3) {
        if self.count < self.minima.len() {
            self.minima[self.count] = (v, n);
            self.count += 1;
        }
    }

    /// Minimum on the side circle ⊥ `u` (one of the axes) from `st`.
    fn circle(&mut self, u_is_a: bool, st: DVec3) {
        let (a, b) = (self.a, self.b);
        let (f, u) = if u_is_a { (a, a.axis) } else { (b, b.axis) };
        let m = circle_min(a, b, u, st);
        self.consider(m);
        // A local minimum on the sphere iff the other body's support
        // point lies between the circle's body's end planes (the one-sided
        // derivatives off the circle are h ∓ (p − c)·u); where it does not,
        // a smooth branch holds the minimum ([`Search::branch`]).
        let v = pov(a, b, m);
        let (pb, pa) = (support(b, m).0, support(a, -m).0);
        let p = if u_is_a { pb } else { pa };
        // Stationary along the circle: the supports differ along m only
        // in the circle's tangent u × m (the degenerate body's generator
        // is along u, so any of its points gives the same component).
        let stationary = (pb - pa).dot(u.cross(m)).abs() <= self.tol;
        if stationary && (p - f.centre).dot(u).abs() <= f.half_length {
            self.record(v, m);
        }
    }

    /// Minimum of the smooth branch (A's end `fa`, B's end `fb`) from `st`.
    fn branch(&mut self, st: DVec3, fa: f64, fb: f64) {
        let (a, b) = (self.a, self.b);
        let m = sphere_min(a, b, st, fa, fb);
        self.consider(m);
        // In its own branch, and stationary (the search may stop short,
        // e.g. on a cap's edge): the supports differ along m only.
        if sig(-m, a.axis) == fa && sig(m, b.axis) == fb {
            let g = support_branch(b, m, fb).0 - support_branch(a, -m, fa).0;
            if (g - g.dot(m) * m).length() <= self.tol {
                self.record(pov(a, b, m), m);
            }
        }
    }

    /// Side circles near `st` and the smooth branches of `st` (and of the
    /// other end of a body whose side circle is near).
    fn from(&mut self, st: DVec3) {
        let (a, b) = (self.a, self.b);
        // Side circles of B and of A (only when the start is near one:
        // parry's normal is accurate to far better than this), then the
        // generic sphere.
        for (u_is_a, u) in [(false, b.axis), (true, a.axis)] {
            if st.dot(u).abs() < 0.1 {
                self.circle(u_is_a, st);
            }
        }
        let (sa, sb) = (sig(-st, a.axis), sig(st, b.axis));
        let near = |u: DVec3| st.dot(u).abs() < 0.1;
        for (fa, fb) in [(sa, sb), (-sa, sb), (sa, -sb)] {
            if (fa != sa && !near(a.axis)) || (fb != sb && !near(b.axis)) {
                continue;
            }
            self.branch(st, fa, fb);
        }
    }
}

/// The minimisation of [`penetration`] (`seeds`: the closest-point normal,
/// and the start candidate, parry's normal or a face normal). With
/// `runner_up`, also the least other local minimum, searched so that it is
/// found whichever of two tied minima wins: besides the searches from the
/// start (parry's normal, which jumps to the winner at a tie), from every
/// face normal within the bowl plus [`END_TIE_BAND`] (instead of the most
/// competitive one within the bowl), and on the side circles near
/// `seeds[0]` (continuous through a tie). Without it the searches, and so
/// the result, are those of the plain minimum.
fn depth_minima(a: &FibreGeom, b: &FibreGeom, seeds: [DVec3; 2], runner_up: bool) -> Minima {
    let w = a.centre - b.centre;
    let mut s = Search {
        a,
        b,
        best: f64::INFINITY,
        best_n: DVec3::ZERO,
        minima: [(0.0, DVec3::ZERO); 16],
        count: 0,
        tol: 1e-6 * (a.radius + b.radius),
    };
    for d in [a.axis, b.axis, a.axis.cross(b.axis), w, seeds[0], seeds[1]] {
        s.consider(d);
    }
    // The face normals (the minimum may sit on a cap, off the normal
    // itself), most competitive first.
    let mut faces = [a.axis, -a.axis, b.axis, -b.axis].map(|u| (pov(a, b, u), u));
    faces.sort_by(|x, y| x.0.total_cmp(&y.0));
    let start = if pov(a, b, seeds[1]) <= s.best + 1e-9 * (a.radius + b.radius) {
        seeds[1]
    } else {
        s.best_n
    };
    let bowl = 2.0 * (dome_sag(a.radius) + dome_sag(b.radius));
    let screen = s.best + bowl + if runner_up { END_TIE_BAND } else { 0.0 };
    s.from(start);
    for &(v, face) in faces.iter().take(if runner_up { 4 } else { 1 }) {
        if v <= screen && (face - start).length() > 1e-12 {
            s.from(face);
        }
    }
    if runner_up {
        let st = seeds[0];
        let l = st.length();
        if l > 1e-12 && l.is_finite() && (st / l - start).length() > 1e-12 {
            for (u_is_a, u) in [(false, b.axis), (true, a.axis)] {
                if (st / l).dot(u).abs() < 0.1 {
                    s.circle(u_is_a, st / l);
                }
            }
        }
    }
    let mut runner: Option<(f64, DVec3)> = None;
    if runner_up {
        for &(v, n) in &s.minima[..s.count] {
            if n.dot(s.best_n) < SAME_MINIMUM_COS && runner.is_none_or(|r| v < r.0) {
                runner = Some((v, n));
            }
        }
    }
    Minima {
        best: s.best,
        best_n: s.best_n,
        runner_up: runner,
    }
}

/// 1-D Newton (numerical derivatives, backtracking) on the great circle
/// `n ⊥ u`, starting from the projection of `seed`.
pub(super) fn circle_min(a: &FibreGeom, b: &FibreGeom, u: DVec3, seed: DVec3) -> DVec3 {
    let mut e1 = seed - seed.dot(u) * u;
    if e1.length_squared() < 1e-24 {
        e1 = u.any_orthonormal_vector();
    }
    let e1 = e1.normalize();
    let e2 = u.cross(e1);
    let at = |th: f64| {
        let (sn, cs) = th.sin_cos();
        cs * e1 + sn * e2
    };
    let f = |th: f64| pov(a, b, at(th));
    let mut th = 0.0;
    let mut v = f(th);
    let eps = 1e-5;
    for _ in 0..30 {
        let (fp, fm) = (f(th + eps), f(th - eps));
        let d1 = (fp - fm) / (2.0 * eps);
        let d2 = (fp - 2.0 * v + fm) / (eps * eps);
        let mut step = if d2 > 0.0 {
            -d1 / d2
        } else {
            -0.05 * d1.signum()
        };
        step = step.clamp(-0.5, 0.5);
        if step.abs() < 1e-11 {
            break;
        }
        let mut moved = false;
        for _ in 0..12 {
            let nv = f(th + step);
            if nv < v {
                th += step;
                v = nv;
                moved = true;
                break;
            }
            step *= 0.5;
        }
        if !moved || step.abs() < 1e-13 {
            break;
        }
    }
    at(th)
}

/// 2-D damped Newton on the sphere for one smooth branch of the domed
/// projection overlap (A's end `sigma_a`, B's end `sigma_b`; analytic
/// gradient `p̃_B(n) − p̃_A(−n)`, Hessian by central differences of it),
/// accepting only decreases. The overlap is the max of its four branches
/// (kinks on the side circles only), so its minimum is a branch minimum
/// lying in that branch's own region, or lies on a side circle
/// ([`circle_min`]). Minimising a smooth branch converges quadratically
/// even when the minimum is microradians from a side circle, where a
/// Newton iteration on the kinked function stalls.
pub(super) fn sphere_min(
    a: &FibreGeom,
    b: &FibreGeom,
    seed: DVec3,
    sigma_a: f64,
    sigma_b: f64,
) -> DVec3 {
    let val = |m: DVec3| support_branch(b, m, sigma_b).1 + support_branch(a, -m, sigma_a).1;
    let mut n = seed;
    let mut best = val(n);
    for _ in 0..30 {
        let e1 = n.any_orthonormal_vector();
        let e2 = n.cross(e1);
        let grad = |m: DVec3| {
            let g = support_branch(b, m, sigma_b).0 - support_branch(a, -m, sigma_a).0;
            (g.dot(e1), g.dot(e2))
        };
        let (g1, g2) = grad(n);
        let eps = 1e-6;
        let (p1, q1) = grad((n + eps * e1).normalize());
        let (m1, r1) = grad((n - eps * e1).normalize());
        let (p2, q2) = grad((n + eps * e2).normalize());
        let (m2, r2) = grad((n - eps * e2).normalize());
        let h11 = (p1 - m1) / (2.0 * eps);
        let h22 = (q2 - r2) / (2.0 * eps);
        let h12 = 0.25 * ((q1 - r1) + (p2 - m2)) / eps;
        let det = h11 * h22 - h12 * h12;
        let (mut d1, mut d2) = if h11 > 0.0 && det > 0.0 {
            (-(h22 * g1 - h12 * g2) / det, -(h11 * g2 - h12 * g1) / det)
        } else {
            let gl = (g1 * g1 + g2 * g2).sqrt().max(1e-300);
            (-0.05 * g1 / gl, -0.05 * g2 / gl)
        };
        if d1.abs() + d2.abs() < 1e-11 {
            break;
        }
        let mut moved = false;
        for _ in 0..12 {
            let m = (n + d1 * e1 + d2 * e2).normalize();
            let v = val(m);
            if v < best {
                best = v;
                n = m;
                moved = true;
                break;
            }
            d1 *= 0.5;
            d2 *= 0.5;
        }
        if !moved || d1.abs() + d2.abs() < 1e-13 {
            break;
        }
    }
    n
}
