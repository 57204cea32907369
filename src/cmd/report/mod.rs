//! `flipcard report FILES… [--deck ID] [--lang TAG] [--out DIR]`: the class
//! report from learners' exported reviews and prompt attempts (cards by
//! their text, first predictions apart from retries, wrong numbers in bins
//! beside the right answer, the misconceptions wrong answers stood for
//! across prompts, retention by tag worst first), as a table in the
//! terminal and, with `--out`, `DIR/report.html` (one self-contained page:
//! tables and SVG bar charts, no scripts, nothing fetched) and
//! `DIR/report.csv`.

mod csv_out;
mod html;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Context;

use crate::cmd::args::{Cli, ReportArgs};
use crate::interop::class::{self, ClassReport, Export};
use crate::text::num::rounded;
pub use crate::text::plural;
use crate::tui::wrap::ellipsize;

/// The report and what went into it.
pub struct Input {
    pub report: ClassReport,
    /// Files left out, with their first problem (`FILE:LINE: message`).
    pub skipped: Vec<String>,
    pub deck: Option<String>,
}

/// Reads every file; a file with a problem is left out whole and named
/// with its first problem.
pub fn read(
    files: &[PathBuf],
    decks: &[crate::deck::Deck],
    only: Option<&str>,
    lang: &str,
) -> Input {
    let mut exports: Vec<Export> = Vec::with_capacity(files.len());
    let mut skipped = Vec::new();
    for path in files {
        let text = match crate::cmd::import_file::read_limited(
            path,
            crate::cmd::import_reviews::MAX_LOG_BYTES,
        ) {
            Ok(bytes) => match String::from_utf8(bytes) {
                Ok(t) => t,
                Err(e) => {
                    let line = 1 + e.as_bytes()[..e.utf8_error().valid_up_to()]
                        .iter()
                        .filter(|b| **b == b'\n')
                        .count();
                    skipped.push(format!("{}:{line}: not valid UTF-8", path.display()));
                    continue;
                }
            },
            Err(e) => {
                skipped.push(format!(
                    "{}: {}",
                    path.display(),
                    crate::cmd::import_file::cannot_read(&e)
                ));
                continue;
            }
        };
        match class::parse(&text) {
            Ok(e) => exports.push(e),
            Err(e) => skipped.push(format!("{}:{}: {}", path.display(), e.line, e.message)),
        }
    }
    Input {
        report: class::aggregate(&exports, decks, only, lang),
        skipped,
        deck: only.map(str::to_string),
    }
}

pub fn run(cli: &Cli, args: &ReportArgs) -> anyhow::Result<ExitCode> {
    let decks = crate::cmd::library::load(cli).loaded.decks;
    if let Some(id) = &args.deck
        && !decks.iter().any(|d| &d.id == id)
    {
        crate::errln!(
            "flipcard: warning: deck `{id}` is not among the decks loaded; prompt texts and tags are unknown"
        );
    }
    let input = read(&args.files, &decks, args.deck.as_deref(), &args.lang);
    for s in &input.skipped {
        crate::errln!("{s}");
    }
    crate::out!("{}", terminal(&input))?;
    if let Some(dir) = &args.out {
        write_outputs(dir, &input)?;
        crate::outln!(
            "wrote {} and {}",
            dir.join("report.html").display(),
            dir.join("report.csv").display()
        )?;
    }
    if input.skipped.is_empty() {
        Ok(ExitCode::SUCCESS)
    } else {
        crate::errln!(
            "flipcard: error: {} skipped; the report covers the rest",
            plural(input.skipped.len(), "file", "files")
        );
        Ok(ExitCode::FAILURE)
    }
}

/// Writes both files, each to a temporary name renamed into place.
pub fn write_outputs(dir: &Path, input: &Input) -> anyhow::Result<()> {
    for (name, body) in [
        ("report.html", html::page(input)),
        ("report.csv", csv_out::table(&input.report)?),
    ] {
        let path = dir.join(name);
        crate::io::write_atomic(&path, body.as_bytes(), crate::io::Durability::Whole)
            .with_context(|| format!("cannot write {}", path.display()))?;
    }
    Ok(())
}

/// `n/total` as a whole percentage.
pub fn percent(n: usize, total: usize) -> String {
    if total == 0 {
        return "–".to_string();
    }
    format!("{}%", rounded(100.0 * n as f64 / total as f64, 3))
}

/// A card, and its direction when it is not the front asked.
pub fn card_name(c: &class::CardRow) -> String {
    if c.direction == "forward" {
        c.card.clone()
    } else {
        format!("{} ({})", c.card, c.direction)
    }
}

pub fn choice_name(c: &class::Choice) -> String {
    match &c.label {
        Some(l) => format!("{} ({l})", c.prediction),
        None => c.prediction.clone(),
    }
}

/// A misconception's title (when the deck is loaded) and the prompts its
/// wrong answers came from, for the CSV's `text`.
pub fn misconception_text(m: &class::MisconceptionRow) -> String {
    let prompts = format!("prompts: {}", m.prompts.join(", "));
    match &m.title {
        Some(t) => format!("{t}; {prompts}"),
        None => prompts,
    }
}

/// Rows in aligned columns.
fn columns(rows: &[Vec<String>]) -> String {
    let n = rows.iter().map(Vec::len).max().unwrap_or(0);
    let mut widths = vec![0usize; n];
    for row in rows {
        for (w, cell) in widths.iter_mut().zip(row) {
            *w = (*w).max(unicode_width::UnicodeWidthStr::width(cell.as_str()));
        }
    }
    let mut out = String::new();
    for row in rows {
        let mut line = String::new();
        for (i, cell) in row.iter().enumerate() {
            line.push_str(cell);
            let pad = widths[i] - unicode_width::UnicodeWidthStr::width(cell.as_str());
            line.push_str(&" ".repeat(pad + 2));
        }
        out.push_str(line.trim_end());
        out.push('\n');
    }
    out
}

/// Who the report covers, in one line.
pub fn headline(input: &Input) -> String {
    let r = &input.report;
    let mut s = format!(
        "Class report{}: {} of reviews, {} of prompt attempts",
        input
            .deck
            .as_ref()
            .map_or_else(String::new, |d| format!(" for {d}")),
        plural(r.review_files, "learner file", "learner files"),
        plural(r.attempt_files, "learner file", "learner files"),
    );
    if !input.skipped.is_empty() {
        s.push_str(&format!(
            "; {} skipped",
            plural(input.skipped.len(), "file", "files")
        ));
    }
    s
}

/// A prompt's retries in words: `3 by 2 learners, 67% right`.
pub fn retries(p: &class::PromptRow) -> String {
    let r = &p.retries;
    if r.attempts == 0 {
        return "–".to_string();
    }
    format!(
        "{} by {}, {} right",
        r.attempts,
        plural(r.learners, "learner", "learners"),
        percent(r.right, r.judged)
    )
}

/// The right answer of a prompt with its formula and what the runs
/// measured, as far as they are known.
pub fn answer_line(p: &class::PromptRow) -> Option<String> {
    let mut parts = Vec::new();
    if let Some(a) = &p.answer {
        parts.push(format!("answer {a}"));
    }
    if let Some(f) = &p.formula {
        parts.push(format!("from {f}"));
    }
    if let Some(m) = p.measured {
        parts.push(format!("the runs measured {}", rounded(m, 4)));
    }
    (!parts.is_empty()).then(|| parts.join("; "))
}

fn terminal(input: &Input) -> String {
    let r = &input.report;
    let mut out = format!("{}\n\nCards, hardest first\n", headline(input));
    let mut rows = vec![vec![
        "DECK".to_string(),
        "CARD".into(),
        "LEARNERS".into(),
        "LAPSED".into(),
        "MEAN DIFFICULTY".into(),
        "TEXT".into(),
    ]];
    for c in &r.cards {
        rows.push(vec![
            c.deck.clone(),
            card_name(c),
            c.learners.to_string(),
            percent(c.lapsed, c.learners),
            c.mean_difficulty
                .map_or_else(|| "–".to_string(), |d| rounded(d, 3)),
            c.text
                .as_deref()
                .map_or_else(String::new, |t| ellipsize(t, 60)),
        ]);
    }
    out.push_str(&columns(&rows));
    out.push_str("\nPrompts, least often predicted right first (first attempts; retries apart)\n");
    let mut rows = vec![vec![
        "DECK".to_string(),
        "PROMPT".into(),
        "LEARNERS".into(),
        "RIGHT".into(),
        "WRONG FIRST PREDICTIONS".into(),
        "RETRIES".into(),
    ]];
    for p in &r.prompts {
        let wrong: Vec<String> = p
            .wrong
            .iter()
            .map(|w| format!("{} ×{}", w.prediction, w.learners))
            .collect();
        let mut right = percent(p.right, p.judged());
        if p.no_verdict > 0 {
            right.push_str(&format!(" ({} without verdict)", p.no_verdict));
        }
        rows.push(vec![
            p.deck.clone(),
            p.prompt.clone(),
            p.learners.to_string(),
            right,
            wrong.join(", "),
            retries(p),
        ]);
    }
    out.push_str(&columns(&rows));
    for p in &r.prompts {
        let (text, answer) = (p.text.as_deref(), answer_line(p));
        if text.is_none() && answer.is_none() {
            continue;
        }
        out.push_str(&format!(
            "\n{}: {}\n",
            p.prompt,
            ellipsize(text.unwrap_or(""), 100)
        ));
        if let Some(a) = answer {
            out.push_str(&format!("  {a}\n"));
        }
        let bins: Vec<String> = p
            .wrong
            .iter()
            .map(|w| format!("{} ×{}", choice_name(w), w.learners))
            .collect();
        if !bins.is_empty() {
            out.push_str(&format!("  wrong first predictions: {}\n", bins.join(", ")));
        }
    }
    if !r.misconceptions.is_empty() {
        out.push_str(
            "\nMisconceptions behind wrong answers, most learners first (every wrong attempt)\n",
        );
        let mut rows = vec![vec![
            "DECK".to_string(),
            "MISCONCEPTION".into(),
            "LEARNERS".into(),
            "ATTEMPTS".into(),
            "PROMPTS".into(),
            "TITLE".into(),
        ]];
        for m in &r.misconceptions {
            rows.push(vec![
                m.deck.clone(),
                m.id.clone(),
                m.learners.to_string(),
                m.attempts.to_string(),
                m.prompts.join(", "),
                m.title
                    .as_deref()
                    .map_or_else(String::new, |t| ellipsize(t, 60)),
            ]);
        }
        out.push_str(&columns(&rows));
    }
    out.push_str("\nRetention by tag, worst first\n");
    let mut rows = vec![vec![
        "TAG".to_string(),
        "LEARNERS".into(),
        "REVIEWS".into(),
        "RETENTION".into(),
    ]];
    for t in &r.tags {
        rows.push(vec![
            t.tag.clone(),
            t.learners.to_string(),
            t.reviews.to_string(),
            percent(t.recalled, t.reviews),
        ]);
    }
    out.push_str(&columns(&rows));
    out
}
