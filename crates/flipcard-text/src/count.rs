//! Counts in words.

use std::fmt;

/// `1 error`, `2 errors`: a count and its noun, agreeing.
pub fn plural<N>(n: N, one: &str, many: &str) -> String
where
    N: fmt::Display + PartialEq + From<u8>,
{
    let noun = if n == N::from(1) { one } else { many };
    format!("{n} {noun}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_agree_with_their_noun() {
        assert_eq!(plural(0usize, "error", "errors"), "0 errors");
        assert_eq!(plural(1u32, "error", "errors"), "1 error");
        assert_eq!(plural(2u64, "bad row", "bad rows"), "2 bad rows");
    }
}
