//! Fixtures for the terminal tests: a small bilingual deck, a fixed clock,
//! and rendering to a test backend.

use std::collections::BTreeMap;
use std::path::PathBuf;

use chrono::{DateTime, Utc};
use ratatui::Terminal;
use ratatui::backend::TestBackend;

use crate::deck::{
    Answer, Card, CardKind, Choice, Cmp, Condition, Deck, Measure, Panel, Prompt, Scene, Section,
    Text, Tolerance,
};

use super::stack::Tui;
use std::ops::{Deref, DerefMut};

use tempfile::TempDir;

use super::services::{Clock, DayZone, Services, Stopwatch};
use super::theme::Theme;
use super::view;
use crate::sched::Config;
use crate::store::Store;

pub fn now() -> DateTime<Utc> {
    DateTime::parse_from_rfc3339("2026-03-02T09:00:00Z")
        .map(|t| t.with_timezone(&Utc))
        .unwrap_or_default()
}

fn text(en: &str, hi: &str) -> Text {
    let mut m = BTreeMap::new();
    m.insert("en".to_string(), en.to_string());
    m.insert("hi-Latn".to_string(), hi.to_string());
    Text(m.into())
}

pub fn deck() -> Deck {
    Deck {
        parent: None,
        misconceptions: Vec::new(),
        explore: Vec::new(),
        derivations: Vec::new(),
        id: "torque-free".into(),
        title: text("Torque-free rotation", "Torque-free rotation (Hinglish)"),
        description: Some(text(
            "Euler's equations and the tennis-racket theorem.",
            "Euler ke equations aur tennis-racket theorem.",
        )),
        languages: vec!["en".into(), "hi-Latn".into()],
        cards: vec![
            Card {
                id: "body-frame-why".into(),
                kind: CardKind::Basic,
                front: text(
                    "Why use the body frame for rotation?",
                    "Rotation ke liye body frame kyun?",
                ),
                back: text(
                    "There the inertia tensor $\\mathbf I = \\mathrm{diag}(I_1, I_2, I_3)$ is constant.",
                    "Wahan inertia tensor $\\mathbf I = \\mathrm{diag}(I_1, I_2, I_3)$ constant rehta hai.",
                ),
                accept: vec![],
                accept_by_lang: Default::default(),
                explain: Some("setup".into()),
                prompt: None,
                tags: vec!["frames".into()],
                formula: None,
            },
            Card {
                id: "euler-1".into(),
                kind: CardKind::Reversed,
                front: text(
                    "Euler's equation for component 1 (torque-free)",
                    "Component 1 ka Euler equation (torque-free)",
                ),
                back: text(
                    "$I_1 \\dot\\omega_1 = (I_2 - I_3)\\,\\omega_2 \\omega_3$",
                    "$I_1 \\dot\\omega_1 = (I_2 - I_3)\\,\\omega_2 \\omega_3$",
                ),
                accept: vec![],
                accept_by_lang: Default::default(),
                explain: Some("euler".into()),
                prompt: None,
                tags: vec![],
                formula: None,
            },
            Card {
                id: "unstable-axis".into(),
                kind: CardKind::Typed,
                front: text(
                    "Which principal axis is unstable: smallest, middle or largest?",
                    "Kaunsa principal axis unstable hai: smallest, middle ya largest?",
                ),
                back: text("The middle one.", "Beech wala (middle)."),
                accept: vec!["middle".into(), "intermediate".into(), "beech wala".into()],
                accept_by_lang: [
                    (
                        "en".to_string(),
                        vec!["middle".into(), "intermediate".into()],
                    ),
                    (
                        "hi-Latn".to_string(),
                        vec!["beech wala".into(), "middle".into()],
                    ),
                ]
                .into_iter()
                .collect(),
                explain: Some("stability".into()),
                prompt: Some("middle-axis".into()),
                tags: vec![],
                formula: None,
            },
        ],
        prompts: vec![
            Prompt {
                id: "middle-axis".into(),
                question: text(
                    "A racket spins about its middle axis with a tiny wobble. Stable, or does it flip?",
                    "Racket apne middle axis par thode wobble ke saath ghoomta hai. Stable, ya flip karega?",
                ),
                scene: "tennis-racket".into(),
                explain: Some("stability".into()),
                answer: Answer::Choice {
                    choices: vec![
                        Choice {
                            misconception: None,
                            id: "stable".into(),
                            label: text("It stays stable", "Stable rahega"),
                            when: Condition::compare(Measure::Flips, Cmp::Eq, 0.0),
                        },
                        Choice {
                            misconception: None,
                            id: "flips".into(),
                            label: text("It flips over and over", "Baar baar flip karega"),
                            when: Condition::compare(Measure::Flips, Cmp::Gt, 0.0),
                        },
                    ],
                    expected: Some("flips".into()),
                },
                tags: vec![],
                measured: None,
                vary: Vec::new(),
            },
            Prompt {
                id: "growth".into(),
                question: text(
                    "How fast does the wobble grow at first (per second)?",
                    "Shuru mein wobble kitni tezi se badhta hai (per second)?",
                ),
                scene: "tennis-racket".into(),
                explain: Some("stability".into()),
                answer: Answer::Number {
                    misconceptions: Vec::new(),
                    measure: Measure::GrowthRate,
                    unit: "1/s".into(),
                    expected: Some(5.0),
                    tolerance: Tolerance::Rel(0.15),
                    formula: Some(text(
                        "$\\sqrt{k} = \\Omega\\sqrt{(I_2-I_1)(I_3-I_2)/(I_1 I_3)}$",
                        "$\\sqrt{k} = \\Omega\\sqrt{(I_2-I_1)(I_3-I_2)/(I_1 I_3)}$",
                    )),
                    slips: Vec::new(),
                },
                tags: vec![],
                measured: None,
                vary: Vec::new(),
            },
        ],
        systems: vec![],
        scenes: vec![Scene {
            id: "tennis-racket".into(),
            title: Some(text("Tennis racket", "Tennis racket")),
            inertia: [1.0, 2.0, 3.0],
            omega: [0.01, 10.0, 0.01],
            duration: 5.0,
            show: vec![
                Panel::Omega,
                Panel::Body,
                Panel::Polhode,
                Panel::Diagnostics,
            ],
            time_unit: "s".into(),
        }],
        sections: vec![
            Section {
                id: "setup".into(),
                title: text("Setup: why the body frame", "Setup: body frame kyun"),
                body: text(
                    "In the lab frame $\\mathbf I$ changes every instant because the body re-orients. \
                     In the *body* frame along the principal axes it is **constant**.\n\n\
                     - the price: the frame rotates\n- time derivatives get an extra term\n\n\
                     $$\\left(\\frac{d\\vec L}{dt}\\right)_{\\text{space}} = \\vec N$$",
                    "Lab frame mein $\\mathbf I$ har pal badalta hai kyunki body re-orient hoti hai. \
                     *Body* frame mein principal axes ke saath yeh **constant** hai.\n\n\
                     - price: frame khud rotate karta hai\n- time derivatives mein extra term aata hai\n\n\
                     $$\\left(\\frac{d\\vec L}{dt}\\right)_{\\text{space}} = \\vec N$$",
                ),
                see: vec!["euler".into(), "stability".into()],
            },
            Section {
                id: "euler".into(),
                title: text("Euler's equations", "Euler ke equations"),
                body: text(
                    "Apply the transport theorem to $\\vec L$ (see [the setup](#setup)) and set \
                     $\\vec N = 0$: $I_1\\dot\\omega_1 = (I_2 - I_3)\\omega_2\\omega_3$ and cyclic.",
                    "$\\vec L$ par transport theorem lagao ([setup dekho](#setup)) aur \
                     $\\vec N = 0$ rakho: $I_1\\dot\\omega_1 = (I_2 - I_3)\\omega_2\\omega_3$ aur cyclic.",
                ),
                see: vec!["stability".into()],
            },
            Section {
                id: "stability".into(),
                title: text("The tennis-racket theorem", "Tennis-racket theorem"),
                body: text(
                    "Spin about the largest or smallest axis is stable; about the middle axis a \
                     tiny wobble grows like $e^{\\sqrt{k} t}$ and the body flips.",
                    "Sabse bade ya sabse chhote axis par spin stable hai; middle axis par chhota \
                     wobble $e^{\\sqrt{k} t}$ ki tarah badhta hai aur body flip karti hai.",
                ),
                see: vec!["setup".into()],
            },
        ],
        units: Vec::new(),
        path: PathBuf::from("tests/decks/valid/torque-free.toml"),
    }
}

/// An app on the fixture deck with a fresh review store in a temporary
/// data dir (removed when this is dropped), a fixed clock and no colours.
pub struct TestApp {
    pub app: Tui,
    pub dir: TempDir,
}

impl Deref for TestApp {
    type Target = Tui;
    fn deref(&self) -> &Tui {
        &self.app
    }
}

impl DerefMut for TestApp {
    fn deref_mut(&mut self) -> &mut Tui {
        &mut self.app
    }
}

pub fn services(dir: &TempDir) -> Services {
    // Siblings are not buried here, so that the fixture's reversed card
    // shows both ways in one session; the tests of burying turn it on.
    let config = Config {
        fuzz: false,
        bury_siblings: false,
        ..Config::default()
    };
    let store = match Store::open(dir.path()) {
        Ok(s) => s,
        Err(e) => panic!("store in {}: {e}", dir.path().display()),
    };
    let mut s = Services::new(Clock::Fixed(now()), config, None, DayZone::Utc, store);
    s.stopwatch = Stopwatch::Frozen;
    s.physics_slice = None;
    s
}

pub fn app(lang: &str) -> TestApp {
    let dir = match tempfile::tempdir() {
        Ok(d) => d,
        Err(e) => panic!("temp dir: {e}"),
    };
    let mut app = Tui::new(vec![deck()], services(&dir), lang, Theme::PLAIN);
    app.size = (80, 24);
    TestApp { app, dir }
}

/// The frame's cells, at the app's size.
pub fn buffer(app: &Tui) -> ratatui::buffer::Buffer {
    let (w, h) = app.size;
    let mut terminal = match Terminal::new(TestBackend::new(w, h)) {
        Ok(t) => t,
        Err(e) => panic!("test backend: {e}"),
    };
    if let Err(e) = terminal.draw(|f| view::draw(f, app)) {
        panic!("draw: {e}");
    }
    terminal.backend().buffer().clone()
}

/// The frame as text, at the app's size.
pub fn render(app: &Tui) -> String {
    let (w, h) = app.size;
    let mut terminal = match Terminal::new(TestBackend::new(w, h)) {
        Ok(t) => t,
        Err(e) => panic!("test backend: {e}"),
    };
    if let Err(e) = terminal.draw(|f| view::draw(f, app)) {
        panic!("draw: {e}");
    }
    terminal.backend().to_string()
}

/// A tmpfs of `kib` KiB mounted for one test (unmounted on drop), to run
/// out of disk space for real. `None` where mounting is not permitted.
pub struct SmallDisk {
    pub dir: TempDir,
}

impl SmallDisk {
    pub fn mount(kib: u32) -> Option<SmallDisk> {
        let dir = tempfile::tempdir().ok()?;
        let mounted = std::process::Command::new("mount")
            .args(["-t", "tmpfs", "-o", &format!("size={kib}k"), "tmpfs"])
            .arg(dir.path())
            .stderr(std::process::Stdio::null())
            .status()
            .is_ok_and(|s| s.success());
        if !mounted {
            // CI runs as root: there the case must run (tests/support).
            let ci = std::env::var("CI").is_ok_and(|v| v == "true" || v == "1");
            assert!(
                !ci,
                "cannot mount a tmpfs (needs root), and CI=true runs every test"
            );
            eprintln!("cannot mount a tmpfs here (needs root): the full-disk case is not run");
            return None;
        }
        Some(SmallDisk { dir })
    }

    /// Fills what is left of the disk; returns the filler file.
    pub fn fill(&self) -> PathBuf {
        use std::io::Write as _;
        let filler = self.dir.path().join("filler");
        if let Ok(mut f) = std::fs::File::create(&filler) {
            let block = vec![0xAAu8; 4096];
            while f.write_all(&block).is_ok() {}
        }
        filler
    }
}

impl Drop for SmallDisk {
    fn drop(&mut self) {
        let _ = std::process::Command::new("umount")
            .arg(self.dir.path())
            .status();
    }
}

/// Answers the prompt the review queue opened (direction `predict`): the
/// first choice, or 1 typed, or a formula; the run played to its verdict
/// (ticks as the event loop gives them), then back to the review.
pub fn answer_prompt(app: &mut Tui) {
    use crate::tui::action::Action;
    use crate::tui::keymap::Context;
    let apply = |app: &mut Tui, a: Action| crate::tui::update::apply(app, a);
    // The deck's answer when it states one (right: Good, so the prompt
    // graduates), else the first choice or 1.
    let expected = match app.screen() {
        crate::tui::screens::Screen::Predict(p) => app
            .decks
            .get(p.deck)
            .and_then(|d| d.prompts.get(p.prompt))
            .and_then(crate::predict::Prediction::expected),
        _ => None,
    };
    // Whatever was typed before (a rating key pressed as the screen
    // opened) goes.
    for _ in 0..32 {
        apply(app, Action::Backspace);
    }
    match (app.context(), expected) {
        (Context::PredictChoice, Some(crate::predict::Prediction::Choice(i))) => {
            apply(app, Action::Choose(i));
            apply(app, Action::Submit);
        }
        (Context::PredictChoice, _) => apply(app, Action::Submit),
        (Context::PredictNumber, Some(crate::predict::Prediction::Number(v))) => {
            for c in crate::text::num::show(v).chars() {
                apply(app, Action::Input(c));
            }
            apply(app, Action::Submit);
        }
        (Context::PredictNumber | Context::PredictFormula, _) => {
            apply(app, Action::Input('1'));
            apply(app, Action::Submit);
        }
        (c, _) => panic!("not asking a prompt: {c:?}"),
    }
    for _ in 0..6 {
        apply(app, Action::Faster);
    }
    for _ in 0..30_000 {
        if app.context() == Context::PredictVerdict && !app.animating() {
            break;
        }
        apply(app, Action::Tick(std::time::Duration::from_millis(100)));
        if app.animating() {
            std::thread::sleep(std::time::Duration::from_micros(200));
        }
    }
    assert_eq!(
        app.context(),
        Context::PredictVerdict,
        "the prompt's run ends"
    );
    apply(app, Action::Back);
}
