//! `flipcard sim --scene ID` through the real binary.

use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_flipcard");

fn sim(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(BIN)
        .arg("sim")
        .args(args)
        .env_remove("FLIPCARD_DECKS")
        .output()
        .expect("run flipcard");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
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
