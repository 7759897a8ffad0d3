"""Scene and fault commands: run, fault, materials, methods, simulate, critical, cycle."""

from __future__ import annotations

import json
import textwrap
from pathlib import Path

import faultslip
from faultslip import models
from faultslip.cli.common import _locked, _number, _output_dir, _outputs, _save_run, _system_from_args, _tolerance
from faultslip.cli.printing import _emit, _emit_estimate, _progress
from faultslip.dynamics.spring_slider.critical import comparison_dataset, comparison_markdown, critical
from faultslip.contract.options import options_of
from faultslip.errors import InputError
from faultslip.friction.materials import bundled_lithologies, presets, user_rate_state_fits
from faultslip.friction.registry import registry_path
from faultslip.io.atomic import save_figure, write_text_atomic
from faultslip.io.catalogs import QUAKEML_SUFFIXES, parse_time, write_quakeml
from faultslip.io.netcdf import write_dataset
from faultslip.io.outputs import FIGURE_SUFFIXES, check_output
from faultslip.io.report import LINE_WIDTH
from faultslip.io.waveforms import (DEFAULT_START, MAX_SAMPLES, STREAM_SUFFIXES, check_datable, sac_path,
                                    write_stream)
from faultslip.plots.figures import critical_comparison_figure
from faultslip.models.fault_estimate import fault_estimate


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


def cmd_run(args) -> int:
    """Any scene, whatever its model family (faultslip.models): its report."""
    options = {option.name: getattr(args, option.name) for option in options_of("run") if option.family}
    if args.estimate:  # the family's cost model, before any work
        asked = {name: True for name in ("richardson", "check_starts") if options.get(name)}
        return _emit_estimate(models.estimate(args.scene, "run", method=args.method, tolerance=_tolerance(args),
                                              **asked), args.json)
    return _emit(models.run(args.scene, method=args.method, tolerance=_tolerance(args),
                            progress=_progress("run", not args.json, "yr"), **options).report(), args.json)


def cmd_fault(args) -> int:
    inputs = {target: getattr(args, flag) for flag, target in _FAULT_QUANTITIES.items() if getattr(args, flag) is not None}
    seed_law = {"mu_so": args.mu_so, "mu_m": args.mu_m, "damping_ratio": args.damping_ratio,
                "b": args.rate_coefficient, "d": args.rate_exponent, "dip": args.dip, "rake": args.rake}
    result = fault_estimate(args.lithology, method=args.method, tolerance=_tolerance(args),
                            observed_slip=args.observed_slip, seed_law=args.seed_law,
                            radiation_damping=args.radiation_damping, name=args.name,
                            **inputs, **{key: value for key, value in seed_law.items() if value is not None})
    return _emit(result.report(), args.json)


def cmd_materials(args) -> int:
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
        for lith in bundled_lithologies().values()  # the user's fits have rows of their own below
    ]
    rate_state_rows = [
        {"name": key, "a": law.a, "b": law.b, "critical_slip": {"value": law.critical_slip, "units": "m"},
         "mu0": law.mu0, "reference_speed": {"value": law.reference_speed, "units": "m/s"},
         "evolution": law.evolution, "intervals_95": entry.get("intervals_95"),
         "bootstrap_samples": len(entry.get("bootstrap") or []), "source": law.source,
         "shear_modulus": {"value": entry["shear_modulus"], "units": "Pa"} if entry.get("shear_modulus") else None}
        for key, (law, entry) in user_rate_state_fits().items()]
    if args.json:
        document = {"presets": preset_rows, "lithologies": lith_rows}
        if rate_state_rows:
            document["rate_state_fits"] = rate_state_rows
        print(json.dumps(document, indent=2))
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

    user = [row for row in preset_rows if row.get("user_fit")]
    print(f"\nUser fits ({registry_path()})" + ("" if user else ": none yet (faultslip fit DATA.csv --name NAME)"))
    for row in user:
        errors = row.get("standard_errors") or {}
        modulus = row.get("shear_modulus")
        print(f"  {row['name']:<26}{row['mu_so']:>7.3g}{row['mu_m']:>7.3g}{row['b']['value']:>11.4g}{row['d']:>8.4g}"
              f"  (+- {errors.get('mu_so', float('nan')):.2g}, {errors.get('mu_m', float('nan')):.2g}, "
              f"{errors.get('b', float('nan')):.2g}, {errors.get('d', float('nan')):.2g})"
              + (f"  G = {modulus['value'] / 1e5:.4g} bar" if modulus else "") + f"  {row['source']}")
    if rate_state_rows:
        print(f"\nRate-and-state fits ({registry_path()}; faultslip fit --law rate-state ... --name NAME)")
        for row in rate_state_rows:
            modulus = row["shear_modulus"]
            print(f"  {row['name']:<26}a {row['a']:.4g}  b {row['b']:.4g}  D_c {row['critical_slip']['value']:.4g} m  "
                  f"{row['evolution']} law, {row['bootstrap_samples']} resamples"
                  + (f"  G = {modulus['value'] / 1e9:.4g} GPa" if modulus else "") + f"  {row['source']}")
    print("\nLithologies (shear modulus; default friction preset on a fault)")
    for row in lith_rows:
        print(f"  {row['name']:<14}G = {row['shear_modulus']['value'] / 1e5:.4g} bar  preset: "
              f"{row['default_preset'] or '(none: give mu_so, mu_m)'}  {row['source']}")
    return 0


def cmd_methods(args) -> int:
    rows = models.methods(args.scene)
    if args.json:
        print(json.dumps({"methods": rows}, indent=2))
        return 0
    for row in rows:  # each field folded at a report's width, under its label
        print(row["name"])
        for label, text in (("friction laws", row["friction_laws"]), ("valid where", row["domain"]),
                            ("cost", row["cost_model"]), ("error", row["declared_error"]),
                            ("families", ", ".join(row["families"])),
                            ("run with" if row["run_method"] else "reached by", row["selected_by"])):
            print("\n".join(textwrap.wrap(text, width=LINE_WIDTH, initial_indent=f"  {label + ':':<15}",
                                           subsequent_indent=" " * 17, break_on_hyphens=False,
                                           break_long_words=False)))
    return 0


def cmd_simulate(args) -> int:
    """Any scene's time series, whatever its model family (faultslip.models); the stream and the events where
    the family records them."""
    if args.estimate:  # the family's cost model, before any work or any output is checked
        options = {"cycles": args.cycles, "slip_solver": args.slip_solver, "output": args.output,
                   "output_dir": args.output_dir, "rtol": _number(args.rtol, "--rtol") if args.rtol else None}
        return _emit_estimate(models.estimate(args.scene, "simulate", **options), args.json)
    outputs = _outputs(args, {"output": ("-o", (".nc",)), "plot": ("--plot", FIGURE_SUFFIXES),
                              "stream": ("--stream", tuple(STREAM_SUFFIXES)), "events": ("--events", QUAKEML_SUFFIXES)},
                       [args.scene])
    if outputs["stream"] and outputs["stream"].suffix.lower() == ".sac":  # one file per component, checked now
        for component in ("D", "S", "R", "F"):
            check_output(sac_path(outputs["stream"], component), label="--stream", suffixes=(".sac",),
                         inputs=[args.scene], overwrite=args.overwrite)
    rate = _number(args.sampling_rate, "--sampling-rate") if args.sampling_rate else None
    start = (float(parse_time(args.start_time, "--start-time").astype("datetime64[ms]").astype("int64")) / 1e3
             if args.start_time else DEFAULT_START)
    result = models.simulate(args.scene, **_simulate_options(args, outputs))
    report = result.report()
    series = result.series
    if outputs["stream"] or outputs["events"]:  # before anything is written
        check_datable(start, float(series["time"].values[-1]), int(series.sizes.get("event", 1)))
    if series is None:
        if outputs["output"] or outputs["plot"]:  # asked for files that cannot be made: never a silent exit 0
            raise InputError(f"{report.title}: this run recorded no time series (it slides stably, or its family "
                             "records none), so -o and --plot have nothing to write; run it without them")
        return _emit(report, args.json)
    _save_run(report, outputs, args, result.to_xarray() if outputs["output"] else None, result.plot,
              "time series and event table" if "event" in series.dims else "time series", "figure")
    if outputs["stream"]:
        stream, sampling, note = result.extras["stream"](rate, start,
                                                         10 * MAX_SAMPLES if args.allow_large else MAX_SAMPLES)
        with _locked(outputs["stream"]):
            written = write_stream(stream, outputs["stream"])
        report.note(f"stream of {', '.join(t.id for t in stream)} at {sampling:.4g} Hz ({stream[0].stats.npts} "
                    f"samples) written to {', '.join(str(p) for p in written)}" + (f"; {note}" if note else ""))
    if outputs["events"]:
        events = result.extras["events"](start)
        with _locked(outputs["events"]):
            write_quakeml(events["times"], events["latitude"], events["longitude"], events["depth"],
                          events["magnitude"], outputs["events"], names=events["names"],
                          comment=f"faultslip simulation of {report.title.removeprefix('faultslip simulation: ')}")
        report.note(f"{len(events['names'])} events (Mw {float(events['magnitude'].max()):.2f}) written as QuakeML "
                    f"to {args.events}" + (f"; {events['note']}" if events["note"] else ""))
    return _emit(report, args.json)


def _simulate_options(args, outputs) -> dict:
    """simulate's options as the families take them (faultslip.contract.options): numbers read, files checked, and
    a file the command writes from the result (--stream, --events) asked for as True."""
    options = {}
    for option in options_of("simulate"):
        if not option.family:
            continue
        value = getattr(args, option.name)
        if option.name in outputs:  # a file checked above: the family is told where, or only that it is wanted
            value = outputs[option.name] if option.name == "output" else bool(outputs[option.name])
        elif option.kind == "number" and value is not None:
            value = _number(value, option.flag)
        options[option.name] = value
    return options


def cmd_critical(args) -> int:
    if args.table:
        return _critical_table(args)

    return _emit(critical(_system_from_args(args)).report(), args.json)


def _critical_table(args) -> int:
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
    result = faultslip.models.scene_cycle(args.scene, loading_rate=args.loading_rate, platform_speed=args.platform_speed,
                         method=args.method, tolerance=_tolerance(args))
    return _emit(result.report(), args.json)
