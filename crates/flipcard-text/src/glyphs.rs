//! Character tables: Unicode sub- and superscripts, combining accents, and
//! the few letterlike forms a terminal font reliably has.

/// The subscript form of `c`, if Unicode has one.
///
/// `y` maps to the Greek subscript gamma `ᵧ`: Unicode has no subscript y and
/// the two look alike in terminal fonts.
pub(super) fn subscript(c: char) -> Option<char> {
    Some(match c {
        '0'..='9' => char::from_u32(0x2080 + (c as u32 - '0' as u32))?,
        '+' => '₊',
        '-' | '−' => '₋',
        '=' => '₌',
        '(' => '₍',
        ')' => '₎',
        'a' => 'ₐ',
        'e' => 'ₑ',
        'h' => 'ₕ',
        'i' => 'ᵢ',
        'j' => 'ⱼ',
        'k' => 'ₖ',
        'l' => 'ₗ',
        'm' => 'ₘ',
        'n' => 'ₙ',
        'o' => 'ₒ',
        'p' => 'ₚ',
        'r' => 'ᵣ',
        's' => 'ₛ',
        't' => 'ₜ',
        'u' => 'ᵤ',
        'v' => 'ᵥ',
        'x' => 'ₓ',
        'y' | 'γ' => 'ᵧ',
        'β' => 'ᵦ',
        'ρ' => 'ᵨ',
        'φ' | 'ϕ' => 'ᵩ',
        'χ' => 'ᵪ',
        _ => return None,
    })
}

/// The superscript form of `c`, if Unicode has one. Primes are already
/// raised and stay as they are; `∘` becomes the degree sign.
pub(super) fn superscript(c: char) -> Option<char> {
    Some(match c {
        '0' => '⁰',
        '1' => '¹',
        '2' => '²',
        '3' => '³',
        '4'..='9' => char::from_u32(0x2074 + (c as u32 - '4' as u32))?,
        '+' => '⁺',
        '-' | '−' => '⁻',
        '=' => '⁼',
        '(' => '⁽',
        ')' => '⁾',
        '′' | '″' | '‴' | '°' => c,
        '∘' => '°',
        'a' => 'ᵃ',
        'b' => 'ᵇ',
        'c' => 'ᶜ',
        'd' => 'ᵈ',
        'e' => 'ᵉ',
        'f' => 'ᶠ',
        'g' => 'ᵍ',
        'h' => 'ʰ',
        'i' => 'ⁱ',
        'j' => 'ʲ',
        'k' => 'ᵏ',
        'l' => 'ˡ',
        'm' => 'ᵐ',
        'n' => 'ⁿ',
        'o' => 'ᵒ',
        'p' => 'ᵖ',
        'r' => 'ʳ',
        's' => 'ˢ',
        't' => 'ᵗ',
        'u' => 'ᵘ',
        'v' => 'ᵛ',
        'w' => 'ʷ',
        'x' => 'ˣ',
        'y' => 'ʸ',
        'z' => 'ᶻ',
        'A' => 'ᴬ',
        'B' => 'ᴮ',
        'D' => 'ᴰ',
        'E' => 'ᴱ',
        'G' => 'ᴳ',
        'H' => 'ᴴ',
        'I' => 'ᴵ',
        'J' => 'ᴶ',
        'K' => 'ᴷ',
        'L' => 'ᴸ',
        'M' => 'ᴹ',
        'N' => 'ᴺ',
        'O' => 'ᴼ',
        'P' => 'ᴾ',
        'R' => 'ᴿ',
        'T' => 'ᵀ',
        'U' => 'ᵁ',
        'V' => 'ⱽ',
        'W' => 'ᵂ',
        'α' => 'ᵅ',
        'β' => 'ᵝ',
        'γ' => 'ᵞ',
        'δ' => 'ᵟ',
        'ε' | 'ϵ' => 'ᵋ',
        'θ' => 'ᶿ',
        'ι' => 'ᶥ',
        'φ' | 'ϕ' => 'ᵠ',
        'χ' => 'ᵡ',
        _ => return None,
    })
}

/// Whether `c` is a combining mark (it draws on the character before it).
pub(super) fn is_combining(c: char) -> bool {
    matches!(c,
        '\u{0300}'..='\u{036F}'
        | '\u{1AB0}'..='\u{1AFF}'
        | '\u{1DC0}'..='\u{1DFF}'
        | '\u{20D0}'..='\u{20FF}'
        | '\u{FE20}'..='\u{FE2F}')
}

/// Whether `s` is exactly one visible character, possibly carrying
/// combining marks.
pub(super) fn is_single_glyph(s: &str) -> bool {
    let mut chars = s.chars();
    match chars.next() {
        Some(first) if !is_combining(first) => chars.all(is_combining),
        _ => false,
    }
}

/// An accent placed over (or under) its base.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Accent {
    Dot,
    Ddot,
    Vec,
    Hat,
    Bar,
    Tilde,
    Check,
    Acute,
    Grave,
    Breve,
    Ring,
    Underline,
}

impl Accent {
    /// The accent for the mark character the parser puts in an over- or
    /// underscript (`\dot x` arrives as `x` with `˙` above it).
    pub(super) fn from_mark(mark: char, above: bool) -> Option<Accent> {
        if !above {
            return (mark == '_').then_some(Accent::Underline);
        }
        Some(match mark {
            '˙' => Accent::Dot,
            '¨' => Accent::Ddot,
            '→' => Accent::Vec,
            '^' | 'ˆ' => Accent::Hat,
            '‾' | '¯' => Accent::Bar,
            '~' | '˜' => Accent::Tilde,
            'ˇ' => Accent::Check,
            '´' => Accent::Acute,
            '`' => Accent::Grave,
            '˘' => Accent::Breve,
            '˚' => Accent::Ring,
            _ => return None,
        })
    }

    /// The combining mark drawn on a single character.
    pub(super) fn combining(self) -> char {
        match self {
            Accent::Dot => '\u{0307}',
            Accent::Ddot => '\u{0308}',
            Accent::Vec => '\u{20D7}',
            Accent::Hat => '\u{0302}',
            Accent::Bar => '\u{0304}',
            Accent::Tilde => '\u{0303}',
            Accent::Check => '\u{030C}',
            Accent::Acute => '\u{0301}',
            Accent::Grave => '\u{0300}',
            Accent::Breve => '\u{0306}',
            Accent::Ring => '\u{030A}',
            Accent::Underline => '\u{0332}',
        }
    }

    /// For a base of several characters: a mark that joins up when put on
    /// every character (a continuous over- or underline), if there is one.
    pub(super) fn spanning(self) -> Option<char> {
        match self {
            Accent::Bar => Some('\u{0305}'),
            Accent::Underline => Some('\u{0332}'),
            _ => None,
        }
    }

    /// For a base of several characters without a spanning mark: the mark
    /// written after the parenthesised base, as in `(x + y)˙`.
    pub(super) fn after_group(self) -> char {
        match self {
            Accent::Dot => '˙',
            Accent::Ddot => '¨',
            Accent::Hat => 'ˆ',
            Accent::Tilde => '˜',
            Accent::Check => 'ˇ',
            Accent::Acute => '´',
            Accent::Grave => '`',
            Accent::Breve => '˘',
            Accent::Ring => '˚',
            // No spacing arrow accent exists; the combining arrow sits on
            // the closing parenthesis.
            Accent::Vec | Accent::Bar | Accent::Underline => self.combining(),
        }
    }
}

/// The precomposed negation of a relation (`\not=` is `≠`), if there is one.
pub(super) fn negated(c: char) -> Option<char> {
    Some(match c {
        '=' => '≠',
        '<' => '≮',
        '>' => '≯',
        '≤' => '≰',
        '≥' => '≱',
        '≡' => '≢',
        '∈' => '∉',
        '∋' => '∌',
        '⊂' => '⊄',
        '⊃' => '⊅',
        '⊆' => '⊈',
        '⊇' => '⊉',
        '∼' => '≁',
        '≈' => '≉',
        '≃' => '≄',
        '≅' => '≇',
        '∣' => '∤',
        '∥' => '∦',
        '→' => '↛',
        '←' => '↚',
        '⇒' => '⇏',
        '⇔' => '⇎',
        '↔' => '↮',
        '∃' => '∄',
        _ => return None,
    })
}

/// `\mathbb` and `\mathcal` letters that live in the Letterlike Symbols
/// block (well covered by terminal fonts); other letters stay plain.
pub(super) fn double_struck(c: char) -> char {
    match c {
        'C' => 'ℂ',
        'H' => 'ℍ',
        'N' => 'ℕ',
        'P' => 'ℙ',
        'Q' => 'ℚ',
        'R' => 'ℝ',
        'Z' => 'ℤ',
        _ => c,
    }
}

pub(super) fn calligraphic(c: char) -> char {
    match c {
        'B' => 'ℬ',
        'E' => 'ℰ',
        'F' => 'ℱ',
        'H' => 'ℋ',
        'I' => 'ℐ',
        'L' => 'ℒ',
        'M' => 'ℳ',
        'R' => 'ℛ',
        _ => c,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn digits_have_both_script_forms() {
        let sub: String = ('0'..='9').filter_map(subscript).collect();
        let sup: String = ('0'..='9').filter_map(superscript).collect();
        assert_eq!(sub, "₀₁₂₃₄₅₆₇₈₉");
        assert_eq!(sup, "⁰¹²³⁴⁵⁶⁷⁸⁹");
    }

    #[test]
    fn letters_without_subscript_form_are_missing() {
        for c in ['b', 'c', 'd', 'f', 'g', 'q', 'w', 'z', 'A', '⟂'] {
            assert_eq!(subscript(c), None, "{c}");
        }
        assert_eq!(superscript('q'), None);
        assert_eq!(superscript('C'), None);
    }

    #[test]
    fn single_glyph_counts_combining_marks_as_part_of_it() {
        assert!(is_single_glyph("ω"));
        assert!(is_single_glyph("ω\u{20D7}\u{0307}"));
        assert!(!is_single_glyph("ω₁"));
        assert!(!is_single_glyph(""));
        assert!(!is_single_glyph("\u{0307}"));
    }
}
