"""Each family's example study: what its sweep's estimate says (the budget's, and 'faultslip sweep --estimate''s)
against the CPU the sweep takes, one worker, in this process.

    python benchmarks/sweep_estimates.py

Writes ``benchmarks/results/sweep_estimates.json``. A cell-by-cell family (PerCell) estimates each cell by its own
cost model (Family.estimate) over the base scene and the grid's corners; the vectorised and discretised families
by their cells' own. The long dipping-fault study (``configs/study_bp3_dip.toml``, about 12 min) runs with
``--all``.

It first measures what a sweep to a file costs beside its cells (faultslip.io.budget.SWEEP_FILE_SECONDS): a
one-cell study of the seed law, swept again and again, less that cell's own estimate, anchored to the "families"
machine reference as every cost model is; then what a simulated rate-and-state cell costs beside its cycles
(faultslip.fault.rate_state_cells.CELL_OVERHEAD), from a study of 120 cheap cells less their cycles' modelled
cost. The estimates that follow use those measured costs. The estimates are
the command's, with the imports this process still owes (budget.with_imports); the CPU is the command's work:
that estimate (whose measuring imports them), the sweep, and the read-back that counts a study's cells by flag
where its family's cells are counted.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import statistics
import sys
import tempfile
import time
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(ROOT))

from faultslip.contract.registry import families  # noqa: E402
from faultslip.fault import rate_state_cells  # noqa: E402
from faultslip.io import budget, machine  # noqa: E402
from faultslip.studies.grid import load_study  # noqa: E402
from faultslip.studies.streaming import cell_counts, default_chunk_cells, run_study  # noqa: E402
from provenance import stamp  # noqa: E402

OUT = HERE / "results" / "sweep_estimates.json"
#: The one-cell study whose sweeps measure the file's own cost: the seed law's closed form, one cell.
FILE_STUDY = '[study]\nbase = "{base}"\n[sweep]\ndamping_ratio = [0.1]\n'
#: The rate-and-state study whose sweeps measure a simulated cell's fixed cost: 120 distinct unstable cells of the
#: 1906 fault with SEAS BP1 friction (K / K_c 0.2 to 0.99), five cycles each.
CELL_STUDY = ('[study]\nbase = "{base}"\ncycles = 5\n[sweep]\ncritical_slip = {{ logspace = ["3 cm", "8 cm", 40] }}\n'
              'a = [0.010, 0.011, 0.012]\n')


def sweep_cpu(study, output: Path) -> float:
    """CPU seconds of one sweep of ``study`` to ``output``, one worker, in this process."""
    started = time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run_study(study, output, chunk_cells=default_chunk_cells(study), workers=1)
    return time.process_time() - started


def _sweeps(template: str, base: str, repeats: int, warm_ups: int, estimated=contextlib.nullcontext) -> tuple:
    """(CPU samples, the cells' estimate, cells) of ``repeats`` sweeps of the study ``template`` over the config
    ``base``, after ``warm_ups`` that import and warm up; the estimate is read inside ``estimated()``."""
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "study.toml"
        path.write_text(template.format(base=(ROOT / "configs" / base).as_posix()), encoding="utf-8")
        study = load_study(path)
        samples = [sweep_cpu(study, Path(folder) / f"sweep_{index}.nc")
                   for index in range(repeats + warm_ups)][warm_ups:]
        with estimated():
            fresh = load_study(path)  # a study keeps the cost it read first
            cells = fresh.size * fresh.seconds_per_cell() + fresh.layout_seconds()
    return samples, cells, study.size


def file_cost(repeats: int) -> dict:
    """A sweep's own cost beside its cells: the median CPU of ``repeats`` sweeps of a one-cell study (after two
    that import and warm up), less the cell's estimate, anchored to the machine reference."""
    samples, cell, _ = _sweeps(FILE_STUDY, "san_andreas_1906.toml", repeats, 2)
    median = statistics.median(samples)
    factor = machine.factor("families")
    return {"study": FILE_STUDY.format(base="san_andreas_1906.toml"), "samples": samples, "median": median,
            "cell_estimate": cell, "machine_factor": factor, "anchored_seconds": (median - cell) / factor}


@contextlib.contextmanager
def _without_cell_overhead():
    saved, rate_state_cells.CELL_OVERHEAD = rate_state_cells.CELL_OVERHEAD, 0.0
    try:
        yield
    finally:
        rate_state_cells.CELL_OVERHEAD = saved


def rate_state_cell_cost(repeats: int) -> dict:
    """What a simulated rate-and-state cell costs beside its cycles' steps (rate_state_cells.CELL_OVERHEAD): the
    median CPU of ``repeats`` sweeps of :data:`CELL_STUDY` (after one that imports and warms up), less its
    cycles by the integrators' cost model and the file's measured cost, per cell, anchored to the machine
    reference. Its cells' cycles are cheap (the C stepper, a few thousand steps each), so the fixed cost shows."""
    samples, cycles, count = _sweeps(CELL_STUDY, "san_andreas_1906_rate_state.toml", repeats, 1,
                                     _without_cell_overhead)
    median = statistics.median(samples)
    factor = machine.factor("families")
    per_cell = (median - cycles - machine.on_this_machine(budget.SWEEP_FILE_SECONDS, "families")) / count
    return {"study": CELL_STUDY.format(base="san_andreas_1906_rate_state.toml"), "cells": count,
            "samples": samples, "median": median, "cycles_estimate": cycles, "machine_factor": factor,
            "anchored_seconds_per_cell": max(per_cell, 0.0) / factor}


def measure(name: str) -> dict:
    """One study: its estimate on one worker, and the CPU of what 'faultslip sweep' does with it in this process:
    the estimate (whose measuring imports what the run will need), the sweep to a netCDF file, and the read-back
    that counts its cells by flag where the family's cells are counted."""
    study = load_study(ROOT / "configs" / name)
    chunk = default_chunk_cells(study)
    with tempfile.TemporaryDirectory() as folder:
        output = Path(folder) / "study.nc"
        started = time.process_time()
        estimate = budget.with_imports(budget.study_estimate(study, output, 1, chunk, "zlib", streamed=True))
        sweep_cpu(study, output)
        if study.cells.counted(study):
            cell_counts(output, tolerance=study.tolerance)
        cpu = time.process_time() - started
    return {"study": name, "family": study.family.name, "cells": study.size, "estimate_seconds": estimate.seconds,
            "cpu_seconds": cpu, "ratio": estimate.seconds / cpu if cpu > 0 else None}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--all", action="store_true", help="the dipping-fault study too (about 12 min)")
    parser.add_argument("--repeats", type=int, default=15, help="sweeps of the one-cell study (default 15)")
    args = parser.parse_args(argv)
    fixed = file_cost(args.repeats)
    budget.SWEEP_FILE_SECONDS = fixed["anchored_seconds"]  # the estimates below use what this run measured
    print(f"a sweep's file: {fixed['median'] * 1e3:.1f} ms of CPU (median of {args.repeats}), "
          f"{fixed['anchored_seconds'] * 1e3:.1f} ms anchored", flush=True)
    cell = rate_state_cell_cost(max(args.repeats // 5, 1))
    rate_state_cells.CELL_OVERHEAD = cell["anchored_seconds_per_cell"]
    print(f"a rate-and-state cell beside its cycles: {cell['anchored_seconds_per_cell'] * 1e3:.2f} ms anchored "
          f"({cell['cells']} cells, {cell['median']:.3f} s of CPU, {cell['cycles_estimate']:.3f} s of it their cycles' "
          "estimate)", flush=True)
    names = [family.example.study for family in families().values() if family.example is not None]
    names += ["study_rate_state.toml", "study_lab_glass.toml"] + (["study_bp3_dip.toml"] if args.all else [])
    rows = []
    for name in names:
        rows.append(measure(name))
        row = rows[-1]
        print(f"{name:32s} {row['cells']:6d} cells  estimate {row['estimate_seconds']:8.3f} s  CPU "
              f"{row['cpu_seconds']:8.3f} s  ratio {row['ratio']:.2f}", flush=True)
    OUT.write_text(json.dumps({**stamp(), "sweep_file": fixed, "rate_state_cell": cell, "rows": rows}, indent=1) + "\n",
                   encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
