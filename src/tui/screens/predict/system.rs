//! Drawing a system scene on the predict screen: the system's panels
//! (plot, phase, sketch, diagnostics) beside the same question, status and
//! verdict as a rigid body's. The keys, the commitment and the verdict are
//! the one flow of `mod.rs`, the run the one player of [`Live`].

use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;

use crate::deck::{Answer, Measure, Prompt, SystemPanel};
use crate::sim::scene::system::SystemRun;
use crate::tui::app::App;
use crate::tui::i18n::Msg;
use crate::tui::live::Live;
use crate::tui::system_plots;

use super::{Prediction, Verdict};

/// Rows the question may take above a running scene.
const QUESTION_ROWS: usize = 3;

/// The measures a prompt's verdict needs.
pub fn measures(prompt: &Prompt) -> Vec<Measure> {
    let mut out: Vec<Measure> = match &prompt.answer {
        Answer::Choice { choices, .. } => choices.iter().flat_map(|c| c.when.measures()).collect(),
        Answer::Number { measure, .. } => vec![*measure],
    };
    out.sort();
    out.dedup();
    out
}

/// The panels the scene shows, side by side in rows of two.
fn panel_areas(area: Rect, show: &[SystemPanel]) -> Vec<(SystemPanel, Rect)> {
    let drawn: Vec<SystemPanel> = show
        .iter()
        .copied()
        .filter(|p| *p != SystemPanel::Diagnostics)
        .collect();
    if drawn.is_empty() {
        return Vec::new();
    }
    let rows = drawn.len().div_ceil(2);
    let row_areas = Layout::vertical(vec![Constraint::Fill(1); rows]).split(area);
    let mut out = Vec::new();
    for (r, chunk) in drawn.chunks(2).enumerate() {
        let cols = Layout::horizontal(vec![Constraint::Fill(1); chunk.len()]).split(row_areas[r]);
        for (p, rect) in chunk.iter().zip(cols.iter()) {
            out.push((*p, *rect));
        }
    }
    out
}

pub fn draw(
    frame: &mut Frame,
    area: Rect,
    app: &App,
    (prompt, prediction): (&Prompt, Prediction),
    (live, run): (&Live, &SystemRun),
    verdict: Option<&Verdict>,
    show_diagnostics: bool,
) {
    let t = &app.theme;
    let diag_lines = if show_diagnostics && run.scene().shows(SystemPanel::Diagnostics) {
        let line = system_plots::diagnostics_line(run, &app.lang);
        super::parts::fold_parts(line.trim_start(), area.width as usize)
    } else {
        Vec::new()
    };
    // The same banner, prediction and evidence as a rigid body's verdict.
    let verdict_lines = verdict
        .map(|v| super::verdict::for_run(app, prompt, prediction, v, live, area.width as usize))
        .unwrap_or_default();
    let verdict_h = (verdict_lines.len() as u16).min(area.height.saturating_sub(6));
    let hints_h = 1;
    // The question wraps (up to three lines, the last cut with "…") above
    // the prediction, so a long one is never cut mid-word.
    let q = crate::text::render(prompt.question.get(&app.lang));
    let width = usize::from(area.width).max(1);
    let mut question = crate::tui::wrap::wrap_plain(&q, t.strong(), width);
    if question.len() > QUESTION_ROWS {
        question.truncate(QUESTION_ROWS);
        if let Some(last) = question.pop() {
            let text: String = last.spans.iter().map(|s| s.content.as_ref()).collect();
            let cut = crate::tui::wrap::ellipsize(&format!("{text} …"), width);
            question.push(Line::styled(cut, t.strong()));
        }
    }
    let top_h = question.len().max(1) as u16 + 1;
    let [top, panels, status, diag_area, hints, verdict_area] = Layout::vertical([
        Constraint::Length(top_h),
        Constraint::Fill(1),
        Constraint::Length(1),
        Constraint::Length(diag_lines.len() as u16),
        Constraint::Length(hints_h),
        Constraint::Length(verdict_h),
    ])
    .areas(area);
    question.push(Line::from(vec![
        Span::styled(format!("{}: ", app.tr(Msg::YourPrediction)), t.dim()),
        Span::styled(
            super::verdict::prediction_text(app, prompt, prediction),
            t.heading(),
        ),
    ]));
    frame.render_widget(Paragraph::new(question), top);
    let sys = run;
    for (panel, rect) in panel_areas(panels, &run.scene().show) {
        match panel {
            SystemPanel::Plot => system_plots::plot(frame, rect, sys, &app.lang, t),
            SystemPanel::Phase => system_plots::phase(frame, rect, sys, &app.lang, t),
            SystemPanel::Sketch => system_plots::sketch(frame, rect, sys, &app.lang, t),
            SystemPanel::Diagnostics => {}
        }
    }
    frame.render_widget(
        super::parts::status_line(app, live, None, status.width),
        status,
    );
    frame.render_widget(super::parts::diagnostics(app, diag_lines), diag_area);
    frame.render_widget(
        super::parts::hints_line(app, prompt, verdict.is_some(), hints.width),
        hints,
    );
    if !verdict_lines.is_empty() {
        frame.render_widget(Paragraph::new(verdict_lines), verdict_area);
    }
}
