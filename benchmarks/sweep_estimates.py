"""Each family's example study: what its sweep's estimate says (the budget's, and 'faultslip sweep --estimate''s)
against the CPU the sweep takes, one worker, in this process.

    python benchmarks/sweep_estimates.py

Writes ``benchmarks/results/sweep_estimates.json``. A cell-by-cell family (PerCell) estimates each cell by its own
cost model (Family.estimate) over the base scene and the grid's corners; the vectorised and discretised families
by their cells' own. The long dipping-fault study (``configs/study_bp3_dip.toml``, about 12 min) runs with
``--all``.

It first measures what a sweep to a file costs beside its cells (faultslip.io.budget.SWEEP_FILE_SECONDS): a
one-cell study of the seed law, swept again and again, less that cell's own estimate, anchored to the "families"
machine reference as every cost model is; the estimates that follow use that measured cost. The estimates are
the command's, with the imports this process still owes (budget.with_imports); the CPU is the command's work:
that estimate (whose measuring imports them), the sweep, and the read-back that counts a study's cells by flag
where its family's cells are counted.
"""

from __future__ import annotations

import argparse
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
from faultslip.io import budget, machine  # noqa: E402
from faultslip.studies.grid import load_study  # noqa: E402
from faultslip.studies.streaming import cell_counts, default_chunk_cells, run_study  # noqa: E402
from provenance import stamp  # noqa: E402

OUT = HERE / "results" / "sweep_estimates.json"
#: The one-cell study whose sweeps measure the file's own cost: the seed law's closed form, one cell.
FILE_STUDY = '[study]\nbase = "{base}"\n[sweep]\ndamping_ratio = [0.1]\n'


def sweep_cpu(study, output: Path) -> float:
    """CPU seconds of one sweep of ``study`` to ``output``, one worker, in this process."""
    started = time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run_study(study, output, chunk_cells=default_chunk_cells(study), workers=1)
    return time.process_time() - started


def file_cost(repeats: int) -> dict:
    """A sweep's own cost beside its cells: the median CPU of ``repeats`` sweeps of a one-cell study (after two
    that import and warm up), less the cell's estimate, anchored to the machine reference."""
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "one_cell.toml"
        path.write_text(FILE_STUDY.format(base=(ROOT / "configs" / "san_andreas_1906.toml").as_posix()),
                        encoding="utf-8")
        study = load_study(path)
        samples = [sweep_cpu(study, Path(folder) / f"sweep_{index}.nc") for index in range(repeats + 2)][2:]
        cell = study.size * study.seconds_per_cell() + study.layout_seconds()
    median = statistics.median(samples)
    factor = machine.factor("families")
    return {"study": FILE_STUDY.format(base="san_andreas_1906.toml"), "samples": samples, "median": median,
            "cell_estimate": cell, "machine_factor": factor, "anchored_seconds": (median - cell) / factor}


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
    names = [family.example.study for family in families().values() if family.example is not None]
    names += ["study_rate_state.toml", "study_lab_glass.toml"] + (["study_bp3_dip.toml"] if args.all else [])
    rows = []
    for name in names:
        rows.append(measure(name))
        row = rows[-1]
        print(f"{name:32s} {row['cells']:6d} cells  estimate {row['estimate_seconds']:8.3f} s  CPU "
              f"{row['cpu_seconds']:8.3f} s  ratio {row['ratio']:.2f}", flush=True)
    OUT.write_text(json.dumps({**stamp(), "sweep_file": fixed, "rows": rows}, indent=1) + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
