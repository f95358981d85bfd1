//! Long cubic not-a-knot interpolants of [`make_interp_spline`](super::make_interp_spline)
//! and bicubic ones of [`make_interp_surface`](super::make_interp_surface) (SciPy's
//! defaults, k = 3, `RectBivariateSpline` with s = 0) through the paper's extended form:
//! geomkit's cubic solvers (`interpolate.rs`, `surface.rs`: the knots at every x, three more
//! beyond each end, N + 2 coefficients per direction, the C3 conditions at x_1 and x_(N-2)
//! as end rows, Thomas sweeps in parallel chunks) followed by a change of basis to SciPy's
//! knots, per direction.
//!
//! Both represent the one cubic spline through the data that is C3 at x_1 and x_(N-2), so
//! the change of basis is exact in real arithmetic: a B-spline coefficient is the blossom
//! of the polynomial piece on any knot interval inside its support, at its inner knots
//! (de Boor–Fix). SciPy's knots t = [x_0]*4 + x_2..x_(N-3) + [x_(N-1)]*4 share every inner
//! B-spline with the extended form: SciPy's c_j = c_(j+1) of the extended form for
//! 3 <= j <= N-4 (the same three inner knots x_(j-1), x_j, x_(j+1); for j = 3 the piece on
//! [x_2, x_3] lies in both supports). The three at each end are blossoms of the piece Q on
//! [x_2, x_3] (inside the supports of SciPy's B_0..B_2 and of the extended B_2..B_4), with
//! e_i the extended coefficients:
//!
//! - Q(x_1, x_2, x_3) = e_3 and Q(x_2, x_3, x_4) = e_4, affine in the changed argument, give
//!   c_2 = Q(x_0, x_2, x_3) = e_3 + (x_0 - x_1)/(x_4 - x_1) (e_4 - e_3);
//! - Q(x_2, x_0, x_1) = e_2 and c_2 give c_1 = Q(x_2, x_0, x_0) = e_2 + (x_0 - x_1)/(x_3 - x_1)
//!   (c_2 - e_2);
//! - c_0 = Q(x_0, x_0, x_0), the value at x_0: e_0 B_0(x_0) + e_1 B_1(x_0) + e_2 B_2(x_0) in
//!   the extended basis (y_0 for a curve through data, to rounding);
//!
//! and the mirror images at the right end. The ratios lie in (-1, 0): no cancellation.
//!
//! A surface takes the map along v in every row of its net, then along u with whole rows
//! as the points. The cost is the cubic solve (memory-bound, in parallel) and one move of
//! the coefficients, in place, against LU with partial pivoting of the general band
//! (`spline.rs`) on every window: several times fewer passes over the data.

use super::curve::{basis_funs, BsplineCurve};
use super::interpolate::{knots_around, EndCondition, Parametrization, Solver1d};
use super::spline::not_a_knot_knots;
use super::surface::{interpolate_heights_at, BsplineSurface};
use crate::par::*;

/// Fewest numbers (points, or grid values) for the fast paths: below this the general band
/// solve (with its iterative refinement) is as fast, and its results stay those it has
/// always given.
pub(super) const MIN_POINTS: usize = 1 << 16;

/// How SciPy's three coefficients at one end come from the extended form's five there
/// (e_0..e_4 counted from that end; module docs).
#[derive(Debug, Clone, Copy)]
struct EndMap {
    /// B_0, B_1, B_2 of the extended knots at the end knot.
    b: [f64; 3],
    /// (x_0 - x_1) / (x_4 - x_1): c_2 = e_3 + a (e_4 - e_3).
    a: f64,
    /// (x_0 - x_1) / (x_3 - x_1): c_1 = e_2 + r (c_2 - e_2).
    r: f64,
}

impl EndMap {
    /// The maps of the two ends for the extended knots `t` (N + 6 of them, x_i at t[i + 3];
    /// N >= 5).
    fn pair(t: &[f64]) -> [EndMap; 2] {
        let n = t.len() - 6;
        let x = |i: usize| t[i + 3];
        // B_0..B_3 at x_0 (B_3 = 0) and B_(N-2)..B_(N+1) at x_(N-1) (B_(N-2) = 0).
        let (mut left, mut right) = ([0.0; 4], [0.0; 4]);
        basis_funs(t, 3, x(0), 3, &mut left);
        basis_funs(t, n + 1, x(n - 1), 3, &mut right);
        let map = |b, [x0, x1, x3, x4]: [f64; 4]| EndMap {
            b,
            a: (x0 - x1) / (x4 - x1),
            r: (x0 - x1) / (x3 - x1),
        };
        [
            map([left[0], left[1], left[2]], [x(0), x(1), x(3), x(4)]),
            map(
                [right[3], right[2], right[1]],
                [x(n - 1), x(n - 2), x(n - 4), x(n - 5)],
            ),
        ]
    }

    /// c_0, c_1, c_2 from e_0..e_4 (points of any one length), written into `out`.
    fn apply(&self, e: [&[f64]; 5], out: [&mut [f64]; 3]) {
        let [c0, c1, c2] = out;
        for k in 0..e[0].len() {
            c0[k] = self.b[0] * e[0][k] + self.b[1] * e[1][k] + self.b[2] * e[2][k];
            c2[k] = e[3][k] + self.a * (e[4][k] - e[3][k]);
            c1[k] = e[2][k] + self.r * (c2[k] - e[2][k]);
        }
    }

    /// The three coefficients of one scalar sequence `e` at this end (`from_right`: counted
    /// from its end).
    fn scalars(&self, e: &[f64], from_right: bool) -> [f64; 3] {
        let m = e.len() - 1;
        let at = |i: usize| if from_right { e[m - i] } else { e[i] };
        let (mut c0, mut c1, mut c2) = ([0.0], [0.0], [0.0]);
        self.apply(
            [&[at(0)], &[at(1)], &[at(2)], &[at(3)], &[at(4)]],
            [&mut c0, &mut c1, &mut c2],
        );
        [c0[0], c1[0], c2[0]]
    }
}

/// SciPy's not-a-knot cubic through (x_i, y_i) (x strictly increasing and finite, y of N
/// finite rows; N >= [`MIN_POINTS`]), or `None` where the general band solve must decide:
/// the cubic solver refuses (knots beyond the ends overflow) or coefficients come out
/// above `limit` (an ill-conditioned system; the band solve refines or refuses it). The
/// knots are the extended form's vector moved in place, the coefficients likewise: no
/// memory besides the result.
pub(super) fn not_a_knot_cubic(
    x: &[f64],
    y: &[f64],
    dim: usize,
    limit: f64,
) -> Option<BsplineCurve> {
    let n = x.len();
    debug_assert!(n >= MIN_POINTS && y.len() == n * dim);
    let solver = Solver1d::new_single(
        knots_around(x),
        &EndCondition::NotAKnot,
        Parametrization::ChordLength,
    )
    .ok()?;
    let (mut t, mut e) = solver
        .interpolate(y, dim, true)
        .ok()?
        .into_curve()
        .into_parts();
    debug_assert_eq!(e.len(), (n + 2) * dim);
    // The three coefficients at each end, from rows the move overwrites.
    let [left, right] = EndMap::pair(&t);
    let mut ends = vec![0.0; 6 * dim];
    {
        let row = |i: usize| &e[i * dim..(i + 1) * dim];
        let mut out = ends.chunks_exact_mut(dim);
        let mut next = || out.next().expect("six rows");
        left.apply(
            [row(0), row(1), row(2), row(3), row(4)],
            [next(), next(), next()],
        );
        right.apply(
            [row(n + 1), row(n), row(n - 1), row(n - 2), row(n - 3)],
            [next(), next(), next()],
        );
    }
    // c_j = e_(j+1); then the ends.
    let bounded = shift_left(&mut e, dim, limit);
    e.truncate(n * dim);
    for (j, v) in [0, 1, 2, n - 1, n - 2, n - 3]
        .into_iter()
        .zip(ends.chunks_exact(dim))
    {
        e[j * dim..(j + 1) * dim].copy_from_slice(v);
    }
    // The extended knots [.., .., .., x_0, x_1, .., x_(N-1), .., .., ..] moved by one hold
    // SciPy's x_2..x_(N-3) at 4..N-1; its ends are x_0 and x_(N-1) four times.
    shift_left(&mut t, 1, f64::INFINITY);
    t.truncate(n + 4);
    t[..4].fill(x[0]);
    t[n..].fill(x[n - 1]);
    bounded.then(|| BsplineCurve::from_trusted(3, t, dim, e))
}

/// SciPy's not-a-knot bicubic through the heights z (row-major, x.len() × y.len(), at
/// least 8 per direction, checked as [`super::make_interp_surface`] checks them) from the
/// extended form's surface ([`interpolate_heights_at`]), its net changed to SciPy's basis in
/// place; `None` as for [`not_a_knot_cubic`].
pub(super) fn not_a_knot_bicubic(
    x: &[f64],
    y: &[f64],
    z: &[f64],
    limit: f64,
) -> Option<BsplineSurface> {
    let (nx, ny) = (x.len(), y.len());
    debug_assert!(nx >= 8 && ny >= 8 && z.len() == nx * ny);
    let (tu, tv, mut e) = interpolate_heights_at(z, x, y, &EndCondition::NotAKnot)
        .ok()?
        .into_parts();
    let w = ny + 2;
    debug_assert_eq!(e.len(), (nx + 2) * w);
    let [vl, vr] = EndMap::pair(&tv);
    // One row of the extended net along v: SciPy's ny numbers (`src`, `dst` apart).
    let along_v = |src: &[f64], dst: &mut [f64]| {
        dst[3..ny - 3].copy_from_slice(&src[4..ny - 2]);
        let [c0, c1, c2] = vl.scalars(&src[..5], false);
        let [d0, d1, d2] = vr.scalars(&src[w - 5..], true);
        (dst[0], dst[1], dst[2]) = (c0, c1, c2);
        (dst[ny - 1], dst[ny - 2], dst[ny - 3]) = (d0, d1, d2);
    };
    // The five rows at each end along v, then SciPy's three end rows from them.
    let converted = |rows: [usize; 5]| -> Vec<Vec<f64>> {
        rows.iter()
            .map(|&i| {
                let mut d = vec![0.0; ny];
                along_v(&e[i * w..(i + 1) * w], &mut d);
                d
            })
            .collect()
    };
    let [ul, ur] = EndMap::pair(&tu);
    let mut ends = vec![0.0; 6 * ny];
    {
        let (l, r) = (
            converted([0, 1, 2, 3, 4]),
            converted([nx + 1, nx, nx - 1, nx - 2, nx - 3]),
        );
        fn refs(v: &[Vec<f64>]) -> [&[f64]; 5] {
            [&v[0], &v[1], &v[2], &v[3], &v[4]]
        }
        let mut out = ends.chunks_exact_mut(ny);
        let mut next = || out.next().expect("six rows");
        ul.apply(refs(&l), [next(), next(), next()]);
        ur.apply(refs(&r), [next(), next(), next()]);
    }
    // Inner rows: SciPy's row i is extended row i + 1 along v, moved forward in place (row i
    // ends before row i + 2 begins: nothing is overwritten before it is read).
    let mut row = vec![0.0; ny];
    for i in 3..nx - 3 {
        along_v(&e[(i + 1) * w..(i + 2) * w], &mut row);
        e[i * ny..(i + 1) * ny].copy_from_slice(&row);
    }
    e.truncate(nx * ny);
    for (i, v) in [0, 1, 2, nx - 1, nx - 2, nx - 3]
        .into_iter()
        .zip(ends.chunks_exact(ny))
    {
        e[i * ny..(i + 1) * ny].copy_from_slice(v);
    }
    let bounded = e
        .par_chunks(1 << 16)
        .all(|c| c.iter().fold(true, |ok, v| ok & (v.abs() <= limit)));
    let (tx, ty) = (not_a_knot_knots(x, 3), not_a_knot_knots(y, 3));
    bounded.then(|| BsplineSurface::from_trusted((3, 3), tx, ty, nx, ny, 1, e))
}

/// Moves `v[by..]` to `v[..len - by]` in parallel chunks (memmove is one thread): each
/// chunk moves its own numbers, then takes the first `by` of the next chunk, saved before.
/// Returns whether every number moved is at most `limit` in magnitude (and not NaN), found
/// on the way.
fn shift_left(v: &mut [f64], by: usize, limit: f64) -> bool {
    const CHUNK: usize = 1 << 18;
    let chunk = CHUNK.max(by).div_ceil(by) * by;
    let heads: Vec<Vec<f64>> = v
        .chunks(chunk)
        .skip(1)
        .map(|c| c[..by.min(c.len())].to_vec())
        .collect();
    let bounded = std::sync::atomic::AtomicBool::new(true);
    v.par_chunks_mut(chunk).for_each(|c| {
        let len = c.len();
        c.copy_within(by.min(len).., 0);
        if !c.iter().fold(true, |ok, x| ok & (x.abs() <= limit)) {
            bounded.store(false, std::sync::atomic::Ordering::Relaxed);
        }
    });
    for (i, head) in heads.iter().enumerate() {
        let end = (i + 1) * chunk;
        v[end - by..end - by + head.len()].copy_from_slice(head);
    }
    bounded.into_inner()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Against the general band solve (LU with partial pivoting on SciPy's own knots) on
    /// uneven data: the same coefficients to rounding, and the ends exactly the data.
    #[test]
    fn equals_the_band_solve_on_scipys_knots() {
        let n = MIN_POINTS + 37;
        let mut x = Vec::with_capacity(n);
        let mut at = -3.0;
        for i in 0..n {
            at += 0.05 + ((i * 7919) % 101) as f64 / 37.0;
            x.push(at);
        }
        let y: Vec<f64> = x
            .iter()
            .flat_map(|&t| [(t / 9.0).sin() * 4.0, (t / 5.0).cos() + t / 1e3])
            .collect();
        let curve = not_a_knot_cubic(&x, &y, 2, f64::MAX).unwrap();
        let t = super::super::spline::not_a_knot_knots(&x, 3);
        assert_eq!(curve.knots(), &t[..]);
        let band = super::super::spline::solve_open(
            &x,
            &y,
            2,
            &t,
            3,
            &[],
            &[],
            super::super::spline::max_abs(&y),
            &crate::progress::Progress::none(),
        )
        .unwrap();
        let fast = curve.control_flat();
        assert_eq!(fast.len(), band.len());
        let worst = fast
            .iter()
            .zip(&band)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        let scale = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(worst <= 1e-14 * scale, "{worst} against data up to {scale}");
        for (c, y) in [
            (&fast[..2], &y[..2]),
            (&fast[(n - 1) * 2..], &y[(n - 1) * 2..]),
        ] {
            assert!(
                (c[0] - y[0]).abs() + (c[1] - y[1]).abs() <= 1e-14 * scale,
                "end {c:?} {y:?}"
            );
        }
    }

    /// The bicubic against SciPy's two directions one after the other, each by the general
    /// band solve (`make_interp_spline` of the rows of z as points, then of the transposed
    /// net): the same knots, the same net to rounding.
    #[test]
    fn bicubic_equals_the_band_solves_direction_by_direction() {
        use super::super::spline::{make_interp_spline, SplineOptions};
        use super::super::surface::transpose;
        let (nx, ny) = (300, 227);
        let axis = |n: usize, s: f64| -> Vec<f64> {
            (0..n)
                .map(|i| i as f64 * s + ((i * 31) % 7) as f64 * s / 9.0)
                .collect()
        };
        let (x, y) = (axis(nx, 0.5), axis(ny, 1.25));
        let z: Vec<f64> = x
            .iter()
            .flat_map(|&a| {
                y.iter()
                    .map(move |&b| (a / 7.0).sin() * (b / 11.0).cos() + a * b / 1e3)
            })
            .collect();
        let scale = z.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let s = not_a_knot_bicubic(&x, &y, &z, f64::MAX).unwrap();
        let sx = make_interp_spline(&x, &z, ny, &SplineOptions::new(3)).unwrap();
        let t = transpose(sx.control_flat(), nx, ny, 1);
        let sy = make_interp_spline(&y, &t, nx, &SplineOptions::new(3)).unwrap();
        let net = transpose(sy.control_flat(), ny, nx, 1);
        assert_eq!(s.knots(), (sx.knots(), sy.knots()));
        let worst = s
            .control_flat()
            .iter()
            .zip(&net)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(
            worst <= 1e-13 * scale,
            "{worst} against heights up to {scale}"
        );
        for (i, a) in x.iter().enumerate().step_by(13) {
            for (j, b) in y.iter().enumerate().step_by(11) {
                let v = s.eval(*a, *b)[0];
                assert!((v - z[i * ny + j]).abs() <= 1e-13 * scale, "({i}, {j})");
            }
        }
    }

    #[test]
    fn shift_left_moves_every_number_by_one_row() {
        for (len, by) in [(10, 1), (1 << 19, 3), ((1 << 18) * 3 + 7, 7), (12, 4)] {
            let mut v: Vec<f64> = (0..len).map(|i| i as f64).collect();
            assert!(shift_left(&mut v, by, len as f64));
            for (i, x) in v[..len - by].iter().enumerate() {
                assert_eq!(*x, (i + by) as f64, "len {len}, by {by}, at {i}");
            }
        }
    }
}
