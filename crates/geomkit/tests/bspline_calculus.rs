//! Identities of the B-spline calculus (issue 22) on random splines of degrees 0 to 7
//! (clamped and non-clamped uneven knots, 1 to 3 coordinates): the derivative of the
//! antiderivative is the curve, integrals are F(b) - F(a) and agree with Gauss–Legendre
//! quadrature per polynomial piece, the derivative curves give the derivatives, knot
//! insertion keeps the curve, periodic evaluation repeats one period apart. The SciPy
//! reference values are in `reference_calculus.rs`.
//!
//! Tolerances follow the rounding of each operation, in units of eps = 2^-52: an
//! antiderivative coefficient is a running sum of terms c_i·Δt_i (error <= n·eps·max|c|·L
//! over knots of length L), its derivative divides differences of them by spans of at least
//! the smallest knot step h, so the round trip is within ~(k+1)·n·eps·max|c|·L/h; values
//! are sums of k+1 terms within a convex combination of the coefficients (a few eps of
//! max|c|). Knot steps here are at least 0.1 on knots of length at most 30.

use geomkit::bspline::{BsplineCurve, Extrapolate};
use geomkit::Error;
use proptest::prelude::*;

const EPS: f64 = f64::EPSILON;

/// A spline: degree, clamped or not, interior knot steps, coefficients, dimension.
fn spline() -> impl Strategy<Value = BsplineCurve> {
    (
        0usize..=7,
        0usize..=6,
        1usize..=3,
        any::<bool>(),
        prop::collection::vec(0.1f64..1.5, 30),
        prop::collection::vec(-5.0f64..5.0, 3 * 20),
    )
        .prop_map(|(k, inner, dim, clamped, steps, coefs)| {
            let n = inner + k + 1;
            let knots: Vec<f64> = if clamped {
                let mut t = vec![0.0; k + 1];
                let mut x = 0.0;
                for s in &steps[..=inner] {
                    x += s;
                    t.push(x);
                }
                let end = t.pop().expect("one step at least");
                t.extend(std::iter::repeat_n(end, k + 1));
                t
            } else {
                let mut x = -1.0;
                std::iter::once(x)
                    .chain(steps[..n + k].iter().map(|s| {
                        x += s;
                        x
                    }))
                    .collect()
            };
            BsplineCurve::from_flat(k, knots, dim, coefs[..n * dim].to_vec()).expect("valid")
        })
}

fn eval(c: &BsplineCurve, x: &[f64], nu: usize, mode: Extrapolate) -> Vec<f64> {
    let mut out = vec![0.0; x.len() * c.dim()];
    c.eval_nu_many(x, nu, mode, &mut out).unwrap();
    out
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// Σ_i |N_i^(nu)(x)|·|c_i| per point and coordinate: the scale of the rounding of
/// evaluating `c`'s nu-th derivative at x, also beyond the domain, where the extended
/// pieces' basis values grow and alternate in sign (the basis values from the curve with the
/// identity as coefficients).
fn spread(c: &BsplineCurve, x: &[f64], nu: usize) -> Vec<f64> {
    let (n, d) = (c.n_control(), c.dim());
    let mut unit = vec![0.0; n * n];
    (0..n).for_each(|i| unit[i * n + i] = 1.0);
    let basis = BsplineCurve::from_flat(c.degree(), c.knots().to_vec(), n, unit).unwrap();
    let values = eval(&basis, x, nu, Extrapolate::Extend);
    values
        .chunks(n)
        .flat_map(|b| {
            (0..d).map(move |j| {
                b.iter()
                    .zip(c.control_flat().chunks(d))
                    .map(|(v, p)| (v * p[j]).abs())
                    .sum::<f64>()
            })
        })
        .collect()
}

/// Knot length over the smallest positive knot step.
fn knot_ratio(c: &BsplineCurve) -> f64 {
    let t = c.knots();
    let h = t
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|&d| d > 0.0)
        .fold(f64::INFINITY, f64::min);
    (t[t.len() - 1] - t[0]) / h
}

/// `count` parameters spread over [a - margin, b + margin].
fn params(a: f64, b: f64, margin: f64, fractions: &[f64]) -> Vec<f64> {
    fractions
        .iter()
        .map(|f| a - margin + f * (b - a + 2.0 * margin))
        .collect()
}

/// 4-point Gauss–Legendre nodes and weights on [-1, 1] (exact to degree 7).
const GAUSS: [(f64, f64); 4] = [
    (-0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
    (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
    (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
    (0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
];

/// ∫_a^b of the extended curve by Gauss–Legendre between the knots, and ∫ of [`spread`]
/// likewise (the scale of its rounding).
fn quadrature(c: &BsplineCurve, a: f64, b: f64) -> (Vec<f64>, Vec<f64>) {
    let (lo, hi) = (a.min(b), a.max(b));
    let mut cuts: Vec<f64> = std::iter::once(lo)
        .chain(c.knots().iter().copied().filter(|&t| t > lo && t < hi))
        .chain(std::iter::once(hi))
        .collect();
    cuts.dedup();
    let d = c.dim();
    let (mut sum, mut abs) = (vec![0.0; d], vec![0.0; d]);
    for w in cuts.windows(2) {
        let (m, r) = (0.5 * (w[0] + w[1]), 0.5 * (w[1] - w[0]));
        let xs: Vec<f64> = GAUSS.iter().map(|(x, _)| m + r * x).collect();
        let (f, s) = (eval(c, &xs, 0, Extrapolate::Extend), spread(c, &xs, 0));
        for ((g, row), s) in GAUSS.iter().zip(f.chunks(d)).zip(s.chunks(d)) {
            for i in 0..d {
                sum[i] += g.1 * r * row[i];
                abs[i] += g.1 * r * s[i];
            }
        }
    }
    let sign = if b < a { -1.0 } else { 1.0 };
    (sum.iter().map(|s| s * sign).collect(), abs)
}

proptest! {
    /// d/dx of the antiderivative is the curve, inside the base interval and beyond it.
    #[test]
    fn antiderivative_differentiates_to_the_curve(
        c in spline(),
        fractions in prop::collection::vec(0.0f64..1.0, 50),
    ) {
        let (a, b) = c.domain();
        let x = params(a, b, 0.3 * (b - a), &fractions);
        let f = c.antiderivative(1).unwrap();
        prop_assert_eq!(f.degree(), c.degree() + 1);
        let df = eval(&f, &x, 1, Extrapolate::Extend);
        let want = eval(&c, &x, 0, Extrapolate::Extend);
        let n = c.n_control() as f64;
        let tol = 8.0 * (c.degree() + 2) as f64 * n * EPS * knot_ratio(&c) * max_abs(&want).max(max_abs(c.control_flat()));
        let (sf, sc) = (spread(&f, &x, 1), spread(&c, &x, 0));
        for (i, (g, w)) in df.iter().zip(&want).enumerate() {
            let tol = tol.max(64.0 * EPS * (sf[i] + sc[i]));
            prop_assert!((g - w).abs() <= tol, "{} vs {} (tol {:e})", g, w, tol);
        }
        // The derivative curve of the antiderivative has the curve's knots and coefficients.
        let back = f.derivative_nu(1).unwrap();
        prop_assert_eq!(back.knots(), c.knots());
        let cmax = max_abs(c.control_flat());
        for (g, w) in back.control_flat().iter().zip(c.control_flat()) {
            prop_assert!((g - w).abs() <= tol.max(8.0 * n * EPS * knot_ratio(&c) * cmax));
        }
    }

    /// integrate = F(b) - F(a) (Extend), the quadrature of the pieces, and the clipped
    /// integral (Nan); one period in Periodic mode is the integral over the base interval.
    #[test]
    fn integrals_are_antiderivative_differences(
        c in spline(),
        ab in (0.0f64..1.0, 0.0f64..1.0),
    ) {
        let (lo, hi) = c.domain();
        let p = hi - lo;
        let (a, b) = (lo - 0.5 * p + 2.0 * p * ab.0, lo - 0.5 * p + 2.0 * p * ab.1);
        let f = c.antiderivative(1).unwrap();
        let fab = eval(&f, &[a, b], 0, Extrapolate::Extend);
        let d = c.dim();
        let got = c.integrate(a, b, Extrapolate::Extend);
        for i in 0..d {
            prop_assert_eq!(got[i], fab[d + i] - fab[i]);
        }
        let (quad, quad_abs) = quadrature(&c, a, b);
        let sf = spread(&f, &[a, b], 0);
        for i in 0..d {
            let scale = quad_abs[i] + sf[i] + sf[d + i];
            // Beyond the domain both sides evaluate extrapolated pieces, whose rounding grows
            // with the distance over the shortest knot span (as in the test above).
            let tol = 64.0 * EPS * c.n_control() as f64 * knot_ratio(&c) * scale;
            prop_assert!((got[i] - quad[i]).abs() <= tol, "{} vs {}", got[i], quad[i]);
        }
        let clipped = c.integrate(a, b, Extrapolate::Nan);
        let (ca, cb) = (a.clamp(lo, hi), b.clamp(lo, hi));
        let inside = c.integrate(ca, cb, Extrapolate::Extend);
        for i in 0..d {
            prop_assert!((clipped[i] - inside[i]).abs() <= 64.0 * EPS * (fab[i].abs() + fab[d + i].abs() + 1.0));
        }
        let period = c.integrate(a, a + p, Extrapolate::Periodic);
        let base = c.integrate(lo, hi, Extrapolate::Extend);
        let fl = eval(&f, &[lo, hi], 0, Extrapolate::Extend);
        for i in 0..d {
            let tol = 64.0 * EPS * (fl[i].abs() + fl[d + i].abs() + max_abs(c.control_flat()) * p);
            prop_assert!((period[i] - base[i]).abs() <= tol, "{} vs {}", period[i], base[i]);
        }
    }

    /// The derivative curves give the derivatives (orders 0..=k), wherever they exist.
    #[test]
    fn derivative_curves_give_the_derivatives(
        c in spline(),
        fractions in prop::collection::vec(0.0f64..1.0, 20),
    ) {
        let (a, b) = c.domain();
        let x = params(a, b, 0.2 * (b - a), &fractions);
        for nu in 0..=c.degree() {
            let dc = c.derivative_nu(nu).unwrap();
            prop_assert_eq!(dc.degree(), c.degree() - nu);
            let got = eval(&dc, &x, 0, Extrapolate::Extend);
            let want = eval(&c, &x, nu, Extrapolate::Extend);
            let tol = 1e-12 * max_abs(&want).max(max_abs(dc.control_flat()));
            let (sd, sc) = (spread(&dc, &x, 0), spread(&c, &x, nu));
            for (i, (g, w)) in got.iter().zip(&want).enumerate() {
                let tol = tol.max(64.0 * EPS * (sd[i] + sc[i]));
                prop_assert!((g - w).abs() <= tol, "order {}: {} vs {}", nu, g, w);
            }
        }
        let e = c.derivative_nu(c.degree() + 1).unwrap_err();
        prop_assert!(matches!(e, Error::DerivativeOrder { .. }), "{}", e);
    }

    /// Inserting a knot (between knots or at one, up to k+1 times) keeps the curve: values at
    /// 50 points of the base interval within 1e-13 of max|c|.
    #[test]
    fn insertion_keeps_the_curve(
        c in spline(),
        at in 0.0f64..1.0,
        on_knot in any::<bool>(),
        m in 1usize..=8,
        fractions in prop::collection::vec(0.0f64..1.0, 50),
    ) {
        let (a, b) = c.domain();
        let inner: Vec<f64> = c.knots().iter().copied().filter(|&t| t > a && t < b).collect();
        let x = if on_knot && !inner.is_empty() {
            inner[(at * inner.len() as f64) as usize % inner.len()]
        } else {
            a + at * (b - a)
        };
        let mult = c.knots().iter().filter(|&&t| t == x).count();
        let m = m.min((c.degree() + 1).saturating_sub(mult)).max(1);
        let i = c.insert_knot(x, m).unwrap();
        prop_assert_eq!(i.n_control(), c.n_control() + m);
        prop_assert_eq!(i.knots().iter().filter(|&&t| t == x).count(),
            c.knots().iter().filter(|&&t| t == x).count() + m);
        // Points of [a, b) (at b the inserted curve may have an empty last interval).
        let ts: Vec<f64> = fractions.iter().map(|f| a + f * (b - a)).collect();
        let (p, q) = (eval(&c, &ts, 0, Extrapolate::Extend), eval(&i, &ts, 0, Extrapolate::Extend));
        let tol = 1e-13 * max_abs(c.control_flat()).max(f64::MIN_POSITIVE);
        for (u, v) in p.iter().zip(&q) {
            prop_assert!((u - v).abs() <= tol, "{} vs {} after inserting {} x{}", u, v, x, m);
        }
    }

    /// Periodic evaluation repeats with the period P = t_n - t_k: values (and the first
    /// derivative) at x and x + jP agree up to the rounding of the mapped parameter.
    #[test]
    fn periodic_evaluation_repeats(
        c in spline(),
        frac in 0.01f64..0.99,
        j in -3i32..=3,
    ) {
        let (a, b) = c.domain();
        let p = b - a;
        let x = a + frac * p;
        let y = x + f64::from(j) * p;
        let dc = c.derivative_nu(1.min(c.degree())).unwrap();
        for nu in [0, 1] {
            let (u, v) = (eval(&c, &[x], nu, Extrapolate::Periodic), eval(&c, &[y], nu, Extrapolate::Periodic));
            // |Δvalue| <= max|f^(nu+1)| · |Δmapped x|, the mapped x within a few ulps of |y| + P.
            let slope = if nu == 0 { max_abs(dc.control_flat()) } else { max_abs(c.derivative_nu(2.min(c.degree())).unwrap().control_flat()) };
            let tol = 8.0 * EPS * (slope * (y.abs() + p + a.abs()) + max_abs(&u));
            for (s, t) in u.iter().zip(&v) {
                prop_assert!((s - t).abs() <= tol, "nu {}: {} vs {} ({} periods)", nu, s, t, j);
            }
        }
    }
}

/// Degrees up to the cap: seven antiderivatives of a degree-7 curve and back; degree 16 is
/// refused by name.
#[test]
fn antiderivatives_up_to_the_degree_cap() {
    let knots: Vec<f64> = (0..20)
        .map(|i| f64::from(i) * 0.5 + 0.01 * f64::from(i * i))
        .collect();
    let c = BsplineCurve::from_flat(
        7,
        knots,
        1,
        (0..12).map(|i| f64::from(i % 5) - 2.0).collect(),
    )
    .unwrap();
    let f = c.antiderivative(8).unwrap();
    assert_eq!(f.degree(), BsplineCurve::MAX_DEGREE);
    let back = f.derivative_nu(8).unwrap();
    assert_eq!(back.knots(), c.knots());
    for (a, b) in back.control_flat().iter().zip(c.control_flat()) {
        assert!((a - b).abs() < 1e-9, "{a} vs {b}");
    }
    // Degree 15 evaluates (values and derivatives) like the curve's integral.
    let (lo, hi) = c.domain();
    let x: Vec<f64> = (0..=10)
        .map(|i| lo + (hi - lo) * f64::from(i) / 10.0)
        .collect();
    let mut d8 = vec![0.0; x.len()];
    f.eval_nu_many(&x, 8, Extrapolate::Extend, &mut d8).unwrap();
    let mut v = vec![0.0; x.len()];
    c.eval_nu_many(&x, 0, Extrapolate::Extend, &mut v).unwrap();
    for (a, b) in d8.iter().zip(&v) {
        assert!((a - b).abs() < 1e-8, "{a} vs {b}");
    }
    let e = f.antiderivative(1).unwrap_err();
    assert_eq!(
        e.to_string(),
        "invalid target degree 16 for a curve of degree 15: B-spline curves hold degrees 0 to \
         15 (BsplineCurve::MAX_DEGREE)"
    );
    assert!(BsplineCurve::from_flat(16, vec![0.0; 34], 1, vec![0.0; 17]).is_err());
}

/// Batches beyond one chunk run in parallel and give the values of the single points.
#[test]
fn large_batches_equal_single_points() {
    let knots: Vec<f64> = (0..40).map(|i| f64::from(i).sqrt()).collect();
    let c = BsplineCurve::from_flat(
        5,
        knots,
        2,
        (0..68).map(|i| f64::from(i % 7) * 0.3).collect(),
    )
    .unwrap();
    let (a, b) = c.domain();
    let x: Vec<f64> = (0..20_000)
        .map(|i| a - 1.0 + (b - a + 2.0) * f64::from((i * 7919) % 20_000) / 20_000.0)
        .collect();
    for mode in [Extrapolate::Extend, Extrapolate::Nan, Extrapolate::Periodic] {
        let mut all = vec![0.0; 2 * x.len()];
        c.eval_nu_many(&x, 2, mode, &mut all).unwrap();
        for (i, &t) in x.iter().enumerate().step_by(997) {
            let mut one = [0.0; 2];
            c.eval_nu_many(&[t], 2, mode, &mut one).unwrap();
            assert_eq!(one[0].to_bits(), all[2 * i].to_bits());
            assert_eq!(one[1].to_bits(), all[2 * i + 1].to_bits());
        }
    }
    let mut short = vec![0.0; 3];
    assert!(matches!(
        c.eval_nu_many(&x, 0, Extrapolate::Extend, &mut short),
        Err(Error::BufferSize { .. })
    ));
}
