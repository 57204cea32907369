//! Sparse LU for the implicit methods on large systems whose Jacobian's
//! pattern no ordering makes a narrow band: a 2-D reaction–diffusion grid
//! (bandwidth about √n per species), an arrowhead (one variable coupled to
//! all), a ring with long-range links.
//!
//! The analysis is done once per run, since the pattern is fixed
//! ([`SparsePlan::plan`]): a fill-reducing order of the variables by
//! minimum degree on the symmetrised pattern (the elimination graph kept
//! explicitly, ties broken by the variable's index, so the order is
//! deterministic), the columns of the reordered matrix, and from the
//! degrees at elimination the fill and flops a factorisation costs when it
//! pivots on the diagonal. Each factorisation ([`SparseLu::new`]) is then
//! numeric: left-looking Gilbert–Peierls, column by column, each column a
//! sparse triangular solve over the pattern reached from its entries
//! through L's graph (a depth-first search, so the work is proportional to
//! the flops), with threshold partial pivoting: the diagonal is kept while
//! it is at least [`PIVOT_TOL`] of the column's largest candidate (so the
//! fill stays near the analysis's), else the largest is taken. Any
//! non-singular matrix is factored; a column with no non-zero candidate is
//! reported singular, as the dense LU reports it.
//!
//! The next matrix of the run (same pattern, new values) is refactored as
//! KLU does ([`SparseLu::refactor`]): the last factorisation's row pivots
//! and the patterns of its L and U are kept and only the values computed,
//! while every reused pivot passes the threshold a fresh factorisation
//! obeys; the first that does not, and the matrix is factored afresh with
//! pivoting (whose pivots the next refactor keeps), so a refactor never
//! solves worse than a fresh factorisation would.

use nalgebra::{ComplexField, DVector};
use std::collections::BTreeSet;

/// The diagonal stays the pivot while it is at least this fraction of the
/// column's largest candidate (KLU's default is 0.001; a tenth bounds the
/// growth of the factors more tightly at little cost in fill here).
pub const PIVOT_TOL: f64 = 0.1;

const NONE: usize = usize::MAX;

/// The analysis gives up once the factors would hold more than n²/4
/// entries, or this many on a small system (whose analysis is cheap
/// whatever its fill).
const FILL_FLOOR: usize = 4096;

/// The symbolic analysis of a pattern: the order and the columns.
#[derive(Debug, Clone, PartialEq)]
pub struct SparsePlan {
    /// `order[k]` is the variable in position k.
    pub order: Vec<usize>,
    /// Columns of the reordered pattern (the diagonal included): rows
    /// `row_idx[col_ptr[k]..col_ptr[k + 1]]` of column k, in positions.
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// Entries of L (below the diagonal) a diagonal-pivoting factorisation
    /// makes, fill included; U has as many above it.
    pub fill: usize,
    /// Multiply–adds of one such factorisation (Σ dₖ² over the degrees dₖ
    /// at elimination).
    pub flops: f64,
}

impl SparsePlan {
    /// The analysis of the pattern `rows` (`rows[i]`: the columns row i
    /// may have non-zero; the diagonal is always counted); `None` when an
    /// index is out of range or the factors would fill more than a quarter
    /// of a large matrix (dense is cheaper there, and the analysis stops
    /// before it costs more than one dense factorisation).
    pub fn plan(rows: &[Vec<usize>]) -> Option<SparsePlan> {
        let n = rows.len();
        if n == 0 || rows.iter().flatten().any(|&j| j >= n) {
            return None;
        }
        let (order, degrees) = min_degree(rows, (n * n / 4).max(FILL_FLOOR))?;
        let mut pos = vec![0; n];
        for (k, &v) in order.iter().enumerate() {
            pos[v] = k;
        }
        let mut cols: Vec<Vec<usize>> = (0..n).map(|k| vec![k]).collect();
        for (i, r) in rows.iter().enumerate() {
            for &j in r {
                cols[pos[j]].push(pos[i]);
            }
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for c in &mut cols {
            c.sort_unstable();
            c.dedup();
            row_idx.extend_from_slice(c);
            col_ptr.push(row_idx.len());
        }
        let fill = degrees.iter().sum();
        let flops = degrees.iter().map(|&d| (d * d) as f64).sum::<f64>() + n as f64;
        Some(SparsePlan {
            order,
            col_ptr,
            row_idx,
            fill,
            flops,
        })
    }

    pub fn n(&self) -> usize {
        self.order.len()
    }

    /// Entries of the reordered pattern.
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }
}

/// Minimum-degree order of the symmetrised pattern, with each variable's
/// degree when it was eliminated; `None` once the fill passes `cap`.
fn min_degree(rows: &[Vec<usize>], cap: usize) -> Option<(Vec<usize>, Vec<usize>)> {
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
    let mut queue: BTreeSet<(usize, usize)> = (0..n).map(|v| (adj[v].len(), v)).collect();
    let mut order = Vec::with_capacity(n);
    let mut degrees = Vec::with_capacity(n);
    let mut fill = 0usize;
    let mut merged = Vec::new();
    while let Some((d, v)) = queue.pop_first() {
        order.push(v);
        degrees.push(d);
        fill += d;
        if fill > cap {
            return None;
        }
        let nb = std::mem::take(&mut adj[v]);
        for &u in &nb {
            queue.remove(&(adj[u].len(), u));
            // adj[u] ← (adj[u] ∪ nb) \ {u, v}: the clique v leaves behind.
            merged.clear();
            let (a, b) = (&adj[u], &nb);
            let (mut p, mut q) = (0, 0);
            while p < a.len() || q < b.len() {
                let next = match (a.get(p), b.get(q)) {
                    (Some(&x), Some(&y)) if x == y => {
                        p += 1;
                        q += 1;
                        x
                    }
                    (Some(&x), Some(&y)) if x < y => {
                        p += 1;
                        x
                    }
                    (Some(&x), None) => {
                        p += 1;
                        x
                    }
                    (_, Some(&y)) => {
                        q += 1;
                        y
                    }
                    (None, None) => unreachable!(),
                };
                if next != u && next != v {
                    merged.push(next);
                }
            }
            std::mem::swap(&mut adj[u], &mut merged);
            queue.insert((adj[u].len(), u));
        }
    }
    Some((order, degrees))
}

/// LU factors with row pivoting of a matrix of the plan's pattern, in the
/// plan's order: P·(Q A Qᵀ) = L U with L unit lower triangular, both kept
/// by columns.
#[derive(Debug, Clone)]
pub struct SparseLu<T> {
    n: usize,
    /// L below the diagonal, rows in pivot positions.
    lp: Vec<usize>,
    li: Vec<usize>,
    lx: Vec<T>,
    /// U above the diagonal, and its diagonal.
    up: Vec<usize>,
    ui: Vec<usize>,
    ux: Vec<T>,
    udiag: Vec<T>,
    /// `rows[p]`: the variable whose equation is pivot row p.
    rows: Vec<usize>,
    /// `cols[k]`: the variable of column k (the plan's order).
    cols: Vec<usize>,
    /// `pinv[i]`: the pivot position of the plan's row i (what
    /// [`SparseLu::refactor`] reuses).
    pinv: Vec<usize>,
    invertible: bool,
}

/// How [`SparseLu::refactor`] went.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refactor {
    /// The previous pivots and pattern were kept.
    Reused,
    /// A reused pivot fell below [`PIVOT_TOL`] of its column (or the
    /// previous factors were singular): factored afresh, with pivoting.
    Fresh,
}

impl<T: ComplexField<RealField = f64> + Copy> SparseLu<T> {
    /// Factors the matrix whose entries in the plan's pattern are
    /// `entry(a, b)`, a and b variables (the rest must be zero).
    pub fn new(plan: &SparsePlan, entry: impl Fn(usize, usize) -> T) -> SparseLu<T> {
        let n = plan.n();
        let fill = plan.fill + plan.fill / 2 + n;
        let mut lu = SparseLu {
            n,
            lp: Vec::with_capacity(n + 1),
            li: Vec::with_capacity(fill),
            lx: Vec::with_capacity(fill),
            up: Vec::with_capacity(n + 1),
            ui: Vec::with_capacity(fill),
            ux: Vec::with_capacity(fill),
            udiag: vec![T::zero(); n],
            rows: Vec::new(),
            cols: plan.order.clone(),
            pinv: Vec::new(),
            invertible: true,
        };
        lu.lp.push(0);
        lu.up.push(0);
        let mut x = vec![T::zero(); n];
        // pinv[i]: the pivot position of row i (positions of Q A Qᵀ).
        let mut pinv = vec![NONE; n];
        let mut xi = vec![0usize; n];
        let mut mark = vec![NONE; n];
        let mut stack: Vec<(usize, usize)> = Vec::new();
        let o = &plan.order;
        for k in 0..n {
            let col = plan.col_ptr[k]..plan.col_ptr[k + 1];
            // The rows column k reaches through L's graph, in topological
            // order at xi[top..].
            let mut top = n;
            for &i in &plan.row_idx[col.clone()] {
                if mark[i] != k {
                    top = lu.reach(i, k, &pinv, &mut mark, &mut stack, &mut xi, top);
                }
            }
            for &i in &plan.row_idx[col] {
                x[i] = entry(o[i], o[k]);
            }
            for &j in &xi[top..] {
                let jn = pinv[j];
                if jn == NONE {
                    continue;
                }
                let xj = x[j];
                if xj == T::zero() {
                    continue;
                }
                for q in lu.lp[jn]..lu.lp[jn + 1] {
                    let r = lu.li[q];
                    x[r] -= lu.lx[q] * xj;
                }
            }
            let mut best = 0.0;
            let mut ipiv = NONE;
            for &i in &xi[top..] {
                if pinv[i] == NONE {
                    let m = x[i].modulus();
                    if m > best || ipiv == NONE {
                        best = m;
                        ipiv = i;
                    }
                } else {
                    lu.ui.push(pinv[i]);
                    lu.ux.push(x[i]);
                }
            }
            if best.is_nan() || best <= 0.0 {
                lu.invertible = false;
                return lu;
            }
            if pinv[k] == NONE && x[k].modulus() >= PIVOT_TOL * best {
                ipiv = k;
            }
            let pivot = x[ipiv];
            lu.udiag[k] = pivot;
            pinv[ipiv] = k;
            for &i in &xi[top..] {
                if pinv[i] == NONE {
                    lu.li.push(i);
                    lu.lx.push(x[i] / pivot);
                }
                x[i] = T::zero();
            }
            lu.lp.push(lu.li.len());
            lu.up.push(lu.ui.len());
        }
        for r in &mut lu.li {
            *r = pinv[*r];
        }
        lu.rows = vec![0; n];
        for (i, &p) in pinv.iter().enumerate() {
            lu.rows[p] = o[i];
        }
        lu.pinv = pinv;
        lu
    }

    /// Factors a new matrix of the same plan in place, as KLU's refactor
    /// does: the previous factorisation's row pivots and the patterns of
    /// its L and U are kept, and only the values are computed (no search
    /// of L's graph, no pivot search, no growth of the factors' vectors),
    /// column by column in
    /// the order the previous factorisation found U's entries (a
    /// topological order, so each is final when it is used).
    ///
    /// A reused pivot is kept only under the rule a fresh factorisation
    /// obeys: at least [`PIVOT_TOL`] of the largest candidate in its
    /// column (the rows not yet pivoted: the pivot's and L's), so the
    /// factors' growth is bounded as a fresh factorisation's is. The first
    /// column where it is not (or where it is zero or not finite), or
    /// previous factors that were singular, and the matrix is factored
    /// afresh with [`SparseLu::new`] ([`Refactor::Fresh`]), whose pivots
    /// the next refactor reuses. The pattern of the matrix's non-zeros is
    /// the plan's, as for [`SparseLu::new`], so the kept patterns hold
    /// every entry the new factors can have.
    pub fn refactor(&mut self, plan: &SparsePlan, entry: impl Fn(usize, usize) -> T) -> Refactor {
        if !self.invertible || self.n != plan.n() || self.pinv.len() != self.n {
            *self = SparseLu::new(plan, entry);
            return Refactor::Fresh;
        }
        let n = self.n;
        let o = &plan.order;
        // x in pivot positions; every entry set is cleared before the
        // next column.
        let mut x = vec![T::zero(); n];
        for k in 0..n {
            for &i in &plan.row_idx[plan.col_ptr[k]..plan.col_ptr[k + 1]] {
                x[self.pinv[i]] = entry(o[i], o[k]);
            }
            for q in self.up[k]..self.up[k + 1] {
                let j = self.ui[q];
                let xj = x[j];
                self.ux[q] = xj;
                x[j] = T::zero();
                if xj == T::zero() {
                    continue;
                }
                for r in self.lp[j]..self.lp[j + 1] {
                    let i = self.li[r];
                    x[i] -= self.lx[r] * xj;
                }
            }
            let pivot = x[k];
            x[k] = T::zero();
            let ls = self.lp[k]..self.lp[k + 1];
            let largest = self.li[ls.clone()]
                .iter()
                .fold(0.0f64, |m, &i| m.max(x[i].modulus()));
            let p = pivot.modulus();
            // NaN anywhere fails one of these.
            if !(p > 0.0 && p.is_finite() && largest.is_finite() && p >= PIVOT_TOL * largest) {
                *self = SparseLu::new(plan, entry);
                return Refactor::Fresh;
            }
            self.udiag[k] = pivot;
            for r in ls {
                let i = self.li[r];
                self.lx[r] = x[i] / pivot;
                x[i] = T::zero();
            }
        }
        Refactor::Reused
    }

    /// Depth-first search from row `start` through L's graph (row j leads
    /// to the rows of L's column pinv[j]); each row finished is put at
    /// `xi[top − 1]`, so `xi[top..]` ends in topological order.
    #[allow(clippy::too_many_arguments)]
    fn reach(
        &self,
        start: usize,
        k: usize,
        pinv: &[usize],
        mark: &mut [usize],
        stack: &mut Vec<(usize, usize)>,
        xi: &mut [usize],
        mut top: usize,
    ) -> usize {
        let first = |j: usize| match pinv[j] {
            NONE => 0,
            jn => self.lp[jn],
        };
        mark[start] = k;
        stack.push((start, first(start)));
        while let Some(&mut (j, ref mut p)) = stack.last_mut() {
            let end = match pinv[j] {
                NONE => 0,
                jn => self.lp[jn + 1],
            };
            let mut next = NONE;
            while *p < end {
                let r = self.li[*p];
                *p += 1;
                if mark[r] != k {
                    next = r;
                    break;
                }
            }
            if next == NONE {
                stack.pop();
                top -= 1;
                xi[top] = j;
            } else {
                mark[next] = k;
                stack.push((next, first(next)));
            }
        }
        top
    }

    pub fn is_invertible(&self) -> bool {
        self.invertible
    }

    /// Entries of L and U (the diagonal counted once).
    pub fn nnz(&self) -> usize {
        self.li.len() + self.ui.len() + self.n
    }

    /// Solves A x = b in place (b and x in the variables' order), with
    /// `scratch` for the permuted copy; false when A is singular.
    pub fn solve(&self, b: &mut DVector<T>, scratch: &mut Vec<T>) -> bool {
        if !self.invertible {
            return false;
        }
        scratch.clear();
        scratch.extend(self.rows.iter().map(|&v| b[v]));
        let y = scratch.as_mut_slice();
        for j in 0..self.n {
            let yj = y[j];
            if yj == T::zero() {
                continue;
            }
            for q in self.lp[j]..self.lp[j + 1] {
                y[self.li[q]] -= self.lx[q] * yj;
            }
        }
        for k in (0..self.n).rev() {
            let yk = y[k] / self.udiag[k];
            y[k] = yk;
            if yk == T::zero() {
                continue;
            }
            for q in self.up[k]..self.up[k + 1] {
                y[self.ui[q]] -= self.ux[q] * yk;
            }
        }
        for (&v, &y) in self.cols.iter().zip(y.iter()) {
            b[v] = y;
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Complex, DMatrix};
    use proptest::prelude::*;

    /// An arrowhead: variable 0 coupled both ways to every other.
    fn arrow(n: usize) -> Vec<Vec<usize>> {
        (0..n)
            .map(|i| if i == 0 { (0..n).collect() } else { vec![0, i] })
            .collect()
    }

    #[test]
    fn minimum_degree_leaves_the_hub_of_an_arrowhead_to_the_end_without_fill() {
        let plan = SparsePlan::plan(&arrow(50)).unwrap();
        // The hub goes when one leaf is left (a tie of degree 1 then).
        assert!(plan.order[48..].contains(&0), "{:?}", plan.order);
        // Each leaf has one neighbour when it goes: 49 entries of L, no fill.
        assert_eq!(plan.fill, 49);
        assert_eq!(plan.nnz(), 50 + 2 * 49);
    }

    #[test]
    fn a_full_pattern_is_not_planned_and_bad_indices_are_refused() {
        let full: Vec<Vec<usize>> = (0..200).map(|_| (0..200).collect()).collect();
        assert_eq!(SparsePlan::plan(&full), None);
        assert_eq!(SparsePlan::plan(&[vec![0, 3], vec![1]]), None);
    }

    fn dense_of(rows: &[Vec<usize>], value: impl Fn(usize, usize) -> f64) -> DMatrix<f64> {
        let n = rows.len();
        let mut a = DMatrix::zeros(n, n);
        for (i, cols) in rows.iter().enumerate() {
            a[(i, i)] = value(i, i);
            for &j in cols {
                a[(i, j)] = value(i, j);
            }
        }
        a
    }

    /// A random sparse pattern of n rows, each with up to `per_row` entries.
    fn pattern(n: usize, per_row: usize) -> impl Strategy<Value = Vec<Vec<usize>>> {
        prop::collection::vec(prop::collection::vec(0..n, 0..=per_row), n)
    }

    /// The condition number of a, by its singular values.
    fn condition<T: ComplexField<RealField = f64>>(a: &DMatrix<T>) -> f64 {
        let s = a.clone().singular_values();
        s.max() / s.min()
    }

    /// The sparse solve of a x = b against nalgebra's dense LU: the same
    /// answer to the accuracy the condition number allows, or, for a
    /// matrix singular to working precision, no answer from either or
    /// answers that agree in residual.
    fn check<T: ComplexField<RealField = f64> + Copy>(
        rows: &[Vec<usize>],
        a: &DMatrix<T>,
        b: &[T],
    ) -> Result<(), TestCaseError> {
        let plan = SparsePlan::plan(rows).unwrap();
        check_lu(&SparseLu::new(&plan, |i, j| a[(i, j)]), a, b)
    }

    /// As `check`, for the factors `lu` of `a` however they were made.
    fn check_lu<T: ComplexField<RealField = f64> + Copy>(
        lu: &SparseLu<T>,
        a: &DMatrix<T>,
        b: &[T],
    ) -> Result<(), TestCaseError> {
        let dense = a.clone().lu();
        let bv = DVector::from_column_slice(b);
        let cond = condition(a);
        if cond.is_nan() || cond >= 1e10 {
            // Singular to working precision: the two may disagree on
            // whether a tiny pivot is zero; neither may panic.
            let mut x = bv.clone();
            let _ = lu.solve(&mut x, &mut Vec::new());
            return Ok(());
        }
        prop_assert!(dense.is_invertible());
        prop_assert!(lu.is_invertible(), "cond {cond:e}");
        let want = dense.solve(&bv).unwrap();
        let mut got = bv.clone();
        prop_assert!(lu.solve(&mut got, &mut Vec::new()));
        let r = a * &got - &bv;
        let scale = a.camax() * want.camax() + bv.camax();
        prop_assert!(r.camax() <= 1e-12 * scale, "residual {}", r.camax());
        let diff = (&got - &want).camax();
        prop_assert!(
            diff <= 1e-14 * cond * want.camax().max(1.0),
            "{diff:e} at condition {cond:e}"
        );
        Ok(())
    }

    fn check_real(rows: &[Vec<usize>], a: &DMatrix<f64>, b: &[f64]) -> Result<(), TestCaseError> {
        check(rows, a, b)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]

        /// Random patterns and values, with the diagonal zero on a third of
        /// the rows and small on the rest when `weak` is near 1, so rows
        /// must be swapped: the sparse solve equals nalgebra's dense LU,
        /// real and complex (a shifted matrix as Radau forms it).
        #[test]
        fn sparse_solves_match_dense_lu(
            rows in pattern(24, 4),
            seed in any::<u64>(),
            weak in 0.0..1.0f64,
        ) {
            let n = rows.len();
            let h = |i: usize, j: usize, s: u64| {
                let x = ((i as u64).wrapping_mul(2654435761) ^ (j as u64).wrapping_mul(40503) ^ seed ^ s)
                    .wrapping_mul(0x9E3779B97F4A7C15);
                (x >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
            };
            let value = |i: usize, j: usize| {
                if i == j {
                    if (i as u64).wrapping_add(seed).is_multiple_of(3) { 0.0 } else { (1.0 - weak) * 4.0 * h(i, j, 1) }
                } else {
                    h(i, j, 2)
                }
            };
            let a = dense_of(&rows, value);
            let b: Vec<f64> = (0..n).map(|i| h(i, i, 3)).collect();
            check_real(&rows, &a, &b)?;

            let shift = Complex::new(weak - 0.5, 2.0 * h(0, 0, 4));
            let ca = DMatrix::from_fn(n, n, |i, j| {
                let v = Complex::new(-a[(i, j)], h(i, j, 5) * a[(i, j)]);
                if i == j { v + shift } else { v }
            });
            let cb: Vec<Complex<f64>> = b.iter().map(|&x| Complex::new(x, -0.5 * x)).collect();
            check(&rows, &ca, &cb)?;
        }
    }

    /// A value in [−1, 1) from a position and a seed.
    fn hash(i: usize, j: usize, seed: u64, s: u64) -> f64 {
        let x = ((i as u64).wrapping_mul(2654435761) ^ (j as u64).wrapping_mul(40503) ^ seed ^ s)
            .wrapping_mul(0x9E3779B97F4A7C15);
        (x >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }

    /// Values on `rows`' pattern whose diagonal is zero on a third of the
    /// rows (which third follows `seed`) and small on the rest when `weak`
    /// is near 1.
    fn values(rows: &[Vec<usize>], seed: u64, weak: f64) -> DMatrix<f64> {
        dense_of(rows, |i, j| {
            if i == j {
                if (i as u64).wrapping_add(seed).is_multiple_of(3) {
                    0.0
                } else {
                    (1.0 - weak) * 4.0 * hash(i, j, seed, 1)
                }
            } else {
                hash(i, j, seed, 2)
            }
        })
    }

    /// The complex matrix Radau forms from a real one: −a with an
    /// imaginary part, shifted on the diagonal.
    fn shifted(a: &DMatrix<f64>, seed: u64, weak: f64) -> DMatrix<Complex<f64>> {
        let shift = Complex::new(weak - 0.5, 2.0 * hash(0, 0, seed, 4));
        DMatrix::from_fn(a.nrows(), a.ncols(), |i, j| {
            let v = Complex::new(-a[(i, j)], hash(i, j, seed, 5) * a[(i, j)]);
            if i == j { v + shift } else { v }
        })
    }

    /// Refactors `lu` (factors of an earlier matrix of the plan) onto `a`
    /// and checks the solve against the dense LU; then a refactor of the
    /// same matrix on the pivots it now has must be done in place and give
    /// the same factors to the bit (the same operations in the same order).
    fn check_refactor<T: ComplexField<RealField = f64> + Copy + PartialEq + std::fmt::Debug>(
        plan: &SparsePlan,
        lu: &mut SparseLu<T>,
        a: &DMatrix<T>,
        b: &[T],
    ) -> Result<Refactor, TestCaseError> {
        let how = lu.refactor(plan, |i, j| a[(i, j)]);
        check_lu(lu, a, b)?;
        if lu.is_invertible() {
            let before = (
                lu.lx.clone(),
                lu.ux.clone(),
                lu.udiag.clone(),
                lu.rows.clone(),
            );
            prop_assert_eq!(lu.refactor(plan, |i, j| a[(i, j)]), Refactor::Reused);
            let after = (
                lu.lx.clone(),
                lu.ux.clone(),
                lu.udiag.clone(),
                lu.rows.clone(),
            );
            prop_assert_eq!(after, before);
        }
        Ok(how)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]

        /// Three matrices of one pattern factored in turn, each on the
        /// last one's pivots (as Radau refactors its Newton matrices): the
        /// diagonal zero on a different third of the rows, or weaker, makes
        /// a reused pivot too small and the refactor starts afresh; either
        /// way the solve equals nalgebra's dense LU, real and complex.
        #[test]
        fn refactor_solves_match_dense_lu(
            rows in pattern(24, 4),
            seeds in prop::array::uniform3(any::<u64>()),
            weak in prop::array::uniform3(0.0..1.0f64),
        ) {
            let plan = SparsePlan::plan(&rows).unwrap();
            let n = rows.len();
            let a: Vec<DMatrix<f64>> = (0..3).map(|k| values(&rows, seeds[k], weak[k])).collect();
            let b: Vec<f64> = (0..n).map(|i| hash(i, i, seeds[0], 3)).collect();
            let mut lu = SparseLu::new(&plan, |i, j| a[0][(i, j)]);
            for m in &a[1..] {
                check_refactor(&plan, &mut lu, m, &b)?;
            }
            let ca: Vec<DMatrix<Complex<f64>>> =
                (0..3).map(|k| shifted(&a[k], seeds[k], weak[k])).collect();
            let cb: Vec<Complex<f64>> = b.iter().map(|&x| Complex::new(x, -0.5 * x)).collect();
            let mut clu = SparseLu::new(&plan, |i, j| ca[0][(i, j)]);
            for m in &ca[1..] {
                check_refactor(&plan, &mut clu, m, &cb)?;
            }
        }
    }

    /// A reused pivot is kept down to a tenth of its column's largest
    /// candidate and factored afresh, on another row, below that; factors
    /// that were singular are never reused.
    #[test]
    fn a_reused_pivot_below_the_threshold_is_factored_afresh() {
        // Two coupled variables (the order is 0, 1: a tie broken by index).
        let rows = vec![vec![0, 1], vec![0, 1]];
        let plan = SparsePlan::plan(&rows).unwrap();
        assert_eq!(plan.order, [0, 1]);
        let m = |d: f64| {
            dense_of(&rows, move |i, j| {
                if i == j && i == 0 {
                    d
                } else {
                    1.0 + (i + 2 * j) as f64
                }
            })
        };
        let b = [1.0, -2.0];
        let first = m(1.0);
        let mut lu = SparseLu::new(&plan, |i, j| first[(i, j)]);
        assert_eq!(lu.rows, [0, 1], "the diagonal pivots");
        let next = |lu: &mut SparseLu<f64>, d: f64| {
            let a = m(d);
            let how = lu.refactor(&plan, |i, j| a[(i, j)]);
            check_lu(lu, &a, &b).unwrap();
            how
        };
        // Column 0's candidates are d and a[(1, 0)] = 2.
        assert_eq!(next(&mut lu, 0.2), Refactor::Reused);
        assert_eq!(lu.rows, [0, 1]);
        assert_eq!(next(&mut lu, -0.2), Refactor::Reused);
        assert_eq!(next(&mut lu, 0.199), Refactor::Fresh);
        assert_eq!(lu.rows, [1, 0], "row 1 pivots now");
        // The new pivot (2) is reused whatever the diagonal, down to zero.
        assert_eq!(next(&mut lu, 19.9), Refactor::Reused);
        assert_eq!(next(&mut lu, 0.0), Refactor::Reused);
        assert_eq!(lu.rows, [1, 0]);
        // Past 20 the diagonal is over ten times row 1's: afresh, on it.
        assert_eq!(next(&mut lu, 20.5), Refactor::Fresh);
        assert_eq!(lu.rows, [0, 1]);
        // Not finite: afresh, and reported singular as a fresh one is.
        assert_eq!(lu.refactor(&plan, |_, _| f64::NAN), Refactor::Fresh);
        assert!(!lu.is_invertible());
        assert_eq!(next(&mut lu, 1.0), Refactor::Fresh);
        assert!(lu.is_invertible());
    }

    /// A matrix whose diagonal is zero everywhere (a permutation's pattern
    /// plus the diagonal): only row swaps factor it.
    #[test]
    fn a_zero_diagonal_is_pivoted_around() {
        let n = 40;
        let rows: Vec<Vec<usize>> = (0..n).map(|i| vec![(i * 7 + 3) % n, 0]).collect();
        let a = dense_of(&rows, |i, j| {
            if i == j {
                0.0
            } else {
                1.0 + (i + 2 * j) as f64 / 10.0
            }
        });
        let b: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        check_real(&rows, &a, &b).unwrap();
    }

    #[test]
    fn a_zero_column_is_singular() {
        let rows = arrow(30);
        let plan = SparsePlan::plan(&rows).unwrap();
        let lu = SparseLu::new(&plan, |i, j| if j == 5 { 0.0 } else { 1.0 + i as f64 });
        assert!(!lu.is_invertible());
        assert!(!lu.solve(&mut DVector::zeros(30), &mut Vec::new()));
        // Two equal rows: singular once the first is eliminated, exactly.
        let rows: Vec<Vec<usize>> = (0..30)
            .map(|i| match i {
                3 | 4 => vec![3, 4],
                _ => vec![i],
            })
            .collect();
        let plan = SparsePlan::plan(&rows).unwrap();
        let lu = SparseLu::new(&plan, |i, j| match (i, j) {
            (3 | 4, 3) => 1.0,
            (3 | 4, 4) => 2.0,
            _ => 1.0,
        });
        assert!(!lu.is_invertible());
    }
}
