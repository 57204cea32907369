//! What a run of a scene measures, for the prompts to check against: flips
//! and the time between them, the early growth of a disturbance about the
//! middle axis, the wobble about a stable axis, the body precession of a
//! symmetric top, how much ω changed, and the drift of the invariants. Each
//! measurement comes with the closed-form value it should match, where one
//! exists, so a verdict can read "measured 5.77 vs √k = 5.77".
//!
//! A [`Meter`] is fed the trajectory sample by sample, in time order, so the
//! live view measures exactly what it plays without keeping the samples.

use std::collections::BTreeMap;

use nalgebra::Vector3;

use crate::rigid::formula::{self, AxisRole};
use crate::rigid::model::Body;
use crate::scene::spec::Measure;

/// A disturbance counts as small while |ω⊥| stays below this fraction of
/// |ω|: the linear growth law holds to about a percent there.
const SMALL: f64 = 0.1;
/// The growth fit starts once the disturbance has grown by e² from its
/// initial size, when the decaying mode has died down.
const SETTLED_GROWTH: f64 = std::f64::consts::E * std::f64::consts::E;

/// One measured value and the formula value it is compared with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reading {
    pub measure: Measure,
    pub value: f64,
    /// What theory gives for the same quantity (`None` where no closed form
    /// applies, e.g. a count of flips).
    pub formula: Option<f64>,
}

impl Reading {
    /// How the formula reads in a verdict ("√k", "2K(m)/λ").
    pub fn formula_name(&self) -> Option<&'static str> {
        self.formula.map(|_| formula_name(self.measure))
    }
}

/// The formula each measure is compared with (its row's `formula`).
pub fn formula_name(measure: Measure) -> &'static str {
    crate::scene::vocabulary::row_of(measure).formula
}

/// Everything one run measured, in the vocabulary's order. A measure that
/// does not apply to the motion (no flips to time, no symmetric top) is
/// absent.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Measurements {
    readings: Vec<Reading>,
    evidence: Evidence,
}

/// What a verdict shows besides the numbers, so that it claims no more
/// than the run showed: how long the run lasted, when each flip came, and
/// how often the motion flips (whether or not this run was long enough to
/// see two of them).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Evidence {
    /// Scene time the run covered.
    pub elapsed: f64,
    /// Times of the flips counted, in order.
    pub flip_times: Vec<f64>,
    /// 2K(m)/λ: the time between flips the closed form gives, `None` when
    /// the motion never flips.
    pub flip_interval: Option<f64>,
}

impl Measurements {
    pub fn get(&self, measure: Measure) -> Option<f64> {
        self.reading(measure).map(|r| r.value)
    }

    /// The closed-form value for `measure`, when the run measured it and a
    /// formula applies.
    pub fn formula(&self, measure: Measure) -> Option<f64> {
        self.reading(measure).and_then(|r| r.formula)
    }

    pub fn reading(&self, measure: Measure) -> Option<&Reading> {
        self.readings.iter().find(|r| r.measure == measure)
    }

    /// The same readings, said to come from a run that covered `elapsed`
    /// (the verdict names the run's length).
    pub fn over(mut self, elapsed: f64) -> Measurements {
        self.evidence.elapsed = elapsed;
        self
    }

    /// Measurements made elsewhere (a system scene's run).
    pub fn from_readings(readings: Vec<Reading>) -> Measurements {
        Measurements {
            readings,
            evidence: Evidence::default(),
        }
    }

    pub fn readings(&self) -> &[Reading] {
        &self.readings
    }

    pub fn evidence(&self) -> &Evidence {
        &self.evidence
    }

    /// The measured values by measure.
    pub fn values(&self) -> BTreeMap<Measure, f64> {
        self.readings.iter().map(|r| (r.measure, r.value)).collect()
    }
}

/// Least-squares line through (t, y) points, kept as running sums.
#[derive(Debug, Clone, Copy, Default)]
struct LineFit {
    n: f64,
    st: f64,
    sy: f64,
    stt: f64,
    sty: f64,
    y_first: f64,
    y_last: f64,
}

impl LineFit {
    fn add(&mut self, t: f64, y: f64) {
        if self.n == 0.0 {
            self.y_first = y;
        }
        self.y_last = y;
        self.n += 1.0;
        self.st += t;
        self.sy += y;
        self.stt += t * t;
        self.sty += t * y;
    }

    fn slope(&self) -> Option<f64> {
        let d = self.n * self.stt - self.st * self.st;
        (self.n >= 3.0 && d > 0.0).then(|| (self.n * self.sty - self.st * self.sy) / d)
    }
}

/// Where the growth fit is along the run.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Window {
    Before,
    Inside,
    Done,
}

/// Sign changes of one component, with their times.
#[derive(Debug, Clone, Default)]
struct Crossings {
    /// The last nonzero sign seen (0 before any).
    sign: f64,
    times: Vec<f64>,
}

impl Crossings {
    /// Mean time between successive crossings (needs two).
    fn mean_gap(&self) -> Option<f64> {
        let n = self.times.len();
        (n >= 2).then(|| (self.times[n - 1] - self.times[0]) / (n - 1) as f64)
    }
}

/// Measures a trajectory fed to it in time order.
#[derive(Debug, Clone)]
pub(crate) struct Meter {
    body: Body,
    omega0: Vector3<f64>,
    dominant: usize,
    /// The two other axes, cyclic after the dominant one.
    perp: [usize; 2],
    role: AxisRole,
    symmetry: Option<usize>,
    energy0: f64,
    l2_0: f64,
    norm0: f64,
    last: Option<(f64, Vector3<f64>)>,
    t_first: f64,
    flips: Crossings,
    wobble: [Crossings; 2],
    growth: LineFit,
    window: Window,
    perp0: f64,
    /// Unwrapped angle of ω⊥ about the symmetry axis, and since when.
    turned: f64,
    omega_change: f64,
    energy_drift: f64,
    l2_drift: f64,
}

impl Meter {
    pub fn new(body: &Body, omega0: &Vector3<f64>) -> Meter {
        let dominant = formula::dominant_axis(omega0);
        let perp = [(dominant + 1) % 3, (dominant + 2) % 3];
        let perp0 = omega0[perp[0]].hypot(omega0[perp[1]]);
        Meter {
            body: *body,
            omega0: *omega0,
            dominant,
            perp,
            role: formula::axis_role(body, dominant),
            symmetry: formula::symmetry_axis(body),
            energy0: body.energy(omega0),
            l2_0: body.l2(omega0),
            norm0: omega0.norm(),
            last: None,
            t_first: 0.0,
            flips: Crossings::default(),
            wobble: [Crossings::default(), Crossings::default()],
            growth: LineFit::default(),
            window: Window::Before,
            perp0,
            turned: 0.0,
            omega_change: 0.0,
            energy_drift: 0.0,
            l2_drift: 0.0,
        }
    }

    /// Adds the state at time `t` (later than every earlier call).
    pub fn record(&mut self, t: f64, omega: &Vector3<f64>) {
        let prev = self.last.replace((t, *omega));
        let Some(prev) = prev else {
            self.t_first = t;
            self.flips.sign = sign(omega[self.dominant]);
            for (c, &axis) in self.wobble.iter_mut().zip(&self.perp) {
                c.sign = sign(omega[axis]);
            }
            self.record_invariants(omega);
            self.record_growth(t, omega);
            return;
        };
        let now = (t, *omega);
        crossing(&self.body, &mut self.flips, self.dominant, &prev, &now);
        for k in 0..2 {
            crossing(&self.body, &mut self.wobble[k], self.perp[k], &prev, &now);
        }
        if let Some(s) = self.symmetry {
            let (a, b) = ((s + 1) % 3, (s + 2) % 3);
            let (x0, y0, x1, y1) = (prev.1[a], prev.1[b], omega[a], omega[b]);
            self.turned += (x0 * y1 - y0 * x1).atan2(x0 * x1 + y0 * y1);
        }
        self.record_invariants(omega);
        self.record_growth(t, omega);
    }

    fn record_invariants(&mut self, omega: &Vector3<f64>) {
        let rel = |x: f64, x0: f64| {
            if x0 != 0.0 {
                ((x - x0) / x0).abs()
            } else {
                x.abs()
            }
        };
        let change = (omega - self.omega0).amax();
        let change = if self.norm0 > 0.0 {
            change / self.norm0
        } else {
            change
        };
        self.omega_change = self.omega_change.max(change);
        self.energy_drift = self
            .energy_drift
            .max(rel(self.body.energy(omega), self.energy0));
        self.l2_drift = self.l2_drift.max(rel(self.body.l2(omega), self.l2_0));
    }

    fn record_growth(&mut self, t: f64, omega: &Vector3<f64>) {
        if self.role != AxisRole::Middle || self.perp0 == 0.0 || self.window == Window::Done {
            return;
        }
        let perp = omega[self.perp[0]].hypot(omega[self.perp[1]]);
        if perp > SMALL * omega.norm() {
            self.window = Window::Done;
            return;
        }
        if self.window == Window::Before && perp >= SETTLED_GROWTH * self.perp0 {
            self.window = Window::Inside;
        }
        if self.window == Window::Inside {
            self.growth.add(t, perp.ln());
        }
    }

    /// The measurements so far, each with its formula value.
    pub fn finish(&self) -> Measurements {
        let mut readings = Vec::new();
        let mut put = |measure: Measure, value: Option<f64>, formula: Option<f64>| {
            if let Some(value) = value.filter(|v| v.is_finite()) {
                readings.push(Reading {
                    measure,
                    value,
                    formula: formula.filter(|f| f.is_finite()),
                });
            }
        };
        let spin = self.omega0[self.dominant];
        let k = formula::stability(&self.body, self.dominant, spin);
        let elapsed = self.last.map_or(0.0, |(t, _)| t - self.t_first);

        put(
            Measure::Flips,
            self.last.map(|_| self.flips.times.len() as f64),
            None,
        );
        let flip_formula = formula::flip_interval(&self.body, &self.omega0, self.dominant);
        put(Measure::FlipPeriod, self.flips.mean_gap(), flip_formula);

        // The fit must span at least one e-folding to mean anything.
        let growth = (self.growth.y_last - self.growth.y_first >= 1.0)
            .then(|| self.growth.slope())
            .flatten();
        let growth_formula = (k > 0.0).then(|| k.sqrt());
        put(Measure::GrowthRate, growth, growth_formula);
        put(
            Measure::EfoldTime,
            growth.filter(|g| *g > 0.0).map(|g| 1.0 / g),
            growth_formula.map(|g| 1.0 / g),
        );

        let wobble = if self.role == AxisRole::Extreme {
            self.wobble
                .iter()
                .filter(|c| c.times.len() >= 2)
                .max_by_key(|c| c.times.len())
                .and_then(Crossings::mean_gap)
                .map(|gap| std::f64::consts::PI / gap)
        } else {
            None
        };
        put(
            Measure::OscillationFreq,
            wobble,
            (k < 0.0).then(|| (-k).sqrt()),
        );

        let rate = self
            .symmetry
            .filter(|_| elapsed > 0.0)
            .map(|_| self.turned / elapsed);
        let rate_formula = formula::body_precession_rate(&self.body, &self.omega0);
        put(Measure::PrecessionRate, rate, rate_formula);
        let period = |r: f64| (r != 0.0).then(|| std::f64::consts::TAU / r.abs());
        put(
            Measure::PrecessionPeriod,
            rate.and_then(period),
            rate_formula.and_then(period),
        );

        let steady = self.last.is_some() && self.symmetry.is_none() && {
            let i = self.body.inertia;
            (0..3).all(|a| {
                let (p, q) = ((a + 1) % 3, (a + 2) % 3);
                (i[p] - i[q]) * self.omega0[p] * self.omega0[q] == 0.0
            })
        };
        put(
            Measure::OmegaChange,
            self.last.map(|_| self.omega_change),
            steady.then_some(0.0),
        );
        put(
            Measure::EnergyDrift,
            self.last.map(|_| self.energy_drift),
            Some(0.0),
        );
        put(
            Measure::MomentumDrift,
            self.last.map(|_| self.l2_drift),
            Some(0.0),
        );
        Measurements {
            readings,
            evidence: Evidence {
                elapsed,
                flip_times: self.flips.times.clone(),
                flip_interval: flip_formula.filter(|f| f.is_finite() && *f > 0.0),
            },
        }
    }

    /// Flips counted so far (the live counter).
    pub fn flips(&self) -> &[f64] {
        &self.flips.times
    }
}

fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// Registers a sign change of component `axis` between two samples, timed
/// by the cubic Hermite interpolant through both values and both slopes
/// (Euler's equations give the slopes exactly), so a coarse grid still
/// times a flip finely.
fn crossing(
    body: &Body,
    c: &mut Crossings,
    axis: usize,
    (t0, w0): &(f64, Vector3<f64>),
    (t1, w1): &(f64, Vector3<f64>),
) {
    let s = sign(w1[axis]);
    if s == 0.0 {
        return;
    }
    if c.sign == 0.0 {
        c.sign = s;
        return;
    }
    if s == c.sign {
        return;
    }
    c.sign = s;
    let h = t1 - t0;
    let (y0, y1) = (w0[axis], w1[axis]);
    let (d0, d1) = (body.omega_dot(w0)[axis] * h, body.omega_dot(w1)[axis] * h);
    let hermite = |x: f64| {
        let x2 = x * x;
        let x3 = x2 * x;
        (2.0 * x3 - 3.0 * x2 + 1.0) * y0
            + (x3 - 2.0 * x2 + x) * d0
            + (-2.0 * x3 + 3.0 * x2) * y1
            + (x3 - x2) * d1
    };
    // Bisection on [0, 1], where the interpolant changes sign (when the
    // previous sample was exactly zero the crossing is at its end).
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    let f_lo = hermite(lo);
    if f_lo == 0.0 {
        c.times.push(*t0);
        return;
    }
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        let f = hermite(mid);
        if sign(f) == sign(f_lo) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    c.times.push(t0 + 0.5 * (lo + hi) * h);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn meter_run(inertia: [f64; 3], omega: [f64; 3], t_end: f64, n: usize) -> Measurements {
        // Small explicit steps of RK4 with many substeps: an independent,
        // accurate enough trajectory for the measurement logic.
        let body = Body::new(inertia).unwrap();
        let mut w = Vector3::from(omega);
        let mut meter = Meter::new(&body, &w);
        meter.record(0.0, &w);
        let sub = 20;
        let h = t_end / (n * sub) as f64;
        for k in 1..=n {
            for _ in 0..sub {
                let k1 = body.omega_dot(&w);
                let k2 = body.omega_dot(&(w + k1 * (0.5 * h)));
                let k3 = body.omega_dot(&(w + k2 * (0.5 * h)));
                let k4 = body.omega_dot(&(w + k3 * h));
                w += (k1 + 2.0 * (k2 + k3) + k4) * (h / 6.0);
            }
            meter.record(k as f64 * t_end / n as f64, &w);
        }
        meter.finish()
    }

    #[test]
    fn middle_axis_flips_at_the_elliptic_half_period() {
        let m = meter_run([1.0, 2.0, 3.0], [0.01, 10.0, 0.01], 12.0, 2000);
        assert_eq!(m.get(Measure::Flips), Some(4.0));
        let period = m.get(Measure::FlipPeriod).unwrap();
        let formula = m.formula(Measure::FlipPeriod).unwrap();
        assert!(
            (period - formula).abs() < 1e-5 * formula,
            "{period} vs {formula}"
        );
        // No wobble about the middle axis, no symmetric top.
        assert_eq!(m.get(Measure::OscillationFreq), None);
        assert_eq!(m.get(Measure::PrecessionRate), None);
    }

    #[test]
    fn early_growth_matches_root_k() {
        let m = meter_run([1.0, 2.0, 3.0], [0.001, 10.0, 0.001], 4.0, 2000);
        let g = m.get(Measure::GrowthRate).unwrap();
        let sqrt_k = (100.0f64 / 3.0).sqrt();
        assert_eq!(m.formula(Measure::GrowthRate), Some(sqrt_k));
        assert!((g - sqrt_k).abs() < 0.02 * sqrt_k, "{g} vs {sqrt_k}");
        let tau = m.get(Measure::EfoldTime).unwrap();
        assert!((tau * g - 1.0).abs() < 1e-12);
    }

    #[test]
    fn stable_axis_wobbles_at_root_minus_k() {
        let m = meter_run([1.0, 2.0, 3.0], [0.01, 0.01, 10.0], 4.0, 2000);
        assert_eq!(m.get(Measure::Flips), Some(0.0));
        let f = m.get(Measure::OscillationFreq).unwrap();
        assert_eq!(m.formula(Measure::OscillationFreq), Some(10.0));
        assert!((f - 10.0).abs() < 1e-3, "{f}");
        assert_eq!(m.get(Measure::GrowthRate), None);
    }

    #[test]
    fn symmetric_top_precesses_with_sign() {
        let m = meter_run([2.0, 2.0, 3.0], [1.0, 0.0, 10.0], 5.0, 1000);
        let rate = m.get(Measure::PrecessionRate).unwrap();
        assert!((rate - 5.0).abs() < 1e-6, "{rate}");
        assert_eq!(m.formula(Measure::PrecessionRate), Some(5.0));
        let period = m.get(Measure::PrecessionPeriod).unwrap();
        assert!((period - std::f64::consts::TAU / 5.0).abs() < 1e-6);
        // A prolate top turns the other way.
        let m = meter_run([1.0, 2.0, 2.0], [4.0, 0.5, 0.0], 5.0, 1000);
        let rate = m.get(Measure::PrecessionRate).unwrap();
        assert!((rate + 2.0).abs() < 1e-6, "{rate}");
    }

    #[test]
    fn sphere_keeps_omega_and_invariants() {
        let m = meter_run([2.0, 2.0, 2.0], [1.0, 2.0, 3.0], 5.0, 100);
        assert_eq!(m.get(Measure::OmegaChange), Some(0.0));
        assert_eq!(m.get(Measure::EnergyDrift), Some(0.0));
        assert_eq!(m.get(Measure::MomentumDrift), Some(0.0));
        assert_eq!(m.get(Measure::PrecessionRate), None);
        let m = meter_run([1.0, 2.0, 3.0], [0.01, 10.0, 0.01], 8.0, 1000);
        assert!(m.get(Measure::OmegaChange).unwrap() > 1.0);
        assert!(m.get(Measure::EnergyDrift).unwrap() < 1e-8);
    }

    #[test]
    fn hermite_timing_beats_the_grid() {
        // 64 samples over 8 s: 0.125 s apart, yet the flips are timed to
        // far better than the spacing.
        let fine = meter_run([1.0, 2.0, 3.0], [0.01, 10.0, 0.01], 12.0, 4000);
        let coarse = meter_run([1.0, 2.0, 3.0], [0.01, 10.0, 0.01], 12.0, 96);
        let (a, b) = (
            fine.get(Measure::FlipPeriod).unwrap(),
            coarse.get(Measure::FlipPeriod).unwrap(),
        );
        assert!((a - b).abs() < 1e-3, "{a} vs {b}");
    }
}
