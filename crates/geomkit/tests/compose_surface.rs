//! Composite surfaces (spec/composite-surfaces.md §3-4): the structural evaluator equals the
//! single formula (9) everywhere — on every knot line, outside the grid, and where the patches
//! do not meet (shifted patches) — and the continuity report finds the jumps.

mod common;

use common::{disagreement, Rng};
use geomkit::bezier::BezierSurface;
use geomkit::bspline::{interpolate_surface, make_interp_surface, SurfaceInterpolationOptions};
use geomkit::compose::{CompositeSurface, GridLine, PolyPatch, SurfaceKind};
use geomkit::Error;
use proptest::prelude::*;

fn random_knots(rng: &mut Rng, n: usize) -> Vec<f64> {
    let mut k = vec![rng.uniform() * 3.0];
    for _ in 0..n {
        let last = k[k.len() - 1];
        k.push(last + 0.05 + (rng.uniform() + 1.0));
    }
    k
}

fn random_patch(rng: &mut Rng, p: usize, q: usize) -> BezierSurface {
    let net = (0..=p)
        .map(|_| {
            (0..=q)
                .map(|_| (0..3).map(|_| rng.uniform() * 4.0).collect())
                .collect()
        })
        .collect();
    BezierSurface::new(net).unwrap()
}

/// Every knot, the cell midpoints and quarter points, and points outside.
fn dense(knots: &[f64]) -> Vec<f64> {
    let (a, b) = (knots[0], knots[knots.len() - 1]);
    let mut xs = vec![a - 1.0, a - 1e-9, b + 1e-9, b + 2.5];
    for w in knots.windows(2) {
        for f in [0.0, 0.25, 0.5, 0.75] {
            xs.push(w[0] + f * (w[1] - w[0]));
        }
    }
    xs.push(b);
    xs
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]
    /// Random knots, random (discontinuous) bicubic patches, n and m from 1 to 10.
    #[test]
    fn structural_equals_formula_everywhere(n in 1usize..=10, m in 1usize..=10, seed in 1u64..u64::MAX) {
        let mut rng = Rng(seed | 1);
        let uk = random_knots(&mut rng, n);
        let vk = random_knots(&mut rng, m);
        let patches: Vec<Vec<BezierSurface>> =
            (0..n).map(|_| (0..m).map(|_| random_patch(&mut rng, 3, 3)).collect()).collect();
        let s = CompositeSurface::from_bezier(uk.clone(), vk.clone(), &patches).unwrap();
        let (worst, scale) = disagreement(&s, &dense(&uk), &dense(&vk));
        prop_assert!(worst <= 1e-12 * scale, "difference {worst:e} at scale {scale}");
        if n * m > 1 {
            prop_assert!(!s.continuity().is_continuous());
        }
    }
}

#[test]
fn continuous_patches_are_reproduced_and_discontinuous_ones_shifted() {
    // A bicubic B-spline surface: its cells meet with C2 continuity.
    let grid: Vec<Vec<Vec<f64>>> = (0..7)
        .map(|i| {
            (0..6)
                .map(|j| {
                    let (x, y) = (i as f64 * 0.5, j as f64 * 0.7);
                    vec![x, y, (x * 1.3).sin() * (y * 0.9).cos()]
                })
                .collect()
        })
        .collect();
    let fit = interpolate_surface(&grid, &SurfaceInterpolationOptions::default()).unwrap();
    let s = CompositeSurface::from_bspline(&fit.surface).unwrap();
    assert!(
        s.continuity().is_continuous(),
        "{:?}",
        s.continuity().max_jump
    );
    let ((u0, u1), (v0, v1)) = s.domain();
    let mut worst = 0.0f64;
    for a in 0..=40 {
        for b in 0..=40 {
            let u = u0 + (u1 - u0) * a as f64 / 40.0;
            let v = v0 + (v1 - v0) * b as f64 / 40.0;
            let want = fit
                .surface
                .eval(u.min(u1 * (1.0 - 1e-15)), v.min(v1 * (1.0 - 1e-15)));
            let got = s.eval(u, v);
            for k in 0..3 {
                worst = worst.max((want[k] - got[k]).abs());
            }
        }
    }
    assert!(worst < 1e-12, "{worst:e}");

    // The cells of random bicubic height fields (SciPy's clamped not-a-knot form) meet within the rounding of their
    // power-basis coefficients (jumps up to ~1.4x 64ε·max|z| were reported as gaps).
    let mut rng = Rng(20261204);
    for _ in 0..200 {
        let z: Vec<f64> = (0..42).map(|_| rng.uniform()).collect();
        let x: Vec<f64> = (0..7).map(f64::from).collect();
        let s = make_interp_surface(&x, &x[..6], &z, (7, 6), (3, 3)).unwrap();
        let c = CompositeSurface::from_bspline(&s)
            .unwrap()
            .continuity()
            .clone();
        assert!(c.is_continuous(), "{:e} > {:e}", c.max_jump, c.tolerance);
        assert!(c.tolerance < 1e-11, "{:e}", c.tolerance);
    }

    // Two flat patches that do not meet: z = 0 on [0,1], z = 1 + u-shaped on [1,2].
    let flat = |z0: f64, z1: f64| PolyPatch::new((1, 0), 1, vec![z0, z1 - z0]).unwrap();
    let s = CompositeSurface::from_poly(
        vec![0.0, 1.0, 2.0],
        vec![0.0, 1.0],
        vec![vec![flat(0.0, 1.0)], vec![flat(5.0, 6.0)]],
        SurfaceKind::Explicit,
    )
    .unwrap();
    let r = s.continuity();
    assert!(!r.is_continuous());
    assert_eq!(r.jumps.len(), 1);
    assert_eq!(r.jumps[0].line, GridLine::U(1));
    assert!((r.max_jump - 4.0).abs() < 1e-15);
    let text = r.statement("x", "y", s.knots());
    assert!(
        text.contains("NOT continuous") && text.contains("shifts"),
        "{text}"
    );
    // Formula (11): the second patch is shifted down by the jump, 4, to stay attached.
    assert_eq!(s.eval(1.5, 0.5), vec![1.5]);
    assert_eq!(s.eval_formula(1.5, 0.5), vec![1.5]);
    // Outside the grid points map onto the boundary.
    assert_eq!(s.eval(7.0, -3.0), vec![2.0]);
    assert_eq!(s.eval_formula(7.0, -3.0), vec![2.0]);
}

#[test]
fn bad_grids_are_errors() {
    let p = || PolyPatch::new((0, 0), 3, vec![0.0; 3]).unwrap();
    let e = CompositeSurface::from_poly(
        vec![0.0, 1.0, 1.0],
        vec![0.0, 1.0],
        vec![vec![p()], vec![p()]],
        SurfaceKind::Parametric,
    )
    .unwrap_err();
    assert!(matches!(e, Error::InvalidKnots { index: 2, .. }), "{e}");
    let e = CompositeSurface::from_poly(
        vec![0.0, 1.0, 2.0],
        vec![0.0, 1.0],
        vec![vec![p()]],
        SurfaceKind::Parametric,
    )
    .unwrap_err();
    assert!(
        matches!(
            e,
            Error::PatchCount {
                expected: 2,
                got: 1,
                ..
            }
        ),
        "{e}"
    );
    let e = CompositeSurface::from_poly(
        vec![0.0, 1.0],
        vec![0.0, 1.0, 2.0],
        vec![vec![p()]],
        SurfaceKind::Parametric,
    )
    .unwrap_err();
    assert!(e.to_string().contains("patches in row 0"), "{e}");
    let e = CompositeSurface::from_poly(
        vec![0.0, f64::NAN],
        vec![0.0, 1.0],
        vec![vec![p()]],
        SurfaceKind::Parametric,
    )
    .unwrap_err();
    assert!(matches!(e, Error::NonFinite { index: 1, .. }), "{e}");
    let s = CompositeSurface::from_poly(
        vec![0.0, 1.0],
        vec![0.0, 1.0],
        vec![vec![p()]],
        SurfaceKind::Parametric,
    )
    .unwrap();
    let mut out = vec![0.0; 3];
    assert!(s.eval_many(&[0.0, f64::NAN], &mut out).is_err());
    assert!(s.eval_many(&[0.0, 0.5], &mut out[..2]).is_err());
}

#[test]
fn bicubic_formula_is_small_and_equals_the_literal_formula() {
    let mut rng = Rng(99);
    let (n, m) = (10, 10);
    let uk = random_knots(&mut rng, n);
    let vk = random_knots(&mut rng, m);
    let patches: Vec<Vec<BezierSurface>> = (0..n)
        .map(|_| (0..m).map(|_| random_patch(&mut rng, 3, 3)).collect())
        .collect();
    let s = CompositeSurface::from_bezier(uk.clone(), vk.clone(), &patches).unwrap();
    let f = s.formula().unwrap();
    // An inner patch is Σ c_ab s^a t^b (a, b >= 1) per coordinate, the 9 monomials shared by
    // x, y, z: about 68 operations per patch, within the 75 (Horner form cost 80,
    // since the engine distributes every constant times a ramp over its two |.| terms).
    let ops = f.op_count();
    assert!(ops <= 75 * n * m, "{ops} operations for {} patches", n * m);
    // Linear growth: 20×20 patches cost at most 4.1 times as much.
    let big: Vec<Vec<BezierSurface>> = (0..2 * n)
        .map(|_| (0..2 * m).map(|_| random_patch(&mut rng, 3, 3)).collect())
        .collect();
    let s2 = CompositeSurface::from_bezier(
        random_knots(&mut rng, 2 * n),
        random_knots(&mut rng, 2 * m),
        &big,
    )
    .unwrap();
    let ops2 = s2.formula().unwrap().op_count();
    assert!(ops2 as f64 <= 4.1 * ops as f64, "{ops} -> {ops2}");
    let us = dense(&uk);
    let vs = dense(&vk);
    let (mut pu, mut pv) = (Vec::new(), Vec::new());
    for &u in &us {
        for &v in &vs {
            pu.push(u);
            pv.push(v);
        }
    }
    let mut out = vec![0.0; pu.len() * 3];
    f.eval_batch(&[&pu, &pv], &mut out).unwrap();
    let mut worst = 0.0f64;
    for (k, p) in out.chunks_exact(3).enumerate() {
        let q = s.eval(pu[k], pv[k]);
        for c in 0..3 {
            worst = worst.max((p[c] - q[c]).abs());
        }
    }
    assert!(worst <= 1e-12 * 100.0, "{worst:e}");
}
