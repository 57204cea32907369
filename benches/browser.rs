//! The card browser with 50,000 items (target < 50 ms each), from the key
//! to the frame drawn (120×40) through the app's own code: the first frame
//! (every item's state and status read, the table drawn), cold (the first
//! opening: the search index is built behind it) and warm (opened before:
//! the index is kept); the first keystroke right after a cold opening
//! (drawn at once, "searching…") and the wall time until its results are
//! drawn (the index built meanwhile); one keystroke of search (the query parsed, the
//! items matched, the table drawn) for a first letter (the broadest fuzzy
//! match), a letter that completes `omega2`, a Backspace, a filter
//! (`is:leech`), a filter with text (`tag:euler omega`); a sort by the next
//! column; and a keystroke while sorted. Each is timed as wall time and
//! as CPU time of the UI thread.

use std::collections::BTreeMap;
use std::time::{Duration, Instant};

use chrono::{DateTime, TimeDelta, Utc};
use criterion::{Criterion, criterion_group, criterion_main};
use ratatui::Terminal;
use ratatui::backend::TestBackend;

use flipcard::deck::{Card, CardKind, Deck, Text};
use flipcard::sched::{Config, Direction, ItemKey, Rating, ReviewKind, Scheduler};
use flipcard::store::{AfterRating, StatusAction, Store};
use flipcard::tui::services::{Clock, DayZone, SearchCache, Services};
use flipcard::tui::theme::Theme;
use flipcard::tui::{Action, Tui, apply, view};

/// Cards of each kind: 30,000 basic + 10,000 reversed (two items each)...
const BASIC: usize = 30_000;
/// ... and 5,000 cloze cards of two numbers: 50,000 items.
const CLOZE: usize = 5_000;
const REVERSED: usize = 5_000;

fn text(en: String, hi: String) -> Text {
    Text(BTreeMap::from([("en".to_string(), en), ("hi-Latn".to_string(), hi)]).into())
}

fn deck() -> Deck {
    let mut cards = Vec::new();
    let card = |id: String, kind, front: Text, back: Text, tag: &str| Card {
        id,
        kind,
        front,
        back,
        accept: Vec::new(),
        accept_by_lang: Default::default(),
        explain: None,
        prompt: None,
        tags: vec![tag.to_string()],
        formula: None,
    };
    for i in 0..BASIC {
        cards.push(card(
            format!("basic-{i}"),
            CardKind::Basic,
            text(
                format!(
                    "Question {i}: what is the angular momentum $L_{{{}}}$ of body {i}?",
                    i % 3 + 1
                ),
                format!(
                    "Sawaal {i}: body {i} ka angular momentum $L_{{{}}}$ kya hai?",
                    i % 3 + 1
                ),
            ),
            text(
                format!(
                    "It is $I_{{{}}} \\omega_{{{}}}$, about {i} units.",
                    i % 3 + 1,
                    i % 3 + 1
                ),
                format!(
                    "Yeh $I_{{{}}} \\omega_{{{}}}$ hai, lagbhag {i} units.",
                    i % 3 + 1,
                    i % 3 + 1
                ),
            ),
            ["frames", "euler", "stability"][i % 3],
        ));
    }
    for i in 0..REVERSED {
        cards.push(card(
            format!("rev-{i}"),
            CardKind::Reversed,
            text(format!("Term {i}"), format!("Shabd {i}")),
            text(
                format!("Meaning {i} of the precession"),
                format!("Arth {i}"),
            ),
            "terms",
        ));
    }
    for i in 0..CLOZE {
        cards.push(card(
            format!("cloze-{i}"),
            CardKind::Cloze,
            text(
                format!("{{{{c1::Torque}}}} {i} changes {{{{c2::$\\vec L$::a vector}}}} in time."),
                format!("{{{{c1::Torque}}}} {i} {{{{c2::$\\vec L$::ek vector}}}} badalta hai."),
            ),
            Text::default(),
            "cloze",
        ));
    }
    Deck {
        parent: None,
        misconceptions: Vec::new(),
        explore: Vec::new(),
        derivations: Vec::new(),
        id: "big".into(),
        title: text("Big".into(), "Bada".into()),
        description: None,
        languages: vec!["en".into(), "hi-Latn".into()],
        cards,
        prompts: Vec::new(),
        scenes: Vec::new(),
        systems: Vec::new(),
        sections: Vec::new(),
        units: Vec::new(),
        path: "big.toml".into(),
    }
}

fn now() -> DateTime<Utc> {
    DateTime::parse_from_rfc3339("2026-03-02T09:00:00Z")
        .map(|t| t.with_timezone(&Utc))
        .unwrap_or_else(|e| panic!("{e}"))
}

/// A store where every other basic card has two reviews, and some items
/// are suspended and leeches.
fn store(dir: &std::path::Path, deck: &Deck) -> Store {
    let mut store = Store::open(dir).unwrap_or_else(|e| panic!("store: {e}"));
    let sched = Scheduler::new(&Config::default());
    let mut reviews = Vec::new();
    let t0 = now() - TimeDelta::days(30);
    for card in deck
        .cards
        .iter()
        .filter(|c| c.kind == CardKind::Basic)
        .step_by(2)
    {
        let key = ItemKey {
            deck: deck.id.clone(),
            card: card.id.clone(),
            direction: Direction::Forward,
        };
        let first = sched.review(&key, None, Rating::Good, t0, 3000);
        let second = sched.review(
            &key,
            Some(&first.after),
            Rating::Good,
            t0 + TimeDelta::days(5),
            3000,
        );
        reviews.push(first);
        reviews.push(second);
    }
    store
        .record_batch(&reviews)
        .unwrap_or_else(|e| panic!("record: {e}"));
    let marked: Vec<ItemKey> = deck
        .cards
        .iter()
        .step_by(50)
        .map(|c| ItemKey {
            deck: deck.id.clone(),
            card: c.id.clone(),
            direction: if c.kind == CardKind::Cloze {
                Direction::Cloze(1)
            } else {
                Direction::Forward
            },
        })
        .collect();
    store
        .set_status(&marked, StatusAction::Suspend, now(), None)
        .unwrap_or_else(|e| panic!("suspend: {e}"));
    // A few leeches through the rating path itself.
    let key = &marked[0];
    let lapse = flipcard::sched::ReviewRecord {
        kind: ReviewKind::Review,
        rating: Rating::Again,
        ..sched.review(key, None, Rating::Again, now(), 1000)
    };
    let after = AfterRating {
        leech_threshold: 1,
        leech_suspend: false,
        bury: Vec::new(),
        bury_until: now(),
    };
    store
        .record_study(&lapse, &after)
        .unwrap_or_else(|e| panic!("leech: {e}"));
    store
}

fn app(dir: &std::path::Path) -> Tui {
    let deck = deck();
    let store = store(dir, &deck);
    let services = Services::new(
        Clock::Fixed(now()),
        Config::default(),
        None,
        DayZone::Utc,
        store,
    );
    let mut app = Tui::new(vec![deck], services, "en", Theme::COLOR);
    app.size = (120, 40);
    app
}

fn draw(t: &mut Terminal<TestBackend>, app: &Tui) {
    t.draw(|f| view::draw(f, app))
        .unwrap_or_else(|e| panic!("draw: {e}"));
}

/// Time spent on a CPU by this thread, so that the figures do not depend on
/// how many other processes share the machine; wall time is measured as
/// well.
fn thread_cpu() -> Duration {
    let t = rustix::time::clock_gettime(rustix::time::ClockId::ThreadCPUTime);
    Duration::new(
        t.tv_sec.max(0) as u64,
        t.tv_nsec.clamp(0, 999_999_999) as u32,
    )
}

#[derive(Clone, Copy)]
enum Timer {
    Wall,
    UiThreadCpu,
}

impl Timer {
    fn name(self) -> &'static str {
        match self {
            Timer::Wall => "wall",
            Timer::UiThreadCpu => "ui thread cpu",
        }
    }
    fn time(self, f: impl FnOnce()) -> Duration {
        match self {
            Timer::Wall => {
                let start = Instant::now();
                f();
                start.elapsed()
            }
            Timer::UiThreadCpu => {
                let start = thread_cpu();
                f();
                thread_cpu().saturating_sub(start)
            }
        }
    }
}

/// Times `step` (a key and the frame drawn after it) `n` times, with
/// `reset` (not timed) after each.
fn keys(
    clock: Timer,
    n: u64,
    app: &mut Tui,
    t: &mut Terminal<TestBackend>,
    step: &[Action],
    reset: &[Action],
) -> Duration {
    let mut total = Duration::ZERO;
    for _ in 0..n {
        total += clock.time(|| {
            for a in step {
                apply(app, *a);
            }
            draw(t, app);
        });
        for a in reset {
            apply(app, *a);
        }
    }
    total
}

/// Ticks, as the event loop does, until a search waiting for the index
/// has run.
fn settle(app: &mut Tui) {
    while app.animating() {
        std::thread::sleep(Duration::from_micros(200));
        apply(app, Action::Tick(Duration::from_micros(200)));
    }
}

fn typed(app: &mut Tui, text: &str) {
    for ch in text.chars() {
        apply(app, Action::Input(ch));
    }
}

fn browser(c: &mut Criterion) {
    let dir = tempfile::tempdir().unwrap_or_else(|e| panic!("temp dir: {e}"));
    let mut app = app(dir.path());
    let mut t = Terminal::new(TestBackend::new(120, 40)).unwrap_or_else(|e| panic!("{e}"));
    let mut g = c.benchmark_group("browser");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(8));
    let clocks = [Timer::Wall, Timer::UiThreadCpu];
    let items = "50,000 items";
    // Cold: the first opening, nothing kept (the search index is built
    // behind the first frame).
    for clock in clocks {
        g.bench_function(
            format!("first_frame cold ({items}, {})", clock.name()),
            |b| {
                b.iter_custom(|n| {
                    let mut total = Duration::ZERO;
                    for _ in 0..n {
                        app.services.browser_index = SearchCache::default();
                        total += keys(clock, 1, &mut app, &mut t, &[Action::OpenBrowser], &[]);
                        apply(&mut app, Action::Back);
                    }
                    total
                })
            },
        );
    }
    // The first key typed right after a cold opening is drawn at once
    // ("searching…"); its results wait for the index (the next case).
    for clock in clocks {
        g.bench_function(
            format!(
                "first keystroke `o` right after a cold opening ({items}, {})",
                clock.name()
            ),
            |b| {
                b.iter_custom(|n| {
                    let mut total = Duration::ZERO;
                    for _ in 0..n {
                        app.services.browser_index = SearchCache::default();
                        apply(&mut app, Action::OpenBrowser);
                        draw(&mut t, &app);
                        apply(&mut app, Action::StartSearch);
                        total += keys(clock, 1, &mut app, &mut t, &[Action::Input('o')], &[]);
                        apply(&mut app, Action::Back);
                    }
                    total
                })
            },
        );
    }
    // Wall time from that key to the frame with its results, the index
    // built meanwhile on two threads.
    g.bench_function(
        format!("results of `o` right after a cold opening ({items}, wall)"),
        |b| {
            b.iter_custom(|n| {
                let mut total = Duration::ZERO;
                for _ in 0..n {
                    app.services.browser_index = SearchCache::default();
                    apply(&mut app, Action::OpenBrowser);
                    draw(&mut t, &app);
                    apply(&mut app, Action::StartSearch);
                    let start = Instant::now();
                    apply(&mut app, Action::Input('o'));
                    settle(&mut app);
                    draw(&mut t, &app);
                    total += start.elapsed();
                    apply(&mut app, Action::Back);
                }
                total
            })
        },
    );
    // Warm: opened before, the decks unchanged, the index kept.
    apply(&mut app, Action::OpenBrowser);
    apply(&mut app, Action::StartSearch);
    apply(&mut app, Action::Input('o'));
    settle(&mut app);
    apply(&mut app, Action::Back);
    for clock in clocks {
        g.bench_function(
            format!("first_frame warm ({items}, {})", clock.name()),
            |b| {
                b.iter_custom(|n| {
                    keys(
                        clock,
                        n,
                        &mut app,
                        &mut t,
                        &[Action::OpenBrowser],
                        &[Action::Back],
                    )
                })
            },
        );
    }
    apply(&mut app, Action::OpenBrowser);
    apply(&mut app, Action::StartSearch);
    let input = Action::Input;
    for (name, prefix, step, reset) in [
        (
            "keystroke: first letter `o`",
            "",
            input('o'),
            Action::Backspace,
        ),
        (
            "keystroke: `omega` → `omega2`",
            "omega",
            input('2'),
            Action::Backspace,
        ),
        (
            "keystroke: `omega2` → Backspace → `omega`",
            "omega2",
            Action::Backspace,
            input('2'),
        ),
        (
            "keystroke: `is:leec` → `is:leech`",
            "is:leec",
            input('h'),
            Action::Backspace,
        ),
        (
            "keystroke: `tag:euler omeg` → `tag:euler omega`",
            "tag:euler omeg",
            input('a'),
            Action::Backspace,
        ),
    ] {
        typed(&mut app, prefix);
        for clock in clocks {
            g.bench_function(format!("{name} ({items}, {})", clock.name()), |b| {
                b.iter_custom(|n| keys(clock, n, &mut app, &mut t, &[step], &[reset]))
            });
        }
        for _ in prefix.chars() {
            apply(&mut app, Action::Backspace);
        }
    }
    // A sort by the next column over every row (each press a new column,
    // all eleven in turn), then a key typed while sorted.
    apply(&mut app, Action::Submit);
    for clock in clocks {
        g.bench_function(
            format!("sort by the next column `o` ({items}, {})", clock.name()),
            |b| b.iter_custom(|n| keys(clock, n, &mut app, &mut t, &[Action::NextSort], &[])),
        );
    }
    apply(&mut app, Action::StartSearch);
    typed(&mut app, "omega");
    for clock in clocks {
        g.bench_function(
            format!(
                "keystroke while sorted: `omega` → `omega2` ({items}, {})",
                clock.name()
            ),
            |b| {
                b.iter_custom(|n| {
                    keys(
                        clock,
                        n,
                        &mut app,
                        &mut t,
                        &[input('2')],
                        &[Action::Backspace],
                    )
                })
            },
        );
    }
    g.finish();
}

/// The study filter (`f` on home) over the same 50,000 items: opening it
/// (every item counted), one key of the tag field (`euler` completed: the
/// count of matching items again), a state chosen, and Enter (the filtered
/// session's first card drawn).
fn filter(c: &mut Criterion) {
    let dir = tempfile::tempdir().unwrap_or_else(|e| panic!("temp dir: {e}"));
    let mut app = app(dir.path());
    let mut t = Terminal::new(TestBackend::new(120, 40)).unwrap_or_else(|e| panic!("{e}"));
    let mut g = c.benchmark_group("filter");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(8));
    let items = "50,000 items";
    for clock in [Timer::Wall, Timer::UiThreadCpu] {
        g.bench_function(
            format!("open with its count ({items}, {})", clock.name()),
            |b| {
                b.iter_custom(|n| {
                    keys(
                        clock,
                        n,
                        &mut app,
                        &mut t,
                        &[Action::OpenFilter],
                        &[Action::Back],
                    )
                })
            },
        );
        apply(&mut app, Action::OpenFilter);
        typed(&mut app, "eule");
        g.bench_function(
            format!(
                "tag key `eule` → `euler` and the count ({items}, {})",
                clock.name()
            ),
            |b| {
                b.iter_custom(|n| {
                    keys(
                        clock,
                        n,
                        &mut app,
                        &mut t,
                        &[Action::Input('r')],
                        &[Action::Backspace],
                    )
                })
            },
        );
        apply(&mut app, Action::Input('r'));
        apply(&mut app, Action::NextField);
        g.bench_function(
            format!(
                "state field: next state and the count ({items}, {})",
                clock.name()
            ),
            |b| {
                b.iter_custom(|n| {
                    keys(
                        clock,
                        n,
                        &mut app,
                        &mut t,
                        &[Action::NextSection],
                        &[Action::PrevSection],
                    )
                })
            },
        );
        apply(&mut app, Action::PrevField);
        // Enter replaces the filter with the session: back home, the filter
        // opened again with the same tag (not timed).
        let reopen: Vec<Action> = [Action::Back, Action::OpenFilter]
            .into_iter()
            .chain("euler".chars().map(Action::Input))
            .collect();
        g.bench_function(
            format!(
                "Enter: the filtered session's first card ({items}, {})",
                clock.name()
            ),
            |b| b.iter_custom(|n| keys(clock, n, &mut app, &mut t, &[Action::Submit], &reopen)),
        );
        apply(&mut app, Action::Back);
    }
    g.finish();
}

criterion_group!(benches, browser, filter);
criterion_main!(benches);
