//! What a run keeps of one quantity to measure it, and where its measures
//! are located exactly rather than read from samples.
//!
//! A run samples each accepted step at [`POINTS_PER_STEP`] points of the
//! solver's dense output. The samples are only where to look:
//!
//! - **Extremes** (`max`, `min`, `amplitude` and the peaks `beat` reads)
//!   are located on the dense output itself, by Brent's method (golden
//!   section and parabolic steps) over the two sample intervals around a
//!   sample that is larger (smaller) than its neighbours, or over the
//!   interval at a step's edge where the quantity rises into it, while the
//!   step's interpolant is still at hand ([`Bracket`]; the run does the
//!   evaluating). A candidate that cannot beat the running extreme by more
//!   than its samples vary is not searched.
//! - **Crossings of a level** (`period`'s upward crossings of the level
//!   halfway between the extremes, known only at the end, and the levels
//!   of `time_of` and `count`) are located on the interpolating polynomial
//!   of degree 5 through the six samples around the crossing (the samples
//!   are points of the dense output, so this is a local interpolant of it),
//!   solved by bisection to the resolution of f64.
//! - **The mean** integrates each step by Simpson's rule over its
//!   [`POINTS_PER_STEP`] equal sub-intervals (trapezoids inside a step not
//!   yet finished, and for a fixed-step method sampled once a step).
//!
//! The measured accuracy against exact values (Kepler orbits, a rosette
//! orbit, coupled oscillators) is asserted in `tests/measure_accuracy.rs`.

use super::ReadingError;
use crate::scene::spec::Stat;
use crate::scene::vocabulary::{Event, Measure, Rel};

/// The level of |N(0)| below which drift is measured absolutely.
pub(crate) const TINY: f64 = 1e-300;

/// An interval of the current step where an extreme may lie, to be
/// searched on the dense output: `max` says which kind, `edge` where it
/// sits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Bracket {
    pub a: f64,
    pub b: f64,
    pub max: bool,
    pub edge: Edge,
    /// The sample at the bracket's edge (a step's start or end; unused
    /// inside), and whether the samples show the quantity still rising
    /// into a step's end at least half as fast as over the interval
    /// before (no turn near that end).
    pub at_edge: f64,
    pub steady: bool,
}

/// Where a bracket sits in its step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Edge {
    /// Around a sample inside the step.
    Inside,
    /// The step's first interval, falling from a start the quantity rose
    /// into: the peak is in it or at its start.
    Start,
    /// The step's last interval, rising into its end: the peak is in it,
    /// or at or past the end (then the next step says).
    End,
}

/// Least relative variation of the squared peaks that makes an envelope
/// (below it they differ only by the solver's error).
const ENVELOPE: f64 = 1e-4;

/// Relative spread of the intervals between upward crossings above which
/// `period` is flagged as measured on a signal that is not periodic at one
/// frequency.
const UNEVEN: f64 = 0.02;

/// Running statistics of one quantity.
#[derive(Debug, Clone)]
pub(super) struct Tally {
    first: f64,
    last: f64,
    t_first: f64,
    t_last: f64,
    max: f64,
    min: f64,
    /// ∫N dt over the finished steps (Simpson), and over the current
    /// step's samples so far (trapezoids) with its Simpson sum.
    integral: f64,
    partial: f64,
    simpson: f64,
    sign: f64,
    crossings: u64,
    drift: f64,
    /// (t, value) for the period, which needs the run's extent first.
    samples: Vec<(f64, f64)>,
    count: u64,
    /// The two samples before the last, oldest first (NaN before there
    /// are any).
    before: [(f64, f64); 2],
    /// Every peak of |N| (time, |N|) when `beat` is measured (N's maxima
    /// above zero and minima below), and the end of the interval the last
    /// maximum and minimum were found in (a peak at a step's edge is found
    /// from both sides).
    peaks: Option<Vec<(f64, f64)>>,
    peak_end: [f64; 2],
    /// Where in `peaks` the last maximum and minimum are.
    peak_at: [usize; 2],
    /// Only the extent is kept (a panel's, no measure's): the mean,
    /// crossings and drift are not.
    extent_only: bool,
    /// What the run asks of it, fixed by its plan: every sample kept (for
    /// a period), extremes located for a measure, or for a panel's extent
    /// (read at each sample, so not looked up in the plan there).
    pub(super) keeps: bool,
    pub(super) measured: bool,
    pub(super) searched: bool,
}

/// Where a sample sits in its step: the `k`-th of `per_step` after the
/// step's start.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct InStep {
    pub k: usize,
    pub per_step: usize,
    /// The step's start.
    pub t0: f64,
}

impl Tally {
    /// A tally; `peaks`: keep every peak (for `beat`).
    pub(super) fn new(peaks: bool) -> Tally {
        Tally {
            first: f64::NAN,
            last: f64::NAN,
            t_first: 0.0,
            t_last: 0.0,
            max: f64::NEG_INFINITY,
            min: f64::INFINITY,
            integral: 0.0,
            partial: 0.0,
            simpson: 0.0,
            sign: 0.0,
            crossings: 0,
            drift: 0.0,
            samples: Vec::new(),
            count: 0,
            before: [(f64::NAN, f64::NAN); 2],
            peaks: peaks.then(Vec::new),
            peak_end: [f64::NAN; 2],
            peak_at: [0; 2],
            extent_only: false,
            keeps: false,
            measured: false,
            searched: false,
        }
    }

    /// A tally of the extent alone, for a panel ([`Tally::extent`]).
    pub(super) fn extent_only() -> Tally {
        Tally {
            extent_only: true,
            ..Tally::new(false)
        }
    }

    /// Takes the sample (t, v); `at` is where it sits in its step (None
    /// for the run's first sample).
    pub(super) fn add(&mut self, t: f64, v: f64, keep: bool, at: Option<InStep>) {
        if self.count == 0 {
            self.first = v;
            self.t_first = t;
        } else if !self.extent_only {
            self.partial += 0.5 * (v + self.last) * (t - self.t_last);
            if let Some(at) = at {
                if at.per_step % 2 == 0 {
                    if at.k == 1 {
                        // The step's start is the last sample.
                        self.simpson = self.last;
                    }
                    self.simpson += v * if at.k == at.per_step {
                        1.0
                    } else if at.k % 2 == 1 {
                        4.0
                    } else {
                        2.0
                    };
                    if at.k == at.per_step {
                        let h = (t - at.t0) / at.per_step as f64;
                        self.integral += self.simpson * h / 3.0;
                        self.partial = 0.0;
                        self.simpson = 0.0;
                    }
                } else {
                    self.integral += self.partial;
                    self.partial = 0.0;
                }
            }
        }
        self.count += 1;
        self.before = [self.before[1], (self.t_last, self.last)];
        self.last = v;
        self.t_last = t;
        self.max = self.max.max(v);
        self.min = self.min.min(v);
        if self.extent_only {
            return;
        }
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

    /// The smallest and largest value so far (the extremes located
    /// between samples included), None before the first sample.
    pub(super) fn extent(&self) -> Option<(f64, f64)> {
        (self.count > 0).then_some((self.min, self.max))
    }

    /// No extreme near the last samples can beat the best so far by the
    /// test [`Tally::brackets`] makes, on any of the samples it reads: it
    /// has nothing to search (most samples of a long run, told at once).
    #[inline]
    pub(super) fn quiet(&self) -> bool {
        if self.peaks.is_some() {
            return false;
        }
        let (v2, v1, v) = (self.before[0].1, self.before[1].1, self.last);
        let hi = v1.max(v).max(v2);
        let lo = v1.min(v).min(v2);
        hi + (hi - lo) <= self.max && lo - (hi - lo) >= self.min
    }

    /// Where an extreme may lie around the samples so far, within the step
    /// that started at `t0` (whose last sample this is when `step_end`):
    /// the intervals worth searching on that step's dense output.
    pub(super) fn brackets(&self, t0: f64, step_end: bool) -> Vec<Bracket> {
        let mut out = Vec::new();
        if self.count < 2 {
            return out;
        }
        let (t2, v2) = self.before[0];
        let (t1, v1) = self.before[1];
        let (t, v) = (self.t_last, self.last);
        if self.quiet() {
            return out;
        }
        for max in [true, false] {
            // Compare as for a maximum: for a minimum, of −N.
            let s = if max { 1.0 } else { -1.0 };
            let best = if max { self.max } else { -self.min };
            // Worth a search only if the extreme nearby can beat the best
            // so far (it exceeds its samples by less than they vary), or if
            // every peak is kept. Samples all equal to the best are a flat
            // stretch (a sketch's fixed dot, a quantity held at a bound):
            // nothing beyond them to find.
            let all = self.peaks.is_some();
            let worth = |vals: &[f64]| {
                let hi = vals.iter().fold(f64::NEG_INFINITY, |m, &x| m.max(s * x));
                let lo = vals.iter().fold(f64::INFINITY, |m, &x| m.min(s * x));
                all || hi + (hi - lo) > best
            };
            let bracket = |a, b, edge| Bracket {
                a,
                b,
                max,
                edge,
                at_edge: if edge == Edge::Start { v1 } else { v },
                steady: edge == Edge::End && {
                    let before = s * (v1 - v2) / (t1 - t2);
                    let last = s * (v - v1) / (t - t1);
                    last > 0.0 && last >= 0.5 * before
                },
            };
            if t1 > t0 {
                // t1 inside the step: a peak at t1 lies in [t2, t].
                if t2 >= t0 && s * v1 >= s * v2 && s * v1 >= s * v && worth(&[v2, v1, v]) {
                    out.push(bracket(t2, t, Edge::Inside));
                }
            } else if s * v1 >= s * v && (v2.is_nan() || s * v2 <= s * v1) && worth(&[v1, v]) {
                // The step's first interval, falling from a start the
                // quantity rose into: the peak's part in this step is here
                // (the part before was searched at the previous step's end).
                out.push(bracket(t1, t, Edge::Start));
            }
            if step_end && s * v >= s * v1 && worth(&[v1, v]) {
                // Rising into the step's end: the peak's part in this step.
                out.push(bracket(t1, t, Edge::End));
            }
        }
        out.dedup();
        out
    }

    /// Takes the extreme `v` at `t` found by searching `br`.
    pub(super) fn found(&mut self, br: Bracket, t: f64, v: f64) {
        if !v.is_finite() {
            return;
        }
        if br.max {
            self.max = self.max.max(v);
        } else {
            self.min = self.min.min(v);
        }
        let Some(peaks) = &mut self.peaks else {
            return;
        };
        // A peak of |N|: a maximum above zero or a minimum below.
        if (br.max && v < 0.0) || (!br.max && v > 0.0) {
            return;
        }
        // A peak at the end of a step rising into it is the next step's to
        // find (or, at the boundary itself, found again from there); the
        // run's start is no turning point.
        if (br.edge == Edge::End && t >= br.b) || t <= self.t_first {
            return;
        }
        let kind = usize::from(!br.max);
        let same = br.a <= self.peak_end[kind];
        self.peak_end[kind] = br.b;
        // The same peak from the other side of a step's edge, or from
        // overlapping intervals of a flat top.
        if same && let Some(last) = peaks.get_mut(self.peak_at[kind]) {
            if v.abs() > last.1 {
                *last = (t, v.abs());
            }
            return;
        }
        self.peak_at[kind] = peaks.len();
        peaks.push((t, v.abs()));
    }

    /// The intervals between the upward crossings `period` uses, and the
    /// level: for the caveat that they are not evenly spaced.
    pub(super) fn period_spread(&self) -> Option<(f64, f64, f64)> {
        let times = self.period_crossings();
        let gaps: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
        if gaps.len() < 2 {
            return None;
        }
        let lo = gaps.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = gaps.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let mean = gaps.iter().sum::<f64>() / gaps.len() as f64;
        ((hi - lo) > UNEVEN * mean).then_some((lo, hi, mean))
    }

    /// The period of the envelope through the peaks of |N|, read on their
    /// squares (N² has a smooth envelope where |N|'s has a corner at each
    /// node of the beat).
    fn beat(&self, name: &str) -> Result<f64, ReadingError> {
        let peaks: Vec<(f64, f64)> = self
            .peaks
            .as_deref()
            .unwrap_or(&[])
            .iter()
            .map(|&(t, v)| (t, v * v))
            .collect();
        let lo = peaks.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
        let hi = peaks.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max);
        if peaks.len() >= 2 && hi - lo <= ENVELOPE * hi {
            return Err(ReadingError::FlatBeat {
                name: name.to_string(),
                peaks: peaks.len(),
            });
        }
        let times = upward_crossings(&peaks, 0.5 * (lo + hi));
        mean_spacing(&times).ok_or(ReadingError::NoBeat {
            name: name.to_string(),
            peaks: peaks.len(),
            upward: times.len(),
        })
    }

    pub(super) fn stat(&self, stat: Stat, name: &str) -> Result<f64, ReadingError> {
        if self.count == 0 {
            return Err(ReadingError::NoSamples {
                stat,
                name: name.to_string(),
            });
        }
        Ok(match stat {
            Stat::Max => self.max,
            Stat::Min => self.min,
            Stat::Final => self.last,
            Stat::Mean => {
                let span = self.t_last - self.t_first;
                if span > 0.0 {
                    (self.integral + self.partial) / span
                } else {
                    self.first
                }
            }
            Stat::Crossings => self.crossings as f64,
            Stat::Drift => self.drift / self.first.abs().max(TINY),
            Stat::Period => return self.period(name),
            Stat::Amplitude => 0.5 * (self.max - self.min),
            Stat::Beat => return self.beat(name),
            // Kept by their own [`Watch`].
            Stat::TimeOf(_) | Stat::Count(_) => {
                return Err(ReadingError::NoSamples {
                    stat,
                    name: name.to_string(),
                });
            }
        })
    }

    /// Mean time between successive upward crossings of the mid level.
    fn period(&self, name: &str) -> Result<f64, ReadingError> {
        let times = self.period_crossings();
        mean_spacing(&times).ok_or(ReadingError::NoPeriod {
            name: name.to_string(),
            upward: times.len(),
        })
    }

    /// The upward crossings of the level halfway between the extremes.
    fn period_crossings(&self) -> Vec<f64> {
        upward_crossings(&self.samples, 0.5 * (self.min + self.max))
    }
}

/// The mean time between the first and last of `times` (None with fewer
/// than two).
fn mean_spacing(times: &[f64]) -> Option<f64> {
    match times {
        [first, .., last] => Some((last - first) / (times.len() - 1) as f64),
        _ => None,
    }
}

/// The times `samples` cross `level` upwards, each located on the local
/// interpolant ([`crossing`]).
pub(super) fn upward_crossings(samples: &[(f64, f64)], level: f64) -> Vec<f64> {
    let mut times = Vec::new();
    for i in 0..samples.len().saturating_sub(1) {
        let (v0, v1) = (samples[i].1, samples[i + 1].1);
        if v0 < level && v1 >= level {
            times.push(crossing(samples, i, level));
        }
    }
    times
}

/// Points of the interpolating polynomial through the crossing.
const NODES: usize = 6;

/// Where the quantity sampled at `samples` crosses `level` between samples
/// `i` and `i + 1` (on opposite sides of it): the root there of the
/// polynomial of degree 5 through the six samples around them (fewer at
/// the ends of the run), by bisection. The polynomial takes the samples'
/// values, so the root lies in the interval.
pub(super) fn crossing(samples: &[(f64, f64)], i: usize, level: f64) -> f64 {
    let n = samples.len();
    let lo = i.saturating_sub(NODES / 2 - 1).min(n.saturating_sub(NODES));
    let nodes = &samples[lo..(lo + NODES).min(n)];
    let (ts, coef) = newton(nodes);
    let p = |t: f64| {
        let mut acc = coef[coef.len() - 1];
        for k in (0..coef.len() - 1).rev() {
            acc = acc * (t - ts[k]) + coef[k];
        }
        acc - level
    };
    let (mut a, mut b) = (samples[i].0, samples[i + 1].0);
    let (mut fa, fb) = (p(a), p(b));
    if fa.is_nan() || fb.is_nan() || fa.signum() == fb.signum() && fa != 0.0 && fb != 0.0 {
        // Rounding: fall back on the straight line between the samples.
        let (v0, v1) = (samples[i].1, samples[i + 1].1);
        return a + (level - v0) / (v1 - v0) * (b - a);
    }
    if fa == 0.0 {
        return a;
    }
    for _ in 0..200 {
        let m = 0.5 * (a + b);
        if m <= a || m >= b {
            break;
        }
        let fm = p(m);
        if fm == 0.0 {
            return m;
        }
        if fm.signum() == fa.signum() {
            a = m;
            fa = fm;
        } else {
            b = m;
        }
    }
    0.5 * (a + b)
}

/// Newton's divided differences of the polynomial through `nodes`: its
/// nodes and coefficients.
fn newton(nodes: &[(f64, f64)]) -> (Vec<f64>, Vec<f64>) {
    let ts: Vec<f64> = nodes.iter().map(|p| p.0).collect();
    let mut c: Vec<f64> = nodes.iter().map(|p| p.1).collect();
    for j in 1..c.len() {
        for k in (j..c.len()).rev() {
            c[k] = (c[k] - c[k - 1]) / (ts[k] - ts[k - j]);
        }
    }
    (ts, c)
}

/// The largest value of `f` on [a, b] and where it is, by Brent's method
/// (golden section with parabolic steps; Brent, *Algorithms for
/// Minimization without Derivatives*, ch. 5), to a relative resolution of
/// about 1e-10 in t. `f` returns None where it cannot be evaluated; the
/// search then stops with the best point so far.
///
/// Brent's method assumes a peak the function climbs to and falls from.
/// A quantity that drops at a jump (a gated observable, `phi·(1 +
/// sign(vr))/2`, whose peak is its value just before vr turns) breaks ties
/// away from the jump: the search finds only equal values past it and
/// ends at the far end, and the peak right beside the near end is never
/// seen (the rosette's apsidal angle read 184.658° for 184.676°). So when
/// an end beats every point inside, the peak lies at that end or between
/// it and the first point inside that falls below it: bisection finds where
/// the quantity falls below the end's value, and a second search between
/// the end and there finds the peak.
#[cfg(test)]
pub(super) fn brent_max(a: f64, b: f64, f: impl FnMut(f64) -> Option<f64>) -> Option<(f64, f64)> {
    brent_max_within(a, b, 0.0, f)
}

/// The search of `brent_max` above (with `within` 0: the same, to about
/// 1e-10 in t; a measure's), stopping as soon as the value is known to
/// about `within` when it is positive, for a panel's extent, which a drawing resolves only so far: once a parabolic step
/// lands where the parabola through the search's last three points
/// predicted, to within `within`, the quantity is that parabola to about
/// `within` around its vertex, and the value found is its extreme to about
/// twice that. A measure's search is never cut short (it is an answer).
pub(super) fn brent_max_within(
    a: f64,
    b: f64,
    within: f64,
    mut f: impl FnMut(f64) -> Option<f64>,
) -> Option<(f64, f64)> {
    let (a, b) = (a.min(b), a.max(b));
    let (x, fx, fa, fb) = brent_inside(a, b, within, &mut f)?;
    let mut best = (x, fx);
    for (end, fe) in [(a, fa), (b, fb)] {
        if fe <= best.1 {
            continue;
        }
        best = (end, fe);
        // Just inside the end first: a quantity that falls away from the
        // end at once (rising into a step's end, the common case, every
        // step) has no jump beside it, and needs no bisection.
        let inside = end + (x - end) * 2f64.powi(-(BISECTIONS as i32));
        if !f(inside).is_some_and(|v| v > fe) {
            continue;
        }
        // The quantity stays at or above the end's value on [end, lo] and
        // falls below it at hi.
        let (mut lo, mut hi) = (end, x);
        for _ in 0..BISECTIONS {
            let mid = 0.5 * (lo + hi);
            if mid == lo || mid == hi {
                break;
            }
            match f(mid) {
                Some(v) if v >= fe => {
                    lo = mid;
                    if v > best.1 {
                        best = (mid, v);
                    }
                }
                Some(_) => hi = mid,
                None => break,
            }
        }
        if lo != end
            && let Some((t, v, _, _)) = brent_inside(end.min(lo), end.max(lo), within, &mut f)
            && v > best.1
        {
            best = (t, v);
        }
    }
    Some(best)
}

/// Bisections that find where a quantity falls below an end's value: the
/// place to within 2⁻⁴⁰ of the bracket.
const BISECTIONS: usize = 40;

/// Brent's search inside [a, b]: the best point it found and its value, and
/// the values at a and b; with `within` > 0 it stops once a parabolic step
/// lands within `within` of the value its parabola predicted
/// ([`brent_max_within`]).
fn brent_inside(
    a: f64,
    b: f64,
    within: f64,
    f: &mut impl FnMut(f64) -> Option<f64>,
) -> Option<(f64, f64, f64, f64)> {
    const GOLD: f64 = 0.381_966_011_250_105_1;
    let g = |v: f64| -v;
    let (mut a, mut b) = (a.min(b), a.max(b));
    let fa = f(a)?;
    let fb = f(b)?;
    let mut x = a + GOLD * (b - a);
    let mut fx = g(f(x)?);
    let (mut w, mut v) = (x, x);
    let (mut fw, mut fv) = (fx, fx);
    let (mut d, mut e) = (0.0f64, 0.0f64);
    for _ in 0..100 {
        let m = 0.5 * (a + b);
        let tol = 1e-10 * x.abs().max(b - a).max(f64::MIN_POSITIVE) + 1e-300;
        let tol2 = 2.0 * tol;
        if (x - m).abs() <= tol2 - 0.5 * (b - a) {
            break;
        }
        let mut golden = true;
        // The parabola's value at its vertex, when the step goes there.
        let mut predicted = f64::NAN;
        if e.abs() > tol {
            let r = (x - w) * (fx - fv);
            let mut q = (x - v) * (fx - fw);
            let mut p = (x - v) * q - (x - w) * r;
            q = 2.0 * (q - r);
            if q > 0.0 {
                p = -p;
            }
            q = q.abs();
            if p.abs() < (0.5 * q * e).abs() && p > q * (a - x) && p < q * (b - x) {
                e = d;
                d = p / q;
                let u = x + d;
                if u - a < tol2 || b - u < tol2 {
                    d = if m >= x { tol } else { -tol };
                } else if within > 0.0 && d.abs() >= tol {
                    predicted = parabola([(x, fx), (w, fw), (v, fv)], u);
                }
                golden = false;
            }
        }
        if golden {
            e = if x >= m { a - x } else { b - x };
            d = GOLD * e;
        }
        let u = if d.abs() >= tol {
            x + d
        } else {
            x + tol.copysign(d)
        };
        let Some(fu) = f(u).map(g) else {
            break;
        };
        let landed = (fu - predicted).abs() <= within;
        if fu <= fx {
            if u >= x {
                a = x;
            } else {
                b = x;
            }
            (v, fv, w, fw, x, fx) = (w, fw, x, fx, u, fu);
        } else {
            if u < x {
                a = u;
            } else {
                b = u;
            }
            if fu <= fw || w == x {
                (v, fv, w, fw) = (w, fw, u, fu);
            } else if fu <= fv || v == x || v == w {
                (v, fv) = (u, fu);
            }
        }
        if landed {
            break;
        }
    }
    Some((x, -fx, fa, fb))
}

/// The parabola through three points, at `t` (NaN when two coincide).
fn parabola(p: [(f64, f64); 3], t: f64) -> f64 {
    let [(x0, y0), (x1, y1), (x2, y2)] = p;
    y0 * (t - x1) * (t - x2) / ((x0 - x1) * (x0 - x2))
        + y1 * (t - x0) * (t - x2) / ((x1 - x0) * (x1 - x2))
        + y2 * (t - x0) * (t - x1) / ((x2 - x0) * (x2 - x1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn brent_finds_the_peak_of_a_smooth_function() {
        let (t, v) = brent_max(0.0, 3.0, |t| Some((t - 1.234_567_89).cos())).unwrap();
        assert!((t - 1.234_567_89).abs() < 1e-7, "{t}");
        assert!((v - 1.0).abs() < 1e-15, "{v}");
        // Monotone: the end.
        let (t, _) = brent_max(0.0, 1.0, Some).unwrap();
        assert_eq!(t, 1.0);
        let (t, _) = brent_max(0.0, 1.0, |t| Some(-t)).unwrap();
        assert_eq!(t, 0.0);
    }

    /// A quantity that climbs from one end and drops to zero at a jump
    /// peaks just before the jump, wherever the jump lies (Brent's search
    /// alone ended at the far end and kept the near end's value for every
    /// jump here); and a smooth peak right beside an end is found too.
    #[test]
    fn brent_finds_a_peak_just_before_a_jump_beside_either_end() {
        for c in [0.3, 0.1, 0.05, 0.0345, 1e-4] {
            let (t, v) =
                brent_max(0.0, 1.0, |t| Some(if t < c { 100.0 + t } else { 0.0 })).unwrap();
            assert!(t < c && c - t < 1e-9, "{c}: {t}");
            assert!((v - (100.0 + c)).abs() < 1e-9, "{c}: {v}");
            let (t, v) = brent_max(0.0, 1.0, |t| {
                Some(if t > 1.0 - c { 101.0 - t } else { 0.0 })
            })
            .unwrap();
            assert!(t > 1.0 - c && t - (1.0 - c) < 1e-9, "{c}: {t}");
            assert!((v - (100.0 + c)).abs() < 1e-9, "{c}: {v}");
            let peak = c / 2.0;
            let (t, _) = brent_max(0.0, 1.0, |t| {
                Some(if t < c { -(t - peak).powi(2) } else { -1.0 })
            })
            .unwrap();
            assert!((t - peak).abs() < 1e-7 * c.max(1e-3), "{c}: {t}");
        }
    }

    /// A panel's extent is searched only to what it shows: on a smooth
    /// peak, wide or narrow, the search stops in fewer evaluations than a
    /// measure's and its value is within twice the tolerance asked of the
    /// peak (never past it); with no tolerance it is the full search.
    #[test]
    fn an_extent_search_stops_at_its_tolerance() {
        for width in [1.0, 20.0, 400.0] {
            let f = |t: f64| 1.0 / (1.0 + width * (t - 1.3).powi(2));
            let search = |within: f64| {
                let mut n = 0;
                let (_, v) = brent_max_within(0.0, 3.0, within, |t| {
                    n += 1;
                    Some(f(t))
                })
                .unwrap();
                (v, n)
            };
            let (full, n_full) = search(0.0);
            assert_eq!((full, n_full), {
                let mut n = 0;
                let (_, v) = brent_max(0.0, 3.0, |t| {
                    n += 1;
                    Some(f(t))
                })
                .unwrap();
                (v, n)
            });
            assert!((1.0 - full).abs() < 1e-15, "{width}: {full}");
            let within = 1e-4;
            let (coarse, n) = search(within);
            assert!(
                coarse <= 1.0 && 1.0 - coarse <= 2.0 * within,
                "{width}: {coarse}"
            );
            assert!(n < n_full, "{width}: {n} evaluations, {n_full} in full");
        }
    }

    #[test]
    fn a_crossing_is_located_on_the_interpolant_not_the_chord() {
        // sin sampled every 0.1 crossing 1/2 upwards at 2π + π/6: the chord
        // misses it by ~3e-4, the quintic by far less.
        let h = 0.1;
        let samples: Vec<(f64, f64)> = (0..16)
            .map(|k| {
                let t = 5.5 + k as f64 * h;
                (t, t.sin())
            })
            .collect();
        let times = upward_crossings(&samples, 0.5);
        assert_eq!(times.len(), 1);
        let exact = 2.0 * std::f64::consts::PI + std::f64::consts::PI / 6.0;
        assert!((times[0] - exact).abs() < 1e-9, "{}", times[0] - exact);
        let i = samples.iter().position(|p| p.0 > exact).unwrap() - 1;
        let (a, b) = (samples[i], samples[i + 1]);
        let chord = a.0 + (0.5 - a.1) / (b.1 - a.1) * h;
        assert!((chord - exact).abs() > 1e-5, "{}", chord - exact);
    }

    #[test]
    fn simpson_integrates_each_finished_step() {
        // N = t² over two steps of 4 sub-intervals: Simpson is exact.
        let mut tally = Tally::new(false);
        tally.add(0.0, 0.0, false, None);
        for (t0, t1) in [(0.0, 1.0), (1.0, 3.0)] {
            for k in 1..=4 {
                let t = t0 + (t1 - t0) * k as f64 / 4.0;
                let at = InStep { k, per_step: 4, t0 };
                tally.add(t, t * t, false, Some(at));
            }
        }
        let mean = tally.stat(Stat::Mean, "x").unwrap();
        assert!((mean - 3.0).abs() < 1e-14, "{mean}");
    }
}

/// What `time_of(N rel level)` and `count(N rel level)` watch: how often
/// the relation has started to hold, and when first (the crossing between
/// two samples is located on the dense output by the run).
#[derive(Debug, Clone)]
pub(super) struct Watch {
    pub q: usize,
    pub stat: Stat,
    event: Event,
    count: u64,
    /// When the relation first held, once located.
    time: Option<f64>,
    /// The samples either side of the first time, to locate.
    pub pending: Option<(f64, f64)>,
    /// The last sample, and the side of the level N was last on (±1).
    prev: Option<(f64, f64)>,
    side: f64,
}

impl Watch {
    pub(super) fn new(q: usize, stat: Stat) -> Option<Watch> {
        Some(Watch {
            q,
            stat,
            event: stat.event()?,
            count: 0,
            time: None,
            pending: None,
            prev: None,
            side: 0.0,
        })
    }

    /// Whether `v` satisfies the relation (for `=`: touches the level).
    fn holds(&self, v: f64) -> bool {
        let l = self.event.level.get();
        match self.event.rel {
            Rel::Above => v > l,
            Rel::AtLeast => v >= l,
            Rel::Below => v < l,
            Rel::AtMost => v <= l,
            Rel::Crosses => v == l,
        }
    }

    pub(super) fn add(&mut self, t: f64, v: f64) {
        let l = self.event.level.get();
        let started = match (self.event.rel, self.prev) {
            (Rel::Crosses, _) => {
                let s = (v - l).signum();
                let crossed = v != l && self.side != 0.0 && s != self.side;
                if v != l {
                    self.side = s;
                }
                if crossed {
                    self.count += 1;
                }
                crossed || (v == l && self.time.is_none())
            }
            (_, None) => self.holds(v),
            (_, Some((_, pv))) => !self.holds(pv) && self.holds(v),
        };
        if started && self.event.rel != Rel::Crosses {
            self.count += 1;
        }
        if started && self.time.is_none() {
            match self.prev {
                Some((pt, _)) if v != l => self.pending = Some((pt, t)),
                _ => self.time = Some(t),
            }
        }
        self.prev = Some((t, v));
    }

    /// The first time, located in `pending` by bisection on `f` (N on the
    /// dense output there).
    pub(super) fn locate(&mut self, mut f: impl FnMut(f64) -> Option<f64>) {
        let Some((mut a, mut b)) = self.pending.take() else {
            return;
        };
        let l = self.event.level.get();
        let side_a = f(a).map(|v| (v - l).signum());
        for _ in 0..200 {
            let m = 0.5 * (a + b);
            if m <= a || m >= b {
                break;
            }
            match (f(m), side_a) {
                (Some(v), Some(sa)) if (v - l).signum() == sa && v != l => a = m,
                (Some(_), Some(_)) => b = m,
                _ => break,
            }
        }
        self.time = Some(b);
    }

    /// The reading of `measure` (this watch's) so far.
    pub(super) fn value(&self, measure: Measure) -> Result<f64, ReadingError> {
        match (self.stat, measure) {
            (Stat::Count(_), _) => Ok(self.count as f64),
            (_, Measure::Of(_, name)) => self.time.ok_or_else(|| ReadingError::Never {
                measure: measure.to_string(),
                what: self.event.relation(name.as_str()),
            }),
            _ => Err(ReadingError::Rigid(measure)),
        }
    }
}
