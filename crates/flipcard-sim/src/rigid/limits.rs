//! What f64 arithmetic can compute honestly for a body and an initial ω,
//! decided before anything runs. `flipcard check` and the simulator call
//! the same functions, so a deck that passes `check` always runs and the
//! simulator refuses, with the reason, what would otherwise print numbers
//! that look plausible and mean nothing.

use crate::error::SolveError;
use nalgebra::Vector3;

use crate::rigid::model::{self, Body};
use crate::rigid::scales::Scales;
use flipcard_text::num::{Num, below};

/// The largest phase Ωt (rad) of the fastest rate Ω a run may reach: 2³².
///
/// A time t and the phase Ωt computed from it carry a relative rounding
/// error of ε = 2⁻⁵², so the phase is known to about ε·Ωt rad: every solver
/// inherits that much from f64 time alone (the exact solution evaluates
/// u₀ + λt, the stepping ones add up steps of Ωdt). At Ωt = 2³² one ulp of
/// the phase is 2⁻²⁰ ≈ 1e-6 rad, so ω and q are still right to about six
/// digits; far beyond, the states look just as plausible and are noise
/// (at Ωt = 2⁵² the phase is not even known to a radian).
pub(crate) const MAX_PHASE: f64 = 4294967296.0;

/// Checks that ω₀ is finite and that the invariants it carries, T = ½ Σ Iᵢωᵢ²
/// and |L|² = Σ (Iᵢωᵢ)², are normal f64 numbers: neither overflows (every
/// energy and |L|² printed would be inf) nor, for a moving body, underflows
/// (they would print as 0 or with a few bits left). This is the one test
/// of representability: the simulator runs it before every run and
/// `flipcard check` runs it on every scene.
pub(crate) fn check_start(body: &Body, omega0: &Vector3<f64>) -> Result<(), SolveError> {
    model::omega([omega0[0], omega0[1], omega0[2]])?;
    let energy = body.energy(omega0);
    let l2 = body.l2(omega0);
    let w = flipcard_text::num::triple(&[omega0[0], omega0[1], omega0[2]], ", ");
    if !(energy.is_finite() && l2.is_finite()) {
        return Err(SolveError::Invalid(format!(
            "ω = ({w}) is too large for these moments: its energy overflows f64 (give ω per a shorter time unit, or the moments in a larger unit)"
        )));
    }
    let moving = omega0.iter().any(|&v| v != 0.0);
    if moving && !(energy >= f64::MIN_POSITIVE && l2 >= f64::MIN_POSITIVE) {
        return Err(SolveError::Invalid(format!(
            "ω = ({w}) is too small for these moments: its energy underflows f64 (give ω per a longer time unit, or the moments in a smaller unit)"
        )));
    }
    Ok(())
}

/// The longest span over which the phase of this motion is resolved: the
/// time at which the fastest rate (the nutation of ω, and the spin as well
/// when the orientation is computed) has turned by [`MAX_PHASE`]. Infinite
/// when nothing moves.
pub(crate) fn max_span(scales: &Scales, orientation: bool) -> f64 {
    let rate = scales.fastest(orientation);
    if rate > 0.0 {
        MAX_PHASE / rate
    } else {
        f64::INFINITY
    }
}

/// Refuses a run to `t_end` beyond [`max_span`], naming the limit; `what`
/// names the time in the message (`t =`, `duration`).
pub(crate) fn check_span(
    scales: &Scales,
    orientation: bool,
    t_end: f64,
    what: &str,
) -> Result<(), SolveError> {
    let limit = max_span(scales, orientation);
    // A NaN time is the solvers' to refuse, with their own message.
    if t_end.is_nan() || t_end <= limit {
        return Ok(());
    }
    Err(SolveError::Invalid(format!(
        "{what} {} is beyond {}, the longest span whose phase f64 resolves for this motion ({} turns the phase by 2^32 rad there, where one ulp of it is 1e-6 rad); use a shorter span",
        Num(t_end),
        Num(below(limit, 4)),
        scales.describe(orientation)
    )))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rigid::scales::scales;

    #[test]
    fn invariants_must_be_normal_numbers() {
        let b = Body::new([1.0, 2.0, 3.0]).unwrap();
        assert!(check_start(&b, &Vector3::new(1.0, 2.0, 3.0)).is_ok());
        assert!(check_start(&b, &Vector3::zeros()).is_ok(), "rest is fine");
        let err = check_start(&b, &Vector3::new(1e200, 0.0, 0.0)).unwrap_err();
        assert!(err.to_string().contains("overflows"), "{err}");
        assert!(err.to_string().contains("1e200"), "{err}");
        let err = check_start(&b, &Vector3::new(0.0, 5e-324, 0.0)).unwrap_err();
        assert!(err.to_string().contains("underflows"), "{err}");
        // Tiny moments with a matching fast spin are a fine body.
        let tiny = Body::new([1e-300, 2e-300, 3e-300]).unwrap();
        assert!(check_start(&tiny, &Vector3::new(1e150, 1e150, 1e150)).is_ok());
        // ...but not slowly: |L|² = (Iω)² would underflow.
        assert!(check_start(&tiny, &Vector3::new(1e10, 1e10, 1e10)).is_err());
    }

    #[test]
    fn span_limit_follows_the_fastest_rate() {
        let b = Body::new([1.0, 2.0, 3.0]).unwrap();
        let w = Vector3::new(0.01, 10.0, 0.01);
        let s = scales(&b, &w);
        let limit = max_span(&s, true);
        assert!((limit * s.spin - MAX_PHASE).abs() < 1e-6 * MAX_PHASE);
        assert!(limit > 3.7e8 && limit < 3.75e8, "{limit}");
        assert!(check_span(&s, true, 1e8, "t =").is_ok());
        let err = check_span(&s, true, 1e17, "t =").unwrap_err().to_string();
        assert!(err.contains("t = 1e17 is beyond 371900000,"), "{err}");
        // Spinning 1e3 times faster shortens the span 1e3 times.
        let fast = scales(&b, &(w * 1e3));
        assert!((limit / max_span(&fast, true) - 1e3).abs() < 1e-6);
        // A body at rest never runs out of phase.
        let rest = scales(&b, &Vector3::zeros());
        assert_eq!(max_span(&rest, true), f64::INFINITY);
    }
}
