//! The frame's layout, which the keys and the screens need before anything
//! is drawn: the smallest terminal the screens are laid out for, and the
//! screen's body between the header and the footer. [`super::view`] draws
//! the frame this way.

use ratatui::layout::Rect;

/// The smallest terminal the screens are laid out for.
pub const MIN_WIDTH: u16 = 40;
pub const MIN_HEIGHT: u16 = 12;

/// The widest a text to read runs, in columns (the reader's sections, the
/// formula sheet): longer lines are hard to follow from one end to the
/// next on a wide terminal.
pub const MEASURE: u16 = 80;

/// The screen body (between header and footer) for a terminal size; the
/// same split `view::draw` makes, so actions can reason about what is
/// visible.
pub fn body_rect(size: (u16, u16)) -> Rect {
    let (w, h) = size;
    Rect::new(0, 1.min(h), w, h.saturating_sub(2))
}
