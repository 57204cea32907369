//! The driver every fixed-step method shares (RK4, the splittings): steps
//! lie on the grid tₙ = n·dt whatever the sample times, a sample between
//! grid points is reached by one partial step from a copy (so the
//! trajectory is the same however often it is sampled), the step budget is
//! checked up front, and times only go forward. A method supplies only
//! what is its own: its point, one step, and the state a point stands for.

use crate::error::SolveError;
use crate::rigid::model::State;
use crate::solvers::budget::Budget;
use crate::solvers::forward::Forward;
use crate::solvers::{Method, Solver, Work};

/// One fixed-step method.
pub(crate) trait Stepper {
    /// What the method carries from step to step.
    type Point: Copy;
    fn method(&self) -> Method;
    fn start(&self) -> Self::Point;
    /// Advances `p` by `h`, counting the right-hand sides it evaluated.
    fn step(&self, p: &mut Self::Point, h: f64, work: &mut Work);
    fn state(&self, p: &Self::Point) -> State;
    /// Refuses a point the run cannot go on from (a step that diverged)
    /// reached on the way to `t`.
    fn check(&self, p: &Self::Point, t: f64) -> Result<(), SolveError> {
        let _ = (p, t);
        Ok(())
    }
    /// The state at t = 0: the start as given (a method whose point is not
    /// ω may not give it back bit for bit).
    fn initial(&self) -> State {
        self.state(&self.start())
    }
}

pub(crate) struct FixedSteps<M: Stepper> {
    method: M,
    dt: f64,
    budget: Budget,
    /// Grid points done, and the point at n·dt.
    n: u64,
    point: M::Point,
    forward: Forward,
    work: Work,
}

impl<M: Stepper> FixedSteps<M> {
    pub(crate) fn new(method: M, dt: f64, budget: Budget) -> FixedSteps<M> {
        FixedSteps {
            point: method.start(),
            method,
            dt,
            budget,
            n: 0,
            forward: Forward::default(),
            work: Work::default(),
        }
    }

    fn check_budget(&self, t: f64) -> Result<(), SolveError> {
        let more = (t / self.dt).floor() - self.n as f64;
        if self.budget.exceeded(self.work.steps, more) {
            return Err(SolveError::StepBudget {
                t: self.n as f64 * self.dt,
                steps: self.work.steps,
                reason: self.budget.fixed(
                    self.method.method().name(),
                    self.dt,
                    t,
                    self.work.steps as f64 + more,
                ),
            });
        }
        Ok(())
    }
}

impl<M: Stepper> Solver for FixedSteps<M> {
    fn method(&self) -> Method {
        self.method.method()
    }

    fn advance(&mut self, t: f64) -> Result<State, SolveError> {
        self.forward.accept(t)?;
        self.check_budget(t)?;
        let mut p = self.point;
        while (self.n + 1) as f64 * self.dt <= t {
            self.method.step(&mut p, self.dt, &mut self.work);
            self.n += 1;
            self.work.steps += 1;
            self.method.check(&p, t)?;
        }
        self.point = p;
        if t == 0.0 {
            return Ok(self.method.initial());
        }
        let rest = t - self.n as f64 * self.dt;
        if rest > 0.0 {
            self.method.step(&mut p, rest, &mut self.work);
            self.method.check(&p, t)?;
        }
        Ok(self.method.state(&p))
    }

    fn work(&self) -> Work {
        self.work
    }

    fn plan(&mut self, t_end: f64) -> Result<(), SolveError> {
        self.check_budget(t_end)
    }
}
