//! Typed answers: compare what the learner typed with a card's accepted
//! answers and suggest a rating, which the learner may change.
//!
//! Both sides are normalised before comparing: Unicode compatibility form
//! (NFKC, so `é` typed as e + accent, full-width letters and `²`/`2` compare
//! equal), lower case, no whitespace at all, and no sentence punctuation or
//! quotes around the answer. Signs, brackets and units inside stay, because
//! in physics they change the meaning (`-1` is not `1`).

use unicode_normalization::UnicodeNormalization;

use super::types::Rating;

/// How a typed answer compares with the accepted ones.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// Equal to an accepted answer after normalisation.
    Exact,
    /// A typo away from an accepted answer (see [`check`]).
    Close,
    Wrong,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TypedCheck {
    pub verdict: Verdict,
    /// Good for exact, Hard for close, Again for wrong.
    pub suggested: Rating,
    /// The accepted answer nearest to what was typed (as the author wrote
    /// it), to show next to the learner's answer.
    pub nearest: Option<String>,
    /// Edit distance between the normalised answer and `nearest`.
    pub distance: usize,
}

/// Compares `typed` with every accepted answer.
///
/// Close means a small edit distance (in characters, after normalisation):
/// none allowed for answers of up to 3 characters, 1 up to 7, then 2, and
/// one per 5 characters beyond 10. Answers whose digits differ are never close: `5.77` against
/// `5.78` is a wrong number, not a typo.
pub fn check(typed: &str, accepted: &[String]) -> TypedCheck {
    let mine = normalize(typed);
    let mut best: Option<(usize, &String, String)> = None;
    for answer in accepted {
        let theirs = normalize(answer);
        let d = strsim::levenshtein(&mine, &theirs);
        if best.as_ref().is_none_or(|(bd, _, _)| d < *bd) {
            best = Some((d, answer, theirs));
        }
    }
    let Some((distance, nearest, theirs)) = best else {
        return TypedCheck {
            verdict: Verdict::Wrong,
            suggested: Rating::Again,
            nearest: None,
            distance: 0,
        };
    };
    let verdict = if mine.is_empty() {
        Verdict::Wrong
    } else if distance == 0 {
        Verdict::Exact
    } else if distance <= allowed_typos(theirs.chars().count()) && digits(&mine) == digits(&theirs)
    {
        Verdict::Close
    } else {
        Verdict::Wrong
    };
    TypedCheck {
        verdict,
        suggested: match verdict {
            Verdict::Exact => Rating::Good,
            Verdict::Close => Rating::Hard,
            Verdict::Wrong => Rating::Again,
        },
        nearest: Some(nearest.clone()),
        distance,
    }
}

/// The comparable form of an answer (see the module docs).
pub fn normalize(text: &str) -> String {
    let folded: String = text
        .nfkc()
        .flat_map(char::to_lowercase)
        .filter(|c| !c.is_whitespace())
        .collect();
    folded
        .trim_start_matches(|c| is_quote(c) || matches!(c, '¿' | '¡'))
        .trim_end_matches(|c| is_quote(c) || matches!(c, '.' | ',' | ';' | ':' | '!' | '?' | '…'))
        .to_string()
}

fn is_quote(c: char) -> bool {
    matches!(c, '"' | '\'' | '`' | '‘' | '’' | '“' | '”' | '«' | '»')
}

/// Typos forgiven in an answer of `len` characters: none in a short one
/// (where one letter is often another word), one up to 7, then at least
/// two, and one per 5 characters in a long one.
fn allowed_typos(len: usize) -> usize {
    match len {
        0..=3 => 0,
        4..=7 => 1,
        n => (n / 5).max(2),
    }
}

fn digits(s: &str) -> Vec<char> {
    s.chars().filter(char::is_ascii_digit).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn accepted(list: &[&str]) -> Vec<String> {
        list.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn case_space_and_punctuation_do_not_matter() {
        let acc = accepted(&["Intermediate axis"]);
        for typed in [
            "intermediate axis",
            "INTERMEDIATE AXIS",
            "  Intermediate   axis.  ",
            "intermediateaxis",
            "\"intermediate axis\"",
            "Intermediate\taxis!",
        ] {
            let c = check(typed, &acc);
            assert_eq!(c.verdict, Verdict::Exact, "{typed:?}");
            assert_eq!(c.suggested, Rating::Good);
            assert_eq!(c.nearest.as_deref(), Some("Intermediate axis"));
        }
    }

    #[test]
    fn unicode_forms_compare_equal() {
        // Precomposed é against e + combining acute; full-width letters;
        // a superscript two against a plain one; Greek capital against small.
        assert_eq!(
            check("re\u{301}sume\u{301}", &accepted(&["résumé"])).verdict,
            Verdict::Exact
        );
        assert_eq!(
            check("ＬＯＲＥＮＴＺ", &accepted(&["lorentz"])).verdict,
            Verdict::Exact
        );
        assert_eq!(check("m/s2", &accepted(&["m/s²"])).verdict, Verdict::Exact);
        assert_eq!(check("Ω", &accepted(&["ω"])).verdict, Verdict::Exact);
    }

    #[test]
    fn signs_and_inner_punctuation_count() {
        assert_eq!(check("1", &accepted(&["-1"])).verdict, Verdict::Wrong);
        assert_eq!(check("-1", &accepted(&["-1"])).verdict, Verdict::Exact);
        assert_eq!(
            check("I1 < I2", &accepted(&["I2 < I1"])).verdict,
            Verdict::Wrong
        );
    }

    #[test]
    fn a_typo_is_close_and_suggests_hard() {
        let acc = accepted(&["precession", "nutation"]);
        let c = check("precesion", &acc);
        assert_eq!(c.verdict, Verdict::Close);
        assert_eq!(c.suggested, Rating::Hard);
        assert_eq!(c.nearest.as_deref(), Some("precession"));
        assert_eq!(c.distance, 1);
        // Three edits in a long answer are still close: 29 characters allow 5.
        assert_eq!(
            check(
                "conservation of angluar momentm",
                &accepted(&["conservation of angular momentum"])
            )
            .verdict,
            Verdict::Close
        );
    }

    #[test]
    fn one_or_two_slips_in_a_long_answer_suggest_hard_not_again() {
        // Swapped letters are two edits: close in an 8-letter word.
        for (typed, answer) in [
            ("mometnum", "momentum"),
            ("intermedaite", "intermediate"),
            ("polhdoe", "polhode"),
        ] {
            let c = check(typed, &accepted(&[answer]));
            if answer.len() >= 8 {
                assert_eq!(c.suggested, Rating::Hard, "{typed} for {answer}");
            } else {
                // Seven letters forgive one slip, not two.
                assert_eq!(c.suggested, Rating::Again, "{typed} for {answer}");
                assert_eq!(
                    check("polhod", &accepted(&[answer])).suggested,
                    Rating::Hard
                );
            }
        }
        // Three slips in an 8-letter word are not a typo.
        assert_eq!(
            check("mmoetnum", &accepted(&["momentum"])).suggested,
            Rating::Again
        );
    }

    #[test]
    fn far_off_or_short_or_numeric_misses_are_wrong() {
        assert_eq!(
            check("nutation", &accepted(&["precession"])).suggested,
            Rating::Again
        );
        // Short answers allow no typo.
        assert_eq!(check("I3", &accepted(&["I2"])).verdict, Verdict::Wrong);
        // A wrong digit is a wrong number.
        assert_eq!(
            check("5.78 s", &accepted(&["5.77 s"])).verdict,
            Verdict::Wrong
        );
        assert_eq!(check("", &accepted(&["x"])).verdict, Verdict::Wrong);
        assert_eq!(check("   ", &accepted(&["x"])).suggested, Rating::Again);
    }

    #[test]
    fn nearest_is_the_closest_accepted_answer() {
        let acc = accepted(&["major axis", "largest axis", "axis of largest moment"]);
        let c = check("larget axis", &acc);
        assert_eq!(c.nearest.as_deref(), Some("largest axis"));
        assert_eq!(c.verdict, Verdict::Close);
        let none = check("anything", &[]);
        assert_eq!((none.verdict, none.nearest), (Verdict::Wrong, None));
    }
}
