//! Automatic choice between the explicit and the implicit method, by cost:
//! DOP853 while it is the cheaper, Radau IIA while it is, on the same
//! trajectory.
//!
//! Two ways into Radau IIA:
//! - DOP853's stiffness test fires (|hλ| above its stability boundary, 6.1,
//!   15 steps in a row): the step is pinned by stability, Radau takes over
//!   for good, as before;
//! - a **probe**, as LSODA compares the two methods' costs: when |hλ| stays
//!   above half the boundary ([`PROBE_RATIO`]) for [`PROBE_COUNT`] steps,
//!   the step is likely held down by stability though the test has not
//!   fired (Robertson at rtol 1e-10 sits at |hλ| ≈ 5.25 for 3,900 steps).
//!   Radau runs [`PROBE_STEPS`] steps, and its cost per unit of time is
//!   compared with DOP853's over its last [`WINDOW`] steps; if Radau costs
//!   more than [`HYSTERESIS`] times as much, DOP853 takes the run back and
//!   the next probe needs twice as many steps (so a non-stiff problem that
//!   brushes the threshold pays a probe rarely, and never thrashes). A
//!   mildly stiff problem, where DOP853's step is held down by the error on
//!   its damped component at a low |hλ| rather than by instability, is
//!   probed every [`ROUTINE_COUNT`] explicit steps (doubling likewise).
//!   And [`EARLY_COUNT`] steps in a row at the stability boundary itself
//!   start a probe at once, measured over those steps: a problem stiff from
//!   its start (E5, a fast linear mode, the Brusselator's diffusion) does
//!   not wait for the stiffness test's 15.
//!
//! Before any step, a **look at the start**: the Jacobian at t₀ by power
//! iteration ([`stiff_at_start`]). When its dominant eigenvalue is real
//! and negative (a damped mode, the power iteration settled on it) and
//! |λ|·(t_stop − t₀) is at least [`START_SPAN`] (DOP853 would need at least
//! [`START_SPAN`] / 6.1 steps held by stability, were the mode to stay),
//! the run starts in Radau IIA on a probe measured against the least
//! DOP853 could cost, [`DOP853_EVALS`] evaluations a step of 6.1/|λ|: a
//! problem stiff from its start (E5, the linear system with eigenvalues
//! −1 and −1e8, Van der Pol at μ = 1e4) pays no explicit steps at all,
//! and one whose fast mode is not what limits the step (Lorenz over a long
//! run) loses the probe and goes on with DOP853 as before.
//!
//! Costs are counted in evaluations of f: one per evaluation, n per
//! Jacobian (what finite differences would take), and per LU
//! decomposition pair what Radau's factors cost in the form it will factor
//! them ([`LuPlan::choose`] on the system's pattern, priced by
//! [`LuPlan::pair_in_evaluations`]: dense, 1 + n²/6, n³/3 real and 4n³/3
//! complex flops against ~10n for an f of n short equations; banded and
//! sparse, their own multiply–adds by their measured weights, far fewer on
//! a large sparse system). Counting, not timing, keeps every run
//! repeatable.
//!
//! The handover happens lazily, at the first step after the decision, so
//! requests inside the last step are still served by the solver that took
//! it and the trajectory has no gap.

use std::collections::VecDeque;

use super::lu::LuPlan;
use super::{
    Atol, Dop853, OdeSolver, OdeSystem, Options, Radau5, Requests, Stepper, StiffnessMode, Work,
};
use crate::error::SolveError;

/// |hλ| above which an explicit step counts towards a probe: half of
/// DOP853's stability boundary on the negative real axis.
const PROBE_RATIO: f64 = 3.05;
/// Steps above [`PROBE_RATIO`] (in a row, [`PROBE_RESET`] below reset the
/// count) before the first probe.
const PROBE_COUNT: u32 = 15;
const PROBE_RESET: u32 = 6;
/// |hλ| above which an explicit step is pinned by stability: DOP853's
/// stability boundary on the negative real axis, where its own stiffness
/// test counts.
const EARLY_RATIO: f64 = 6.1;
/// Steps in a row above [`EARLY_RATIO`] that start a probe at once, over
/// the steps there are (at least this many) rather than [`WINDOW`]: on a
/// problem stiff from its start the stiffness test's 15 steps and the
/// window's 20 were most of `auto`'s extra cost (E5 at rtol 1e-3: 18
/// explicit steps, 325 evaluations of f, before Radau IIA's 31 steps and
/// 211 evaluations; the linear system with eigenvalues −1 and −1e8: 486
/// evaluations before a Radau run of 184). Doubles after each lost probe
/// like [`PROBE_COUNT`].
const EARLY_COUNT: u32 = 4;
/// A second, slower way to a probe, whatever |hλ| says: every
/// [`ROUTINE_COUNT`] explicit steps. On a mildly stiff problem DOP853's
/// step is held down by the error its stability function makes on the
/// fast, damped component, not by instability, and |hλ| stays low: on
/// x' = −50(x − cos t) it takes 3,512 steps at |hλ| ≈ 1.4 (rtol 1e-7) and
/// 7,754 at 0.6 (rtol 1e-9) where Radau takes 864 and 2,649 at a tenth of
/// the cost. Only trying tells; the count is long enough that a short run
/// never pays a probe, and doubles after each lost probe like the other.
const ROUTINE_COUNT: u32 = 200;
/// |λ|·(t_stop − t₀) from which a dominant damped mode at the start makes
/// the run start in Radau IIA: DOP853 would need at least 800 steps
/// (START_SPAN / 6.1), some 10,000 evaluations of f, held by stability.
const START_SPAN: f64 = 5e3;
/// Evaluations of f a DOP853 step costs (twelve stages, the first shared
/// with the step before, and the dense output's three when asked).
const DOP853_EVALS: f64 = 12.0;
/// Systems above this size skip the look at the start: the dense Jacobian
/// it takes is n² numbers.
const START_MAX_DIM: usize = 512;
/// How long, in units of the fast mode's time 1/|λ|, the probe of the
/// look at the start waits for a step [`START_STEP`] times DOP853's
/// stability bound before it is lost: the mode has decayed by e⁻⁴⁰ by
/// then, below any tolerance, so a step still short of the bound is held
/// by something else than that mode. At most START_TRANSIENT /
/// [`START_SPAN`] of the run (0.8 %) is spent waiting.
const START_TRANSIENT: f64 = 40.0;
/// How many of DOP853's longest stable steps Radau IIA's step must span
/// before the probe of the look at the start is measured.
const START_STEP: f64 = 2.0;
/// Power iterations of the look at the start.
const START_ITERATIONS: usize = 40;

/// Explicit steps whose cost per unit time a probe is measured against.
const WINDOW: usize = 20;
/// Implicit steps a probe takes before the costs are compared.
const PROBE_STEPS: u64 = 20;
/// Radau keeps the run while it costs at most this many times DOP853.
const HYSTERESIS: f64 = 1.2;
/// After a routine probe (no sign of stiffness in |hλ|) Radau must cost at
/// most this much of DOP853: the count of evaluations leaves out Radau's
/// own work per step (the transformed stages, two solves a Newton
/// iteration), which on a small system is as much again (Van der Pol at
/// μ = 10: a Radau step takes 0.9 of a DOP853 step's instructions where
/// the count says 0.56), so only a clear win is taken.
const ROUTINE_BAR: f64 = 0.5;
/// After a routine probe won, Radau's cost is checked every this many
/// steps against DOP853's rate before the probe, and the run goes back to
/// DOP853 when Radau has come to cost more: a probe wins where the problem
/// happens to be slow (Kepler far from the Sun, e = 0.9 at rtol 1e-6) and
/// must not keep Radau through the fast stretches that follow.
const RECHECK_STEPS: u64 = 50;

enum Phase<S> {
    Explicit(Box<Dop853<S>>),
    Implicit(Box<Radau5<S>>),
    /// Only while the system moves from one solver to the other.
    Moving,
}

/// A probe of the implicit method in course.
#[derive(Debug, Clone, Copy)]
struct Probe {
    /// DOP853's cost per unit time before the probe.
    explicit_rate: f64,
    /// Where the implicit phase started: time, cost, accepted steps.
    t0: f64,
    cost0: f64,
    steps0: u64,
    /// A check of a won routine probe, not a probe.
    recheck: bool,
    /// For the probe of the look at the start: DOP853's stability bound
    /// 6.1/|λ|. The probe is measured from Radau's first step at least
    /// this long (on E5 at rtol 1e-6 Radau's first steps resolve a
    /// transient on the scale 1/|λ|, where they cost more than DOP853's
    /// stability-bound steps would, and DOP853 could not take those
    /// either), and lost if none is by [`START_TRANSIENT`] / |λ|. 0 for
    /// the others.
    wait_h: f64,
    /// DOP853's last step size, to go back with.
    h_explicit: f64,
    /// The most Radau may cost, as a multiple of DOP853's rate.
    bar: f64,
    /// Time and cost halfway through the probe: Radau's rate is measured
    /// over the second half, so the first steps' climb from DOP853's
    /// stability-bound step (a Jacobian and a factorisation each) is not
    /// taken for what it will keep costing. Without it the 200-variable
    /// Brusselator lost its early probe at rtol 1e-6 and `auto` took 117
    /// steps and 1,185 evaluations where Radau alone takes 79 and 552.
    mid: Option<(f64, f64)>,
}

pub struct Auto<S> {
    phase: Phase<S>,
    opts: Options,
    n: usize,
    /// What a pair of Radau's LU decompositions costs, in evaluations of f.
    lu_price: f64,
    switched_at: Option<f64>,
    /// Work of the phases that are over.
    done: Work,
    requests: Requests,
    /// Explicit steps above [`PROBE_RATIO`], and below it since the last.
    probe_count: u32,
    probe_below: u32,
    /// Explicit steps in a row above [`EARLY_RATIO`].
    early_count: u32,
    /// [`EARLY_COUNT`] (a field so a test can turn the early probe off).
    early_needed: u32,
    /// Explicit steps since the run started or came back to DOP853.
    explicit_steps: u32,
    /// Steps above the ratio that start a probe (doubles after each lost;
    /// [`ROUTINE_COUNT`] scaled alike).
    probe_needed: u32,
    /// [`PROBE_RATIO`] (a field so a test can make every step count).
    probe_ratio: f64,
    /// (time, cost) after each of the last [`WINDOW`] explicit steps.
    window: VecDeque<(f64, f64)>,
    probe: Option<Probe>,
    /// Probes that went back to DOP853.
    probes_lost: u32,
}

/// The cost of `w` in evaluations of f, for a system of `n` components
/// whose LU decomposition pairs cost `lu_price` each.
fn cost(w: Work, n: usize, lu_price: f64) -> f64 {
    w.rhs_evals as f64 + n as f64 * w.jac_evals as f64 + lu_price * w.lu_decomps as f64
}

/// The look at the start: the rate |λ| of the Jacobian's dominant
/// eigenvalue at (t, y), among the modes f(t, y) has a part in, when it is
/// real and negative, found by power iteration on the exact Jacobian
/// (`OdeSystem::jacobian`, one evaluation counted in `work`, and one of f)
/// from f, and trusted only when the iteration settled: the
/// Rayleigh quotient q = vᵀJv within a tenth of −|Jv| and the residual
/// |Jv − qv| within a third of it. A pair ±λ (Kepler's orbit near the
/// centre), an oscillation or a growing mode gives `None`; so do a system
/// larger than [`START_MAX_DIM`] and a Jacobian that is not finite.
pub(crate) fn stiff_at_start<S: OdeSystem>(
    sys: &S,
    t: f64,
    y: &[f64],
    work: &mut Work,
) -> Option<f64> {
    let n = y.len();
    if n == 0 || n > START_MAX_DIM {
        return None;
    }
    let mut jac = nalgebra::DMatrix::<f64>::zeros(n, n);
    sys.jacobian(t, y, &mut jac);
    work.jac_evals += 1;
    if jac.iter().any(|v| !v.is_finite()) {
        return None;
    }
    // The non-zero entries by row, so a large sparse system costs its
    // entries, not n², an iteration.
    let entries: Vec<(usize, usize, f64)> = (0..n)
        .flat_map(|i| (0..n).map(move |j| (i, j)))
        .filter_map(|(i, j)| {
            let v = jac[(i, j)];
            (v != 0.0).then_some((i, j, v))
        })
        .collect();
    // The iteration starts from f itself: the modes the solution moves in
    // (a fast mode that is never excited, a' = −1e4·a from a = 0 beside
    // an oscillator, is none of them, and does not send a run whose
    // explicit steps it never limits to Radau IIA).
    let mut v = vec![0.0; n];
    sys.rhs(t, y, &mut v);
    work.rhs_evals += 1;
    let mut jv = vec![0.0; n];
    let mut settled = None;
    for _ in 0..START_ITERATIONS {
        let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if !(norm.is_finite() && norm > 0.0) {
            return None;
        }
        v.iter_mut().for_each(|x| *x /= norm);
        jv.fill(0.0);
        for &(i, j, a) in &entries {
            jv[i] += a * v[j];
        }
        let rate = jv.iter().map(|x| x * x).sum::<f64>().sqrt();
        if !(rate.is_finite() && rate > 0.0) {
            return None;
        }
        let q: f64 = v.iter().zip(&jv).map(|(a, b)| a * b).sum();
        let residual = v
            .iter()
            .zip(&jv)
            .map(|(a, b)| (b - q * a).powi(2))
            .sum::<f64>()
            .sqrt();
        settled = (q <= -0.9 * rate && residual <= rate / 3.0).then_some(rate);
        std::mem::swap(&mut v, &mut jv);
    }
    settled
}

impl<S: OdeSystem> Auto<S> {
    pub fn new(sys: S, t0: f64, y0: &[f64], opts: &Options) -> Result<Auto<S>, SolveError> {
        Auto::build(sys, t0, y0, opts, true)
    }

    /// [`Auto::new`], with the look at the start or without it (a test
    /// measures the other ways into Radau IIA on their own).
    fn build(
        sys: S,
        t0: f64,
        y0: &[f64],
        opts: &Options,
        look: bool,
    ) -> Result<Auto<S>, SolveError> {
        let n = sys.dim();
        let lu_price = LuPlan::choose(n, sys.sparsity().as_deref()).pair_in_evaluations(n);
        // Radau's own checks, so a bad setting shows now and not at the switch.
        if opts.rtol <= 10.0 * f64::EPSILON {
            return Err(SolveError::Invalid(format!(
                "auto needs rtol above {:e} (for radau5), not {}",
                10.0 * f64::EPSILON,
                opts.rtol
            )));
        }
        let mut done = Work::default();
        let stiff = match opts.t_stop {
            Some(stop) if look && y0.len() == n => stiff_at_start(&sys, t0, y0, &mut done)
                .filter(|rate| rate * (stop - t0).abs() >= START_SPAN),
            _ => None,
        };
        let (phase, probe, switched_at) = match stiff {
            Some(rate) => {
                let radau = Radau5::new(sys, t0, y0, opts)?;
                let probe = Probe {
                    explicit_rate: DOP853_EVALS * rate / EARLY_RATIO,
                    t0,
                    cost0: cost(done, n, lu_price),
                    steps0: 0,
                    recheck: false,
                    wait_h: START_STEP * EARLY_RATIO / rate,
                    // DOP853 chooses its own first step if it takes over.
                    h_explicit: 0.0,
                    bar: HYSTERESIS,
                    mid: None,
                };
                (Phase::Implicit(Box::new(radau)), Some(probe), Some(t0))
            }
            None => {
                let dop = Dop853::new(sys, t0, y0, opts)?.with_stiffness(StiffnessMode::Report);
                (Phase::Explicit(Box::new(dop)), None, None)
            }
        };
        Ok(Auto {
            phase,
            opts: opts.clone(),
            n,
            lu_price,
            switched_at,
            done,
            requests: Requests::new(t0, y0),
            probe_count: 0,
            probe_below: 0,
            early_count: 0,
            early_needed: EARLY_COUNT,
            explicit_steps: 0,
            probe_needed: PROBE_COUNT,
            probe_ratio: PROBE_RATIO,
            window: VecDeque::with_capacity(WINDOW + 1),
            probe,
            probes_lost: 0,
        })
    }

    /// When the switch to Radau IIA happened (the time DOP853 found the
    /// problem stiff, or a probe that Radau won started), if it did.
    pub fn switched_at(&self) -> Option<f64> {
        self.switched_at
    }

    /// Probes that found DOP853 the cheaper and gave the run back to it.
    pub fn probes_lost(&self) -> u32 {
        self.probes_lost
    }

    /// The cost so far, in evaluations of f.
    fn cost_now(&self) -> f64 {
        cost(self.work_done(), self.n, self.lu_price)
    }

    /// DOP853's cost per unit time over its last steps (infinite until
    /// there are `least` of them).
    fn explicit_rate(&self, least: usize) -> f64 {
        match (self.window.front(), self.window.back()) {
            (Some(a), Some(b)) if self.window.len() >= least.max(2) && b.0 > a.0 => {
                (b.1 - a.1) / (b.0 - a.0)
            }
            _ => f64::INFINITY,
        }
    }

    fn hand_to_implicit(&mut self, probe: Option<Probe>) -> Result<(), SolveError> {
        let Phase::Explicit(dop) = std::mem::replace(&mut self.phase, Phase::Moving) else {
            return Err(SolveError::Invalid(
                "auto: no explicit phase to leave".into(),
            ));
        };
        let h = dop.next_step_size();
        let mut opts = self.opts.clone();
        if let Some(b) = dop.by_size() {
            opts.atol = Atol::BySize(b.clone());
        }
        let (sys, t, y, work) = dop.into_parts();
        self.done = self.done + work;
        // DOP853's last step is bounded by stability, so it is a safe start;
        // Radau's step control lengthens it within a few steps.
        if h > 0.0 && h.is_finite() {
            opts.h0 = Some(h);
        }
        let radau = Radau5::new(sys, t, &y, &opts)?;
        self.phase = Phase::Implicit(Box::new(radau));
        self.probe = probe.map(|p| Probe { h_explicit: h, ..p });
        Ok(())
    }

    fn hand_to_explicit(&mut self, h: f64) -> Result<(), SolveError> {
        let Phase::Implicit(radau) = std::mem::replace(&mut self.phase, Phase::Moving) else {
            return Err(SolveError::Invalid(
                "auto: no implicit phase to leave".into(),
            ));
        };
        let mut opts = self.opts.clone();
        if let Some(b) = radau.by_size() {
            opts.atol = Atol::BySize(b.clone());
        }
        let (sys, t, y, work, _) = radau.into_parts();
        self.done = self.done + work;
        if h > 0.0 && h.is_finite() {
            opts.h0 = Some(h);
        }
        let dop = Dop853::new(sys, t, &y, &opts)?.with_stiffness(StiffnessMode::Report);
        // Dop853::new evaluated f once more at the start.
        self.done.rhs_evals = self.done.rhs_evals.saturating_sub(1);
        self.phase = Phase::Explicit(Box::new(dop));
        self.window.clear();
        self.probe_count = 0;
        self.probe_below = 0;
        self.early_count = 0;
        self.explicit_steps = 0;
        Ok(())
    }

    /// Before a step: hand the run over if the decision says so.
    fn decide(&mut self) -> Result<(), SolveError> {
        match &self.phase {
            Phase::Explicit(d) => {
                if let Some(t) = d.stiffness() {
                    self.switched_at = Some(t);
                    return self.hand_to_implicit(None);
                }
                let scale = self.probe_needed / PROBE_COUNT;
                let routine = ROUTINE_COUNT.saturating_mul(scale);
                let early = self.early_needed.saturating_mul(scale);
                let pinned = self.probe_count >= self.probe_needed || self.early_count >= early;
                if pinned || self.explicit_steps >= routine {
                    let least = if self.early_count >= early {
                        early as usize
                    } else {
                        WINDOW
                    };
                    let rate = self.explicit_rate(least);
                    if rate.is_finite() {
                        let (t0, cost0) = (d.window().1, self.cost_now());
                        self.switched_at = Some(t0);
                        return self.hand_to_implicit(Some(Probe {
                            explicit_rate: rate,
                            t0,
                            cost0,
                            // The implicit solver starts with no steps.
                            steps0: 0,
                            recheck: false,
                            wait_h: 0.0,
                            h_explicit: 0.0,
                            bar: if pinned { HYSTERESIS } else { ROUTINE_BAR },
                            mid: None,
                        }));
                    }
                }
                Ok(())
            }
            Phase::Implicit(r) => {
                let Some(p) = self.probe else {
                    return Ok(());
                };
                if p.wait_h > 0.0 {
                    let (a, b) = r.window();
                    let steps = r.work().steps;
                    if b - a >= p.wait_h {
                        // Measured from here, over the probe's steps.
                        self.probe = Some(Probe {
                            t0: b,
                            cost0: self.cost_now(),
                            steps0: steps,
                            wait_h: 0.0,
                            ..p
                        });
                        return Ok(());
                    }
                    let rate = START_STEP * EARLY_RATIO / p.wait_h;
                    if (b - p.t0).abs() * rate < START_TRANSIENT {
                        return Ok(());
                    }
                    // The mode seen at the start has died out and the step
                    // is still short: look again where the run is now (the
                    // Jacobian at the start need not be the one that
                    // matters: Robertson's is −0.04 alone at t = 0 and
                    // some 1e4 once its fast reactions start).
                    let mut look = Work::default();
                    let now = stiff_at_start(r.system(), b, r.current(), &mut look);
                    self.done = self.done + look;
                    return match now {
                        Some(rho) if b - a >= START_STEP * EARLY_RATIO / rho => {
                            self.probe = Some(Probe {
                                explicit_rate: DOP853_EVALS * rho / EARLY_RATIO,
                                t0: b,
                                cost0: self.cost_now(),
                                steps0: steps,
                                wait_h: 0.0,
                                ..p
                            });
                            Ok(())
                        }
                        _ => self.lose_probe(p),
                    };
                }
                let done = r.work().steps.saturating_sub(p.steps0);
                if done < PROBE_STEPS {
                    if p.mid.is_none() && done >= PROBE_STEPS / 2 {
                        let mid = (r.window().1, self.cost_now());
                        self.probe = Some(Probe {
                            mid: Some(mid),
                            ..p
                        });
                    }
                    return Ok(());
                }
                let t = r.window().1;
                let (t_from, cost_from) = p.mid.unwrap_or((p.t0, p.cost0));
                let rate = (self.cost_now() - cost_from) / (t - t_from);
                self.probe = None;
                let routine = p.bar < HYSTERESIS;
                // A won routine probe is checked again (against DOP853's
                // rate, not the stricter bar: hysteresis), a pinned one
                // not: its step was held by stability.
                let recheck = |steps: u64| Probe {
                    t0: t,
                    cost0: self.cost_now(),
                    steps0: steps,
                    recheck: true,
                    bar: 1.0,
                    mid: None,
                    ..p
                };
                if p.recheck && rate.is_finite() && rate <= p.explicit_rate {
                    self.probe = Some(recheck(r.work().steps + RECHECK_STEPS - PROBE_STEPS));
                    return Ok(());
                }
                if !p.recheck && rate.is_finite() && rate <= p.bar * p.explicit_rate {
                    if routine {
                        self.probe = Some(recheck(r.work().steps + RECHECK_STEPS - PROBE_STEPS));
                    }
                    return Ok(());
                }
                self.lose_probe(p)
            }
            Phase::Moving => Ok(()),
        }
    }

    /// DOP853 was found the cheaper: the run goes back to it, and the next
    /// probe waits twice as long.
    fn lose_probe(&mut self, p: Probe) -> Result<(), SolveError> {
        self.probe = None;
        self.probes_lost += 1;
        self.probe_needed = self.probe_needed.saturating_mul(2);
        self.switched_at = None;
        self.hand_to_explicit(p.h_explicit)
    }

    /// After an explicit step: its |hλ| and cost.
    fn note_explicit(&mut self) {
        let Phase::Explicit(d) = &self.phase else {
            return;
        };
        let (t, hl) = (d.window().1, d.h_lambda());
        self.explicit_steps += 1;
        if hl > self.probe_ratio * (EARLY_RATIO / PROBE_RATIO) {
            self.early_count += 1;
        } else {
            self.early_count = 0;
        }
        if hl > self.probe_ratio {
            self.probe_count += 1;
            self.probe_below = 0;
        } else {
            self.probe_below += 1;
            if self.probe_below >= PROBE_RESET {
                self.probe_count = 0;
            }
        }
        let c = self.cost_now();
        self.window.push_back((t, c));
        if self.window.len() > WINDOW {
            self.window.pop_front();
        }
    }
}

impl<S: OdeSystem> Stepper for Auto<S> {
    fn method_name(&self) -> &'static str {
        match &self.phase {
            Phase::Explicit(_) => "dop853",
            Phase::Implicit(_) => "radau5",
            Phase::Moving => "auto",
        }
    }
    fn size(&self) -> usize {
        self.requests.out.len()
    }
    fn work_done(&self) -> Work {
        match &self.phase {
            Phase::Explicit(d) => self.done + d.work(),
            Phase::Implicit(r) => self.done + r.work(),
            Phase::Moving => self.done,
        }
    }
    fn stiff_from(&self) -> Option<f64> {
        match &self.phase {
            Phase::Explicit(d) => d.stiffness(),
            _ => self.switched_at,
        }
    }
    fn abs_tol(&self) -> Option<&[f64]> {
        match &self.phase {
            Phase::Explicit(d) => Some(d.atol_now()),
            Phase::Implicit(r) => Some(r.atol_now()),
            Phase::Moving => None,
        }
    }
    fn requests(&mut self) -> &mut Requests {
        &mut self.requests
    }
    fn t_stop(&self) -> Option<f64> {
        self.opts.t_stop
    }
    fn window(&self) -> (f64, f64) {
        match &self.phase {
            Phase::Explicit(d) => d.window(),
            Phase::Implicit(r) => r.window(),
            Phase::Moving => (f64::NAN, f64::NAN),
        }
    }
    fn current(&self) -> &[f64] {
        match &self.phase {
            Phase::Explicit(d) => d.current(),
            Phase::Implicit(r) => r.current(),
            Phase::Moving => &[],
        }
    }
    fn raw_step(&mut self) -> Result<(), SolveError> {
        self.decide()?;
        match &mut self.phase {
            Phase::Explicit(d) => d.raw_step()?,
            Phase::Implicit(r) => r.raw_step()?,
            Phase::Moving => return Err(SolveError::Invalid("auto: lost its solver".into())),
        }
        self.note_explicit();
        Ok(())
    }
    fn interpolate(&mut self, t: f64, out: &mut [f64]) {
        match &mut self.phase {
            Phase::Explicit(d) => d.interpolate(t, out),
            Phase::Implicit(r) => r.interpolate(t, out),
            Phase::Moving => out.fill(f64::NAN),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solvers::ode::{Method, OdeSolver, make as make_solver};

    /// x'' = −x: not stiff at all, where Radau IIA costs several times
    /// what DOP853 does at a tight tolerance.
    struct Oscillator;
    impl OdeSystem for Oscillator {
        fn dim(&self) -> usize {
            2
        }
        fn rhs(&self, _: f64, y: &[f64], dy: &mut [f64]) {
            dy[0] = y[1];
            dy[1] = -y[0];
        }
    }

    fn opts() -> Options {
        Options {
            rtol: 1e-10,
            atol: super::super::Atol::Scalar(1e-12),
            t_stop: Some(60.0),
            ..Options::default()
        }
    }

    /// With every step counted towards a probe, `auto` probes Radau IIA
    /// on a non-stiff oscillator, finds it costlier per unit time, and
    /// gives the run back to DOP853 (each time after twice as many steps):
    /// the answer stays right, no switch is reported, and the whole run
    /// costs far less than Radau alone.
    #[test]
    fn a_probe_that_costs_more_gives_the_run_back_to_the_explicit_method() {
        let mut auto = Auto::new(Oscillator, 0.0, &[1.0, 0.0], &opts()).unwrap();
        auto.probe_ratio = 0.0;
        let y = auto.advance(60.0).unwrap().to_vec();
        assert!((y[0] - 60f64.cos()).abs() < 1e-7, "{y:?}");
        assert!(auto.probes_lost() >= 2, "{}", auto.probes_lost());
        assert_eq!(auto.method_name(), "dop853");
        assert_eq!(auto.stiff_from(), None);
        let mut radau = make_solver(Method::Radau5, Oscillator, 0.0, &[1.0, 0.0], &opts()).unwrap();
        radau.advance(60.0).unwrap();
        let mut dop = make_solver(
            Method::Dop853 {
                stiffness: StiffnessMode::Report,
            },
            Oscillator,
            0.0,
            &[1.0, 0.0],
            &opts(),
        )
        .unwrap();
        dop.advance(60.0).unwrap();
        let (a, r, d) = (
            cost(auto.work(), 2, auto.lu_price),
            cost(radau.work(), 2, auto.lu_price),
            cost(dop.work(), 2, auto.lu_price),
        );
        assert!(a < 0.5 * r, "auto {a}, radau {r}, dop853 {d}");
        assert!(a < 2.0 * d, "auto {a}, radau {r}, dop853 {d}");
    }

    /// n variables coupled in a ring with a link across it: sparse to
    /// Radau, whatever its values.
    struct Ring(usize);
    impl OdeSystem for Ring {
        fn dim(&self) -> usize {
            self.0
        }
        fn rhs(&self, _: f64, y: &[f64], dy: &mut [f64]) {
            let n = self.0;
            for i in 0..n {
                dy[i] = y[(i + 1) % n] - 2.0 * y[i] + y[(i + n / 3) % n];
            }
        }
        fn sparsity(&self) -> Option<Vec<Vec<usize>>> {
            let n = self.0;
            Some(
                (0..n)
                    .map(|i| vec![i, (i + 1) % n, (i + n / 3) % n])
                    .collect(),
            )
        }
    }

    /// The probe prices Radau's LU in the form Radau will factor in: dense
    /// on a small system (1 + n²/6 evaluations of f a pair), the sparse
    /// form's own cost on a large sparse one, far below the dense price.
    #[test]
    fn the_lu_is_priced_in_the_form_radau_factors_in() {
        let y0 = [1.0, 0.0];
        let small = Auto::new(Oscillator, 0.0, &y0, &opts()).unwrap();
        assert!((small.lu_price - (1.0 + 4.0 / 6.0)).abs() < 1e-12);
        let n = 300;
        let y0: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        let ring = Auto::new(Ring(n), 0.0, &y0, &opts()).unwrap();
        let plan = LuPlan::choose(n, Ring(n).sparsity().as_deref());
        assert_eq!(plan.kind(), super::super::lu::LuKind::Sparse);
        assert_eq!(ring.lu_price, plan.pair_in_evaluations(n));
        let dense = 1.0 + (n * n) as f64 / 6.0;
        assert!(
            ring.lu_price < dense / 20.0,
            "{} against {dense}",
            ring.lu_price
        );
        assert!((LuPlan::Dense.pair_in_evaluations(n) / dense - 1.0).abs() < 1e-12);
    }

    /// E5 (Hairer & Wanner's chemical pyrolysis), stiff from its start.
    struct E5;
    impl OdeSystem for E5 {
        fn dim(&self) -> usize {
            4
        }
        fn rhs(&self, _: f64, x: &[f64], y: &mut [f64]) {
            let (a, b, c, m) = (7.89e-10, 1.1e7, 1.13e3, 1e6);
            y[0] = -a * x[0] - b * x[0] * x[2];
            y[1] = a * x[0] - m * c * x[1] * x[2];
            y[2] = a * x[0] - b * x[0] * x[2] - m * c * x[1] * x[2] + c * x[3];
            y[3] = b * x[0] * x[2] - c * x[3];
        }
        fn jacobian(&self, _: f64, x: &[f64], j: &mut nalgebra::DMatrix<f64>) {
            let (a, b, c, m) = (7.89e-10, 1.1e7, 1.13e3, 1e6);
            j.fill(0.0);
            j[(0, 0)] = -a - b * x[2];
            j[(0, 2)] = -b * x[0];
            j[(1, 0)] = a;
            j[(1, 1)] = -m * c * x[2];
            j[(1, 2)] = -m * c * x[1];
            j[(2, 0)] = a - b * x[2];
            j[(2, 1)] = -m * c * x[2];
            j[(2, 2)] = -b * x[0] - m * c * x[1];
            j[(2, 3)] = c;
            j[(3, 0)] = b * x[2];
            j[(3, 2)] = b * x[0];
            j[(3, 3)] = -c;
        }
    }

    /// y' = A y with eigenvalues −1 and −1e8.
    struct Linear;
    impl OdeSystem for Linear {
        fn dim(&self) -> usize {
            2
        }
        fn rhs(&self, _: f64, x: &[f64], y: &mut [f64]) {
            let (d, o) = (-50000000.5, 49999999.5);
            y[0] = d * x[0] + o * x[1];
            y[1] = o * x[0] + d * x[1];
        }
        fn jacobian(&self, _: f64, _: &[f64], j: &mut nalgebra::DMatrix<f64>) {
            let (d, o) = (-50000000.5, 49999999.5);
            j.copy_from_slice(&[d, o, o, d]);
        }
    }

    /// The cost of `auto` without its look at the start, of that without
    /// its early probe too, and of Radau IIA alone on `sys` to `t_end`,
    /// and when the first of them switched.
    fn costs<S: OdeSystem + 'static>(
        sys: fn() -> S,
        y0: &[f64],
        t_end: f64,
        o: &Options,
    ) -> (f64, f64, f64, f64) {
        let n = y0.len();
        let mut auto = Auto::build(sys(), 0.0, y0, o, false).unwrap();
        auto.advance(t_end).unwrap();
        let mut late = Auto::build(sys(), 0.0, y0, o, false).unwrap();
        late.early_needed = u32::MAX;
        late.advance(t_end).unwrap();
        let mut radau = make_solver(Method::Radau5, sys(), 0.0, y0, o).unwrap();
        radau.advance(t_end).unwrap();
        let from = auto.switched_at().expect("auto switches");
        (
            cost(auto.work(), n, auto.lu_price),
            cost(late.work(), n, auto.lu_price),
            cost(radau.work(), n, auto.lu_price),
            from,
        )
    }

    /// On a problem stiff from its start, four explicit steps in a row at
    /// DOP853's stability boundary start a probe, which Radau IIA wins:
    /// without it `auto` waited for the stiffness test's 15 steps (and the
    /// probe's window of 20) before switching. Counted in evaluations of f
    /// as `auto` counts them.
    #[test]
    fn a_problem_stiff_from_its_start_goes_to_radau_within_a_few_steps() {
        for rtol in [1e-3, 1e-6] {
            let o = Options {
                rtol,
                atol: super::super::Atol::Scalar(1e-24),
                t_stop: Some(1e5),
                ..Options::default()
            };
            let (a, late, r, from) = costs(|| E5, &[1.76e-3, 0.0, 0.0, 0.0], 1e5, &o);
            let msg = format!(
                "E5 rtol {rtol}: auto {a}, without the early probe {late}, radau {r}, switched at {from}"
            );
            assert!(a < late, "{msg}");
            assert!(a <= 1.4 * r, "{msg}");
            let o = Options {
                rtol,
                atol: super::super::Atol::Scalar(rtol * 1e-6),
                t_stop: Some(10.0),
                ..Options::default()
            };
            let (a, late, r, from) = costs(|| Linear, &[2.0, 0.0], 10.0, &o);
            let msg = format!(
                "linear rtol {rtol}: auto {a}, without the early probe {late}, radau {r}, switched at {from}"
            );
            assert!(a < late, "{msg}");
            assert!(from < 1e-6, "{msg}");
        }
    }

    /// The look at the start sends a problem stiff from its start (E5,
    /// the linear system, Van der Pol at μ = 1e4) to Radau IIA before any
    /// explicit step: `auto` costs what Radau alone does, within the one
    /// Jacobian and the one f the look takes, and reaches the same state.
    #[test]
    fn a_problem_stiff_at_its_start_starts_in_radau() {
        for rtol in [1e-3, 1e-6, 1e-9] {
            let cases: [Case; 3] = [
                ("E5", Box::new(E5), vec![1.76e-3, 0.0, 0.0, 0.0], 1e5, 1e-24),
                (
                    "linear",
                    Box::new(Linear),
                    vec![2.0, 0.0],
                    10.0,
                    rtol * 1e-6,
                ),
                (
                    "Van der Pol",
                    Box::new(VanDerPol(1e4)),
                    vec![2.0, 0.0],
                    2e4,
                    rtol,
                ),
            ];
            for (name, sys, y0, t_end, atol) in cases {
                let o = Options {
                    rtol,
                    atol: super::super::Atol::Scalar(atol),
                    t_stop: Some(t_end),
                    ..Options::default()
                };
                let n = y0.len();
                let mut auto = Auto::new(&*sys, 0.0, &y0, &o).unwrap();
                let ya = auto.advance(t_end).unwrap().to_vec();
                let mut radau = Radau5::new(&*sys, 0.0, &y0, &o).unwrap();
                let yr = radau.advance(t_end).unwrap().to_vec();
                let (a, r) = (
                    cost(auto.work(), n, auto.lu_price),
                    cost(radau.work(), n, auto.lu_price),
                );
                let msg = format!("{name} rtol {rtol}: auto {a} {ya:?}, radau {r} {yr:?}");
                assert_eq!(auto.switched_at(), Some(0.0), "{msg}");
                assert_eq!(auto.probes_lost(), 0, "{msg}");
                assert!(a <= r + n as f64 + 1.0, "{msg}");
                assert_eq!(ya, yr, "{msg}");
            }
        }
    }

    /// A problem: its name, system, start, end and absolute tolerance.
    type Case = (&'static str, Box<dyn OdeSystem>, Vec<f64>, f64, f64);

    /// Van der Pol's oscillator x'' = μ(1 − x²)x' − x.
    struct VanDerPol(f64);
    impl OdeSystem for VanDerPol {
        fn dim(&self) -> usize {
            2
        }
        fn rhs(&self, _: f64, x: &[f64], y: &mut [f64]) {
            y[0] = x[1];
            y[1] = self.0 * (1.0 - x[0] * x[0]) * x[1] - x[0];
        }
        fn jacobian(&self, _: f64, x: &[f64], j: &mut nalgebra::DMatrix<f64>) {
            j.copy_from_slice(&[
                0.0,
                -2.0 * self.0 * x[0] * x[1] - 1.0,
                1.0,
                self.0 * (1.0 - x[0] * x[0]),
            ]);
        }
    }

    /// Lorenz's system from (1, 1, 1): its Jacobian there has a dominant
    /// damped eigenvalue (−22.53), so over a long run the look at the
    /// start sends it to Radau IIA, whose step never reaches twice
    /// DOP853's stability bound: the probe is lost by t = 40/22.53, DOP853
    /// takes the run from its own first step, and the state matches
    /// Radau's alone.
    struct Lorenz;
    impl OdeSystem for Lorenz {
        fn dim(&self) -> usize {
            3
        }
        fn rhs(&self, _: f64, x: &[f64], y: &mut [f64]) {
            y[0] = 10.0 * (x[1] - x[0]);
            y[1] = x[0] * (28.0 - x[2]) - x[1];
            y[2] = x[0] * x[1] - 8.0 / 3.0 * x[2];
        }
        fn jacobian(&self, _: f64, x: &[f64], j: &mut nalgebra::DMatrix<f64>) {
            j.fill(0.0);
            j[(0, 0)] = -10.0;
            j[(0, 1)] = 10.0;
            j[(1, 0)] = 28.0 - x[2];
            j[(1, 1)] = -1.0;
            j[(1, 2)] = -x[0];
            j[(2, 0)] = x[1];
            j[(2, 1)] = x[0];
            j[(2, 2)] = -8.0 / 3.0;
        }
    }

    #[test]
    fn a_start_that_only_looks_stiff_goes_back_to_the_explicit_method() {
        let y0 = [1.0, 1.0, 1.0];
        let mut work = Work::default();
        let rate = stiff_at_start(&Lorenz, 0.0, &y0, &mut work).expect("a damped mode");
        assert!((rate - 22.53).abs() < 0.1, "{rate}");
        let o = Options {
            rtol: 1e-8,
            atol: super::super::Atol::Scalar(1e-11),
            t_stop: Some(1e3),
            ..Options::default()
        };
        let mut auto = Auto::new(Lorenz, 0.0, &y0, &o).unwrap();
        auto.advance(2.0).unwrap();
        assert_eq!(auto.probes_lost(), 1);
        assert_eq!(auto.method_name(), "dop853");
        assert_eq!(auto.switched_at(), None);
        let ya = auto.advance(3.0).unwrap().to_vec();
        let mut radau = make_solver(Method::Radau5, Lorenz, 0.0, &y0, &o).unwrap();
        let yr = radau.advance(3.0).unwrap().to_vec();
        for (a, r) in ya.iter().zip(&yr) {
            assert!((a - r).abs() < 1e-5 * r.abs().max(1.0), "{ya:?} {yr:?}");
        }
        // Kepler's orbit at its pericentre (e = 0.99): the pair ±√2/r^1.5
        // is no damped mode, and the oscillator has none either.
        let kepler = [0.01, 0.0, 0.0, (1.99f64 / 0.01).sqrt()];
        assert_eq!(stiff_at_start(&Kepler, 0.0, &kepler, &mut work), None);
        assert_eq!(
            stiff_at_start(&Oscillator, 0.0, &[1.0, 0.0], &mut work),
            None
        );
    }

    /// Kepler's problem, GM = 1, as (x, y, vx, vy).
    struct Kepler;
    impl OdeSystem for Kepler {
        fn dim(&self) -> usize {
            4
        }
        fn rhs(&self, _: f64, s: &[f64], d: &mut [f64]) {
            let r3 = (s[0] * s[0] + s[1] * s[1]).powf(1.5);
            d[0] = s[2];
            d[1] = s[3];
            d[2] = -s[0] / r3;
            d[3] = -s[1] / r3;
        }
    }

    /// Robertson's kinetics, y1 + y2 + y3 = 1.
    struct Robertson;
    impl OdeSystem for Robertson {
        fn dim(&self) -> usize {
            3
        }
        fn rhs(&self, _: f64, y: &[f64], d: &mut [f64]) {
            d[0] = -0.04 * y[0] + 1e4 * y[1] * y[2];
            d[1] = 0.04 * y[0] - 1e4 * y[1] * y[2] - 3e7 * y[1] * y[1];
            d[2] = 3e7 * y[1] * y[1];
        }
        fn jacobian(&self, _: f64, y: &[f64], j: &mut nalgebra::DMatrix<f64>) {
            j.copy_from_slice(&[
                -0.04,
                0.04,
                0.0,
                1e4 * y[2],
                -1e4 * y[2] - 6e7 * y[1],
                6e7 * y[1],
                1e4 * y[1],
                -1e4 * y[1],
                0.0,
            ]);
        }
    }

    /// Robertson's Jacobian at the start is −0.04 alone: over 1e11 the
    /// look at the start sends it to Radau IIA, whose step stays short of
    /// twice DOP853's stability bound for that rate (305) long after the
    /// mode has died out (t = 40/0.04). Looked at again there, the rate is
    /// some 1e4 (the fast reactions have started) and the step far past
    /// its bound: the probe is measured from there and won, and `auto`
    /// costs what Radau alone does (it lost the probe and paid up to 1.28×
    /// Radau's instructions before the second look).
    #[test]
    fn a_second_look_keeps_radau_where_the_start_was_not_yet_stiff() {
        for rtol in [1e-4, 1e-6, 1e-8] {
            let o = Options {
                rtol,
                atol: super::super::Atol::Scalar(rtol * 1e-6),
                t_stop: Some(1e11),
                ..Options::default()
            };
            let y0 = [1.0, 0.0, 0.0];
            let mut auto = Auto::new(Robertson, 0.0, &y0, &o).unwrap();
            auto.advance(1e11).unwrap();
            let mut radau = make_solver(Method::Radau5, Robertson, 0.0, &y0, &o).unwrap();
            radau.advance(1e11).unwrap();
            let (a, r) = (
                cost(auto.work(), 3, auto.lu_price),
                cost(radau.work(), 3, auto.lu_price),
            );
            let msg = format!("rtol {rtol}: auto {a}, radau {r}");
            assert_eq!(auto.probes_lost(), 0, "{msg}");
            assert_eq!(auto.switched_at(), Some(0.0), "{msg}");
            assert!(a <= r + 2.0 * (3.0 + 1.0), "{msg}");
        }
    }

    /// a' = −1e4·a from a = 0 beside an oscillator: the fast mode is never
    /// excited (f has no part in it), so the look at the start does not
    /// send the run to Radau IIA, which cost 4.3× DOP853's evaluations at
    /// rtol 1e-10 over 1,000 time units.
    struct Unexcited;
    impl OdeSystem for Unexcited {
        fn dim(&self) -> usize {
            3
        }
        fn rhs(&self, _: f64, y: &[f64], d: &mut [f64]) {
            d[0] = -1e4 * y[0];
            d[1] = y[2];
            d[2] = -y[1];
        }
        fn jacobian(&self, _: f64, _: &[f64], j: &mut nalgebra::DMatrix<f64>) {
            j.fill(0.0);
            j[(0, 0)] = -1e4;
            j[(1, 2)] = 1.0;
            j[(2, 1)] = -1.0;
        }
    }

    #[test]
    fn a_fast_mode_never_excited_is_not_looked_at() {
        let mut work = Work::default();
        assert_eq!(
            stiff_at_start(&Unexcited, 0.0, &[0.0, 1.0, 0.0], &mut work),
            None
        );
        // Excited, it is.
        let rate = stiff_at_start(&Unexcited, 0.0, &[1.0, 1.0, 0.0], &mut work);
        assert!(rate.is_some_and(|r| (r - 1e4).abs() < 1.0), "{rate:?}");
        let o = Options {
            rtol: 1e-8,
            atol: super::super::Atol::Scalar(1e-11),
            t_stop: Some(1e3),
            ..Options::default()
        };
        let mut auto = Auto::new(Unexcited, 0.0, &[0.0, 1.0, 0.0], &o).unwrap();
        auto.advance(50.0).unwrap();
        assert_eq!(auto.method_name(), "dop853");
        assert_eq!(auto.switched_at(), None);
    }
}
