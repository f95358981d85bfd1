//! Formulas of spec/composite-surfaces.md built directly on the engine, for tests and
//! benchmarks: the paper's cube (section 2) and composite surfaces of formula (9) with
//! polynomial patches. (The full constructions with validation, continuity report and
//! structural evaluator live in `geomkit::compose`.)

use num_rational::BigRational;

use crate::graph::{Const, Graph, Id};
use crate::parse::parse;

/// The cube with vertices (±1, ±1, ±1) exactly as printed in the paper (section 2), in
/// the variables `u ∈ [0, 4]`, `v ∈ [0, 3]`: `[x, y, z]`.
///
/// ```
/// use geomkit_expr::{fixtures, Graph};
/// let mut g = Graph::new();
/// let [x, _, z] = fixtures::cube(&mut g);
/// assert_eq!(g.eval(x, &[("u", 0.5), ("v", 1.5)]).unwrap(), 0.0);
/// assert_eq!(g.eval(z, &[("u", 0.5), ("v", 0.0)]).unwrap(), 1.0);
/// ```
pub fn cube(g: &mut Graph) -> [Id; 3] {
    const X: &str = "1/2*(1 - abs(u) + abs(u-1) + abs(u-2) - abs(u-3))*(abs(v) - abs(v-1) - abs(v-2) + abs(v-3))";
    const Y: &str = "1/2*(1 - abs(u-1) + abs(u-2) + abs(u-3) - abs(u-4))*(abs(v) - abs(v-1) - abs(v-2) + abs(v-3))";
    const Z: &str = "-abs(v-1) + abs(v-2)";
    [X, Y, Z].map(|t| parse(g, t).expect("the cube's formulas parse"))
}

/// The ramp P(t, a, w) = (w + |t − a| − |t − a − w|) / (2w) of formula (1), `w > 0`.
pub fn ramp(g: &mut Graph, t: Id, a: &BigRational, w: &BigRational) -> Id {
    let a_id = g.rat(a.clone());
    let aw = g.rat(a + w);
    let w_id = g.rat(w.clone());
    let d0 = g.sub(t, a_id);
    let d1 = g.sub(t, aw);
    let abs0 = g.abs(d0);
    let abs1 = g.abs(d1);
    let num = g.lin(&[
        (Const::int(1), w_id),
        (Const::int(1), abs0),
        (Const::int(-1), abs1),
    ]);
    let inv = Const::Rat(BigRational::from_integer(2.into()) * w)
        .powi(-1)
        .expect("w > 0");
    g.scale(&inv, num)
}

/// A composite surface of formula (9) over the grid `u_knots × v_knots` (increasing,
/// exact) whose patch in cell (i, j) is the polynomial
/// `r_ij(s, t) = Σ_{k ≤ du, l ≤ dv} coef(i, j, k, l, c) s^k t^l` (coordinate `c < dim`) in
/// the cell's local coordinates `s, t ∈ [0, 1]`, in the variables `u`, `v`.
///
/// With local coordinates the clamped arguments of (3) are the ramps themselves,
/// `s = P(u, u_i, u_(i+1) − u_i)`, and `r_ij(0, t)`, `r_ij(s, 0)` drop the terms with
/// `k = 0` or `l = 0`, so (9) is exactly
/// `R = Σ_ij Σ_kl [k ≥ 1 or i = 0] [l ≥ 1 or j = 0] b^ij_kl P_i^k Q_j^l`: one flat sum per
/// coordinate sharing the ramps and their powers.
pub fn composite_poly(
    g: &mut Graph,
    u_knots: &[BigRational],
    v_knots: &[BigRational],
    degree: (usize, usize),
    dim: usize,
    mut coef: impl FnMut(usize, usize, usize, usize, usize) -> f64,
) -> Vec<Id> {
    let u = g.var("u");
    let v = g.var("v");
    let ramps = |g: &mut Graph, x: Id, knots: &[BigRational]| -> Vec<Id> {
        knots
            .windows(2)
            .map(|k| ramp(g, x, &k[0], &(&k[1] - &k[0])))
            .collect()
    };
    let p = ramps(g, u, u_knots);
    let q = ramps(g, v, v_knots);
    let mut terms: Vec<Vec<(Const, Id)>> = vec![Vec::new(); dim];
    for (i, &pi) in p.iter().enumerate() {
        for (j, &qj) in q.iter().enumerate() {
            for k in 0..=degree.0 {
                if k == 0 && i > 0 {
                    continue;
                }
                for l in 0..=degree.1 {
                    if l == 0 && j > 0 {
                        continue;
                    }
                    let mono = g.prod(&[(pi, k as i32), (qj, l as i32)]);
                    for (c, t) in terms.iter_mut().enumerate() {
                        let b = coef(i, j, k, l, c);
                        if b != 0.0 {
                            t.push((Const::Float(b), mono));
                        }
                    }
                }
            }
        }
    }
    terms.iter().map(|t| g.lin(t)).collect()
}

/// Evaluates the same surface by formula (9) literally, term by term in `f64` (the
/// reference for [`composite_poly`]): `R_ij(u, v) = r_ij(P_i(u), Q_j(v))` and
/// `R = R_00 + Σ_i (R_i0(u,v) − R_i0(u_i,v)) + Σ_j (R_0j(u,v) − R_0j(u,v_j))
/// + Σ_ij (R_ij(u,v) − R_ij(u_i,v) − R_ij(u,v_j) + R_ij(u_i,v_j))`.
pub fn composite_poly_literal(
    u_knots: &[f64],
    v_knots: &[f64],
    degree: (usize, usize),
    dim: usize,
    mut coef: impl FnMut(usize, usize, usize, usize, usize) -> f64,
    (u, v): (f64, f64),
) -> Vec<f64> {
    let ramp = |t: f64, a: f64, w: f64| (w + (t - a).abs() - (t - a - w).abs()) / (2.0 * w);
    let mut out = vec![0.0; dim];
    for i in 0..u_knots.len() - 1 {
        for j in 0..v_knots.len() - 1 {
            let (ui, hi) = (u_knots[i], u_knots[i + 1] - u_knots[i]);
            let (vj, hj) = (v_knots[j], v_knots[j + 1] - v_knots[j]);
            let mut r = |s: f64, t: f64, c: usize| -> f64 {
                let mut sum = 0.0;
                for k in 0..=degree.0 {
                    for l in 0..=degree.1 {
                        sum += coef(i, j, k, l, c) * s.powi(k as i32) * t.powi(l as i32);
                    }
                }
                sum
            };
            let (p, q) = (ramp(u, ui, hi), ramp(v, vj, hj));
            for (c, o) in out.iter_mut().enumerate() {
                let mut x = r(p, q, c);
                if i > 0 {
                    x -= r(0.0, q, c);
                }
                if j > 0 {
                    x -= r(p, 0.0, c);
                }
                if i > 0 && j > 0 {
                    x += r(0.0, 0.0, c);
                }
                *o += x;
            }
        }
    }
    out
}

/// A counter-based pseudo-random number in [0, 1) (SplitMix64 of `seed`), reproducible in
/// any language.
pub fn unit(seed: u64) -> f64 {
    let mut z = seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64
}

/// Random patch coefficients in [-1, 1) for [`composite_poly`], reproducible from `seed`.
pub fn random_coef(
    seed: u64,
    cells: (usize, usize),
    degree: (usize, usize),
    dim: usize,
) -> impl Fn(usize, usize, usize, usize, usize) -> f64 {
    move |i, j, k, l, c| {
        let idx = (((i * cells.1 + j) * (degree.0 + 1) + k) * (degree.1 + 1) + l) * dim + c;
        2.0 * unit(seed.wrapping_mul(1_000_003).wrapping_add(idx as u64)) - 1.0
    }
}

/// `n + 1` exact uniform knots from 0 to `n`.
pub fn uniform_knots(n: usize) -> Vec<BigRational> {
    (0..=n)
        .map(|i| BigRational::from_integer((i as i64).into()))
        .collect()
}
