"""Estimate a run's cells, memory, disk and time before starting, and refuse what will not fit.

The default budget is what this machine has: half its available memory, the free disk where the
output goes, and about an hour of wall time. A run beyond it is refused with one sentence giving
the estimate and the flag that overrides it (``--allow-large``). The throughputs below are
conservative figures from ``benchmarks/`` on a 2-core machine; an estimate is an order of
magnitude, meant to stop a two-week run or a 100 GB allocation, not to predict to the second.
"""

from __future__ import annotations

import os
import shutil
from dataclasses import dataclass
from pathlib import Path

from faultslip.errors import InputError

#: Default wall-time budget in seconds; the environment variable FAULTSLIP_TIME_BUDGET (seconds) sets another.
TIME_BUDGET = 3600.0
#: Cells per second per worker of a closed-form/exact-cycle study, including compression.
STUDY_CELL_RATE = 4e5
#: Cells per second per worker when every cell is simulated (friction laws without a closed form).
SIMULATED_CELL_RATE = 25.0
#: Disk bytes per raw output byte under zlib (measured 0.37 on the San Andreas studies).
ZLIB_RATIO = 0.5
#: Largest number of values of one swept dimension (its coordinate alone would take 0.8 GB).
MAX_DIMENSION_VALUES = 100_000_000
OVERRIDE = "--allow-large"


def available_memory() -> float:
    """Bytes of memory available now (Linux MemAvailable; else total physical memory)."""
    try:
        with open("/proc/meminfo", encoding="ascii") as handle:
            for line in handle:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024.0
    except OSError:
        pass
    try:
        return float(os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):
        return 8.0 * 2**30


def free_disk(path) -> float:
    folder = Path(path).parent if not Path(path).is_dir() else Path(path)
    try:
        return float(shutil.disk_usage(folder if str(folder) else ".").free)
    except OSError:
        return float("inf")


def _size(n: float) -> str:
    for unit, scale in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if n >= scale:
            return f"{n / scale:.3g} {unit}"
    return f"{n:.0f} B"


def _duration(seconds: float) -> str:
    for unit, scale in (("days", 86400.0), ("hours", 3600.0), ("minutes", 60.0)):
        if seconds >= scale:
            return f"{seconds / scale:.3g} {unit}"
    return f"{seconds:.2g} s"


@dataclass
class Estimate:
    """What a run is expected to need."""

    what: str  # e.g. "this sweep of 1e+12 cells"
    memory: float = 0.0  # bytes held at once
    disk: float = 0.0  # bytes written
    seconds: float = 0.0
    output: object = None  # where the disk bytes go

    def describe(self) -> str:
        parts = []
        if self.seconds:
            parts.append(f"about {_duration(self.seconds)}")
        if self.memory:
            parts.append(f"{_size(self.memory)} of memory")
        if self.disk:
            parts.append(f"{_size(self.disk)} of disk")
        return ", ".join(parts)


def time_budget() -> float:
    """The wall-time budget in seconds: FAULTSLIP_TIME_BUDGET if set to a positive number, else one hour."""
    try:
        value = float(os.environ.get("FAULTSLIP_TIME_BUDGET", TIME_BUDGET))
    except ValueError:
        return TIME_BUDGET
    return value if value > 0 else TIME_BUDGET


def check(estimate: Estimate, allow_large: bool = False, seconds_allowed: float | None = None) -> None:
    """Refuse ``estimate`` if it exceeds the budget, unless ``allow_large``."""
    if allow_large:
        return
    seconds_allowed = time_budget() if seconds_allowed is None else seconds_allowed
    reasons = []
    memory = available_memory()
    if estimate.memory > 0.5 * memory:
        reasons.append(f"{_size(estimate.memory)} of memory (half of the {_size(memory)} available is the budget)")
    if estimate.disk and estimate.output is not None:
        disk = free_disk(estimate.output)
        if estimate.disk > disk:
            reasons.append(f"{_size(estimate.disk)} of disk ({_size(disk)} free)")
    if estimate.seconds > seconds_allowed:
        reasons.append(f"about {_duration(estimate.seconds)} (the budget is {_duration(seconds_allowed)})")
    if reasons:
        raise InputError(f"{estimate.what} would need {' and '.join(reasons)}; make it smaller, or pass "
                         f"{OVERRIDE} to run it anyway")


def study_estimate(study, output, workers: int, chunk_cells: int, compression: str = "zlib") -> Estimate:
    """Memory, disk and time of a sweep, from its shape alone (nothing is allocated)."""
    cells = float(study.size)
    outputs = 12
    raw = cells * outputs * 8.0
    disk = raw * (1.0 if compression == "none" else ZLIB_RATIO)
    rate = max(workers, 1) / study.seconds_per_cell()
    block = min(cells, float(chunk_cells))
    memory = block * 40 * 8.0 * (max(workers, 1) + 1)  # ~40 grid-sized temporaries per block in flight
    return Estimate(what=f"this sweep of {cells:.3g} cells", memory=memory, disk=disk, seconds=cells / rate,
                    output=output)


def simulation_estimate(cycles: int, samples_per_slip: int, integrated: bool, output=None) -> Estimate:
    """Memory and time of ``simulate``: the time series holds about (samples + 2) rows per cycle."""
    rows = float(cycles) * (samples_per_slip + 2)
    memory = rows * 6 * 8.0 * 3  # six columns, about three copies while the dataset is built
    seconds = float(cycles) * (2.5e-3 if integrated else 2e-6) + rows * 1e-8
    return Estimate(what=f"a simulation of {cycles:.3g} cycles", memory=memory, disk=rows * 6 * 8.0 if output else 0.0,
                    seconds=seconds, output=output)
