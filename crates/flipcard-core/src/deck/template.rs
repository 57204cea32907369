//! A new card to append to a deck file (the app's `A`): a `[[card]]`
//! table of the given kind with a fresh id and placeholder texts in each of
//! the deck's languages, valid as written, for the learner to replace.

use super::model::{CardKind, Deck};

/// An id for a new card of `deck` that no card, prompt or derivation of
/// it uses and that `taken` (ids with history, such as an old card's
/// orphaned reviews) does not hold: `new-card-N`, N from 1.
pub fn fresh_card_id(deck: &Deck, taken: &dyn Fn(&str) -> bool) -> String {
    let used = |id: &str| {
        deck.cards.iter().any(|c| c.id == id)
            || deck.prompts.iter().any(|p| p.id == id)
            || deck.derivations.iter().any(|d| d.id == id)
            || taken(id)
    };
    (1u64..)
        .map(|n| format!("new-card-{n}"))
        .find(|id| !used(id))
        .unwrap_or_default()
}

/// The `[[card]]` table of a new card of `kind` named `id`, with texts in
/// each of `languages`, starting with a blank line (appended to a file).
pub fn card_table(kind: CardKind, id: &str, languages: &[String]) -> String {
    let mut out = String::from("\n[[card]]\n");
    out.push_str(&format!("id = \"{id}\"\n"));
    if kind != CardKind::Basic {
        out.push_str(&format!("kind = \"{}\"\n", kind.as_str()));
    }
    let langs: Vec<&str> = if languages.is_empty() {
        vec!["en"]
    } else {
        languages.iter().map(String::as_str).collect()
    };
    let text = |key: &str, value: &str, out: &mut String| {
        for lang in &langs {
            out.push_str(&format!("{key}.{lang} = '''{value}'''\n"));
        }
    };
    match kind {
        CardKind::Cloze => {
            text(
                "text",
                "The text, with {{c1::the part to hide}} marked.",
                &mut out,
            );
            text("back", "Notes under the answer.", &mut out);
        }
        _ => {
            text("front", "The question.", &mut out);
            text("back", "The answer.", &mut out);
        }
    }
    match kind {
        CardKind::Typed => out.push_str("accept = [\"the answer\"]\n"),
        CardKind::Formula => {
            out.push_str("expected = \"2 x\"\n");
            out.push_str("vars = { x = [1, 2] }\n");
        }
        _ => {}
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::deck::files::Memory;
    use crate::deck::load::load_tree;
    use std::path::PathBuf;

    const HEAD: &str = "[deck]\nid = \"d\"\ntitle = { en = 'D', hi-Latn = 'D' }\nlanguages = [\"en\", \"hi-Latn\"]\n\n[[card]]\nid = \"new-card-1\"\nfront.en = 'x'\nfront.hi-Latn = 'x'\nback.en = 'y'\nback.hi-Latn = 'y'\n";

    fn load(text: &str) -> crate::deck::Loaded {
        let text: &'static str = Box::leak(text.to_string().into_boxed_str());
        let tree = Memory::new(vec![
            (PathBuf::from("decks/d.toml"), text.as_bytes()),
            (PathBuf::from("content/d/en.toml"), &b""[..]),
            (PathBuf::from("content/d/hi-Latn.toml"), &b""[..]),
        ]);
        load_tree(&tree, &[PathBuf::from("decks")])
    }

    #[test]
    fn every_kinds_template_loads_as_a_card_of_that_kind() {
        let langs = vec!["en".to_string(), "hi-Latn".to_string()];
        for kind in [
            CardKind::Basic,
            CardKind::Reversed,
            CardKind::Typed,
            CardKind::Cloze,
            CardKind::Formula,
        ] {
            let deck = load(HEAD).decks.remove(0);
            let id = fresh_card_id(&deck, &|id| id == "new-card-2");
            assert_eq!(id, "new-card-3");
            let text = format!("{HEAD}{}", card_table(kind, &id, &langs));
            let loaded = load(&text);
            assert_eq!(loaded.errors(), 0, "{kind:?}: {}", loaded.render_all());
            assert_eq!(loaded.warnings(), 0, "{kind:?}: {}", loaded.render_all());
            let card = loaded.decks[0].card(&id).expect("the new card");
            assert_eq!(card.kind, kind);
        }
    }
}
