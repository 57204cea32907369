//! The terminal app's time budgets: the first frame after start with the
//! bundled decks (target < 100 ms), and one frame of the seed simulation
//! (physics step + drawing; at 30 frames per second, < 5% of one core
//! leaves about 1.6 ms per frame), and a knob change while exploring the
//! pendulum, from the key to the first new frame (target < 50 ms: the new
//! run built, one 33 ms frame of its physics, the frame drawn).

use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use ratatui::Terminal;
use ratatui::backend::TestBackend;

use flipcard::sched::Config;
use flipcard::store::Store;
use flipcard::tui::services::{Clock, DayZone, Services};
use flipcard::tui::theme::Theme;
use flipcard::tui::{Action, Tui, apply, view};

fn app(dir: &std::path::Path) -> Tui {
    let loaded = flipcard::bundled::load();
    let store = Store::open(dir).unwrap_or_else(|e| panic!("store: {e}"));
    let services = Services::new(
        Clock::System,
        Config::default(),
        None,
        DayZone::Local,
        store,
    );
    Tui::new(loaded.decks, services, "en", Theme::COLOR)
}

fn terminal() -> Terminal<TestBackend> {
    Terminal::new(TestBackend::new(120, 40)).unwrap_or_else(|e| panic!("terminal: {e}"))
}

fn first_frame(c: &mut Criterion) {
    let dir = tempfile::tempdir().unwrap_or_else(|e| panic!("temp dir: {e}"));
    c.bench_function("tui/first_frame (load decks, open store, draw home)", |b| {
        b.iter(|| {
            let app = app(dir.path());
            let mut t = terminal();
            t.draw(|f| view::draw(f, &app))
                .unwrap_or_else(|e| panic!("draw: {e}"));
        })
    });
}

fn simulation_frame(c: &mut Criterion) {
    let dir = tempfile::tempdir().unwrap_or_else(|e| panic!("temp dir: {e}"));
    let mut app = app(dir.path());
    app.size = (120, 40);
    // The seed prompt: the middle axis of the torque-free deck (whichever
    // place the bundled decks give it).
    let (deck, selected) = app
        .decks
        .iter()
        .enumerate()
        .find_map(|(d, deck)| {
            let i = deck.prompts.iter().position(|p| p.id == "middle-axis")?;
            Some((d, i))
        })
        .unwrap_or_else(|| panic!("no middle-axis prompt in the bundled decks"));
    app.stack.push(flipcard::tui::screens::Screen::Prompts(
        flipcard::tui::screens::prompts::PromptsState { deck, selected },
    ));
    apply(&mut app, Action::Open);
    apply(&mut app, Action::Choose(1));
    apply(&mut app, Action::Submit);
    assert!(app.animating(), "the simulation should be playing");
    let mut t = terminal();
    c.bench_function(
        "tui/simulation_frame (33 ms of physics + draw, seed scene)",
        |b| {
            b.iter(|| {
                if !app.animating() {
                    apply(&mut app, Action::Restart);
                }
                apply(&mut app, Action::Tick(Duration::from_millis(33)));
                t.draw(|f| view::draw(f, &app))
                    .unwrap_or_else(|e| panic!("draw: {e}"));
            })
        },
    );
}

fn knob_change(c: &mut Criterion) {
    let dir = tempfile::tempdir().unwrap_or_else(|e| panic!("temp dir: {e}"));
    let mut app = app(dir.path());
    app.size = (120, 40);
    let deck = app
        .decks
        .iter()
        .position(|d| d.id == "oscillations")
        .unwrap_or_else(|| panic!("no oscillations deck"));
    let selected = app.decks[deck]
        .prompts
        .iter()
        .position(|p| p.scene == "pendulum-30")
        .unwrap_or_else(|| panic!("no prompt on pendulum-30"));
    app.stack.push(flipcard::tui::screens::Screen::Prompts(
        flipcard::tui::screens::prompts::PromptsState { deck, selected },
    ));
    apply(&mut app, Action::Explore);
    assert_eq!(
        app.context(),
        flipcard::tui::keymap::Context::PredictExplore,
        "exploring the pendulum"
    );
    let mut t = terminal();
    let mut up = true;
    c.bench_function(
        "tui/knob_change (pendulum: key → new run → 33 ms of physics → frame drawn)",
        |b| {
            b.iter(|| {
                // Back and forth between two values, so every key is a change.
                apply(&mut app, if up { Action::KnobUp } else { Action::KnobDown });
                up = !up;
                apply(&mut app, Action::Tick(Duration::from_millis(33)));
                t.draw(|f| view::draw(f, &app))
                    .unwrap_or_else(|e| panic!("draw: {e}"));
            })
        },
    );
}

criterion_group!(benches, first_frame, simulation_frame, knob_change);
criterion_main!(benches);
