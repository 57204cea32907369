//! The fixed sums of a system's equations, proven from their expressions:
//! linear combinations c·y whose rate c·f is zero for every t and y, as
//! an identity of the equations as written, not a reading of them at some
//! points.
//!
//! Each equation is expanded into a sum of terms, each an exact rational
//! coefficient (every number and parameter read as the exact value of its
//! double) times a product of atoms: a variable, `t`, or a piece the
//! expansion does not open (a function call, a power that is not a small
//! whole number, a division by something that is not a constant or a
//! single term), keyed by how it is written. Observables are expanded where
//! they are used. c·f = 0 holds identically when, for every product, the
//! coefficients weighted by c add up to exactly 0: then it holds whatever
//! values the atoms take. So the sums are the null space of the matrix
//! product × equation of coefficients, found by exact elimination over the
//! rationals.
//!
//! That is sound, never guessed: a forcing that switches on later
//! (`max(t - 15, 0)`, `exp(-(t - 20)^2)`), a term on one side of a sign
//! (`abs(x)`), a leak far smaller than the exchange beside it
//! (`k*a - k*b - D*b` with D/k = 1e-12) each leave a product whose
//! coefficients do not cancel, and no sum is found. It may miss a sum that
//! needs an identity beyond expanding (sin² + cos² = 1), or one whose
//! equations write the same piece two ways (`x*y` and `y*x` inside a
//! call): then nothing is held, as before.
//!
//! Work is bounded: at most [`MAX_TERMS`] terms in any expansion and
//! [`MAX_PRODUCT`] term pairs in a product, else no sums; systems of more
//! than [`crate::solvers::ode::fixed::MAX_DIM`] variables are not searched.

use std::collections::{BTreeMap, HashMap};

use num_rational::BigRational;
use num_traits::{One, Signed, ToPrimitive, Zero};

use super::expr::Node;
use super::spec::SystemScene;

/// The most terms an expansion may have.
const MAX_TERMS: usize = 2048;
/// The most term pairs one product may multiply.
const MAX_PRODUCT: usize = 16384;
/// The most terms all the additions and products of a scene may touch.
const MAX_WORK: usize = 1 << 20;
/// The most products × variables² the elimination may take on (its work
/// is about that many operations).
const MAX_ELIMINATION: usize = 1 << 20;
/// The most bits a number of the elimination may grow to.
const MAX_BITS: u64 = 4096;

/// Whole powers up to this are expanded (`(a + b)^3`); larger ones are
/// atoms.
const MAX_POWER: i64 = 6;

/// A product of atoms with their powers, sorted by atom.
type Monomial = Vec<(u32, i32)>;
/// A sum of terms.
type Poly = BTreeMap<Monomial, BigRational>;

/// Why an expansion gave up (the caller then finds no sums).
struct TooBig;

struct Expander<'a> {
    scene: &'a SystemScene,
    /// Each observable's expansion, once made.
    expanded: Vec<Option<Poly>>,
    /// Atoms that are not variables or `t`, by how they are written.
    atoms: HashMap<String, u32>,
    /// Terms touched so far, against [`MAX_WORK`].
    work: usize,
}

fn constant(v: BigRational) -> Poly {
    let mut p = Poly::new();
    if !v.is_zero() {
        p.insert(Vec::new(), v);
    }
    p
}

fn number(v: f64) -> Result<Poly, TooBig> {
    BigRational::from_float(v).map(constant).ok_or(TooBig)
}

fn add(work: &mut usize, mut a: Poly, b: &Poly, sign: i32) -> Result<Poly, TooBig> {
    *work += a.len() + b.len();
    if *work > MAX_WORK {
        return Err(TooBig);
    }
    for (m, c) in b {
        let c = if sign < 0 { -c.clone() } else { c.clone() };
        let sum = match a.remove(m) {
            Some(old) => old + c,
            None => c,
        };
        if !sum.is_zero() {
            a.insert(m.clone(), sum);
        }
    }
    if a.len() > MAX_TERMS {
        return Err(TooBig);
    }
    Ok(a)
}

fn times_monomial(a: &Monomial, b: &Monomial) -> Monomial {
    let mut out: Monomial = a.clone();
    for &(atom, p) in b {
        match out.iter_mut().find(|(x, _)| *x == atom) {
            Some(entry) => entry.1 += p,
            None => out.push((atom, p)),
        }
    }
    out.retain(|(_, p)| *p != 0);
    out.sort_unstable();
    out
}

fn mul(work: &mut usize, a: &Poly, b: &Poly) -> Result<Poly, TooBig> {
    let pairs = a.len().saturating_mul(b.len());
    *work += pairs;
    if pairs > MAX_PRODUCT || *work > MAX_WORK {
        return Err(TooBig);
    }
    let mut out = Poly::new();
    for (ma, ca) in a {
        for (mb, cb) in b {
            let m = times_monomial(ma, mb);
            let c = ca * cb;
            let sum = match out.remove(&m) {
                Some(old) => old + c,
                None => c,
            };
            if !sum.is_zero() {
                out.insert(m, sum);
            }
        }
    }
    if out.len() > MAX_TERMS {
        return Err(TooBig);
    }
    Ok(out)
}

/// The one term of `p`, if it has exactly one.
fn single(p: &Poly) -> Option<(&Monomial, &BigRational)> {
    let mut it = p.iter();
    let first = it.next()?;
    it.next().is_none().then_some(first)
}

/// How `node` is written, fully parenthesised: the key of an atom.
fn written(node: &Node) -> String {
    match node {
        Node::Num(v) => format!("{v:e}"),
        Node::Name(n, _) => n.clone(),
        Node::Neg(a) => format!("(-{})", written(a)),
        Node::Bin(op, a, b) => format!("({}{op}{})", written(a), written(b)),
        Node::Call(f, args) => {
            let args: Vec<String> = args.iter().map(written).collect();
            format!("{f}({})", args.join(","))
        }
    }
}

impl Expander<'_> {
    fn atom(&mut self, node: &Node, power: i32) -> Poly {
        let key = written(node);
        let next = (self.scene.variables.len() + 1 + self.atoms.len()) as u32;
        let id = *self.atoms.entry(key).or_insert(next);
        let mut p = Poly::new();
        p.insert(vec![(id, power)], BigRational::one());
        p
    }

    fn name(&mut self, name: &str) -> Result<Poly, TooBig> {
        let n = self.scene.variables.len();
        match name {
            "pi" => return number(std::f64::consts::PI),
            "e" => return number(std::f64::consts::E),
            "t" => {
                let mut p = Poly::new();
                p.insert(vec![(n as u32, 1)], BigRational::one());
                return Ok(p);
            }
            _ => {}
        }
        if let Some(k) = self.scene.variables.iter().position(|v| v == name) {
            let mut p = Poly::new();
            p.insert(vec![(k as u32, 1)], BigRational::one());
            return Ok(p);
        }
        if let Some((_, v)) = self.scene.params.iter().find(|(p, _)| p == name) {
            return number(*v);
        }
        // Observables are expanded in order before the equations (each uses
        // only the ones before it), so a name finds its own made: no
        // recursion through a chain of them.
        if let Some(k) = self.scene.observables.iter().position(|(o, _)| o == name) {
            return self.expanded.get(k).cloned().flatten().ok_or(TooBig);
        }
        Err(TooBig)
    }

    fn expand(&mut self, node: &Node) -> Result<Poly, TooBig> {
        Ok(match node {
            Node::Num(v) => number(*v)?,
            Node::Name(n, _) => self.name(n)?,
            Node::Neg(a) => {
                let a = self.expand(a)?;
                add(&mut self.work, Poly::new(), &a, -1)?
            }
            Node::Bin(op @ ('+' | '-'), a, b) => {
                let (a, b) = (self.expand(a)?, self.expand(b)?);
                add(&mut self.work, a, &b, if *op == '+' { 1 } else { -1 })?
            }
            Node::Bin('*', a, b) => {
                let (a, b) = (self.expand(a)?, self.expand(b)?);
                mul(&mut self.work, &a, &b)?
            }
            Node::Bin('/', a, b) => {
                let num = self.expand(a)?;
                let den = self.expand(b)?;
                match single(&den) {
                    // A constant or a single term: its inverse is a term.
                    Some((m, c)) => {
                        let inv: Monomial = m.iter().map(|&(x, p)| (x, -p)).collect();
                        let mut p = Poly::new();
                        p.insert(inv, c.recip());
                        mul(&mut self.work, &num, &p)?
                    }
                    None if den.is_empty() => return Err(TooBig),
                    None => {
                        let inv = self.atom(b, -1);
                        mul(&mut self.work, &num, &inv)?
                    }
                }
            }
            Node::Bin(_, a, b) => {
                let whole = match **b {
                    Node::Num(e) if e.fract() == 0.0 && (1.0..=MAX_POWER as f64).contains(&e) => {
                        Some(e as i64)
                    }
                    _ => None,
                };
                match whole {
                    Some(k) => {
                        let base = self.expand(a)?;
                        let mut p = constant(BigRational::one());
                        for _ in 0..k {
                            p = mul(&mut self.work, &p, &base)?;
                        }
                        p
                    }
                    None => self.atom(node, 1),
                }
            }
            Node::Call(..) => self.atom(node, 1),
        })
    }
}

/// The fixed sums of `scene`'s equations (parsed: `equations`, and the
/// observables they may use), each a row c over the variables, scaled to
/// whole numbers where they are small ones (`[0, 1, -1, -1]`) and else to
/// a largest coefficient of 1; in reduced row-echelon form. Empty where
/// there are none, the system is larger than
/// [`crate::solvers::ode::fixed::MAX_DIM`] or an expansion is too large.
pub fn fixed_sums(scene: &SystemScene, equations: &[Node], observables: &[Node]) -> Vec<Vec<f64>> {
    let n = scene.variables.len();
    if !(2..=crate::solvers::ode::fixed::MAX_DIM).contains(&n) || equations.len() != n {
        return Vec::new();
    }
    let mut ex = Expander {
        scene,
        expanded: vec![None; scene.observables.len()],
        atoms: HashMap::new(),
        work: 0,
    };
    for (k, node) in observables.iter().enumerate().take(scene.observables.len()) {
        // One too large is only a loss where it is used.
        ex.expanded[k] = ex.expand(node).ok();
    }
    let mut polys = Vec::with_capacity(n);
    for e in equations {
        match ex.expand(e) {
            Ok(p) => polys.push(p),
            Err(TooBig) => return Vec::new(),
        }
    }
    // The matrix product × equation.
    let mut rows: BTreeMap<&Monomial, Vec<BigRational>> = BTreeMap::new();
    for (i, p) in polys.iter().enumerate() {
        for (m, c) in p {
            rows.entry(m)
                .or_insert_with(|| vec![BigRational::zero(); n])[i] = c.clone();
        }
    }
    if rows.len().saturating_mul(n * n) > MAX_ELIMINATION {
        return Vec::new();
    }
    let matrix: Vec<Vec<BigRational>> = rows.into_values().collect();
    let Some(null) = null_space(matrix, n) else {
        return Vec::new();
    };
    null.into_iter().map(|row| scaled(&row)).collect()
}

/// Whether `x` has grown past [`MAX_BITS`].
fn too_long(x: &BigRational) -> bool {
    x.numer().bits() + x.denom().bits() > MAX_BITS
}

/// The reduced row-echelon form of `m` (rows of length n), exactly; with
/// the pivot columns. `None` if a number grows past [`MAX_BITS`].
fn echelon(mut m: Vec<Vec<BigRational>>, n: usize) -> Option<(Vec<Vec<BigRational>>, Vec<usize>)> {
    let mut pivots = Vec::new();
    let mut r = 0;
    for col in 0..n {
        let Some(k) = (r..m.len()).find(|&k| !m[k][col].is_zero()) else {
            continue;
        };
        m.swap(r, k);
        let p = m[r][col].clone();
        for x in m[r].iter_mut() {
            *x = &*x / &p;
        }
        if m[r].iter().any(too_long) {
            return None;
        }
        let pivot_row = m[r].clone();
        for (k, row) in m.iter_mut().enumerate() {
            if k != r && !row[col].is_zero() {
                let f = row[col].clone();
                for (x, y) in row.iter_mut().zip(&pivot_row) {
                    *x = &*x - &f * y;
                }
            }
        }
        pivots.push(col);
        r += 1;
        if r == m.len() {
            break;
        }
    }
    m.truncate(r);
    Some((m, pivots))
}

/// A basis of {c : m·c = 0}, in reduced row-echelon form; `None` if the
/// numbers grow too long.
fn null_space(m: Vec<Vec<BigRational>>, n: usize) -> Option<Vec<Vec<BigRational>>> {
    let (r, pivots) = echelon(m, n)?;
    let free: Vec<usize> = (0..n).filter(|c| !pivots.contains(c)).collect();
    let basis: Vec<Vec<BigRational>> = free
        .iter()
        .map(|&f| {
            let mut v = vec![BigRational::zero(); n];
            v[f] = BigRational::one();
            for (row, &p) in r.iter().zip(&pivots) {
                v[p] = -row[f].clone();
            }
            v
        })
        .collect();
    if basis.is_empty() {
        return Some(basis);
    }
    echelon(basis, n).map(|(b, _)| b)
}

/// A row as doubles: whole numbers when its entries are small fractions
/// (denominators and the whole numbers they make at most 1e6), its first
/// non-zero entry positive; else scaled to a largest entry of 1.
fn scaled(row: &[BigRational]) -> Vec<f64> {
    use num_integer::Integer;
    let lcm = row
        .iter()
        .filter(|x| !x.is_zero())
        .fold(num_bigint::BigInt::one(), |l, x| l.lcm(x.denom()));
    let whole: Vec<num_bigint::BigInt> = row.iter().map(|x| (x * &lcm).to_integer()).collect();
    let gcd = whole
        .iter()
        .fold(num_bigint::BigInt::zero(), |g, x| g.gcd(x));
    let sign = match row.iter().find(|x| !x.is_zero()) {
        Some(x) if x.is_negative() => -1.0,
        _ => 1.0,
    };
    let small = !gcd.is_zero()
        && whole
            .iter()
            .all(|x| (x / &gcd).abs() <= num_bigint::BigInt::from(1_000_000));
    if small {
        return whole
            .iter()
            .map(|x| sign * (x / &gcd).to_f64().unwrap_or(f64::NAN))
            .collect();
    }
    let v: Vec<f64> = row.iter().map(|x| x.to_f64().unwrap_or(0.0)).collect();
    let big = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    v.iter().map(|x| sign * x / big).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system::compile::tests::pendulum;

    fn scene(variables: &[&str], equations: &[&str], params: &[(&str, f64)]) -> SystemScene {
        SystemScene {
            variables: variables.iter().map(|s| s.to_string()).collect(),
            initial: vec![1.0; variables.len()],
            params: params.iter().map(|(n, v)| (n.to_string(), *v)).collect(),
            equations: equations.iter().map(|s| s.to_string()).collect(),
            observables: Vec::new(),
            conserved: Vec::new(),
            sketch: Vec::new(),
            ..pendulum()
        }
    }

    fn sums(s: &SystemScene) -> Vec<Vec<f64>> {
        let eqs: Vec<Node> = s
            .equations
            .iter()
            .map(|e| super::super::expr::parse(e).unwrap())
            .collect();
        let obs: Vec<Node> = s
            .observables
            .iter()
            .map(|(_, e)| super::super::expr::parse(e).unwrap())
            .collect();
        fixed_sums(s, &eqs, &obs)
    }

    /// E5 keeps y2 − y3 − y4, Robertson y1 + y2 + y3, 3A → B keeps
    /// A + 3B: each as whole numbers.
    #[test]
    fn the_sums_chemistry_keeps_are_found_in_whole_numbers() {
        let e5 = scene(
            &["y1", "y2", "y3", "y4"],
            &[
                "-A*y1 - B*y1*y3",
                "A*y1 - M*C*y2*y3",
                "A*y1 - B*y1*y3 - M*C*y2*y3 + C*y4",
                "B*y1*y3 - C*y4",
            ],
            &[("A", 7.89e-10), ("B", 1.1e7), ("C", 1.13e3), ("M", 1e6)],
        );
        assert_eq!(sums(&e5), vec![vec![0.0, 1.0, -1.0, -1.0]]);
        let rob = scene(
            &["y1", "y2", "y3"],
            &[
                "-0.04*y1 + 1e4*y2*y3",
                "0.04*y1 - 1e4*y2*y3 - 3e7*y2^2",
                "3e7*y2^2",
            ],
            &[],
        );
        assert_eq!(sums(&rob), vec![vec![1.0, 1.0, 1.0]]);
        let three = scene(&["A", "B"], &["-3*k*A^3", "k*A^3"], &[("k", 0.7)]);
        assert_eq!(sums(&three), vec![vec![1.0, 3.0]]);
        // Two at once, and through an observable.
        let mut two = scene(
            &["a", "b", "c", "d", "e"],
            &["-2*a", "2*a - r", "r", "-d^2 + e/2", "d*d - 0.5*e"],
            &[],
        );
        two.observables = vec![("r".into(), "3*b".into())];
        assert_eq!(
            sums(&two),
            vec![vec![1.0, 1.0, 1.0, 0.0, 0.0], vec![0.0, 0.0, 0.0, 1.0, 1.0]]
        );
    }

    /// What holds only near the start, on one side of a sign, or up to a
    /// leak is no fixed sum (each of these was held by a search that read
    /// the equations at points near the start, and printed a wrong answer).
    #[test]
    fn what_holds_only_somewhere_or_nearly_is_no_sum() {
        for (vars, eqs, params) in [
            (&["x", "y"][..], &["-x + exp(-(t-20)^2)", "x"][..], &[][..]),
            (&["x", "y"], &["-x + max(t-15,0)", "x"], &[]),
            (&["x", "y"], &["1", "-1 + max(x-5,0)"], &[]),
            (&["x", "v", "y"], &["v", "-x", "abs(x)-x"], &[]),
            (&["x", "y"], &["-1", "1-sign(x)"], &[]),
            (
                &["a", "b"],
                &["-k*a + k*b", "k*a - k*b - D*b"],
                &[("k", 1e6), ("D", 1e-6)],
            ),
            (
                &["a", "b"],
                &["-k*a + k*b", "k*a - k*b - D*b"],
                &[("k", 1.0), ("D", 5e-300)],
            ),
            (&["x", "y"], &["-3*x", "3*x - 1e-14*3*x^2"], &[]),
            (&["x", "v"], &["v", "-x"], &[]),
            (&["x", "y"], &["-x/(x+y)", "x/(y+x)"], &[]),
        ] {
            let s = scene(vars, eqs, params);
            assert!(sums(&s).is_empty(), "{eqs:?}: {:?}", sums(&s));
        }
        // The same shapes where the terms do cancel are found.
        for (vars, eqs) in [
            (
                &["x", "y"][..],
                &["-x + exp(-(t-20)^2)", "x - exp(-(t-20)^2)"][..],
            ),
            (&["x", "y"], &["-x/(x+y)", "x/(x+y)"]),
            (&["x", "y"], &["(x+y)^2 - x*y", "-x^2 - y^2 - x*y"]),
        ] {
            let s = scene(vars, eqs, &[]);
            assert_eq!(sums(&s), vec![vec![1.0, 1.0]], "{eqs:?}");
        }
    }

    /// An exact sum with a coefficient that is no small fraction keeps it.
    #[test]
    fn an_exact_sum_keeps_its_coefficient() {
        let s = scene(&["x", "y"], &["-3*x", "(1 - 1e-9)*3*x"], &[]);
        let got = sums(&s);
        assert_eq!(got.len(), 1);
        assert!(
            (got[0][0] - (1.0 - 1e-9)).abs() < 1e-15 && got[0][1] == 1.0,
            "{got:?}"
        );
    }

    /// Expansions past the bounds give up (no sums), quickly.
    #[test]
    fn a_huge_expansion_gives_up() {
        let s = scene(
            &["x", "y"],
            &["(x+y+t+1)^6*(x+y+t+2)^6*(x-y+t+3)^6", "-x"],
            &[],
        );
        assert!(sums(&s).is_empty());
    }
}
