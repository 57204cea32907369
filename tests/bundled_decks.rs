//! The decks that ship with flipcard load without errors, and every text in
//! every declared language renders without a LaTeX error.

use flipcard::deck::{Answer, Deck, Text};

/// Every text of a deck, named for the failure message.
fn texts(deck: &Deck) -> Vec<(String, &Text)> {
    let mut out = vec![("deck title".to_string(), &deck.title)];
    if let Some(d) = &deck.description {
        out.push(("deck description".into(), d));
    }
    for c in &deck.cards {
        out.push((format!("card {} front", c.id), &c.front));
        out.push((format!("card {} back", c.id), &c.back));
    }
    for p in &deck.prompts {
        out.push((format!("prompt {} question", p.id), &p.question));
        match &p.answer {
            Answer::Choice { choices, .. } => {
                for ch in choices {
                    out.push((format!("prompt {} choice {}", p.id, ch.id), &ch.label));
                }
            }
            Answer::Number { formula, .. } => {
                if let Some(f) = formula {
                    out.push((format!("prompt {} formula", p.id), f));
                }
            }
            Answer::Formula(_) => {}
        }
    }
    for s in &deck.scenes {
        if let Some(t) = &s.title {
            out.push((format!("scene {} title", s.id), t));
        }
    }
    for s in &deck.sections {
        out.push((format!("section {} title", s.id), &s.title));
        out.push((format!("section {} body", s.id), &s.body));
    }
    out
}

#[test]
fn bundled_decks_load_and_all_their_math_renders() {
    let loaded = flipcard::bundled::load();
    assert_eq!(loaded.errors(), 0, "\n{}", loaded.render_all());
    let mut problems = Vec::new();
    let mut checked = 0;
    for deck in &loaded.decks {
        for (name, text) in texts(deck) {
            for lang in &deck.languages {
                let Some(s) = text.0.get(lang) else {
                    problems.push(format!("{}: {name}: no {lang} text", deck.id));
                    continue;
                };
                checked += 1;
                for e in flipcard::text::check(s) {
                    problems.push(format!(
                        "{}: {name} [{lang}] at byte {}: {}",
                        deck.id, e.offset, e.message
                    ));
                }
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    assert!(!loaded.decks.is_empty(), "no bundled decks");
    assert!(checked > 0);
}
