//! Texts: every declared language present and no other, no empty strings,
//! no control characters, LaTeX that renders.

use std::fmt::Display;

use crate::deck::model::Text;
use crate::deck::raw::{RawText, Str};
use crate::deck::report::FileReport;
use crate::deck::suggest;
use crate::deck::tomlstr;
use flipcard_text::MathError;

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
    /// The text of a cloze card: math checked as for `Math` once its
    /// markers read (a marker that does not is the cloze check's one error,
    /// not a LaTeX error as well).
    Cloze,
}

/// `what` names the text in its errors (`the front of card \`c1\``); it is
/// formatted only when one is reported, so callers pass `format_args!`.
pub fn text(
    rep: &mut FileReport,
    raw: &RawText,
    langs: &Langs,
    what: impl Display + Copy,
) -> Option<Text> {
    text_of(rep, raw, langs, what, Kind::Math)
}

/// [`text`] for strings of `kind`.
pub(crate) fn text_of(
    rep: &mut FileReport,
    raw: &RawText,
    langs: &Langs,
    what: impl Display + Copy,
    kind: Kind,
) -> Option<Text> {
    // Gathered, then sorted once into the text's map.
    let mut out: Vec<(String, String)> = Vec::new();
    let mut ok = true;
    match raw {
        RawText::Plain(s) => {
            ok &= string(rep, s, kind, what);
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
                out.push((lang.clone(), s.value.clone()));
            }
        }
        RawText::ByLang { span, entries } => {
            let mut missing: Vec<&String> = if langs.known {
                langs
                    .list
                    .iter()
                    .filter(|l| !entries.iter().any(|(k, _)| &k.value == *l))
                    .collect()
            } else {
                Vec::new()
            };
            let undeclared = entries
                .iter()
                .filter(|(k, _)| langs.known && !langs.list.contains(&k.value))
                .count();
            for (lang, s) in entries {
                ok &= string(
                    rep,
                    s,
                    kind,
                    format_args!("the `{}` text of {what}", lang.value),
                );
                if langs.known && !langs.list.contains(&lang.value) {
                    ok = false;
                    // A misspelt key is one mistake: the language it was
                    // meant for is not reported missing as well.
                    let meant = suggest::closest(&lang.value, missing.iter().map(|l| l.as_str()))
                        .map(str::to_string)
                        .or_else(|| {
                            (undeclared == 1 && missing.len() == 1).then(|| missing[0].clone())
                        });
                    let hint = match &meant {
                        Some(l) => Some(format!("{what} has no `{l}` text: did you mean `{l}`?")),
                        None => suggest::did_you_mean(
                            &lang.value,
                            langs.list.iter().map(String::as_str),
                        )
                        .or_else(|| {
                            Some(format!(
                                "the deck declares languages = [{}]",
                                quoted(&langs.list)
                            ))
                        }),
                    };
                    missing.retain(|l| Some(*l) != meant.as_ref());
                    rep.error(
                        lang.span.clone(),
                        format!("language `{}` is not declared by the deck", lang.value),
                        hint,
                    );
                }
                out.push((lang.value.clone(), s.value.clone()));
            }
            for lang in missing {
                ok = false;
                rep.error(
                    span.clone(),
                    format!("{what} has no `{lang}` text"),
                    Some(format!("add {lang} = '...'")),
                );
            }
        }
    }
    (ok && langs.known).then(|| Text(out.into_iter().collect()))
}

pub fn quoted(list: &[String]) -> String {
    list.iter()
        .map(|l| format!("\"{l}\""))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Checks one string; false when it has an error.
pub fn string(rep: &mut FileReport, s: &Str, kind: Kind, what: impl Display + Copy) -> bool {
    string_with(rep, s, kind, what, flipcard_text::check)
}

/// [`string`] with the math checker given (tests pass their own to pin
/// down where its errors land in the file).
fn string_with(
    rep: &mut FileReport,
    s: &Str,
    kind: Kind,
    what: impl Display + Copy,
    math_check: impl Fn(&str) -> Vec<MathError>,
) -> bool {
    if s.value.trim().is_empty() {
        rep.error(s.span.clone(), format!("{what} is empty"), None);
        return false;
    }
    let source: &str = rep.source;
    let token = source.get(s.span.clone()).unwrap_or("");
    if !control_characters(rep, s, token, what) {
        // The math would be checked on a mangled string; the control
        // characters already say what is wrong.
        return false;
    }
    if kind == Kind::Cloze && crate::deck::cloze::parse(&s.value).is_err() {
        return true;
    }
    if kind != Kind::Plain {
        let errors = math_check(&s.value);
        for e in &errors {
            let (at, _) = tomlstr::locate(token, e.offset);
            let start = s.span.start + at;
            rep.error(start..start + 1, format!("LaTeX: {}", e.message), None);
        }
        if errors.is_empty() {
            latex_warnings(rep, s, token);
        }
        return errors.is_empty();
    }
    true
}

/// Warnings for a text that renders, but not as written: LaTeX outside
/// `$...$` (the learner sees `\mu`), and commands the terminal cannot draw.
fn latex_warnings(rep: &mut FileReport, s: &Str, token: &str) {
    for w in flipcard_text::warnings(&s.value) {
        let (at, _) = tomlstr::locate(token, w.offset);
        let start = s.span.start + at;
        // The character warned about (a `\` or a micro sign, which is two
        // bytes) and, after a `\`, the command's name.
        let first = s.value[w.offset..].chars().next().map_or(1, char::len_utf8);
        let name_len = if s.value[w.offset..].starts_with('\\') {
            s.value[w.offset + first..]
                .bytes()
                .take_while(u8::is_ascii_alphabetic)
                .count()
        } else {
            0
        };
        let hint = if s.value[w.offset..].starts_with('\u{b5}') {
            "replace it with the Greek `μ` (U+03BC)".to_string()
        } else if w.message.contains("outside") {
            let name = &s.value[w.offset..w.offset + first + name_len];
            format!("put it in math: `${name}$`")
        } else {
            "write the formula without it (say in words what the brace or box marks), or split it in two formulas".to_string()
        };
        let end = s.span.start + tomlstr::locate(token, w.offset + first + name_len).0;
        rep.warning(
            start..end.max(start + 1),
            format!("LaTeX: {}", w.message),
            Some(hint),
        );
    }
}

/// Reports control characters; false when there are any. A real line break
/// in a multi-line string is fine; one written as the escape `\n` (as in
/// `"\nu"`) is not.
fn control_characters(rep: &mut FileReport, s: &Str, token: &str, what: impl Display) -> bool {
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

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::deck::diag::Diagnostic;

    /// The string value `v` of `source` as the reader would give it.
    fn value(source: &str) -> Str {
        let table: toml::Table = toml::from_str(source).unwrap();
        let start = source.find("v = ").unwrap() + 4;
        let end = source.trim_end().len();
        Str {
            value: table["v"].as_str().unwrap().to_string(),
            span: start..end,
        }
    }

    /// Diagnostics when the math checker flags the first `marker` in the
    /// decoded text.
    fn flag(source: &str, marker: &str) -> Vec<Diagnostic> {
        let s = value(source);
        let mut rep = FileReport::new(Path::new("d.toml"), source);
        let ok = string_with(&mut rep, &s, Kind::Math, "a text", |text| {
            vec![MathError {
                offset: text.find(marker).unwrap(),
                message: "unknown command".into(),
            }]
        });
        assert!(!ok);
        rep.finish()
    }

    fn at(d: &[Diagnostic]) -> (usize, usize) {
        assert_eq!(d.len(), 1, "{d:?}");
        (d[0].line, d[0].col)
    }

    #[test]
    fn math_errors_in_literal_strings_land_exactly() {
        let src = "# c\nv = 'a $\\bad{x}$'\n";
        let d = flag(src, r"\bad");
        assert_eq!(at(&d), (2, 9));
        assert_eq!(d[0].message, "LaTeX: unknown command");
    }

    #[test]
    fn math_errors_in_multiline_strings_land_on_their_line() {
        let src = "v = '''\nfirst line\n  then $\\bad$'''\n";
        assert_eq!(at(&flag(src, r"\bad")), (3, 9));
    }

    #[test]
    fn math_errors_after_escapes_land_on_the_written_character() {
        let src = r#"v = "\u00e9 \"q\" $\\bad$""#;
        // The escape `\\` that gives the backslash of `\bad` is column 20.
        assert_eq!(at(&flag(src, r"\bad")), (1, 20));
    }

    #[test]
    fn a_written_tab_and_an_escaped_one_are_both_reported() {
        let src = "v = \"a\tb \\theta\"\n";
        let s = value(src);
        let mut rep = FileReport::new(Path::new("d.toml"), src);
        assert!(!string(&mut rep, &s, Kind::Math, "a text"));
        let d = rep.finish();
        assert_eq!(d.len(), 2, "{d:?}");
        assert_eq!((d[0].line, d[0].col), (1, 7));
        assert!(d[0].message.contains("a tab"), "{}", d[0].message);
        assert_eq!((d[1].line, d[1].col), (1, 10));
        assert!(
            d[1].message
                .contains(r"`\theta` becomes a tab followed by `heta`"),
            "{}",
            d[1].message
        );
    }

    #[test]
    fn line_breaks_are_fine_only_when_written_in_multiline_strings() {
        let ok = "v = '''\nline one\nline two'''\n";
        let mut rep = FileReport::new(Path::new("d.toml"), ok);
        assert!(string(&mut rep, &value(ok), Kind::Math, "a text"));
        assert!(rep.finish().is_empty());

        let escaped = "v = \"\"\"\nfrequency $\\nu$\"\"\"\n";
        let mut rep = FileReport::new(Path::new("d.toml"), escaped);
        assert!(!string(&mut rep, &value(escaped), Kind::Math, "a text"));
        assert_eq!(at(&rep.finish()), (2, 12));
    }
}
