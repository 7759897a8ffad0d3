r"""Slide-hold-slide: frictional healing against hold time (Dieterich 1972; Beeler, Tullis & Weeks 1994).

For each hold of a record (a segment where the load point stops, between two sliding segments):

- mu_ss, the steady friction before the hold: the median over the last fifth of the slide before it;
- mu_min, the least friction during the hold (the relaxation Delta mu_c = mu_ss - mu_min);
- mu_peak, the largest friction on reloading, within the slide after the hold;
- Delta mu = mu_peak - mu_ss, the healing, against the hold time t_h.

The healing rate is the slope beta of Delta mu against log10 t_h, by ordinary least squares with its
standard error and a Student-t 95 % interval (three holds or more; two give a slope without one):

.. math:: \Delta\mu = \beta \log_{10} t_h + c.

For the aging law on a stiff machine, Delta mu approaches b ln(1 + t_h V / D_c) at long holds, so beta tends
to b ln 10 (Beeler et al. 1994, JGR 99(B9), 18217); the slip law heals only as much as the slider slips during
the hold, far less.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from faultslip.errors import InputError
from faultslip.datasets import ToXarray

#: the share of the slide before a hold over which its steady friction is taken
STEADY_SHARE = 0.2


@dataclass
class Healing(ToXarray):
    """Each hold's healing and relaxation, and the healing rate per decade of hold time."""

    hold_time: np.ndarray  # s
    healing: np.ndarray  # Delta mu = mu_peak - mu_ss
    relaxation: np.ndarray  # Delta mu_c = mu_ss - mu_min
    steady: np.ndarray  # mu_ss before each hold
    hold_start: np.ndarray  # s
    rate: float = math.nan  # beta, per decade of hold time
    rate_error: float = math.nan
    rate_interval: tuple = (math.nan, math.nan)
    intercept: float = math.nan
    notes: list = field(default_factory=list)

    def as_dict(self) -> dict:
        def number(value):
            return value if math.isfinite(value) else None

        return {"holds": [{"start": {"value": float(s), "units": "s"}, "hold_time": {"value": float(t), "units": "s"},
                           "healing": float(h), "relaxation": float(r), "steady_friction": float(m)}
                          for s, t, h, r, m in zip(self.hold_start, self.hold_time, self.healing, self.relaxation,
                                                   self.steady)],
                "healing_rate": {"value": number(self.rate), "units": "1 per decade of hold time",
                                 "standard_error": number(self.rate_error),
                                 "interval_95": [number(v) for v in self.rate_interval]},
                "notes": self.notes}

    def to_dataset(self):
        """The holds as an xarray Dataset on dimension ``hold``, with the rate in its attributes."""
        import xarray as xr  # heavy: imported where used

        return xr.Dataset(
            {"hold_time": ("hold", self.hold_time, {"units": "s", "long_name": "hold time"}),
             "healing": ("hold", self.healing, {"units": "1", "long_name": "peak friction on reloading less the "
                                                                        "steady friction before the hold"}),
             "relaxation": ("hold", self.relaxation, {"units": "1", "long_name": "friction lost during the hold"}),
             "steady_friction": ("hold", self.steady, {"units": "1", "long_name": "steady friction before the hold"}),
             "hold_start": ("hold", self.hold_start, {"units": "s", "long_name": "when the hold began"})},
            attrs={"healing_rate_per_decade": self.rate, "healing_rate_standard_error": self.rate_error,
                   "healing_rate_interval_95": list(self.rate_interval)})


def healing(record) -> Healing:
    """Healing and relaxation at each hold of ``record`` and the healing rate (see the module).

    Parameters
    ----------
    record : StepRecord
        Friction against time with its load history (holds are segments of zero load-point speed).

    Returns
    -------
    Healing
        Per hold: hold time (s), Delta mu, Delta mu_c, mu_ss; and beta per decade with its 95 % interval.
    """
    from scipy.special import stdtrit  # heavy: imported where used

    times, speeds = record.history.times, record.history.speeds
    rows = []
    for i, speed in enumerate(speeds):
        if speed != 0.0 or i == 0 or i + 1 >= len(speeds) or speeds[i - 1] <= 0 or speeds[i + 1] <= 0:
            continue  # a hold between two slides
        before_start, start, end, after_end = times[i - 1], times[i], times[i + 1], times[i + 2]
        steady = (record.time >= start - STEADY_SHARE * (start - before_start)) & (record.time < start)
        during = (record.time >= start) & (record.time <= end)
        after = (record.time > end) & (record.time <= after_end)
        if steady.sum() < 3 or not during.any() or after.sum() < 3:
            continue
        mu_ss = float(np.median(record.friction[steady]))
        rows.append((start, end - start, float(np.max(record.friction[after])) - mu_ss,
                     mu_ss - float(np.min(record.friction[during])), mu_ss))
    if not rows:
        raise InputError(f"{record.source or 'the record'} has no hold between two slides: slide-hold-slide needs "
                         "the load point to stop and start again")
    start, hold, heal, relax, steady = (np.array(column, dtype=float) for column in zip(*rows))
    result = Healing(hold, heal, relax, steady, start)
    distinct = np.unique(np.round(np.log10(hold), 6))
    if distinct.size >= 2:
        x = np.log10(hold)
        slope, intercept = np.polyfit(x, heal, 1)
        result.rate, result.intercept = float(slope), float(intercept)
        if hold.size >= 3:
            residual = heal - (slope * x + intercept)
            dof = hold.size - 2
            error = math.sqrt(float(residual @ residual) / dof / float(np.sum((x - x.mean()) ** 2)))
            quantile = float(stdtrit(dof, 0.975))
            result.rate_error = error
            result.rate_interval = (slope - quantile * error, slope + quantile * error)
        else:
            result.notes.append("two holds give a healing rate without an interval: three or more give one")
    else:
        result.notes.append("every hold is as long as the others: no healing rate, only each hold's healing")
    return result


@dataclass
class SteadyStep:
    """A velocity step's steady-state friction change: a - b = Delta mu_ss / ln(V_after / V_before)."""

    time: float  # s
    speed_before: float  # m/s
    speed_after: float
    friction_before: float
    friction_after: float

    @property
    def a_minus_b(self) -> float:
        return (self.friction_after - self.friction_before) / math.log(self.speed_after / self.speed_before)


class SteadySteps(list, ToXarray):
    """:func:`steady_state_dependence`'s list of :class:`SteadyStep`, which also gives xarray."""

    def to_dataset(self):
        """One row a step on dimension ``step``: time, speeds, steady frictions and a - b."""
        import xarray as xr  # heavy: imported where used

        column = lambda key: np.array([getattr(row, key) for row in self], dtype=float)  # noqa: E731
        return xr.Dataset(
            {"time": ("step", column("time"), {"units": "s", "long_name": "when the step came"}),
             "speed_before": ("step", column("speed_before"), {"units": "m/s"}),
             "speed_after": ("step", column("speed_after"), {"units": "m/s"}),
             "friction_before": ("step", column("friction_before"), {"units": "1", "long_name": "steady friction"}),
             "friction_after": ("step", column("friction_after"), {"units": "1", "long_name": "steady friction"}),
             "a_minus_b": ("step", column("a_minus_b"), {"units": "1", "long_name": "d mu_ss / d ln V"})},
            coords={"step": ("step", np.arange(1, len(self) + 1))}, attrs={"Conventions": "CF-1.8"})


def steady_state_dependence(record) -> SteadySteps:
    """Each step between two slides at steady state: the friction over the last fifth of the segment before and of
    the segment after it (medians), and a - b = d mu_ss / d ln V (Dieterich 1979), which no fit of a, b and D_c
    is needed for.

    Parameters
    ----------
    record : StepRecord
        Friction against time with its load history.

    Returns
    -------
    SteadySteps
        A list of :class:`SteadyStep`, each step's time (s), speeds (m/s), steady frictions before and after, and
        ``a_minus_b``; ``to_dataset()``.
    """
    times, speeds = record.history.times, record.history.speeds
    rows = SteadySteps()
    for i in range(1, len(speeds)):
        if speeds[i - 1] <= 0 or speeds[i] <= 0:
            continue
        before = (record.time >= times[i] - STEADY_SHARE * (times[i] - times[i - 1])) & (record.time < times[i])
        after = (record.time >= times[i + 1] - STEADY_SHARE * (times[i + 1] - times[i])) & (record.time < times[i + 1])
        if before.sum() < 3 or after.sum() < 3:
            continue
        rows.append(SteadyStep(float(times[i]), float(speeds[i - 1]), float(speeds[i]),
                               float(np.median(record.friction[before])), float(np.median(record.friction[after]))))
    return rows
