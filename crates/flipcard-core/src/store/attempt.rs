//! Predict-then-check attempts: what the learner predicted, what the
//! simulation measured, and whether the prediction held.
//!
//! An attempt is kept when the learner commits to it ([`Store::commit_attempt`]),
//! before the run plays, and on disk before the screen moves on: a learner
//! who leaves the run and answers again has both answers kept, the first as
//! the first attempt, the second as a retry. The verdict is written once,
//! when the run ends ([`Store::judge_attempt`]); the schema's trigger
//! refuses every other change (schema version 4). Since version 5 the
//! verdict names the misconception a wrong answer stands for, when the
//! deck names one.

use chrono::{DateTime, Utc};
use rusqlite::params;

use super::codec::to_ms;
use super::db::Store;
use super::error::StoreError;

/// A judged attempt, written whole ([`Store::record_attempt`]): an attempt
/// whose commitment and verdict arrive together (tests, tools).
#[derive(Debug, Clone, PartialEq)]
pub struct PromptAttempt {
    pub deck: String,
    pub prompt: String,
    pub attempted_at: DateTime<Utc>,
    /// The learner's answer as given (a choice id, or the number typed).
    pub prediction: String,
    /// The measured value the verdict compared against, if a number.
    pub measured: Option<f64>,
    pub correct: bool,
}

/// What the learner commits to, before the run.
#[derive(Debug, Clone, PartialEq)]
pub struct Commitment {
    pub deck: String,
    pub prompt: String,
    pub committed_at: DateTime<Utc>,
    /// A choice id, or the number typed.
    pub prediction: String,
    /// The seed of a varied prompt's numbers (`predict::variant`), at
    /// most 2⁵³ − 1; `None` for a prompt asked the same way every time.
    pub variant: Option<u64>,
}

/// A commitment as stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Committed {
    /// Its row, for [`Store::judge_attempt`].
    pub id: i64,
    /// 1 for the first attempt at the prompt; 2, 3 … for retries.
    pub attempt: u32,
}

impl Committed {
    pub fn is_retry(&self) -> bool {
        self.attempt > 1
    }
}

/// What the run said of an attempt.
#[derive(Debug, Clone, PartialEq)]
pub struct AttemptVerdict {
    /// The measured value the verdict compared against, if a number.
    pub measured: Option<f64>,
    pub correct: bool,
    pub judged_at: DateTime<Utc>,
    /// The id of the deck's misconception a wrong answer stands for
    /// (`predict::Verdict::misconception`); never on a right answer.
    pub misconception: Option<String>,
}

/// An attempt as stored, verdict or not.
#[derive(Debug, Clone, PartialEq)]
pub struct StoredAttempt {
    pub id: i64,
    pub deck: String,
    pub prompt: String,
    /// When the learner committed (for attempts stored before version 4:
    /// when the run ended).
    pub attempted_at: DateTime<Utc>,
    pub prediction: String,
    /// 1 for the first attempt at the prompt; 2, 3 … for retries.
    pub attempt: u32,
    /// The seed of a varied prompt's numbers.
    pub variant: Option<u64>,
    /// `None`: the learner left before the run's end.
    pub verdict: Option<AttemptVerdict>,
}

impl StoredAttempt {
    pub fn is_retry(&self) -> bool {
        self.attempt > 1
    }
}

fn refuse_empty(deck: &str, prompt: &str) -> Result<(), StoreError> {
    if deck.is_empty() || prompt.is_empty() {
        return Err(StoreError::BadRow {
            id: 0,
            detail: "refusing to record a prompt attempt without deck or prompt id".into(),
        });
    }
    Ok(())
}

/// A right answer names no misconception.
pub(crate) fn refuse_misconception(id: i64, verdict: &AttemptVerdict) -> Result<(), StoreError> {
    if verdict.correct && verdict.misconception.is_some() {
        return Err(StoreError::BadRow {
            id,
            detail: "a right answer stands for no misconception".into(),
        });
    }
    Ok(())
}

/// Writes the verdict of attempt `id` inside a write; the number of rows
/// changed (0: no such attempt; the trigger refuses a second verdict).
pub(crate) fn judge_in(
    w: &rusqlite::Connection,
    id: i64,
    verdict: &AttemptVerdict,
) -> rusqlite::Result<usize> {
    // NaN or infinite measurements are kept as unknown: SQLite cannot
    // store NaN, and an infinite value is no measurement.
    let measured = verdict.measured.filter(|m| m.is_finite());
    let mut st = w.prepare_cached(
        "UPDATE prompt_attempt SET measured = ?2, correct = ?3, judged_at = ?4, \
         misconception = ?5 WHERE id = ?1",
    )?;
    st.execute(params![
        id,
        measured,
        verdict.correct,
        to_ms(verdict.judged_at),
        verdict.misconception,
    ])
}

/// The largest variant seed the schema keeps (2⁵³ − 1, as the CHECK of
/// version 6; the generator's `MAX_SEED`).
pub const MAX_VARIANT: u64 = (1 << 53) - 1;

/// The next attempt's number at the prompt `?2`/`?3` of an INSERT: one
/// statement, so two apps committing at once cannot both take the same.
const NEXT_ATTEMPT: &str =
    "(SELECT coalesce(max(attempt), 0) + 1 FROM prompt_attempt WHERE deck = ?2 AND prompt = ?3)";

impl Store {
    /// Keeps a commitment, numbered after every earlier attempt at its
    /// prompt; committed (on disk) before this returns.
    pub fn commit_attempt(&mut self, c: &Commitment) -> Result<Committed, StoreError> {
        refuse_empty(&c.deck, &c.prompt)?;
        let sql = format!(
            "INSERT INTO prompt_attempt (session, deck, prompt, attempted_at, prediction, \
             attempt, variant) VALUES (?1, ?2, ?3, ?4, ?5, {NEXT_ATTEMPT}, ?6) RETURNING id, attempt"
        );
        let variant = match c.variant {
            None => None,
            Some(v) if v <= MAX_VARIANT => Some(v as i64),
            Some(_) => {
                return Err(StoreError::BadRow {
                    id: 0,
                    detail: "a variant seed is at most 2^53 - 1".into(),
                });
            }
        };
        self.write(|w| {
            let session = w.session()?;
            let mut st = w.prepare_cached(&sql)?;
            Ok(st.query_row(
                params![
                    session,
                    c.deck,
                    c.prompt,
                    to_ms(c.committed_at),
                    c.prediction,
                    variant
                ],
                |r| {
                    Ok(Committed {
                        id: r.get(0)?,
                        attempt: r.get(1)?,
                    })
                },
            )?)
        })
    }

    /// Writes the verdict of attempt `id`, once: an attempt already judged,
    /// or one that does not exist, is an error and nothing changes.
    pub fn judge_attempt(&mut self, id: i64, verdict: &AttemptVerdict) -> Result<(), StoreError> {
        refuse_misconception(id, verdict)?;
        let n = self.write(|w| Ok(judge_in(w, id, verdict)?))?;
        if n == 0 {
            return Err(StoreError::BadRow {
                id,
                detail: "no such prompt attempt to judge".into(),
            });
        }
        Ok(())
    }

    /// Appends one judged attempt (commitment and verdict at once),
    /// committed before this returns. Returns its id.
    pub fn record_attempt(&mut self, attempt: &PromptAttempt) -> Result<i64, StoreError> {
        refuse_empty(&attempt.deck, &attempt.prompt)?;
        let measured = attempt.measured.filter(|m| m.is_finite());
        let sql = format!(
            "INSERT INTO prompt_attempt (session, deck, prompt, attempted_at, prediction, \
             measured, correct, judged_at, attempt) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?4, \
             {NEXT_ATTEMPT}) RETURNING id"
        );
        self.write(|w| {
            let session = w.session()?;
            let mut st = w.prepare_cached(&sql)?;
            Ok(st.query_row(
                params![
                    session,
                    attempt.deck,
                    attempt.prompt,
                    to_ms(attempt.attempted_at),
                    attempt.prediction,
                    measured,
                    attempt.correct,
                ],
                |r| r.get(0),
            )?)
        })
    }

    /// Whether the latest judged attempt at each prompt of `deck` was
    /// right, by prompt id; prompts never judged are absent.
    pub fn last_attempts(
        &self,
        deck: &str,
    ) -> Result<std::collections::HashMap<String, bool>, StoreError> {
        // The latest by time, the later-logged on a tie.
        let mut st = self
            .conn
            .prepare_cached(
                "SELECT prompt, correct FROM prompt_attempt AS a WHERE deck = ?1 AND id = \
                 (SELECT b.id FROM prompt_attempt AS b WHERE b.deck = a.deck AND \
                 b.prompt = a.prompt AND b.correct IS NOT NULL \
                 ORDER BY b.attempted_at DESC, b.id DESC LIMIT 1)",
            )
            .map_err(|e| self.err(e))?;
        st.query_map([deck], |r| {
            Ok((r.get::<_, String>(0)?, r.get::<_, bool>(1)?))
        })
        .and_then(|rows| rows.collect())
        .map_err(|e| self.err(e))
    }
}

impl Store {
    /// How many attempts the prompt has had, and the variant seed of the
    /// latest (for a new attempt to draw other numbers).
    pub fn attempts_at(&self, deck: &str, prompt: &str) -> Result<(u32, Option<u64>), StoreError> {
        self.conn
            .query_row(
                "SELECT count(*), (SELECT variant FROM prompt_attempt WHERE deck = ?1 \
                 AND prompt = ?2 ORDER BY id DESC LIMIT 1) \
                 FROM prompt_attempt WHERE deck = ?1 AND prompt = ?2",
                [deck, prompt],
                |r| {
                    Ok((
                        u32::try_from(r.get::<_, i64>(0)?).unwrap_or(u32::MAX),
                        r.get::<_, Option<i64>>(1)?
                            .and_then(|v| u64::try_from(v).ok()),
                    ))
                },
            )
            .map_err(|e| self.err(e))
    }

    /// Every prompt attempt in id order, handed to `each` one at a time;
    /// stops at the first error `each` returns.
    pub fn each_attempt<E>(
        &self,
        mut each: impl FnMut(StoredAttempt) -> Result<(), E>,
    ) -> Result<(), E>
    where
        E: From<StoreError>,
    {
        let mut st = self
            .conn
            .prepare(
                "SELECT id, deck, prompt, attempted_at, prediction, attempt, measured, \
                 correct, judged_at, misconception, variant FROM prompt_attempt ORDER BY id",
            )
            .map_err(|e| self.err(e))?;
        let mut rows = st.query([]).map_err(|e| self.err(e))?;
        while let Some(row) = rows.next().map_err(|e| self.err(e))? {
            let attempt = (|| -> rusqlite::Result<StoredAttempt> {
                let correct: Option<bool> = row.get(7)?;
                let judged: Option<super::codec::Ms> = row.get(8)?;
                let attempted_at = row.get::<_, super::codec::Ms>(3)?.0;
                Ok(StoredAttempt {
                    id: row.get(0)?,
                    deck: row.get(1)?,
                    prompt: row.get(2)?,
                    attempted_at,
                    prediction: row.get(4)?,
                    attempt: row.get(5)?,
                    variant: row
                        .get::<_, Option<i64>>(10)?
                        .and_then(|v| u64::try_from(v).ok()),
                    verdict: match correct {
                        Some(correct) => Some(AttemptVerdict {
                            measured: row.get(6)?,
                            correct,
                            // A row written whole by another program.
                            judged_at: judged.map_or(attempted_at, |t| t.0),
                            misconception: row.get(9)?,
                        }),
                        None => None,
                    },
                })
            })()
            .map_err(|e| self.err(e))?;
            each(attempt)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(s: &str) -> DateTime<Utc> {
        DateTime::parse_from_rfc3339(s).unwrap().with_timezone(&Utc)
    }

    fn commitment(prompt: &str, prediction: &str, t: &str) -> Commitment {
        Commitment {
            deck: "d".into(),
            variant: None,
            prompt: prompt.into(),
            committed_at: at(t),
            prediction: prediction.into(),
        }
    }

    fn all(store: &Store) -> Vec<StoredAttempt> {
        let mut out = Vec::new();
        store
            .each_attempt(|a| {
                out.push(a);
                Ok::<_, StoreError>(())
            })
            .unwrap();
        out
    }

    #[test]
    fn commitments_are_numbered_per_prompt_and_judged_once() {
        let dir = tempfile::tempdir().unwrap();
        let mut store = Store::open(dir.path()).unwrap();
        let a = store
            .commit_attempt(&commitment("p", "1.5", "2026-01-01T10:00:00Z"))
            .unwrap();
        let b = store
            .commit_attempt(&commitment("q", "x", "2026-01-01T10:01:00Z"))
            .unwrap();
        let c = store
            .commit_attempt(&commitment("p", "2", "2026-01-01T10:02:00Z"))
            .unwrap();
        assert_eq!((a.attempt, b.attempt, c.attempt), (1, 1, 2));
        assert!(c.is_retry() && !a.is_retry());
        let verdict = AttemptVerdict {
            measured: Some(2.0),
            correct: true,
            judged_at: at("2026-01-01T10:02:09Z"),
            misconception: None,
        };
        store.judge_attempt(c.id, &verdict).unwrap();
        let again = store.judge_attempt(
            c.id,
            &AttemptVerdict {
                correct: false,
                ..verdict.clone()
            },
        );
        assert!(
            again.is_err_and(|e| e
                .to_string()
                .contains("only the verdict may be written, once")),
            "a verdict is written once"
        );
        assert!(
            store.judge_attempt(999, &verdict).is_err(),
            "no such attempt"
        );
        let rows = all(&store);
        assert_eq!(rows.len(), 3);
        assert_eq!(rows[0].verdict, None, "left before the end: no verdict");
        assert_eq!(rows[2].verdict, Some(verdict));
        // A judged attempt written whole is numbered after the others.
        store
            .record_attempt(&PromptAttempt {
                deck: "d".into(),
                prompt: "p".into(),
                attempted_at: at("2026-01-02T10:00:00Z"),
                prediction: "2".into(),
                measured: None,
                correct: true,
            })
            .unwrap();
        assert_eq!(all(&store)[3].attempt, 3);
        // What was judged is what the prompt list and the stats read.
        assert_eq!(store.last_attempts("d").unwrap().get("p"), Some(&true));
        assert_eq!(store.last_attempts("d").unwrap().get("q"), None);
    }

    #[test]
    fn a_row_cannot_be_rewritten_or_deleted() {
        let dir = tempfile::tempdir().unwrap();
        let mut store = Store::open(dir.path()).unwrap();
        let a = store
            .commit_attempt(&commitment("p", "1.5", "2026-01-01T10:00:00Z"))
            .unwrap();
        for sql in [
            "UPDATE prompt_attempt SET prediction = '2', correct = 1",
            "UPDATE prompt_attempt SET attempt = 2",
            "UPDATE prompt_attempt SET attempted_at = 0",
            // A measurement without a verdict.
            "UPDATE prompt_attempt SET measured = 1.0",
            "DELETE FROM prompt_attempt",
        ] {
            let e = store.conn.execute(sql, []).unwrap_err();
            assert!(e.to_string().contains("append-only"), "{sql}: {e}");
        }
        // The verdict, once.
        store
            .conn
            .execute("UPDATE prompt_attempt SET correct = 0", [])
            .unwrap();
        let e = store
            .conn
            .execute("UPDATE prompt_attempt SET correct = 1", [])
            .unwrap_err();
        assert!(e.to_string().contains("once"), "{e}");
        assert_eq!(all(&store)[0].id, a.id);
        assert_eq!(all(&store)[0].prediction, "1.5");
    }
}
