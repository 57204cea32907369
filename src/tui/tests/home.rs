//! The home screen, help overlay, language toggle and small terminals.

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};

use super::{key, press};
use crate::tui::action::Action;
use crate::tui::i18n::{ENGLISH, HINGLISH};
use crate::tui::keymap::Context;
use crate::tui::screens::Screen;
use crate::tui::testkit::{self, render};
use crate::tui::update::apply;

#[test]
fn home_keys() {
    let app = testkit::app(ENGLISH);
    assert_eq!(app.context(), Context::Home);
    let cases = [
        (KeyCode::Enter, Action::OpenReview),
        (KeyCode::Char('c'), Action::OpenCram),
        (KeyCode::Char('r'), Action::OpenReader),
        (KeyCode::Char('p'), Action::OpenPrompts),
        (KeyCode::Char('t'), Action::OpenStats),
        (KeyCode::Char('l'), Action::ToggleLanguage),
        (KeyCode::Char('?'), Action::ToggleHelp),
        (KeyCode::Char('q'), Action::Quit),
        (KeyCode::Char('j'), Action::Down),
        (KeyCode::Up, Action::Up),
    ];
    for (code, action) in cases {
        assert_eq!(key(&app, code), Some(action), "{code:?}");
    }
    assert_eq!(key(&app, KeyCode::Char('z')), None);
}

#[test]
fn ctrl_c_quits_from_anywhere_even_under_help() {
    let mut app = testkit::app(ENGLISH);
    app.help = true;
    let ctrl_c = KeyEvent::new(KeyCode::Char('c'), KeyModifiers::CONTROL);
    assert_eq!(crate::tui::key_action(&app, ctrl_c), Some(Action::Quit));
    apply(&mut app, Action::Quit);
    assert!(app.quit);
}

#[test]
fn help_opens_and_any_key_closes_it() {
    let mut app = testkit::app(ENGLISH);
    press(&mut app, KeyCode::Char('?'));
    assert!(app.help);
    assert_eq!(key(&app, KeyCode::Char('q')), Some(Action::CloseHelp));
    press(&mut app, KeyCode::Char('q'));
    assert!(!app.help);
    assert!(!app.quit, "the key that closes help does nothing else");
}

#[test]
fn q_on_home_quits() {
    let mut app = testkit::app(ENGLISH);
    press(&mut app, KeyCode::Char('q'));
    assert!(app.quit);
}

#[test]
fn language_toggles_both_ways_and_changes_the_interface() {
    let mut app = testkit::app(ENGLISH);
    let before = render(&app);
    press(&mut app, KeyCode::Char('l'));
    assert_eq!(app.lang, HINGLISH);
    let after = render(&app);
    assert!(after.contains("Hinglish"), "{after}");
    assert!(after.contains("baaki"), "{after}");
    press(&mut app, KeyCode::Char('l'));
    assert_eq!(app.lang, ENGLISH);
    assert_eq!(render(&app), before);
}

#[test]
fn every_context_has_help_for_every_bound_key() {
    use Context::*;
    for ctx in [
        Home,
        Reader,
        ReaderSearch,
        ReviewFront,
        ReviewTyping,
        ReviewDerive,
        ReviewBack,
        ReviewDone,
        Prompts,
        PredictChoice,
        PredictNumber,
        PredictFormula,
        PredictRun,
        PredictVerdict,
        PredictExplore,
        Stats,
    ] {
        let binds = crate::tui::screens::bindings(ctx);
        assert!(binds.iter().any(|b| b.label.contains("F1")), "{ctx:?}");
        for b in &binds {
            assert!(
                !b.help.0.is_empty() && !b.help.1.is_empty(),
                "{ctx:?} {}",
                b.label
            );
        }
    }
}

#[test]
fn too_small_terminal_shows_a_message_and_never_panics() {
    let mut app = testkit::app(ENGLISH);
    for (w, h) in [(39, 24), (80, 11), (20, 6), (1, 1), (2, 1), (1, 5)] {
        app.size = (w, h);
        let text = render(&app);
        if w >= 10 && h >= 3 {
            assert!(text.contains("enlarge"), "{w}×{h}: {text}");
        }
    }
    app.size = (40, 12);
    assert!(!render(&app).contains("enlarge"));
}

#[test]
fn every_screen_survives_every_size() {
    use KeyCode::{Char, Enter};
    let routes: [&[KeyCode]; 8] = [
        &[],
        &[Enter],
        &[Enter, Char(' ')],
        &[Char('r')],
        &[Char('r'), Char('/'), Char('x')],
        &[Char('p')],
        &[Char('p'), Enter],
        &[Char('t')],
    ];
    for route in routes {
        let mut app = testkit::app(ENGLISH);
        super::press_all(&mut app, route);
        for w in [1, 3, 39, 40, 41, 60, 200] {
            for h in [1, 2, 11, 12, 13, 50] {
                apply(&mut app, Action::Resize(w, h));
                super::press_all(&mut app, &[KeyCode::Down, KeyCode::End, KeyCode::PageUp]);
                app.help = false;
                render(&app);
                app.help = true;
                render(&app);
            }
        }
    }
}

#[test]
fn snapshot_home() {
    let app = testkit::app(ENGLISH);
    insta::assert_snapshot!(render(&app));
    let app = testkit::app(HINGLISH);
    insta::assert_snapshot!("home_hinglish", render(&app));
}

#[test]
fn snapshot_home_help() {
    for lang in [ENGLISH, HINGLISH] {
        let mut app = testkit::app(lang);
        press(&mut app, KeyCode::Char('?'));
        insta::assert_snapshot!(format!("home_help_{lang}"), render(&app));
    }
}

#[test]
fn prompts_list_opens_and_closes() {
    let mut app = testkit::app(ENGLISH);
    press(&mut app, KeyCode::Char('p'));
    assert!(matches!(app.screen(), Screen::Prompts(_)));
    press(&mut app, KeyCode::Char('j'));
    let Screen::Prompts(p) = app.screen() else {
        unreachable!()
    };
    assert_eq!(p.selected, 1);
    press(&mut app, KeyCode::Char('j'));
    let Screen::Prompts(p) = app.screen() else {
        unreachable!()
    };
    assert_eq!(p.selected, 1, "stays on the last prompt");
    for lang in [ENGLISH, HINGLISH] {
        app.lang = lang.into();
        insta::assert_snapshot!(format!("prompts_{lang}"), render(&app));
    }
    press(&mut app, KeyCode::Esc);
    assert!(matches!(app.screen(), Screen::Home(_)));
}

/// Every screen the colour tests look at, as key routes from home.
fn colour_routes() -> Vec<Vec<KeyCode>> {
    use KeyCode::{Char, Enter};
    vec![
        vec![],
        vec![Enter, Char(' ')],
        vec![Char('r')],
        vec![Char('p'), Enter, Char('2'), Enter],
        vec![Char('t')],
        vec![Char('?')],
    ]
}

#[test]
fn no_color_means_no_colours_at_all() {
    use ratatui::style::Color;
    for route in colour_routes() {
        let mut app = testkit::app(ENGLISH);
        app.theme = crate::tui::theme::Theme::PLAIN;
        super::press_all(&mut app, &route);
        apply(
            &mut app,
            Action::Tick(std::time::Duration::from_millis(500)),
        );
        let buf = testkit::buffer(&app);
        for cell in buf.content() {
            assert_eq!(cell.fg, Color::Reset, "{route:?}: {cell:?}");
            assert_eq!(cell.bg, Color::Reset, "{route:?}: {cell:?}");
        }
    }
}

#[test]
fn colours_are_the_sixteen_every_terminal_has() {
    use ratatui::style::Color;
    let mut used = std::collections::BTreeSet::new();
    for route in colour_routes() {
        let mut app = testkit::app(ENGLISH);
        app.theme = crate::tui::theme::Theme::COLOR;
        super::press_all(&mut app, &route);
        apply(
            &mut app,
            Action::Tick(std::time::Duration::from_millis(500)),
        );
        for cell in testkit::buffer(&app).content() {
            for c in [cell.fg, cell.bg] {
                assert!(
                    !matches!(c, Color::Rgb(..) | Color::Indexed(_)),
                    "{route:?}: {c:?} is not one of the 16 ANSI colours"
                );
                used.insert(format!("{c:?}"));
            }
        }
    }
    assert!(used.len() > 4, "the colour theme uses colours: {used:?}");
}

#[test]
fn the_language_choice_is_saved_for_the_next_run() {
    let mut app = testkit::app(ENGLISH);
    let path = app.dir.path().join("config.toml");
    std::fs::write(&path, "# my settings\nnew_per_day = 5\n").unwrap_or_else(|e| panic!("{e}"));
    app.services.config_path = Some(path.clone());
    press(&mut app, KeyCode::Char('l'));
    let saved = crate::sched::Config::load(Some(&path)).map(|c| (c.language, c.new_per_day));
    assert_eq!(saved.ok(), Some((HINGLISH.to_string(), 5)));
    let text = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(text.contains("# my settings"), "comments survive: {text}");
    // A config that cannot be written is reported, not fatal.
    app.services.config_path = Some(app.dir.path().join("no-such-dir/\0/config.toml"));
    press(&mut app, KeyCode::Char('l'));
    assert_eq!(app.lang, ENGLISH);
    assert!(
        app.status.as_ref().is_some_and(|s| s.error),
        "{:?}",
        app.status
    );
}

#[test]
fn help_overlay_of_every_screen_in_both_languages() {
    use KeyCode::{Char, Enter, F};
    let routes: [(&str, &[KeyCode]); 7] = [
        ("prompts", &[Char('p')]),
        ("predict_choice", &[Char('p'), Enter]),
        ("predict_number", &[Char('p'), Char('j'), Enter]),
        ("stats", &[Char('t')]),
        ("reader_search", &[Char('r'), Char('/')]),
        (
            "review_done",
            &[
                Enter,
                Char(' '),
                Char('4'),
                Char(' '),
                Char('4'),
                Char(' '),
                Char('4'),
            ],
        ),
        (
            "review_typing",
            &[
                Enter,
                Char(' '),
                Char('4'),
                Char(' '),
                Char('4'),
                Char(' '),
                Char('4'),
            ],
        ),
    ];
    for (name, route) in routes {
        for lang in [ENGLISH, HINGLISH] {
            let mut app = testkit::app(lang);
            super::press_all(&mut app, route);
            if name == "review_done" {
                super::type_text(&mut app, "middle");
                super::press_all(&mut app, &[Enter, Char('4')]);
            }
            insta::assert_snapshot!(format!("screen_{name}_{lang}"), render(&app));
            // F1 opens the help everywhere, even where `?` is typed into a field.
            press(&mut app, F(1));
            assert!(app.help, "{name}: F1 opens the help");
            insta::assert_snapshot!(format!("screen_{name}_help_{lang}"), render(&app));
        }
    }
}

#[test]
fn keys_do_nothing_unseen_while_the_terminal_is_too_small() {
    let mut app = testkit::app(ENGLISH);
    press(&mut app, KeyCode::Enter);
    press(&mut app, KeyCode::Char(' '));
    apply(&mut app, Action::Resize(20, 6));
    assert_eq!(key(&app, KeyCode::Char('3')), None, "no rating blind");
    assert_eq!(key(&app, KeyCode::Esc), None, "nothing closes unseen");
    assert_eq!(
        key(&app, KeyCode::Char('q')),
        Some(Action::Quit),
        "q quits, as the message offers"
    );
    assert!(flat(&render(&app)).contains("press q to quit"));
    let ctrl_c = KeyEvent::new(KeyCode::Char('c'), KeyModifiers::CONTROL);
    assert_eq!(
        crate::tui::key_action(&app, ctrl_c),
        Some(Action::Quit),
        "Ctrl-C still quits"
    );
    apply(&mut app, Action::Resize(80, 24));
    assert!(matches!(
        key(&app, KeyCode::Char('3')),
        Some(Action::Rate(_))
    ));
}

#[test]
fn a_long_error_wraps_above_the_footer_instead_of_being_cut() {
    let mut app = testkit::app(ENGLISH);
    app.size = (60, 20);
    let path = "/home/learner/.local/share/flipcard/backups/flipcard-2026-03-01.db";
    app.error(format!(
        "database /home/learner/.local/share/flipcard/flipcard.db is corrupt; the newest backup is {path}"
    ));
    let screen = render(&app);
    let joined: String = screen
        .lines()
        .map(|l| l.trim_matches('"').trim_end())
        .collect::<Vec<_>>()
        .join("");
    assert!(joined.contains(path), "{screen}");
    // The footer's last line holds the end of the message.
    let last = screen.lines().last().unwrap_or_default();
    assert!(last.contains("01.db"), "{screen}");
}

#[test]
fn no_decks_says_how_many_files_failed_and_how_to_see_why() {
    use crate::tui::app::DeckLoad;
    let mut app = testkit::app(ENGLISH);
    app.decks.clear();
    app.deck_load = DeckLoad {
        from: Some("/srv/course/decks".into()),
        errors: 5,
        failed_files: 2,
        failed: Vec::new(),
    };
    let screen = flat(&render(&app));
    assert!(screen.contains("2 files have errors"), "{screen}");
    assert!(
        screen.contains("flipcard check /srv/course/decks"),
        "{screen}"
    );
    app.deck_load = DeckLoad {
        from: Some("/srv/empty".into()),
        errors: 0,
        failed_files: 0,
        failed: Vec::new(),
    };
    let screen = render(&app);
    assert!(screen.contains("No decks found in /srv/empty"), "{screen}");
}

/// The screen's text as one line: rows trimmed and joined by spaces, so
/// that wrapped sentences can be searched.
fn flat(screen: &str) -> String {
    screen
        .lines()
        .map(|l| l.trim_matches('"').trim())
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join(" ")
}

#[test]
fn counts_of_one_read_in_the_singular_in_both_languages() {
    for (lang, one, two) in [
        (ENGLISH, "1 problem in the decks", "2 problems in the decks"),
        (HINGLISH, "1 decks mein galti ", "2 decks mein galtiyan "),
    ] {
        let mut app = testkit::app(lang);
        let deck = &mut app.decks[0];
        deck.cards.truncate(1);
        deck.prompts.truncate(1);
        deck.sections.truncate(1);
        app.deck_load.errors = 1;
        let text = render(&app);
        assert!(text.contains("1 card · 1 prompt · 1 section "), "{text}");
        assert!(text.contains(one), "{text}");
        app.deck_load.errors = 2;
        let text = render(&app);
        assert!(text.contains(two), "{text}");
    }
}

#[test]
fn no_decks_counts_failed_files_in_the_singular_in_hinglish_too() {
    use crate::tui::app::DeckLoad;
    let mut app = testkit::app(HINGLISH);
    app.decks.clear();
    for (files, text) in [(1, "1 file mein galtiyan"), (2, "2 files mein galtiyan")] {
        app.deck_load = DeckLoad {
            from: Some("/srv/decks".into()),
            errors: 3,
            failed_files: files,
            failed: Vec::new(),
        };
        let screen = flat(&render(&app));
        assert!(screen.contains(text), "{screen}");
    }
}

#[test]
fn prompts_list_shows_extreme_scene_values_with_exponents() {
    let mut deck = testkit::deck();
    let scene = &mut deck.scenes[0];
    scene.inertia = [1e-300, 2e-300, 3e-300];
    scene.omega = [1e150, 1e150, 5e149];
    scene.duration = 5e-324;
    let dir = tempfile::tempdir().unwrap();
    let mut app = crate::tui::Tui::new(
        vec![deck],
        testkit::services(&dir),
        ENGLISH,
        crate::tui::theme::Theme::PLAIN,
    );
    app.size = (120, 30);
    press(&mut app, KeyCode::Char('p'));
    assert!(matches!(app.screen(), Screen::Prompts(_)));
    let screen = render(&app);
    assert!(screen.contains("I = (1e-300, 2e-300, 3e-300)"), "{screen}");
    assert!(screen.contains("5e-324 s"), "{screen}");
    let longest = screen
        .split(|c: char| !c.is_ascii_digit())
        .map(str::len)
        .max()
        .unwrap_or(0);
    assert!(longest < 30, "a {longest}-digit run in\n{screen}");
}

#[test]
fn decks_left_out_are_named_above_the_ones_that_opened() {
    for (lang, said) in [
        (ENGLISH, "Run `flipcard decks` to see why"),
        (HINGLISH, "`flipcard decks` chalao"),
    ] {
        let mut app = testkit::app(lang);
        app.deck_load.failed = vec!["/srv/course/broken.toml".into()];
        app.deck_load.failed_files = 1;
        let screen = flat(&render(&app));
        assert!(screen.contains("/srv/course/broken.toml"), "{screen}");
        assert!(screen.contains(said), "{screen}");
        let title = app.decks[0].title.get(lang).to_string();
        assert!(
            screen.contains(&title),
            "the good deck still shows: {screen}"
        );
    }
}

#[test]
fn esc_on_home_says_how_to_quit_and_q_quits() {
    // Esc backs out of every screen; on the first one it used to close the
    // app under a learner who pressed it once too often.
    let mut app = testkit::app(ENGLISH);
    press(&mut app, KeyCode::Esc);
    assert!(!app.quit, "Esc on home closed the app");
    assert!(
        render(&app).contains("you are on the first screen: q quits"),
        "{}",
        render(&app)
    );
    press(&mut app, KeyCode::Char('q'));
    assert!(app.quit);
}

/// At 40×12 the selected deck's details took every row below the list's
/// first deck, hiding the others: the list keeps its decks (up to five) and
/// the details are cut from their end instead, in both languages.
#[test]
fn a_small_terminal_still_lists_every_deck() {
    for lang in [ENGLISH, HINGLISH] {
        let mut app = testkit::app(lang);
        app.decks = crate::bundled::load().decks;
        assert!(app.decks.len() >= 2, "the test needs two decks");
        app.size = (40, 12);
        let text = render(&app);
        for deck in &app.decks {
            let title: String = deck.title.get(&app.lang).chars().take(20).collect();
            assert!(text.contains(&title), "{title} missing at 40×12:\n{text}");
        }
        // The keys stay, and the selected deck's counts still show.
        assert!(text.contains("q "), "{text}");
        assert!(text.contains(" · 0 "), "{text}");
    }
}
