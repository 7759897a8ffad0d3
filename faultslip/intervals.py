"""Percentile intervals that contain their own estimate: the one rule for every range faultslip prints.

A 95 % range is the 2.5th and 97.5th percentiles of the same estimator over resamples (a bootstrap,
or a fit's resamples carried through the model). For a skewed estimator, a point estimate from
the original data can fall outside them (issue 27: a BPT mean of 6.66e8 s printed with a range of
[8.0e4, 6.0e8] s, from a catalog whose 2.4-hour interval drove the aperiodicity to 2,800). A range
that excludes its own estimate describes nothing; here it is widened to reach the estimate, and the
caller is told so that it can say why.
"""

from __future__ import annotations

import math

import numpy as np


def percentile_interval(samples, estimate: float, level: float = 0.95) -> tuple[float, float, bool]:
    """(low, high, widened): the ``level`` percentile interval of the ``samples`` (NaNs left out), widened to
    contain ``estimate`` if it does not; ``widened`` says whether it had to be. NaNs without samples."""
    values = np.asarray(samples, dtype=float).ravel()
    values = values[~np.isnan(values)]  # an infinite sample (say K / K_c of a strengthening resample) counts
    if values.size == 0:
        return math.nan, math.nan, False
    tail = 50.0 * (1.0 - level)
    method = "linear" if np.all(np.isfinite(values)) else "nearest"  # no interpolation between infinities
    low, high = (float(v) for v in np.percentile(values, [tail, 100.0 - tail], method=method))
    if not math.isfinite(estimate) or low <= estimate <= high:
        return low, high, False
    return min(low, float(estimate)), max(high, float(estimate)), True
