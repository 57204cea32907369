//! Predict, then check on a system scene: the same commitment and controls
//! as a rigid body's, with the system's panels (plot, phase, sketch,
//! diagnostics) and a verdict from the measures of its variables and
//! observables.

use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;

use crate::deck::{Answer, Measure, Prompt, SystemPanel, SystemScene};
use crate::sim::scene::system::{StartError, measure_system};
use crate::sim::solvers::ode::{OdeKind, OdeMethod};
use crate::text::num::Num;
use crate::tui::action::Action;
use crate::tui::app::App;
use crate::tui::i18n::Msg;
use crate::tui::live_system::LiveSystem;
use crate::tui::system_plots;

use super::{Judging, Measuring, Nav, Phase, PredictState, Prediction, Verdict};
use crate::sim::scene::measure::{Measurements, Reading};

/// Rows the question may take above a running scene.
const QUESTION_ROWS: usize = 3;

/// The measures a prompt's verdict needs.
pub fn measures(prompt: &Prompt) -> Vec<Measure> {
    let mut out: Vec<Measure> = match &prompt.answer {
        Answer::Choice { choices, .. } => choices.iter().map(|c| c.when.measure).collect(),
        Answer::Number { measure, .. } => vec![*measure],
    };
    out.sort();
    out.dedup();
    out
}

/// The method a system scene plays with first: auto at its default
/// tolerance.
pub fn default_method(scene: &SystemScene) -> OdeMethod {
    OdeMethod::default_for(OdeKind::Auto, scene.duration)
}

pub fn commit(
    app: &mut App,
    state: &mut PredictState,
    prediction: Prediction,
    scene: &SystemScene,
) -> Nav {
    let Some(prompt) = super::prompt(app, state).cloned() else {
        return Nav::Pop;
    };
    // As for a rigid body: the run is built, the commitment kept, then
    // the run starts.
    match LiveSystem::new(scene, default_method(scene), &measures(&prompt)) {
        Ok(run) => {
            if let Some(committed) = super::keep_commitment(app, state, &prompt, prediction) {
                state.phase = Phase::System {
                    prediction,
                    committed,
                    run: Box::new(run),
                    verdict: None,
                    judging: Judging::Idle,
                };
            }
        }
        Err(e) => app.error(format!("{}: {e}", scene.id)),
    }
    Nav::Stay
}

pub fn apply(app: &mut App, state: &mut PredictState, action: Action, prompt: &Prompt) -> Nav {
    let deck = state.deck;
    let Phase::System {
        run,
        prediction,
        committed,
        verdict,
        judging,
    } = &mut state.phase
    else {
        return Nav::Stay;
    };
    if action == Action::Explain {
        if verdict.is_some()
            && let Some(id) = &prompt.explain
        {
            return super::super::reader::open_at(app, deck, id);
        }
        return Nav::Stay;
    }
    let replace = |run: &mut Box<LiveSystem>,
                   next: Result<LiveSystem, StartError>,
                   app: &mut App| match next {
        Ok(r) => **run = r,
        Err(e) => app.error(e.to_string()),
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
            let next = run.restart_with(run.next_method());
            replace(run, next, app);
        }
        Action::SmallerStep | Action::LargerStep => {
            let m = run.method().finer(action == Action::SmallerStep);
            let next = run.restart_with(m);
            replace(run, next, app);
        }
        _ => {}
    }
    if verdict.is_none() && run.finished() {
        judge(
            app,
            prompt,
            run,
            (*prediction, *committed),
            verdict,
            judging,
        );
    }
    Nav::Stay
}

/// The verdict from the run just watched when it ran with the default
/// method to the end; else from a default run of the scene, made off the UI
/// thread: the physics' answer, whatever method the learner tried. When the
/// default run itself stops early (the scene leaves its domain), there is
/// no verdict and the attempt stays without one: the status line says why.
fn judge(
    app: &mut App,
    prompt: &Prompt,
    run: &LiveSystem,
    attempt: (Prediction, super::Committed),
    verdict: &mut Option<Verdict>,
    judging: &mut Judging,
) {
    let ms = measures(prompt);
    let scene = run.scene();
    if run.method() == default_method(scene) {
        if run.error().is_some() {
            *judging = Judging::Failed;
        } else {
            let measured = run.run().measurements(&ms);
            *verdict = Some(super::record(app, prompt, &measured, attempt));
        }
        return;
    }
    super::settle(app, prompt, attempt, verdict, judging, || {
        let scene = scene.clone();
        Measuring::start(move || {
            let values =
                measure_system(&scene, default_method(&scene), &ms).map_err(|e| e.to_string())?;
            // The reference run reaches the scene's end (else it is an
            // error): its evidence covers the whole duration.
            let elapsed = scene.duration;
            Ok(Measurements::from_readings(
                ms.iter()
                    .zip(values)
                    .filter_map(|(m, v)| {
                        v.ok().map(|value| Reading {
                            measure: *m,
                            value,
                            formula: None,
                        })
                    })
                    .collect(),
            )
            .over(elapsed))
        })
    });
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
    prompt: &Prompt,
    prediction: Prediction,
    run: &LiveSystem,
    verdict: Option<&Verdict>,
) {
    let t = &app.theme;
    let diag = run.scene().shows(SystemPanel::Diagnostics);
    // The same banner, prediction and evidence as a rigid body's verdict.
    let verdict_lines = verdict
        .map(|v| {
            let unit = &run.scene().time_unit;
            let width = area.width as usize;
            let mut lines = super::verdict::lines(app, prompt, unit, prediction, v, width);
            // Another method (or step) than the reference: the verdict is
            // the reference run's; say what the run on screen showed.
            let reference = default_method(run.scene());
            if run.method() != reference {
                let shown = super::verdict::on_screen(run.error(), run.finished(), || {
                    crate::predict::verdict(
                        prompt,
                        &run.run().measurements(&measures(prompt)),
                        prediction,
                    )
                });
                lines.extend(super::verdict::run_on_screen(
                    app,
                    prompt,
                    unit,
                    (v, &reference.label()),
                    (shown, &run.method().label()),
                    width,
                ));
            }
            lines
        })
        .unwrap_or_default();
    let verdict_h = (verdict_lines.len() as u16).min(area.height.saturating_sub(6));
    let hints_h = u16::from(verdict.is_none());
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
        Constraint::Length(u16::from(diag)),
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
    let sys = run.run();
    for (panel, rect) in panel_areas(panels, &run.scene().show) {
        match panel {
            SystemPanel::Plot => system_plots::plot(frame, rect, sys, &app.lang, t),
            SystemPanel::Phase => system_plots::phase(frame, rect, sys, &app.lang, t),
            SystemPanel::Sketch => system_plots::sketch(frame, rect, sys, &app.lang, t),
            SystemPanel::Diagnostics => {}
        }
    }
    let mut s = vec![Span::styled(
        format!(
            " t = {:.2} / {} {}",
            run.t(),
            Num(run.scene().duration),
            run.scene().time_unit
        ),
        t.text(),
    )];
    s.push(Span::styled(
        format!(" · {} ×{}", app.tr(Msg::Speed), super::fmt_speed(run.speed)),
        t.dim(),
    ));
    s.push(Span::styled(
        format!(" · {}", run.method().label()),
        t.dim(),
    ));
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
    if diag {
        frame.render_widget(
            Paragraph::new(Span::styled(
                system_plots::diagnostics_line(sys, &app.lang),
                t.dim(),
            )),
            diag_area,
        );
    }
    if verdict.is_none() {
        run_hints(frame, hints, app);
    }
    if !verdict_lines.is_empty() {
        frame.render_widget(Paragraph::new(verdict_lines), verdict_area);
    }
}

/// The run's keys, one line.
fn run_hints(frame: &mut Frame, hints: Rect, app: &App) {
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
