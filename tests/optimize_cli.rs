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

    let applied = flipcard(dir.path(), &config, &["optimize", "--apply"]);
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
