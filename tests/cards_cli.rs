//! `flipcard cards list|suspend|unsuspend|bury` and the filter flags of
//! `flipcard review` through the real binary, on the study fixture deck:
//! exact CSV header, JSON rows, all-or-nothing status changes, clear
//! one-line errors.

use std::path::Path;

use crate::support::{Flipcard, Output};

const NOW: &str = "2026-05-10T12:00:00Z";
const HEADER: &str = "deck,card,direction,state,due,stability,difficulty,retrievability,reviews,lapses,suspended,buried,leech,tags,front";

fn flipcard(data: &Path, args: &[&str]) -> Output {
    // The bundled decks are open too: a listing looks at the fixture deck
    // unless the query names a deck itself.
    let mut args = args.to_vec();
    if args.starts_with(&["cards", "list"]) && !args.iter().any(|a| a.starts_with("deck:")) {
        args.push("deck:study");
    }
    if args.first() == Some(&"review") && args.get(1).is_some_and(|a| a.starts_with("--")) {
        args.insert(1, "study");
    }
    Flipcard::new(data)
        .now(NOW)
        .decks(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/decks/study/decks"
        ))
        .args(args)
        .run()
}

/// (card/direction, suspended, buried) of every row of `cards list QUERY`.
fn marks(data: &Path, query: &str) -> Vec<(String, String, String)> {
    let o = flipcard(data, &["cards", "list", query]);
    assert!(o.status.success(), "{}", o.stderr());
    let text = o.stdout();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(HEADER));
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (
                format!("{}/{}", f[1], f[2]),
                f[10].to_string(),
                f[11].to_string(),
            )
        })
        .collect()
}

#[test]
fn list_prints_one_row_per_item_in_csv_and_json() {
    let dir = tempfile::tempdir().unwrap();
    let rows = marks(dir.path(), "");
    let items: Vec<&str> = rows.iter().map(|r| r.0.as_str()).collect();
    assert_eq!(
        items,
        [
            "torque-rate/c1",
            "torque-rate/c2",
            "torque-rate/c3",
            "spin-axis/forward",
            "spin-axis/backward",
            "middle/forward"
        ]
    );
    let o = flipcard(
        dir.path(),
        &["cards", "list", "tag:frames", "--format", "json"],
    );
    assert!(o.status.success(), "{}", o.stderr());
    let json: serde_json::Value = serde_json::from_str(&o.stdout()).unwrap();
    let rows = json.as_array().unwrap();
    assert_eq!(rows.len(), 3);
    let fields: Vec<&str> = rows[0]
        .as_object()
        .unwrap()
        .keys()
        .map(String::as_str)
        .collect();
    let mut want: Vec<&str> = HEADER.split(',').collect();
    let mut got = fields.clone();
    want.sort();
    got.sort();
    assert_eq!(got, want);
    assert_eq!(rows[2]["tags"], "euler frames");
    // What each item asks, math rendered, on one line.
    for r in rows.iter() {
        let front = r["front"].as_str().unwrap();
        assert!(
            !front.is_empty() && !front.contains('\n') && !front.contains('$'),
            "{r}"
        );
    }
    assert_eq!(rows[0]["state"], "new");
    assert_eq!(rows[0]["due"], "");

    // Math as written and as rendered.
    assert_eq!(marks(dir.path(), "omega2").len(), 3);
    assert_eq!(marks(dir.path(), "ω₂").len(), 3);
}

#[test]
fn suspend_unsuspend_bury_change_all_or_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // One unknown item: exit 1, naming it, and the good one is untouched.
    let o = flipcard(d, &["cards", "suspend", "study/middle", "study/nope"]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        o.stderr().trim(),
        "flipcard: error: unknown item `study/nope`: deck `study` has no card `nope`"
    );
    assert!(marks(d, "is:suspended").is_empty());
    for bad in [
        "study/torque-rate/c7",
        "study/middle/backward",
        "nodeck/x",
        "study",
    ] {
        let o = flipcard(d, &["cards", "bury", bad]);
        assert_eq!(o.status.code(), Some(1), "{bad}");
        assert_eq!(o.stderr().lines().count(), 1, "{bad}: {}", o.stderr());
        assert!(o.stderr().contains(bad), "{bad}: {}", o.stderr());
    }
    assert!(marks(d, "state:buried").is_empty());

    let o = flipcard(
        d,
        &[
            "cards",
            "suspend",
            "study/spin-axis",
            "study/torque-rate/c2",
        ],
    );
    assert!(o.status.success(), "{}", o.stderr());
    assert_eq!(o.stdout().trim(), "suspended: 3 items");
    let s: Vec<String> = marks(d, "is:suspended").into_iter().map(|r| r.0).collect();
    assert_eq!(
        s,
        ["torque-rate/c2", "spin-axis/forward", "spin-axis/backward"]
    );

    let o = flipcard(d, &["cards", "bury", "study/middle/forward"]);
    assert!(o.status.success(), "{}", o.stderr());
    assert_eq!(
        marks(d, "is:buried"),
        [(
            "middle/forward".to_string(),
            "false".to_string(),
            "true".to_string()
        )]
    );
    let o = flipcard(
        d,
        &[
            "cards",
            "unsuspend",
            "study/spin-axis/backward",
            "study/middle",
        ],
    );
    assert!(o.status.success(), "{}", o.stderr());
    let s: Vec<String> = marks(d, "is:suspended").into_iter().map(|r| r.0).collect();
    assert_eq!(s, ["torque-rate/c2", "spin-axis/forward"]);
    assert!(marks(d, "is:buried").is_empty(), "unsuspend lifts a bury");

    // The marks come from the status log: a rebuild gives them again.
    let o = flipcard(d, &["db", "rebuild"]);
    assert!(o.status.success(), "{}", o.stderr());
    let s: Vec<String> = marks(d, "is:suspended").into_iter().map(|r| r.0).collect();
    assert_eq!(s, ["torque-rate/c2", "spin-axis/forward"]);
    let o = flipcard(d, &["stats"]);
    assert!(
        o.stdout()
            .contains("Suspended: 2; buried today: 0; leeches: 0"),
        "{}",
        o.stdout()
    );
}

#[test]
fn bad_queries_and_filters_say_what_is_wrong() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (args, says) in [
        (
            vec!["cards", "list", "tag:nope"],
            "no card has tag `nope`; tags are ",
        ),
        (
            vec!["cards", "list", "state:asleep"],
            "unknown state `asleep`",
        ),
        (
            vec!["cards", "list", "deck:other"],
            "no deck `other`; decks are ",
        ),
        (
            vec!["cards", "list", "colour:red"],
            "unknown filter `colour:`",
        ),
        (
            vec!["cards", "list", "due:<3y"],
            "`3y` is not a span of time",
        ),
        (vec!["review", "--tag", "nope"], "no card has tag `nope`"),
        (
            vec!["review", "--state", "asleep"],
            "unknown state `asleep`",
        ),
        (vec!["review", "--state", "suspended"], "add --cram"),
        (
            vec!["review", "--due-within", "soon"],
            "`soon` is not a span of time",
        ),
        (
            vec!["review", "--due-within", "3d"],
            "no card of deck `study` matches the filter",
        ),
    ] {
        let o = flipcard(d, &args);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", o.stderr());
        assert!(o.stderr().contains(says), "{args:?}: {}", o.stderr());
        assert_eq!(o.stderr().lines().count(), 1, "{args:?}: {}", o.stderr());
    }
    // A query that matches nothing: the header, and a line saying so.
    let o = flipcard(d, &["cards", "list", "zzqqxx"]);
    assert!(o.status.success());
    assert_eq!(o.stdout().trim(), HEADER);
    assert!(
        o.stderr().contains("no item matches `zzqqxx"),
        "{}",
        o.stderr()
    );
}

#[test]
fn an_item_named_twenty_thousand_times_changes_once() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // With a card (both directions) and one of its directions again.
    let mut args = vec!["cards", "suspend"];
    args.extend(std::iter::repeat_n("study/middle/forward", 20_000));
    args.extend(["study/spin-axis", "study/spin-axis/backward"]);
    let o = flipcard(d, &args);
    assert!(o.status.success(), "{}", o.stderr());
    assert_eq!(o.stdout().trim(), "suspended: 3 items");
    let db = rusqlite::Connection::open(d.join("flipcard.db")).unwrap();
    let events: Vec<(String, String)> = db
        .prepare("SELECT card, direction FROM status_event ORDER BY id")
        .unwrap()
        .query_map([], |r| Ok((r.get(0)?, r.get(1)?)))
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap();
    // One event per item, in the order first named.
    assert_eq!(
        events,
        [
            ("middle".into(), "forward".into()),
            ("spin-axis".into(), "forward".into()),
            ("spin-axis".into(), "backward".into())
        ]
    );
    for action in ["unsuspend", "bury"] {
        let mut args = vec!["cards", action];
        args.extend(std::iter::repeat_n("study/middle", 20_000));
        let o = flipcard(d, &args);
        assert!(o.status.success(), "{}", o.stderr());
        let n: i64 = db
            .query_row(
                "SELECT count(*) FROM status_event WHERE action = ?1",
                [action],
                |r| r.get(0),
            )
            .unwrap();
        assert_eq!(n, 1, "{action}");
    }
}

#[test]
fn a_due_date_rfc_3339_cannot_hold_is_left_blank_and_named() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    drop(flipcard::store::Store::open(d).unwrap());
    {
        // Written straight into the database, as an import before dates
        // were checked could have: due in the year 10000.
        let db = rusqlite::Connection::open(d.join("flipcard.db")).unwrap();
        let (at, due) = (1_778_400_000_000i64, 253_402_300_800_000i64);
        db.execute(
            "INSERT INTO review (id, deck, card, direction, reviewed_at, rating, kind, \
             elapsed_days, scheduled_days, stability, difficulty, state, due, duration_ms) \
             VALUES (1, 'study', 'middle', 'forward', ?1, 4, 'review', 0, 36500, 1e9, 1, \
             'review', ?2, 1000)",
            [at, due],
        )
        .unwrap();
        db.execute(
            "INSERT INTO card_state (deck, card, direction, state, stability, difficulty, due, \
             last_review, reps, lapses, review_id) \
             VALUES ('study', 'middle', 'forward', 'review', 1e9, 1, ?2, ?1, 1, 0, 1)",
            [at, due],
        )
        .unwrap();
    }
    for format in ["csv", "json"] {
        let o = flipcard(d, &["cards", "list", "--format", format]);
        assert_eq!(o.status.code(), Some(1), "{format}: {}", o.stderr());
        let text = o.stdout();
        assert!(
            !text.contains("+10000") && !text.contains("10000-"),
            "{text}"
        );
        let rows: Vec<(String, String)> = if format == "csv" {
            let mut r = csv::Reader::from_reader(text.as_bytes());
            r.records()
                .map(|row| {
                    let row = row.unwrap();
                    (format!("{}/{}", &row[1], &row[2]), row[4].to_string())
                })
                .collect()
        } else {
            let all: Vec<serde_json::Value> = serde_json::from_str(&text).unwrap();
            all.iter()
                .map(|r| {
                    (
                        format!(
                            "{}/{}",
                            r["card"].as_str().unwrap(),
                            r["direction"].as_str().unwrap()
                        ),
                        r["due"].as_str().unwrap().to_string(),
                    )
                })
                .collect()
        };
        // Every item is listed; the one due date is blank.
        assert_eq!(rows.len(), 6, "{text}");
        let middle = rows.iter().find(|r| r.0 == "middle/forward").unwrap();
        assert_eq!(middle.1, "", "{text}");
        assert!(
            o.stderr().contains(
                "study/middle/forward: its due date is stored in the year 10000, which RFC 3339 cannot write; left blank"
            ),
            "{}",
            o.stderr()
        );
        assert!(
            o.stderr()
                .lines()
                .last()
                .unwrap()
                .starts_with("flipcard: error: 1 item")
        );
    }
}

/// The query as Anki users type it, through the real binary: `or`, `-`,
/// parentheses, `*` in tags, decks and text, `is:`, `prop:`, `rated:`, and
/// errors that name the column.
#[test]
fn queries_as_anki_users_type_them() {
    let dir = tempfile::tempdir().unwrap();
    let o = flipcard(dir.path(), &["cards", "suspend", "study/middle"]);
    assert!(o.status.success(), "{}", o.stderr());
    let items =
        |q: &str| -> Vec<String> { marks(dir.path(), q).into_iter().map(|r| r.0).collect() };
    let spin = ["spin-axis/forward", "spin-axis/backward"];
    let torque = ["torque-rate/c1", "torque-rate/c2", "torque-rate/c3"];
    assert_eq!(
        items("(is:suspended or -tag:euler)"),
        [&spin[..], &["middle/forward"]].concat()
    );
    assert_eq!(items("is:new -tag:fram*"), torque);
    assert_eq!(items("(-(tag:euler or tag:frames))"), Vec::<String>::new());
    assert_eq!(items("tag:euler -is:suspended"), torque);
    assert_eq!(items("tor*ue"), torque);
    assert_eq!(items("(\"largest moment\" or ax*larg*)"), spin);
    assert_eq!(
        items("deck:stu* is:new -is:suspended prop:reps=0"),
        [&torque[..], &spin[..]].concat()
    );
    // Nothing was answered: nothing has an interval or was rated.
    assert_eq!(
        items("(prop:ivl>=0 or rated:365 or is:due)"),
        Vec::<String>::new()
    );
    for (q, says) in [
        (
            "(tag:euler or is:new",
            "at column 1: this `(` is never closed",
        ),
        ("is:soon", "at column 4: unknown state `soon`"),
        ("prop:ivl>>3", "at column 10: `>3` is not a number"),
        ("flag:8", "at column 6: `flag:8`: flags are 0 (none), 1 red"),
    ] {
        let o = flipcard(dir.path(), &["cards", "list", q]);
        assert_eq!(o.status.code(), Some(1), "{q}");
        let err = o.stderr();
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.contains(says), "{q}: {err}");
    }
}

#[test]
fn a_query_may_start_with_a_minus_and_flags_still_count() {
    let dir = tempfile::tempdir().unwrap();
    let all = marks(dir.path(), "");
    let framed = marks(dir.path(), "tag:frames");
    let want: Vec<_> = all
        .iter()
        .filter(|r| !framed.contains(r))
        .cloned()
        .collect();
    assert!(!framed.is_empty() && !want.is_empty());
    // Without `--`, as with it.
    assert_eq!(marks(dir.path(), "-tag:frames"), want);
    let o = flipcard(dir.path(), &["cards", "list", "--", "-tag:frames"]);
    assert!(o.status.success(), "{}", o.stderr());
    assert_eq!(o.stdout().lines().count(), want.len() + 1);
    // --format after the query is the flag, before it too.
    for args in [
        &["cards", "list", "-tag:frames", "--format", "json"][..],
        &["cards", "list", "-tag:frames", "--format=json"][..],
        &["cards", "list", "--format", "json", "-tag:frames"][..],
    ] {
        let o = flipcard(dir.path(), args);
        assert!(o.status.success(), "{args:?}: {}", o.stderr());
        let json: serde_json::Value = serde_json::from_str(&o.stdout()).unwrap();
        assert_eq!(json.as_array().unwrap().len(), want.len(), "{args:?}");
    }
    // Another flag there is refused, never searched for.
    for (args, says) in [
        (
            &["cards", "list", "-tag:frames", "--colour"][..],
            "--colour",
        ),
        (
            &["cards", "list", "-tag:frames", "--format", "xml"][..],
            "csv or json",
        ),
        (
            &[
                "cards", "list", "--format", "json", "-tag:x", "--format", "csv",
            ][..],
            "twice",
        ),
    ] {
        let o = flipcard(dir.path(), args);
        assert!(!o.status.success(), "{args:?}");
        assert!(o.stdout.is_empty(), "{args:?}");
        assert!(o.stderr().contains(says), "{args:?}: {}", o.stderr());
    }
}
