"""The 2-D runs behind the one slider's declared model error: a designed set of 2-D faults, and the block beside
each (``python benchmarks/fault_2d_calibration.py`` writes ``data/fault_2d_model_error.json``; the one slider's
family reads it, :mod:`faultslip.models.rate_state_slider.model_error`)."""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass

import numpy as np

from faultslip.dynamics.rate_state.slider import RateStateSlider, fault_cycles
from faultslip.friction.rate_state import RateStateLaw
from faultslip.models.fault_2d.analysis import classify, system_size
from faultslip.models.fault_2d.scene import Fault2DScene, _constant, _Table, build_fault

# --- the designed set (issue 42, item 3) -----------------------------------------------------------------

#: What every design shares: SEAS BP1's elasticity, loading and reference friction.
SHEAR_MODULUS, SHEAR_WAVE_SPEED, PLATE_RATE = 32.04e9, 3464.0, 1e-9


@dataclass(frozen=True)
class Design:
    """One 2-D fault of the calibration set, and what a one-slider scene can say of it.

    Depth is measured from the free surface. A velocity-strengthening cap of ``cap`` W (0: the fault breaks the
    surface) lies above the velocity-weakening width W (``seismogenic_width``); below it, a ramp of ``ramp`` W
    (0: one element) rises to ``a_strengthening``, which continues for ``below`` W more before steady slip at
    the plate rate is imposed (0: right below the ramp). The one slider sees W, a, b, D_c, sigma_n, G and V_pl
    only: the cap, the ramp and the depth below are what its model error must cover.
    """

    name: str
    width_over_nucleation: float
    a: float
    b: float = 0.015
    normal_stress: float = 50e6
    seismogenic_width: float = 15e3
    cap: float = 0.0
    ramp: float = 0.0
    below: float = 0.0
    a_strengthening: float = 0.025

    @property
    def critical_slip(self) -> float:
        """D_c that puts W / h* at ``width_over_nucleation`` (h* = (pi / 2) G D_c b / [sigma_n (b - a)^2])."""
        nucleation = self.seismogenic_width / self.width_over_nucleation
        return nucleation * self.normal_stress * (self.b - self.a) ** 2 / (math.pi / 2 * SHEAR_MODULUS * self.b)

    @property
    def law(self) -> RateStateLaw:
        """The velocity-weakening friction, as the one-slider scene states it."""
        return RateStateLaw(self.a, self.b, self.critical_slip, 0.6, 1e-6, "aging", source=self.name)

    def profile_a(self, element: float):
        """a(z) as a table: the cap, the weakening width, the ramp and what lies below."""
        width = self.seismogenic_width
        top, bottom = self.cap * width, (self.cap + 1.0) * width
        ramp = max(self.ramp * width, element)
        depths = [0.0]
        values = [self.a_strengthening if self.cap > 0 else self.a]
        if self.cap > 0:
            depths += [max(top - element, element / 2), top]
            values += [self.a_strengthening, self.a]
        depths += [bottom, bottom + ramp]
        values += [self.a, self.a_strengthening]
        return _Table(np.array(depths), np.array(values))

    def total_width(self, element: float) -> float:
        """W_f: the cap, W, the ramp and the strengthening depth below, a whole number of elements."""
        width = self.seismogenic_width
        raw = (self.cap + 1.0 + self.below) * width + max(self.ramp * width, element)
        return math.ceil(raw / element) * element

    def two_d(self, elements_per_process_zone: float = 3.0, duration: float | None = None,
              rtol: float = 1e-8, initial_speed: float = PLATE_RATE,
              geometry_resolution: float | None = None) -> Fault2DScene:
        """The 2-D fault, on elements resolving L_b = G D_c / (sigma_n b) ``elements_per_process_zone`` times, starting
        at steady state with every element slipping at ``initial_speed`` (m/s; BP1's start, eqs. 8-9).

        The fault's depth extent and the one-element steps of its profile are whole elements at
        ``geometry_resolution`` per L_b (default: the run's own): set it to run one fault at several element sizes
        (at a whole multiple of it), since moving the creeping base by part of an element moves the answer too."""
        process = SHEAR_MODULUS * self.critical_slip / (self.normal_stress * self.b)
        element = process / elements_per_process_zone
        shape = process / (geometry_resolution or elements_per_process_zone)
        width = self.total_width(shape)
        settings = {"width": width, "shear_modulus": SHEAR_MODULUS, "shear_wave_speed": SHEAR_WAVE_SPEED,
                    "plate_rate": PLATE_RATE, "evolution": "aging", "reference_speed": 1e-6,
                    "reference_friction": 0.6, "initial_speed": initial_speed, "max_elements": 8192,
                    "profiles": {"a": self.profile_a(shape), "b": _constant(self.b),
                                 "critical_slip": _constant(self.critical_slip),
                                 "normal_stress": _constant(self.normal_stress)}}
        built = build_fault(settings, width / round(width / element), self.name)
        return Fault2DScene(name=self.name, fault=built, duration=duration or 0.0, rtol=rtol,
                            stations=(0.0, self.cap * self.seismogenic_width), settings=settings)

    def slider(self, stiffness: float) -> RateStateSlider:
        """The one slider of this fault's friction at ``stiffness`` (Pa/m), with the radiation damper."""
        return RateStateSlider.at_fault(self.law, SHEAR_MODULUS, SHEAR_MODULUS / stiffness, self.normal_stress,
                                        density=SHEAR_MODULUS / SHEAR_WAVE_SPEED ** 2,
                                        shear_wave_speed=SHEAR_WAVE_SPEED)


def run_design(design: Design, cycles: int = 8, elements_per_process_zone: float = 3.0,
               initial_speed: float = PLATE_RATE, geometry_resolution: float | None = None) -> dict:
    """The 2-D fault of ``design`` over ``cycles`` system-size events after the spin-up: its recurrence, the slip
    of its settled events over the weakening width and at the surface, and the sequence it forms (from a steady
    start at ``initial_speed``, m/s; its geometry whole elements at ``geometry_resolution``: :meth:`Design.two_d`)."""
    # the block at the geometric stiffness bounds the 2-D recurrence from above: long enough for the cycles
    block = fault_cycles(design.slider(geometric_stiffness(design.seismogenic_width)), PLATE_RATE, cycles=3)
    scene = design.two_d(elements_per_process_zone, duration=(cycles + 4) * block.recurrence,
                         initial_speed=initial_speed, geometry_resolution=geometry_resolution)
    # as a run about to start here: a worker's first run loads the compiled step too (1 s of a 2 s small fault's)
    estimate = scene.estimate(in_this_process=True)
    started = time.process_time()
    run = scene.run()
    cpu = time.process_time() - started
    # system-size events by their slip over the weakening width (a buried fault's surface barely slips)
    weakening = scene.fault.b > scene.fault.a
    starts, slip = run.events["start"], run.events["slip"]
    mean_slip = slip[:, weakening].mean(axis=1) if starts.size else np.empty(0)
    system = system_size(slip, weakening)
    sequence = classify(np.diff(starts[system]), 0.01) if system.size > 1 else classify(np.empty(0), 0.01)
    window = system[sequence.first_event:]
    closing = window[1:] if window.size > 1 else window
    # the events that are not system-size: where they start (down dip, over W from the zone's top) and how much of
    # the zone they break (slip above a tenth of the largest event's there)
    partial = np.setdiff1d(np.arange(starts.size), system)
    top = design.cap * design.seismogenic_width
    broken = (slip[partial][:, weakening] > 0.1 * slip[:, weakening].max()).mean(axis=1) if partial.size else []
    return {"partial_hypocentres": ((run.events["hypocentre_depth"][partial] - top) / design.seismogenic_width).tolist(),
            "partial_broken": list(map(float, broken)),
            "design": asdict(design), "critical_slip": design.critical_slip, "elements": int(scene.fault.a.size),
            "element_size": scene.fault.element_size, "duration": scene.duration, "sequence": sequence.kind,
            "period": sequence.period, "events": int(starts.size), "system_events": int(system.size),
            "recurrence_2d": float(sequence.mean_interval), "spread_2d": float(sequence.spread),
            "mean_slip_2d": float(mean_slip[closing].mean()) if closing.size else math.nan,
            "surface_slip_2d": float(slip[closing, 0].mean()) if closing.size else math.nan,
            "intervals": np.diff(starts[system]).tolist() if system.size > 1 else [],
            "system_slips": mean_slip[system].tolist() if system.size else [],
            "steps": run.steps, "wall_time": run.wall_time, "cpu_time": cpu,
            "estimated_seconds": estimate.seconds, "estimated_steps": scene.estimated_steps()}


def geometric_stiffness(width: float, shear_modulus: float = SHEAR_MODULUS) -> float:
    """The stiffness of a slipping patch of width W breaking the free surface: 2 G / (pi W) (Pa/m).

    A mode III crack of half-width W under a uniform stress drop slips on average (pi / 2) dtau W / G; the free
    surface mirrors a surface-breaking fault of width W into it (Knopoff 1958; Scholz 2019, eq. 4.26)."""
    return 2.0 * shear_modulus / (math.pi * width)


def block_errors(row: dict, stiffness: float, cycles: int = 5) -> dict:
    """The one slider at ``stiffness`` against a design's 2-D answer: relative errors in recurrence and in slip
    per event (the 2-D slip averaged over the weakening width), and the model error, the larger."""
    design = Design(**row["design"])
    block = fault_cycles(design.slider(stiffness), PLATE_RATE, cycles=cycles)
    slip = float(block.slip_per_event.mean())
    recurrence_error = block.recurrence / row["recurrence_2d"] - 1
    slip_error = slip / row["mean_slip_2d"] - 1
    return {"recurrence_one_slider": block.recurrence, "slip_one_slider": slip,
            "recurrence_error": recurrence_error, "slip_error": slip_error,
            "model_error": max(abs(recurrence_error), abs(slip_error))}
