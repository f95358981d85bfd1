//! The shared traits of `geomkit::geom` on every curve and surface of the library: batches
//! equal single-point evaluation bit for bit (both parallelism values, random and sorted
//! parameters), uniform samples over the curve's own domain, derivatives against central
//! differences and against exact references, errors for bad buffers and parameters.

mod common;

use common::{random_curve, Rng};
use geomkit::bezier::{BezierSurface, RationalBezierCurve};
use geomkit::bspline::{
    interpolate_curve, interpolate_curve_at, interpolate_heights, interpolate_surface,
    BsplineCurve, EndCondition, InterpolationOptions, SurfaceInterpolationOptions,
};
use geomkit::compose::{bodies, CompositeSurface, ExprPatch, Piecewise, RuledCurve, SurfaceKind};
use geomkit::exact::{rational_from_f64, rational_to_f64, ExactBezierCurve, Rational};
use geomkit::geom::{BatchOptions, Curve, Parallelism, Surface};
use geomkit::pointcalc::{Nodes, PointEquation, PointSurface, PrintedSurface};
use geomkit::Error;
use proptest::prelude::*;

const BOTH: [Parallelism; 2] = [Parallelism::Auto, Parallelism::Sequential];

/// Largest absolute coordinate of a point array.
fn max_abs(xs: &[f64]) -> f64 {
    xs.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// Every curve type of the library, named.
fn curves() -> Vec<(&'static str, Box<dyn Curve>)> {
    let pts: Vec<Vec<f64>> = (0..40)
        .map(|k| {
            let x = k as f64 * 0.37;
            vec![x.sin() * 3.0, x.cos() + 0.1 * x, x]
        })
        .collect();
    let bspline = interpolate_curve(&pts, &InterpolationOptions::default())
        .unwrap()
        .into_curve();
    let quintic = {
        let knots: Vec<f64> = (0..16).map(|k| k as f64 * 0.5).collect();
        let control: Vec<Vec<f64>> = (0..10)
            .map(|k| vec![k as f64, (k * k % 7) as f64])
            .collect();
        BsplineCurve::new(5, knots, control).unwrap()
    };
    let nodes = Nodes::new(vec![0.0, 0.3, 0.5, 0.9, 1.4]).unwrap();
    let eq_pts: Vec<Vec<f64>> = (0..5)
        .map(|k| vec![k as f64, (k * k) as f64 - 2.0])
        .collect();
    let many_nodes = Nodes::new((0..20).map(|k| k as f64 / 19.0).collect()).unwrap();
    let many_pts: Vec<Vec<f64>> = (0..20).map(|k| vec![(k as f64 * 0.3).sin()]).collect();
    vec![
        ("bezier", Box::new(random_curve(7, 3, 1))),
        ("bezier of degree 70", Box::new(random_curve(70, 2, 2))),
        (
            "rational",
            Box::new(
                RationalBezierCurve::new(
                    vec![vec![1.0, 0.0], vec![1.0, 1.0], vec![0.0, 1.0]],
                    vec![1.0, std::f64::consts::FRAC_1_SQRT_2, 1.0],
                )
                .unwrap(),
            ),
        ),
        ("bspline", Box::new(bspline.clone())),
        ("bspline of degree 5", Box::new(quintic)),
        ("piecewise", Box::new(bspline.to_piecewise().unwrap())),
        (
            "point equation",
            Box::new(PointEquation::new(nodes, eq_pts).unwrap()),
        ),
        (
            "point equation of 20 nodes",
            Box::new(PointEquation::new(many_nodes, many_pts).unwrap()),
        ),
        (
            "composite polyline",
            Box::new(
                Piecewise::polyline(
                    vec![vec![0.0, 0.0], vec![1.0, 2.0], vec![3.0, 1.0]],
                    None,
                    true,
                )
                .unwrap(),
            ),
        ),
        (
            "composite function",
            Box::new(Piecewise::function(vec![-1.0, 0.0, 1.0, 2.0], &["-x", "x^2", "1"]).unwrap()),
        ),
        (
            "ruled circle",
            Box::new(RuledCurve::Circle {
                center: [1.0, 2.0, 3.0],
                radius: 2.0,
            }),
        ),
        (
            "ruled polygon",
            Box::new(
                RuledCurve::polygon(vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.5]])
                    .unwrap(),
            ),
        ),
        (
            "ruled formula",
            Box::new(RuledCurve::formula(["cos(t)", "sin(t)", "t/10"], (0.0, 6.0)).unwrap()),
        ),
    ]
}

/// sin(x) cos(y) on [0, 2] × [0, 1] from two formula cells, the second 1 higher (shifted
/// back by formula (11)).
fn sin_cos_composite() -> CompositeSurface {
    let z = |f: &str| ExprPatch::parse(&[("z", f)], &["x", "y"], None).unwrap();
    CompositeSurface::from_expr(
        vec![0.0, 1.0, 2.0],
        vec![0.0, 1.0],
        vec![vec![z("sin(x)*cos(y)")], vec![z("sin(x)*cos(y) + 1")]],
        SurfaceKind::Explicit,
    )
    .unwrap()
}

/// Every surface type of the library, named.
fn surfaces() -> Vec<(&'static str, Box<dyn Surface>)> {
    let z: Vec<f64> = (0..30)
        .map(|k| ((k / 6) as f64 * 0.7).sin() + ((k % 6) as f64).powi(2) * 0.1)
        .collect();
    let heights =
        interpolate_heights(&z, 5, 6, (0.0, 0.0), (1.0, 0.5), &EndCondition::NotAKnot).unwrap();
    let grid = |dim: usize| -> Vec<Vec<Vec<f64>>> {
        (0..6)
            .map(|i| {
                (0..5)
                    .map(|j| {
                        (0..dim)
                            .map(|c| ((i * 3 + j * 5 + c * 7) % 11) as f64 * 0.3 + i as f64)
                            .collect()
                    })
                    .collect()
            })
            .collect()
    };
    let surf = |dim| {
        interpolate_surface(&grid(dim), &SurfaceInterpolationOptions::default())
            .unwrap()
            .surface
    };
    let bezier =
        BezierSurface::new(grid(3)[..4].iter().map(|r| r[..3].to_vec()).collect()).unwrap();
    let net3: Vec<Vec<Vec<f64>>> = (0..3)
        .map(|i| {
            (0..3)
                .map(|j| vec![j as f64, i as f64, ((i * j) % 2) as f64])
                .collect()
        })
        .collect();
    let point = PointSurface::rows_then_across(
        vec![
            Nodes::paper_third(),
            Nodes::paper_half(),
            Nodes::paper_two_thirds(),
        ],
        Nodes::paper_half(),
        net3.clone(),
    )
    .unwrap();
    vec![
        ("bezier", Box::new(bezier)),
        ("bspline heights", Box::new(heights.clone())),
        ("bspline 2-D", Box::new(surf(2))),
        ("bspline 3-D", Box::new(surf(3))),
        ("bspline 4-D", Box::new(surf(4))),
        (
            "composite of a bspline",
            Box::new(CompositeSurface::from_bspline(&heights).unwrap()),
        ),
        ("composite of formulas", Box::new(sin_cos_composite())),
        ("ruled cube", Box::new(bodies::cube().unwrap())),
        (
            "ruled cylinder",
            Box::new(bodies::cylinder(1.5, 2.0).unwrap()),
        ),
        ("point surface", Box::new(point)),
        (
            "printed surface",
            Box::new(PrintedSurface::new(net3).unwrap()),
        ),
    ]
}

/// `n` parameters over [a, b] widened by a tenth on each side (extrapolation included),
/// in random order, and the same sorted.
fn params(a: f64, b: f64, n: usize, seed: u64) -> [Vec<f64>; 2] {
    let mut rng = Rng(seed);
    let w = b - a;
    let mut ts: Vec<f64> = (0..n)
        .map(|_| a + w * (0.5 + 0.6 * rng.uniform()))
        .collect();
    ts.extend([a, b]);
    let mut sorted = ts.clone();
    sorted.sort_by(f64::total_cmp);
    [ts, sorted]
}

#[test]
fn curve_batches_equal_single_points_bit_for_bit() {
    for (name, c) in curves() {
        let (a, b) = c.domain();
        let d = c.dim();
        for ts in params(a, b, 9000, 3) {
            for parallelism in BOTH {
                let options = BatchOptions::default().with_parallelism(parallelism);
                let mut out = vec![0.0; ts.len() * d];
                c.eval_batch(&ts, &mut out, &options).unwrap();
                for (t, p) in ts.iter().zip(out.chunks_exact(d)) {
                    let mut one = vec![0.0; d];
                    c.eval_into(*t, &mut one);
                    assert_eq!(p, &one[..], "{name} at t = {t} ({parallelism:?})");
                }
            }
        }
    }
}

#[test]
fn surface_batches_equal_single_points_bit_for_bit() {
    for (name, s) in surfaces() {
        let ((u0, u1), (v0, v1)) = s.domain();
        let d = s.dim();
        let [us, us_sorted] = params(u0, u1, 6000, 5);
        let [vs, _] = params(v0, v1, 6000, 7);
        for us in [us, us_sorted] {
            let uv: Vec<f64> = us.iter().zip(&vs).flat_map(|(&u, &v)| [u, v]).collect();
            for parallelism in BOTH {
                let options = BatchOptions::default().with_parallelism(parallelism);
                let mut out = vec![0.0; uv.len() / 2 * d];
                s.eval_batch(&uv, &mut out, &options).unwrap();
                for (q, p) in uv.chunks_exact(2).zip(out.chunks_exact(d)) {
                    let mut one = vec![0.0; d];
                    s.eval_into(q[0], q[1], &mut one);
                    assert_eq!(p, &one[..], "{name} at {q:?} ({parallelism:?})");
                }
            }
        }
        // The grid agrees with single points within rounding.
        let (gu, gv) = ([u0, 0.3 * u0 + 0.7 * u1, u1], [v0, 0.5 * (v0 + v1), v1]);
        let mut grid = vec![0.0; 9 * d];
        s.eval_grid(&gu, &gv, &mut grid).unwrap();
        let scale = max_abs(&grid).max(1.0);
        for (k, p) in grid.chunks_exact(d).enumerate() {
            let one = s.eval(gu[k / 3], gv[k % 3]);
            for (x, y) in p.iter().zip(&one) {
                assert!(
                    (x - y).abs() <= 64.0 * f64::EPSILON * scale,
                    "{name}: grid {k}"
                );
            }
        }
    }
}

/// The B-spline batch through the piecewise form (a large batch on few spans) agrees with
/// single points within the documented 8·eps·max|P|, and exactly with `bit_exact`.
#[test]
fn bspline_fast_path_is_within_its_agreement() {
    let pts: Vec<Vec<f64>> = (0..30)
        .map(|k| vec![(k as f64 * 0.4).sin() * 5.0, k as f64 * 0.25])
        .collect();
    let curve = interpolate_curve(&pts, &InterpolationOptions::default())
        .unwrap()
        .into_curve();
    let scale = max_abs(curve.control_flat());
    let (a, b) = curve.domain();
    for ts in params(a, b, 1 << 16, 11) {
        for parallelism in BOTH {
            let options = BatchOptions::default().with_parallelism(parallelism);
            let mut fast = vec![0.0; ts.len() * 2];
            curve.eval_batch(&ts, &mut fast, &options).unwrap();
            let mut exact = vec![0.0; ts.len() * 2];
            curve
                .eval_batch(&ts, &mut exact, &options.with_bit_exact(true))
                .unwrap();
            let mut worst = 0.0f64;
            for ((t, p), q) in ts
                .iter()
                .zip(fast.chunks_exact(2))
                .zip(exact.chunks_exact(2))
            {
                let one = curve.eval(*t);
                assert_eq!(q, &one[..], "bit exact at {t}");
                worst = worst.max(max_abs(&[p[0] - one[0], p[1] - one[1]]));
            }
            // Inside the domain (outside, the end cubics' rounding grows with their values).
            let inside = ts.iter().filter(|t| (a..=b).contains(*t)).count();
            assert!(inside > 1000);
            let mut worst_inside = 0.0f64;
            for (t, p) in ts.iter().zip(fast.chunks_exact(2)) {
                if (a..=b).contains(t) {
                    let one = curve.eval(*t);
                    worst_inside = worst_inside.max(max_abs(&[p[0] - one[0], p[1] - one[1]]));
                }
            }
            assert!(
                worst_inside <= 8.0 * f64::EPSILON * scale,
                "{worst_inside:e} > 8 eps {scale}"
            );
            assert!(worst < 1e-9 * scale, "{worst:e}");
        }
    }
}

/// A B-spline fitted over parameters [0, 7.3]: `sample_uniform` spans its own domain, hits
/// both ends exactly and equals `eval` at t_k = 7.3 k/(count-1) within the forward
/// differences' reported bound.
#[test]
fn sample_uniform_covers_the_curves_own_domain() {
    let n = 20;
    let t: Vec<f64> = (0..n).map(|k| 7.3 * k as f64 / (n - 1) as f64).collect();
    let pts: Vec<f64> = t
        .iter()
        .flat_map(|&x| [x.sin(), x.cos(), x * 0.1])
        .collect();
    let fit = interpolate_curve_at(3, &pts, &t, &EndCondition::NotAKnot).unwrap();
    let curve = fit.curve();
    assert_eq!(Curve::domain(curve), (0.0, 7.3));
    for count in [2usize, 7, 1001] {
        let samples = curve.sample_uniform(count);
        assert_eq!(samples.len(), count * 3);
        assert_eq!(&samples[..3], &curve.eval(0.0)[..], "count {count}");
        assert_eq!(
            &samples[(count - 1) * 3..],
            &curve.eval(7.3)[..],
            "count {count}"
        );
        let mut fd = vec![0.0; count * 3];
        let bound = curve.sample_uniform_fd(count, &mut fd).unwrap().bound;
        let step = 7.3 / (count - 1) as f64;
        for k in 0..count {
            let tk = if k + 1 == count { 7.3 } else { k as f64 * step };
            let p = curve.eval(tk);
            for c in 0..3 {
                let e = (samples[3 * k + c] - p[c]).abs();
                assert!(
                    e <= bound + 4.0 * f64::EPSILON,
                    "count {count}, k {k}: {e:e}"
                );
            }
        }
    }
    // A Bézier curve (the trait's default) samples [0, 1] by exact evaluation.
    let c = random_curve(5, 2, 9);
    let s = c.sample_uniform(11);
    for k in 0..11 {
        let tk = if k == 10 {
            1.0
        } else {
            k as f64 * (1.0 / 10.0)
        };
        assert_eq!(&s[2 * k..2 * k + 2], &c.eval(tk)[..]);
    }
}

/// Central differences of order 1 and 2 from the order below, at interior parameters away
/// from breaks; the step scales with the domain.
fn check_curve_fd(name: &str, c: &dyn Curve, max_order: usize) {
    let (a, b) = c.domain();
    let breaks = c.breaks();
    let d = c.dim();
    let h = (b - a) * 1e-5;
    let mut rng = Rng(17);
    let mut checked = 0;
    for _ in 0..40 {
        let t = a + (b - a) * (0.5 + 0.45 * rng.uniform());
        if breaks.iter().any(|x| (x - t).abs() < 4.0 * h) {
            continue;
        }
        for order in 1..=max_order {
            let (mut lo, mut hi, mut got) = (vec![0.0; d], vec![0.0; d], vec![0.0; d]);
            c.derivative_into(t - h, order - 1, &mut lo).unwrap();
            c.derivative_into(t + h, order - 1, &mut hi).unwrap();
            c.derivative_into(t, order, &mut got).unwrap();
            let scale = max_abs(&got).max(max_abs(&lo)).max(1.0);
            for k in 0..d {
                let fd = (hi[k] - lo[k]) / (2.0 * h);
                assert!(
                    (fd - got[k]).abs() <= 1e-6 * scale,
                    "{name} order {order} at {t}: {fd} vs {}",
                    got[k]
                );
            }
        }
        checked += 1;
    }
    assert!(checked > 10, "{name}");
}

#[test]
fn curve_derivatives_match_central_differences() {
    for (name, c) in curves() {
        let orders = match name {
            "composite polyline" | "ruled polygon" => 1,
            _ => 2,
        };
        check_curve_fd(name, c.as_ref(), orders);
        let mut out = vec![0.0; c.dim()];
        let (a, b) = c.domain();
        let t = 0.5 * (a + b);
        c.derivative_into(t, 0, &mut out).unwrap();
        assert_eq!(out, c.eval(t), "{name}: order 0 is the point");
    }
}

/// Formula pieces and curves by the engine's symbolic derivative, in closed form.
#[test]
fn formula_derivatives_are_symbolic() {
    let f = Piecewise::function(vec![-1.0, 0.0, 1.0, 2.0], &["-x", "x^3", "1"]).unwrap();
    let mut d = [0.0];
    for (x, k, want) in [
        (-0.5, 1, -1.0),
        (-0.5, 2, 0.0),
        (0.5, 1, 0.75),
        (0.5, 2, 3.0),
        (0.5, 3, 6.0),
        (1.5, 1, 0.0),
        (2.5, 1, 0.0),
    ] {
        f.derivative_into(x, k, &mut d).unwrap();
        assert!((d[0] - want).abs() < 1e-14, "x {x} k {k}: {}", d[0]);
    }
    let c = RuledCurve::formula(["cos(t)", "sin(t)", "t/10"], (0.0, 6.0)).unwrap();
    let mut p = [0.0; 3];
    for t in [0.0, 1.3, 5.9] {
        c.derivative_into(t, 1, &mut p).unwrap();
        let want = [-f64::sin(t), t.cos(), 0.1];
        c.derivative_into(t, 2, &mut p[..]).unwrap();
        let want2 = [-t.cos(), -t.sin(), 0.0];
        for i in 0..3 {
            assert!((p[i] - want2[i]).abs() < 1e-14, "{t}");
        }
        c.derivative_into(t, 1, &mut p).unwrap();
        for i in 0..3 {
            assert!((p[i] - want[i]).abs() < 1e-14, "{t}");
        }
    }
}

/// The Bézier hodographs against exact rational arithmetic: p^(k)(t) = Σ_j j!/(j-k)! s_j
/// t^(j-k) with the exact power coefficients s_j, at a parameter taken exactly.
#[test]
fn bezier_derivatives_match_exact_hodographs() {
    for (n, seed) in [(3usize, 1u64), (6, 2), (11, 3)] {
        let c = random_curve(n, 2, seed);
        let exact = ExactBezierCurve::from_f64(2, c.points_flat()).unwrap();
        let s = exact.to_power();
        for t in [0.3, 0.77, 1.0] {
            let tq = rational_from_f64(t).unwrap();
            for k in 0..=n + 1 {
                let mut want = [0.0f64; 2];
                for (coord, w) in want.iter_mut().enumerate() {
                    let mut acc = Rational::from_integer(0.into());
                    let mut power = Rational::from_integer(1.into());
                    for j in k..=n {
                        let falling: i64 = ((j - k + 1)..=j).map(|x| x as i64).product();
                        acc += &s[j * 2 + coord] * &power * Rational::from_integer(falling.into());
                        power *= &tq;
                    }
                    *w = rational_to_f64(&acc);
                }
                let mut got = [0.0; 2];
                c.derivative_into(t, k, &mut got).unwrap();
                let scale = max_abs(&want).max(1.0) * (1u64 << k.min(20)) as f64;
                for i in 0..2 {
                    assert!(
                        (got[i] - want[i]).abs() <= 1e3 * f64::EPSILON * scale * n as f64,
                        "n {n} k {k} t {t}: {} vs {}",
                        got[i],
                        want[i]
                    );
                }
            }
        }
    }
}

/// A cubic B-spline interpolating samples of a cubic with not-a-knot ends reproduces it:
/// its derivatives are those of the cubic, in closed form.
#[test]
fn bspline_derivatives_reproduce_a_cubic() {
    let f = |t: f64| [t * t * t - 2.0 * t, 0.5 * t * t * t + t * t];
    let df = |t: f64, k: usize| match k {
        1 => [3.0 * t * t - 2.0, 1.5 * t * t + 2.0 * t],
        2 => [6.0 * t, 3.0 * t + 2.0],
        3 => [6.0, 3.0],
        _ => [0.0, 0.0],
    };
    let t: Vec<f64> = (0..9)
        .map(|k| k as f64 * 0.3 + (k * k) as f64 * 0.01)
        .collect();
    let pts: Vec<f64> = t.iter().flat_map(|&x| f(x)).collect();
    let curve = interpolate_curve_at(2, &pts, &t, &EndCondition::NotAKnot)
        .unwrap()
        .into_curve();
    let pp = curve.to_piecewise().unwrap();
    for x in [0.05, 0.31, 1.0, 1.77, 2.9] {
        for k in 1..=4 {
            let want = df(x, k);
            for (name, c) in [("bspline", &curve as &dyn Curve), ("piecewise", &pp)] {
                let mut got = [0.0; 2];
                c.derivative_into(x, k, &mut got).unwrap();
                for i in 0..2 {
                    assert!(
                        (got[i] - want[i]).abs() <= 1e-10,
                        "{name} k {k} at {x}: {got:?} vs {want:?}"
                    );
                }
            }
        }
    }
}

/// A point equation through samples of a quadratic is that quadratic: M' = 2at + b,
/// M'' = 2a; from the number of nodes on, zero; a quartic's third and fourth derivatives.
#[test]
fn point_equation_derivatives_reproduce_a_quadratic() {
    let f = |t: f64| 3.0 * t * t - t + 0.5;
    let nodes = Nodes::new(vec![0.0, 0.4, 1.0]).unwrap();
    let pts = nodes.values().iter().map(|&t| vec![f(t)]).collect();
    let eq = PointEquation::new(nodes, pts).unwrap();
    for t in [0.1, 0.4, 0.77] {
        let mut d = [0.0];
        eq.derivative_into(t, 1, &mut d).unwrap();
        assert!((d[0] - (6.0 * t - 1.0)).abs() < 1e-13, "{t}");
        eq.derivative_into(t, 2, &mut d).unwrap();
        assert!((d[0] - 6.0).abs() < 1e-12, "{t}");
        eq.derivative_into(t, 3, &mut d).unwrap();
        assert_eq!(d, [0.0]);
    }
    // Above order 2: powers of the differentiation matrix. A quartic through 5 nodes.
    let g = |t: f64| t.powi(4) - 2.0 * t * t * t;
    let nodes = Nodes::new(vec![0.0, 0.25, 0.6, 0.75, 1.0]).unwrap();
    let pts = nodes.values().iter().map(|&t| vec![g(t)]).collect();
    let five = PointEquation::new(nodes, pts).unwrap();
    for t in [0.1, 0.6, 0.9] {
        for (k, want) in [(3, 24.0 * t - 12.0), (4, 24.0), (5, 0.0)] {
            let mut d = [0.0];
            five.derivative_into(t, k, &mut d).unwrap();
            assert!((d[0] - want).abs() < 1e-10, "k {k} at {t}: {}", d[0]);
        }
    }
}

/// The rational quarter circle: p' is tangent (p · p' = 0) and central differences agree.
#[test]
fn rational_derivative_is_tangent_to_the_circle() {
    let arc = RationalBezierCurve::new(
        vec![vec![1.0, 0.0], vec![1.0, 1.0], vec![0.0, 1.0]],
        vec![1.0, std::f64::consts::FRAC_1_SQRT_2, 1.0],
    )
    .unwrap();
    for t in [0.0, 0.2, 0.5, 0.9] {
        let p = arc.eval(t);
        let mut d = [0.0; 2];
        arc.derivative_into(t, 1, &mut d).unwrap();
        assert!((p[0] * d[0] + p[1] * d[1]).abs() < 1e-14, "{t}");
        // |p''| along the normal: p'' · p = -|p'|² on the unit circle.
        let mut dd = [0.0; 2];
        arc.derivative_into(t, 2, &mut dd).unwrap();
        let v2 = d[0] * d[0] + d[1] * d[1];
        assert!(
            (dd[0] * p[0] + dd[1] * p[1] + v2).abs() < 1e-13 * v2.max(1.0),
            "{t}"
        );
    }
}

/// Partial derivatives of every surface against central differences of the order below.
#[test]
fn surface_derivatives_match_central_differences() {
    for (name, s) in surfaces() {
        let ((u0, u1), (v0, v1)) = s.domain();
        let (bu, bv) = s.breaks();
        let d = s.dim();
        let (hu, hv) = ((u1 - u0) * 1e-5, (v1 - v0) * 1e-5);
        let mut rng = Rng(23);
        let mut checked = 0;
        for _ in 0..30 {
            let u = u0 + (u1 - u0) * (0.5 + 0.45 * rng.uniform());
            let v = v0 + (v1 - v0) * (0.5 + 0.45 * rng.uniform());
            if bu.iter().any(|x| (x - u).abs() < 4.0 * hu)
                || bv.iter().any(|x| (x - v).abs() < 4.0 * hv)
            {
                continue;
            }
            for (ku, kv) in [(1, 0), (0, 1), (2, 0), (1, 1), (0, 2)] {
                let (du, dv) = if ku > 0 { (1, 0) } else { (0, 1) };
                let lower = (ku - du, kv - dv);
                let (mut lo, mut hi, mut got) = (vec![0.0; d], vec![0.0; d], vec![0.0; d]);
                let (h, pu, pv) = if du == 1 {
                    (hu, hu, 0.0)
                } else {
                    (hv, 0.0, hv)
                };
                s.derivative_into(u - pu, v - pv, lower, &mut lo).unwrap();
                s.derivative_into(u + pu, v + pv, lower, &mut hi).unwrap();
                s.derivative_into(u, v, (ku, kv), &mut got).unwrap();
                let scale = max_abs(&got).max(max_abs(&lo)).max(1.0);
                for k in 0..d {
                    let fd = (hi[k] - lo[k]) / (2.0 * h);
                    assert!(
                        (fd - got[k]).abs() <= 1e-5 * scale,
                        "{name} ({ku}, {kv}) at ({u}, {v}): {fd} vs {}",
                        got[k]
                    );
                }
            }
            checked += 1;
        }
        assert!(checked > 5, "{name}");
        let mut out = vec![0.0; d];
        s.derivative_into(u0, v0, (0, 0), &mut out).unwrap();
        assert_eq!(out, s.eval(u0, v0), "{name}");
    }
}

/// Exact references for surfaces: a bicubic height field reproduced by a not-a-knot
/// B-spline surface (derivatives in closed form), and its composite surface, whose
/// derivatives come from another implementation (polynomial cells).
#[test]
fn surface_derivatives_reproduce_a_bicubic() {
    let f = |x: f64, y: f64| x * x * x - x * y * y + 2.0 * y;
    let df = |x: f64, y: f64, k: (usize, usize)| match k {
        (1, 0) => 3.0 * x * x - y * y,
        (0, 1) => -2.0 * x * y + 2.0,
        (2, 0) => 6.0 * x,
        (1, 1) => -2.0 * y,
        (0, 2) => -2.0 * x,
        (3, 0) => 6.0,
        (1, 2) => -2.0,
        _ => 0.0,
    };
    let (rows, cols) = (6, 7);
    let (dx, dy) = (0.5, 0.25);
    let z: Vec<f64> = (0..rows * cols)
        .map(|k| f((k / cols) as f64 * dx, (k % cols) as f64 * dy))
        .collect();
    let s = interpolate_heights(
        &z,
        rows,
        cols,
        (0.0, 0.0),
        (dx, dy),
        &EndCondition::NotAKnot,
    )
    .unwrap();
    let c = CompositeSurface::from_bspline(&s).unwrap();
    // Which of u, v is x: the surface reproduces f under one of the two readings.
    let at = Surface::eval(&s, 0.3, 0.2)[0];
    let x_is_u = (at - f(0.3, 0.2)).abs() < 1e-9;
    assert!(x_is_u || (at - f(0.2, 0.3)).abs() < 1e-9, "{at}");
    for (u, v) in [(0.3, 0.2), (1.1, 0.8), (1.2, 1.1)] {
        let (x, y) = if x_is_u { (u, v) } else { (v, u) };
        for k in [
            (1, 0),
            (0, 1),
            (2, 0),
            (1, 1),
            (0, 2),
            (3, 0),
            (1, 2),
            (4, 0),
        ] {
            let kxy = if x_is_u { k } else { (k.1, k.0) };
            let want = df(x, y, kxy);
            for (name, surface) in [("bspline", &s as &dyn Surface), ("composite", &c)] {
                let mut got = [0.0];
                surface.derivative_into(u, v, k, &mut got).unwrap();
                assert!(
                    (got[0] - want).abs() <= 1e-9,
                    "{name} {k:?} at ({u}, {v}): {} vs {want}",
                    got[0]
                );
            }
        }
    }
}

/// A composite of formula patches by the engine's symbolic derivative, against the closed
/// form of sin(x) cos(y) (the shift of the second cell is a constant).
#[test]
fn composite_formula_derivatives_are_symbolic() {
    let s = sin_cos_composite();
    for (x, y) in [(0.3f64, 0.2f64), (1.5, 0.5), (1.9, 0.9)] {
        for (k, want) in [
            ((1, 0), x.cos() * y.cos()),
            ((0, 1), -x.sin() * y.sin()),
            ((1, 1), -x.cos() * y.sin()),
            ((2, 0), -x.sin() * y.cos()),
            ((0, 3), x.sin() * y.sin()),
        ] {
            let mut d = [0.0];
            s.derivative_into(x, y, k, &mut d).unwrap();
            assert!((d[0] - want).abs() < 1e-14, "{k:?} at ({x}, {y}): {}", d[0]);
        }
    }
}

#[test]
fn bad_buffers_and_parameters_are_errors() {
    let options = BatchOptions::default();
    for (name, c) in curves() {
        let d = c.dim();
        let (a, _) = c.domain();
        let short = c.eval_batch(&[a, a], &mut vec![0.0; 2 * d - 1], &options);
        assert!(
            matches!(short, Err(Error::BufferSize { .. })),
            "{name}: {short:?}"
        );
        let nan = c.eval_batch(&[a, f64::NAN], &mut vec![0.0; 2 * d], &options);
        assert!(
            matches!(nan, Err(Error::NonFinite { index: 1, .. })),
            "{name}: {nan:?}"
        );
        assert!(matches!(
            c.derivative_into(f64::INFINITY, 1, &mut vec![0.0; d]),
            Err(Error::NonFinite { .. })
        ));
        assert!(matches!(
            c.derivative_into(a, 0, &mut vec![0.0; d + 1]),
            Err(Error::BufferSize { .. })
        ));
    }
    for (name, s) in surfaces() {
        let d = s.dim();
        let ((u, _), (v, _)) = s.domain();
        let odd = s.eval_batch(&[u, v, u], &mut vec![0.0; d], &options);
        assert!(
            matches!(odd, Err(Error::BufferSize { .. })),
            "{name}: {odd:?}"
        );
        let short = s.eval_batch(&[u, v], &mut vec![0.0; d + 1], &options);
        assert!(
            matches!(short, Err(Error::BufferSize { .. })),
            "{name}: {short:?}"
        );
        let nan = s.eval_batch(&[u, v, u, f64::NAN], &mut vec![0.0; 2 * d], &options);
        assert!(
            matches!(nan, Err(Error::NonFinite { index: 3, .. })),
            "{name}: {nan:?}"
        );
        let grid = s.eval_grid(&[u], &[v, f64::NAN], &mut vec![0.0; 2 * d]);
        assert!(
            matches!(grid, Err(Error::NonFinite { .. })),
            "{name}: {grid:?}"
        );
        assert!(matches!(
            s.derivative_into(u, f64::NAN, (1, 0), &mut vec![0.0; d]),
            Err(Error::NonFinite { .. })
        ));
        assert!(matches!(
            s.derivative_into(u, v, (0, 0), &mut []),
            Err(Error::BufferSize { .. })
        ));
    }
}

#[test]
fn traits_are_shared_across_threads() {
    let all: Vec<(&str, Box<dyn Curve>)> = curves();
    std::thread::scope(|scope| {
        for (name, c) in &all {
            scope.spawn(move || {
                let (a, b) = c.domain();
                assert_eq!(c.sample_uniform(5).len(), 5 * c.dim(), "{name}");
                let _ = (a, b);
            });
        }
    });
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Random Bézier and B-spline curves: batches of any length equal single points bit for
    /// bit on either parallelism.
    #[test]
    fn random_batches_equal_single_points(
        n in 0usize..12,
        dim in 1usize..5,
        seed in 1u64..u64::MAX,
        len in 0usize..40,
    ) {
        let c = random_curve(n, dim, seed);
        let mut rng = Rng(seed | 1);
        let ts: Vec<f64> = (0..len).map(|_| 0.5 + 0.7 * rng.uniform()).collect();
        let degree = 1 + n % 4;
        let n_c = n + 4;
        let mut knots: Vec<f64> = (0..n_c + degree + 1).map(|_| rng.uniform()).collect();
        knots.sort_by(f64::total_cmp);
        let control: Vec<f64> = (0..dim * n_c).map(|_| rng.uniform()).collect();
        let b = BsplineCurve::from_flat(degree, knots, dim, control);
        let mut list: Vec<Box<dyn Curve>> = vec![Box::new(c)];
        if let Ok(b) = b {
            list.push(Box::new(b));
        }
        for curve in &list {
            for parallelism in BOTH {
                let mut out = vec![0.0; len * dim];
                let options = BatchOptions::default().with_parallelism(parallelism);
                curve.eval_batch(&ts, &mut out, &options).unwrap();
                for (t, p) in ts.iter().zip(out.chunks_exact(dim)) {
                    prop_assert_eq!(p, &curve.eval(*t)[..]);
                }
            }
        }
    }
}
