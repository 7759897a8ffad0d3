r"""The Gutenberg-Richter b-value of a catalogue by maximum likelihood, with its uncertainty.

Above a completeness magnitude M_c, Gutenberg-Richter's log10 N(>= M) = a - b M makes the magnitudes
exponential with rate beta = b ln 10. For continuous magnitudes Aki's (1965) maximum-likelihood estimate is

.. math:: \hat b = \frac{\log_{10} e}{\bar M - M_c},

with Aki's standard error \hat b / \sqrt{n} and Shi & Bolt's (1982)
2.30 \hat b^2 \sqrt{\sum (M_i - \bar M)^2 / (n (n - 1))}. Its interval is exact: S = \sum (M_i - M_c) is
Gamma(n, beta), so 2 beta S is chi-square with 2n degrees of freedom, and b lies in
[\chi^2_{2n}(\alpha/2), \chi^2_{2n}(1 - \alpha/2)] / (2 S \ln 10) with confidence 1 - alpha.

Magnitudes binned to \Delta M (M_c the lowest bin's centre) are geometric instead: k_i = (M_i - M_c) / \Delta M
takes k with probability p (1 - p)^k, 1 - p = 10^{-b \Delta M}. The exact maximum-likelihood estimate is Tinti &
Mulargia's (1987, BSSA 77, 2125; Bender 1983, BSSA 73, 831)

.. math:: \hat b = \frac{1}{\Delta M} \log_{10}\left(1 + \frac{\Delta M}{\bar M - M_c}\right),

which tends to Aki's as \Delta M -> 0. Utsu's (1966) shortcut, Aki's with M_c - \Delta M / 2, is biased low
where the bins are wide and b large, and its chi-square interval then misses the truth too often (measured in
docs/spring_chain.md). The geometric law's interval is exact too: K = \sum k_i is
negative binomial, so p lies between the Beta(n, K + 1) quantile alpha / 2 and the Beta(n, K) quantile
1 - alpha / 2 (the negative binomial's Clopper-Pearson bounds), and b = -log10(1 - p) / \Delta M is monotone
in p. Its standard error is p / (\Delta M \ln 10 \sqrt{n (1 - p)}), Aki's in the limit.
"""

from __future__ import annotations

import math

import numpy as np

from faultslip.errors import InputError


def b_value(magnitudes, completeness: float | None = None, bin_width: float = 0.0, confidence: float = 0.95) -> dict:
    """The maximum-likelihood b-value of the magnitudes at or above ``completeness``: Aki's for continuous
    magnitudes, Tinti & Mulargia's for binned ones (see the module).

    Parameters
    ----------
    magnitudes : array
        The catalogue's magnitudes.
    completeness : float, optional
        M_c: magnitudes below it are left out (default: the smallest magnitude). For binned magnitudes, the
        lowest bin's centre.
    bin_width : float
        Delta M, the binning of the magnitudes (0: continuous); the magnitudes must lie on its grid from M_c.
    confidence : float
        Of the interval.

    Returns
    -------
    dict
        ``b``, ``aki_error`` (the maximum-likelihood standard error: b / sqrt n for continuous magnitudes),
        ``shi_bolt_error``, ``interval`` (low, high), ``count``, ``completeness``, ``method``, ``mean_magnitude``
        and ``a`` (log10 of the count at or above M_c, plus b M_c).
    """
    from scipy.stats import beta as beta_distribution, chi2  # heavy: imported where used

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
    if not float(np.sum(kept - cutoff)) > 0 or float(np.ptp(kept)) <= 1e-9 * max(1.0, abs(cutoff)):
        raise InputError(f"every magnitude at or above M_c = {cutoff:g} equals it: the catalogue has no spread to give "
                         "a b-value")  # equal to round-off: no spread
    count = kept.size
    mean = float(kept.mean())
    spread = float(np.sum((kept - mean) ** 2))
    alpha = 1 - confidence
    if bin_width == 0:
        excess = float(np.sum(kept - cutoff))
        b = math.log10(math.e) / (mean - cutoff)
        error = b / math.sqrt(count)
        interval = (float(chi2.ppf(alpha / 2, 2 * count)) / (2 * excess * math.log(10)),
                    float(chi2.ppf(1 - alpha / 2, 2 * count)) / (2 * excess * math.log(10)))
        method = "Aki (1965), continuous magnitudes; exact chi-square interval"
    else:
        steps = (kept - cutoff) / bin_width
        off = float(np.max(np.abs(steps - np.round(steps))))
        if off > 1e-6:
            raise InputError(f"the magnitudes are not on a grid of {bin_width:g} from M_c = {cutoff:g} (one is "
                             f"{off * bin_width:.3g} off it): give M_c as a bin's centre and the bin width they were "
                             "rounded to, or bin width 0 for continuous magnitudes")
        total = float(np.sum(np.round(steps)))
        chance = count / (count + total)  # p, the maximum-likelihood geometric parameter
        b = -math.log10(1 - chance) / bin_width
        error = chance / (bin_width * math.log(10) * math.sqrt(count * (1 - chance)))
        low = float(beta_distribution.ppf(alpha / 2, count, total + 1))
        high = float(beta_distribution.ppf(1 - alpha / 2, count, total))
        interval = (-math.log10(1 - low) / bin_width, -math.log10(1 - high) / bin_width)
        method = "Tinti & Mulargia (1987), binned magnitudes; exact negative-binomial interval"
    return {"b": b, "aki_error": error, "shi_bolt_error": 2.30 * b ** 2 * math.sqrt(spread / (count * (count - 1))),
            "interval": interval, "confidence": confidence, "count": int(count), "completeness": cutoff,
            "method": method,
            "bin_width": float(bin_width), "mean_magnitude": mean, "a": math.log10(count) + b * cutoff}


#: The p-value below which a catalogue is said not to follow Gutenberg-Richter (Clauset, Shalizi & Newman 2009,
#: section 4.1: "if p <= 0.1 the power law is ruled out").
GR_P_THRESHOLD = 0.1
#: Fewest magnitudes above a candidate cutoff (CSN's scan stops where too few remain to fit).
MIN_ABOVE_CUTOFF = 20
#: Candidate cutoffs scanned at most (CSN scan every magnitude: for 10,000 events that is 1e8 comparisons).
CANDIDATES = 200


def exponential_ks_distance(excess, scale: float) -> float:
    """The Kolmogorov-Smirnov distance D between sorted excesses and the exponential of mean ``scale``.

    D = max over i of max(i / n - F(x_i), F(x_i) - (i - 1) / n), F(x) = 1 - exp(-x / scale) (e.g. Press et al.
    2007, section 14.3.3): scipy.stats.kstest's statistic, without the exact p-value it computes beside it,
    which the scan for M_c does not use and which costs most of a small catalogue's test.

    Parameters
    ----------
    excess : array
        Magnitudes above a cutoff, minus it, in ascending order.
    scale : float
        The exponential's mean, 1 / beta.
    """
    x = np.asarray(excess, float)
    n = x.size
    cdf = -np.expm1(-x / scale)
    ranks = np.arange(1, n + 1) / n
    return float(max(np.max(ranks - cdf), np.max(cdf - (ranks - 1.0 / n))))


def gr_test(magnitudes, samples: int = 999, seed: int = 0) -> dict:
    """Does a catalogue follow Gutenberg-Richter above some cutoff? Its b-value's goodness of fit.

    Above M_c, GR makes continuous magnitudes exponential with rate beta = b ln 10 (module docstring). Following
    Clauset, Shalizi & Newman (2009, SIAM Review 51, 661, section 3.3), M_c is the candidate (each magnitude with
    at least :data:`MIN_ABOVE_CUTOFF` above it) whose fitted exponential lies closest to the magnitudes above it
    in the Kolmogorov-Smirnov distance D. At that M_c the p-value is Monte Carlo (``samples`` draws, seeded):
    the share of exponential samples of the same size, each refitted, whose D is at least the catalogue's
    (scipy.stats.goodness_of_fit; the rate re-estimated in each draw, as Lilliefors 1969 does for the
    exponential). GR is ruled out where p <= :data:`GR_P_THRESHOLD`. The b-values at every candidate cutoff give
    the spread of b that the choice of M_c alone moves.

    Parameters
    ----------
    magnitudes : array
        Continuous magnitudes (a synthetic catalogue's Mw).
    samples : int
        Monte Carlo draws of the p-value.
    seed : int
        Their seed.

    Returns
    -------
    dict
        ``completeness`` (M_c), ``count`` above it, ``b`` there, ``ks_distance`` D, ``p_value``, ``holds``
        (p > 0.1), ``b_range`` (smallest and largest b over the candidate cutoffs), ``method``.
    """
    from scipy import stats  # heavy: imported where used

    values = np.sort(np.asarray(magnitudes, float).ravel())
    values = values[np.isfinite(values)]
    if values.size < MIN_ABOVE_CUTOFF:
        raise InputError(f"a Gutenberg-Richter test needs at least {MIN_ABOVE_CUTOFF} magnitudes, got {values.size}")
    # candidate cutoffs: the magnitudes that leave enough above them, at most CANDIDATES of them (evenly by rank)
    eligible = values[: values.size - MIN_ABOVE_CUTOFF + 1]
    picks = np.unique(np.linspace(0, eligible.size - 1, min(eligible.size, CANDIDATES)).round().astype(int))
    candidates = np.unique(eligible[picks])
    best, bs = None, []
    for cutoff in candidates:
        above = values[values >= cutoff]
        excess = above - cutoff
        if not excess.mean() > 0:
            continue
        scale = excess.mean()
        bs.append(math.log10(math.e) / scale)
        distance = exponential_ks_distance(excess, scale)
        if best is None or distance < best[1]:
            best = (float(cutoff), float(distance), above)
    if best is None:
        raise InputError("every magnitude is the same: no Gutenberg-Richter law to test")
    cutoff, distance, above = best
    fitted = stats.goodness_of_fit(stats.expon, above - cutoff, known_params={"loc": 0.0}, statistic="ks",
                                   n_mc_samples=samples, rng=np.random.default_rng(seed))
    p_value = float(fitted.pvalue)
    b = math.log10(math.e) / float(np.mean(above - cutoff))
    return {"completeness": cutoff, "count": int(above.size), "b": b, "ks_distance": distance, "p_value": p_value,
            "holds": p_value > GR_P_THRESHOLD, "b_range": (float(min(bs)), float(max(bs))),
            "method": (f"M_c by the least Kolmogorov-Smirnov distance (Clauset, Shalizi & Newman 2009); p-value from "
                       f"{samples} refitted exponential samples; Gutenberg-Richter ruled out at p <= "
                       f"{GR_P_THRESHOLD:g}")}
