use super::*;
use crate::rigid::elliptic::complete_k;
use crate::scene::spec::Mark;
use crate::system::Name;

fn pendulum(theta0_deg: f64, show: &[SystemPanel]) -> SystemScene {
    SystemScene {
        id: "pendulum".into(),
        title: None,
        variables: vec!["theta".into(), "omega".into()],
        initial: vec![theta0_deg.to_radians(), 0.0],
        params: vec![("g".into(), 9.81), ("L".into(), 1.0)],
        equations: vec!["omega".into(), "-g/L*sin(theta)".into()],
        observables: vec![
            (
                "energy".into(),
                "0.5*L^2*omega^2 + g*L*(1 - cos(theta))".into(),
            ),
            ("x".into(), "L*sin(theta)".into()),
            ("y".into(), "-L*cos(theta)".into()),
        ],
        conserved: vec!["energy".into()],
        duration: 20.0,
        show: show.to_vec(),
        plot: vec!["theta".into()],
        phase: Some(["theta".into(), "omega".into()]),
        sketch: vec![
            Mark::Line(["0".into(), "0".into(), "x".into(), "y".into()]),
            Mark::Trail(["x".into(), "y".into()]),
        ],
        time_unit: "s".into(),
        atol: None,
        hamiltonian: None,
        labels: Vec::new(),
    }
}

fn of(stat: Stat, name: &str) -> Measure {
    Measure::Of(stat, Name::new(name).unwrap())
}

fn auto() -> OdeMethod {
    OdeMethod::default_for(OdeKind::Auto, 1.0)
}

/// T = 4K(m)√(L/g), m = sin²(θ₀/2).
fn exact_period(theta0_deg: f64) -> f64 {
    let m = (theta0_deg.to_radians() / 2.0).sin().powi(2);
    4.0 * complete_k(1.0 - m) * (1.0 / 9.81f64).sqrt()
}

#[test]
fn pendulum_period_matches_the_elliptic_integral() {
    let t0 = 2.0 * std::f64::consts::PI * (1.0 / 9.81f64).sqrt();
    for (deg, ratio) in [(30.0, 1.0174), (90.0, 1.1803), (170.0, 2.4394)] {
        let scene = pendulum(deg, &[SystemPanel::Plot]);
        for kind in [
            OdeKind::Auto,
            OdeKind::Adaptive,
            OdeKind::Radau,
            OdeKind::Rk4,
        ] {
            let method = OdeMethod::default_for(kind, scene.duration);
            let got = measure_system(&scene, method, &[of(Stat::Period, "theta")]).unwrap();
            let period = got[0].clone().unwrap();
            let exact = exact_period(deg);
            assert!(
                (period - exact).abs() < 1e-4 * exact,
                "{deg}° {kind:?}: {period} vs {exact}"
            );
            assert!(
                (period / t0 - ratio).abs() < 1e-4,
                "{deg}°: T/T0 = {}",
                period / t0
            );
        }
    }
}

#[test]
fn measures_follow_their_definitions() {
    let scene = pendulum(90.0, &[SystemPanel::Plot]);
    let ms = [
        of(Stat::Max, "theta"),
        of(Stat::Min, "theta"),
        of(Stat::Final, "omega"),
        of(Stat::Mean, "theta"),
        of(Stat::Crossings, "theta"),
        of(Stat::Drift, "energy"),
        of(Stat::Max, "y"),
    ];
    let got: Vec<f64> = measure_system(&scene, auto(), &ms)
        .unwrap()
        .into_iter()
        .map(Result::unwrap)
        .collect();
    let amp = 90f64.to_radians();
    assert!((got[0] - amp).abs() < 1e-6, "max {}", got[0]);
    // The far turning point is found among the samples (16 a step).
    assert!((got[1] + amp).abs() < 1e-4, "min {}", got[1]);
    // θ swings symmetrically: its time average is near zero (an unfinished
    // swing at the end leaves a little).
    assert!(got[3].abs() < 0.1, "mean {}", got[3]);
    // Two sign changes per period over 20 s.
    let expected = (2.0 * 20.0 / exact_period(90.0) + 0.5).floor();
    assert!(
        (got[4] - expected).abs() <= 1.0,
        "crossings {} vs {expected}",
        got[4]
    );
    assert!(got[5] < 1e-6, "energy drift {}", got[5]);
    // y = −cos θ is largest at the turning points: −cos 90° = 0.
    assert!(got[6].abs() < 1e-4);
    // The exact final ω (from sn, cn) is not needed: it is the last sample.
    let mut run = SystemRun::new(&scene, auto(), &ms).unwrap();
    run.run_to_end().unwrap();
    assert_eq!(run.measure(ms[2]).unwrap(), run.state()[1]);
}

#[test]
fn period_is_refused_without_two_upward_crossings() {
    let mut scene = pendulum(90.0, &[SystemPanel::Plot]);
    scene.duration = 0.3;
    let got = measure_system(&scene, auto(), &[of(Stat::Period, "theta")]).unwrap();
    let reason = got[0].clone().unwrap_err().to_string();
    assert!(reason.contains("a period needs two"), "{reason}");
}

#[test]
fn blow_up_is_reported_near_its_time() {
    let scene = SystemScene {
        id: "b".into(),
        title: None,
        variables: vec!["x".into()],
        initial: vec![1.0],
        params: vec![],
        equations: vec!["x^2".into()],
        observables: vec![],
        conserved: vec![],
        duration: 2.0,
        show: vec![SystemPanel::Plot],
        plot: vec!["x".into()],
        phase: None,
        sketch: vec![],
        time_unit: "s".into(),
        atol: None,
        hamiltonian: None,
        labels: Vec::new(),
    };
    for kind in OdeKind::ALL {
        let e = measure_system(
            &scene,
            OdeMethod::default_for(kind, 2.0),
            &[of(Stat::Max, "x")],
        )
        .unwrap_err();
        assert_eq!(
            e.to_string(),
            "the solution blows up near t = 1.0",
            "{kind:?}"
        );
    }
}

#[test]
fn computes_only_what_is_shown_or_measured() {
    let radau = OdeMethod::default_for(OdeKind::Radau, 1.0);
    let adaptive = OdeMethod::default_for(OdeKind::Adaptive, 1.0);
    // Plot θ only: no observable, no sketch, no reference, no Jacobian.
    let s = pendulum(30.0, &[SystemPanel::Plot]);
    let p = SystemPlan::for_scene(&s, adaptive, &[]);
    assert_eq!(p.observables, vec![false, false, false]);
    assert!(!p.sketch && !p.reference && !p.jacobian);
    assert!(p.metered.is_empty());
    // An implicit method compiles the Jacobian.
    assert!(SystemPlan::for_scene(&s, radau, &[]).jacobian);
    assert!(SystemPlan::for_scene(&s, auto(), &[]).jacobian);
    // A measure of an observable evaluates that one only.
    let p = SystemPlan::for_scene(&s, adaptive, &[of(Stat::Max, "y")]);
    assert_eq!(p.observables, vec![false, false, true]);
    assert_eq!(p.metered, vec![4]);
    // Diagnostics: the conserved energy and a reference run.
    let s = pendulum(30.0, &[SystemPanel::Diagnostics]);
    let p = SystemPlan::for_scene(&s, adaptive, &[]);
    assert_eq!(p.observables, vec![true, false, false]);
    assert!(p.reference && !p.sketch);
    // The sketch evaluates its own expressions, not the observables' list.
    let s = pendulum(30.0, &[SystemPanel::Sketch]);
    let p = SystemPlan::for_scene(&s, adaptive, &[]);
    assert!(p.sketch && !p.reference);
    assert_eq!(p.observables, vec![false, false, false]);

    // And the run does what the plan says.
    let s = pendulum(30.0, &[SystemPanel::Plot]);
    let mut run = SystemRun::new(&s, adaptive, &[]).unwrap();
    run.advance_to(5.0);
    assert!(!run.has_reference());
    assert!(run.trail().is_empty());
    assert_eq!(run.trace().last().unwrap().values.len(), 1);
    assert_eq!(run.work().jac_evals, 0);
    let s = pendulum(
        30.0,
        &[
            SystemPanel::Plot,
            SystemPanel::Sketch,
            SystemPanel::Diagnostics,
        ],
    );
    let mut run = SystemRun::new(&s, adaptive, &[]).unwrap();
    run.advance_to(5.0);
    assert!(run.has_reference());
    assert_eq!(run.trail().last().unwrap().values.len(), 6);
    let d = run.diagnostics();
    assert_eq!(d.drift.len(), 1);
    assert!(d.error.unwrap() < 1e-6, "{d:?}");
}

fn van_der_pol(mu: f64) -> SystemScene {
    SystemScene {
        id: "vdp".into(),
        title: None,
        variables: vec!["x".into(), "v".into()],
        initial: vec![2.0, 0.0],
        params: vec![("mu".into(), mu)],
        equations: vec!["v".into(), "mu*(1 - x^2)*v - x".into()],
        observables: vec![],
        conserved: vec![],
        duration: 3000.0,
        show: vec![SystemPanel::Plot, SystemPanel::Diagnostics],
        plot: vec!["x".into()],
        phase: None,
        sketch: vec![],
        time_unit: "s".into(),
        atol: None,
        hamiltonian: None,
        labels: Vec::new(),
    }
}

#[test]
fn van_der_pol_switches_to_radau_and_keeps_its_shape() {
    let scene = van_der_pol(1000.0);
    let ms = [of(Stat::Max, "x"), of(Stat::Period, "x")];
    let method = OdeMethod::default_for(OdeKind::Auto, scene.duration);
    let mut run = SystemRun::new(&scene, method, &ms).unwrap();
    run.run_to_end().unwrap();
    let d = run.diagnostics();
    assert_eq!(d.solver, "radau5");
    assert!(d.stiff_at.is_some_and(|t| t < 10.0), "{d:?}");
    let amp = run.measure(ms[0]).unwrap();
    assert!((amp - 2.0).abs() < 0.02, "amplitude {amp}");
    // (3 − 2 ln 2)μ ≈ 1614 to leading order.
    let period = run.measure(ms[1]).unwrap_err().to_string();
    assert!(period.contains("period(x)"), "{period}");
    // Over 3000 s there is one full cycle and a bit: x crosses its mid
    // level upwards once, so the period is refused; over 4000 s, measured.
    let mut long = scene.clone();
    long.duration = 4000.0;
    let got = measure_system(&long, method, &ms[1..]).unwrap();
    let p = got[0].clone().unwrap();
    assert!((p - 1614.0).abs() < 0.02 * 1614.0, "period {p}");
    // adaptive refuses the stiff problem with the reason.
    let e = measure_system(
        &scene,
        OdeMethod::default_for(OdeKind::Adaptive, scene.duration),
        &ms,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("stiff") && e.contains("radau"), "{e}");
}

/// A slice whose deadline has passed: each call takes one step.
fn spent() -> Slice {
    Slice::until(std::time::Instant::now())
}

#[test]
fn a_spent_slice_takes_one_step_and_changes_nothing() {
    let s = pendulum(
        170.0,
        &[SystemPanel::Plot, SystemPanel::Phase, SystemPanel::Sketch],
    );
    let ms = [of(Stat::Period, "theta"), of(Stat::Max, "energy")];
    for kind in OdeKind::ALL {
        let method = OdeMethod::default_for(kind, s.duration);
        let mut whole = SystemRun::new(&s, method, &ms).unwrap();
        whole.run_to_end().unwrap();
        let mut sliced = SystemRun::new(&s, method, &ms).unwrap();
        assert!(!sliced.advance_within(s.duration, spent()), "{kind:?}");
        assert_eq!(sliced.work().steps, 1, "{kind:?}");
        let t = sliced.t();
        assert!(
            t > 0.0 && t < s.duration && !sliced.finished(),
            "{kind:?}: {t}"
        );
        let mut calls = 1;
        while !sliced.advance_within(s.duration, spent()) {
            calls += 1;
            assert_eq!(sliced.work().steps, calls, "{kind:?}: one step a call");
        }
        assert!(sliced.finished() && sliced.error().is_none(), "{kind:?}");
        // The same samples, so the same measures and curves.
        assert_eq!(
            sliced.measurements(&ms),
            whole.measurements(&ms),
            "{kind:?}"
        );
        assert_eq!(sliced.trace(), whole.trace(), "{kind:?}");
        assert_eq!(sliced.trail(), whole.trail(), "{kind:?}");
        assert_eq!(sliced.state(), whole.state(), "{kind:?}");
    }
}

#[test]
fn samples_stop_at_the_frame_and_faults_wait_for_the_run_to_get_there() {
    // x = cos t, lnx = ln x: NaN from t = π/2 on. A step may reach past
    // the frame; what lies beyond it is not computed yet.
    let scene = SystemScene {
        id: "lnx".into(),
        title: None,
        variables: vec!["x".into(), "v".into()],
        initial: vec![1.0, 0.0],
        params: vec![],
        equations: vec!["v".into(), "-x".into()],
        observables: vec![("lnx".into(), "ln(x)".into())],
        conserved: vec![],
        duration: 10.0,
        show: vec![SystemPanel::Plot],
        plot: vec!["lnx".into()],
        phase: None,
        sketch: vec![],
        time_unit: "s".into(),
        atol: None,
        hamiltonian: None,
        labels: Vec::new(),
    };
    let method = OdeMethod::default_for(OdeKind::Adaptive, scene.duration);
    let mut run = SystemRun::new(&scene, method, &[]).unwrap();
    run.advance_to(1.5);
    assert!(run.error().is_none());
    assert!(run.trace().iter().all(|p| p.t <= 1.5));
    run.advance_to(2.0);
    let e = run.error().expect("lnx leaves its domain at π/2");
    assert_eq!(
        e.to_string().split(" (ln(").next().unwrap(),
        "`lnx` is NaN at t = 1.571: ln of a negative number"
    );
    assert!(matches!(
        e,
        RunError::Domain {
            at: Some(crate::system::compile::Source::Observable(0)),
            ..
        }
    ));
    // The frame stays at the last good sample, before π/2.
    assert!(
        run.t() < std::f64::consts::FRAC_PI_2 && run.t() > 1.5,
        "{}",
        run.t()
    );
    assert!(run.finished());
}

/// A pendulum released at 179.9°: a loose tolerance tips it over the top,
/// so the run never swings back and shows no period. The measure says the
/// run is too coarse, at which tolerance the period shows, and its value
/// there (near the elliptic integral's); the default tolerance measures it.
#[test]
fn a_period_a_coarse_run_misses_is_named_with_the_tolerance_that_shows_it() {
    let mut scene = pendulum(179.9, &[SystemPanel::Plot]);
    scene.duration = 40.0;
    let exact = exact_period(179.9);
    let period = [of(Stat::Period, "theta")];
    // From the loosest setting too: it takes a run a million times finer.
    for (setting, label) in [(1e-3, "auto rtol 0.001"), (1e-2, "auto rtol 0.01")] {
        let coarse = OdeMethod::with_setting(OdeKind::Auto, setting).unwrap();
        let got = measure_system(&scene, coarse, &period).unwrap();
        match &got[0] {
            Err(ReadingError::TooCoarse {
                measure,
                method,
                finer,
                value,
                ..
            }) => {
                assert_eq!(measure, "period(theta)");
                assert_eq!(method, label);
                assert!(finer.starts_with("auto rtol 1e-"), "{finer}");
                assert!((value / exact - 1.0).abs() < 0.02, "{value} vs {exact}");
            }
            other => panic!("{label}: {other:?}"),
        }
    }
    let coarse = OdeMethod::with_setting(OdeKind::Auto, 1e-3).unwrap();
    let got = measure_system(&scene, coarse, &period).unwrap();
    let text = got[0].clone().unwrap_err().to_string();
    assert!(text.contains("too coarse"), "{text}");
    let fine = measure_system(&scene, auto(), &period).unwrap();
    let value = fine[0].clone().unwrap();
    assert!((value / exact - 1.0).abs() < 1e-3, "{value} vs {exact}");
}

/// A variable whose samples all sat below its absolute tolerance has a
/// typical size of 0: the cure named is a tolerance ten thousand times
/// tighter than the one it has, never the one that already failed (E5
/// with atol 1e-20 on y2 was told to set atol y2 = 1e-20).
#[test]
fn an_uncontrolled_variable_of_size_zero_is_told_a_tighter_tolerance() {
    let e = RunError::Inaccurate {
        t: 4.07e12,
        h: 0.0084,
        uncontrolled: vec![("y2".into(), 0.0, 1e-20)],
        rtol: 1e-6,
        radau: true,
        grew: None,
        at_floor: vec![],
    };
    let text = e.to_string();
    assert!(text.contains("`atol = { y2 = 1e-24 }`"), "{text}");
    assert!(text.contains("--atol y2=1e-24"), "{text}");
    let sized = RunError::Inaccurate {
        t: 1.0,
        h: 1e-12,
        uncontrolled: vec![("y2".into(), 3.5e-11, 1e-5)],
        rtol: 1e-3,
        radau: true,
        grew: None,
        at_floor: vec![],
    };
    assert!(sized.to_string().contains("y2 = 1e-17"), "{sized}");
    assert!(!sized.to_string().contains("no tolerance cures"), "{sized}");
    // Below the default's floor the message says the value may be rounding
    // and names the cure that is not a tolerance.
    let floor = RunError::Inaccurate {
        t: 1.0,
        h: 1e-12,
        uncontrolled: vec![("y3".into(), 3.5e-21, 1.8e-19)],
        rtol: 1e-3,
        radau: true,
        grew: None,
        at_floor: vec!["y3".into()],
    };
    let text = floor.to_string();
    assert!(
        text.contains("; `y3` fell below 1e-16 of the largest size")
            && text.contains("held against it"),
        "{text}"
    );
}

/// Kepler's e-orbit (a = 1 AU, GM = 4π²: period 1 yr) started at aphelion
/// (−(1 + e), 0), so perihelion (a(1 − e), 0) comes at t = ½, 1½, …
fn kepler_from_aphelion(e: f64, periods: f64) -> SystemScene {
    let gm = 4.0 * std::f64::consts::PI.powi(2);
    let va = (gm * (1.0 - e) / (1.0 + e)).sqrt();
    SystemScene {
        id: "kepler".into(),
        title: None,
        variables: vec!["x".into(), "y".into(), "vx".into(), "vy".into()],
        initial: vec![-(1.0 + e), 0.0, 0.0, -va],
        params: vec![("GM".into(), gm)],
        equations: vec![
            "vx".into(),
            "vy".into(),
            "-GM*x/r^3".into(),
            "-GM*y/r^3".into(),
        ],
        observables: vec![("r".into(), "sqrt(x^2 + y^2)".into())],
        conserved: vec![],
        duration: periods,
        show: vec![SystemPanel::Plot, SystemPanel::Sketch],
        plot: vec!["r".into(), "x".into()],
        phase: None,
        sketch: vec![
            Mark::Trail(["x".into(), "y".into()]),
            Mark::Dot(["0".into(), "0".into()], None),
            Mark::Dot(["x".into(), "y".into()], None),
        ],
        time_unit: "yr".into(),
        atol: None,
        hamiltonian: None,
        labels: Vec::new(),
    }
}

/// RK4 at 8448 steps a period over 40 periods: 337,920 samples, of which
/// the drawn record keeps every 256th, and perihelion (sample 4224 of each
/// period) falls halfway between two kept ones, 0.015 yr from each, where
/// the planet is back at r = 0.26 AU (x = −0.08): what the panels were
/// scaled to. The extents the run reports are the continuous solution's.
#[test]
fn the_extent_of_a_run_includes_the_perihelion_its_samples_skip() {
    let e = 0.9;
    let scene = kepler_from_aphelion(e, 40.0);
    let method = OdeMethod::with_setting(OdeKind::Rk4, 1.0 / 8448.0).unwrap();
    let mut run = SystemRun::new(&scene, method, &[]).unwrap();
    run.run_to_end().unwrap();
    let (rp, ra) = (1.0 - e, 1.0 + e);
    // What the panels were scaled to: the record of r and x (the sketch's
    // trail kept the same samples).
    let sampled_r = (run.trace().iter()).fold(f64::INFINITY, |m, p| m.min(p.values[0]));
    let sampled_x = (run.trace().iter()).fold(f64::NEG_INFINITY, |m, p| m.max(p.values[1]));
    assert!(sampled_r > 0.26, "the record reaches r = {sampled_r}");
    assert!(sampled_x < -0.07, "the record reaches x = {sampled_x}");
    let [(x0, x1), (y0, y1)] = run.sketch_extent().expect("the sketch's extent");
    assert!((x1 - rp).abs() < 1e-5, "x reaches {x1}, perihelion is {rp}");
    assert!(
        (x0 + ra).abs() < 1e-5,
        "x reaches {x0}, aphelion is {}",
        -ra
    );
    let b = (1.0 - e * e).sqrt();
    assert!(
        (y1 - b).abs() < 1e-5 && (y0 + b).abs() < 1e-5,
        "y {y0}..{y1}, b = {b}"
    );
    let (r0, r1) = run.extent(4).expect("r's extent");
    assert_eq!(run.plot_extent(), Some((x0, r1)), "r and x together");
    assert!((r0 - rp).abs() < 1e-5, "r reaches {r0}, perihelion is {rp}");
    assert!((r1 - ra).abs() < 1e-5, "r reaches {r1}, aphelion is {ra}");
    // The trail passes within its resolution of perihelion on every orbit
    // (the chord between the samples either side passed 0.18 AU away).
    let span = 2.0 * ra;
    let near = |t: f64| {
        (run.trail().windows(2))
            .filter(|w| (w[0].t - t).abs() < 0.1)
            .map(|w| {
                let at = |p: &Point| (p.values[0], p.values[1]);
                trail::to_segment((rp, 0.0), at(&w[0]), at(&w[1]))
            })
            .fold(f64::INFINITY, f64::min)
    };
    for k in 0..40 {
        let d = near(k as f64 + 0.5);
        assert!(
            d < span / trail::RESOLUTION,
            "orbit {k}: the trail passes {d} from perihelion"
        );
    }
    assert!(
        run.trail().len() <= trail::TRAIL_LEN,
        "{}",
        run.trail().len()
    );
}

/// The extents and the trail are computed only for the panels shown, and
/// never for a run nobody draws.
#[test]
fn extents_and_trails_follow_the_shown_panels() {
    let mut scene = kepler_from_aphelion(0.5, 1.0);
    let method = OdeMethod::with_setting(OdeKind::Rk4, 1e-3).unwrap();
    let r = 4; // the observable r, after the four variables
    scene.show = vec![SystemPanel::Plot];
    let plan = SystemPlan::for_scene(&scene, method, &[]);
    assert_eq!((plan.extents.clone(), plan.trail), (vec![r, 0], false));
    let mut run = SystemRun::new(&scene, method, &[]).unwrap();
    run.run_to_end().unwrap();
    assert!(run.plot_extent().is_some() && run.sketch_extent().is_none());
    assert!(run.trail().is_empty());
    // A plotted quantity is not a measure the run was asked for.
    assert_eq!(
        run.measure(of(Stat::Max, "r")),
        Err(ReadingError::NotPlanned(of(Stat::Max, "r")))
    );
    scene.show = vec![SystemPanel::Sketch];
    let plan = SystemPlan::for_scene(&scene, method, &[]);
    // The six coordinates of the trail and the two dots.
    assert_eq!(
        (plan.extents.clone(), plan.trail),
        ((5..11).collect(), true)
    );
    let headless = plan.headless();
    assert!(headless.extents.is_empty() && !headless.trail && !headless.sketch);
    let mut run = SystemRun::new(&scene, method, &[]).unwrap();
    run.run_to_end().unwrap();
    assert!(run.plot_extent().is_none() && run.sketch_extent().is_some());
    assert!(!run.trail().is_empty());
}

/// What the panels cost on the run of
/// `the_extent_of_a_run_includes_the_perihelion_its_samples_skip` (Kepler
/// e = 0.9, RK4 at 8448 steps a period, 40 periods, plot and sketch
/// shown) against the same run headless: dense-output evaluations between
/// samples and wall time. `FLIPCARD_COST_MODE=shown` or `headless` runs
/// only that one (for `perf stat -e instructions` on the test process).
#[test]
#[ignore = "a measurement: cargo test --release -p flipcard-sim --lib panels_cost -- --ignored --nocapture"]
fn panels_cost_measured() {
    let scene = kepler_from_aphelion(0.9, 40.0);
    let method = OdeMethod::with_setting(OdeKind::Rk4, 1.0 / 8448.0).unwrap();
    let mode = std::env::var("FLIPCARD_COST_MODE").unwrap_or_default();
    for (name, headless) in [("shown", false), ("headless", true)] {
        if !mode.is_empty() && mode != name {
            continue;
        }
        let plan = SystemPlan::for_scene(&scene, method, &[]);
        let plan = if headless { plan.headless() } else { plan };
        let start = std::time::Instant::now();
        let mut run = SystemRun::with_plan(&scene, method, plan).unwrap();
        run.run_to_end().unwrap();
        let secs = start.elapsed().as_secs_f64();
        let p = run.probes();
        println!(
            "{name}: {:.3} s, {} searches, {} trail evaluations, {} trail points",
            secs,
            p.searches,
            p.trail,
            run.trail().len()
        );
    }
}
