"""The sweep engine before and after a change, interleaved on one machine: the docs' sweep rows (engine against
numpy, the floor, the second core) measured with each source tree's own code in alternating processes, so that
load and machine state fall on both alike.

    python benchmarks/sweep_before_after.py OLD_TREE NEW_TREE [--rounds 3]

OLD_TREE is a checkout of the commit before (``git worktree add /tmp/oldtree REV``). Prints, per figure, the
median of the rounds for each tree and the change; writes benchmarks/results/sweep_before_after.json.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

from provenance import stamp  # noqa: E402  (one stamp for every results file)

ROOT = Path(__file__).resolve().parent.parent
PROBE = ("import json, sys; sys.path.insert(0, 'benchmarks'); import sweep_scale as s; "
         "engine = [s.engine(c, 15) for c in (1e6, 1e7)]; floor = s.floor(1e7); "
         "print(json.dumps({'engine_1e6': engine[0]['fraction_of_numpy'], 'engine_1e7': engine[1]['fraction_of_numpy'], "
         "'ratio_to_floor': floor['ratio_to_floor'], 'second_worker_speedup': floor['second_worker_speedup'], "
         "'sweep_s': floor['sweep_s']['default (2 workers)'], 'one_cell_s': floor['sweep_s']['one cell']}))")


def measure(tree: Path) -> dict:
    env = dict(os.environ, PYTHONPATH=str(tree))
    done = subprocess.run([sys.executable, "-c", PROBE], cwd=tree, env=env, capture_output=True, text=True, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("old", type=Path)
    parser.add_argument("new", type=Path)
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args(argv)
    rows = {"old": [], "new": []}
    for _ in range(args.rounds):  # interleaved: old, new, old, new, ...
        for label, tree in (("old", args.old), ("new", args.new)):
            rows[label].append(measure(tree.resolve()))
            print(label, rows[label][-1], flush=True)
    summary = {}
    for key in rows["old"][0]:
        old = statistics.median(r[key] for r in rows["old"])
        new = statistics.median(r[key] for r in rows["new"])
        summary[key] = {"old": old, "new": new, "change": new / old - 1}
        print(f"{key:24s} old {old:.4g}  new {new:.4g}  change {100 * (new / old - 1):+.1f} %")
    out = ROOT / "benchmarks" / "results" / "sweep_before_after.json"
    out.write_text(json.dumps({**stamp(), "rounds": rows, "median": summary}, indent=2) + "\n")


if __name__ == "__main__":
    main()
