//! Review: a card's front, the answer on demand, then a rating that is
//! written to the review log before the next card appears.

use std::collections::HashMap;

use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Margin, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Paragraph};

use crate::deck::{Card, CardKind, Deck};
use crate::sched::typed::{self, TypedCheck};
use crate::sched::{CardState, CramQueue, Direction, ItemKey, Preview, Queue, Rating};
use crate::tui::action::Action;
use crate::tui::app::App;
use crate::tui::i18n::Msg;
use crate::tui::services::Stamp;
use crate::tui::wrap::{Run, wrap};

use super::Nav;

/// Where the cards come from.
pub enum Source {
    /// Today's due, learning and new cards.
    Daily(Queue),
    /// Every card now; answers logged as cram, scheduling unchanged.
    Cram(CramQueue),
}

#[derive(Debug, Clone, PartialEq)]
pub struct TypedAnswer {
    pub text: String,
    pub check: TypedCheck,
}

#[derive(Debug, Clone, PartialEq)]
pub enum Phase {
    /// The question; `input` holds a typed card's answer so far.
    Front { input: String },
    /// The answer, with what each rating would schedule.
    Back {
        typed: Option<TypedAnswer>,
        previews: Option<Box<[Preview; 4]>>,
    },
    /// Nothing left: the session summary.
    Done,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Session {
    pub reviewed: u32,
    pub again: u32,
}

pub struct ReviewState {
    pub deck: usize,
    pub cram: bool,
    pub source: Source,
    pub states: HashMap<ItemKey, CardState>,
    /// The item shown, and when it appeared (for the answer duration).
    pub current: Option<(ItemKey, Stamp)>,
    pub phase: Phase,
    pub session: Session,
    pub started: Stamp,
    /// Ratings of this screen, newest last: undo never reaches further back.
    pub rated: Vec<(ItemKey, Rating)>,
    /// The card shown is a typed card (its front takes text).
    pub typed: bool,
}

impl ReviewState {
    pub fn open(app: &mut App, deck: usize, cram: bool) -> Result<ReviewState, String> {
        let d = app.decks.get(deck).ok_or("no such deck")?;
        let now = app.services.now();
        let (source, states) = if cram {
            let states = app
                .services
                .store
                .states(&d.id)
                .map_err(|e| e.to_string())?;
            (
                Source::Cram(CramQueue::new(crate::sched::cram_items(d, None))),
                states,
            )
        } else {
            let (queue, states) = app.services.queue(d, now).map_err(|e| e.to_string())?;
            (Source::Daily(queue), states)
        };
        // Undo reaches back to the start of this review, never into another deck's.
        app.services
            .store
            .start_session()
            .map_err(|e| e.to_string())?;
        let mut state = ReviewState {
            deck,
            cram,
            source,
            states,
            current: None,
            phase: Phase::Done,
            session: Session::default(),
            started: app.services.stopwatch.stamp(),
            rated: Vec::new(),
            typed: false,
        };
        state.next_card(app);
        Ok(state)
    }

    fn next_card(&mut self, app: &App) {
        let now = app.services.now();
        let next = match &self.source {
            Source::Daily(q) => q.next(now).map(|(k, _)| k.clone()),
            Source::Cram(c) => c.next().cloned(),
        };
        self.show(app, next);
    }

    fn show(&mut self, app: &App, key: Option<ItemKey>) {
        match key {
            Some(key) => {
                self.typed = app
                    .decks
                    .get(self.deck)
                    .and_then(|d| d.card(&key.card))
                    .is_some_and(|c| c.kind == CardKind::Typed);
                self.current = Some((key, app.services.stopwatch.stamp()));
                self.phase = Phase::Front {
                    input: String::new(),
                };
            }
            None => {
                self.current = None;
                self.typed = false;
                self.phase = Phase::Done;
            }
        }
    }

    /// The card shown and which way it is asked.
    pub fn card<'a>(&self, deck: &'a Deck) -> Option<(&'a Card, Direction)> {
        let (key, _) = self.current.as_ref()?;
        deck.card(&key.card).map(|c| (c, key.direction))
    }

    /// "12 due · 3 learning · 5 new", or the cards left when cramming.
    pub fn progress(&self, app: &App) -> String {
        match &self.source {
            Source::Daily(q) => {
                let c = q.counts();
                format!(
                    "{} {} · {} {} · {} {}",
                    c.due,
                    app.tr(Msg::Due),
                    c.learning,
                    app.tr(Msg::Learning),
                    c.new,
                    app.tr(Msg::New)
                )
            }
            Source::Cram(c) => format!(
                "{} {} · {}",
                c.remaining(),
                app.tr(Msg::Cards),
                app.tr(Msg::Cram)
            ),
        }
    }
}

pub fn apply(app: &mut App, state: &mut ReviewState, action: Action) -> Nav {
    match (&mut state.phase, action) {
        (_, Action::Back) => return Nav::Pop,
        (_, Action::Undo) => undo(app, state),
        (_, Action::Explain) => return explain(app, state),
        (Phase::Front { input }, Action::Input(c)) => input.push(c),
        (Phase::Front { input }, Action::Backspace) => {
            input.pop();
        }
        (Phase::Front { .. }, Action::Reveal | Action::Submit) => reveal(app, state),
        (Phase::Back { .. }, Action::Rate(r)) => rate(app, state, r),
        (Phase::Back { typed, .. }, Action::Submit) => {
            let r = typed.as_ref().map_or(Rating::Good, |t| t.check.suggested);
            rate(app, state, r);
        }
        (Phase::Back { .. }, Action::OpenCardPrompt) => return open_prompt(app, state),
        (Phase::Done, Action::Submit | Action::Open) => return Nav::Pop,
        _ => {}
    }
    Nav::Stay
}

fn reveal(app: &mut App, state: &mut ReviewState) {
    let Some((key, _)) = state.current.clone() else {
        return;
    };
    let Some(deck) = app.decks.get(state.deck) else {
        return;
    };
    let typed = match (&state.phase, state.card(deck)) {
        (Phase::Front { input }, Some((card, _))) if card.kind == CardKind::Typed => {
            Some(TypedAnswer {
                text: input.clone(),
                check: typed::check(input, &card.accept),
            })
        }
        _ => None,
    };
    let previews = (!state.cram).then(|| {
        Box::new(
            app.services
                .scheduler
                .preview(&key, state.states.get(&key), app.services.now()),
        )
    });
    state.phase = Phase::Back { typed, previews };
}

fn rate(app: &mut App, state: &mut ReviewState, rating: Rating) {
    let Some((key, shown)) = state.current.clone() else {
        return;
    };
    let now = app.services.now();
    let duration = app.services.stopwatch.elapsed_ms(shown);
    let before = state.states.get(&key).copied();
    let s = &app.services.scheduler;
    let record = if state.cram {
        s.cram(&key, before.as_ref(), rating, now, duration)
    } else {
        s.review(&key, before.as_ref(), rating, now, duration)
    };
    // Durable before anything else changes: if the write fails, the card
    // stays on screen and the rating can be given again.
    if let Err(e) = app.services.store.record(&record) {
        app.error(e.to_string());
        return;
    }
    match &mut state.source {
        Source::Daily(q) => q.answered(&record),
        Source::Cram(c) => c.answered(&record),
    }
    if !state.cram {
        state.states.insert(key.clone(), record.after);
    }
    state.session.reviewed += 1;
    if rating == Rating::Again {
        state.session.again += 1;
    }
    state.rated.push((key, rating));
    app.status = None;
    state.next_card(app);
}

fn undo(app: &mut App, state: &mut ReviewState) {
    if state.rated.is_empty() {
        app.info(app.tr(Msg::NothingToUndo));
        return;
    }
    let record = match app.services.store.undo_last() {
        Ok(Some(r)) => r,
        Ok(None) => {
            app.info(app.tr(Msg::NothingToUndo));
            return;
        }
        Err(e) => {
            app.error(e.to_string());
            return;
        }
    };
    let key = record.record.key.clone();
    let restored = match app.services.store.state(&key) {
        Ok(s) => s,
        Err(e) => {
            app.error(e.to_string());
            None
        }
    };
    match &mut state.source {
        Source::Daily(q) => q.restore(&key, restored.as_ref()),
        Source::Cram(c) => c.restore(&key),
    }
    if !state.cram {
        match restored {
            Some(s) => state.states.insert(key.clone(), s),
            None => state.states.remove(&key),
        };
    }
    state.rated.pop();
    state.session.reviewed = state.session.reviewed.saturating_sub(1);
    if record.record.rating == Rating::Again {
        state.session.again = state.session.again.saturating_sub(1);
    }
    // The undone card comes back at once, as the learner expects.
    state.show(app, Some(key));
    app.info(app.tr(Msg::Undone));
}

fn explain(app: &mut App, state: &ReviewState) -> Nav {
    let Some(deck) = app.decks.get(state.deck) else {
        return Nav::Stay;
    };
    let section = state.card(deck).and_then(|(c, _)| c.explain.clone());
    match section {
        Some(id) => super::reader::open_at(app, state.deck, &id),
        None => Nav::Stay,
    }
}

fn open_prompt(app: &mut App, state: &ReviewState) -> Nav {
    let Some(deck) = app.decks.get(state.deck) else {
        return Nav::Stay;
    };
    let prompt = state
        .card(deck)
        .and_then(|(c, _)| c.prompt.as_ref())
        .and_then(|id| deck.prompts.iter().position(|p| &p.id == id));
    match prompt {
        Some(i) => Nav::Push(super::Screen::Predict(Box::new(
            super::predict::PredictState::new(app, state.deck, i),
        ))),
        None => Nav::Stay,
    }
}

fn rating_label(app: &App, r: Rating) -> &'static str {
    match r {
        Rating::Again => app.tr(Msg::Again),
        Rating::Hard => app.tr(Msg::Hard),
        Rating::Good => app.tr(Msg::Good),
        Rating::Easy => app.tr(Msg::Easy),
    }
}

/// "3m 20s", "45s", "1h 05m".
pub fn fmt_duration(ms: i64) -> String {
    let s = ms.max(0) / 1000;
    match s {
        s if s < 60 => format!("{s}s"),
        s if s < 3600 => format!("{}m {:02}s", s / 60, s % 60),
        s => format!("{}h {:02}m", s / 3600, (s % 3600) / 60),
    }
}

pub fn draw(frame: &mut Frame, area: Rect, app: &App, state: &ReviewState) {
    let t = &app.theme;
    let Some(deck) = app.decks.get(state.deck) else {
        return;
    };
    let [progress, rest] =
        Layout::vertical([Constraint::Length(1), Constraint::Fill(1)]).areas(area);
    frame.render_widget(
        Paragraph::new(Span::styled(
            format!(" {}", state.progress(app)),
            t.heading(),
        )),
        progress,
    );

    if state.phase == Phase::Done {
        draw_summary(frame, rest, app, state);
        return;
    }
    let Some((card, direction)) = state.card(deck) else {
        return;
    };
    let (question, answer) = match direction {
        Direction::Forward => (&card.front, &card.back),
        Direction::Backward => (&card.back, &card.front),
    };
    // Borders and a column of margin on each side.
    let width = rest.width.saturating_sub(4) as usize;
    let para = |text: &str, style| {
        wrap(
            &[Run::new(crate::text::render(text), style)],
            width,
            Run::new("", style),
            Run::new("", style),
        )
    };
    let mut lines = para(question.get(&app.lang), t.strong());
    lines.push(Line::default());
    match &state.phase {
        Phase::Front { input } => {
            if card.kind == CardKind::Typed {
                lines.push(Line::styled(app.tr(Msg::TypeAnswer), t.dim()));
                lines.push(Line::from(vec![
                    Span::styled("> ", t.key()),
                    Span::styled(format!("{input}▏"), t.strong()),
                ]));
            }
        }
        Phase::Back { typed, .. } => {
            lines.push(Line::styled("─".repeat(width.min(40)), t.dim()));
            lines.extend(para(answer.get(&app.lang), t.text()));
            if let Some(ta) = typed {
                lines.push(Line::default());
                let (mark, style) = match ta.check.verdict {
                    typed::Verdict::Exact => ("✓", t.good()),
                    typed::Verdict::Close => ("≈", t.warn()),
                    typed::Verdict::Wrong => ("✗", t.bad()),
                };
                lines.push(Line::from(vec![
                    Span::styled(format!("{mark} {}: ", app.tr(Msg::YouTyped)), style),
                    Span::raw(ta.text.clone()),
                ]));
                if let Some(n) = &ta.check.nearest {
                    lines.push(Line::from(vec![
                        Span::styled(format!("  {}: ", app.tr(Msg::Accepted)), t.dim()),
                        Span::raw(n.clone()),
                    ]));
                }
            }
            if let Some(p) = card.prompt.as_ref().and_then(|id| deck.prompt(id)) {
                lines.push(Line::default());
                let q = crate::text::render(p.question.get(&app.lang));
                lines.extend(wrap(
                    &[
                        Run::new(format!("{}: ", app.tr(Msg::TryPrompt)), t.heading()),
                        Run::new(q, t.text()),
                    ],
                    width,
                    Run::new("p ", t.key()),
                    Run::new("  ", t.text()),
                ));
            }
        }
        Phase::Done => {}
    }
    while lines.last().is_some_and(|l| l.spans.is_empty()) {
        lines.pop();
    }
    // The card is as tall as its text (a blank line above and below),
    // with the buttons right under it.
    let card_h = (lines.len() as u16 + 4).min(rest.height.saturating_sub(2));
    let [card_area, buttons, hints] = Layout::vertical([
        Constraint::Length(card_h),
        Constraint::Length(1),
        Constraint::Length(1),
    ])
    .areas(rest);
    let block = Block::default()
        .borders(Borders::ALL)
        .border_style(t.border());
    let inner = block.inner(card_area).inner(Margin::new(1, 1));
    frame.render_widget(block, card_area);
    frame.render_widget(Paragraph::new(lines), inner);

    // Rating buttons with the interval each would give.
    if let Phase::Back { typed, previews } = &state.phase {
        let suggested = typed.as_ref().map(|t| t.check.suggested);
        let mut spans = vec![Span::raw(" ")];
        for (i, r) in Rating::ALL.into_iter().enumerate() {
            let interval = previews
                .as_ref()
                .map(|p| format!(" {}", p[i].label))
                .unwrap_or_default();
            let mut style = t.rating(i);
            if suggested == Some(r) {
                style = style.patch(t.selected());
            }
            spans.push(Span::styled(format!("{} ", i + 1), t.key()));
            spans.push(Span::styled(
                format!("{}{interval}", rating_label(app, r)),
                style,
            ));
            spans.push(Span::raw("   "));
        }
        if let Some(r) = suggested {
            spans.push(Span::styled(
                format!("({}: {})", app.tr(Msg::Suggested), rating_label(app, r)),
                t.dim(),
            ));
        }
        frame.render_widget(Paragraph::new(Line::from(spans)), buttons);
    } else if card.kind != CardKind::Typed {
        frame.render_widget(
            Paragraph::new(Line::from(vec![
                Span::styled(" Space ", t.key()),
                Span::styled(app.tr(Msg::ShowAnswer), t.dim()),
            ])),
            buttons,
        );
    } else {
        frame.render_widget(
            Paragraph::new(Line::from(vec![
                Span::styled(" Enter ", t.key()),
                Span::styled(app.tr(Msg::ShowAnswer), t.dim()),
            ])),
            buttons,
        );
    }
    let mut h = vec![Span::raw(" ")];
    if card.explain.is_some() {
        h.push(Span::styled("e ", t.key()));
        h.push(Span::styled(
            format!("{}  ", app.tr(Msg::Explanation)),
            t.dim(),
        ));
    }
    h.push(Span::styled("u ", t.key()));
    h.push(Span::styled("undo", t.dim()));
    frame.render_widget(Paragraph::new(Line::from(h)), hints);
}

fn draw_summary(frame: &mut Frame, area: Rect, app: &App, state: &ReviewState) {
    let t = &app.theme;
    let s = state.session;
    let mut lines = Vec::new();
    if s.reviewed == 0 {
        lines.push(Line::styled(app.tr(Msg::NothingDue), t.heading()));
    } else {
        lines.push(Line::styled(app.tr(Msg::SessionDone), t.heading()));
        lines.push(Line::default());
        let rate = 100.0 * f64::from(s.again) / f64::from(s.reviewed);
        lines.push(Line::from(format!(
            "{} {} · {} {} · {} {:.0}%",
            s.reviewed,
            app.tr(Msg::Reviewed),
            app.tr(Msg::Time),
            fmt_duration(app.services.stopwatch.elapsed_ms(state.started)),
            app.tr(Msg::AgainRate),
            rate
        )));
    }
    if let Source::Daily(q) = &state.source
        && let Some(due) = q.next_learning_due()
    {
        let wait = due - app.services.now();
        lines.push(Line::default());
        lines.push(Line::styled(
            format!(
                "{} {} → {}",
                app.tr(Msg::Learning),
                app.tr(Msg::Due),
                crate::sched::format_interval(wait)
            ),
            t.dim(),
        ));
    }
    lines.push(Line::default());
    lines.push(Line::from(vec![
        Span::styled("Enter ", t.key()),
        Span::styled(app.tr(Msg::Back), t.dim()),
    ]));
    let inner = area.inner(Margin::new(2, 1));
    frame.render_widget(Paragraph::new(lines), inner);
}
