//! `report.csv`: every table of the report in one sheet, one row per item,
//! the `section` column saying which table it belongs to: `card` (its text
//! in `text`), `prompt` (first attempts: `count` right of `total` with a
//! verdict), `answer` (the right answer, formula and median measured in
//! `text`), `no_verdict` (first attempts left before the run's end that no
//! answer could grade), `wrong_choice` (a wrong first prediction, or a bin
//! of numbers around a value typed), `retry` (later attempts: `learners`
//! who retried, `count` right of `total` judged), `misconception` (the
//! deck's misconception in `id`, `learners` whose wrong answers stood for
//! it, `count` such attempts, its title and prompts in `text`) and `tag`
//! (worst retention first). New sections may be added; columns never change.
//!
//! A spreadsheet runs a cell that starts with `=`, `+`, `-` or `@` as a
//! formula (and some read a leading tab or carriage return the same way):
//! a learner's prediction `=HYPERLINK(…)` must stay text. Every text cell
//! that starts so is written with a `'` in front (OWASP's rule for CSV
//! injection), except a plain decimal number (a prediction `-9.8` typed by
//! a learner), which a spreadsheet reads as the number it is. The numeric
//! columns are ours (counts, shares from 0 to 1, difficulties from 1 to
//! 10) and never start with such a character.

use std::borrow::Cow;

use crate::interop::class::ClassReport;
use crate::text::num::Num;

/// The CSV header: a contract for instructors' spreadsheets.
pub const HEADER: [&str; 9] = [
    "section",
    "deck",
    "id",
    "learners",
    "count",
    "total",
    "share",
    "mean_difficulty",
    "text",
];

/// A text cell a spreadsheet will not run as a formula.
pub fn text_cell(s: &str) -> Cow<'_, str> {
    if s.starts_with(['=', '+', '-', '@', '\t', '\r']) && !is_plain_number(s) {
        Cow::Owned(format!("'{s}"))
    } else {
        Cow::Borrowed(s)
    }
}

/// `-9.8`, `+3`, `1.5e-3`: a sign, digits, an optional fraction and
/// exponent, nothing else.
fn is_plain_number(s: &str) -> bool {
    let digits = |t: &str| !t.is_empty() && t.bytes().all(|b| b.is_ascii_digit());
    let s = s.strip_prefix(['+', '-']).unwrap_or(s);
    let (mantissa, exponent) = match s.split_once(['e', 'E']) {
        Some((m, e)) => (m, Some(e.strip_prefix(['+', '-']).unwrap_or(e))),
        None => (s, None),
    };
    let mantissa_ok = match mantissa.split_once('.') {
        Some((whole, frac)) => digits(whole) && digits(frac),
        None => digits(mantissa),
    };
    mantissa_ok && exponent.is_none_or(digits)
}

pub fn table(r: &ClassReport) -> anyhow::Result<String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(HEADER)?;
    let share = |n: usize, total: usize| {
        if total == 0 {
            String::new()
        } else {
            Num(n as f64 / total as f64).to_string()
        }
    };
    for c in &r.cards {
        w.write_record([
            "card",
            &text_cell(&c.deck),
            &text_cell(&super::card_name(c)),
            &c.learners.to_string(),
            &c.lapsed.to_string(),
            &c.learners.to_string(),
            &share(c.lapsed, c.learners),
            &c.mean_difficulty
                .map_or_else(String::new, |d| Num(d).to_string()),
            &text_cell(c.text.as_deref().unwrap_or("")),
        ])?;
    }
    for p in &r.prompts {
        w.write_record([
            "prompt",
            &text_cell(&p.deck),
            &text_cell(&p.prompt),
            &p.learners.to_string(),
            &p.right.to_string(),
            &p.judged().to_string(),
            &share(p.right, p.judged()),
            "",
            &text_cell(p.text.as_deref().unwrap_or("")),
        ])?;
        if let Some(a) = super::answer_line(p) {
            w.write_record([
                "answer",
                &text_cell(&p.deck),
                &text_cell(&p.prompt),
                "",
                "",
                "",
                "",
                "",
                &text_cell(&a),
            ])?;
        }
        if p.no_verdict > 0 {
            w.write_record([
                "no_verdict",
                &text_cell(&p.deck),
                &text_cell(&p.prompt),
                &p.learners.to_string(),
                &p.no_verdict.to_string(),
                &p.learners.to_string(),
                &share(p.no_verdict, p.learners),
                "",
                "",
            ])?;
        }
        if p.retries.attempts > 0 {
            let r = &p.retries;
            w.write_record([
                "retry",
                &text_cell(&p.deck),
                &text_cell(&p.prompt),
                &r.learners.to_string(),
                &r.right.to_string(),
                &r.judged.to_string(),
                &share(r.right, r.judged),
                "",
                &format!("{} retries", r.attempts),
            ])?;
        }
        let wrong: usize = p.wrong.iter().map(|c| c.learners).sum();
        for c in &p.wrong {
            w.write_record([
                "wrong_choice",
                &text_cell(&p.deck),
                &text_cell(&p.prompt),
                &p.learners.to_string(),
                &c.learners.to_string(),
                &wrong.to_string(),
                &share(c.learners, wrong),
                "",
                &text_cell(&super::choice_name(c)),
            ])?;
        }
    }
    for m in &r.misconceptions {
        w.write_record([
            "misconception",
            &text_cell(&m.deck),
            &text_cell(&m.id),
            &m.learners.to_string(),
            &m.attempts.to_string(),
            "",
            "",
            "",
            &text_cell(&super::misconception_text(m)),
        ])?;
    }
    for t in &r.tags {
        w.write_record([
            "tag",
            "",
            &text_cell(&t.tag),
            &t.learners.to_string(),
            &t.recalled.to_string(),
            &t.reviews.to_string(),
            &share(t.recalled, t.reviews),
            "",
            "",
        ])?;
    }
    Ok(String::from_utf8(w.into_inner()?)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formulas_are_neutralised_and_numbers_kept() {
        for (cell, want) in [
            ("=HYPERLINK(\"x\")", "'=HYPERLINK(\"x\")"),
            ("+1+1", "'+1+1"),
            ("-2+3+cmd|' /C calc'!A0", "'-2+3+cmd|' /C calc'!A0"),
            ("@SUM(A1)", "'@SUM(A1)"),
            ("\t=1", "'\t=1"),
            ("\r=1", "'\r=1"),
            ("-", "'-"),
            ("-e5", "'-e5"),
            ("-9.8", "-9.8"),
            ("+3", "+3"),
            ("-1.5e-3", "-1.5e-3"),
            ("torque", "torque"),
            ("", ""),
        ] {
            assert_eq!(text_cell(cell), want, "{cell:?}");
        }
    }

    proptest::proptest! {
        /// No cell written starts with a formula character unless it is a
        /// plain number. Run longer with
        /// `PROPTEST_CASES=100000 cargo test --lib cmd::report`.
        #[test]
        fn no_text_cell_starts_a_formula(s in "[-=+@\t\r0-9.eE a-z'\"(]{0,12}") {
            let cell = text_cell(&s);
            let risky = cell.starts_with(['=', '+', '-', '@', '\t', '\r']);
            proptest::prop_assert!(!risky || s.parse::<f64>().is_ok_and(f64::is_finite), "{:?}", cell);
            let quoted = format!("'{}", s);
            proptest::prop_assert!(cell == s || cell == quoted);
        }
    }
}
