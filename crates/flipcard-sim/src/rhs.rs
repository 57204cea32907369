//! The one trait of a right-hand side y' = f(t, y), [`OdeSystem`], below
//! both stacks: the systems written in a deck implement it, and so does the
//! rigid body (its Euler equations, [`crate::rigid::euler`]), so every
//! solver steps the same kind of thing. It sits apart from `solvers` and
//! `rigid` so that both use it and neither uses the other through it.

use nalgebra::DMatrix;

/// A system y' = f(t, y) of fixed dimension.
pub trait OdeSystem {
    /// Number of components of y (at least 1).
    fn dim(&self) -> usize;

    /// Writes f(t, y) into `dy` (both of length `dim()`). A value of f that
    /// is not finite is not an error here: the solvers shrink the step, and
    /// stop with [`crate::error::SolveError::BlowUp`] if that does not help.
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]);

    /// Writes the Jacobian ∂f/∂y at (t, y) into `jac` (n×n, `jac[(i, j)]` =
    /// ∂fᵢ/∂yⱼ). The default is [`finite_difference_jacobian`]; systems
    /// that know their derivatives should override it (implicit methods
    /// converge faster with an exact Jacobian, and save 2n evaluations of f
    /// per Jacobian).
    fn jacobian(&self, t: f64, y: &[f64], jac: &mut DMatrix<f64>) {
        finite_difference_jacobian(self, t, y, jac);
    }

    /// The positions and momenta of a separable Hamiltonian system, for
    /// the symplectic methods ([`crate::solvers::ode::Verlet`]): `None`
    /// (the default) for a system that declares none.
    fn split(&self) -> Option<Split> {
        None
    }

    /// The columns each row of the Jacobian may have non-zero
    /// (`rows[i]`: the variables fᵢ reads), when the system knows them:
    /// Radau IIA then factors large systems as banded matrices
    /// ([`crate::solvers::ode::band`]). `None` (the default): dense.
    fn sparsity(&self) -> Option<Vec<Vec<usize>>> {
        None
    }

    /// The linear sums cᵀy of the variables the equations keep fixed
    /// (cᵀf = 0 everywhere), found near (t, y), each a row c: the solvers
    /// hold them against rounding ([`crate::solvers::ode::fixed`]). Empty
    /// (the default) for a system that does not know them.
    fn fixed_sums(&self, _t: f64, _y: &[f64]) -> Vec<Vec<f64>> {
        Vec::new()
    }
}

/// A separable Hamiltonian H = T(p) + V(q) written as y' = f(t, y): the
/// components that are positions (`q`, whose rates read only momenta) and
/// momenta (`p`, same length, whose rates read only positions), each
/// component in exactly one of them.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Split {
    pub q: Vec<usize>,
    pub p: Vec<usize>,
}

impl<S: OdeSystem + ?Sized> OdeSystem for &S {
    fn dim(&self) -> usize {
        (**self).dim()
    }
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        (**self).rhs(t, y, dy)
    }
    fn jacobian(&self, t: f64, y: &[f64], jac: &mut DMatrix<f64>) {
        (**self).jacobian(t, y, jac)
    }
    fn split(&self) -> Option<Split> {
        (**self).split()
    }
    fn sparsity(&self) -> Option<Vec<Vec<usize>>> {
        (**self).sparsity()
    }
    fn fixed_sums(&self, t: f64, y: &[f64]) -> Vec<Vec<f64>> {
        (**self).fixed_sums(t, y)
    }
}

impl<S: OdeSystem + ?Sized> OdeSystem for Box<S> {
    fn dim(&self) -> usize {
        (**self).dim()
    }
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        (**self).rhs(t, y, dy)
    }
    fn jacobian(&self, t: f64, y: &[f64], jac: &mut DMatrix<f64>) {
        (**self).jacobian(t, y, jac)
    }
    fn split(&self) -> Option<Split> {
        (**self).split()
    }
    fn sparsity(&self) -> Option<Vec<Vec<usize>>> {
        (**self).sparsity()
    }
    fn fixed_sums(&self, t: f64, y: &[f64]) -> Vec<Vec<f64>> {
        (**self).fixed_sums(t, y)
    }
}

/// Central differences (error O(δ²) instead of O(δ) for forward ones) with
/// δⱼ = ε^(1/3)·max(|yⱼ|, 10⁻³), the increment that balances truncation
/// against rounding for a second-order formula. The floor keeps δ from
/// vanishing at yⱼ = 0; where f is not finite on one side of y (the edge of
/// its domain, say √y at y = 0) the one-sided difference on the other side
/// is used instead.
pub fn finite_difference_jacobian<S: OdeSystem + ?Sized>(
    sys: &S,
    t: f64,
    y: &[f64],
    jac: &mut DMatrix<f64>,
) {
    let n = y.len();
    if jac.nrows() != n || jac.ncols() != n {
        *jac = DMatrix::zeros(n, n);
    }
    let cbrt_eps = f64::EPSILON.cbrt();
    let mut yp = y.to_vec();
    let mut f_plus = vec![0.0; n];
    let mut f_minus = vec![0.0; n];
    let mut f_mid: Option<Vec<f64>> = None;
    for j in 0..n {
        let yj = y[j];
        let raw = cbrt_eps * yj.abs().max(1e-3);
        // Rounding yⱼ ± δ back gives the increments actually applied.
        yp[j] = yj + raw;
        let up = yp[j] - yj;
        sys.rhs(t, &yp, &mut f_plus);
        yp[j] = yj - raw;
        let down = yj - yp[j];
        sys.rhs(t, &yp, &mut f_minus);
        yp[j] = yj;
        let plus_ok = f_plus.iter().all(|v| v.is_finite());
        let minus_ok = f_minus.iter().all(|v| v.is_finite());
        if plus_ok && minus_ok {
            for i in 0..n {
                jac[(i, j)] = (f_plus[i] - f_minus[i]) / (up + down);
            }
            continue;
        }
        let mid = f_mid.get_or_insert_with(|| {
            let mut f = vec![0.0; n];
            sys.rhs(t, y, &mut f);
            f
        });
        for i in 0..n {
            jac[(i, j)] = if plus_ok {
                (f_plus[i] - mid[i]) / up
            } else {
                (mid[i] - f_minus[i]) / down
            };
        }
    }
}
