//! The exact orientation q(t), body → space, in the internal frame.
//!
//! Write l̂ = L_body/|L| and n = σ e₃ (σ = sign ω₃, so n·l̂ = |L₃|/|L| ≥ 0
//! never vanishes along the orbit). Let M(t) be the smallest rotation taking
//! l̂(t) to n, as a quaternion M ∝ (|L| + |L₃|, σL₂, −σL₁, 0). Then
//!
//!   q(t) = M(0)⁻¹ ⊗ R_n(ψ(t)) ⊗ M(t),
//!
//! because q(t) l̂(t) = M(0)⁻¹ n = l̂(0) is the constant space-frame L, and
//! only the angle ψ about n is left. Matching body angular velocities,
//! ω = ω_M + ψ̇ l̂, and the twist of the smallest rotation is
//! ω_M·l̂ = n·(l̂ × l̂̇)/(1 + n·l̂); with l̂̇ = l̂ × ω (Euler's equations):
//!
//!   ψ̇ = (2T/|L| + n·ω) / (1 + n·l̂) = (2T + |L| A₃ dn u) / (|L| + J₃ A₃ dn u).
//!
//! Splitting 1/(α + β dn) = (α − β dn)/(α² − β² dn²) and using dn du = d(am u)
//! integrates this in closed form (all signs checked against Euler's
//! equations and against the constancy of q (Iω) q⁻¹ in the tests):
//!
//!   ψ(t) = (|L|/J₃) t + C [P(u) − P(u₀)] − ε [Θ(u) − Θ(u₀)],
//!   P(u) = Π(n; am u | m),  n = −J₃(J₂−J₁)/(J₁(J₃−J₂)) ≤ 0,
//!   C = |L|(J₃−J₁)/(J₁J₃λ),  Θ(u) = atan(κ tan am u),  κ² = J₂(J₃−J₁)/(J₁(J₃−J₂)).
//!
//! The arctangent term has coefficient exactly ε (the amplitudes cancel). Two
//! rewritings keep every digit:
//! - P is never evaluated through the amplitude φ = am u, whose error near
//!   φ = π/2 is amplified by 1/Δ ~ 1/√m_c. Instead P(r) = r + (n/3) sn³ R_J(cn²,
//!   dn², 1, 1 − n sn²) for |r| ≤ K/2, and for K/2 < |r| ≤ K the reflected
//!   form about K, with w = K − |r| and relatively accurate sn, cn, dn of w:
//!   P(K − w) = Π(n|m) − w/(1−n) + n m_c sn³ R_J(cn², dn², 1, (dn² − n cn²)/(1−n)) / (3(1−n)²).
//!   P grows by 2Π(n|m) and Θ by π per half period 2K.
//! - The linear rate is |L|/J_max (J_max the largest moment) and every
//!   other term is non-negative: for J₁ > J₂ > J₃ this means moving C·u out
//!   of C·P (|L|/J₃ + Cλ = |L|/J₁), which avoids cancelling a rate of order
//!   |L|/J_min against another for needle-like bodies.

use super::orbit::{Orbit, Point, Shape};
use crate::sim::elliptic::{self, carlson};
use std::f64::consts::PI;

/// A quaternion as (w, x, y, z).
pub(super) type Quat = [f64; 4];

pub(super) fn mul(a: Quat, b: Quat) -> Quat {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

#[derive(Debug, Clone)]
enum Angle {
    /// Symmetric top: ψ̇ = |L|/J₁ − ελ is constant.
    Uniform,
    /// Asymmetric body off the separatrix.
    Periodic {
        n: f64,
        mc: f64,
        /// 0 when J₃ is the largest moment, 1 when the smallest.
        beta: f64,
        /// Π(n|m) − K.
        pi_minus_k: f64,
        /// ψ gained per half period 2K beyond the linear term.
        per_half: f64,
        /// The periodic part at t = 0, and its half-period count.
        offset: f64,
        half_periods0: f64,
    },
    /// On the separatrix, P(u) = [u + ν atan(ν tanh u)]/(1 − n), ν = √−n.
    Separatrix {
        nu: f64,
        /// C ν / (1 − n).
        coefficient: f64,
        offset: f64,
    },
}

/// Everything ψ(t) and M(t) need beyond the orbit, computed once.
#[derive(Debug, Clone)]
pub(super) struct Attitude {
    /// Coefficient of t in ψ, in the caller's time.
    lin: f64,
    c: f64,
    kappa: f64,
    angle: Angle,
    /// M(0)⁻¹.
    q0: Quat,
}

impl Attitude {
    pub(super) fn new(orbit: &Orbit, time_scale: f64) -> Attitude {
        let [j1, j2, j3] = orbit.j;
        let l = orbit.l_norm;
        let c = l * orbit.d31 / (j1 * j3 * orbit.rate_scaled);
        let kappa = (j2 * orbit.d31 / (j1 * orbit.d32)).sqrt();
        let n = -j3 * orbit.d21 / (j1 * orbit.d32);
        let at_start = orbit.point(0.0);
        let m0 = smallest_rotation(orbit, &at_start);
        let q0 = [m0[0], -m0[1], -m0[2], -m0[3]];
        let mut attitude = Attitude {
            lin: 0.0,
            c,
            kappa,
            angle: Angle::Uniform,
            q0,
        };
        match &orbit.shape {
            Shape::Circular => {
                attitude.lin = time_scale * (l / j1 - orbit.eps * orbit.rate_scaled);
            }
            Shape::Elliptic { jacobi, .. } => {
                let beta = if orbit.eps > 0.0 { 0.0 } else { 1.0 };
                let j_max = if orbit.eps > 0.0 { j3 } else { j1 };
                let mc = jacobi.mc();
                let pi_minus_k = elliptic::complete_pi_minus_k(n, mc);
                let per_half = 2.0 * c * ((1.0 - beta) * jacobi.k() + pi_minus_k) - orbit.eps * PI;
                attitude.lin = time_scale * l / j_max;
                attitude.angle = Angle::Periodic {
                    n,
                    mc,
                    beta,
                    pi_minus_k,
                    per_half,
                    offset: 0.0,
                    half_periods0: at_start.reduced.half_periods,
                };
                let offset = attitude.periodic(orbit, &at_start);
                if let Angle::Periodic { offset: o, .. } = &mut attitude.angle {
                    *o = offset;
                }
            }
            Shape::Separatrix => {
                let nu = (-n).sqrt();
                attitude.lin = time_scale * (l / j3 + c * orbit.rate_scaled / (1.0 - n));
                attitude.angle = Angle::Separatrix {
                    nu,
                    coefficient: c * nu / (1.0 - n),
                    offset: 0.0,
                };
                let offset = attitude.periodic(orbit, &at_start);
                if let Angle::Separatrix { offset: o, .. } = &mut attitude.angle {
                    *o = offset;
                }
            }
        }
        attitude
    }

    /// The orientation (internal frame) at time t, given the orbit there.
    pub(super) fn orientation(&self, orbit: &Orbit, point: &Point, t: f64) -> Quat {
        let psi = self.psi(orbit, point, t);
        let (s, c) = (0.5 * psi).sin_cos();
        let m = smallest_rotation(orbit, point);
        let sigma = orbit.sigma;
        // R_n(ψ) ⊗ M with R = (c, 0, 0, σs) and M = (m₀, m₁, m₂, 0).
        let rm = [
            c * m[0],
            c * m[1] - sigma * s * m[2],
            c * m[2] + sigma * s * m[1],
            sigma * s * m[0],
        ];
        mul(self.q0, rm)
    }

    pub(super) fn psi(&self, orbit: &Orbit, point: &Point, t: f64) -> f64 {
        let linear = self.lin * t;
        match &self.angle {
            Angle::Uniform => linear,
            Angle::Periodic {
                per_half,
                offset,
                half_periods0,
                ..
            } => {
                linear
                    + (point.reduced.half_periods - half_periods0) * per_half
                    + (self.periodic(orbit, point) - offset)
            }
            Angle::Separatrix { offset, .. } => linear + (self.periodic(orbit, point) - offset),
        }
    }

    /// C g(r) − ε Θ(r): the bounded part of ψ within the current half period.
    fn periodic(&self, orbit: &Orbit, point: &Point) -> f64 {
        let theta = (self.kappa * point.sn).atan2(point.cn);
        match &self.angle {
            Angle::Uniform => 0.0,
            Angle::Periodic {
                n,
                mc,
                beta,
                pi_minus_k,
                ..
            } => {
                let r = point.reduced.r;
                let g_abs = match point.quarter {
                    Some(q) => (1.0 - beta) * r.abs() + p_tilde(*n, *mc, *pi_minus_k, &q),
                    None => (1.0 - beta) * r.abs(),
                };
                let g = if r.is_sign_negative() { -g_abs } else { g_abs };
                self.c * g - orbit.eps * theta
            }
            Angle::Separatrix {
                nu, coefficient, ..
            } => coefficient * (nu * point.sn).atan() - theta,
        }
    }
}

/// P(|r|) − |r| from the relatively accurate functions at |r| or at K − |r|.
fn p_tilde(n: f64, mc: f64, pi_minus_k: f64, q: &elliptic::Quarter) -> f64 {
    if n == 0.0 {
        return 0.0;
    }
    let (s, c, d) = (q.sn, q.cn, q.dn);
    let (s2, c2, d2) = (s * s, c * c, d * d);
    if q.reflected {
        let one_n = 1.0 - n;
        let rj = carlson::rj(c2, d2, 1.0, (d2 - n * c2) / one_n);
        pi_minus_k - (q.arg * n / one_n - n * mc * s * s2 * rj / (3.0 * one_n * one_n))
    } else {
        n / 3.0 * s * s2 * carlson::rj(c2, d2, 1.0, 1.0 - n * s2)
    }
}

/// M(t) ∝ (|L| + |L₃|, σL₂, −σL₁, 0): the smallest rotation taking l̂ to σe₃.
fn smallest_rotation(orbit: &Orbit, point: &Point) -> Quat {
    let [j1, j2, j3] = orbit.j;
    let [w1, w2, w3] = point.omega;
    let (l1, l2, l3) = (j1 * w1, j2 * w2, j3 * w3);
    let sigma = orbit.sigma;
    let v = [orbit.l_norm + l3.abs(), sigma * l2, -sigma * l1, 0.0];
    let inv = 1.0 / (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    [v[0] * inv, v[1] * inv, v[2] * inv, 0.0]
}
