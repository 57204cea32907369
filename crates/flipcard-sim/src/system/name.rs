//! A short name (of a variable or observable) held inline, so that a
//! measure naming one stays `Copy` like every other measure.

use std::fmt;

/// Longest name held, in bytes.
pub(crate) const CAPACITY: usize = 31;

#[derive(Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Name {
    len: u8,
    bytes: [u8; CAPACITY],
}

impl Name {
    /// `None` when `s` is longer than [`CAPACITY`] bytes.
    pub fn new(s: &str) -> Option<Name> {
        if s.len() > CAPACITY {
            return None;
        }
        let mut bytes = [0; CAPACITY];
        bytes[..s.len()].copy_from_slice(s.as_bytes());
        Some(Name {
            len: s.len() as u8,
            bytes,
        })
    }

    pub fn as_str(&self) -> &str {
        // Built from a &str and never changed, so always UTF-8.
        std::str::from_utf8(&self.bytes[..self.len as usize]).unwrap_or("")
    }
}

impl fmt::Debug for Name {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:?}", self.as_str())
    }
}

impl fmt::Display for Name {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn holds_short_names_only() {
        assert_eq!(Name::new("theta").unwrap().as_str(), "theta");
        assert_eq!(Name::new(&"x".repeat(31)).unwrap().as_str().len(), 31);
        assert!(Name::new(&"x".repeat(32)).is_none());
        assert!(Name::new("a").unwrap() < Name::new("b").unwrap());
    }
}
