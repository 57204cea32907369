//! Deck presets through the real binary: `optimize --deck ID --apply`
//! writes the fitted parameters into the deck's preset (a new one named
//! after the deck when it has none, then the same one again), keeping
//! the config's comments; a config naming an unknown preset is refused
//! with file, line and key before anything opens.

use std::path::Path;

use flipcard::sched::Config;

use crate::support::{Flipcard, Output};

const NOW: &str = "2026-06-10T12:00:00Z";

fn flipcard(data: &Path, config: &Path, args: &[&str]) -> Output {
    Flipcard::new(data).config(config).now(NOW).args(args).run()
}

fn fixture() -> String {
    concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/golden/synthetic_learner.csv"
    )
    .to_string()
}

#[test]
fn optimize_deck_apply_writes_the_decks_preset() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("config.toml");
    let original =
        "# mine\nnew_per_day = 12 # enough\n\n[preset.other]\ndesired_retention = 0.95\n";
    std::fs::write(&config, original).unwrap();
    let imported = flipcard(dir.path(), &config, &["import", "--reviews", &fixture()]);
    assert!(imported.status.success(), "{}", imported.stderr());

    let out = flipcard(
        dir.path(),
        &config,
        // The synthetic learner's fit does not beat the defaults on held-out
        // answers, so the guard would keep them: `--force` writes it.
        &["optimize", "--deck", "synth", "--apply", "--force"],
    );
    assert!(out.status.success(), "{}", out.stderr());
    let said = out.stdout();
    assert!(
        said.contains("as fsrs_parameters of [preset.synth] (a new preset, now deck synth's"),
        "{said}"
    );
    let text = std::fs::read_to_string(&config).unwrap();
    assert!(text.starts_with(original), "{text}");
    let c = Config::load(Some(&config)).unwrap();
    assert_eq!(c.preset_of("synth"), Some("synth"));
    let fitted = c.presets["synth"].fsrs_parameters.expect("fitted");
    assert_ne!(fitted, flipcard::sched::scheduler::default_parameters());
    // The top level keeps the defaults; the deck studies with the fit.
    assert_eq!(c.fsrs_parameters, None);
    assert_eq!(c.for_deck("synth").fsrs_parameters, Some(fitted));
    assert_eq!(c.for_deck("synth").new_per_day, 12);
    assert_eq!(c.presets["other"].desired_retention, Some(0.95));

    // Again, in JSON: the same preset, named in the report.
    let json = flipcard(
        dir.path(),
        &config,
        &["optimize", "--deck", "synth", "--apply", "--format", "json"],
    );
    assert!(json.status.success(), "{}", json.stderr());
    let v: serde_json::Value = serde_json::from_str(&json.stdout()).unwrap();
    // The preset's parameters are now the fit's: the same fit predicts no
    // better than they do, so the guard keeps them ...
    assert_eq!(v["kept_current"], true);
    assert_eq!(v["applied"], false);
    let json = flipcard(
        dir.path(),
        &config,
        &[
            "optimize", "--deck", "synth", "--apply", "--force", "--format", "json",
        ],
    );
    assert!(json.status.success(), "{}", json.stderr());
    let v: serde_json::Value = serde_json::from_str(&json.stdout()).unwrap();
    // ... and `--force` writes it into the same preset.
    assert_eq!(v["applied"], true);
    assert_eq!(v["preset"], "synth");
    let again = std::fs::read_to_string(&config).unwrap();
    assert_eq!(again.matches("[preset.synth]").count(), 1, "{again}");
    assert_eq!(again.matches("[deck.synth]").count(), 1, "{again}");
}

#[test]
fn an_unknown_preset_is_refused_with_file_line_and_key() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("config.toml");
    std::fs::write(
        &config,
        "[preset.fast]\nnew_per_day = 40\n\n[deck.rotation]\npreset = \"fats\"\n",
    )
    .unwrap();
    for args in [&["stats"][..], &["review"][..], &["optimize"][..]] {
        let out = flipcard(dir.path(), &config, args);
        assert!(!out.status.success(), "{args:?}");
        let err = out.stderr();
        assert!(
            err.contains(&format!(
                "{}:5:10: `deck.rotation.preset`: no preset \"fats\"; defined: fast",
                config.display()
            )),
            "{args:?}: {err}"
        );
    }
}
