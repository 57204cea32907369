//! Issue 23, section 1: `check` proves the prompts on system scenes as it
//! proves the rigid-body ones, through the real binary. The instructor's
//! mistakes are the fixture decks `tests/decks/invalid/system-*` (their
//! whole `check` output is asserted by `check_cli`); here the same decks
//! through `sim --scene` (exit 1 on a wrong answer), `decks add` (refused),
//! a copy of the bundled deck with one wrong number, and a prompt on a
//! scene that blows up.

use std::path::{Path, PathBuf};

use crate::support::{Flipcard, Output};

fn case(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/decks/invalid")
        .join(name)
}

fn case_deck(name: &str) -> PathBuf {
    case(name).join("decks").join(format!("{name}.toml"))
}

fn run(args: &[&str]) -> Output {
    Flipcard::without_data().args(args).run()
}

/// The error headlines of a `check` run (`path:line:col: error: …`), with
/// the path cut to its file name.
fn errors(stderr: &str) -> Vec<String> {
    stderr
        .lines()
        .filter(|l| l.contains(": error: "))
        .map(|l| {
            let start = l[..l.find(": error: ").unwrap()]
                .rfind('/')
                .map_or(0, |i| i + 1);
            l[start..].to_string()
        })
        .collect()
}

/// The issue's example: a copy of the bundled oscillations deck whose
/// pendulum-170 prompt expects 9.99 s. `check` refuses it at that number,
/// with what the run measures and the fix; the untouched copy passes.
#[test]
fn a_wrong_number_in_a_copy_of_the_bundled_deck_is_refused_at_its_line() {
    let bundled = Path::new(env!("CARGO_MANIFEST_DIR")).join("decks/oscillations.toml");
    let text = std::fs::read_to_string(&bundled).unwrap();
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("decks")).unwrap();
    let content = Path::new(env!("CARGO_MANIFEST_DIR")).join("content/oscillations");
    let copy = dir.path().join("content/oscillations");
    std::fs::create_dir_all(&copy).unwrap();
    for e in std::fs::read_dir(&content).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), copy.join(e.file_name())).unwrap();
    }
    let path = dir.path().join("decks/oscillations.toml");

    std::fs::write(&path, &text).unwrap();
    let o = run(&["check", path.to_str().unwrap()]);
    assert_eq!(o.code(), Some(0), "{}", o.stderr());

    assert_eq!(text.matches("expected = 4.894").count(), 1);
    let line = text
        .lines()
        .position(|l| l.starts_with("expected = 4.894"))
        .unwrap()
        + 1;
    std::fs::write(
        &path,
        text.replacen("expected = 4.894", "expected = 9.99", 1),
    )
    .unwrap();
    let o = run(&["check", path.to_str().unwrap()]);
    assert_eq!(o.code(), Some(1), "{}", o.stderr());
    let got = errors(&o.stderr());
    assert_eq!(
        got,
        [format!(
            "oscillations.toml:{line}:12: error: expected period(theta) = 9.99 s, but this 20 s run measures 4.894 s: change `expected` to about 4.894 or widen `tolerance`"
        )],
        "{}",
        o.stderr()
    );
    assert!(
        o.stderr().ends_with("1 error, 0 warnings\n"),
        "{}",
        o.stderr()
    );
}

/// `sim --scene` on a system scene says WRONG and exits 1 when the run
/// contradicts a prompt, as it does for a rigid scene; a right answer
/// exits 0.
#[test]
fn sim_scene_exits_1_on_a_wrong_answer_for_systems_and_rigid_bodies() {
    for (name, scene, line) in [
        (
            "system-answer-contradicts-run",
            "pendulum-170",
            "p1: expected period(theta) = 9.99 s: WRONG; measured 4.89",
        ),
        (
            "system-beat-period-wrong",
            "coupled",
            "p1: expected period(transfer) = 10.32 s: WRONG; measured 20.6",
        ),
        (
            "system-answer-depends-on-run-length",
            "resonance",
            "p1: expected bounded: WRONG; holds: bounded",
        ),
        (
            "answer-contradicts-run",
            "sc1",
            "p1: expected repeatedly: WRONG",
        ),
    ] {
        let deck = if name == "answer-contradicts-run" {
            case(name).join("decks/runs-short.toml")
        } else {
            case_deck(name)
        };
        let o = run(&["sim", "--deck", deck.to_str().unwrap(), "--scene", scene]);
        assert_eq!(o.code(), Some(1), "{name}: {}{}", o.stdout(), o.stderr());
        assert!(o.stdout().contains(line), "{name}: {}", o.stdout());
    }
    // The system fixture of the sim tests, whose answers are right.
    let good = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/systems/decks/oscillations-test.toml");
    let o = run(&[
        "sim",
        "--deck",
        good.to_str().unwrap(),
        "--scene",
        "pendulum-170",
    ]);
    assert_eq!(o.code(), Some(0), "{}{}", o.stdout(), o.stderr());
    assert!(!o.stdout().contains("WRONG"), "{}", o.stdout());
}

/// The measurement report says why a measure cannot be made, and the
/// prompt on it is wrong.
#[test]
fn sim_scene_says_why_a_period_cannot_be_measured() {
    let deck = case_deck("system-period-one-crossing");
    let o = run(&[
        "sim",
        "--deck",
        deck.to_str().unwrap(),
        "--scene",
        "pendulum-170",
    ]);
    assert_eq!(o.code(), Some(1), "{}{}", o.stdout(), o.stderr());
    let out = o.stdout();
    assert!(
        out.contains("period(theta)      - (period(theta): theta crosses the level halfway between its minimum and maximum upwards once over the run; a period needs two)"),
        "{out}"
    );
    assert!(
        out.contains("p1: expected period(theta) = 4.894 s: WRONG; measured - s"),
        "{out}"
    );
}

/// `decks add` refuses a deck whose answers `check` refuses, system or
/// rigid, showing the same diagnostics, and copies nothing.
#[test]
fn decks_add_refuses_a_deck_whose_answers_the_runs_contradict() {
    for name in [
        "system-answer-contradicts-run",
        "system-choices-overlap",
        "system-period-one-crossing",
        "answer-contradicts-run",
    ] {
        let dir = tempfile::tempdir().unwrap();
        let data = dir.path().join("data");
        let o = Flipcard::new(&data)
            .args(["decks", "add"])
            .arg(case(name))
            .run();
        assert_eq!(o.code(), Some(1), "{name}: {}{}", o.stdout(), o.stderr());
        let e = o.stderr();
        assert!(e.contains(": error: "), "{name}: {e}");
        assert!(
            e.contains("does not pass `check` (1 error); nothing added"),
            "{name}: {e}"
        );
        assert!(
            !data.join("decks").exists()
                || std::fs::read_dir(data.join("decks"))
                    .unwrap()
                    .next()
                    .is_none(),
            "{name}"
        );
    }
}

/// A prompt on a scene whose solution blows up mid-run cannot be checked:
/// the scene is refused where it is written and the prompt at its answer.
#[test]
fn a_prompt_on_a_scene_that_blows_up_is_refused_at_both_places() {
    let deck = r#"[deck]
id = "blows"
title = { en = 'Deck' }
languages = ["en"]

[[card]]
id = "c1"
front = { en = 'Front' }
back = { en = 'Back' }
prompt = "p1"

[[prompt]]
id = "p1"
question = { en = 'How high does x get?' }
scene = "blowup"

[prompt.answer]
kind = "number"
measure = "max(x)"
unit = "m"
expected = 10.0
tolerance = { rel = 0.1 }

[[scene]]
id = "blowup"
variables = ["x"]
initial = [1.0]
equations = ["x^2"]
duration = 2.0
show = ["plot"]
plot = ["x"]
"#;
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("decks")).unwrap();
    std::fs::create_dir_all(dir.path().join("content/blows")).unwrap();
    std::fs::write(dir.path().join("content/blows/en.toml"), "").unwrap();
    let path = dir.path().join("decks/blows.toml");
    std::fs::write(&path, deck).unwrap();
    let o = run(&["check", path.to_str().unwrap()]);
    assert_eq!(o.code(), Some(1), "{}", o.stderr());
    assert_eq!(
        errors(&o.stderr()),
        [
            "blows.toml:25:6: error: scene `blowup` does not run to its end: the solution blows up near t = 1.0",
            "blows.toml:21:12: error: the answer cannot be checked: scene `blowup` does not run to its end (the solution blows up near t = 1.0)",
        ],
        "{}",
        o.stderr()
    );
}
