//! What sync must never do, through the real binary: leave a restored
//! database without its own answers, let two copies of one data folder
//! write one file, let a forged or damaged file take back another machine's
//! answers (or have them published again as someone else's), let a clock
//! that runs ahead make a learner's change do nothing, merge a line with an
//! impossible id or date, repeat the same warning at every sync, recurse
//! on a dangling machine id, or fail when two syncs of one data folder run
//! at once.

use std::path::Path;
use std::process::{Command, Stdio};

use flipcard::sched::Rating;

use crate::support::{Flipcard, Output};
use crate::sync::{DECK, NOW, live_log, mkfifo, pair, same, statuses, study, sync, sync_cmd};

fn id_of(data: &Path) -> String {
    std::fs::read_to_string(data.join("machine-id"))
        .unwrap()
        .trim()
        .to_string()
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// A consistent copy of the database, as the daily backup makes one.
fn backup(data: &Path, to: &Path) {
    let conn = rusqlite::Connection::open(data.join("flipcard.db")).unwrap();
    conn.execute("VACUUM INTO ?1", [to.to_str().unwrap()])
        .unwrap();
}

/// A copy of the database put back over it (the -wal and -shm of the
/// newer one removed), as a learner restoring by hand would.
fn put_back(copy: &Path, data: &Path) {
    for ext in ["-wal", "-shm"] {
        let _ = std::fs::remove_file(data.join(format!("flipcard.db{ext}")));
    }
    std::fs::copy(copy, data.join("flipcard.db")).unwrap();
}

#[test]
fn a_restored_database_gets_its_own_answers_back_from_its_file() {
    let p = pair();
    study(
        &p.laptop,
        "2026-05-01T08:00:00Z",
        &[
            ("torque-free-meaning", Rating::Good, 0),
            ("body-frame-why", Rating::Again, 1),
        ],
    );
    sync(&p.laptop, &p.folder);
    let copy = p.laptop.join("copy.db");
    backup(&p.laptop, &copy);
    study(
        &p.laptop,
        "2026-05-02T08:00:00Z",
        &[
            ("body-frame-why", Rating::Good, 0),
            ("l-not-parallel", Rating::Easy, 2),
            ("euler-component-1", Rating::Hard, 4),
        ],
    );
    sync(&p.laptop, &p.folder);
    sync(&p.lab, &p.folder);
    let before = live_log(&p.laptop);
    assert_eq!(before.len(), 5);

    put_back(&copy, &p.laptop);
    assert_eq!(live_log(&p.laptop).len(), 2, "the copy is older");
    let old_id = id_of(&p.laptop);
    let out = sync(&p.laptop, &p.folder);
    let (said, err) = (out.stdout(), out.stderr());
    assert!(said.contains("3 reviews merged"), "{said}");
    assert!(err.contains("restored from a backup"), "{err}");
    assert_ne!(id_of(&p.laptop), old_id, "a new id for the restored copy");
    assert_eq!(live_log(&p.laptop), before, "every answer back");
    sync(&p.lab, &p.folder);
    sync(&p.laptop, &p.folder);
    same(&p.laptop, &p.lab);
}

#[test]
fn flipcard_db_restore_then_sync_brings_back_what_the_copy_lacks() {
    let p = pair();
    study(
        &p.laptop,
        "2026-05-01T08:00:00Z",
        &[("torque-free-meaning", Rating::Good, 0)],
    );
    sync(&p.laptop, &p.folder);
    let copy = p.laptop.join("older.db");
    backup(&p.laptop, &copy);
    study(
        &p.laptop,
        "2026-05-02T08:00:00Z",
        &[("body-frame-why", Rating::Good, 0)],
    );
    sync(&p.laptop, &p.folder);
    let out = Flipcard::new(&p.laptop)
        .now(NOW)
        .args(["db", "restore"])
        .arg(&copy)
        .arg("--force")
        .run();
    assert!(out.status.success(), "{}", out.stderr());
    assert_eq!(live_log(&p.laptop).len(), 1);
    let out = sync(&p.laptop, &p.folder);
    assert!(out.stdout().contains("1 review merged"), "{}", out.stdout());
    assert_eq!(live_log(&p.laptop).len(), 2);
}

#[test]
fn a_copied_data_folder_takes_a_new_id_and_the_copies_exchange_everything() {
    let p = pair();
    study(
        &p.laptop,
        "2026-05-01T08:00:00Z",
        &[("torque-free-meaning", Rating::Good, 0)],
    );
    sync(&p.laptop, &p.folder);
    // The whole data folder copied to a second machine (the lab).
    let status = Command::new("cp")
        .arg("-a")
        .arg(&p.laptop)
        .arg(&p.lab)
        .status()
        .unwrap();
    assert!(status.success());
    assert_eq!(id_of(&p.laptop), id_of(&p.lab));
    study(
        &p.lab,
        "2026-05-02T08:00:00Z",
        &[("body-frame-why", Rating::Again, 0)],
    );
    sync(&p.lab, &p.folder);
    study(
        &p.laptop,
        "2026-05-02T09:00:00Z",
        &[("l-not-parallel", Rating::Easy, 0)],
    );
    let out = sync(&p.laptop, &p.folder);
    let err = out.stderr();
    assert!(err.contains("copied to another machine"), "{err}");
    assert!(out.stdout().contains("1 review merged"), "{}", out.stdout());
    assert_ne!(
        id_of(&p.laptop),
        id_of(&p.lab),
        "the copies have an id each"
    );
    sync(&p.lab, &p.folder);
    sync(&p.laptop, &p.folder);
    same(&p.laptop, &p.lab);
    assert_eq!(live_log(&p.lab).len(), 3);
    // Each machine's answers are in its own file only.
    let lines = |data: &Path| {
        std::fs::read_to_string(p.folder.join(format!("{}.jsonl", id_of(data)))).unwrap_or_default()
    };
    assert!(lines(&p.laptop).contains("l-not-parallel"));
    assert!(!lines(&p.laptop).contains("body-frame-why"));
    assert!(!lines(&p.laptop).contains("torque-free-meaning"));
}

const FORGED: &str = "ffffffffffffffffffffffffffffffff";

#[test]
fn a_forged_file_cannot_take_back_another_machines_answers() {
    let p = pair();
    let cards = [
        "torque-free-meaning",
        "body-frame-why",
        "l-not-parallel",
        "euler-component-1",
    ];
    let answers: Vec<(&str, Rating, i64)> = cards
        .iter()
        .enumerate()
        .map(|(i, c)| (*c, Rating::Good, i as i64))
        .collect();
    study(&p.laptop, "2026-05-01T08:00:00Z", &answers);
    sync(&p.laptop, &p.folder);
    let theirs =
        std::fs::read_to_string(p.folder.join(format!("{}.jsonl", id_of(&p.laptop)))).unwrap();
    // Every answer undone, twice over: undo lines, and copies marked undone.
    let mut forged = String::new();
    for line in theirs.lines() {
        let v: serde_json::Value = serde_json::from_str(line).unwrap();
        forged.push_str(&format!(
            "{{\"event\":\"undo_review\",\"deck\":{},\"card\":{},\"direction\":{},\"reviewed_at\":{},\"rating\":{}}}\n",
            v["deck"], v["card"], v["direction"], v["reviewed_at"], v["rating"]
        ));
        forged.push_str(&line.replace("\"undone\":false", "\"undone\":true"));
        forged.push('\n');
    }
    std::fs::write(p.folder.join(format!("{FORGED}.jsonl")), &forged).unwrap();

    let out = sync(&p.lab, &p.folder);
    assert!(out.stderr.is_empty(), "{}", out.stderr());
    assert_eq!(live_log(&p.lab).len(), 4, "the lab keeps every answer");
    sync(&p.laptop, &p.folder);
    assert_eq!(
        live_log(&p.laptop).len(),
        4,
        "the laptop keeps every answer"
    );
    same(&p.laptop, &p.lab);
    // The lab publishes nothing of the laptop's, undos included.
    let lab_file = p.folder.join(format!("{}.jsonl", id_of(&p.lab)));
    assert!(
        !lab_file.exists(),
        "the lab has nothing of its own to write"
    );
    study(
        &p.lab,
        "2026-05-03T08:00:00Z",
        &[("spin-axis", Rating::Easy, 0)],
    );
    sync(&p.lab, &p.folder);
    let lab_lines = std::fs::read_to_string(&lab_file).unwrap();
    assert_eq!(lab_lines.lines().count(), 1, "{lab_lines}");
    assert!(lab_lines.contains("spin-axis"), "{lab_lines}");
}

#[test]
fn many_answers_taken_back_in_one_sync_are_said_loudly() {
    let p = pair();
    let answers: Vec<(String, Rating, i64)> = (0..7)
        .map(|i| (format!("card-{i}"), Rating::Good, i))
        .collect();
    let refs: Vec<(&str, Rating, i64)> = answers
        .iter()
        .map(|(c, r, m)| (c.as_str(), *r, *m))
        .collect();
    study(&p.laptop, "2026-05-01T08:00:00Z", &refs);
    sync(&p.laptop, &p.folder);
    sync(&p.lab, &p.folder);
    // The laptop's own file says it undid them all (as a file of its own
    // damaged or forged would).
    let file = p.folder.join(format!("{}.jsonl", id_of(&p.laptop)));
    let theirs = std::fs::read_to_string(&file).unwrap();
    let mut more = theirs.clone();
    for line in theirs.lines() {
        let v: serde_json::Value = serde_json::from_str(line).unwrap();
        more.push_str(&format!(
            "{{\"event\":\"undo_review\",\"deck\":{},\"card\":{},\"direction\":{},\"reviewed_at\":{},\"rating\":{}}}\n",
            v["deck"], v["card"], v["direction"], v["reviewed_at"], v["rating"]
        ));
    }
    std::fs::write(&file, more).unwrap();
    let out = sync(&p.lab, &p.folder);
    let err = out.stderr();
    assert!(err.contains("takes back 7 answers"), "{err}");
    assert!(err.contains(&id_of(&p.laptop)), "{err}");
    assert_eq!(live_log(&p.lab).len(), 0);
}

fn cards(data: &Path, now: &str, args: &[&str]) -> Output {
    Flipcard::new(data)
        .now(now)
        .arg("cards")
        .args(args)
        .run()
        .ok()
}

#[test]
fn an_unsuspend_takes_effect_after_a_suspend_from_a_clock_that_runs_ahead() {
    let p = pair();
    let item = format!("{DECK}/body-frame-why");
    // The lab's clock runs an hour ahead.
    cards(&p.lab, "2026-06-01T13:00:00Z", &["suspend", &item]);
    sync(&p.lab, &p.folder);
    sync(&p.laptop, &p.folder);
    assert_eq!(statuses(&p.laptop).len(), 1, "suspended here too");
    // Ten minutes later by the laptop's clock (before the lab's suspend by
    // the lab's), the learner unsuspends it on the laptop.
    cards(&p.laptop, "2026-06-01T12:10:00Z", &["unsuspend", &item]);
    let listed = cards(&p.laptop, "2026-06-01T12:10:00Z", &["list", "is:suspended"]);
    assert!(
        !listed.stdout().contains("body-frame-why"),
        "{}",
        listed.stdout()
    );
    assert!(statuses(&p.laptop).is_empty(), "{:?}", statuses(&p.laptop));
    sync(&p.laptop, &p.folder);
    sync(&p.lab, &p.folder);
    assert!(statuses(&p.lab).is_empty(), "{:?}", statuses(&p.lab));
    same(&p.laptop, &p.lab);
}

#[test]
fn lines_with_impossible_ids_or_dates_are_refused_and_said_once() {
    let p = pair();
    let review = |deck: &str, card: &str, direction: &str, at: &str| {
        format!(
            "{{\"event\":\"review\",\"deck\":\"{deck}\",\"card\":\"{card}\",\"direction\":\"{direction}\",\"reviewed_at\":\"{at}\",\"rating\":3,\"cram\":false,\"duration_ms\":100,\"undone\":false}}\n"
        )
    };
    let ok = "2026-05-01T08:00:00Z";
    let mut forged = String::new();
    for line in [
        review(DECK, "c", "forward", "1969-12-31T23:59:59Z"),
        review(DECK, "c", "forward", "9999-12-31T23:59:59.999-23:59"),
        review(DECK, "c", "forward", "3000-01-01T00:00:00Z"),
        review("../../etc", "c", "forward", ok),
        review(DECK, "a/b", "forward", ok),
        review(DECK, "x\\u001b]0;pwned\\u0007", "forward", ok),
        review(DECK, "c", "c1000", ok),
        review(DECK, "c", "sideways", ok),
        "not json at all\n".to_string(),
        review(DECK, "good-card", "forward", ok),
    ] {
        forged.push_str(&line);
    }
    // A line dated two days after this machine's clock: perhaps a clock
    // that runs ahead, so read again later.
    forged.push_str(&review(DECK, "later", "forward", "2026-06-03T12:00:00Z"));
    let file = p.folder.join(format!("{FORGED}.jsonl"));
    std::fs::write(&file, &forged).unwrap();
    let out = sync(&p.lab, &p.folder);
    let (said, err) = (out.stdout(), out.stderr());
    assert!(said.contains("1 review merged"), "{said}");
    assert!(!err.contains('\u{1b}') && !err.contains('\u{7}'), "{err:?}");
    assert_eq!(
        err.lines().count(),
        2,
        "one warning for each kind of line: {err}"
    );
    assert!(err.contains(":1: skipped: 1969-12-31T23:59:59"), "{err}");
    assert!(err.contains("(and 8 more)"), "{err}");
    assert!(err.contains(":11: skipped: 2026-06-03T12:00:00"), "{err}");
    assert!(err.contains("read again at the next sync"), "{err}");
    let live = live_log(&p.lab);
    assert_eq!(live.len(), 1);
    assert_eq!(live[0].card, "good-card");
    // Said once: nothing again at the next sync.
    let out = sync(&p.lab, &p.folder);
    assert!(out.stderr.is_empty(), "{}", out.stderr());

    // A file of garbage: one warning, with the count.
    let garbage: String = (0..1000).map(|i| format!("garbage {i}\n")).collect();
    std::fs::write(
        p.folder.join("eeeeeeeeeeeeeeeeeeeeeeeeeeeeeeee.jsonl"),
        garbage,
    )
    .unwrap();
    let out = sync(&p.lab, &p.folder);
    let err = out.stderr();
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("(and 999 more)"), "{err}");
}

#[test]
fn a_machine_id_that_links_to_nothing_is_one_line() {
    let p = pair();
    std::fs::create_dir_all(&p.laptop).unwrap();
    std::os::unix::fs::symlink("/nonexistent/machine-id", p.laptop.join("machine-id")).unwrap();
    let out = sync_cmd(&p.laptop, &p.folder).run();
    let err = out.stderr();
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("machine-id: a link to nothing"), "{err}");
    // A FIFO there is refused too, never waited on.
    std::fs::remove_file(p.laptop.join("machine-id")).unwrap();
    mkfifo(&p.laptop.join("machine-id"));
    let out = sync_cmd(&p.laptop, &p.folder).run();
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stderr().contains("FIFO"), "{}", out.stderr());
}

#[test]
fn two_syncs_of_one_data_folder_at_once_both_succeed() {
    let p = pair();
    for round in 0..8 {
        study(
            &p.laptop,
            &format!("2026-05-{:02}T08:00:00Z", round + 1),
            &[("torque-free-meaning", Rating::Good, 0)],
        );
        let children: Vec<_> = (0..2)
            .map(|_| {
                sync_cmd(&p.laptop, &p.folder)
                    .command()
                    .stdout(Stdio::piped())
                    .stderr(Stdio::piped())
                    .spawn()
                    .unwrap()
            })
            .collect();
        for c in children {
            let out = c.wait_with_output().unwrap();
            assert!(out.status.success(), "round {round}: {}", text(&out.stderr));
        }
    }
    sync(&p.lab, &p.folder);
    same(&p.laptop, &p.lab);
    assert_eq!(live_log(&p.lab).len(), 8);
}
