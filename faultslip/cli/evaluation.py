"""Method evaluation commands: bench, stability."""

from __future__ import annotations

import faultslip

import json
from pathlib import Path

from faultslip.cli.common import _locked, _number, _output_dir, _outputs, _workers
from faultslip.cli.printing import _emit, _emit_estimate, _progress
from faultslip.io.outputs import FIGURE_SUFFIXES
from faultslip import ranges
from faultslip.errors import FaultslipError, InputError
from faultslip.evaluation import bench, rate_state_bench, stability
from faultslip.evaluation.bench import all_scenes, markdown, method_names, work_precision
from faultslip.evaluation.stability import DAMPING_RATIOS, METHODS, RATIOS, SEPARATIONS, failure_text, stability_map
from faultslip.io.atomic import save_figure, write_text_atomic
from faultslip.io.netcdf import write_dataset


def cmd_bench(args) -> int:
    for name in args.scene or []:
        if name not in all_scenes():
            raise InputError(f"unknown bench scene {name!r}; allowed: {', '.join(all_scenes())}")
    for name in args.method or []:
        if name not in method_names():
            raise InputError(f"unknown bench method {name!r}; allowed: {', '.join(method_names())}")
    seed, asked = _held_out_seed(args, bench.HELD_OUT_SEED)
    out = Path(_output_dir(args, "bench", [f"work_precision.{ext}" for ext in ("nc", "md", "png")]))
    workers = _workers(args)
    with _locked(out / "work_precision.nc"):
        dataset = work_precision(quick=args.quick, workers=workers, scenes=args.scene, methods=args.method,
                                 progress=_progress("bench", not args.json))
        table = markdown(dataset)
        held = None
        if asked or not (args.quick or args.scene or args.method):  # the declared errors, on scenes not set on
            held = bench.declared_error_summary(bench.declared_error_check(
                bench.random_scenes(seed, bench.HELD_OUT_SCENES), workers=workers,
                progress=_progress("held-out scenes", not args.json)))
            table += (f"\n\nThe event-driven integrators' declared errors on {bench.HELD_OUT_SCENES} random scenes "
                      f"(seed {seed}) they were not set on, rtol 1e-3 to 1e-12, "
                      f"{bench.CHECK_CYCLES} cycles a run:\n\n" + bench.declared_error_text(held))
        write_dataset(dataset, out / "work_precision.nc")
        write_text_atomic(out / "work_precision.md", table + "\n")
        save_figure(bench.chart(dataset), out / "work_precision.png", dpi=120)
    files = [str(out / f"work_precision.{ext}") for ext in ("nc", "md", "png")]
    if args.json:
        print(json.dumps({"files": files, "wall_time": {"value": dataset.attrs["total_wall_time_s"], "units": "s"},
                          "scenes": [str(s) for s in dataset["scene"].values],
                          "methods": [str(m) for m in dataset["method"].values],
                          **({"declared_errors_held_out": held, "held_out_seed": seed} if held else {})}, indent=2))
    else:
        print(table.split("\n\nOutcome")[0])
        if held:
            print("\nDeclared errors on the held-out scenes:\n" + bench.declared_error_text(held))
        print(f"\nwrote {', '.join(files)} in {dataset.attrs['total_wall_time_s']:.1f} s")
    return 0


def _held_out_seed(args, shipped: int) -> tuple[int, bool]:
    """(the held-out draw's seed, whether --held-out-seed asked for it)."""
    if args.held_out_seed is None:
        return shipped, False
    if args.held_out_seed < 0:
        raise InputError(f"--held-out-seed must be 0 or more, got {args.held_out_seed}")
    return args.held_out_seed, True


def cmd_stability(args) -> int:
    def floats(values, default):
        return tuple(sorted(_number(v, "grid value") for v in values)) if values else default

    for name in args.method or []:
        if name not in METHODS:
            raise FaultslipError(f"unknown stability method {name!r}; allowed: {', '.join(METHODS)}")
    ratios, dampings, separations = (floats(args.ratio, RATIOS), floats(args.damping_ratio, DAMPING_RATIOS),
                                     floats(args.separation, SEPARATIONS))
    # the same ranges as the default grid (zeta <= 0: negative or no damping, rows without a critical rate)
    if any(not 0 < r <= 100 for r in ratios) or any(not 1 <= s <= 1e12 for s in separations):
        raise FaultslipError("--ratio must lie in (0, 100] (theta / theta_c) and --separation in [1, 1e12] (stick "
                             "over slip duration)")
    if any(not -1 < z < 1 for z in dampings):
        raise FaultslipError("--damping-ratio must lie in (-1, 1)")
    out = Path(_output_dir(args, "stability", [f"stability.{ext}" for ext in ("nc", "md", "png")]))
    workers = _workers(args)
    with _locked(out / "stability.nc"):
        dataset = stability_map(ratios, dampings, separations, tuple(args.method or METHODS),
                                workers=workers, progress=_progress("stability", not args.json))
        text = failure_text(dataset)
        write_dataset(dataset, out / "stability.nc")
        write_text_atomic(out / "stability.md", text + "\n")
        save_figure(stability.chart(dataset), out / "stability.png", dpi=120)
    files = [str(out / f"stability.{ext}") for ext in ("nc", "md", "png")]
    if args.json:
        print(json.dumps({"files": files, "failure_regions": text.splitlines(),
                          "wall_time": {"value": dataset.attrs["total_wall_time_s"], "units": "s"}}, indent=2))
    else:
        print(text)
        print(f"\nwrote {', '.join(files)} in {dataset.attrs['total_wall_time_s']:.1f} s")
    return 0


def cmd_rate_state_bench(args) -> int:
    names = [f"work_precision_rate_state.{ext}" for ext in ("nc", "md", "png")] + ["failure_map_rate_state.nc"]
    seed, asked = _held_out_seed(args, rate_state_bench.HELD_OUT_SEED)
    out = Path(_output_dir(args, "bench", names))
    workers = _workers(args)
    ratios = tuple(float(r) for r in (1e-6, 1e-4, 1e-2, 0.3, 0.99)) if args.quick else rate_state_bench.MAP_RATIOS
    with _locked(out / names[0]):
        work = rate_state_bench.work_precision(quick=args.quick, workers=workers,
                                               progress=_progress("rate-state bench", not args.json))
        failures = rate_state_bench.failure_map(ratios, workers=workers,
                                                progress=_progress("failure map", not args.json))
        table = rate_state_bench.markdown(work)
        text = rate_state_bench.failure_text(failures)
        held = None if args.quick and not asked else rate_state_bench.declared_error_summary(
            rate_state_bench.declared_error_check(
                rate_state_bench.random_faults(seed, rate_state_bench.HELD_OUT_FAULTS), workers=workers,
                progress=_progress("held-out faults", not args.json)))
        unseen = "" if held is None else (
            f"\n\nOn {rate_state_bench.HELD_OUT_FAULTS} random faults held out from the declared errors' fit "
            f"(seed {seed}; benchmarks/rate_state_calibration.py):\n\n" + rate_state_bench.declared_error_text(held))
        write_dataset(work, out / names[0])
        write_dataset(failures, out / names[3])
        write_text_atomic(out / names[1], table + "\n\nWhere each method fails (rtol 1e-7, "
                          f"{rate_state_bench.STEP_BUDGET} steps):\n\n" + text + unseen + "\n")
        save_figure(rate_state_bench.chart(work, failures), out / names[2], dpi=120)
    files = [str(out / name) for name in names]
    seconds = work.attrs["total_wall_time_s"] + failures.attrs["total_wall_time_s"]
    if args.json:
        print(json.dumps({"files": files, "failure_regions": text.splitlines(),
                          "wall_time": {"value": seconds, "units": "s"},
                          **({"declared_errors_held_out": held, "held_out_seed": seed} if held else {})}, indent=2))
    else:
        print(table)
        print("\nWhere each method fails:\n" + text + unseen)
        print(f"\nwrote {', '.join(files)} in {seconds:.1f} s")
    return 0


def cmd_model_error(args) -> int:
    """The shipped calibration of one slider against the 2-D fault, a scene's declared error, the chart."""
    if args.estimate:  # the ladder's cost models, before any rung runs or any output is checked
        if not args.scene:
            raise InputError("model-error --estimate estimates a fault scene's ladder: give the scene")
        return _emit_estimate(faultslip.models.estimate(args.scene, "ladder", include_3d=args.include_3d), args.json)
    plot = _outputs(args, {"plot": ("--plot", FIGURE_SUFFIXES)}, [args.scene] if args.scene else [])["plot"]
    tolerance = ranges.check_tolerance(args.tolerance, "--tolerance")
    result = faultslip.models.model_error(args.scene, tolerance, include_3d=args.include_3d)
    report = result.report()
    if plot:
        with _locked(plot):
            save_figure(result.plot(), plot, dpi=150)
        report.note(f"model-error map drawn to {args.plot}")
    return _emit(report, args.json)


def cmd_predictability(args) -> int:
    """A catalogue's recurrence models tested (faultslip.hazard.catalog_predictability), and QuakeCaster's figure."""
    plot = _outputs(args, {"plot": ("--plot", FIGURE_SUFFIXES)}, [args.catalog])["plot"]
    result = faultslip.hazard.catalog_predictability(args.catalog, name=args.name, seed=args.seed)
    report = result.report(f"faultslip predictability: {args.catalog}" + (f" ({args.name})" if args.name else ""))
    if plot:
        with _locked(plot):
            save_figure(faultslip.plots.predictability_figure(result), plot, dpi=150)
        report.note(f"figure drawn to {args.plot}")
    return _emit(report, args.json)
