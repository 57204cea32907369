//! ω(t) in the internal frame: Jacobi elliptic functions, their circular
//! limit (symmetric top) and their hyperbolic limit (separatrix).
//!
//! With internal moments J₁, J₂, J₃ (axis 3 the one ω circulates about, axis
//! 2 the middle one, so J₁ < J₂ < J₃ or J₁ > J₂ > J₃), ε = sign(J₃ − J₁) and
//! σ = sign ω₃ (constant along the orbit):
//!
//!   ω₁ = A₁ cn u,   ω₂ = εσ A₂ sn u,   ω₃ = σ A₃ dn u,   u = u₀ + λt,
//!
//! where, with D₁ = L² − 2TJ₁, D₃ = 2TJ₃ − L², D₂ = L² − 2TJ₂,
//!
//!   A₁² = D₃ / (J₁(J₃−J₁)),  A₂² = D₃ / (J₂(J₃−J₂)),  A₃² = D₁ / (J₃(J₃−J₁)),
//!   λ² = (J₃−J₂) D₁ / (J₁J₂J₃),
//!   m = (J₂−J₁) D₃ / ((J₃−J₂) D₁),  m_c = (J₃−J₁) D₂ / ((J₃−J₂) D₁).
//!
//! Every ratio is positive in both orderings. The signs follow from
//! substituting into Euler's equations (d sn = cn dn, d cn = −sn dn,
//! d dn = −m sn cn): J₁ω̇₁ = (J₂−J₃)ω₂ω₃ forces s₁ = ε s₂ s₃, and cyclically.
//! The D's are never formed as differences of L² and 2TJ: each is expanded
//! into inertia differences times ω², e.g. D₁ = J₂(J₂−J₁)ω₂² + J₃(J₃−J₁)ω₃²,
//! so m_c keeps its relative accuracy next to the separatrix (D₂ → 0), and
//! D₂ = J₃(J₃−J₂)ω₃² − J₁(J₂−J₁)ω₁² is exactly zero when the products are.

use crate::sim::elliptic::{self, Jacobi, Quarter, Reduced};

#[derive(Debug, Clone)]
pub(super) enum Shape {
    /// m = 0 exactly (two equal moments): sin, cos, 1.
    Circular,
    /// 0 < m < 1.
    Elliptic { jacobi: Jacobi, m: f64 },
    /// m = 1 (D₂ = 0): sn = tanh, cn = dn = sech; the middle axis is
    /// approached forever and never crossed.
    Separatrix,
}

/// One trajectory of Euler's equations in the internal frame, in units where
/// the largest moment and the largest |ω₀ᵢ| are of order one.
#[derive(Debug, Clone)]
pub(super) struct Orbit {
    /// Internal moments J₁, J₂, J₃ (scaled).
    pub j: [f64; 3],
    /// J₂ − J₁, J₃ − J₁, J₃ − J₂.
    pub d21: f64,
    pub d31: f64,
    pub d32: f64,
    /// sign(J₃ − J₁): +1 when ω circulates about the largest moment.
    pub eps: f64,
    /// sign ω₃, constant along the orbit.
    pub sigma: f64,
    /// |L| (scaled).
    pub l_norm: f64,
    /// Signed amplitudes of ω₁ (cn), ω₂ (sn), ω₃ (dn) (scaled).
    pub amp: [f64; 3],
    /// λ in scaled time, and λ in the caller's time (λ̂ × time scale).
    pub rate_scaled: f64,
    pub rate: f64,
    pub u0: f64,
    pub shape: Shape,
}

/// The orbit at one instant.
#[derive(Debug, Clone, Copy)]
pub(super) struct Point {
    /// ω in the internal frame (scaled).
    pub omega: [f64; 3],
    /// The phase u = 2jK + r (Circular: j = 0, r = u; Separatrix: likewise).
    pub reduced: Reduced,
    /// sn r and cn r (cn r ≥ 0 when elliptic).
    pub sn: f64,
    pub cn: f64,
    /// The relatively accurate functions behind sn r, cn r (elliptic only).
    pub quarter: Option<Quarter>,
}

impl Orbit {
    /// `j` and `w`: internal moments and ω₀ (scaled) of a body that is not
    /// in steady rotation, ordered so that D₂ ≥ 0 when J₃ is the largest
    /// moment and D₂ < 0 when it is the smallest. `time_scale` converts the
    /// rate back to the caller's time.
    pub(super) fn new(j: [f64; 3], w: [f64; 3], time_scale: f64) -> Orbit {
        let [j1, j2, j3] = j;
        let [w1, w2, w3] = w;
        let d21 = j2 - j1;
        let d31 = j3 - j1;
        let d32 = j3 - j2;
        let big_d1 = j2 * d21 * (w2 * w2) + j3 * d31 * (w3 * w3);
        let big_d2 = j3 * d32 * (w3 * w3) - j1 * d21 * (w1 * w1);
        let big_d3 = j1 * d31 * (w1 * w1) + j2 * d32 * (w2 * w2);
        let eps = if d31 > 0.0 { 1.0 } else { -1.0 };
        let sigma = if w3 >= 0.0 { 1.0 } else { -1.0 };
        let a1 = (big_d3 / (j1 * d31)).sqrt();
        let a2 = (big_d3 / (j2 * d32)).sqrt();
        let a3 = (big_d1 / (j3 * d31)).sqrt();
        let rate_scaled = (d32 * big_d1 / (j1 * j2 * j3)).sqrt();
        let l = [j1 * w1, j2 * w2, j3 * w3];
        let l_norm = (l[0] * l[0] + l[1] * l[1] + l[2] * l[2]).sqrt();

        let (shape, amp, u0) = if big_d2 == 0.0 {
            // Separatrix (only reached with J₁ < J₂ < J₃): ω₁ and ω₃ keep
            // their signs s₁, s₃ for all time, and s₂ = s₁ s₃.
            let s1 = if w1 >= 0.0 { 1.0 } else { -1.0 };
            let s2 = s1 * sigma;
            // sinh u₀ = tanh u₀ / sech u₀ = (s₂ω₂/A₂) / (|ω₁|/A₁)
            let u0 = (s2 * w2 * a1 / (a2 * w1.abs())).asinh();
            (Shape::Separatrix, [s1 * a1, s2 * a2, sigma * a3], u0)
        } else {
            let m = d21 * big_d3 / (d32 * big_d1);
            let mc = d31 * big_d2 / (d32 * big_d1);
            let amp = [a1, eps * sigma * a2, sigma * a3];
            let cn0 = w1 / a1;
            let sn0 = eps * sigma * w2 / a2;
            if m == 0.0 {
                (Shape::Circular, amp, sn0.atan2(cn0))
            } else {
                let jacobi = Jacobi::new(mc);
                let dn0 = w3.abs() / a3;
                // u₀ = F(φ₀ | m) with φ₀ = atan2(sn₀, cn₀) ∈ (−π, π]; from the
                // squares directly, so that small cn₀, dn₀ keep their digits.
                let base = elliptic::incomplete_f(sn0, cn0 * cn0, dn0 * dn0);
                let u0 = if cn0 >= 0.0 {
                    base
                } else {
                    (2.0 * jacobi.k()).copysign(sn0) - base
                };
                (Shape::Elliptic { jacobi, m }, amp, u0)
            }
        };
        Orbit {
            j,
            d21,
            d31,
            d32,
            eps,
            sigma,
            l_norm,
            amp,
            rate_scaled,
            rate: rate_scaled * time_scale,
            u0,
            shape,
        }
    }

    /// The parameter m and its complement m_c.
    pub(super) fn parameter(&self) -> (f64, f64) {
        match &self.shape {
            Shape::Circular => (0.0, 1.0),
            Shape::Elliptic { jacobi, m } => (*m, jacobi.mc()),
            Shape::Separatrix => (1.0, 0.0),
        }
    }

    /// K(m): π/2 for the symmetric top, ∞ on the separatrix.
    pub(super) fn quarter_period_phase(&self) -> f64 {
        match &self.shape {
            Shape::Circular => std::f64::consts::FRAC_PI_2,
            Shape::Elliptic { jacobi, .. } => jacobi.k(),
            Shape::Separatrix => f64::INFINITY,
        }
    }

    pub(super) fn point(&self, t: f64) -> Point {
        let u = self.u0 + self.rate * t;
        let [a1, a2, a3] = self.amp;
        match &self.shape {
            Shape::Circular => {
                // sin_cos reduces huge phases exactly; no need to fold.
                let (sn, cn) = u.sin_cos();
                Point {
                    omega: [a1 * cn, a2 * sn, a3],
                    reduced: Reduced {
                        half_periods: 0.0,
                        r: u,
                    },
                    sn,
                    cn,
                    quarter: None,
                }
            }
            Shape::Elliptic { jacobi, .. } => {
                let reduced = jacobi.reduce(u);
                let quarter = jacobi.quarter(reduced.r);
                let (sn_abs, cn, dn) = jacobi.at_point(&quarter);
                let sn = if reduced.r.is_sign_negative() {
                    -sn_abs
                } else {
                    sn_abs
                };
                let parity = reduced.parity();
                Point {
                    omega: [a1 * parity * cn, a2 * parity * sn, a3 * dn],
                    reduced,
                    sn,
                    cn,
                    quarter: Some(quarter),
                }
            }
            Shape::Separatrix => {
                let sn = u.tanh();
                let cn = 1.0 / u.cosh();
                Point {
                    omega: [a1 * cn, a2 * sn, a3 * cn],
                    reduced: Reduced {
                        half_periods: 0.0,
                        r: u,
                    },
                    sn,
                    cn,
                    quarter: None,
                }
            }
        }
    }
}
