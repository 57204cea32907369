//! The one error of a simulation run, whichever stack computes it: the
//! rigid body's solvers (exact, adaptive, splitting, RK4) and the solvers
//! of deck systems (DOP853, Radau IIA, RK4, auto) both stop with a
//! [`SolveError`], so scenes, the bench, the CLI and the terminal view
//! handle one type. Errors are values and leave the solver stopped. It
//! holds [`ModelError`] too (a body or spin that is not physical), so that
//! it uses nothing of the stacks and they both use it.

use flipcard_text::num::Num;

/// Why a run could not go on (or could not start).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolveError {
    /// The rigid body or its starting spin is not physical.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// A component became non-finite or exceeded
    /// [`crate::solvers::ode::BLOW_UP_LIMIT`], or the step size fell below
    /// what t can resolve while the solution grew past a million times its
    /// starting size: the solution is singular near `t`, the last time
    /// reached with a valid state.
    #[error("the solution blows up near t = {t}")]
    BlowUp { t: f64 },
    /// The step size fell to `h`, below what t can resolve, near `t`, while
    /// the solution stayed within a million times its starting size: not a
    /// blow-up — the method cannot meet its tolerance there (a component
    /// the absolute tolerance does not control, a right-hand side that
    /// leaves its domain or jumps).
    #[error(
        "the step size fell to {} near t = {} while the solution stayed bounded: the tolerance cannot be met here",
        flipcard_text::num::sig(*h, 2), flipcard_text::num::sig(*t, 4)
    )]
    StepSize { t: f64, h: f64 },
    /// The run needed (or would need) more step attempts than its budget:
    /// `t` is the time reached and `steps` the attempts made when it
    /// stopped (a span refused up front stops at its start); `reason`
    /// says why and what to use instead.
    #[error("{reason}")]
    StepBudget { t: f64, steps: u64, reason: String },
    /// The explicit method found the problem stiff at `t` and was told to
    /// refuse stiff problems.
    #[error("the problem is stiff from t = {t}; an implicit method (radau) suits it")]
    Stiff { t: f64 },
    /// A fixed-step method whose step is past its stability bound: near
    /// `t` the system's fastest rate (the spectral radius of its Jacobian,
    /// estimated) is `rate`, and `dt`·`rate` exceeds `limit`; every step
    /// from there would amplify errors instead of the solution.
    #[error(
        "{method} with dt = {} is unstable here: near t = {} the system's fastest rate is about {} per time unit, and {method} is stable only while dt·rate < {} (dt < {}); take a smaller dt, or auto",
        Num(*dt), flipcard_text::num::sig(*t, 4), flipcard_text::num::sig(*rate, 3), Num(*limit), flipcard_text::num::sig(limit / rate, 2)
    )]
    Unstable {
        method: &'static str,
        t: f64,
        rate: f64,
        dt: f64,
        limit: f64,
    },
    /// A setting or a request the solver cannot take.
    #[error("{0}")]
    Invalid(String),
}

/// Why an input is not a physical rigid body or state.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
    #[error("moment of inertia I{axis} = {} is not finite", Num(*.value))]
    NonFiniteInertia { axis: usize, value: f64 },
    #[error("moment of inertia I{axis} = {} is not positive", Num(*.value))]
    NonPositiveInertia { axis: usize, value: f64 },
    #[error(
        "moments break the triangle inequality: I{i} + I{j} = {} < I{k} = {} (no rigid body has these principal moments)",
        Num(*.sum),
        Num(*.value)
    )]
    Triangle {
        i: usize,
        j: usize,
        k: usize,
        sum: f64,
        value: f64,
    },
    #[error("angular velocity ω{axis} = {} is not finite", Num(*.value))]
    NonFiniteOmega { axis: usize, value: f64 },
}
