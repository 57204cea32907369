//! Exam mode: the learner names the exam day, the planner spreads the
//! reviews that bring every card of the deck to the desired retention on
//! that day, and today's share is studied at once, with the expected recall
//! on exam day shown above the card, rising as the answers come in.

use chrono::{NaiveDate, Utc};
use crossterm::event::KeyCode::{Backspace, Enter, Esc};
use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Margin, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Wrap};

use crate::sched::DayOf as _;
use crate::sched::plan::{self, Model, Plan, PlanError};
use crate::sched::{ItemKey, deck_items};
use crate::text::num::rounded;
use crate::tui::action::Action;
use crate::tui::app::App;
use crate::tui::i18n::{Msg, Words, exam as words};
use crate::tui::keymap::{Binding, Context};

use super::review::ReviewState;
use super::{Nav, View};

/// Typing the exam date.
pub const DATE_KEYS: &[Binding] = &[
    Binding::typing(Words("the exam date", "exam ki tareekh")),
    Binding::new(
        "Enter",
        Words(
            "plan, and study today's share",
            "plan banao, aaj ka hissa padho",
        ),
        &[(Enter, Action::Submit)],
    ),
    Binding::new(
        "Backspace",
        Words("delete a character", "ek akshar mitao"),
        &[(Backspace, Action::Backspace)],
    ),
    Binding::new(
        "Esc",
        Words("back to the decks", "decks par wapas"),
        &[(Esc, Action::Back)],
    ),
];

pub enum Phase {
    /// The date so far, and what was wrong with the last one entered.
    Date { input: String, error: Option<Words> },
    /// Today's share, reviewed on an ordinary review screen.
    Study(Box<Study>),
}

pub struct Study {
    pub exam: NaiveDate,
    pub today: NaiveDate,
    pub keys: Vec<ItemKey>,
    pub plan: Plan,
    /// Planned for today.
    pub share: usize,
    /// Expected recall on exam day when the mode opened, and now.
    pub start: f64,
    pub now: f64,
    pub review: ReviewState,
}

pub struct ExamState {
    pub deck: usize,
    pub phase: Phase,
}

impl ExamState {
    /// The date prompt, filled with the exam date remembered while it is
    /// still ahead.
    pub fn new(app: &App, deck: usize) -> ExamState {
        let (today, _) = grid(app);
        let input = app
            .services
            .study
            .config
            .exam_ahead(today)
            .map(|d| d.format("%Y-%m-%d").to_string())
            .unwrap_or_default();
        ExamState {
            deck,
            phase: Phase::Date { input, error: None },
        }
    }
}

impl View for ExamState {
    fn ends_session(&self) -> bool {
        true
    }

    fn context(&self) -> Context {
        match &self.phase {
            Phase::Date { .. } => Context::ExamDate,
            Phase::Study(s) => s.review.context(),
        }
    }
    fn apply(&mut self, app: &mut App, action: Action) -> Nav {
        apply(app, self, action)
    }
    fn draw(&self, frame: &mut Frame, area: Rect, app: &App) {
        draw(frame, area, app, self)
    }
    fn name(&self) -> Msg {
        Msg::Exam
    }
    fn deck(&self) -> Option<usize> {
        Some(self.deck)
    }
}

pub fn apply(app: &mut App, state: &mut ExamState, action: Action) -> Nav {
    match &mut state.phase {
        Phase::Date { input, error } => match action {
            Action::Back => return Nav::Pop,
            Action::Input(c) => {
                input.push(c);
                *error = None;
            }
            Action::Backspace => {
                input.pop();
                *error = None;
            }
            Action::Submit => match start(app, state.deck, &input.clone()) {
                Ok(study) => {
                    // Remembered once planned for; a config that cannot be
                    // written is said, and the study goes on.
                    if let Err(e) = app.services.remember_exam(study.exam) {
                        app.error(e);
                    }
                    state.phase = Phase::Study(Box::new(study));
                }
                Err(Ok(why)) => *error = Some(why),
                Err(Err(e)) => app.error(e),
            },
            _ => {}
        },
        Phase::Study(study) => {
            let nav = study.review.apply(app, action);
            study.now = expected_now(app, study);
            return nav;
        }
    }
    Nav::Stay
}

/// The study day of now and a function naming the study day of any time,
/// with the day boundary the app uses.
type DayOf = Box<dyn Fn(chrono::DateTime<Utc>) -> NaiveDate>;

fn grid(app: &App) -> (NaiveDate, DayOf) {
    let days = app.services.study.days();
    (
        days.day_of(app.services.now()),
        Box::new(move |t| days.day_of(t)),
    )
}

/// Plans for the date typed and opens today's share. `Err(Ok(words))`: the
/// date is wrong (said in the screen); `Err(Err(text))`: the store failed.
fn start(app: &mut App, deck: usize, input: &str) -> Result<Study, Result<Words, String>> {
    let exam =
        NaiveDate::parse_from_str(input.trim(), "%Y-%m-%d").map_err(|_| Ok(words::NOT_A_DATE))?;
    let Some(d) = app.decks.get(deck) else {
        return Err(Err("no such deck".into()));
    };
    // A suspended item is out of every queue: no plan schedules it.
    let statuses = app
        .services
        .study
        .store
        .statuses()
        .map_err(|e| Err(e.to_string()))?;
    let mut keys = deck_items(d);
    keys.retain(|k| !statuses.get(k).is_some_and(|s| s.suspended));
    let states = app
        .services
        .study
        .store
        .states(&d.id)
        .map_err(|e| Err(e.to_string()))?;
    let (today, day_of) = grid(app);
    // The deck's preset: its retention, daily limit and parameters.
    let config = app.services.study.config.for_deck(&d.id);
    let problem = plan::exam_problem(
        &keys,
        &states,
        today,
        exam,
        &day_of,
        config.desired_retention,
        config.reviews_per_day as usize,
    )
    .map_err(|e| match e {
        PlanError::ExamInPast { .. } => Ok(words::IN_PAST),
        PlanError::ExamTooFar { .. } => Ok(words::TOO_FAR),
        other => Err(other.to_string()),
    })?;
    let scheduler = app.services.study.scheduler_for(&d.id);
    let plan = plan::plan(&scheduler, &problem).map_err(|e| Err(e.to_string()))?;
    let todays: Vec<ItemKey> = plan
        .due_on(0)
        .into_iter()
        .map(|i| keys[i].clone())
        .collect();
    let share = todays.len();
    let review = ReviewState::open_plan(app, deck, todays).map_err(Err)?;
    let mut study = Study {
        exam,
        today,
        keys,
        start: plan.expected_without(),
        now: 0.0,
        plan,
        share,
        review,
    };
    study.now = expected_now(app, &study);
    Ok(study)
}

/// Expected recall on exam day from the states as they are now (the
/// answers given today included), with no more reviews.
fn expected_now(app: &App, study: &Study) -> f64 {
    let (today, day_of) = grid(app);
    let deck = study.keys.first().map_or("", |k| k.deck.as_str());
    let scheduler = app.services.study.scheduler_for(deck);
    let model = Model::new(&scheduler, (study.exam - today).num_days());
    plan::memories(&study.keys, &study.review.states, today, &day_of)
        .iter()
        .map(|m| model.without(m.as_ref()))
        .sum()
}

pub fn draw(frame: &mut Frame, area: Rect, app: &App, state: &ExamState) {
    match &state.phase {
        Phase::Date { input, error } => draw_date(frame, area, app, input, *error),
        Phase::Study(study) => draw_study(frame, area, app, study),
    }
}

fn draw_date(frame: &mut Frame, area: Rect, app: &App, input: &str, error: Option<Words>) {
    let t = &app.theme;
    let mut lines = vec![
        Line::styled(words::DATE_PROMPT.get(&app.lang), t.heading()),
        Line::from(vec![
            Span::styled("> ", t.key()),
            Span::styled(format!("{input}▏"), t.strong()),
        ]),
        Line::default(),
        Line::styled(words::DATE_HINT.get(&app.lang), t.dim()),
    ];
    if let Some(why) = error {
        lines.push(Line::default());
        lines.push(Line::styled(why.get(&app.lang), t.bad()));
    }
    frame.render_widget(
        Paragraph::new(lines).wrap(Wrap { trim: false }),
        area.inner(Margin::new(2, 1)),
    );
}

fn draw_study(frame: &mut Frame, area: Rect, app: &App, study: &Study) {
    let t = &app.theme;
    let short = study.plan.shortfall();
    let [head, said, gauge, note, rest] = Layout::vertical([
        Constraint::Length(1),
        Constraint::Length(1),
        Constraint::Length(1),
        Constraint::Length(u16::from(short > 0)),
        Constraint::Fill(1),
    ])
    .areas(area);
    let target = rounded(study.plan.target, 4);
    let header = words::header(
        &app.lang,
        &study.exam.to_string(),
        (study.exam - study.today).num_days(),
        &target,
        study.share,
        study.plan.reviews(),
    );
    frame.render_widget(
        Paragraph::new(Span::styled(format!(" {header}"), t.heading())),
        head,
    );
    let n = study.keys.len();
    let label = words::expected(
        &app.lang,
        &rounded(study.now, 3),
        n,
        &rounded(study.start, 3),
        &rounded(study.plan.expected_with(), 3),
    );
    let ratio = if n == 0 {
        0.0
    } else {
        (study.now / n as f64).clamp(0.0, 1.0)
    };
    // The words on their own line and the bar under them: a label drawn
    // over the bar was overprinted by its blocks.
    frame.render_widget(
        Paragraph::new(Span::styled(format!(" {label}"), t.strong())),
        said,
    );
    // Blocks, not colour alone: the bar reads with NO_COLOR too.
    let room = usize::from(gauge.width).saturating_sub(7);
    let filled = ((ratio * room as f64).round() as usize).min(room);
    frame.render_widget(
        Paragraph::new(Line::from(vec![
            Span::raw(" "),
            Span::styled("█".repeat(filled), t.good()),
            Span::styled("░".repeat(room - filled), t.dim()),
            Span::styled(format!(" {:>3.0}%", 100.0 * ratio), t.dim()),
        ])),
        gauge,
    );
    if short > 0 {
        frame.render_widget(
            Paragraph::new(Span::styled(
                format!(" {}", words::short(&app.lang, short, &target)),
                t.warn(),
            )),
            note,
        );
    }
    study.review.draw(frame, rest, app);
}
