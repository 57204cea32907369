//! Drawing the review screen: the progress line, the card sized to its
//! text, the rating buttons with their intervals, the session summary.

use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Margin, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Clear, Paragraph};

use crate::deck::CardKind;
use crate::sched::typed;
use crate::sched::{Direction, Rating};
use crate::tui::app::App;
use crate::tui::i18n::Msg;
use crate::tui::i18n::study;
use crate::tui::wrap::{Run, columns, ellipsize, pack, wrap, wrap_plain};

use super::{Phase, ReviewState};

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

/// The widest a card runs, text columns: long lines are hard to read on a
/// wide terminal.
pub const MEASURE: u16 = 80;

/// The card's outer area in the screen's body below the progress line:
/// centred, at most [`MEASURE`] columns of text wide.
pub fn card_width(rest: Rect) -> Rect {
    let w = rest.width.min(MEASURE + 4);
    Rect {
        x: rest.x + (rest.width - w) / 2,
        width: w,
        ..rest
    }
}

/// The card's lines at a text width.
pub fn card_lines(app: &App, state: &ReviewState, width: usize) -> Vec<Line<'static>> {
    let t = &app.theme;
    let lang = app.lang.as_str();
    let Some(deck) = app.decks.get(state.deck) else {
        return Vec::new();
    };
    if let (Some(walk), Some(d)) = (&state.walk, state.derivation(deck)) {
        let input = match &state.phase {
            Phase::Front { input } => input.as_str(),
            _ => "",
        };
        return walk.lines(app, d, input, width);
    }
    let para = |text: &str, style| {
        wrap(
            &crate::tui::wrap::math_runs(text, style),
            width,
            Run::new("", style),
            Run::new("", style),
        )
    };
    // A cloze text: the part asked about stands out, the rest is plain.
    let cloze = |segs: Vec<crate::deck::cloze::Segment>, plain, asked| {
        let r: Vec<Run> = segs
            .into_iter()
            .flat_map(|s| {
                let style = if s.asked { asked } else { plain };
                crate::tui::wrap::math_runs(&s.text, style)
            })
            .collect();
        wrap(&r, width, Run::new("", plain), Run::new("", plain))
    };
    if let Some(i) = state.prompt(deck) {
        // A prompt due as a review item: what it is, and how it is
        // answered (on its own screen, with new numbers when it varies).
        let p = &deck.prompts[i];
        let mut lines = wrap(
            &[Run::new(app.tr(Msg::PredictItem).to_string(), t.heading())],
            width,
            Run::new("", t.text()),
            Run::new("", t.text()),
        );
        lines.push(Line::default());
        // The numbers are drawn when it opens: shown as "…" here.
        lines.extend(para(&p.question_listed(lang), t.strong()));
        lines.push(Line::default());
        lines.extend(wrap(
            &[Run::new(app.tr(Msg::PredictItemHint).to_string(), t.dim())],
            width,
            Run::new("", t.dim()),
            Run::new("", t.dim()),
        ));
        return lines;
    }
    let Some((card, direction)) = state.card(deck) else {
        return Vec::new();
    };
    let (mut lines, answer) = match direction {
        Direction::Predict => return Vec::new(),
        Direction::Forward => (para(card.front.get(lang), t.strong()), &card.back),
        Direction::Backward => (para(card.back.get(lang), t.strong()), &card.front),
        // Drawn by the walk, above.
        Direction::Derive => return Vec::new(),
        Direction::Cloze(n) => {
            let text = card.front.get(lang);
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
            if card.kind.is_typed() {
                lines.push(Line::styled(app.tr(Msg::TypeAnswer), t.dim()));
                lines.extend(wrap(
                    &[Run::new(
                        format!("{}▏", crate::text::safe::one_line(input)),
                        t.strong(),
                    )],
                    width,
                    Run::new("> ", t.key()),
                    Run::new("  ", t.key()),
                ));
            }
        }
        Phase::Back { typed, .. } => {
            lines.push(Line::styled("─".repeat(width.min(40)), t.dim()));
            // A cloze card's back is optional notes under the revealed text.
            if !answer.get(lang).is_empty() {
                lines.extend(para(answer.get(lang), t.text()));
            }
            if let Some(ta) = typed {
                lines.push(Line::default());
                lines.extend(typed_lines(app, ta, width));
            }
            if let Some(p) = card.prompt.as_ref().and_then(|id| deck.prompt(id)) {
                lines.push(Line::default());
                let q = crate::text::render(&p.question_listed(lang));
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
    lines
}

/// What was typed, above what was expected, aligned so that the two can
/// be compared letter by letter.
fn typed_lines(app: &App, ta: &super::TypedAnswer, width: usize) -> Vec<Line<'static>> {
    let t = &app.theme;
    let lang = app.lang.as_str();
    let (mark, style) = match ta.check.verdict {
        typed::Verdict::Exact => ("✓", t.good()),
        typed::Verdict::Close => ("≈", t.warn()),
        typed::Verdict::Wrong => ("✗", t.bad()),
    };
    let typed_label = study::YOU_TYPED.get(lang);
    let expected_label = study::EXPECTED.get(lang);
    let label_w = columns(typed_label).max(columns(expected_label));
    let pad = |label: &str| format!("{label}:{} ", " ".repeat(label_w - columns(label)));
    let mut out = wrap(
        &[Run::new(
            crate::text::safe::one_line(&ta.text).into_owned(),
            t.strong(),
        )],
        width,
        Run::new(format!("{mark} {}", pad(typed_label)), style),
        Run::new(" ".repeat(label_w + 4), style),
    );
    if let Some(n) = &ta.check.nearest
        && ta.check.verdict != typed::Verdict::Exact
    {
        out.extend(wrap(
            &[Run::new(n.clone(), t.good())],
            width,
            Run::new(format!("  {}", pad(expected_label)), t.dim()),
            Run::new(" ".repeat(label_w + 4), t.dim()),
        ));
    }
    // A formula's slip, named.
    if let Some(said) = ta
        .formula
        .as_ref()
        .and_then(|v| crate::tui::i18n::formula_words::feedback(v, lang))
    {
        out.extend(wrap(
            &[Run::new(said, t.bad())],
            width,
            Run::new(" ".repeat(label_w + 4), t.dim()),
            Run::new(" ".repeat(label_w + 4), t.dim()),
        ));
    }
    out
}

/// Where the card, its buttons and the hints go below the progress line.
pub struct CardLayout {
    pub lines: Vec<Line<'static>>,
    pub buttons: Vec<Line<'static>>,
    pub card_area: Rect,
    pub button_area: Rect,
    pub hints: Rect,
    /// Blank lines above and below the text inside the border.
    pub margin: u16,
    /// Lines of text the card shows at once.
    pub room: usize,
}

/// The card is as tall as its text (with a blank line above and below when
/// there is room), the buttons right under it; a card taller than the
/// screen scrolls (j/k), saying so on its border.
pub fn layout(app: &App, state: &ReviewState, kind: CardKind, rest: Rect) -> CardLayout {
    let outer = card_width(rest);
    // Borders and a column of margin on each side.
    let width = outer.width.saturating_sub(4) as usize;
    let lines = card_lines(app, state, width);
    let buttons = button_lines(app, state, kind, outer.width);
    let below = (buttons.len() as u16).max(1) + 1;
    let margin = if rest.height < 16 { 0 } else { 1 };
    let card_h = (lines.len() as u16 + 2 + 2 * margin).min(rest.height.saturating_sub(below));
    let [card_area, button_area, hints] = Layout::vertical([
        Constraint::Length(card_h),
        Constraint::Length(below - 1),
        Constraint::Length(1),
    ])
    .areas(rest);
    // The buttons and hints line up under the card.
    let under = |r: Rect| Rect {
        x: outer.x,
        width: outer.width,
        ..r
    };
    let (card_area, button_area, hints) = (under(card_area), under(button_area), under(hints));
    let room = card_h.saturating_sub(2 + 2 * margin).max(1) as usize;
    CardLayout {
        lines,
        buttons,
        card_area,
        button_area,
        hints,
        margin,
        room,
    }
}

pub fn draw(frame: &mut Frame, area: Rect, app: &App, state: &ReviewState) {
    let t = &app.theme;
    let lang = app.lang.as_str();
    let Some(deck) = app.decks.get(state.deck) else {
        return;
    };
    let [progress, rest] =
        Layout::vertical([Constraint::Length(1), Constraint::Fill(1)]).areas(area);
    frame.render_widget(
        Paragraph::new(Span::styled(
            ellipsize(&format!(" {}", state.progress(app)), progress.width.into()),
            t.heading(),
        )),
        progress,
    );

    if state.phase == Phase::Done {
        draw_summary(frame, rest, app, state);
        return;
    }
    // What the item is: a card, a derivation, or a prompt (drawn as a
    // basic card's front: its lines say what it is).
    let (kind, explain) = match (state.card(deck), state.derivation(deck)) {
        (Some((card, _)), _) => (card.kind, card.explain.is_some()),
        (None, Some(d)) => (CardKind::Basic, d.explain.is_some()),
        (None, None) if state.prompt(deck).is_some() => (CardKind::Basic, false),
        (None, None) => return,
    };
    let CardLayout {
        lines,
        buttons,
        card_area,
        button_area,
        hints,
        margin,
        room,
    } = layout(app, state, kind, rest);
    let max_scroll = lines.len().saturating_sub(room);
    let scroll = state.scroll.min(max_scroll);
    let typing = state.typed && matches!(state.phase, Phase::Front { .. });
    let mut block = Block::default()
        .borders(Borders::ALL)
        .border_style(t.border());
    if scroll > 0 {
        let up = if typing {
            "↑"
        } else {
            study::MORE_ABOVE.get(lang)
        };
        block = block.title_top(Line::styled(format!(" {up} "), t.key()).right_aligned());
    }
    if scroll < max_scroll {
        let down = if typing {
            study::MORE_BELOW_TYPING.get(lang)
        } else {
            study::MORE_BELOW.get(lang)
        };
        block = block.title_bottom(Line::styled(format!(" {down} "), t.key()).right_aligned());
    }
    let inner = block.inner(card_area).inner(Margin::new(1, margin));
    frame.render_widget(block, card_area);
    let shown: Vec<Line> = lines.into_iter().skip(scroll).take(room).collect();
    frame.render_widget(Paragraph::new(shown), inner);
    frame.render_widget(Paragraph::new(buttons), button_area);

    // Keys that type letters while a typed card's answer is edited are
    // not offered there.
    let mut h = vec![Span::raw(" ")];
    if !typing {
        if explain {
            h.push(Span::styled("e ", t.key()));
            h.push(Span::styled(
                format!("{}  ", app.tr(Msg::Explanation)),
                t.dim(),
            ));
        }
        h.push(Span::styled("u ", t.key()));
        h.push(Span::styled(app.tr(Msg::Undo), t.dim()));
    }
    frame.render_widget(Paragraph::new(Line::from(h)), hints);
}

/// The rating buttons with the interval each would give (or the key that
/// shows the answer), wrapped onto a second line when the screen is narrow.
fn button_lines(app: &App, state: &ReviewState, kind: CardKind, width: u16) -> Vec<Line<'static>> {
    let t = &app.theme;
    let Phase::Back { typed, previews } = &state.phase else {
        let next = app
            .decks
            .get(state.deck)
            .and_then(|deck| Some(state.walk.as_ref()?.next(state.derivation(deck)?)));
        let (key, what) = if let Some(next) = next {
            use super::Next;
            use crate::tui::i18n::derive as words;
            match next {
                Next::Step | Next::Done => (" Space ", words::NEXT_STEP.get(&app.lang)),
                Next::Reveal => (" Space ", words::REVEAL.get(&app.lang)),
                Next::Choose => (" 1-9 Enter ", words::CHECK.get(&app.lang)),
                Next::Type => (" Enter ", words::CHECK.get(&app.lang)),
            }
        } else if kind.is_typed() {
            (" Enter ", study::CHECK.get(&app.lang))
        } else {
            (" Space ", app.tr(Msg::ShowAnswer))
        };
        return vec![Line::from(vec![
            Span::styled(key, t.key()),
            Span::styled(what, t.dim()),
        ])];
    };
    let suggested = match &state.walk {
        // A derivation with faded steps suggests from their verdicts.
        Some(w) if w.faded_count() > 0 => Some(w.suggested()),
        Some(_) => None,
        None => typed.as_ref().map(|t| t.check.suggested),
    };
    let mut groups: Vec<Vec<Span<'static>>> = Vec::new();
    for (i, r) in Rating::ALL.into_iter().enumerate() {
        let interval = previews
            .as_ref()
            .map(|p| format!(" {}", p[i].label))
            .unwrap_or_default();
        let mut style = t.rating(i);
        let mut label = format!("{}{interval}", rating_label(app, r));
        if suggested == Some(r) {
            style = style.patch(t.selected());
            // Marked by more than the colour (NO_COLOR).
            label = format!("{label} ◂");
        }
        groups.push(vec![
            Span::styled(format!("{} ", i + 1), t.key()),
            Span::styled(label, style),
        ]);
    }
    if let Some(r) = suggested {
        groups.push(vec![Span::styled(
            format!("({}: {})", app.tr(Msg::Suggested), rating_label(app, r)),
            t.dim(),
        )]);
    }
    pack(groups, usize::from(width), 3)
}

/// The end of a session: what was done, and what comes next.
fn draw_summary(frame: &mut Frame, area: Rect, app: &App, state: &ReviewState) {
    let inner = summary_area(area);
    let lines = summary_lines(app, state, usize::from(inner.width.max(1)));
    let room = inner.height as usize;
    let max = lines.len().saturating_sub(room);
    let scroll = state.scroll.min(max);
    let shown: Vec<Line> = lines.into_iter().skip(scroll).take(room).collect();
    frame.render_widget(Paragraph::new(shown), inner);
    if scroll < max {
        let more = study::MORE_BELOW.get(&app.lang);
        let w = columns(more) as u16;
        let at = Rect::new(
            inner.right().saturating_sub(w),
            inner.bottom().saturating_sub(1),
            w.min(inner.width),
            1,
        );
        frame.render_widget(Clear, at);
        frame.render_widget(Paragraph::new(Span::styled(more, app.theme.key())), at);
    }
}

/// Where the summary's text goes, below the progress line.
pub fn summary_area(rest: Rect) -> Rect {
    rest.inner(Margin::new(2, 1))
}

/// The summary's lines at a width.
pub fn summary_lines(app: &App, state: &ReviewState, width: usize) -> Vec<Line<'static>> {
    let t = &app.theme;
    let lang = app.lang.as_str();
    let s = state.session;
    let mut lines = Vec::new();
    if s.reviewed == 0 {
        lines.extend(wrap_plain(app.tr(Msg::NothingDue), t.heading(), width));
    } else {
        lines.push(Line::styled(app.tr(Msg::SessionDone), t.heading()));
        lines.push(Line::default());
        let rate = 100.0 * f64::from(s.again) / f64::from(s.reviewed);
        lines.extend(wrap_plain(
            &format!(
                "{} {} · {} {} · {} {:.0}%",
                s.reviewed,
                app.tr(Msg::Reviewed),
                app.tr(Msg::Time),
                fmt_duration(app.services.stopwatch.elapsed_ms(state.started)),
                app.tr(Msg::AgainRate),
                rate
            ),
            t.text(),
            width,
        ));
    }
    lines.push(Line::default());
    let next = state.what_next(app);
    if let Some(wait) = next.learning_in {
        lines.extend(wrap_plain(
            &format!(
                "{} {} → {}",
                app.tr(Msg::Learning),
                app.tr(Msg::Due),
                crate::sched::format_interval(wait)
            ),
            t.text(),
            width,
        ));
    }
    if !state.cram {
        if next.later_today > 0 {
            lines.extend(wrap_plain(
                &format!("{}: {}", study::LATER_TODAY.get(lang), next.later_today),
                t.text(),
                width,
            ));
        }
        lines.extend(wrap_plain(
            &format!("{}: {}", study::DUE_TOMORROW.get(lang), next.due_tomorrow),
            t.text(),
            width,
        ));
        let mut new = format!("{}: {}", study::NEW_LEFT.get(lang), next.new_cards);
        if next.new_cards > 0 && next.new_limit_reached {
            new.push_str(&format!(" · {}", study::NEW_TOMORROW.get(lang)));
        }
        lines.extend(wrap_plain(&new, t.text(), width));
    }
    lines.push(Line::default());
    for (key, what) in [
        ("c", study::CRAM_NOW.get(lang)),
        ("Enter", app.tr(Msg::Back)),
    ] {
        lines.extend(wrap(
            &[Run::new(what, t.dim())],
            width,
            Run::new(format!("{key} "), t.key()),
            Run::new(" ".repeat(columns(key) + 1), t.dim()),
        ));
    }
    lines
}
