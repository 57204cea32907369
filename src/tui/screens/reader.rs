//! The reader: a deck's explanation sections, the list beside the body,
//! math rendered, wrapped to the width, searchable, with the links between
//! sections (the concept map) followable.

use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::Style;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, List, ListItem, ListState, Paragraph};

use crate::deck::Deck;
use crate::text::markup::{self, Block as MBlock, Style as MStyle};
use crate::tui::action::Action;
use crate::tui::app::App;
use crate::tui::i18n::Msg;
use crate::tui::theme::Theme;
use crate::tui::view;
use crate::tui::wrap::{Run, line_text, wrap};

use super::Nav;
use crate::tui::i18n::Words;
use crate::tui::keymap::Binding;
use crossterm::event::KeyCode::{
    BackTab, Backspace, Char, Down, End, Enter, Esc, Home, Left, PageDown, PageUp, Right, Tab, Up,
};

pub const KEYS: &[Binding] = &[
    Binding::new(
        "j k ↑↓",
        Words("scroll", "scroll karo"),
        &[
            (Down, Action::Down),
            (Up, Action::Up),
            (Char('j'), Action::Down),
            (Char('k'), Action::Up),
        ],
    ),
    Binding::new(
        "PgUp PgDn",
        Words("scroll a page", "ek page scroll"),
        &[
            (PageUp, Action::PageUp),
            (PageDown, Action::PageDown),
            (Char(' '), Action::PageDown),
        ],
    ),
    Binding::new(
        "g G",
        Words("top / bottom", "shuru / ant"),
        &[
            (Char('g'), Action::Top),
            (Char('G'), Action::Bottom),
            (Home, Action::Top),
            (End, Action::Bottom),
        ],
    ),
    Binding::new(
        "← → h",
        Words("previous / next section", "pichhla / agla section"),
        &[
            (Left, Action::PrevSection),
            (Right, Action::NextSection),
            (Char('h'), Action::PrevSection),
        ],
    ),
    Binding::new(
        "/",
        Words("search every section", "har section mein khojo"),
        &[(Char('/'), Action::StartSearch)],
    ),
    Binding::new(
        "n N",
        Words("next / previous match", "agla / pichhla match"),
        &[
            (Char('n'), Action::NextMatch),
            (Char('N'), Action::PrevMatch),
        ],
    ),
    Binding::new(
        "Tab",
        Words("choose a linked section", "juda section chuno"),
        &[(Tab, Action::NextLink), (BackTab, Action::NextLink)],
    ),
    Binding::new(
        "Enter",
        Words("follow the link", "link kholo"),
        &[(Enter, Action::FollowLink)],
    ),
    Binding::new(
        "Esc q",
        Words("back", "wapas"),
        &[(Esc, Action::Back), (Char('q'), Action::Back)],
    ),
];

/// While a search is typed.
pub const SEARCH_KEYS: &[Binding] = &[
    Binding::typing(Words("the words to find", "khojne ke shabd")),
    Binding::new("Enter", Words("find", "khojo"), &[(Enter, Action::Submit)]),
    Binding::new(
        "Backspace",
        Words("delete a character", "ek akshar mitao"),
        &[(Backspace, Action::Backspace)],
    ),
    Binding::new("Esc", Words("cancel", "radd karo"), &[(Esc, Action::Back)]),
];

#[derive(Debug, Clone, PartialEq, Default)]
pub struct ReaderState {
    pub deck: usize,
    pub section: usize,
    /// First body line shown.
    pub scroll: usize,
    /// The focused link of the section's "see also" list.
    pub link: Option<usize>,
    /// The search being typed (`/`), if any.
    pub search: Option<String>,
    /// The last search made, highlighted and repeated by `n`/`N`.
    pub query: Option<String>,
    /// The match jumped to last (section, line): `n`/`N` go on from here.
    pub hit: Option<(usize, usize)>,
    /// Where following links came from, so Esc walks back.
    pub history: Vec<(usize, usize)>,
}

impl ReaderState {
    pub fn new(deck: usize) -> ReaderState {
        ReaderState {
            deck,
            ..ReaderState::default()
        }
    }
}

/// Opens the reader at a section (from a card or a verdict).
pub fn open_at(app: &App, deck: usize, section: &str) -> Nav {
    let index = app
        .decks
        .get(deck)
        .and_then(|d| d.sections.iter().position(|s| s.id == section));
    match index {
        Some(i) => Nav::Push(super::Screen::Reader(ReaderState {
            section: i,
            ..ReaderState::new(deck)
        })),
        None => Nav::Stay,
    }
}

/// The reader's areas inside the screen body: section list, text, and the
/// line of links (or the search field).
pub fn areas(body: Rect) -> (Rect, Rect, Rect) {
    let list_w = (body.width / 3).clamp(12, 30);
    let [list, right] =
        Layout::horizontal([Constraint::Length(list_w), Constraint::Fill(1)]).areas(body);
    let [text, links] = Layout::vertical([Constraint::Fill(1), Constraint::Length(1)]).areas(right);
    // One column of margin on the left of the text.
    let text = Rect {
        x: text.x.saturating_add(1).min(text.right()),
        width: text.width.saturating_sub(1),
        ..text
    };
    (list, text, links)
}

fn runs(spans: &[markup::Span], theme: &Theme) -> Vec<Run> {
    spans
        .iter()
        .map(|s| {
            let style = match s.style {
                MStyle::Plain => theme.text(),
                MStyle::Emphasis => theme.emphasis(),
                MStyle::Strong => theme.strong(),
                MStyle::Math => theme.math(),
            };
            // Paragraph lines are joined; wrapping decides the breaks.
            Run::new(s.text.replace('\n', " "), style)
        })
        .collect()
}

/// A section's title and body as wrapped lines.
pub fn section_lines(app: &App, deck: &Deck, section: usize, width: usize) -> Vec<Line<'static>> {
    let t = &app.theme;
    let Some(sec) = deck.sections.get(section) else {
        return Vec::new();
    };
    let none = || Run::new("", Style::new());
    let mut lines = wrap(
        &[Run::new(
            crate::text::render(sec.title.get(&app.lang)),
            t.heading(),
        )],
        width,
        none(),
        none(),
    );
    lines.push(Line::default());
    for block in markup::parse(sec.body.get(&app.lang)) {
        match block {
            MBlock::Paragraph(spans) => {
                lines.extend(wrap(&runs(&spans, t), width, none(), none()));
                lines.push(Line::default());
            }
            MBlock::Item(spans) => {
                lines.extend(wrap(
                    &runs(&spans, t),
                    width,
                    Run::new("• ", t.key()),
                    Run::new("  ", t.text()),
                ));
            }
            MBlock::Display(math) => {
                if lines.last().is_some_and(|l| !l.spans.is_empty()) {
                    lines.push(Line::default());
                }
                for row in math.lines() {
                    lines.extend(wrap(
                        &[Run::new(row, t.math())],
                        width,
                        Run::new("    ", t.math()),
                        Run::new("    ", t.math()),
                    ));
                }
                lines.push(Line::default());
            }
        }
    }
    while lines.last().is_some_and(|l| l.spans.is_empty()) && lines.len() > 1 {
        lines.pop();
    }
    lines
}

/// Body text area for the app's terminal size.
fn text_area(app: &App) -> Rect {
    let (_, text, _) = areas(view::body_rect(app.size));
    text
}

fn max_scroll(app: &App, deck: &Deck, state: &ReaderState) -> usize {
    let area = text_area(app);
    let n = section_lines(app, deck, state.section, area.width as usize).len();
    n.saturating_sub(area.height as usize)
}

fn lowercase_chars(s: &str) -> Vec<char> {
    s.chars()
        .map(|c| c.to_lowercase().next().unwrap_or(c))
        .collect()
}

/// Char ranges of `query` in `text`, case-insensitively.
fn matches(text: &str, query: &[char]) -> Vec<(usize, usize)> {
    if query.is_empty() {
        return Vec::new();
    }
    let hay = lowercase_chars(text);
    let mut out = Vec::new();
    let mut i = 0;
    while i + query.len() <= hay.len() {
        if hay[i..i + query.len()] == *query {
            out.push((i, i + query.len()));
            i += query.len();
        } else {
            i += 1;
        }
    }
    out
}

/// The line with every match of `query` in `style`.
fn highlight(line: Line<'static>, query: &[char], style: Style) -> Line<'static> {
    let ranges = matches(&line_text(&line), query);
    if ranges.is_empty() {
        return line;
    }
    let mut out = Vec::new();
    let mut pos = 0;
    for span in line.spans {
        let mut buf = String::new();
        let mut buf_hit = false;
        for c in span.content.chars() {
            let hit = ranges.iter().any(|&(a, b)| pos >= a && pos < b);
            if hit != buf_hit && !buf.is_empty() {
                let st = if buf_hit {
                    span.style.patch(style)
                } else {
                    span.style
                };
                out.push(Span::styled(std::mem::take(&mut buf), st));
            }
            buf_hit = hit;
            buf.push(c);
            pos += 1;
        }
        if !buf.is_empty() {
            let st = if buf_hit {
                span.style.patch(style)
            } else {
                span.style
            };
            out.push(Span::styled(buf, st));
        }
    }
    Line::from(out)
}

/// The next (or previous) match of `query` from just after (before) the
/// current position, through every section, wrapping around.
fn find(
    app: &App,
    deck: &Deck,
    state: &ReaderState,
    query: &str,
    forward: bool,
    from_here: bool,
) -> Option<(usize, usize)> {
    let q = lowercase_chars(query);
    let width = text_area(app).width as usize;
    let n = deck.sections.len();
    let all: Vec<Vec<usize>> = (0..n)
        .map(|s| {
            section_lines(app, deck, s, width)
                .iter()
                .enumerate()
                .filter(|(_, l)| !matches(&line_text(l), &q).is_empty())
                .map(|(i, _)| i)
                .collect()
        })
        .collect();
    // Positions in reading order: (section, line).
    let hits: Vec<(usize, usize)> = all
        .iter()
        .enumerate()
        .flat_map(|(s, ls)| ls.iter().map(move |&l| (s, l)))
        .collect();
    let here = match state.hit {
        Some(hit) if hit.0 == state.section => hit,
        _ => (state.section, state.scroll),
    };
    let pick = if forward {
        hits.iter()
            .find(|&&h| if from_here { h >= here } else { h > here })
            .or(hits.first())
    } else {
        hits.iter().rev().find(|&&h| h < here).or(hits.last())
    };
    pick.copied()
}

impl super::View for ReaderState {
    fn context(&self) -> crate::tui::keymap::Context {
        if self.search.is_some() {
            crate::tui::keymap::Context::ReaderSearch
        } else {
            crate::tui::keymap::Context::Reader
        }
    }
    fn apply(&mut self, app: &mut App, action: Action) -> Nav {
        apply(app, self, action)
    }
    fn draw(&self, frame: &mut Frame, area: Rect, app: &App) {
        draw(frame, area, app, self)
    }
    fn name(&self) -> Msg {
        Msg::Reader
    }
    fn deck(&self) -> Option<usize> {
        Some(self.deck)
    }
}

pub fn apply(app: &mut App, state: &mut ReaderState, action: Action) -> Nav {
    let Some(deck) = app.decks.get(state.deck) else {
        return Nav::Pop;
    };
    // The language or the size may have changed since the last key.
    let max = max_scroll(app, deck, state);
    state.scroll = state.scroll.min(max);
    let page = (text_area(app).height as usize).saturating_sub(1).max(1);
    let n_sections = deck.sections.len();
    let links = deck.sections.get(state.section).map_or(0, |s| s.see.len());

    if let Some(input) = &mut state.search {
        match action {
            Action::Input(c) => input.push(c),
            Action::Backspace => {
                input.pop();
            }
            Action::Back => state.search = None,
            Action::Submit => {
                let query = state.search.take().unwrap_or_default();
                if !query.trim().is_empty() {
                    state.query = Some(query.clone());
                    jump(app, state, &query, true, true);
                }
            }
            _ => {}
        }
        return Nav::Stay;
    }

    match action {
        Action::Up => state.scroll = state.scroll.saturating_sub(1),
        Action::Down => state.scroll = (state.scroll + 1).min(max),
        Action::PageUp => state.scroll = state.scroll.saturating_sub(page),
        Action::PageDown => state.scroll = (state.scroll + page).min(max),
        Action::Top => state.scroll = 0,
        Action::Bottom => state.scroll = max,
        Action::PrevSection if state.section > 0 => go(state, state.section - 1, false),
        Action::NextSection if state.section + 1 < n_sections => {
            go(state, state.section + 1, false)
        }
        Action::NextLink if links > 0 => {
            state.link = Some(state.link.map_or(0, |l| (l + 1) % links));
        }
        Action::FollowLink if links > 0 => {
            let i = state.link.unwrap_or(0).min(links - 1);
            let target = deck.sections[state.section].see[i].clone();
            if let Some(to) = deck.sections.iter().position(|s| s.id == target) {
                go(state, to, true);
            }
        }
        Action::StartSearch => state.search = Some(String::new()),
        Action::NextMatch | Action::PrevMatch => {
            if let Some(q) = state.query.clone() {
                jump(app, state, &q, action == Action::NextMatch, false);
            }
        }
        Action::Back => match state.history.pop() {
            Some((section, scroll)) => {
                state.section = section;
                state.scroll = scroll;
                state.link = None;
            }
            None => return Nav::Pop,
        },
        _ => {}
    }
    Nav::Stay
}

fn go(state: &mut ReaderState, section: usize, remember: bool) {
    if remember {
        state.history.push((state.section, state.scroll));
    }
    state.section = section;
    state.scroll = 0;
    state.link = None;
}

fn jump(app: &mut App, state: &mut ReaderState, query: &str, forward: bool, from_here: bool) {
    let Some(deck) = app.decks.get(state.deck) else {
        return;
    };
    match find(app, deck, state, query, forward, from_here) {
        Some((section, line)) => {
            state.section = section;
            state.hit = Some((section, line));
            state.link = None;
            let max = max_scroll(app, deck, state);
            state.scroll = line.min(max);
            app.status = None;
        }
        None => {
            let msg = format!("{}: {query}", app.tr(Msg::NoMatch));
            app.info(msg);
        }
    }
}

pub fn draw(frame: &mut Frame, area: Rect, app: &App, state: &ReaderState) {
    let t = &app.theme;
    let Some(deck) = app.decks.get(state.deck) else {
        return;
    };
    if deck.sections.is_empty() {
        frame.render_widget(Paragraph::new(app.tr(Msg::NoSections)), area);
        return;
    }
    let (list_area, text_area, links_area) = areas(area);

    let items = deck
        .sections
        .iter()
        .map(|s| ListItem::new(Line::from(crate::text::render(s.title.get(&app.lang)))));
    let list = List::new(items)
        .block(
            Block::default()
                .borders(Borders::RIGHT)
                .border_style(t.border()),
        )
        .highlight_style(t.selected());
    let mut ls = ListState::default().with_selected(Some(state.section));
    frame.render_stateful_widget(list, list_area, &mut ls);

    let lines = section_lines(app, deck, state.section, text_area.width as usize);
    let max = lines.len().saturating_sub(text_area.height as usize);
    let scroll = state.scroll.min(max);
    let query = state.query.as_deref().map(lowercase_chars);
    let shown: Vec<Line> = lines
        .into_iter()
        .skip(scroll)
        .take(text_area.height as usize)
        .map(|l| match &query {
            Some(q) => highlight(l, q, t.highlight()),
            None => l,
        })
        .collect();
    frame.render_widget(Paragraph::new(shown), text_area);

    let bottom = if let Some(input) = &state.search {
        Line::from(vec![
            Span::styled(format!(" /{input}▏"), t.strong()),
            Span::styled(format!("  {}", app.tr(Msg::Search)), t.dim()),
        ])
    } else {
        let see = deck
            .sections
            .get(state.section)
            .map(|s| s.see.as_slice())
            .unwrap_or(&[]);
        let mut spans = Vec::new();
        if !see.is_empty() {
            spans.push(Span::styled(
                format!(" {}: ", app.tr(Msg::SeeAlso)),
                t.dim(),
            ));
            for (i, id) in see.iter().enumerate() {
                let title = deck
                    .section(id)
                    .map(|s| crate::text::render(s.title.get(&app.lang)))
                    .unwrap_or_else(|| id.clone());
                let style = if state.link == Some(i) {
                    t.selected()
                } else {
                    t.link()
                };
                spans.push(Span::styled(format!("[{title}]"), style));
                spans.push(Span::raw(" "));
            }
        }
        let pos = format!(" {}/{} ", state.section + 1, deck.sections.len());
        spans.push(Span::styled(pos, t.dim()));
        Line::from(spans)
    };
    frame.render_widget(Paragraph::new(bottom), links_area);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_are_case_insensitive_char_ranges() {
        let q = lowercase_chars("ω₂");
        assert_eq!(matches("a Ω₂ b ω₂", &q), vec![(2, 4), (7, 9)]);
        assert!(matches("abc", &[]).is_empty());
    }

    #[test]
    fn highlight_splits_spans_at_match_edges() {
        let line = Line::from(vec![Span::raw("tennis ra"), Span::raw("cket theorem")]);
        let out = highlight(
            line,
            &lowercase_chars("racket"),
            Style::new().add_modifier(ratatui::style::Modifier::BOLD),
        );
        let texts: Vec<&str> = out.spans.iter().map(|s| s.content.as_ref()).collect();
        assert_eq!(texts, ["tennis ", "ra", "cket", " theorem"]);
        assert_eq!(line_text(&out), "tennis racket theorem");
    }
}
