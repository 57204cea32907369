//! Drawing a system scene on the predict screen: the system's panels
//! (plot, phase, sketch, diagnostics) beside the same question, status and
//! verdict as a rigid body's. The keys, the commitment and the verdict are
//! the one flow of `mod.rs`, the run the one player of [`Live`].

use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::widgets::Paragraph;

use crate::deck::{Answer, Measure, Prompt, SystemPanel};
use crate::sim::scene::system::SystemRun;
use crate::tui::app::App;
use crate::tui::live::Live;
use crate::tui::system_plots;

use super::{Prediction, Verdict};

/// The measures a prompt's verdict needs.
pub fn measures(prompt: &Prompt) -> Vec<Measure> {
    let mut out: Vec<Measure> = match &prompt.answer {
        Answer::Choice { choices, .. } => choices.iter().flat_map(|c| c.when.measures()).collect(),
        Answer::Number { measure, .. } => vec![*measure],
        Answer::Formula(_) => Vec::new(),
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

/// A system's panels in `area`.
pub(super) fn system_panels(frame: &mut Frame, area: Rect, app: &App, sys: &SystemRun) {
    let t = &app.theme;
    for (panel, rect) in panel_areas(area, &sys.scene().show) {
        match panel {
            SystemPanel::Plot => system_plots::plot(frame, rect, sys, &app.lang, t),
            SystemPanel::Phase => system_plots::phase(frame, rect, sys, &app.lang, t),
            SystemPanel::Sketch => system_plots::sketch(frame, rect, sys, &app.lang, t),
            SystemPanel::Diagnostics => {}
        }
    }
}

pub fn draw(
    frame: &mut Frame,
    area: Rect,
    app: &App,
    (prompt, prediction): (&Prompt, Prediction),
    (live, run): (&Live, &SystemRun),
    verdict: Option<(&Verdict, &std::cell::Cell<usize>, Option<&str>)>,
    (show_diagnostics, question_first, explorable): (bool, bool, bool),
) {
    let scheduled = verdict.and_then(|v| v.2);
    let (verdict, scroll) = (verdict.map(|v| v.0), verdict.map(|v| v.1));
    let diag_lines = if show_diagnostics && run.scene().shows(SystemPanel::Diagnostics) {
        let line = system_plots::diagnostics_line(run, &app.lang);
        super::parts::fold_parts(line.trim_start(), area.width as usize)
    } else {
        Vec::new()
    };
    // The same banner, prediction and evidence as a rigid body's verdict.
    let mut verdict_lines = verdict
        .map(|v| super::verdict::for_run(app, prompt, prediction, v, live, area.width as usize))
        .unwrap_or_default();
    super::parts::push_scheduled(app, &mut verdict_lines, scheduled, area.width as usize);
    // The same rows as a rigid body's: the question whole above the run
    // (the panels give way first), the prediction under it until the
    // verdict, which repeats it.
    let width = usize::from(area.width).max(1);
    let question = super::parts::question_lines(app, prompt, width.saturating_sub(1).max(1));
    let [top, said, panels, status, diag_area, hints, verdict_area] = super::parts::play_areas(
        area,
        question.len(),
        verdict_lines.len(),
        diag_lines.len() as u16,
        (verdict.is_none(), question_first),
    );
    let question_cut = question_first || question.len() > usize::from(top.height);
    super::parts::draw_question(frame, app, (prompt, prediction), question, (top, said));
    system_panels(frame, panels, app, run);
    frame.render_widget(
        super::parts::status_line(app, live, None, status.width),
        status,
    );
    frame.render_widget(super::parts::diagnostics(app, diag_lines), diag_area);
    frame.render_widget(
        super::parts::hints_line(
            app,
            prompt,
            (verdict.is_some(), question_cut, explorable),
            hints.width,
        ),
        hints,
    );
    if !verdict_lines.is_empty() {
        let shown = super::parts::verdict_window(app, verdict_lines, scroll, verdict_area);
        frame.render_widget(Paragraph::new(shown), verdict_area);
    }
}
