//! What a system scene declares conserved, through the binary: `sim`
//! reports each quantity's largest drift over the run (the JSON's
//! `stats.conserved`, the `--stats` line), every method is stopped when one
//! moves by more than its own size, RK4 is refused past its stability
//! bound, and the symplectic methods (`verlet`, `verlet4`) run only a scene
//! that declares a separable `hamiltonian`, keeping Kepler's energy bounded
//! over 100 periods where RK4 at the same step drifts.

use crate::support::Flipcard;

/// Runs `flipcard args`: exit code, stdout, stderr.
fn run(args: &[&str]) -> (i32, String, String) {
    let out = Flipcard::without_data().args(args).run();
    (out.status.code().unwrap_or(-1), out.stdout(), out.stderr())
}

/// A deck with one system scene `s` (`scene` is its body after the id) in
/// a temporary folder; the folder and the deck file's path.
fn deck(scene: &str) -> (tempfile::TempDir, String) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("decks")).unwrap();
    std::fs::create_dir_all(dir.path().join("content/k")).unwrap();
    std::fs::write(dir.path().join("content/k/en.toml"), "").unwrap();
    let text = format!(
        "[deck]\nid = \"k\"\ntitle = 'T'\nlanguages = [\"en\"]\n\n[[card]]\nid = \"c\"\nfront = 'F'\nback = 'B'\n\n[[scene]]\nid = \"s\"\n{scene}"
    );
    let path = dir.path().join("decks/k.toml");
    std::fs::write(&path, text).unwrap();
    (dir, path.to_str().unwrap().to_string())
}

/// Kepler's orbit (GM = 1, semi-major axis 1, period 2π, H = −1/2) of
/// eccentricity `e` from pericentre over `periods` periods, declaring H
/// and L conserved and, with `hamiltonian`, the separable split.
fn kepler(e: f64, periods: f64, hamiltonian: bool) -> String {
    let v = ((1.0 + e) / (1.0 - e)).sqrt();
    format!(
        "variables = [\"x\", \"y\", \"vx\", \"vy\"]\ninitial = [{}, 0.0, 0.0, {v:?}]\nequations = [\"vx\", \"vy\", \"-x/(x^2 + y^2)^1.5\", \"-y/(x^2 + y^2)^1.5\"]\nobservables = {{ H = \"0.5*(vx^2 + vy^2) - 1/sqrt(x^2 + y^2)\", L = \"x*vy - y*vx\" }}\nconserved = [\"H\", \"L\"]\n{}duration = {:?}\nshow = [\"plot\"]\nplot = [\"x\"]\n",
        1.0 - e,
        if hamiltonian {
            "hamiltonian = { q = [\"x\", \"y\"], p = [\"vx\", \"vy\"] }\n"
        } else {
            ""
        },
        periods * std::f64::consts::TAU
    )
}

/// The sampled run as JSON, parsed (it must be well formed whatever the
/// exit code), with the exit code.
fn json(path: &str, args: &[&str]) -> (i32, serde_json::Value, String) {
    let mut all = vec!["sim", "--deck", path, "--scene", "s", "--format", "json"];
    all.extend_from_slice(args);
    let (code, out, err) = run(&all);
    let v = serde_json::from_str(&out).unwrap_or_else(|e| panic!("{e}: {out}{err}"));
    (code, v, err)
}

/// `stats.conserved`'s (max_change, max_drift) of `name`.
fn drift(v: &serde_json::Value, name: &str) -> (f64, f64) {
    let list = v["stats"]["conserved"]
        .as_array()
        .unwrap_or_else(|| panic!("no stats.conserved: {v}"));
    let c = list
        .iter()
        .find(|c| c["name"] == name)
        .unwrap_or_else(|| panic!("no {name} in {v}"));
    (
        c["max_change"].as_f64().unwrap(),
        c["max_drift"].as_f64().unwrap(),
    )
}

#[test]
fn sampled_runs_report_each_conserved_quantitys_largest_drift() {
    // Kepler at e = 0.9 over 100 periods with auto at its default
    // tolerance: H and L drift by a few millionths, and the drift covers
    // every sample the run computed, so at least the rows printed.
    let (_dir, path) = deck(&kepler(0.9, 100.0, false));
    let (code, v, err) = json(&path, &["--samples", "11"]);
    assert_eq!(code, 0, "{err}");
    let (change, rel) = drift(&v, "H");
    assert!(rel > 1e-9 && rel < 1e-4, "{v}");
    assert!((rel - change / 0.5).abs() < 1e-12 * rel.max(1.0), "{v}");
    for row in v["samples"].as_array().unwrap() {
        let h = row["H"].as_f64().unwrap();
        assert!((h + 0.5).abs() <= change * (1.0 + 1e-12), "{h} vs {change}");
    }
    let (_, l_rel) = drift(&v, "L");
    assert!(l_rel > 0.0 && l_rel < 1e-4, "{v}");
    assert_eq!(v["stats"]["conserved"][0]["start"], -0.5);
    // The CSV's --stats line says the same.
    let (code, _, err) = run(&[
        "sim",
        "--deck",
        &path,
        "--scene",
        "s",
        "--samples",
        "3",
        "--stats",
    ]);
    assert_eq!(code, 0, "{err}");
    let line = err.lines().find(|l| l.starts_with("stats:")).unwrap();
    assert!(line.contains(", H drifts by up to "), "{line}");
    assert!(line.contains(" of its start, L drifts by up to "), "{line}");
    // A scene that declares nothing conserved has no such field.
    let (_d2, plain) = deck(
        "variables = [\"x\"]\ninitial = [1.0]\nequations = [\"-x\"]\nduration = 1.0\nshow = [\"plot\"]\nplot = [\"x\"]\n",
    );
    let (_, v, _) = json(&plain, &["--samples", "2"]);
    assert!(v["stats"].get("conserved").is_none(), "{v}");
}

#[test]
fn rk4_losing_keplers_energy_is_stopped_and_says_how_far_it_drifted() {
    // e = 0.99: the default step (20,000 over the run) is past RK4's
    // stability bound at pericentre, and a step just within it takes H
    // from −0.5 to positive (an orbit that escapes) in one pass: both are
    // refused, never printed, the JSON closed with the reason.
    let (_dir, path) = deck(&kepler(0.99, 100.0, false));
    let (code, v, _) = json(&path, &["--samples", "3", "--method", "rk4"]);
    assert_eq!(code, 1);
    let why = v["error"].as_str().unwrap();
    assert!(
        why.contains("rk4 with dt = 0.0314") && why.contains("is unstable here"),
        "{why}"
    );
    let (code, v, _) = json(
        &path,
        &["--samples", "3", "--method", "rk4", "--dt", "0.0019"],
    );
    assert_eq!(code, 1);
    let why = v["error"].as_str().unwrap();
    assert!(
        why.contains("`H`, declared conserved, went from -0.5000 at the start to"),
        "{why}"
    );
    assert_eq!(v["samples"].as_array().unwrap().len(), 1, "only t = 0: {v}");
    let (_, rel) = drift(&v, "H");
    assert!(rel > 1.0, "the drift that stopped it: {v}");
}

#[test]
fn rk4_past_its_stability_bound_is_refused() {
    // x' = −100x at dt = 0.03: dt·rate = 3 > 2.78, where RK4 printed 1.1e11
    // for an answer of 3e-109.
    let (_dir, path) = deck(
        "variables = [\"x\"]\ninitial = [1.0]\nequations = [\"-100*x\"]\nduration = 2.5\nshow = [\"plot\"]\nplot = [\"x\"]\n",
    );
    let (code, out, err) = run(&[
        "sim",
        "--deck",
        &path,
        "--scene",
        "s",
        "--samples",
        "3",
        "--method",
        "rk4",
        "--dt",
        "0.03",
    ]);
    assert_eq!(code, 1, "{out}");
    assert_eq!(out, "t,x\n0,1\n");
    assert!(
        err.contains("rk4 with dt = 0.03 is unstable here: near t = 0 the system's fastest rate is about 100 per time unit, and rk4 is stable only while dt·rate < 2.78"),
        "{err}"
    );
    let (code, out, err) = run(&[
        "sim",
        "--deck",
        &path,
        "--scene",
        "s",
        "--samples",
        "3",
        "--method",
        "rk4",
        "--dt",
        "0.02",
    ]);
    assert_eq!(code, 0, "{err}");
    let last: f64 = out
        .lines()
        .last()
        .unwrap()
        .split(',')
        .nth(1)
        .unwrap()
        .parse()
        .unwrap();
    // Stable: each step multiplies x by R(−2) = 1/3 (e^−2 exactly), so x
    // decays, to 3^−125 ≈ 2e-60 at t = 2.5.
    assert!(last > 0.0 && last < 1e-55, "{out}");
}

#[test]
fn verlet_needs_a_declared_separable_hamiltonian() {
    let (_dir, path) = deck(&kepler(0.9, 1.0, false));
    for method in ["verlet", "verlet4"] {
        let (code, out, err) = run(&[
            "sim",
            "--deck",
            &path,
            "--scene",
            "s",
            "--samples",
            "3",
            "--method",
            method,
        ]);
        assert_eq!(code, 1, "{out}");
        assert_eq!(
            err.trim_end(),
            format!(
                "flipcard: error: {method} needs a separable Hamiltonian: scene s declares none (`hamiltonian = {{ q = [...], p = [...] }}`, positions and their momenta); use rk4 or auto"
            )
        );
    }
    let (_d2, with) = deck(&kepler(0.9, 1.0, true));
    let (code, _, err) = run(&[
        "sim",
        "--deck",
        &with,
        "--scene",
        "s",
        "--samples",
        "3",
        "--method",
        "verlet",
        "--tol",
        "1e-6",
    ]);
    assert_eq!(code, 1);
    assert!(
        err.contains("--tol: verlet takes a step (--dt), not a tolerance"),
        "{err}"
    );
    let (code, out, err) = run(&[
        "sim",
        "--deck",
        &with,
        "--scene",
        "s",
        "--samples",
        "3",
        "--method",
        "verlet4",
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(out.lines().count(), 4, "{out}");
}

#[test]
fn verlet_keeps_keplers_energy_bounded_where_rk4_at_the_same_step_drifts() {
    // e = 0.9 at 1,000 steps a period: over 10 and over 100 periods.
    let dt = format!("{:?}", std::f64::consts::TAU / 1000.0);
    let (_d10, ten) = deck(&kepler(0.9, 10.0, true));
    let (_d100, hundred) = deck(&kepler(0.9, 100.0, true));
    let h_drift = |path: &str, method: &str| {
        let (code, v, err) = json(path, &["--samples", "2", "--method", method, "--dt", &dt]);
        assert_eq!(code, 0, "{method}: {err}");
        (drift(&v, "H").1, drift(&v, "L").1)
    };
    let (v10, v100) = (h_drift(&ten, "verlet"), h_drift(&hundred, "verlet"));
    let (r10, r100) = (h_drift(&ten, "rk4"), h_drift(&hundred, "rk4"));
    // Verlet's energy error is the same over 100 periods as over 10: it
    // oscillates (largest at pericentre, ~0.1 at this step) and does not
    // grow; RK4's grows with the number of orbits.
    assert!(v100.0 < 1.2 * v10.0, "verlet: {v10:?} → {v100:?}");
    assert!(r100.0 > 5.0 * r10.0, "rk4: {r10:?} → {r100:?}");
    // Störmer–Verlet keeps the angular momentum of a central force to
    // rounding; RK4 does not.
    assert!(v100.1 < 1e-12 && r100.1 > 1e-5, "L: {v100:?}, {r100:?}");
}

mod hamiltonian_key {
    //! Property: any `hamiltonian` a scene declares (names drawn from its
    //! variables and from elsewhere, repeated, missing, or not a list; the
    //! equations separable or not) loads without a panic, and the deck is
    //! accepted exactly when the declaration names every variable once, as
    //! many positions as momenta, and the equations split by it; a refused
    //! declaration is an error at a real place of the file. The default
    //! 256 cases take a second or two; for a longer search:
    //!
    //! ```sh
    //! PROPTEST_CASES=20000 cargo test --test main system_conserved::hamiltonian_key
    //! ```

    use proptest::prelude::*;

    const VARS: [&str; 4] = ["x", "y", "vx", "vy"];
    /// Equations of each variable, with the variables each reads.
    const EQUATIONS: [[(&str, &[&str]); 3]; 4] = [
        [
            ("vx", &["vx"]),
            ("vx + 0*x", &["vx", "x"]),
            ("vy*vx", &["vx", "vy"]),
        ],
        [("vy", &["vy"]), ("vy - y", &["vy", "y"]), ("2", &[])],
        [
            ("-x/(x^2 + y^2 + 1)^1.5", &["x", "y"]),
            ("-x - vx", &["x", "vx"]),
            ("-x", &["x"]),
        ],
        [
            ("-y/(x^2 + y^2 + 1)^1.5", &["x", "y"]),
            ("t - y", &["y"]),
            ("-vy*y", &["y", "vy"]),
        ],
    ];
    const NAMES: [&str; 7] = ["x", "y", "vx", "vy", "z", "X", "t"];

    fn cases() -> u32 {
        std::env::var("PROPTEST_CASES")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(256)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(cases()))]

        #[test]
        fn any_declaration_is_accepted_exactly_when_it_splits_the_equations(
            eqs in proptest::collection::vec(0usize..3, 4),
            q in proptest::collection::vec(0usize..NAMES.len(), 0..4),
            p in proptest::collection::vec(0usize..NAMES.len(), 0..4),
            shape in 0u8..4,
            perm in Just(vec![0usize, 1, 2, 3]).prop_shuffle(),
            proper in any::<bool>(),
        ) {
            // Half the cases name each variable once, two and two, so
            // that separability itself decides.
            let (q, p) = match proper {
                true => (perm[..2].to_vec(), perm[2..].to_vec()),
                false => (q, p),
            };
            let equations: Vec<&str> = (0..4).map(|k| EQUATIONS[k][eqs[k]].0).collect();
            let list = |v: &[usize]| {
                let names: Vec<String> = v.iter().map(|&i| format!("{:?}", NAMES[i])).collect();
                format!("[{}]", names.join(", "))
            };
            let declared = match shape {
                0 => format!("{{ q = {}, p = {} }}", list(&q), list(&p)),
                1 => format!("{{ q = {} }}", list(&q)),
                2 => format!("{{ q = {}, p = {}, r = [\"x\"] }}", list(&q), list(&p)),
                _ => list(&q),
            };
            let body = format!(
                "variables = [\"x\", \"y\", \"vx\", \"vy\"]\ninitial = [1.0, 0.0, 0.0, 1.0]\nequations = [{}]\nhamiltonian = {declared}\nduration = 1.0\nshow = [\"plot\"]\nplot = [\"x\"]\n",
                equations.iter().map(|e| format!("{e:?}")).collect::<Vec<_>>().join(", ")
            );
            let (dir, _) = super::deck(&body);
            let loaded = flipcard::deck::load_dir(&dir.path().join("decks"));
            let _ = loaded.render_all();
            let (qn, pn): (Vec<&str>, Vec<&str>) = (
                q.iter().map(|&i| NAMES[i]).collect(),
                p.iter().map(|&i| NAMES[i]).collect(),
            );
            let each_once = VARS.iter().all(|v| qn.iter().chain(&pn).filter(|n| *n == v).count() == 1)
                && qn.len() + pn.len() == 4;
            // The variables the equation of `v` reads (`v` a variable).
            let reads = |v: &str| {
                let k = VARS.iter().position(|x| *x == v).unwrap();
                EQUATIONS[k][eqs[k]].1
            };
            let splits = || {
                qn.iter().all(|v| reads(v).iter().all(|r| !qn.contains(r)))
                    && pn.iter().all(|v| reads(v).iter().all(|r| !pn.contains(r)))
            };
            let valid = shape == 0 && each_once && qn.len() == pn.len() && splits();
            prop_assert_eq!(loaded.errors() == 0, valid, "{}\n{}", body, loaded.render_all());
            for d in &loaded.diagnostics {
                prop_assert!(d.line >= 1 && d.col >= 1, "{}", d.headline());
            }
        }
    }
}
