//! The one shape of every id a deck names (decks, cards, prompts, scenes,
//! sections): `[a-z0-9]` words joined by single `-`. Reading, validating,
//! importing and the review log all check it, so it sits below them all.

/// `[a-z0-9]` words joined by single `-`.
pub fn is_id(s: &str) -> bool {
    !s.is_empty()
        && s.split('-').all(|part| {
            !part.is_empty()
                && part
                    .bytes()
                    .all(|b| b.is_ascii_lowercase() || b.is_ascii_digit())
        })
}
