//! The batched evaluator: the DAG compiled to a register program run over blocks of
//! [`LANES`] points, one instruction at a time over the whole block, so every inner loop is
//! a plain slice loop the compiler vectorizes.

use std::collections::HashMap;

use crate::error::{ExprError, Result};
use crate::graph::{powi, Func, Graph, Id, Node};

/// Points per block: each instruction runs over this many points at once.
pub const LANES: usize = 256;

type Block = [f64; LANES];

#[derive(Clone, Copy, Debug)]
enum Op {
    Add(u32, u32, u32),
    Sub(u32, u32, u32),
    Mul(u32, u32, u32),
    Div(u32, u32, u32),
    /// d = a + c·b.
    MulAdd(u32, u32, u32, f64),
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
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Val {
    Reg(u32),
    Imm(f64),
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
    nregs: usize,
    nvars: usize,
    outs: Vec<Val>,
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
                    for (k, t) in ts.iter() {
                        match val[pos[t]] {
                            Val::Imm(x) => imm += k.to_f64() * x,
                            Val::Reg(r) => regs.push((k.to_f64(), r)),
                        }
                    }
                    // Start from a term with coefficient 1 when there is one.
                    if let Some(j) = regs.iter().position(|(k, _)| *k == 1.0) {
                        regs.swap(0, j);
                    }
                    let mut em = Emitter {
                        ops: &mut ops,
                        alloc: &mut alloc,
                    };
                    let (k0, r0) = regs[0];
                    let mut acc = if k0 == 1.0 {
                        Owned::Borrowed(r0)
                    } else if k0 == -1.0 {
                        em.un(Op::Neg, Owned::Borrowed(r0))
                    } else {
                        em.un(|d, a| Op::MulC(d, a, k0), Owned::Borrowed(r0))
                    };
                    for &(k, r) in &regs[1..] {
                        let b = Owned::Borrowed(r);
                        acc = if k == 1.0 {
                            em.bin(Op::Add, acc, b)
                        } else if k == -1.0 {
                            em.bin(Op::Sub, acc, b)
                        } else {
                            em.bin(|d, a, b| Op::MulAdd(d, a, b, k), acc, b)
                        };
                    }
                    if imm != 0.0 {
                        acc = em.un(|d, a| Op::AddC(d, a, imm), acc);
                    }
                    Val::Reg(em.finish(acc))
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
        let outs = roots.iter().map(|r| val[pos[r]]).collect();
        Ok(Tape {
            ops,
            nregs: alloc.next as usize,
            nvars,
            outs,
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
        let mut start = 0;
        while start < n {
            let len = LANES.min(n - start);
            for (k, x) in inputs.iter().enumerate() {
                regs[k][..len].copy_from_slice(&x[start..start + len]);
            }
            run(&self.ops, &mut regs, len);
            for (o, v) in out.iter_mut().zip(&self.outs) {
                match *v {
                    Val::Reg(r) => o[start..start + len].copy_from_slice(&regs[r as usize][..len]),
                    Val::Imm(x) => o[start..start + len].fill(x),
                }
            }
            start += len;
        }
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
        if out.len() != self.outs.len() {
            return shape("number of output arrays", out.len(), self.outs.len());
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

/// Runs the program over one block of `len` points, compiled for the CPU's AVX2 where it
/// has it (checked once by `pulp`), else as it is: the same bits either way (the loops use
/// no fused multiply-adds), in wider instructions.
fn run(ops: &[Op], regs: &mut [Block], len: usize) {
    #[cfg(target_arch = "x86_64")]
    if let Some(v3) = pulp::x86::V3::try_new() {
        return v3.vectorize(
            #[inline(always)]
            || run_ops(ops, regs, len),
        );
    }
    run_ops(ops, regs, len)
}

#[inline(always)]
fn run_ops(ops: &[Op], regs: &mut [Block], len: usize) {
    for op in ops {
        match *op {
            Op::Add(d, a, b) => bin(regs, d, a, b, len, |x, y| x + y),
            Op::Sub(d, a, b) => bin(regs, d, a, b, len, |x, y| x - y),
            Op::Mul(d, a, b) => bin(regs, d, a, b, len, |x, y| x * y),
            Op::Div(d, a, b) => bin(regs, d, a, b, len, |x, y| x / y),
            Op::MulAdd(d, a, b, c) => bin(regs, d, a, b, len, |x, y| x + c * y),
            Op::AddC(d, a, c) => un(regs, d, a, len, |x| x + c),
            Op::MulC(d, a, c) => un(regs, d, a, len, |x| c * x),
            Op::RDivC(d, a, c) => un(regs, d, a, len, |x| c / x),
            Op::DivC(d, a, c) => un(regs, d, a, len, |x| x / c),
            Op::Neg(d, a) => un(regs, d, a, len, |x| -x),
            Op::Square(d, a) => un(regs, d, a, len, |x| x * x),
            Op::Cube(d, a) => un(regs, d, a, len, |x| x * x * x),
            Op::Powi(d, a, n) => un(regs, d, a, len, |x| powi(x, n)),
            Op::Fun(d, a, f) => match f {
                Func::Abs => un(regs, d, a, len, f64::abs),
                Func::Sqrt => un(regs, d, a, len, f64::sqrt),
                Func::Sign => un(regs, d, a, len, crate::graph::sign),
                f => un(regs, d, a, len, |x| f.apply(x)),
            },
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

#[inline(always)]
fn un(regs: &mut [Block], d: u32, a: u32, len: usize, f: impl Fn(f64) -> f64) {
    let [dst, x] = regs
        .get_disjoint_mut([d as usize, a as usize])
        .expect("tape registers are distinct");
    for (o, &x) in dst[..len].iter_mut().zip(&x[..len]) {
        *o = f(x);
    }
}

#[inline(always)]
fn bin(regs: &mut [Block], d: u32, a: u32, b: u32, len: usize, f: impl Fn(f64, f64) -> f64) {
    if a == b {
        let [dst, x] = regs
            .get_disjoint_mut([d as usize, a as usize])
            .expect("tape registers are distinct");
        for (o, &x) in dst[..len].iter_mut().zip(&x[..len]) {
            *o = f(x, x);
        }
    } else {
        let [dst, x, y] = regs
            .get_disjoint_mut([d as usize, a as usize, b as usize])
            .expect("tape registers are distinct");
        for ((o, &x), &y) in dst[..len].iter_mut().zip(&x[..len]).zip(&y[..len]) {
            *o = f(x, y);
        }
    }
}
