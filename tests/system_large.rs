//! Large systems through the binary: the 200-variable Brusselator
//! (tests/fixtures/brusselator, written with its reference by make.py)
//! runs under Radau IIA, whose LU factors are banded for it, and the
//! Brusselator on a 15×15 grid (tests/fixtures/brusselator2d, 450
//! variables, no narrow band) under sparse LU factors; each lands on
//! SciPy's solution at rtol 1e-10.

use std::path::Path;

use crate::support::Flipcard;

/// The fixture's reference state at its end, by variable.
fn reference(root: &Path) -> Vec<(String, f64)> {
    std::fs::read_to_string(root.join("reference.csv"))
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| {
            let (name, value) = l.split_once(',').unwrap();
            (name.to_string(), value.parse().unwrap())
        })
        .collect()
}

#[test]
fn brusselator_of_200_variables_runs_under_radau_and_matches_the_reference() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/brusselator");
    let reference = reference(&root);
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
    assert_eq!(v["stats"]["lu"], "banded", "{}", v["stats"]);
}

/// The grid's Jacobian is sparse but no ordering bands it narrowly: the
/// run says it factored sparse, in the JSON and on the `--stats` line,
/// and lands on the reference as closely as the dense factors would (the
/// simulator's own test, `sparse_lu`, runs both forms on this system).
#[test]
fn brusselator_on_a_grid_runs_with_sparse_lu_and_matches_the_reference() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/brusselator2d");
    let reference = reference(&root);
    assert_eq!(reference.len(), 450);
    let deck = root.join("decks/bruss2d.toml");
    let sim = |format: &str| {
        Flipcard::without_data()
            .args([
                "sim",
                "--deck",
                deck.to_str().unwrap(),
                "--scene",
                "bruss2d",
            ])
            .args(["--method", "radau", "--tol", "1e-6", "--samples", "2"])
            .args(["--format", format, "--stats"])
            .run()
    };
    let out = sim("json");
    assert_eq!(out.status.code(), Some(0), "{}", out.stderr());
    let v: serde_json::Value = serde_json::from_str(&out.stdout()).unwrap();
    let last = &v["samples"][1];
    assert_eq!(last["t"].as_f64(), Some(10.0), "{last}");
    let worst = reference
        .iter()
        .map(|(name, want)| (last[name].as_f64().expect(name) - want).abs())
        .fold(0.0, f64::max);
    // The state is of size 0.7–3.1; at --tol 1e-6 the error is about 1e-6.
    assert!(worst < 1e-5, "largest error {worst:e}");
    assert_eq!(v["stats"]["lu"], "sparse", "{}", v["stats"]);
    let csv = sim("csv");
    assert_eq!(csv.status.code(), Some(0), "{}", csv.stderr());
    assert!(
        csv.stderr().contains(" LU decompositions (sparse)"),
        "{}",
        csv.stderr()
    );
}

/// A method that factors nothing says so: `lu` is null.
#[test]
fn an_explicit_run_names_no_lu() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/brusselator");
    let deck = root.join("decks/bruss.toml");
    let out = Flipcard::without_data()
        .args(["sim", "--deck", deck.to_str().unwrap(), "--scene", "bruss"])
        .args(["--method", "rk4", "--samples", "2", "--format", "json"])
        .run();
    assert_eq!(out.status.code(), Some(0), "{}", out.stderr());
    let v: serde_json::Value = serde_json::from_str(&out.stdout()).unwrap();
    assert_eq!(v["stats"]["lu"], serde_json::Value::Null, "{}", v["stats"]);
    assert_eq!(v["stats"]["lu_decompositions"], 0, "{}", v["stats"]);
}
