//! Jacobi elliptic functions sn, cn, dn and the complete integral K, all
//! parametrised by the complementary parameter m_c = 1 − m.
//!
//! Near the separatrix of the rigid body m → 1 and everything of interest
//! lives in m_c, which the caller computes directly from inertia differences;
//! forming 1 − m here would throw those digits away. The functions come from
//! the descending Gauss–Landen (AGM) transformation in Bulirsch's form: the
//! AGM ladder depends only on m_c, so [`Jacobi`] builds it once and each
//! evaluation costs one `sin_cos` plus a short backward recursion.
//!
//! Accuracy: on 0 ≤ u ≤ K/2 every quantity in the recursion is positive, so
//! sn, cn and dn come out with a few ulps of *relative* error each, even
//! where cn and dn are as small as √m_c. Larger arguments are folded onto
//! that range (periodicity, parity, and the quarter-period shift
//! sn(K − w) = cd w, cn(K − w) = √m_c sd w, dn(K − w) = √m_c nd w), so the
//! relative accuracy carries over up to the rounding of the argument itself.

pub(crate) mod carlson;

use std::f64::consts::FRAC_PI_2;

/// Below this argument the Maclaurin series is exact to the last bit, and the
/// recursion (which divides by sin u) would overflow for tiny u.
const SMALL_ARGUMENT: f64 = 1.0 / 67_108_864.0; // 2^-26

/// The AGM stops when a and b agree to this relative tolerance; one more
/// arithmetic mean is then exact to rounding (quadratic convergence).
const AGM_TOLERANCE: f64 = 1e-8;

/// AGM steps for any m_c down to the smallest subnormal need at most 14.
const MAX_LEVELS: usize = 20;

/// The Gauss–Landen ladder for one value of m_c, with K(m).
#[derive(Debug, Clone)]
pub(crate) struct Jacobi {
    mc: f64,
    kc: f64,
    levels: usize,
    /// Arithmetic means a₀ = 1, a₁, … and their reciprocals.
    a: [f64; MAX_LEVELS],
    a_inv: [f64; MAX_LEVELS],
    /// Geometric means b₀ = √m_c, b₁, …
    b: [f64; MAX_LEVELS],
    /// AGM(1, √m_c) = π / (2K).
    agm: f64,
    k: f64,
    /// 1 / (2K), 0 on the separatrix.
    inv_half_period: f64,
}

/// sn, cn, dn at |r| for a reduced phase, each relatively accurate. When the
/// point lies in the upper half of the quarter period the values are those
/// at w = K − |r| instead, from which the caller can form well-conditioned
/// integrals; [`Jacobi::at_point`] converts back.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Quarter {
    /// `false`: `arg` = |r| ≤ K/2; `true`: `arg` = w = K − |r| < K/2.
    pub reflected: bool,
    pub arg: f64,
    pub sn: f64,
    pub cn: f64,
    pub dn: f64,
}

/// A phase u split as u = 2jK + r with |r| ≤ K.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Reduced {
    /// Number of half periods 2K (an integer, kept as f64 for huge phases).
    pub half_periods: f64,
    pub r: f64,
}

impl Reduced {
    /// −1 when an odd number of half periods was removed (sn and cn change
    /// sign every 2K), +1 otherwise.
    pub(crate) fn parity(&self) -> f64 {
        let j = self.half_periods;
        let odd = if j.abs() < 9.0e15 {
            (j as i64) & 1 == 1
        } else {
            j.rem_euclid(2.0) == 1.0
        };
        if odd { -1.0 } else { 1.0 }
    }
}

impl Jacobi {
    /// The ladder for 0 ≤ m_c ≤ 1 (m_c = 0 is the separatrix, where
    /// sn = tanh, cn = dn = sech and K = ∞). Values outside are clamped.
    pub(crate) fn new(mc: f64) -> Jacobi {
        let mc = if mc.is_nan() { 0.0 } else { mc.clamp(0.0, 1.0) };
        let mut jacobi = Jacobi {
            mc,
            kc: mc.sqrt(),
            levels: 0,
            a: [0.0; MAX_LEVELS],
            a_inv: [0.0; MAX_LEVELS],
            b: [0.0; MAX_LEVELS],
            agm: 0.0,
            k: f64::INFINITY,
            inv_half_period: 0.0,
        };
        if mc == 0.0 {
            return jacobi;
        }
        let mut a = 1.0;
        let mut b = jacobi.kc;
        let mut mean = 0.5 * (a + b);
        for level in 0..MAX_LEVELS {
            jacobi.a[level] = a;
            jacobi.a_inv[level] = 1.0 / a;
            jacobi.b[level] = b;
            jacobi.levels = level + 1;
            mean = 0.5 * (a + b);
            if (a - b).abs() <= AGM_TOLERANCE * a {
                break;
            }
            b = (a * b).sqrt();
            a = mean;
        }
        jacobi.agm = mean;
        jacobi.k = FRAC_PI_2 / mean;
        jacobi.inv_half_period = 0.5 / jacobi.k;
        jacobi
    }

    /// The complementary parameter m_c = 1 − m.
    pub(crate) fn mc(&self) -> f64 {
        self.mc
    }

    /// √m_c = k'.
    pub(crate) fn kc(&self) -> f64 {
        self.kc
    }

    /// The complete integral K(m) (∞ on the separatrix).
    pub(crate) fn k(&self) -> f64 {
        self.k
    }

    /// Splits u = 2jK + r with |r| ≤ K.
    pub(crate) fn reduce(&self, u: f64) -> Reduced {
        if !self.k.is_finite() {
            return Reduced {
                half_periods: 0.0,
                r: u,
            };
        }
        let half = 2.0 * self.k;
        let j = round_to_integer(u * self.inv_half_period);
        Reduced {
            half_periods: j,
            r: u - j * half,
        }
    }

    /// The three functions at |r| for |r| ≤ K, evaluated on whichever side
    /// of K/2 keeps them relatively accurate.
    pub(crate) fn quarter(&self, r: f64) -> Quarter {
        let ra = r.abs();
        if ra <= 0.5 * self.k {
            let (sn, cn, dn) = self.landen(ra);
            Quarter {
                reflected: false,
                arg: ra,
                sn,
                cn,
                dn,
            }
        } else {
            let w = (self.k - ra).max(0.0);
            let (sn, cn, dn) = self.landen(w);
            Quarter {
                reflected: true,
                arg: w,
                sn,
                cn,
                dn,
            }
        }
    }

    /// sn, cn, dn at |r| (not at `arg`) from a [`Quarter`]: when reflected,
    /// sn(K − w) = cd w = 1 − m_c sn²w / (dn w (dn w + cn w)) (so its distance
    /// from 1 keeps its digits), cn(K − w) = √m_c sd w, dn(K − w) = √m_c nd w.
    pub(crate) fn at_point(&self, q: &Quarter) -> (f64, f64, f64) {
        if q.reflected {
            let inv = 1.0 / q.dn;
            let sn = 1.0 - self.mc * q.sn * q.sn * inv / (q.dn + q.cn);
            (sn, self.kc * q.sn * inv, self.kc * inv)
        } else {
            (q.sn, q.cn, q.dn)
        }
    }

    /// sn(u), cn(u), dn(u) for any real u.
    pub(crate) fn sncndn(&self, u: f64) -> (f64, f64, f64) {
        let reduced = self.reduce(u);
        let (sn, cn, dn) = self.at_point(&self.quarter(reduced.r));
        let parity = reduced.parity();
        (parity * sn.copysign(reduced.r), parity * cn, dn)
    }

    /// Bulirsch's backward recursion; relatively accurate for 0 ≤ u ≤ K/2.
    fn landen(&self, u: f64) -> (f64, f64, f64) {
        if self.mc == 0.0 {
            let sech = 1.0 / u.cosh();
            return (u.tanh(), sech, sech);
        }
        if u.abs() < SMALL_ARGUMENT {
            let u2 = u * u;
            return (u, 1.0 - 0.5 * u2, 1.0 - 0.5 * (1.0 - self.mc) * u2);
        }
        let (s, c) = sin_cos_octant(u * self.agm);
        if s == 0.0 {
            return (s, c, 1.0);
        }
        let mut a = c / s;
        let mut ratio = self.agm * a;
        let mut dn = 1.0;
        for level in (0..self.levels).rev() {
            a *= ratio;
            ratio *= dn;
            dn = (self.b[level] + a) / (self.a[level] + a);
            a = ratio * self.a_inv[level];
        }
        let sn = (1.0 / (ratio * ratio + 1.0).sqrt()).copysign(s);
        (sn, ratio * sn, dn)
    }
}

/// Nearest integer (ties to even) without a library call: adding and
/// removing 1.5·2⁵² leaves the rounded value for |x| < 2⁵¹.
fn round_to_integer(x: f64) -> f64 {
    const MAGIC: f64 = 6_755_399_441_055_744.0;
    if x.abs() < 2_251_799_813_685_248.0 {
        (x + MAGIC) - MAGIC
    } else {
        x.round()
    }
}

/// sin x and cos x for 0 ≤ x ≤ π/4 (the Landen phase of a point within K/2)
/// by their Taylor polynomials, truncated below 1e-22: no range reduction.
fn sin_cos_octant(x: f64) -> (f64, f64) {
    let x2 = x * x;
    // sin x = x Σ (−x²)ᵏ/(2k+1)!, cos x = 1 − x² Σ (−x²)ᵏ/(2k+2)!, k ≤ 9.
    let mut s = INV_FACTORIAL[19];
    let mut c = INV_FACTORIAL[20];
    for k in (0..9).rev() {
        s = INV_FACTORIAL[2 * k + 1] - x2 * s;
        c = INV_FACTORIAL[2 * k + 2] - x2 * c;
    }
    (x * s, 1.0 - x2 * c)
}

/// 1/n! for n = 0 … 20.
const INV_FACTORIAL: [f64; 21] = {
    let mut table = [1.0; 21];
    let mut factorial = 1.0;
    let mut n = 1;
    while n < 21 {
        factorial *= n as f64;
        table[n] = 1.0 / factorial;
        n += 1;
    }
    table
};

/// K(m) = π / (2 AGM(1, √m_c)) given m_c = 1 − m.
pub(crate) fn complete_k(mc: f64) -> f64 {
    Jacobi::new(mc).k()
}

/// Π(n | m) − K(m) = (n/3) R_J(0, m_c, 1, 1 − n), for n < 1 and m_c > 0:
/// the part of the complete third-kind integral beyond K, without forming
/// the difference.
#[cfg(test)]
pub(crate) fn complete_pi_minus_k(n: f64, mc: f64) -> f64 {
    if n == 0.0 {
        return 0.0;
    }
    n / 3.0 * carlson::rj(0.0, mc, 1.0, 1.0 - n)
}

/// F(φ | m) for |φ| ≤ π/2 from sin φ, cos²φ and Δ² = 1 − m sin²φ supplied
/// separately (so Δ² = cos²φ + m_c sin²φ keeps its relative accuracy).
pub(crate) fn incomplete_f(sin_phi: f64, cos2: f64, delta2: f64) -> f64 {
    sin_phi * carlson::rf(cos2, delta2, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn assert_close(got: f64, want: f64, abs: f64, rel: f64, what: &str) {
        let err = (got - want).abs();
        assert!(
            err <= abs || err <= rel * want.abs(),
            "{what}: got {got:e}, want {want:e}, error {err:e}"
        );
    }

    #[test]
    fn matches_reference_table() {
        for &(u, mc, sn, cn, dn) in super::reference::TABLE {
            let jac = Jacobi::new(mc);
            let (s, c, d) = jac.sncndn(u);
            let what = format!("u = {u}, m_c = {mc:e}");
            // Absolute accuracy everywhere (the argument's own rounding
            // limits it near the zeros of cn), relative inside the quarter.
            // The period removed from u carries K's rounding: ε|u| more.
            let (abs, rel) = (4.0 * f64::EPSILON * (1.0 + u.abs()), 6.0 * f64::EPSILON);
            assert_close(s, sn, abs, rel, &format!("sn {what}"));
            assert_close(c, cn, abs, rel, &format!("cn {what}"));
            assert_close(d, dn, abs, rel, &format!("dn {what}"));
            if u.abs() <= 0.5 * jac.k() {
                // Relative accuracy inside the quarter, up to the condition
                // number ~|u| of the functions with respect to u itself.
                let rel = rel * (1.0 + u.abs());
                assert_close(s, sn, 0.0, rel, &format!("sn (relative) {what}"));
                assert_close(c, cn, 0.0, rel, &format!("cn (relative) {what}"));
                assert_close(d, dn, 0.0, rel, &format!("dn (relative) {what}"));
            }
        }
    }

    #[test]
    fn identities_hold_across_the_parameter_range() {
        for &mc in &[
            1.0,
            1.0 - 1e-12,
            0.7,
            0.3,
            1e-4,
            1e-16,
            1e-40,
            1e-200,
            5e-324,
        ] {
            let jac = Jacobi::new(mc);
            let m = 1.0 - mc;
            let k = jac.k();
            for i in 0..200 {
                let u = (i as f64 - 100.0) * 0.037 * k.min(50.0) + 0.01;
                let (s, c, d) = jac.sncndn(u);
                assert!(s.is_finite() && c.is_finite() && d.is_finite());
                assert!(
                    (s * s + c * c - 1.0).abs() <= 4.0 * f64::EPSILON,
                    "sn²+cn² at {u}, {mc}"
                );
                // dn² + m sn² = 1, i.e. dn² − cn² = m_c sn² (free of cancellation)
                assert!(
                    (d * d + m * s * s - 1.0).abs() <= 4.0 * f64::EPSILON,
                    "dn²+m sn² at {u}, {mc}"
                );
                assert!(d > 0.0 && d <= 1.0);
            }
        }
    }

    #[test]
    fn derivatives_match_the_differential_equations() {
        // d sn/du = cn dn, d cn/du = −sn dn, d dn/du = −m sn cn (central differences).
        for &mc in &[0.9, 0.2, 1e-6, 1e-20] {
            let jac = Jacobi::new(mc);
            let m = 1.0 - mc;
            for &u in &[0.1, 0.8, 2.5, 7.0, -3.3] {
                let h = 1e-5;
                let (sp, cp, dp) = jac.sncndn(u + h);
                let (sm, cm, dm) = jac.sncndn(u - h);
                let (s, c, d) = jac.sncndn(u);
                let tol = 1e-9;
                assert!(((sp - sm) / (2.0 * h) - c * d).abs() < tol);
                assert!(((cp - cm) / (2.0 * h) + s * d).abs() < tol);
                assert!(((dp - dm) / (2.0 * h) + m * s * c).abs() < tol);
            }
        }
    }

    #[test]
    fn octant_sine_and_cosine_match_the_library() {
        for i in 0..=1000 {
            let x = std::f64::consts::FRAC_PI_4 * i as f64 / 1000.0;
            let (s, c) = sin_cos_octant(x);
            assert!((s - x.sin()).abs() <= f64::EPSILON * x.sin(), "sin {x}");
            assert!((c - x.cos()).abs() <= f64::EPSILON * x.cos(), "cos {x}");
        }
    }

    #[test]
    fn rounding_and_parity_of_half_periods() {
        for &(x, want) in &[
            (0.5, 0.0),
            (1.5, 2.0),
            (-2.5, -2.0),
            (7.49, 7.0),
            (-3.7, -4.0),
        ] {
            assert_eq!(round_to_integer(x), want);
        }
        let odd = Reduced {
            half_periods: -3.0,
            r: 0.0,
        };
        let even = Reduced {
            half_periods: 1e17,
            r: 0.0,
        };
        assert_eq!((odd.parity(), even.parity()), (-1.0, 1.0));
    }

    #[test]
    fn complete_integral_limits() {
        assert_eq!(complete_k(1.0), FRAC_PI_2);
        // K(1/2) = Γ(1/4)² / (4√π) = 1.8540746773013719184…
        assert_close(complete_k(0.5), 1.854_074_677_301_372, 0.0, 4e-16, "K(1/2)");
        // K ≈ ln(4/k') + (m_c/4)(ln(4/k') − 1) near the separatrix.
        for &mc in &[1e-10, 1e-20, 1e-100, 1e-300] {
            let l = (4.0 / f64::sqrt(mc)).ln();
            assert_close(
                complete_k(mc),
                l + 0.25 * mc * (l - 1.0),
                0.0,
                3e-16,
                "K near m=1",
            );
        }
        assert!(complete_k(0.0).is_infinite());
        // Small m: K = π/2 (1 + m/4 + 9m²/64 + …)
        let m = 1e-9;
        assert_close(
            complete_k(1.0 - m),
            FRAC_PI_2 * (1.0 + m / 4.0 + 9.0 * m * m / 64.0),
            0.0,
            1e-15,
            "K small m",
        );
    }

    #[test]
    fn separatrix_limit_is_tanh_and_sech() {
        let jac = Jacobi::new(0.0);
        for &u in &[-30.0, -1.0, 0.0, 0.5, 4.0, 800.0] {
            let (s, c, d) = jac.sncndn(u);
            assert_eq!(s, f64::tanh(u));
            assert_eq!(c, 1.0 / f64::cosh(u));
            assert_eq!(d, c);
        }
    }

    #[test]
    fn periods_and_symmetries() {
        let jac = Jacobi::new(0.37);
        let k = jac.k();
        let (s, c, d) = jac.sncndn(k);
        assert_close(s, 1.0, 1e-15, 0.0, "sn K");
        assert_close(c, 0.0, 1e-15, 0.0, "cn K");
        assert_close(d, 0.37f64.sqrt(), 0.0, 1e-15, "dn K = k'");
        for &u in &[0.3, 1.1, 2.9] {
            let (s, c, d) = jac.sncndn(u);
            let (s4, c4, d4) = jac.sncndn(u + 4.0 * k);
            assert_close(s4, s, 1e-14, 0.0, "4K period sn");
            assert_close(c4, c, 1e-14, 0.0, "4K period cn");
            assert_close(d4, d, 1e-14, 0.0, "2K period dn");
            let (sm, cm, dm) = jac.sncndn(-u);
            assert_eq!((sm, cm, dm), (-s, c, d));
        }
        // m = 0: sin, cos, 1
        let circ = Jacobi::new(1.0);
        let (s, c, d) = circ.sncndn(2.0);
        assert_close(s, 2f64.sin(), 2e-16, 0.0, "sin");
        assert_close(c, 2f64.cos(), 2e-16, 0.0, "cos");
        assert_eq!(d, 1.0);
        assert_close(circ.k(), PI / 2.0, 0.0, 1e-16, "K(0)");
    }

    #[test]
    fn complete_third_kind_matches_independent_values() {
        // (n, m_c, Π(n | 1 − m_c)) in high precision for the exact m_c.
        for &(n, mc, want) in &[
            (-0.5, 0.5, 1.4878469926687985),
            (-3.0, 0.1, 1.0837422223440127),
            (-0.001, 0.9, 1.6116251264228962),
            (-20.0, 1e-08, 0.7922682522909351),
            (0.3, 0.6, 2.1487954158664566),
            (-7.0, 1e-100, 14.964424738750425),
        ] {
            // Π − K comes without cancellation; adding K back costs ε K.
            let k = complete_k(mc);
            let ours = k + complete_pi_minus_k(n, mc);
            assert_close(
                ours,
                want,
                4.0 * f64::EPSILON * k,
                0.0,
                &format!("Π({n} | m_c = {mc})"),
            );
        }
    }

    #[test]
    fn incomplete_first_kind_inverts_sn() {
        for &mc in &[0.8, 1e-3, 1e-30] {
            let jac = Jacobi::new(mc);
            for &f in &[0.05, 0.3, 0.5, 0.9, 0.999] {
                let u = f * jac.k();
                let q = jac.quarter(u);
                let (s, c, d) = jac.at_point(&q);
                let back = incomplete_f(s, c * c, d * d);
                // relative accuracy only as good as that of cn, dn at u
                let tol = if q.reflected {
                    4.0 * f64::EPSILON * jac.k()
                } else {
                    4.0 * f64::EPSILON * u
                };
                assert_close(
                    back,
                    u,
                    tol,
                    0.0,
                    &format!("F(am u) at m_c = {mc}, u = {u}"),
                );
            }
        }
    }
}

#[cfg(test)]
mod reference;
