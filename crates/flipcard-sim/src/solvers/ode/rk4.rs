//! Classical fixed-step RK4, the textbook baseline for comparisons.
//!
//! Steps lie on the grid tₙ = t₀ + n·dt whatever the requests: a time
//! between grid points is reached by one partial RK4 step from the grid
//! point before it, on a copy, so sampling never changes the trajectory.

use super::{OdeSystem, Options, Requests, Stepper, Work, is_sane};
use crate::error::SolveError;
use crate::solvers::rk4::rk4_step;

pub struct Rk4<S> {
    sys: S,
    dt: f64,
    t0: f64,
    /// Grid index of the current point.
    index: u64,
    max_steps: u64,
    t: f64,
    y: Vec<f64>,
    t_old: f64,
    y_old: Vec<f64>,
    y_new: Vec<f64>,
    k: [Vec<f64>; 4],
    tmp: Vec<f64>,
    requests: Requests,
    work: Work,
}

impl<S: OdeSystem> Rk4<S> {
    /// Steps of `dt` from (t0, y0); only `opts.max_steps` applies.
    pub fn new(sys: S, t0: f64, y0: &[f64], dt: f64, opts: &Options) -> Result<Rk4<S>, SolveError> {
        super::check_start(&sys, t0, y0)?;
        if !(dt.is_finite() && dt > 0.0) {
            return Err(SolveError::Invalid(format!(
                "rk4: dt = {dt} must be positive"
            )));
        }
        if opts.max_steps == 0 {
            return Err(SolveError::Invalid("max_steps must be at least 1".into()));
        }
        let n = sys.dim();
        Ok(Rk4 {
            sys,
            dt,
            t0,
            index: 0,
            max_steps: opts.max_steps,
            t: t0,
            y: y0.to_vec(),
            t_old: t0,
            y_old: y0.to_vec(),
            y_new: vec![0.0; n],
            k: [vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            tmp: vec![0.0; n],
            requests: Requests::new(t0, y0),
            work: Work::default(),
        })
    }

    /// One RK4 step of size h from (t, y) into `out`.
    fn rk4(&mut self, t: f64, from_old: bool, h: f64, out: &mut [f64]) {
        let y: &[f64] = if from_old { &self.y_old } else { &self.y };
        let sys = &self.sys;
        let rhs = |t: f64, y: &[f64], dy: &mut [f64]| sys.rhs(t, y, dy);
        rk4_step(rhs, t, h, y, &mut self.k, &mut self.tmp, out);
        self.work.rhs_evals += 4;
    }

    fn grid(&self, index: u64) -> f64 {
        self.t0 + index as f64 * self.dt
    }
}

impl<S: OdeSystem> Stepper for Rk4<S> {
    fn method_name(&self) -> &'static str {
        "rk4"
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
        (self.t_old, self.t)
    }
    fn current(&self) -> &[f64] {
        &self.y
    }
    fn check_span(&self, t: f64) -> Result<(), SolveError> {
        let more = ((t - self.t) / self.dt).ceil().max(0.0);
        let total = self.work.steps as f64 + more;
        if total > self.max_steps as f64 {
            return Err(SolveError::StepBudget {
                t: self.t,
                steps: self.max_steps,
                reason: format!(
                    "rk4: dt = {} needs ~{total:.0e} steps to reach t = {t} (budget {:.0e}); \
                     use a larger dt or an adaptive method",
                    self.dt, self.max_steps as f64
                ),
            });
        }
        Ok(())
    }
    fn raw_step(&mut self) -> Result<(), SolveError> {
        self.check_span(self.t + self.dt)?;
        let t_new = self.grid(self.index + 1);
        let h = t_new - self.t;
        let mut out = std::mem::take(&mut self.y_new);
        self.rk4(self.t, false, h, &mut out);
        let sane = is_sane(&out);
        self.y_new = out;
        if !sane {
            return Err(SolveError::BlowUp { t: self.t });
        }
        std::mem::swap(&mut self.y_old, &mut self.y);
        std::mem::swap(&mut self.y, &mut self.y_new);
        self.t_old = self.t;
        self.t = t_new;
        self.index += 1;
        self.work.steps += 1;
        Ok(())
    }
    fn interpolate(&mut self, t: f64, out: &mut [f64]) {
        let h = t - self.t_old;
        self.rk4(self.t_old, true, h, out);
    }
}
