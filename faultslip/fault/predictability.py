"""Is a sequence of earthquakes periodic, time-predictable, slip-predictable or Poisson? (issue 45, item 2)

The exercise students do with QuakeCaster (Linton & Stein 2012) and the recurrence models it tests:

* **time-predictable** (Shimazaki & Nakata 1980): an earthquake happens when stress reaches a fixed upper level,
  so the larger an event's slip, the longer the interval that *follows* it: the correlation of slip s_k with the
  next interval T_k is positive;
* **slip-predictable**: an earthquake drops stress to a fixed lower level, so the longer the interval that
  *precedes* an event, the larger its slip: the correlation of T_(k-1) with s_k is positive;
* **periodic** or **Poisson**: the intervals' coefficient of variation (sd / mean) near 0, or near 1 (the
  exponential intervals of a Poisson process).

Correlations are Pearson's r with a 95 % range from Fisher's z (atanh r has standard error 1 / sqrt(m - 3)). The
coefficient of variation is the sample's, with a 95 % range from a seeded bootstrap of the intervals (percentiles:
at a dozen events such ranges hold the truth about 90 % of the time, not 95 %; the renewal fits of
:mod:`faultslip.fault.recurrence` give exact pivots for a model's aperiodicity, which is not the sample's CV for a
Poisson process). Each verdict states its rule: a positive correlation needs its range above 0; periodic means the
coefficient of variation's range lies below 0.5 (what hazard models call quasi-periodic, Ellsworth et al. 1999);
Poisson means its range holds 1.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from faultslip.errors import InputError
from faultslip.io.report import Report
from faultslip.datasets import ToXarray
from faultslip.units import is_quantity, takes_units

#: The aperiodicity below which a sequence is called periodic (its whole 95 % range), after Ellsworth et al. (1999).
PERIODIC_BELOW = 0.5
Z95 = 1.959963984540054


@dataclass
class Predictability(ToXarray):
    """What :func:`predictability` found: the intervals, the two correlations and the aperiodicity, each with its
    95 % range, and the verdicts."""
    #: the units and dimensions of to_xarray() (faultslip.datasets.ToXarray)
    UNITS = {'times': 's', 'slips': 'm', 'intervals': 's', 'time_correlation': '1', 'time_range': '1', 'slip_correlation': '1', 'slip_range': '1', 'aperiodicity': '1', 'aperiodicity_range': '1'}
    DIMENSIONS = {'times': 'event', 'slips': 'event'}

    times: np.ndarray  # s, the events' times from the first
    slips: np.ndarray  # each event's slip (m), or its size in any unit proportional to slip (a moment)
    intervals: np.ndarray  # s
    time_correlation: float  # r(s_k, T_k): slip against the interval that follows
    time_range: tuple
    slip_correlation: float  # r(T_(k-1), s_k): the interval before against the slip
    slip_range: tuple
    aperiodicity: float  # the intervals' coefficient of variation, sd (n - 1) / mean
    aperiodicity_range: tuple
    slip_unit: str = "m"

    def to_xarray(self):
        """The result as an xarray Dataset; the slips carry the unit they were given in (a moment's N m)."""
        dataset = super().to_xarray()
        dataset["slips"].attrs["units"] = self.slip_unit.split(" (")[0]
        return dataset

    @property
    def verdicts(self) -> dict:
        """Each recurrence model: whether the sequence supports it, by the rules of the module docstring."""
        return {"time_predictable": bool(self.time_range[0] > 0), "slip_predictable": bool(self.slip_range[0] > 0),
                "periodic": bool(self.aperiodicity_range[1] < PERIODIC_BELOW),
                "poisson": bool(self.aperiodicity_range[0] <= 1.0 <= self.aperiodicity_range[1])}

    def report(self, title: str = "faultslip predictability") -> Report:
        """The statistics and verdicts as a report (text and ``--json``)."""
        years = 365.25 * 86400.0
        report = Report(title)
        report.add("events", int(self.times.size))
        report.add("mean_interval", float(self.intervals.mean()), "s", also=("yr",), label="mean interval")
        report.add("aperiodicity", self.aperiodicity, label="coefficient of variation of the intervals (sd / mean)")
        report.add("aperiodicity_95", list(self.aperiodicity_range), "1", label="its 95 % range (bootstrap)")
        report.add("time_predictable_correlation", self.time_correlation,
                   label="r(slip, the interval after it): time-predictable where its range is above 0")
        report.add("time_predictable_correlation_95", list(self.time_range), "1", label="its 95 % range (Fisher z)")
        report.add("slip_predictable_correlation", self.slip_correlation,
                   label="r(the interval before, slip): slip-predictable where its range is above 0")
        report.add("slip_predictable_correlation_95", list(self.slip_range), "1", label="its 95 % range (Fisher z)")
        for model, supported in self.verdicts.items():
            report.add(model, supported, label=f"{model.replace('_', '-')}: {'supported' if supported else 'not supported'}")
        report.note(f"periodic: the coefficient of variation's 95 % range below {PERIODIC_BELOW:g}; Poisson: it holds 1; "
                    "a predictable model: its correlation's 95 % range above 0")
        report.note(f"intervals: {', '.join(f'{value / years:.4g}' for value in self.intervals)} yr")
        if not _varies(self.slips):
            report.note("every event has the same size here: neither predictable model can be tested (r = 0, its "
                        "range -1 to 1); a catalogue of nominal magnitudes says nothing of slip")
        return report


def _varies(values) -> bool:
    """Whether a sample varies by more than its values' round-off."""
    return bool(np.ptp(values) > 1e-12 * np.max(np.abs(values)))


def correlation(x, y) -> tuple[float, tuple[float, float]]:
    """Pearson's r of ``x`` and ``y`` and its 95 % range by Fisher's z transform.

    Parameters
    ----------
    x, y : array_like
        Paired samples, at least 4.

    Returns
    -------
    tuple
        (r, (low, high)), dimensionless; r is 0 with the range (-1, 1) where either sample does not vary.
    """
    x, y = np.asarray(x, float), np.asarray(y, float)
    if x.size < 4:
        raise InputError(f"a correlation's 95 % range needs 4 pairs or more, got {x.size}")
    if not (_varies(x) and _varies(y)):  # equal sizes (a catalogue's nominal magnitudes): nothing to correlate
        return 0.0, (-1.0, 1.0)
    dx, dy = x - x.mean(), y - y.mean()
    scale = math.sqrt(float(np.sum(dx * dx) * np.sum(dy * dy)))
    r = float(np.clip(np.sum(dx * dy) / scale, -1.0, 1.0))
    if abs(r) == 1.0:
        return r, (r, r)
    z, se = math.atanh(r), 1.0 / math.sqrt(x.size - 3)
    return r, (math.tanh(z - Z95 * se), math.tanh(z + Z95 * se))


@takes_units(times="time")
def predictability(times, slips, draws: int = 20000, seed: int = 0, slip_unit: str = "m") -> Predictability:
    """Test a sequence's recurrence models: time-predictable, slip-predictable, periodic and Poisson.

    Parameters
    ----------
    times : array_like
        The events' times (s), increasing.
    slips : array_like or Quantity
        Each event's slip (m), or any size proportional to it (a seismic moment, with ``slip_unit`` saying so; a
        Quantity says its own unit).
    draws : int
        Bootstrap resamples of the intervals.
    seed : int
        Their generator's seed (the answer is reproducible).
    slip_unit : str
        The unit of ``slips``, for the report.

    Returns
    -------
    Predictability
        The correlations, the aperiodicity, their 95 % ranges, and the verdicts.
    """
    if is_quantity(slips):  # the tests are scale-free: the slips keep the unit they were given in
        slips, slip_unit = slips.magnitude, f"{slips.units:~C}"
    times, slips = np.asarray(times, float), np.asarray(slips, float)
    if times.ndim != 1 or times.shape != slips.shape:
        raise InputError("times and slips must be two lists of the same length")
    if times.size < 6:
        raise InputError(f"testing recurrence models needs 6 events or more (5 intervals), got {times.size}")
    if not (np.all(np.isfinite(times)) and np.all(np.isfinite(slips)) and np.all(slips > 0)):
        raise InputError("every event needs a finite time and a positive slip")
    intervals = np.diff(times)
    if not np.all(intervals > 0):
        raise InputError("the events' times must increase")
    time_r, time_range = correlation(slips[:-1], intervals)
    slip_r, slip_range = correlation(intervals, slips[1:])
    aperiodicity = float(intervals.std(ddof=1) / intervals.mean())
    resampled = np.random.default_rng(seed).choice(intervals, size=(draws, intervals.size), replace=True)
    spread = resampled.std(axis=1, ddof=1) / resampled.mean(axis=1)
    low, high = (float(v) for v in np.percentile(spread, [2.5, 97.5]))
    return Predictability(times - times[0], slips, intervals, time_r, time_range, slip_r, slip_range, aperiodicity,
                          (low, high), slip_unit)
