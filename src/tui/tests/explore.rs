//! Exploring a scene with its knobs (issue 24 §1), through the keys: `x` on
//! the prompt list or after a verdict, `←/→` (`h/l`) turning the selected
//! knob, `Tab` selecting another; the run restarts with the new value, the
//! knob row shows it, and the explore curve gains a point per value.

use std::time::Duration;

use crossterm::event::KeyCode;

use super::{press, press_all};
use crate::tui::action::Action;
use crate::tui::i18n::{ENGLISH, HINGLISH};
use crate::tui::keymap::Context;
use crate::tui::live::Sim;
use crate::tui::screens::Screen;
use crate::tui::screens::predict::Phase;
use crate::tui::screens::predict::explore::Exploring;
use crate::tui::screens::prompts::PromptsState;
use crate::tui::testkit::{self, TestApp, render};

const DEG: f64 = std::f64::consts::PI / 180.0;

/// The app on the bundled decks, on the prompt list of deck `deck_id` with
/// the first prompt on scene `scene` selected.
fn prompt_list(lang: &str, deck_id: &str, scene: &str) -> TestApp {
    let mut app = testkit::app(lang);
    app.decks = crate::bundled::load().decks;
    let deck = app
        .decks
        .iter()
        .position(|d| d.id == deck_id)
        .unwrap_or_else(|| panic!("no bundled deck {deck_id}"));
    let selected = app.decks[deck]
        .prompts
        .iter()
        .position(|p| p.scene == scene)
        .unwrap_or_else(|| panic!("no prompt on {scene}"));
    app.stack
        .push(Screen::Prompts(PromptsState { deck, selected }));
    app.size = (100, 30);
    app
}

fn exploring(app: &TestApp) -> (&crate::tui::live::Live, &Exploring) {
    match app.screen() {
        Screen::Predict(p) => match &p.phase {
            Phase::Explore { run, explore } => (run, explore),
            _ => panic!("not exploring"),
        },
        _ => panic!("not on the predict screen"),
    }
}

/// The system run's initial value of its first variable.
fn theta0(app: &TestApp) -> f64 {
    match exploring(app).0.sim() {
        Sim::System { run, .. } => run.scene().initial[0],
        Sim::Rigid(_) => panic!("not a system"),
    }
}

fn tick(app: &mut TestApp, ms: u64) {
    crate::tui::update::apply(app, Action::Tick(Duration::from_millis(ms)));
}

/// Ticks (as the event loop does, but taking no scene time, so the run
/// stands where the test put it) until the curve holds `n` points, the
/// measurements running on their thread (bounded: a curve that never
/// grows fails the test).
fn until_points(app: &mut TestApp, n: usize) {
    for _ in 0..4000 {
        if exploring(app).1.curve.len() >= n {
            return;
        }
        tick(app, 0);
        std::thread::sleep(Duration::from_millis(2));
    }
    panic!("the curve has {} points", exploring(app).1.curve.len());
}

#[test]
fn x_explores_and_a_knob_restarts_the_run_at_its_new_value() {
    let mut app = prompt_list(ENGLISH, "oscillations", "pendulum-30");
    press(&mut app, KeyCode::Char('x'));
    assert_eq!(app.context(), Context::PredictExplore);
    assert!((theta0(&app) - 30.0 * DEG).abs() < 1e-12);
    let screen = render(&app);
    assert!(screen.contains("‹ release angle θ₀ (deg) 30 ›"), "{screen}");
    until_points(&mut app, 1);
    for _ in 0..10 {
        tick(&mut app, 100);
    }
    assert!(exploring(&app).0.t() > 0.0);
    press(&mut app, KeyCode::Right);
    let (run, e) = exploring(&app);
    assert_eq!(run.t(), 0.0, "a turned knob restarts the run");
    assert_eq!(e.values, vec![35.0]);
    assert!(
        (theta0(&app) - 35.0 * DEG).abs() < 1e-12,
        "{}",
        theta0(&app)
    );
    assert!(render(&app).contains("‹ release angle θ₀ (deg) 35 ›"));
    until_points(&mut app, 2);
    // h and l turn it too (l is not the language here).
    press_all(&mut app, &[KeyCode::Char('l'), KeyCode::Char('l')]);
    assert_eq!(exploring(&app).1.values, vec![45.0]);
    assert_eq!(app.lang, ENGLISH);
    press(&mut app, KeyCode::Char('h'));
    assert_eq!(exploring(&app).1.values, vec![40.0]);
    until_points(&mut app, 3);
    // The points: the period at each value visited, longer with the angle.
    let curve = exploring(&app).1.curve_now();
    assert!(curve.len() >= 3, "{curve:?}");
    let at = |x: f64| curve.iter().find(|p| p.0 == x).map(|p| p.1);
    let (t30, t40) = (at(30.0).unwrap(), at(40.0).unwrap());
    // T(30°) = 2.0 s × 1.0174 = 2.0410 s for g = 9.81, L = 1.
    assert!((t30 - 2.0410).abs() < 0.002, "{t30}");
    assert!(t40 > t30, "{curve:?}");
    let screen = render(&app);
    assert!(screen.contains("period(theta)"), "{screen}");
    // The curve is read by its measured range, written on it.
    let top = curve.iter().map(|p| p.1).fold(f64::MIN, f64::max);
    let low = curve.iter().map(|p| p.1).fold(f64::MAX, f64::min);
    let sig = |v: f64| crate::text::num::sig(v, 4);
    assert!(screen.contains(&format!("max {}", sig(top))), "{screen}");
    assert!(screen.contains(&format!("min {}", sig(low))), "{screen}");
}

#[test]
fn a_value_where_the_measure_is_undefined_says_so() {
    let mut app = prompt_list(ENGLISH, "oscillations", "pendulum-30");
    press(&mut app, KeyCode::Char('x'));
    // Down to 5°, then up to the end: 179° outlasts the 12 s run.
    for _ in 0..40 {
        press(&mut app, KeyCode::Right);
    }
    assert_eq!(exploring(&app).1.values, vec![179.0]);
    for _ in 0..4000 {
        let e = exploring(&app).1;
        if e.point_here().is_some() && !e.measuring() {
            break;
        }
        tick(&mut app, 0);
        std::thread::sleep(Duration::from_millis(2));
    }
    let screen = render(&app);
    assert!(
        screen.contains("period(theta) at 179: not measurable at this value"),
        "{screen}"
    );
}

#[test]
fn tab_selects_the_next_knob_of_a_rigid_body() {
    let mut app = prompt_list(ENGLISH, "torque-free-rotation", "middle-axis-spin");
    press(&mut app, KeyCode::Char('x'));
    assert_eq!(app.context(), Context::PredictExplore);
    press(&mut app, KeyCode::Right);
    let rigid = |app: &TestApp| match exploring(app).0.sim() {
        Sim::Rigid(r) => (r.scene().inertia, r.scene().omega),
        Sim::System { .. } => panic!("not a rigid body"),
    };
    let (inertia, _) = rigid(&app);
    assert!((inertia[1] - 2.1).abs() < 1e-12, "{inertia:?}");
    press(&mut app, KeyCode::Tab);
    assert_eq!(exploring(&app).1.selected, 1);
    press(&mut app, KeyCode::Right);
    let (inertia, omega) = rigid(&app);
    assert_eq!(omega[1], 11.0);
    assert!(
        (inertia[1] - 2.1).abs() < 1e-12,
        "the first knob keeps its value"
    );
    let screen = render(&app);
    assert!(screen.contains("‹ spin ω₂ (rad/s) 11 ›"), "{screen}");
    assert!(screen.contains("middle moment I₂ (kg·m²) 2.1"), "{screen}");
    // The flip time at this spin: a point, plotted against the spin.
    until_points(&mut app, 1);
    assert!(
        render(&app).contains("flip_period at 11: "),
        "{}",
        render(&app)
    );
}

#[test]
fn after_the_verdict_a_knob_key_explores() {
    let mut app = prompt_list(ENGLISH, "oscillations", "pendulum-30");
    press(&mut app, KeyCode::Enter);
    press_all(&mut app, &[KeyCode::Char('1'), KeyCode::Enter]);
    for _ in 0..6 {
        press(&mut app, KeyCode::Char('+'));
    }
    for _ in 0..4000 {
        if app.context() == Context::PredictVerdict {
            break;
        }
        tick(&mut app, 100);
        std::thread::sleep(Duration::from_millis(1));
    }
    assert_eq!(app.context(), Context::PredictVerdict);
    // The verdict's key row offers it (this scene has knobs).
    let screen = render(&app);
    assert!(screen.contains("x explore"), "{screen}");
    press(&mut app, KeyCode::Right);
    assert_eq!(app.context(), Context::PredictExplore);
    assert_eq!(exploring(&app).1.values, vec![35.0]);
    assert!((theta0(&app) - 35.0 * DEG).abs() < 1e-12);
    assert_eq!(exploring(&app).0.speed, 64.0, "the learner's speed is kept");
}

#[test]
fn a_scene_without_knobs_stays_on_the_list() {
    let mut app = prompt_list(ENGLISH, "oscillations", "pendulum-90");
    press(&mut app, KeyCode::Char('x'));
    assert_eq!(app.context(), Context::Prompts);
    assert!(render(&app).contains("no knobs"), "{}", render(&app));
}

#[test]
fn the_knob_row_in_both_languages_at_every_size() {
    for (lang, label) in [
        (ENGLISH, "release angle θ₀ (deg)"),
        (HINGLISH, "chhodne ka angle θ₀ (deg)"),
    ] {
        let mut app = prompt_list(lang, "oscillations", "pendulum-30");
        press(&mut app, KeyCode::Char('x'));
        press(&mut app, KeyCode::Right);
        until_points(&mut app, 2);
        for (size, curve) in [((100, 30), true), ((80, 24), true), ((40, 12), false)] {
            app.size = size;
            let screen = render(&app);
            assert!(
                screen.contains(&format!("{label} 35")),
                "{size:?}\n{screen}"
            );
            // The reading stays whole; the curve's panel (its ends) only
            // where there is room.
            assert!(screen.contains("period(theta)"), "{size:?}\n{screen}");
            assert_eq!(screen.contains("5 … 179"), curve, "{size:?}\n{screen}");
        }
        for size in [(1, 1), (2, 1), (1, 5), (20, 6), (39, 11)] {
            app.size = size;
            render(&app);
        }
    }
    // `L` changes the language there (`l` turns the knob).
    let mut app = prompt_list(ENGLISH, "oscillations", "pendulum-30");
    press_all(&mut app, &[KeyCode::Char('x'), KeyCode::Char('L')]);
    assert_eq!(app.lang, HINGLISH);
    assert!(render(&app).contains("chhodne ka angle θ₀ (deg) 30"));
}

#[test]
fn the_help_lists_the_knob_keys_once() {
    let rows = crate::tui::screens::bindings(Context::PredictExplore);
    assert!(rows.iter().any(|b| b.label == "← → h l"));
    assert!(rows.iter().any(|b| b.label == "Tab"));
    // The shared `l` (language) gives way to the knob's `l`.
    assert!(!rows.iter().any(|b| b.label == "l"), "{rows:?}");
    assert!(
        crate::tui::screens::bindings(Context::Prompts)
            .iter()
            .any(|b| b.label == "x")
    );
    assert!(
        crate::tui::screens::bindings(Context::PredictVerdict)
            .iter()
            .any(|b| b.label.starts_with('x'))
    );
}

#[test]
fn explore_screens_snapshot_in_both_languages() {
    for lang in [ENGLISH, HINGLISH] {
        let mut app = prompt_list(lang, "oscillations", "pendulum-30");
        press(&mut app, KeyCode::Char('x'));
        press_all(&mut app, &[KeyCode::Right, KeyCode::Right]);
        until_points(&mut app, 2);
        press(&mut app, KeyCode::Left);
        until_points(&mut app, 3);
        for _ in 0..12 {
            tick(&mut app, 100);
        }
        for (w, h) in [(100, 30), (80, 24), (40, 12)] {
            app.size = (w, h);
            insta::assert_snapshot!(format!("explore_pendulum_{lang}_{w}x{h}"), render(&app));
        }
    }
}
