//! Classical fixed-step RK4, the textbook baseline, with q put back on the
//! unit sphere after every step.
//!
//! Steps lie on the grid tₙ = n·dt whatever the sample times: a sample
//! between grid points is reached by one partial step from a copy, so the
//! trajectory is the same however often it is sampled.

use nalgebra::Vector3;

use crate::sim::rigid::euler::System;
use crate::sim::rigid::model::State;
use crate::sim::rigid::scales::Scales;
use crate::sim::solvers::budget::Budget;
use crate::sim::solvers::{Method, SimError, Solver, Work};
use crate::text::num::Num;

pub struct Rk4<S, const N: usize> {
    sys: S,
    dt: f64,
    budget: Budget,
    scales: Scales,
    orientation: bool,
    /// State at the grid point n·dt.
    n: u64,
    y: [f64; N],
    last_request: f64,
    work: Work,
}

impl<S: System<N>, const N: usize> Rk4<S, N> {
    pub fn new(
        sys: S,
        omega0: &Vector3<f64>,
        dt: f64,
        budget: Budget,
        scales: Scales,
        orientation: bool,
    ) -> Rk4<S, N> {
        Rk4 {
            sys,
            dt,
            budget,
            scales,
            orientation,
            n: 0,
            y: sys.initial(omega0),
            last_request: 0.0,
            work: Work::default(),
        }
    }

    fn step(&mut self, y: &[f64; N], h: f64) -> [f64; N] {
        let sys = self.sys;
        let k1 = sys.rhs(y);
        let k2 = sys.rhs(&axpy(y, 0.5 * h, &k1));
        let k3 = sys.rhs(&axpy(y, 0.5 * h, &k2));
        let k4 = sys.rhs(&axpy(y, h, &k3));
        let mut out = *y;
        for i in 0..N {
            out[i] += h / 6.0 * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i]);
        }
        sys.normalize(&mut out);
        self.work.rhs_evals += 4;
        out
    }

    fn check_budget(&self, t: f64) -> Result<(), SimError> {
        let more = (t / self.dt).floor() - self.n as f64;
        if self.budget.exceeded(self.work.steps, more) {
            return Err(SimError::Budget(self.budget.fixed(
                "rk4",
                self.dt,
                t,
                self.work.steps as f64 + more,
            )));
        }
        Ok(())
    }

    fn blew_up(&self, t: f64) -> SimError {
        let rate = self.scales.fastest(self.orientation);
        SimError::Invalid(format!(
            "rk4 diverged before t = {}: dt = {} is too coarse for {} (try dt ≤ {:.1e})",
            Num(t),
            Num(self.dt),
            self.scales.describe(self.orientation),
            1.0 / rate
        ))
    }
}

#[inline(always)]
fn axpy<const N: usize>(y: &[f64; N], a: f64, x: &[f64; N]) -> [f64; N] {
    let mut out = *y;
    for i in 0..N {
        out[i] += a * x[i];
    }
    out
}

impl<S: System<N>, const N: usize> Solver for Rk4<S, N> {
    fn method(&self) -> Method {
        Method::Rk4 { dt: self.dt }
    }

    fn advance(&mut self, t: f64) -> Result<State, SimError> {
        if !t.is_finite() || t < self.last_request {
            return Err(SimError::Invalid(format!(
                "time {} is before the previous sample {} (runs only go forward)",
                Num(t),
                Num(self.last_request)
            )));
        }
        self.last_request = t;
        self.check_budget(t)?;
        while (self.n + 1) as f64 * self.dt <= t {
            let y = self.y;
            self.y = self.step(&y, self.dt);
            self.n += 1;
            self.work.steps += 1;
            if !self.y.iter().all(|v| v.is_finite()) {
                return Err(self.blew_up(t));
            }
        }
        let rest = t - self.n as f64 * self.dt;
        let y = if rest > 0.0 {
            let y = self.y;
            self.step(&y, rest)
        } else {
            self.y
        };
        if !y.iter().all(|v| v.is_finite()) {
            return Err(self.blew_up(t));
        }
        Ok(self.sys.state(&y))
    }

    fn work(&self) -> Work {
        self.work
    }

    fn plan(&mut self, t_end: f64) -> Result<(), SimError> {
        self.check_budget(t_end)
    }
}
