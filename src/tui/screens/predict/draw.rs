//! Drawing the predict screen: the question and the commitment, then the
//! scene's panels, the run's status and diagnostics, and the verdict.

use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Wrap};

use crate::deck::{Answer, Measure, Panel, Prompt};
use crate::text::num::Num;
use crate::tui::app::App;
use crate::tui::i18n::Msg;
use crate::tui::live::LiveRun;
use crate::tui::plots;
use crate::tui::wrap::{Run, wrap};

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
        } => draw_play(frame, area, app, prompt, *prediction, run, verdict.as_ref()),
        Phase::System {
            prediction,
            run,
            verdict,
        } => super::system::draw(frame, area, app, prompt, *prediction, run, verdict.as_ref()),
    }
}

fn question_lines(app: &App, prompt: &Prompt, width: usize) -> Vec<Line<'static>> {
    let t = &app.theme;
    let q = crate::text::render(prompt.question.get(&app.lang));
    wrap(
        &[Run::new(q, t.strong())],
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
    let mut lines = vec![Line::styled(app.tr(Msg::Question), t.heading())];
    lines.extend(question_lines(app, prompt, width));
    lines.push(Line::default());
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
                lines.push(Line::from(vec![
                    Span::styled(marker, t.key()),
                    Span::styled(format!("{}. {label}", i + 1), style),
                ]));
            }
        }
        Answer::Number { unit, .. } => {
            lines.push(Line::from(vec![
                Span::styled("> ", t.key()),
                Span::styled(format!("{input}▏"), t.strong()),
            ]));
            let hint = format!("  unit: {unit} ({})", app.tr(Msg::UnitOptional));
            lines.push(Line::styled(hint, t.dim()));
            if let Some(e) = error {
                lines.push(Line::styled(e.to_string(), t.bad()));
            }
        }
    }
    lines.push(Line::default());
    let hint = app.tr(Msg::CommitFirst);
    lines.extend(wrap(
        &[Run::new(hint, t.dim())],
        width,
        Run::new("", t.dim()),
        Run::new("", t.dim()),
    ));
    frame.render_widget(Paragraph::new(lines), area);
}

pub(super) fn prediction_text(app: &App, prompt: &Prompt, p: Prediction) -> String {
    match (p, &prompt.answer) {
        (Prediction::Choice(i), Answer::Choice { choices, .. }) => choices
            .get(i)
            .map(|c| crate::text::render(c.label.get(&app.lang)))
            .unwrap_or_default(),
        (Prediction::Number(v), Answer::Number { unit, .. }) => format!("{} {unit}", fmt_value(v)),
        _ => String::new(),
    }
}

/// Areas for the scene's panels (diagnostics is a text line, not a panel).
fn panel_areas(area: Rect, panels: &[Panel]) -> Vec<(Panel, Rect)> {
    let plots: Vec<Panel> = panels
        .iter()
        .copied()
        .filter(|p| *p != Panel::Diagnostics)
        .collect();
    let wide = area.width >= area.height * 3;
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
            // ω against time gets a full-width strip; the others share the rest.
            let (first, rest): (Vec<Panel>, Vec<Panel>) = if many.contains(&Panel::Omega) {
                (
                    vec![Panel::Omega],
                    many.iter()
                        .copied()
                        .filter(|p| *p != Panel::Omega)
                        .collect(),
                )
            } else {
                (Vec::new(), many.to_vec())
            };
            let (top, bottom) = if first.is_empty() {
                (None, area)
            } else {
                let [t, b] =
                    Layout::vertical([Constraint::Percentage(40), Constraint::Fill(1)]).areas(area);
                (Some(t), b)
            };
            let mut out = Vec::new();
            if let Some(t) = top {
                out.push((Panel::Omega, t));
            }
            let cols = Layout::horizontal(vec![Constraint::Fill(1); rest.len()]).split(bottom);
            out.extend(rest.into_iter().zip(cols.iter().copied()));
            out
        }
    }
}

fn draw_play(
    frame: &mut Frame,
    area: Rect,
    app: &App,
    prompt: &Prompt,
    prediction: Prediction,
    run: &LiveRun,
    verdict: Option<&Verdict>,
) {
    let t = &app.theme;
    let diag = run.scene().shows(Panel::Diagnostics);
    let verdict_h = if verdict.is_some() { 5 } else { 0 };
    let hints_h = u16::from(verdict.is_none());
    let [top, panels, status, diag_area, hints_area, verdict_area] = Layout::vertical([
        Constraint::Length(2),
        Constraint::Fill(1),
        Constraint::Length(1),
        Constraint::Length(u16::from(diag)),
        Constraint::Length(hints_h),
        Constraint::Length(verdict_h),
    ])
    .areas(area);

    let q = crate::text::render(prompt.question.get(&app.lang));
    frame.render_widget(
        Paragraph::new(vec![
            Line::styled(q, t.strong()),
            Line::from(vec![
                Span::styled(format!("{}: ", app.tr(Msg::YourPrediction)), t.dim()),
                Span::styled(prediction_text(app, prompt, prediction), t.heading()),
            ]),
        ]),
        top,
    );

    for (panel, rect) in panel_areas(panels, &run.scene().show) {
        match panel {
            Panel::Omega => plots::omega(frame, rect, run, format!(" {} ", app.tr(Msg::Omega)), t),
            Panel::Body => plots::body(frame, rect, run, format!(" {} ", app.tr(Msg::Body)), t),
            Panel::Polhode => {
                plots::polhode(frame, rect, run, format!(" {} ", app.tr(Msg::Polhode)), t)
            }
            Panel::Diagnostics => {}
        }
    }

    let mut s = vec![
        Span::styled(
            format!(
                " t = {:.2} / {} {}",
                run.t(),
                Num(run.scene().duration),
                run.scene().time_unit
            ),
            t.strong(),
        ),
        Span::styled(
            format!(" · {} ×{}", app.tr(Msg::Speed), fmt_speed(run.speed)),
            t.dim(),
        ),
        Span::styled(format!(" · {}", run.method().label()), t.dim()),
    ];
    if run.paused {
        s.push(Span::styled(
            format!(" · {}", app.tr(Msg::Paused)),
            t.warn(),
        ));
    }
    if let Some(e) = run.error() {
        s.push(Span::styled(format!(" · {e}"), t.bad()));
    }
    frame.render_widget(Paragraph::new(Line::from(s)), status);

    if let Some(d) = run.diagnostics() {
        let err = d.error.map_or("—".to_string(), sci);
        let mut line = format!(
            " {} · ΔE/E {} · Δ|L|²/|L|² {} · {} {}",
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
        frame.render_widget(Paragraph::new(Span::styled(line, t.dim())), diag_area);
    }

    if verdict.is_none() {
        hints(frame, hints_area, app);
    }
    if let Some(v) = verdict {
        draw_verdict(frame, verdict_area, app, prompt, prediction, v);
    }
}

/// The run's keys, one line.
pub(super) fn hints(frame: &mut Frame, hints: Rect, app: &App) {
    let t = &app.theme;
    {
        let key = |k: &'static str, what: Msg| {
            [
                Span::styled(k, t.key()),
                Span::styled(format!(" {}  ", app.tr(what)), t.dim()),
            ]
        };
        let mut spans = vec![Span::raw(" ")];
        spans.extend(key("Space", Msg::Pause));
        spans.extend(key("+ -", Msg::Speed));
        spans.extend(key("r", Msg::Restart));
        spans.extend(key("m", Msg::Method));
        spans.extend(key("[ ]", Msg::Step));
        frame.render_widget(Paragraph::new(Line::from(spans)), hints);
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

pub(super) fn fmt_speed(speed: f64) -> String {
    if speed >= 1.0 {
        format!("{speed:.0}")
    } else {
        format!("1/{:.0}", 1.0 / speed)
    }
}

pub(super) fn draw_verdict(
    frame: &mut Frame,
    area: Rect,
    app: &App,
    prompt: &Prompt,
    prediction: Prediction,
    v: &Verdict,
) {
    let t = &app.theme;
    let (headline, style) = if v.correct {
        (app.tr(Msg::Right), t.good())
    } else {
        (app.tr(Msg::Wrong), t.bad())
    };
    let mut lines = vec![Line::from(vec![
        Span::styled(format!(" {}: ", app.tr(Msg::Verdict)), t.heading()),
        Span::styled(headline, style),
        Span::styled(
            format!(
                "  {}: {}",
                app.tr(Msg::YourPrediction),
                prediction_text(app, prompt, prediction)
            ),
            t.text(),
        ),
    ])];
    let unit = match &prompt.answer {
        Answer::Number { unit, .. } => format!(" {unit}"),
        Answer::Choice { .. } => String::new(),
    };
    let measured: Vec<String> = v
        .readings
        .iter()
        .map(|r| {
            let formula = match (r.formula_name(), r.formula) {
                (Some(name), Some(x)) if r.measure != Measure::Flips => {
                    format!(" ({name} = {})", fmt_value(x))
                }
                _ => String::new(),
            };
            format!(
                "{} = {}{unit}{formula}",
                crate::tui::i18n::measure_label(r.measure, &app.lang),
                fmt_value(r.value)
            )
        })
        .collect();
    let measured = if measured.is_empty() {
        vec!["—".to_string()]
    } else {
        measured
    };
    lines.push(Line::from(vec![
        Span::styled(format!(" {}: ", app.tr(Msg::Measured)), t.dim()),
        Span::raw(measured.join(", ")),
    ]));
    match &prompt.answer {
        Answer::Number {
            expected,
            formula,
            unit,
            ..
        } => {
            let f = formula
                .as_ref()
                .map(|f| format!("{} = ", crate::text::render(f.get(&app.lang))))
                .unwrap_or_default();
            lines.push(Line::from(vec![
                Span::styled(format!(" {}: ", app.tr(Msg::Formula)), t.dim()),
                Span::raw(format!("{f}{} {unit}", fmt_value(*expected))),
            ]));
        }
        Answer::Choice { choices, .. } => {
            if let Some(c) = v.right_choice.and_then(|i| choices.get(i)) {
                lines.push(Line::from(vec![
                    Span::styled(format!(" {}: ", app.tr(Msg::RightAnswer)), t.dim()),
                    Span::raw(crate::text::render(c.label.get(&app.lang))),
                ]));
            }
        }
    }
    if prompt.explain.is_some() {
        lines.push(Line::from(vec![
            Span::styled(" e ", t.key()),
            Span::styled(app.tr(Msg::Explanation), t.dim()),
            Span::styled("   r ", t.key()),
            Span::styled(app.tr(Msg::Restart), t.dim()),
        ]));
    }
    frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: false }), area);
}
