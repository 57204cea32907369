//! Classical fixed-step RK4, the textbook baseline: [`rk4_step`], the one
//! step both stacks take (the systems' [`crate::solvers::ode::Rk4`] and the
//! rigid body's), and the rigid body's stepper, which puts q back on the
//! unit sphere after every step. Its grid, sampling and budget are the
//! shared fixed-step driver's ([`crate::solvers::fixed`]).

use crate::error::SolveError;
use nalgebra::Vector3;

use crate::rigid::euler::RigidSystem;
use crate::rigid::model::State;
use crate::rigid::scales::Scales;
use crate::solvers::Method;
use crate::solvers::budget::Budget;
use crate::solvers::fixed::{FixedSteps, StepRule};
use crate::solvers::ode::Work;
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

/// One classical RK4 step of size `h` from (t, y) into `out`, for f
/// written as `rhs(t, y, dy)`; `k` holds the four stages and `tmp` the
/// argument of the next, each of y's length. Uses four evaluations of f.
#[inline(always)]
pub(crate) fn rk4_step<K: AsRef<[f64]> + AsMut<[f64]>>(
    mut rhs: impl FnMut(f64, &[f64], &mut [f64]),
    t: f64,
    h: f64,
    y: &[f64],
    k: &mut [K; 4],
    tmp: &mut [f64],
    out: &mut [f64],
) {
    rhs(t, y, k[0].as_mut());
    for (s, c) in [(1, 0.5), (2, 0.5), (3, 1.0)] {
        let (done, rest) = k.split_at_mut(s);
        for ((tmp, y), k) in tmp.iter_mut().zip(y).zip(done[s - 1].as_ref()) {
            *tmp = y + c * h * k;
        }
        rhs(t + c * h, tmp, rest[0].as_mut());
    }
    let [k0, k1, k2, k3] = k.each_ref().map(|k| k.as_ref());
    for (i, o) in out.iter_mut().enumerate() {
        *o = y[i] + h / 6.0 * (k0[i] + 2.0 * (k1[i] + k2[i]) + k3[i]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// y' = y from 1 over one step: the step is the degree-4 Taylor
    /// polynomial of eʰ, whatever the storage of the stages.
    #[test]
    fn one_step_is_the_taylor_polynomial() {
        let rhs = |_: f64, y: &[f64], f: &mut [f64]| f[0] = y[0];
        let h: f64 = 0.1;
        let taylor = 1.0 + h + h * h / 2.0 + h.powi(3) / 6.0 + h.powi(4) / 24.0;
        let mut out = [0.0];
        rk4_step(
            rhs,
            0.0,
            h,
            &[1.0],
            &mut [[0.0; 1]; 4],
            &mut [0.0],
            &mut out,
        );
        assert!((out[0] - taylor).abs() < 1e-15, "{}", out[0]);
        let mut k = [vec![0.0], vec![0.0], vec![0.0], vec![0.0]];
        let mut out2 = [0.0];
        rk4_step(rhs, 0.0, h, &[1.0], &mut k, &mut [0.0], &mut out2);
        assert_eq!(out, out2);
    }

    /// The stage times: f = t integrates exactly (to t²/2).
    #[test]
    fn stages_see_their_times() {
        let rhs = |t: f64, _: &[f64], f: &mut [f64]| f[0] = t;
        let mut out = [0.0];
        rk4_step(
            rhs,
            1.0,
            0.5,
            &[0.0],
            &mut [[0.0; 1]; 4],
            &mut [0.0],
            &mut out,
        );
        assert!((out[0] - (1.5f64.powi(2) - 1.0) / 2.0).abs() < 1e-15);
    }
}
