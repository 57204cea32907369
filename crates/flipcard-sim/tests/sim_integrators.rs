//! The step-based solvers against closed forms (the symmetric top, the
//! separatrix of I = (3, 4, 6)), their orders of convergence, their
//! invariants, their step budgets and the extreme cases of the model.

use flipcard_sim::error::SolveError;
use flipcard_sim::solvers::budget::Budget;
use flipcard_sim::solvers::registry::{Kind, default_dt_for};
use flipcard_sim::{Body, Method, Needs, Options, Solver, State, make, make_with};
use nalgebra::{UnitQuaternion, Vector3};

const OMEGA: Needs = Needs { orientation: false };
const BOTH: Needs = Needs { orientation: true };

fn body(i: [f64; 3]) -> Body {
    Body::new(i).expect("physical body")
}

fn solver(method: Method, b: Body, w: [f64; 3], needs: Needs) -> Box<dyn Solver> {
    make(method, b, Vector3::from(w), needs).expect("valid run")
}

/// States at `n + 1` evenly spaced times over [0, t_end].
fn trajectory(s: &mut dyn Solver, t_end: f64, n: usize) -> Vec<(f64, State)> {
    (0..=n)
        .map(|k| {
            let t = t_end * k as f64 / n as f64;
            (t, s.advance(t).expect("run within budget"))
        })
        .collect()
}

/// Symmetric top I = (I⊥, I⊥, I₃): the two terms of
/// H = |L|²/2I⊥ + (1/I₃ − 1/I⊥) L₃²/2 commute, so the motion is a turn of
/// φ = |L|t/I⊥ about the initial body L followed by θ = (1/I₃ − 1/I⊥)L₃t
/// about e₃ (L in the body turns by −θ).
fn symmetric_top(i_perp: f64, i3: f64, w0: Vector3<f64>, t: f64) -> State {
    let l0 = Vector3::new(i_perp * w0[0], i_perp * w0[1], i3 * w0[2]);
    let phi = l0.norm() * t / i_perp;
    let theta = (1.0 / i3 - 1.0 / i_perp) * l0[2] * t;
    let q = UnitQuaternion::from_scaled_axis(l0.normalize() * phi)
        * UnitQuaternion::from_scaled_axis(Vector3::z() * theta);
    let l = UnitQuaternion::from_scaled_axis(Vector3::z() * -theta) * l0;
    State {
        omega: Vector3::new(l[0] / i_perp, l[1] / i_perp, l[2] / i3),
        q,
    }
}

const TOP: (f64, f64, [f64; 3]) = (2.0, 3.0, [1.0, -0.5, 3.0]);

/// Largest error of ω (relative to |ω|) and of q over a run of the top.
fn top_errors(method: Method, needs: Needs, t_end: f64) -> (f64, f64) {
    let (ip, i3, w) = TOP;
    let mut s = solver(method, body([ip, ip, i3]), w, needs);
    let (mut ew, mut eq) = (0.0f64, 0.0f64);
    for (t, state) in trajectory(s.as_mut(), t_end, 97) {
        let exact = symmetric_top(ip, i3, Vector3::from(w), t);
        ew = ew.max((state.omega - exact.omega).norm() / exact.omega.norm());
        let dq = state.q.quaternion() - exact.q.quaternion();
        let dq_flip = state.q.quaternion() + exact.q.quaternion();
        eq = eq.max(dq.norm().min(dq_flip.norm()));
    }
    (ew, eq)
}

fn order(errors: &[f64]) -> Vec<f64> {
    errors.windows(2).map(|e| (e[0] / e[1]).log2()).collect()
}

#[test]
fn the_closed_form_top_obeys_euler_and_keeps_space_momentum() {
    // Guard the reference itself: finite differences against Euler's
    // equations and q̇ = ½ q ⊗ (0, ω), and constant space-frame L.
    let (ip, i3, w) = TOP;
    let b = body([ip, ip, i3]);
    let w0 = Vector3::from(w);
    let (t, h) = (1.3, 1e-5);
    let s = symmetric_top(ip, i3, w0, t);
    let (a, c) = (
        symmetric_top(ip, i3, w0, t + h),
        symmetric_top(ip, i3, w0, t - h),
    );
    let w_dot = (a.omega - c.omega) / (2.0 * h);
    assert!((w_dot - b.omega_dot(&s.omega)).norm() < 1e-8);
    let q_dot = (a.q.quaternion() - c.q.quaternion()) / (2.0 * h);
    let expected = s.q.quaternion() * nalgebra::Quaternion::from_imag(s.omega) * 0.5;
    assert!((q_dot - expected).norm() < 1e-8);
    let l0 = b.momentum(&w0);
    assert!((b.momentum_in_space(&s) - l0).norm() < 1e-13);
}

#[test]
fn rk4_converges_at_fourth_order() {
    let errs: Vec<(f64, f64)> = [0.04, 0.02, 0.01]
        .iter()
        .map(|&dt| top_errors(Method::Rk4 { dt }, BOTH, 10.0))
        .collect();
    for p in order(&errs.iter().map(|e| e.0).collect::<Vec<_>>()) {
        assert!((3.7..4.4).contains(&p), "ω order {p}: {errs:?}");
    }
    for p in order(&errs.iter().map(|e| e.1).collect::<Vec<_>>()) {
        assert!((3.7..4.4).contains(&p), "q order {p}: {errs:?}");
    }
}

#[test]
fn strang_splitting_converges_at_second_order() {
    let errs: Vec<(f64, f64)> = [0.02, 0.01, 0.005]
        .iter()
        .map(|&dt| top_errors(Method::Splitting { dt }, BOTH, 10.0))
        .collect();
    for p in order(&errs.iter().map(|e| e.0).collect::<Vec<_>>()) {
        assert!((1.9..2.1).contains(&p), "ω order {p}: {errs:?}");
    }
    for p in order(&errs.iter().map(|e| e.1).collect::<Vec<_>>()) {
        assert!((1.9..2.1).contains(&p), "q order {p}: {errs:?}");
    }
}

#[test]
fn suzuki_composition_converges_at_fourth_order() {
    let errs: Vec<(f64, f64)> = [0.08, 0.04, 0.02]
        .iter()
        .map(|&dt| top_errors(Method::Splitting4 { dt }, BOTH, 10.0))
        .collect();
    for p in order(&errs.iter().map(|e| e.0).collect::<Vec<_>>()) {
        assert!((3.7..4.4).contains(&p), "ω order {p}: {errs:?}");
    }
    for p in order(&errs.iter().map(|e| e.1).collect::<Vec<_>>()) {
        assert!((3.7..4.4).contains(&p), "q order {p}: {errs:?}");
    }
}

/// Largest error of ω (relative to |ω|) and of q against the exact solver
/// over `n + 1` evenly spaced samples.
fn exact_errors(method: Method, b: Body, w: [f64; 3], t_end: f64, n: usize) -> (f64, f64) {
    let mut exact = solver(Method::Exact, b, w, BOTH);
    let mut s = solver(method, b, w, BOTH);
    let (mut ew, mut eq) = (0.0f64, 0.0f64);
    for (t, state) in trajectory(s.as_mut(), t_end, n) {
        let r = exact.advance(t).expect("exact");
        ew = ew.max((state.omega - r.omega).norm() / r.omega.norm());
        let (a, z) = (state.q.quaternion(), r.q.quaternion());
        eq = eq.max((a - z).norm().min((a + z).norm()));
    }
    (ew, eq)
}

/// The fixed-step methods against the exact solution of an asymmetric body
/// through two flips: the error at the end shrinks as dt^p.
fn orders_against_exact(method: fn(f64) -> Method, dts: [f64; 3]) -> Vec<f64> {
    let b = body([1.0, 2.0, 3.0]);
    let w = [0.5, 2.0, 0.3];
    let errors: Vec<f64> = dts
        .iter()
        .map(|&dt| exact_errors(method(dt), b, w, 5.0, 1).0)
        .collect();
    order(&errors)
}

#[test]
fn orders_hold_on_a_flipping_body() {
    for p in orders_against_exact(|dt| Method::Rk4 { dt }, [0.02, 0.01, 0.005]) {
        assert!((3.7..4.4).contains(&p), "rk4 {p}");
    }
    for p in orders_against_exact(|dt| Method::Splitting { dt }, [0.01, 0.005, 0.0025]) {
        assert!((1.9..2.1).contains(&p), "splitting {p}");
    }
    for p in orders_against_exact(|dt| Method::Splitting4 { dt }, [0.04, 0.02, 0.01]) {
        assert!((3.7..4.4).contains(&p), "splitting4 {p}");
    }
}

/// Well-conditioned asymmetric cases (far enough from the separatrix that
/// rounding is not amplified beyond the tolerance): precession about the
/// largest and the smallest axis, a needle-like body, and a few flips of
/// the notes' case (a).
const CONDITIONED: [([f64; 3], [f64; 3], f64); 4] = [
    ([1.0, 2.0, 3.0], [0.3, 1.0, 3.0], 100.0),
    ([1.0, 2.0, 3.0], [3.0, 1.0, 0.3], 100.0),
    ([1e-3, 1.0, 1.0005], [1.0, 1.0, 0.0], 100.0),
    ([1.0, 2.0, 3.0], [0.01, 10.0, 0.01], 20.0),
];

#[test]
fn adaptive_agrees_with_the_exact_solver() {
    for (i, w, t_end) in CONDITIONED {
        for tol in [1e-8, 1e-10] {
            let (ew, eq) = exact_errors(Method::Adaptive { tol }, body(i), w, t_end, 1000);
            assert!(ew < 100.0 * tol, "{i:?} {w:?} tol {tol}: ω error {ew}");
            assert!(eq < 1000.0 * tol, "{i:?} {w:?} tol {tol}: q error {eq}");
        }
    }
}

#[test]
fn fixed_step_methods_agree_with_the_exact_solver() {
    for (i, w, t_end) in CONDITIONED {
        let dt = 1e-5 * t_end;
        for method in [Method::Rk4 { dt }, Method::Splitting4 { dt }] {
            let (ew, eq) = exact_errors(method, body(i), w, t_end, 100);
            assert!(ew < 1e-6 && eq < 1e-6, "{method:?} {i:?} {w:?}: {ew} {eq}");
        }
    }
}

#[test]
fn adaptive_meets_its_tolerance() {
    // 100 s is 150 rad of body precession and 160 rad of spin.
    let mut last = f64::INFINITY;
    for tol in [1e-6, 1e-8, 1e-10, 1e-12] {
        for needs in [OMEGA, BOTH] {
            let (ew, eq) = top_errors(Method::Adaptive { tol }, needs, 100.0);
            assert!(ew < 100.0 * tol, "tol {tol} {needs:?}: ω error {ew}");
            if needs.orientation {
                assert!(eq < 100.0 * tol, "tol {tol}: q error {eq}");
            }
            if !needs.orientation {
                assert!(ew < last, "tighter tol must help: {ew} after {last}");
                last = ew;
            }
        }
    }
}

#[test]
fn adaptive_dense_output_is_as_good_as_its_steps() {
    // Samples far denser than the steps, all served by interpolation.
    let (ip, i3, w) = TOP;
    let mut s = solver(Method::Adaptive { tol: 1e-10 }, body([ip, ip, i3]), w, BOTH);
    let mut worst = 0.0f64;
    for (t, state) in trajectory(s.as_mut(), 20.0, 5000) {
        let exact = symmetric_top(ip, i3, Vector3::from(w), t);
        worst = worst.max((state.omega - exact.omega).norm() / exact.omega.norm());
    }
    assert!(s.work().steps < 500, "{:?}", s.work());
    assert!(worst < 1e-8, "{worst}");
}

#[test]
fn sampling_never_changes_the_trajectory() {
    let b = body([1.0, 2.0, 3.0]);
    let w = [0.01, 10.0, 0.01];
    for method in [
        Method::Adaptive { tol: 1e-9 },
        Method::Rk4 { dt: 0.003 },
        Method::Splitting { dt: 0.003 },
        Method::Splitting4 { dt: 0.01 },
    ] {
        let mut dense = solver(method, b, w, BOTH);
        trajectory(dense.as_mut(), 7.7, 1000);
        let mut sparse = solver(method, b, w, BOTH);
        let end = sparse.advance(7.7).unwrap();
        let end_dense = dense.advance(7.7).unwrap();
        assert_eq!(end, end_dense, "{method:?}");
        assert_eq!(dense.work().steps, sparse.work().steps, "{method:?}");
    }
}

#[test]
fn going_back_in_time_is_refused() {
    let b = body([1.0, 2.0, 3.0]);
    for method in [
        Method::Adaptive { tol: 1e-9 },
        Method::Rk4 { dt: 0.01 },
        Method::Splitting { dt: 0.01 },
    ] {
        let mut s = solver(method, b, [1.0, 1.0, 1.0], BOTH);
        s.advance(1.0).unwrap();
        assert!(matches!(s.advance(0.5), Err(SolveError::Invalid(_))));
        assert!(matches!(s.advance(f64::NAN), Err(SolveError::Invalid(_))));
    }
}

#[test]
fn omega_only_runs_leave_q_alone() {
    let b = body([1.0, 2.0, 3.0]);
    let w = [0.3, 2.0, 0.1];
    for method in [
        Method::Adaptive { tol: 1e-10 },
        Method::Rk4 { dt: 0.01 },
        Method::Splitting { dt: 0.01 },
        Method::Splitting4 { dt: 0.01 },
    ] {
        let mut lean = solver(method, b, w, OMEGA);
        let mut full = solver(method, b, w, BOTH);
        for (t, state) in trajectory(lean.as_mut(), 10.0, 50) {
            assert_eq!(state.q, UnitQuaternion::identity(), "{method:?}");
            let other = full.advance(t).unwrap();
            assert!(
                (state.omega - other.omega).norm() < 1e-7,
                "{method:?} at {t}: {} vs {}",
                state.omega,
                other.omega
            );
        }
    }
}

#[test]
fn splitting_keeps_momentum_and_unit_quaternion_to_rounding() {
    let b = body([1.0, 2.0, 3.0]);
    let w0 = Vector3::new(0.01, 10.0, 0.01);
    let l0 = b.momentum(&w0);
    for method in [
        Method::Splitting { dt: 0.01 },
        Method::Splitting4 { dt: 0.01 },
    ] {
        let mut s = make(method, b, w0, BOTH).unwrap();
        for (_, state) in trajectory(s.as_mut(), 1000.0, 200) {
            let l2 = b.l2(&state.omega);
            assert!(
                (l2 / l0.norm_squared() - 1.0).abs() < 1e-12,
                "{method:?} |L|²"
            );
            assert!(
                (state.q.quaternion().norm() - 1.0).abs() < 1e-12,
                "{method:?} |q|"
            );
            let drift = (b.momentum_in_space(&state) - l0).norm() / l0.norm();
            assert!(drift < 1e-11, "{method:?} space L drift {drift}");
        }
    }
}

/// Largest relative energy error over the first and the last tenth of a run.
fn energy_error_early_late(method: Method, t_end: f64) -> (f64, f64) {
    let b = body([1.0, 2.0, 3.0]);
    let w0 = Vector3::new(1.0, 0.5, 0.8);
    let e0 = b.energy(&w0);
    let mut s = make(method, b, w0, OMEGA).unwrap();
    let n = 2000;
    let (mut early, mut late) = (0.0f64, 0.0f64);
    for (k, (_, state)) in trajectory(s.as_mut(), t_end, n).into_iter().enumerate() {
        let e = (b.energy(&state.omega) / e0 - 1.0).abs();
        assert!(e.is_finite());
        if k <= n / 10 {
            early = early.max(e);
        } else if k >= n - n / 10 {
            late = late.max(e);
        }
    }
    (early, late)
}

#[test]
fn splitting_energy_error_stays_bounded_while_rk4_drifts() {
    // ~1.3e4 nutation periods at about 25 steps each.
    let t_end = 2e4;
    let (early, late) = energy_error_early_late(Method::Splitting { dt: 0.1 }, t_end);
    assert!(
        late < 2.0 * early,
        "splitting energy drifts: {early} → {late}"
    );
    assert!(late < 1e-2);
    let (early, late) = energy_error_early_late(Method::Rk4 { dt: 0.1 }, t_end);
    assert!(
        late > 5.0 * early,
        "rk4 energy should drift: {early} → {late}"
    );
}

#[test]
fn budget_refuses_fast_spins_up_front() {
    let b = body([1.0, 2.0, 3.0]);
    let w = Vector3::new(1e9, 2e8, 3e8);
    for needs in [OMEGA, BOTH] {
        let mut s = make(Method::Adaptive { tol: 1e-10 }, b, w, needs).unwrap();
        let err = s.plan(3.0).unwrap_err();
        let SolveError::StepBudget { reason: msg, .. } = &err else {
            panic!("{err:?}")
        };
        assert!(msg.starts_with("stiff: "), "{msg}");
        assert!(
            msg.contains("rad/s") && msg.contains("use the exact solver"),
            "{msg}"
        );
        // Without a plan, the first advance refuses just the same, unstepped.
        let mut s = make(Method::Adaptive { tol: 1e-10 }, b, w, needs).unwrap();
        assert!(matches!(s.advance(3.0), Err(SolveError::StepBudget { .. })));
        assert_eq!(s.work().steps, 0);
    }
    let mut s = make(Method::Rk4 { dt: 1e-9 }, b, w, BOTH).unwrap();
    assert!(matches!(s.plan(3.0), Err(SolveError::StepBudget { .. })));
    let mut s = make(Method::Splitting { dt: 1e-9 }, b, w, BOTH).unwrap();
    assert!(matches!(s.advance(3.0), Err(SolveError::StepBudget { .. })));
    assert_eq!(s.work().steps, 0);
}

#[test]
fn budget_stops_a_run_that_outgrows_its_estimate() {
    // The up-front estimate passes (it is deliberately low), the count
    // during the run does not.
    let b = body([1.0, 2.0, 3.0]);
    let w = Vector3::new(0.01, 10.0, 0.01);
    let options = Options {
        budget: Budget { max_steps: 1000 },
    };
    let mut s = make_with(Method::Adaptive { tol: 1e-10 }, b, w, OMEGA, options).unwrap();
    s.plan(100.0).expect("estimate under budget");
    let mut outcome = Ok(());
    for k in 1..=100 {
        if let Err(e) = s.advance(k as f64) {
            outcome = Err(e);
            break;
        }
    }
    assert!(
        matches!(outcome, Err(SolveError::StepBudget { .. })),
        "{outcome:?}"
    );
    let w = s.work();
    assert!(w.steps + w.rejected <= 1001, "{w:?}");
}

/// Relative drift of energy and |L|² over a run, asserting finite values.
fn invariant_drift(method: Method, i: [f64; 3], w: [f64; 3], t_end: f64) -> (f64, f64) {
    let b = body(i);
    let w0 = Vector3::from(w);
    let (e0, l0) = (b.energy(&w0), b.l2(&w0));
    let mut s = make(method, b, w0, BOTH).unwrap();
    s.plan(t_end).unwrap();
    let (mut de, mut dl) = (0.0f64, 0.0f64);
    for (t, state) in trajectory(s.as_mut(), t_end, 400) {
        let finite = state.omega.iter().all(|v| v.is_finite())
            && state.q.coords.iter().all(|v| v.is_finite());
        assert!(finite, "{method:?} {i:?} {w:?}: non-finite at t = {t}");
        if e0 > 0.0 {
            de = de.max((b.energy(&state.omega) / e0 - 1.0).abs());
            dl = dl.max((b.l2(&state.omega) / l0 - 1.0).abs());
        } else {
            de = de.max(b.energy(&state.omega));
            dl = dl.max(b.l2(&state.omega));
        }
    }
    (de, dl)
}

/// The extreme cases of the model: every method stays finite and keeps the
/// invariants within its accuracy class, and the adaptive solver agrees with
/// the exact one (to a bound that is looser where the case itself amplifies
/// rounding: dozens of flips next to the separatrix).
#[test]
fn extreme_cases_stay_finite_and_keep_invariants() {
    // (name, inertia, ω₀, span, bound on the adaptive ω error vs exact)
    type Case = (&'static str, [f64; 3], [f64; 3], f64, f64);
    let cases: [Case; 8] = [
        ("needle 1e6", [1e-6, 1.0, 1.0], [0.3, 1.0, 0.5], 10.0, 1e-8),
        (
            "needle asymmetric",
            [1e-6, 1.0, 1.0 + 1e-6],
            [0.3, 1.0, 0.5],
            10.0,
            1e-8,
        ),
        (
            "I1 = I2(1 + 1e-12)",
            [1.0 + 1e-12, 1.0, 1.5],
            [0.4, 0.3, 2.0],
            10.0,
            1e-8,
        ),
        ("flat body", [1.0, 1.0, 2.0], [0.5, 1.0, 1.0], 10.0, 1e-8),
        ("separatrix", [3.0, 4.0, 6.0], [2.0, 0.5, 1.0], 20.0, 1e-8),
        (
            "near separatrix",
            [3.0, 4.0, 6.0],
            [2.0, 0.5, 1.0 + 1e-12],
            20.0,
            1e-8,
        ),
        ("fast spin", [1.0, 2.0, 3.0], [10.0, 1e4, 10.0], 0.1, 1e-6),
        (
            "perturbation 1e-15",
            [1.0, 2.0, 3.0],
            [1e-15, 10.0, 1e-15],
            10.0,
            1e-6,
        ),
    ];
    for (name, i, w, t_end, bound) in cases {
        let b = body(i);
        let dt = flipcard_sim::solvers::registry::default_dt(&b, &Vector3::from(w));
        let (de, dl) = invariant_drift(Method::Adaptive { tol: 1e-10 }, i, w, t_end);
        assert!(de < 1e-8 && dl < 1e-8, "adaptive {name}: {de} {dl}");
        let (ew, eq) = exact_errors(Method::Adaptive { tol: 1e-10 }, b, w, t_end, 400);
        assert!(
            ew < bound && eq < 10.0 * bound,
            "adaptive vs exact, {name}: {ew} {eq}"
        );
        let (de, dl) = invariant_drift(Method::Rk4 { dt }, i, w, t_end);
        assert!(de < 1e-4 && dl < 1e-4, "rk4 {name}: {de} {dl}");
        let w0 = Vector3::from(w);
        for method in [
            Method::Splitting {
                dt: default_dt_for(Kind::Splitting, &b, &w0),
            },
            Method::Splitting4 {
                dt: default_dt_for(Kind::Splitting4, &b, &w0),
            },
        ] {
            let (de, dl) = invariant_drift(method, i, w, t_end);
            // Rounding only: a random walk over up to ~1e6 rotations.
            assert!(dl < 1e-12, "{method:?} {name}: |L|² {dl}");
            assert!(de < 1e-3, "{method:?} {name}: energy {de}");
        }
    }
}

#[test]
fn zero_spin_stays_at_rest() {
    let b = body([1.0, 2.0, 3.0]);
    for method in [
        Method::Adaptive { tol: 1e-10 },
        Method::Rk4 { dt: 0.01 },
        Method::Splitting { dt: 0.01 },
        Method::Splitting4 { dt: 0.01 },
    ] {
        let mut s = solver(method, b, [0.0; 3], BOTH);
        for (_, state) in trajectory(s.as_mut(), 100.0, 10) {
            assert_eq!(state.omega, Vector3::zeros(), "{method:?}");
            assert_eq!(state.q.quaternion().w, 1.0, "{method:?}");
        }
    }
    // Nothing moves, so the adaptive solver strides over the span.
    let mut s = solver(Method::Adaptive { tol: 1e-10 }, b, [0.0; 3], BOTH);
    s.advance(1e6).unwrap();
    assert!(s.work().steps < 100, "{:?}", s.work());
}

/// On the separatrix of I = (3, 4, 6) with ω = (2, 0.5, 1) (Δ₂ = 0 exactly),
/// ω₂ = W tanh(λt + c), ω₃ = √(19/18) sech(λt + c), ω₁ = 2ω₃ with W² = 19/4,
/// λ = √19/6: the body creeps towards the middle axis and never flips.
#[test]
fn adaptive_follows_the_separatrix_without_flipping() {
    let b = body([3.0, 4.0, 6.0]);
    let w0 = Vector3::new(2.0, 0.5, 1.0);
    assert_eq!(
        b.l2(&w0),
        2.0 * b.energy(&w0) * 4.0,
        "exactly on the separatrix"
    );
    let big_w = (19.0f64 / 4.0).sqrt();
    let lambda = 19.0f64.sqrt() / 6.0;
    let c = (0.5 / big_w).atanh();
    let mut s = make(Method::Adaptive { tol: 1e-12 }, b, w0, OMEGA).unwrap();
    let mut previous = 0.0;
    for (t, state) in trajectory(s.as_mut(), 20.0, 200) {
        let u = lambda * t + c;
        let w3 = (19.0f64 / 18.0).sqrt() / u.cosh();
        let exact = Vector3::new(2.0 * w3, big_w * u.tanh(), w3);
        let err = (state.omega - exact).norm() / exact.norm();
        assert!(err < 1e-9, "t = {t}: {} vs {exact} ({err})", state.omega);
        assert!(state.omega[1] >= previous, "ω₂ must creep up monotonically");
        previous = state.omega[1];
    }
}

#[test]
fn tiny_perturbation_of_the_middle_axis_grows_at_sqrt_k() {
    // k = (I3 − I2)(I2 − I1)/(I1 I3) Ω² = 100/3 for I = (1, 2, 3), Ω = 10.
    let b = body([1.0, 2.0, 3.0]);
    let mut s = make(
        Method::Adaptive { tol: 1e-12 },
        b,
        Vector3::new(1e-15, 10.0, 1e-15),
        OMEGA,
    )
    .unwrap();
    // ω₁ grows from 1e-15 to ~1e-7 by t = 3 and ~1e-3 by t = 4.5: measure
    // there, well above the absolute error floor tol·|ω₀| and still linear.
    let (t1, t2) = (3.0, 4.5);
    let a = s.advance(t1).unwrap().omega[0].abs();
    let z = s.advance(t2).unwrap().omega[0].abs();
    let rate = (z / a).ln() / (t2 - t1);
    let sqrt_k = (100.0f64 / 3.0).sqrt();
    assert!((rate / sqrt_k - 1.0).abs() < 1e-3, "{rate} vs {sqrt_k}");
}

#[test]
fn long_splitting_run_over_1e5_periods_stays_on_its_orbit() {
    // Precession about the largest axis, nutation period 2π/λ ≈ 4.2 s;
    // 1e5 periods at 24 steps per period, ω only.
    let b = body([1.0, 2.0, 3.0]);
    let w0 = Vector3::new(0.3, 0.2, 1.0);
    let lambda = flipcard_sim::rigid::scales::scales(&b, &w0).nutation;
    let period = std::f64::consts::TAU / lambda;
    let t_end = 1e5 * period;
    let (e0, l0) = (b.energy(&w0), b.l2(&w0));
    let mut s = make(Method::Splitting { dt: period / 24.0 }, b, w0, OMEGA).unwrap();
    s.plan(t_end).unwrap();
    let mut worst = 0.0f64;
    for (_, state) in trajectory(s.as_mut(), t_end, 100) {
        worst = worst.max((b.energy(&state.omega) / e0 - 1.0).abs());
        assert!((b.l2(&state.omega) / l0 - 1.0).abs() < 1e-11);
    }
    assert!(worst < 1e-2, "energy error {worst}");
}

/// The rigid body is a system like a deck's: the solvers of deck systems
/// (Radau IIA, auto, DOP853 with stiffness detection) integrate its Euler
/// equations through the one right-hand side, and agree with the exact
/// solution.
#[test]
fn the_solvers_of_deck_systems_integrate_the_rigid_body() {
    use flipcard_sim::rigid::euler::{OmegaOnly, RigidSystem, WithOrientation};
    use flipcard_sim::solvers::ode;
    let b = body([1.0, 2.0, 2.5]);
    let w = Vector3::new(1.0, 0.3, 2.0);
    let opts = ode::Options::with_tol(1e-11, 1e-13);
    let mut exact = make(Method::Exact, b, w, BOTH).unwrap();
    let want = exact.advance(5.0).unwrap();
    let methods = [
        ode::Method::Radau5,
        ode::Method::Auto,
        ode::Method::Dop853 {
            stiffness: ode::StiffnessMode::Report,
        },
    ];
    for method in methods {
        let sys = OmegaOnly::new(&b, &w);
        let mut s = ode::make(method, sys, 0.0, &sys.initial(&w), &opts).unwrap();
        let got = sys.state(&s.advance(5.0).unwrap().try_into().unwrap());
        assert!(
            (got.omega - want.omega).norm() < 1e-7,
            "{method:?}: {got:?}"
        );
        let sys = WithOrientation::new(&b, &w);
        let mut s = ode::make(method, sys, 0.0, &sys.initial(&w), &opts).unwrap();
        let got = sys.state(&s.advance(5.0).unwrap().try_into().unwrap());
        assert!(
            (got.omega - want.omega).norm() < 1e-7,
            "{method:?}: {got:?}"
        );
        assert!(got.q.angle_to(&want.q) < 1e-6, "{method:?}: {got:?}");
    }
}
