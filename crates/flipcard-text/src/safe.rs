//! Text from files flipcard did not write (a deck, a sync line, a learner's
//! export, an Anki collection) may hold control characters: an escape
//! sequence printed raw can move the cursor, rewrite the screen or set the
//! window title. Everything the commands print goes through [`escape`] at
//! the output edge (`cmd::output`); the terminal app's widgets drop control
//! characters themselves (ratatui filters them).
//!
//! A control character is written as `\u` and four hexadecimal digits, the
//! spelling JSON uses, so escaping a JSON document leaves it the same JSON.

use std::borrow::Cow;

/// Whether `c` is written escaped: the C0 controls but line feed and tab,
/// DEL, the C1 controls, and the bidirectional embeddings, overrides and
/// isolates (they reorder what a reader sees).
pub fn is_unsafe(c: char) -> bool {
    (c.is_control() && c != '\n' && c != '\t')
        || matches!(c, '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}')
}

/// `text` with each unsafe character written as `\uXXXX`; line feeds and
/// tabs are kept (multi-line messages stay multi-line).
pub fn escape(text: &str) -> Cow<'_, str> {
    escape_if(text, is_unsafe)
}

/// `text` on one line: like [`escape`], and line feeds, carriage returns
/// and tabs escaped too (a value quoted inside a message).
pub fn one_line(text: &str) -> Cow<'_, str> {
    escape_if(text, |c| is_unsafe(c) || c.is_control())
}

fn escape_if(text: &str, unsafe_char: impl Fn(char) -> bool) -> Cow<'_, str> {
    if !text.chars().any(&unsafe_char) {
        return Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 16);
    for c in text.chars() {
        if unsafe_char(c) {
            out.push_str(&format!("\\u{:04x}", u32::from(c)));
        } else {
            out.push(c);
        }
    }
    Cow::Owned(out)
}

/// Escapes a stream of bytes written in pieces (a `Write` at the output
/// edge): a character split between two writes is held until its end
/// arrives. Bytes that are not UTF-8 pass as they are (only whole
/// characters are judged).
#[derive(Debug, Default)]
pub struct Escaper {
    /// The start of a character whose end has not arrived yet.
    held: Vec<u8>,
}

impl Escaper {
    /// The escaped bytes of `buf`, after what was held from before.
    pub fn feed<'a>(&mut self, buf: &'a [u8]) -> Cow<'a, [u8]> {
        let plain = |b: &u8| (0x20..0x7f).contains(b) || *b == b'\n' || *b == b'\t';
        if self.held.is_empty() && buf.iter().all(plain) {
            return Cow::Borrowed(buf);
        }
        let mut bytes = std::mem::take(&mut self.held);
        bytes.extend_from_slice(buf);
        let mut out = Vec::with_capacity(bytes.len() + 16);
        let mut rest = &bytes[..];
        while !rest.is_empty() {
            match std::str::from_utf8(rest) {
                Ok(s) => {
                    out.extend_from_slice(escape(s).as_bytes());
                    rest = &[];
                }
                Err(e) => {
                    let (good, after) = rest.split_at(e.valid_up_to());
                    // The prefix is valid UTF-8 by construction.
                    if let Ok(s) = std::str::from_utf8(good) {
                        out.extend_from_slice(escape(s).as_bytes());
                    }
                    match e.error_len() {
                        // A character cut at the end of this write.
                        None => {
                            self.held = after.to_vec();
                            rest = &[];
                        }
                        Some(n) => {
                            out.extend_from_slice(&after[..n]);
                            rest = &after[n..];
                        }
                    }
                }
            }
        }
        Cow::Owned(out)
    }

    /// What is still held (a cut character at the very end), as it is.
    pub fn finish(&mut self) -> Vec<u8> {
        std::mem::take(&mut self.held)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escape_sequences_are_spelled_out_and_the_rest_kept() {
        assert_eq!(escape("plain ω₂\tand\nlines"), "plain ω₂\tand\nlines");
        assert!(matches!(escape("plain"), Cow::Borrowed(_)));
        assert_eq!(escape("a\u{1b}[2Jb"), "a\\u001b[2Jb");
        assert_eq!(escape("\u{7f}\u{9b}31m\r"), "\\u007f\\u009b31m\\u000d");
        assert_eq!(escape("x\u{202e}y"), "x\\u202ey");
        assert_eq!(one_line("a\nb\tc"), "a\\u000ab\\u0009c");
    }

    #[test]
    fn escaped_json_is_the_same_json() {
        let v = serde_json::json!({"t": "a\u{1b}b\u{7f}c\u{85}d"});
        let text = serde_json::to_string(&v).unwrap();
        let back: serde_json::Value = serde_json::from_str(&escape(&text)).unwrap();
        assert_eq!(back, v);
    }

    #[test]
    fn a_character_cut_between_writes_is_judged_whole() {
        let text = "é\u{9b}x\u{1b}ω";
        let bytes = text.as_bytes();
        for cut in 0..=bytes.len() {
            let mut e = Escaper::default();
            let mut out = e.feed(&bytes[..cut]).into_owned();
            out.extend_from_slice(&e.feed(&bytes[cut..]));
            out.extend(e.finish());
            assert_eq!(String::from_utf8(out).unwrap(), escape(text), "cut {cut}");
        }
        let mut e = Escaper::default();
        assert_eq!(&*e.feed(b"a\xffb\x1b"), b"a\xffb\\u001b");
    }
}
