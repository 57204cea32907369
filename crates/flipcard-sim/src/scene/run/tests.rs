use super::*;
use crate::scene::spec::{Measure, Panel};

fn scene(inertia: [f64; 3], omega: [f64; 3], duration: f64, show: &[Panel]) -> Scene {
    Scene {
        id: "test".into(),
        title: None,
        inertia,
        omega,
        duration,
        show: show.to_vec(),
        time_unit: "s".into(),
    }
}

fn seed(show: &[Panel]) -> Scene {
    scene([1.0, 2.0, 3.0], [0.01, 10.0, 0.01], 8.0, show)
}

fn methods() -> [Method; 5] {
    [
        Method::Exact,
        Method::Adaptive { tol: 1e-10 },
        Method::Splitting { dt: 1e-3 },
        Method::Splitting4 { dt: 4e-3 },
        Method::Rk4 { dt: 1e-3 },
    ]
}

/// Plays a run at 30 frames per scene second and checks every frame.
fn play(run: &mut SceneRun, mut check: impl FnMut(&Frame)) {
    let mut t = 0.0;
    while !run.finished() {
        t += 1.0 / 30.0;
        let frame = *run.advance_to(t);
        check(&frame);
    }
}

#[test]
fn omega_only_scene_never_evaluates_an_orientation() {
    let s = seed(&[Panel::Omega]);
    for method in methods() {
        let mut run = SceneRun::new(&s, method).unwrap();
        assert!(!run.plan().needs.orientation);
        play(&mut run, |f| assert!(f.q.is_none()));
        assert!(run.error().is_none(), "{method:?}: {:?}", run.error());
        // The solver itself hands back the untouched identity for q at every
        // time, far from where the tumbling body has turned.
        let mut solver = make(method, *run.body(), run.omega0(), run.plan().needs).unwrap();
        for k in 1..=20 {
            let state = solver.advance(0.4 * k as f64).unwrap();
            assert_eq!(state.q, UnitQuaternion::identity(), "{method:?}");
        }
    }
}

#[test]
fn body_scene_turns_the_body_about_fixed_momentum() {
    let s = seed(&[Panel::Omega, Panel::Body, Panel::Diagnostics]);
    for method in [Method::Exact, Method::Adaptive { tol: 1e-10 }] {
        let mut run = SceneRun::new(&s, method).unwrap();
        let body = *run.body();
        let l0 = body.momentum(&run.omega0());
        let mut turned = 0.0f64;
        play(&mut run, |f| {
            let q = f.q.expect("the body is drawn, so q is computed");
            turned = turned.max(q.angle());
            let l = q * body.momentum(&f.omega);
            assert!((l - l0).norm() < 1e-6 * l0.norm(), "{method:?} t={}", f.t);
        });
        assert!(turned > 1.0, "the body tumbles");
        let d = run.diagnostics().unwrap();
        assert!(d.lspace_drift.unwrap() < 1e-6 && d.qnorm_drift.unwrap() < 1e-9);
    }
}

#[test]
fn polhode_and_reference_only_when_shown() {
    let plain = SceneRun::new(&seed(&[Panel::Omega]), Method::Adaptive { tol: 1e-8 }).unwrap();
    assert!(plain.polhode().is_none() && plain.frame().polhode.is_none());
    assert!(plain.diagnostics().is_none() && !plain.has_reference());

    let mut shown = SceneRun::new(
        &seed(&[Panel::Polhode, Panel::Diagnostics]),
        Method::Rk4 { dt: 1e-3 },
    )
    .unwrap();
    assert!(shown.has_reference());
    let polhode = shown.polhode().unwrap().clone();
    assert_eq!(polhode.separatrix.len(), 2);
    play(&mut shown, |f| {
        let p = f.polhode.unwrap();
        assert!((p.norm() - 1.0).abs() < 1e-6);
    });
    let d = shown.diagnostics().unwrap();
    let err = d.error.unwrap();
    assert!(err > 0.0 && err < 1e-3, "rk4 dt=1e-3 error {err}");
    // The exact run needs no second run to compare with.
    let exact = SceneRun::new(&seed(&[Panel::Diagnostics]), Method::Exact).unwrap();
    assert!(!exact.has_reference());
    assert_eq!(exact.diagnostics().unwrap().error, None);
}

#[test]
fn trace_has_the_requested_points_whatever_the_frame_rate() {
    let s = seed(&[Panel::Omega]);
    let mut fast = SceneRun::with_trace_len(&s, Method::Exact, 300).unwrap();
    play(&mut fast, |_| {});
    let mut slow = SceneRun::with_trace_len(&s, Method::Exact, 300).unwrap();
    slow.advance_to(3.3);
    slow.advance_to(100.0);
    assert_eq!(fast.trace().len(), 300);
    assert_eq!(fast.trace(), slow.trace());
    assert_eq!(fast.trace().last().unwrap().t, 8.0);
    assert_eq!(fast.measurements(), slow.measurements());
}

#[test]
fn live_measurements_match_the_headless_ones() {
    let s = seed(&[Panel::Omega, Panel::Body, Panel::Polhode]);
    let mut run = SceneRun::new(&s, Method::Exact).unwrap();
    play(&mut run, |_| {});
    let live = run.measurements();
    let headless = measure_scene(&s, Method::Exact).unwrap();
    assert_eq!(live.get(Measure::Flips), Some(3.0));
    assert_eq!(live.readings().len(), headless.readings().len());
    for (a, b) in live.readings().iter().zip(headless.readings()) {
        assert_eq!(a.measure, b.measure);
        assert_eq!(a.formula, b.formula);
        let scale = a.value.abs().max(1.0);
        assert!((a.value - b.value).abs() <= 1e-9 * scale, "{a:?} vs {b:?}");
    }
}

#[test]
fn budget_stops_the_run_with_a_reason() {
    let s = scene([1.0, 2.0, 3.0], [0.01, 10.0, 0.01], 1e4, &[Panel::Omega]);
    let run = SceneRun::new(&s, Method::Rk4 { dt: 1e-3 }).unwrap();
    let err = run.error().expect("refused up front").to_string();
    assert!(err.contains("rk4"), "{err}");
    assert!(measure_scene(&s, Method::Rk4 { dt: 1e-3 }).is_err());
}

#[test]
fn earlier_times_are_ignored() {
    let mut run = SceneRun::new(&seed(&[Panel::Omega]), Method::Exact).unwrap();
    let at_two = *run.advance_to(2.0);
    let again = *run.advance_to(1.0);
    assert_eq!(at_two, again);
    assert_eq!(run.advance_to(f64::NAN).t, 2.0);
}

#[test]
fn needle_scenes_refuse_what_would_be_garbage() {
    // A needle 1e-9 thin: the splitting would carry its thin axis's ω as a
    // rounding error divided by 1e-9, so the scene refuses it up front; the
    // methods that carry ω play it and agree with the closed form.
    let s = scene([1e-9, 1.0, 1.0], [1.0, 1.0, 0.5], 10.0, &[Panel::Omega]);
    for method in [
        Method::Splitting { dt: 1e-3 },
        Method::Splitting4 { dt: 1e-3 },
    ] {
        let err = SceneRun::new(&s, method).err().expect("refused");
        assert!(err.to_string().contains("use the exact method"), "{err}");
        assert!(measure_scene(&s, method).is_err());
    }
    let exact = measure_scene(&s, Method::Exact).unwrap();
    for method in [Method::Adaptive { tol: 1e-10 }, Method::Rk4 { dt: 1e-3 }] {
        let m = measure_scene(&s, method).unwrap();
        let (a, b) = (
            m.get(Measure::OmegaChange).unwrap(),
            exact.get(Measure::OmegaChange).unwrap(),
        );
        assert!((a - b).abs() < 1e-6, "{method:?}: {a} vs {b}");
    }
    // A moderately thin needle runs, but a step too coarse for it stops
    // with the reason instead of measuring a state the body cannot have.
    let s = scene([1e-6, 1.0, 1.0], [1.0, 1.0, 0.5], 10.0, &[Panel::Omega]);
    let mut run = SceneRun::new(&s, Method::Splitting { dt: 0.1 }).unwrap();
    play(&mut run, |f| {
        assert!(
            (f.omega[0] - 1.0).abs() < 0.5,
            "ω₁ = {} at {}",
            f.omega[0],
            f.t
        )
    });
    let err = run.error().expect("stopped").to_string();
    assert!(
        err.contains("left the motion") && err.contains("smaller dt"),
        "{err}"
    );
}

/// A slice whose deadline has passed: each call does one unit of work.
fn spent() -> Slice {
    Slice::until(std::time::Instant::now())
}

#[test]
fn a_spent_slice_stops_at_the_next_grid_point_and_changes_nothing() {
    let s = seed(&[
        Panel::Omega,
        Panel::Body,
        Panel::Polhode,
        Panel::Diagnostics,
    ]);
    for method in [Method::Exact, Method::Rk4 { dt: 1e-3 }] {
        let mut whole = SceneRun::new(&s, method).unwrap();
        whole.advance_to(s.duration);
        let mut sliced = SceneRun::new(&s, method).unwrap();
        // One call with its slice spent: one grid point, not the end.
        assert!(!sliced.advance_within(s.duration, spent()));
        let first = sliced.frame().t;
        assert!(first > 0.0 && first < 0.01, "{method:?}: {first}");
        assert!(!sliced.finished());
        let mut calls = 1;
        while !sliced.advance_within(s.duration, spent()) {
            calls += 1;
        }
        assert!(calls > 1000, "{method:?}: {calls}");
        assert!(sliced.finished());
        // The same run, frame for frame.
        assert_eq!(sliced.measurements(), whole.measurements(), "{method:?}");
        assert_eq!(sliced.trace(), whole.trace(), "{method:?}");
        assert_eq!(sliced.frame(), whole.frame(), "{method:?}");
    }
}
