//! Tiles for splines of any degree (issue 22) and progress reports (issue 23's hooks):
//! [`make_interp_spline_tiled`] and the streaming [`SplineTiler`] against the global solve
//! [`make_interp_spline`] (itself checked against SciPy in `reference_spline.rs`), for
//! k = 1..7, every kind of end-condition pair the tiles take, uniform and uneven x, 1-D and
//! 3-D values; the tiler's memory bound; its errors; and the progress hook of the builds.

use geomkit::bspline::{
    make_interp_spline, make_interp_spline_tiled, make_interp_spline_with_progress,
    make_interp_surface, make_interp_surface_with_progress, EndSpec, SplineEnds, SplineOptions,
    SplineTiler, TileOptions, MIN_SPLINE_HALO,
};
use geomkit::progress::Progress;
use geomkit::Error;
use std::ops::ControlFlow;
use std::sync::Mutex;

fn data(n: usize, dim: usize, uneven: bool) -> (Vec<f64>, Vec<f64>) {
    let mut x = Vec::with_capacity(n);
    let mut v = 0.0;
    for i in 0..n {
        x.push(v);
        v += if uneven {
            0.2 + 1.7 * ((i as f64 * 0.61).sin() * 0.5 + 0.5)
        } else {
            1.0
        };
    }
    let y = x
        .iter()
        .flat_map(|&t| (0..dim).map(move |d| (0.013 * t * (d + 1) as f64).sin() + 0.1 * d as f64))
        .collect();
    (x, y)
}

fn d(order: usize, value: f64) -> (usize, Vec<f64>) {
    (order, vec![value])
}

/// The end pairs the tiles take for degree k: not-a-knot; for odd k every split of the
/// k - 1 derivative conditions (orders 1.., values nonzero), natural/clamped and Bessel.
fn end_pairs(k: usize) -> Vec<SplineEnds> {
    let mut out = vec![SplineEnds::default()];
    if k % 2 == 1 && k > 1 {
        let m = k - 1;
        for nl in 0..=m {
            let left = (1..=nl).map(|o| d(o, 0.3 * o as f64)).collect();
            let right = (1..=m - nl).map(|o| d(o, -0.2)).collect();
            out.push(SplineEnds::Open {
                left: EndSpec::Derivatives(left),
                right: EndSpec::Derivatives(right),
            });
        }
        if k == 3 {
            out.push(SplineEnds::both(EndSpec::natural()));
            out.push(SplineEnds::Open {
                left: EndSpec::clamped(),
                right: EndSpec::natural(),
            });
            out.push(SplineEnds::both(EndSpec::Bessel));
        }
    }
    out
}

/// Whether the ends hold numbers of conditions that differ by at most one.
fn balanced(ends: &SplineEnds) -> bool {
    let count = |e: &EndSpec| match e {
        EndSpec::Derivatives(l) => l.len(),
        EndSpec::Bessel => 1,
        _ => 0,
    };
    match ends {
        SplineEnds::Open { left, right } => count(left).abs_diff(count(right)) <= 1,
        _ => true,
    }
}

fn rel_diff(a: &[f64], b: &[f64]) -> f64 {
    let scale = a.iter().fold(1e-300f64, |m, v| m.max(v.abs()));
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (p, q)| m.max((p - q).abs() / scale))
}

/// The tiles one by one, in order, as a streaming caller would (each from its own points).
fn streamed(
    x: &[f64],
    y: &[f64],
    dim: usize,
    opts: &SplineOptions,
    tiles: &TileOptions,
) -> Result<(Vec<f64>, Vec<f64>), Error> {
    let tiler = SplineTiler::new(x.len(), dim, opts, tiles)?;
    let (mut c, mut t) = (Vec::new(), Vec::new());
    for p in tiler.plan() {
        let r = p.read.clone();
        let tile = tiler.solve(&p, &x[r.clone()], &y[r.start * dim..r.end * dim])?;
        c.extend_from_slice(&tile.coefficients);
        t.extend_from_slice(&tile.knots);
    }
    assert_eq!(
        (c.len(), t.len()),
        (tiler.n_coefficients() * dim, tiler.n_knots())
    );
    Ok((c, t))
}

#[test]
fn tiles_equal_the_global_solve_for_every_degree() {
    let tiles = TileOptions::default().with_tile_size(150);
    let (mut solved, mut refused, mut not_streamed) = (0, 0, 0);
    for k in 1..=7 {
        for uneven in [false, true] {
            for dim in [1, 3] {
                let (x, y) = data(700, dim, uneven);
                for ends in end_pairs(k) {
                    let opts = SplineOptions::new(k).with_ends(ends.clone());
                    let what = format!("k={k} uneven={uneven} dim={dim} {ends:?}");
                    let tiled =
                        make_interp_spline_tiled(&x, &y, dim, &opts, &tiles, &Progress::none());
                    let global = match make_interp_spline(&x, &y, dim, &opts) {
                        Ok(g) => g,
                        // All conditions at one end of 700 points: too ill-conditioned for
                        // f64 (SciPy's answer has no digits either); the tiles refuse too.
                        Err(e) => {
                            assert!(!balanced(&ends), "{what}");
                            assert_eq!(tiled, Err(e), "{what}");
                            refused += 1;
                            continue;
                        }
                    };
                    let tiled = tiled.unwrap();
                    solved += 1;
                    assert_eq!(global.knots(), tiled.knots(), "{what}");
                    let e = rel_diff(global.control_flat(), tiled.control_flat());
                    assert!(e <= 1e-12, "{what}: {e:e}");
                    // Streaming gives the parallel tiles' bits.
                    let (c, t) = match streamed(&x, &y, dim, &opts, &tiles) {
                        Ok(ct) => ct,
                        // Conditions far from balanced between the ends amplify (the global
                        // solve refines them); a tile refuses them rather than lose digits.
                        Err(e) if !balanced(&ends) => {
                            assert!(e.to_string().contains("ill-conditioned"), "{what}: {e}");
                            not_streamed += 1;
                            continue;
                        }
                        Err(e) => panic!("{what}: {e}"),
                    };
                    assert_eq!(t, global.knots(), "{what}");
                    assert_eq!(c, tiled.control_flat(), "{what}");
                }
            }
        }
    }
    assert!(
        solved >= 60,
        "{solved} solved, {refused} refused, {not_streamed} not streamed"
    );
}

/// Every tile size from 1 to past N (tiles owning a few coefficients, tiles whose halo
/// reaches just short of an end, one tile), streamed and in parallel, for every degree and
/// the balanced end pairs: the global solve's knots and coefficients. (Windows stopping a
/// few rows short of an end once read data before the first point — a panic — or ended
/// on the end's knots without its conditions — a singular system.)
#[test]
fn every_tile_size_equals_the_global_solve() {
    let (x, y) = data(260, 2, true);
    for k in 1..=7 {
        for ends in end_pairs(k).into_iter().filter(balanced) {
            let opts = SplineOptions::new(k).with_ends(ends.clone());
            let global = make_interp_spline(&x, &y, 2, &opts).unwrap();
            for size in 1..=270 {
                let what = format!("k={k} tile={size} {ends:?}");
                let tiles = TileOptions::default().with_tile_size(size);
                let (c, t) = streamed(&x, &y, 2, &opts, &tiles).unwrap_or_else(|e| {
                    panic!("{what}: {e}");
                });
                assert_eq!(t, global.knots(), "{what}");
                let e = rel_diff(global.control_flat(), &c);
                assert!(e <= 1e-12, "{what}: {e:e}");
                // In parallel: the same tiles, or the whole solve where a seam's rows do not
                // hold to rounding.
                let tiled =
                    make_interp_spline_tiled(&x, &y, 2, &opts, &tiles, &Progress::none()).unwrap();
                assert_eq!(tiled.knots(), global.knots(), "{what}");
                let e = rel_diff(global.control_flat(), tiled.control_flat());
                assert!(e <= 1e-12, "{what}: {e:e}");
            }
        }
    }
}

#[test]
fn even_degrees_with_derivative_ends_are_solved_whole() {
    // Knots at the data: no decay, the tiler refuses; the tiled call gives the global curve.
    let (x, y) = data(600, 2, true);
    for (k, ends) in [
        (
            2,
            SplineEnds::Open {
                left: EndSpec::clamped(),
                right: EndSpec::NotAKnot,
            },
        ),
        (
            4,
            SplineEnds::Open {
                left: EndSpec::Derivatives(vec![d(1, 0.5), d(2, 0.0)]),
                right: EndSpec::natural(),
            },
        ),
    ] {
        let opts = SplineOptions::new(k).with_ends(ends);
        let tiles = TileOptions::default().with_tile_size(100);
        let e = SplineTiler::new(x.len(), 2, &opts, &tiles).unwrap_err();
        assert!(e.to_string().contains("does not decay"), "{e}");
        let global = make_interp_spline(&x, &y, 2, &opts).unwrap();
        let tiled = make_interp_spline_tiled(&x, &y, 2, &opts, &tiles, &Progress::none()).unwrap();
        assert_eq!(global, tiled);
    }
}

#[test]
fn a_tile_reads_a_bounded_stretch() {
    // The memory of a stream: every tile reads its owned points, the halos and a few more,
    // whatever N.
    for k in [1, 2, 5, 7] {
        for n in [1_000, 100_000, 10_000_000] {
            let tiles = TileOptions::default().with_tile_size(4096);
            let tiler = SplineTiler::new(n, 3, &SplineOptions::new(k), &tiles).unwrap();
            let plan = tiler.plan();
            let bound = 4096 + 2 * MIN_SPLINE_HALO + 6 * k + 8;
            assert!(plan.iter().all(|p| p.read.len() <= bound), "k={k} n={n}");
            // The tiles cover every coefficient and knot once, in order.
            let (mut c, mut t) = (0, 0);
            for p in &plan {
                assert_eq!((p.write.start, p.knots.start), (c, t));
                (c, t) = (p.write.end, p.knots.end);
            }
            assert_eq!((c, t), (tiler.n_coefficients(), tiler.n_knots()));
        }
    }
}

#[test]
fn bad_tiles_are_refused() {
    let tiles = TileOptions::default().with_tile_size(100);
    let err = |opts: SplineOptions, n: usize| SplineTiler::new(n, 1, &opts, &tiles).unwrap_err();
    assert!(matches!(
        err(SplineOptions::new(3).with_ends(SplineEnds::Periodic), 500),
        Error::InvalidOption { .. }
    ));
    assert!(matches!(
        err(SplineOptions::new(3).with_knots(vec![0.0; 20]), 500),
        Error::InvalidOption { .. }
    ));
    assert!(matches!(
        err(SplineOptions::new(0), 500),
        Error::InvalidOption { .. }
    ));
    assert!(matches!(
        err(SplineOptions::new(8), 500),
        Error::InvalidOption { .. }
    ));
    assert!(matches!(
        err(SplineOptions::new(3), 1),
        Error::TooFewPoints { .. }
    ));
    // Too many conditions for the degree.
    let e = err(
        SplineOptions::new(3).with_ends(SplineEnds::both(EndSpec::Derivatives(vec![
            d(1, 0.0),
            d(2, 0.0),
        ]))),
        500,
    );
    assert!(e.to_string().contains("does not match"), "{e}");
    // A tile's buffers of the wrong length, and decreasing x inside a tile.
    let tiler = SplineTiler::new(500, 1, &SplineOptions::new(3), &tiles).unwrap();
    let p = &tiler.plan()[1];
    let (x, y) = data(500, 1, false);
    assert!(matches!(
        tiler.solve(p, &x[..3], &y[..3]),
        Err(Error::BufferSize { .. })
    ));
    let mut bad = x[p.read.clone()].to_vec();
    bad.swap(5, 6);
    let e = tiler.solve(p, &bad, &y[p.read.clone()]).unwrap_err();
    assert!(e.to_string().contains("strictly increasing"), "{e}");
    let mut nan = y[p.read.clone()].to_vec();
    nan[7] = f64::NAN;
    assert!(matches!(
        tiler.solve(p, &x[p.read.clone()], &nan),
        Err(Error::NonFinite { .. })
    ));
}

/// Records every report.
fn recorder(seen: &Mutex<Vec<(u64, u64)>>) -> impl Fn(u64, u64) -> ControlFlow<()> + Sync + '_ {
    move |done, total| {
        seen.lock().unwrap().push((done, total));
        ControlFlow::Continue(())
    }
}

fn take(seen: &Mutex<Vec<(u64, u64)>>) -> Vec<(u64, u64)> {
    std::mem::take(&mut *seen.lock().unwrap())
}

fn check_reports(seen: Vec<(u64, u64)>, what: &str) {
    assert!(!seen.is_empty(), "{what}: no report");
    assert!(
        seen.windows(2)
            .all(|w| w[0].0 <= w[1].0 && w[0].1 <= w[1].1),
        "{what}: {seen:?}"
    );
    assert!(seen.iter().all(|&(d, t)| d <= t), "{what}");
    let (d, t) = *seen.last().unwrap();
    assert!(d == t && t > 0, "{what}: ends at {d}/{t}");
}

#[test]
fn progress_reports_are_monotone_and_the_results_the_same_bits() {
    // Large enough for the parallel windows (more than 65 536 rows).
    let (x, y) = data(200_000, 2, true);
    for k in [2, 3, 5] {
        let opts = SplineOptions::new(k);
        let seen = Mutex::new(Vec::new());
        let report = recorder(&seen);
        let with =
            make_interp_spline_with_progress(&x, &y, 2, &opts, &Progress::new(&report)).unwrap();
        let without = make_interp_spline(&x, &y, 2, &opts).unwrap();
        assert_eq!(with, without, "k={k}");
        let seen = take(&seen);
        // The default cubic of this length is one unit (the extended form's solve and the
        // change of basis, `scipy_cubic.rs`); the band solves report once per two windows
        // of 16 384 rows (solved together).
        let least = if k == 3 { 2 } else { 6 };
        assert!(
            seen.len() >= least,
            "k={k}: one report per two windows, {} reports",
            seen.len()
        );
        check_reports(seen, "make_interp_spline");

        let seen = Mutex::new(Vec::new());
        let report = recorder(&seen);
        let tiles = TileOptions::default().with_tile_size(20_000);
        let tiled =
            make_interp_spline_tiled(&x, &y, 2, &opts, &tiles, &Progress::new(&report)).unwrap();
        assert!(rel_diff(tiled.control_flat(), without.control_flat()) <= 1e-12);
        check_reports(take(&seen), "tiled");
    }
    // A surface: rows along x, then the rows of the net along y.
    let (gx, gy) = (
        (0..300).map(|i| i as f64).collect::<Vec<_>>(),
        (0..400).map(|i| i as f64 * 0.5).collect::<Vec<_>>(),
    );
    let z: Vec<f64> = gx
        .iter()
        .flat_map(|a| gy.iter().map(move |b| (a * 0.02).sin() * (b * 0.03).cos()))
        .collect();
    let seen = Mutex::new(Vec::new());
    let report = recorder(&seen);
    let with = make_interp_surface_with_progress(
        &gx,
        &gy,
        &z,
        (300, 400),
        (3, 5),
        &Progress::new(&report),
    )
    .unwrap();
    assert_eq!(
        with,
        make_interp_surface(&gx, &gy, &z, (300, 400), (3, 5)).unwrap()
    );
    check_reports(take(&seen), "surface");
}

#[test]
fn cancellation_returns_an_error_not_a_curve() {
    let (x, y) = data(200_000, 1, false);
    let calls = Mutex::new(0);
    let stop_third = |_: u64, _: u64| {
        let mut c = calls.lock().unwrap();
        *c += 1;
        if *c >= 3 {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    };
    let p = Progress::new(&stop_third);
    assert_eq!(
        make_interp_spline_with_progress(&x, &y, 1, &SplineOptions::new(5), &p),
        Err(Error::Cancelled)
    );
    assert!(p.is_cancelled());
    let stop = |_: u64, _: u64| ControlFlow::Break(());
    let tiles = TileOptions::default().with_tile_size(10_000);
    assert_eq!(
        make_interp_spline_tiled(
            &x,
            &y,
            1,
            &SplineOptions::new(3),
            &tiles,
            &Progress::new(&stop)
        ),
        Err(Error::Cancelled)
    );
    let z = vec![1.0; 300 * 300];
    let g: Vec<f64> = (0..300).map(|i| i as f64).collect();
    assert_eq!(
        make_interp_surface_with_progress(&g, &g, &z, (300, 300), (3, 3), &Progress::new(&stop)),
        Err(Error::Cancelled)
    );
}
