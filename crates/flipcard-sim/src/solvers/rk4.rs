//! Classical fixed-step RK4 on the rigid body: the one RK4 step
//! ([`rk4_step`], the systems' too), after which q is put back on the unit
//! sphere. Its grid, sampling and budget are the shared fixed-step
//! stepper's ([`crate::solvers::fixed`]).

use crate::error::SolveError;
use nalgebra::Vector3;

use crate::rigid::euler::RigidSystem;
use crate::rigid::model::State;
use crate::rigid::scales::Scales;
use crate::solvers::Method;
use crate::solvers::budget::Budget;
use crate::solvers::fixed::{FixedSteps, StepRule};
use crate::solvers::ode::{Work, rk4_step};
use flipcard_text::num::Num;

/// RK4 on one of the rigid body's systems (ω alone, or ω and q).
pub(crate) type Rk4<S, const N: usize> = FixedSteps<Rk4Steps<S, N>>;

pub(crate) struct Rk4Steps<S, const N: usize> {
    sys: S,
    y0: [f64; N],
    dt: f64,
    scales: Scales,
    orientation: bool,
}

/// An RK4 run from `omega0` with step `dt`.
pub(crate) fn rk4<S: RigidSystem<N>, const N: usize>(
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

impl<S: RigidSystem<N>, const N: usize> StepRule for Rk4Steps<S, N> {
    type Point = [f64; N];

    fn method(&self) -> Method {
        Method::Rk4 { dt: self.dt }
    }

    fn size(&self) -> usize {
        N
    }

    fn start(&self) -> [f64; N] {
        self.y0
    }

    fn step(&self, y: &mut [f64; N], h: f64, work: &mut Work) {
        let sys = self.sys;
        let rhs = |_: f64, y: &[f64], f: &mut [f64]| sys.rhs(0.0, y, f);
        let (y0, mut k, mut tmp) = (*y, [[0.0; N]; 4], [0.0; N]);
        rk4_step(rhs, 0.0, h, &y0, &mut k, &mut tmp, y);
        sys.normalize(y);
        work.rhs_evals += 4;
    }

    fn state(&self, y: &[f64]) -> State {
        let mut point = [0.0; N];
        point.copy_from_slice(y);
        self.sys.state(&point)
    }

    fn check(&self, y: &[f64], t: f64) -> Result<(), SolveError> {
        if y.iter().all(|v| v.is_finite()) {
            return Ok(());
        }
        let rate = self.scales.fastest(self.orientation);
        Err(SolveError::Invalid(format!(
            "rk4 diverged before t = {}: dt = {} is too coarse for {} (try dt ≤ {:.1e})",
            Num(t),
            Num(self.dt),
            self.scales.describe(self.orientation),
            1.0 / rate
        )))
    }
}
