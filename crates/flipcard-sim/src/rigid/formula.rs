//! The closed-form predictions a measurement is shown next to: the linear
//! stability of a spin about a principal axis (growth rate √k or oscillation
//! frequency √−k), the body precession rate of a symmetric top, and the time
//! between flips, half the period of ω(t) from K(m) (the exact solver's).

use nalgebra::Vector3;

use crate::rigid::exact::{self, Exact, Regime};
use crate::rigid::model::Body;
use crate::rigid::solver::Needs;

/// Relative difference below which two moments count as equal: a body that
/// close to symmetric precesses like a symmetric top for far longer than
/// any scene runs.
pub(crate) const SYMMETRY_TOL: f64 = 1e-9;

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
/// small deviations grow like e^(√k t) when k > 0 (the middle axis) and
/// oscillate at √−k when k < 0 (the largest or smallest axis).
pub fn stability(body: &Body, axis: usize, spin: f64) -> f64 {
    exact::linear_stability(body, axis, spin)
}

/// Where the moments of a body put a given axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum AxisRole {
    /// The unstable middle axis of three distinct moments.
    Middle,
    /// The largest or smallest moment, or the symmetry axis of a top.
    Extreme,
    /// An axis in the degenerate plane of a symmetric body, or any axis of a
    /// sphere: neither stable nor unstable.
    Neutral,
}

pub(crate) fn axis_role(body: &Body, axis: usize) -> AxisRole {
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
pub(crate) fn symmetry_axis(body: &Body) -> Option<usize> {
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

/// The time between successive sign changes of the component of ω along
/// `axis`: half the period, 2K(m)/λ, when ω circulates about another axis;
/// `None` when that component never changes sign (ω circulates about it),
/// on the separatrix, and for steady spins and symmetric bodies.
pub fn flip_interval(body: &Body, omega0: &Vector3<f64>, axis: usize) -> Option<f64> {
    let exact = Exact::new(*body, *omega0, Needs { orientation: false }).ok()?;
    match exact.regime() {
        Regime::Circulation { axis: about } if about != axis => exact.flip_interval(),
        _ => None,
    }
}

/// The period of ω(t) (4K(m)/λ, or 2π/|Ω| for a symmetric top); `None`
/// when ω is constant or on the separatrix.
pub fn period(body: &Body, omega0: &Vector3<f64>) -> Option<f64> {
    Exact::new(*body, *omega0, Needs { orientation: false })
        .ok()?
        .period()
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
    fn flip_interval_of_the_notes_case() {
        // ω₀ = (0.01, 10, 0.01): the deck's authored 2.753 s.
        let b = body([1.0, 2.0, 3.0]);
        let w = Vector3::new(0.01, 10.0, 0.01);
        let t = flip_interval(&b, &w, 1).unwrap();
        assert!((t - 2.753).abs() < 2e-3, "{t}");
        assert!((period(&b, &w).unwrap() - 2.0 * t).abs() < 1e-12);
        // ω circulates about axis 3 here (L² > 2E·I₂), so ω₁ flips too and
        // ω₃ never does.
        assert_eq!(flip_interval(&b, &w, 0), Some(t));
        assert_eq!(flip_interval(&b, &w, 2), None);
        // A stable spin about axis 3 never flips ω₃.
        assert_eq!(flip_interval(&b, &Vector3::new(0.5, 0.5, 10.0), 2), None);
    }

    #[test]
    fn separatrix_symmetric_and_steady_have_no_flips() {
        let b = body([3.0, 4.0, 6.0]);
        assert_eq!(flip_interval(&b, &Vector3::new(2.0, 0.5, 1.0), 1), None);
        let top = body([2.0, 2.0, 3.0]);
        assert_eq!(flip_interval(&top, &Vector3::new(1.0, 0.0, 1.0), 0), None);
        let b = body([1.0, 2.0, 3.0]);
        assert_eq!(flip_interval(&b, &Vector3::new(0.0, 5.0, 0.0), 1), None);
    }
}
