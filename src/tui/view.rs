//! Drawing the whole frame: header, the current screen, footer, the help
//! overlay, or the "please enlarge" message when the terminal is too small.
//! Drawing never does I/O.

use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Clear, Paragraph, Row, Table, Wrap};

use super::app::App;
use super::i18n::Msg;
use super::keymap::{self, Context};

/// The smallest terminal the screens are laid out for.
pub const MIN_WIDTH: u16 = 40;
pub const MIN_HEIGHT: u16 = 12;

pub fn draw(frame: &mut Frame, app: &App) {
    let area = frame.area();
    if area.width < MIN_WIDTH || area.height < MIN_HEIGHT {
        let p = Paragraph::new(app.tr(Msg::Enlarge))
            .style(app.theme.warn())
            .wrap(Wrap { trim: true });
        frame.render_widget(p, area);
        return;
    }
    let body = body_rect((area.width, area.height));
    let header = Rect::new(area.x, area.y, area.width, 1);
    let footer = Rect::new(area.x, area.bottom().saturating_sub(1), area.width, 1);
    draw_header(frame, header, app);
    app.screen().view().draw(frame, body, app);
    draw_footer(frame, footer, app);
    if app.help {
        draw_help(frame, body, app);
    }
}

/// What the screen is, without the deck ("Review", "Reader").
fn screen_name(app: &App) -> &'static str {
    app.tr(app.screen().view().name())
}

/// `text` cut to `width` columns, with an ellipsis when cut.
fn fit(text: &str, width: usize) -> String {
    use unicode_width::UnicodeWidthChar;
    let total: usize = text.chars().map(|c| c.width().unwrap_or(0)).sum();
    if total <= width {
        return text.to_string();
    }
    let mut out = String::new();
    let mut used = 0;
    for c in text.chars() {
        let w = c.width().unwrap_or(0);
        if used + w + 1 > width {
            break;
        }
        used += w;
        out.push(c);
    }
    if width > 0 {
        out.push('…');
    }
    out
}

/// The screen's name, after the deck's title when it is about one deck.
fn screen_title(app: &App) -> String {
    let view = app.screen().view();
    let name = app.tr(view.name());
    match view.deck().and_then(|d| app.decks.get(d)) {
        Some(d) => format!("{} · {name}", d.title.get(&app.lang)),
        None => name.to_string(),
    }
}

fn draw_header(frame: &mut Frame, area: Rect, app: &App) {
    let t = &app.theme;
    let lang = format!("{} ", app.tr(Msg::LanguageName));
    let [l, _, r] = Layout::horizontal([
        Constraint::Fill(1),
        Constraint::Length(1),
        Constraint::Length(lang.chars().count() as u16),
    ])
    .areas(area);
    let room = (l.width as usize).saturating_sub(" flipcard · ".chars().count());
    let left = Line::from(vec![
        Span::styled(" flipcard ", t.title()),
        Span::styled("· ", t.dim()),
        Span::styled(fit(&screen_title(app), room), t.heading()),
    ]);
    frame.render_widget(Paragraph::new(left), l);
    frame.render_widget(Paragraph::new(Span::styled(lang, t.dim())), r);
}

fn draw_footer(frame: &mut Frame, area: Rect, app: &App) {
    let t = &app.theme;
    if let Some(status) = &app.status {
        draw_status(frame, area, app, status);
        return;
    }
    let ctx = app.context();
    let hint = |key: &'static str, msg: Msg| {
        vec![
            Span::styled(key, t.key()),
            Span::styled(format!(" {}  ", app.tr(msg)), t.dim()),
        ]
    };
    let mut spans = vec![Span::raw(" ")];
    if ctx.is_text_input() {
        spans.extend(hint("F1", Msg::Help));
    } else {
        spans.extend(hint("?", Msg::Help));
        spans.extend(hint("l", Msg::Language));
    }
    let back = if ctx == Context::Home {
        Msg::Quit
    } else {
        Msg::Back
    };
    spans.extend(hint(if ctx == Context::Home { "q" } else { "Esc" }, back));
    frame.render_widget(Paragraph::new(Line::from(spans)), area);
}

/// A status message, wrapped: it grows upwards from the footer over the
/// screen (at most half of it) so that a long one, such as a path to a
/// damaged database and its backup, stays readable.
fn draw_status(frame: &mut Frame, footer: Rect, app: &App, status: &super::app::Status) {
    let t = &app.theme;
    let style = if status.error { t.bad() } else { t.good() };
    let width = usize::from(footer.width.max(1));
    let lines = super::wrap::wrap_plain(&status.text, style, width);
    let room = (footer.bottom() / 2).max(1);
    let height = u16::try_from(lines.len())
        .unwrap_or(u16::MAX)
        .clamp(1, room);
    let area = Rect::new(
        footer.x,
        footer.bottom().saturating_sub(height),
        footer.width,
        height,
    );
    frame.render_widget(Clear, area);
    frame.render_widget(Paragraph::new(lines), area);
}

/// The help overlay: every key of the current screen.
pub fn draw_help(frame: &mut Frame, area: Rect, app: &App) {
    let t = &app.theme;
    let binds = keymap::bindings(app.context());
    let label_w = binds
        .iter()
        .map(|b| b.label.chars().count())
        .max()
        .unwrap_or(4) as u16;
    let help_w = binds
        .iter()
        .map(|b| b.help(&app.lang).chars().count())
        .max()
        .unwrap_or(10) as u16;
    let width = (label_w + help_w + 7).min(area.width);
    let height = (binds.len() as u16 + 2).min(area.height);
    let popup = Rect {
        x: area.x + (area.width - width) / 2,
        y: area.y + (area.height - height) / 2,
        width,
        height,
    };
    let rows = binds.iter().map(|b| {
        Row::new(vec![
            Span::styled(b.label, t.key()),
            Span::raw(b.help(&app.lang)),
        ])
    });
    let title = format!(" {} · {} ", app.tr(Msg::HelpTitle), screen_name(app));
    let table = Table::new(rows, [Constraint::Length(label_w), Constraint::Fill(1)])
        .column_spacing(2)
        .block(
            Block::default()
                .borders(Borders::ALL)
                .border_style(t.border())
                .title(Span::styled(title, t.title()))
                .title_bottom(Span::styled(
                    format!(" {} ", app.tr(Msg::AnyKeyCloses)),
                    t.dim(),
                )),
        );
    frame.render_widget(Clear, popup);
    frame.render_widget(table, popup);
}

/// The screen body (between header and footer) for a terminal size; the
/// same split `draw` makes, so actions can reason about what is visible.
pub fn body_rect(size: (u16, u16)) -> Rect {
    let (w, h) = size;
    Rect::new(0, 1.min(h), w, h.saturating_sub(2))
}
