"""The installed package itself: the compiled module from the wheel (not the source tree),
its stubs matching it, the docs and markers the issue asks for, and the README's example."""

import ast
import inspect
import re
from pathlib import Path

import numpy as np
import pytest

import geomkit
from geomkit import _geomkit

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = Path(geomkit.__file__).resolve().parent


def test_installed_package_is_tested():
    # tests/python/run.sh installs the wheel into the venv: the package comes from
    # site-packages, with its compiled module, not from python/ of the work tree.
    assert "site-packages" in PACKAGE.parts, PACKAGE
    assert Path(_geomkit.__file__).name.endswith(".abi3.so")
    assert (PACKAGE / "py.typed").is_file()
    assert (PACKAGE / "_geomkit.pyi").is_file()


def _stub_signatures():
    """{name: [parameter names]} of every function and method of _geomkit.pyi."""
    tree = ast.parse((PACKAGE / "_geomkit.pyi").read_text())
    out = {}
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            out[node.name] = [a.arg for a in node.args.args]
        elif isinstance(node, ast.ClassDef):
            for item in node.body:
                if isinstance(item, ast.FunctionDef):
                    is_property = any(getattr(d, "id", None) == "property"
                                      for d in item.decorator_list)
                    args = None if is_property else [a.arg for a in item.args.args][1:]
                    out[f"{node.name}.{item.name}"] = args
    return out


def _runtime_signatures():
    out = {}
    for name, obj in vars(_geomkit).items():
        if name.startswith("_"):
            continue
        if inspect.isclass(obj):
            for attr, member in vars(obj).items():
                if attr.startswith("__") and attr != "__new__":
                    continue
                if isinstance(member, property) or type(member).__name__ == "getset_descriptor":
                    out[f"{name}.{attr}"] = None
                    continue
                # The constructor's signature is the class's (PyO3's __text_signature__).
                sig = inspect.signature(obj if attr == "__new__" else getattr(obj, attr))
                params = [p for p in sig.parameters if p not in ("self", "cls", "$self")]
                out[f"{name}.{attr}"] = params
        elif callable(obj):
            out[name] = list(inspect.signature(obj).parameters)
    return out


def test_stubs_match_the_compiled_module():
    stubs, runtime = _stub_signatures(), _runtime_signatures()
    assert stubs == runtime
    stub_text = (PACKAGE / "_geomkit.pyi").read_text()
    for constant in ("MAX_SPLINE_DEGREE", "MAX_DEGREE", "MIN_TILE_SIZE"):
        assert re.search(rf"^{constant}: int$", stub_text, re.MULTILINE)
        assert isinstance(getattr(_geomkit, constant), int)


def test_public_api_has_numpy_style_docstrings():
    public = [geomkit.make_interp_spline, geomkit.BSpline, geomkit.RectBivariateSpline,
              geomkit.make_splprep]
    for cls in (geomkit.BSpline, geomkit.RectBivariateSpline):
        public += [getattr(cls, n) for n in vars(cls) if not n.startswith("_")
                   and callable(getattr(cls, n))]
    for obj in public:
        doc = inspect.getdoc(obj) or ""
        assert doc, f"{obj} has no docstring"
        if obj in (geomkit.make_interp_spline, geomkit.BSpline, geomkit.RectBivariateSpline,
                   geomkit.make_splprep):
            for section in ("Parameters\n----------", "Raises\n------", "Examples\n--------"):
                assert section in doc, f"{obj.__name__}: no {section.splitlines()[0]}"
        elif inspect.signature(obj).parameters.keys() - {"self"}:
            assert "Parameters\n----------" in doc or "Returns\n-------" in doc, obj
    assert {"BSpline", "RectBivariateSpline", "make_interp_spline",
            "make_splprep"} <= set(geomkit.__all__)


def test_signatures_are_scipys():
    import scipy.interpolate as si

    def params(f):
        return [(p.name, p.default) for p in inspect.signature(f).parameters.values()]

    # SciPy's parameters, then geomkit's keyword-only tile (none by default).
    assert params(geomkit.make_interp_spline)[:-1] == params(si.make_interp_spline)
    assert params(geomkit.make_interp_spline)[-1] == ("tile", None)
    tile = inspect.signature(geomkit.make_interp_spline).parameters["tile"]
    assert tile.kind is inspect.Parameter.KEYWORD_ONLY
    assert params(geomkit.BSpline) == params(si.BSpline)
    # SciPy's keywords, in SciPy's order, then geomkit's param and tile
    assert params(geomkit.make_splprep)[:-2] == params(si.make_splprep)
    assert params(geomkit.make_splprep)[-2:] == [("param", "chord"), ("tile", None)]
    for name in ("__call__", "derivative", "antiderivative", "integrate", "insert_knot"):
        assert params(getattr(geomkit.BSpline, name)) == params(getattr(si.BSpline, name))
    assert params(geomkit.RectBivariateSpline) == params(si.RectBivariateSpline)
    for name in ("__call__", "ev", "integral", "get_knots", "get_coeffs"):
        assert params(getattr(geomkit.RectBivariateSpline, name)) == \
            params(getattr(si.RectBivariateSpline, name))


def test_readme_example_runs():
    """The README's "From Python" example, executed as written (it asserts against SciPy)."""
    text = (ROOT / "README.md").read_text()
    section = text.split("## From Python", 1)[1].split("\n## ", 1)[0]
    blocks = re.findall(r"```python\n(.*?)```", section, re.DOTALL)
    assert len(blocks) == 1, "one python block in the README's From Python section"
    namespace = {}
    exec(compile(blocks[0], "README.md (From Python)", "exec"), namespace)
    assert isinstance(namespace["spline"], geomkit.BSpline)
    assert namespace["report"].real_degree == 3
    assert namespace["cube"].mesh().volume == pytest.approx(8.0, rel=1e-9)
    assert namespace["svg"].startswith("<svg")


def test_docs_python_tour_runs_and_draws(tmp_path, monkeypatch):
    """docs/python-tour.md, cell by cell in one namespace, from a scratch directory: every
    block runs (each asserts its own facts) and every picture it links is written."""
    text = (ROOT / "docs" / "python-tour.md").read_text(encoding="utf-8")
    blocks = re.findall(r"```python\n(.*?)```", text, re.DOTALL)
    pictures = re.findall(r"!\[[^\]]*\]\((images/[^)]+)\)", text)
    assert len(blocks) == 5 and len(pictures) == 4
    monkeypatch.chdir(tmp_path)
    (tmp_path / "images").mkdir()
    namespace: dict = {}
    for i, block in enumerate(blocks):
        exec(compile(block, f"docs/python-tour.md (cell {i + 1})", "exec"), namespace)
    for picture in pictures:
        data = (tmp_path / picture).read_bytes()
        assert data.startswith(b"\x89PNG" if picture.endswith(".png") else b"<svg"), picture


def test_arrays_are_converted_once():
    from geomkit._arrays import contiguous

    a = np.linspace(0.0, 1.0, 10)
    assert contiguous(a, "x") is a  # contiguous float64: the array itself, no copy
    for other in (a[::2], np.asfortranarray(np.ones((3, 4))), a.astype(np.float32),
                  np.arange(10)):
        converted = contiguous(other, "x")
        assert converted.flags.c_contiguous and converted.dtype == np.float64
        assert not np.shares_memory(converted, other)
        assert np.array_equal(converted, other)


def test_compiled_module_refuses_what_it_cannot_read():
    """The private module called directly with arrays the package never passes: exceptions,
    never a crash or a write into a read-only or aliased array."""
    import pytest

    t = np.r_[[0.0] * 4, 1.0, 2.0, [3.0] * 4]
    c = np.arange(12.0).reshape(6, 2)
    curve = _geomkit.Curve(3, t, c)
    x = np.linspace(0, 3, 5)
    with pytest.raises(TypeError):
        _geomkit.Curve(3, t[::2], c[:2])  # not contiguous
    with pytest.raises(TypeError):
        _geomkit.Curve(3, t.astype(np.int64), c)  # not float64
    with pytest.raises(TypeError):
        _geomkit.Curve(3, t, c.ravel())  # not 2-D
    with pytest.raises(OverflowError):
        _geomkit.Curve(-1, t, c)
    with pytest.raises(ValueError, match="output buffer has length 8, expected 10"):
        curve.eval_into(x, 0, "extend", np.empty((4, 2)))
    read_only = np.empty((5, 2))
    read_only.flags.writeable = False
    with pytest.raises(TypeError, match="not writeable"):
        curve.eval_into(x, 0, "extend", read_only)
    with pytest.raises(TypeError):
        curve.eval_into(x, 0, "extend", np.empty((5, 2), dtype=np.float32))
    with pytest.raises(ValueError, match="extrapolate mode"):
        curve.eval_into(x, 0, "sideways", np.empty((5, 2)))
    both = np.linspace(0, 3, 10).reshape(5, 2)
    with pytest.raises(TypeError, match="already borrowed"):  # x and out one array
        curve.eval_into(both.reshape(-1)[:5], 0, "extend", both)
    with pytest.raises(ValueError):
        _geomkit.make_interp_spline_curve(x, np.ones((4, 1)), 3)
    surface = _geomkit.make_interp_surface_heights(np.arange(4.0), np.arange(5.0),
                                                   np.ones((4, 5)), 3, 3)
    with pytest.raises(ValueError):
        surface.eval_into(np.arange(3.0), np.arange(2.0), 0, 0, False, np.empty(3))


def _seen_inside(call, function, marker):
    """How often the main thread, polling while `call` runs in another thread, finds that
    thread's innermost Python frame in `function` (or a function or lambda defined in it) at
    a line holding `marker` (the call into the compiled module). With the GIL held there the
    main thread could not run at all while the compiled code does (a count of about 0);
    released, it polls all along."""
    import linecache
    import sys
    import threading
    import types

    codes, todo = set(), [function.__code__]
    while todo:
        code = todo.pop()
        codes.add(code)
        todo.extend(c for c in code.co_consts if isinstance(c, types.CodeType))
    done = threading.Event()
    worker = threading.Thread(target=lambda: (call(), done.set()))
    seen = 0
    worker.start()
    while not done.is_set():
        frame = sys._current_frames().get(worker.ident)
        if frame is not None and frame.f_code in codes and \
                marker in linecache.getline(frame.f_code.co_filename, frame.f_lineno):
            seen += 1
    worker.join()
    return seen


def test_the_gil_is_released_during_computations():
    rng = np.random.default_rng(11)
    x = np.sort(rng.uniform(0, 10, 1_000_000))
    y = rng.normal(size=(x.size, 3))
    build = _seen_inside(lambda: geomkit.make_interp_spline(x, y, k=5),
                         geomkit.make_interp_spline, "make_interp_spline_curve(")
    spline = geomkit.make_interp_spline(x[::50], y[::50], k=5)
    points = rng.uniform(-1, 11, 4_000_000)
    evaluate = _seen_inside(lambda: spline(points), geomkit.BSpline.__call__, "eval_into(")
    surface = geomkit.RectBivariateSpline(np.arange(300.0), np.arange(200.0),
                                          rng.normal(size=(300, 200)))
    grid = np.linspace(0, 299, 2000)
    on_grid = _seen_inside(lambda: surface(grid, grid[:1500]),
                           geomkit.RectBivariateSpline.__call__, "True, on_grid")
    assert min(build, evaluate, on_grid) > 20, (build, evaluate, on_grid)


def test_the_gil_is_released_during_tiled_builds():
    rng = np.random.default_rng(12)
    x = np.sort(rng.uniform(0, 10, 1_000_000))
    y = rng.normal(size=(x.size, 3))
    spline = _seen_inside(lambda: geomkit.make_interp_spline(x, y, k=5, tile=50_000),
                          geomkit.make_interp_spline, "make_interp_spline_curve(")
    g = np.arange(800.0)
    grid = np.stack([*np.meshgrid(g, g, indexing="ij"), rng.normal(size=(800, 800))], axis=-1)
    surface = _seen_inside(lambda: geomkit.make_interp_surface(grid, tile=200),
                           geomkit.make_interp_surface, "interpolate_grid(")
    assert min(spline, surface) > 20, (spline, surface)


def unaligned(a):
    """A C-contiguous float64 copy of `a` whose buffer is not 8-byte aligned (as arrays
    unpickled from another process can be)."""
    a = np.asarray(a, dtype=float)
    buf = bytearray(a.nbytes + 1)
    out = np.frombuffer(memoryview(buf)[1:], dtype=float).reshape(a.shape)
    out[...] = a
    assert not out.flags.aligned and out.flags.c_contiguous
    return out


def test_unaligned_arrays_are_read():
    x = np.linspace(0.0, 3.0, 20)
    y = np.sin(x)[:, None] * [1.0, 2.0]
    spl = geomkit.make_interp_spline(unaligned(x), unaligned(y))
    assert np.array_equal(spl.c, geomkit.make_interp_spline(x, y).c)
    assert np.array_equal(spl(unaligned(x[:5])), spl(x[:5]))
    c = geomkit.BezierCurve(unaligned([[0, 0], [1, 2], [3, 1]]))
    assert np.array_equal(c(unaligned([0.25, 0.5])), c([0.25, 0.5]))
