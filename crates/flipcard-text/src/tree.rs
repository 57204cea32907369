//! The parser's flat event stream folded into a small tree: a fraction needs
//! to see its whole numerator before it knows whether to parenthesise it.

use std::iter::Peekable;

use pulldown_latex::event::{
    Content, Dimension, DimensionUnit, EnvironmentFlow, Event, Font, Grouping, ScriptPosition,
    ScriptType, StateChange, Visual,
};
use pulldown_latex::{Parser, ParserError};

use super::glyphs::{self, Accent};

/// Nesting beyond this is reported as an error rather than risking the stack.
const MAX_DEPTH: usize = 100;

/// Widest run of spaces an explicit space command turns into.
const MAX_SPACE: u8 = 8;

/// How an atom spaces itself against its neighbours (TeX's atom classes,
/// plus fractions and roots, which read badly when glued to a factor).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Class {
    Ord,
    /// Large operator: `∑`, `∫`.
    Op,
    Bin,
    Rel,
    Open,
    Close,
    Punct,
    /// Named function: `sin`, `diag` from `\operatorname`.
    Function,
    Frac,
    Radical,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Leaf<'a> {
    Char(char),
    Pair(char, char),
    Str(&'a str),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum EnvKind {
    /// Matrices and arrays: cells `a, b`, rows `a; b`.
    Matrix,
    /// `cases` (brace on the left) or `rcases` (on the right).
    Cases { left: bool },
    /// `align`, `gather` and friends: one equation per line.
    Lines,
}

#[derive(Debug, Clone, PartialEq)]
pub(super) enum Node<'a> {
    Leaf(Leaf<'a>, Class),
    /// Explicit space, in terminal columns.
    Space(u8),
    /// A state change standing where an element was expected.
    Empty,
    Group(Vec<Node<'a>>),
    Fenced(Option<char>, Vec<Node<'a>>, Option<char>),
    /// Rows of cells of nodes.
    Env(EnvKind, Vec<Vec<Vec<Node<'a>>>>),
    Script(Box<Scripted<'a>>),
    Accent(Box<Node<'a>>, Accent),
    /// Numerator, denominator.
    Frac(Box<[Node<'a>; 2]>),
    Sqrt(Box<Node<'a>>),
    /// Radicand, index.
    Root(Box<[Node<'a>; 2]>),
    Negated(Box<Node<'a>>),
}

/// A base with its sub- and superscript (one allocation for all three).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Scripted<'a> {
    pub base: Node<'a>,
    pub sub: Option<Node<'a>>,
    pub sup: Option<Node<'a>>,
}

/// Why the events could not be folded into a tree.
#[derive(Debug)]
pub(super) enum BuildError {
    Parser(ParserError),
    /// A problem the parser does not report (too deep, stream cut short).
    Shape(&'static str),
}

impl From<ParserError> for BuildError {
    fn from(e: ParserError) -> Self {
        BuildError::Parser(e)
    }
}

/// Fold the whole formula into a list of nodes.
pub(super) fn build<'a>(parser: Parser<'a>) -> Result<Vec<Node<'a>>, BuildError> {
    let mut builder = Builder {
        events: parser.peekable(),
        depth: 0,
    };
    builder.list(Font::UpRight, Until::Eof)
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Until {
    Eof,
    End,
}

struct Builder<'a> {
    events: Peekable<Parser<'a>>,
    depth: usize,
}

impl<'a> Builder<'a> {
    fn next(&mut self) -> Result<Option<Event<'a>>, BuildError> {
        self.events.next().transpose().map_err(BuildError::from)
    }

    /// Elements up to the matching `End` (or the end of input at the top).
    fn list(&mut self, mut font: Font, until: Until) -> Result<Vec<Node<'a>>, BuildError> {
        let mut nodes = Vec::new();
        loop {
            match self.events.peek() {
                None if until == Until::Eof => return Ok(nodes),
                None => return Err(BuildError::Shape("a group is not closed")),
                Some(Ok(Event::End)) => {
                    self.events.next();
                    if until == Until::End {
                        return Ok(nodes);
                    }
                    return Err(BuildError::Shape("a group is closed that was never opened"));
                }
                Some(Ok(Event::StateChange(change))) => {
                    if let StateChange::Font(f) = change {
                        font = f.unwrap_or(Font::UpRight);
                    }
                    self.events.next();
                }
                _ => nodes.push(self.element(font)?),
            }
        }
    }

    /// One element: a content atom, a group, or a construct with its
    /// arguments.
    fn element(&mut self, font: Font) -> Result<Node<'a>, BuildError> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(BuildError::Shape("the formula is nested too deeply"));
        }
        let node = self.element_inner(font);
        self.depth -= 1;
        node
    }

    fn element_inner(&mut self, font: Font) -> Result<Node<'a>, BuildError> {
        let Some(event) = self.next()? else {
            return Err(BuildError::Shape("an argument is missing"));
        };
        Ok(match event {
            Event::Content(content) => content_node(content, font),
            Event::Begin(grouping) => self.group(grouping, font)?,
            Event::End => return Err(BuildError::Shape("an argument is missing")),
            Event::Visual(visual) => match visual {
                Visual::SquareRoot => Node::Sqrt(Box::new(self.element(font)?)),
                Visual::Root => {
                    let radicand = self.element(font)?;
                    let index = self.element(font)?;
                    Node::Root(Box::new([radicand, index]))
                }
                Visual::Fraction(_) => {
                    let num = self.element(font)?;
                    let den = self.element(font)?;
                    Node::Frac(Box::new([num, den]))
                }
                Visual::Negation => Node::Negated(Box::new(self.element(font)?)),
            },
            Event::Script { ty, position } => self.script(ty, position, font)?,
            Event::Space { width, .. } => Node::Space(columns(width)),
            Event::StateChange(_) => Node::Empty,
            Event::EnvironmentFlow(_) => {
                return Err(BuildError::Shape("`&` or `\\\\` outside an environment"));
            }
        })
    }

    fn group(&mut self, grouping: Grouping, font: Font) -> Result<Node<'a>, BuildError> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(BuildError::Shape("the formula is nested too deeply"));
        }
        let node = match grouping {
            Grouping::Normal => self.list(font, Until::End).map(Node::Group),
            Grouping::LeftRight(open, close) => self
                .list(font, Until::End)
                .map(|body| Node::Fenced(open, body, close)),
            Grouping::Cases { left } => self.env(EnvKind::Cases { left }, font),
            Grouping::Array(_) | Grouping::Matrix { .. } | Grouping::SubArray { .. } => {
                self.env(EnvKind::Matrix, font)
            }
            _ => self.env(EnvKind::Lines, font),
        };
        self.depth -= 1;
        node
    }

    fn env(&mut self, kind: EnvKind, font: Font) -> Result<Node<'a>, BuildError> {
        let mut rows = Vec::new();
        let mut row = Vec::new();
        let mut cell = Vec::new();
        loop {
            match self.events.peek() {
                None => return Err(BuildError::Shape("an environment is not closed")),
                Some(Ok(Event::End)) => {
                    self.events.next();
                    break;
                }
                Some(Ok(Event::EnvironmentFlow(flow))) => {
                    match flow {
                        EnvironmentFlow::Alignment => row.push(std::mem::take(&mut cell)),
                        EnvironmentFlow::NewLine { .. } => {
                            row.push(std::mem::take(&mut cell));
                            rows.push(std::mem::take(&mut row));
                        }
                        EnvironmentFlow::StartLines { .. } => {}
                    }
                    self.events.next();
                }
                Some(Ok(Event::StateChange(_))) => {
                    self.events.next();
                }
                _ => cell.push(self.element(font)?),
            }
        }
        if !cell.is_empty() || !row.is_empty() {
            row.push(cell);
            rows.push(row);
        }
        Ok(Node::Env(kind, rows))
    }

    fn script(
        &mut self,
        ty: ScriptType,
        position: ScriptPosition,
        font: Font,
    ) -> Result<Node<'a>, BuildError> {
        let base = self.element(font)?;
        let (sub, sup) = match ty {
            ScriptType::Subscript => (Some(self.element(font)?), None),
            ScriptType::Superscript => (None, Some(self.element(font)?)),
            ScriptType::SubSuperscript => {
                let sub = self.element(font)?;
                (Some(sub), Some(self.element(font)?))
            }
        };
        if position == ScriptPosition::AboveBelow {
            let mark = match (&sub, &sup) {
                (None, Some(Node::Leaf(Leaf::Char(c), _))) => Accent::from_mark(*c, true),
                (Some(Node::Leaf(Leaf::Char(c), _)), None) => Accent::from_mark(*c, false),
                _ => None,
            };
            if let Some(accent) = mark {
                return Ok(accented(base, accent));
            }
        }
        Ok(Node::Script(Box::new(Scripted { base, sub, sup })))
    }
}

/// `\dot{\omega_1}` reads as `\dot\omega_1`: the accent goes on the letter,
/// not on the letter with its subscript.
fn accented(base: Node<'_>, accent: Accent) -> Node<'_> {
    match base {
        Node::Group(mut nodes) if nodes.len() == 1 => {
            let inner = nodes.pop().unwrap_or(Node::Empty);
            if matches!(inner, Node::Script(_)) {
                accented(inner, accent)
            } else {
                Node::Accent(Box::new(Node::Group(vec![inner])), accent)
            }
        }
        Node::Script(mut scripted) => {
            let base = std::mem::replace(&mut scripted.base, Node::Empty);
            scripted.base = accented(base, accent);
            Node::Script(scripted)
        }
        other => Node::Accent(Box::new(other), accent),
    }
}

fn content_node(content: Content<'_>, font: Font) -> Node<'_> {
    let (leaf, class) = match content {
        // `~` and `\ ` arrive as an HTML entity meant for MathML.
        Content::Text("&nbsp;") => return Node::Space(1),
        Content::Text(text) => (Leaf::Str(text), Class::Ord),
        Content::Number(number) => (Leaf::Str(number), Class::Ord),
        Content::Function(name) => (Leaf::Str(name), Class::Function),
        Content::Ordinary { content, .. } => (Leaf::Char(styled(content, font)), Class::Ord),
        Content::LargeOp { content, .. } => (Leaf::Char(content), Class::Op),
        // A slash between factors is ordinary in TeX, whatever the parser says.
        Content::BinaryOp { content: '/', .. } => (Leaf::Char('/'), Class::Ord),
        Content::BinaryOp { content, .. } => (Leaf::Char(content), Class::Bin),
        Content::Relation { content, .. } => {
            let mut buf = [0u8; 8];
            let bytes = content.encode_utf8_to_buf(&mut buf);
            let mut chars = std::str::from_utf8(bytes).unwrap_or("?").chars();
            let first = chars.next().unwrap_or('?');
            let leaf = match chars.next() {
                Some(second) => Leaf::Pair(first, second),
                None => Leaf::Char(first),
            };
            (leaf, Class::Rel)
        }
        Content::Delimiter { content, ty, .. } => {
            let class = match ty {
                pulldown_latex::event::DelimiterType::Open => Class::Open,
                pulldown_latex::event::DelimiterType::Close => Class::Close,
                pulldown_latex::event::DelimiterType::Fence => Class::Ord,
            };
            (Leaf::Char(content), class)
        }
        Content::Punctuation(c) => (Leaf::Char(c), Class::Punct),
    };
    Node::Leaf(leaf, class)
}

fn styled(c: char, font: Font) -> char {
    match font {
        Font::DoubleStruck => glyphs::double_struck(c),
        Font::Script => glyphs::calligraphic(c),
        _ => c,
    }
}

/// Terminal columns for a TeX space: anything up to about half a quad is
/// one column, a quad two.
fn columns(width: Option<Dimension>) -> u8 {
    let Some(Dimension { value, unit }) = width else {
        return 0;
    };
    let em = value
        * match unit {
            DimensionUnit::Em => 1.0,
            DimensionUnit::Mu => 1.0 / 18.0,
            DimensionUnit::Ex => 0.43,
            DimensionUnit::Pt | DimensionUnit::Bp | DimensionUnit::Dd => 0.1,
            DimensionUnit::Pc | DimensionUnit::Cc => 1.2,
            DimensionUnit::In => 7.2,
            DimensionUnit::Cm => 2.85,
            DimensionUnit::Mm => 0.285,
            DimensionUnit::Sp => 0.1 / 65536.0,
        };
    if em.is_nan() || em <= 0.0 {
        0
    } else if em < 0.75 {
        1
    } else {
        (em * 2.0).round().min(f32::from(MAX_SPACE)) as u8
    }
}
