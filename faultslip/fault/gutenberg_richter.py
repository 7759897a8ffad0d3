r"""The Gutenberg-Richter b-value of a catalogue by maximum likelihood, with its uncertainty.

Above a completeness magnitude M_c, Gutenberg-Richter's log10 N(>= M) = a - b M makes the magnitudes
exponential with rate beta = b ln 10. Aki's (1965) maximum-likelihood estimate is

.. math:: \hat b = \frac{\log_{10} e}{\bar M - M_0},

with M_0 = M_c for continuous magnitudes and M_0 = M_c - \Delta M / 2 for magnitudes binned to
\Delta M (Utsu 1966's correction, as Bender 1983 and Marzocchi & Sandri 2003 review it). Its
uncertainty is given two ways:

- Aki's standard error \hat b / \sqrt{n}, and Shi & Bolt's (1982)
  2.30 \hat b^2 \sqrt{\sum (M_i - \bar M)^2 / (n (n - 1))};
- an exact interval for continuous magnitudes: S = \sum (M_i - M_0) is Gamma(n, beta), so
  2 beta S is chi-square with 2n degrees of freedom, and b lies in
  [\chi^2_{2n}(\alpha/2), \chi^2_{2n}(1 - \alpha/2)] / (2 S \ln 10) with confidence 1 - alpha.
"""

from __future__ import annotations

import math

import numpy as np

from faultslip.errors import InputError


def b_value(magnitudes, completeness: float | None = None, bin_width: float = 0.0, confidence: float = 0.95) -> dict:
    """Aki's maximum-likelihood b-value of the magnitudes at or above ``completeness`` (see the module).

    Parameters
    ----------
    magnitudes : array
        The catalogue's magnitudes.
    completeness : float, optional
        M_c: magnitudes below it are left out (default: the smallest magnitude).
    bin_width : float
        Delta M, the binning of the magnitudes (0: continuous).
    confidence : float
        Of the interval.

    Returns
    -------
    dict
        ``b``, ``aki_error`` (b / sqrt n), ``shi_bolt_error``, ``interval`` (low, high), ``count``,
        ``completeness``, ``mean_magnitude`` and ``a`` (log10 of the count at or above M_c, plus b M_c).
    """
    from scipy.stats import chi2  # heavy: imported where used

    values = np.asarray(magnitudes, float).ravel()
    if values.size == 0 or not np.all(np.isfinite(values)):
        raise InputError("a b-value needs finite magnitudes, at least two of them")
    if not (math.isfinite(bin_width) and bin_width >= 0):
        raise InputError(f"the magnitude bin width must be zero or positive, got {bin_width!r}")
    if not 0 < confidence < 1:
        raise InputError(f"the confidence must lie between 0 and 1, got {confidence!r}")
    cutoff = float(values.min()) if completeness is None else float(completeness)
    kept = values[values >= cutoff - 1e-9 * max(1.0, abs(cutoff))]
    if kept.size < 2:
        raise InputError(f"a b-value needs at least two magnitudes at or above M_c = {cutoff:g}, got {kept.size}")
    origin = cutoff - bin_width / 2
    excess = float(np.sum(kept - origin))
    if not excess > 0 or float(np.ptp(kept)) <= 1e-9 * max(1.0, abs(cutoff)):  # equal to round-off: no spread
        raise InputError(f"every magnitude at or above M_c = {cutoff:g} equals it: the catalogue has no spread to give "
                         "a b-value")
    count = kept.size
    mean = float(kept.mean())
    b = math.log10(math.e) / (mean - origin)
    spread = float(np.sum((kept - mean) ** 2))
    alpha = 1 - confidence
    interval = (float(chi2.ppf(alpha / 2, 2 * count)) / (2 * excess * math.log(10)),
                float(chi2.ppf(1 - alpha / 2, 2 * count)) / (2 * excess * math.log(10)))
    return {"b": b, "aki_error": b / math.sqrt(count),
            "shi_bolt_error": 2.30 * b ** 2 * math.sqrt(spread / (count * (count - 1))),
            "interval": interval, "confidence": confidence, "count": int(count), "completeness": cutoff,
            "bin_width": float(bin_width), "mean_magnitude": mean, "a": math.log10(count) + b * cutoff}
