r"""Fault-displacement hazard: the annual rate of exceeding a displacement at a site on a fault's trace.

For the ruptures k (annual rates r_k, magnitudes M_k) whose principal trace passes through the site, at
x_k / L_k along each, the probabilistic fault-displacement hazard of principal faulting is
(Youngs et al. 2003, Earthquake Spectra 19(1), 191-219, eq. 1; Petersen et al. 2011, BSSA 101(2), 805-825):

.. math:: \lambda(D > d) = \sum_k r_k \, P(\mathrm{sr} \mid M_k) \, P(D > d \mid x_k / L_k, \cdot),

- the probability that a rupture reaches the surface, P(sr | M) = e^{f} / (1 + e^{f}), f = -12.51 + 2.053 M
  (Wells & Coppersmith 1993, "Likelihood of surface rupture as a function of magnitude", SRL 64(1), 54);
- the displacement at the site, lognormal about an along-strike profile. Petersen et al. (2011) regress
  principal displacements of strike-slip ruptures (their elliptical ln(D) model):

  .. math:: \ln(D / \mathrm{cm}) = 3.3041\, x^* + 1.7927\, M - 11.2192, \quad \sigma = 1.1348,
            \quad x^* = \sqrt{1 - (x/L - 1/2)^2 / (1/2)^2}.

  ``petersen_2011`` uses it as it stands. ``faultslip`` keeps its shape and sigma and sets its level by
  faultslip's slip per event, read as the rupture's average displacement AD: the median is
  AD e^{b x^*} / <e^{b x^*}> e^{-\sigma^2/2}, so that the mean over the rupture of the expected
  displacement is AD (<.> the mean over x/L from 0 to 1, b = 3.3041).

All displacements are in m; rates in 1/yr.
"""

from __future__ import annotations

import math
import warnings
from functools import lru_cache

import numpy as np

from faultslip.errors import InputError
from faultslip.units import takes_units

#: Petersen et al. (2011), elliptical ln(D) model for principal displacement (D in cm)
PETERSEN_2011 = {"position": 3.3041, "magnitude": 1.7927, "constant": -11.2192, "sigma": 1.1348}
#: Wells & Coppersmith (1993): the logistic regression of surface rupture on magnitude
SURFACE_RUPTURE = {"constant": -12.51, "magnitude": 2.053}
#: The field's models through fdhpy (UCLA NHR3's implementations, MIT; ``pip install 'faultslip[fdh]'``): name ->
#: (fdhpy class, the styles of faulting it was regressed on, its metric, its version). Each gives P(D > d | M, x/L,
#: a surface rupture); faultslip weighs it by P(sr | M) as it does its own.
FDHPY_MODELS = {
    "youngs_2003": ("YoungsEtAl2003", ("normal",), "principal", "d/ad"),
    "moss_ross_2011": ("MossRoss2011", ("reverse",), "principal", "d/ad"),
    "lavrentiadis_abrahamson_2023": ("LavrentiadisAbrahamson2023", ("strike-slip", "reverse", "normal"), "aggregate",
                                     "full rupture"),
    "moss_2024": ("MossEtAl2024", ("reverse",), "principal", "d/ad"),
    "kuehn_2024": ("KuehnEtAl2024", ("strike-slip", "reverse", "normal"), "aggregate", "median_coeffs"),
    "chiou_2025": ("ChiouEtAl2025", ("strike-slip",), "sum-of-principal", "model7"),
    "petersen_2011_fdhpy": ("PetersenEtAl2011", ("strike-slip",), "principal", "elliptical"),
}
#: Every model, and ``logic_tree``: the models that apply to a rupture's style, equally weighted.
MODELS = ("faultslip", "petersen_2011") + tuple(FDHPY_MODELS) + ("logic_tree",)


def style_of(rake: float) -> str:
    """The style of faulting of a rake (degrees, Aki & Richards): reverse from 45 to 135, normal from -135 to -45,
    strike-slip otherwise (the fdhpy models' classes)."""
    rake = ((float(rake) + 180.0) % 360.0) - 180.0
    if 45.0 <= rake <= 135.0:
        return "reverse"
    if -135.0 <= rake <= -45.0:
        return "normal"
    return "strike-slip"


def applicable_models(style: str) -> list[str]:
    """The models that apply to ``style``: faultslip's own (its level from the fault's own slip), Petersen et al.
    (2011) for strike-slip, and each fdhpy model regressed on that style."""
    own = ["faultslip"] + (["petersen_2011"] if style == "strike-slip" else [])
    return own + [name for name, (_, styles, _, _) in FDHPY_MODELS.items() if style in styles
                  and name != "petersen_2011_fdhpy"]


def fdhpy_exceedance(name: str, displacements, magnitudes, positions, style: str) -> tuple[np.ndarray, list]:
    """(P(D > d | M, x/L, surface rupture) as (ruptures, displacements), notes) from fdhpy's model ``name``.

    Parameters
    ----------
    name : str
        A key of :data:`FDHPY_MODELS`.
    displacements : array
        d (m).
    magnitudes, positions : array
        Each rupture's Mw and the site's x/L along it.
    style : str
        strike-slip, reverse or normal.

    Returns
    -------
    tuple
        The probabilities, and notes (a magnitude outside the model's range is said, not hidden).
    """
    try:
        import fdhpy  # heavy: an optional extra (fdh), imported where used
    except ImportError:
        raise InputError(f"the displacement model {name} comes from fdhpy, which is not installed: pip install "
                         "'faultslip[fdh]'") from None
    model_class, styles, metric, version = FDHPY_MODELS[name]
    if style not in styles:
        raise InputError(f"{name} was regressed on {' and '.join(styles)} ruptures, not {style}; for {style}: "
                         f"{', '.join(applicable_models(style))}")
    cls = getattr(fdhpy, model_class)
    low, high = cls._CONDITIONS["style"][style].get("magnitude", (-math.inf, math.inf))
    d = np.asarray(displacements, float)
    rows, notes = [], []
    outside = [m for m in np.asarray(magnitudes, float) if not low <= m <= high]
    if outside:
        notes.append(f"{name}: Mw {', '.join(f'{m:.2f}' for m in outside)} outside its range {low:g}-{high:g}: "
                     "extrapolated")
    for magnitude, position in zip(np.asarray(magnitudes, float), np.asarray(positions, float)):
        kwargs = {"style": style, "magnitude": float(magnitude), "xl": float(position), "metric": metric,
                  "version": version, "displ_array": d}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # fdhpy warns of extrapolation; said above in a note instead
            rows.append(np.asarray(cls(**kwargs).prob_exceed, float))
    return np.clip(np.array(rows), 0.0, 1.0), notes


def surface_rupture_probability(magnitude):
    """P(sr | M) = e^f / (1 + e^f), f = -12.51 + 2.053 M (Wells & Coppersmith 1993)."""
    f = SURFACE_RUPTURE["constant"] + SURFACE_RUPTURE["magnitude"] * np.asarray(magnitude, dtype=float)
    return 1.0 / (1.0 + np.exp(-f))


def elliptical_position(position):
    """x* = sqrt(1 - (x/L - 1/2)^2 / (1/2)^2) for x/L from 0 to 1 (Petersen et al. 2011)."""
    position = np.asarray(position, dtype=float)
    if np.any((position < 0) | (position > 1)) or not np.all(np.isfinite(position)):
        raise InputError("a site's position along a rupture, x/L, must lie from 0 to 1")
    return np.sqrt(np.clip(1.0 - (position - 0.5) ** 2 / 0.25, 0.0, 1.0))


@lru_cache(maxsize=None)
def _mean_shape() -> float:
    """<e^{b x*}> over x/L from 0 to 1."""
    from scipy.integrate import quad  # heavy: imported where used

    b = PETERSEN_2011["position"]
    value, _ = quad(lambda u: math.exp(b * math.sqrt(max(1.0 - (u - 0.5) ** 2 / 0.25, 0.0))), 0.0, 1.0,
                    epsabs=0.0, epsrel=1e-13, limit=200)
    return value


def petersen_2011(magnitude, position):
    """(mean of ln D with D in m, sigma) of Petersen et al. (2011)'s elliptical model."""
    c = PETERSEN_2011
    mean_cm = (c["position"] * elliptical_position(position) + c["magnitude"] * np.asarray(magnitude, float)
               + c["constant"])
    return mean_cm - math.log(100.0), c["sigma"]


def faultslip_profile(average_displacement, position):
    """(mean of ln D with D in m, sigma): Petersen et al. (2011)'s elliptical shape and sigma with the level of
    faultslip's average displacement (see the module)."""
    average = np.asarray(average_displacement, dtype=float)
    if np.any(~(average > 0)):
        raise InputError("a rupture's average displacement must be positive")
    b, sigma = PETERSEN_2011["position"], PETERSEN_2011["sigma"]
    return (np.log(average) + b * elliptical_position(position) - math.log(_mean_shape()) - 0.5 * sigma ** 2,
            sigma)


def exceedance_probability(displacement, mean_log, sigma):
    """P(D > d) for D lognormal with ln D ~ N(mean_log, sigma^2); ``displacement`` (m) broadcast against the
    means (put displacements on a trailing axis)."""
    from scipy.special import ndtr  # heavy: imported where used

    d = np.asarray(displacement, dtype=float)
    if np.any(~(d > 0)):
        raise InputError("displacements must be positive lengths")
    return ndtr(-(np.log(d) - mean_log) / sigma)


@takes_units(displacements="length", rates=("rate", "1/yr"), average_displacements="length")
def displacement_hazard_curve(displacements, rates, magnitudes, positions, average_displacements=None,
                              model: str = "faultslip", surface_rupture: bool = True,
                              style: str = "strike-slip") -> np.ndarray:
    """Annual rate of exceeding each of ``displacements`` (m) at a site, summed over ruptures (see the module).

    Parameters
    ----------
    displacements : array
        Displacements d (m).
    rates : array
        Each rupture's annual rate (1/yr).
    magnitudes : array
        Each rupture's Mw.
    positions : array
        The site's x/L along each rupture.
    average_displacements : array, optional
        Each rupture's average displacement AD (m): ``faultslip``'s level; a leading axis of draws is summed
        separately (the result then has that axis too).
    model : str
        ``faultslip``, ``petersen_2011`` or one of :data:`FDHPY_MODELS` (through fdhpy).
    surface_rupture : bool
        Weigh each rupture by P(sr | M) (Wells & Coppersmith 1993); False takes every rupture to the surface.
    style : str
        The ruptures' style of faulting (strike-slip, reverse or normal), for the fdhpy models.

    Returns
    -------
    array
        lambda(D > d) (1/yr), one per displacement (and per draw).
    """
    if model not in MODELS or model == "logic_tree":
        raise InputError(f"the displacement model must be one of {', '.join(MODELS[:-1])}, got {model!r}"
                         + (" (the logic tree is displacement_hazard's)" if model == "logic_tree" else ""))
    rates, magnitudes = np.asarray(rates, float), np.asarray(magnitudes, float)
    positions = np.asarray(positions, float)
    if np.any(~(rates >= 0)):
        raise InputError("rupture rates must be zero or positive")
    weight = rates * (surface_rupture_probability(magnitudes) if surface_rupture else 1.0)
    d = np.asarray(displacements, float)
    if model in FDHPY_MODELS:
        if np.any(~(d > 0)):
            raise InputError("displacements must be positive lengths")
        probability, _ = fdhpy_exceedance(model, d, magnitudes, positions, style)
        return probability.T @ weight
    if model == "petersen_2011":
        mean_log, sigma = petersen_2011(magnitudes, positions)
    else:
        if average_displacements is None:
            raise InputError("the faultslip displacement model needs each rupture's average displacement")
        mean_log, sigma = faultslip_profile(average_displacements, positions)
    probability = exceedance_probability(d, np.asarray(mean_log)[..., None], sigma)  # (..., ruptures, d)
    return np.einsum("...kd,k->...d", probability, weight)
