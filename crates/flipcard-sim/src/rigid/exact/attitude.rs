//! The exact orientation q(t), body → space, in the internal frame.
//!
//! Write l̂ = L_body/|L| and n = σ e₃ (σ = sign ω₃, so n·l̂ = |L₃|/|L| > 0
//! along the whole orbit). Let M(t) be the smallest rotation taking l̂(t) to
//! n, as a quaternion M ∝ (|L| + |L₃|, σL₂, −σL₁, 0). Then
//!
//!   q(t) = M(0)⁻¹ ⊗ R_n(ψ(t)) ⊗ M(t),
//!
//! because q(t) l̂(t) = M(0)⁻¹ n = l̂(0) is the constant space-frame L, and
//! only the angle ψ about n is left. Matching body angular velocities,
//! ω = ω_M + ψ̇ l̂, where the twist of the smallest rotation is
//! ω_M·l̂ = n·(l̂ × l̂̇)/(1 + n·l̂); with l̂̇ = l̂ × ω (Euler's equations),
//!
//!   ψ̇ = (2T/|L| + n·ω)/(1 + n·l̂) = (2T + |L|A₃ dn u)/(|L| + β dn u)
//!      = |L|/J₃ + (D₃/(J₃β)) / (ρ + dn u),      β = J₃A₃, ρ = |L|/β ≥ 1.
//!
//! Integrating 1/(ρ + dn) through the amplitude (Π(n; am u) and an arctangent)
//! would split this smooth integrand into two sharp, nearly cancelling
//! pieces whenever L passes close to the pole n (needle-like bodies). The
//! descending Landen transformation avoids that: with k₁ = (1 − k')/(1 + k'),
//! v = u/(1 + k₁) and s₁ = sn(v | k₁²), dn(u) = (1 − k₁s₁²)/(1 + k₁s₁²), so
//!
//!   ∫₀ᵘ dw/(ρ + dn w) = (1 + k₁)/(ρ + 1) · [v + 2k₁/(ρ + 1) · G(v)],
//!   G(v) = ∫₀ᵛ s₁²/(1 − N₁s₁²) = (1/3) s₁³ R_J(c₁², d₁², 1, 1 − N₁s₁²),
//!   N₁ = −k₁(ρ − 1)/(ρ + 1) ∈ (−1, 0],
//!
//! a sum of positive terms. Near the quarter period the reflected form about
//! K₁ keeps relative accuracy (see [`g_reduced`]). ψ is then its mean rate
//! times t plus a bounded periodic part. The mean rate is |L|/J₃ plus a
//! positive term when J₃ is the largest moment; when J₃ is the smallest the
//! two terms nearly cancel for needle-like bodies, so the mean of the
//! (positive) ψ̇ is taken by the trapezoidal rule over one period instead,
//! which converges geometrically because ψ̇ is analytic in |Im u| < K'.
//! Every sign here is checked against Euler's equations and the constancy
//! of q (Iω) q⁻¹ in the tests.

use super::orbit::{Orbit, Point, Shape};
use crate::rigid::elliptic::{Jacobi, carlson};

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

// One per solver, read on every evaluation: boxing the large variant
// would only add an indirection.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone)]
enum Angle {
    /// Symmetric top: ψ̇ = |L|/J₁ − ελ is constant.
    Uniform,
    /// Asymmetric body off the separatrix: ψ = lin t + scale (G̃(r₁) − G̃(r₁₀)),
    /// G̃ the periodic part of G, r₁ = r/(1 + k₁) the reduced Landen phase.
    Landen {
        jacobi1: Jacobi,
        k1: f64,
        /// K₁ = K/(1 + k₁), N₁, G(K₁) and G(K₁)/K₁.
        quarter1: f64,
        n1: f64,
        g_quarter: f64,
        g_slope: f64,
        scale: f64,
        offset: f64,
    },
    /// On the separatrix the integral is elementary: with dn = sech,
    /// ∫ du/(ρ + sech u) = u/ρ − (2/(ρ√(ρ²−1))) atan(√((ρ−1)/(ρ+1)) tanh(u/2)).
    Separatrix {
        /// √((ρ−1)/(ρ+1)) and the coefficient of the arctangent in ψ.
        ratio: f64,
        scale: f64,
        offset: f64,
    },
}

/// Everything ψ(t) and M(t) need beyond the orbit, computed once.
#[derive(Debug, Clone)]
pub(super) struct Attitude {
    /// Mean rate of ψ, in the caller's time.
    lin: f64,
    angle: Angle,
    /// M(0)⁻¹.
    q0: Quat,
}

impl Attitude {
    pub(super) fn new(orbit: &Orbit, time_scale: f64) -> Attitude {
        let [j1, _, j3] = orbit.j;
        let l = orbit.l_norm;
        let at_start = orbit.point(0.0);
        let m0 = smallest_rotation(orbit, &at_start);
        let q0 = [m0[0], -m0[1], -m0[2], -m0[3]];
        let beta = j3 * orbit.amp[2].abs();
        // ρ − 1 = (|L|² − β²)/(β(|L| + β)) with |L|² − β² = J₁D₃/(J₃ − J₁) ≥ 0.
        let rho_minus_1 = j1 * orbit.big_d3 / orbit.d31 / (beta * (l + beta));
        let rho_plus_1 = 2.0 + rho_minus_1;
        // ψ̇ = |L|/J₃ + coefficient / (ρ + dn), in scaled time.
        let coefficient = orbit.big_d3 / (j3 * beta);
        let (lin_scaled, angle) = match &orbit.shape {
            Shape::Circular => (l / j1 - orbit.eps * orbit.rate_scaled, Angle::Uniform),
            Shape::Elliptic { jacobi, m } => {
                let kc = jacobi.kc();
                let k1 = m / ((1.0 + kc) * (1.0 + kc));
                let mc1 = 4.0 * kc / ((1.0 + kc) * (1.0 + kc));
                let n1 = -k1 * rho_minus_1 / rho_plus_1;
                let quarter1 = jacobi.k() / (1.0 + k1);
                let g_quarter = carlson::rj(0.0, mc1, 1.0, 1.0 - n1) / 3.0;
                let g_slope = g_quarter / quarter1;
                let mean = if orbit.eps > 0.0 {
                    let f_mean = (1.0 + 2.0 * k1 / rho_plus_1 * g_slope) / rho_plus_1;
                    l / j3 + coefficient * f_mean
                } else {
                    mean_rate(orbit, jacobi, beta)
                };
                let scale = coefficient / orbit.rate_scaled * (1.0 + k1) * 2.0 * k1
                    / (rho_plus_1 * rho_plus_1);
                let angle = Angle::Landen {
                    jacobi1: Jacobi::new(mc1),
                    k1,
                    quarter1,
                    n1,
                    g_quarter,
                    g_slope,
                    scale,
                    offset: 0.0,
                };
                (mean, angle)
            }
            Shape::Separatrix => {
                // ρ² − 1 = (ρ − 1)(ρ + 1)
                let root = (rho_minus_1 * rho_plus_1).sqrt();
                let rho = 1.0 + rho_minus_1;
                let angle = Angle::Separatrix {
                    ratio: (rho_minus_1 / rho_plus_1).sqrt(),
                    scale: -2.0 * coefficient / (orbit.rate_scaled * rho * root),
                    offset: 0.0,
                };
                (l / j3 + coefficient / rho, angle)
            }
        };
        let mut attitude = Attitude {
            lin: time_scale * lin_scaled,
            angle,
            q0,
        };
        let start = attitude.periodic(&at_start);
        match &mut attitude.angle {
            Angle::Landen { offset, .. } | Angle::Separatrix { offset, .. } => *offset = start,
            Angle::Uniform => {}
        }
        attitude
    }

    /// The orientation (internal frame) at time t, given the orbit there.
    pub(super) fn orientation(&self, orbit: &Orbit, point: &Point, t: f64) -> Quat {
        let psi = self.psi(point, t);
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

    fn psi(&self, point: &Point, t: f64) -> f64 {
        let linear = self.lin * t;
        match &self.angle {
            Angle::Uniform => linear,
            Angle::Landen { offset, .. } | Angle::Separatrix { offset, .. } => {
                linear + (self.periodic(point) - offset)
            }
        }
    }

    /// The bounded part of ψ at this point of the orbit.
    fn periodic(&self, point: &Point) -> f64 {
        match &self.angle {
            Angle::Uniform => 0.0,
            Angle::Landen {
                jacobi1,
                k1,
                quarter1,
                n1,
                g_quarter,
                g_slope,
                scale,
                ..
            } => {
                let r1 = point.reduced.r / (1.0 + k1);
                let g = g_reduced(jacobi1, *quarter1, *n1, *g_quarter, r1);
                scale * (g - g_slope * r1)
            }
            Angle::Separatrix { ratio, scale, .. } => {
                let u = point.reduced.r;
                scale * (ratio * (0.5 * u).tanh()).atan()
            }
        }
    }
}

/// G(r) = ∫₀ʳ s²/(1 − N s²) at the Landen level for |r| ≤ K₁, from the
/// functions at |r| or, past K₁/2, at w = K₁ − |r|, where
/// G(K₁ − w) = G(K₁) − [w − m_c₁/(1−N) · (1/3) sn³w R_J(cn²w, dn²w, 1, (dn²w − N cn²w)/(1 − N))]/(1 − N).
fn g_reduced(jacobi1: &Jacobi, quarter1: f64, n1: f64, g_quarter: f64, r: f64) -> f64 {
    let ra = r.abs();
    let value = if ra <= 0.5 * quarter1 {
        let q = jacobi1.quarter(ra);
        let s2 = q.sn * q.sn;
        q.sn * s2 * carlson::rj(q.cn * q.cn, q.dn * q.dn, 1.0, 1.0 - n1 * s2) / 3.0
    } else {
        let w = (quarter1 - ra).max(0.0);
        let q = jacobi1.quarter(w);
        let (s2, c2, d2) = (q.sn * q.sn, q.cn * q.cn, q.dn * q.dn);
        let one_n = 1.0 - n1;
        let rj = carlson::rj(c2, d2, 1.0, (d2 - n1 * c2) / one_n);
        g_quarter - (w - jacobi1.mc() / one_n * q.sn * s2 * rj / 3.0) / one_n
    };
    if r.is_sign_negative() { -value } else { value }
}

/// The mean of ψ̇ = (2T + |L|A₃ dn)/(|L| + β dn) over a period, by the
/// trapezoidal rule: the integrand is periodic (period 2K) and analytic in
/// the strip |Im u| < K', so the error falls like exp(−πK'N/K).
fn mean_rate(orbit: &Orbit, jacobi: &Jacobi, beta: f64) -> f64 {
    let k = jacobi.k();
    let k_prime = Jacobi::new(1.0 - jacobi.mc()).k();
    let nodes = (14.0 * k / k_prime).ceil().clamp(8.0, 1e6) as usize;
    let a3 = orbit.amp[2].abs();
    let (two_t, l) = (orbit.two_t, orbit.l_norm);
    let sum: f64 = (0..nodes)
        .map(|i| {
            let (_, _, dn) = jacobi.sncndn(2.0 * k * i as f64 / nodes as f64);
            (two_t + l * a3 * dn) / (l + beta * dn)
        })
        .sum();
    sum / nodes as f64
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed-form mean rate (used when J₃ is the largest moment) and the
    /// trapezoidal one (used when it is the smallest) agree where both apply.
    #[test]
    fn closed_form_and_quadrature_mean_rates_agree() {
        for (j, w) in [
            ([1.0, 2.0, 2.5], [0.3, 1.0, -0.8]),
            ([1.0, 2.0, 3.0], [0.01, 10.0, 0.01]),
            ([1e-6, 1.0, 1.0 + 5e-7], [1e-3, 0.4, 1.0]),
            ([3.0, 4.0, 6.0], [2.0, 0.5, 1.0 + 1e-12]),
        ] {
            let orbit = Orbit::new(j, w, 1.0);
            let Shape::Elliptic { jacobi, .. } = &orbit.shape else {
                panic!("elliptic orbit expected");
            };
            let beta = j[2] * orbit.amp[2].abs();
            let closed = Attitude::new(&orbit, 1.0).lin;
            let quadrature = mean_rate(&orbit, jacobi, beta);
            assert!(
                (closed - quadrature).abs() <= 2e-15 * closed,
                "{j:?}: {closed} vs {quadrature}"
            );
        }
    }
}
