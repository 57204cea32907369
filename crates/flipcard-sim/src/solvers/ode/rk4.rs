//! Classical fixed-step RK4, the textbook baseline for comparisons.
//!
//! Steps lie on the grid tₙ = t₀ + n·dt whatever the requests: a time
//! between grid points is reached by one partial RK4 step from the grid
//! point before it, on a copy, so sampling never changes the trajectory.
//!
//! A step past RK4's stability bound prints numbers that only look like an
//! answer (x' = −100x at dt = 0.03 grows to 1e34 where the solution is
//! 1e-326). So at the start and every [`CHECK_EVERY`] steps the fastest
//! rate of the system is estimated — the spectral radius of its Jacobian,
//! by power iteration on finite differences of the right-hand side — and a
//! step with dt·rate above [`STABLE`] is refused with both numbers
//! ([`SolveError::Unstable`]), as the rigid body's fixed-step methods are.

use super::{OdeSystem, Options, Requests, Stepper, Work, is_sane};
use crate::error::SolveError;

/// RK4's stability bound on the negative real axis (|R(z)| = 1 at
/// z ≈ −2.785; on the imaginary axis it is 2√2).
pub(crate) const STABLE: f64 = 2.78;
/// Steps between two estimates of the fastest rate.
const CHECK_EVERY: u64 = 32;
/// Power iterations per estimate.
const ITERATIONS: usize = 12;
/// The last iterations whose growth is averaged (even, so that a growth
/// alternating between two values is read whole).
const SETTLED: usize = 8;

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

    /// The system's fastest rate at the current point ([`fastest_rate`]).
    fn fastest_rate(&mut self) -> f64 {
        fastest_rate(&self.sys, self.t, &self.y, &mut self.work)
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
        if self.index.is_multiple_of(CHECK_EVERY) {
            let rate = self.fastest_rate();
            if self.dt * rate > STABLE {
                return Err(SolveError::Unstable {
                    method: "rk4",
                    t: self.t,
                    rate,
                    dt: self.dt,
                    limit: STABLE,
                });
            }
        }
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
/// The fastest rate of `sys` at (t, y): the spectral radius
/// of its Jacobian J by power iteration, J v by a forward difference of
/// the right-hand side, read as the geometric mean of the growth
/// |J v| / |v| over the last [`SETTLED`] iterations (a single ratio
/// overstates it for a non-normal J: for x'' = −ω²x written as (x, v),
/// |J v| / |v| alternates between ω² and 1 while the rate is ω). 0 where
/// it cannot be evaluated.
pub(crate) fn fastest_rate<S: OdeSystem>(sys: &S, t: f64, y: &[f64], work: &mut Work) -> f64 {
    let n = y.len();
    let mut f0 = vec![0.0; n];
    sys.rhs(t, y, &mut f0);
    work.rhs_evals += 1;
    let scale = y.iter().fold(1.0f64, |m, v| m.max(v.abs()));
    let eps = f64::EPSILON.sqrt() * scale;
    // A fixed start with every component, unequal so that no
    // symmetric mode is missed.
    let mut v: Vec<f64> = (0..n).map(|i| 1.0 + 0.37 * i as f64).collect();
    let mut growth: Vec<f64> = Vec::with_capacity(ITERATIONS);
    let (mut yp, mut fp) = (vec![0.0; n], vec![0.0; n]);
    for _ in 0..ITERATIONS {
        let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if !(norm.is_finite() && norm > 0.0) {
            break;
        }
        for i in 0..n {
            v[i] /= norm;
            yp[i] = y[i] + eps * v[i];
        }
        sys.rhs(t, &yp, &mut fp);
        work.rhs_evals += 1;
        for i in 0..n {
            v[i] = (fp[i] - f0[i]) / eps;
        }
        let jv = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if !(jv.is_finite() && jv > 0.0) {
            break;
        }
        growth.push(jv.ln());
    }
    let last = &growth[growth.len().saturating_sub(SETTLED)..];
    if last.is_empty() {
        return 0.0;
    }
    (last.iter().sum::<f64>() / last.len() as f64).exp()
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
