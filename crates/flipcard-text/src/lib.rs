//! Math text: `$...$` and `$$...$$` LaTeX rendered as Unicode for the
//! terminal, and the light markup of explanation sections. Never imports
//! ratatui.
//!
//! LaTeX is parsed by `pulldown-latex`; its events are folded into a small
//! tree (`tree`) and written out as one line of Unicode (`unicode`).

mod count;
mod dollar;
pub mod fill;
mod glyphs;
mod lang;
mod lint;
mod locate;
pub mod markup;
pub mod num;
pub mod safe;
mod tree;
mod unicode;
pub mod units;

#[cfg(test)]
mod seed_tests;

pub use count::plural;
pub use lang::{Lang, LangMap, Text};
pub use lint::warnings;

use pulldown_latex::{Parser, Storage};

use dollar::Piece;
use tree::BuildError;

/// A LaTeX problem inside a text, at a byte offset of that text.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{message}")]
pub struct MathError {
    /// Byte offset into the text where the problem is (for line:col).
    pub offset: usize,
    pub message: String,
}

/// Every LaTeX problem in `text` (empty when it all renders): formulas that
/// do not parse, at the place the parser points to (else at the formula's
/// opening `$`), and `$` or `$$` that are never closed. An unclosed `$` is
/// reported where its partner is most likely missing (see
/// `lint::likely_unclosed`), not at the last `$` of the paragraph; the
/// formulas the wrong pairing made after it are not reported.
pub fn check(text: &str) -> Vec<MathError> {
    let mut errors = check_in_order(text);
    let Some(last) = errors.last() else {
        return errors;
    };
    if !last.message.starts_with("`$` is not closed") {
        return errors;
    }
    let at = last.offset;
    let start = paragraph_start(text, at);
    let end = paragraph_end(text, at);
    let Some(culprit) = lint::likely_unclosed(&text[start..end], start) else {
        return errors;
    };
    errors.pop();
    errors.retain(|e| e.offset < culprit);
    errors.push(MathError {
        offset: culprit,
        message: "`$` is most likely not closed here: paired in order, the `$` after it make \
                  formulas of prose and leave LaTeX outside them; end this formula with `$`, \
                  or write a literal dollar as `\\$`"
            .to_string(),
    });
    errors
}

/// The start of the paragraph (after the last blank line) holding `at`.
fn paragraph_start(text: &str, at: usize) -> usize {
    let bytes = text.as_bytes();
    let mut line = text[..at].rfind('\n').map_or(0, |n| n + 1);
    loop {
        if line == 0 {
            return 0;
        }
        let prev = text[..line - 1].rfind('\n').map_or(0, |n| n + 1);
        if bytes[prev..line - 1].iter().all(u8::is_ascii_whitespace) {
            return line;
        }
        line = prev;
    }
}

/// The end of the paragraph (the newline before a blank line) holding `at`.
fn paragraph_end(text: &str, at: usize) -> usize {
    let mut i = at;
    while let Some(n) = text[i..].find('\n') {
        let newline = i + n;
        if dollar::is_blank_line_after(text.as_bytes(), newline) {
            return newline;
        }
        i = newline + 1;
    }
    text.len()
}

/// [`check`] with every `$` paired in order.
fn check_in_order(text: &str) -> Vec<MathError> {
    let mut errors = Vec::new();
    let mut scratch = String::new();
    for piece in dollar::pieces(text) {
        match piece {
            Piece::Math(math) => {
                scratch.clear();
                if let Err(e) = write_math(math.latex, &mut scratch) {
                    errors.push(MathError {
                        offset: e.at.map_or(math.offset, |at| math.latex_offset + at),
                        message: e.message,
                    });
                }
            }
            Piece::Unclosed { offset, display } => errors.push(unclosed(offset, display)),
            Piece::Text(_) | Piece::Dollar => {}
        }
    }
    errors
}

/// A variable's name as a panel shows it: a Greek letter's name as the
/// letter, with its index as a subscript (`theta` → θ, `omega2` → ω₂,
/// `phi_1` → φ₁); any other name as written.
pub fn variable_name(name: &str) -> String {
    const GREEK: [&str; 24] = [
        "alpha", "beta", "gamma", "delta", "epsilon", "zeta", "eta", "theta", "iota", "kappa",
        "lambda", "mu", "nu", "xi", "pi", "rho", "sigma", "tau", "upsilon", "phi", "chi", "psi",
        "omega", "varphi",
    ];
    let letters = name.trim_end_matches(|c: char| c.is_ascii_digit() || c == '_');
    let index = name[letters.len()..].trim_start_matches('_');
    let capital = letters
        .strip_prefix(|c: char| c.is_ascii_uppercase())
        .is_some_and(|rest| rest.chars().all(|c| c.is_ascii_lowercase()));
    let lower = letters.to_ascii_lowercase();
    if !GREEK.contains(&lower.as_str()) || !(index.chars().all(|c| c.is_ascii_digit())) {
        return name.to_string();
    }
    // LaTeX has capitals only for the letters that differ from Latin ones.
    let latex = if capital {
        let mut c = lower.chars();
        c.next()
            .map(|f| format!("{}{}", f.to_ascii_uppercase(), c.as_str()))
            .unwrap_or_default()
    } else {
        lower
    };
    let sub = if index.is_empty() {
        String::new()
    } else {
        format!("_{{{index}}}")
    };
    let shown = render(&format!("$\\{latex}{sub}$"));
    if shown.contains('\\') {
        name.to_string()
    } else {
        shown
    }
}

/// `c` with a compatibility character folded to its usual form when that
/// is one character (NFKC): the micro sign µ is the Greek μ, `Ω` the ohm
/// sign is Ω, fullwidth letters are letters. One character in, one out, so
/// a search can fold texts and still point at their characters.
pub fn compat_char(c: char) -> char {
    if c.is_ascii() {
        return c;
    }
    use unicode_normalization::UnicodeNormalization;
    let mut folded = std::iter::once(c).nfkc();
    match (folded.next(), folded.next()) {
        (Some(f), None) => f,
        _ => c,
    }
}

/// `text` with every math span rendered as Unicode and `\$` as `$`; the
/// rest is unchanged. Display math (`$$...$$`) is put on a line of its own.
/// A formula that does not parse is left as written (see [`check`]).
pub fn render(text: &str) -> String {
    render_with(text, &mut |latex, out| write_math(latex, out).is_ok(), None)
}

/// [`render`], in pieces: each formula rendered (`true`) apart from the
/// text around it (`false`), so that a wrapper can keep a formula whole
/// and break it only where mathematics breaks (see [`math_breaks`]).
/// The pieces joined are [`render`]'s output.
pub fn render_pieces(text: &str) -> Vec<(String, bool)> {
    let mut ranges = Vec::new();
    let out = render_with(
        text,
        &mut |latex, out| write_math(latex, out).is_ok(),
        Some(&mut ranges),
    );
    let mut pieces = Vec::new();
    let mut at = 0;
    for r in ranges {
        if r.start > at {
            pieces.push((out[at..r.start].to_string(), false));
        }
        if r.end > r.start {
            pieces.push((out[r.clone()].to_string(), true));
        }
        at = r.end;
    }
    if at < out.len() {
        pieces.push((out[at..].to_string(), false));
    }
    pieces
}

/// Where a rendered formula may break across lines, best first: the byte
/// offsets of its spaces, each with a rank. Rank 0: beside a relation or
/// binary operator outside every bracket (`a + b`, `T ≈ …`): the place
/// mathematics breaks. Rank 1: any other space outside brackets (between
/// factors: `I₂ I₃`, `ln x`). Inside brackets the same two ranks follow
/// per level of depth (2 and 3 at depth 1, 4 and 5 at depth 2, …), so a
/// formula that must break inside a bracket breaks in the outermost one
/// it can: `√((ω₀² − ω²)² + (2ζω₀ω)²)` at its `+`, not inside `(ω₀² − ω²)`.
/// A break inside a symbol with its scripts, or inside a number, is never
/// offered.
pub fn math_breaks(rendered: &str) -> Vec<(usize, u8)> {
    const OPERATORS: &[char] = &[
        '=', '≈', '≠', '<', '>', '≤', '≥', '≡', '∝', '→', '⇒', '⇔', '↔', '∼', '~', '+', '−', '-',
        '±', '∓', '×', '·', '⋅', '÷', ',', ';',
    ];
    let mut depth: i32 = 0;
    let mut out = Vec::new();
    let chars: Vec<(usize, char)> = rendered.char_indices().collect();
    for (k, &(i, c)) in chars.iter().enumerate() {
        match c {
            '(' | '[' | '{' | '⟨' | '⌊' | '⌈' => depth += 1,
            ')' | ']' | '}' | '⟩' | '⌋' | '⌉' => depth = (depth - 1).max(0),
            ' ' => {
                let before = chars[..k].iter().rev().map(|&(_, c)| c).find(|c| *c != ' ');
                let after = chars[k + 1..].iter().map(|&(_, c)| c).find(|c| *c != ' ');
                let beside_op = before.is_some_and(|c| OPERATORS.contains(&c))
                    || after.is_some_and(|c| OPERATORS.contains(&c));
                let level = u8::try_from(depth).unwrap_or(u8::MAX / 2).min(100);
                let rank = 2 * level + u8::from(!beside_op);
                out.push((i, rank));
            }
            _ => {}
        }
    }
    out
}

/// Renders many texts, each distinct formula once (decks repeat their
/// formulas: a search index over fifty thousand cards renders a few
/// hundred). The same output as [`render`].
#[derive(Debug, Default)]
pub struct Renderer {
    /// Each formula seen, rendered (`None`: it does not parse).
    memo: std::collections::HashMap<String, Option<String>>,
}

impl Renderer {
    pub fn render(&mut self, text: &str) -> String {
        let mut math = |latex: &str, out: &mut String| {
            if let Some(done) = self.memo.get(latex) {
                return done.as_deref().map(|d| out.push_str(d)).is_some();
            }
            let mut one = String::with_capacity(latex.len());
            let ok = write_math(latex, &mut one).is_ok();
            if ok {
                out.push_str(&one);
            }
            self.memo.insert(latex.to_string(), ok.then_some(one));
            ok
        };
        render_with(text, &mut math, None)
    }
}

/// [`render`], with `math` appending one formula to the text (false: it
/// does not parse, and what it appended is taken back); `ranges`, when
/// given, receives the byte range of each formula rendered.
fn render_with(
    text: &str,
    write: &mut dyn FnMut(&str, &mut String) -> bool,
    mut ranges: Option<&mut Vec<std::ops::Range<usize>>>,
) -> String {
    let mut out = String::with_capacity(text.len());
    let mut after_display = false;
    for piece in dollar::pieces(text) {
        match piece {
            Piece::Text(mut s) => {
                if after_display {
                    s = s.trim_start_matches([' ', '\t']);
                    if !s.is_empty() && !s.starts_with('\n') {
                        out.push('\n');
                    }
                }
                out.push_str(s);
            }
            Piece::Dollar => {
                if after_display {
                    out.push('\n');
                }
                out.push('$');
            }
            Piece::Math(math) => {
                if after_display {
                    out.push('\n');
                }
                if math.display {
                    let kept = out.trim_end_matches([' ', '\t']).len();
                    out.truncate(kept);
                    if !out.is_empty() && !out.ends_with('\n') {
                        out.push('\n');
                    }
                }
                let start = out.len();
                if !write(math.latex, &mut out) {
                    out.truncate(start);
                    out.push_str(math.source);
                } else if let Some(r) = ranges.as_deref_mut() {
                    r.push(start..out.len());
                }
            }
            Piece::Unclosed { offset, .. } => {
                if after_display {
                    out.push('\n');
                }
                out.push_str(&text[offset..]);
            }
        }
        after_display = matches!(piece, Piece::Math(m) if m.display);
    }
    out
}

/// One formula (the LaTeX between the dollars) as Unicode. The error's
/// offset is a byte offset into `latex`.
pub fn math_to_unicode(latex: &str) -> Result<String, MathError> {
    let mut out = String::with_capacity(latex.len());
    match write_math(latex, &mut out) {
        Ok(()) => Ok(out),
        Err(e) => Err(MathError {
            offset: e.at.unwrap_or(0),
            message: e.message,
        }),
    }
}

/// A formula's problem, at a byte offset of the formula when known.
pub(crate) struct FormulaError {
    at: Option<usize>,
    message: String,
}

/// Longest formula rendered, in bytes: real formulas are a few hundred
/// bytes, and a runaway one (a stray `$` in a huge text) must not cost
/// seconds and hundreds of megabytes.
pub(crate) const MAX_FORMULA_BYTES: usize = 10_000;

/// Append the rendered formula to `out` (on error `out` may hold part of
/// it).
pub(crate) fn write_math(latex: &str, out: &mut String) -> Result<(), FormulaError> {
    if latex.len() > MAX_FORMULA_BYTES {
        return Err(FormulaError {
            at: None,
            message: format!(
                "formula too long ({} bytes; at most {MAX_FORMULA_BYTES}): is a `$` missing?",
                latex.len()
            ),
        });
    }
    if latex.trim().is_empty() {
        return Ok(());
    }
    let storage = Storage::new();
    let nodes = tree::build(Parser::new(latex, &storage)).map_err(|e| math_error(latex, e))?;
    unicode::render(&nodes, out);
    Ok(())
}

fn math_error(latex: &str, err: BuildError) -> FormulaError {
    match err {
        BuildError::Parser(err) => {
            let at = locate::offset(latex);
            let message = match locate::message(&err).as_str() {
                "unknown primitive command found" => {
                    let rest = &latex[at.unwrap_or(latex.len())..];
                    let name: String = rest
                        .chars()
                        .skip(1)
                        .take_while(char::is_ascii_alphabetic)
                        .collect();
                    if rest.starts_with('\\') && !name.is_empty() {
                        format!("unknown command `\\{name}`")
                    } else {
                        "unknown command".to_string()
                    }
                }
                "expected a token" => {
                    "a command is missing its argument (a symbol or a `{...}` group)".to_string()
                }
                other => other.to_string(),
            };
            FormulaError { at, message }
        }
        BuildError::Shape(what) => FormulaError {
            at: None,
            message: what.to_string(),
        },
    }
}

fn unclosed(offset: usize, display: bool) -> MathError {
    let message = if display {
        "display math `$$` is not closed (math cannot run across a blank line)"
    } else {
        "`$` is not closed: end the formula with `$`, or write a literal dollar as `\\$` \
         (a `$` followed by a digit never closes a formula)"
    };
    MathError {
        offset,
        message: message.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn required_example() {
        assert_eq!(
            math_to_unicode(r"I_1\dot\omega_1 = (I_2-I_3)\,\omega_2\omega_3").as_deref(),
            Ok("I₁ω̇₁ = (I₂ − I₃) ω₂ω₃")
        );
    }

    #[test]
    fn render_replaces_only_the_math() {
        assert_eq!(
            render(r"Euler: $I_1\dot\omega_1$, see *below*."),
            "Euler: I₁ω̇₁, see *below*."
        );
    }

    #[test]
    fn escaped_dollar_renders_as_dollar() {
        assert_eq!(render(r"costs \$5, or $x^2$"), "costs $5, or x²");
    }

    #[test]
    fn display_math_goes_on_its_own_line() {
        assert_eq!(render("so $$a = b$$ holds"), "so\na = b\nholds");
        assert_eq!(render("so\n$$a = b$$\nholds"), "so\na = b\nholds");
        assert_eq!(render("$$a$$"), "a");
        assert_eq!(render("$$a$$ $$b$$"), "a\nb");
    }

    #[test]
    fn bad_math_is_left_as_written() {
        assert_eq!(render(r"a $\foo x$ b"), r"a $\foo x$ b");
        assert_eq!(render("a $x b"), "a $x b");
    }

    #[test]
    fn text_without_math_is_unchanged() {
        let text = "Plain text, *stars*, back\\slashes and 100% Unicode ω.\n\nTwo paragraphs.";
        assert_eq!(render(text), text);
        assert!(check(text).is_empty());
    }

    #[test]
    fn check_reports_unknown_command_at_its_offset() {
        let text = r"Spin: $\omega + \foo x$.";
        assert_eq!(
            check(text),
            vec![MathError {
                offset: text.find(r"\foo").unwrap_or(usize::MAX),
                message: "unknown command `\\foo`".to_string(),
            }]
        );
    }

    #[test]
    fn check_reports_every_problem() {
        let text = r"$\foo$ then $\bar{x$ then $\frac{a}{b}$ then $x";
        let errors = check(text);
        let offsets: Vec<usize> = errors.iter().map(|e| e.offset).collect();
        // `\foo` at 1; the group opened in `\bar{x` is still open at the
        // closing `$` (offset 19); the last `$` is never closed (at 45).
        assert_eq!(offsets, vec![1, 19, 45], "{errors:?}");
        assert!(errors[1].message.contains("unbalanced group"), "{errors:?}");
        assert!(errors[2].message.contains("not closed"), "{errors:?}");
    }

    #[test]
    fn an_unclosed_dollar_is_reported_where_its_partner_is_missing() {
        let text = "Intro.\n\nThe moment $I = mr^2$ holds, and the speed $\\omega is measured in radians per second while $L = I\\omega$ follows.\n\nMore $x$.";
        let errors = check(text);
        assert_eq!(errors.len(), 1, "{errors:?}");
        assert_eq!(errors[0].offset, text.find("$\\omega").unwrap());
        assert!(
            errors[0].message.contains("most likely not closed"),
            "{errors:?}"
        );
        // A lone last `$` stays where it is.
        let errors = check("a $x$ then $y");
        assert_eq!(errors.len(), 1, "{errors:?}");
        assert_eq!(errors[0].offset, 11);
    }

    #[test]
    fn check_reports_stray_brace_at_it() {
        let text = "Here: $a + b} = c$";
        let errors = check(text);
        assert_eq!(errors.len(), 1);
        assert_eq!(errors[0].offset, text.find('}').unwrap_or(usize::MAX));
        assert!(errors[0].message.contains("unbalanced"), "{errors:?}");
    }

    #[test]
    fn check_reports_unclosed_display_math() {
        let errors = check("Look: $$x = 1$ here");
        assert_eq!(errors.len(), 1);
        assert_eq!(errors[0].offset, 6);
        assert!(errors[0].message.contains("$$"));
    }

    #[test]
    fn check_reports_missing_argument() {
        let errors = check(r"$\frac{a}$");
        assert_eq!(errors.len(), 1);
        assert!(
            errors[0].message.contains("missing its argument"),
            "{errors:?}"
        );
    }

    #[test]
    fn math_to_unicode_reports_offset_in_the_formula() {
        let err = math_to_unicode(r"a = \qux").unwrap_err();
        assert_eq!(err.offset, 4);
        assert_eq!(err.message, "unknown command `\\qux`");
    }

    #[test]
    fn overlong_formula_is_an_error_at_its_dollar() {
        let text = format!("ok ${}$", "x+".repeat(MAX_FORMULA_BYTES));
        let errors = check(&text);
        assert_eq!(errors.len(), 1);
        assert_eq!(errors[0].offset, 3, "at the opening `$`");
        assert!(errors[0].message.contains("too long"), "{errors:?}");
        assert_eq!(render(&text), text);
        let just_fits = "x".repeat(MAX_FORMULA_BYTES);
        assert_eq!(
            math_to_unicode(&just_fits).as_deref(),
            Ok(just_fits.as_str())
        );
    }

    #[test]
    fn deep_nesting_is_an_error_not_a_crash() {
        let deep = format!("{}x{}", "{".repeat(2000), "}".repeat(2000));
        let err = math_to_unicode(&deep).unwrap_err();
        assert!(err.message.contains("nested too deeply"), "{err:?}");
        // No position inside the formula: the error is at its `$`.
        let errors = check(&format!("a ${deep}$"));
        assert_eq!(errors.len(), 1);
        assert_eq!(errors[0].offset, 2);
        let deep_frac = r"\frac{".repeat(300) + &"}{x}".repeat(300);
        assert!(math_to_unicode(&deep_frac).is_err());
    }

    /// Deterministic random texts built from LaTeX and markup fragments:
    /// nothing panics and every error offset can be turned into line:col.
    #[test]
    fn random_texts_give_locatable_errors() {
        const FRAGMENTS: &[&str] = &[
            "$",
            "$$",
            r"\$",
            r"\frac",
            r"\sqrt",
            "{",
            "}",
            "[",
            "]",
            "x",
            "ω",
            "_",
            "^",
            r"\left(",
            r"\right)",
            r"\begin{matrix}",
            r"\end{matrix}",
            "&",
            r"\\",
            r"\dot",
            r"\vec",
            r"\text{a b}",
            r"\mathbf",
            "1.5",
            ",",
            "-",
            "+",
            "=",
            r"\,",
            r"\quad",
            r"\big(",
            r"\not",
            r"\foo",
            "#",
            r"\begin{cases}",
            r"\end{cases}",
            r"\sum",
            "%",
            "'",
            r"\",
            "é",
            " ",
            "\n",
            "\n\n",
            "*",
            "**",
            "- ",
            r"\operatorname{f}",
            "~",
            r"\hspace{3cm}",
        ];
        let mut seed: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        for _ in 0..3000 {
            let len = (next() % 16) as usize;
            let text: String = (0..len)
                .map(|_| FRAGMENTS[(next() % FRAGMENTS.len() as u64) as usize])
                .collect();
            for e in check(&text) {
                assert!(
                    e.offset <= text.len() && text.is_char_boundary(e.offset),
                    "{text:?}: {e:?}"
                );
            }
            let _ = render(&text);
            let _ = markup::parse(&text);
        }
    }

    #[test]
    fn odd_bytes_never_panic() {
        for text in [
            "$",
            "$$",
            "$$$",
            "$$$$",
            "\\",
            "\\$",
            "$\\$",
            "$\\",
            "$x\\",
            "$$\\$$",
            "\u{0}$\u{7f}$",
            "$ω\\",
            "$\\frac$",
            "$^$",
            "$_^$",
            "$&$",
            "$\\\\$",
            "$#$",
            "$\\left($",
            "$}{$",
            "$\\begin{matrix}a&b\\\\c\\end{matrix}$",
            "$\\def\\a{\\a}\\a$",
        ] {
            let _ = render(text);
            let _ = check(text);
        }
    }
}

#[cfg(test)]
mod variable_names {
    use super::variable_name as shown_name;

    #[test]
    fn greek_names_show_as_letters_and_others_as_written() {
        assert_eq!(shown_name("theta"), "θ");
        assert_eq!(shown_name("omega2"), "ω₂");
        assert_eq!(shown_name("phi_1"), "ϕ₁");
        assert_eq!(shown_name("Omega"), "Ω");
        assert_eq!(shown_name("x"), "x");
        assert_eq!(shown_name("xc"), "xc");
        assert_eq!(shown_name("thetadot"), "thetadot");
        assert_eq!(shown_name("energy"), "energy");
        assert_eq!(shown_name("eta_b"), "eta_b");
    }
}

#[cfg(test)]
mod compat {
    use super::{compat_char, warnings};

    #[test]
    fn compatibility_characters_fold_one_for_one() {
        assert_eq!(compat_char('\u{b5}'), '\u{3bc}');
        assert_eq!(compat_char('\u{2126}'), '\u{3a9}');
        assert_eq!(compat_char('a'), 'a');
        assert_eq!(compat_char('ω'), 'ω');
        // A ligature would be two letters: kept as it is.
        assert_eq!(compat_char('\u{fb01}'), '\u{fb01}');
    }

    #[test]
    fn the_micro_sign_in_prose_is_a_warning_at_its_place() {
        let w = warnings("a muon lives 2.2 \u{b5}s");
        assert_eq!(w.len(), 1, "{w:?}");
        assert_eq!(w[0].offset, "a muon lives 2.2 ".len());
        assert!(w[0].message.contains("micro sign"), "{}", w[0].message);
        assert!(warnings("a muon lives 2.2 \u{3bc}s").is_empty());
    }
}
