"""STEP from Python (issue 26): `Drawable.save("x.step")` / `to_step()`, `geomkit.load` and
`geomkit.read_step` of .step files. References: the objects' own arrays (a round trip gives
the same control points, weights and knots bit for bit), a structural Part 21 check written
here (every instance defined once, every reference defined), files written by OpenCASCADE
(the Rust tests' fixtures, made by bench/compat_step.sh), and the CLI's `geomkit export`."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import numpy as np
import pytest

import geomkit

ROOT = Path(__file__).resolve().parents[2]
CLI = ROOT / "target" / "release" / "geomkit"
FIXTURES = ROOT / "crates" / "geomkit-model" / "tests" / "fixtures" / "step"
H = np.sqrt(0.5)


def part21(text: str) -> dict[int, str]:
    """The instances of an ISO 10303-21 file ({number: record}), checked: header and trailer
    present, every instance defined once, every reference to a defined instance."""
    assert text.startswith("ISO-10303-21;") and text.rstrip().endswith("END-ISO-10303-21;")
    data = text[text.index("DATA;") + 5:text.index("ENDSEC;", text.index("DATA;"))]
    instances: dict[int, str] = {}
    for m in re.finditer(r"#(\d+)\s*=\s*(.*?);\s*(?=#\d+\s*=|$)", data, re.S):
        n = int(m.group(1))
        assert n not in instances, f"#{n} defined twice"
        instances[n] = m.group(2)
    assert instances
    for record in instances.values():
        for ref in re.findall(r"#(\d+)", record):
            assert int(ref) in instances, f"#{ref} is not defined"
    return instances


def models():
    x = np.linspace(0.0, 3.0, 9)
    spline = geomkit.make_interp_spline(x, np.column_stack([x, np.sin(x), np.cos(2 * x)]))
    return [
        ("spline", spline),
        ("bezier", geomkit.BezierCurve([[0, 0, 0], [1, 2, 0.5], [3, 1, 1], [4, 0, 2]])),
        ("arc", geomkit.BezierCurve([[1, 0], [1, 1], [0, 1]], weights=[1, H, 1])),
        ("cylinder", geomkit.BezierSurface(
            [[[1, 0, 0], [1, 0, 2]], [[1, 1, 0], [1, 1, 2]], [[0, 1, 0], [0, 1, 2]]],
            weights=[[1, 1], [H, H], [1, 1]])),
        ("net", geomkit.make_interp_surface(
            np.array([[[i, j, np.sin(i + 0.5 * j)] for j in range(5)] for i in range(6)],
                     dtype=float))),
    ]


@pytest.mark.parametrize("name, obj", models(), ids=[m[0] for m in models()])
def test_round_trip_is_bit_for_bit(tmp_path, name, obj):
    path = tmp_path / f"{name}.step"
    obj.save(path)
    text = path.read_text()
    part21(text)
    assert f"'{name}'" in text  # the product is named after the file
    back = geomkit.load(path)
    assert type(back) is type(obj)
    for attr in ("t", "c", "points", "weights", "net"):
        if hasattr(obj, attr) and getattr(obj, attr) is not None:
            a, b = np.asarray(getattr(obj, attr)), np.asarray(getattr(back, attr))
            if attr in ("points", "net") and b.shape[-1] == a.shape[-1] + 1:
                # Points in R^2 are written with z = 0 (STEP geometry lives in R^3).
                assert np.all(b[..., -1] == 0)
                b = b[..., :-1]
            assert a.shape == b.shape and np.array_equal(a, b), attr
    if hasattr(obj, "control_points"):
        assert np.array_equal(obj.control_points, back.control_points)
    # The same text twice, and the CLI's export of the saved model file says the same.
    assert obj.to_step(name=name) == text
    json_path = tmp_path / f"{name}.json"
    obj.save(json_path)
    out = tmp_path / f"cli-{name}.step"
    subprocess.run([str(CLI), "export", str(json_path), "-o", str(out), "--name", name],
                   check=True, capture_output=True)
    assert out.read_text() == text


def test_bodies_are_closed_solids():
    text = geomkit.body("cube").to_step(schema="ap242")
    inst = part21(text)
    records = list(inst.values())
    assert sum(r.startswith("MANIFOLD_SOLID_BREP") for r in records) == 1
    assert sum(r.startswith("ADVANCED_FACE") for r in records) == 6
    assert sum(r.startswith("EDGE_CURVE") for r in records) == 12
    assert sum(r.startswith("VERTEX_POINT") for r in records) == 8
    assert "AP242" in text.upper()


def test_files_written_by_opencascade():
    box = geomkit.read_step(FIXTURES / "occt_box.step")
    assert len(box.models) == 6 and all(isinstance(m.model, geomkit.BezierSurface)
                                         for m in box.models)
    corners = np.unique(np.round(np.concatenate(
        [m.model.net.reshape(-1, 3) for m in box.models]), 9), axis=0)
    assert corners.shape == (8, 3)
    curve = geomkit.load(FIXTURES / "occt_bezier_curve.step")
    assert isinstance(curve, geomkit.BezierCurve)
    surface = geomkit.load(FIXTURES / "occt_bspline_surface.step")
    assert surface.describe().startswith("B-spline surface")
    with pytest.raises(ValueError, match="holds 6 curves and surfaces.*read_step"):
        geomkit.load(FIXTURES / "occt_box.step")


def test_bad_files_and_models(tmp_path):
    good = geomkit.BezierCurve([[0, 0, 0], [1, 1, 1]]).to_step()
    cut = tmp_path / "cut.step"
    cut.write_text(good[: len(good) // 2])
    with pytest.raises(ValueError, match="cut.step"):
        geomkit.read_step(cut)
    dangling = tmp_path / "dangling.step"
    dangling.write_text(re.sub(r"CARTESIAN_POINT\('',\(", "CARTESIAN_POINT('',#9999,(", good,
                               count=1))
    with pytest.raises(ValueError, match="#"):
        geomkit.read_step(dangling)
    pm = geomkit.PointModel.fit({"t": [0.0, 0.5, 1.0]}, [0.0, 1.0, 0.0])
    with pytest.raises(ValueError, match="point"):
        pm.save(tmp_path / "pm.step")
    assert not (tmp_path / "pm.step").exists()
    with pytest.raises(ValueError, match="schema"):
        geomkit.BezierCurve([[0, 0], [1, 1]]).to_step(schema="ap203")


EXPLICIT = ('{"type": "composite_explicit", "x_knots": [0, 1, 2], "y_knots": [0, 1], '
            '"patches": [["sin(x) * exp(y)"], ["sqrt(1 + x^2 + y^2)"]]}')


def test_formulas_are_approximated_within_the_reported_deviation(tmp_path):
    from scipy.interpolate import bisplev

    model = geomkit.loads(EXPLICIT)
    out = model.step_export(name="f", tolerance=1e-7)
    assert [a.piece for a in out.approximations] == ["patch (0, 0)", "patch (1, 0)"]
    diagonal = np.sqrt(4 + 1 + 6)  # x in [0, 2], y in [0, 1], z in [0, sqrt(6)]
    formulas = [lambda x, y: np.sin(x) * np.exp(y), lambda x, y: np.sqrt(1 + x**2 + y**2)]
    path = tmp_path / "f.step"
    with pytest.warns(geomkit.StepApproximationWarning) as caught:
        model.save(path, tolerance=1e-7)
    assert [str(w.message) for w in caught] == [f"approximated {a}" for a in out.approximations]
    assert "max deviation" in str(caught[1].message)
    assert path.read_text() == out.text
    back = geomkit.read_step(path).models
    assert len(back) == 2
    for a, m, f in zip(out.approximations, back, formulas):
        assert a.deviation <= a.tolerance and a.tolerance == pytest.approx(1e-7 * diagonal)
        # SciPy's bisplev of the imported B-spline, per coordinate, against NumPy's formula.
        tu, tv = m.model.knots
        net = m.model.net
        ku, kv = len(tu) - net.shape[0] - 1, len(tv) - net.shape[1] - 1
        (u0, u1), (v0, v1) = (tu[ku], tu[-ku - 1]), (tv[kv], tv[-kv - 1])
        u, v = np.linspace(u0, u1, 301), np.linspace(v0, v1, 301)
        xyz = [bisplev(u, v, [tu, tv, net[..., c].ravel(), ku, kv]) for c in range(3)]
        uu, vv = np.meshgrid(u, v, indexing="ij")
        dist = np.sqrt((xyz[0] - uu) ** 2 + (xyz[1] - vv) ** 2 + (xyz[2] - f(uu, vv)) ** 2)
        assert dist.max() <= a.deviation * 1.02, (a, dist.max())
    # The CLI writes the same file and names the same pieces.
    json_path = tmp_path / "f.json"
    json_path.write_text(EXPLICIT)
    cli = tmp_path / "cli.step"
    r = subprocess.run([str(CLI), "export", str(json_path), "-o", str(cli), "--name", "f",
                        "--tolerance", "1e-7"], check=True, capture_output=True, text=True)
    assert cli.read_text() == out.text
    assert r.stderr.count("warning: approximated patch") == 2
    # Exact models give no report and no warning.
    assert geomkit.BezierCurve([[0, 0, 0], [1, 1, 1]]).step_export().approximations == []
    with pytest.raises(ValueError, match="tolerance"):
        model.to_step(tolerance=0.0)
    with pytest.raises(TypeError, match="tolerance"):
        model.to_step(tolerance="small")


def test_rational_splines_of_several_spans_import_as_pieces():
    circle = geomkit.read_step(FIXTURES / "occt_rational_circle.step").models
    assert len(circle) == 3
    assert all(m.note.startswith(f"span {k + 1} of 3") for k, m in enumerate(circle))
