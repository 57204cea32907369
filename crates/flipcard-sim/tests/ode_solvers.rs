//! The generic ODE solvers on problems with known answers: stiff
//! oscillators and kinetics, a stiff linear system with a closed-form
//! solution, orders of convergence, blow-up and dense output.

use flipcard_sim::error::SolveError;
use flipcard_sim::solvers::ode::{
    Atol, Auto, Dop853, Method, OdeSolver, OdeSystem, Options, Radau5, Rk4, StiffnessMode,
    finite_difference_jacobian, make,
};
use nalgebra::DMatrix;

// ---------------------------------------------------------------- systems

/// x'' − μ(1 − x²)x' + x = 0 as (x, v).
struct VanDerPol {
    mu: f64,
}

impl OdeSystem for VanDerPol {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = y[1];
        dy[1] = self.mu * (1.0 - y[0] * y[0]) * y[1] - y[0];
    }
    fn jacobian(&self, _t: f64, y: &[f64], jac: &mut DMatrix<f64>) {
        jac[(0, 0)] = 0.0;
        jac[(0, 1)] = 1.0;
        jac[(1, 0)] = -2.0 * self.mu * y[0] * y[1] - 1.0;
        jac[(1, 1)] = self.mu * (1.0 - y[0] * y[0]);
    }
}

/// Robertson's chemical kinetics.
struct Robertson;

impl OdeSystem for Robertson {
    fn dim(&self) -> usize {
        3
    }
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
        let r1 = 0.04 * y[0];
        let r2 = 1e4 * y[1] * y[2];
        let r3 = 3e7 * y[1] * y[1];
        dy[0] = -r1 + r2;
        dy[1] = r1 - r2 - r3;
        dy[2] = r3;
    }
    fn jacobian(&self, _t: f64, y: &[f64], jac: &mut DMatrix<f64>) {
        jac[(0, 0)] = -0.04;
        jac[(0, 1)] = 1e4 * y[2];
        jac[(0, 2)] = 1e4 * y[1];
        jac[(1, 0)] = 0.04;
        jac[(1, 1)] = -1e4 * y[2] - 6e7 * y[1];
        jac[(1, 2)] = -1e4 * y[1];
        jac[(2, 0)] = 0.0;
        jac[(2, 1)] = 6e7 * y[1];
        jac[(2, 2)] = 0.0;
    }
}

/// Robertson without its Jacobian, so the solvers difference f.
struct RobertsonNoJacobian;

impl OdeSystem for RobertsonNoJacobian {
    fn dim(&self) -> usize {
        3
    }
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        Robertson.rhs(t, y, dy)
    }
}

/// y' = A y with A = Q [[a, c], [0, b]] Qᵀ: eigenvalues a = −1 and
/// b = −10⁶, a strongly non-normal coupling c, and a rotation Q that fills
/// every entry. In the triangular coordinates (u, v) = Qᵀy the solution is
/// v = v₀e^{bt}, u = u₀e^{at} + c v₀ (e^{bt} − e^{at})/(b − a).
struct StiffLinear {
    a: f64,
    b: f64,
    c: f64,
    cos: f64,
    sin: f64,
}

impl StiffLinear {
    fn new() -> StiffLinear {
        let phi: f64 = 0.3;
        StiffLinear {
            a: -1.0,
            b: -1e6,
            c: 1e3,
            cos: phi.cos(),
            sin: phi.sin(),
        }
    }
    fn matrix(&self) -> [[f64; 2]; 2] {
        let q = [[self.cos, -self.sin], [self.sin, self.cos]];
        let m = [[self.a, self.c], [0.0, self.b]];
        let mut qm = [[0.0; 2]; 2];
        let mut out = [[0.0; 2]; 2];
        for i in 0..2 {
            for j in 0..2 {
                qm[i][j] = (0..2).map(|k| q[i][k] * m[k][j]).sum();
            }
        }
        for i in 0..2 {
            for j in 0..2 {
                // Qᵀ[k][j] = q[j][k]
                out[i][j] = (0..2).map(|k| qm[i][k] * q[j][k]).sum();
            }
        }
        out
    }
    fn exact(&self, y0: &[f64], t: f64) -> [f64; 2] {
        let (c, s) = (self.cos, self.sin);
        let u0 = c * y0[0] + s * y0[1];
        let v0 = -s * y0[0] + c * y0[1];
        let (ea, eb) = ((self.a * t).exp(), (self.b * t).exp());
        let v = v0 * eb;
        let u = u0 * ea + self.c * v0 * (eb - ea) / (self.b - self.a);
        [c * u - s * v, s * u + c * v]
    }
}

impl OdeSystem for StiffLinear {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
        let m = self.matrix();
        dy[0] = m[0][0] * y[0] + m[0][1] * y[1];
        dy[1] = m[1][0] * y[0] + m[1][1] * y[1];
    }
    fn jacobian(&self, _t: f64, _y: &[f64], jac: &mut DMatrix<f64>) {
        let m = self.matrix();
        for i in 0..2 {
            for j in 0..2 {
                jac[(i, j)] = m[i][j];
            }
        }
    }
}

/// x' = −ω(t) y, y' = ω(t) x with ω = 1 + t: a rotation by
/// θ(t) = t + t²/2, smooth, non-autonomous and known exactly.
struct Spin;

impl OdeSystem for Spin {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        let w = 1.0 + t;
        dy[0] = -w * y[1];
        dy[1] = w * y[0];
    }
}

fn spin_exact(t: f64) -> [f64; 2] {
    let theta = t + 0.5 * t * t;
    [theta.cos(), theta.sin()]
}

/// x' = x², x(0) = 1: x = 1/(1 − t) blows up at t = 1.
struct Square;

impl OdeSystem for Square {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = y[0] * y[0];
    }
}

// ---------------------------------------------------------------- helpers

/// Zero crossings of component 0 (time, upward?) found step by step and
/// located by bisection on the dense output; also the largest |x| seen
/// (step ends plus 16 dense points per step).
fn crossings_and_peak(s: &mut dyn OdeSolver, t_end: f64) -> (Vec<(f64, bool)>, f64) {
    let mut out = Vec::new();
    let mut buf = vec![0.0; s.dim()];
    let mut prev = s.advance(s.t()).expect("start")[0];
    let mut peak = prev.abs();
    while s.t() < t_end {
        let (t0, t1) = s.step().expect("step");
        for k in 1..16 {
            s.dense(t0 + (t1 - t0) * k as f64 / 16.0, &mut buf)
                .expect("dense");
            peak = peak.max(buf[0].abs());
        }
        s.dense(t1, &mut buf).expect("dense");
        let x1 = buf[0];
        peak = peak.max(x1.abs());
        if prev.signum() != x1.signum() && prev != 0.0 {
            let (mut lo, mut hi) = (t0, t1);
            for _ in 0..100 {
                let mid = 0.5 * (lo + hi);
                if mid <= lo || mid >= hi {
                    break;
                }
                s.dense(mid, &mut buf).expect("dense");
                if buf[0].signum() == prev.signum() {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            out.push((0.5 * (lo + hi), x1 > prev));
        }
        prev = x1;
    }
    (out, peak)
}

fn upward(c: &[(f64, bool)]) -> Vec<f64> {
    c.iter().filter(|(_, up)| *up).map(|(t, _)| *t).collect()
}

fn vdp_opts(rtol: f64) -> Options {
    Options::with_tol(rtol, rtol)
}

fn robertson_opts(rtol: f64) -> Options {
    Options {
        rtol,
        // y₂ lives at 10⁻⁵ to 10⁻¹³: its absolute tolerance must sit far
        // below it for the late values to mean anything.
        atol: Atol::PerComponent(vec![rtol * 1e-4, rtol * 1e-10, rtol * 1e-4]),
        ..Options::default()
    }
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

// ---------------------------------------------------------------- Van der Pol

const MU: f64 = 1000.0;
/// Two upward crossings of x = 0 fall in [0, 3400] (at ≈ 1614 and ≈ 3228).
const VDP_END: f64 = 3400.0;

#[test]
fn van_der_pol_period_and_amplitude_with_radau() {
    let mut radau = Radau5::new(VanDerPol { mu: MU }, 0.0, &[2.0, 0.0], &vdp_opts(1e-6)).unwrap();
    let (cross, peak) = crossings_and_peak(&mut radau, VDP_END);
    let up = upward(&cross);
    assert_eq!(up.len(), 2, "crossings {cross:?}");
    let period = up[1] - up[0];
    // Asymptotic period (3 − 2 ln 2)μ + 3α μ^(−1/3), α = 2.338… (the first
    // zero of Ai(−x)), whose next terms are O(μ⁻¹ ln μ) ≈ 0.005 here.
    let asymptotic = (3.0 - 2.0 * 2f64.ln()) * MU + 7.014 * MU.powf(-1.0 / 3.0);
    assert!(
        (period - asymptotic).abs() < 0.05,
        "period {period} vs asymptotic {asymptotic}"
    );
    // Against the same method at a much tighter tolerance.
    let mut tight = Radau5::new(VanDerPol { mu: MU }, 0.0, &[2.0, 0.0], &vdp_opts(1e-10)).unwrap();
    let (cross_ref, peak_ref) = crossings_and_peak(&mut tight, VDP_END);
    let up_ref = upward(&cross_ref);
    assert_eq!(up_ref.len(), 2, "crossings {cross_ref:?}");
    let period_ref = up_ref[1] - up_ref[0];
    assert!(
        (period - period_ref).abs() < 1e-5 * period_ref,
        "period {period} vs reference {period_ref}"
    );
    // By the symmetry x → −x, the down-crossing before the first upward
    // one is half a period earlier.
    let down: Vec<f64> = cross.iter().filter(|c| !c.1).map(|c| c.0).collect();
    assert!((2.0 * (up[0] - down[0]) - period).abs() < 0.05);
    // The peak, right after each jump, is 2 + (α/3) μ^(−4/3) + O(μ⁻² ln μ)
    // (the correction is 7.8e-5 here, the next term below 1e-5).
    let peak_asymptotic = 2.0 + 2.338_107 / 3.0 * MU.powf(-4.0 / 3.0);
    assert!((peak - peak_ref).abs() < 1e-6, "peak {peak} vs {peak_ref}");
    assert!(
        (peak - peak_asymptotic).abs() < 1e-5,
        "peak {peak} vs asymptotic {peak_asymptotic}"
    );
    let w = radau.work();
    assert!(w.steps < 3000, "{w:?}");
    assert!(w.jac_evals < w.steps, "Jacobians are reused: {w:?}");
    assert!(
        w.lu_decomps < w.steps + w.rejected,
        "LU factors are reused: {w:?}"
    );
    eprintln!(
        "vdp: period {period:.6} (tight {period_ref:.6}, asymptotic {asymptotic:.6}), \
         peak {peak:.8} (tight {peak_ref:.8}, asymptotic {peak_asymptotic:.8}), work {w:?}"
    );
}

#[test]
fn van_der_pol_auto_switches_to_radau() {
    let mut auto = Auto::new(VanDerPol { mu: MU }, 0.0, &[2.0, 0.0], &vdp_opts(1e-6)).unwrap();
    assert_eq!(auto.name(), "dop853");
    let y = auto.advance(3000.0).expect("auto finishes").to_vec();
    let t_switch = auto.stiffness().expect("stiffness detected");
    assert_eq!(auto.switched_at(), Some(t_switch));
    assert!(t_switch > 0.0 && t_switch < 1.0, "switch at {t_switch}");
    assert_eq!(auto.name(), "radau5");
    let w = auto.work();
    assert!(w.steps < 3000, "{w:?}");
    let mut radau = Radau5::new(VanDerPol { mu: MU }, 0.0, &[2.0, 0.0], &vdp_opts(1e-8)).unwrap();
    let y_ref = radau.advance(3000.0).unwrap();
    assert!((y[0] - y_ref[0]).abs() < 1e-3, "{y:?} vs {y_ref:?}");
    eprintln!("vdp auto: switch at t = {t_switch}, work {w:?}");
}

#[test]
fn van_der_pol_dop853_refuses_when_told() {
    let mut dop = Dop853::new(VanDerPol { mu: MU }, 0.0, &[2.0, 0.0], &vdp_opts(1e-6))
        .unwrap()
        .with_stiffness(StiffnessMode::Refuse);
    match dop.advance(3000.0) {
        Err(SolveError::Stiff { t }) => {
            assert!(t > 0.0 && t < 1.0, "stiff at {t}");
            assert!(dop.work().steps < 1000, "{:?}", dop.work());
            // The refusal is final.
            assert!(matches!(dop.advance(3000.0), Err(SolveError::Stiff { .. })));
        }
        other => panic!("expected a refusal, got {other:?}"),
    }
}

// ---------------------------------------------------------------- Robertson

/// Reference values, as published: at t = 40 from Hairer & Wanner's stiff
/// test problems (*Solving ODEs II*), at t = 1e11 from the IVP
/// test set of Mazzia & Magherini (problem ROBER). A Radau IIA run at
/// rtol = 1e-12 reproduces all 16 digits given to a relative 1e-9 or
/// better (`robertson_reference_values_hold_at_tight_tolerance`: 3e-11 at
/// 40, 2e-10 at 1e11).
#[allow(clippy::excessive_precision)]
const ROBERTSON_40: [f64; 3] = [0.7158270687193433, 9.185534764557338e-6, 0.2841637457458766];
#[allow(clippy::excessive_precision)]
const ROBERTSON_1E11: [f64; 3] = [
    0.2083340149701255e-7,
    0.8333360770334713e-13,
    0.9999999791665050,
];

#[test]
fn robertson_with_radau() {
    // The run ends on a step end at 1e11 (as a run to a chosen end would).
    let opts = Options {
        t_stop: Some(1e11),
        ..robertson_opts(1e-6)
    };
    let mut radau = Radau5::new(Robertson, 0.0, &[1.0, 0.0, 0.0], &opts).unwrap();
    let mut worst_mass: f64 = 0.0;
    // Logarithmically spaced samples from 1e-6 to 1e11, with t = 40 among them.
    let mut times: Vec<f64> = (0..=170)
        .map(|k| 10f64.powf(-6.0 + k as f64 * 0.1).min(1e11))
        .collect();
    times.push(40.0);
    times.sort_by(f64::total_cmp);
    let mut at_40 = None;
    for &t in &times {
        let y = radau.advance(t).unwrap();
        worst_mass = worst_mass.max((y[0] + y[1] + y[2] - 1.0).abs());
        if t == 40.0 {
            at_40 = Some(y.to_vec());
        }
    }
    let y40 = at_40.unwrap();
    let y_end = radau.advance(1e11).unwrap().to_vec();
    assert!(worst_mass <= 1e-9, "mass drifts by {worst_mass}");
    for i in 0..3 {
        assert!(
            rel(y40[i], ROBERTSON_40[i]) < 1e-4,
            "y{} at 40: {} vs {}",
            i + 1,
            y40[i],
            ROBERTSON_40[i]
        );
        assert!(
            rel(y_end[i], ROBERTSON_1E11[i]) < 1e-4,
            "y{} at 1e11: {} vs {}",
            i + 1,
            y_end[i],
            ROBERTSON_1E11[i]
        );
    }
    let w = radau.work();
    assert!(w.steps < 1000, "{w:?}");
    eprintln!(
        "robertson rtol 1e-6: mass {worst_mass:e}, at 40 rel err {:?}, at 1e11 rel err {:?}, {w:?}",
        (0..3)
            .map(|i| rel(y40[i], ROBERTSON_40[i]))
            .collect::<Vec<_>>(),
        (0..3)
            .map(|i| rel(y_end[i], ROBERTSON_1E11[i]))
            .collect::<Vec<_>>()
    );
}

#[test]
fn robertson_reference_values_hold_at_tight_tolerance() {
    // Landing on 1e11 with a step end: between step ends the collocation
    // polynomial is an order less accurate, and the last steps are ~1e10.
    let opts = Options {
        t_stop: Some(1e11),
        ..robertson_opts(1e-12)
    };
    let mut radau = Radau5::new(Robertson, 0.0, &[1.0, 0.0, 0.0], &opts).unwrap();
    let y40 = radau.advance(40.0).unwrap().to_vec();
    let y_end = radau.advance(1e11).unwrap().to_vec();
    for i in 0..3 {
        // Ten digits at 40, as published by Hairer & Wanner.
        assert!(
            rel(y40[i], ROBERTSON_40[i]) < 1e-9,
            "y{} at 40: {}",
            i + 1,
            y40[i]
        );
        assert!(
            rel(y_end[i], ROBERTSON_1E11[i]) < 1e-9,
            "y{} at 1e11: {}",
            i + 1,
            y_end[i]
        );
    }
    eprintln!(
        "robertson rtol 1e-12: at 40 {y40:?}, at 1e11 {y_end:?}, {:?}",
        radau.work()
    );
}

#[test]
fn robertson_with_finite_difference_jacobian_agrees() {
    let opts = robertson_opts(1e-6);
    let mut exact = Radau5::new(Robertson, 0.0, &[1.0, 0.0, 0.0], &opts).unwrap();
    let mut fd = Radau5::new(RobertsonNoJacobian, 0.0, &[1.0, 0.0, 0.0], &opts).unwrap();
    for t in [1e-3, 1.0, 40.0, 1e5, 1e11] {
        let a = exact.advance(t).unwrap().to_vec();
        let b = fd.advance(t).unwrap();
        for i in 0..3 {
            assert!(
                rel(b[i], a[i]) < 1e-5,
                "t = {t}, y{}: {} vs {}",
                i + 1,
                b[i],
                a[i]
            );
        }
    }
}

#[test]
fn robertson_auto_switches_and_dop853_reports() {
    let mut auto = Auto::new(Robertson, 0.0, &[1.0, 0.0, 0.0], &robertson_opts(1e-6)).unwrap();
    let y = auto.advance(40.0).unwrap().to_vec();
    assert!(auto.stiffness().is_some());
    for i in 0..3 {
        assert!(rel(y[i], ROBERTSON_40[i]) < 1e-4, "{y:?}");
    }
    // Across the switch the samples follow a tight Radau run (to 4e-5 for
    // y₂ in its fast rise, the explicit phase's error at rtol 1e-6): the
    // last explicit step still serves its dense output.
    let t_switch = auto.stiffness().unwrap();
    let mut sampled = Auto::new(Robertson, 0.0, &[1.0, 0.0, 0.0], &robertson_opts(1e-6)).unwrap();
    let mut tight = Radau5::new(Robertson, 0.0, &[1.0, 0.0, 0.0], &robertson_opts(1e-10)).unwrap();
    for k in 1..=200 {
        let t = 2.0 * t_switch * k as f64 / 200.0;
        let a = sampled.advance(t).unwrap();
        let b = tight.advance(t).unwrap();
        for i in 0..3 {
            assert!(
                (a[i] - b[i]).abs() <= 1e-4 * b[i].abs() + 1e-12,
                "t = {t}: {a:?} vs {b:?}"
            );
        }
    }
    assert_eq!(sampled.switched_at(), Some(t_switch));
    // In report mode DOP853 records the time and carries on.
    let mut dop = Dop853::new(Robertson, 0.0, &[1.0, 0.0, 0.0], &robertson_opts(1e-6)).unwrap();
    dop.advance(0.5).unwrap();
    let t_stiff = dop.stiffness().expect("stiffness reported");
    assert!(t_stiff < 0.5);
    assert_eq!(dop.t(), dop.t().max(0.5));
}

// ---------------------------------------------------------------- stiff linear

#[test]
fn stiff_linear_error_falls_with_tolerance() {
    let sys = StiffLinear::new();
    let y0 = [1.0, 2.0];
    let times = [1e-7, 1e-6, 1e-5, 1e-3, 0.1, 1.0, 3.0];
    let mut errors = Vec::new();
    for tol in [1e-3, 1e-5, 1e-7, 1e-9] {
        let sys_run = StiffLinear::new();
        // A tiny atol makes the control relative, so the decaying slow
        // mode is followed to the same relative accuracy throughout.
        let opts = Options::with_tol(tol, tol * 1e-6);
        let mut radau = Radau5::new(sys_run, 0.0, &y0, &opts).unwrap();
        let mut err: f64 = 0.0;
        for &t in &times {
            let y = radau.advance(t).unwrap();
            let e = sys.exact(&y0, t);
            for i in 0..2 {
                err = err.max(rel(y[i], e[i]));
            }
        }
        errors.push((tol, err / tol, radau.work().steps));
    }
    eprintln!("stiff linear (tol, error/tol, steps): {errors:?}");
    for w in errors.windows(2) {
        let (tol_a, ratio_a, _) = w[0];
        let (tol_b, ratio_b, _) = w[1];
        assert!(ratio_b * tol_b < ratio_a * tol_a, "{errors:?}");
    }
    for (tol, ratio, _) in &errors {
        assert!(*ratio < 30.0, "error {} at tol {tol}", ratio * tol);
    }
}

// ---------------------------------------------------------------- orders

/// Errors at t = 2 of a fixed-step run with n steps each, and the observed
/// orders between successive halvings.
fn observed_orders(errors: &[f64]) -> Vec<f64> {
    errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect()
}

fn spin_error(s: &mut dyn OdeSolver) -> f64 {
    let y = s.advance(2.0).unwrap();
    let e = spin_exact(2.0);
    ((y[0] - e[0]).powi(2) + (y[1] - e[1]).powi(2)).sqrt()
}

#[test]
fn radau_fixed_steps_converge_with_order_5() {
    let errors: Vec<f64> = [8, 16, 32, 64]
        .iter()
        .map(|&n| {
            spin_error(&mut Radau5::new_fixed(Spin, 0.0, &[1.0, 0.0], 2.0 / n as f64).unwrap())
        })
        .collect();
    let orders = observed_orders(&errors);
    eprintln!("radau errors {errors:?}, orders {orders:?}");
    for p in &orders {
        assert!((p - 5.0).abs() < 0.3, "orders {orders:?}");
    }
}

#[test]
fn dop853_fixed_steps_converge_with_order_8() {
    let errors: Vec<f64> = [4, 8, 16, 32]
        .iter()
        .map(|&n| {
            spin_error(&mut Dop853::new_fixed(Spin, 0.0, &[1.0, 0.0], 2.0 / n as f64).unwrap())
        })
        .collect();
    let orders = observed_orders(&errors);
    eprintln!("dop853 errors {errors:?}, orders {orders:?}");
    for p in &orders {
        assert!((p - 8.0).abs() < 0.3, "orders {orders:?}");
    }
}

#[test]
fn rk4_converges_with_order_4() {
    let opts = Options::default();
    let errors: Vec<f64> = [20, 40, 80, 160]
        .iter()
        .map(|&n| spin_error(&mut Rk4::new(Spin, 0.0, &[1.0, 0.0], 2.0 / n as f64, &opts).unwrap()))
        .collect();
    let orders = observed_orders(&errors);
    eprintln!("rk4 errors {errors:?}, orders {orders:?}");
    for p in &orders {
        assert!((p - 4.0).abs() < 0.3, "orders {orders:?}");
    }
}

// ---------------------------------------------------------------- blow-up

#[test]
fn blow_up_stops_every_method_near_the_singularity() {
    let opts = Options::default();
    let methods = [
        Method::Dop853 {
            stiffness: StiffnessMode::Report,
        },
        Method::Radau5,
        Method::Auto,
        Method::Rk4 { dt: 1e-4 },
    ];
    for method in methods {
        let mut s = make(method, Square, 0.0, &[1.0], &opts).unwrap();
        let mut failure = None;
        for k in 1..=200 {
            match s.advance(k as f64 * 0.01) {
                Ok(y) => assert!(y[0].is_finite() && y[0] > 0.0, "{method:?}: {y:?}"),
                Err(e) => {
                    failure = Some(e);
                    break;
                }
            }
        }
        match failure {
            Some(SolveError::BlowUp { t }) => {
                assert!((t - 1.0).abs() < 1e-3, "{method:?} stopped at {t}")
            }
            other => panic!("{method:?}: {other:?}"),
        }
        // Stopped for good, still without a panic.
        assert!(matches!(s.advance(2.0), Err(SolveError::BlowUp { .. })));
    }
}

// ---------------------------------------------------------------- dense output

#[test]
fn samples_do_not_change_the_steps() {
    type Build = Box<dyn Fn() -> Box<dyn OdeSolver>>;
    let cases: Vec<(&str, Build, f64)> = vec![
        (
            "dop853",
            Box::new(|| {
                make(
                    Method::Dop853 {
                        stiffness: StiffnessMode::Report,
                    },
                    VanDerPol { mu: 5.0 },
                    0.0,
                    &[2.0, 0.0],
                    &vdp_opts(1e-7),
                )
                .unwrap()
            }),
            30.0,
        ),
        (
            "radau5",
            Box::new(|| {
                make(
                    Method::Radau5,
                    VanDerPol { mu: MU },
                    0.0,
                    &[2.0, 0.0],
                    &vdp_opts(1e-6),
                )
                .unwrap()
            }),
            3000.0,
        ),
        (
            "auto",
            Box::new(|| {
                make(
                    Method::Auto,
                    Robertson,
                    0.0,
                    &[1.0, 0.0, 0.0],
                    &robertson_opts(1e-6),
                )
                .unwrap()
            }),
            100.0,
        ),
        (
            "rk4",
            Box::new(|| {
                make(
                    Method::Rk4 { dt: 0.01 },
                    Spin,
                    0.0,
                    &[1.0, 0.0],
                    &Options::default(),
                )
                .unwrap()
            }),
            2.0,
        ),
    ];
    for (name, build, t_end) in cases {
        let mut plain = build();
        let y_plain = plain.advance(t_end).unwrap().to_vec();
        let mut sampled = build();
        for k in 1..=1000 {
            let y = sampled.advance(t_end * k as f64 / 1000.0).unwrap();
            assert!(y.iter().all(|v| v.is_finite()));
        }
        let y_sampled = sampled.advance(t_end).unwrap().to_vec();
        let (a, b) = (plain.work(), sampled.work());
        assert_eq!((a.steps, a.rejected), (b.steps, b.rejected), "{name}");
        assert_eq!(y_plain, y_sampled, "{name}");
    }
}

#[test]
fn dense_output_is_accurate_between_steps() {
    // Radau's collocation polynomial and DOP853's interpolant against the
    // exact rotation, at points that are not step ends.
    let opts = Options::with_tol(1e-10, 1e-10);
    let mut solvers: Vec<Box<dyn OdeSolver>> = vec![
        Box::new(Dop853::new(Spin, 0.0, &[1.0, 0.0], &opts).unwrap()),
        Box::new(Radau5::new(Spin, 0.0, &[1.0, 0.0], &opts).unwrap()),
    ];
    for s in solvers.iter_mut() {
        for k in 1..=97 {
            let t = 2.0 * k as f64 / 97.0;
            let y = s.advance(t).unwrap();
            let e = spin_exact(t);
            let err = (y[0] - e[0]).abs().max((y[1] - e[1]).abs());
            assert!(err < 1e-7, "{} at {t}: {err}", s.name());
        }
    }
}

// ---------------------------------------------------------------- interface

#[test]
fn finite_difference_jacobian_matches_the_analytic_one() {
    let sys = VanDerPol { mu: 30.0 };
    let y = [1.3, -0.7];
    let mut exact = DMatrix::zeros(2, 2);
    sys.jacobian(0.0, &y, &mut exact);
    let mut fd = DMatrix::zeros(2, 2);
    finite_difference_jacobian(&sys, 0.0, &y, &mut fd);
    for i in 0..2 {
        for j in 0..2 {
            let scale = exact[(i, j)].abs().max(1.0);
            assert!(
                (fd[(i, j)] - exact[(i, j)]).abs() < 1e-8 * scale,
                "[{i}][{j}]: {} vs {}",
                fd[(i, j)],
                exact[(i, j)]
            );
        }
    }
}

#[test]
fn bad_inputs_are_errors_not_panics() {
    let opts = Options::default();
    let invalid =
        |r: Result<Box<dyn OdeSolver>, SolveError>| matches!(r, Err(SolveError::Invalid(_)));
    let methods = [
        Method::Dop853 {
            stiffness: StiffnessMode::Report,
        },
        Method::Radau5,
        Method::Auto,
        Method::Rk4 { dt: 0.1 },
    ];
    for m in methods {
        assert!(
            invalid(make(m, Spin, 0.0, &[1.0], &opts)),
            "{m:?}: wrong length"
        );
        assert!(
            invalid(make(m, Spin, 0.0, &[f64::NAN, 0.0], &opts)),
            "{m:?}: NaN"
        );
        assert!(
            invalid(make(m, Spin, f64::INFINITY, &[1.0, 0.0], &opts)),
            "{m:?}: t0"
        );
        let mut s = make(m, Spin, 0.0, &[1.0, 0.0], &opts).unwrap();
        s.advance(1.0).unwrap();
        assert!(
            matches!(s.advance(0.5), Err(SolveError::Invalid(_))),
            "{m:?}: backwards"
        );
        assert!(
            matches!(s.advance(f64::NAN), Err(SolveError::Invalid(_))),
            "{m:?}: NaN t"
        );
        // A refused request does not stop the run.
        assert!(s.advance(1.5).is_ok(), "{m:?}");
        let mut buf = [0.0; 2];
        assert!(s.dense(-1.0, &mut buf).is_err());
        assert!(s.dense(s.t(), &mut [0.0; 3]).is_err());
    }
    for bad in [
        Options {
            rtol: f64::NAN,
            ..Options::default()
        },
        Options {
            rtol: -1.0,
            ..Options::default()
        },
        Options {
            atol: Atol::Scalar(0.0),
            ..Options::default()
        },
        Options {
            atol: Atol::PerComponent(vec![1e-6]),
            ..Options::default()
        },
        Options {
            max_steps: 0,
            ..Options::default()
        },
        Options {
            h0: Some(-1.0),
            ..Options::default()
        },
        Options {
            t_stop: Some(f64::NAN),
            ..Options::default()
        },
    ] {
        assert!(
            invalid(make(Method::Radau5, Spin, 0.0, &[1.0, 0.0], &bad)),
            "{bad:?}"
        );
        assert!(
            invalid(make(Method::Auto, Spin, 0.0, &[1.0, 0.0], &bad)),
            "{bad:?}"
        );
    }
    assert!(invalid(make(
        Method::Rk4 { dt: 0.0 },
        Spin,
        0.0,
        &[1.0, 0.0],
        &opts
    )));
}

#[test]
fn step_budget_is_a_value() {
    let opts = Options {
        max_steps: 50,
        ..vdp_opts(1e-6)
    };
    let mut dop = Dop853::new(VanDerPol { mu: MU }, 0.0, &[2.0, 0.0], &opts).unwrap();
    assert!(matches!(
        dop.advance(3000.0),
        Err(SolveError::StepBudget { .. })
    ));
    let mut rk4 = Rk4::new(Spin, 0.0, &[1.0, 0.0], 1e-3, &opts).unwrap();
    // Refused before stepping: 1000 steps would be needed.
    assert!(matches!(
        rk4.advance(1.0),
        Err(SolveError::StepBudget { .. })
    ));
    assert_eq!(rk4.work().steps, 0);
}

#[test]
fn t_stop_lands_exactly_and_bounds_requests() {
    let opts = Options {
        t_stop: Some(1.0),
        ..Options::with_tol(1e-8, 1e-8)
    };
    for m in [
        Method::Dop853 {
            stiffness: StiffnessMode::Report,
        },
        Method::Radau5,
        Method::Auto,
    ] {
        let mut s = make(m, Square, 0.0, &[0.5], &opts).unwrap();
        let y = s.advance(1.0).unwrap()[0];
        assert_eq!(s.t(), 1.0, "{m:?}");
        // x = 0.5/(1 − 0.5 t) = 1 at t = 1.
        assert!((y - 1.0).abs() < 1e-6, "{m:?}: {y}");
        assert!(matches!(s.advance(1.5), Err(SolveError::Invalid(_))));
    }
}

/// y' = −√y reaches 0 at t = 2 (y = (1 − t/2)²) and f is undefined below.
struct SqrtDecay;

impl OdeSystem for SqrtDecay {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = -y[0].sqrt();
    }
}

#[test]
fn leaving_the_domain_of_f_stops_without_nan() {
    let methods = [
        Method::Dop853 {
            stiffness: StiffnessMode::Report,
        },
        Method::Radau5,
        Method::Auto,
        Method::Rk4 { dt: 1e-2 },
    ];
    for method in methods {
        let mut s = make(method, SqrtDecay, 0.0, &[1.0], &Options::default()).unwrap();
        let mut failure = None;
        for k in 1..=300 {
            match s.advance(k as f64 * 0.01) {
                Ok(y) => assert!(y[0].is_finite() && y[0] >= 0.0, "{method:?}: {y:?}"),
                Err(e) => {
                    failure = Some(e);
                    break;
                }
            }
        }
        // y stays within [0, 1]: the steps collapse at the edge of f's
        // domain, which is no blow-up (the scene names the domain).
        match failure {
            Some(SolveError::StepSize { t, .. }) => {
                assert!((t - 2.0).abs() < 0.02, "{method:?}: {t}")
            }
            Some(SolveError::BlowUp { t }) if matches!(method, Method::Rk4 { .. }) => {
                assert!((t - 2.0).abs() < 0.02, "{method:?}: {t}")
            }
            other => panic!("{method:?}: {other:?}"),
        }
    }
}

/// x' = −λx.
struct Decay(f64);

impl OdeSystem for Decay {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = -self.0 * y[0];
    }
}

/// x'' = −ω²x as (x, v): a non-normal Jacobian whose rate is ω, not ω².
struct Spring(f64);

impl OdeSystem for Spring {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = y[1];
        dy[1] = -self.0 * self.0 * y[0];
    }
}

#[test]
fn rk4_past_its_stability_bound_is_refused_with_the_rate_and_the_bound() {
    let opts = Options::default();
    // x' = −100x: stable while dt·100 < 2.78.
    let mut s = make(Method::Rk4 { dt: 0.03 }, Decay(100.0), 0.0, &[1.0], &opts).unwrap();
    match s.advance(1.0) {
        Err(SolveError::Unstable {
            rate, dt, limit, ..
        }) => {
            assert!((rate - 100.0).abs() < 1.0, "{rate}");
            assert_eq!((dt, limit), (0.03, 2.78));
        }
        other => panic!("{other:?}"),
    }
    let e = make(Method::Rk4 { dt: 0.03 }, Decay(100.0), 0.0, &[1.0], &opts)
        .unwrap()
        .advance(1.0)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("dt < 0.028") && e.contains("about 100 per time unit"),
        "{e}"
    );
    // Inside the bound it runs, and decays (R(−2) = 1/3 a step).
    let mut s = make(Method::Rk4 { dt: 0.02 }, Decay(100.0), 0.0, &[1.0], &opts).unwrap();
    let x = s.advance(1.0).unwrap()[0];
    assert!(x > 0.0 && x < 1e-20, "{x}");
    // A stiff spring ω = 1000 written as (x, v): the rate is 1000 (not
    // ω² = 1e6), so dt = 3e-3 is refused and 1e-4 runs accurately.
    let mut s = make(
        Method::Rk4 { dt: 3e-3 },
        Spring(1000.0),
        0.0,
        &[1.0, 0.0],
        &opts,
    )
    .unwrap();
    match s.advance(0.1) {
        Err(SolveError::Unstable { rate, .. }) => assert!((rate - 1000.0).abs() < 20.0, "{rate}"),
        other => panic!("{other:?}"),
    }
    let mut s = make(
        Method::Rk4 { dt: 1e-4 },
        Spring(1000.0),
        0.0,
        &[1.0, 0.0],
        &opts,
    )
    .unwrap();
    let y = s.advance(0.1).unwrap().to_vec();
    assert!((y[0] - (1000.0f64 * 0.1).cos()).abs() < 1e-3, "{y:?}");
}
