//! The hash-consed expression DAG, its simplifying constructors, `substitute`, `diff`,
//! `op_count` and scalar `eval`.

use std::collections::HashMap;
use std::hash::{Hash, Hasher};

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, ToPrimitive, Zero};

use crate::error::{ExprError, Result};

/// A node of a [`Graph`]: an index into its arena. Children always have smaller ids than
/// their parents, so ascending id order is a topological order.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, PartialOrd, Ord)]
pub struct Id(pub(crate) u32);

impl Id {
    /// The arena index of the node.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// Most bits of the numerator, and of the denominator, of an exact constant (4096 bits:
/// about 1233 decimal digits). A constant that would be longer — a literal such as
/// `1e-2000`, a power such as `1.5^10000`, a sum or product of long constants, any folded
/// constant — is rounded to the nearest `f64` instead (a power beyond the limit is computed
/// in `f64`, within about `|n|·2⁻⁵³` relative error). This bounds the time and memory of
/// exact arithmetic: no constant operation handles more than twice this many bits.
/// [`crate::parse`] refuses a constant whose rounding would overflow to infinity or
/// underflow to zero, naming it.
pub const MAX_EXACT_BITS: u64 = 4096;

/// A constant: an exact rational or an `f64`.
///
/// Exact constants fold exactly (`1/3 + 2/3 = 1`) while their numerator and denominator
/// have at most [`MAX_EXACT_BITS`] bits; as soon as an `f64` takes part, or a result would be
/// longer, folding is done in `f64`.
///
/// Constants compare and hash by their parts: rationals by numerator and denominator (a
/// graph stores them reduced, with a positive denominator), `f64` by their bits.
#[derive(Clone, Debug)]
pub enum Const {
    /// An exact rational.
    Rat(BigRational),
    /// A floating-point number (compared and hashed by its bits; `-0.0` is stored as `0.0`).
    Float(f64),
}

impl PartialEq for Const {
    fn eq(&self, other: &Self) -> bool {
        match (self, other) {
            // By parts, not num-rational's value comparison (a continued-fraction walk for
            // unequal denominators): the graph's rationals are reduced.
            (Const::Rat(a), Const::Rat(b)) => a.numer() == b.numer() && a.denom() == b.denom(),
            (Const::Float(a), Const::Float(b)) => a.to_bits() == b.to_bits(),
            _ => false,
        }
    }
}
impl Eq for Const {}
impl Hash for Const {
    fn hash<H: Hasher>(&self, h: &mut H) {
        match self {
            Const::Rat(r) => {
                // By parts: num-rational's own Hash recurses once per continued-fraction
                // term, which overflowed the stack on `1.5^100000`.
                0u8.hash(h);
                r.numer().hash(h);
                r.denom().hash(h);
            }
            Const::Float(f) => {
                1u8.hash(h);
                f.to_bits().hash(h)
            }
        }
    }
}

impl Const {
    pub(crate) fn int(n: i64) -> Const {
        Const::Rat(BigRational::from_integer(BigInt::from(n)))
    }
    pub(crate) fn float(x: f64) -> Const {
        // One zero and one NaN, so equal values share one node.
        if x == 0.0 {
            Const::Float(0.0)
        } else if x.is_nan() {
            Const::Float(f64::NAN)
        } else {
            Const::Float(x)
        }
    }
    /// `r` itself while its numerator and denominator have at most [`MAX_EXACT_BITS`] bits,
    /// else its nearest `f64`.
    pub(crate) fn bounded(r: BigRational) -> Const {
        if r.numer().bits() > MAX_EXACT_BITS || r.denom().bits() > MAX_EXACT_BITS {
            Const::float(rat_to_f64(&r))
        } else {
            Const::Rat(r)
        }
    }
    /// The form a graph stores: rationals reduced with a positive denominator (a zero
    /// denominator gives the `f64` ±inf or NaN), within [`MAX_EXACT_BITS`]; one zero and one
    /// NaN among `f64`.
    pub(crate) fn canonical(self) -> Const {
        match self {
            Const::Float(x) => Const::float(x),
            Const::Rat(r) => {
                let (n, d) = (r.numer(), r.denom());
                if d.is_zero() {
                    let x = if n.is_zero() {
                        f64::NAN
                    } else if n.is_negative() {
                        f64::NEG_INFINITY
                    } else {
                        f64::INFINITY
                    };
                    return Const::float(x);
                }
                if n.bits() > 4 * MAX_EXACT_BITS || d.bits() > 4 * MAX_EXACT_BITS {
                    // Not worth reducing (a gcd of huge numbers): the f64 it rounds to.
                    return Const::float(rat_to_f64(&r));
                }
                Const::bounded(BigRational::new(n.clone(), d.clone()))
            }
        }
    }
    /// Is it exactly zero (`0` or `0.0`)?
    pub fn is_zero(&self) -> bool {
        match self {
            Const::Rat(r) => r.is_zero(),
            Const::Float(f) => *f == 0.0,
        }
    }
    /// Is it exactly one (`1` or `1.0`)?
    pub fn is_one(&self) -> bool {
        match self {
            Const::Rat(r) => r.is_one(),
            Const::Float(f) => *f == 1.0,
        }
    }
    /// Is it `-1` or `-1.0`?
    pub fn is_minus_one(&self) -> bool {
        match self {
            Const::Rat(r) => *r == -BigRational::one(),
            Const::Float(f) => *f == -1.0,
        }
    }
    /// Is it negative?
    pub fn is_negative(&self) -> bool {
        match self {
            Const::Rat(r) => r.is_negative(),
            Const::Float(f) => *f < 0.0,
        }
    }
    /// Is it finite (every rational is)?
    pub fn is_finite(&self) -> bool {
        match self {
            Const::Rat(_) => true,
            Const::Float(f) => f.is_finite(),
        }
    }
    /// The nearest `f64` (±inf for a rational beyond the range of `f64`).
    pub fn to_f64(&self) -> f64 {
        match self {
            Const::Rat(r) => rat_to_f64(r),
            Const::Float(f) => *f,
        }
    }
    pub(crate) fn add(&self, o: &Const) -> Const {
        match (self, o) {
            (Const::Rat(a), Const::Rat(b)) => Const::bounded(a + b),
            _ => {
                let s = self.to_f64() + o.to_f64();
                // A sum of two finite f64 that rounds to zero is exactly zero.
                if s == 0.0 {
                    Const::int(0)
                } else {
                    Const::float(s)
                }
            }
        }
    }
    pub(crate) fn mul(&self, o: &Const) -> Const {
        match (self, o) {
            (Const::Rat(a), Const::Rat(b)) => Const::bounded(a * b),
            // An exact zero times a finite number is exactly zero.
            (Const::Rat(z), x) | (x, Const::Rat(z)) if z.is_zero() && x.is_finite() => {
                Const::int(0)
            }
            _ => Const::float(self.to_f64() * o.to_f64()),
        }
    }
    pub(crate) fn abs(&self) -> Const {
        match self {
            Const::Rat(a) => Const::Rat(a.abs()),
            Const::Float(f) => Const::float(f.abs()),
        }
    }
    /// `self^n`, or `None` for a zero to a negative power. A power whose exact value would
    /// have more than [`MAX_EXACT_BITS`] bits is computed in `f64` without computing it
    /// exactly.
    pub(crate) fn powi(&self, n: i32) -> Option<Const> {
        match self {
            Const::Rat(a) => {
                if a.is_zero() {
                    return match n {
                        n if n < 0 => None,
                        0 => Some(Const::int(1)),
                        _ => Some(Const::int(0)),
                    };
                }
                // |a^n| has at least |n|·(b-1)+1 bits in its longer part; the exact power is
                // computed only when that is within the limit (then it has at most twice as
                // many).
                let b = a.numer().bits().max(a.denom().bits());
                let k = u64::from(n.unsigned_abs());
                if b >= 2 && k.saturating_mul(b - 1).saturating_add(1) > MAX_EXACT_BITS {
                    return Some(Const::float(rat_to_f64(a).powi(n)));
                }
                Some(Const::bounded(num_traits::Pow::pow(a, n)))
            }
            Const::Float(f) if *f == 0.0 && n < 0 => None,
            Const::Float(f) => Some(Const::float(f.powi(n))),
        }
    }
    /// Is it a constant the engine can compute with: a finite `f64`, or a rational that is
    /// zero or within the range of `f64` (its `f64` neither infinite nor zero)? Else the
    /// error naming it.
    pub(crate) fn check(&self) -> Result<()> {
        match self {
            Const::Float(f) if !f.is_finite() => Err(ExprError::NonFiniteConstant {
                value: format!("{f:?}"),
            }),
            Const::Rat(r)
                if !r.is_zero() && !matches!(rat_to_f64(r), x if x.is_finite() && x != 0.0) =>
            {
                Err(ExprError::ConstantOutOfRange {
                    value: approx_text(r),
                })
            }
            _ => Ok(()),
        }
    }
}

/// A short scientific-notation text of a long rational (`-3.3333e400`) for messages.
pub(crate) fn approx_text(r: &BigRational) -> String {
    let n = r.numer().abs().to_string();
    let d = r.denom().to_string();
    let lead = |s: &str| -> f64 {
        let k = s.len().min(17);
        s[..k].parse::<f64>().unwrap_or(1.0) / 10f64.powi(k as i32 - 1)
    };
    let mut m = lead(&n) / lead(&d);
    let mut e = n.len() as i64 - d.len() as i64;
    while m < 1.0 && m > 0.0 {
        m *= 10.0;
        e -= 1;
    }
    let sign = if r.is_negative() { "-" } else { "" };
    format!("{sign}{m:.4}e{e}")
}

/// The nearest `f64` (±inf beyond the range of `f64`, 0 below it).
pub(crate) fn rat_to_f64(r: &BigRational) -> f64 {
    r.to_f64().unwrap_or_else(|| {
        let n = r.numer().to_f64().unwrap_or(f64::NAN);
        let d = r.denom().to_f64().unwrap_or(f64::NAN);
        n / d
    })
}

/// The elementary functions of the engine.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
#[non_exhaustive]
pub enum Func {
    /// `|x|`.
    Abs,
    /// The sign: -1, 0 or 1 (the derivative of `abs`).
    Sign,
    /// Square root.
    Sqrt,
    /// Sine.
    Sin,
    /// Cosine.
    Cos,
    /// Tangent.
    Tan,
    /// Exponential.
    Exp,
    /// Natural logarithm.
    Ln,
    /// Arc tangent.
    Atan,
    /// Arc sine.
    Asin,
    /// Arc cosine.
    Acos,
    /// Hyperbolic sine.
    Sinh,
    /// Hyperbolic cosine.
    Cosh,
    /// Hyperbolic tangent.
    Tanh,
}

impl Func {
    /// Every function, in a fixed order.
    pub const ALL: [Func; 14] = [
        Func::Abs,
        Func::Sign,
        Func::Sqrt,
        Func::Sin,
        Func::Cos,
        Func::Tan,
        Func::Exp,
        Func::Ln,
        Func::Atan,
        Func::Asin,
        Func::Acos,
        Func::Sinh,
        Func::Cosh,
        Func::Tanh,
    ];
    /// The name the parser accepts and the SymPy-like spelling (lower case).
    pub fn name(self) -> &'static str {
        match self {
            Func::Abs => "abs",
            Func::Sign => "sign",
            Func::Sqrt => "sqrt",
            Func::Sin => "sin",
            Func::Cos => "cos",
            Func::Tan => "tan",
            Func::Exp => "exp",
            Func::Ln => "ln",
            Func::Atan => "atan",
            Func::Asin => "asin",
            Func::Acos => "acos",
            Func::Sinh => "sinh",
            Func::Cosh => "cosh",
            Func::Tanh => "tanh",
        }
    }
    /// The function in `f64`. `sign(0) = 0`, `sign(NaN) = NaN`.
    #[inline(always)]
    pub fn apply(self, x: f64) -> f64 {
        match self {
            Func::Abs => x.abs(),
            Func::Sign => sign(x),
            Func::Sqrt => x.sqrt(),
            Func::Sin => x.sin(),
            Func::Cos => x.cos(),
            Func::Tan => x.tan(),
            Func::Exp => x.exp(),
            Func::Ln => x.ln(),
            Func::Atan => x.atan(),
            Func::Asin => x.asin(),
            Func::Acos => x.acos(),
            Func::Sinh => x.sinh(),
            Func::Cosh => x.cosh(),
            Func::Tanh => x.tanh(),
        }
    }
    /// Defined and finite for every finite argument (so `0 * f(x)` may fold to 0).
    fn total(self) -> bool {
        matches!(
            self,
            Func::Abs
                | Func::Sign
                | Func::Sin
                | Func::Cos
                | Func::Atan
                | Func::Tanh
                | Func::Exp
                | Func::Sinh
                | Func::Cosh
        )
    }
}

/// `sign(x)`: -1, 0 or 1 (NaN stays NaN).
#[inline(always)]
pub(crate) fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        x * 0.0
    }
}

/// One node of the DAG, in canonical form.
#[derive(Clone, PartialEq, Eq, Hash, Debug)]
pub enum Node {
    /// A constant.
    Const(Const),
    /// A variable, by name.
    Var(Box<str>),
    /// The constant π, kept symbolic.
    Pi,
    /// `c + Σ coef_k · term_k`: terms sorted by id, never constants, sums or products with a
    /// coefficient other than 1.
    Add(Const, Box<[(Const, Id)]>),
    /// `c · Π base_k ^ exp_k`: factors sorted by (base, exp); bases are never products and
    /// never constants (except an exact zero to a negative power: division by zero).
    Mul(Const, Box<[(Id, i32)]>),
    /// An elementary function of one argument.
    Fun(Func, Id),
}

/// The arena of hash-consed expression nodes. Equal expressions built twice get the same
/// [`Id`]; constructors simplify as they build (see the crate documentation).
#[derive(Clone, Debug, Default)]
pub struct Graph {
    nodes: Vec<Node>,
    /// Defined and finite for every finite value of the variables (so `0·x` may fold).
    total: Vec<bool>,
    /// Nesting depth (1 for leaves).
    depth: Vec<u32>,
    interned: HashMap<Node, Id>,
    /// For a product `c·M` with `c ≠ 1`: the id of `M` (the product without coefficient).
    unit: HashMap<Id, Id>,
}

impl Graph {
    /// An empty graph.
    pub fn new() -> Self {
        Self::default()
    }

    /// Number of nodes in the arena (every node ever built, reachable or not).
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Whether the arena is empty.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The node behind an id.
    ///
    /// # Panics
    /// If `id` comes from another graph and is out of range.
    pub fn node(&self, id: Id) -> &Node {
        &self.nodes[id.index()]
    }

    /// Nesting depth of an expression (1 for a variable or constant).
    pub fn depth(&self, id: Id) -> u32 {
        self.depth[id.index()]
    }

    pub(crate) fn is_total(&self, id: Id) -> bool {
        self.total[id.index()]
    }

    fn intern(&mut self, n: Node) -> Id {
        if let Some(&id) = self.interned.get(&n) {
            return id;
        }
        let (total, depth) = match &n {
            Node::Const(c) => (c.is_finite(), 1),
            Node::Var(_) | Node::Pi => (true, 1),
            Node::Add(c, ts) => (
                c.is_finite() && ts.iter().all(|(k, t)| k.is_finite() && self.is_total(*t)),
                1 + ts.iter().map(|(_, t)| self.depth(*t)).max().unwrap_or(0),
            ),
            Node::Mul(c, fs) => (
                c.is_finite() && fs.iter().all(|&(b, e)| e > 0 && self.is_total(b)),
                1 + fs.iter().map(|(b, _)| self.depth(*b)).max().unwrap_or(0),
            ),
            Node::Fun(f, a) => (f.total() && self.is_total(*a), 1 + self.depth(*a)),
        };
        let id = Id(u32::try_from(self.nodes.len()).expect("more than 2^32 expression nodes"));
        self.nodes.push(n.clone());
        self.total.push(total);
        self.depth.push(depth);
        self.interned.insert(n, id);
        id
    }

    /// A constant node. A rational is stored reduced; one with more than
    /// [`MAX_EXACT_BITS`] bits in its numerator or denominator as its nearest `f64`; one with
    /// a zero denominator (`BigRational::new_raw(1, 0)`) as the `f64` ±inf or NaN, which
    /// [`Graph::eval`], [`crate::Tape::new`] and the printers refuse.
    pub fn constant(&mut self, c: Const) -> Id {
        self.intern(Node::Const(c.canonical()))
    }

    /// The variable called `name` (the same name gives the same id). Any non-empty name is
    /// accepted here; the parser accepts identifiers `[A-Za-z_][A-Za-z0-9_]*`.
    pub fn var(&mut self, name: &str) -> Id {
        self.intern(Node::Var(name.into()))
    }

    /// An `f64` constant. Never fails; a NaN or infinite constant is stored as given, and
    /// [`Graph::eval`], [`crate::Tape::new`] and the printers ([`Graph::print`], ...) then
    /// report [`ExprError::NonFiniteConstant`]. `-0.0` is stored as `0.0`.
    pub fn num(&mut self, x: f64) -> Id {
        self.constant(Const::float(x))
    }

    /// An exact integer constant.
    pub fn int(&mut self, n: i64) -> Id {
        self.constant(Const::int(n))
    }

    /// The exact rational `num/den` (reduced; as its nearest `f64` beyond
    /// [`MAX_EXACT_BITS`]). A zero denominator gives the exact expression `num · 0^(-1)`,
    /// which evaluates to [`ExprError::DivisionByZero`].
    pub fn rational(&mut self, num: impl Into<BigInt>, den: impl Into<BigInt>) -> Id {
        let (n, d) = (num.into(), den.into());
        if d.is_zero() {
            let a = self.constant(Const::Rat(BigRational::from_integer(n)));
            let z = self.int(0);
            return self.div(a, z);
        }
        self.constant(Const::Rat(BigRational::new_raw(n, d)))
    }

    /// The exact rational constant `r` (as [`Graph::constant`]: its nearest `f64` beyond
    /// [`MAX_EXACT_BITS`]).
    pub fn rat(&mut self, r: BigRational) -> Id {
        self.constant(Const::Rat(r))
    }

    /// The symbolic constant π.
    pub fn pi(&mut self) -> Id {
        self.intern(Node::Pi)
    }

    /// The constant value of `e` if it is a constant node.
    pub fn as_const(&self, e: Id) -> Option<&Const> {
        match self.node(e) {
            Node::Const(c) => Some(c),
            _ => None,
        }
    }

    /// `a + b`.
    pub fn add(&mut self, a: Id, b: Id) -> Id {
        self.sum(&[a, b])
    }

    /// `a - b`.
    pub fn sub(&mut self, a: Id, b: Id) -> Id {
        self.lin_canonical(&[(Const::int(1), a), (Const::int(-1), b)])
    }

    /// `-a`.
    pub fn neg(&mut self, a: Id) -> Id {
        self.scale(&Const::int(-1), a)
    }

    /// `a · b`.
    pub fn mul(&mut self, a: Id, b: Id) -> Id {
        self.prod(&[(a, 1), (b, 1)])
    }

    /// `a / b` (stored as `a · b^(-1)`).
    pub fn div(&mut self, a: Id, b: Id) -> Id {
        self.prod(&[(a, 1), (b, -1)])
    }

    /// `a^n` for an integer `n` (`a^0 = 1`; `n = i32::MIN` is kept as `a^(n/2)·a^(n/2)`, so
    /// that every exponent can be negated).
    pub fn powi(&mut self, a: Id, n: i32) -> Id {
        self.prod(&[(a, n)])
    }

    /// The sum of all terms, flattened into one n-ary sum with like terms collected.
    pub fn sum(&mut self, terms: &[Id]) -> Id {
        let one = Const::int(1);
        let lin: Vec<(Const, Id)> = terms.iter().map(|&t| (one.clone(), t)).collect();
        self.lin_canonical(&lin)
    }

    /// The product of all factors, flattened, with equal bases combined.
    pub fn product(&mut self, factors: &[Id]) -> Id {
        let fs: Vec<(Id, i32)> = factors.iter().map(|&f| (f, 1)).collect();
        self.prod(&fs)
    }

    /// `c · a` for a constant `c`.
    pub fn scale(&mut self, c: &Const, a: Id) -> Id {
        let cid = self.constant(c.clone());
        self.prod(&[(cid, 1), (a, 1)])
    }

    /// Splits `t` into (coefficient, rest) with `t = coefficient · rest`.
    fn split(&self, t: Id) -> (Const, Id) {
        if let Node::Mul(c, _) = self.node(t) {
            if let Some(&u) = self.unit.get(&t) {
                return (c.clone(), u);
            }
        }
        (Const::int(1), t)
    }

    /// The linear combination `Σ k_i · t_i`, flattened, like terms collected, constants
    /// folded.
    pub fn lin(&mut self, terms: &[(Const, Id)]) -> Id {
        let terms: Vec<(Const, Id)> = terms
            .iter()
            .map(|(k, t)| (k.clone().canonical(), *t))
            .collect();
        self.lin_canonical(&terms)
    }

    /// [`Graph::lin`] of coefficients already in canonical form (the engine's own).
    fn lin_canonical(&mut self, terms: &[(Const, Id)]) -> Id {
        let mut c = Const::int(0);
        let mut list: Vec<(Id, Const)> = Vec::with_capacity(terms.len());
        for (k, t) in terms {
            match self.node(*t) {
                Node::Const(x) => c = c.add(&k.mul(x)),
                Node::Add(c0, ts) => {
                    c = c.add(&k.mul(c0));
                    list.extend(ts.iter().map(|(ki, ti)| (*ti, k.mul(ki))));
                }
                _ => {
                    let (m, u) = self.split(*t);
                    list.push((u, k.mul(&m)));
                }
            }
        }
        list.sort_by_key(|a| a.0);
        let mut merged: Vec<(Const, Id)> = Vec::with_capacity(list.len());
        for (t, k) in list {
            match merged.last_mut() {
                Some(last) if last.1 == t => last.0 = last.0.add(&k),
                _ => merged.push((k, t)),
            }
        }
        // x - x = 0 only where x is defined everywhere; otherwise keep 0·x (NaN stays NaN).
        merged.retain(|(k, t)| !(k.is_zero() && self.is_total(*t)));
        if merged.is_empty() {
            return self.constant(c);
        }
        if c.is_zero() && merged.len() == 1 {
            let (k, t) = merged.pop().expect("one term");
            if k.is_one() {
                return t;
            }
            let kid = self.constant(k);
            return self.prod(&[(kid, 1), (t, 1)]);
        }
        self.intern(Node::Add(c, merged.into_boxed_slice()))
    }

    /// The product `Π f_i ^ e_i`, flattened, equal bases combined (when their exponents have
    /// the same sign, so `x/x` is not folded to 1), constants folded, a constant distributed
    /// over a single sum.
    pub fn prod(&mut self, factors: &[(Id, i32)]) -> Id {
        let mut c = Const::int(1);
        let mut list: Vec<(Id, i32)> = Vec::with_capacity(factors.len());
        for &(t, e) in factors {
            self.push_factor(t, e, &mut c, &mut list);
        }
        list.sort();
        let mut merged: Vec<(Id, i32)> = Vec::with_capacity(list.len());
        for (b, e) in list {
            match merged.last_mut() {
                Some(last) if last.0 == b && (last.1 > 0) == (e > 0) => {
                    match last.1.checked_add(e).filter(|&s| s != i32::MIN) {
                        Some(s) => last.1 = s,
                        None => merged.push((b, e)),
                    }
                }
                _ => merged.push((b, e)),
            }
        }
        if c.is_zero() && merged.iter().all(|&(b, e)| e > 0 && self.is_total(b)) {
            return self.constant(c);
        }
        if merged.is_empty() {
            return self.constant(c);
        }
        if merged.len() == 1 && merged[0].1 == 1 {
            let b = merged[0].0;
            if c.is_one() {
                return b;
            }
            if let Node::Add(c0, ts) = self.node(b) {
                // Distribute: c·(a + b) = c·a + c·b keeps sums flat and signs canonical.
                let mut lin: Vec<(Const, Id)> = ts.iter().map(|(k, t)| (k.mul(&c), *t)).collect();
                let cc = c0.mul(&c);
                let cid = self.constant(cc);
                lin.push((Const::int(1), cid));
                return self.lin_canonical(&lin);
            }
        }
        let unit = if c.is_one() {
            None
        } else if merged.len() == 1 && merged[0].1 == 1 {
            Some(merged[0].0)
        } else {
            Some(self.intern(Node::Mul(Const::int(1), merged.clone().into_boxed_slice())))
        };
        let id = self.intern(Node::Mul(c, merged.into_boxed_slice()));
        if let Some(u) = unit {
            self.unit.insert(id, u);
        }
        id
    }

    fn push_factor(&mut self, t: Id, e: i32, c: &mut Const, list: &mut Vec<(Id, i32)>) {
        if e == 0 {
            return;
        }
        if e == i32::MIN {
            // No exponent is i32::MIN (its negation overflows): t^(-2^31) = t^(-2^30)·t^(-2^30).
            self.push_factor(t, e / 2, c, list);
            self.push_factor(t, e / 2, c, list);
            return;
        }
        match self.node(t).clone() {
            Node::Const(x) => match x.powi(e) {
                Some(p) => *c = c.mul(&p),
                None => list.push((t, e)),
            },
            Node::Mul(m, fs) => {
                let scaled: Option<Vec<(Id, i32)>> = fs
                    .iter()
                    .map(|&(b, k)| {
                        k.checked_mul(e)
                            .filter(|&ke| ke != i32::MIN)
                            .map(|ke| (b, ke))
                    })
                    .collect();
                match (m.powi(e), scaled) {
                    (Some(p), Some(scaled)) => {
                        *c = c.mul(&p);
                        list.extend(scaled);
                    }
                    _ => list.push((t, e)),
                }
            }
            // |x|^(2k) = x^(2k).
            Node::Fun(Func::Abs, a) if e % 2 == 0 => self.push_factor(a, e, c, list),
            _ => list.push((t, e)),
        }
    }

    /// `f(a)`, folded where exact (`|−3| = 3`, `sqrt(9/4) = 3/2`, `sin(0) = 0`, ...) or when
    /// the argument is an `f64` constant; `|−x| = |x|`, `|c·x| = |c|·|x|`, `||x|| = |x|`,
    /// `|x^2| = x^2`, `sqrt(x^2) = |x|`.
    pub fn fun(&mut self, f: Func, a: Id) -> Id {
        if let Node::Const(c) = self.node(a).clone() {
            if let Some(r) = fold_fun(f, &c) {
                return self.constant(r);
            }
        }
        match (f, self.node(a).clone()) {
            (Func::Abs, Node::Fun(Func::Abs, _)) => return a,
            (Func::Abs, Node::Mul(m, fs)) => {
                if fs.iter().all(|&(_, e)| e % 2 == 0) {
                    // Even powers: the product has the sign of its coefficient.
                    let u = self.split(a).1;
                    return self.scale(&m.abs(), u);
                }
                if !m.is_one() {
                    let u = self.split(a).1;
                    let au = self.fun(Func::Abs, u);
                    return self.scale(&m.abs(), au);
                }
            }
            (Func::Abs, Node::Add(_, ts)) if ts[0].0.is_negative() => {
                let na = self.neg(a);
                return self.fun(Func::Abs, na);
            }
            (Func::Sign, Node::Mul(m, _)) if !m.is_one() => {
                let u = self.split(a).1;
                let su = self.fun(Func::Sign, u);
                let s = if m.is_negative() { -1 } else { 1 };
                return self.scale(&Const::int(s), su);
            }
            (Func::Sqrt, Node::Mul(m, fs)) if m.is_one() && fs.len() == 1 && fs[0].1 == 2 => {
                return self.fun(Func::Abs, fs[0].0);
            }
            _ => {}
        }
        self.intern(Node::Fun(f, a))
    }

    /// `|a|`.
    pub fn abs(&mut self, a: Id) -> Id {
        self.fun(Func::Abs, a)
    }
    /// `sign(a)`.
    pub fn sign(&mut self, a: Id) -> Id {
        self.fun(Func::Sign, a)
    }
    /// `sqrt(a)`.
    pub fn sqrt(&mut self, a: Id) -> Id {
        self.fun(Func::Sqrt, a)
    }
    /// `sin(a)`.
    pub fn sin(&mut self, a: Id) -> Id {
        self.fun(Func::Sin, a)
    }
    /// `cos(a)`.
    pub fn cos(&mut self, a: Id) -> Id {
        self.fun(Func::Cos, a)
    }
    /// `tan(a)`.
    pub fn tan(&mut self, a: Id) -> Id {
        self.fun(Func::Tan, a)
    }
    /// `exp(a)`.
    pub fn exp(&mut self, a: Id) -> Id {
        self.fun(Func::Exp, a)
    }
    /// `ln(a)`.
    pub fn ln(&mut self, a: Id) -> Id {
        self.fun(Func::Ln, a)
    }
    /// `atan(a)`.
    pub fn atan(&mut self, a: Id) -> Id {
        self.fun(Func::Atan, a)
    }
    /// `asin(a)`.
    pub fn asin(&mut self, a: Id) -> Id {
        self.fun(Func::Asin, a)
    }
    /// `acos(a)`.
    pub fn acos(&mut self, a: Id) -> Id {
        self.fun(Func::Acos, a)
    }
    /// `sinh(a)`.
    pub fn sinh(&mut self, a: Id) -> Id {
        self.fun(Func::Sinh, a)
    }
    /// `cosh(a)`.
    pub fn cosh(&mut self, a: Id) -> Id {
        self.fun(Func::Cosh, a)
    }
    /// `tanh(a)`.
    pub fn tanh(&mut self, a: Id) -> Id {
        self.fun(Func::Tanh, a)
    }

    /// Every node reachable from `roots`, in ascending id order (a topological order:
    /// children first). No recursion, so any depth is fine.
    pub fn reachable(&self, roots: &[Id]) -> Vec<Id> {
        let mut seen = vec![false; self.nodes.len()];
        let mut stack: Vec<Id> = roots.to_vec();
        let mut out = Vec::new();
        while let Some(id) = stack.pop() {
            if std::mem::replace(&mut seen[id.index()], true) {
                continue;
            }
            out.push(id);
            self.for_each_child(id, |c| stack.push(c));
        }
        out.sort();
        out
    }

    /// Calls `f` on every child of `id` (with repetition for repeated children).
    pub fn for_each_child(&self, id: Id, mut f: impl FnMut(Id)) {
        match self.node(id) {
            Node::Const(_) | Node::Var(_) | Node::Pi => {}
            Node::Add(_, ts) => ts.iter().for_each(|(_, t)| f(*t)),
            Node::Mul(_, fs) => fs.iter().for_each(|(b, _)| f(*b)),
            Node::Fun(_, a) => f(*a),
        }
    }

    /// Rebuilds every node reachable from `roots` bottom-up: `leaf` maps leaves (or returns
    /// `None` to keep them), inner nodes are rebuilt from their mapped children with the
    /// simplifying constructors. Returns the map old id → new id.
    fn rebuild(
        &mut self,
        roots: &[Id],
        mut leaf: impl FnMut(&mut Self, Id) -> Option<Id>,
    ) -> HashMap<Id, Id> {
        let order = self.reachable(roots);
        let mut map: HashMap<Id, Id> = HashMap::with_capacity(order.len());
        for id in order {
            let new = match self.node(id).clone() {
                Node::Const(_) | Node::Var(_) | Node::Pi => leaf(self, id).unwrap_or(id),
                Node::Add(c, ts) => {
                    let changed = ts.iter().any(|(_, t)| map[t] != *t);
                    if changed {
                        let cid = self.constant(c);
                        let mut lin: Vec<(Const, Id)> =
                            ts.iter().map(|(k, t)| (k.clone(), map[t])).collect();
                        lin.push((Const::int(1), cid));
                        self.lin_canonical(&lin)
                    } else {
                        id
                    }
                }
                Node::Mul(c, fs) => {
                    let changed = fs.iter().any(|(b, _)| map[b] != *b);
                    if changed {
                        let cid = self.constant(c);
                        let mut fl: Vec<(Id, i32)> = fs.iter().map(|(b, e)| (map[b], *e)).collect();
                        fl.push((cid, 1));
                        self.prod(&fl)
                    } else {
                        id
                    }
                }
                Node::Fun(f, a) => {
                    if map[&a] != a {
                        self.fun(f, map[&a])
                    } else {
                        id
                    }
                }
            };
            map.insert(id, new);
        }
        map
    }

    /// `e` with the variable `var` replaced by the expression `by` (simplified again, so
    /// substituting a knot into the ramp gives exactly 0 or 1 with rational knots).
    pub fn substitute(&mut self, e: Id, var: &str, by: Id) -> Id {
        self.substitute_many(&[e], &[(var, by)])[0]
    }

    /// Substitutes several variables at once in several roots (simultaneously: a
    /// replacement is not substituted again).
    pub fn substitute_many(&mut self, roots: &[Id], subs: &[(&str, Id)]) -> Vec<Id> {
        let map = self.rebuild(roots, |g, id| match g.node(id) {
            Node::Var(name) => subs.iter().find(|(v, _)| **v == **name).map(|(_, by)| *by),
            _ => None,
        });
        roots.iter().map(|r| map[r]).collect()
    }

    /// The symbolic derivative of `e` with respect to `var`. `abs' = sign` (so the
    /// derivative of `|x|` at 0 is 0), `sign' = 0`; the derivative is simplified as it is
    /// built and shares nodes with `e`.
    pub fn diff(&mut self, e: Id, var: &str) -> Id {
        let order = self.reachable(&[e]);
        let zero = self.int(0);
        let mut d: HashMap<Id, Id> = HashMap::with_capacity(order.len());
        for id in order {
            let de = match self.node(id).clone() {
                Node::Const(_) | Node::Pi => zero,
                Node::Var(name) => {
                    if &*name == var {
                        self.int(1)
                    } else {
                        zero
                    }
                }
                Node::Add(_, ts) => {
                    let lin: Vec<(Const, Id)> = ts
                        .iter()
                        .filter(|(_, t)| d[t] != zero)
                        .map(|(k, t)| (k.clone(), d[t]))
                        .collect();
                    self.lin_canonical(&lin)
                }
                Node::Mul(c, fs) => {
                    let mut terms = Vec::new();
                    for (i, &(b, e)) in fs.iter().enumerate() {
                        if d[&b] == zero {
                            continue;
                        }
                        let mut f: Vec<(Id, i32)> = Vec::with_capacity(fs.len() + 2);
                        for (j, &(bj, ej)) in fs.iter().enumerate() {
                            if j != i {
                                f.push((bj, ej));
                            }
                        }
                        if e != 1 {
                            f.push((b, e - 1));
                        }
                        f.push((d[&b], 1));
                        let t = self.prod(&f);
                        terms.push((c.mul(&Const::int(e as i64)), t));
                    }
                    self.lin_canonical(&terms)
                }
                Node::Fun(f, a) => {
                    let da = d[&a];
                    if da == zero {
                        zero
                    } else {
                        let outer = self.fun_deriv(f, a, id);
                        self.mul(outer, da)
                    }
                }
            };
            d.insert(id, de);
        }
        d[&e]
    }

    /// f'(a) where `fa` is the node f(a).
    fn fun_deriv(&mut self, f: Func, a: Id, fa: Id) -> Id {
        let one = self.int(1);
        match f {
            Func::Abs => self.sign(a),
            Func::Sign => self.int(0),
            Func::Sqrt => {
                let h = Const::Rat(BigRational::new(1.into(), 2.into()));
                let r = self.powi(fa, -1);
                self.scale(&h, r)
            }
            Func::Sin => self.cos(a),
            Func::Cos => {
                let s = self.sin(a);
                self.neg(s)
            }
            Func::Tan => {
                let t2 = self.powi(fa, 2);
                self.add(one, t2)
            }
            Func::Exp => fa,
            Func::Ln => self.powi(a, -1),
            Func::Atan => {
                let a2 = self.powi(a, 2);
                let s = self.add(one, a2);
                self.powi(s, -1)
            }
            Func::Asin | Func::Acos => {
                let a2 = self.powi(a, 2);
                let s = self.sub(one, a2);
                let r = self.sqrt(s);
                let inv = self.powi(r, -1);
                if f == Func::Asin {
                    inv
                } else {
                    self.neg(inv)
                }
            }
            Func::Sinh => self.cosh(a),
            Func::Cosh => self.sinh(a),
            Func::Tanh => {
                let t2 = self.powi(fa, 2);
                self.sub(one, t2)
            }
        }
    }

    /// The number of arithmetic operations of the DAG reachable from `roots`, each shared
    /// node counted once: an n-term sum costs n−1 additions (+1 for a constant term, +1 per
    /// coefficient other than ±1), a product n−1 multiplications or divisions (+1 for a
    /// coefficient other than 1), each distinct power `b^k` (|k| ≥ 2) 1 however many
    /// products use it (the [`crate::Tape`] computes it once), a function call 1.
    pub fn op_count(&self, roots: &[Id]) -> usize {
        let mut n = 0;
        let mut powers: std::collections::HashSet<(Id, u32)> = std::collections::HashSet::new();
        for id in self.reachable(roots) {
            n += match self.node(id) {
                Node::Const(_) | Node::Var(_) | Node::Pi => 0,
                Node::Add(c, ts) => {
                    ts.len() - 1
                        + usize::from(!c.is_zero())
                        + ts.iter()
                            .filter(|(k, _)| !k.is_one() && !k.is_minus_one())
                            .count()
                        + usize::from(ts.iter().all(|(k, _)| k.is_negative()))
                }
                Node::Mul(c, fs) => {
                    fs.len() - 1
                        + usize::from(!c.is_one())
                        + usize::from(fs.iter().all(|(_, e)| *e < 0))
                        + fs.iter()
                            .filter(|(b, e)| {
                                e.unsigned_abs() >= 2 && powers.insert((*b, e.unsigned_abs()))
                            })
                            .count()
                }
                Node::Fun(..) => 1,
            };
        }
        n
    }

    /// The names of the variables `roots` depend on, sorted.
    pub fn variables(&self, roots: &[Id]) -> Vec<String> {
        let mut v: Vec<String> = self
            .reachable(roots)
            .into_iter()
            .filter_map(|id| match self.node(id) {
                Node::Var(n) => Some(n.to_string()),
                _ => None,
            })
            .collect();
        v.sort();
        v
    }

    /// The first node reachable from `roots` (in topological order) that depends on no
    /// variable and has no finite `f64` value: a function of a constant outside its domain
    /// (`asin(3/2)`, `sqrt(-2)`, `ln(0)`, which the engine keeps unfolded), a division by an
    /// exact zero, or a constant beyond the range of `f64`. Such a node makes every value of
    /// the expression NaN or infinite whatever the variables; `None` when there is none.
    ///
    /// ```
    /// use geomkit_expr::{parse, Graph};
    /// let mut g = Graph::new();
    /// let ok = parse(&mut g, "asin(x) + asin(1/2)").unwrap();
    /// assert_eq!(g.undefined_constant(&[ok]), None);
    /// let bad = parse(&mut g, "x + asin(3/2)").unwrap();
    /// let at = g.undefined_constant(&[bad]).unwrap();
    /// assert!(g.eval(at, &[]).unwrap().is_nan());
    /// ```
    pub fn undefined_constant(&self, roots: &[Id]) -> Option<Id> {
        let order = self.reachable(roots);
        // The value of each node that depends on no variable (children come first: ids
        // are given out bottom-up).
        let mut val: HashMap<Id, Option<f64>> = HashMap::with_capacity(order.len());
        for id in order {
            let mut constant = !matches!(self.node(id), Node::Var(_));
            self.for_each_child(id, |c| constant &= val[&c].is_some());
            let x = if constant {
                match self.eval_node(id, |c| val[&c].unwrap_or(f64::NAN), |_| None) {
                    Ok(x) if x.is_finite() => Some(x),
                    _ => return Some(id),
                }
            } else {
                None
            };
            val.insert(id, x);
        }
        None
    }

    /// The value of `e` in `f64` with the given variable values.
    ///
    /// # Errors
    /// [`ExprError::UnknownVariable`] for a variable without a value,
    /// [`ExprError::DivisionByZero`] for a division by an exact-zero constant,
    /// [`ExprError::NonFiniteConstant`] for a NaN or infinite constant,
    /// [`ExprError::ConstantOutOfRange`] for an exact constant outside the range of `f64`
    /// (such as `10^400` or `10^-400`: its `f64` would be infinite or zero). A division by a sub-expression that happens to be zero follows `f64`
    /// (±inf or NaN), as do values that overflow.
    ///
    /// ```
    /// use geomkit_expr::{parse, Graph};
    /// let mut g = Graph::new();
    /// let e = parse(&mut g, "abs(u - 1) / 2 + v^2").unwrap();
    /// assert_eq!(g.eval(e, &[("u", -1.0), ("v", 3.0)]).unwrap(), 10.0);
    /// ```
    pub fn eval(&self, e: Id, vars: &[(&str, f64)]) -> Result<f64> {
        let order = self.reachable(&[e]);
        let mut val: HashMap<Id, f64> = HashMap::with_capacity(order.len());
        for id in order {
            let x = self.eval_node(
                id,
                |c| val[&c],
                |name| vars.iter().find(|(n, _)| *n == name).map(|(_, x)| *x),
            )?;
            val.insert(id, x);
        }
        Ok(val[&e])
    }

    /// The constants a node holds itself: the constant of a constant node, the constant
    /// term and coefficients of a sum, the coefficient of a product.
    pub(crate) fn node_constants(&self, id: Id) -> impl Iterator<Item = &Const> {
        let (first, rest): (Option<&Const>, &[(Const, Id)]) = match self.node(id) {
            Node::Const(c) | Node::Mul(c, _) => (Some(c), &[]),
            Node::Add(c, ts) => (Some(c), ts),
            Node::Var(_) | Node::Pi | Node::Fun(..) => (None, &[]),
        };
        first.into_iter().chain(rest.iter().map(|t| &t.0))
    }

    /// [`ExprError::NonFiniteConstant`] if the node itself holds a NaN or infinite constant
    /// (as a constant, a constant term or a coefficient), [`ExprError::ConstantOutOfRange`]
    /// for an exact one outside the range of `f64`.
    pub(crate) fn check_constants(&self, id: Id) -> Result<()> {
        self.node_constants(id).try_for_each(Const::check)
    }

    /// The value of one node from its children's values.
    pub(crate) fn eval_node(
        &self,
        id: Id,
        child: impl Fn(Id) -> f64,
        var: impl Fn(&str) -> Option<f64>,
    ) -> Result<f64> {
        self.check_constants(id)?;
        Ok(match self.node(id) {
            Node::Const(c) => c.to_f64(),
            Node::Pi => std::f64::consts::PI,
            Node::Var(name) => var(name).ok_or_else(|| ExprError::UnknownVariable {
                name: name.to_string(),
            })?,
            Node::Add(c, ts) => {
                let mut s = 0.0;
                for (k, t) in ts.iter() {
                    let x = child(*t);
                    s += if k.is_one() {
                        x
                    } else if k.is_minus_one() {
                        -x
                    } else {
                        k.to_f64() * x
                    };
                }
                s + c.to_f64()
            }
            Node::Mul(c, fs) => {
                let (mut num, mut den, mut has_num) = (1.0, 1.0, false);
                for &(b, e) in fs.iter() {
                    if matches!(self.node(b), Node::Const(z) if z.is_zero()) && e < 0 {
                        return Err(ExprError::DivisionByZero);
                    }
                    let x = child(b);
                    if e > 0 {
                        num *= powi(x, e);
                        has_num = true;
                    } else {
                        den *= powi(x, -e);
                    }
                }
                // As the tape and the printed code: c/den without a numerator (not
                // c·(1/den), which is 0·inf = NaN for c = 0 and a subnormal den).
                if !has_num {
                    c.to_f64() / den
                } else if den == 1.0 {
                    c.to_f64() * num
                } else {
                    c.to_f64() * (num / den)
                }
            }
            Node::Fun(f, a) => f.apply(child(*a)),
        })
    }
}

/// `x^n` for `n >= 1` by repeated squaring (the same rounding as the printed C code's
/// repeated multiplication for n <= 3).
#[inline(always)]
pub(crate) fn powi(x: f64, n: i32) -> f64 {
    match n {
        1 => x,
        2 => x * x,
        3 => x * x * x,
        _ => x.powi(n),
    }
}

/// Exact or `f64` folding of a function of a constant; `None` keeps it symbolic.
fn fold_fun(f: Func, c: &Const) -> Option<Const> {
    match c {
        // Folded only to a finite value: `sqrt(-2.5)` or `exp(1e300)` stay as they are (and
        // evaluate as f64 would), as `sqrt(-2)` does.
        Const::Float(x) => {
            let y = f.apply(*x);
            y.is_finite().then(|| Const::float(y))
        }
        Const::Rat(r) => {
            let zero = r.is_zero();
            match f {
                Func::Abs => Some(Const::Rat(r.abs())),
                Func::Sign => Some(Const::int(if zero {
                    0
                } else if r.is_negative() {
                    -1
                } else {
                    1
                })),
                Func::Sqrt => {
                    if r.is_negative() {
                        return None;
                    }
                    let (n, d) = (r.numer(), r.denom());
                    let (sn, sd) = (n.sqrt(), d.sqrt());
                    (&sn * &sn == *n && &sd * &sd == *d)
                        .then(|| Const::Rat(BigRational::new(sn, sd)))
                }
                Func::Sin | Func::Tan | Func::Atan | Func::Asin | Func::Sinh | Func::Tanh
                    if zero =>
                {
                    Some(Const::int(0))
                }
                Func::Cos | Func::Exp | Func::Cosh if zero => Some(Const::int(1)),
                Func::Ln if r.is_one() => Some(Const::int(0)),
                Func::Acos if r.is_one() => Some(Const::int(0)),
                _ => None,
            }
        }
    }
}
