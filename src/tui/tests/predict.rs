//! Predict, then check: commit first, then the run, then the verdict.

use crate::tui::screens::predict::{ParseError, parse_number};

#[test]
fn numbers_parse_with_or_without_the_unit() {
    assert_eq!(parse_number("5.77", "1/s"), Ok(5.77));
    assert_eq!(parse_number(" 5.77 1/s ", "1/s"), Ok(5.77));
    assert_eq!(parse_number("5,77 1 / S", "1/s"), Ok(5.77));
    assert_eq!(parse_number("−3e-2", "rad/s"), Ok(-0.03));
    assert_eq!(parse_number("305 d", "d"), Ok(305.0));
    assert_eq!(parse_number("305 days", "d"), Err(ParseError::WrongUnit));
    assert_eq!(parse_number("fast", "1/s"), Err(ParseError::NotANumber));
    assert_eq!(parse_number("", "1/s"), Err(ParseError::NotANumber));
    assert_eq!(parse_number("1e999", "1/s"), Err(ParseError::NotANumber));
}
