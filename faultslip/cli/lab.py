"""Laboratory commands: fit, record, decay, quasi-harmonic, nanoscale."""

from __future__ import annotations

import argparse
import json
import math
import tempfile

import numpy as np

import faultslip
from faultslip import ranges
from faultslip.cli.common import _locked, _number, _outputs, _save_run
from faultslip.cli.printing import _emit, _progress
from faultslip.constants import STANDARD_GRAVITY
from faultslip.dynamics.vibration import (ERROR_CONSTANT, amplitude_table, error_against_eps,
                                         error_over_eps_squared, hand_over_map, regions)
from faultslip.errors import FaultslipError, InputError
from faultslip.friction.fitting import fit_figure, fit_rate_law, read_friction_data
from faultslip.friction.materials import check_fit_name, save_user_fit
from faultslip.io.atomic import save_figure
from faultslip.io.bundle import compare_numbers, extract_record, package_versions, read_bundle, write_bundle
from faultslip.io.netcdf import write_dataset
from faultslip.io.outputs import FIGURE_SUFFIXES
from faultslip.io.report import Report
from faultslip.lab.classroom import analyse as analyse_classroom
from faultslip.lab.classroom import is_accelerometer_csv, read_accelerometer
from faultslip.lab.fit_workflow import INTERVALS_NOTE, fit_record
from faultslip.lab.posterior import parse_prior
from faultslip.lab.look_reduction import run_r_file
from faultslip.lab.records import analyze_record, free_decay, free_decay_from_record, hysteresis_figure, read_record
from faultslip.plots.figures import classroom_figure
from faultslip.plots.posterior import corner_figure, record_fit_figure
from faultslip.plots.vibration import error_figure, hand_over_figure, regions_figure
from faultslip.units import to_si


#: the options of 'faultslip fit' a bundle records and a replay sets again (outputs and the registry aside)
FIT_OPTIONS = ("law", "loss", "bootstrap", "seed", "mu_m", "stiffness", "select_law", "stiffness_free", "joint", "area",
               "units", "detrend", "steps", "min_change", "each_step", "windows", "posterior", "samples", "walkers", "max_steps",
               "prior", "workers", "evolution", "two_state", "shear_modulus", "columns", "span")
#: what each of them holds, as the fit's parser declares it (tests/capabilities/lab/test_fit_bundle.py holds the two together):
#: a whole number, a switch, a repeated text, or text (None where not given); a bundle's option of another kind is
#: refused before the replay runs
FIT_OPTION_KINDS = {**{name: "text" for name in FIT_OPTIONS},
                    **{name: "count" for name in ("bootstrap", "seed", "samples", "walkers", "max_steps", "workers")},
                    **{name: "switch" for name in ("select_law", "stiffness_free", "each_step", "posterior", "two_state")},
                    "joint": "texts", "prior": "texts"}
#: the options the fit's parser gives a default other than None: a bundle may not leave them empty
FIT_OPTIONS_NOT_NONE = ("law", "loss", "seed", "detrend", "min_change", "samples", "max_steps", "evolution",
                        "select_law", "stiffness_free", "each_step", "posterior", "two_state")
#: the options whose text is one of a few
FIT_OPTION_CHOICES = {"law": ("rate-law", "rate-state"), "detrend": ("none", "linear", "quadratic", "fitted"),
                      "evolution": ("aging", "slip")}


_KIND_WORDS = {"count": "a whole number", "switch": "true or false", "texts": "a list of texts", "text": "text"}


def _check_bundle_options(options: dict, source) -> None:
    """A bundle's options, each of the kind 'faultslip fit' takes (:data:`FIT_OPTION_KINDS`), or one sentence."""
    unknown = sorted(set(options) - set(FIT_OPTIONS))
    if unknown:
        raise FaultslipError(f"fit bundle {source}: option {unknown[0]!r} is not one 'faultslip fit' has")
    for name, value in options.items():
        kind = FIT_OPTION_KINDS[name]
        fits = (value is None and kind != "switch" and name not in FIT_OPTIONS_NOT_NONE or
                kind == "count" and isinstance(value, int) and not isinstance(value, bool) or
                kind == "switch" and isinstance(value, bool) or
                kind == "texts" and isinstance(value, list) and all(isinstance(v, str) for v in value) or
                kind == "text" and isinstance(value, str))
        if not fits:
            raise FaultslipError(f"fit bundle {source}: option {name!r} holds {value!r}, where 'faultslip fit' takes "
                                 f"{_KIND_WORDS[kind]}")
        if name in FIT_OPTION_CHOICES and value is not None and value not in FIT_OPTION_CHOICES[name]:
            raise FaultslipError(f"fit bundle {source}: option {name!r} is {value!r}, not one of "
                                 f"{', '.join(FIT_OPTION_CHOICES[name])}")


def cmd_fit(args) -> int:
    if args.replay is not None:
        return _replay_fit(args)
    if args.data is None:
        raise FaultslipError("fit needs a data file (or --replay FIT.zip)")
    bundle = _outputs(args, {"bundle": ("--bundle", (".zip",))}, [args.data])["bundle"]
    if bundle is not None and args.joint:
        raise FaultslipError("--bundle holds one record: a --joint fit's further records are not bundled")
    if args.name is not None:  # before any work: a fit is never computed only to be refused at the end
        check_fit_name(args.name, args.overwrite)
    report, draws = _fit(args)
    if bundle is not None:
        options = {name: getattr(args, name) for name in FIT_OPTIONS}
        with _locked(bundle):
            manifest = write_bundle(bundle, record_path=args.data, options=options, report=report.to_dict(),
                                    draws=draws)
        report.note(f"bundle written to {args.bundle}: the record (SHA-256 {manifest['record']['sha256'][:12]}...), "
                    f"every option, the versions, the draws and this report; replay it with 'faultslip fit --replay "
                    f"{args.bundle}'")
    return _emit(report, args.json)


def _fit(args):
    """Run the fit the options ask for: (its report, its draws by kind for a bundle)."""
    if args.law == "rate-state":
        return _fit_rate_state(args)
    for flag, given in (("--stiffness-free", args.stiffness_free), ("--select-law", args.select_law),
                        ("--joint", args.joint)):
        if given:
            raise FaultslipError(f"{flag} applies to a rate-and-state record (--law rate-state)")
    plot = _outputs(args, {"plot": ("--plot", FIGURE_SUFFIXES)}, [args.data])["plot"]
    if args.bootstrap is None:
        args.bootstrap = 200
    ranges.check_count(args.bootstrap, "--bootstrap", 0, ranges.MOST_RESAMPLES)
    if args.loss not in ("linear", "soft_l1", "huber", "cauchy"):
        raise FaultslipError(f"--loss must be linear, soft_l1, huber or cauchy, got {args.loss!r}")
    ranges.check_count(args.seed, "--seed")
    modulus = None
    if args.shear_modulus:
        modulus = ranges.check("shear_modulus", to_si(args.shear_modulus, "pressure", "shear modulus"))
    fixed = None if args.mu_m is None else _number(args.mu_m, "mu_m")
    data = read_friction_data(args.data, fixed_mu_m=fixed)
    fit = fit_rate_law(data, loss=args.loss, bootstrap=args.bootstrap, seed=args.seed, fixed_mu_m=fixed)
    report = fit.report(f"faultslip fit: {args.data}")
    if plot:
        with _locked(plot):
            save_figure(fit_figure(data, fit), plot, dpi=150)
        report.note(f"plot written to {args.plot}")
    if args.name:  # only after the fit succeeded: a failed fit never touches the registry
        path = save_user_fit(args.name, fit, shear_modulus=modulus, note=args.note or "", overwrite=args.overwrite)
        report.note(f"saved as {args.name!r} in {path}; use it with 'faultslip fault --lithology {args.name} ...'")
    return report, {"bootstrap": (["mu_so", "mu_m", "b", "d"], fit.bootstrap)}


def _replay_fit(args) -> int:
    """fit --replay FIT.zip: the bundle's fit again, on its own record and options; every number compared."""
    given = [flag for flag, value in (("a data file", args.data), ("--bundle", args.bundle), ("--name", args.name),
                                      ("--plot", args.plot), ("--corner", args.corner)) if value]
    if given:
        raise FaultslipError(f"--replay runs the bundle's own fit: it takes no {given[0]}")
    bundle = read_bundle(args.replay)
    options = bundle.manifest["options"]
    _check_bundle_options(options, args.replay)
    with tempfile.TemporaryDirectory(prefix="faultslip-replay-") as folder:
        record = extract_record(bundle, folder)
        replay = argparse.Namespace(**{**vars(args), **options, "data": str(record), "replay": None, "bundle": None,
                                       "name": None, "plot": None, "corner": None, "json": True})
        report, draws = _fit(replay)
    comparison = compare_numbers(bundle.report, report.to_dict())
    moved_draws = []
    for kind, (names, values) in bundle.draws.items():
        again = np.asarray(draws.get(kind, ([], np.empty((0, 0))))[1], dtype=float)
        if again.shape != values.shape or not np.array_equal(again, values):
            change = (float(np.max(np.abs(again - values)) / max(float(np.max(np.abs(values))), 1e-300))
                      if again.shape == values.shape else math.inf)
            moved_draws.append((kind, change))
    versions = bundle.manifest.get("versions", {})
    if not (isinstance(versions, dict) and all(isinstance(v, str) or v is None for v in versions.values())):
        raise FaultslipError(f"fit bundle {args.replay}: its manifest's versions is not a table of package versions")
    now = package_versions()
    differ = sorted(name for name in set(versions) | set(now) if versions.get(name) != now.get(name))
    # a replay that computes numbers its bundle lacks, or finds none to compare, has shown nothing identical
    identical = (not comparison["moved"] and not moved_draws and not comparison["missing"] and not comparison["extra"]
                 and comparison["compared"] > 0)
    result = {"bundle": str(args.replay), "identical": identical, "numbers_compared": comparison["compared"],
              "numbers_moved": [{"key": key, "bundle": old, "replay": new, "relative_change": change}
                                for key, old, new, change in comparison["moved"]],
              "numbers_missing": comparison["missing"], "numbers_only_in_replay": comparison["extra"],
              "draws_compared": {kind: list(values.shape) for kind, (_, values) in bundle.draws.items()},
              "draws_moved": [{"kind": kind, "largest_relative_change": change} for kind, change in moved_draws],
              "versions_that_differ": {name: [versions.get(name), now.get(name)] for name in differ}}
    if args.json:
        print(json.dumps(result, indent=2, allow_nan=False, default=str))
    else:
        print(f"faultslip fit --replay {args.replay}")
        print(f"  {comparison['compared']} numbers and "
              f"{sum(values.size for _, values in bundle.draws.values())} draws compared")
        if differ:
            print("  versions that differ: " + ", ".join(f"{n} {versions.get(n)} -> {now.get(n)}" for n in differ))
        if identical:
            print("  replayed bit for bit: every number and every draw is the same")
        for key, old, new, change in comparison["moved"][:40]:
            print(f"  moved: {key}: {old!r} -> {new!r} (relative {change:.2e})")
        for kind, change in moved_draws:
            print(f"  draws moved: {kind} (largest relative change {change:.2e})")
        for key in comparison["missing"][:20]:
            print(f"  missing from the replay: {key}")
        for key in comparison["extra"][:20]:
            print(f"  not in the bundle's report: {key}")
        if not comparison["compared"]:
            print("  no number of the bundle's report could be compared: nothing was shown identical")
    return 0 if identical else 1


def _parse_units(text):
    """``"time=ms, shear_load=kN"`` -> {name: unit}."""
    units = {}
    for part in (text or "").split(","):
        if not part.strip():
            continue
        name, _, unit = part.partition("=")
        if not unit.strip():
            raise FaultslipError(f"--units takes name=unit pairs separated by commas, got {part.strip()!r}")
        units[name.strip()] = unit.strip()
    return units


def _fit_rate_state(args) -> int:
    """fit --law rate-state: parse the options, run faultslip.lab.fit_workflow.fit_record, draw, save, print."""
    if args.stiffness is None:
        raise FaultslipError("fit --law rate-state needs --stiffness: the machine stiffness as friction per slip "
                             "('1e-2 1/um'), stress per slip ('50 MPa/mm') or force per slip ('200 kN/mm', with "
                             "--area)")
    if args.mu_m is not None or args.loss != "linear":
        raise FaultslipError("--mu-m and --loss apply to the seed's rate law, not to --law rate-state")
    outputs = _outputs(args, {"plot": ("--plot", FIGURE_SUFFIXES), "corner": ("--corner", FIGURE_SUFFIXES)},
                       [args.data])
    if outputs["corner"] is not None and not args.posterior:
        raise FaultslipError("--corner draws the posterior: give --posterior too")
    modulus = None
    if args.shear_modulus:
        modulus = ranges.check("shear_modulus", to_si(args.shear_modulus, "pressure", "shear modulus"))
    steps = [to_si(part, "time", "--steps") for part in args.steps.split(",") if part.strip()] if args.steps else None
    result = fit_record(args.data, args.stiffness, area=args.area, units=_parse_units(args.units),
                        detrend=args.detrend, steps=steps, min_change=_number(args.min_change, "--min-change"),
                        evolution=args.evolution, two_state=args.two_state,
                        bootstrap=(0 if args.posterior else 50) if args.bootstrap is None else args.bootstrap,
                        seed=args.seed, windows=_parse_windows(args.windows), each_step=args.each_step,
                        posterior=args.posterior, priors=dict(parse_prior(text) for text in (args.prior or [])),
                        samples=args.samples, walkers=args.walkers, max_steps=args.max_steps,
                        workers=args.workers or 1, stiffness_free=args.stiffness_free, select=args.select_law,
                        joint=args.joint or (), columns=_parse_columns(args.columns), span=_parse_span(args.span),
                        progress=_progress("fit", not args.json))
    report, posterior = result.report, result.posterior
    if outputs["plot"] is not None or outputs["corner"] is not None:
        with _locked(outputs["plot"], outputs["corner"]):
            if outputs["plot"] is not None:
                fitted = result.fitted_friction(seed=args.seed)
                save_figure(record_fit_figure(result.record, fitted["friction"], fitted["band"],
                                              title=f"{args.data}: {fitted['law'].evolution} law",
                                              raw_friction=fitted["raw_friction"], trend=None), outputs["plot"], dpi=150)
                report.note(f"record and fit drawn to {args.plot}")
            if outputs["corner"] is not None:
                save_figure(corner_figure(posterior), outputs["corner"], dpi=130)
                report.note(f"corner plot drawn to {args.corner}")
    report.note(INTERVALS_NOTE)
    if args.name:  # only after the fit succeeded: a failed fit never touches the registry
        path = save_user_fit(args.name, result.saved, shear_modulus=modulus, note=args.note or "",
                             source=str(args.data), overwrite=args.overwrite)
        report.note(f"saved as {args.name!r} in {path} with its {'posterior draws' if posterior else 'resamples'}; "
                    f"use it with 'faultslip fault --lithology {args.name} ...'")
    draws = {"bootstrap": (list(result.fit.parameters), result.fit.bootstrap)}
    if posterior is not None:
        draws["posterior"] = (list(posterior.names), posterior.samples)
    return report, draws


def _parse_columns(text):
    """--columns 'time=Time, load_point_displacement=LP_disp' as {faultslip's name: the file's}."""
    if not text:
        return None
    columns = {}
    for part in text.split(","):
        name, separator, source = part.strip().partition("=")
        if not separator or not name.strip() or not source.strip():
            raise FaultslipError(f"--columns takes name=column pairs separated by commas, e.g. 'time=Time, "
                                 f"load_point_displacement=LP_disp'; got {part.strip()!r}")
        if name.strip() in columns:
            raise FaultslipError(f"--columns names {name.strip()!r} twice")
        columns[name.strip()] = source.strip()
    return columns


def _parse_span(text):
    """--span '2400 s - 3150 s' as (start, end) in seconds."""
    if not text:
        return None
    start, separator, end = text.strip().partition(" - ")
    if not separator:
        raise FaultslipError(f"--span takes 'start - end' with units, e.g. '2400 s - 3150 s'; got {text.strip()!r}")
    return to_si(start, "time", "--span"), to_si(end, "time", "--span")


def _parse_windows(text):
    """--windows '50 s - 130 s, 200 s - 260 s' as [(start, end)] in seconds."""
    if not text:
        return None
    windows = []
    for part in text.split(","):
        start, separator, end = part.strip().partition(" - ")
        if not separator:
            raise FaultslipError(f"--windows takes 'start - end' pairs with units, separated by commas, "
                                 f"e.g. '50 s - 130 s'; got {part.strip()!r}")
        windows.append((to_si(start, "time", "--windows"), to_si(end, "time", "--windows")))
    return windows


def cmd_record(args) -> int:
    plot = _outputs(args, {"plot": ("--plot", FIGURE_SUFFIXES)}, [args.record])["plot"]
    if args.velocity not in ("auto", "differentiate", "integrate"):
        raise FaultslipError(f"--velocity must be auto, differentiate or integrate, got {args.velocity!r}")
    for flag, kind, name in (("stiffness", "stiffness", "stiffness"), ("normal_load", "force", "normal_load"),
                             ("mass", "mass", "mass"), ("platform_speed", "speed", "platform_speed")):
        if getattr(args, flag):
            ranges.check(name, to_si(getattr(args, flag), kind, f"--{flag.replace('_', '-')}"))
    if args.dashpot and not to_si(args.dashpot, "damping", "dashpot") >= 0:
        raise FaultslipError(f"--dashpot must not be negative, got {args.dashpot}")
    if is_accelerometer_csv(args.record):  # the classroom experiment: acceleration alone (docs/classroom.md)
        return _record_classroom(args, plot)
    if args.axis:
        raise InputError("--axis applies to accelerometer records (phyphox); this record has a displacement")
    if not (args.stiffness and args.normal_load):
        raise InputError("a motion record needs --stiffness and --normal-load (seed 003 eq. 3-2)")
    record = read_record(args.record)
    speed = to_si(args.platform_speed, "speed", "platform speed") if args.platform_speed else None
    analysis = analyze_record(record, to_si(args.mass, "mass", "mass") if args.mass else
                              to_si(args.normal_load, "force", "normal load") / STANDARD_GRAVITY,
                              to_si(args.stiffness, "stiffness", "stiffness"), to_si(args.normal_load, "force", "normal load"),
                              speed, to_si(args.dashpot, "damping", "dashpot") if args.dashpot else 0.0,
                              velocity_method=args.velocity)
    report = analysis.report(f"faultslip record analysis: {args.record}")
    _save_run(report, {"plot": plot}, args, None, lambda: hysteresis_figure(analysis), drawing="mu against sliding speed")
    return _emit(report, args.json)


def _record_classroom(args, plot) -> int:
    if args.axis and args.axis not in ("x", "y", "z"):
        raise InputError(f"--axis must be x, y or z, got {args.axis!r}")
    analysis = analyse_classroom(read_accelerometer(args.record), axis=args.axis)
    report = analysis.report(f"faultslip record (classroom stick-slip): {args.record}")
    _save_run(report, {"plot": plot}, args, None, lambda: classroom_figure(analysis),
              drawing="acceleration with its slip phases")
    return _emit(report, args.json)


def cmd_decay(args) -> int:
    stiffness = to_si(args.stiffness, "stiffness", "stiffness")
    if args.record:
        result = free_decay_from_record(read_record(args.record), stiffness)
    else:
        if args.ratio is None or args.cycles is None or args.frequency is None:
            raise InputError("give a free-decay record, or --ratio, --cycles-between and --frequency")
        frequency = to_si(args.frequency, "frequency", "damped frequency")  # rad/s is converted to Hz
        result = free_decay(_number(args.ratio, "amplitude ratio"), _number(args.cycles, "cycles"), frequency, stiffness)
    return _emit(result.report(), args.json)


def cmd_quasi_harmonic(args) -> int:
    plot = _outputs(args, {"plot": ("--plot", FIGURE_SUFFIXES)}, [args.scene])["plot"]
    speeds = None
    if args.speeds:
        speeds = (args.speeds[0], args.speeds[1], int(_number(args.speeds[2], "--speeds count")))
    if plot and speeds is None:
        raise InputError("--plot draws the amplitude against speed: give --speeds START STOP COUNT too")
    result = faultslip.models.amplitude_study(args.scene, speed=args.speed, speeds=speeds, method=args.method,
                             tolerance=ranges.check_tolerance(args.tolerance or 1e-3, "--tolerance"))
    report, sweep, system = result.report(), result.extras["sweep"], result.extras["system"]
    if args.regions:
        chart = _outputs(args, {"regions": ("--regions", FIGURE_SUFFIXES)}, [args.scene])["regions"]
        if not (args.speeds and args.dampings):
            raise InputError("--regions draws the (v, r) plane: give --speeds START STOP COUNT and --dampings too")
        low, high = (to_si(text, "damping", "--dampings") for text in args.dampings[:2])
        count = int(_number(args.dampings[2], "--dampings count"))
        if not (0 <= low < high and 2 <= count <= 200):
            raise InputError("--dampings needs 0 <= START < STOP and a count from 2 to 200")
        with _locked(chart):
            save_figure(regions_figure(system, regions(system, sweep["speed"], np.linspace(low, high, count))),
                        chart, dpi=150)
        report.note(f"the (v, r) plane drawn to {args.regions}")
    if args.hand_over_chart:
        chart = _outputs(args, {"hand_over_chart": ("--hand-over-chart", FIGURE_SUFFIXES)}, [args.scene])["hand_over_chart"]
        with _locked(chart):
            save_figure(hand_over_figure(hand_over_map()), chart, dpi=150)
        report.note(f"averaging's hand-over against event-driven simulation drawn to {args.hand_over_chart}")
    if args.error_chart:
        chart = _outputs(args, {"error_chart": ("--error-chart", FIGURE_SUFFIXES)}, [args.scene])["error_chart"]
        table = error_against_eps(scene=system)
        with _locked(chart):
            save_figure(error_figure(table), chart, dpi=150)
        summary = error_over_eps_squared(table)
        report.section(f"Averaging's error against integration, measured (declared {ERROR_CONSTANT:g} eps^2)")
        for curve, measured in summary.items():
            low, high = measured["small_parameter"]
            report.add(f"error_over_eps_squared: {curve}", f"{measured['lowest']:.3f} to {measured['highest']:.3f}",
                       label=f"error / eps^2, {curve} (eps {low:.2g} to {high:.2g})")
        report.add("averaging_error", {"measured": {key: (table[key].tolist()) for key in table},
                                       "error_over_eps_squared": summary}, in_text=False)
        report.note(f"averaging's error against the small parameter drawn to {args.error_chart}")
    if plot:
        with _locked(plot):
            save_figure(result.plot(), plot, dpi=150)
        report.note(f"amplitude against speed drawn to {args.plot}")
    code = _emit(report, args.json)
    if sweep is not None and not args.json:
        print("\n" + amplitude_table(sweep))
    return code


def cmd_nanoscale(args) -> int:
    paths = _outputs(args, {"output": ("-o", (".nc",)), "plot": ("--plot", FIGURE_SUFFIXES)}, [args.scene])
    result = faultslip.models.nanoscale_swing(args.scene, damping=None if args.damping is None else _number(args.damping, "--damping"),
                   integrate=not args.no_run, allow_large=args.allow_large)
    report = result.report()
    if result.series is not None:
        _save_run(report, paths, args, result.series if paths["output"] else None, result.plot)
    return _emit(report, args.json)


def cmd_asperity(args) -> int:
    """Seed 004: a speed sweep of the asperity slider (m_D, stick, loops), its peaks against eqs. (28)-(29)."""
    paths = _outputs(args, {"output": ("-o", (".nc",)), "plot": ("--plot", FIGURE_SUFFIXES),
                            "map": ("--map", FIGURE_SUFFIXES)}, [args.scene])
    result = faultslip.models.asperity_speed_study(args.scene, args.low, args.high, args.points, dashpot=args.dashpot, method=args.method,
                         integrator_map=bool(paths["map"]), progress=_progress("speed sweep", not args.json, "speed"),
                         tolerance=args.tolerance)
    report = result.report()
    with _locked(paths["output"], paths["plot"], paths["map"]):
        if paths["map"]:
            save_figure(result.extras["map_figure"](), paths["map"])
            report.note(f"integrator map written to {args.map}")
        if paths["output"]:
            write_dataset(result.series, paths["output"])
            report.note(f"sweep written to {args.output}")
        if paths["plot"]:
            save_figure(result.plot(), paths["plot"])
            report.note(f"figure written to {args.plot}")
    return _emit(report, args.json)


def cmd_reduce(args) -> int:
    """An xlook r-file's reduction: each slot's name, unit, records and range; the columns to netCDF with -o."""
    outputs = _outputs(args, {"output": ("-o", (".nc",))}, [args.r_file])
    reduction = run_r_file(args.r_file)
    report = Report(f"faultslip reduce: {reduction.source}")
    report.add("commands", reduction.commands)
    report.add("commands_run", " ".join(reduction.ran), label="the commands run, in order")
    report.add("commands_skipped", list(reduction.skipped), label="display commands skipped (no data changes)")
    for name, (values, unit) in reduction.as_dict().items():
        finite = values[np.isfinite(values)]
        report.add(name, [float(finite.min()), float(finite.max())] if finite.size else None, None,
                   f"{name} ({unit}): {values.size} records, min and max")
    if outputs["output"]:
        with _locked(outputs["output"]):
            write_dataset(reduction.to_dataset(), outputs["output"])
        report.note(f"reduced columns written to {outputs['output']}")
    return _emit(report, args.json)
