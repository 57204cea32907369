//! The step-size controller of the adaptive explicit solver: DOP853 (one
//! implementation, [`crate::solvers::ode::Dop853`], stepping deck systems
//! and the rigid body alike) decides here whether a trial step is accepted
//! and how large the next one is, and takes its first step from Hairer's
//! starting-step guess here.
//!
//! The control is Hairer's DOP853 with a PI term (the shape of ode-solvers'
//! shared controller): after a trial with error `err` (relative to the
//! tolerance, accept when ≤ 1) the step changes by
//! 0.9·err^(−1/8+0.2β)·err_prev^β, clamped to [1/3, 6], and never grows
//! right after a rejection. Norms come in two arithmetics ([`Arithmetic`]):
//! the rigid body's arranged so that no square overflows, the systems'
//! Hairer's plain sum of squares; one would change the last bits of every
//! number the other prints, so a run says which it takes.

/// Safety factor on the optimal step.
pub(crate) const SAFETY: f64 = 0.9;
/// Bounds of h_new/h: never shrink below a third nor grow beyond six times
/// (Hairer's FAC1 = 0.333, FAC2 = 6, as the divisors h/h_new).
pub(crate) const SHRINK_LIMIT: f64 = 1.0 / 0.333;
pub(crate) const GROW_LIMIT: f64 = 1.0 / 6.0;
/// Weight of the previous step's error (PI control). With 0.04 instead of
/// DOP853's default 0 the step sequence is smoother: on flipping bodies it
/// rejects a few percent of the trials instead of 10–30 %, for the same
/// error per unit of work.
pub(crate) const BETA: f64 = 0.04;
/// The previous error starts here and never falls below it.
const FACOLD_FLOOR: f64 = 1e-4;

/// The controller's state along one run: the previous accepted error and
/// whether the last trial was rejected.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct StepControl {
    /// 1/order − 0.2β, the exponent of the current error.
    exponent: f64,
    facold: f64,
    rejected_last: bool,
}

impl StepControl {
    /// A controller for a method whose error estimate is of order
    /// `order − 1` (8 for DOP853).
    pub(crate) fn new(order: f64) -> StepControl {
        StepControl {
            exponent: 1.0 / order - 0.2 * BETA,
            facold: FACOLD_FLOOR,
            rejected_last: false,
        }
    }

    /// The next step after an accepted trial of size `h` with error `err`.
    pub(crate) fn accept(&mut self, h: f64, err: f64) -> f64 {
        let fac11 = err.powf(self.exponent);
        let fac = fac11 / self.facold.powf(BETA);
        let fac = GROW_LIMIT.max(SHRINK_LIMIT.min(fac / SAFETY));
        self.facold = err.max(FACOLD_FLOOR);
        let mut h_new = h / fac;
        if self.rejected_last {
            h_new = h_new.min(h);
        }
        self.rejected_last = false;
        h_new
    }

    /// The step to try after a rejected trial of size `h` with error `err`.
    /// NaN-safe: `f64::min` drops a NaN operand, so a non-finite error
    /// shrinks the step by the largest allowed factor.
    pub(crate) fn reject(&mut self, h: f64, err: f64) -> f64 {
        let fac11 = err.powf(self.exponent);
        self.rejected_last = true;
        h / SHRINK_LIMIT.min(fac11 / SAFETY)
    }
}

/// Hairer's starting step (HINIT in DOP853 and RADAU5's companions) for a
/// method of order `order`: an explicit Euler step sized from |f|/|y|, then
/// corrected by an estimate of the second derivative so that the local
/// error of a method of order `order − 1` is about the tolerance. `scale`
/// holds atol + rtol·|yᵢ|; `rhs(h, y1, f1)` evaluates f at t + h. With
/// `Arithmetic::Logarithmic` the norms are taken without squaring and the
/// sizes compared in logarithms, so that spins past ~1e140 (|f|/sk ~ |ω|/tol,
/// and the second derivative ~ |ω|³/tol) do not overflow.
pub(crate) fn initial_step(
    arithmetic: Arithmetic,
    mut rhs: impl FnMut(f64, &[f64], &mut [f64]),
    y: &[f64],
    f0: &[f64],
    scale: &[f64],
    order: f64,
    h_max: f64,
) -> f64 {
    let n = y.len();
    let mut y1 = vec![0.0; n];
    let mut f1 = vec![0.0; n];
    match arithmetic {
        Arithmetic::Plain => {
            let dnf = rms(f0, scale).powi(2) * n as f64;
            let dny = rms(y, scale).powi(2) * n as f64;
            let mut h = if dnf <= 1e-10 || dny <= 1e-10 {
                1e-6
            } else {
                (dny / dnf).sqrt() * 0.01
            };
            h = h.min(h_max);
            for ((y1, y), f) in y1.iter_mut().zip(y).zip(f0) {
                *y1 = y + h * f;
            }
            rhs(h, &y1, &mut f1);
            let diff: Vec<f64> = f1.iter().zip(f0).map(|(a, b)| a - b).collect();
            let der2 = rms(&diff, scale) * (n as f64).sqrt() / h;
            let der12 = der2.max(dnf.sqrt());
            let h1 = if der12.is_nan() || der12 <= 1e-15 {
                // Also the branch for a NaN estimate (f not finite after the
                // trial step): start small and let the step control find
                // its way.
                (h * 1e-3).max(1e-6)
            } else {
                (0.01 / der12).powf(1.0 / order)
            };
            let h = (100.0 * h).min(h1).min(h_max);
            if h.is_finite() && h > 0.0 { h } else { 1e-6 }
        }
        Arithmetic::Logarithmic => {
            let scaled =
                |v: &[f64]| -> Vec<f64> { v.iter().zip(scale).map(|(v, s)| v / s).collect() };
            let dnf = norm(&scaled(f0));
            let dny = norm(&scaled(y));
            let h0 = if dnf <= 1e-5 || dny <= 1e-5 {
                1e-6
            } else {
                (dny / dnf) * 0.01
            };
            for ((y1, y), f) in y1.iter_mut().zip(y).zip(f0) {
                *y1 = *y;
                *y1 += h0 * f;
            }
            rhs(h0, &y1, &mut f1);
            let diff: Vec<f64> = f1.iter().zip(f0).map(|(f1, f0)| f1 - f0).collect();
            let der2 = norm(&scaled(&diff));
            let log_der12 = (der2.ln() - h0.ln()).max(dnf.ln());
            let h1 = if log_der12 <= 1e-15f64.ln() {
                (h0 * 1e-3).max(1e-6)
            } else {
                ((0.01f64.ln() - log_der12) * (1.0 / order)).exp()
            };
            // Not `min`: that would turn a NaN guess into h_max.
            let h = (100.0 * h0).min(h1);
            if h > h_max { h_max } else { h }
        }
    }
}

/// How [`initial_step`] takes its norms.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Arithmetic {
    /// Hairer's sums of squares (the systems of a deck).
    Plain,
    /// Norms scaled by their largest entry and sizes in logarithms (the
    /// rigid body, whose spins may be huge).
    Logarithmic,
}

/// RMS norm of `v` weighted by 1/`scale`.
pub(crate) fn rms(v: &[f64], scale: &[f64]) -> f64 {
    let sum: f64 = v.iter().zip(scale).map(|(v, s)| (v / s).powi(2)).sum();
    (sum / v.len() as f64).sqrt()
}

/// The 2-norm of v, scaled by its largest entry so that no square
/// overflows or underflows.
pub(crate) fn norm(v: &[f64]) -> f64 {
    let big = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if big == 0.0 || !big.is_finite() {
        return big;
    }
    big * v.iter().map(|x| (x / big).powi(2)).sum::<f64>().sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn growth_and_shrinkage_stay_within_their_bounds() {
        let mut c = StepControl::new(8.0);
        // A tiny error grows the step by at most six times.
        assert!((c.accept(1.0, 1e-30) - 6.0).abs() < 1e-12);
        // A huge or non-finite error shrinks it by at most three.
        assert!((c.reject(1.0, 1e30) - 0.333).abs() < 1e-12);
        assert!((c.reject(1.0, f64::NAN) - 0.333).abs() < 1e-12);
        // Right after a rejection the step does not grow.
        assert_eq!(c.accept(1.0, 1e-30), 1.0);
        assert!(c.accept(1.0, 1e-30) > 1.0);
    }

    #[test]
    fn both_arithmetics_agree_on_a_tame_problem() {
        let rhs = |_: f64, y: &[f64], f: &mut [f64]| {
            f[0] = y[1];
            f[1] = -y[0];
        };
        let y = [1.0, 0.5];
        let f0 = [0.5, -1.0];
        let scale = [1e-8 + 1e-6, 1e-8 + 0.5e-6];
        let guess = |how| initial_step(how, rhs, &y, &f0, &scale, 8.0, f64::INFINITY);
        let (a, b) = (guess(Arithmetic::Plain), guess(Arithmetic::Logarithmic));
        assert!((a / b - 1.0).abs() < 1e-12, "{a} vs {b}");
    }

    #[test]
    fn logarithmic_guess_survives_huge_rates() {
        // |f|/sk = 1e200: its square overflows, its logarithm does not.
        let rhs = |_: f64, _: &[f64], f: &mut [f64]| f[0] = 1e190;
        let (y, f0, scale) = ([1.0], [1e190], [1e-10]);
        let h = initial_step(
            Arithmetic::Logarithmic,
            rhs,
            &y,
            &f0,
            &scale,
            8.0,
            f64::INFINITY,
        );
        assert!(h > 0.0 && h <= 1e-189, "{h}");
    }
}
