//! A wrong answer that stands for one of the deck's misconceptions: the
//! verdict shows its title, why it seems right and the fix in the
//! learner's language at every size (a verdict taller than its rows
//! scrolls with `j`, nothing cut), `e` opens where the deck explains it,
//! and the stored attempt keeps its id.

use crossterm::event::KeyCode;

use super::predict::{bundled_prompt_in, flat, play_to_the_end, verdict_of};
use super::predict_attempts::on_disk;
use super::{press, press_all, type_text};
use crate::tui::i18n::{ENGLISH, HINGLISH};
use crate::tui::keymap::Context;
use crate::tui::screens::Screen;
use crate::tui::testkit::{TestApp, render};

/// The rows of the screen, each as drawn.
fn rows(app: &TestApp) -> Vec<String> {
    render(app)
        .lines()
        .map(|l| l.trim_matches('"').to_string())
        .collect()
}

/// Where the verdict's last row says how far it scrolls, if it does.
fn marker(rows: &[String]) -> Option<(usize, bool)> {
    rows.iter().enumerate().find_map(|(i, r)| {
        let t = r.trim();
        if t.starts_with('↓') && t.ends_with("(j)") {
            Some((i, false))
        } else if t == "↑ (k)" {
            Some((i, true))
        } else {
            None
        }
    })
}

/// Everything the screen says once the verdict is read whole: the screen
/// as drawn and, while the verdict says more lines wait below, each line
/// `j` brings up (one a press, above the marker row).
fn read_whole(app: &mut TestApp) -> String {
    let first = rows(app);
    let Some((at, _)) = marker(&first) else {
        return flat(&first.join("\n"));
    };
    let mut text: Vec<String> = first[..at].to_vec();
    for _ in 0..200 {
        press(app, KeyCode::Char('j'));
        let now = rows(app);
        let (at, end) = marker(&now).expect("the verdict still scrolls");
        text.push(now[at - 1].clone());
        if end {
            return flat(&text.join("\n"));
        }
    }
    panic!("the verdict never ends");
}

fn words(s: &str) -> String {
    crate::text::render(s)
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
}

/// Choosing the choice that stands for misconception A of the torque-free
/// deck ("stays steady" on the middle axis) shows its title, steel-man and
/// fix beside the evidence, whole, at 100×30, 80×24 and 40×12 in both
/// languages; the attempt on disk names it; `e` opens its section.
#[test]
fn a_misconception_choice_shows_the_steel_man_and_the_fix_at_every_size() {
    for lang in [ENGLISH, HINGLISH] {
        for size in [(100, 30), (80, 24), (40, 12)] {
            let mut app = bundled_prompt_in("torque-free-rotation", lang, "middle-axis", size);
            press_all(&mut app, &[KeyCode::Char('1'), KeyCode::Enter]);
            play_to_the_end(&mut app);
            let v = verdict_of(&app);
            assert!(!v.correct);
            assert_eq!(v.misconception.as_deref(), Some("omega-constant"));
            let m = app.decks[0]
                .misconception("omega-constant")
                .unwrap()
                .clone();
            let said = read_whole(&mut app);
            for (part, text) in [
                ("title", &m.title),
                ("why it seems right", &m.why_it_seems_right),
                ("fix", &m.fix),
            ] {
                let want = words(text.get(lang));
                assert!(
                    said.contains(&want),
                    "{lang} {size:?}: the {part} {want:?} is not whole in\n{said}"
                );
            }
            let label = match lang {
                ENGLISH => "Why it seems right:",
                _ => "Sahi kyun lagta hai:",
            };
            assert!(said.contains(label), "{lang} {size:?}: {said}");
            if size == (40, 12) {
                // Past the end `j` stays there: one `k` brings a line back
                // (each key drawn, as the event loop does).
                for _ in 0..5 {
                    press(&mut app, KeyCode::Char('j'));
                    rows(&app);
                }
                press(&mut app, KeyCode::Char('k'));
                let more = match lang {
                    ENGLISH => "↓ 1 more line (j)",
                    _ => "↓ 1 aur line (j)",
                };
                assert!(
                    rows(&app).iter().any(|r| r.trim() == more),
                    "{:#?}",
                    rows(&app)
                );
            }
            // Beside the evidence: the run's flips.
            assert!(said.contains("flip") || said.contains("palat"), "{said}");
            let rows = on_disk(&app);
            let last = rows.last().expect("the attempt is kept");
            assert_eq!(last.prediction, "stable");
            assert_eq!(
                last.verdict
                    .as_ref()
                    .and_then(|v| v.misconception.as_deref()),
                Some("omega-constant"),
                "the stored attempt names its misconception"
            );
            // `e` opens where the deck explains the misconception.
            press(&mut app, KeyCode::Char('e'));
            let Screen::Reader(r) = app.screen() else {
                panic!("explanation not open");
            };
            let section = app.decks[0]
                .sections
                .iter()
                .position(|s| s.id == "mistake-omega-constant")
                .unwrap();
            assert_eq!(r.section, section, "{lang} {size:?}");
            press(&mut app, KeyCode::Esc);
            assert_eq!(app.context(), Context::PredictVerdict);
        }
    }
}

/// A right answer stands for no misconception: nothing is shown and the
/// attempt names none.
#[test]
fn a_right_choice_names_no_misconception() {
    let mut app = bundled_prompt_in("torque-free-rotation", ENGLISH, "middle-axis", (100, 30));
    press_all(&mut app, &[KeyCode::Char('2'), KeyCode::Enter]);
    play_to_the_end(&mut app);
    let screen = flat(&render(&app));
    assert!(screen.contains("✓ Right ✓"), "{screen}");
    assert!(!screen.contains("Common mistake"), "{screen}");
    let rows = on_disk(&app);
    let v = rows.last().unwrap().verdict.as_ref().unwrap();
    assert!(v.correct && v.misconception.is_none(), "{v:?}");
}

/// A wrong number in a range the deck maps to a misconception (the
/// small-angle period for a 170° swing) names it on screen and on disk; a
/// wrong number outside every range and slip names none.
#[test]
fn a_number_in_a_misconception_range_names_it() {
    for (typed, named) in [("2.0", Some("small-angle-formula")), ("3.3", None)] {
        let mut app = bundled_prompt_in("oscillations", ENGLISH, "pendulum-170-period", (100, 30));
        type_text(&mut app, typed);
        press(&mut app, KeyCode::Enter);
        play_to_the_end(&mut app);
        let said = read_whole(&mut app);
        let title = words(
            app.decks[0]
                .misconception("small-angle-formula")
                .unwrap()
                .title
                .get(ENGLISH),
        );
        assert_eq!(said.contains(&title), named.is_some(), "{typed}: {said}");
        let rows = on_disk(&app);
        let v = rows.last().unwrap().verdict.as_ref().unwrap();
        assert!(!v.correct);
        assert_eq!(v.misconception.as_deref(), named, "{typed}");
    }
}
