"""The ``faultslip`` command line. Thin: it parses, calls the library, prints.

Every command that computes has ``--json``. Bad input exits with status 2 and
one sentence on stderr, never a traceback.
"""

from __future__ import annotations

import argparse
import json
import math
import sys

from faultslip import __version__
from faultslip.errors import FaultslipError

_FAULT_QUANTITIES = {
    # flag -> Fault argument
    "shear_modulus": "shear_modulus",
    "zone_width": "zone_width",
    "normal_stress": "normal_stress",
    "shear_stress": "shear_stress",
    "slip_rate": "slip_rate",
    "rupture_length": "rupture_length",
    "depth": "seismogenic_depth",
    "density": "density",
    "shear_wave_speed": "shear_wave_speed",
}


class _Parser(argparse.ArgumentParser):
    """argparse with a one-line error and exit status 2."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message} (see '{self.prog} --help')\n")


def _emit(report, as_json: bool) -> int:
    print(report.to_json() if as_json else report.to_text())
    return 0


def _outputs(args, specs, inputs=()):
    """Check every output option before any work; returns {attribute: Path or None}.

    ``specs`` maps an attribute of ``args`` to (label, allowed suffixes). Two options naming one
    file are refused too.
    """
    from faultslip.io.outputs import check_output, same_file

    checked = {}
    for attribute, (label, suffixes) in specs.items():
        value = getattr(args, attribute, None)
        checked[attribute] = None if value is None else check_output(
            value, label=label, suffixes=suffixes, inputs=inputs, overwrite=getattr(args, "overwrite", False))
    paths = [(a, p) for a, p in checked.items() if p is not None]
    for i, (first, a) in enumerate(paths):
        for second, b in paths[i + 1:]:
            if same_file(a, b):
                raise FaultslipError(f"{specs[first][0]} and {specs[second][0]} name the same file {str(a)!r}")
    return checked


def _locked(*paths):
    """Hold the output lock of every given path (None skipped) while the outputs are written."""
    import contextlib

    from faultslip.io.outputs import output_lock

    stack = contextlib.ExitStack()
    for path in paths:
        if path is not None:
            stack.enter_context(output_lock(path, " ".join(["faultslip"] + sys.argv[1:3])))
    return stack


def _output_dir(args, default, names):
    """Check an output folder and the files it will receive, before any work; create the folder."""
    from pathlib import Path

    from faultslip.io.outputs import check_output

    folder = check_output(args.output or default, label="-o", directory=True)
    for name in names:
        target = Path(folder) / name
        if target.exists() and not args.overwrite:
            raise FaultslipError(f"{str(target)!r} already exists; pass --overwrite to replace it")
        if target.is_dir():
            raise FaultslipError(f"{str(target)!r} is a folder; it cannot be written as a file")
    folder.mkdir(exist_ok=True)
    return folder


def _workers(args, tasks=None) -> int:
    """--workers capped at what helps; the cap is said on stderr (and in --json output)."""
    import os

    from faultslip.io.processes import usable_workers

    if args.workers is None:  # not given: as many as help, silently
        return usable_workers(os.cpu_count() or 1, tasks)[0]
    workers, note = usable_workers(args.workers, tasks)
    if note:
        args.notes = getattr(args, "notes", []) + [note]
        if not args.json:
            print(f"faultslip: note: {note}", file=sys.stderr)
    return workers


def _note_origin(report, *origins):
    for origin in origins:
        if origin:
            report.notes.insert(0, origin)


# --- handlers ---------------------------------------------------------------


def _tolerance(args):
    if getattr(args, "tolerance", None) is None:
        return None
    value = _number(args.tolerance, "tolerance")
    if not 0 < value < 1:
        from faultslip.errors import InputError

        raise InputError(f"tolerance must be a relative error between 0 and 1, got {args.tolerance}")
    return value


def cmd_run(args) -> int:
    from faultslip.fault.scene import load_scene, run_scene

    tolerance = _tolerance(args)
    return _emit(run_scene(load_scene(args.scene), method=args.method, tolerance=tolerance), args.json)


def cmd_fault(args) -> int:
    from faultslip.fault.scaling import Fault

    inputs = {target: getattr(args, flag) for flag, target in _FAULT_QUANTITIES.items() if getattr(args, flag) is not None}
    for key in ("mu_so", "mu_m", "damping_ratio"):
        if getattr(args, key) is not None:
            inputs[key] = getattr(args, key)
    if args.rate_coefficient is not None:
        inputs["b"] = args.rate_coefficient
    if args.rate_exponent is not None:
        inputs["d"] = args.rate_exponent
    fault = Fault(lithology=args.lithology, radiation_damping=args.radiation_damping, name=args.name, **_required(inputs))
    if args.observed_slip is not None:
        return _emit(fault.infer_kinetic_friction(args.observed_slip).report(), args.json)
    return _emit(fault.estimate(method=args.method or "auto", tolerance=_tolerance(args)).report(), args.json)


def _required(inputs: dict) -> dict:
    from faultslip.errors import InputError

    missing = [flag for flag in ("zone_width", "slip_rate") if flag not in inputs]
    if missing:
        raise InputError(f"missing {', '.join('--' + m.replace('_', '-') for m in missing)}, required for a fault estimate")
    return inputs


def cmd_materials(args) -> int:
    from faultslip.friction.materials import lithologies, presets

    preset_rows = []
    for preset in presets().values():
        row = {"name": preset.name, "material": preset.material, "condition": preset.condition,
               "lithology": preset.lithology, "stick_slip": preset.stick_slip, "source": preset.source}
        if preset.stick_slip:
            law = preset.rate_law
            row.update(mu_so=law.mu_so, mu_m=law.mu_m, b={"value": law.b, "units": f"s^{law.d:g}"}, d=law.d)
        else:
            row["friction"] = preset.friction
        if preset.material == "user fit":
            entry = preset.printed.get("registry", {})
            row.update(user_fit=True, standard_errors=entry.get("standard_errors"), intervals_95=entry.get("intervals_95"),
                       points=entry.get("points"), shear_modulus=({"value": entry["shear_modulus"], "units": "Pa"}
                                                                  if entry.get("shear_modulus") else None))
        if preset.normal_load is not None:
            row.update(
                normal_load={"value": preset.normal_load, "units": "N"},
                stiffness={"value": preset.stiffness, "units": "N/m"},
                mass={"value": preset.mass, "units": "kg"},
            )
        preset_rows.append(row)
    lith_rows = [
        {"name": lith.name, "shear_modulus": {"value": lith.shear_modulus, "units": "Pa"},
         "default_preset": lith.default_preset, "source": lith.source}
        for lith in lithologies().values()
    ]
    if args.json:
        print(json.dumps({"presets": preset_rows, "lithologies": lith_rows}, indent=2))
        return 0
    print("Presets (seed 003 Table I; W, K of its apparatus; M = W/g)")
    print(f"  {'name':<26}{'mu_so':>7}{'mu_m':>7}{'b (s^d)':>11}{'d':>8}{'W (N)':>9}{'K (N/m)':>11}{'M (kg)':>8}  source")
    for row in preset_rows:
        if row.get("user_fit"):
            continue
        if row["stick_slip"]:
            print(f"  {row['name']:<26}{row['mu_so']:>7.3g}{row['mu_m']:>7.3g}{row['b']['value']:>11.4g}{row['d']:>8.4g}"
                  f"{row['normal_load']['value']:>9.1f}{row['stiffness']['value']:>11.4g}{row['mass']['value']:>8.1f}  {row['source']}")
        else:
            print(f"  {row['name']:<26}  steady sliding, mu = {row['friction']:.2f} (no stick-slip)  {row['source']}")
    from faultslip.friction.registry import registry_path

    user = [row for row in preset_rows if row.get("user_fit")]
    print(f"\nUser fits ({registry_path()})" + ("" if user else ": none yet (faultslip fit DATA.csv --name NAME)"))
    for row in user:
        errors = row.get("standard_errors") or {}
        modulus = row.get("shear_modulus")
        print(f"  {row['name']:<26}{row['mu_so']:>7.3g}{row['mu_m']:>7.3g}{row['b']['value']:>11.4g}{row['d']:>8.4g}"
              f"  (+- {errors.get('mu_so', float('nan')):.2g}, {errors.get('mu_m', float('nan')):.2g}, "
              f"{errors.get('b', float('nan')):.2g}, {errors.get('d', float('nan')):.2g})"
              + (f"  G = {modulus['value'] / 1e5:.4g} bar" if modulus else "") + f"  {row['source']}")
    print("\nLithologies (shear modulus; default friction preset on a fault)")
    for row in lith_rows:
        print(f"  {row['name']:<14}G = {row['shear_modulus']['value'] / 1e5:.4g} bar  preset: "
              f"{row['default_preset'] or '(none: give mu_so, mu_m)'}  {row['source']}")
    return 0


def cmd_methods(args) -> int:
    from faultslip.dynamics.methods import describe_all

    rows = describe_all()
    if args.json:
        print(json.dumps({"methods": rows}, indent=2))
        return 0
    for row in rows:
        print(f"{row['name']}\n  friction laws: {row['friction_laws']}\n  valid where:   {row['domain']}\n"
              f"  cost:          {row['cost_model']}")
    return 0


def cmd_plot_rate_law(args) -> int:
    from faultslip.io.atomic import save_figure
    from faultslip.friction.materials import get_preset, table_i_presets
    from faultslip.plots.figures import rate_law_figure

    from faultslip.io.outputs import FIGURE_SUFFIXES

    output = _outputs(args, {"output": ("-o", FIGURE_SUFFIXES)})["output"]
    chosen = [get_preset(name) for name in args.preset] if args.preset else table_i_presets()
    for preset in chosen:
        preset.require_stick_slip()
    figure = rate_law_figure(chosen)
    with _locked(output):
        save_figure(figure, output, dpi=150)
    print(f"wrote {args.output}")
    return 0


def cmd_simulate(args) -> int:
    from faultslip.io import budget
    from faultslip.io.netcdf import write_dataset
    from faultslip.io.outputs import FIGURE_SUFFIXES
    from faultslip.fault.scene import CHOICES, load_scene
    from faultslip.dynamics.simulate import simulate, summary_report

    scene = load_scene(args.scene)
    outputs = _outputs(args, {"output": ("-o", (".nc",)), "plot": ("--plot", FIGURE_SUFFIXES)}, [scene.path])
    settings = scene.simulation
    if args.cycles is not None:
        if args.cycles < 1:
            raise FaultslipError(f"--cycles must be at least 1, got {args.cycles}")
        settings["cycles"] = args.cycles
    if args.slip_solver is not None:
        allowed = CHOICES[("simulation", "slip_solver")]
        if args.slip_solver not in allowed:
            raise FaultslipError(f"--slip-solver must be one of {', '.join(allowed)}, got {args.slip_solver!r}")
        settings["slip_solver"] = args.slip_solver
    if args.rtol is not None:
        rtol = _number(args.rtol, "--rtol")
        if not 1e-14 <= rtol < 1:
            raise FaultslipError(f"--rtol must lie in [1e-14, 1), got {args.rtol}")
        settings["rtol"] = rtol
    system = scene.slider()
    integrated = not system.is_linear or settings.get("slip_solver", "auto") not in ("auto", "analytic")
    budget.check(budget.simulation_estimate(settings.get("cycles", 100), settings.get("samples_per_slip", 64),
                                            integrated, outputs["output"]), args.allow_large)
    dataset = simulate(system, scene=scene.name, **settings)
    dataset.attrs["scene_text"] = scene.text
    report = summary_report(dataset, f"faultslip simulation: {scene.name}")
    _note_origin(report, scene.origin and f"scene: {scene.origin}")
    with _locked(outputs["output"], outputs["plot"]):
        if outputs["output"]:
            write_dataset(dataset, outputs["output"])
            report.note(f"time series and event table written to {args.output}")
        if outputs["plot"]:
            from faultslip.io.atomic import save_figure
            from faultslip.plots.figures import sawtooth_figure

            save_figure(sawtooth_figure(dataset), outputs["plot"], dpi=150)
            report.note(f"sawtooth record drawn to {args.plot}")
    return _emit(report, args.json)


def _system_from_args(args):
    from faultslip.errors import InputError
    from faultslip.fault.scene import load_scene
    from faultslip.dynamics.slider import SliderSystem

    if args.preset and getattr(args, "scene", None):
        raise InputError("give a preset or a scene, not both")
    if args.preset:
        zeta = 0.0 if args.damping_ratio is None else _number(args.damping_ratio, "damping ratio")
        return SliderSystem.from_preset(args.preset, loading_rate="1 1/s", damping_ratio=zeta)
    if getattr(args, "scene", None):
        system = load_scene(args.scene).slider()
        if args.damping_ratio is not None:
            from faultslip.dynamics.closed_form import dashpot_for_damping_ratio

            zeta = _number(args.damping_ratio, "damping ratio")
            system = system.with_(dashpot=float(dashpot_for_damping_ratio(zeta, system.stiffness, system.mass)))
        return system
    raise InputError("give --preset NAME (with --damping-ratio) or a scene file")


def _number(text, name):
    from faultslip.units import to_si

    return to_si(text, "dimensionless", name)


def cmd_critical(args) -> int:
    if args.table:
        return _critical_table(args)
    from faultslip.dynamics.critical import critical

    return _emit(critical(_system_from_args(args)).report(), args.json)


def _critical_table(args) -> int:
    from pathlib import Path

    from faultslip.io.atomic import save_figure, write_text_atomic
    from faultslip.dynamics.critical import comparison_dataset, comparison_markdown
    from faultslip.io.netcdf import write_dataset
    from faultslip.plots.figures import critical_comparison_figure

    out = Path(_output_dir(args, ".", [f"critical_comparison.{ext}" for ext in ("nc", "md", "png")]))
    dataset = comparison_dataset()
    markdown = comparison_markdown(dataset)
    with _locked(out / "critical_comparison.nc"):
        write_dataset(dataset, out / "critical_comparison.nc")
        write_text_atomic(out / "critical_comparison.md", markdown + "\n")
        save_figure(critical_comparison_figure(dataset), out / "critical_comparison.png", dpi=150)
    if args.json:
        print(json.dumps({"files": [str(out / f"critical_comparison.{ext}") for ext in ("nc", "md", "png")],
                          "critical_loading_rate": {"value": dataset["critical_loading_rate"].values.tolist(), "units": "1/s"},
                          "seed_appendix_I_loading_rate": {"value": dataset["seed_appendix_I_loading_rate"].values.tolist(), "units": "1/s"},
                          "preset": [str(p) for p in dataset["preset"].values],
                          "damping_ratio": dataset["damping_ratio"].values.tolist()}, indent=2))
    else:
        print(markdown)
        print(f"\nwrote {out / 'critical_comparison.nc'}, .md and .png")
    return 0


def cmd_cycle(args) -> int:
    from faultslip.errors import InputError
    from faultslip.dynamics.methods import solve
    from faultslip.fault.scene import load_scene
    from faultslip.units import to_si

    scene = load_scene(args.scene)
    system = scene.slider()
    if (args.loading_rate is None) == (args.platform_speed is None):
        raise InputError("give exactly one of --loading-rate or --platform-speed")
    if args.loading_rate is not None:
        system = system.at_loading_rate(to_si(args.loading_rate, "rate", "loading rate"))
    else:
        system = system.with_(platform_speed=to_si(args.platform_speed, "speed", "platform speed"))
    tolerance = _tolerance(args) or scene.tolerance
    solution = solve(system, method=args.method or scene.method, tolerance=tolerance, cycles=200)
    return _emit(solution.report(f"faultslip cycle: {scene.name}"), args.json)


def cmd_plot_phase_plane(args) -> int:
    from faultslip.io.atomic import save_figure
    from faultslip.plots.figures import phase_plane_figure

    from faultslip.io.outputs import FIGURE_SUFFIXES

    output = _outputs(args, {"output": ("-o", FIGURE_SUFFIXES)}, [getattr(args, "scene", None)])["output"]
    system = _system_from_args(args)
    factors = tuple(_number(f, "rate factor") for f in args.rate_factor) if args.rate_factor else (0.3, 0.999, 1.5)
    for factor in factors:
        if not 0 < factor < 1e6:
            raise FaultslipError(f"--rate-factor must be positive (a multiple of theta_c), got {factor:g}")
    with _locked(output):
        save_figure(phase_plane_figure(system, factors), output, dpi=150)
    print(f"wrote {args.output}")
    return 0


def _progress(label):
    """A one-line progress counter on stderr, only when it is a terminal."""
    if not sys.stderr.isatty():
        return None

    def show(done, total):
        end = "\n" if done == total else ""
        print(f"\r{label}: {done}/{total}", end=end, file=sys.stderr, flush=True)

    return show


def cmd_bench(args) -> int:
    from pathlib import Path

    from faultslip.io.atomic import save_figure, write_text_atomic
    from faultslip.evaluation.bench import chart, markdown, method_names, standard_scenes, work_precision
    from faultslip.errors import InputError
    from faultslip.io.netcdf import write_dataset

    for name in args.scene or []:
        if name not in standard_scenes():
            raise InputError(f"unknown bench scene {name!r}; allowed: {', '.join(standard_scenes())}")
    for name in args.method or []:
        if name not in method_names():
            raise InputError(f"unknown bench method {name!r}; allowed: {', '.join(method_names())}")
    out = Path(_output_dir(args, "bench", [f"work_precision.{ext}" for ext in ("nc", "md", "png")]))
    workers = _workers(args)
    with _locked(out / "work_precision.nc"):
        dataset = work_precision(quick=args.quick, workers=workers, scenes=args.scene, methods=args.method,
                                 progress=None if args.json else _progress("bench"))
        table = markdown(dataset)
        write_dataset(dataset, out / "work_precision.nc")
        write_text_atomic(out / "work_precision.md", table + "\n")
        save_figure(chart(dataset), out / "work_precision.png", dpi=120)
    files = [str(out / f"work_precision.{ext}") for ext in ("nc", "md", "png")]
    if args.json:
        print(json.dumps({"files": files, "wall_time": {"value": dataset.attrs["total_wall_time_s"], "units": "s"},
                          "scenes": [str(s) for s in dataset["scene"].values],
                          "methods": [str(m) for m in dataset["method"].values]}, indent=2))
    else:
        print(table.split("\n\nOutcome")[0])
        print(f"\nwrote {', '.join(files)} in {dataset.attrs['total_wall_time_s']:.1f} s")
    return 0


def cmd_stability(args) -> int:
    from pathlib import Path

    from faultslip.io.atomic import save_figure, write_text_atomic
    from faultslip.io.netcdf import write_dataset
    from faultslip.evaluation.stability import DAMPING_RATIOS, METHODS, RATIOS, SEPARATIONS, chart, failure_text, stability_map

    def floats(values, default):
        return tuple(sorted(_number(v, "grid value") for v in values)) if values else default

    for name in args.method or []:
        if name not in METHODS:
            raise FaultslipError(f"unknown stability method {name!r}; allowed: {', '.join(METHODS)}")
    ratios, dampings, separations = (floats(args.ratio, RATIOS), floats(args.damping_ratio, DAMPING_RATIOS),
                                     floats(args.separation, SEPARATIONS))
    if any(not 0 < r < 100 for r in ratios) or any(not 0 < s < 1e9 for s in separations):
        raise FaultslipError("--ratio must lie in (0, 100) (theta / theta_c) and --separation in (0, 1e9)")
    if any(not 0 < z < 1 for z in dampings):
        raise FaultslipError("--damping-ratio must lie in (0, 1): a critical rate needs damping")
    out = Path(_output_dir(args, "stability", [f"stability.{ext}" for ext in ("nc", "md", "png")]))
    workers = _workers(args)
    with _locked(out / "stability.nc"):
        dataset = stability_map(ratios, dampings, separations, tuple(args.method or METHODS),
                                workers=workers, progress=None if args.json else _progress("stability"))
        text = failure_text(dataset)
        write_dataset(dataset, out / "stability.nc")
        write_text_atomic(out / "stability.md", text + "\n")
        save_figure(chart(dataset), out / "stability.png", dpi=120)
    files = [str(out / f"stability.{ext}") for ext in ("nc", "md", "png")]
    if args.json:
        print(json.dumps({"files": files, "failure_regions": text.splitlines(),
                          "wall_time": {"value": dataset.attrs["total_wall_time_s"], "units": "s"}}, indent=2))
    else:
        print(text)
        print(f"\nwrote {', '.join(files)} in {dataset.attrs['total_wall_time_s']:.1f} s")
    return 0


def _delayed_progress(label, enabled):
    """Progress on stderr for runs longer than a few seconds, only on a terminal."""
    if not enabled or not sys.stderr.isatty():
        return None
    import time

    started = time.perf_counter()

    def show(done, total):
        if time.perf_counter() - started < 2.0 and done < total:
            return
        print(f"\r{label}: {done}/{total} chunks ({100 * done / total:.0f} %)", end="\n" if done == total else "",
              file=sys.stderr, flush=True)

    return show


def cmd_sweep(args) -> int:
    from faultslip.io import budget
    from faultslip.io.outputs import check_output
    from faultslip.studies.streaming import DEFAULT_CHUNK_CELLS, run_study
    from faultslip.studies.grid import load_study

    study = load_study(args.study)
    inputs = [args.study, study.scene.path]
    # --resume continues into the same output: an existing final file is still refused without --overwrite
    output = check_output(args.output, label="-o", suffixes=(".nc",), inputs=inputs, overwrite=args.overwrite)
    if args.chunks is not None and not 1 <= args.chunks <= 10**9:
        raise FaultslipError(f"--chunks must be a number of cells from 1 to 1e9, got {args.chunks}")
    chunk_cells = args.chunks or DEFAULT_CHUNK_CELLS
    # at least this many chunks (whole trailing dimensions may make more); known without listing them
    chunk_count = -(-study.size // chunk_cells)
    workers = (args.workers or 2) if args.scheduler else _workers(args, chunk_count)
    budget.check(budget.study_estimate(study, output, workers, chunk_cells, args.compression), args.allow_large)
    summary = run_study(study, output, chunk_cells=chunk_cells, scheduler=args.scheduler, workers=workers,
                        resume=args.resume, progress=_delayed_progress("sweep", not args.json),
                        compression=args.compression, overwrite=args.overwrite, inputs=inputs)
    if args.json:
        print(json.dumps({"output": summary["output"], "cells": summary["cells"], "blocks": summary["blocks"],
                          "resumed_blocks": summary["resumed_blocks"], "executor": summary["executor"],
                          "wall_time": {"value": summary["seconds"], "units": "s"},
                          "dimensions": {name: len(values) for name, values in study.dims.items()},
                          "notes": getattr(args, "notes", []) + ([f"base scene: {study.scene.origin}"]
                                                                 if study.scene.origin else [])}, indent=2))
    else:
        print(f"faultslip sweep: {study.name}")
        print(f"  {summary['cells']} cells ({' x '.join(f'{n} {len(v)}' for n, v in study.dims.items())}) in "
              f"{summary['blocks']} chunks on {summary['executor']}"
              + (f", {summary['resumed_blocks']} reused" if summary["resumed_blocks"] else ""))
        print(f"  wrote {summary['output']} in {summary['seconds']:.2f} s")
    return 0


def cmd_reproduce(args) -> int:
    from faultslip.studies.streaming import reproduce

    workers = _workers(args)
    result = reproduce(args.file, output=args.output, workers=workers, overwrite=args.overwrite)
    if args.json:
        print(json.dumps({key: (None if isinstance(value, float) and not math.isfinite(value) else value)
                          for key, value in result.items() if key != "differences"}
                         | {"differences": {k: (v if math.isfinite(v) else None) for k, v in result["differences"].items()}},
                         indent=2))
    else:
        verdict = "matches" if result["matches"] else "DIFFERS"
        print(f"faultslip reproduce: {args.file} {verdict} (largest relative difference {result['largest_difference']:.3g} "
              f"over {result['cells']} cells)")
        for name, value in result["differences"].items():
            print(f"  {name:26s} {value:.3g}")
        for label, key in (("missing from the file", "missing"), ("not reproduced (extra in the file)", "extra"),
                           ("attributes that differ", "attribute_differences")):
            if result[key]:
                print(f"  {label}: {', '.join(result[key])}")
    return 0 if result["matches"] else 1


def cmd_map(args) -> int:
    from pathlib import Path

    from faultslip.io.atomic import save_figure
    from faultslip.studies.maps import load_map, map_figure, observed_figure, observed_table, run_map
    from faultslip.io.netcdf import write_dataset

    from faultslip.io.outputs import FIGURE_SUFFIXES, check_output

    spec = load_map(args.map)
    outputs = _outputs(args, {"output": ("-o", (".nc",)), "plot": ("--plot", FIGURE_SUFFIXES)}, spec.inputs)
    observed = None
    if outputs["plot"] is not None and spec.segments is not None:
        target = Path(outputs["plot"])
        observed = check_output(target.with_name(target.stem + "_observed" + target.suffix), label="--plot (observed)",
                                inputs=spec.inputs + [outputs["output"]], overwrite=args.overwrite)
    tolerance = _tolerance(args) or 1e-6
    dataset = run_map(spec, method=args.method or "auto", tolerance=tolerance)
    plots = []
    with _locked(outputs["output"], outputs["plot"], observed):
        write_dataset(dataset, outputs["output"])
        if outputs["plot"]:
            save_figure(map_figure(dataset), outputs["plot"], dpi=150)
            plots.append(args.plot)
            if "observed_recurrence" in dataset and observed is not None:
                save_figure(observed_figure(dataset), observed, dpi=150)
                plots.append(str(observed))
    if args.json:
        year = 365.25 * 86400
        rows = []
        if "segment" in dataset.dims:
            for i, segment in enumerate(dataset["segment"].values):
                row = dataset.isel(segment=i)
                rows.append({"segment": str(segment),
                             "slip_per_event": {"value": float(row["slip_per_event"]), "units": "m"},
                             "recurrence_period": {"value": float(row["recurrence_period"]) if math.isfinite(float(row["recurrence_period"])) else None, "units": "s"},
                             "moment_magnitude": float(row["moment_magnitude"]) if math.isfinite(float(row["moment_magnitude"])) else None,
                             "observed_recurrence": {"value": float(row["observed_recurrence"]) if math.isfinite(float(row["observed_recurrence"])) else None, "units": "s"},
                             "recurrence_ratio": float(row["recurrence_ratio"]) if math.isfinite(float(row["recurrence_ratio"])) else None,
                             "slip_ratio": float(row["slip_ratio"]) if math.isfinite(float(row["slip_ratio"])) else None})
        print(json.dumps({"output": args.output, "plots": plots, "segments": rows, "year": {"value": year, "units": "s"},
                          "notes": spec.notes}, indent=2))
    else:
        print(f"faultslip map: {spec.name}")
        for note in spec.notes:
            print(f"  {note}")
        if "segment" in dataset.dims:
            print(observed_table(dataset))
        print(f"\nwrote {args.output}" + (f", {', '.join(plots)}" if plots else ""))
    return 0


def cmd_fit(args) -> int:
    from faultslip.friction.fitting import fit_figure, fit_rate_law, read_friction_data

    from faultslip.io.outputs import FIGURE_SUFFIXES

    plot = _outputs(args, {"plot": ("--plot", FIGURE_SUFFIXES)}, [args.data])["plot"]
    if not 0 <= args.bootstrap <= 100_000:
        raise FaultslipError(f"--bootstrap must lie between 0 and 100000 samples, got {args.bootstrap}")
    if args.loss not in ("linear", "soft_l1", "huber", "cauchy"):
        raise FaultslipError(f"--loss must be linear, soft_l1, huber or cauchy, got {args.loss!r}")
    if args.seed < 0:
        raise FaultslipError(f"--seed must not be negative, got {args.seed}")
    modulus = None
    if args.shear_modulus:
        from faultslip import ranges
        from faultslip.units import to_si

        modulus = ranges.check("shear_modulus", to_si(args.shear_modulus, "pressure", "shear modulus"))
    fixed = None if args.mu_m is None else _number(args.mu_m, "mu_m")
    data = read_friction_data(args.data, fixed_mu_m=fixed)
    fit = fit_rate_law(data, loss=args.loss, bootstrap=args.bootstrap, seed=args.seed, fixed_mu_m=fixed)
    report = fit.report(f"faultslip fit: {args.data}")
    if plot:
        from faultslip.io.atomic import save_figure

        with _locked(plot):
            save_figure(fit_figure(data, fit), plot, dpi=150)
        report.note(f"plot written to {args.plot}")
    if args.name:  # only after the fit succeeded: a failed fit never touches the registry
        from faultslip.friction.materials import save_user_fit

        path = save_user_fit(args.name, fit, shear_modulus=modulus, note=args.note or "")
        report.note(f"saved as {args.name!r} in {path}; use it with 'faultslip fault --lithology {args.name} ...'")
    return _emit(report, args.json)


def cmd_record(args) -> int:
    from faultslip.lab.records import analyze_record, hysteresis_figure, read_record
    from faultslip.units import to_si

    from faultslip import ranges
    from faultslip.io.outputs import FIGURE_SUFFIXES

    plot = _outputs(args, {"plot": ("--plot", FIGURE_SUFFIXES)}, [args.record])["plot"]
    if args.velocity not in ("auto", "differentiate", "integrate"):
        raise FaultslipError(f"--velocity must be auto, differentiate or integrate, got {args.velocity!r}")
    for flag, kind, name in (("stiffness", "stiffness", "stiffness"), ("normal_load", "force", "normal_load"),
                             ("mass", "mass", "mass"), ("platform_speed", "speed", "platform_speed")):
        if getattr(args, flag):
            ranges.check(name, to_si(getattr(args, flag), kind, f"--{flag.replace('_', '-')}"))
    if args.dashpot and not to_si(args.dashpot, "damping", "dashpot") >= 0:
        raise FaultslipError(f"--dashpot must not be negative, got {args.dashpot}")
    record = read_record(args.record)
    speed = to_si(args.platform_speed, "speed", "platform speed") if args.platform_speed else None
    analysis = analyze_record(record, to_si(args.mass, "mass", "mass") if args.mass else
                              to_si(args.normal_load, "force", "normal load") / 9.80665,
                              to_si(args.stiffness, "stiffness", "stiffness"), to_si(args.normal_load, "force", "normal load"),
                              speed, to_si(args.dashpot, "damping", "dashpot") if args.dashpot else 0.0,
                              velocity_method=args.velocity)
    report = analysis.report(f"faultslip record analysis: {args.record}")
    if plot:
        from faultslip.io.atomic import save_figure

        with _locked(plot):
            save_figure(hysteresis_figure(analysis), plot, dpi=150)
        report.note(f"mu against sliding speed drawn to {args.plot}")
    return _emit(report, args.json)


def cmd_decay(args) -> int:
    from faultslip.errors import InputError
    from faultslip.lab.records import free_decay, free_decay_from_record, read_record
    from faultslip.units import to_si

    stiffness = to_si(args.stiffness, "stiffness", "stiffness")
    if args.record:
        result = free_decay_from_record(read_record(args.record), stiffness)
    else:
        if args.ratio is None or args.cycles is None or args.frequency is None:
            raise InputError("give a free-decay record, or --ratio, --cycles and --frequency")
        frequency = to_si(args.frequency, "frequency", "damped frequency")  # rad/s is converted to Hz
        result = free_decay(_number(args.ratio, "amplitude ratio"), _number(args.cycles, "cycles"), frequency, stiffness)
    return _emit(result.report(), args.json)


# --- parser -----------------------------------------------------------------


def _method_flags(parser):
    from faultslip.fault.scene import METHOD_NAMES

    parser.add_argument("--method", choices=METHOD_NAMES, help="solution method (default: auto, the cheapest "
                        "method whose error model meets the tolerance)")
    parser.add_argument("--tolerance", help="relative error the method must meet (default 1e-6)")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="faultslip", description="Laboratory rock friction to earthquake slip and recurrence.")
    parser.add_argument("--version", action="version", version=f"faultslip {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)

    run = commands.add_parser("run", help="run a scene (default: the 1906 San Francisco scene)")
    run.add_argument("scene", nargs="?", help="scene TOML file or bundled scene name")
    _method_flags(run)
    run.add_argument("--json", action="store_true", help="print one JSON object")
    run.set_defaults(handler=cmd_run)

    fault = commands.add_parser("fault", help="direct fault estimate (seed 003 §5-2) without a scene file")
    fault.add_argument("--lithology", help="lithology or preset; supplies G and the friction law unless given")
    fault.add_argument("--shear-modulus", help="G, e.g. '0.25e6 bar'")
    fault.add_argument("--zone-width", help="elastic-zone half-width D, e.g. '13 mi'")
    stress = fault.add_mutually_exclusive_group()
    stress.add_argument("--normal-stress", help="effective normal stress, e.g. '385 bar'")
    stress.add_argument("--shear-stress", help="shear stress tau; sigma_n = tau / mu_so, e.g. '250 bar'")
    fault.add_argument("--slip-rate", help="tectonic slip rate, e.g. '2 in/yr'")
    fault.add_argument("--mu-so", help="static friction at vanishing loading rate")
    fault.add_argument("--mu-m", help="kinetic friction")
    fault.add_argument("--rate-coefficient", help="b of eq. 2-18 (in s^d)")
    fault.add_argument("--rate-exponent", help="d of eq. 2-18")
    fault.add_argument("--rupture-length", help="rupture length L for M0 and Mw, e.g. '270 mi'")
    fault.add_argument("--depth", help="seismogenic depth H for M0 and Mw, e.g. '12 km'")
    fault.add_argument("--damping-ratio", help="damping ratio zeta of the slip phase (default 0)")
    fault.add_argument("--radiation-damping", action="store_true", help="add the radiation damper G/(2 c_s)")
    fault.add_argument("--density", help="rock density for M = rho D (default 2700 kg/m^3)")
    fault.add_argument("--shear-wave-speed", help="c_s for radiation damping (default 3.3 km/s)")
    fault.add_argument("--observed-slip", help="inverse: report the mu_m that reproduces this slip, e.g. '21 ft'")
    fault.add_argument("--name", default="fault", help="a name for the report")
    _method_flags(fault)
    fault.add_argument("--json", action="store_true", help="print one JSON object")
    fault.set_defaults(handler=cmd_fault)

    materials = commands.add_parser("materials", help="list presets and lithologies with their sources")
    materials.add_argument("--json", action="store_true", help="print one JSON object")
    materials.set_defaults(handler=cmd_materials)

    simulate = commands.add_parser("simulate", help="event-driven simulation of stick-slip cycles of a scene")
    simulate.add_argument("scene", help="scene TOML file or bundled scene name")
    simulate.add_argument("-o", "--output", help="write the time series and event table to OUT.nc")
    simulate.add_argument("--plot", help="draw the sawtooth record to FILE.png")
    simulate.add_argument("--allow-large", action="store_true", help="run even beyond the memory, disk and one-hour budget")
    simulate.add_argument("--overwrite", action="store_true", help="replace outputs that already exist")
    simulate.add_argument("--cycles", type=int, help="number of stick-slip cycles (default: the scene's, else 100)")
    simulate.add_argument("--slip-solver", help="analytic, RK45, RK23, DOP853, Radau, BDF or LSODA (default auto)")
    simulate.add_argument("--rtol", help="integrator relative tolerance (default 1e-10)")
    simulate.add_argument("--json", action="store_true", help="print one JSON object")
    simulate.set_defaults(handler=cmd_simulate)

    critical = commands.add_parser("critical", help="critical loading rate: exact and seed Appendix I")
    critical.add_argument("scene", nargs="?", help="scene file (alternative to --preset)")
    critical.add_argument("--preset", help="Table I preset on its apparatus")
    critical.add_argument("--damping-ratio", help="damping ratio zeta of the dashpot")
    critical.add_argument("--table", action="store_true", help="write the exact-vs-seed comparison (nc, md, png)")
    critical.add_argument("-o", "--output", help="directory for --table (default: current)")
    critical.add_argument("--overwrite", action="store_true", help="replace outputs that already exist")
    critical.add_argument("--json", action="store_true", help="print one JSON object")
    critical.set_defaults(handler=cmd_critical)

    cycle = commands.add_parser("cycle", help="exact stick-slip cycle of a scene at a loading rate")
    cycle.add_argument("scene", help="scene TOML file or bundled scene name")
    cycle.add_argument("--loading-rate", help="theta_dot, e.g. '0.1 1/s'")
    cycle.add_argument("--platform-speed", help="V, e.g. '1e-4 in/s'")
    _method_flags(cycle)
    cycle.add_argument("--json", action="store_true", help="print one JSON object")
    cycle.set_defaults(handler=cmd_cycle)

    bench = commands.add_parser("bench", help="work-precision study of every method on standard scenes")
    bench.add_argument("--quick", action="store_true", help="fewer tolerances and cycles (under 2 minutes on 2 cores)")
    bench.add_argument("-o", "--output", default="bench", help="output directory (default: bench/)")
    bench.add_argument("--overwrite", action="store_true", help="replace outputs that already exist")
    bench.add_argument("--scene", action="append", help="only this standard scene (repeatable)")
    bench.add_argument("--method", action="append", help="only this method (repeatable)")
    bench.add_argument("--workers", type=int, help="parallel processes (default: the cores)")
    bench.add_argument("--json", action="store_true", help="print one JSON object")
    bench.set_defaults(handler=cmd_bench)

    stability = commands.add_parser("stability", help="map where each method fails (rate, damping, separation)")
    stability.add_argument("-o", "--output", default="stability", help="output directory (default: stability/)")
    stability.add_argument("--overwrite", action="store_true", help="replace outputs that already exist")
    stability.add_argument("--ratio", action="append", help="only these theta/theta_c values (repeatable)")
    stability.add_argument("--damping-ratio", action="append", help="only these damping ratios (repeatable)")
    stability.add_argument("--separation", action="append", help="only these stick/slip ratios (repeatable)")
    stability.add_argument("--method", action="append", help="only this method (repeatable)")
    stability.add_argument("--workers", type=int, help="parallel processes (default: the cores)")
    stability.add_argument("--json", action="store_true", help="print one JSON object")
    stability.set_defaults(handler=cmd_stability)

    sweep = commands.add_parser("sweep", help="gridded parameter study to CF netCDF")
    sweep.add_argument("study", help="study TOML file")
    sweep.add_argument("-o", "--output", required=True, help="output netCDF file (written atomically)")
    sweep.add_argument("--allow-large", action="store_true", help="run even beyond the memory, disk and one-hour budget")
    sweep.add_argument("--overwrite", action="store_true", help="replace outputs that already exist")
    sweep.add_argument("--scheduler", help="'local' for a dask LocalCluster, or the address of a dask scheduler")
    sweep.add_argument("--chunks", type=int, help="cells per chunk (default 524288)")
    sweep.add_argument("--workers", type=int, help="parallel workers (default: the cores, at most one per chunk)")
    sweep.add_argument("--resume", action="store_true", help="reuse the chunks of an interrupted run of the same study")
    sweep.add_argument("--compression", choices=("zlib", "zstd", "none"), default="zlib",
                       help="netCDF4 filter (default zlib, readable everywhere; zstd writes ~2.5x faster)")
    sweep.add_argument("--json", action="store_true", help="print one JSON object")
    sweep.set_defaults(handler=cmd_sweep)

    reproduce = commands.add_parser("reproduce", help="re-run the study embedded in a sweep's netCDF and compare")
    reproduce.add_argument("file", help="a netCDF written by faultslip sweep")
    reproduce.add_argument("-o", "--output", help="keep the reproduced file here")
    reproduce.add_argument("--overwrite", action="store_true", help="replace outputs that already exist")
    reproduce.add_argument("--workers", type=int, help="parallel workers (default: the cores, at most one per chunk)")
    reproduce.add_argument("--json", action="store_true", help="print one JSON object")
    reproduce.set_defaults(handler=cmd_reproduce)

    regional = commands.add_parser("map", help="regional map from a fault-segment table or a raster")
    regional.add_argument("map", help="map TOML file")
    regional.add_argument("-o", "--output", required=True, help="output netCDF file")
    regional.add_argument("--plot", help="draw the maps to FILE.png (and predicted vs observed to FILE_observed.png)")
    regional.add_argument("--overwrite", action="store_true", help="replace outputs that already exist")
    _method_flags(regional)
    regional.add_argument("--json", action="store_true", help="print one JSON object")
    regional.set_defaults(handler=cmd_map)

    fit = commands.add_parser("fit", help="fit the rate law (eq. 2-18) to laboratory data, with uncertainty")
    fit.add_argument("data", help="CSV or netCDF: loading_rate (or platform_speed, stiffness, normal_load), static_friction[, amplitude]")
    fit.add_argument("--name", help="save the fit under this name in the user registry")
    fit.add_argument("--shear-modulus", help="shear modulus of the rock, stored with the fit for fault predictions")
    fit.add_argument("--note", help="a note stored with the fit (e.g. rock and condition)")
    fit.add_argument("--plot", help="draw data, fit and 95 % band to FILE.png")
    fit.add_argument("--overwrite", action="store_true", help="replace outputs that already exist")
    fit.add_argument("--loss", default="linear", help="least-squares loss: linear, soft_l1, huber or cauchy (robust)")
    fit.add_argument("--bootstrap", type=int, default=200, help="bootstrap samples (default 200)")
    fit.add_argument("--seed", type=int, default=0, help="bootstrap seed (default 0): results are reproducible")
    fit.add_argument("--mu-m", help="fix the kinetic friction instead of fitting it")
    fit.add_argument("--json", action="store_true", help="print one JSON object")
    fit.set_defaults(handler=cmd_fit)

    record = commands.add_parser("record", help="friction and stick-slip events from a measured motion record")
    record.add_argument("record", help="CSV or netCDF: time, displacement, and acceleration or force")
    record.add_argument("--stiffness", required=True, help="spring stiffness K, e.g. '1.94e4 lbf/in'")
    record.add_argument("--normal-load", required=True, help="normal load W, e.g. '225.8 lbf'")
    record.add_argument("--mass", help="moving mass M (default W/g)")
    record.add_argument("--dashpot", help="dashpot C, e.g. '0 N*s/m' (default 0, as seed 003 eq. 3-2)")
    record.add_argument("--platform-speed", help="platform speed V (default: the median slider speed)")
    record.add_argument("--velocity", default="auto", help="auto, differentiate (x) or integrate (x'')")
    record.add_argument("--plot", help="draw mu against sliding speed to FILE.png")
    record.add_argument("--overwrite", action="store_true", help="replace outputs that already exist")
    record.add_argument("--json", action="store_true", help="print one JSON object")
    record.set_defaults(handler=cmd_record)

    decay = commands.add_parser("decay", help="system identification from free decay (seed 002 Appendix C)")
    decay.add_argument("record", nargs="?", help="a free-decay displacement record (alternative to --ratio ...)")
    decay.add_argument("--stiffness", required=True, help="known stiffness, e.g. '70.5 lbf/in'")
    decay.add_argument("--ratio", help="amplitude ratio X_n / X_{n+N}, e.g. 1.225")
    decay.add_argument("--cycles", help="N, the cycles between the two amplitudes, e.g. 10")
    decay.add_argument("--frequency", help="damped frequency, e.g. '19.9 Hz'")
    decay.add_argument("--json", action="store_true", help="print one JSON object")
    decay.set_defaults(handler=cmd_decay)

    methods = commands.add_parser("methods", help="the solution methods: friction laws, domain and cost of each")
    methods.add_argument("--json", action="store_true", help="print one JSON object")
    methods.set_defaults(handler=cmd_methods)

    plot = commands.add_parser("plot", help="draw a figure")
    figures = plot.add_subparsers(dest="figure", metavar="FIGURE", parser_class=_Parser)
    rate_law = figures.add_parser("rate-law", help="mu_s and amplitude against log10 loading rate (seed Figs. 4-1 to 4-22)")
    rate_law.add_argument("--preset", action="append", help="preset name (repeatable; default: all of Table I)")
    rate_law.add_argument("-o", "--output", required=True, help="output image, e.g. rate_law.png")
    rate_law.add_argument("--overwrite", action="store_true", help="replace outputs that already exist")
    rate_law.set_defaults(handler=cmd_plot_rate_law)
    phase = figures.add_parser("phase-plane", help="phase-plane limit cycles below, at and above the critical rate")
    phase.add_argument("--preset", help="Table I preset on its apparatus")
    phase.add_argument("--scene", help="or a scene file")
    phase.add_argument("--damping-ratio", help="damping ratio zeta (needed for a critical rate)")
    phase.add_argument("--rate-factor", action="append", help="loading rate as a multiple of theta_c (repeatable)")
    phase.add_argument("-o", "--output", required=True, help="output image")
    phase.add_argument("--overwrite", action="store_true", help="replace outputs that already exist")
    phase.set_defaults(handler=cmd_plot_phase_plane)
    return parser


def _show_warning(message, category, filename, lineno, file=None, line=None):
    print(f"faultslip: warning: {message}", file=sys.stderr)


def main(argv=None) -> int:
    """Run one command; returns the exit status (0, 1 machine error, 2 bad input, 130 interrupted)."""
    import warnings

    try:
        warnings.showwarning = _show_warning
        parser = build_parser()
        args = parser.parse_args(argv)
        handler = getattr(args, "handler", None)
        if handler is None:
            parser.print_help(sys.stderr)
            return 2
        return handler(args)
    except FaultslipError as exc:
        print(f"faultslip: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        if _AS_PROGRAM:  # answered once: a further Ctrl-C while cleaning up must not end in a traceback
            import signal

            signal.signal(signal.SIGINT, signal.SIG_IGN)
        print("faultslip: interrupted; no output file was left half-written", file=sys.stderr)
        return 130
    except MemoryError:
        print("faultslip: error: out of memory; make the run smaller (see --allow-large and the budget)", file=sys.stderr)
        return 1
    except BrokenPipeError:  # the reader (e.g. head) closed the pipe: stop quietly
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except OSError as exc:  # the machine, not the input: a full disk, a permission, a vanished file
        where = f" ({exc.filename})" if getattr(exc, "filename", None) else ""
        print(f"faultslip: error: {exc.strerror or exc}{where}", file=sys.stderr)
        return 1


def console() -> None:
    """The ``faultslip`` program: :func:`main`, then exit without a second chance for Ctrl-C.

    Once main has answered (and printed its one line), a late Ctrl-C during interpreter shutdown
    (joining pool threads, atexit handlers) would otherwise end the process with a traceback.
    """
    import signal

    global _AS_PROGRAM
    _AS_PROGRAM = True
    code = main()
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if code == 130:
        # A Ctrl-C that landed inside an import leaves CPython's "unhandled KeyboardInterrupt" flag
        # set, and the interpreter would then end itself with SIGINT (status -2) although the
        # interrupt was handled. Outputs are closed and pools stopped by now: leave at once.
        import os

        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(130)
    sys.exit(code)


_AS_PROGRAM = False  # True when running as the faultslip program, not called from Python


if __name__ == "__main__":
    console()
