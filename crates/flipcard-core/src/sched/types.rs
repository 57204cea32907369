//! The vocabulary shared by the scheduler and the store.

use chrono::{DateTime, Utc};

/// The learner's answer to a card.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Rating {
    Again = 1,
    Hard = 2,
    Good = 3,
    Easy = 4,
}

impl Rating {
    pub const ALL: [Rating; 4] = [Rating::Again, Rating::Hard, Rating::Good, Rating::Easy];
    pub fn from_number(n: i64) -> Option<Rating> {
        Rating::ALL.into_iter().find(|r| *r as i64 == n)
    }
}

/// Where a card is in its life. `New` means never reviewed (no log row).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum State {
    New = 0,
    Learning = 1,
    Review = 2,
    Relearning = 3,
}

/// Which way a card is asked. Basic and typed cards have only `Forward`;
/// reversed cards are two review items with separate state; each deletion
/// number of a cloze card is its own item (`c1`, `c2`, …).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Direction {
    /// front → back
    Forward,
    /// back → front
    Backward,
    /// The text with deletion number `n` hidden.
    Cloze(u16),
    /// A predict-then-check prompt, scheduled as a review item: the
    /// item's `card` is the prompt's id (issue 24 §2).
    Predict,
    /// A derivation worked step by step (`[[derivation]]`; the item's
    /// `card` is the derivation's id).
    Derive,
}

impl Direction {
    pub fn as_str(self) -> std::borrow::Cow<'static, str> {
        match self {
            Direction::Forward => "forward".into(),
            Direction::Backward => "backward".into(),
            Direction::Cloze(n) => format!("c{n}").into(),
            Direction::Predict => "predict".into(),
            Direction::Derive => "derive".into(),
        }
    }
    pub fn parse(s: &str) -> Option<Direction> {
        match s {
            "forward" => Some(Direction::Forward),
            "backward" => Some(Direction::Backward),
            "predict" => Some(Direction::Predict),
            "derive" => Some(Direction::Derive),
            _ => {
                let digits = s.strip_prefix('c')?;
                // One spelling per number: `c01` would be a second key for `c1`.
                if digits.starts_with('0') || !digits.bytes().all(|b| b.is_ascii_digit()) {
                    return None;
                }
                digits
                    .parse()
                    .ok()
                    .filter(|n| (1..=crate::deck::cloze::MAX_NUMBER).contains(n))
                    .map(Direction::Cloze)
            }
        }
    }
}

/// One review item: history is keyed by deck id + card id (+ direction).
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ItemKey {
    pub deck: String,
    pub card: String,
    pub direction: Direction,
}

impl ItemKey {
    /// An item named by a file flipcard did not write (a sync line, a
    /// learner's export, an imported log): deck and card ids of the deck
    /// format's pattern (`[a-z0-9]` words joined by `-`),
    /// a direction `forward`, `backward`, `c1` … `c999` or `derive`. The error quotes
    /// the value on one line, control characters escaped.
    pub fn parse(deck: &str, card: &str, direction: &str) -> Result<ItemKey, KeyError> {
        for (what, id) in [("deck", deck), ("card", card)] {
            if !crate::deck::validate::is_id(id) {
                return Err(KeyError::NotAnId {
                    what,
                    quoted: flipcard_text::safe::one_line(&shorten(id)).into_owned(),
                });
            }
        }
        let direction = Direction::parse(direction).ok_or_else(|| KeyError::NotADirection {
            quoted: flipcard_text::safe::one_line(&shorten(direction)).into_owned(),
        })?;
        Ok(ItemKey {
            deck: deck.into(),
            card: card.into(),
            direction,
        })
    }
}

/// Items' states by key: what a queue, a plan or a count reads. Hashed
/// with foldhash rather than SipHash: a deck of 50,000 cards with a history
/// hashes 50,000 keys to show home's counts.
pub type States = std::collections::HashMap<ItemKey, CardState, foldhash::fast::RandomState>;

/// An item named by borrowed ids: what a deck's items are while only
/// counted or looked up, so a deck of 50,000 cards does not copy 100,000
/// ids to show home's counts. A map keyed by [`ItemKey`] is searched with
/// it as `map.get(item as &dyn AsItem)` (see [`AsItem`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ItemRef<'a> {
    pub deck: &'a str,
    pub card: &'a str,
    pub direction: Direction,
}

impl ItemRef<'_> {
    /// The owned key of this item.
    pub fn to_key(&self) -> ItemKey {
        ItemKey {
            deck: self.deck.to_string(),
            card: self.card.to_string(),
            direction: self.direction,
        }
    }
}

impl ItemKey {
    /// This key's ids, borrowed.
    pub fn as_ref(&self) -> ItemRef<'_> {
        ItemRef {
            deck: &self.deck,
            card: &self.card,
            direction: self.direction,
        }
    }
}

/// An item's ids, however they are held: the form a map keyed by
/// [`ItemKey`] is searched by without building a key. `ItemKey` borrows as
/// `dyn AsItem`, whose hash and equality are the key's own (fields hashed
/// in the same order, a `&str` as its `String`), so both find the same
/// entry: proptest `an_item_ref_finds_what_its_key_finds`.
pub trait AsItem {
    fn item(&self) -> ItemRef<'_>;
}

impl AsItem for ItemKey {
    fn item(&self) -> ItemRef<'_> {
        self.as_ref()
    }
}

impl AsItem for ItemRef<'_> {
    fn item(&self) -> ItemRef<'_> {
        *self
    }
}

impl<'a> std::borrow::Borrow<dyn AsItem + 'a> for ItemKey {
    fn borrow(&self) -> &(dyn AsItem + 'a) {
        self
    }
}

impl std::hash::Hash for dyn AsItem + '_ {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.item().hash(state)
    }
}

impl PartialEq for dyn AsItem + '_ {
    fn eq(&self, other: &Self) -> bool {
        self.item() == other.item()
    }
}

impl Eq for dyn AsItem + '_ {}

/// Why [`ItemKey::parse`] refused an item: the value is quoted on one line,
/// shortened, control characters escaped.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum KeyError {
    /// `what` is `deck` or `card`.
    #[error(
        "{what} id \"{quoted}\" is not an id (lowercase letters and digits in words joined by -)"
    )]
    NotAnId { what: &'static str, quoted: String },
    #[error("direction \"{quoted}\" is not forward, backward, c1 … c999, predict or derive")]
    NotADirection { quoted: String },
}

/// At most 40 characters of a value quoted in a message.
fn shorten(s: &str) -> String {
    match s.char_indices().nth(40) {
        Some((i, _)) => format!("{}…", &s[..i]),
        None => s.to_string(),
    }
}

/// What kind of answer a review-log row records.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ReviewKind {
    Learn,
    Review,
    Relearn,
    /// Exam cramming: logged, but does not change the scheduling state.
    Cram,
}

impl ReviewKind {
    pub fn as_str(self) -> &'static str {
        match self {
            ReviewKind::Learn => "learn",
            ReviewKind::Review => "review",
            ReviewKind::Relearn => "relearn",
            ReviewKind::Cram => "cram",
        }
    }
}

/// The scheduling state of one review item, as py-fsrs's `Card` holds it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CardState {
    pub state: State,
    /// Index into the learning or relearning steps (None in Review / New).
    pub step: Option<u32>,
    pub stability: Option<f64>,
    pub difficulty: Option<f64>,
    pub due: DateTime<Utc>,
    pub last_review: Option<DateTime<Utc>>,
}

/// One row of the append-only review log, as the scheduler produces it and
/// the store writes it. The state after the review is stored in full, so the
/// card states can be rebuilt from the log alone.
#[derive(Debug, Clone, PartialEq)]
pub struct ReviewRecord {
    pub key: ItemKey,
    pub reviewed_at: DateTime<Utc>,
    pub rating: Rating,
    pub kind: ReviewKind,
    /// Days since the previous review of this item (0 for the first).
    pub elapsed_days: i64,
    /// Days from this review to the next due date.
    pub scheduled_days: i64,
    /// The item's state after this review (for `Cram`, the unchanged state).
    pub after: CardState,
    /// How long the learner took to answer.
    pub duration_ms: i64,
    /// The interval in whole days the load balancer chose for this answer
    /// (`None`: the day was drawn uniformly, or not fuzzed). Kept with the
    /// answer so that a replay, which cannot know the due counts of that
    /// moment, places the item on the same day (see
    /// [`super::Scheduler::replay`]).
    pub balanced_days: Option<i64>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn item_keys_from_other_files_are_ids_of_the_deck_format() {
        let k = ItemKey::parse("euler", "card-2", "c999").unwrap();
        assert_eq!(k.direction, Direction::Cloze(999));
        let k = ItemKey::parse("euler", "euler-equations", "derive").unwrap();
        assert_eq!(k.direction, Direction::Derive);
        assert_eq!(k.direction.as_str(), "derive");
        for (deck, card, dir, why) in [
            ("../x", "c", "forward", "deck id"),
            ("d", "a/b", "forward", "card id"),
            ("d", "", "forward", "card id"),
            ("D", "c", "forward", "deck id"),
            ("d", "c\u{1b}[2J", "forward", "\\u001b"),
            ("d", "c", "c1000", "c999"),
            ("d", "c", "c0", "c999"),
            ("d", "c", "sideways", "c999"),
            ("d", "c", "Derive", "derive"),
            ("d", "c", "derived", "derive"),
        ] {
            let err = ItemKey::parse(deck, card, dir).unwrap_err().to_string();
            assert!(err.contains(why), "{deck} {card} {dir}: {err}");
            assert!(!err.contains('\u{1b}'), "{err}");
        }
    }

    fn direction() -> impl proptest::strategy::Strategy<Value = Direction> {
        use proptest::prelude::*;
        prop_oneof![
            Just(Direction::Forward),
            Just(Direction::Backward),
            Just(Direction::Predict),
            Just(Direction::Derive),
            (1u16..=999).prop_map(Direction::Cloze),
        ]
    }

    proptest::proptest! {
        /// A map keyed by owned keys finds through a borrowed item exactly
        /// the entries it finds through the key (ids that differ only in
        /// where one ends and the next begins included).
        #[test]
        fn an_item_ref_finds_what_its_key_finds(
            keys in proptest::collection::vec(("[a-c]{0,3}", "[a-c]{0,3}", direction()), 0..20),
            probes in proptest::collection::vec(("[a-c]{0,3}", "[a-c]{0,3}", direction()), 0..20),
        ) {
            let key = |(deck, card, direction): &(String, String, Direction)| ItemKey {
                deck: deck.clone(),
                card: card.clone(),
                direction: *direction,
            };
            let map: std::collections::HashMap<ItemKey, usize> =
                keys.iter().enumerate().map(|(i, k)| (key(k), i)).collect();
            for p in keys.iter().chain(&probes) {
                let owned = key(p);
                let r = ItemRef { deck: &p.0, card: &p.1, direction: p.2 };
                proptest::prop_assert_eq!(map.get(&r as &dyn AsItem), map.get(&owned));
                proptest::prop_assert_eq!(r.to_key(), owned.clone());
                proptest::prop_assert_eq!(owned.as_ref(), r);
            }
        }
    }
}
