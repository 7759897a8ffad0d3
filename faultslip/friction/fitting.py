"""Fitting the static-friction rate law (seed 003 eq. 2-18) to laboratory data, with uncertainty.

.. math:: \\mu_s(\\dot\\theta) = \\mu_m + \\frac{\\mu_{so} - \\mu_m}{1 + (\\mu_{so} - \\mu_m)\\, b\\, \\dot\\theta^{d}}

Data: a CSV (or netCDF) whose header names columns with units, e.g.
``loading_rate (1/s),static_friction`` or ``platform_speed (in/s),stiffness (lbf/in),normal_load (lbf),static_friction``
(then theta_dot = K V / W). An ``amplitude`` column (with units) is fitted jointly through
alpha = A0 (mu_s - mu_m), A0 = 2W/K (seed 003, note under Table I); A0 comes from the row's W and
K, or from ``apparatus_amplitude``. A ``kinetic_friction`` column, or ``fixed_mu_m``, fixes mu_m.

The fit is bounded least squares (scipy ``least_squares``, trust-region reflective) in a
well-conditioned parameterisation: mu_m, ln(mu_so - mu_m) (so mu_so > mu_m), ln b and ln d.
Starting values come from the data: the low-rate plateau, the high-rate floor and a straight-line
fit of ln(dmu / (mu_s - mu_m) - 1) = ln(b dmu) + d ln theta_dot. Uncertainty: the covariance
s^2 (J^T J)^-1 mapped to the natural parameters; a seeded residual bootstrap on the fixed design
of rates, summarised as 95 % intervals from the bootstrap standard error with a Student-t
quantile (log scale for b and d); the residual RMS; and flags when the data do not constrain a
parameter.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from faultslip import ranges
from faultslip.contract.result import ReportedValues, Result, with_draws
from faultslip.errors import InputError, did_you_mean
from faultslip.friction.laws import static_friction
from faultslip.io.resources import open_netcdf, read_numeric_csv, split_header
from faultslip.units import to_si
from faultslip.friction.laws import RateLaw
from faultslip.io.report import Report
from faultslip.io.resources import check_input_file
from faultslip.datasets import ToXarray

PARAMETERS = ("mu_so", "mu_m", "b", "d")
COLUMNS = {
    "loading_rate": "rate", "platform_speed": "speed", "stiffness": "stiffness", "normal_load": "force",
    "static_friction": "dimensionless", "amplitude": "length", "kinetic_friction": "dimensionless",
    "apparatus_amplitude": "length",
}
LOSSES = ("linear", "soft_l1", "huber", "cauchy")
Z95 = 1.959963984540054


@dataclass
class FrictionData(ToXarray):
    """Observations in SI: loading rates, static friction, optional amplitude and A0 = 2W/K."""
    #: the units and dimensions of to_xarray() (faultslip.datasets.ToXarray)
    UNITS = {'loading_rate': '1/s', 'static_friction': '1', 'amplitude': 'm', 'apparatus_amplitude': 'm', 'kinetic_friction': '1', 'normal_load': 'N', 'stiffness': 'N/m'}
    DIMENSIONS = {'loading_rate': 'point', 'static_friction': 'point', 'amplitude': 'point', 'apparatus_amplitude': 'point', 'normal_load': 'point', 'stiffness': 'point'}

    loading_rate: np.ndarray
    static_friction: np.ndarray
    amplitude: np.ndarray | None = None
    apparatus_amplitude: np.ndarray | None = None
    kinetic_friction: float | None = None
    source: str = ""
    normal_load: np.ndarray | None = None
    stiffness: np.ndarray | None = None

    @property
    def size(self) -> int:
        return int(self.loading_rate.size)


#: Relative tolerances of the least-squares fit (scipy's defaults, stated): it stops once a step changes the
#: parameters or the cost by less than this, so a fitted value is known to about this, times the conditioning.
LEAST_SQUARES_TOLERANCE = 1e-8


def _read_columns(path: Path) -> dict:
    if path.suffix == ".nc":
        data = open_netcdf(path, "friction data")
        columns = {}
        for name, variable in data.data_vars.items():
            try:
                values = np.asarray(variable.values, dtype=float).ravel()
            except (TypeError, ValueError):
                raise InputError(f"friction data {path.name}: variable {name!r} is not numeric") from None
            units = variable.attrs.get("units")
            columns[name] = (values, units if isinstance(units, str) else None)
        sizes = {values.size for values, _ in columns.values()}
        if len(sizes) > 1:
            raise InputError(f"friction data {path.name}: the variables differ in length ({sorted(sizes)})")
        return columns
    return read_numeric_csv(path, path.name)


def _table_columns(table) -> dict:
    """A DataFrame's or mapping's columns as ``{name: (values, unit)}``, the unit from a ``"name (unit)"`` header."""
    columns = {}
    for header in list(table.keys()):
        name, unit = split_header(str(header))
        if name in columns:
            raise InputError(f"the table's column {name!r} appears twice")
        try:
            values = np.asarray(table[header], dtype=float).ravel()
        except (TypeError, ValueError):
            raise InputError(f"the table's column {name!r} is not numeric") from None
        columns[name] = (values, unit)
    return columns


def read_friction_data(source, fixed_mu_m: float | None = None) -> FrictionData:
    """Read and validate friction data; every check raises one clear sentence.

    ``source`` is a CSV or netCDF file, or a table in memory: a pandas DataFrame or a mapping of
    column to values, whose column names carry their units as the CSV's do
    (``"loading_rate (1/s)"``, ``"static_friction"``).

    Parameters
    ----------
    source : path, DataFrame or mapping
        The measurements.
    fixed_mu_m : float, optional
        A kinetic friction held fixed.

    Returns
    -------
    FrictionData
        Loading rate (1/s) and static friction (dimensionless).
    """
    if hasattr(source, "columns") or isinstance(source, Mapping):
        columns, label, origin = _table_columns(source), "the table", "table in memory"
    else:
        path = check_input_file(source, "data file")
        columns, label, origin = _read_columns(path), path.name, str(path)
    for name in columns:
        if name not in COLUMNS:
            hint = did_you_mean(name, COLUMNS)
            raise InputError(f"{label}: unknown column {name!r}{hint} (allowed: {', '.join(COLUMNS)})")

    def si(name):
        values, unit = columns[name]
        kind = COLUMNS[name]
        if kind == "dimensionless":
            if unit not in (None, "", "1"):
                raise InputError(f"{label}: {name} is dimensionless, but its header gives the unit {unit!r}")
            out = values
        else:
            if unit in (None, ""):
                raise InputError(f"{label}: column {name!r} needs a unit in its header, e.g. '{name} ("
                                 f"{'1/s' if kind == 'rate' else 'in/s' if kind == 'speed' else 'lbf/in' if kind == 'stiffness' else 'lbf' if kind == 'force' else 'in'})'")
            out = values * to_si(f"1 {unit}", kind, f"{label}, column {name}")
        if not np.all(np.isfinite(out)):
            row = int(np.argmax(~np.isfinite(out))) + 2
            raise InputError(f"{label}, row {row}: {name} is NaN or infinite")
        return out

    if "static_friction" not in columns:
        raise InputError(f"{label} needs a static_friction column")
    mu = si("static_friction")
    if "loading_rate" in columns:
        if "platform_speed" in columns:
            raise InputError(f"{label} gives both loading_rate and platform_speed; give one")
        rate = si("loading_rate")
    elif {"platform_speed", "stiffness", "normal_load"} <= set(columns):
        rate = si("stiffness") * si("platform_speed") / si("normal_load")  # seed 003 eq. 2-3
    else:
        raise InputError(f"{label} needs loading_rate, or platform_speed with stiffness and normal_load")
    if np.any(rate <= 0):
        row = int(np.argmax(rate <= 0)) + 2
        raise InputError(f"{label}, row {row}: loading rate must be positive, got {rate[row - 2]:g} 1/s")
    if np.any(mu < 0):
        raise InputError(f"{label}: static friction must be non-negative")
    amplitude = apparatus = None
    load = stiffness = None
    if "normal_load" in columns and "stiffness" in columns:
        load, stiffness = si("normal_load"), si("stiffness")
    if "amplitude" in columns:
        amplitude = si("amplitude")
        if "apparatus_amplitude" in columns:
            apparatus = si("apparatus_amplitude")
        elif load is not None:
            apparatus = 2.0 * load / stiffness  # A0 = 2W/K, seed 003 Table I note
        else:
            raise InputError(f"{label}: fitting amplitude needs A0 = 2W/K: give normal_load and stiffness "
                             "columns, or apparatus_amplitude")
    kinetic = fixed_mu_m
    if "kinetic_friction" in columns:
        kinetic = float(np.mean(si("kinetic_friction")))
    data = FrictionData(rate, mu, amplitude, apparatus, kinetic, origin, load, stiffness)
    check_data(data)
    return data


def check_data(data: FrictionData) -> None:
    """Refuse data that cannot determine the four constants."""
    name = Path(data.source).name or "the data"
    if data.size < len(PARAMETERS) + 1:
        raise InputError(f"{name} has {data.size} points; fitting mu_so, mu_m, b and d needs at least 5")
    if np.unique(np.round(np.log10(data.loading_rate), 9)).size < 3:
        raise InputError(f"{name}: all points are at one loading rate (or two); the rate law needs a spread of rates")
    if data.kinetic_friction is not None and np.all(data.static_friction <= data.kinetic_friction):
        raise InputError(f"{name}: static friction is below the kinetic friction {data.kinetic_friction:g} everywhere; "
                         "there is no stick-slip excess to fit")
    if np.ptp(data.static_friction) == 0 and data.amplitude is None:
        raise InputError(f"{name}: static friction does not vary with loading rate; eq. 2-18 cannot be fitted")


@dataclass
class FitResult(ReportedValues):
    """A fitted rate law with its uncertainty (natural parameters; b in s^d). ``fit["b"]`` is a reported value with
    its units (``fit.values`` the plain fitted numbers)."""

    values: dict
    covariance: np.ndarray
    standard_errors: dict
    intervals: dict  # 95 % intervals: bootstrap standard error, Student-t quantile
    wald_intervals: dict  # 95 % from the covariance (delta method)
    residual_rms: float
    residual_rms_amplitude: float | None
    points: int
    loss: str
    bootstrap: np.ndarray  # (n, 4) samples of (mu_so, mu_m, b, d)
    flags: list = field(default_factory=list)
    source: str = ""
    seed: int = 0

    @property
    def law(self):

        return RateLaw(self.values["mu_so"], self.values["mu_m"], self.values["b"], self.values["d"])

    def as_result(self) -> Result:
        """The fit's report as a :class:`Result`."""
        return Result("rate_law_fit", self.report())

    def to_xarray(self):
        """The fit as a CF Dataset, the schema every Result writes (each number a variable with its ``units``, each
        95 % range on ``quantile``), with the bootstrap resamples on (bootstrap_draw, bootstrap_parameter)."""
        return with_draws(self.as_result().to_xarray(), "bootstrap", PARAMETERS, self.bootstrap)

    def report(self, title="faultslip fit"):

        r = Report(title)
        r.section("Rate law (seed 003 eq. 2-18)")
        for name in PARAMETERS:
            low, high = self.intervals[name]
            unit = f"s^{self.values['d']:.4g}" if name == "b" else None
            r.add(name, self.values[name], unit, name)
            r.add(f"{name}_standard_error", self.standard_errors[name], unit, f"{name} standard error")
            r.add(f"{name}_95", [low, high], unit or "1", f"{name} 95 % (bootstrap SE, t quantile)")
        r.section("Fit")
        r.add("points", self.points)
        r.add("loss", self.loss)
        r.add("residual_rms", self.residual_rms, label="residual RMS of mu_s")
        if self.residual_rms_amplitude is not None:
            r.add("residual_rms_amplitude", self.residual_rms_amplitude, "m", "residual RMS of amplitude")
        r.add("bootstrap_samples", int(self.bootstrap.shape[0]), label=f"bootstrap samples (seed {self.seed})")
        r.add("flags", "; ".join(self.flags) if self.flags else "none")
        return r

    def to_record(self) -> dict:
        return {"mu_so": self.values["mu_so"], "mu_m": self.values["mu_m"], "b": self.values["b"], "d": self.values["d"],
                "standard_errors": self.standard_errors, "intervals_95": {k: list(v) for k, v in self.intervals.items()},
                "covariance": self.covariance.tolist(), "residual_rms": self.residual_rms, "points": self.points,
                "loss": self.loss, "flags": self.flags, "source": self.source, "seed": self.seed,
                "bootstrap": self.bootstrap.tolist()}


def _natural(theta, fixed_mu_m):
    mu_m = fixed_mu_m if fixed_mu_m is not None else theta[0]
    offset = 0 if fixed_mu_m is not None else 1
    drop, b, d = np.exp(theta[offset]), np.exp(theta[offset + 1]), np.exp(theta[offset + 2])
    return np.array([mu_m + drop, mu_m, b, d])


def starting_values(data: FrictionData, fixed_mu_m=None):
    """Plateau, floor, and a straight-line fit in log-log of the excess (see module docstring)."""
    order = np.argsort(data.loading_rate)
    rate, mu = data.loading_rate[order], data.static_friction[order]
    tenth = max(1, rate.size // 10)
    mu_so = float(np.median(mu[:tenth]))
    mu_m = fixed_mu_m if fixed_mu_m is not None else float(np.min(mu)) - 0.05 * max(mu_so - float(np.min(mu)), 1e-3)
    drop = max(mu_so - mu_m, 1e-4)
    excess = mu - mu_m
    y = drop / np.clip(excess, 1e-9, None) - 1.0
    usable = (y > 1e-3) & (y < 1e3) & (excess > 0)
    if usable.sum() >= 2 and np.ptp(np.log(rate[usable])) > 0:
        slope, intercept = np.polyfit(np.log(rate[usable]), np.log(y[usable]), 1)
        d = float(np.clip(slope, 0.1, 4.0))
        b = float(np.exp(intercept) / drop)
    else:  # no transition in the data: put it at the highest rate measured
        d = 1.0
        b = 1.0 / (drop * rate[-1])
    return mu_so, mu_m, max(b, 1e-30), d


def fit_rate_law(data, loss: str = "linear", bootstrap: int = 200, seed: int = 0,
                 fixed_mu_m: float | None = None) -> FitResult:
    """Fit mu_so, mu_m, b, d (see module docstring); ``bootstrap`` resamples with a seeded generator.

    ``data`` is :class:`FrictionData`, or anything :func:`read_friction_data` reads: a file, a pandas
    DataFrame or a mapping of columns with units in their names.

    Parameters
    ----------
    data : FrictionData, path, DataFrame or mapping
        Static friction (dimensionless) against loading rate (1/s).
    loss : str
        linear, soft_l1, huber or cauchy.
    bootstrap : int
        Resamples of the 95 % intervals.
    seed : int
        The resamples' seed.
    fixed_mu_m : float, optional
        Hold mu_m at this value.

    Returns
    -------
    FitResult
        mu_so, mu_m (dimensionless), b (s^d), d, their 95 % intervals and ``report()``.
    """
    if loss not in LOSSES:
        raise InputError(f"robust loss must be one of {', '.join(LOSSES)}, got {loss!r}")
    bootstrap = ranges.check_count(bootstrap, "bootstrap", 0, ranges.MOST_RESAMPLES)
    seed = ranges.check_count(seed, "seed")
    if not isinstance(data, FrictionData):  # a file, a DataFrame or a mapping of columns
        data = read_friction_data(data, fixed_mu_m)
    fixed_mu_m = fixed_mu_m if fixed_mu_m is not None else data.kinetic_friction
    check_data(data)
    mu_so, mu_m, b, d = starting_values(data, fixed_mu_m)
    theta0 = np.array(([] if fixed_mu_m is not None else [mu_m]) + [math.log(mu_so - mu_m), math.log(b), math.log(d)])
    lower = np.array(([] if fixed_mu_m is not None else [0.0]) + [math.log(1e-6), -80.0, math.log(0.02)])
    upper = np.array(([] if fixed_mu_m is not None else [3.0]) + [math.log(3.0), 80.0, math.log(6.0)])
    theta0 = np.clip(theta0, lower + 1e-9, upper - 1e-9)
    scale_mu = max(float(np.std(data.static_friction)), 1e-4)

    def residuals(theta, rate, mu, amplitude, apparatus, weight_amplitude):
        natural = _natural(theta, fixed_mu_m)
        model = static_friction(rate, *natural)
        out = model - mu
        if amplitude is not None:
            predicted = apparatus * (model - natural[1])
            out = np.concatenate([out, weight_amplitude * (predicted - amplitude)])
        return out

    def solve(rate, mu, amplitude, apparatus, start, weight):
        from scipy.optimize import least_squares  # heavy: imported where used

        return least_squares(residuals, start, bounds=(lower, upper), loss=loss, f_scale=0.1 * scale_mu if loss != "linear" else 1.0,
                             args=(rate, mu, amplitude, apparatus, weight), x_scale="jac", max_nfev=2000,
                             xtol=LEAST_SQUARES_TOLERANCE, ftol=LEAST_SQUARES_TOLERANCE, gtol=LEAST_SQUARES_TOLERANCE)

    solve.loss, solve.lower, solve.upper = loss, lower, upper

    weight = 0.0
    if data.amplitude is not None:  # scale the amplitude residuals to the friction ones (two passes)
        first = solve(data.loading_rate, data.static_friction, None, None, theta0, 0.0)
        natural = _natural(first.x, fixed_mu_m)
        rms_mu = max(float(np.sqrt(np.mean(first.fun**2))), 1e-6)
        predicted = data.apparatus_amplitude * (static_friction(data.loading_rate, *natural) - natural[1])
        rms_alpha = max(float(np.sqrt(np.mean((predicted - data.amplitude) ** 2))), 1e-12)
        weight = rms_mu / rms_alpha
        theta0 = first.x
    result = solve(data.loading_rate, data.static_friction, data.amplitude, data.apparatus_amplitude, theta0, weight)
    natural = _natural(result.x, fixed_mu_m)
    n_obs = result.fun.size
    free = result.x.size
    dof = max(n_obs - free, 1)
    sigma2 = float(np.sum(result.fun**2) / dof)
    jac = result.jac
    try:
        covariance_internal = sigma2 * np.linalg.pinv(jac.T @ jac)
    except np.linalg.LinAlgError:
        covariance_internal = np.full((free, free), np.inf)
    transform = _transform_jacobian(result.x, fixed_mu_m)
    covariance = transform @ covariance_internal @ transform.T
    errors = np.sqrt(np.clip(np.diag(covariance), 0, None))
    standard_errors = dict(zip(PARAMETERS, errors.tolist()))
    wald = _wald_intervals(result.x, covariance_internal, fixed_mu_m)
    samples = _bootstrap(data, solve, result.x, bootstrap, seed, weight, fixed_mu_m)
    intervals = bootstrap_intervals(natural, samples, dof) if samples.shape[0] >= 10 else wald
    residual_mu = result.fun[: data.size]
    rms_alpha = None
    if data.amplitude is not None:
        predicted = data.apparatus_amplitude * (static_friction(data.loading_rate, *natural) - natural[1])
        rms_alpha = float(np.sqrt(np.mean((predicted - data.amplitude) ** 2)))
    fit = FitResult(values=dict(zip(PARAMETERS, natural.tolist())), covariance=covariance,
                    standard_errors=standard_errors, intervals=intervals, wald_intervals=wald,
                    residual_rms=float(np.sqrt(np.mean(residual_mu**2))), residual_rms_amplitude=rms_alpha,
                    points=data.size, loss=loss, bootstrap=samples, source=data.source, seed=seed)
    fit.flags = constraint_flags(data, fit, result, lower, upper, fixed_mu_m)
    return fit


def _transform_jacobian(theta, fixed_mu_m):
    """d(mu_so, mu_m, b, d) / d(internal parameters)."""
    offset = 0 if fixed_mu_m is not None else 1
    drop, b, d = np.exp(theta[offset:offset + 3])
    rows = np.zeros((4, theta.size))
    if fixed_mu_m is None:
        rows[0, 0] = 1.0  # mu_so = mu_m + drop
        rows[1, 0] = 1.0
    rows[0, offset] = drop
    rows[2, offset + 1] = b
    rows[3, offset + 2] = d
    return rows


def _wald_intervals(theta, covariance_internal, fixed_mu_m):
    """95 % intervals from the covariance, taken in the internal (log) parameters where that is natural."""
    offset = 0 if fixed_mu_m is not None else 1
    se = np.sqrt(np.clip(np.diag(covariance_internal), 0, None))
    out = {}
    if fixed_mu_m is None:
        mu_m, se_mu_m = theta[0], se[0]
        out["mu_m"] = (mu_m - Z95 * se_mu_m, mu_m + Z95 * se_mu_m)
        # mu_so = mu_m + exp(log drop): variance from the delta method
        grad = np.zeros(theta.size)
        grad[0], grad[1] = 1.0, math.exp(theta[1])
        var = float(grad @ covariance_internal @ grad)
        mu_so = theta[0] + math.exp(theta[1])
        out["mu_so"] = (mu_so - Z95 * math.sqrt(max(var, 0)), mu_so + Z95 * math.sqrt(max(var, 0)))
    else:
        out["mu_m"] = (fixed_mu_m, fixed_mu_m)
        drop, se_drop = theta[0], se[0]
        out["mu_so"] = (fixed_mu_m + _exp(drop - Z95 * se_drop), fixed_mu_m + _exp(drop + Z95 * se_drop))
    for name, index in (("b", offset + 1), ("d", offset + 2)):
        out[name] = (_exp(theta[index] - Z95 * se[index]), _exp(theta[index] + Z95 * se[index]))
    return out


def _exp(value):
    """exp that saturates to 0 or inf for an unconstrained parameter instead of overflowing."""
    return math.exp(min(max(value, -745.0), 709.0)) if math.isfinite(value) else (math.inf if value > 0 else 0.0)


def bootstrap_intervals(values, samples, dof) -> dict:
    """95 % intervals from the bootstrap standard error with a Student-t quantile on n - p dof.

    On the natural scale for mu_so and mu_m, on the log scale for b and d (positive, skewed).
    Measured coverage (tests/capabilities/friction/test_fitting.py): about 95 % across the Table I presets; the plain
    percentile interval covered 93 % on the same fits.
    """
    from scipy.special import stdtrit  # heavy: imported where used (scipy.stats would add ~1 s for one quantile)

    quantile = float(stdtrit(max(dof, 1), 0.975))  # Student-t quantile, as scipy.stats.t.ppf
    out = {}
    for index, name in enumerate(PARAMETERS):
        column = samples[:, index]
        if name in ("b", "d"):
            spread = float(np.std(np.log(column), ddof=1))
            centre = math.log(values[index])
            out[name] = (_exp(centre - quantile * spread), _exp(centre + quantile * spread))
        else:
            spread = float(np.std(column, ddof=1))
            out[name] = (float(values[index] - quantile * spread), float(values[index] + quantile * spread))
    return out


def _bootstrap(data, solve, theta, count, seed, weight, fixed_mu_m):
    """Residual bootstrap: the rates are the experiment's fixed design, so the fitted curve plus
    resampled residuals (rescaled by sqrt(n / (n - p)) for the fitted degrees of freedom) stands
    for a repeated experiment. Seeded: the same seed gives the same samples."""
    if count <= 0:
        return np.empty((0, 4))
    rng = np.random.default_rng(seed)
    natural = _natural(theta, fixed_mu_m)
    fitted = static_friction(data.loading_rate, *natural)
    inflate = math.sqrt(data.size / max(data.size - theta.size, 1))
    residual = (data.static_friction - fitted) * inflate
    residual -= residual.mean()
    if data.amplitude is not None:
        fitted_alpha = data.apparatus_amplitude * (fitted - natural[1])
        residual_alpha = (data.amplitude - fitted_alpha) * inflate
        residual_alpha -= residual_alpha.mean()
    if data.amplitude is None:  # one call draws the same stream as one call per resample
        picks = rng.integers(0, data.size, (count, data.size))
        draws = [(fitted + residual[pick], None) for pick in picks]
    else:
        draws = []
        for _ in range(count):  # friction and amplitude picks interleave in the stream
            pick = rng.integers(0, data.size, data.size)
            amplitude = fitted_alpha + residual_alpha[rng.integers(0, data.size, data.size)]
            draws.append((fitted + residual[pick], amplitude))
    thetas = np.full((count, theta.size), np.nan)
    if data.amplitude is None and solve.loss == "linear":  # many resamples at once (see _batched_fit)
        rows = max(1, BATCH_VALUES // data.size)  # a batch's Jacobian stays in cache, whatever the count
        for start in range(0, count, rows):
            chunk = slice(start, start + rows)
            thetas[chunk], _ = _batched_fit(data.loading_rate, fitted[None, :] + residual[picks[chunk]], theta,
                                            solve.lower, solve.upper, fixed_mu_m)
    for index in np.flatnonzero(~np.all(np.isfinite(thetas), axis=1)):  # the rest one by one
        mu, amplitude = draws[index]
        thetas[index] = solve(data.loading_rate, mu, amplitude, data.apparatus_amplitude, theta, weight).x
    return np.array([_natural(t, fixed_mu_m) for t in thetas])


#: Data values per batch of resamples solved together: about 2 MB of Jacobian per batch.
BATCH_VALUES = 65536


def _model_and_jacobian(rate, thetas, fixed_mu_m):
    """eq. 2-18 and its analytic derivatives in the fitted coordinates, for a batch of parameter rows.

    Returns the model (rows, points) and the Jacobian (rows, parameters, points).

    With g = Delta b r^d: mu = mu_m + Delta/(1 + g), d mu/d ln Delta = Delta/(1 + g)^2,
    d mu/d ln b = -Delta g/(1 + g)^2 and d mu/d ln d = -Delta g d ln(r)/(1 + g)^2.
    """
    offset = 0 if fixed_mu_m is not None else 1
    mu_m = np.full(thetas.shape[0], fixed_mu_m) if fixed_mu_m is not None else thetas[:, 0]
    drop, b, d = (np.exp(thetas[:, offset + k])[:, None] for k in range(3))
    log_rate = np.log(rate)[None, :]
    g = drop * b * np.exp(d * log_rate)
    inverse = 1.0 / (1.0 + g)
    model = mu_m[:, None] + drop * inverse
    # (rows, parameters, points): each derivative is one contiguous row, filled in place
    jac = np.empty((thetas.shape[0], thetas.shape[1], rate.size))
    if fixed_mu_m is None:
        jac[:, 0] = 1.0
    np.multiply(drop * inverse, inverse, out=jac[:, offset])
    np.multiply(jac[:, offset], g, out=jac[:, offset + 1])
    np.negative(jac[:, offset + 1], out=jac[:, offset + 1])
    np.multiply(jac[:, offset + 1], d * log_rate, out=jac[:, offset + 2])
    return model, jac


def _batched_fit(rate, mu, theta, lower, upper, fixed_mu_m, iterations=200):
    """Levenberg-Marquardt on every bootstrap resample at once (linear loss, friction only).

    Starts each resample from the best fit, uses the analytic Jacobian, and stops a row when its
    step and cost change reach round-off. Rows that end on a bound or do not converge are
    returned as NaN, and the caller fits them one by one with scipy's bounded least_squares.
    The minimum is the same, so the intervals agree with fitting one resample at a time to
    least_squares' own tolerance (tests/capabilities/friction/test_fitting.py).
    """
    count = mu.shape[0]
    thetas = np.repeat(theta[None, :], count, axis=0)
    damping = np.full(count, 1e-6)  # the best fit is close: start as Gauss-Newton
    model, jac = _model_and_jacobian(rate, thetas, fixed_mu_m)
    residual = model - mu
    cost = np.einsum("ij,ij->i", residual, residual)
    active = np.ones(count, dtype=bool)
    eye = np.eye(theta.size)
    for _ in range(iterations):
        rows = np.flatnonzero(active)
        if rows.size == 0:
            break
        j, r = jac[rows], residual[rows]
        normal = j @ j.transpose(0, 2, 1)  # batched BLAS on (rows, parameters, points)
        gradient = (j @ r[..., None])[..., 0]
        scaled = normal + damping[rows, None, None] * (normal * eye)
        try:
            step = -np.linalg.solve(scaled, gradient[..., None])[..., 0]
        except np.linalg.LinAlgError:
            return np.full_like(thetas, np.nan), 0
        trial = np.clip(thetas[rows] + step, lower, upper)
        trial_model, trial_jac = _model_and_jacobian(rate, trial, fixed_mu_m)
        trial_residual = trial_model - mu[rows]
        trial_cost = np.einsum("ij,ij->i", trial_residual, trial_residual)
        better = trial_cost <= cost[rows]
        # at the minimum a step changes the cost only by round-off, in either direction: done
        change = np.abs(cost[rows] - trial_cost) / np.maximum(cost[rows], 1e-300)
        moved = np.max(np.abs(trial - thetas[rows]), axis=1) / (1.0 + np.max(np.abs(thetas[rows]), axis=1))
        done = (change < 1e-13) | (moved < 1e-11)  # tighter than least_squares' own 1e-8
        accepted = rows[better]
        thetas[accepted], jac[accepted], residual[accepted], cost[accepted] = (
            trial[better], trial_jac[better], trial_residual[better], trial_cost[better])
        damping[accepted] = np.maximum(damping[accepted] / 3.0, 1e-12)
        damping[rows[~better]] *= 4.0
        active[rows[done]] = False
        active[rows[~better & ~done][damping[rows[~better & ~done]] > 1e12]] = False  # stuck: to least_squares
    on_bound = np.any((thetas <= lower + 1e-9) | (thetas >= upper - 1e-9), axis=1)
    unconverged = active | on_bound | (damping > 1e12)  # still moving, on a bound, or stuck
    thetas[unconverged] = np.nan
    return thetas, int(unconverged.sum())


def constraint_flags(data, fit, result, lower, upper, fixed_mu_m) -> list:
    """Plain statements of what the data cannot pin down."""
    flags = []
    values = fit.values
    drop = values["mu_so"] - values["mu_m"]
    with np.errstate(over="ignore", divide="ignore"):  # an extreme fit gives an infinite half-drop rate
        half_rate = float(np.power(1.0 / (values["b"] * drop), 1.0 / values["d"])) \
            if values["b"] > 0 and drop > 0 else math.inf
    rates = data.loading_rate
    if not np.any(rates > 3 * half_rate):
        flags.append(f"no points well above the half-drop rate {half_rate:.3g} 1/s: mu_m and d are poorly pinned "
                     "(the friction floor is not reached)")
    if not np.any(rates < half_rate / 3):
        flags.append(f"no points well below the half-drop rate {half_rate:.3g} 1/s: mu_so is poorly pinned "
                     "(the low-rate plateau is not reached)")
    for index, name in enumerate(["mu_m", "log drop", "log b", "log d"][(1 if fixed_mu_m is not None else 0):]):
        if abs(result.x[index] - lower[index]) < 1e-6 or abs(result.x[index] - upper[index]) < 1e-6:
            flags.append(f"{name} sits on its bound: the data do not constrain it")
    for name in PARAMETERS:
        low, high = fit.intervals[name]
        value = values[name]
        if name in ("b", "d") and value > 0 and high / max(low, 1e-300) > 100:
            flags.append(f"{name} is unconstrained: its 95 % interval spans more than a factor 100")
        elif name in ("mu_so", "mu_m") and (high - low) > max(drop, 1e-3):
            flags.append(f"{name} is unconstrained: its 95 % interval is wider than mu_so - mu_m")
    return flags


def synthetic_data(preset, points=40, noise=0.005, seed=0, rates=None, amplitude_noise=None):
    """Friction data drawn from a Table I preset's law with Gaussian noise (seeded), for tests and demos."""
    rng = np.random.default_rng(seed)
    law = preset.rate_law
    if rates is None:
        drop = law.mu_so - law.mu_m
        half = (1.0 / (law.b * drop)) ** (1.0 / law.d)
        rates = np.geomspace(half / 1e3, half * 1e3, points)
    mu = law.static(rates) + noise * rng.standard_normal(rates.size)
    amplitude = apparatus = None
    if amplitude_noise is not None:
        apparatus = np.full(rates.size, 2 * preset.normal_load / preset.stiffness)
        amplitude = apparatus * (law.static(rates) - law.mu_m) + amplitude_noise * rng.standard_normal(rates.size)
    return FrictionData(rates, mu, amplitude, apparatus, None, f"synthetic {preset.name}")


def fit_figure(data: FrictionData, fit: FitResult):
    """Data, fit and 95 % band against log10 loading rate (the style of seed 003 Figs. 4-1 to 4-22).

    Parameters
    ----------
    data : FrictionData
        The measured static friction against loading rate.
    fit : FitResult
        :func:`fit_rate_law`'s fit.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt  # heavy: imported where used

    panels = 2 if data.amplitude is not None else 1
    figure, axes = plt.subplots(1, panels, figsize=(5.6 * panels, 4.4), constrained_layout=True, squeeze=False)
    rates = np.geomspace(data.loading_rate.min() / 3, data.loading_rate.max() * 3, 300)
    curves = np.array([static_friction(rates, *sample) for sample in fit.bootstrap]) if fit.bootstrap.size else None
    axis = axes[0, 0]
    axis.plot(np.log10(data.loading_rate), data.static_friction, "o", mfc="none", color="k", label="data")
    axis.plot(np.log10(rates), fit.law.static(rates), color="C0", label="fit, eq. 2-18")
    if curves is not None:
        low, high = np.percentile(curves, [2.5, 97.5], axis=0)
        axis.fill_between(np.log10(rates), low, high, color="C0", alpha=0.25, label="95 % band (bootstrap)")
    axis.axhline(fit.values["mu_m"], color="C0", ls="--", lw=0.8)
    axis.set_xlabel(r"$\log_{10}\,\dot\theta$  ($\dot\theta$ in 1/s)")
    axis.set_ylabel(r"static friction $\mu_s$")
    axis.set_title(f"μso = {fit.values['mu_so']:.3f}, μm = {fit.values['mu_m']:.3f}, b = {fit.values['b']:.3g}, "
                   f"d = {fit.values['d']:.3f}", fontsize=9)
    axis.legend(fontsize=8)
    axis.grid(True, alpha=0.3)
    if data.amplitude is not None:
        axis = axes[0, 1]
        apparatus = float(np.median(data.apparatus_amplitude))
        axis.plot(np.log10(data.loading_rate), data.amplitude / 0.0254, "o", mfc="none", color="k", label="data")
        model = apparatus * (fit.law.static(rates) - fit.values["mu_m"])
        axis.plot(np.log10(rates), model / 0.0254, color="C1", label="fit, α = A0 (μs − μm)")
        if curves is not None:
            alphas = apparatus * (curves - fit.bootstrap[:, 1:2])
            low, high = np.percentile(alphas, [2.5, 97.5], axis=0)
            axis.fill_between(np.log10(rates), low / 0.0254, high / 0.0254, color="C1", alpha=0.25, label="95 % band")
        axis.set_xlabel(r"$\log_{10}\,\dot\theta$  ($\dot\theta$ in 1/s)")
        axis.set_ylabel(r"amplitude $\alpha$ (in)")
        axis.legend(fontsize=8)
        axis.grid(True, alpha=0.3)
    figure.suptitle(f"Rate-law fit: {Path(fit.source).name}")
    return figure
