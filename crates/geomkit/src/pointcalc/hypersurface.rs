//! Point equations of hypersurfaces over k factors (spec/point-calculus.md §1, §4): a grid of
//! experimental points (or source points of any dimension), each factor with its own nodes
//! (levels), M(x_1..x_k) = Σ f^1_(i_1)(x_1) ··· f^k_(i_k)(x_k) A_(i_1..i_k).
//!
//! Nothing is solved: the model is its source points and nodes. Evaluation contracts one
//! factor at a time, the last (fastest-varying) first: Π n_i multiply-adds, then
//! Π_(i<k-1) n_i, ...; [`Hypersurface::eval_many`] does it for blocks of 8 or 4 points at
//! once, each source value read once per block (the kernels of `kernel.rs`); adding
//! or removing a factor or a level touches only that factor's nodes and the values of the
//! added or removed slice. The shares (function-parameters) of all source points at a point
//! are a first-class result and sum to 1.
//!
//! ```
//! use geomkit::pointcalc::{Factor, Hypersurface, Nodes};
//! // y = a + 2b over a 3×2 grid of levels.
//! let records: Vec<Vec<f64>> = [0.0, 1.0, 3.0].iter()
//!     .flat_map(|&a| [0.0, 1.0].map(move |b| vec![a, b, a + 2.0 * b]))
//!     .collect();
//! let model = Hypersurface::from_records(&["a".into(), "b".into()], &records, &[], &Default::default())
//!     .unwrap();
//! assert_eq!(model.eval(&[3.0, 1.0]).unwrap(), vec![5.0]); // an experimental point
//! assert!((model.eval(&[2.0, 0.5]).unwrap()[0] - 3.0).abs() < 1e-14);
//! let shares = model.shares(&[2.0, 0.5]).unwrap();
//! assert!((shares.iter().sum::<f64>() - 1.0).abs() < 1e-14);
//! ```

use super::equation::{check_lebesgue, PointOptions, Warning};
use super::kernel::{self, Buffers, EvalPoints, Grid, LANES};
use super::nodes::Nodes;
use super::wide::{exponent, ldexp, short};
use crate::par::*;
use crate::{Error, Result};

/// A factor of a multi-factor model: its name and its nodes (the levels).
#[derive(Debug, Clone, PartialEq)]
pub struct Factor {
    name: String,
    nodes: Nodes,
}

impl Factor {
    /// A factor named `name` with levels at `nodes`.
    pub fn new(name: impl Into<String>, nodes: Nodes) -> Self {
        Factor {
            name: name.into(),
            nodes,
        }
    }

    /// The name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The nodes (levels).
    pub fn nodes(&self) -> &Nodes {
        &self.nodes
    }
}

/// A point equation over k factors through a full grid of source points.
#[derive(Debug, Clone, PartialEq)]
pub struct Hypersurface {
    factors: Vec<Factor>,
    dim: usize,
    /// Row-major over the factors (factor 0 slowest), `dim` values per cell.
    values: Vec<f64>,
    warnings: Vec<Warning>,
}

impl Hypersurface {
    /// The most numbers a model holds: dim · Π n_i (cells of the grid times numbers per
    /// cell), 10^8 (800 MB). Larger grids are refused with [`Error::TooMany`] before
    /// anything is allocated.
    pub const MAX_VALUES: usize = 100_000_000;

    /// The model through `values` (row-major over the factors, factor 0 slowest, `dim`
    /// numbers per cell). Errors: no factors, duplicate factor names, dim = 0, more than
    /// [`Hypersurface::MAX_VALUES`] numbers, a value count other than dim · Π n_i,
    /// non-finite values, a large Lebesgue constant when strict.
    pub fn new(
        factors: Vec<Factor>,
        dim: usize,
        values: Vec<f64>,
        options: &PointOptions,
    ) -> Result<Self> {
        if factors.is_empty() {
            return Err(Error::Empty { what: "factors" });
        }
        if dim == 0 {
            return Err(Error::ZeroDimension {
                what: "source points",
            });
        }
        // A set, not pairs: a model file may hold many factors.
        let mut names = std::collections::HashSet::with_capacity(factors.len());
        if !factors.iter().all(|f| names.insert(f.name.as_str())) {
            return Err(Error::InvalidOption {
                option: "factors",
                reason: "duplicate factor name",
            });
        }
        let expected = value_count(&factors, dim)?;
        if values.len() != expected {
            return Err(Error::PointCount {
                what: "values of the grid".into(),
                expected,
                got: values.len(),
            });
        }
        if let Some(k) = values.iter().position(|x| !x.is_finite()) {
            return Err(Error::NonFinite {
                what: "source point",
                index: k / dim,
            });
        }
        let mut warnings = Vec::new();
        for f in &factors {
            if let Some(w) = check_lebesgue(&format!("factor {}", f.name), &f.nodes, options)? {
                warnings.push(w);
            }
        }
        Ok(Hypersurface {
            factors,
            dim,
            values,
            warnings,
        })
    }

    /// The model sampling `f` at every grid cell (`f(levels, out)` writes dim values).
    /// Errors as [`Hypersurface::new`] (the size is checked before `f` is called).
    pub fn from_fn(
        factors: Vec<Factor>,
        dim: usize,
        mut f: impl FnMut(&[f64], &mut [f64]),
        options: &PointOptions,
    ) -> Result<Self> {
        if dim == 0 {
            return Err(Error::ZeroDimension {
                what: "source points",
            });
        }
        let total = value_count(&factors, dim)?;
        let shape: Vec<usize> = factors.iter().map(|f| f.nodes.len()).collect();
        let mut values = vec![0.0; total];
        let mut x = vec![0.0; factors.len()];
        for (c, out) in values.chunks_exact_mut(dim.max(1)).enumerate() {
            let mut rest = c;
            for k in (0..factors.len()).rev() {
                x[k] = factors[k].nodes.values()[rest % shape[k]];
                rest /= shape[k];
            }
            f(&x, out);
        }
        Hypersurface::new(factors, dim, values, options)
    }

    /// The model through experimental records: each record holds the k factor values then the
    /// response (one or more numbers). The levels of a factor are the distinct values in its
    /// column, or the nodes given for it in `nodes[k]` (data levels within 1e-9 of the node
    /// span of a node are matched to it; useful for exact rational nodes like 1/3).
    ///
    /// Errors ([`Error::GridRecord`] names the record): wrong record length, non-finite
    /// values, a level not among the given nodes, a cell given twice; [`Error::MissingCell`]
    /// when the records do not cover the full grid.
    pub fn from_records(
        names: &[String],
        records: &[Vec<f64>],
        nodes: &[Option<Nodes>],
        options: &PointOptions,
    ) -> Result<Self> {
        let k = names.len();
        if k == 0 {
            return Err(Error::Empty { what: "factors" });
        }
        let first = records.first().ok_or(Error::Empty { what: "records" })?;
        if first.len() <= k {
            return Err(Error::GridRecord {
                record: 0,
                reason: format!(
                    "has {} values; need the {k} factors and at least one response",
                    first.len()
                ),
            });
        }
        let width = first.len();
        let dim = width - k;
        for (r, rec) in records.iter().enumerate() {
            if rec.len() != width {
                return Err(Error::GridRecord {
                    record: r,
                    reason: format!("has {} values, expected {width}", rec.len()),
                });
            }
            if let Some(c) = rec.iter().position(|x| !x.is_finite()) {
                let column = names.get(c).cloned().unwrap_or_else(|| "response".into());
                return Err(Error::GridRecord {
                    record: r,
                    reason: format!("the value of '{column}' is not a finite number"),
                });
            }
        }
        // Levels of each factor and the level index of every record.
        let mut factors = Vec::with_capacity(k);
        let mut index = vec![vec![0usize; k]; records.len()];
        for f in 0..k {
            let given = nodes.get(f).cloned().flatten();
            let levels = match &given {
                Some(n) => n.clone(),
                None => {
                    let mut v: Vec<f64> = records.iter().map(|r| r[f]).collect();
                    v.sort_by(f64::total_cmp);
                    v.dedup();
                    Nodes::new(v)?
                }
            };
            let (lo, hi) = levels.domain();
            let tolerance = 1e-9 * (hi - lo).abs().max(lo.abs()).max(hi.abs()).max(1e-300);
            for (r, rec) in records.iter().enumerate() {
                let x = rec[f];
                let vals = levels.values();
                let j = vals.partition_point(|&v| v < x);
                let near = [j.wrapping_sub(1), j]
                    .into_iter()
                    .filter(|&j| j < vals.len())
                    .min_by(|&a, &b| (vals[a] - x).abs().total_cmp(&(vals[b] - x).abs()));
                match near {
                    Some(j) if (vals[j] - x).abs() <= tolerance => index[r][f] = j,
                    _ => {
                        return Err(Error::GridRecord {
                            record: r,
                            reason: format!(
                                "level {}={x} is not one of the nodes given for it",
                                names[f]
                            ),
                        })
                    }
                }
            }
            factors.push(Factor::new(names[f].clone(), levels));
        }
        let shape: Vec<usize> = factors.iter().map(|f| f.nodes.len()).collect();
        // The records sorted by cell (row-major order is the lexicographic order of the level
        // indices): duplicates are neighbours, and the first gap is the first missing cell.
        // Memory in the number of records, whatever the size of the grid they imply.
        let mut order: Vec<usize> = (0..records.len()).collect();
        order.sort_by(|&a, &b| index[a].cmp(&index[b]).then(a.cmp(&b)));
        let duplicate = order
            .windows(2)
            .filter(|w| index[w[0]] == index[w[1]])
            .min_by_key(|w| w[1]);
        if let Some(w) = duplicate {
            return Err(Error::GridRecord {
                record: w[1],
                reason: format!(
                    "duplicate cell {} (also record {})",
                    describe_cell(&factors, &index[w[1]]),
                    w[0]
                ),
            });
        }
        let cells = shape.iter().try_fold(1usize, |acc, &n| acc.checked_mul(n));
        if cells != Some(records.len()) {
            // Fewer records than cells: the first cell (row-major) that no record has.
            let mut want = vec![0usize; k];
            for &r in &order {
                if index[r] != want {
                    break;
                }
                for f in (0..k).rev() {
                    want[f] += 1;
                    if want[f] < shape[f] || f == 0 {
                        break;
                    }
                    want[f] = 0;
                }
            }
            return Err(Error::MissingCell {
                cell: describe_cell(&factors, &want),
                missing: cells.map_or(usize::MAX, |c| c - records.len()),
            });
        }
        value_count(&factors, dim)?;
        let mut values = vec![0.0; records.len() * dim];
        for (r, rec) in records.iter().enumerate() {
            let c = index[r]
                .iter()
                .zip(&shape)
                .fold(0, |acc, (i, n)| acc * n + i);
            values[c * dim..(c + 1) * dim].copy_from_slice(&rec[k..]);
        }
        Hypersurface::new(factors, dim, values, options)
    }

    /// The factors.
    pub fn factors(&self) -> &[Factor] {
        &self.factors
    }

    /// Number of factors k.
    pub fn k(&self) -> usize {
        self.factors.len()
    }

    /// Dimension of the source points (1 for a scalar response).
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// The source points, row-major over the factors (factor 0 slowest).
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// Number of levels of every factor.
    pub fn shape(&self) -> Vec<usize> {
        self.factors.iter().map(|f| f.nodes.len()).collect()
    }

    /// Warnings found when building.
    pub fn warnings(&self) -> &[Warning] {
        &self.warnings
    }

    /// The factor levels of grid cell `cell` (row-major index).
    pub fn cell_levels(&self, cell: usize) -> Vec<f64> {
        unflatten(cell, &self.shape())
            .iter()
            .zip(&self.factors)
            .map(|(&i, f)| f.nodes.values()[i])
            .collect()
    }

    /// Index of the factor named `name`.
    pub fn factor_index(&self, name: &str) -> Result<usize> {
        self.factors
            .iter()
            .position(|f| f.name == name)
            .ok_or_else(|| Error::UnknownFactor { name: name.into() })
    }

    /// The box spanned by the factors' nodes: (low, high) per factor.
    pub fn domain(&self) -> Vec<(f64, f64)> {
        self.factors.iter().map(|f| f.nodes.domain()).collect()
    }

    fn check_point(&self, x: &[f64]) -> Result<()> {
        if x.len() != self.k() {
            return Err(Error::DimensionMismatch {
                what: "evaluation point",
                index: 0,
                expected: self.k(),
                got: x.len(),
            });
        }
        match x.iter().position(|v| !v.is_finite()) {
            Some(index) => Err(Error::NonFinite {
                what: "factor value",
                index,
            }),
            None => Ok(()),
        }
    }

    /// M(x) into `out` (length dim). Errors: x of the wrong length or not finite, wrong
    /// buffer length; [`Error::ResultOverflow`] where the result is beyond f64;
    /// [`Error::LostToRounding`] far outside the box of the nodes (see
    /// [`Hypersurface::eval_many`]). At a grid cell the result is exactly its source point.
    pub fn eval_into(&self, x: &[f64], out: &mut [f64]) -> Result<()> {
        self.check_point(x)?;
        if out.len() != self.dim {
            return Err(Error::BufferSize {
                expected: self.dim,
                got: out.len(),
            });
        }
        let grid = self.grid();
        let mut buffers = Buffers::new(&grid);
        kernel::dispatch(EvalPoints {
            grid: &grid,
            xs: x,
            out: &mut *out,
            buffers: &mut buffers,
        });
        if self.needs_wide(x, out) {
            self.eval_wide(x, &self.scaled(), out)?;
        }
        Ok(())
    }

    /// Whether M(x) goes through [`Hypersurface::eval_wide`]: x outside the box of the nodes
    /// (extrapolation: the shares grow without bound and their sum cancels), or a result
    /// of the fast kernels that is not finite (an intermediate sum overflowed).
    fn needs_wide(&self, x: &[f64], out: &[f64]) -> bool {
        out.iter().any(|v| !v.is_finite())
            || self.factors.iter().zip(x).any(|(f, &t)| {
                let (lo, hi) = f.nodes.domain();
                t < lo || t > hi
            })
    }

    /// The values scaled by a power of two to |v| < 1 (exact), and that power.
    fn scaled(&self) -> (Vec<f64>, i64) {
        let max = self.values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let e = exponent(max);
        (self.values.iter().map(|&v| ldexp(v, -e)).collect(), e)
    }

    /// M(x) with nothing overflowing on the way: the values scaled to |v| < 1
    /// (`scaled` from [`Hypersurface::scaled`]), every factor's shares as mantissas with an
    /// exponent of their own (the product form, [`Nodes::basis_wide`]), contracted, and only
    /// then scaled back; the same roundings as the plain computation. Errors:
    /// [`Error::ResultOverflow`] when the result is beyond f64; outside the box of the nodes,
    /// [`Error::LostToRounding`] when the rounding error bound γ Σ |share| |value| (γ = (4 Σ
    /// n_i + 8 k + 8) ε) exceeds both the result and the largest source value.
    fn eval_wide(&self, x: &[f64], scaled: &(Vec<f64>, i64), out: &mut [f64]) -> Result<()> {
        let (values, ev) = scaled;
        let k = self.k();
        let nodes: Vec<&Nodes> = self.factors.iter().map(|f| &f.nodes).collect();
        let grid = Grid::new(nodes.clone(), values, self.dim);
        let mut bases: Vec<[f64; 1]> = Vec::with_capacity(grid.offsets[k]);
        let mut tmp = Vec::new();
        let mut e_sum: i64 = 0;
        for (n, &t) in nodes.iter().zip(x) {
            tmp.resize(n.len(), 0.0);
            e_sum += n.basis_wide(t, &mut tmp);
            bases.extend(tmp.iter().map(|&v| [v]));
        }
        let cells = self.values.len() / self.dim;
        let mut work = vec![[0.0]; cells / nodes[k - 1].len()];
        let outside = self.factors.iter().zip(x).any(|(f, &t)| {
            let (lo, hi) = f.nodes.domain();
            t < lo || t > hi
        });
        let magnitudes = outside.then(|| {
            let abs: Vec<f64> = values.iter().map(|v| v.abs()).collect();
            let bases: Vec<[f64; 1]> = bases.iter().map(|b| [b[0].abs()]).collect();
            (abs, bases)
        });
        let total_n: usize = nodes.iter().map(|n| n.len()).sum();
        let gamma = (4 * total_n + 8 * k + 8) as f64 * f64::EPSILON;
        let largest = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (c, o) in out.iter_mut().enumerate() {
            let sum = kernel::contract::<kernel::Plain, 1>(&grid, &bases, &mut work, c)[0];
            let value = ldexp(sum, ev + e_sum);
            if !value.is_finite() {
                return Err(Error::ResultOverflow {
                    what: format!("{} at {}", self.what_value(c), self.describe_at(x)),
                });
            }
            if let Some((abs, abs_bases)) = &magnitudes {
                let grid = Grid::new(nodes.clone(), abs, self.dim);
                let bound = kernel::contract::<kernel::Plain, 1>(&grid, abs_bases, &mut work, c)[0];
                // In units of 2^(ev + e_sum), like `sum`.
                let data = ldexp(largest, -e_sum);
                if gamma * bound > sum.abs().max(data) {
                    return Err(Error::LostToRounding {
                        what: format!("{} at {}", self.what_value(c), self.describe_at(x)),
                        error: ldexp(gamma * bound, ev + e_sum),
                    });
                }
            }
            *o = value;
        }
        Ok(())
    }

    /// "the modeled value" (dim 1) or "component c of the modeled point".
    fn what_value(&self, c: usize) -> String {
        if self.dim == 1 {
            "the modeled value".into()
        } else {
            format!("component {c} of the modeled point")
        }
    }

    /// "a=1e308, b=0": the factor values of a point, for messages.
    pub(crate) fn describe_at(&self, x: &[f64]) -> String {
        self.factors
            .iter()
            .zip(x)
            .map(|(f, &v)| format!("{}={}", f.name, short(v)))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// M(x).
    pub fn eval(&self, x: &[f64]) -> Result<Vec<f64>> {
        let mut out = vec![0.0; self.dim];
        self.eval_into(x, &mut out)?;
        Ok(out)
    }

    /// The kernels' view of the model.
    fn grid(&self) -> Grid<'_> {
        Grid::new(
            self.factors.iter().map(|f| &f.nodes).collect(),
            &self.values,
            self.dim,
        )
    }

    /// Evaluates at many points (`xs` row-major, k numbers each) into `out` (dim numbers
    /// each), in parallel over chunks of points. Every chunk runs in blocks of points (8 with
    /// AVX2+FMA or AVX-512, 4 on baseline x86-64; the CPU is checked at run time): their
    /// cardinal functions first, then one pass over the source values multiplying each into
    /// all the block's points (fused multiply-adds where the CPU has FMA). The same values as
    /// [`Hypersurface::eval`] point by point (which runs the same operations).
    ///
    /// Points outside the box of the nodes (extrapolation), and points whose result the
    /// kernels could not hold (huge source values whose partial sums overflow), are then
    /// evaluated again one by one with nothing overflowing on the way (the values scaled by a
    /// power of two, the shares in the product form with an exponent of their own).
    ///
    /// Errors: lengths, non-finite factor values; [`Error::ResultOverflow`] for a result beyond
    /// f64 (far outside the nodes, or huge source values); [`Error::LostToRounding`] outside
    /// the box when the rounding error bound γ Σ |share| |value| (γ = (4 Σ n_i + 8 k + 8) ε)
    /// exceeds both the result and the largest source value (extrapolating so far that no
    /// digit would be right). Each names the first such point.
    ///
    /// ```
    /// use geomkit::pointcalc::{Factor, Hypersurface, Nodes, PointOptions};
    /// let factors = vec![Factor::new("a", Nodes::paper_half()), Factor::new("b", Nodes::paper_third())];
    /// let m = Hypersurface::from_fn(factors, 1, |x, o| o[0] = x[0] * x[1], &PointOptions::default())
    ///     .unwrap();
    /// let xs = [0.25, 0.5, 1.0, 1.0 / 3.0, 0.7, 0.1];
    /// let mut out = [0.0; 3];
    /// m.eval_many(&xs, &mut out).unwrap();
    /// assert!((out[0] - 0.125).abs() < 1e-15 && (out[2] - 0.07).abs() < 1e-15);
    /// assert_eq!(out[1], m.eval(&xs[2..4]).unwrap()[0]);
    /// ```
    pub fn eval_many(&self, xs: &[f64], out: &mut [f64]) -> Result<()> {
        let k = self.k();
        if !xs.len().is_multiple_of(k) || out.len() != xs.len() / k * self.dim {
            return Err(Error::BufferSize {
                expected: xs.len() / k * self.dim,
                got: out.len(),
            });
        }
        if let Some(i) = xs.iter().position(|v| !v.is_finite()) {
            return Err(Error::NonFinite {
                what: "factor value of point",
                index: i / k,
            });
        }
        // About 2^16 multiply-adds per chunk: large enough to hide the scheduling.
        let cost = (self.values.len() + k * 16).max(1);
        let chunk = ((1 << 16) / cost)
            .clamp(LANES, 4096)
            .next_multiple_of(LANES);
        let d = self.dim;
        let grid = self.grid();
        let domain = self.domain();
        // Per chunk: whether a point needs the wide evaluation (checked where the chunk ran,
        // in one branch-free pass).
        let mut flagged = vec![false; xs.len().div_ceil(chunk * k)];
        xs.par_chunks(chunk * k)
            .zip(out.par_chunks_mut(chunk * d))
            .zip(flagged.par_iter_mut())
            .for_each_init(
                || Buffers::new(&grid),
                |buffers, ((xc, oc), flag)| {
                    kernel::dispatch(EvalPoints {
                        grid: &grid,
                        xs: xc,
                        out: &mut *oc,
                        buffers,
                    });
                    let mut bad = false;
                    for x in xc.chunks_exact(k) {
                        for (&t, &(lo, hi)) in x.iter().zip(&domain) {
                            bad |= (t < lo) | (t > hi);
                        }
                    }
                    for v in oc.iter() {
                        bad |= !v.is_finite();
                    }
                    *flag = bad;
                },
            );
        let mut scaled = None;
        let chunks = xs.chunks(chunk * k).zip(out.chunks_mut(chunk * d));
        for ((xc, oc), _) in chunks.zip(&flagged).filter(|(_, &f)| f) {
            for (x, o) in xc.chunks_exact(k).zip(oc.chunks_exact_mut(d)) {
                if self.needs_wide(x, o) {
                    let scaled = scaled.get_or_insert_with(|| self.scaled());
                    self.eval_wide(x, scaled, o)?;
                }
            }
        }
        Ok(())
    }

    /// The gradient: ∂M/∂x_f for every factor f, `k * dim` numbers (factor-major).
    /// Errors: as [`Hypersurface::eval`]; [`Error::ResultOverflow`] when a component is beyond f64.
    pub fn gradient(&self, x: &[f64]) -> Result<Vec<f64>> {
        self.check_point(x)?;
        let grid = self.grid();
        let mut l = Vec::with_capacity(self.k());
        let mut d = Vec::with_capacity(self.k());
        for (f, &xf) in self.factors.iter().zip(x) {
            let n = f.nodes.len();
            let (mut lf, mut df) = (vec![0.0; n], vec![0.0; n]);
            f.nodes.basis_derivatives(xf, &mut lf, &mut df, None);
            l.push(lf);
            d.push(df);
        }
        let mut bases = Vec::with_capacity(grid.offsets[self.k()]);
        let mut work = vec![[0.0]; self.values.len() / self.dim];
        let mut out = vec![0.0; self.k() * self.dim];
        for f in 0..self.k() {
            bases.clear();
            for g in 0..self.k() {
                let b = if g == f { &d[g] } else { &l[g] };
                bases.extend(b.iter().map(|&v| [v]));
            }
            for c in 0..self.dim {
                out[f * self.dim + c] =
                    kernel::contract::<kernel::Plain, 1>(&grid, &bases, &mut work, c)[0];
            }
        }
        if out.iter().any(|v| !v.is_finite()) {
            return Err(Error::ResultOverflow {
                what: format!("the gradient at {}", self.describe_at(x)),
            });
        }
        Ok(out)
    }

    /// The shares of all source points in M(x) (row-major like the values, one number per
    /// cell): the products of the factors' function-parameters. They sum to 1 (up to
    /// rounding: far outside the nodes they are huge, of both signs, and their sum cancels).
    /// Errors: as [`Hypersurface::eval`]; [`Error::ResultOverflow`] naming the first share beyond
    /// f64 (far outside the nodes a share grows like x^(n-1) per factor).
    pub fn shares(&self, x: &[f64]) -> Result<Vec<f64>> {
        self.check_point(x)?;
        let shares = self.outer_product(x, |nodes, t, b| nodes.basis_into(t, b));
        if shares.iter().all(|s| s.is_finite()) {
            return Ok(shares);
        }
        // Far outside the nodes: mantissas with an exponent per factor, so that no product
        // overflows on the way, and only then the shares.
        let mut e: i64 = 0;
        let mut shares = self.outer_product(x, |nodes, t, b| e += nodes.basis_wide(t, b));
        for (c, s) in shares.iter_mut().enumerate() {
            *s = ldexp(*s, e);
            if !s.is_finite() {
                let levels = self.describe_at(&self.cell_levels(c));
                return Err(Error::ResultOverflow {
                    what: format!(
                        "the share of point {c} ({levels}) at {}",
                        self.describe_at(x)
                    ),
                });
            }
        }
        Ok(shares)
    }

    /// The outer product of the factors' cardinal functions at x, written by `basis(nodes,
    /// t, out)` (row-major, built in place from the back).
    fn outer_product(&self, x: &[f64], mut basis: impl FnMut(&Nodes, f64, &mut [f64])) -> Vec<f64> {
        let mut shares = vec![0.0; self.values.len() / self.dim];
        shares[0] = 1.0;
        let mut len = 1;
        let mut b = Vec::new();
        for (f, &xf) in self.factors.iter().zip(x) {
            let n = f.nodes.len();
            b.resize(n, 0.0);
            basis(&f.nodes, xf, &mut b);
            for j in (0..len).rev() {
                let s = shares[j];
                for (o, bi) in shares[j * n..(j + 1) * n].iter_mut().zip(&b) {
                    *o = s * bi;
                }
            }
            len *= n;
        }
        shares
    }

    fn stride(&self, factor: usize) -> (usize, usize, usize) {
        let shape = self.shape();
        let outer: usize = shape[..factor].iter().product();
        let inner: usize = shape[factor + 1..].iter().product::<usize>() * self.dim;
        (outer, shape[factor], inner)
    }

    /// The source points of level `level` of `factor` (the grid of the other factors,
    /// row-major): what [`Hypersurface::add_level`] takes.
    pub fn level_slice(&self, factor: usize, level: usize) -> Result<Vec<f64>> {
        self.check_factor_level(factor, level)?;
        let (outer, n, inner) = self.stride(factor);
        Ok((0..outer)
            .flat_map(|o| {
                self.values[(o * n + level) * inner..][..inner]
                    .iter()
                    .copied()
            })
            .collect())
    }

    fn check_factor_level(&self, factor: usize, level: usize) -> Result<()> {
        if factor >= self.k() {
            return Err(Error::IndexOutOfRange {
                what: "factor",
                index: factor,
                len: self.k(),
            });
        }
        let n = self.factors[factor].nodes.len();
        if level >= n {
            return Err(Error::IndexOutOfRange {
                what: "level",
                index: level,
                len: n,
            });
        }
        Ok(())
    }

    /// The same model with its values scaled by 2^-e (exact for normal values): what
    /// [`super::optimize`] searches, so that no Bernstein coefficient or range overflows.
    pub(crate) fn scaled_by(&self, e: i64) -> Hypersurface {
        Hypersurface {
            factors: self.factors.clone(),
            dim: self.dim,
            values: self.values.iter().map(|&v| ldexp(v, -e)).collect(),
            warnings: Vec::new(),
        }
    }

    fn rebuilt(&self, factors: Vec<Factor>, values: Vec<f64>) -> Result<Hypersurface> {
        Hypersurface::new(factors, self.dim, values, &PointOptions::default())
    }

    /// The model without level `level` of `factor`: that factor's nodes lose a node (weights
    /// updated from the positions), its slice of source points is dropped; nothing else
    /// changes. Errors: indices out of range, the factor's last level (remove the factor).
    pub fn remove_level(&self, factor: usize, level: usize) -> Result<Hypersurface> {
        self.check_factor_level(factor, level)?;
        let nodes = self.factors[factor].nodes.without(level)?;
        let (outer, n, inner) = self.stride(factor);
        let mut values = Vec::with_capacity(self.values.len() / n * (n - 1));
        for o in 0..outer {
            for i in (0..n).filter(|&i| i != level) {
                values.extend_from_slice(&self.values[(o * n + i) * inner..][..inner]);
            }
        }
        let mut factors = self.factors.clone();
        factors[factor].nodes = nodes;
        self.rebuilt(factors, values)
    }

    /// The model with a new level of `factor` at `value`, whose source points are `slice`
    /// (the grid of the other factors, row-major, as [`Hypersurface::level_slice`] gives).
    /// Errors: index out of range, a level already there, a slice of the wrong length.
    pub fn add_level(&self, factor: usize, value: f64, slice: &[f64]) -> Result<Hypersurface> {
        self.check_factor_level(factor, 0)?;
        let (outer, n, inner) = self.stride(factor);
        if slice.len() != outer * inner {
            return Err(Error::PointCount {
                what: "values of the new level".into(),
                expected: outer * inner,
                got: slice.len(),
            });
        }
        let (nodes, at) = self.factors[factor].nodes.with_node(value)?;
        let mut values = Vec::with_capacity(self.values.len() + slice.len());
        for o in 0..outer {
            for i in 0..=n {
                if i == at {
                    values.extend_from_slice(&slice[o * inner..(o + 1) * inner]);
                } else {
                    let src = if i < at { i } else { i - 1 };
                    values.extend_from_slice(&self.values[(o * n + src) * inner..][..inner]);
                }
            }
        }
        let mut factors = self.factors.clone();
        factors[factor].nodes = nodes;
        self.rebuilt(factors, values)
    }

    /// The model with `factor` removed by keeping its level `level` (the section of the
    /// model there). Errors: indices out of range, removing the only factor.
    pub fn remove_factor(&self, factor: usize, level: usize) -> Result<Hypersurface> {
        self.check_factor_level(factor, level)?;
        if self.k() == 1 {
            return Err(Error::TooFewPoints {
                what: "factors",
                got: 0,
                min: 1,
            });
        }
        let values = self.level_slice(factor, level)?;
        let mut factors = self.factors.clone();
        factors.remove(factor);
        self.rebuilt(factors, values)
    }

    /// The model with `factor` fixed at the value `x` (contracted there) and removed.
    /// Errors: indices out of range, x not finite, the only factor; [`Error::ResultOverflow`] when a
    /// value of the section is beyond f64 (x far outside the factor's nodes).
    pub fn fix_factor(&self, factor: usize, x: f64) -> Result<Hypersurface> {
        self.check_factor_level(factor, 0)?;
        if !x.is_finite() {
            return Err(Error::NonFinite {
                what: "factor value",
                index: factor,
            });
        }
        if self.k() == 1 {
            return Err(Error::TooFewPoints {
                what: "factors",
                got: 0,
                min: 1,
            });
        }
        let b = self.factors[factor].nodes.basis(x);
        let (outer, n, inner) = self.stride(factor);
        let mut values = vec![0.0; outer * inner];
        for o in 0..outer {
            for (i, bi) in b.iter().enumerate() {
                let src = &self.values[(o * n + i) * inner..][..inner];
                for (v, s) in values[o * inner..(o + 1) * inner].iter_mut().zip(src) {
                    *v += bi * s;
                }
            }
        }
        if values.iter().any(|v| !v.is_finite()) {
            return Err(Error::ResultOverflow {
                what: format!(
                    "the section at {}={} (the model with factor {} fixed there)",
                    self.factors[factor].name,
                    short(x),
                    self.factors[factor].name
                ),
            });
        }
        let mut factors = self.factors.clone();
        factors.remove(factor);
        self.rebuilt(factors, values)
    }

    /// The model with a new factor at position `position` (0..=k): `slices[i]` holds the
    /// source points of its level i (the current grid, row-major). Errors: position out of
    /// range, a name already used, slice count or lengths wrong.
    pub fn add_factor(
        &self,
        position: usize,
        factor: Factor,
        slices: &[Vec<f64>],
    ) -> Result<Hypersurface> {
        if position > self.k() {
            return Err(Error::IndexOutOfRange {
                what: "factor position",
                index: position,
                len: self.k() + 1,
            });
        }
        let n = factor.nodes.len();
        if slices.len() != n {
            return Err(Error::PointCount {
                what: format!("slices of factor {}", factor.name),
                expected: n,
                got: slices.len(),
            });
        }
        if let Some(s) = slices.iter().find(|s| s.len() != self.values.len()) {
            return Err(Error::PointCount {
                what: format!("values of a level of factor {}", factor.name),
                expected: self.values.len(),
                got: s.len(),
            });
        }
        let shape = self.shape();
        let outer: usize = shape[..position].iter().product();
        let inner: usize = shape[position..].iter().product::<usize>() * self.dim;
        let mut values = Vec::with_capacity(self.values.len() * n);
        for o in 0..outer {
            for s in slices {
                values.extend_from_slice(&s[o * inner..(o + 1) * inner]);
            }
        }
        let mut factors = self.factors.clone();
        factors.insert(position, factor);
        Hypersurface::new(factors, self.dim, values, &PointOptions::default())
    }
}

/// dim · Π n_i, checked against [`Hypersurface::MAX_VALUES`] (and usize overflow).
fn value_count(factors: &[Factor], dim: usize) -> Result<usize> {
    let total = factors
        .iter()
        .try_fold(dim, |acc, f| acc.checked_mul(f.nodes.len()));
    match total {
        Some(t) if t <= Hypersurface::MAX_VALUES => Ok(t),
        t => Err(Error::TooMany {
            what: "numbers in the model's grid (cells times numbers per cell)",
            got: t.unwrap_or(usize::MAX),
            max: Hypersurface::MAX_VALUES,
        }),
    }
}

/// Multi-index of a row-major flat index.
pub(crate) fn unflatten(mut c: usize, shape: &[usize]) -> Vec<usize> {
    let mut idx = vec![0; shape.len()];
    for k in (0..shape.len()).rev() {
        idx[k] = c % shape[k];
        c /= shape[k];
    }
    idx
}

fn describe_cell(factors: &[Factor], idx: &[usize]) -> String {
    factors
        .iter()
        .zip(idx)
        .map(|(f, &i)| format!("{}={}", f.name, f.nodes.values()[i]))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn records() -> Vec<Vec<f64>> {
        let mut r = Vec::new();
        for a in [1.0, 2.0, 4.0] {
            for b in [0.0, 0.5] {
                r.push(vec![a, b, a * a - b]);
            }
        }
        r
    }

    #[test]
    fn grid_errors_name_the_record() {
        let names = vec!["a".to_string(), "b".to_string()];
        let mut r = records();
        r[4][1] = 0.5;
        r[5][1] = 0.5;
        match Hypersurface::from_records(&names, &r, &[], &PointOptions::default()) {
            Err(Error::GridRecord { record: 5, reason }) => assert!(reason.contains("duplicate")),
            other => panic!("{other:?}"),
        }
        let mut r = records();
        r.pop();
        assert!(matches!(
            Hypersurface::from_records(&names, &r, &[], &PointOptions::default()),
            Err(Error::MissingCell { missing: 1, .. })
        ));
        let mut r = records();
        r[2][2] = f64::NAN;
        assert!(matches!(
            Hypersurface::from_records(&names, &r, &[], &PointOptions::default()),
            Err(Error::GridRecord { record: 2, .. })
        ));
    }

    #[test]
    fn gradient_matches_polynomial() {
        let names = vec!["a".to_string(), "b".to_string()];
        let m =
            Hypersurface::from_records(&names, &records(), &[], &PointOptions::default()).unwrap();
        let g = m.gradient(&[1.5, 0.2]).unwrap();
        assert!(
            (g[0] - 3.0).abs() < 1e-13 && (g[1] + 1.0).abs() < 1e-13,
            "{g:?}"
        );
    }
}
