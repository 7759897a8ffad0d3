"""Sweep commands: sweep (with --retry-failed), convert, reproduce. Kept apart from the map command, so that a
sweep's start-up imports nothing of maps, hazard or their figures (a whole command's time is what the second
worker is measured on, benchmarks/sweep_scale.py)."""

from __future__ import annotations

import json
import math
import sys

from faultslip.cli.common import _workers
from faultslip.cli.printing import _emit_estimate, _progress
from faultslip.errors import FaultslipError
from faultslip.io import budget
from faultslip.io.convert import zarr_to_netcdf
from faultslip.io.processes import retain_freed_memory
from faultslip.studies.grid import load_study
from faultslip.studies.streaming import (cell_counts, check_study_output, choose_execution, default_chunk_cells,
                                         output_format, reproduce, retry_failed, run_study, sweep_estimate)


def cmd_sweep(args) -> int:
    retain_freed_memory()  # this process computes blocks too (in process, or as the pool's parent)
    study = load_study(args.study)
    inputs = [args.study, study.scene.path]
    if args.retry_failed:
        if args.estimate:
            raise FaultslipError("--estimate estimates a whole sweep; --retry-failed reruns the cells a finished "
                                 "one's ledger lists: give one of them")
        return _retry_failed(args, study)
    file_format = output_format(args.output, args.format)
    if args.chunks is not None and not 1 <= args.chunks <= 10**9:
        raise FaultslipError(f"--chunks must be a number of cells from 1 to 1e9, got {args.chunks}")
    chunk_cells = args.chunks or default_chunk_cells(study)
    # at least this many chunks (whole trailing dimensions may make more); known without listing them
    chunk_count = -(-study.size // chunk_cells)
    workers = (args.workers or 2) if args.scheduler else _workers(args, chunk_count)
    if args.estimate:  # each cell's cost from its family's cost model, before any output is checked or cell runs
        return _emit_estimate(sweep_estimate(study, args.output, workers, chunk_cells, args.scheduler,
                                             args.compression), args.json)
    # estimated on the workers the run will use: a small study runs in this process whatever --workers says
    working = choose_execution(study, chunk_count, workers, args.scheduler)[0]
    # --resume continues into the same output: an existing final file is still refused without --overwrite
    output = check_study_output(args.output, file_format, inputs=inputs, overwrite=args.overwrite)
    budget.check(budget.study_estimate(study, output, working, chunk_cells, args.compression, streamed=True),
                 args.allow_large)
    summary = run_study(study, output, chunk_cells=chunk_cells, scheduler=args.scheduler, workers=workers,
                        resume=args.resume, progress=_progress("sweep", not args.json, "chunk"),
                        compression=args.compression, overwrite=args.overwrite, inputs=inputs,
                        file_format=file_format)
    counts = cell_counts(output, file_format, study.tolerance) if study.cells.counted(study) else {}
    if args.json:
        document = {"output": summary["output"], "cells": summary["cells"], "blocks": summary["blocks"],
                    "resumed_blocks": summary["resumed_blocks"], "executor": summary["executor"],
                    "wall_time": {"value": summary["seconds"], "units": "s"},
                    "dimensions": {name: len(values) for name, values in study.dims.items()},
                    "notes": getattr(args, "notes", []) + ([f"base scene: {study.scene.origin}"]
                                                           if study.scene.origin else [])}
        if counts:
            document["cells_by_flag"] = counts
        print(json.dumps(document, indent=2))
    else:
        print(f"faultslip sweep: {study.name}")
        print(f"  {summary['cells']} cells ({' x '.join(f'{n} {len(v)}' for n, v in study.dims.items())}) in "
              f"{_count(summary['blocks'], 'chunk')}, {_where(summary['executor'])}"
              + (f", {summary['resumed_blocks']} reused" if summary["resumed_blocks"] else ""))
        for line in _count_lines(counts, study):
            print(f"  {line}")
        print(f"  wrote {summary['output']} in {summary['seconds']:.2f} s")
    return _failed_cells(summary)


def _failed_cells(summary: dict) -> int:
    """Say how many cells failed and where they are listed (exit 1), or nothing (exit 0)."""
    if not summary["failed_cells"]:
        return 0
    print(f"faultslip sweep: {summary['failed_cells']} cells failed and hold fill values; {summary['failure_ledger']} "
          "lists each with its reason; fix the cause and run the same command with --retry-failed", file=sys.stderr)
    return 1


def _retry_failed(args, study) -> int:
    """sweep --retry-failed: the ledger's cells computed again into the existing output."""
    if args.resume:
        raise FaultslipError("--retry-failed reruns the failed cells of a finished study; --resume continues an "
                             "interrupted one: give one of them")
    file_format = output_format(args.output, args.format)
    summary = retry_failed(study, args.output, scheduler=args.scheduler, workers=args.workers or 2,
                           progress=_progress("sweep", not args.json, "cell"), file_format=file_format)
    if args.json:
        print(json.dumps({key: summary[key] for key in ("output", "retried", "recovered", "still_failed",
                                                        "failure_ledger", "executor")}
                         | {"wall_time": {"value": summary["seconds"], "units": "s"}}, indent=2))
    else:
        print(f"faultslip sweep --retry-failed: {study.name}")
        print(f"  {summary['retried']} failed cells computed again, {_where(summary['executor'])}: "
              f"{summary['recovered']} now hold values, {summary['still_failed']} failed again")
        print(f"  wrote {summary['output']} in {summary['seconds']:.2f} s")
    return _failed_cells({"failed_cells": summary["still_failed"], "failure_ledger": summary["failure_ledger"]})


def _count_lines(counts: dict, study) -> list[str]:
    """What a sweep found (its cells by each flag), and any cell that needs attention, in sentences."""
    lines = []
    for name, by_meaning in counts.items():
        if isinstance(by_meaning, dict):
            found = ", ".join(f"{count} {meaning.replace('_', ' ')}" for meaning, count in by_meaning.items() if count)
            lines.append(f"{name}: {found or 'no cell'}")
    if counts.get("unbounded_error_cells"):
        lines.append(f"estimated relative error unbounded in {counts['unbounded_error_cells']} cells (a model error "
                     "outside its calibration; model_error holds each cell's); largest elsewhere "
                     f"{counts['largest_bounded_estimated_relative_error']:.2g}")
    elif "largest_estimated_relative_error" in counts:
        lines.append(f"largest estimated relative error {counts['largest_estimated_relative_error']:.2g}")
    if counts.get("above_tolerance"):
        lines.append(f"note: {counts['above_tolerance']} cells' estimated error exceeds the tolerance "
                     f"{study.tolerance:g}; estimated_relative_error holds each cell's")
    failed = sum(by_meaning.get("solver_failed", 0) for by_meaning in counts.values() if isinstance(by_meaning, dict))
    if failed:
        lines.append(f"warning: the solver failed in {failed} cells (method flag solver_failed, outputs NaN); "
                     "rerun with another method or a smaller tolerance")
    return lines


def cmd_convert(args) -> int:
    workers = args.workers or 2
    summary = zarr_to_netcdf(args.store, args.output, workers=workers, overwrite=args.overwrite,
                             allow_large=args.allow_large, progress=_progress("convert", not args.json, "chunk"))
    if args.json:
        print(json.dumps(summary | {"seconds": {"value": summary["seconds"], "units": "s"}}, indent=2))
    else:
        print(f"faultslip convert: {summary['input']} -> {summary['output']}: {summary['variables']} variables, "
              f"{_count(summary['chunks'], 'chunk')} on {_count(summary['workers'], 'worker')} in "
              f"{summary['seconds']:.2f} s")
    return 0


def cmd_reproduce(args) -> int:
    workers = _workers(args)
    result = reproduce(args.file, output=args.output, workers=(args.workers or 2) if args.scheduler else workers,
                       overwrite=args.overwrite, allow_large=args.allow_large, cells=args.cells, seed=args.seed,
                       scheduler=args.scheduler)
    if args.json:
        print(json.dumps({key: (None if isinstance(value, float) and not math.isfinite(value) else value)
                          for key, value in result.items() if key != "differences"}
                         | {"differences": {k: (v if math.isfinite(v) else None) for k, v in result["differences"].items()}},
                         indent=2))
    else:
        verdict = "matches" if result["matches"] else "DIFFERS"
        if "sample_seed" in result:  # a spot check
            print(f"faultslip reproduce: {args.file} {verdict} (largest relative difference "
                  f"{result['largest_difference']:.3g} over {result['cells']} of its {result['of_cells']} cells, drawn "
                  f"with --seed {result['sample_seed']}; the other cells and the file's attributes are checked by its "
                  "checksum)")
        else:
            print(f"faultslip reproduce: {args.file} {verdict} (largest relative difference "
                  f"{result['largest_difference']:.3g} over {result['cells']} cells)")
        checksum = {"differs": "the file does not match the checksum written with it: it changed after writing",
                    "damaged": "the file has lost its checksum, or its checksum attribute is damaged: it changed "
                               "after writing",
                    "absent": "the file carries no checksum (an older faultslip wrote it): it is compared unchecked"}
        if result["checksum"] in checksum:
            print(f"  {checksum[result['checksum']]}")
        for name, value in result["differences"].items():
            print(f"  {name:26s} {value:.3g}")
        for label, key in (("missing from the file", "missing"), ("not reproduced (extra in the file)", "extra"),
                           ("attributes that differ", "attribute_differences")):
            if result[key]:
                print(f"  {label}: {', '.join(result[key])}")
    return 0 if result["matches"] else 1


def _count(number, noun: str) -> str:
    """'1 chunk', '3 chunks'."""
    return f"{number} {noun}{'' if number == 1 else 's'}"


def _where(executor: str) -> str:
    """How a sweep ran, as a phrase: 'in this process', 'on a process pool (2 workers)', ..."""
    return "in this process" + executor.removeprefix("in-process") if executor.startswith("in-process") else \
        f"on {executor}"
