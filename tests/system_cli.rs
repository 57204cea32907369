//! System scenes through the real binary: `check` down to the character
//! inside an expression, `sim --scene` sampled, measured and reported, and
//! the methods that apply.

use std::path::{Path, PathBuf};

use crate::support::Flipcard;

fn deck() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/systems/decks/oscillations-test.toml")
}

fn run(args: &[&str]) -> (i32, String, String) {
    let out = Flipcard::without_data().args(args).run();
    (out.status.code().unwrap_or(-1), out.stdout(), out.stderr())
}

fn sim(args: &[&str]) -> (i32, String, String) {
    let d = deck();
    let mut all = vec!["sim", "--deck", d.to_str().unwrap()];
    all.extend_from_slice(args);
    run(&all)
}

#[test]
fn the_issues_deck_format_checks_clean() {
    let d = deck();
    let (code, out, err) = run(&["check", "--no-simulate", d.to_str().unwrap()]);
    assert_eq!(code, 0, "{out}{err}");
    assert!(out.contains("4 scenes"), "{out}");
    // Run, the scene that blows up at t = 1 of its 2 does not play to its
    // end: refused at its id, the rest run clean.
    let (code, out, err) = run(&["check", d.to_str().unwrap()]);
    assert_eq!(code, 1, "{out}{err}");
    assert!(
        err.contains(
            "oscillations-test.toml:74:6: error: scene `blowup` does not run to its end: the solution blows up near t = 1.0"
        ),
        "{err}"
    );
    assert!(err.contains("1 error, 0 warnings"), "{err}");
}

#[test]
fn csv_has_time_variables_then_observables_in_deck_order() {
    let (code, out, err) = sim(&["--scene", "pendulum-170", "--samples", "5"]);
    assert_eq!(code, 0, "{err}");
    let mut lines = out.lines();
    assert_eq!(lines.next(), Some("t,theta,omega,energy,x,y"));
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 5);
    assert_eq!(rows[0][1], 2.9670597283903604);
    assert_eq!(rows[4][0], 20.0);
    for r in &rows {
        // The observables are the deck's expressions of the state.
        assert!((r[4] - r[1].sin()).abs() < 1e-15);
        assert!((r[5] + r[1].cos()).abs() < 1e-15);
        let e = 0.5 * r[2] * r[2] + 9.81 * (1.0 - r[1].cos());
        assert!((r[3] - e).abs() < 1e-12 * e);
    }
    let (code, out, _) = sim(&[
        "--scene",
        "pendulum-170",
        "--samples",
        "3",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["method"], "auto");
    assert_eq!(v["samples"].as_array().unwrap().len(), 3);
    assert_eq!(v["samples"][0]["theta"], 2.9670597283903604);
}

#[test]
fn measures_print_one_value_a_line() {
    let (code, out, err) = sim(&[
        "--scene",
        "pendulum-170",
        "--measure",
        "period(theta)",
        "--measure",
        "max(x)",
    ]);
    assert_eq!(code, 0, "{err}");
    let values: Vec<f64> = out.lines().map(|l| l.parse().unwrap()).collect();
    assert_eq!(values.len(), 2);
    // T = 4K(m)√(L/g) with m = sin²(85°): 2.4394 T₀.
    let t0 = 2.0 * std::f64::consts::PI / 9.81f64.sqrt();
    assert!((values[0] / t0 - 2.4394).abs() < 1e-4, "{}", values[0] / t0);
    assert!(values[1] > 0.99 && values[1] <= 1.0);
    for bad in ["period(thet)", "flips", "peroid(theta)", "period(theta"] {
        let (code, out, err) = sim(&["--scene", "pendulum-170", "--measure", bad]);
        assert_eq!(code, 1, "{bad}");
        assert!(out.is_empty(), "{bad}: {out}");
        assert_eq!(err.lines().count(), 1, "{bad}: {err}");
    }
}

#[test]
fn methods_apply_to_their_kind_of_scene() {
    for m in ["auto", "adaptive", "radau", "rk4"] {
        let (code, out, err) = sim(&[
            "--scene",
            "pendulum-170",
            "--method",
            m,
            "--measure",
            "period(theta)",
        ]);
        assert_eq!(code, 0, "{m}: {err}");
        let p: f64 = out.trim().parse().unwrap();
        assert!((p - 4.8935).abs() < 1e-3, "{m}: {p}");
    }
    let (code, _, err) = sim(&[
        "--scene",
        "pendulum-170",
        "--method",
        "exact",
        "--samples",
        "3",
    ]);
    assert_eq!(code, 1);
    assert!(
        err.contains("is a system, which takes auto, adaptive, radau or rk4"),
        "{err}"
    );
    let (code, _, err) = run(&["sim", "--scene", "middle-axis-spin", "--method", "radau"]);
    assert_eq!(code, 1);
    assert!(err.contains("only system scenes use it"), "{err}");
    // adaptive refuses the stiff Van der Pol, with the reason and the way out.
    let (code, _, err) = sim(&[
        "--scene",
        "vdp",
        "--method",
        "adaptive",
        "--measure",
        "max(x)",
    ]);
    assert_eq!(code, 1);
    assert!(err.contains("stiff") && err.contains("radau"), "{err}");
    let (code, out, err) = sim(&["--scene", "vdp", "--measure", "max(x)"]);
    assert_eq!(code, 0, "{err}");
    let amp: f64 = out.trim().parse().unwrap();
    assert!((amp - 2.0).abs() < 0.01, "{amp}");
}

#[test]
fn blow_up_stops_with_its_time_and_no_garbage() {
    for m in ["auto", "adaptive", "radau", "rk4"] {
        let (code, out, err) = sim(&["--scene", "blowup", "--method", m, "--samples", "5"]);
        assert_eq!(code, 1, "{m}");
        assert!(
            err.contains("the solution blows up near t = 1.0"),
            "{m}: {err}"
        );
        assert!(!out.contains("NaN") && !out.contains("inf"), "{m}: {out}");
    }
}

#[test]
fn a_refusal_midway_leaves_well_formed_json_with_its_reason() {
    for m in ["auto", "adaptive", "radau", "rk4"] {
        let (code, out, err) = sim(&[
            "--scene",
            "blowup",
            "--method",
            m,
            "--samples",
            "5",
            "--format",
            "json",
        ]);
        assert_eq!(code, 1, "{m}: {err}");
        let doc: serde_json::Value =
            serde_json::from_str(&out).unwrap_or_else(|e| panic!("{m}: not JSON ({e}):\n{out}"));
        let why = doc["error"].as_str().unwrap_or_default();
        assert!(why.contains("blows up near t = 1.0"), "{m}: {out}");
        assert!(err.contains(why), "{m}: {err}");
        let samples = doc["samples"].as_array().unwrap();
        assert!(!samples.is_empty() && samples.len() < 5, "{m}: {out}");
        assert_eq!(samples[0]["t"], 0.0, "{m}");
    }
    // A run that ends: the same document without `error`.
    let (code, out, err) = sim(&["--scene", "blowup", "--samples", "3", "--format", "json"]);
    assert_eq!(code, 1, "{err}");
    let (code2, out2, _) = sim(&["--scene", "vdp", "--samples", "3", "--format", "json"]);
    assert_eq!(code2, 0);
    let doc: serde_json::Value = serde_json::from_str(&out2).unwrap();
    assert!(doc.get("error").is_none(), "{out2}");
    assert_eq!(doc["samples"].as_array().unwrap().len(), 3);
    assert!(out.contains("\"error\""));
}

#[test]
fn a_sampled_run_says_what_it_did() {
    // The bundled stiff Van der Pol: auto switches to Radau IIA at once.
    let (code, out, err) = run(&["sim", "--scene", "vdp-stiff", "--samples", "3", "--stats"]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(out.lines().count(), 4, "{out}");
    let line = err
        .lines()
        .find(|l| l.starts_with("stats: "))
        .unwrap_or_else(|| panic!("{err}"));
    assert!(
        line.contains("LU decompositions") && line.contains("switched to radau"),
        "{line}"
    );
    let (code, out, err) = run(&[
        "sim",
        "--scene",
        "vdp-stiff",
        "--samples",
        "3",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{err}");
    let doc: serde_json::Value = serde_json::from_str(&out).unwrap();
    let stats = &doc["stats"];
    let n = |k: &str| {
        stats[k]
            .as_u64()
            .unwrap_or_else(|| panic!("{k} in {stats}"))
    };
    assert!(n("steps") > 0 && n("rhs_evals") > n("steps"), "{stats}");
    assert!(
        n("jacobian_evals") > 0 && n("lu_decompositions") >= n("jacobian_evals"),
        "{stats}"
    );
    // From its start: the look at the Jacobian there finds the damped
    // mode of rate 3μ and the run starts in Radau IIA.
    let t = stats["stiff_from"].as_f64().unwrap();
    assert_eq!(t, 0.0, "{stats}");
    // Without --stats the CSV run says nothing more.
    let (_, _, err) = run(&["sim", "--scene", "vdp-stiff", "--samples", "3"]);
    assert!(!err.contains("stats:"), "{err}");
}

#[test]
fn rigid_scenes_sample_and_measure_too() {
    let (code, out, err) = run(&["sim", "--scene", "middle-axis-spin", "--samples", "3"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.starts_with("t,w1,w2,w3,qw,qx,qy,qz,energy,l2\n"),
        "{out}"
    );
    assert_eq!(out.lines().count(), 4);
    let (code, out, err) = run(&["sim", "--scene", "middle-axis-spin", "--measure", "flips"]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(out.trim(), "3");
}

#[test]
fn scene_report_gives_prompt_verdicts() {
    let (code, out, err) = sim(&["--scene", "pendulum-170"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("period(theta)"), "{out}");
    assert!(
        out.contains("p1: expected period(theta) = 4.89 s: ok"),
        "{out}"
    );
    assert!(out.contains("p2: expected swings: ok"), "{out}");
}

/// A copy of the test deck with one replacement, checked: the single
/// error's position and message.
fn check_with(from: &str, to: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/systems");
    std::fs::create_dir_all(dir.path().join("decks")).unwrap();
    std::fs::create_dir_all(dir.path().join("content/oscillations-test")).unwrap();
    for lang in ["en", "hi-Latn"] {
        let p = format!("content/oscillations-test/{lang}.toml");
        std::fs::copy(src.join(&p), dir.path().join(&p)).unwrap();
    }
    let text = std::fs::read_to_string(deck()).unwrap();
    assert!(text.contains(from), "{from}");
    let path = dir.path().join("decks/oscillations-test.toml");
    std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    let (code, out, err) = run(&["check", path.to_str().unwrap()]);
    assert_eq!(code, 1, "{from} -> {to}: {out}{err}");
    let all = format!("{out}{err}");
    all.lines()
        .find(|l| l.contains(": error: "))
        .map(|l| l[l.find("oscillations-test.toml:").unwrap()..].to_string())
        .unwrap_or(all)
}

#[test]
fn check_points_inside_the_expression() {
    let line = |needle: &str| {
        let text = std::fs::read_to_string(deck()).unwrap();
        text.lines().position(|l| l.contains(needle)).unwrap() + 1
    };
    let eq = line("equations = [\"omega\"");
    let cases = [
        (
            "\"-g/L*sin(theta)\"",
            "\"-g/L*sin(thta)\"",
            33,
            "unknown name `thta`",
        ),
        (
            "\"-g/L*sin(theta)\"",
            "\"-g/L*sin(theta\"",
            38,
            "expected `,` or `)`",
        ),
        (
            "\"-g/L*sin(theta)\"",
            "\"-g/L*atan2(theta)\"",
            29,
            "`atan2` takes 2 arguments, found 1",
        ),
        (
            "\"-g/L*sin(theta)\"",
            "\"-g/L*sin(theta) 2\"",
            40,
            "unexpected a number",
        ),
    ];
    for (from, to, col, msg) in cases {
        let got = check_with(from, to);
        let want =
            format!("oscillations-test.toml:{eq}:{col}: error: the equation of `omega`: {msg}");
        assert!(got.starts_with(&want), "{got}\nwanted {want}");
    }
    let got = check_with("-g/L*sin(theta)", "-g/L*sin(thta)");
    assert!(got.contains("unknown name `thta`"));
    for (from, to, msg) in [
        (
            "initial = [2.9670597283903604, 0.0]",
            "initial = [2.9670597283903604]",
            "`initial` of scene `pendulum-170` has 1 number for 2 variables",
        ),
        (
            "params = { g = 9.81, L = 1.0 }",
            "params = { g = 9.81, L = 1.0, sin = 2.0 }",
            "parameter name `sin` shadows the function `sin`",
        ),
        (
            "conserved = [\"energy\"]",
            "conserved = [\"enrgy\"]",
            "`conserved` names `enrgy`",
        ),
        (
            "phase = [\"theta\", \"omega\"]",
            "phase = [\"theta\", \"omga\"]",
            "`phase` names `omga`",
        ),
        (
            "measure = \"period(theta)\"",
            "measure = \"period(thet)\"",
            "`thet` is not a variable or observable",
        ),
        (
            "measure = \"period(theta)\"",
            "measure = \"flips\"",
            "`flips` is a rigid-body measure",
        ),
        (
            "equations = [\"x^2\"]",
            "equations = [\"x^2/(x - 1)\"]",
            "gives inf at t = 0",
        ),
        (
            "variables = [\"x\"]",
            "variables = [\"x\"]\ninertia = [1.0, 2.0, 3.0]",
            "`inertia` belongs to a rigid-body scene",
        ),
        (
            "duration = 1e11",
            "duration = -1.0",
            "duration -1 is not a positive finite number",
        ),
        (
            "y = \"-L*cos(theta)\"",
            "y = \"-L*cos(theta) + z\", z = \"0\"",
            "uses `z`, which is not defined before it",
        ),
        (
            "show = [\"plot\"]\nplot = [\"x\"]",
            "show = [\"plot\", \"polhode\"]\nplot = [\"x\"]",
            "unknown panel `polhode`",
        ),
    ] {
        let got = check_with(from, to);
        assert!(got.contains(msg), "{from} -> {to}: {got}");
    }
}
