//! A `derive` item in the review screen (issue 24 §5): the derivation
//! walked one step at a time. The steps `study::derive::faded` picks are
//! hidden (their reason shown as a hint) and the learner supplies each
//! (think then reveal, a choice, a formula) before its math appears with
//! the verdict; the rest are shown as a worked example. After the last
//! step the rating goes through `Study::rate` as a card's does.

use ratatui::text::Line;

use crate::deck::{AskKind, Derivation};
use crate::sched::Rating;
use crate::study::derive::{self, Progress, StepAnswer, StepVerdict};
use crate::tui::app::App;
use crate::tui::derivation::{number, step_lines, why_lines};
use crate::tui::i18n::Words;
use crate::tui::i18n::derive as words;
use crate::tui::wrap::{Run, columns, math_runs, wrap, wrap_plain};

/// How far the learner has walked a derivation.
#[derive(Debug, Clone, PartialEq)]
pub struct Walk {
    /// Which steps are faded this time.
    pub faded: Vec<bool>,
    /// Steps shown so far: the next one is `shown`.
    pub shown: usize,
    /// The choice picked for the faded step at `shown` (a choice ask).
    pub chosen: Option<usize>,
    /// Per step: the verdict on the learner's answer (faded steps).
    pub verdicts: Vec<Option<StepVerdict>>,
    /// Per step: what the learner answered, as shown beside the verdict.
    pub answers: Vec<Option<Given>>,
}

/// What the learner gave at a faded step.
#[derive(Debug, Clone, PartialEq)]
pub enum Given {
    /// The label of the choice picked (may hold math).
    Chose(String),
    /// The formula typed (shown as typed).
    Typed(String),
}

/// What the key that goes on does at the step the walk stands at.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Next {
    /// Show the next worked step.
    Step,
    /// Reveal a faded step after thinking.
    Reveal,
    /// Check the choice picked.
    Choose,
    /// Check the formula typed.
    Type,
    /// Every step is shown.
    Done,
}

impl Walk {
    /// A walk with the steps `progress` fades; the first step is shown at
    /// once unless it is faded (or the only one).
    pub fn new(d: &Derivation, progress: Progress) -> Walk {
        let faded = derive::faded(&d.steps, progress);
        let n = d.steps.len();
        let shown = usize::from(n > 1 && !faded.first().copied().unwrap_or(true));
        Walk {
            faded,
            shown,
            chosen: None,
            verdicts: vec![None; n],
            answers: vec![None; n],
        }
    }

    pub fn faded_count(&self) -> usize {
        self.faded.iter().filter(|f| **f).count()
    }

    /// What going on does now.
    pub fn next(&self, d: &Derivation) -> Next {
        let Some(step) = d.steps.get(self.shown) else {
            return Next::Done;
        };
        if !self.faded.get(self.shown).copied().unwrap_or(false) {
            return Next::Step;
        }
        match step.ask.as_ref().map(|a| &a.kind) {
            None | Some(AskKind::Reveal) => Next::Reveal,
            Some(AskKind::Choice { .. }) => Next::Choose,
            Some(AskKind::Formula(_)) => Next::Type,
        }
    }

    /// Whether the learner types at this step (a faded formula ask).
    pub fn typing(&self, d: &Derivation) -> bool {
        self.next(d) == Next::Type
    }

    /// Picks choice `i` of a faded choice step (out of range: nothing).
    pub fn choose(&mut self, d: &Derivation, i: usize) {
        if self.next(d) != Next::Choose {
            return;
        }
        let n = match d.steps[self.shown].ask.as_ref().map(|a| &a.kind) {
            Some(AskKind::Choice { choices, .. }) => choices.len(),
            _ => 0,
        };
        if i < n {
            self.chosen = Some(i);
        }
    }

    /// Goes on by one step: a worked step is shown, a faded one checked
    /// against `input` (a formula) or the choice picked, then shown with
    /// its verdict. `Err` with the words to say when a choice is missing.
    pub fn advance(&mut self, d: &Derivation, input: &str, lang: &str) -> Result<(), &'static str> {
        let i = self.shown;
        let Some(step) = d.steps.get(i) else {
            return Ok(());
        };
        let ask = step.ask.as_ref();
        match self.next(d) {
            Next::Done => return Ok(()),
            Next::Step => {}
            Next::Reveal => self.verdicts[i] = Some(derive::check(ask, &StepAnswer::Revealed)),
            Next::Choose => {
                let Some(c) = self.chosen else {
                    return Err(words::CHOOSE_FIRST.get(lang));
                };
                let (id, label) = match ask.map(|a| &a.kind) {
                    Some(AskKind::Choice { choices, .. }) => match choices.get(c) {
                        Some(ch) => (ch.id.as_str(), ch.label.get(lang).to_string()),
                        None => return Err(words::CHOOSE_FIRST.get(lang)),
                    },
                    _ => return Ok(()),
                };
                self.verdicts[i] = Some(derive::check(ask, &StepAnswer::Chose(id)));
                self.answers[i] = Some(Given::Chose(label));
            }
            Next::Type => {
                self.verdicts[i] = Some(derive::check(ask, &StepAnswer::Typed(input)));
                self.answers[i] = Some(Given::Typed(input.to_string()));
            }
        }
        self.chosen = None;
        self.shown += 1;
        Ok(())
    }

    /// The rating the walk suggests (from the faded steps' verdicts).
    pub fn suggested(&self) -> Rating {
        let v: Vec<StepVerdict> = self.verdicts.iter().flatten().cloned().collect();
        derive::suggested(&v)
    }

    /// The lines of the derivation as far as it is walked; `input` is the
    /// formula typed so far, `done` whether the rating is asked.
    pub fn lines(
        &self,
        app: &App,
        d: &Derivation,
        input: &str,
        width: usize,
    ) -> Vec<Line<'static>> {
        let t = &app.theme;
        let lang = app.lang.as_str();
        let mut lines = wrap(
            &math_runs(d.title.get(lang), t.heading()),
            width,
            Run::new("", t.text()),
            Run::new("", t.text()),
        );
        let faded = self.faded_count();
        let intro = if faded == 0 {
            words::WORKED.get(lang).to_string()
        } else {
            format!(
                "{}: {faded} {} {}",
                words::FADED.get(lang),
                words::OF.get(lang),
                d.steps.len()
            )
        };
        lines.extend(wrap_plain(&intro, t.dim(), width));
        for (i, step) in d.steps.iter().enumerate().take(self.shown) {
            lines.push(Line::default());
            lines.extend(step_lines(app, step, i, width));
            if let Some(v) = &self.verdicts[i] {
                lines.extend(verdict_lines(app, v, self.answers[i].as_ref(), i, width));
            }
        }
        if let Some(step) = d.steps.get(self.shown)
            && self.faded[self.shown]
        {
            let i = self.shown;
            let n = number(i);
            let indent = " ".repeat(columns(&n));
            lines.push(Line::default());
            lines.extend(wrap(
                &[Run::new(words::HIDDEN.get(lang), t.highlight())],
                width,
                Run::new(n, t.key()),
                Run::new(indent.clone(), t.text()),
            ));
            lines.extend(why_lines(app, step, &indent, words::HINT.get(lang), width));
            let ask = step.ask.as_ref();
            if let Some(q) = ask.and_then(|a| a.question.as_ref()) {
                lines.extend(wrap(
                    &math_runs(q.get(lang), t.strong()),
                    width,
                    Run::new(indent.clone(), t.text()),
                    Run::new(indent.clone(), t.text()),
                ));
            }
            let say = |w: Words| {
                wrap(
                    &[Run::new(w.get(lang), t.dim())],
                    width,
                    Run::new(indent.clone(), t.text()),
                    Run::new(indent.clone(), t.text()),
                )
            };
            match ask.map(|a| &a.kind) {
                None | Some(AskKind::Reveal) => lines.extend(say(words::THINK)),
                Some(AskKind::Choice { choices, .. }) => {
                    lines.extend(say(words::CHOOSE));
                    for (k, c) in choices.iter().enumerate() {
                        let picked = self.chosen == Some(k);
                        let mark = if picked { "▸" } else { " " };
                        let style = if picked { t.selected() } else { t.text() };
                        let label = format!("{indent}{mark} {} ", k + 1);
                        let pad = " ".repeat(columns(&label));
                        lines.extend(wrap(
                            &math_runs(c.label.get(lang), style),
                            width,
                            Run::new(label, t.key()),
                            Run::new(pad, t.text()),
                        ));
                    }
                }
                Some(AskKind::Formula(_)) => {
                    lines.extend(say(words::TYPE));
                    lines.extend(wrap(
                        &[Run::new(
                            format!("{}▏", crate::text::safe::one_line(input)),
                            t.strong(),
                        )],
                        width,
                        Run::new(format!("{indent}> "), t.key()),
                        Run::new(format!("{indent}  "), t.key()),
                    ));
                }
            }
        }
        if self.shown >= d.steps.len() && faded > 0 {
            let right = self
                .verdicts
                .iter()
                .flatten()
                .filter(|v| !v.is_wrong())
                .count();
            lines.push(Line::default());
            lines.extend(wrap_plain(
                &format!("{}: {right}/{faded}", words::RESULT.get(lang)),
                t.heading(),
                width,
            ));
        }
        lines
    }
}

/// The verdict under a faded step's math, with what the learner gave.
fn verdict_lines(
    app: &App,
    v: &StepVerdict,
    given: Option<&Given>,
    i: usize,
    width: usize,
) -> Vec<Line<'static>> {
    let t = &app.theme;
    let lang = app.lang.as_str();
    let indent = " ".repeat(columns(&number(i)));
    let (said, style) = match v {
        StepVerdict::Seen => (words::SEEN.get(lang), t.dim()),
        StepVerdict::Right => (words::RIGHT.get(lang), t.good()),
        StepVerdict::Wrong(_) => (words::WRONG.get(lang), t.bad()),
    };
    let mut runs = vec![Run::new(said, style)];
    match given {
        Some(Given::Chose(label)) => {
            runs.push(Run::new(
                format!(" · {}: ", words::YOU_CHOSE.get(lang)),
                t.dim(),
            ));
            runs.extend(math_runs(label, t.text()));
        }
        Some(Given::Typed(text)) => {
            runs.push(Run::new(
                format!(" · {}: ", words::YOU_TYPED.get(lang)),
                t.dim(),
            ));
            runs.push(Run::new(
                crate::text::safe::one_line(text).into_owned(),
                t.text(),
            ));
        }
        None => {}
    }
    let mut out = wrap(
        &runs,
        width,
        Run::new(indent.clone(), t.text()),
        Run::new(indent.clone(), t.text()),
    );
    // A wrong formula's slip, named as a formula card's is.
    if let StepVerdict::Wrong(Some(fv)) = v
        && let Some(s) = crate::tui::i18n::formula_words::feedback(fv, lang)
    {
        out.extend(wrap(
            &[Run::new(s, t.bad())],
            width,
            Run::new(indent.clone(), t.text()),
            Run::new(indent, t.text()),
        ));
    }
    out
}
