"""Estimate a run's cells, memory, disk and time before starting, and refuse what will not fit.

The default budget is what this machine has: half its available memory, the free disk where the
output goes, and about an hour of wall time. A run beyond it is refused with one sentence giving
the estimate and the flag that overrides it (``--allow-large``). The throughputs below are
conservative figures from ``benchmarks/`` on a 2-core machine; an estimate is an order of
magnitude, meant to stop a two-week run or a 100 GB allocation, not to predict to the second.
"""

from __future__ import annotations

import importlib
import os
import shutil
import sys
import time
from dataclasses import dataclass, replace
from functools import lru_cache
from importlib.metadata import entry_points
from pathlib import Path

from faultslip import ranges
from faultslip.io import machine
from faultslip.errors import InputError
from faultslip.io.report import Report
from faultslip.io.resources import read_bundled_table

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
#: What a run that builds an xarray Dataset imports: xarray, and dask.array, which xarray's first Dataset imports
#: where dask is installed (0.4 and 0.6 s of CPU in a fresh process).
DATASET_IMPORTS = ("xarray", "dask.array")
#: What an integrating run imports: scipy's integrators and the root finders that locate its events.
INTEGRATION_IMPORTS = ("scipy.integrate", "scipy.optimize")
#: What writing a Dataset to netCDF through xarray imports (:func:`faultslip.io.netcdf.write_dataset`: a
#: simulation's or a map's output): netCDF4, and distributed, which xarray's writer imports where it is installed
#: to ask whether a dask client is active (0.3-0.4 s of CPU). A sweep's chunk writer imports neither.
DATASET_WRITER_IMPORTS = ("netCDF4", "distributed")
#: What every run imports where it checks its budget (:func:`available_memory`).
BUDGET_IMPORTS = ("psutil",)
#: numba's extensions (rocket-fft), which its first compiled call loads: a name :func:`import_modules` takes.
NUMBA_EXTENSIONS = "numba:extensions"


def available_memory() -> float:
    """Bytes of memory available now (psutil: MemAvailable on Linux, its equivalent elsewhere)."""
    import psutil  # heavy: imported where used (a budget check, not every command)

    try:
        return float(psutil.virtual_memory().available)
    except (psutil.Error, OSError, RuntimeError):  # an unusual container without the kernel's figures
        return 8.0 * 2**30


def free_disk(path) -> float:
    """Free bytes where ``path`` (a file or folder) would be written; inf where the system cannot say (a name it
    cannot look up is refused, in one sentence, by the writer's guard: :mod:`faultslip.io.outputs`)."""
    try:
        folder = Path(path) if Path(path).is_dir() else Path(path).parent
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
    """What a run is expected to need, before it starts: a family's cost model's answer (``faultslip run SCENE
    --estimate``).

    Attributes
    ----------
    what : str
        What is estimated ("a simulation of 100 cycles").
    memory, disk : float
        Bytes held at once, and written (B).
    seconds : float
        CPU time (s), about; for work on several workers, its time on them, together (what the budget holds).
    output : path or None
        Where the disk bytes go.
    outside_fit : tuple of str
        Where the scene lies outside the scenes the cost model was fitted on (then :func:`check` refuses it
        without ``--allow-large``).
    notes : tuple of str
        What the estimate leaves out and may follow (a rerun that only happens if the run ends unsettled).
    workers : int
        Workers the work is shared by (a sweep's); with more than one, ``cpu_seconds`` is their CPU summed.
    cpu_seconds : float or None
        CPU time over every worker (s), where ``workers`` > 1.
    imports : tuple of str
        The modules the run imports where it runs (its heavy, lazily imported ones; :data:`DATASET_IMPORTS`,
        ``"scipy.integrate"``, :data:`NUMBA_EXTENSIONS`): :func:`with_imports` counts those this process lacks.
    import_seconds : float
        CPU seconds of those imports, measured by :func:`with_imports` and included in ``seconds``.
    """

    what: str  # e.g. "this sweep of 1e+12 cells"
    memory: float = 0.0  # bytes held at once
    disk: float = 0.0  # bytes written
    seconds: float = 0.0
    output: object = None  # where the disk bytes go
    outside_fit: tuple = ()  # sentences: where the scene lies outside the range the estimate was fitted on
    workers: int = 1
    cpu_seconds: float | None = None
    notes: tuple = ()
    imports: tuple = ()
    import_seconds: float = 0.0

    @property
    def modelled_seconds(self) -> float:
        """The cost model's seconds alone, ``seconds - import_seconds``: the same in every process on this machine,
        where the imports measured depend on what the process has imported already."""
        return self.seconds - self.import_seconds

    def report(self, title: str | None = None, started: float | None = None):
        """The estimate as a :class:`~faultslip.io.report.Report` (what ``--estimate`` prints).

        Parameters
        ----------
        title : str, optional
            The report's title.
        started : float, optional
            CPU seconds the estimating process had used when it estimated (a command's interpreter and imports,
            ``time.process_time()``), which no cost model counts: reported beside the estimate, and added to it as
            the command's whole CPU time.

        Returns
        -------
        Report
            ``seconds`` (s), ``memory`` and ``disk`` (B), and where the cost model was fitted on other scenes."""
        # a long description is the 'what' row's alone, not repeated as a title over several lines
        short = len(self.what) <= 80
        report = Report(title or ("faultslip estimate: " + self.what if short else "faultslip estimate"))
        report.add("what", self.what)
        shared = self.workers > 1  # then seconds is the workers' time together, not the CPU they use
        report.add("seconds", self.seconds, "s",
                   label=f"time on its {self.workers} workers, about" if shared else "CPU time, about")
        if shared:
            report.add("cpu_seconds", self.cpu_seconds, "s", label="CPU time over the workers, about")
        if self.import_seconds:
            report.add("import_seconds", self.import_seconds, "s",
                       label="of which imports the run needs, measured")
        if started is not None:
            started = max(started - self.import_seconds, 0.0)  # the run's own imports are in seconds already
            report.add("process_start_seconds", started, "s", label="CPU to start (Python, imports), measured")
            report.add("command_seconds", self.seconds + started, "s",
                       label="the command's time, about" if shared else "the command's CPU time, about")
        report.add("memory", self.memory, "B", also=("MB",), label="memory held at once")
        report.add("disk", self.disk, "B", also=("MB",), label="disk written")
        report.add("within_budget", self.fits(), label="within the budget (time, memory, disk)")
        if self.seconds:
            report.note(machine.describe())
        for sentence in self.outside_fit:
            report.note(f"outside the scenes the cost model was fitted on: {sentence}")
        for sentence in self.notes:
            report.note(sentence)
        return report

    def fits(self) -> bool:
        """Whether :func:`check` would let this estimate run without ``--allow-large``."""
        try:
            check(self)
        except InputError:
            return False
        return True

    def to_xarray(self):
        """The estimate as an xarray Dataset: ``seconds`` (s), ``memory`` and ``disk`` (B), with its ``what``."""
        import xarray as xr  # heavy: imported where used

        return xr.Dataset({name: ((), float(getattr(self, name)), {"units": unit})
                           for name, unit in (("seconds", "s"), ("memory", "B"), ("disk", "B"))},
                          attrs={"title": self.what, "outside_fit": "; ".join(self.outside_fit)})

    def describe(self) -> str:
        parts = []
        if self.seconds:
            parts.append(f"about {_duration(self.seconds)}")
        if self.memory:
            parts.append(f"{_size(self.memory)} of memory")
        if self.disk:
            parts.append(f"{_size(self.disk)} of disk")
        return ", ".join(parts)


#: Modules :func:`import_modules` found missing in this process: not owed again.
_MISSING: set = set()


def import_modules(modules) -> None:
    """Import those of ``modules`` this process has not imported yet: a run's, before it needs them (a pool's
    workers that fork afterwards share them), or an estimate's, to measure them (:func:`measure_imports`).

    Parameters
    ----------
    modules : iterable of str
        Module names (``"scipy.integrate"``), or :data:`NUMBA_EXTENSIONS`: numba's extensions, loaded.

    Returns
    -------
    None
        A module not installed here is noted as missing, not raised: the run says so where it needs it.
    """
    for name in dict.fromkeys(modules):
        try:
            if name == NUMBA_EXTENSIONS:
                importlib.import_module("numba.core.entrypoints").init_all()  # once per process; then a no-op
            elif name not in sys.modules:
                importlib.import_module(name)
        except ImportError:  # not installed here: the run says so where it needs it; an estimate is no place to fail
            _MISSING.add(name)


def measure_imports(modules) -> float:
    """CPU seconds this process spends importing those of ``modules`` it has not imported yet, measured by
    importing them (:func:`import_modules`; the run would: an estimate that leaves them out misses a short run's
    time several times over).

    Parameters
    ----------
    modules : iterable of str
        What :func:`import_modules` takes.

    Returns
    -------
    float
        Process CPU seconds (``time.process_time``); 0 where every one is imported already.
    """
    start = time.process_time()
    import_modules(modules)
    return time.process_time() - start


@lru_cache(maxsize=1)
def _numba_extension_modules() -> tuple:
    """The modules of numba's extensions: the ``init`` entry points of group ``numba_extensions``, which numba's
    first compiled call loads (the public record of them; numba keeps whether it has loaded them to itself)."""
    return tuple(point.module for point in entry_points(group="numba_extensions", name="init"))


def _numba_extensions_loaded() -> bool:
    return all(module in sys.modules for module in _numba_extension_modules())


def with_imports(estimate: Estimate) -> Estimate:
    """``estimate`` with the CPU its run's imports cost this process (:func:`measure_imports` of its ``imports``
    and :data:`BUDGET_IMPORTS`) added to its seconds, and said in a note where there are any."""
    modules = (*BUDGET_IMPORTS, *estimate.imports)
    owed = [name for name in dict.fromkeys(modules) if name not in _MISSING
            and (not _numba_extensions_loaded() if name == NUMBA_EXTENSIONS else name not in sys.modules)]
    if not owed:  # every one imported already: the estimate as it is, not a measured microsecond more
        return estimate
    seconds = measure_imports(owed)
    # added to what an earlier call measured: a second call finds the modules imported, and adds nothing
    counted = {"import_seconds": estimate.import_seconds + seconds, "seconds": estimate.seconds + seconds}
    if seconds < 1e-3:
        return replace(estimate, **counted)
    names = ", ".join("numba's extensions" if name == NUMBA_EXTENSIONS else name for name in owed
                      if name not in BUDGET_IMPORTS) or "the budget's check"
    note = f"{_duration(seconds)} of the CPU time imports what the run needs ({names}), measured by importing it"
    return replace(estimate, **counted, notes=(*estimate.notes, note),
                   cpu_seconds=None if estimate.cpu_seconds is None else estimate.cpu_seconds + seconds)


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


def with_one_off(what: str, seconds: float, one_off: tuple) -> tuple[str, float]:
    """``what`` and ``seconds`` with a one-off cost added: ``one_off`` is (seconds, what they are spent on), as a
    compiled step's first run (:func:`faultslip.models.fault_2d.cost.fault_2d_first_run`); unchanged where 0."""
    extra, why = one_off
    if extra <= 0:
        return what, seconds
    return f"{what}, {extra:.2g} s of it {why}", seconds + extra


def one_after_another(what: str, estimates: list[Estimate]) -> Estimate:
    """Runs made one after another: their CPU time and disk summed, the largest memory any holds at once, and where
    any lies outside its cost model's fit (so that :func:`check` refuses the whole as it would that run)."""
    outside = tuple(dict.fromkeys(sentence for e in estimates for sentence in e.outside_fit))
    return Estimate(what, memory=max(e.memory for e in estimates), disk=sum(e.disk for e in estimates),
                    seconds=sum(e.seconds for e in estimates), output=estimates[0].output, outside_fit=outside,
                    imports=tuple(dict.fromkeys(name for e in estimates for name in e.imports)))


def rungs_estimate(what: str, rungs: dict) -> Estimate:
    """A ladder's rungs run one after another (:func:`one_after_another`), each named with its own CPU time in
    ``what``: ``rungs`` maps a rung's name to its estimate."""
    return one_after_another(f"{what}, its rungs one after another: " + "; ".join(
        f"{name} ({_duration(rung.seconds)}: {rung.what})" for name, rung in rungs.items()), list(rungs.values()))


def netcdf_disk(raw_bytes: float, variables: int, compression: str = "zlib") -> float:
    """Disk bytes of a netCDF4 file holding ``raw_bytes`` of data in ``variables`` variables."""
    return raw_bytes * (1.0 if compression == "none" else ZLIB_RATIO) + NETCDF_OVERHEAD + NETCDF_PER_VARIABLE * variables


#: CPU seconds a sweep to a file spends beside its cells, once: creating the netCDF file and its chunk map, its
#: ledger, and sealing it with its checksums. Without it a small study's estimate was a third of its CPU, or less
#: (a 305-cell closed-form study: 1 ms against 23 ms). The median of a one-cell seed-law study's sweeps less its
#: cell's own estimate, anchored to the "families" machine reference (benchmarks/sweep_estimates.py writes it;
#: tests/capabilities/contract/test_families.py checks it against that file).
SWEEP_FILE_SECONDS = 0.02298


def study_estimate(study, output, workers: int, chunk_cells: int, compression: str = "zlib",
                   streamed: bool = False, cells: int | None = None) -> Estimate:
    """Memory, disk and time of a sweep, from its shape alone (nothing is allocated). ``streamed``: a run to a
    file, which first computes one cell where the family does not declare its outputs' layout
    (``study.layout_seconds()``), and then every cell again in its block; a run to a file also spends
    :data:`SWEEP_FILE_SECONDS` on the file. ``cells``: only that many of its cells run (a reproduction's sample),
    each its own block."""
    cells = float(study.size if cells is None else cells)
    outputs = 17
    raw = cells * outputs * 8.0
    disk = netcdf_disk(raw, outputs + len(study.dims), compression)
    rate = max(workers, 1) / study.seconds_per_cell()
    block = min(cells, float(chunk_cells))
    memory = block * 40 * 8.0 * (max(workers, 1) + 1)  # ~40 grid-sized temporaries per block in flight
    # the workers start together: each spends its one-off setup once (Study.seconds_per_worker)
    once = study.layout_seconds() if streamed else 0.0  # the layout's cell, and the file's own cost
    if output is not None:
        once += machine.on_this_machine(SWEEP_FILE_SECONDS, "families")
    # its Dataset in memory, or the netCDF file it streams its blocks into, read back lazily only where the command
    # counts its cells by flag (a closed-form study's command never imports xarray and dask.array, 0.4 s), and
    # what its family's cells import where they run
    read_back = output is None or study.cells.counted(study)
    imports = (*(DATASET_IMPORTS if read_back else ()), *(("netCDF4",) if output is not None else ()),
               *study.imports())
    return Estimate(what=f"this sweep of {cells:.3g} cells on {max(workers, 1)} worker{'s' * (workers > 1)}",
                    memory=memory, disk=disk, seconds=cells / rate + study.seconds_per_worker() + once,
                    output=output, workers=max(workers, 1),
                    cpu_seconds=cells * study.seconds_per_cell() + max(workers, 1) * study.seconds_per_worker()
                    + once, imports=imports)


#: Bytes held per cell of a map's raster (coordinates, unit vectors, nearest index and distance, four maps).
MAP_BYTES_PER_CELL = 200.0
#: Bytes per densified trace point (unit vector, owner, k-d tree), and cells a second through the tree.
MAP_BYTES_PER_POINT, MAP_CELLS_PER_SECOND = 120.0, 2e6


def map_estimate(cells: float, trace_points: float, output=None, model_seconds: float = 0.0) -> Estimate:
    """Memory, disk and time of a map of ``cells`` raster cells against ``trace_points`` densified trace points,
    and ``model_seconds`` of its predictions (a rate-and-state map's cycles, estimated by its caller)."""
    return Estimate(what=f"this map of {cells:.3g} cells", memory=cells * MAP_BYTES_PER_CELL
                    + trace_points * MAP_BYTES_PER_POINT, disk=netcdf_disk(cells * 6 * 8.0, 12) if output else 0.0,
                    seconds=(cells + trace_points) / MAP_CELLS_PER_SECOND + model_seconds, output=output)


#: The per-unit cost models the families declare (each family's cost.py says what its unit is), fitted on each
#: family's example by ``benchmarks/family_costs.py``.
FAMILY_COSTS_FILE = "family_costs.json"


@lru_cache(maxsize=1)
def family_costs() -> dict:
    """The fitted per-unit costs: family -> entry -> {unit, overhead (s), seconds_per_unit (s), fitted_on}."""
    table = read_bundled_table(FAMILY_COSTS_FILE, "the families' cost models", "benchmarks/family_costs.py")
    if not isinstance(table.get("families"), dict):
        raise InputError(f"{FAMILY_COSTS_FILE} has no families; rerun benchmarks/family_costs.py")
    return table


def fitted_estimate(family: str, entry: str, units: float, what: str, memory: float = 0.0, disk: float = 0.0,
                    output=None, imports: tuple = ()) -> Estimate:
    """An estimate from a family's fitted cost model: overhead + seconds_per_unit x ``units``.

    Parameters
    ----------
    family, entry : str
        The family and its cost entry ("simulate", "run:averaging", ...), as ``data/family_costs.json`` has them.
    units : float
        The work, in the entry's unit (cycles, simulated seconds, block-events).
    what : str
        What is estimated, for the budget's sentence.
    memory, disk : float
        Bytes held at once and written (B).
    output : path, optional
        Where the disk bytes go.
    imports : tuple of str
        The modules the run imports where it runs (:attr:`Estimate.imports`).

    Returns
    -------
    Estimate
        Its seconds are this machine's now (:func:`faultslip.io.machine.factor`).
    """
    return Estimate(what=what, memory=memory, disk=disk,
                    seconds=machine.on_this_machine(fitted_seconds(family, entry, units), "families"),
                    output=output, imports=tuple(imports))


def fitted_seconds(family: str, entry: str, units: float) -> float:
    """overhead + seconds_per_unit x ``units`` of a family's fitted cost entry (``data/family_costs.json``), in the
    seconds of the machine state it was fitted in (:func:`fitted_estimate` carries them to this one's)."""
    fitted = family_costs()["families"].get(family, {}).get(entry)
    if not isinstance(fitted, dict):
        raise InputError(f"{family}: no fitted cost model for {entry}; rerun benchmarks/family_costs.py")
    return float(fitted["overhead"]) + float(fitted["seconds_per_unit"]) * max(float(units), 0.0)
