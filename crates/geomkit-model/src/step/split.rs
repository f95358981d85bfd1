//! Rational B-splines of several spans as rational Bézier pieces: knot insertion (Boehm's
//! algorithm) in homogeneous coordinates until every knot of the domain has multiplicity p,
//! then each span's p + 1 control points are its Bézier points (Piegl & Tiller, The NURBS
//! Book, A5.1 and A5.6). Where the knots already have multiplicity p (circles made of
//! Bézier arcs) nothing is computed: the pieces' points and weights are the file's.

/// One Bézier span: its parameter interval, its p + 1 control rows and, for each, the index
/// of the given row it is (`None` for rows computed by knot insertion).
pub(crate) struct Span {
    pub from: f64,
    pub to: f64,
    pub rows: Vec<Vec<f64>>,
    pub origin: Vec<Option<usize>>,
}

/// Inserts `x` once into the degree-`p` B-spline (`knots`, control `rows` of any length)
/// whose domain starts at `a`: Q_i = (1 - α_i) P_(i-1) + α_i P_i, α_i = (x - u_i) /
/// (u_(i+p) - u_i), for k-p+1 <= i <= k where u_k < x <= u_(k+1) (u_k <= x < u_(k+1) at
/// the domain's start), so that k <= n - 1 also at the domain's end.
fn insert(
    p: usize,
    a: f64,
    knots: &mut Vec<f64>,
    rows: &mut Vec<Vec<f64>>,
    origin: &mut Vec<Option<usize>>,
    x: f64,
) {
    let k = if x > a {
        knots.partition_point(|&u| u < x) - 1
    } else {
        knots.partition_point(|&u| u <= x) - 1
    };
    let mut out = Vec::with_capacity(rows.len() + 1);
    out.extend(rows[..k + 1 - p].iter().cloned());
    for i in k + 1 - p..=k {
        let alpha = (x - knots[i]) / (knots[i + p] - knots[i]);
        let q = rows[i - 1]
            .iter()
            .zip(&rows[i])
            .map(|(a, b)| (1.0 - alpha) * a + alpha * b)
            .collect();
        out.push(q);
    }
    out.extend(rows[k..].iter().cloned());
    knots.insert(k + 1, x);
    *rows = out;
    let mut o = origin[..k + 1 - p].to_vec();
    o.extend(std::iter::repeat_n(None, p));
    o.extend_from_slice(&origin[k..]);
    *origin = o;
}

/// The Bézier spans of the degree-`p` B-spline with full knot vector `knots` (n + p + 1
/// values, non-decreasing, u_p < u_n) and n control rows, over its domain [u_p, u_n].
pub(crate) fn spans(p: usize, knots: &[f64], rows: &[Vec<f64>]) -> Vec<Span> {
    let n = rows.len();
    let (a, b) = (knots[p], knots[n]);
    let mut knots = knots.to_vec();
    let mut rows = rows.to_vec();
    let mut origin: Vec<Option<usize>> = (0..n).map(Some).collect();
    let mut distinct: Vec<f64> = knots
        .iter()
        .copied()
        .filter(|&u| a <= u && u <= b)
        .collect();
    distinct.dedup();
    for &x in &distinct {
        // The domain's ends need p knots (a clamped end has p + 1 already); inside, p.
        while knots.iter().filter(|&&u| u == x).count() < p {
            insert(p, a, &mut knots, &mut rows, &mut origin, x);
        }
    }
    distinct
        .windows(2)
        .map(|w| {
            // The last knot equal to the span's start: its Bézier points end there.
            let j = knots.partition_point(|&u| u <= w[0]) - 1;
            Span {
                from: w[0],
                to: w[1],
                rows: rows[j - p..=j].to_vec(),
                origin: origin[j - p..=j].to_vec(),
            }
        })
        .collect()
}

/// The same B-spline clamped to its domain [u_p, u_n]: each end knot inserted until it has
/// multiplicity p, then the knots beyond it replaced by one more copy (C(a) = P_(k-p) when
/// a = u_(k-p+1) = ... = u_k), the control rows outside dropped. Knot vectors already
/// clamped come back unchanged.
pub(crate) fn clamp(p: usize, knots: &[f64], rows: &[Vec<f64>]) -> (Vec<f64>, Vec<Vec<f64>>) {
    let n = rows.len();
    let (a, b) = (knots[p], knots[n]);
    let mut knots = knots.to_vec();
    let mut rows = rows.to_vec();
    let mut origin: Vec<Option<usize>> = (0..n).map(Some).collect();
    for x in [a, b] {
        while knots.iter().filter(|&&u| u == x).count() < p {
            insert(p, a, &mut knots, &mut rows, &mut origin, x);
        }
    }
    // Start: k the last index of a.
    let k = knots.partition_point(|&u| u <= a) - 1;
    let mut out_knots = vec![a; p + 1];
    let first = k - p;
    // End: j the first index of b.
    let j = knots.partition_point(|&u| u < b);
    out_knots.extend_from_slice(&knots[k + 1..j]);
    out_knots.extend(std::iter::repeat_n(b, p + 1));
    (out_knots, rows[first..j].to_vec())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_single_knot_splits_a_quadratic_at_its_homogeneous_midpoint() {
        // Knots 0, 0, 0, 1, 2, 2, 2: inserting 1 once gives (P1 + P2) / 2 (α = 1/2).
        let rows = vec![vec![0.0], vec![2.0], vec![6.0], vec![8.0]];
        let s = spans(2, &[0.0, 0.0, 0.0, 1.0, 2.0, 2.0, 2.0], &rows);
        assert_eq!(s.len(), 2);
        assert_eq!(s[0].rows, vec![vec![0.0], vec![2.0], vec![4.0]]);
        assert_eq!(s[1].rows, vec![vec![4.0], vec![6.0], vec![8.0]]);
        assert_eq!(s[1].origin, vec![None, Some(2), Some(3)]);
        assert_eq!((s[1].from, s[1].to), (1.0, 2.0));
    }

    #[test]
    fn clamping_keeps_the_curve_on_its_domain() {
        // The uniform cubic of the next test, clamped: its single span's Bézier points.
        let rows = vec![vec![0.0], vec![6.0], vec![12.0], vec![6.0]];
        let knots: Vec<f64> = (0..8).map(f64::from).collect();
        let (k, r) = clamp(3, &knots, &rows);
        assert_eq!(k, vec![3.0, 3.0, 3.0, 3.0, 4.0, 4.0, 4.0, 4.0]);
        assert_eq!(r.len(), 4);
        assert!(
            (r[0][0] - 6.0).abs() < 1e-14 && (r[3][0] - 10.0).abs() < 1e-14,
            "{r:?}"
        );
        // Clamped already: unchanged.
        let k0 = [0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0];
        let r0 = vec![vec![1.0], vec![2.0], vec![3.0], vec![4.0]];
        assert_eq!(clamp(2, &k0, &r0), (k0.to_vec(), r0));
    }

    #[test]
    fn unclamped_ends_are_clamped_to_the_domain() {
        // A uniform cubic on knots 0..7 (domain [3, 4]): one span, the B-spline's Bézier
        // points (1/6)(P0 + 4P1 + P2) ... of the uniform cubic.
        let rows = vec![vec![0.0], vec![6.0], vec![12.0], vec![6.0]];
        let knots: Vec<f64> = (0..8).map(f64::from).collect();
        let s = spans(3, &knots, &rows);
        assert_eq!(s.len(), 1);
        let want = [
            (0.0 + 4.0 * 6.0 + 12.0) / 6.0,
            (2.0 * 6.0 + 12.0) / 3.0,
            (6.0 + 2.0 * 12.0) / 3.0,
            (6.0 + 4.0 * 12.0 + 6.0) / 6.0,
        ];
        for (r, w) in s[0].rows.iter().zip(want) {
            assert!((r[0] - w).abs() < 1e-14, "{r:?} {w}");
        }
    }
}
