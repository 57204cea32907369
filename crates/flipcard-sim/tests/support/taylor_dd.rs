//! An independent reference for the rigid body: a high-order Taylor series
//! integrator of Euler's equations and q̇ = ½ q ⊗ (0, ω) in double-double
//! arithmetic (~32 digits). It shares nothing with the solvers under test:
//! the Taylor coefficients come from Cauchy products of the quadratic
//! right-hand side, and the step size from the decay of those coefficients.

#![allow(dead_code)]

use std::ops::{Add, Mul, Neg, Sub};

/// An unevaluated sum hi + lo with |lo| ≤ ulp(hi)/2.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dd {
    pub hi: f64,
    pub lo: f64,
}

fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

fn quick_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    (s, b - (s - a))
}

impl Dd {
    pub const ZERO: Dd = Dd { hi: 0.0, lo: 0.0 };

    pub fn new(x: f64) -> Dd {
        Dd { hi: x, lo: 0.0 }
    }

    pub fn to_f64(self) -> f64 {
        self.hi + self.lo
    }

    pub fn div(self, y: Dd) -> Dd {
        let q1 = self.hi / y.hi;
        let r = self - y * Dd::new(q1);
        let q2 = r.hi / y.hi;
        let r = r - y * Dd::new(q2);
        let q3 = r.hi / y.hi;
        let (s, e) = quick_two_sum(q1, q2);
        Dd { hi: s, lo: e } + Dd::new(q3)
    }

    pub fn abs(self) -> f64 {
        self.hi.abs()
    }
}

impl Add for Dd {
    type Output = Dd;
    fn add(self, y: Dd) -> Dd {
        let (s1, s2) = two_sum(self.hi, y.hi);
        let (t1, t2) = two_sum(self.lo, y.lo);
        let (s1, s2) = quick_two_sum(s1, s2 + t1);
        let (hi, lo) = quick_two_sum(s1, s2 + t2);
        Dd { hi, lo }
    }
}

impl Neg for Dd {
    type Output = Dd;
    fn neg(self) -> Dd {
        Dd {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
}

impl Sub for Dd {
    type Output = Dd;
    fn sub(self, y: Dd) -> Dd {
        self + (-y)
    }
}

impl Mul for Dd {
    type Output = Dd;
    fn mul(self, y: Dd) -> Dd {
        let p = self.hi * y.hi;
        let e = self.hi.mul_add(y.hi, -p);
        let e = e + (self.hi * y.lo + self.lo * y.hi);
        let (hi, lo) = quick_two_sum(p, e);
        Dd { hi, lo }
    }
}

/// Taylor order; with the step chosen so the last terms are below 1e-32.
const ORDER: usize = 28;
const TOLERANCE: f64 = 1e-32;

/// ω and q at the requested times (which must be non-decreasing and ≥ 0),
/// starting from ω₀ and q = 1 at t = 0, as (ω, [w, x, y, z]) in f64.
pub fn integrate(inertia: [f64; 3], omega0: [f64; 3], times: &[f64]) -> Vec<([f64; 3], [f64; 4])> {
    let inertia = inertia.map(Dd::new);
    // ω̇ᵢ = cᵢ ω_a ω_b with (a, b) the next two axes cyclically.
    let coef: [Dd; 3] = std::array::from_fn(|i| {
        let (a, b) = ((i + 1) % 3, (i + 2) % 3);
        (inertia[a] - inertia[b]).div(inertia[i])
    });
    let mut omega = omega0.map(Dd::new);
    let mut q = [Dd::new(1.0), Dd::ZERO, Dd::ZERO, Dd::ZERO];
    let mut t = Dd::ZERO;
    let mut out = Vec::with_capacity(times.len());
    let mut next = 0;
    while next < times.len() {
        let (w, qc) = coefficients(&coef, omega, q);
        let h = step_size(&w, &qc);
        let t_end = t + Dd::new(h);
        while next < times.len() && (Dd::new(times[next]) - t_end).hi <= 0.0 {
            let dt = (Dd::new(times[next]) - t).to_f64();
            let (we, qe) = evaluate(&w, &qc, dt);
            out.push((we.map(Dd::to_f64), qe.map(Dd::to_f64)));
            next += 1;
        }
        let (we, qe) = evaluate(&w, &qc, h);
        omega = we;
        q = qe;
        t = t_end;
    }
    out
}

type Series3 = Vec<[Dd; 3]>;
type Series4 = Vec<[Dd; 4]>;

fn coefficients(coef: &[Dd; 3], omega: [Dd; 3], q: [Dd; 4]) -> (Series3, Series4) {
    let mut w: Series3 = vec![[Dd::ZERO; 3]; ORDER + 1];
    let mut qc: Series4 = vec![[Dd::ZERO; 4]; ORDER + 1];
    w[0] = omega;
    qc[0] = q;
    for k in 0..ORDER {
        let inv = Dd::new(1.0).div(Dd::new((k + 1) as f64));
        for i in 0..3 {
            let (a, b) = ((i + 1) % 3, (i + 2) % 3);
            let mut s = Dd::ZERO;
            for l in 0..=k {
                s = s + w[l][a] * w[k - l][b];
            }
            w[k + 1][i] = coef[i] * s * inv;
        }
        // q ⊗ (0, ω) = (−q⃗·ω, q₀ω + q⃗ × ω)
        let mut s = [Dd::ZERO; 4];
        for l in 0..=k {
            let [q0, q1, q2, q3] = qc[l];
            let [w1, w2, w3] = w[k - l];
            s[0] = s[0] - (q1 * w1 + q2 * w2 + q3 * w3);
            s[1] = s[1] + q0 * w1 + (q2 * w3 - q3 * w2);
            s[2] = s[2] + q0 * w2 + (q3 * w1 - q1 * w3);
            s[3] = s[3] + q0 * w3 + (q1 * w2 - q2 * w1);
        }
        let half = inv * Dd::new(0.5);
        qc[k + 1] = s.map(|v| v * half);
    }
    (w, qc)
}

/// The step at which the last two terms of the series fall below the
/// tolerance relative to the size of the solution.
fn step_size(w: &Series3, qc: &Series4) -> f64 {
    let size = w[0].iter().map(|v| v.abs()).fold(1e-300, f64::max).max(1.0);
    let mut h = f64::INFINITY;
    for k in [ORDER - 1, ORDER] {
        let cw = w[k].iter().map(|v| v.abs()).fold(0.0, f64::max) / size;
        let cq = qc[k].iter().map(|v| v.abs()).fold(0.0, f64::max);
        let c = cw.max(cq);
        if c > 0.0 {
            h = h.min((TOLERANCE / c).powf(1.0 / k as f64));
        }
    }
    0.7 * h.min(1e6)
}

fn evaluate(w: &Series3, qc: &Series4, dt: f64) -> ([Dd; 3], [Dd; 4]) {
    let h = Dd::new(dt);
    let mut we = w[ORDER];
    let mut qe = qc[ORDER];
    for k in (0..ORDER).rev() {
        for i in 0..3 {
            we[i] = we[i] * h + w[k][i];
        }
        for i in 0..4 {
            qe[i] = qe[i] * h + qc[k][i];
        }
    }
    (we, qe)
}
