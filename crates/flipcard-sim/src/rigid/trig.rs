//! sin and cos together for the small angles of the splitting's rotations.
//!
//! A splitting step turns the body by Lᵢh/Iᵢ about one axis at a time,
//! almost always well under π/4; there a Taylor polynomial is as accurate as
//! libm (truncation below 1e-18) and several times cheaper than its two
//! range-reducing calls. Larger angles go to libm.

use std::f64::consts::FRAC_PI_4;

/// 1/(2k+1)! with alternating signs, k = 1..8.
const SIN: [f64; 8] = [
    -1.0 / 6.0,
    1.0 / 120.0,
    -1.0 / 5040.0,
    1.0 / 362_880.0,
    -1.0 / 39_916_800.0,
    1.0 / 6_227_020_800.0,
    -1.0 / 1_307_674_368_000.0,
    1.0 / 355_687_428_096_000.0,
];

/// 1/(2k)! with alternating signs, k = 2..8.
const COS: [f64; 7] = [
    1.0 / 24.0,
    -1.0 / 720.0,
    1.0 / 40_320.0,
    -1.0 / 3_628_800.0,
    1.0 / 479_001_600.0,
    -1.0 / 87_178_291_200.0,
    1.0 / 20_922_789_888_000.0,
];

/// (sin x, cos x).
#[inline(always)]
pub(crate) fn sin_cos(x: f64) -> (f64, f64) {
    if x.abs() > FRAC_PI_4 {
        return x.sin_cos();
    }
    let z = x * x;
    let mut s = SIN[7];
    for c in SIN[..7].iter().rev() {
        s = s * z + c;
    }
    let mut c = COS[6];
    for k in COS[..6].iter().rev() {
        c = c * z + k;
    }
    // Small corrections added last onto the leading terms.
    (x + x * z * s, (1.0 - 0.5 * z) + z * z * c)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ulps(a: f64, b: f64) -> f64 {
        (a - b).abs() / (f64::EPSILON * b.abs().max(f64::MIN_POSITIVE))
    }

    #[test]
    fn agrees_with_libm_to_an_ulp_or_two() {
        let mut worst = (0.0f64, 0.0f64);
        for k in -20_000..=20_000 {
            let x = k as f64 * FRAC_PI_4 / 20_000.0;
            let (s, c) = sin_cos(x);
            let (s0, c0) = x.sin_cos();
            if x != 0.0 {
                worst.0 = worst.0.max(ulps(s, s0));
            }
            worst.1 = worst.1.max(ulps(c, c0));
        }
        assert!(worst.0 <= 2.0 && worst.1 <= 2.0, "{worst:?}");
        for x in [1e-300, -1e-20, 1e-8, 0.0] {
            assert_eq!(sin_cos(x).0, x, "sin x = x for tiny x");
            assert_eq!(sin_cos(x).1, 1.0);
        }
    }

    #[test]
    fn large_angles_fall_back_to_libm() {
        for x in [0.8, -3.0, 100.0, 1e10] {
            assert_eq!(sin_cos(x), x.sin_cos());
        }
    }
}
