"""A rate-and-state fit of one laboratory record, start to end: what ``faultslip fit --law rate-state`` runs.

:func:`fit_record` reads the record (friction, or a rig's raw loads), prepares a raw one (the fit's spring
from the machine stiffness, the steps and holds, a stated trend removed), fits the whole record with its
covariance and bootstrap intervals, fits each step on request, and samples the posterior on request. It
returns a :class:`RecordFit`: the report and everything a figure or the fit registry needs. The command
line only parses options, draws and prints (issue 40: no workflow in ``cli/``).
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np

from faultslip import ranges
from faultslip.dynamics.rate_state.slider import RateStateSlider, simulate_rate_state
from faultslip.contract.result import ReportedValues, Result, with_draws
from faultslip.errors import InputError
from faultslip.friction.fitting import fit_rate_law
from faultslip.io.report import Report, display_unit, significant
from faultslip.io.resources import resolve_path
from faultslip.lab.posterior import sample_posterior
from faultslip.lab.raw_records import RawRecord, fit_each_step, read_rig_record, prepare_record
from faultslip.lab.healing import healing
from faultslip.lab.law_selection import select_law
from faultslip.lab.rate_state_fit import fit_joint, fit_velocity_steps
from faultslip.units import takes_units, to_si

#: The rate-and-state parameters in words, for reports.
PARAMETER_WORDS = {"mu0": "mu0, steady friction at V0", "a": "a, direct effect", "b": "b, evolution effect",
                   "critical_slip": "D_c, critical slip distance", "b2": "b2, second evolution effect",
                   "critical_slip2": "D_c2, second critical slip distance",
                   "stiffness": "k, machine stiffness (fitted, friction per slip)",
                   "trend": "c, fitted trend (friction per metre of load-point displacement)"}
#: Each parameter's SI unit (None: dimensionless).
PARAMETER_UNITS = {"mu0": None, "a": None, "b": None, "critical_slip": "m", "b2": None, "critical_slip2": "m",
                   "stiffness": "1/m", "trend": "1/m"}
#: How the intervals were made, said under every fit.
INTERVALS_NOTE = ("covariance intervals: s^2 (J^T J)^-1 at the optimum; bootstrap intervals: residual bootstrap, "
                  "each resample refitted; posterior: emcee, converged before it is reported; all coverage-tested on "
                  "synthetic records (tests/capabilities/lab/test_rate_state_fit.py, tests/capabilities/lab/test_raw_records.py)")


@dataclass
class RecordFit(ReportedValues):
    """What :func:`fit_record` found: the report, the (prepared) record, the fit's spring (friction per metre),
    the least-squares fit and, on request, the posterior. ``fit["critical_slip"]`` is a reported value with its
    units, as a run's Result gives it."""

    report: Report
    record: object  # StepRecord
    prepared: object | None  # PreparedRecord of a raw record, else None
    stiffness: float  # 1/m
    fit: object  # RateStateFit
    posterior: object | None = None  # Posterior
    selection: object | None = None  # LawSelection

    def to_xarray(self):
        """The fit as a CF Dataset, the schema every Result writes (each reported number a variable with its
        ``units``, each 95 % range on ``quantile``), with the posterior's samples where there is one."""
        dataset = self.as_result().to_xarray()
        if self.posterior is not None:
            dataset = with_draws(dataset, "posterior", self.posterior.names, self.posterior.samples)
        return dataset

    def as_result(self) -> Result:
        """The fit's report as a :class:`Result`."""
        return Result("rate_state_fit", self.report)

    def fitted_friction(self, seed: int = 0) -> dict:
        """The fitted law's friction through the record's own load history, for a figure of record and fit.

        Parameters
        ----------
        seed : int
            The seed of the posterior predictive band's draws.

        Returns
        -------
        dict
            ``law`` (the posterior's mean law where there is a posterior, else the fit's), ``friction`` (the law's
            friction at the record's times, dimensionless, rtol 1e-9), ``band`` (the posterior predictive band, or
            None) and ``raw_friction`` (a raw record's friction before its trend was removed, or None).
        """
        law = self.posterior.law() if self.posterior is not None else self.fit.law
        friction = simulate_rate_state(RateStateSlider(law, self.stiffness, 1.0), self.record.history,
                                       t_eval=self.record.time, rtol=1e-9).friction
        trend = (self.posterior.median() if self.posterior is not None else self.fit.parameters).get("trend")
        if trend is not None:  # a fitted trend is part of the model the record is compared with
            friction = friction + trend * self.record.history.displacement(self.record.time)
        band = self.posterior.predictive(self.record, seed=seed) if self.posterior is not None else None
        return {"law": law, "friction": friction, "band": band,
                "raw_friction": None if self.prepared is None else self.prepared.raw_friction}

    @property
    def saved(self):
        """What the registry keeps: the posterior's draws where there is one, else the fit and its resamples."""
        return self.posterior if self.posterior is not None else self.fit


def _shown(value, low, high, units):
    """A figure in the unit and to the digits its interval supports (faultslip.io.report)."""
    unit, factor = display_unit([low, high], units or "1")
    return f"{significant(value / factor, (high - low) / factor / 10)}{(' ' + unit) if unit else ''}"


@takes_units(steps="time", windows="time")
def fit_record(data, stiffness, *, area=None, units: dict | None = None, detrend: str = "none", steps=None,
               min_change: float | None = None, evolution: str = "aging", two_state: bool = False,
               bootstrap: int = 50, seed: int = 0, windows=None, each_step: bool = False, posterior: bool = False,
               priors: dict | None = None, samples=None, walkers=None, max_steps=None, workers: int = 1,
               title: str | None = None, stiffness_free: bool = False, select: bool = False,
               joint=(), columns: dict | None = None, span=None, progress=None) -> RecordFit:
    """Fit a rate-and-state law to a velocity-step record.

    Parameters
    ----------
    data : str or path
        The record: friction (time, friction, load-point speed or displacement) or a rig's raw loads.
    stiffness : str or float
        The machine stiffness: friction per slip (1/m, or "1e-2 1/um"), stress per slip ("50 MPa/mm") or force
        per slip ("200 kN/mm", with ``area``). A friction record takes it as friction per slip.
    area : str or float, optional
        The sample's contact area (m^2, or text with units): turns loads into stresses.
    units : dict, optional
        Units of bare column names of a raw record, by column.
    detrend : {"none", "linear", "quadratic", "fitted"}
        A stated trend of friction with the sample's slip, removed with a level per speed (raw records), or
        ``fitted``: a linear trend in the load point's displacement fitted with the law (each fit its own; its
        uncertainty enters the others' intervals).
    steps : list of float, optional
        The steps' times (s), instead of detecting them (raw records).
    min_change : float, optional
        The smallest relative speed change detected as a step (raw records).
    evolution : {"aging", "slip"}
        The state evolution law.
    two_state : bool
        Fit a second state variable (b2, D_c2).
    bootstrap : int
        Residual-bootstrap resamples, each refitted (0: none).
    seed : int
        The bootstrap's and the posterior's random seed.
    windows : list of (float, float), optional
        Step windows (s) for each step's own fit (raw records).
    each_step : bool
        Fit each detected step on its own as well.
    posterior : bool
        Sample the posterior of the parameters (emcee), reported only once converged.
    priors : dict, optional
        Priors by parameter (:func:`faultslip.lab.posterior.parse_prior`).
    samples, walkers, max_steps, workers
        The sampler's settings (its defaults where None).
    title : str, optional
        The report's title.
    stiffness_free : bool
        Fit the machine stiffness too, from ``stiffness`` (its prior's median in a posterior).
    select : bool
        Also fit the aging, slip and two-state aging laws and say which the record supports, by BIC
        (:func:`faultslip.lab.law_selection.select_law`).
    joint : sequence of str or path
        Further records of the same rock, prepared as ``data`` is: one law fitted to all of them, a, b and D_c
        shared, each record's mu0 (and k) its own (:func:`faultslip.lab.rate_state_fit.fit_joint`).
    columns : dict, optional
        The record's columns by faultslip's names, ``{"time": "Time", "load_point_displacement": "LP_disp",
        "shear_stress": "Shear_stress", "normal_stress": "Nor_stress"}``: a file whose columns have its own
        names (an xlook reduction's netCDF).
    span : (float, float), optional
        Fit only the rows from ``span[0]`` to ``span[1]`` seconds of the file's own time.
    progress : bool or callable, optional
        Show the bootstrap's refits and the posterior's steps (True: a bar on stderr, its expected time said
        first; a callable receives (done, total)).

    Returns
    -------
    RecordFit
        The report, the record, the fit's spring k (1/m), the fit and the posterior.
    """
    if ranges.check_count(bootstrap, "--bootstrap", 0, 10_000) == 1:  # one resample has no spread
        raise InputError(f"--bootstrap must be 0 or lie between 2 and 10000 resamples, got {bootstrap}")
    seed = ranges.check_count(seed, "--seed")
    if priors and not posterior:
        raise InputError("--prior sets the posterior's priors: give --posterior too")
    if detrend not in ("none", "linear", "quadratic", "fitted"):
        raise InputError(f"--detrend must be none, linear, quadratic or fitted, got {detrend!r}")
    trend = detrend == "fitted"
    loaded = read_rig_record(data, units=units, area=area, columns=columns, span=span)
    report = Report(title or f"faultslip fit --law rate-state: {data}")
    prepared = None
    if isinstance(loaded, RawRecord):
        prepared = prepare_record(loaded, stiffness, area=area, detrend="none" if trend else detrend, step_times=steps,
                                  **({} if min_change is None else {"min_change": min_change}))
        record, spring = prepared.record, prepared.stiffness
        _prepared_section(report, record, prepared, detrend)
    else:
        if steps is not None or detrend not in ("none", "fitted"):
            raise InputError("--steps and --detrend linear or quadratic prepare raw records; this record holds "
                             "friction already")
        if windows:
            raise InputError("--windows sets raw records' step windows; this record holds friction already")
        record = loaded
        spring = stiffness if isinstance(stiffness, (int, float)) else to_si(stiffness, "inverse_length",
                                                                               "--stiffness")
        if not spring > 0:
            raise InputError(f"--stiffness must be positive, got {stiffness}")
    fit = fit_velocity_steps(record, spring, evolution=evolution, two_state=two_state, bootstrap=bootstrap,
                             seed=seed, stiffness_free=stiffness_free, trend=trend, progress=progress)
    if record.metadata:  # what the file says of its experiment travels into the report, its JSON and a bundle
        report.add("record_metadata", dict(record.metadata), label="the record's metadata, as its file gives it")
    _fit_section(report, fit, seed)
    if 0.0 in record.history.speeds[1:-1]:  # a hold between two slides: its healing
        try:
            _healing_section(report, healing(record))
        except InputError as exc:
            report.note(f"slide-hold-slide: {exc}")
    if joint:
        others = [_prepared_record(path, stiffness, area, units, "none" if trend else detrend, min_change, columns,
                                   span) for path in joint]
        together = fit_joint([record, *(other for other, _ in others)], [spring, *(k for _, k in others)],
                             evolution=evolution, two_state=two_state, stiffness_free=stiffness_free, trend=trend,
                             progress=progress)
        _joint_section(report, together, [str(data), *map(str, joint)])
    selection = None
    if select:
        selection = select_law(record, spring, stiffness_free=stiffness_free, trend=trend, progress=progress)
        _selection_section(report, selection)
    if windows:
        for start, end in windows:
            if not 0 <= start < end <= record.time[-1]:
                raise InputError(f"window {start:g} s - {end:g} s must lie inside the record (0 to "
                                 f"{record.time[-1]:g} s) and end after it starts")
    if prepared is not None and (each_step or windows):
        _each_step_section(report, prepared, evolution, windows, stiffness_free, trend, progress)
    sampled = None
    if posterior:
        settings = {key: value for key, value in (("samples", samples), ("walkers", walkers),
                                                  ("max_steps", max_steps)) if value is not None}
        sampled = sample_posterior(record, spring, evolution=evolution, two_state=two_state, priors=priors or {},
                                   seed=seed, workers=workers or 1, initial_fit=fit, stiffness_free=stiffness_free,
                                   trend=trend, progress=progress, **settings)
        _posterior_section(report, sampled)
    if stiffness_free:  # the record's spring is the fitted one from here on (figures, predictions)
        spring = sampled.median()["stiffness"] if sampled is not None else fit.parameters["stiffness"]
    return RecordFit(report, record, prepared, spring, fit, sampled, selection)


def _prepared_section(report: Report, record, prepared, detrend: str) -> None:
    report.section("The raw record, prepared")
    report.add("stiffness", prepared.stiffness, "1/m", label="the fit's spring k (friction per slip)")
    for i, (t, before, after) in enumerate(zip(record.history.times[1:-1], record.history.speeds[:-1],
                                               record.history.speeds[1:]), start=1):
        report.add(f"step_{i}", {"time": {"value": t, "units": "s"}, "speed_before": {"value": before, "units": "m/s"},
                                 "speed_after": {"value": after, "units": "m/s"}},
                   label=f"step {i} at {t:.4g} s: {before * 1e6:.4g} -> {after * 1e6:.4g} um/s"
                   + (" (hold)" if after == 0 else ""))
    report.add("detrend", detrend, label="trend removed (stated)")
    if prepared.trend_coefficients:
        report.add("trend_per_mm", prepared.trend_coefficients, "1",
                   label="trend coefficients, friction per mm^j of the sample's slip")
    for note in prepared.notes:
        report.note(note)


def _fit_section(report: Report, fit, seed: int) -> None:
    report.section("Least-squares fit over the whole record")
    for name, value in fit.parameters.items():
        low, high = fit.intervals[name]
        unit = PARAMETER_UNITS[name]
        report.add(name, value, unit, label=PARAMETER_WORDS.get(name, name), error=(high - low) / 2)
        report.add(f"{name}_95", [low, high], unit or "1", label="  95 % interval (covariance)")
        if name in fit.bootstrap_intervals:
            low, high = fit.bootstrap_intervals[name]
            report.add(f"{name}_95_bootstrap", [low, high], unit or "1", label="  95 % interval (bootstrap)")
    report.add("reference_speed", fit.law.reference_speed, "m/s", label="V0 (the first load-point speed)")
    report.add("evolution", fit.law.evolution).add("residual_rms", fit.residual_rms, label="rms misfit in friction")
    report.add("points", fit.points).add("model_evaluations", fit.evaluations)
    resamples = int(fit.bootstrap.shape[0])
    report.add("bootstrap_samples", resamples, label=f"bootstrap resamples (seed {seed})" if resamples else
               "bootstrap resamples (none asked for)")
    for note in fit.notes:
        report.note(note)


def _prepared_record(path, stiffness, area, units, detrend, min_change, columns, span):
    """A further record for a joint fit, made ready as the first one was: (StepRecord, spring in 1/m)."""
    loaded = read_rig_record(path, units=units, area=area, columns=columns, span=span)
    if isinstance(loaded, RawRecord):
        prepared = prepare_record(loaded, stiffness, area=area, detrend=detrend,
                                  **({} if min_change is None else {"min_change": min_change}))
        return prepared.record, prepared.stiffness
    spring = stiffness if isinstance(stiffness, (int, float)) else to_si(stiffness, "inverse_length", "--stiffness")
    return loaded, spring


def _joint_section(report: Report, joint, sources) -> None:
    report.section(f"Joint fit of {len(sources)} records (a, b, D_c shared)")
    for name, value in joint.shared.items():
        low, high = joint.intervals[name]
        unit = PARAMETER_UNITS[name]
        report.add(f"joint_{name}", value, unit, label=f"{PARAMETER_WORDS.get(name, name)} (all records)",
                   error=(high - low) / 2)
        report.add(f"joint_{name}_95", [low, high], unit or "1", label="  95 % interval (covariance)")
    for i, (source, row, rms) in enumerate(zip(sources, joint.per_record, joint.residual_rms), start=1):
        report.add(f"joint_record_{i}", {"source": source, **{key: {"value": value, "units": "1/m" if key == "stiffness"
                                                                   else "1"} for key, value in row.items()},
                                         "residual_rms": rms},
                   label=f"record {i} ({source}): mu0 {row['mu0']:.5g}"
                         + (f", k {row['stiffness']:.4g} 1/m" if "stiffness" in row else "") + f", rms {rms:.3g}")
    for note in joint.notes:
        report.note(note)


def _healing_section(report: Report, result) -> None:
    report.section("Slide-hold-slide: healing against hold time")
    for number, (start, hold, heal, relax) in enumerate(zip(result.hold_start, result.hold_time, result.healing,
                                                             result.relaxation), start=1):
        report.add(f"hold_{number}", {"start": {"value": float(start), "units": "s"},
                                      "hold_time": {"value": float(hold), "units": "s"},
                                      "healing": float(heal), "relaxation": float(relax)},
                   label=f"hold {number} at {start:.4g} s for {hold:.4g} s: healing {heal:.4g}, relaxation {relax:.4g}")
    if np.isfinite(result.rate):
        low, high = result.rate_interval
        report.add("healing_rate", result.rate, "1", label="healing rate, per decade of hold time",
                   error=(high - low) / 2 if np.isfinite(low) else None)
        if np.isfinite(low):
            report.add("healing_rate_95", [low, high], "1", label="  95 % interval (least squares, Student t)")
    for note in result.notes:
        report.note(note)


def _selection_section(report: Report, selection) -> None:
    report.section("Which law the record supports (BIC)")
    for row in selection.rows:
        if "bic" in row:
            report.add(f"law_{row['law']}", {"parameters": row["parameters"], "bic": row["bic"], "delta_bic": row["delta"],
                                             "weight": row["weight"]},
                       label=f"{row['law']}: {row['parameters']} parameters, BIC {row['bic']:.6g}, Delta "
                             f"{row['delta']:.3g}, Schwarz weight {row['weight']:.3g}")
        else:
            report.add(f"law_{row['law']}", {"error": row["error"]}, label=f"{row['law']}: not fitted ({row['error']})")
    report.add("law_selected", selection.chosen, label="the law the record supports")
    report.add("law_selection_effective_points", selection.effective_points,
               label=f"points the criterion counts (of {selection.points}; residuals' lag-one autocorrelation "
                     f"{selection.autocorrelation:.3g})")
    report.note(selection.verdict())


def _each_step_section(report: Report, prepared, evolution: str, windows, stiffness_free: bool, trend: bool,
                       progress=None) -> None:
    report.section("Each step's own fit")
    for entry in fit_each_step(prepared, evolution=evolution, windows=windows, stiffness_free=stiffness_free,
                               trend=trend, progress=progress):
        start, end = entry["window"]
        if "fit" in entry:
            p = entry["fit"].parameters
            report.add(f"step_fit_{entry['step']}", {name: {"value": value, "units": PARAMETER_UNITS[name] or "1"}
                                                     for name, value in p.items()},
                       label=f"step {entry['step']} ({start:.4g}-{end:.4g} s): a {p['a']:.4g}, b {p['b']:.4g}, "
                             f"D_c {p['critical_slip'] * 1e6:.4g} um")
        else:
            report.add(f"step_fit_{entry['step']}", {"error": entry["error"]},
                       label=f"step {entry['step']} ({start:.4g}-{end:.4g} s): {entry['error']}")


def _posterior_section(report: Report, posterior) -> None:
    report.section("Posterior (emcee)")
    summary = posterior.to_dict()
    for name, row in summary["parameters"].items():
        low, high = row["credible_95"]
        unit = PARAMETER_UNITS[name]
        report.add(f"{name}_posterior", {"median": row["median"], "credible_95": [low, high],
                                         "units": row["units"], "prior": row["prior"],
                                         "r_hat": row["r_hat"], "effective_sample_size":
                                             row["effective_sample_size"],
                                         "autocorrelation_time": row["autocorrelation_time"]},
                   label=f"{PARAMETER_WORDS.get(name, name)}: median {_shown(row['median'], low, high, unit)}"
                         f", 95 % {_shown(low, low, high, unit)} to {_shown(high, low, high, unit)}; "
                         f"R-hat {row['r_hat']:.3f}, {row['effective_sample_size']:.0f} effective samples; "
                         f"prior {row['prior']}")
    report.add("posterior_draws", summary["draws"], label=f"draws after burn-in ({summary['walkers']} walkers, "
                                                           f"{summary['steps']} steps, burn-in {summary['burn_in']})")
    report.add("posterior_seconds", summary["seconds"], "s")
    report.note(f"noise: Jeffreys prior 1/sigma, integrated out; median sigma {summary['noise']['median']:.3g}")
    for note in posterior.notes:
        report.note(note)


#: The laws :func:`fit` fits, as ``faultslip fit --law`` names them.
FIT_LAWS = ("rate", "rate-state")


def fit(data, law: str = "rate", **options):
    """Fit a friction law to laboratory data: what ``faultslip fit`` computes, by the same names.

    ``law="rate"`` fits seed 003's static-friction rate law, mu_s = mu_so - b theta_dot^d... (eq. 2-18), to
    static-friction measurements (:func:`faultslip.friction.fitting.fit_rate_law`; options ``loss``,
    ``bootstrap``, ``seed``, ``fixed_mu_m``). ``law="rate-state"`` fits a, b and D_c to a velocity-step record
    (:func:`fit_record`; ``stiffness`` is then required, and every option of that function applies).

    A bare file name with no such file here is a bundled example's (``fit("example_friction_data.csv")``), as
    ``faultslip fit`` reads it (:func:`faultslip.io.bundled_examples`).

    Parameters
    ----------
    data : str, path or table
        A file (CSV, text, netCDF, xlsx), or columns with units in their names.
    law : str
        ``"rate"`` or ``"rate-state"``.
    **options
        The chosen fit's own keywords.

    Returns
    -------
    FitResult or RecordFit
        The rate law's fit (parameters, covariance, bootstrap; ``report()``), or the record's
        (:class:`RecordFit`).
    """
    if law not in FIT_LAWS:
        raise InputError(f"law is one of {', '.join(FIT_LAWS)}, got {law!r}")
    if isinstance(data, (str, os.PathLike)):
        data = str(resolve_path(data, "data file", kind="example")[0])
    if law == "rate":
        return fit_rate_law(data, **options)
    if "stiffness" not in options:
        raise InputError("a rate-and-state fit needs the machine stiffness: fit(data, law='rate-state', "
                         "stiffness='1e-2 1/um')")
    return fit_record(data, **options)
