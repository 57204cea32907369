//! The closed-form predictions a measurement is shown next to: the linear
//! stability of a spin about a principal axis (growth rate √k or oscillation
//! frequency √−k), the body precession rate of a symmetric top, and the time
//! between flips, half the period of ω(t) from K(m).

use nalgebra::Vector3;

use super::model::Body;

/// Relative difference below which two moments count as equal: a body that
/// close to symmetric precesses like a symmetric top for far longer than
/// any scene runs.
pub const SYMMETRY_TOL: f64 = 1e-9;

/// The axis (0-based) with the largest |ωᵢ| at t = 0, the first one on a tie.
pub fn dominant_axis(omega0: &Vector3<f64>) -> usize {
    let mut best = 0;
    for k in 1..3 {
        if omega0[k].abs() > omega0[best].abs() {
            best = k;
        }
    }
    best
}

/// Linear stability of a steady spin at rate `spin` about principal `axis`:
/// small deviations of the other two components obey ξ̈ = k ξ with
/// k = (I_a − I_j)(I_l − I_a) spin² / (I_j I_l). k > 0: they grow like
/// e^(√k t) (the middle axis); k < 0: they oscillate at √−k (the largest or
/// smallest axis); k = 0: neutral.
pub fn stability(body: &Body, axis: usize, spin: f64) -> f64 {
    let i = body.inertia;
    let a = axis % 3;
    let (j, l) = ((a + 1) % 3, (a + 2) % 3);
    (i[a] - i[j]) * (i[l] - i[a]) * spin * spin / (i[j] * i[l])
}

/// Where the moments of a body put a given axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AxisRole {
    /// The unstable middle axis of three distinct moments.
    Middle,
    /// The largest or smallest moment, or the symmetry axis of a top.
    Extreme,
    /// An axis in the degenerate plane of a symmetric body, or any axis of a
    /// sphere: neither stable nor unstable.
    Neutral,
}

pub fn axis_role(body: &Body, axis: usize) -> AxisRole {
    let i = body.inertia;
    let a = axis % 3;
    let (j, l) = ((a + 1) % 3, (a + 2) % 3);
    if close(i[a], i[j]) || close(i[a], i[l]) {
        AxisRole::Neutral
    } else if (i[a] - i[j]) * (i[l] - i[a]) > 0.0 {
        AxisRole::Middle
    } else {
        AxisRole::Extreme
    }
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= SYMMETRY_TOL * a.abs().max(b.abs())
}

/// The symmetry axis of a body with exactly two (nearly) equal moments; none
/// for a sphere or an asymmetric body.
pub fn symmetry_axis(body: &Body) -> Option<usize> {
    let i = body.inertia;
    (0..3).find(|&k| close(i[(k + 1) % 3], i[(k + 2) % 3]) && !close(i[k], i[(k + 1) % 3]))
}

/// Ω_b = (I_s − I⊥) ω_s / I⊥ for a symmetric top with symmetry axis s: the
/// rate at which (ω_{s+1}, ω_{s+2}) turns about axis s in the body frame,
/// positive from axis s+1 towards axis s+2 (cyclic).
pub fn body_precession_rate(body: &Body, omega0: &Vector3<f64>) -> Option<f64> {
    let s = symmetry_axis(body)?;
    let i = body.inertia;
    let perp = 0.5 * (i[(s + 1) % 3] + i[(s + 2) % 3]);
    Some((i[s] - perp) * omega0[s] / perp)
}

/// The elliptic parameter of an orbit that circulates about an extreme axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Circulation {
    /// The axis ω circulates about (0-based, in the body's own order).
    pub axis: usize,
    /// λ: ω(t) is a function of λt.
    pub rate: f64,
    /// m_c = 1 − m, computed without cancellation.
    pub complement: f64,
}

/// The circulation of an asymmetric body's orbit through ω₀, or `None` on
/// the separatrix, for a steady spin, a symmetric body or a sphere.
///
/// With I_a < I_b < I_c and D_x = L² − 2E·I_x = Σ Iᵢωᵢ²(Iᵢ − I_x): about c
/// when D_b > 0, λ² = (I_c − I_b) D_a / (I_a I_b I_c) and
/// m_c = (I_c − I_a) D_b / ((I_c − I_b) D_a); about a symmetrically.
pub fn circulation(body: &Body, omega0: &Vector3<f64>) -> Option<Circulation> {
    let mut axes = [0usize, 1, 2];
    axes.sort_by(|&p, &q| body.inertia[p].total_cmp(&body.inertia[q]));
    let [a, b, c] = axes;
    let i = body.inertia;
    if close(i[a], i[b]) || close(i[b], i[c]) {
        return None;
    }
    let w2 = omega0.component_mul(omega0);
    let d_a = i[b] * w2[b] * (i[b] - i[a]) + i[c] * w2[c] * (i[c] - i[a]);
    let d_c = i[a] * w2[a] * (i[c] - i[a]) + i[b] * w2[b] * (i[c] - i[b]);
    let d_b = i[c] * w2[c] * (i[c] - i[b]) - i[a] * w2[a] * (i[b] - i[a]);
    let product = i[a] * i[b] * i[c];
    let (axis, rate2, complement) = if d_b > 0.0 {
        (
            c,
            (i[c] - i[b]) * d_a / product,
            (i[c] - i[a]) * d_b / ((i[c] - i[b]) * d_a),
        )
    } else if d_b < 0.0 {
        (
            a,
            (i[b] - i[a]) * d_c / product,
            (i[c] - i[a]) * -d_b / ((i[b] - i[a]) * d_c),
        )
    } else {
        return None;
    };
    let steady = (0..3).all(|k| {
        let (p, q) = ((k + 1) % 3, (k + 2) % 3);
        (i[p] - i[q]) * omega0[p] * omega0[q] == 0.0
    });
    if steady || rate2.is_nan() || rate2 <= 0.0 || !complement.is_finite() {
        return None;
    }
    Some(Circulation {
        axis,
        rate: rate2.sqrt(),
        complement: complement.clamp(0.0, 1.0),
    })
}

/// K(m) from the complementary parameter: π / (2 AGM(1, √m_c)), accurate
/// however close m is to 1.
pub fn complete_k(complement: f64) -> f64 {
    let (mut a, mut g) = (1.0f64, complement.sqrt());
    for _ in 0..64 {
        if (a - g).abs() <= 2.0 * f64::EPSILON * a {
            break;
        }
        (a, g) = (0.5 * (a + g), (a * g).sqrt());
    }
    std::f64::consts::FRAC_PI_2 / a
}

/// The time between successive sign changes of the component of ω along
/// `axis`: half the period, 2K(m)/λ, when ω circulates about another axis;
/// `None` when that component never changes sign (ω circulates about it) or
/// the motion is not a circulation.
pub fn flip_interval(body: &Body, omega0: &Vector3<f64>, axis: usize) -> Option<f64> {
    let orbit = circulation(body, omega0)?;
    if orbit.axis == axis || orbit.complement == 0.0 {
        return None;
    }
    Some(2.0 * complete_k(orbit.complement) / orbit.rate)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn body(i: [f64; 3]) -> Body {
        Body::new(i).unwrap()
    }

    #[test]
    fn middle_axis_grows_extremes_oscillate() {
        let b = body([1.0, 2.0, 3.0]);
        assert!((stability(&b, 1, 10.0) - 100.0 / 3.0).abs() < 1e-12);
        assert!((stability(&b, 2, 10.0) + 100.0).abs() < 1e-12);
        assert!((stability(&b, 0, 10.0) + 100.0 / 3.0).abs() < 1e-12);
        assert_eq!(axis_role(&b, 1), AxisRole::Middle);
        assert_eq!(axis_role(&b, 0), AxisRole::Extreme);
        assert_eq!(axis_role(&body([2.0, 2.0, 3.0]), 0), AxisRole::Neutral);
        assert_eq!(axis_role(&body([2.0, 2.0, 3.0]), 2), AxisRole::Extreme);
    }

    #[test]
    fn symmetric_top_precession_is_signed() {
        let top = body([2.0, 2.0, 3.0]);
        assert_eq!(symmetry_axis(&top), Some(2));
        let rate = body_precession_rate(&top, &Vector3::new(1.0, 0.0, 10.0));
        assert_eq!(rate, Some(5.0));
        // A prolate top (I_s < I⊥) turns the other way.
        let prolate = body([1.0, 2.0, 2.0]);
        let rate = body_precession_rate(&prolate, &Vector3::new(4.0, 0.5, 0.0));
        assert_eq!(rate, Some(-2.0));
        assert_eq!(symmetry_axis(&body([2.0, 2.0, 2.0])), None);
        assert_eq!(symmetry_axis(&body([1.0, 2.0, 3.0])), None);
    }

    #[test]
    fn k_matches_known_values() {
        // K(1/2) = 1.854074677301372 (Abramowitz & Stegun 17.3).
        assert!((complete_k(0.5) - 1.854_074_677_301_372).abs() < 1e-14);
        assert!((complete_k(1.0) - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        // Near m = 1: K ≈ ln(4/√m_c) + (m_c/4)(ln(4/√m_c) − 1).
        let mc = 1e-12f64;
        let l = (4.0 / mc.sqrt()).ln();
        assert!((complete_k(mc) - (l + mc / 4.0 * (l - 1.0))).abs() < 1e-12);
    }

    #[test]
    fn flip_interval_of_the_notes_case() {
        // ω₀ = (0.01, 10, 0.01): the deck's authored 2.753 s.
        let b = body([1.0, 2.0, 3.0]);
        let w = Vector3::new(0.01, 10.0, 0.01);
        let t = flip_interval(&b, &w, 1).unwrap();
        assert!((t - 2.753).abs() < 2e-3, "{t}");
        // The circulation axis itself never flips.
        let orbit = circulation(&b, &w).unwrap();
        assert_eq!(flip_interval(&b, &w, orbit.axis), None);
        // A stable spin about axis 3 never flips ω₃.
        assert_eq!(flip_interval(&b, &Vector3::new(0.5, 0.5, 10.0), 2), None);
    }

    #[test]
    fn separatrix_symmetric_and_steady_have_no_circulation() {
        let b = body([3.0, 4.0, 6.0]);
        assert_eq!(circulation(&b, &Vector3::new(2.0, 0.5, 1.0)), None);
        assert_eq!(
            circulation(&body([2.0, 2.0, 3.0]), &Vector3::new(1.0, 0.0, 1.0)),
            None
        );
        assert_eq!(
            circulation(&body([1.0, 2.0, 3.0]), &Vector3::new(0.0, 5.0, 0.0)),
            None
        );
    }
}
