//! Texts that render, but not as the author meant: a LaTeX command written
//! outside `$...$` reaches the learner as written (`\mu`), a command the
//! terminal renderer cannot draw (`\underbrace`) comes out garbled, and an
//! unclosed `$` is most often not the last one but the one whose partner
//! is missing. These are the judgements; `check` and `warnings` in the
//! crate root report them.

use super::dollar::{self, Piece};
use super::{MathError, write_math};

/// Commands the parser accepts but the one-line Unicode renderer cannot
/// draw: braces and brackets over or under a part (`\underbrace{T+V}_{E}`
/// comes out as `(T + V)_⏟_E`), colours (dropped), stretched arrows and
/// stacked symbols (drawn as a superscript). The reader sees something
/// else than the author wrote.
pub(crate) const CANNOT_DRAW: &[&str] = &[
    "underbrace",
    "overbrace",
    "undergroup",
    "overgroup",
    "underparen",
    "overparen",
    "wideparen",
    "underbracket",
    "overbracket",
    "underleftarrow",
    "underrightarrow",
    "underleftrightarrow",
    "overleftrightarrow",
    "color",
    "textcolor",
    "xrightarrow",
    "xleftarrow",
    "overset",
    "underset",
    "stackrel",
];

/// The commands of `latex` (`\name`), with their byte offsets.
fn commands(latex: &str) -> impl Iterator<Item = (usize, &str)> {
    let bytes = latex.as_bytes();
    let mut i = 0;
    std::iter::from_fn(move || {
        while i < bytes.len() {
            if bytes[i] != b'\\' {
                i += 1;
                continue;
            }
            let start = i;
            let len = bytes[i + 1..]
                .iter()
                .take_while(|b| b.is_ascii_alphabetic())
                .count();
            // `\\`, `\$`, `\,`: one character taken with the backslash.
            i += 1 + len.max(1);
            if len > 0 {
                return Some((start, &latex[start + 1..start + 1 + len]));
            }
        }
        None
    })
}

/// Whether `\name` is a LaTeX command the renderer knows (a symbol, or a
/// command that wants its arguments), so that prose holding it is a
/// formula that lost its `$`.
fn is_latex_command(name: &str) -> bool {
    let mut out = String::new();
    match write_math(&format!("\\{name}"), &mut out) {
        Ok(()) => true,
        Err(e) => !e.message.starts_with("unknown command"),
    }
}

/// Warnings for `text`: LaTeX commands outside math, and commands inside
/// math the renderer cannot draw, each at its backslash.
pub fn warnings(text: &str) -> Vec<MathError> {
    let mut found = Vec::new();
    let mut offset = 0;
    for piece in dollar::pieces(text) {
        match piece {
            Piece::Text(t) => {
                for (at, _) in t.match_indices('\u{b5}') {
                    found.push(MathError {
                        offset: offset + at,
                        message: "the micro sign `µ` (U+00B5) looks like the Greek `μ` (U+03BC) but is \
                                  another character: write `μ` (or `$\\mu$`) so the deck says one thing"
                            .to_string(),
                    });
                }
                for (at, name) in commands(t) {
                    if is_latex_command(name) {
                        found.push(MathError {
                            offset: offset + at,
                            message: format!(
                                "`\\{name}` outside `$...$` is shown as written, backslash and all"
                            ),
                        });
                    }
                }
                offset += t.len();
            }
            Piece::Dollar => offset += 2,
            Piece::Math(m) => {
                for (at, name) in commands(m.latex) {
                    if CANNOT_DRAW.contains(&name) {
                        found.push(MathError {
                            offset: m.latex_offset + at,
                            message: format!(
                                "`\\{name}` cannot be drawn in the terminal: the learner would see the formula without it"
                            ),
                        });
                    }
                }
                offset = m.offset + m.source.len();
            }
            // The rest is reported by `check`.
            Piece::Unclosed { .. } => break,
        }
    }
    found
}

/// Most `$` in one paragraph weighed when an unclosed one is looked for:
/// each is tried as the one missing its partner, and each try reads all
/// the others.
const MAX_WEIGHED: usize = 200;

/// The `$` of the paragraph `para` (at byte `base` of its text) most likely
/// missing its partner, when the single `$` of the paragraph are odd in
/// number: the one whose leaving out pairs the others into formulas that
/// look least like prose and prose that looks least like LaTeX. `None` when
/// the last `$` (the one reported by default) is as good as any, or when the
/// paragraph holds display math or too many `$` to weigh.
pub(crate) fn likely_unclosed(para: &str, base: usize) -> Option<usize> {
    let bytes = para.as_bytes();
    let mut dollars = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'\\' => i += 2,
            // Display math, and a `$` before a digit (which never closes
            // a formula), pair by other rules: not weighed.
            b'$' if bytes.get(i + 1) == Some(&b'$') => return None,
            b'$' if bytes.get(i + 1).is_some_and(u8::is_ascii_digit) => return None,
            b'$' => {
                dollars.push(i);
                i += 1;
            }
            _ => i += 1,
        }
    }
    if dollars.len() % 2 == 0 || dollars.len() > MAX_WEIGHED {
        return None;
    }
    let score = |left_out: usize| -> usize {
        let kept: Vec<usize> = dollars
            .iter()
            .enumerate()
            .filter(|&(k, _)| k != left_out)
            .map(|(_, &d)| d)
            .collect();
        let mut total = 0;
        let mut prose_from = 0;
        for pair in kept.chunks(2) {
            let [open, close] = pair else { break };
            total += tex_in_prose(&para[prose_from..*open]);
            total += prose_in_math(&para[open + 1..*close]);
            prose_from = close + 1;
        }
        total + tex_in_prose(&para[prose_from..])
    };
    let last = dollars.len() - 1;
    let last_score = score(last);
    let (best, best_score) = (0..last)
        .map(|k| (k, score(k)))
        .min_by_key(|&(k, s)| (s, std::cmp::Reverse(k)))?;
    (best_score < last_score).then(|| base + dollars[best])
}

/// How much `text`, read as prose, looks like LaTeX: its commands and its
/// `^` and `_` scripts.
fn tex_in_prose(text: &str) -> usize {
    commands(text)
        .filter(|(_, name)| is_latex_command(name))
        .count()
        + text.matches(['^', '_']).count()
}

/// How much `latex`, read as a formula, looks like prose: pairs of
/// neighbouring words (two letters or more, not commands) outside
/// `\text{...}`.
fn prose_in_math(latex: &str) -> usize {
    let mut outside = String::with_capacity(latex.len());
    let mut rest = latex;
    while let Some(at) = rest.find("\\text") {
        outside.push_str(&rest[..at]);
        let after = &rest[at..];
        let end = after.find('}').map_or(after.len(), |e| e + 1);
        outside.push(' ');
        rest = &after[end..];
    }
    outside.push_str(rest);
    let is_word =
        |w: &str| w.chars().count() >= 2 && w.chars().all(|c| c.is_alphabetic() || c == '\'');
    let words: Vec<&str> = outside
        .split(|c: char| c.is_whitespace() || ",.;:!?".contains(c))
        .filter(|w| !w.is_empty())
        .collect();
    words
        .windows(2)
        .filter(|w| is_word(w[0]) && is_word(w[1]))
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn messages(text: &str) -> Vec<(usize, String)> {
        warnings(text)
            .into_iter()
            .map(|e| (e.offset, e.message))
            .collect()
    }

    #[test]
    fn latex_outside_math_is_found_at_its_backslash() {
        let text = r"friction \mu times $N$, then \alpha and \frac{a}{b}";
        let found = messages(text);
        let at: Vec<usize> = found.iter().map(|(o, _)| *o).collect();
        assert_eq!(
            at,
            [
                text.find(r"\mu").unwrap(),
                text.find(r"\alpha").unwrap(),
                text.find(r"\frac").unwrap()
            ]
        );
        assert!(found[0].1.contains(r"`\mu` outside `$...$`"), "{found:?}");
    }

    #[test]
    fn backslashes_that_are_not_latex_are_left_alone() {
        for text in [
            r"costs \$5",
            r"a path C:\Users\me",
            r"$\mu N$ only in math",
            r"a \ b",
        ] {
            assert_eq!(messages(text), [], "{text}");
        }
    }

    #[test]
    fn commands_the_renderer_cannot_draw_are_found() {
        let text = r"energy $\underbrace{T + V}_{E} = \overbrace{c}$";
        let found = messages(text);
        assert_eq!(found.len(), 2, "{found:?}");
        assert_eq!(found[0].0, text.find(r"\underbrace").unwrap());
        assert!(found[0].1.contains("cannot be drawn"), "{found:?}");
        assert_eq!(found[1].0, text.find(r"\overbrace").unwrap());
    }

    #[test]
    fn the_dollar_that_lost_its_partner_is_found() {
        // The `$` before `\omega` has lost its closing `$`: pairing by
        // order makes a formula of the prose after it.
        let text = r"The moment $I = mr^2$ holds, and the speed $\omega is measured in radians per second while $L = I\omega$ follows.";
        assert_eq!(likely_unclosed(text, 0), text.find(r"$\omega"));
        // A `$` missing before `\omega`: the closing one is alone.
        let text = r"Spin \omega_3$ is constant, as $L$ is.";
        assert_eq!(
            likely_unclosed(text, 10),
            Some(10 + text.find('$').unwrap())
        );
        // When the last one is as likely as any, nothing better is known.
        assert_eq!(likely_unclosed(r"a $x$ and $y", 0), None);
        assert_eq!(likely_unclosed(r"a $x$ and $y$", 0), None);
    }

    #[test]
    fn prose_and_math_are_told_apart() {
        assert_eq!(prose_in_math(r"I = mr^2"), 0);
        assert_eq!(prose_in_math(r"v = \text{the speed of light}"), 0);
        assert!(prose_in_math(r"\omega is measured in radians") >= 3);
        assert_eq!(tex_in_prose("plain words"), 0);
        assert_eq!(tex_in_prose(r"the \omega_3 "), 2);
    }
}
