//! Fuzz tests of the single formulas of spec/composite-surfaces.md (issue 21): random patch
//! grids (Bézier and B-spline; huge, tiny and degenerate coordinates, near-coincident
//! knots), random piecewise functions (jumps, pieces undefined beyond or inside their
//! interval, coincident and near breakpoints), polylines and ruled surfaces. Property: no
//! panic; the construction is an error, or its formula holds finite f64 constants only and,
//! evaluated by the engine's tape, equals the structural evaluation (within a tolerance
//! scaled to the data: the values, the slopes and the ramps' rounding) at random
//! parameters, at every breakpoint and beyond the knots, wherever the structural value is
//! finite.

#[path = "common/fuzz.rs"]
mod fuzz;

use geomkit::bezier::BezierSurface;
use geomkit::bspline::BsplineSurface;
use geomkit::compose::{
    bodies, CompositeSurface, ExprPatch, Formula, Piecewise, RuledCurve, RuledSurface, SurfaceKind,
};
use geomkit::expr::{Const, Node};
use proptest::prelude::*;

const EPS: f64 = f64::EPSILON;

/// A coordinate: mostly ordinary, sometimes at the edges of f64 (huge, tiny, the extremes).
fn coordinate() -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => -10.0..10.0f64,
        1 => prop_oneof![Just(0.0), Just(1.0), Just(-1.0)],
        1 => (1e300..f64::MAX, any::<bool>()).prop_map(|(x, s)| if s { x } else { -x }),
        1 => prop_oneof![
            Just(f64::MAX),
            Just(-f64::MAX),
            Just(1.7e308),
            Just(-1e308),
            Just(8e307),
            Just(1e-300),
            Just(-5e-324),
            Just(f64::MIN_POSITIVE),
        ],
        1 => 1e-310..1e-290f64,
    ]
}

/// `len` coordinates: in a quarter of the cases with edge values among them
/// ([`coordinate`]), else ordinary ones only (so that most cases build and reach the
/// comparison of the formula with the evaluator).
fn coordinates(len: usize) -> impl Strategy<Value = Vec<f64>> {
    prop_oneof![
        3 => prop::collection::vec(-10.0..10.0f64, len),
        1 => prop::collection::vec(coordinate(), len),
    ]
}

/// The gap between two consecutive knots: ordinary, near-coincident (relative 1e-12),
/// coincident (an error), the smallest normal and subnormal widths, huge ones.
fn gap() -> impl Strategy<Value = f64> {
    prop_oneof![
        8 => 0.01..5.0f64,
        1 => Just(1.0),
        1 => 1e-12..1e-9f64,
        1 => prop_oneof![
            Just(0.0),
            Just(f64::MIN_POSITIVE),
            Just(5e-324),
            Just(1e307),
            Just(4e307),
            Just(f64::MAX),
        ],
    ]
}

/// Knots: a start (ordinary or huge) and `n` gaps, summed (an overflow to infinity is one
/// of the errors the constructions must give).
fn knots(n: std::ops::RangeInclusive<usize>) -> impl Strategy<Value = Vec<f64>> {
    (
        prop_oneof![4 => -3.0..3.0f64, 1 => coordinate()],
        prop::collection::vec(gap(), n),
    )
        .prop_map(|(start, gaps)| {
            let mut k = vec![start];
            for g in gaps {
                let last = k[k.len() - 1];
                k.push(last + g);
            }
            k
        })
}

/// Every constant of the formula is a finite f64.
fn assert_finite_constants(f: &Formula) {
    for id in f.graph.reachable(&f.roots) {
        let consts: Vec<&Const> = match f.graph.node(id) {
            Node::Const(c) | Node::Mul(c, _) => vec![c],
            Node::Add(c, ts) => std::iter::once(c).chain(ts.iter().map(|t| &t.0)).collect(),
            _ => vec![],
        };
        for c in consts {
            assert!(c.to_f64().is_finite(), "constant {c:?} in the formula");
        }
    }
}

/// Points from `lo` to `hi` widened by a quarter each side, the knots, the knots nudged by
/// a tiny step, and two a span beyond (the formulas are checked for overflow on the knots'
/// interval widened by its span).
fn sample_points(knots: &[f64], randoms: &[f64]) -> Vec<f64> {
    let (lo, hi) = (knots[0], knots[knots.len() - 1]);
    let span = hi - lo;
    let mut xs: Vec<f64> = randoms
        .iter()
        .map(|r| lo - span / 4.0 + r * 1.5 * span)
        .collect();
    for &k in knots {
        xs.extend([k, k - 1e-9 * span, k + 1e-9 * span]);
    }
    xs.extend([lo - span, hi + span]);
    xs.retain(|x| x.is_finite());
    xs
}

/// a · b, and 0 for a = 0 whatever b (a constant does not feel the ramps' rounding, even
/// where that rounding is unbounded).
fn times(a: f64, b: f64) -> f64 {
    if a == 0.0 {
        0.0
    } else {
        a * b
    }
}

/// Every (u, v) of the grid `us` × `vs`, as the u and v columns of the points.
fn grid_pairs(us: &[f64], vs: &[f64]) -> (Vec<f64>, Vec<f64>) {
    us.iter()
        .flat_map(|&u| vs.iter().map(move |&v| (u, v)))
        .unzip()
}

/// The smallest gap of the knots.
fn min_gap(k: &[f64]) -> f64 {
    k.windows(2).fold(f64::INFINITY, |m, w| m.min(w[1] - w[0]))
}

/// A piece of a random function on [a, b], with what the tolerance needs: the largest
/// |value| on the interval, the largest |slope|, and for a root-like end the factor of
/// sqrt(δ) that an argument δ off the end costs.
#[derive(Debug, Clone)]
enum Piece {
    Const(f64),
    Linear(f64, f64),
    Sin(f64, f64),
    SqrtLeft(f64),
    SqrtRight(f64),
    Asin(f64),
    Recip(f64, f64),
    /// NaN in the middle of the interval (a warning, not an error).
    Hole,
}

fn piece() -> impl Strategy<Value = Piece> {
    prop_oneof![
        2 => coordinate().prop_map(Piece::Const),
        2 => (coordinate(), -5.0..5.0f64).prop_map(|(c, k)| Piece::Linear(c, k)),
        1 => (-3.0..3.0f64, -4.0..4.0f64).prop_map(|(c, k)| Piece::Sin(c, k)),
        1 => (-3.0..3.0f64).prop_map(Piece::SqrtLeft),
        1 => (-3.0..3.0f64).prop_map(Piece::SqrtRight),
        1 => (-3.0..3.0f64).prop_map(Piece::Asin),
        1 => (-3.0..3.0f64, 0.1..10.0f64).prop_map(|(c, d)| Piece::Recip(c, d)),
        1 => Just(Piece::Hole),
    ]
}

impl Piece {
    /// The formula in x on [a, b], and (scale, slope, root factor).
    fn text(&self, a: f64, b: f64) -> (String, f64, f64, f64) {
        let (w, m) = (b - a, a + (b - a) / 2.0);
        match *self {
            Piece::Const(c) => (format!("{c:?}"), c.abs(), 0.0, 0.0),
            Piece::Linear(c, k) => (
                format!("{c:?} + {k:?}*(x - {m:?})"),
                c.abs() + k.abs() * w,
                k.abs(),
                0.0,
            ),
            Piece::Sin(c, k) => (
                format!("{c:?} + sin({k:?}*(x - {m:?}))"),
                c.abs() + 1.0,
                k.abs(),
                0.0,
            ),
            Piece::SqrtLeft(c) => (
                format!("{c:?}*sqrt(x - {a:?})"),
                c.abs() * w.sqrt(),
                0.0,
                c.abs(),
            ),
            Piece::SqrtRight(c) => (
                format!("{c:?}*sqrt({b:?} - x)"),
                c.abs() * w.sqrt(),
                0.0,
                c.abs(),
            ),
            // asin of ±1 at the ends: about sqrt(2 δ / h) off by an argument δ.
            Piece::Asin(c) => (
                format!("{c:?}*asin((x - {m:?})/{:?})", w / 2.0),
                c.abs() * 2.0,
                0.0,
                c.abs() * 2.0 / (w / 2.0).sqrt(),
            ),
            Piece::Recip(c, d) => {
                let p = a - d * w;
                (
                    format!("{c:?}/(x - {p:?})"),
                    c.abs() / (d * w),
                    c.abs() / (d * w).powi(2),
                    0.0,
                )
            }
            Piece::Hole => (
                format!("sqrt((x - {m:?})^2 - {:?})", (w / 8.0).powi(2)),
                w,
                1.0,
                1.0,
            ),
        }
    }
}

/// Checks a piecewise function or curve: finite constants, and the formula's tape equal to
/// the structural evaluation within `tol(x)` wherever the latter is finite.
fn check_piecewise(p: &Piecewise, randoms: &[f64], tol: impl Fn(f64) -> f64) {
    let Ok(f) = p.formula() else { return };
    assert_finite_constants(&f);
    let xs = sample_points(p.knots(), randoms);
    let d = p.dim();
    let mut out = vec![0.0; xs.len() * d];
    f.eval_batch(&[&xs], &mut out).unwrap();
    for (x, got) in xs.iter().zip(out.chunks_exact(d)) {
        let want = p.eval(*x);
        for c in 0..d {
            if !want[c].is_finite() {
                continue;
            }
            assert!(
                (got[c] - want[c]).abs() <= tol(*x),
                "x = {x:e}: formula {:e}, evaluator {:e}, tolerance {:e}",
                got[c],
                want[c],
                tol(*x)
            );
        }
    }
}

proptest! {
    #![proptest_config(fuzz::config(64))]

    /// Random piecewise functions: jumps, constants at the edges of f64, pieces with
    /// infinite slopes at their ends, pieces undefined inside their interval, near and
    /// coincident breakpoints.
    #[test]
    fn fuzz_piecewise_functions(
        k in knots(1..=5),
        pieces in prop::collection::vec(piece(), 5),
        randoms in prop::collection::vec(0.0..1.0f64, 16),
    ) {
        let n = k.len() - 1;
        let described: Vec<(String, f64, f64, f64)> =
            (0..n).map(|i| pieces[i].text(k[i], k[i + 1])).collect();
        let texts: Vec<&str> = described.iter().map(|d| d.0.as_str()).collect();
        let Ok(p) = Piecewise::function(k.clone(), &texts) else { return Ok(()) };
        // The ramps' rounding moves an argument by about δ(x); a piece's value moves by its
        // slope times δ, or by its root factor times sqrt(δ) at a root-like end; the sum of
        // the pieces and their shifts adds rounding of the sizes of the values.
        let kmax = k[0].abs().max(k[n].abs());
        let values: f64 = described.iter().map(|d| d.1).sum::<f64>() + p.continuity().max_jump;
        let tol = |x: f64| {
            let delta = 16.0 * EPS * (x.abs() + kmax) * (1.0 + (k[n] - k[0]) / min_gap(&k));
            described.iter().fold(64.0 * EPS * values * n as f64, |t, d| {
                t + times(d.2, delta) + times(d.3, delta.sqrt())
            })
        };
        check_piecewise(&p, &randoms, tol);
    }

    /// Polylines and polygons through random points (at the edges of f64, repeated), at
    /// default or random knots.
    #[test]
    fn fuzz_polylines(
        points in prop::collection::vec(prop::collection::vec(coordinate(), 2), 2..6),
        k in prop::option::of(knots(5..=5)),
        closed in any::<bool>(),
        randoms in prop::collection::vec(0.0..1.0f64, 8),
    ) {
        let count = points.len() + usize::from(closed);
        let k = k.map(|k| k[..count].to_vec());
        let Ok(p) = Piecewise::polyline(points.clone(), k, closed) else { return Ok(()) };
        let kn = p.knots().to_vec();
        let n = kn.len() - 1;
        let scale = points.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
        let kmax = kn[0].abs().max(kn[n].abs());
        let tol = |x: f64| {
            64.0 * EPS * scale * (n as f64 + 1.0) * (1.0 + (x.abs() + kmax) / min_gap(&kn))
        };
        check_piecewise(&p, &randoms, tol);
    }

    /// Random explicit composites of formula patches z(x, y): polynomial ones and ones
    /// with square roots and arc sines that are 0 or ±1 at the cells' edges (clamped in
    /// the formula and the evaluator alike), at random and edge knots.
    #[test]
    fn fuzz_formula_patches(
        xk in knots(1..=3),
        yk in knots(1..=2),
        kinds in prop::collection::vec((0u8..4, -3.0..3.0f64), 6),
        randoms in prop::collection::vec(0.0..1.0f64, 10),
    ) {
        let (n, m) = (xk.len() - 1, yk.len() - 1);
        // Each patch with (largest |value| on the cell, largest slope, root factor).
        let mut sizes = Vec::new();
        let patches: Result<Vec<Vec<ExprPatch>>, _> = (0..n)
            .map(|i| {
                (0..m)
                    .map(|j| {
                        let (a, b) = (xk[i], xk[i + 1]);
                        let (kind, c) = kinds[(i * m + j) % kinds.len()];
                        let (w, mid) = (b - a, a + (b - a) / 2.0);
                        let ymax = yk[j].abs().max(yk[j + 1].abs());
                        let (text, size) = match kind {
                            0 => (format!("{c:?} + x*y"), (c.abs() + a.abs().max(b.abs()) * ymax, ymax.max(1.0), 0.0)),
                            1 => (format!("{c:?}*sqrt(x - {a:?}) + y"), (c.abs() * w.sqrt() + ymax, 1.0, c.abs())),
                            2 => (format!("{c:?}*sqrt({b:?} - x)*y"), (c.abs() * w.sqrt() * ymax, 1.0, c.abs() * ymax)),
                            _ => (format!("asin((x - {mid:?})/{:?}) + {c:?}*y", w / 2.0), (2.0 + c.abs() * ymax, c.abs(), 2.0 / (w / 2.0).sqrt())),
                        };
                        sizes.push(size);
                        // (A width that halves to 0 divides by an exact zero: an error.)
                        ExprPatch::parse(&[("z", &text)], &["x", "y"], None)
                    })
                    .collect()
            })
            .collect();
        let Ok(patches) = patches else { return Ok(()) };
        let Ok(s) = CompositeSurface::from_expr(xk.clone(), yk.clone(), patches, SurfaceKind::Explicit) else {
            return Ok(());
        };
        let Ok(f) = s.formula() else { return Ok(()) };
        assert_finite_constants(&f);
        let xs = sample_points(&xk, &randoms);
        let ys = sample_points(&yk, &randoms[5..]);
        let (px, py) = grid_pairs(&xs, &ys);
        let mut out = vec![0.0; px.len()];
        f.eval_batch(&[&px, &py], &mut out).unwrap();
        let (kx, ky) = (xk[0].abs().max(xk[n].abs()), yk[0].abs().max(yk[m].abs()));
        let values: f64 = sizes.iter().map(|z| z.0).sum();
        for (k, got) in out.iter().enumerate() {
            let want = geomkit::geom::Surface::eval(&s, px[k], py[k])[0];
            if !want.is_finite() {
                continue;
            }
            // Formula (11) adds each patch four times; the ramps move an argument by δ.
            let delta = 16.0 * EPS * (1.0 + (px[k].abs() + kx) / min_gap(&xk) + (py[k].abs() + ky) / min_gap(&yk))
                * (kx + ky + 1.0);
            let tol = sizes.iter().fold(64.0 * EPS * 4.0 * values, |t, z| {
                t + 4.0 * (times(z.1, delta) + times(z.2, delta.sqrt()))
            });
            prop_assert!(
                (got - want).abs() <= tol,
                "({:e}, {:e}): formula {got:e}, evaluator {want:e}, tol {tol:e}",
                px[k],
                py[k]
            );
        }
    }

    /// Random grids of Bézier patches (degrees 1 to 3, dimension 1 to 3, degenerate ones
    /// with every point equal, coordinates at the edges of f64) over random knots.
    #[test]
    fn fuzz_patch_grids(
        uk in knots(1..=3),
        vk in knots(1..=3),
        dim in 1usize..=3,
        degrees in (1usize..=3, 1usize..=3),
        coords in coordinates(9 * 16 * 3),
        degenerate in prop::collection::vec(any::<bool>(), 9),
        randoms in prop::collection::vec(0.0..1.0f64, 12),
    ) {
        let (n, m) = (uk.len() - 1, vk.len() - 1);
        let (p, q) = degrees;
        let mut it = coords.iter().copied().cycle();
        let patches: Vec<Vec<BezierSurface>> = (0..n)
            .map(|i| {
                (0..m)
                    .map(|j| {
                        let first: Vec<f64> = (0..dim).map(|_| it.next().unwrap()).collect();
                        let net = (0..=p)
                            .map(|_| {
                                (0..=q)
                                    .map(|_| {
                                        if degenerate[(i * m + j) % 9] {
                                            first.clone()
                                        } else {
                                            (0..dim).map(|_| it.next().unwrap()).collect()
                                        }
                                    })
                                    .collect()
                            })
                            .collect();
                        BezierSurface::new(net).unwrap()
                    })
                    .collect()
            })
            .collect();
        let Ok(s) = CompositeSurface::from_bezier(uk.clone(), vk.clone(), &patches) else {
            return Ok(());
        };
        check_surface(&s, &randoms);
    }

    /// B-spline surfaces as their cells (the single formula of a fitted surface), with
    /// control points at the edges of f64 and random clamped knots.
    #[test]
    fn fuzz_bspline_cells(
        inner in knots(0..=2),
        degree in 1usize..=3,
        coords in coordinates(36),
        randoms in prop::collection::vec(0.0..1.0f64, 8),
    ) {
        let p = degree;
        let mut kn = vec![inner[0]; p];
        kn.extend(&inner);
        kn.extend(vec![inner[inner.len() - 1]; p]);
        let count = kn.len() - p - 1;
        if count < p + 1 {
            return Ok(());
        }
        let net: Vec<f64> = (0..count * count).map(|k| coords[k % coords.len()]).collect();
        let Ok(b) = BsplineSurface::from_flat((p, p), kn.clone(), kn, count, count, 1, net) else {
            return Ok(());
        };
        let Ok(s) = CompositeSurface::from_bspline(&b) else { return Ok(()) };
        check_surface(&s, &randoms);
    }

    /// Ruled surfaces over points, polygons and circles with coordinates at the edges of f64,
    /// at random v values and u ranges.
    #[test]
    fn fuzz_ruled_surfaces(
        kinds in prop::collection::vec(0u8..3, 2..5),
        coords in coordinates(64),
        v in knots(4..=4),
        u in knots(1..=1),
        randoms in prop::collection::vec(0.0..1.0f64, 6),
    ) {
        let mut it = coords.iter().copied().cycle();
        let mut point = || [it.next().unwrap(), it.next().unwrap(), it.next().unwrap()];
        let curves: Vec<RuledCurve> = kinds
            .iter()
            .filter_map(|k| match k {
                0 => Some(RuledCurve::Point(point())),
                1 => RuledCurve::polygon(vec![point(), point(), point()]).ok(),
                _ => Some(RuledCurve::Circle {
                    center: point(),
                    radius: point()[0].abs(),
                }),
            })
            .collect();
        let vv = v[..curves.len().min(v.len())].to_vec();
        let Ok(s) = RuledSurface::new(curves.clone(), vv, (u[0], u[1])) else {
            return Ok(());
        };
        let Ok(f) = s.formula() else { return Ok(()) };
        assert_finite_constants(&f);
        let ((u0, u1), (v0, v1)) = s.domain();
        let us = sample_points(&[u0, u1], &randoms);
        let vs = sample_points(s.v_values(), &randoms);
        let scale = coords.iter().take(3 * 4 * curves.len() + 3).fold(0.0f64, |m, x| m.max(x.abs()));
        let (pu, pv) = grid_pairs(&us, &vs);
        let mut out = vec![0.0; pu.len() * 3];
        f.eval_batch(&[&pu, &pv], &mut out).unwrap();
        let (kv, ku) = (v0.abs().max(v1.abs()), u0.abs().max(u1.abs()));
        for (k, got) in out.chunks_exact(3).enumerate() {
            let want = s.eval(pu[k], pv[k]);
            // Weights in v: Σ |v - v_k| / Δv; polygons in u: Σ |u - u_k| / Δu (3 edges).
            let tol = times(
                256.0 * EPS * scale * curves.len() as f64,
                (1.0 + (pv[k].abs() + kv) / min_gap(s.v_values()))
                    * (1.0 + 4.0 * (pu[k].abs() + ku) / (u1 - u0)),
            );
            for c in 0..3 {
                if want[c].is_finite() {
                    prop_assert!(
                        (got[c] - want[c]).abs() <= tol,
                        "({:e}, {:e}) coordinate {c}: formula {:e}, evaluator {:e}, tol {tol:e}",
                        pu[k], pv[k], got[c], want[c]
                    );
                }
            }
        }
    }

    /// Bodies of random sizes (zero, negative, huge, tiny): an error, or a formula with
    /// finite constants that evaluates to finite points on its domain.
    #[test]
    fn fuzz_body_sizes(a in coordinate(), b in coordinate(), c in coordinate()) {
        for body in [
            bodies::rectangular_box(a, b, c),
            bodies::square_pyramid(a, b),
            bodies::frustum(a, b, c),
        ] {
            let Ok(s) = body else { continue };
            let Ok(f) = s.formula() else { continue };
            assert_finite_constants(&f);
            let ((u0, u1), (v0, v1)) = s.domain();
            let mut out = [0.0; 3];
            f.eval_batch(&[&[(u0 + u1) / 3.0], &[(v0 + v1) / 3.0]], &mut out).unwrap();
            prop_assert!(out.iter().all(|x| x.is_finite()), "{out:?}");
        }
    }
}

/// Checks a composite surface: finite constants, and the formula's tape equal to the
/// structural evaluator (within ε times the patches' coefficients and the ramps' rounding)
/// at random points, the grid's knots and beyond, wherever the evaluator is finite.
fn check_surface(s: &CompositeSurface, randoms: &[f64]) {
    let Ok(f) = s.formula() else { return };
    assert_finite_constants(&f);
    let (uk, vk) = s.knots();
    let (n, m) = s.cells();
    let us = sample_points(uk, randoms);
    let vs = sample_points(vk, &randoms[randoms.len() / 2..]);
    // Σ |coefficients| over all patches (each monomial is at most 1 on the cell).
    let mut coefs = 0.0;
    let mut degree = 0;
    for i in 0..n {
        for j in 0..m {
            let p = s.patch(i, j).unwrap();
            let (a, b) = p.degrees();
            degree = degree.max(a + b);
            coefs += p.scale() * ((a + 1) * (b + 1)) as f64;
        }
    }
    let (ku, kv) = (uk[0].abs().max(uk[n].abs()), vk[0].abs().max(vk[m].abs()));
    let (pu, pv) = grid_pairs(&us, &vs);
    let d = s.dim();
    let mut out = vec![0.0; pu.len() * d];
    f.eval_batch(&[&pu, &pv], &mut out).unwrap();
    for (k, got) in out.chunks_exact(d).enumerate() {
        let want = s.eval(pu[k], pv[k]);
        let ramp = 16.0
            * EPS
            * (1.0 + (pu[k].abs() + ku) / min_gap(uk) + (pv[k].abs() + kv) / min_gap(vk));
        let tol = times(coefs, 64.0 * EPS + 4.0 * degree as f64 * ramp);
        for c in 0..d {
            if want[c].is_finite() {
                assert!(
                    (got[c] - want[c]).abs() <= tol,
                    "({:e}, {:e}) coordinate {c}: formula {:e}, evaluator {:e}, tol {tol:e}",
                    pu[k],
                    pv[k],
                    got[c],
                    want[c]
                );
            }
        }
    }
}
