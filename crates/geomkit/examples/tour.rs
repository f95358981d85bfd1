//! The README's library tour (README.md quotes this file between the markers; the test
//! `tests/readme_tour.rs` runs it and checks that the README's copy is the same text).

use geomkit::bezier::{ApproxOptions, BezierCurve, ReductionNorm};
use geomkit::bspline::{interpolate_curve, EndCondition, InterpolationOptions, Parametrization};
use geomkit::compose::bodies;
use geomkit::expr::Format;
use geomkit::geom::Curve;
use geomkit::mesh::{tessellate_surface, SurfaceOptions};
use geomkit::pointcalc::{
    optimize, Factor, Goal, Hypersurface, Nodes, OptimizeOptions, PointOptions,
};

/// Runs the tour; every step checks what it claims.
pub fn main() -> geomkit::Result<()> {
    // README-TOUR-START
    // 1. Bézier order change: Example 2 of the paper, a quintic of real degree 3.
    let c = BezierCurve::new(vec![
        vec![10., 0.],
        vec![22., 6.],
        vec![19., 12.],
        vec![11., 15.],
        vec![8., 12.],
        vec![20., 0.],
    ])?;
    let report = c.degree_report(None)?; // degree 5, real degree 3, defect 2
    let cubic = c.reduce_degree(3, None)?; // exact: (10,0), (30,10), (0,20), (20,0)
    let high = cubic.elevate_degree(40)?; // one step, within eps of exact
    let approx = c.reduce_degree_approx(
        2,
        &ApproxOptions::default()
            .with_continuity(Some(0), Some(0))
            .with_norm(ReductionNorm::Chebyshev),
    )?;
    println!(
        "real degree {}, L2 error of the quadratic {:.3}",
        report.real_degree, approx.l2_error
    );

    // 2. A closed cubic B-spline exactly through measured points (an isoline).
    let isoline: Vec<Vec<f64>> = (0..12)
        .map(|k| {
            let a = k as f64 * std::f64::consts::TAU / 12.0;
            vec![
                (2.0 + (3.0 * a).cos() * 0.3) * a.cos(),
                (1.0 + 0.2 * a.sin()) * a.sin(),
            ]
        })
        .collect();
    let options = InterpolationOptions::default()
        .with_end(EndCondition::Periodic)
        .with_parametrization(Parametrization::Centripetal);
    let fit = interpolate_curve(&isoline, &options)?;
    let through = fit.curve().eval(fit.parameters()[5]); // == isoline[5] within 1e-15

    // 3. The paper's cube as one formula, printed for Mathematica, and meshed watertight.
    let cube = bodies::cube()?;
    let formula = cube.formula()?.print(Format::Mathematica)?;
    let mesh = tessellate_surface(&cube, &SurfaceOptions::uniform(9, 7))?;
    println!("{formula}volume {}", mesh.volume()); // 8

    // 4. A 2-factor model through 3×4 experimental points: shares and the certified maximum.
    let factors = vec![
        Factor::new("temperature", Nodes::new(vec![60.0, 75.0, 90.0])?),
        Factor::new("time", Nodes::new(vec![1.0, 2.0, 3.0, 4.0])?),
    ];
    let response = |x: &[f64], y: &mut [f64]| y[0] = 80.0 - (x[0] - 78.0).powi(2) / 20.0 + x[1];
    let model = Hypersurface::from_fn(factors, 1, response, &PointOptions::default())?;
    let shares = model.shares(&[70.0, 2.5])?; // one per source point, summing to 1
    let best = optimize(&model, Goal::Max, &OptimizeOptions::default())?;
    println!(
        "max {} at {:?} (certified bound {})",
        best.value, best.at, best.bound
    );
    // README-TOUR-END

    assert_eq!(
        (report.degree, report.real_degree, report.defect),
        (5, 3, 2)
    );
    assert_eq!(
        cubic.points(),
        vec![vec![10., 0.], vec![30., 10.], vec![0., 20.], vec![20., 0.]]
    );
    for t in [0.0, 0.3, 0.7, 1.0] {
        let (a, b) = (high.eval(t), c.eval(t));
        assert!((a[0] - b[0]).abs() < 1e-13 && (a[1] - b[1]).abs() < 1e-13);
    }
    assert!(approx.l2_error > 0.0 && approx.linf.upper_bound >= approx.l2_error);
    assert!(
        (through[0] - isoline[5][0]).abs() < 1e-14 && (through[1] - isoline[5][1]).abs() < 1e-14
    );
    assert!(formula.contains("Abs["));
    assert!(mesh.is_watertight() && (mesh.volume() - 8.0).abs() < 1e-12);
    assert!((shares.iter().sum::<f64>() - 1.0).abs() < 1e-14 && shares.len() == 12);
    // The response is quadratic in temperature and linear in time: reproduced exactly, so
    // the maximum is at temperature 78, time 4: 84.
    assert!((best.value - 84.0).abs() < 1e-9 && best.bound - best.value < 1e-6);
    Ok(())
}
