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
