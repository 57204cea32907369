//! Fixed sums: linear combinations cᵀy of the variables that the equations
//! keep constant (cᵀf(t, y) = 0 for every t and y), found from the
//! equations and held against rounding while a solver steps.
//!
//! Every Runge–Kutta method keeps such a sum exactly in exact arithmetic;
//! rounding does not. Where the sum's direction is one the equations never
//! damp, the drift stays and can swamp variables that are small beside the
//! terms their rates are made of. E5 (Hairer & Wanner's pyrolysis) keeps
//! y2 − y3 − y4 = 0; by t = 1e13 rounding has moved it by ~1e-20 while y2
//! and y3 are 8.86e-23, and a run with `atol = 1e-24` printed y2 = 4e-20,
//! y3 = 3e-29 (both are 8.86e-23) with exit 0. Held, the same run ends
//! within 5e-5 of the reference (the atol's own level), and within 1e-9
//! with `--atol 1e-30`, as the three-variable form with the sum written
//! out does.
//!
//! **Finding them** is the system's business
//! ([`crate::OdeSystem::fixed_sums`]): a deck's system proves them from its
//! expressions ([`crate::system::sums`]), exactly, so a sum that holds only
//! near the start, on one side of a sign or up to a small leak is never
//! held (an earlier search that read the equations at a few points near
//! the start held `x + y` for x' = −x + exp(−(t − 20)²), y' = x, and the
//! run printed y(40) = 1.0 where it is 2.77).
//!
//! **Holding them** ([`Held::hold`]): after each accepted step y moves to
//! the nearest point (in the step's error weights w, atol + rtol·|y|) with
//! the start's sums: y ← y − W Cᵀ (C W Cᵀ)⁻¹ (C y − s), W = diag(w²). The
//! correction goes to the variables the error control allows the most
//! room, and is of the size of rounding.

use nalgebra::DMatrix;

/// Systems larger than this are not searched (the exact elimination
/// grows as n³ in numbers that may grow too).
pub const MAX_DIM: usize = 64;

/// A fixed sum written with the variables' names: `y2 - y3 - y4`,
/// `y1 + 2*y2`.
pub fn show(c: &[f64], names: &[String]) -> String {
    let mut out = String::new();
    for (&a, name) in c.iter().zip(names) {
        if a == 0.0 {
            continue;
        }
        let size = a.abs();
        let sign = if a < 0.0 { "-" } else { "+" };
        if out.is_empty() {
            if a < 0.0 {
                out.push('-');
            }
        } else {
            out.push_str(&format!(" {sign} "));
        }
        if size != 1.0 {
            out.push_str(&format!("{}*", flipcard_text::num::show(size)));
        }
        out.push_str(name);
    }
    out
}

/// The sums a solver holds, and their values at the start.
#[derive(Debug, Clone)]
pub struct Held {
    c: Vec<Vec<f64>>,
    s: Vec<f64>,
}

impl Held {
    /// `None` without sums, or where a sum at `y0` is not finite.
    pub fn new(c: Vec<Vec<f64>>, y0: &[f64]) -> Option<Held> {
        if c.is_empty() || c.iter().any(|r| r.len() != y0.len()) {
            return None;
        }
        let s: Vec<f64> = c.iter().map(|r| dot(r, y0)).collect();
        s.iter().all(|v| v.is_finite()).then_some(Held { c, s })
    }

    /// The rows, as found.
    pub fn rows(&self) -> &[Vec<f64>] {
        &self.c
    }

    /// Moves `y` to the nearest point, in the weights `w(i, yᵢ)` (each
    /// variable's atol + rtol·|y|), where every sum has its start's value.
    /// Leaves `y` as it is where the correction would not be finite. One
    /// sum (the usual case) allocates nothing: this runs at every accepted
    /// step.
    pub fn hold(&self, y: &mut [f64], w: impl Fn(usize, f64) -> f64) {
        if let [c] = self.c.as_slice() {
            let r = dot(c, y) - self.s[0];
            if r == 0.0 || !r.is_finite() {
                return;
            }
            let w2 = |i: usize, v: f64| {
                let w = w(i, v);
                w * w
            };
            let g: f64 = (0..y.len()).map(|i| c[i] * w2(i, y[i]) * c[i]).sum();
            let lambda = r / g;
            if (0..y.len()).any(|i| !(w2(i, y[i]) * (c[i] * lambda)).is_finite()) {
                return;
            }
            for (i, v) in y.iter_mut().enumerate() {
                *v -= w2(i, *v) * (c[i] * lambda);
            }
            return;
        }
        let m = self.c.len();
        let r: Vec<f64> = self
            .c
            .iter()
            .zip(&self.s)
            .map(|(c, s)| dot(c, y) - s)
            .collect();
        if r.iter().all(|v| *v == 0.0) || r.iter().any(|v| !v.is_finite()) {
            return;
        }
        let w2: Vec<f64> = (0..y.len())
            .map(|i| {
                let w = w(i, y[i]);
                w * w
            })
            .collect();
        // G = C W Cᵀ, and λ = G⁻¹ r.
        let g = DMatrix::from_fn(m, m, |a, b| {
            (0..y.len())
                .map(|i| self.c[a][i] * w2[i] * self.c[b][i])
                .sum::<f64>()
        });
        let Some(lambda) = g.lu().solve(&nalgebra::DVector::from_vec(r)) else {
            return;
        };
        let delta: Vec<f64> = (0..y.len())
            .map(|i| w2[i] * (0..m).map(|a| self.c[a][i] * lambda[a]).sum::<f64>())
            .collect();
        if delta.iter().all(|d| d.is_finite()) {
            for (v, d) in y.iter_mut().zip(&delta) {
                *v -= d;
            }
        }
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn sums_read_with_their_names() {
        let names: Vec<String> = ["y1", "y2", "y3", "y4"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        assert_eq!(show(&[0.0, 1.0, -1.0, -1.0], &names), "y2 - y3 - y4");
        assert_eq!(show(&[1.0, 3.0, 0.0, 0.0], &names), "y1 + 3*y2");
        assert_eq!(show(&[-0.5, 0.0, 0.0, 1.0], &names), "-0.5*y1 + y4");
    }

    proptest! {
        /// Holding moves y onto the start's sums (to rounding) and moves
        /// no variable that is not in a sum.
        #[test]
        fn holding_restores_the_sums(
            y0 in prop::collection::vec(-1e3f64..1e3, 4),
            drift in prop::collection::vec(-1e-6f64..1e-6, 4),
            w in prop::collection::vec(1e-9f64..1.0, 4),
        ) {
            let c = vec![vec![0.0, 1.0, -1.0, -1.0], vec![1.0, 0.0, 0.0, 2.0]];
            let held = Held::new(c.clone(), &y0).unwrap();
            let mut y: Vec<f64> = y0.iter().zip(&drift).map(|(a, b)| a + b).collect();
            held.hold(&mut y, |i, _| w[i]);
            for row in &c {
                let before = dot(row, &y0);
                let after = dot(row, &y);
                let size = row.iter().zip(&y0).map(|(a, b)| (a * b).abs()).sum::<f64>();
                prop_assert!((after - before).abs() <= 1e-12 * size.max(1.0), "{before} {after}");
            }
            let one = Held::new(vec![vec![0.0, 1.0, -1.0, -1.0]], &y0).unwrap();
            let mut z: Vec<f64> = y0.iter().zip(&drift).map(|(a, b)| a + b).collect();
            let z0 = z[0];
            one.hold(&mut z, |i, _| w[i]);
            prop_assert_eq!(z[0], z0);
            let size = y0[1..].iter().map(|v| v.abs()).sum::<f64>();
            prop_assert!((dot(&[0.0, 1.0, -1.0, -1.0], &z) - dot(&[0.0, 1.0, -1.0, -1.0], &y0)).abs() <= 1e-12 * size.max(1.0));
        }
    }
}
