//! The tree written out as one line of Unicode: TeX's spacing reduced to
//! whole columns, fractions as `a/b` with the parentheses the linear form
//! needs, scripts as Unicode sub- and superscripts where they exist.

use super::glyphs::{self, Accent};
use super::tree::{Class, EnvKind, Leaf, Node, Scripted};

/// Write the formula's nodes to `out`.
pub(super) fn render(nodes: &[Node<'_>], out: &mut String) {
    list(nodes, out, Mode::Text);
}

/// Scripts are set tight: TeX drops the spaces around operators and
/// relations there too.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Mode {
    Text,
    Script,
}

/// What the written form of a list looks like from outside, to decide
/// where parentheses are needed.
#[derive(Debug, Default, Clone, Copy)]
struct Shape {
    /// Atoms side by side at the top level (`I₁I₂` is two).
    items: usize,
    /// A top-level operator, relation, punctuation or space: `a + b`.
    loose: bool,
    /// A top-level fraction.
    frac: bool,
    /// Starts with a sign: `−a`.
    signed: bool,
    /// A differential like `dt` or `∂x`, which reads as one factor.
    differential: bool,
    /// Already enclosed in one pair of brackets: `(x + y)`, `|k|`.
    bracketed: bool,
    /// Ends in a script written plainly as `_b` or `^q`, which would run
    /// into a following letter.
    open_tail: bool,
}

impl Shape {
    fn atom() -> Shape {
        Shape {
            items: 1,
            ..Shape::default()
        }
    }

    /// As the base of a script or under a root.
    fn compound(&self) -> bool {
        self.loose || self.frac || self.items > 1
    }

    fn needs_parens_as_numerator(&self) -> bool {
        self.loose || self.frac
    }

    fn needs_parens_as_denominator(&self) -> bool {
        self.loose || self.frac || self.signed || (self.items > 1 && !self.differential)
    }
}

fn list(nodes: &[Node<'_>], out: &mut String, mode: Mode) -> Shape {
    let mut shape = Shape::default();
    let mut prev: Option<Class> = None;
    let mut prev_open_tail = false;
    // The last node was an operator with limits (`lim_{x→0}`, `Σ_k`).
    let mut prev_limits = false;
    let mut pending: u8 = 0;
    let mut first_item = 0..0;
    // Bracket nesting: what sits inside `( ... )` or `| ... |` is one item
    // seen from outside, however loose it is inside.
    let mut depth = 0usize;
    let mut bar_open: Option<usize> = None;
    let mut first_opens = false;
    let mut last_closes = false;
    for (i, node) in nodes.iter().enumerate() {
        match node {
            Node::Empty => continue,
            Node::Space(n) => {
                pending = pending.saturating_add(*n);
                continue;
            }
            _ => {}
        }
        let mut class = class_of(node);
        if class == Class::Bin {
            let after_operand = matches!(
                prev,
                Some(Class::Ord | Class::Close | Class::Frac | Class::Radical)
            );
            let before_operand = !matches!(
                next_class(&nodes[i + 1..]),
                None | Some(Class::Rel | Class::Close | Class::Punct)
            );
            if !(after_operand && before_operand) {
                // A sign, not an operator: `−x`, `= +Ω`.
                class = Class::Ord;
                if prev.is_none() {
                    shape.signed = true;
                }
            }
        }
        // A fraction next to another factor or a function is bracketed so
        // that it cannot be misread: `(1/2)mv²`, `(4/ω₀) ln(8/(π − θ₀))`,
        // not `1/2 mv²`, `4/ω₀ ln 8/(π − θ₀)`. Bracketed, it spaces as a
        // bracket does.
        let factor = |c: Option<Class>| {
            matches!(
                c,
                Some(Class::Ord | Class::Frac | Class::Radical | Class::Function | Class::Op)
            )
        };
        // (After a big operator, `lim (sin x)/x`, the fraction is its
        // operand as written.)
        let bracketed_frac = class == Class::Frac
            && mode == Mode::Text
            && ((factor(prev) && prev != Some(Class::Op) && !prev_limits)
                || matches!(prev, Some(Class::Close))
                || factor(next_class(&nodes[i + 1..]))
                || matches!(next_class(&nodes[i + 1..]), Some(Class::Open)));
        let top = depth == 0;
        if let Some(p) = prev {
            let shown = if bracketed_frac { Class::Open } else { class };
            let mut gap = gap(p, shown, mode).max(pending);
            // `Ω_b t`, not `Ω_bt`: a plain `_b` must not run into the
            // next letter.
            if prev_open_tail
                && mode == Mode::Text
                && !matches!(class, Class::Close | Class::Punct | Class::Open)
            {
                gap = gap.max(1);
            }
            push_spaces(out, gap);
            shape.loose |= top && gap > 0;
        }
        shape.loose |= top && matches!(class, Class::Bin | Class::Rel | Class::Punct);
        let bar = matches!(node, Node::Leaf(Leaf::Char('|' | '‖' | '∥'), Class::Ord));
        let (opens, closes) = match class {
            Class::Open => (true, false),
            Class::Close => (false, true),
            _ if bar && bar_open == Some(depth.wrapping_sub(1)) => (false, true),
            _ if bar && bar_open.is_none() => (true, false),
            _ => (false, false),
        };
        if opens {
            if bar {
                bar_open = Some(depth);
            }
            depth += 1;
        } else if closes {
            depth = depth.saturating_sub(1);
            if bar {
                bar_open = None;
            }
        }
        pending = 0;
        let start = out.len();
        let mut inner = node_shape(node, out, mode);
        if bracketed_frac {
            wrap(out, start);
            inner.frac = false;
        }
        if top {
            shape.frac |= inner.frac && inner.items == 1 && !inner.loose;
            shape.items += 1;
            if shape.items == 1 {
                first_item = start..out.len();
                first_opens = opens;
            }
        }
        last_closes = closes && depth == 0;
        prev_open_tail = inner.open_tail;
        prev = Some(if bracketed_frac { Class::Close } else { class });
        prev_limits = matches!(node, Node::Script(sc)
            if sc.sub.is_some() && matches!(class_of(&sc.base), Class::Op | Class::Function));
    }
    shape.bracketed = shape.items == 1 && first_opens && last_closes;
    shape.open_tail = prev_open_tail;
    shape.differential =
        shape.items == 2 && !shape.loose && matches!(&out[first_item], "d" | "∂" | "δ" | "Δ");
    shape
}

fn push_spaces(out: &mut String, n: u8) {
    for _ in 0..n {
        out.push(' ');
    }
}

fn next_class(nodes: &[Node<'_>]) -> Option<Class> {
    nodes
        .iter()
        .find(|n| !matches!(n, Node::Empty | Node::Space(_)))
        .map(class_of)
}

fn class_of(node: &Node<'_>) -> Class {
    match node {
        Node::Leaf(_, class) => *class,
        Node::Group(nodes) => {
            let mut real = nodes
                .iter()
                .filter(|n| !matches!(n, Node::Empty | Node::Space(_)));
            match (real.next(), real.next()) {
                (Some(only), None) => class_of(only),
                _ => Class::Ord,
            }
        }
        Node::Script(scripted) => match class_of(&scripted.base) {
            Class::Frac | Class::Radical => Class::Ord,
            other => other,
        },
        Node::Accent(base, _) => match class_of(base) {
            Class::Frac | Class::Radical => Class::Ord,
            other => other,
        },
        Node::Negated(inner) => class_of(inner),
        Node::Frac(..) => Class::Frac,
        Node::Sqrt(_) | Node::Root(..) => Class::Radical,
        Node::Fenced(..) | Node::Env(..) | Node::Space(_) | Node::Empty => Class::Ord,
    }
}

/// Columns between two neighbouring atoms.
fn gap(prev: Class, cur: Class, mode: Mode) -> u8 {
    use Class::*;
    if mode == Mode::Script {
        return u8::from(prev == Function && matches!(cur, Ord | Function | Op | Radical));
    }
    let spaced = match (prev, cur) {
        (Open, _) | (_, Close) | (_, Punct) => false,
        (Bin, _) | (_, Bin) => true,
        (Rel, Rel) => false,
        (Rel, _) | (_, Rel) => true,
        (Punct, _) => true,
        (Op, Open) | (Function, Open) => false,
        (Op | Function, _) => true,
        (Ord | Close | Frac | Radical, Op | Function) => true,
        (Frac, _) => true,
        (Ord | Close | Radical, Frac) => true,
        (Radical, Ord | Radical) => true,
        _ => false,
    };
    u8::from(spaced)
}

fn wrap(out: &mut String, start: usize) {
    out.insert(start, '(');
    out.push(')');
}

fn node_shape(node: &Node<'_>, out: &mut String, mode: Mode) -> Shape {
    match node {
        Node::Leaf(leaf, _) => {
            match leaf {
                Leaf::Char(c) => out.push(*c),
                Leaf::Pair(a, b) => {
                    out.push(*a);
                    out.push(*b);
                }
                Leaf::Str(s) => out.push_str(s),
            }
            Shape::atom()
        }
        Node::Space(n) => {
            push_spaces(out, *n);
            Shape::default()
        }
        Node::Empty => Shape::default(),
        Node::Group(nodes) => list(nodes, out, mode),
        Node::Fenced(open, body, close) => {
            if let Some(c) = open {
                out.push(*c);
            }
            list(body, out, mode);
            if let Some(c) = close {
                out.push(*c);
            }
            Shape {
                bracketed: open.is_some() && close.is_some(),
                ..Shape::atom()
            }
        }
        Node::Env(kind, rows) => {
            env(*kind, rows, out, mode);
            Shape::atom()
        }
        Node::Script(scripted) => {
            let Scripted { base, sub, sup } = &**scripted;
            let start = out.len();
            if node_shape(base, out, mode).compound() {
                wrap(out, start);
            }
            let limits = class_of(base) == Class::Op;
            let mut open_tail = false;
            if let Some(sub) = sub {
                open_tail = script(sub, out, Position::Sub, limits);
            }
            if let Some(sup) = sup {
                open_tail = script(sup, out, Position::Sup, limits);
            }
            Shape {
                open_tail,
                ..Shape::atom()
            }
        }
        Node::Accent(base, accent) => {
            accented(base, *accent, out, mode);
            Shape::atom()
        }
        Node::Frac(parts) => {
            let [num, den] = &**parts;
            let start = out.len();
            if node_shape(num, out, mode).needs_parens_as_numerator() {
                wrap(out, start);
            }
            out.push('/');
            let start = out.len();
            if node_shape(den, out, mode).needs_parens_as_denominator() {
                wrap(out, start);
            }
            Shape {
                frac: true,
                ..Shape::atom()
            }
        }
        Node::Sqrt(radicand) => {
            out.push('√');
            radicand_shape(radicand, out, mode);
            Shape::atom()
        }
        Node::Root(parts) => {
            let [radicand, index] = &**parts;
            let mut idx = String::new();
            node_shape(index, &mut idx, Mode::Script);
            match idx.as_str() {
                "2" => out.push('√'),
                "3" => out.push('∛'),
                "4" => out.push('∜'),
                _ => {
                    match converted(&idx, glyphs::superscript) {
                        Some(raised) => out.push_str(&raised),
                        None => {
                            out.push('(');
                            out.push_str(&idx);
                            out.push(')');
                        }
                    }
                    out.push('√');
                }
            }
            radicand_shape(radicand, out, mode);
            Shape::atom()
        }
        Node::Negated(inner) => {
            let start = out.len();
            let shape = node_shape(inner, out, mode);
            let mut chars = out[start..].chars();
            match (chars.next(), chars.next()) {
                (Some(c), None) if glyphs::negated(c).is_some() => {
                    out.truncate(start);
                    out.push(glyphs::negated(c).unwrap_or(c));
                }
                _ => out.push('\u{0338}'),
            }
            shape
        }
    }
}

fn radicand_shape(radicand: &Node<'_>, out: &mut String, mode: Mode) {
    let start = out.len();
    if node_shape(radicand, out, mode).compound() {
        wrap(out, start);
    }
}

fn accented(base: &Node<'_>, accent: Accent, out: &mut String, mode: Mode) {
    let start = out.len();
    let shape = node_shape(base, out, mode);
    if glyphs::is_single_glyph(&out[start..]) {
        out.push(accent.combining());
    } else if let Some(mark) = accent.spanning() {
        let written = out.split_off(start);
        for c in written.chars() {
            out.push(c);
            if !glyphs::is_combining(c) && c != ' ' {
                out.push(mark);
            }
        }
    } else if start < out.len() {
        if !shape.bracketed {
            wrap(out, start);
        }
        out.push(accent.after_group());
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Position {
    Sub,
    Sup,
}

/// A sub- or superscript: Unicode script characters when every character
/// has one (parenthesised with script parentheses when it is more than one
/// symbol or number), else `_x`, `_(xy)`, `^x`, `^(xy)`. True when written
/// as a plain `_x` or `^x`.
fn script(node: &Node<'_>, out: &mut String, position: Position, limits: bool) -> bool {
    let start = out.len();
    node_shape(node, out, Mode::Script);
    if start == out.len() {
        return false;
    }
    let (map, open, close, marker): (fn(char) -> Option<char>, _, _, _) = match position {
        Position::Sub => (glyphs::subscript, '₍', '₎', '_'),
        Position::Sup => (glyphs::superscript, '⁽', '⁾', '^'),
    };
    let written = &out[start..];
    let single = glyphs::is_single_glyph(written) || is_number(written) || is_primes(written);
    let convertible = written
        .chars()
        .all(|c| glyphs::is_combining(c) || map(c).is_some());
    if !convertible {
        if single {
            out.insert(start, marker);
        } else {
            out.insert(start, '(');
            out.insert(start, marker);
            out.push(')');
        }
        return single;
    }
    // Rewrite the tail in place; scripts are short, so a stack copy.
    let mut copy = [0u8; 64];
    let owned;
    let tail: &str = if written.len() <= copy.len() {
        copy[..written.len()].copy_from_slice(written.as_bytes());
        std::str::from_utf8(&copy[..written.len()]).unwrap_or_default()
    } else {
        owned = written.to_string();
        &owned
    };
    out.truncate(start);
    let parens = !(single || limits);
    if parens {
        out.push(open);
    }
    out.extend(tail.chars().map(|c| map(c).unwrap_or(c)));
    if parens {
        out.push(close);
    }
    false
}

/// `s` with every character mapped, combining marks kept; `None` when one
/// character has no mapped form.
fn converted(s: &str, map: fn(char) -> Option<char>) -> Option<String> {
    s.chars()
        .map(|c| {
            if glyphs::is_combining(c) {
                Some(c)
            } else {
                map(c)
            }
        })
        .collect()
}

/// A signed decimal number such as `12`, `−1` or `2.5`.
fn is_number(s: &str) -> bool {
    let digits = s.strip_prefix(['−', '-', '+']).unwrap_or(s);
    digits.starts_with(|c: char| c.is_ascii_digit())
        && digits
            .chars()
            .all(|c| c.is_ascii_digit() || c == '.' || c == ',')
}

fn is_primes(s: &str) -> bool {
    !s.is_empty() && s.chars().all(|c| matches!(c, '′' | '″' | '‴'))
}

fn env(kind: EnvKind, rows: &[Vec<Vec<Node<'_>>>], out: &mut String, mode: Mode) {
    let (cell_sep, row_sep) = match kind {
        EnvKind::Matrix => (", ", "; "),
        EnvKind::Cases { .. } => ("  ", "; "),
        EnvKind::Lines => ("", "\n"),
    };
    if kind == (EnvKind::Cases { left: true }) {
        out.push_str("{ ");
    }
    for (r, row) in rows.iter().enumerate() {
        if r > 0 {
            out.push_str(row_sep);
        }
        for (c, cell) in row.iter().enumerate() {
            if c > 0 {
                if kind == EnvKind::Lines {
                    // `a &= b`: the cells are one equation split for
                    // alignment; pairs of them (`&` between equations)
                    // are set a quad apart.
                    let joins_relation = matches!(next_class(cell), Some(Class::Rel | Class::Bin))
                        || matches!(
                            row[c - 1]
                                .iter()
                                .rev()
                                .find(|n| !matches!(n, Node::Empty | Node::Space(_)))
                                .map(class_of),
                            Some(Class::Rel | Class::Bin)
                        );
                    if joins_relation {
                        out.push(' ');
                    } else if c % 2 == 0 {
                        out.push_str("  ");
                    }
                } else {
                    out.push_str(cell_sep);
                }
            }
            list(cell, out, mode);
        }
    }
    if kind == (EnvKind::Cases { left: false }) {
        out.push_str(" }");
    }
}

#[cfg(test)]
mod tests {
    use crate::math_to_unicode;

    #[track_caller]
    fn renders(latex: &str, expected: &str) {
        match math_to_unicode(latex) {
            Ok(got) => assert_eq!(got, expected, "rendering {latex}"),
            Err(e) => panic!("{latex} did not render: {e} at {}", e.offset),
        }
    }

    #[test]
    fn greek_letters_and_variants() {
        renders(
            r"\alpha\beta\gamma\delta\epsilon\varepsilon\zeta\eta\theta\vartheta\iota\kappa\lambda\mu\nu\xi\pi\rho\sigma\tau\upsilon\phi\varphi\chi\psi\omega",
            "αβγδϵεζηθϑικλµνξπρστυϕφχψω",
        );
        renders(
            r"\Gamma\Delta\Theta\Lambda\Xi\Pi\Sigma\Upsilon\Phi\Psi\Omega",
            "ΓΔΘΛΞΠΣΥΦΨΩ",
        );
    }

    #[test]
    fn subscripts_use_unicode_where_every_character_has_one() {
        renders(r"x_1", "x₁");
        renders(r"x_{12}", "x₁₂");
        renders(r"x_{xy}", "x₍ₓᵧ₎");
        renders(r"x_{i=1}", "x₍ᵢ₌₁₎");
    }

    #[test]
    fn subscripts_fall_back_to_underscore() {
        renders(r"\Omega_b", "Ω_b");
        renders(r"x_{bc}", "x_(bc)");
        renders(r"x_{\text{max}}", "x₍ₘₐₓ₎");
        renders(r"x_{\text{body}}", "x_(body)");
    }

    #[test]
    fn plain_fallback_script_does_not_run_into_the_next_letter() {
        renders(r"\cos(\Omega_b t)", "cos(Ω_b t)");
        renders(r"I_bI_c", "I_b I_c");
        renders(r"x^q y", "x^q y");
        renders(r"\Omega_b = 0", "Ω_b = 0");
        renders(r"f_b(x)", "f_b(x)");
        renders(r"(I_b)", "(I_b)");
    }

    #[test]
    fn absolute_value_bars_bracket_like_parentheses() {
        renders(r"\sqrt{|k|}", "√|k|");
        renders(r"\sqrt{|a| + |b|}", "√(|a| + |b|)");
        renders(r"\frac{1}{|x - y|}", "1/|x − y|");
        renders(r"\frac{\|v\|}{2}", "∥v∥/2");
    }

    #[test]
    fn superscripts() {
        renders(r"x^2", "x²");
        renders(r"x^{-1}", "x⁻¹");
        renders(r"x^{ab}", "x⁽ᵃᵇ⁾");
        renders(r"x^q", "x^q");
        renders(r"x^{qq}", "x^(qq)");
        renders(r"e^{-t/\tau}", "e^(−t/τ)");
        renders(r"A^T", "Aᵀ");
        renders(r"30^\circ", "30°");
        renders(r"f'(x) + g^{\prime\prime}", "f′(x) + g′′");
    }

    #[test]
    fn sub_and_superscript_together() {
        renders(r"I_i^2", "Iᵢ²");
        renders(r"x^2_1", "x₁²");
    }

    #[test]
    fn script_on_a_compound_base_is_parenthesised() {
        renders(r"{ab}^2", "(ab)²");
        renders(r"\frac{a}{b}^2", "(a/b)²");
        renders(r"(a+b)^2", "(a + b)²");
    }

    #[test]
    fn accents_on_a_letter_are_combining_marks() {
        renders(r"\dot x", "x\u{307}");
        renders(r"\ddot x", "x\u{308}");
        renders(r"\vec x", "x\u{20d7}");
        renders(r"\hat x", "x\u{302}");
        renders(r"\bar x", "x\u{304}");
        renders(r"\tilde x", "x\u{303}");
        renders(r"\hat{\mathbf n}", "n\u{302}");
        renders(r"\dot{\omega_1}", "ω\u{307}₁");
        renders(r"\dot{\vec L}", "L\u{20d7}\u{307}");
    }

    #[test]
    fn accents_on_a_group_fall_back() {
        renders(r"\bar{AB}", "A\u{305}B\u{305}");
        renders(r"\overline{AB}", "A\u{305}B\u{305}");
        renders(r"\dot{(x+y)}", "(x + y)˙");
        renders(r"\hat{xy}", "(xy)ˆ");
        renders(r"\vec{AB}", "(AB)\u{20d7}");
    }

    #[test]
    fn fractions_get_the_parentheses_they_need() {
        renders(r"\frac{a}{b}", "a/b");
        renders(r"\frac{I_2-I_3}{I_1}", "(I₂ − I₃)/I₁");
        renders(r"\frac{a}{b+c}", "a/(b + c)");
        renders(r"\frac{a}{bc}", "a/(bc)");
        renders(r"\frac{ab}{c}", "ab/c");
        renders(r"\frac{a}{-b}", "a/(−b)");
        renders(r"\frac{\frac{a}{b}}{c}", "(a/b)/c");
        renders(r"\frac{(a+b)}{c}", "(a + b)/c");
    }

    #[test]
    fn differentials_read_as_one_factor() {
        renders(r"\frac{dx}{dt}", "dx/dt");
        renders(r"\frac{d^2x}{dt^2}", "d²x/dt²");
        renders(r"\frac{\partial L}{\partial q}", "∂L/∂q");
        renders(r"\frac{\mathrm{d}x}{\mathrm{d}t}", "dx/dt");
        renders(r"\frac{\Delta x}{\Delta t}", "Δx/Δt");
    }

    #[test]
    fn fraction_is_set_apart_from_a_neighbouring_factor() {
        renders(r"\frac{1}{2}mv^2", "(1/2)mv²");
        renders(r"2\frac{a}{b}", "2(a/b)");
        renders(r"\frac{a}{b} + c", "a/b + c");
        renders(r"x = \frac{a}{b}", "x = a/b");
        renders(
            r"T \approx \frac{4}{\omega_0}\ln\frac{8}{\pi - \theta_0}",
            "T ≈ (4/ω₀) ln(8/(π − θ₀))",
        );
        renders(r"-\frac{g}{L}\sin\theta", "−(g/L) sin θ");
        renders(r"\frac{a}{b}(x+y)", "(a/b)(x + y)");
    }

    #[test]
    fn display_and_text_fractions() {
        renders(r"\dfrac{a}{b}", "a/b");
        renders(r"\tfrac{x+1}{y}", "(x + 1)/y");
        renders(r"\dfrac{a}{b}c", "(a/b)c");
    }

    #[test]
    fn font_commands_write_plain_letters() {
        renders(r"\mathrm{diag}(a)", "diag(a)");
        renders(r"\mathbf{F} = m\mathbf{a}", "F = ma");
        renders(r"\mathit{x}", "x");
        renders(r"\text{if } x", "if x");
        renders(r"\operatorname{tr} A", "tr A");
        renders(r"\mathbb R \mathcal L", "ℝℒ");
    }

    #[test]
    fn named_functions_are_spaced_from_their_argument() {
        renders(r"\sin\theta", "sin θ");
        renders(r"\cos(\omega t)", "cos(ωt)");
        renders(
            r"\lim_{x\to 0} \frac{\sin x}{x} = 1",
            "lim_(x→0) (sin x)/x = 1",
        );
    }

    #[test]
    fn large_operators() {
        renders(r"\sum_{i=1}^3 x_i", "∑ᵢ₌₁³ xᵢ");
        renders(r"\prod_i a_i", "∏ᵢ aᵢ");
        renders(r"\int_0^1 f\,dx", "∫₀¹ f dx");
    }

    #[test]
    fn binary_operators_are_spaced() {
        renders(r"a \times b", "a × b");
        renders(r"a\cdot b", "a ⋅ b");
        renders(r"a \pm b", "a ± b");
        renders(r"a - b", "a − b");
        renders(r"a+b", "a + b");
    }

    #[test]
    fn signs_are_not_spaced() {
        renders(r"-x", "−x");
        renders(r"-x = -1 + -y - z", "−x = −1 + −y − z");
        renders(r"\pm x", "±x");
        renders(r"(-a)", "(−a)");
        renders(r"a = +b", "a = +b");
    }

    #[test]
    fn relations_are_spaced() {
        renders(
            r"a \approx b \Rightarrow c \to d \rightarrow e \le f \ge g \ne h \neq i",
            "a ≈ b ⇒ c → d → e ≤ f ≥ g ≠ h ≠ i",
        );
        renders(
            r"a \equiv b \propto c \perp d \parallel e \ll f \gg g \sim h",
            "a ≡ b ∝ c ⟂ d ∥ e ≪ f ≫ g ∼ h",
        );
        renders(r"a=b", "a = b");
        renders(r"a\not= b", "a ≠ b");
    }

    #[test]
    fn symbols() {
        renders(r"\partial\infty", "∂∞");
        renders(r"1, 2, \ldots, n", "1, 2, …, n");
        renders(r"a_1 + \cdots + a_n", "a₁ + ⋯ + aₙ");
        renders(r"\dots", "⋯");
        renders(r"\langle x \rangle \|v\| |x|", "⟨x⟩∥v∥|x|");
    }

    #[test]
    fn square_roots() {
        renders(r"\sqrt{x}", "√x");
        renders(r"\sqrt{x+y}", "√(x + y)");
        renders(r"\sqrt{2}", "√2");
        renders(r"\sqrt{I_1 I_2}", "√(I₁I₂)");
        renders(r"\sqrt{\frac{a}{b}}", "√(a/b)");
        renders(r"\sqrt[3]{x}", "∛x");
        renders(r"\sqrt[n]{x}", "ⁿ√x");
    }

    #[test]
    fn delimiter_sizes_are_dropped() {
        renders(r"\left( \frac{a}{b} \right)", "(a/b)");
        renders(r"\big( x \big)", "(x)");
        renders(r"\Big[ y \Big]", "[y]");
        renders(r"\bigl( z \bigr)", "(z)");
        renders(r"\left| x \right|", "|x|");
        renders(r"\left. x \right|", "x|");
    }

    #[test]
    fn spacing_commands() {
        renders(r"a\quad b", "a  b");
        renders(r"a\qquad b", "a    b");
        renders(r"a\,b", "a b");
        renders(r"a\;b", "a b");
        renders(r"a\:b", "a b");
        renders(r"a\!b", "ab");
        renders(r"a~b", "a b");
        renders(r"a\ b", "a b");
        renders(r"a \, = b", "a = b");
        renders(r"\quad a \quad", "a");
    }

    #[test]
    fn environments() {
        renders(
            r"\begin{pmatrix} a & b \\ c & d \end{pmatrix}",
            "(a, b; c, d)",
        );
        renders(
            r"\begin{cases} 1 & x > 0 \\ 0 & \text{otherwise} \end{cases}",
            "{ 1  x > 0; 0  otherwise",
        );
        renders(
            r"\begin{aligned} a &= b + c \\ d &= e \end{aligned}",
            "a = b + c\nd = e",
        );
    }

    #[test]
    fn unknown_commands_are_errors() {
        for latex in [r"\foo", r"x + \unknowncmd{y}", r"\dddot x"] {
            let err = math_to_unicode(latex).unwrap_err();
            assert!(err.message.starts_with("unknown command"), "{err:?}");
            assert_eq!(Some(err.offset), latex.find('\\'), "{latex}");
        }
    }

    #[test]
    fn empty_formula_is_empty() {
        renders("", "");
        renders("  ", "");
        renders("{}", "");
    }
}
