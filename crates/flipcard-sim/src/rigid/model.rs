//! The torque-free rigid body: principal moments, state, Euler's equations
//! and the invariants every solver is judged by.
//!
//! Conventions (shared by every solver):
//! - `inertia` keeps the axes in the order the user gave them;
//! - `omega` is the body-frame angular velocity;
//! - `q` maps body vectors to space vectors (`v_space = q * v_body`), identity
//!   at t = 0, and obeys q̇ = ½ q ⊗ (0, ω);
//! - Euler's equations: I ω̇ = (I ω) × ω, i.e. I₁ω̇₁ = (I₂ − I₃) ω₂ω₃ and cyclic.

use crate::error::ModelError;
use nalgebra::{UnitQuaternion, Vector3};

/// A rigid body by its principal moments of inertia (kg·m²), in the order given.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Body {
    pub inertia: Vector3<f64>,
}

impl Body {
    /// Accepts only physical moments: finite, positive, and Iᵢ + Iⱼ ≥ Iₖ for
    /// every axis (equality is a flat body, which is allowed). Moments that
    /// miss the inequality by no more than the rounding of decimal figures
    /// are taken as the flat body they stand for, Iₖ = Iᵢ + Iⱼ: left as
    /// given, a needle such as (1e-300, 1, 1 + 4e-16) would couple its thin
    /// axis through (I₂ − I₃)/I₁ ≈ 4e284, which no rigid body has.
    pub fn new(inertia: [f64; 3]) -> Result<Body, ModelError> {
        let mut inertia = inertia;
        for (axis, &value) in inertia.iter().enumerate() {
            if !value.is_finite() {
                return Err(ModelError::NonFiniteInertia {
                    axis: axis + 1,
                    value,
                });
            }
            if value <= 0.0 {
                return Err(ModelError::NonPositiveInertia {
                    axis: axis + 1,
                    value,
                });
            }
        }
        for k in 0..3 {
            let (i, j) = ((k + 1) % 3, (k + 2) % 3);
            let sum = inertia[i] + inertia[j];
            // A flat body sits exactly on the boundary; allow rounding of the
            // author's decimal figures by a few ulps.
            if sum < inertia[k] * (1.0 - 4.0 * f64::EPSILON) {
                let (i, j) = (i.min(j), i.max(j));
                return Err(ModelError::Triangle {
                    i: i + 1,
                    j: j + 1,
                    k: k + 1,
                    sum,
                    value: inertia[k],
                });
            }
            if sum < inertia[k] {
                inertia[k] = sum;
            }
        }
        Ok(Body {
            inertia: Vector3::from(inertia),
        })
    }

    /// Body-frame angular momentum L = I ω.
    pub fn momentum(&self, omega: &Vector3<f64>) -> Vector3<f64> {
        self.inertia.component_mul(omega)
    }

    /// Kinetic energy T = ½ Σ Iᵢωᵢ².
    pub fn energy(&self, omega: &Vector3<f64>) -> f64 {
        0.5 * self.inertia.dot(&omega.component_mul(omega))
    }

    /// |L|² = Σ (Iᵢωᵢ)².
    pub fn l2(&self, omega: &Vector3<f64>) -> f64 {
        self.momentum(omega).norm_squared()
    }

    /// A bound on every |ωᵢ| along the orbit through `omega` (the ω plot's
    /// range): energy and |L| are conserved, so |ωᵢ| ≤ √(2T/Iᵢ) and
    /// |ωᵢ| ≤ |L|/Iᵢ.
    pub fn omega_bound(&self, omega: &Vector3<f64>) -> f64 {
        let two_t = 2.0 * self.energy(omega);
        let l = self.l2(omega).sqrt();
        (0..3)
            .map(|i| {
                let ii = self.inertia[i];
                (two_t / ii).sqrt().min(l / ii)
            })
            .fold(0.0, f64::max)
    }

    /// Euler's equations, torque-free: ω̇ = I⁻¹ ((I ω) × ω).
    pub fn omega_dot(&self, omega: &Vector3<f64>) -> Vector3<f64> {
        self.momentum(omega)
            .cross(omega)
            .component_div(&self.inertia)
    }

    /// Space-frame angular momentum q (I ω) q⁻¹; constant along the true motion.
    pub fn momentum_in_space(&self, state: &State) -> Vector3<f64> {
        state.q * self.momentum(&state.omega)
    }
}

/// Checks a body-frame angular velocity.
pub fn omega(values: [f64; 3]) -> Result<Vector3<f64>, ModelError> {
    for (axis, &value) in values.iter().enumerate() {
        if !value.is_finite() {
            return Err(ModelError::NonFiniteOmega {
                axis: axis + 1,
                value,
            });
        }
    }
    Ok(Vector3::from(values))
}

/// Body-frame angular velocity and body→space orientation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct State {
    pub omega: Vector3<f64>,
    pub q: UnitQuaternion<f64>,
}

impl State {
    pub fn new(omega: Vector3<f64>) -> State {
        State {
            omega,
            q: UnitQuaternion::identity(),
        }
    }
}
