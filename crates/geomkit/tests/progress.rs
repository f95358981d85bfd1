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

#[test]
fn surface_build_reports_per_block_of_rows() {
    let (rows, cols) = (400, 300);
    let grid: Vec<f64> = (0..rows)
        .flat_map(|i| {
            (0..cols).flat_map(move |j| {
                let (u, v) = (i as f64 * 0.01, j as f64 * 0.02);
                [u, v, (u * 3.0).sin() * v.cos()]
            })
        })
        .collect();
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
