//! Euler's equations as a fixed-size first-order system for the step-based
//! solvers: either ω alone (3 components) or ω with the orientation
//! quaternion (7 components: ω₁ ω₂ ω₃ q_w q_x q_y q_z). Plain arrays keep the
//! inner loops free of allocation.
//!
//! The rigid body is a system like any other: its right-hand side is the
//! one [`OdeSystem::rhs`] every solver of deck systems steps too (so Radau
//! IIA or `auto` can integrate a rigid body), and [`RigidSystem`] adds only
//! what a rigid body has beyond it: the map to and from the shared
//! [`State`], the quaternion's return to the unit sphere, and its error
//! floor.

use nalgebra::{Quaternion, UnitQuaternion, Vector3};

use crate::rhs::OdeSystem;
use crate::rigid::model::{Body, State};

/// A rigid body's system y' = f(y) on N components (f is its
/// [`OdeSystem::rhs`]), with the map to and from the shared [`State`].
pub trait RigidSystem<const N: usize>: OdeSystem + Copy {
    /// f(y) by value, for the fixed-size solvers' inner loops: the one
    /// right-hand side, [`OdeSystem::rhs`], at t = 0 (the body's equations
    /// do not depend on t).
    #[inline(always)]
    fn f(&self, y: &[f64; N]) -> [f64; N] {
        let mut dy = [0.0; N];
        self.rhs(0.0, y, &mut dy);
        dy
    }
    fn initial(&self, omega: &Vector3<f64>) -> [f64; N];
    /// The state a vector stands for; q is passed through as integrated (its
    /// norm drift is part of what a solver is judged by), identity without q.
    fn state(&self, y: &[f64; N]) -> State;
    /// Puts q back on the unit sphere (nothing to do without q).
    fn normalize(&self, y: &mut [f64; N]);
    /// Absolute error floor of each component for a tolerance: ω against the
    /// size of the initial ω, q against 1.
    fn atol(&self, tol: f64) -> [f64; N];
}

/// ω̇ᵢ = aᵢ ωⱼ ωₖ with aᵢ = (Iⱼ − Iₖ)/Iᵢ, (i, j, k) cyclic. The differences are
/// taken of the moments themselves, exactly when they are close, instead of
/// cancelling two large products at every evaluation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coupling {
    pub a: [f64; 3],
}

impl Coupling {
    pub fn new(body: &Body) -> Coupling {
        let i = body.inertia;
        Coupling {
            a: [
                (i[1] - i[2]) / i[0],
                (i[2] - i[0]) / i[1],
                (i[0] - i[1]) / i[2],
            ],
        }
    }

    #[inline(always)]
    pub fn omega_dot(&self, w: [f64; 3]) -> [f64; 3] {
        [
            self.a[0] * w[1] * w[2],
            self.a[1] * w[2] * w[0],
            self.a[2] * w[0] * w[1],
        ]
    }
}

/// q̇ = ½ q ⊗ (0, ω).
#[inline(always)]
pub(crate) fn quaternion_dot(q: [f64; 4], w: [f64; 3]) -> [f64; 4] {
    let [qw, qx, qy, qz] = q;
    [
        -0.5 * (qx * w[0] + qy * w[1] + qz * w[2]),
        0.5 * (qw * w[0] + qy * w[2] - qz * w[1]),
        0.5 * (qw * w[1] + qz * w[0] - qx * w[2]),
        0.5 * (qw * w[2] + qx * w[1] - qy * w[0]),
    ]
}

/// ω only; the orientation is never touched.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OmegaOnly {
    pub coupling: Coupling,
    pub omega_scale: f64,
}

/// ω and the body→space quaternion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WithOrientation {
    pub coupling: Coupling,
    pub omega_scale: f64,
}

impl OmegaOnly {
    pub fn new(body: &Body, omega0: &Vector3<f64>) -> OmegaOnly {
        OmegaOnly {
            coupling: Coupling::new(body),
            omega_scale: omega0.norm(),
        }
    }
}

impl WithOrientation {
    pub fn new(body: &Body, omega0: &Vector3<f64>) -> WithOrientation {
        WithOrientation {
            coupling: Coupling::new(body),
            omega_scale: omega0.norm(),
        }
    }
}

/// The ω error floor: relative to |ω₀| (the problem is scale-free in ω), and
/// never zero so that a body at rest still has a defined error norm.
fn omega_atol(tol: f64, scale: f64) -> f64 {
    if scale > 0.0 { tol * scale } else { tol }
}

impl OdeSystem for OmegaOnly {
    fn dim(&self) -> usize {
        3
    }

    #[inline(always)]
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
        dy.copy_from_slice(&self.coupling.omega_dot([y[0], y[1], y[2]]));
    }
}

impl RigidSystem<3> for OmegaOnly {
    fn initial(&self, omega: &Vector3<f64>) -> [f64; 3] {
        [omega[0], omega[1], omega[2]]
    }

    fn state(&self, y: &[f64; 3]) -> State {
        State::new(Vector3::new(y[0], y[1], y[2]))
    }

    fn normalize(&self, _y: &mut [f64; 3]) {}

    fn atol(&self, tol: f64) -> [f64; 3] {
        [omega_atol(tol, self.omega_scale); 3]
    }
}

impl OdeSystem for WithOrientation {
    fn dim(&self) -> usize {
        7
    }

    #[inline(always)]
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
        let w = [y[0], y[1], y[2]];
        let dw = self.coupling.omega_dot(w);
        let dq = quaternion_dot([y[3], y[4], y[5], y[6]], w);
        dy.copy_from_slice(&[dw[0], dw[1], dw[2], dq[0], dq[1], dq[2], dq[3]]);
    }
}

impl RigidSystem<7> for WithOrientation {
    fn initial(&self, omega: &Vector3<f64>) -> [f64; 7] {
        [omega[0], omega[1], omega[2], 1.0, 0.0, 0.0, 0.0]
    }

    fn state(&self, y: &[f64; 7]) -> State {
        State {
            omega: Vector3::new(y[0], y[1], y[2]),
            q: UnitQuaternion::new_unchecked(Quaternion::new(y[3], y[4], y[5], y[6])),
        }
    }

    fn normalize(&self, y: &mut [f64; 7]) {
        let n = (y[3] * y[3] + y[4] * y[4] + y[5] * y[5] + y[6] * y[6]).sqrt();
        if n > 0.0 && n.is_finite() {
            for v in &mut y[3..] {
                *v /= n;
            }
        }
    }

    fn atol(&self, tol: f64) -> [f64; 7] {
        let w = omega_atol(tol, self.omega_scale);
        [w, w, w, tol, tol, tol, tol]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coupling_matches_euler_equations() {
        let body = Body::new([1.0, 2.5, 3.0]).unwrap();
        let w = Vector3::new(0.3, -1.2, 0.7);
        let expected = body.omega_dot(&w);
        let got = Coupling::new(&body).omega_dot([w[0], w[1], w[2]]);
        for k in 0..3 {
            assert!(
                (got[k] - expected[k]).abs() < 1e-15,
                "{got:?} vs {expected}"
            );
        }
    }

    #[test]
    fn quaternion_rate_matches_nalgebra_product() {
        let q = UnitQuaternion::from_euler_angles(0.3, -0.2, 1.1);
        let w = Vector3::new(0.4, 2.0, -0.5);
        let expected = q.quaternion() * Quaternion::from_imag(w) * 0.5;
        let got = quaternion_dot([q.w, q.i, q.j, q.k], [w[0], w[1], w[2]]);
        let want = [expected.w, expected.i, expected.j, expected.k];
        for k in 0..4 {
            assert!((got[k] - want[k]).abs() < 1e-15, "{got:?} vs {want:?}");
        }
    }
}
