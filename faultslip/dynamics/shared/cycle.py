"""The stick-slip limit cycle as a result shared by every solution method."""

from __future__ import annotations

from dataclasses import dataclass, field

from faultslip.io.report import Report
from faultslip.datasets import ToXarray, dataclass_dataset

#: Regimes a method can report.
STICK_SLIP = "stick_slip"
STEADY_SLIDING = "steady_sliding"
GROWING_OSCILLATION = "growing_oscillation"
REGIMES = (STICK_SLIP, STEADY_SLIDING, GROWING_OSCILLATION)


@dataclass
class CycleResult(ToXarray):
    """Quantities of one stick-slip limit cycle (SI; force units follow the system scale).

    Three lengths describe one event, and they differ at high loading rate:

    * ``amplitude``, the **peak-to-peak swing** x_max - x_min of the slider (what seed 003 read
      from its force records);
    * ``stress_drop_slip``, the seeds' alpha = x1 - x2, the drop of spring extension from
      break-away to re-stick, i.e. stress drop / K (eq. 2-19 approximates it);
    * ``slip_per_event``, the **slip of the event**: the relative sliding of slider and platform
      during the slip phase, the integral of u = V - x' over it, which equals V times the period.
      This is an earthquake's slip.

    ``stress_drop`` is the drop of the holding force K x + C V from break-away to re-stick (N in
    the lab, Pa on a fault). All three lengths agree as the loading rate tends to zero.
    """

    method: str
    regime: str
    loading_rate: float
    platform_speed: float
    static_friction: float
    damping_ratio: float
    dimensionless_rate: float
    amplitude: float
    slip_per_event: float
    stick_duration: float
    slip_duration: float
    period: float
    peak_slip_speed: float
    stress_drop: float
    scale: str = "lab"
    extra: dict = field(default_factory=dict)
    stress_drop_slip: float = float("nan")

    #: the units of to_xarray() (faultslip.datasets.ToXarray); the stress drop's follows the scale
    UNITS = {"loading_rate": "1/s", "platform_speed": "m/s", "static_friction": "1", "damping_ratio": "1",
             "dimensionless_rate": "1", "amplitude": "m", "slip_per_event": "m", "stick_duration": "s",
             "slip_duration": "s", "period": "s", "peak_slip_speed": "m/s", "stress_drop_slip": "m"}

    def to_xarray(self):
        """The cycle's numbers as an xarray Dataset with their units (the stress drop in N in the lab, Pa on a
        fault)."""
        return dataclass_dataset(self, {**self.UNITS, "stress_drop": "N" if self.scale == "lab" else "Pa"})

    def report(self, title: str) -> Report:
        force = "Pa" if self.scale == "fault" else "N"
        time_also = ("yr",) if self.scale == "fault" else ("ms",)
        r = Report(title)
        r.section("Cycle")
        r.add("method", self.method)
        r.add("regime", self.regime)
        r.add("loading_rate", self.loading_rate, "1/s", "loading rate theta_dot")
        r.add("platform_speed", self.platform_speed, "m/s", "platform speed V", also=("in/s",) if self.scale == "lab" else ("mm/yr",))
        r.add("static_friction", self.static_friction, label="static friction mu_s")
        r.add("damping_ratio", self.damping_ratio, label="damping ratio zeta")
        r.add("dimensionless_rate", self.dimensionless_rate, label="epsilon = theta_dot/(omega_n dmu_s)")
        length = ("in",) if self.scale == "lab" else ("ft",)
        r.add("slip_per_event", self.slip_per_event, "m", "slip per event, integral of u dt = V T", also=length)
        r.add("stress_drop_slip", self.stress_drop_slip, "m", "stress-drop slip alpha = x1 - x2 = drop / K", also=length)
        r.add("peak_to_peak_swing", self.amplitude, "m", "peak-to-peak swing x_max - x_min", also=length)
        r.add("stick_duration", self.stick_duration, "s", "stick duration", also=time_also)
        r.add("slip_duration", self.slip_duration, "s", "slip duration", also=("ms",) if self.scale == "lab" else ())
        r.add("period", self.period, "s", "cycle period T", also=time_also)
        r.add("peak_slip_speed", self.peak_slip_speed, "m/s", "peak sliding speed")
        r.add("stress_drop", self.stress_drop, force, "stress drop" if self.scale == "fault" else "force drop", also=("bar",) if self.scale == "fault" else ("lbf",))
        for key, (value, unit, label) in self.extra.items():
            r.add(key, value, unit, label)
        return r
