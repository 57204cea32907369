//! Predict, then check: the learner commits to an answer, then the scene's
//! simulation plays live, then the verdict compares the prediction with
//! what was measured. One flow for rigid bodies and systems: the commitment
//! (kept on disk before the run starts), the run's keys on the one player
//! ([`Live`]), and the verdict from the reference run (the one watched, or
//! one made off the UI thread when the learner played another method).
//! Only the panels are drawn apart (`draw.rs`, `system.rs`). After the
//! verdict, or from the prompt list, the scene's knobs may be turned
//! (`explore.rs`).

use crate::deck::{Answer, Deck, Prompt};
use crate::sim::Method;
use crate::tui::action::Action;
use crate::tui::app::App;
use crate::tui::i18n::Msg;
use crate::tui::keymap::Context;
use crate::tui::live::{Live, system_reference};

use super::Nav;

mod draw;
pub mod explore;
mod keys;
mod parts;
mod system;
pub mod verdict;
pub use draw::{draw, fmt_value};
pub use keys::{CHOICE_KEYS, EXPLORE_KEYS, FORMULA_KEYS, NUMBER_KEYS, RUN_KEYS, VERDICT_KEYS};

pub use crate::predict::{Prediction, Verdict};
use crate::sim::scene::measure::Measurements;
use crate::store::{AttemptVerdict, Commitment, Committed};

pub enum Phase {
    /// Waiting for the commitment: the selected choice or the typed number.
    Ask {
        selected: usize,
        input: String,
        error: Option<String>,
    },
    /// The run playing, then its verdict.
    Play {
        prediction: Prediction,
        /// The attempt as stored when the learner committed.
        committed: Committed,
        run: Box<Live>,
        verdict: Option<Verdict>,
        judging: Judging,
    },
    /// Exploring the scene with its knobs: no prediction, the run
    /// restarted at the knobs' values.
    Explore {
        run: Box<Live>,
        explore: Box<explore::Exploring>,
    },
}

/// Where the verdict stands once the run has ended.
pub enum Judging {
    /// The run has not ended (or its own measurements give the verdict).
    Idle,
    /// The scene's default run measuring off the UI thread, for a learner
    /// who watched another method: a long run never holds up the keys.
    Measuring(Measuring),
    /// No verdict: the scene's run cannot measure (the status line says
    /// why); the attempt stays stored without one.
    Failed,
}

/// A measurement made on another thread.
pub struct Measuring(std::sync::mpsc::Receiver<Result<Measurements, String>>);

impl Measuring {
    pub fn start(
        work: impl FnOnce() -> Result<Measurements, String> + Send + 'static,
    ) -> Measuring {
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            // The screen may have closed meanwhile: nobody listens then.
            let _ = tx.send(work());
        });
        Measuring(rx)
    }

    /// The measurements once they are made.
    pub fn poll(&self) -> Option<Result<Measurements, String>> {
        match self.0.try_recv() {
            Ok(r) => Some(r),
            Err(std::sync::mpsc::TryRecvError::Empty) => None,
            Err(std::sync::mpsc::TryRecvError::Disconnected) => {
                Some(Err("the measurement stopped".to_string()))
            }
        }
    }
}

pub struct PredictState {
    pub deck: usize,
    pub prompt: usize,
    /// The prompt's id: found again by it when its deck is edited.
    pub prompt_id: String,
    /// A choice prompt (else a number or a formula).
    pub choice: bool,
    /// A formula prompt: the learner types a formula, graded at the
    /// commitment by equivalence (`predict::formula`), not by the run.
    pub formula: bool,
    pub phase: Phase,
    /// The learner asked for the solver's diagnostics (`d`); a run with
    /// another method than the reference shows them anyway, unless the
    /// learner hid them.
    pub diagnostics: Option<bool>,
    /// The learner asked for the whole question first (`w`): on a screen
    /// too small for it beside the verdict, the verdict gives way.
    pub question_first: bool,
    /// How far the learner scrolled a verdict taller than its rows (`j`):
    /// drawing keeps it within the verdict's lines, so `k` brings it back
    /// at once however often `j` was pressed.
    pub verdict_scroll: std::cell::Cell<usize>,
    /// A varied prompt as this attempt asks it: its numbers drawn, the
    /// question filled in, the scene set (issue 24 §2).
    pub variant: Option<Box<crate::predict::variant::Resolved>>,
    /// The prompt's rating from its verdict, when it was due (or new):
    /// handed to the review screen that opened it.
    pub rated: Option<crate::study::Rated>,
    /// When the question appeared (the answer's duration).
    pub shown: crate::tui::services::Stamp,
}

impl PredictState {
    pub fn new(app: &App, deck: usize, prompt: usize) -> PredictState {
        let choice = app
            .decks
            .get(deck)
            .and_then(|d| d.prompts.get(prompt))
            .is_some_and(|p| matches!(p.answer, Answer::Choice { .. }));
        let formula = app
            .decks
            .get(deck)
            .and_then(|d| d.prompts.get(prompt))
            .is_some_and(|p| matches!(p.answer, Answer::Formula(_)));
        let prompt_id = app
            .decks
            .get(deck)
            .and_then(|d| d.prompts.get(prompt))
            .map(|p| p.id.clone())
            .unwrap_or_default();
        PredictState {
            deck,
            prompt,
            prompt_id,
            choice,
            formula,
            diagnostics: None,
            question_first: false,
            verdict_scroll: std::cell::Cell::new(0),
            variant: draw_variant(app, deck, prompt).map(Box::new),
            rated: None,
            shown: app.services.stopwatch.stamp(),
            phase: Phase::Ask {
                selected: 0,
                input: String::new(),
                error: None,
            },
        }
    }

    /// The predict screen of `prompt` exploring its scene's knobs at once
    /// (the prompt list's `x`); `Err` with what the status line says when
    /// the scene has no knobs or cannot run.
    pub fn exploring(app: &App, deck: usize, prompt: usize) -> Result<PredictState, String> {
        let mut state = PredictState::new(app, deck, prompt);
        let (Some(d), Some(p)) = (
            app.decks.get(deck),
            app.decks.get(deck).and_then(|d| d.prompts.get(prompt)),
        ) else {
            return Err(explore::no_knobs(app).to_string());
        };
        let (run, explore) = explore::enter(app, d, p, 1.0)?;
        state.phase = Phase::Explore { run, explore };
        Ok(state)
    }

    /// The deck was edited and reloaded (`F4`, `F7` while typing the
    /// answer): before the commitment the prompt is asked again as the
    /// file has it now (a varied prompt with the numbers already drawn,
    /// while it still varies), what was typed kept; a prompt whose id is
    /// gone closes the screen at the next key. A run under way is left
    /// as it is.
    pub fn deck_edited(&mut self, app: &App, edited: &crate::tui::edit::Edited) {
        if edited.deck != self.deck || !matches!(self.phase, Phase::Ask { .. }) {
            return;
        }
        let Some(d) = app.decks.get(self.deck) else {
            return;
        };
        let Some(i) = d.prompts.iter().position(|p| p.id == self.prompt_id) else {
            self.prompt = usize::MAX;
            self.variant = None;
            return;
        };
        let p = &d.prompts[i];
        self.prompt = i;
        self.choice = matches!(p.answer, Answer::Choice { .. });
        self.formula = matches!(p.answer, Answer::Formula(_));
        let seed = self
            .variant
            .as_ref()
            .and_then(|v| v.variant.as_ref())
            .and_then(|v| v.seed);
        self.variant = match seed {
            _ if p.vary.is_empty() => None,
            Some(seed) => {
                let v = crate::predict::variant::draw(p, seed);
                crate::predict::variant::resolve(d, p, Some(&v)).map(Box::new)
            }
            None => draw_variant(app, self.deck, i).map(Box::new),
        };
        if let (Phase::Ask { selected, .. }, Answer::Choice { choices, .. }) =
            (&mut self.phase, &p.answer)
        {
            *selected = (*selected).min(choices.len().saturating_sub(1));
        }
    }

    /// Whether the diagnostics line is shown (when the scene has one): the
    /// learner's choice, else only for a run with another method than the
    /// reference, where the error it reports is the lesson.
    pub fn shows_diagnostics(&self) -> bool {
        match (&self.phase, self.diagnostics) {
            (_, Some(shown)) => shown,
            (Phase::Play { run, .. } | Phase::Explore { run, .. }, None) => !run.is_reference(),
            (Phase::Ask { .. }, None) => false,
        }
    }

    pub fn animating(&self) -> bool {
        match &self.phase {
            // Ticks poll a measurement under way.
            Phase::Play {
                judging: Judging::Measuring(_),
                ..
            } => true,
            Phase::Play { run, .. } => run.playing(),
            // Ticks poll the curve's measurement too.
            Phase::Explore { run, explore } => run.playing() || explore.measuring(),
            Phase::Ask { .. } => false,
        }
    }
}

/// A new variant of a varied prompt: the seed from the deck, the prompt,
/// its attempts so far and the time; other numbers than the last attempt's
/// when the prompt has others. `None` for a prompt that does not vary.
fn draw_variant(
    app: &App,
    deck: usize,
    prompt: usize,
) -> Option<crate::predict::variant::Resolved> {
    use crate::predict::variant;
    let d = app.decks.get(deck)?;
    let p = d.prompts.get(prompt)?;
    if p.vary.is_empty() {
        return None;
    }
    // A store that cannot say counts as none: the draw is fresh anyway.
    let (attempts, last) = app
        .services
        .study
        .store
        .attempts_at(&d.id, &p.id)
        .unwrap_or((0, None));
    let now = app.services.now().timestamp_millis();
    let seed = variant::seed_for(&d.id, &p.id, attempts, now);
    let last = last.map(|s| variant::draw(p, s));
    let v = variant::fresh(p, seed, last.as_ref());
    variant::resolve(d, p, Some(&v))
}

fn deck<'a>(app: &'a App, s: &PredictState) -> Option<&'a Deck> {
    app.decks.get(s.deck)
}

/// The prompt as this attempt asks it (a varied prompt's variant).
pub(super) fn prompt<'a>(app: &'a App, s: &'a PredictState) -> Option<&'a Prompt> {
    if let Some(v) = &s.variant {
        return Some(&v.prompt);
    }
    deck(app, s).and_then(|d| d.prompts.get(s.prompt))
}

pub use crate::predict::typed::{ParseError, parse_number, parse_number_in};

impl super::View for PredictState {
    fn context(&self) -> Context {
        match &self.phase {
            Phase::Ask { .. } if self.choice => Context::PredictChoice,
            Phase::Ask { .. } if self.formula => Context::PredictFormula,
            Phase::Ask { .. } => Context::PredictNumber,
            Phase::Play { verdict: None, .. } => Context::PredictRun,
            Phase::Play { .. } => Context::PredictVerdict,
            Phase::Explore { .. } => Context::PredictExplore,
        }
    }
    fn apply(&mut self, app: &mut App, action: Action) -> Nav {
        apply(app, self, action)
    }
    fn draw(&self, frame: &mut ratatui::Frame, area: ratatui::layout::Rect, app: &App) {
        match &self.phase {
            Phase::Explore { run, explore } => {
                explore::draw(frame, area, app, (run, explore), self.shows_diagnostics())
            }
            _ => draw(frame, area, app, self),
        }
    }
    fn name(&self) -> Msg {
        Msg::Predict
    }
    fn deck(&self) -> Option<usize> {
        Some(self.deck)
    }
    fn animating(&self) -> bool {
        PredictState::animating(self)
    }
}

pub fn apply(app: &mut App, state: &mut PredictState, action: Action) -> Nav {
    let Some(prompt) = prompt(app, state).cloned() else {
        return Nav::Pop;
    };
    if action == Action::ToggleDiagnostics {
        state.diagnostics = Some(!state.shows_diagnostics());
        return Nav::Stay;
    }
    if action == Action::ToggleQuestion {
        state.question_first = !state.question_first;
        return Nav::Stay;
    }
    if matches!(action, Action::Down | Action::Up)
        && matches!(
            state.phase,
            Phase::Play {
                verdict: Some(_),
                ..
            }
        )
    {
        let now = state.verdict_scroll.get();
        state.verdict_scroll.set(match action {
            Action::Down => now.saturating_add(1),
            _ => now.saturating_sub(1),
        });
        return Nav::Stay;
    }
    if matches!(state.phase, Phase::Explore { .. }) {
        return explore_apply(app, state, action);
    }
    // After the verdict the knobs turn the scene (`x`, or a knob's keys).
    if matches!(
        action,
        Action::Explore | Action::KnobUp | Action::KnobDown | Action::NextKnob
    ) && let Phase::Play {
        verdict: Some(_),
        run,
        ..
    } = &state.phase
    {
        let speed = run.speed;
        let Some(d) = deck(app, state) else {
            return Nav::Pop;
        };
        match explore::enter(app, d, &prompt, speed) {
            Ok((run, explore)) => state.phase = Phase::Explore { run, explore },
            Err(e) => {
                app.info(e);
                return Nav::Stay;
            }
        }
        if action == Action::Explore {
            return Nav::Stay;
        }
        return explore_apply(app, state, action);
    }
    let known = deck(app, state)
        .is_some_and(|d| d.system(&prompt.scene).is_some() || d.scene(&prompt.scene).is_some());
    if !known {
        app.error(format!("scene {} not found", prompt.scene));
        return Nav::Pop;
    }
    // While the answer is typed, `E` and `A` are letters: F4 edits the
    // prompt in its deck file, F7 adds a card (what is typed stays).
    if matches!(state.phase, Phase::Ask { .. })
        && matches!(action, Action::EditItem | Action::AddCard)
    {
        let target = match action {
            Action::EditItem => crate::tui::edit::Target::Item(crate::sched::ItemKey {
                deck: deck(app, state).map(|d| d.id.clone()).unwrap_or_default(),
                card: state.prompt_id.clone(),
                direction: crate::sched::Direction::Predict,
            }),
            _ => crate::tui::edit::Target::NewCard(crate::deck::CardKind::Basic),
        };
        app.request_edit(state.deck, target);
        return Nav::Stay;
    }
    let units = app.decks.get(state.deck).map_or(&[][..], |d| &d.units[..]);
    let deck_index = state.deck;
    let shown = state.shown;
    match &mut state.phase {
        Phase::Ask {
            selected,
            input,
            error,
        } => {
            let committed = match (&prompt.answer, action) {
                (_, Action::Back) => return Nav::Pop,
                (Answer::Choice { choices, .. }, a) => {
                    let n = choices.len();
                    match a {
                        Action::Up => *selected = selected.saturating_sub(1),
                        Action::Down => *selected = (*selected + 1).min(n.saturating_sub(1)),
                        Action::Choose(i) if i < n => *selected = i,
                        Action::Submit if n > 0 => {}
                        _ => return Nav::Stay,
                    }
                    (a == Action::Submit && n > 0)
                        .then(|| Prediction::Choice((*selected).min(n - 1)))
                }
                (Answer::Formula(_), a) => match a {
                    Action::Input(c) => {
                        // A formula is short: the grader reads at most
                        // `MAX_ANSWER` bytes, so typing stops there.
                        if input.len() + c.len_utf8() <= crate::sim::system::equiv::MAX_ANSWER {
                            input.push(c);
                        }
                        *error = None;
                        return Nav::Stay;
                    }
                    Action::Backspace => {
                        input.pop();
                        *error = None;
                        return Nav::Stay;
                    }
                    Action::Submit => {
                        let Some(v) = crate::predict::formula(&prompt, input) else {
                            return Nav::Stay;
                        };
                        // A formula that does not read is not committed:
                        // the field stays, with where and why.
                        if let Some(f) = &v.formula
                            && let crate::sim::system::equiv::Verdict::Unreadable(e) = &f.1
                        {
                            *error = Some(format!(
                                "{}: {}",
                                app.tr(Msg::FormulaUnreadable),
                                crate::text::safe::one_line(&e.to_string())
                            ));
                            return Nav::Stay;
                        }
                        return commit_formula(app, state, v);
                    }
                    _ => return Nav::Stay,
                },
                (Answer::Number { unit, .. }, a) => match a {
                    Action::Input(c) => {
                        input.push(c);
                        *error = None;
                        None
                    }
                    Action::Backspace => {
                        input.pop();
                        *error = None;
                        None
                    }
                    Action::Submit => match parse_number_in(input, unit, units) {
                        Ok(v) => Some(Prediction::Number(v)),
                        Err(ParseError::NotANumber) => {
                            *error = Some(app.tr(Msg::NotANumber).to_string());
                            None
                        }
                        Err(ParseError::WrongUnit) => {
                            *error = Some(format!("{} {unit}", app.tr(Msg::WrongUnit)));
                            None
                        }
                    },
                    _ => None,
                },
            };
            if let Some(p) = committed {
                return commit(app, state, p, None);
            }
            Nav::Stay
        }
        Phase::Explore { .. } => Nav::Stay,
        Phase::Play {
            verdict: Some(_), ..
        } if action == Action::NextPrompt => {
            let n = deck(app, state).map_or(0, |d| d.prompts.len());
            if n == 0 {
                return Nav::Pop;
            }
            let next = PredictState::new(app, state.deck, (state.prompt + 1) % n);
            Nav::Replace(super::Screen::Predict(Box::new(next)))
        }
        Phase::Play {
            verdict: Some(_), ..
        } if action == Action::Rate(crate::sched::Rating::Hard) => {
            lower_to_hard(app, state);
            Nav::Stay
        }
        Phase::Play { verdict, .. } if action == Action::Explain => {
            // A wrong answer's misconception opens where the deck explains
            // it; otherwise the prompt's own explanation.
            let named = verdict
                .as_ref()
                .and_then(|v| v.misconception.as_deref())
                .and_then(|m| app.decks.get(deck_index)?.misconception(m)?.explain.clone());
            if verdict.is_some()
                && let Some(id) = named.as_ref().or(prompt.explain.as_ref())
            {
                return super::reader::open_at(app, state.deck, id);
            }
            Nav::Stay
        }
        Phase::Play {
            run,
            prediction,
            committed,
            verdict,
            judging,
        } => {
            let replace =
                |run: &mut Box<Live>, next: Result<Live, String>, app: &mut App| match next {
                    Ok(r) => **run = r,
                    Err(e) => app.error(e),
                };
            match action {
                Action::Back => return Nav::Pop,
                Action::Tick(dt) => {
                    let slice = app.services.physics_slice();
                    run.tick_within(dt.as_secs_f64(), slice);
                }
                Action::TogglePause => {
                    if run.finished() {
                        let next = run.restart();
                        replace(run, next, app);
                    } else {
                        run.paused = !run.paused;
                    }
                }
                Action::Faster => run.speed = (run.speed * 2.0).min(64.0),
                Action::Slower => run.speed = (run.speed / 2.0).max(1.0 / 64.0),
                Action::Restart => {
                    let next = run.restart();
                    replace(run, next, app);
                }
                Action::NextMethod => {
                    let next = run.next_method();
                    replace(run, next, app);
                }
                Action::SmallerStep | Action::LargerStep => {
                    match run.step(action == Action::LargerStep) {
                        Some(next) => replace(run, next, app),
                        None => app.info(app.tr(Msg::NoStepToChange)),
                    }
                }
                _ => {}
            }
            // The first time a run reaches the end, the verdict.
            if verdict.is_none() && run.finished() {
                judge(
                    app,
                    &prompt,
                    run,
                    (*prediction, *committed),
                    verdict,
                    judging,
                    (deck_index, shown, &mut state.rated),
                );
            }
            Nav::Stay
        }
    }
}

/// A key while exploring: a knob turned or another selected restarts the
/// run at once with the knobs' values; the run's own keys as in a run.
fn explore_apply(app: &mut App, state: &mut PredictState, action: Action) -> Nav {
    let deck_index = state.deck;
    let Phase::Explore { run, explore } = &mut state.phase else {
        return Nav::Stay;
    };
    let Some(deck) = app.decks.get(deck_index) else {
        return Nav::Pop;
    };
    let mut restart = false;
    match action {
        Action::Back => return Nav::Pop,
        Action::KnobUp | Action::KnobDown => {
            restart = explore.turn(action == Action::KnobUp);
        }
        Action::NextKnob => explore.next_knob(),
        Action::Tick(dt) => {
            let slice = app.services.physics_slice();
            run.tick_within(dt.as_secs_f64(), slice);
        }
        Action::TogglePause => {
            if run.finished() {
                restart = true;
            } else {
                run.paused = !run.paused;
            }
        }
        Action::Faster => run.speed = (run.speed * 2.0).min(64.0),
        Action::Slower => run.speed = (run.speed / 2.0).max(1.0 / 64.0),
        Action::Restart => restart = true,
        _ => {}
    }
    match restart.then(|| explore.run(deck, run.speed)) {
        Some(Ok(next)) => **run = next,
        Some(Err(e)) => {
            app.error(e);
            return Nav::Stay;
        }
        None => {}
    }
    if let Some(deck) = app.decks.get(deck_index) {
        explore.poll(deck);
    }
    Nav::Stay
}

/// The verdict from the run just watched when it was the reference run
/// (a rigid body's exact solution, a system's auto method at its default
/// tolerance), else from a reference run of the scene made off the UI
/// thread: a learner who switched to RK4 with a huge step still gets the
/// physics' answer. When the reference run itself stops early (the scene
/// leaves its domain) there is no verdict and the attempt stays without
/// one: the status line says why. The verdict is written to the attempt
/// stored at the commitment.
fn judge(
    app: &mut App,
    prompt: &Prompt,
    run: &Live,
    attempt: (Prediction, Committed),
    verdict: &mut Option<Verdict>,
    judging: &mut Judging,
    rate: Rate<'_>,
) {
    if run.is_reference() {
        if run.error().is_some() {
            *judging = Judging::Failed;
        } else {
            let (v, r) = record(app, prompt, &run.measurements(), attempt, (rate.0, rate.1));
            *verdict = Some(v);
            *rate.2 = r;
        }
        return;
    }
    settle(app, prompt, attempt, verdict, judging, rate, || {
        Measuring::start(run.reference_measurement())
    });
}

/// Where a verdict's rating goes: the deck, when the question appeared,
/// and the screen's `rated`.
type Rate<'a> = (
    usize,
    crate::tui::services::Stamp,
    &'a mut Option<crate::study::Rated>,
);

/// Starts the measurement `start` makes when none is under way, and gives
/// the verdict once it is there (or says why there is none).
fn settle(
    app: &mut App,
    prompt: &Prompt,
    attempt: (Prediction, Committed),
    verdict: &mut Option<Verdict>,
    judging: &mut Judging,
    rate: Rate<'_>,
    start: impl FnOnce() -> Measuring,
) {
    match judging {
        Judging::Idle => *judging = Judging::Measuring(start()),
        Judging::Failed => return,
        Judging::Measuring(_) => {}
    }
    let Judging::Measuring(m) = judging else {
        return;
    };
    match m.poll() {
        None => {}
        Some(Ok(measured)) => {
            let (v, r) = record(app, prompt, &measured, attempt, (rate.0, rate.1));
            *verdict = Some(v);
            *rate.2 = r;
            *judging = Judging::Idle;
        }
        Some(Err(e)) => {
            app.error(e);
            *judging = Judging::Failed;
        }
    }
}

/// The verdict on the measurements, written to the attempt stored at the
/// commitment (once: a restarted run shows the verdict again but the
/// attempt keeps its first).
fn record(
    app: &mut App,
    prompt: &Prompt,
    measurements: &crate::sim::scene::measure::Measurements,
    (prediction, committed): (Prediction, Committed),
    (deck, shown): (usize, crate::tui::services::Stamp),
) -> (Verdict, Option<crate::study::Rated>) {
    let verdict = crate::predict::verdict(prompt, measurements, prediction);
    let judged = AttemptVerdict {
        measured: verdict.readings.first().map(|r| r.value),
        correct: verdict.correct,
        judged_at: app.services.now(),
        misconception: verdict.misconception.clone(),
    };
    let rated = judge_and_rate(app, deck, committed, &judged, &prompt.id, shown);
    (verdict, rated)
}

/// The verdict written and, when the prompt is due or new, its rating in
/// the same write (wrong Again, right Good); the verdict's last line says
/// what was scheduled.
fn judge_and_rate(
    app: &mut App,
    deck: usize,
    committed: Committed,
    judged: &AttemptVerdict,
    prompt: &str,
    shown: crate::tui::services::Stamp,
) -> Option<crate::study::Rated> {
    let duration = app.services.stopwatch.elapsed_ms(shown);
    let d = app.decks.get(deck)?.clone();
    let result = app
        .services
        .study
        .judge_and_rate(&d, committed, judged, prompt, duration);
    match result {
        Ok(Some(r)) => Some(r),
        Ok(None) => None,
        Err(e) => {
            app.error(e.to_string());
            None
        }
    }
}

/// "prediction scheduled: Good · back in 3d", the verdict's last line.
pub(super) fn scheduled_text(app: &App, r: &crate::study::Rated) -> String {
    let rating = match r.record.rating {
        crate::sched::Rating::Again => Msg::Again,
        crate::sched::Rating::Hard => Msg::Hard,
        crate::sched::Rating::Good => Msg::Good,
        crate::sched::Rating::Easy => Msg::Easy,
    };
    format!(
        "{}: {} · {} {}",
        app.tr(Msg::PromptScheduled),
        app.tr(rating),
        app.tr(Msg::BackIn),
        crate::sched::format_interval(r.record.after.due - r.record.reviewed_at)
    )
}

/// `2` after a right verdict: the prompt's Good becomes Hard.
fn lower_to_hard(app: &mut App, state: &mut PredictState) {
    let Some(rated) = state.rated.clone() else {
        app.info(app.tr(Msg::NotRatedPractice));
        return;
    };
    let Some(d) = app.decks.get(state.deck).cloned() else {
        return;
    };
    let now = app.services.now();
    match app.services.study.lower_to_hard(&d, &rated, now) {
        Ok(Some(r)) => state.rated = Some(r),
        Ok(None) => app.info(app.tr(Msg::NotRatedPractice)),
        Err(e) => app.error(e.to_string()),
    }
}

/// A formula prompt's commitment: the typed formula is stored as the
/// attempt's prediction and judged at once (its verdict is `v`, decided by
/// equivalence, not by the run); the scene then plays as the evidence to
/// look at. A scene that cannot run stores nothing, as for any prompt.
fn commit_formula(app: &mut App, state: &mut PredictState, v: Verdict) -> Nav {
    let nav = commit(
        app,
        state,
        Prediction::Formula,
        v.formula.as_ref().map(|f| f.0.clone()),
    );
    if let Phase::Play {
        committed, verdict, ..
    } = &mut state.phase
    {
        let judged = AttemptVerdict {
            measured: None,
            correct: v.correct,
            judged_at: app.services.now(),
            misconception: v.misconception.clone(),
        };
        let committed = *committed;
        *verdict = Some(v);
        let id = prompt(app, state).map(|p| p.id.clone()).unwrap_or_default();
        state.rated = judge_and_rate(app, state.deck, committed, &judged, &id, state.shown);
    }
    nav
}

/// The prediction as stored: a choice's id, or the number typed (a
/// formula's text is given by the caller).
fn given(prompt: &Prompt, prediction: Prediction) -> String {
    match (prediction, &prompt.answer) {
        (Prediction::Choice(i), Answer::Choice { choices, .. }) => {
            choices.get(i).map(|c| c.id.clone()).unwrap_or_default()
        }
        (Prediction::Number(v), _) => crate::text::num::show(v),
        _ => String::new(),
    }
}

/// Keeps the learner's commitment, on disk before the run starts (the
/// rule of a rating). `None` when the write failed: the status line says
/// why and the screen stays on the question, the answer still typed.
fn keep_commitment(
    app: &mut App,
    state: &PredictState,
    prompt: &Prompt,
    prediction: Prediction,
    typed: Option<String>,
) -> Option<Committed> {
    let commitment = Commitment {
        deck: deck(app, state).map(|d| d.id.clone()).unwrap_or_default(),
        prompt: prompt.id.clone(),
        committed_at: app.services.now(),
        prediction: typed.unwrap_or_else(|| given(prompt, prediction)),
        variant: state
            .variant
            .as_ref()
            .and_then(|v| v.variant.as_ref())
            .and_then(|v| v.seed),
    };
    match app.services.study.commit_attempt(&commitment) {
        Ok(c) => Some(c),
        Err(e) => {
            app.error(e.to_string());
            None
        }
    }
}

/// The commitment: the run is built first (a scene that cannot run stores
/// nothing), then the commitment is kept, then the run starts.
fn commit(
    app: &mut App,
    state: &mut PredictState,
    prediction: Prediction,
    typed: Option<String>,
) -> Nav {
    let Some(prompt) = prompt(app, state).cloned() else {
        return Nav::Pop;
    };
    let Some(deck) = deck(app, state) else {
        return Nav::Pop;
    };
    let run = if let Some(v) = &state.variant {
        match &v.scene {
            crate::predict::variant::SceneOf::System(sys) => {
                Live::system(sys, system_reference(sys), &system::measures(&prompt))
                    .map_err(|e| format!("{}: {e}", sys.id))
            }
            crate::predict::variant::SceneOf::Rigid(scene) => {
                Live::rigid(scene, Method::Exact).map_err(|e| format!("{}: {e}", scene.id))
            }
        }
    } else if let Some(sys) = deck.system(&prompt.scene) {
        Live::system(sys, system_reference(sys), &system::measures(&prompt))
            .map_err(|e| format!("{}: {e}", sys.id))
    } else if let Some(scene) = deck.scene(&prompt.scene) {
        Live::rigid(scene, Method::Exact).map_err(|e| format!("{}: {e}", scene.id))
    } else {
        app.error(format!("scene {} not found", prompt.scene));
        return Nav::Pop;
    };
    match run {
        Ok(run) => {
            if let Some(committed) = keep_commitment(app, state, &prompt, prediction, typed) {
                state.phase = Phase::Play {
                    prediction,
                    committed,
                    run: Box::new(run),
                    verdict: None,
                    judging: Judging::Idle,
                };
            }
        }
        Err(e) => app.error(e),
    }
    Nav::Stay
}

/// A run's speed as its status line shows it, the rigid body's and a
/// system's alike. A scene in seconds shows how fast it plays against real
/// time (`speed ×1`, `×1.67`, `×64`, `×1/8`); a scene in other units
/// shows the learner's multiplier and the scene time a second of the clock
/// covers (`speed ×1 · 13 yr/s`). A run whose steps cannot keep up with
/// the clock says so: it plays slower than shown.
pub(super) fn speed_text(app: &App, live: &Live) -> String {
    let (_, unit) = live.timing();
    let mut out = if unit == "s" {
        format!("{} ×{}", app.tr(Msg::Speed), ratio(live.rate()))
    } else {
        format!(
            "{} ×{} · {} {unit}/s",
            app.tr(Msg::Speed),
            ratio(live.speed),
            crate::text::num::sig(live.rate(), 3)
        )
    };
    if live.lagging() {
        out.push_str(&format!(" · {}", app.tr(Msg::CannotKeepUp)));
    }
    out
}

/// A speed factor: `4`, `1.67`, `1/8`.
fn ratio(x: f64) -> String {
    let whole = |v: f64| (v - v.round()).abs() < 1e-9 * v.max(1.0);
    if x >= 1.0 && whole(x) {
        format!("{x:.0}")
    } else if x > 0.0 && x < 1.0 && whole(1.0 / x) {
        format!("1/{:.0}", 1.0 / x)
    } else {
        crate::text::num::sig(x, 3)
    }
}
