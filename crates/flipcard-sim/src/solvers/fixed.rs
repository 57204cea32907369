//! The driver every fixed-step method of the rigid body shares (RK4, the
//! splittings): steps lie on the grid tₙ = n·dt whatever the sample times, a
//! sample between grid points is reached by one partial step from a copy
//! (so the trajectory is the same however often it is sampled, and no step
//! is taken past the last time asked for), the step budget is checked up
//! front, and times only go forward. A method supplies only its rule
//! ([`StepRule`]): its point, one step, and the state a point stands for.
//! The driver is a [`Stepper`] like every other solver, and a
//! [`RigidStepper`].

use crate::error::SolveError;
use crate::rigid::model::State;
use crate::solvers::Method;
use crate::solvers::budget::Budget;
use crate::solvers::ode::{Requests, Stepper, Work};
use crate::solvers::stepped::RigidStepper;

/// One fixed-step method's rule.
pub(crate) trait StepRule {
    /// What the method carries from step to step: its coordinates, of
    /// which the first [`StepRule::size`] are used.
    type Point: Copy + AsRef<[f64]> + AsMut<[f64]>;
    fn method(&self) -> Method;
    fn size(&self) -> usize;
    fn start(&self) -> Self::Point;
    /// Advances `p` by `h`, counting the right-hand sides it evaluated.
    fn step(&self, p: &mut Self::Point, h: f64, work: &mut Work);
    fn state(&self, p: &[f64]) -> State;
    /// Refuses a point the run cannot go on from (a step that diverged)
    /// reached on the way to `t`.
    fn check(&self, p: &[f64], t: f64) -> Result<(), SolveError> {
        let _ = (p, t);
        Ok(())
    }
    /// The state at t = 0: the start as given (a method whose point is not
    /// ω may not give it back bit for bit).
    fn initial(&self) -> State {
        self.state(self.start().as_ref())
    }
}

pub(crate) struct FixedSteps<M: StepRule> {
    method: M,
    dt: f64,
    budget: Budget,
    /// Grid points done, and the points at n·dt and (n − 1)·dt.
    n: u64,
    point: M::Point,
    previous: M::Point,
    /// The time the run is being advanced to (named when a step diverges).
    target: f64,
    requests: Requests,
    work: Work,
}

impl<M: StepRule> FixedSteps<M> {
    pub(crate) fn new(method: M, dt: f64, budget: Budget) -> FixedSteps<M> {
        let point = method.start();
        FixedSteps {
            requests: Requests::new(0.0, &point.as_ref()[..method.size()]),
            point,
            previous: point,
            method,
            dt,
            budget,
            n: 0,
            target: 0.0,
            work: Work::default(),
        }
    }

    fn grid(&self, n: u64) -> f64 {
        n as f64 * self.dt
    }

    fn check_budget(&self, t: f64) -> Result<(), SolveError> {
        let more = (t / self.dt).floor() - self.n as f64;
        if self.budget.exceeded(self.work.steps, more) {
            return Err(SolveError::StepBudget {
                t: self.grid(self.n),
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

impl<M: StepRule> Stepper for FixedSteps<M> {
    fn method_name(&self) -> &'static str {
        self.method.method().name()
    }
    fn work_done(&self) -> Work {
        self.work
    }
    fn requests(&mut self) -> &mut Requests {
        &mut self.requests
    }
    fn t_stop(&self) -> Option<f64> {
        None
    }
    fn window(&self) -> (f64, f64) {
        (self.grid(self.n.saturating_sub(1)), self.grid(self.n))
    }
    fn current(&self) -> &[f64] {
        &self.point.as_ref()[..self.method.size()]
    }
    fn check_span(&self, t: f64) -> Result<(), SolveError> {
        self.check_budget(t)
    }
    fn next_grid(&self) -> Option<f64> {
        Some(self.grid(self.n + 1))
    }
    fn raw_step(&mut self) -> Result<(), SolveError> {
        let mut p = self.point;
        self.method.step(&mut p, self.dt, &mut self.work);
        self.previous = self.point;
        self.point = p;
        self.n += 1;
        self.work.steps += 1;
        self.method.check(self.current(), self.target)
    }
    /// Within the last step, a partial step from its start; ahead of it (up
    /// to the next grid point), a partial step from the current point.
    fn interpolate(&mut self, t: f64, out: &mut [f64]) {
        let (t_old, t_new) = self.window();
        let (mut p, from) = if t >= t_new {
            (self.point, t_new)
        } else {
            (self.previous, t_old)
        };
        let rest = t - from;
        if rest > 0.0 {
            self.method.step(&mut p, rest, &mut self.work);
        }
        out.copy_from_slice(&p.as_ref()[..self.method.size()]);
    }
}

impl<M: StepRule> RigidStepper for FixedSteps<M> {
    fn method(&self) -> Method {
        self.method.method()
    }
    fn state_at(&self, y: &[f64]) -> State {
        self.method.state(y)
    }
    fn initial(&self) -> State {
        self.method.initial()
    }
    fn aim(&mut self, t: f64) -> Result<(), SolveError> {
        self.target = t;
        self.check_budget(t)
    }
    fn plan(&mut self, t_end: f64) -> Result<(), SolveError> {
        self.check_budget(t_end)
    }
    fn check(&self, y: &[f64], t: f64) -> Result<(), SolveError> {
        self.method.check(y, t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rigid::model::Body;
    use crate::solvers::Solver;
    use crate::solvers::ode::OdeSolver;
    use crate::solvers::splitting::{Scheme, splitting};
    use crate::solvers::stepped::Stepped;
    use nalgebra::Vector3;

    fn run(orientation: bool) -> FixedSteps<crate::solvers::splitting::SplittingSteps> {
        let body = Body::new([1.0, 2.0, 3.0]).unwrap();
        let omega = Vector3::new(0.3, 2.0, 0.1);
        splitting(
            &body,
            &omega,
            0.01,
            Scheme::Strang,
            orientation,
            Budget::default(),
        )
    }

    /// The fixed-step stepper is a stepper like every other: driven through
    /// the systems' interface it serves the same points as the rigid body's
    /// solver, and neither takes a step past the last time asked for.
    #[test]
    fn both_interfaces_serve_the_same_points_without_stepping_past_a_request() {
        for orientation in [false, true] {
            let mut rigid = Stepped::new(run(orientation));
            let mut ode = run(orientation);
            let size = ode.current().len();
            assert_eq!(size, if orientation { 7 } else { 3 });
            for t in [0.0, 0.004, 0.01, 0.0371, 0.5, 0.503, 1.25] {
                let state = rigid.advance(t).unwrap();
                let y = OdeSolver::advance(&mut ode, t).unwrap().to_vec();
                assert_eq!(y.len(), size);
                // (At t = 0 the rigid body gives back its start as given.)
                if t > 0.0 {
                    let other = ode.state_at(&y);
                    let pairs = state.omega.iter().zip(other.omega.iter());
                    let pairs = pairs.chain(state.q.coords.iter().zip(other.q.coords.iter()));
                    for (a, b) in pairs {
                        assert_eq!(a.to_bits(), b.to_bits(), "t = {t}");
                    }
                }
                // Grid points at or before t only: floor(t/dt) steps.
                let steps = (0..).take_while(|&n| n as f64 * 0.01 <= t).last().unwrap();
                assert_eq!(rigid.work().steps, steps, "t = {t}");
                assert_eq!(OdeSolver::work(&ode).steps, steps, "t = {t}");
            }
        }
    }
}
