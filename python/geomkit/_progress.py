"""Progress bars for long evaluations, only when asked: ``with geomkit.progress(): ...``.

A context manager rather than a keyword, so that the SciPy-shaped calls keep SciPy's exact
signatures. Inside the block, an evaluation over many points runs in about a hundred steps
(each step with the GIL released, the bar updated between steps) and shows a bar: tqdm's if
tqdm is installed, else a line on standard error; outside, nothing changes (one call, no
bar). The setting is a context variable: it holds for the thread (or task) that entered the
block, not for others.
"""

from __future__ import annotations

import contextlib
import contextvars
import math
import sys
from collections.abc import Callable, Iterator
from typing import Any

__all__ = ["progress"]


# (bar factory or None, the fewest points that get a bar) while enabled.
_SETTING: contextvars.ContextVar[tuple[Callable[..., Any] | None, int] | None] = (
    contextvars.ContextVar("geomkit_progress", default=None)
)

# Steps of a bar, and the fewest points per step (each step is one call into Rust).
_STEPS = 100
_MIN_STEP = 1 << 16


@contextlib.contextmanager
def progress(bar: Callable[..., Any] | None = None, *,
             min_points: int = 1 << 20) -> Iterator[None]:
    """Shows progress bars for the long evaluations made inside the block.

    Evaluations of B-splines (`BSpline`, `RectBivariateSpline`, `BSplineSurface`),
    composite formulas (`Evaluator`) and point-calculus models (`PointModel.eval`) over at
    least `min_points` points then run in steps of at least 65 536 points with a bar. The
    results are the same bits as without it.

    Parameters
    ----------
    bar : callable, optional
        Makes a bar: called as ``bar(total=n, desc=text, unit="pt")`` and returning an object
        with ``update(k)`` and ``close()`` (e.g. ``tqdm.tqdm`` or ``tqdm.notebook.tqdm``).
        Default: ``tqdm.auto.tqdm`` when tqdm is installed, else a line on standard error.
    min_points : int, optional
        Smaller evaluations run in one call without a bar (default 2**20).

    Examples
    --------
    >>> import numpy as np, geomkit
    >>> spline = geomkit.make_interp_spline(np.arange(10.0), np.arange(10.0) ** 2)
    >>> with geomkit.progress(min_points=10):
    ...     values = spline(np.linspace(0, 9, 1000))
    """
    if not isinstance(min_points, int) or min_points < 0:
        raise ValueError(f"min_points must be a non-negative integer, not {min_points!r}")
    if bar is not None and not callable(bar):
        raise TypeError(f"bar must be callable (e.g. tqdm.tqdm), not {type(bar).__name__}")
    token = _SETTING.set((bar, min_points))
    try:
        yield
    finally:
        _SETTING.reset(token)


def chunked(count: int, step: Callable[[int, int], None], desc: str, per: int = 1) -> None:
    """Runs ``step(a, b)`` over ``[0, count)``: in one call, or in steps with a bar inside a
    `progress` block when ``count * per`` points reach its threshold (`per`: points per
    unit of `count`, e.g. the columns of a grid whose rows are split). A step after the
    first that raises ValueError (a point the core refuses, named by its index in the step)
    is answered by the one call's error, which names the index in the whole input."""
    setting = _SETTING.get()
    total = count * per
    if setting is None or total < setting[1] or count < 2:
        step(0, count)
        return
    factory, _ = setting
    size = max(math.ceil(count / _STEPS), math.ceil(_MIN_STEP / max(per, 1)), 1)
    bar = _make_bar(factory, total, desc)
    refused = False
    try:
        for a in range(0, count, size):
            b = min(count, a + size)
            try:
                step(a, b)
            except ValueError:
                if a == 0:
                    raise
                refused = True
                break
            bar.update((b - a) * per)
    finally:
        bar.close()
    if refused:
        step(0, count)


def _make_bar(factory: Callable[..., Any] | None, total: int, desc: str) -> Any:
    if factory is not None:
        return factory(total=total, desc=desc, unit="pt")
    try:
        from tqdm.auto import tqdm  # type: ignore[import-untyped, unused-ignore]
    except ImportError:
        return _TextBar(total, desc)
    return tqdm(total=total, desc=desc, unit="pt", unit_scale=True)


class _TextBar:
    """A bar without tqdm: the percentage on one line of standard error."""

    def __init__(self, total: int, desc: str) -> None:
        self.total, self.desc, self.done, self.shown = total, desc, 0, -1

    def update(self, k: int) -> None:
        self.done += k
        percent = 100 * self.done // max(self.total, 1)
        if percent != self.shown:
            self.shown = percent
            sys.stderr.write(f"\r{self.desc}: {percent:3d}% of {self.total:,} points")
            sys.stderr.flush()

    def close(self) -> None:
        sys.stderr.write("\n")
        sys.stderr.flush()


def reporter(points: int, desc: str) -> _Reporter | None:
    """The `progress` callback of a long build over `points` numbers inside a `progress`
    block (None outside, or below its threshold; `points` < 0: always inside a block). Call
    its ``close()`` when the build returns."""
    setting = _SETTING.get()
    if setting is None or 0 <= points < setting[1]:
        return None
    return _Reporter(setting[0], desc)


class _Reporter:
    """Called with (done, total) by the compiled core while a build runs; drives a bar made
    at the first report."""

    def __init__(self, factory: Callable[..., Any] | None, desc: str) -> None:
        self.factory, self.desc = factory, desc
        self.bar: Any = None
        self.done = 0
        self.total = 0

    def __call__(self, done: int, total: int) -> None:
        if self.bar is None:
            if total <= 0:
                return
            self.bar = _make_bar(self.factory, total, self.desc)
            self.total = total
        elif total != self.total and hasattr(self.bar, "total"):
            self.total = total
            self.bar.total = total
        if done > self.done:
            self.bar.update(done - self.done)
            self.done = done

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
