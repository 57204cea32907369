//! The comparison of formula answers: right answers in every spelling,
//! each slip named, keys checked, and (by proptest) any string graded
//! without a panic, equivalence reflexive and symmetric. Run the
//! properties longer with `PROPTEST_CASES=5000 cargo test --lib equiv::`.

use super::*;
use proptest::prelude::*;

fn euler() -> Key {
    let d = |name: &str, lo: f64, hi: f64| Domain {
        name: name.to_string(),
        lo,
        hi,
    };
    Key {
        expected: "(I_2 - I_3) omega_2 omega_3 / I_1".to_string(),
        vars: vec![
            d("I1", 1.0, 3.0),
            d("I2", 1.0, 3.0),
            d("I3", 1.0, 3.0),
            d("omega2", -2.0, 2.0),
            d("omega3", -2.0, 2.0),
        ],
    }
}

#[test]
fn every_spelling_of_the_right_formula_is_right() {
    let key = euler();
    for answer in [
        "(I2-I3)*w2*w3/I1",
        "(I_2 - I_3) omega_2 omega_3 / I_1",
        "omega2 omega3 (I2 - I3)/I1",
        "-(I3-I2)*omega2*omega3*I1^-1",
        "(I2 w2 w3 - I3 w2 w3)/I1",
        "2(I2-I3)w2 w3/(2I1)",
        // As a keyboard with math symbols types it: Greek letters,
        // subscript digits, × · and the Unicode minus.
        "(I₂ − I₃)·ω₂×ω₃/I₁",
        "(I_2 − I_3) ω_2 ω_3 / I_1",
    ] {
        assert_eq!(grade(&key, answer), Verdict::Right, "{answer}");
    }
    // A slip typed in Greek is named in the key's names.
    assert_eq!(
        grade(&key, "(I₂ − I₃)ω₂/I₁"),
        Verdict::Wrong(Some(Slip::Missing(vec!["omega3".to_string()])))
    );
    // Where a typed answer fails to read is counted in characters, Greek
    // or not: `?` is the 10th.
    let Verdict::Unreadable(e) = grade(&key, "(I₂ − I₃)?ω₂ω₃") else {
        panic!()
    };
    assert_eq!((e.at, e.len), (9, 1), "{e:?}");
    assert!(e.to_string().contains("at character 10"), "{e}");
    // A deck's equations stay ASCII: the Greek letter is refused there.
    assert!(crate::system::expr::parse("ω + 1").is_err());
}

#[test]
fn each_slip_is_named() {
    let key = euler();
    let slip = |a: &str| match grade(&key, a) {
        Verdict::Wrong(s) => s,
        other => panic!("{a}: {other:?}"),
    };
    assert_eq!(slip("(I3-I2)*w2*w3/I1"), Some(Slip::Sign));
    assert_eq!(slip("2(I2-I3)*w2*w3/I1"), Some(Slip::Factor(2.0)));
    match slip("(I2-I3)*w2*w3/(2 I1)") {
        Some(Slip::Factor(c)) => assert!((c - 0.5).abs() < 1e-12, "{c}"),
        other => panic!("{other:?}"),
    }
    assert_eq!(slip("I1/((I2-I3)*w2*w3)"), Some(Slip::Reciprocal));
    assert_eq!(
        slip("(I2-I3)*w2/I1"),
        Some(Slip::Missing(vec!["omega3".to_string()]))
    );
    assert_eq!(
        slip("(I2-I3)*w2*w3/I1 + x"),
        Some(Slip::Extra(vec!["x".to_string()]))
    );
    assert_eq!(slip("sqrt(-I1) + I2 w2 w3 I3"), Some(Slip::Undefined));
    assert_eq!(slip("(I2+I3)*w2*w3/I1"), None);
}

#[test]
fn an_answer_that_does_not_read_says_where() {
    let key = euler();
    let Verdict::Unreadable(e) = grade(&key, "(I2-I3)*w2*") else {
        panic!()
    };
    assert_eq!(e.at, 11);
    let long = "w2+".repeat(400) + "w2";
    assert!(matches!(grade(&key, &long), Verdict::Unreadable(_)));
    let deep = "(".repeat(5000) + "w2" + &")".repeat(5000);
    assert!(matches!(
        grade(&key, &deep[..MAX_ANSWER]),
        Verdict::Unreadable(_)
    ));
}

#[test]
fn a_key_is_checked_against_its_domain() {
    let mut key = euler();
    assert_eq!(check(&key), vec![]);
    key.vars[0].lo = 4.0;
    key.vars.push(Domain {
        name: "omega1".into(),
        lo: 0.0,
        hi: 1.0,
    });
    key.vars.push(Domain {
        name: "I_2".into(),
        lo: 0.0,
        hi: 1.0,
    });
    assert_eq!(
        check(&key),
        vec![
            KeyProblem::Range(0),
            KeyProblem::Twice(6),
            KeyProblem::Unused(5)
        ]
    );
    let key = Key {
        expected: "sqrt(x - 5) + y".into(),
        vars: vec![
            Domain {
                name: "x".into(),
                lo: 0.0,
                hi: 5.0,
            },
            Domain {
                name: "y".into(),
                lo: 0.0,
                hi: 1.0,
            },
        ],
    };
    assert_eq!(
        check(&key),
        vec![KeyProblem::Undefined {
            found: 0,
            drawn: MAX_DRAWS
        }]
    );
    let key = Key {
        expected: "x + z".into(),
        vars: vec![Domain {
            name: "x".into(),
            lo: 0.0,
            hi: 5.0,
        }],
    };
    let problems = check(&key);
    let [KeyProblem::Expected(e)] = problems.as_slice() else {
        panic!("{problems:?}")
    };
    assert_eq!((e.at, e.unknown.as_deref()), (4, Some("z")));
}

#[test]
fn time_may_be_a_variable() {
    let key = Key {
        expected: "A cos(omega t)".into(),
        vars: ["A", "omega", "t"]
            .iter()
            .map(|n| Domain {
                name: n.to_string(),
                lo: 0.5,
                hi: 2.0,
            })
            .collect(),
    };
    assert_eq!(check(&key), vec![]);
    assert_eq!(grade(&key, "A*cos(w*t)"), Verdict::Right);
    assert_eq!(
        grade(&key, "A*cos(w)"),
        Verdict::Wrong(Some(Slip::Missing(vec!["t".into()])))
    );
}

/// A formula over x, y, z from a small grammar that stays finite on
/// [1, 2]³ (no division by something that may vanish, no roots of
/// negatives).
fn formula() -> impl Strategy<Value = String> {
    let leaf = prop_oneof![
        Just("x".to_string()),
        Just("y".to_string()),
        Just("z".to_string()),
        (1u8..5).prop_map(|n| n.to_string()),
    ];
    leaf.prop_recursive(4, 24, 2, |inner| {
        prop_oneof![
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("({a} + {b})")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("({a} - {b})")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("({a})({b})")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("({a})/(x^2 + ({b})^2)")),
            inner.clone().prop_map(|a| format!("sin({a})")),
            inner.clone().prop_map(|a| format!("-{a}")),
        ]
    })
}

fn xyz() -> Vec<Domain> {
    ["x", "y", "z"]
        .iter()
        .map(|n| Domain {
            name: n.to_string(),
            lo: 1.0,
            hi: 2.0,
        })
        .collect()
}

proptest! {
    #[test]
    fn any_string_is_graded_without_a_panic(answer in "\\PC{0,80}|[-+*/^() a-zI_0-9.,]{0,200}") {
        let _ = grade(&euler(), &answer);
    }

    #[test]
    fn equivalence_is_reflexive_and_symmetric(a in formula(), b in formula()) {
        let vars = xyz();
        prop_assert_eq!(equivalent(&a, &a, &vars), Some(true));
        let ab = equivalent(&a, &b, &vars);
        let ba = equivalent(&b, &a, &vars);
        prop_assert_eq!(ab, ba, "{} vs {}", a, b);
        // An equal formula written otherwise is equal.
        let c = format!("({a}) + 0 (y)");
        prop_assert_eq!(equivalent(&a, &c, &vars), Some(true));
    }
}

/// The deck's answer as the reader shows math: Greek names as letters,
/// trailing digits as subscripts, powers raised, parentheses only where
/// the order needs them.
#[test]
fn a_formula_is_shown_as_math() {
    let shown = |f: &str| flipcard_text::render(&format!("${}$", latex(f).unwrap()));
    for (f, want) in [
        (
            "(I_3 - I_2)(I_2 - I_1) Omega^2 / (I_1 I_3)",
            "(I₃ − I₂)(I₂ − I₁)Ω²/(I₁I₃)",
        ),
        ("(I2-I3)*w2*w3/I1", "(I₂ − I₃)w₂w₃/I₁"),
        ("-(a - b)^2 + 2*3 + sqrt(x)", "−(a − b)² + 2 ⋅ 3 + √x"),
        ("a - (b - c)", "a − (b − c)"),
        ("a / (b c)", "a/(bc)"),
        ("omega_2 t + sin(theta)", "ω₂t + sin(θ)"),
    ] {
        assert_eq!(shown(f), want, "{f}");
    }
    assert!(latex("(a").is_none());
}
