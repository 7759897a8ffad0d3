"""The six-state asperity run at its own steps against steps bounded to 1/3000 of a natural period (docs/asperity.md).

    python benchmarks/asperity_lsoda_steps.py            # ~4 min on 2 cores
    python benchmarks/asperity_lsoda_steps.py --quick    # 4 runs a draw

asperity_LSODA's events test signs at LSODA's step ends, and the least relative speed of a slip is not searched
(dynamics._graze says why): a stick whose relative speed dips past the platform's and back inside one step would
go unseen, as one did in the quasi-static run at 3.727 mm/s. LSODA's steps follow the kHz normal mode, about 650 a
natural period there. Here each run is repeated with its steps bounded to 1/3000 of a natural period, which no
such dip outlasts, over three draws: seed 004's scene at speeds log-uniform over 1-20 mm/s; the same in the band
2-5 mm/s, where its slips come closest to sticking; and random systems about case 6 (as
asperity_quasistatic_check.py draws them) at 0.95-1.1 of a critical speed. Each runs 3 s at rtol 1e-7 (a sweep's).
Recorded: whether the status and the number of sticks agree, the stick fraction's difference, and how many touches
the step search (dynamics._graze_between_steps) found in each run: the bounded run, the reference, should need none.

Writes benchmarks/results/asperity_lsoda_steps.json.
"""

from __future__ import annotations

import argparse
import math
import sys
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from faultslip.models.asperity import dynamics  # noqa: E402
from faultslip.models.asperity.dynamics import AsperityModel, analyse, simulate  # noqa: E402
from faultslip.models.asperity.scene import load_asperity_scene  # noqa: E402
from probes import found_by  # noqa: E402
from provenance import write_results  # noqa: E402  (one stamp for every results file)

#: the bounded run's steps: at most this fraction of a natural period
FINE_STEPS = 3000
DURATION, RTOL = 3.0, 1e-7
#: (name, seed, runs): the draws
DRAWS = (("scene, 1-20 mm/s", 41, 20), ("scene, 2-5 mm/s", 42, 30), ("random systems near v_cn", 43, 20))


def _model(draw: str, seed: int, index: int) -> AsperityModel:
    rng = np.random.default_rng([seed, index])
    if draw.startswith("scene"):
        low, high = (1e-3, 2e-2) if "1-20" in draw else (2e-3, 5e-3)
        model = load_asperity_scene(ROOT / "configs" / "asperity_seed004.toml")[0]
        return replace(model, platform_speed=float(np.exp(rng.uniform(math.log(low), math.log(high)))))
    model = AsperityModel(natural_frequency=float(10 ** rng.uniform(math.log10(5.0), 2.0)),
                          slope_std=float(rng.uniform(0.05, 0.35)),
                          initial_approach=float(rng.uniform(0.2e-6, 0.45e-6)),
                          contact_length=float(10 ** rng.uniform(math.log10(0.03e-6), math.log10(0.3e-6))),
                          dashpot=float(10 ** rng.uniform(-0.5, 0.7)))
    order = int(rng.integers(1, 4))
    speed = float(model.critical_speeds((order,))[0] * rng.uniform(0.95, 1.1))
    return replace(model, platform_speed=min(speed, 0.9 * model.contact_loss_speed))


def _counted(model, max_step):
    """The run, and how many touches the step search (dynamics._graze_between_steps) found in it."""
    with found_by(dynamics, "_graze_between_steps") as found:
        return simulate(model, DURATION, "asperity_LSODA", RTOL, max_step=max_step), found[0]


def measure(job) -> dict:
    draw, seed, index = job
    model = _model(draw, seed, index)
    (own, own_found), (fine, fine_found) = (_counted(model, step)
                                            for step in (None, 1.0 / (FINE_STEPS * model.natural_frequency)))
    runs = [own, fine]
    row = {"draw": draw, "index": index, "platform_speed": model.platform_speed,
           "natural_frequency": model.natural_frequency, "status": [own.status, fine.status],
           "sticks": [own.sticks, fine.sticks], "touches_found": [own_found, fine_found]}
    if own.status == fine.status == "ok":
        fractions = [analyse(run).stick_fraction for run in runs]
        row.update(stick_fraction=fractions, stick_fraction_difference=abs(fractions[0] - fractions[1]))
    row["agree"] = own.status == fine.status and own.sticks == fine.sticks
    return row


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="4 runs a draw")
    args = parser.parse_args(argv)
    jobs = [(draw, seed, index) for draw, seed, count in DRAWS for index in range(4 if args.quick else count)]
    with ProcessPoolExecutor(2) as pool:
        rows = list(pool.map(measure, jobs))
    document = {"fine_steps_per_period": FINE_STEPS, "duration": DURATION, "rtol": RTOL, "quick": bool(args.quick),
                "runs": len(rows), "agree": sum(row["agree"] for row in rows),
                "sticking": sum(row["sticks"][1] > 0 for row in rows),
                "largest_stick_fraction_difference": max(row.get("stick_fraction_difference", 0.0) for row in rows),
                "touches_found": [sum(row["touches_found"][k] for row in rows) for k in (0, 1)],
                "rows": rows}
    write_results("asperity_lsoda_steps.json", document)
    print(f"{document['agree']} of {len(rows)} runs agree in status and sticks ({document['sticking']} stick); "
          f"largest stick-fraction difference {document['largest_stick_fraction_difference']:.2g}; touches found "
          f"by the search at LSODA's own steps {document['touches_found'][0]}, at the bounded steps "
          f"{document['touches_found'][1]}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
