"""SciPy's `make_interp_spline` answered by the geomkit CLI (issue 22, acceptance).

    from swap import make_interp_spline      # same signature as scipy.interpolate's

Writes x and y (the interpolation axis moved first, every trailing axis flattened: N x d)
to .npy files in a temporary directory, runs

    geomkit interpolate curve Y.npy --params X.npy --degree K --form scipy
        [--end periodic] [--left=COND] [--right=COND] -o OUT.json

and returns a real `scipy.interpolate.BSpline` built from the JSON model's "knots" (SciPy's
t) and "control_points" (SciPy's c), reshaped to SciPy's shape, with SciPy's axis and
`extrapolate='periodic'` for periodic curves, exactly as make_interp_spline builds it
(`BSpline.construct_fast(t, c, k, axis=axis)`).

The layer only shapes arguments, as the Python package will: Python types (k through
operator.index: TypeError; integer arrays to float64; bc_type unpacked as SciPy unpacks it,
so a bc_type that is not a pair or a string is SciPy's own ValueError). Every check on the
values (lengths, sorted x, finite values, periodic ends, derivative orders and counts) is the
CLI's: its exit status 1 and one `error: ...` line become `ValueError(line)`, so SciPy's
`pytest.raises(ValueError, match=...)` sees the CLI's wording. So does exit status 2 with one
`error: invalid value ...` line (an end condition the argument parser refuses, e.g. 'typo').
Any other ending is a GeomkitCrash (a RuntimeError: the test fails, visibly).

Not expressible through the CLI, so refused here with NotImplementedError (not a
ValueError: a test expecting ValueError fails and is classified, it does not pass by
accident): complex values. `check_finite=False` is accepted and ignored
(the CLI always refuses non-finite input).

Environment: GEOMKIT_BIN (default: target/release/geomkit of this repository).
"""

import json
import operator
import os
import subprocess
import tempfile
from pathlib import Path

import numpy as np
from scipy.interpolate import BSpline
from scipy.interpolate import RectBivariateSpline as _RectBivariateSpline

ROOT = Path(__file__).resolve().parents[2]
GEOMKIT = os.environ.get("GEOMKIT_BIN") or str(ROOT / "target" / "release" / "geomkit")

# Every call of make_interp_spline and every CLI run of this process (argv without the
# binary, exit status, stderr): the pytest plugin (plugin.py) reads them to know which tests
# went through geomkit.
invocations = 0
calls = []


class GeomkitCrash(RuntimeError):
    """The CLI ended otherwise than with success or its one-line error (exit status 1)."""


def _number(v):
    """One value of a derivative condition, as the CLI reads it (Python's repr)."""
    if isinstance(v, (bool, np.bool_)):
        return repr(float(v))
    if isinstance(v, (int, np.integer)):
        return repr(int(v))
    if isinstance(v, (float, np.floating)):
        return repr(float(v))
    return repr(v)  # complex or anything else: the CLI refuses it in its own words


def _order(o):
    if isinstance(o, (int, np.integer)) and not isinstance(o, (bool, np.bool_)):
        return repr(int(o))
    if isinstance(o, (float, np.floating)) and float(o).is_integer():
        return repr(int(o))  # SciPy's np.atleast_1d(ords) keeps 1.0 usable as an order
    return repr(o)


def _end(cond):
    """SciPy's bc_type[i] (None, a string, or [(order, value), ...]) as a CLI COND."""
    if cond is None:
        return "not-a-knot"
    if isinstance(cond, str):
        return cond  # the CLI accepts or refuses the name
    # SciPy: `ords, vals = zip(*deriv)`; anything else is its ValueError.
    try:
        pairs = [tuple(p) for p in cond]
        if any(len(p) != 2 for p in pairs) or not pairs:
            raise TypeError
    except TypeError as e:
        raise ValueError(
            "Derivatives, `bc_type`, should be specified as a pair of "
            "iterables of pairs of (order, value)."
        ) from e
    parts = []
    for order, value in pairs:
        value = np.asarray(value)
        if np.iscomplexobj(value):
            raise NotImplementedError("complex values are out of scope (issue 22)")
        values = ",".join(_number(v) for v in value.ravel(order="C").tolist())
        parts.append(f"{_order(order)}:{values}")
    return ";".join(parts)


def _as_float(a, what):
    a = np.asarray(a)
    if np.iscomplexobj(a):
        raise NotImplementedError(f"complex {what}: out of scope (issue 22)")
    if a.dtype.kind not in "fiub":
        raise TypeError(f"{what} must hold real numbers, not {a.dtype}")
    return np.ascontiguousarray(a, dtype=np.float64)


def _run(args):
    proc = subprocess.run([GEOMKIT, *args], capture_output=True, text=True)
    calls.append((args, proc.returncode, proc.stderr))
    lines = proc.stderr.strip().splitlines()
    one_line = len(lines) == 1 and lines[0].startswith("error: ")
    # 1: the CLI's refusal of the data; 2: an argument value its parser (clap) refuses
    # ("invalid value 'typo' for '--left <COND>'"): both a ValueError in Python.
    if one_line and (proc.returncode == 1 or (
            proc.returncode == 2 and lines[0].startswith("error: invalid value"))):
        raise ValueError(lines[0][len("error: "):])
    if proc.returncode != 0:
        raise GeomkitCrash(
            f"geomkit {' '.join(args)} exited with {proc.returncode}:\n{proc.stderr}"
        )


def make_interp_spline(x, y, k=3, t=None, bc_type=None, axis=0, check_finite=True):
    """scipy.interpolate.make_interp_spline through `geomkit interpolate curve`."""
    global invocations
    invocations += 1
    # bc_type exactly as SciPy unpacks it (before anything else, as SciPy).
    periodic = isinstance(bc_type, str) and bc_type == "periodic"
    if bc_type is None or (isinstance(bc_type, str) and bc_type in ("not-a-knot", "periodic")):
        deriv_l = deriv_r = None
    elif isinstance(bc_type, str):
        deriv_l = deriv_r = bc_type
    else:
        try:
            deriv_l, deriv_r = bc_type
        except TypeError as e:
            raise ValueError(f"Unknown boundary condition: {bc_type}") from e

    k = operator.index(k)

    x = _as_float(x, "x")
    y = _as_float(y, "y")
    axis = np.lib.array_utils.normalize_axis_index(axis, y.ndim)
    y = np.moveaxis(y, axis, 0)
    trailing = y.shape[1:]
    ys = np.ascontiguousarray(y.reshape(y.shape[0], int(np.prod(trailing))) if y.ndim else y)

    with tempfile.TemporaryDirectory(prefix="geomkit-swap-") as tmp:
        tmp = Path(tmp)
        np.save(tmp / "x.npy", x)
        np.save(tmp / "y.npy", ys)
        args = ["interpolate", "curve", str(tmp / "y.npy"), "--params", str(tmp / "x.npy"),
                "--degree", str(k), "--form", "scipy"]
        if t is not None:
            np.save(tmp / "t.npy", _as_float(t, "t"))
            args += ["--knots", str(tmp / "t.npy")]
        if periodic:
            args += ["--end", "periodic"]
        elif deriv_l is not None or deriv_r is not None:
            args += [f"--left={_end(deriv_l)}", f"--right={_end(deriv_r)}"]
        args += ["-o", str(tmp / "out.json")]
        _run(args)
        model = json.loads((tmp / "out.json").read_text())

    if model.get("degree") != k:
        raise GeomkitCrash(f"asked for degree {k}, the model has {model.get('degree')}")
    t = np.asarray(model["knots"], dtype=np.float64)
    c = np.asarray(model["control_points"], dtype=np.float64)
    c = np.ascontiguousarray(c.reshape((c.shape[0],) + trailing))
    return BSpline.construct_fast(
        t, c, k, extrapolate="periodic" if periodic else True, axis=axis
    )


class RectBivariateSpline(_RectBivariateSpline):
    """scipy.interpolate.RectBivariateSpline (s=0, the interpolating spline) through
    `geomkit interpolate surface Z.npy --heights --x X.npy --y Y.npy --degree KX,KY --form
    scipy -o OUT.json`: FITPACK's knots and coefficients; SciPy's evaluation (`__call__`,
    `ev`, `partial_derivative`, `integral`) runs on them. What the CLI cannot be given is
    refused with NotImplementedError: s other than 0 (smoothing: out of scope) and a bbox
    other than the data's. SciPy's own argument checks that precede the fit (bbox shape, s
    sign) are SciPy's, and kept here in its words.
    """

    def __init__(self, x, y, z, bbox=[None] * 4, kx=3, ky=3, s=0, maxit=20):
        global invocations
        invocations += 1
        x, y, bbox = np.ravel(x), np.ravel(y), np.ravel(bbox)
        z = np.asarray(z)
        if bbox.shape != (4,):
            raise ValueError(f"bbox shape should be (4,), got {bbox.shape}")
        if s is not None and s < 0.0:
            raise ValueError("s should be s >= 0.0")
        if s is None or s != 0:
            raise NotImplementedError(f"s={s}: smoothing is out of scope (issue 22)")
        if any(b is not None for b in bbox.tolist()) and bbox.tolist() != [x[0], x[-1], y[0], y[-1]]:
            raise NotImplementedError(f"bbox {bbox.tolist()}: not a CLI option")
        if z.ndim != 2:
            raise ValueError(f"z must be a 2-D array, got shape {z.shape}")
        with tempfile.TemporaryDirectory(prefix="geomkit-swap-") as tmp:
            tmp = Path(tmp)
            np.save(tmp / "z.npy", _as_float(z, "z"))
            np.save(tmp / "x.npy", _as_float(x, "x"))
            np.save(tmp / "y.npy", _as_float(y, "y"))
            _run(["interpolate", "surface", str(tmp / "z.npy"), "--heights",
                  "--x", str(tmp / "x.npy"), "--y", str(tmp / "y.npy"),
                  "--degree", f"{int(kx)},{int(ky)}", "--form", "scipy",
                  "-o", str(tmp / "out.json")])
            model = json.loads((tmp / "out.json").read_text())
        tx = np.asarray(model["knots_u"], dtype=np.float64)
        ty = np.asarray(model["knots_v"], dtype=np.float64)
        c = np.asarray(model["net"], dtype=np.float64)
        if c.ndim == 3:
            c = c[..., 0]
        self.fp = 0.0
        self.tck = tx, ty, np.ascontiguousarray(c).ravel()
        self.degrees = int(kx), int(ky)
