//! Card info (`i` on the review screen and in the browser), as Anki's: what
//! the item asks, its state now (due, stability, difficulty,
//! retrievability), and its review history, one line per answer: when, the
//! rating, the interval it gave, the time taken, the retrievability at
//! that moment and the stability and difficulty after it.

use chrono::{DateTime, TimeDelta, Utc};
use ratatui::Frame;
use ratatui::layout::{Margin, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;

use crate::catalog;
use crate::sched::{CardState, ItemKey, Rating, ReviewKind, State};
use crate::study::DayZone;
use crate::tui::action::Action;
use crate::tui::app::App;
use crate::tui::i18n::{Msg, Words, info as w};
use crate::tui::keymap::{Binding, Context};
use crate::tui::wrap::ellipsize;

use super::Nav;
use crossterm::event::KeyCode::{Char, Down, End, Esc, Home, PageDown, PageUp, Up};

pub const KEYS: &[Binding] = &[
    Binding::new(
        "j k ↑↓",
        Words("scroll the history", "history scroll karo"),
        &[
            (Down, Action::Down),
            (Up, Action::Up),
            (Char('j'), Action::Down),
            (Char('k'), Action::Up),
        ],
    ),
    Binding::new(
        "PgUp PgDn g G",
        Words("a page, the ends", "ek page, shuru / ant"),
        &[
            (PageUp, Action::PageUp),
            (PageDown, Action::PageDown),
            (Char('g'), Action::Top),
            (Char('G'), Action::Bottom),
            (Home, Action::Top),
            (End, Action::Bottom),
        ],
    ),
    Binding::new(
        "E",
        Words(
            "edit this item in its deck file",
            "yeh item uski deck file mein badlo",
        ),
        &[(Char('E'), Action::EditItem)],
    ),
    Binding::new(
        "Esc q i",
        Words("back", "wapas"),
        &[
            (Esc, Action::Back),
            (Char('q'), Action::Back),
            (Char('i'), Action::Back),
        ],
    ),
];

/// The key row that opens card info, shared by the review screen and the
/// browser.
pub const OPEN: Binding = Binding::new(
    "i",
    Words(
        "card info: its review history",
        "card info: iski review history",
    ),
    &[(Char('i'), Action::CardInfo)],
);

/// The width (cells) from which the history shows the full date and the
/// time taken.
pub const WIDE: u16 = 58;

/// One answer of the item's history.
#[derive(Debug, Clone, PartialEq)]
pub struct Answer {
    pub at: DateTime<Utc>,
    pub rating: Rating,
    pub kind: ReviewKind,
    /// From the answer to the due date it gave.
    pub interval: TimeDelta,
    pub took_ms: i64,
    /// The chance of recall at the moment of the answer (`None`: the
    /// first one).
    pub recall: Option<f64>,
    pub stability: Option<f64>,
    pub difficulty: Option<f64>,
}

pub struct InfoState {
    pub deck: usize,
    pub key: ItemKey,
    /// What the item asks, on one line.
    pub asked: String,
    /// Its state now (`None`: never answered).
    pub state: Option<CardState>,
    pub reps: u32,
    pub lapses: u32,
    pub recall_now: Option<f64>,
    /// Oldest first; undone answers left out.
    pub answers: Vec<Answer>,
    pub now: DateTime<Utc>,
    pub zone: DayZone,
    pub scroll: usize,
    /// Lines of the history in view at the last draw (for PgUp / PgDn).
    pub page: std::cell::Cell<usize>,
}

impl InfoState {
    /// Reads everything the screen shows (drawing does no I/O).
    /// After `E`: the item read again from its edited deck (what it asks,
    /// its history), at the same scroll.
    pub fn deck_edited(&mut self, app: &App, edited: &crate::tui::edit::Edited) {
        if edited.deck != self.deck {
            return;
        }
        if let Ok(fresh) = InfoState::open(app, self.deck, self.key.clone()) {
            let scroll = self.scroll;
            *self = fresh;
            self.scroll = scroll;
        }
    }

    pub fn open(app: &App, deck: usize, key: ItemKey) -> Result<InfoState, String> {
        let d = app.decks.get(deck).ok_or("no such deck")?;
        let index = match key.direction {
            crate::sched::Direction::Predict => d.prompts.iter().position(|p| p.id == key.card),
            crate::sched::Direction::Derive => d.derivations.iter().position(|x| x.id == key.card),
            _ => d.cards.iter().position(|c| c.id == key.card),
        };
        let asked = index
            .and_then(|i| catalog::asked(d, key.direction, i, &app.lang))
            .unwrap_or_default()
            .split_whitespace()
            .collect::<Vec<_>>()
            .join(" ");
        let s = &app.services.study;
        let now = app.services.now();
        let history = s.store.history(&key).map_err(|e| e.to_string())?;
        let cached = s.store.cached_state(&key).map_err(|e| e.to_string())?;
        // The item's deck's scheduler: its preset's parameters.
        let scheduler = s.scheduler_for(&key.deck);
        let mut before: Option<CardState> = None;
        let mut answers = Vec::new();
        for logged in history.into_iter().filter(|l| !l.undone) {
            let r = &logged.record;
            let recall = before
                .filter(|b| b.state != State::New)
                .map(|b| scheduler.retrievability(&b, r.reviewed_at));
            answers.push(Answer {
                at: r.reviewed_at,
                rating: r.rating,
                kind: r.kind,
                interval: r.after.due - r.reviewed_at,
                took_ms: r.duration_ms,
                recall,
                stability: r.after.stability,
                difficulty: r.after.difficulty,
            });
            // A cram answer leaves the schedule as it was.
            if r.kind != ReviewKind::Cram {
                before = Some(r.after);
            }
        }
        let state = cached.as_ref().map(|c| c.state);
        Ok(InfoState {
            deck,
            recall_now: state
                .filter(|x| x.state != State::New)
                .map(|x| scheduler.retrievability(&x, now)),
            state,
            reps: cached.as_ref().map_or(0, |c| c.reps),
            lapses: cached.as_ref().map_or(0, |c| c.lapses),
            key,
            asked: crate::text::safe::one_line(&asked).into_owned(),
            answers,
            now,
            zone: s.zone,
            scroll: 0,
            page: std::cell::Cell::new(10),
        })
    }

    fn date(&self, t: DateTime<Utc>) -> String {
        match self.zone {
            DayZone::Local => t
                .with_timezone(&chrono::Local)
                .format("%Y-%m-%d %H:%M")
                .to_string(),
            DayZone::Utc => t.format("%Y-%m-%d %H:%M").to_string(),
        }
    }

    /// The lines of the screen: the head, then the history (narrower
    /// than [`WIDE`] cells: the date without its year and time, and no
    /// time taken).
    pub fn lines(&self, app: &App, width: u16) -> (Vec<Line<'static>>, Vec<Line<'static>>) {
        let wide = width >= WIDE;
        let t = &app.theme;
        let lang = app.lang.as_str();
        let mut head = vec![
            Line::from(Span::styled(
                format!(
                    "{}/{}/{}",
                    self.key.deck,
                    self.key.card,
                    self.key.direction.as_str()
                ),
                t.dim(),
            )),
            Line::from(self.asked.clone()),
            Line::default(),
        ];
        let state_name = catalog::state_name(self.state.map_or(State::New, |s| s.state));
        let mut facts = vec![
            (w::STATE.get(lang), state_name.to_string()),
            (w::REVIEWS.get(lang), self.reps.to_string()),
            (w::LAPSES.get(lang), self.lapses.to_string()),
        ];
        if let Some(s) = self.state.filter(|s| s.state != State::New) {
            facts.push((w::DUE.get(lang), self.date(s.due)));
            if let Some(last) = s.last_review {
                facts.push((w::INTERVAL.get(lang), span(s.due - last)));
            }
            if let Some(x) = s.stability {
                facts.push((w::STABILITY.get(lang), days(x)));
            }
            if let Some(x) = s.difficulty {
                facts.push((w::DIFFICULTY.get(lang), format!("{x:.1}")));
            }
        }
        if let Some(r) = self.recall_now {
            facts.push((w::RECALL_NOW.get(lang), percent(r)));
        }
        for (label, value) in facts {
            head.push(Line::from(vec![
                Span::styled(format!("{label}: "), t.dim()),
                Span::raw(value),
            ]));
        }
        head.push(Line::default());
        let mut body = Vec::new();
        if self.answers.is_empty() {
            body.push(Line::from(Span::styled(
                w::NO_REVIEWS.get(lang).to_string(),
                t.dim(),
            )));
            return (head, body);
        }
        let row = |date: &str, rating: &str, ivl: &str, took: &str, r: &str, s: &str, d: &str| {
            if wide {
                format!("{date:<16} {rating:<8} {ivl:>6} {took:>6} {r:>5} {s:>6} {d:>4}")
            } else {
                format!("{date:<5} {rating:<7} {ivl:>6} {r:>5} {s:>6} {d:>4}")
            }
        };
        body.push(Line::from(Span::styled(
            row(
                w::DATE.get(lang),
                w::RATING.get(lang),
                w::IVL.get(lang),
                w::TOOK.get(lang),
                "R",
                "S",
                "D",
            ),
            t.dim(),
        )));
        // Newest first, as Anki lists them.
        for a in self.answers.iter().rev() {
            let rating = match a.kind {
                ReviewKind::Cram => format!("{}*", rating_name(app, a.rating)),
                _ => rating_name(app, a.rating).to_string(),
            };
            let date = if wide {
                self.date(a.at)
            } else {
                self.date(a.at).get(5..10).unwrap_or_default().to_string()
            };
            body.push(Line::from(row(
                &date,
                &ellipsize(&rating, if wide { 8 } else { 7 }),
                &span(a.interval),
                &format!("{:.1}s", a.took_ms as f64 / 1000.0),
                &a.recall.map_or("—".to_string(), percent),
                &a.stability.map_or("—".to_string(), days),
                &a.difficulty.map_or("—".to_string(), |d| format!("{d:.1}")),
            )));
        }
        body.push(Line::from(Span::styled(
            w::LEGEND.get(lang).to_string(),
            t.dim(),
        )));
        if self.answers.iter().any(|a| a.kind == ReviewKind::Cram) {
            body.push(Line::from(Span::styled(
                w::CRAM_NOTE.get(lang).to_string(),
                t.dim(),
            )));
        }
        (head, body)
    }
}

fn rating_name(app: &App, r: Rating) -> &'static str {
    app.tr(match r {
        Rating::Again => Msg::Again,
        Rating::Hard => Msg::Hard,
        Rating::Good => Msg::Good,
        Rating::Easy => Msg::Easy,
    })
}

fn percent(r: f64) -> String {
    format!("{:.0}%", (r * 100.0).clamp(0.0, 100.0))
}

fn days(x: f64) -> String {
    if x < 10.0 {
        format!("{x:.1}d")
    } else {
        format!("{x:.0}d")
    }
}

/// A span of time in its largest fitting unit: `10m`, `5h`, `3d`, `1.2y`.
pub fn span(d: TimeDelta) -> String {
    let m = d.num_minutes().max(0);
    if m < 60 {
        format!("{m}m")
    } else if m < 60 * 24 {
        format!("{}h", m / 60)
    } else if m < 60 * 24 * 365 {
        format!("{}d", (m as f64 / 1440.0).round() as i64)
    } else {
        format!("{:.1}y", m as f64 / (1440.0 * 365.25))
    }
}

impl super::View for InfoState {
    fn context(&self) -> Context {
        Context::Info
    }
    fn apply(&mut self, app: &mut App, action: Action) -> Nav {
        // The history's lines below its column names: one per answer and
        // the notes under them.
        let total = self.answers.len() + 2;
        let page = self.page.get().max(1);
        let last = total.saturating_sub(page);
        match action {
            Action::Back | Action::CardInfo => return Nav::Pop,
            Action::EditItem => {
                app.request_edit(self.deck, crate::tui::edit::Target::Item(self.key.clone()))
            }
            Action::Down => self.scroll = (self.scroll + 1).min(last),
            Action::Up => self.scroll = self.scroll.saturating_sub(1),
            Action::PageDown => self.scroll = (self.scroll + page).min(last),
            Action::PageUp => self.scroll = self.scroll.saturating_sub(page),
            Action::Top => self.scroll = 0,
            Action::Bottom => self.scroll = last,
            _ => {}
        }
        Nav::Stay
    }
    fn draw(&self, frame: &mut Frame, area: Rect, app: &App) {
        draw(frame, area, app, self)
    }
    fn name(&self) -> Msg {
        Msg::CardInfo
    }
    fn deck(&self) -> Option<usize> {
        Some(self.deck)
    }
}

pub fn draw(frame: &mut Frame, area: Rect, app: &App, s: &InfoState) {
    let inner = area.inner(Margin::new(1, 0));
    if inner.width == 0 || inner.height == 0 {
        return;
    }
    let (head, body) = s.lines(app, inner.width);
    // The head stays; the history scrolls below it (its column names
    // kept on top), and the head gives way when the screen is short.
    let head_h = (head.len() as u16).min(inner.height / 2);
    let [top, rest] = ratatui::layout::Layout::vertical([
        ratatui::layout::Constraint::Length(head_h),
        ratatui::layout::Constraint::Fill(1),
    ])
    .areas(inner);
    frame.render_widget(Paragraph::new(head), top);
    let mut body = body.into_iter();
    let Some(names) = body.next() else {
        return;
    };
    if rest.height == 0 {
        return;
    }
    let [names_area, list] = ratatui::layout::Layout::vertical([
        ratatui::layout::Constraint::Length(1),
        ratatui::layout::Constraint::Fill(1),
    ])
    .areas(rest);
    frame.render_widget(Paragraph::new(names), names_area);
    s.page.set(usize::from(list.height).max(1));
    let shown: Vec<Line> = body.skip(s.scroll).take(usize::from(list.height)).collect();
    frame.render_widget(Paragraph::new(shown), list);
}
