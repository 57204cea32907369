//! Drawing the review screen: the progress line, the card sized to its
//! text, the rating buttons with their intervals, the session summary.

use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Margin, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Paragraph};

use crate::deck::CardKind;
use crate::sched::typed;
use crate::sched::{Direction, Rating};
use crate::tui::app::App;
use crate::tui::i18n::Msg;
use crate::tui::wrap::{Run, wrap};

use super::{Phase, ReviewState, Source};

fn rating_label(app: &App, r: Rating) -> &'static str {
    match r {
        Rating::Again => app.tr(Msg::Again),
        Rating::Hard => app.tr(Msg::Hard),
        Rating::Good => app.tr(Msg::Good),
        Rating::Easy => app.tr(Msg::Easy),
    }
}

/// "3m 20s", "45s", "1h 05m".
pub fn fmt_duration(ms: i64) -> String {
    let s = ms.max(0) / 1000;
    match s {
        s if s < 60 => format!("{s}s"),
        s if s < 3600 => format!("{}m {:02}s", s / 60, s % 60),
        s => format!("{}h {:02}m", s / 3600, (s % 3600) / 60),
    }
}

pub fn draw(frame: &mut Frame, area: Rect, app: &App, state: &ReviewState) {
    let t = &app.theme;
    let Some(deck) = app.decks.get(state.deck) else {
        return;
    };
    let [progress, rest] =
        Layout::vertical([Constraint::Length(1), Constraint::Fill(1)]).areas(area);
    frame.render_widget(
        Paragraph::new(Span::styled(
            format!(" {}", state.progress(app)),
            t.heading(),
        )),
        progress,
    );

    if state.phase == Phase::Done {
        draw_summary(frame, rest, app, state);
        return;
    }
    let Some((card, direction)) = state.card(deck) else {
        return;
    };
    // Borders and a column of margin on each side.
    let width = rest.width.saturating_sub(4) as usize;
    let runs = |runs: Vec<Run>, style| wrap(&runs, width, Run::new("", style), Run::new("", style));
    let para = |text: &str, style| runs(vec![Run::new(crate::text::render(text), style)], style);
    // A cloze text: the part asked about stands out, the rest is plain.
    let cloze = |segs: Vec<crate::deck::cloze::Segment>, plain, asked| {
        let r = segs
            .into_iter()
            .map(|s| {
                let style = if s.asked { asked } else { plain };
                Run::new(crate::text::render(&s.text), style)
            })
            .collect();
        runs(r, plain)
    };
    let (mut lines, answer) = match direction {
        Direction::Forward => (para(card.front.get(&app.lang), t.strong()), &card.back),
        Direction::Backward => (para(card.back.get(&app.lang), t.strong()), &card.front),
        Direction::Cloze(n) => {
            let text = card.front.get(&app.lang);
            let shown = if matches!(state.phase, Phase::Back { .. }) {
                crate::deck::cloze::back(text, n)
            } else {
                crate::deck::cloze::front(text, n)
            };
            (cloze(shown, t.strong(), t.highlight()), &card.back)
        }
    };
    lines.push(Line::default());
    match &state.phase {
        Phase::Front { input } => {
            if card.kind == CardKind::Typed {
                lines.push(Line::styled(app.tr(Msg::TypeAnswer), t.dim()));
                lines.push(Line::from(vec![
                    Span::styled("> ", t.key()),
                    Span::styled(format!("{input}▏"), t.strong()),
                ]));
            }
        }
        Phase::Back { typed, .. } => {
            lines.push(Line::styled("─".repeat(width.min(40)), t.dim()));
            // A cloze card's back is optional notes under the revealed text.
            if !answer.get(&app.lang).is_empty() {
                lines.extend(para(answer.get(&app.lang), t.text()));
            }
            if let Some(ta) = typed {
                lines.push(Line::default());
                let (mark, style) = match ta.check.verdict {
                    typed::Verdict::Exact => ("✓", t.good()),
                    typed::Verdict::Close => ("≈", t.warn()),
                    typed::Verdict::Wrong => ("✗", t.bad()),
                };
                lines.push(Line::from(vec![
                    Span::styled(format!("{mark} {}: ", app.tr(Msg::YouTyped)), style),
                    Span::raw(ta.text.clone()),
                ]));
                if let Some(n) = &ta.check.nearest {
                    lines.push(Line::from(vec![
                        Span::styled(format!("  {}: ", app.tr(Msg::Accepted)), t.dim()),
                        Span::raw(n.clone()),
                    ]));
                }
            }
            if let Some(p) = card.prompt.as_ref().and_then(|id| deck.prompt(id)) {
                lines.push(Line::default());
                let q = crate::text::render(p.question.get(&app.lang));
                lines.extend(wrap(
                    &[
                        Run::new(format!("{}: ", app.tr(Msg::TryPrompt)), t.heading()),
                        Run::new(q, t.text()),
                    ],
                    width,
                    Run::new("p ", t.key()),
                    Run::new("  ", t.text()),
                ));
            }
        }
        Phase::Done => {}
    }
    while lines.last().is_some_and(|l| l.spans.is_empty()) {
        lines.pop();
    }
    // The card is as tall as its text (a blank line above and below),
    // with the buttons right under it.
    let card_h = (lines.len() as u16 + 4).min(rest.height.saturating_sub(2));
    let [card_area, buttons, hints] = Layout::vertical([
        Constraint::Length(card_h),
        Constraint::Length(1),
        Constraint::Length(1),
    ])
    .areas(rest);
    let block = Block::default()
        .borders(Borders::ALL)
        .border_style(t.border());
    let inner = block.inner(card_area).inner(Margin::new(1, 1));
    frame.render_widget(block, card_area);
    frame.render_widget(Paragraph::new(lines), inner);

    // Rating buttons with the interval each would give.
    if let Phase::Back { typed, previews } = &state.phase {
        let suggested = typed.as_ref().map(|t| t.check.suggested);
        let mut spans = vec![Span::raw(" ")];
        for (i, r) in Rating::ALL.into_iter().enumerate() {
            let interval = previews
                .as_ref()
                .map(|p| format!(" {}", p[i].label))
                .unwrap_or_default();
            let mut style = t.rating(i);
            if suggested == Some(r) {
                style = style.patch(t.selected());
            }
            spans.push(Span::styled(format!("{} ", i + 1), t.key()));
            spans.push(Span::styled(
                format!("{}{interval}", rating_label(app, r)),
                style,
            ));
            spans.push(Span::raw("   "));
        }
        if let Some(r) = suggested {
            spans.push(Span::styled(
                format!("({}: {})", app.tr(Msg::Suggested), rating_label(app, r)),
                t.dim(),
            ));
        }
        frame.render_widget(Paragraph::new(Line::from(spans)), buttons);
    } else if card.kind != CardKind::Typed {
        frame.render_widget(
            Paragraph::new(Line::from(vec![
                Span::styled(" Space ", t.key()),
                Span::styled(app.tr(Msg::ShowAnswer), t.dim()),
            ])),
            buttons,
        );
    } else {
        frame.render_widget(
            Paragraph::new(Line::from(vec![
                Span::styled(" Enter ", t.key()),
                Span::styled(app.tr(Msg::ShowAnswer), t.dim()),
            ])),
            buttons,
        );
    }
    let mut h = vec![Span::raw(" ")];
    if card.explain.is_some() {
        h.push(Span::styled("e ", t.key()));
        h.push(Span::styled(
            format!("{}  ", app.tr(Msg::Explanation)),
            t.dim(),
        ));
    }
    h.push(Span::styled("u ", t.key()));
    h.push(Span::styled(app.tr(Msg::Undo), t.dim()));
    frame.render_widget(Paragraph::new(Line::from(h)), hints);
}

fn draw_summary(frame: &mut Frame, area: Rect, app: &App, state: &ReviewState) {
    let t = &app.theme;
    let s = state.session;
    let mut lines = Vec::new();
    if s.reviewed == 0 {
        lines.push(Line::styled(app.tr(Msg::NothingDue), t.heading()));
    } else {
        lines.push(Line::styled(app.tr(Msg::SessionDone), t.heading()));
        lines.push(Line::default());
        let rate = 100.0 * f64::from(s.again) / f64::from(s.reviewed);
        lines.push(Line::from(format!(
            "{} {} · {} {} · {} {:.0}%",
            s.reviewed,
            app.tr(Msg::Reviewed),
            app.tr(Msg::Time),
            fmt_duration(app.services.stopwatch.elapsed_ms(state.started)),
            app.tr(Msg::AgainRate),
            rate
        )));
    }
    if let Source::Daily(q) = &state.source
        && let Some(due) = q.next_learning_due()
    {
        let wait = due - app.services.now();
        lines.push(Line::default());
        lines.push(Line::styled(
            format!(
                "{} {} → {}",
                app.tr(Msg::Learning),
                app.tr(Msg::Due),
                crate::sched::format_interval(wait)
            ),
            t.dim(),
        ));
    }
    lines.push(Line::default());
    lines.push(Line::from(vec![
        Span::styled("Enter ", t.key()),
        Span::styled(app.tr(Msg::Back), t.dim()),
    ]));
    let inner = area.inner(Margin::new(2, 1));
    frame.render_widget(Paragraph::new(lines), inner);
}
