"""The machine speed record against one probe: which carries a cost model to the CPU a run takes (faultslip.io.machine).

    python benchmarks/machine_record.py [--pairs 40] [--out benchmarks/results/machine_record.json]

Starts ``--pairs`` pairs of fresh processes, the two of a pair at once (as a pool's two workers), on one record
that starts empty in a temporary folder. Each process does the same work: it estimates a 2-D run of one scene
(configs/fault_2d_small.toml at 62.5 m elements over 2,400 yr, about 5 s of steps) and runs it, and reports its
own probe's reading, the record's median (this process's reading among the kept ones), the cost model's seconds
at the anchored machine and the CPU the run used. So every estimate can be made again, from the same run against
the one CPU time, with a factor taking a weight w of the process's own probe beside the record's median
(:data:`WEIGHTS`): ``import_seconds + anchored_seconds x (median / anchor)^(1 - w) x (probe / anchor)^w``. w = 0 is
the median alone, w = 1 the probe alone (as estimates were made before the record), and faultslip's PROBE_WEIGHT
the weight it ships, set from this benchmark's first run (``probe_weight_fit``, the least squares slope of the runs'
speed on the probe, both over the median, in logs) and tested on a second run that never set it
(``--out benchmarks/results/machine_record_held_out.json``).

The work is the same in every process, so the cost model's own error is one factor common to all; what differs
from process to process is the machine's speed and how well each reading follows it: the spread of estimate over
CPU (its standard deviation in ln, and its range) measures that. The summary reads the processes whose record held
at least :data:`SETTLED_READINGS` readings (a new record starts from the first processes' probes, as the probe
alone does).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))
from faultslip.io.machine import PROBE_WEIGHT  # noqa: E402
from provenance import stamp  # noqa: E402

OUT = ROOT / "benchmarks" / "results" / "machine_record.json"
#: The second run, which PROBE_WEIGHT was tested on after the first had set it (``--out`` this).
HELD_OUT = ROOT / "benchmarks" / "results" / "machine_record_held_out.json"
#: Readings a record holds before its median is read here as the record's (the first pairs fill it).
SETTLED_READINGS = 9
#: The scene's changes from configs/fault_2d_small.toml: a run of a few seconds, long beside its imports.
EDITS = {'element_size = "250 m"': 'element_size = "62.5 m"', 'duration = "600 yr"': 'duration = "2400 yr"'}

#: One process's work: estimate, run, report (run as ``python -c``, in a fresh interpreter).
WORK = """
import json, sys, time
from faultslip import models
from faultslip.io import machine
estimate = models.estimate(sys.argv[1])
with machine.assumed(1.0):
    anchored = models.estimate(sys.argv[1]).modelled_seconds
started = time.process_time()
result = models.run(sys.argv[1])
cpu = time.process_time() - started
speed = machine.speed_reading()
print(json.dumps({"reading": speed["reading"], "median": speed["median"], "readings": speed["readings"],
                  "anchor": machine.references()["fault_2d_step"], "modelled_seconds": estimate.modelled_seconds,
                  "anchored_seconds": anchored,
                  "import_seconds": estimate.import_seconds, "estimated_seconds": estimate.seconds,
                  "cpu_time": cpu, "steps": int(result.values["steps"])}))
"""


def scene_text() -> str:
    text = (ROOT / "configs" / "fault_2d_small.toml").read_text(encoding="utf-8")
    for old, new in EDITS.items():
        assert text.count(old) == 1, old  # the example changed: choose the edits again
        text = text.replace(old, new)
    return text


#: How much of each process's own probe an estimate takes beside the record's median: ln factor = (1 - w) ln median
#: + w ln probe. 0 is the record's median alone, 1 the probe alone (as before the record), and the weight faultslip
#: ships (faultslip.io.machine.PROBE_WEIGHT, set from the first run's probe_weight_fit).
WEIGHTS = {"with_record": 0.0, "blended": PROBE_WEIGHT, "probe_alone": 1.0}


def anchored_seconds(row: dict) -> float:
    """The cost model's seconds at the anchored machine (factor 1); rows written before they kept it carry the
    estimate made with the record's median alone."""
    if "anchored_seconds" in row:
        return row["anchored_seconds"]
    return (row["estimated_seconds"] - row["import_seconds"]) * row["anchor"] / row["median"]


def ratio(row: dict, weight: float) -> float:
    """One process's estimate over its CPU, the factor taking ``weight`` of its own probe (:data:`WEIGHTS`)."""
    factor = (row["median"] / row["anchor"]) ** (1.0 - weight) * (row["reading"] / row["anchor"]) ** weight
    return (row["import_seconds"] + anchored_seconds(row) * factor) / row["cpu_time"]


def spread(values: list) -> dict:
    logs = [math.log(value) for value in values]
    return {"median": statistics.median(values), "min": min(values), "max": max(values),
            "max_over_min": max(values) / min(values), "sd_ln": statistics.stdev(logs),
            "within_1_25x_of_median": sum(abs(v - statistics.median(logs)) <= math.log(1.25) for v in logs),
            "within_2x": sum(0.5 <= value <= 2.0 for value in values)}


def summarise(rows: list) -> dict:
    settled = [row for row in rows if row["readings"] >= SETTLED_READINGS]
    speeds = [(row["cpu_time"] - row["import_seconds"]) / anchored_seconds(row) for row in settled]
    logs = [(math.log(row["reading"] / row["median"]), math.log(speed * row["anchor"] / row["median"]))
            for row, speed in zip(settled, speeds)]
    probe_mean = statistics.fmean(x for x, _ in logs)
    run_mean = statistics.fmean(y for _, y in logs)
    covariance = sum((x - probe_mean) * (y - run_mean) for x, y in logs)
    return {"processes": len(settled), "settled_readings": SETTLED_READINGS,
            **{key: spread([ratio(row, weight) for row in settled]) for key, weight in WEIGHTS.items()},
            # the machine's speed each process saw: its run's CPU over the cost model's at the anchored machine
            "run_speed": spread(speeds),
            "probe_speed": spread([row["reading"] / row["anchor"] for row in settled]),
            # least squares of the run's speed over the record's median on the probe's: the weight a process's own
            # probe earns beside the median (0: it says nothing of the run; 1: it says everything)
            "probe_weight_fit": covariance / sum((x - probe_mean) ** 2 for x, _ in logs)}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--pairs", type=int, default=40)
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args(argv)
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        scene = Path(folder) / "scene.toml"
        scene.write_text(scene_text(), encoding="utf-8")
        env = {key: value for key, value in os.environ.items() if key != "FAULTSLIP_MACHINE_FACTOR"}
        env["FAULTSLIP_MACHINE_RECORD"] = str(Path(folder) / "machine_speed.json")
        env["PYTHONWARNINGS"] = "ignore"
        for pair in range(args.pairs):
            started = [subprocess.Popen([sys.executable, "-c", WORK, str(scene)], env=env, stdout=subprocess.PIPE,
                                        text=True) for _ in range(2)]
            for worker, process in enumerate(started):
                out, _ = process.communicate()
                if process.returncode:
                    raise SystemExit(f"pair {pair}: a process failed (exit {process.returncode})")
                row = json.loads(out.strip().splitlines()[-1]) | {"pair": pair, "worker": worker}
                rows.append(row)
                print(f"pair {pair} worker {worker}: probe {row['reading'] / row['anchor']:.2f}, record "
                      f"{row['median'] / row['anchor']:.2f} over {row['readings']}; estimate / CPU "
                      f"{ratio(row, 0.0):.2f} (probe alone {ratio(row, 1.0):.2f})", flush=True)
    summary = summarise(rows)
    args.out.write_text(json.dumps({**stamp(), "scene_edits": EDITS, "summary": summary, "rows": rows}, indent=1)
                        + "\n", encoding="utf-8")
    for key in (*WEIGHTS, "run_speed", "probe_speed"):
        line = summary[key]
        print(f"{key}: median {line['median']:.2f}, {line['min']:.2f} to {line['max']:.2f}, sd in ln "
              f"{line['sd_ln']:.3f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
