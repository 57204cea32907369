//! `report.csv`: every table of the report in one sheet, one row per item,
//! the `section` column saying which table it belongs to.

use crate::store::class::ClassReport;
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
            &c.deck,
            &super::card_name(c),
            &c.learners.to_string(),
            &c.lapsed.to_string(),
            &c.learners.to_string(),
            &share(c.lapsed, c.learners),
            &c.mean_difficulty
                .map_or_else(String::new, |d| Num(d).to_string()),
            "",
        ])?;
    }
    for p in &r.prompts {
        w.write_record([
            "prompt",
            &p.deck,
            &p.prompt,
            &p.learners.to_string(),
            &p.right.to_string(),
            &p.learners.to_string(),
            &share(p.right, p.learners),
            "",
            p.text.as_deref().unwrap_or(""),
        ])?;
        let wrong: usize = p.wrong.iter().map(|c| c.learners).sum();
        for c in &p.wrong {
            w.write_record([
                "wrong_choice",
                &p.deck,
                &p.prompt,
                &p.learners.to_string(),
                &c.learners.to_string(),
                &wrong.to_string(),
                &share(c.learners, wrong),
                "",
                &super::choice_name(c),
            ])?;
        }
    }
    for t in &r.tags {
        w.write_record([
            "tag",
            "",
            &t.tag,
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
