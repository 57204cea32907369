//! The formula sheet (`F` in the reader): every formula of a deck's cards
//! (fronts and backs) and sections on one scrollable page, in the language
//! on screen. Each formula is listed once, under the first place that
//! writes it (the cards in deck order, then the sections in reading
//! order); formulas are wrapped whole, breaking only where mathematics
//! breaks (`wrap`, as the reader's formulas).

use std::cell::RefCell;
use std::rc::Rc;

use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::Style;
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;

use crate::deck::{CardKind, Deck};
use crate::text::markup::{self, Block as MBlock, Style as MStyle};
use crate::tui::action::Action;
use crate::tui::app::App;
use crate::tui::i18n::{Msg, Words, formulas as words};
use crate::tui::keymap::{Binding, Context};
use crate::tui::layout::{MEASURE, body_rect};
use crate::tui::wrap::{Run, columns, math_runs, wrap};

use super::Nav;
use crossterm::event::KeyCode::{Char, Esc};

pub const KEYS: &[Binding] = &[
    Binding::SCROLL[0],
    Binding::SCROLL[1],
    Binding::SCROLL[2],
    Binding::new(
        "Esc F q",
        Words("back to the reader", "reader pe wapas"),
        &[
            (Esc, Action::Back),
            (Char('F'), Action::Back),
            (Char('q'), Action::Back),
        ],
    ),
];

/// The sheet of one deck, scrolled to `scroll` (its first line shown).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FormulaSheet {
    pub deck: usize,
    pub scroll: usize,
    /// The sheet as last laid out: every key and every frame needs it, and
    /// it changes only with the language and the width.
    laid_out: RefCell<Option<LaidOut>>,
}

#[derive(Debug, Clone, PartialEq)]
struct LaidOut {
    lang: String,
    width: usize,
    lines: Rc<Vec<Line<'static>>>,
    count: usize,
}

impl FormulaSheet {
    /// The sheet of deck `deck`, at its top.
    pub fn new(deck: usize) -> FormulaSheet {
        FormulaSheet {
            deck,
            ..FormulaSheet::default()
        }
    }

    /// [`lines`] at `width` in the app's language, laid out again only
    /// when either changed.
    fn lines(&self, app: &App, deck: &Deck, width: usize) -> (Rc<Vec<Line<'static>>>, usize) {
        let mut cache = self.laid_out.borrow_mut();
        match &*cache {
            Some(l) if l.lang == app.lang && l.width == width => (l.lines.clone(), l.count),
            _ => {
                let (lines, count) = lines(app, deck, width);
                let lines = Rc::new(lines);
                *cache = Some(LaidOut {
                    lang: app.lang.clone(),
                    width,
                    lines: lines.clone(),
                    count,
                });
                (lines, count)
            }
        }
    }
}

/// Where formulas are written, and the formulas first written there.
#[derive(Debug, Clone, PartialEq)]
pub struct Group {
    pub from: Source,
    /// The card's front or the section's title, as written (may hold math).
    pub heading: String,
    /// Each formula rendered (a display formula's rows on lines of their
    /// own).
    pub formulas: Vec<String>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Source {
    Card,
    Section,
}

/// The formulas of `text` (no markup: a card's), rendered.
fn card_formulas(text: &str) -> Vec<String> {
    crate::text::render_pieces(text)
        .into_iter()
        .filter(|(_, math)| *math)
        .map(|(f, _)| f.trim().to_string())
        .collect()
}

/// The formulas of a section's body, rendered: its display formulas and the
/// inline ones of its paragraphs and items (code is no formula).
fn body_formulas(body: &str) -> Vec<String> {
    let mut out = Vec::new();
    for block in markup::parse(body) {
        match block {
            MBlock::Display(math) => out.push(math.trim().to_string()),
            MBlock::Paragraph(spans) | MBlock::Item(spans) => {
                // Each math span is a formula (the markup joins two only
                // when nothing stands between them).
                out.extend(
                    spans
                        .into_iter()
                        .filter(|s| s.style == MStyle::Math)
                        .map(|s| s.text.trim().to_string()),
                );
            }
        }
    }
    out
}

/// What a formula is compared as when the sheet leaves out repeats: its
/// symbols, whatever the spacing (`\,` or none between factors).
fn key(formula: &str) -> String {
    formula.split_whitespace().collect()
}

/// A formula that relates or computes something (`T₀ = 2π√(L/g)`,
/// `ζ < 1`, `e^{-t/τ}`), not a bare symbol a sentence names (`L`, `θ₀`,
/// `K(m)`), which would bury the sheet's formulas among its letters.
fn states_something(formula: &str) -> bool {
    const MARKS: [&str; 24] = [
        "=", "<", ">", "+", "-", "/", "^", "\\frac", "\\sqrt", "\\approx", "\\propto", "\\le",
        "\\ge", "\\sim", "\\cdot", "\\times", "\\int", "\\sum", "\\ll", "\\gg", "\\neq", "\\to",
        "\\equiv", "\\pm",
    ];
    !formula.is_empty() && MARKS.iter().any(|m| formula.contains(m))
}

/// The sheet's groups in `lang`: each place with the formulas it writes
/// first; places without a new formula are left out.
pub fn groups(deck: &Deck, lang: &str) -> Vec<Group> {
    let mut seen = std::collections::HashSet::new();
    let mut out = Vec::new();
    let mut add = |from: Source, heading: &str, formulas: Vec<String>| {
        let new: Vec<String> = formulas
            .into_iter()
            .filter(|f| states_something(f) && seen.insert(key(f)))
            .collect();
        if !new.is_empty() {
            out.push(Group {
                from,
                heading: heading.to_string(),
                formulas: new,
            });
        }
    };
    for card in &deck.cards {
        let front = card.front.get(lang);
        let front = if card.kind == CardKind::Cloze {
            crate::deck::cloze::revealed(front)
        } else {
            front.to_string()
        };
        let mut formulas = card_formulas(&front);
        formulas.extend(card_formulas(card.back.get(lang)));
        add(Source::Card, &front, formulas);
    }
    for section in &deck.sections {
        add(
            Source::Section,
            section.title.get(lang),
            body_formulas(section.body.get(lang)),
        );
    }
    out
}

/// The text's area and the status line's inside the screen body.
fn areas(body: Rect) -> (Rect, Rect) {
    let [text, status] = Layout::vertical([Constraint::Fill(1), Constraint::Length(1)]).areas(body);
    // A column of margin, and lines no longer than the reader's.
    let text = Rect {
        x: text.x.saturating_add(1).min(text.right()),
        width: text.width.saturating_sub(1).min(MEASURE),
        ..text
    };
    (text, status)
}

/// The sheet laid out at `width`, and how many formulas it lists.
pub fn lines(app: &App, deck: &Deck, width: usize) -> (Vec<Line<'static>>, usize) {
    let t = &app.theme;
    let lang = app.lang.as_str();
    let groups = groups(deck, lang);
    if groups.is_empty() {
        return (wrap_text(words::NONE.get(lang), t.dim(), width), 0);
    }
    let mut lines = Vec::new();
    let mut count = 0;
    for g in &groups {
        if !lines.is_empty() {
            lines.push(Line::default());
        }
        let label = match g.from {
            Source::Card => words::CARD.get(lang),
            Source::Section => words::SECTION.get(lang),
        };
        lines.extend(wrap(
            &math_runs(&g.heading.replace('\n', " "), t.heading()),
            width,
            Run::new(format!("{label} · "), t.dim()),
            Run::new("  ", t.heading()),
        ));
        for f in &g.formulas {
            count += 1;
            for row in f.lines() {
                lines.extend(formula_lines(row, t.math(), width));
            }
        }
    }
    (lines, count)
}

/// One row of a formula at `width`, indented, whole on a line when it
/// fits and else broken where mathematics breaks (`wrap` with the formula
/// glued, as the reader's display formulas).
pub fn formula_lines(row: &str, style: Style, width: usize) -> Vec<Line<'static>> {
    wrap(
        &[Run::new(row.trim(), style).glued()],
        width,
        Run::new("  ", style),
        Run::new("    ", style),
    )
}

/// The width of the sheet's text on a terminal of `size`.
pub fn text_width(size: (u16, u16)) -> usize {
    usize::from(areas(body_rect(size)).0.width)
}

fn wrap_text(text: &str, style: Style, width: usize) -> Vec<Line<'static>> {
    crate::tui::wrap::wrap_plain(text, style, width)
}

/// The text area at the app's terminal size.
fn text_area(app: &App) -> Rect {
    areas(body_rect(app.size)).0
}

fn max_scroll(app: &App, deck: &Deck, state: &FormulaSheet) -> usize {
    let area = text_area(app);
    let (lines, _) = state.lines(app, deck, area.width as usize);
    lines.len().saturating_sub(area.height as usize)
}

impl super::View for FormulaSheet {
    fn context(&self) -> Context {
        Context::Formulas
    }

    fn apply(&mut self, app: &mut App, action: Action) -> Nav {
        let Some(deck) = app.decks.get(self.deck) else {
            return Nav::Pop;
        };
        // The language or the size may have changed since the last key.
        let max = max_scroll(app, deck, self);
        self.scroll = self.scroll.min(max);
        let page = (text_area(app).height as usize).saturating_sub(1).max(1);
        match action {
            Action::Up => self.scroll = self.scroll.saturating_sub(1),
            Action::Down => self.scroll = (self.scroll + 1).min(max),
            Action::PageUp => self.scroll = self.scroll.saturating_sub(page),
            Action::PageDown => self.scroll = (self.scroll + page).min(max),
            Action::Top => self.scroll = 0,
            Action::Bottom => self.scroll = max,
            Action::Back => return Nav::Pop,
            _ => {}
        }
        Nav::Stay
    }

    fn draw(&self, frame: &mut Frame, area: Rect, app: &App) {
        draw(frame, area, app, self)
    }

    fn name(&self) -> Msg {
        Msg::FormulaSheet
    }

    fn deck(&self) -> Option<usize> {
        Some(self.deck)
    }
}

pub fn draw(frame: &mut Frame, area: Rect, app: &App, state: &FormulaSheet) {
    let t = &app.theme;
    let Some(deck) = app.decks.get(state.deck) else {
        return;
    };
    let lang = app.lang.as_str();
    let (text_area, status_area) = areas(area);
    let (lines, count) = state.lines(app, deck, text_area.width as usize);
    let total = lines.len();
    let height = text_area.height as usize;
    let scroll = state.scroll.min(total.saturating_sub(height));
    let shown: Vec<Line> = lines.iter().skip(scroll).take(height).cloned().collect();
    frame.render_widget(Paragraph::new(shown), text_area);

    let counted = format!(" {count} {}", words::FORMULAS.get(lang));
    let position = if total > height {
        format!("{}–{}/{total} ", scroll + 1, (scroll + height).min(total))
    } else {
        String::new()
    };
    let width = usize::from(status_area.width);
    let gap = width.saturating_sub(columns(&counted) + columns(&position));
    let status = Line::from(vec![
        Span::styled(counted, t.dim()),
        Span::raw(" ".repeat(gap)),
        Span::styled(position, t.dim()),
    ]);
    frame.render_widget(Paragraph::new(status), status_area);
}

#[cfg(test)]
mod states {
    use super::states_something;

    #[test]
    fn a_bare_symbol_is_no_formula_of_the_sheet() {
        for bare in ["L", "\\theta_0", "K(m)", "\\dot\\theta", "\\vec L", ""] {
            assert!(!states_something(bare), "{bare}");
        }
        for formula in [
            "T_0 = 2\\pi\\sqrt{L/g}",
            "\\zeta < 1",
            "e^{-t/\\tau}",
            "Q \\approx 10",
        ] {
            assert!(states_something(formula), "{formula}");
        }
    }
}
