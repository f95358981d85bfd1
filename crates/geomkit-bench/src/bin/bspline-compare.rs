//! Timing driver of the side-by-side comparison of method 2 with SciPy
//! (`bash bench/compare_bspline.sh`): interpolating cubic B-spline curves and height
//! surfaces, their evaluation, peak memory and accuracy.
//!
//! Usage: `bspline-compare CASE` where CASE is one JSON object (or `@FILE`). One case per
//! process, so that the peak-memory figure of the build is that of a fresh process. Prints
//! one JSON object to stdout.
//!
//! The inputs are not passed in: the driver generates them from `seed` and the sizes with the
//! fixtures of `geomkit_bench` ([`helix_points`], [`height_grid`], [`random_params`],
//! [`linspace`]), which `bench/compare_bspline.py` rebuilds bit for bit with numpy.
//!
//! Cases (all take `"seed"`, and the timing knobs `"samples"` (default 15),
//! `"min_batch_seconds"` (0.02), `"max_seconds"` (10)):
//!
//! - `{"op": "curve_build", "variant": V, "n": N, "check": K}`: N points of
//!   [`helix_points`] (3-D), not-a-knot ends. V = `"uniform"`
//!   (`interpolate_curve_flat`, `Parametrization::Uniform`: SciPy's `make_interp_spline(arange(N), y)`),
//!   `"chord"` (`interpolate_curve_flat`, `ChordLength`: computes the parameters too),
//!   `"at"` (`interpolate_curve_at` with the chord-length parameters computed beforehand
//!   by `geomkit::bspline::parameters`: SciPy's `make_interp_spline(x, y)`),
//!   `"tiled"` (`interpolate_curve_tiled`, uniform parameters, default tiles),
//!   `"into"` (a `CurveInterpolator` for uniform parameters set up once, then `solve_into`
//!   a control buffer the caller keeps: the timed calls reuse it; `setup_s` is the setup).
//!   Reports the build time, its peak memory, the interpolation residual at all N points,
//!   the curve at K check parameters (midpoints between data parameters, for the agreement
//!   with SciPy), and the times of a few sub-steps.
//! - `{"op": "curve_eval", "variant": "uniform" | "chord", "n": N, "check": K, "kinds": [..]}`:
//!   builds the curve as `curve_build` does, then times each kind
//!   `{"kind": "fd" | "par" | "par_new" | "seq" | "nu" | "pp", "params": "uniform" | "sorted" | "unsorted",
//!   "count": M, "param_seed": s}`: `fd` = `sample_uniform_fd(M)` (uniform only), `par` =
//!   `eval_many_par`, `par_new` = `eval_many_par` into a new buffer each call (allocation and first-touch page faults
//!   included, as in a call from Python; `geomkit::mem::zeros`: huge pages advised, as NumPy does), `seq` = `Curve::eval_batch` on the calling thread, bit exact (the B-spline kernels),
//!   `nu` = `eval_nu_many(t, 0, Extrapolate::Extend, out)` (SciPy's algorithm: the kernel of
//!   the Python package's `BSpline.__call__`, `bench/compare_python.sh`), `pp` = `PiecewiseCurve::eval_many_par`
//!   of `to_piecewise()` (built once, untimed; its time is `piecewise_build`); parameters = `linspace` over the
//!   domain, or [`random_params`] over the domain (sorted or as generated). Reports the
//!   values at K of the M parameters (every M/K-th).
//! - `{"op": "surface", "variant": "heights" | "heights_at", "rows": R, "cols": C,
//!   "grid_eval": G, "scattered": S, "param_seed": s, "check": K}`: heights
//!   [`height_grid`] at x_i = i/(R-1), y_j = j/(C-1); `interpolate_heights` (regular grid)
//!   or `interpolate_heights_at` (the coordinates given), not-a-knot. Reports the build
//!   time and peak memory, the residual at all R·C nodes, `eval_grid` on a G×G grid
//!   (linspace over the domain), at S scattered points `eval_into` one by one and the
//!   batched `eval_many_par`, and values at K scattered points and on a sub-grid.
//!
//! `"only_time": true` skips everything but the timing of the build (for `perf record`).
//!
//! Peak memory: the driver writes `5` to `/proc/self/clear_refs` (resets the peak RSS to
//! the current RSS) after generating the input, reads `VmRSS`, runs the operation once,
//! and reads `VmHWM` while the result is alive: `peak_extra_bytes` = VmHWM - VmRSS, which
//! includes the result itself (`output_bytes`).

use std::hint::black_box;
use std::time::Instant;

use geomkit::bspline::{
    interpolate_curve_at, interpolate_curve_flat, interpolate_curve_tiled, interpolate_heights,
    interpolate_heights_at, make_interp_spline, parameters, BsplineCurve, BsplineSurface,
    CurveInterpolation, CurveInterpolator, EndCondition, Extrapolate, InterpolationOptions,
    Parametrization, SplineOptions, TileOptions,
};
use geomkit::geom::{BatchOptions, Curve};
use geomkit_bench::{height_grid, helix_points, linspace, random_params};
use serde::Deserialize;
use serde_json::{json, Value};

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Case {
    op: String,
    variant: String,
    #[serde(default)]
    seed: u64,
    #[serde(default)]
    n: usize,
    #[serde(default)]
    rows: usize,
    #[serde(default)]
    cols: usize,
    #[serde(default)]
    check: usize,
    /// Degree of `spline_build` (default 3).
    #[serde(default)]
    degree: Option<usize>,
    #[serde(default)]
    kinds: Vec<EvalKind>,
    #[serde(default)]
    grid_eval: usize,
    #[serde(default)]
    scattered: usize,
    #[serde(default)]
    param_seed: u64,
    #[serde(default)]
    samples: Option<usize>,
    #[serde(default)]
    min_batch_seconds: Option<f64>,
    #[serde(default)]
    max_seconds: Option<f64>,
    /// Time the operation only (no residual, checks or sub-steps): for profiling with
    /// `perf record`.
    #[serde(default)]
    only_time: bool,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct EvalKind {
    kind: String,
    params: String,
    count: usize,
    #[serde(default)]
    param_seed: u64,
}

/// Timing knobs of one case.
#[derive(Debug, Clone, Copy)]
struct Timing {
    samples: usize,
    min_batch: f64,
    max_seconds: f64,
}

/// What [`time_it`] measured: seconds per call.
#[derive(Debug, Clone, Copy)]
struct Times {
    first: f64,
    median: f64,
    min: f64,
    samples: usize,
    inner: usize,
}

impl Times {
    fn json(&self, items: usize) -> Value {
        json!({
            "first_s": self.first,
            "median_s": self.median,
            "min_s": self.min,
            "samples": self.samples,
            "calls_per_sample": self.inner,
            "items": items,
            "items_per_s": items as f64 / self.median,
        })
    }
}

/// The scheme of `bezier-compare` (and of the Python side): one first call (its result is
/// returned; the caller may measure memory around it), then `samples` batches of `inner`
/// calls, `inner` chosen so that a batch lasts >= `min_batch` s, at least 3 batches, the
/// case kept under ~`max_seconds`. Median and min per call.
fn time_it<T>(mut f: impl FnMut() -> T, timing: Timing) -> (T, Times) {
    let start = Instant::now();
    let result = black_box(f());
    let first = start.elapsed().as_secs_f64().max(1e-9);
    let (times, inner) = time_more(&mut f, first, timing);
    (result, summarize(first, times, inner))
}

fn time_more<T>(f: &mut impl FnMut() -> T, first: f64, timing: Timing) -> (Vec<f64>, usize) {
    let inner = ((timing.min_batch / first).ceil() as usize).clamp(1, 10_000_000);
    let budget = (timing.max_seconds / (first * inner as f64)).floor() as usize;
    let samples = timing.samples.min(budget).max(3);
    let mut times = Vec::with_capacity(samples);
    for _ in 0..samples {
        let t0 = Instant::now();
        for _ in 0..inner {
            black_box(f());
        }
        times.push(t0.elapsed().as_secs_f64() / inner as f64);
    }
    (times, inner)
}

fn summarize(first: f64, mut times: Vec<f64>, inner: usize) -> Times {
    times.sort_by(f64::total_cmp);
    let s = times.len();
    let median = if s % 2 == 1 {
        times[s / 2]
    } else {
        0.5 * (times[s / 2 - 1] + times[s / 2])
    };
    Times {
        first,
        median,
        min: times[0],
        samples: s,
        inner,
    }
}

/// Times one call of `f` (for sub-steps): the median of 3 calls.
fn time_small<T>(mut f: impl FnMut() -> T) -> f64 {
    let mut t: Vec<f64> = (0..3)
        .map(|_| {
            let t0 = Instant::now();
            black_box(f());
            t0.elapsed().as_secs_f64()
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[1]
}

// ------------------------------------------------------------------------------ memory

/// A field of /proc/self/status, in bytes.
fn status_bytes(field: &str) -> Option<u64> {
    let text = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = text.lines().find(|l| l.starts_with(field))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Resets the peak RSS (VmHWM) to the current RSS; false where the kernel does not allow it.
fn reset_peak() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

/// Runs `f` once between a peak reset and a read of the peak: (result, seconds, memory JSON).
fn measured_first_call<T>(
    f: impl FnOnce() -> T,
    output_bytes: impl Fn(&T) -> u64,
) -> (T, f64, Value) {
    let reset = reset_peak();
    let rss0 = status_bytes("VmRSS");
    let t0 = Instant::now();
    let result = black_box(f());
    let secs = t0.elapsed().as_secs_f64();
    let hwm = status_bytes("VmHWM");
    let rss1 = status_bytes("VmRSS");
    let out = output_bytes(&result);
    let mem = match (reset, rss0, hwm) {
        (true, Some(r0), Some(h)) => json!({
            "rss_before_bytes": r0,
            "peak_extra_bytes": h.saturating_sub(r0),
            "rss_after_extra_bytes": rss1.map(|r| r.saturating_sub(r0)),
            "output_bytes": out,
        }),
        _ => json!({"output_bytes": out, "error": "no /proc/self/clear_refs or status"}),
    };
    (result, secs, mem)
}

/// Starts rayon's pool (a tiny parallel evaluation) so that its threads are not counted in
/// the first measured call.
fn warm_pool() {
    let c = interpolate_curve_flat(1, &[0.0, 1.0, 0.5, 2.0], &InterpolationOptions::default())
        .expect("tiny curve");
    let ts = vec![0.5; 10_000];
    let mut out = vec![0.0; ts.len()];
    c.curve().eval_many_par(&ts, &mut out).expect("tiny eval");
}

// ------------------------------------------------------------------------------ curves

/// Bytes of a built curve: knots and control points (the parameters are the inner knots).
fn curve_bytes(c: &CurveInterpolation) -> u64 {
    8 * (c.curve().knots().len() + c.curve().control_flat().len()) as u64
}

fn not_a_knot(p: Parametrization) -> InterpolationOptions {
    InterpolationOptions::default()
        .with_end(EndCondition::NotAKnot)
        .with_parametrization(p)
}

/// Builds the curve of a case (`variant`), given the points (and, for `at`, parameters).
fn build_curve(variant: &str, points: &[f64], x: &[f64]) -> geomkit::Result<CurveInterpolation> {
    match variant {
        "uniform" => interpolate_curve_flat(3, points, &not_a_knot(Parametrization::Uniform)),
        "chord" => interpolate_curve_flat(3, points, &not_a_knot(Parametrization::ChordLength)),
        "at" => interpolate_curve_at(3, points, x, &EndCondition::NotAKnot),
        "tiled" => interpolate_curve_tiled(
            3,
            points,
            &not_a_knot(Parametrization::Uniform),
            &TileOptions::default(),
        ),
        other => panic!("unknown curve variant {other:?}"),
    }
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// max_i |a_i - b_i| over row-major points (max over coordinates).
fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}

fn rows(flat: &[f64], dim: usize) -> Vec<Vec<f64>> {
    flat.chunks_exact(dim).map(<[f64]>::to_vec).collect()
}

/// K check parameters of a curve: the domain ends and midpoints between data parameters at
/// evenly spaced indices.
fn check_params(t: &[f64], k: usize) -> Vec<f64> {
    let n = t.len();
    let mut out = vec![t[0], t[n - 1]];
    let k = k.min(n - 1);
    for j in 0..k {
        let i = j * (n - 1) / k;
        out.push(0.5 * (t[i] + t[i + 1]));
    }
    out
}

/// 16 input rows at evenly spaced indices (the Python side checks that its copy of the
/// fixture is bit for bit the same).
fn input_sample(flat: &[f64], dim: usize) -> Value {
    let n = flat.len() / dim;
    let idx: Vec<usize> = (0..16).map(|k| k * (n - 1) / 15).collect();
    json!({
        "index": idx,
        "values": idx.iter().map(|&i| flat[i * dim..(i + 1) * dim].to_vec()).collect::<Vec<_>>(),
    })
}

/// Seconds to fill `len` numbers (already allocated and touched) from `threads` threads: the
/// memory-bandwidth floor of writing an output of that size.
fn fill_floor(len: usize, threads: usize) -> f64 {
    let mut buf = vec![1.0f64; len];
    let chunk = len.div_ceil(threads.max(1)).max(1);
    time_small(|| {
        std::thread::scope(|scope| {
            for c in buf.chunks_mut(chunk) {
                scope.spawn(move || c.fill(0.5));
            }
        });
    })
}

/// The `into` variant of `curve_build`: a [`CurveInterpolator`] for N uniform parameters,
/// set up once (timed apart), then `solve_into` the caller's control buffer, reused across
/// the timed calls (the first call, measured for memory, writes a fresh buffer).
fn curve_solve_into(case: &Case, timing: Timing) -> Value {
    let n = case.n;
    let points = helix_points(n, case.seed);
    warm_pool();
    let t0 = Instant::now();
    let solver = match CurveInterpolator::uniform(n, &EndCondition::NotAKnot) {
        Ok(s) => s,
        Err(e) => return json!({"ok": false, "error": e.to_string()}),
    };
    let setup_s = t0.elapsed().as_secs_f64();
    let mut control = vec![0.0; solver.n_control() * 3];
    let (first, first_s, memory) = measured_first_call(
        || solver.solve_into(&points, 3, &mut control),
        |_| 8 * (solver.n_control() * 3) as u64,
    );
    if let Err(e) = first {
        return json!({"ok": false, "error": e.to_string()});
    }
    let (times, inner) = time_more(
        &mut || {
            solver
                .solve_into(&points, 3, &mut control)
                .expect("same input")
        },
        first_s,
        timing,
    );
    let times = summarize(first_s, times, inner);
    let curve = BsplineCurve::from_flat(3, solver.knots().to_vec(), 3, control).expect("finite");
    let mut report = curve_report(&curve, solver.parameters(), &points, case.check);
    report["time"] = times.json(n);
    report["memory"] = memory;
    report["setup_s"] = json!(setup_s);
    report
}

/// What every curve build reports besides its times: sizes, the residual at all data
/// points, the input sample and the curve at check parameters (for the agreement).
fn curve_report(curve: &BsplineCurve, parameters: &[f64], points: &[f64], check: usize) -> Value {
    let mut at_data = vec![0.0; points.len()];
    curve
        .eval_many_par(parameters, &mut at_data)
        .expect("finite parameters");
    let scale = max_abs(points);
    let residual = max_diff(&at_data, points) / scale;
    let cp = check_params(parameters, check);
    let mut cv = vec![0.0; cp.len() * 3];
    curve.eval_many_par(&cp, &mut cv).expect("finite");
    json!({
        "ok": true,
        "n": parameters.len(),
        "n_control": curve.n_control(),
        "uniform_knots": curve.is_uniform(),
        "max_abs_p": scale,
        "input_sample": input_sample(points, 3),
        "residual_rel": residual,
        "check_params": cp,
        "check_values": rows(&cv, 3),
    })
}

/// `spline_build`: [`make_interp_spline`] of degree k (SciPy's form, not-a-knot) through
/// the helix points at their chord-length parameters (SciPy's `make_interp_spline(x, y, k)`);
/// variant "tiled": `make_interp_spline_tiled` with the default tiles. Reports the build time, its peak memory, and the residual at all N points.
fn spline_build(case: &Case, timing: Timing) -> Value {
    let (n, k) = (case.n, case.degree.unwrap_or(3));
    let points = helix_points(n, case.seed);
    let x = parameters(&points, 3, Parametrization::ChordLength, false).expect("distinct points");
    let options = SplineOptions::new(k);
    warm_pool();
    // Variant "tiled": the tiles of `make_interp_spline_tiled` (65 536 coefficients each).
    let tiles = geomkit::bspline::TileOptions::default();
    let none = geomkit::progress::Progress::none();
    let build = || match case.variant.as_str() {
        "tiled" => {
            geomkit::bspline::make_interp_spline_tiled(&x, &points, 3, &options, &tiles, &none)
        }
        _ => make_interp_spline(&x, &points, 3, &options),
    };
    let bytes = |r: &geomkit::Result<BsplineCurve>| {
        r.as_ref()
            .map_or(0, |c| 8 * (c.knots().len() + c.control_flat().len()) as u64)
    };
    let (first, first_s, memory) = measured_first_call(build, bytes);
    let curve = match first {
        Ok(c) => c,
        Err(e) => return json!({"ok": false, "error": e.to_string()}),
    };
    let (times, inner) = time_more(&mut || build().expect("same input"), first_s, timing);
    let times = summarize(first_s, times, inner);
    let mut at = vec![0.0; n * 3];
    curve.eval_many_par(&x, &mut at).expect("finite parameters");
    let residual = max_diff(&at, &points) / max_abs(&points);
    json!({"ok": true, "n": n, "degree": k, "time": times.json(n), "memory": memory,
           "residual_rel": residual})
}

fn curve_build(case: &Case, timing: Timing) -> Value {
    if case.variant == "into" {
        return curve_solve_into(case, timing);
    }
    let n = case.n;
    let points = helix_points(n, case.seed);
    let x = if case.variant == "at" {
        parameters(&points, 3, Parametrization::ChordLength, false).expect("distinct points")
    } else {
        Vec::new()
    };
    warm_pool();
    let (first_fit, first_s, memory) = measured_first_call(
        || build_curve(&case.variant, &points, &x),
        |r| r.as_ref().map_or(0, curve_bytes),
    );
    let fit = match first_fit {
        Ok(f) => f,
        Err(e) => return json!({"ok": false, "error": e.to_string()}),
    };
    let (times, inner) = time_more(
        &mut || build_curve(&case.variant, &points, &x).expect("same input"),
        first_s,
        timing,
    );
    let times = summarize(first_s, times, inner);
    if case.only_time {
        return json!({"ok": true, "n": n, "time": times.json(n), "memory": memory});
    }
    let mut report = curve_report(fit.curve(), fit.parameters(), &points, case.check);
    // Sub-steps (profiling hints): parameters, the curve constructor (validation and the
    // uniform-knot test), a copy of the result's size (the memory-bandwidth floor).
    let param_kind = if case.variant == "chord" || case.variant == "at" {
        Parametrization::ChordLength
    } else {
        Parametrization::Uniform
    };
    let substeps = json!({
        "parameters_s": time_small(|| parameters(&points, 3, param_kind, false)),
        "clone_knots_control_s": time_small(|| (fit.curve().knots().to_vec(), fit.curve().control_flat().to_vec())),
        "clone_and_from_flat_s": time_small(|| BsplineCurve::from_flat(
            3, fit.curve().knots().to_vec(), 3, fit.curve().control_flat().to_vec())),
        "eval_many_par_at_data_s": time_small(|| {
            let mut o = vec![0.0; points.len()];
            fit.curve().eval_many_par(fit.parameters(), &mut o).map(|()| o)
        }),
        "copy_points_s": time_small(|| points.to_vec()),
    });
    report["time"] = times.json(n);
    report["memory"] = memory;
    report["substeps"] = substeps;
    report
}

fn curve_eval(case: &Case, timing: Timing) -> Value {
    let points = helix_points(case.n, case.seed);
    let variant = match case.variant.as_str() {
        "uniform" | "chord" => case.variant.as_str(),
        other => return json!({"ok": false, "error": format!("eval variant {other:?}")}),
    };
    let fit = match build_curve(variant, &points, &[]) {
        Ok(f) => f,
        Err(e) => return json!({"ok": false, "error": e.to_string()}),
    };
    let curve = fit.curve();
    let scale = max_abs(&points);
    let (a, b) = curve.domain();
    warm_pool();
    let (pp, pp_times) = match time_it(|| curve.to_piecewise(), timing) {
        (Ok(pp), t) => (pp, t),
        (Err(e), _) => return json!({"ok": false, "error": e.to_string()}),
    };
    let mut results = Vec::new();
    for k in &case.kinds {
        let m = k.count;
        let ts = match k.params.as_str() {
            "uniform" => linspace(a, b, m),
            "sorted" => {
                let mut t = random_params(m, a, b, k.param_seed);
                t.sort_by(f64::total_cmp);
                t
            }
            "unsorted" => random_params(m, a, b, k.param_seed),
            other => {
                results.push(json!({"ok": false, "error": format!("params {other:?}")}));
                continue;
            }
        };
        let mut out = vec![0.0; m * 3];
        let seq_options = BatchOptions::sequential().with_bit_exact(true);
        let (r, times) = match k.kind.as_str() {
            "fd" if k.params == "uniform" => {
                time_it(|| curve.sample_uniform_fd(m, &mut out).map(|_| ()), timing)
            }
            "par" => time_it(|| curve.eval_many_par(&ts, &mut out), timing),
            "par_new" => {
                // Into a new buffer each call, as a Python call returns a new array (and
                // with huge pages advised, as NumPy's large arrays are).
                let timed = time_it(
                    || {
                        let mut fresh = geomkit::mem::zeros(m * 3);
                        curve
                            .eval_many_par(&ts, &mut fresh)
                            .map(|()| drop(black_box(fresh)))
                    },
                    timing,
                );
                (
                    timed.0.and_then(|()| curve.eval_many_par(&ts, &mut out)),
                    timed.1,
                )
            }
            "nu" => time_it(
                || curve.eval_nu_many(&ts, 0, Extrapolate::Extend, &mut out),
                timing,
            ),
            "seq" => time_it(|| curve.eval_batch(&ts, &mut out, &seq_options), timing),
            "pp" => time_it(|| pp.eval_many_par(&ts, &mut out), timing),
            other => {
                results.push(json!({"ok": false, "error": format!("kind {other:?} with params {:?}", k.params)}));
                continue;
            }
        };
        if let Err(e) = r {
            results.push(json!({"ok": false, "error": e.to_string()}));
            continue;
        }
        let step = (m / case.check.max(1)).max(1);
        let idx: Vec<usize> = (0..m).step_by(step).chain([m - 1]).collect();
        let cp: Vec<f64> = idx.iter().map(|&i| ts[i]).collect();
        let cv: Vec<f64> = idx
            .iter()
            .flat_map(|&i| out[3 * i..3 * i + 3].to_vec())
            .collect();
        // Direct evaluation at the same parameters, point by point (span by span de Boor;
        // for fd: the drift of the differences).
        let mut direct = vec![0.0; cv.len()];
        for (t, o) in cp.iter().zip(direct.chunks_exact_mut(3)) {
            curve.eval_into(*t, o);
        }
        let fd_report = if k.kind == "fd" {
            let rep = curve.sample_uniform_fd(m, &mut out).expect("as timed");
            json!({"max_steps": rep.max_steps, "bound_rel": rep.bound / scale})
        } else {
            Value::Null
        };
        results.push(json!({
            "ok": true,
            "kind": k.kind,
            "params": k.params,
            "count": m,
            "time": times.json(m),
            "check_params": cp,
            "check_values": rows(&cv, 3),
            "vs_direct_rel": max_diff(&cv, &direct) / scale,
            "fd_report": fd_report,
        }));
    }
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let biggest = case.kinds.iter().map(|k| k.count).max().unwrap_or(0);
    json!({
        "ok": true,
        "n": case.n,
        "input_sample": input_sample(&points, 3),
        "fill_floor": {"count": biggest, "threads": threads, "seconds": fill_floor(3 * biggest, threads)},
        "uniform_knots": curve.is_uniform(),
        "domain": [a, b],
        "max_abs_p": scale,
        "piecewise_build": pp_times.json(pp.n_pieces()),
        "kinds": results,
    })
}

// ------------------------------------------------------------------------------ surfaces

fn surface_bytes(s: &BsplineSurface) -> u64 {
    let (ku, kv) = s.knots();
    8 * (ku.len() + kv.len() + s.control_flat().len()) as u64
}

/// Evaluates at scattered points with `eval_into`, one point after the other.
fn eval_scattered(s: &BsplineSurface, u: &[f64], v: &[f64], out: &mut [f64]) {
    for ((a, b), o) in u.iter().zip(v).zip(out.iter_mut()) {
        s.eval_into(*a, *b, std::slice::from_mut(o));
    }
}

fn surface(case: &Case, timing: Timing) -> Value {
    let (r, c) = (case.rows, case.cols);
    let z = height_grid(r, c, case.seed);
    let (dx, dy) = (1.0 / (r - 1) as f64, 1.0 / (c - 1) as f64);
    let xs: Vec<f64> = (0..r).map(|i| i as f64 * dx).collect();
    let ys: Vec<f64> = (0..c).map(|j| j as f64 * dy).collect();
    let build = || match case.variant.as_str() {
        "heights" => interpolate_heights(&z, r, c, (0.0, 0.0), (dx, dy), &EndCondition::NotAKnot),
        "heights_at" => interpolate_heights_at(&z, &xs, &ys, &EndCondition::NotAKnot),
        other => panic!("unknown surface variant {other:?}"),
    };
    warm_pool();
    let (first, first_s, memory) =
        measured_first_call(build, |s| s.as_ref().map_or(0, surface_bytes));
    let s = match first {
        Ok(s) => s,
        Err(e) => return json!({"ok": false, "error": e.to_string()}),
    };
    let (times, inner) = time_more(&mut || build().expect("same input"), first_s, timing);
    let build_times = summarize(first_s, times, inner);
    if case.only_time {
        return json!({"ok": true, "time": build_times.json(r * c), "memory": memory});
    }
    let scale = max_abs(&z);
    // Residual at every node.
    let mut at_nodes = vec![0.0; r * c];
    s.eval_grid(&xs, &ys, &mut at_nodes).expect("finite");
    let residual = max_diff(&at_nodes, &z) / scale;
    let worst = at_nodes
        .iter()
        .zip(&z)
        .map(|(a, b)| (a - b).abs())
        .enumerate()
        .fold((0, 0.0f64), |m, (k, e)| if e > m.1 { (k, e) } else { m })
        .0;
    drop(at_nodes);
    let ((u0, u1), (v0, v1)) = s.domain();
    // Grid evaluation.
    let g = case.grid_eval;
    let (gu, gv) = (linspace(u0, u1, g), linspace(v0, v1, g));
    let mut grid_out = vec![0.0; g * g];
    let (_, grid_times) = time_it(|| s.eval_grid(&gu, &gv, &mut grid_out), timing);
    let sub = (g / 64).max(1);
    let sub_idx: Vec<usize> = (0..g).step_by(sub).collect();
    let grid_check = json!({
        "u": sub_idx.iter().map(|&i| gu[i]).collect::<Vec<_>>(),
        "v": sub_idx.iter().map(|&j| gv[j]).collect::<Vec<_>>(),
        "values": sub_idx.iter().map(|&i| sub_idx.iter().map(|&j| grid_out[i * g + j]).collect::<Vec<_>>()).collect::<Vec<_>>(),
    });
    drop(grid_out);
    // Scattered evaluation.
    let m = case.scattered;
    let su = random_params(m, u0, u1, case.param_seed);
    let sv = random_params(m, v0, v1, case.param_seed + 1);
    let mut sc_out = vec![0.0; m];
    let (_, seq_times) = time_it(|| eval_scattered(&s, &su, &sv, &mut sc_out), timing);
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let (_, thr_times) = time_it(|| s.eval_many_par(&su, &sv, &mut sc_out).unwrap(), timing);
    let k = case.check.min(m);
    json!({
        "ok": true,
        "rows": r,
        "cols": c,
        "net": s.net_size(),
        "time": build_times.json(r * c),
        "memory": memory,
        "max_abs_z": scale,
        "input_sample": input_sample(&z, 1),
        "residual_rel": residual,
        "residual_at": [worst / c, worst % c],
        "grid_eval": {"g": g, "time": grid_times.json(g * g),
            "fill_floor_s": fill_floor(g * g, threads)},
        "scattered_seq": {"count": m, "time": seq_times.json(m)},
        "scattered_threads": {"count": m, "threads": threads, "time": thr_times.json(m)},
        "check_scattered": {"u": &su[..k], "v": &sv[..k], "values": &sc_out[..k]},
        "check_grid": grid_check,
    })
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let arg = std::env::args()
        .nth(1)
        .ok_or("usage: bspline-compare CASE-JSON (or @FILE)")?;
    let text = match arg.strip_prefix('@') {
        Some(path) => std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?,
        None => arg,
    };
    let case: Case = serde_json::from_str(&text)?;
    let timing = Timing {
        samples: case.samples.unwrap_or(15).max(1),
        min_batch: case.min_batch_seconds.unwrap_or(0.02),
        max_seconds: case.max_seconds.unwrap_or(10.0),
    };
    let mut result = match case.op.as_str() {
        "curve_build" => curve_build(&case, timing),
        "spline_build" => spline_build(&case, timing),
        "curve_eval" => curve_eval(&case, timing),
        "surface" => surface(&case, timing),
        other => json!({"ok": false, "error": format!("unknown op {other:?}")}),
    };
    result["op"] = json!(case.op);
    result["variant"] = json!(case.variant);
    result["geomkit_version"] = json!(env!("CARGO_PKG_VERSION"));
    result["threads"] = json!(std::thread::available_parallelism().map_or(1, |n| n.get()));
    serde_json::to_writer(std::io::stdout().lock(), &result)?;
    println!();
    Ok(())
}
