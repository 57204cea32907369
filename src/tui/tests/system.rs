//! A system scene in the predict-then-check screen: the same controls as a
//! rigid body's, the system's panels, and the verdict from its measures.

use std::collections::BTreeMap;
use std::time::Duration;

use crossterm::event::KeyCode;

use super::{press, press_all};
use crate::deck::{
    Answer, Choice, Cmp, Condition, Measure, Prompt, Stat, SystemPanel, SystemScene, Text,
};
use crate::sim::scene::spec::Mark;
use crate::sim::system::Name;
use crate::tui::action::Action;
use crate::tui::i18n::{ENGLISH, HINGLISH};
use crate::tui::screens::Screen;
use crate::tui::screens::predict::Phase;
use crate::tui::testkit::{self, TestApp, render};
use crate::tui::theme::Theme;

fn text(en: &str, hi: &str) -> Text {
    let mut m = BTreeMap::new();
    m.insert("en".to_string(), en.to_string());
    m.insert("hi-Latn".to_string(), hi.to_string());
    Text(m.into())
}

fn pendulum() -> SystemScene {
    SystemScene {
        id: "pendulum-170".into(),
        title: Some(text(
            "Pendulum released at 170°",
            "170° se chhoda gaya pendulum",
        )),
        variables: vec!["theta".into(), "omega".into()],
        initial: vec![2.9670597283903604, 0.0],
        params: vec![("g".into(), 9.81), ("L".into(), 1.0)],
        equations: vec!["omega".into(), "-g/L*sin(theta)".into()],
        observables: vec![
            (
                "energy".into(),
                "0.5*L^2*omega^2 + g*L*(1 - cos(theta))".into(),
            ),
            ("x".into(), "L*sin(theta)".into()),
            ("y".into(), "-L*cos(theta)".into()),
        ],
        conserved: vec!["energy".into()],
        duration: 20.0,
        show: vec![
            SystemPanel::Plot,
            SystemPanel::Phase,
            SystemPanel::Sketch,
            SystemPanel::Diagnostics,
        ],
        plot: vec!["theta".into()],
        phase: Some(["theta".into(), "omega".into()]),
        sketch: vec![
            Mark::Line(["0".into(), "0".into(), "x".into(), "y".into()]),
            Mark::Dot(["x".into(), "y".into()], None),
            Mark::Trail(["x".into(), "y".into()]),
        ],
        time_unit: "s".into(),
        atol: None,
        hamiltonian: None,
        labels: Vec::new(),
    }
}

fn app(lang: &str) -> TestApp {
    let mut deck = testkit::deck();
    deck.systems.push(pendulum());
    let period = Measure::Of(Stat::Period, Name::new("theta").unwrap());
    deck.prompts.push(Prompt {
        id: "pendulum-period".into(),
        question: text(
            "Released at 170°, is the period longer than twice the small-swing one?",
            "170° se chhodne par, kya period chhote swing wale se do guna se zyada hai?",
        ),
        scene: "pendulum-170".into(),
        explain: None,
        answer: Answer::Choice {
            choices: vec![
                Choice {
                    misconception: None,
                    id: "longer".into(),
                    label: text("Longer than 2 T₀", "2 T₀ se zyada"),
                    when: Condition::compare(period, Cmp::Gt, 4.0121),
                },
                Choice {
                    misconception: None,
                    id: "shorter".into(),
                    label: text("At most 2 T₀", "2 T₀ tak"),
                    when: Condition::compare(period, Cmp::Le, 4.0121),
                },
            ],
            expected: Some("longer".into()),
        },
        tags: vec![],
        measured: None,
        vary: Vec::new(),
    });
    open_third_prompt(deck, lang)
}

/// The app on `deck` at 100×30 in `lang`, on the predict screen of the
/// deck's third prompt (the test deck has two before the one added).
fn open_third_prompt(deck: crate::deck::Deck, lang: &str) -> TestApp {
    let dir = tempfile::tempdir().unwrap();
    let mut app = crate::tui::Tui::new(vec![deck], testkit::services(&dir), lang, Theme::PLAIN);
    app.size = (100, 30);
    let mut app = TestApp { app, dir };
    press(&mut app, KeyCode::Char('p'));
    press_all(&mut app, &[KeyCode::Char('j'), KeyCode::Char('j')]);
    press(&mut app, KeyCode::Enter);
    app
}

fn tick(app: &mut TestApp, ms: u64) {
    crate::tui::update::apply(app, Action::Tick(Duration::from_millis(ms)));
}

/// The system's run playing on the predict screen.
fn system_run(app: &TestApp) -> &crate::sim::scene::system::SystemRun {
    match running(app).sim() {
        crate::tui::live::Sim::System { run, .. } => run,
        crate::tui::live::Sim::Rigid(_) => panic!("not a system run"),
    }
}

fn running(app: &TestApp) -> &crate::tui::live::Live {
    match app.screen() {
        Screen::Predict(p) => match &p.phase {
            Phase::Play { run, .. } => run,
            _ => panic!("not a system run"),
        },
        _ => panic!("not on the predict screen"),
    }
}

#[test]
fn a_system_scene_plays_with_the_run_controls() {
    let mut app = app(ENGLISH);
    assert!(render(&app).contains("170°"), "{}", render(&app));
    press_all(&mut app, &[KeyCode::Char('1'), KeyCode::Enter]);
    assert!(app.animating());
    // 20 s plays in 12 s of wall time at speed 1.
    for _ in 0..6 {
        tick(&mut app, 100);
    }
    let t = running(&app).t();
    assert!((t - 1.0).abs() < 1e-9, "{t}");
    press(&mut app, KeyCode::Char(' '));
    assert!(!app.animating());
    press(&mut app, KeyCode::Char(' '));
    press(&mut app, KeyCode::Char('+'));
    assert_eq!(running(&app).speed, 2.0);
    let mut seen = vec![system_run(&app).method().kind.name()];
    for _ in 0..4 {
        press(&mut app, KeyCode::Char('m'));
        seen.push(system_run(&app).method().kind.name());
    }
    assert_eq!(seen, ["auto", "adaptive", "radau", "rk4", "auto"]);
    assert_eq!(running(&app).t(), 0.0, "a new method restarts");
    press(&mut app, KeyCode::Char('['));
    assert_eq!(system_run(&app).method().setting, 1e-9);
    press_all(&mut app, &[KeyCode::Char(']'), KeyCode::Char(']')]);
    assert_eq!(system_run(&app).method().setting, 1e-7);
}

#[test]
fn system_panels_snapshot_in_both_languages() {
    for lang in [ENGLISH, HINGLISH] {
        let mut app = app(lang);
        press_all(&mut app, &[KeyCode::Char('1'), KeyCode::Enter]);
        for _ in 0..20 {
            tick(&mut app, 100);
        }
        let screen = render(&app);
        assert!(
            screen.contains("θ against time") || screen.contains("θ time ke saath"),
            "{screen}"
        );
        insta::assert_snapshot!(format!("system_run_{lang}"), screen);
        // To the end: the verdict from period(theta).
        for _ in 0..200 {
            tick(&mut app, 100);
        }
        let screen = render(&app);
        insta::assert_snapshot!(format!("system_verdict_{lang}"), screen);
    }
}

/// A deck with `scene` and one choice prompt on it (`measure` above or not
/// above `threshold`), opened on the predict screen.
fn app_on(scene: SystemScene, measure: Measure, threshold: f64) -> TestApp {
    let mut deck = testkit::deck();
    let id = scene.id.clone();
    deck.systems.push(scene);
    let choice = |id: &str, op: Cmp| Choice {
        misconception: None,
        id: id.into(),
        label: text(id, id),
        when: Condition::compare(measure, op, threshold),
    };
    deck.prompts.push(Prompt {
        id: "p".into(),
        question: text("Above?", "Upar?"),
        scene: id,
        explain: None,
        answer: Answer::Choice {
            choices: vec![choice("above", Cmp::Gt), choice("below", Cmp::Le)],
            expected: Some("above".into()),
        },
        tags: vec![],
        measured: None,
        vary: Vec::new(),
    });
    open_third_prompt(deck, ENGLISH)
}

/// x'' = −x with 45,056 compiled operations of observables in the
/// equation: `check` plays it, but a step costs about a million
/// operations.
fn heavy() -> SystemScene {
    let term = crate::sim::system::compile::balanced_sum(12);
    let mut observables = vec![("a0".to_string(), term.clone())];
    for i in 1..11 {
        observables.push((format!("a{i}"), format!("a{} + {term}", i - 1)));
    }
    SystemScene {
        id: "heavy".into(),
        title: None,
        variables: vec!["x".into(), "v".into()],
        initial: vec![1.0, 0.0],
        params: vec![],
        equations: vec!["v".into(), "-x + 1e-30*a10".into()],
        observables,
        conserved: vec![],
        duration: 300.0,
        show: vec![SystemPanel::Plot],
        plot: vec!["x".into()],
        phase: None,
        sketch: vec![],
        time_unit: "s".into(),
        atol: None,
        hamiltonian: None,
        labels: Vec::new(),
    }
}

#[test]
fn a_frame_of_a_heavy_scene_stops_at_its_slice_and_esc_answers() {
    let scene = heavy();
    // What check accepts.
    let cost = crate::sim::system::System::compile(&scene, true)
        .unwrap()
        .cost();
    assert!(crate::sim::scene::system::check_cost(&scene, &cost).is_ok());
    let max_x = Measure::Of(Stat::Max, Name::new("x").unwrap());
    let mut app = app_on(scene, max_x, 0.5);
    // The app's frames work within a slice; here one already spent, so a
    // frame takes one step whatever the clock asks for.
    app.services.physics_slice = Some(Duration::ZERO);
    press_all(&mut app, &[KeyCode::Char('1'), KeyCode::Enter]);
    assert!(app.animating());
    for frame in 1..=3 {
        // A second of wall clock asks for 25 s of scene time.
        tick(&mut app, 1000);
        let run = running(&app);
        assert_eq!(system_run(&app).work().steps, frame, "one step a frame");
        assert!(run.t() > 0.0 && run.t() < 25.0, "{}", run.t());
        assert!(!run.finished() && app.animating());
        // The status line says the run plays slower than its speed.
        let screen = render(&app);
        assert!(
            screen.contains("slower than shown: the steps cannot keep up"),
            "{screen}"
        );
    }
    // Esc is the next event: the run is dropped, the prompt list is back.
    press(&mut app, KeyCode::Esc);
    assert!(
        matches!(app.screen(), Screen::Prompts(_)),
        "{}",
        render(&app)
    );
    assert!(!app.animating());
}

#[test]
fn a_scene_that_leaves_its_domain_gives_no_verdict_and_records_nothing() {
    // lnx = ln(x) with x = cos t: NaN from t = π/2. Its sign changes used
    // to count as crossings and give "✓ Right".
    let mut scene = pendulum();
    scene.id = "lnx".into();
    scene.variables = vec!["x".into(), "v".into()];
    scene.initial = vec![1.0, 0.0];
    scene.params = vec![];
    scene.equations = vec!["v".into(), "-x".into()];
    scene.observables = vec![("lnx".into(), "ln(x)".into())];
    scene.conserved = vec![];
    scene.show = vec![SystemPanel::Plot];
    scene.plot = vec!["lnx".into()];
    scene.phase = None;
    scene.sketch = vec![];
    let crossings = Measure::Of(Stat::Crossings, Name::new("lnx").unwrap());
    let mut app = app_on(scene, crossings, 10.0);
    press_all(&mut app, &[KeyCode::Char('1'), KeyCode::Enter]);
    for _ in 0..200 {
        tick(&mut app, 100);
    }
    assert!(running(&app).finished());
    assert!(!app.animating());
    let screen = render(&app);
    assert!(
        screen.contains("`lnx` is NaN at t = 1.571: ln of a negative number"),
        "{screen}"
    );
    assert!(
        !screen.contains("Right") && !screen.contains("Wrong"),
        "{screen}"
    );
    let Screen::Predict(p) = app.screen() else {
        panic!("left the predict screen");
    };
    assert!(matches!(p.phase, Phase::Play { verdict: None, .. }));
    // No verdict recorded: the attempt kept at the commitment has none,
    // and counts in no accuracy.
    let items = crate::sched::deck_items(&app.decks[0]);
    let scope = crate::store::StatsScope {
        deck: Some(&app.decks[0].id),
        items: &items,
    };
    let grid = crate::sched::DayGrid::new(chrono::Utc, app.services.study.config.day_starts_at);
    let stats = app
        .services
        .study
        .store
        .stats(scope, testkit::now(), &grid)
        .unwrap();
    assert_eq!(stats.prompts.overall.total, 0);
}

/// x'' = −x for 100 s, energy ½(x² + v²) = 0.5 throughout: RK4 at a step of
/// one second loses most of it, the reference run none.
fn spring() -> SystemScene {
    SystemScene {
        id: "spring".into(),
        title: Some(text("Spring", "Spring")),
        variables: vec!["x".into(), "v".into()],
        initial: vec![1.0, 0.0],
        params: vec![],
        equations: vec!["v".into(), "-x".into()],
        observables: vec![("energy".into(), "0.5*(x^2 + v^2)".into())],
        conserved: vec!["energy".into()],
        duration: 100.0,
        show: vec![SystemPanel::Plot],
        plot: vec!["energy".into()],
        phase: None,
        sketch: vec![],
        time_unit: "s".into(),
        atol: None,
        hamiltonian: None,
        labels: Vec::new(),
    }
}

fn verdict_text(app: &mut TestApp) -> String {
    for _ in 0..2000 {
        if !app.animating() {
            break;
        }
        tick(app, 100);
    }
    // The reference run may still be measuring on its thread.
    super::predict::settle_verdict(app);
    assert!(!app.animating(), "the run ends");
    // One paragraph, whatever the wrapping.
    render(app)
        .lines()
        .map(|l| l.trim_matches('"').trim())
        .collect::<Vec<_>>()
        .join(" ")
}

#[test]
fn the_verdict_says_which_run_it_describes_when_the_learner_changed_the_method() {
    let min_energy = Measure::Of(Stat::Min, Name::new("energy").unwrap());
    // The reference run's method: nothing more is said.
    let mut app = app_on(spring(), min_energy, 0.45);
    press_all(&mut app, &[KeyCode::Char('1'), KeyCode::Enter]);
    let screen = verdict_text(&mut app);
    assert!(screen.contains("Right"), "{screen}");
    assert!(!screen.contains("reference run"), "{screen}");

    // RK4 at a coarse step: the run on screen loses its energy and would
    // say "below"; the verdict is the reference run's, and says so.
    let mut app = app_on(spring(), min_energy, 0.45);
    press_all(&mut app, &[KeyCode::Char('1'), KeyCode::Enter]);
    for _ in 0..3 {
        press(&mut app, KeyCode::Char('m'));
    }
    assert_eq!(system_run(&app).method().kind.name(), "rk4");
    for _ in 0..20 {
        if system_run(&app).method().setting >= 1.0 {
            break;
        }
        press(&mut app, KeyCode::Char(']'));
    }
    let dt = system_run(&app).method().setting;
    assert!(dt >= 0.5, "a coarse step: {dt}");
    let label = system_run(&app).method().label();
    let screen = verdict_text(&mut app);
    assert!(screen.contains("Right"), "the physics decides: {screen}");
    // The evidence is the reference run's, over the whole scene.
    assert!(screen.contains("in this 100 s run"), "{screen}");
    assert!(
        screen.contains("This verdict describes the reference run (auto"),
        "{screen}"
    );
    assert!(
        screen.contains(&format!("With {label} the run on screen shows")),
        "{screen}"
    );
    assert!(screen.contains("the method, not the physics"), "{screen}");

    // RK4 at its own default step agrees with the reference: said as such.
    let mut app = app_on(spring(), min_energy, 0.45);
    press_all(&mut app, &[KeyCode::Char('1'), KeyCode::Enter]);
    for _ in 0..3 {
        press(&mut app, KeyCode::Char('m'));
    }
    let label = system_run(&app).method().label();
    let screen = verdict_text(&mut app);
    assert!(
        screen.contains(&format!("With {label} the run on screen shows the same")),
        "{screen}"
    );
}

#[test]
fn a_long_question_wraps_above_the_running_scene_and_the_list_names_prompts_by_it() {
    let mut app = app(ENGLISH);
    // The list names each prompt by its question, not its id.
    press(&mut app, KeyCode::Esc);
    let list = render(&app);
    assert!(
        list.contains("Released at 170°, is the period"),
        "the list shows the question:\n{list}"
    );
    assert!(!list.contains("pendulum-period"), "not the id:\n{list}");
    press(&mut app, KeyCode::Enter);
    // Narrow enough that the question needs two lines.
    app.size = (48, 30);
    press_all(&mut app, &[KeyCode::Char('1'), KeyCode::Enter]);
    assert!(app.animating());
    let screen = render(&app);
    // The backend quotes each row.
    let words: Vec<&str> = screen
        .split(|c: char| c.is_whitespace() || c == '"')
        .collect();
    for word in [
        "Released",
        "170°,",
        "period",
        "longer",
        "twice",
        "small-swing",
        "one?",
    ] {
        assert!(
            words.contains(&word),
            "`{word}` is shown whole above the run:\n{screen}"
        );
    }
}

#[test]
fn after_a_system_verdict_n_opens_the_next_prompt_as_after_a_rigid_one() {
    // The one predict flow: the verdict keys of a rigid body's run work on
    // a system's too, and its hint line lists them.
    let mut app = app(ENGLISH);
    press_all(&mut app, &[KeyCode::Char('1'), KeyCode::Enter]);
    for _ in 0..200 {
        tick(&mut app, 100);
    }
    let screen = render(&app);
    assert!(screen.contains("Right"), "{screen}");
    assert!(screen.contains("n next prompt"), "{screen}");
    let Screen::Predict(before) = app.screen() else {
        panic!("left the predict screen");
    };
    let (deck, prompt) = (before.deck, before.prompt);
    let n = app.decks[deck].prompts.len();
    assert!(n > 1, "the deck has another prompt to go to");
    press(&mut app, KeyCode::Char('n'));
    let Screen::Predict(after) = app.screen() else {
        panic!("left the predict screen");
    };
    assert_eq!(after.prompt, (prompt + 1) % n);
    assert!(matches!(after.phase, Phase::Ask { .. }));
}

#[test]
fn the_status_line_says_how_fast_scene_time_runs() {
    // A scene in seconds: its speed against real time (20 s play in 12 s).
    let mut app = app(ENGLISH);
    press_all(&mut app, &[KeyCode::Char('1'), KeyCode::Enter]);
    tick(&mut app, 100);
    let screen = render(&app);
    assert!(screen.contains("speed ×1.67 ·"), "{screen}");
    assert!(!screen.contains("cannot keep up"), "{screen}");
    press(&mut app, KeyCode::Char('-'));
    assert!(render(&app).contains("speed ×0.833 ·"), "{}", render(&app));
    // A 130-year scene plays in 10 s: 13 years a second, shown as such.
    let mut years = spring();
    years.duration = 130.0;
    years.time_unit = "yr".into();
    let min_energy = Measure::Of(Stat::Min, Name::new("energy").unwrap());
    let mut app = app_on(years, min_energy, 0.45);
    press_all(&mut app, &[KeyCode::Char('1'), KeyCode::Enter]);
    for _ in 0..10 {
        tick(&mut app, 100);
    }
    let screen = render(&app);
    assert!(screen.contains("speed ×1 · 13.0 yr/s"), "{screen}");
    assert!((running(&app).t() - 13.0).abs() < 1e-9, "{screen}");
    press(&mut app, KeyCode::Char('+'));
    assert!(
        render(&app).contains("speed ×2 · 26.0 yr/s"),
        "{}",
        render(&app)
    );
}

#[test]
fn two_dots_of_a_sketch_are_two_glyphs() {
    // A planet around a Sun at the origin: two objects, told apart.
    let mut scene = spring();
    scene.id = "orbit".into();
    scene.observables = vec![
        ("energy".into(), "0.5*(x^2 + v^2)".into()),
        ("sx".into(), "0".into()),
        ("sy".into(), "0".into()),
    ];
    scene.show = vec![SystemPanel::Sketch];
    scene.sketch = vec![
        Mark::Dot(["sx".into(), "sy".into()], None),
        Mark::Dot(["x".into(), "v".into()], None),
        Mark::Trail(["x".into(), "v".into()]),
    ];
    let min_energy = Measure::Of(Stat::Min, Name::new("energy").unwrap());
    let mut app = app_on(scene, min_energy, 0.45);
    press_all(&mut app, &[KeyCode::Char('1'), KeyCode::Enter]);
    for _ in 0..5 {
        tick(&mut app, 100);
    }
    let screen = render(&app);
    assert_eq!(screen.matches('●').count(), 1, "{screen}");
    assert_eq!(screen.matches('◆').count(), 1, "{screen}");
}

#[test]
fn a_dot_is_drawn_with_its_label_in_the_learners_language() {
    let mut scene = spring();
    scene.id = "orbit".into();
    scene.observables = vec![
        ("energy".into(), "0.5*(x^2 + v^2)".into()),
        ("sx".into(), "0".into()),
        ("sy".into(), "0".into()),
    ];
    scene.show = vec![SystemPanel::Sketch];
    scene.sketch = vec![
        Mark::Dot(["sx".into(), "sy".into()], Some(text("Sun", "Suraj"))),
        Mark::Dot(["x".into(), "v".into()], Some(text("planet", "grah"))),
    ];
    let min_energy = Measure::Of(Stat::Min, Name::new("energy").unwrap());
    for (lang, sun, planet) in [
        (ENGLISH, "● Sun", "◆ planet"),
        (HINGLISH, "● Suraj", "◆ grah"),
    ] {
        let mut app = app_on(scene.clone(), min_energy, 0.45);
        app.app.lang = lang.to_string();
        press_all(&mut app, &[KeyCode::Char('1'), KeyCode::Enter]);
        tick(&mut app, 300);
        let screen = render(&app);
        assert!(screen.contains(sun), "{screen}");
        assert!(screen.contains(planet), "{screen}");
    }
}

#[test]
fn a_number_verdict_names_its_measurement_with_its_unit_and_no_empty_formula() {
    // The pendulum's period asked as a number: "period of θ 4.89 s", and
    // the deck's answer on its own line (the prompt has no closed form).
    let mut deck = testkit::deck();
    deck.systems.push(pendulum());
    deck.prompts.push(Prompt {
        id: "period-number".into(),
        question: text("Its period, in seconds?", "Iska period, seconds mein?"),
        scene: "pendulum-170".into(),
        explain: None,
        answer: Answer::Number {
            misconceptions: Vec::new(),
            measure: Measure::Of(Stat::Period, Name::new("theta").unwrap()),
            unit: "s".into(),
            expected: Some(4.89),
            tolerance: crate::deck::Tolerance::Rel(0.01),
            formula: None,
            slips: Vec::new(),
        },
        tags: vec![],
        measured: None,
        vary: Vec::new(),
    });
    let mut app = open_third_prompt(deck, ENGLISH);
    for c in "4.9".chars() {
        press(&mut app, KeyCode::Char(c));
    }
    press(&mut app, KeyCode::Enter);
    let screen = verdict_text(&mut app);
    assert!(screen.contains("Right"), "{screen}");
    assert!(screen.contains("period of θ: 4.89 s"), "{screen}");
    assert!(screen.contains("the deck's answer: 4.89 s"), "{screen}");
    assert!(!screen.contains("formula:"), "{screen}");
}
