//! Störmer–Verlet, the symplectic fixed-step method for a separable
//! Hamiltonian H = T(p) + V(q) that a scene declares
//! (`hamiltonian = { q = [...], p = [...] }`, seen here as
//! [`OdeSystem::split`]).
//!
//! Why it exists: a general method (RK4, or an adaptive one at a loose
//! tolerance) loses a little energy every orbit, and over many orbits the
//! loss adds up — Kepler at e = 0.9 with RK4 drifts steadily. A symplectic
//! method keeps a nearby energy exactly, so its energy error stays bounded
//! (oscillating, largest at pericentre) however long it runs, and for a
//! central force it keeps the angular momentum to rounding.
//!
//! One step of size h is kick–drift–kick: p += h/2·p'(q), q += h·q'(p),
//! p += h/2·p'(q); `verlet4` composes three such steps (Yoshida's triple
//! jump) for order 4, still symplectic. A rate of q is read from f at a
//! state whose momenta are current, a rate of p at a state whose positions
//! are: so f is evaluated whole and only the components of the half
//! wanted are used, which is exact because q' reads only p and p' only q
//! (the scene's check refuses a declaration where that fails).
//!
//! Steps lie on the grid tₙ = t₀ + n·dt, as RK4's do: a time between grid
//! points is a partial step from the point before it, on a copy. The
//! stability bound (h·rate < 2 for Verlet on an oscillation; about 1.57
//! for the triple jump, whose largest substep is 1.35·h) is checked at
//! the start and every [`CHECK_EVERY`] steps, as RK4's is.

use super::{OdeSystem, Options, Requests, Stepper, Work, is_sane};
use crate::error::SolveError;
use crate::rhs::Split;

/// Steps between two estimates of the fastest rate.
const CHECK_EVERY: u64 = 32;

/// Yoshida's triple jump: substeps w₁·h, w₀·h, w₁·h with
/// w₁ = 1/(2 − 2^(1/3)) and w₀ = 1 − 2w₁ make Verlet fourth order.
const W1: f64 = 1.351_207_191_959_657_8;
const W0: f64 = -1.702_414_383_919_315_3;

pub struct Verlet<S> {
    sys: S,
    split: Split,
    dt: f64,
    /// 2 (Störmer–Verlet) or 4 (the triple jump).
    order: u8,
    t0: f64,
    index: u64,
    max_steps: u64,
    t: f64,
    y: Vec<f64>,
    t_old: f64,
    y_old: Vec<f64>,
    y_new: Vec<f64>,
    f: Vec<f64>,
    /// f at the current point (`g_current`): its momenta's rates open
    /// the next step.
    g: Vec<f64>,
    g_current: bool,
    tmp: Vec<f64>,
    requests: Requests,
    work: Work,
}

impl<S: OdeSystem> Verlet<S> {
    /// Steps of `dt` from (t0, y0) of order 2 or 4; only `opts.max_steps`
    /// applies. Refused for a system that declares no split.
    pub fn new(
        sys: S,
        t0: f64,
        y0: &[f64],
        dt: f64,
        order: u8,
        opts: &Options,
    ) -> Result<Verlet<S>, SolveError> {
        super::check_start(&sys, t0, y0)?;
        let name = if order == 4 { "verlet4" } else { "verlet" };
        if !(dt.is_finite() && dt > 0.0) {
            return Err(SolveError::Invalid(format!(
                "{name}: dt = {dt} must be positive"
            )));
        }
        if opts.max_steps == 0 {
            return Err(SolveError::Invalid("max_steps must be at least 1".into()));
        }
        let n = sys.dim();
        let split = sys.split().ok_or_else(|| {
            SolveError::Invalid(format!(
                "{name} needs a separable Hamiltonian: the scene declares none (`hamiltonian = {{ q = [...], p = [...] }}`)"
            ))
        })?;
        let mut seen = vec![false; n];
        let ok = split.q.len() == split.p.len()
            && split.q.iter().chain(&split.p).all(|&i| {
                let fresh = i < n && !seen[i];
                if fresh {
                    seen[i] = true;
                }
                fresh
            })
            && seen.iter().all(|&s| s);
        if !ok {
            return Err(SolveError::Invalid(format!(
                "{name}: the split must name every one of the {n} components once, as many positions as momenta"
            )));
        }
        Ok(Verlet {
            sys,
            split,
            dt,
            order: if order == 4 { 4 } else { 2 },
            t0,
            index: 0,
            max_steps: opts.max_steps,
            t: t0,
            y: y0.to_vec(),
            t_old: t0,
            y_old: y0.to_vec(),
            y_new: vec![0.0; n],
            f: vec![0.0; n],
            g: vec![0.0; n],
            g_current: false,
            tmp: vec![0.0; n],
            requests: Requests::new(t0, y0),
            work: Work::default(),
        })
    }

    fn grid(&self, index: u64) -> f64 {
        self.t0 + index as f64 * self.dt
    }

    /// One kick–drift–kick of size h from time t on `y` in place; `g`
    /// holds f at (t, y) on entry (its momenta's rates are used) and at
    /// (t + h, y) on return, so each step after the first evaluates f
    /// twice: at (q, p½) for the drift, at (q₁, p½) for the last kick.
    fn verlet(&mut self, t: f64, h: f64, y: &mut [f64], g: &mut [f64]) {
        let Verlet { sys, split, f, .. } = self;
        for &i in &split.p {
            y[i] += 0.5 * h * g[i];
        }
        sys.rhs(t + 0.5 * h, y, f);
        for &i in &split.q {
            y[i] += h * f[i];
        }
        sys.rhs(t + h, y, g);
        for &i in &split.p {
            y[i] += 0.5 * h * g[i];
        }
        self.work.rhs_evals += 2;
    }

    /// A step of size h (of the method's order) on `y` in place, `g` as
    /// for [`Verlet::verlet`].
    fn advance_by(&mut self, t: f64, h: f64, y: &mut [f64], g: &mut [f64]) {
        if self.order == 4 {
            self.verlet(t, W1 * h, y, g);
            self.verlet(t + W1 * h, W0 * h, y, g);
            self.verlet(t + (W1 + W0) * h, W1 * h, y, g);
        } else {
            self.verlet(t, h, y, g);
        }
    }

    /// The largest h·rate the method is stable for on an oscillation.
    fn stable(&self) -> f64 {
        if self.order == 4 { 2.0 / W1 } else { 2.0 }
    }
}

impl<S: OdeSystem> Stepper for Verlet<S> {
    fn method_name(&self) -> &'static str {
        if self.order == 4 { "verlet4" } else { "verlet" }
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
                    "{}: dt = {} needs ~{total:.0e} steps to reach t = {t} (budget {:.0e}); use a larger dt or an adaptive method",
                    self.method_name(),
                    self.dt,
                    self.max_steps as f64
                ),
            });
        }
        Ok(())
    }
    fn raw_step(&mut self) -> Result<(), SolveError> {
        self.check_span(self.t + self.dt)?;
        if self.index.is_multiple_of(CHECK_EVERY) {
            let rate = super::rk4::fastest_rate(&self.sys, self.t, &self.y, &mut self.work);
            if self.dt * rate > self.stable() {
                return Err(SolveError::Unstable {
                    method: self.method_name(),
                    t: self.t,
                    rate,
                    dt: self.dt,
                    limit: self.stable(),
                });
            }
        }
        let t_new = self.grid(self.index + 1);
        let h = t_new - self.t;
        let mut y = std::mem::take(&mut self.y_new);
        y.copy_from_slice(&self.y);
        let mut g = std::mem::take(&mut self.g);
        if !self.g_current {
            self.sys.rhs(self.t, &self.y, &mut g);
            self.work.rhs_evals += 1;
        }
        self.advance_by(self.t, h, &mut y, &mut g);
        self.g = g;
        self.g_current = true;
        let sane = is_sane(&y);
        self.y_new = y;
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
        out.copy_from_slice(&self.y_old);
        let mut g = std::mem::take(&mut self.tmp);
        self.sys.rhs(self.t_old, &self.y_old, &mut g);
        self.work.rhs_evals += 1;
        let h = t - self.t_old;
        self.advance_by(self.t_old, h, out, &mut g);
        self.tmp = g;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solvers::ode::OdeSolver;

    /// x'' = −x as (x, v), declared separable.
    struct Oscillator;
    impl OdeSystem for Oscillator {
        fn dim(&self) -> usize {
            2
        }
        fn rhs(&self, _: f64, y: &[f64], dy: &mut [f64]) {
            dy[0] = y[1];
            dy[1] = -y[0];
        }
        fn split(&self) -> Option<Split> {
            Some(Split {
                q: vec![0],
                p: vec![1],
            })
        }
    }

    /// The global error falls by 2^order when the step is halved.
    #[test]
    fn orders_two_and_four() {
        for order in [2u8, 4] {
            let err = |dt: f64| {
                let mut s =
                    Verlet::new(Oscillator, 0.0, &[1.0, 0.0], dt, order, &Options::default())
                        .unwrap();
                let y = s.advance(10.0).unwrap().to_vec();
                ((y[0] - 10f64.cos()).powi(2) + (y[1] + 10f64.sin()).powi(2)).sqrt()
            };
            let ratio = err(0.02) / err(0.01);
            let want = f64::from(1u32 << order);
            assert!((ratio / want - 1.0).abs() < 0.1, "order {order}: {ratio}");
        }
    }

    /// Energy stays within a bound over 10⁴ periods at a coarse step.
    #[test]
    fn energy_bounded_over_many_periods() {
        let mut s = Verlet::new(Oscillator, 0.0, &[1.0, 0.0], 0.1, 2, &Options::default()).unwrap();
        let mut worst: f64 = 0.0;
        for k in 1..=1000 {
            let y = s.advance(k as f64 * 62.8).unwrap();
            worst = worst.max((0.5 * (y[0] * y[0] + y[1] * y[1]) - 0.5).abs());
        }
        // h²/8 relative for the harmonic oscillator.
        assert!(worst < 0.5 * 0.1 * 0.1 / 4.0, "{worst}");
    }

    #[test]
    fn refused_without_a_split_or_past_its_stability_bound() {
        struct Plain;
        impl OdeSystem for Plain {
            fn dim(&self) -> usize {
                1
            }
            fn rhs(&self, _: f64, y: &[f64], dy: &mut [f64]) {
                dy[0] = -y[0];
            }
        }
        let e = Verlet::new(Plain, 0.0, &[1.0], 0.1, 2, &Options::default())
            .err()
            .unwrap();
        assert!(e.to_string().contains("separable Hamiltonian"), "{e}");
        let mut s = Verlet::new(Oscillator, 0.0, &[1.0, 0.0], 2.5, 2, &Options::default()).unwrap();
        assert!(matches!(s.advance(10.0), Err(SolveError::Unstable { .. })));
    }
}
