//! `flipcard grade`: a formula answer graded through the real binary
//! against the bundled torque-free deck's formula card and prompt: right
//! in any spelling (exit 0), each common slip named (exit 1), a usage or
//! deck error exit 2, and a hostile answer (control characters, deep
//! nesting, a huge string) answered on one escaped line, never a panic.

use crate::support::Flipcard;

const DECK: &str = "torque-free-rotation";
const CARD: &str = "euler-omega1-dot-formula";
const PROMPT: &str = "middle-axis-growth-formula";

fn grade(item: &str, id: &str, answer: &str) -> crate::support::Output {
    Flipcard::without_data()
        .args(["grade", "--deck", DECK, item, id, answer])
        .run()
}

#[test]
fn a_right_formula_in_any_spelling_exits_0() {
    for answer in [
        "(I2-I3)*w2*w3/I1",
        "(I_2 - I_3) omega_2 omega_3 / I_1",
        "-(I3 - I2) w3 w2 I1^-1",
    ] {
        let out = grade("--card", CARD, answer).ok();
        assert_eq!(out.stdout(), "right\n", "{answer}");
    }
    let out = grade("--prompt", PROMPT, "(I3-I2)(I2-I1)Omega^2/(I1 I3)").ok();
    assert_eq!(out.stdout(), "right\n");
}

#[test]
fn each_slip_is_named_and_exits_1() {
    for (answer, said) in [
        ("(I3-I2)*w2*w3/I1", "wrong: the sign is wrong"),
        ("2(I2-I3)*w2*w3/I1", "yours is 2 times the answer"),
        ("(I2-I3)*w2*w3/(4 I1)", "yours is 0.25 times the answer"),
        (
            "I1/((I2-I3)*w2*w3)",
            "upside down: yours is 1 over the answer",
        ),
        ("(I2-I3)*w2/I1", "it leaves out `omega3`"),
        (
            "(I2-I3)*w2*w3/I1 + q",
            "`q`: not a variable of this problem",
        ),
        ("(I2+I3)*w2*w3/I1", "it differs from the answer"),
    ] {
        let out = grade("--card", CARD, answer).fails();
        let text = out.stdout();
        assert!(text.contains(said), "{answer}: {text}");
        assert!(
            text.contains("expected: (I_2 - I_3) omega_2 omega_3 / I_1"),
            "{text}"
        );
    }
    let out = grade("--prompt", PROMPT, "(I2-I3)(I2-I1)Omega^2/(I1 I3)").fails();
    assert!(
        out.stdout().contains("the sign is wrong"),
        "{}",
        out.stdout()
    );
}

#[test]
fn usage_and_deck_errors_exit_2() {
    let code = |out: crate::support::Output| (out.code(), out.stderr());
    let (c, e) = code(
        Flipcard::without_data()
            .args(["grade", "--deck", "nope", "--card", CARD, "x"])
            .run(),
    );
    assert_eq!(c, Some(2), "{e}");
    assert!(e.contains("no deck `nope`"), "{e}");
    let (c, e) = code(grade("--prompt", "middle-axis", "x"));
    assert_eq!(c, Some(2), "{e}");
    assert!(e.contains("does not take a formula"), "{e}");
    let (c, e) = code(grade("--card", "transport-theorem", "x"));
    assert_eq!(c, Some(2), "{e}");
    assert!(e.contains("not a formula card"), "{e}");
    let (c, e) = code(grade("--card", "no-such-card", "x"));
    assert_eq!(c, Some(2), "{e}");
    // Neither --card nor --prompt: clap's usage error.
    let (c, _) = code(
        Flipcard::without_data()
            .args(["grade", "--deck", DECK, "x"])
            .run(),
    );
    assert_eq!(c, Some(2));
}

#[test]
fn a_hostile_answer_gets_one_escaped_line() {
    let deep = format!("{}w2{}", "(".repeat(5000), ")".repeat(5000));
    for answer in [
        "w2\u{1b}[31m\u{7}*w3\r\n".to_string(),
        deep,
        "w2+".repeat(10_000),
        "\u{202e}I1".to_string(),
    ] {
        let out = grade("--card", CARD, &answer).fails();
        let text = out.stdout();
        assert!(text.starts_with("wrong"), "{text}");
        assert!(
            !text.chars().any(|c| c.is_control() && c != '\n'),
            "unescaped control character: {text:?}"
        );
        assert_eq!(text.lines().count(), 2, "{text:?}");
        assert!(out.stderr().is_empty(), "{}", out.stderr());
    }
}
