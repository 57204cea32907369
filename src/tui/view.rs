//! Drawing the whole frame: header, the current screen, footer, the help
//! overlay, or the "please enlarge" message when the terminal is too small.
//! Drawing never does I/O.

use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Clear, Paragraph, Wrap};

use super::app::App;
use super::i18n::Msg;
use super::keymap::Context;
use super::layout::{MIN_HEIGHT, MIN_WIDTH, body_rect};
use super::screens;
use super::stack::Tui;

pub fn draw(frame: &mut Frame, app: &Tui) {
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
fn screen_name(app: &Tui) -> &'static str {
    app.tr(app.screen().view().name())
}

/// `text` cut to `width` columns, with an ellipsis when cut.
fn fit(text: &str, width: usize) -> String {
    super::wrap::ellipsize(text, width)
}

/// The screen's name, after the deck's title when it is about one deck.
fn screen_title(app: &Tui) -> String {
    let view = app.screen().view();
    let name = app.tr(view.name());
    match view.deck().and_then(|d| app.decks.get(d)) {
        Some(d) => format!("{} · {name}", d.title.get(&app.lang)),
        None => name.to_string(),
    }
}

fn draw_header(frame: &mut Frame, area: Rect, app: &Tui) {
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

fn draw_footer(frame: &mut Frame, area: Rect, app: &Tui) {
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
    // While a field takes the letters, the keys that edit the deck there,
    // as its table has them (`F4`, `F7`), after the back key, as far as
    // the width allows.
    let mut typing_keys: Vec<Vec<Span>> = Vec::new();
    if screens::is_text_input(ctx) {
        spans.extend(hint("F1", Msg::Help));
        let rows = screens::bindings(ctx);
        for (action, word) in [
            (super::action::Action::EditItem, super::i18n::edit::EDIT_KEY),
            (super::action::Action::AddCard, super::i18n::edit::ADD_KEY),
        ] {
            if let Some(b) = rows.iter().find(|b| {
                matches!(b.keys, super::keymap::Keys::Map(keys)
                    if keys.iter().any(|(_, a)| *a == action))
            }) {
                typing_keys.push(vec![
                    Span::styled(b.label, t.key()),
                    Span::styled(format!(" {}  ", word.get(&app.lang)), t.dim()),
                ]);
            }
        }
    } else {
        spans.extend(hint("?", Msg::Help));
        // The language's key where this screen has it (the explore view's
        // `l` turns a knob; `L` changes the language there).
        let language = screens::bindings(ctx)
            .into_iter()
            .find(|b| {
                matches!(b.keys, super::keymap::Keys::Map(keys)
                    if keys.iter().any(|(_, a)| *a == super::action::Action::ToggleLanguage))
            })
            .map_or("l", |b| b.label);
        spans.extend(hint(language, Msg::Language));
    }
    let back = if ctx == Context::Home {
        Msg::Quit
    } else {
        Msg::Back
    };
    spans.extend(hint(if ctx == Context::Home { "q" } else { "Esc" }, back));
    let width = |spans: &[Span]| {
        spans
            .iter()
            .map(|s| super::wrap::columns(&s.content))
            .sum::<usize>()
    };
    for group in typing_keys {
        if width(&spans) + width(&group) > usize::from(area.width) {
            break;
        }
        spans.extend(group);
    }
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

/// The help overlay's rows wrapped to fit the body, and the popup's size.
fn help_layout(app: &Tui, area: Rect) -> (Vec<Line<'static>>, Rect) {
    use super::wrap::{Run, columns, wrap};
    let t = &app.theme;
    let binds = screens::bindings(app.context());
    let label_w = binds.iter().map(|b| columns(b.label)).max().unwrap_or(4);
    let help_w = binds
        .iter()
        .map(|b| columns(b.help(&app.lang)))
        .max()
        .unwrap_or(10);
    // Borders, a space each side, two between the columns.
    let width = (label_w + help_w + 6).min(usize::from(area.width));
    // The wrap width counts the label column too: all but the borders.
    let text_w = width.saturating_sub(2).max(1);
    let mut lines = Vec::new();
    for b in &binds {
        let pad = " ".repeat(label_w - columns(b.label));
        lines.extend(wrap(
            &[Run::new(b.help(&app.lang), t.text())],
            text_w,
            Run::new(format!(" {}{pad}  ", b.label), t.key()),
            Run::new(" ".repeat(label_w + 3), t.text()),
        ));
    }
    let height = (lines.len() + 2).min(usize::from(area.height));
    let (w, h) = (width as u16, height as u16);
    let popup = Rect {
        x: area.x + (area.width - w) / 2,
        y: area.y + (area.height - h) / 2,
        width: w,
        height: h,
    };
    (lines, popup)
}

/// How far the help overlay can scroll at the app's size (0: it fits).
pub fn help_scroll_max(app: &Tui) -> usize {
    let (lines, popup) = help_layout(app, body_rect(app.size));
    lines
        .len()
        .saturating_sub(usize::from(popup.height.saturating_sub(2)))
}

/// The help overlay: every key of the current screen, wrapped to the
/// screen; when it is taller than the screen it scrolls (j/k).
pub fn draw_help(frame: &mut Frame, area: Rect, app: &Tui) {
    let t = &app.theme;
    let (lines, popup) = help_layout(app, area);
    let room = usize::from(popup.height.saturating_sub(2));
    let max = lines.len().saturating_sub(room);
    let scroll = app.help_scroll.min(max);
    let title = fit(
        &format!(" {} · {} ", app.tr(Msg::HelpTitle), screen_name(app)),
        usize::from(popup.width.saturating_sub(2)),
    );
    let bottom = if scroll < max {
        format!(" ↓ j · {} ", app.tr(Msg::AnyKeyCloses))
    } else {
        format!(" {} ", app.tr(Msg::AnyKeyCloses))
    };
    let bottom = fit(&bottom, usize::from(popup.width.saturating_sub(2)));
    let block = Block::default()
        .borders(Borders::ALL)
        .border_style(t.border())
        .title(Span::styled(title, t.title()))
        .title_bottom(Span::styled(bottom, t.dim()));
    let shown: Vec<Line> = lines.into_iter().skip(scroll).take(room).collect();
    frame.render_widget(Clear, popup);
    frame.render_widget(Paragraph::new(shown).block(block), popup);
}
