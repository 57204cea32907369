//! The internal principal frame: the user's axes permuted so that axis 3 is
//! the one ω circulates about, with one axis reversed when the permutation
//! is odd so the frame stays right-handed.
//!
//! Euler's equations and the kinematics q̇ = ½ q ⊗ (0, ω) are covariant under
//! proper rotations, and a signed permutation with determinant +1 is one:
//! ω_int = S ω_user and q_user = Sᵀ q_int S, i.e. the same scalar part and
//! the vector part mapped back like ω. A plain odd permutation would be a
//! reflection, under which Euler's equations run backwards in time.

use nalgebra::Vector3;

#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Frame {
    /// Internal axis k is user axis `perm[k]` …
    perm: [usize; 3],
    /// … multiplied by `sign[k]`.
    sign: [f64; 3],
}

impl Frame {
    pub(super) fn new(perm: [usize; 3]) -> Frame {
        let inversions = (0..3)
            .flat_map(|i| (i + 1..3).map(move |j| (i, j)))
            .filter(|&(i, j)| perm[i] > perm[j])
            .count();
        let parity = if inversions % 2 == 0 { 1.0 } else { -1.0 };
        Frame {
            perm,
            sign: [1.0, parity, 1.0],
        }
    }

    /// The user axis that internal axis `k` comes from.
    pub(super) fn user_axis(self, k: usize) -> usize {
        self.perm[k]
    }

    /// Components of a user-frame vector along the internal axes.
    pub(super) fn to_internal(self, v: &Vector3<f64>) -> [f64; 3] {
        [
            self.sign[0] * v[self.perm[0]],
            self.sign[1] * v[self.perm[1]],
            self.sign[2] * v[self.perm[2]],
        ]
    }

    /// Moments of inertia along the internal axes (no signs: a tensor).
    pub(super) fn moments(self, inertia: &Vector3<f64>) -> [f64; 3] {
        [
            inertia[self.perm[0]],
            inertia[self.perm[1]],
            inertia[self.perm[2]],
        ]
    }

    /// A vector (angular velocity or quaternion vector part) back in the
    /// user's axes.
    pub(super) fn to_user(self, v: [f64; 3]) -> Vector3<f64> {
        let mut out = Vector3::zeros();
        for (k, value) in v.into_iter().enumerate() {
            out[self.perm[k]] = self.sign[k] * value;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn odd_permutations_reverse_one_axis() {
        for perm in [
            [0, 1, 2],
            [1, 2, 0],
            [2, 0, 1],
            [0, 2, 1],
            [2, 1, 0],
            [1, 0, 2],
        ] {
            let frame = Frame::new(perm);
            // The map is a proper rotation: e1 × e2 = e3 survives it.
            let e = |k: usize| {
                let mut v = [0.0; 3];
                v[k] = 1.0;
                frame.to_user(v)
            };
            assert_eq!(e(0).cross(&e(1)), e(2), "{perm:?}");
            let v = Vector3::new(0.3, -1.2, 2.5);
            assert_eq!(frame.to_user(frame.to_internal(&v)), v);
        }
    }
}
