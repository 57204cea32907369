//! Predict-then-check attempts: what the learner predicted, what the
//! simulation measured, and whether the prediction held.

use chrono::{DateTime, Utc};
use rusqlite::params;

use super::codec::to_ms;
use super::db::Store;
use super::error::StoreError;

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

impl Store {
    /// Appends one attempt, committed before this returns. Returns its id.
    pub fn record_attempt(&mut self, attempt: &PromptAttempt) -> Result<i64, StoreError> {
        if attempt.deck.is_empty() || attempt.prompt.is_empty() {
            return Err(StoreError::BadRow {
                id: 0,
                detail: "refusing to record a prompt attempt without deck or prompt id".into(),
            });
        }
        // NaN or infinite measurements are kept as unknown: SQLite cannot
        // store NaN, and an infinite value is no measurement.
        let measured = attempt.measured.filter(|m| m.is_finite());
        let session = match self.session {
            Some(s) => s,
            None => self.start_session()?,
        };
        self.conn
            .prepare_cached(
                "INSERT INTO prompt_attempt (session, deck, prompt, attempted_at, prediction, \
                 measured, correct) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7) RETURNING id",
            )
            .and_then(|mut st| {
                st.query_row(
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
                )
            })
            .map_err(|e| self.err(e))
    }

    /// Whether the latest attempt at each prompt of `deck` was right, by
    /// prompt id; prompts never attempted are absent.
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
                 b.prompt = a.prompt ORDER BY b.attempted_at DESC, b.id DESC LIMIT 1)",
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
    /// Every prompt attempt in id order, handed to `each` one at a time;
    /// stops at the first error `each` returns.
    pub fn each_attempt<E>(
        &self,
        mut each: impl FnMut(PromptAttempt) -> Result<(), E>,
    ) -> Result<(), E>
    where
        E: From<StoreError>,
    {
        let mut st = self
            .conn
            .prepare(
                "SELECT deck, prompt, attempted_at, prediction, measured, correct \
                 FROM prompt_attempt ORDER BY id",
            )
            .map_err(|e| self.err(e))?;
        let mut rows = st.query([]).map_err(|e| self.err(e))?;
        while let Some(row) = rows.next().map_err(|e| self.err(e))? {
            let attempt = (|| -> rusqlite::Result<PromptAttempt> {
                Ok(PromptAttempt {
                    deck: row.get(0)?,
                    prompt: row.get(1)?,
                    attempted_at: row.get::<_, super::codec::Ms>(2)?.0,
                    prediction: row.get(3)?,
                    measured: row.get(4)?,
                    correct: row.get(5)?,
                })
            })()
            .map_err(|e| self.err(e))?;
            each(attempt)?;
        }
        Ok(())
    }
}
