//! Banded LU for the implicit methods on large sparse systems.
//!
//! Radau IIA factors one real and one complex n×n matrix (γ/h − J and
//! (α + iβ)/h − J) whenever the step or the Jacobian changes. Dense, that
//! costs about n³/3 each: on a 200-variable reaction–diffusion system
//! (the Brusselator) it is most of the run. The Jacobian of such a system
//! is sparse, and its pattern is known from the equations
//! ([`crate::rhs::OdeSystem::sparsity`]); reordered by reverse
//! Cuthill–McKee it is banded with a few diagonals either side, and a
//! banded LU with partial pivoting (LAPACK's `gbtrf` layout: the upper band
//! widened by the lower one for the row swaps) costs n·kl·(kl + ku).
//!
//! [`Band::plan`] picks the ordering (the variables' own or RCM's, the
//! narrower) and says whether the band is worth it; small systems keep the
//! dense LU, which is faster there.

use nalgebra::ComplexField;

/// Systems of at most this many variables keep the dense LU.
pub const DENSE_MAX: usize = 20;

/// An ordering of the variables under which the Jacobian is banded.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Band {
    /// `order[k]` is the variable in position k.
    pub order: Vec<usize>,
    /// Sub- and super-diagonals of the reordered pattern.
    pub kl: usize,
    pub ku: usize,
}

impl Band {
    /// The band of the pattern `rows` (`rows[i]`: the columns row i may
    /// have non-zero; the diagonal is always counted) under the
    /// variables' own order and under reverse Cuthill–McKee, the narrower;
    /// `None` when the system is small or the band costs as much as dense.
    pub fn plan(rows: &[Vec<usize>]) -> Option<Band> {
        let n = rows.len();
        if n <= DENSE_MAX {
            return None;
        }
        Band::narrowest(rows).filter(|b| b.cost() * 4.0 < Band::dense_cost(n))
    }

    /// The narrower band of the two orders, whatever its width; `None`
    /// when an index is out of range.
    pub fn narrowest(rows: &[Vec<usize>]) -> Option<Band> {
        let n = rows.len();
        if n == 0 || rows.iter().flatten().any(|&j| j >= n) {
            return None;
        }
        let own = Band::with_order(rows, (0..n).collect());
        let rcm = Band::with_order(rows, rcm(rows));
        Some(if rcm.cost() < own.cost() { rcm } else { own })
    }

    /// Multiply–adds of one solve with the factors (about).
    pub fn solve_cost(&self) -> f64 {
        (self.order.len() * (2 * self.kl + self.ku + 1)) as f64
    }

    /// Flops of one banded LU of this band (about).
    pub fn cost(&self) -> f64 {
        let n = self.order.len() as f64;
        n * (self.kl as f64 + 1.0) * (self.kl + self.ku + 1) as f64
    }

    /// Flops of one dense LU of n×n (about).
    pub fn dense_cost(n: usize) -> f64 {
        let n = n as f64;
        n * n * n / 3.0
    }

    fn with_order(rows: &[Vec<usize>], order: Vec<usize>) -> Band {
        let mut pos = vec![0; order.len()];
        for (k, &v) in order.iter().enumerate() {
            pos[v] = k;
        }
        let (mut kl, mut ku) = (0, 0);
        for (i, cols) in rows.iter().enumerate() {
            for &j in cols {
                let (pi, pj) = (pos[i], pos[j]);
                kl = kl.max(pi.saturating_sub(pj));
                ku = ku.max(pj.saturating_sub(pi));
            }
        }
        Band { order, kl, ku }
    }
}

/// Reverse Cuthill–McKee ordering of the symmetrised pattern: each
/// connected part from a vertex of least degree, neighbours by degree.
fn rcm(rows: &[Vec<usize>]) -> Vec<usize> {
    let n = rows.len();
    let mut adj: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (i, cols) in rows.iter().enumerate() {
        for &j in cols {
            if i != j {
                adj[i].push(j);
                adj[j].push(i);
            }
        }
    }
    for a in &mut adj {
        a.sort_unstable();
        a.dedup();
    }
    let degree: Vec<usize> = adj.iter().map(Vec::len).collect();
    let mut by_degree: Vec<usize> = (0..n).collect();
    by_degree.sort_by_key(|&v| (degree[v], v));
    let mut seen = vec![false; n];
    let mut order = Vec::with_capacity(n);
    for &start in &by_degree {
        if seen[start] {
            continue;
        }
        seen[start] = true;
        let mut head = order.len();
        order.push(start);
        while head < order.len() {
            let v = order[head];
            head += 1;
            let mut next: Vec<usize> = adj[v].iter().copied().filter(|&w| !seen[w]).collect();
            next.sort_by_key(|&w| (degree[w], w));
            for w in next {
                seen[w] = true;
                order.push(w);
            }
        }
    }
    order.reverse();
    order
}

/// LU factors (with partial pivoting) of a banded matrix, stored by rows:
/// row i holds columns i − kl ..= i + kl + ku.
#[derive(Debug, Clone)]
pub struct BandLu<T> {
    n: usize,
    kl: usize,
    ku: usize,
    a: Vec<T>,
    piv: Vec<usize>,
    /// No zero pivot was met.
    invertible: bool,
}

impl<T: ComplexField<RealField = f64> + Copy> BandLu<T> {
    /// Factors the n×n matrix whose entries inside the band (`kl` below,
    /// `ku` above the diagonal) are `entry(i, j)`; the entries outside it
    /// must be zero.
    pub fn new(n: usize, kl: usize, ku: usize, entry: impl Fn(usize, usize) -> T) -> BandLu<T> {
        let w = 2 * kl + ku + 1;
        let mut lu = BandLu {
            n,
            kl,
            ku,
            a: vec![T::zero(); n * w],
            piv: vec![0; n],
            invertible: true,
        };
        for i in 0..n {
            for j in i.saturating_sub(kl)..=(i + ku).min(n - 1) {
                *lu.at(i, j) = entry(i, j);
            }
        }
        lu.factor();
        lu
    }

    #[inline]
    fn idx(&self, i: usize, j: usize) -> usize {
        i * (2 * self.kl + self.ku + 1) + (j + self.kl - i)
    }

    #[inline]
    fn at(&mut self, i: usize, j: usize) -> &mut T {
        let k = self.idx(i, j);
        &mut self.a[k]
    }

    #[inline]
    fn get(&self, i: usize, j: usize) -> T {
        self.a[self.idx(i, j)]
    }

    fn factor(&mut self) {
        let (n, kl) = (self.n, self.kl);
        let reach = kl + self.ku;
        for k in 0..n {
            let last = (k + kl).min(n - 1);
            let mut p = k;
            let mut best = self.get(k, k).modulus();
            for i in k + 1..=last {
                let m = self.get(i, k).modulus();
                if m > best {
                    best = m;
                    p = i;
                }
            }
            self.piv[k] = p;
            if best == 0.0 {
                self.invertible = false;
                continue;
            }
            let right = (k + reach).min(n - 1);
            if p != k {
                for j in k..=right {
                    let (x, y) = (self.idx(k, j), self.idx(p, j));
                    self.a.swap(x, y);
                }
            }
            let pivot = self.get(k, k);
            for i in k + 1..=last {
                let l = self.get(i, k) / pivot;
                *self.at(i, k) = l;
                if l == T::zero() {
                    continue;
                }
                for j in k + 1..=right {
                    let u = self.get(k, j);
                    *self.at(i, j) -= l * u;
                }
            }
        }
    }

    pub fn is_invertible(&self) -> bool {
        self.invertible
    }

    /// Solves in place; false when the matrix is singular.
    #[allow(clippy::needless_range_loop)] // the band's (i, j) indexing
    pub fn solve_mut(&self, b: &mut [T]) -> bool {
        if !self.invertible {
            return false;
        }
        let (n, kl) = (self.n, self.kl);
        let reach = kl + self.ku;
        for k in 0..n {
            b.swap(k, self.piv[k]);
            let bk = b[k];
            for i in k + 1..=(k + kl).min(n - 1) {
                b[i] -= self.get(i, k) * bk;
            }
        }
        for k in (0..n).rev() {
            let mut s = b[k];
            for j in k + 1..=(k + reach).min(n - 1) {
                s -= self.get(k, j) * b[j];
            }
            b[k] = s / self.get(k, k);
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Complex, DMatrix, DVector};

    /// The Brusselator's pattern, u1..uN then v1..vN: tridiagonal blocks
    /// coupled by their diagonals.
    fn ladder(m: usize) -> Vec<Vec<usize>> {
        (0..2 * m)
            .map(|i| {
                let (b, k) = (i / m * m, i % m);
                let mut c = vec![b + k, (i + m) % (2 * m)];
                if k > 0 {
                    c.push(b + k - 1);
                }
                if k + 1 < m {
                    c.push(b + k + 1);
                }
                c
            })
            .collect()
    }

    #[test]
    fn rcm_narrows_the_ladder_and_small_systems_stay_dense() {
        assert_eq!(Band::plan(&ladder(10)), None);
        let band = Band::plan(&ladder(100)).expect("a band");
        assert!(band.kl <= 3 && band.ku <= 3, "{band:?}");
        let mut sorted = band.order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..200).collect::<Vec<_>>());
        // A full pattern is not worth a band.
        let full: Vec<Vec<usize>> = (0..30).map(|_| (0..30).collect()).collect();
        assert_eq!(Band::plan(&full), None);
    }

    /// The banded solve of a reordered sparse matrix (which needs row
    /// swaps: small diagonal) equals nalgebra's dense LU, real and complex.
    #[test]
    fn banded_solves_match_dense_lu() {
        let m = 40;
        let rows = ladder(m);
        let n = 2 * m;
        let band = Band::plan(&rows).unwrap();
        let value = |i: usize, j: usize| {
            if i == j {
                0.01 * (i as f64 + 1.0).sin()
            } else {
                ((3 * i + 7 * j) as f64).cos() + 0.5
            }
        };
        let mut jac = DMatrix::zeros(n, n);
        for (i, cols) in rows.iter().enumerate() {
            for &j in cols {
                jac[(i, j)] = value(i, j);
            }
        }
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).cos()).collect();
        let o = &band.order;
        let lu = BandLu::new(n, band.kl, band.ku, |i, j| jac[(o[i], o[j])]);
        let mut x: Vec<f64> = o.iter().map(|&v| b[v]).collect();
        assert!(lu.solve_mut(&mut x));
        let dense = jac
            .clone()
            .lu()
            .solve(&DVector::from_vec(b.clone()))
            .unwrap();
        for (k, &v) in o.iter().enumerate() {
            assert!((x[k] - dense[v]).abs() <= 1e-10 * dense.amax(), "{k}");
        }
        let shift = Complex::new(0.3, 2.0);
        let cjac = DMatrix::from_fn(n, n, |i, j| {
            Complex::new(-jac[(i, j)], 0.0)
                + if i == j {
                    shift
                } else {
                    Complex::new(0.0, 0.0)
                }
        });
        let cb: Vec<Complex<f64>> = b.iter().map(|&x| Complex::new(x, -x)).collect();
        let clu = BandLu::new(n, band.kl, band.ku, |i, j| cjac[(o[i], o[j])]);
        let mut cx: Vec<Complex<f64>> = o.iter().map(|&v| cb[v]).collect();
        assert!(clu.solve_mut(&mut cx));
        let cdense = cjac.lu().solve(&DVector::from_vec(cb)).unwrap();
        for (k, &v) in o.iter().enumerate() {
            assert!((cx[k] - cdense[v]).norm() <= 1e-10, "{k}");
        }
    }

    #[test]
    fn a_zero_column_is_singular() {
        let lu = BandLu::new(
            25,
            1,
            1,
            |i, j| if j == 3 { 0.0 } else { (i + j) as f64 + 1.0 },
        );
        assert!(!lu.is_invertible());
        assert!(!lu.solve_mut(&mut [0.0; 25]));
    }
}
