//! Every TOML example in README.md and docs/*.md is loaded, so that none can
//! rot: whole deck and content files together through the deck loader,
//! fragments of a deck (a card, a prompt's answer, a text) inside the
//! smallest deck that holds them, content fragments inside a content file,
//! settings through the config loader. Only comments (a `#:schema` line)
//! and Taplo's own `.taplo.toml` are merely parsed as TOML.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use flipcard::deck::load_dir;
use flipcard::sched::Config;

/// A fenced ```toml block: where it is, the line before it, its text.
struct Example {
    at: String,
    before: String,
    text: String,
}

fn examples() -> Vec<Example> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = vec![root.join("README.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root.join("docs"))
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    docs.retain(|p| p.extension().is_some_and(|e| e == "md"));
    docs.sort();
    files.extend(docs);
    let mut out = Vec::new();
    for file in files {
        let text =
            std::fs::read_to_string(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let lines: Vec<&str> = text.lines().collect();
        let mut i = 0;
        while i < lines.len() {
            if lines[i].trim() == "```toml" {
                let start = i + 1;
                let end = (start..lines.len())
                    .find(|&j| lines[j].trim() == "```")
                    .unwrap_or_else(|| panic!("{}:{i}: unclosed block", file.display()));
                let before = lines[..i]
                    .iter()
                    .rev()
                    .find(|l| !l.trim().is_empty())
                    .unwrap_or(&"")
                    .to_string();
                out.push(Example {
                    at: format!("{}:{}", file.display(), i + 1),
                    before,
                    text: lines[start..end].join("\n") + "\n",
                });
                i = end;
            }
            i += 1;
        }
    }
    out
}

fn table(e: &Example) -> toml::Table {
    toml::from_str(&e.text).unwrap_or_else(|err| panic!("{}: not valid TOML: {err}", e.at))
}

/// Section ids a fragment names (`explain`, `see`), anywhere in it.
fn section_refs(v: &toml::Value, out: &mut BTreeSet<String>) {
    match v {
        toml::Value::Table(t) => {
            for (k, v) in t {
                match (k.as_str(), v) {
                    ("explain", toml::Value::String(s)) => {
                        out.insert(s.clone());
                    }
                    ("see", toml::Value::Array(a)) => {
                        out.extend(a.iter().filter_map(|s| s.as_str().map(str::to_string)));
                    }
                    _ => section_refs(v, out),
                }
            }
        }
        toml::Value::Array(a) => a.iter().for_each(|v| section_refs(v, out)),
        _ => {}
    }
}

fn stub_sections(ids: &BTreeSet<String>, except: &BTreeSet<String>) -> String {
    ids.difference(except)
        .map(|id| format!("\n[[section]]\nid = \"{id}\"\ntitle = 'Stub'\nbody = 'Stub.'\n"))
        .collect()
}

/// Writes a deck and its content files to a fresh folder and loads it; the
/// example passes when the loader reports no error.
fn load(at: &str, deck_id: &str, deck: &str, content: &[(String, String)]) -> usize {
    let dir = tempfile::tempdir().unwrap_or_else(|e| panic!("temp dir: {e}"));
    let decks = dir.path().join("decks");
    let content_dir = dir.path().join("content").join(deck_id);
    for d in [&decks, &content_dir] {
        std::fs::create_dir_all(d).unwrap_or_else(|e| panic!("{}: {e}", d.display()));
    }
    let write = |p: PathBuf, text: &str| {
        std::fs::write(&p, text).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
    };
    write(decks.join(format!("{deck_id}.toml")), deck);
    for (lang, text) in content {
        write(content_dir.join(format!("{lang}.toml")), text);
    }
    let loaded = load_dir(&decks);
    assert_eq!(
        loaded.errors(),
        0,
        "{at}: the example does not load:\n{}\n--- deck ---\n{deck}",
        loaded.render_all()
    );
    assert_eq!(loaded.decks.len(), 1, "{at}");
    loaded.decks[0].cards.len() + loaded.decks[0].prompts.len()
}

const HEADER: &str = "[deck]\nid = \"doc\"\ntitle = { en = 'Doc', hi-Latn = 'Doc' }\nlanguages = [\"en\", \"hi-Latn\"]\n";

/// A deck fragment inside the smallest deck that holds it.
fn deck_fragment(e: &Example) {
    let t = table(e);
    let mut refs = BTreeSet::new();
    section_refs(&toml::Value::Table(t.clone()), &mut refs);
    let first_header = e
        .text
        .lines()
        .map(str::trim)
        .find(|l| l.starts_with('['))
        .unwrap_or("");
    let deck = if first_header.starts_with("[[card]]")
        || first_header.starts_with("[[scene]]")
        || first_header.starts_with("[[derivation]]")
    {
        format!("{HEADER}\n{}", e.text)
    } else if first_header.starts_with("[prompt.answer]") {
        format!(
            "{HEADER}\n[[prompt]]\nid = \"p\"\nquestion = {{ en = 'Q?', hi-Latn = 'Q?' }}\nscene = \"s\"\n\n{}\n\
             [[scene]]\nid = \"s\"\ninertia = [1, 2, 2.5]\nomega = [0.01, 10, 0.01]\nduration = 5\nshow = [\"omega\"]\n",
            e.text
        )
    } else if first_header.is_empty() {
        // Keys of a card (a text written one way or another).
        let back = if t.contains_key("back") {
            ""
        } else {
            "back = { en = 'B', hi-Latn = 'B' }\n"
        };
        let front = if t.contains_key("front") {
            ""
        } else {
            "front = { en = 'F', hi-Latn = 'F' }\n"
        };
        format!("{HEADER}\n[[card]]\nid = \"c\"\n{front}{back}{}", e.text)
    } else {
        panic!("{}: a TOML example of a kind this test does not know", e.at)
    };
    let stubs = stub_sections(&refs, &BTreeSet::new());
    let content = ["en", "hi-Latn"].map(|l| (l.to_string(), stubs.clone()));
    load(&e.at, "doc", &deck, &content);
}

/// `[[section]]`s of one content file, with stubs for the sections they
/// link to.
fn content_fragment(e: &Example) {
    let t = table(e);
    let own: BTreeSet<String> = t
        .get("section")
        .and_then(|s| s.as_array())
        .map(|a| {
            a.iter()
                .filter_map(|s| s.get("id").and_then(|i| i.as_str()).map(str::to_string))
                .collect()
        })
        .unwrap_or_default();
    let mut refs = BTreeSet::new();
    section_refs(&toml::Value::Table(t), &mut refs);
    let deck = "[deck]\nid = \"doc\"\ntitle = 'Doc'\nlanguages = [\"en\"]\n\n[[card]]\nid = \"c\"\nfront = 'F'\nback = 'B'\n";
    let text = format!("{}{}", e.text, stub_sections(&refs, &own));
    load(&e.at, "doc", deck, &[("en".to_string(), text)]);
}

fn only_comments(text: &str) -> bool {
    text.lines()
        .all(|l| l.trim().is_empty() || l.trim_start().starts_with('#'))
}

#[test]
fn every_toml_example_in_the_docs_loads() {
    let all = examples();
    assert!(all.len() >= 10, "found only {} examples", all.len());
    let mut checked = 0;
    let mut i = 0;
    while i < all.len() {
        let e = &all[i];
        i += 1;
        if only_comments(&e.text) {
            table(e);
            checked += 1;
            continue;
        }
        let t = table(e);
        // A config's `[deck.ID]` tables hold tables; a deck's `[deck]` has
        // its id.
        let config_tables = t.contains_key("preset")
            || t.get("deck")
                .and_then(|d| d.as_table())
                .is_some_and(|d| !d.is_empty() && d.values().all(|v| v.is_table()));
        if t.contains_key("deck") && !config_tables {
            // A whole deck: the content files follow, each introduced by
            // its path (`content/<id>/<lang>.toml`).
            let id = t["deck"]
                .get("id")
                .and_then(|v| v.as_str())
                .unwrap_or_else(|| panic!("{}: a deck without an id", e.at))
                .to_string();
            let mut content = Vec::new();
            while let Some(next) = all.get(i) {
                let marker = format!("content/{id}/");
                let Some(rest) = next.before.split(&marker).nth(1) else {
                    break;
                };
                let lang = rest.split(".toml").next().unwrap_or_default().to_string();
                content.push((lang, next.text.clone()));
                i += 1;
            }
            assert!(!content.is_empty(), "{}: the deck's content files", e.at);
            let items = load(&e.at, &id, &e.text, &content);
            assert!(items > 0, "{}", e.at);
            checked += 1 + content.len();
        } else if t.contains_key("rule") {
            // Taplo's own configuration: TOML is all there is to check.
            checked += 1;
        } else if t.contains_key("section") {
            content_fragment(e);
            checked += 1;
        } else if !t.is_empty()
            && t.keys().all(|k| {
                let k = k.as_str();
                flipcard::sched::config::KEYS.contains(&k)
                    || flipcard::sched::config::FITTED_KEYS.contains(&k)
                    || ["deck_paths", "sync_dir", "preset", "deck"].contains(&k)
                    || ["load_balance", "easy_days", "exam_date"].contains(&k)
            })
        {
            Config::parse(&e.text, Path::new("config.toml"))
                .unwrap_or_else(|err| panic!("{}: settings that do not load: {err}", e.at));
            checked += 1;
        } else {
            deck_fragment(e);
            checked += 1;
        }
    }
    assert_eq!(checked, all.len());
}

/// The test above must be able to fail: a broken example is caught.
#[test]
fn a_broken_example_is_caught() {
    let bad = Example {
        at: "test".into(),
        before: String::new(),
        text: "[[card]]\nid = \"c\"\nfront = { en = 'Euler''s', hi-Latn = 'x' }\nback = { en = 'b', hi-Latn = 'b' }\n".into(),
    };
    assert!(toml::from_str::<toml::Table>(&bad.text).is_err());
    let wrong = Example {
        at: "test".into(),
        before: String::new(),
        text: "[[card]]\nid = \"c\"\nfront = { en = 'F', hi-Latn = 'F' }\nback = { en = '$\\frac{$', hi-Latn = 'b' }\n".into(),
    };
    let caught = std::panic::catch_unwind(|| deck_fragment(&wrong));
    assert!(
        caught.is_err(),
        "a deck error in an example must fail the test"
    );
}

/// The deck format's measure tables say what the vocabulary's table says:
/// each rigid-body measure with its help text, each statistic as `stat(N)`.
#[test]
fn the_measure_tables_in_the_docs_match_the_vocabulary() {
    use flipcard::sim::scene::vocabulary;
    let doc =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/deck-format.md"))
            .unwrap();
    for (row, _) in vocabulary::rigid_rows() {
        let line = format!("| `{}` | {} |", row.name, row.help.replace('|', "\\|"));
        assert!(doc.contains(&line), "docs/deck-format.md lacks {line}");
    }
    for (row, stat) in vocabulary::stat_rows() {
        let call = format!("`{}`", vocabulary::call(row.name, stat));
        assert!(doc.contains(&call), "docs/deck-format.md lacks {call}");
    }
}
