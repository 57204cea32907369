//! Cloze deletions in Anki's syntax: `{{c1::answer}}` and
//! `{{c1::answer::hint}}`. Each number is one review item; its front shows
//! the text with that number's deletions blanked and the others revealed.
//!
//! Markers are read outside math only, so LaTeX's own `{{` and `}}` (as in
//! `$x^{{2}}$`) are left alone, while math may sit inside a deletion
//! (`{{c1::$\omega_2$}}`) and around it.

use std::collections::BTreeSet;

/// The largest deletion number accepted (Anki's own limit is far above
/// anything a card needs; this keeps `c` numbers short and finite).
pub const MAX_NUMBER: u16 = 999;

/// One part of a cloze text.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Piece<'a> {
    /// Text shown as it is (may hold math).
    Text(&'a str),
    Deletion {
        number: u16,
        answer: &'a str,
        hint: Option<&'a str>,
    },
}

/// A problem in a cloze text, at a byte offset of that text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ClozeError {
    pub offset: usize,
    pub message: String,
    pub hint: Option<String>,
}

fn err(offset: usize, message: impl Into<String>, hint: Option<&str>) -> ClozeError {
    ClozeError {
        offset,
        message: message.into(),
        hint: hint.map(str::to_string),
    }
}

/// Splits a cloze text into pieces; the first problem met is the error.
pub fn parse(text: &str) -> Result<Vec<Piece<'_>>, ClozeError> {
    let bytes = text.as_bytes();
    let mut pieces = Vec::new();
    let mut plain_from = 0;
    let mut i = 0;
    let mut math = false;
    while i < bytes.len() {
        match bytes[i] {
            b'\\' => i += 2,
            b'$' => {
                math = !math;
                // `$$` opens or closes display math as one delimiter.
                i += if bytes.get(i + 1) == Some(&b'$') {
                    2
                } else {
                    1
                };
            }
            b'{' if !math && bytes.get(i + 1) == Some(&b'{') => {
                if i > plain_from {
                    pieces.push(Piece::Text(&text[plain_from..i]));
                }
                let (piece, end) = deletion(text, i)?;
                pieces.push(piece);
                i = end;
                plain_from = end;
            }
            b'}' if !math && bytes.get(i + 1) == Some(&b'}') => {
                return Err(err(
                    i,
                    "`}}` closes no cloze deletion",
                    Some("a deletion is written {{c1::answer}}"),
                ));
            }
            _ => i += 1,
        }
    }
    if plain_from < text.len() {
        pieces.push(Piece::Text(&text[plain_from..]));
    }
    Ok(pieces)
}

/// Reads the deletion whose `{{` is at `start`; returns it and the offset
/// after its `}}`.
fn deletion(text: &str, start: usize) -> Result<(Piece<'_>, usize), ClozeError> {
    let shape = Some("a deletion is written {{c1::answer}} or {{c1::answer::hint}}");
    let after = &text[start + 2..];
    let Some(rest) = after.strip_prefix('c') else {
        return Err(err(
            start,
            "a cloze marker must start with `{{c` and a number",
            shape,
        ));
    };
    let digits = rest.bytes().take_while(u8::is_ascii_digit).count();
    let number = rest[..digits]
        .parse::<u16>()
        .ok()
        .filter(|n| (1..=MAX_NUMBER).contains(n) && !rest.starts_with('0'));
    let Some(number) = number else {
        return Err(err(
            start,
            format!(
                "a cloze number must be a whole number from 1 to {MAX_NUMBER}, written without leading zeros"
            ),
            shape,
        ));
    };
    let Some(body) = rest[digits..].strip_prefix("::") else {
        return Err(err(
            start,
            format!("the cloze marker `{{{{c{number}` must be followed by `::`"),
            shape,
        ));
    };
    let body_start = text.len() - body.len();
    // The closing `}}`, outside math; a `{{` before it is a nested deletion.
    let bytes = text.as_bytes();
    let mut math = false;
    let mut i = body_start;
    let close = loop {
        if i >= bytes.len() {
            return Err(err(
                start,
                format!("cloze deletion `{{{{c{number}::` is never closed with `}}}}`"),
                None,
            ));
        }
        match bytes[i] {
            b'\\' => i += 2,
            b'$' => {
                math = !math;
                i += if bytes.get(i + 1) == Some(&b'$') {
                    2
                } else {
                    1
                };
            }
            b'{' if !math && bytes.get(i + 1) == Some(&b'{') => {
                return Err(err(
                    i,
                    "cloze deletions cannot be nested",
                    Some("close the outer deletion first, or give the inner text its own"),
                ));
            }
            b'}' if !math && bytes.get(i + 1) == Some(&b'}') => break i,
            _ => i += 1,
        }
    };
    let inner = &text[body_start..close];
    let (answer, hint) = match split_hint(inner) {
        Some((a, h)) => (a, Some(h)),
        None => (inner, None),
    };
    if answer.trim().is_empty() {
        return Err(err(
            start,
            format!("cloze deletion c{number} is empty"),
            Some("write the hidden text between `::` and `}}`"),
        ));
    }
    if hint.is_some_and(|h| h.trim().is_empty()) {
        return Err(err(
            start,
            format!("the hint of cloze deletion c{number} is empty"),
            Some("drop the second `::` or write a hint after it"),
        ));
    }
    Ok((
        Piece::Deletion {
            number,
            answer,
            hint,
        },
        close + 2,
    ))
}

/// `answer::hint`, the separator taken outside math.
fn split_hint(inner: &str) -> Option<(&str, &str)> {
    let bytes = inner.as_bytes();
    let mut math = false;
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'\\' => i += 2,
            b'$' => {
                math = !math;
                i += 1;
            }
            b':' if !math && bytes.get(i + 1) == Some(&b':') => {
                return Some((&inner[..i], &inner[i + 2..]));
            }
            _ => i += 1,
        }
    }
    None
}

/// The deletion numbers of a text, ascending (empty when it does not parse).
pub fn numbers(text: &str) -> BTreeSet<u16> {
    parse(text)
        .map(|pieces| {
            pieces
                .iter()
                .filter_map(|p| match p {
                    Piece::Deletion { number, .. } => Some(*number),
                    Piece::Text(_) => None,
                })
                .collect()
        })
        .unwrap_or_default()
}

/// A part of a shown cloze text: markup (with math) and whether it is the
/// part asked about (the blank on the front, the answer on the back).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Segment {
    pub text: String,
    pub asked: bool,
}

/// The front for deletion `number`: its deletions as `[…]` (or `[hint]`),
/// every other deletion revealed.
pub fn front(text: &str, number: u16) -> Vec<Segment> {
    shown(text, number, true)
}

/// The back for deletion `number`: the whole text, its answers marked.
pub fn back(text: &str, number: u16) -> Vec<Segment> {
    shown(text, number, false)
}

/// The text with every deletion revealed and no markers (for search).
pub fn revealed(text: &str) -> String {
    shown(text, 0, false).into_iter().map(|s| s.text).collect()
}

fn shown(text: &str, number: u16, blank: bool) -> Vec<Segment> {
    let Ok(pieces) = parse(text) else {
        return vec![Segment {
            text: text.to_string(),
            asked: false,
        }];
    };
    let mut out: Vec<Segment> = Vec::new();
    let mut push = |text: String, asked: bool| match out.last_mut() {
        Some(last) if last.asked == asked && !asked => last.text.push_str(&text),
        _ => out.push(Segment { text, asked }),
    };
    for p in pieces {
        match p {
            Piece::Text(t) => push(t.to_string(), false),
            Piece::Deletion {
                number: n,
                answer,
                hint,
            } if n == number => {
                if blank {
                    push(format!("[{}]", hint.unwrap_or("…")), true);
                } else {
                    push(answer.to_string(), true);
                }
            }
            Piece::Deletion { answer, .. } => push(answer.to_string(), false),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn joined(segs: &[Segment]) -> String {
        segs.iter()
            .map(|s| {
                if s.asked {
                    format!("<{}>", s.text)
                } else {
                    s.text.clone()
                }
            })
            .collect()
    }

    #[test]
    fn fronts_blank_one_number_and_reveal_the_others() {
        let t = r"{{c1::Torque}} is the rate of change of {{c2::$\vec L$::a vector}}; {{c1::it}} vanishes";
        assert_eq!(numbers(t).into_iter().collect::<Vec<_>>(), [1, 2]);
        assert_eq!(
            joined(&front(t, 1)),
            r"<[…]> is the rate of change of $\vec L$; <[…]> vanishes"
        );
        assert_eq!(
            joined(&front(t, 2)),
            r"Torque is the rate of change of <[a vector]>; it vanishes"
        );
        assert_eq!(
            joined(&back(t, 2)),
            r"Torque is the rate of change of <$\vec L$>; it vanishes"
        );
        assert_eq!(
            revealed(t),
            r"Torque is the rate of change of $\vec L$; it vanishes"
        );
    }

    #[test]
    fn latex_braces_are_not_markers() {
        let t = r"$x^{{2}}$ and {{c1::$\frac{a}{b^{2}}$}} and $$\sqrt{{y}}$$";
        let pieces = parse(t).unwrap();
        assert_eq!(pieces.len(), 3, "{pieces:?}");
        assert_eq!(
            pieces[1],
            Piece::Deletion {
                number: 1,
                answer: r"$\frac{a}{b^{2}}$",
                hint: None
            }
        );
    }

    #[test]
    fn malformed_markers_are_located() {
        let cases = [
            ("a {{c1::b", 2, "never closed"),
            ("a }} b", 2, "closes no"),
            ("a {{x::b}}", 2, "must start"),
            ("a {{c0::b}}", 2, "from 1 to"),
            ("a {{c01::b}}", 2, "from 1 to"),
            ("a {{c1:b}}", 2, "followed by `::`"),
            ("a {{c1::}}", 2, "is empty"),
            ("a {{c1::  }}", 2, "is empty"),
            ("a {{c1::b::}}", 2, "hint"),
            ("a {{c1::b {{c2::d}} }}", 10, "nested"),
            ("{{c1000::b}}", 0, "from 1 to"),
        ];
        for (text, offset, says) in cases {
            let e = parse(text).unwrap_err();
            assert_eq!(e.offset, offset, "{text}: {e:?}");
            assert!(e.message.contains(says), "{text}: {}", e.message);
        }
    }
}
