//! The deletions of a cloze card: well formed in every language, the same
//! numbers in each, at least one, and every formula holding one drawable
//! with its gap and with its answer.

use std::collections::BTreeSet;

use crate::deck::cloze;
use crate::deck::raw::{RawText, Str};
use crate::deck::report::FileReport;
use crate::deck::tomlstr;

/// Reports every problem of the deletions of `raw`; false when there is one.
pub fn deletions(rep: &mut FileReport, raw: &RawText, what: &str) -> bool {
    let strings: Vec<(Option<&Str>, &Str)> = match raw {
        RawText::Plain(s) => vec![(None, s)],
        RawText::ByLang { entries, .. } => entries.iter().map(|(l, s)| (Some(l), s)).collect(),
    };
    let mut ok = true;
    let mut found: Vec<(Option<&Str>, &Str, BTreeSet<u16>)> = Vec::new();
    for (lang, s) in strings {
        let token = rep.source.get(s.span.clone()).unwrap_or("").to_string();
        match cloze::parse(&s.value) {
            Err(e) => {
                ok = false;
                let (at, _) = tomlstr::locate(&token, e.offset);
                let start = s.span.start + at;
                rep.error(start..start + 2, format!("{what}: {}", e.message), e.hint);
            }
            Ok(_) => {
                // A deletion inside math: the formula must draw with its
                // gap and with its answer.
                for e in cloze::render_errors(&s.value) {
                    ok = false;
                    let (at, _) = tomlstr::locate(&token, e.offset);
                    let start = s.span.start + at;
                    rep.error(start..start + 1, format!("{what}: {}", e.message), e.hint);
                }
                let numbers = cloze::numbers(&s.value);
                if numbers.is_empty() {
                    ok = false;
                    rep.error(
                        s.span.clone(),
                        format!("cloze {what} has no deletion"),
                        Some("mark the hidden text as {{c1::answer}}".to_string()),
                    );
                } else {
                    found.push((lang, s, numbers));
                }
            }
        }
    }
    // Each number is one review item: a number in one language only would
    // be an item that cannot be shown in the other.
    let all: BTreeSet<u16> = found
        .iter()
        .flat_map(|(_, _, n)| n.iter().copied())
        .collect();
    for (lang, s, numbers) in &found {
        let missing: Vec<String> = all.difference(numbers).map(|n| format!("c{n}")).collect();
        if missing.is_empty() {
            continue;
        }
        ok = false;
        let lang = lang.map_or(String::new(), |l| format!("the `{}` text of ", l.value));
        rep.error(
            s.span.clone(),
            format!(
                "{lang}{what} lacks {} that another language has",
                missing.join(", ")
            ),
            Some("every language needs the same deletion numbers".to_string()),
        );
    }
    ok
}
