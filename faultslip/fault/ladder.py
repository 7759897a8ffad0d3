"""The ladder of fault models: one description of a fault, the one slider derived from it, and the correction and
95 % ranges that the 2-D fault calibrates (issue 68).

Every rung reads one description of the fault, its friction with depth (:class:`FaultDescription`). The one slider
is derived from it, not stated beside it:

* the **rupture zone** is the contiguous velocity-weakening run of the profile (a < b), of width W, buried
  under a velocity-strengthening cap of depth d_cap (0: the fault breaks the surface);
* the **block** carries the zone's mean a, b, D_c and sigma_n, and the stiffness of a surface-breaking crack of
  width W, K = 2 G / (pi W) (Knopoff 1958; Scholz 2019, eq. 4.26), with the radiation damper G / (2 c_s);
* its recurrence T_block and slip per event s_block are then **corrected** by what the 2-D fault shows over a
  calibrated box (``benchmarks/ladder_calibration.py``): ln(T_2d / T_block) and ln(s_2d / s_block) are linear in
  the groups that move the 2-D answer (:func:`groups`), fitted by least squares over 2-D designs, and the
  **95 % range** is the regression's prediction interval (t quantile, leverage included).

Outside the box, where some group lies beyond the values the calibration designs span, nothing is declared: the
block is reported with no range, and a tolerance moves the run to the 2-D rung. On a dipping fault among those
measured in plane strain, the block is corrected against plane strain directly (:mod:`faultslip.fault.dip_slider`);
on another, the antiplane range widens by the antiplane rung's dip error (:mod:`faultslip.fault.dip_error`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from faultslip.dynamics.rate_state.slider import RateStateSlider, fault_cycles
from faultslip.contract.result import Result
from faultslip.fault import dip_error, dip_slider, regression
from faultslip.fault.one_slider_error import range_within
from faultslip.errors import InputError
from faultslip.friction.rate_state import RateStateLaw, nucleation_size
from faultslip.io.report import Report
from faultslip.io.resources import read_bundled_table

CALIBRATION_FILE = "ladder_calibration.json"

#: The groups the correction is linear in, in this order after the constant (see :func:`features`).
FEATURES = ("log_width_over_nucleation", "log_width_over_nucleation_squared", "log_width_over_process_zone",
            "burial", "ramp", "log_strengthening_depth", "strengthening_ratio")
#: The ladder's lowest rung as a method ('faultslip methods'): every fault family's run takes it by this name.
ONE_SLIDER_METHOD = {
    "name": "one_slider",
    "friction_laws": "rate-and-state (aging or slip law): one quasi-dynamic spring-block for the whole fault",
    "domain": "a fault scene (2-D or 3-D): the block derived from its friction profile, the rupture zone's mean a, b, "
              "D_c and sigma_n with K = 2 G / (pi W), corrected where the fault's groups lie inside what the "
              "calibration faults span (outside: the uncorrected block, no range, no declared error); a block scene: "
              "its own block, K = c G / W (or the seed's G / D)",
    "cost_model": "one block's earthquake cycles: milliseconds (faultslip.models.rate_state_slider.cost)",
    "declared_error": "the 95 % range of recurrence and slip per event against the 2-D fault of the same scene, in "
                      "years and metres (the calibration's prediction interval: faultslip.fault.ladder.declared_error; "
                      "docs/ladder.md measures it on held-out faults); on a dipping fault among those measured in "
                      "plane strain, its own calibration against plane strain (faultslip.fault.dip_slider, "
                      "docs/dipping_faults.md), elsewhere the antiplane range widened by the dip error; compounded "
                      "with the 2-D fault's against the 3-D one on a 3-D scene"}
#: The quantities the one slider predicts, and what each is in the 2-D fault's report.
QUANTITIES = {"recurrence": "recurrence_interval", "mean_slip": "mean_slip_per_event",
              "surface_slip": "slip_per_event"}


@dataclass(frozen=True)
class FaultDescription:
    """A fault as every rung reads it: friction on elements down dip, elasticity and loading (SI).

    ``depth`` holds the element centres (m, down dip from the free surface: the depth on a vertical fault) of
    elements ``element_size`` long; ``a``,
    ``b``, ``critical_slip`` (D_c, m) and ``normal_stress`` (sigma_n, Pa) are the friction there. Below the last
    element the fault slips steadily at ``plate_rate``.
    """

    depth: np.ndarray
    a: np.ndarray
    b: np.ndarray
    critical_slip: np.ndarray
    normal_stress: np.ndarray
    element_size: float
    shear_modulus: float
    shear_wave_speed: float
    plate_rate: float
    reference_speed: float = 1e-6
    reference_friction: float = 0.6
    evolution: str = "aging"
    name: str = "fault"
    plane: str = "antiplane"  # or "strain": slip down dip on a fault dipping ``dip`` degrees (SEAS BP3)
    dip: float = 90.0
    sense: str = "thrust"  # plane strain: thrust or normal
    poisson_ratio: float = 0.25

    @property
    def width(self) -> float:
        """W_f, the frictional fault's depth extent (m)."""
        return self.element_size * self.depth.size


def rupture_zone(fault: FaultDescription) -> slice:
    """The elements of the widest contiguous velocity-weakening run (a < b): the zone that ruptures.

    Raises
    ------
    InputError
        Where no element weakens: the fault creeps and no rung has earthquakes.
    """
    weakening = np.asarray(fault.a < fault.b)
    if not weakening.any():
        raise InputError(f"{fault.name}: a >= b at every depth; the fault creeps and has no earthquakes")
    edges = np.flatnonzero(np.diff(np.concatenate(([0], weakening.astype(int), [0]))))
    starts, ends = edges[::2], edges[1::2]
    widest = int(np.argmax(ends - starts))
    return slice(int(starts[widest]), int(ends[widest]))


def groups(fault: FaultDescription) -> dict:
    """The nondimensional groups that move a 2-D fault's answer, from its profile.

    Returns
    -------
    dict
        ``width`` W (m) of the rupture zone and its mean ``a``, ``b``, ``critical_slip`` (m), ``normal_stress`` (Pa);
        ``nucleation_size`` h* = (pi / 2) G D_c b / [sigma_n (b - a)^2] (Rubin & Ampuero 2005) and
        ``process_zone`` L_b = G D_c / (sigma_n b) (m); ``width_over_nucleation`` W / h*,
        ``width_over_process_zone`` W / L_b; ``burial``: the strengthening cap's depth over W; ``ramp``: the depth
        below the zone over which a rises to 95 % of its largest value below, over W; ``strengthening_depth``:
        the frictional fault below the zone, over W; ``strengthening_ratio``: (a - b) of the strengthening zone
        below at its largest over (b - a) of the rupture zone (all dimensionless).
    """
    zone = rupture_zone(fault)
    size = fault.element_size
    width = (zone.stop - zone.start) * size
    a, b = float(fault.a[zone].mean()), float(fault.b[zone].mean())
    critical_slip, sigma = float(fault.critical_slip[zone].mean()), float(fault.normal_stress[zone].mean())
    modulus = fault.shear_modulus
    nucleation = nucleation_size(modulus, critical_slip, a, b, sigma)
    process = modulus * critical_slip / (sigma * b)
    below_a, below_b = fault.a[zone.stop:], fault.b[zone.stop:]
    if below_a.size:
        excess = below_a - below_b
        largest = float(excess.max())
        reach = float(below_a.min()) + 0.95 * (float(below_a.max()) - float(below_a.min()))
        ramp = (int(np.argmax(below_a >= reach)) + 1) * size
    else:
        largest, ramp = 0.0, 0.0
    return {"width": width, "a": a, "b": b, "critical_slip": critical_slip, "normal_stress": sigma,
            "nucleation_size": nucleation, "process_zone": process,
            "width_over_nucleation": width / nucleation, "width_over_process_zone": width / process,
            "burial": zone.start * size / width, "ramp": ramp / width,
            "strengthening_depth": (fault.depth.size - zone.stop) * size / width,
            "strengthening_ratio": max(largest, 0.0) / (b - a)}


def features(group: dict) -> np.ndarray:
    """The regression's row for a fault's groups: 1, then :data:`FEATURES` in order."""
    ratio = math.log(group["width_over_nucleation"])
    return np.array([1.0, ratio, ratio ** 2, math.log(group["width_over_process_zone"]), group["burial"],
                     group["ramp"], math.log1p(group["strengthening_depth"]), group["strengthening_ratio"]])


def block_stiffness(width: float, shear_modulus: float) -> float:
    """K = 2 G / (pi W): a surface-breaking mode-III crack of width W under uniform stress drop, mirrored in the
    free surface (Knopoff 1958; Scholz 2019, eq. 4.26), in Pa/m."""
    return 2.0 * shear_modulus / (math.pi * width)


def derived_block(fault: FaultDescription) -> tuple[RateStateSlider, dict]:
    """The one slider a fault description stands for: its rupture zone's mean friction at K = 2 G / (pi W).

    Returns
    -------
    tuple
        (the :class:`RateStateSlider`, with the radiation damper; the fault's :func:`groups`).
    """
    group = groups(fault)
    law = RateStateLaw(group["a"], group["b"], group["critical_slip"], fault.reference_friction,
                       fault.reference_speed, fault.evolution, source=f"{fault.name}: rupture-zone means")
    stiffness = block_stiffness(group["width"], fault.shear_modulus)
    slider = RateStateSlider.at_fault(law, fault.shear_modulus, fault.shear_modulus / stiffness,
                                      group["normal_stress"], density=fault.shear_modulus / fault.shear_wave_speed ** 2,
                                      shear_wave_speed=fault.shear_wave_speed)
    return slider, group


def block_answer(fault: FaultDescription, cycles: int = 5) -> tuple[dict, dict]:
    """The derived block's uncorrected recurrence (s) and slip per event (m), and the fault's groups."""
    slider, group = derived_block(fault)
    block = fault_cycles(slider, fault.plate_rate, cycles=cycles)
    return {"recurrence": float(block.recurrence), "slip": float(np.mean(block.slip_per_event))}, group


@lru_cache(maxsize=1)
def load_calibration() -> dict:
    """The shipped calibration of the derived block against the 2-D fault (``data/ladder_calibration.json``,
    written by ``benchmarks/ladder_calibration.py``).

    Returns
    -------
    dict
        Per quantity of :data:`QUANTITIES`: ``coefficients``, ``inverse_gram`` (X^T X)^-1, ``residual_sd``,
        ``dof`` and ``t_quantile``; ``box`` (each feature's calibrated range); ``held_out`` and ``provenance``.
    """
    table = read_bundled_table(CALIBRATION_FILE, "the ladder's calibration", "benchmarks/ladder_calibration.py")
    missing = [key for key in ("recurrence", "mean_slip", "box") if not isinstance(table.get(key), dict)]
    if missing:
        raise InputError(f"{CALIBRATION_FILE} lacks {', '.join(missing)}; rerun benchmarks/ladder_calibration.py")
    return table


def outside_box(group: dict, calibration: dict) -> list[str]:
    """The groups of a fault that lie outside the calibrated box, as sentences (empty: inside)."""
    row = dict(zip(FEATURES, features(group)[1:]))
    out = []
    for name, (low, high) in calibration["box"].items():
        value = row[name]
        if not low <= value <= high:
            out.append(f"{name} = {value:.3g} (calibrated {low:.3g} to {high:.3g})")
    return out


def predict(quantity: str, raw: float, group: dict, calibration: dict, level: float = 0.95) -> dict:
    """The corrected value of ``quantity`` and its range at ``level`` from the regression.

    The log of 2-D over block is x . beta; the range is exp(+- t s sqrt(1 + x^T (X^T X)^-1 x)) about it, the
    ordinary least-squares prediction interval (e.g. Montgomery, Peck & Vining 2012, eq. 3.55).

    Returns
    -------
    dict
        ``value``, ``low``, ``high`` (the quantity's units), ``half_width`` (relative: exp(t s ...) - 1).
    """
    if level != 0.95:
        raise InputError("the ladder's ranges are calibrated at 95 %")
    return regression.corrected(raw, features(group), calibration[quantity])


def fit(rows: list[dict], targets: np.ndarray, level: float = 0.95) -> dict:
    """Least squares of ``targets`` (ln 2-D / block) on the rows' :func:`features`, with what the prediction
    interval needs (:func:`faultslip.fault.regression.least_squares`)."""
    return regression.least_squares(np.array([features(row) for row in rows]), targets, level)


def box_of(rows: list[dict]) -> dict:
    """Each feature's calibrated range over the calibration faults' groups."""
    table = np.array([features(row)[1:] for row in rows])
    return {name: [float(table[:, k].min()), float(table[:, k].max())] for k, name in enumerate(FEATURES)}


def clamped_recurrence(raw: float, group: dict, calibration: dict) -> float:
    """The block's recurrence ``raw`` (s) corrected at the nearest point of the calibrated box: each group clamped
    to its calibrated range (and the square of ln W/h* taken of the clamped value), so that the correction is never
    extrapolated. A budget's expectation for a fault outside the box, not a declared answer."""
    x = features(group)
    for k, name in enumerate(FEATURES, start=1):
        low, high = calibration["box"][name]
        x[k] = min(max(x[k], low), high)
    x[FEATURES.index("log_width_over_nucleation_squared") + 1] = x[FEATURES.index("log_width_over_nucleation") + 1] ** 2
    return raw * math.exp(float(x @ np.asarray(calibration["recurrence"]["coefficients"], float)))


def expected_recurrence(fault: FaultDescription, calibration: dict | None = None) -> float:
    """The recurrence (s) the one-slider rung expects of a fault: the corrected block inside the calibrated box,
    and outside it the correction at the box's nearest point (:func:`clamped_recurrence`): what a run's budget
    counts its events by. On 14 faults below the box (W / h* 0.55-1.2, ``benchmarks/ladder_outside_box.py``) the
    clamped correction's worst fault lay nearer its 2-D recurrence than the block's, or the block times the
    calibration's median ratio (which the budget had taken, short on every fault): docs/ladder.md."""
    table = calibration or load_calibration()
    raw, group = block_answer(fault, cycles=2)
    if _dip_calibrated(fault, group):
        return _dip_bands(raw, group, fault)["recurrence"]["value"]
    if outside_box(group, table):
        return clamped_recurrence(raw["recurrence"], group, table)
    return predict("recurrence", raw["recurrence"], group, table)["value"]


def one_slider_report(fault: FaultDescription, reason: str, calibration: dict | None = None):
    """The one-slider rung on a fault description: the derived block, corrected, with its 95 % ranges.

    Parameters
    ----------
    fault : FaultDescription
        The fault, as every rung reads it.
    reason : str
        Why this rung runs (said in the report).
    calibration : dict, optional
        The calibration (the shipped one otherwise, :func:`load_calibration`).

    Returns
    -------
    Report
        ``recurrence_interval`` (s) with ``recurrence_range``, ``mean_slip_per_event`` (m, over the rupture zone)
        with its range and, on a surface-breaking fault, ``slip_per_event`` (m, at the surface) with
        ``slip_per_event_range``; the block's uncorrected answers, its groups, ``estimated_relative_error`` (the
        widest range's half-width, relative) and the median bias; outside the calibrated box, the uncorrected
        block with no ranges and no declared error.
    """
    table = calibration or load_calibration()
    raw, group = block_answer(fault)
    report = Report(f"faultslip one slider: {fault.name}")
    report.add("method", "one_slider").add("method_reason", reason)
    report.add("rupture_width", group["width"], "m", also=("km",), label="rupture zone W (velocity-weakening, a < b)")
    report.add("stiffness", block_stiffness(group["width"], fault.shear_modulus), "Pa/m",
               label="the block's stiffness K = 2 G / (pi W)")
    report.add("width_over_nucleation", group["width_over_nucleation"], label="W / h*")
    report.add("width_over_process_zone", group["width_over_process_zone"], label="W / L_b")
    report.add("burial", group["burial"], label="strengthening cap over W (0: breaks the surface)")
    report.add("block_recurrence", raw["recurrence"], "s", also=("yr",), label="the block's recurrence, uncorrected")
    report.add("block_slip_per_event", raw["slip"], "m", label="the block's slip per event, uncorrected")
    direct = _dip_calibrated(fault, group)
    if direct:  # a dipping fault among those measured in plane strain: the block corrected against it directly
        bands, dipping = _dip_bands(raw, group, fault), 0.0
    else:
        outside = outside_box(group, table)
        if fault.plane == "strain":
            report.note("the dipping faults measured in plane strain (benchmarks/dip_slider_calibration.py) do not "
                        "span this one: " + "; ".join(dip_slider.outside(group, fault.dip, fault.sense))
                        + ", so its ranges are the antiplane calibration's widened by the antiplane fault's error")
        if outside:
            return _no_range(report, raw, outside)
        bands = _bands(raw, group, table)
        dipping = _dip_error(fault, group)
        if not dipping < 1.0:  # unmeasured, or so large that it bounds the plane-strain answer from below only
            return _no_dip_range(report, bands, fault, group, dipping)
        bands = {name: _widened(band, dipping) for name, band in bands.items()}  # against plane strain
    report.add("recurrence_interval", bands["recurrence"]["value"], "s", also=("yr",),
               label="recurrence of system-size events (the block corrected by the 2-D calibration)")
    report.add("recurrence_range", [bands["recurrence"]["low"], bands["recurrence"]["high"]], "s", also=("yr",),
               label="95 % range of the recurrence")
    if "surface_slip" in bands:
        report.add("slip_per_event", bands["surface_slip"]["value"], "m", label="surface slip per event")
        report.add("slip_per_event_range", [bands["surface_slip"]["low"], bands["surface_slip"]["high"]], "m",
                   label="95 % range of the surface slip per event")
    report.add("mean_slip_per_event", bands["mean_slip"]["value"], "m", label="slip per event, mean over the rupture zone")
    report.add("mean_slip_per_event_range", [bands["mean_slip"]["low"], bands["mean_slip"]["high"]], "m",
               label="95 % range of the mean slip per event")
    if "surface_slip" not in bands:
        report.add("slip_per_event_range", None, label="95 % range of the surface slip (none: a buried fault, or a "
                                                       "dipping one whose dip error leaves it no upper end; see "
                                                       "mean_slip_per_event_range)")
    widest = max(band["half_width"] for band in bands.values())
    report.add("estimated_relative_error", widest,
               label="declared model error against the 2-D fault: the widest 95 % range's half-width (relative)")
    fitted = dip_slider.load_table() if direct else table
    report.add("median_bias", fitted["recurrence"]["median_bias_corrected"],
               label="median bias of the corrected recurrence over the calibration faults")
    report.add("calibrated_against", "the 2-D fault in plane strain" if direct else "the 2-D fault in antiplane strain",
               label="the rung the correction and its ranges were fitted to")
    if dipping:
        report.add("dip_model_error", dipping, label=f"the antiplane fault's model error on a {fault.dip:g}-degree "
                                                     "dip-slip fault, in the ranges (benchmarks/dip_model_error.py)")
    years = 365.25 * 86400.0
    t = bands["recurrence"]
    source = (f"{fitted['recurrence']['faults']} dipping 2-D faults in plane strain "
              "(benchmarks/dip_slider_calibration.py)" if direct else
              f"{table['provenance'].get('calibration_faults', '?')} 2-D faults (benchmarks/ladder_calibration.py)")
    report.note(f"T = {t['value'] / years:.0f} yr ({t['low'] / years:.0f}-{t['high'] / years:.0f} yr, 95 %): the block "
                f"derived from the fault's profile, corrected by {source}; the range is the correction's prediction "
                "interval, tested on faults held out of it")
    limits = table.get("limits")
    if limits and not direct:  # why the range is as wide as it is (docs/ladder.md, "What limits the range")
        longer = math.exp(limits["recurrence"]["mean_residual_interleaving"] - limits["recurrence"]["mean_residual_single"])
        report.note(f"the range is wide because the 2-D fault's sequences are of two kinds that the block cannot tell "
                    f"apart: on {limits['calibration_interleaving']} of {limits['calibration_faults']} calibration "
                    "faults it interleaves smaller events that do not break the zone, and there its system-size "
                    f"recurrence is {100 * (longer - 1):.0f} % longer than where every event breaks it. For a "
                    "narrower answer run the 2-D fault (--model fault_2d)")
    return report


def _no_range(report: Report, raw: dict, outside: list) -> Report:
    """The report of a fault outside the calibrated box: the uncorrected block, no range, no declared error."""
    report.add("recurrence_interval", raw["recurrence"], "s", also=("yr",),
               label="recurrence: the block's, uncorrected (outside the calibration: no range)")
    report.add("mean_slip_per_event", raw["slip"], "m", label="slip per event: the block's, uncorrected")
    report.add("recurrence_range", None, label="95 % range of the recurrence (none: outside the calibration)")
    report.add("slip_per_event_range", None, label="95 % range of the slip per event (none: outside the calibration)")
    report.add("estimated_relative_error", None, label="declared model error (none: outside the calibration)")
    report.note("outside the calibrated box, so no range is declared: " + "; ".join(outside)
                + ". Run the 2-D fault (--model fault_2d) for an answer with a declared error")
    return report


def _no_dip_range(report: Report, bands: dict, fault: FaultDescription, group: dict, dipping: float) -> Report:
    """The report of a dipping fault whose antiplane fault's error leaves no range: the corrected block alone."""
    report.add("recurrence_interval", bands["recurrence"]["value"], "s", also=("yr",),
               label="recurrence (the block corrected by the 2-D calibration; no range on this dip)")
    report.add("mean_slip_per_event", bands["mean_slip"]["value"], "m", label="slip per event, mean over the rupture zone")
    report.add("recurrence_range", None, label="95 % range of the recurrence (none on this dip and W / h*)")
    report.add("slip_per_event_range", None, label="95 % range of the slip per event (none)")
    report.add("estimated_relative_error", None, label="declared model error (none on this dip and W / h*)")
    why = (dip_error.why_undeclared(fault.dip, group["width_over_nucleation"]) if not math.isfinite(dipping)
           else f"and the antiplane rung's declared error on such a fault is {dipping:.0%}, which leaves the "
                "plane-strain answer no upper bound")
    report.note(f"the fault dips {fault.dip:g} degrees with W / h* = {group['width_over_nucleation']:.3g}: {why} "
                "(benchmarks/dip_model_error.py), so no range; run the 2-D fault in plane strain")
    return report


def _dip_calibrated(fault: FaultDescription, group: dict) -> bool:
    """Whether the one slider's calibration against plane strain covers ``fault``: a dipping fault inside the
    measured dipping faults' box (:func:`faultslip.fault.dip_slider.outside`)."""
    return fault.plane == "strain" and not dip_slider.outside(group, fault.dip, fault.sense)


def _dip_bands(raw: dict, group: dict, fault: FaultDescription) -> dict:
    """The block's recurrence and mean slip corrected against plane strain, with their 95 % ranges
    (:func:`faultslip.fault.dip_slider.predict`); on a fault that breaks the surface, the surface slip as the
    antiplane calibration gives it, its range widened by the dip error (none where that error leaves no upper
    end): its own correction against plane strain did not hold on held-out faults."""
    bands = {quantity: dip_slider.predict(quantity, raw[block], group, fault.dip, fault.sense)
             for quantity, block in dip_slider.QUANTITIES.items()}
    table = load_calibration()
    if group["burial"] == 0.0 and "surface_slip" in table and not outside_box(group, table):
        dipping = _dip_error(fault, group)
        if dipping < 1.0:
            bands["surface_slip"] = _widened(predict("surface_slip", raw["slip"], group, table), dipping)
    return bands


def _bands(raw: dict, group: dict, table: dict) -> dict:
    """The block's answers ``raw`` corrected, with their 95 % ranges (:func:`predict`): the recurrence and the mean
    slip, and on a fault that breaks the surface its surface slip."""
    bands = {"recurrence": predict("recurrence", raw["recurrence"], group, table),
             "mean_slip": predict("mean_slip", raw["slip"], group, table)}
    if group["burial"] == 0.0 and "surface_slip" in table:
        bands["surface_slip"] = predict("surface_slip", raw["slip"], group, table)
    return bands


def _dip_error(fault: FaultDescription, group: dict) -> float:
    """The antiplane rung's model error against plane strain on a dipping fault (0 on a vertical strike-slip one,
    inf where none is declared: :func:`faultslip.fault.dip_error.declared`)."""
    if fault.plane != "strain":
        return 0.0
    return dip_error.declared(fault.dip, width_over_nucleation=group["width_over_nucleation"])


def declared_error(fault: FaultDescription, calibration: dict | None = None) -> float | None:
    """The one slider's declared model error on ``fault``, as :func:`one_slider_report` declares it, from the
    fault's groups alone, before its block runs: the widest 95 % range's half-width (the prediction interval's
    does not depend on the block's answer), compounded with a dipping fault's error against plane strain; None
    outside the calibrated box or where the dip's error leaves no range. An estimate reads it to tell whether a
    tolerance stops at the one slider."""
    group = groups(fault)
    if _dip_calibrated(fault, group):
        bands = _dip_bands({"recurrence": 1.0, "slip": 1.0}, group, fault)
        return max(band["half_width"] for band in bands.values())
    return composed_error(fault, calibration)


def composed_error(fault: FaultDescription, calibration: dict | None = None) -> float | None:
    """The one slider's declared error through the antiplane calibration: its widest 95 % range's half-width,
    compounded with a dipping fault's error against plane strain (:func:`faultslip.fault.dip_error.declared`);
    None outside the calibrated box or where the dip's error leaves no range. What :func:`declared_error` is
    outside the calibration against plane strain."""
    table = calibration or load_calibration()
    group = groups(fault)
    dipping = _dip_error(fault, group)
    if outside_box(group, table) or not dipping < 1.0:
        return None
    return max(compounded(band["half_width"], dipping)
               for band in _bands({"recurrence": 1.0, "slip": 1.0}, group, table).values())


def _widened(band: dict, dipping: float) -> dict:
    """An antiplane range read against plane strain: its ends put through :func:`truth_range` at the dip error
    ``dipping``, its half-width compounded with it."""
    return {**band, "low": truth_range(band["low"], dipping)[0], "high": truth_range(band["high"], dipping)[1],
            "half_width": compounded(band["half_width"], dipping)}


def ladder_report(title: str, rungs: list[dict], tolerance: float | None, above: str, slip_label: str) -> Report:
    """Every rung's answer, declared range, error and cost, and how each lower rung stands against the top one
    (the 2-D and the 3-D ladders' ``model-error``).

    Parameters
    ----------
    title : str
        The report's title.
    rungs : list of dict
        :func:`rung_of` rows, cheapest first; the last is the answer the others are measured against.
    tolerance : float, optional
        Say which rungs' declared errors meet it.
    above : str
        The top rung's name in labels ("2-D", "3-D").
    slip_label : str
        What the rungs' slip is ("surface slip per event", "slip per event").
    """
    report = Report(title)
    for rung in rungs:
        name = rung["name"]
        report.add(f"{name}_recurrence", rung["recurrence"], "s", also=("yr",), label=f"{name}: recurrence")
        if rung["recurrence_range"] is not None:
            report.add(f"{name}_recurrence_range", list(rung["recurrence_range"]), "s", also=("yr",),
                       label=f"{name}: its declared range")
        report.add(f"{name}_slip_per_event", rung["slip"], "m", label=f"{name}: {slip_label}")
        if rung["slip_range"] is not None:
            report.add(f"{name}_slip_per_event_range", list(rung["slip_range"]), "m", label=f"{name}: its declared range")
        report.add(f"{name}_declared_error", rung["error"], label=f"{name}: declared error (relative; null: none)")
        if rung.get("slip_error", rung["error"]) != rung["error"]:
            report.add(f"{name}_slip_declared_error", rung["slip_error"],
                       label=f"{name}: declared error of its slip per event (relative; null: none)")
        if rung["error"] is not None and rung["error"] >= 1 and rung["recurrence_range"] is None:
            report.note(f"{name}: its declared error, {rung['error']:.0%}, bounds the {above} answer from below only "
                        "(at value / (1 + e): |value / truth - 1| <= e sets no upper end once e >= 1), so no range is "
                        "declared")
        report.add(f"{name}_cpu_time", rung["cpu_time"], "s", label=f"{name}: CPU time")
        if tolerance is not None:
            report.add(f"{name}_meets_tolerance", rung["error"] is not None and rung["error"] <= tolerance,
                       label=f"{name}: declared error within {tolerance:g}")
    truth = rungs[-1]
    for rung in rungs[:-1]:
        report.add(f"{rung['name']}_off_recurrence", rung["recurrence"] / truth["recurrence"] - 1,
                   label=f"{rung['name']}: off the {above} recurrence (relative)")
        band, slip_band = rung["recurrence_range"], rung["slip_range"]
        holds = None if band is None else bool(band[0] <= truth["recurrence"] <= band[1] and (
            slip_band is None or slip_band[0] <= truth["slip"] <= slip_band[1]))
        report.add(f"{rung['name']}_range_holds", holds,
                   label=f"{rung['name']}: its ranges hold the {above} answer (null: no range declared)")
    return report


def compounded(*errors) -> float | None:
    """Relative errors compounded, (1 + e1)(1 + e2)... - 1; None where any is unknown or unbounded."""
    total = 1.0
    for error in errors:
        if error is None or not math.isfinite(error):
            return None
        total *= 1.0 + error
    return total - 1.0


def truth_range(value: float, error: float | None) -> list | None:
    """Where the answer a rung stands for lies, given the rung's ``value`` and its declared relative error
    ``error`` (a model error is measured as |value / truth - 1|, and a numerical one as the same against the exact
    answer): [value / (1 + e), value / (1 - e)] (:func:`faultslip.fault.one_slider_error.range_within`); None
    where nothing is declared, or from e = 1, where the truth has no upper bound."""
    if error is None:
        return None
    bounds = range_within(value, error)
    return None if bounds is None or bounds[1] is None else list(bounds)


def with_model_error(rung: dict, model_error: float) -> dict:
    """A rung whose declared error adds a model error against the rung above: the errors compound
    (:func:`compounded`) and the ranges are where that rung's answer lies (:func:`truth_range`); an unbounded
    model error leaves no error and no range."""
    error = compounded(rung["error"] or 0.0, model_error)
    slip_error = compounded(rung.get("slip_error", rung["error"]) or 0.0, model_error)
    return {**rung, "error": error, "recurrence_range": truth_range(rung["recurrence"], error),
            "slip_error": slip_error, "slip_range": truth_range(rung["slip"], slip_error)}


def rung_of(name: str, result: Result, cpu: float, slip: str = "surface") -> dict:
    """A rung's row for :func:`ladder_report`: its recurrence (s) and slip (m), their declared ranges (the one
    slider's own 95 % ranges; a 2-D or 3-D run's from its declared relative error), that error and the CPU (s).
    ``slip``: "surface", the surface slip per event where the rung gives one (the 2-D ladder's), or "mean", the
    slip averaged over the velocity-weakening zone (what the 3-D fault gives: a ladder with it compares that)."""
    values = result.values

    def pair(key):
        band = values[key] if key in result else None
        return None if band is None else tuple(float(v.to("s" if "recurrence" in key else "m").magnitude) for v in band)

    error = result.estimated_relative_error
    # the slip's own declared error where the rung gives one (the 3-D fault's), else the recurrence's (the 2-D
    # fault's, which covers its mean slip on every run measured, tests/models/fault_2d/test_fault_2d.py)
    slip_error = result.si("slip_per_event_error") if "slip_per_event_error" in result else error
    surface = slip == "surface" and "slip_per_event" in result and values["slip_per_event"] is not None
    slip_key = "slip_per_event" if surface or "mean_slip_per_event" not in result else "mean_slip_per_event"
    own_range = "slip_per_event_range" if slip_key == "slip_per_event" else "mean_slip_per_event_range"
    return {"name": name, "cpu_time": cpu, "recurrence": float(values["recurrence_interval"].to("s").magnitude),
            "recurrence_range": pair("recurrence_range") if name == "one_slider"
            else _declared(result, "recurrence_interval", "s", error),
            "slip": float(values[slip_key].to("m").magnitude),
            "slip_range": pair(own_range) if name == "one_slider" else _declared(result, slip_key, "m", slip_error),
            "error": error, "slip_error": slip_error}


def _declared(result: Result, key: str, unit: str, error: float | None):
    """A 2-D or 3-D answer's range from its declared relative error (:func:`truth_range`)."""
    return truth_range(float(result.values[key].to(unit).magnitude), error)
