//! The polhode picture: the body-frame angular momentum L = Iω moves on the
//! sphere |L| = const along its intersection with the energy ellipsoid
//! Σ Lᵢ²/Iᵢ = 2T. Everything here is scaled to the unit sphere (L/|L|).
//! Built only for scenes that draw the polhode.

use crate::error::SolveError;
use nalgebra::Vector3;

use crate::rigid::model::Body;
use crate::rigid::solver::Solver;

/// Points on each separatrix circle.
const SEPARATRIX_POINTS: usize = 181;
/// Points on the closed curve of the orbit.
const ORBIT_POINTS: usize = 256;

#[derive(Debug, Clone, PartialEq)]
pub struct Polhode {
    /// |L|, the radius of the momentum sphere the points are divided by.
    pub radius: f64,
    /// Semi-axes of the energy ellipsoid on the unit sphere's scale:
    /// √(2T Iᵢ)/|L|.
    pub ellipsoid: Vector3<f64>,
    /// The two great circles through the middle axis that separate
    /// circulation about the largest axis from circulation about the
    /// smallest (empty when two moments are equal).
    pub separatrix: Vec<Vec<Vector3<f64>>>,
    /// The orbit's own closed curve, over one period of ω (or the whole run
    /// when ω has no period, as on the separatrix).
    pub orbit: Vec<Vector3<f64>>,
}

impl Polhode {
    /// Builds the picture; `solver` is a fresh run of the same motion, read
    /// over `span` (one period or the scene's duration).
    pub fn new(
        body: &Body,
        omega0: &Vector3<f64>,
        solver: &mut dyn Solver,
        span: f64,
    ) -> Result<Polhode, SolveError> {
        let radius = body.l2(omega0).sqrt();
        let two_t = 2.0 * body.energy(omega0);
        let scale = if radius > 0.0 { radius } else { 1.0 };
        let ellipsoid = body.inertia.map(|i| (two_t * i).sqrt() / scale);
        let mut orbit = Vec::with_capacity(ORBIT_POINTS);
        for k in 0..ORBIT_POINTS {
            let t = span * k as f64 / (ORBIT_POINTS - 1) as f64;
            let state = solver.advance(t)?;
            orbit.push(body.momentum(&state.omega) / scale);
        }
        Ok(Polhode {
            radius,
            ellipsoid,
            separatrix: separatrix(body),
            orbit,
        })
    }

    /// The point of ω on the unit sphere.
    pub fn point(&self, body: &Body, omega: &Vector3<f64>) -> Vector3<f64> {
        let scale = if self.radius > 0.0 { self.radius } else { 1.0 };
        body.momentum(omega) / scale
    }
}

/// On the unit sphere the separatrix is where Σ Lᵢ²/Iᵢ = 1/I_b, the energy
/// of a spin about the middle axis b: two great circles through ±e_b,
/// L = (±α sin θ) e_a + cos θ e_b + (γ sin θ) e_c with
/// α² = (1/I_b − 1/I_c)/(1/I_a − 1/I_c) and γ² = 1 − α².
pub fn separatrix(body: &Body) -> Vec<Vec<Vector3<f64>>> {
    let mut axes = [0usize, 1, 2];
    axes.sort_by(|&p, &q| body.inertia[p].total_cmp(&body.inertia[q]));
    let [a, b, c] = axes;
    let inv = body.inertia.map(|i| 1.0 / i);
    let span = inv[a] - inv[c];
    let upper = inv[b] - inv[c];
    if !(upper > 0.0 && inv[a] - inv[b] > 0.0 && span > 0.0) {
        return Vec::new();
    }
    let alpha = (upper / span).sqrt();
    let gamma = (1.0 - alpha * alpha).max(0.0).sqrt();
    [1.0, -1.0]
        .iter()
        .map(|&side| {
            (0..SEPARATRIX_POINTS)
                .map(|k| {
                    let th = std::f64::consts::TAU * k as f64 / (SEPARATRIX_POINTS - 1) as f64;
                    let mut p = Vector3::zeros();
                    p[a] = side * alpha * th.sin();
                    p[b] = th.cos();
                    p[c] = gamma * th.sin();
                    p
                })
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn separatrix_lies_on_sphere_and_middle_energy() {
        let body = Body::new([1.0, 2.0, 3.0]).unwrap();
        let circles = separatrix(&body);
        assert_eq!(circles.len(), 2);
        for p in circles.iter().flatten() {
            assert!((p.norm() - 1.0).abs() < 1e-12);
            let e: f64 = (0..3).map(|i| p[i] * p[i] / body.inertia[i]).sum();
            assert!((e - 0.5).abs() < 1e-12, "{e}");
        }
        assert!(separatrix(&Body::new([2.0, 2.0, 3.0]).unwrap()).is_empty());
        assert!(separatrix(&Body::new([2.0, 2.0, 2.0]).unwrap()).is_empty());
    }
}
