//! How the implicit methods factor their Newton matrices: dense, banded
//! ([`super::band`]) or sparse ([`super::sparse`]), chosen once per run
//! from the Jacobian's pattern by estimated cost, and the factors of one
//! step in that form.
//!
//! Radau IIA factors γ/h − J (real) and (α + iβ)/h − J (complex) whenever
//! the step or the Jacobian changes, and solves with both at each Newton
//! iteration. The cost of a choice is one factorisation and
//! [`SOLVES_PER_LU`] solves, in multiply–adds, weighted by what a
//! multiply–add costs in that form (contiguous dense loops are the
//! fastest per operation, the sparse factor's indirect ones the slowest;
//! the weights are measured, see [`BAND_WEIGHT`], [`SPARSE_WEIGHT`]).

use nalgebra::{Complex, DMatrix, DVector, Dyn, LU};

use super::band::{Band, BandLu, DENSE_MAX};
use super::sparse::{Refactor, SparseLu, SparsePlan};

/// The forms of the Newton matrices' LU, as `--stats` and the JSON
/// diagnostics name them (`"lu"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LuKind {
    /// The whole n×n matrix (small systems, or no pattern worth using).
    Dense,
    /// A band after reordering by reverse Cuthill–McKee.
    Banded,
    /// Sparse, in a minimum-degree order, with partial pivoting.
    Sparse,
}

impl LuKind {
    pub const ALL: [LuKind; 3] = [LuKind::Dense, LuKind::Banded, LuKind::Sparse];

    /// The word the diagnostics print.
    pub fn name(self) -> &'static str {
        match self {
            LuKind::Dense => "dense",
            LuKind::Banded => "banded",
            LuKind::Sparse => "sparse",
        }
    }

    /// What it means, for the documentation of the diagnostics.
    pub fn help(self) -> &'static str {
        match self {
            LuKind::Dense => "dense LU of the n×n Newton matrices",
            LuKind::Banded => {
                "banded LU, the variables reordered by reverse Cuthill–McKee into a narrow band"
            }
            LuKind::Sparse => {
                "sparse LU (Gilbert–Peierls with partial pivoting) in a minimum-degree order"
            }
        }
    }
}

/// Solves per factorisation the cost counts (Newton iterations and the
/// error estimate of a step, a factorisation every step or two).
pub const SOLVES_PER_LU: f64 = 4.0;
/// Time of a banded multiply–add over a dense one (row-major band with
/// index arithmetic). Measured with `lu_weights_are_measured` (ignored
/// test; `cargo test -p flipcard-sim --lib lu_weights -- --ignored
/// --nocapture`, the simulator is optimised in test builds): per estimated
/// multiply–add, dense 6.3–6.5 ns, banded 9.9 ns (1-D Brusselator, 200
/// variables) and 13 ns (15×15 grid).
pub const BAND_WEIGHT: f64 = 2.0;
/// Time of a sparse multiply–add over a dense one (indirect addressing,
/// the depth-first search of each column), measured the same way: 14 ns on
/// the grid, 36 ns on the 1-D Brusselator, whose factors are so thin that
/// the per-entry work dominates. With these weights the 1-D Brusselator
/// stays banded (the two forms took 0.030 and 0.036 ms a factorisation)
/// and the grid goes sparse (1.9 ms against 11 ms banded, 197 ms dense).
pub const SPARSE_WEIGHT: f64 = 4.0;

/// The form chosen for a run, with its analysis.
#[derive(Debug, Clone)]
pub enum LuPlan {
    Dense,
    Banded(Band),
    Sparse(SparsePlan),
}

impl LuPlan {
    /// The cheapest form for a system of `n` variables whose Jacobian has
    /// the pattern `rows` (`None`: unknown, so dense). Small systems
    /// ([`DENSE_MAX`] variables or fewer) stay dense.
    pub fn choose(n: usize, rows: Option<&[Vec<usize>]>) -> LuPlan {
        let Some(rows) = rows.filter(|r| r.len() == n && n > DENSE_MAX) else {
            return LuPlan::Dense;
        };
        let mut best = LuPlan::Dense;
        let mut cost = best.cost(n);
        let candidates = [
            Band::narrowest(rows).map(LuPlan::Banded),
            SparsePlan::plan(rows).map(LuPlan::Sparse),
        ];
        for plan in candidates.into_iter().flatten() {
            let c = plan.cost(n);
            if c < cost {
                (best, cost) = (plan, c);
            }
        }
        best
    }

    /// The form `kind` for this pattern whatever its cost (to compare the
    /// forms on one problem); `None` when it has no pattern for it.
    pub fn forced(kind: LuKind, n: usize, rows: Option<&[Vec<usize>]>) -> Option<LuPlan> {
        let rows = rows.filter(|r| r.len() == n);
        match kind {
            LuKind::Dense => Some(LuPlan::Dense),
            LuKind::Banded => Band::narrowest(rows?).map(LuPlan::Banded),
            LuKind::Sparse => SparsePlan::plan(rows?).map(LuPlan::Sparse),
        }
    }

    pub fn kind(&self) -> LuKind {
        match self {
            LuPlan::Dense => LuKind::Dense,
            LuPlan::Banded(_) => LuKind::Banded,
            LuPlan::Sparse(_) => LuKind::Sparse,
        }
    }

    /// What a multiply–add of this form costs over a dense one.
    fn weight(&self) -> f64 {
        match self {
            LuPlan::Dense => 1.0,
            LuPlan::Banded(_) => BAND_WEIGHT,
            LuPlan::Sparse(_) => SPARSE_WEIGHT,
        }
    }

    /// Multiply–adds of one factorisation (about; dense n³/3).
    pub fn flops(&self, n: usize) -> f64 {
        match self {
            LuPlan::Dense => Band::dense_cost(n),
            LuPlan::Banded(b) => b.cost(),
            LuPlan::Sparse(s) => s.flops,
        }
    }

    /// What factoring the real and the complex Newton matrix in this form
    /// costs in evaluations of f, for `auto`'s comparison of the methods'
    /// costs: the weighted multiply–adds of the pair (a complex one is
    /// about four real ones) against ~10n for an f of n short equations,
    /// plus one; dense, 1 + n²/6.
    pub fn pair_in_evaluations(&self, n: usize) -> f64 {
        1.0 + 5.0 * self.weight() * self.flops(n) / (10.0 * n.max(1) as f64)
    }

    /// The weighted cost of one factorisation and [`SOLVES_PER_LU`]
    /// solves, in dense multiply–adds.
    pub fn cost(&self, n: usize) -> f64 {
        let solve = match self {
            LuPlan::Dense => (n * n) as f64,
            LuPlan::Banded(b) => b.solve_cost(),
            LuPlan::Sparse(s) => (2 * s.fill + s.nnz()) as f64,
        };
        self.weight() * (self.flops(n) + SOLVES_PER_LU * solve)
    }

    /// The factors of γ − J (real; γ = `fac1`) and (α + iβ) − J (complex),
    /// J the n×n Jacobian.
    pub fn factor(&self, jac: &DMatrix<f64>, fac1: f64, alpha: f64, beta: f64) -> Factors {
        self.refactor(None, jac, fac1, alpha, beta).0
    }

    /// As [`LuPlan::factor`], reusing `previous` (this plan's factors of
    /// an earlier step) where the form allows: a sparse LU keeps its pivot
    /// order and its factors' patterns while every reused pivot passes the
    /// threshold a fresh factorisation obeys, and is factored afresh
    /// otherwise ([`SparseLu::refactor`]). With how many of the two
    /// matrices were refactored in place.
    pub fn refactor(
        &self,
        previous: Option<Factors>,
        jac: &DMatrix<f64>,
        fac1: f64,
        alpha: f64,
        beta: f64,
    ) -> (Factors, Reuse) {
        let n = jac.nrows();
        let real = |i: usize, j: usize| {
            let v = -jac[(i, j)];
            if i == j { fac1 + v } else { v }
        };
        let complex = |i: usize, j: usize| {
            let v = -jac[(i, j)];
            if i == j {
                Complex::new(alpha + v, beta)
            } else {
                Complex::new(v, 0.0)
            }
        };
        if let (LuPlan::Sparse(plan), Some(Factors::Sparse(mut f))) = (self, previous) {
            let counts = [f.0.refactor(plan, real), f.1.refactor(plan, complex)];
            let reused = counts.iter().filter(|&&r| r == Refactor::Reused).count();
            let reuse = Reuse {
                reused: reused as u64,
                fresh: (2 - reused) as u64,
            };
            return (Factors::Sparse(f), reuse);
        }
        let fresh = Reuse {
            reused: 0,
            fresh: u64::from(matches!(self, LuPlan::Sparse(_))) * 2,
        };
        let factors = match self {
            LuPlan::Dense => Factors::Dense(
                DMatrix::from_fn(n, n, real).lu(),
                DMatrix::from_fn(n, n, complex).lu(),
            ),
            LuPlan::Banded(band) => {
                let o = &band.order;
                Factors::Banded(
                    o.clone(),
                    BandLu::new(n, band.kl, band.ku, |i, j| real(o[i], o[j])),
                    BandLu::new(n, band.kl, band.ku, |i, j| complex(o[i], o[j])),
                )
            }
            LuPlan::Sparse(plan) => Factors::Sparse(Box::new((
                SparseLu::new(plan, real),
                SparseLu::new(plan, complex),
            ))),
        };
        (factors, fresh)
    }
}

/// Sparse factorisations (real and complex counted apart) that reused
/// the previous pivots and patterns, and that were done afresh.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Reuse {
    pub reused: u64,
    pub fresh: u64,
}

impl std::ops::AddAssign for Reuse {
    fn add_assign(&mut self, o: Reuse) {
        self.reused += o.reused;
        self.fresh += o.fresh;
    }
}

/// The LU factors of the real and the complex matrix of a step.
#[derive(Debug, Clone)]
pub enum Factors {
    Dense(LU<f64, Dyn, Dyn>, LU<Complex<f64>, Dyn, Dyn>),
    /// In the band's order of the variables.
    Banded(Vec<usize>, BandLu<f64>, BandLu<Complex<f64>>),
    /// Boxed: the two factors' vectors are many.
    Sparse(Box<(SparseLu<f64>, SparseLu<Complex<f64>>)>),
}

impl Factors {
    /// Neither matrix is singular.
    pub fn is_invertible(&self) -> bool {
        match self {
            Factors::Dense(a, b) => a.is_invertible() && b.is_invertible(),
            Factors::Banded(_, a, b) => a.is_invertible() && b.is_invertible(),
            Factors::Sparse(f) => f.0.is_invertible() && f.1.is_invertible(),
        }
    }

    /// Solves the real system in place; false when it is singular.
    /// `scratch` holds the reordered copy (kept by the caller, so Newton
    /// iterations allocate nothing).
    pub fn solve_real(&self, b: &mut DVector<f64>, scratch: &mut Vec<f64>) -> bool {
        match self {
            Factors::Dense(lu, _) => lu.solve_mut(b),
            Factors::Banded(order, lu, _) => permuted(order, b, scratch, |x| lu.solve_mut(x)),
            Factors::Sparse(f) => f.0.solve(b, scratch),
        }
    }

    /// Solves the complex system in place; false when it is singular.
    pub fn solve_complex(
        &self,
        b: &mut DVector<Complex<f64>>,
        scratch: &mut Vec<Complex<f64>>,
    ) -> bool {
        match self {
            Factors::Dense(_, lu) => lu.solve_mut(b),
            Factors::Banded(order, _, lu) => permuted(order, b, scratch, |x| lu.solve_mut(x)),
            Factors::Sparse(f) => f.1.solve(b, scratch),
        }
    }
}

fn permuted<T: Copy>(
    order: &[usize],
    b: &mut DVector<T>,
    x: &mut Vec<T>,
    solve: impl FnOnce(&mut [T]) -> bool,
) -> bool {
    x.clear();
    x.extend(order.iter().map(|&v| b[v]));
    let ok = solve(x);
    for (&v, x) in order.iter().zip(x.iter()) {
        b[v] = *x;
    }
    ok
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 1-D Brusselator's pattern: u1..um then v1..vm, tridiagonal
    /// blocks coupled by their diagonals.
    pub(crate) fn ladder(m: usize) -> Vec<Vec<usize>> {
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

    /// A 2-D reaction–diffusion grid of side `side`, two species: u then
    /// v, each a five-point Laplacian, coupled at each cell.
    pub(crate) fn grid(side: usize) -> Vec<Vec<usize>> {
        let m = side * side;
        (0..2 * m)
            .map(|i| {
                let (b, c) = (i / m * m, i % m);
                let (r, q) = (c / side, c % side);
                let mut cols = vec![i, (i + m) % (2 * m)];
                if r > 0 {
                    cols.push(b + c - side);
                }
                if r + 1 < side {
                    cols.push(b + c + side);
                }
                if q > 0 {
                    cols.push(b + c - 1);
                }
                if q + 1 < side {
                    cols.push(b + c + 1);
                }
                cols
            })
            .collect()
    }

    fn arrow(n: usize) -> Vec<Vec<usize>> {
        (0..n)
            .map(|i| if i == 0 { (0..n).collect() } else { vec![0, i] })
            .collect()
    }

    fn kind(rows: &[Vec<usize>]) -> LuKind {
        LuPlan::choose(rows.len(), Some(rows)).kind()
    }

    #[test]
    fn the_choice_follows_the_pattern() {
        // Small: dense whatever the pattern.
        assert_eq!(kind(&ladder(10)), LuKind::Dense);
        // A narrow band after RCM stays banded.
        assert_eq!(kind(&ladder(100)), LuKind::Banded);
        // A 2-D grid (band about 2·side wide) and an arrowhead (band n/2
        // after RCM) are sparse.
        assert_eq!(kind(&grid(15)), LuKind::Sparse);
        assert_eq!(kind(&arrow(200)), LuKind::Sparse);
        // A ring with a long-range link from each variable.
        let ring: Vec<Vec<usize>> = (0..200)
            .map(|i| vec![(i + 1) % 200, (i + 199) % 200, (i + 67) % 200])
            .collect();
        assert_eq!(kind(&ring), LuKind::Sparse);
        // A full pattern, or none, is dense.
        let full: Vec<Vec<usize>> = (0..60).map(|_| (0..60).collect()).collect();
        assert_eq!(kind(&full), LuKind::Dense);
        assert_eq!(LuPlan::choose(100, None).kind(), LuKind::Dense);
        let names: Vec<&str> = LuKind::ALL.iter().map(|k| k.name()).collect();
        assert_eq!(names, ["dense", "banded", "sparse"]);
    }

    /// The three forms give the same Newton solves on one matrix (a 2-D
    /// grid's Jacobian with a weak diagonal).
    #[test]
    fn the_three_forms_solve_alike() {
        let rows = grid(6);
        let n = rows.len();
        let mut jac = DMatrix::zeros(n, n);
        for (i, cols) in rows.iter().enumerate() {
            for &j in cols {
                jac[(i, j)] = ((3 * i + 7 * j) as f64).cos() + if i == j { -4.0 } else { 0.5 };
            }
        }
        let plans = [
            LuPlan::Dense,
            LuPlan::Banded(Band::narrowest(&rows).unwrap()),
            LuPlan::Sparse(SparsePlan::plan(&rows).unwrap()),
        ];
        let b = DVector::from_fn(n, |i, _| (i as f64 * 0.37).cos());
        let cb = b.map(|x| Complex::new(x, 1.0 - x));
        let mut answers = Vec::new();
        for plan in &plans {
            let f = plan.factor(&jac, 0.3, 0.2, 0.9);
            assert!(f.is_invertible());
            let (mut x, mut cx) = (b.clone(), cb.clone());
            assert!(f.solve_real(&mut x, &mut Vec::new()));
            assert!(f.solve_complex(&mut cx, &mut Vec::new()));
            answers.push((x, cx));
        }
        for (x, cx) in &answers[1..] {
            assert!((x - &answers[0].0).amax() < 1e-10);
            assert!((cx - &answers[0].1).camax() < 1e-10);
        }
    }

    /// Times one factorisation of each form per estimated multiply–add
    /// (real and complex together), for [`BAND_WEIGHT`] and
    /// [`SPARSE_WEIGHT`].
    #[test]
    #[ignore = "a measurement: run with --release --ignored --nocapture"]
    fn lu_weights_are_measured() {
        for (name, rows) in [("grid 15", grid(15)), ("ladder 100", ladder(100))] {
            let n = rows.len();
            let mut jac = DMatrix::zeros(n, n);
            for (i, cols) in rows.iter().enumerate() {
                for &j in cols {
                    jac[(i, j)] = ((3 * i + 7 * j) as f64).cos();
                }
            }
            let plans = [
                LuPlan::Dense,
                LuPlan::Banded(Band::narrowest(&rows).unwrap()),
                LuPlan::Sparse(SparsePlan::plan(&rows).unwrap()),
            ];
            for plan in &plans {
                let reps = 20;
                let start = std::time::Instant::now();
                for r in 0..reps {
                    let f = plan.factor(&jac, 10.0 + r as f64, 8.0, 3.0);
                    assert!(f.is_invertible());
                }
                let secs = start.elapsed().as_secs_f64() / reps as f64;
                let flops = plan.flops(n);
                println!(
                    "{name}: {:?} {:.3} ms, {:.0} flops, {:.2} ns/flop, weighted cost {:.0}",
                    plan.kind(),
                    secs * 1e3,
                    flops,
                    secs * 1e9 / flops,
                    plan.cost(n)
                );
            }
        }
    }
}
