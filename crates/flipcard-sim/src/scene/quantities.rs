//! The numbers of a scene a number prompt's formulas may name (its known
//! slips, `value = "1/k"`): a rigid body's moments, its spin at t = 0 and
//! the stability k of that spin, which the verdict's closed forms use
//! (growth rate √k, e-folding time 1/√k); a system's `params`. Every
//! formula may also name `measured`, the run's value of the prompt's
//! measure, given at the verdict.

use nalgebra::Vector3;

use crate::rigid::formula;
use crate::rigid::model::Body;

/// The name of the run's value of the prompt's own measure.
pub const MEASURED: &str = "measured";

/// The names a formula on a rigid-body scene reads, with what each is, in
/// the order the deck format documents them.
pub const RIGID: [(&str, &str); 7] = [
    ("I1", "the first principal moment, as `inertia` gives it"),
    ("I2", "the second principal moment"),
    ("I3", "the third principal moment"),
    (
        "w1",
        "the first component of ω at t = 0, as `omega` gives it",
    ),
    ("w2", "the second component of ω at t = 0"),
    ("w3", "the third component of ω at t = 0"),
    (
        "k",
        "the linear stability of the spin about the axis ω starts nearest: (I_a − I_b)(I_c − I_a)Ω²/(I_b I_c); √k is the growth rate when k > 0, √−k the wobble's angular frequency when k < 0",
    ),
];

/// Each name of [`RIGID`] with its value for a body with moments
/// `inertia` spinning at `omega`; `k` is left out when the moments are no
/// body's (the scene's own check says why).
pub fn rigid(inertia: [f64; 3], omega: [f64; 3]) -> Vec<(String, f64)> {
    let mut out: Vec<(String, f64)> = (0..3)
        .map(|i| (RIGID[i].0.to_string(), inertia[i]))
        .chain((0..3).map(|i| (RIGID[3 + i].0.to_string(), omega[i])))
        .collect();
    let w = Vector3::from(omega);
    if let Ok(body) = Body::new(inertia) {
        let axis = formula::dominant_axis(&w);
        let k = formula::stability(&body, axis, w[axis]);
        if k.is_finite() {
            out.push((RIGID[6].0.to_string(), k));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn k_is_the_stability_of_the_spin_the_body_starts_with() {
        // The bundled e-folding scene: I = (1, 2, 3), Ω = 10 about the middle.
        let names = rigid([1.0, 2.0, 3.0], [0.01, 10.0, 0.01]);
        let k = names.iter().find(|(n, _)| n == "k").unwrap().1;
        assert!((k - 100.0 / 3.0).abs() < 1e-9, "{k}");
        // About the largest axis the spin is stable: k < 0.
        let names = rigid([1.0, 2.0, 3.0], [0.01, 0.01, 10.0]);
        let k = names.iter().find(|(n, _)| n == "k").unwrap().1;
        assert!((k + 100.0).abs() < 1e-9, "{k}");
        assert_eq!(names.len(), RIGID.len());
        // Moments no body has: no k.
        assert_eq!(rigid([1.0, 1.0, 5.0], [0.0, 0.0, 1.0]).len(), 6);
    }
}
