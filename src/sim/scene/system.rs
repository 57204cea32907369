//! A system scene's run: what it computes (its [`SystemPlan`], from what is
//! shown and measured), the run as the view plays it or a command samples
//! it, and the measures of its variables and observables.
//!
//! Each accepted step is sampled by dense output at [`POINTS_PER_STEP`]
//! points, so the measures follow the solution wherever the solver had to
//! look closely (Van der Pol's fast jumps, Robertson's first second) and
//! never depend on how often a frame is drawn.

use crate::sim::scene::measure::{Measurements, Reading};
use crate::sim::scene::spec::{Measure, Stat, SystemPanel, SystemScene};
use crate::sim::solvers::ode::{self, OdeError, OdeKind, OdeMethod, OdeSolver, Work};
use crate::sim::system::System;

/// Dense-output points per accepted step of an adaptive method (RK4's
/// small fixed steps are sampled at their ends).
pub const POINTS_PER_STEP: usize = 16;
/// Points kept for each drawn curve (plot, phase, trail).
pub const TRACE_LEN: usize = 2048;
/// The level of |N(0)| below which drift is measured absolutely.
pub const TINY: f64 = 1e-300;

/// What a system scene computes, from what it shows and measures.
#[derive(Debug, Clone, PartialEq)]
pub struct SystemPlan {
    /// Per observable: evaluated at all (plotted, drawn in the phase
    /// portrait, sketched through, measured or conserved in diagnostics).
    pub observables: Vec<bool>,
    /// Quantities (variables, then observables) the meter tracks.
    pub metered: Vec<usize>,
    /// The sketch's expressions are evaluated.
    pub sketch: bool,
    /// A second, tight run for the error in the diagnostics.
    pub reference: bool,
    /// The Jacobian is compiled (implicit methods only).
    pub jacobian: bool,
    /// Quantities whose every sample is kept (for their period).
    pub periods: Vec<usize>,
}

impl SystemPlan {
    pub fn for_scene(scene: &SystemScene, method: OdeMethod, measures: &[Measure]) -> SystemPlan {
        let n = scene.variables.len();
        let index = |name: &str| -> Option<usize> {
            scene.variables.iter().position(|v| v == name).or_else(|| {
                scene
                    .observables
                    .iter()
                    .position(|(o, _)| o == name)
                    .map(|k| n + k)
            })
        };
        let diagnostics = scene.shows(SystemPanel::Diagnostics);
        let mut metered: Vec<usize> = Vec::new();
        let add = |q: Option<usize>, metered: &mut Vec<usize>| {
            if let Some(q) = q
                && !metered.contains(&q)
            {
                metered.push(q);
            }
        };
        let mut periods = Vec::new();
        for m in measures {
            if let Measure::Of(stat, name) = m {
                add(index(name.as_str()), &mut metered);
                if *stat == Stat::Period {
                    add(index(name.as_str()), &mut periods);
                }
            }
        }
        if diagnostics {
            for c in &scene.conserved {
                add(index(c), &mut metered);
            }
        }
        let mut drawn = metered.clone();
        if scene.shows(SystemPanel::Plot) {
            for p in &scene.plot {
                add(index(p), &mut drawn);
            }
        }
        if scene.shows(SystemPanel::Phase)
            && let Some(pair) = &scene.phase
        {
            for p in pair {
                add(index(p), &mut drawn);
            }
        }
        let sketch = scene.shows(SystemPanel::Sketch) && !scene.sketch.is_empty();
        let mut observables = vec![false; scene.observables.len()];
        for q in &drawn {
            if *q >= n {
                observables[q - n] = true;
            }
        }
        SystemPlan {
            observables,
            metered,
            sketch,
            reference: diagnostics,
            jacobian: method.kind.implicit(),
            periods,
        }
    }
}

/// Running statistics of one quantity.
#[derive(Debug, Clone)]
struct Tally {
    first: f64,
    last: f64,
    t_first: f64,
    t_last: f64,
    max: f64,
    min: f64,
    integral: f64,
    sign: f64,
    crossings: u64,
    drift: f64,
    /// (t, value) for the period, which needs the run's extent first.
    samples: Vec<(f64, f64)>,
    count: u64,
}

impl Tally {
    fn new() -> Tally {
        Tally {
            first: f64::NAN,
            last: f64::NAN,
            t_first: 0.0,
            t_last: 0.0,
            max: f64::NEG_INFINITY,
            min: f64::INFINITY,
            integral: 0.0,
            sign: 0.0,
            crossings: 0,
            drift: 0.0,
            samples: Vec::new(),
            count: 0,
        }
    }

    fn add(&mut self, t: f64, v: f64, keep: bool) {
        if self.count == 0 {
            self.first = v;
            self.t_first = t;
        } else {
            self.integral += 0.5 * (v + self.last) * (t - self.t_last);
        }
        self.count += 1;
        self.last = v;
        self.t_last = t;
        self.max = self.max.max(v);
        self.min = self.min.min(v);
        if v != 0.0 {
            let s = v.signum();
            if self.sign != 0.0 && s != self.sign {
                self.crossings += 1;
            }
            self.sign = s;
        }
        self.drift = self.drift.max((v - self.first).abs());
        if keep {
            self.samples.push((t, v));
        }
    }

    fn stat(&self, stat: Stat, name: &str) -> Result<f64, String> {
        if self.count == 0 {
            return Err(format!("{}({name}): the run has no samples", stat.name()));
        }
        Ok(match stat {
            Stat::Max => self.max,
            Stat::Min => self.min,
            Stat::Final => self.last,
            Stat::Mean => {
                let span = self.t_last - self.t_first;
                if span > 0.0 {
                    self.integral / span
                } else {
                    self.first
                }
            }
            Stat::Crossings => self.crossings as f64,
            Stat::Drift => self.drift / self.first.abs().max(TINY),
            Stat::Period => return self.period(name),
        })
    }

    /// Mean time between successive upward crossings of the mid level.
    fn period(&self, name: &str) -> Result<f64, String> {
        let level = 0.5 * (self.min + self.max);
        let mut times = Vec::new();
        for w in self.samples.windows(2) {
            let ((t0, v0), (t1, v1)) = (w[0], w[1]);
            if v0 < level && v1 >= level {
                let f = (level - v0) / (v1 - v0);
                times.push(t0 + f * (t1 - t0));
            }
        }
        if times.len() < 2 {
            return Err(format!(
                "period({name}): {name} crosses the level halfway between its minimum and maximum upwards {} over the run; a period needs two",
                match times.len() {
                    0 => "never".to_string(),
                    _ => "once".to_string(),
                }
            ));
        }
        Ok((times[times.len() - 1] - times[0]) / (times.len() - 1) as f64)
    }
}

/// One point of a drawn curve: time and the values of the drawn
/// quantities (or sketch coordinates).
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    pub t: f64,
    pub values: Vec<f64>,
}

/// A fixed-length record of a run for drawing: every k-th sample, k
/// doubling when full, so it always spans the whole run so far.
#[derive(Debug, Clone, Default)]
pub struct Trace {
    pub points: Vec<Point>,
    stride: usize,
    seen: usize,
}

impl Trace {
    fn push(&mut self, p: Point) {
        if self.stride == 0 {
            self.stride = 1;
        }
        if self.seen.is_multiple_of(self.stride) {
            self.points.push(p);
            if self.points.len() >= TRACE_LEN {
                let kept: Vec<Point> = self.points.iter().step_by(2).cloned().collect();
                self.points = kept;
                self.stride *= 2;
            }
        }
        self.seen += 1;
    }
}

/// What the diagnostics panel shows.
#[derive(Debug, Clone, PartialEq)]
pub struct SystemDiagnostics {
    /// The solver now stepping.
    pub solver: &'static str,
    pub work: Work,
    /// When auto found the problem stiff and switched to Radau IIA.
    pub stiff_at: Option<f64>,
    /// Drift so far of each conserved observable (name, relative drift).
    pub drift: Vec<(String, f64)>,
    /// Largest error against the reference run so far, relative to the
    /// size of the state (None while no reference runs).
    pub error: Option<f64>,
}

/// A system scene running.
pub struct SystemRun {
    scene: SystemScene,
    system: System,
    plan: SystemPlan,
    method: OdeMethod,
    solver: Box<dyn OdeSolver>,
    reference: Option<Box<dyn OdeSolver>>,
    /// Index into the quantities of each plotted name, phase pair.
    plot: Vec<usize>,
    phase: Option<[usize; 2]>,
    /// Frame time and state.
    t: f64,
    state: Vec<f64>,
    /// Last sampled time (the meter's frontier).
    sampled: f64,
    tallies: Vec<(usize, Tally)>,
    trace: Trace,
    trail: Trace,
    error: Option<OdeError>,
    ref_error: f64,
    scratch: Vec<f64>,
}

/// `the solution blows up near t = 1.0`: the time to four significant
/// digits, always with a decimal point.
pub fn describe(e: &OdeError) -> String {
    match e {
        OdeError::BlowUp { t } => {
            let mut s = crate::text::num::rounded(*t, 4);
            if !s.contains(['.', 'e', 'E']) {
                s.push_str(".0");
            }
            format!("the solution blows up near t = {s}")
        }
        OdeError::Stiff { t } => format!(
            "the problem is stiff from t = {}: adaptive (explicit) refuses it; use --method radau or auto",
            crate::text::num::rounded(*t, 4)
        ),
        e => e.to_string(),
    }
}

impl SystemRun {
    /// A run that computes what `scene` shows and what `measures` need.
    pub fn new(
        scene: &SystemScene,
        method: OdeMethod,
        measures: &[Measure],
    ) -> Result<SystemRun, String> {
        let plan = SystemPlan::for_scene(scene, method, measures);
        SystemRun::with_plan(scene, method, plan)
    }

    pub fn with_plan(
        scene: &SystemScene,
        method: OdeMethod,
        plan: SystemPlan,
    ) -> Result<SystemRun, String> {
        let system = System::compile(scene, plan.jacobian)?;
        let (m, opts) = method.solver(scene.duration);
        let solver =
            ode::make(m, system.clone(), 0.0, &scene.initial, &opts).map_err(|e| describe(&e))?;
        let reference = if plan.reference {
            let r = OdeMethod::with_setting(OdeKind::Radau, ode::REFERENCE_RTOL)?;
            let (m, opts) = r.solver(scene.duration);
            let sys = System::compile(scene, true)?;
            Some(ode::make(m, sys, 0.0, &scene.initial, &opts).map_err(|e| describe(&e))?)
        } else {
            None
        };
        let n = scene.variables.len();
        let index = |name: &str| -> usize {
            scene
                .variables
                .iter()
                .position(|v| v == name)
                .or_else(|| {
                    scene
                        .observables
                        .iter()
                        .position(|(o, _)| o == name)
                        .map(|k| n + k)
                })
                .unwrap_or(0)
        };
        let plot = if scene.shows(SystemPanel::Plot) {
            scene.plot.iter().map(|p| index(p)).collect()
        } else {
            Vec::new()
        };
        let phase = scene
            .phase
            .as_ref()
            .filter(|_| scene.shows(SystemPanel::Phase))
            .map(|[a, b]| [index(a), index(b)]);
        let tallies = plan.metered.iter().map(|&q| (q, Tally::new())).collect();
        let mut run = SystemRun {
            scene: scene.clone(),
            system,
            plan,
            method,
            solver,
            reference,
            plot,
            phase,
            t: 0.0,
            state: scene.initial.clone(),
            sampled: 0.0,
            tallies,
            trace: Trace::default(),
            trail: Trace::default(),
            error: None,
            ref_error: 0.0,
            scratch: vec![0.0; n],
        };
        let y0 = scene.initial.clone();
        run.sample(0.0, &y0);
        Ok(run)
    }

    /// The index of a variable or observable among the quantities.
    pub fn quantity(&self, name: &str) -> Option<usize> {
        let n = self.scene.variables.len();
        self.scene
            .variables
            .iter()
            .position(|v| v == name)
            .or_else(|| {
                self.scene
                    .observables
                    .iter()
                    .position(|(o, _)| o == name)
                    .map(|k| n + k)
            })
    }

    /// Quantity `q` at (t, y): a variable, or an observable (evaluated).
    fn value(&self, q: usize, t: f64, y: &[f64]) -> f64 {
        let n = y.len();
        if q < n {
            y[q]
        } else {
            self.system.observable(q - n, t, y)
        }
    }

    fn sample(&mut self, t: f64, y: &[f64]) {
        for k in 0..self.tallies.len() {
            let q = self.tallies[k].0;
            let v = self.value(q, t, y);
            let keep = self.plan.periods.contains(&q);
            self.tallies[k].1.add(t, v, keep);
        }
        let mut drawn: Vec<usize> = self.plot.clone();
        if let Some([a, b]) = self.phase {
            drawn.push(a);
            drawn.push(b);
        }
        if !drawn.is_empty() {
            let values = drawn.iter().map(|&q| self.value(q, t, y)).collect();
            self.trace.push(Point { t, values });
        }
        if self.plan.sketch {
            let values = (0..self.system.mark_count())
                .map(|k| self.system.mark(k, t, y))
                .collect();
            self.trail.push(Point { t, values });
        }
        self.sampled = t;
    }

    /// Samples every step up to `target`, then sets the frame there.
    pub fn advance_to(&mut self, target: f64) {
        if self.error.is_some() {
            return;
        }
        let target = target.min(self.scene.duration);
        if target <= self.t {
            return;
        }
        let per_step = if self.method.kind == OdeKind::Rk4 {
            1
        } else {
            POINTS_PER_STEP
        };
        while self.solver.t() < target {
            let (t0, t1) = match self.solver.step() {
                Ok(w) => w,
                Err(e) => {
                    self.error = Some(e);
                    return;
                }
            };
            let end = t1.min(self.scene.duration);
            let mut y = std::mem::take(&mut self.scratch);
            for k in 1..=per_step {
                let t = if k == per_step {
                    end
                } else {
                    t0 + (end - t0) * k as f64 / per_step as f64
                };
                if t <= self.sampled {
                    continue;
                }
                if let Err(e) = self.solver.dense(t, &mut y) {
                    self.error = Some(e);
                    self.scratch = y;
                    return;
                }
                self.sample(t, &y.clone());
            }
            self.scratch = y;
            if t1 >= self.scene.duration {
                break;
            }
        }
        let mut y = vec![0.0; self.state.len()];
        match self.solver.dense(target, &mut y) {
            Ok(()) => {
                self.state = y;
                self.t = target;
            }
            Err(e) => self.error = Some(e),
        }
        if let Some(r) = &mut self.reference {
            match r.advance(self.t) {
                Ok(yr) => {
                    let scale = yr.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1e-300);
                    let err = yr
                        .iter()
                        .zip(&self.state)
                        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
                        / scale;
                    self.ref_error = self.ref_error.max(err);
                }
                Err(_) => self.reference = None,
            }
        }
    }

    /// Runs to the end (or the first error).
    pub fn run_to_end(&mut self) -> Result<(), OdeError> {
        self.advance_to(self.scene.duration);
        match &self.error {
            Some(e) => Err(e.clone()),
            None => Ok(()),
        }
    }

    pub fn scene(&self) -> &SystemScene {
        &self.scene
    }
    pub fn plan(&self) -> &SystemPlan {
        &self.plan
    }
    pub fn method(&self) -> OdeMethod {
        self.method
    }
    pub fn t(&self) -> f64 {
        self.t
    }
    pub fn state(&self) -> &[f64] {
        &self.state
    }
    pub fn finished(&self) -> bool {
        self.error.is_some() || self.t >= self.scene.duration
    }
    pub fn error(&self) -> Option<&OdeError> {
        self.error.as_ref()
    }
    pub fn has_reference(&self) -> bool {
        self.reference.is_some()
    }
    /// The plotted quantities, then the phase pair, over the run so far.
    pub fn trace(&self) -> &[Point] {
        &self.trace.points
    }
    /// The sketch's coordinates over the run so far.
    pub fn trail(&self) -> &[Point] {
        &self.trail.points
    }
    /// How many plotted quantities lead each trace point.
    pub fn plot_count(&self) -> usize {
        self.plot.len()
    }
    /// The sketch's coordinates at the frame.
    pub fn marks_now(&self) -> Vec<f64> {
        (0..self.system.mark_count())
            .map(|k| self.system.mark(k, self.t, &self.state))
            .collect()
    }
    pub fn work(&self) -> Work {
        self.solver.work()
    }

    pub fn diagnostics(&self) -> SystemDiagnostics {
        let drift = self
            .scene
            .conserved
            .iter()
            .filter_map(|c| {
                let q = self.quantity(c)?;
                let (_, tally) = self.tallies.iter().find(|(k, _)| *k == q)?;
                Some((c.clone(), tally.stat(Stat::Drift, c).ok()?))
            })
            .collect();
        SystemDiagnostics {
            solver: self.solver.name(),
            work: self.solver.work(),
            stiff_at: self.solver.stiffness(),
            drift,
            error: self.reference.as_ref().map(|_| self.ref_error),
        }
    }

    /// One measure of the run so far, or why it cannot be made.
    pub fn measure(&self, m: Measure) -> Result<f64, String> {
        let Measure::Of(stat, name) = m else {
            return Err(format!(
                "`{m}` is a rigid-body measure; this scene is a system"
            ));
        };
        let q = self.quantity(name.as_str()).ok_or_else(|| {
            format!(
                "`{name}` is not a variable or observable of scene {}",
                self.scene.id
            )
        })?;
        let (_, tally) = self
            .tallies
            .iter()
            .find(|(k, _)| *k == q)
            .ok_or_else(|| format!("{m} was not planned for this run"))?;
        let v = tally.stat(stat, name.as_str())?;
        if v.is_finite() {
            Ok(v)
        } else {
            Err(format!("{m} is not a finite number"))
        }
    }

    /// The readings of `measures` the run could make.
    pub fn measurements(&self, measures: &[Measure]) -> Measurements {
        let readings = measures
            .iter()
            .filter_map(|&m| {
                self.measure(m).ok().map(|value| Reading {
                    measure: m,
                    value,
                    formula: None,
                })
            })
            .collect();
        Measurements::from_readings(readings).over(self.t())
    }
}

/// Runs a scene to its end for `measures`; each value, or why it cannot be
/// made. A failed run is an error for all.
pub fn measure_system(
    scene: &SystemScene,
    method: OdeMethod,
    measures: &[Measure],
) -> Result<Vec<Result<f64, String>>, String> {
    let plan = SystemPlan {
        reference: false,
        sketch: false,
        ..SystemPlan::for_scene(scene, method, measures)
    };
    let mut run = SystemRun::with_plan(scene, method, plan)?;
    run.run_to_end().map_err(|e| describe(&e))?;
    Ok(measures.iter().map(|&m| run.measure(m)).collect())
}

#[cfg(test)]
mod tests;
