//! Large systems through the binary: the 200-variable Brusselator
//! (tests/fixtures/brusselator, written with its reference by make.py)
//! runs under Radau IIA, whose LU factors are banded for it, and lands on
//! SciPy's solution at rtol 1e-10.

use std::path::Path;

use crate::support::Flipcard;

#[test]
fn brusselator_of_200_variables_runs_under_radau_and_matches_the_reference() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/brusselator");
    let reference: Vec<(String, f64)> = std::fs::read_to_string(root.join("reference.csv"))
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| {
            let (name, value) = l.split_once(',').unwrap();
            (name.to_string(), value.parse().unwrap())
        })
        .collect();
    assert_eq!(reference.len(), 200);
    let deck = root.join("decks/bruss.toml");
    let out = Flipcard::without_data()
        .args(["sim", "--deck", deck.to_str().unwrap(), "--scene", "bruss"])
        .args(["--method", "radau", "--tol", "1e-6", "--samples", "2"])
        .args(["--format", "json"])
        .run();
    assert_eq!(out.status.code(), Some(0), "{}", out.stderr());
    let v: serde_json::Value = serde_json::from_str(&out.stdout()).unwrap();
    let last = &v["samples"][1];
    assert_eq!(last["t"].as_f64(), Some(10.0), "{last}");
    let worst = reference
        .iter()
        .map(|(name, want)| (last[name].as_f64().expect(name) - want).abs())
        .fold(0.0, f64::max);
    // The state is of size 1–4; at --tol 1e-6 the error is about 4e-7.
    assert!(worst < 1e-5, "largest error {worst:e}");
    let lu = v["stats"]["lu_decompositions"].as_f64().unwrap();
    assert!(lu > 10.0 && lu < 200.0, "{}", v["stats"]);
}
