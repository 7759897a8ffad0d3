"""Rate-and-state faults cell by cell: K / K_c in closed form everywhere, earthquake cycles where asked.

The vectorised counterpart of :func:`faultslip.fault.rate_state_fault.estimate_rate_state_fault`
for studies and maps. Every input is an SI array (or scalar) that broadcasts against the others.
Each cell is seed 003's spring-slider scaled to a fault (§5-2): K = G / D, and quasi-statically

    K_c = sigma_n (b - a) / D_c                                         (Ruina 1983)

(the radiation damper lowers it by eta V_pl / D_c, a relative 1e-9 at plate rates: the closed
form is the quasi-static one, as :func:`faultslip.dynamics.rate_state.slider.fault_cycles` uses). Steady
sliding is unstable where K < K_c and b > a; with ``cycles`` > 0 those cells are simulated
quasi-dynamically, each distinct set of friction and fault inputs once (sweeping the rupture
length, for example, costs nothing more), each by the cheapest integrator whose declared error meets the
tolerance (:func:`~faultslip.dynamics.rate_state.methods.choose_cycle_method`) unless one is named. A cell's
cycles are measured once they settle (:func:`~faultslip.dynamics.rate_state.slider.fault_cycles`), and its cost
counts the cycles settling takes (:func:`~faultslip.dynamics.rate_state.methods.cycle_steps`).

Every simulated cell declares its numerical error: the plate balance |mean cycle slip / (V_pl T) - 1|,
zero for exactly periodic cycles, which grows where the cycles have not settled within the
spin-up (near K / K_c = 1) or the solver drifts. As the fault's answer a cell's cycles also carry
the one block's model error against the 2-D fault it stands for (the zone-width calibration at
the cell's D / h*, :mod:`faultslip.fault.one_slider_error`); the declared error is the larger. A cell whose solver fails, or whose fault has
no event faster than 1 mm/s within the time limit, is flagged (``method`` -1 or ``regime``
slow_or_creeping), never filled with zeros.
"""

from __future__ import annotations

import numpy as np

from faultslip.dynamics.rate_state import native
from faultslip.dynamics.rate_state.slider import EVENT_SPEED, RateStateSlider, fault_cycles
from faultslip.dynamics.rate_state.methods import CYCLE_METHODS as INTEGRATORS, choose_cycle_method
from faultslip.errors import InputError, NoEventsError, SolverError
from faultslip.io import machine
from faultslip.fault.one_slider_error import zone_width_model_error
from faultslip.fault.scaling import moment_magnitude, seismic_moment
from faultslip.friction.rate_state import EVOLUTION_LAWS, RateStateLaw, steady_state_friction

#: regime flags: a cell's behaviour (closed form, or the cycles where they ran)
REGIME_CODES = {"stick_slip": 0, "stable_sliding": 1, "velocity_strengthening": 2, "slow_or_creeping": 3}
#: method flags: how a cell's outputs were found
METHOD_CODES = {"solver_failed": -1, "closed_form": 0, "lsoda": 1, "dopri5": 2, "dopri5_compiled": 3}
#: cycle methods a study or map may name (auto: per cell)
CYCLE_METHODS = ("auto", "lsoda", "dopri5", "dopri5_compiled")
#: the least spin-up before a cell's cycles are judged settled (fault_cycles' spin_up)
SPIN_UP = 2
#: CPU seconds of a simulated cell beside its integrator steps (law, slider, event bookkeeping), on the "families"
#: machine reference: 120 cheap cells' sweeps less their cycles' modelled cost and the file's, per cell
#: (benchmarks/sweep_estimates.py writes it; tests/capabilities/contract/test_families.py checks it against that
#: file). Once the seconds per step were measured it is small: the steps' model holds a run's own fixed cost. It
#: had been 10 ms, typed, and a study of 120 such cells was estimated at 5.7 times its CPU. A residual of two
#: larger numbers, it moves between runs (0.014 ms and 0.23 ms in two of them): either is under a quarter
#: of such a cell's cycles.
CELL_OVERHEAD = 3.794e-4

#: name -> (unit, long name) of every output
OUTPUT_ATTRS = {
    "stiffness": ("Pa/m", "fault stiffness K = G / D"),
    "critical_stiffness": ("Pa/m", "critical stiffness K_c = sigma_n (b - a) / D_c (Ruina 1983)"),
    "stiffness_ratio": ("1", "K / K_c (inf where b <= a: steady sliding is stable at every stiffness)"),
    "steady_state_friction": ("1", "steady-state friction at the plate rate, mu0 + (a - b) ln(V_pl / V0)"),
    "recurrence_period": ("s", "recurrence period of the simulated cycles (NaN without cycles)"),
    "slip_per_event": ("m", "slip per event while the slip rate exceeds 1 mm/s (0 for steady sliding)"),
    "stress_drop": ("Pa", "stress drop per event (0 for steady sliding)"),
    "peak_slip_rate": ("m/s", "peak slip rate of the events (the plate rate for steady sliding)"),
    "estimated_relative_error": ("1", "declared relative error of the recurrence and slip as the fault's: the larger "
                                      "of model_error and numerical_error where the cycles ran (0 for the closed "
                                      "form, whose K / K_c is exact; inf: unbounded)"),
    "numerical_error": ("1", "the cycles' own error: the larger of the integrator's declared error (c rtol) plus "
                             "what settling left, and the measured plate balance |mean cycle slip / (V_pl T) - 1| "
                             "(0 for the closed form)"),
    "model_error": ("1", "declared model error of this one block (K = G / D) against the 2-D fault it stands for, "
                         "relative, recurrence or slip (data/fault_2d_model_error.json, zone-width table; inf: outside "
                         "the calibrated W / h*, not known; NaN where b <= a)"),
    "width_over_nucleation": ("1", "D / h*, h* = (pi / 2) G D_c b / [sigma_n (b - a)^2] (Rubin & Ampuero 2005): what "
                                   "governs the model error (0 where b <= a)"),
    "seismic_moment": ("N m", "seismic moment M0 = G L H (slip per event)"),
    "moment_magnitude": ("1", "moment magnitude Mw = (2/3)(log10 M0 - 9.1), M0 in N m"),
}


def _evolution_codes(evolution) -> np.ndarray:
    """Evolution-law names (str or array of str) as integer codes (index into EVOLUTION_LAWS); codes pass."""
    if np.issubdtype(np.asarray(evolution).dtype, np.integer):
        codes = np.asarray(evolution, dtype=np.int8)
        if np.any((codes < 0) | (codes >= len(EVOLUTION_LAWS))):
            raise InputError(f"evolution-law codes index {EVOLUTION_LAWS}, got {codes.ravel()[0]}")
        return codes
    names = np.asarray(evolution, dtype=object)
    codes = np.empty(names.shape, dtype=np.int8)
    for index, name in np.ndenumerate(names):
        if str(name) not in EVOLUTION_LAWS:
            raise InputError(f"evolution law must be one of {', '.join(EVOLUTION_LAWS)}, got {name!r}")
        codes[index] = EVOLUTION_LAWS.index(str(name))
    return codes


def evolution_codes(evolution):
    """Evolution-law names as int8 codes, labels kept for a DataArray (dask cannot chunk strings)."""
    import xarray as xr  # heavy: imported where used

    if isinstance(evolution, xr.DataArray):
        return evolution.copy(data=_evolution_codes(evolution.values))
    return _evolution_codes(evolution)


def check_friction(a, b, critical_slip, mu0, reference_speed, where: str = "") -> None:
    """Refuse rate-and-state parameters outside the ranges :class:`RateStateLaw` accepts (array-wise)."""
    place = f" ({where})" if where else ""
    for label, values, low, high, rule in (("a", a, 0.0, 1.0, "in (0, 1)"), ("b", b, 0.0, 1.0, "in [0, 1)"),
                                           ("D_c", critical_slip, 1e-9, 10.0, "from 1 nm to 10 m"),
                                           ("mu0", mu0, 0.0, np.inf, "positive"),
                                           ("V0", reference_speed, 0.0, np.inf, "positive")):
        values = np.asarray(values, dtype=float)
        with np.errstate(invalid="ignore"):
            if label == "b":
                bad = ~((values >= low) & (values < high))
            elif label == "D_c":
                bad = ~((values >= low) & (values <= high))
            else:
                bad = ~((values > low) & (values < high))
        if np.any(bad):
            first = float(values[bad].flat[0])
            raise InputError(f"rate-and-state {label} must be {rule}, got {first:g}{place}")


def check_cycle_method(method, where: str = "the cycle method") -> None:
    """Refuse, before any work, a cycles' integrator that is not one, or that this install did not build."""
    if method not in CYCLE_METHODS:
        raise InputError(f"{where} must be one of {', '.join(CYCLE_METHODS)} (how the cycles are integrated), "
                         f"got {method!r}")
    if method == "dopri5_compiled" and not native.available():
        raise InputError(f"{where} dopri5_compiled was not built with this install (no C compiler at install "
                         "time); use dopri5, the same scheme in Python, or auto")


def rate_state_cells(*, shear_modulus, zone_width, normal_stress, plate_rate, a, b, critical_slip, mu0=0.6,
                     reference_speed=1e-6, evolution="aging", density=2700.0, shear_wave_speed=None,
                     rupture_length=None, seismogenic_depth=None, cycles: int = 0, method: str = "auto",
                     tolerance: float = 1e-6) -> dict:
    """Outputs of every cell (name -> array over the broadcast shape of the inputs), SI.

    Always: ``stiffness``, ``critical_stiffness``, ``stiffness_ratio``, ``steady_state_friction``,
    ``regime`` and ``method`` (int8 flags, see :data:`REGIME_CODES`, :data:`METHOD_CODES`).
    With ``cycles`` > 0 also ``recurrence_period``, ``slip_per_event``, ``stress_drop``,
    ``peak_slip_rate``, ``estimated_relative_error``, ``numerical_error``, ``model_error`` and
    ``width_over_nucleation`` (see :data:`OUTPUT_ATTRS`); with a rupture length and seismogenic
    depth, ``seismic_moment`` and ``moment_magnitude``. ``tolerance`` is the relative error asked of the
    cycles: each cell runs the cheapest integrator (or ``method``) at the loosest rtol whose declared error
    meets it (:func:`faultslip.dynamics.rate_state.methods.choose_cycle_method`).
    """
    check_cycle_method(method)
    if not isinstance(cycles, int) or isinstance(cycles, bool) or not 0 <= cycles <= 1000:
        raise InputError(f"cycles must be a whole number from 0 (closed form only) to 1000, got {cycles!r}")
    check_friction(a, b, critical_slip, mu0, reference_speed)
    evolution_code = _evolution_codes(evolution)
    wave_speed = np.sqrt(np.divide(shear_modulus, density)) if shear_wave_speed is None else shear_wave_speed
    has_moment = rupture_length is not None and seismogenic_depth is not None
    sizes = (rupture_length, seismogenic_depth) if has_moment else (0.0, 0.0)
    arrays = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (
        shear_modulus, zone_width, normal_stress, plate_rate, a, b, critical_slip, mu0, reference_speed, density,
        wave_speed, *sizes)), evolution_code)
    (modulus, width, sigma, plate, a, b, slip_scale, mu0, v0, rho, wave, length, depth), law_code = arrays[:-1], arrays[-1]
    stiffness = modulus / width
    critical = sigma * (b - a) / slip_scale
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(critical > 0, stiffness / critical, np.inf)
    unstable = ratio < 1
    regime = np.where(b <= a, REGIME_CODES["velocity_strengthening"],
                      np.where(unstable, REGIME_CODES["stick_slip"], REGIME_CODES["stable_sliding"])).astype(np.int8)
    outputs = {"stiffness": stiffness, "critical_stiffness": critical, "stiffness_ratio": ratio,
               "steady_state_friction": steady_state_friction(plate, a, b, mu0, v0),
               "regime": regime, "method": np.full(ratio.shape, METHOD_CODES["closed_form"], dtype=np.int8)}
    if cycles:
        outputs.update(_simulate_cells(unstable, (modulus, width, sigma, plate, a, b, slip_scale, mu0, v0, rho, wave),
                                       law_code, cycles, method, tolerance, outputs))
        # the cycles are one block's: as the fault's answer they carry its model error (as `run` declares it)
        ratio_to_nucleation, model = zone_width_model_error(modulus, width, sigma, a, b, slip_scale)
        numerical = outputs["estimated_relative_error"]
        outputs.update(numerical_error=numerical, model_error=model, width_over_nucleation=ratio_to_nucleation,
                       estimated_relative_error=np.where(unstable, np.maximum(numerical, model), numerical))
        if has_moment:
            moment = seismic_moment(modulus, length, depth, outputs["slip_per_event"])
            with np.errstate(divide="ignore"):  # log10(0) = -inf where nothing slips: NaN, not a magnitude
                outputs["seismic_moment"] = np.where(moment > 0, moment, np.nan)
                outputs["moment_magnitude"] = np.where(moment > 0, moment_magnitude(moment), np.nan)
    return outputs


def _simulate_cells(unstable, columns, law_code, cycles, method, tolerance, outputs) -> dict:
    """Cycles of every distinct unstable cell; steady sliding (0 slip, plate-rate speed) elsewhere."""
    shape = unstable.shape
    plate = columns[3]
    result = {"recurrence_period": np.full(shape, np.nan), "slip_per_event": np.zeros(shape),
              "stress_drop": np.zeros(shape), "peak_slip_rate": plate.astype(float).copy(),
              "estimated_relative_error": np.zeros(shape)}
    if not unstable.any():
        return result
    table = np.column_stack([c[unstable] for c in columns] + [law_code[unstable]])
    distinct, owner = np.unique(table, axis=0, return_inverse=True)
    owner = owner.ravel()
    found = np.full((distinct.shape[0], 5), np.nan)
    codes = np.empty((distinct.shape[0], 2), dtype=np.int8)  # method, regime
    for row_index, row in enumerate(distinct):
        found[row_index], codes[row_index] = _one_cell(row, cycles, method, tolerance)
    for key, column in zip(("recurrence_period", "slip_per_event", "stress_drop", "peak_slip_rate",
                            "estimated_relative_error"), found.T):
        result[key][unstable] = column[owner]
    outputs["method"][unstable] = codes[owner, 0]
    outputs["regime"][unstable] = codes[owner, 1]
    return result


def _one_cell(row, cycles, method, tolerance):
    """(recurrence, slip, stress drop, peak rate, plate balance), (method code, regime code) of one cell."""
    modulus, width, sigma, plate, a, b, slip_scale, mu0, v0, rho, wave, law_code = row
    law = RateStateLaw(a=float(a), b=float(b), critical_slip=float(slip_scale), mu0=float(mu0),
                       reference_speed=float(v0), evolution=EVOLUTION_LAWS[int(law_code)])
    slider = RateStateSlider.at_fault(law, float(modulus), float(width), float(sigma), density=float(rho),
                                      shear_wave_speed=float(wave))
    ratio = slider.stiffness / slider.critical_stiffness()
    if method == "auto":
        chosen, rtol, assessment, _ = choose_cycle_method(ratio, tolerance, cycles, a_over_b=float(a / b))
    else:
        assessment = INTEGRATORS[method].assess(ratio, tolerance, cycles, a_over_b=float(a / b))
        chosen, rtol = method, assessment.settings["rtol"]
    try:
        run = fault_cycles(slider, float(plate), cycles=cycles, spin_up=SPIN_UP, method=chosen, rtol=rtol)
    except NoEventsError:  # K < K_c, yet no slip faster than 1 mm/s: slow oscillation or creep, not failure
        return (np.nan, 0.0, 0.0, np.nan, np.nan), (METHOD_CODES[chosen], REGIME_CODES["slow_or_creeping"])
    except SolverError:
        return (np.nan,) * 5, (METHOD_CODES["solver_failed"], REGIME_CODES["stick_slip"])
    # declared: the integrator's bound plus what settling left (run.estimated_relative_error), or the plate balance
    balance = max(abs(float(np.mean(run.cycle_slip)) / (plate * run.recurrence) - 1.0), assessment.estimated_error,
                  run.estimated_relative_error)
    return ((run.recurrence, float(np.mean(run.slip_per_event)), float(np.mean(run.stress_drop)),
             float(np.max(run.peak_slip_rate)), balance),
            (METHOD_CODES[run.method], REGIME_CODES["stick_slip"]))


def output_names(cycles: int, has_moment: bool) -> list[str]:
    """The outputs :func:`rate_state_cells` gives, in order, for these options."""
    names = ["stiffness", "critical_stiffness", "stiffness_ratio", "steady_state_friction", "regime", "method"]
    if cycles:
        names += ["recurrence_period", "slip_per_event", "stress_drop", "peak_slip_rate", "estimated_relative_error",
                  "numerical_error", "model_error", "width_over_nucleation"]
        if has_moment:
            names += ["seismic_moment", "moment_magnitude"]
    return names


def friction_ratio(inputs: dict, shape: tuple) -> np.ndarray:
    """a / b of :func:`rate_state_cells`' ``inputs``, over the cells' ``shape`` (inf where b is 0)."""
    a, b = (np.broadcast_to(np.asarray(getattr(inputs[key], "values", inputs[key]), dtype=float), shape)
            for key in ("a", "b"))
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(b > 0, a / np.where(b > 0, b, 1.0), np.inf)


def estimated_seconds(stiffness_ratio, a_over_b, cycles: int, tolerance: float = 1e-6, method: str = "auto") -> float:
    """CPU seconds of :func:`rate_state_cells` for these cells on one core, on this machine: every unstable cell's
    cycles, those it takes to settle and ``cycles`` measured, by the integrators' calibrated cost models
    (:meth:`~faultslip.dynamics.rate_state.methods.CycleMethod.assess` with the law's a / b), plus a fixed cost
    per cell; anchored to the "families" machine reference, as the bench that fits the seconds per step is."""
    if not cycles:
        return 0.0
    pairs = np.column_stack(np.broadcast_arrays(np.asarray(stiffness_ratio, dtype=float).ravel(),
                                                np.asarray(a_over_b, dtype=float).ravel()))
    distinct, counts = np.unique(pairs, axis=0, return_counts=True)
    total = 0.0
    for (ratio, ratio_ab), count in zip(distinct, counts):
        if not ratio < 1:
            continue
        if method == "auto":
            cost = choose_cycle_method(float(ratio), tolerance, cycles, a_over_b=float(ratio_ab))[2].estimated_cost
        else:
            cost = INTEGRATORS[method].assess(float(ratio), tolerance, cycles,
                                              a_over_b=float(ratio_ab)).estimated_cost
        total += count * (cost + CELL_OVERHEAD)
    return machine.on_this_machine(total, "families")


__all__ = ["rate_state_cells", "check_cycle_method", "output_names", "evolution_codes", "check_friction",
           "estimated_seconds", "friction_ratio", "REGIME_CODES", "METHOD_CODES",
           "OUTPUT_ATTRS", "CYCLE_METHODS", "EVENT_SPEED"]
