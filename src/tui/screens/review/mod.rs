//! Review: a card's front, the answer on demand, then a rating that is
//! written to the review log before the next card appears.

use crate::deck::{Card, CardKind, Deck};
use crate::sched::typed::{self, TypedCheck};
use crate::sched::{CramQueue, Direction, ItemKey, Preview, Queue, Rating, States};
use crate::tui::action::Action;
use crate::tui::app::App;
use crate::tui::i18n::{Msg, Noun};
use crate::tui::keymap::Context;
use crate::tui::services::Stamp;

use super::Nav;

mod derive;
mod draw;
mod keys;
pub(crate) mod status;
pub use derive::{Given, Next, Walk};
pub use draw::{draw, fmt_duration};
pub use keys::{BACK_KEYS, DERIVE_KEYS, DONE_KEYS, FRONT_KEYS, TYPING_KEYS};

/// Where the cards come from.
pub enum Source {
    /// Today's due, learning and new cards.
    Daily(Queue),
    /// A fixed list of cards, each once (again after Again, at the back):
    /// every card of a deck, or the cards a filter chose, when cramming.
    /// Cram answers leave the scheduling unchanged, so no step is waited for.
    Cram(CramQueue),
    /// The cards a filter chose, each once in deck order, answered as real
    /// reviews: a card left (re)learning comes back at its step time, as in
    /// the day's queue.
    Filtered(Queue),
    /// Today's share of an exam plan: real reviews of the planned items,
    /// an item left (re)learning coming back at its step time.
    Plan(Queue),
}

#[derive(Debug, Clone, PartialEq)]
pub struct TypedAnswer {
    pub text: String,
    pub check: TypedCheck,
    /// A formula card's verdict by equivalence (`check` then says right
    /// or wrong, and its `nearest` is the deck's formula).
    pub formula: Option<crate::sim::system::equiv::Verdict>,
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
    /// The deck of the card shown (before any, the session's first deck):
    /// its content, explanations and settings are the card's own.
    pub deck: usize,
    /// The decks the session draws from: one, or every deck for a filter
    /// without a deck.
    pub decks: Vec<usize>,
    pub cram: bool,
    pub source: Source,
    pub states: States,
    /// The item shown, and when it appeared (for the answer duration).
    pub current: Option<(ItemKey, Stamp)>,
    pub phase: Phase,
    pub session: Session,
    pub started: Stamp,
    /// Ratings of this screen, newest last: undo never reaches further back.
    pub rated: Vec<(ItemKey, Rating)>,
    /// Suspends and buries made on this screen (items of each), newest last.
    pub marks: Vec<Vec<ItemKey>>,
    /// For each rating of `rated`, the siblings it took out of the queue.
    pub aside: Vec<Vec<ItemKey>>,
    /// The cards were chosen by a filter (see [`filtered_items`]).
    pub filtered: bool,
    /// Those cards, so that `c` at the end crams the same ones.
    pub listed: Vec<ItemKey>,
    /// The card shown is a typed card (its front takes text).
    pub typed: bool,
    /// First line of the card shown, when it is taller than the screen.
    pub scroll: usize,
    /// The learner was told, once this session, why a card's other
    /// direction left the queue with its answer.
    pub bury_said: bool,
    /// The item shown is a derivation: how far it is walked.
    pub walk: Option<Walk>,
}

/// What comes after a session, for its summary.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WhatNext {
    /// Review items due during the next study day (not those due later
    /// today: a learning step ten minutes away is not "tomorrow").
    pub due_tomorrow: usize,
    /// Review items due later in this study day.
    pub later_today: usize,
    /// Cards with a direction never reviewed.
    pub new_cards: usize,
    /// Today's limit of new cards is used up (more come tomorrow).
    pub new_limit_reached: bool,
    /// When the next learning step of today is due.
    pub learning_in: Option<chrono::TimeDelta>,
}

impl ReviewState {
    /// A session over `items` of `deck` (every deck when `None`), chosen
    /// by [`filtered_items`] (the filter screen and the command line count
    /// them first), each once, in deck order.
    pub fn open_listed(
        app: &mut App,
        deck: Option<usize>,
        items: Vec<ItemKey>,
        cram: bool,
    ) -> Result<ReviewState, String> {
        let decks = scope_decks(app, deck)?;
        let mut states = States::default();
        for &i in &decks {
            let d = &app.decks[i];
            states.extend(
                app.services
                    .study
                    .store
                    .states(&d.id)
                    .map_err(|e| e.to_string())?,
            );
        }
        app.services
            .study
            .store
            .start_session()
            .map_err(|e| e.to_string())?;
        let now = app.services.now();
        let listed = items.clone();
        let source = if cram {
            Source::Cram(CramQueue::new(items))
        } else {
            Source::Filtered(Queue::listed(items, app.services.study.study_day(now)))
        };
        let mut state = ReviewState {
            deck: decks[0],
            decks,
            cram,
            source,
            states,
            current: None,
            phase: Phase::Done,
            session: Session::default(),
            started: app.services.stopwatch.stamp(),
            rated: Vec::new(),
            marks: Vec::new(),
            aside: Vec::new(),
            filtered: true,
            listed,
            typed: false,
            scroll: 0,
            bury_said: false,
            walk: None,
        };
        state.next_card(app);
        Ok(state)
    }

    /// Today's study of deck `deck` and every deck below it (or cramming
    /// them all), each deck within its own limits and its parents'.
    pub fn open(app: &mut App, deck: usize, cram: bool) -> Result<ReviewState, String> {
        app.decks.get(deck).ok_or("no such deck")?;
        let now = app.services.now();
        let tree = crate::deck::DeckTree::new(&app.decks);
        let sub = tree.subtree(deck);
        let decks: Vec<usize> = sub.iter().map(|(i, _)| *i).collect();
        let (source, states) = if cram {
            let mut states = States::default();
            let mut items = Vec::new();
            for &i in &decks {
                let d = &app.decks[i];
                states.extend(
                    app.services
                        .study
                        .store
                        .states(&d.id)
                        .map_err(|e| e.to_string())?,
                );
                items.extend(crate::sched::cram_items(d, None));
            }
            (Source::Cram(CramQueue::new(items)), states)
        } else {
            let parts: Vec<(&Deck, Option<usize>)> =
                sub.iter().map(|&(i, up)| (&app.decks[i], up)).collect();
            let (queue, states) = app
                .services
                .study
                .queue_tree(&parts, now)
                .map_err(|e| e.to_string())?;
            (Source::Daily(queue), states)
        };
        // Undo reaches back to the start of this review, never into another deck's.
        app.services
            .study
            .store
            .start_session()
            .map_err(|e| e.to_string())?;
        let mut state = ReviewState {
            deck,
            decks,
            cram,
            source,
            states,
            current: None,
            phase: Phase::Done,
            session: Session::default(),
            started: app.services.stopwatch.stamp(),
            rated: Vec::new(),
            marks: Vec::new(),
            aside: Vec::new(),
            filtered: false,
            listed: Vec::new(),
            typed: false,
            scroll: 0,
            bury_said: false,
            walk: None,
        };
        state.next_card(app);
        Ok(state)
    }

    /// Reviews of `items` (today's share of an exam plan), scheduled as
    /// ordinary reviews.
    pub fn open_plan(
        app: &mut App,
        deck: usize,
        items: Vec<ItemKey>,
    ) -> Result<ReviewState, String> {
        let d = app.decks.get(deck).ok_or("no such deck")?;
        let states = app
            .services
            .study
            .store
            .states(&d.id)
            .map_err(|e| e.to_string())?;
        let mut state = ReviewState::open(app, deck, false)?;
        let day = app.services.study.study_day(app.services.now());
        state.source = Source::Plan(Queue::listed(items, day));
        state.states = states;
        state.decks = vec![deck];
        state.next_card(app);
        Ok(state)
    }

    pub(super) fn next_card(&mut self, app: &App) {
        let now = app.services.now();
        let next = match &self.source {
            Source::Daily(q) | Source::Filtered(q) | Source::Plan(q) => {
                q.next(now).map(|(k, _)| k.clone())
            }
            Source::Cram(c) => c.next().cloned(),
        };
        self.show(app, next);
    }

    pub(super) fn show(&mut self, app: &App, key: Option<ItemKey>) {
        self.scroll = 0;
        match key {
            Some(key) => {
                if let Some(i) = app.decks.iter().position(|d| d.id == key.deck) {
                    self.deck = i;
                }
                self.typed = key.direction != Direction::Predict
                    && app
                        .decks
                        .get(self.deck)
                        .and_then(|d| d.card(&key.card))
                        .is_some_and(|c| c.kind.is_typed());
                // A derivation: faded by the item's own record.
                self.walk = match key.direction {
                    Direction::Derive => app
                        .decks
                        .get(self.deck)
                        .and_then(|d| d.derivation(&key.card))
                        .map(|d| {
                            // Cramming leaves the schedule alone, and so the
                            // fading: a cram walk fades as a review would.
                            let progress = app.services.study.progress(&key).unwrap_or_default();
                            let walk = Walk::new(d, progress);
                            self.typed = walk.typing(d);
                            walk
                        }),
                    _ => None,
                };
                self.current = Some((key, app.services.stopwatch.stamp()));
                self.phase = Phase::Front {
                    input: String::new(),
                };
            }
            None => {
                self.current = None;
                self.typed = false;
                self.walk = None;
                self.phase = Phase::Done;
            }
        }
    }

    /// The card shown and which way it is asked (`None` for a prompt or
    /// a derivation).
    pub fn card<'a>(&self, deck: &'a Deck) -> Option<(&'a Card, Direction)> {
        let (key, _) = self.current.as_ref()?;
        if matches!(key.direction, Direction::Predict | Direction::Derive) {
            return None;
        }
        deck.card(&key.card).map(|c| (c, key.direction))
    }

    /// The prompt shown, when the item is one (direction `predict`): its
    /// position in the deck's prompts.
    pub fn prompt(&self, deck: &Deck) -> Option<usize> {
        let (key, _) = self.current.as_ref()?;
        (key.direction == Direction::Predict)
            .then(|| deck.prompts.iter().position(|p| p.id == key.card))
            .flatten()
    }

    /// The prompt opened from this screen was answered there: its rating
    /// (from the verdict) moves the queue on as a card's would. A rating
    /// of another item (none should come) changes nothing here.
    pub fn answered_elsewhere(&mut self, app: &App, rated: crate::study::Rated) {
        let Some((key, _)) = self.current.clone() else {
            return;
        };
        if rated.record.key != key {
            return;
        }
        let record = rated.record;
        match &mut self.source {
            Source::Daily(q) | Source::Filtered(q) | Source::Plan(q) => q.answered(&record),
            Source::Cram(c) => c.answered(&record),
        }
        self.states.insert(key.clone(), record.after);
        self.session.reviewed += 1;
        if record.rating == Rating::Again {
            self.session.again += 1;
        }
        self.rated.push((key, record.rating));
        self.aside.push(Vec::new());
        self.next_card(app);
    }

    /// The deck `edited.deck` was edited and reloaded (`E`, `A`, or
    /// `F4`, `F7` while typing): the card shown is shown again as the file
    /// has it now (from its front, with the answer typed so far, and a
    /// derivation walked as far as it was while its steps are as many);
    /// one whose id is gone leaves the queue (its history stays with the
    /// old id); a new card joins the queue and is shown at once, unless a
    /// prompt is being answered on its own screen above (`on_top` false:
    /// its rating comes back here) or an answer is part typed: the new
    /// card then comes next.
    pub fn deck_edited(&mut self, app: &App, edited: &crate::tui::edit::Edited, on_top: bool) {
        if !self.decks.contains(&edited.deck) {
            return;
        }
        let Some(deck) = app.decks.get(edited.deck) else {
            return;
        };
        // An explanation edited from the reader above: the deck file,
        // and so the card and where the learner is with it, did not change.
        if matches!(edited.target, crate::tui::edit::Target::Section { .. }) {
            return;
        }
        let answering_elsewhere = !on_top
            && self.current.as_ref().is_some_and(|(k, _)| {
                k.direction == Direction::Predict && crate::tui::edit::item_exists(deck, k)
            });
        if let Some(id) = &edited.new_card {
            let keys: Vec<ItemKey> = crate::sched::deck_items(deck)
                .into_iter()
                .filter(|k| &k.card == id)
                .collect();
            for k in keys.iter().rev() {
                match &mut self.source {
                    Source::Daily(q) | Source::Filtered(q) | Source::Plan(q) => q.restore(k, None),
                    Source::Cram(c) => c.restore(k),
                }
            }
            self.listed.extend(keys.iter().cloned());
            // An answer part typed stays on screen: the new card is next.
            let typing = matches!(&self.phase, Phase::Front { input } if !input.is_empty());
            if let Some(first) = keys.first()
                && !answering_elsewhere
                && !typing
            {
                self.show(app, Some(first.clone()));
            }
            return;
        }
        let Some((key, _)) = self.current.clone() else {
            return;
        };
        if key.deck != deck.id || answering_elsewhere {
            return;
        }
        if crate::tui::edit::item_exists(deck, &key) {
            // What the learner typed stays (checked again with Enter).
            let typed = match &self.phase {
                Phase::Front { input } => input.clone(),
                Phase::Back { typed, .. } => {
                    typed.as_ref().map(|t| t.text.clone()).unwrap_or_default()
                }
                Phase::Done => String::new(),
            };
            let walk = match self.phase {
                Phase::Front { .. } => self.walk.take(),
                _ => None,
            };
            self.show(app, Some(key));
            if let (Some(walk), Some(d)) = (walk, self.derivation(deck))
                && walk.faded.len() == d.steps.len()
            {
                self.typed = walk.typing(d);
                self.walk = Some(walk);
            }
            if let Phase::Front { input } = &mut self.phase {
                *input = typed;
            }
        } else {
            match &mut self.source {
                Source::Daily(q) | Source::Filtered(q) | Source::Plan(q) => q.set_aside(&key),
                Source::Cram(c) => c.set_aside(&key),
            }
            self.next_card(app);
        }
    }

    /// The derivation shown, when the item is one.
    pub fn derivation<'a>(&self, deck: &'a Deck) -> Option<&'a crate::deck::Derivation> {
        let (key, _) = self.current.as_ref()?;
        (key.direction == Direction::Derive)
            .then(|| deck.derivation(&key.card))
            .flatten()
    }

    /// Due tomorrow, new cards left, the next learning step: what the
    /// summary says comes next.
    pub fn what_next(&self, app: &App) -> WhatNext {
        let now = app.services.now();
        let mut next = WhatNext {
            due_tomorrow: 0,
            later_today: 0,
            new_cards: 0,
            new_limit_reached: false,
            learning_in: None,
        };
        let day_end = match &self.source {
            Source::Daily(q) | Source::Filtered(q) | Source::Plan(q) => q.day().1,
            Source::Cram(_) => now + chrono::TimeDelta::days(1),
        };
        let tomorrow_end = day_end + chrono::TimeDelta::days(1);
        for deck in self.decks.iter().filter_map(|&i| app.decks.get(i)) {
            let mut new_cards: Vec<&str> = Vec::new();
            for key in crate::sched::deck_items(deck) {
                match self.states.get(&key) {
                    Some(s) if s.state != crate::sched::State::New => {
                        if s.due >= day_end && s.due < tomorrow_end {
                            next.due_tomorrow += 1;
                        } else if s.due >= now && s.due < day_end {
                            next.later_today += 1;
                        }
                    }
                    _ => {
                        let id = match key.direction {
                            Direction::Derive => deck.derivation(&key.card).map(|d| d.id.as_str()),
                            _ => deck.card(&key.card).map(|c| c.id.as_str()),
                        };
                        if let Some(id) = id
                            && !new_cards.contains(&id)
                        {
                            new_cards.push(id);
                        }
                    }
                }
            }
            next.new_cards += new_cards.len();
        }
        match &self.source {
            Source::Daily(q) => {
                next.new_limit_reached = q.counts().new == 0 && next.new_cards > 0;
                next.learning_in = q.next_learning_due().map(|due| due - now);
            }
            Source::Filtered(q) | Source::Plan(q) => {
                next.learning_in = q.next_learning_due().map(|due| due - now)
            }
            Source::Cram(_) => {}
        }
        next
    }

    /// "12 due · 3 learning · 5 new", or the cards left when cramming.
    pub fn progress(&self, app: &App) -> String {
        match &self.source {
            Source::Daily(q) => {
                let c = q.counts();
                format!(
                    "{} {} · {} {} · {}",
                    c.due,
                    app.tr(Msg::Due),
                    c.learning,
                    app.tr(Msg::Learning),
                    crate::tui::i18n::count(&app.lang, c.new, crate::tui::i18n::Noun::New)
                )
            }
            Source::Cram(c) => format!(
                "{} · {}",
                app.count(c.remaining(), Noun::Card),
                app.tr(Msg::Cram)
            ),
            Source::Filtered(q) | Source::Plan(q) => {
                // "0 cards · Exam" said nothing of what the count is:
                // the cards left of this session, named by where it came
                // from.
                let c = q.counts();
                let label = match self.source {
                    Source::Plan(_) => Msg::LeftInExamPlan,
                    _ => Msg::LeftInFilter,
                };
                let mut line = format!("{} {}", app.count(c.total(), Noun::Card), app.tr(label));
                if c.learning > 0 {
                    line.push_str(&format!(" · {} {}", c.learning, app.tr(Msg::Learning)));
                }
                line
            }
        }
    }
}

impl super::View for ReviewState {
    fn ends_session(&self) -> bool {
        true
    }

    fn context(&self) -> Context {
        match &self.phase {
            Phase::Front { .. } if self.typed => Context::ReviewTyping,
            Phase::Front { .. } if self.walk.is_some() => Context::ReviewDerive,
            Phase::Front { .. } => Context::ReviewFront,
            Phase::Back { .. } => Context::ReviewBack,
            Phase::Done => Context::ReviewDone,
        }
    }
    fn apply(&mut self, app: &mut App, action: Action) -> Nav {
        apply(app, self, action)
    }
    fn draw(&self, frame: &mut ratatui::Frame, area: ratatui::layout::Rect, app: &App) {
        draw(frame, area, app, self)
    }
    fn name(&self) -> Msg {
        if self.cram { Msg::Cram } else { Msg::Review }
    }
    fn deck(&self) -> Option<usize> {
        Some(self.deck)
    }
}

pub fn apply(app: &mut App, state: &mut ReviewState, action: Action) -> Nav {
    match (&mut state.phase, action) {
        (_, Action::Back) => return Nav::Pop,
        (_, Action::Undo) if state.rated.is_empty() && !state.marks.is_empty() => {
            status::undo(app, state)
        }
        // The drawing clamps it to the card's length.
        (_, Action::Down) => {
            state.scroll = state.scroll.saturating_add(1).min(scroll_max(app, state))
        }
        (_, Action::Up) => state.scroll = state.scroll.saturating_sub(1),
        (Phase::Done, Action::OpenCram) => {
            // A filtered session crams its own cards, over every deck it
            // covered; otherwise the whole deck.
            let cram = if state.filtered {
                let scope = (state.decks.len() == 1).then(|| state.decks[0]);
                ReviewState::open_listed(app, scope, state.listed.clone(), true)
            } else {
                // The deck studied, with its subdecks.
                ReviewState::open(
                    app,
                    state.decks.first().copied().unwrap_or(state.deck),
                    true,
                )
            };
            return match cram {
                Ok(r) => Nav::Replace(super::Screen::Review(Box::new(r))),
                Err(e) => {
                    app.error(e);
                    Nav::Stay
                }
            };
        }
        (_, Action::Undo) => undo(app, state),
        (Phase::Front { .. } | Phase::Back { .. }, Action::Suspend | Action::Bury) => {
            status::mark(app, state, action)
        }
        (_, Action::Explain) => return explain(app, state),
        (Phase::Front { .. } | Phase::Back { .. }, Action::CardInfo) => {
            if let Some((key, _)) = &state.current {
                // The item's own deck (a filtered session spans decks).
                let deck = app
                    .decks
                    .iter()
                    .position(|d| d.id == key.deck)
                    .unwrap_or(state.deck);
                match super::info::InfoState::open(app, deck, key.clone()) {
                    Ok(i) => return Nav::Push(super::Screen::Info(Box::new(i))),
                    Err(e) => app.error(e),
                }
            }
        }
        (Phase::Front { .. } | Phase::Back { .. }, Action::EditItem) => {
            match state.current.clone() {
                Some((key, _)) => app.request_edit(state.deck, crate::tui::edit::Target::Item(key)),
                None => app.info(crate::tui::i18n::edit::NOTHING_TO_EDIT.get(&app.lang)),
            }
        }
        (Phase::Front { .. } | Phase::Back { .. }, Action::AddCard) => {
            let kind = app
                .decks
                .get(state.deck)
                .and_then(|d| state.card(d))
                .map_or(CardKind::Basic, |(c, _)| c.kind);
            app.request_edit(state.deck, crate::tui::edit::Target::NewCard(kind));
        }
        (Phase::Front { input }, Action::Input(c)) => input.push(c),
        (Phase::Front { input }, Action::Backspace) => {
            input.pop();
        }
        (Phase::Front { .. }, Action::Choose(i)) => {
            if let (Some(walk), Some(d)) = (
                state.walk.as_mut(),
                app.decks
                    .get(state.deck)
                    .and_then(|d| state_derivation(d, &state.current)),
            ) {
                walk.choose(d, i);
            }
        }
        (Phase::Front { .. }, Action::Reveal | Action::Submit) if state.walk.is_some() => {
            step(app, state)
        }
        (Phase::Front { .. }, Action::Reveal | Action::Submit) => {
            // A prompt is answered on its own screen, with new numbers;
            // its verdict's rating comes back (`answered_elsewhere`).
            if let Some(i) = app.decks.get(state.deck).and_then(|d| state.prompt(d)) {
                return Nav::Push(super::Screen::Predict(Box::new(
                    super::predict::PredictState::new(app, state.deck, i),
                )));
            }
            reveal(app, state)
        }
        (Phase::Back { .. }, Action::Rate(r)) => rate(app, state, r),
        (Phase::Back { typed, .. }, Action::Submit) => {
            let r = match &state.walk {
                Some(walk) => walk.suggested(),
                None => typed.as_ref().map_or(Rating::Good, |t| t.check.suggested),
            };
            rate(app, state, r);
        }
        (Phase::Back { .. }, Action::OpenCardPrompt) => return open_prompt(app, state),
        (Phase::Done, Action::Submit | Action::Open) => return Nav::Pop,
        _ => {}
    }
    Nav::Stay
}

/// The derivation an item names (`None` for a card).
fn state_derivation<'a>(
    deck: &'a Deck,
    current: &Option<(ItemKey, Stamp)>,
) -> Option<&'a crate::deck::Derivation> {
    let (key, _) = current.as_ref()?;
    (key.direction == Direction::Derive)
        .then(|| deck.derivation(&key.card))
        .flatten()
}

/// One step on through a derivation: a worked step shown, a faded one
/// checked and shown with its verdict; after the last, the rating.
fn step(app: &mut App, state: &mut ReviewState) {
    let Some(d) = app
        .decks
        .get(state.deck)
        .and_then(|d| state.derivation(d))
        .cloned()
    else {
        return;
    };
    let d = &d;
    let Phase::Front { input } = &mut state.phase else {
        return;
    };
    let Some(walk) = state.walk.as_mut() else {
        return;
    };
    if let Err(said) = walk.advance(d, input, &app.lang) {
        app.info(said);
        return;
    }
    input.clear();
    state.typed = walk.typing(d);
    if walk.shown >= d.steps.len() {
        reveal(app, state);
    }
    // The step just shown (or asked) is in view.
    state.scroll = scroll_max(app, state);
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
                check: typed::check(input, &card.accepted(&app.lang)),
                formula: None,
            })
        }
        (Phase::Front { input }, Some((card, _))) if card.kind == CardKind::Formula => {
            card.formula.as_ref().map(|key| formula_answer(key, input))
        }
        _ => None,
    };
    // The buttons' intervals as a rating now would schedule them (over the
    // same daily load); if the load cannot be read, the rating will say why.
    let previews = (!state.cram)
        .then(|| {
            app.services
                .study
                .preview(&key, state.states.get(&key), app.services.now())
                .ok()
                .map(Box::new)
        })
        .flatten();
    state.phase = Phase::Back { typed, previews };
    state.scroll = answer_scroll(app, state);
}

/// A formula card's answer graded by equivalence: right suggests Good,
/// anything else Again (the learner may change it), with the deck's
/// formula beside what was typed.
fn formula_answer(key: &crate::deck::FormulaKey, input: &str) -> TypedAnswer {
    let v = crate::sim::system::equiv::grade(key, input);
    let right = v.is_right();
    TypedAnswer {
        text: input.to_string(),
        check: TypedCheck {
            verdict: if right {
                typed::Verdict::Exact
            } else {
                typed::Verdict::Wrong
            },
            suggested: if right { Rating::Good } else { Rating::Again },
            nearest: Some(key.expected.clone()),
            distance: 0,
        },
        formula: Some(v),
    }
}

/// Where a card taller than the screen stands when its answer appears: at
/// the rule above the answer, so the answer is in view (on a small screen
/// it was below the fold, several `j` away); 0 when the card fits.
fn answer_scroll(app: &App, state: &ReviewState) -> usize {
    let max = scroll_max(app, state);
    if max == 0 {
        return 0;
    }
    let body = crate::tui::layout::body_rect(app.size);
    let rest = ratatui::layout::Rect::new(0, 0, body.width, body.height.saturating_sub(1));
    let kind = app
        .decks
        .get(state.deck)
        .and_then(|d| state.card(d))
        .map_or(CardKind::Basic, |(c, _)| c.kind);
    let lines = draw::layout(app, state, kind, rest).lines;
    let rule = lines.iter().position(|l| {
        let text = crate::tui::wrap::line_text(l);
        !text.is_empty() && text.chars().all(|c| c == '─')
    });
    rule.unwrap_or(0).min(max)
}

/// How far the card (or the summary) can scroll at the app's size.
fn scroll_max(app: &App, state: &ReviewState) -> usize {
    let body = crate::tui::layout::body_rect(app.size);
    // The progress line above; the buttons (up to two lines) and the hints
    // below; the card's borders and margins.
    let rest_h = body.height.saturating_sub(1);
    let rest = ratatui::layout::Rect::new(0, 0, body.width, rest_h);
    if state.phase == Phase::Done {
        let inner = draw::summary_area(rest);
        let lines = draw::summary_lines(app, state, usize::from(inner.width.max(1)));
        return lines.len().saturating_sub(inner.height as usize);
    }
    let kind = app
        .decks
        .get(state.deck)
        .and_then(|d| state.card(d))
        .map_or(CardKind::Basic, |(c, _)| c.kind);
    let l = draw::layout(app, state, kind, rest);
    let (lines, room) = (l.lines.len(), l.room);
    lines.saturating_sub(room)
}

fn rate(app: &mut App, state: &mut ReviewState, rating: Rating) {
    let Some((key, shown)) = state.current.clone() else {
        return;
    };
    if !state.cram && status::changed_meanwhile(app, state, &key) {
        return;
    }
    let now = app.services.now();
    let answer = crate::study::Answer {
        key: &key,
        before: state.states.get(&key),
        rating,
        duration_ms: app.services.stopwatch.elapsed_ms(shown),
        cram: state.cram,
    };
    // Durable before anything else changes: if the write fails, the card
    // stays on screen and the rating can be given again.
    let deck = app.decks.get(state.deck);
    let rated = match app.services.study.rate(deck, answer, now) {
        Ok(r) => r,
        Err(e) => {
            app.error(e.to_string());
            return;
        }
    };
    let crate::study::Rated {
        record,
        after,
        recorded,
    } = rated;
    match &mut state.source {
        Source::Daily(q) | Source::Filtered(q) | Source::Plan(q) => q.answered(&record),
        Source::Cram(c) => c.answered(&record),
    }
    if !state.cram {
        state.states.insert(key.clone(), record.after);
    }
    state.session.reviewed += 1;
    if rating == Rating::Again {
        state.session.again += 1;
    }
    state.rated.push((key.clone(), rating));
    app.status = None;
    status::after_rating(app, state, &key, &after, recorded.leech);
    state.next_card(app);
}

fn undo(app: &mut App, state: &mut ReviewState) {
    if state.rated.is_empty() {
        app.info(app.tr(Msg::NothingToUndo));
        return;
    }
    let record = match app.services.study.undo() {
        Ok(Some(crate::store::Undone::Review(r))) => r,
        Ok(Some(crate::store::Undone::Status(events))) => {
            status::undone(app, state, &events);
            return;
        }
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
    let restored = match app.services.study.store.state(&key) {
        Ok(s) => s,
        Err(e) => {
            app.error(e.to_string());
            None
        }
    };
    match &mut state.source {
        Source::Daily(q) | Source::Filtered(q) | Source::Plan(q) => {
            q.restore(&key, restored.as_ref())
        }
        Source::Cram(c) => c.restore(&key),
    }
    if !state.cram {
        match restored {
            Some(s) => state.states.insert(key.clone(), s),
            None => state.states.remove(&key),
        };
    }
    state.rated.pop();
    if let Some(siblings) = state.aside.pop() {
        status::bring_back(app, state, &siblings);
    }
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
    let section = match state.derivation(deck) {
        Some(d) => d.explain.clone(),
        None => state.card(deck).and_then(|(c, _)| c.explain.clone()),
    };
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

/// The decks a filtered session over `deck` draws from: that one, or
/// every deck when `None`.
fn scope_decks(app: &App, deck: Option<usize>) -> Result<Vec<usize>, String> {
    match deck {
        Some(i) if i < app.decks.len() => Ok(vec![i]),
        Some(_) => Err("no such deck".into()),
        None if app.decks.is_empty() => Err("no decks to review".into()),
        None => Ok((0..app.decks.len()).collect()),
    }
}

/// The items of `deck` (every deck when `None`) a filtered session would
/// show, deck by deck in deck order. A tag or deck named by the filter must
/// exist in the decks searched, not in each of them. Suspended and buried
/// cards are left out unless cramming: their answers would change a
/// schedule they are out of.
pub fn filtered_items(
    app: &App,
    deck: Option<usize>,
    filter: &crate::catalog::Filter,
    cram: bool,
) -> Result<Vec<ItemKey>, String> {
    use crate::catalog;
    use crate::catalog::search::{Search, select};
    if !cram && filter.asks_suspended() {
        return Err(app.tr(Msg::SuspendedNeedsCram).to_string());
    }
    let decks: &[Deck] = match deck {
        Some(i) => std::slice::from_ref(app.decks.get(i).ok_or("no such deck")?),
        None => &app.decks,
    };
    filter.check_names(decks).map_err(|e| e.to_string())?;
    let now = app.services.now();
    let rows = catalog::rows(
        decks,
        &app.services.study.store,
        &app.services.study.scheduler,
        now,
    )
    .map_err(|e| e.to_string())?;
    let mut search = Search::for_filter(filter, decks, &rows);
    let mut picked = select(decks, &rows, &mut search, filter, now);
    picked.sort_unstable();
    Ok(picked
        .into_iter()
        .filter(|&i| cram || rows[i].status.studyable(now))
        .map(|i| rows[i].key(decks))
        .collect())
}
