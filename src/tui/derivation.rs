//! Drawing a derivation's steps (issue 24 §5), shared by the review screen
//! (a `derive` item, steps faded for the learner) and the reader (every
//! derivation as a worked example): a step's number and math, and under
//! it why the step is taken.

use ratatui::text::Line;

use crate::deck::Step;
use crate::tui::app::App;
use crate::tui::i18n::derive as words;
use crate::tui::wrap::{Run, columns, math_runs, wrap};

/// The prefix of step `i` (counted from 0): "3. ".
pub fn number(i: usize) -> String {
    format!("{}. ", i + 1)
}

/// Step `i` shown whole: its math after its number, then why, indented.
pub fn step_lines(app: &App, step: &Step, i: usize, width: usize) -> Vec<Line<'static>> {
    let t = &app.theme;
    let lang = app.lang.as_str();
    let n = number(i);
    let indent = " ".repeat(columns(&n));
    let mut out = wrap(
        &math_runs(step.math.get(lang), t.strong()),
        width,
        Run::new(n, t.key()),
        Run::new(indent.clone(), t.text()),
    );
    out.extend(why_lines(app, step, &indent, words::WHY.get(lang), width));
    out
}

/// Why the step is taken, after `label` ("why: …", or "hint: …" on a
/// faded step), indented under the step's math.
pub fn why_lines(
    app: &App,
    step: &Step,
    indent: &str,
    label: &str,
    width: usize,
) -> Vec<Line<'static>> {
    let t = &app.theme;
    let mut runs = vec![Run::new(format!("{label}: "), t.dim())];
    runs.extend(math_runs(step.why.get(&app.lang), t.text()));
    wrap(
        &runs,
        width,
        Run::new(indent.to_string(), t.text()),
        Run::new(indent.to_string(), t.text()),
    )
}
