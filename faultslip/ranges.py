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
#: the rules a function's own domain may name (:func:`faultslip.units.takes_units`'s ``domains``)
RULE_KINDS = (POSITIVE, NON_NEGATIVE, DAMPING, FINITE)

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
    "b_value": (POSITIVE, "Gutenberg-Richter b-value", ""),
    "element_size": (POSITIVE, "element size", "m"),
    "fault_length": (POSITIVE, "fault length", "m"),
    "area": (POSITIVE, "sample area", "m^2"),
    "reference_friction": (POSITIVE, "reference friction f0", ""),
    "critical_slip": (POSITIVE, "critical slip distance D_c", "m"),
    "plate_rate": (POSITIVE, "plate rate", "m/s"),
    "time_budget": (POSITIVE, "time budget FAULTSLIP_TIME_BUDGET", "s"),
    "machine_factor": (POSITIVE, "machine factor FAULTSLIP_MACHINE_FACTOR", ""),
    "initial_offset": (NON_NEGATIVE, "initial offset", "m"),
    "min_magnitude": (FINITE, "minimum magnitude", ""),
    "max_magnitude": (FINITE, "maximum magnitude", ""),
    "characteristic_magnitude": (FINITE, "characteristic magnitude", ""),
    "bin_width": (POSITIVE, "magnitude bin width", ""),
    # the Python API's unit-string arguments (faultslip.units.takes_units checks them by name)
    "slip": (POSITIVE, "slip", "m"),
    "slip_per_event": (POSITIVE, "slip per event", "m"),
    "seismic_moment": (POSITIVE, "seismic moment", "N m"),
    "width": (POSITIVE, "fault width", "m"),
    "radiation_damper": (NON_NEGATIVE, "radiation damper", "N s/m"),
}

#: Arguments named otherwise than the range they take (faultslip.units.takes_units)
ALIASES = {"rupture_length_m": "rupture_length"}

#: Bounds (inclusive, SI) beyond the rule: values outside them are not physical, or would overflow the
#: arithmetic done on them (an area of 1e-300 m^2 divides a load into infinity). Each bound says why.
BOUNDS: dict[str, tuple[float, float]] = {
    # elastic constants: a 1 kPa hydrogel (analogue friction experiments) to ten times diamond's 0.5 TPa; air to
    # ten times osmium; the slowest soils to ten times any rock's shear-wave speed
    "shear_modulus": (1e3, 1e13),
    "density": (0.1, 1e5),
    "shear_wave_speed": (1.0, 1e5),
    # lengths of a fault: 1 mm (a lab sample) to 10,000 km, longer than any plate boundary (a width of 1e300 km
    # made the stiffness G / D and the slider's frequency underflow to 0, and a run divide by it); depths to
    # 1,000 km, below the deepest earthquakes
    "zone_width": (1e-3, 1e7),
    "rupture_length": (1e-3, 1e7),
    "seismogenic_depth": (1e-3, 1e6),
    "observed_slip": (1e-9, 1e3),  # a nanometre (lab) to 1 km, 20 times the largest slip measured (~50 m)
    # stresses: 1 mPa (a sheet of paper resting on a table exerts ~0.1 Pa) to 100 GPa (the lower mantle)
    "normal_stress": (1e-3, 1e11),
    "shear_stress": (1e-3, 1e11),
    "slip_rate": (1e-15, 10.0),  # sub-mm per Myr to 10 m/s, above any seismic slip rate
    # friction: clean metals in vacuum reach a few; 100 bounds any coefficient measured
    "mu_so": (1e-6, 100.0),
    "mu_m": (0.0, 100.0),
    "b": (0.0, 1e9),  # seed 003 Table I: 1-300 s^d
    "d": (1e-3, 10.0),  # seed 003 Table I: 0.3-1.2
    # a lab slider: loads of a micronewton to a meganewton-scale rig (x1e3), stiffnesses and masses as wide, and
    # drive speeds to 100 m/s; a loading rate K V / N down to the fault scale's 1e-11 1/s and far below
    "platform_speed": (1e-15, 100.0),
    "loading_rate": (1e-20, 1e9),
    "normal_load": (1e-6, 1e12),
    "stiffness": (1e-6, 1e15),
    "mass": (1e-9, 1e12),
    "kinetic_slope": (-1e12, 1e12),
    "b_value": (0.2, 3.0),  # tectonic catalogues: 0.5-1.5; beyond, the GR balance loses its meaning
    "element_size": (1e-3, 1e5),  # 1 mm (lab faults) to 100 km
    "fault_length": (1.0, 1e7),  # 1 m to 10,000 km: longer than any plate boundary
    "area": (1e-10, 1e4),  # 10 um^2 (a micro-contact) to 1 ha (the largest rotary-shear rigs are ~1 m^2)
    "reference_friction": (1e-3, 3.0),  # rock friction lies near 0.6 (Byerlee); 3 bounds any measured value
    "critical_slip": (1e-9, 10.0),  # nm (nanoscale contacts) to 10 m (seismic slip weakening)
    "plate_rate": (1e-15, 1.0),  # from sub-mm per Myr to 1 m/s
    "time_budget": (1e-9, 1e9),  # up to 30 years of computing (a tiny budget refuses every run: tests use it)
    "initial_offset": (0.0, 1e4),  # a chain's blocks start within 10 km: beyond any analogue's slip (a lab chain's
    # um-mm, a fault patch's metres an event); 1e303 m overflowed the chain's event loop, which then never ended
    "machine_factor": (1e-3, 1e3),  # a machine a thousand times faster or slower than the one the costs were fitted on
    "min_magnitude": (-2.0, 10.5),  # what the engine's MFDs take
    "bin_width": (1e-3, 0.5),
    "max_magnitude": (-2.0, 10.5),
    "characteristic_magnitude": (-2.0, 10.5),
    # the Python API's unit strings: slips as observed_slip's; a moment from Mw -10 (a lab's acoustic emission is
    # near -8) to Mw 10.5, the magnitudes above, with M0 = 10^(1.5 Mw + 9.1) N m; a fault's width as a zone's
    "slip": (1e-9, 1e3),
    "slip_per_event": (1e-9, 1e3),
    "seismic_moment": (1e-6, 1e25),
    "width": (1e-3, 1e7),
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


def check(name: str, value, where: str = "", bounded: bool = True):
    """Raise :class:`InputError` unless ``value`` (SI, scalar or array) lies in the range of ``name``.

    ``where`` (e.g. ``"[sweep] zone_width in study.toml"``) is added to the sentence. Names
    without a rule pass. ``bounded`` False checks the rule alone, not :data:`BOUNDS` (a value in
    another unit than the rule's: a fault's stiffness in Pa/m). Returns ``value`` unchanged.
    """
    if name not in RULES:
        return value
    rule, label, unit = RULES[name]
    values = _checked(name, rule, value, where)
    if bounded and name in BOUNDS:
        low, high = BOUNDS[name]
        outside = (values < low) | (values > high)
        if np.any(outside):
            first = float(values[outside].flat[0]) if values.ndim else float(values)
            place = f" ({where})" if where else ""
            raise InputError(f"{label} must lie between {low:g} and {high:g} {unit}".rstrip()
                             + f", got {first:g} {unit}".rstrip() + place)
    return value


def check_rule(name: str, rule: str, value, where: str = ""):
    """Raise :class:`InputError` unless ``value`` meets ``rule`` (:data:`RULE_KINDS`), said with the label and unit
    of ``name``'s rule: a function defined beyond a scene's range (a loading rate of 0) checks its own domain."""
    _checked(name, rule, value, where)
    return value


def _checked(name: str, rule: str, value, where: str) -> np.ndarray:
    """``value`` as a float array, once it meets ``rule``; else one sentence with ``name``'s label and unit."""
    _, label, unit = RULES[name]
    place = f" ({where})" if where else ""
    try:
        values = np.asarray(value, dtype=float)
    except (TypeError, ValueError):  # text, None, a mapping: one sentence, not numpy's conversion error
        raise InputError(f"{label} must be a number, got {value!r}{place}") from None
    bad = _violates(rule, values)
    if np.any(bad):
        first = float(values[bad].flat[0]) if values.ndim else float(values)
        raise InputError(f"{label} {_PHRASES[rule]}, got {f'{first:g} {unit}'.rstrip()}{place}")
    return values


def parse_number(name: str, text, where: str = "") -> float:
    """A number given as text (an option, an environment variable) checked against the range of ``name``."""
    try:
        value = float(str(text).strip())
    except ValueError:
        label = RULES[name][1] if name in RULES else name
        raise InputError(f"{label} must be a number, got {text!r}{f' ({where})' if where else ''}") from None
    return check(name, value, where)


#: The most bootstrap resamples a fit takes: beyond it the intervals no longer move, and the time grows.
MOST_RESAMPLES = 100_000


def check_count(value, label: str, lowest: int = 0, highest: int | None = None) -> int:
    """A whole number (a resample count, a seed; 200.0 is 200) from ``lowest`` to ``highest``, as an int; anything
    else (text, a fraction, a boolean, out of range) is refused in one sentence naming ``label`` (``"--bootstrap"``)."""
    real = isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, (bool, np.bool_))
    whole = real and bool(np.isfinite(value)) and float(value).is_integer()  # 200.0 is 200, as a count reads
    if whole and value >= lowest and (highest is None or value <= highest):
        return int(value)
    span = f"from {lowest} to {highest}" if highest is not None else f"of at least {lowest}"
    raise InputError(f"{label} must be a whole number {span}, got {value!r}")


def check_tolerance(tolerance, where: str = "", label: str = "tolerance") -> float | None:
    """A requested relative error in (0, 1), from a number or text (``"0.1"``, ``"1e-3"``, ``"10 %"``); None stays
    None (no tolerance). Every method's choice and every front door refuses the rest in one sentence.

    Parameters
    ----------
    tolerance : float, str, dimensionless pint Quantity or None
        The relative error.
    where : str
        Where it was given (added to the sentence).
    label : str
        What the sentence calls it.

    Returns
    -------
    float or None
        The tolerance, dimensionless.
    """
    if tolerance is None:
        return None
    value = None
    if isinstance(tolerance, str):
        text = tolerance.strip()
        percent = text.endswith("%")
        try:
            value = float(text[:-1].strip()) / 100 if percent else float(text)
        except ValueError:
            value = None
    elif isinstance(tolerance, (int, float, np.integer, np.floating)) and not isinstance(tolerance, bool):
        value = float(tolerance)
    elif getattr(tolerance, "dimensionless", False) and np.ndim(getattr(tolerance, "magnitude", None)) == 0:
        value = float(tolerance.to("dimensionless").magnitude)  # a pint Quantity: 10 percent, 0.1
    if value is None or not 0 < value < 1:
        place = f" ({where})" if where else ""
        raise InputError(f"{label} must be a relative error between 0 and 1 (0.1, 1e-3 or 10 %), got "
                         f"{tolerance!r}{place}")
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
