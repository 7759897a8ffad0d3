"""How often the printed 95 % ranges of a renewal fit hold the truth (issue 42): synthetic catalogs of 12 events
(11 intervals) from each model at several aperiodicities, each fitted as ``faultslip catalog`` fits one; the
generalized pivotal ranges against the parametric bootstrap's percentiles they replaced.

    python benchmarks/renewal_coverage.py [--catalogs 2000] [--events 12]

Writes benchmarks/results/renewal_coverage.json and the table in docs/catalogs.md (between its table markers).
"""

from __future__ import annotations

import argparse
import json
import re
from pathlib import Path

import numpy as np

from faultslip.fault import recurrence
from faultslip.intervals import percentile_interval
from provenance import stamp  # noqa: E402  (one stamp for every results file)

ROOT = Path(__file__).resolve().parent.parent
APERIODICITIES = (0.3, 0.5, 0.8)
TRUE_MEAN = 100.0


def _bootstrap(model, values, count, rng):
    """The percentile parametric bootstrap the pivots replaced: draw from the fitted model, refit."""
    mean, aperiodicity = recurrence.fit_parameters(model, values)
    law = recurrence.distribution(model, float(mean), float(aperiodicity))
    samples = law.rvs(size=(count, values.size), random_state=rng)
    means, aperiodicities = recurrence.fit_parameters(model, samples)
    return means, aperiodicities


def coverage(model, aperiodicity, catalogs, events, draws, seed):
    rng = np.random.default_rng(seed)
    law = recurrence.distribution(model, TRUE_MEAN, aperiodicity)
    held = {"pivotal": [0, 0], "bootstrap": [0, 0]}
    for _ in range(catalogs):
        values = law.rvs(size=events - 1, random_state=rng)
        mean, spread = (float(v) for v in recurrence.fit_parameters(model, values))
        for name, draw in (("pivotal", recurrence.pivotal_draws), ("bootstrap", _bootstrap)):
            means, aperiodicities = draw(model, values, draws, rng)
            low, high, _ = percentile_interval(means, mean)
            held[name][0] += low <= TRUE_MEAN <= high
            low, high, _ = percentile_interval(aperiodicities, spread)
            held[name][1] += low <= aperiodicity <= high
    return {name: {"mean": hits[0] / catalogs, "aperiodicity": hits[1] / catalogs} for name, hits in held.items()}


def table(rows) -> str:
    lines = ["| model | aperiodicity | mean: pivotal | mean: bootstrap | aperiodicity: pivotal | aperiodicity: bootstrap |",
             "| --- | --- | --- | --- | --- | --- |"]
    for row in rows:
        c = row["coverage"]
        lines.append(f"| {row['model']} | {row['aperiodicity']:g} | **{100 * c['pivotal']['mean']:.1f} %** | "
                     f"{100 * c['bootstrap']['mean']:.1f} % | **{100 * c['pivotal']['aperiodicity']:.1f} %** | "
                     f"{100 * c['bootstrap']['aperiodicity']:.1f} % |")
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--catalogs", type=int, default=2000)
    parser.add_argument("--events", type=int, default=12)
    parser.add_argument("--draws", type=int, default=1000)
    args = parser.parse_args(argv)
    rows = []
    for index, model in enumerate(recurrence.MODELS):
        for k, aperiodicity in enumerate(APERIODICITIES):
            result = coverage(model, aperiodicity, args.catalogs, args.events, args.draws, seed=100 * index + k)
            rows.append({"model": model, "aperiodicity": aperiodicity, "coverage": result})
            print(model, aperiodicity, json.dumps(result), flush=True)
    out = ROOT / "benchmarks" / "results" / "renewal_coverage.json"
    out.write_text(json.dumps({**stamp(), "catalogs": args.catalogs, "events": args.events, "draws": args.draws,
                               "rows": rows}, indent=2) + "\n")
    docs = ROOT / "docs" / "catalogs.md"
    text = docs.read_text(encoding="utf-8")
    block = (f"<!-- table:renewal_coverage -->\n{table(rows)}\n\n{args.catalogs} catalogs of {args.events} events "
             f"per row, {args.draws} draws each (benchmarks/renewal_coverage.py).\n<!-- /table:renewal_coverage -->")
    text = re.sub(r"<!-- table:renewal_coverage -->.*?<!-- /table:renewal_coverage -->", lambda _: block, text,
                  flags=re.S)
    docs.write_text(text, encoding="utf-8")
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
