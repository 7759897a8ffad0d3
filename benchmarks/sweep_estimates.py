"""Each family's example study: what its sweep's estimate says (the budget's, and 'faultslip sweep --estimate''s)
against the CPU the sweep takes, one worker, in this process.

    python benchmarks/sweep_estimates.py

Writes ``benchmarks/results/sweep_estimates.json``. A cell-by-cell family (PerCell) estimates each cell by its own
cost model (Family.estimate) over the base scene and the grid's corners; the vectorised and discretised families
by their cells' own. The long dipping-fault study (``configs/study_bp3_dip.toml``, about 12 min) runs with
``--all``.
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(ROOT))

from faultslip.contract.registry import families  # noqa: E402
from faultslip.io import budget  # noqa: E402
from faultslip.studies.grid import load_study  # noqa: E402
from faultslip.studies.streaming import default_chunk_cells, run_study  # noqa: E402
from provenance import stamp  # noqa: E402

OUT = HERE / "results" / "sweep_estimates.json"


def measure(name: str) -> dict:
    """One study: its estimate on one worker, and the CPU of the sweep to a netCDF file in this process."""
    study = load_study(ROOT / "configs" / name)
    chunk = default_chunk_cells(study)
    with tempfile.TemporaryDirectory() as folder:
        output = Path(folder) / "study.nc"
        estimate = budget.study_estimate(study, output, 1, chunk, "zlib", streamed=True)
        started = time.process_time()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            run_study(study, output, chunk_cells=chunk, workers=1)
        cpu = time.process_time() - started
    return {"study": name, "family": study.family.name, "cells": study.size, "estimate_seconds": estimate.seconds,
            "cpu_seconds": cpu, "ratio": estimate.seconds / cpu if cpu > 0 else None}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--all", action="store_true", help="the dipping-fault study too (about 12 min)")
    args = parser.parse_args(argv)
    names = [family.example.study for family in families().values() if family.example is not None]
    names += ["study_rate_state.toml", "study_lab_glass.toml"] + (["study_bp3_dip.toml"] if args.all else [])
    rows = []
    for name in names:
        rows.append(measure(name))
        row = rows[-1]
        print(f"{name:32s} {row['cells']:6d} cells  estimate {row['estimate_seconds']:8.3f} s  CPU "
              f"{row['cpu_seconds']:8.3f} s  ratio {row['ratio']:.2f}", flush=True)
    OUT.write_text(json.dumps({**stamp(), "rows": rows}, indent=1) + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
