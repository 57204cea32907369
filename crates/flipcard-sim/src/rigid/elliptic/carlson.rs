//! Carlson's symmetric elliptic integrals R_F, R_J and R_C by duplication
//! (Carlson 1995, with the seventh-order closing series of DLMF §19.36(i)).
//!
//! The symmetric forms take the squared cosine and squared Δ of an amplitude
//! as separate arguments, so a caller that knows cn² and dn² to full relative
//! precision (even when both are tiny, next to the separatrix) gets the
//! integral to full precision: nothing here ever forms 1 − m or 1 − sin².

/// Stops the duplication when the arguments agree to (ε/5)^(1/8): the
/// neglected terms of the seventh-order series are then below ε.
const TOLERANCE_FACTOR: f64 = 111.0; // ≈ (f64::EPSILON / 5)^(-1/8)

/// More duplications than any finite positive input needs (each step shrinks
/// the spread of the arguments fourfold).
const MAX_STEPS: usize = 64;

/// R_F(x, y, z) = ½ ∫₀^∞ dt / √((t+x)(t+y)(t+z)), for x, y, z ≥ 0 with at
/// most one of them zero.
pub(crate) fn rf(x: f64, y: f64, z: f64) -> f64 {
    let a0 = (x + y + z) / 3.0;
    let q = TOLERANCE_FACTOR * (a0 - x).abs().max((a0 - y).abs()).max((a0 - z).abs());
    let (mut xn, mut yn, mut zn, mut an) = (x, y, z, a0);
    let mut scale = 1.0; // 4^-n
    for _ in 0..MAX_STEPS {
        if scale * q < an.abs() {
            break;
        }
        let (sx, sy, sz) = (xn.sqrt(), yn.sqrt(), zn.sqrt());
        let lambda = sx * (sy + sz) + sy * sz;
        xn = 0.25 * (xn + lambda);
        yn = 0.25 * (yn + lambda);
        zn = 0.25 * (zn + lambda);
        an = 0.25 * (an + lambda);
        scale *= 0.25;
    }
    let dx = scale * (a0 - x) / an;
    let dy = scale * (a0 - y) / an;
    let dz = -(dx + dy);
    let e2 = dx * dy - dz * dz;
    let e3 = dx * dy * dz;
    let series = 1.0 - e2 / 10.0 + e3 / 14.0 + e2 * e2 / 24.0
        - 3.0 * e2 * e3 / 44.0
        - 5.0 * e2 * e2 * e2 / 208.0
        + 3.0 * e3 * e3 / 104.0
        + e2 * e2 * e3 / 16.0;
    series / an.sqrt()
}

/// R_J(x, y, z, p) = (3/2) ∫₀^∞ dt / ((t+p) √((t+x)(t+y)(t+z))), for
/// x, y, z ≥ 0 with at most one of them zero, and p > 0.
///
/// Fast path: when (p−x)(p−y)(p−z) ≥ 0, which holds for every call made by
/// the rigid-body solver, each R_C term is an arctangent (or its series).
pub(crate) fn rj(x: f64, y: f64, z: f64, p: f64) -> f64 {
    let a0 = (x + y + z + p + p) / 5.0;
    let delta = (p - x) * (p - y) * (p - z);
    let q = TOLERANCE_FACTOR
        * (a0 - x)
            .abs()
            .max((a0 - y).abs())
            .max((a0 - z).abs())
            .max((a0 - p).abs());
    let (mut xn, mut yn, mut zn, mut pn, mut an) = (x, y, z, p, a0);
    let mut scale = 1.0; // 4^-n
    let mut delta_n = delta; // 4^-3n δ
    let mut sum = 0.0;
    for _ in 0..MAX_STEPS {
        if scale * q < an.abs() {
            break;
        }
        let (sx, sy, sz, sp) = (xn.sqrt(), yn.sqrt(), zn.sqrt(), pn.sqrt());
        let lambda = sx * (sy + sz) + sy * sz;
        let d = (sp + sx) * (sp + sy) * (sp + sz);
        let e = delta_n / (d * d);
        sum += scale * rc_one_plus(e) / d;
        xn = 0.25 * (xn + lambda);
        yn = 0.25 * (yn + lambda);
        zn = 0.25 * (zn + lambda);
        pn = 0.25 * (pn + lambda);
        an = 0.25 * (an + lambda);
        scale *= 0.25;
        delta_n *= 1.0 / 64.0;
    }
    let dx = scale * (a0 - x) / an;
    let dy = scale * (a0 - y) / an;
    let dz = scale * (a0 - z) / an;
    let dp = -0.5 * (dx + dy + dz);
    let xyz = dx * dy * dz;
    let p2 = dp * dp;
    let p3 = p2 * dp;
    let e2 = dx * dy + dx * dz + dy * dz - 3.0 * p2;
    let e3 = xyz + 2.0 * e2 * dp + 4.0 * p3;
    let e4 = (2.0 * xyz + e2 * dp + 3.0 * p3) * dp;
    let e5 = xyz * p2;
    let series = 1.0 - 3.0 * e2 / 14.0 + e3 / 6.0 + 9.0 * e2 * e2 / 88.0
        - 3.0 * e4 / 22.0
        - 9.0 * e2 * e3 / 52.0
        + 3.0 * e5 / 26.0
        - e2 * e2 * e2 / 16.0
        + 3.0 * e3 * e3 / 40.0
        + 3.0 * e2 * e4 / 20.0
        + 45.0 * e2 * e2 * e3 / 272.0
        - 9.0 * (e3 * e4 + e2 * e5) / 68.0;
    scale * series / (an * an.sqrt()) + 6.0 * sum
}

/// R_C(x, y) = ½ ∫₀^∞ dt / ((t+y) √(t+x)), for x ≥ 0, y > 0.
#[cfg(test)]
pub(crate) fn rc(x: f64, y: f64) -> f64 {
    if x == 0.0 {
        return std::f64::consts::FRAC_PI_2 / y.sqrt();
    }
    rc_one_plus(y / x - 1.0) / x.sqrt()
}

/// R_C(1, 1 + e) for e > −1: arctan(√e)/√e, or artanh(√−e)/√−e, with the
/// series near e = 0 where both lose digits.
fn rc_one_plus(e: f64) -> f64 {
    if e.abs() < 1e-3 {
        // 1 − e/3 + e²/5 − e³/7 + e⁴/9 − e⁵/11; the next term is below 1e-18.
        1.0 + e * (-1.0 / 3.0 + e * (1.0 / 5.0 + e * (-1.0 / 7.0 + e * (1.0 / 9.0 - e / 11.0))))
    } else if e > 0.0 {
        let s = e.sqrt();
        s.atan() / s
    } else {
        let s = (-e).sqrt();
        s.atanh() / s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, rel: f64) -> bool {
        (a - b).abs() <= rel * b.abs()
    }

    #[test]
    fn rf_matches_closed_forms_and_tables() {
        // R_F(0, 1, 2) = 1.3110287771460599052… (lemniscate case, DLMF 19.20.2)
        assert!(close(rf(0.0, 1.0, 2.0), 1.311_028_777_146_059_9, 4e-16));
        // R_F(x, x, x) = 1/√x
        assert!(close(rf(4.0, 4.0, 4.0), 0.5, 2e-16));
        // R_F(0, y, y) = π / (2√y)
        assert!(close(rf(0.0, 9.0, 9.0), std::f64::consts::PI / 6.0, 4e-16));
        // R_F(x, y, y) = R_C(x, y)
        assert!(close(rf(2.0, 3.0, 3.0), rc(2.0, 3.0), 4e-16));
        // Homogeneity: R_F(λx, λy, λz) = R_F(x, y, z)/√λ, and symmetry.
        let base = rf(0.3, 1.7, 2.9);
        assert!(close(
            rf(4.0 * 0.3, 4.0 * 1.7, 4.0 * 2.9),
            base / 2.0,
            4e-16
        ));
        assert!(close(rf(2.9, 0.3, 1.7), base, 4e-16));
    }

    #[test]
    fn rj_matches_closed_forms_and_an_independent_implementation() {
        // R_J(x, x, x, x) = x^(-3/2)
        assert!(close(rj(4.0, 4.0, 4.0, 4.0), 0.125, 4e-16));
        // R_J(x, y, z, z) = R_D(x, y, z); R_D(0, 2, 1) = 1.7972103521033883112 (DLMF 19.20.18 example values)
        assert!(close(
            rj(0.0, 2.0, 1.0, 1.0),
            ellip::elliprd(0.0, 2.0, 1.0).unwrap(),
            4e-15
        ));
        for &(x, y, z, p) in &[
            (0.0, 0.5, 1.0, 1.5),
            (1e-12, 1e-12, 1.0, 1.0 + 3.0),
            (0.25, 0.3, 1.0, 7.0),
            (1e-3, 0.2, 1.0, 0.15),
            (0.0, 1e-30, 1.0, 1e6),
            (0.9, 0.95, 1.0, 0.92),
        ] {
            let ours = rj(x, y, z, p);
            let theirs = ellip::elliprj(x, y, z, p).unwrap();
            assert!(
                close(ours, theirs, 2e-15),
                "{x} {y} {z} {p}: {ours} vs {theirs}"
            );
        }
    }

    #[test]
    fn rc_branches_agree_with_elementary_forms() {
        assert!(close(rc(1.0, 4.0), 3f64.sqrt().atan() / 3f64.sqrt(), 4e-16));
        assert!(close(
            rc(4.0, 1.0),
            (2.0 + 3f64.sqrt()).ln() / 3f64.sqrt(),
            4e-16
        ));
        assert!(close(rc(1.0, 1.0 + 1e-9), 1.0 - 1e-9 / 3.0, 1e-16));
        assert!(close(rc(0.0, 4.0), std::f64::consts::FRAC_PI_4, 2e-16));
    }
}
