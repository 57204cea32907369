//! `flipcard bench --quick --out DIR` through the real binary: the CSV has
//! the exact header and a row for every case × method, the numbers of the
//! runs that finished are finite, the adaptive error falls as the tolerance
//! tightens, and the SVG parses.

use std::collections::{BTreeMap, BTreeSet};

use crate::support::Flipcard;

const HEADER: &str =
    "case,method,setting,steps,rhs_evals,wall_s,err_omega,err_energy,err_l2,err_lspace,err_qnorm";

/// Splits one CSV line, honouring double quotes.
fn fields(line: &str) -> Vec<String> {
    let mut out = vec![String::new()];
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '"' if quoted && chars.peek() == Some(&'"') => {
                chars.next();
                out.last_mut().unwrap().push('"');
            }
            '"' => quoted = !quoted,
            ',' if !quoted => out.push(String::new()),
            c => out.last_mut().unwrap().push(c),
        }
    }
    out
}

#[test]
fn quick_bench_writes_csv_and_svg() {
    let dir = tempfile::tempdir().unwrap();
    let out = Flipcard::without_data()
        .args(["bench", "--quick", "--out"])
        .arg(dir.path())
        .run();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("bench [1/"), "progress on stderr: {stderr}");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.starts_with("case"), "table on stdout: {stdout}");

    let csv = std::fs::read_to_string(dir.path().join("work_precision.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some(HEADER));
    let mut seen = BTreeSet::new();
    // (case) → [(tol, err_omega)] of the adaptive runs.
    let mut adaptive: BTreeMap<String, Vec<(f64, f64)>> = BTreeMap::new();
    let mut finished = 0;
    for line in lines {
        let f = fields(line);
        assert_eq!(f.len(), 11, "{line}");
        seen.insert((f[0].clone(), f[1].clone()));
        if f[3].is_empty() {
            // A run its budget refused: the reason follows the setting.
            assert!(f[2].contains('('), "{line}");
            assert!(f[4..].iter().all(String::is_empty), "{line}");
            continue;
        }
        finished += 1;
        let numbers: Vec<f64> = f[3..]
            .iter()
            .map(|x| x.parse::<f64>().unwrap_or_else(|_| panic!("{line}")))
            .collect();
        assert!(numbers.iter().all(|x| x.is_finite() && *x >= 0.0), "{line}");
        assert!(numbers[2] > 0.0, "wall time: {line}");
        if f[1] == "adaptive" {
            let tol: f64 = f[2].trim_start_matches("tol=").parse().unwrap();
            adaptive
                .entry(f[0].clone())
                .or_default()
                .push((tol, numbers[3]));
        }
        if f[1] == "splitting" || f[1] == "splitting4" {
            // Rotations keep |q| and |L|² to rounding.
            assert!(numbers[7] < 1e-9 && numbers[5] < 1e-9, "{line}");
        }
    }
    assert!(finished >= 50, "{finished} runs finished");
    for case in ["a", "b", "c", "d", "e"] {
        for method in ["exact", "adaptive", "splitting", "splitting4", "rk4"] {
            assert!(
                seen.contains(&(case.to_string(), method.to_string())),
                "no row for case {case}, {method}"
            );
        }
    }
    for (case, mut runs) in adaptive {
        runs.sort_by(|a, b| b.0.total_cmp(&a.0));
        let (loose, tight) = (runs[0].1, runs[runs.len() - 1].1);
        assert!(
            tight * 1e3 < loose,
            "case {case}: error at the tightest tolerance {tight:e} vs loosest {loose:e}"
        );
        // Down to the rounding floor, each tolerance step cuts the error.
        for w in runs.windows(2) {
            if w[0].1 > 1e-9 {
                assert!(w[1].1 < w[0].1, "case {case}: {runs:?}");
            }
        }
    }

    let svg = std::fs::read_to_string(dir.path().join("work_precision.svg")).unwrap();
    assert!(svg.starts_with("<svg"), "{}", &svg[..svg.len().min(200)]);
    assert!(svg.trim_end().ends_with("</svg>"));
    // Well formed: every opened element is closed.
    let opened = svg.matches('<').count() - svg.matches("</").count() * 2;
    let self_closed = svg.matches("/>").count();
    assert_eq!(opened, self_closed, "unbalanced tags");
    for label in ["(a)", "(e)", "adaptive", "splitting4", "rk4", "wall time"] {
        assert!(svg.contains(label), "no {label} in the plot");
    }
    assert!(svg.contains("<text"), "labels are SVG text");
}

#[test]
fn unwritable_output_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("a-file");
    std::fs::write(&file, "x").unwrap();
    let out = Flipcard::without_data()
        .args(["bench", "--quick", "--out"])
        .arg(&file)
        .run();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("output folder"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

const SYSTEMS_HEADER: &str =
    "case,method,setting,steps,rhs_evals,jac_evals,lu_decomps,wall_s,err_state,err_conserved";

#[test]
fn quick_bench_writes_the_systems_csv() {
    let dir = tempfile::tempdir().unwrap();
    let out = Flipcard::without_data()
        .args(["bench", "--quick", "--out"])
        .arg(dir.path())
        .run();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");

    let csv = std::fs::read_to_string(dir.path().join("work_precision_systems.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some(SYSTEMS_HEADER));
    // (case, method) → settings seen, in order.
    let mut settings: BTreeMap<(String, String), Vec<String>> = BTreeMap::new();
    // tol → (err_state, err_conserved) of the pendulum's adaptive runs.
    let mut pendulum: Vec<(f64, f64, f64)> = Vec::new();
    for line in lines {
        let f = fields(line);
        assert_eq!(f.len(), 10, "{line}");
        let key = (f[0].clone(), f[1].clone());
        let setting = f[2].split(" (").next().unwrap().to_string();
        let seen = settings.entry(key).or_default();
        assert!(!seen.contains(&setting), "a duplicate row: {line}");
        seen.push(setting);
        if f[3].is_empty() {
            // Refused, with the reason after the setting.
            assert!(f[2].contains('('), "{line}");
            assert!(f[4..].iter().all(String::is_empty), "{line}");
            continue;
        }
        let numbers: Vec<f64> = f[3..9]
            .iter()
            .map(|x| x.parse::<f64>().unwrap_or_else(|_| panic!("{line}")))
            .collect();
        assert!(numbers.iter().all(|x| x.is_finite() && *x >= 0.0), "{line}");
        assert!(numbers[0] > 0.0 && numbers[4] > 0.0, "steps, wall: {line}");
        let conserved = match f[0].as_str() {
            "vdp" => {
                assert!(f[9].is_empty(), "Van der Pol conserves nothing: {line}");
                None
            }
            _ => Some(f[9].parse::<f64>().unwrap_or_else(|_| panic!("{line}"))),
        };
        if let Some(c) = conserved {
            assert!(c.is_finite() && c >= 0.0, "{line}");
        }
        if f[1] == "radau" {
            assert!(
                numbers[2] > 0.0 && numbers[3] > 0.0,
                "radau uses J and LU: {line}"
            );
        }
        if f[0] == "pendulum" && f[1] == "adaptive" {
            let tol: f64 = f[2].trim_start_matches("tol=").parse().unwrap();
            pendulum.push((tol, numbers[5], conserved.unwrap()));
        }
    }
    for case in ["pendulum", "vdp", "robertson"] {
        for method in ["adaptive", "radau", "rk4", "auto"] {
            let seen = settings.get(&(case.to_string(), method.to_string()));
            assert!(
                seen.is_some_and(|s| !s.is_empty()),
                "no row for {case}, {method}"
            );
        }
        // The stiff cases are solved by radau, each at every tolerance.
        let radau = &settings[&(case.to_string(), "radau".to_string())];
        assert!(radau.len() >= 2, "{case}: {radau:?}");
    }
    // Kepler at e = 0.9 over 100 periods: every method has rows, and at the
    // same step the symplectic ones keep the angular momentum (its drift
    // is part of err_conserved) and verlet4 the energy far better than rk4.
    for method in ["adaptive", "radau", "rk4", "auto", "verlet", "verlet4"] {
        let seen = settings.get(&("kepler".to_string(), method.to_string()));
        assert!(
            seen.is_some_and(|s| !s.is_empty()),
            "no row for kepler, {method}"
        );
    }
    assert!(
        !settings.contains_key(&("vdp".to_string(), "verlet".to_string())),
        "verlet runs only the separable cases"
    );
    let kepler = |method: &str| -> Vec<(String, f64)> {
        csv.lines()
            .map(fields)
            .filter(|f| f[0] == "kepler" && f[1] == method && !f[9].is_empty())
            .map(|f| (f[2].clone(), f[9].parse().unwrap()))
            .collect()
    };
    let (rk4, verlet4) = (kepler("rk4"), kepler("verlet4"));
    let finest = |rows: &[(String, f64)]| rows.last().cloned().unwrap();
    assert_eq!(finest(&rk4).0, finest(&verlet4).0, "{rk4:?} {verlet4:?}");
    assert!(
        finest(&verlet4).1 * 10.0 < finest(&rk4).1,
        "{rk4:?} {verlet4:?}"
    );
    assert!(pendulum.len() >= 3, "{pendulum:?}");
    pendulum.sort_by(|a, b| b.0.total_cmp(&a.0));
    for w in pendulum.windows(2) {
        assert!(
            w[1].1 < w[0].1,
            "error against the exact solution: {pendulum:?}"
        );
    }
    let (loose, tight) = (pendulum[0], pendulum[pendulum.len() - 1]);
    assert!(tight.1 * 1e3 < loose.1, "{pendulum:?}");
    assert!(tight.2 < loose.2, "energy drift: {pendulum:?}");

    let svg = std::fs::read_to_string(dir.path().join("work_precision.svg")).unwrap();
    for label in [
        "(pendulum)",
        "(vdp)",
        "(robertson)",
        "(kepler)",
        "radau",
        "error of the state",
    ] {
        assert!(svg.contains(label), "no {label} in the plot");
    }
}
