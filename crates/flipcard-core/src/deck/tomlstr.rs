//! Where a character of a decoded TOML string sits in the source.
//!
//! A LaTeX error or a control character is found in the decoded string; the
//! report must point into the file. Literal strings (`'...'`, `'''...'''`)
//! map one to one after the opening delimiter; basic strings (`"..."`,
//! `"""..."""`) are walked escape by escape.

/// The source byte (relative to the start of the string token, quotes
/// included) where the decoded character at byte `decoded` begins, and
/// whether that character came from an escape sequence. Offsets past the end
/// map to the closing delimiter.
pub(crate) fn locate(token: &str, decoded: usize) -> (usize, bool) {
    let (start, basic) = content_start(token);
    let end = content_end(token);
    if !basic {
        return ((start + decoded).min(end), false);
    }
    let bytes = token.as_bytes();
    let mut i = start;
    let mut d = 0;
    while i < end {
        let (raw_len, produced, escaped) = if bytes[i] == b'\\' {
            escape_at(token, i, end)
        } else if bytes[i] == b'\r' && bytes.get(i + 1) == Some(&b'\n') {
            // A multi-line string's CRLF line break decodes as one newline.
            (2, 1, false)
        } else {
            let len = utf8_len(bytes[i]);
            (len, len, false)
        };
        if produced > 0 && decoded < d + produced {
            return (i, escaped);
        }
        d += produced;
        i += raw_len.max(1);
    }
    (end, false)
}

/// Offset of the first content byte, and whether the string is basic
/// (escapes apply). A multi-line string drops a newline right after `'''`.
fn content_start(token: &str) -> (usize, bool) {
    let (delim, basic) = if token.starts_with("'''") {
        (3, false)
    } else if token.starts_with('\'') {
        (1, false)
    } else if token.starts_with("\"\"\"") {
        (3, true)
    } else {
        (1, true)
    };
    let rest = &token[delim.min(token.len())..];
    let skip = if delim == 3 && rest.starts_with("\r\n") {
        2
    } else if delim == 3 && rest.starts_with('\n') {
        1
    } else {
        0
    };
    ((delim + skip).min(token.len()), basic)
}

fn content_end(token: &str) -> usize {
    let delim = if token.starts_with("'''") || token.starts_with("\"\"\"") {
        3
    } else {
        1
    };
    token
        .len()
        .saturating_sub(delim)
        .max(content_start(token).0)
}

/// Raw length, decoded length, and "is an escape" of the escape at `i`.
fn escape_at(token: &str, i: usize, end: usize) -> (usize, usize, bool) {
    let bytes = token.as_bytes();
    let hex_char = |digits: usize| {
        token
            .get(i + 2..i + 2 + digits)
            .and_then(|h| u32::from_str_radix(h, 16).ok())
            .and_then(char::from_u32)
            .map(|c| (2 + digits, c.len_utf8(), true))
            .unwrap_or((2, 1, true))
    };
    match bytes.get(i + 1) {
        Some(b'u') => hex_char(4),
        Some(b'U') => hex_char(8),
        Some(b'x') => hex_char(2),
        Some(b' ' | b'\t' | b'\r' | b'\n') => {
            // Line-ending backslash of a multi-line basic string: the line
            // break and all whitespace after it vanish.
            let mut j = i + 1;
            while j < end && matches!(bytes[j], b' ' | b'\t' | b'\r' | b'\n') {
                j += 1;
            }
            (j - i, 0, true)
        }
        Some(_) => (2, 1, true),
        None => (1, 1, true),
    }
}

fn utf8_len(first: u8) -> usize {
    match first {
        0xF0..=0xFF => 4,
        0xE0..=0xEF => 3,
        0xC0..=0xDF => 2,
        _ => 1,
    }
}

/// Whether the token is a multi-line string (where a real line break is fine).
pub(crate) fn is_multiline(token: &str) -> bool {
    token.starts_with("'''") || token.starts_with("\"\"\"")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Decode with the real parser, then check every character maps back to
    /// where it is written.
    fn decoded(token: &str) -> String {
        let doc = format!("v = {token}");
        let t: toml::Table = toml::from_str(&doc).unwrap();
        t["v"].as_str().unwrap().to_string()
    }

    #[test]
    fn literal_strings_map_one_to_one() {
        let tok = r"'a $\frac{1}{2}$'";
        let text = decoded(tok);
        let at = text.find(r"\frac").unwrap();
        assert_eq!(locate(tok, at), (tok.find(r"\frac").unwrap(), false));
    }

    #[test]
    fn multiline_literal_skips_the_first_newline() {
        let tok = "'''\nline one\n$x^$'''";
        let text = decoded(tok);
        let at = text.find('^').unwrap();
        assert_eq!(locate(tok, at).0, tok.find('^').unwrap());
    }

    #[test]
    fn basic_strings_walk_escapes() {
        let tok = r#""θ \"q\" \u00e9 \theta x""#;
        let text = decoded(tok);
        let tab = text.find('\t').unwrap();
        assert_eq!(locate(tok, tab), (tok.find(r"\theta").unwrap(), true));
        let x = text.rfind('x').unwrap();
        assert_eq!(locate(tok, x), (tok.rfind('x').unwrap(), false));
        let e = text.find('é').unwrap();
        assert_eq!(locate(tok, e), (tok.find(r"\u00e9").unwrap(), true));
        let q = text.find('q').unwrap();
        assert_eq!(locate(tok, q), (tok.find('q').unwrap(), false));
    }

    #[test]
    fn line_ending_backslash_produces_nothing() {
        let tok = "\"\"\"\nab \\\n   cd\"\"\"";
        let text = decoded(tok);
        assert_eq!(text, "ab cd");
        let c = text.find('c').unwrap();
        assert_eq!(locate(tok, c).0, tok.find('c').unwrap());
    }

    #[test]
    fn past_the_end_maps_to_the_closing_quote() {
        let tok = "'abc'";
        assert_eq!(locate(tok, 10).0, 4);
        assert_eq!(locate("\"ab\"", 2).0, 3);
    }

    #[test]
    fn odd_tokens_do_not_panic() {
        for tok in [
            "",
            "'",
            "\"",
            "'''",
            "\"\"\"",
            "\"\\",
            "\"\\u12",
            "\"\\U0011ffff\"",
        ] {
            for d in 0..6 {
                let (at, _) = locate(tok, d);
                assert!(at <= tok.len());
            }
        }
    }
}
