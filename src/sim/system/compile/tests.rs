use super::*;
use crate::sim::scene::spec::{Mark, SystemPanel};

pub(crate) fn pendulum() -> SystemScene {
    SystemScene {
        id: "p".into(),
        title: None,
        variables: vec!["theta".into(), "omega".into()],
        initial: vec![2.9670597283903604, 0.0],
        params: vec![("g".into(), 9.81), ("L".into(), 1.0)],
        equations: vec!["omega".into(), "-g/L*sin(theta)".into()],
        observables: vec![
            (
                "energy".into(),
                "0.5*L^2*omega^2 + g*L*(1 - cos(theta))".into(),
            ),
            ("x".into(), "L*sin(theta)".into()),
            ("y".into(), "-L*cos(theta)".into()),
            ("r".into(), "sqrt(x^2 + y^2)".into()),
        ],
        conserved: vec!["energy".into()],
        duration: 20.0,
        show: vec![SystemPanel::Plot],
        plot: vec!["theta".into()],
        phase: None,
        sketch: vec![Mark::Line(["0".into(), "0".into(), "x".into(), "y".into()])],
        time_unit: "s".into(),
    }
}

fn one(equation: &str, observables: &[(&str, &str)]) -> SystemScene {
    SystemScene {
        variables: vec!["x".into(), "v".into()],
        initial: vec![1.0, 0.0],
        params: vec![("k".into(), 2.0)],
        equations: vec!["v".into(), equation.into()],
        observables: observables
            .iter()
            .map(|(n, e)| (n.to_string(), e.to_string()))
            .collect(),
        conserved: vec![],
        sketch: vec![],
        ..pendulum()
    }
}

#[test]
fn evaluates_what_was_written() {
    let s = System::compile(&pendulum(), true).unwrap();
    let y = [0.7, -1.3];
    let mut dy = [0.0; 2];
    s.rhs(0.0, &y, &mut dy);
    assert_eq!(dy[0], -1.3);
    assert!((dy[1] + 9.81 * 0.7f64.sin()).abs() < 1e-14);
    let e = 0.5 * 1.3f64.powi(2) + 9.81 * (1.0 - 0.7f64.cos());
    assert!((s.observable(0, 0.0, &y) - e).abs() < 1e-13);
    // An observable built on earlier ones.
    assert!((s.observable(3, 0.0, &y) - 1.0).abs() < 1e-15);
    let mut all = [0.0; 4];
    s.observables_into(0.0, &y, &mut all);
    assert_eq!(all[3], s.observable(3, 0.0, &y));
    assert!((s.mark(2, 0.0, &y) - 0.7f64.sin()).abs() < 1e-15);
    assert_eq!(s.mark(0, 0.0, &y), 0.0);
}

#[test]
fn exact_jacobian_matches_differences() {
    let mut scene = pendulum();
    scene.equations[1] = "-g/L*sin(theta) - 0.1*abs(omega)*omega + t^2".into();
    let s = System::compile(&scene, true).unwrap();
    let y = [0.4, 0.9];
    let mut j = DMatrix::zeros(2, 2);
    s.jacobian(1.5, &y, &mut j);
    let mut fd = DMatrix::zeros(2, 2);
    crate::sim::solvers::ode::finite_difference_jacobian(&s, 1.5, &y, &mut fd);
    assert!((&j - &fd).abs().max() < 1e-8, "{j} vs {fd}");
    assert_eq!(j[(0, 1)], 1.0);
    // d/dω of −0.1|ω|ω is −0.2|ω|, exactly.
    assert_eq!(j[(1, 1)], -0.2 * 0.9);
    let s = System::compile(&pendulum(), true).unwrap();
    s.jacobian(0.0, &y, &mut j);
    assert!((j[(1, 0)] + 9.81 * 0.4f64.cos()).abs() < 1e-14);
    assert_eq!(j[(1, 1)], 0.0);
}

#[test]
fn every_function_is_differentiated_exactly() {
    let bodies = [
        "sin(x*v)",
        "cos(x - v)",
        "tan(0.3*x)",
        "asin(0.5*x)",
        "acos(0.4*v)",
        "atan(x*v)",
        "sinh(x)",
        "cosh(v)",
        "tanh(x + v)",
        "exp(-x*v)",
        "ln(x + 2)",
        "log10(v + 3)",
        "sqrt(x^2 + 1)",
        "abs(x - 2*v)",
        "sign(v) + x",
        "atan2(v, x)",
        "min(x, v^2)",
        "max(x, v^2)",
        "x^v",
        "2^x / v",
        "(x + v)^3",
        "-x/(1 + v^2)",
        "e^(x*t) + pi*t",
    ];
    for body in bodies {
        let s = System::compile(&one(body, &[]), true).unwrap();
        for y in [[0.7, 0.6], [1.3, -0.45], [0.2, 0.9]] {
            let mut j = DMatrix::zeros(2, 2);
            s.jacobian(0.3, &y, &mut j);
            let mut fd = DMatrix::zeros(2, 2);
            finite_difference_jacobian_of(&s, 0.3, &y, &mut fd);
            let scale = fd.abs().max().max(1.0);
            assert!(
                (&j - &fd).abs().max() < 1e-7 * scale,
                "{body} at {y:?}: {j} vs {fd}"
            );
        }
    }
}

fn finite_difference_jacobian_of(s: &System, t: f64, y: &[f64], j: &mut DMatrix<f64>) {
    crate::sim::solvers::ode::finite_difference_jacobian(s, t, y, j);
}

#[test]
fn mathematics_conventions_hold() {
    let mut scene = pendulum();
    scene.observables = vec![
        ("a".into(), "-theta^2".into()),
        ("b".into(), "2^3^2".into()),
        ("c".into(), "1e-3*theta + 2.5E+1".into()),
        (
            "d".into(),
            "atan2(1, -1) + min(theta, 0) + max(theta, 0) + sign(-3)".into(),
        ),
        ("f".into(), "pi + e + log10(100) + ln(e)".into()),
    ];
    scene.sketch.clear();
    let s = System::compile(&scene, false).unwrap();
    let y = [3.0, 0.0];
    assert_eq!(s.observable(0, 0.0, &y), -9.0);
    assert_eq!(s.observable(1, 0.0, &y), 512.0);
    assert!((s.observable(2, 0.0, &y) - 25.003).abs() < 1e-12);
    let d = (1.0f64).atan2(-1.0) + 0.0 + 3.0 - 1.0;
    assert!((s.observable(3, 0.0, &y) - d).abs() < 1e-14);
    let f = std::f64::consts::PI + std::f64::consts::E + 3.0;
    assert!((s.observable(4, 0.0, &y) - f).abs() < 1e-14);
}

/// `o0 = x`, `o1 = o0 + o0`, …, `o{k} = o{k-1} + o{k-1}`.
fn doublings(k: usize) -> Vec<(String, String)> {
    let mut obs = vec![("o0".to_string(), "x".to_string())];
    for i in 1..=k {
        obs.push((format!("o{i}"), format!("o{} + o{}", i - 1, i - 1)));
    }
    obs
}

#[test]
fn observables_built_on_each_other_are_compiled_once_each() {
    // Inlined, o60 would be 2^60 additions; shared, one each.
    let mut scene = one("-x + 1e-18*o60", &[]);
    scene.observables = doublings(60);
    let s = System::compile(&scene, true).unwrap();
    let cost = s.cost();
    assert!(cost.rhs < 100, "{cost:?}");
    assert!(cost.observables < 100, "{cost:?}");
    let y = [1.5, 0.25];
    // o_k = 2^k x, by hand: o60 = 2^60 · 1.5.
    assert_eq!(s.observable(60, 0.0, &y), 1.5 * 2f64.powi(60));
    assert_eq!(s.observable(3, 0.0, &y), 12.0);
    let mut dy = [0.0; 2];
    s.rhs(0.0, &y, &mut dy);
    assert_eq!(dy[1], -1.5 + 1e-18 * 1.5 * 2f64.powi(60));
    // The derivative through the chain: d/dx (−x + 1e-18·2^60·x).
    let mut j = DMatrix::zeros(2, 2);
    s.jacobian(0.0, &y, &mut j);
    assert_eq!(j[(1, 0)], -1.0 + 1e-18 * 2f64.powi(60));
    assert_eq!(j[(1, 1)], 0.0);
}

/// A balanced sum of 2^levels `x`s: deep only `levels`.
fn balanced(levels: usize) -> String {
    if levels == 0 {
        "x".to_string()
    } else {
        let half = balanced(levels - 1);
        format!("({half})+({half})")
    }
}

#[test]
fn a_program_too_long_names_its_expression() {
    // Each observable is within the parser's limits (8191 nodes, 12 deep,
    // 4096 operations compiled: one x, 4095 additions); the equation,
    // through the chain, exceeds MAX_PROGRAM at the 13th.
    let term = balanced(12);
    let mut obs = vec![("a0".to_string(), term.clone())];
    for i in 1..16 {
        obs.push((format!("a{i}"), format!("a{} + {term}", i - 1)));
    }
    let mut scene = one("a15", &[]);
    scene.observables = obs;
    let Err(e) = System::compile(&scene, false) else {
        panic!("compiled");
    };
    assert_eq!(e.source, Some(Source::Observable(12)), "{}", e.message);
    assert_eq!(
        e.message,
        "`a12` compiles to more than 50000 operations (with the observables it uses)"
    );
}

#[test]
fn a_value_that_is_not_finite_names_its_first_cause() {
    let scene = one(
        "-k*x",
        &[
            ("lnx", "ln(x)"),
            ("root", "sqrt(x - 1)"),
            ("inv", "1/(x - 2)"),
            ("big", "exp(1000*x)"),
            ("arc", "asin(x)"),
            ("pw", "(x - 3)^0.5"),
            ("uses", "2*root"),
        ],
    );
    let s = System::compile(&scene, false).unwrap();
    // The first observable (in order) that is not finite.
    let cause = |x: f64| {
        s.observable_fault(0.0, &[x, 0.0])
            .map(|f| (f.source, f.cause))
    };
    assert_eq!(
        cause(5.0).unwrap(),
        (Source::Observable(3), Cause::Overflow("exp"))
    );
    let arc = System::compile(&one("-x", &[("arc", "asin(x)")]), false).unwrap();
    assert_eq!(
        arc.observable_fault(0.0, &[5.0, 0.0]).unwrap().cause,
        Cause::OutsideUnitRange("asin", 5.0)
    );
    assert_eq!(
        cause(-0.5).unwrap(),
        (Source::Observable(0), Cause::LogOfNegative("ln", -0.5))
    );
    assert_eq!(cause(0.0).unwrap().1, Cause::LogOfZero("ln"));
    let f = s.observable_fault(0.0, &[0.5, 0.0]).unwrap();
    assert_eq!(f.cause, Cause::SqrtOfNegative(-0.5));
    assert_eq!(
        f.describe(&scene, 1.5),
        "`root` is NaN at t = 1.5: square root of a negative number (sqrt(-0.5))"
    );
    let inv = System::compile(&one("-k*x", &[("inv", "1/(x - 2)")]), false).unwrap();
    let f = inv.observable_fault(2.0, &[2.0, 0.0]).unwrap();
    assert_eq!(f.cause, Cause::DivisionByZero);
    assert!(f.value.is_infinite());
    assert_eq!(
        f.describe(&one("-k*x", &[("inv", "1/(x - 2)")]), 2.0),
        "`inv` is infinite at t = 2.0: division by zero"
    );
    let big = System::compile(&one("-k*x", &[("big", "exp(1000*x)")]), false).unwrap();
    let f = big.observable_fault(0.0, &[1.0, 0.0]).unwrap();
    assert_eq!(f.cause, Cause::Overflow("exp"));
    assert!(!f.cause.is_domain());
    // Through an observable an equation uses: the equation is named, and
    // where the operation was written.
    let eq = one("-x + root", &[("root", "sqrt(x)")]);
    let s = System::compile(&eq, true).unwrap();
    let f = s.rhs_fault(0.0, &[-4.0, 0.0]).unwrap();
    assert_eq!(
        f.describe(&eq, 0.25),
        "the equation of `v` is NaN at t = 0.25: square root of a negative number (sqrt(-4)) in `root`"
    );
    assert_eq!(s.rhs_fault(0.0, &[4.0, 0.0]), None);
    // A negative number to a fractional power; zero to a negative one.
    let p = one("-x", &[("a", "x^0.5"), ("b", "x^-1")]);
    let s = System::compile(&p, false).unwrap();
    assert_eq!(
        s.observable_fault(0.0, &[-2.0, 0.0]).unwrap().cause,
        Cause::NegativeToFractionalPower(-2.0, 0.5)
    );
    assert_eq!(
        s.observable_fault(0.0, &[0.0, 0.0]).unwrap().cause,
        Cause::ZeroToNegativePower(-1.0)
    );
}

#[test]
fn numbers_are_worked_out_once() {
    // g/L*2 is one constant; the program reads theta and runs sin, times.
    let s = System::compile(&one("-k/2*3*sin(x)", &[]), false).unwrap();
    assert_eq!(s.cost().rhs, 5, "{:?}", s.cost());
    let mut dy = [0.0; 2];
    s.rhs(0.0, &[0.5, 0.0], &mut dy);
    assert_eq!(dy[1], -2.0 / 2.0 * 3.0 * 0.5f64.sin());
    // A constant that is not finite stays an operation, so the run names it.
    let s = System::compile(&one("-x", &[("bad", "sqrt(-1)")]), false).unwrap();
    assert_eq!(
        s.observable_fault(0.0, &[0.5, 0.0]).unwrap().cause,
        Cause::SqrtOfNegative(-1.0)
    );
}
