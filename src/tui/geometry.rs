//! The 3-D geometry of the simulation panels: the sides of a body whose
//! moments match the scene's, and a camera with or without perspective.

use nalgebra::Vector3;

/// Half-sides (a, b, c) of a uniform box with principal moments
/// proportional to `inertia`: I₁ ∝ b² + c², I₂ ∝ a² + c², I₃ ∝ a² + b², so
/// a² ∝ (I₂ + I₃ − I₁)/2 and cyclic. Scaled so the longest half-side is 1;
/// a flat body gets a thin but visible thickness.
pub fn box_half_sides(inertia: [f64; 3]) -> [f64; 3] {
    let [i1, i2, i3] = inertia;
    let sq = [
        (i2 + i3 - i1) / 2.0,
        (i1 + i3 - i2) / 2.0,
        (i1 + i2 - i3) / 2.0,
    ];
    let sides = sq.map(|s| s.max(0.0).sqrt());
    let longest = sides.iter().cloned().fold(0.0, f64::max);
    if !(longest > 0.0 && longest.is_finite()) {
        return [1.0, 1.0, 1.0];
    }
    sides.map(|s| (s / longest).max(0.03))
}

/// A camera looking at the origin: `up` is drawn vertical, the view comes
/// from `elevation` radians above the horizontal plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    right: Vector3<f64>,
    up: Vector3<f64>,
    /// From the eye towards the origin.
    forward: Vector3<f64>,
    /// Eye distance; `None` for an orthographic view.
    distance: Option<f64>,
}

impl Camera {
    /// `up` is made vertical on screen; `azimuth_hint` picks the horizontal
    /// direction the eye looks along (any vector not parallel to `up`).
    pub fn new(
        up: Vector3<f64>,
        azimuth_hint: Vector3<f64>,
        elevation: f64,
        distance: Option<f64>,
    ) -> Camera {
        let up = up.try_normalize(1e-300).unwrap_or(Vector3::z());
        let mut side = up.cross(&azimuth_hint);
        if side.norm() < 1e-9 {
            side = up.cross(&Vector3::x());
            if side.norm() < 1e-9 {
                side = up.cross(&Vector3::y());
            }
        }
        let side = side.normalize();
        // Horizontal look direction, then tilted down by the elevation.
        let level = side.cross(&up);
        let forward = (level * elevation.cos() - up * elevation.sin()).normalize();
        let right = forward.cross(&up).normalize();
        let up = right.cross(&forward).normalize();
        Camera {
            right,
            up,
            forward,
            distance,
        }
    }

    /// Screen right, screen up and the viewing direction, as space vectors.
    pub fn right(&self) -> Vector3<f64> {
        self.right
    }
    pub fn up(&self) -> Vector3<f64> {
        self.up
    }
    pub fn forward(&self) -> Vector3<f64> {
        self.forward
    }

    /// Screen position (x right, y up) and depth (positive = further away).
    pub fn project(&self, p: &Vector3<f64>) -> (f64, f64, f64) {
        let depth = p.dot(&self.forward);
        let (x, y) = (p.dot(&self.right), p.dot(&self.up));
        match self.distance {
            Some(d) => {
                let s = d / (d + depth).max(1e-3);
                (x * s, y * s, depth)
            }
            None => (x, y, depth),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_sides_reproduce_the_moment_ratios() {
        let inertia = [2.0, 3.0, 4.0];
        let [a, b, c] = box_half_sides(inertia);
        let moments = [b * b + c * c, a * a + c * c, a * a + b * b];
        for i in 0..3 {
            let ratio = moments[i] / moments[0];
            assert!(
                (ratio - inertia[i] / inertia[0]).abs() < 1e-12,
                "{moments:?}"
            );
        }
        // The smallest moment belongs to the longest side.
        assert_eq!(a, 1.0);
    }

    #[test]
    fn flat_and_degenerate_bodies_stay_drawable() {
        // I = (1, 2, 3) is a flat plate (I₃ = I₁ + I₂): drawn thin, not flat.
        let [a, b, c] = box_half_sides([1.0, 2.0, 3.0]);
        assert!(c > 0.0 && c < 0.1 && a == 1.0 && b < a, "{a} {b} {c}");
        assert_eq!(box_half_sides([0.0, 0.0, 0.0]), [1.0, 1.0, 1.0]);
    }

    #[test]
    fn camera_keeps_up_vertical_and_centres_the_origin() {
        let cam = Camera::new(Vector3::y(), Vector3::new(1.0, 0.0, 0.3), 0.3, Some(4.0));
        let (x, y, _) = cam.project(&Vector3::zeros());
        assert!(x.abs() < 1e-12 && y.abs() < 1e-12);
        let (x, y, _) = cam.project(&Vector3::y());
        assert!(x.abs() < 1e-12 && y > 0.5, "({x}, {y})");
    }
}
