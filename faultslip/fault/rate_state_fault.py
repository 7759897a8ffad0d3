"""A fault's earthquakes from a rate-and-state law: K / K_c, cycles, their uncertainty, and the seed law beside them.

The fault is seed 003's spring-slider scaled as in §5-2: stiffness K = G / D (Pa/m), effective
normal stress sigma_n, plate rate V_pl, and, quasi-dynamically, the radiation damper
eta = G / (2 c_s) (Rice 1993). Steady sliding is unstable where

    K < K_c = sigma_n (b - a) / D_c                                    (Ruina 1983)

and there the fault has earthquake cycles, simulated by :func:`faultslip.dynamics.rate_state.slider.fault_cycles`.
A fitted law's bootstrap resamples carry its uncertainty into K / K_c (closed form, every
resample) and into recurrence and slip per event (cycles of a subset of resamples).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

from faultslip.constants import JULIAN_YEAR
import numpy as np

from faultslip import ranges
from faultslip.dynamics.rate_state.slider import RateStateSlider, fault_cycles
from faultslip.intervals import percentile_interval
from faultslip.errors import FaultslipError, InputError
from faultslip.fault.rate_state_series import cycles_series
from faultslip.fault.scaling import Fault, moment_magnitude, radiation_damper, seismic_moment
from faultslip.friction.materials import resolve_material
from faultslip.friction.rate_state import RateStateLaw
from faultslip.io.report import Report
from faultslip.units import to_si

YEAR = JULIAN_YEAR
#: a fault's quantities by Fault field name: (unit kind, SI unit)
FAULT_QUANTITIES = {"shear_modulus": ("pressure", "Pa"), "zone_width": ("length", "m"),
                    "normal_stress": ("pressure", "Pa"), "shear_stress": ("pressure", "Pa"),
                    "slip_rate": ("speed", "m/s"), "rupture_length": ("length", "m"),
                    "seismogenic_depth": ("length", "m"), "density": ("density", "kg/m^3"),
                    "shear_wave_speed": ("speed", "m/s")}


@dataclass
class RateStateFaultEstimate:
    """What :func:`estimate_rate_state_fault` found, SI units."""

    law: RateStateLaw
    stiffness: float  # Pa/m
    critical_stiffness: float  # Pa/m, quasi-static
    normal_stress: float
    plate_rate: float
    cycles: object = None  # RateStateCycles, or None for a stable fault
    moment: float | None = None
    magnitude: float | None = None
    uncertainty: dict = field(default_factory=dict)  # name -> (low, high) 95 %
    distribution: dict = field(default_factory=dict)  # name -> its QUANTILES over the fit's draws
    seed_law: object = None  # FaultEstimate of the seed law on the same fault, if asked
    notes: list = field(default_factory=list)
    #: the fault it was estimated on (SI): shear_modulus, zone_width (D: K = G / D), density, shear_wave_speed
    fault_inputs: dict = field(default_factory=dict)

    @property
    def stiffness_ratio(self) -> float:
        return self.stiffness / self.critical_stiffness if self.critical_stiffness > 0 else math.inf

    @property
    def regime(self) -> str:
        if self.law.b <= self.law.a:
            return "stable_sliding (velocity strengthening, b <= a)"
        return "stick_slip (K < K_c)" if self.stiffness_ratio < 1 else "stable_sliding (K >= K_c)"

    def report(self, title: str) -> Report:
        r = Report(title)
        law = self.law
        r.add("a", law.a).add("b", law.b).add("critical_slip", law.critical_slip, "m", also=("mm",))
        r.add("evolution", law.evolution).add("law_source", law.source)
        r.add("stiffness", self.stiffness, "Pa/m", label="K = G / D")
        r.add("normal_stress", self.normal_stress, "Pa", also=("MPa",))
        r.add("plate_rate", self.plate_rate, "m/s", also=("mm/yr",))
        r.add("critical_stiffness", self.critical_stiffness, "Pa/m", label="K_c = sigma_n (b - a) / D_c")
        ratio = self.stiffness_ratio
        r.add("stiffness_ratio", ratio if math.isfinite(ratio) else None, label="K / K_c")
        r.add("regime", self.regime)
        if self.cycles is not None:
            c = self.cycles
            r.add("recurrence_period", c.recurrence, "s", also=("yr",))
            r.add("slip_per_event", float(c.slip_per_event.mean()), "m")
            r.add("stress_drop", float(c.stress_drop.mean()), "Pa", also=("MPa",))
            r.add("peak_slip_rate", float(c.peak_slip_rate.max()), "m/s")
            r.add("cycles", int(c.slip_per_event.size)).add("model", c.model)
            # the same method names as the rate-and-state slider family's fault runs: one spring-block, K = G / D
            r.add("method", "one_slider")
            r.add("method_reason", "one quasi-dynamic spring-block, K = G / D (the 2-D fault it stands for runs with "
                                   "--method fault_2d on a rate-and-state scene)")
            c.report_settling(r)
            if self.moment is not None:
                r.add("seismic_moment", self.moment, "N*m", label="M0 = G L H (slip per event)")
                r.add("moment_magnitude", self.magnitude, label="Mw")
        for name, (low, high) in self.uncertainty.items():
            unit = {"recurrence_period": "s", "slip_per_event": "m"}.get(name, "1")
            r.add(f"{name}_95", [low, high], unit, label=f"{name} 95 % (from the fit's draws)")
        for name, values in self.distribution.items():
            unit = {"recurrence_period": "s", "slip_per_event": "m"}.get(name, "1")
            r.add(f"{name}_quantiles", values, unit,
                  label=f"{name} at the {', '.join(f'{q:g}' for q in QUANTILES)} % quantiles of the fit's draws")
        if self.seed_law is not None:
            seed = self.seed_law
            r.add("seed_law_lithology", seed.fault.lithology or "given mu_so, mu_m")
            r.add("seed_law_slip_per_event", seed.slip_per_event, "m", label="seed law (eq. 2-18) on the same fault")
            r.add("seed_law_recurrence_period", seed.recurrence_period, "s", also=("yr",),
                  label="seed law recurrence on the same fault")
            if self.cycles is not None:
                r.add("slip_ratio_rate_state_to_seed", float(self.cycles.slip_per_event.mean()) / seed.slip_per_event)
        for note in self.notes:
            r.note(note)
        return r


#: the percentiles of a prediction's distribution over a fit's draws
QUANTILES = (2.5, 16.0, 50.0, 84.0, 97.5)


def _resample_laws(law: RateStateLaw, entry: dict | None) -> list[RateStateLaw]:
    """The draws stored with a fit (posterior draws, or bootstrap resamples), as laws (empty if it has none)."""
    stored = (entry or {}).get("samples") or (entry or {}).get("bootstrap")
    if not stored:
        return []
    names = entry.get("names") or ["mu0", "a", "b", "critical_slip"]
    rows = np.asarray(stored, dtype=float)
    if rows.ndim != 2 or rows.shape[1] != len(names):
        raise InputError("the fit's stored draws do not match its parameters; refit it with --name")
    laws = []
    for row in rows:
        values = dict(zip(names, row))
        laws.append(RateStateLaw(a=values["a"], b=values["b"], critical_slip=values["critical_slip"],
                                 mu0=values["mu0"], reference_speed=law.reference_speed, evolution=law.evolution,
                                 b2=values.get("b2", 0.0), critical_slip2=values.get("critical_slip2"),
                                 source=law.source))
    return laws


def estimate_rate_state_fault(law: RateStateLaw, *, shear_modulus: float, zone_width: float, normal_stress: float,
                              plate_rate: float, density: float = 2700.0, shear_wave_speed: float | None = None,
                              cycles: int = 5, entry: dict | None = None, uncertainty_cycles: int = 20,
                              time_budget: float = 15.0,
                              rupture_length: float | None = None, seismogenic_depth: float | None = None,
                              seed_law: Fault | None = None, record: bool = False) -> RateStateFaultEstimate:
    """Earthquake cycles of a rate-and-state fault (SI inputs), quasi-dynamic with the radiation damper.

    ``entry`` is a registry entry with bootstrap resamples: K / K_c gets a 95 % interval over all of
    them, recurrence and slip per event over up to ``uncertainty_cycles`` of them (2 cycles each
    after one of spin-up), as many as ``time_budget`` seconds allow (a stiff fault, K / K_c near
    1e-4, takes about a second a cycle); the report says how many were used.
    ``seed_law`` is a :class:`Fault` of the seed's law on the same fault, estimated beside.
    ``record`` keeps the cycles' time series (:func:`cycles_dataset` writes it).
    """
    if law.two_state:
        raise InputError("fault predictions take a one-state law here (K_c of a two-state law has no closed form)")
    wave = shear_wave_speed or math.sqrt(shear_modulus / density)
    slider = RateStateSlider.at_fault(law, shear_modulus, zone_width, normal_stress, density=density,
                                      shear_wave_speed=wave)
    estimate = RateStateFaultEstimate(law=law, stiffness=slider.stiffness,
                                      critical_stiffness=normal_stress * (law.b - law.a) / law.critical_slip,
                                      normal_stress=normal_stress, plate_rate=plate_rate,
                                      fault_inputs={"shear_modulus": shear_modulus, "zone_width": zone_width,
                                                    "density": density, "shear_wave_speed": wave})
    estimate.notes.append(f"quasi-dynamic: radiation damper G / (2 c_s) = {radiation_damper(shear_modulus, wave):.4g} "
                          "Pa s/m; events are slip faster than 1 mm/s (the SEAS convention)")
    if estimate.stiffness_ratio < 1:
        estimate.cycles = fault_cycles(slider, plate_rate, cycles=cycles, record=record)
        if rupture_length is not None and seismogenic_depth is not None:
            estimate.moment = float(seismic_moment(shear_modulus, rupture_length, seismogenic_depth,
                                                   float(estimate.cycles.slip_per_event.mean())))
            estimate.magnitude = float(moment_magnitude(estimate.moment))
    resamples = _resample_laws(law, entry)
    if resamples:
        ratios = np.array([slider.stiffness * s.critical_slip / (normal_stress * (s.b - s.a)) if s.b > s.a else np.inf
                           for s in resamples])
        estimate.uncertainty["stiffness_ratio"] = percentile_interval(ratios, estimate.stiffness_ratio)[:2]
        unstable = ratios < 1
        what = "posterior draws" if entry.get("samples_kind") == "posterior" else "bootstrap resamples"
        estimate.distribution["stiffness_ratio"] = np.percentile(ratios, QUANTILES).tolist()
        estimate.notes.append(f"{int(unstable.sum())} of {ratios.size} {what} of the fit give "
                              "earthquake cycles (K < K_c)")
        if estimate.cycles is not None and unstable.sum() >= 5:
            chosen = [s for s, u in zip(resamples, unstable) if u][:uncertainty_cycles]
            recurrence, slip, started = [], [], time.perf_counter()
            for sample in chosen:
                if time.perf_counter() - started > time_budget:
                    break
                try:
                    run = fault_cycles(RateStateSlider.at_fault(sample, shear_modulus, zone_width, normal_stress,
                                                                density=density, shear_wave_speed=wave),
                                       plate_rate, cycles=2, spin_up=1)
                except FaultslipError:
                    continue
                recurrence.append(run.recurrence)
                slip.append(float(run.slip_per_event.mean()))
            if len(recurrence) >= 5:
                estimate.distribution["recurrence_period"] = np.percentile(recurrence, QUANTILES).tolist()
                estimate.distribution["slip_per_event"] = np.percentile(slip, QUANTILES).tolist()
                estimate.uncertainty["recurrence_period"] = percentile_interval(recurrence,
                                                                                estimate.cycles.recurrence)[:2]
                estimate.uncertainty["slip_per_event"] = percentile_interval(
                    slip, float(estimate.cycles.slip_per_event.mean()))[:2]
                estimate.notes.append(f"recurrence and slip intervals from cycles of {len(recurrence)} {what} "
                                      "(percentiles: a spread, not a coverage-tested interval)")
            else:
                estimate.notes.append(f"only {len(recurrence)} resamples' cycles ran within {time_budget:g} s: no "
                                      "interval for recurrence and slip (K / K_c's interval stands)")
    if seed_law is not None:
        estimate.seed_law = seed_law.estimate()
    return estimate


def cycles_dataset(estimate: RateStateFaultEstimate, title: str):
    """The recorded cycles of ``estimate`` (``record=True``) as a CF dataset (:func:`cycles_series`)."""
    return cycles_series(estimate.cycles, estimate.law, title)


def seed_law_fault(lithology: str, **values) -> Fault:
    """The seed law's :class:`Fault` (eq. 2-18 of ``lithology``) on the same fault, radiation-damped as the
    quasi-dynamic rate-and-state fault is. ``values``: SI numbers by Fault field name."""
    return Fault(lithology=lithology, radiation_damping=True,
                 **{key: f"{value!r} {FAULT_QUANTITIES[key][1]}" for key, value in values.items() if value is not None})


def estimate_fault_from_fit(name: str, inputs: dict, *, seed_law: str | None = "granodiorite",
                            cycles: int = 5) -> RateStateFaultEstimate:
    """``fault --lithology NAME`` for a rate-and-state fit saved in the registry.

    ``inputs`` holds quantity text (or SI numbers) by Fault field name: ``zone_width``,
    ``slip_rate`` and one of ``normal_stress`` or ``shear_stress`` (then sigma_n = tau / mu0);
    ``shear_modulus`` unless the fit was saved with one; optionally ``rupture_length``,
    ``seismogenic_depth``, ``density`` and ``shear_wave_speed``. ``seed_law`` names the seed-law
    lithology or preset estimated beside it (None: none).
    """
    choice = resolve_material(name)
    if choice.rate_state is None:
        raise InputError(f"{name!r} is not a rate-and-state fit")
    unknown = sorted(set(inputs) - set(FAULT_QUANTITIES))
    if unknown:
        flags = ", ".join("--" + key.replace("_", "-").replace("seismogenic-", "") for key in unknown)
        raise InputError(f"{flags} do not apply to a rate-and-state fit ({name!r}): its friction is a, b and D_c, "
                         "and its faults are always quasi-dynamic")
    values = {key: ranges.check(key, to_si(text, FAULT_QUANTITIES[key][0], key.replace("_", " "))) for key, text in inputs.items()}
    for key in ("zone_width", "slip_rate"):
        if key not in values:
            raise InputError(f"missing --{key.replace('_', '-')}, required for a fault estimate")
    if ("normal_stress" in values) == ("shear_stress" in values):
        raise InputError("give exactly one of --normal-stress or --shear-stress (sigma_n = tau / mu0)")
    law = choice.rate_state
    normal = values.get("normal_stress") or values["shear_stress"] / law.mu0
    modulus = values.get("shear_modulus") or (choice.lithology.shear_modulus if choice.lithology else None)
    if modulus is None:
        raise InputError(f"the fit {name!r} was saved without a shear modulus; give --shear-modulus, e.g. '30 GPa'")
    compare = None
    if seed_law:
        given = {key: value for key, value in values.items() if key != "shear_stress"}
        given.update(shear_modulus=modulus, normal_stress=normal)
        compare = seed_law_fault(seed_law, **given)
    estimate = estimate_rate_state_fault(law, shear_modulus=modulus, zone_width=values["zone_width"],
                                         normal_stress=normal, plate_rate=values["slip_rate"],
                                         density=values.get("density", 2700.0),
                                         shear_wave_speed=values.get("shear_wave_speed"), cycles=cycles,
                                         entry=choice.rate_state_entry, rupture_length=values.get("rupture_length"),
                                         seismogenic_depth=values.get("seismogenic_depth"), seed_law=compare)
    if "shear_stress" in values:
        estimate.notes.append(f"sigma_n = tau / mu0 = {normal:.4g} Pa (mu0 = {law.mu0:.4g}, the fit's)")
    if compare is not None:
        estimate.notes.append(f"seed law beside it: {seed_law}, with radiation damping as the rate-and-state "
                              "fault has")
    return estimate
