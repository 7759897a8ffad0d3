"""The rupture rates' cost model: CPU time of a fault system's rate solve against its size.

    python benchmarks/rupture_rate_cost.py [--quick]

The bundled California system (configs/california_fault_system.toml) cut into sections of 5, 3, 2 and 1.5 km
(jump 5 km, turn 60 degrees) and solved on the faultslip branch as a map solves it
(faultslip.studies.rupture_sets: enumeration, magnitudes, rates), and rule sets drawn at random as
benchmarks/rupture_rate_stability.py draws them (seed 11). Each solve is timed in process CPU (its NNLS and
least-norm steps are LAPACK, which may use both cores). The model is

    seconds = branches x (overhead + c x (sections + RATE_BIN_ROWS)^2 x ruptures + e x ruptures)

(faultslip.studies.rupture_sets.RATE_SOLVE_SECONDS; each branch enumerates its ruptures and their magnitudes, e),

since NNLS's active-set loop changes each of its rows' columns a few times and each change is a least-squares
solve of ruptures x rows: the fit takes the rate constant from the cut systems (the median of their
seconds / (rows^2 ruptures), carried to the machine state of the "families" cost group by the reference work,
faultslip.io.machine), the overhead as the 95th percentile of the drawn rule sets' solves, and the enumeration's
per rupture as the median of the cut systems'. Held out of the fit: the system cut into 1.2 km sections and the
WC1994 branch of the 2 km cut. Writes benchmarks/results/rupture_rate_cost.json.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from faultslip.errors import InputError, SolverError  # noqa: E402
from faultslip.io import machine  # noqa: E402
from faultslip.studies import rupture_sets as rs  # noqa: E402
from faultslip.studies.maps import read_map, run_map  # noqa: E402
from provenance import stamp  # noqa: E402
from rupture_rate_stability import SYSTEM, draw  # noqa: E402

OUT = ROOT / "benchmarks" / "results" / "rupture_rate_cost.json"
#: (subsection length m, relation, held out of the fit)
CUTS = ((5e3, "faultslip", False), (3e3, "faultslip", False), (2e3, "faultslip", False),
        (1.5e3, "faultslip", False), (2e3, "WC1994", True), (1.2e3, "faultslip", True))
DRAW_SEED = 11


def timed(spec, dataset, rules, relation) -> dict | None:
    """One rule set's enumeration and solve, in process CPU seconds; None where it is refused."""
    shear_modulus = float(spec.scene.fault().shear_modulus)
    rs._LAST_ENUMERATION.clear()  # each cut's enumeration timed afresh (the WC1994 cut has the 2 km cut's sections)
    start = time.process_time()
    sections = rs.fault_sections(spec, dataset, rules)
    ruptures = rs.enumerate_ruptures(sections, rules)
    magnitude, slip = rs.rupture_magnitudes(sections, ruptures, relation, shear_modulus)
    enumerated = time.process_time()
    try:
        rs.solve_rates(sections, ruptures, magnitude, slip, rules, relation, shear_modulus)
    except (InputError, SolverError):
        return None
    solved = time.process_time()
    return {"relation": relation, "sections": sections.count, "ruptures": len(ruptures),
            "rows": sections.count + rs.RATE_BIN_ROWS, "enumeration_seconds": enumerated - start,
            "solve_seconds": solved - enumerated}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="cuts of 5, 3 and 2 km only, 10 drawn rule sets")
    args = parser.parse_args(argv)
    spec = read_map(SYSTEM)
    dataset = run_map(spec)
    reference_before = machine.probe_seconds()
    cuts = []
    for length, relation, held_out in CUTS:
        if args.quick and length < 2e3:
            continue
        rules = rs.Rules(max_jump=5e3, max_azimuth_change=60.0, subsection_length=length)
        row = timed(spec, dataset, rules, relation)
        row.update(subsection_length=length, held_out=held_out)
        cuts.append(row)
        print(row, flush=True)
    rng = np.random.default_rng(DRAW_SEED)
    drawn = []
    for _ in range(10 if args.quick else 40):
        rules, relation = draw(rng)
        row = timed(spec, dataset, rules, relation)
        if row is not None:
            drawn.append(row)
    reference = 0.5 * (reference_before + machine.probe_seconds())
    # the constants in the machine state of the "families" group, as every family's cost model is
    anchored = machine.references()["families"] / reference
    fitted = [row for row in cuts if not row["held_out"]]
    rate_constant = float(np.median([row["solve_seconds"] / (row["rows"] ** 2 * row["ruptures"])
                                     for row in fitted])) * anchored
    enumeration = float(np.median([row["enumeration_seconds"] / row["ruptures"] for row in fitted])) * anchored
    overhead = float(np.percentile([row["solve_seconds"] for row in drawn], 95)) * anchored
    for row in cuts + drawn:
        model = overhead + rate_constant * row["rows"] ** 2 * row["ruptures"] + enumeration * row["ruptures"]
        row["estimate_over_cpu"] = model / anchored / (row["solve_seconds"] + row["enumeration_seconds"])
    result = {**stamp(), "system": SYSTEM.name, "reference_work_seconds_measured": reference,
              "fit": {"rate_seconds": rate_constant, "overhead_seconds": overhead,
                      "enumeration_seconds": enumeration, "group": "families"},
              "cuts": cuts, "drawn": drawn, "draw_seed": DRAW_SEED, "quick": args.quick}
    OUT.write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")
    print(json.dumps(result["fit"]), f"written to {OUT}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
