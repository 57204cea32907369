//! Building a solver: the one place that knows every method, checks its
//! setting, fills in defaults and picks what to integrate (ω alone, or ω and
//! q) from what the run needs.

use crate::error::SolveError;
use nalgebra::Vector3;

use crate::rigid::euler::{OmegaOnly, WithOrientation};
use crate::rigid::exact::Exact;
pub(crate) use crate::rigid::limits::check_start;
use crate::rigid::model::Body;
use crate::rigid::scales::{Scales, momentum_gain, scales};
pub use crate::solvers::Kind;
use crate::solvers::budget::Budget;
use crate::solvers::dop853::Adaptive;
use crate::solvers::guard::Guard;
use crate::solvers::rk4::rk4;
use crate::solvers::splitting::{Scheme, splitting};
use crate::solvers::stepped::Stepped;
use crate::solvers::{Method, Needs, Solver};
use flipcard_text::num::Num;

/// Default tolerance of the adaptive solver (relative, and absolute against
/// |ω₀| for ω): about 1e-9 relative error in ω over the notes' 36 flips.
pub(crate) const DEFAULT_TOL: f64 = 1e-10;
pub(crate) use crate::rigid::solver::MIN_TOL;
/// Default fixed step: this many steps per turn (2π) of the fastest rate of
/// the orbit, nutation or spin.
pub(crate) const DEFAULT_STEPS_PER_TURN: f64 = 256.0;
/// The largest [`momentum_gain`] the splitting accepts. It carries L and
/// divides by the moments for ω, so each rounding of L (ε relative) shows
/// in ω multiplied by the gain. A budget's worth of steps is up to 1e8
/// rotations, whose roundings add up like a random walk (√1e8 = 1e4), so a
/// gain of 1e-8/ε ≈ 4.5e7 keeps their sum in ω below ~1e-4 of |ω|. Needles
/// thinner than that are left to the methods that carry ω itself.
pub(crate) const MAX_SPLITTING_GAIN: f64 = 1e-8 / f64::EPSILON;

/// Settings of one run beyond the method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Options {
    pub budget: Budget,
}

/// The default fixed step for a body and initial ω: 2π/(256·Ω), Ω the
/// fastest rate on the orbit (nutation frequency or largest |ω|), so ω and
/// q both get 256 steps per turn; 1 s when nothing moves. It does not depend
/// on whether q is needed, so ω comes out the same either way.
pub fn default_dt(body: &Body, omega0: &Vector3<f64>) -> f64 {
    let rate = scales(body, omega0).fastest(true);
    if rate > 0.0 {
        std::f64::consts::TAU / (DEFAULT_STEPS_PER_TURN * rate)
    } else {
        1.0
    }
}

/// The default step of a family. The splitting's error in ω is its error
/// in L multiplied by [`momentum_gain`], so its step shrinks by the gain's
/// square root (2nd order) or fourth root (4th order) to keep the same
/// accuracy in ω as on a compact body.
pub fn default_dt_for(kind: Kind, body: &Body, omega0: &Vector3<f64>) -> f64 {
    let order = match kind {
        Kind::Splitting => 2.0,
        Kind::Splitting4 => 4.0,
        _ => return default_dt(body, omega0),
    };
    default_dt(body, omega0) / momentum_gain(body, omega0).powf(1.0 / order)
}

/// Refuses the splitting for a body whose [`momentum_gain`] is past
/// [`MAX_SPLITTING_GAIN`].
fn check_splitting(method: &Method, body: &Body, omega0: &Vector3<f64>) -> Result<(), SolveError> {
    if !matches!(method, Method::Splitting { .. } | Method::Splitting4 { .. }) {
        return Ok(());
    }
    let gain = momentum_gain(body, omega0);
    if gain <= MAX_SPLITTING_GAIN {
        return Ok(());
    }
    let i = body.inertia;
    Err(SolveError::Invalid(format!(
        "{} carries L = Iω and divides by the moments to get ω; for this body (I_max/I_min = {:.1e}) that multiplies every rounding of L by {:.1e} in ω, beyond the {:.1e} it can afford: use the exact method (or rk4 or adaptive, which carry ω)",
        method.name(),
        i.max() / i.min(),
        gain,
        MAX_SPLITTING_GAIN
    )))
}

/// A method from a family and the knobs the user gave (`None` = default).
/// A knob the family has no use for is an error, not silently ignored.
pub fn method(
    kind: Kind,
    tol: Option<f64>,
    dt: Option<f64>,
    body: &Body,
    omega0: &Vector3<f64>,
) -> Result<Method, SolveError> {
    let name = kind.name();
    check_start(body, omega0)?;
    let fixed_step = matches!(kind, Kind::Splitting | Kind::Splitting4 | Kind::Rk4);
    if tol.is_some() && kind != Kind::Adaptive {
        return Err(SolveError::Invalid(format!(
            "tol applies only to the adaptive method, not to {name}{}",
            if fixed_step { " (use dt)" } else { "" }
        )));
    }
    if dt.is_some() && !fixed_step {
        return Err(SolveError::Invalid(format!(
            "dt applies only to the fixed-step methods (splitting, splitting4, rk4), not to {name}"
        )));
    }
    let dt = || dt.unwrap_or_else(|| default_dt_for(kind, body, omega0));
    let method = match kind {
        Kind::Exact => Method::Exact,
        Kind::Adaptive => Method::Adaptive {
            tol: tol.unwrap_or(DEFAULT_TOL),
        },
        Kind::Splitting => Method::Splitting { dt: dt() },
        Kind::Splitting4 => Method::Splitting4 { dt: dt() },
        Kind::Rk4 => Method::Rk4 { dt: dt() },
    };
    check_method(&method)?;
    check_splitting(&method, body, omega0)?;
    Ok(method)
}

fn check_method(method: &Method) -> Result<(), SolveError> {
    match *method {
        Method::Exact => Ok(()),
        Method::Adaptive { tol } => {
            if !(tol.is_finite() && tol > 0.0) {
                Err(SolveError::Invalid(format!(
                    "tol must be a positive number, got {}",
                    Num(tol)
                )))
            } else if tol < MIN_TOL {
                Err(SolveError::Invalid(format!(
                    "tol = {} is below what f64 arithmetic can deliver (use at least {})",
                    Num(tol),
                    Num(MIN_TOL)
                )))
            } else if tol >= 1.0 {
                Err(SolveError::Invalid(format!(
                    "tol = {} is not a tolerance (use a value below 1, e.g. 1e-8)",
                    Num(tol)
                )))
            } else {
                Ok(())
            }
        }
        Method::Splitting { dt } | Method::Splitting4 { dt } | Method::Rk4 { dt } => {
            if dt.is_finite() && dt > 0.0 {
                Ok(())
            } else {
                Err(SolveError::Invalid(format!(
                    "dt must be a positive number, got {}",
                    Num(dt)
                )))
            }
        }
    }
}

/// Refuses a fixed step that turns the fastest phase by more than half a
/// turn (π): a rotation by θ and by θ + 2π are the same to a step, so the
/// motion is aliased whatever the method does with it (RK4 also diverges
/// past Ωdt = 2√2). The splitting turns L by ωᵢdt about each axis even
/// when q is not wanted, so its rate includes the spin.
fn check_step(method: &Method, rates: &Scales, orientation: bool) -> Result<(), SolveError> {
    let (dt, rate) = match *method {
        Method::Splitting { dt } | Method::Splitting4 { dt } => (dt, rates.fastest(true)),
        Method::Rk4 { dt } => (dt, rates.fastest(orientation)),
        Method::Exact | Method::Adaptive { .. } => return Ok(()),
    };
    if rate * dt <= std::f64::consts::PI {
        return Ok(());
    }
    Err(SolveError::Invalid(format!(
        "{}: dt = {} turns the {} by {} rad per step, more than half a turn, so the motion aliases; use dt ≤ {} or the exact method",
        method.name(),
        Num(dt),
        rates.describe(orientation || !matches!(method, Method::Rk4 { .. })),
        flipcard_text::num::rounded(rate * dt, 3),
        Num(flipcard_text::num::below(std::f64::consts::PI / rate, 3))
    )))
}

/// A solver for `method` with the default step budget.
pub fn make(
    method: Method,
    body: Body,
    omega0: Vector3<f64>,
    needs: Needs,
) -> Result<Box<dyn Solver>, SolveError> {
    make_with(method, body, omega0, needs, Options::default())
}

/// A solver for `method`, integrating q only when `needs.orientation`,
/// behind a [`Guard`] that refuses spans and states f64 cannot honestly
/// give.
pub fn make_with(
    method: Method,
    body: Body,
    omega0: Vector3<f64>,
    needs: Needs,
    options: Options,
) -> Result<Box<dyn Solver>, SolveError> {
    // `Body` has a public field: check it again rather than trust it.
    let body = Body::new([body.inertia[0], body.inertia[1], body.inertia[2]])?;
    check_start(&body, &omega0)?;
    check_method(&method)?;
    check_splitting(&method, &body, &omega0)?;
    let rates = scales(&body, &omega0);
    let budget = options.budget;
    let q = needs.orientation;
    check_step(&method, &rates, q)?;
    let solver: Box<dyn Solver> = match method {
        Method::Exact => Box::new(Exact::new(body, omega0, needs)?),
        Method::Adaptive { tol } if q => Box::new(Stepped::new(Adaptive::<_, 7>::new(
            WithOrientation::new(&body, &omega0),
            &omega0,
            tol,
            budget,
            rates,
            q,
        ))),
        Method::Adaptive { tol } => Box::new(Stepped::new(Adaptive::<_, 3>::new(
            OmegaOnly::new(&body, &omega0),
            &omega0,
            tol,
            budget,
            rates,
            q,
        ))),
        Method::Rk4 { dt } if q => Box::new(Stepped::new(rk4::<_, 7>(
            WithOrientation::new(&body, &omega0),
            &omega0,
            dt,
            budget,
            rates,
            q,
        ))),
        Method::Rk4 { dt } => Box::new(Stepped::new(rk4::<_, 3>(
            OmegaOnly::new(&body, &omega0),
            &omega0,
            dt,
            budget,
            rates,
            q,
        ))),
        Method::Splitting { dt } => Box::new(Stepped::new(splitting(
            &body,
            &omega0,
            dt,
            Scheme::Strang,
            q,
            budget,
        ))),
        Method::Splitting4 { dt } => Box::new(Stepped::new(splitting(
            &body,
            &omega0,
            dt,
            Scheme::Suzuki,
            q,
            budget,
        ))),
    };
    Ok(Box::new(Guard::new(solver, body, &omega0, rates, q)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn case_a() -> (Body, Vector3<f64>) {
        (
            Body::new([1.0, 2.0, 3.0]).unwrap(),
            Vector3::new(0.01, 10.0, 0.01),
        )
    }

    #[test]
    fn defaults_fill_in_and_misplaced_knobs_are_refused() {
        let (b, w) = case_a();
        assert_eq!(
            method(Kind::Adaptive, None, None, &b, &w),
            Ok(Method::Adaptive { tol: DEFAULT_TOL })
        );
        match method(Kind::Rk4, None, None, &b, &w) {
            Ok(Method::Rk4 { dt }) => assert!(dt > 1e-4 && dt < 1e-2, "{dt}"),
            other => panic!("{other:?}"),
        }
        assert!(method(Kind::Rk4, Some(1e-8), None, &b, &w).is_err());
        assert!(method(Kind::Adaptive, None, Some(0.01), &b, &w).is_err());
        assert!(method(Kind::Exact, Some(1e-8), None, &b, &w).is_err());
        assert!(method(Kind::Splitting, None, Some(0.0), &b, &w).is_err());
        assert!(method(Kind::Splitting, None, Some(f64::NAN), &b, &w).is_err());
        assert!(method(Kind::Adaptive, Some(-1e-8), None, &b, &w).is_err());
        assert!(method(Kind::Adaptive, Some(1e-20), None, &b, &w).is_err());
    }

    #[test]
    fn default_step_shrinks_with_spin() {
        let (b, w) = case_a();
        let slow = default_dt(&b, &w);
        let fast = default_dt(&b, &(w * 1e4));
        assert!((slow / fast - 1e4).abs() < 1e-6);
        assert_eq!(default_dt(&b, &Vector3::zeros()), 1.0);
    }

    #[test]
    fn overflowing_spin_is_refused() {
        let (b, _) = case_a();
        let huge = Vector3::new(1e200, 0.0, 0.0);
        let needs = Needs { orientation: false };
        assert!(make(Method::Adaptive { tol: 1e-8 }, b, huge, needs).is_err());
    }
}
