"""Coverage of the rate-and-state fit's 95 % intervals on synthetic raw records with a known law (issue 29).

Each case is a raw rig record made by the model (:func:`faultslip.lab.raw_records.synthetic_raw_record`:
aging law a 0.008, b 0.012, D_c 20 µm, mu0 0.62; 1 -> 10 -> 1 µm/s; k = 8000 / m; 5 Hz; friction noise
3e-4), seeded by its number, prepared as a user's record would be (steps detected, no trend), then:

- the least-squares fit with a 100-resample residual bootstrap: its bootstrap 95 % intervals;
- the posterior (emcee until converged, 2,000 draws): its 95 % equal-tailed credible intervals.

The fraction of cases whose interval holds the truth, for a, b and D_c, should be 95 ± 5 %. The test
suite runs a small form of this (tests/capabilities/lab/test_raw_records.py); this runs the full study and draws
docs/figures/fit_coverage.png, with the numbers in benchmarks/results/fit_coverage.json.

    python benchmarks/fit_coverage.py [--cases 200] [--workers 2]     # about 15 minutes on 2 cores
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
from provenance import stamp  # noqa: E402  (one stamp for every results file)

ROOT = Path(__file__).resolve().parent.parent
TRUTH = {"a": 0.008, "b": 0.012, "critical_slip": 20e-6}


def one_case(seed: int) -> dict:
    from faultslip.dynamics.rate_state.slider import LoadHistory
    from faultslip.errors import FaultslipError
    from faultslip.friction.rate_state import RateStateLaw
    from faultslip.lab.posterior import sample_posterior
    from faultslip.lab.rate_state_fit import fit_velocity_steps
    from faultslip.lab.raw_records import prepare_record, synthetic_raw_record

    law = RateStateLaw(a=0.008, b=0.012, critical_slip=20e-6, mu0=0.62, reference_speed=1e-6)
    history = LoadHistory((0.0, 20.0, 40.0, 100.0), (1e-6, 1e-5, 1e-6))
    raw = synthetic_raw_record(law, 2e8, 0.0025, 25e3, history, rate=5.0, friction_noise=3e-4, load_noise=0.0,
                               displacement_noise=5e-9, seed=10_000 + seed)
    prepared = prepare_record(raw, "8e-3 1/um")
    out = {"seed": seed}
    started = time.perf_counter()
    try:
        fit = fit_velocity_steps(prepared.record, prepared.stiffness, bootstrap=100, seed=seed)
        out["bootstrap"] = {name: list(fit.bootstrap_intervals[name]) for name in TRUTH}
        out["covariance"] = {name: list(fit.intervals[name]) for name in TRUTH}
    except FaultslipError as exc:
        out["bootstrap_error"] = str(exc)
        fit = None
    out["bootstrap_seconds"] = time.perf_counter() - started
    started = time.perf_counter()
    try:
        posterior = sample_posterior(prepared.record, prepared.stiffness, samples=2000, seed=seed,
                                     initial_fit=fit)
        out["posterior"] = {name: list(posterior.intervals()[name]) for name in TRUTH}
        out["posterior_steps"] = posterior.steps
    except FaultslipError as exc:
        out["posterior_error"] = str(exc)
    out["posterior_seconds"] = time.perf_counter() - started
    return out


def _coverage(cases, kind, truths=None):
    """Per parameter of ``truths`` (this study's by default): the share of the cases whose ``kind`` interval holds
    the truth, how many cases, and where a perfect 95 % lands 95 times in 100."""
    rows = [case[kind] for case in cases if kind in case]
    result = {}
    for name, truth in (truths or TRUTH).items():
        hits = [low < truth < high for low, high in (row[name] for row in rows)]
        rate = float(np.mean(hits)) if hits else math.nan
        result[name] = {"coverage": rate, "cases": len(hits),
                        "binomial_95": [float(v) for v in _binomial_band(len(hits))]}
    return result


def _binomial_band(n, p=0.95):
    """Where the observed coverage of n cases falls 95 % of the time when the true coverage is p."""
    from scipy.stats import binom

    return binom.ppf(0.025, n, p) / max(n, 1), binom.ppf(0.975, n, p) / max(n, 1)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=200)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--results", default=str(ROOT / "benchmarks" / "results" / "fit_coverage.json"))
    parser.add_argument("--figure", default=str(ROOT / "docs" / "figures" / "fit_coverage.png"))
    parser.add_argument("--replot", action="store_true")
    args = parser.parse_args(argv)
    if args.replot:
        _figure(json.loads(Path(args.results).read_text()), args.figure)
        return 0
    started = time.perf_counter()
    with ProcessPoolExecutor(args.workers) as pool:
        cases = list(pool.map(one_case, range(args.cases)))
    result = {"cases": cases, "coverage": {kind: _coverage(cases, kind) for kind in
                                           ("bootstrap", "covariance", "posterior")},
              "failures": {"bootstrap": sum("bootstrap_error" in c for c in cases),
                           "posterior": sum("posterior_error" in c for c in cases)},
              "wall_time_s": time.perf_counter() - started,
              **stamp()}
    Path(args.results).write_text(json.dumps(result, indent=1) + "\n")
    for kind, rows in result["coverage"].items():
        print(kind, {name: f"{row['coverage']:.3f} of {row['cases']}" for name, row in rows.items()})
    print("failures", result["failures"], f"wall {result['wall_time_s']:.0f} s")
    _figure(result, args.figure)
    return 0


def _figure(result, path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axis = plt.subplots(figsize=(9, 4))
    kinds = ("covariance", "bootstrap", "posterior")
    names = list(TRUTH)
    width = 0.25
    for k, kind in enumerate(kinds):
        rates = [result["coverage"][kind][name]["coverage"] for name in names]
        axis.bar(np.arange(len(names)) + (k - 1) * width, rates, width, label=kind)
    band = result["coverage"]["posterior"][names[0]]["binomial_95"]
    axis.axhspan(*band, color="0.85", zorder=0, label=f"95 % of a true 95 % ({result['coverage']['posterior'][names[0]]['cases']} cases)")
    axis.axhline(0.95, color="k", lw=0.8)
    axis.set_xticks(np.arange(len(names)), ["a", "b", "D_c"])
    axis.set_ylim(0.8, 1.0)
    axis.set_ylabel("fraction of 95 % intervals holding the truth")
    axis.set_title(f"Coverage on synthetic raw records ({result['machine']}, {result['date']})", fontsize=9)
    axis.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    figure.tight_layout()
    figure.savefig(path, dpi=130)


if __name__ == "__main__":
    sys.exit(main())
