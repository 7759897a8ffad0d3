"""Whole-process runs measured the same way for faultslip and a peer code: pinned to one core, interleaved.

Every benchmark that puts faultslip beside another program (QDYN's 2-D fault and spring-block) uses
these, so that both sides of a ratio are measured alike:

- each run is a whole process (start-up, input, output), its standard output to a file as a user's
  run to a log would be;
- it is pinned to one core (``os.sched_setaffinity`` in the child before it starts), so that neither
  code gains from the other core and a busy neighbour on the other core does not land on one side;
- wall time, the child's own CPU time (user + system, from ``os.wait4``) and its peak resident memory
  (``ru_maxrss``) are read for that child alone;
- the runs of a comparison are interleaved in rounds, the order reversed every other round, and the
  median of the rounds kept, so that a slow moment of the machine falls on every code alike.
"""

from __future__ import annotations

import os
import shutil
import statistics
import subprocess
import time
from pathlib import Path

GNU_TIME = "/usr/bin/time" if Path("/usr/bin/time").is_file() else shutil.which("gtime")

# The tolerance grid every code is studied on: wide enough that each code's loosest passing tolerance is
# found, not assumed (issue 43: a grid that stops at 1e-6 for one code and 1e-4 for the other is not fair).
COMMON_GRID = (1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10)


def environment() -> dict:
    """The environment a user's run sees (a user's install has its bytecode compiled; this machine's
    shell may forbid writing it)."""
    return {key: value for key, value in os.environ.items() if key != "PYTHONDONTWRITEBYTECODE"}


def measured(command: list[str], folder: Path | None, log: Path, core: int | None = 0) -> dict:
    """Run ``command`` as one process pinned to ``core`` (None: any core) and measure it.

    Returns ``status``, ``wall_s``, ``cpu_s`` (user + system of the command and anything it waited
    for) and ``peak_mib`` (its peak resident set). The peak is read by GNU time, which forks the
    command: a process forked from this interpreter would inherit the interpreter's own size as its
    ``ru_maxrss`` (Linux records the old image's peak at exec), which for a small code like QDYN
    is most of what it would report."""
    pin = (lambda: os.sched_setaffinity(0, {core})) if core is not None else None
    peak_file = log.with_suffix(".peak")
    launcher = [GNU_TIME, "-f", "%M", "-o", str(peak_file)] if GNU_TIME else []
    with open(log, "w", encoding="utf-8") as out:
        start = time.perf_counter()
        child = subprocess.Popen(launcher + command, cwd=folder, stdout=out, stderr=subprocess.STDOUT,
                                 env=environment(), preexec_fn=pin)
        _, status, usage = os.wait4(child.pid, 0)
        wall = time.perf_counter() - start
    child.returncode = os.waitstatus_to_exitcode(status)
    peak_kib = float(usage.ru_maxrss)
    if GNU_TIME:
        try:  # GNU time writes "Command exited with non-zero status N" before the figure on failure
            peak_kib = float(peak_file.read_text(encoding="utf-8").split()[-1])
        except (OSError, ValueError, IndexError):
            pass
        peak_file.unlink(missing_ok=True)
    return {"status": child.returncode, "wall_s": wall, "cpu_s": usage.ru_utime + usage.ru_stime,
            "peak_mib": peak_kib / 1024.0}


def interleaved(runs: dict, rounds: int) -> dict[str, list[dict]]:
    """Each named run ``runs[name]()`` once per round, the order reversed every other round."""
    names = list(runs)
    measured_rounds: dict[str, list[dict]] = {name: [] for name in names}
    for round_number in range(rounds):
        for name in (names if round_number % 2 == 0 else names[::-1]):
            measured_rounds[name].append(runs[name]())
    return measured_rounds


def medians(rows: list[dict]) -> dict:
    """The median wall, CPU and peak memory of a run's rounds, with the rounds themselves."""
    return {"rounds": len(rows), "wall_s": statistics.median(row["wall_s"] for row in rows),
            "cpu_s": statistics.median(row["cpu_s"] for row in rows),
            "peak_mib": statistics.median(row["peak_mib"] for row in rows),
            "wall_s_each": [row["wall_s"] for row in rows]}
