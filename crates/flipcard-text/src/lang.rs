//! Texts written in several languages.

use std::collections::BTreeMap;

/// A BCP 47 language tag as declared by the deck (`en`, `hi-Latn`).
pub type Lang = String;

/// A text given in every declared language of its deck.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Text(pub LangMap);

impl Text {
    /// The text in `lang`, falling back to any language present (a validated
    /// deck has every language, so the fallback only matters for a language
    /// the deck does not declare).
    pub fn get(&self, lang: &str) -> &str {
        self.0
            .get(lang)
            .or_else(|| self.0.values().next())
            .map(String::as_str)
            .unwrap_or("")
    }
}

/// A text's strings by language, in language order, as a map with the
/// parts of `BTreeMap`'s interface the texts use.
///
/// Kept as a short sorted list: a text has one or two languages, and a
/// deck of 50,000 cards holds 100,000 texts, where a `BTreeMap` would give
/// each a node of half a kilobyte. Lookups are binary searches; building
/// from an iterator sorts once (a later entry for a language replaces an
/// earlier one, as in a `BTreeMap`), so no input makes it quadratic.
#[derive(Debug, Clone, PartialEq, Eq, Default, PartialOrd, Ord, Hash)]
pub struct LangMap(Vec<(Lang, String)>);

impl LangMap {
    /// An empty map.
    pub const fn new() -> LangMap {
        LangMap(Vec::new())
    }

    fn find(&self, lang: &str) -> Result<usize, usize> {
        self.0.binary_search_by(|(l, _)| l.as_str().cmp(lang))
    }

    pub fn get(&self, lang: &str) -> Option<&String> {
        self.find(lang).ok().map(|i| &self.0[i].1)
    }

    pub fn contains_key(&self, lang: &str) -> bool {
        self.find(lang).is_ok()
    }

    /// Sets the string of `lang`, returning the one it replaces.
    pub fn insert(&mut self, lang: Lang, text: String) -> Option<String> {
        match self.find(&lang) {
            Ok(i) => Some(std::mem::replace(&mut self.0[i].1, text)),
            Err(i) => {
                self.0.insert(i, (lang, text));
                None
            }
        }
    }

    pub fn len(&self) -> usize {
        self.0.len()
    }

    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// The languages and their strings, in language order.
    pub fn iter(&self) -> Iter<'_> {
        Iter(self.0.iter())
    }

    pub fn iter_mut(&mut self) -> impl DoubleEndedIterator<Item = (&Lang, &mut String)> {
        self.0.iter_mut().map(|(l, t)| (&*l, t))
    }

    pub fn values_mut(&mut self) -> impl DoubleEndedIterator<Item = &mut String> {
        self.0.iter_mut().map(|(_, t)| t)
    }

    pub fn keys(&self) -> impl DoubleEndedIterator<Item = &Lang> + ExactSizeIterator + Clone {
        self.0.iter().map(|(l, _)| l)
    }

    pub fn values(&self) -> impl DoubleEndedIterator<Item = &String> + ExactSizeIterator + Clone {
        self.0.iter().map(|(_, t)| t)
    }
}

/// The entries of a [`LangMap`], by reference.
#[derive(Clone)]
pub struct Iter<'a>(std::slice::Iter<'a, (Lang, String)>);

impl<'a> Iterator for Iter<'a> {
    type Item = (&'a Lang, &'a String);
    fn next(&mut self) -> Option<Self::Item> {
        self.0.next().map(|(l, t)| (l, t))
    }
    fn size_hint(&self) -> (usize, Option<usize>) {
        self.0.size_hint()
    }
}

impl DoubleEndedIterator for Iter<'_> {
    fn next_back(&mut self) -> Option<Self::Item> {
        self.0.next_back().map(|(l, t)| (l, t))
    }
}

impl ExactSizeIterator for Iter<'_> {}

impl<'a> IntoIterator for &'a LangMap {
    type Item = (&'a Lang, &'a String);
    type IntoIter = Iter<'a>;
    fn into_iter(self) -> Iter<'a> {
        self.iter()
    }
}

impl IntoIterator for LangMap {
    type Item = (Lang, String);
    type IntoIter = std::vec::IntoIter<(Lang, String)>;
    fn into_iter(self) -> Self::IntoIter {
        self.0.into_iter()
    }
}

impl FromIterator<(Lang, String)> for LangMap {
    fn from_iter<I: IntoIterator<Item = (Lang, String)>>(iter: I) -> LangMap {
        LangMap::from_vec(iter.into_iter().collect())
    }
}

impl LangMap {
    /// The map of `entries`, where of equal languages the later entry
    /// stays (as inserting them into a `BTreeMap` one by one would). No
    /// new list is made: entries already in order (as every map written by
    /// flipcard is) are taken as they are.
    fn from_vec(mut v: Vec<(Lang, String)>) -> LangMap {
        if v.windows(2).all(|w| w[0].0 < w[1].0) {
            return LangMap(v);
        }
        // Stable: equal languages stay in the order given.
        v.sort_by(|a, b| a.0.cmp(&b.0));
        // Backwards, the later of equal languages comes first and is kept.
        v.reverse();
        v.dedup_by(|later, kept| later.0 == kept.0);
        v.reverse();
        LangMap(v)
    }
}

impl<const N: usize> From<[(Lang, String); N]> for LangMap {
    fn from(entries: [(Lang, String); N]) -> LangMap {
        entries.into_iter().collect()
    }
}

impl From<BTreeMap<Lang, String>> for LangMap {
    fn from(map: BTreeMap<Lang, String>) -> LangMap {
        LangMap(map.into_iter().collect())
    }
}

impl From<LangMap> for BTreeMap<Lang, String> {
    fn from(map: LangMap) -> BTreeMap<Lang, String> {
        map.0.into_iter().collect()
    }
}

impl serde::Serialize for LangMap {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_map(self.iter())
    }
}

impl<'de> serde::Deserialize<'de> for LangMap {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<LangMap, D::Error> {
        struct Visit;
        impl<'de> serde::de::Visitor<'de> for Visit {
            type Value = LangMap;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a map of language to text")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                mut a: A,
            ) -> Result<LangMap, A::Error> {
                // Bounded by what the input holds, never by its claim.
                let mut v = Vec::with_capacity(a.size_hint().unwrap_or(0).min(8));
                while let Some(entry) = a.next_entry::<Lang, String>()? {
                    v.push(entry);
                }
                Ok(LangMap::from_vec(v))
            }
        }
        d.deserialize_map(Visit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// Whatever is put in, in whatever order, the map holds what a
        /// `BTreeMap` given the same entries holds, in the same order.
        #[test]
        fn a_lang_map_is_a_btree_map(
            entries in proptest::collection::vec(("[a-c]{1,2}", "[x-z]{0,2}"), 0..12),
        ) {
            let mut tree = BTreeMap::new();
            let mut inserted = LangMap::new();
            for (l, t) in &entries {
                prop_assert_eq!(tree.insert(l.clone(), t.clone()), inserted.insert(l.clone(), t.clone()));
            }
            let collected: LangMap = entries.iter().cloned().collect();
            prop_assert_eq!(&collected, &inserted);
            let listed: Vec<_> = tree.iter().collect();
            prop_assert_eq!(inserted.iter().collect::<Vec<_>>(), listed);
            prop_assert_eq!(inserted.len(), tree.len());
            for l in ["a", "b", "c", "aa", "zz"] {
                prop_assert_eq!(inserted.get(l), tree.get(l));
            }
            prop_assert_eq!(BTreeMap::from(inserted), tree);
        }
    }
}
