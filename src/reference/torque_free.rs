//! The torque-free rigid body in closed form: regular precession for two
//! equal moments, Jacobi's elliptic-function solution for three distinct
//! ones (Landau & Lifshitz, *Mechanics*, §33 and §37).
//!
//! **Angular momentum** (body frame, Landau–Lifshitz Eq. 37.10 written for
//! `L = J ω`). Work in a right-handed frame of signed principal axes with
//! moments `J₁, J₂, J₃`, `J₂` the intermediate one and `J₃` the axis `L`
//! circulates about: the largest when `M² > 2E J₂`, else the smallest. With
//! `Dᵢ = M² − 2E Jᵢ` (each a sum of squares of `L`, so no digits are lost),
//! `L₁ = A₁ cn u`, `L₂ = s₂ A₂ sn u`, `L₃ = s₃ A₃ dn u`, `u = λt + u₀`,
//! `A₁² = J₁(−D₃)/(J₃ − J₁)`, `A₂² = J₂(−D₃)/(J₃ − J₂)`,
//! `A₃² = J₃ D₁/(J₃ − J₁)`, `λ² = (J₃ − J₂) D₁/(J₁J₂J₃)`,
//! `m = (J₂ − J₁)(−D₃)/((J₃ − J₂) D₁)`, `1 − m = (J₃ − J₁) D₂/((J₃ − J₂) D₁)`;
//! `s₃ = sign L₃` and `s₂ = ±s₃` (`+` about the largest axis) follow from
//! Euler's equations.
//!
//! **Orientation.** `q(t) ⊗ P = exp(Δφ(t) L̂) ⊗ q₀ ⊗ P ⊗ B(L(0))* ⊗ B(L(t))`,
//! `P` the working frame, `B(l) = R_x(θ) R_z(ψ)` the zxz Euler rotation that
//! takes `l` to `M ẑ` (`l = M (sin θ sin ψ, sin θ cos ψ, cos θ)`) and `φ`
//! the precession angle about the conserved world `L`, whose rate is
//! Landau–Lifshitz Eq. 37.16, `φ̇ = M (L₁²/J₁ + L₂²/J₂)/(L₁² + L₂²)`. With the
//! solution above this is `M/J₃ + M (1/J₁ − 1/J₃)/(1 − n sn²u)`,
//! `n = 1 − J₂(J₃ − J₁)/(J₁(J₃ − J₂)) < 0`, so
//! `Δφ = M t/J₃ + M (1/J₁ − 1/J₃)/λ [Π(n; am u|m) − Π(n; am u₀|m)]`, an
//! elliptic integral of the third kind (the form of Celledoni, Fassò,
//! Säfström & Zanna, SIAM J. Sci. Comput. 30 (2008), §2, reached here from
//! Landau–Lifshitz directly).
//!
//! Every parameter is computed from the three `Dᵢ` and `M²`; a caller that
//! carries those as conserved numbers ([`crate::integrate::rotate`]'s `split`)
//! gets bit-constant frequencies in free flight.

use super::elliptic::{jacobi, Jacobi, Legendre};
use crate::math::exp_map;
use glam::{DMat3, DQuat, DVec3};

/// `Dᵢ = M² − 2E Iᵢ = Σⱼ Lⱼ² (1 − Iᵢ/Iⱼ)` for each body axis `i`, without
/// cancellation of the `j = i` term.
pub fn casimir_gaps(inertia: DVec3, l_b: DVec3) -> DVec3 {
    let l2 = l_b * l_b;
    let gap = |i: usize| -> f64 {
        (0..3)
            .filter(|&j| j != i)
            .map(|j| l2[j] * (1.0 - inertia[i] / inertia[j]))
            .sum()
    };
    DVec3::new(gap(0), gap(1), gap(2))
}

/// The axis of symmetry of a body with two equal principal moments (index),
/// or `None` for three distinct ones. A sphere gives axis 0.
pub fn symmetry_axis(inertia: DVec3) -> Option<usize> {
    let [a, b, c] = inertia.to_array();
    if b == c {
        Some(0)
    } else if a == c {
        Some(1)
    } else if a == b {
        Some(2)
    } else {
        None
    }
}

/// `B(l)`: the rotation `R_x(θ) R_z(ψ)` taking `l` onto `|l| ẑ`, with
/// `ψ = atan2(l₁, l₂)` and `θ = atan2(√(l₁² + l₂²), l₃)` (module docs).
#[inline]
pub fn alignment(l: DVec3) -> DQuat {
    let psi = l.x.atan2(l.y);
    let theta = l.x.hypot(l.y).atan2(l.z);
    let (sp, cp) = (0.5 * psi).sin_cos();
    let (st, ct) = (0.5 * theta).sin_cos();
    DQuat::from_xyzw(st, 0.0, 0.0, ct) * DQuat::from_xyzw(0.0, 0.0, sp, cp)
}

/// The elliptic-function motion of an asymmetric body's angular momentum
/// (module docs), with everything that stays constant while no torque acts.
#[derive(Debug, Clone, PartialEq)]
pub struct Polhode {
    /// Body indices of the working axes 1, 2, 3.
    axes: [usize; 3],
    /// `±1`: the working axis 3 is `σ₃` times body axis `axes[2]`.
    sigma3: f64,
    /// The working frame in the body frame (working → body).
    pub perm: DQuat,
    /// `J₁, J₂, J₃`.
    j: DVec3,
    /// `M = |L|`.
    pub big_m: f64,
    /// `A₁, A₂, A₃`.
    amp: DVec3,
    /// `s₂, s₃`.
    signs: (f64, f64),
    /// `λ`, 1/s.
    pub lambda: f64,
    /// `m`, `1 − m`, `n`, `K(m)`, `Π(n|m)`.
    pub legendre: Legendre,
    /// `M/J₃`, the uniform part of the precession rate.
    precession_rate: f64,
    /// `M (1/J₁ − 1/J₃)/λ`, the factor of the `Π` part.
    precession_pi: f64,
}

impl Polhode {
    /// The polhode through body momentum `l_b` of a body with distinct
    /// principal moments `inertia`, for `M² = m2` and gaps `d`
    /// ([`casimir_gaps`], possibly carried from earlier). `None` when the
    /// moments are not distinct, `L` lies on a principal axis (a steady
    /// rotation) or exactly on the separatrix `D₂ = 0`.
    pub fn new(inertia: DVec3, l_b: DVec3, m2: f64, d: DVec3) -> Option<Self> {
        let mut order = [0usize, 1, 2];
        order.sort_by(|&a, &b| inertia[a].total_cmp(&inertia[b]));
        let [lo, mid, hi] = order;
        if !(inertia[lo] < inertia[mid] && inertia[mid] < inertia[hi]) || d[mid] == 0.0 {
            return None;
        }
        let about_largest = d[mid] > 0.0;
        let axes = if about_largest {
            [lo, mid, hi]
        } else {
            [hi, mid, lo]
        };
        let unit = |i: usize| DVec3::AXES[i];
        let (e1, e2) = (unit(axes[0]), unit(axes[1]));
        let e3 = e1.cross(e2);
        let sigma3 = e3[axes[2]];
        let perm = DQuat::from_mat3(&DMat3::from_cols(e1, e2, e3));
        let j = DVec3::new(inertia[axes[0]], inertia[axes[1]], inertia[axes[2]]);
        // D₁, D₂ and −D₃: one sign (+ about the largest axis, − about the
        // smallest), so every ratio below is positive.
        let (d1, d2, d3) = (d[axes[0]], d[axes[1]], -d[axes[2]]);
        let amp = DVec3::new(
            (j.x * d3 / (j.z - j.x)).sqrt(),
            (j.y * d3 / (j.z - j.y)).sqrt(),
            (j.z * d1 / (j.z - j.x)).sqrt(),
        );
        let lambda = ((j.z - j.y) * d1 / (j.x * j.y * j.z)).sqrt();
        let m = (j.y - j.x) * d3 / ((j.z - j.y) * d1);
        let m1 = (j.z - j.x) * d2 / ((j.z - j.y) * d1);
        let n = 1.0 - j.y * (j.z - j.x) / (j.x * (j.z - j.y));
        let positive = |v: f64| v > 0.0 && v.is_finite();
        if !(amp.to_array().into_iter().all(positive)
            && positive(lambda)
            && positive(m1)
            && m.is_finite()
            && n.is_finite())
        {
            return None;
        }
        let l3 = sigma3 * l_b[axes[2]];
        let s3 = if l3 < 0.0 { -1.0 } else { 1.0 };
        let s2 = if about_largest { s3 } else { -s3 };
        let big_m = m2.sqrt();
        Some(Polhode {
            axes,
            sigma3,
            perm,
            j,
            big_m,
            amp,
            signs: (s2, s3),
            lambda,
            legendre: Legendre::new(m, m1, n),
            precession_rate: big_m / j.z,
            precession_pi: big_m * (1.0 / j.x - 1.0 / j.z) / lambda,
        })
    }

    /// Body components in the working frame.
    #[inline]
    pub fn to_working(&self, l_b: DVec3) -> DVec3 {
        DVec3::new(
            l_b[self.axes[0]],
            l_b[self.axes[1]],
            self.sigma3 * l_b[self.axes[2]],
        )
    }

    /// Working components in the body frame.
    #[inline]
    pub fn to_body(&self, l_w: DVec3) -> DVec3 {
        let mut out = [0.0; 3];
        out[self.axes[0]] = l_w.x;
        out[self.axes[1]] = l_w.y;
        out[self.axes[2]] = self.sigma3 * l_w.z;
        DVec3::from_array(out)
    }

    /// The amplitude `am u` and the argument `u` of working momentum `l`.
    /// `u = F(am)` by Carlson's `R_F`, then one Newton step on
    /// `am(u) = am` with the Landen `am` that the flow evaluates, so the two
    /// algorithms' last-bit disagreement does not bias the phase each time
    /// it is taken.
    pub fn phase(&self, l: DVec3) -> (f64, f64) {
        let cn = l.x / self.amp.x;
        let sn = self.signs.0 * l.y / self.amp.y;
        let am = sn.atan2(cn);
        let u = self.legendre.f(am);
        let e = self.at(u);
        (am, u + (am - e.am) / e.dn)
    }

    /// The elliptic functions at argument `u`.
    #[inline]
    pub fn at(&self, u: f64) -> Jacobi {
        jacobi(u, self.legendre.m, self.legendre.m1)
    }

    /// Working momentum at the elliptic functions `e`.
    #[inline]
    pub fn momentum(&self, e: &Jacobi) -> DVec3 {
        DVec3::new(
            self.amp.x * e.cn,
            self.signs.0 * self.amp.y * e.sn,
            self.signs.1 * self.amp.z * e.dn,
        )
    }

    /// Precession angle about `L` while the amplitude goes from `am0` (with
    /// `Π(am0)` given as `pi0`) to `am1` over time `t`.
    #[inline]
    pub fn precession(&self, pi0: f64, am1: f64, t: f64) -> f64 {
        self.precession_rate * t + self.precession_pi * (self.legendre.pi(am1) - pi0)
    }

    /// The time between two flips of the intermediate axis (sign changes of
    /// `L₂ ∝ sn u`): half the period of the polhode, `2K(m)/λ`.
    pub fn flip_period(&self) -> f64 {
        2.0 * self.legendre.k / self.lambda
    }

    /// Advance `q` by the exact torque-free flow over time `t`, the argument
    /// going from `u0` to `u1 = u0 + λt` (`t` is passed, not recovered from
    /// the rounded arguments: `(u1 − u0)/λ` errs by `ε u0/λ`, a bias of the
    /// precession at every step), for world momentum `l_world`: returns the new
    /// orientation and body momentum. The start is taken from the elliptic
    /// functions at `u0`, so consecutive steps telescope to the closed form;
    /// or, when `start` gives the state's own working momentum and amplitude
    /// (the argument was just derived from them), from those, so that the
    /// inverse of [`Self::phase`] adds no tilt.
    pub fn flow(
        &self,
        q: DQuat,
        l_world: DVec3,
        (u0, u1): (f64, f64),
        t: f64,
        start: Option<(DVec3, f64)>,
    ) -> (DQuat, DVec3) {
        let e1 = self.at(u1);
        let (l0, am0) = start.unwrap_or_else(|| {
            let e0 = self.at(u0);
            (self.momentum(&e0), e0.am)
        });
        let l1 = self.momentum(&e1);
        let dphi = self.precession(self.legendre.pi(am0), e1.am, t);
        let body = self.perm * alignment(l0).conjugate() * alignment(l1) * self.perm.conjugate();
        let q1 = exp_map(l_world * (dphi / self.big_m)) * q * body;
        (q1, self.to_body(l1))
    }
}

/// How a torque-free body moves.
#[derive(Debug, Clone, PartialEq)]
enum Motion {
    /// Two (or three) equal moments: `q(t) = exp(t L/I⊥) q₀ exp(t ν e_s)`,
    /// `ν = (1/I_s − 1/I⊥) L_s` (Landau–Lifshitz §33).
    Symmetric {
        axis: DVec3,
        l_axial: f64,
        i_perp: f64,
        spin: f64,
    },
    /// Three distinct moments.
    Asymmetric {
        polhode: Box<Polhode>,
        /// `am u₀`, `u₀`, `Π(am u₀)` and `B(L(0))` of the start.
        am0: f64,
        u0: f64,
        pi0: f64,
        b0: DQuat,
    },
    /// `L` along a principal axis: a steady rotation.
    Steady { omega_b: DVec3 },
}

/// The exact motion of a torque-free rigid body from a given start.
#[derive(Debug, Clone, PartialEq)]
pub struct TorqueFree {
    q0: DQuat,
    l_world: DVec3,
    l_b0: DVec3,
    inertia: DVec3,
    motion: Motion,
}

/// Why a torque-free start has no closed form here.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TorqueFreeError {
    /// `M² = 2E I₂` exactly: the asymptotic motion on the separatrix.
    Separatrix,
}

impl TorqueFree {
    /// The motion from orientation `q0` (body → world) and body angular
    /// velocity `omega_b0`, for principal moments `inertia`.
    pub fn new(inertia: DVec3, q0: DQuat, omega_b0: DVec3) -> Result<Self, TorqueFreeError> {
        let l_b0 = inertia * omega_b0;
        let l_world = q0 * l_b0;
        let steady = l_b0.to_array().iter().filter(|c| **c == 0.0).count() >= 2;
        let motion = match symmetry_axis(inertia) {
            _ if steady => Motion::Steady { omega_b: omega_b0 },
            Some(s) => {
                let i_s = inertia[s];
                let i_perp = inertia[(s + 1) % 3];
                Motion::Symmetric {
                    axis: DVec3::AXES[s],
                    l_axial: l_b0[s],
                    i_perp,
                    spin: (1.0 / i_s - 1.0 / i_perp) * l_b0[s],
                }
            }
            None => {
                let d = casimir_gaps(inertia, l_b0);
                let polhode = Polhode::new(inertia, l_b0, l_b0.length_squared(), d)
                    .ok_or(TorqueFreeError::Separatrix)?;
                let l = polhode.to_working(l_b0);
                let (am0, u0) = polhode.phase(l);
                let pi0 = polhode.legendre.pi(am0);
                Motion::Asymmetric {
                    b0: alignment(l),
                    polhode: Box::new(polhode),
                    am0,
                    u0,
                    pi0,
                }
            }
        };
        Ok(TorqueFree {
            q0,
            l_world,
            l_b0,
            inertia,
            motion,
        })
    }

    /// Orientation at time `t` (body → world).
    pub fn orientation(&self, t: f64) -> DQuat {
        match &self.motion {
            Motion::Steady { omega_b } => self.q0 * exp_map(*omega_b * t),
            Motion::Symmetric {
                axis, i_perp, spin, ..
            } => exp_map(self.l_world * (t / i_perp)) * self.q0 * exp_map(*axis * (spin * t)),
            Motion::Asymmetric {
                polhode: p,
                u0,
                pi0,
                b0,
                ..
            } => {
                let e = p.at(u0 + p.lambda * t);
                let dphi = p.precession(*pi0, e.am, t);
                let body = p.perm * b0.conjugate() * alignment(p.momentum(&e)) * p.perm.conjugate();
                exp_map(self.l_world * (dphi / p.big_m)) * self.q0 * body
            }
        }
    }

    /// Body-frame angular velocity at time `t`.
    pub fn omega_body(&self, t: f64) -> DVec3 {
        let l_b = match &self.motion {
            Motion::Steady { omega_b } => return *omega_b,
            Motion::Symmetric { axis, spin, .. } => {
                // L_b turns backwards about the symmetry axis at rate ν.
                DQuat::from_axis_angle(*axis, -spin * t) * self.l_b0
            }
            Motion::Asymmetric { polhode: p, u0, .. } => {
                p.to_body(p.momentum(&p.at(u0 + p.lambda * t)))
            }
        };
        l_b / self.inertia
    }

    /// The conserved world angular momentum, N m s.
    pub fn angular_momentum(&self) -> DVec3 {
        self.l_world
    }

    /// The conserved rotational energy, J.
    pub fn energy(&self) -> f64 {
        0.5 * self.l_b0.dot(self.l_b0 / self.inertia)
    }

    /// For three distinct moments, the time between flips of the
    /// intermediate axis, `2K(m)/λ` (the Dzhanibekov effect).
    pub fn flip_period(&self) -> Option<f64> {
        match &self.motion {
            Motion::Asymmetric { polhode, .. } => Some(polhode.flip_period()),
            _ => None,
        }
    }

    /// The body's axial angular momentum `L_s` about its symmetry axis, for
    /// two equal moments.
    pub fn axial_momentum(&self) -> Option<f64> {
        match &self.motion {
            Motion::Symmetric { l_axial, .. } => Some(*l_axial),
            _ => None,
        }
    }

    /// `am u₀`: the start's amplitude on the polhode (asymmetric bodies).
    pub fn start_amplitude(&self) -> Option<f64> {
        match &self.motion {
            Motion::Asymmetric { am0, .. } => Some(*am0),
            _ => None,
        }
    }
}
