"""Composite formulas from Python (method 3, spec/composite-surfaces.md): bodies, ruled
surfaces, composite surfaces of patches, piecewise functions and curves.

Independent references: the paper's cube formula (spec section 2) parsed by SymPy; SymPy
parsing the printed formula and evaluating it exactly; SymPy's lambdify(cse=True); the NumPy
printer executed, the C printer compiled by cc and the JavaScript printer run by node (where
present); SciPy's B-splines for the formulas of B-spline cells; Bernstein polynomials in
NumPy for Bézier patches; jumps built into the scenes for the continuity reports.
"""

import doctest
import json
import pickle
import shutil
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from fractions import Fraction
from math import comb

import numpy as np
import pytest
import sympy
from hypothesis import given
from hypothesis import strategies as st

import geomkit
import geomkit._compose
from conftest import assert_near

RNG = np.random.default_rng(20261204)

# The paper's cube (spec/composite-surfaces.md section 2), as the spec writes it.
PAPER_CUBE = {
    "x": "(1 - Abs(u) + Abs(u-1) + Abs(u-2) - Abs(u-3)) * (Abs(v) - Abs(v-1) - Abs(v-2) + Abs(v-3)) / 2",
    "y": "(1 - Abs(u-1) + Abs(u-2) + Abs(u-3) - Abs(u-4)) * (Abs(v) - Abs(v-1) - Abs(v-2) + Abs(v-3)) / 2",
    "z": "-Abs(v-1) + Abs(v-2)",
}

# `geomkit compose piecewise pw.json -o pwf.json` of {"type": "piecewise", "knots": [0, 1, 2],
# "pieces": ["x^2", "2*x-1"]}, as the CLI wrote it.
CLI_FORMULA_FILE = r"""{
  "type": "formula",
  "what": "piecewise function of 2 pieces",
  "variables": ["x"],
  "coordinates": ["f"],
  "op_count": 13,
  "formulas": {
    "c": "#include <math.h>\ndouble f(double x) { return fabs(x - 1.0) - fabs(x - 2.0) + (fabs(x)/2.0 - fabs(x - 1.0)/2.0 + (1.0/2.0))*(fabs(x)/2.0 - fabs(x - 1.0)/2.0 + (1.0/2.0)) + 1.0; }\n",
    "desmos": "f_{f}(x)=\\left|x - 1\\right| - \\left|x - 2\\right| + {\\left(\\frac{\\left|x\\right|}{2} - \\frac{\\left|x - 1\\right|}{2} + \\frac{1}{2}\\right)}^{2} + 1\n",
    "glsl": "float f(float x) { return abs(x - 1.0) - abs(x - 2.0) + (abs(x)/2.0 - abs(x - 1.0)/2.0 + (1.0/2.0))*(abs(x)/2.0 - abs(x - 1.0)/2.0 + (1.0/2.0)) + 1.0; }\n",
    "js": "const f = (x) => Math.abs(x - 1) - Math.abs(x - 2) + (Math.abs(x)/2 - Math.abs(x - 1)/2 + (1/2))*(Math.abs(x)/2 - Math.abs(x - 1)/2 + (1/2)) + 1;\n",
    "latex": "f(x) = \\left|x - 1\\right| - \\left|x - 2\\right| + {\\left(\\frac{\\left|x\\right|}{2} - \\frac{\\left|x - 1\\right|}{2} + \\frac{1}{2}\\right)}^{2} + 1\n",
    "maple": "f := (x) -> abs(x - 1) - abs(x - 2) + (abs(x)/2 - abs(x - 1)/2 + 1/2)^2 + 1;\n",
    "mathematica": "f[x_] := Abs[x - 1] - Abs[x - 2] + (Abs[x]/2 - Abs[x - 1]/2 + 1/2)^2 + 1\n",
    "matlab": "f = @(x) abs(x - 1) - abs(x - 2) + (abs(x)./2 - abs(x - 1)./2 + 1/2).^2 + 1;\n",
    "numpy": "import numpy as np\nf = lambda x: np.abs(x - 1) - np.abs(x - 2) + (np.abs(x)/2 - np.abs(x - 1)/2 + 1/2)**2 + 1\n",
    "rust": "fn f(x: f64) -> f64 { (x - 1.0).abs() - (x - 2.0).abs() + (x.abs()/2.0 - (x - 1.0).abs()/2.0 + (1.0/2.0)).powi(2) + 1.0 }\n",
    "sympy": "from sympy import *\nx = symbols(\"x\")\nf = Abs(x - 1) - Abs(x - 2) + (Abs(x)/2 - Abs(x - 1)/2 + Rational(1, 2))**2 + 1\n"
  },
  "continuity": {
    "continuous": true,
    "jumps": [
      {
        "at": 1.0,
        "max_jump": 0.0
      }
    ],
    "max_jump": 0.0,
    "statement": "continuous: the largest jump at a breakpoint is 0.00e0 (tolerance 4.26e-14); the formula reproduces every piece",
    "tolerance": 4.263256414560601e-14
  },
  "model": {
    "type": "piecewise",
    "knots": [0.0, 1.0, 2.0],
    "pieces": ["x^2", "2*x-1"]
  }
}
"""


def bicubic_scene(n, m, seed=1):
    """A composite surface of n x m bicubic Bézier patches with random nets (not continuous:
    the single formula is still one continuous formula)."""
    rng = np.random.default_rng(seed)
    nets = rng.uniform(-1.0, 1.0, size=(n, m, 4, 4, 3))
    return geomkit.CompositeSurface.from_bezier(np.arange(n + 1.0), np.arange(m + 1.0), nets)


def examples():
    """One object of every kind, with a ramp-heavy formula each."""
    return {
        "cube": geomkit.body("cube"),
        "cylinder": geomkit.body("cylinder", radius=1.5, height=0.5),
        "frustum": geomkit.body("frustum", radius=2.0, top_radius=0.5, height=3.0),
        "prism": geomkit.body("prism", polygon=[[0, 0], [2, 0], [2, 1], [0, 1.5]], height=1),
        "bicubic": bicubic_scene(2, 2),
        "explicit": geomkit.CompositeSurface({
            "type": "composite_explicit", "x_knots": [0, 1, 3], "y_knots": [-1, 0, 1],
            "patches": [["x*y", "sin(x) + y^2"], ["exp(-x) * y", {"z": "x + y"}]]}),
        "curve": geomkit.Piecewise([0, 1, 2.5], [
            {"x": "cos(t)", "y": "sin(t)", "z": "t", "domain": [0, 3.141592653589793]},
            {"x": "t", "y": "t^2", "z": "0.1*t", "domain": [-1, 1]}]),
        "function": geomkit.Piecewise([-1, 0, 0.5, 2], ["-x", "sqrt(x + 1) - 1", "1/3"]),
    }


def sample(obj, count, rng=RNG, margin=0.5):
    """Random points of the domain widened by `margin` (the formula clamps outside)."""
    return [rng.uniform(a - margin, b + margin, count) for a, b in obj.domain]


# -- the paper's cube ---------------------------------------------------------------------
def test_the_papers_cube_formula():
    cube = geomkit.body("cube")
    u, v = sympy.symbols("u v")
    paper = [sympy.parse_expr(PAPER_CUBE[c], local_dict={"u": u, "v": v}) for c in "xyz"]
    ours = cube.to_sympy()
    for c, a, b in zip("xyz", ours, paper):
        assert sympy.expand(a - b) == 0, c
    # The paper's numbers: the poles at v = 0 and 3, the eight vertices (+-1, +-1, +-1) at
    # the integer u on the squares v = 1 (top) and v = 2 (bottom); u in [0, 4], v in [0, 3].
    f = cube.evaluator()
    vertices = {(ui, vi): tuple(float(c) for c in f(ui, vi)) for ui in range(5) for vi in (1, 2)}
    assert vertices[(0, 1)] == (1.0, 1.0, 1.0) == vertices[(4, 1)]
    assert vertices[(1, 1)] == (-1.0, 1.0, 1.0)
    assert vertices[(2, 1)] == (-1.0, -1.0, 1.0)
    assert vertices[(3, 1)] == (1.0, -1.0, 1.0)
    assert vertices[(1, 2)] == (-1.0, 1.0, -1.0)
    assert {p for p in vertices.values()} == {(a, b, c) for a in (-1.0, 1.0)
                                              for b in (-1.0, 1.0) for c in (-1.0, 1.0)}
    for ui in np.linspace(0, 4, 9):
        assert [float(c) for c in f(ui, 0.0)] == [0.0, 0.0, 1.0]
        assert [float(c) for c in f(ui, 3.0)] == [0.0, 0.0, -1.0]
    # Every point is on the cube's surface: max |coordinate| = 1.
    x, y, z = f(*sample(cube, 2000, margin=0.0))
    largest = np.max(np.abs([x, y, z]), axis=0)
    assert np.all(np.abs(largest - 1.0) <= 4 * np.finfo(float).eps)
    # The printed Maple text is the paper's, as the spec shows it.
    assert cube.formula("maple").splitlines()[2] == "z := (u, v) -> -abs(v - 1) + abs(v - 2);"
    r = cube.report()
    assert r.closed_body and r.ends_are_points and r.open_curves == ()
    assert r.v == (0.0, 1.0, 2.0, 3.0)
    assert r.max_difference <= 4 * np.finfo(float).eps


# -- the printed formula against SymPy ---------------------------------------------------
@pytest.mark.parametrize("name", list(examples()))
def test_printed_sympy_formula_equals_the_evaluator(name):
    """The 'sympy' print, executed as SymPy code (independently of to_sympy's parser) and
    evaluated exactly at rational points, equals the compiled evaluator."""
    obj = examples()[name]
    namespace = {}
    exec(obj.formula("sympy"), namespace)
    exprs = [namespace[c] for c in obj.coordinates]
    symbols = [sympy.Symbol(v) for v in obj.variables]
    points = [np.round(p * 64) / 64 for p in sample(obj, 6)]  # exact binary fractions
    values = obj.evaluator()(*points)
    values = [values] if obj.dim == 1 else list(values)
    for i in range(6):
        subs = {s: sympy.Rational(Fraction(float(p[i]))) for s, p in zip(symbols, points)}
        for k, e in enumerate(exprs):
            exact = float(e.subs(subs).evalf(30))
            assert abs(values[k][i] - exact) <= 1e-12 * max(1.0, abs(exact)), (name, k, i)


@pytest.mark.parametrize("name", list(examples()))
def test_to_sympy_lambdify_agrees_with_the_compiled_evaluator(name):
    obj = examples()[name]
    exprs = obj.to_sympy()
    assert len(exprs) == obj.dim
    symbols = sympy.symbols(obj.variables)
    points = sample(obj, 500)
    reference = [sympy.lambdify(symbols, e, modules="numpy", cse=True)(*points) for e in exprs]
    ours = obj.evaluator()(*points)
    ours = [ours] if obj.dim == 1 else list(ours)
    for k in range(obj.dim):
        assert_near(ours[k], np.broadcast_to(reference[k], points[0].shape), rel=1e-12,
                    what=f"{name} {obj.coordinates[k]}")
    # The structural evaluator equals the single formula within rounding.
    cells = obj.evaluator("cells")(*points)
    cells = [cells] if obj.dim == 1 else list(cells)
    for k in range(obj.dim):
        assert_near(cells[k], ours[k], rel=1e-12, what=f"{name} cells")


def test_to_sympy_keeps_constants_exact():
    f = geomkit.Piecewise([0, 1, 3], ["x/3", "0.1*x + 7/30"])
    (e,) = f.to_sympy()
    x = sympy.Symbol("x")
    assert e.subs(x, 0) == 0
    assert e.subs(x, 1) == sympy.Rational(1, 3)
    assert "Rational(4, 15)" in f.formula("sympy")
    # A decimal constant of the formula, if printed as one, is read as the f64 it denotes.
    s = geomkit.CompositeSurface.from_bspline([0, 0, 0.1, 1, 1], [0, 0, 1, 1],
                                              [[[0.3], [0.5]], [[0.7], [0.9]], [[1.1], [1.3]]], degree=(1, 1))
    (z,) = s.to_sympy()
    u, v = sympy.symbols("x y")
    assert abs(float(z.subs({u: sympy.Rational(1, 20), v: 0})) - 0.5) <= 1e-15
    assert float(s.evaluator()(0.05, 0.0)) == 0.5
    floats = z.atoms(sympy.Float)
    assert floats
    assert "1.9999999999999998*Abs(x)" in s.formula("sympy")
    for a in floats:  # f64 values (53 bits), not SymPy's decimal reading of 17 digits
        assert sympy.Rational(a) == sympy.Rational(Fraction(float(a)))


def test_to_sympy_without_sympy(monkeypatch):
    monkeypatch.setitem(sys.modules, "sympy", None)
    with pytest.raises(ImportError, match="pip install sympy"):
        geomkit.body("cube").to_sympy()


# -- the other printers, run by real parsers and compilers --------------------------------
@pytest.mark.parametrize("name", ["cube", "bicubic", "curve", "function"])
def test_numpy_printer_executed(name):
    obj = examples()[name]
    namespace = {}
    exec(obj.formula("numpy"), namespace)
    points = sample(obj, 300)
    ours = obj.evaluator()(*points)
    ours = [ours] if obj.dim == 1 else list(ours)
    for k, c in enumerate(obj.coordinates):
        ref = np.broadcast_to(namespace[c](*points), points[0].shape)
        assert_near(ours[k], ref, rel=1e-12, what=f"{name} {c}")
    program = {}
    exec("import numpy as np\n" + "\n".join(f"{v} = P{i}" for i, v in enumerate(obj.variables))
         + "\n" + obj.formula("numpy", program=True),
         {**{f"P{i}": p for i, p in enumerate(points)}}, program)
    for k, c in enumerate(obj.coordinates):
        assert_near(ours[k], np.broadcast_to(program[c], points[0].shape), rel=1e-12)


@pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler")
def test_c_printer_compiled(tmp_path):
    import ctypes

    obj = examples()["cube"]
    src = tmp_path / "f.c"
    src.write_text(obj.formula("c"))
    lib = tmp_path / "f.so"
    subprocess.run(["cc", "-shared", "-fPIC", "-O1", "-o", str(lib), str(src), "-lm"],
                   check=True)
    dll = ctypes.CDLL(str(lib))
    u, v = sample(obj, 200)
    ours = obj.evaluator()(u, v)
    for k, c in enumerate(obj.coordinates):
        fn = getattr(dll, c)
        fn.restype = ctypes.c_double
        fn.argtypes = [ctypes.c_double, ctypes.c_double]
        ref = np.array([fn(a, b) for a, b in zip(u, v)])
        assert np.array_equal(ours[k], ref) or np.max(np.abs(ours[k] - ref)) <= 1e-15


@pytest.mark.skipif(shutil.which("rustc") is None, reason="no rustc")
def test_rust_printer_compiled(tmp_path):
    obj = examples()["explicit"]
    x, y = (np.round(p * 64) / 64 for p in sample(obj, 40))
    calls = "".join(f"    println!(\"{{}}\", z({float(a)!r}_f64, {float(b)!r}_f64));\n" for a, b in zip(x, y))
    src = tmp_path / "f.rs"
    src.write_text("#![allow(unused_parens)]\n" + obj.formula("rust") + "fn main() {\n" + calls
                   + "}\n")
    exe = tmp_path / "f"
    subprocess.run(["rustc", "-O", "-o", str(exe), str(src)], check=True, capture_output=True)
    out = subprocess.run([str(exe)], check=True, capture_output=True, text=True).stdout
    assert_near(obj.evaluator()(x, y), np.array([float(t) for t in out.split()]), rel=1e-14)


@pytest.mark.skipif(shutil.which("node") is None, reason="no node")
def test_js_printer_run_by_node():
    obj = examples()["function"]
    x = sample(obj, 50)[0]
    script = obj.formula("js") + f"console.log(JSON.stringify({json.dumps(x.tolist())}.map(f)));"
    out = subprocess.run(["node", "-e", script], check=True, capture_output=True, text=True)
    assert_near(obj.evaluator()(x), np.array(json.loads(out.stdout)), rel=1e-14)


def test_every_format_prints_and_unknown_ones_are_listed():
    cube = geomkit.body("cube")
    assert geomkit.CompositeSurface.FORMATS == ("maple", "mathematica", "sympy", "numpy",
                                                "matlab", "latex", "c", "rust", "glsl", "js",
                                                "desmos")
    texts = cube.formulas()
    assert set(texts) == set(cube.FORMATS)
    assert texts["mathematica"].startswith("x[u_, v_] := ")
    assert texts["latex"].startswith("x(u, v) = ")
    assert "fabs(v - 1.0)" in texts["c"]
    assert cube.formula("octave") == texts["matlab"]
    assert cube.formula("python") == texts["sympy"]
    assert "t0 = " in cube.formula("sympy", program=True)
    with pytest.raises(ValueError, match="maple, mathematica, sympy, numpy, matlab, latex, c, "
                                         "rust, glsl, js, desmos"):
        cube.formula("fortran")
    with pytest.raises(TypeError):
        cube.formula(3)


# -- independent values: SciPy's B-splines, Bernstein polynomials --------------------------
def test_bspline_cells_equal_scipys_surface():
    from scipy.interpolate import RectBivariateSpline

    x, y = np.linspace(0, 3, 7), np.linspace(-1, 1, 6)
    z = np.random.default_rng(7).normal(size=(7, 6))
    rbs = RectBivariateSpline(x, y, z, s=0)
    tx, ty = rbs.get_knots()
    c = rbs.get_coeffs().reshape(len(tx) - 4, len(ty) - 4, 1)
    s = geomkit.CompositeSurface.from_bspline(tx, ty, c, degree=(3, 3))
    assert s.kind == "explicit" and s.variables == ("x", "y") and s.coordinates == ("z",)
    px, py = RNG.uniform(0, 3, 2000), RNG.uniform(-1, 1, 2000)
    assert_near(s.evaluator()(px, py), rbs.ev(px, py), rel=1e-11, what="tape")
    assert_near(s.evaluator("cells")(px, py), rbs.ev(px, py), rel=1e-11, what="cells")
    # A B-spline surface is continuous: its cells meet within the rounding of their
    # power-basis coefficients, which the report's tolerance covers.
    report = s.continuity()
    assert report.continuous and report.max_jump <= 1e-12 * np.abs(z).max()
    assert report.statement.startswith("continuous")
    for spline in (rbs, geomkit.RectBivariateSpline(x, y, z, kx=2, ky=5)):
        ref = spline.ev(px, py) if spline is rbs else \
            RectBivariateSpline(x, y, z, kx=2, ky=5, s=0).ev(px, py)
        assert_near(geomkit.CompositeSurface.from_spline(spline).evaluator()(px, py), ref,
                    rel=1e-10, what=f"from_spline {type(spline).__module__}")
    with pytest.raises(TypeError, match="get_knots"):
        geomkit.CompositeSurface.from_spline(object())


def test_piecewise_from_scipy_bspline():
    from scipy.interpolate import make_interp_spline

    t = np.linspace(0, 2, 9)
    spl = make_interp_spline(t, np.c_[np.cos(t), np.sin(3 * t)], k=3)
    p = geomkit.Piecewise.from_bspline(spl)
    assert p.kind == "curve" and p.variables == ("t",)
    q = RNG.uniform(0, 2, 500)
    x, y = p.evaluator()(q)
    assert_near(np.c_[x, y], spl(q), rel=1e-12)
    f = geomkit.Piecewise.from_bspline(make_interp_spline(t, t**2, k=2))
    assert f.kind == "function"
    assert_near(f.evaluator()(q), q**2, rel=1e-12)


def test_bezier_patches_equal_bernstein():
    nets = RNG.uniform(-1, 1, size=(2, 3, 4, 3, 3))
    uk, vk = np.array([0.0, 0.5, 2.0]), np.array([0.0, 1.0, 1.5, 3.0])
    s = geomkit.CompositeSurface.from_bezier(uk, vk, nets)
    u, v = RNG.uniform(0, 2, 300), RNG.uniform(0, 3, 300)
    x, y, z = s.evaluator("cells")(u, v)
    # Inside cell (0, 0) the formula is patch (0, 0) itself (it is never shifted).
    inside = (u < 0.5) & (v < 1.0)
    a, b = u[inside] / 0.5, v[inside]
    ref = np.zeros((inside.sum(), 3))
    for i in range(4):
        for j in range(3):
            w = comb(3, i) * a**i * (1 - a) ** (3 - i) * comb(2, j) * b**j * (1 - b) ** (2 - j)
            ref += w[:, None] * nets[0, 0, i, j]
    assert inside.sum() > 10
    assert_near(np.c_[x, y, z][inside], ref, rel=1e-13)
    assert_near(np.array(s.evaluator()(u, v)), np.array([x, y, z]), rel=1e-12)


# -- continuity reports ---------------------------------------------------------------------
def test_continuity_report_of_a_known_scene():
    # Patch (1, 0) lies 0.25 above where patch (0, 0) ends on u = 1: one jump of exactly 0.25.
    scene = {"type": "composite_surface", "u_knots": [0, 1, 2], "v_knots": [0, 1],
             "patches": [[{"x": "u", "y": "v", "z": "0"}],
                         [{"x": "u", "y": "v", "z": "1/4 + (u - 1)*v"}]]}
    s = geomkit.CompositeSurface(scene)
    r = s.continuity()
    assert not r.continuous
    assert r.max_jump == 0.25
    assert len(r.jumps) == 1
    (j,) = r.jumps
    assert (j.line, j.index, j.cell, j.max_jump) == ("u", 1, 0, 0.25)
    assert r.statement.startswith("NOT continuous: 1 of 1 shared edges jump")
    # The formula matches patch (0, 0) and shifts patch (1, 0) down by the jump.
    assert float(s.evaluator()(1.5, 0.5)[2]) == 0.25 + 0.25 - 0.25
    ok = geomkit.CompositeSurface({**scene, "patches": [[{"x": "u", "y": "v", "z": "0"}],
                                                        [{"x": "u", "y": "v",
                                                          "z": "(u - 1)*v"}]]})
    r = ok.continuity()
    assert r.continuous and r.max_jump <= r.tolerance
    assert r.statement.startswith("continuous")
    p = geomkit.Piecewise([0, 1, 2, 3], ["x", "x + 1", "5 - x"]).continuity()
    assert [(j.at, j.max_jump) for j in p.jumps] == [(1.0, 1.0), (2.0, 0.0)]
    assert not p.continuous


def test_ruled_report_of_an_open_surface():
    s = geomkit.RuledSurface([{"polyline": [[0, 0, 0], [1, 0, 0]]},
                              {"polygon": [[0, 0, 1], [1, 0, 1], [1, 1, 1]]}], [0, 2])
    r = s.report(samples=11)
    assert r.open_curves == ((0, 1.0),)
    assert not r.closed_body and not r.ends_are_points and r.samples == 11
    assert r.max_difference <= 1e-15
    with pytest.raises(ValueError, match="samples"):
        s.report(samples=1)


# -- model files and pickling -------------------------------------------------------------
def test_model_files_round_trip(tmp_path):
    for name, obj in examples().items():
        path = tmp_path / f"{name}.json"
        obj.save(path)
        back = geomkit.load(path)
        assert isinstance(back, type(obj)) or isinstance(obj, geomkit.Body), name
        assert back.formula("maple") == obj.formula("maple"), name
    kinds = {name: json.loads(obj.to_json())["type"] for name, obj in examples().items()}
    assert kinds == {"cube": "ruled", "cylinder": "ruled", "frustum": "ruled", "prism": "ruled",
                     "bicubic": "composite_surface", "explicit": "composite_explicit",
                     "curve": "piecewise", "function": "piecewise"}


def test_reads_the_clis_formula_file():
    f = geomkit.loads(CLI_FORMULA_FILE)
    assert isinstance(f, geomkit.Piecewise) and f.kind == "function"
    x = np.linspace(-1, 3, 41)
    assert_near(f.evaluator()(x), np.where(x < 1, np.clip(x, 0, 1) ** 2, 2 * np.clip(x, 1, 2) - 1))
    assert json.loads(f.to_json()) == json.loads(CLI_FORMULA_FILE)  # the file it came from
    assert geomkit.loads(json.dumps({"type": "polygon", "points": [[0, 0], [1, 0], [0, 1]]})
                         ).kind == "curve"


def test_writes_the_clis_formula_file(tmp_path):
    """formula_file is the file `geomkit compose piecewise ... -o f.json` writes, to the
    letter of its JSON (the interoperability of the two front ends), and loads back."""
    p = geomkit.Piecewise([0, 1, 2], ["x^2", "2*x-1"])
    assert json.loads(p.formula_file("piecewise function of 2 pieces")) == \
        json.loads(CLI_FORMULA_FILE)
    for name, obj in examples().items():
        path = tmp_path / f"{name}.json"
        obj.save_formula(path)
        back = geomkit.load(path)
        assert type(back) is type(obj) or isinstance(obj, geomkit.Body), name
        f = json.loads(path.read_text())
        assert f["type"] == "formula" and f["formulas"] == obj.formulas(), name
        assert back.formula("c") == obj.formula("c")
        assert json.loads(back.formula_file()) == json.loads(obj.formula_file()), name
    r = json.loads(examples()["explicit"].formula_file())["continuity"]
    assert set(r) == {"max_jump", "tolerance", "continuous", "statement", "jumps"}
    assert set(r["jumps"][0]) == {"line", "index", "cell", "max_jump", "at"}


def test_pickling():
    for name, obj in examples().items():
        back = pickle.loads(pickle.dumps(obj))
        assert type(back) is type(obj), name
        pts = sample(obj, 100)
        a, b = obj.evaluator()(*pts), back.evaluator()(*pts)
        assert np.array_equal(np.asarray(a), np.asarray(b)), name
    f = examples()["bicubic"].evaluator("cells", threads=1)
    g = pickle.loads(pickle.dumps(f))
    u, v = sample(examples()["bicubic"], 50)
    assert np.array_equal(np.array(f(u, v)), np.array(g(u, v)))
    cube = pickle.loads(pickle.dumps(geomkit.body("box", size=(1, 2, 3))))
    assert cube.name == "box" and cube.params == {"size": (1, 2, 3)}


# -- the evaluator: broadcasting, threads, refusals --------------------------------------
def test_evaluator_broadcasts_like_numpy():
    cube = geomkit.body("cube")
    f = cube.evaluator()
    u = np.linspace(0, 4, 5)[:, None]
    v = np.linspace(0, 3, 7)[None, :]
    x, y, z = f(u, v)
    assert x.shape == y.shape == z.shape == (5, 7)
    for i in range(5):
        for j in range(7):
            assert [x[i, j], y[i, j], z[i, j]] == [float(c) for c in f(u[i, 0], v[0, j])]
    assert f(1.0, 2.0)[0].shape == ()
    assert f(np.empty(0), 1.0)[0].shape == (0,)
    # non-contiguous and other dtypes: converted, same values
    w = np.linspace(0, 4, 40)
    assert np.array_equal(f(w[::3], 1.5)[0], f(np.ascontiguousarray(w[::3]), 1.5)[0])
    assert np.array_equal(f(np.arange(5), 1)[1], f(np.arange(5.0), 1.0)[1])
    with pytest.raises(ValueError, match="broadcast"):
        f(np.zeros(3), np.zeros(4))
    with pytest.raises(TypeError, match="2 arguments"):
        f(1.0)
    with pytest.raises(TypeError, match="complex"):
        f(1j, 1.0)
    with pytest.raises(TypeError):
        f(np.array(["a"]), 1.0)
    # NaN follows f64 in the formula, and is refused by the structural evaluator.
    assert np.isnan(f(np.nan, 1.0)[0])
    with pytest.raises(ValueError, match="finite"):
        cube.evaluator("cells")(np.nan, 1.0)
    with pytest.raises(ValueError, match="method"):
        cube.evaluator("sympy")
    with pytest.raises(ValueError, match="threads"):
        cube.evaluator(threads=0)


def test_threads_give_the_same_bits():
    s = bicubic_scene(3, 3)
    u, v = RNG.uniform(-0.5, 3.5, 100_000), RNG.uniform(-0.5, 3.5, 100_000)
    one = np.array(s.evaluator(threads=1)(u, v))
    assert np.array_equal(one, np.array(s.evaluator(threads=4)(u, v)))
    f = s.evaluator()
    with ThreadPoolExecutor(8) as pool:
        results = list(pool.map(lambda _: np.array(f(u, v)), range(8)))
    for r in results:
        assert np.array_equal(r, one)


def test_the_compiled_module_refuses_bad_buffers():
    inner = geomkit.body("cube")._inner
    u = np.zeros(4)
    with pytest.raises(ValueError, match="shape"):
        inner.eval_into([u, u], np.empty((3, 5)))
    with pytest.raises(ValueError, match="lengths"):
        inner.eval_into([u, np.zeros(3)], np.empty((3, 4)))
    with pytest.raises(ValueError, match="variables"):
        inner.eval_into([u], np.empty((3, 4)))
    with pytest.raises(TypeError):
        inner.eval_into([u.astype(np.float32), u], np.empty((3, 4)))
    with pytest.raises(TypeError):
        inner.eval_into([np.zeros(8)[::2], u], np.empty((3, 4)))


# -- bad input --------------------------------------------------------------------------------
def test_bad_input():
    with pytest.raises(ValueError, match="unknown body"):
        geomkit.body("sphere")
    with pytest.raises(ValueError, match="height"):
        geomkit.body("cone", height=-1.0)
    with pytest.raises(ValueError, match="must be finite"):
        geomkit.body("cylinder", radius=float("nan"))
    with pytest.raises(TypeError, match="unknown option"):
        geomkit.body("cube", colour="red")
    with pytest.raises(TypeError):
        geomkit.body("cone", radius="1")
    with pytest.raises(ValueError, match="ngon"):
        geomkit.body("prism", ngon=2)
    with pytest.raises(ValueError, match="polygon"):
        geomkit.body("prism", polygon=[[0, 0], [1, 1]])
    with pytest.raises(ValueError, match="NaN"):
        geomkit.Piecewise([0, float("nan")], ["x"])
    with pytest.raises(ValueError):
        geomkit.Piecewise([0, 1, 2], ["x"])  # one piece for two intervals
    with pytest.raises(ValueError, match="piece 0"):
        geomkit.Piecewise([0, 1], ["x +* 2"])
    with pytest.raises(TypeError):
        geomkit.Piecewise([0, 1], "x")
    with pytest.raises(ValueError, match="patches"):
        geomkit.CompositeSurface({"type": "composite_surface", "u_knots": [0, 1],
                                  "v_knots": [0, 1]})
    with pytest.raises(ValueError):
        geomkit.CompositeSurface({"type": "composite_surface", "u_knots": [0, 0],
                                  "v_knots": [0, 1], "patches": [[{"x": "u", "y": "v"}]]})
    with pytest.raises(ValueError, match="NaN"):
        geomkit.CompositeSurface({"type": "composite_explicit", "x_knots": [0, float("nan")],
                                  "y_knots": [0, 1], "patches": [["x"]]})
    with pytest.raises(ValueError, match="ruled"):
        geomkit.CompositeSurface({"type": "ruled", "v": [0, 1],
                                  "curves": [{"point": [0, 0, 0]}, {"point": [0, 0, 1]}]})
    with pytest.raises(TypeError):
        geomkit.CompositeSurface(42)
    with pytest.raises(ValueError, match="shape"):
        geomkit.CompositeSurface.from_bezier([0, 1], [0, 1], np.zeros((1, 1, 2, 2)))
    with pytest.raises(ValueError, match="cells"):
        geomkit.CompositeSurface.from_bezier([0, 1, 2], [0, 1], np.zeros((1, 1, 2, 2, 3)))
    with pytest.raises(ValueError):
        geomkit.CompositeSurface.from_bspline([0, 0, 1, 1], [0, 0, 1, 1], np.zeros((3, 2, 1)),
                                              degree=(1, 1))
    with pytest.raises(TypeError):
        geomkit.Piecewise.from_bspline(object())
    with pytest.raises(ValueError):
        geomkit.RuledSurface([{"point": [0, 0, 0]}, {"point": [0, 0, 1]}], [1, 0])
    with pytest.raises(ValueError, match="is a"):
        geomkit.loads('{"type": "bezier_curve", "points": [[0, 0], [1, 1]]}') and \
            geomkit._compose._from_json(
                '{"type": "bezier_curve", "points": [[0, 0], [1, 1]]}')


def test_docstring_examples():
    result = doctest.testmod(geomkit._compose, optionflags=doctest.ELLIPSIS)
    assert result.attempted >= 15
    assert result.failed == 0


def test_the_gil_is_released_during_evaluation():
    from test_package import _seen_inside

    s = bicubic_scene(4, 4)
    u, v = RNG.uniform(0, 4, 400_000), RNG.uniform(0, 4, 400_000)
    tape, cells = s.evaluator(threads=1), s.evaluator("cells", threads=1)
    seen = [_seen_inside(lambda: f(u, v), geomkit.Evaluator.__call__, marker)
            for f, marker in ((tape, "run(flat, out"), (cells, "run(flat, out"))]
    assert min(seen) > 20, seen


@given(st.lists(st.tuples(st.integers(1, 160), st.integers(-800, 800)), min_size=1,
                max_size=12),
       st.integers(-200, 200), st.integers(-4000, 4000))
def test_continuous_pieces_give_the_polyline(steps, y0, x0):
    """Linear pieces joined end to end: the single formula of section 5 is the polyline
    through the joints (NumPy's interp), and the continuity report finds no jump. Widths,
    slopes and starts are multiples of 1/16, 1/8, 1/4 (no constant underflows, which the
    library refuses by design)."""
    pieces = [(w / 16, a / 8) for w, a in steps]
    x0, y0 = x0 / 4, y0 / 4
    knots, values, texts = [x0], [y0], []
    for width, slope in pieces:
        xi, yi = knots[-1], values[-1]
        texts.append(f"{slope!r}*(x - {xi!r}) + {yi!r}")
        knots.append(xi + width)
        values.append(yi + slope * (knots[-1] - xi))
    f = geomkit.Piecewise(knots, texts)
    x = np.linspace(knots[0] - 1.0, knots[-1] + 1.0, 301)
    ref = np.interp(x, knots, values)
    scale = max(1.0, float(np.max(np.abs(values))), abs(x0) * 100)
    for method in ("tape", "cells"):
        assert np.max(np.abs(f.evaluator(method)(x) - ref)) <= 1e-9 * scale
    r = f.continuity()
    assert r.max_jump <= 1e-9 * scale
