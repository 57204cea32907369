//! The solvers. The rigid body's: the interface every one of them offers
//! (so scenes, the CLI, the bench and the terminal view can switch methods
//! freely), the adaptive DOP853, RK4, the splitting methods, and the
//! registry that builds any of them behind the guard. `ode`: the same
//! family, with Radau IIA and stiffness detection, for systems of any size
//! written in a deck.

pub mod budget;
pub mod dop853;
pub mod dop853_tableau;
pub mod guard;
pub mod ode;
pub mod registry;
pub mod rk4;
pub mod splitting;

use crate::sim::rigid::model::{ModelError, State};

/// A solver and its one accuracy knob.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    /// Closed form (Jacobi elliptic functions); the reference for every error figure.
    Exact,
    /// Embedded Runge–Kutta pair with error control and dense output.
    Adaptive { tol: f64 },
    /// Strang splitting into exactly solvable free-rotor flows (2nd order).
    Splitting { dt: f64 },
    /// 4th-order composition of the Strang splitting.
    Splitting4 { dt: f64 },
    /// Classical fixed-step RK4 with the quaternion renormalised.
    Rk4 { dt: f64 },
}

impl Method {
    pub fn name(&self) -> &'static str {
        match self {
            Method::Exact => "exact",
            Method::Adaptive { .. } => "adaptive",
            Method::Splitting { .. } => "splitting",
            Method::Splitting4 { .. } => "splitting4",
            Method::Rk4 { .. } => "rk4",
        }
    }
}

/// What a run must produce: a scene that draws no body asks for no
/// orientation, and then none is computed (q stays the identity).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Needs {
    pub orientation: bool,
}

/// Work counters of a run so far.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Work {
    /// Accepted steps (0 for the exact solver).
    pub steps: u64,
    /// Evaluations of the right-hand side (Euler's equations, with or without q).
    pub rhs_evals: u64,
    /// Rejected steps of an adaptive solver.
    pub rejected: u64,
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimError {
    #[error(transparent)]
    Model(#[from] ModelError),
    /// The run would need more steps than its budget; `reason` says why and
    /// what to use instead.
    #[error("{0}")]
    Budget(String),
    #[error("{0}")]
    Invalid(String),
}

/// A solver advancing one trajectory forward in time.
pub trait Solver {
    fn method(&self) -> Method;
    /// The state at time `t`; `t` must not go back before the previous call's
    /// `t` (solvers may keep their internal step sequence and use dense
    /// output or a trial sub-step to land exactly on `t`).
    fn advance(&mut self, t: f64) -> Result<State, SimError>;
    fn work(&self) -> Work;
    /// Announces the last time the run will ask for, so that a stepping
    /// solver can refuse at once a span its step budget cannot cover (and
    /// check its progress against that span while it runs). Solvers without
    /// a budget accept any span.
    fn plan(&mut self, t_end: f64) -> Result<(), SimError> {
        let _ = t_end;
        Ok(())
    }
}
