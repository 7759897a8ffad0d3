"""Ranges faultslip prints: percentile intervals that contain their own estimate, and the mean of a correlated
sequence.

A 95 % range is the 2.5th and 97.5th percentiles of the same estimator over resamples (a bootstrap,
or a fit's resamples carried through the model). For a skewed estimator, a point estimate from
the original data can fall outside them (issue 27: a BPT mean of 6.66e8 s printed with a range of
[8.0e4, 6.0e8] s, from a catalog whose 2.4-hour interval drove the aperiodicity to 2,800). A range
that excludes its own estimate describes nothing; here it is widened to reach the estimate, and the
caller is told so that it can say why.

A sequence a simulation produces (a chain's intervals between system-size events) is serially correlated, and
the mean of n correlated values varies as the mean of n / tau independent ones, tau the integrated
autocorrelation time (:func:`integrated_autocorrelation_time`, :func:`correlated_mean_half_width`).
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


#: Sokal's window: the autocorrelations are summed to the first lag M >= c tau(M) (Madras & Sokal 1988).
AUTOCORRELATION_WINDOW = 5.0


def integrated_autocorrelation_time(values, window: float = AUTOCORRELATION_WINDOW) -> float:
    """tau = 1 + 2 sum_{k=1}^{M} rho_k, the factor by which serial correlation multiplies the variance of a
    stationary sequence's mean (Madras & Sokal 1988, J. Stat. Phys. 50, 109; Sokal 1997, "Monte Carlo methods
    in statistical mechanics: foundations and new algorithms"), with M the first lag at or beyond ``window``
    tau(M) (the automatic window). 1 for fewer than 4 values or no spread; for an AR(1) sequence of lag-1 correlation
    phi it tends to (1 + phi) / (1 - phi).

    Parameters
    ----------
    values : array
        The sequence, in order.
    window : float
        c of the automatic window.

    Returns
    -------
    float
        tau (dimensionless; below 1 for an anticorrelated sequence).
    """
    x = np.asarray(values, dtype=float).ravel()
    count = x.size
    x = x - x.mean() if count else x
    if count < 4 or not np.any(x):
        return 1.0
    spectrum = np.fft.rfft(x, 2 * count)  # zero-padded: the linear, not circular, autocovariance
    covariance = np.fft.irfft(spectrum * np.conj(spectrum))[:count]
    correlation = covariance / covariance[0]
    running = 1.0 + 2.0 * np.cumsum(correlation[1:])
    lags = np.arange(1, count)
    reached = np.flatnonzero(lags >= window * running)
    return float(running[reached[0]] if reached.size else running[-1])


def correlated_mean_half_width(values, level: float = 0.95, inflation: float = 1.0) -> float:
    """The ``level`` half-width of a correlated sequence's mean, relative to it:
    ``inflation`` t_{n-1} s sqrt(max(1, tau)) / (sqrt(n) mean), Student's t over n values of standard deviation
    s, tau their :func:`integrated_autocorrelation_time` (an anticorrelated sequence is not credited). NaN below
    two values or for a mean that is not positive.
    """
    from scipy.stats import t as student  # heavy: imported where used

    x = np.asarray(values, dtype=float).ravel()
    count = x.size
    if count < 2 or not x.mean() > 0:
        return math.nan
    tau = max(1.0, integrated_autocorrelation_time(x))
    return float(inflation * student.ppf(0.5 + level / 2, count - 1) * x.std(ddof=1) * math.sqrt(tau)
                 / (math.sqrt(count) * x.mean()))
