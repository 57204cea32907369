//! Geometric splitting: H = L₁²/2I₁ + L₂²/2I₂ + L₃²/2I₃ is split into its
//! three terms, each the Hamiltonian of a rotation about one body axis, which
//! is solved exactly.
//!
//! Under the term of axis i alone, Lᵢ is constant and ω = (Lᵢ/Iᵢ)eᵢ, so the
//! body-frame L turns about eᵢ by −Lᵢh/Iᵢ and the orientation by the opposite
//! turn, q ← q ⊗ exp(½ (Lᵢh/Iᵢ) eᵢ). Every sub-flow is a rotation, so |L|, |q|
//! and the space-frame L = q L q⁻¹ are kept to rounding (q is rescaled once
//! per step so that roundings cannot add up), and the composition is a
//! Poisson map: the energy error stays bounded instead of drifting.
//!
//! Strang splitting applies a–b–c–b–a with half steps on a and b, which is
//! 2nd order; Suzuki's 5-stage symmetric composition of it (steps p, p,
//! 1 − 4p, p, p with p = 1/(4 − 4^⅓)) is 4th order. Adjacent half-flows about
//! the same axis commute and are merged, so a Strang step costs five
//! rotations and the composition twenty-one.

use nalgebra::{Quaternion, UnitQuaternion, Vector3};

use crate::rigid::model::{Body, State};
use crate::rigid::trig;
use crate::solvers::Method;
use crate::solvers::budget::Budget;
use crate::solvers::fixed::{FixedSteps, StepRule};
use crate::solvers::ode::Work;

/// Which composition of the Strang step to use.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Scheme {
    /// 2nd order.
    Strang,
    /// 4th order, Suzuki's 5-stage composition.
    Suzuki,
}

/// Rotations in one step: at most 5 Strang stages × 5 flows, less merges.
const MAX_FLOWS: usize = 25;

/// One step as a sequence of exact axis rotations, (axis, fraction of dt).
#[derive(Debug, Clone, Copy)]
struct Sequence {
    flows: [(usize, f64); MAX_FLOWS],
    len: usize,
}

impl Sequence {
    fn new(order: [usize; 3], scheme: Scheme) -> Sequence {
        let gammas: &[f64] = match scheme {
            Scheme::Strang => &[1.0],
            Scheme::Suzuki => {
                let p = 1.0 / (4.0 - 4f64.cbrt());
                &[p, p, 1.0 - 4.0 * p, p, p][..]
            }
        };
        let [a, b, c] = order;
        let mut seq = Sequence {
            flows: [(0, 0.0); MAX_FLOWS],
            len: 0,
        };
        for &g in gammas {
            for (axis, fraction) in [(a, 0.5), (b, 0.5), (c, 1.0), (b, 0.5), (a, 0.5)] {
                seq.push(axis, g * fraction);
            }
        }
        seq
    }

    fn push(&mut self, axis: usize, fraction: f64) {
        if self.len > 0 && self.flows[self.len - 1].0 == axis {
            self.flows[self.len - 1].1 += fraction;
        } else {
            self.flows[self.len] = (axis, fraction);
            self.len += 1;
        }
    }

    fn flows(&self) -> &[(usize, f64)] {
        &self.flows[..self.len]
    }
}

/// The order of the axes in a–b–c–b–a: smallest moment innermost, largest
/// outermost (the arrangement with the smallest error on flipping bodies).
fn axis_order(inertia: &Vector3<f64>) -> [usize; 3] {
    let mut axes = [0usize, 1, 2];
    axes.sort_by(|&i, &j| inertia[j].total_cmp(&inertia[i]));
    axes
}

/// Body-frame L, then q = (w, x, y, z) when the run carries it.
pub(crate) type Point = [f64; 7];

/// A splitting run: the shared fixed-step driver over [`SplittingSteps`].
pub(crate) type Splitting = FixedSteps<SplittingSteps>;

pub(crate) struct SplittingSteps {
    inertia: [f64; 3],
    inverse: [f64; 3],
    scheme: Scheme,
    sequence: Sequence,
    orientation: bool,
    dt: f64,
    /// The start exactly as given (L/I need not give back ω bit for bit).
    omega0: Vector3<f64>,
    start: Point,
}

/// A splitting run from `omega0` with step `dt`, carrying q when
/// `orientation`; the a–b–c–b–a axes put the smallest moment innermost.
pub(crate) fn splitting(
    body: &Body,
    omega0: &Vector3<f64>,
    dt: f64,
    scheme: Scheme,
    orientation: bool,
    budget: Budget,
) -> Splitting {
    // The flows depend on the moments only through L/I, so the moments
    // are taken relative to the largest (a power of two, exact): 1/I
    // cannot overflow for tiny moments, nor L = Iω underflow.
    let unit = body
        .inertia
        .max()
        .log2()
        .floor()
        .clamp(-1074.0, 1023.0)
        .exp2();
    let inertia = body.inertia / unit;
    let l = inertia.component_mul(omega0);
    let steps = SplittingSteps {
        inertia: [inertia[0], inertia[1], inertia[2]],
        inverse: [1.0 / inertia[0], 1.0 / inertia[1], 1.0 / inertia[2]],
        scheme,
        sequence: Sequence::new(axis_order(&body.inertia), scheme),
        orientation,
        dt,
        omega0: *omega0,
        start: [l[0], l[1], l[2], 1.0, 0.0, 0.0, 0.0],
    };
    FixedSteps::new(steps, dt, budget)
}

impl StepRule for SplittingSteps {
    type Point = Point;

    fn method(&self) -> Method {
        match self.scheme {
            Scheme::Strang => Method::Splitting { dt: self.dt },
            Scheme::Suzuki => Method::Splitting4 { dt: self.dt },
        }
    }

    fn size(&self) -> usize {
        if self.orientation { 7 } else { 3 }
    }

    fn start(&self) -> Point {
        self.start
    }

    fn step(&self, p: &mut Point, h: f64, work: &mut Work) {
        let q = self.orientation;
        for &(axis, fraction) in self.sequence.flows() {
            rotate(p, q, axis, p[axis] * self.inverse[axis] * fraction * h);
        }
        // Each turn keeps |q| only to rounding, and with nearly equal angles
        // step after step the roundings line up into a drift; rescaling q
        // (the same rotation) keeps |q| = 1 to an ulp for any run length.
        if q {
            let q = &mut p[3..];
            let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
            for v in q.iter_mut() {
                *v /= n;
            }
        }
        // One evaluation of the field per rotation: the comparable unit of work.
        work.rhs_evals += self.sequence.len as u64;
    }

    fn state(&self, p: &[f64]) -> State {
        let omega = Vector3::new(
            p[0] / self.inertia[0],
            p[1] / self.inertia[1],
            p[2] / self.inertia[2],
        );
        State {
            omega,
            q: match p {
                [_, _, _, w, x, y, z] => {
                    UnitQuaternion::new_unchecked(Quaternion::new(*w, *x, *y, *z))
                }
                _ => UnitQuaternion::identity(),
            },
        }
    }

    fn initial(&self) -> State {
        State::new(self.omega0)
    }
}

/// The exact flow of Lᵢ²/2Iᵢ for a body angle `angle` = Lᵢh/Iᵢ: L turns by
/// −angle about eᵢ, and q by +angle (so q L q⁻¹ is unchanged).
#[inline(always)]
fn rotate(p: &mut Point, orientation: bool, i: usize, angle: f64) {
    let (j, k) = ((i + 1) % 3, (i + 2) % 3);
    let (lj, lk) = (p[j], p[k]);
    match orientation {
        false => {
            let (s, c) = trig::sin_cos(angle);
            p[j] = c * lj + s * lk;
            p[k] = c * lk - s * lj;
        }
        true => {
            let (sh, ch) = trig::sin_cos(0.5 * angle);
            let (s, c) = (2.0 * sh * ch, 1.0 - 2.0 * sh * sh);
            p[j] = c * lj + s * lk;
            p[k] = c * lk - s * lj;
            let q = &mut p[3..];
            // q ⊗ (cos ½θ, sin ½θ eᵢ), written in the cyclic frame (i, j, k).
            let w = q[0];
            let (vi, vj, vk) = (q[1 + i], q[1 + j], q[1 + k]);
            q[0] = ch * w - sh * vi;
            q[1 + i] = ch * vi + sh * w;
            q[1 + j] = ch * vj + sh * vk;
            q[1 + k] = ch * vk - sh * vj;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn merged_sequences_have_the_expected_length_and_total() {
        for (scheme, len) in [(Scheme::Strang, 5), (Scheme::Suzuki, 21)] {
            let seq = Sequence::new([2, 1, 0], scheme);
            assert_eq!(seq.len, len);
            // Each axis gets exactly one full step in total.
            for axis in 0..3 {
                let total: f64 = seq
                    .flows()
                    .iter()
                    .filter(|f| f.0 == axis)
                    .map(|f| f.1)
                    .sum();
                assert!(
                    (total - 1.0).abs() < 1e-14,
                    "{scheme:?} axis {axis}: {total}"
                );
            }
        }
    }

    #[test]
    fn one_rotation_matches_the_sub_flow() {
        // Flow of L₃²/2I₃: L̇ = L × (L₃/I₃)e₃, q̇ = ½ q ⊗ (0, (L₃/I₃)e₃).
        let mut p: Point = [1.0, 2.0, 3.0, 1.0, 0.0, 0.0, 0.0];
        let theta = 0.7;
        rotate(&mut p, true, 2, theta);
        let (s, c) = theta.sin_cos();
        let expected = [c * 1.0 + s * 2.0, c * 2.0 - s * 1.0, 3.0];
        for (got, want) in p[..3].iter().zip(&expected) {
            assert!((got - want).abs() < 1e-15);
        }
        let q = &p[3..];
        let want = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), theta);
        assert!((q[0] - want.w).abs() < 1e-15 && (q[3] - want.k).abs() < 1e-15);
        // Space-frame L unchanged.
        let uq = UnitQuaternion::new_unchecked(Quaternion::new(q[0], q[1], q[2], q[3]));
        let l_space = uq * Vector3::new(p[0], p[1], p[2]);
        assert!((l_space - Vector3::new(1.0, 2.0, 3.0)).norm() < 1e-14);
    }
}
