"""The machine speed record against one probe: which carries a cost model to the CPU a run takes (faultslip.io.machine).

    python benchmarks/machine_record.py [--pairs 30] [--out benchmarks/results/machine_record.json]

Starts ``--pairs`` pairs of fresh processes, the two of a pair at once (as a pool's two workers), on one record
that starts empty in a temporary folder. Each process does the same work: it estimates a 2-D run of one scene
(configs/fault_2d_small.toml at 62.5 m elements over 2,400 yr, about 5 s of steps) and runs it, and reports its
own probe's reading, the record's median that the estimate took (this process's reading among the kept ones),
the estimate and the CPU the run used. So every estimate is read both ways, from the same run against the one
CPU time:

* with the record: the estimate as made, ``import_seconds + modelled_seconds``;
* with the probe alone: ``import_seconds + modelled_seconds x probe / median``, what it was before the record.

The work is the same in every process, so the cost model's own error is one factor common to all; what differs
from process to process is the machine's speed and how well each reading follows it: the spread of estimate over
CPU (its standard deviation in ln, and its range) measures that. The summary reads the processes whose record held
at least :data:`SETTLED_READINGS` readings (a new record starts from the first processes' probes, as the probe
alone does). Writes benchmarks/results/machine_record.json.
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
sys.path.insert(0, str(ROOT / "benchmarks"))
from provenance import stamp  # noqa: E402

OUT = ROOT / "benchmarks" / "results" / "machine_record.json"
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
started = time.process_time()
result = models.run(sys.argv[1])
cpu = time.process_time() - started
speed = machine.speed_reading()
print(json.dumps({"reading": speed["reading"], "median": speed["median"], "readings": speed["readings"],
                  "anchor": machine.references()["fault_2d_step"], "modelled_seconds": estimate.modelled_seconds,
                  "import_seconds": estimate.import_seconds, "estimated_seconds": estimate.seconds,
                  "cpu_time": cpu, "steps": int(result.values["steps"])}))
"""


def scene_text() -> str:
    text = (ROOT / "configs" / "fault_2d_small.toml").read_text(encoding="utf-8")
    for old, new in EDITS.items():
        assert text.count(old) == 1, old  # the example changed: choose the edits again
        text = text.replace(old, new)
    return text


def ratios(row: dict) -> tuple[float, float]:
    """(estimate over CPU with the record, with the probe alone) of one process."""
    alone = row["import_seconds"] + (row["estimated_seconds"] - row["import_seconds"]) * row["reading"] / row["median"]
    return row["estimated_seconds"] / row["cpu_time"], alone / row["cpu_time"]


def spread(values: list) -> dict:
    logs = [math.log(value) for value in values]
    return {"median": statistics.median(values), "min": min(values), "max": max(values),
            "max_over_min": max(values) / min(values), "sd_ln": statistics.stdev(logs),
            "within_1_25x_of_median": sum(abs(v - statistics.median(logs)) <= math.log(1.25) for v in logs),
            "within_2x": sum(0.5 <= value <= 2.0 for value in values)}


def summarise(rows: list) -> dict:
    settled = [row for row in rows if row["readings"] >= SETTLED_READINGS]
    pairs = [ratios(row) for row in settled]
    return {"processes": len(settled), "settled_readings": SETTLED_READINGS,
            "with_record": spread([pair[0] for pair in pairs]), "probe_alone": spread([pair[1] for pair in pairs]),
            # the machine's speed each process saw: its run's CPU over the cost model's at the anchored machine
            "run_speed": spread([row["cpu_time"] / ((row["estimated_seconds"] - row["import_seconds"])
                                                   * row["anchor"] / row["median"]) for row in settled]),
            "probe_speed": spread([row["reading"] / row["anchor"] for row in settled])}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--pairs", type=int, default=30)
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
                with_record, alone = ratios(row)
                print(f"pair {pair} worker {worker}: probe {row['reading'] / row['anchor']:.2f}, record "
                      f"{row['median'] / row['anchor']:.2f} over {row['readings']}; estimate / CPU {with_record:.2f} "
                      f"(probe alone {alone:.2f})", flush=True)
    summary = summarise(rows)
    args.out.write_text(json.dumps({**stamp(), "scene_edits": EDITS, "summary": summary, "rows": rows}, indent=1)
                        + "\n", encoding="utf-8")
    for key in ("with_record", "probe_alone", "run_speed", "probe_speed"):
        line = summary[key]
        print(f"{key}: median {line['median']:.2f}, {line['min']:.2f} to {line['max']:.2f}, sd in ln "
              f"{line['sd_ln']:.3f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
