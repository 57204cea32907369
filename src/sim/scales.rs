//! Time scales of a torque-free motion, read off the two invariants before
//! any integration: how fast ω moves (the nutation frequency) and how fast
//! the body turns (the largest |ω| on the orbit). Step budgets and default
//! step sizes are sized from these.

use nalgebra::Vector3;

use super::model::Body;

/// The fastest rates (rad/s) of one trajectory.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scales {
    /// Frequency parameter λ of the elliptic solution: ω(t) is a function of
    /// λt (sn, cn, dn), so λ sets how finely ω must be resolved.
    pub nutation: f64,
    /// Largest |ω| anywhere on the orbit: the rate at which q turns.
    pub spin: f64,
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
pub fn scales(body: &Body, omega: &Vector3<f64>) -> Scales {
    Scales {
        nutation: nutation(body, omega),
        spin: max_spin(body, omega),
    }
}

/// λ² = (I_c − I_b)(L² − 2E·I_a)/(I_a I_b I_c) when the orbit circulates about
/// the largest axis (L² ≥ 2E·I_b), else (I_b − I_a)(2E·I_c − L²)/(I_a I_b I_c),
/// with I_a ≤ I_b ≤ I_c. Each Δ is summed from non-negative terms, so nothing
/// cancels even next to the separatrix or for nearly equal moments.
fn nutation(body: &Body, omega: &Vector3<f64>) -> f64 {
    let mut axes = [0usize, 1, 2];
    axes.sort_by(|&i, &j| body.inertia[i].total_cmp(&body.inertia[j]));
    let [a, b, c] = axes;
    let (ia, ib, ic) = (body.inertia[a], body.inertia[b], body.inertia[c]);
    let (wa2, wb2, wc2) = (omega[a].powi(2), omega[b].powi(2), omega[c].powi(2));
    // L² − 2E·I_x = Σ I_i ω_i² (I_i − I_x).
    let above_a = ib * wb2 * (ib - ia) + ic * wc2 * (ic - ia);
    let below_c = ia * wa2 * (ic - ia) + ib * wb2 * (ic - ib);
    let around_b = ic * wc2 * (ic - ib) - ia * wa2 * (ib - ia);
    let lambda2 = if around_b >= 0.0 {
        (ic - ib) * (above_a / (ia * ib * ic))
    } else {
        (ib - ia) * (below_c / (ia * ib * ic))
    };
    lambda2.max(0.0).sqrt()
}

/// The squares xᵢ = ωᵢ² obey two linear constraints (2E and L²), so the orbit
/// lives on a segment x₀ + s·d of the positive octant, d = I × I² (component-
/// wise squares). |ω|² = Σ xᵢ is linear along it, so its maximum sits at an end.
fn max_spin(body: &Body, omega: &Vector3<f64>) -> f64 {
    let i = body.inertia;
    let x0 = omega.component_mul(omega);
    let d = Vector3::new(
        i[1] * i[2] * (i[2] - i[1]),
        i[2] * i[0] * (i[0] - i[2]),
        i[0] * i[1] * (i[1] - i[0]),
    );
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
    let sum_d = d.sum();
    let sum_x = x0.sum();
    let ends = [if lo_set { lo } else { 0.0 }, if hi_set { hi } else { 0.0 }];
    let best = ends.iter().map(|s| sum_x + s * sum_d).fold(sum_x, f64::max);
    best.max(0.0).sqrt()
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
