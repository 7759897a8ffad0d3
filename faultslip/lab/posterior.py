"""Bayesian posteriors of rate-and-state parameters from a velocity-step record, sampled with emcee.

The model is the fit's (:mod:`faultslip.lab.rate_state_fit`): the quasi-static slider on the record's
spring and load history, run by the compiled Dormand-Prince kernel where numba is installed. The
likelihood takes independent Gaussian noise of unknown sigma in friction; with Jeffreys' prior
p(sigma) ~ 1/sigma, sigma integrates out exactly,

    p(data | theta) ~ SSR(theta)^(-n/2),   SSR = sum (mu_model - mu_observed)^2,

so the sampler moves in the law's parameters only, and each draw's sigma is reported as
sqrt(SSR / n). Priors are stated and changeable (:func:`parse_prior`); the defaults are broad:
uniform mu0 on [0, 2], a on [1e-5, 0.1], b and b2 on [0, 0.1], log-uniform D_c on [1e-8, 1e-2] m and
D_c2 on [1e-8, 1e-1] m. D_c and D_c2 are sampled as their logarithms. A free machine stiffness k (friction
per slip, sampled as ln k) has by default a log-normal prior about the stated stiffness, one sd of ln k being
ln 2 (a factor of two: labs know their machine's stiffness that well, and fit it because it biases D_c).

emcee's affine-invariant ensemble (Foreman-Mackey et al. 2013; a mixture of differential-evolution
moves, which mix faster on these correlated parameters) starts in a small ball around the least-squares
fit and runs in blocks until it has converged, and only then reports:

- the integrated autocorrelation time tau of every parameter (emcee's estimator) is known to 10 %
  between checks and the chain is longer than 50 tau (emcee's rule);
- the effective sample size, walkers x kept steps / tau, is at least 400 for every parameter;
- the split R-hat over the walkers (Gelman et al. 2013, after the burn-in of 3 tau) is below 1.05.
  An ensemble's walkers are not independent chains, and each holds only about N / tau independent
  draws, so their R-hat falls as 1 + O(tau / N): 1.01 would ask for chains of some 130 tau (measured),
  where 1.05, Gelman & Rubin's customary bound, checks that no walker is stuck apart.

A chain that reaches ``max_steps`` first raises :class:`SolverError` with the diagnostics: no
posterior is reported from a chain that has not converged.
"""

from __future__ import annotations

import math
import time as clock
from dataclasses import dataclass, field

import emcee
import numpy as np

from faultslip.dynamics.rate_state.compiled import available as compiled_kernel_available
from faultslip.dynamics.rate_state.slider import RateStateSlider, quasi_static_friction, simulate_rate_state
from faultslip.errors import FaultslipError, InputError, SolverError
from faultslip.friction.rate_state import RateStateLaw
from faultslip.io.progress import announce, duration, reporter
from faultslip.lab.rate_state_fit import TREND_LIMIT, StepRecord, correlation_notes, fit_velocity_steps
from faultslip.datasets import ToXarray
from faultslip.units import takes_units

PRIOR_KINDS = ("uniform", "loguniform", "normal", "lognormal")
LOG_SAMPLED = ("critical_slip", "critical_slip2", "stiffness")
UNITS = {"mu0": "1", "a": "1", "b": "1", "critical_slip": "m", "b2": "1", "critical_slip2": "m", "stiffness": "1/m",
         "trend": "1/m"}
#: a free machine stiffness's default prior: log-normal about the stated value, a factor of 2 as one sd of ln k
STIFFNESS_SPREAD = math.log(2.0)
MIN_EFFECTIVE = 400
MAX_R_HAT = 1.05
TAU_FACTOR = 50
TAU_STABILITY = 0.1  # the estimate of tau moves less than this between checks (100 steps apart)
BLOCK = 100
#: The autocorrelation time (steps) the posterior's first time estimate assumes, before one is measured.
TAU_GUESS = 40


@dataclass(frozen=True)
class Prior:
    """A prior on one parameter: uniform or log-uniform on [first, second], normal (mean, sd), or
    log-normal (median, sd of the natural logarithm).

    Parameters
    ----------
    kind : str
        uniform, loguniform, normal or lognormal.
    first, second : float
        The bounds (uniform, log-uniform), mean and sd (normal), or median and sd of the natural logarithm
        (log-normal), in the parameter's SI unit.
    """

    kind: str
    first: float
    second: float

    def __post_init__(self):
        if self.kind not in PRIOR_KINDS:
            raise InputError(f"a prior is one of {', '.join(PRIOR_KINDS)}, got {self.kind!r}")
        if not (math.isfinite(self.first) and math.isfinite(self.second)):
            raise InputError(f"a {self.kind} prior needs two finite numbers, got {self.first!r}, {self.second!r}")
        if self.kind in ("uniform", "loguniform") and not self.first < self.second:
            raise InputError(f"a {self.kind} prior needs low < high, got {self.first:g} and {self.second:g}")
        if self.kind in ("loguniform", "lognormal") and self.first <= 0:
            raise InputError(f"a {self.kind} prior lives on positive values: its first number must be > 0")
        if self.kind in ("normal", "lognormal") and self.second <= 0:
            raise InputError(f"a {self.kind} prior needs a positive spread, got {self.second:g}")

    def log_density(self, value: float) -> float:
        """ln p(value) on the natural scale, up to a constant; -inf outside the support."""
        if self.kind == "uniform":
            return 0.0 if self.first <= value <= self.second else -math.inf
        if value <= 0 and self.kind in ("loguniform", "lognormal"):
            return -math.inf
        if self.kind == "loguniform":
            return -math.log(value) if self.first <= value <= self.second else -math.inf
        if self.kind == "normal":
            return -0.5 * ((value - self.first) / self.second) ** 2
        return -0.5 * ((math.log(value) - math.log(self.first)) / self.second) ** 2 - math.log(value)

    def describe(self) -> str:
        if self.kind in ("uniform", "loguniform"):
            return f"{self.kind} on [{self.first:g}, {self.second:g}]"
        if self.kind == "normal":
            return f"normal, mean {self.first:g}, sd {self.second:g}"
        return f"log-normal, median {self.first:g}, sd of ln {self.second:g}"


DEFAULT_PRIORS = {"mu0": Prior("uniform", 0.0, 2.0), "a": Prior("uniform", 1e-5, 0.1), "b": Prior("uniform", 0.0, 0.1),
                  "critical_slip": Prior("loguniform", 1e-8, 1e-2), "b2": Prior("uniform", 0.0, 0.1),
                  "critical_slip2": Prior("loguniform", 1e-8, 1e-1)}


def parse_prior(text: str) -> tuple[str, Prior]:
    """``"a=uniform:0:0.05"``, ``"critical_slip=loguniform:1e-7:1e-3"``, ``"b=normal:0.012:0.002"`` (SI).

    Parameters
    ----------
    text : str
        ``name=kind:first:second``.

    Returns
    -------
    tuple
        (parameter name, :class:`Prior`).
    """
    name, _, spec = str(text).partition("=")
    name = name.strip()
    if name not in DEFAULT_PRIORS and name not in ("stiffness", "trend"):
        raise InputError(f"a prior is set on one of {', '.join(DEFAULT_PRIORS)}, stiffness or trend, as "
                         f"name=kind:first:second; got {text!r}")
    parts = spec.split(":")
    if len(parts) != 3:
        raise InputError(f"prior {text!r} must read name=kind:first:second, e.g. a=uniform:0:0.05")
    try:
        first, second = float(parts[1]), float(parts[2])
    except ValueError:
        raise InputError(f"prior {text!r}: its two numbers must be numbers (SI)") from None
    return name, Prior(parts[0].strip(), first, second)


def _split_r_hat(chains: np.ndarray) -> np.ndarray:
    """Split R-hat (Gelman et al. 2013, BDA3 eq. 11.4) of ``chains`` (steps, chains, parameters)."""
    steps = chains.shape[0] // 2 * 2
    halves = np.concatenate([chains[: steps // 2], chains[steps // 2: steps]], axis=1)
    n = halves.shape[0]
    means = halves.mean(axis=0)
    within = halves.var(axis=0, ddof=1).mean(axis=0)
    between = n * means.var(axis=0, ddof=1)
    pooled = (n - 1) / n * within + between / n
    return np.sqrt(pooled / np.maximum(within, 1e-300))


@dataclass
class Posterior(ToXarray):
    """Posterior draws of a rate-and-state law, with the sampler's diagnostics and what it assumed."""

    names: list
    samples: np.ndarray  # (draws, parameters), natural scale, after burn-in and thinning
    noise: np.ndarray  # sigma of each draw, sqrt(SSR / n)
    priors: dict
    autocorrelation_time: dict  # steps, per parameter
    effective_sample_size: dict
    r_hat: dict
    acceptance: float
    walkers: int
    steps: int
    burn: int
    thin: int
    evaluations: int
    seconds: float
    reference_speed: float
    evolution: str
    stiffness: float
    fit: object  # the least-squares fit the walkers started from
    seed: int = 0
    notes: list = field(default_factory=list)

    def median(self) -> dict:
        return {name: float(np.median(self.samples[:, i])) for i, name in enumerate(self.names)}

    def intervals(self, level: float = 0.95) -> dict:
        """Equal-tailed credible intervals."""
        tail = 50.0 * (1.0 - level)
        return {name: (float(np.percentile(self.samples[:, i], tail)), float(np.percentile(self.samples[:, i],
                                                                                           100.0 - tail)))
                for i, name in enumerate(self.names)}

    def law(self, row=None) -> RateStateLaw:
        values = dict(zip(self.names, self.median().values() if row is None else row))
        return RateStateLaw(a=values["a"], b=values["b"], critical_slip=values["critical_slip"], mu0=values["mu0"],
                            reference_speed=self.reference_speed, evolution=self.evolution,
                            b2=values.get("b2", 0.0), critical_slip2=values.get("critical_slip2"), source="posterior")

    def spring(self, row=None) -> float:
        """The stiffness of a draw (``row``) or the median, where it was sampled; the stated one otherwise."""
        if "stiffness" not in self.names:
            return self.stiffness
        return float(dict(zip(self.names, self.median().values() if row is None else row))["stiffness"])

    def predictive(self, record: StepRecord, draws: int = 200, level: float = 0.95, seed: int = 0) -> dict:
        """Posterior bands over the record: of the model (credible) and of new data (model plus each draw's
        noise), from ``draws`` draws; {"time", "model": (low, median, high), "data": (low, high)}."""
        rng = np.random.default_rng(seed)
        chosen = rng.choice(self.samples.shape[0], size=min(draws, self.samples.shape[0]), replace=False)
        curves, data = [], []
        for index in chosen:
            try:
                run = simulate_rate_state(RateStateSlider(self.law(self.samples[index]), self.spring(self.samples[index]),
                                                          1.0), record.history, t_eval=record.time, rtol=1e-8)
            except FaultslipError:
                continue
            friction = run.friction + (dict(zip(self.names, self.samples[index]))["trend"]
                                       * record.history.displacement(record.time) if "trend" in self.names else 0.0)
            curves.append(friction)
            data.append(friction + self.noise[index] * rng.standard_normal(record.time.size))
        curves, data = np.asarray(curves), np.asarray(data)
        tail = 50.0 * (1.0 - level)
        return {"time": record.time, "model": tuple(np.percentile(curves, q, axis=0) for q in (tail, 50.0, 100 - tail)),
                "data": tuple(np.percentile(data, q, axis=0) for q in (tail, 100 - tail))}

    def to_dict(self) -> dict:
        intervals, median = self.intervals(), self.median()
        return {"law": self.evolution, "reference_speed": {"value": self.reference_speed, "units": "m/s"},
                "parameters": {name: {"median": median[name], "credible_95": list(intervals[name]),
                                      "units": UNITS[name], "prior": self.priors[name].describe(),
                                      "autocorrelation_time": self.autocorrelation_time[name],
                                      "effective_sample_size": self.effective_sample_size[name],
                                      "r_hat": self.r_hat[name]} for name in self.names},
                "noise": {"median": float(np.median(self.noise)), "units": "1",
                          "prior": "Jeffreys 1/sigma, integrated out"},
                "draws": int(self.samples.shape[0]), "walkers": self.walkers, "steps": self.steps,
                "burn_in": self.burn, "thin": self.thin, "acceptance": self.acceptance,
                "model_evaluations": self.evaluations, "seconds": self.seconds, "seed": self.seed,
                "notes": self.notes}

    def to_dataset(self):
        """The draws as an xarray Dataset on dimension ``draw``, one variable a parameter with its CF unit, its prior,
        R-hat, effective sample size and 95 % credible interval in its attributes; each draw's noise sigma."""
        import xarray as xr  # heavy: imported where used

        intervals = self.intervals()
        data = {name: ("draw", self.samples[:, i],
                       {"units": UNITS[name], "prior": self.priors[name].describe(), "r_hat": self.r_hat[name],
                        "effective_sample_size": self.effective_sample_size[name],
                        "credible_95": list(intervals[name])})
                for i, name in enumerate(self.names)}
        data["noise"] = ("draw", self.noise, {"units": "1", "long_name": "each draw's noise sigma, sqrt(SSR / n)"})
        return xr.Dataset(data, coords={"draw": ("draw", np.arange(self.samples.shape[0]))},
                          attrs={"evolution": self.evolution, "reference_speed_m_s": self.reference_speed,
                                 "walkers": self.walkers, "steps": self.steps, "burn_in": self.burn, "seed": self.seed,
                                 "acceptance": self.acceptance, "notes": "; ".join(self.notes),
                                 "Conventions": "CF-1.8"})

    def to_record(self, keep: int = 500) -> dict:
        """The registry entry: the median law, the priors, the diagnostics and up to ``keep`` draws that carry
        the posterior into fault predictions."""
        law = self.law()
        step = max(1, self.samples.shape[0] // keep)
        return {"kind": "rate_state", "a": law.a, "b": law.b, "critical_slip": law.critical_slip, "mu0": law.mu0,
                "reference_speed": law.reference_speed, "evolution": law.evolution, "b2": law.b2,
                "critical_slip2": law.critical_slip2, "names": list(self.names),
                "samples": self.samples[::step][:keep].tolist(), "samples_kind": "posterior",
                "intervals_95": {k: list(v) for k, v in self.intervals().items()},
                "priors": {name: [p.kind, p.first, p.second] for name, p in self.priors.items()},
                "diagnostics": {"r_hat": self.r_hat, "effective_sample_size": self.effective_sample_size,
                                "autocorrelation_time": self.autocorrelation_time},
                "seed": self.seed, "residual_rms": float(np.median(self.noise)), "points": int(self.fit.points)}


class _LogPosterior:
    """ln p(theta | data) up to a constant, theta = (mu0, a, b, ln D_c[, b2, ln D_c2]); picklable for a pool."""

    def __init__(self, record, stiffness, names, priors, reference_speed, evolution, rtol):
        self.time, self.friction, self.history = record.time, record.friction, record.history
        self.stiffness, self.names, self.priors = stiffness, names, priors
        self.reference_speed, self.evolution, self.rtol = reference_speed, evolution, rtol
        self.load_point = record.history.displacement(record.time) if "trend" in names else None

    def natural(self, theta):
        return [math.exp(v) if name in LOG_SAMPLED else v for name, v in zip(self.names, theta)]

    def __call__(self, theta):
        values = self.natural(theta)
        total = 0.0
        for name, value, raw in zip(self.names, values, theta):
            density = self.priors[name].log_density(value)
            if not math.isfinite(density):
                return -math.inf, math.nan
            total += density + (raw if name in LOG_SAMPLED else 0.0)  # the Jacobian of sampling ln D_c
        params = dict(zip(self.names, values))
        try:
            law = RateStateLaw(a=params["a"], b=params["b"], critical_slip=params["critical_slip"], mu0=params["mu0"],
                               reference_speed=self.reference_speed, evolution=self.evolution,
                               b2=params.get("b2", 0.0), critical_slip2=params.get("critical_slip2"))
            friction = quasi_static_friction(law, params.get("stiffness", self.stiffness), self.history, self.time,
                                             self.rtol)
        except FaultslipError:
            return -math.inf, math.nan
        if self.load_point is not None:
            friction = friction + params["trend"] * self.load_point
        misfit = friction - self.friction
        ssr = float(misfit @ misfit)
        if not (math.isfinite(ssr) and ssr > 0):
            return -math.inf, math.nan
        return total - 0.5 * self.time.size * math.log(ssr), ssr


_WORKER_POSTERIOR = None


def _install(log_posterior) -> None:
    global _WORKER_POSTERIOR
    _WORKER_POSTERIOR = log_posterior


def _evaluate(theta):
    return _WORKER_POSTERIOR(theta)


class _Pool:
    """A process pool for emcee that holds the log-posterior (and its record) in each worker once, instead
    of pickling it with every batch of walkers; workers die with the parent (``terminate`` in a finally)."""

    def __init__(self, log_posterior, workers: int):
        import multiprocessing  # a platform module: the likelihood's workers

        self.workers = workers
        self.pool = multiprocessing.get_context("spawn").Pool(workers, initializer=_install,
                                                                initargs=(log_posterior,))

    def map(self, function, thetas):
        thetas = list(thetas)
        return self.pool.map(_evaluate, thetas, chunksize=max(1, -(-len(thetas) // self.workers)))

    def terminate(self):
        self.pool.terminate()


@takes_units(stiffness="inverse_length")
def sample_posterior(record: StepRecord, stiffness: float, *, evolution: str = "aging", two_state: bool = False,
                     priors: dict | None = None, samples: int = 10_000, walkers: int | None = None, seed: int = 0,
                     max_steps: int = 20_000, rtol: float = 1e-7, workers: int = 1, initial_fit=None,
                     stiffness_free: bool = False, trend: bool = False, progress=None) -> Posterior:
    """Sample the posterior of (mu0, a, b, D_c[, b2, D_c2]) given ``record`` on a spring of ``stiffness``
    (friction per metre) until the chain has converged (module docstring) and holds at least ``samples``
    draws after burn-in; raise :class:`SolverError` with the diagnostics if ``max_steps`` come first.

    Parameters
    ----------
    record : StepRecord
        The record.
    stiffness : float
        The spring (1/m).
    evolution : str
        aging or slip.
    two_state : bool
        A second state variable.
    priors : dict, optional
        Parameter -> :class:`Prior`.
    samples : int
        Draws after burn-in.
    walkers : int, optional
        Ensemble walkers.
    seed : int
        The seed.
    max_steps : int
        The step budget.
    rtol : float
        The integrator's tolerance.
    workers : int
        Processes.
    initial_fit : RateStateFit, optional
        Where the walkers start.
    stiffness_free : bool
        Sample the machine stiffness k too (prior: log-normal about ``stiffness``, sd of ln k = ln 2, unless
        ``priors`` sets one).
    trend : bool
        Sample a linear trend c in the load point's displacement too (friction per metre; prior uniform within
        +-:data:`faultslip.lab.rate_state_fit.TREND_LIMIT`), as :func:`fit_velocity_steps` fits it.

    Returns
    -------
    Posterior
        Draws of the parameters (SI), the diagnostics and ``report()``.
    """
    if not 100 <= samples <= 1_000_000:
        raise InputError(f"the number of posterior draws must be from 100 to 1e6, got {samples}")
    if not 100 <= max_steps <= 10_000_000:
        raise InputError(f"the chain's longest length must be from 100 to 1e7 steps, got {max_steps}")
    names = (["mu0", "a", "b", "critical_slip"] + (["b2", "critical_slip2"] if two_state else [])
             + (["stiffness"] if stiffness_free else []) + (["trend"] if trend else []))
    chosen = dict(DEFAULT_PRIORS, stiffness=Prior("lognormal", stiffness, STIFFNESS_SPREAD),
                  trend=Prior("uniform", -TREND_LIMIT, TREND_LIMIT))
    if "stiffness" in (priors or {}) and not stiffness_free:
        raise InputError("a prior on the stiffness needs the stiffness free (--stiffness-free)")
    if "trend" in (priors or {}) and not trend:
        raise InputError("a prior on the trend needs the trend fitted (--detrend fitted)")
    for name, prior in (priors or {}).items():
        if name not in chosen:
            raise InputError(f"a prior is set on one of {', '.join(DEFAULT_PRIORS)}, got {name!r}")
        chosen[name] = prior if isinstance(prior, Prior) else Prior(*prior)
    chosen = {name: chosen[name] for name in names}
    walkers = walkers or max(16, 4 * len(names))
    if walkers < 2 * len(names) or walkers % 2:
        raise InputError(f"the ensemble needs an even number of walkers, at least {2 * len(names)}, got {walkers}")
    started = clock.perf_counter()
    fit = initial_fit or fit_velocity_steps(record, stiffness, evolution=evolution, two_state=two_state,
                                            stiffness_free=stiffness_free, trend=trend)
    if stiffness_free and "stiffness" not in fit.parameters:
        raise InputError("the posterior's starting fit must have the stiffness free too")
    if trend and "trend" not in fit.parameters:
        raise InputError("the posterior's starting fit must fit the trend too")
    reference_speed = fit.law.reference_speed
    log_posterior = _LogPosterior(record, stiffness, names, chosen, reference_speed, evolution, rtol)
    centre = np.array([math.log(fit.parameters[n]) if n in LOG_SAMPLED else fit.parameters[n] for n in names])
    spread = np.array([fit.standard_errors[n] / fit.parameters[n] if n in LOG_SAMPLED else fit.standard_errors[n]
                       for n in names])
    spread = np.where(np.isfinite(spread) & (spread > 0), spread, 1e-3 * np.maximum(np.abs(centre), 1e-6))
    rng = np.random.default_rng(seed)
    start, tries = [], 0
    timing = clock.process_time()
    while len(start) < walkers:  # a small ball around the fit, inside the priors
        trial = centre + 0.1 * spread * rng.standard_normal(len(names))
        tries += 1
        if math.isfinite(log_posterior(trial)[0]):
            start.append(trial)
        elif not start and tries >= 100:
            raise SolverError("no start near the least-squares fit has a finite posterior: the priors exclude it; "
                              "widen them")
    evaluation = (clock.process_time() - timing) / max(tries, 1)
    report = reporter(progress, "posterior", "step")
    if report is not None:  # its expected time first: a guess, revised as the autocorrelation time is measured
        guess = max(TAU_FACTOR * TAU_GUESS, 3 * TAU_GUESS + math.ceil(samples / walkers))
        expected = guess * walkers * evaluation / max(workers, 1)
        announce(report, f"sampling the posterior: about {duration(expected)} "
                         f"({walkers} walkers, about {guess} steps at {duration(evaluation)} a likelihood"
                         f"{'' if compiled_kernel_available() or two_state else ', on LSODA without numba'}); the "
                         "total is revised as the chain's autocorrelation time is measured", expected)
    pool = _Pool(log_posterior, workers) if workers > 1 else None
    try:
        sampler = emcee.EnsembleSampler(walkers, len(names), log_posterior, pool=pool,
                                        moves=[(emcee.moves.DEMove(), 0.8), (emcee.moves.DESnookerMove(), 0.2)],
                                        blobs_dtype=[("ssr", float)])
        sampler.random_state = np.random.RandomState(seed).get_state()  # emcee's own generator: reproducible
        state, previous, diagnostics = np.array(start), None, {}
        while True:
            state = sampler.run_mcmc(state, BLOCK, progress=False)
            length = sampler.iteration
            tau = sampler.get_autocorr_time(tol=0)
            longest = float(np.max(tau))
            burn = int(math.ceil(3 * longest))
            thin = 1  # every draw after burn-in is kept; their effective number is reported beside
            kept = length - burn
            stable = previous is not None and bool(np.all(np.abs(tau - previous) / tau < TAU_STABILITY))
            previous = tau
            if kept > 10:
                chain = sampler.get_chain(discard=burn)
                r_hat = _split_r_hat(chain)
                effective = walkers * kept / tau
            else:
                r_hat, effective = np.full(len(names), np.inf), np.zeros(len(names))
            diagnostics = {"tau": tau, "r_hat": r_hat, "effective": effective, "length": length}
            enough = walkers * kept >= samples
            if report is not None:
                needed = max(length + BLOCK, math.ceil(TAU_FACTOR * longest), burn + math.ceil(samples / walkers))
                report(length, min(int(math.ceil(needed / BLOCK) * BLOCK), max_steps))
            if (length > TAU_FACTOR * longest and stable and np.all(r_hat < MAX_R_HAT)
                    and np.all(effective >= MIN_EFFECTIVE) and enough):
                break
            if length >= max_steps:
                worst = names[int(np.argmax(tau))]
                raise SolverError(
                    f"the posterior did not converge in {length} steps of {walkers} walkers: the autocorrelation "
                    f"time of {worst} is {longest:.0f} steps (the chain must exceed {TAU_FACTOR} of them"
                    f"{', and its estimate is still moving' if not stable else ''}), R-hat up to "
                    f"{float(np.max(r_hat)):.3f} (needs < {MAX_R_HAT}), effective samples down to "
                    f"{float(np.min(effective)):.0f} (needs {MIN_EFFECTIVE}); raise the step limit, narrow the "
                    "priors, or fit fewer parameters (no posterior is reported)")
    finally:
        if pool is not None:
            pool.terminate()
        if report is not None and hasattr(report, "close"):
            report.close()
    notes = correlation_notes(fit.residuals)  # the likelihood treats the samples as independent too
    if two_state or not compiled_kernel_available():
        notes.append("the likelihood ran on LSODA" + (" (a two-state law)" if two_state else
                     ": numba is not installed (pip install 'faultslip[fast]' makes it about 15 times faster)"))
    draws = sampler.get_chain(discard=burn, thin=thin, flat=True)
    blobs = sampler.get_blobs(discard=burn, thin=thin, flat=True)
    natural = np.column_stack([np.exp(draws[:, i]) if n in LOG_SAMPLED else draws[:, i] for i, n in enumerate(names)])
    tau, r_hat, effective = diagnostics["tau"], diagnostics["r_hat"], diagnostics["effective"]
    return Posterior(
        names=names, samples=natural, noise=np.sqrt(np.asarray(blobs["ssr"], dtype=float) / record.time.size),
        priors=chosen, autocorrelation_time={n: float(t) for n, t in zip(names, tau)},
        effective_sample_size={n: float(e) for n, e in zip(names, effective)},
        r_hat={n: float(r) for n, r in zip(names, r_hat)}, acceptance=float(np.mean(sampler.acceptance_fraction)),
        walkers=walkers, steps=int(sampler.iteration), burn=burn, thin=thin,
        evaluations=int(sampler.iteration) * walkers, seconds=clock.perf_counter() - started,
        reference_speed=reference_speed, evolution=evolution, stiffness=stiffness, fit=fit, seed=seed,
        notes=notes + [f"converged: chain of {sampler.iteration} steps > {TAU_FACTOR} x the longest autocorrelation time "
               f"({float(np.max(tau)):.0f}), R-hat <= {float(np.max(r_hat)):.4f}, effective samples >= "
               f"{float(np.min(effective)):.0f}"])
