//! Misconceptions on every path an attempt travels, through the real
//! binary: `export --attempts` writes the id a wrong answer stood for (the
//! last column), and `report` groups the class's wrong answers by
//! misconception across prompts, reading the id from the learners' files
//! (checked like every id) or, for older exports, from the loaded deck.

use std::path::Path;

use crate::class_report::flipcard;

const DECK: &str = "torque-free-rotation";

fn at(s: &str) -> chrono::DateTime<chrono::Utc> {
    chrono::DateTime::parse_from_rfc3339(s)
        .unwrap()
        .with_timezone(&chrono::Utc)
}

/// A store with a wrong answer that stood for a misconception, a wrong one
/// that stood for none and a right one.
fn store_with_attempts(data: &Path) {
    use flipcard::store::{AttemptVerdict, Commitment, Store};
    let mut store = Store::open(data).unwrap();
    for (i, (prompt, prediction, correct, misconception)) in [
        ("middle-axis", "stable", false, Some("omega-constant")),
        ("sphere-omega", "changes", false, None),
        ("largest-axis", "stable", true, None),
    ]
    .into_iter()
    .enumerate()
    {
        let t = at(&format!("2026-05-01T10:0{i}:00Z"));
        let c = store
            .commit_attempt(&Commitment {
                deck: DECK.into(),
                variant: None,
                prompt: prompt.into(),
                committed_at: t,
                prediction: prediction.into(),
            })
            .unwrap();
        store
            .judge_attempt(
                c.id,
                &AttemptVerdict {
                    measured: None,
                    correct,
                    judged_at: t + chrono::Duration::seconds(9),
                    misconception: misconception.map(str::to_string),
                },
            )
            .unwrap();
    }
}

#[test]
fn export_writes_the_misconception_last_in_csv_and_json() {
    let dir = tempfile::tempdir().unwrap();
    store_with_attempts(&dir.path().join("data"));
    let csv = flipcard(dir.path(), &["export", "--attempts", "--format", "csv"]).ok();
    let csv = csv.stdout();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(
        lines[0],
        "deck,prompt,attempted_at,prediction,measured,correct,attempt,retry,misconception,variant"
    );
    assert!(
        lines[1].ends_with(",false,1,false,omega-constant,"),
        "{csv}"
    );
    assert!(lines[2].ends_with(",false,1,false,,"), "{csv}");
    assert!(lines[3].ends_with(",true,1,false,,"), "{csv}");
    let json = flipcard(dir.path(), &["export", "--attempts"]).ok();
    let rows: Vec<serde_json::Value> = serde_json::from_str(&json.stdout()).unwrap();
    let ids: Vec<&serde_json::Value> = rows.iter().map(|r| &r["misconception"]).collect();
    assert_eq!(
        ids,
        [
            &serde_json::json!("omega-constant"),
            &serde_json::Value::Null,
            &serde_json::Value::Null
        ]
    );
}

/// Three learners: one exported with the column (CSV), one as JSON, one
/// from before misconceptions (no column: the deck's choice says). The
/// report counts learners and attempts per misconception across prompts,
/// with its title; a right answer and an answer that stood for none are
/// not counted; a file whose misconception is not an id is left out and
/// named at its line.
#[test]
fn report_groups_wrong_answers_by_misconception_across_prompts() {
    let dir = tempfile::tempdir().unwrap();
    let head = "deck,prompt,attempted_at,prediction,measured,correct,attempt,retry";
    let files = [
        (
            "asha.csv",
            format!(
                "{head},misconception\n\
                 {DECK},middle-axis,2026-05-01T10:00:00.000Z,stable,,false,1,false,omega-constant\n\
                 {DECK},middle-axis,2026-05-01T10:05:00.000Z,stable,,false,2,true,omega-constant\n\
                 {DECK},smallest-axis,2026-05-01T10:06:00.000Z,flips,,false,1,false,axes-equally-stable\n\
                 {DECK},largest-axis,2026-05-01T10:07:00.000Z,stable,,true,1,false,\n"
            ),
        ),
        (
            "ben.json",
            format!(
                "[\n{{\"deck\":\"{DECK}\",\"prompt\":\"largest-axis\",\"attempted_at\":\"2026-05-01T10:00:00.000Z\",\"prediction\":\"flips\",\"measured\":null,\"correct\":false,\"attempt\":1,\"retry\":false,\"misconception\":\"energy-pumped\"}},\n\
                 {{\"deck\":\"{DECK}\",\"prompt\":\"smallest-axis\",\"attempted_at\":\"2026-05-01T10:01:00.000Z\",\"prediction\":\"flips\",\"measured\":null,\"correct\":false,\"attempt\":1,\"retry\":false,\"misconception\":\"axes-equally-stable\"}}\n]\n"
            ),
        ),
        (
            "old.csv",
            format!(
                "{head}\n\
                 {DECK},middle-axis,2026-05-01T10:00:00.000Z,stable,,false,1,false\n\
                 {DECK},sphere-omega,2026-05-01T10:01:00.000Z,changes,,false,1,false\n"
            ),
        ),
        (
            "bad.csv",
            format!(
                "{head},misconception\n\
                 {DECK},middle-axis,2026-05-01T10:00:00.000Z,stable,,false,1,false,Omega Constant\n"
            ),
        ),
    ];
    for (name, text) in &files {
        std::fs::write(dir.path().join(name), text).unwrap();
    }
    let out = flipcard(
        dir.path(),
        &[
            "report", "asha.csv", "ben.json", "old.csv", "bad.csv", "--out", "r",
        ],
    );
    assert_eq!(out.code(), Some(1), "a file was skipped");
    let err = out.stderr();
    assert!(
        err.contains("bad.csv:2: misconception \"Omega Constant\" is not an id"),
        "{err}"
    );
    let text = out.stdout();
    let section = text
        .split("Misconceptions behind wrong answers")
        .nth(1)
        .unwrap_or_else(|| panic!("no misconception section:\n{text}"));
    let rows: Vec<Vec<&str>> = section
        .lines()
        .skip(2)
        .take_while(|l| !l.trim().is_empty())
        .map(|l| {
            l.split("  ")
                .map(str::trim)
                .filter(|c| !c.is_empty())
                .collect()
        })
        .collect();
    let row = |id: &str| {
        rows.iter()
            .find(|r| r.get(1) == Some(&id))
            .unwrap_or_else(|| panic!("no row for {id}:\n{section}"))
            .clone()
    };
    // Most learners first: omega-constant (asha twice, old once) and
    // axes-equally-stable (asha, ben) have two learners each.
    assert_eq!(
        row("omega-constant")[..5],
        [DECK, "omega-constant", "2", "3", "middle-axis"]
    );
    assert!(row("omega-constant")[5].starts_with("No torque, so ω⃗ stays constant"));
    assert_eq!(
        row("axes-equally-stable")[..5],
        [DECK, "axes-equally-stable", "2", "2", "smallest-axis"]
    );
    assert_eq!(
        row("energy-pumped")[..5],
        [DECK, "energy-pumped", "1", "1", "largest-axis"]
    );
    assert_eq!(rows.len(), 3, "{section}");
    assert_eq!(rows[2][1], "energy-pumped", "fewest learners last");
    let csv = std::fs::read_to_string(dir.path().join("r/report.csv")).unwrap();
    assert!(
        csv.lines()
            .any(|l| l.starts_with(&format!("misconception,{DECK},omega-constant,2,3,,,,"))),
        "{csv}"
    );
    let html = std::fs::read_to_string(dir.path().join("r/report.html")).unwrap();
    assert!(
        html.contains("Misconceptions behind wrong answers"),
        "{html}"
    );
}
