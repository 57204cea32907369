//! The exact motion of the torque-free rigid body: ω(t) from Jacobi elliptic
//! functions and q(t) in closed form with the third-kind integral Π. It is
//! the reference for every error figure of the other solvers.
//!
//! The user's axes may come in any order. Internally they are permuted so
//! that axis 3 is the one ω circulates about (largest moment when
//! L² > 2T I_mid, smallest when L² < 2T I_mid), with one axis reversed for
//! odd permutations so the internal frame stays right-handed (`frame`).
//! Moments and ω are rescaled by powers of two (exact) so nothing overflows;
//! components of ω₀ below 2^-500 of the largest are dropped, since their
//! squares would underflow beside the others.
//!
//! Regimes: rest and steady spin (ω an eigenvector of I: a sphere, a spin
//! along any principal axis including the unstable middle one, or a spin in
//! the degenerate plane of a symmetric body) keep ω constant; exactly
//! symmetric bodies use sin/cos; exactly on the separatrix (D₂ = 0) tanh and
//! sech; every other case the elliptic functions with m_c computed directly
//! from inertia differences (`orbit`). Orientation: `attitude`.
//!
//! Accuracy (crates/flipcard-sim/tests/sim_exact.rs, against a 32-digit Taylor integration):
//! ω and q within a few 1e-16 · (1 + λt) across all regimes, including
//! needles of inertia ratio 1e6, bodies symmetric to 1e-12 and orbits within
//! 1e-12 of the separatrix.

mod attitude;
mod frame;
mod orbit;

use crate::error::SolveError;
use std::sync::OnceLock;

use nalgebra::{Quaternion, UnitQuaternion, Vector3};

use crate::rigid::model::{self, Body, State};
use crate::rigid::solver::{Method, Needs, Solver, Work};
use attitude::Attitude;
use flipcard_text::num::Num;
use frame::Frame;
use orbit::{Orbit, Shape};

/// What kind of motion a body and initial ω make. Axis numbers are 0-based
/// indices into the moments as the user gave them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Regime {
    /// ω = 0.
    Rest,
    /// ω along a principal axis (for a sphere, any ω): ω never changes and
    /// the body turns uniformly about it. Includes the unstable middle axis,
    /// where the exact motion is an equilibrium.
    Steady,
    /// Exactly two equal moments: ω precesses uniformly about `axis`, the
    /// symmetry axis.
    SymmetricTop { axis: usize },
    /// ω circulates about `axis`, the axis of largest or smallest moment,
    /// and the middle-axis component of ω reverses every half period.
    Circulation { axis: usize },
    /// Exactly on the separatrix (L² = 2T I_mid): ω creeps towards the
    /// middle axis `middle` for ever and never flips.
    Separatrix { middle: usize },
}

// One per solver, read on every evaluation: boxing the large variant
// would only add an indirection.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone)]
enum Motion {
    Steady,
    Moving {
        frame: Frame,
        /// ω scale (a power of two): internal ω̂ = ω / scale.
        scale: f64,
        orbit: Orbit,
    },
}

/// The exact solver. Cheap to evaluate at any t, in any order.
#[derive(Debug, Clone)]
pub struct Exact {
    body: Body,
    omega0: Vector3<f64>,
    needs: Needs,
    motion: Motion,
    /// Orientation constants, built at construction when `needs.orientation`
    /// and otherwise on the first call to [`Exact::state_at`].
    attitude: OnceLock<Attitude>,
}

impl Exact {
    /// Validates the body and ω₀ and sets up the closed form.
    pub fn new(body: Body, omega0: Vector3<f64>, needs: Needs) -> Result<Exact, SolveError> {
        let body = Body::new([body.inertia[0], body.inertia[1], body.inertia[2]])?;
        let omega0 = model::omega([omega0[0], omega0[1], omega0[2]])?;
        let motion = Motion::new(&body.inertia, &omega0);
        let exact = Exact {
            body,
            omega0,
            needs,
            motion,
            attitude: OnceLock::new(),
        };
        if let (true, Motion::Moving { scale, orbit, .. }) = (needs.orientation, &exact.motion) {
            exact.attitude(orbit, *scale);
        }
        Ok(exact)
    }

    pub fn body(&self) -> &Body {
        &self.body
    }

    pub fn omega0(&self) -> Vector3<f64> {
        self.omega0
    }

    pub fn regime(&self) -> Regime {
        match &self.motion {
            Motion::Steady if self.omega0 == Vector3::zeros() => Regime::Rest,
            Motion::Steady => Regime::Steady,
            Motion::Moving { frame, orbit, .. } => match orbit.shape {
                Shape::Circular => Regime::SymmetricTop {
                    axis: frame.user_axis(2),
                },
                Shape::Elliptic { .. } => Regime::Circulation {
                    axis: frame.user_axis(2),
                },
                Shape::Separatrix => Regime::Separatrix {
                    middle: frame.user_axis(1),
                },
            },
        }
    }

    /// λ, the rate of the elliptic phase u = u₀ + λt (rad/s; 0 when steady).
    /// Errors are judged relative to 1 + λt.
    pub fn rate(&self) -> f64 {
        match &self.motion {
            Motion::Steady => 0.0,
            Motion::Moving { orbit, .. } => orbit.rate,
        }
    }

    /// The parameter (m, m_c) of the elliptic functions: (0, 1) for a
    /// symmetric top, (1, 0) on the separatrix, None when steady.
    pub fn parameter(&self) -> Option<(f64, f64)> {
        match &self.motion {
            Motion::Steady => None,
            Motion::Moving { orbit, .. } => Some(orbit.parameter()),
        }
    }

    /// The period of ω(t): 4K(m)/λ (2π/λ for a symmetric top). None when ω
    /// is constant or on the separatrix.
    pub fn period(&self) -> Option<f64> {
        self.quarter_period().map(|quarter| 4.0 * quarter)
    }

    /// The time between successive reversals of the middle-axis component of
    /// ω: 2K(m)/λ, half the period. Only for an asymmetric body circulating
    /// about an extreme axis (the flips of the tennis-racket effect).
    pub fn flip_interval(&self) -> Option<f64> {
        match self.regime() {
            Regime::Circulation { .. } => self.quarter_period().map(|quarter| 2.0 * quarter),
            _ => None,
        }
    }

    /// For a body with exactly two equal moments I⊥ and symmetry axis s:
    /// Ω = (I_s − I⊥) ω_s / I⊥, the rate at which ω (and L) turn about the
    /// symmetry axis in the body frame (dω/dt = Ω e_s × ω). None otherwise.
    #[cfg(test)]
    pub(crate) fn precession_rate(&self) -> Option<f64> {
        let i = self.body.inertia;
        let axis = (0..3).find(|&k| i[(k + 1) % 3] == i[(k + 2) % 3] && i[k] != i[(k + 1) % 3])?;
        let perp = i[(axis + 1) % 3];
        Some((i[axis] - perp) * self.omega0[axis] / perp)
    }

    /// Whether the orientation constants have been built (they are only when
    /// an orientation was asked for).
    pub fn orientation_prepared(&self) -> bool {
        matches!(self.motion, Motion::Steady) || self.attitude.get().is_some()
    }

    /// ω(t) in the user's axes, without any orientation work. At t = 0 it is
    /// ω₀ exactly.
    pub fn omega_at(&self, t: f64) -> Vector3<f64> {
        match &self.motion {
            _ if t == 0.0 => self.omega0,
            Motion::Steady => self.omega0,
            Motion::Moving {
                frame,
                scale,
                orbit,
            } => frame.to_user(orbit.point(t).omega) * *scale,
        }
    }

    /// ω(t) and the orientation q(t) (body → space, identity at t = 0). q is
    /// continuous in t, so it never jumps to −q.
    pub fn state_at(&self, t: f64) -> State {
        match &self.motion {
            Motion::Steady => State {
                omega: self.omega0,
                q: steady_rotation(&self.omega0, t),
            },
            Motion::Moving {
                frame,
                scale,
                orbit,
            } => {
                let point = orbit.point(t);
                let [w, x, y, z] = self.attitude(orbit, *scale).orientation(orbit, &point, t);
                let v = frame.to_user([x, y, z]);
                State {
                    omega: if t == 0.0 {
                        self.omega0
                    } else {
                        frame.to_user(point.omega) * *scale
                    },
                    q: UnitQuaternion::new_normalize(Quaternion::new(w, v[0], v[1], v[2])),
                }
            }
        }
    }

    fn quarter_period(&self) -> Option<f64> {
        match &self.motion {
            Motion::Moving { orbit, .. } if !matches!(orbit.shape, Shape::Separatrix) => {
                Some(orbit.quarter_period_phase() / orbit.rate)
            }
            _ => None,
        }
    }

    fn attitude(&self, orbit: &Orbit, scale: f64) -> &Attitude {
        self.attitude.get_or_init(|| Attitude::new(orbit, scale))
    }
}

impl Motion {
    fn new(inertia: &Vector3<f64>, omega: &Vector3<f64>) -> Motion {
        let inertia_scale = power_of_two_at_most(inertia.max());
        let i = inertia / inertia_scale;
        let largest = omega.amax();
        if largest == 0.0 {
            return Motion::Steady;
        }
        let scale = power_of_two_at_most(largest);
        // Components below 2^-500 |ω| are dropped: their squares would
        // underflow next to the others, and such a perturbation needs
        // λt > 340 to reach even the last digit of ω.
        let w = (omega / scale).map(|v| if v.abs() < TINY_COMPONENT { 0.0 } else { v });
        // ω is an eigenvector of I exactly when (I ω) × ω vanishes.
        let steady = (0..3).all(|k| {
            let (a, b) = ((k + 1) % 3, (k + 2) % 3);
            (i[a] - i[b]) * w[a] * w[b] == 0.0
        });
        if steady {
            return Motion::Steady;
        }
        let mut ascending = [0, 1, 2];
        ascending.sort_by(|&a, &b| i[a].total_cmp(&i[b]));
        let [small, mid, large] = ascending;
        // The sign of D₂ = L² − 2T I_mid picks the circulation axis; scaling
        // the two components first keeps tiny perturbations from underflowing.
        let gap_scale = power_of_two_at_most(w[small].abs().max(w[large].abs()));
        let d2 = orbit::middle_gap(
            [i[small], i[mid], i[large]],
            w[small] / gap_scale,
            w[large] / gap_scale,
        );
        let frame = Frame::new(if d2 >= 0.0 {
            [small, mid, large]
        } else {
            [large, mid, small]
        });
        let orbit = Orbit::new(frame.moments(&i), frame.to_internal(&w), scale);
        Motion::Moving {
            frame,
            scale,
            orbit,
        }
    }
}

/// Uniform rotation about a fixed ω: q = exp(½ ω t), continuous in t.
fn steady_rotation(omega: &Vector3<f64>, t: f64) -> UnitQuaternion<f64> {
    let largest = omega.amax();
    if largest == 0.0 {
        return UnitQuaternion::identity();
    }
    let scale = power_of_two_at_most(largest);
    let unit = omega / scale;
    let norm = unit.norm();
    let half_angle = 0.5 * norm * (scale * t);
    let (s, c) = half_angle.sin_cos();
    let axis = unit / norm;
    UnitQuaternion::new_unchecked(Quaternion::new(c, s * axis[0], s * axis[1], s * axis[2]))
}

/// 2^-500: relative size below which a component of ω₀ is treated as zero.
const TINY_COMPONENT: f64 = 3.054936363499605e-151;

/// The largest power of two not above x (x > 0, finite), kept well inside
/// the normal range.
fn power_of_two_at_most(x: f64) -> f64 {
    x.log2().floor().clamp(-1000.0, 1000.0).exp2()
}

/// Linear stability of a steady spin at rate `spin` about principal `axis`
/// (0-based): small deviations of the other two components obey ξ̈ = k ξ with
/// k = (I_a − I_j)(I_l − I_a) spin² / (I_j I_l). k > 0: they grow like
/// e^(√k t) (the middle axis); k < 0: they oscillate at √−k (largest or
/// smallest axis); k = 0: neutral (symmetric body).
pub fn linear_stability(body: &Body, axis: usize, spin: f64) -> f64 {
    let i = body.inertia;
    let a = axis % 3;
    let (j, l) = ((a + 1) % 3, (a + 2) % 3);
    (i[a] - i[j]) * (i[l] - i[a]) * spin * spin / (i[j] * i[l])
}

impl Solver for Exact {
    fn method(&self) -> Method {
        Method::Exact
    }

    fn advance(&mut self, t: f64) -> Result<State, SolveError> {
        if !t.is_finite() {
            return Err(SolveError::Invalid(format!(
                "time t = {} is not finite",
                Num(t)
            )));
        }
        let state = if self.needs.orientation {
            self.state_at(t)
        } else {
            State::new(self.omega_at(t))
        };
        let finite = state.omega.iter().all(|v| v.is_finite())
            && state.q.coords.iter().all(|v| v.is_finite());
        if !finite {
            return Err(SolveError::Invalid(format!(
                "t = {} puts the phase beyond what double precision can represent for this spin",
                Num(t)
            )));
        }
        Ok(state)
    }

    fn work(&self) -> Work {
        Work::default()
    }
}

#[cfg(test)]
mod tests;
