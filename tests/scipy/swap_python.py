"""SciPy's `make_interp_spline`, `make_splprep` and `RectBivariateSpline` answered by the
geomkit Python package (issue 23): the second mode of the swap layer
(GEOMKIT_SCIPY_SWAP=python; swap.py is the CLI's). Nothing is shaped here: the package's own
functions run, the calls only counted for the pytest plugin (plugin.py), and what SciPy's
tests do with the results (evaluate, differentiate, integrate, compare attributes) runs on
geomkit's BSpline and RectBivariateSpline, not SciPy's.
"""

import geomkit

# Calls of the swapped functions in this process (plugin.py reads it to know which tests
# went through geomkit); `calls` is the CLI mode's list of runs, empty here.
invocations = 0
calls = []


def make_interp_spline(*args, **kwargs):
    """geomkit.make_interp_spline, counted."""
    global invocations
    invocations += 1
    return geomkit.make_interp_spline(*args, **kwargs)


def make_splprep(*args, **kwargs):
    """geomkit.make_splprep (s = 0), counted."""
    global invocations
    invocations += 1
    return geomkit.make_splprep(*args, **kwargs)


class RectBivariateSpline(geomkit.RectBivariateSpline):
    """geomkit.RectBivariateSpline, counted."""

    def __init__(self, *args, **kwargs):
        global invocations
        invocations += 1
        super().__init__(*args, **kwargs)
