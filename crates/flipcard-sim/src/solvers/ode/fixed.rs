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
//! **Finding them** ([`find`]): at a few points around the start, every
//! column of the exact Jacobian and the value of f, each scaled to unit
//! length, are rows a fixed sum's c is orthogonal to; the singular vectors
//! of that stack with singular values below [`NULL`] of the largest span
//! the candidates. A candidate is kept only if, at other points, cᵀf is
//! within [`CHECK`] of the size of its terms; if any fails none is kept
//! (holding a sum the equations do not keep would teach wrong physics).
//! The basis is brought to reduced row-echelon form, so each sum reads
//! simply (`y2 - y3 - y4`, Robertson's `y1 + y2 + y3`), and coefficients
//! within 1e-12 of a small fraction are snapped to it.
//!
//! **Holding them** ([`Held::hold`]): after each accepted step y moves to
//! the nearest point (in the step's error weights w, atol + rtol·|y|) with
//! the start's sums: y ← y − W Cᵀ (C W Cᵀ)⁻¹ (C y − s), W = diag(w²). The
//! correction goes to the variables the error control allows the most
//! room, and is of the size of rounding.

use nalgebra::DMatrix;

/// Systems larger than this are not searched: the stack's SVD grows as n³.
pub const MAX_DIM: usize = 64;
/// Points the candidates are found at, and checked at.
const FIND_POINTS: usize = 3;
const CHECK_POINTS: usize = 3;
/// Singular values below this fraction of the largest span the null space.
const NULL: f64 = 1e-11;
/// cᵀf within this fraction of Σ|cᵢfᵢ| counts as zero.
const CHECK: f64 = 1e-11;

/// The equations: `f(t, y, out)`.
pub type Rhs<'a> = dyn Fn(f64, &[f64], &mut [f64]) + 'a;
/// Their exact Jacobian: `jac(t, y, J)`, false where it cannot be had.
pub type Jacobian<'a> = dyn Fn(f64, &[f64], &mut DMatrix<f64>) -> bool + 'a;

/// A deterministic stream of numbers in [0, 1), so a scene's sums are the
/// same on every run.
struct Stream(u64);
impl Stream {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Points around (t, y): each variable moved within half of its size, and
/// one that is 0 given a size a thousandth of the largest (at least 1e-3),
/// positive, since many systems (concentrations, populations) are defined
/// only there; times within 10 of t.
fn points(t: f64, y: &[f64], count: usize, seed: u64) -> Vec<(f64, Vec<f64>)> {
    let big = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let floor = if big > 0.0 && big.is_finite() {
        big * 1e-3
    } else {
        1e-3
    };
    let mut s = Stream(seed);
    (0..count)
        .map(|_| {
            let p = y
                .iter()
                .map(|&v| {
                    let u = s.next();
                    if v.abs() >= floor {
                        v * (0.5 + u)
                    } else {
                        floor * (0.5 + u) + v
                    }
                })
                .collect();
            (t + 10.0 * s.next(), p)
        })
        .collect()
}

/// The fixed sums of y' = f(t, y) near (t, y): each a row c (its largest
/// coefficient 1 in size), `f(t, y, out)` the equations and
/// `jac(t, y, J)` their exact Jacobian (false where it cannot be had).
/// Empty for a system larger than [`MAX_DIM`], where the equations or
/// their Jacobian are not finite at the points tried, or where a
/// candidate does not hold.
pub fn find(t: f64, y: &[f64], f: &Rhs, jac: &Jacobian) -> Vec<Vec<f64>> {
    let n = y.len();
    if !(2..=MAX_DIM).contains(&n) || !t.is_finite() || y.iter().any(|v| !v.is_finite()) {
        return Vec::new();
    }
    let mut rows: Vec<Vec<f64>> = Vec::new();
    let mut push = |v: Vec<f64>| {
        let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm > 0.0 && norm.is_finite() {
            rows.push(v.into_iter().map(|x| x / norm).collect());
        }
    };
    let mut fv = vec![0.0; n];
    let mut j = DMatrix::<f64>::zeros(n, n);
    for (tp, p) in points(t, y, FIND_POINTS, 0x5eed_f1ed) {
        f(tp, &p, &mut fv);
        if !jac(tp, &p, &mut j) || fv.iter().chain(j.iter()).any(|v| !v.is_finite()) {
            return Vec::new();
        }
        push(fv.clone());
        for col in 0..n {
            push(j.column(col).iter().copied().collect());
        }
    }
    if rows.is_empty() {
        // f and its Jacobian vanish: every sum is fixed, and nothing moves
        // that holding would correct.
        return Vec::new();
    }
    let stack = DMatrix::from_fn(rows.len(), n, |r, c| rows[r][c]);
    let Some(null) = null_space(stack) else {
        return Vec::new();
    };
    if null.is_empty() {
        return Vec::new();
    }
    let sums = echelon(null);
    // Checked where they were not found.
    for (tp, p) in points(t, y, CHECK_POINTS, 0xc0ff_ee00) {
        f(tp, &p, &mut fv);
        if fv.iter().any(|v| !v.is_finite()) {
            return Vec::new();
        }
        for c in &sums {
            let dot: f64 = c.iter().zip(&fv).map(|(a, b)| a * b).sum();
            let size: f64 = c.iter().zip(&fv).map(|(a, b)| (a * b).abs()).sum();
            if dot.abs() > CHECK * size {
                return Vec::new();
            }
        }
    }
    sums
}

/// An orthonormal basis (as rows) of the vectors the rows of `a` are all
/// orthogonal to, by the SVD; `None` if it does not converge.
fn null_space(a: DMatrix<f64>) -> Option<Vec<Vec<f64>>> {
    let n = a.ncols();
    // Pad to at least n rows so V is n×n.
    let a = if a.nrows() < n {
        a.resize_vertically(n, 0.0)
    } else {
        a
    };
    let svd = a.try_svd(false, true, f64::EPSILON, 1000)?;
    let v_t = svd.v_t?;
    let top = svd.singular_values.iter().fold(0.0f64, |m, s| m.max(*s));
    Some(
        svd.singular_values
            .iter()
            .enumerate()
            .filter(|(_, s)| **s <= NULL * top)
            .map(|(k, _)| v_t.row(k).iter().copied().collect())
            .collect(),
    )
}

/// The rows brought to reduced row-echelon form (each led by a 1 in a
/// column the others have 0 in), coefficients within 1e-12 of a fraction
/// p/q with q ≤ 12 snapped to it, tiny ones to 0, each row then scaled so
/// its largest coefficient is 1 in size.
fn echelon(mut m: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
    let n = m.first().map_or(0, Vec::len);
    let mut lead = 0;
    for r in 0..m.len() {
        // The column with the largest entry among the remaining rows.
        let mut best: Option<(usize, usize)> = None;
        let mut col = lead;
        while col < n && best.is_none() {
            let (row, size) = (r..m.len())
                .map(|k| (k, m[k][col].abs()))
                .fold((r, 0.0), |a, b| if b.1 > a.1 { b } else { a });
            if size > 1e-9 {
                best = Some((row, col));
            } else {
                col += 1;
            }
        }
        let Some((row, col)) = best else {
            m.truncate(r);
            break;
        };
        m.swap(r, row);
        let pivot = m[r][col];
        m[r].iter_mut().for_each(|x| *x /= pivot);
        for k in 0..m.len() {
            if k != r {
                let factor = m[k][col];
                if factor != 0.0 {
                    let pr = m[r].clone();
                    for (x, p) in m[k].iter_mut().zip(&pr) {
                        *x -= factor * p;
                    }
                }
            }
        }
        lead = col + 1;
    }
    for row in &mut m {
        for x in row.iter_mut() {
            *x = snap(*x);
        }
        let big = row.iter().fold(0.0f64, |a, b| a.max(b.abs()));
        if big > 0.0 {
            row.iter_mut().for_each(|x| *x /= big);
        }
    }
    m.retain(|row| row.iter().any(|x| *x != 0.0));
    m
}

/// `x` snapped to a fraction p/q (q ≤ 12) within 1e-12, or to 0 below it.
fn snap(x: f64) -> f64 {
    if x.abs() < 1e-12 {
        return 0.0;
    }
    for q in 1..=12 {
        let p = (x * q as f64).round();
        if (x - p / q as f64).abs() <= 1e-12 * x.abs().max(1.0) {
            return p / q as f64;
        }
    }
    x
}

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

    /// Moves `y` to the nearest point, in the weights `w` (each variable's
    /// atol + rtol·|y|), where every sum has its start's value. Leaves `y`
    /// as it is where the correction would not be finite.
    pub fn hold(&self, y: &mut [f64], w: &[f64]) {
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
        let w2: Vec<f64> = w.iter().map(|v| v * v).collect();
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

    fn e5(_: f64, x: &[f64], y: &mut [f64]) {
        let (a, b, c, m) = (7.89e-10, 1.1e7, 1.13e3, 1e6);
        y[0] = -a * x[0] - b * x[0] * x[2];
        y[1] = a * x[0] - m * c * x[1] * x[2];
        y[2] = a * x[0] - b * x[0] * x[2] - m * c * x[1] * x[2] + c * x[3];
        y[3] = b * x[0] * x[2] - c * x[3];
    }
    fn e5_jac(_: f64, x: &[f64], j: &mut DMatrix<f64>) -> bool {
        let (a, b, c, m) = (7.89e-10, 1.1e7, 1.13e3, 1e6);
        j.fill(0.0);
        j[(0, 0)] = -a - b * x[2];
        j[(0, 2)] = -b * x[0];
        j[(1, 0)] = a;
        j[(1, 1)] = -m * c * x[2];
        j[(1, 2)] = -m * c * x[1];
        j[(2, 0)] = a - b * x[2];
        j[(2, 1)] = -m * c * x[2];
        j[(2, 2)] = -b * x[0] - m * c * x[1];
        j[(2, 3)] = c;
        j[(3, 0)] = b * x[2];
        j[(3, 2)] = b * x[0];
        j[(3, 3)] = -c;
        true
    }

    fn names(n: usize) -> Vec<String> {
        (1..=n).map(|i| format!("y{i}")).collect()
    }

    /// E5 keeps y2 − y3 − y4, Robertson y1 + y2 + y3, and each reads so.
    #[test]
    fn e5_and_robertson_keep_the_sums_chemistry_says() {
        let sums = find(0.0, &[1.76e-3, 0.0, 0.0, 0.0], &e5, &e5_jac);
        assert_eq!(sums, vec![vec![0.0, 1.0, -1.0, -1.0]]);
        assert_eq!(show(&sums[0], &names(4)), "y2 - y3 - y4");
        let rob = |_: f64, y: &[f64], d: &mut [f64]| {
            d[0] = -0.04 * y[0] + 1e4 * y[1] * y[2];
            d[1] = 0.04 * y[0] - 1e4 * y[1] * y[2] - 3e7 * y[1] * y[1];
            d[2] = 3e7 * y[1] * y[1];
        };
        let rob_jac = |_: f64, y: &[f64], j: &mut DMatrix<f64>| {
            j.copy_from_slice(&[
                -0.04,
                0.04,
                0.0,
                1e4 * y[2],
                -1e4 * y[2] - 6e7 * y[1],
                6e7 * y[1],
                1e4 * y[1],
                -1e4 * y[1],
                0.0,
            ]);
            true
        };
        let sums = find(0.0, &[1.0, 0.0, 0.0], &rob, &rob_jac);
        assert_eq!(sums, vec![vec![1.0, 1.0, 1.0]]);
        assert_eq!(show(&sums[0], &names(3)), "y1 + y2 + y3");
    }

    /// No sum is fixed by an oscillator, Lorenz's system or a forced
    /// decay, and none by equations that are not finite where tried.
    #[test]
    fn systems_without_a_fixed_sum_have_none() {
        let osc = |_: f64, y: &[f64], d: &mut [f64]| {
            d[0] = y[1];
            d[1] = -y[0];
        };
        let osc_jac = |_: f64, _: &[f64], j: &mut DMatrix<f64>| {
            j.copy_from_slice(&[0.0, -1.0, 1.0, 0.0]);
            true
        };
        assert!(find(0.0, &[1.0, 0.0], &osc, &osc_jac).is_empty());
        // x' = −x + cos t, y' = x: x + … is not fixed, since t enters.
        let forced = |t: f64, y: &[f64], d: &mut [f64]| {
            d[0] = -y[0] + t.cos();
            d[1] = y[0] - t.cos();
        };
        let forced_jac = |_: f64, _: &[f64], j: &mut DMatrix<f64>| {
            j.copy_from_slice(&[-1.0, 1.0, 0.0, 0.0]);
            true
        };
        // The Jacobian says x + y, f agrees: x' + y' = 0.
        assert_eq!(
            find(0.0, &[1.0, 0.0], &forced, &forced_jac),
            vec![vec![1.0, 1.0]]
        );
        let forced2 = |t: f64, y: &[f64], d: &mut [f64]| {
            d[0] = -y[0] + t.cos();
            d[1] = y[0];
        };
        assert!(find(0.0, &[1.0, 0.0], &forced2, &forced_jac).is_empty());
        let bad = |_: f64, y: &[f64], d: &mut [f64]| {
            d[0] = (-y[0]).sqrt();
            d[1] = -d[0];
        };
        let bad_jac = |_: f64, _: &[f64], j: &mut DMatrix<f64>| {
            j.fill(f64::NAN);
            true
        };
        assert!(find(0.0, &[1.0, 0.0], &bad, &bad_jac).is_empty());
    }

    /// A sum that leaks is not fixed: x' = −kx, y' = kx − δkx² keeps
    /// x + y only to δ; at δ = 1e-9 and 1e-6 none is found, at 1e-14 (below
    /// the rounding of the terms' size) x + y is. (y' = (1 − δ)kx has an
    /// exact one, (1 − δ)x + y, found with its coefficient.)
    #[test]
    fn a_leak_above_rounding_is_no_fixed_sum() {
        for (delta, found) in [(1e-9, false), (1e-6, false), (1e-14, true)] {
            let f = move |_: f64, y: &[f64], d: &mut [f64]| {
                d[0] = -3.0 * y[0];
                d[1] = 3.0 * y[0] - delta * 3.0 * y[0] * y[0];
            };
            let jac = move |_: f64, y: &[f64], j: &mut DMatrix<f64>| {
                j.copy_from_slice(&[-3.0, 3.0 - 6.0 * delta * y[0], 0.0, 0.0]);
                true
            };
            let sums = find(0.0, &[1.0, 0.0], &f, &jac);
            assert_eq!(!sums.is_empty(), found, "{delta}: {sums:?}");
        }
        let f = |_: f64, y: &[f64], d: &mut [f64]| {
            d[0] = -3.0 * y[0];
            d[1] = (1.0 - 1e-9) * 3.0 * y[0];
        };
        let jac = |_: f64, _: &[f64], j: &mut DMatrix<f64>| {
            j.copy_from_slice(&[-3.0, (1.0 - 1e-9) * 3.0, 0.0, 0.0]);
            true
        };
        let sums = find(0.0, &[1.0, 0.0], &f, &jac);
        assert_eq!(sums.len(), 1);
        assert!(
            (sums[0][0] - (1.0 - 1e-9)).abs() < 1e-15 && sums[0][1] == 1.0,
            "{sums:?}"
        );
    }

    /// Two sums at once (a chain A → B → C beside D ⇌ E): both found, in
    /// echelon form.
    #[test]
    fn two_sums_are_found_in_echelon_form() {
        let f = |_: f64, y: &[f64], d: &mut [f64]| {
            d[0] = -2.0 * y[0];
            d[1] = 2.0 * y[0] - 3.0 * y[1];
            d[2] = 3.0 * y[1];
            d[3] = -y[3] * y[3] + 0.5 * y[4];
            d[4] = y[3] * y[3] - 0.5 * y[4];
        };
        let jac = |_: f64, y: &[f64], j: &mut DMatrix<f64>| {
            j.fill(0.0);
            j[(0, 0)] = -2.0;
            j[(1, 0)] = 2.0;
            j[(1, 1)] = -3.0;
            j[(2, 1)] = 3.0;
            j[(3, 3)] = -2.0 * y[3];
            j[(3, 4)] = 0.5;
            j[(4, 3)] = 2.0 * y[3];
            j[(4, 4)] = -0.5;
            true
        };
        let sums = find(0.0, &[1.0, 0.0, 0.0, 0.3, 0.1], &f, &jac);
        assert_eq!(
            sums,
            vec![vec![1.0, 1.0, 1.0, 0.0, 0.0], vec![0.0, 0.0, 0.0, 1.0, 1.0]]
        );
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
            held.hold(&mut y, &w);
            for row in &c {
                let before = dot(row, &y0);
                let after = dot(row, &y);
                let size = row.iter().zip(&y0).map(|(a, b)| (a * b).abs()).sum::<f64>();
                prop_assert!((after - before).abs() <= 1e-12 * size.max(1.0), "{before} {after}");
            }
            let one = Held::new(vec![vec![0.0, 1.0, -1.0, -1.0]], &y0).unwrap();
            let mut z: Vec<f64> = y0.iter().zip(&drift).map(|(a, b)| a + b).collect();
            let z0 = z[0];
            one.hold(&mut z, &w);
            prop_assert_eq!(z[0], z0);
        }

        /// A random linear system with a planted fixed sum: the sum is
        /// found (up to scale) and nothing else.
        #[test]
        fn a_planted_sum_is_found(
            a in prop::collection::vec(-5.0f64..5.0, 9),
            c in prop::collection::vec(prop::sample::select(vec![-2.0, -1.0, 1.0, 2.0]), 3),
        ) {
            // f = M y with M = (I − c cᵀ/cᵀc)·A: cᵀ M = 0.
            let cc: f64 = c.iter().map(|x| x * x).sum();
            let am = DMatrix::from_row_slice(3, 3, &a);
            let cv = nalgebra::DVector::from_vec(c.clone());
            let p = DMatrix::identity(3, 3) - &cv * cv.transpose() / cc;
            let m = p * am;
            // Skip the rare draw whose M has rank below 2.
            let rank = m.clone().svd(false, false).singular_values.iter().filter(|s| **s > 1e-6).count();
            prop_assume!(rank == 2);
            let m2 = m.clone();
            let f = move |_: f64, y: &[f64], d: &mut [f64]| {
                let v = &m * nalgebra::DVector::from_column_slice(y);
                d.copy_from_slice(v.as_slice());
            };
            let jac = move |_: f64, _: &[f64], j: &mut DMatrix<f64>| {
                j.copy_from(&m2);
                true
            };
            let sums = find(0.0, &[1.0, 0.5, 0.25], &f, &jac);
            prop_assert_eq!(sums.len(), 1);
            let big = c.iter().fold(0.0f64, |x, v| x.max(v.abs()));
            let lead = c.iter().position(|v| *v != 0.0).unwrap();
            let scale = sums[0][lead] / (c[lead] / big);
            for (s, v) in sums[0].iter().zip(&c) {
                prop_assert!((s - scale * v / big).abs() < 1e-9, "{:?} {:?}", sums, c);
            }
        }
    }
}
