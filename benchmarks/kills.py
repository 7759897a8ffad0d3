"""Kill sweeps at random moments and check that nothing is lost, left half-written or left running.

    python benchmarks/kills.py [--kills 30] [--seed 0] [--out benchmarks/results/kills.json]

Each round starts ``faultslip sweep`` with two pool workers on a study whose cells are simulated
(slow enough to interrupt), waits a random time, and sends SIGKILL to the parent or SIGINT to the
whole process group (a terminal's Ctrl-C). It then checks: no file under the final name unless the
run finished; no worker process left alive; exit 130 and one line on stderr after SIGINT; and,
after ``--resume``, values bit-identical to an uninterrupted run. Concurrency rounds start two
sweeps on one output and check that exactly one is refused and the other's file is complete.
"""

from __future__ import annotations

import argparse
import json
import os
import random
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from faultslip.io.processes import children, is_alive
from provenance import stamp  # noqa: E402  (one stamp for every results file)

# every cell integrated (DOP853 slip phases of a polynomial kinetic law, ~30 ms): slow enough to kill mid-run
STUDY = ('[study]\nbase = "lab_steel_dry_polynomial.toml"\n[sweep]\n'
         'platform_speed = { logspace = ["1e-5 m/s", "1e-4 m/s", 300] }\n')


def _faultslip(*args):
    return subprocess.Popen([sys.executable, "-m", "faultslip.cli", *map(str, args)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, start_new_session=True)


def _values(path):
    import xarray as xr

    with xr.open_dataset(path) as data:
        return {name: data[name].values.copy() for name in data.data_vars}


def _same(a, b):
    return a.keys() == b.keys() and all(np.array_equal(a[k], b[k], equal_nan=True) for k in a)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--kills", type=int, default=30)
    parser.add_argument("--races", type=int, default=5, help="rounds of two sweeps on one output")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", default=str(Path(__file__).resolve().parent / "results" / "kills.json"))
    args = parser.parse_args(argv)
    rng = random.Random(args.seed)
    folder = Path(tempfile.mkdtemp(prefix="faultslip-kills-"))
    study = folder / "slow.toml"
    study.write_text(STUDY)
    reference = folder / "reference.nc"
    subprocess.run([sys.executable, "-m", "faultslip.cli", "sweep", study, "-o", reference, "--chunks", "6"],
                   check=True, capture_output=True)
    expected = _values(reference)
    tally = {"kill -9": 0, "ctrl-c": 0, "finished before the signal": 0, "problems": []}
    started = time.perf_counter()
    for round_ in range(args.kills):
        out = folder / f"run{round_}.nc"
        process = _faultslip("sweep", study, "-o", out, "--chunks", "6", "--workers", "2")
        time.sleep(rng.uniform(0.3, 4.0))  # some signals land during start-up
        workers = children(process.pid)
        how = rng.choice(["kill -9", "ctrl-c"])
        if process.poll() is None:
            if how == "kill -9":
                process.send_signal(signal.SIGKILL)
            else:
                os.killpg(process.pid, signal.SIGINT)
            tally[how] += 1
        else:
            tally["finished before the signal"] += 1
        _, stderr = process.communicate(timeout=60)
        if how == "ctrl-c" and process.returncode not in (0, 130):
            tally["problems"].append(f"round {round_}: Ctrl-C gave exit {process.returncode}")
        lines = [line for line in stderr.splitlines() if line.strip() and "warning" not in line]
        if how == "ctrl-c" and process.returncode == 130 and (len(lines) != 1 or "Traceback" in stderr):
            tally["problems"].append(f"round {round_}: Ctrl-C printed {len(lines)} lines")
        deadline = time.time() + 10
        while time.time() < deadline and any(is_alive(p) for p in workers):
            time.sleep(0.1)
        if any(is_alive(p) for p in workers):
            tally["problems"].append(f"round {round_}: workers outlived the parent after {how}")
        if out.exists() and not _same(_values(out), expected):  # a run interrupted after its rename is complete
            tally["problems"].append(f"round {round_}: an incomplete file under the final name after {how}")
        resumed = subprocess.run([sys.executable, "-m", "faultslip.cli", "sweep", study, "-o", out, "--chunks", "6",
                                  "--resume", "--overwrite"], capture_output=True, text=True)
        if resumed.returncode != 0:
            tally["problems"].append(f"round {round_}: resume failed: {resumed.stderr.strip()[:200]}")
        elif not _same(_values(out), expected):
            tally["problems"].append(f"round {round_}: the resumed result differs from an uninterrupted run")
    races = {"rounds": 0, "one_refused": 0, "problems": []}
    for round_ in range(args.races):
        out = folder / f"race{round_}.nc"
        first = _faultslip("sweep", study, "-o", out, "--chunks", "6", "--workers", "1")
        time.sleep(rng.uniform(1.5, 3.0))
        second = _faultslip("sweep", study, "-o", out, "--chunks", "6", "--workers", "1", "--overwrite")
        outcomes = [p.communicate(timeout=300) for p in (first, second)]
        codes = sorted(p.returncode for p in (first, second))
        races["rounds"] += 1
        if codes == [0, 2] and "another faultslip run" in (outcomes[1][1] + outcomes[0][1]):
            races["one_refused"] += 1
        elif codes != [0, 0]:  # both may succeed if the first finished before the second started
            races["problems"].append(f"race {round_}: exit codes {codes}")
        if not _same(_values(out), expected):
            races["problems"].append(f"race {round_}: the surviving file is not the complete result")
    result = {"kills": tally, "races": races, "wall_time_s": time.perf_counter() - started,
              **stamp()}
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")
    print(json.dumps(result, indent=1))
    return 1 if tally["problems"] or races["problems"] else 0


if __name__ == "__main__":
    sys.exit(main())
