"""The installed package itself: the compiled module from the wheel (not the source tree),
its stubs matching it, the docs and markers the issue asks for, and the README's example."""

import ast
import inspect
import re
from pathlib import Path

import numpy as np

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
    for constant in ("MAX_SPLINE_DEGREE", "MAX_DEGREE"):
        assert re.search(rf"^{constant}: int$", stub_text, re.MULTILINE)
        assert isinstance(getattr(_geomkit, constant), int)


def test_public_api_has_numpy_style_docstrings():
    public = [geomkit.make_interp_spline, geomkit.BSpline, geomkit.RectBivariateSpline]
    for cls in (geomkit.BSpline, geomkit.RectBivariateSpline):
        public += [getattr(cls, n) for n in vars(cls) if not n.startswith("_")
                   and callable(getattr(cls, n))]
    for obj in public:
        doc = inspect.getdoc(obj) or ""
        assert doc, f"{obj} has no docstring"
        if obj in (geomkit.make_interp_spline, geomkit.BSpline, geomkit.RectBivariateSpline):
            for section in ("Parameters\n----------", "Raises\n------", "Examples\n--------"):
                assert section in doc, f"{obj.__name__}: no {section.splitlines()[0]}"
        elif inspect.signature(obj).parameters.keys() - {"self"}:
            assert "Parameters\n----------" in doc or "Returns\n-------" in doc, obj
    assert set(geomkit.__all__) == {"BSpline", "RectBivariateSpline", "make_interp_spline"}


def test_signatures_are_scipys():
    import scipy.interpolate as si

    def params(f):
        return [(p.name, p.default) for p in inspect.signature(f).parameters.values()]

    assert params(geomkit.make_interp_spline) == params(si.make_interp_spline)
    assert params(geomkit.BSpline) == params(si.BSpline)
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
    assert np.isfinite(namespace["area"])
