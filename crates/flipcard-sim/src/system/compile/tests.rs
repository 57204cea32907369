use super::*;
use crate::scene::spec::{Mark, SystemPanel};

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
        atol: None,
        hamiltonian: None,
        labels: Vec::new(),
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
    crate::solvers::ode::finite_difference_jacobian(&s, 1.5, &y, &mut fd);
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
    crate::solvers::ode::finite_difference_jacobian(s, t, y, j);
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

use super::balanced_sum as balanced;

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
fn a_square_is_a_product() {
    // No power is computed for `x^2`: one product, exactly x·x, and its
    // derivative 2x in the Jacobian; `x^3` stays a power.
    let s = System::compile(&one("-x^2", &[]), true).unwrap();
    let pow = System::compile(&one("-x^3", &[]), true).unwrap();
    assert_eq!(
        s.cost().rhs + 1,
        pow.cost().rhs,
        "{:?} {:?}",
        s.cost(),
        pow.cost()
    );
    let mut dy = [0.0; 2];
    let mut j = DMatrix::zeros(2, 2);
    for x in [-3.7, -1e-160, 0.1, 1.0000000000000002, 7.3e150] {
        s.rhs(0.0, &[x, 0.0], &mut dy);
        assert_eq!(dy[1], -(x * x), "{x}");
        s.jacobian(0.0, &[x, 0.0], &mut j);
        assert_eq!(j[(1, 0)], -2.0 * x, "{x}");
    }
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

/// The value of `node` by walking the tree, as written: the reference the
/// tape must agree with bit for bit.
fn reference(node: &Node, env: &dyn Fn(&str) -> f64) -> f64 {
    match node {
        Node::Num(v) => *v,
        Node::Name(n, _) => match n.as_str() {
            "pi" => std::f64::consts::PI,
            "e" => std::f64::consts::E,
            _ => env(n),
        },
        Node::Neg(a) => -reference(a, env),
        // A square is a product (exact: `powf` may be off in the last bit).
        Node::Bin('^', a, b) if matches!(**b, Node::Num(e) if e == 2.0) => {
            let a = reference(a, env);
            a * a
        }
        Node::Bin(op, a, b) => {
            let (a, b) = (reference(a, env), reference(b, env));
            match op {
                '+' => a + b,
                '-' => a - b,
                '*' => a * b,
                '/' => a / b,
                _ => a.powf(b),
            }
        }
        Node::Call(f, args) => {
            let v: Vec<f64> = args.iter().map(|a| reference(a, env)).collect();
            let fun = Fun::of(f).unwrap();
            if v.len() == 2 {
                fun.apply2(v[0], v[1])
            } else {
                fun.apply1(v[0])
            }
        }
    }
}

mod props {
    use super::*;
    use proptest::prelude::*;

    /// Expressions over x, v, t, a parameter and numbers, every function.
    fn expression(depth: u32) -> impl Strategy<Value = String> {
        let leaf = prop_oneof![
            Just("x".to_string()),
            Just("v".to_string()),
            Just("t".to_string()),
            Just("k".to_string()),
            Just("pi".to_string()),
            (-5.0f64..5.0).prop_map(|c| format!("{c:e}")),
        ];
        leaf.prop_recursive(depth, 64, 2, |inner| {
            let funs = expr::FUNCTIONS;
            prop_oneof![
                (
                    inner.clone(),
                    inner.clone(),
                    prop::sample::select(vec!["+", "-", "*", "/", "^"])
                )
                    .prop_map(|(a, b, op)| format!("({a}){op}({b})")),
                inner.clone().prop_map(|a| format!("-({a})")),
                (inner.clone(), inner, prop::sample::select(funs.to_vec())).prop_map(
                    |(a, b, (f, n))| if n == 2 {
                        format!("{f}({a}, {b})")
                    } else {
                        format!("{f}({a})")
                    }
                ),
            ]
        })
    }

    fn same(a: f64, b: f64) -> bool {
        a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
    }

    proptest! {
        /// Any text: the parser returns (never panics, never recurses past
        /// its limit: it runs here on a 1 MB stack), and what it accepts is
        /// within the depth and size limits.
        #[test]
        fn any_text_parses_or_is_refused_within_bounds(
            tokens in prop::collection::vec(
                prop::sample::select(vec![
                    "(", ")", "x", "+", "-", "*", "/", "^", "sin(", "atan2(", ",",
                    "1e3", " ", "2", ".5", "y",
                ]),
                0..1500,
            )
        ) {
            let text: String = tokens.concat();
            let t = text.clone();
            let result = std::thread::Builder::new()
                .stack_size(1024 * 1024)
                .spawn(move || {
                    let parsed = expr::parse(&t);
                    let depth = parsed.as_ref().ok().map(depth_of);
                    (parsed.map(|_| ()), depth)
                })
                .unwrap()
                .join()
                .expect("the parser stays within a small stack");
            match result {
                (Ok(()), Some(d)) => prop_assert!(d <= expr::MAX_DEPTH, "{} deep", d),
                (Err(e), _) => prop_assert!(e.at <= text.len(), "{:?}", e),
                _ => {}
            }
        }

        /// One kind of nesting repeated any number of times, on a 1 MB
        /// stack (half a test thread's): accepted up to its limit, refused
        /// at the one too many beyond it.
        #[test]
        fn nesting_is_refused_at_the_level_too_many(
            kind in prop::sample::select(vec!["(", "sin(", "-", "x^"]),
            n in 0usize..3000,
        ) {
            let close = if kind.ends_with('(') { ")".repeat(n) } else { String::new() };
            let text = format!("{}x{close}", kind.repeat(n));
            let t = text.clone();
            let parsed = std::thread::Builder::new()
                .stack_size(1024 * 1024)
                .spawn(move || expr::parse(&t).map(|_| ()))
                .unwrap()
                .join()
                .expect("the parser stays within a small stack");
            // Parentheses and calls: MAX_NESTING open at once, the error at
            // the `(` one too many. Signs and powers: a tree MAX_DEPTH deep
            // (x itself is one level), the error at the sign or `^` one too
            // many, or at the outermost when the count is just one over.
            let (limit, at) = match kind {
                "(" | "sin(" => (expr::MAX_NESTING, expr::MAX_NESTING * kind.len() + kind.len() - 1),
                "-" => (expr::MAX_DEPTH - 1, if n == expr::MAX_DEPTH { 0 } else { expr::MAX_DEPTH }),
                _ => (expr::MAX_DEPTH - 1, if n == expr::MAX_DEPTH { 1 } else { 2 * expr::MAX_DEPTH + 1 }),
            };
            if n <= limit {
                prop_assert!(parsed.is_ok(), "{} × {}: {:?}", kind, n, parsed);
            } else {
                let e = parsed.unwrap_err();
                prop_assert_eq!(e.at, at, "{} × {}: {}", kind, n, e);
            }
        }

        /// The tape gives what the tree gives, bit for bit, and its
        /// Jacobian what central differences give where f is smooth.
        #[test]
        fn the_tape_evaluates_as_written(
            body in expression(6),
            x in -3.0f64..3.0,
            v in -3.0f64..3.0,
            t in 0.0f64..2.0,
        ) {
            let scene = one(&body, &[]);
            let s = System::compile(&scene, true).unwrap();
            let node = expr::parse(&body).unwrap();
            let env = |n: &str| match n {
                "x" => x,
                "v" => v,
                "t" => t,
                "k" => 2.0,
                _ => f64::NAN,
            };
            let want = reference(&node, &env);
            let mut dy = [0.0; 2];
            s.rhs(t, &[x, v], &mut dy);
            prop_assert!(same(dy[1], want), "{} = {} by the tape, {} by the tree", body, dy[1], want);
            prop_assert_eq!(dy[0], v);
            // Where nothing is singular nearby, the exact derivative is
            // what differences at two step sizes agree on.
            let at = |x: f64, v: f64| {
                let mut d = [0.0; 2];
                s.rhs(t, &[x, v], &mut d);
                d[1]
            };
            let mut j = DMatrix::zeros(2, 2);
            s.jacobian(t, &[x, v], &mut j);
            for (col, (dx, dv)) in [(1.0, 0.0), (0.0, 1.0)].into_iter().enumerate() {
                let diff = |h: f64| (at(x + h * dx, v + h * dv) - at(x - h * dx, v - h * dv)) / (2.0 * h);
                let (d1, d2) = (diff(1e-5), diff(1e-6));
                let scale = d1.abs().max(1.0);
                if d1.is_finite() && d2.is_finite() && (d1 - d2).abs() < 1e-6 * scale && want.abs() < 1e6 {
                    prop_assert!((j[(1, col)] - d1).abs() < 1e-4 * scale, "{}: d/d{} = {} exact, {} by differences", body, ["x", "v"][col], j[(1, col)], d1);
                }
            }
        }

        /// Observables built on any earlier ones compile to no more than
        /// the sum of their own sizes, and give the values of their
        /// expansion.
        #[test]
        fn observables_share_their_values(
            picks in prop::collection::vec((0usize..100, 0usize..100, prop::sample::select(vec!["+", "*", "-"])), 1..40),
            x in 0.5f64..1.5,
        ) {
            let mut obs: Vec<(String, String)> = vec![("o0".into(), "x".into())];
            for (i, (a, b, op)) in picks.iter().enumerate() {
                let k = i + 1;
                obs.push((format!("o{k}"), format!("o{}{op}o{}", a % k, b % k)));
            }
            let last = obs.len() - 1;
            let refs: Vec<(&str, &str)> = obs.iter().map(|(n, e)| (n.as_str(), e.as_str())).collect();
            let scene = one(&format!("-x + 0*o{last}"), &refs);
            let s = System::compile(&scene, true).unwrap();
            prop_assert!(s.cost().observables <= 1 + 2 * obs.len(), "{:?}", s.cost());
            prop_assert!(s.cost().rhs <= 6 + 2 * obs.len(), "{:?}", s.cost());
            // The expansion's value, each observable from the ones before.
            let mut values: Vec<f64> = Vec::new();
            for (_, e) in &obs {
                let node = expr::parse(e).unwrap();
                let v = reference(&node, &|n| {
                    if n == "x" { x } else { values[n[1..].parse::<usize>().unwrap()] }
                });
                values.push(v);
            }
            let mut got = vec![0.0; obs.len()];
            s.observables_into(0.0, &[x, 0.0], &mut got);
            for k in 0..obs.len() {
                prop_assert!(same(got[k], values[k]), "o{}: {} vs {}", k, got[k], values[k]);
            }
        }
    }

    fn depth_of(node: &Node) -> usize {
        match node {
            Node::Num(_) | Node::Name(..) => 1,
            Node::Neg(a) => 1 + depth_of(a),
            Node::Bin(_, a, b) => 1 + depth_of(a).max(depth_of(b)),
            Node::Call(_, args) => 1 + args.iter().map(depth_of).max().unwrap_or(0),
        }
    }
}

/// A chain of 30 variables, each rate reading its neighbours through
/// functions with their own rules (and one through an observable).
fn chain() -> SystemScene {
    let n = 30;
    let name = |i: usize| format!("y{i}");
    let equations = (0..n)
        .map(|i| {
            let left = if i > 0 { name(i - 1) } else { "1".into() };
            let right = if i + 1 < n { name(i + 1) } else { "2".into() };
            let me = name(i);
            if i == 7 {
                format!("-(-{me}) + w*sin({left}) - {right}^2")
            } else {
                format!("{me}^2*{left} - exp(-{right})/(2 + cos({me})) + abs({left} - {right})")
            }
        })
        .collect();
    SystemScene {
        variables: (0..n).map(name).collect(),
        initial: (0..n).map(|i| 0.1 * i as f64).collect(),
        equations,
        observables: vec![("w".into(), "y3*y4".into())],
        conserved: vec![],
        sketch: vec![],
        ..pendulum()
    }
}

/// The passes that run only the operations reading each variable give the
/// same Jacobian as the full passes, bit for bit (up to the sign of zero),
/// and the pattern is the variables each equation reads.
#[test]
fn sparse_jacobian_passes_equal_full_passes() {
    let s = System::compile(&chain(), true).unwrap();
    let deps = s.deps.as_ref().expect("small enough to list");
    let n = 30;
    let y: Vec<f64> = (0..n).map(|i| 0.3 + 0.05 * i as f64).collect();
    let (mut sparse, mut full) = (DMatrix::zeros(n, n), DMatrix::zeros(n, n));
    assert!(s.rhs.jacobian(0.4, &y, &mut sparse, Some(deps)));
    assert!(s.rhs.jacobian(0.4, &y, &mut full, None));
    for i in 0..n {
        for j in 0..n {
            assert_eq!(sparse[(i, j)], full[(i, j)], "({i}, {j})");
        }
    }
    let rows = s.sparsity().unwrap();
    let mut expect: Vec<Vec<usize>> = (0..n)
        .map(|i| (i.saturating_sub(1)..=(i + 1).min(n - 1)).collect())
        .collect();
    expect[7] = vec![3, 4, 6, 7, 8];
    assert_eq!(rows, expect);
    // The Jacobian's work is the pairs listed, far below n passes.
    assert!(s.cost().jacobian * 5 < s.rhs.len() * n, "{:?}", s.cost());
}
