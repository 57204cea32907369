//! Predict, then check: commit first, then the run, then the verdict.

use std::time::Duration;

use crossterm::event::KeyCode;

use super::{key, press, press_all, type_text};
use crate::tui::action::Action;
use crate::tui::i18n::{ENGLISH, HINGLISH};
use crate::tui::keymap::Context;
use crate::tui::screens::Screen;
use crate::tui::screens::predict::{Phase, PredictState, Prediction};
use crate::tui::testkit::{self, TestApp, render};

/// The prompt list, then prompt `n` (0: the middle-axis choice prompt,
/// 1: the growth-rate number prompt).
fn open(lang: &str, n: usize) -> TestApp {
    let mut app = testkit::app(lang);
    press(&mut app, KeyCode::Char('p'));
    for _ in 0..n {
        press(&mut app, KeyCode::Char('j'));
    }
    press(&mut app, KeyCode::Enter);
    app
}

/// The verdict on the screen's run (the run must have ended).
pub(super) fn verdict_of(app: &TestApp) -> &crate::predict::Verdict {
    match &predict(app).phase {
        Phase::Play {
            verdict: Some(v), ..
        } => v,
        _ => panic!("no verdict"),
    }
}

pub(super) fn predict(app: &TestApp) -> &PredictState {
    match app.screen() {
        Screen::Predict(p) => p,
        _ => panic!("not on the predict screen"),
    }
}

#[test]
fn choice_keys_commit_before_anything_runs() {
    let mut app = open(ENGLISH, 0);
    assert_eq!(app.context(), Context::PredictChoice);
    assert!(!app.animating(), "nothing runs before the commitment");
    assert_eq!(key(&app, KeyCode::Char('2')), Some(Action::Choose(1)));
    assert_eq!(key(&app, KeyCode::Down), Some(Action::Down));
    assert_eq!(key(&app, KeyCode::Enter), Some(Action::Submit));
    press(&mut app, KeyCode::Char('9'));
    let Phase::Ask { selected, .. } = &predict(&app).phase else {
        panic!("committed too early");
    };
    assert_eq!(*selected, 0, "no ninth choice");
    press_all(&mut app, &[KeyCode::Down, KeyCode::Down, KeyCode::Up]);
    press(&mut app, KeyCode::Char('2'));
    insta::assert_snapshot!("predict_choice_en", render(&app));
    press(&mut app, KeyCode::Enter);
    let Phase::Play { prediction, .. } = &predict(&app).phase else {
        panic!("not running after the commitment");
    };
    assert_eq!(*prediction, Prediction::Choice(1));
    assert!(app.animating());
    assert_eq!(app.context(), Context::PredictRun);
}

#[test]
fn number_prompt_takes_a_number_with_its_unit() {
    let mut app = open(ENGLISH, 1);
    assert_eq!(app.context(), Context::PredictNumber);
    // `j` and `q` are text here, not keys.
    type_text(&mut app, "5j");
    press(&mut app, KeyCode::Enter);
    assert!(render(&app).contains("unit should be 1/s"));
    press_all(&mut app, &[KeyCode::Backspace, KeyCode::Backspace]);
    type_text(&mut app, "5.7 1/s");
    insta::assert_snapshot!("predict_number_en", render(&app));
    press(&mut app, KeyCode::Enter);
    let Phase::Play { prediction, .. } = &predict(&app).phase else {
        panic!("not running");
    };
    assert_eq!(*prediction, Prediction::Number(5.7));
}

#[test]
fn a_number_prompt_takes_the_units_its_deck_declares() {
    let mut app = testkit::app(ENGLISH);
    // The deck declares "per_min" (the prompt's unit is 1/s).
    app.app.decks[0].units = vec![crate::predict::typed::declare("per_min", "1 1/min").unwrap()];
    press_all(
        &mut app,
        &[KeyCode::Char('p'), KeyCode::Char('j'), KeyCode::Enter],
    );
    type_text(&mut app, "342 per_min");
    press(&mut app, KeyCode::Enter);
    let Phase::Play { prediction, .. } = &predict(&app).phase else {
        panic!("not running: {}", render(&app));
    };
    let Prediction::Number(v) = prediction else {
        panic!("{prediction:?}");
    };
    assert!((v - 5.7).abs() < 1e-12, "{v}");
    // Another deck's unit is refused with the prompt's.
    let mut app = open(ENGLISH, 1);
    type_text(&mut app, "342 per_min");
    press(&mut app, KeyCode::Enter);
    assert!(render(&app).contains("unit should be 1/s"));
}

#[test]
fn run_controls_pause_speed_restart_method_and_step() {
    let mut app = open(ENGLISH, 0);
    press_all(&mut app, &[KeyCode::Char('2'), KeyCode::Enter]);
    let run_t = |app: &TestApp| match &predict(app).phase {
        Phase::Play { run, .. } => (run.t(), run.speed, run.paused, run.method_label()),
        _ => panic!("not running"),
    };
    // Scene time follows the wall clock: 0.5 s of ticks, 0.5 s of scene.
    for _ in 0..5 {
        apply_tick(&mut app, 100);
    }
    assert!((run_t(&app).0 - 0.5).abs() < 1e-9, "{:?}", run_t(&app));
    press(&mut app, KeyCode::Char(' '));
    assert!(run_t(&app).2, "paused");
    assert!(!app.animating(), "no ticks while paused");
    apply_tick(&mut app, 1000);
    assert!(
        (run_t(&app).0 - 0.5).abs() < 1e-9,
        "time stands still when paused"
    );
    press(&mut app, KeyCode::Char(' '));
    press_all(&mut app, &[KeyCode::Char('+'), KeyCode::Char('+')]);
    assert_eq!(run_t(&app).1, 4.0);
    apply_tick(&mut app, 100);
    assert!(
        (run_t(&app).0 - 0.9).abs() < 1e-9,
        "×4: 0.1 s of wall time is 0.4 s"
    );
    press(&mut app, KeyCode::Char('-'));
    assert_eq!(run_t(&app).1, 2.0);
    press(&mut app, KeyCode::Char('r'));
    assert_eq!(run_t(&app).0, 0.0, "restarted");
    assert_eq!(run_t(&app).1, 2.0, "speed kept");
    assert_eq!(run_t(&app).3, "exact");
    press(&mut app, KeyCode::Char('['));
    assert!(
        app.status
            .as_ref()
            .is_some_and(|s| s.text.contains("no step"))
    );
    let mut seen = vec![run_t(&app).3];
    for _ in 0..5 {
        press(&mut app, KeyCode::Char('m'));
        seen.push(run_t(&app).3.split(' ').next().unwrap_or("").to_string());
    }
    assert_eq!(
        seen,
        [
            "exact",
            "adaptive",
            "splitting",
            "splitting4",
            "rk4",
            "exact"
        ]
    );
    // RK4 with its step doubled twice.
    for _ in 0..4 {
        press(&mut app, KeyCode::Char('m'));
    }
    let before = run_t(&app).3;
    press_all(&mut app, &[KeyCode::Char(']'), KeyCode::Char(']')]);
    let after = run_t(&app).3;
    let dt = |s: &str| {
        s.split("dt=")
            .nth(1)
            .and_then(|x| x.parse::<f64>().ok())
            .unwrap_or(0.0)
    };
    assert!(
        (dt(&after) / dt(&before) - 4.0).abs() < 0.1,
        "{before} → {after}"
    );
}

fn apply_tick(app: &mut TestApp, ms: u64) {
    crate::tui::update::apply(app, Action::Tick(Duration::from_millis(ms)));
}

/// Ticks, as the event loop would, while the verdict's measurement runs
/// on its thread (bounded: one that never ends fails the test).
pub(super) fn settle_verdict(app: &mut TestApp) {
    for _ in 0..30_000 {
        if !app.animating() {
            return;
        }
        std::thread::sleep(Duration::from_millis(1));
        apply_tick(app, 1);
    }
    panic!("the verdict's measurement never ended");
}

#[test]
fn the_run_plays_to_the_end_and_stops_ticking() {
    let mut app = open(ENGLISH, 0);
    press_all(&mut app, &[KeyCode::Char('2'), KeyCode::Enter]);
    for _ in 0..60 {
        apply_tick(&mut app, 100);
    }
    let Phase::Play { run, .. } = &predict(&app).phase else {
        panic!("not running");
    };
    assert_eq!(run.t(), 5.0, "the scene lasts 5 s");
    assert!(run.finished());
    assert!(!app.animating(), "a finished run needs no frames");
}

#[test]
fn snapshots_of_the_run_in_both_languages() {
    for lang in [ENGLISH, HINGLISH] {
        let mut app = open(lang, 0);
        app.size = (100, 36);
        press_all(&mut app, &[KeyCode::Char('2'), KeyCode::Enter]);
        for _ in 0..25 {
            apply_tick(&mut app, 100);
        }
        insta::assert_snapshot!(format!("predict_run_{lang}"), redact_drifts(&render(&app)));
        press(&mut app, KeyCode::Char('?'));
        insta::assert_snapshot!(
            format!("predict_run_help_{lang}"),
            redact_drifts(&render(&app))
        );
    }
}

/// Drifts at rounding level (1e-16) depend on the machine's libm: the
/// snapshots show their order of magnitude only.
fn redact_drifts(screen: &str) -> String {
    screen
        .lines()
        .map(|line| {
            let mut out = String::new();
            let mut rest = line;
            while let Some(i) = rest.find("e-") {
                let (head, tail) = rest.split_at(i);
                // Drop the mantissa's digits: "5.7e-16" → "?e-16".
                let keep = head.trim_end_matches(|c: char| c.is_ascii_digit() || c == '.');
                out.push_str(keep);
                out.push('?');
                let digits = tail[2..].chars().take_while(|c| c.is_ascii_digit()).count();
                let exp: i32 = tail[2..2 + digits].parse().unwrap_or(0);
                // Anything below 1e-12 is rounding; say so rather than which ulp.
                out.push_str(if exp >= 12 {
                    "e-tiny"
                } else {
                    &tail[..2 + digits]
                });
                rest = &tail[2 + digits..];
            }
            out.push_str(rest);
            out
        })
        .collect::<Vec<_>>()
        .join("\n")
}

fn attempts(app: &TestApp) -> Option<(u64, u64)> {
    let items = crate::sched::deck_items(&app.decks[0]);
    let scope = crate::store::StatsScope {
        deck: Some("torque-free"),
        items: &items,
    };
    let grid = crate::sched::DayGrid::new(chrono::Utc, app.services.study.config.day_starts_at);
    let stats = app
        .services
        .study
        .store
        .stats(scope, testkit::now(), &grid)
        .ok()?;
    Some((stats.prompts.overall.total, stats.prompts.overall.passed))
}

#[test]
fn predict_run_verdict_right_and_logged() {
    let mut app = open(ENGLISH, 0);
    press_all(&mut app, &[KeyCode::Char('2'), KeyCode::Enter]);
    assert_eq!(app.context(), Context::PredictRun);
    // Play at ×8 to the end: 5 s of scene in 0.625 s of ticks.
    press_all(
        &mut app,
        &[KeyCode::Char('+'), KeyCode::Char('+'), KeyCode::Char('+')],
    );
    for _ in 0..7 {
        apply_tick(&mut app, 100);
    }
    assert_eq!(app.context(), Context::PredictVerdict);
    eprintln!("STATUS {:?}", app.status);
    let v = verdict_of(&app);
    assert!(v.correct, "{v:?}");
    assert_eq!(v.right_choice, Some(1), "the racket flips");
    let flips = v
        .readings
        .iter()
        .find(|r| r.measure == crate::deck::Measure::Flips);
    assert!(flips.is_some_and(|r| r.value >= 1.0), "{v:?}");
    assert_eq!(
        attempts(&app),
        Some((1, 1)),
        "one attempt, right, in the log"
    );
    for lang in [ENGLISH, HINGLISH] {
        app.lang = lang.into();
        insta::assert_snapshot!(
            format!("predict_verdict_{lang}"),
            redact_drifts(&render(&app))
        );
    }
    // The explanation is one key away, and Esc comes back to the verdict.
    press(&mut app, KeyCode::Char('e'));
    let Screen::Reader(r) = app.screen() else {
        panic!("explanation not open");
    };
    assert_eq!(r.section, 2, "the prompt links the stability section");
    press(&mut app, KeyCode::Esc);
    assert_eq!(app.context(), Context::PredictVerdict);
    // Watching again does not log another attempt.
    press(&mut app, KeyCode::Char('r'));
    for _ in 0..10 {
        apply_tick(&mut app, 100);
    }
    assert_eq!(attempts(&app), Some((1, 1)));
}

#[test]
fn a_wrong_prediction_is_wrong_and_shows_the_right_one() {
    let mut app = open(ENGLISH, 0);
    press_all(&mut app, &[KeyCode::Char('1'), KeyCode::Enter]);
    // Switching to RK4 mid-run does not change the physics' answer.
    for _ in 0..4 {
        press(&mut app, KeyCode::Char('m'));
    }
    for _ in 0..60 {
        apply_tick(&mut app, 100);
    }
    // The exact run that decides measures off the UI thread.
    settle_verdict(&mut app);
    let v = verdict_of(&app);
    assert!(!v.correct);
    let text = render(&app);
    assert!(text.contains("✗ Wrong ✗"), "{text}");
    assert!(
        text.contains("right in this run: It flips over and over"),
        "the right choice is named: {text}"
    );
    assert!(
        text.contains("your prediction: It stays stable"),
        "the prediction on its own line: {text}"
    );
    assert_eq!(attempts(&app), Some((1, 0)));
}

#[test]
fn a_number_prediction_is_checked_against_the_measured_rate() {
    let mut app = open(ENGLISH, 1);
    // √k for I = (1, 2, 3), Ω = 10: 10·√(1·1/3) ≈ 5.77 per second.
    type_text(&mut app, "5.8");
    press(&mut app, KeyCode::Enter);
    press_all(
        &mut app,
        &[KeyCode::Char('+'), KeyCode::Char('+'), KeyCode::Char('+')],
    );
    for _ in 0..7 {
        apply_tick(&mut app, 100);
    }
    let v = verdict_of(&app);
    let rate = v.readings.first().map(|r| r.value).unwrap_or(f64::NAN);
    assert!((rate - 5.77).abs() < 0.1, "measured growth rate {rate}");
    assert!(v.correct, "{v:?}");
    insta::assert_snapshot!("predict_verdict_number_en", redact_drifts(&render(&app)));
}

#[test]
fn every_bundled_prompt_plays_to_a_verdict_at_any_size() {
    let loaded = crate::bundled::load();
    assert!(!loaded.decks.is_empty(), "bundled decks load");
    for (d, deck) in loaded.decks.iter().enumerate() {
        for (i, prompt) in deck.prompts.iter().enumerate() {
            let mut app = testkit::app(ENGLISH);
            app.decks = loaded.decks.clone();
            let mut state = PredictState::new(&app, d, i);
            // A varied prompt's answer is the one its variant's run decides.
            let answer = match &state.variant {
                Some(v) => {
                    let run = crate::predict::audit::variant_run(deck, v)
                        .unwrap_or_else(|e| panic!("{}: {e}", prompt.id));
                    let p = crate::predict::variant::decided(&v.prompt, &run.measured)
                        .unwrap_or_else(|e| panic!("{}: {e:?}", prompt.id));
                    crate::predict::Prediction::expected(&p)
                }
                None => crate::predict::Prediction::expected(prompt),
            };
            // A formula prompt's answer is its key's formula, typed.
            let answer = match (&prompt.answer, answer) {
                (crate::deck::Answer::Formula(key), _) => {
                    for ch in key.expected.chars() {
                        crate::tui::screens::predict::apply(
                            &mut app,
                            &mut state,
                            Action::Input(ch),
                        );
                    }
                    None
                }
                (_, Some(a)) => Some(a),
                (_, None) => panic!("{}: no expected answer", prompt.id),
            };
            match answer {
                None | Some(Prediction::Formula) => {}
                Some(Prediction::Choice(c)) => {
                    crate::tui::screens::predict::apply(&mut app, &mut state, Action::Choose(c));
                }
                Some(Prediction::Number(v)) => {
                    for ch in format!("{v}").chars() {
                        crate::tui::screens::predict::apply(
                            &mut app,
                            &mut state,
                            Action::Input(ch),
                        );
                    }
                }
            }
            crate::tui::screens::predict::apply(&mut app, &mut state, Action::Submit);
            app.stack.push(Screen::Predict(Box::new(state)));
            for _ in 0..6 {
                press(&mut app, KeyCode::Char('+'));
            }
            let mut ticks = 0;
            while app.animating() && ticks < 1000 {
                apply_tick(&mut app, 100);
                ticks += 1;
            }
            assert_eq!(
                app.context(),
                Context::PredictVerdict,
                "{}: no verdict",
                prompt.id
            );
            for size in [(120, 40), (80, 24), (40, 12), (20, 6)] {
                app.size = size;
                render(&app);
            }
        }
    }
}

/// The bundled deck's prompt `id` on the predict screen, at `size`, with
/// the answer `choice` committed.
fn bundled_prompt(lang: &str, id: &str, size: (u16, u16)) -> TestApp {
    bundled_prompt_in("torque-free-rotation", lang, id, size)
}

/// Prompt `id` of the bundled deck `deck`, open at `size`.
pub(super) fn bundled_prompt_in(deck: &str, lang: &str, id: &str, size: (u16, u16)) -> TestApp {
    let loaded = crate::bundled::load();
    let mut app = testkit::app(lang);
    app.decks = loaded.decks.into_iter().filter(|d| d.id == deck).collect();
    app.size = size;
    let i = app.decks[0]
        .prompts
        .iter()
        .position(|p| p.id == id)
        .unwrap_or_else(|| panic!("no prompt {id}"));
    let state = PredictState::new(&app, 0, i);
    app.stack.push(Screen::Predict(Box::new(state)));
    app
}

pub(super) fn play_to_the_end(app: &mut TestApp) {
    for _ in 0..6 {
        press(app, KeyCode::Char('+'));
    }
    let mut ticks = 0;
    while app.animating() && ticks < 1000 {
        apply_tick(app, 100);
        ticks += 1;
    }
    // The exact run may still be measuring on its thread.
    settle_verdict(app);
    assert_eq!(app.context(), Context::PredictVerdict);
}

/// The simulation screen at every size in both languages, mid-run (two
/// flips counted and marked) and after the verdict: a right prediction in
/// English, a wrong one in Hinglish.
#[test]
fn snapshots_of_the_simulation_at_every_size() {
    for (lang, choice) in [(ENGLISH, '2'), (HINGLISH, '1')] {
        for size in [(40, 12), (80, 24), (100, 30), (160, 48)] {
            let mut app = bundled_prompt(lang, "middle-axis", size);
            press_all(&mut app, &[KeyCode::Char(choice), KeyCode::Enter]);
            for _ in 0..45 {
                apply_tick(&mut app, 100);
            }
            let name = format!("sim_{lang}_{}x{}", size.0, size.1);
            let screen = redact_drifts(&render(&app));
            assert!(screen.contains("flips: 2"), "{name}: live count\n{screen}");
            insta::assert_snapshot!(format!("{name}_run"), screen);
            play_to_the_end(&mut app);
            let screen = redact_drifts(&render(&app));
            let banner = if choice == '2' {
                "✓ Right ✓"
            } else {
                "✗ Galat ✗"
            };
            assert!(screen.contains(banner), "{name}\n{screen}");
            insta::assert_snapshot!(format!("{name}_verdict"), screen);
        }
    }
}

/// The verdict says what this run showed, with the flip times, and no
/// more; the question is never lost, only cut with "…" when rows run out.
#[test]
fn the_verdict_shows_the_evidence_and_the_question_survives() {
    let mut app = bundled_prompt(ENGLISH, "middle-axis", (100, 30));
    press_all(&mut app, &[KeyCode::Char('2'), KeyCode::Enter]);
    let screen = flat(&render(&app));
    assert!(
        screen.contains("Over 8 s, does it keep spinning steadily or flip?"),
        "the question wraps in full:\n{screen}"
    );
    play_to_the_end(&mut app);
    let screen = flat(&render(&app));
    assert!(
        screen.contains("in this 8 s run: flipped 3 times: at 1.49, 4.24 and 7.00 s"),
        "{screen}"
    );
    assert!(!screen.contains("physics says"), "{screen}");
    // The run's keys stay listed after the verdict, with `n`.
    for k in ["n next prompt", "Space pause", "r restart", "m method"] {
        assert!(screen.contains(k), "{k}:\n{screen}");
    }
    // Hinglish: the key clause of the question is there too.
    let mut app = bundled_prompt(HINGLISH, "middle-axis", (80, 24));
    press_all(&mut app, &[KeyCode::Char('2'), KeyCode::Enter]);
    let screen = flat(&render(&app));
    assert!(
        screen.contains("8 s mein steady ghoomta rahega ya palat jaayega?"),
        "{screen}"
    );
    // At 40×12 the question is cut, and says so.
    let mut app = bundled_prompt(ENGLISH, "middle-axis", (40, 12));
    press_all(&mut app, &[KeyCode::Char('2'), KeyCode::Enter]);
    play_to_the_end(&mut app);
    let screen = render(&app);
    assert!(screen.contains('…'), "{screen}");
    assert!(screen.contains("✓ Right ✓"), "{screen}");
}

/// A number answer's verdict: the e-folding time with the formula's value,
/// the deck's answer beside it, and the growth on a log axis.
#[test]
fn a_growth_prompt_shows_the_growth_on_a_log_axis() {
    let mut app = bundled_prompt(ENGLISH, "efold-time", (80, 24));
    type_text(&mut app, "0.17");
    press(&mut app, KeyCode::Enter);
    play_to_the_end(&mut app);
    let screen = redact_drifts(&render(&app));
    assert!(screen.contains("|ω⊥|, log scale"), "{screen}");
    assert!(
        screen.contains("e-folding time: 0.173 s, formula 1/√k = 0.173 s"),
        "{screen}"
    );
    assert!(
        screen.contains("formula: 1/√k = 0.173 s · the deck's answer: 0.1732 s"),
        "{screen}"
    );
    insta::assert_snapshot!("sim_growth_verdict_en", screen);
}

/// `n` after the verdict opens the deck's next prompt, ready for a new
/// prediction; before the verdict it does nothing.
#[test]
fn n_goes_to_the_next_prompt_after_the_verdict() {
    let mut app = bundled_prompt(ENGLISH, "middle-axis", (80, 24));
    press_all(&mut app, &[KeyCode::Char('2'), KeyCode::Enter]);
    press(&mut app, KeyCode::Char('n'));
    assert_eq!(predict(&app).prompt, 0, "no skipping before the verdict");
    play_to_the_end(&mut app);
    let depth = app.stack.len();
    press(&mut app, KeyCode::Char('n'));
    assert_eq!(predict(&app).prompt, 1);
    assert_eq!(app.context(), Context::PredictChoice);
    assert_eq!(app.stack.len(), depth, "replaced, not stacked");
}

/// The screen's text as one line: rows joined, runs of spaces made one, so
/// a wrapped sentence reads whole.
pub(super) fn flat(screen: &str) -> String {
    let joined: String = screen
        .lines()
        .map(|l| l.trim_matches('"'))
        .collect::<Vec<_>>()
        .join(" ");
    joined.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// The prompt list names each prompt by its question (two prompts on one
/// scene stay apart), marked with
/// the last attempt: ✗ after a wrong prediction, ✓ once it is right, ·
/// before any.
#[test]
fn the_prompt_list_marks_the_last_attempt() {
    let mut app = open(ENGLISH, 0);
    press(&mut app, KeyCode::Esc);
    let list = render(&app);
    assert!(
        list.contains(" 1. · A racket spins about its middle axis"),
        "{list}"
    );
    press(&mut app, KeyCode::Enter);
    press_all(&mut app, &[KeyCode::Char('1'), KeyCode::Enter]);
    play_to_the_end(&mut app);
    press(&mut app, KeyCode::Esc);
    let list = render(&app);
    assert!(list.contains(" 1. ✗ A racket spins"), "{list}");
    assert!(
        list.contains(" 2. · How fast does the wobble grow"),
        "{list}"
    );
    press(&mut app, KeyCode::Enter);
    press_all(&mut app, &[KeyCode::Char('2'), KeyCode::Enter]);
    play_to_the_end(&mut app);
    press(&mut app, KeyCode::Esc);
    assert!(render(&app).contains(" 1. ✓ A racket spins"));
}

/// Without colour the verdict and the plot still read: the banner by its
/// symbol and reverse video, the three ω curves by line style (named in
/// the legend); with colour the banner is green or red as well.
#[test]
fn the_verdict_and_the_plot_do_not_need_colour() {
    use ratatui::style::{Color, Modifier};
    let mut app = bundled_prompt(ENGLISH, "middle-axis", (80, 24));
    press_all(&mut app, &[KeyCode::Char('1'), KeyCode::Enter]);
    play_to_the_end(&mut app);
    let screen = render(&app);
    assert!(screen.contains("ω₁━ ω₂┅ ω₃╌"), "{screen}");
    let banner = |app: &TestApp| {
        let buf = testkit::buffer(app);
        let row = (0..24)
            .find(|&y| (0..80).any(|x| buf[(x, y)].symbol() == "✗"))
            .expect("a ✗ banner");
        buf[(3, row)].style()
    };
    let plain = banner(&app);
    assert!(plain.add_modifier.contains(Modifier::REVERSED), "{plain:?}");
    assert!(
        matches!(plain.fg, None | Some(Color::Reset)),
        "no colour under NO_COLOR: {plain:?}"
    );
    app.theme = crate::tui::theme::Theme::COLOR;
    let coloured = banner(&app);
    assert_eq!(coloured.fg, Some(Color::Red));
    assert!(coloured.add_modifier.contains(Modifier::REVERSED));
    // Colour keeps the legend's names but draws every curve solid.
    assert!(!render(&app).contains("ω₂┅"));
}

/// At 40×12 the question gives way (cut with "…"), never the answers or
/// the hint that says what to do.
#[test]
fn the_ask_phase_keeps_answers_and_hint_at_40x12() {
    let loaded = crate::bundled::load();
    let deck = loaded
        .decks
        .iter()
        .find(|d| d.id == "torque-free-rotation")
        .expect("bundled deck");
    for lang in [ENGLISH, HINGLISH] {
        for prompt in &deck.prompts {
            let app = bundled_prompt(lang, &prompt.id, (40, 12));
            let screen = render(&app);
            let hint_start: String = app
                .tr(crate::tui::i18n::Msg::CommitFirst)
                .split_whitespace()
                .take(2)
                .collect::<Vec<_>>()
                .join(" ");
            assert!(
                screen.contains(&hint_start),
                "{lang} {}: no hint {hint_start:?}\n{screen}",
                prompt.id
            );
            if let crate::deck::Answer::Choice { choices, .. } = &prompt.answer {
                let last = format!("{}. ", choices.len());
                assert!(
                    screen.contains(&last),
                    "{lang} {}: choice {last} lost\n{screen}",
                    prompt.id
                );
            }
        }
    }
}

/// Played with another method than the exact solution, the verdict says it
/// is the exact run's and what the run on screen showed; with the exact
/// solution nothing more is said.
#[test]
fn the_verdict_names_the_exact_run_when_the_learner_played_another_method() {
    let mut app = open(ENGLISH, 0);
    press_all(&mut app, &[KeyCode::Char('1'), KeyCode::Enter]);
    play_to_the_end(&mut app);
    let exact = flat(&render(&app));
    assert!(!exact.contains("reference run"), "{exact}");

    let mut app = open(ENGLISH, 0);
    press_all(&mut app, &[KeyCode::Char('1'), KeyCode::Enter]);
    press(&mut app, KeyCode::Char('m'));
    let label = match &predict(&app).phase {
        Phase::Play { run, .. } => run.method_label(),
        _ => panic!("not running"),
    };
    assert!(label.starts_with("adaptive"), "{label}");
    play_to_the_end(&mut app);
    let screen = flat(&render(&app));
    assert!(
        screen.contains("This verdict describes the reference run (exact), not the run on screen."),
        "{screen}"
    );
    assert!(
        screen.contains(&format!("With {label} the run on screen shows the same.")),
        "{screen}"
    );
}

#[test]
fn diagnostics_wait_behind_d_and_come_by_themselves_for_another_method() {
    let mut app = open(ENGLISH, 0);
    press_all(&mut app, &[KeyCode::Char('2'), KeyCode::Enter]);
    apply_tick(&mut app, 100);
    // The exact run: the solver's numbers are not the lesson; hidden.
    assert!(!render(&app).contains("ΔE/E"), "{}", render(&app));
    press(&mut app, KeyCode::Char('d'));
    assert!(render(&app).contains("ΔE/E"), "{}", render(&app));
    press(&mut app, KeyCode::Char('d'));
    assert!(!render(&app).contains("ΔE/E"), "{}", render(&app));
    // Another method: its error against the exact run is the lesson, shown
    // unless the learner hid it.
    let mut app = open(ENGLISH, 0);
    press_all(&mut app, &[KeyCode::Char('2'), KeyCode::Enter]);
    press(&mut app, KeyCode::Char('m'));
    apply_tick(&mut app, 100);
    assert!(render(&app).contains("ΔE/E"), "{}", render(&app));
    // Narrow: folded at its separators, never cut inside a part.
    app.size = (60, 30);
    let screen = render(&app);
    let diag: Vec<&str> = screen
        .lines()
        .map(|l| l.trim_matches('"').trim_end())
        .skip_while(|l| !l.contains("ΔE/E"))
        .take_while(|l| !l.trim_start().starts_with("Space") && !l.is_empty())
        .collect();
    assert!(diag.len() >= 2, "{screen}");
    for line in &diag {
        assert!(!line.ends_with('…'), "cut: {line}\n{screen}");
        assert!(!line.trim_end().ends_with('·'), "{line}");
    }
    assert!(screen.contains("µs draw"), "{screen}");
}

/// The line of the reader's page for `section` of deck 0 that starts the
/// block whose text begins with `words` (found in the laid-out lines, not
/// from the anchors).
fn line_starting(app: &TestApp, section: usize, words: &str) -> usize {
    let body = crate::tui::layout::body_rect(app.size);
    let (_, text, _) = crate::tui::screens::reader::areas(body);
    let page =
        crate::tui::screens::reader::page(app, &app.decks[0], section, text.width as usize, None);
    page.lines
        .iter()
        .position(|l| {
            crate::tui::wrap::line_text(l)
                .trim_start()
                .starts_with(words)
        })
        .unwrap_or_else(|| panic!("no line starts with {words:?}"))
}

/// The first words of the block an anchor of `section` names, in `lang`,
/// read from the deck's own body (the line after `{#anchor}`).
fn anchored_words(app: &TestApp, section: &str, anchor: &str, lang: &str) -> String {
    let sec = app.decks[0].section(section).unwrap();
    let body = sec.body.get(lang);
    let marker = format!("{{#{anchor}}}");
    let after = body
        .lines()
        .skip_while(|l| l.trim() != marker)
        .nth(1)
        .unwrap_or_else(|| panic!("no {marker} in {section}"));
    // The first three words, as the reader shows them (markup and math
    // rendered): the block's own text.
    let block = crate::text::markup::parse(after);
    block[0]
        .text()
        .split_whitespace()
        .take(3)
        .collect::<Vec<_>>()
        .join(" ")
}

/// A wrong number that is a known slip: the verdict says which formula it
/// is and what it means, in each language, beside what the run measured;
/// a wrong number that is no slip gets no such line.
#[test]
fn a_wrong_number_that_is_a_known_slip_is_told_what_it_is() {
    for lang in [ENGLISH, HINGLISH] {
        let mut app = bundled_prompt(lang, "efold-time", (100, 30));
        type_text(&mut app, "0.03");
        press(&mut app, KeyCode::Enter);
        play_to_the_end(&mut app);
        let v = verdict_of(&app);
        assert!(!v.correct, "{v:?}");
        let (i, value) = v.slip.expect("0.03 s is the slip 1/k");
        let prompt = app.decks[0].prompt("efold-time").unwrap();
        let crate::deck::Answer::Number { slips, .. } = &prompt.answer else {
            panic!("a number prompt");
        };
        assert_eq!(slips[i].value, "1/k");
        let screen = flat(&render(&app));
        let said = match lang {
            ENGLISH => "your number is",
            _ => "tumhara number hai",
        };
        let head = format!("{said} 1/k = {} s:", crate::text::num::sig(value, 3));
        assert!(screen.contains(&head), "{head}\n{screen}");
        // What the slip says, rendered, follows in the learner's language.
        let says = crate::text::render(slips[i].says.get(lang));
        let start: String = says
            .split_whitespace()
            .take(6)
            .collect::<Vec<_>>()
            .join(" ");
        assert!(screen.contains(&start), "{start}\n{screen}");
        // Beside the measured fact.
        assert!(screen.contains("0.173"), "{screen}");
        insta::assert_snapshot!(
            format!("predict_verdict_slip_{lang}"),
            redact_drifts(&render(&app))
        );
    }
    let mut app = bundled_prompt(ENGLISH, "efold-time", (100, 30));
    type_text(&mut app, "0.5");
    press(&mut app, KeyCode::Enter);
    play_to_the_end(&mut app);
    let v = verdict_of(&app);
    assert!(!v.correct && v.slip.is_none(), "{v:?}");
    assert!(!flat(&render(&app)).contains("your number is"));
}

/// `e` after a verdict opens the reader with the paragraph the prompt's
/// anchor names on the first line: a rigid body's choice prompt, and a
/// system scene's number prompt whose wrong number is a slip too.
#[test]
fn e_after_a_verdict_opens_the_anchored_paragraph() {
    for (deck, id, key, size) in [
        ("torque-free-rotation", "largest-axis", "1", (80, 24)),
        ("oscillations", "damping-efold", "1.6", (100, 30)),
    ] {
        for lang in [ENGLISH, HINGLISH] {
            let mut app = bundled_prompt_in(deck, lang, id, size);
            let explain = app.decks[0].prompt(id).unwrap().explain.clone().unwrap();
            let anchor = explain
                .anchor
                .clone()
                .expect("the bundled prompt names an anchor");
            if key.contains('.') {
                type_text(&mut app, key);
                press(&mut app, KeyCode::Enter);
            } else {
                press_all(
                    &mut app,
                    &[KeyCode::Char(key.chars().next().unwrap()), KeyCode::Enter],
                );
            }
            play_to_the_end(&mut app);
            if key.contains('.') {
                // 1.6 s is the energy's e-folding time, a known slip.
                let screen = flat(&render(&app));
                assert!(screen.contains("1/(2·ζ·w0) = 1.59 s"), "{screen}");
            }
            press(&mut app, KeyCode::Char('e'));
            let Screen::Reader(r) = app.screen() else {
                panic!("explanation not open");
            };
            let section = app.decks[0]
                .sections
                .iter()
                .position(|s| s.id == explain.section)
                .unwrap();
            assert_eq!(r.section, section);
            let words = anchored_words(&app, &explain.section, &anchor, lang);
            let line = line_starting(&app, section, &words);
            assert!(line > 0, "{id}: the anchor is not the top of the section");
            assert_eq!(
                r.scroll, line,
                "{id} in {lang}: {words:?} on the first line"
            );
            let screen = render(&app);
            assert!(flat(&screen).contains(&words), "{words}\n{screen}");
            press(&mut app, KeyCode::Esc);
            assert_eq!(app.context(), Context::PredictVerdict);
        }
    }
}

/// A rigid body's prompt and a system's through the same assertions, at
/// 100×30 and 80×24 in both languages: the question whole (no word of it
/// torn or left out) while the run plays and under the verdict, the
/// measurement named in words with its unit, and `n` opening the next
/// prompt.
#[test]
fn both_scene_kinds_keep_the_question_whole_name_the_measure_and_go_on_with_n() {
    // (deck, prompt, choice, what the verdict reads in English, in Hinglish)
    let cases = [
        (
            "torque-free-rotation",
            "middle-axis",
            '2',
            "flipped 3 times: at 1.49, 4.24 and 7.00 s",
            "3 baar palta: 1.49, 4.24 aur 7.00 s par",
        ),
        (
            "oscillations",
            "damping-settle",
            '2',
            "time for B to get within 1% of rest: 4.30 s",
            "B ko rest ke 1% ke andar aane mein laga time: 4.30 s",
        ),
    ];
    for (deck, id, choice, en, hi) in cases {
        for (lang, reads) in [(ENGLISH, en), (HINGLISH, hi)] {
            for size in [(100, 30), (80, 24)] {
                let mut app = bundled_prompt_in(deck, lang, id, size);
                let question = {
                    let Screen::Predict(p) = app.screen() else {
                        panic!("not on the predict screen");
                    };
                    crate::text::render(app.decks[0].prompts[p.prompt].question.get(lang))
                };
                let whole = |screen: &str, when: &str| {
                    let shown: std::collections::HashSet<&str> = screen
                        .split(|c: char| c.is_whitespace() || c == '"')
                        .collect();
                    for word in question.split_whitespace() {
                        assert!(
                            shown.contains(word),
                            "{deck}/{id} {lang} {size:?} {when}: `{word}` of the question is not shown whole:\n{screen}"
                        );
                    }
                };
                press_all(&mut app, &[KeyCode::Char(choice), KeyCode::Enter]);
                apply_tick(&mut app, 300);
                whole(&render(&app), "while the run plays");
                play_to_the_end(&mut app);
                let screen = render(&app);
                whole(&screen, "under the verdict");
                // The keys' row lists whole entries: none cut mid-word.
                for line in screen.lines().filter(|l| l.contains("Space ")) {
                    assert!(
                        !line.trim_matches('"').trim_end().ends_with('…'),
                        "{deck}/{id} {lang} {size:?}: a key cut short:\n{screen}"
                    );
                }
                assert!(
                    flat(&screen).contains(reads),
                    "{deck}/{id} {lang} {size:?}: the verdict reads `{reads}`:\n{screen}"
                );
                let Screen::Predict(before) = app.screen() else {
                    panic!("left the predict screen");
                };
                let (d, p) = (before.deck, before.prompt);
                let n = app.decks[d].prompts.len();
                press(&mut app, KeyCode::Char('n'));
                let Screen::Predict(after) = app.screen() else {
                    panic!("{deck}/{id}: `n` left the predict screen");
                };
                assert_eq!(
                    after.prompt,
                    (p + 1) % n,
                    "{deck}/{id}: `n` opens the next prompt"
                );
                assert!(matches!(after.phase, Phase::Ask { .. }));
            }
        }
    }
}

/// A scene in its own time unit says so on the plot's time axis as in the
/// status line and the verdict, the axis label shown whole: "50 time
/// units", not "50 time u" cut by the panel's border.
#[test]
fn the_time_axis_shows_the_scenes_time_unit_whole() {
    for size in [(100, 30), (80, 24)] {
        let mut app = bundled_prompt_in("oscillations", ENGLISH, "vdp-period", size);
        type_text(&mut app, "19");
        press(&mut app, KeyCode::Enter);
        play_to_the_end(&mut app);
        let screen = render(&app);
        let axis = screen
            .lines()
            .find(|l| l.contains("min -2.01"))
            .unwrap_or_else(|| panic!("the plot's lower edge:\n{screen}"));
        assert!(axis.contains("50 time units"), "{size:?}:\n{screen}");
        assert!(
            flat(&screen).contains("period of x: 19.1 time units"),
            "{size:?}:\n{screen}"
        );
    }
}

/// The words of a frame (runs of letters and digits).
fn frame_words(frame: &str) -> std::collections::HashSet<String> {
    frame
        .split(|c: char| !c.is_alphanumeric())
        .filter(|w| !w.is_empty())
        .map(str::to_string)
        .collect()
}

/// A rigid body's prompt and a system's, at every size in both languages,
/// while the run plays and under the verdict: no row ends in a piece of a
/// word (the status line drops the method or the speed whole, the keys'
/// row whole entries, the prediction is cut at a word with "…"); the
/// same screen drawn wide enough is the judge of what a whole word is.
#[test]
fn no_row_of_either_scene_kind_is_cut_mid_word() {
    let cases = [
        ("torque-free-rotation", "middle-axis", '1'),
        ("oscillations", "pendulum-over-the-top", '1'),
    ];
    for (deck, id, choice) in cases {
        for lang in [ENGLISH, HINGLISH] {
            for size in [(40, 12), (80, 24), (100, 30)] {
                let mut app = bundled_prompt_in(deck, lang, id, size);
                press_all(&mut app, &[KeyCode::Char(choice), KeyCode::Enter]);
                apply_tick(&mut app, 300);
                let check = |app: &mut TestApp, when: &str| {
                    app.size = (400, 60);
                    let known = frame_words(&render(app));
                    app.size = size;
                    let frame = render(app);
                    for line in frame.lines() {
                        let line = line.trim_matches('"').trim_end();
                        let body = line.trim_end_matches('…');
                        let tail: String = body
                            .chars()
                            .rev()
                            .take_while(|c| c.is_alphanumeric())
                            .collect::<Vec<_>>()
                            .into_iter()
                            .rev()
                            .collect();
                        if tail.is_empty() || body.len() == line.len() && line.len() < 2 {
                            continue;
                        }
                        assert!(
                            known.contains(&tail),
                            "{deck}/{id} {lang} {size:?} {when}: `{tail}` is a piece of a word:\n{frame}"
                        );
                    }
                };
                check(&mut app, "while the run plays");
                play_to_the_end(&mut app);
                check(&mut app, "under the verdict");
            }
        }
    }
}

/// The README's example of a verdict (the middle axis, in Hinglish, at
/// 100×30) is what the app shows: its status line, keys and verdict rows,
/// and the question above them.
#[test]
fn the_readmes_example_verdict_is_what_the_app_shows() {
    let readme = include_str!("../../../README.md");
    let block = readme
        .split("Predict, then check — spin about the middle axis, in Hinglish, after the run:")
        .nth(1)
        .and_then(|rest| rest.split("```").nth(1))
        .expect("the README's example block");
    let shown: Vec<&str> = block.lines().skip(1).map(str::trim_end).collect();
    let mut app = bundled_prompt(HINGLISH, "middle-axis", (100, 30));
    press_all(&mut app, &[KeyCode::Char('2'), KeyCode::Enter]);
    let mut ticks = 0;
    while app.animating() && ticks < 1000 {
        apply_tick(&mut app, 100);
        ticks += 1;
    }
    settle_verdict(&mut app);
    let screen = render(&app);
    let rows: Vec<String> = screen
        .lines()
        .map(|l| l.trim_matches('"').trim_end().to_string())
        .collect();
    let from = |rows: &[&str]| rows.iter().position(|l| l.starts_with(" t = ")).unwrap();
    let readme_tail = &shown[from(&shown)..];
    let rows_ref: Vec<&str> = rows.iter().map(String::as_str).collect();
    let app_tail: Vec<&str> = rows_ref[from(&rows_ref)..]
        .iter()
        .copied()
        .filter(|l| !l.is_empty())
        .collect();
    assert_eq!(readme_tail, app_tail.as_slice(), "{screen}");
    // Above them, row for row: the title, the question, where the panels
    // stand (their drawings, sampled as frames come, and their legends,
    // marked without colour here, are left out).
    let frame = |rows: &[&str]| -> Vec<String> {
        rows[..from(rows)]
            .iter()
            .map(|l| match l.chars().next() {
                Some(c @ ('│' | '┌' | '└')) => c.to_string(),
                _ => l.to_string(),
            })
            .collect()
    };
    assert_eq!(frame(&shown), frame(&rows_ref), "{screen}");
}

/// A scene that labels its quantities has its plots name them as the
/// question does: A and B, not the equations' `xc` and `xh`.
#[test]
fn the_plots_name_the_quantities_as_the_question_does() {
    for lang in [ENGLISH, HINGLISH] {
        let mut app = bundled_prompt_in("oscillations", lang, "damping-settle", (100, 30));
        press_all(&mut app, &[KeyCode::Char('2'), KeyCode::Enter]);
        apply_tick(&mut app, 300);
        let screen = render(&app);
        let plot = if lang == ENGLISH {
            "┌ A, B against time"
        } else {
            "┌ A, B time ke saath"
        };
        assert!(screen.contains(plot), "{lang}:\n{screen}");
        assert!(
            screen.contains("phase portrait (A, v(A))"),
            "{lang}:\n{screen}"
        );
        assert!(!screen.contains("xc"), "{lang}:\n{screen}");
    }
}

/// At 40×12 a long question cannot stand whole beside the verdict (the
/// Hinglish damping question wraps to 9 lines): the keys' row offers `w`,
/// which shows the question whole with the verdict giving way, and `w`
/// again brings the verdict back. Both scene kinds, both languages.
#[test]
fn a_question_too_long_for_a_small_screen_is_read_whole_with_w() {
    let cases = [
        ("torque-free-rotation", "middle-axis", '2'),
        ("oscillations", "damping-settle", '2'),
    ];
    for (deck, id, choice) in cases {
        for lang in [ENGLISH, HINGLISH] {
            let mut app = bundled_prompt_in(deck, lang, id, (40, 12));
            let question = {
                let Screen::Predict(p) = app.screen() else {
                    panic!("not on the predict screen");
                };
                crate::text::render(app.decks[0].prompts[p.prompt].question.get(lang))
            };
            let missing = |screen: &str| -> Vec<String> {
                let shown: std::collections::HashSet<&str> = screen
                    .split(|c: char| c.is_whitespace() || c == '"')
                    .collect();
                question
                    .split_whitespace()
                    .filter(|w| !shown.contains(w))
                    .map(str::to_string)
                    .collect()
            };
            press_all(&mut app, &[KeyCode::Char(choice), KeyCode::Enter]);
            play_to_the_end(&mut app);
            let screen = render(&app);
            assert!(
                !missing(&screen).is_empty(),
                "{deck}/{id} {lang}: the question fits at 40×12, the case tests nothing:\n{screen}"
            );
            assert!(
                screen.lines().any(|l| l.contains(" w ")),
                "{deck}/{id} {lang}: the keys' row offers no `w`:\n{screen}"
            );
            press(&mut app, KeyCode::Char('w'));
            let screen = render(&app);
            assert_eq!(
                missing(&screen),
                Vec::<String>::new(),
                "{deck}/{id} {lang}: `w` shows the question whole:\n{screen}"
            );
            press(&mut app, KeyCode::Char('w'));
            let screen = render(&app);
            assert!(
                screen.contains('✗') || screen.contains('✓'),
                "{deck}/{id} {lang}: `w` again brings the verdict back:\n{screen}"
            );
        }
    }
}
