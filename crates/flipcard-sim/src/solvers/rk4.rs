//! Classical fixed-step RK4, the textbook baseline, with q put back on the
//! unit sphere after every step. The grid, sampling and budget are the
//! shared fixed-step driver's ([`crate::solvers::fixed`]).

use nalgebra::Vector3;

use crate::rigid::euler::System;
use crate::rigid::model::State;
use crate::rigid::scales::Scales;
use crate::solvers::budget::Budget;
use crate::solvers::fixed::{FixedSteps, Stepper};
use crate::solvers::{Method, SimError, Work};
use flipcard_text::num::Num;

/// RK4 on one of the rigid body's systems (ω alone, or ω and q).
pub type Rk4<S, const N: usize> = FixedSteps<Rk4Steps<S, N>>;

pub struct Rk4Steps<S, const N: usize> {
    sys: S,
    y0: [f64; N],
    dt: f64,
    scales: Scales,
    orientation: bool,
}

/// An RK4 run from `omega0` with step `dt`.
pub fn rk4<S: System<N>, const N: usize>(
    sys: S,
    omega0: &Vector3<f64>,
    dt: f64,
    budget: Budget,
    scales: Scales,
    orientation: bool,
) -> Rk4<S, N> {
    let steps = Rk4Steps {
        sys,
        y0: sys.initial(omega0),
        dt,
        scales,
        orientation,
    };
    FixedSteps::new(steps, dt, budget)
}

impl<S: System<N>, const N: usize> Stepper for Rk4Steps<S, N> {
    type Point = [f64; N];

    fn method(&self) -> Method {
        Method::Rk4 { dt: self.dt }
    }

    fn start(&self) -> [f64; N] {
        self.y0
    }

    fn step(&self, y: &mut [f64; N], h: f64, work: &mut Work) {
        let sys = self.sys;
        let k1 = sys.rhs(y);
        let k2 = sys.rhs(&axpy(y, 0.5 * h, &k1));
        let k3 = sys.rhs(&axpy(y, 0.5 * h, &k2));
        let k4 = sys.rhs(&axpy(y, h, &k3));
        for i in 0..N {
            y[i] += h / 6.0 * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i]);
        }
        sys.normalize(y);
        work.rhs_evals += 4;
    }

    fn state(&self, y: &[f64; N]) -> State {
        self.sys.state(y)
    }

    fn check(&self, y: &[f64; N], t: f64) -> Result<(), SimError> {
        if y.iter().all(|v| v.is_finite()) {
            return Ok(());
        }
        let rate = self.scales.fastest(self.orientation);
        Err(SimError::Invalid(format!(
            "rk4 diverged before t = {}: dt = {} is too coarse for {} (try dt ≤ {:.1e})",
            Num(t),
            Num(self.dt),
            self.scales.describe(self.orientation),
            1.0 / rate
        )))
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
