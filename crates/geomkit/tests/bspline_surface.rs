//! Interpolating bicubic B-spline surfaces (spec/bspline-interpolation.md §3).

mod common;

use common::Rng;
use geomkit::bspline::{
    interpolate_heights, interpolate_surface, interpolate_surface_flat, EndCondition,
    Parametrization, SurfaceInterpolationOptions,
};
use geomkit::Error;

fn terrain(rows: usize, cols: usize, seed: u64) -> Vec<Vec<Vec<f64>>> {
    let mut rng = Rng(seed | 1);
    (0..rows)
        .map(|i| {
            (0..cols)
                .map(|j| {
                    let (x, y) = (
                        i as f64 + 0.2 * rng.uniform(),
                        j as f64 + 0.2 * rng.uniform(),
                    );
                    vec![
                        x,
                        y,
                        (0.4 * x).sin() * (0.3 * y).cos() + 0.1 * rng.uniform(),
                    ]
                })
                .collect()
        })
        .collect()
}

fn grid_residual(grid: &[Vec<Vec<f64>>], fit: &geomkit::bspline::SurfaceInterpolation) -> f64 {
    let scale = grid
        .iter()
        .flatten()
        .flatten()
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let mut worst = 0.0f64;
    for (i, row) in grid.iter().enumerate().take(fit.params_u.len()) {
        for (j, p) in row.iter().enumerate().take(fit.params_v.len()) {
            let q = fit.surface.eval(fit.params_u[i], fit.params_v[j]);
            for (a, b) in p.iter().zip(&q) {
                worst = worst.max((a - b).abs());
            }
        }
    }
    worst / scale
}

#[test]
fn passes_through_every_grid_point() {
    let ends = [
        EndCondition::Natural,
        EndCondition::NotAKnot,
        EndCondition::Clamped {
            start: None,
            end: None,
        },
        EndCondition::Bessel,
        EndCondition::OuterPoints { offset: 0.1 },
    ];
    for (rows, cols) in [(2usize, 2usize), (3, 5), (14, 14), (40, 23)] {
        for end in &ends {
            for param in common::PARAMETRIZATIONS {
                let grid = terrain(rows, cols, (rows * 100 + cols) as u64);
                let opts = SurfaceInterpolationOptions::default()
                    .with_end(end.clone())
                    .with_parametrization(param);
                let fit = interpolate_surface(&grid, &opts).unwrap();
                let r = grid_residual(&grid, &fit);
                assert!(r <= 1e-14, "{rows}x{cols} {end:?} {param:?}: {r:e}");
            }
        }
    }
}

#[test]
fn paper_boundary_gives_m_plus_2_by_n_plus_2_net() {
    let grid = terrain(14, 14, 3);
    let opts = SurfaceInterpolationOptions::default()
        .with_end(EndCondition::OuterPoints { offset: 0.1 })
        .with_parametrization(Parametrization::Uniform);
    let fit = interpolate_surface(&grid, &opts).unwrap();
    assert_eq!(fit.surface.net_size(), (16, 16));
    // The corner of the outer ring is the diagonal extrapolation of the corner point:
    // 1.21 k00 - 0.11 k01 - 0.11 k10 + 0.01 k11.
    let corner = &fit.surface.control_flat()[..3];
    for c in 0..3 {
        let want = 1.21 * grid[0][0][c] - 0.11 * grid[0][1][c] - 0.11 * grid[1][0][c]
            + 0.01 * grid[1][1][c];
        assert!(
            (corner[c] - want).abs() < 1e-13,
            "{c}: {} vs {want}",
            corner[c]
        );
    }
}

#[test]
fn torus_is_periodic_in_both_directions() {
    let (m, n) = (12usize, 16usize);
    let grid: Vec<Vec<Vec<f64>>> = (0..m)
        .map(|i| {
            let a = i as f64 * std::f64::consts::TAU / m as f64;
            (0..n)
                .map(|j| {
                    let b = j as f64 * std::f64::consts::TAU / n as f64;
                    let r = 3.0 + b.cos();
                    vec![r * a.cos(), r * a.sin(), b.sin()]
                })
                .collect()
        })
        .collect();
    let opts = SurfaceInterpolationOptions::default().with_end(EndCondition::Periodic);
    let fit = interpolate_surface(&grid, &opts).unwrap();
    assert!(grid_residual(&grid, &fit) < 1e-14);
    let ((u0, u1), (v0, v1)) = fit.surface.domain();
    for v in [v0, 0.37 * (v1 - v0) + v0] {
        for (ku, kv) in [(0, 0), (1, 0), (2, 0), (0, 1), (0, 2), (1, 1)] {
            let (mut a, mut b) = ([0.0; 3], [0.0; 3]);
            fit.surface.eval_derivative(u0, v, ku, kv, &mut a);
            fit.surface.eval_derivative(u1, v, ku, kv, &mut b);
            for c in 0..3 {
                assert!(
                    (a[c] - b[c]).abs() < 1e-10 * (1.0 + a[c].abs()),
                    "d({ku},{kv}) {a:?} {b:?}"
                );
            }
        }
    }
    assert!(fit.surface.normal(u0, v0).unwrap().is_some());
}

#[test]
fn heights_over_a_regular_grid() {
    let (rows, cols) = (30usize, 20usize);
    let z: Vec<f64> = (0..rows * cols)
        .map(|k| {
            let (x, y) = (
                10.0 + 0.5 * (k / cols) as f64,
                -3.0 + 0.25 * (k % cols) as f64,
            );
            (x * 0.3).sin() + y * y * 0.1
        })
        .collect();
    let s = interpolate_heights(
        &z,
        rows,
        cols,
        (10.0, -3.0),
        (0.5, 0.25),
        &EndCondition::NotAKnot,
    )
    .unwrap();
    for k in (0..rows * cols).step_by(7) {
        let (x, y) = (
            10.0 + 0.5 * (k / cols) as f64,
            -3.0 + 0.25 * (k % cols) as f64,
        );
        assert!((s.eval(x, y)[0] - z[k]).abs() < 1e-14 * 2.0);
    }
    // A grid evaluation equals point evaluation.
    let xs = [10.0, 12.3, 24.5];
    let ys = [-3.0, -1.1, 1.75];
    let mut out = vec![0.0; 9];
    s.eval_grid(&xs, &ys, &mut out).unwrap();
    for (a, x) in xs.iter().enumerate() {
        for (b, y) in ys.iter().enumerate() {
            assert!((out[a * 3 + b] - s.eval(*x, *y)[0]).abs() < 1e-14);
        }
    }
    // So does the scattered batch, and it rejects mismatched inputs.
    let ((u0, u1), (v0, v1)) = s.domain();
    let (us, vs): (Vec<f64>, Vec<f64>) = (0..1000)
        .map(|k| {
            let f = k as f64 / 999.0;
            (u0 + (u1 - u0) * f, v0 + (v1 - v0) * (1.0 - f * f))
        })
        .unzip();
    let mut batch = vec![0.0; us.len()];
    s.eval_many_par(&us, &vs, &mut batch).unwrap();
    for ((u, v), got) in us.iter().zip(&vs).zip(&batch) {
        let want = s.eval(*u, *v)[0];
        assert!((got - want).abs() < 1e-14, "({u}, {v}): {got} vs {want}");
    }
    assert!(s.eval_many_par(&us[1..], &vs, &mut batch[1..]).is_err());
    assert!(s
        .eval_many_par(&[f64::NAN], &[0.0], &mut batch[..1])
        .is_err());
    // Bicubic polynomials are reproduced exactly by not-a-knot.
    let zp: Vec<f64> = (0..rows * cols)
        .map(|k| {
            let (x, y) = ((k / cols) as f64, (k % cols) as f64);
            0.01 * x * x * x - 0.2 * x * y * y + y + 1.0
        })
        .collect();
    let sp = interpolate_heights(
        &zp,
        rows,
        cols,
        (0.0, 0.0),
        (1.0, 1.0),
        &EndCondition::NotAKnot,
    )
    .unwrap();
    let (x, y) = (7.3, 11.6);
    assert!((sp.eval(x, y)[0] - (0.01 * x * x * x - 0.2 * x * y * y + y + 1.0)).abs() < 1e-11);
    assert!(matches!(
        interpolate_heights(
            &z,
            rows,
            cols,
            (0.0, 0.0),
            (0.0, 1.0),
            &EndCondition::Natural
        ),
        Err(Error::InvalidOption { .. })
    ));
    assert!(matches!(
        interpolate_heights(
            &z[1..],
            rows,
            cols,
            (0.0, 0.0),
            (1.0, 1.0),
            &EndCondition::Natural
        ),
        Err(Error::BufferSize { .. })
    ));
}

#[test]
fn bad_grids_are_clear_errors() {
    let opts = SurfaceInterpolationOptions::default();
    assert!(matches!(
        interpolate_surface(&[], &opts),
        Err(Error::Empty { .. })
    ));
    let ragged = vec![vec![vec![0.0, 0.0, 0.0]; 3], vec![vec![0.0, 0.0, 0.0]; 2]];
    assert!(matches!(
        interpolate_surface(&ragged, &opts),
        Err(Error::RaggedNet { row: 1, .. })
    ));
    let mut g = terrain(4, 4, 1);
    g[2][3][1] = f64::NAN;
    assert!(matches!(
        interpolate_surface(&g, &opts),
        Err(Error::NonFinite { index: 11, .. })
    ));
    let one_row = terrain(1, 5, 2);
    assert!(matches!(
        interpolate_surface(&one_row, &opts),
        Err(Error::TooFewPoints { got: 1, .. })
    ));
    let given = opts.with_end(EndCondition::Clamped {
        start: Some(vec![1.0, 0.0, 0.0]),
        end: None,
    });
    assert!(matches!(
        interpolate_surface(&terrain(4, 4, 1), &given),
        Err(Error::InvalidOption { .. })
    ));
}

#[test]
fn heights_on_a_non_uniform_grid() {
    use geomkit::bspline::interpolate_heights_at;
    let xs = [0.0, 0.3, 1.0, 1.1, 2.5, 4.0];
    let ys = [-1.0, 0.0, 0.2, 3.0, 3.5];
    let f = |x: f64, y: f64| (x * 1.3).sin() + 0.2 * y * y - x * y * 0.1;
    let z: Vec<f64> = xs
        .iter()
        .flat_map(|&x| ys.iter().map(move |&y| f(x, y)))
        .collect();
    let s = interpolate_heights_at(&z, &xs, &ys, &EndCondition::NotAKnot).unwrap();
    for (i, &x) in xs.iter().enumerate() {
        for (j, &y) in ys.iter().enumerate() {
            assert!((s.eval(x, y)[0] - z[i * ys.len() + j]).abs() < 1e-14);
        }
    }
    // Bicubic polynomials are reproduced.
    let g = |x: f64, y: f64| 0.5 * x * x * x - x * y + 0.25 * y * y * y + 1.0;
    let zg: Vec<f64> = xs
        .iter()
        .flat_map(|&x| ys.iter().map(move |&y| g(x, y)))
        .collect();
    let sg = interpolate_heights_at(&zg, &xs, &ys, &EndCondition::NotAKnot).unwrap();
    assert!((sg.eval(1.7, 2.1)[0] - g(1.7, 2.1)).abs() < 1e-12);
    let bad = [0.0, 0.3, 0.3, 1.1, 2.5, 4.0];
    assert!(matches!(
        interpolate_heights_at(&z, &bad, &ys, &EndCondition::NotAKnot),
        Err(Error::InvalidParameter { index: 2, .. })
    ));
}

#[test]
fn surface_tiles_equal_the_global_solve() {
    use geomkit::bspline::{interpolate_surface_flat, interpolate_surface_tiled, TileOptions};
    let (rows, cols) = (1024usize, 1024usize);
    let z: Vec<f64> = (0..rows * cols)
        .map(|k| {
            let (x, y) = ((k / cols) as f64 * 0.01, (k % cols) as f64 * 0.013);
            (x * 3.0).sin() * (y * 2.0).cos() + 0.3 * ((k * 2654435761) % 1000) as f64 / 1000.0
        })
        .collect();
    let scale = z.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for end in [EndCondition::NotAKnot, EndCondition::Natural] {
        let opts = SurfaceInterpolationOptions::default()
            .with_end(end.clone())
            .with_parametrization(Parametrization::Uniform);
        let global = interpolate_surface_flat(rows, cols, 1, &z, &opts).unwrap();
        let tiled = interpolate_surface_tiled(
            rows,
            cols,
            1,
            &z,
            &opts,
            &TileOptions::default().with_tile_size(300),
        )
        .unwrap();
        assert_eq!(global.surface.knots(), tiled.surface.knots());
        let err = global
            .surface
            .control_flat()
            .iter()
            .zip(tiled.surface.control_flat())
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        // max|p| over the solution's control points (the paper's p*): two passes of rounding,
        // each a few ulps of the controls, which noisy data make ~4x larger than the data.
        let cscale = global
            .surface
            .control_flat()
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(
            err <= 4.0 * f64::EPSILON * cscale,
            "{end:?}: {err:e} (data {scale}, control {cscale})"
        );
    }
    assert!(interpolate_surface_tiled(
        rows,
        cols,
        1,
        &z,
        &SurfaceInterpolationOptions::default().with_end(EndCondition::Periodic),
        &TileOptions::default()
    )
    .is_err());
}

/// Large scattered batches on nets larger than the caches are grouped by span before they
/// are evaluated: each point must get the value it gets in a small batch, bit for bit, for
/// height surfaces and surfaces in R^3, with points in any order and outside the domain.
#[test]
fn grouped_scattered_evaluation_equals_small_batches() {
    let mut rng = Rng(23);
    let heights: Vec<f64> = (0..800 * 800).map(|_| rng.uniform()).collect();
    let h = interpolate_heights(
        &heights,
        800,
        800,
        (0.0, 0.0),
        (1.0, 1.0),
        &EndCondition::NotAKnot,
    )
    .unwrap();
    let grid = terrain(440, 420, 3);
    let r3 = interpolate_surface(&grid, &SurfaceInterpolationOptions::default())
        .unwrap()
        .surface;
    for s in [&h, &r3] {
        let d = s.dim();
        assert!(
            s.control_flat().len() * 8 >= 4 << 20,
            "the net must exceed the caches"
        );
        let ((u0, u1), (v0, v1)) = s.domain();
        let n = 60_000;
        // The grouped path takes batches of at least 32 points per net row.
        assert!(n >= 32 * s.net_size().0);
        let us: Vec<f64> = (0..n)
            .map(|_| (u0 + u1) / 2.0 + (u1 - u0) * 0.55 * rng.uniform())
            .collect();
        let vs: Vec<f64> = (0..n)
            .map(|_| (v0 + v1) / 2.0 + (v1 - v0) * 0.55 * rng.uniform())
            .collect();
        let mut all = vec![0.0; n * d];
        s.eval_many_par(&us, &vs, &mut all).unwrap();
        let mut small = vec![0.0; n * d];
        for ((u, v), o) in us
            .chunks(1000)
            .zip(vs.chunks(1000))
            .zip(small.chunks_mut(1000 * d))
        {
            s.eval_many_par(u, v, o).unwrap();
        }
        assert!(all == small, "dim {d}");
        // And the small batches are the surface (within rounding of the summation order;
        // past the domain's ends the cubic pieces are extrapolated, and rounding grows with
        // the cube of the distance in end spans, [`past_end`]).
        let (ku, kv) = s.knots();
        for k in (0..n).step_by(997) {
            let want = s.eval(us[k], vs[k]);
            let tol =
                1e-13 * (1.0 + past_end(us[k], ku)).powi(3) * (1.0 + past_end(vs[k], kv)).powi(3);
            for (g, w) in all[k * d..(k + 1) * d].iter().zip(&want) {
                assert!((g - w).abs() <= tol * (1.0 + w.abs()), "{g} vs {w}");
            }
        }
    }
}

/// Heights rows are swept side by side where they lie (blocks of 8, and single leftover
/// rows), points of several coordinates through transposed blocks: both give the same
/// control values, bit for bit.
#[test]
fn height_rows_solve_like_point_rows() {
    let (rows, cols) = (21usize, 37usize);
    let z: Vec<f64> = (0..rows * cols)
        .map(|k| ((k / cols) as f64 * 0.4).sin() * ((k % cols) as f64 * 0.3).cos())
        .collect();
    let pairs: Vec<f64> = z.iter().flat_map(|v| [*v, 1.0 - v]).collect();
    for end in [EndCondition::NotAKnot, EndCondition::Natural] {
        let h = interpolate_heights(&z, rows, cols, (0.0, 0.0), (1.0, 1.0), &end).unwrap();
        let options = SurfaceInterpolationOptions::default()
            .with_end(end.clone())
            .with_parametrization(Parametrization::Uniform);
        let p = interpolate_surface_flat(rows, cols, 2, &pairs, &options).unwrap();
        let from_pairs: Vec<f64> = p
            .surface
            .control_flat()
            .iter()
            .step_by(2)
            .copied()
            .collect();
        assert_eq!(h.control_flat(), &from_pairs[..], "{end:?}");
    }
}

/// How far t lies past the domain of cubic `knots`, in widths of the end span there.
fn past_end(t: f64, knots: &[f64]) -> f64 {
    let n = knots.len();
    let (a, b) = (knots[3], knots[n - 4]);
    if t < a {
        (a - t) / (knots[4] - a)
    } else if t > b {
        (t - b) / (b - knots[n - 5])
    } else {
        0.0
    }
}

/// Scattered batches on uneven knots (heights over uneven coordinates, chord-length
/// surfaces of 2-D and 3-D points), large enough for the span tables: every point, at the
/// knots, between them and past the ends, matches single-point evaluation within rounding
/// (a wrong span would miss by far more inside the domain).
#[test]
fn scattered_batches_on_uneven_knots_match_point_evaluation() {
    let mut rng = Rng(41);
    let mut coord = |n: usize| -> Vec<f64> {
        let mut x = vec![0.0];
        for k in 1..n {
            // Steps of 0.01 and of 0.5 to 3: clusters and long gaps.
            let step = if k % 7 < 3 {
                0.01
            } else {
                1.75 + 1.25 * rng.uniform()
            };
            x.push(x[k - 1] + step);
        }
        x
    };
    let (xs, ys) = (coord(57), coord(43));
    let z: Vec<f64> = (0..xs.len() * ys.len())
        .map(|k| (xs[k / ys.len()] * 0.3).sin() + (ys[k % ys.len()] * 0.2).cos())
        .collect();
    let heights =
        geomkit::bspline::interpolate_heights_at(&z, &xs, &ys, &EndCondition::NotAKnot).unwrap();
    let chord =
        SurfaceInterpolationOptions::default().with_parametrization(Parametrization::ChordLength);
    let r3 = interpolate_surface(&terrain(30, 26, 9), &chord)
        .unwrap()
        .surface;
    let r2: Vec<Vec<Vec<f64>>> = terrain(22, 31, 4)
        .into_iter()
        .map(|row| row.into_iter().map(|p| p[..2].to_vec()).collect())
        .collect();
    let r2 = interpolate_surface(&r2, &chord).unwrap().surface;
    for s in [&heights, &r2, &r3] {
        let d = s.dim();
        let ((u0, u1), (v0, v1)) = s.domain();
        let (ku, kv) = s.knots();
        let mut us: Vec<f64> = (0..4000)
            .map(|_| (u0 + u1) / 2.0 + (u1 - u0) * 0.55 * rng.uniform())
            .collect();
        let mut vs: Vec<f64> = (0..4000)
            .map(|_| (v0 + v1) / 2.0 + (v1 - v0) * 0.55 * rng.uniform())
            .collect();
        us.extend(ku.iter().copied().cycle().take(kv.len().max(ku.len())));
        vs.extend(kv.iter().copied().cycle().take(kv.len().max(ku.len())));
        let mut got = vec![0.0; us.len() * d];
        s.eval_many_par(&us, &vs, &mut got).unwrap();
        let scale = s.control_flat().iter().fold(0.0f64, |m, c| m.max(c.abs()));
        for ((u, v), g) in us.iter().zip(&vs).zip(got.chunks_exact(d)) {
            // Past the ends the end pieces are extrapolated: rounding grows with the cube
            // of the distance in end-span widths.
            let tol =
                1e-14 * scale * (1.0 + past_end(*u, ku)).powi(3) * (1.0 + past_end(*v, kv)).powi(3);
            for (a, b) in g.iter().zip(s.eval(*u, *v)) {
                assert!((a - b).abs() <= tol, "dim {d} at ({u}, {v}): {a} vs {b}");
            }
        }
    }
}
