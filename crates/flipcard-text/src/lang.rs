//! Texts written in several languages.

use std::collections::BTreeMap;

/// A BCP 47 language tag as declared by the deck (`en`, `hi-Latn`).
pub type Lang = String;

/// A text given in every declared language of its deck.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Text(pub BTreeMap<Lang, String>);

impl Text {
    /// The text in `lang`, falling back to any language present (a validated
    /// deck has every language, so the fallback only matters for a language
    /// the deck does not declare).
    pub fn get(&self, lang: &str) -> &str {
        self.0
            .get(lang)
            .or_else(|| self.0.values().next())
            .map(String::as_str)
            .unwrap_or("")
    }
}
