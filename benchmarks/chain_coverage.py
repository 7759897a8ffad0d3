"""Set and check the spring-block chain's declared range of its mean system-size interval (docs/spring_chain.md).

    python benchmarks/chain_coverage.py            # ~8 min on 2 cores
    python benchmarks/chain_coverage.py --quick    # 8 chains per draw

Chains are drawn at random about configs/spring_chain.toml: 8 to 80 blocks, threshold spread 0.1 to 0.8, k_c / k_p
2 to 32 and the damping ratio 0.02 to 0.5 (both log-uniform), and the thresholds' own seed. Each is run twice from
the scene's start: for the run a user makes (its events) and thirty (or twelve) times longer. The long run's mean
interval, its first tenth left out, stands for the truth. For each short run with at least
``MIN_SYSTEM_INTERVALS`` intervals, z = |truth / mean - 1| over its half-width at factor 1 is how much the
half-width must grow to hold the truth; the shipped ``RANGE_FACTOR`` is the 95th percentile of z over the
calibration draws, rounded up to two figures. The held-out draws, one of the same length and one of 500 events,
are then measured once against it.

Writes benchmarks/results/chain_coverage.json (benchmarks/readme.py renders docs/spring_chain.md's table).
"""

from __future__ import annotations

import argparse
import math
import sys
import tomllib
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from faultslip.models.spring_chain import family  # noqa: E402
from faultslip.models.spring_chain.scene import parse_chain_scene  # noqa: E402
from provenance import write_results  # noqa: E402  (one stamp for every results file)

#: (seed, chains, events of the user's run, how many times longer the reference run is)
CALIBRATION = ((11, 60, 200, 30), (12, 60, 200, 30))
HELD_OUT = ((22, 60, 200, 30), (21, 60, 500, 12))
#: the share of the long run's intervals left out as its start
REFERENCE_SPIN_UP = 0.1
COVERAGE = 0.95


def draw(seed: int, count: int) -> list[dict]:
    """``count`` random chains' parameters (see the module)."""
    rng = np.random.default_rng(seed)
    chains = []
    for _ in range(count):
        chains.append({"blocks": int(rng.integers(8, 81)), "threshold_spread": float(rng.uniform(0.1, 0.8)),
                       "coupling_ratio": float(10 ** rng.uniform(0.3, 1.5)),
                       "damping_ratio": float(10 ** rng.uniform(-1.7, -0.3)), "seed": int(rng.integers(1, 10 ** 6))})
    return chains


def scene(parameters: dict):
    """configs/spring_chain.toml with ``parameters``, as a ChainScene."""
    with open(ROOT / "configs" / "spring_chain.toml", "rb") as handle:
        document = tomllib.load(handle)
    chain = document["chain"]
    leaf = float(chain["leaf_stiffness"].split()[0])  # kN/m
    chain.update({"blocks": parameters["blocks"], "threshold_spread": parameters["threshold_spread"],
                  "coupling_stiffness": f"{leaf * parameters['coupling_ratio']!r} kN/m",
                  "damping_ratio": parameters["damping_ratio"], "seed": parameters["seed"]})
    return parse_chain_scene(document, "chain_coverage")


def measure(job) -> dict:
    """One chain: its short run's mean interval, intervals and half-width at factor 1, and the long run's mean."""
    parameters, events, longer = job
    loaded = scene(parameters)
    row = dict(parameters, events=events)
    for label, count in (("short", events), ("long", events * longer)):
        _, run, _, _ = family._run(loaded, count)
        row[label] = np.diff(family.system_event_times(run, loaded.system_size))
    short, long = row.pop("short"), row.pop("long")
    reference = long[int(REFERENCE_SPIN_UP * long.size):]
    row.update(intervals=int(short.size), reference_intervals=int(reference.size),
               reference=float(reference.mean()) if reference.size else math.nan,
               mean=float(short.mean()) if short.size else math.nan,
               unit_half_width=family.recurrence_half_width(short, factor=1.0),
               independent_half_width=independent_half_width(short))
    declared = math.isfinite(row["unit_half_width"]) and row["reference_intervals"] >= 2
    off = abs(row["reference"] / row["mean"] - 1) if declared else math.nan
    row["z"] = off / row["unit_half_width"] if declared else math.nan
    row["independent_held"] = bool(off <= row["independent_half_width"]) if declared else None
    return row


def independent_half_width(intervals) -> float:
    """The half-width the chain declared before: Student's t over the intervals taken as independent."""
    from scipy.stats import t as student

    if intervals.size < 2:
        return math.nan
    return float(student.ppf(0.975, intervals.size - 1) * intervals.std(ddof=1)
                 / (math.sqrt(intervals.size) * intervals.mean()))


def run_draws(draws, quick: bool) -> list[dict]:
    jobs = [(parameters, events, longer) for seed, count, events, longer in draws
            for parameters in draw(seed, 8 if quick else count)]
    seeds = [seed for seed, count, _, _ in draws for _ in range(8 if quick else count)]
    with ProcessPoolExecutor(2) as pool:
        rows = list(pool.map(measure, jobs))
    for seed, row in zip(seeds, rows):
        row["draw"] = seed
    return rows


def factor_from(rows) -> float:
    """The 95th percentile of z over the rows that declare a range, rounded up to two significant figures."""
    z = np.array([row["z"] for row in rows if math.isfinite(row["z"])])
    quantile = float(np.quantile(z, COVERAGE))
    digits = 1 - math.floor(math.log10(quantile))
    return math.ceil(quantile * 10 ** digits) / 10 ** digits


def summary(rows, factor: float) -> dict:
    """Per draw: chains, those declaring a range, how many hold the reference at ``factor``, at factor 1 (the
    correlated half-width alone) and by the independent Student's t (the half-width before)."""
    out = {}
    for seed in sorted({row["draw"] for row in rows}):
        part = [row for row in rows if row["draw"] == seed]
        declared = [row for row in part if math.isfinite(row["z"])]
        out[str(seed)] = {"chains": len(part), "events": part[0]["events"], "declared": len(declared),
                          "held": sum(row["z"] <= factor for row in declared),
                          "held_unit": sum(row["z"] <= 1.0 for row in declared),
                          "held_independent": sum(bool(row["independent_held"]) for row in declared),
                          "median_half_width": float(np.median([factor * row["unit_half_width"] for row in declared]))
                          if declared else math.nan}
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="8 chains per draw")
    args = parser.parse_args(argv)
    calibration = run_draws(CALIBRATION, args.quick)
    fitted = factor_from(calibration)
    held_out = run_draws(HELD_OUT, args.quick)
    document = {"fitted_factor": fitted, "shipped_factor": family.RANGE_FACTOR, "coverage": COVERAGE,
                "min_system_intervals": family.MIN_SYSTEM_INTERVALS, "reference_spin_up": REFERENCE_SPIN_UP,
                "calibration_draws": [list(d) for d in CALIBRATION], "held_out_draws": [list(d) for d in HELD_OUT],
                "calibration": summary(calibration, family.RANGE_FACTOR),
                "held_out": summary(held_out, family.RANGE_FACTOR), "quick": bool(args.quick),
                "rows": {"calibration": calibration, "held_out": held_out}}
    write_results("chain_coverage.json", document)
    print(f"fitted factor {fitted:g} (shipped {family.RANGE_FACTOR:g})")
    for name in ("calibration", "held_out"):
        for seed, found in document[name].items():
            print(f"{name} draw {seed} ({found['events']} events): {found['held']} of {found['declared']} ranges hold "
                  f"(factor 1: {found['held_unit']}); {found['chains'] - found['declared']} declare none")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
