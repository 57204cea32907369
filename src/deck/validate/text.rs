//! Texts: every declared language present and no other, no empty strings,
//! no control characters, LaTeX that renders.

use std::collections::BTreeMap;

use crate::deck::model::Text;
use crate::deck::raw::{RawText, Str};
use crate::deck::report::FileReport;
use crate::deck::suggest;
use crate::deck::tomlstr;

/// Control characters reported per string at most; one is usually enough to
/// see the pattern.
const MAX_CONTROL_REPORTS: usize = 5;

/// The deck's declared languages. When `languages` itself is broken the
/// per-text language checks are skipped (that error is already reported).
#[derive(Debug, Clone, Default)]
pub struct Langs {
    pub list: Vec<String>,
    pub known: bool,
}

/// What a string may hold.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Shown to the learner: may hold `$...$` math, checked with the renderer.
    Math,
    /// A name, tag, unit or typed answer: plain characters only.
    Plain,
}

pub fn text(rep: &mut FileReport, raw: &RawText, langs: &Langs, what: &str) -> Option<Text> {
    let mut out = BTreeMap::new();
    let mut ok = true;
    match raw {
        RawText::Plain(s) => {
            ok &= string(rep, s, Kind::Math, what);
            if langs.known && langs.list.len() != 1 {
                let example = langs
                    .list
                    .iter()
                    .map(|l| format!("{l} = '...'"))
                    .collect::<Vec<_>>()
                    .join(", ");
                rep.error(
                    s.span.clone(),
                    format!("{what} must give the text in every declared language"),
                    Some(format!("write {{ {example} }}")),
                );
                return None;
            }
            if let Some(lang) = langs.list.first() {
                out.insert(lang.clone(), s.value.clone());
            }
        }
        RawText::ByLang { span, entries } => {
            for (lang, s) in entries {
                ok &= string(
                    rep,
                    s,
                    Kind::Math,
                    &format!("the `{}` text of {what}", lang.value),
                );
                if langs.known && !langs.list.contains(&lang.value) {
                    ok = false;
                    let hint =
                        suggest::did_you_mean(&lang.value, langs.list.iter().map(String::as_str))
                            .or_else(|| {
                                Some(format!(
                                    "the deck declares languages = [{}]",
                                    quoted(&langs.list)
                                ))
                            });
                    rep.error(
                        lang.span.clone(),
                        format!("language `{}` is not declared by the deck", lang.value),
                        hint,
                    );
                }
                out.insert(lang.value.clone(), s.value.clone());
            }
            if langs.known {
                for lang in &langs.list {
                    if !out.contains_key(lang) {
                        ok = false;
                        rep.error(
                            span.clone(),
                            format!("{what} has no `{lang}` text"),
                            Some(format!("add {lang} = '...'")),
                        );
                    }
                }
            }
        }
    }
    (ok && langs.known).then_some(Text(out))
}

pub fn quoted(list: &[String]) -> String {
    list.iter()
        .map(|l| format!("\"{l}\""))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Checks one string; false when it has an error.
pub fn string(rep: &mut FileReport, s: &Str, kind: Kind, what: &str) -> bool {
    if s.value.trim().is_empty() {
        rep.error(s.span.clone(), format!("{what} is empty"), None);
        return false;
    }
    let token = rep.source.get(s.span.clone()).unwrap_or("").to_string();
    if !control_characters(rep, s, &token, what) {
        // The math would be checked on a mangled string; the control
        // characters already say what is wrong.
        return false;
    }
    if kind == Kind::Math {
        let errors = crate::text::check(&s.value);
        for e in &errors {
            let (at, _) = tomlstr::locate(&token, e.offset);
            let start = s.span.start + at;
            rep.error(start..start + 1, format!("LaTeX: {}", e.message), None);
        }
        return errors.is_empty();
    }
    true
}

/// Reports control characters; false when there are any. A real line break
/// in a multi-line string is fine; one written as the escape `\n` (as in
/// `"\nu"`) is not.
fn control_characters(rep: &mut FileReport, s: &Str, token: &str, what: &str) -> bool {
    let multiline = tomlstr::is_multiline(token);
    let mut reported = 0;
    let mut chars = s.value.char_indices().peekable();
    while let Some((at, c)) = chars.next() {
        if !c.is_control() {
            continue;
        }
        let (raw_at, escaped) = tomlstr::locate(token, at);
        let line_break = c == '\n' || (c == '\r' && chars.peek().map(|&(_, n)| n) == Some('\n'));
        if multiline && line_break && !escaped {
            continue;
        }
        reported += 1;
        if reported > MAX_CONTROL_REPORTS {
            continue;
        }
        let start = s.span.start + raw_at;
        let name = control_name(c);
        if escaped {
            // The escape and the letters after it: most likely a LaTeX
            // command that lost its backslash.
            let escape: String = token[raw_at..].chars().take(2).collect();
            let rest: String = token[raw_at + escape.len()..]
                .chars()
                .take_while(|ch| ch.is_ascii_alphabetic())
                .collect();
            let became = if rest.is_empty() {
                name
            } else {
                format!("{name} followed by `{rest}`")
            };
            rep.error(
                start..start + escape.len() + rest.len(),
                format!(
                    "control character in {what}: `{escape}{rest}` becomes {became} in a \"...\" string"
                ),
                Some(
                    "write texts with math in a literal string '...' or '''...''', where backslashes are kept as written"
                        .to_string(),
                ),
            );
        } else {
            rep.error(
                start..start + c.len_utf8(),
                format!("control character in {what}: {name}"),
                Some(if c == '\t' {
                    "use spaces instead of tabs".to_string()
                } else if c == '\n' || c == '\r' {
                    "a line break needs a multi-line string '''...'''".to_string()
                } else {
                    "remove the control character".to_string()
                }),
            );
        }
    }
    reported == 0
}

fn control_name(c: char) -> String {
    match c {
        '\t' => "a tab".to_string(),
        '\n' => "a line break".to_string(),
        '\r' => "a carriage return".to_string(),
        '\u{8}' => "a backspace".to_string(),
        '\u{c}' => "a form feed".to_string(),
        '\u{1b}' => "an escape character".to_string(),
        other => format!("the control character U+{:04X}", other as u32),
    }
}
