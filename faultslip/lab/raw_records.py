"""Raw velocity-step and slide-hold-slide records, as a rig writes them, made ready for a rate-and-state fit.

A rig writes time, the load point's displacement and the shear and normal load (or stress), in its
own units: a CSV with ``name (unit)`` headers, a whitespace-delimited text file (``name(unit)``
headers or a line of units under the names), or netCDF with ``units`` attributes. Units missing
from the file are given by the caller (``units={"shear_load": "kN"}``). RSFit3000 (Skarbek & Savage
2019) and xlook do the same preparation by hand; here it is one call, :func:`prepare_record`:

1. **friction** mu = tau / sigma_n, loads divided by the sample's contact ``area``;
2. **machine stiffness**: the machine (with the sample) is the spring of the slider. Given as a
   stiffness K in N/m (with the area), Pa/m or directly as friction per slip, the fit's spring is
   k = K / (sigma_n A) in 1/m, and the sample's own displacement is the load point's less the
   machine's elastic stretch, delta_s = delta_lp - mu / k;
3. **steps and holds** (:func:`detect_steps`): the load-point speed from moving least-squares slopes
   of the displacement; a change of more than ``min_change`` (30 %) between the slopes on either
   side is a step, placed where two straight lines, joined there, fit the displacement best; a
   segment slower than a thousandth of the median speed is a hold. Step times given by the user
   replace the detection;
4. **detrending** (stated in the result): friction often drifts with slip. A polynomial of degree
   1 or 2 in delta_s is fitted to the steady-state tails of the sliding segments, each speed with
   its own level (the velocity dependence), and removed from the whole record. A record that
   returns to a speed it ran at before pins the trend; one that does not leaves only each tail's
   own slope, which the report's coefficient then carries with its noise.

The result carries a :class:`faultslip.lab.rate_state_fit.StepRecord` for the joint fit and
windows for each step's own fit (:func:`fit_each_step`).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from faultslip.dynamics.rate_state.slider import LoadHistory, RateStateSlider, simulate_rate_state
from faultslip import ranges
from faultslip.errors import InputError, SolverError
from faultslip.io.progress import counted
from faultslip.io.resources import check_input_file, open_netcdf, read_numeric_table, read_table_metadata, split_header
from faultslip.lab.rate_state_fit import StepRecord, fit_velocity_steps, step_record_from_columns
from faultslip.units import takes_units, to_si_scalar, unit_factor
from faultslip.datasets import ToXarray

RAW_COLUMNS = {"time": "time", "load_point_displacement": "length", "shear_load": "force",
               "normal_load": "force", "shear_stress": "pressure", "normal_stress": "pressure"}
MIN_CHANGE = 0.3  # a speed change of 30 % or more is a step
HOLD_FRACTION = 1e-3  # slower than this fraction of the median speed: a hold
TAIL_FRACTION = 0.3  # the steady-state tail of a segment used for detrending


@dataclass
class RawRecord(ToXarray):
    """A rig's record in SI: time (s), load-point displacement (m), shear and normal stress (Pa)."""

    time: np.ndarray
    load_point_displacement: np.ndarray
    shear_stress: np.ndarray
    normal_stress: np.ndarray
    source: str = ""
    notes: list = field(default_factory=list)
    metadata: dict = field(default_factory=dict)  # what the file says of the experiment (id, stresses, area...)

    @property
    def friction(self) -> np.ndarray:
        return self.shear_stress / self.normal_stress

    def to_dataset(self):
        """The record as an xarray Dataset on dimension ``time`` with CF units (SI), friction beside the stresses,
        the file's metadata in attributes."""
        import xarray as xr  # heavy: imported where used

        return xr.Dataset(
            {"load_point_displacement": ("time", self.load_point_displacement,
                                         {"units": "m", "long_name": "load-point displacement"}),
             "shear_stress": ("time", self.shear_stress, {"units": "Pa", "long_name": "shear stress"}),
             "normal_stress": ("time", self.normal_stress, {"units": "Pa", "long_name": "normal stress"}),
             "friction": ("time", self.friction, {"units": "1", "long_name": "shear over normal stress"})},
            coords={"time": ("time", self.time, {"units": "s"})},
            attrs={"source": self.source, "notes": "; ".join(self.notes), "Conventions": "CF-1.8",
                   **{f"record_{key}": str(value) for key, value in self.metadata.items()}})


def _columns_to_raw(columns: dict, source: str, units: dict | None, area) -> RawRecord:
    units = dict(units or {})
    for name in units:
        if name not in RAW_COLUMNS:
            raise InputError(f"raw record {source}: a unit was given for {name!r}, which is not one of its columns "
                             f"({', '.join(RAW_COLUMNS)})")
    unknown = [name for name in columns if name not in RAW_COLUMNS]
    if unknown:
        raise InputError(f"raw record {source}: unknown column {unknown[0]!r} (allowed: {', '.join(RAW_COLUMNS)})")
    for required in ("time", "load_point_displacement"):
        if required not in columns:
            raise InputError(f"raw record {source} needs a {required} column")
    notes = []
    si = {}
    for name, (values, unit) in columns.items():
        unit = units.get(name, unit)
        if not unit:
            raise InputError(f"raw record {source}: column {name!r} has no unit; give it in the header "
                             f"('{name} (unit)') or with units, e.g. --units {name}=...")
        si[name] = np.asarray(values, dtype=float) * unit_factor(unit, RAW_COLUMNS[name],
                                                                  f"raw record {source}, column {name}")
    stresses = {}
    for kind in ("shear", "normal"):
        if f"{kind}_stress" in si:
            stresses[kind] = si[f"{kind}_stress"]
        elif f"{kind}_load" in si:
            if area is None:
                raise InputError(f"raw record {source} gives the {kind} load: give the sample's contact area "
                                 f"(--area) to make it a stress")
            stresses[kind] = si[f"{kind}_load"] / area
            notes.append(f"{kind} stress = {kind} load / {area:.4g} m^2")
        else:
            raise InputError(f"raw record {source} needs a {kind}_load or {kind}_stress column")
    time, displacement = si["time"], si["load_point_displacement"]
    if time.size < 50:
        raise InputError(f"raw record {source} has {time.size} rows; steps need at least 50")
    for name, values in (("time", time), ("load_point_displacement", displacement), ("shear", stresses["shear"]),
                         ("normal", stresses["normal"])):
        if not np.all(np.isfinite(values)):
            raise InputError(f"raw record {source}: the {name} column holds values that are not finite numbers")
    if np.any(np.diff(time) <= 0):
        raise InputError(f"raw record {source}: times must increase")
    if np.any(stresses["normal"] <= 0):
        raise InputError(f"raw record {source}: the normal stress must be positive (compression) throughout")
    return RawRecord(time - time[0], displacement - displacement[0], stresses["shear"], stresses["normal"], source,
                     notes)


def raw_record(table, units: dict | None = None, area=None, source: str = "<table>") -> RawRecord:
    """A raw record from a pandas DataFrame or a mapping of columns (``"time (s)"`` headers, pint Quantity
    columns, or bare names with ``units``); ``area`` (m^2, or a string with units) turns loads into stresses.

    Parameters
    ----------
    table : DataFrame or mapping
        The record's columns.
    units : dict, optional
        Column -> unit, for bare column names.
    area : str, Quantity or float, optional
        The sample's area (m^2).
    source : str
        A name for messages.

    Returns
    -------
    RawRecord
    """
    if hasattr(table, "columns") and hasattr(table, "to_dict"):
        items = [(str(column), table[column].to_numpy()) for column in table.columns]
    elif isinstance(table, dict):
        items = list(table.items())
    else:
        raise InputError(f"a raw record is a DataFrame, a mapping of columns or a file, got {type(table).__name__}")
    columns = {}
    for header, values in items:
        name, unit = split_header(str(header))
        if hasattr(values, "units") and hasattr(values, "magnitude"):
            values, unit = values.magnitude, str(values.units)
        columns[name] = (np.asarray(values, dtype=float), unit)
    return _columns_to_raw(columns, source, units, _area(area))


def _area(area):
    if area is None:
        return None
    value = to_si_scalar(area, "area", "the contact area", default_unit="m^2")
    return ranges.check("area", value, f"--area {area}")


def _read_columns(path, what: str, only=None) -> tuple:
    """(path, {name: (values, unit)}) of a table through the reader gate: netCDF (``units`` attributes),
    whitespace text (``.txt``, ``.dat``, ``.tsv``), an Excel workbook (``.xlsx``) or CSV; ``only`` keeps netCDF's
    named variables."""
    path = check_input_file(path, what)
    label = f"{what} {path.name}"
    if path.suffix.lower() == ".nc":
        data = open_netcdf(path, what)
        names = [n for n in list(data.data_vars) + list(data.coords) if only is None or n in only]
        return path, {name: (data[name].values, data[name].attrs.get("units")) for name in names}
    return path, read_numeric_table(path, label)


def read_raw_record(path, units: dict | None = None, area=None) -> RawRecord:
    """A raw record from CSV (``name (unit)`` headers), whitespace-delimited text (``.txt``, ``.dat``,
    ``.tsv``: see :func:`faultslip.io.resources.read_numeric_text`) or netCDF (``units`` attributes).

    Parameters
    ----------
    path : str or path
        The record.
    units : dict, optional
        Column -> unit, for bare column names.
    area : str, Quantity or float, optional
        The sample's area (m^2).

    Returns
    -------
    RawRecord
    """
    path, columns = _read_columns(path, "raw record", only=RAW_COLUMNS)
    return _columns_to_raw(columns, path.name, units, _area(area))


def is_raw_table(names) -> bool:
    """Whether columns named ``names`` are a raw record (loads or stresses) rather than a friction record."""
    names = set(names)
    return "friction" not in names and bool(names & {"shear_load", "shear_stress"})


def _window_slopes(time, displacement, width):
    """Least-squares slopes of displacement over the ``width`` samples left and right of each sample."""
    n = time.size
    c = lambda values: np.concatenate(([0.0], np.cumsum(values)))  # noqa: E731
    st, sd, stt, std = c(time), c(displacement), c(time * time), c(time * displacement)

    def slope(lo, hi):
        count = hi - lo
        mean_t = (st[hi] - st[lo]) / count
        mean_d = (sd[hi] - sd[lo]) / count
        var = (stt[hi] - stt[lo]) / count - mean_t ** 2
        cov = (std[hi] - std[lo]) / count - mean_t * mean_d
        return cov / np.maximum(var, 1e-300)

    index = np.arange(n)
    left = slope(np.clip(index - width, 0, n), np.clip(index, 1, n))
    right = slope(np.clip(index, 0, n - 1), np.clip(index + width, 1, n))
    return left, right


def _hinge_fits(time, displacement):
    """(knots, residual sums of squares, coefficients) of the continuous two-line fit d = c0 + c1 min(t - t_k, 0)
    + c2 max(t - t_k, 0) with its knot at each sample t_k, k = 2 .. n - 3: every knot's 3 x 3 normal equations
    from running sums, so all n fits cost O(n) (c1 and c2 are the speeds before and after the knot)."""
    t = np.asarray(time, dtype=float)
    d = np.asarray(displacement, dtype=float)
    t, d = t - t.mean(), d - d.mean()  # centred: the normal equations stay well conditioned
    n = t.size
    knots = np.arange(2, n - 2)
    if knots.size == 0:
        return knots, np.empty(0), np.empty((0, 3))
    running = lambda values: np.concatenate(([0.0], np.cumsum(values)))  # noqa: E731
    s_1, s_t, s_tt, s_d, s_td = (running(v) for v in (np.ones(n), t, t * t, d, t * d))
    total_dd = float(d @ d)
    at = t[knots]
    left = [s[knots] for s in (s_1, s_t, s_tt, s_d, s_td)]
    right = [s[-1] - s[knots] for s in (s_1, s_t, s_tt, s_d, s_td)]
    sides = []
    for count, sum_t, sum_tt, sum_d, sum_td in (left, right):
        sides.append((sum_t - at * count, sum_tt - 2 * at * sum_t + at * at * count, sum_td - at * sum_d))
    (x1, x1x1, x1d), (x2, x2x2, x2d) = sides
    normal = np.zeros((knots.size, 3, 3))
    normal[:, 0, 0] = n
    normal[:, 0, 1] = normal[:, 1, 0] = x1
    normal[:, 0, 2] = normal[:, 2, 0] = x2
    normal[:, 1, 1], normal[:, 2, 2] = x1x1, x2x2
    rhs = np.stack([np.full(knots.size, float(s_d[-1])), x1d, x2d], axis=1)
    coefficients = np.linalg.solve(normal, rhs[..., None])[..., 0]
    return knots, total_dd - np.einsum("ij,ij->i", coefficients, rhs), coefficients


def _hinge_time(time, displacement, lo, hi):
    """The time in samples [lo, hi) where two straight lines joined there fit the displacement best."""
    knots, errors, _ = _hinge_fits(time[lo:hi], displacement[lo:hi])
    return float(time[lo + knots[np.argmin(errors)]]) if knots.size else float(time[lo])


SPLIT_F = 1000.0  # a segment is split where two joined lines beat one by F > 1000 (a step, not the noise's wander)
MIN_SEGMENT = 20  # samples on each side of a boundary


def _refine_boundaries(time, displacement, boundaries, min_change):
    """Each step placed again on the samples themselves, between its neighbours' midpoints (a coarse search's
    window spans short segments), segments shorter than :data:`MIN_SEGMENT` samples dropped, and a segment
    split where two joined lines fit its samples far better than one (F > :data:`SPLIT_F`) with speeds
    differing by more than ``min_change``: a segment shorter than the coarse search's window (p655's 4 s at
    23 um/s after 228.6 um/s) is found this way. Repeated until nothing moves."""
    bounds = [float(b) for b in boundaries]
    threshold = math.log1p(min_change)
    for _ in range(20):
        before = list(bounds)
        for i in range(1, len(bounds) - 1):
            lo, hi = 0.5 * (bounds[i - 1] + bounds[i]), 0.5 * (bounds[i] + bounds[i + 1])
            rows = np.flatnonzero((time >= lo) & (time <= hi))
            knots, errors, _ = _hinge_fits(time[rows], displacement[rows])
            if knots.size:
                bounds[i] = float(time[rows[knots[np.argmin(errors)]]])
        counts = [int(((time >= a) & (time < b)).sum()) for a, b in zip(bounds[:-1], bounds[1:])]
        short = [i for i, c in enumerate(counts) if c < MIN_SEGMENT]
        if short and len(bounds) > 2:  # drop the boundary that closes (or, for the last, opens) a short segment
            i = short[0]
            del bounds[min(i + 1, len(bounds) - 2) if i + 1 < len(bounds) - 1 else i]
            continue
        split = []
        for a, b in zip(bounds[:-1], bounds[1:]):
            rows = np.flatnonzero((time >= a) & (time <= b))
            if rows.size < 4 * MIN_SEGMENT:
                continue
            knots, errors, coefficients = _hinge_fits(time[rows], displacement[rows])
            allowed = (knots >= MIN_SEGMENT) & (knots <= rows.size - MIN_SEGMENT)
            if not allowed.any():
                continue
            best = int(np.argmin(np.where(allowed, errors, np.inf)))
            t, d = time[rows] - time[rows].mean(), displacement[rows]
            line = np.polyfit(t, d, 1)
            single = float(np.sum((np.polyval(line, t) - d) ** 2))
            two = max(float(errors[best]), 1e-300)
            speed_before, speed_after = abs(coefficients[best, 1]), abs(coefficients[best, 2])
            floor = 0.02 * max(speed_before, speed_after, 1e-300)
            if ((single - two) / (two / (rows.size - 3)) > SPLIT_F
                    and abs(math.log((speed_after + floor) / (speed_before + floor))) > threshold):
                split.append(float(time[rows[knots[best]]]))
        bounds = sorted(bounds + split)
        if bounds == before:
            break
    return bounds


def _segment_speeds(time, displacement, boundaries):
    """Each segment's load-point speed: the slope of a straight line through its middle 80 %."""
    speeds = []
    for start, end in zip(boundaries[:-1], boundaries[1:]):
        inside = (time >= start + 0.1 * (end - start)) & (time <= end - 0.1 * (end - start))
        if inside.sum() < 3:
            inside = (time >= start) & (time <= end)
        if inside.sum() < 2:
            raise InputError(f"the segment from {start:.4g} s to {end:.4g} s holds fewer than two samples")
        speeds.append(float(np.polyfit(time[inside], displacement[inside], 1)[0]))
    return speeds


@takes_units(time="time", displacement="length", step_times="time")
def detect_steps(time, displacement, min_change: float = MIN_CHANGE, width: int | None = None,
                 step_times=None, resample: bool = True) -> LoadHistory:
    """The load history (segment start times and constant speeds) of a load-point displacement record.

    With ``step_times`` the segments are the user's and only their speeds are measured.

    Parameters
    ----------
    time : array_like
        Sample times (s).
    displacement : array_like
        Load-point displacement (m).
    min_change : float
        The smallest relative change of speed that is a step.
    width : int, optional
        The smoothing window (samples).
    step_times : array_like, optional
        The user's step times (s).
    resample : bool
        Where the sampling interval changes more than twofold, find the steps on bin means of a uniform grid at
        the coarse interval (the speeds are measured on the samples).

    Returns
    -------
    LoadHistory
        Segment start times (s) and speeds (m/s).
    """
    time, displacement = np.asarray(time, dtype=float), np.asarray(displacement, dtype=float)
    n = time.size
    intervals = np.diff(time)
    if resample and step_times is None and n > 4 and np.percentile(intervals, 99) > 2.0 * np.percentile(intervals, 1):
        # a rig that changes its sampling rate (p655: 0.1 s, 10 ms, 1 ms) would give windows of a fixed number of
        # samples a hundredfold range of durations: the steps are found on bin means of a uniform grid at the
        # coarse interval, and each segment's speed is measured on the samples themselves
        binned_time, binned = _uniform_bins(time, displacement, float(np.percentile(intervals, 99)))
        found = detect_steps(binned_time - binned_time[0], binned, min_change, width, resample=False)
        boundaries = [float(time[0]), *(t + binned_time[0] for t in found.times[1:-1]), float(time[-1])]
        return _history(time, displacement, _refine_boundaries(time, displacement, boundaries, min_change),
                        min_change, merge=True)
    if step_times is not None:
        steps = sorted(float(t) for t in step_times)
        if any(not (time[0] < t < time[-1]) for t in steps):
            raise InputError(f"step times must lie inside the record (0 to {time[-1]:.6g} s), got {steps}")
        boundaries = [float(time[0])] + steps + [float(time[-1])]
    else:
        if not 0.01 <= min_change <= 10:
            raise InputError(f"the smallest speed change taken for a step must be from 0.01 to 10, got {min_change}")
        width = width or max(5, n // 200)
        left, right = _window_slopes(time, displacement, width)
        # speeds below 2 % of the typical one count as equal: an LVDT's noise in a hold makes no steps
        typical = float(np.median(np.abs(left[width:])))
        floor = max(0.02 * typical, 1e-30)
        score = np.abs(np.log((np.abs(right) + floor) / (np.abs(left) + floor)))
        score[:width] = score[-width:] = 0.0
        threshold = math.log1p(min_change)
        candidates = []
        order = np.argsort(score)[::-1]
        taken = np.zeros(n, dtype=bool)
        for i in order:
            if score[i] < threshold:
                break
            if taken[max(0, i - width):i + width + 1].any():
                continue
            taken[i] = True
            candidates.append(int(i))
        refined = sorted(_hinge_time(time, displacement, max(0, i - 2 * width), min(n, i + 2 * width + 1))
                         for i in candidates)
        # two candidates on the flanks of one change (a hold's slow start) refine to one time: keep one
        spacing = width * float(np.median(np.diff(time)))
        steps = [t for k, t in enumerate(refined) if k == 0 or t - refined[k - 1] > spacing]
        boundaries = _refine_boundaries(time, displacement, [float(time[0])] + steps + [float(time[-1])], min_change)
    return _history(time, displacement, boundaries, min_change, merge=step_times is None)


def _uniform_bins(time, displacement, step: float):
    """(mean time, mean displacement) of the samples in each bin of width ``step`` that holds any."""
    index = np.minimum(((time - time[0]) / step).astype(np.int64), int((time[-1] - time[0]) / step))
    counts = np.bincount(index)
    held = counts > 0
    return (np.bincount(index, weights=time)[held] / counts[held],
            np.bincount(index, weights=displacement)[held] / counts[held])


def _history(time, displacement, boundaries, min_change, merge: bool) -> LoadHistory:
    """The segments' speeds measured on the samples, holds set to zero, and (``merge``) neighbours at one speed
    joined."""
    speeds = _segment_speeds(time, displacement, boundaries)
    typical = max(abs(s) for s in speeds)
    speeds = [0.0 if abs(s) < HOLD_FRACTION * typical else s for s in speeds]
    if merge:  # neighbours at one speed (a hold cut by noise) are one segment, measured again
        kept = [0]
        for i in range(1, len(speeds)):
            a, b = speeds[kept[-1]], speeds[i]
            if not ((a == 0.0 and b == 0.0) or (a > 0 and b > 0 and abs(math.log(b / a)) < 0.5 * math.log1p(min_change))):
                kept.append(i)
        if len(kept) < len(speeds):
            boundaries = [boundaries[i] for i in kept] + [boundaries[-1]]
            speeds = _segment_speeds(time, displacement, boundaries)
            speeds = [0.0 if abs(s) < HOLD_FRACTION * typical else s for s in speeds]
    if speeds[0] <= 0:
        raise InputError("the record must start sliding: its first segment has no positive load-point speed")
    if any(s < 0 for s in speeds):
        raise InputError("a segment runs the load point backwards (negative speed); faultslip fits forward loading")
    return LoadHistory(tuple(boundaries), tuple(speeds))


@dataclass
class PreparedRecord(ToXarray):
    """A raw record made ready: the step record to fit, the spring, the steps and the stated corrections."""

    record: StepRecord  # detrended friction, detected load history
    stiffness: float  # the fit's spring, friction per metre
    sample_displacement: np.ndarray  # m: load point less the machine's stretch
    raw_friction: np.ndarray
    trend: np.ndarray  # the removed trend, friction at each sample
    trend_coefficients: list  # c_j of sum_j c_j (delta_s / 1 mm)^j
    detrend: str
    raw: RawRecord
    notes: list = field(default_factory=list)

    @property
    def steps(self) -> list[float]:
        return list(self.record.history.times[1:-1])

    def to_dataset(self):
        """The prepared record (:meth:`StepRecord.to_dataset`) with the friction before detrending, the removed
        trend and the sample's own displacement; the fit's spring and the stated corrections in attributes."""
        dataset = self.record.to_dataset()
        dataset["raw_friction"] = ("time", self.raw_friction, {"units": "1", "long_name": "friction before detrending"})
        dataset["trend"] = ("time", self.trend, {"units": "1", "long_name": f"removed trend ({self.detrend})"})
        dataset["sample_displacement"] = ("time", self.sample_displacement,
                                          {"units": "m", "long_name": "load point less the machine's stretch"})
        dataset.attrs.update({"stiffness_per_m": self.stiffness, "detrend": self.detrend,
                              "trend_coefficients_per_mm": list(self.trend_coefficients),
                              "notes": "; ".join(self.notes)})
        return dataset

    def summary(self) -> dict:
        history = self.record.history
        return {"steps": [{"time": {"value": t, "units": "s"}, "speed_before": {"value": a, "units": "m/s"},
                           "speed_after": {"value": b, "units": "m/s"}, "hold": b == 0.0}
                          for t, a, b in zip(history.times[1:-1], history.speeds[:-1], history.speeds[1:])],
                "stiffness": {"value": self.stiffness, "units": "1/m"}, "detrend": self.detrend,
                "trend_coefficients_per_mm": self.trend_coefficients, "notes": self.notes}


def _stiffness(stiffness, normal_stress: float, area) -> tuple[float, str]:
    """The fit's spring in friction per metre from K in 1/m, Pa/m or N/m (with the area)."""
    text = str(stiffness)
    for kind, convert in (("inverse_length", lambda v: v), ("stress_per_length", lambda v: v / normal_stress),
                          ("stiffness", None)):
        try:
            value = to_si_scalar(stiffness, kind, "the stiffness", default_unit="1/m" if kind == "inverse_length" else None)
        except InputError:
            continue
        if convert is None:
            if area is None:
                raise InputError(f"a machine stiffness in force per length ({text}) needs the sample's contact area "
                                 "(--area) to become friction per slip")
            spring = value / (normal_stress * _area(area))
            if not (math.isfinite(spring) and spring > 0):  # K / (sigma_n A) can overflow on extreme inputs
                raise InputError(f"the stiffness {text} over sigma_n A = {normal_stress:.4g} Pa x {_area(area):.4g} m^2 "
                                 "is no finite friction per slip; check --stiffness, --area and the normal load")
            return spring, f"k = K / (sigma_n A) = {text} / ({normal_stress:.4g} Pa x {_area(area):.4g} m^2)"
        return convert(value), (f"k = {text}" if kind == "inverse_length" else
                                f"k = K / sigma_n = {text} / {normal_stress:.4g} Pa")
    raise InputError(f"the stiffness {text!r} must be friction per slip (1/um), stress per slip (MPa/mm) or force "
                     "per slip (kN/mm, with --area)")


@takes_units(step_times="time")
def prepare_record(raw: RawRecord, stiffness, *, area=None, detrend: str = "none", step_times=None,
                   min_change: float = MIN_CHANGE) -> PreparedRecord:
    """Friction, the fit's spring, the sample's displacement, the steps and holds, and the stated trend
    removed (``detrend`` none, linear or quadratic).

    Parameters
    ----------
    raw : RawRecord
        :func:`read_raw_record`'s record.
    stiffness : str, Quantity or float
        The machine stiffness: friction per slip (1/m), stress per slip (Pa/m) or force per slip (N/m, with
        ``area``).
    area : str, Quantity or float, optional
        The sample's area (m^2).
    detrend : str
        none, linear or quadratic.
    step_times : array_like, optional
        The steps' times (s).
    min_change : float
        The smallest relative change of speed that is a step.

    Returns
    -------
    PreparedRecord
        Friction (dimensionless), the spring (1/m), the load history and the holds.
    """
    if detrend not in ("none", "linear", "quadratic"):
        raise InputError(f"detrend must be none, linear or quadratic, got {detrend!r}")
    normal = float(np.median(raw.normal_stress))
    spring, spring_note = _stiffness(stiffness, normal, _area(area))
    if not (math.isfinite(spring) and spring > 0):
        raise InputError(f"the stiffness must be positive, got {stiffness!r}")
    friction = raw.friction
    sample = raw.load_point_displacement - (friction - friction[0]) / spring
    history = detect_steps(raw.time, raw.load_point_displacement, min_change=min_change, step_times=step_times)
    notes = list(raw.notes) + [spring_note, f"{len(history.speeds) - 1} step(s) "
                               + ("given" if step_times is not None else "detected")
                               + (f", {sum(s == 0 for s in history.speeds)} hold(s)" if 0.0 in history.speeds else "")]
    trend = np.zeros_like(friction)
    coefficients = []
    if detrend != "none":
        degree = 1 if detrend == "linear" else 2
        scale = 1e-3  # polynomial in millimetres: coefficients of order one
        # one level per distinct speed (within 5 %): segments that return to a speed identify the trend
        rows, segment_of, groups = [], [], []
        for i, speed in enumerate(history.speeds):
            if speed <= 0:
                continue
            group = next((g for g, value in enumerate(groups) if abs(speed / value - 1) < 0.05), None)
            if group is None:
                groups.append(speed)
                group = len(groups) - 1
            start, end = history.times[i], history.times[i + 1]
            tail = (raw.time >= end - TAIL_FRACTION * (end - start)) & (raw.time <= end)
            rows.extend(np.flatnonzero(tail))
            segment_of.extend([group] * int(tail.sum()))
        rows = np.asarray(rows)
        if rows.size < len(groups) + degree + 2:
            raise InputError("too few steady-state samples to fit a trend; fit without detrending")
        levels = np.zeros((rows.size, len(groups)))
        levels[np.arange(rows.size), segment_of] = 1.0
        powers = np.column_stack([(sample[rows] / scale) ** j for j in range(1, degree + 1)])
        solution, *_ = np.linalg.lstsq(np.hstack([levels, powers]), friction[rows], rcond=None)
        coefficients = [float(c) for c in solution[len(groups):]]
        trend = sum(c * (sample / scale) ** (j + 1) for j, c in enumerate(coefficients))
        notes.append(f"{detrend} trend in the sample's displacement removed, fitted to the last "
                     f"{TAIL_FRACTION:.0%} of each sliding segment with a level per speed: "
                     + ", ".join(f"{c:+.4g} per mm^{j + 1}" for j, c in enumerate(coefficients))
                     + "; the fit's intervals are conditional on it (its own uncertainty is not carried)")
    record = StepRecord(raw.time, friction - trend, history, raw.source, dict(raw.metadata))
    return PreparedRecord(record, spring, sample, friction, trend, coefficients, detrend, raw, notes)


def step_windows(prepared: PreparedRecord, lead: float = 0.5) -> list[tuple[float, float]]:
    """Each step's window: from ``lead`` of the sliding segment before it to the next step, or, for a hold,
    through the hold and the reslide after it (slide-hold-slide)."""
    times, speeds = prepared.record.history.times, prepared.record.history.speeds
    windows = []
    for i in range(1, len(times) - 1):
        if speeds[i - 1] <= 0:
            continue  # a reslide: inside its hold's window
        end = times[i + 2] if speeds[i] == 0 and i + 2 < len(times) else times[i + 1]
        windows.append((times[i] - lead * (times[i] - times[i - 1]), end))
    return windows


def window_record(record: StepRecord, start: float, end: float, source: str) -> StepRecord | None:
    """The part of ``record`` from ``start`` to ``end`` (s), its clock and load history starting there; None where
    the window holds no step from sliding, or fewer than 20 samples.

    Parameters
    ----------
    record : StepRecord
        A prepared record.
    start, end : float
        The window (s of the record's time).
    source : str
        The window's name.

    Returns
    -------
    StepRecord or None
    """
    boundaries, speeds = record.history.times, record.history.speeds
    inside = (record.time >= start) & (record.time <= end)
    first = max(i for i, t in enumerate(boundaries[:-1]) if t <= start)
    inner = [t for t in boundaries[1:-1] if start < t < end]
    if not inner or speeds[first] <= 0 or inside.sum() < 20:
        return None
    origin = float(record.time[inside][0])
    times = record.time[inside] - origin
    history = LoadHistory((0.0, *(t - origin for t in inner), float(times[-1])),
                          tuple(speeds[first:first + len(inner) + 1]))
    return StepRecord(times, record.friction[inside], history, source, record.metadata)


class StepFits(list, ToXarray):
    """:func:`fit_each_step`'s list of ``{"step", "window", "fit"}`` or ``{"step", "window", "error"}``, which also
    gives xarray."""

    def to_dataset(self):
        """One row a step on dimension ``step``: its window (s), each fitted parameter with its 95 % interval (NaN
        where the step has no fit) and the reason where it has none."""
        import xarray as xr  # heavy: imported where used

        names = list(dict.fromkeys(name for entry in self if "fit" in entry for name in entry["fit"].parameters))
        units = {"critical_slip": "m", "stiffness": "1/m", "trend": "1/m", "critical_slip2": "m"}
        data = {"window_start": ("step", [e["window"][0] for e in self], {"units": "s"}),
                "window_end": ("step", [e["window"][1] for e in self], {"units": "s"}),
                "error": ("step", [e.get("error", "") for e in self], {"long_name": "why the step has no fit"})}
        for name in names:
            for suffix, pick in (("", lambda f, n: f.parameters[n]), ("_low", lambda f, n: f.intervals[n][0]),
                                 ("_high", lambda f, n: f.intervals[n][1])):
                data[name + suffix] = ("step", [pick(e["fit"], name) if "fit" in e and name in e["fit"].parameters
                                                else np.nan for e in self], {"units": units.get(name, "1")})
        return xr.Dataset(data, coords={"step": ("step", [e["step"] for e in self])}, attrs={"Conventions": "CF-1.8"})


@takes_units(windows="time")
def fit_each_step(prepared: PreparedRecord, evolution: str = "aging", windows=None, *, stiffness_free: bool = False,
                  trend: bool = False, progress=None) -> StepFits:
    """Each step's own fit (its window started at steady state at the speed before it): a list of
    ``{"step", "window", "fit"}`` or ``{"step", "window", "error"}`` where a window does not constrain the law.

    Parameters
    ----------
    prepared : PreparedRecord
        :func:`prepare_record`'s record.
    evolution : str
        aging or slip.
    windows : list, optional
        (start, end) times of each step's window (s).
    stiffness_free : bool
        Fit each window's machine stiffness too (from the prepared spring).
    trend : bool
        Fit each window's own linear trend in the load point's displacement
        (:func:`faultslip.lab.rate_state_fit.fit_velocity_steps`).
    progress : bool or callable, optional
        Report the windows fitted (True: a bar; the rest's expected time said after the first).

    Returns
    -------
    StepFits
        A list, per step: its window (s) and its fit (a, b, D_c in m) or the reason it has none; ``to_dataset()``.
    """
    record, results = prepared.record, StepFits()
    spans = list(windows or step_windows(prepared))
    step = counted(progress, "each step", len(spans), "fit", "fitting each step's window")
    for number, (start, end) in enumerate(spans, start=1):
        began = time.process_time()
        if step is not None and number > 1:
            step(number - 1)
        entry = {"step": number, "window": (float(start), float(end))}
        window = window_record(record, start, end, f"{record.source} step {number}")
        if window is None:
            entry["error"] = "the window holds no step from sliding, or fewer than 20 samples"
            results.append(entry)
            continue
        try:
            entry["fit"] = fit_velocity_steps(window, prepared.stiffness, evolution=evolution,
                                              stiffness_free=stiffness_free, trend=trend)
        except (SolverError, InputError) as exc:
            entry["error"] = str(exc)
        results.append(entry)
        if step is not None and number == 1:
            step(1, time.process_time() - began)
    if step is not None:
        step(len(spans))
    return results


@takes_units(
    machine_stiffness="stiffness", area="area", normal_load="force", rate="frequency", displacement_noise="length",
    drift="inverse_length")
def synthetic_raw_record(law, machine_stiffness: float, area: float, normal_load: float, history: LoadHistory,
                         rate: float = 10.0, friction_noise: float = 1e-4, load_noise: float = 2e-4,
                         displacement_noise: float = 2e-8, drift: float = 0.0, seed: int = 0) -> RawRecord:
    """A raw record made by the model, as a rig would write it: the slider of ``law`` on a spring
    K / (sigma_n A) sampled at ``rate`` Hz; Gaussian noise on the shear stress (``friction_noise`` times
    sigma_n), on the normal load (relative ``load_noise``) and on the load-point displacement (m); a
    linear ``drift`` in friction per metre of the load point's travel. SI in and out.

    Parameters
    ----------
    law : RateStateLaw
        The friction law.
    machine_stiffness : float
        K (N/m).
    area : float
        A (m^2).
    normal_load : float
        N.
    history : LoadHistory
        The load history.
    rate : float
        Samples per second.
    friction_noise, load_noise, displacement_noise, drift : float
        The noise and drift described above.
    seed : int
        The noise's seed.

    Returns
    -------
    RawRecord
    """
    normal = normal_load / area
    spring = machine_stiffness / (normal * area)
    times = np.arange(0.0, history.duration + 0.5 / rate, 1.0 / rate)
    times = times[times <= history.duration]
    run = simulate_rate_state(RateStateSlider(law, spring, 1.0), history, t_eval=times, rtol=1e-10)
    rng = np.random.default_rng(seed)
    load_point = np.zeros_like(times)
    for start, end, speed in zip(history.times[:-1], history.times[1:], history.speeds):
        load_point += speed * np.clip(times - start, 0.0, end - start)
    friction = run.friction + drift * load_point
    normal_stress = normal * (1.0 + load_noise * rng.standard_normal(times.size))
    shear = friction * normal + friction_noise * normal * rng.standard_normal(times.size)
    return RawRecord(times, load_point + displacement_noise * rng.standard_normal(times.size), shear, normal_stress,
                     "synthetic")


def read_rig_record(path, units: dict | None = None, area=None, columns: dict | None = None, span=None):
    """A friction record (:class:`StepRecord`: time, friction, load-point speed or displacement) or a raw rig
    record (:class:`RawRecord`: loads or stresses), whichever the file's columns are; with the file's metadata
    (:func:`faultslip.io.resources.read_table_metadata`) beside it.

    Parameters
    ----------
    path : str or path
        CSV, text, XLSX or netCDF.
    units : dict, optional
        Column -> unit, for bare column names.
    area : str, Quantity or float, optional
        The sample's area (m^2).
    columns : dict, optional
        faultslip's column name -> the file's (``{"time": "Time", "load_point_displacement": "LP_disp"}``); only
        the named columns are read.
    span : (float, float), optional
        The rows from ``span[0]`` to ``span[1]`` of the file's time (s, or text with units: "40 min"), both ends
        included.

    Returns
    -------
    StepRecord or RawRecord
    """
    path, table = _read_columns(path, "velocity-step record", only=None if columns is None else
                                set(columns.values()))
    label = f"velocity-step record {path.name}"
    metadata = read_table_metadata(path, label)
    if columns is not None:
        missing = [name for name in columns.values() if name not in table]
        if missing:
            raise InputError(f"{label} has no column {missing[0]!r} (--columns); it has "
                             f"{', '.join(sorted(table)) or 'none'}")
        if len(set(columns.values())) < len(columns):
            raise InputError(f"--columns names one of the file's columns twice: {columns}")
        table = {name: table[source] for name, source in columns.items()}
    if span is not None:
        table = _span(table, span, label)
    if is_raw_table(table):
        record = _columns_to_raw(table, path.name, units, _area(area))
    elif units or area is not None:
        raise InputError(f"{label} holds friction already: --units and --area apply to raw records (loads or "
                         "stresses)")
    else:
        record = step_record_from_columns(table, path.name)
    record.metadata = metadata
    return record


def _span(table: dict, span, label: str) -> dict:
    """The rows of ``table`` ({name: (values, unit)}) whose time lies in ``span`` (s, both ends)."""
    if "time" not in table:
        raise InputError(f"{label}: --span needs a time column")
    start, end = (to_si_scalar(v, "time", "the span", default_unit="s") for v in span)
    values, unit = table["time"]
    seconds = np.asarray(values, dtype=float) * unit_factor(unit or "s", "time", f"{label}, column time")
    if not (math.isfinite(start) and math.isfinite(end) and start < end):
        raise InputError(f"--span must run from an earlier to a later time, got {start:g} s - {end:g} s")
    inside = (seconds >= start) & (seconds <= end)
    if not inside.any():
        raise InputError(f"{label}: no row lies in the span {start:g} s - {end:g} s (its time runs from "
                         f"{np.nanmin(seconds):g} s to {np.nanmax(seconds):g} s)")
    return {name: (np.asarray(v)[inside], u) for name, (v, u) in table.items()}
