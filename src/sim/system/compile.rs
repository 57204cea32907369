//! A system scene compiled once into expressions `exmex` evaluates: the
//! right-hand side, the observables, the sketch, and (only for implicit
//! methods) the Jacobian from symbolic partial derivatives, with central
//! differences for an entry whose function has no derivative rule
//! (`abs`, `sign`, `min`, `max`, `atan2`). Nothing is parsed inside a step.

use exmex::prelude::*;
use exmex::{BinOp, MakeOperators, MatchLiteral, Operator, ops_factory};
use nalgebra::DMatrix;

use super::expr::{self, Node, Subst};
use crate::sim::scene::spec::SystemScene;
use crate::sim::solvers::ode::OdeSystem;

ops_factory!(
    SceneOps,
    f64,
    Operator::make_bin(
        "^",
        BinOp {
            apply: |a, b| a.powf(b),
            prio: 4,
            is_commutative: false,
        }
    ),
    Operator::make_bin(
        "*",
        BinOp {
            apply: |a, b| a * b,
            prio: 2,
            is_commutative: true,
        }
    ),
    Operator::make_bin(
        "/",
        BinOp {
            apply: |a, b| a / b,
            prio: 3,
            is_commutative: false,
        }
    ),
    Operator::make_bin_unary(
        "+",
        BinOp {
            apply: |a, b| a + b,
            prio: 0,
            is_commutative: true,
        },
        |a| a
    ),
    Operator::make_bin_unary(
        "-",
        BinOp {
            apply: |a, b| a - b,
            prio: 1,
            is_commutative: false,
        },
        |a| -a
    ),
    Operator::make_bin(
        "atan2",
        BinOp {
            apply: |y, x| y.atan2(x),
            prio: 0,
            is_commutative: false,
        }
    ),
    Operator::make_bin(
        "min",
        BinOp {
            apply: |a, b| a.min(b),
            prio: 0,
            is_commutative: true,
        }
    ),
    Operator::make_bin(
        "max",
        BinOp {
            apply: |a, b| a.max(b),
            prio: 0,
            is_commutative: true,
        }
    ),
    Operator::make_unary("sin", |a| a.sin()),
    Operator::make_unary("cos", |a| a.cos()),
    Operator::make_unary("tan", |a| a.tan()),
    Operator::make_unary("asin", |a| a.asin()),
    Operator::make_unary("acos", |a| a.acos()),
    Operator::make_unary("atan", |a| a.atan()),
    Operator::make_unary("sinh", |a| a.sinh()),
    Operator::make_unary("cosh", |a| a.cosh()),
    Operator::make_unary("tanh", |a| a.tanh()),
    Operator::make_unary("exp", |a| a.exp()),
    Operator::make_unary("ln", |a| a.ln()),
    Operator::make_unary("log10", |a| a.log10()),
    Operator::make_unary("sqrt", |a| a.sqrt()),
    Operator::make_unary("abs", |a| a.abs()),
    Operator::make_unary("sign", |a| if a == 0.0 { 0.0 } else { a.signum() })
);

/// Numbers as the canonical text writes them: digits, an optional
/// fraction, an optional exponent.
#[derive(Clone, Debug)]
pub struct SceneNumbers;

impl MatchLiteral for SceneNumbers {
    fn is_literal(text: &str) -> Option<&str> {
        let b = text.as_bytes();
        let mut i = 0;
        while i < b.len() && b[i].is_ascii_digit() {
            i += 1;
        }
        if i < b.len() && b[i] == b'.' {
            i += 1;
            while i < b.len() && b[i].is_ascii_digit() {
                i += 1;
            }
        }
        if i == 0 || (i == 1 && b[0] == b'.') {
            return None;
        }
        if i < b.len() && (b[i] == b'e' || b[i] == b'E') {
            let mut j = i + 1;
            if j < b.len() && (b[j] == b'+' || b[j] == b'-') {
                j += 1;
            }
            let digits = j;
            while j < b.len() && b[j].is_ascii_digit() {
                j += 1;
            }
            if j > digits {
                i = j;
            }
        }
        Some(&text[..i])
    }
}

type Ex = FlatEx<f64, SceneOps, SceneNumbers>;

/// Where an expression's inputs come from: slot `k < n` is variable k,
/// slot `n` is time.
#[derive(Debug, Clone)]
enum Fast {
    Const(f64),
    Slot(usize),
    Ex { ex: Box<Ex>, slots: Vec<usize> },
}

/// Most inputs gathered on the stack; more go through a heap buffer.
const STACK: usize = 16;

impl Fast {
    fn new(ex: Ex, slot_of: &dyn Fn(&str) -> Option<usize>) -> Result<Fast, String> {
        let names = ex.var_names().to_vec();
        let mut slots = Vec::with_capacity(names.len());
        for n in &names {
            slots.push(slot_of(n).ok_or_else(|| format!("unknown name `{n}`"))?);
        }
        if slots.is_empty() {
            let v = ex.eval(&[]).map_err(|e| e.to_string())?;
            return Ok(Fast::Const(v));
        }
        // A bare variable (`omega`) is read directly.
        let bare = ex.unparse().trim_matches(|c| c == '(' || c == ')');
        if slots.len() == 1
            && bare.starts_with('{')
            && bare.ends_with('}')
            && bare.matches('{').count() == 1
        {
            return Ok(Fast::Slot(slots[0]));
        }
        Ok(Fast::Ex {
            ex: Box::new(ex),
            slots,
        })
    }

    #[inline]
    fn eval(&self, input: &[f64]) -> f64 {
        match self {
            Fast::Const(v) => *v,
            Fast::Slot(k) => input[*k],
            Fast::Ex { ex, slots } => {
                let r = if slots.len() <= STACK {
                    let mut buf = [0.0; STACK];
                    for (b, &s) in buf.iter_mut().zip(slots) {
                        *b = input[s];
                    }
                    ex.eval(&buf[..slots.len()])
                } else {
                    let buf: Vec<f64> = slots.iter().map(|&s| input[s]).collect();
                    ex.eval(&buf)
                };
                r.unwrap_or(f64::NAN)
            }
        }
    }
}

/// The parsed, checked expressions of a scene, before compilation.
struct Parsed {
    equations: Vec<Node>,
    observables: Vec<Node>,
    marks: Vec<Node>,
}

/// Canonical texts of the observables, each with earlier ones expanded.
fn observable_texts(scene: &SystemScene, nodes: &[Node]) -> Vec<String> {
    let mut texts: Vec<String> = Vec::new();
    for node in nodes {
        let t = canonical(scene, node, &texts);
        texts.push(t);
    }
    texts
}

fn canonical(scene: &SystemScene, node: &Node, obs: &[String]) -> String {
    expr::canonical(node, &|name| {
        if let Some((_, v)) = scene.params.iter().find(|(p, _)| p == name) {
            return Subst::Value(*v);
        }
        if let Some(k) = scene.observables.iter().position(|(o, _)| o == name)
            && let Some(t) = obs.get(k)
        {
            return Subst::Text(t);
        }
        Subst::Var
    })
}

fn parse_all(scene: &SystemScene) -> Result<Parsed, String> {
    let p = |what: &str, text: &str| expr::parse(text).map_err(|e| format!("{what} `{text}`: {e}"));
    Ok(Parsed {
        equations: scene
            .equations
            .iter()
            .map(|e| p("equation", e))
            .collect::<Result<_, _>>()?,
        observables: scene
            .observables
            .iter()
            .map(|(_, e)| p("observable", e))
            .collect::<Result<_, _>>()?,
        marks: scene
            .sketch
            .iter()
            .flat_map(|m| m.exprs())
            .map(|e| p("sketch", e))
            .collect::<Result<_, _>>()?,
    })
}

/// A system scene compiled for the solvers.
#[derive(Debug, Clone)]
pub struct System {
    n: usize,
    rhs: Vec<Fast>,
    /// Row-major n×n; `None` where no derivative rule applies (that entry
    /// is a central difference of its equation). Empty unless built.
    jac: Vec<Option<Fast>>,
    observables: Vec<Fast>,
    marks: Vec<Fast>,
}

impl System {
    /// Compiles the right-hand side, observables and sketch; with
    /// `jacobian`, also the symbolic partial derivatives.
    pub fn compile(scene: &SystemScene, jacobian: bool) -> Result<System, String> {
        let parsed = parse_all(scene)?;
        let n = scene.variables.len();
        let obs = observable_texts(scene, &parsed.observables);
        let slot_of = |name: &str| -> Option<usize> {
            if name == "t" {
                Some(n)
            } else {
                scene.variables.iter().position(|v| v == name)
            }
        };
        let build = |text: &str| -> Result<(Ex, Fast), String> {
            let ex = Ex::parse(text).map_err(|e| format!("`{text}`: {e}"))?;
            let fast = Fast::new(ex.clone(), &slot_of)?;
            Ok((ex, fast))
        };
        let mut rhs = Vec::with_capacity(n);
        let mut rhs_ex = Vec::with_capacity(n);
        for node in &parsed.equations {
            let (ex, fast) = build(&canonical(scene, node, &obs))?;
            rhs.push(fast);
            rhs_ex.push(ex);
        }
        let mut jac = Vec::new();
        if jacobian {
            for ex in &rhs_ex {
                let names = ex.var_names().to_vec();
                for v in &scene.variables {
                    let entry = match names.iter().position(|x| x == v) {
                        None => Some(Fast::Const(0.0)),
                        Some(idx) => match ex.clone().partial(idx) {
                            Ok(d) => Some(Fast::new(d, &slot_of)?),
                            Err(_) => None,
                        },
                    };
                    jac.push(entry);
                }
            }
        }
        let observables = obs
            .iter()
            .map(|t| build(t).map(|b| b.1))
            .collect::<Result<_, _>>()?;
        let marks = parsed
            .marks
            .iter()
            .map(|node| build(&canonical(scene, node, &obs)).map(|b| b.1))
            .collect::<Result<_, _>>()?;
        Ok(System {
            n,
            rhs,
            jac,
            observables,
            marks,
        })
    }

    pub fn has_jacobian(&self) -> bool {
        !self.jac.is_empty()
    }

    /// How many Jacobian entries fall back to differences.
    pub fn differenced_entries(&self) -> usize {
        self.jac.iter().filter(|e| e.is_none()).count()
    }

    fn input(&self, t: f64, y: &[f64]) -> InputBuf {
        let mut buf = InputBuf::new(self.n + 1);
        buf.as_mut()[..self.n].copy_from_slice(y);
        buf.as_mut()[self.n] = t;
        buf
    }

    /// Observable `k` at (t, y).
    pub fn observable(&self, k: usize, t: f64, y: &[f64]) -> f64 {
        self.observables[k].eval(self.input(t, y).as_ref())
    }

    pub fn observable_count(&self) -> usize {
        self.observables.len()
    }

    /// Sketch coordinate `k` (the sketch's expressions in order) at (t, y).
    pub fn mark(&self, k: usize, t: f64, y: &[f64]) -> f64 {
        self.marks[k].eval(self.input(t, y).as_ref())
    }

    pub fn mark_count(&self) -> usize {
        self.marks.len()
    }
}

/// The input slots (variables, then t), on the stack for small systems.
enum InputBuf {
    Stack([f64; STACK], usize),
    Heap(Vec<f64>),
}

impl InputBuf {
    fn new(len: usize) -> InputBuf {
        if len <= STACK {
            InputBuf::Stack([0.0; STACK], len)
        } else {
            InputBuf::Heap(vec![0.0; len])
        }
    }
    fn as_mut(&mut self) -> &mut [f64] {
        match self {
            InputBuf::Stack(a, n) => &mut a[..*n],
            InputBuf::Heap(v) => v,
        }
    }
    fn as_ref(&self) -> &[f64] {
        match self {
            InputBuf::Stack(a, n) => &a[..*n],
            InputBuf::Heap(v) => v,
        }
    }
}

impl OdeSystem for System {
    fn dim(&self) -> usize {
        self.n
    }

    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        let input = self.input(t, y);
        for (d, f) in dy.iter_mut().zip(&self.rhs) {
            *d = f.eval(input.as_ref());
        }
    }

    fn jacobian(&self, t: f64, y: &[f64], jac: &mut DMatrix<f64>) {
        let n = self.n;
        if jac.nrows() != n || jac.ncols() != n {
            *jac = DMatrix::zeros(n, n);
        }
        if self.jac.is_empty() {
            crate::sim::solvers::ode::finite_difference_jacobian(self, t, y, jac);
            return;
        }
        let mut input = self.input(t, y);
        for i in 0..n {
            for j in 0..n {
                jac[(i, j)] = match &self.jac[i * n + j] {
                    Some(d) => d.eval(input.as_ref()),
                    None => {
                        let yj = y[j];
                        let h = f64::EPSILON.cbrt() * yj.abs().max(1e-3);
                        input.as_mut()[j] = yj + h;
                        let up = self.rhs[i].eval(input.as_ref());
                        input.as_mut()[j] = yj - h;
                        let down = self.rhs[i].eval(input.as_ref());
                        input.as_mut()[j] = yj;
                        (up - down) / (2.0 * h)
                    }
                };
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::scene::spec::{Mark, SystemPanel};

    pub(crate) fn pendulum() -> SystemScene {
        SystemScene {
            id: "p".into(),
            title: None,
            variables: vec!["theta".into(), "omega".into()],
            initial: vec![2.9670597283903604, 0.0],
            params: vec![("g".into(), 9.81), ("L".into(), 1.0)],
            equations: vec!["omega".into(), "-g/L*sin(theta)".into()],
            observables: vec![
                (
                    "energy".into(),
                    "0.5*L^2*omega^2 + g*L*(1 - cos(theta))".into(),
                ),
                ("x".into(), "L*sin(theta)".into()),
                ("y".into(), "-L*cos(theta)".into()),
                ("r".into(), "sqrt(x^2 + y^2)".into()),
            ],
            conserved: vec!["energy".into()],
            duration: 20.0,
            show: vec![SystemPanel::Plot],
            plot: vec!["theta".into()],
            phase: None,
            sketch: vec![Mark::Line(["0".into(), "0".into(), "x".into(), "y".into()])],
            time_unit: "s".into(),
        }
    }

    #[test]
    fn evaluates_what_was_written() {
        let s = System::compile(&pendulum(), true).unwrap();
        let y = [0.7, -1.3];
        let mut dy = [0.0; 2];
        s.rhs(0.0, &y, &mut dy);
        assert_eq!(dy[0], -1.3);
        assert!((dy[1] + 9.81 * 0.7f64.sin()).abs() < 1e-14);
        let e = 0.5 * 1.3f64.powi(2) + 9.81 * (1.0 - 0.7f64.cos());
        assert!((s.observable(0, 0.0, &y) - e).abs() < 1e-13);
        // An observable built on earlier ones.
        assert!((s.observable(3, 0.0, &y) - 1.0).abs() < 1e-15);
        assert!((s.mark(2, 0.0, &y) - 0.7f64.sin()).abs() < 1e-15);
        assert_eq!(s.mark(0, 0.0, &y), 0.0);
    }

    #[test]
    fn symbolic_jacobian_matches_differences() {
        let mut scene = pendulum();
        scene.equations[1] = "-g/L*sin(theta) - 0.1*abs(omega)*omega + t^2".into();
        let s = System::compile(&scene, true).unwrap();
        // Differentiating a row that calls `abs` fails as a whole.
        assert_eq!(s.differenced_entries(), 2);
        let y = [0.4, 0.9];
        let mut j = DMatrix::zeros(2, 2);
        s.jacobian(1.5, &y, &mut j);
        let mut fd = DMatrix::zeros(2, 2);
        crate::sim::solvers::ode::finite_difference_jacobian(&s, 1.5, &y, &mut fd);
        assert!((&j - &fd).abs().max() < 1e-8, "{j} vs {fd}");
        assert_eq!(j[(0, 1)], 1.0);
        let s = System::compile(&pendulum(), true).unwrap();
        assert_eq!(s.differenced_entries(), 0);
        s.jacobian(0.0, &y, &mut j);
        assert!((j[(1, 0)] + 9.81 * 0.4f64.cos()).abs() < 1e-14);
        assert_eq!(j[(1, 1)], 0.0);
    }

    #[test]
    fn mathematics_conventions_hold() {
        let mut scene = pendulum();
        scene.observables = vec![
            ("a".into(), "-theta^2".into()),
            ("b".into(), "2^3^2".into()),
            ("c".into(), "1e-3*theta + 2.5E+1".into()),
            (
                "d".into(),
                "atan2(1, -1) + min(theta, 0) + max(theta, 0) + sign(-3)".into(),
            ),
            ("f".into(), "pi + e + log10(100) + ln(e)".into()),
        ];
        scene.sketch.clear();
        let s = System::compile(&scene, false).unwrap();
        let y = [3.0, 0.0];
        assert_eq!(s.observable(0, 0.0, &y), -9.0);
        assert_eq!(s.observable(1, 0.0, &y), 512.0);
        assert!((s.observable(2, 0.0, &y) - 25.003).abs() < 1e-12);
        let d = (1.0f64).atan2(-1.0) + 0.0 + 3.0 - 1.0;
        assert!((s.observable(3, 0.0, &y) - d).abs() < 1e-14);
        let f = std::f64::consts::PI + std::f64::consts::E + 3.0;
        assert!((s.observable(4, 0.0, &y) - f).abs() < 1e-14);
    }
}
