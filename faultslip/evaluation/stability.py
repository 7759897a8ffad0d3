"""Stability map: where each method fails, over loading rate, damping and time-scale separation.

Axes: loading rate over the critical rate r = theta/theta_c (1e-4 to 10), damping ratio zeta
(-0.05 to 0.5), and time-scale separation S = stick duration / slip duration (1 to 1e10, the
lab-to-fault range). In the dimensionless slip dynamics these are not independent: S is about
2/(pi eps) with eps = theta/(omega_n (mu_s - mu_m)). Each cell is therefore realised as a genuine
rate-law slider (seed 003 eq. 2-18): S fixes eps through the closed form's own stick/slip ratio,
S = (1 + e^(-lambda pi)) sqrt(1 - zeta^2) / (pi eps), and the rate law's exponent d and
coefficient b are chosen so that theta/theta_c = r. Cells that no rate law with d <= 4 can
produce (e.g. a low rate with little separation) are marked ``unrealisable``. Without damping
(zeta <= 0) there is no critical rate; those rows do not depend on r.

Each method runs a few cycles per cell; outcomes: ok, exception, step-size collapse, budget
exceeded, solver failure, wrong regime (stick-slip where the exact cycle has none, or the
reverse), plus the relative amplitude error.
"""

from __future__ import annotations

import math
import time

import numpy as np

from faultslip.evaluation.bench import STATUS, STATUS_CODE, _classify, parallel_map
from faultslip.errors import FaultslipError
from faultslip.dynamics.spring_slider.critical import cached_critical_dimensionless_rate
from faultslip.dynamics.spring_slider.exact_cycle import exact_cycle
from faultslip.dynamics.spring_slider.slider import SliderSystem
from faultslip.evaluation.bench import run_once
from faultslip.friction.laws import ConstantKinetic, LinearKinetic, RateLaw
import warnings

RATIOS = (1e-4, 1e-3, 1e-2, 0.1, 0.3, 0.6, 0.9, 1.1, 1.5, 3.0, 10.0)
DAMPING_RATIOS = (-0.05, -0.02, 0.0, 0.01, 0.05, 0.1, 0.2, 0.3, 0.5)
SEPARATIONS = (1.0, 1e2, 1e4, 1e6, 1e8, 1e10)
METHODS = ("closed_form", "exact_cycle", "event_driven_RK45", "event_driven_DOP853", "event_driven_Radau",
           "event_driven_LSODA", "regularized_RK45", "regularized_LSODA", "quasi_harmonic_averaging")
UNREALISABLE = 7
STATUS_ALL = {**STATUS, UNREALISABLE: "unrealisable"}
MAX_EXPONENT = 4.0
RTOL = 1e-6
REGULARIZATION = 1e-2  # width w = 0.01 V
DROP, MU_M, OMEGA_N, STIFFNESS, LOAD = 0.1, 0.5, 100.0, 1e6, 1e3


def dimensionless_rate_for_separation(separation, zeta):
    """eps giving the closed form's stick/slip ratio S = (1 + e^(-lambda pi)) sqrt(1 - zeta^2) / (pi eps)."""
    root = math.sqrt(1 - zeta * zeta)
    return (1 + math.exp(-math.pi * zeta / root)) * root / (math.pi * separation)


def grid_system(ratio: float, zeta: float, separation: float):
    """A rate-law slider with theta/theta_c = ratio, damping ratio zeta and separation S; None if unrealisable."""

    eps = dimensionless_rate_for_separation(separation, zeta)
    mass = STIFFNESS / OMEGA_N**2
    if zeta > 0:
        eps_c = cached_critical_dimensionless_rate(zeta)
        q = ratio * eps_c / eps  # required mu_s(r theta_c) - mu_m over mu_s(theta_c) - mu_m
        if (ratio < 1 and q < 1) or (ratio > 1 and q > 1):
            return None
        needed = abs(math.log(q)) / abs(math.log(ratio)) if q != 1 else 0.0
        exponent = max(0.5, 1.5 * needed)
        if exponent > MAX_EXPONENT:
            return None
        scaled = ratio**exponent
        coefficient = (q - 1) / (1 - q * scaled) if ratio < 1 else (1 - q) / (q * scaled - 1)
        theta_c = OMEGA_N * eps_c * DROP / (1 + coefficient)
        b = coefficient / (DROP * theta_c**exponent)
        theta = ratio * theta_c
    else:  # no critical rate: rate-independent static friction at the requested separation
        exponent, b = 1.0, 0.0
        theta = eps * OMEGA_N * DROP
    law = RateLaw(MU_M + DROP, MU_M, b, exponent)
    if zeta >= 0:
        kinetic, dashpot = ConstantKinetic(MU_M), 2 * zeta * math.sqrt(STIFFNESS * mass)
    else:  # negative damping from friction that weakens with sliding speed
        kinetic, dashpot = LinearKinetic(MU_M, 2 * zeta * math.sqrt(STIFFNESS * mass) / LOAD), 0.0
    return SliderSystem(mass=mass, stiffness=STIFFNESS, normal_load=LOAD, platform_speed=theta * LOAD / STIFFNESS,
                        static_law=law, kinetic_law=kinetic, dashpot=dashpot, name=f"grid r={ratio:g} zeta={zeta:g} S={separation:g}")


def _run(system, method, cycles, budget):

    if method.startswith("regularized_"):
        method = f"{method}_w{REGULARIZATION:g}V"
    return run_once(system, method, RTOL, cycles, budget)


def evaluate_cell(system, method: str, cycles: int = 3, budgets=(100_000, 100_000)):
    """(status, relative amplitude error, evaluations) of one method on one grid system."""


    exact = exact_cycle(system)
    budget = budgets[1] if method.startswith("regularized_") else budgets[0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            amplitude, period, events, evaluations, regime = _run(system, method, cycles, budget)
        except (FaultslipError, RuntimeError, ValueError, ArithmeticError) as error:
            return _classify(error), math.nan, -1
    method_sticks = np.size(events) >= min(cycles, 2) and math.isfinite(amplitude) and regime != "steady_sliding"
    exact_sticks = exact.regime != "steady_sliding"
    if method_sticks != exact_sticks:
        return STATUS_CODE["wrong_regime"], math.nan, int(evaluations)
    error = abs(amplitude / exact.amplitude - 1) if exact_sticks else math.nan
    return STATUS_CODE["ok"], error, int(evaluations)


def _row_job(args):
    ratio, zeta, separations, methods, cycles = args
    out = []
    for separation in separations:
        system = grid_system(ratio, zeta, separation)
        for method in methods:
            out.append((UNREALISABLE, math.nan, -1) if system is None else evaluate_cell(system, method, cycles))
    return ratio, zeta, out


def stability_map(ratios=RATIOS, damping_ratios=DAMPING_RATIOS, separations=SEPARATIONS, methods=METHODS,
                  cycles: int = 3, workers: int = 2, progress=None):
    """Evaluate every method on every grid cell; returns an xarray Dataset (ratio, damping_ratio, separation, method)."""
    import xarray as xr  # heavy: imported where used

    started = time.perf_counter()
    jobs = []
    for zeta in damping_ratios:
        # without damping there is no critical rate: one row serves every ratio
        for ratio in (ratios if zeta > 0 else ratios[:1]):
            jobs.append((ratio, zeta, separations, methods, cycles))
    results = {(ratio, zeta): out for ratio, zeta, out in parallel_map(_row_job, jobs, workers, progress)}
    shape = (len(ratios), len(damping_ratios), len(separations), len(methods))
    status = np.full(shape, UNREALISABLE, dtype=np.int8)
    error = np.full(shape, np.nan)
    evaluations = np.full(shape, -1, dtype=np.int64)
    for i, ratio in enumerate(ratios):
        for j, zeta in enumerate(damping_ratios):
            out = results[(ratio, zeta) if zeta > 0 else (ratios[0], zeta)]
            for k in range(len(separations)):
                for m in range(len(methods)):
                    status[i, j, k, m], error[i, j, k, m], evaluations[i, j, k, m] = out[k * len(methods) + m]
    dims = ("ratio", "damping_ratio", "separation", "method")
    return xr.Dataset(
        data_vars={
            "status": (dims, status, {"units": "1", "long_name": "outcome",
                                      "flag_values": np.array(sorted(STATUS_ALL), dtype=np.int8),
                                      "flag_meanings": " ".join(STATUS_ALL[k] for k in sorted(STATUS_ALL))}),
            "amplitude_error": (dims, error, {"units": "1", "long_name": "relative amplitude error against the exact cycle"}),
            "evaluations": (dims, evaluations, {"units": "1", "long_name": "right-hand-side evaluations"}),
        },
        coords={
            "ratio": ("ratio", np.array(ratios), {"units": "1", "long_name": "loading rate / critical loading rate"}),
            "damping_ratio": ("damping_ratio", np.array(damping_ratios), {"units": "1", "long_name": "damping ratio zeta"}),
            "separation": ("separation", np.array(separations), {"units": "1", "long_name": "stick duration / slip duration"}),
            "method": ("method", np.array(methods, dtype=object), {"long_name": "solution method"}),
        },
        attrs={"title": "faultslip stability map", "Conventions": "CF-1.8", "rtol": RTOL,
               "regularization_width_over_V": REGULARIZATION, "cycles": cycles,
               "comment": "zeta <= 0 rows do not depend on the ratio (no critical rate)",
               "total_wall_time_s": time.perf_counter() - started},
    )


def _where(mask) -> str:
    """Where a boolean (ratio, damping_ratio, separation) mask is true, in words."""
    values = mask.values
    ratios, zetas, separations = (mask[name].values for name in ("ratio", "damping_ratio", "separation"))
    damped_ratios = [ratios[i] for i in range(len(ratios)) if values[i][zetas > 0].any()]
    rate = _span(damped_ratios) if damped_ratios else ""
    if values[:, zetas <= 0].any():
        rate = (rate + "; " if rate else "") + "any rate where zeta <= 0"
    zeta_hit = [zetas[j] for j in range(len(zetas)) if values[:, j].any()]
    sep_hit = [separations[k] for k in range(len(separations)) if values[:, :, k].any()]
    return f"theta/theta_c {rate}, zeta {_span(zeta_hit)}, separation {_span(sep_hit)}"


def _span(values, unit=""):
    values = sorted(set(float(v) for v in values))
    if not values:
        return "none"
    if len(values) == 1:
        return f"{values[0]:g}{unit}"
    return f"{values[0]:g} to {values[-1]:g}{unit}"


def failure_text(dataset) -> str:
    """Each method's failure region in words, generated from the map."""
    lines = []
    status = dataset["status"]
    # rows without damping repeat along the ratio axis (no critical rate): count them once
    distinct = (dataset["damping_ratio"] > 0) | (dataset["ratio"] == dataset["ratio"].values[0])
    realisable = (status.isel(method=0) != UNREALISABLE) & distinct
    total = int(realisable.sum())
    for method in dataset["method"].values:
        part = status.sel({"method": method})
        err = dataset["amplitude_error"].sel({"method": method})
        parts = []
        for code, name in STATUS_ALL.items():
            if code in (STATUS_CODE["ok"], UNREALISABLE, STATUS_CODE["not_applicable"]):
                continue
            mask = (part == code) & realisable
            count = int(mask.sum())
            if not count:
                continue
            said = "declined, handing over (outside its domain, said so)" if code == STATUS_CODE["declined"] else name
            parts.append(f"{said.replace('_', ' ')} in {count} of {total} cells ({_where(mask)})")
        ok = (part == STATUS_CODE["ok"]) & realisable
        inaccurate = ok & (err > 1e-3)
        if int(inaccurate.sum()):
            parts.append(f"amplitude error above 1e-3 in {int(inaccurate.sum())} cells ({_where(inaccurate)})")
        accurate = int((ok & ((err <= 1e-6) | err.isnull())).sum())
        summary = "; ".join(parts) if parts else "no failures"
        lines.append(f"- **{method}**: {summary}. Correct regime with amplitude error <= 1e-6 (or correctly no "
                     f"stick-slip) in {accurate} of {total} cells.")
    return "\n".join(lines)


def chart(dataset):
    """One panel per method: worst outcome over zeta > 0 in the (theta/theta_c, separation) plane."""
    import matplotlib.pyplot as plt  # heavy: imported where used
    from matplotlib.colors import ListedColormap  # heavy: imported where used

    methods = list(dataset["method"].values)
    columns = 4
    rows = math.ceil(len(methods) / columns)
    figure, axes = plt.subplots(rows, columns, figsize=(4.2 * columns, 3.6 * rows), constrained_layout=True, squeeze=False)
    zetas = dataset["damping_ratio"].values
    # the worst over zeta > 0 (where a critical rate exists); a grid with none shows its undamped rows
    damped = dataset.sel({"damping_ratio": zetas[zetas > 0] if (zetas > 0).any() else zetas})
    # outcome classes, by severity: ok & accurate, ok but error > 1e-6, declined (outside its domain, said
    # so), wrong regime, budget, other failure; unrealisable cells are shown but never the worst
    colours = ListedColormap(["#2ca02c", "#bcbd22", "#9ecae1", "#d62728", "#9467bd", "#ff7f0e", "#dddddd"])
    labels = ["error <= 1e-6", "error > 1e-6", "declined (outside its domain)", "wrong regime", "budget exceeded",
              "exception / step collapse / solver failure", "unrealisable"]
    unrealisable_class = len(labels) - 1
    for axis, method in zip(axes.ravel(), methods):
        part = damped.sel({"method": method})
        code = part["status"].values
        err = part["amplitude_error"].values
        cls = np.full(code.shape, unrealisable_class)
        cls[(code == 0) & ~(err > 1e-6)] = 0
        cls[(code == 0) & (err > 1e-6)] = 1
        cls[code == STATUS_CODE["declined"]] = 2
        cls[code == STATUS_CODE["wrong_regime"]] = 3
        cls[code == STATUS_CODE["budget_exceeded"]] = 4
        cls[np.isin(code, [STATUS_CODE["exception"], STATUS_CODE["step_size_collapse"], STATUS_CODE["solver_failure"]])] = 5
        worst = np.where(cls == unrealisable_class, -1, cls).max(axis=1)  # worst over zeta, ignoring unrealisable
        worst = np.where(worst < 0, unrealisable_class, worst)
        axis.imshow(worst.T, origin="lower", cmap=colours, vmin=-0.5, vmax=unrealisable_class + 0.5, aspect="auto")
        axis.set_xticks(range(dataset.sizes["ratio"]), [f"{r:g}" for r in dataset["ratio"].values], rotation=60, fontsize=7)
        axis.set_yticks(range(dataset.sizes["separation"]), [f"{s:g}" for s in dataset["separation"].values], fontsize=7)
        axis.axvline(np.searchsorted(dataset["ratio"].values, 1.0) - 0.5, color="k", lw=0.8, ls="--")
        axis.set_title(method, fontsize=9)
        axis.set_xlabel("theta / theta_c")
        axis.set_ylabel("stick / slip duration")
    for axis in axes.ravel()[len(methods):]:
        axis.set_visible(False)
    handles = [plt.Rectangle((0, 0), 1, 1, color=colours(i)) for i in range(len(labels))]
    figure.legend(handles, labels, loc="outside lower center", ncol=4, fontsize=8)
    figure.suptitle(f"Stability map: worst outcome over zeta > 0 (rtol {dataset.attrs['rtol']:g}; dashed: theta_c)")
    return figure
