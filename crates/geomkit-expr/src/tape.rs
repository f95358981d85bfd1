//! The batched evaluator: the DAG compiled to a register program run over blocks of
//! [`LANES`] points, one instruction at a time over the whole block, so every inner loop is
//! a plain slice loop the compiler vectorizes.

use std::collections::HashMap;
use std::ops::Range;

use crate::error::{ExprError, Result};
use crate::graph::{powi, Func, Graph, Id, Node};

/// Points per block: each instruction runs over this many points at once.
pub const LANES: usize = 512;

type Block = [f64; LANES];

#[derive(Clone, Copy, Debug)]
enum Op {
    Mul(u32, u32, u32),
    Div(u32, u32, u32),
    AddC(u32, u32, f64),
    MulC(u32, u32, f64),
    /// d = c / a.
    RDivC(u32, u32, f64),
    /// d = a / c.
    DivC(u32, u32, f64),
    Neg(u32, u32),
    Square(u32, u32),
    Cube(u32, u32),
    Powi(u32, u32, i32),
    Fun(u32, u32, Func),
    /// d = k0·x0 + k1·x1 + … (+ c), left to right, over the terms `start..start + len` of
    /// [`Tape::terms`] (2 to [`LIN`] of them): a sum in one pass instead of one per term.
    Lin(u32, u32, u32, Option<f64>),
    /// d = Σ k·|k_in·x + a| (+ c) over the terms `start..start + len` of
    /// [`Tape::ramp_terms`] (2 to [`LIN`] of them), left to right: the papers' sums of
    /// |t − a_j| in one variable, in one pass that reads x alone.
    AbsSum(u32, u32, u32, u32, Option<f64>),
    /// d = |a + c| (the ramps' |t − a| of the papers' formulas).
    AbsAddC(u32, u32, f64),
    /// d = c·(a·b).
    MulMulC(u32, u32, u32, f64),
}

impl Op {
    /// The register (or, from [`OUT`] on, the output) the instruction writes.
    fn dest_mut(&mut self) -> &mut u32 {
        match self {
            Op::Mul(d, ..)
            | Op::Div(d, ..)
            | Op::AddC(d, ..)
            | Op::MulC(d, ..)
            | Op::RDivC(d, ..)
            | Op::DivC(d, ..)
            | Op::Neg(d, ..)
            | Op::Square(d, ..)
            | Op::Cube(d, ..)
            | Op::Powi(d, ..)
            | Op::Fun(d, ..)
            | Op::AbsAddC(d, ..)
            | Op::MulMulC(d, ..)
            | Op::Lin(d, ..)
            | Op::AbsSum(d, ..) => d,
        }
    }

    /// The registers the instruction reads (`terms`: the tape's, for [`Op::Lin`]).
    fn sources<'a>(&self, terms: &'a [(u32, f64)]) -> impl Iterator<Item = u32> + 'a {
        let (pair, sum): ([Option<u32>; 2], &[(u32, f64)]) = match *self {
            Op::Lin(_, start, len, _) => ([None, None], &terms[start as usize..][..len as usize]),
            Op::Mul(_, a, b) | Op::Div(_, a, b) | Op::MulMulC(_, a, b, _) => {
                ([Some(a), Some(b)], &[])
            }
            Op::AddC(_, a, _)
            | Op::MulC(_, a, _)
            | Op::RDivC(_, a, _)
            | Op::DivC(_, a, _)
            | Op::Neg(_, a)
            | Op::Square(_, a)
            | Op::Cube(_, a)
            | Op::Powi(_, a, _)
            | Op::Fun(_, a, _)
            | Op::AbsAddC(_, a, _)
            | Op::AbsSum(_, a, ..) => ([Some(a), None], &[]),
        };
        pair.into_iter().flatten().chain(sum.iter().map(|t| t.0))
    }

    /// [`Op::dest_mut`], by value.
    fn dest(mut self) -> u32 {
        *self.dest_mut()
    }

    /// Whether the instruction reads register `r`.
    fn reads(&self, r: u32, terms: &[(u32, f64)]) -> bool {
        self.sources(terms).any(|s| s == r)
    }
}

/// The most terms of one [`Op::Lin`]; longer sums chain several.
const LIN: usize = 4;

/// Destination `OUT + k` of an instruction is output `k` itself: the root's values are
/// written where the caller wants them, not into a register and then copied.
const OUT: u32 = 1 << 31;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Val {
    Reg(u32),
    Imm(f64),
}

/// Where a root's values come from, after the program has run over a block.
#[derive(Clone, Copy, Debug)]
enum Sink {
    /// Its instruction wrote them into the output.
    Written,
    /// Input or register `r` (a root read by later instructions, a root that is also
    /// another root, or a variable).
    Copy(u32),
    /// A constant.
    Fill(f64),
}

/// A compiled, batched evaluator of several expressions in the same variables.
///
/// ```
/// use geomkit_expr::{parse, Graph, Tape};
/// let mut g = Graph::new();
/// let x = parse(&mut g, "abs(u - 1) + v^2").unwrap();
/// let tape = Tape::new(&g, &[x], &["u", "v"]).unwrap();
/// let (u, v) = ([0.0, 1.0, 3.0], [1.0, 2.0, 0.5]);
/// let mut out = [0.0; 3];
/// tape.eval_batch(&[&u, &v], &mut [&mut out]).unwrap();
/// assert_eq!(out, [2.0, 4.0, 2.25]);
/// ```
#[derive(Clone, Debug)]
pub struct Tape {
    ops: Vec<Op>,
    /// The (register, coefficient) terms of the [`Op::Lin`] sums.
    terms: Vec<(u32, f64)>,
    /// The (k, k_in, a) terms k·|k_in·x + a| of the [`Op::AbsSum`] sums.
    ramp_terms: Vec<[f64; 3]>,
    nregs: usize,
    nvars: usize,
    /// Where each root's values come from.
    sinks: Vec<Sink>,
}

struct Alloc {
    free: Vec<u32>,
    next: u32,
}

impl Alloc {
    fn get(&mut self) -> u32 {
        self.free.pop().unwrap_or_else(|| {
            self.next += 1;
            self.next - 1
        })
    }
}

impl Tape {
    /// Compiles `roots` as functions of `vars` (in this order, the order of the inputs of
    /// [`Tape::eval_batch`]). Sub-expressions without variables are folded to constants.
    ///
    /// # Errors
    /// [`ExprError::UnknownVariable`] if a root uses a variable not in `vars`,
    /// [`ExprError::DuplicateVariable`], [`ExprError::DivisionByZero`] (division by an exact
    /// zero constant; a folded sub-expression that is 0 divides as `f64`, as in
    /// [`Graph::eval`]), [`ExprError::NonFiniteConstant`].
    pub fn new(g: &Graph, roots: &[Id], vars: &[&str]) -> Result<Self> {
        for (i, v) in vars.iter().enumerate() {
            if vars[..i].contains(v) {
                return Err(ExprError::DuplicateVariable {
                    name: v.to_string(),
                });
            }
        }
        let order = g.reachable(roots);
        let pos: HashMap<Id, usize> = order.iter().enumerate().map(|(i, &id)| (id, i)).collect();
        let mut last_use = vec![0usize; order.len()];
        let mut is_const = vec![false; order.len()];
        for (i, &id) in order.iter().enumerate() {
            let mut all_const = !matches!(g.node(id), Node::Var(_));
            g.for_each_child(id, |c| {
                last_use[pos[&c]] = i;
                all_const &= is_const[pos[&c]];
            });
            is_const[i] = all_const;
        }
        for r in roots {
            last_use[pos[r]] = usize::MAX;
        }
        // Powers b^k (k >= 2) are computed once and shared by every product that uses them.
        let mut pow_last: HashMap<(Id, u32), usize> = HashMap::new();
        for (i, &id) in order.iter().enumerate() {
            if let Node::Mul(_, fs) = g.node(id) {
                for &(b, e) in fs.iter() {
                    if e.unsigned_abs() >= 2 {
                        pow_last.insert((b, e.unsigned_abs()), i);
                    }
                }
            }
        }
        let mut pow_reg: HashMap<(Id, u32), u32> = HashMap::new();
        let nvars = vars.len();
        let mut alloc = Alloc {
            free: Vec::new(),
            next: nvars as u32,
        };
        let mut ops = Vec::new();
        let mut terms: Vec<(u32, f64)> = Vec::new();
        let mut ramp_terms: Vec<[f64; 3]> = Vec::new();
        let mut val: Vec<Val> = Vec::with_capacity(order.len());
        let mut consts: Vec<f64> = vec![0.0; order.len()];
        for (i, &id) in order.iter().enumerate() {
            g.check_constants(id)?;
            if is_const[i] {
                let x = g.eval_node(id, |c| consts[pos[&c]], |_| None)?;
                consts[i] = x;
                val.push(Val::Imm(x));
                continue;
            }
            let v = match g.node(id) {
                Node::Var(name) => match vars.iter().position(|v| **v == **name) {
                    Some(k) => Val::Reg(k as u32),
                    None => {
                        return Err(ExprError::UnknownVariable {
                            name: name.to_string(),
                        })
                    }
                },
                Node::Const(_) | Node::Pi => unreachable!("constants are folded"),
                Node::Add(c, ts) => {
                    let mut imm = c.to_f64();
                    let mut regs: Vec<(f64, u32)> = Vec::new();
                    let mut ids: Vec<Id> = Vec::new();
                    for (k, t) in ts.iter() {
                        match val[pos[t]] {
                            Val::Imm(x) => imm += k.to_f64() * x,
                            Val::Reg(r) => {
                                regs.push((k.to_f64(), r));
                                ids.push(*t);
                            }
                        }
                    }
                    // Start from a term with coefficient 1 when there is one.
                    if let Some(j) = regs.iter().position(|(k, _)| *k == 1.0) {
                        regs.swap(0, j);
                        ids.swap(0, j);
                    }
                    let var_reg = |id: Id| match val[pos[&id]] {
                        Val::Reg(r) if (r as usize) < nvars => Some(r),
                        _ => None,
                    };
                    let ramps = abs_terms(g, &regs, &ids, var_reg);
                    let mut em = Emitter {
                        ops: &mut ops,
                        alloc: &mut alloc,
                    };
                    if let [(k0, r0)] = regs[..] {
                        let r0 = Owned::Borrowed(r0);
                        let mut acc = if k0 == 1.0 {
                            r0
                        } else if k0 == -1.0 {
                            em.un(Op::Neg, r0)
                        } else {
                            em.un(|d, a| Op::MulC(d, a, k0), r0)
                        };
                        if imm != 0.0 {
                            acc = em.un(|d, a| Op::AddC(d, a, imm), acc);
                        }
                        Val::Reg(em.finish(acc))
                    } else if let Some((x, list)) = ramps {
                        let start = ramp_terms.len() as u32;
                        ramp_terms.extend(list);
                        let d = em.alloc.get();
                        let end = (imm != 0.0).then_some(imm);
                        em.ops.push(Op::AbsSum(d, x, start, regs.len() as u32, end));
                        Val::Reg(d)
                    } else {
                        Val::Reg(em.sum(&mut terms, &regs, imm))
                    }
                }
                Node::Mul(c, fs) => {
                    let mut coef = c.to_f64();
                    let mut em = Emitter {
                        ops: &mut ops,
                        alloc: &mut alloc,
                    };
                    // Constant divisors whose reciprocal overflows (subnormal, or a power
                    // that underflows): divided by, as Graph::eval and the printed code do
                    // (v·(1/1e-320) is 0·inf = NaN at v = 0, v/1e-320 is 0).
                    let mut kden = 1.0;
                    let mut num: Option<Owned> = None;
                    let mut den: Option<Owned> = None;
                    for &(b, e) in fs.iter() {
                        match val[pos[&b]] {
                            Val::Imm(x) => {
                                // As Graph::eval: an exact-zero constant divisor is an error,
                                // a folded sub-expression that happens to be 0 follows f64.
                                if e < 0 && matches!(g.node(b), Node::Const(z) if z.is_zero()) {
                                    return Err(ExprError::DivisionByZero);
                                }
                                let r = x.powi(e);
                                if e < 0 && !r.is_finite() {
                                    kden *= x.powi(-e);
                                } else {
                                    coef *= r;
                                }
                            }
                            Val::Reg(r) => {
                                let n = e.unsigned_abs();
                                let p = if n == 1 {
                                    Owned::Borrowed(r)
                                } else if let Some(&pr) = pow_reg.get(&(b, n)) {
                                    Owned::Borrowed(pr)
                                } else {
                                    let pr = match n {
                                        2 => em.un(Op::Square, Owned::Borrowed(r)),
                                        3 => em.un(Op::Cube, Owned::Borrowed(r)),
                                        _ => em.un(
                                            |d, a| Op::Powi(d, a, n as i32),
                                            Owned::Borrowed(r),
                                        ),
                                    }
                                    .reg();
                                    pow_reg.insert((b, n), pr);
                                    Owned::Borrowed(pr)
                                };
                                let slot = if e > 0 { &mut num } else { &mut den };
                                *slot = Some(match slot.take() {
                                    None => p,
                                    Some(q) => em.bin(Op::Mul, q, p),
                                });
                            }
                        }
                    }
                    let acc = match (num, den) {
                        (Some(n), None) => n,
                        (Some(n), Some(d)) => em.bin(Op::Div, n, d),
                        (None, Some(d)) => {
                            let k = coef;
                            coef = 1.0;
                            em.un(|dst, a| Op::RDivC(dst, a, k), d)
                        }
                        (None, None) => unreachable!("a product without variables is constant"),
                    };
                    let acc = if coef == 1.0 {
                        acc
                    } else if coef == -1.0 {
                        em.un(Op::Neg, acc)
                    } else {
                        em.un(|d, a| Op::MulC(d, a, coef), acc)
                    };
                    let acc = if kden == 1.0 {
                        acc
                    } else {
                        em.un(|d, a| Op::DivC(d, a, kden), acc)
                    };
                    Val::Reg(em.finish(acc))
                }
                Node::Fun(f, a) => {
                    let Val::Reg(r) = val[pos[a]] else {
                        unreachable!("constant argument is folded")
                    };
                    let d = alloc.get();
                    ops.push(Op::Fun(d, r, *f));
                    Val::Reg(d)
                }
            };
            val.push(v);
            // Children whose last use is this node give their registers back.
            let mut freed: Vec<u32> = Vec::new();
            g.for_each_child(id, |c| {
                let p = pos[&c];
                if last_use[p] == i {
                    if let Val::Reg(r) = val[p] {
                        if r as usize >= nvars && !freed.contains(&r) {
                            freed.push(r);
                        }
                    }
                }
            });
            if let Node::Mul(_, fs) = g.node(id) {
                for &(b, e) in fs.iter() {
                    let key = (b, e.unsigned_abs());
                    if pow_last.get(&key) == Some(&i) {
                        if let Some(r) = pow_reg.remove(&key) {
                            freed.push(r);
                        }
                    }
                }
            }
            alloc.free.extend(freed);
        }
        let roots: Vec<Val> = roots.iter().map(|r| val[pos[r]]).collect();
        let ops = live(ops, &roots, &terms);
        let mut ops = fuse(ops, &roots, &terms);
        let sinks = route_outputs(&mut ops, &roots, &terms, nvars);
        Ok(Tape {
            ops,
            terms,
            ramp_terms,
            nregs: alloc.next as usize,
            nvars,
            sinks,
        })
    }

    /// Number of instructions.
    pub fn len(&self) -> usize {
        self.ops.len()
    }

    /// Whether the program has no instructions (every root is a variable or a constant).
    pub fn is_empty(&self) -> bool {
        self.ops.is_empty()
    }

    /// Number of registers (each a block of [`LANES`] `f64`).
    pub fn registers(&self) -> usize {
        self.nregs
    }

    /// Evaluates every root at every point: `inputs[k][i]` is variable `k` at point `i`,
    /// `out[r][i]` receives root `r` at point `i`. NaN and infinities follow `f64`.
    ///
    /// # Errors
    /// [`ExprError::Shape`] when the number of inputs or outputs or a length is wrong.
    pub fn eval_batch(&self, inputs: &[&[f64]], out: &mut [&mut [f64]]) -> Result<()> {
        let n = self.check_shapes(inputs, out)?;
        let mut regs: Vec<Block> = vec![[0.0; LANES]; self.nregs.max(1)];
        run(self, &mut regs, inputs, out, n);
        Ok(())
    }

    fn check_shapes(&self, inputs: &[&[f64]], out: &[&mut [f64]]) -> Result<usize> {
        let shape = |what: &str, got: usize, expected: usize| {
            Err(ExprError::Shape {
                what: what.to_string(),
                got,
                expected,
            })
        };
        if inputs.len() != self.nvars {
            return shape("number of input arrays", inputs.len(), self.nvars);
        }
        if out.len() != self.sinks.len() {
            return shape("number of output arrays", out.len(), self.sinks.len());
        }
        let n = inputs
            .first()
            .map_or_else(|| out.first().map_or(0, |o| o.len()), |x| x.len());
        for (k, x) in inputs.iter().enumerate() {
            if x.len() != n {
                return shape(&format!("length of input {k}"), x.len(), n);
            }
        }
        for (k, o) in out.iter().enumerate() {
            if o.len() != n {
                return shape(&format!("length of output {k}"), o.len(), n);
            }
        }
        Ok(n)
    }
}

/// The terms of a sum (`regs`: coefficient and register, `ids`: the nodes) as
/// (k, k_in, a) of k·|k_in·x + a| when every one is such an absolute value of the same
/// variable x (2 to [`LIN`] terms; a variable's register is never reused, where an
/// intermediate x may be gone by the time of the sum): x's register and the list, else
/// `None`. k_in·x + a is what the
/// program computes for the node inside the absolute value (`x + a` for k_in = 1, `−x + a`
/// for −1: the same bits), |x| is |1·x + 0| (x + 0 differs from x only at −0, where the
/// absolute values agree).
fn abs_terms(
    g: &Graph,
    regs: &[(f64, u32)],
    ids: &[Id],
    var_reg: impl Fn(Id) -> Option<u32>,
) -> Option<(u32, Vec<[f64; 3]>)> {
    if !(2..=LIN).contains(&regs.len()) {
        return None;
    }
    let mut x0 = None;
    let mut list = Vec::with_capacity(regs.len());
    for (&(k, _), &id) in regs.iter().zip(ids) {
        let Node::Fun(Func::Abs, arg) = g.node(id) else {
            return None;
        };
        let (x, k_in, a) = match g.node(*arg) {
            Node::Add(c, ts) if ts.len() == 1 => (var_reg(ts[0].1)?, ts[0].0.to_f64(), c.to_f64()),
            _ => (var_reg(*arg)?, 1.0, 0.0),
        };
        if *x0.get_or_insert(x) != x {
            return None;
        }
        list.push([k, k_in, a]);
    }
    Some((x0?, list))
}

/// The instructions whose results are used (by a later instruction before the register is
/// written again, or as a root): an [`Op::AbsSum`] leaves the absolute values it
/// recomputes unread.
fn live(ops: Vec<Op>, roots: &[Val], terms: &[(u32, f64)]) -> Vec<Op> {
    let mut needed: Vec<u32> = roots
        .iter()
        .filter_map(|v| match v {
            Val::Reg(r) => Some(*r),
            Val::Imm(_) => None,
        })
        .collect();
    let mut keep = vec![false; ops.len()];
    for (i, op) in ops.iter().enumerate().rev() {
        let d = op.dest();
        let Some(j) = needed.iter().position(|&r| r == d) else {
            continue;
        };
        keep[i] = true;
        needed.swap_remove(j);
        for r in op.sources(terms) {
            if !needed.contains(&r) {
                needed.push(r);
            }
        }
    }
    ops.into_iter()
        .zip(keep)
        .filter_map(|(op, k)| k.then_some(op))
        .collect()
}

/// The program with pairs of instructions merged where the first one's result is read
/// only by the second, which follows it (and whose register is not one of the first one's
/// operands: no instruction writes what it reads): `AddC` then `abs` into
/// [`Op::AbsAddC`], `Mul` then `MulC` into [`Op::MulMulC`] (the same operations in the
/// same order: the same bits, one pass over the block instead of two).
fn fuse(ops: Vec<Op>, roots: &[Val], terms: &[(u32, f64)]) -> Vec<Op> {
    // Whether register `t`, written by ops[i], is read by ops[i + 1] alone.
    let only_next = |i: usize, t: u32| {
        for op in &ops[i + 2..] {
            if op.reads(t, terms) {
                return false;
            }
            if op.dest() == t {
                return true;
            }
        }
        !roots.contains(&Val::Reg(t))
    };
    let mut out = Vec::with_capacity(ops.len());
    let mut i = 0;
    while i < ops.len() {
        let merged = match (ops[i], ops.get(i + 1).copied()) {
            (Op::AddC(t, a, c), Some(Op::Fun(d, t2, Func::Abs)))
                if t2 == t && d != a && only_next(i, t) =>
            {
                Some(Op::AbsAddC(d, a, c))
            }
            (Op::Mul(t, a, b), Some(Op::MulC(d, t2, c)))
                if t2 == t && d != a && d != b && only_next(i, t) =>
            {
                Some(Op::MulMulC(d, a, b, c))
            }
            _ => None,
        };
        match merged {
            Some(op) => {
                out.push(op);
                i += 2;
            }
            None => {
                out.push(ops[i]);
                i += 1;
            }
        }
    }
    out
}

/// The sink of every root, its instruction writing straight into the output where it can:
/// a root in a register of its own (not a variable) that is no other root and that no
/// later instruction reads.
fn route_outputs(ops: &mut [Op], roots: &[Val], terms: &[(u32, f64)], nvars: usize) -> Vec<Sink> {
    roots
        .iter()
        .enumerate()
        .map(|(k, v)| match *v {
            Val::Imm(x) => Sink::Fill(x),
            Val::Reg(r) => {
                let shared = roots.iter().filter(|w| **w == Val::Reg(r)).count() > 1;
                // A root's register is never freed: its last writer defines it.
                let last = ops.iter().rposition(|op| op.dest() == r);
                match last {
                    Some(j)
                        if r as usize >= nvars
                            && !shared
                            && !ops[j + 1..].iter().any(|op| op.reads(r, terms)) =>
                    {
                        *ops[j].dest_mut() = OUT + k as u32;
                        Sink::Written
                    }
                    _ => Sink::Copy(r),
                }
            }
        })
        .collect()
}

/// Runs the program over the `n` points, block by block, compiled for the CPU's AVX-512 or
/// AVX2 where it has them (checked once by `pulp`), else as it is: the same bits either way
/// (the loops use no fused multiply-adds), in wider instructions.
fn run(program: &Tape, regs: &mut [Block], ins: &[&[f64]], outs: &mut [&mut [f64]], n: usize) {
    let job = Job {
        program,
        regs,
        ins,
        outs,
        n,
    };
    #[cfg(target_arch = "x86_64")]
    {
        if let Some(v4) = pulp::x86::V4::try_new() {
            return v4.vectorize(job);
        }
        if let Some(v3) = pulp::x86::V3::try_new() {
            return v3.vectorize(job);
        }
    }
    pulp::NullaryFnOnce::call(job)
}

/// [`run_blocks`]'s arguments, called by `pulp` inside its target-feature function through
/// an `#[inline(always)]` method: with a closure instead, the whole loop was once compiled
/// outside it (in the closure's call shim, for the baseline CPU: half the speed).
struct Job<'a, 'o> {
    program: &'a Tape,
    regs: &'a mut [Block],
    ins: &'a [&'a [f64]],
    outs: &'a mut [&'o mut [f64]],
    n: usize,
}

impl pulp::NullaryFnOnce for Job<'_, '_> {
    type Output = ();

    #[inline(always)]
    fn call(self) {
        run_blocks(self.program, self.regs, self.ins, self.outs, self.n)
    }
}

#[inline(always)]
fn run_blocks(
    program: &Tape,
    regs: &mut [Block],
    ins: &[&[f64]],
    outs: &mut [&mut [f64]],
    n: usize,
) {
    let mut start = 0;
    let fetch = Prefetcher::new();
    while start < n {
        let at = start..LANES.min(n - start) + start;
        // The next block's inputs and outputs on their way to the cache while this one
        // runs (about a tenth off on 10^6 points, where the arrays are beyond the caches).
        let next = at.end..(at.end + LANES).min(n);
        for x in ins {
            fetch.lines(&x[next.clone()]);
        }
        for x in outs.iter() {
            fetch.lines(&x[next.clone()]);
        }
        run_ops(program, regs, ins, outs, &at);
        for (k, sink) in program.sinks.iter().enumerate() {
            match *sink {
                Sink::Written => {}
                Sink::Copy(r) => {
                    let (dst, reads) = Io {
                        regs: &mut *regs,
                        ins,
                        outs: &mut *outs,
                        at: &at,
                    }
                    .split(OUT + k as u32);
                    dst.copy_from_slice(&reads.get(r)[..dst.len()]);
                }
                Sink::Fill(x) => outs[k][at.clone()].fill(x),
            }
        }
        start = at.end;
    }
}

#[inline(always)]
fn run_ops(
    program: &Tape,
    regs: &mut [Block],
    ins: &[&[f64]],
    outs: &mut [&mut [f64]],
    at: &Range<usize>,
) {
    let (terms, ramp_terms) = (&program.terms[..], &program.ramp_terms[..]);
    for op in &program.ops {
        let io = Io {
            regs: &mut *regs,
            ins,
            outs: &mut *outs,
            at,
        };
        match *op {
            Op::Mul(d, a, b) => io.bin(d, a, b, |x, y| x * y),
            Op::Div(d, a, b) => io.bin(d, a, b, |x, y| x / y),
            Op::AddC(d, a, c) => io.un(d, a, |x| x + c),
            Op::MulC(d, a, c) => io.un(d, a, |x| c * x),
            Op::RDivC(d, a, c) => io.un(d, a, |x| c / x),
            Op::DivC(d, a, c) => io.un(d, a, |x| x / c),
            Op::Neg(d, a) => io.un(d, a, |x| -x),
            Op::Square(d, a) => io.un(d, a, |x| x * x),
            Op::Cube(d, a) => io.un(d, a, |x| x * x * x),
            Op::Powi(d, a, n) => io.un(d, a, |x| powi(x, n)),
            Op::Lin(d, start, len, c) => {
                let t = &terms[start as usize..][..len as usize];
                match c {
                    None => io.lin(d, t, |x| x),
                    Some(c) => io.lin(d, t, |x| x + c),
                }
            }
            Op::AbsSum(d, x, start, len, c) => {
                let t = &ramp_terms[start as usize..][..len as usize];
                match c {
                    None => io.abs_sum(d, x, t, |x| x),
                    Some(c) => io.abs_sum(d, x, t, |x| x + c),
                }
            }
            Op::AbsAddC(d, a, c) => io.un(d, a, |x| (x + c).abs()),
            Op::MulMulC(d, a, b, c) => io.bin(d, a, b, |x, y| c * (x * y)),
            Op::Fun(d, a, f) => match f {
                Func::Abs => io.un(d, a, f64::abs),
                Func::Sqrt => io.un(d, a, f64::sqrt),
                Func::Sign => io.un(d, a, crate::graph::sign),
                f => io.un(d, a, |x| f.apply(x)),
            },
        }
    }
}

/// Requests cache lines ahead of their use (x86-64; elsewhere nothing).
#[derive(Clone, Copy)]
struct Prefetcher {
    #[cfg(target_arch = "x86_64")]
    sse: Option<pulp::core_arch::x86::Sse>,
}

impl Prefetcher {
    fn new() -> Self {
        Prefetcher {
            #[cfg(target_arch = "x86_64")]
            sse: pulp::core_arch::x86::Sse::try_new(),
        }
    }

    /// Every cache line of `xs` (a request: nothing waits for it).
    #[inline(always)]
    fn lines(self, xs: &[f64]) {
        #[cfg(target_arch = "x86_64")]
        if let Some(sse) = self.sse {
            for x in xs.iter().step_by(8) {
                let line = std::ptr::from_ref(x).cast();
                sse._mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(line);
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = xs;
    }
}

/// The operands of one instruction over the points `at`: registers `0..ins.len()` are the
/// inputs themselves, the others blocks of `regs`; destinations from [`OUT`] on are the
/// outputs.
struct Io<'a, 'o> {
    regs: &'a mut [Block],
    ins: &'a [&'a [f64]],
    outs: &'a mut [&'o mut [f64]],
    at: &'a Range<usize>,
}

impl<'a> Io<'a, '_> {
    /// The slice written (`len` points) and the readable registers below and above it.
    #[inline(always)]
    fn split(self, d: u32) -> (&'a mut [f64], Reads<'a>) {
        let len = self.at.len();
        let (dst, lo, hi): (&mut [f64], &[Block], &[Block]) = if d >= OUT {
            let o = &mut self.outs[(d - OUT) as usize][self.at.clone()];
            (o, self.regs, &[])
        } else {
            let (lo, rest) = self.regs.split_at_mut(d as usize);
            let (dst, hi) = rest.split_first_mut().expect("a register of the tape");
            (&mut dst[..len], lo, hi)
        };
        let reads = Reads {
            ins: self.ins,
            lo,
            hi,
            at: self.at,
        };
        (dst, reads)
    }

    #[inline(always)]
    fn un(self, d: u32, a: u32, f: impl Fn(f64) -> f64) {
        let (dst, reads) = self.split(d);
        let x = &reads.get(a)[..dst.len()];
        for (o, &x) in dst.iter_mut().zip(x) {
            *o = f(x);
        }
    }

    /// The sum of 2 to [`LIN`] terms, left to right, then `end`.
    #[inline(always)]
    fn lin(self, d: u32, terms: &[(u32, f64)], end: impl Fn(f64) -> f64) {
        let (dst, reads) = self.split(d);
        let n = dst.len();
        let mut x: [&[f64]; LIN] = [&[]; LIN];
        let mut k = [0.0; LIN];
        for (j, &(r, c)) in terms.iter().enumerate() {
            x[j] = &reads.get(r)[..n];
            k[j] = c;
        }
        let o = dst.iter_mut();
        match terms.len() {
            2 => {
                for ((o, &a), &b) in o.zip(x[0]).zip(x[1]) {
                    *o = end(k[0] * a + k[1] * b);
                }
            }
            3 => {
                for (((o, &a), &b), &c) in o.zip(x[0]).zip(x[1]).zip(x[2]) {
                    *o = end(k[0] * a + k[1] * b + k[2] * c);
                }
            }
            _ => {
                for ((((o, &a), &b), &c), &e) in o.zip(x[0]).zip(x[1]).zip(x[2]).zip(x[3]) {
                    *o = end(k[0] * a + k[1] * b + k[2] * c + k[3] * e);
                }
            }
        }
    }

    /// Σ k·|k_in·x + a| over 2 to [`LIN`] terms, left to right, then `end`.
    #[inline(always)]
    fn abs_sum(self, d: u32, x: u32, terms: &[[f64; 3]], end: impl Fn(f64) -> f64) {
        let (dst, reads) = self.split(d);
        let xs = &reads.get(x)[..dst.len()];
        let mut t = [[0.0; 3]; LIN];
        t[..terms.len()].copy_from_slice(terms);
        let o = dst.iter_mut().zip(xs);
        match terms.len() {
            2 => {
                for (o, &x) in o {
                    *o = end(ramp(&t[0], x) + ramp(&t[1], x));
                }
            }
            3 => {
                for (o, &x) in o {
                    *o = end(ramp(&t[0], x) + ramp(&t[1], x) + ramp(&t[2], x));
                }
            }
            _ => {
                for (o, &x) in o {
                    *o = end(ramp(&t[0], x) + ramp(&t[1], x) + ramp(&t[2], x) + ramp(&t[3], x));
                }
            }
        }
    }

    #[inline(always)]
    fn bin(self, d: u32, a: u32, b: u32, f: impl Fn(f64, f64) -> f64) {
        let (dst, reads) = self.split(d);
        let n = dst.len();
        let (x, y) = (&reads.get(a)[..n], &reads.get(b)[..n]);
        for ((o, &x), &y) in dst.iter_mut().zip(x).zip(y) {
            *o = f(x, y);
        }
    }
}

/// k·|k_in·x + a| of the term [k, k_in, a].
#[inline(always)]
fn ramp(t: &[f64; 3], x: f64) -> f64 {
    t[0] * (t[1] * x + t[2]).abs()
}

/// What an instruction may read besides its destination (which is never one of its
/// operands: the allocator hands out a node's register before freeing its children's).
struct Reads<'a> {
    ins: &'a [&'a [f64]],
    lo: &'a [Block],
    hi: &'a [Block],
    at: &'a Range<usize>,
}

impl<'a> Reads<'a> {
    #[inline(always)]
    fn get(&self, r: u32) -> &'a [f64] {
        let r = r as usize;
        if let Some(x) = self.ins.get(r) {
            &x[self.at.clone()]
        } else if r < self.lo.len() {
            &self.lo[r]
        } else {
            &self.hi[r - self.lo.len() - 1]
        }
    }
}

/// A register that is either a child's (read only, freed by its owner) or an intermediate
/// of the node being compiled (freed as soon as it is consumed).
#[derive(Clone, Copy)]
enum Owned {
    Borrowed(u32),
    Temp(u32),
}

impl Owned {
    fn reg(self) -> u32 {
        match self {
            Owned::Borrowed(r) | Owned::Temp(r) => r,
        }
    }
}

struct Emitter<'a> {
    ops: &'a mut Vec<Op>,
    alloc: &'a mut Alloc,
}

impl Emitter<'_> {
    fn release(&mut self, o: Owned) {
        if let Owned::Temp(r) = o {
            self.alloc.free.push(r);
        }
    }
    fn un(&mut self, op: impl Fn(u32, u32) -> Op, a: Owned) -> Owned {
        let d = self.alloc.get();
        self.ops.push(op(d, a.reg()));
        self.release(a);
        Owned::Temp(d)
    }
    fn bin(&mut self, op: impl Fn(u32, u32, u32) -> Op, a: Owned, b: Owned) -> Owned {
        let d = self.alloc.get();
        self.ops.push(op(d, a.reg(), b.reg()));
        self.release(a);
        self.release(b);
        Owned::Temp(d)
    }
    /// The sum Σ k·x over `regs` (at least two (k, register) terms) plus `imm`, as
    /// [`Op::Lin`]s of up to [`LIN`] terms, each after the first continuing the previous one
    /// (its first term, coefficient 1): the additions in the order of `regs`.
    fn sum(&mut self, terms: &mut Vec<(u32, f64)>, regs: &[(f64, u32)], imm: f64) -> u32 {
        let mut acc: Option<u32> = None;
        let mut rest = regs;
        loop {
            let room = if acc.is_some() { LIN - 1 } else { LIN };
            let (now, later) = rest.split_at(room.min(rest.len()));
            let start = terms.len();
            terms.extend(acc.map(|a| (a, 1.0)));
            terms.extend(now.iter().map(|&(k, r)| (r, k)));
            let end = (later.is_empty() && imm != 0.0).then_some(imm);
            let d = self.alloc.get();
            self.ops
                .push(Op::Lin(d, start as u32, (terms.len() - start) as u32, end));
            if let Some(a) = acc {
                self.alloc.free.push(a);
            }
            acc = Some(d);
            if later.is_empty() {
                return d;
            }
            rest = later;
        }
    }

    /// The node's result register (a copy of a borrowed register is never needed: a node
    /// whose value is a child's register would have been folded by the constructors).
    fn finish(&mut self, o: Owned) -> u32 {
        match o {
            Owned::Temp(r) => r,
            Owned::Borrowed(r) => {
                let d = self.alloc.get();
                self.ops.push(Op::MulC(d, r, 1.0));
                d
            }
        }
    }
}
