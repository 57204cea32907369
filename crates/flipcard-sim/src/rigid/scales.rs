//! Time scales of a torque-free motion, read off the two invariants before
//! any integration: how fast ω moves (the nutation frequency) and how fast
//! the body turns (the largest |ω| on the orbit). Step budgets and default
//! step sizes are sized from these.

use nalgebra::Vector3;

use crate::rigid::model::Body;

/// The fastest rates (rad/s) of one trajectory, and how large each
/// component of ω can get on it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scales {
    /// Frequency parameter λ of the elliptic solution: ω(t) is a function of
    /// λt (sn, cn, dn), so λ sets how finely ω must be resolved.
    pub nutation: f64,
    /// Largest |ω| anywhere on the orbit: the rate at which q turns.
    pub spin: f64,
    /// Smallest |ω| anywhere on the orbit.
    pub slowest: f64,
    /// Largest |ωᵢ| of each component anywhere on the orbit...
    pub extent: [f64; 3],
    /// ...and smallest.
    pub floor: [f64; 3],
}

impl Scales {
    /// The rate a solver must resolve: nutation alone for ω, and the spin as
    /// well when the orientation is integrated.
    pub fn fastest(&self, orientation: bool) -> f64 {
        if orientation {
            self.nutation.max(self.spin)
        } else {
            self.nutation
        }
    }

    /// What to call the limiting rate in a message.
    pub fn describe(&self, orientation: bool) -> String {
        if orientation && self.spin > self.nutation {
            format!("spin at {:.1e} rad/s", self.spin)
        } else {
            format!("nutation at {:.1e} rad/s", self.nutation)
        }
    }
}

/// Rates of the orbit through `omega`.
///
/// Euler's equations do not change when every moment is multiplied by one
/// factor, and scaling ω by s only scales time by 1/s; so the moments and ω
/// are brought to order one by powers of two (exact) before anything is
/// squared or multiplied, and the rates scaled back. Products such as
/// I_a I_b I_c would otherwise overflow for moments near 1e103 and
/// underflow near 1e-103, and ω² for |ω| past 1e154.
pub fn scales(body: &Body, omega: &Vector3<f64>) -> Scales {
    let largest = omega.amax();
    if largest == 0.0 || !largest.is_finite() {
        return Scales {
            nutation: 0.0,
            spin: 0.0,
            slowest: 0.0,
            extent: [0.0; 3],
            floor: [0.0; 3],
        };
    }
    let i = body.inertia / power_of_two_at_most(body.inertia.max());
    let w_scale = power_of_two_at_most(largest);
    let w = omega / w_scale;
    let e = orbit_extent(&i, &w);
    Scales {
        nutation: nutation(&i, &w) * w_scale,
        spin: e.spin * w_scale,
        slowest: e.slowest * w_scale,
        extent: e.extent.map(|v| v * w_scale),
        floor: e.floor.map(|v| v * w_scale),
    }
}

/// How much a relative error of the body-frame momentum L becomes in ω =
/// I⁻¹L, relative to |ω|: |L| / (I_min · min |ω| on the orbit), between 1
/// (a sphere) and I_max/I_min (a needle turning about its thin axis). A
/// solver that carries L instead of ω (the splitting) sees its every error
/// multiplied by this much in ω.
pub(crate) fn momentum_gain(body: &Body, omega: &Vector3<f64>) -> f64 {
    let largest = omega.amax();
    if largest == 0.0 || !largest.is_finite() {
        return 1.0;
    }
    let i = body.inertia / power_of_two_at_most(body.inertia.max());
    let w = omega / power_of_two_at_most(largest);
    let l = i.component_mul(&w);
    let l_norm = l[0].hypot(l[1]).hypot(l[2]);
    let slowest = orbit_extent(&i, &w).slowest;
    if slowest > 0.0 {
        (l_norm / (i.min() * slowest)).max(1.0)
    } else {
        1.0
    }
}

/// The largest power of two not above x (x > 0, finite).
fn power_of_two_at_most(x: f64) -> f64 {
    x.log2().floor().clamp(-1074.0, 1023.0).exp2()
}

/// λ² = (I_c − I_b)(L² − 2E·I_a)/(I_a I_b I_c) when the orbit circulates about
/// the largest axis (L² ≥ 2E·I_b), else (I_b − I_a)(2E·I_c − L²)/(I_a I_b I_c),
/// with I_a ≤ I_b ≤ I_c. Each Δ is summed from non-negative terms, so nothing
/// cancels even next to the separatrix or for nearly equal moments.
fn nutation(inertia: &Vector3<f64>, omega: &Vector3<f64>) -> f64 {
    let mut axes = [0usize, 1, 2];
    axes.sort_by(|&i, &j| inertia[i].total_cmp(&inertia[j]));
    let [a, b, c] = axes;
    let (ia, ib, ic) = (inertia[a], inertia[b], inertia[c]);
    let (wa2, wb2, wc2) = (omega[a].powi(2), omega[b].powi(2), omega[c].powi(2));
    // L² − 2E·I_x = Σ I_i ω_i² (I_i − I_x).
    let above_a = ib * wb2 * (ib - ia) + ic * wc2 * (ic - ia);
    let around_b = ic * wc2 * (ic - ib) - ia * wa2 * (ib - ia);
    // After scaling I_c and the largest |ωᵢ| are about 1, but a needle's
    // I_a can be anything down to 5e-324. The triangle inequality keeps
    // (I_c − I_b)/I_a at most about 1, so dividing by I_a there, and not
    // in the product I_a I_b I_c, neither overflows nor underflows.
    let needle = (ic - ib) / ia;
    let lambda2 = if around_b >= 0.0 {
        needle * above_a / (ib * ic)
    } else {
        // (2E·I_c − L²)/I_a = ω_a²(I_c − I_a) + ω_b² I_b (I_c − I_b)/I_a.
        (ib - ia) / (ib * ic) * (wa2 * (ic - ia) + ib * wb2 * needle)
    };
    lambda2.max(0.0).sqrt()
}

/// Extremes of |ω| and of each |ωᵢ| on an orbit.
struct Extent {
    slowest: f64,
    spin: f64,
    extent: [f64; 3],
    floor: [f64; 3],
}

/// The squares xᵢ = ωᵢ² obey two linear constraints (2E and L²), so the orbit
/// lives on a segment x₀ + s·d of the positive octant, d = I × I² (component-
/// wise squares). Each xᵢ and |ω|² = Σ xᵢ are linear along it, so their
/// extremes sit at the ends.
fn orbit_extent(inertia: &Vector3<f64>, omega: &Vector3<f64>) -> Extent {
    let i = inertia;
    let x0 = omega.component_mul(omega);
    let d = Vector3::new(
        i[1] * i[2] * (i[2] - i[1]),
        i[2] * i[0] * (i[0] - i[2]),
        i[0] * i[1] * (i[1] - i[0]),
    );
    // Only the direction of d matters; bringing it to order one keeps a
    // needle's tiny components from underflowing in s·d.
    let big = d.amax();
    let d = if big > 0.0 { d / big } else { d };
    let (mut lo, mut hi) = (0.0f64, 0.0f64);
    let (mut lo_set, mut hi_set) = (false, false);
    for k in 0..3 {
        if d[k] > 0.0 {
            let s = -x0[k] / d[k];
            lo = if lo_set { lo.max(s) } else { s };
            lo_set = true;
        } else if d[k] < 0.0 {
            let s = x0[k] / -d[k];
            hi = if hi_set { hi.min(s) } else { s };
            hi_set = true;
        }
    }
    let at = |s: f64| (x0 + d * s).map(|x| x.max(0.0));
    let ends = [
        at(if lo_set { lo } else { 0.0 }),
        at(if hi_set { hi } else { 0.0 }),
    ];
    let extent = [0, 1, 2].map(|k| x0[k].max(ends[0][k]).max(ends[1][k]).sqrt());
    let floor = [0, 1, 2].map(|k| x0[k].min(ends[0][k]).min(ends[1][k]).sqrt());
    let sums = [x0.sum(), ends[0].sum(), ends[1].sum()];
    Extent {
        slowest: sums.iter().copied().fold(f64::INFINITY, f64::min).sqrt(),
        spin: sums.iter().copied().fold(0.0, f64::max).sqrt(),
        extent,
        floor,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn body(i: [f64; 3]) -> Body {
        Body::new(i).unwrap()
    }

    #[test]
    fn middle_axis_rate_is_the_linear_growth_rate() {
        // Near the middle axis λ → √k with k = (I3−I2)(I2−I1)/(I1 I3) Ω².
        let s = scales(&body([1.0, 2.0, 3.0]), &Vector3::new(1e-9, 10.0, 1e-9));
        let sqrt_k = (1.0f64 * 1.0 / 3.0 * 100.0).sqrt();
        assert!((s.nutation - sqrt_k).abs() < 1e-6 * sqrt_k, "{s:?}");
        // All the energy can go into the smallest axis at the far side of a flip.
        assert!(s.spin >= 10.0 && s.spin < 14.2, "{s:?}");
    }

    #[test]
    fn symmetric_top_rate_is_the_body_precession() {
        // I⊥ = 2, I3 = 3: Ω_b = (I3 − I⊥) ω3 / I⊥.
        let s = scales(&body([2.0, 2.0, 3.0]), &Vector3::new(0.3, -0.4, 5.0));
        assert!((s.nutation - 0.5 * 5.0).abs() < 1e-12, "{s:?}");
        let w = (0.09f64 + 0.16 + 25.0).sqrt();
        assert!(
            (s.spin - w).abs() < 1e-12,
            "|ω| is constant for a symmetric top: {s:?}"
        );
    }

    #[test]
    fn needle_is_not_mistaken_for_a_fast_body() {
        // A needle turning slowly end over end: nothing here is fast.
        let s = scales(&body([1e-6, 1.0, 1.0]), &Vector3::new(1.0, 1.0, 0.0));
        assert!(s.nutation < 1.01 && s.spin < 1.5, "{s:?}");
    }

    #[test]
    fn sphere_and_rest_have_no_nutation() {
        let s = scales(&body([2.0, 2.0, 2.0]), &Vector3::new(1.0, 2.0, 2.0));
        assert_eq!(s.nutation, 0.0);
        assert!((s.spin - 3.0).abs() < 1e-12);
        let s = scales(&body([1.0, 2.0, 3.0]), &Vector3::zeros());
        assert_eq!((s.nutation, s.spin), (0.0, 0.0));
    }

    #[test]
    fn rates_scale_with_spin() {
        let b = body([1.0, 2.0, 3.0]);
        let w = Vector3::new(0.3, 1.0, 0.2);
        let s1 = scales(&b, &w);
        let s2 = scales(&b, &(w * 1e4));
        assert!((s2.nutation / s1.nutation - 1e4).abs() < 1e-8);
        assert!((s2.spin / s1.spin - 1e4).abs() < 1e-8);
    }
}
