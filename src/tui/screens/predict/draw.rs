//! Drawing the predict screen: the question and the commitment, then the
//! scene's panels, the run's status and diagnostics, and the verdict.

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

use super::parts::{diagnostics, fit_spans, fold_parts, hints_line, status_line};
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
            let diag = state.shows_diagnostics();
            let said = (prompt, *prediction);
            match run.sim() {
                Sim::Rigid(r) => draw_play(frame, area, app, said, (run, r), verdict, diag),
                Sim::System { run: sys, .. } => {
                    super::system::draw(frame, area, app, said, (run, sys), verdict, diag)
                }
            }
        }
    }
}

pub(super) fn question_lines(app: &App, prompt: &Prompt, width: usize) -> Vec<Line<'static>> {
    let t = &app.theme;
    wrap(
        &crate::tui::wrap::math_runs(prompt.question.get(&app.lang), t.strong()),
        width,
        Run::new("", t.text()),
        Run::new("", t.text()),
    )
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
    verdict: Option<&Verdict>,
    show_diagnostics: bool,
) {
    let t = &app.theme;
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
    let verdict_lines = verdict
        .map(|v| super::verdict::for_run(app, prompt, prediction, v, live, width))
        .unwrap_or_default();
    let question = question_lines(app, prompt, width.saturating_sub(1).max(1));
    let [top, said, panels, status, diag_area, hints, verdict_area] = play_areas(
        area,
        question.len(),
        verdict_lines.len(),
        diag,
        verdict.is_none(),
    );
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
    let mut panes: Vec<Pane> = run.scene().show.iter().map(|p| Pane::Scene(*p)).collect();
    if growth {
        let at = panes
            .iter()
            .position(|p| *p == Pane::Scene(Panel::Omega))
            .map_or(0, |i| i + 1);
        panes.insert(at, Pane::Growth);
    }
    if verdict.is_some() && panels.height < 12 {
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

    let flips = Some(run.flip_times().len());
    frame.render_widget(status_line(app, live, flips, status.width), status);
    frame.render_widget(diagnostics(app, diag_lines), diag_area);

    frame.render_widget(
        hints_line(app, prompt, verdict.is_some(), hints.width),
        hints,
    );
    if verdict.is_some() {
        let shown = cut_lines(
            verdict_lines,
            verdict_area.height as usize,
            verdict_area.width as usize,
        );
        frame.render_widget(Paragraph::new(shown), verdict_area);
    }
}

/// The rows of a playing scene, a rigid body's and a system's alike:
/// question, prediction (before the verdict), panels, status, diagnostics,
/// hints, verdict. Who gives way when rows are short: the panels first
/// (they take what the question leaves, and are dropped below 3 rows),
/// then the question's later lines; the verdict and one question line
/// stay.
pub(super) fn play_areas(
    area: Rect,
    question: usize,
    verdict: usize,
    diag: u16,
    before_verdict: bool,
) -> [Rect; 7] {
    let before = u16::from(before_verdict);
    let mut rest = area.height.saturating_sub(1 + diag + 1 + before);
    let verdict_h = (verdict as u16).min(rest.saturating_sub(1));
    rest -= verdict_h;
    let question_h = (question as u16).max(1).min(rest);
    rest -= question_h;
    // Below three rows a panel is all border: the question keeps them.
    let (question_h, panels_h) = if rest < 3 {
        (question_h + rest, 0)
    } else {
        (question_h, rest)
    };
    Layout::vertical([
        Constraint::Length(question_h),
        Constraint::Length(before),
        Constraint::Length(panels_h),
        Constraint::Length(1),
        Constraint::Length(diag),
        Constraint::Length(1),
        Constraint::Length(verdict_h),
    ])
    .areas(area)
}

/// The question (wrapped, its math kept whole; cut with "…" only when not
/// even the panels' giving way leaves it room) and, before the verdict,
/// the learner's prediction under it.
pub(super) fn draw_question(
    frame: &mut Frame,
    app: &App,
    (prompt, prediction): (&Prompt, Prediction),
    question: Vec<Line<'static>>,
    (top, said): (Rect, Rect),
) {
    let t = &app.theme;
    let shown = cut_lines(question, top.height as usize, top.width as usize);
    frame.render_widget(Paragraph::new(shown), top);
    if said.height > 0 {
        // One row: cut at a word with "…" when the prediction is longer
        // (the verdict repeats it whole).
        let lines = wrap(
            &[
                Run::new(format!("{}: ", app.tr(Msg::YourPrediction)), t.dim()),
                Run::new(
                    super::verdict::prediction_text(app, prompt, prediction),
                    t.heading(),
                ),
            ],
            (said.width as usize).saturating_sub(1).max(1),
            Run::new("", t.dim()),
            Run::new("", t.dim()),
        );
        frame.render_widget(
            Paragraph::new(cut_lines(lines, 1, said.width as usize)),
            said,
        );
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

/// The first `n` of `lines`, the last one ending in "…" when some were
/// left out.
fn cut_lines(mut lines: Vec<Line<'static>>, n: usize, width: usize) -> Vec<Line<'static>> {
    if lines.len() <= n {
        return lines;
    }
    lines.truncate(n);
    if let Some(last) = lines.pop() {
        let mut spans = last.spans;
        spans.push(Span::raw("…"));
        let used: usize = spans.iter().map(|s| s.width()).sum();
        // Room for the ellipsis inside the width.
        let spans = if used > width {
            fit_spans(spans[..spans.len() - 1].to_vec(), width.saturating_sub(1))
                .spans
                .into_iter()
                .chain([Span::raw("…")])
                .collect()
        } else {
            spans
        };
        lines.push(Line::from(spans));
    }
    lines
}

/// A drift or error: "0" when exactly zero, else two significant digits.
fn sci(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else {
        format!("{x:.1e}")
    }
}
