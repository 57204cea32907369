//! `flipcard optimize` through the real binary, on the synthetic learner's
//! log (`tests/golden/synthetic_learner.csv`, made by
//! `tests/golden/gen_synthetic_learner.py`): the JSON contract, `--apply`
//! writing the parameters into the config with its comments kept, the
//! scheduler and stats using them, and too little data changing nothing.

use std::path::Path;

use flipcard::sched::Config;
use flipcard::sched::config::PARAMETER_BOUNDS;

use crate::support::{Flipcard, Output};

const NOW: &str = "2026-06-10T12:00:00Z";

fn flipcard(data: &Path, config: &Path, args: &[&str]) -> Output {
    Flipcard::new(data).config(config).now(NOW).args(args).run()
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

fn fixture() -> String {
    concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/golden/synthetic_learner.csv"
    )
    .to_string()
}

#[test]
fn optimize_fits_reports_and_applies() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("config.toml");
    let original = "# my settings\nlanguage = \"hi-Latn\" # for my sister\n";
    std::fs::write(&config, original).unwrap();
    let imported = flipcard(dir.path(), &config, &["import", "--reviews", &fixture()]);
    assert!(imported.status.success(), "{}", imported.stderr());

    let out = flipcard(dir.path(), &config, &["optimize", "--format", "json"]);
    assert!(out.status.success(), "{}", out.stderr());
    let stdout = out.stdout();
    assert_eq!(stdout.lines().count(), 1, "exactly one object: {stdout}");
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(v["reviews"], 2779);
    assert_eq!(v["cards"], 300);
    assert_eq!(v["applied"], false);
    for which in ["default", "fitted"] {
        for metric in ["log_loss", "rmse_bins"] {
            let x = v[which][metric].as_f64().expect(metric);
            assert!(x > 0.0 && x < 1.0, "{which}.{metric} = {x}");
        }
    }
    let params: Vec<f64> = v["parameters"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p.as_f64().unwrap())
        .collect();
    assert_eq!(params.len(), 21);
    for (i, (p, (lo, hi))) in params.iter().zip(PARAMETER_BOUNDS).enumerate() {
        assert!((lo..=hi).contains(p), "w{i} = {p}");
    }
    assert_ne!(params, flipcard::sched::scheduler::default_parameters());
    assert_eq!(std::fs::read_to_string(&config).unwrap(), original);

    let human = flipcard(dir.path(), &config, &["optimize"]);
    let human_text = human.stdout();
    assert!(
        human_text.starts_with("fitted FSRS-6 to 2779 reviews of 300 cards"),
        "{human_text}"
    );
    assert!(human_text.contains("not applied"), "{human_text}");

    // This fit predicts the held-out reviews worse than the defaults in
    // use (see `apply_keeps_the_current_parameters_unless_the_fit_is_better`):
    // `--force` writes it.
    let applied = flipcard(dir.path(), &config, &["optimize", "--apply", "--force"]);
    assert!(applied.status.success(), "{}", applied.stderr());
    assert!(applied.stdout().contains("applied: written to"));
    let written = std::fs::read_to_string(&config).unwrap();
    assert!(written.starts_with(original), "{written}");
    let loaded = Config::load(Some(&config)).unwrap();
    assert_eq!(loaded.language, "hi-Latn");
    let fitted = loaded.fsrs_parameters.expect("fitted parameters");
    assert_eq!(fitted.to_vec(), params, "the same fit, deterministic");
    assert_eq!(
        loaded.fsrs_fitted_at.map(|t| t.to_rfc3339()),
        Some("2026-06-10T12:00:00+00:00".into())
    );

    let stats = flipcard(dir.path(), &config, &["stats", "--json"]);
    let s: serde_json::Value = serde_json::from_slice(&stats.stdout).unwrap();
    assert_eq!(s["fsrs_parameters"]["source"], "fitted");
    assert_eq!(
        s["fsrs_parameters"]["fitted_at"],
        "2026-06-10T12:00:00+00:00"
    );
    let text_stats = text(&flipcard(dir.path(), &config, &["stats"]).stdout);
    assert!(
        text_stats.contains("FSRS parameters: fitted to your reviews on 2026-06-10"),
        "{text_stats}"
    );

    // A bad hand edit is refused with its place.
    let broken = written.replace("fsrs_parameters = [", "fsrs_parameters = [1000.0, ");
    std::fs::write(&config, &broken).unwrap();
    let refused = flipcard(dir.path(), &config, &["stats"]);
    assert_eq!(refused.status.code(), Some(1));
    let msg = refused.stderr();
    assert!(
        msg.contains(&format!("{}:3:", config.display())) && msg.contains("fsrs_parameters"),
        "{msg}"
    );
}

#[test]
fn too_few_reviews_change_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("config.toml");
    let small = dir.path().join("small.csv");
    let all = std::fs::read_to_string(fixture()).unwrap();
    let head: Vec<&str> = all.lines().take(120).collect();
    std::fs::write(&small, head.join("\n") + "\n").unwrap();
    assert!(
        flipcard(
            dir.path(),
            &config,
            &["import", "--reviews", small.to_str().unwrap()]
        )
        .status
        .success()
    );
    for format in ["text", "json"] {
        let out = flipcard(
            dir.path(),
            &config,
            &["optimize", "--apply", "--format", format],
        );
        assert!(out.status.success(), "{}", out.stderr());
        let s = out.stdout();
        if format == "json" {
            let v: serde_json::Value = serde_json::from_str(&s).unwrap();
            assert_eq!(v["applied"], false);
            let needed = v["needed"].as_u64().unwrap();
            assert!(needed > 0 && needed <= 64, "{s}");
            assert_eq!(v["parameters"], serde_json::Value::Null);
        } else {
            assert!(s.starts_with("not enough reviews to fit FSRS"), "{s}");
            assert!(s.contains("more (answered on a later day"), "{s}");
        }
    }
    assert!(!config.exists(), "no config written");
    let unknown = flipcard(dir.path(), &config, &["optimize", "--deck", "nope"]);
    assert_eq!(unknown.status.code(), Some(1));
    assert!(unknown.stderr().contains("no reviews of deck `nope`"));
}

/// `--apply` compares the fit with the parameters in use on the same
/// held-out answers and keeps them unless the fit's log loss is lower
/// (as Anki does), unless `--force`.
#[test]
fn apply_keeps_the_current_parameters_unless_the_fit_is_better() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("config.toml");
    std::fs::write(&config, "# mine\n").unwrap();
    let imported = flipcard(dir.path(), &config, &["import", "--reviews", &fixture()]);
    assert!(imported.status.success(), "{}", imported.stderr());

    // The defaults in use predict the held-out answers better than the fit.
    let json = |args: &[&str]| -> serde_json::Value {
        let out = flipcard(dir.path(), &config, args);
        assert!(out.status.success(), "{}", out.stderr());
        serde_json::from_str(&out.stdout()).unwrap()
    };
    let v = json(&["optimize", "--apply", "--format", "json"]);
    let loss = |v: &serde_json::Value, which: &str| v[which]["log_loss"].as_f64().unwrap();
    assert_eq!(
        v["current"], v["default"],
        "nothing fitted yet: the defaults are in use"
    );
    assert!(loss(&v, "fitted") >= loss(&v, "current"), "{v}");
    assert_eq!(
        (v["applied"].as_bool(), v["kept_current"].as_bool()),
        (Some(false), Some(true))
    );
    assert_eq!(std::fs::read_to_string(&config).unwrap(), "# mine\n");
    let out = flipcard(dir.path(), &config, &["optimize", "--apply"]);
    let said = out.stdout();
    assert!(
        said.contains("kept the current parameters: the fit predicts the held-out reviews no better (log loss 0.3222 against 0.3139)"),
        "{said}"
    );
    assert!(said.contains("--apply --force"), "{said}");
    assert_eq!(std::fs::read_to_string(&config).unwrap(), "# mine\n");

    // Forced, the fit is written; from then on it is the current one,
    // judged on the same answers.
    let v = json(&["optimize", "--apply", "--force", "--format", "json"]);
    assert_eq!(
        (v["applied"].as_bool(), v["kept_current"].as_bool()),
        (Some(true), Some(false))
    );
    assert!(
        Config::load(Some(&config))
            .unwrap()
            .fsrs_parameters
            .is_some()
    );
    let v = json(&["optimize", "--format", "json"]);
    assert_ne!(v["current"], v["default"], "{v}");
    let table = flipcard(dir.path(), &config, &["optimize"]).stdout();
    assert!(table.contains("\n  current "), "{table}");

    // --force alone is refused: it only qualifies --apply.
    let refused = flipcard(dir.path(), &config, &["optimize", "--force"]);
    assert_eq!(refused.status.code(), Some(2));
    assert!(refused.stderr().contains("--apply"), "{}", refused.stderr());
}

/// A learner whose every pass is Easy: the fit beats the defaults on the
/// held-out answers, so `--apply` writes it, and the parameters the data
/// pushed to a bound of their range are named.
#[test]
fn a_better_fit_is_applied_and_a_pinned_parameter_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("config.toml");
    let easy = dir.path().join("easy.csv");
    let all = std::fs::read_to_string(fixture()).unwrap();
    let mut lines = all.lines();
    let mut text = format!("{}\n", lines.next().unwrap());
    for line in lines {
        let (head, rating) = line.rsplit_once(',').unwrap();
        let rating = if rating == "1" { "1" } else { "4" };
        text.push_str(&format!("{head},{rating}\n"));
    }
    std::fs::write(&easy, text).unwrap();
    let imported = flipcard(
        dir.path(),
        &config,
        &["import", "--reviews", easy.to_str().unwrap()],
    );
    assert!(imported.status.success(), "{}", imported.stderr());

    let out = flipcard(
        dir.path(),
        &config,
        &["optimize", "--apply", "--format", "json"],
    );
    assert!(out.status.success(), "{}", out.stderr());
    let v: serde_json::Value = serde_json::from_str(&out.stdout()).unwrap();
    assert_eq!(
        (v["applied"].as_bool(), v["kept_current"].as_bool()),
        (Some(true), Some(false))
    );
    let params = v["parameters"].as_array().unwrap();
    let pinned = v["pinned"].as_array().unwrap();
    assert!(!pinned.is_empty(), "{v}");
    for p in pinned {
        let i = p["index"].as_u64().unwrap() as usize;
        let (lo, hi) = PARAMETER_BOUNDS[i];
        let bound = if p["bound"] == "upper" { hi } else { lo };
        assert_eq!(p["value"].as_f64(), Some(bound), "{p}");
        assert_eq!(params[i].as_f64(), Some(bound), "{p}");
    }
    assert!(
        pinned
            .iter()
            .any(|p| p["index"] == 7 && p["bound"] == "lower"),
        "{v}"
    );

    let text = flipcard(dir.path(), &config, &["optimize"]).stdout();
    assert!(
        text.contains("pinned: w7 (pull of difficulty back to its start) = 0.001 at the lower bound of 0.001–0.75"),
        "{text}"
    );
}
