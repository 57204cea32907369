//! The rigid body's view of a stepper. Every solver that steps — DOP853,
//! RK4 and Radau IIA on a deck's system, DOP853, RK4 and the splittings on
//! a rigid body — is one [`Stepper`]: a point, one step, the window of the
//! last step and the values inside it. A rigid body's stepper adds what the
//! body needs ([`RigidStepper`]: its method, the state its vector stands
//! for, a budget aimed at the time asked for, a check of a state reached),
//! and [`Stepped`] turns it into the rigid body's [`Solver`], which the
//! exact solution implements too without taking steps.

use crate::error::SolveError;
use crate::rigid::model::State;
use crate::solvers::forward::Forward;
use crate::solvers::ode::Stepper;
use crate::solvers::{Method, Solver, Work};

/// What a stepper of the rigid body adds to [`Stepper`].
pub(crate) trait RigidStepper: Stepper {
    fn method(&self) -> Method;
    /// The state a vector of this stepper stands for.
    fn state_at(&self, y: &[f64]) -> State;
    /// The state at t = 0: the start as given (a method whose vector is not
    /// ω may not give it back bit for bit).
    fn initial(&self) -> State {
        self.state_at(self.current())
    }
    /// The run is about to be advanced to `t`: refuses at once a span the
    /// budget cannot cover, and remembers `t` for the checks on the way.
    fn aim(&mut self, t: f64) -> Result<(), SolveError>;
    /// Announces the last time the run will ask for ([`Solver::plan`]).
    fn plan(&mut self, t_end: f64) -> Result<(), SolveError>;
    /// Refuses a state served between steps that the run cannot stand on.
    fn check(&self, y: &[f64], t: f64) -> Result<(), SolveError> {
        let _ = (y, t);
        Ok(())
    }
}

/// A rigid body's stepper as a [`Solver`].
pub(crate) struct Stepped<R> {
    inner: R,
    forward: Forward,
    out: Vec<f64>,
}

impl<R: RigidStepper> Stepped<R> {
    pub(crate) fn new(inner: R) -> Stepped<R> {
        let out = inner.current().to_vec();
        Stepped {
            inner,
            forward: Forward::default(),
            out,
        }
    }
}

impl<R: RigidStepper> Solver for Stepped<R> {
    fn method(&self) -> Method {
        self.inner.method()
    }

    /// Steps until `t` is covered (a fixed-step method up to the last grid
    /// point before it), then reads the dense output.
    fn advance(&mut self, t: f64) -> Result<State, SolveError> {
        self.forward.accept(t)?;
        let r = &mut self.inner;
        r.aim(t)?;
        while r.window().1 < t && r.next_grid().is_none_or(|g| g <= t) {
            r.raw_step()?;
        }
        if t == 0.0 {
            return Ok(r.initial());
        }
        if t == r.window().1 {
            self.out.copy_from_slice(r.current());
        } else {
            r.interpolate(t, &mut self.out);
            r.check(&self.out, t)?;
        }
        Ok(r.state_at(&self.out))
    }

    fn work(&self) -> Work {
        let w = self.inner.work_done();
        Work {
            steps: w.steps,
            rhs_evals: w.rhs_evals,
            rejected: w.rejected,
        }
    }

    fn plan(&mut self, t_end: f64) -> Result<(), SolveError> {
        self.inner.plan(t_end)
    }
}
