//! Precedence-correct printers for eleven targets, inline (one expression) or as a program
//! with common-subexpression temporaries.
//!
//! Per-target spelling:
//!
//! | target | `abs` | `x^3` | `1/3` | `x^12` |
//! |---|---|---|---|---|
//! | Maple | `abs(x)` | `x^3` | `1/3` | `x^12` |
//! | Mathematica | `Abs[x]` | `x^3` | `1/3` | `x^12` |
//! | SymPy | `Abs(x)` | `x**3` | `Rational(1, 3)` | `x**12` |
//! | NumPy | `np.abs(x)` | `x**3` | `1/3` | `x**12` |
//! | MATLAB/Octave | `abs(x)` | `x.^3` | `1/3` | `x.^12` |
//! | LaTeX | `\left\|x\right\|` | `{x}^{3}` | `\frac{1}{3}` | `{x}^{12}` |
//! | C | `fabs(x)` | `x*x*x` | `(1.0/3.0)` | `pow(x, 12.0)` |
//! | Rust | `x.abs()` | `x.powi(3)` | `(1.0/3.0)` | `x.powi(12)` |
//! | GLSL | `abs(x)` | `x*x*x` | `(1.0/3.0)` | `pow(abs(x), 12.0)` (never `pow` of a negative) |
//! | JavaScript | `Math.abs(x)` | `x*x*x` | `(1/3)` | `Math.pow(x, 12)` |
//! | Desmos | `\left\|x\right\|` | `{x}^{3}` | `\frac{1}{3}` | `{x}^{12}` |
//!
//! MATLAB uses the element-wise operators `.*`, `./`, `.^` so formulas work on arrays.

use std::collections::{HashMap, HashSet};
use std::fmt::Write as _;

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed};

use crate::error::{ExprError, Result};
use crate::graph::{rat_to_f64, Const, Func, Graph, Id, Node};

/// The printer targets.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
#[non_exhaustive]
pub enum Format {
    /// Maple.
    Maple,
    /// Wolfram Mathematica.
    Mathematica,
    /// SymPy (Python), exact: `Rational(1, 3)`, `Abs`, `**`.
    Sympy,
    /// NumPy (Python), vectorized: `np.abs`, `**`.
    Numpy,
    /// MATLAB / Octave, element-wise operators.
    Matlab,
    /// LaTeX math.
    Latex,
    /// C (C99, `<math.h>`).
    C,
    /// Rust (`f64` methods).
    Rust,
    /// GLSL (no `pow` of possibly negative bases).
    Glsl,
    /// JavaScript (`Math.*`).
    Js,
    /// Desmos (its LaTeX dialect; variable names as `a_{1}`).
    Desmos,
}

impl Format {
    /// Every format.
    pub const ALL: [Format; 11] = [
        Format::Maple,
        Format::Mathematica,
        Format::Sympy,
        Format::Numpy,
        Format::Matlab,
        Format::Latex,
        Format::C,
        Format::Rust,
        Format::Glsl,
        Format::Js,
        Format::Desmos,
    ];

    /// The lower-case name used on command lines (`maple`, `mathematica`, `sympy`, `numpy`,
    /// `matlab`, `latex`, `c`, `rust`, `glsl`, `js`, `desmos`).
    pub fn name(self) -> &'static str {
        match self {
            Format::Maple => "maple",
            Format::Mathematica => "mathematica",
            Format::Sympy => "sympy",
            Format::Numpy => "numpy",
            Format::Matlab => "matlab",
            Format::Latex => "latex",
            Format::C => "c",
            Format::Rust => "rust",
            Format::Glsl => "glsl",
            Format::Js => "js",
            Format::Desmos => "desmos",
        }
    }

    /// The format called `name` (as [`Format::name`]; also `octave`, `python`,
    /// `javascript`, `wolfram`, `tex`).
    pub fn from_name(name: &str) -> Option<Format> {
        let n = name.to_ascii_lowercase();
        let alias = match n.as_str() {
            "octave" => "matlab",
            "python" => "sympy",
            "javascript" => "js",
            "wolfram" => "mathematica",
            "tex" => "latex",
            s => s,
        };
        Format::ALL.iter().copied().find(|f| f.name() == alias)
    }

    fn c_like(self) -> bool {
        matches!(self, Format::C | Format::Rust | Format::Glsl)
    }
    fn tex(self) -> bool {
        matches!(self, Format::Latex | Format::Desmos)
    }
    /// Does the target compute in `f64` (so a constant beyond its range would be infinity)?
    /// Maple, Mathematica, SymPy and LaTeX keep exact rationals exact.
    fn computes_in_f64(self) -> bool {
        !matches!(
            self,
            Format::Maple | Format::Mathematica | Format::Sympy | Format::Latex
        )
    }
}

/// Most bytes a printer writes (256 MiB): an inline print repeats every shared
/// sub-expression where it occurs, so a DAG of a few hundred nodes can print exponentially
/// long; beyond this the printers return [`ExprError::PrintTooLong`] without writing
/// anything.
pub const MAX_PRINT_BYTES: usize = 1 << 28;

/// Binding strength of a printed piece (higher binds tighter).
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Debug)]
enum Prec {
    Sum,
    Unary,
    Product,
    Power,
    Atom,
}

/// Printed text as literal text and references to the text of other nodes (a temporary's
/// name, or the node's definition), expanded only when the whole is written. No node's text
/// is copied into its parent's, so printing is linear in the output, and the length of the
/// output is known before it is written.
#[derive(Clone, Default, Debug)]
struct Tpl(Vec<Seg>);

#[derive(Clone, Debug)]
enum Seg {
    Text(String),
    /// The text of a node where it is used: its temporary's name, or its definition.
    Node(Id),
}

impl Tpl {
    fn text(s: &str) -> Tpl {
        Tpl::default().s(s)
    }
    fn node(id: Id) -> Tpl {
        Tpl(vec![Seg::Node(id)])
    }
    /// Appends literal text.
    fn s(mut self, text: &str) -> Tpl {
        if !text.is_empty() {
            match self.0.last_mut() {
                Some(Seg::Text(t)) => t.push_str(text),
                _ => self.0.push(Seg::Text(text.to_string())),
            }
        }
        self
    }
    /// Appends another piece of text.
    fn t(mut self, other: &Tpl) -> Tpl {
        for seg in &other.0 {
            self = match seg {
                Seg::Text(t) => self.s(t),
                Seg::Node(id) => {
                    self.0.push(Seg::Node(*id));
                    self
                }
            };
        }
        self
    }
    fn join(parts: &[Tpl], sep: &str) -> Tpl {
        let mut out = Tpl::default();
        for (i, p) in parts.iter().enumerate() {
            if i > 0 {
                out = out.s(sep);
            }
            out = out.t(p);
        }
        out
    }
}

type Piece = (Tpl, Prec);

/// The definition of a node: its text, how tightly it binds, its length once expanded.
struct Def {
    tpl: Tpl,
    prec: Prec,
    len: usize,
}

struct Printer<'g> {
    g: &'g Graph,
    f: Format,
    names: HashMap<Id, String>,
    /// The definition of every node to print (by index), built children first.
    defs: Vec<Option<Def>>,
}

impl<'g> Printer<'g> {
    fn new(g: &'g Graph, f: Format) -> Self {
        Printer {
            g,
            f,
            names: HashMap::new(),
            defs: Vec::new(),
        }
    }

    /// Builds the definitions of every node `roots` reach, children first (no recursion, so
    /// any depth prints), after the temporaries are named. Refuses a constant the target
    /// cannot hold: NaN or infinite, or (in a target computing in `f64`) an exact constant
    /// beyond the range of `f64`.
    fn prepare(&mut self, roots: &[Id]) -> Result<()> {
        for id in self.g.reachable(roots) {
            for c in self.g.node_constants(id) {
                match c {
                    Const::Rat(_) if !self.f.computes_in_f64() => {}
                    c => c.check()?,
                }
            }
            let (tpl, prec) = self.definition(id);
            let len = self.len(&tpl);
            if self.defs.len() <= id.index() {
                self.defs.resize_with(id.index() + 1, || None);
            }
            self.defs[id.index()] = Some(Def { tpl, prec, len });
        }
        Ok(())
    }

    /// The definition of a prepared node.
    fn def(&self, id: Id) -> &Def {
        self.defs[id.index()]
            .as_ref()
            .expect("nodes are prepared children first")
    }

    /// The length of `tpl` once expanded (saturating).
    fn len(&self, tpl: &Tpl) -> usize {
        tpl.0.iter().fold(0usize, |n, seg| {
            n.saturating_add(match seg {
                Seg::Text(t) => t.len(),
                Seg::Node(id) => match self.names.get(id) {
                    Some(name) => name.len(),
                    None => self.def(*id).len,
                },
            })
        })
    }

    /// [`ExprError::PrintTooLong`] unless the pieces fit [`MAX_PRINT_BYTES`] together.
    fn check_length<'a>(&self, pieces: impl IntoIterator<Item = &'a Tpl>) -> Result<()> {
        let total = pieces
            .into_iter()
            .fold(0usize, |n, t| n.saturating_add(self.len(t)));
        if total > MAX_PRINT_BYTES {
            return Err(ExprError::PrintTooLong {
                max: MAX_PRINT_BYTES,
            });
        }
        Ok(())
    }

    /// The text of `tpl`, its node references expanded (with an explicit stack: no
    /// recursion).
    fn write(&self, tpl: &Tpl) -> String {
        let mut out = String::with_capacity(self.len(tpl).min(MAX_PRINT_BYTES));
        let mut stack: Vec<std::slice::Iter<'_, Seg>> = vec![tpl.0.iter()];
        while let Some(top) = stack.last_mut() {
            match top.next() {
                None => {
                    stack.pop();
                }
                Some(Seg::Text(t)) => out.push_str(t),
                Some(Seg::Node(id)) => match self.names.get(id) {
                    Some(name) => out.push_str(name),
                    None => stack.push(self.def(*id).tpl.0.iter()),
                },
            }
        }
        out
    }

    fn paren(&self, (t, p): Piece, min: Prec) -> Tpl {
        if p >= min {
            t
        } else if self.f.tex() {
            Tpl::text("\\left(").t(&t).s("\\right)")
        } else {
            Tpl::text("(").t(&t).s(")")
        }
    }

    fn int_text(&self, n: &BigInt) -> String {
        if self.f.c_like() {
            format!("{n}.0")
        } else {
            n.to_string()
        }
    }

    /// A positive rational the target computes in `f64` but whose numerator or denominator
    /// does not fit an `f64` literal: printed as its nearest `f64` instead (`prepare` has
    /// checked that the value itself is in range).
    fn too_long_for_f64(&self, r: &BigRational) -> bool {
        self.f.computes_in_f64() && (r.numer().bits() > 1023 || r.denom().bits() > 1023)
    }

    fn float_text(&self, x: f64) -> String {
        // Non-finite constants never get here: `prepare` refuses them.
        let s = format!("{:?}", x.abs());
        match s.split_once('e') {
            None => s,
            Some((m, e)) => match self.f {
                Format::Mathematica => format!("{m}*^{e}"),
                Format::Latex | Format::Desmos => format!("{m}\\cdot 10^{{{e}}}"),
                _ => s,
            },
        }
    }

    /// A constant on its own.
    fn konst(&self, c: &Const) -> Piece {
        let neg = c.is_negative();
        let (s, p): (String, Prec) = match c {
            Const::Float(x) => (self.float_text(*x), Prec::Atom),
            Const::Rat(r) if self.too_long_for_f64(r) => {
                (self.float_text(rat_to_f64(r)), Prec::Atom)
            }
            Const::Rat(r) => {
                let r = r.abs();
                let (n, d) = (r.numer(), r.denom());
                if d.is_one() {
                    (self.int_text(n), Prec::Atom)
                } else {
                    match self.f {
                        Format::Sympy => (format!("Rational({n}, {d})"), Prec::Atom),
                        Format::C | Format::Rust | Format::Glsl => {
                            (format!("({n}.0/{d}.0)"), Prec::Atom)
                        }
                        Format::Js => (format!("({n}/{d})"), Prec::Atom),
                        Format::Latex | Format::Desmos => {
                            (format!("\\frac{{{n}}}{{{d}}}"), Prec::Atom)
                        }
                        Format::Matlab | Format::Maple | Format::Mathematica | Format::Numpy => {
                            (format!("{n}/{d}"), Prec::Product)
                        }
                    }
                }
            }
        };
        if neg {
            (
                Tpl::text("-").t(&self.paren((Tpl::text(&s), p), Prec::Power)),
                Prec::Unary,
            )
        } else {
            (Tpl::text(&s), p)
        }
    }

    fn var_name(&self, name: &str) -> String {
        if self.f.tex() && name.chars().count() > 1 {
            let mut cs = name.chars();
            let first = cs.next().unwrap_or('x');
            let rest: String = cs.filter(|&c| c != '_').collect();
            if rest.is_empty() {
                first.to_string()
            } else {
                format!("{first}_{{{rest}}}")
            }
        } else {
            name.to_string()
        }
    }

    /// The text of `id` where it is used (a temporary's name if it has one). `id` must be
    /// prepared.
    fn piece(&self, id: Id) -> Piece {
        if let Some(n) = self.names.get(&id) {
            return (Tpl::text(n), Prec::Atom);
        }
        (Tpl::node(id), self.def(id).prec)
    }

    /// The text of `id` itself, ignoring its own temporary name (its children prepared).
    fn definition(&self, id: Id) -> Piece {
        match self.g.node(id) {
            Node::Const(c) => self.konst(c),
            Node::Var(n) => (Tpl::text(&self.var_name(n)), Prec::Atom),
            Node::Pi => (
                Tpl::text(match self.f {
                    Format::Maple | Format::Mathematica => "Pi",
                    Format::Sympy | Format::Matlab => "pi",
                    Format::Numpy => "np.pi",
                    Format::Latex | Format::Desmos => "\\pi",
                    Format::C | Format::Glsl => "3.141592653589793",
                    Format::Rust => "std::f64::consts::PI",
                    Format::Js => "Math.PI",
                }),
                Prec::Atom,
            ),
            Node::Add(c, ts) => self.sum(c, ts),
            Node::Mul(c, fs) => {
                let (t, neg) = self.product(c, fs);
                if neg {
                    (Tpl::text("-").t(&t), Prec::Unary)
                } else {
                    (t, Prec::Product)
                }
            }
            Node::Fun(f, a) => self.call(*f, *a),
        }
    }

    fn sum(&self, c: &Const, ts: &[(Const, Id)]) -> Piece {
        let mut out = Tpl::default();
        let mut first = true;
        let mut push = |out: Tpl, text: &Tpl, neg: bool| {
            let sep = match (first, neg) {
                (true, false) => "",
                (true, true) => "-",
                (false, false) => " + ",
                (false, true) => " - ",
            };
            first = false;
            out.s(sep).t(text)
        };
        for (k, t) in ts {
            let (text, neg) = match (self.g.node(*t), self.names.contains_key(t)) {
                (Node::Mul(m, fs), false) if m.is_one() => self.product(k, fs),
                _ => self.product(k, &[(*t, 1)]),
            };
            out = push(out, &text, neg);
        }
        if !c.is_zero() {
            let text = self.paren(self.konst(&c.abs()), Prec::Product);
            out = push(out, &text, c.is_negative());
        }
        (out, Prec::Sum)
    }

    /// `|c| · Π b^e` as text and whether `c` is negative.
    fn product(&self, c: &Const, fs: &[(Id, i32)]) -> (Tpl, bool) {
        let f = self.f;
        let mut num: Vec<Tpl> = Vec::new();
        let mut den: Vec<Tpl> = Vec::new();
        let mut den_simple = true;
        match c.abs() {
            Const::Rat(r) if self.too_long_for_f64(&r) => {
                num.push(Tpl::text(&self.float_text(rat_to_f64(&r))));
            }
            Const::Rat(r) => {
                if !r.numer().is_one() {
                    num.push(Tpl::text(&self.int_text(r.numer())));
                }
                if !r.denom().is_one() {
                    den.push(Tpl::text(&self.int_text(r.denom())));
                }
            }
            Const::Float(x) => {
                if x != 1.0 {
                    num.push(Tpl::text(&self.float_text(x)));
                }
            }
        }
        for &(b, e) in fs {
            let (s, p) = self.power(b, e.unsigned_abs());
            if e > 0 {
                num.push(self.paren((s, p), Prec::Product));
            } else {
                den_simple &= p >= Prec::Power;
                den.push(self.paren((s, p), Prec::Product));
            }
        }
        let (mul, div) = match f {
            Format::Matlab => (".*", "./"),
            Format::Latex => (" ", "/"),
            Format::Desmos => ("\\cdot ", "/"),
            _ => ("*", "/"),
        };
        let one = if f.c_like() { "1.0" } else { "1" };
        let num_s = if num.is_empty() {
            Tpl::text(one)
        } else {
            Tpl::join(&num, mul)
        };
        let text = if den.is_empty() {
            num_s
        } else if f.tex() {
            Tpl::text("\\frac{")
                .t(&num_s)
                .s("}{")
                .t(&Tpl::join(&den, mul))
                .s("}")
        } else if den.len() == 1 && den_simple {
            num_s.s(div).t(&den[0])
        } else {
            num_s.s(div).s("(").t(&Tpl::join(&den, mul)).s(")")
        };
        (text, c.is_negative())
    }

    /// `b^n` for `n >= 1`.
    fn power(&self, b: Id, n: u32) -> Piece {
        let base = self.piece(b);
        if n == 1 {
            return (self.paren(base, Prec::Power), Prec::Power);
        }
        let atom = self.paren(base, Prec::Atom);
        let a = || atom.clone();
        match self.f {
            Format::Maple | Format::Mathematica => (a().s(&format!("^{n}")), Prec::Power),
            Format::Matlab => (a().s(&format!(".^{n}")), Prec::Power),
            Format::Sympy | Format::Numpy => (a().s(&format!("**{n}")), Prec::Power),
            Format::Latex | Format::Desmos => (
                Tpl::text("{").t(&atom).s(&format!("}}^{{{n}}}")),
                Prec::Power,
            ),
            Format::Rust if self.g.as_const(b).is_some() => (
                Tpl::text("f64::powi(").t(&atom).s(&format!(", {n})")),
                Prec::Atom,
            ),
            Format::Rust => (a().s(&format!(".powi({n})")), Prec::Atom),
            Format::C | Format::Js | Format::Glsl if n <= 4 => {
                (Tpl::join(&vec![atom; n as usize], "*"), Prec::Product)
            }
            Format::C => (
                Tpl::text("pow(").t(&atom).s(&format!(", {n}.0)")),
                Prec::Atom,
            ),
            Format::Js => (
                Tpl::text("Math.pow(").t(&atom).s(&format!(", {n})")),
                Prec::Atom,
            ),
            Format::Glsl => {
                // pow(x, y) is undefined for x < 0 in GLSL: |x|^n, times sign(x) when n is odd.
                let p = Tpl::text("pow(abs(").t(&atom).s(&format!("), {n}.0)"));
                if n.is_multiple_of(2) {
                    (p, Prec::Atom)
                } else {
                    (p.s("*sign(").t(&atom).s(")"), Prec::Product)
                }
            }
        }
    }

    fn call(&self, fun: Func, a: Id) -> Piece {
        let (arg, arg_prec) = self.piece(a);
        let f = self.f;
        let wrap = |pre: &str, post: &str| Tpl::text(pre).t(&arg).s(post);
        if f.tex() {
            let s = match fun {
                Func::Abs => wrap("\\left|", "\\right|"),
                Func::Sqrt => wrap("\\sqrt{", "}"),
                Func::Exp => return (wrap("e^{", "}"), Prec::Power),
                Func::Sign if f == Format::Desmos => {
                    wrap("\\operatorname{sign}\\left(", "\\right)")
                }
                Func::Sign => wrap("\\operatorname{sgn}\\left(", "\\right)"),
                _ => {
                    let name = match fun {
                        Func::Ln => "ln",
                        Func::Atan => "arctan",
                        Func::Asin => "arcsin",
                        Func::Acos => "arccos",
                        other => other.name(),
                    };
                    wrap(&format!("\\{name}\\left("), "\\right)")
                }
            };
            return (s, Prec::Atom);
        }
        if f == Format::Rust {
            if self.g.as_const(a).is_some() {
                // `2.0.sqrt()` does not compile (ambiguous float type): `f64::sqrt(2.0)`.
                let m = if fun == Func::Ln { "ln" } else { fun.name() };
                if fun != Func::Sign {
                    return (wrap(&format!("f64::{m}("), ")"), Prec::Atom);
                }
            }
            let recv = self.paren((arg.clone(), arg_prec), Prec::Atom);
            let s = match fun {
                Func::Sign => Tpl::text("(if ")
                    .t(&recv)
                    .s(" > 0.0 { 1.0 } else if ")
                    .t(&recv)
                    .s(" < 0.0 { -1.0 } else { 0.0 })"),
                _ => {
                    let m = match fun {
                        Func::Abs => "abs",
                        Func::Sqrt => "sqrt",
                        Func::Ln => "ln",
                        other => other.name(),
                    };
                    recv.s(&format!(".{m}()"))
                }
            };
            return (s, Prec::Atom);
        }
        if f == Format::C && fun == Func::Sign {
            let x = self.paren((arg.clone(), arg_prec), Prec::Atom);
            return (
                Tpl::text("(double)((")
                    .t(&x)
                    .s(" > 0.0) - (")
                    .t(&x)
                    .s(" < 0.0))"),
                Prec::Atom,
            );
        }
        let name: &str = match (f, fun) {
            (Format::Mathematica, _) => match fun {
                Func::Abs => "Abs",
                Func::Sign => "Sign",
                Func::Sqrt => "Sqrt",
                Func::Sin => "Sin",
                Func::Cos => "Cos",
                Func::Tan => "Tan",
                Func::Exp => "Exp",
                Func::Ln => "Log",
                Func::Atan => "ArcTan",
                Func::Asin => "ArcSin",
                Func::Acos => "ArcCos",
                Func::Sinh => "Sinh",
                Func::Cosh => "Cosh",
                Func::Tanh => "Tanh",
            },
            (Format::Maple, Func::Sign) => "signum",
            (Format::Maple, Func::Atan) => "arctan",
            (Format::Maple, Func::Asin) => "arcsin",
            (Format::Maple, Func::Acos) => "arccos",
            (Format::Sympy, Func::Abs) => "Abs",
            (Format::Sympy | Format::Matlab | Format::Glsl | Format::C, Func::Ln) => "log",
            (Format::C, Func::Abs) => "fabs",
            (Format::Numpy, _) => match fun {
                Func::Ln => "np.log",
                Func::Atan => "np.arctan",
                Func::Asin => "np.arcsin",
                Func::Acos => "np.arccos",
                Func::Abs => "np.abs",
                Func::Sign => "np.sign",
                Func::Sqrt => "np.sqrt",
                Func::Sin => "np.sin",
                Func::Cos => "np.cos",
                Func::Tan => "np.tan",
                Func::Exp => "np.exp",
                Func::Sinh => "np.sinh",
                Func::Cosh => "np.cosh",
                Func::Tanh => "np.tanh",
            },
            (Format::Js, _) => match fun {
                Func::Ln => "Math.log",
                Func::Abs => "Math.abs",
                Func::Sign => "Math.sign",
                Func::Sqrt => "Math.sqrt",
                Func::Sin => "Math.sin",
                Func::Cos => "Math.cos",
                Func::Tan => "Math.tan",
                Func::Exp => "Math.exp",
                Func::Atan => "Math.atan",
                Func::Asin => "Math.asin",
                Func::Acos => "Math.acos",
                Func::Sinh => "Math.sinh",
                Func::Cosh => "Math.cosh",
                Func::Tanh => "Math.tanh",
            },
            _ => fun.name(),
        };
        let s = if f == Format::Mathematica {
            wrap(&format!("{name}["), "]")
        } else {
            wrap(&format!("{name}("), ")")
        };
        (s, Prec::Atom)
    }

    /// Chooses temporaries for a program printing `roots`: nodes used more than once, and
    /// bases of powers the target prints by repeated multiplication, or arguments it repeats.
    fn plan(&mut self, roots: &[Id], prefix: &str) -> Vec<Id> {
        let order = self.g.reachable(roots);
        let mut uses: HashMap<Id, u32> = HashMap::with_capacity(order.len());
        for &r in roots {
            *uses.entry(r).or_default() += 1;
        }
        let mut repeated: HashSet<Id> = HashSet::new();
        for &id in &order {
            self.g
                .for_each_child(id, |c| *uses.entry(c).or_default() += 1);
            match self.g.node(id) {
                Node::Mul(_, fs) if matches!(self.f, Format::C | Format::Js | Format::Glsl) => {
                    repeated.extend(
                        fs.iter()
                            .filter(|(_, e)| e.unsigned_abs() >= 2)
                            .map(|(b, _)| *b),
                    );
                }
                Node::Fun(Func::Sign, a) if matches!(self.f, Format::C | Format::Rust) => {
                    repeated.insert(*a);
                }
                _ => {}
            }
        }
        let leaf = |id: Id| matches!(self.g.node(id), Node::Const(_) | Node::Var(_) | Node::Pi);
        let temps: Vec<Id> = order
            .iter()
            .copied()
            .filter(|id| !leaf(*id) && (uses[id] >= 2 || repeated.contains(id)))
            .collect();
        for (i, &t) in temps.iter().enumerate() {
            let name = if self.f.tex() {
                format!("{prefix}_{{{i}}}")
            } else {
                format!("{prefix}{i}")
            };
            self.names.insert(t, name);
        }
        temps
    }

    /// Prepares `roots` and returns the definitions of `temps` and the texts of `roots`, or
    /// the error of a constant the target cannot hold or of a text too long.
    fn texts(&mut self, temps: &[Id], roots: &[Id]) -> Result<(Vec<String>, Vec<String>)> {
        self.prepare(roots)?;
        let results: Vec<Tpl> = roots.iter().map(|&r| self.piece(r).0).collect();
        self.check_length(temps.iter().map(|t| &self.def(*t).tpl).chain(&results))?;
        let defs = temps
            .iter()
            .map(|t| self.write(&self.def(*t).tpl))
            .collect();
        let results = results.iter().map(|t| self.write(t)).collect();
        Ok((defs, results))
    }
}

/// A prefix for temporaries that no variable of `g` starts with.
fn temp_prefix(g: &Graph, roots: &[Id]) -> String {
    let vars = g.variables(roots);
    let mut prefix = "t".to_string();
    while vars.iter().any(|v| v.starts_with(prefix.as_str())) {
        prefix.push('_');
    }
    prefix
}

impl Graph {
    /// `e` as one inline expression in the target's syntax (no temporaries: shared
    /// sub-expressions are printed again where they occur).
    ///
    /// Every printer walks the graph without recursion (any depth prints; the parser reads
    /// back at most [`crate::MAX_DEPTH`] levels) and knows the length of its text before
    /// writing it.
    ///
    /// # Errors
    /// Every printer refuses, rather than print a number the target would read as infinity,
    /// NaN or zero: [`ExprError::NonFiniteConstant`] for a NaN or infinite constant (in any
    /// target), [`ExprError::ConstantOutOfRange`] for an exact constant outside the range of
    /// `f64` in a target that computes in `f64` (all but Maple, Mathematica, SymPy and
    /// LaTeX, which print it exactly); and [`ExprError::PrintTooLong`] for a text longer than
    /// [`MAX_PRINT_BYTES`] (an inline print of a DAG can be exponentially long: print a
    /// program instead).
    ///
    /// ```
    /// use geomkit_expr::{parse, ExprError, Format, Graph};
    /// let mut g = Graph::new();
    /// let e = parse(&mut g, "abs(u - 1)^3 / 3").unwrap();
    /// assert_eq!(g.print(e, Format::C).unwrap(), "fabs(u - 1.0)*fabs(u - 1.0)*fabs(u - 1.0)/3.0");
    /// assert_eq!(g.print(e, Format::Rust).unwrap(), "(u - 1.0).abs().powi(3)/3.0");
    /// assert_eq!(g.print(e, Format::Mathematica).unwrap(), "Abs[u - 1]^3/3");
    /// let u = g.var("u");
    /// let inf = g.num(f64::INFINITY);
    /// let bad = g.mul(u, inf);
    /// assert!(matches!(g.print(bad, Format::C), Err(ExprError::NonFiniteConstant { .. })));
    /// ```
    pub fn print(&self, e: Id, f: Format) -> Result<String> {
        let (_, mut texts) = Printer::new(self, f).texts(&[], &[e])?;
        Ok(texts.pop().unwrap_or_default())
    }

    /// One definition `name(params) = e` that the target accepts as it is (inline, no
    /// temporaries): Maple `x := (u, v) -> e;`, Mathematica `x[u_, v_] := e`, SymPy
    /// `x = e` after `u, v = symbols("u v")` (the caller prints that line once:
    /// [`Graph::print_preamble`]), NumPy `x = lambda u, v: e`, MATLAB/Octave
    /// `x = @(u, v) e;`, C `double x(double u, double v) { return e; }`, Rust
    /// `fn x(u: f64, v: f64) -> f64 { e }`, GLSL `float x(float u, float v) { return e; }`,
    /// JavaScript `const x = (u, v) => e;`, LaTeX `x(u, v) = e`, Desmos `f_{x}(u,v)=e`
    /// (Desmos reserves x, y, z, so a coordinate is the subscript of f).
    ///
    /// # Errors
    /// As [`Graph::print`].
    ///
    /// ```
    /// use geomkit_expr::{parse, Format, Graph};
    /// let mut g = Graph::new();
    /// let e = parse(&mut g, "abs(u) - v").unwrap();
    /// assert_eq!(g.print_definition("x", &["u", "v"], e, Format::Mathematica).unwrap(), "x[u_, v_] := Abs[u] - v");
    /// assert_eq!(g.print_definition("x", &["u", "v"], e, Format::Maple).unwrap(), "x := (u, v) -> abs(u) - v;");
    /// assert_eq!(g.print_definition("x", &["u", "v"], e, Format::Js).unwrap(), "const x = (u, v) => Math.abs(u) - v;");
    /// ```
    pub fn print_definition(
        &self,
        name: &str,
        params: &[&str],
        e: Id,
        f: Format,
    ) -> Result<String> {
        let mut p = Printer::new(self, f);
        let rhs = p.texts(&[], &[e])?.1.pop().unwrap_or_default();
        let name = p.var_name(name);
        let vars: Vec<String> = params.iter().map(|v| p.var_name(v)).collect();
        let list = vars.join(", ");
        let typed = |ty: &str, suffix: &str| -> String {
            vars.iter()
                .map(|v| format!("{ty}{v}{suffix}"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        Ok(match f {
            Format::Maple => format!("{name} := ({list}) -> {rhs};"),
            Format::Mathematica => {
                let pats: Vec<String> = vars.iter().map(|v| format!("{v}_")).collect();
                format!("{name}[{}] := {rhs}", pats.join(", "))
            }
            Format::Sympy => format!("{name} = {rhs}"),
            Format::Numpy => format!("{name} = lambda {list}: {rhs}"),
            Format::Matlab => format!("{name} = @({list}) {rhs};"),
            Format::Latex => format!("{name}({list}) = {rhs}"),
            Format::C => format!(
                "double {name}({}) {{ return {rhs}; }}",
                typed("double ", "")
            ),
            Format::Rust => format!("fn {name}({}) -> f64 {{ {rhs} }}", typed("", ": f64")),
            Format::Glsl => format!("float {name}({}) {{ return {rhs}; }}", typed("float ", "")),
            Format::Js => format!("const {name} = ({list}) => {rhs};"),
            Format::Desmos => format!("f_{{{name}}}({})={rhs}", vars.join(",")),
        })
    }

    /// What must come before the definitions of [`Graph::print_definition`] in format `f`
    /// for them to run as pasted: SymPy `from sympy import *` and the symbols, NumPy
    /// `import numpy as np`, C `#include <math.h>`; empty for the others.
    pub fn print_preamble(&self, params: &[&str], f: Format) -> String {
        match f {
            Format::Sympy if params.len() == 1 => {
                format!("from sympy import *\n{0} = symbols(\"{0}\")\n", params[0])
            }
            Format::Sympy => format!(
                "from sympy import *\n{} = symbols(\"{}\")\n",
                params.join(", "),
                params.join(" ")
            ),
            Format::Numpy => "import numpy as np\n".into(),
            Format::C => "#include <math.h>\n".into(),
            _ => String::new(),
        }
    }

    /// A program computing all `outputs` (name, expression) with common-subexpression
    /// temporaries: C `const double t0 = ...;`, Rust `let`, GLSL `float`, JS `const`,
    /// SymPy/NumPy/MATLAB assignments, Maple `:=`, Mathematica `=` (wrap it in `Module`
    /// yourself or use [`Graph::print_function`]), LaTeX `\begin{aligned}` lines, Desmos
    /// lines. Temporaries are named `t0, t1, ...` (a prefix no variable starts with).
    ///
    /// # Errors
    /// As [`Graph::print`] (each shared sub-expression is printed once, so only a DAG of
    /// hundreds of MB of text is too long here).
    pub fn print_program(&self, outputs: &[(&str, Id)], f: Format) -> Result<String> {
        let roots: Vec<Id> = outputs.iter().map(|o| o.1).collect();
        let mut p = Printer::new(self, f);
        let temps = p.plan(&roots, &temp_prefix(self, &roots));
        let (defs, results) = p.texts(&temps, &roots)?;
        let mut out = String::new();
        let mut lines: Vec<(String, String)> = Vec::new();
        for (t, d) in temps.iter().zip(defs) {
            lines.push((p.names[t].clone(), d));
        }
        for ((name, _), r) in outputs.iter().zip(results) {
            lines.push((p.var_name(name), r));
        }
        if f == Format::Latex {
            out.push_str("\\begin{aligned}\n");
        }
        for (name, rhs) in lines {
            let _ = match f {
                Format::C => writeln!(out, "const double {name} = {rhs};"),
                Format::Rust => writeln!(out, "let {name} = {rhs};"),
                Format::Glsl => writeln!(out, "float {name} = {rhs};"),
                Format::Js => writeln!(out, "const {name} = {rhs};"),
                Format::Sympy | Format::Numpy => writeln!(out, "{name} = {rhs}"),
                Format::Matlab | Format::Mathematica => writeln!(out, "{name} = {rhs};"),
                Format::Maple => writeln!(out, "{name} := {rhs};"),
                Format::Latex => writeln!(out, "{name} &= {rhs} \\\\"),
                Format::Desmos => writeln!(out, "{name}={rhs}"),
            };
        }
        if f == Format::Latex {
            out.push_str("\\end{aligned}\n");
        }
        Ok(out)
    }

    /// A batched Rust function over slices — the generated-code fast path: compile it
    /// into your program (or let a build script write it) and every point runs the
    /// straight-line code of [`Graph::print_program`] in a loop the compiler vectorizes.
    /// Signature: `pub fn name(u: &[f64], v: &[f64], out0: &mut [f64], ...)`; all slices
    /// must have the length of the first parameter's (the function panics otherwise).
    ///
    /// # Errors
    /// As [`Graph::print_program`].
    ///
    /// ```
    /// use geomkit_expr::{parse, Graph};
    /// let mut g = Graph::new();
    /// let x = parse(&mut g, "abs(u - 1)*v").unwrap();
    /// let text = g.print_batch_rust("f", &["u", "v"], &[x]).unwrap();
    /// assert!(text.starts_with("pub fn f(u: &[f64], v: &[f64], out0: &mut [f64]) {"));
    /// ```
    pub fn print_batch_rust(&self, name: &str, params: &[&str], roots: &[Id]) -> Result<String> {
        let outs: Vec<String> = (0..roots.len()).map(|i| format!("out{i}")).collect();
        let pairs: Vec<(&str, Id)> = outs
            .iter()
            .map(String::as_str)
            .zip(roots.iter().copied())
            .collect();
        let body = self.print_program(&pairs, Format::Rust)?;
        let first = params.first().copied().unwrap_or("x");
        let mut out = String::new();
        let args: Vec<String> = params
            .iter()
            .map(|p| format!("{p}: &[f64]"))
            .chain(outs.iter().map(|o| format!("{o}: &mut [f64]")))
            .collect();
        let _ = writeln!(out, "pub fn {name}({}) {{", args.join(", "));
        let _ = writeln!(out, "    let n = {first}.len();");
        for p in params {
            let _ = writeln!(out, "    let {p}_s = &{p}[..n];");
        }
        for o in &outs {
            let _ = writeln!(out, "    let {o}_s = &mut {o}[..n];");
        }
        let _ = writeln!(out, "    for i in 0..n {{");
        for p in params {
            let _ = writeln!(out, "        let {p} = {p}_s[i];");
        }
        for line in body.lines() {
            let _ = writeln!(out, "        {line}");
        }
        for o in &outs {
            let _ = writeln!(out, "        {o}_s[i] = {o};");
        }
        out.push_str("    }\n}\n");
        Ok(out)
    }

    /// A complete function `name(params...)` returning all `roots`, with
    /// common-subexpression temporaries: C `void name(double u, ..., double *out)`, Rust
    /// `pub fn name(u: f64, ...) -> [f64; N]`, GLSL `void name(float u, ..., out float
    /// out0, ...)`, JS `function`, Python `def` (SymPy or NumPy), MATLAB `function [o0, ...]
    /// = name(...)`, Maple `proc`, Mathematica `name[u_, ...] := Module[...]`; LaTeX and
    /// Desmos get the program lines of [`Graph::print_program`] with outputs
    /// `name_0, name_1, ...`.
    ///
    /// # Errors
    /// As [`Graph::print_program`].
    ///
    /// ```
    /// use geomkit_expr::{parse, Format, Graph};
    /// let mut g = Graph::new();
    /// let x = parse(&mut g, "abs(u) + sin(abs(u))").unwrap();
    /// let text = g.print_function("f", &["u"], &[x], Format::C).unwrap();
    /// assert_eq!(text, "void f(double u, double *out) {\n    const double t0 = fabs(u);\n    out[0] = t0 + sin(t0);\n}\n");
    /// ```
    pub fn print_function(
        &self,
        name: &str,
        params: &[&str],
        roots: &[Id],
        f: Format,
    ) -> Result<String> {
        let mut p = Printer::new(self, f);
        let temps = p.plan(roots, &temp_prefix(self, roots));
        let (texts, results) = p.texts(&temps, roots)?;
        let defs: Vec<(String, String)> = temps
            .iter()
            .map(|t| p.names[t].clone())
            .zip(texts)
            .collect();
        let n = roots.len();
        let mut out = String::new();
        let ind = "    ";
        let join_params = |ty: &str, suffix: &str| -> String {
            params
                .iter()
                .map(|v| format!("{ty}{v}{suffix}"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        match f {
            Format::C => {
                let _ = writeln!(
                    out,
                    "void {name}({}, double *out) {{",
                    join_params("double ", "")
                );
                for (t, d) in &defs {
                    let _ = writeln!(out, "{ind}const double {t} = {d};");
                }
                for (i, r) in results.iter().enumerate() {
                    let _ = writeln!(out, "{ind}out[{i}] = {r};");
                }
                out.push_str("}\n");
            }
            Format::Rust => {
                let _ = writeln!(
                    out,
                    "pub fn {name}({}) -> [f64; {n}] {{",
                    join_params("", ": f64")
                );
                for (t, d) in &defs {
                    let _ = writeln!(out, "{ind}let {t} = {d};");
                }
                let _ = writeln!(out, "{ind}[{}]", results.join(", "));
                out.push_str("}\n");
            }
            Format::Glsl => {
                let outs: Vec<String> = (0..n).map(|i| format!("out float out{i}")).collect();
                let _ = writeln!(
                    out,
                    "void {name}({}, {}) {{",
                    join_params("float ", ""),
                    outs.join(", ")
                );
                for (t, d) in &defs {
                    let _ = writeln!(out, "{ind}float {t} = {d};");
                }
                for (i, r) in results.iter().enumerate() {
                    let _ = writeln!(out, "{ind}out{i} = {r};");
                }
                out.push_str("}\n");
            }
            Format::Js => {
                let _ = writeln!(out, "function {name}({}) {{", params.join(", "));
                for (t, d) in &defs {
                    let _ = writeln!(out, "{ind}const {t} = {d};");
                }
                let _ = writeln!(out, "{ind}return [{}];", results.join(", "));
                out.push_str("}\n");
            }
            Format::Sympy | Format::Numpy => {
                let _ = writeln!(out, "def {name}({}):", params.join(", "));
                for (t, d) in &defs {
                    let _ = writeln!(out, "{ind}{t} = {d}");
                }
                let _ = writeln!(out, "{ind}return ({},)", results.join(", "));
            }
            Format::Matlab => {
                let outs: Vec<String> = (0..n).map(|i| format!("o{i}")).collect();
                let _ = writeln!(
                    out,
                    "function [{}] = {name}({})",
                    outs.join(", "),
                    params.join(", ")
                );
                for (t, d) in &defs {
                    let _ = writeln!(out, "{ind}{t} = {d};");
                }
                for (i, r) in results.iter().enumerate() {
                    let _ = writeln!(out, "{ind}o{i} = {r};");
                }
                out.push_str("end\n");
            }
            Format::Maple => {
                let _ = writeln!(out, "{name} := proc({})", params.join(", "));
                if !defs.is_empty() {
                    let locals: Vec<&str> = defs.iter().map(|d| d.0.as_str()).collect();
                    let _ = writeln!(out, "{ind}local {};", locals.join(", "));
                }
                for (t, d) in &defs {
                    let _ = writeln!(out, "{ind}{t} := {d};");
                }
                let _ = writeln!(out, "{ind}[{}];", results.join(", "));
                out.push_str("end proc:\n");
            }
            Format::Mathematica => {
                let pats: Vec<String> = params.iter().map(|v| format!("{v}_")).collect();
                let locals: Vec<&str> = defs.iter().map(|d| d.0.as_str()).collect();
                let _ = writeln!(
                    out,
                    "{name}[{}] := Module[{{{}}},",
                    pats.join(", "),
                    locals.join(", ")
                );
                for (t, d) in &defs {
                    let _ = writeln!(out, "{ind}{t} = {d};");
                }
                let _ = writeln!(out, "{ind}{{{}}}\n]", results.join(", "));
            }
            Format::Latex | Format::Desmos => {
                let names: Vec<String> = (0..n).map(|i| format!("{name}_{i}")).collect();
                let outputs: Vec<(&str, Id)> = names
                    .iter()
                    .map(String::as_str)
                    .zip(roots.iter().copied())
                    .collect();
                return self.print_program(&outputs, f);
            }
        }
        Ok(out)
    }
}
