//! Bodies as single formulas (spec/composite-surfaces.md §2): the paper's cube exactly, and
//! the other bodies' formulas equal to their structural evaluators.

use geomkit::compose::{bodies, RuledSurface};
use geomkit::expr::{parse, Format};
use geomkit::Error;

const PAPER_CUBE: [&str; 3] = [
    "1/2*(1 - abs(u) + abs(u-1) + abs(u-2) - abs(u-3))*(abs(v) - abs(v-1) - abs(v-2) + abs(v-3))",
    "1/2*(1 - abs(u-1) + abs(u-2) + abs(u-3) - abs(u-4))*(abs(v) - abs(v-1) - abs(v-2) + abs(v-3))",
    "-abs(v-1) + abs(v-2)",
];

fn grid(s: &RuledSurface, k: usize) -> (Vec<f64>, Vec<f64>) {
    let ((u0, u1), (v0, v1)) = s.domain();
    let mut us = Vec::new();
    let mut vs = Vec::new();
    for a in 0..k {
        for b in 0..k {
            us.push(u0 + (u1 - u0) * a as f64 / (k - 1) as f64);
            vs.push(v0 + (v1 - v0) * b as f64 / (k - 1) as f64);
        }
    }
    (us, vs)
}

#[test]
fn cube_formula_is_the_papers() {
    let f = bodies::cube().unwrap().formula().unwrap();
    let mut g = f.graph.clone();
    for (k, text) in PAPER_CUBE.iter().enumerate() {
        let paper = parse(&mut g, text).unwrap();
        assert_eq!(
            paper,
            f.roots[k],
            "coordinate {k}: {}",
            g.print(f.roots[k], Format::Maple).unwrap()
        );
    }
    assert_eq!(
        f.print(Format::Maple).unwrap(),
        format!(
            "x := (u, v) -> {};\ny := (u, v) -> {};\nz := (u, v) -> {};\n",
            g.print(f.roots[0], Format::Maple).unwrap(),
            g.print(f.roots[1], Format::Maple).unwrap(),
            g.print(f.roots[2], Format::Maple).unwrap()
        )
    );
}

#[test]
fn cube_points_lie_on_the_cube_and_reach_corners_and_poles() {
    let cube = bodies::cube().unwrap();
    let f = cube.formula().unwrap();
    let (us, vs) = grid(&cube, 97);
    let mut out = vec![0.0; us.len() * 3];
    f.eval_batch(&[&us, &vs], &mut out).unwrap();
    let mut corners = 0;
    let mut poles = 0;
    for (k, p) in out.chunks_exact(3).enumerate() {
        let m = p.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        assert!((m - 1.0).abs() <= 1e-15, "{p:?} at ({}, {})", us[k], vs[k]);
        if p.iter().all(|x| (x.abs() - 1.0).abs() <= 1e-15) {
            corners += 1;
        }
        if p[0] == 0.0 && p[1] == 0.0 {
            poles += 1;
        }
        let q = cube.eval(us[k], vs[k]);
        for c in 0..3 {
            assert!((q[c] - p[c]).abs() <= 1e-15);
        }
    }
    // Every corner is reached (u = 0..4 on the two squares).
    let mut seen = std::collections::BTreeSet::new();
    for p in out.chunks_exact(3) {
        if p.iter().all(|x| (x.abs() - 1.0).abs() <= 1e-15) {
            seen.insert([p[0] > 0.0, p[1] > 0.0, p[2] > 0.0]);
        }
    }
    assert_eq!(seen.len(), 8, "{corners} corner hits");
    assert!(poles >= 2);
    let g = &f.graph;
    assert_eq!(g.eval(f.roots[2], &[("u", 1.3), ("v", 0.0)]).unwrap(), 1.0);
    assert_eq!(g.eval(f.roots[2], &[("u", 1.3), ("v", 3.0)]).unwrap(), -1.0);
}

#[test]
fn every_body_formula_equals_its_structural_evaluator() {
    let hexagon = bodies::regular_polygon(6, 1.5).unwrap();
    let cases: Vec<(&str, RuledSurface)> = vec![
        ("box", bodies::rectangular_box(3.0, 2.0, 0.5).unwrap()),
        ("pyramid", bodies::square_pyramid(2.0, 1.5).unwrap()),
        ("cone", bodies::cone(1.0, 2.0).unwrap()),
        ("cylinder", bodies::cylinder(0.5, 2.0).unwrap()),
        ("prism", bodies::prism(&hexagon, 1.0).unwrap()),
        ("frustum", bodies::frustum(2.0, 1.0, 1.5).unwrap()),
        ("hex pyramid", bodies::pyramid(&hexagon, 0.7).unwrap()),
    ];
    for (name, s) in cases {
        let f = s.formula().unwrap();
        let (mut us, mut vs) = grid(&s, 41);
        us.extend([-1.0, 100.0]);
        vs.extend([-5.0, 9.0]);
        let mut out = vec![0.0; us.len() * 3];
        f.eval_batch(&[&us, &vs], &mut out).unwrap();
        for (k, p) in out.chunks_exact(3).enumerate() {
            let q = s.eval_formula(us[k], vs[k]);
            for c in 0..3 {
                assert!(
                    (q[c] - p[c]).abs() <= 1e-13,
                    "{name} at ({}, {}): {p:?} {q:?}",
                    us[k],
                    vs[k]
                );
            }
        }
        for (k, p) in out.chunks_exact(3).enumerate().take(41 * 41) {
            let q = s.eval(us[k], vs[k]);
            for c in 0..3 {
                assert!(
                    (q[c] - p[c]).abs() <= 1e-13,
                    "{name} structural at ({}, {})",
                    us[k],
                    vs[k]
                );
            }
        }
    }
}

#[test]
fn bad_bodies_are_errors() {
    assert!(matches!(
        bodies::rectangular_box(1.0, 0.0, 1.0),
        Err(Error::InvalidShape { .. })
    ));
    assert!(matches!(
        bodies::cone(-1.0, 1.0),
        Err(Error::InvalidShape { .. })
    ));
    assert!(matches!(
        bodies::cylinder(1.0, f64::NAN),
        Err(Error::InvalidShape { .. })
    ));
    assert!(matches!(
        bodies::prism(&[[0.0, 0.0], [1.0, 0.0]], 1.0),
        Err(Error::TooFewPoints { .. })
    ));
    // A bow tie is not simple.
    let e = bodies::prism(&[[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]], 1.0).unwrap_err();
    assert!(e.to_string().contains("not simple"), "{e}");
    let e = bodies::prism(&[[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [0.0, 1.0]], 1.0).unwrap_err();
    assert!(e.to_string().contains("coincide"), "{e}");
    assert!(bodies::regular_polygon(2, 1.0).is_err());
}
