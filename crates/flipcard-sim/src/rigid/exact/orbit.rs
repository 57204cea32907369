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
//! so m_c keeps its relative accuracy next to the separatrix (D₂ → 0).
//! D₂ = J₃(J₃−J₂)ω₃² − J₁(J₂−J₁)ω₁² is a genuine difference: its two terms
//! are evaluated in double-double, so it is exactly zero when they are equal
//! and otherwise correct to about 1e-32 of their size.

use crate::rigid::elliptic::{self, Jacobi, Reduced};

// One per solver, read on every evaluation: boxing the large variant
// would only add an indirection.
#[allow(clippy::large_enum_variant)]
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
    /// J₃ − J₁.
    pub d31: f64,
    /// sign(J₃ − J₁): +1 when ω circulates about the largest moment.
    pub eps: f64,
    /// sign ω₃, constant along the orbit.
    pub sigma: f64,
    /// |L|, 2T and D₃ = 2TJ₃ − L² (scaled).
    pub l_norm: f64,
    pub two_t: f64,
    pub big_d3: f64,
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
        let big_d2 = middle_gap(j, w1, w3);
        let big_d3 = j1 * d31 * (w1 * w1) + j2 * d32 * (w2 * w2);
        let eps = if d31 > 0.0 { 1.0 } else { -1.0 };
        let sigma = if w3 >= 0.0 { 1.0 } else { -1.0 };
        let a1 = (big_d3 / (j1 * d31)).sqrt();
        let a2 = (big_d3 / (j2 * d32)).sqrt();
        let a3 = (big_d1 / (j3 * d31)).sqrt();
        let rate_scaled = (d32 * big_d1 / (j1 * j2 * j3)).sqrt();
        let l = [j1 * w1, j2 * w2, j3 * w3];
        let l_norm = (l[0] * l[0] + l[1] * l[1] + l[2] * l[2]).sqrt();
        let two_t = j1 * (w1 * w1) + j2 * (w2 * w2) + j3 * (w3 * w3);

        let m = d21 * big_d3 / (d32 * big_d1);
        let mc = d31 * big_d2 / (d32 * big_d1);
        let (shape, amp, u0) = if m == 0.0 {
            let amp = [a1, eps * sigma * a2, sigma * a3];
            (Shape::Circular, amp, (eps * sigma * w2 / a2).atan2(w1 / a1))
        } else if mc == 0.0 {
            // Separatrix (D₂ = 0, or below the range of f64): ω₁ and ω₃
            // keep their signs s₁, s₃ for all time, and s₂ = ε s₁ s₃.
            let s1 = if w1 >= 0.0 { 1.0 } else { -1.0 };
            let s2 = eps * s1 * sigma;
            // sinh u₀ = tanh u₀ / sech u₀ = (s₂ω₂/A₂) / (|ω₁|/A₁)
            let u0 = (s2 * w2 * a1 / (a2 * w1.abs())).asinh();
            (Shape::Separatrix, [s1 * a1, s2 * a2, sigma * a3], u0)
        } else {
            let amp = [a1, eps * sigma * a2, sigma * a3];
            let cn0 = w1 / a1;
            let sn0 = eps * sigma * w2 / a2;
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
        };
        Orbit {
            j,
            d31,
            eps,
            sigma,
            l_norm,
            two_t,
            big_d3,
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
                }
            }
        }
    }
}

/// D₂ = L² − 2TJ₂ = J₃(J₃−J₂)ω₃² − J₁(J₂−J₁)ω₁², in double-double arithmetic
/// and rounded once. Near the separatrix the two terms agree to many digits;
/// in plain f64 the rounding of each product would swamp their difference.
pub(super) fn middle_gap(j: [f64; 3], w1: f64, w3: f64) -> f64 {
    let [j1, j2, j3] = j;
    let upper = dd_mul(dd_mul(dd_mul(two_sum(j3, -j2), j3), w3), w3);
    let lower = dd_mul(dd_mul(dd_mul(two_sum(j2, -j1), j1), w1), w1);
    let (hi, lo) = dd_add(upper, (-lower.0, -lower.1));
    hi + lo
}

/// a + b = s + e exactly.
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

fn quick_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    (s, b - (s - a))
}

/// A double-double times a double.
fn dd_mul((hi, lo): (f64, f64), b: f64) -> (f64, f64) {
    let p = hi * b;
    let e = hi.mul_add(b, -p) + lo * b;
    quick_two_sum(p, e)
}

fn dd_add(a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    let (s1, s2) = two_sum(a.0, b.0);
    let (t1, t2) = two_sum(a.1, b.1);
    let (s1, s2) = quick_two_sum(s1, s2 + t1);
    quick_two_sum(s1, s2 + t2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn middle_gap_resolves_what_plain_products_lose() {
        // I = (3, 4, 6), ω = (2, ·, 1): both terms are 12 exactly.
        assert_eq!(middle_gap([3.0, 4.0, 6.0], 2.0, 1.0), 0.0);
        // ω₃ = 1 − 1e-12 (as a double): D₂ = 12(ω₃² − 1), which needs ω₃²
        // beyond double precision.
        let w3: f64 = 0.999999999999;
        let exact = 12.0 * ((w3 - 1.0) * (w3 + 1.0));
        let gap = middle_gap([3.0, 4.0, 6.0], 2.0, w3);
        assert!(
            (gap - exact).abs() < 1e-15 * exact.abs(),
            "{gap:e} vs {exact:e}"
        );
        let naive = 6.0 * 2.0 * (w3 * w3) - 3.0 * 1.0 * 4.0;
        assert!((naive - exact).abs() > 1e-6 * exact.abs());
        // L² − 2TJ₂ does not depend on the frame: reversing the axes gives
        // the same value to the last bit, so both orderings agree on the regime.
        assert_eq!(middle_gap([6.0, 4.0, 3.0], w3, 2.0), gap);
    }
}
