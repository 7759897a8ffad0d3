"""Start-up time of the command line against ``python -c "import numpy"``, measured in one run.

    python benchmarks/startup.py [--repeats 15]

Targets (issue 32): ``faultslip --help`` at most 1x and ``faultslip fault ... --json`` at most 3x
the time of importing numpy (issue 10 had asked for 2x and 4.5x). Runs are interleaved and the medians compared; the program is
started as ``python -m faultslip.cli`` so that no shell wrapper is timed.

A command whose units were seen before starts without pint (faultslip.units memoises pint's
factors in the user cache folder, as pint caches its own definitions). The first run on a
machine fills both caches; it is measured too, each time with empty caches (a fresh
XDG_CACHE_HOME), and shown as its own row.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from provenance import stamp  # noqa: E402  (one stamp for every results file)

FAULT = ["fault", "--lithology", "granodiorite", "--zone-width", "13 mi", "--shear-stress", "250 bar",
         "--slip-rate", "2 in/yr", "--json"]
COMMANDS = {
    "import numpy": [sys.executable, "-c", "import numpy"],
    "faultslip --help": [sys.executable, "-m", "faultslip.cli", "--help"],
    "faultslip fault ... --json": [sys.executable, "-m", "faultslip.cli", *FAULT],
}


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=15)
    args = parser.parse_args(argv)
    times = {name: [] for name in COMMANDS}
    for name, command in COMMANDS.items():  # warm the file cache
        subprocess.run(command, capture_output=True, check=True)
    cold = "faultslip fault ... --json, first run (empty caches)"
    times[cold] = []
    for _ in range(args.repeats):
        for name, command in COMMANDS.items():
            started = time.perf_counter()
            subprocess.run(command, capture_output=True, check=True)
            times[name].append(time.perf_counter() - started)
        with tempfile.TemporaryDirectory() as empty:
            started = time.perf_counter()
            subprocess.run(COMMANDS["faultslip fault ... --json"], capture_output=True, check=True,
                           env=dict(os.environ, XDG_CACHE_HOME=empty))
            times[cold].append(time.perf_counter() - started)
    medians = {name: statistics.median(values) for name, values in times.items()}
    base = medians["import numpy"]
    result = {"seconds": medians, "ratio_to_numpy": {name: value / base for name, value in medians.items()},
              "targets": {"faultslip --help": 1.0, "faultslip fault ... --json": 3.0},
              **stamp()}
    out = Path(__file__).resolve().parent / "results" / "startup.json"
    out.write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")
    for name, value in medians.items():
        print(f"{name:28s} {value * 1e3:7.1f} ms  {value / base:5.2f}x numpy")
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    import readme

    readme.update()
    return result


if __name__ == "__main__":
    main()
