//! The interface every solver of the rigid body offers, so scenes, the
//! CLI, the bench and the terminal view can switch methods freely: the
//! [`Solver`] trait, the [`Method`] with its one accuracy knob, what a run
//! [`Needs`], its [`Work`] and its [`SolveError`]. The exact solution here in
//! `rigid` implements it, and so does every stepper of [`crate::solvers`]
//! through [`crate::solvers::stepped::Stepped`] (DOP853, RK4 and the
//! splittings on the rigid body's equations).

use crate::error::SolveError;
use crate::method::{MethodError, MethodName};
use crate::rigid::model::State;

/// Tolerances tighter than this are below f64 rounding for an 8th-order pair.
pub(crate) const MIN_TOL: f64 = 1e-14;

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

/// The solver families, before their accuracy knob is chosen, in the order
/// the live view cycles through them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    Exact,
    Adaptive,
    Splitting,
    Splitting4,
    Rk4,
}

impl Kind {
    pub const ALL: [Kind; 5] = [
        Kind::Exact,
        Kind::Adaptive,
        Kind::Splitting,
        Kind::Splitting4,
        Kind::Rk4,
    ];

    /// Its name in the one vocabulary ([`crate::method`]).
    pub fn method(self) -> MethodName {
        match self {
            Kind::Exact => MethodName::Exact,
            Kind::Adaptive => MethodName::Adaptive,
            Kind::Splitting => MethodName::Splitting,
            Kind::Splitting4 => MethodName::Splitting4,
            Kind::Rk4 => MethodName::Rk4,
        }
    }

    /// The name the command line, the CSV files and the screen use.
    pub fn name(self) -> &'static str {
        self.method().name()
    }

    /// The family a method names, or why a rigid body refuses it.
    pub fn from_method(method: MethodName) -> Result<Kind, MethodError> {
        Kind::ALL
            .into_iter()
            .find(|k| k.method() == method)
            .ok_or(MethodError::NotRigid(method))
    }

    /// The family after this one, wrapping round.
    pub fn next(self) -> Kind {
        let i = Kind::ALL.iter().position(|k| *k == self).unwrap_or(0);
        Kind::ALL[(i + 1) % Kind::ALL.len()]
    }
}

impl Method {
    pub fn kind(&self) -> Kind {
        match self {
            Method::Exact => Kind::Exact,
            Method::Adaptive { .. } => Kind::Adaptive,
            Method::Splitting { .. } => Kind::Splitting,
            Method::Splitting4 { .. } => Kind::Splitting4,
            Method::Rk4 { .. } => Kind::Rk4,
        }
    }

    pub fn name(&self) -> &'static str {
        self.kind().name()
    }

    /// The accuracy knob as the work–precision CSV writes it: `-`,
    /// `tol=1e-10`, `dt=2.4544e-3` (five digits, so rows stay distinct).
    pub fn setting(&self) -> String {
        match *self {
            Method::Exact => "-".to_string(),
            Method::Adaptive { tol } => format!("tol={tol:.0e}"),
            Method::Splitting { dt } | Method::Splitting4 { dt } | Method::Rk4 { dt } => {
                format!("dt={dt:.4e}")
            }
        }
    }

    /// The method as the screen shows it: `exact`, `adaptive tol=1e-10`,
    /// `rk4 dt=2.5e-3` (two digits: a label, not a record).
    pub fn label(&self) -> String {
        match *self {
            Method::Exact => "exact".into(),
            Method::Adaptive { tol } => format!("adaptive tol={tol:.0e}"),
            Method::Splitting { dt } | Method::Splitting4 { dt } | Method::Rk4 { dt } => {
                format!("{} dt={dt:.1e}", self.name())
            }
        }
    }

    /// The same family one notch coarser (`larger`) or finer: the step
    /// doubled or halved, the tolerance multiplied or divided by 100 within
    /// `[MIN_TOL, 1e-2]`; `None` for the exact solver, which has no knob.
    pub fn scaled(&self, larger: bool) -> Option<Method> {
        let f = if larger { 2.0 } else { 0.5 };
        match *self {
            Method::Exact => None,
            Method::Adaptive { tol } => {
                let tol = if larger { tol * 100.0 } else { tol / 100.0 };
                Some(Method::Adaptive {
                    tol: tol.clamp(MIN_TOL, 1e-2),
                })
            }
            Method::Splitting { dt } => Some(Method::Splitting { dt: dt * f }),
            Method::Splitting4 { dt } => Some(Method::Splitting4 { dt: dt * f }),
            Method::Rk4 { dt } => Some(Method::Rk4 { dt: dt * f }),
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

/// A solver advancing one trajectory forward in time.
pub trait Solver {
    fn method(&self) -> Method;
    /// The state at time `t`; `t` must not go back before the previous call's
    /// `t` (solvers may keep their internal step sequence and use dense
    /// output or a trial sub-step to land exactly on `t`).
    fn advance(&mut self, t: f64) -> Result<State, SolveError>;
    fn work(&self) -> Work;
    /// Announces the last time the run will ask for, so that a stepping
    /// solver can refuse at once a span its step budget cannot cover (and
    /// check its progress against that span while it runs). Solvers without
    /// a budget accept any span.
    fn plan(&mut self, t_end: f64) -> Result<(), SolveError> {
        let _ = t_end;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::METHODS;

    /// The vocabulary's `rigid` column and the families agree.
    #[test]
    fn the_families_are_the_methods_a_rigid_body_takes() {
        for row in METHODS {
            assert_eq!(
                Kind::from_method(row.method).is_ok(),
                row.rigid,
                "{}",
                row.name
            );
        }
        for kind in Kind::ALL {
            assert_eq!(Kind::from_method(kind.method()), Ok(kind));
        }
    }
}
