//! The sketch's trails as they are drawn: a polyline through the run's
//! samples that keeps to the continuous solution within a resolution
//! that follows the sketch's extent ([`RESOLUTION`]).
//!
//! - **Between two samples** the chord may cut a corner the curve turns
//!   (perihelion on an eccentric orbit, where a fixed step or a coarse
//!   tolerance leaves few samples): where the curvature the last three
//!   samples show says the chord strays by more than a quarter of the
//!   resolution, the interval is halved on the step's dense output until
//!   each midpoint lies within the resolution of its chord, at most
//!   [`MAX_DEPTH`] times (31 evaluations an interval at the most, so a
//!   hostile deck costs a bounded multiple of a sample's work).
//! - **Thinned where straight**: a point is dropped while every point
//!   dropped since the last one kept lies within the resolution of the
//!   chord that replaces them (at most [`MAX_SKIPPED`] in a row). The
//!   dropped points are not measured again at each sample: the directions
//!   from the last point kept whose chords pass within the resolution of
//!   every one of them form a cone (an interval of angles, [`Cone`]), and a
//!   chord in it that reaches at least as far as the farthest of them keeps
//!   them all; only a chord outside it (once per point kept) or short of
//!   them (where the curve turns back) measures each. A trail
//!   longer than [`TRAIL_LEN`] points is thinned again at twice the
//!   distance, which then holds until the extent outgrows it, so it always
//!   spans the run and its drawing costs a bounded time.

use super::Point;
use crate::scene::spec::Mark;

/// The sketch's extent over this is the distance a trail keeps to the
/// curve: the sketch panel keeps its aspect, so a cell is at least the
/// longer extent over the panel's cells along it, and a panel up to 512
/// cells across draws the trail within a cell of the solution.
pub const RESOLUTION: f64 = 512.0;

/// Most halvings of one interval between samples.
pub(crate) const MAX_DEPTH: u32 = 5;

/// Most points dropped in a row.
const MAX_SKIPPED: usize = 64;

/// Most points a trail keeps.
pub const TRAIL_LEN: usize = 4096;

/// A trail as drawn; see the module's documentation.
#[derive(Debug, Clone)]
pub(crate) struct Trail {
    /// The index of each trail's x among the sketch's coordinates (its y
    /// follows).
    pairs: Vec<usize>,
    /// The points kept; the last is always the latest sample.
    points: Vec<Point>,
    /// The points dropped since the last one kept before the latest, and
    /// the room of those let go ([`Trail::point`]).
    skipped: Vec<Point>,
    spare: Vec<Point>,
    /// The chords from that point that keep them all ([`Cone`]), and
    /// room for the next (so a sample allocates nothing).
    cone: Cone,
    next: Cone,
    /// The least distance kept to the curve: raised when the trail outgrew
    /// [`TRAIL_LEN`] points.
    floor: f64,
    /// The two samples before the latest, oldest first (for the curvature).
    recent: Vec<Point>,
}

impl Trail {
    pub(crate) fn new(sketch: &[Mark]) -> Trail {
        let mut pairs = Vec::new();
        let mut k = 0;
        for m in sketch {
            if matches!(m, Mark::Trail(_)) {
                pairs.push(k);
            }
            k += m.exprs().len();
        }
        Trail {
            pairs,
            points: Vec::new(),
            skipped: Vec::new(),
            spare: Vec::new(),
            cone: Cone::new(0.0, 0),
            next: Cone::new(0.0, 0),
            floor: 0.0,
            recent: Vec::new(),
        }
    }

    /// A point at `t` with `values`, in the room of one let go if there is
    /// one.
    pub(crate) fn point(&mut self, t: f64, values: &[f64]) -> Point {
        match self.spare.pop() {
            Some(mut p) => {
                p.t = t;
                p.values.clear();
                p.values.extend_from_slice(values);
                p
            }
            None => Point {
                t,
                values: values.to_vec(),
            },
        }
    }

    pub(crate) fn points(&self) -> &[Point] {
        &self.points
    }

    /// The longer side of the largest trail's extent, from `extent` of
    /// each sketch coordinate (its index among them).
    pub(crate) fn span(&self, extent: impl Fn(usize) -> Option<(f64, f64)>) -> f64 {
        let side = |k: usize| extent(k).map_or(0.0, |(lo, hi)| hi - lo);
        (self.pairs.iter())
            .map(|&k| side(k).max(side(k + 1)))
            .fold(0.0, f64::max)
    }

    /// The distance kept to the curve, for a sketch of `span`.
    fn tolerance(&self, span: f64) -> f64 {
        (span / RESOLUTION).max(self.floor)
    }

    /// Takes the sample `p`; `span` is the trail's extent so far
    /// ([`Trail::span`]) and `between(t)` the sketch's coordinates at a time
    /// between the last sample and `p` on the dense output (None where it
    /// has none or they are not finite).
    pub(crate) fn add(
        &mut self,
        p: Point,
        span: f64,
        mut between: impl FnMut(f64) -> Option<Vec<f64>>,
    ) {
        let eps = self.tolerance(span);
        if let [a, b] = &self.recent[..]
            && self.stray(a, b, &p) > 0.25 * eps
        {
            let mut found = Vec::new();
            let b = b.clone();
            self.refine(&b, &p, eps, MAX_DEPTH, &mut between, &mut found);
            for q in found {
                self.keep(q, eps);
            }
        }
        if self.recent.len() < 2 {
            self.recent.push(p.clone());
        } else {
            // The oldest's room for the newest.
            self.recent.rotate_left(1);
            let last = &mut self.recent[1];
            last.t = p.t;
            last.values.clone_from(&p.values);
        }
        self.keep(p, eps);
        let mut eps = eps;
        while self.points.len() > TRAIL_LEN {
            eps *= 2.0;
            self.floor = eps;
            let all = std::mem::take(&mut self.points);
            self.skipped.clear();
            self.cone.reset(eps, self.pairs.len());
            for q in all {
                self.keep(q, eps);
            }
        }
    }

    /// How far the chord from `b` to `p` strays from the curve through
    /// `a`, `b`, `p`, estimated from its curvature (the second divided
    /// difference): |c''| h² / 8.
    fn stray(&self, a: &Point, b: &Point, p: &Point) -> f64 {
        let (h0, h1) = (b.t - a.t, p.t - b.t);
        if !(h0 > 0.0 && h1 > 0.0) {
            return 0.0;
        }
        let mut worst = 0.0f64;
        for &k in &self.pairs {
            let second = |j: usize| {
                let slope0 = (b.values[j] - a.values[j]) / h0;
                let slope1 = (p.values[j] - b.values[j]) / h1;
                2.0 * (slope1 - slope0) / (h0 + h1)
            };
            let c2 = second(k).hypot(second(k + 1));
            worst = worst.max(c2 * h1 * h1 / 8.0);
        }
        if worst.is_nan() { 0.0 } else { worst }
    }

    /// The points of the curve between `a` and `b` (in time order, ends
    /// left out) that keep the chords within `eps` of their midpoints,
    /// halving at most `depth` more times.
    fn refine(
        &self,
        a: &Point,
        b: &Point,
        eps: f64,
        depth: u32,
        between: &mut impl FnMut(f64) -> Option<Vec<f64>>,
        out: &mut Vec<Point>,
    ) {
        let t = 0.5 * (a.t + b.t);
        if depth == 0 || !(t > a.t && t < b.t) {
            return;
        }
        let Some(values) = between(t) else {
            return;
        };
        let m = Point { t, values };
        if self.off(&m, a, b) <= eps {
            return;
        }
        self.refine(a, &m, eps, depth - 1, between, out);
        let m2 = m.clone();
        out.push(m);
        self.refine(&m2, b, eps, depth - 1, between, out);
    }

    /// The largest distance of `p` from the segment `a`–`b`, over the
    /// trails.
    fn off(&self, p: &Point, a: &Point, b: &Point) -> f64 {
        let mut worst = 0.0f64;
        for &k in &self.pairs {
            let at = |q: &Point| (q.values[k], q.values[k + 1]);
            worst = worst.max(to_segment(at(p), at(a), at(b)));
        }
        worst
    }

    /// Appends `p`, dropping the latest point when the chord that would
    /// replace it keeps every point dropped since the last kept within
    /// `eps`.
    fn keep(&mut self, p: Point, eps: f64) {
        let n = self.points.len();
        if n < 2 {
            self.points.push(p);
            return;
        }
        let anchor = &self.points[n - 2];
        let latest = &self.points[n - 1];
        if self.cone.eps != eps {
            // The distance changed: the cone of the points dropped so far
            // for the new one.
            self.cone.reset(eps, self.pairs.len());
            for q in &self.skipped {
                self.cone.add(&self.pairs, anchor, q);
            }
        }
        self.next.clone_from(&self.cone);
        self.next.add(&self.pairs, anchor, latest);
        let fits = self.skipped.len() < MAX_SKIPPED
            && (self.next.keeps(&self.pairs, anchor, &p)
                || (self.off(latest, anchor, &p) <= eps
                    && (self.skipped.iter()).all(|q| self.off(q, anchor, &p) <= eps)));
        if fits {
            let latest = self.points.pop().expect("two points");
            self.skipped.push(latest);
            std::mem::swap(&mut self.cone, &mut self.next);
        } else {
            if self.spare.len() < MAX_SKIPPED {
                self.spare.append(&mut self.skipped);
            }
            self.skipped.clear();
            self.cone.reset(eps, self.pairs.len());
        }
        self.points.push(p);
    }
}

/// The chords from a trail's anchor (its last point kept) that pass within
/// `eps` of every point dropped since: for each trail, the directions from
/// the anchor within asin(eps/d) of each dropped point's (d its distance
/// from the anchor), and the farthest of them. A chord in every such
/// interval that reaches at least that far keeps each dropped point
/// within `eps`: the point projects onto the chord (the angle between them
/// is under a right angle, and the chord is the longer), and its distance
/// from the chord's line is d·sin of that angle. The directions are kept
/// as the tangents of their angles from the first bounding one (within a
/// right angle of it, where the tangent is monotone), so no trigonometry
/// is done; an interval that reaches past a right angle is cut there, and
/// a point beyond one empties the cone (every chord is then measured),
/// both on the safe side. The intervals are narrowed by a billionth so
/// rounding never lets through a chord the direct measurement would
/// refuse.
#[derive(Debug)]
struct Cone {
    eps: f64,
    arcs: Vec<Arc>,
    /// Some dropped point is within `eps` of no chord known here (then
    /// every chord is measured).
    empty: bool,
}

/// One trail's directions in a [`Cone`].
#[derive(Debug, Clone, Copy)]
struct Arc {
    /// The first direction that bounds it (a unit vector), None while every
    /// dropped point is within `eps` of the anchor; the tangents of the
    /// interval's ends' angles from it.
    dir: Option<(f64, f64)>,
    lo: f64,
    hi: f64,
    /// The farthest dropped point's distance from the anchor.
    reach: f64,
}

impl Clone for Cone {
    fn clone(&self) -> Cone {
        Cone {
            eps: self.eps,
            arcs: self.arcs.clone(),
            empty: self.empty,
        }
    }

    /// Into the room `self` has (a sample allocates nothing).
    fn clone_from(&mut self, from: &Cone) {
        self.eps = from.eps;
        self.arcs.clone_from(&from.arcs);
        self.empty = from.empty;
    }
}

impl Cone {
    fn new(eps: f64, pairs: usize) -> Cone {
        let mut cone = Cone {
            eps,
            arcs: Vec::new(),
            empty: false,
        };
        cone.reset(eps, pairs);
        cone
    }

    /// No point dropped, for the distance `eps`.
    fn reset(&mut self, eps: f64, pairs: usize) {
        let arc = Arc {
            dir: None,
            lo: f64::NEG_INFINITY,
            hi: f64::INFINITY,
            reach: 0.0,
        };
        self.eps = eps;
        self.arcs.clear();
        self.arcs.resize(pairs, arc);
        self.empty = false;
    }

    /// Narrows the cone to the chords that keep `q` too (empty when none
    /// does, or none is known to).
    fn add(&mut self, pairs: &[usize], anchor: &Point, q: &Point) {
        if self.empty {
            return;
        }
        let eps = self.eps * (1.0 - 1e-9);
        for (arc, &k) in self.arcs.iter_mut().zip(pairs) {
            let (dx, dy) = (
                q.values[k] - anchor.values[k],
                q.values[k + 1] - anchor.values[k + 1],
            );
            let d = (dx * dx + dy * dy).sqrt();
            if d.is_nan() {
                self.empty = true;
                return;
            }
            arc.reach = arc.reach.max(d);
            if d <= eps {
                continue;
            }
            // tan of the half-width asin(eps/d).
            let w = eps / (d * d - eps * eps).sqrt();
            let (ux, uy) = *arc.dir.get_or_insert((dx / d, dy / d));
            let (along, across) = (ux * dx + uy * dy, ux * dy - uy * dx);
            if !(along > 0.0 && w.is_finite()) {
                self.empty = true;
                return;
            }
            let tq = across / along;
            // tan(θq ± half), or past a right angle on that side.
            let up = 1.0 - tq * w;
            let hi = if up > 0.0 {
                (tq + w) / up
            } else {
                f64::INFINITY
            };
            let down = 1.0 + tq * w;
            let lo = if down > 0.0 {
                (tq - w) / down
            } else {
                f64::NEG_INFINITY
            };
            arc.lo = arc.lo.max(lo);
            arc.hi = arc.hi.min(hi);
            if arc.lo > arc.hi {
                self.empty = true;
                return;
            }
        }
    }

    /// The chord from `anchor` to `p` keeps every dropped point within
    /// `eps` (false: not known without measuring).
    fn keeps(&self, pairs: &[usize], anchor: &Point, p: &Point) -> bool {
        !self.empty
            && self.arcs.iter().zip(pairs).all(|(arc, &k)| {
                let (dx, dy) = (
                    p.values[k] - anchor.values[k],
                    p.values[k + 1] - anchor.values[k + 1],
                );
                let d = (dx * dx + dy * dy).sqrt();
                if !(d >= arc.reach && d > 0.0) {
                    return false;
                }
                match arc.dir {
                    None => true,
                    Some((ux, uy)) => {
                        let (along, across) = (ux * dx + uy * dy, ux * dy - uy * dx);
                        along > 0.0 && {
                            let t = across / along;
                            arc.lo <= t && t <= arc.hi
                        }
                    }
                }
            })
    }
}

/// The distance from `p` to the segment from `a` to `b` (NaN counts as
/// far).
pub(super) fn to_segment(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len2 = dx * dx + dy * dy;
    let s = if len2 > 0.0 {
        (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let d = (p.0 - a.0 - s * dx).hypot(p.1 - a.1 - s * dy);
    if d.is_nan() { f64::INFINITY } else { d }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn trail() -> Trail {
        Trail::new(&[Mark::Trail(["x".into(), "y".into()])])
    }

    fn at(t: f64) -> Point {
        Point {
            t,
            values: vec![t.cos(), t.sin()],
        }
    }

    /// A circle sampled every quarter turn is drawn round: the dense output
    /// fills each quarter until every chord is within the resolution, and
    /// a straight run is thinned to its ends.
    #[test]
    fn a_coarsely_sampled_circle_is_followed_and_a_line_thinned() {
        let mut tr = trail();
        let quarter = std::f64::consts::FRAC_PI_2;
        for k in 0..=8 {
            let t = k as f64 * quarter;
            tr.add(at(t), 2.0, |t| Some(at(t).values));
        }
        let pts = tr.points();
        let eps = 2.0 / RESOLUTION;
        // Every chord's midpoint on the circle's radius within eps, after
        // the first half turn (sampled at 3 points: no curvature known
        // before the third).
        for w in pts.windows(2).filter(|w| w[0].t >= 2.0 * quarter) {
            let mid = 0.5 * (w[0].t + w[1].t);
            let d = 1.0 - (mid - w[0].t).cos();
            assert!(d <= 2.0 * eps, "chord {}..{} strays {d}", w[0].t, w[1].t);
        }
        assert!(pts.len() > 20, "{}", pts.len());

        let mut line = trail();
        for k in 0..100 {
            let t = k as f64;
            line.add(
                Point {
                    t,
                    values: vec![t, 2.0 * t],
                },
                100.0,
                |_| None,
            );
        }
        let pts = line.points();
        assert_eq!(pts.len(), 3, "{pts:?}");
        assert_eq!(pts.last().unwrap().t, 99.0);
    }

    /// A dense output that zigzags at every halving costs at most
    /// 2^MAX_DEPTH − 1 evaluations an interval, and the trail stays within
    /// its length.
    #[test]
    fn a_hostile_curve_costs_bounded_work() {
        let mut tr = trail();
        let mut calls = 0usize;
        let mut most = 0;
        // Noise: every midpoint is off its chord.
        let zig = |t: f64| vec![t, ((t * 12.9898).sin() * 43758.5453).fract().abs() * 50.0];
        for k in 0..5000 {
            let t = k as f64;
            let before = calls;
            let y = if k % 2 == 0 { 0.0 } else { 50.0 };
            tr.add(
                Point {
                    t,
                    values: vec![t, y],
                },
                100.0,
                |s| {
                    calls += 1;
                    Some(zig(s))
                },
            );
            most = most.max(calls - before);
        }
        assert!(
            most < 1 << MAX_DEPTH && most > 1 << (MAX_DEPTH - 1),
            "{most}"
        );
        assert!(tr.points().len() <= TRAIL_LEN);
        assert_eq!(tr.points().last().unwrap().t, 4999.0);
    }
}
