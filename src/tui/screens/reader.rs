//! The reader: a deck's explanation sections, the list beside the body,
//! math rendered, wrapped to the width, searchable, with the links between
//! sections (the concept map) followable. After the sections come the
//! deck's derivations, each a page of its steps in order with their
//! reasons (a worked example).

use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::Style;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, List, ListItem, ListState, Paragraph};

use crate::deck::{Deck, Explain};
use crate::text::markup::{self, Block as MBlock, Style as MStyle};
use crate::tui::action::Action;
use crate::tui::app::App;
use crate::tui::i18n::Msg;
use crate::tui::i18n::reader as words;
use crate::tui::layout::{MEASURE, body_rect};
use crate::tui::theme::Theme;
use crate::tui::wrap::{Run, columns, ellipsize, line_text, wrap, wrap_tagged};

use super::Nav;
use crate::tui::i18n::Words;
use crate::tui::keymap::Binding;
use crossterm::event::KeyCode::{BackTab, Backspace, Char, Enter, Esc, Left, Right, Tab};

pub const KEYS: &[Binding] = &[
    Binding::SCROLL[0],
    Binding::SCROLL[1],
    Binding::SCROLL[2],
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
        "Tab S-Tab",
        Words(
            "choose the next / previous link",
            "agla / pichhla link chuno",
        ),
        &[(Tab, Action::NextLink), (BackTab, Action::PrevLink)],
    ),
    Binding::new(
        "Enter",
        Words(
            "follow the chosen link (a derivation: its next step)",
            "chuna hua link kholo (derivation mein: agla step)",
        ),
        &[(Enter, Action::FollowLink)],
    ),
    Binding::new(
        "F",
        Words("formula sheet", "formula sheet"),
        &[(Char('F'), Action::OpenFormulas)],
    ),
    Binding::new(
        "E",
        Words(
            "edit this section in the language shown",
            "yeh section dikhti bhasha mein edit karo",
        ),
        &[(Char('E'), Action::EditItem)],
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
    /// The chosen link of the section (inline links first, then "see
    /// also"); always on screen while chosen.
    pub link: Option<usize>,
    /// The search being typed (`/`), if any.
    pub search: Option<String>,
    /// The last search made, highlighted and repeated by `n`/`N`.
    pub query: Option<String>,
    /// The match jumped to last (section, line, first char): `n`/`N` go on
    /// from here, and it is drawn apart from the other matches.
    pub hit: Option<(usize, usize, usize)>,
    /// Where following links came from, so Esc walks back.
    pub history: Vec<(usize, usize)>,
    /// Opened at an anchor: the section and the anchor. That section
    /// scrolls at least as far as the anchor's paragraph (in the language
    /// and width on screen), so the paragraph is the first line shown even
    /// near the section's end.
    pub anchored: Option<(usize, String)>,
    /// On a derivation's page, how many of its steps are shown: one at a
    /// time, Enter the next (0 counts as 1).
    pub steps: usize,
}

impl ReaderState {
    pub fn new(deck: usize) -> ReaderState {
        ReaderState {
            deck,
            ..ReaderState::default()
        }
    }
}

impl ReaderState {
    /// The deck was edited and reloaded (`E`): the page edited is shown
    /// again, found by its id, at the same scroll as far as it still
    /// reaches; a page whose id is gone gives way to the nearest one.
    pub fn deck_edited(&mut self, app: &App, edited: &crate::tui::edit::Edited) {
        if edited.deck != self.deck {
            return;
        }
        let Some(d) = app.decks.get(self.deck) else {
            return;
        };
        let found = match &edited.target {
            crate::tui::edit::Target::Section { id: Some(id), .. } => {
                d.sections.iter().position(|s| &s.id == id)
            }
            crate::tui::edit::Target::Item(key)
                if key.direction == crate::sched::Direction::Derive =>
            {
                d.derivations
                    .iter()
                    .position(|x| x.id == key.card)
                    .map(|i| d.sections.len() + i)
            }
            _ => None,
        };
        let n = pages(d);
        self.section = found.unwrap_or(self.section).min(n.saturating_sub(1));
        for (section, _) in &mut self.history {
            *section = (*section).min(n.saturating_sub(1));
        }
        self.link = None;
        self.hit = None;
        self.anchored = None;
        self.scroll = self.scroll.min(max_scroll(app, d, self));
    }
}

/// What `E` edits on the page shown: the section in the content file of
/// the language on screen (the deck's first in order when it lacks that
/// one, as the texts fall back), or a derivation in the deck file.
fn edit_target(app: &App, deck: &Deck, state: &ReaderState) -> crate::tui::edit::Target {
    if let Some(d) = derivation_at(deck, state.section) {
        return crate::tui::edit::Target::Item(crate::sched::ItemKey {
            deck: deck.id.clone(),
            card: d.id.clone(),
            direction: crate::sched::Direction::Derive,
        });
    }
    let lang = if deck.languages.contains(&app.lang) {
        app.lang.clone()
    } else {
        deck.languages.iter().min().cloned().unwrap_or_default()
    };
    crate::tui::edit::Target::Section {
        id: deck.sections.get(state.section).map(|s| s.id.clone()),
        lang,
    }
}

/// Opens the reader at a section (from a card or a verdict), scrolled so
/// that the paragraph its anchor names (`section#anchor`) is the first
/// line shown (below the section's end, the page is blank).
pub fn open_at(app: &App, deck: usize, explain: &Explain) -> Nav {
    let Some(d) = app.decks.get(deck) else {
        return Nav::Stay;
    };
    let Some(i) = d.sections.iter().position(|s| s.id == explain.section) else {
        return Nav::Stay;
    };
    let mut state = ReaderState {
        section: i,
        ..ReaderState::new(deck)
    };
    if let Some(anchor) = &explain.anchor {
        let width = text_area(app).width as usize;
        let page = page(app, d, i, width, None);
        if let Some(&(_, line)) = page.anchors.iter().find(|(a, _)| a == anchor) {
            state.scroll = line;
            state.anchored = Some((i, anchor.clone()));
        }
    }
    Nav::Push(super::Screen::Reader(state))
}

/// The reader's areas inside the screen body: section list, text, and the
/// status line (the chosen link, the search, the position).
pub fn areas(body: Rect) -> (Rect, Rect, Rect) {
    // A wide terminal gives the list what the capped text leaves over, so
    // that titles are not cut.
    let list_w = if body.width >= 120 {
        (body.width - MEASURE - 2).clamp(40, 60)
    } else {
        (body.width / 3).clamp(12, 30)
    };
    let [list, right] =
        Layout::horizontal([Constraint::Length(list_w), Constraint::Fill(1)]).areas(body);
    let [text, status] =
        Layout::vertical([Constraint::Fill(1), Constraint::Length(1)]).areas(right);
    // One column of margin on the left of the text (the current search
    // match is marked there).
    let text = Rect {
        x: text.x.saturating_add(1).min(text.right()),
        width: text.width.saturating_sub(1).min(MEASURE),
        ..text
    };
    (list, text, status)
}

/// A link of a section: the section it opens and the first line it is on.
#[derive(Debug, Clone, PartialEq)]
pub struct LinkAt {
    pub target: String,
    pub line: usize,
}

/// A section laid out at a width: its lines and its links.
pub struct Page {
    pub lines: Vec<Line<'static>>,
    pub links: Vec<LinkAt>,
    /// Lines of the section's own text, before "see also" (which search
    /// leaves out: it names other sections).
    pub text_lines: usize,
    /// Each anchor of the section's body (`{#name}`) with the line its
    /// block starts on.
    pub anchors: Vec<(String, usize)>,
}

fn style_of(s: &markup::Span, theme: &Theme) -> Style {
    match s.style {
        MStyle::Plain => theme.text(),
        MStyle::Emphasis => theme.emphasis(),
        MStyle::Strong => theme.strong(),
        MStyle::Math => theme.math(),
        MStyle::Code => theme.code(),
    }
}

/// The runs of a paragraph or item; each inline link becomes one entry of
/// `links` (its line filled in after wrapping) and tags its runs.
fn runs(
    spans: &[markup::Span],
    theme: &Theme,
    links: &mut Vec<LinkAt>,
    chosen: Option<usize>,
) -> Vec<Run> {
    let mut out = Vec::new();
    let mut last: Option<&str> = None;
    for s in spans {
        let tag = match &s.link {
            Some(target) => {
                if last != Some(target.as_str()) {
                    links.push(LinkAt {
                        target: target.clone(),
                        line: 0,
                    });
                }
                Some(links.len() - 1)
            }
            None => None,
        };
        last = s.link.as_deref();
        let mut style = style_of(s, theme);
        if let Some(i) = tag {
            style = style.patch(if chosen == Some(i) {
                theme.selected()
            } else {
                theme.link()
            });
        }
        // Paragraph lines are joined; wrapping decides the breaks, except
        // inside a formula.
        let run = Run::new(s.text.replace('\n', " "), style).tagged(tag);
        out.push(if s.style == MStyle::Math {
            run.glued()
        } else {
            run
        });
    }
    out
}

/// Appends wrapped lines, recording on which line each link starts.
fn extend(
    lines: &mut Vec<Line<'static>>,
    links: &mut [LinkAt],
    (wrapped, tags): (Vec<Line<'static>>, Vec<(usize, usize)>),
) {
    let base = lines.len();
    let mut seen = Vec::new();
    for (tag, line) in tags {
        if !seen.contains(&tag)
            && let Some(l) = links.get_mut(tag)
        {
            l.line = base + line;
            seen.push(tag);
        }
    }
    lines.extend(wrapped);
}

/// One row of a display equation at `width`: indented, whole on a line
/// when it fits, else folded where mathematics breaks (at a top-level
/// operator first) with the folds indented further.
pub fn display_lines(row: &str, style: Style, width: usize) -> Vec<Line<'static>> {
    wrap(
        &[Run::new(row, style).glued()],
        width,
        Run::new("    ", style),
        Run::new("      ", style),
    )
}

/// A section laid out at `width`, with link `chosen` drawn as chosen.
/// The pages of a deck: its sections, then its derivations.
pub fn pages(deck: &Deck) -> usize {
    deck.sections.len() + deck.derivations.len()
}

/// Before a derivation's title, in the list and on its page.
const DERIVATION_MARK: &str = "∴ ";

/// A derivation's page: its title, then its first `shown` steps with their
/// reasons, and what brings the next.
fn derivation_page(app: &App, d: &crate::deck::Derivation, width: usize, shown: usize) -> Page {
    let t = &app.theme;
    let none = || Run::new("", Style::new());
    let mut lines = wrap(
        &crate::tui::wrap::math_runs(d.title.get(&app.lang), t.heading()),
        width,
        Run::new(DERIVATION_MARK, t.heading()),
        none(),
    );
    lines.extend(crate::tui::wrap::wrap_plain(
        crate::tui::i18n::derive::WORKED.get(&app.lang),
        t.dim(),
        width,
    ));
    for (i, step) in d.steps.iter().enumerate().take(shown.max(1)) {
        lines.push(Line::default());
        lines.extend(crate::tui::derivation::step_lines(app, step, i, width));
    }
    if shown.max(1) < d.steps.len() {
        lines.push(Line::default());
        lines.extend(crate::tui::wrap::wrap_plain(
            &format!(
                "{} ({}/{})",
                crate::tui::i18n::derive::READER_NEXT.get(&app.lang),
                shown.max(1),
                d.steps.len()
            ),
            t.key(),
            width,
        ));
    }
    Page {
        text_lines: lines.len(),
        lines,
        links: Vec::new(),
        anchors: Vec::new(),
    }
}

/// A page as the reader shows it now: a derivation's steps so far.
fn page_shown(app: &App, deck: &Deck, state: &ReaderState, width: usize) -> Page {
    match derivation_at(deck, state.section) {
        Some(d) => derivation_page(app, d, width, state.steps),
        None => page(app, deck, state.section, width, state.link),
    }
}

/// The derivation on page `section`, when it is one.
fn derivation_at(deck: &Deck, section: usize) -> Option<&crate::deck::Derivation> {
    section
        .checked_sub(deck.sections.len())
        .and_then(|i| deck.derivations.get(i))
}

/// Page `section` whole (a derivation with every step: what a search
/// reads).
pub fn page(app: &App, deck: &Deck, section: usize, width: usize, chosen: Option<usize>) -> Page {
    let t = &app.theme;
    if let Some(d) = derivation_at(deck, section) {
        return derivation_page(app, d, width, usize::MAX);
    }
    let Some(sec) = deck.sections.get(section) else {
        return Page {
            lines: Vec::new(),
            links: Vec::new(),
            text_lines: 0,
            anchors: Vec::new(),
        };
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
    let mut links: Vec<LinkAt> = Vec::new();
    let (blocks, anchored) = markup::parse_anchored(sec.body.get(&app.lang));
    // The line each block starts on.
    let mut starts: Vec<usize> = Vec::with_capacity(blocks.len());
    for block in blocks {
        let opens_apart =
            !matches!(block, MBlock::Item(_)) && lines.last().is_some_and(|l| !l.spans.is_empty());
        starts.push(lines.len() + usize::from(opens_apart));
        match block {
            MBlock::Paragraph(spans) => {
                // A list ends with a blank line before the next paragraph.
                if lines.last().is_some_and(|l| !l.spans.is_empty()) {
                    lines.push(Line::default());
                }
                let r = runs(&spans, t, &mut links, chosen);
                extend(
                    &mut lines,
                    &mut links,
                    wrap_tagged(&r, width, none(), none()),
                );
                lines.push(Line::default());
            }
            MBlock::Item(spans) => {
                let r = runs(&spans, t, &mut links, chosen);
                extend(
                    &mut lines,
                    &mut links,
                    wrap_tagged(&r, width, Run::new("• ", t.key()), Run::new("  ", t.text())),
                );
            }
            MBlock::Display(math) => {
                if lines.last().is_some_and(|l| !l.spans.is_empty()) {
                    lines.push(Line::default());
                }
                for row in math.lines() {
                    lines.extend(display_lines(row, t.math(), width));
                }
                lines.push(Line::default());
            }
        }
    }
    while lines.last().is_some_and(|l| l.spans.is_empty()) && lines.len() > 1 {
        lines.pop();
    }
    let anchors = anchored
        .into_iter()
        .map(|(name, block)| {
            let line = starts.get(block).copied().unwrap_or(lines.len());
            (name, line.min(lines.len().saturating_sub(1)))
        })
        .collect();
    // "See also": the linked sections the text does not link to already,
    // one per line so that every one is seen.
    let text_lines = lines.len();
    let inline: Vec<String> = links.iter().map(|l| l.target.clone()).collect();
    let see: Vec<&String> = sec.see.iter().filter(|id| !inline.contains(id)).collect();
    if !see.is_empty() {
        lines.push(Line::default());
        lines.push(Line::styled(app.tr(Msg::SeeAlso), t.heading()));
        for id in see {
            let title = deck
                .section(id)
                .map(|s| crate::text::render(s.title.get(&app.lang)))
                .unwrap_or_else(|| id.clone());
            let i = links.len();
            links.push(LinkAt {
                target: id.clone(),
                line: 0,
            });
            let style = if chosen == Some(i) {
                t.selected()
            } else {
                t.link()
            };
            let r = [Run::new(title, style).tagged(Some(i))];
            extend(
                &mut lines,
                &mut links,
                wrap_tagged(&r, width, Run::new("→ ", t.key()), Run::new("  ", t.text())),
            );
        }
    }
    Page {
        lines,
        links,
        text_lines,
        anchors,
    }
}

/// A section's lines at a width (no link chosen).
pub fn section_lines(app: &App, deck: &Deck, section: usize, width: usize) -> Vec<Line<'static>> {
    page(app, deck, section, width, None).lines
}

/// Body text area for the app's terminal size.
fn text_area(app: &App) -> Rect {
    let (_, text, _) = areas(body_rect(app.size));
    text
}

fn max_scroll(app: &App, deck: &Deck, state: &ReaderState) -> usize {
    let area = text_area(app);
    let page = page_shown(app, deck, state, area.width as usize);
    page.lines
        .len()
        .saturating_sub(area.height as usize)
        .max(anchored_line(state, &page.anchors))
}

/// How far the section on screen scrolls to keep the paragraph it was
/// opened at on the first line: the line of its anchor among `anchors`
/// (the page's), 0 when not opened at an anchor of this section.
fn anchored_line(state: &ReaderState, anchors: &[(String, usize)]) -> usize {
    match &state.anchored {
        Some((section, name)) if *section == state.section => anchors
            .iter()
            .find(|(a, _)| a == name)
            .map_or(0, |&(_, line)| line),
        _ => 0,
    }
}

/// `s` as search compares it: lower case, compatibility characters folded
/// (the micro sign finds the Greek mu), one char for each char of `s`.
fn lowercase_chars(s: &str) -> Vec<char> {
    s.chars()
        .map(crate::text::compat_char)
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

/// The line with every match of `query` in `style`, and the one starting
/// at char `current` (if any) in `current_style`.
fn highlight(
    line: Line<'static>,
    query: &[char],
    style: Style,
    current: Option<(usize, Style)>,
) -> Line<'static> {
    let ranges = matches(&line_text(&line), query);
    if ranges.is_empty() {
        return line;
    }
    let style_at = |pos: usize| -> Option<Style> {
        let &(a, _) = ranges.iter().find(|&&(a, b)| pos >= a && pos < b)?;
        Some(match current {
            Some((c, cs)) if c == a => cs,
            _ => style,
        })
    };
    let mut out = Vec::new();
    let mut pos = 0;
    for span in line.spans {
        let mut buf = String::new();
        let mut buf_hit: Option<Style> = None;
        for c in span.content.chars() {
            let hit = style_at(pos);
            if hit != buf_hit && !buf.is_empty() {
                let st = buf_hit.map_or(span.style, |h| span.style.patch(h));
                out.push(Span::styled(std::mem::take(&mut buf), st));
            }
            buf_hit = hit;
            buf.push(c);
            pos += 1;
        }
        if !buf.is_empty() {
            let st = buf_hit.map_or(span.style, |h| span.style.patch(h));
            out.push(Span::styled(buf, st));
        }
    }
    Line::from(out)
}

/// Every match of `query` in the deck, in reading order: (section, line,
/// first char), as laid out at the app's size.
fn occurrences(app: &App, deck: &Deck, query: &str) -> Vec<(usize, usize, usize)> {
    let q = lowercase_chars(query);
    let width = text_area(app).width as usize;
    let mut out = Vec::new();
    for s in 0..pages(deck) {
        let p = page(app, deck, s, width, None);
        for (i, l) in p.lines.iter().take(p.text_lines).enumerate() {
            for (a, _) in matches(&line_text(l), &q) {
                out.push((s, i, a));
            }
        }
    }
    out
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
) -> Option<(usize, usize, usize)> {
    let hits = occurrences(app, deck, query);
    let here = match state.hit {
        Some(hit) if hit.0 == state.section => hit,
        _ => (state.section, state.scroll, 0),
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

/// Scrolls so that `line` is on screen (as little as needed).
fn reveal(state: &mut ReaderState, line: usize, height: usize, max: usize) {
    let height = height.max(1);
    if line < state.scroll {
        state.scroll = line;
    } else if line >= state.scroll + height {
        state.scroll = line + 1 - height;
    }
    state.scroll = state.scroll.min(max);
}

pub fn apply(app: &mut App, state: &mut ReaderState, action: Action) -> Nav {
    let Some(deck) = app.decks.get(state.deck) else {
        return Nav::Pop;
    };
    // The language or the size may have changed since the last key.
    let max = max_scroll(app, deck, state);
    state.scroll = state.scroll.min(max);
    let area = text_area(app);
    let height = area.height as usize;
    let page_len = height.saturating_sub(1).max(1);
    let n_sections = pages(deck);
    let links = page(app, deck, state.section, area.width as usize, None).links;
    let visible = |scroll: usize, l: &LinkAt| l.line >= scroll && l.line < scroll + height;

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
        Action::PageUp => state.scroll = state.scroll.saturating_sub(page_len),
        Action::PageDown => state.scroll = (state.scroll + page_len).min(max),
        Action::Top => state.scroll = 0,
        Action::Bottom => state.scroll = max,
        Action::PrevSection if state.section > 0 => go(state, state.section - 1, false),
        Action::NextSection if state.section + 1 < n_sections => {
            go(state, state.section + 1, false)
        }
        Action::NextLink | Action::PrevLink if !links.is_empty() => {
            let n = links.len();
            let next = match (state.link, action == Action::NextLink) {
                (Some(l), true) => (l + 1) % n,
                (Some(l), false) => (l + n - 1) % n,
                // Nothing chosen yet: start from what is on screen.
                (None, true) => links
                    .iter()
                    .position(|l| visible(state.scroll, l))
                    .unwrap_or(0),
                (None, false) => links
                    .iter()
                    .rposition(|l| visible(state.scroll, l))
                    .unwrap_or(n - 1),
            };
            state.link = Some(next);
            reveal(state, links[next].line, height, max);
        }
        // On a derivation's page Enter shows the next step, scrolled into
        // view.
        Action::FollowLink if derivation_at(deck, state.section).is_some() => {
            let n = derivation_at(deck, state.section).map_or(0, |d| d.steps.len());
            state.steps = (state.steps.max(1) + 1).min(n.max(1));
            let max = max_scroll(app, deck, state);
            state.scroll = max;
        }
        // Enter opens only a link the learner sees chosen; with none
        // chosen it chooses the first on screen.
        Action::FollowLink => match state.link.and_then(|i| links.get(i)) {
            Some(l) => {
                if let Some(to) = deck.sections.iter().position(|s| s.id == l.target) {
                    go(state, to, true);
                }
            }
            None if !links.is_empty() => {
                return apply(app, state, Action::NextLink);
            }
            None => {}
        },
        Action::EditItem => {
            let target = edit_target(app, deck, state);
            app.request_edit(state.deck, target);
        }
        Action::StartSearch => state.search = Some(String::new()),
        Action::OpenFormulas => {
            return Nav::Push(super::Screen::Formulas(super::formulas::FormulaSheet::new(
                state.deck,
            )));
        }
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
    // A chosen link scrolled out of sight is no longer chosen: Enter must
    // never open a link that is not on screen.
    if let Some(i) = state.link
        && links.get(i).is_none_or(|l| !visible(state.scroll, l))
        && matches!(
            action,
            Action::Up
                | Action::Down
                | Action::PageUp
                | Action::PageDown
                | Action::Top
                | Action::Bottom
                | Action::Resize(..)
                | Action::ToggleLanguage
        )
    {
        state.link = None;
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
    state.steps = 1;
}

fn jump(app: &mut App, state: &mut ReaderState, query: &str, forward: bool, from_here: bool) {
    let Some(deck) = app.decks.get(state.deck) else {
        return;
    };
    match find(app, deck, state, query, forward, from_here) {
        Some((section, line, col)) => {
            state.section = section;
            state.hit = Some((section, line, col));
            state.link = None;
            // A match in a derivation's step: every step shown, so it is.
            state.steps = usize::MAX;
            let max = max_scroll(app, deck, state);
            state.scroll = line.min(max);
            app.status = None;
        }
        None => {
            state.hit = None;
            let msg = format!("{}: {query}", app.tr(Msg::NoMatch));
            app.info(msg);
        }
    }
}

/// "match 3/9" for the current search, or "0/9" before a jump.
fn match_count(app: &App, deck: &Deck, state: &ReaderState, query: &str) -> String {
    let hits = occurrences(app, deck, query);
    let at = state
        .hit
        .and_then(|h| hits.iter().position(|&x| x == h))
        .map_or(0, |i| i + 1);
    format!("{} {at}/{}", words::MATCH.get(&app.lang), hits.len())
}

pub fn draw(frame: &mut Frame, area: Rect, app: &App, state: &ReaderState) {
    let t = &app.theme;
    let Some(deck) = app.decks.get(state.deck) else {
        return;
    };
    if pages(deck) == 0 {
        frame.render_widget(Paragraph::new(app.tr(Msg::NoSections)), area);
        return;
    }
    let (list_area, text_area, status_area) = areas(area);

    // Titles that do not fit end with "…" (one column goes to the border).
    let title_w = usize::from(list_area.width.saturating_sub(1));
    let sections = deck
        .sections
        .iter()
        .map(|s| crate::text::render(s.title.get(&app.lang)));
    let derivations = deck.derivations.iter().map(|d| {
        format!(
            "{DERIVATION_MARK}{}",
            crate::text::render(d.title.get(&app.lang))
        )
    });
    let items = sections
        .chain(derivations)
        .map(|title| ListItem::new(Line::from(ellipsize(&title, title_w))));
    let list = List::new(items)
        .block(
            Block::default()
                .borders(Borders::RIGHT)
                .border_style(t.border()),
        )
        .highlight_style(t.selected());
    let mut ls = ListState::default().with_selected(Some(state.section));
    frame.render_stateful_widget(list, list_area, &mut ls);

    let Page {
        lines,
        links,
        text_lines,
        anchors,
    } = page_shown(app, deck, state, text_area.width as usize);
    let total = lines.len();
    let height = text_area.height as usize;
    let max = total
        .saturating_sub(height)
        .max(anchored_line(state, &anchors));
    let scroll = state.scroll.min(max);
    let query = state.query.as_deref().map(lowercase_chars);
    let current = state
        .hit
        .filter(|h| h.0 == state.section)
        .map(|(_, line, col)| (line, col));
    let current_style = t.selected().add_modifier(ratatui::style::Modifier::BOLD);
    let shown: Vec<Line> = lines
        .into_iter()
        .enumerate()
        .skip(scroll)
        .take(height)
        .map(|(i, l)| match &query {
            Some(q) if i < text_lines => {
                let cur = current.filter(|c| c.0 == i).map(|c| (c.1, current_style));
                highlight(l, q, t.highlight(), cur)
            }
            _ => l,
        })
        .collect();
    frame.render_widget(Paragraph::new(shown), text_area);
    // The current match is also marked in the margin, for `NO_COLOR`.
    if let Some((line, _)) = current
        && query.is_some()
        && line >= scroll
        && line < scroll + height
        && text_area.x > 0
    {
        let y = text_area.y + (line - scroll) as u16;
        let mark = Rect::new(text_area.x - 1, y, 1, 1);
        frame.render_widget(Paragraph::new(Span::styled("›", t.key())), mark);
    }

    let status = if let Some(input) = &state.search {
        Line::from(vec![
            Span::styled(format!(" /{input}▏"), t.strong()),
            Span::styled(format!("  {}", app.tr(Msg::Search)), t.dim()),
        ])
    } else {
        status_line(
            app,
            deck,
            state,
            &links,
            (scroll, height, total),
            status_area.width,
        )
    };
    frame.render_widget(Paragraph::new(status), status_area);
}

/// The status line under the text: the chosen link (or how many there
/// are), the search's match count, the lines shown and the section number.
/// When it does not all fit, the position loses its words first, then the
/// "Enter opens" hint, and only then is the link's title cut with "…".
fn status_line(
    app: &App,
    deck: &Deck,
    state: &ReaderState,
    links: &[LinkAt],
    (scroll, height, total): (usize, usize, usize),
    width: u16,
) -> Line<'static> {
    let t = &app.theme;
    let lang = app.lang.as_str();
    let width = usize::from(width);
    let position = |words_too: bool| {
        let mut right = Vec::new();
        if let Some(q) = &state.query {
            right.push(match_count(app, deck, state, q));
        }
        if total > height {
            let last = (scroll + height).min(total);
            let lines = if words_too {
                words::LINES.get(lang)
            } else {
                ""
            };
            let text = format!("{lines} {}–{last}/{total}", scroll + 1);
            right.push(text.trim().to_string());
        }
        // The list beside shows which section this is.
        if words_too {
            right.push(format!("§{}/{}", state.section + 1, pages(deck)));
        }
        format!(" {} ", right.join(" · "))
    };
    let (full, short) = (position(true), position(false));

    // The left part as (text, style) pieces, most wanted first.
    let (pieces, cut): (Vec<(String, Style)>, usize) =
        match state.link.and_then(|i| links.get(i).map(|l| (i, l))) {
            Some((i, l)) => {
                let title = deck
                    .section(&l.target)
                    .map(|s| crate::text::render(s.title.get(lang)))
                    .unwrap_or_else(|| l.target.clone());
                (
                    vec![
                        (format!(" {}/{} → ", i + 1, links.len()), t.key()),
                        (title, t.selected()),
                        (format!("  {}", words::ENTER_OPENS.get(lang)), t.dim()),
                    ],
                    1,
                )
            }
            None if !links.is_empty() => (
                vec![(
                    format!(
                        " {} · {}",
                        crate::tui::i18n::count(lang, links.len(), crate::tui::i18n::Noun::Link),
                        words::TAB_TO_CHOOSE.get(lang)
                    ),
                    t.dim(),
                )],
                0,
            ),
            None => (vec![(" ".to_string(), t.dim())], 0),
        };
    let len = |ps: &[(String, Style)]| ps.iter().map(|(s, _)| columns(s)).sum::<usize>();
    let mut left = pieces.clone();
    let mut right = full.clone();
    if len(&left) + columns(&right) > width {
        right = short;
    }
    if len(&left) + columns(&right) > width && left.len() > 2 {
        left.pop();
    }
    if len(&left) + columns(&right) > width {
        let others: usize = left
            .iter()
            .enumerate()
            .filter(|(i, _)| *i != cut)
            .map(|(_, (s, _))| columns(s))
            .sum();
        let room = width.saturating_sub(others + columns(&right));
        if let Some((s, _)) = left.get_mut(cut) {
            *s = ellipsize(s, room);
        }
    }
    let mut spans: Vec<Span> = left
        .into_iter()
        .map(|(s, st)| Span::styled(s, st))
        .collect();
    let used: usize = spans.iter().map(|s| columns(&s.content)).sum();
    spans.push(Span::raw(
        " ".repeat(width.saturating_sub(used + columns(&right))),
    ));
    spans.push(Span::styled(right, t.dim()));
    Line::from(spans)
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
            None,
        );
        let texts: Vec<&str> = out.spans.iter().map(|s| s.content.as_ref()).collect();
        assert_eq!(texts, ["tennis ", "ra", "cket", " theorem"]);
        assert_eq!(line_text(&out), "tennis racket theorem");
    }
}
