//! `flipcard sim --scene ID` through the real binary.

use crate::support::Flipcard;

fn sim(args: &[&str]) -> (bool, String, String) {
    let out = Flipcard::without_data().arg("sim").args(args).run();
    (out.status.success(), out.stdout(), out.stderr())
}

#[test]
fn scene_prints_measurements_with_formulas_and_prompt_verdicts() {
    let (ok, out, err) = sim(&["--scene", "flip-period"]);
    assert!(ok, "{err}");
    assert!(
        out.starts_with("scene flip-period (torque-free-rotation)"),
        "{out}"
    );
    let line = |name: &str| {
        out.lines()
            .find(|l| l.trim_start().starts_with(name))
            .unwrap_or_else(|| panic!("no {name} in\n{out}"))
            .to_string()
    };
    let flips: Vec<String> = line("flips ")
        .split_whitespace()
        .map(String::from)
        .collect();
    assert_eq!(flips[1], "4");
    let period = line("flip_period");
    let words: Vec<&str> = period.split_whitespace().collect();
    let measured: f64 = words[1].parse().unwrap();
    let formula: f64 = words.last().unwrap().parse().unwrap();
    assert!((measured - 2.753).abs() < 2e-3, "{period}");
    assert!((measured - formula).abs() < 1e-4, "{period}");
    assert!(period.contains("2K(m)/λ"), "{period}");
    assert!(
        out.contains("flip-period: expected flip_period = 2.753 s: ok"),
        "{out}"
    );
}

#[test]
fn scene_with_a_stepping_method_and_a_deck_path() {
    let deck = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/decks/torque-free-rotation.toml"
    );
    let (ok, out, err) = sim(&[
        "--scene",
        "middle-axis-spin",
        "--deck",
        deck,
        "--method",
        "rk4",
        "--dt",
        "0.001",
    ]);
    assert!(ok, "{err}");
    assert!(out.contains("method rk4"), "{out}");
    assert!(out.contains("middle-axis: expected flips: ok"), "{out}");
}

#[test]
fn unknown_scene_and_bad_settings_fail_with_a_reason() {
    let (ok, _, err) = sim(&["--scene", "nope"]);
    assert!(!ok);
    assert!(err.contains("no scene \"nope\""), "{err}");
    assert!(err.contains("middle-axis-spin"), "{err}");
    let (ok, _, err) = sim(&["--scene", "efold", "--method", "exact", "--tol", "1e-8"]);
    assert!(!ok);
    assert!(
        err.contains("tol applies only to the adaptive method"),
        "{err}"
    );
    let (ok, _, err) = sim(&["--scene", "efold", "--deck", "/no/such/deck"]);
    assert!(!ok);
    assert!(err.contains("no such file"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn extreme_scene_values_are_reported_with_exponents() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("content/tiny")).unwrap();
    std::fs::create_dir(dir.path().join("decks")).unwrap();
    std::fs::write(dir.path().join("content/tiny/en.toml"), "").unwrap();
    let deck = dir.path().join("decks/tiny.toml");
    std::fs::write(
        &deck,
        "[deck]\nid = \"tiny\"\ntitle = 'Tiny'\nlanguages = [\"en\"]\n\n\
         [[scene]]\nid = \"speck\"\ninertia = [1e-300, 2e-300, 3e-300]\n\
         omega = [1e150, 1e150, 5e149]\nduration = 5e-324\nshow = [\"omega\"]\n",
    )
    .unwrap();
    let (ok, out, err) = sim(&["--scene", "speck", "--deck", deck.to_str().unwrap()]);
    assert!(ok, "{err}");
    assert!(
        out.starts_with(
            "scene speck (tiny): I = (1e-300, 2e-300, 3e-300), ω₀ = (1e150, 1e150, 5e149), 5e-324 s"
        ),
        "{out}"
    );
    let longest = out
        .split(|c: char| !c.is_ascii_digit())
        .map(str::len)
        .max()
        .unwrap_or(0);
    assert!(longest < 30, "a {longest}-digit run in\n{out}");
    let (ok, list, err) = sim(&[
        "--list",
        "--decks",
        dir.path().join("decks").to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(
        list.contains("inertia=1e-300,2e-300,3e-300\tomega=1e150,1e150,5e149\tduration=5e-324 s"),
        "{list}"
    );
}

/// A scene whose prompt expects what the run does not show exits 1 and
/// says why under the prompt; the bundled scenes, all right, exit 0.
#[test]
fn a_wrong_expected_answer_fails_the_scene() {
    let deck = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/decks/invalid/answer-contradicts-run/decks"
    );
    let (ok, out, _) = sim(&["--scene", "sc1", "--deck", deck]);
    assert!(!ok, "{out}");
    assert!(out.contains("p1: expected repeatedly: WRONG"), "{out}");
    assert!(
        out.contains("make the run longer than two flip periods"),
        "{out}"
    );
    let (ok, out, err) = sim(&["--scene", "middle-axis-spin"]);
    assert!(ok, "{out}{err}");
    assert!(out.contains("middle-axis: expected flips: ok"), "{out}");
}

/// Each known slip is worked out on the run and printed beside the
/// measurement (1/k and √k from the e-folding time the run measures: τ² and
/// 1/τ, since τ = 1/√k); a slip the run makes a right answer fails the scene
/// as `check` fails the deck.
#[test]
fn scene_prints_each_slip_and_refuses_one_the_run_makes_right() {
    let (ok, out, err) = sim(&["--scene", "efold"]);
    assert!(ok, "{err}");
    let line = out
        .lines()
        .find(|l| l.contains("efold-time: expected"))
        .unwrap_or_else(|| panic!("{out}"));
    let after = |key: &str| -> f64 {
        let rest = line
            .split(key)
            .nth(1)
            .unwrap_or_else(|| panic!("{key}: {line}"));
        rest.split_whitespace().next().unwrap().parse().unwrap()
    };
    let tau = after("measured ");
    let inverse_k = after("1/k = ");
    let root_k = after("sqrt(k) = ");
    assert!((inverse_k - tau * tau).abs() < 2e-3 * inverse_k, "{line}");
    assert!((root_k - 1.0 / tau).abs() < 2e-3 * root_k, "{line}");

    let deck = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/decks/invalid/slip-right-in-the-run/decks/slip-run.toml"
    );
    let (ok, out, _) = sim(&["--scene", "sc1", "--deck", deck]);
    assert!(!ok, "{out}");
    assert!(
        out.contains("p1: expected efold_time = 0.165 s: WRONG"),
        "{out}"
    );
    assert!(
        out.contains(
            "slip `0.19` gives 0.1900 s, within the tolerance of what this 2 s run measures"
        ),
        "{out}"
    );
}
