//! Where in the formula a parser error is.
//!
//! `pulldown-latex` 0.8 does not expose the error position; it only prints
//! a window of about 12 bytes either side of it. Parsing the formula again
//! with blank padding on both sides makes that window land fully inside the
//! input, so it can be matched back to one position (the first one that is
//! consistent with how the window is cut). When that fails, `None`: the
//! caller falls back to the start of the formula.

use std::error::Error as _;

use pulldown_latex::{Parser, ParserError, Storage};

/// Bytes of context the parser prints on each side of the error position.
const CONTEXT: usize = 12;
/// Padding: more than the context plus the widest UTF-8 character.
const PAD: usize = CONTEXT + 4;

const HEAD: &str = "╭─► context:\n│\n";

/// The parser's own message, without the context window.
pub(super) fn message(err: &ParserError) -> String {
    match err.source() {
        Some(kind) => kind.to_string(),
        None => err.to_string(),
    }
}

/// Byte offset in `latex` of the error the parser reports first, moved back
/// onto the start of the offending command (`\foo`, `\\`, `}`, `&`).
pub(super) fn offset(latex: &str) -> Option<usize> {
    // Carriage returns would be lost in the printed window (it is split
    // into lines); a space parses the same.
    let mut padded = String::with_capacity(latex.len() + 2 * PAD);
    padded.extend(std::iter::repeat_n(' ', PAD));
    padded.extend(latex.chars().map(|c| if c == '\r' { ' ' } else { c }));
    padded.extend(std::iter::repeat_n(' ', PAD));

    let storage = Storage::new();
    let err = Parser::new(&padded, &storage).find_map(Result::err)?;
    let window = window(&err.to_string())?;
    let index = position(&padded, &window)?;
    let at = index.checked_sub(PAD)?.min(latex.len());
    Some(start_of_token(latex, at))
}

/// The window of input text printed in the error, lines rejoined.
fn window(printed: &str) -> Option<String> {
    let (_, rest) = printed.split_once(HEAD)?;
    // Macro expansions print more than one window; that is not matched.
    if rest.contains("├") {
        return None;
    }
    let lines: Vec<&str> = rest.split('\n').collect();
    // Window lines, then the caret line, then the closing rule.
    let body = lines.get(..lines.len().checked_sub(2)?)?;
    let mut text = String::new();
    for (i, line) in body.iter().enumerate() {
        if i > 0 {
            text.push('\n');
        }
        let line = line.strip_prefix('│')?;
        let line = line
            .strip_prefix('…')
            .or_else(|| line.strip_prefix(' '))
            .unwrap_or(line);
        text.push_str(line);
    }
    Some(text)
}

/// The parser's window is `input[floor(i - 12)..floor(i + 12)]`, with
/// `floor` rounding down to a character boundary; find the `i` that gives
/// `window`.
fn position(input: &str, window: &str) -> Option<usize> {
    let floor = |i: usize| {
        if i >= input.len() {
            input.len()
        } else {
            (0..=i)
                .rev()
                .find(|&j| input.is_char_boundary(j))
                .unwrap_or(0)
        }
    };
    let printed =
        |range: std::ops::Range<usize>| input[range].lines().collect::<Vec<_>>().join("\n");
    let starts =
        (0..input.len()).filter(|&i| input.is_char_boundary(i) && input[i..].starts_with(window));
    starts.into_iter().find_map(|lower| {
        (0..4).map(|d| lower + CONTEXT + d).find(|&index| {
            index <= input.len()
                && input.is_char_boundary(index)
                && floor(index - CONTEXT) == lower
                && printed(lower..floor(index + CONTEXT)) == window
        })
    })
}

/// The parser points just past the token it choked on (and the blanks a
/// control word swallows); step back onto it.
fn start_of_token(latex: &str, at: usize) -> usize {
    let before = latex[..at].trim_end();
    let at = before.len();
    let letters = before.len()
        - before
            .trim_end_matches(|c: char| c.is_ascii_alphabetic())
            .len();
    if letters > 0 && before[..at - letters].ends_with('\\') {
        return at - letters - 1;
    }
    if let Some(env) = environment_start(before) {
        return env;
    }
    let mut chars = before.chars().rev();
    match (chars.next(), chars.next()) {
        (Some(c), Some('\\')) if !c.is_ascii_alphabetic() => at - c.len_utf8() - 1,
        (Some(c @ ('}' | '&' | '#' | '$')), _) => at - c.len_utf8(),
        _ => at,
    }
}

/// `\begin{name}` or `\end{name}` ending `before`: its backslash.
fn environment_start(before: &str) -> Option<usize> {
    let open = before.strip_suffix('}')?.rfind('{')?;
    let name = &before[open + 1..before.len() - 1];
    if name.contains(['{', '}', '\\']) {
        return None;
    }
    ["\\begin", "\\end"]
        .iter()
        .find(|cmd| before[..open].trim_end().ends_with(*cmd))
        .map(|cmd| before[..open].trim_end().len() - cmd.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_command_points_at_its_backslash() {
        assert_eq!(offset(r"x + \foo y"), Some(4));
        assert_eq!(offset(r"\foo"), Some(0));
    }

    #[test]
    fn stray_closing_brace_points_at_it() {
        assert_eq!(offset("a + b} + c"), Some(5));
    }

    #[test]
    fn unclosed_group_points_at_the_end() {
        assert_eq!(offset("a + {b + c"), Some(10));
    }

    #[test]
    fn unknown_environment_points_at_begin() {
        assert_eq!(offset(r"x \begin{foo} y \end{foo}"), Some(2));
    }

    #[test]
    fn position_is_found_past_multibyte_text() {
        assert_eq!(offset(r"ωωωωωωωωωω + \foo"), Some(23));
        assert_eq!(offset("ω\r\nω + \\foo"), Some(9));
    }

    #[test]
    fn repeated_text_picks_the_failing_occurrence() {
        // The first `\alpha + \beta` parses; the error is the unknown
        // command after the second.
        let latex = r"\alpha + \beta + \gamma \alpha + \beta + \nope";
        assert_eq!(offset(latex), latex.find(r"\nope"));
    }

    #[test]
    fn valid_formula_has_no_offset() {
        assert_eq!(offset(r"\frac{a}{b}"), None);
    }
}
