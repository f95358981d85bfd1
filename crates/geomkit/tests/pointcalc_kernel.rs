//! The batched evaluation kernels of k-factor models (`Hypersurface::eval_many`: blocks of 8
//! or 4 points, fused multiply-adds where the CPU has them) against single points, against
//! the shares (an independent sum over the grid) and at the grid cells, for k = 1..5 factors,
//! odd numbers of levels (1 to 17: the unrolled, general and large-node-set paths), dim 1
//! and 3, and odd numbers of points (not a multiple of the block).

use geomkit::pointcalc::{Factor, Hypersurface, NodePreset, Nodes, PointOptions};

/// A Weyl sequence in [0, 1) (evenly spread, deterministic).
struct Rng(f64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = (self.0 + 0.618_033_988_749_894_9) % 1.0;
        self.0
    }
}

/// A model with the given numbers of levels (Chebyshev, equispaced or the paper's nodes by
/// factor) and `dim` values per cell from a smooth function plus noise.
fn model(shape: &[usize], dim: usize, rng: &mut Rng) -> Hypersurface {
    let factors: Vec<Factor> = shape
        .iter()
        .enumerate()
        .map(|(f, &n)| {
            let nodes = match (n, f % 3) {
                (3, 2) => Nodes::paper_third(),
                (_, 1) if n <= 7 => Nodes::preset(NodePreset::Equispaced, n, -2.0, 3.0).unwrap(),
                _ => Nodes::preset(
                    NodePreset::ChebyshevSecond,
                    n,
                    0.5 * f as f64,
                    2.0 + f as f64,
                )
                .unwrap(),
            };
            Factor::new(format!("x{f}"), nodes)
        })
        .collect();
    let noise: Vec<f64> = (0..shape.iter().product::<usize>() * dim)
        .map(|_| rng.next() - 0.5)
        .collect();
    let mut cell = 0;
    Hypersurface::from_fn(
        factors,
        dim,
        |x, o| {
            let s: f64 = x.iter().sum();
            for (c, v) in o.iter_mut().enumerate() {
                *v = (s + c as f64).sin() * 3.0 + noise[cell];
                cell += 1;
            }
        },
        &PointOptions::default(),
    )
    .unwrap()
}

/// `count` points: inside the box, outside it, on nodes, on node planes.
fn points(m: &Hypersurface, count: usize, rng: &mut Rng) -> Vec<f64> {
    let mut xs = Vec::new();
    for i in 0..count {
        for f in m.factors() {
            let (lo, hi) = f.nodes().domain();
            let v = f.nodes().values();
            let x = match (i + xs.len()) % 11 {
                0 => v[(rng.next() * v.len() as f64) as usize],
                1 => lo - 0.3 * (hi - lo + 1.0) * rng.next(),
                2 => hi + 0.3 * (hi - lo + 1.0) * rng.next(),
                _ => lo + (hi - lo) * rng.next(),
            };
            xs.push(x);
        }
    }
    xs
}

const SHAPES: &[&[usize]] = &[
    &[1],
    &[3],
    &[7],
    &[17],
    &[5, 2],
    &[3, 9],
    &[1, 4],
    &[3, 3, 3],
    &[3, 7, 1],
    &[2, 5, 11],
    &[3, 5, 2, 7],
    &[8, 1, 6, 3],
    &[3, 3, 3, 3, 3],
    &[5, 4, 3, 2, 7],
];

#[test]
fn batched_equals_single_points_and_the_shares() {
    let mut rng = Rng(0.11);
    for &shape in SHAPES {
        for dim in [1, 3] {
            let m = model(shape, dim, &mut rng);
            let k = shape.len();
            for count in [1, 5, 37] {
                let xs = points(&m, count, &mut rng);
                let mut many = vec![0.0; count * dim];
                m.eval_many(&xs, &mut many).unwrap();
                for (p, x) in xs.chunks_exact(k).enumerate() {
                    let one = m.eval(x).unwrap();
                    let shares = m.shares(x).unwrap();
                    for c in 0..dim {
                        // The scale of the sum: Σ |share| |value|.
                        let (sum, scale) =
                            shares
                                .iter()
                                .enumerate()
                                .fold((0.0, 0.0), |(s, a), (cell, w)| {
                                    let v = m.values()[cell * dim + c];
                                    (s + w * v, a + (w * v).abs())
                                });
                        let got = many[p * dim + c];
                        assert!(
                            (got - one[c]).abs() <= 4.0 * f64::EPSILON * scale,
                            "{shape:?} dim {dim} point {x:?}: batched {got} vs single {}",
                            one[c]
                        );
                        assert!(
                            (got - sum).abs() <= 1e-13 * scale.max(1e-300),
                            "{shape:?} dim {dim} point {x:?}: {got} vs Σ shares·values {sum}"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn batched_evaluation_is_exact_at_every_cell() {
    let mut rng = Rng(0.5);
    for &shape in SHAPES {
        let m = model(shape, 2, &mut rng);
        let cells = m.values().len() / 2;
        let xs: Vec<f64> = (0..cells).flat_map(|c| m.cell_levels(c)).collect();
        let mut out = vec![0.0; cells * 2];
        m.eval_many(&xs, &mut out).unwrap();
        assert_eq!(out, m.values(), "{shape:?}");
    }
}

#[test]
fn shares_are_the_products_of_the_cardinal_functions() {
    let mut rng = Rng(0.3);
    for &shape in SHAPES {
        let m = model(shape, 1, &mut rng);
        let xs = points(&m, 7, &mut rng);
        for x in xs.chunks_exact(shape.len()) {
            let bases: Vec<Vec<f64>> = m
                .factors()
                .iter()
                .zip(x)
                .map(|(f, &t)| f.nodes().basis(t))
                .collect();
            let shares = m.shares(x).unwrap();
            assert_eq!(shares.len(), m.values().len());
            for (cell, s) in shares.iter().enumerate() {
                let mut rest = cell;
                let mut idx = vec![0; shape.len()];
                for f in (0..shape.len()).rev() {
                    idx[f] = rest % shape[f];
                    rest /= shape[f];
                }
                let want = idx.iter().zip(&bases).fold(1.0, |acc, (&i, b)| acc * b[i]);
                assert_eq!(*s, want, "{shape:?} {x:?} cell {cell}");
            }
        }
    }
}
