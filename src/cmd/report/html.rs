//! `report.html`: one page that needs nothing else. Styles are inline, the
//! charts are SVG drawn here, there is no script and no address to fetch,
//! so it opens the same from a USB stick, a mail attachment or a browser
//! without network. It names no learner's file (learners are counted, not
//! named), so it can be shared.

use std::fmt::Write as _;

use super::{Input, card_name, choice_name, headline, percent};
use crate::text::num::rounded;

fn esc(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

const STYLE: &str = "body{font-family:system-ui,sans-serif;margin:2em;max-width:60em;color:#222}\
table{border-collapse:collapse;margin:1em 0}th,td{border:1px solid #ccc;padding:.3em .6em;text-align:left;vertical-align:top}\
th{background:#f0f0f0}td.n{text-align:right}.q{color:#555;font-size:.9em}.skip{color:#a40}\
svg text{font:12px system-ui,sans-serif}";

/// A horizontal bar chart: one bar per item, its length the share (0–1).
fn bars(title: &str, items: &[(String, f64, &str)]) -> String {
    if items.is_empty() {
        return String::new();
    }
    let (label_w, bar_w, row_h) = (260.0, 360.0, 20.0);
    let height = row_h * items.len() as f64 + 30.0;
    let mut svg = format!(
        "<svg role=\"img\" width=\"{w}\" height=\"{height}\" \
         viewBox=\"0 0 {w} {height}\"><title>{t}</title>",
        w = label_w + bar_w + 60.0,
        t = esc(title)
    );
    for (i, (label, share, colour)) in items.iter().enumerate() {
        let y = 20.0 + row_h * i as f64;
        let share = if share.is_finite() {
            share.clamp(0.0, 1.0)
        } else {
            0.0
        };
        let shown: String = label.chars().take(40).collect();
        let _ = write!(
            svg,
            "<text x=\"{x}\" y=\"{ty}\" text-anchor=\"end\">{l}</text>\
             <rect x=\"{bx}\" y=\"{y}\" width=\"{bw}\" height=\"{h}\" fill=\"{colour}\"/>\
             <text x=\"{vx}\" y=\"{ty}\">{v}%</text>",
            x = label_w - 6.0,
            ty = y + 13.0,
            l = esc(&shown),
            bx = label_w,
            bw = rounded(bar_w * share, 4),
            h = row_h - 4.0,
            vx = label_w + bar_w * share + 4.0,
            v = rounded(100.0 * share, 3),
        );
    }
    let _ = write!(
        svg,
        "<line x1=\"{label_w}\" y1=\"16\" x2=\"{label_w}\" y2=\"{y2}\" stroke=\"#444\"/></svg>",
        y2 = height - 8.0
    );
    svg
}

pub fn page(input: &Input) -> String {
    let r = &input.report;
    let mut h = String::new();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <meta name=\"viewport\" content=\"width=device-width\">\
         <title>Class report</title><style>{STYLE}</style></head><body>\
         <h1>Class report</h1><p>{}</p>",
        esc(&headline(input))
    );
    // The page is made to be passed around: it names no learner's file,
    // not even one skipped (the terminal output, for the teacher, does).
    if !input.skipped.is_empty() {
        let _ = write!(
            h,
            "<p class=\"skip\">{} left out for a problem; the terminal output of \
             <code>flipcard report</code> names {}.</p>",
            super::plural(input.skipped.len(), "file was", "files were"),
            if input.skipped.len() == 1 {
                "it"
            } else {
                "them"
            }
        );
    }

    h.push_str("<h2>Cards, hardest first</h2>");
    let top: Vec<(String, f64, &str)> = r
        .cards
        .iter()
        .take(30)
        .map(|c| {
            (
                c.text.clone().unwrap_or_else(|| card_name(c)),
                c.lapsed as f64 / c.learners.max(1) as f64,
                "#c0504d",
            )
        })
        .collect();
    h.push_str(&bars("Share of learners who lapsed, per card", &top));
    h.push_str(
        "<table><tr><th>Deck</th><th>Card</th><th>Text</th><th>Learners</th><th>Lapsed</th>\
         <th>Mean difficulty</th></tr>",
    );
    for c in &r.cards {
        let _ = write!(
            h,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td class=\"n\">{}</td><td class=\"n\">{}</td><td class=\"n\">{}</td></tr>",
            esc(&c.deck),
            esc(&card_name(c)),
            esc(c.text.as_deref().unwrap_or("")),
            c.learners,
            percent(c.lapsed, c.learners),
            c.mean_difficulty
                .map_or_else(|| "–".to_string(), |d| rounded(d, 3))
        );
    }
    h.push_str("</table>");

    h.push_str("<h2>Predictions, least often right first</h2>");
    for p in &r.prompts {
        let _ = write!(
            h,
            "<h3>{} <small>({})</small></h3><p class=\"q\">{}</p><p>First predictions: {} right of {}{}.</p>",
            esc(&p.prompt),
            esc(&p.deck),
            esc(p
                .text
                .as_deref()
                .unwrap_or("(the deck is not loaded: no text)")),
            percent(p.right, p.judged()),
            super::plural(p.judged(), "learner", "learners"),
            if p.no_verdict > 0 {
                format!(" ({} left the run before a verdict)", p.no_verdict)
            } else {
                String::new()
            },
        );
        if let Some(a) = super::answer_line(p) {
            let _ = write!(h, "<p>{}</p>", esc(&a));
        }
        if p.retries.attempts > 0 {
            let _ = write!(h, "<p>Retries: {}.</p>", esc(&super::retries(p)));
        }
        let mut items = vec![(
            "right".to_string(),
            p.right as f64 / p.learners.max(1) as f64,
            "#4f81bd",
        )];
        for c in &p.wrong {
            items.push((
                choice_name(c),
                c.learners as f64 / p.learners.max(1) as f64,
                "#c0504d",
            ));
        }
        h.push_str(&bars(&format!("First predictions on {}", p.prompt), &items));
        if !p.wrong.is_empty() {
            h.push_str("<table><tr><th>Wrong prediction</th><th>Learners</th></tr>");
            for c in &p.wrong {
                let _ = write!(
                    h,
                    "<tr><td>{}</td><td class=\"n\">{}</td></tr>",
                    esc(&choice_name(c)),
                    c.learners
                );
            }
            h.push_str("</table>");
        }
    }

    if !r.misconceptions.is_empty() {
        h.push_str("<h2>Misconceptions behind wrong answers, most learners first</h2>");
        h.push_str("<table><tr><th>Deck</th><th>Misconception</th><th>Learners</th><th>Attempts</th><th>Prompts</th></tr>");
        for m in &r.misconceptions {
            let _ = write!(
                h,
                "<tr><td>{}</td><td>{}</td><td class=\"n\">{}</td><td class=\"n\">{}</td><td>{}</td></tr>",
                esc(&m.deck),
                esc(&m
                    .title
                    .as_ref()
                    .map_or(m.id.clone(), |t| format!("{t} ({})", m.id))),
                m.learners,
                m.attempts,
                esc(&m.prompts.join(", "))
            );
        }
        h.push_str("</table>");
    }
    h.push_str("<h2>Retention by tag, worst first</h2>");
    let tags: Vec<(String, f64, &str)> = r
        .tags
        .iter()
        .map(|t| {
            (
                t.tag.clone(),
                t.recalled as f64 / t.reviews.max(1) as f64,
                "#9bbb59",
            )
        })
        .collect();
    h.push_str(&bars("Retention by tag", &tags));
    h.push_str("<table><tr><th>Tag</th><th>Learners</th><th>Reviews</th><th>Retention</th></tr>");
    for t in &r.tags {
        let _ = write!(
            h,
            "<tr><td>{}</td><td class=\"n\">{}</td><td class=\"n\">{}</td><td class=\"n\">{}</td></tr>",
            esc(&t.tag),
            t.learners,
            t.reviews,
            percent(t.recalled, t.reviews)
        );
    }
    h.push_str("</table></body></html>\n");
    h
}
