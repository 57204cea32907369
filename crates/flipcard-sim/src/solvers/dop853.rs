//! The rigid body's adaptive solver: the systems' DOP853
//! ([`crate::solvers::ode::Dop853`], one implementation of the method)
//! stepping Euler's equations, with what is the rigid body's own around it.
//!
//! The step sequence depends only on the trajectory and the tolerance:
//! sample times are served from the dense output of the step that covers
//! them, so asking for more or fewer samples never changes the steps taken.
//!
//! What the rigid body adds: its absolute tolerances (ω against |ω₀|, q
//! against 1), norms and the starting step taken without squares (spins up
//! to ~1e150), no magnitude cap (its size is bounded by its energy), and a
//! step budget refused up front from the body's time scales and checked
//! after every trial against the projected count, with a reason that names
//! the motion. The trials themselves ([`Dop853::trial`]) and the dense
//! output are the systems' code, so both kinds of scene step alike.

use crate::error::SolveError;
use nalgebra::Vector3;

use crate::rigid::euler::RigidSystem;
use crate::rigid::model::State;
use crate::rigid::scales::Scales;
use crate::solvers::Method;
use crate::solvers::budget::Budget;
use crate::solvers::ode::{Dop853, Requests, Stepper, Work};
use crate::solvers::stepped::RigidStepper;
use flipcard_text::num::Num;

/// DOP853's order (the exponent of the step-size control is its inverse).
const ORDER: f64 = 8.0;
const ORDER_EXPONENT: f64 = 1.0 / ORDER;
/// The projected step count is checked this often during a long advance.
const PROJECTION_EVERY: u64 = 256;
/// ...once this many steps give the projection some footing.
const PROJECTION_AFTER: u64 = 1000;

/// Steps per radian of the fastest rate at tolerance `tol`: 2–6 times fewer
/// than DOP853 takes on Euler's equations (measured on flipping, precessing
/// and needle-like bodies, tol 1e-6 to 1e-12), so that the up-front check
/// refuses only spans clearly beyond the budget; the count during the run
/// is exact.
fn steps_per_radian(tol: f64) -> f64 {
    0.05 * tol.powf(-ORDER_EXPONENT)
}

/// Expected steps to cover `span` at `tol` when the fastest rate is `rate`.
pub(crate) fn estimated_steps(rate: f64, span: f64, tol: f64) -> f64 {
    rate * span * steps_per_radian(tol)
}

/// DOP853 on one of the rigid body's systems (ω alone, or ω and q).
pub(crate) struct Adaptive<S, const N: usize> {
    stepper: Dop853<S, N>,
    sys: S,
    tol: f64,
    budget: Budget,
    scales: Scales,
    orientation: bool,
    horizon: f64,
    /// The end the step budget is projected to (the time asked for, or
    /// the planned end if later).
    end: f64,
    requests: Requests,
}

impl<S: RigidSystem<N>, const N: usize> Adaptive<S, N> {
    pub(crate) fn new(
        sys: S,
        omega0: &Vector3<f64>,
        tol: f64,
        budget: Budget,
        scales: Scales,
        orientation: bool,
    ) -> Adaptive<S, N> {
        let y = sys.initial(omega0);
        Adaptive {
            stepper: Dop853::rigid(sys, &y, tol, sys.atol(tol).to_vec()),
            sys,
            tol,
            budget,
            scales,
            orientation,
            horizon: 0.0,
            end: 0.0,
            requests: Requests::new(0.0, &y),
        }
    }

    fn t(&self) -> f64 {
        self.stepper.window().1
    }

    fn attempts(&self) -> u64 {
        let w = self.stepper.work_done();
        w.steps + w.rejected
    }

    fn stiff(&self, steps: f64) -> SolveError {
        SolveError::StepBudget {
            t: self.t(),
            steps: self.attempts(),
            reason: self
                .budget
                .stiff(&self.scales.describe(self.orientation), steps),
        }
    }

    /// Refuses up front a span the budget clearly cannot cover.
    fn check_estimate(&self, end: f64) -> Result<(), SolveError> {
        let more = estimated_steps(
            self.scales.fastest(self.orientation),
            end - self.t(),
            self.tol,
        );
        if self.budget.exceeded(self.attempts(), more) {
            return Err(self.stiff(self.attempts() as f64 + more));
        }
        Ok(())
    }

    /// During the run: extrapolates the steps taken so far to the end of the
    /// span, and stops at the hard cap whatever the projection says.
    fn check_progress(&self, end: f64) -> Result<(), SolveError> {
        let taken = self.attempts();
        let t = self.t();
        let projected = if t > 0.0 {
            taken as f64 * (end / t).max(1.0)
        } else {
            f64::INFINITY
        };
        if taken > self.budget.max_steps {
            return Err(self.stiff(projected));
        }
        if taken >= PROJECTION_AFTER
            && taken.is_multiple_of(PROJECTION_EVERY)
            && projected > 1.25 * self.budget.max_steps as f64
        {
            return Err(self.stiff(projected));
        }
        Ok(())
    }

    /// One accepted step (after as many rejected trials as it takes).
    fn step(&mut self) -> Result<(), SolveError> {
        let end = self.end;
        self.stepper.start_next();
        loop {
            let h = self.stepper.step_to_try();
            let t = self.t();
            let resolvable = h > 4.0 * f64::EPSILON * t.abs();
            if !resolvable || !self.stepper.current().iter().all(|v| v.is_finite()) {
                return Err(SolveError::Invalid(format!(
                    "adaptive: step size underflow at t = {} (the solution is not resolvable at tol = {})",
                    Num(t),
                    Num(self.tol)
                )));
            }
            let accepted = self.stepper.trial(h)?;
            self.check_progress(end)?;
            if accepted {
                return Ok(());
            }
        }
    }
}

impl<S: RigidSystem<N>, const N: usize> Stepper for Adaptive<S, N> {
    fn method_name(&self) -> &'static str {
        self.stepper.method_name()
    }
    fn work_done(&self) -> Work {
        self.stepper.work_done()
    }
    fn requests(&mut self) -> &mut Requests {
        &mut self.requests
    }
    fn t_stop(&self) -> Option<f64> {
        None
    }
    fn window(&self) -> (f64, f64) {
        self.stepper.window()
    }
    fn current(&self) -> &[f64] {
        self.stepper.current()
    }
    fn check_span(&self, t: f64) -> Result<(), SolveError> {
        self.check_estimate(t.max(self.horizon))
    }
    fn raw_step(&mut self) -> Result<(), SolveError> {
        self.step()
    }
    fn interpolate(&mut self, t: f64, out: &mut [f64]) {
        self.stepper.interpolate(t, out)
    }
}

impl<S: RigidSystem<N>, const N: usize> RigidStepper for Adaptive<S, N> {
    fn method(&self) -> Method {
        Method::Adaptive { tol: self.tol }
    }

    fn state_at(&self, y: &[f64]) -> State {
        let mut point = [0.0; N];
        point.copy_from_slice(y);
        self.sys.state(&point)
    }

    fn aim(&mut self, t: f64) -> Result<(), SolveError> {
        if t > self.t() {
            self.end = t.max(self.horizon);
            self.check_estimate(self.end)?;
        }
        Ok(())
    }

    fn plan(&mut self, t_end: f64) -> Result<(), SolveError> {
        self.horizon = self.horizon.max(t_end);
        self.check_estimate(self.horizon.max(self.t()))
    }
}
