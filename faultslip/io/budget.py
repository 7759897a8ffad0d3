"""Estimate a run's cells, memory, disk and time before starting, and refuse what will not fit.

The default budget is what this machine has: half its available memory, the free disk where the
output goes, and about an hour of wall time. A run beyond it is refused with one sentence giving
the estimate and the flag that overrides it (``--allow-large``). The throughputs below are
conservative figures from ``benchmarks/`` on a 2-core machine; an estimate is an order of
magnitude, meant to stop a two-week run or a 100 GB allocation, not to predict to the second.
"""

from __future__ import annotations

import math
import os
import shutil
from dataclasses import dataclass
from pathlib import Path

from faultslip import ranges
from faultslip.errors import InputError

#: Default wall-time budget in seconds; the environment variable FAULTSLIP_TIME_BUDGET (seconds) sets another.
TIME_BUDGET = 3600.0
#: Cells per second per worker of a closed-form/exact-cycle study, including compression.
STUDY_CELL_RATE = 4e5
#: Cells per second per worker when every cell is simulated (friction laws without a closed form).
SIMULATED_CELL_RATE = 25.0
#: Disk bytes per raw output byte under zlib (measured 0.37 on the San Andreas studies).
ZLIB_RATIO = 0.5
#: Largest number of values of one swept dimension: a study's axis is held as Python numbers while the study is read
#: (1e8 of them took gigabytes before any budget was checked); a million is far past any grid a study runs.
MAX_DIMENSION_VALUES = 1_000_000
OVERRIDE = "--allow-large"


def available_memory() -> float:
    """Bytes of memory available now (psutil: MemAvailable on Linux, its equivalent elsewhere)."""
    import psutil  # heavy: imported where used (a budget check, not every command)

    try:
        return float(psutil.virtual_memory().available)
    except (psutil.Error, OSError, RuntimeError):  # an unusual container without the kernel's figures
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
            value = f"{seconds / scale:.3g}"
            return f"{value} {unit[:-1] if value == '1' else unit}"
    return f"{seconds:.2g} s"


@dataclass
class Estimate:
    """What a run is expected to need."""

    what: str  # e.g. "this sweep of 1e+12 cells"
    memory: float = 0.0  # bytes held at once
    disk: float = 0.0  # bytes written
    seconds: float = 0.0
    output: object = None  # where the disk bytes go
    outside_fit: tuple = ()  # sentences: where the scene lies outside the range the estimate was fitted on

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
    """The wall-time budget in seconds: FAULTSLIP_TIME_BUDGET where set, else one hour.

    A value that is not a number of seconds within :data:`faultslip.ranges.BOUNDS` (empty, ``nan``,
    negative, zero, text) is refused in one sentence: it never silently means the default."""
    text = os.environ.get("FAULTSLIP_TIME_BUDGET")
    if text is None:
        return TIME_BUDGET
    return ranges.parse_number("time_budget", text, "the environment variable, in seconds")


def check(estimate: Estimate, allow_large: bool = False, seconds_allowed: float | None = None) -> None:
    """Refuse ``estimate`` if it exceeds the budget, unless ``allow_large``."""
    if allow_large:
        return
    if estimate.outside_fit:
        raise InputError(f"{estimate.what}: its cost estimate was fitted on other scenes "
                         f"({'; '.join(estimate.outside_fit)}) and may be far off; pass {OVERRIDE} to run it anyway "
                         "(a run that reaches twice the time budget checkpoints and stops)")
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


#: Bytes of a netCDF4 file besides its data: HDF5's superblock and object headers, and per variable its
#: header, attributes and chunk index (measured: 51 kB for a 17-output sweep of 12 cells).
NETCDF_OVERHEAD, NETCDF_PER_VARIABLE = 16e3, 3e3


def netcdf_disk(raw_bytes: float, variables: int, compression: str = "zlib") -> float:
    """Disk bytes of a netCDF4 file holding ``raw_bytes`` of data in ``variables`` variables."""
    return raw_bytes * (1.0 if compression == "none" else ZLIB_RATIO) + NETCDF_OVERHEAD + NETCDF_PER_VARIABLE * variables


def study_estimate(study, output, workers: int, chunk_cells: int, compression: str = "zlib") -> Estimate:
    """Memory, disk and time of a sweep, from its shape alone (nothing is allocated)."""
    cells = float(study.size)
    outputs = 17
    raw = cells * outputs * 8.0
    disk = netcdf_disk(raw, outputs + len(study.dims), compression)
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


#: Seconds of LSODA per unit of nanoscale time (1/omega), measured on seed 001's scene (2 cores, 2026-11-24:
#: 30,000 units in 9 s); taken 2x for a slower machine.
NANOSCALE_SECONDS_PER_UNIT = 6e-4


def nanoscale_estimate(duration: float, samples: int) -> Estimate:
    """Time and memory of a nanoscale run over ``duration`` (in 1/omega) kept at ``samples`` points."""
    return Estimate(what=f"a nanoscale run over {duration:.3g}/omega", seconds=duration * NANOSCALE_SECONDS_PER_UNIT,
                    memory=float(samples) * 6 * 8.0 * 3)


#: A 2-D fault run's steps per simulated year (benchmarks/fault_2d_cost.py fits it to measured step counts,
#: which do not depend on the machine): A (V_pl / 1e-9 m/s) (W / h*) (rtol / 1e-7)^-0.18 g(h / L_b), where
#: W is the velocity-weakening width, h* the nucleation size, L_b the process zone and h the element size.
#: More cycles (a faster plate) and more partial ruptures (W >> h*) cost steps in proportion; an element
#: coarser than L_b makes the sequence irregular (g = (h / L_b)^0.31) and a finer one sharpens the fronts
#: (g grows as (L_b / h)^0.45 below h = L_b / 4, from BP1 at 50 and 25 m). Fitted over D_c 6-48 mm,
#: V_pl 1e-10 to 1e-8 m/s, h 250 m to 2 km, rtol 1e-7 and 1e-5, and BP1: within 0.75-1.4x of the measured
#: steps; the estimate takes twice the fit, so that it errs long.
FAULT_2D_STEPS = {"scale": 15.0, "plate_rate": 1.02, "width_over_nucleation": 0.99, "rtol": -0.18,
                  "coarse": 0.31, "fine": 0.45, "fine_below": 0.25, "margin": 2.0}
#: CPU seconds per Dormand-Prince step (six force balances and the stress kernel) on N elements with the whole step
#: compiled (numba and rocket-fft, the FFT kernel): c0 + c1 N, least squares over the ten FFT runs of
#: benchmarks/ladder_designs.py and benchmarks/ladder_escalations.py (564-1,036 elements, rtol 1e-8, two runs at a
#: time on the 2-core machine), within 0.87-1.16x of each (tests/test_budget_fit.py refits it). Another step path
#: scales it by its measured cost (:func:`faultslip.models.fault_2d.kernel.relative_step_cost`).
FAULT_2D_STEP_SECONDS = (1.237e-4, 2.279e-7, 1.0)
#: CPU seconds per step of a plane-strain (dipping) 2-D fault, whose kernels are dense: c0 + c2 N^2, fitted by
#: benchmarks/plane_strain_step.py (SEAS BP3-QD on 200-1,600 elements, within 1.31x of each; tests/test_budget_fit.py
#: refits it from benchmarks/results/plane_strain_step.json).
PLANE_STRAIN_STEP_SECONDS = (4.308e-4, 8.563e-9)
#: Steps from the events a run will see (issue 68): ln steps = ln A + p ln(events) + q ln(W / h*) + r ln(N), fitted
#: on the 36 calibration runs of benchmarks/ladder_designs.py (3 elements per L_b, rtol 1e-8), where a run's events
#: come from its duration over the recurrence the one-slider rung predicts; with the per-step seconds above, the
#: 34 held-out runs' CPU time came within 0.63-2.5x (30 of 34 within 2x). The resolution and rtol factors of
#: FAULT_2D_STEPS carry it to other element sizes and tolerances.
FAULT_2D_EVENT_STEPS = {"scale": math.exp(5.33), "events": 0.782, "width_over_nucleation": 0.509, "elements": 0.581,
                        "resolution": 3.0, "rtol": 1e-8}


#: The scenes the 2-D step models were fitted on: W / h* at the weakest element (FAULT_2D_STEPS' BP1 at D_c 6-48 mm
#: gives 0.55-4.4; the ladder designs 1.56-7.88) and the normal stress on the velocity-weakening part (BP1's
#: 50 MPa; the designs 25.1-99.0 MPa), each rounded outward (tests/test_budget_fit.py recomputes them). A scene
#: outside them (a sigma_n of 1e-6 MPa, or one falling to 0.01 MPa in the weakening zone) can step far more
#: often than either model knows: :func:`check` refuses it without --allow-large.
FAULT_2D_FITTED = {"width_over_nucleation": (0.5, 8.0), "normal_stress": (25e6, 100e6)}


def fault_2d_outside_fit(*, width_over_nucleation: float, normal_stress_low: float,
                         normal_stress_high: float) -> tuple:
    """Where a 2-D scene lies outside :data:`FAULT_2D_FITTED`, as sentences (empty: inside)."""
    low, high = FAULT_2D_FITTED["width_over_nucleation"]
    out = []
    if not low <= width_over_nucleation <= high:
        out.append(f"its W/h* is {width_over_nucleation:.3g}, fitted {low:g} to {high:g}")
    low, high = FAULT_2D_FITTED["normal_stress"]
    if normal_stress_low < low or normal_stress_high > high:
        out.append(f"its normal stress on the weakening part spans {normal_stress_low / 1e6:.3g} to "
                   f"{normal_stress_high / 1e6:.3g} MPa, fitted {low / 1e6:g} to {high / 1e6:g} MPa")
    return tuple(out)


def _resolution_factor(ratio: float) -> float:
    """How the steps grow with the element size h over L_b (:data:`FAULT_2D_STEPS`)."""
    c = FAULT_2D_STEPS
    ratio = min(max(ratio, 1e-6), 1e6)
    return ratio ** c["coarse"] * max(1.0, c["fine_below"] / ratio) ** c["fine"]


def fault_2d_steps(*, years: float, plate_rate: float, element_size: float, process_zone: float,
                   nucleation_size: float, seismogenic_width: float, rtol: float, events: float | None = None,
                   elements: int | None = None) -> float:
    """Steps a 2-D fault run takes over ``years``: from the ``events`` it will see where they are known
    (:data:`FAULT_2D_EVENT_STEPS`, a central estimate), else an upper estimate from :data:`FAULT_2D_STEPS`."""
    c = FAULT_2D_STEPS
    # a fault without weakening (b = 0 everywhere: L_b infinite) creeps: its resolution costs nothing extra
    ratio = element_size / process_zone if 0 < process_zone < math.inf else 1.0
    resolution = _resolution_factor(ratio)
    partial = max(seismogenic_width, element_size) / nucleation_size if math.isfinite(nucleation_size) else 0.1
    if events is not None and elements and events > 0 and math.isfinite(nucleation_size):
        e = FAULT_2D_EVENT_STEPS
        return (e["scale"] * events ** e["events"] * partial ** e["width_over_nucleation"]
                * elements ** e["elements"] * resolution / _resolution_factor(1.0 / e["resolution"])
                * (rtol / e["rtol"]) ** c["rtol"]) + 100.0
    per_year = (c["scale"] * (plate_rate / 1e-9) ** c["plate_rate"] * partial ** c["width_over_nucleation"]
                * (rtol / 1e-7) ** c["rtol"] * resolution)
    return c["margin"] * per_year * years + 100.0


def fault_2d_estimate(elements: int, years: float, stations: int, output=None, *, steps: float,
                      outside_fit: tuple = (), step_cost: float = 1.0, plane_strain: bool = False) -> Estimate:
    """Time, memory and disk of a 2-D fault run of ``steps`` steps (:func:`fault_2d_steps`): station rows every
    step (in memory, and as SEAS text). ``plane_strain``: a dipping fault's dense step
    (:data:`PLANE_STRAIN_STEP_SECONDS`), and its two N x N kernels in memory."""
    c0, c1, margin = FAULT_2D_STEP_SECONDS
    per_step = c0 + c1 * elements
    kernels = 0.0
    if plane_strain:
        dense0, dense2 = PLANE_STRAIN_STEP_SECONDS
        per_step, step_cost, kernels = dense0 + dense2 * elements ** 2, 1.0, 2 * 8.0 * elements ** 2 * 2
    return Estimate(what=f"a 2-D fault run of {elements} elements over {years:.4g} yr (about {steps:.3g} steps)",
                    seconds=margin * steps * per_step * step_cost,
                    memory=steps * (1 + 4 * stations) * 8.0 * 2 + kernels,
                    disk=steps * stations * 100.0 if output else 0.0, output=output, outside_fit=outside_fit)


#: Bytes held per cell of a map's raster (coordinates, unit vectors, nearest index and distance, four maps).
MAP_BYTES_PER_CELL = 200.0
#: Bytes per densified trace point (unit vector, owner, k-d tree), and cells a second through the tree.
MAP_BYTES_PER_POINT, MAP_CELLS_PER_SECOND = 120.0, 2e6


def map_estimate(cells: float, trace_points: float, output=None) -> Estimate:
    """Memory, disk and time of a map of ``cells`` raster cells against ``trace_points`` densified trace points."""
    return Estimate(what=f"this map of {cells:.3g} cells", memory=cells * MAP_BYTES_PER_CELL
                    + trace_points * MAP_BYTES_PER_POINT, disk=netcdf_disk(cells * 6 * 8.0, 12) if output else 0.0,
                    seconds=(cells + trace_points) / MAP_CELLS_PER_SECOND, output=output)
