use std::path::Path;

use proptest::prelude::*;

use super::*;
use crate::sched::config::{Config, ConfigError};

fn parse(text: &str) -> Result<Config, ConfigError> {
    Config::parse(text, Path::new("config.toml"))
}

const FULL: &str = r#"# mine
new_per_day = 15
hide_bundled = true
maximum_interval = 3650

[preset.exam]
new_per_day = 40
reviews_per_day = 900
learning_steps = ["1m", "5m"]
relearning_steps = []
desired_retention = 0.99
maximum_interval = 30

[preset.slow] # for the long haul
desired_retention = 0.8

[deck.rotation]
preset = "exam"

[deck.orbits]
"#;

#[test]
fn presets_and_deck_tables_are_read() {
    let c = parse(FULL).unwrap();
    assert!(c.hide_bundled);
    assert_eq!(c.maximum_interval, 3650);
    let exam = &c.presets["exam"];
    assert_eq!(exam.new_per_day, Some(40));
    assert_eq!(exam.reviews_per_day, Some(900));
    assert_eq!(
        exam.learning_steps,
        Some(vec![TimeDelta::minutes(1), TimeDelta::minutes(5)])
    );
    assert_eq!(exam.relearning_steps, Some(vec![]));
    assert_eq!(exam.desired_retention, Some(0.99));
    assert_eq!(exam.maximum_interval, Some(30));
    assert_eq!(exam.fsrs_parameters, None);
    assert_eq!(c.presets["slow"].desired_retention, Some(0.8));
    assert_eq!(c.preset_of("rotation"), Some("exam"));
    assert_eq!(c.preset_of("orbits"), None);
    assert_eq!(c.preset_of("elsewhere"), None);

    // A deck's settings: its preset over the top level.
    let r = c.for_deck("rotation");
    assert_eq!((r.new_per_day, r.reviews_per_day), (40, 900));
    assert_eq!(r.desired_retention, 0.99);
    assert_eq!(r.maximum_interval, 30);
    assert!(r.relearning_steps.is_empty());
    // What the preset leaves out is the top level's.
    assert_eq!(r.day_starts_at, c.day_starts_at);
    let o = c.for_deck("orbits");
    assert_eq!((o.new_per_day, o.maximum_interval), (15, 3650));
    assert_eq!(o, c);
}

#[test]
fn hostile_preset_values_name_file_line_and_key() {
    let cases = [
        (
            "[preset.a]\ndesired_retention = 0.995\n",
            "config.toml:2:21: `preset.a.desired_retention`: 0.995 is outside 0.70–0.99",
        ),
        (
            "[preset.a]\ndesired_retention = nan\n",
            "`preset.a.desired_retention`: NaN",
        ),
        (
            "[preset.a]\nnew_per_day = -3\n",
            "config.toml:2:15: `preset.a.new_per_day`: -3 is outside 0–10000",
        ),
        (
            "[preset.a]\nreviews_per_day = 100001\n",
            "`preset.a.reviews_per_day`: 100001 is outside 0–100000",
        ),
        (
            "[preset.a]\nmaximum_interval = 0\n",
            "`preset.a.maximum_interval`: 0 is outside 1–36500 days",
        ),
        (
            "maximum_interval = 36501\n",
            "config.toml:1:20: `maximum_interval`: 36501 is outside 1–36500 days",
        ),
        (
            "[preset.a]\nlearning_steps = [\"1m\", \"9y\"]\n",
            "config.toml:2:25: `preset.a.learning_steps[1]`",
        ),
        (
            "[preset.a]\nfsrs_parameters = [1.0]\n",
            "`preset.a.fsrs_parameters`: 1 numbers; FSRS-6 has 21",
        ),
        (
            "[preset.\"two words\"]\nnew_per_day = 1\n",
            "`preset.two words`: \"two words\" is not a preset name",
        ),
        (
            "[preset.a]\n[deck.rotation]\npreset = \"b\"\n",
            "config.toml:3:10: `deck.rotation.preset`: no preset \"b\"; defined: a",
        ),
        (
            "[deck.rotation]\npreset = \"b\"\n",
            "no preset \"b\"; define it as a [preset.NAME] table",
        ),
        ("[deck.\"Not An Id\"]\n", "`deck.Not An Id`: not a deck id"),
        (
            "[preset.a]\nnew_per_day = 1\n[deck.x]\npreset = \"a\\u001b[31m\"\n",
            "no preset \"a\\u001b[31m\"",
        ),
    ];
    for (text, want) in cases {
        let msg = parse(text).unwrap_err().to_string();
        assert!(msg.contains(want), "{text:?} gave {msg:?}, wanted {want:?}");
        assert!(msg.starts_with("config.toml:"), "{msg}");
        assert!(!msg.contains('\u{1b}'), "{msg:?}");
    }
    // An unknown key in a preset is named with its line, as at the top.
    let msg = parse("[preset.a]\nnew_per_dya = 3\n")
        .unwrap_err()
        .to_string();
    assert!(
        msg.contains("new_per_dya") && msg.contains("line 2"),
        "{msg}"
    );
    let msg = parse("[deck.x]\npreset = \"a\"\ncolour = 1\n")
        .unwrap_err()
        .to_string();
    assert!(msg.contains("colour") && msg.contains("line 3"), "{msg}");
    // Wrong types are parse errors, not defaults.
    for text in [
        "[preset.a]\nnew_per_day = \"ten\"\n",
        "preset = 3\n",
        "[deck.x]\npreset = 3\n",
        "hide_bundled = \"yes\"\n",
    ] {
        assert!(
            matches!(parse(text), Err(ConfigError::Parse { .. })),
            "{text}"
        );
    }
}

#[test]
fn save_writes_presets_keeping_comments_and_other_keys() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("config.toml");
    std::fs::write(&path, FULL).unwrap();
    let mut c = Config::load(Some(&path)).unwrap();
    c.presets.get_mut("slow").unwrap().new_per_day = Some(3);
    c.presets.insert(
        "fresh".into(),
        Preset {
            maximum_interval: Some(90),
            ..Preset::default()
        },
    );
    c.decks.insert(
        "orbits".into(),
        DeckSettings {
            preset: Some("fresh".into()),
        },
    );
    // A new top-level key must not land in the last table.
    c.fuzz = false;
    c.save(&path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.starts_with("# mine\nnew_per_day = 15\n"), "{text}");
    assert!(
        text.contains(
            "[preset.slow] # for the long haul\ndesired_retention = 0.8\nnew_per_day = 3\n"
        ),
        "{text}"
    );
    assert!(
        text.contains("[preset.fresh]\nmaximum_interval = 90\n"),
        "{text}"
    );
    assert!(
        text.contains("[deck.orbits]\npreset = \"fresh\"\n"),
        "{text}"
    );
    let fuzz = text.find("fuzz = false").unwrap();
    assert!(fuzz < text.find("[preset.exam]").unwrap(), "{text}");
    assert_eq!(Config::load(Some(&path)).unwrap(), c);

    // One key of one preset, as `optimize --apply --deck` writes it.
    let w = crate::sched::scheduler::default_parameters();
    c.presets.get_mut("exam").unwrap().fsrs_parameters = Some(w);
    c.save_preset_key(&path, "exam", "fsrs_parameters").unwrap();
    let again = std::fs::read_to_string(&path).unwrap();
    assert!(
        again.starts_with(&text[..text.find("[preset.slow]").unwrap()].replace(
            "maximum_interval = 30\n",
            &format!(
            "maximum_interval = 30\nfsrs_parameters = {}\n",
            Preset {
                fsrs_parameters: Some(w),
                ..Preset::default()
            }
            .value_of("fsrs_parameters")
            .unwrap()
        )
        ))
    );
    assert_eq!(Config::load(Some(&path)).unwrap(), c);
    assert!(matches!(
        c.save_preset_key(&path, "nope", "new_per_day"),
        Err(ConfigError::UnknownKey(_))
    ));
}

#[test]
fn a_top_level_key_saved_after_tables_stays_top_level() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("config.toml");
    std::fs::write(&path, "[preset.a]\nnew_per_day = 1\n").unwrap();
    let mut c = Config::load(Some(&path)).unwrap();
    c.language = "hi-Latn".into();
    c.save_key(&path, "language").unwrap();
    let back = Config::load(Some(&path)).unwrap();
    assert_eq!(back.language, "hi-Latn");
    assert_eq!(back.presets["a"].new_per_day, Some(1));
}

fn step() -> impl Strategy<Value = TimeDelta> {
    prop_oneof![
        (1i64..=3600).prop_map(TimeDelta::seconds),
        (1i64..=365).prop_map(TimeDelta::days),
    ]
}

fn preset() -> impl Strategy<Value = Preset> {
    (
        proptest::option::of(0u32..=10_000),
        proptest::option::of(0u32..=100_000),
        proptest::option::of(proptest::collection::vec(step(), 0..4)),
        proptest::option::of(proptest::collection::vec(step(), 0..3)),
        proptest::option::of(70u32..=99),
        proptest::option::of(1u32..=MAX_INTERVAL_DAYS),
        proptest::bool::ANY,
    )
        .prop_map(|(n, r, l, rl, ret, max, fitted)| Preset {
            new_per_day: n,
            reviews_per_day: r,
            learning_steps: l,
            relearning_steps: rl,
            desired_retention: ret.map(|x| f64::from(x) / 100.0),
            maximum_interval: max,
            fsrs_parameters: fitted.then(crate::sched::scheduler::default_parameters),
        })
}

fn name() -> impl Strategy<Value = String> {
    "[a-zA-Z0-9_-]{1,12}"
}

fn config() -> impl Strategy<Value = Config> {
    (
        proptest::collection::btree_map(name(), preset(), 0..4),
        proptest::collection::vec("[a-z0-9]{1,6}(-[a-z0-9]{1,4})?", 0..4),
        1u32..=MAX_INTERVAL_DAYS,
        proptest::bool::ANY,
    )
        .prop_map(|(presets, decks, max, hide)| {
            let names: Vec<String> = presets.keys().cloned().collect();
            let decks = decks
                .into_iter()
                .enumerate()
                .map(|(i, id)| {
                    let preset = (!names.is_empty()).then(|| names[i % names.len()].clone());
                    (id, DeckSettings { preset })
                })
                .collect();
            Config {
                maximum_interval: max,
                hide_bundled: hide,
                presets,
                decks,
                ..Config::default()
            }
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// The config as a file reads back as itself.
    #[test]
    fn display_round_trips(c in config()) {
        prop_assert_eq!(parse(&c.to_string()).unwrap(), c);
    }

    /// Saving over a commented file keeps the comments and reads back.
    #[test]
    fn save_then_load_round_trips(c in config(), first in config()) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("config.toml");
        let original = format!("# keep me\n{first}# and me\n");
        std::fs::write(&path, &original).unwrap();
        // What the file had stays unless `c` sets it: start from it.
        let mut want = Config::load(Some(&path)).unwrap();
        want.maximum_interval = c.maximum_interval;
        want.hide_bundled = c.hide_bundled;
        for (n, p) in &c.presets {
            let mine = want.presets.entry(n.clone()).or_default();
            for key in PRESET_KEYS {
                if p.value_of(key).is_some() {
                    match key {
                        "new_per_day" => mine.new_per_day = p.new_per_day,
                        "reviews_per_day" => mine.reviews_per_day = p.reviews_per_day,
                        "learning_steps" => mine.learning_steps.clone_from(&p.learning_steps),
                        "relearning_steps" => mine.relearning_steps.clone_from(&p.relearning_steps),
                        "desired_retention" => mine.desired_retention = p.desired_retention,
                        "maximum_interval" => mine.maximum_interval = p.maximum_interval,
                        _ => mine.fsrs_parameters = p.fsrs_parameters,
                    }
                }
            }
        }
        for (id, d) in &c.decks {
            if d.preset.is_some() {
                want.decks.insert(id.clone(), d.clone());
            } else {
                want.decks.entry(id.clone()).or_default();
            }
        }
        want.save(&path).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        prop_assert!(text.starts_with("# keep me\n"), "{}", text);
        prop_assert!(text.contains("# and me"), "{}", text);
        let back = Config::load(Some(&path)).unwrap();
        // A deck table without a preset that the file lacked is not written.
        want.decks.retain(|id, d| d.preset.is_some() || back.decks.contains_key(id));
        prop_assert_eq!(back, want);
    }

    /// Any text: an error or a config, never a panic; a preset value out of
    /// its range is refused at its key.
    #[test]
    fn hostile_text_never_panics(text in "(\\[(preset|deck)\\.[a-z\"]{1,4}\\]\n|[a-z_]{1,18} = (-?[0-9]{1,7}(\\.[0-9]{1,3})?|\"[a-z0-9 ]{0,5}\"|\\[\\]|nan|inf)\n){0,8}") {
        let _ = parse(&text);
    }

    #[test]
    fn preset_retention_outside_range_is_refused(r in prop_oneof![0.0f64..0.6999, 0.99001f64..5.0]) {
        let msg = parse(&format!("[preset.p]\ndesired_retention = {r:?}\n")).unwrap_err().to_string();
        prop_assert!(msg.starts_with("config.toml:2:21: `preset.p.desired_retention`"), "{}", msg);
    }
}
