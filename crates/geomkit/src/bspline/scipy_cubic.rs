//! The long cubic not-a-knot interpolant of [`make_interp_spline`](super::make_interp_spline)
//! (SciPy's default, k = 3) through the paper's extended form: geomkit's cubic solver
//! (`interpolate.rs`: the knots at every x, three more beyond each end, N + 2 coefficients,
//! the C3 conditions at x_1 and x_(N-2) as its end rows, Thomas sweeps in parallel chunks)
//! followed by a change of basis to SciPy's knots.
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
//! - c_0 = Q(x_0, x_0, x_0) = y_0 (the interpolation condition itself);
//!
//! and the mirror images at the right end. The ratios lie in (-1, 0): no cancellation.
//!
//! The cost is the cubic solve (memory-bound, in parallel) and one move of the coefficients
//! by one row, against LU with partial pivoting of the general band (`spline.rs`) on every
//! window: about 3 times fewer passes over the data.

use super::curve::BsplineCurve;
use super::interpolate::{knots_around, EndCondition, Parametrization, Solver1d};
use crate::par::*;

/// Fewest points for [`not_a_knot_cubic`]: below this the general band solve (with its
/// iterative refinement) is as fast, and its results stay those it has always given.
pub(super) const MIN_POINTS: usize = 1 << 16;

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
    let row = |e: &[f64], i: usize| e[i * dim..(i + 1) * dim].to_vec();
    // The three coefficients at each end, from rows the move overwrites.
    let ends = |at: [usize; 3], [x0, x1, x3, x4]: [f64; 4]| -> [Vec<f64>; 2] {
        let (e2, e3, e4) = (row(&e, at[0]), row(&e, at[1]), row(&e, at[2]));
        let (a, b) = ((x0 - x1) / (x4 - x1), (x0 - x1) / (x3 - x1));
        let c2: Vec<f64> = (0..dim).map(|k| e3[k] + a * (e4[k] - e3[k])).collect();
        let c1 = (0..dim).map(|k| e2[k] + b * (c2[k] - e2[k])).collect();
        [c1, c2]
    };
    let [l1, l2] = ends([2, 3, 4], [x[0], x[1], x[3], x[4]]);
    let [r1, r2] = ends(
        [n - 1, n - 2, n - 3],
        [x[n - 1], x[n - 2], x[n - 4], x[n - 5]],
    );
    // c_j = e_(j+1); then the ends.
    let bounded = shift_left(&mut e, dim, limit);
    e.truncate(n * dim);
    for (j, v) in [
        (0, &y[..dim]),
        (1, &l1[..]),
        (2, &l2[..]),
        (n - 3, &r2[..]),
        (n - 2, &r1[..]),
        (n - 1, &y[(n - 1) * dim..]),
    ] {
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
        let band = super::super::spline::solve_open(&x, &y, 2, &t, 3, &[], &[]).unwrap();
        let fast = curve.control_flat();
        assert_eq!(fast.len(), band.len());
        let worst = fast
            .iter()
            .zip(&band)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        let scale = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(worst <= 1e-14 * scale, "{worst} against data up to {scale}");
        assert_eq!(fast[..2], y[..2]);
        assert_eq!(fast[(n - 1) * 2..], y[(n - 1) * 2..]);
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
