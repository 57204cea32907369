//! Splitting a text at its `$...$` and `$$...$$` math delimiters.
//!
//! `\$` outside math is a literal dollar. Inside math a backslash always
//! takes the next character with it, so `\$` there is LaTeX's own dollar
//! sign. Math never runs across a blank line, and a `$` directly followed by
//! a digit does not close inline math: `costs $5 and $10` is a missing
//! `\$`, not the formula `5 and `.

/// One piece of a text.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Piece<'a> {
    /// Plain text, to be written as it is.
    Text(&'a str),
    /// A `\$` escape: a literal dollar sign.
    Dollar,
    Math(Math<'a>),
    /// A `$` or `$$` that is never closed; the rest of the text follows
    /// as plain text.
    Unclosed {
        offset: usize,
        display: bool,
    },
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Math<'a> {
    /// The LaTeX between the delimiters.
    pub latex: &'a str,
    /// The whole span with its delimiters, as written.
    pub source: &'a str,
    /// Byte offset of `source` (its first `$`) in the text.
    pub offset: usize,
    /// Byte offset of `latex` in the text.
    pub latex_offset: usize,
    pub display: bool,
}

/// The pieces of `text`, in order.
pub(crate) fn pieces(text: &str) -> Pieces<'_> {
    Pieces { text, pos: 0 }
}

pub(crate) struct Pieces<'a> {
    text: &'a str,
    pos: usize,
}

impl<'a> Iterator for Pieces<'a> {
    type Item = Piece<'a>;

    fn next(&mut self) -> Option<Piece<'a>> {
        let bytes = self.text.as_bytes();
        let start = self.pos;
        if start >= bytes.len() {
            return None;
        }
        if bytes[start..].starts_with(b"\\$") {
            self.pos += 2;
            return Some(Piece::Dollar);
        }
        if bytes[start] == b'$' {
            let display = bytes[start..].starts_with(b"$$");
            let open = if display { 2 } else { 1 };
            let Some((end, close)) = closing(self.text, start + open, display) else {
                // Report once; what follows is read as plain text.
                self.pos = bytes.len();
                return Some(Piece::Unclosed {
                    offset: start,
                    display,
                });
            };
            self.pos = close;
            return Some(Piece::Math(Math {
                latex: &self.text[start + open..end],
                source: &self.text[start..close],
                offset: start,
                latex_offset: start + open,
                display,
            }));
        }
        let end = bytes[start..]
            .iter()
            .enumerate()
            .position(|(i, &b)| {
                b == b'$' || (b == b'\\' && bytes.get(start + i + 1) == Some(&b'$'))
            })
            .map_or(bytes.len(), |i| start + i);
        self.pos = end;
        Some(Piece::Text(&self.text[start..end]))
    }
}

/// End of the math starting at `from` and the position after its closing
/// delimiter.
fn closing(text: &str, from: usize, display: bool) -> Option<(usize, usize)> {
    let bytes = text.as_bytes();
    let mut i = from;
    while i < bytes.len() {
        match bytes[i] {
            b'\\' => i += 2,
            b'$' if display => {
                return (bytes.get(i + 1) == Some(&b'$')).then_some((i, i + 2));
            }
            b'$' => {
                if bytes.get(i + 1).is_some_and(u8::is_ascii_digit) {
                    return None;
                }
                return Some((i, i + 1));
            }
            b'\n' if is_blank_line_after(bytes, i) => return None,
            _ => i += 1,
        }
    }
    None
}

/// Whether the line after the newline at `i` is blank (a paragraph break).
pub(crate) fn is_blank_line_after(bytes: &[u8], i: usize) -> bool {
    bytes[i + 1..]
        .iter()
        .take_while(|&&b| b != b'\n')
        .all(|b| b.is_ascii_whitespace())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn math(latex: &str, display: bool, offset: usize) -> Piece<'_> {
        let open = if display { 2 } else { 1 };
        Piece::Math(Math {
            latex,
            source: "",
            offset,
            latex_offset: offset + open,
            display,
        })
    }

    /// Pieces with `source` blanked, to compare against `math(..)`.
    fn split(text: &str) -> Vec<Piece<'_>> {
        pieces(text)
            .map(|p| match p {
                Piece::Math(m) => Piece::Math(Math { source: "", ..m }),
                other => other,
            })
            .collect()
    }

    #[test]
    fn inline_and_display_math_are_found() {
        assert_eq!(
            split(r"a $x$ b $$y$$ c"),
            vec![
                Piece::Text("a "),
                math("x", false, 2),
                Piece::Text(" b "),
                math("y", true, 8),
                Piece::Text(" c"),
            ]
        );
    }

    #[test]
    fn source_keeps_the_delimiters() {
        let Some(Piece::Math(m)) = pieces("$$a$$").next() else {
            panic!("no math");
        };
        assert_eq!(m.source, "$$a$$");
    }

    #[test]
    fn escaped_dollar_is_literal_outside_math() {
        assert_eq!(
            split(r"costs \$5"),
            vec![Piece::Text("costs "), Piece::Dollar, Piece::Text("5")]
        );
    }

    #[test]
    fn escaped_dollar_inside_math_does_not_close_it() {
        assert_eq!(split(r"$\$5$"), vec![math(r"\$5", false, 0)]);
    }

    #[test]
    fn unclosed_dollar_is_reported_at_its_offset() {
        assert_eq!(
            split("ok $x"),
            vec![
                Piece::Text("ok "),
                Piece::Unclosed {
                    offset: 3,
                    display: false
                }
            ]
        );
        assert_eq!(
            split("$$x$"),
            vec![Piece::Unclosed {
                offset: 0,
                display: true
            }]
        );
    }

    #[test]
    fn dollar_before_a_digit_does_not_close() {
        assert_eq!(
            split("costs $5 and $10"),
            vec![
                Piece::Text("costs "),
                Piece::Unclosed {
                    offset: 6,
                    display: false
                }
            ]
        );
    }

    #[test]
    fn math_does_not_cross_a_blank_line() {
        assert_eq!(
            split("$a\n\nb$"),
            vec![Piece::Unclosed {
                offset: 0,
                display: false
            }]
        );
        assert_eq!(split("$a\nb$"), vec![math("a\nb", false, 0)]);
    }
}
