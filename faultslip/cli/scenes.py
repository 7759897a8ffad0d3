"""Scene and fault commands: run, fault, materials, methods, simulate, critical, cycle."""

from __future__ import annotations

import json
from pathlib import Path

from faultslip.cli.common import (_emit, _locked, _note_origin, _number, _output_dir, _outputs, _save_run,
                                  _system_from_args, _tolerance)
from faultslip.dynamics.critical import comparison_dataset, comparison_markdown, critical
from faultslip.dynamics.averaging import report as averaging_report
from faultslip.dynamics.averaging import settled_amplitude, simulate_vibration, vibration_dataset, vibration_report
from faultslip.dynamics.methods import describe_all, solve
from faultslip.dynamics.nanoscale import choose_method
from faultslip.dynamics.nanoscale import report as nanoscale_report
from faultslip.dynamics.nanoscale import run_dataset as nanoscale_dataset
from faultslip.dynamics.simulate import simulate, summary_report, uniform_channels
from faultslip.errors import FaultslipError, InputError
from faultslip.fault.rate_state_fault import cycles_dataset, estimate_fault_from_fit
from faultslip.fault.scaling import Fault
from faultslip.fault.scene import CHOICES, estimate_scene_rate_state, load_scene, run_scene
from faultslip.fault.synthetic import simulated_events
from faultslip.friction.materials import lithologies, presets, resolve_material, user_rate_state_fits
from faultslip.friction.registry import registry_path
from faultslip.io import budget
from faultslip.io.atomic import save_figure, write_text_atomic
from faultslip.io.catalogs import QUAKEML_SUFFIXES, parse_time, write_quakeml
from faultslip.io.netcdf import write_dataset
from faultslip.io.outputs import FIGURE_SUFFIXES, check_output
from faultslip.io.waveforms import MAX_SAMPLES, STREAM_SUFFIXES, build_stream, check_datable, sac_path, write_stream
from faultslip.dynamics.asperity import choose_method as asperity_choose
from faultslip.dynamics.asperity import report as asperity_report
from faultslip.dynamics.asperity import run_dataset as asperity_dataset
from faultslip.dynamics.asperity import simulate as asperity_simulate
from faultslip.lab.asperity_scene import is_asperity_scene, load_asperity_scene
from faultslip.plots.asperity import response_figure as asperity_response_figure
from faultslip.lab.nanoscale_scene import is_nanoscale_scene, load_nanoscale_scene
from faultslip.lab.rough_slider import is_rough_scene, load_rough_scene
from faultslip.lab.vibration_scene import is_vibration_scene, load_vibration_scene
from faultslip.plots.figures import critical_comparison_figure, sawtooth_figure
from faultslip.plots.rate_state import cycles_figure
from faultslip.plots.vibration import nanoscale_figure, vibration_series_figure
from faultslip.units import to_si


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
    tolerance = _tolerance(args)
    if args.scene is not None and is_asperity_scene(args.scene):
        return _run_asperity(args, tolerance)
    if args.scene is not None and is_nanoscale_scene(args.scene):
        return _run_nanoscale(args, tolerance)
    if args.scene is not None and is_vibration_scene(args.scene):
        return _run_vibration(args, tolerance)
    if args.scene is not None and is_rough_scene(args.scene):  # seed 000: a kinetic law on seed 003's engine
        system, details, settings = load_rough_scene(args.scene)
        solution = solve(system, method=args.method or "auto", tolerance=tolerance or 1e-6, cycles=settings["cycles"])
        report = solution.report(f"faultslip rough-surface slider (seed 000): {system.name}")
        _rough_details(report, details)
        return _emit(report, args.json)
    return _emit(run_scene(load_scene(args.scene), method=args.method, tolerance=tolerance), args.json)


def _run_nanoscale(args, tolerance) -> int:
    """A nanoscale scene (seed 001): the regime in closed form, integrated only where the swing needs it."""
    model, settings, notes = load_nanoscale_scene(args.scene)
    method = args.method or settings["method"]
    # the closed form, when asked for by name, answers the regime alone
    wanted = ("regime",) if method == "nanoscale_linear_stability" else ("regime", "force_swing")
    choice = choose_method(model, wanted, method, tolerance or settings["tolerance"])
    run = (model.simulate(settings["duration"], settings["samples"], rtol=choice.rtol)
           if choice.method == "nanoscale_LSODA" else None)
    report = nanoscale_report(model, run, choice, f"faultslip nanoscale scene: {notes['name']}")
    _note_origin(report, notes.get("origin") and f"scene: {notes['origin']}")
    return _emit(report, args.json)


def _run_asperity(args, tolerance) -> int:
    """An asperity scene (seed 004): critical speeds in closed form, the response where it is asked."""
    model, settings, notes = load_asperity_scene(args.scene)
    choice = asperity_choose(model, ("response",), tolerance or settings["tolerance"], args.method or settings["method"])
    run = (asperity_simulate(model, settings["duration"], choice.method)
           if choice.method != "asperity_wavelength" else None)
    report = asperity_report(model, run, choice, f"faultslip asperity scene (seed 004): {notes['name']}")
    _note_origin(report, notes.get("origin") and f"scene: {notes['origin']}")
    return _emit(report, args.json)


def _simulate_asperity(args) -> int:
    """An asperity scene's time series, its report and the seed 004 response figure."""
    _refuse_seed_law_flags(args, "an asperity scene sets its run in [run] duration and its method in [method]")
    model, settings, notes = load_asperity_scene(args.scene)
    outputs = _outputs(args, {"output": ("-o", (".nc",)), "plot": ("--plot", FIGURE_SUFFIXES)}, [args.scene])
    choice = asperity_choose(model, ("response", "time_series"), settings["tolerance"], settings["method"])
    if choice.method == "asperity_wavelength":
        raise InputError("asperity_wavelength gives critical speeds only; a simulation needs asperity_quasistatic "
                         "or asperity_LSODA in [method] name")
    run = asperity_simulate(model, settings["duration"], choice.method)
    report = asperity_report(model, run, choice, f"faultslip asperity simulation (seed 004): {notes['name']}")
    _note_origin(report, notes.get("origin") and f"scene: {notes['origin']}")
    if run.status != "ok":
        raise FaultslipError(f"{choice.method} did not finish {notes['name']}: {run.reason}")
    _save_run(report, outputs, args, asperity_dataset(run) if outputs["output"] else None,
              lambda: asperity_response_figure(run), "time series", "seed 004 response panels")
    return _emit(report, args.json)


def _run_vibration(args, tolerance) -> int:
    """A vibration scene (seed 002): the settled amplitude, by averaging where it is accurate enough."""
    system, notes = load_vibration_scene(args.scene)
    method = {None: "auto", "auto": "auto", "quasi_harmonic_averaging": "averaging",
              "quasi_harmonic_integration": "integration"}.get(args.method)
    if method is None:
        raise InputError(f"a vibration scene takes --method auto, quasi_harmonic_averaging or "
                         f"quasi_harmonic_integration, got {args.method!r}")
    result = system.analyse()
    settled = settled_amplitude(system, method, tolerance or 1e-3) if result.valid else None
    report = averaging_report(system, result, None, settled)
    _note_origin(report, notes.get("origin") and f"scene: {notes['origin']}")
    return _emit(report, args.json)


def _rough_details(report, details) -> None:
    report.section("Rough surfaces (seed 000)")
    report.add("static_friction_model", details["static_friction"], label="mu_s = p_s / H")
    report.add("area_fraction_at_rest", details["area_fraction_at_rest"], label="real / nominal area at rest (L / H A_n)")
    report.add("compression_at_rest", details["compression_at_rest"], "m", label="static compression h0 (H A(h0) = L)")
    reference = "RMS" if details["separation_reference"] == "rms" else "h0"
    report.add("separation_per_speed", details["separation_per_speed"], "s",
               label=f"separation per sliding speed c {reference} (m per m/s)")
    report.add("separation_memory", details["separation_memory"],
               label="separation memory (none, held, falling)")
    report.add("natural_frequency", details["natural_frequency"], "Hz", label="sqrt(k/M) / 2 pi")


def _simulate_rough(args) -> int:
    """A rough-surface scene's stick-slip on seed 003's event-driven engine."""
    system, details, settings = load_rough_scene(args.scene)
    outputs = _outputs(args, {"output": ("-o", (".nc",)), "plot": ("--plot", FIGURE_SUFFIXES)}, [args.scene])
    cycles = args.cycles or settings["cycles"]
    if not 1 <= cycles <= 10_000:
        raise FaultslipError(f"--cycles must be from 1 to 10000, got {cycles}")
    dataset = simulate(system, cycles=cycles, slip_solver=args.slip_solver or "DOP853",
                       rtol=_number(args.rtol, "--rtol") if args.rtol else 1e-8, scene=system.name)
    report = summary_report(dataset, f"faultslip simulation (seed 000 rough surfaces): {system.name}")
    _rough_details(report, details)
    _save_run(report, outputs, args, dataset, lambda: sawtooth_figure(dataset), "time series and event table",
              "sawtooth record")
    return _emit(report, args.json)


def _refuse_seed_law_flags(args, why: str) -> None:
    """The seed law's simulation flags, refused for a scene of another kind."""
    extra = [flag for flag in ("cycles", "slip_solver", "rtol") if getattr(args, flag) is not None]
    if extra:
        raise InputError(f"--{extra[0].replace('_', '-')} applies to seed-law scenes; {why}")


def _simulate_vibration(args) -> int:
    """A vibration scene's eq. (10) time series from a small disturbance, beside the averaged envelope."""
    _refuse_seed_law_flags(args, "a vibration scene is integrated by DOP853 at rtol 1e-10 until its cycle settles")
    system, notes = load_vibration_scene(args.scene)
    outputs = _outputs(args, {"output": ("-o", (".nc",)), "plot": ("--plot", FIGURE_SUFFIXES)}, [args.scene])
    run = simulate_vibration(system)
    report = vibration_report(run)
    _note_origin(report, notes.get("origin") and f"scene: {notes['origin']}")
    _save_run(report, outputs, args, vibration_dataset(run) if outputs["output"] else None,
              lambda: vibration_series_figure(run), "time series", "displacement and envelope")
    return _emit(report, args.json)


def _simulate_nanoscale(args) -> int:
    """A nanoscale scene's time series (LSODA), the report and the seed 001 Fig. 3 plot."""
    _refuse_seed_law_flags(args, "a nanoscale scene sets its run in [run] and its accuracy in [method] tolerance")
    model, settings, notes = load_nanoscale_scene(args.scene)
    outputs = _outputs(args, {"output": ("-o", (".nc",)), "plot": ("--plot", FIGURE_SUFFIXES)}, [args.scene])
    choice = choose_method(model, ("regime", "force_swing", "time_series"), "auto", settings["tolerance"])
    run = model.simulate(settings["duration"], settings["samples"], rtol=choice.rtol,
                         allow_large=getattr(args, "allow_large", False))
    report = nanoscale_report(model, run, choice, f"faultslip nanoscale simulation: {notes['name']}")
    _note_origin(report, notes.get("origin") and f"scene: {notes['origin']}")
    _save_run(report, outputs, args, nanoscale_dataset(run) if outputs["output"] else None,
              lambda: nanoscale_figure(run), "time series", "seed 001 Fig. 3")
    return _emit(report, args.json)


def cmd_fault(args) -> int:
    inputs = {target: getattr(args, flag) for flag, target in _FAULT_QUANTITIES.items() if getattr(args, flag) is not None}
    if args.lithology and resolve_material(args.lithology).rate_state is not None:
        return _fault_rate_state(args, inputs)
    if args.seed_law:
        raise InputError("--seed-law goes with a rate-and-state fit as --lithology")
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


def _fault_rate_state(args, inputs) -> int:
    extra = [flag for flag in ("mu_so", "mu_m", "rate_coefficient", "rate_exponent", "damping_ratio",
                               "observed_slip", "method") if getattr(args, flag, None) is not None]
    if extra or args.radiation_damping:
        flags = ", ".join("--" + f.replace("_", "-") for f in extra + (["radiation_damping"] if args.radiation_damping
                                                                       else []))
        raise InputError(f"{flags} do not apply to the rate-and-state fit {args.lithology!r} (its fault is always "
                         "quasi-dynamic, with the radiation damper)")
    estimate = estimate_fault_from_fit(args.lithology, inputs, seed_law=args.seed_law or "granodiorite")
    return _emit(estimate.report(f"faultslip fault: {args.name} (rate-and-state fit {args.lithology!r})"), args.json)


def _required(inputs: dict) -> dict:
    missing = [flag for flag in ("zone_width", "slip_rate") if flag not in inputs]
    if missing:
        raise InputError(f"missing {', '.join('--' + m.replace('_', '-') for m in missing)}, required for a fault estimate")
    return inputs


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
        for lith in lithologies().values()
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
    rows = describe_all()
    if args.json:
        print(json.dumps({"methods": rows}, indent=2))
        return 0
    for row in rows:
        print(f"{row['name']}\n  friction laws: {row['friction_laws']}\n  valid where:   {row['domain']}\n"
              f"  cost:          {row['cost_model']}")
    return 0


def cmd_simulate(args) -> int:
    if is_asperity_scene(args.scene):
        return _simulate_asperity(args)
    if is_nanoscale_scene(args.scene):
        return _simulate_nanoscale(args)
    if is_vibration_scene(args.scene):
        return _simulate_vibration(args)
    if is_rough_scene(args.scene):
        return _simulate_rough(args)
    scene = load_scene(args.scene)
    outputs = _outputs(args, {"output": ("-o", (".nc",)), "plot": ("--plot", FIGURE_SUFFIXES),
                              "stream": ("--stream", tuple(STREAM_SUFFIXES)), "events": ("--events", QUAKEML_SUFFIXES)},
                       [scene.path])
    if scene.rate_state:
        if outputs["stream"] or outputs["events"]:
            raise InputError("--stream and --events apply to seed-law scenes; a rate-and-state scene's cycles are "
                             "written with -o")
        return _simulate_rate_state(args, scene, outputs)
    if outputs["stream"] and outputs["stream"].suffix.lower() == ".sac":  # one file per component, checked now
        for component in ("D", "S", "R", "F"):
            check_output(sac_path(outputs["stream"], component), label="--stream", suffixes=(".sac",),
                         inputs=[scene.path], overwrite=args.overwrite)
    if outputs["events"] and scene.kind != "fault":
        raise InputError("--events writes earthquakes with Mw from M0: it needs a fault scene")
    rate = _number(args.sampling_rate, "--sampling-rate") if args.sampling_rate else None
    start = (float(parse_time(args.start_time, "--start-time").astype("datetime64[ms]").astype("int64")) / 1e3
             if args.start_time else 946684800.0)
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
    if outputs["stream"] or outputs["events"]:  # before anything is written
        check_datable(start, float(dataset["time"].values[-1]), settings.get("cycles", 100))
    dataset.attrs["scene_text"] = scene.text
    report = summary_report(dataset, f"faultslip simulation: {scene.name}")
    _note_origin(report, scene.origin and f"scene: {scene.origin}")
    _save_run(report, outputs, args, dataset, lambda: sawtooth_figure(dataset), "time series and event table",
              "sawtooth record")
    if outputs["stream"]:
        rate, channels, note = uniform_channels(dataset, rate, 10 * MAX_SAMPLES if args.allow_large else MAX_SAMPLES)
        stream = build_stream(rate, channels, start_seconds=start)
        with _locked(outputs["stream"]):
            written = write_stream(stream, outputs["stream"])
        report.note(f"stream of {', '.join(t.id for t in stream)} at {rate:.4g} Hz ({stream[0].stats.npts} samples) "
                    f"written to {', '.join(str(p) for p in written)}" + (f"; {note}" if note else ""))
    if outputs["events"]:
        events = simulated_events(dataset, scene.fault(), scene.trace, start)
        with _locked(outputs["events"]):
            write_quakeml(events["times"], events["latitude"], events["longitude"], events["depth"],
                          events["magnitude"], outputs["events"], names=events["names"],
                          comment=f"faultslip simulation of {scene.name}")
        report.note(f"{len(events['names'])} events (Mw {float(events['magnitude'].max()):.2f}) written as QuakeML "
                    f"to {args.events}" + (f"; {events['note']}" if events["note"] else ""))
    return _emit(report, args.json)


def _simulate_rate_state(args, scene, outputs) -> int:
    """simulate of a fault scene with rate-and-state friction: its quasi-dynamic cycles as a time series."""
    if args.slip_solver is not None or args.rtol is not None:
        raise FaultslipError("--slip-solver and --rtol belong to the seed law's simulation; a rate-and-state fault's "
                             "cycles run at rtol 1e-7 with the method auto picks")
    cycles = 5 if args.cycles is None else args.cycles
    if not 1 <= cycles <= 1000:
        raise FaultslipError(f"--cycles must be from 1 to 1000 for a rate-and-state fault, got {cycles}")
    estimate = estimate_scene_rate_state(scene, cycles=cycles, record=True)
    report = estimate.report(f"faultslip simulation (rate-and-state fault): {scene.name}")
    _note_origin(report, scene.origin and f"scene: {scene.origin}")
    if estimate.cycles is None:
        report.note("steady sliding is stable here (K >= K_c): no cycles to record")
        return _emit(report, args.json)
    dataset = cycles_dataset(estimate, f"faultslip rate-and-state cycles: {scene.name}")
    dataset.attrs["scene_text"] = scene.text
    report.add("samples", int(dataset.sizes["time"]), label="time samples (the integrator's steps)")
    _save_run(report, outputs, args, dataset, lambda: cycles_figure(dataset), "time series and event table",
              "cycles")
    return _emit(report, args.json)


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
