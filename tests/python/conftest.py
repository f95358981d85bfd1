"""Shared helpers of the Python package's tests (bash tests/python/run.sh).

SciPy is the independent reference: every value test builds the same spline with SciPy and
compares (never geomkit with itself). Hypothesis runs derandomized (the same examples every
run) and keeps no database in the work tree.
"""

import numpy as np
from hypothesis import settings

settings.register_profile("geomkit", derandomize=True, database=None, deadline=None,
                          max_examples=60)
settings.load_profile("geomkit")


def assert_near(ours, scipy_value, *, rel=1e-10, what=""):
    """ours == scipy_value within `rel` of the data's scale (the largest magnitude of the
    SciPy values, at least 1): the house style's tolerance that scales with the data."""
    ours = np.asarray(ours)
    scipy_value = np.asarray(scipy_value)
    assert ours.shape == scipy_value.shape, f"{what}: shape {ours.shape} != {scipy_value.shape}"
    finite = np.isfinite(scipy_value)
    assert np.array_equal(finite, np.isfinite(ours)), f"{what}: NaN/inf at other places"
    scale = max(1.0, float(np.max(np.abs(scipy_value[finite]), initial=0.0)))
    err = float(np.max(np.abs(ours[finite] - scipy_value[finite]), initial=0.0))
    assert err <= rel * scale, f"{what}: largest difference {err:.3g} > {rel:g} x {scale:.3g}"
