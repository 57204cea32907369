//! Colours and emphasis. Only the 16 named ANSI colours are used, so every
//! terminal shows them; `NO_COLOR` keeps bold and reverse video (needed to
//! see the selection) and drops every colour.

use ratatui::style::{Color, Modifier, Style};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Theme {
    pub color: bool,
}

impl Theme {
    /// Colours unless `NO_COLOR` is set to a non-empty value (no-color.org).
    pub fn from_env() -> Theme {
        Theme::from_no_color(std::env::var_os("NO_COLOR").as_deref())
    }

    /// The theme for a value of `NO_COLOR` (`None`: unset).
    pub fn from_no_color(value: Option<&std::ffi::OsStr>) -> Theme {
        let no_color = value.is_some_and(|v| !v.is_empty());
        Theme { color: !no_color }
    }

    pub const COLOR: Theme = Theme { color: true };
    pub const PLAIN: Theme = Theme { color: false };

    fn fg(&self, color: Color) -> Style {
        if self.color {
            Style::new().fg(color)
        } else {
            Style::new()
        }
    }

    pub fn text(&self) -> Style {
        Style::new()
    }
    /// Hints and secondary text. Palette grey 8 (`DarkGray`) is near
    /// invisible on many dark themes; grey 7 stays readable while still
    /// quieter than the text.
    pub fn dim(&self) -> Style {
        if self.color {
            Style::new().fg(Color::Gray)
        } else {
            Style::new()
        }
    }
    pub fn title(&self) -> Style {
        self.fg(Color::Cyan).add_modifier(Modifier::BOLD)
    }
    pub fn heading(&self) -> Style {
        self.fg(Color::Yellow).add_modifier(Modifier::BOLD)
    }
    pub fn key(&self) -> Style {
        self.fg(Color::Cyan).add_modifier(Modifier::BOLD)
    }
    pub fn selected(&self) -> Style {
        Style::new().add_modifier(Modifier::REVERSED)
    }
    pub fn emphasis(&self) -> Style {
        Style::new().add_modifier(Modifier::ITALIC)
    }
    pub fn strong(&self) -> Style {
        Style::new().add_modifier(Modifier::BOLD)
    }
    pub fn math(&self) -> Style {
        self.fg(Color::LightMagenta)
    }
    /// A command or name written as code in a section (`` `flipcard sim` ``).
    pub fn code(&self) -> Style {
        self.fg(Color::Cyan)
    }
    pub fn good(&self) -> Style {
        self.fg(Color::Green).add_modifier(Modifier::BOLD)
    }
    pub fn bad(&self) -> Style {
        self.fg(Color::Red).add_modifier(Modifier::BOLD)
    }
    pub fn warn(&self) -> Style {
        self.fg(Color::Yellow)
    }
    /// Links: dark blue (palette 4) is hard to read on black, the light
    /// one (12) is not; underlined so they show without colour too.
    pub fn link(&self) -> Style {
        self.fg(Color::LightBlue).add_modifier(Modifier::UNDERLINED)
    }
    pub fn highlight(&self) -> Style {
        if self.color {
            Style::new().fg(Color::Black).bg(Color::Yellow)
        } else {
            Style::new().add_modifier(Modifier::REVERSED)
        }
    }
    pub fn border(&self) -> Style {
        self.dim()
    }
    /// Line colour of the plots: one per body axis.
    pub fn axis(&self, i: usize) -> Color {
        if self.color {
            [Color::LightRed, Color::LightGreen, Color::LightBlue][i % 3]
        } else {
            Color::Reset
        }
    }
    /// A plain colour for canvas shapes (Reset when colours are off).
    pub fn plot(&self, color: Color) -> Color {
        if self.color { color } else { Color::Reset }
    }
    /// Rating buttons: Again red, Hard yellow, Good green, Easy blue.
    pub fn rating(&self, n: usize) -> Style {
        let c = [Color::Red, Color::Yellow, Color::Green, Color::Blue][n.min(3)];
        self.fg(c).add_modifier(Modifier::BOLD)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ffi::OsStr;

    #[test]
    fn hints_and_links_avoid_the_colours_dark_themes_hide() {
        let t = Theme::COLOR;
        for style in [t.dim(), t.link(), t.border(), t.key()] {
            assert!(
                !matches!(style.fg, Some(Color::DarkGray | Color::Blue | Color::Black)),
                "{style:?}"
            );
        }
    }

    #[test]
    fn no_color_set_to_anything_but_empty_turns_colours_off() {
        assert_eq!(Theme::from_no_color(None), Theme::COLOR);
        assert_eq!(Theme::from_no_color(Some(OsStr::new(""))), Theme::COLOR);
        assert_eq!(Theme::from_no_color(Some(OsStr::new("1"))), Theme::PLAIN);
    }
}
