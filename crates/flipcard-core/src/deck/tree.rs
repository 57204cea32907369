//! Decks as a tree: a deck's `parent` puts it under another on home, and
//! studying a deck studies every deck below it (Anki's `A::B` deck names).
//!
//! The loader refuses cycles and warns of a parent that is not loaded
//! ([`check_parents`]); [`DeckTree`] is still total over any list of decks:
//! a deck whose parent is missing, or that sits on a cycle, is a root.

use std::collections::HashMap;
use std::ops::Range;
use std::path::PathBuf;

use super::diag::Diagnostic;
use super::model::Deck;
use super::report::FileReport;

/// The decks of a list as a tree, by index into the list.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct DeckTree {
    /// Each deck's parent, when it has one in the list (and no cycle).
    pub parent: Vec<Option<usize>>,
    /// Every deck once, parents before their children, siblings in list
    /// order, with its depth (0 for a root).
    pub order: Vec<(usize, usize)>,
}

impl DeckTree {
    pub fn new(decks: &[Deck]) -> DeckTree {
        let index: HashMap<&str, usize> = decks
            .iter()
            .enumerate()
            .map(|(i, d)| (d.id.as_str(), i))
            .collect();
        let mut parent: Vec<Option<usize>> = decks
            .iter()
            .map(|d| d.parent.as_deref().and_then(|p| index.get(p).copied()))
            .collect();
        // A deck on a cycle is a root: walking up from it never ends.
        for i in 0..decks.len() {
            let mut at = parent[i];
            let mut steps = 0;
            while let Some(up) = at {
                if up == i || steps > decks.len() {
                    parent[i] = None;
                    break;
                }
                at = parent[up];
                steps += 1;
            }
        }
        let mut children: Vec<Vec<usize>> = vec![Vec::new(); decks.len()];
        for (i, p) in parent.iter().enumerate() {
            if let Some(p) = p {
                children[*p].push(i);
            }
        }
        let mut order = Vec::with_capacity(decks.len());
        let mut stack: Vec<(usize, usize)> = (0..decks.len())
            .rev()
            .filter(|&i| parent[i].is_none())
            .map(|i| (i, 0))
            .collect();
        while let Some((i, depth)) = stack.pop() {
            order.push((i, depth));
            stack.extend(children[i].iter().rev().map(|&c| (c, depth + 1)));
        }
        DeckTree { parent, order }
    }

    /// Deck `root` and every deck below it, parents first: each as its
    /// index in the list and the position of its parent in this subtree
    /// (`None` for `root`), the shape `Study::queue_tree` takes.
    pub fn subtree(&self, root: usize) -> Vec<(usize, Option<usize>)> {
        let Some(start) = self.order.iter().position(|(i, _)| *i == root) else {
            return vec![(root, None)];
        };
        let depth = self.order[start].1;
        let mut out: Vec<(usize, Option<usize>)> = vec![(root, None)];
        for &(i, d) in &self.order[start + 1..] {
            if d <= depth {
                break;
            }
            let up = self.parent[i].and_then(|p| out.iter().position(|(j, _)| *j == p));
            out.push((i, up));
        }
        out
    }

    /// Whether deck `i` has decks below it.
    pub fn has_children(&self, i: usize) -> bool {
        self.parent.contains(&Some(i))
    }
}

/// Where a deck file names its parent: the deck's index among the loaded
/// decks, the file and the span of the `parent` value.
#[derive(Debug, Clone)]
pub(crate) struct ParentAt {
    pub deck: usize,
    pub path: PathBuf,
    pub span: Range<usize>,
}

/// Checks every `parent` against the decks loaded: one that is not loaded
/// is a warning (the deck is shown at the top level); decks whose parents
/// go round in a cycle are errors, and are returned to be left out.
pub(crate) fn check_parents(
    decks: &[Deck],
    at: &[ParentAt],
    sources: &std::collections::BTreeMap<PathBuf, String>,
) -> (Vec<Diagnostic>, Vec<usize>) {
    let index: HashMap<&str, usize> = decks
        .iter()
        .enumerate()
        .map(|(i, d)| (d.id.as_str(), i))
        .collect();
    let mut out = Vec::new();
    let mut refused = Vec::new();
    for a in at {
        let Some(deck) = decks.get(a.deck) else {
            continue;
        };
        let Some(parent) = deck.parent.as_deref() else {
            continue;
        };
        let source = sources.get(&a.path).map_or("", String::as_str);
        let mut rep = FileReport::new(&a.path, source);
        if !index.contains_key(parent) {
            let hint =
                super::suggest::did_you_mean(parent, index.keys().copied()).unwrap_or_else(|| {
                    "add the parent deck (`flipcard decks add`), or check the deck with it"
                        .to_string()
                });
            rep.warning(
                a.span.clone(),
                format!("parent deck `{parent}` is not among the decks loaded; `{}` is shown at the top level", deck.id),
                Some(hint),
            );
            out.extend(rep.finish());
            continue;
        }
        // Walk up: back at this deck is a cycle.
        let mut path = vec![deck.id.as_str()];
        let mut here = parent;
        let mut cycle = false;
        for _ in 0..=decks.len() {
            path.push(here);
            if here == deck.id {
                cycle = true;
                break;
            }
            match index.get(here).and_then(|&i| decks[i].parent.as_deref()) {
                Some(up) => here = up,
                None => break,
            }
        }
        if cycle {
            rep.error(
                a.span.clone(),
                format!(
                    "decks {} go round in a cycle of parents",
                    path.iter()
                        .map(|d| format!("`{d}`"))
                        .collect::<Vec<_>>()
                        .join(" → ")
                ),
                Some("a deck's parent must lead up to a deck without one".to_string()),
            );
            out.extend(rep.finish());
            refused.push(a.deck);
        }
    }
    (out, refused)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn deck(id: &str, parent: Option<&str>) -> Deck {
        Deck {
            id: id.into(),
            title: Default::default(),
            description: None,
            languages: vec!["en".into()],
            cards: vec![],
            prompts: vec![],
            scenes: vec![],
            systems: vec![],
            sections: vec![],
            units: vec![],
            misconceptions: vec![],
            explore: vec![],
            derivations: vec![],
            path: format!("{id}.toml").into(),
            parent: parent.map(str::to_string),
        }
    }

    #[test]
    fn order_puts_children_under_their_parent() {
        let decks = vec![
            deck("b-child", Some("a")),
            deck("a", None),
            deck("c", None),
            deck("a-grand", Some("b-child")),
            deck("a-two", Some("a")),
            deck("orphan", Some("missing")),
        ];
        let t = DeckTree::new(&decks);
        let names: Vec<(String, usize)> = t
            .order
            .iter()
            .map(|&(i, d)| (decks[i].id.clone(), d))
            .collect();
        // Roots in list order, each child under its parent.
        assert_eq!(
            names,
            [
                ("a", 0),
                ("b-child", 1),
                ("a-grand", 2),
                ("a-two", 1),
                ("c", 0),
                ("orphan", 0)
            ]
            .map(|(n, d)| (n.to_string(), d))
        );
        let sub: Vec<(String, Option<usize>)> = t
            .subtree(1)
            .into_iter()
            .map(|(i, p)| (decks[i].id.clone(), p))
            .collect();
        assert_eq!(
            sub,
            [
                ("a", None),
                ("b-child", Some(0)),
                ("a-grand", Some(1)),
                ("a-two", Some(0))
            ]
            .map(|(n, p)| (n.to_string(), p))
        );
        assert_eq!(t.subtree(2), vec![(2, None)]);
        assert!(t.has_children(1) && !t.has_children(2));
    }

    #[test]
    fn a_cycle_does_not_hang_the_tree() {
        let decks = vec![
            deck("a", Some("b")),
            deck("b", Some("a")),
            deck("c", Some("a")),
        ];
        let t = DeckTree::new(&decks);
        assert_eq!(t.order.len(), 3);
        // The cycle is cut where it is first met: `a` is a root.
        assert_eq!(t.parent, vec![None, Some(0), Some(0)]);
        assert_eq!(t.subtree(0).len(), 3);
    }
}
