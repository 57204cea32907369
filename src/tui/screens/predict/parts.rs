//! What the predict screen draws alike for a rigid body and a system: the
//! rows of a playing scene (who gives way when rows are short), the
//! question above the run, the run's status line, its keys, the solver's
//! diagnostics folded to the width. Below both panels' drawings
//! (`draw.rs`, `system.rs`).

use std::cell::Cell;

use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;

use crate::deck::Prompt;
use crate::text::num::Num;
use crate::tui::app::App;
use crate::tui::i18n::{Msg, sim_words as w};
use crate::tui::live::Live;
use crate::tui::wrap::{Run, wrap};

use super::Prediction;

/// The run's status line, a rigid body's and a system's alike: scene time,
/// the flips so far (a rigid body), why the run stopped, the speed, the
/// method, paused; cut with "…" to `width`.
pub(super) fn status_line(
    app: &App,
    live: &Live,
    flips: Option<usize>,
    width: u16,
) -> Paragraph<'static> {
    let t = &app.theme;
    let (duration, unit) = live.timing();
    let mut s = vec![Span::styled(
        format!(" t = {:.2} / {} {unit}", live.t(), Num(duration)),
        t.strong(),
    )];
    if let Some(flips) = flips {
        s.push(Span::styled(
            format!(" · {}: {flips}", w::FLIPS.get(&app.lang)),
            t.strong(),
        ));
    }
    // Why the run stopped comes before what the learner can change: a
    // narrow line keeps it.
    if let Some(e) = live.error() {
        s.push(Span::styled(format!(" · {e}"), t.bad()));
    }
    // What the learner can change, kept whole or left out (most wanted
    // first: paused, the speed, the method), never cut mid-word.
    let mut optional = vec![
        (
            1,
            Span::styled(format!(" · {}", super::speed_text(app, live)), t.dim()),
        ),
        (
            2,
            Span::styled(format!(" · {}", live.method_label()), t.dim()),
        ),
    ];
    if live.paused {
        optional.push((
            0,
            Span::styled(format!(" · {}", app.tr(Msg::Paused)), t.warn()),
        ));
    }
    let mut used: usize = s.iter().map(|x| x.width()).sum();
    let mut rank: Vec<usize> = (0..optional.len()).collect();
    rank.sort_by_key(|&i| optional[i].0);
    let mut keep = vec![false; optional.len()];
    for i in rank {
        let w = optional[i].1.width();
        if used + w <= usize::from(width) {
            used += w;
            keep[i] = true;
        }
    }
    s.extend(
        optional
            .into_iter()
            .zip(keep)
            .filter(|(_, k)| *k)
            .map(|((_, span), _)| span),
    );
    Paragraph::new(fit_spans(s, usize::from(width)))
}

/// The diagnostics lines (see [`fold_parts`]), dim.
pub(super) fn diagnostics(app: &App, lines: Vec<String>) -> Paragraph<'static> {
    let t = &app.theme;
    Paragraph::new(
        lines
            .into_iter()
            .map(|l| Line::styled(l, t.dim()))
            .collect::<Vec<_>>(),
    )
}

/// The run's keys, one line; they stay listed after the verdict, with what
/// it adds (the next prompt, the explanation). A rigid body's and a
/// system's alike.
/// The hint for `w` on the keys' row.
const WHOLE_QUESTION: crate::tui::i18n::Words = crate::tui::i18n::Words("question", "sawaal");

pub(super) fn hints_line(
    app: &App,
    prompt: &Prompt,
    (judged, question_cut, explorable): (bool, bool, bool),
    width: u16,
) -> Paragraph<'static> {
    let mut keys: Vec<(&str, &str)> = Vec::new();
    // A question the screen cuts (or one shown first) says how to read it
    // whole before anything else.
    if question_cut {
        keys.push(("w", WHOLE_QUESTION.get(&app.lang)));
    }
    if judged {
        keys.push(("n", w::NEXT.get(&app.lang)));
        if explorable {
            keys.push(("x", EXPLORE.get(&app.lang)));
        }
        if prompt.explain.is_some() {
            keys.push(("e", app.tr(Msg::Explanation)));
        }
    }
    keys.extend([
        ("Space", app.tr(Msg::Pause)),
        ("+ -", app.tr(Msg::Speed)),
        ("r", app.tr(Msg::Restart)),
        ("m", app.tr(Msg::Method)),
        ("[ ]", app.tr(Msg::Step)),
    ]);
    key_row(app, &keys, width)
}

/// After the verdict, on a scene with knobs.
const EXPLORE: crate::tui::i18n::Words = crate::tui::i18n::Words("explore", "explore karo");

/// A row of keys and what they do, `width` wide: whole entries only; what
/// does not fit is left to the help (`?`), never cut mid-word.
pub(super) fn key_row(app: &App, keys: &[(&str, &str)], width: u16) -> Paragraph<'static> {
    let t = &app.theme;
    let mut spans = vec![Span::raw(" ")];
    let mut used = 1;
    for (k, what) in keys {
        let entry = format!(" {what}");
        let w = unicode_width::UnicodeWidthStr::width(*k)
            + unicode_width::UnicodeWidthStr::width(entry.as_str());
        let gap = if used > 1 { 2 } else { 0 };
        if used + gap + w > usize::from(width) {
            break;
        }
        if gap > 0 {
            spans.push(Span::raw("  "));
        }
        spans.push(Span::styled(k.to_string(), t.key()));
        spans.push(Span::styled(entry, t.dim()));
        used += gap + w;
    }
    Paragraph::new(Line::from(spans))
}

/// A diagnostics text ("a · b · c") folded to `width` at its separators,
/// never inside a part, at most three lines (the last ending in "…" when
/// parts were left out); a part wider than a line is cut with "…". Each
/// line starts with a space.
pub(super) fn fold_parts(text: &str, width: usize) -> Vec<String> {
    const MAX_LINES: usize = 3;
    let room = width.saturating_sub(1).max(1);
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for part in text.split(" · ") {
        let part = crate::tui::wrap::ellipsize(part, room);
        let joined = if line.is_empty() {
            part.clone()
        } else {
            format!("{line} · {part}")
        };
        if unicode_width::UnicodeWidthStr::width(joined.as_str()) <= room {
            line = joined;
        } else {
            lines.push(std::mem::replace(&mut line, part));
        }
    }
    if !line.is_empty() {
        lines.push(line);
    }
    if lines.len() > MAX_LINES {
        lines.truncate(MAX_LINES);
        if let Some(last) = lines.pop() {
            lines.push(crate::tui::wrap::ellipsize(&format!("{last} …"), room));
        }
    }
    lines.into_iter().map(|l| format!(" {l}")).collect()
}

/// Spans cut to `width` columns, ending in "…" where cut.
pub(super) fn fit_spans(spans: Vec<Span<'static>>, width: usize) -> Line<'static> {
    use unicode_width::UnicodeWidthChar;
    let total: usize = spans.iter().map(|s| s.width()).sum();
    if total <= width {
        return Line::from(spans);
    }
    let mut out = Vec::new();
    let mut used = 0;
    for s in spans {
        let mut text = String::new();
        for c in s.content.chars() {
            let w = c.width().unwrap_or(0);
            if used + w + 1 > width {
                break;
            }
            used += w;
            text.push(c);
        }
        let full = text.len() == s.content.len();
        out.push(Span::styled(text, s.style));
        if !full {
            break;
        }
    }
    if width > 0 {
        out.push(Span::raw("…"));
    }
    Line::from(out)
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

/// The rows of a playing scene, a rigid body's and a system's alike:
/// question, prediction (before the verdict), panels, status, diagnostics,
/// hints, verdict. Who gives way when rows are short: the panels first
/// (they take what the question leaves, and are dropped below 3 rows),
/// then the question's later lines; the verdict and one question line
/// stay. With `question_first` (the `w` key) the question keeps its rows
/// and the verdict takes what is left.
pub(super) fn play_areas(
    area: Rect,
    question: usize,
    verdict: usize,
    diag: u16,
    (before_verdict, question_first): (bool, bool),
) -> [Rect; 7] {
    let before = u16::from(before_verdict);
    let mut rest = area.height.saturating_sub(1 + diag + 1 + before);
    let (question_h, verdict_h) = if question_first {
        let q = (question as u16).max(1).min(rest);
        (q, (verdict as u16).min(rest - q))
    } else {
        let v = (verdict as u16).min(rest.saturating_sub(1));
        (((question as u16).max(1)).min(rest - v), v)
    };
    rest -= verdict_h + question_h;
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

/// The verdict's rows: every line when they fit; otherwise the learner's
/// window on them (`scroll`, from `j`/`k`, kept here within the lines) and
/// a last row saying how many lines are below, so no text is ever cut
/// where the learner cannot reach it.
pub(super) fn verdict_window(
    app: &App,
    mut lines: Vec<Line<'static>>,
    scroll: Option<&std::cell::Cell<usize>>,
    area: Rect,
) -> Vec<Line<'static>> {
    let rows = usize::from(area.height);
    if lines.len() <= rows || rows < 2 {
        if let Some(s) = scroll {
            s.set(0);
        }
        return lines;
    }
    let body = rows - 1;
    let from = scroll.map_or(0, Cell::get).min(lines.len() - body);
    if let Some(s) = scroll {
        s.set(from);
    }
    let below = lines.len() - from - body;
    let mut shown: Vec<Line<'static>> = lines.drain(from..from + body).collect();
    let more = if below > 0 {
        let n = crate::text::plural(
            below,
            w::MORE_LINE.get(&app.lang),
            w::MORE_LINES.get(&app.lang),
        );
        w::VERDICT_MORE.get(&app.lang).replace("{n}", &n)
    } else {
        "↑ (k)".to_string()
    };
    shown.push(Line::from(Span::styled(more, app.theme.dim())));
    shown
}

/// The first `n` of `lines`, the last one ending in "…" when some were
/// left out.
pub(super) fn cut_lines(
    mut lines: Vec<Line<'static>>,
    n: usize,
    width: usize,
) -> Vec<Line<'static>> {
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

/// What the verdict's rating scheduled (`prediction scheduled: Good · back
/// in 10m`), as the verdict's last line: the lesson comes first, and a
/// small screen scrolls to it.
pub(super) fn push_scheduled(
    app: &App,
    lines: &mut Vec<Line<'static>>,
    scheduled: Option<&str>,
    width: usize,
) {
    let Some(text) = scheduled else {
        return;
    };
    if lines.is_empty() {
        return;
    }
    let style = app.theme.dim();
    lines.extend(crate::tui::wrap::wrap(
        &[crate::tui::wrap::Run::new(text.to_string(), style)],
        width.max(1),
        crate::tui::wrap::Run::new(" ", style),
        crate::tui::wrap::Run::new(" ", style),
    ));
}
