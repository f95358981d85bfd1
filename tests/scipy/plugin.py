"""pytest plugin: SciPy's own tests with make_interp_spline and RectBivariateSpline answered
by geomkit: through the CLI (tests/scipy/swap.py, issue 22) or, with
GEOMKIT_SCIPY_SWAP=python, by the Python package (tests/scipy/swap_python.py, issue 23).

    python -m pytest -p plugin --pyargs scipy.interpolate.tests.test_bsplines \
        scipy.interpolate.tests.test_fitpack2                          # run.sh does this

1. Swap: the test modules import them by name (make_splprep too, in the package's mode); their module attributes become swap's,
   and so does every parametrized argument that is SciPy's function (test_bsplines.py's
   TestBatch passes make_interp_spline as `make_spline`).
2. Selection: the tests that call one of them, found in their source: the test function,
   its class's setup_method, a method of its class it calls as `self.NAME(` (and TestBatch's
   parameter). The others are deselected (GEOMKIT_SCIPY_SELECT=all keeps them and reports
   any of them that calls a swapped function: a check of this selection). A selected test
   that never calls one is an error of the run.
3. Expectations: expected.txt (the CLI) or expected-python.txt (the package) lists the
   selected tests that do not pass, each with its kind ("gap": in scope of the issue, to be
   fixed; "n/a": a feature outside what that front end offers) and reason. They are marked
   xfail(strict=True): one that starts to pass fails the run (take it off the list); every
   other selected test must pass.
"""

import inspect
import os
import re
from pathlib import Path

import pytest
import scipy.interpolate

# The swap layer: the CLI's (swap.py, issue 22) or the Python package's (swap_python.py,
# issue 23), each with its own list of expected failures.
MODE = os.environ.get("GEOMKIT_SCIPY_SWAP", "cli")
if MODE == "python":
    import swap_python as swap

    EXPECTED = "expected-python.txt"
    ISSUE = "issue 23"
elif MODE == "cli":
    import swap

    EXPECTED = "expected.txt"
    ISSUE = "issue 22"
else:
    raise ValueError(f"GEOMKIT_SCIPY_SWAP={MODE!r}: expected cli or python")

HERE = Path(__file__).resolve().parent
# name in the test modules -> (SciPy's, geomkit's)
SWAPS = {
    "make_interp_spline": (scipy.interpolate.make_interp_spline, swap.make_interp_spline),
    "RectBivariateSpline": (scipy.interpolate.RectBivariateSpline, swap.RectBivariateSpline),
}
if MODE == "python":  # the package's make_splprep (s = 0), which the CLI does not offer
    SWAPS["make_splprep"] = (scipy.interpolate.make_splprep, swap.make_splprep)
ORIGINALS = {id(orig): ours for orig, ours in SWAPS.values()}


def _load_expected():
    """expected.txt (or expected-python.txt): `ID KIND REASON...` per line (# comments); ID
    as pytest prints it from the module's file name on (test_bsplines.py::Class::test[params])."""
    expected = {}
    for number, line in enumerate((HERE / EXPECTED).read_text().splitlines(), 1):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        test_id, kind, reason = (line.split(None, 2) + ["", ""])[:3]
        if kind not in ("gap", "n/a") or not reason:
            raise pytest.UsageError(f"{EXPECTED}:{number}: want `ID gap|n/a REASON`")
        if test_id in expected:
            raise pytest.UsageError(f"{EXPECTED}:{number}: {test_id} listed twice")
        expected[test_id] = (kind, reason)
    return expected


def _source(obj):
    """The source of a function from its `def` on (its decorators, such as a parametrize
    over make_interp_spline and other functions, are not its body)."""
    try:
        text = inspect.getsource(obj)
    except (OSError, TypeError):
        return ""
    match = re.search(r"^\s*def ", text, re.MULTILINE)
    return text[match.start():] if match else text


def _calls_it(item):
    """Whether the item's test calls a swapped function (statically, from its source)."""
    callspec = getattr(item, "callspec", None)
    if callspec and any(id(v) in ORIGINALS for v in callspec.params.values()):
        return True
    module = getattr(item, "module", None)
    names = [n for n, pair in SWAPS.items() if getattr(module, n, None) in pair]
    text = _source(item.function)
    cls = getattr(item, "cls", None)
    sources = [text]
    if cls is not None:
        sources += [_source(getattr(cls, m, None)) for m in ("setup_method", "setup_class")]
        sources += [_source(getattr(cls, m, None)) for m in set(re.findall(r"self\.(\w+)\(", text))]
    return any(re.search(rf"\b{n}\b", src) for n in names for src in sources)


def _short_id(nodeid):
    """test_bsplines.py::Class::test[params], whatever the path pytest prints."""
    path, _, rest = nodeid.partition("::")
    return f"{Path(path).name}::{rest}" if rest else nodeid


class Suite:
    def __init__(self, config):
        self.config = config
        self.expected = _load_expected()
        self.keep_all = os.environ.get("GEOMKIT_SCIPY_SELECT") == "all"
        self.selected = {}  # short id -> item
        self.outcomes = {}  # short id -> passed | failed | xfailed | xpassed | skipped
        self.invoked = {}  # short id -> swap invocations in setup + call
        self.failures = {}  # short id -> one line of why

    # -- 1 + 2 -----------------------------------------------------------------------------
    # First, so that it sees every test of the module (before -k or -m deselect some).
    @pytest.hookimpl(tryfirst=True)
    def pytest_collection_modifyitems(self, session, config, items):
        keep, drop = [], []
        for item in items:
            module = getattr(item, "module", None)
            for name, (orig, ours) in SWAPS.items():
                if module is not None and getattr(module, name, None) is orig:
                    setattr(module, name, ours)
            short = _short_id(item.nodeid)
            if _calls_it(item):
                self.selected[short] = item
                keep.append(item)
                if short in self.expected:
                    kind, reason = self.expected[short]
                    item.add_marker(pytest.mark.xfail(reason=f"{kind}: {reason}", strict=True))
            elif self.keep_all:
                keep.append(item)
            else:
                drop.append(item)
        if drop:
            config.hook.pytest_deselected(items=drop)
        items[:] = keep

    @pytest.hookimpl(tryfirst=True)
    def pytest_pyfunc_call(self, pyfuncitem):
        for name, value in pyfuncitem.funcargs.items():
            if id(value) in ORIGINALS:
                pyfuncitem.funcargs[name] = ORIGINALS[id(value)]

    @pytest.hookimpl(wrapper=True)
    def pytest_runtest_protocol(self, item, nextitem):
        before = swap.invocations
        try:
            return (yield)
        finally:
            self.invoked[_short_id(item.nodeid)] = swap.invocations - before

    def pytest_runtest_logreport(self, report):
        short = _short_id(report.nodeid)
        if report.failed:
            strict_xpass = str(report.longrepr).startswith("[XPASS(strict)]")
            self.outcomes[short] = "xpassed" if strict_xpass else "failed"
            self.failures.setdefault(short, _why(report))
        elif self.outcomes.get(short) in ("failed", "xpassed"):
            pass
        elif report.skipped:
            self.outcomes[short] = "xfailed" if hasattr(report, "wasxfail") else "skipped"
        elif report.when == "call":
            self.outcomes[short] = "xpassed" if hasattr(report, "wasxfail") else "passed"

    # -- 3 ---------------------------------------------------------------------------------
    def problems(self):
        out = []
        for short in sorted(set(self.expected) - set(self.selected)):
            out.append(f"{EXPECTED} names {short}, which is not a selected test")
        for short in sorted(self.selected):
            if self.outcomes.get(short) not in (None, "skipped") and not self.invoked.get(short):
                out.append(f"{short} is selected but never calls a swapped function")
        if self.keep_all:
            for short, count in sorted(self.invoked.items()):
                if count and short not in self.selected:
                    out.append(f"{short} calls a swapped function but is not selected")
        return out

    def pytest_sessionfinish(self, session, exitstatus):
        if self.problems() and session.exitstatus == 0:
            session.exitstatus = 1

    def pytest_terminal_summary(self, terminalreporter, exitstatus, config):
        tr = terminalreporter
        tr.section("geomkit: SciPy's own tests through "
                   + ("the Python package" if MODE == "python" else "the CLI"))
        ran = {s: self.outcomes[s] for s in self.selected if s in self.outcomes}
        bsplines = "make_interp_spline" + (" or make_splprep" if MODE == "python" else "")
        for module, what in (("test_bsplines.py", bsplines),
                             ("test_fitpack2.py", "RectBivariateSpline")):
            mine = {s: o for s, o in ran.items() if s.startswith(module + "::")}
            if mine:
                self._summary(tr, f"{module}: {len(mine)} tests call {what}", mine)
        for p in self.problems():
            tr.write_line(f"  SELECTION: {p}")
        if MODE == "python":
            tr.write_line(f"{swap.invocations} calls of the geomkit package")
            return
        codes = {}
        for _, code, _ in swap.calls:
            codes[code] = codes.get(code, 0) + 1
        tr.write_line(
            f"{len(swap.calls)} geomkit runs (exit status: "
            + ", ".join(f"{c}: {n}" for c, n in sorted(codes.items())) + ")"
        )

    def _summary(self, tr, title, ran):
        listed = {s: self.expected[s] for s in self.expected if s in ran}
        passed = sorted(s for s, o in ran.items() if o == "passed" and s not in listed)
        gaps = sorted(s for s, (k, _) in listed.items() if k == "gap" and ran[s] == "xfailed")
        na = sorted(s for s, (k, _) in listed.items() if k == "n/a" and ran[s] == "xfailed")
        own_xfail = sorted(s for s, o in ran.items() if o == "xfailed" and s not in listed)
        skipped = sorted(s for s, o in ran.items() if o == "skipped")
        unexpected = sorted(
            s for s, o in ran.items()
            if o == "xpassed" or (o == "failed" and s not in listed)
        )
        tr.write_line(
            f"{title}: {len(passed)} pass, {len(gaps)} fail on a gap of {ISSUE} (expected), "
            f"{len(na)} do not apply, {len(own_xfail)} xfail in SciPy itself, "
            f"{len(skipped)} skipped, {len(unexpected)} unexpected"
        )
        for kind, ids in ((f"gap ({ISSUE})", gaps), ("does not apply", na)):
            for s in ids:
                tr.write_line(f"  {kind}: {s}: {listed[s][1]}")
        for s in own_xfail:
            tr.write_line(f"  xfail in SciPy: {s}")
        for s in skipped:
            tr.write_line(f"  skipped: {s}")
        for s in unexpected:
            if ran[s] == "xpassed":
                tr.write_line(f"  UNEXPECTED PASS: {s}: take it off tests/scipy/{EXPECTED}")
            else:
                tr.write_line(f"  UNEXPECTED FAILURE: {s}: {self.failures.get(s, '?')}")


def _why(report):
    """Where and why a test failed, on one line: the test file's line and the exception's
    message (for a failed `pytest.raises(match=...)`: the pattern and the actual message)."""
    crash = getattr(report.longrepr, "reprcrash", None)
    if crash is None:
        text = str(report.longrepr).strip()
        return text.splitlines()[-1] if text else "?"
    lines = [ln.strip() for ln in crash.message.splitlines() if ln.strip()]
    text = " | ".join(lines)
    if len(text) > 400:
        text = text[:400] + " ..."
    return f"{Path(crash.path).name}:{crash.lineno}: {text}"


def pytest_configure(config):
    config.pluginmanager.register(Suite(config), "geomkit-scipy-suite")
