"""geomkit.progress(): bars for long evaluations only when asked, with the same bits."""

from __future__ import annotations

import sys
import threading
from typing import Any

import numpy as np
import pytest

import geomkit


class Recorder:
    """A bar factory that records what the evaluations report."""

    def __init__(self) -> None:
        self.bars: list[dict[str, Any]] = []

    def __call__(self, total: int, desc: str, unit: str) -> Recorder:
        self.bars.append(dict(total=total, desc=desc, unit=unit, updates=[], closed=False))
        return self

    def update(self, k: int) -> None:
        self.bars[-1]["updates"].append(k)

    def close(self) -> None:
        self.bars[-1]["closed"] = True


def check_bar(rec: Recorder, total: int, desc: str) -> None:
    assert len(rec.bars) == 1
    bar = rec.bars[0]
    assert (bar["total"], bar["desc"], bar["unit"], bar["closed"]) == (total, desc, "pt", True)
    assert sum(bar["updates"]) == total and len(bar["updates"]) > 1


RNG = np.random.default_rng(23)


def same_with_bar(call: Any, total: int, desc: str) -> None:
    plain = call()
    rec = Recorder()
    with geomkit.progress(rec, min_points=1):
        shown = call()
    check_bar(rec, total, desc)
    for a, b in zip(plain if isinstance(plain, tuple) else (plain,),
                    shown if isinstance(shown, tuple) else (shown,)):
        assert np.array_equal(a, b)


def test_bspline_values_and_derivatives() -> None:
    x = np.linspace(0, 10, 50)
    s = geomkit.make_interp_spline(x, np.c_[np.sin(x), np.cos(x)], k=5)
    t = np.sort(RNG.uniform(-1, 11, 300_000))
    same_with_bar(lambda: s(t), 300_000, "BSpline")
    same_with_bar(lambda: s(t, nu=2), 300_000, "BSpline")


def test_rect_bivariate_spline_grid_and_points() -> None:
    x, y = np.linspace(0, 1, 30), np.linspace(0, 2, 40)
    s = geomkit.RectBivariateSpline(x, y, np.add.outer(np.sin(5 * x), np.cos(3 * y)))
    xs, ys = np.linspace(0, 1, 700), np.linspace(0, 2, 300)
    same_with_bar(lambda: s(xs, ys), 700 * 300, "RectBivariateSpline")
    px, py = RNG.uniform(0, 1, 200_000), RNG.uniform(0, 2, 200_000)
    same_with_bar(lambda: s.ev(px, py), 200_000, "RectBivariateSpline")


def test_parametric_surface_composite_formula_and_point_model() -> None:
    u, v = np.meshgrid(np.arange(5.0), np.arange(6.0), indexing="ij")
    s = geomkit.make_interp_surface(np.stack([u, v, np.sin(u + v)], axis=-1))
    same_with_bar(lambda: s(np.linspace(0, 4, 500), np.linspace(0, 5, 400)), 200_000,
                  "BSplineSurface")
    f = geomkit.body("cube").evaluator()
    uu, vv = RNG.uniform(0, 4, 250_000), RNG.uniform(0, 3, 250_000)
    same_with_bar(lambda: f(uu, vv), 250_000, "Evaluator")
    m = geomkit.PointModel.fit({"a": [0.0, 0.5, 1.0], "b": [0.0, 1.0]},
                               np.array([[1.0, 2.0], [3.0, 5.0], [4.0, 4.0]]))
    xs = RNG.uniform(0, 1, (150_000, 2))
    same_with_bar(lambda: m.eval(xs), 150_000, "PointModel")


def test_no_bar_outside_the_block_below_the_threshold_or_in_other_threads() -> None:
    s = geomkit.make_interp_spline(np.arange(10.0), np.arange(10.0) ** 2)
    t = np.linspace(0, 9, 200_000)
    rec = Recorder()
    s(t)
    with geomkit.progress(rec, min_points=300_000):
        s(t)
        other = threading.Thread(target=lambda: s(np.linspace(0, 9, 400_000)))
        other.start()
        other.join()
    with geomkit.progress(rec, min_points=1):
        s(t[:1])
    assert rec.bars == []


def test_tqdm_when_installed_else_a_line_on_stderr(capsys: pytest.CaptureFixture[str],
                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    pytest.importorskip("tqdm")
    s = geomkit.make_interp_spline(np.arange(10.0), np.arange(10.0) ** 2)
    t = np.linspace(0, 9, 300_000)
    with geomkit.progress(min_points=1):
        s(t)
    err = capsys.readouterr().err
    assert "BSpline" in err and "300k/300k" in err
    monkeypatch.setitem(sys.modules, "tqdm.auto", None)  # import fails: the text bar
    with geomkit.progress(min_points=1):
        s(t)
    err = capsys.readouterr().err
    assert "BSpline: 100% of 300,000 points" in err


def test_bad_arguments() -> None:
    with pytest.raises(ValueError, match="min_points"):
        with geomkit.progress(min_points=-1):
            pass
    with pytest.raises(TypeError, match="callable"):
        with geomkit.progress("tqdm"):  # type: ignore[arg-type]
            pass


# --- builds and meshes (the library's progress hook) -----------------------------------


class BuildRecorder(Recorder):
    """A fake tqdm for builds: records totals as the core changes them."""

    total = 0

    def __call__(self, total: int, desc: str, unit: str) -> BuildRecorder:
        super().__call__(total, desc, unit)
        self.total = total
        return self


def check_build(rec: BuildRecorder, desc: str) -> None:
    assert len(rec.bars) == 1, rec.bars
    bar = rec.bars[0]
    assert bar["desc"] == desc and bar["closed"]
    assert all(k > 0 for k in bar["updates"])
    # The updates (increments) reach the job's final total, whatever it was at the start.
    assert sum(bar["updates"]) == rec.total > 0


def test_make_interp_spline_build_reports_and_gives_the_same_bits() -> None:
    x = np.cumsum(RNG.uniform(0.5, 1.5, 300_000))
    y = np.c_[np.sin(x * 1e-3), np.cos(x * 2e-3)]
    for k in (2, 3, 5):
        plain = geomkit.make_interp_spline(x, y, k=k)
        rec = BuildRecorder()
        with geomkit.progress(rec, min_points=1):
            shown = geomkit.make_interp_spline(x, y, k=k)
        check_build(rec, "make_interp_spline")
        assert np.array_equal(plain.t, shown.t) and np.array_equal(plain.c, shown.c)
    # Below the threshold: no bar.
    rec = BuildRecorder()
    with geomkit.progress(rec):
        geomkit.make_interp_spline(x[:100], y[:100], k=3)
    assert rec.bars == []


def test_surface_builds_and_meshes_report() -> None:
    gx, gy = np.linspace(0, 3, 400), np.linspace(0, 2, 300)
    z = np.sin(gx)[:, None] * np.cos(gy)[None, :]
    plain = geomkit.RectBivariateSpline(gx, gy, z, kx=3, ky=5)
    rec = BuildRecorder()
    with geomkit.progress(rec, min_points=1):
        shown = geomkit.RectBivariateSpline(gx, gy, z, kx=3, ky=5)
    check_build(rec, "RectBivariateSpline")
    assert all(np.array_equal(a, b) for a, b in zip(plain.tck, shown.tck))
    grid = np.stack([*np.meshgrid(gx, gy, indexing="ij"), z], axis=-1)
    plain_s = geomkit.make_interp_surface(grid)
    rec = BuildRecorder()
    with geomkit.progress(rec, min_points=1):
        shown_s = geomkit.make_interp_surface(grid)
    check_build(rec, "make_interp_surface")
    uv = np.linspace(0, 1, 7)
    assert np.array_equal(plain_s(uv, uv), shown_s(uv, uv))
    # A mesh inside a block reports its refinement rounds; the same mesh.
    rec = BuildRecorder()
    m0 = plain_s.mesh()
    with geomkit.progress(rec):
        m1 = plain_s.mesh()
    check_build(rec, "mesh")
    assert np.array_equal(m0.vertices, m1.vertices) and np.array_equal(m0.faces, m1.faces)


def test_tiled_builds_report_and_give_the_same_bits() -> None:
    """make_interp_spline, make_splprep and make_interp_surface with tile=T report per tile
    (the library's hook) inside a block, with the same bits as without it."""
    x = np.cumsum(RNG.uniform(0.5, 1.5, 200_000))
    y = np.c_[np.sin(x * 1e-3), np.cos(x * 2e-3)]
    for k in (3, 4, 5):
        plain = geomkit.make_interp_spline(x, y, k=k, tile=20_000)
        rec = BuildRecorder()
        with geomkit.progress(rec, min_points=1):
            shown = geomkit.make_interp_spline(x, y, k=k, tile=20_000)
        check_build(rec, "make_interp_spline")
        assert np.array_equal(plain.t, shown.t) and np.array_equal(plain.c, shown.c)
    plain_p, _ = geomkit.make_splprep(y.T, tile=20_000)
    rec = BuildRecorder()
    with geomkit.progress(rec, min_points=1):
        shown_p, _ = geomkit.make_splprep(y.T, tile=20_000)
    check_build(rec, "make_interp_spline")
    assert np.array_equal(plain_p.c, shown_p.c)
    gx, gy = np.linspace(0, 3, 400), np.linspace(0, 2, 300)
    grid = np.stack([*np.meshgrid(gx, gy, indexing="ij"),
                     np.sin(gx)[:, None] * np.cos(gy)[None, :]], axis=-1)
    plain_s = geomkit.make_interp_surface(grid, tile=64)
    rec = BuildRecorder()
    with geomkit.progress(rec, min_points=1):
        shown_s = geomkit.make_interp_surface(grid, tile=64)
    check_build(rec, "make_interp_surface")
    assert np.array_equal(plain_s.net, shown_s.net)


def test_an_interrupted_tiled_build_raises_keyboard_interrupt() -> None:
    x = np.arange(2_000_000, dtype=float)
    with pytest.raises(KeyboardInterrupt):
        with geomkit.progress(Interrupting(), min_points=1):
            geomkit.make_interp_spline(x, np.sin(x * 1e-4), k=5, tile=10_000)
    g = np.arange(1500.0)
    grid = np.stack([*np.meshgrid(g, g, indexing="ij"), np.sin(g)[:, None] * g], axis=-1)
    with pytest.raises(KeyboardInterrupt):
        with geomkit.progress(Interrupting(), min_points=1):
            geomkit.make_interp_surface(grid, tile=128)


class Interrupting(BuildRecorder):
    """A bar whose first update raises KeyboardInterrupt, as Ctrl-C would during a build."""

    def update(self, k: int) -> None:
        raise KeyboardInterrupt


def test_an_interrupted_build_raises_keyboard_interrupt_promptly() -> None:
    x = np.arange(2_000_000, dtype=float)
    y = np.sin(x * 1e-4)
    with pytest.raises(KeyboardInterrupt):
        with geomkit.progress(Interrupting(), min_points=1):
            geomkit.make_interp_spline(x, y, k=5)
    # A real SIGINT (Python's handler runs on the main thread while the build runs).
    timer = threading.Timer(0.02, lambda: __import__("_thread").interrupt_main())
    rec = BuildRecorder()
    with pytest.raises(KeyboardInterrupt):
        with geomkit.progress(rec, min_points=1):
            timer.start()
            for _ in range(50):
                geomkit.make_interp_spline(x, y, k=7)
    timer.cancel()


# --- curve meshes and the evaluations of Bézier and point-calculus models --------------


def test_curve_meshes_report_and_give_the_same_polyline(tmp_path: Any) -> None:
    # A B-spline of ~3000 spans: the mesher's windows are its breaks.
    x = np.linspace(0.0, 60.0, 3000)
    curve = geomkit.make_interp_spline(x, np.c_[np.cos(x), np.sin(x), 0.01 * x])
    plain = curve.mesh(tolerance=1e-6)
    rec = BuildRecorder()
    with geomkit.progress(rec):
        shown = curve.mesh(tolerance=1e-6)
    check_build(rec, "mesh")
    # One unit per starting window: the curve's 2997 spans cut by the 16 equal steps.
    assert 2997 <= rec.total <= 2997 + 16
    assert np.array_equal(plain.points, shown.points)
    assert np.array_equal(plain.parameters, shown.parameters)
    # Writing meshes it the same way (the file is the same bytes).
    curve.write(tmp_path / "a.obj", tolerance=1e-6)
    rec = BuildRecorder()
    with geomkit.progress(rec):
        curve.write(tmp_path / "b.obj", tolerance=1e-6)
    check_build(rec, "mesh")
    assert (tmp_path / "a.obj").read_bytes() == (tmp_path / "b.obj").read_bytes()


def test_an_interrupted_curve_mesh_raises_keyboard_interrupt() -> None:
    x = np.linspace(0.0, 600.0, 30_000)
    curve = geomkit.make_interp_spline(x, np.c_[np.cos(x), np.sin(x)])
    with pytest.raises(KeyboardInterrupt):
        with geomkit.progress(Interrupting()):
            curve.mesh(tolerance=1e-7)


def test_bezier_evaluations_show_bars_with_the_same_bits() -> None:
    c = geomkit.BezierCurve([[0, 0, 0], [1, 3, 1], [3, -2, 2], [4, 1, 0], [6, 0, 1]])
    t = RNG.uniform(0, 1, 300_000)
    same_with_bar(lambda: c(t), 300_000, "BezierCurve")
    same_with_bar(lambda: c(t, nu=2), 300_000, "BezierCurve")
    r = geomkit.BezierCurve([[1, 0], [1, 1], [0, 1]], weights=[1, 2 ** -0.5, 1])
    same_with_bar(lambda: r(t), 300_000, "BezierCurve")
    same_with_bar(lambda: r(t, nu=1), 300_000, "BezierCurve")
    net = RNG.uniform(-1, 1, (4, 5, 3))
    s = geomkit.BezierSurface(net)
    u, v = np.linspace(0, 1, 700), np.linspace(0, 1, 300)
    same_with_bar(lambda: s(u, v), 700 * 300, "BezierSurface")
    same_with_bar(lambda: s(u, v, du=1, dv=1), 700 * 300, "BezierSurface")
    same_with_bar(lambda: s.normal(u, v), 700 * 300, "BezierSurface")
    pu, pv = RNG.uniform(0, 1, 200_000), RNG.uniform(0, 1, 200_000)
    same_with_bar(lambda: s(pu, pv, grid=False), 200_000, "BezierSurface")
    w = RNG.uniform(0.5, 2.0, (4, 5))
    rs = geomkit.BezierSurface(net, weights=w)
    same_with_bar(lambda: rs(u, v, du=1), 700 * 300, "BezierSurface")
    same_with_bar(lambda: rs.normal(pu, pv, grid=False), 200_000, "BezierSurface")


def test_point_curve_and_surface_evaluations_show_bars_with_the_same_bits() -> None:
    pc = geomkit.point_curve([[0.0, 1.0], [1.0, 3.0], [2.0, 2.0], [3.0, 5.0]])
    t = RNG.uniform(0, 3, 300_000)
    same_with_bar(lambda: pc(t), 300_000, "PointCurve")
    ps = geomkit.point_surface(RNG.uniform(0, 1, (3, 4)))
    u, v = RNG.uniform(0, 2, 200_000), RNG.uniform(0, 3, 200_000)
    same_with_bar(lambda: ps(u, v), 200_000, "PointSurface")
    same_with_bar(lambda: ps.grid(np.linspace(0, 2, 600), np.linspace(0, 3, 400)), 600 * 400,
                  "PointSurface")


def test_a_refused_point_in_a_later_step_is_named_as_without_a_bar() -> None:
    c = geomkit.BezierCurve([[0.0, 0.0], [1.0, 2.0], [2.0, 0.0]])
    t = np.linspace(0, 1, 300_000)
    t[250_000] = np.nan
    with pytest.raises(ValueError) as plain:
        c(t)
    rec = Recorder()
    with pytest.raises(ValueError) as shown:
        with geomkit.progress(rec, min_points=1):
            c(t)
    assert str(shown.value) == str(plain.value) and "250000" in str(plain.value)
    assert rec.bars and rec.bars[0]["closed"]


def test_bezier_degree_changes_report_with_the_same_bits() -> None:
    pts = np.c_[np.arange(600.0), np.sin(np.arange(600.0) * 0.05), np.arange(600) % 11]
    c = geomkit.BezierCurve(pts)
    w = geomkit.BezierCurve(pts[:300], weights=1.0 + 0.5 * (np.arange(300) % 3))
    small = geomkit.BezierCurve(pts[:20]).elevate(60)
    u, v = np.meshgrid(np.arange(60.0), np.arange(50.0), indexing="ij")
    net = np.stack([u, v, (u + v) % 13.0], axis=-1)
    s = geomkit.BezierSurface(net)
    calls = [
        (lambda: c.elevate(1500), lambda r: r.points),
        (lambda: c.change_degree(1400), lambda r: r.points),
        (lambda: w.elevate(900), lambda r: r.weights),
        (lambda: small.reduce(19), lambda r: r.points),
        (lambda: s.elevate((120, 90)), lambda r: r.net),
        (lambda: s.change_degree((100, 80)), lambda r: r.net),
    ]
    for call, arrays in calls:
        plain = call()
        rec = BuildRecorder()
        with geomkit.progress(rec, min_points=1):
            shown = call()
        check_build(rec, "degree change")
        assert np.array_equal(arrays(plain), arrays(shown))
        assert plain.degree == shown.degree
    # The exact reduction of an elevated curve gives its points back (the reference).
    assert np.allclose(small.reduce(19).points, pts[:20], rtol=0, atol=1e-9)
    # Small changes stay below the default threshold: no bar.
    rec = BuildRecorder()
    with geomkit.progress(rec):
        geomkit.BezierCurve(pts[:10]).elevate(20)
    assert rec.bars == []
    # Ctrl-C from the bar: KeyboardInterrupt, no curve.
    with pytest.raises(KeyboardInterrupt):
        with geomkit.progress(Interrupting(), min_points=1):
            c.elevate(3000)
    with pytest.raises(KeyboardInterrupt):
        with geomkit.progress(Interrupting(), min_points=1):
            s.elevate((300, 200))


def test_ctrl_c_between_the_steps_of_an_evaluation() -> None:
    c = geomkit.BezierCurve([[0.0, 0.0], [1.0, 2.0], [2.0, 0.0]])
    s = geomkit.make_interp_spline(np.arange(10.0), np.arange(10.0) ** 2)
    t = np.linspace(0, 1, 300_000)
    for call in (lambda: c(t), lambda: s(9 * t)):
        with pytest.raises(KeyboardInterrupt):
            with geomkit.progress(Interrupting(), min_points=1):
                call()
