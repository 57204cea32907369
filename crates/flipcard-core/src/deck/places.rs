//! Where a prompt's answer and a system scene's expressions sit in its deck
//! file, for checks made after loading (the simulation's verdict on the
//! author's answer, a scene that does not run to its end) to point at the
//! line an author has to change.

use std::collections::HashMap;
use std::path::Path;

use super::diag::LineIndex;
use super::raw::{self, RawAnswer};
use super::report::FileReport;

/// A position in a file: 1-based line and character column, and how many
/// characters to underline.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Place {
    pub line: usize,
    pub col: usize,
    pub width: usize,
}

/// Where one prompt's answer is written.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub(crate) struct AnswerPlaces {
    /// The `expected` value.
    pub expected: Option<Place>,
    /// Each choice's `when`, in the prompt's order.
    pub when: Vec<Option<Place>>,
    /// Each slip's `value` (a number answer), in the prompt's order.
    pub slips: Vec<Option<Place>>,
    /// The prompt's `vary`, when it varies: where a variant that its run
    /// cannot decide is reported.
    pub vary: Option<Place>,
}

/// The deck file `source` read raw; `None` when it does not parse (the
/// loader reports it).
fn read(path: &Path, source: &str) -> Option<raw::RawDeckFile> {
    let mut rep = FileReport::new(path, source);
    super::chunked::read_deck(&mut rep, source)
}

/// Where `span` of `source` is.
fn place(index: &LineIndex, source: &str, span: &std::ops::Range<usize>) -> Place {
    let (line, col) = index.position(source, span.start);
    Place {
        line,
        col,
        width: index.width(source, span),
    }
}

/// The answer places of every prompt of the deck file `source`, by prompt
/// id. A file that does not parse has none (the loader reports it).
pub(crate) fn answer_places(path: &Path, source: &str) -> HashMap<String, AnswerPlaces> {
    let Some(file) = read(path, source) else {
        return HashMap::new();
    };
    let index = LineIndex::new(source);
    let place = |span: &std::ops::Range<usize>| place(&index, source, span);
    file.prompts
        .iter()
        .filter_map(|p| {
            let id = p.id.as_ref()?.value.clone();
            let places = match p.answer.as_ref()? {
                RawAnswer::Choice {
                    expected, choices, ..
                } => AnswerPlaces {
                    expected: expected.as_ref().map(|e| place(&e.span)),
                    when: choices
                        .as_ref()
                        .map(|l| {
                            l.items
                                .iter()
                                .map(|c| c.when.as_ref().map(|w| place(&w.span)))
                                .collect()
                        })
                        .unwrap_or_default(),
                    slips: Vec::new(),
                    vary: None,
                },
                RawAnswer::Formula(f) => AnswerPlaces {
                    expected: f.expected.as_ref().map(|e| place(&e.span)),
                    when: Vec::new(),
                    slips: Vec::new(),
                    vary: None,
                },
                RawAnswer::Number {
                    expected,
                    computed,
                    slips,
                    ..
                } => AnswerPlaces {
                    expected: expected
                        .as_ref()
                        .map(|e| place(&e.span))
                        .or_else(|| computed.as_ref().map(|e| place(&e.span))),
                    vary: None,
                    when: Vec::new(),
                    slips: slips
                        .as_ref()
                        .map(|l| {
                            l.items
                                .iter()
                                .map(|s| s.value.as_ref().map(|v| place(&v.span)))
                                .collect()
                        })
                        .unwrap_or_default(),
                },
            };
            let places = AnswerPlaces {
                vary: p.vary.as_ref().map(|v| place(&v.span)),
                ..places
            };
            Some((id, places))
        })
        .collect()
}

/// Where a system scene is written: its `id`, `duration`, each equation,
/// each observable's expression and each sketch expression (in order).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub(crate) struct ScenePlaces {
    pub id: Option<Place>,
    pub duration: Option<Place>,
    pub equations: Vec<Place>,
    pub observables: Vec<Place>,
    pub marks: Vec<Place>,
}

/// The places of every system scene of the deck file `source`, by scene id.
pub(crate) fn scene_places(path: &Path, source: &str) -> HashMap<String, ScenePlaces> {
    let Some(file) = read(path, source) else {
        return HashMap::new();
    };
    let index = LineIndex::new(source);
    let place = |span: &std::ops::Range<usize>| place(&index, source, span);
    file.scenes
        .iter()
        .filter_map(|s| {
            let sys = s.system.as_ref()?;
            let id = s.id.as_ref()?;
            let places = ScenePlaces {
                id: Some(place(&id.span)),
                duration: s.duration.as_ref().map(|d| place(&d.span)),
                equations: sys
                    .equations
                    .as_ref()
                    .map(|l| l.items.iter().map(|e| place(&e.span)).collect())
                    .unwrap_or_default(),
                observables: sys
                    .observables
                    .as_ref()
                    .map(|o| o.entries.iter().map(|e| place(&e.value.span)).collect())
                    .unwrap_or_default(),
                marks: sys
                    .sketch
                    .as_ref()
                    .map(|l| {
                        l.items
                            .iter()
                            .flat_map(|m| &m.exprs.items)
                            .map(|e| place(&e.span))
                            .collect()
                    })
                    .unwrap_or_default(),
            };
            Some((id.value.clone(), places))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn places_point_at_the_expected_value_and_each_condition() {
        let src = "[[prompt]]\nid = \"p\"\n[prompt.answer]\nkind = \"choice\"\n\
                   expected = \"b\"\nchoices = [\n  { id = \"a\", label = 'A', when = \"flips == 0\" },\n\
                   \x20 { id = \"b\", label = 'B', when = \"flips > 0\" },\n]\n";
        let places = answer_places(Path::new("x.toml"), src);
        let p = &places["p"];
        assert_eq!(p.expected.map(|e| (e.line, e.col)), Some((5, 12)));
        assert_eq!(p.when.len(), 2);
        assert_eq!(p.when[1].map(|w| w.line), Some(8));
    }
}

/// What kind of table an item of a deck file is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ItemTable {
    Card,
    Prompt,
    Derivation,
}

/// The line (1-based) of the `id` of the card, prompt or derivation `id`
/// in the deck file `source`: where an editor opens it. `None` when the
/// file does not parse or has no such item.
pub fn item_line(path: &Path, source: &str, table: ItemTable, id: &str) -> Option<usize> {
    let file = read(path, source)?;
    let ids: Vec<&super::raw::Str> = match table {
        ItemTable::Card => file.cards.iter().filter_map(|c| c.id.as_ref()).collect(),
        ItemTable::Prompt => file.prompts.iter().filter_map(|p| p.id.as_ref()).collect(),
        ItemTable::Derivation => file
            .derivations
            .iter()
            .filter_map(|d| d.id.as_ref())
            .collect(),
    };
    let found = ids.into_iter().find(|s| s.value == id)?;
    let index = LineIndex::new(source);
    Some(index.position(source, found.span.start).0)
}

/// The line (1-based) of the `id` of section `id` in the content file
/// `source`: where an editor opens it. `None` when the file does not parse
/// or has no such section.
pub fn section_line(path: &Path, source: &str, id: &str) -> Option<usize> {
    let mut rep = FileReport::new(path, source);
    let (root, span) = super::syntax::parse(&mut rep, source)?;
    let file = raw::read_content_file(&mut rep, &root, span);
    let found = file
        .sections
        .iter()
        .filter_map(|s| s.id.as_ref())
        .find(|s| s.value == id)?;
    let index = LineIndex::new(source);
    Some(index.position(source, found.span.start).0)
}

#[cfg(test)]
mod item_line_tests {
    use super::*;

    #[test]
    fn an_items_line_is_the_line_of_its_id() {
        let src = "[deck]\nid = \"d\"\ntitle.en = 'D'\nlanguages = [\"en\"]\n\n[[card]]\nid = \"a\"\nfront.en = 'x'\nback.en = 'y'\n\n[[card]]\n\nid = \"b\"\nfront.en = 'x'\nback.en = 'y'\n";
        let p = Path::new("d.toml");
        assert_eq!(item_line(p, src, ItemTable::Card, "a"), Some(7));
        assert_eq!(item_line(p, src, ItemTable::Card, "b"), Some(13));
        assert_eq!(item_line(p, src, ItemTable::Card, "c"), None);
        assert_eq!(item_line(p, src, ItemTable::Prompt, "a"), None);
        assert_eq!(item_line(p, "[[card", ItemTable::Card, "a"), None);
    }

    #[test]
    fn a_sections_line_is_the_line_of_its_id() {
        let src = "# notes\n[[section]]\nid = \"a\"\ntitle = 'A'\nbody = '''x'''\n\n[[section]]\n\nid = \"b\"\ntitle = 'B'\nbody = 'y'\n";
        let p = Path::new("en.toml");
        assert_eq!(section_line(p, src, "a"), Some(3));
        assert_eq!(section_line(p, src, "b"), Some(9));
        assert_eq!(section_line(p, src, "c"), None);
        assert_eq!(section_line(p, "[[section", "a"), None);
        assert_eq!(section_line(p, "", "a"), None);
    }
}

#[cfg(test)]
mod item_line_props {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// Any text: an answer or none, never a panic, and a line of the
        /// file when there is one.
        #[test]
        fn any_text_gives_a_line_of_it_or_none(text in "\\PC{0,400}", id in "[a-z]{1,6}") {
            if let Some(line) = item_line(Path::new("x.toml"), &text, ItemTable::Card, &id) {
                prop_assert!(line >= 1 && line <= text.lines().count().max(1));
            }
        }

        /// Cards separated by any number of blank lines and comments: each
        /// id's line is the line its `id = …` is written on.
        #[test]
        fn each_cards_line_is_where_its_id_is_written(gaps in proptest::collection::vec((0usize..4, any::<bool>()), 1..8)) {
            let mut text = String::from("[deck]\nid = \"d\"\ntitle.en = 'D'\nlanguages = [\"en\"]\n");
            let mut want = Vec::new();
            for (i, (blank, comment)) in gaps.iter().enumerate() {
                text.push_str("\n[[card]]\n");
                for _ in 0..*blank {
                    text.push('\n');
                }
                if *comment {
                    text.push_str("# a comment\n");
                }
                want.push(text.lines().count() + 1);
                text.push_str(&format!("id = \"c{i}\"\nfront.en = 'x'\nback.en = 'y'\n"));
            }
            for (i, line) in want.iter().enumerate() {
                let id = format!("c{i}");
                prop_assert_eq!(item_line(Path::new("d.toml"), &text, ItemTable::Card, &id), Some(*line));
            }
        }

        /// Any text as a content file: a line of it or none, never a panic.
        #[test]
        fn any_content_text_gives_a_line_of_it_or_none(text in "\\PC{0,400}", id in "[a-z]{1,6}") {
            if let Some(line) = section_line(Path::new("en.toml"), &text, &id) {
                prop_assert!(line >= 1 && line <= text.lines().count().max(1));
            }
        }

        /// Sections separated by blank lines and comments: each id's line
        /// is the line its `id = …` is written on.
        #[test]
        fn each_sections_line_is_where_its_id_is_written(gaps in proptest::collection::vec((0usize..4, any::<bool>()), 1..8)) {
            let mut text = String::new();
            let mut want = Vec::new();
            for (i, (blank, comment)) in gaps.iter().enumerate() {
                text.push_str("\n[[section]]\n");
                for _ in 0..*blank {
                    text.push('\n');
                }
                if *comment {
                    text.push_str("# a comment\n");
                }
                want.push(text.lines().count() + 1);
                text.push_str(&format!("id = \"s{i}\"\ntitle = 'T'\nbody = '''b'''\n"));
            }
            for (i, line) in want.iter().enumerate() {
                let id = format!("s{i}");
                prop_assert_eq!(section_line(Path::new("en.toml"), &text, &id), Some(*line));
            }
        }
    }
}
