"""The critical loading rate above which stick-slip stops (seed 003 Appendix I).

Exact condition
---------------
Stick-slip stops where the slip trajectory only just touches x' = V again: the first velocity
maximum after break-away equals V (tangency: x' = V, x'' = 0; seed Fig. 2-8b). In the
dimensionless form of :mod:`faultslip.dynamics.spring_slider.exact_cycle` this is a condition on
:math:`\\epsilon = \\dot\\theta/(\\omega_n(\\mu_s-\\mu_m))` alone, :math:`\\epsilon = \\epsilon_c(\\zeta)`,
found by root-finding on the analytic velocity maximum. With the rate law it becomes

.. math:: b\\,\\dot\\theta_c^{d+1} + \\frac{\\dot\\theta_c}{\\mu_{so}-\\mu_m} - \\omega_n\\epsilon_c(\\zeta) = 0,

the same algebraic form as the seed's eq. I-22 with :math:`Z = \\omega_n\\epsilon_c(\\zeta)`.
For light damping :math:`\\epsilon_c \\approx 1/\\sqrt{4\\pi\\zeta}`: more damping, lower critical rate.
Without damping (:math:`\\zeta \\le 0`) the velocity always returns and there is no critical rate.

The seed's approximation
------------------------
Eq. I-22 with Z of eq. I-21, P = omega_d (C + W beta)/K and R of eq. I-15 (the + root; the
- root gives Z < 0 for every damping ratio here), implemented as printed in
:func:`seed_critical_loading_rate`. Its eq. I-9a drops a factor lambda in front of
V_c/omega_d (it should read A(1 + lambda^2) + lambda V_c/omega_d): the exact tangency satisfies
the corrected I-9a, I-7a and I-10a to round-off but not I-9a as printed, nor the quadratic I-14
built on it. The resulting Z grows like zeta instead of falling like zeta^(-1/2), so the
seed's critical rate *rises* with damping. See docs/critical_rate.md.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

from faultslip.constants import STANDARD_GRAVITY
import numpy as np

from faultslip.dynamics.spring_slider.exact_cycle import _Oscillator, _require_linear_rate_system, slip_cycle
from faultslip.errors import InputError
from faultslip.io.report import Report
from faultslip.friction.materials import get_preset
from faultslip.datasets import ToXarray


def _velocity_overshoot(zeta, eps):
    """First velocity maximum after break-away minus V, in units of omega_n L."""
    osc = _Oscillator(zeta, 1.0 - 2.0 * zeta * eps, eps)
    s_max = osc.first_zero("a") + np.pi / osc.omega
    return osc("v", s_max) - eps


def critical_dimensionless_rate(damping_ratio, iterations=200):
    """:math:`\\epsilon_c(\\zeta)`: the tangency value of :math:`\\dot\\theta/(\\omega_n(\\mu_s-\\mu_m))`.

    Vectorised bisection in :math:`\\log\\epsilon` on the analytic first velocity maximum
    (a single sign change for ``0 < zeta < 1``), to round-off. Returns ``inf`` for
    ``zeta <= 0`` (no critical rate) and NaN for ``zeta >= 1``.
    """
    zeta = np.asarray(damping_ratio, dtype=float)
    out = np.full(zeta.shape, np.nan)
    out[zeta <= 0] = np.inf
    work = (zeta > 0) & (zeta < 1)
    if work.any():
        z = zeta[work]
        lo = np.full(z.shape, np.log(1e-300))
        hi = np.full(z.shape, np.log(1e300))
        for _ in range(iterations):
            mid = 0.5 * (lo + hi)
            with np.errstate(over="ignore", invalid="ignore"):
                positive = _velocity_overshoot(z, np.exp(mid)) > 0
            lo = np.where(positive, mid, lo)
            hi = np.where(positive, hi, mid)
            if np.all(hi - lo <= 4 * np.finfo(float).eps * np.maximum(np.abs(hi), 1.0)):
                break
        out[work] = np.exp(0.5 * (lo + hi))
    return out if out.ndim else float(out)


def critical_rate_without_dashpot_force(damping_ratio: float, iterations: int = 200) -> float:
    """eps_c as it would be if break-away ignored the dashpot force C V (the slip starting from a unit offset,
    U(0) = 1, as seed 003's Appendix I eq. I-1 has it): bisection in log eps on the exact slip phase's regime.
    Against :func:`critical_dimensionless_rate` it measures what leaving C V out costs
    (docs/seed_discrepancies.md)."""
    low, high = 1e-9, 1e3
    for _ in range(iterations):
        middle = float(np.sqrt(low * high))
        low, high = (low, middle) if int(slip_cycle(damping_ratio, middle, initial_offset=1.0)["regime"]) == 1 \
            else (middle, high)
    return low


@lru_cache(maxsize=4096)
def cached_critical_dimensionless_rate(damping_ratio: float) -> float:
    """:func:`critical_dimensionless_rate` for one damping ratio, memoised (it depends on zeta alone)."""
    return float(critical_dimensionless_rate(float(damping_ratio)))


def solve_rate_law_critical(z_value, mu_so, mu_m, b, d):
    """Solve :math:`b\\theta^{d+1} + \\theta/(\\mu_{so}-\\mu_m) = Z` for :math:`\\theta > 0` (vectorised).

    The left side increases monotonically from 0, so the root is unique. Newton's method in
    :math:`\\ln\\theta` on this convex, increasing function, started from an upper bound,
    converges monotonically. Z <= 0 gives NaN; Z = inf gives inf.
    """
    z_value, mu_so, mu_m, b, d = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (z_value, mu_so, mu_m, b, d)))
    drop = mu_so - mu_m
    result = np.full(z_value.shape, np.nan)
    result[np.isinf(z_value) & (z_value > 0)] = np.inf
    work = np.isfinite(z_value) & (z_value > 0) & (drop > 0)
    if work.any():
        zz, dd, bb, ex = z_value[work], drop[work], b[work], d[work]
        with np.errstate(divide="ignore"):
            bound = np.minimum(zz * dd, np.where(bb > 0, (zz / bb) ** (1.0 / (ex + 1.0)), np.inf))
        y = np.log(bound)
        for _ in range(100):
            rate = np.exp(y)
            g = bb * rate ** (ex + 1.0) + rate / dd - zz
            slope = (ex + 1.0) * bb * rate ** (ex + 1.0) + rate / dd
            step = g / slope
            y = y - step
            if np.all(np.abs(step) < 1e-15):
                break
        result[work] = np.exp(y)
    return result if result.ndim else float(result)


def critical_loading_rate(natural_frequency, damping_ratio, mu_so, mu_m, b, d):
    """Exact critical loading rate :math:`\\dot\\theta_c` in 1/s (vectorised; see module docstring)."""
    eps_c = critical_dimensionless_rate(damping_ratio)
    return solve_rate_law_critical(np.asarray(natural_frequency) * eps_c, mu_so, mu_m, b, d)


def seed_z_parameter(natural_frequency, damping_ratio, normal_load=1.0, stiffness=1.0, kinetic_slope=0.0):
    """Z of seed 003 eq. I-21 as printed, with its P and R (eq. I-15, + root).

    ``damping_ratio`` is the slip phase's total (C + beta W)/(2 sqrt(K M)); the seed's
    P = omega_d (C + W beta)/K = 2 zeta sqrt(1 - zeta^2). Returns NaN where the seed's
    inequality I-16 (a real R) fails.
    """
    zeta = np.asarray(damping_ratio, dtype=float)
    omega_d = natural_frequency * np.sqrt(1.0 - zeta**2)
    lam = zeta / np.sqrt(1.0 - zeta**2)
    p = 2.0 * zeta * np.sqrt(1.0 - zeta**2)
    discriminant = 5 * p**2 * lam**2 - 2 * p * (p + 2) * lam + (5 * p**2 - 4 * p + 4)  # I-16
    with np.errstate(invalid="ignore", divide="ignore"):
        r_plus = (2 - p - 3 * lam * p) + np.sqrt(np.where(discriminant >= 0, discriminant, np.nan))
        inverse = normal_load / stiffness * kinetic_slope + r_plus / (2 * p * (1 + lam**2) * omega_d)
        z_value = 1.0 / inverse
    return z_value


def seed_critical_loading_rate(natural_frequency, damping_ratio, mu_so, mu_m, b, d, normal_load=1.0,
                               stiffness=1.0, kinetic_slope=0.0):
    """The seed's approximation: eq. I-22, :math:`b\\theta^{d+1} + \\theta/(\\mu_{so}-\\mu_m) - Z = 0`.

    Labelled as the seed's approximation: it rests on a slip in eq. I-9a (see module docstring).
    Zero damping gives Z = 0 and so a critical rate of 0, where the exact answer is infinite.
    """
    z_value = seed_z_parameter(natural_frequency, damping_ratio, normal_load, stiffness, kinetic_slope)
    zero = np.asarray(damping_ratio) == 0
    rate = solve_rate_law_critical(np.where(zero, 1.0, z_value), mu_so, mu_m, b, d)
    return np.where(zero, 0.0, rate) if np.ndim(rate) else (0.0 if zero else rate)


@dataclass
class CriticalResult(ToXarray):
    """Exact and seed critical loading rates of one system."""
    #: the units and dimensions of to_xarray() (faultslip.datasets.ToXarray)
    UNITS = {'damping_ratio': '1', 'natural_frequency': 'rad/s', 'critical_dimensionless_rate': '1', 'critical_loading_rate': '1/s', 'critical_platform_speed': 'm/s', 'seed_loading_rate': '1/s', 'seed_platform_speed': 'm/s'}

    system_name: str
    scale: str
    damping_ratio: float
    natural_frequency: float
    critical_dimensionless_rate: float
    critical_loading_rate: float
    critical_platform_speed: float
    seed_loading_rate: float
    seed_platform_speed: float

    def report(self) -> Report:
        r = Report(f"faultslip critical loading rate: {self.system_name}")
        r.add("method", "exact_tangency")
        r.add("damping_ratio", self.damping_ratio, label="damping ratio zeta")
        r.add("natural_frequency", self.natural_frequency, "rad/s", "natural frequency omega_n")
        r.add("critical_dimensionless_rate", self.critical_dimensionless_rate, label="epsilon_c(zeta)")
        r.add("critical_loading_rate", self.critical_loading_rate, "1/s", "critical loading rate theta_c")
        r.add("critical_platform_speed", self.critical_platform_speed, "m/s", "critical platform speed V_c",
              also=("in/s",) if self.scale == "lab" else ("mm/yr",))
        r.add("seed_appendix_I_loading_rate", self.seed_loading_rate, "1/s", "seed eq. I-22 (approximation)")
        r.add("seed_appendix_I_platform_speed", self.seed_platform_speed, "m/s", "seed eq. I-22 platform speed")
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = self.seed_loading_rate / self.critical_loading_rate
        r.add("seed_over_exact", float(ratio), label="seed / exact")
        if self.damping_ratio <= 0:
            r.note("Without damping the velocity always returns to V: stick-slip persists at every loading rate.")
        r.note("The seed's eq. I-22 rests on a slip in its eq. I-9a (a missing factor lambda); "
               "its critical rate rises with damping where the exact one falls. See docs/critical_rate.md.")
        return r


def critical(system) -> CriticalResult:
    """Exact and seed critical loading rates for a :class:`~faultslip.dynamics.spring_slider.slider.SliderSystem`.

    Parameters
    ----------
    system : SliderSystem
        The slider.

    Returns
    -------
    CriticalResult
        The exact critical loading rate theta_c (1/s), the seed's Appendix I value and their ratio, with
        ``report()``.
    """
    _require_linear_rate_system(system, "critical loading rate")
    law = system.static_law
    if not hasattr(law, "mu_so"):
        raise InputError(f"critical loading rate needs the rate law of eq. 2-18; {system.name} has {type(law).__name__}")
    omega_n = system.natural_frequency
    zeta = system.damping_ratio
    exact = float(critical_loading_rate(omega_n, zeta, law.mu_so, system.mu_m, law.b, law.d))
    seed = float(seed_critical_loading_rate(omega_n, (system.dashpot + system.kinetic_slope * system.normal_load)
                                            / (2 * np.sqrt(system.stiffness * system.mass)),
                                            law.mu_so, system.mu_m, law.b, law.d,
                                            system.normal_load, system.stiffness, system.kinetic_slope))
    to_speed = system.normal_load / system.stiffness
    return CriticalResult(
        system_name=system.name,
        scale=system.scale,
        damping_ratio=zeta,
        natural_frequency=omega_n,
        critical_dimensionless_rate=float(critical_dimensionless_rate(zeta)),
        critical_loading_rate=exact,
        critical_platform_speed=exact * to_speed,
        seed_loading_rate=seed,
        seed_platform_speed=seed * to_speed,
    )


#: Presets and damping ratios of the exact-versus-seed comparison (issue: dynamics, §3).
COMPARISON_PRESETS = ("steel_heavy_petrolatum", "glass_dry", "pyrite_dry", "granodiorite_water")
COMPARISON_DAMPING_RATIOS = (0.001, 0.01, 0.05, 0.2, 0.3)


def comparison_dataset(presets=COMPARISON_PRESETS, damping_ratios=COMPARISON_DAMPING_RATIOS):
    """Exact against seed critical loading rates over presets x damping ratios, as an xarray Dataset.

    Each preset runs on its Table I apparatus (W, K, M = W/g) with a dashpot giving the damping
    ratio. Vectorised: one call per method for the whole table.
    """
    import xarray as xr  # heavy: imported where used


    chosen = [get_preset(name) for name in presets]
    zeta = np.asarray(damping_ratios, dtype=float)[None, :]
    mu_so = np.array([p.rate_law.mu_so for p in chosen])[:, None]
    mu_m = np.array([p.rate_law.mu_m for p in chosen])[:, None]
    b = np.array([p.rate_law.b for p in chosen])[:, None]
    d = np.array([p.rate_law.d for p in chosen])[:, None]
    load = np.array([p.normal_load for p in chosen])[:, None]
    stiffness = np.array([p.stiffness for p in chosen])[:, None]
    omega_n = np.sqrt(stiffness / (load / STANDARD_GRAVITY))
    exact = critical_loading_rate(omega_n, zeta, mu_so, mu_m, b, d)
    seed = seed_critical_loading_rate(omega_n, zeta, mu_so, mu_m, b, d)
    dims = ("preset", "damping_ratio")

    def var(data, unit, long_name):
        return (dims, np.broadcast_to(data, exact.shape).astype(float), {"units": unit, "long_name": long_name})

    return xr.Dataset(
        data_vars={
            "critical_loading_rate": var(exact, "1/s", "exact critical loading rate (tangency of the slip trajectory)"),
            "seed_appendix_I_loading_rate": var(seed, "1/s", "seed 003 eq. I-22 as printed (approximation)"),
            "seed_over_exact": var(seed / exact, "1", "seed / exact"),
            "critical_platform_speed": var(exact * load / stiffness, "m/s", "exact critical platform speed"),
            "seed_appendix_I_platform_speed": var(seed * load / stiffness, "m/s", "seed eq. I-22 platform speed"),
            "critical_dimensionless_rate": var(critical_dimensionless_rate(zeta), "1",
                                               "epsilon_c(zeta) = theta_c / (omega_n (mu_s - mu_m))"),
            "natural_frequency": (("preset",), omega_n[:, 0], {"units": "rad/s", "long_name": "omega_n = sqrt(K/M)"}),
        },
        coords={
            "preset": ("preset", np.array([p.name for p in chosen], dtype=object), {"long_name": "Table I preset"}),
            "damping_ratio": ("damping_ratio", zeta[0], {"units": "1", "long_name": "damping ratio zeta of the slip phase"}),
        },
        attrs={
            "title": "Critical loading rate: exact tangency against seed 003 Appendix I eq. I-22",
            "Conventions": "CF-1.8",
            "source": "faultslip critical --table",
            "comment": "Apparatus of seed 003 Table I (W, K, M = W/g); dashpot C = 2 zeta sqrt(K M); beta = 0.",
        },
    )


def comparison_markdown(dataset) -> str:
    """The comparison as a Markdown table, with the trend in damping stated from the numbers."""
    zetas = dataset["damping_ratio"].values
    lines = ["| preset | " + " | ".join(f"zeta = {z:g}" for z in zetas) + " |",
             "| --- | " + " | ".join("---" for _ in zetas) + " |"]
    for preset in dataset["preset"].values:
        row = dataset.sel(preset=preset)
        cells = [f"{e:.4g} / {s:.4g} ({r:.3g})" for e, s, r in zip(
            row["critical_loading_rate"].values, row["seed_appendix_I_loading_rate"].values, row["seed_over_exact"].values)]
        lines.append(f"| {preset} | " + " | ".join(cells) + " |")
    exact_falls = bool(np.all(np.diff(dataset["critical_loading_rate"].values, axis=1) < 0))
    seed_rises = bool(np.all(np.diff(dataset["seed_appendix_I_loading_rate"].values, axis=1) > 0))
    close = np.abs(np.log(dataset["seed_over_exact"].values)) < np.log(1.25)
    agree = sorted({f"{z:g}" for z in zetas[np.any(close, axis=0)]})
    lines += [
        "",
        "Cells: exact / seed theta_c in 1/s (seed / exact).",
        f"Exact theta_c falls as damping rises for every preset: {exact_falls}. "
        f"Seed theta_c rises as damping rises for every preset: {seed_rises}.",
        f"Within 25 % of each other only at zeta = {', '.join(agree) if agree else 'none of these'}.",
    ]
    return "\n".join(lines)
