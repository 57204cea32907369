//! Drawing the predict screen: the question and the commitment, then the
//! scene's panels, the run's status and diagnostics, and the verdict.

use std::cell::Cell;

use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;

use crate::deck::{Answer, Measure, Panel, Prompt};
use crate::sim::scene::SceneRun;
use crate::tui::app::App;
use crate::tui::i18n::Msg;
use crate::tui::live::{Live, Sim};
use crate::tui::plots;
use crate::tui::wrap::{Run, wrap};

use super::parts::{
    cut_lines, diagnostics, draw_question, fold_parts, hints_line, play_areas, question_lines,
    status_line,
};
use super::{Phase, PredictState, Prediction, Verdict, prompt};

/// A number as the verdict shows it: integers plainly, others with 3
/// significant digits.
pub fn fmt_value(v: f64) -> String {
    if v.fract() == 0.0 && v.abs() < 1e9 {
        format!("{v:.0}")
    } else if v != 0.0 && (v.abs() < 1e-3 || v.abs() >= 1e6) {
        format!("{v:.2e}")
    } else {
        let digits = (2 - v.abs().log10().floor() as i32).max(0) as usize;
        format!("{v:.digits$}")
    }
}

pub fn draw(frame: &mut Frame, area: Rect, app: &App, state: &PredictState) {
    let Some(prompt) = prompt(app, state) else {
        return;
    };
    match &state.phase {
        Phase::Ask {
            selected,
            input,
            error,
        } => draw_ask(frame, area, app, prompt, *selected, input, error.as_deref()),
        Phase::Play {
            prediction,
            run,
            verdict,
            ..
        } => {
            let verdict = verdict.as_ref();
            // Whether the scene has knobs: the key row then offers `x`.
            let explorable = app
                .decks
                .get(state.deck)
                .and_then(|d| d.explore(&prompt.scene))
                .is_some_and(|e| !e.knobs.is_empty());
            let diag = (state.shows_diagnostics(), state.question_first, explorable);
            let said = (prompt, *prediction);
            let scheduled = state.rated.as_ref().map(|r| super::scheduled_text(app, r));
            let verdict = verdict.map(|v| (v, &state.verdict_scroll, scheduled.as_deref()));
            match run.sim() {
                Sim::Rigid(r) => draw_play(frame, area, app, said, (run, r), verdict, diag),
                Sim::System { run: sys, .. } => {
                    super::system::draw(frame, area, app, said, (run, sys), verdict, diag)
                }
            }
        }
        // Drawn by `explore.rs` (which draws the panels with this module's
        // helpers), chosen in `mod.rs`.
        Phase::Explore { .. } => {}
    }
}

fn draw_ask(
    frame: &mut Frame,
    area: Rect,
    app: &App,
    prompt: &Prompt,
    selected: usize,
    input: &str,
    error: Option<&str>,
) {
    let t = &app.theme;
    let area = area.inner(ratatui::layout::Margin::new(1, 0));
    let width = area.width as usize;
    let mut answer = Vec::new();
    match &prompt.answer {
        Answer::Choice { choices, .. } => {
            for (i, c) in choices.iter().enumerate() {
                let label = crate::text::render(c.label.get(&app.lang));
                let style = if i == selected {
                    t.selected()
                } else {
                    t.text()
                };
                let marker = if i == selected { "› " } else { "  " };
                answer.push(Line::from(vec![
                    Span::styled(marker, t.key()),
                    Span::styled(format!("{}. {label}", i + 1), style),
                ]));
            }
        }
        Answer::Formula(_) => {
            answer.push(Line::from(vec![
                Span::styled("> ", t.key()),
                Span::styled(
                    format!("{}▏", crate::text::safe::one_line(input)),
                    t.strong(),
                ),
            ]));
            if let Some(e) = error {
                answer.push(Line::styled(e.to_string(), t.bad()));
            }
        }
        Answer::Number { unit, .. } => {
            answer.push(Line::from(vec![
                Span::styled("> ", t.key()),
                Span::styled(format!("{input}▏"), t.strong()),
            ]));
            let hint = format!("  unit: {unit} ({})", app.tr(Msg::UnitOptional));
            answer.push(Line::styled(hint, t.dim()));
            if let Some(e) = error {
                answer.push(Line::styled(e.to_string(), t.bad()));
            }
        }
    }
    let hint = wrap(
        &[Run::new(app.tr(Msg::CommitFirst), t.dim())],
        width,
        Run::new("", t.dim()),
        Run::new("", t.dim()),
    );
    // On a short screen the answers and the hint keep their rows: the
    // spacing goes first, then the question's later lines (cut with "…").
    let question = question_lines(app, prompt, width);
    let rows = area.height as usize;
    let fixed = 1 + answer.len() + hint.len();
    let spaced = fixed + question.len() + 2 <= rows;
    let room = rows.saturating_sub(fixed).max(1);
    let shown = if spaced {
        question.len()
    } else {
        room.min(question.len())
    };
    let mut lines = vec![Line::styled(app.tr(Msg::Question), t.heading())];
    lines.extend(cut_lines(question, shown, width));
    if spaced {
        lines.push(Line::default());
    }
    lines.extend(answer);
    if spaced {
        lines.push(Line::default());
    }
    lines.extend(hint);
    frame.render_widget(Paragraph::new(lines), area);
}

fn draw_play(
    frame: &mut Frame,
    area: Rect,
    app: &App,
    (prompt, prediction): (&Prompt, Prediction),
    (live, run): (&Live, &SceneRun),
    verdict: Option<(&Verdict, &Cell<usize>, Option<&str>)>,
    (show_diagnostics, question_first, explorable): (bool, bool, bool),
) {
    let scheduled = verdict.and_then(|v| v.2);
    let (verdict, scroll) = (verdict.map(|v| v.0), verdict.map(|v| v.1));
    let width = area.width as usize;
    let diag_lines = match run.diagnostics() {
        Some(d) if show_diagnostics && run.scene().shows(Panel::Diagnostics) => {
            let err = d.error.map_or("—".to_string(), sci);
            let mut line = format!(
                "{} · ΔE/E {} · Δ|L|²/|L|² {} · {} {}",
                run.method().label(),
                sci(d.energy_drift),
                sci(d.momentum_drift),
                app.tr(Msg::ErrorVsExact),
                err,
            );
            line.push_str(&format!(
                " · {} µs phys + {} µs draw",
                app.frame_us.physics, app.frame_us.draw
            ));
            if let Some(q) = d.qnorm_drift {
                line.push_str(&format!(" · ||q|−1| {}", sci(q)));
            }
            fold_parts(&line, width)
        }
        _ => Vec::new(),
    };
    let diag = diag_lines.len() as u16;
    let mut verdict_lines = verdict
        .map(|v| super::verdict::for_run(app, prompt, prediction, v, live, width))
        .unwrap_or_default();
    super::parts::push_scheduled(app, &mut verdict_lines, scheduled, width);
    let question = question_lines(app, prompt, width.saturating_sub(1).max(1));
    let [top, said, panels, status, diag_area, hints, verdict_area] = play_areas(
        area,
        question.len(),
        verdict_lines.len(),
        diag,
        (verdict.is_none(), question_first),
    );
    let question_cut = question_first || question.len() > usize::from(top.height);
    draw_question(frame, app, (prompt, prediction), question, (top, said));

    // A small screen after the verdict keeps the evidence: ω (and the
    // growth on its log scale) rather than every panel squeezed.
    let growth = matches!(
        prompt.answer,
        Answer::Number {
            measure: Measure::GrowthRate | Measure::EfoldTime,
            ..
        }
    );
    rigid_panels(frame, panels, app, run, (growth, verdict.is_some()));

    let flips = Some(run.flip_times().len());
    frame.render_widget(status_line(app, live, flips, status.width), status);
    frame.render_widget(diagnostics(app, diag_lines), diag_area);

    frame.render_widget(
        hints_line(
            app,
            prompt,
            (verdict.is_some(), question_cut, explorable),
            hints.width,
        ),
        hints,
    );
    if verdict.is_some() {
        let shown = super::parts::verdict_window(app, verdict_lines, scroll, verdict_area);
        frame.render_widget(Paragraph::new(shown), verdict_area);
    }
}

/// A rigid body's panels in `panels`: the scene's, with |ω⊥| on a log
/// scale for a growth prompt (`growth`); a small area beside other text
/// (`crowded`: the verdict) keeps ω only.
pub(super) fn rigid_panels(
    frame: &mut Frame,
    panels: Rect,
    app: &App,
    run: &SceneRun,
    (growth, crowded): (bool, bool),
) {
    let t = &app.theme;
    let mut panes: Vec<Pane> = run.scene().show.iter().map(|p| Pane::Scene(*p)).collect();
    if growth {
        let at = panes
            .iter()
            .position(|p| *p == Pane::Scene(Panel::Omega))
            .map_or(0, |i| i + 1);
        panes.insert(at, Pane::Growth);
    }
    if crowded && panels.height < 12 {
        panes.retain(|p| matches!(p, Pane::Scene(Panel::Omega) | Pane::Growth));
    }
    for (pane, rect) in pane_areas(panels, &panes) {
        match pane {
            Pane::Scene(Panel::Omega) => {
                plots::omega(frame, rect, run, app.tr(Msg::Omega).to_string(), t)
            }
            Pane::Scene(Panel::Body) => crate::tui::solid::draw(frame, rect, run, &app.lang, t),
            Pane::Scene(Panel::Polhode) => {
                plots::polhode(frame, rect, run, format!(" {} ", app.tr(Msg::Polhode)), t)
            }
            Pane::Scene(Panel::Diagnostics) => {}
            Pane::Growth => crate::tui::logplot::growth(frame, rect, run, &app.lang, t),
        }
    }
}

/// What the panel area holds: the scene's panels and, for a growth-rate
/// prompt, |ω⊥| on a logarithmic axis.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Pane {
    Scene(Panel),
    Growth,
}

/// Areas for the panes (diagnostics is a text line, not a pane).
fn pane_areas(area: Rect, panes: &[Pane]) -> Vec<(Pane, Rect)> {
    let plots: Vec<Pane> = panes
        .iter()
        .copied()
        .filter(|p| *p != Pane::Scene(Panel::Diagnostics))
        .collect();
    // Below three rows a panel is all border.
    if area.height < 3 || area.width < 3 {
        return Vec::new();
    }
    let wide = area.width >= area.height * 3;
    let strip = |p: &Pane| matches!(p, Pane::Scene(Panel::Omega) | Pane::Growth);
    match plots.as_slice() {
        [] => Vec::new(),
        [one] => vec![(*one, area)],
        [a, b] => {
            let [x, y] = if wide {
                Layout::horizontal([Constraint::Fill(1); 2]).areas(area)
            } else {
                Layout::vertical([Constraint::Fill(1); 2]).areas(area)
            };
            vec![(*a, x), (*b, y)]
        }
        many => {
            // The plots against time get a full-width strip; the others
            // share the rest.
            let (first, rest): (Vec<Pane>, Vec<Pane>) = many.iter().partition(|p| strip(p));
            let (top, bottom) = if first.is_empty() {
                (None, area)
            } else if rest.is_empty() {
                (Some(area), Rect::default())
            } else {
                let [t, b] =
                    Layout::vertical([Constraint::Percentage(45), Constraint::Fill(1)]).areas(area);
                (Some(t), b)
            };
            let mut out = Vec::new();
            if let Some(t) = top {
                let cols = Layout::horizontal(vec![Constraint::Fill(1); first.len()]).split(t);
                out.extend(first.into_iter().zip(cols.iter().copied()));
            }
            if !rest.is_empty() {
                let cols = Layout::horizontal(vec![Constraint::Fill(1); rest.len()]).split(bottom);
                out.extend(rest.into_iter().zip(cols.iter().copied()));
            }
            out
        }
    }
}

/// A drift or error: "0" when exactly zero, else two significant digits.
fn sci(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else {
        format!("{x:.1e}")
    }
}
