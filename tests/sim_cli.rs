//! `flipcard sim` through the real binary: output format, sample times,
//! precision, invariants, and a one-line exit-1 answer to every bad input.

use crate::support::{Flipcard, Output};

fn sim(args: &[&str]) -> Output {
    Flipcard::without_data().arg("sim").args(args).run()
}

fn stdout(out: &Output) -> String {
    String::from_utf8(out.stdout.clone()).expect("utf-8 output")
}

fn stderr(out: &Output) -> String {
    String::from_utf8(out.stderr.clone()).expect("utf-8 errors")
}

const CASE_A: [&str; 6] = [
    "--inertia",
    "1,2,3",
    "--omega",
    "0.01,10,0.01",
    "--t-end",
    "100",
];

fn run_ok(args: &[&str]) -> String {
    let out = sim(args);
    assert!(out.status.success(), "{args:?}: {}", stderr(&out));
    assert!(stderr(&out).is_empty(), "{}", stderr(&out));
    stdout(&out)
}

fn rows(csv: &str) -> Vec<Vec<f64>> {
    csv.lines()
        .skip(1)
        .map(|line| {
            line.split(',')
                .map(|v| v.parse::<f64>().expect("number"))
                .collect()
        })
        .collect()
}

#[test]
fn csv_has_the_exact_header_and_n_rows_at_even_times() {
    for method in ["adaptive", "splitting", "splitting4", "rk4"] {
        let csv = run_ok(&[&CASE_A[..], &["--method", method, "--samples", "7"]].concat());
        let mut lines = csv.lines();
        assert_eq!(lines.next(), Some("t,w1,w2,w3,qw,qx,qy,qz,energy,l2"));
        let rows = rows(&csv);
        assert_eq!(rows.len(), 7, "{method}");
        for (k, row) in rows.iter().enumerate() {
            assert_eq!(row.len(), 10);
            let t = if k == 6 {
                100.0
            } else {
                k as f64 * 100.0 / 6.0
            };
            assert_eq!(row[0], t, "{method} row {k}");
        }
        assert_eq!(rows[0][1..8], [0.01, 10.0, 0.01, 1.0, 0.0, 0.0, 0.0]);
    }
}

#[test]
fn default_is_101_samples() {
    let csv = run_ok(&[&CASE_A[..], &["--method", "adaptive"]].concat());
    assert_eq!(csv.lines().count(), 102);
}

#[test]
fn every_float_is_printed_in_shortest_round_trip_form() {
    let csv = run_ok(
        &[
            "--inertia",
            "0.1,0.2,0.25",
            "--omega",
            "0.3,-1.7,2.9",
            "--t-end",
            "3.3",
            "--samples",
            "13",
            "--method",
            "adaptive",
        ][..],
    );
    for line in csv.lines().skip(1) {
        for field in line.split(',') {
            let v: f64 = field.parse().unwrap();
            assert_eq!(
                flipcard::text::num::show(v),
                field,
                "not shortest round-trip"
            );
        }
    }
}

#[test]
fn invariant_columns_match_omega_and_stay_constant() {
    let csv = run_ok(&[&CASE_A[..], &["--method", "adaptive", "--tol", "1e-12"]].concat());
    let i = [1.0, 2.0, 3.0];
    let rows = rows(&csv);
    let (e0, l0) = (rows[0][8], rows[0][9]);
    assert_eq!((e0, l0), (100.0002, 400.001));
    for row in &rows {
        let w = &row[1..4];
        let e: f64 = 0.5 * (0..3).map(|k| i[k] * w[k] * w[k]).sum::<f64>();
        let l2: f64 = (0..3).map(|k| (i[k] * w[k]).powi(2)).sum();
        assert!((row[8] - e).abs() <= 1e-14 * e && (row[9] - l2).abs() <= 1e-14 * l2);
        assert!(
            (row[8] / e0 - 1.0).abs() < 1e-9,
            "energy drift at t = {}",
            row[0]
        );
        assert!(
            (row[9] / l0 - 1.0).abs() < 1e-9,
            "|L|² drift at t = {}",
            row[0]
        );
        let qn: f64 = row[4..8].iter().map(|v| v * v).sum::<f64>().sqrt();
        assert!((qn - 1.0).abs() < 1e-9, "|q| at t = {}", row[0]);
    }
}

#[test]
fn columns_follow_the_axes_as_given() {
    // The same body with axes listed in another order: same motion, permuted.
    let a = rows(&run_ok(
        &[
            &CASE_A[..],
            &["--method", "rk4", "--dt", "0.001", "--samples", "5"],
        ]
        .concat(),
    ));
    let b = rows(&run_ok(&[
        "--inertia",
        "2,3,1",
        "--omega",
        "10,0.01,0.01",
        "--t-end",
        "100",
        "--method",
        "rk4",
        "--dt",
        "0.001",
        "--samples",
        "5",
    ]));
    for (ra, rb) in a.iter().zip(&b) {
        // (w1, w2, w3) of a is (w3', w1', w2') of b.
        assert!((ra[1] - rb[3]).abs() < 1e-9 * 10.0, "{ra:?} vs {rb:?}");
        assert!((ra[2] - rb[1]).abs() < 1e-9 * 10.0);
        assert!((ra[3] - rb[2]).abs() < 1e-9 * 10.0);
    }
}

#[test]
fn json_carries_inputs_and_the_same_samples() {
    let args = [
        &CASE_A[..],
        &["--method", "splitting", "--dt", "0.01", "--samples", "4"],
    ]
    .concat();
    let csv = rows(&run_ok(&args));
    let json = run_ok(&[&args[..], &["--format", "json"]].concat());
    let v: serde_json::Value = serde_json::from_str(&json).expect("valid JSON");
    assert_eq!(v["inertia"], serde_json::json!([1.0, 2.0, 3.0]));
    assert_eq!(v["omega"], serde_json::json!([0.01, 10.0, 0.01]));
    assert_eq!(v["t_end"], 100.0);
    assert_eq!(v["method"], "splitting");
    assert_eq!(v["dt"], 0.01);
    assert!(v["tol"].is_null());
    let samples = v["samples"].as_array().expect("samples array");
    assert_eq!(samples.len(), 4);
    let names = [
        "t", "w1", "w2", "w3", "qw", "qx", "qy", "qz", "energy", "l2",
    ];
    for s in samples {
        for name in names {
            assert!(s[name].is_f64(), "{name} in {s}");
        }
    }
    // serde_json's default float parser may be an ulp off, so read the
    // number texts (one sample object per line) with Rust's exact parser.
    let lines: Vec<&str> = json.lines().filter(|l| l.starts_with("{\"t\"")).collect();
    assert_eq!(lines.len(), 4);
    for (line, row) in lines.iter().zip(&csv) {
        let body = line
            .trim_end_matches(',')
            .trim_start_matches('{')
            .trim_end_matches('}');
        for (field, (name, value)) in body.split(',').zip(names.iter().zip(row)) {
            let (key, text) = field.split_once(':').expect("key:value");
            assert_eq!(key, format!("\"{name}\""));
            assert_eq!(text.parse::<f64>().unwrap(), *value, "{name}");
        }
    }
}

#[test]
fn json_reports_the_default_settings_it_used() {
    let json = run_ok(
        &[
            &CASE_A[..],
            &["--method", "adaptive", "--format", "json", "--samples", "2"],
        ]
        .concat(),
    );
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["tol"], 1e-10);
    assert!(v["dt"].is_null());
}

fn assert_one_line_failure(args: &[&str], expect: &str) {
    let out = sim(args);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
    assert!(stdout(&out).is_empty(), "{args:?} printed output");
    assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
    assert!(err.starts_with("flipcard: error: "), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(err.contains(expect), "{args:?}: '{err}' lacks '{expect}'");
}

#[test]
fn every_invalid_input_is_one_line_and_exit_1() {
    let with = |extra: &[&'static str]| -> Vec<&'static str> {
        let mut v = vec!["--inertia", "1,2,3", "--omega", "1,2,3", "--t-end", "5"];
        v.extend_from_slice(extra);
        v
    };
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["--omega", "1,2,3", "--t-end", "5"], "--inertia"),
        (vec!["--inertia", "1,2,3", "--t-end", "5"], "--omega"),
        (vec!["--inertia", "1,2,3", "--omega", "1,2,3"], "--t-end"),
        (
            vec!["--inertia", "1,2", "--omega", "1,2,3", "--t-end", "5"],
            "expected 3",
        ),
        (
            vec!["--inertia", "1,2,3,4", "--omega", "1,2,3", "--t-end", "5"],
            "expected 3",
        ),
        (
            vec!["--inertia", "1,x,3", "--omega", "1,2,3", "--t-end", "5"],
            "not a number",
        ),
        (
            vec!["--inertia", "1,2,4", "--omega", "1,2,3", "--t-end", "5"],
            "triangle",
        ),
        (
            vec!["--inertia", "0,2,3", "--omega", "1,2,3", "--t-end", "5"],
            "not positive",
        ),
        (
            vec!["--inertia", "-1,2,3", "--omega", "1,2,3", "--t-end", "5"],
            "not positive",
        ),
        (
            vec!["--inertia", "inf,2,3", "--omega", "1,2,3", "--t-end", "5"],
            "not finite",
        ),
        (
            vec!["--inertia", "1,2,3", "--omega", "1,nan,3", "--t-end", "5"],
            "not finite",
        ),
        (
            vec!["--inertia", "1,2,3", "--omega", "1,2,", "--t-end", "5"],
            "not a number",
        ),
        (
            vec!["--inertia", "1,2,3", "--omega", "1,2,3", "--t-end", "0"],
            "--t-end",
        ),
        (
            vec!["--inertia", "1,2,3", "--omega", "1,2,3", "--t-end", "-4"],
            "--t-end",
        ),
        (
            vec!["--inertia", "1,2,3", "--omega", "1,2,3", "--t-end", "inf"],
            "--t-end",
        ),
        (
            vec!["--inertia", "1,2,3", "--omega", "1,2,3", "--t-end", "soon"],
            "not a number",
        ),
        (with(&["--samples", "1"]), "--samples"),
        (with(&["--samples", "0"]), "--samples"),
        (with(&["--samples", "-3"]), "--samples"),
        (with(&["--samples", "many"]), "--samples"),
        (
            with(&["--samples", "18446744073709551615"]),
            "--samples: at most",
        ),
        (
            vec![
                "--inertia",
                "1,2,3",
                "--omega",
                "1,2,3",
                "--t-end",
                "5e-324",
                "--samples",
                "3",
            ],
            "--samples: at most 2 over t = 5e-324",
        ),
        (with(&["--method", "adaptive", "--tol", "0"]), "tol"),
        (with(&["--method", "adaptive", "--tol", "-1e-8"]), "tol"),
        (with(&["--method", "adaptive", "--tol", "1e-30"]), "tol"),
        (with(&["--method", "adaptive", "--tol", "tight"]), "--tol"),
        (with(&["--method", "rk4", "--tol", "1e-8"]), "tol"),
        (with(&["--method", "splitting", "--tol", "1e-8"]), "tol"),
        (with(&["--method", "adaptive", "--dt", "0.01"]), "dt"),
        (with(&["--method", "rk4", "--dt", "0"]), "dt"),
        (with(&["--method", "splitting4", "--dt", "-0.1"]), "dt"),
        (with(&["--method", "splitting", "--dt", "nan"]), "dt"),
        // A step past half a turn of the fastest rate aliases the motion.
        (
            with(&["--method", "splitting", "--dt", "50"]),
            "more than half a turn",
        ),
        (
            with(&["--method", "rk4", "--dt", "1"]),
            "more than half a turn",
        ),
        (with(&["--method", "leapfrog"]), "--method"),
        (with(&["--format", "xml"]), "--format"),
        (with(&["--bogus"]), "--bogus"),
        (
            vec![
                "--inertia",
                "1,2,3",
                "--omega",
                "1e200,0,0",
                "--t-end",
                "1",
                "--method",
                "rk4",
            ],
            "too large",
        ),
    ];
    for (args, expect) in cases {
        assert_one_line_failure(&args, expect);
    }
}

#[test]
fn a_run_beyond_the_step_budget_is_refused_at_once_with_the_reason() {
    let out = sim(&[
        "--inertia",
        "1,2,3",
        "--omega",
        "1e9,2e8,3e8",
        "--t-end",
        "1",
        "--method",
        "adaptive",
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        stdout(&out).is_empty(),
        "nothing printed before the refusal"
    );
    let err = stderr(&out);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("stiff: ") && err.contains("use the exact solver"),
        "{err}"
    );
    let out = sim(&[&CASE_A[..], &["--method", "rk4", "--dt", "1e-9"]].concat());
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("budget"), "{}", stderr(&out));
}

#[test]
fn extreme_inputs_give_finite_output() {
    let cases: [[&str; 2]; 5] = [
        ["1e-6,1,1", "0.3,1,0.5"],
        ["1,1,2", "0.5,1,1"],
        ["3,4,6", "2,0.5,1"],
        ["1,2,3", "0,0,0"],
        ["1,2,3", "1e-15,10,1e-15"],
    ];
    for [i, w] in cases {
        for method in ["adaptive", "splitting", "splitting4", "rk4"] {
            let csv = run_ok(&[
                "--inertia",
                i,
                "--omega",
                w,
                "--t-end",
                "10",
                "--method",
                method,
                "--samples",
                "11",
            ]);
            for row in rows(&csv) {
                assert!(
                    row.iter().all(|v| v.is_finite()),
                    "{i} {w} {method}: {row:?}"
                );
            }
        }
    }
}

#[test]
fn list_names_every_bundled_scene_with_its_setup() {
    let text = run_ok(&["--list"]);
    let decks = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("decks");
    let declared: usize = std::fs::read_dir(&decks)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.path().extension().is_some_and(|x| x == "toml"))
        .map(|e| {
            std::fs::read_to_string(e.path())
                .unwrap()
                .lines()
                .filter(|l| l.trim() == "[[scene]]")
                .count()
        })
        .sum();
    assert!(declared > 0);
    assert_eq!(text.lines().count(), declared, "{text}");
    for line in text.lines() {
        let fields: Vec<&str> = line.split('\t').collect();
        assert_eq!(fields.len(), 7, "{line}");
        if let Some(variables) = fields[2].strip_prefix("variables=") {
            // A system scene: one finite initial value per variable.
            let initial: Vec<f64> = fields[3]
                .strip_prefix("initial=")
                .unwrap()
                .split(',')
                .map(|v| v.parse().unwrap())
                .collect();
            assert_eq!(initial.len(), variables.split(',').count(), "{line}");
            assert!(initial.iter().all(|v| v.is_finite()), "{line}");
        } else {
            let inertia: Vec<f64> = fields[2]
                .strip_prefix("inertia=")
                .unwrap()
                .split(',')
                .map(|v| v.parse().unwrap())
                .collect();
            assert!(flipcard::sim::Body::new([inertia[0], inertia[1], inertia[2]]).is_ok());
        }
        assert!(fields[5].starts_with("show="), "{line}");
    }
    assert!(text.contains("middle-axis-spin\t"), "{text}");
    assert!(text.contains("pendulum-170\toscillations\t"), "{text}");
}

#[test]
fn exact_is_the_default_and_the_integrators_agree_with_it() {
    let setup = [
        "--inertia",
        "1,2,3",
        "--omega",
        "0.3,1,3",
        "--t-end",
        "20",
        "--samples",
        "21",
    ];
    let exact = rows(&run_ok(&setup));
    assert_eq!(
        exact,
        rows(&run_ok(&[&setup[..], &["--method", "exact"]].concat()))
    );
    let (e0, l0) = (exact[0][8], exact[0][9]);
    for row in &exact {
        assert!((row[8] / e0 - 1.0).abs() < 1e-13 && (row[9] / l0 - 1.0).abs() < 1e-13);
    }
    for (method, knob, value, bound) in [
        ("adaptive", "--tol", "1e-12", 1e-10),
        ("rk4", "--dt", "1e-3", 1e-9),
        ("splitting4", "--dt", "1e-3", 1e-9),
        ("splitting", "--dt", "1e-3", 1e-4),
    ] {
        let other = rows(&run_ok(
            &[&setup[..], &["--method", method, knob, value]].concat(),
        ));
        for (a, b) in exact.iter().zip(&other) {
            assert_eq!(a[0], b[0]);
            let err = (1..8).map(|k| (a[k] - b[k]).abs()).fold(0.0, f64::max);
            // ω is of size ~3, q of size 1: an absolute bound serves both.
            assert!(err < 3.0 * bound, "{method} at t = {}: {err}", a[0]);
        }
    }
}

/// The longest run of consecutive ASCII digits in `text`.
fn longest_digit_run(text: &str) -> usize {
    text.split(|c: char| !c.is_ascii_digit())
        .map(str::len)
        .max()
        .unwrap_or(0)
}

/// Exact rows of the same run, for comparing another method against.
fn exact_rows(inertia: &str, omega: &str, t_end: &str, samples: &str) -> Vec<Vec<f64>> {
    rows(&run_ok(&[
        "--inertia",
        inertia,
        "--omega",
        omega,
        "--t-end",
        t_end,
        "--samples",
        samples,
    ]))
}

#[test]
fn needles_are_computed_accurately_or_refused_never_garbage() {
    // Needles as thin as 1e-6, 1e-9 and 1e-300 of the other moments, with
    // every method and both output formats: a run either prints finite
    // states that agree with the exact solution, or exits 1 with a reason
    // and a way out.
    for inertia in ["1e-6,1,1", "1e-9,1,1", "1e-300,1,1", "1e-9,1,1.000000001"] {
        let omega = "1,1,0.5";
        let exact = exact_rows(inertia, omega, "10", "11");
        for method in ["exact", "adaptive", "splitting", "splitting4", "rk4"] {
            for format in ["csv", "json"] {
                let args = [
                    "--inertia",
                    inertia,
                    "--omega",
                    omega,
                    "--t-end",
                    "10",
                    "--samples",
                    "11",
                    "--method",
                    method,
                    "--format",
                    format,
                ];
                let out = sim(&args);
                let (text, err) = (stdout(&out), stderr(&out));
                assert!(!text.contains("inf") && !text.contains("NaN"), "{args:?}");
                if !out.status.success() {
                    assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
                    assert!(text.is_empty(), "{args:?} printed before refusing");
                    assert_eq!(err.lines().count(), 1, "{err}");
                    assert!(err.contains("exact method"), "{args:?}: {err}");
                    continue;
                }
                let got: Vec<Vec<f64>> = if format == "csv" {
                    rows(&text)
                } else {
                    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
                    let names = [
                        "t", "w1", "w2", "w3", "qw", "qx", "qy", "qz", "energy", "l2",
                    ];
                    v["samples"]
                        .as_array()
                        .unwrap()
                        .iter()
                        .map(|s| {
                            // A non-finite number would be `null` in JSON.
                            names
                                .iter()
                                .map(|n| s[n].as_f64().unwrap_or(f64::NAN))
                                .collect()
                        })
                        .collect()
                };
                assert_eq!(got.len(), exact.len(), "{args:?}");
                for (a, b) in got.iter().zip(&exact) {
                    assert!(a.iter().all(|v| v.is_finite()), "{args:?}: {a:?}");
                    let err = (1..4).map(|k| (a[k] - b[k]).abs()).fold(0.0, f64::max);
                    assert!(err < 1e-3, "{args:?} at t = {}: ω off by {err}", a[0]);
                }
            }
        }
    }
}

#[test]
fn a_span_beyond_what_f64_resolves_is_refused_with_its_limit() {
    // I = (1, 2, 3), ω = (0.01, 10, 0.01): the spin reaches 11.55 rad/s, so
    // the phase passes 2^32 rad at t ≈ 3.719e8.
    for method in ["exact", "adaptive", "splitting", "splitting4", "rk4"] {
        let out = sim(&[&CASE_A[..4], &["--t-end", "1e17", "--method", method]].concat());
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(1), "{method}: {err}");
        assert!(stdout(&out).is_empty(), "{method}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(
            err.contains("t = 1e17 is beyond 371900000, the longest span"),
            "{method}: {err}"
        );
    }
    // Inside the limit the exact solution still answers.
    let csv = run_ok(&[&CASE_A[..4], &["--t-end", "3.7e8", "--samples", "3"]].concat());
    assert_eq!(rows(&csv).len(), 3);
}

#[test]
fn no_number_is_printed_as_a_long_string_of_digits() {
    // (arguments, whether the run succeeds): outputs and messages that
    // hold extreme magnitudes, each of which must spell them with an
    // exponent.
    let cases: Vec<(Vec<&str>, bool)> = vec![
        (
            vec![
                "--inertia",
                "1,2,3",
                "--omega",
                "1e-150,2e-150,1e-150",
                "--t-end",
                "1e150",
            ],
            true,
        ),
        (
            vec![
                "--inertia",
                "1e-300,2e-300,3e-300",
                "--omega",
                "1e150,1e150,5e149",
                "--t-end",
                "5e-324",
            ],
            true,
        ),
        (
            vec![
                "--inertia",
                "1,2,3",
                "--omega",
                "1,2,3",
                "--t-end",
                "5e-324",
            ],
            true,
        ),
        (
            vec![
                "--inertia",
                "-1e-300,1,1",
                "--omega",
                "1,2,3",
                "--t-end",
                "1",
            ],
            false,
        ),
        (
            vec![
                "--inertia",
                "1e-300,1,3",
                "--omega",
                "1,2,3",
                "--t-end",
                "1",
            ],
            false,
        ),
        (
            vec!["--inertia", "1,2,3", "--omega", "1e200,0,0", "--t-end", "1"],
            false,
        ),
        (
            vec![
                "--inertia",
                "1,2,3",
                "--omega",
                "1e-300,0,0",
                "--t-end",
                "1",
            ],
            false,
        ),
        (
            vec![
                "--inertia",
                "1,2,3",
                "--omega",
                "1,2,3",
                "--t-end",
                "-1e-300",
            ],
            false,
        ),
        (
            vec!["--inertia", "1,2,3", "--omega", "1,2,3", "--t-end", "1e300"],
            false,
        ),
        (
            vec![
                "--inertia",
                "1,2,3",
                "--omega",
                "1,2,3",
                "--t-end",
                "1",
                "--method",
                "adaptive",
                "--tol",
                "1e-300",
            ],
            false,
        ),
        (
            vec![
                "--inertia",
                "1,2,3",
                "--omega",
                "1,2,3",
                "--t-end",
                "1",
                "--method",
                "rk4",
                "--dt",
                "5e-324",
            ],
            false,
        ),
        (
            vec![
                "--inertia",
                "1,2,3",
                "--omega",
                "1,2,3",
                "--t-end",
                "1",
                "--method",
                "splitting",
                "--dt",
                "1e300",
            ],
            false,
        ),
    ];
    for (args, succeeds) in cases {
        for format in ["csv", "json"] {
            let args = [&args[..], &["--samples", "2", "--format", format]].concat();
            let out = sim(&args);
            let (text, err) = (stdout(&out), stderr(&out));
            assert_eq!(out.status.success(), succeeds, "{args:?}: {err}");
            let longest = longest_digit_run(&text).max(longest_digit_run(&err));
            assert!(
                longest < 30,
                "{args:?}: a {longest}-digit run in\n{text}{err}"
            );
        }
    }
}
