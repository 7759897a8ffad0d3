"""The physical range of every named input, checked the same way wherever a value enters.

A value swept in a study, read from a map's table or given to ``faultslip fault`` passes the
same check, so a width of zero is refused everywhere with the same sentence. Values are SI
(after :func:`faultslip.units.to_si`); arrays are checked element by element and the first
offending value is named.
"""

from __future__ import annotations

import numpy as np

from faultslip.errors import InputError

POSITIVE = "positive"
NON_NEGATIVE = "non-negative"
DAMPING = "damping"  # |zeta| < 1: an oscillating slip phase (seed 003 eq. 2-8)
FINITE = "finite"

#: name -> (rule, label, SI unit for messages)
RULES: dict[str, tuple[str, str, str]] = {
    "shear_modulus": (POSITIVE, "shear modulus", "Pa"),
    "zone_width": (POSITIVE, "elastic-zone width", "m"),
    "normal_stress": (POSITIVE, "normal stress", "Pa"),
    "shear_stress": (POSITIVE, "shear stress", "Pa"),
    "slip_rate": (POSITIVE, "slip rate", "m/s"),
    "rupture_length": (POSITIVE, "rupture length", "m"),
    "seismogenic_depth": (POSITIVE, "seismogenic depth", "m"),
    "density": (POSITIVE, "density", "kg/m^3"),
    "shear_wave_speed": (POSITIVE, "shear-wave speed", "m/s"),
    "observed_slip": (POSITIVE, "observed slip", "m"),
    "mu_so": (POSITIVE, "mu_so", ""),
    "mu_m": (NON_NEGATIVE, "mu_m", ""),
    "b": (NON_NEGATIVE, "rate coefficient b", ""),
    "d": (POSITIVE, "rate exponent d", ""),
    "damping_ratio": (DAMPING, "damping ratio", ""),
    "platform_speed": (POSITIVE, "platform speed", "m/s"),
    "loading_rate": (POSITIVE, "loading rate", "1/s"),
    "kinetic_slope": (FINITE, "kinetic slope", "s/m"),
    "normal_load": (POSITIVE, "normal load", "N"),
    "stiffness": (POSITIVE, "stiffness", "N/m"),
    "mass": (POSITIVE, "mass", "kg"),
}


def _violates(rule: str, values: np.ndarray) -> np.ndarray:
    with np.errstate(invalid="ignore"):
        if rule == POSITIVE:
            return ~(values > 0) | ~np.isfinite(values)
        if rule == NON_NEGATIVE:
            return ~(values >= 0) | ~np.isfinite(values)
        if rule == DAMPING:
            return ~(np.abs(values) < 1)
        return ~np.isfinite(values)


_PHRASES = {
    POSITIVE: "must be positive",
    NON_NEGATIVE: "must not be negative",
    DAMPING: "must lie in (-1, 1) for an oscillating slip phase",
    FINITE: "must be finite",
}


def check(name: str, value, where: str = ""):
    """Raise :class:`InputError` unless ``value`` (SI, scalar or array) lies in the range of ``name``.

    ``where`` (e.g. ``"[sweep] zone_width in study.toml"``) is added to the sentence. Names
    without a rule pass. Returns ``value`` unchanged.
    """
    if name not in RULES:
        return value
    rule, label, unit = RULES[name]
    values = np.asarray(value, dtype=float)
    bad = _violates(rule, values)
    if np.any(bad):
        first = float(values[bad].flat[0]) if values.ndim else float(values)
        shown = f"{first:g} {unit}".rstrip()
        place = f" ({where})" if where else ""
        raise InputError(f"{label} {_PHRASES[rule]}, got {shown}{place}")
    return value


def check_friction_drop(mu_so, mu_m, where: str = ""):
    """Refuse mu_m >= mu_so: without a static excess there is no stick-slip to predict (eq. 2-18)."""
    so, m = np.broadcast_arrays(np.asarray(mu_so, dtype=float), np.asarray(mu_m, dtype=float))
    bad = ~(so > m)
    if np.any(bad):
        index = np.argwhere(bad)[0] if so.ndim else ()
        first_so, first_m = float(so[tuple(index)]), float(m[tuple(index)])
        place = f" ({where})" if where else ""
        raise InputError(f"mu_m = {first_m:g} is not below mu_so = {first_so:g}{place}: without a static excess "
                         "there is no stick-slip to predict; narrow the sweep so that mu_m < mu_so in every cell")
