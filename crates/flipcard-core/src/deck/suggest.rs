//! Did-you-mean suggestions for misspelt names.

/// The candidate closest to `name`, if it is close enough to be a likely
/// typo: at most a third of the name's length in edits (at least one), or
/// else the shortest candidate the name (3 characters or more) begins.
pub(crate) fn closest<'c>(
    name: &str,
    candidates: impl IntoIterator<Item = &'c str>,
) -> Option<&'c str> {
    let candidates: Vec<&'c str> = candidates.into_iter().collect();
    let name_lower = name.to_lowercase();
    let limit = (name.chars().count() / 3).max(1);
    let by_edits = candidates
        .iter()
        .map(|&c| {
            (
                strsim::damerau_levenshtein(&name_lower, &c.to_lowercase()),
                c,
            )
        })
        .filter(|&(d, _)| d <= limit)
        .min_by_key(|&(d, _)| d)
        .map(|(_, c)| c);
    by_edits.or_else(|| {
        candidates
            .iter()
            .copied()
            .filter(|c| name.chars().count() >= 3 && c.to_lowercase().starts_with(&name_lower))
            .min_by_key(|c| c.len())
    })
}

/// `did you mean `x`?` for the closest candidate.
pub(crate) fn did_you_mean<'c>(
    name: &str,
    candidates: impl IntoIterator<Item = &'c str>,
) -> Option<String> {
    closest(name, candidates).map(|c| format!("did you mean `{c}`?"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggests_close_names_only() {
        let known = ["id", "front", "back", "explain", "tags"];
        assert_eq!(closest("fornt", known), Some("front"));
        assert_eq!(closest("Back", known), Some("back"));
        assert_eq!(closest("explian", known), Some("explain"));
        assert_eq!(closest("colour", known), None);
        assert_eq!(closest("expl", known), Some("explain"));
        assert_eq!(closest("ex", known), None);
        assert_eq!(
            closest("efold", ["efold_time", "flips"]),
            Some("efold_time")
        );
        assert_eq!(
            did_you_mean("tag", known).as_deref(),
            Some("did you mean `tags`?")
        );
    }
}
