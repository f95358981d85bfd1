//! The progress hook ([`geomkit::progress`]) of the paper's cubic tiles, the surface builds
//! and the mesher: reports whose done counts never decrease and end at the total, results
//! bit for bit those without a hook, and cancellation as an error. (The splines of any
//! degree: `spline_tiles.rs`.)

use geomkit::bspline::{
    interpolate_curve_tiled, interpolate_curve_tiled_with_progress, interpolate_surface_flat,
    interpolate_surface_flat_with_progress, EndCondition, InterpolationOptions,
    SurfaceInterpolationOptions, TileOptions,
};
use geomkit::compose::bodies;
use geomkit::mesh::{tessellate_surface_report, tessellate_surface_with_progress, SurfaceOptions};
use geomkit::progress::Progress;
use geomkit::Error;
use std::ops::ControlFlow;
use std::sync::Mutex;

type Seen = Mutex<Vec<(u64, u64)>>;

fn recorder(seen: &Seen) -> impl Fn(u64, u64) -> ControlFlow<()> + Sync + '_ {
    move |done, total| {
        seen.lock().unwrap().push((done, total));
        ControlFlow::Continue(())
    }
}

fn check(seen: &Seen, what: &str) -> usize {
    let seen = std::mem::take(&mut *seen.lock().unwrap());
    assert!(!seen.is_empty(), "{what}: no report");
    assert!(
        seen.windows(2)
            .all(|w| w[0].0 <= w[1].0 && w[0].1 <= w[1].1),
        "{what}: {seen:?}"
    );
    assert!(seen.iter().all(|&(d, t)| d <= t), "{what}");
    let (d, t) = *seen.last().unwrap();
    assert!(d == t && t > 0, "{what}: ends at {d}/{t}");
    seen.len()
}

fn stop(_: u64, _: u64) -> ControlFlow<()> {
    ControlFlow::Break(())
}

#[test]
fn cubic_tiles_report_per_tile() {
    let pts: Vec<f64> = (0..50_000)
        .flat_map(|i| {
            let t = i as f64 * 0.01;
            [t.cos() * (1.0 + 0.1 * t), t.sin(), 0.01 * t]
        })
        .collect();
    let opts = InterpolationOptions::default();
    let tiles = TileOptions::default().with_tile_size(1000);
    let seen = Seen::default();
    let report = recorder(&seen);
    let with =
        interpolate_curve_tiled_with_progress(3, &pts, &opts, &tiles, &Progress::new(&report))
            .unwrap();
    let without = interpolate_curve_tiled(3, &pts, &opts, &tiles).unwrap();
    assert_eq!(with.curve(), without.curve());
    assert!(check(&seen, "cubic tiles") >= 50);
    let e = interpolate_curve_tiled_with_progress(3, &pts, &opts, &tiles, &Progress::new(&stop));
    assert_eq!(e.err(), Some(Error::Cancelled));
}

/// A rows × cols grid of 3-D points on z = sin(3u) cos(v), its columns `uneven` apart
/// by turns (0: evenly).
fn sheet(rows: usize, cols: usize, uneven: f64) -> Vec<f64> {
    (0..rows)
        .flat_map(|i| {
            (0..cols).flat_map(move |j| {
                let (u, v) = (i as f64 * 0.01, j as f64 * 0.02 + (j % 5) as f64 * uneven);
                [u, v, (u * 3.0).sin() * v.cos()]
            })
        })
        .collect()
}

#[test]
fn surface_build_reports_per_block_of_rows() {
    let (rows, cols) = (400, 300);
    let grid = sheet(rows, cols, 0.0);
    for end in [EndCondition::Natural, EndCondition::Periodic] {
        let opts = SurfaceInterpolationOptions::default().with_end(end.clone());
        let seen = Seen::default();
        let report = recorder(&seen);
        let with = interpolate_surface_flat_with_progress(
            rows,
            cols,
            3,
            &grid,
            &opts,
            &Progress::new(&report),
        )
        .unwrap();
        let without = interpolate_surface_flat(rows, cols, 3, &grid, &opts).unwrap();
        assert_eq!(with.surface, without.surface, "{end:?}");
        check(&seen, "surface");
        let e = interpolate_surface_flat_with_progress(
            rows,
            cols,
            3,
            &grid,
            &opts,
            &Progress::new(&stop),
        );
        assert_eq!(e.err(), Some(Error::Cancelled));
    }
}

#[test]
fn mesher_reports_rounds_and_the_mesh_is_the_same() {
    let cone = bodies::cone(1.0, 2.0).unwrap();
    for options in [SurfaceOptions::default(), SurfaceOptions::uniform(40, 30)] {
        let seen = Seen::default();
        let report = recorder(&seen);
        let (with, r1) =
            tessellate_surface_with_progress(&cone, &options, &Progress::new(&report)).unwrap();
        let (without, r2) = tessellate_surface_report(&cone, &options).unwrap();
        assert_eq!(with.positions(), without.positions());
        assert_eq!(with.triangles(), without.triangles());
        assert_eq!(r1.deviation, r2.deviation);
        check(&seen, "mesh");
        let e = tessellate_surface_with_progress(&cone, &options, &Progress::new(&stop));
        assert_eq!(e.err(), Some(Error::Cancelled));
    }
}

// --- the calls hooked for issue 23's remaining long jobs --------------------------------

/// Runs `job` with a recording hook, with none, cancelled at the first report and at the
/// middle report: monotone reports ending at the total, the same result as without a hook,
/// and `Cancelled` (never a result) both times. Returns the number of reports.
fn hooked<T: PartialEq + std::fmt::Debug>(
    what: &str,
    job: impl Fn(&Progress) -> geomkit::Result<T>,
) -> usize {
    let seen = Seen::default();
    let report = recorder(&seen);
    let with = job(&Progress::new(&report)).unwrap();
    let without = job(&Progress::none()).unwrap();
    assert!(with == without, "{what}: other bits with the hook");
    let reports = check(&seen, what);
    assert_eq!(
        job(&Progress::new(&stop)).err(),
        Some(Error::Cancelled),
        "{what}"
    );
    // Cancelled in the middle of the job (inside the solve's chunks, tiles or windows).
    let calls = std::sync::atomic::AtomicUsize::new(0);
    let middle = |_: u64, _: u64| {
        if calls.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1 >= reports.div_ceil(2) {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    };
    assert_eq!(
        job(&Progress::new(&middle)).err(),
        Some(Error::Cancelled),
        "{what}"
    );
    reports
}

/// A helix of n points with uneven steps (chord lengths differ).
fn helix(n: usize) -> Vec<f64> {
    (0..n)
        .flat_map(|i| {
            let t = i as f64 * 0.01 + (i % 7) as f64 * 1e-3;
            [t.cos() * (1.0 + 0.1 * t), t.sin(), 0.01 * t]
        })
        .collect()
}

/// The curve passes through its points at its parameters (an interpolant's defining
/// property, independent of the solve's route).
fn assert_interpolates(fit: &geomkit::bspline::CurveInterpolation, pts: &[f64], what: &str) {
    use geomkit::geom::Curve;
    let scale = pts.iter().fold(1.0f64, |m, v| m.max(v.abs()));
    for i in (0..pts.len() / 3).step_by(997) {
        let at = fit.curve().eval(fit.parameters()[i]);
        for c in 0..3 {
            let err = (at[c] - pts[3 * i + c]).abs();
            assert!(err <= 1e-11 * scale, "{what}: point {i}: {err:e}");
        }
    }
}

#[test]
fn extended_curve_reports_per_chunk_for_every_end_and_parametrization() {
    use geomkit::bspline::{interpolate_curve_flat, interpolate_curve_flat_with_progress};
    use geomkit::bspline::{EndCondition as E, Parametrization as P};
    // 40 000 points of 3-D: about five chunks of the parallel solves (8 192 rows each).
    let pts = helix(40_000);
    let cases = [
        (E::NotAKnot, P::Uniform),
        (E::NotAKnot, P::ChordLength),
        (E::Natural, P::Centripetal),
        (E::Bessel, P::ChordLength),
        (E::OuterPoints { offset: 0.5 }, P::Uniform),
        (E::Periodic, P::ChordLength),
        (E::Repeat, P::Uniform),
    ];
    for (end, param) in cases {
        let opts = InterpolationOptions::default()
            .with_end(end.clone())
            .with_parametrization(param);
        let what = format!("{end:?} {param:?}");
        let reports = hooked(&what, |p| {
            interpolate_curve_flat_with_progress(3, &pts, &opts, p)
        });
        // Parameters, then the solve: per chunk when it runs in parallel chunks.
        let parallel = rayon::current_num_threads() > 1 && !matches!(end, E::Periodic | E::Repeat);
        assert!(
            reports >= if parallel { 5 } else { 3 },
            "{what}: {reports} reports"
        );
        let fit = interpolate_curve_flat(3, &pts, &opts).unwrap();
        if end != E::Repeat {
            assert_interpolates(&fit, &pts, &what);
        }
    }
}

#[test]
fn curve_at_given_parameters_reports_and_cancels() {
    use geomkit::bspline::interpolate_curve_at_with_progress;
    let pts = helix(30_000);
    let x: Vec<f64> = (0..30_000).map(|i| (i as f64).powf(1.1)).collect();
    for end in [EndCondition::NotAKnot, EndCondition::Natural] {
        let what = format!("at {end:?}");
        hooked(&what, |p| {
            interpolate_curve_at_with_progress(3, &pts, &x, &end, p)
        });
        let fit = interpolate_curve_at_with_progress(3, &pts, &x, &end, &Progress::none());
        assert_interpolates(&fit.unwrap(), &pts, &what);
    }
}

#[test]
fn heights_report_per_block_of_rows() {
    use geomkit::bspline::{
        interpolate_heights_at_with_progress, interpolate_heights_with_progress,
    };
    let (rows, cols) = (300, 200);
    let f = |x: f64, y: f64| (x * 0.05).sin() * (y * 0.03).cos();
    let z: Vec<f64> = (0..rows * cols)
        .map(|k| f((k / cols) as f64, (k % cols) as f64))
        .collect();
    for end in [EndCondition::NotAKnot, EndCondition::Natural] {
        let what = format!("heights {end:?}");
        let origin_spacing = ((1.0, -2.0), (0.5, 0.25));
        let (o, h) = origin_spacing;
        hooked(&what, |p| {
            interpolate_heights_with_progress(&z, rows, cols, o, h, &end, p)
        });
        let xs: Vec<f64> = (0..rows).map(|i| (i as f64).powf(1.2)).collect();
        let ys: Vec<f64> = (0..cols)
            .map(|j| j as f64 * 0.5 + (j % 3) as f64 * 0.1)
            .collect();
        hooked(&what, |p| {
            interpolate_heights_at_with_progress(&z, &xs, &ys, &end, p)
        });
        // Through the heights at the grid (the definition, not the solve).
        let s =
            interpolate_heights_at_with_progress(&z, &xs, &ys, &end, &Progress::none()).unwrap();
        for (i, j) in [(0, 0), (17, 150), (299, 199), (150, 3)] {
            let at = s.eval(xs[i], ys[j])[0];
            assert!((at - z[i * cols + j]).abs() < 1e-12, "{what}: ({i}, {j})");
        }
    }
}

#[test]
fn tiled_surface_reports_as_its_blocks_solve() {
    use geomkit::bspline::{interpolate_surface_tiled_with_progress, TileOptions};
    let (rows, cols) = (260, 230);
    let grid = sheet(rows, cols, 1e-3);
    let opts = SurfaceInterpolationOptions::default();
    let tiles = TileOptions::default().with_tile_size(100).with_halo(32);
    let reports = hooked("tiled surface", |p| {
        interpolate_surface_tiled_with_progress(rows, cols, 3, &grid, &opts, &tiles, p)
            .map(|s| s.surface)
    });
    // Nine blocks, each a few blocks of rows and its second direction.
    assert!(reports >= 18, "{reports}");
    // Equal to the global solve within rounding (the tiles' guarantee), hook or not.
    let tiled = interpolate_surface_tiled_with_progress(
        rows,
        cols,
        3,
        &grid,
        &opts,
        &tiles,
        &Progress::none(),
    )
    .unwrap();
    let global = interpolate_surface_flat(rows, cols, 3, &grid, &opts).unwrap();
    let err = tiled
        .surface
        .control_flat()
        .iter()
        .zip(global.surface.control_flat())
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(err < 1e-12, "{err:e}");
}

#[test]
fn curve_mesh_reports_windows_and_long_refinements() {
    use geomkit::bezier::BezierCurve;
    use geomkit::bspline::interpolate_curve_flat;
    use geomkit::mesh::{tessellate_curve_with_progress, CurveOptions};
    // A B-spline of 3 000 spans: its breaks make the windows, reported in batches.
    let pts = helix(3_000);
    let fit = interpolate_curve_flat(3, &pts, &InterpolationOptions::default()).unwrap();
    let options = CurveOptions::default().with_tolerance(1e-6);
    let reports = hooked("spline mesh", |p| {
        tessellate_curve_with_progress(fit.curve(), &options, p)
    });
    assert!((100..=1100).contains(&reports), "{reports}");
    // One window refined into ~40 000 points: reports during the bisection too.
    let wave: Vec<Vec<f64>> = (0..12)
        .map(|i| vec![i as f64, if i % 2 == 0 { 1.0 } else { -1.0 }])
        .collect();
    let c = BezierCurve::new(wave).unwrap();
    let mut options = CurveOptions::default().with_tolerance(1e-9);
    options.min_segments = 1;
    let reports = hooked("bezier mesh", |p| {
        tessellate_curve_with_progress(&c, &options, p)
    });
    assert!(reports >= 3, "{reports}");
}

#[test]
fn bezier_degree_changes_report_as_the_new_points_are_computed() {
    use geomkit::bezier::{BezierCurve, BezierSurface, RationalBezierCurve, RationalBezierSurface};
    // A curve of degree 599 in 3-D elevated to 1500: about ten reports of 2^18 multiply-adds.
    let pts: Vec<Vec<f64>> = (0..600)
        .map(|i| {
            let t = i as f64 * 0.05;
            vec![t, t.sin(), (i % 11) as f64]
        })
        .collect();
    let c = BezierCurve::new(pts.clone()).unwrap();
    let reports = hooked("curve elevation", |p| {
        c.change_degree_with_progress(1500, None, p)
    });
    assert!(reports >= 8, "{reports}");
    let plain = c.elevate_degree(1500).unwrap();
    let with = c
        .change_degree_with_progress(1500, None, &Progress::none())
        .unwrap();
    assert_eq!(plain, with);
    // The elevated curve is the same curve (an independent check: de Casteljau on both).
    use geomkit::geom::Curve;
    for t in [0.0, 0.123, 0.5, 0.987, 1.0] {
        let (a, b) = (c.eval(t), with.eval(t));
        assert!(
            a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-9),
            "t = {t}"
        );
    }
    // A reduction reports at its end; back to the same control points (the exact
    // reduction of an elevated curve).
    let small = BezierCurve::new(pts[..20].to_vec()).unwrap();
    let up = small.elevate_degree(60).unwrap();
    let back = up
        .change_degree_with_progress(19, None, &Progress::none())
        .unwrap();
    let err = back
        .points_flat()
        .iter()
        .zip(small.points_flat())
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(err < 1e-9, "{err:e}");
    hooked("curve reduction", |p| {
        up.change_degree_with_progress(19, None, p)
    });
    let weights: Vec<f64> = (0..600).map(|i| 1.0 + 0.5 * ((i % 3) as f64)).collect();
    let r = RationalBezierCurve::new(pts, weights).unwrap();
    hooked("rational curve", |p| {
        r.change_degree_with_progress(1200, None, p)
    });
    assert_eq!(
        r.change_degree_with_progress(600, None, &Progress::none())
            .unwrap(),
        r.elevate_degree(600).unwrap()
    );
    // A 60 × 50 net of 3-D points elevated to degrees (120, 90): rows, then columns.
    let net: Vec<Vec<Vec<f64>>> = (0..60)
        .map(|i| {
            (0..50)
                .map(|j| vec![i as f64, j as f64, ((i * j) % 13) as f64])
                .collect()
        })
        .collect();
    let s = BezierSurface::new(net.clone()).unwrap();
    let reports = hooked("surface elevation", |p| {
        s.change_degree_with_progress(120, 90, None, p)
    });
    assert!(reports >= 6, "{reports}");
    assert_eq!(
        s.change_degree_with_progress(120, 90, None, &Progress::none())
            .unwrap(),
        s.change_degree(120, 90, None).unwrap()
    );
    let w: Vec<Vec<f64>> = (0..60)
        .map(|i| (0..50).map(|j| 1.0 + ((i + j) % 4) as f64 * 0.25).collect())
        .collect();
    let rs = RationalBezierSurface::new(net, w).unwrap();
    hooked("rational surface", |p| {
        rs.change_degree_with_progress(80, 70, None, p)
    });
}
