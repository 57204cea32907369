//! A system scene compiled once into flat programs the solvers run: the
//! right-hand side, the observables and the sketch. A program is a list of
//! operations, each reading the values of earlier ones (a tape), so running
//! it is one loop without recursion, and its length is the work of one
//! evaluation.
//!
//! An observable is compiled once into each program that uses it, and every
//! later use reads its value: observables built on each other (`o1 = o0 +
//! o0`, `o2 = o1 + o1`, …) cost their own size, never the size of their
//! expansion. Each program is capped at [`MAX_PROGRAM`] operations, and
//! [`Cost`] says what a step of the scene costs, so a deck is refused
//! before it runs when its scene would be too slow to play.
//!
//! The Jacobian the implicit methods need is the exact derivative of the
//! right-hand side, by forward differentiation along the same tape: one
//! pass per variable, never a symbolic expression that could grow (every
//! function has its rule, `abs`, `sign`, `min`, `max` and `atan2` too).
//! The pass for a variable runs only the operations that read it
//! ([`Deps`]), so a large sparse system (a 200-variable reaction–diffusion
//! chain) costs the entries that can be non-zero, not n² of them, and the
//! same lists give the solvers the Jacobian's pattern
//! ([`OdeSystem::sparsity`]).
//!
//! When a value is not finite, [`Program::fault`] runs the tape again at
//! that point and finds the first operation that made it so, and why (a
//! log of a negative number, a division by zero): work done only on the
//! failure path.

use nalgebra::DMatrix;

use super::expr::{self, Node};
use crate::rhs::Split;
use crate::solvers::ode::OdeSystem;
use crate::solvers::ode::lu::LuPlan;
use crate::system::spec::SystemScene;
use flipcard_text::num::Num;

/// Most operations in one compiled program (an expression with the
/// observables it uses, or all the equations, or all the observables).
pub(crate) const MAX_PROGRAM: usize = 50_000;

/// The functions of [`expr::FUNCTIONS`], as the tape runs them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Fun {
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Sinh,
    Cosh,
    Tanh,
    Exp,
    Ln,
    Log10,
    Sqrt,
    Abs,
    Sign,
    Atan2,
    Min,
    Max,
}

impl Fun {
    fn of(name: &str) -> Option<Fun> {
        Some(match name {
            "sin" => Fun::Sin,
            "cos" => Fun::Cos,
            "tan" => Fun::Tan,
            "asin" => Fun::Asin,
            "acos" => Fun::Acos,
            "atan" => Fun::Atan,
            "sinh" => Fun::Sinh,
            "cosh" => Fun::Cosh,
            "tanh" => Fun::Tanh,
            "exp" => Fun::Exp,
            "ln" => Fun::Ln,
            "log10" => Fun::Log10,
            "sqrt" => Fun::Sqrt,
            "abs" => Fun::Abs,
            "sign" => Fun::Sign,
            "atan2" => Fun::Atan2,
            "min" => Fun::Min,
            "max" => Fun::Max,
            _ => return None,
        })
    }

    fn name(self) -> &'static str {
        match self {
            Fun::Sin => "sin",
            Fun::Cos => "cos",
            Fun::Tan => "tan",
            Fun::Asin => "asin",
            Fun::Acos => "acos",
            Fun::Atan => "atan",
            Fun::Sinh => "sinh",
            Fun::Cosh => "cosh",
            Fun::Tanh => "tanh",
            Fun::Exp => "exp",
            Fun::Ln => "ln",
            Fun::Log10 => "log10",
            Fun::Sqrt => "sqrt",
            Fun::Abs => "abs",
            Fun::Sign => "sign",
            Fun::Atan2 => "atan2",
            Fun::Min => "min",
            Fun::Max => "max",
        }
    }

    #[inline]
    fn apply1(self, a: f64) -> f64 {
        match self {
            Fun::Sin => a.sin(),
            Fun::Cos => a.cos(),
            Fun::Tan => a.tan(),
            Fun::Asin => a.asin(),
            Fun::Acos => a.acos(),
            Fun::Atan => a.atan(),
            Fun::Sinh => a.sinh(),
            Fun::Cosh => a.cosh(),
            Fun::Tanh => a.tanh(),
            Fun::Exp => a.exp(),
            Fun::Ln => a.ln(),
            Fun::Log10 => a.log10(),
            Fun::Sqrt => a.sqrt(),
            Fun::Abs => a.abs(),
            Fun::Sign => {
                if a == 0.0 {
                    0.0
                } else {
                    a.signum()
                }
            }
            Fun::Atan2 | Fun::Min | Fun::Max => f64::NAN,
        }
    }

    #[inline]
    fn apply2(self, a: f64, b: f64) -> f64 {
        match self {
            Fun::Atan2 => a.atan2(b),
            Fun::Min => a.min(b),
            Fun::Max => a.max(b),
            _ => f64::NAN,
        }
    }
}

/// One operation; its result is the value at its own index.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Op {
    Const(f64),
    /// Input slot: variable k (k < n), or time (slot n).
    Slot(u32),
    Neg(u32),
    Add(u32, u32),
    Sub(u32, u32),
    Mul(u32, u32),
    Div(u32, u32),
    Pow(u32, u32),
    Call1(Fun, u32),
    Call2(Fun, u32, u32),
}

impl Op {
    /// The values this operation reads.
    fn operands(&self) -> (Option<u32>, Option<u32>) {
        match *self {
            Op::Const(_) | Op::Slot(_) => (None, None),
            Op::Neg(a) | Op::Call1(_, a) => (Some(a), None),
            Op::Add(a, b)
            | Op::Sub(a, b)
            | Op::Mul(a, b)
            | Op::Div(a, b)
            | Op::Pow(a, b)
            | Op::Call2(_, a, b) => (Some(a), Some(b)),
        }
    }

    #[inline]
    fn eval(&self, vals: &[f64], t: f64, y: &[f64]) -> f64 {
        let v = |k: u32| vals[k as usize];
        match *self {
            Op::Const(c) => c,
            Op::Slot(k) => y.get(k as usize).copied().unwrap_or(t),
            Op::Neg(a) => -v(a),
            Op::Add(a, b) => v(a) + v(b),
            Op::Sub(a, b) => v(a) - v(b),
            Op::Mul(a, b) => v(a) * v(b),
            Op::Div(a, b) => v(a) / v(b),
            Op::Pow(a, b) => v(a).powf(v(b)),
            Op::Call1(f, a) => f.apply1(v(a)),
            Op::Call2(f, a, b) => f.apply2(v(a), v(b)),
        }
    }
}

/// Which expression of the scene something was written in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Source {
    /// The equation of variable k.
    Equation(usize),
    /// Observable k.
    Observable(usize),
    /// Expression k of the sketch (its marks' coordinates in order).
    Mark(usize),
}

impl Source {
    /// "the equation of `v`", "`lnx`", "the sketch's expression 3".
    pub fn describe(self, scene: &SystemScene) -> String {
        match self {
            Source::Equation(k) => format!(
                "the equation of `{}`",
                scene.variables.get(k).map_or("?", String::as_str)
            ),
            Source::Observable(k) => format!(
                "`{}`",
                scene.observables.get(k).map_or("?", |(o, _)| o.as_str())
            ),
            Source::Mark(k) => {
                let mut left = k;
                for m in &scene.sketch {
                    let exprs = m.exprs();
                    if left < exprs.len() {
                        return format!("the sketch's `{}` `{}`", m.key(), exprs[left]);
                    }
                    left -= exprs.len();
                }
                format!("sketch expression {}", k + 1)
            }
        }
    }
}

/// Why a scene does not compile, and in which expression.
#[derive(Debug, Clone, PartialEq)]
pub struct CompileError {
    /// The expression at fault; `None` for the scene as a whole.
    pub source: Option<Source>,
    pub message: String,
}

impl std::fmt::Display for CompileError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for CompileError {}

/// Why a value is not finite: the first operation that made it so.
#[derive(Debug, Clone, PartialEq)]
pub enum Cause {
    /// `ln` or `log10` of a negative number.
    LogOfNegative(&'static str, f64),
    /// `ln` or `log10` of zero.
    LogOfZero(&'static str),
    SqrtOfNegative(f64),
    DivisionByZero,
    /// Zero to a negative power (a division by zero too).
    ZeroToNegativePower(f64),
    /// A negative number to a power that is not an integer.
    NegativeToFractionalPower(f64, f64),
    /// `asin` or `acos` of a number outside [−1, 1].
    OutsideUnitRange(&'static str, f64),
    /// A finite operation whose result is too large for f64: which.
    Overflow(&'static str),
}

impl Cause {
    /// A value outside the domain of an operation (as opposed to a value
    /// too large to hold, which is what a solution blowing up looks like).
    pub(crate) fn is_domain(&self) -> bool {
        !matches!(self, Cause::Overflow(_))
    }
}

impl std::fmt::Display for Cause {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Cause::LogOfNegative(fun, a) => {
                write!(f, "{fun} of a negative number ({fun}({}))", Num(*a))
            }
            Cause::LogOfZero(fun) => write!(f, "{fun} of zero"),
            Cause::SqrtOfNegative(a) => {
                write!(f, "square root of a negative number (sqrt({}))", Num(*a))
            }
            Cause::DivisionByZero => f.write_str("division by zero"),
            Cause::ZeroToNegativePower(b) => {
                write!(
                    f,
                    "zero to a negative power (0^{}), a division by zero",
                    Num(*b)
                )
            }
            Cause::NegativeToFractionalPower(a, b) => write!(
                f,
                "a negative number to a fractional power ({}^{})",
                Num(*a),
                Num(*b)
            ),
            Cause::OutsideUnitRange(fun, a) => {
                write!(f, "{fun} of a number outside [-1, 1] ({fun}({}))", Num(*a))
            }
            Cause::Overflow(what) => write!(f, "{what} overflows"),
        }
    }
}

/// A value that is not finite: which expression, the value, the first
/// operation at fault and the expression that operation was written in
/// (an observable the expression uses, say).
#[derive(Debug, Clone, PartialEq)]
pub struct Fault {
    pub source: Source,
    pub value: f64,
    pub cause: Cause,
    pub written_in: Source,
}

impl Fault {
    /// "`lnx` is NaN: ln of a negative number (ln(-0.5))"; the caller adds
    /// the time.
    pub fn describe(&self, scene: &SystemScene, t: f64) -> String {
        let value = if self.value.is_nan() {
            "NaN".to_string()
        } else if self.value > 0.0 {
            "infinite".to_string()
        } else {
            "-infinite".to_string()
        };
        let mut s = format!(
            "{} is {value} at t = {}: {}",
            self.source.describe(scene),
            time(t),
            self.cause
        );
        if self.written_in != self.source {
            s.push_str(&format!(" in {}", self.written_in.describe(scene)));
        }
        s
    }
}

/// A time to four significant digits, always with a decimal point.
pub fn time(t: f64) -> String {
    let mut s = flipcard_text::num::rounded(t, 4);
    if !s.contains(['.', 'e', 'E']) {
        s.push_str(".0");
    }
    s
}

/// The first operation of `ops` (in order) that gives a non-finite value
/// from finite operands, among those `out` depends on, and why.
fn cause_of(ops: &[Op], vals: &[f64], out: usize) -> Option<(usize, Cause)> {
    let mut needed = vec![false; out + 1];
    needed[out] = true;
    for i in (0..=out).rev() {
        if needed[i] {
            let (a, b) = ops[i].operands();
            for k in [a, b].into_iter().flatten() {
                needed[k as usize] = true;
            }
        }
    }
    for i in 0..=out {
        if !needed[i] || vals[i].is_finite() {
            continue;
        }
        let (a, b) = ops[i].operands();
        let x = a.map(|k| vals[k as usize]);
        let z = b.map(|k| vals[k as usize]);
        if x.is_some_and(|v| !v.is_finite()) || z.is_some_and(|v| !v.is_finite()) {
            continue;
        }
        let x = x.unwrap_or(0.0);
        let z = z.unwrap_or(0.0);
        let cause = match ops[i] {
            Op::Div(..) if z == 0.0 => Cause::DivisionByZero,
            Op::Div(..) => Cause::Overflow("a division"),
            Op::Pow(..) if x == 0.0 && z < 0.0 => Cause::ZeroToNegativePower(z),
            Op::Pow(..) if x < 0.0 && z.fract() != 0.0 => Cause::NegativeToFractionalPower(x, z),
            Op::Pow(..) => Cause::Overflow("a power"),
            Op::Call1(f @ (Fun::Ln | Fun::Log10), _) if x == 0.0 => Cause::LogOfZero(f.name()),
            Op::Call1(f @ (Fun::Ln | Fun::Log10), _) => Cause::LogOfNegative(f.name(), x),
            Op::Call1(Fun::Sqrt, _) => Cause::SqrtOfNegative(x),
            Op::Call1(f @ (Fun::Asin | Fun::Acos), _) => Cause::OutsideUnitRange(f.name(), x),
            Op::Call1(f, _) | Op::Call2(f, ..) => Cause::Overflow(match f {
                Fun::Exp => "exp",
                Fun::Sinh => "sinh",
                Fun::Cosh => "cosh",
                Fun::Tan => "tan",
                _ => "a function",
            }),
            Op::Add(..) => Cause::Overflow("a sum"),
            Op::Sub(..) => Cause::Overflow("a difference"),
            Op::Mul(..) => Cause::Overflow("a product"),
            Op::Neg(..) | Op::Const(_) | Op::Slot(_) => continue,
        };
        return Some((i, cause));
    }
    None
}

/// The values of a tape: on the stack when short, else in a buffer of the
/// thread kept between evaluations (a long tape is run thousands of times
/// a second).
const STACK: usize = 64;

thread_local! {
    static VALUES: std::cell::RefCell<Vec<f64>> = const { std::cell::RefCell::new(Vec::new()) };
}

fn with_values<R>(len: usize, f: impl FnOnce(&mut [f64]) -> R) -> R {
    if len <= STACK {
        let mut buf = [0.0; STACK];
        return f(&mut buf[..len]);
    }
    VALUES.with(|cell| match cell.try_borrow_mut() {
        Ok(mut buf) => {
            if buf.len() < len {
                buf.resize(len, 0.0);
            }
            f(&mut buf[..len])
        }
        // Only if an evaluation ever ran inside another.
        Err(_) => f(&mut vec![0.0; len]),
    })
}

/// Most (variable, operation) pairs [`Deps`] lists; a scene with more
/// (every operation reading every one of many variables) runs the full
/// pass per variable instead.
const MAX_DEPS: usize = 4_000_000;

/// For each variable, the operations whose value moves with it (in tape
/// order) and the outputs among them: the only work of its pass of the
/// Jacobian.
#[derive(Debug, Clone, Default)]
struct Deps {
    ops: Vec<Vec<u32>>,
    /// (row, operation) of each output that reads the variable.
    outputs: Vec<Vec<(u32, u32)>>,
}

impl Deps {
    /// The lists of `prog` for `n` variables; `None` past [`MAX_DEPS`].
    fn of(prog: &Program, n: usize) -> Option<Deps> {
        let mut by_op: Vec<Vec<u32>> = Vec::with_capacity(prog.ops.len());
        let mut total = 0usize;
        for op in &prog.ops {
            let mut r: Vec<u32> = Vec::new();
            if let Op::Slot(k) = op
                && (*k as usize) < n
            {
                r.push(*k);
            }
            let (a, b) = op.operands();
            for k in [a, b].into_iter().flatten() {
                r.extend_from_slice(&by_op[k as usize]);
            }
            r.sort_unstable();
            r.dedup();
            total += r.len();
            if total > MAX_DEPS {
                return None;
            }
            by_op.push(r);
        }
        let mut deps = Deps {
            ops: vec![Vec::new(); n],
            outputs: vec![Vec::new(); n],
        };
        for (i, vars) in by_op.iter().enumerate() {
            for &v in vars {
                deps.ops[v as usize].push(i as u32);
            }
        }
        for (row, (k, _)) in prog.outputs.iter().enumerate() {
            for &v in &by_op[*k as usize] {
                deps.outputs[v as usize].push((row as u32, *k));
            }
        }
        Some(deps)
    }

    /// Operations of one Jacobian.
    fn work(&self) -> usize {
        self.ops.iter().map(Vec::len).sum()
    }
}

/// A compiled tape with its outputs.
#[derive(Debug, Clone, Default)]
pub struct Program {
    ops: Vec<Op>,
    /// The expression each operation was written in (failure path only).
    origin: Vec<Source>,
    /// The value of each output, and the expression it is.
    outputs: Vec<(u32, Source)>,
}

impl Program {
    /// Operations run per evaluation.
    pub(crate) fn len(&self) -> usize {
        self.ops.len()
    }

    fn run(&self, t: f64, y: &[f64], vals: &mut [f64]) {
        for (i, op) in self.ops.iter().enumerate() {
            vals[i] = op.eval(vals, t, y);
        }
    }

    /// Every output at (t, y), into `out`.
    pub(crate) fn eval_into(&self, t: f64, y: &[f64], out: &mut [f64]) {
        with_values(self.ops.len(), |vals| {
            self.run(t, y, vals);
            for (o, (k, _)) in out.iter_mut().zip(&self.outputs) {
                *o = vals[*k as usize];
            }
        });
    }

    /// Which of the `n` variables each output reads, by the operations it
    /// is computed from (structurally: `0*x` reads `x`).
    pub(crate) fn reads(&self, n: usize) -> Vec<Vec<bool>> {
        let mut by_op: Vec<Vec<bool>> = Vec::with_capacity(self.ops.len());
        for op in &self.ops {
            let mut r = vec![false; n];
            if let Op::Slot(k) = op
                && (*k as usize) < n
            {
                r[*k as usize] = true;
            }
            let (a, b) = op.operands();
            for k in [a, b].into_iter().flatten() {
                for (x, y) in r.iter_mut().zip(&by_op[k as usize]) {
                    *x |= *y;
                }
            }
            by_op.push(r);
        }
        self.outputs
            .iter()
            .map(|(k, _)| by_op[*k as usize].clone())
            .collect()
    }

    /// Output `k` alone at (t, y): only the operations up to it run.
    pub(crate) fn eval_one(&self, k: usize, t: f64, y: &[f64]) -> f64 {
        let Some(&(last, _)) = self.outputs.get(k) else {
            return f64::NAN;
        };
        let len = last as usize + 1;
        with_values(len, |vals| {
            for (i, op) in self.ops[..len].iter().enumerate() {
                vals[i] = op.eval(vals, t, y);
            }
            vals[last as usize]
        })
    }

    /// Outputs `0..=k` at (t, y), into `out[..=k]`: only the operations up
    /// to output k run.
    pub(crate) fn eval_upto(&self, k: usize, t: f64, y: &[f64], out: &mut [f64]) {
        let Some(&(last, _)) = self.outputs.get(k) else {
            return;
        };
        let len = last as usize + 1;
        with_values(len, |vals| {
            for (i, op) in self.ops[..len].iter().enumerate() {
                vals[i] = op.eval(vals, t, y);
            }
            for (o, (v, _)) in out.iter_mut().zip(&self.outputs[..=k]) {
                *o = vals[*v as usize];
            }
        });
    }

    /// The first output `which` picks that is not finite at (t, y), with
    /// the first operation that made it so; `None` when each is finite (or
    /// the first that is not has no operation to blame).
    pub(crate) fn fault(&self, t: f64, y: &[f64], which: &dyn Fn(usize) -> bool) -> Option<Fault> {
        let mut vals = vec![0.0; self.ops.len()];
        self.run(t, y, &mut vals);
        let &(out, source) = self
            .outputs
            .iter()
            .enumerate()
            .find(|(k, (v, _))| which(*k) && !vals[*v as usize].is_finite())
            .map(|(_, o)| o)?;
        let (at, cause) = cause_of(&self.ops, &vals, out as usize)?;
        Some(Fault {
            source,
            value: vals[out as usize],
            cause,
            written_in: self.origin[at],
        })
    }

    /// A division whose divisor is zero at (t1, y1) or changes sign
    /// between (t0, y0) and (t1, y1), among the operations of the outputs:
    /// the equation then grows without bound there, which a step-size
    /// collapse alone would call a blow-up.
    pub(crate) fn divisor_crossing(
        &self,
        t0: f64,
        y0: &[f64],
        t1: f64,
        y1: &[f64],
    ) -> Option<Fault> {
        let mut a = vec![0.0; self.ops.len()];
        let mut b = vec![0.0; self.ops.len()];
        self.run(t0, y0, &mut a);
        self.run(t1, y1, &mut b);
        self.crossing(&a, &b)
    }

    /// Every operation's value at (t, y), into `vals` (resized to the
    /// program), for [`Program::crossing`] between two points.
    pub(crate) fn tape(&self, t: f64, y: &[f64], vals: &mut Vec<f64>) {
        vals.resize(self.ops.len(), 0.0);
        self.run(t, y, vals);
    }

    /// [`Program::divisor_crossing`] between two points whose tapes are
    /// `a` and `b` ([`Program::tape`]). A step where no divisor anywhere
    /// crosses (nearly every step) costs one pass over the operations.
    pub(crate) fn crossing(&self, a: &[f64], b: &[f64]) -> Option<Fault> {
        let crossed = |k: u32| {
            let (p, q) = (a[k as usize], b[k as usize]);
            p.is_finite() && q.is_finite() && (q == 0.0 || p.signum() != q.signum())
        };
        let any = self.ops.iter().any(|op| match *op {
            Op::Div(_, d) => crossed(d),
            Op::Pow(base, e) => crossed(base) && b[e as usize] < 0.0,
            _ => false,
        });
        if !any {
            return None;
        }
        for (&(out, source), _) in self.outputs.iter().zip(0..) {
            let mut needed = vec![false; out as usize + 1];
            needed[out as usize] = true;
            for i in (0..=out as usize).rev() {
                if !needed[i] {
                    continue;
                }
                let (x, z) = self.ops[i].operands();
                for k in [x, z].into_iter().flatten() {
                    needed[k as usize] = true;
                }
            }
            for (i, op) in self.ops[..=out as usize].iter().enumerate() {
                if !needed[i] {
                    continue;
                }
                let cause = match *op {
                    Op::Div(_, d) if crossed(d) => Cause::DivisionByZero,
                    Op::Pow(base, e) if crossed(base) && b[e as usize] < 0.0 => {
                        Cause::ZeroToNegativePower(b[e as usize])
                    }
                    _ => continue,
                };
                return Some(Fault {
                    source,
                    value: a[out as usize],
                    cause,
                    written_in: self.origin[i],
                });
            }
        }
        None
    }

    /// ∂(output i)/∂(y_j) for every output i and variable j < n at (t, y),
    /// by forward differentiation along the tape, into `jac` (outputs ×
    /// n). A derivative of an operation none of whose operands moves with
    /// y_j is zero, so a singular rule (√ at 0) elsewhere cannot spoil it.
    /// True when every entry is finite.
    fn jacobian(&self, t: f64, y: &[f64], jac: &mut DMatrix<f64>, deps: Option<&Deps>) -> bool {
        let len = self.ops.len();
        let mut vals = vec![0.0; len];
        self.run(t, y, &mut vals);
        let mut dot = vec![0.0; len];
        if let Some(deps) = deps {
            // Only the operations that move with y_j; every other tangent
            // stays 0 (reset after each pass).
            jac.as_mut_slice().fill(0.0);
            let mut finite = true;
            for (j, ops) in deps.ops.iter().enumerate() {
                for &i in ops {
                    let i = i as usize;
                    dot[i] = derivative(&self.ops[i], &vals, &dot, i, j);
                }
                for &(r, k) in &deps.outputs[j] {
                    let d = dot[k as usize];
                    finite &= d.is_finite();
                    jac[(r as usize, j)] = d;
                }
                for &i in ops {
                    dot[i as usize] = 0.0;
                }
            }
            return finite;
        }
        for j in 0..y.len() {
            for (i, op) in self.ops.iter().enumerate() {
                dot[i] = derivative(op, &vals, &dot, i, j);
            }
            for (r, (k, _)) in self.outputs.iter().enumerate() {
                jac[(r, j)] = dot[*k as usize];
            }
        }
        jac.as_slice().iter().all(|v| v.is_finite())
    }
}

/// `d` times the factor `f`, zero when `d` is (so an infinite factor of a
/// term that does not move stays out).
#[inline]
fn times(d: f64, f: f64) -> f64 {
    if d == 0.0 { 0.0 } else { d * f }
}

/// The tangent of operation `i` from its operands' values and tangents.
#[inline]
fn derivative(op: &Op, vals: &[f64], dot: &[f64], i: usize, j: usize) -> f64 {
    let v = |k: u32| vals[k as usize];
    let d = |k: u32| dot[k as usize];
    let me = vals[i];
    match *op {
        Op::Const(_) => 0.0,
        Op::Slot(k) => {
            if k as usize == j {
                1.0
            } else {
                0.0
            }
        }
        Op::Neg(a) => -d(a),
        Op::Add(a, b) => d(a) + d(b),
        Op::Sub(a, b) => d(a) - d(b),
        Op::Mul(a, b) => times(d(a), v(b)) + times(d(b), v(a)),
        Op::Div(a, b) => times(d(a), 1.0 / v(b)) - times(d(b), me / v(b)),
        Op::Pow(a, b) => {
            let (x, e) = (v(a), v(b));
            let by_base = if d(a) == 0.0 {
                0.0
            } else {
                d(a) * e * x.powf(e - 1.0)
            };
            by_base + times(d(b), me * x.ln())
        }
        Op::Call1(f, a) => {
            let da = d(a);
            if da == 0.0 {
                return 0.0;
            }
            let x = v(a);
            da * match f {
                Fun::Sin => x.cos(),
                Fun::Cos => -x.sin(),
                Fun::Tan => 1.0 + me * me,
                Fun::Asin => 1.0 / (1.0 - x * x).sqrt(),
                Fun::Acos => -1.0 / (1.0 - x * x).sqrt(),
                Fun::Atan => 1.0 / (1.0 + x * x),
                Fun::Sinh => x.cosh(),
                Fun::Cosh => x.sinh(),
                Fun::Tanh => 1.0 - me * me,
                Fun::Exp => me,
                Fun::Ln => 1.0 / x,
                Fun::Log10 => 1.0 / (x * std::f64::consts::LN_10),
                Fun::Sqrt => 0.5 / me,
                Fun::Abs => Fun::Sign.apply1(x),
                Fun::Sign => 0.0,
                Fun::Atan2 | Fun::Min | Fun::Max => f64::NAN,
            }
        }
        Op::Call2(f, a, b) => {
            let (x, z) = (v(a), v(b));
            match f {
                // atan2(y = x, x = z): (z dy − y dz) / (y² + z²).
                Fun::Atan2 => {
                    let r2 = x * x + z * z;
                    times(d(a), z / r2) - times(d(b), x / r2)
                }
                // The branch the value came from.
                Fun::Min | Fun::Max => {
                    if me == x {
                        d(a)
                    } else {
                        d(b)
                    }
                }
                _ => f64::NAN,
            }
        }
    }
}

/// Builds one program: each observable it needs compiled once, before the
/// expressions that use it.
struct Builder<'a> {
    scene: &'a SystemScene,
    n: usize,
    prog: Program,
    slots: Vec<Option<u32>>,
    observables: Vec<Option<u32>>,
    source: Source,
}

impl<'a> Builder<'a> {
    fn new(scene: &'a SystemScene) -> Builder<'a> {
        let n = scene.variables.len();
        Builder {
            scene,
            n,
            prog: Program::default(),
            slots: vec![None; n + 1],
            observables: vec![None; scene.observables.len()],
            source: Source::Equation(0),
        }
    }

    fn push(&mut self, op: Op) -> Result<u32, CompileError> {
        // Operations of numbers are done now, unless the result is not
        // finite (then the run names it, with its cause).
        let (a, b) = op.operands();
        let konst = |k: Option<u32>| match k.map(|k| self.prog.ops[k as usize]) {
            None => true,
            Some(Op::Const(_)) => true,
            Some(_) => false,
        };
        let op = if a.is_some() && konst(a) && konst(b) {
            let value = op.eval(&self.const_values(a, b), 0.0, &[]);
            if value.is_finite() {
                // The operands were pushed just before and nothing else
                // reads a number: they go.
                for k in [b, a].into_iter().flatten() {
                    if k as usize + 1 == self.prog.ops.len() {
                        self.prog.ops.pop();
                        self.prog.origin.pop();
                    }
                }
                Op::Const(value)
            } else {
                op
            }
        } else {
            op
        };
        if self.prog.ops.len() >= MAX_PROGRAM {
            return Err(CompileError {
                source: Some(self.source),
                message: format!(
                    "{} compiles to more than {MAX_PROGRAM} operations (with the observables it uses)",
                    self.source.describe(self.scene)
                ),
            });
        }
        self.prog.ops.push(op);
        self.prog.origin.push(self.source);
        Ok((self.prog.ops.len() - 1) as u32)
    }

    /// A value table where the constant operands sit at their indices.
    fn const_values(&self, a: Option<u32>, b: Option<u32>) -> Vec<f64> {
        let top = a.max(b).map_or(0, |k| k as usize + 1);
        let mut vals = vec![0.0; top];
        for k in [a, b].into_iter().flatten() {
            if let Op::Const(c) = self.prog.ops[k as usize] {
                vals[k as usize] = c;
            }
        }
        vals
    }

    fn slot(&mut self, k: usize) -> Result<u32, CompileError> {
        if let Some(v) = self.slots[k] {
            return Ok(v);
        }
        let v = self.push(Op::Slot(k as u32))?;
        self.slots[k] = Some(v);
        Ok(v)
    }

    fn name(&mut self, name: &str) -> Result<u32, CompileError> {
        match name {
            "pi" => return self.push(Op::Const(std::f64::consts::PI)),
            "e" => return self.push(Op::Const(std::f64::consts::E)),
            "t" => return self.slot(self.n),
            _ => {}
        }
        if let Some(k) = self.scene.variables.iter().position(|v| v == name) {
            return self.slot(k);
        }
        if let Some((_, v)) = self.scene.params.iter().find(|(p, _)| p == name) {
            return self.push(Op::Const(*v));
        }
        if let Some(k) = self.scene.observables.iter().position(|(o, _)| o == name)
            && let Some(v) = self.observables[k]
        {
            return Ok(v);
        }
        Err(CompileError {
            source: Some(self.source),
            message: format!(
                "{} uses `{name}`, which is not defined before it",
                self.source.describe(self.scene)
            ),
        })
    }

    /// Compiles `node`; recursion is bounded by [`expr::MAX_DEPTH`].
    fn expr(&mut self, node: &Node) -> Result<u32, CompileError> {
        Ok(match node {
            Node::Num(v) => self.push(Op::Const(*v))?,
            Node::Name(n, _) => self.name(n)?,
            Node::Neg(a) => {
                let a = self.expr(a)?;
                self.push(Op::Neg(a))?
            }
            // `x^2` is `x*x`: exact (the correctly rounded square, where
            // `powf` may be off in the last bit) and several times faster,
            // in the right-hand side and in the Jacobian built from it.
            Node::Bin('^', a, b) if matches!(**b, Node::Num(e) if e == 2.0) => {
                let a = self.expr(a)?;
                self.push(Op::Mul(a, a))?
            }
            Node::Bin(op, a, b) => {
                let a = self.expr(a)?;
                let b = self.expr(b)?;
                self.push(match op {
                    '+' => Op::Add(a, b),
                    '-' => Op::Sub(a, b),
                    '*' => Op::Mul(a, b),
                    '/' => Op::Div(a, b),
                    _ => Op::Pow(a, b),
                })?
            }
            Node::Call(f, args) => {
                let fun = Fun::of(f).ok_or_else(|| CompileError {
                    source: Some(self.source),
                    message: format!("`{f}` is not a function"),
                })?;
                match args.as_slice() {
                    [a] => {
                        let a = self.expr(a)?;
                        self.push(Op::Call1(fun, a))?
                    }
                    [a, b] => {
                        let a = self.expr(a)?;
                        let b = self.expr(b)?;
                        self.push(Op::Call2(fun, a, b))?
                    }
                    _ => {
                        return Err(CompileError {
                            source: Some(self.source),
                            message: format!("`{f}` takes {} arguments", args.len()),
                        });
                    }
                }
            }
        })
    }

    /// Compiles the observables `nodes` need (those they use, and those
    /// these use, in order), each once.
    fn observables_for(&mut self, parsed: &Parsed, nodes: &[&Node]) -> Result<(), CompileError> {
        let m = parsed.observables.len();
        let mut needed = vec![false; m];
        for node in nodes {
            for k in parsed.uses(node) {
                needed[k] = true;
            }
        }
        // An observable uses only earlier ones: one pass downwards closes.
        for k in (0..m).rev() {
            if needed[k] {
                for &j in &parsed.deps[k] {
                    needed[j] = true;
                }
            }
        }
        let before = self.source;
        for (k, &need) in needed.iter().enumerate() {
            if need && self.observables[k].is_none() {
                self.source = Source::Observable(k);
                let v = self.expr(&parsed.observables[k])?;
                self.observables[k] = Some(v);
            }
        }
        self.source = before;
        Ok(())
    }

    /// Compiles each `(source, node)` as an output.
    fn outputs(
        mut self,
        parsed: &Parsed,
        exprs: &[(Source, &Node)],
    ) -> Result<Program, CompileError> {
        let nodes: Vec<&Node> = exprs.iter().map(|(_, n)| *n).collect();
        self.observables_for(parsed, &nodes)?;
        for (source, node) in exprs {
            self.source = *source;
            let v = self.expr(node)?;
            self.prog.outputs.push((v, *source));
        }
        Ok(self.prog)
    }
}

/// One formula's tree compiled over `vars` (each read from the state
/// vector, in this order; the name `t` reads the time argument) into a
/// program with one output, by the same builder as a scene's expressions
/// (a formula answer, [`super::equiv`]).
pub(crate) fn formula_program(node: &Node, vars: &[String]) -> Result<Program, CompileError> {
    let scene = SystemScene::one_formula(
        vars.to_vec(),
        Vec::new(),
        ("the formula".to_string(), String::new()),
    );
    let mut b = Builder::new(&scene);
    b.source = Source::Observable(0);
    let v = b.expr(node)?;
    b.prog.outputs.push((v, Source::Observable(0)));
    Ok(b.prog)
}

/// The parsed expressions of a scene, and which observables each
/// observable uses.
struct Parsed {
    equations: Vec<Node>,
    observables: Vec<Node>,
    marks: Vec<Node>,
    /// Observables (by index) each observable uses directly.
    deps: Vec<Vec<usize>>,
    names: Vec<String>,
}

impl Parsed {
    fn new(scene: &SystemScene) -> Result<Parsed, CompileError> {
        let parse = |source: Source, text: &str| {
            expr::parse(text).map_err(|e| CompileError {
                source: Some(source),
                message: format!("{}: {e}", source.describe(scene)),
            })
        };
        let equations = scene
            .equations
            .iter()
            .enumerate()
            .map(|(k, e)| parse(Source::Equation(k), e))
            .collect::<Result<Vec<_>, _>>()?;
        let observables = scene
            .observables
            .iter()
            .enumerate()
            .map(|(k, (_, e))| parse(Source::Observable(k), e))
            .collect::<Result<Vec<_>, _>>()?;
        let marks = scene
            .sketch
            .iter()
            .flat_map(|m| m.exprs())
            .enumerate()
            .map(|(k, e)| parse(Source::Mark(k), e))
            .collect::<Result<Vec<_>, _>>()?;
        let names: Vec<String> = scene.observables.iter().map(|(o, _)| o.clone()).collect();
        let mut parsed = Parsed {
            equations,
            observables,
            marks,
            deps: Vec::new(),
            names,
        };
        parsed.deps = parsed.observables.iter().map(|o| parsed.uses(o)).collect();
        Ok(parsed)
    }

    /// The observables `node` names.
    fn uses(&self, node: &Node) -> Vec<usize> {
        let mut names = Vec::new();
        expr::names(node, &mut names);
        names
            .iter()
            .filter_map(|n| self.names.iter().position(|o| o == n))
            .collect()
    }
}

/// What a step of a scene costs, in operations of its programs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Cost {
    /// Variables.
    pub n: usize,
    /// Operations of one evaluation of the right-hand side.
    pub rhs: usize,
    /// Of all the observables, and of the sketch's expressions.
    pub observables: usize,
    pub marks: usize,
    /// Operations of one exact Jacobian (the passes over the operations
    /// that read each variable; at most `rhs` × `n`).
    pub jacobian: usize,
    /// Flops of one LU factorisation (dense n³, or the band's or the
    /// sparse factors' as [`LuPlan::choose`] picks).
    pub lu: usize,
}

/// Right-hand side evaluations of one step of the costliest method (DOP853's
/// twelve stages and the new point; Radau's Newton iterations are fewer).
pub(crate) const EVALS_PER_STEP: usize = 13;

/// Dense-output points per accepted step of an adaptive method (RK4's
/// small fixed steps are sampled at their ends): the run samples its
/// observables and sketch there ([`crate::scene::system`]), and the
/// cost of a step counts them.
pub(crate) const POINTS_PER_STEP: usize = 16;

impl Cost {
    /// Operations one step may run: the stages, the Jacobian (one pass per
    /// variable over the operations that read it), its LU decomposition
    /// (about n³, or the band's n·kl·(kl + ku), or the sparse factors'), and the
    /// samples of every observable and sketch expression
    /// ([`POINTS_PER_STEP`] a step).
    pub(crate) fn per_step(&self) -> f64 {
        let points = POINTS_PER_STEP as f64;
        (self.rhs as f64) * EVALS_PER_STEP as f64
            + self.jacobian as f64
            + self.lu as f64
            + points * (self.observables + self.marks + self.n) as f64
    }
}

/// A system scene compiled for the solvers.
#[derive(Debug, Clone)]
pub struct System {
    n: usize,
    rhs: Program,
    observables: Program,
    marks: Program,
    /// The exact Jacobian is used (implicit methods); else differences.
    jacobian: bool,
    /// The operations each variable's pass of the Jacobian runs.
    deps: Option<Deps>,
    /// The positions and momenta the scene declares, by index.
    split: Option<Split>,
    /// The fixed sums the equations keep, proven from them
    /// ([`super::sums`]).
    sums: Vec<Vec<f64>>,
}

impl System {
    /// Compiles the right-hand side, observables and sketch; with
    /// `jacobian`, the solvers get the exact derivative of the equations.
    pub fn compile(scene: &SystemScene, jacobian: bool) -> Result<System, CompileError> {
        let parsed = Parsed::new(scene)?;
        let equations: Vec<(Source, &Node)> = parsed
            .equations
            .iter()
            .enumerate()
            .map(|(k, e)| (Source::Equation(k), e))
            .collect();
        let rhs = Builder::new(scene).outputs(&parsed, &equations)?;
        let observables: Vec<(Source, &Node)> = parsed
            .observables
            .iter()
            .enumerate()
            .map(|(k, e)| (Source::Observable(k), e))
            .collect();
        // Each observable is its own output, and the output of a later one
        // reads the earlier ones' values.
        let mut b = Builder::new(scene);
        for (source, node) in &observables {
            b.source = *source;
            let v = b.expr(node)?;
            if let Source::Observable(k) = source {
                b.observables[*k] = Some(v);
            }
            b.prog.outputs.push((v, *source));
        }
        let observables = b.prog;
        let marks: Vec<(Source, &Node)> = parsed
            .marks
            .iter()
            .enumerate()
            .map(|(k, e)| (Source::Mark(k), e))
            .collect();
        let marks = Builder::new(scene).outputs(&parsed, &marks)?;
        let index = |name: &String| scene.variables.iter().position(|v| v == name);
        let split = scene.hamiltonian.as_ref().and_then(|h| {
            Some(Split {
                q: h.q.iter().map(index).collect::<Option<_>>()?,
                p: h.p.iter().map(index).collect::<Option<_>>()?,
            })
        });
        let n = scene.variables.len();
        let deps = Deps::of(&rhs, n);
        let sums = super::sums::fixed_sums(scene, &parsed.equations, &parsed.observables);
        Ok(System {
            n,
            deps,
            rhs,
            observables,
            marks,
            jacobian,
            split,
            sums,
        })
    }

    /// Why the scene's `hamiltonian` is not a separable split of its
    /// equations, if it is not: a variable named twice or not at all, or a
    /// position whose rate reads a position (or a momentum whose rate
    /// reads a momentum), after observables are expanded.
    pub fn hamiltonian_error(&self, scene: &SystemScene) -> Option<String> {
        let h = scene.hamiltonian.as_ref()?;
        let Some(split) = &self.split else {
            return Some("`hamiltonian` names a quantity that is not a variable".into());
        };
        if h.q.len() != h.p.len() {
            return Some(format!(
                "`hamiltonian` declares {} positions and {} momenta; a position needs its momentum",
                h.q.len(),
                h.p.len()
            ));
        }
        let mut seen = vec![0u8; self.n];
        for &i in split.q.iter().chain(&split.p) {
            seen[i] += 1;
        }
        if let Some(i) = seen.iter().position(|&c| c != 1) {
            return Some(format!(
                "`hamiltonian` names `{}` {}; it must name every variable once, in `q` or in `p`",
                scene.variables[i],
                if seen[i] == 0 { "nowhere" } else { "twice" }
            ));
        }
        let reads = self.rhs.reads(self.n);
        for (own, what, other) in [
            (&split.q, "position", "momenta"),
            (&split.p, "momentum", "positions"),
        ] {
            for &i in own {
                if let Some(&j) = own.iter().find(|&&j| reads[i][j]) {
                    return Some(format!(
                        "the rate of the {what} `{}` reads the {what} `{}`: not a separable Hamiltonian (the rate of each {what} may read only {other})",
                        scene.variables[i], scene.variables[j]
                    ));
                }
            }
        }
        None
    }

    pub fn cost(&self) -> Cost {
        let n = self.n;
        let lu = match LuPlan::choose(n, self.sparsity().as_deref()) {
            LuPlan::Dense => n * n * n,
            plan => plan.flops(n) as usize,
        };
        Cost {
            n,
            rhs: self.rhs.len(),
            observables: self.observables.len(),
            marks: self.marks.len(),
            jacobian: match &self.deps {
                Some(d) => d.work(),
                None => self.rhs.len() * n,
            },
            lu,
        }
    }

    /// Observable `k` at (t, y).
    pub fn observable(&self, k: usize, t: f64, y: &[f64]) -> f64 {
        self.observables.eval_one(k, t, y)
    }

    /// Every observable at (t, y), into `out`.
    pub fn observables_into(&self, t: f64, y: &[f64], out: &mut [f64]) {
        self.observables.eval_into(t, y, out);
    }

    pub fn observable_count(&self) -> usize {
        self.observables.outputs.len()
    }

    /// Sketch coordinate `k` (the sketch's expressions in order) at (t, y).
    pub fn mark(&self, k: usize, t: f64, y: &[f64]) -> f64 {
        self.marks.eval_one(k, t, y)
    }

    /// Every sketch coordinate at (t, y), into `out`.
    pub(crate) fn marks_into(&self, t: f64, y: &[f64], out: &mut [f64]) {
        self.marks.eval_into(t, y, out);
    }

    pub(crate) fn mark_count(&self) -> usize {
        self.marks.outputs.len()
    }

    /// Observables `0..=k` at (t, y), into `out[..=k]`.
    pub(crate) fn observables_upto(&self, k: usize, t: f64, y: &[f64], out: &mut [f64]) {
        self.observables.eval_upto(k, t, y, out);
    }

    /// The programs, for the failure path ([`Program::fault`]).
    pub fn equations(&self) -> &Program {
        &self.rhs
    }
    pub(crate) fn observable_program(&self) -> &Program {
        &self.observables
    }
    pub(crate) fn mark_program(&self) -> &Program {
        &self.marks
    }

    /// Why an equation is not finite at (t, y), if one is not.
    pub fn rhs_fault(&self, t: f64, y: &[f64]) -> Option<Fault> {
        self.rhs.fault(t, y, &|_| true)
    }

    /// Why an observable is not finite at (t, y), if one is not.
    pub fn observable_fault(&self, t: f64, y: &[f64]) -> Option<Fault> {
        self.observables.fault(t, y, &|_| true)
    }
}

impl OdeSystem for System {
    fn dim(&self) -> usize {
        self.n
    }

    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        self.rhs.eval_into(t, y, dy);
    }

    fn split(&self) -> Option<Split> {
        self.split.clone()
    }

    fn jacobian(&self, t: f64, y: &[f64], jac: &mut DMatrix<f64>) {
        let n = self.n;
        if jac.nrows() != n || jac.ncols() != n {
            *jac = DMatrix::zeros(n, n);
        }
        if self.jacobian && self.rhs.jacobian(t, y, jac, self.deps.as_ref()) {
            return;
        }
        // At a point where a derivative is singular (√ at 0), differences
        // (one-sided where f is not finite on one side) still give a matrix.
        crate::solvers::ode::finite_difference_jacobian(self, t, y, jac);
    }

    fn fixed_sums(&self, _t: f64, _y: &[f64]) -> Vec<Vec<f64>> {
        self.sums.clone()
    }

    fn sparsity(&self) -> Option<Vec<Vec<usize>>> {
        let deps = self.deps.as_ref()?;
        let mut rows = vec![Vec::new(); self.n];
        for (j, outs) in deps.outputs.iter().enumerate() {
            for &(r, _) in outs {
                rows[r as usize].push(j);
            }
        }
        Some(rows)
    }
}

/// A balanced sum of 2^levels `x`s, deep only `levels`: the widest
/// expression of a depth, which tests of the limits (here and in the app)
/// build their too-long programs from.
pub fn balanced_sum(levels: usize) -> String {
    if levels == 0 {
        "x".to_string()
    } else {
        let half = balanced_sum(levels - 1);
        format!("({half})+({half})")
    }
}

#[cfg(test)]
pub(crate) mod tests;
