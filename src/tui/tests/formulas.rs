//! Formulas are never torn: every text of the bundled decks that holds
//! math, wrapped as the screens wrap it at every width from 20 to 160
//! columns, breaks only at spaces (never inside a symbol with its scripts
//! or inside a number), and a formula breaks inside brackets only when
//! breaking outside them cannot make it fit.

use ratatui::style::Style;

use crate::tui::wrap::{Run, line_text, math_runs, wrap};

/// Every text with a formula in the bundled decks, in both languages.
fn texts() -> Vec<String> {
    let loaded = crate::bundled::load();
    let mut out = Vec::new();
    for deck in &loaded.decks {
        let mut all: Vec<&crate::text::Text> = Vec::new();
        for c in &deck.cards {
            all.extend([&c.front, &c.back]);
        }
        for s in &deck.sections {
            all.push(&s.body);
        }
        for p in &deck.prompts {
            all.push(&p.question);
            if let crate::deck::Answer::Number {
                formula: Some(f), ..
            } = &p.answer
            {
                all.push(f);
            }
        }
        for t in all {
            for text in t.0.values() {
                for para in text.split("\n\n") {
                    if para.contains('$') && !para.contains("$$") {
                        out.push(para.to_string());
                    }
                }
            }
        }
    }
    out
}

fn squash(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

#[test]
fn no_line_break_splits_a_token_in_any_bundled_formula() {
    let texts = texts();
    assert!(texts.len() > 100, "only {} texts with math", texts.len());
    let mut checked = 0;
    for text in &texts {
        let rendered = crate::text::render(text);
        let longest = rendered
            .split_whitespace()
            .map(crate::tui::wrap::columns)
            .max()
            .unwrap_or(0);
        for width in 20..=160 {
            if longest > width {
                // A single token wider than the line must be cut somewhere.
                continue;
            }
            let lines = wrap(
                &math_runs(text, Style::default()),
                width,
                Run::new("", Style::default()),
                Run::new("", Style::default()),
            );
            for l in &lines {
                let w = crate::tui::wrap::columns(&line_text(l));
                assert!(w <= width, "{w} > {width}: {:?}", line_text(l));
            }
            // Every line break stands where the text had a space: joined
            // with spaces, the lines give the text back.
            let joined: Vec<String> = lines.iter().map(line_text).collect();
            assert_eq!(
                squash(&joined.join(" ")),
                squash(&rendered),
                "at {width} columns a break fell inside a token:\n{}",
                joined.join("\n")
            );
            // A number keeps its unit: no line ends in a number whose unit
            // starts the next.
            for pair in joined.windows(2) {
                let end = pair[0].trim_end();
                let next = pair[1].split_whitespace().next().unwrap_or("");
                let unit = next.trim_end_matches([',', '.', ';', ':', ')']);
                assert!(
                    !(end.ends_with(|c: char| c.is_ascii_digit())
                        && ["s", "m", "m/s²", "rad/s", "d", "kg", "Hz"].contains(&unit)),
                    "a number torn from its unit at {width} columns:\n{}",
                    joined.join("\n")
                );
            }
            checked += 1;
        }
    }
    assert!(checked > 10_000, "{checked}");
}

#[test]
fn a_long_formula_breaks_at_a_top_level_operator_before_inside_brackets() {
    let text = r"Euler: $I_1\dot\omega_1 = (I_2 - I_3)\,\omega_2\omega_3 + \tau_1$ holds.";
    let lines: Vec<String> = wrap(
        &math_runs(text, Style::default()),
        24,
        Run::new("", Style::default()),
        Run::new("", Style::default()),
    )
    .iter()
    .map(line_text)
    .collect();
    // The bracket (I₂ − I₃) is never split while breaks outside it fit.
    assert!(lines.iter().any(|l| l.contains("(I₂ − I₃)")), "{lines:#?}");
    for l in &lines {
        assert!(!l.trim_end().ends_with('('), "{lines:#?}");
    }
}

/// Every row of a display equation in the bundled decks' sections, both
/// languages.
fn display_rows() -> Vec<String> {
    let loaded = crate::bundled::load();
    let mut out = Vec::new();
    for deck in &loaded.decks {
        for s in &deck.sections {
            for text in s.body.0.values() {
                let (blocks, _) = crate::text::markup::parse_anchored(text);
                for b in blocks {
                    if let crate::text::markup::Block::Display(math) = b {
                        out.extend(math.lines().map(str::to_string));
                    }
                }
            }
        }
    }
    out
}

/// A display equation wider than the reader folds at its top-level
/// operators, its folds indented further, and breaks inside a bracket only
/// in a piece that does not fit without: at 40×12 (26 columns of text),
/// `tan δ = 2ζω₀ω/(ω₀² − ω²)` after the wide `A(ω) = …` keeps its bracket.
#[test]
fn a_display_equation_folds_at_top_level_operators_with_an_indent() {
    let rows = display_rows();
    assert!(rows.len() > 20, "only {} display rows", rows.len());
    let row = rows
        .iter()
        .find(|r| r.starts_with("A(ω) =") && r.contains("tan δ"))
        .expect("the driven oscillator's display equation");
    let lines: Vec<String> = crate::tui::screens::reader::display_lines(row, Style::default(), 26)
        .iter()
        .map(line_text)
        .collect();
    assert!(
        lines.iter().any(|l| l.contains("2ζω₀ω/(ω₀² − ω²)")),
        "{lines:#?}"
    );
    // A(ω) too wide for one line breaks in its outermost bracket (at the
    // `+` under the root), never inside the inner `(ω₀² − ω²)`.
    assert!(
        lines.iter().any(|l| l.contains("(ω₀² − ω²)²")),
        "the inner bracket is torn: {lines:#?}"
    );
    assert!(lines[0].starts_with("    ") && !lines[0].starts_with("     "));
    for l in &lines[1..] {
        assert!(
            l.starts_with("      "),
            "a fold is indented further: {lines:#?}"
        );
    }
    // Every row at every width: the folds give the row back, and no line
    // is wider than the screen unless one token is.
    for row in &rows {
        let longest = row
            .split_whitespace()
            .map(crate::tui::wrap::columns)
            .max()
            .unwrap_or(0);
        // Below that, a token wider than a line must be cut somewhere.
        for width in (longest + 6).max(20)..=160 {
            let lines: Vec<String> =
                crate::tui::screens::reader::display_lines(row, Style::default(), width)
                    .iter()
                    .map(line_text)
                    .collect();
            assert_eq!(squash(&lines.join(" ")), squash(row), "{width}: {lines:#?}");
            for l in &lines {
                assert!(crate::tui::wrap::columns(l) <= width, "{width}: {lines:#?}");
            }
        }
    }
}
