//! The schema and its migrations. `PRAGMA user_version` holds the number of
//! migrations applied; each migration runs in its own transaction, and an
//! existing database is copied with `VACUUM INTO` before the first one.

use std::path::{Path, PathBuf};

use rusqlite::Connection;

use crate::sched::clock::Clock;

use super::error::StoreError;

/// Migration `i` takes the schema from version `i` to `i + 1`.
pub const MIGRATIONS: &[&str] = &[V1, V2, V3, V4, V5, V6, V7, V8];

/// The schema version this build writes.
pub(crate) fn current_version() -> i64 {
    MIGRATIONS.len() as i64
}

/// Version 1: the append-only review log, the caches rebuilt from it (card
/// states, answer tallies), predict-then-check attempts and sessions (so
/// undo only reaches back within one running app, even with two apps open).
const V1: &str = r#"
CREATE TABLE session (
    id          INTEGER PRIMARY KEY,
    started_at  INTEGER NOT NULL
) STRICT;

CREATE TABLE review (
    id              INTEGER PRIMARY KEY,
    session         INTEGER REFERENCES session(id),
    deck            TEXT NOT NULL CHECK (deck <> ''),
    card            TEXT NOT NULL CHECK (card <> ''),
    direction       TEXT NOT NULL CHECK (direction IN ('forward', 'backward')),
    reviewed_at     INTEGER NOT NULL,
    rating          INTEGER NOT NULL CHECK (rating BETWEEN 1 AND 4),
    kind            TEXT NOT NULL CHECK (kind IN ('learn', 'review', 'relearn', 'cram')),
    elapsed_days    INTEGER NOT NULL,
    scheduled_days  INTEGER NOT NULL,
    stability       REAL,
    difficulty      REAL,
    state           TEXT NOT NULL CHECK (state IN ('new', 'learning', 'review', 'relearning')),
    step            INTEGER CHECK (step >= 0),
    due             INTEGER NOT NULL,
    last_review     INTEGER,
    duration_ms     INTEGER NOT NULL CHECK (duration_ms >= 0),
    undone          INTEGER NOT NULL DEFAULT 0 CHECK (undone IN (0, 1))
) STRICT;

CREATE INDEX review_item ON review(deck, card, direction, id);
CREATE INDEX review_time ON review(reviewed_at);
CREATE INDEX review_deck_time ON review(deck, reviewed_at);
CREATE INDEX review_session ON review(session, id);
-- Items answered only in cram mode have no card_state row; this finds them.
CREATE INDEX review_cram ON review(deck, card, direction, undone) WHERE kind = 'cram';

-- The log is append-only: no row is ever deleted, and the only change a row
-- may see is being marked undone.
CREATE TRIGGER review_no_delete BEFORE DELETE ON review
BEGIN
    SELECT RAISE(ABORT, 'the review log is append-only: rows are never deleted');
END;

CREATE TRIGGER review_only_undo BEFORE UPDATE ON review
WHEN NEW.undone IS NOT 1
  OR NEW.id IS NOT OLD.id
  OR NEW.session IS NOT OLD.session
  OR NEW.deck IS NOT OLD.deck
  OR NEW.card IS NOT OLD.card
  OR NEW.direction IS NOT OLD.direction
  OR NEW.reviewed_at IS NOT OLD.reviewed_at
  OR NEW.rating IS NOT OLD.rating
  OR NEW.kind IS NOT OLD.kind
  OR NEW.elapsed_days IS NOT OLD.elapsed_days
  OR NEW.scheduled_days IS NOT OLD.scheduled_days
  OR NEW.stability IS NOT OLD.stability
  OR NEW.difficulty IS NOT OLD.difficulty
  OR NEW.state IS NOT OLD.state
  OR NEW.step IS NOT OLD.step
  OR NEW.due IS NOT OLD.due
  OR NEW.last_review IS NOT OLD.last_review
  OR NEW.duration_ms IS NOT OLD.duration_ms
BEGIN
    SELECT RAISE(ABORT, 'the review log is append-only: only undone may change, to 1');
END;

-- A cache of each item's state, derived from the log (`flipcard db rebuild`).
-- An item without a row is new.
CREATE TABLE card_state (
    deck         TEXT NOT NULL,
    card         TEXT NOT NULL,
    direction    TEXT NOT NULL CHECK (direction IN ('forward', 'backward')),
    state        TEXT NOT NULL CHECK (state IN ('new', 'learning', 'review', 'relearning')),
    step         INTEGER,
    stability    REAL,
    difficulty   REAL,
    due          INTEGER NOT NULL,
    last_review  INTEGER,
    reps         INTEGER NOT NULL CHECK (reps >= 0),
    lapses       INTEGER NOT NULL CHECK (lapses >= 0),
    review_id    INTEGER NOT NULL REFERENCES review(id),
    PRIMARY KEY (deck, card, direction)
) STRICT, WITHOUT ROWID;

CREATE INDEX card_state_due ON card_state(deck, due);

-- How many answers that count (not undone) each deck has, by kind and
-- rating: all-time figures without reading the whole log. Derived from the
-- log like card_state, and rebuilt with it.
CREATE TABLE review_tally (
    deck    TEXT NOT NULL,
    kind    TEXT NOT NULL CHECK (kind IN ('learn', 'review', 'relearn', 'cram')),
    rating  INTEGER NOT NULL CHECK (rating BETWEEN 1 AND 4),
    n       INTEGER NOT NULL CHECK (n >= 0),
    PRIMARY KEY (deck, kind, rating)
) STRICT, WITHOUT ROWID;

CREATE TABLE prompt_attempt (
    id            INTEGER PRIMARY KEY,
    session       INTEGER REFERENCES session(id),
    deck          TEXT NOT NULL CHECK (deck <> ''),
    prompt        TEXT NOT NULL CHECK (prompt <> ''),
    attempted_at  INTEGER NOT NULL,
    prediction    TEXT NOT NULL,
    measured      REAL,
    correct       INTEGER NOT NULL CHECK (correct IN (0, 1))
) STRICT;

CREATE INDEX prompt_attempt_deck ON prompt_attempt(deck, prompt);

CREATE TRIGGER prompt_attempt_no_delete BEFORE DELETE ON prompt_attempt
BEGIN
    SELECT RAISE(ABORT, 'prompt attempts are append-only: rows are never deleted');
END;

CREATE TRIGGER prompt_attempt_no_update BEFORE UPDATE ON prompt_attempt
BEGIN
    SELECT RAISE(ABORT, 'prompt attempts are append-only: rows never change');
END;
"#;

/// Version 2: cloze items (directions `c1`, `c2`, …), and the status log:
/// suspend, unsuspend, bury and leech events, append-only like the review
/// log, with the status cache derived from it. SQLite cannot change a
/// CHECK constraint in place, so the review log is copied into a table
/// that allows the new directions.
const V2: &str = r#"
CREATE TABLE review_v2 (
    id              INTEGER PRIMARY KEY,
    session         INTEGER REFERENCES session(id),
    deck            TEXT NOT NULL CHECK (deck <> ''),
    card            TEXT NOT NULL CHECK (card <> ''),
    direction       TEXT NOT NULL CHECK (direction IN ('forward', 'backward')
                        OR (direction GLOB 'c[1-9]*' AND direction NOT GLOB 'c*[^0-9]*')),
    reviewed_at     INTEGER NOT NULL,
    rating          INTEGER NOT NULL CHECK (rating BETWEEN 1 AND 4),
    kind            TEXT NOT NULL CHECK (kind IN ('learn', 'review', 'relearn', 'cram')),
    elapsed_days    INTEGER NOT NULL,
    scheduled_days  INTEGER NOT NULL,
    stability       REAL,
    difficulty      REAL,
    state           TEXT NOT NULL CHECK (state IN ('new', 'learning', 'review', 'relearning')),
    step            INTEGER CHECK (step >= 0),
    due             INTEGER NOT NULL,
    last_review     INTEGER,
    duration_ms     INTEGER NOT NULL CHECK (duration_ms >= 0),
    undone          INTEGER NOT NULL DEFAULT 0 CHECK (undone IN (0, 1))
) STRICT;
INSERT INTO review_v2 SELECT * FROM review;

-- The cache is kept in a table without constraints meanwhile: a row
-- referring to the old log while it is dropped would count as a violation.
CREATE TABLE card_state_copy AS SELECT * FROM card_state;
DROP TABLE card_state;
DROP TRIGGER review_no_delete;
DROP TRIGGER review_only_undo;
DROP TABLE review;
ALTER TABLE review_v2 RENAME TO review;

CREATE TABLE card_state (
    deck         TEXT NOT NULL,
    card         TEXT NOT NULL,
    direction    TEXT NOT NULL,
    state        TEXT NOT NULL CHECK (state IN ('new', 'learning', 'review', 'relearning')),
    step         INTEGER,
    stability    REAL,
    difficulty   REAL,
    due          INTEGER NOT NULL,
    last_review  INTEGER,
    reps         INTEGER NOT NULL CHECK (reps >= 0),
    lapses       INTEGER NOT NULL CHECK (lapses >= 0),
    review_id    INTEGER NOT NULL REFERENCES review(id),
    PRIMARY KEY (deck, card, direction)
) STRICT, WITHOUT ROWID;
INSERT INTO card_state SELECT * FROM card_state_copy;
DROP TABLE card_state_copy;

CREATE INDEX review_item ON review(deck, card, direction, id);
CREATE INDEX review_time ON review(reviewed_at);
CREATE INDEX review_deck_time ON review(deck, reviewed_at);
CREATE INDEX review_session ON review(session, id);
CREATE INDEX review_cram ON review(deck, card, direction, undone) WHERE kind = 'cram';
CREATE INDEX card_state_due ON card_state(deck, due);

CREATE TRIGGER review_no_delete BEFORE DELETE ON review
BEGIN
    SELECT RAISE(ABORT, 'the review log is append-only: rows are never deleted');
END;

CREATE TRIGGER review_only_undo BEFORE UPDATE ON review
WHEN NEW.undone IS NOT 1
  OR NEW.id IS NOT OLD.id
  OR NEW.session IS NOT OLD.session
  OR NEW.deck IS NOT OLD.deck
  OR NEW.card IS NOT OLD.card
  OR NEW.direction IS NOT OLD.direction
  OR NEW.reviewed_at IS NOT OLD.reviewed_at
  OR NEW.rating IS NOT OLD.rating
  OR NEW.kind IS NOT OLD.kind
  OR NEW.elapsed_days IS NOT OLD.elapsed_days
  OR NEW.scheduled_days IS NOT OLD.scheduled_days
  OR NEW.stability IS NOT OLD.stability
  OR NEW.difficulty IS NOT OLD.difficulty
  OR NEW.state IS NOT OLD.state
  OR NEW.step IS NOT OLD.step
  OR NEW.due IS NOT OLD.due
  OR NEW.last_review IS NOT OLD.last_review
  OR NEW.duration_ms IS NOT OLD.duration_ms
BEGIN
    SELECT RAISE(ABORT, 'the review log is append-only: only undone may change, to 1');
END;

-- Changes of an item's status. `cause` is the rating that brought the
-- event about (a leech found, siblings buried), undone with it;
-- `after_review` is the newest review id when the event was written, so
-- that undo can tell which came last; `batch` (the id of its first event)
-- groups the events of one change. `until` ends a bury.
CREATE TABLE status_event (
    id            INTEGER PRIMARY KEY,
    session       INTEGER REFERENCES session(id),
    deck          TEXT NOT NULL CHECK (deck <> ''),
    card          TEXT NOT NULL CHECK (card <> ''),
    direction     TEXT NOT NULL CHECK (direction IN ('forward', 'backward')
                      OR (direction GLOB 'c[1-9]*' AND direction NOT GLOB 'c*[^0-9]*')),
    at            INTEGER NOT NULL,
    action        TEXT NOT NULL CHECK (action IN ('suspend', 'unsuspend', 'bury', 'leech')),
    until         INTEGER,
    cause         INTEGER REFERENCES review(id),
    after_review  INTEGER NOT NULL DEFAULT 0,
    batch         INTEGER NOT NULL,
    undone        INTEGER NOT NULL DEFAULT 0 CHECK (undone IN (0, 1)),
    CHECK ((action = 'bury') = (until IS NOT NULL))
) STRICT;

CREATE INDEX status_event_item ON status_event(deck, card, direction, id);
CREATE INDEX status_event_session ON status_event(session, id);
CREATE INDEX status_event_cause ON status_event(cause) WHERE cause IS NOT NULL;

CREATE TRIGGER status_event_no_delete BEFORE DELETE ON status_event
BEGIN
    SELECT RAISE(ABORT, 'the status log is append-only: rows are never deleted');
END;

CREATE TRIGGER status_event_only_undo BEFORE UPDATE ON status_event
WHEN NEW.undone IS NOT 1
  OR NEW.id IS NOT OLD.id
  OR NEW.session IS NOT OLD.session
  OR NEW.deck IS NOT OLD.deck
  OR NEW.card IS NOT OLD.card
  OR NEW.direction IS NOT OLD.direction
  OR NEW.at IS NOT OLD.at
  OR NEW.action IS NOT OLD.action
  OR NEW.until IS NOT OLD.until
  OR NEW.cause IS NOT OLD.cause
  OR NEW.after_review IS NOT OLD.after_review
  OR NEW.batch IS NOT OLD.batch
BEGIN
    SELECT RAISE(ABORT, 'the status log is append-only: only undone may change, to 1');
END;

-- Each item's status from the events that count (`flipcard db rebuild`
-- derives it again); an item without a row is active.
CREATE TABLE item_status (
    deck          TEXT NOT NULL,
    card          TEXT NOT NULL,
    direction     TEXT NOT NULL,
    suspended     INTEGER NOT NULL CHECK (suspended IN (0, 1)),
    buried_until  INTEGER,
    leech         INTEGER NOT NULL CHECK (leech IN (0, 1)),
    PRIMARY KEY (deck, card, direction)
) STRICT, WITHOUT ROWID;
"#;

/// Version 3: where each answer and status event came from, for sync.
/// `origin` is the machine id of the sync file an event was merged from;
/// NULL is this database's own machine. It may be set once (a row merged
/// before origins were kept, or this machine's rows when it takes a new id)
/// and never changed after. The sync tables remember, per folder, what the
/// last sync saw (so a sync with nothing new does nothing) and, per file,
/// the line up to which its problems were reported (a written line never
/// changes, so each is reported once).
const V3: &str = r#"
ALTER TABLE review ADD COLUMN origin TEXT CHECK (origin <> '');
ALTER TABLE status_event ADD COLUMN origin TEXT CHECK (origin <> '');

DROP TRIGGER review_only_undo;
CREATE TRIGGER review_only_undo BEFORE UPDATE ON review
WHEN (NEW.undone IS NOT OLD.undone AND NEW.undone IS NOT 1)
  OR (NEW.origin IS NOT OLD.origin AND OLD.origin IS NOT NULL)
  OR NEW.id IS NOT OLD.id
  OR NEW.session IS NOT OLD.session
  OR NEW.deck IS NOT OLD.deck
  OR NEW.card IS NOT OLD.card
  OR NEW.direction IS NOT OLD.direction
  OR NEW.reviewed_at IS NOT OLD.reviewed_at
  OR NEW.rating IS NOT OLD.rating
  OR NEW.kind IS NOT OLD.kind
  OR NEW.elapsed_days IS NOT OLD.elapsed_days
  OR NEW.scheduled_days IS NOT OLD.scheduled_days
  OR NEW.stability IS NOT OLD.stability
  OR NEW.difficulty IS NOT OLD.difficulty
  OR NEW.state IS NOT OLD.state
  OR NEW.step IS NOT OLD.step
  OR NEW.due IS NOT OLD.due
  OR NEW.last_review IS NOT OLD.last_review
  OR NEW.duration_ms IS NOT OLD.duration_ms
BEGIN
    SELECT RAISE(ABORT, 'the review log is append-only: only undone may change, to 1, and origin, once');
END;

DROP TRIGGER status_event_only_undo;
CREATE TRIGGER status_event_only_undo BEFORE UPDATE ON status_event
WHEN (NEW.undone IS NOT OLD.undone AND NEW.undone IS NOT 1)
  OR (NEW.origin IS NOT OLD.origin AND OLD.origin IS NOT NULL)
  OR NEW.id IS NOT OLD.id
  OR NEW.session IS NOT OLD.session
  OR NEW.deck IS NOT OLD.deck
  OR NEW.card IS NOT OLD.card
  OR NEW.direction IS NOT OLD.direction
  OR NEW.at IS NOT OLD.at
  OR NEW.action IS NOT OLD.action
  OR NEW.until IS NOT OLD.until
  OR NEW.cause IS NOT OLD.cause
  OR NEW.after_review IS NOT OLD.after_review
  OR NEW.batch IS NOT OLD.batch
BEGIN
    SELECT RAISE(ABORT, 'the status log is append-only: only undone may change, to 1, and origin, once');
END;

-- A new status event is timed after every one this log holds (a hybrid
-- logical clock): the latest is found through this index.
CREATE INDEX status_event_at ON status_event(at);

-- The ids this data folder synced under before its current one (a sync
-- that finds its file written by another copy takes a new one): its rows
-- found in those files came from there.
CREATE TABLE machine_history (
    id  TEXT PRIMARY KEY
) STRICT;

-- The newest rows written before origins were kept: a row up to these with
-- no origin may have been merged from another machine without saying so.
CREATE TABLE sync_legacy (
    review_max  INTEGER NOT NULL,
    status_max  INTEGER NOT NULL
) STRICT;
INSERT INTO sync_legacy
    SELECT (SELECT coalesce(max(id), 0) FROM review),
           (SELECT coalesce(max(id), 0) FROM status_event);

CREATE TABLE sync_folder (
    dir          TEXT PRIMARY KEY,
    fingerprint  TEXT NOT NULL
) STRICT;

CREATE TABLE sync_file (
    dir               TEXT NOT NULL,
    name              TEXT NOT NULL,
    reported_through  INTEGER NOT NULL CHECK (reported_through >= 0),
    PRIMARY KEY (dir, name)
) STRICT, WITHOUT ROWID;
"#;

/// Version 4: an attempt is kept when the learner commits to it, before the
/// run plays, and its verdict is written once when the run ends. `attempt`
/// numbers the attempts at one prompt from 1 (a later one is a retry; a
/// row another program inserts without one is a first); `correct` is NULL
/// (with `measured` and `judged_at`, when the verdict was written) until
/// the run ends, and for good when the learner left the run before. Attempts stored before kept their verdict: they were
/// written at the run's end, so their `judged_at` is their `attempted_at`,
/// and they are numbered in the order of their times. SQLite cannot drop a
/// NOT NULL in place, so the table is copied into one that allows the
/// verdict to wait.
const V4: &str = r#"
CREATE TABLE prompt_attempt_v4 (
    id            INTEGER PRIMARY KEY,
    session       INTEGER REFERENCES session(id),
    deck          TEXT NOT NULL CHECK (deck <> ''),
    prompt        TEXT NOT NULL CHECK (prompt <> ''),
    attempted_at  INTEGER NOT NULL,
    prediction    TEXT NOT NULL,
    measured      REAL,
    correct       INTEGER CHECK (correct IN (0, 1)),
    attempt       INTEGER NOT NULL DEFAULT 1 CHECK (attempt >= 1),
    judged_at     INTEGER,
    CHECK (correct IS NOT NULL OR (measured IS NULL AND judged_at IS NULL))
) STRICT;
INSERT INTO prompt_attempt_v4 (id, session, deck, prompt, attempted_at, prediction,
                               measured, correct, attempt, judged_at)
    SELECT id, session, deck, prompt, attempted_at, prediction, measured, correct,
           row_number() OVER (PARTITION BY deck, prompt ORDER BY attempted_at, id),
           attempted_at
    FROM prompt_attempt;
DROP TRIGGER prompt_attempt_no_delete;
DROP TRIGGER prompt_attempt_no_update;
DROP TABLE prompt_attempt;
ALTER TABLE prompt_attempt_v4 RENAME TO prompt_attempt;

CREATE INDEX prompt_attempt_deck ON prompt_attempt(deck, prompt, attempt);

CREATE TRIGGER prompt_attempt_no_delete BEFORE DELETE ON prompt_attempt
BEGIN
    SELECT RAISE(ABORT, 'prompt attempts are append-only: rows are never deleted');
END;

-- The one change a row may see: its verdict (correct, with measured and
-- judged_at) written once, where there was none.
CREATE TRIGGER prompt_attempt_verdict_once BEFORE UPDATE ON prompt_attempt
WHEN OLD.correct IS NOT NULL
  OR NEW.correct IS NULL
  OR NEW.id IS NOT OLD.id
  OR NEW.session IS NOT OLD.session
  OR NEW.deck IS NOT OLD.deck
  OR NEW.prompt IS NOT OLD.prompt
  OR NEW.attempted_at IS NOT OLD.attempted_at
  OR NEW.prediction IS NOT OLD.prediction
  OR NEW.attempt IS NOT OLD.attempt
BEGIN
    SELECT RAISE(ABORT, 'prompt attempts are append-only: only the verdict may be written, once');
END;
"#;

/// Version 5: an attempt's verdict names the misconception a wrong answer
/// stands for (issue 24 §3), the deck's misconception id, written with the
/// verdict (the one UPDATE the trigger of version 4 allows: `correct` goes
/// from NULL to a value in the same statement) and never on a right
/// answer. Earlier attempts keep every column and have none. A column
/// added in place keeps the table, its rows and its append-only triggers.
const V5: &str = r#"
ALTER TABLE prompt_attempt ADD COLUMN misconception TEXT
    CHECK (misconception IS NULL OR (misconception <> '' AND correct = 0));
"#;

/// Version 6 (issue 24): prompts and derivations are review items, so the
/// logs take their directions, `predict` and `derive`, beside `forward`,
/// `backward` and `cN`; and an attempt at a varied prompt keeps the seed
/// its numbers were drawn from (`variant`, written with the commitment, at
/// most 2⁵³ − 1, exact in JSON; NULL for a prompt asked the same way every
/// time and for every earlier attempt), held by the append-only trigger as
/// the prediction is. SQLite cannot change a CHECK in place, so `review`
/// and `status_event` are copied into tables that allow the new
/// directions (every row, id and column kept), as version 2 did: the
/// caches that refer to them (`card_state`, and the events' `cause`) are
/// set aside meanwhile, and every index and append-only trigger is made
/// again as it was.
const V6: &str = r#"
CREATE TABLE review_v6 (
    id              INTEGER PRIMARY KEY,
    session         INTEGER REFERENCES session(id),
    deck            TEXT NOT NULL CHECK (deck <> ''),
    card            TEXT NOT NULL CHECK (card <> ''),
    direction       TEXT NOT NULL CHECK (direction IN ('forward', 'backward', 'predict', 'derive')
                        OR (direction GLOB 'c[1-9]*' AND direction NOT GLOB 'c*[^0-9]*')),
    reviewed_at     INTEGER NOT NULL,
    rating          INTEGER NOT NULL CHECK (rating BETWEEN 1 AND 4),
    kind            TEXT NOT NULL CHECK (kind IN ('learn', 'review', 'relearn', 'cram')),
    elapsed_days    INTEGER NOT NULL,
    scheduled_days  INTEGER NOT NULL,
    stability       REAL,
    difficulty      REAL,
    state           TEXT NOT NULL CHECK (state IN ('new', 'learning', 'review', 'relearning')),
    step            INTEGER CHECK (step >= 0),
    due             INTEGER NOT NULL,
    last_review     INTEGER,
    duration_ms     INTEGER NOT NULL CHECK (duration_ms >= 0),
    undone          INTEGER NOT NULL DEFAULT 0 CHECK (undone IN (0, 1)),
    origin          TEXT CHECK (origin <> '')
) STRICT;
INSERT INTO review_v6 SELECT * FROM review;

CREATE TABLE status_event_v6 (
    id            INTEGER PRIMARY KEY,
    session       INTEGER REFERENCES session(id),
    deck          TEXT NOT NULL CHECK (deck <> ''),
    card          TEXT NOT NULL CHECK (card <> ''),
    direction     TEXT NOT NULL CHECK (direction IN ('forward', 'backward', 'predict', 'derive')
                      OR (direction GLOB 'c[1-9]*' AND direction NOT GLOB 'c*[^0-9]*')),
    at            INTEGER NOT NULL,
    action        TEXT NOT NULL CHECK (action IN ('suspend', 'unsuspend', 'bury', 'leech')),
    until         INTEGER,
    cause         INTEGER,
    after_review  INTEGER NOT NULL DEFAULT 0,
    batch         INTEGER NOT NULL,
    undone        INTEGER NOT NULL DEFAULT 0 CHECK (undone IN (0, 1)),
    origin        TEXT CHECK (origin <> ''),
    CHECK ((action = 'bury') = (until IS NOT NULL))
) STRICT;
INSERT INTO status_event_v6 SELECT * FROM status_event;

-- The cache is kept in a table without constraints meanwhile: a row
-- referring to the old log while it is dropped would count as a violation.
CREATE TABLE card_state_copy AS SELECT * FROM card_state;
DROP TABLE card_state;
DROP TRIGGER status_event_no_delete;
DROP TRIGGER status_event_only_undo;
DROP TABLE status_event;
DROP TRIGGER review_no_delete;
DROP TRIGGER review_only_undo;
DROP TABLE review;
ALTER TABLE review_v6 RENAME TO review;

CREATE TABLE status_event (
    id            INTEGER PRIMARY KEY,
    session       INTEGER REFERENCES session(id),
    deck          TEXT NOT NULL CHECK (deck <> ''),
    card          TEXT NOT NULL CHECK (card <> ''),
    direction     TEXT NOT NULL CHECK (direction IN ('forward', 'backward', 'predict', 'derive')
                      OR (direction GLOB 'c[1-9]*' AND direction NOT GLOB 'c*[^0-9]*')),
    at            INTEGER NOT NULL,
    action        TEXT NOT NULL CHECK (action IN ('suspend', 'unsuspend', 'bury', 'leech')),
    until         INTEGER,
    cause         INTEGER REFERENCES review(id),
    after_review  INTEGER NOT NULL DEFAULT 0,
    batch         INTEGER NOT NULL,
    undone        INTEGER NOT NULL DEFAULT 0 CHECK (undone IN (0, 1)),
    origin        TEXT CHECK (origin <> ''),
    CHECK ((action = 'bury') = (until IS NOT NULL))
) STRICT;
INSERT INTO status_event SELECT * FROM status_event_v6;
DROP TABLE status_event_v6;

CREATE TABLE card_state (
    deck         TEXT NOT NULL,
    card         TEXT NOT NULL,
    direction    TEXT NOT NULL,
    state        TEXT NOT NULL CHECK (state IN ('new', 'learning', 'review', 'relearning')),
    step         INTEGER,
    stability    REAL,
    difficulty   REAL,
    due          INTEGER NOT NULL,
    last_review  INTEGER,
    reps         INTEGER NOT NULL CHECK (reps >= 0),
    lapses       INTEGER NOT NULL CHECK (lapses >= 0),
    review_id    INTEGER NOT NULL REFERENCES review(id),
    PRIMARY KEY (deck, card, direction)
) STRICT, WITHOUT ROWID;
INSERT INTO card_state SELECT * FROM card_state_copy;
DROP TABLE card_state_copy;

CREATE INDEX review_item ON review(deck, card, direction, id);
CREATE INDEX review_time ON review(reviewed_at);
CREATE INDEX review_deck_time ON review(deck, reviewed_at);
CREATE INDEX review_session ON review(session, id);
CREATE INDEX review_cram ON review(deck, card, direction, undone) WHERE kind = 'cram';
CREATE INDEX card_state_due ON card_state(deck, due);
CREATE INDEX status_event_item ON status_event(deck, card, direction, id);
CREATE INDEX status_event_session ON status_event(session, id);
CREATE INDEX status_event_cause ON status_event(cause) WHERE cause IS NOT NULL;
CREATE INDEX status_event_at ON status_event(at);

CREATE TRIGGER review_no_delete BEFORE DELETE ON review
BEGIN
    SELECT RAISE(ABORT, 'the review log is append-only: rows are never deleted');
END;

CREATE TRIGGER review_only_undo BEFORE UPDATE ON review
WHEN (NEW.undone IS NOT OLD.undone AND NEW.undone IS NOT 1)
  OR (NEW.origin IS NOT OLD.origin AND OLD.origin IS NOT NULL)
  OR NEW.id IS NOT OLD.id
  OR NEW.session IS NOT OLD.session
  OR NEW.deck IS NOT OLD.deck
  OR NEW.card IS NOT OLD.card
  OR NEW.direction IS NOT OLD.direction
  OR NEW.reviewed_at IS NOT OLD.reviewed_at
  OR NEW.rating IS NOT OLD.rating
  OR NEW.kind IS NOT OLD.kind
  OR NEW.elapsed_days IS NOT OLD.elapsed_days
  OR NEW.scheduled_days IS NOT OLD.scheduled_days
  OR NEW.stability IS NOT OLD.stability
  OR NEW.difficulty IS NOT OLD.difficulty
  OR NEW.state IS NOT OLD.state
  OR NEW.step IS NOT OLD.step
  OR NEW.due IS NOT OLD.due
  OR NEW.last_review IS NOT OLD.last_review
  OR NEW.duration_ms IS NOT OLD.duration_ms
BEGIN
    SELECT RAISE(ABORT, 'the review log is append-only: only undone may change, to 1, and origin, once');
END;

CREATE TRIGGER status_event_no_delete BEFORE DELETE ON status_event
BEGIN
    SELECT RAISE(ABORT, 'the status log is append-only: rows are never deleted');
END;

CREATE TRIGGER status_event_only_undo BEFORE UPDATE ON status_event
WHEN (NEW.undone IS NOT OLD.undone AND NEW.undone IS NOT 1)
  OR (NEW.origin IS NOT OLD.origin AND OLD.origin IS NOT NULL)
  OR NEW.id IS NOT OLD.id
  OR NEW.session IS NOT OLD.session
  OR NEW.deck IS NOT OLD.deck
  OR NEW.card IS NOT OLD.card
  OR NEW.direction IS NOT OLD.direction
  OR NEW.at IS NOT OLD.at
  OR NEW.action IS NOT OLD.action
  OR NEW.until IS NOT OLD.until
  OR NEW.cause IS NOT OLD.cause
  OR NEW.after_review IS NOT OLD.after_review
  OR NEW.batch IS NOT OLD.batch
BEGIN
    SELECT RAISE(ABORT, 'the status log is append-only: only undone may change, to 1, and origin, once');
END;

ALTER TABLE prompt_attempt ADD COLUMN variant INTEGER
    CHECK (variant IS NULL OR (variant >= 0 AND variant <= 9007199254740991));
DROP TRIGGER prompt_attempt_verdict_once;
CREATE TRIGGER prompt_attempt_verdict_once BEFORE UPDATE ON prompt_attempt
WHEN OLD.correct IS NOT NULL
  OR NEW.correct IS NULL
  OR NEW.id IS NOT OLD.id
  OR NEW.session IS NOT OLD.session
  OR NEW.deck IS NOT OLD.deck
  OR NEW.prompt IS NOT OLD.prompt
  OR NEW.attempted_at IS NOT OLD.attempted_at
  OR NEW.prediction IS NOT OLD.prediction
  OR NEW.attempt IS NOT OLD.attempt
  OR NEW.variant IS NOT OLD.variant
BEGIN
    SELECT RAISE(ABORT, 'prompt attempts are append-only: only the verdict may be written, once');
END;
"#;

/// Version 7: the state another program left an item in (an Anki import:
/// Anki's due date, interval and memory state), kept as the base its
/// answers are replayed from (`store::kept`). It holds from `at` (that
/// program's last answer, or its last review when the log has none of its
/// answers): answers up to then are that program's and end in this state,
/// later ones are replayed from it. An item with no answer in the log
/// takes it as its state.
const V7: &str = r#"
CREATE TABLE kept_state (
    deck         TEXT NOT NULL,
    card         TEXT NOT NULL,
    direction    TEXT NOT NULL,
    at           INTEGER NOT NULL,
    state        TEXT NOT NULL CHECK (state IN ('learning', 'review', 'relearning')),
    step         INTEGER,
    stability    REAL,
    difficulty   REAL,
    due          INTEGER NOT NULL,
    last_review  INTEGER,
    PRIMARY KEY (deck, card, direction)
) STRICT, WITHOUT ROWID;
"#;

/// Version 8: an answer keeps the interval the load balancer chose for it
/// (`balanced_days`, whole days; NULL when the day was drawn uniformly or
/// not fuzzed, and for every earlier answer), so a replay of the log (a
/// merge, a sync) puts the item on the same day without the due counts of
/// that moment. A column added in place keeps the table and its rows; the
/// append-only trigger is made again to hold the new column too.
const V8: &str = r#"
ALTER TABLE review ADD COLUMN balanced_days INTEGER
    CHECK (balanced_days IS NULL OR balanced_days BETWEEN 1 AND 36500);
DROP TRIGGER review_only_undo;
CREATE TRIGGER review_only_undo BEFORE UPDATE ON review
WHEN (NEW.undone IS NOT OLD.undone AND NEW.undone IS NOT 1)
  OR (NEW.origin IS NOT OLD.origin AND OLD.origin IS NOT NULL)
  OR NEW.id IS NOT OLD.id
  OR NEW.session IS NOT OLD.session
  OR NEW.deck IS NOT OLD.deck
  OR NEW.card IS NOT OLD.card
  OR NEW.direction IS NOT OLD.direction
  OR NEW.reviewed_at IS NOT OLD.reviewed_at
  OR NEW.rating IS NOT OLD.rating
  OR NEW.kind IS NOT OLD.kind
  OR NEW.elapsed_days IS NOT OLD.elapsed_days
  OR NEW.scheduled_days IS NOT OLD.scheduled_days
  OR NEW.stability IS NOT OLD.stability
  OR NEW.difficulty IS NOT OLD.difficulty
  OR NEW.state IS NOT OLD.state
  OR NEW.step IS NOT OLD.step
  OR NEW.due IS NOT OLD.due
  OR NEW.last_review IS NOT OLD.last_review
  OR NEW.duration_ms IS NOT OLD.duration_ms
  OR NEW.balanced_days IS NOT OLD.balanced_days
BEGIN
    SELECT RAISE(ABORT, 'the review log is append-only: only undone may change, to 1, and origin, once');
END;
"#;

/// Brings the database at `path` up to the last of `migrations`. Before the
/// first migration of a database that already holds a schema, a copy is made
/// next to it (`flipcard.db.bak-v<old>-<timestamp>`).
pub(crate) fn migrate(
    conn: &mut Connection,
    path: &Path,
    migrations: &[&str],
    stamp: &str,
) -> Result<(), StoreError> {
    let sql_err = |e: rusqlite::Error| StoreError::from_sqlite(path, e);
    let target = migrations.len() as i64;
    let found = user_version(conn).map_err(sql_err)?;
    if found == target {
        return Ok(());
    }
    if found > target {
        return Err(StoreError::TooNew {
            path: path.to_path_buf(),
            found,
            supported: target,
        });
    }
    if found == 0 && has_tables(conn).map_err(sql_err)? {
        return Err(StoreError::Foreign {
            path: path.to_path_buf(),
        });
    }
    if found > 0 {
        backup_before_migration(conn, path, found, stamp)?;
    }
    for (i, sql) in migrations.iter().enumerate() {
        // The version is read again inside the write transaction: another
        // instance opening at the same moment may have migrated meanwhile.
        super::write::immediate(conn, path, None, Clock::System, |tx| {
            if user_version(tx)? > i as i64 {
                return Ok(());
            }
            tx.execute_batch(sql)?;
            tx.pragma_update(None, "user_version", i as i64 + 1)?;
            Ok(())
        })?;
    }
    if found == 0 {
        // A new database went through every migration at once, leaving the
        // pages of the tables later ones replaced free inside the file;
        // they are given back so the file is as small as a fresh one.
        conn.execute_batch("VACUUM").map_err(sql_err)?;
        // In WAL mode the vacuumed pages sit in the write-ahead log until
        // a checkpoint a thousand pages later: copied into the file now,
        // the log starts empty (a small disk is not half filled by it).
        conn.query_row("PRAGMA wal_checkpoint(TRUNCATE)", [], |_| Ok(()))
            .map_err(sql_err)?;
    }
    Ok(())
}

fn user_version(conn: &Connection) -> rusqlite::Result<i64> {
    conn.pragma_query_value(None, "user_version", |r| r.get(0))
}

fn has_tables(conn: &Connection) -> rusqlite::Result<bool> {
    conn.query_row(
        "SELECT count(*) FROM sqlite_schema WHERE type = 'table'",
        [],
        |r| r.get::<_, i64>(0),
    )
    .map(|n| n > 0)
}

/// The path of the copy made before migrating from `old` (unique: a counter
/// is added when a copy with the same stamp exists).
pub(crate) fn migration_backup_path(db: &Path, old: i64, stamp: &str) -> PathBuf {
    let name = db
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "flipcard.db".to_string());
    let base = db.with_file_name(format!("{name}.bak-v{old}-{stamp}"));
    let mut candidate = base.clone();
    let mut n = 1;
    while candidate.exists() {
        n += 1;
        candidate = PathBuf::from(format!("{}-{n}", base.display()));
    }
    candidate
}

fn backup_before_migration(
    conn: &Connection,
    db: &Path,
    old: i64,
    stamp: &str,
) -> Result<(), StoreError> {
    let target = migration_backup_path(db, old, stamp);
    super::backup::vacuum_into(conn, &target)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tables(conn: &Connection) -> Vec<String> {
        let mut st = conn
            .prepare("SELECT name FROM sqlite_schema WHERE type = 'table' ORDER BY name")
            .unwrap();
        st.query_map([], |r| r.get(0))
            .unwrap()
            .collect::<Result<_, _>>()
            .unwrap()
    }

    #[test]
    fn version_8_keeps_every_row_and_holds_the_balanced_day_append_only() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("flipcard.db");
        let mut conn = Connection::open(&path).unwrap();
        migrate(&mut conn, &path, &MIGRATIONS[..7], "20260101T000000Z").unwrap();
        conn.execute_batch(
            "INSERT INTO session (id, started_at) VALUES (1, 0);
             INSERT INTO review (session, deck, card, direction, reviewed_at, rating, kind,
               elapsed_days, scheduled_days, stability, difficulty, state, step, due,
               last_review, duration_ms, undone, origin) VALUES
               (1, 'd', 'a', 'forward', 1000, 3, 'learn', 0, 0, 2.3, 5.1, 'learning', 1, 61000,
                1000, 900, 0, NULL),
               (1, 'd', 'a', 'forward', 90000, 4, 'learn', 0, 8, 9.1, 4.2, 'review', NULL,
                691290000, 90000, 1200, 0, 'ab12'),
               (1, 'd', 'b', 'c2', 95000, 1, 'cram', 0, 0, NULL, NULL, 'new', NULL, 95000,
                NULL, 50, 1, NULL);
             INSERT INTO card_state VALUES ('d', 'a', 'forward', 'review', NULL, 9.1, 4.2,
               691290000, 90000, 2, 0, 2);
             INSERT INTO status_event (session, deck, card, direction, at, action, batch)
               VALUES (1, 'd', 'a', 'backward', 90000, 'suspend', 1);",
        )
        .unwrap();
        let dump = |conn: &Connection, sql: &str| -> Vec<String> {
            let mut st = conn.prepare(sql).unwrap();
            let n = st.column_count();
            st.query_map([], |r| {
                Ok((0..n)
                    .map(|i| format!("{:?}", r.get_ref(i).unwrap()))
                    .collect::<Vec<_>>()
                    .join("|"))
            })
            .unwrap()
            .collect::<Result<_, _>>()
            .unwrap()
        };
        let tables = ["review", "card_state", "status_event", "session"];
        let before: Vec<Vec<String>> = tables
            .iter()
            .map(|t| dump(&conn, &format!("SELECT * FROM {t} ORDER BY 1, 2")))
            .collect();
        drop(conn);
        let mut conn = Connection::open(&path).unwrap();
        migrate(&mut conn, &path, MIGRATIONS, "20260102T000000Z").unwrap();
        assert_eq!(user_version(&conn).unwrap(), 8);
        // Every row and column as it was; the new column empty.
        let review_cols = "id, session, deck, card, direction, reviewed_at, rating, kind, \
             elapsed_days, scheduled_days, stability, difficulty, state, step, due, \
             last_review, duration_ms, undone, origin";
        for (t, want) in tables.iter().zip(&before) {
            let cols = if *t == "review" { review_cols } else { "*" };
            assert_eq!(
                &dump(&conn, &format!("SELECT {cols} FROM {t} ORDER BY 1, 2")),
                want,
                "{t}"
            );
        }
        assert_eq!(
            dump(
                &conn,
                "SELECT count(*) FROM review WHERE balanced_days IS NULL"
            ),
            ["Integer(3)"]
        );
        // Held by the append-only trigger, and only an interval.
        let e = conn
            .execute("UPDATE review SET balanced_days = 5 WHERE id = 1", [])
            .unwrap_err();
        assert!(e.to_string().contains("append-only"), "{e}");
        conn.execute("UPDATE review SET undone = 1 WHERE id = 1", [])
            .unwrap();
        for bad in [0, -1, 36_501] {
            let e = conn
                .execute(
                    "INSERT INTO review (deck, card, direction, reviewed_at, rating, kind, \
                     elapsed_days, scheduled_days, state, due, duration_ms, balanced_days) \
                     VALUES ('d', 'z', 'forward', 5000, 3, 'review', 0, 9, 'review', 5600, 10, ?1)",
                    [bad],
                )
                .unwrap_err();
            assert!(e.to_string().contains("CHECK"), "{bad}: {e}");
        }
        drop(conn);
        // The store reads the migrated log (no day kept) and rebuilds the
        // same states from it.
        let mut store = crate::store::Store::open(dir.path()).unwrap();
        let history = store
            .history(&crate::sched::ItemKey::parse("d", "a", "forward").unwrap())
            .unwrap();
        assert_eq!(history.len(), 2);
        assert!(history.iter().all(|l| l.record.balanced_days.is_none()));
        let report = store.rebuild().unwrap();
        assert_eq!(report.reviews, 3);
    }

    #[test]
    fn version_7_adds_the_kept_states_and_keeps_every_row() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("flipcard.db");
        let mut conn = Connection::open(&path).unwrap();
        migrate(&mut conn, &path, &MIGRATIONS[..6], "20260101T000000Z").unwrap();
        conn.execute("INSERT INTO session (id, started_at) VALUES (1, 0)", [])
            .unwrap();
        let count = |conn: &Connection, t: &str| -> i64 {
            conn.query_row(&format!("SELECT count(*) FROM {t}"), [], |r| r.get(0))
                .unwrap()
        };
        let before: Vec<i64> = ["review", "card_state", "status_event"]
            .iter()
            .map(|t| count(&conn, t))
            .collect();
        drop(conn);
        let mut conn = Connection::open(&path).unwrap();
        migrate(&mut conn, &path, &MIGRATIONS[..7], "20260102T000000Z").unwrap();
        assert_eq!(user_version(&conn).unwrap(), 7);
        let after: Vec<i64> = ["review", "card_state", "status_event"]
            .iter()
            .map(|t| count(&conn, t))
            .collect();
        assert_eq!(after, before);
        assert_eq!(count(&conn, "kept_state"), 0);
        // A kept state is learning, review or relearning, never new.
        let insert = |state: &str| {
            conn.execute(
                "INSERT INTO kept_state (deck, card, direction, at, state, due) \
                 VALUES ('d', ?1, 'forward', 0, ?1, 0)",
                [state],
            )
        };
        assert!(insert("review").is_ok());
        assert!(insert("new").is_err());
    }

    #[test]
    fn fresh_database_gets_every_table_and_no_backup() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("flipcard.db");
        let mut conn = Connection::open(&path).unwrap();
        migrate(&mut conn, &path, MIGRATIONS, "20260101T000000Z").unwrap();
        assert_eq!(user_version(&conn).unwrap(), current_version());
        assert_eq!(
            tables(&conn),
            [
                "card_state",
                "item_status",
                "kept_state",
                "machine_history",
                "prompt_attempt",
                "review",
                "review_tally",
                "session",
                "status_event",
                "sync_file",
                "sync_folder",
                "sync_legacy"
            ]
        );
        let entries = std::fs::read_dir(dir.path()).unwrap().count();
        assert_eq!(entries, 1, "no backup of a brand-new database");
    }

    #[test]
    fn migrating_an_existing_database_backs_it_up_first() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("flipcard.db");
        let mut conn = Connection::open(&path).unwrap();
        migrate(&mut conn, &path, MIGRATIONS, "20260101T000000Z").unwrap();
        conn.execute("INSERT INTO session (id, started_at) VALUES (7, 1000)", [])
            .unwrap();

        let v2 = "CREATE TABLE extra (x INTEGER) STRICT;";
        let mut next: Vec<&str> = MIGRATIONS.to_vec();
        next.push(v2);
        migrate(&mut conn, &path, &next, "20260102T030405Z").unwrap();
        assert_eq!(user_version(&conn).unwrap(), current_version() + 1);
        assert!(tables(&conn).contains(&"extra".to_string()));

        let backup = dir.path().join(format!(
            "flipcard.db.bak-v{}-20260102T030405Z",
            current_version()
        ));
        let old = Connection::open(&backup).expect("backup written");
        assert_eq!(user_version(&old).unwrap(), current_version());
        assert!(!tables(&old).contains(&"extra".to_string()));
        let started: i64 = old
            .query_row("SELECT started_at FROM session WHERE id = 7", [], |r| {
                r.get(0)
            })
            .unwrap();
        assert_eq!(started, 1000);
    }

    #[test]
    fn version_4_numbers_old_attempts_and_keeps_their_verdicts() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("flipcard.db");
        let mut conn = Connection::open(&path).unwrap();
        conn.pragma_update(None, "recursive_triggers", true)
            .unwrap();
        migrate(&mut conn, &path, &MIGRATIONS[..3], "20260101T000000Z").unwrap();
        // Version 3 kept an attempt when its run ended, always judged.
        conn.execute_batch(
            "INSERT INTO prompt_attempt (deck, prompt, attempted_at, prediction, measured, correct) VALUES
               ('d', 'p', 3000, 'b', 2.0, 1),
               ('d', 'p', 1000, 'a', 2.0, 0),
               ('d', 'q', 2000, '7', NULL, 0),
               ('e', 'p', 500, 'x', NULL, 1);",
        )
        .unwrap();
        migrate(&mut conn, &path, &MIGRATIONS[..4], "20260102T000000Z").unwrap();
        assert_eq!(user_version(&conn).unwrap(), 4);
        let mut st = conn
            .prepare(
                "SELECT deck || '/' || prompt || ':' || prediction, attempt, correct, \
                 judged_at IS attempted_at FROM prompt_attempt ORDER BY id",
            )
            .unwrap();
        let got: Vec<(String, i64, Option<i64>, bool)> = st
            .query_map([], |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?, r.get(3)?)))
            .unwrap()
            .collect::<Result<_, _>>()
            .unwrap();
        let want = [
            ("d/p:b", 2, Some(1)),
            ("d/p:a", 1, Some(0)),
            ("d/q:7", 1, Some(0)),
            ("e/p:x", 1, Some(1)),
        ]
        .map(|(row, n, correct)| (row.to_string(), n, correct, true));
        assert_eq!(
            got, want,
            "numbered by time per prompt; judged when they were written"
        );
        // The triggers hold on the new table: a judged row never changes,
        // no row is deleted, and an open one takes its verdict once.
        let upd = conn
            .execute(
                "UPDATE prompt_attempt SET correct = 1 WHERE prediction = 'a'",
                [],
            )
            .unwrap_err();
        assert!(upd.to_string().contains("append-only"), "{upd}");
        let del = conn.execute("DELETE FROM prompt_attempt", []).unwrap_err();
        assert!(del.to_string().contains("append-only"), "{del}");
        conn.execute(
            "INSERT INTO prompt_attempt (deck, prompt, attempted_at, prediction, attempt) \
             VALUES ('d', 'p', 4000, 'c', 3)",
            [],
        )
        .unwrap();
        conn.execute(
            "UPDATE prompt_attempt SET correct = 1, measured = 2.0, judged_at = 4100 \
             WHERE prediction = 'c'",
            [],
        )
        .unwrap();
        let twice = conn
            .execute(
                "UPDATE prompt_attempt SET correct = 0, judged_at = 4200 WHERE prediction = 'c'",
                [],
            )
            .unwrap_err();
        assert!(twice.to_string().contains("once"), "{twice}");
    }

    #[test]
    fn version_5_keeps_every_attempt_and_names_misconceptions_with_the_verdict() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("flipcard.db");
        let mut conn = Connection::open(&path).unwrap();
        conn.pragma_update(None, "recursive_triggers", true)
            .unwrap();
        migrate(&mut conn, &path, &MIGRATIONS[..4], "20260101T000000Z").unwrap();
        // Version 4: judged, open (left before the end) and retried attempts.
        conn.execute_batch(
            "INSERT INTO prompt_attempt (deck, prompt, attempted_at, prediction, measured, \
               correct, attempt, judged_at) VALUES
               ('d', 'p', 1000, 'stays', NULL, 0, 1, 1100),
               ('d', 'p', 2000, 'flips', NULL, 1, 2, 2100),
               ('d', 'q', 3000, '4.5', 5.3, 0, 1, 3100);
             INSERT INTO prompt_attempt (deck, prompt, attempted_at, prediction, attempt) \
               VALUES ('d', 'q', 4000, '5.3', 2);",
        )
        .unwrap();
        let rows = |conn: &Connection| -> Vec<String> {
            let mut st = conn
                .prepare(
                    "SELECT id || ' ' || deck || '/' || prompt || ' ' || attempted_at || ' ' || \
                     prediction || ' ' || coalesce(measured, '-') || ' ' || \
                     coalesce(correct, '-') || ' ' || attempt || ' ' || \
                     coalesce(judged_at, '-') FROM prompt_attempt ORDER BY id",
                )
                .unwrap();
            st.query_map([], |r| r.get(0))
                .unwrap()
                .collect::<Result<_, _>>()
                .unwrap()
        };
        let before = rows(&conn);
        drop(conn);
        // Opened by the build of version 5: a backup, then version 5.
        let mut conn = Connection::open(&path).unwrap();
        migrate(&mut conn, &path, &MIGRATIONS[..5], "20260102T000000Z").unwrap();
        assert_eq!(user_version(&conn).unwrap(), 5);
        assert_eq!(rows(&conn), before, "every attempt kept, every column");
        assert!(
            path.with_file_name("flipcard.db.bak-v4-20260102T000000Z")
                .exists(),
            "the version 4 file is kept"
        );
        let none: i64 = conn
            .query_row(
                "SELECT count(*) FROM prompt_attempt WHERE misconception IS NOT NULL",
                [],
                |r| r.get(0),
            )
            .unwrap();
        assert_eq!(none, 0, "older attempts name no misconception");
        // The open attempt takes its verdict with its misconception, once.
        conn.execute(
            "UPDATE prompt_attempt SET correct = 0, measured = 5.3, judged_at = 4100, \
             misconception = 'small-angle-formula' WHERE prediction = '5.3'",
            [],
        )
        .unwrap();
        let again = conn
            .execute(
                "UPDATE prompt_attempt SET misconception = 'other' WHERE prediction = '5.3'",
                [],
            )
            .unwrap_err();
        assert!(again.to_string().contains("append-only"), "{again}");
        let judged = conn
            .execute(
                "UPDATE prompt_attempt SET misconception = 'x' WHERE prediction = 'stays'",
                [],
            )
            .unwrap_err();
        assert!(judged.to_string().contains("append-only"), "{judged}");
        let del = conn.execute("DELETE FROM prompt_attempt", []).unwrap_err();
        assert!(del.to_string().contains("append-only"), "{del}");
        // Never on a right answer, never empty.
        for (correct, id) in [(1, "'m'"), (0, "''")] {
            conn.execute(
                "INSERT INTO prompt_attempt (deck, prompt, attempted_at, prediction, attempt) \
                 VALUES ('d', 'r', 5000, 'a', 1)",
                [],
            )
            .unwrap();
            let e = conn
                .execute(
                    &format!(
                        "UPDATE prompt_attempt SET correct = {correct}, judged_at = 5100, \
                         misconception = {id} WHERE prompt = 'r' AND correct IS NULL"
                    ),
                    [],
                )
                .unwrap_err();
            assert!(e.to_string().contains("CHECK"), "{e}");
        }
    }

    #[test]
    fn version_6_keeps_every_row_and_takes_prompts_as_review_items() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("flipcard.db");
        let mut conn = Connection::open(&path).unwrap();
        conn.pragma_update(None, "foreign_keys", true).unwrap();
        conn.pragma_update(None, "recursive_triggers", true)
            .unwrap();
        migrate(&mut conn, &path, &MIGRATIONS[..5], "20260101T000000Z").unwrap();
        // Version 5: answers (one merged from another machine, one undone),
        // their cached state, status events (one caused by an answer, a
        // bury with its end) and an attempt.
        conn.execute_batch(
            "INSERT INTO session (id, started_at) VALUES (1, 1000);
             INSERT INTO review (id, session, deck, card, direction, reviewed_at, rating, kind, \
               elapsed_days, scheduled_days, stability, difficulty, state, step, due, \
               last_review, duration_ms, undone, origin) VALUES
               (1, 1, 'd', 'a', 'forward', 1000, 3, 'learn', 0, 0, 2.3, 5.1, 'learning', 1, \
                1600, 1000, 4000, 0, NULL),
               (2, 1, 'd', 'a', 'backward', 2000, 1, 'learn', 0, 0, 0.4, 7.2, 'learning', 0, \
                2060, 2000, 3000, 1, NULL),
               (3, NULL, 'd', 'c', 'c12', 3000, 4, 'review', 3, 9, 30.5, 2.2, 'review', NULL, \
                900000, 3000, 2500, 0, 'machine-b');
             INSERT INTO card_state VALUES
               ('d', 'a', 'forward', 'learning', 1, 2.3, 5.1, 1600, 1000, 1, 0, 1),
               ('d', 'c', 'c12', 'review', NULL, 30.5, 2.2, 900000, 3000, 1, 0, 3);
             INSERT INTO status_event (id, session, deck, card, direction, at, action, until, \
               cause, after_review, batch, undone, origin) VALUES
               (1, 1, 'd', 'a', 'backward', 1000, 'bury', 86400000, 1, 1, 1, 0, NULL),
               (2, 1, 'd', 'c', 'c12', 3100, 'suspend', NULL, NULL, 3, 2, 1, 'machine-b');
             INSERT INTO item_status VALUES ('d', 'a', 'backward', 0, 86400000, 0);
             INSERT INTO prompt_attempt (deck, prompt, attempted_at, prediction, measured, \
               correct, attempt, judged_at) VALUES ('d', 'p', 1000, 'flips', NULL, 1, 1, 1100);",
        )
        .unwrap();
        let dump = |conn: &Connection, table: &str| -> Vec<String> {
            let mut st = conn
                .prepare(&format!("SELECT * FROM {table} ORDER BY 1, 2"))
                .unwrap();
            let n = st.column_count();
            st.query_map([], |r| {
                Ok((0..n)
                    .map(|i| format!("{:?}", r.get_ref(i).unwrap()))
                    .collect::<Vec<_>>()
                    .join(" "))
            })
            .unwrap()
            .collect::<Result<_, _>>()
            .unwrap()
        };
        let tables = ["review", "card_state", "status_event", "item_status"];
        let before: Vec<Vec<String>> = tables.iter().map(|t| dump(&conn, t)).collect();
        let attempts = dump(&conn, "prompt_attempt");
        drop(conn);
        let mut conn = Connection::open(&path).unwrap();
        conn.pragma_update(None, "foreign_keys", true).unwrap();
        migrate(&mut conn, &path, &MIGRATIONS[..6], "20260102T000000Z").unwrap();
        assert_eq!(user_version(&conn).unwrap(), 6);
        for (t, rows) in tables.iter().zip(&before) {
            assert_eq!(&dump(&conn, t), rows, "every row of {t} kept, every column");
        }
        // The attempts gain an empty `variant` column, nothing else.
        let after: Vec<String> = dump(&conn, "prompt_attempt")
            .into_iter()
            .map(|r| r.strip_suffix(" Null").unwrap().to_string())
            .collect();
        assert_eq!(after, attempts);
        let fk: i64 = conn
            .query_row("SELECT count(*) FROM pragma_foreign_key_check", [], |r| {
                r.get(0)
            })
            .unwrap();
        assert_eq!(fk, 0, "every reference still points at its row");
        // Prompts and derivations are review items now.
        for (id, direction) in [(4, "predict"), (5, "derive")] {
            conn.execute(
                &format!(
                    "INSERT INTO review (id, deck, card, direction, reviewed_at, rating, kind, \
                     elapsed_days, scheduled_days, state, due, duration_ms) VALUES \
                     ({id}, 'd', 'p', '{direction}', 5000, 3, 'learn', 0, 0, 'learning', 5600, 10)"
                ),
                [],
            )
            .unwrap();
        }
        let bad = conn
            .execute(
                "INSERT INTO review (deck, card, direction, reviewed_at, rating, kind, \
                 elapsed_days, scheduled_days, state, due, duration_ms) VALUES \
                 ('d', 'p', 'sideways', 5000, 3, 'learn', 0, 0, 'learning', 5600, 10)",
                [],
            )
            .unwrap_err();
        assert!(bad.to_string().contains("CHECK"), "{bad}");
        // The logs are still append-only.
        for (sql, word) in [
            ("DELETE FROM review WHERE id = 1", "append-only"),
            ("UPDATE review SET rating = 4 WHERE id = 1", "append-only"),
            ("DELETE FROM status_event WHERE id = 1", "append-only"),
            (
                "UPDATE status_event SET action = 'leech' WHERE id = 1",
                "append-only",
            ),
        ] {
            let e = conn.execute(sql, []).unwrap_err();
            assert!(e.to_string().contains(word), "{sql}: {e}");
        }
        conn.execute("UPDATE review SET undone = 1 WHERE id = 1", [])
            .unwrap();
        // A varied attempt keeps its seed, as its prediction: once, in range.
        conn.execute(
            "INSERT INTO prompt_attempt (deck, prompt, attempted_at, prediction, attempt, variant) \
             VALUES ('d', 'v', 6000, '2.1', 1, 9007199254740991)",
            [],
        )
        .unwrap();
        let e = conn
            .execute(
                "UPDATE prompt_attempt SET correct = 1, judged_at = 6100, variant = 3 \
                 WHERE prompt = 'v'",
                [],
            )
            .unwrap_err();
        assert!(e.to_string().contains("append-only"), "{e}");
        let e = conn
            .execute(
                "INSERT INTO prompt_attempt (deck, prompt, attempted_at, prediction, attempt, \
                 variant) VALUES ('d', 'v', 7000, '2.1', 2, 9007199254740992)",
                [],
            )
            .unwrap_err();
        assert!(e.to_string().contains("CHECK"), "{e}");
    }

    #[test]
    fn newer_schema_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("flipcard.db");
        let mut conn = Connection::open(&path).unwrap();
        conn.pragma_update(None, "user_version", 99).unwrap();
        let err = migrate(&mut conn, &path, MIGRATIONS, "x").unwrap_err();
        assert!(matches!(err, StoreError::TooNew { found: 99, .. }), "{err}");
    }

    #[test]
    fn foreign_database_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("flipcard.db");
        let mut conn = Connection::open(&path).unwrap();
        conn.execute_batch("CREATE TABLE notes (t TEXT);").unwrap();
        let err = migrate(&mut conn, &path, MIGRATIONS, "x").unwrap_err();
        assert!(matches!(err, StoreError::Foreign { .. }), "{err}");
        assert_eq!(tables(&conn), ["notes"]);
    }

    #[test]
    fn log_rows_cannot_be_deleted_or_rewritten() {
        let mut conn = Connection::open_in_memory().unwrap();
        conn.pragma_update(None, "recursive_triggers", true)
            .unwrap();
        migrate(&mut conn, Path::new(":memory:"), MIGRATIONS, "x").unwrap();
        conn.execute(
            "INSERT INTO review (id, deck, card, direction, reviewed_at, rating, kind,
             elapsed_days, scheduled_days, state, due, duration_ms)
             VALUES (1, 'd', 'c', 'forward', 0, 3, 'learn', 0, 0, 'learning', 60000, 900)",
            [],
        )
        .unwrap();
        let del = conn.execute("DELETE FROM review", []).unwrap_err();
        assert!(del.to_string().contains("append-only"), "{del}");
        let upd = conn
            .execute("UPDATE review SET rating = 4 WHERE id = 1", [])
            .unwrap_err();
        assert!(upd.to_string().contains("append-only"), "{upd}");
        let replace = conn
            .execute(
                "INSERT OR REPLACE INTO review (id, deck, card, direction, reviewed_at, rating,
                 kind, elapsed_days, scheduled_days, state, due, duration_ms)
                 VALUES (1, 'd', 'c', 'forward', 0, 1, 'learn', 0, 0, 'learning', 0, 0)",
                [],
            )
            .unwrap_err();
        assert!(replace.to_string().contains("append-only"), "{replace}");
        conn.execute("UPDATE review SET undone = 1 WHERE id = 1", [])
            .unwrap();
        let back = conn
            .execute("UPDATE review SET undone = 0 WHERE id = 1", [])
            .unwrap_err();
        assert!(back.to_string().contains("append-only"), "{back}");
        let rating: i64 = conn
            .query_row("SELECT rating FROM review WHERE id = 1", [], |r| r.get(0))
            .unwrap();
        assert_eq!(rating, 3);
    }

    #[test]
    fn version_6_takes_derive_items_and_keeps_every_row_and_trigger() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("flipcard.db");
        let mut conn = Connection::open(&path).unwrap();
        conn.pragma_update(None, "foreign_keys", true).unwrap();
        migrate(&mut conn, &path, &MIGRATIONS[..5], "20260101T000000Z").unwrap();
        conn.execute_batch(
            "INSERT INTO session (id, started_at) VALUES (1, 10);
             INSERT INTO review (session, deck, card, direction, reviewed_at, rating, kind,
               elapsed_days, scheduled_days, stability, difficulty, state, step, due,
               last_review, duration_ms, undone, origin) VALUES
               (1, 'd', 'a', 'forward', 1000, 3, 'learn', 0, 0, 2.0, 5.0, 'learning', 0, 2000,
                1000, 10, 0, NULL),
               (1, 'd', 'b', 'c2', 1100, 1, 'learn', 0, 0, 0.5, 7.0, 'learning', 0, 2100,
                1100, 20, 1, 'machine-b');
             INSERT INTO card_state VALUES ('d', 'a', 'forward', 'learning', 0, 2.0, 5.0, 2000,
               1000, 1, 0, 1);
             INSERT INTO status_event (session, deck, card, direction, at, action, until, cause,
               after_review, batch, undone, origin) VALUES
               (1, 'd', 'a', 'backward', 1000, 'bury', 5000, 1, 1, 1, 0, NULL);",
        )
        .unwrap();
        let dump = |conn: &Connection, table: &str| -> Vec<String> {
            let mut st = conn
                .prepare(&format!("SELECT * FROM {table} ORDER BY 1, 2"))
                .unwrap();
            let n = st.column_count();
            st.query_map([], |r| {
                Ok((0..n)
                    .map(|i| format!("{:?}", r.get_ref(i).unwrap()))
                    .collect::<Vec<_>>()
                    .join(" "))
            })
            .unwrap()
            .collect::<Result<_, _>>()
            .unwrap()
        };
        let tables = ["review", "card_state", "status_event"];
        let before: Vec<Vec<String>> = tables.iter().map(|t| dump(&conn, t)).collect();
        let derive = "INSERT INTO review (deck, card, direction, reviewed_at, rating, kind, \
             elapsed_days, scheduled_days, state, due, duration_ms) VALUES \
             ('d', 'euler', 'derive', 3000, 3, 'learn', 0, 0, 'learning', 4000, 5)";
        assert!(conn.execute(derive, []).is_err(), "version 5 has no derive");
        drop(conn);
        let mut conn = Connection::open(&path).unwrap();
        conn.pragma_update(None, "foreign_keys", true).unwrap();
        migrate(&mut conn, &path, &MIGRATIONS[..6], "20260102T000000Z").unwrap();
        assert_eq!(user_version(&conn).unwrap(), 6);
        let after: Vec<Vec<String>> = tables.iter().map(|t| dump(&conn, t)).collect();
        assert_eq!(after, before, "every row and column kept");
        conn.execute(derive, []).unwrap();
        conn.execute(
            "INSERT INTO status_event (deck, card, direction, at, action, batch) \
             VALUES ('d', 'euler', 'derive', 3100, 'suspend', 2)",
            [],
        )
        .unwrap();
        for bad in [
            derive.replace("'derive'", "'derived'"),
            derive.replace("'derive'", "'c0'"),
        ] {
            assert!(conn.execute(&bad, []).is_err(), "{bad}");
        }
        // The logs stay append-only.
        for (sql, says) in [
            ("DELETE FROM review WHERE card = 'euler'", "append-only"),
            (
                "UPDATE review SET direction = 'forward' WHERE card = 'euler'",
                "append-only",
            ),
            ("DELETE FROM status_event", "append-only"),
            ("UPDATE review SET undone = 1 WHERE card = 'euler'", ""),
        ] {
            match conn.execute(sql, []) {
                Ok(_) => assert!(says.is_empty(), "{sql} was allowed"),
                Err(e) => assert!(
                    !says.is_empty() && e.to_string().contains(says),
                    "{sql}: {e}"
                ),
            }
        }
        for index in [
            "review_item",
            "review_cram",
            "status_event_at",
            "card_state_due",
        ] {
            let n: i64 = conn
                .query_row(
                    "SELECT count(*) FROM sqlite_schema WHERE type = 'index' AND name = ?1",
                    [index],
                    |r| r.get(0),
                )
                .unwrap();
            assert_eq!(n, 1, "{index}");
        }
        let fk: i64 = conn
            .query_row("SELECT count(*) FROM pragma_foreign_key_check", [], |r| {
                r.get(0)
            })
            .unwrap();
        assert_eq!(fk, 0);
    }
}
