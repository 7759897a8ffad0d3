"""Fitting rate-and-state parameters to a velocity-step record, as RSFit3000 and PyRSF do.

A record gives friction against time with the load point's speed (a ``load_point_speed``
column, or ``load_point_displacement`` from which the speed is taken segment by segment) and the
machine's stiffness in friction per unit slip (k / sigma_n, e.g. "1e-3 1/um"). The model is the
quasi-static slider of :mod:`faultslip.dynamics.rate_state.slider`, started at steady state at the
first speed, V0 that speed and mu0 the friction there. ``a``, ``b``, ``D_c`` and ``mu0`` (and, for
a two-state law, ``b2`` and ``D_c2``) minimise the squared misfit in friction (scipy's
least_squares, trust-region reflective, on log D_c so that D_c stays positive). Intervals come
from the covariance s^2 (J^T J)^-1 at the optimum with Student's t quantile and, with
``bootstrap=N``, from a seeded residual bootstrap: the fitted record plus residuals drawn with
replacement, each resample refitted from the best fit; the 95 % interval is the estimate plus or
minus the t quantile times the resamples' standard deviation (on log D_c), the rule the seed-law
fit uses. The tests check the coverage of both on synthetic records with known parameters.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from faultslip.dynamics.rate_state.slider import (LoadHistory, RateStateSlider, quasi_static_friction,
                                                  simulate_rate_state)
from faultslip.errors import InputError, SolverError
from faultslip.friction.rate_state import RateStateLaw
from faultslip.io.progress import announce as _announce, counted, duration as _duration, reporter
from faultslip.io.resources import check_input_file, open_netcdf, read_numeric_table, split_header
from faultslip.units import takes_units, to_si_scalar, unit_factor
from faultslip.datasets import ToXarray

STEP_COLUMNS = {"time": "time", "friction": "dimensionless", "load_point_speed": "speed",
                "load_point_displacement": "length"}


@dataclass
class StepRecord(ToXarray):
    """A velocity-step record in SI: times, friction, and the load history it was run under."""

    time: np.ndarray
    friction: np.ndarray
    history: LoadHistory
    source: str = ""
    metadata: dict = field(default_factory=dict)  # what the file says of the experiment (id, stresses, area...)

    def to_dataset(self):
        """The record as an xarray Dataset on dimension ``time``: friction, and the load point's speed and
        displacement from its load history; the steps' times and speeds and the file's metadata in attributes."""
        import xarray as xr  # heavy: imported where used

        history = self.history
        segment = np.clip(np.searchsorted(history.times, self.time, side="right") - 1, 0, len(history.speeds) - 1)
        return xr.Dataset(
            {"friction": ("time", self.friction, {"units": "1", "long_name": "friction, shear over normal stress"}),
             "load_point_speed": ("time", np.asarray(history.speeds, dtype=float)[segment],
                                  {"units": "m/s", "long_name": "load-point speed (the load history's)"}),
             "load_point_displacement": ("time", history.displacement(self.time),
                                         {"units": "m", "long_name": "load-point displacement (the load history's)"})},
            coords={"time": ("time", self.time, {"units": "s"})},
            attrs={"source": self.source, "step_times_s": list(map(float, history.times[1:-1])),
                   "segment_speeds_m_s": list(map(float, history.speeds)), "Conventions": "CF-1.8",
                   **{f"record_{key}": str(value) for key, value in self.metadata.items()}})


def _speeds_from_displacement(time, displacement, source):
    """Piecewise-constant speeds from a load-point displacement sampled at the record's times."""
    speed = np.gradient(displacement, time)
    # a speed change is a jump of more than 1 % between neighbouring samples
    changes = np.flatnonzero(np.abs(np.diff(speed)) > 0.01 * np.maximum(np.abs(speed[1:]), np.abs(speed[:-1])))
    starts = [0] + [int(i) + 1 for i in changes if i + 1 < speed.size]
    merged = [starts[0]] + [s for prev, s in zip(starts, starts[1:]) if s - prev > 2]
    return merged, speed


def step_record(table, source: str = "<table>") -> StepRecord:
    """A velocity-step record from a pandas DataFrame or a mapping of columns, as a notebook holds one.

    Column names carry their units as in a CSV header (``"time (s)"``, ``"load_point_speed (um/s)"``),
    or a column is a pint Quantity array under its bare name; see :data:`STEP_COLUMNS`.

    Parameters
    ----------
    table : DataFrame or mapping
        The record's columns.
    source : str
        A name for messages.

    Returns
    -------
    StepRecord
    """
    if hasattr(table, "columns") and hasattr(table, "to_dict"):  # a pandas DataFrame
        items = [(str(column), table[column].to_numpy()) for column in table.columns]
    elif isinstance(table, dict):
        items = [(str(column), values) for column, values in table.items()]
    else:
        raise InputError(f"a velocity-step record is a DataFrame, a mapping of columns or a file, got "
                         f"{type(table).__name__}")
    columns = {}
    for header, values in items:
        name, unit = split_header(header)
        if hasattr(values, "units") and hasattr(values, "magnitude"):  # a pint Quantity column
            values, unit = values.magnitude, str(values.units)
        columns[name] = (np.asarray(values, dtype=float), unit)
    return step_record_from_columns(columns, source)


def step_record_from_columns(columns: dict, source: str) -> StepRecord:
    """``columns`` maps names to ``(values, unit)`` (see :data:`STEP_COLUMNS`)."""
    for name in columns:
        if name not in STEP_COLUMNS:
            raise InputError(f"velocity-step record {source}: unknown column {name!r} "
                             f"(allowed: {', '.join(STEP_COLUMNS)})")
    for required in ("time", "friction"):
        if required not in columns:
            raise InputError(f"velocity-step record {source} needs a {required} column")
    if "load_point_speed" not in columns and "load_point_displacement" not in columns:
        raise InputError(f"velocity-step record {source} needs a load_point_speed or load_point_displacement column")
    si = {}
    for name, (values, unit) in columns.items():
        kind = STEP_COLUMNS[name]
        if kind != "dimensionless" and not unit:
            raise InputError(f"velocity-step record {source}: column {name!r} needs a unit in its header, "
                             f"e.g. '{name} (s)'")
        factor = unit_factor(unit, kind, f"record {source}, column {name}") if unit else 1.0
        si[name] = np.asarray(values, dtype=float) * factor
    time, friction = si["time"], si["friction"]
    if time.size < 20:
        raise InputError(f"velocity-step record {source} has {time.size} rows; a fit needs at least 20")
    if not (np.all(np.isfinite(time)) and np.all(np.isfinite(friction))):
        raise InputError(f"velocity-step record {source} holds values that are not finite numbers")
    if np.any(np.diff(time) <= 0):
        raise InputError(f"velocity-step record {source}: times must increase")
    time = time - time[0]
    if "load_point_speed" in si:
        speed = si["load_point_speed"]
        if np.any(speed < 0) or not np.all(np.isfinite(speed)):
            raise InputError(f"velocity-step record {source}: load-point speeds must be finite and not negative")
        starts = [0] + [int(i) + 1 for i in np.flatnonzero(np.diff(speed) != 0)]
    else:
        starts, speed = _speeds_from_displacement(time, si["load_point_displacement"], source)
    times = [float(time[i]) for i in starts] + [float(time[-1])]
    speeds = [float(np.median(speed[s:e])) for s, e in zip(starts, starts[1:] + [time.size])]
    # a hold's displacement is constant: its round-off speeds (1e-20 of the sliding ones) are zero, and neighbours
    # at one speed (a hold cut by round-off into pieces) are one segment
    fastest = max(abs(v) for v in speeds)
    speeds = [0.0 if abs(v) <= 1e-9 * fastest else v for v in speeds]
    kept_times, kept_speeds = [times[0]], [speeds[0]]
    for start, value in zip(times[1:-1], speeds[1:]):
        previous = kept_speeds[-1]
        if value == previous or abs(value - previous) <= 0.01 * max(abs(value), abs(previous)):
            continue
        kept_times.append(start)
        kept_speeds.append(value)
    times, speeds = kept_times + [times[-1]], kept_speeds
    if speeds[0] <= 0:
        raise InputError(f"velocity-step record {source} must start sliding (a positive first load-point speed)")
    return StepRecord(time, friction, LoadHistory(tuple(times), tuple(speeds)), source)


def read_step_record(path) -> StepRecord:
    """A velocity-step record from CSV (units in the headers) or netCDF (units attributes).

    Parameters
    ----------
    path : str or path
        The record.

    Returns
    -------
    StepRecord
        Time (s), friction (dimensionless) and the load-point speed (m/s).
    """
    path = check_input_file(path, "velocity-step record")
    if path.suffix.lower() == ".nc":
        data = open_netcdf(path, "velocity-step record")
        columns = {name: (data[name].values, data[name].attrs.get("units")) for name in
                   list(data.data_vars) + list(data.coords) if name in STEP_COLUMNS}
    else:
        columns = read_numeric_table(path, f"velocity-step record {path.name}")
    return step_record_from_columns(columns, path.name)


@dataclass
class RateStateFit(ToXarray):
    """A fitted law, its parameters' standard errors and 95 % intervals, and the misfit."""

    law: RateStateLaw
    parameters: dict  # name -> value (SI)
    standard_errors: dict
    intervals: dict  # name -> (low, high), 95 %
    residual_rms: float
    points: int
    evaluations: int
    notes: list = field(default_factory=list)
    bootstrap: np.ndarray = field(default_factory=lambda: np.empty((0, 0)))  # (n, p) resamples, natural scale
    bootstrap_intervals: dict = field(default_factory=dict)  # name -> (low, high), 95 %, bootstrap SE
    seed: int = 0
    residuals: np.ndarray = field(default_factory=lambda: np.empty(0))  # model less record, at the record's times

    def to_dict(self) -> dict:
        units = {"mu0": "1", "a": "1", "b": "1", "critical_slip": "m", "b2": "1", "critical_slip2": "m",
                 "stiffness": "1/m", "trend": "1/m"}
        return {"law": self.law.evolution, "mu0": self.law.mu0, "reference_speed": {"value": self.law.reference_speed,
                                                                                 "units": "m/s"},
                "parameters": {name: {"value": value, "standard_error": self.standard_errors[name],
                                      "interval_95": list(self.intervals[name]), "units": units[name]}
                               for name, value in self.parameters.items()},
                "residual_rms": self.residual_rms, "points": self.points, "evaluations": self.evaluations,
                "bootstrap_intervals_95": {name: list(pair) for name, pair in self.bootstrap_intervals.items()},
                "bootstrap_samples": int(self.bootstrap.shape[0]), "seed": self.seed, "notes": self.notes}

    def to_dataset(self):
        """The fit as an xarray Dataset with CF units: each parameter with ``*_low`` and ``*_high`` (its 95 %
        covariance interval) and ``*_standard_error``; the bootstrap resamples on dimension ``draw``, if any."""
        import xarray as xr  # heavy: imported where used

        units = self.to_dict()["parameters"]
        data = {}
        for name, value in self.parameters.items():
            low, high = self.intervals[name]
            unit = units[name]["units"]
            data[name] = ((), value, {"units": unit, "long_name": name})
            data[f"{name}_low"] = ((), low, {"units": unit, "long_name": f"{name}, 95 % interval's low end"})
            data[f"{name}_high"] = ((), high, {"units": unit, "long_name": f"{name}, 95 % interval's high end"})
            data[f"{name}_standard_error"] = ((), self.standard_errors[name], {"units": unit})
        if self.bootstrap.size:
            for i, name in enumerate(self.parameters):
                data[f"{name}_bootstrap"] = ("draw", self.bootstrap[:, i], {"units": units[name]["units"],
                                                                            "long_name": f"{name}, resampled"})
        return xr.Dataset(data, attrs={"evolution": self.law.evolution, "reference_speed_m_s": self.law.reference_speed,
                                       "residual_rms": self.residual_rms, "points": self.points, "seed": self.seed,
                                       "notes": "; ".join(self.notes), "Conventions": "CF-1.8"})

    def to_record(self) -> dict:
        """The registry entry: the law, its intervals and the resamples that carry them into fault predictions."""
        law = self.law
        return {"kind": "rate_state", "a": law.a, "b": law.b, "critical_slip": law.critical_slip, "mu0": law.mu0,
                "reference_speed": law.reference_speed, "evolution": law.evolution, "b2": law.b2,
                "critical_slip2": law.critical_slip2, "names": list(self.parameters),
                "standard_errors": self.standard_errors,
                "intervals_95": {k: list(v) for k, v in self.intervals.items()},
                "bootstrap_intervals_95": {k: list(v) for k, v in self.bootstrap_intervals.items()},
                "bootstrap": self.bootstrap.tolist(), "seed": self.seed, "residual_rms": self.residual_rms,
                "points": self.points}


def _law(values, names, reference_speed, evolution):
    params = dict(zip(names, values))
    return RateStateLaw(a=params["a"], b=params["b"], critical_slip=math.exp(params["log_critical_slip"]),
                        mu0=params["mu0"],
                        reference_speed=reference_speed, evolution=evolution, b2=params.get("b2", 0.0),
                        critical_slip2=math.exp(params["log_critical_slip2"]) if "log_critical_slip2" in params else None,
                        source="fitted")


def _exp_interval(centre: float, half: float) -> tuple[float, float]:
    """(e^(centre - half), e^(centre + half)), an unbounded end where the exponential overflows."""
    return (math.exp(max(centre - half, -745.0)), math.exp(centre + half) if centre + half < 709.0 else math.inf)


def _estimates(result, names, points):
    """(parameters, standard errors, 95 % intervals, notes) of a least-squares ``result`` in natural units: the
    covariance s^2 (J^T J)^-1, Student-t intervals, the delta method and exponentiated bounds for log parameters."""
    from scipy.special import stdtrit  # heavy: imported where used

    count = len(names)
    dof = max(points - count, 1)
    s2 = float(result.fun @ result.fun) / dof
    try:
        covariance = np.linalg.inv(result.jac.T @ result.jac) * s2
    except np.linalg.LinAlgError:
        raise SolverError("the fit's Jacobian is singular: the record does not constrain every parameter "
                          "(add a velocity step, or fit one state variable)") from None
    quantile = float(stdtrit(dof, 0.975))
    parameters, errors, intervals, notes = {}, {}, {}, []
    for i, name in enumerate(names):
        value, error = float(result.x[i]), math.sqrt(max(covariance[i, i], 0.0))
        if name.startswith("log_"):
            real = name[4:]
            parameters[real] = math.exp(value)
            errors[real] = math.exp(value) * error  # delta method
            # a parameter the record does not constrain has an error of hundreds of e-folds: [0, inf), said so
            intervals[real] = _exp_interval(value, quantile * error)
            if quantile * error > math.log(1e3):
                notes.append(f"{real} is not constrained by the record: its 95 % interval spans more than a factor "
                             "of 1e6")
        else:
            parameters[name], errors[name] = value, error
            intervals[name] = (value - quantile * error, value + quantile * error)
    if any(abs(result.active_mask)):
        notes.append("a parameter ended on its bound: its interval is not reliable")
    return parameters, errors, intervals, notes


#: how far from its stated value a free stiffness may go (a factor either way)
STIFFNESS_RANGE = 100.0
#: the largest fitted trend, friction per metre of load-point displacement (10 per mm: far beyond any gouge's)
TREND_LIMIT = 1e4


class _FitWatch:
    """Progress of one least-squares fit (scipy's trf: at most 100 n Jacobian-and-residual rounds of n + 1
    evaluations, the limit passed to it): the slider integrations done against that bound, and, from the second
    evaluation's time, the most the fit can take, said before it goes on when that is 10 s or more. The first
    evaluation also loads the compiled kernel (or compiles it), once: timed on its own it made the bound tens of
    times too long."""

    clock = staticmethod(time.process_time)

    def __init__(self, progress, label: str, parameters: int):
        self.limit = 100 * parameters
        self.total = self.limit * (parameters + 1)
        self.report = reporter(progress, label, "integration")
        self.count, self.stamps = 0, []  # when the first three evaluations began

    def evaluated(self) -> None:
        self.count += 1
        if len(self.stamps) < 3:
            self.stamps.append(self.clock())
        if self.report is None:
            return
        if self.count == 3:
            each = self.stamps[2] - self.stamps[1]
            _announce(self.report, f"fitting: at most {self.total} slider integrations, at most about "
                                   f"{_duration(each * self.total)} (one takes {_duration(each)}); most fits end "
                                   "far sooner", each * self.total)
        if self.count % 10 == 0:
            self.report(min(self.count, self.total), self.total)

    def done(self) -> None:
        """The fit has ended: the bar completes, and the bootstrap's refits (which reuse the model) report on their
        own."""
        if self.report is not None:
            self.report(self.total, self.total)
        self.report = None


def fit_velocity_steps(record: StepRecord, stiffness: float, *, evolution: str = "aging", two_state: bool = False,
                       initial=None, rtol: float = 1e-10, bootstrap: int = 0, seed: int = 0,
                       stiffness_free: bool = False, trend: bool = False, progress=None) -> RateStateFit:
    """Fit a, b, D_c (and b2, D_c2) of a quasi-static slider with ``stiffness`` (friction per metre) to ``record``;
    with ``stiffness_free`` the machine's stiffness is fitted too, from ``stiffness`` (as RSFit3000 does,
    Skarbek & Savage 2019: the apparatus' effective stiffness is poorly known and biases D_c).

    ``record`` is a :class:`StepRecord`, a pandas DataFrame or a mapping of columns (:func:`step_record`);
    ``stiffness`` a float in 1/m or a string or Quantity with units ("1e-3 1/um").

    ``bootstrap`` resamples (seeded by ``seed``) add bootstrap intervals; each costs one refit. ``progress``
    (True, or a callable (done, total); :mod:`faultslip.io.progress`) shows the fit's slider integrations against
    their bound, then the refits, each with its expected time first when that is 10 s or more.

    Parameters
    ----------
    record : StepRecord, DataFrame or mapping
        Friction against time through the velocity steps.
    stiffness : float, str or Quantity
        The spring as friction per slip (1/m).
    evolution : str
        aging or slip.
    two_state : bool
        Fit a second state variable (b2, D_c2).
    initial : dict, optional
        Starting values (SI).
    rtol : float
        The integrator's relative tolerance.
    bootstrap : int
        Resamples of the intervals.
    seed : int
        Their seed.
    stiffness_free : bool
        Fit the stiffness k (1/m) too, started at ``stiffness`` and bounded within a factor of
        :data:`STIFFNESS_RANGE` of it.
    trend : bool
        Fit a linear trend too: friction mu_RS(t) + c delta_lp(t), c (1/m) per metre of the load point's
        displacement since the record's start, as RSFit3000's linear detrending but fitted with the law so that
        its uncertainty enters a, b and D_c's intervals (slip weakening over a fast segment; p655's 228.6 um/s).

    Returns
    -------
    RateStateFit
        a, b (dimensionless), D_c (m) (and k, 1/m; the trend c, 1/m), their intervals and ``report()``.
    """
    from scipy.optimize import least_squares  # heavy: imported where used
    from scipy.special import stdtrit  # heavy: imported where used

    if not isinstance(record, StepRecord):
        record = step_record(record)
    stiffness = to_si_scalar(stiffness, "inverse_length", "the stiffness", default_unit="1/m")
    if not (stiffness > 0 and math.isfinite(stiffness)):
        raise InputError(f"the stiffness must be a positive number of friction per metre, got {stiffness!r}")
    # the slider starts at steady state: friction is mu0 until the first step (its median resists noise)
    before = record.friction[record.time < record.history.times[1]]
    mu0 = float(np.median(before)) if before.size >= 5 else float(record.friction[0])
    reference_speed = float(record.history.speeds[0])
    # mu0 is fitted too (started at the steady friction before the first step): fixing it at a noisy
    # estimate would leave its error out of the other parameters' intervals
    names = ["mu0", "a", "b", "log_critical_slip"] + (["b2", "log_critical_slip2"] if two_state else [])
    guess = dict(initial or {})
    start = [mu0, guess.get("a", 0.01), guess.get("b", 0.01), math.log(guess.get("critical_slip", 10e-6))]
    lower, upper = [mu0 - 0.5, 1e-5, 0.0, math.log(1e-8)], [mu0 + 0.5, 0.5, 0.5, math.log(1.0)]
    if two_state:
        start += [guess.get("b2", 0.005), math.log(guess.get("critical_slip2", 100e-6))]
        lower += [0.0, math.log(1e-8)]
        upper += [0.5, math.log(1.0)]
    if stiffness_free:
        names.append("log_stiffness")
        start.append(math.log(guess.get("stiffness", stiffness)))
        lower.append(math.log(stiffness / STIFFNESS_RANGE))
        upper.append(math.log(stiffness * STIFFNESS_RANGE))
        start[-1] = min(max(start[-1], lower[-1]), upper[-1])
    if trend:
        names.append("trend")
        start.append(float(guess.get("trend", 0.0)))
        lower.append(-TREND_LIMIT)
        upper.append(TREND_LIMIT)
    load_point = record.history.displacement(record.time) if trend else None
    evaluations = {"n": 0}

    watch = _FitWatch(progress, "fit", len(names))

    def model(values, tolerance):
        evaluations["n"] += 1
        watch.evaluated()
        try:
            law = _law(values, names, reference_speed, evolution)
            spring = math.exp(values[names.index("log_stiffness")]) if stiffness_free else stiffness
            # the compiled kernel where it serves (one state, numba), LSODA otherwise: ~10x fewer seconds a fit
            friction = quasi_static_friction(law, spring, record.history, record.time, tolerance)
        except (SolverError, InputError):
            return None
        return friction + values[names.index("trend")] * load_point if trend else friction

    def residuals(values, observed=record.friction, tolerance=rtol):
        predicted = model(values, tolerance)
        if predicted is None:
            return np.full(record.time.size, 1.0)  # a trial the slider cannot follow: a large misfit, not a crash
        return predicted - observed

    # finite differences of 1e-4 relative: far above the solver's error (rtol), so the Jacobian,
    # and with it the covariance, is not polluted by integration noise
    result = least_squares(residuals, start, bounds=(lower, upper), method="trf", x_scale="jac",
                           xtol=1e-10, ftol=1e-12, gtol=1e-12, diff_step=1e-4, max_nfev=watch.limit)
    watch.done()
    if not result.success:
        raise SolverError(f"the rate-and-state fit did not converge ({result.message}); give a closer initial guess")
    points, count = record.time.size, len(names)
    quantile = float(stdtrit(max(points - count, 1), 0.975))
    law = _law(result.x, names, reference_speed, evolution)
    parameters, errors, intervals, notes = _estimates(result, names, points)
    notes.extend(correlation_notes(result.fun))
    samples, boot_intervals = np.empty((0, count)), {}
    if bootstrap:
        fitted = record.friction + result.fun
        rng = np.random.default_rng(seed)
        # residual bootstrap: the load history is the experiment's fixed design
        centred = result.fun - result.fun.mean()
        rows, failed = [], 0
        # a refit starts at the best fit and takes fewer evaluations than the fit: the rest timed on the first
        step = counted(progress, "bootstrap", bootstrap, "refit", "bootstrap refits")
        refits_started = time.process_time()
        for done in range(bootstrap):
            if step is not None:
                step(done, time.process_time() - refits_started if done == 1 else None)
            observed = fitted + rng.choice(centred, size=points, replace=True)
            # each resample starts at the best fit; rtol 1e-9 stays far below any noise a lab records
            refit = least_squares(residuals, result.x, bounds=(lower, upper), method="trf", x_scale="jac",
                                  xtol=1e-8, ftol=1e-10, gtol=1e-10, diff_step=1e-4,
                                  kwargs={"observed": observed, "tolerance": 1e-9})
            if refit.success:
                rows.append(refit.x)
            else:
                failed += 1
        if step is not None:
            step(bootstrap)
        if len(rows) < max(2, (bootstrap + 1) // 2):
            raise SolverError(f"only {len(rows)} of {bootstrap} bootstrap refits converged; the record does not "
                              "constrain the law well enough for bootstrap intervals (fit without --bootstrap)")
        if failed:
            notes.append(f"{failed} of {bootstrap} bootstrap refits did not converge and were left out")
        raw = np.asarray(rows)
        samples = np.column_stack([np.exp(raw[:, i]) if n.startswith("log_") else raw[:, i]
                                   for i, n in enumerate(names)])
        for i, name in enumerate(names):
            spread = float(np.std(raw[:, i], ddof=1))
            value = float(result.x[i])
            if name.startswith("log_"):
                boot_intervals[name[4:]] = _exp_interval(value, quantile * spread)
            else:
                boot_intervals[name] = (value - quantile * spread, value + quantile * spread)
    return RateStateFit(law=law, parameters=parameters, standard_errors=errors, intervals=intervals,
                        residual_rms=math.sqrt(float(result.fun @ result.fun) / points), points=points,
                        evaluations=evaluations["n"], notes=notes, bootstrap=samples,
                        bootstrap_intervals=boot_intervals, seed=seed, residuals=np.asarray(result.fun))


#: residuals correlated beyond this lag-one autocorrelation get a note: the intervals assume independent noise
CORRELATED_RESIDUALS = 0.3


def lag_one_autocorrelation(residuals) -> float:
    """rho = sum r_i r_(i+1) / sum r_i^2 of the centred residuals, clipped to [0, 0.999]: the AR(1) coefficient
    behind the effective number of points n (1 - rho) / (1 + rho).

    Parameters
    ----------
    residuals : array_like
        A fit's residuals in time order.

    Returns
    -------
    float
        rho, dimensionless.
    """
    r = np.asarray(residuals, dtype=float)
    r = r - r.mean()
    total = float(r @ r)
    if r.size < 3 or not total > 0:
        return 0.0
    return float(min(max(float(r[:-1] @ r[1:]) / total, 0.0), 0.999))


def correlation_notes(residuals) -> list:
    """A note where a fit's residuals are correlated (lag-one autocorrelation rho > :data:`CORRELATED_RESIDUALS`):
    covariance, residual-bootstrap and posterior intervals treat every sample as independent, so for AR(1) noise
    they are about sqrt((1 + rho) / (1 - rho)) too narrow (the variance of a mean of correlated points)."""
    rho = lag_one_autocorrelation(residuals)
    if rho <= CORRELATED_RESIDUALS:
        return []
    factor = math.sqrt((1 + rho) / (1 - rho))
    return [f"the residuals are correlated (lag-one autocorrelation {rho:.2f}): the intervals assume independent "
            f"noise and are about {factor:.2g} times too narrow; thin the record or read them so"]


def synthetic_step_record(law: RateStateLaw, stiffness: float, history: LoadHistory, samples: int,
                          noise: float = 0.0, seed: int = 0) -> StepRecord:
    """A record made by the model itself, with Gaussian noise of standard deviation ``noise`` in friction."""
    times = np.linspace(0.0, history.duration, samples)
    run = simulate_rate_state(RateStateSlider(law, stiffness, 1.0), history, t_eval=times, rtol=1e-11)
    rng = np.random.default_rng(seed)
    return StepRecord(times, run.friction + noise * rng.standard_normal(samples), history, "synthetic")


@dataclass
class JointFit(ToXarray):
    """A law fitted to several records at once: shared a, b, D_c (and b2, D_c2), each record's own mu0 (and k)."""

    evolution: str
    shared: dict  # name -> value (SI)
    per_record: list  # one dict a record: mu0 (and stiffness), at the record's first speed
    standard_errors: dict  # by the fit's names: a, b, critical_slip, mu0_1, stiffness_1, ...
    intervals: dict
    residual_rms: list  # each record's
    points: list
    reference_speeds: list
    notes: list = field(default_factory=list)

    def law(self, record: int = 0) -> RateStateLaw:
        """The law as it acts on record ``record`` (its mu0 and reference speed)."""
        values = self.shared
        return RateStateLaw(a=values["a"], b=values["b"], critical_slip=values["critical_slip"],
                            mu0=self.per_record[record]["mu0"], reference_speed=self.reference_speeds[record],
                            evolution=self.evolution, b2=values.get("b2", 0.0),
                            critical_slip2=values.get("critical_slip2"), source="fitted jointly")

    def to_dataset(self):
        """The fit as an xarray Dataset with CF units: the shared parameters (with ``*_low`` and ``*_high``, the 95 %
        interval) and, on dimension ``record``, each record's mu0 (and stiffness), misfit, points and first speed."""
        import xarray as xr  # heavy: imported where used

        units = {"a": "1", "b": "1", "critical_slip": "m", "b2": "1", "critical_slip2": "m"}
        data = {}
        for name, value in self.shared.items():
            low, high = self.intervals[name]
            data[name] = ((), value, {"units": units[name], "long_name": f"{name} (shared by every record)"})
            data[f"{name}_low"] = ((), low, {"units": units[name], "long_name": f"{name}, 95 % interval's low end"})
            data[f"{name}_high"] = ((), high, {"units": units[name], "long_name": f"{name}, 95 % interval's high end"})
        for key in self.per_record[0]:
            data[key] = ("record", np.array([row[key] for row in self.per_record]),
                         {"units": "1/m" if key in ("stiffness", "trend") else "1", "long_name": f"each record's {key}"})
        data["residual_rms"] = ("record", np.array(self.residual_rms), {"units": "1", "long_name": "rms misfit"})
        data["points"] = ("record", np.array(self.points), {"units": "1", "long_name": "samples"})
        data["reference_speed"] = ("record", np.array(self.reference_speeds),
                                   {"units": "m/s", "long_name": "the record's first load-point speed (mu0's)"})
        return xr.Dataset(data, coords={"record": ("record", np.arange(1, len(self.points) + 1))},
                          attrs={"evolution": self.evolution, "Conventions": "CF-1.8"})

    def to_dict(self) -> dict:
        units = {"a": "1", "b": "1", "critical_slip": "m", "b2": "1", "critical_slip2": "m"}
        return {"law": self.evolution, "shared": {name: {"value": value, "standard_error": self.standard_errors[name],
                                                         "interval_95": list(self.intervals[name]),
                                                         "units": units[name]}
                                                  for name, value in self.shared.items()},
                "records": [{**{name: {"value": value, "interval_95": list(self.intervals[f"{name}_{i + 1}"]),
                                       "units": "1/m" if name in ("stiffness", "trend") else "1"}
                                for name, value in row.items()},
                             "residual_rms": rms, "points": n, "reference_speed": {"value": v0, "units": "m/s"}}
                            for i, (row, rms, n, v0) in enumerate(zip(self.per_record, self.residual_rms, self.points,
                                                                      self.reference_speeds))],
                "notes": self.notes}


@takes_units(stiffness="inverse_length")
def fit_joint(records, stiffness, *, evolution: str = "aging", two_state: bool = False,
              stiffness_free: bool = False, trend: bool = False, rtol: float = 1e-10, progress=None) -> JointFit:
    """Fit one law to several velocity-step records (several steps of one run, or several experiments): a, b and
    D_c (and b2, D_c2) shared, each record's steady friction mu0 at its own first speed (and, with
    ``stiffness_free``, its own stiffness; with ``trend``, its own linear trend in the load point's displacement) a
    nuisance of its own. The residuals of all records are minimised
    together; the covariance and intervals are :func:`fit_velocity_steps`'s.

    Parameters
    ----------
    records : sequence of StepRecord (or tables)
        Two or more records.
    stiffness : float or sequence of float
        The stiffness (1/m) of every record, or of each.
    evolution : str
        aging or slip.
    two_state : bool
        A second state variable, shared.
    stiffness_free : bool
        Fit each record's stiffness, started at its stated one.
    trend : bool
        Fit each record's linear trend (friction per metre of its load point's displacement).
    rtol : float
        The integrator's tolerance.

    Returns
    -------
    JointFit
        The shared parameters, each record's nuisances, their intervals and each record's misfit.
    """
    from scipy.optimize import least_squares  # heavy: imported where used

    records = [record if isinstance(record, StepRecord) else step_record(record) for record in records]
    if len(records) < 2:
        raise InputError("a joint fit needs two or more records")
    springs = list(stiffness) if isinstance(stiffness, (list, tuple, np.ndarray)) else [stiffness] * len(records)
    if len(springs) != len(records):
        raise InputError(f"give one stiffness, or one for each of the {len(records)} records; got {len(springs)}")
    springs = [to_si_scalar(k, "inverse_length", "the stiffness", default_unit="1/m") for k in springs]
    if not all(k > 0 and math.isfinite(k) for k in springs):
        raise InputError(f"every stiffness must be a positive number of friction per metre, got {springs}")
    shared = ["a", "b", "log_critical_slip"] + (["b2", "log_critical_slip2"] if two_state else [])
    start = [0.01, 0.01, math.log(10e-6)] + ([0.005, math.log(100e-6)] if two_state else [])
    lower = [1e-5, 0.0, math.log(1e-8)] + ([0.0, math.log(1e-8)] if two_state else [])
    upper = [0.5, 0.5, math.log(1.0)] + ([0.5, math.log(1.0)] if two_state else [])
    names = list(shared)
    for i, (record, spring) in enumerate(zip(records, springs), start=1):
        before = record.friction[record.time < record.history.times[1]]
        mu0 = float(np.median(before)) if before.size >= 5 else float(record.friction[0])
        names.append(f"mu0_{i}")
        start.append(mu0)
        lower.append(mu0 - 0.5)
        upper.append(mu0 + 0.5)
        if stiffness_free:
            names.append(f"log_stiffness_{i}")
            start.append(math.log(spring))
            lower.append(math.log(spring / STIFFNESS_RANGE))
            upper.append(math.log(spring * STIFFNESS_RANGE))
        if trend:
            names.append(f"trend_{i}")
            start.append(0.0)
            lower.append(-TREND_LIMIT)
            upper.append(TREND_LIMIT)
    position = {name: i for i, name in enumerate(names)}
    load_points = [record.history.displacement(record.time) if trend else None for record in records]
    speeds = [float(record.history.speeds[0]) for record in records]

    def each(values, i):
        """(law, spring) of record i (0-based) at ``values``."""
        params = {name: values[position[name]] for name in shared}
        law = _law([*params.values(), values[position[f"mu0_{i + 1}"]]], [*params, "mu0"], speeds[i], evolution)
        spring = math.exp(values[position[f"log_stiffness_{i + 1}"]]) if stiffness_free else springs[i]
        return law, spring

    watch = _FitWatch(progress, "joint fit", len(names))

    def residuals(values):
        watch.evaluated()
        parts = []
        for i, record in enumerate(records):
            try:
                law, spring = each(values, i)
                friction = quasi_static_friction(law, spring, record.history, record.time, rtol)
                if trend:
                    friction = friction + values[position[f"trend_{i + 1}"]] * load_points[i]
                parts.append(friction - record.friction)
            except (SolverError, InputError):
                parts.append(np.full(record.time.size, 1.0))  # a trial a slider cannot follow: a large misfit
        return np.concatenate(parts)

    result = least_squares(residuals, start, bounds=(lower, upper), method="trf", x_scale="jac", xtol=1e-10,
                           ftol=1e-12, gtol=1e-12, diff_step=1e-4, max_nfev=watch.limit)
    watch.done()
    if not result.success:
        raise SolverError(f"the joint rate-and-state fit did not converge ({result.message}); give closer records or "
                          "fit them one at a time first")
    points = [record.time.size for record in records]
    parameters, errors, intervals, notes = _estimates(result, names, sum(points))
    notes.extend(correlation_notes(result.fun))
    common = [name.removeprefix("log_") for name in shared]
    per_record = []
    for i in range(len(records)):
        row = {"mu0": parameters[f"mu0_{i + 1}"]}
        if stiffness_free:
            row["stiffness"] = parameters[f"stiffness_{i + 1}"]
        if trend:
            row["trend"] = parameters[f"trend_{i + 1}"]
        per_record.append(row)
    bounds = np.cumsum([0, *points])
    rms = [math.sqrt(float(np.mean(result.fun[a:b] ** 2))) for a, b in zip(bounds[:-1], bounds[1:])]
    return JointFit(evolution, {name: parameters[name] for name in common}, per_record, errors, intervals, rms, points,
                    speeds, notes)
