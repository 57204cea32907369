//! Cloze deletions in Anki's syntax: `{{c1::answer}}` and
//! `{{c1::answer::hint}}`. Each number is one review item; its front shows
//! the text with that number's deletions blanked and the others revealed.
//!
//! Deletions may sit around math (`{{c1::$\omega_2$}}`) and inside it, as in
//! Anki: `$I_1\dot\omega_1 = {{c1::(I_2 - I_3)}}\,\omega_2\omega_3$` hides
//! part of the formula, and the gap is drawn inside the rendered formula.
//! Inside math a marker is `{{c` and a digit; any other `{{` there is
//! LaTeX's own (`$x^{{2}}$`), and a deletion's closing `}}` is the first one
//! outside the braces it opened itself, so `{{c1::\frac{a}{b}}}` reads.
//! A marker that cannot be read is an error with its offset, never dropped.

use std::collections::BTreeSet;

/// The largest deletion number accepted (Anki's own limit is far above
/// anything a card needs; this keeps `c` numbers short and finite).
pub(crate) const MAX_NUMBER: u16 = 999;

/// One part of a cloze text.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Piece<'a> {
    /// Text shown as it is (may hold math).
    Text(&'a str),
    Deletion {
        number: u16,
        answer: &'a str,
        hint: Option<&'a str>,
        /// Whether the deletion sits inside a formula (`$...{{c1::x}}...$`):
        /// its answer is LaTeX, and the gap is drawn in the rendered formula.
        math: bool,
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
            b'{' if bytes.get(i + 1) == Some(&b'{') && (!math || is_math_marker(bytes, i)) => {
                if i > plain_from {
                    pieces.push(Piece::Text(&text[plain_from..i]));
                }
                let (piece, end) = deletion(text, i, math)?;
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

/// Whether the `{{` at `i`, inside math, is a cloze marker: `{{c` and a
/// digit (LaTeX writes `{{c_1}}` or `{{x}}`, never that).
fn is_math_marker(bytes: &[u8], i: usize) -> bool {
    bytes.get(i + 2) == Some(&b'c') && bytes.get(i + 3).is_some_and(u8::is_ascii_digit)
}

/// Reads the deletion whose `{{` is at `start` (inside a formula when
/// `in_math`); returns it and the offset after its `}}`.
fn deletion(text: &str, start: usize, in_math: bool) -> Result<(Piece<'_>, usize), ClozeError> {
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
    // Inside a formula it is the first `}}` outside the deletion's own
    // braces, and the formula may not end before it.
    let bytes = text.as_bytes();
    let mut math = false;
    let mut depth = 0usize;
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
            b'$' if in_math => {
                return Err(err(
                    i,
                    format!("the formula ends inside cloze deletion c{number}"),
                    Some(
                        "a deletion that starts inside `$...$` must end inside it: close it with `}}` before the `$`, or put the whole formula in the deletion ({{c1::$...$}})",
                    ),
                ));
            }
            b'{' if in_math && bytes.get(i + 1) == Some(&b'{') && is_math_marker(bytes, i) => {
                return Err(err(
                    i,
                    "cloze deletions cannot be nested",
                    Some("close the outer deletion first, or give the inner text its own"),
                ));
            }
            b'{' if in_math => {
                depth += 1;
                i += 1;
            }
            b'}' if in_math && depth > 0 => {
                depth -= 1;
                i += 1;
            }
            b'}' if in_math && bytes.get(i + 1) == Some(&b'}') => break i,
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
            math: in_math,
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
/// part asked about (the blank on the front, the answer on the back). A
/// formula holding the asked deletion comes already rendered, cut at the
/// gap (its `$` escaped as `\$`), so rendering every segment as markup
/// draws the gap inside the formula.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Segment {
    pub text: String,
    pub asked: bool,
}

/// The front for deletion `number`: its deletions as `[…]` (or `[hint]`),
/// every other deletion revealed.
pub fn front(text: &str, number: u16) -> Vec<Segment> {
    shown(text, number, true).0
}

/// The back for deletion `number`: the whole text, its answers marked.
pub fn back(text: &str, number: u16) -> Vec<Segment> {
    shown(text, number, false).0
}

/// The text with every deletion revealed and no markers (for search): math
/// stays LaTeX, a deletion inside a formula as its `{answer}`.
pub fn revealed(text: &str) -> String {
    shown(text, 0, false)
        .0
        .into_iter()
        .map(|s| s.text)
        .collect()
}

/// A formula that can be drawn for deletion `number`, shown and hidden:
/// every formula holding one of its deletions renders with the gap in it
/// and with the answer in it (empty when the text does not parse, which
/// [`parse`] reports).
pub(crate) fn render_errors(text: &str) -> Vec<ClozeError> {
    let mut errors: Vec<ClozeError> = Vec::new();
    for number in numbers(text) {
        for blank in [true, false] {
            for (offset, message) in shown(text, number, blank).1 {
                if errors.iter().any(|e| e.offset == offset) {
                    continue;
                }
                let state = if blank { "hidden" } else { "shown" };
                errors.push(err(
                    offset,
                    format!("this formula cannot be drawn with c{number} {state}: {message}"),
                    Some("a deletion inside math holds a whole part of the formula, e.g. {{c1::(I_2 - I_3)}} or \\frac{ {{c1::a}} }{b}"),
                ));
            }
        }
    }
    errors.sort_by_key(|e| e.offset);
    errors
}

/// Where, in a formula with an asked deletion, its gap goes (front) and
/// where its answer starts and ends (back): characters of Unicode's private
/// use area carried through the renderer inside `\text{}`.
const GAP: char = '\u{E000}';
const START: char = '\u{E001}';
const END: char = '\u{E002}';

/// A formula holding a deletion, collected until its closing `$`.
struct Formula {
    /// Byte offset of its opening delimiter in the text.
    offset: usize,
    open: &'static str,
    /// The LaTeX with the deletions replaced: revealed ones by `{answer}`,
    /// the asked ones by the marks above.
    latex: String,
    /// What each [`GAP`] shows, in order (`[…]` or `[hint]`).
    gaps: Vec<String>,
    /// The answers of the asked deletions (their marks are counted).
    answers: Vec<String>,
    asked: bool,
}

/// The segments being built: plain runs are joined.
#[derive(Default)]
struct Out {
    segs: Vec<Segment>,
    errors: Vec<(usize, String)>,
}

impl Out {
    fn push(&mut self, text: &str, asked: bool) {
        if text.is_empty() {
            return;
        }
        match self.segs.last_mut() {
            Some(last) if !last.asked && !asked => last.text.push_str(text),
            _ => self.segs.push(Segment {
                text: text.to_string(),
                asked,
            }),
        }
    }

    /// A formula's end: as LaTeX when nothing in it is asked, else drawn
    /// here with the gap (or the marked answer) inside it.
    fn formula(&mut self, f: Formula, close: &str) {
        if !f.asked {
            self.push(f.open, false);
            self.push(&f.latex, false);
            self.push(close, false);
            return;
        }
        let drawn = if close.is_empty() {
            Err("the formula is not closed".to_string())
        } else {
            flipcard_text::math_to_unicode(&f.latex).map_err(|e| e.message)
        };
        let marks_kept = |s: &str| {
            s.chars().filter(|&c| c == GAP).count() == f.gaps.len()
                && s.chars().filter(|&c| c == START).count() == f.answers.len()
                && s.chars().filter(|&c| c == END).count() == f.answers.len()
        };
        match drawn {
            Ok(unicode) if marks_kept(&unicode) => {
                let display = f.open == "$$";
                if display && self.segs.last().is_some_and(|s| !s.text.ends_with('\n')) {
                    self.push("\n", false);
                }
                self.marked(&unicode, &f.gaps, &|s| s.replace('$', "\\$"));
                if display {
                    self.push("\n", false);
                }
            }
            drawn => {
                self.errors.push((
                    f.offset,
                    drawn
                        .err()
                        .unwrap_or_else(|| "the renderer cannot keep the gap in place".to_string()),
                ));
                // Shown as written, the asked part still apart.
                let raw: String = f
                    .latex
                    .replace(&format!("\\text{{{START}}}"), &START.to_string())
                    .replace(&format!("\\text{{{END}}}"), &END.to_string())
                    .replace(&format!("\\text{{{GAP}}}"), &GAP.to_string());
                self.push(&f.open.replace('$', "\\$"), false);
                self.marked(&raw, &f.gaps, &|s| s.replace('$', "\\$"));
                self.push(&close.replace('$', "\\$"), false);
            }
        }
    }

    /// `s` cut at its marks: a gap becomes the next of `gaps`, the text
    /// between a start and an end is the asked part.
    fn marked(&mut self, s: &str, gaps: &[String], escape: &dyn Fn(&str) -> String) {
        let mut gaps = gaps.iter();
        let mut asked = false;
        let mut run = String::new();
        for c in s.chars() {
            match c {
                GAP | START | END => {
                    // The marks are atoms to the renderer, which spaces
                    // them: the asked part is shown without that space.
                    let part = if asked { run.trim() } else { run.as_str() };
                    self.push(&escape(part), asked);
                    run.clear();
                    match c {
                        GAP => self.push(&escape(gaps.next().map_or("[…]", |g| g)), true),
                        START => asked = true,
                        _ => asked = false,
                    }
                }
                c => run.push(c),
            }
        }
        self.push(&escape(&run), asked);
    }
}

/// The math delimiters of `s` as `parse` reads them: offset and length
/// (`$` or `$$`), a backslash taking the next character with it.
fn delimiters(s: &str) -> impl Iterator<Item = (usize, usize)> + '_ {
    let bytes = s.as_bytes();
    let mut i = 0;
    std::iter::from_fn(move || {
        while i < bytes.len() {
            match bytes[i] {
                b'\\' => i += 2,
                b'$' => {
                    let len = if bytes.get(i + 1) == Some(&b'$') {
                        2
                    } else {
                        1
                    };
                    i += len;
                    return Some((i - len, len));
                }
                _ => i += 1,
            }
        }
        None
    })
}

fn shown(text: &str, number: u16, blank: bool) -> (Vec<Segment>, Vec<(usize, String)>) {
    let Ok(pieces) = parse(text) else {
        let seg = Segment {
            text: text.to_string(),
            asked: false,
        };
        return (vec![seg], Vec::new());
    };
    let mut out = Out::default();
    let mut formula: Option<Formula> = None;
    for p in pieces {
        match p {
            Piece::Text(t) => {
                let base = t.as_ptr() as usize - text.as_ptr() as usize;
                let mut from = 0;
                for (at, len) in delimiters(t) {
                    match formula.take() {
                        Some(mut f) => {
                            f.latex.push_str(&t[from..at]);
                            out.formula(f, &t[at..at + len]);
                        }
                        None => {
                            out.push(&t[from..at], false);
                            formula = Some(Formula {
                                offset: base + at,
                                open: if len == 2 { "$$" } else { "$" },
                                latex: String::new(),
                                gaps: Vec::new(),
                                answers: Vec::new(),
                                asked: false,
                            });
                        }
                    }
                    from = at + len;
                }
                match &mut formula {
                    Some(f) => f.latex.push_str(&t[from..]),
                    None => out.push(&t[from..], false),
                }
            }
            Piece::Deletion {
                number: n,
                answer,
                hint,
                math: true,
            } => {
                let f = formula.get_or_insert_with(|| Formula {
                    offset: answer.as_ptr() as usize - text.as_ptr() as usize,
                    open: "",
                    latex: String::new(),
                    gaps: Vec::new(),
                    answers: Vec::new(),
                    asked: false,
                });
                if n != number {
                    f.latex.push('{');
                    f.latex.push_str(answer);
                    f.latex.push('}');
                } else if blank {
                    f.asked = true;
                    f.latex.push_str(&format!("{{\\text{{{GAP}}}}}"));
                    f.gaps.push(format!("[{}]", hint.unwrap_or("…")));
                } else {
                    f.asked = true;
                    f.latex
                        .push_str(&format!("{{\\text{{{START}}}{answer}\\text{{{END}}}}}"));
                    f.answers.push(answer.to_string());
                }
            }
            Piece::Deletion {
                number: n,
                answer,
                hint,
                math: false,
            } => {
                if let Some(f) = formula.take() {
                    // Unreachable for a text `parse` accepted; kept apart.
                    out.formula(f, "");
                }
                if n != number {
                    out.push(answer, false);
                } else if blank {
                    out.push(&format!("[{}]", hint.unwrap_or("…")), true);
                } else {
                    out.push(answer, true);
                }
            }
        }
    }
    if let Some(f) = formula {
        out.formula(f, "");
    }
    if out.segs.last().is_some_and(|s| !s.asked && s.text == "\n") {
        out.segs.pop();
    }
    (out.segs, out.errors)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

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
                hint: None,
                math: false
            }
        );
    }

    const EULER: &str = r"$I_1\dot\omega_1 = {{c1::(I_2 - I_3)}}\,\omega_2\omega_3$";

    #[test]
    fn a_deletion_inside_math_is_an_item() {
        assert_eq!(numbers(EULER).into_iter().collect::<Vec<_>>(), [1]);
        let pieces = parse(EULER).unwrap();
        assert_eq!(
            pieces[1],
            Piece::Deletion {
                number: 1,
                answer: "(I_2 - I_3)",
                hint: None,
                math: true
            }
        );
    }

    #[test]
    fn the_gap_is_drawn_inside_the_rendered_formula() {
        assert_eq!(joined(&front(EULER, 1)), "I₁ω̇₁ = <[…]> ω₂ω₃");
        assert_eq!(joined(&back(EULER, 1)), "I₁ω̇₁ = <(I₂ − I₃)> ω₂ω₃");
        let hinted = r"Euler: $\tau = {{c1::I\alpha::product}}$ and {{c2::torque}}.";
        assert_eq!(
            joined(&front(hinted, 1)),
            "Euler: τ = <[product]> and torque."
        );
        // The other item reveals the formula, left as LaTeX for the screen.
        assert_eq!(
            joined(&front(hinted, 2)),
            r"Euler: $\tau = {I\alpha}$ and <[…]>."
        );
        assert_eq!(
            revealed(EULER),
            r"$I_1\dot\omega_1 = {(I_2 - I_3)}\,\omega_2\omega_3$"
        );
        // A whole argument of a command, and braces of its own.
        let frac = r"$\omega = \frac{ {{c1::\sqrt{k}}} }{m}$";
        assert_eq!(joined(&front(frac, 1)), "ω = <[…]>/m");
        assert_eq!(joined(&back(frac, 1)), "ω = <√k>/m");
        assert!(render_errors(frac).is_empty());
        // A dollar in the rendered formula is not read as math again.
        assert_eq!(joined(&back(r"$\${{c1::x}}$", 1)), r"\$<x>");
    }

    #[test]
    fn display_math_with_a_gap_stands_on_its_own_line() {
        let t = r"so $$E = {{c1::mc^2}}$$ holds";
        assert_eq!(joined(&front(t, 1)), "so \nE = <[…]>\n holds");
    }

    #[test]
    fn a_formula_that_cannot_be_drawn_is_an_error_at_its_dollar() {
        let t = r"ok $\frac{a}{{c1::b}} \left( {{c2::\right)}}$";
        let errors = render_errors(t);
        assert!(!errors.is_empty());
        assert!(errors.iter().all(|e| e.offset == 3), "{errors:?}");
        assert!(errors[0].message.contains("cannot be drawn"), "{errors:?}");
        // Still shown, as written, the gap apart.
        let front = joined(&front(t, 2));
        assert!(front.contains("<[…]>"), "{front}");
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
            // Inside math: a marker is `{{c` and a digit, read as strictly.
            ("$a = {{c1:b}}$", 5, "followed by `::`"),
            ("$a = {{c1::b$ c", 12, "formula ends inside"),
            ("$a = {{c1::b", 5, "never closed"),
            ("$a = {{c1::}}$", 5, "is empty"),
            ("$a = {{c1::x {{c2::y}} }}$", 13, "nested"),
            ("$a = {{c01::b}}$", 5, "from 1 to"),
        ];
        for (text, offset, says) in cases {
            let e = parse(text).unwrap_err();
            assert_eq!(e.offset, offset, "{text}: {e:?}");
            assert!(e.message.contains(says), "{text}: {}", e.message);
        }
    }

    /// One part of a generated cloze text: prose, a formula with
    /// deletions inside it, or a deletion around prose.
    #[derive(Debug, Clone)]
    enum Part {
        Prose(String),
        /// LaTeX pieces, each either plain or a deletion (number, answer).
        Formula(Vec<(String, Option<u16>)>),
        Deletion(u16, String),
    }

    fn part() -> impl Strategy<Value = Part> {
        let prose = "[a-z ,.ω]{1,12}".prop_map(Part::Prose);
        let latex = prop::sample::select(vec![
            "x",
            "I_2",
            r"\omega_3",
            " + ",
            "x^{2}",
            r"\frac{a}{b}",
            r"\,",
            "(I_2 - I_3)",
            "{{y}}",
            "=",
            r"\sqrt{k}",
            "{c}",
        ])
        .prop_map(str::to_string);
        let answer = prop::sample::select(vec![
            "a",
            r"\dot\omega",
            "(I_2 - I_3)",
            r"\frac{1}{2}",
            "{b}c",
        ])
        .prop_map(str::to_string);
        let item = prop_oneof![
            latex.clone().prop_map(|l| (l, None)),
            (1u16..4, answer).prop_map(|(n, a)| (a, Some(n))),
        ];
        prop_oneof![
            prose,
            prop::collection::vec(item, 1..6).prop_map(Part::Formula),
            (1u16..4, "[a-z]{1,6}").prop_map(|(n, a)| Part::Deletion(n, a)),
        ]
    }

    /// The text, the text outside the markers, and the text revealed.
    fn written(parts: &[Part]) -> (String, String, String) {
        let (mut text, mut outside, mut shown) = (String::new(), String::new(), String::new());
        for p in parts {
            match p {
                Part::Prose(s) => {
                    for out in [&mut text, &mut outside, &mut shown] {
                        out.push_str(s);
                    }
                }
                Part::Deletion(n, a) => {
                    text.push_str(&format!("{{{{c{n}::{a}}}}}"));
                    shown.push_str(a);
                }
                Part::Formula(items) => {
                    // `$x$$y$` would read `$$`: formulas are kept apart.
                    let sep = if text.ends_with('$') { " $" } else { "$" };
                    for out in [&mut text, &mut outside, &mut shown] {
                        out.push_str(sep);
                    }
                    for (l, n) in items {
                        match n {
                            None => {
                                for out in [&mut text, &mut outside, &mut shown] {
                                    out.push_str(l);
                                }
                            }
                            Some(n) => {
                                text.push_str(&format!("{{{{c{n}::{l}}}}}"));
                                shown.push_str(&format!("{{{l}}}"));
                            }
                        }
                    }
                    for out in [&mut text, &mut outside, &mut shown] {
                        out.push('$');
                    }
                }
            }
        }
        (text, outside, shown)
    }

    proptest! {
        /// Deletions inside and outside math are all read, the text outside
        /// the markers comes back unchanged, and every item's front and back
        /// can be built.
        #[test]
        fn cloze_in_math_round_trips(parts in prop::collection::vec(part(), 0..8)) {
            let (text, outside, shown) = written(&parts);
            let pieces = parse(&text).map_err(|e| TestCaseError::fail(format!("{text}: {e:?}")))?;
            let plain: String = pieces
                .iter()
                .filter_map(|p| match p {
                    Piece::Text(t) => Some(*t),
                    Piece::Deletion { .. } => None,
                })
                .collect();
            prop_assert_eq!(plain, outside);
            prop_assert_eq!(revealed(&text), shown);
            let expected: BTreeSet<u16> = parts
                .iter()
                .flat_map(|p| match p {
                    Part::Deletion(n, _) => vec![*n],
                    Part::Formula(items) => items.iter().filter_map(|(_, n)| *n).collect(),
                    Part::Prose(_) => vec![],
                })
                .collect();
            prop_assert_eq!(numbers(&text), expected.clone());
            prop_assert!(render_errors(&text).is_empty(), "{}: {:?}", text, render_errors(&text));
            for n in expected {
                let f = front(&text, n);
                prop_assert!(f.iter().any(|s| s.asked), "{}: c{} {:?}", text, n, f);
                let b = back(&text, n);
                prop_assert!(b.iter().any(|s| s.asked), "{}: c{} {:?}", text, n, b);
            }
        }

        /// Any text: parsing, the fronts and backs and the render check
        /// never panic, and an error's offset is inside the text.
        #[test]
        fn any_text_is_read_or_refused(text in r"(\$|\{\{c1::|\{\{c|\}\}|\{|\}|::|\\|[a-z ]|\\frac|\{\{|c2|:|\$\$|é)*") {
            match parse(&text) {
                Ok(_) => {
                    for e in render_errors(&text) {
                        prop_assert!(e.offset <= text.len() && text.is_char_boundary(e.offset));
                    }
                    for n in numbers(&text) {
                        let _ = front(&text, n);
                        let _ = back(&text, n);
                    }
                }
                Err(e) => prop_assert!(e.offset <= text.len() && text.is_char_boundary(e.offset), "{:?}", e),
            }
            let _ = revealed(&text);
        }
    }
}
