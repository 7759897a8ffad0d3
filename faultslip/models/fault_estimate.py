"""``faultslip fault``: a fault's estimate from quantities with units, by the model its lithology calls for.

A lithology or preset with the seed's rate law gives seed 003's estimate (§5-2; or, with an observed slip,
the inverse for mu_m); a rate-and-state fit saved in the registry gives one quasi-dynamic rate-and-state block
with the seed law beside it. The command line and :func:`faultslip.run` with keywords both come here.
"""

from __future__ import annotations

from faultslip.errors import InputError
from faultslip.fault.rate_state_fault import estimate_fault_from_fit
from faultslip.fault.scaling import Fault
from faultslip.friction.materials import resolve_material
from faultslip.contract.registry import load
from faultslip.contract.result import Result, judge_tolerance

#: the seed law's own inputs, which a rate-and-state fit does not take
SEED_LAW_ONLY = ("mu_so", "mu_m", "b", "d", "damping_ratio")


def fault_estimate(lithology: str | None = None, *, method: str | None = None, tolerance: float | None = None,
                   observed_slip=None, seed_law: str | None = None, radiation_damping: bool = False,
                   name: str = "fault", **quantities) -> Result:
    """A fault's slip per event and recurrence from its quantities (``faultslip fault``).

    Parameters
    ----------
    lithology : str, optional
        A lithology, a Table I preset or a saved fit (``faultslip materials``).
    method, tolerance : optional
        The seed law's method and relative error allowed.
    observed_slip : str or Quantity, optional
        An observed slip per event ("21 ft"): the inverse for the kinetic friction mu_m.
    seed_law : str, optional
        Beside a rate-and-state fit, the seed-law lithology estimated on the same fault (default granodiorite).
    radiation_damping : bool
        The radiation damper G / (2 c_s) on the seed law's fault.
    name : str
        A name for the report.
    **quantities
        ``zone_width``, ``slip_rate``, ``shear_modulus``, ``normal_stress`` or ``shear_stress``,
        ``rupture_length``, ``seismogenic_depth``, ``density``, ``shear_wave_speed`` with units; the seed law's
        ``mu_so``, ``mu_m``, ``b``, ``d`` and ``damping_ratio`` as numbers.

    Returns
    -------
    Result
        Slip per event (m), recurrence (s), moment and magnitude where the rupture is given, the method, and
        whether its declared error meets ``tolerance``.
    """
    return judge_tolerance(_estimate(lithology, method, tolerance, observed_slip, seed_law, radiation_damping, name,
                                     quantities), tolerance)


def _estimate(lithology, method, tolerance, observed_slip, seed_law, radiation_damping, name, quantities) -> Result:
    """:func:`fault_estimate`'s answer, by the model its lithology calls for."""
    for key in ("zone_width", "slip_rate"):
        if key not in quantities:
            raise InputError(f"missing --{key.replace('_', '-')}, required for a fault estimate")
    if lithology and resolve_material(lithology).rate_state is not None:
        extra = [key for key in SEED_LAW_ONLY if quantities.get(key) is not None]
        extra += [key for key, value in (("observed_slip", observed_slip), ("method", method),
                                         ("radiation_damping", radiation_damping)) if value]
        if extra:
            flags = ", ".join("--" + key.replace("_", "-") for key in extra)
            raise InputError(f"{flags} do not apply to the rate-and-state fit {lithology!r} (its fault is always "
                             "quasi-dynamic, with the radiation damper)")
        estimate = estimate_fault_from_fit(lithology, quantities, seed_law=seed_law or "granodiorite")
        report = estimate.report(f"faultslip fault: {name} (rate-and-state fit {lithology!r})")
        # on the family's ladder: its model error against the 2-D fault declared, a tolerance it misses escalated
        return load("rate_state_slider").adopt(estimate, report, name, tolerance=tolerance)
    if seed_law:
        raise InputError("--seed-law goes with a rate-and-state fit as --lithology")
    fault = Fault(lithology=lithology, radiation_damping=radiation_damping, name=name,
                  **{key: value for key, value in quantities.items() if value is not None})
    if observed_slip is not None:
        return Result("spring_slider", fault.infer_kinetic_friction(observed_slip).report())
    return Result("spring_slider", fault.estimate(method=method or "auto", tolerance=tolerance).report())
