"""The map command: regional maps, hazard sources and their figures (the sweep commands are in cli/sweeps.py)."""

from __future__ import annotations

import importlib.util

import json
import math
from datetime import datetime, timezone

import numpy as np
from pathlib import Path

from faultslip.constants import JULIAN_YEAR
from faultslip.cli.common import _number, _locked, _outputs, _tolerance
from faultslip.errors import InputError
from faultslip.io.atomic import save_figure
from faultslip.io.netcdf import write_dataset
from faultslip.io.outputs import check_output, FIGURE_SUFFIXES
from faultslip.units import to_si
from faultslip.io.atomic import claim
from faultslip.fault import mfd as mfds
from faultslip.plots.displacement import displacement_hazard_figure
from faultslip.plots.fault_maps import fault_system_figure
from faultslip.studies import displacement_hazard, hazard, rupture_sets
from faultslip.cli.printing import _emit_estimate
from faultslip.studies.maps import (check_map_size, has_observations, map_size_estimate, read_map, map_figure,
                                    observed_figure, observed_table, run_map, segment_rows)

#: Segments printed in the text table; all of them are in the netCDF file and in --json.
MOST_ROWS = 50


def _hazard_options(args, spec, outputs) -> dict | None:
    """Check the NRML and engine-job options and claim every file they will write, before any work."""
    if args.mfd not in mfds.KINDS:
        raise InputError(f"--mfd must be one of {', '.join(mfds.KINDS)}, got {args.mfd!r}")
    relations = hazard.parse_relations(args.scaling_relations)
    wanted = outputs["nrml"] is not None
    if not wanted:
        # without --nrml, an engine job may still run the time-dependent sources (checked in _renewal_options)
        job_flags = () if outputs["time_dependent"] is not None else (("--engine-job", outputs["engine_job"]),
                                                                       ("--sites", args.sites))
        for flag, value in (*job_flags, ("--scaling-relations", args.scaling_relations)):
            if value is not None:
                raise InputError(f"{flag} describes NRML sources: give --nrml FILE.xml too")
        return None
    if spec.segments is None:
        raise InputError("--nrml writes fault sources: it needs a segment map ([segments]), not a raster")
    if (outputs["engine_job"] is None) != (args.sites is None):
        raise InputError("--engine-job and --sites go together: the job computes hazard at the sites")
    options = {"relations": relations, "kind": args.mfd,
               "b_value": _number(args.b_value, "--b-value"), "min_magnitude": _number(args.min_magnitude,
                                                                                     "--min-magnitude"),
               "bin_width": _number(args.mfd_bin_width, "--mfd-bin-width"),
               "moment_constant": _number(args.moment_constant, "--moment-constant"),
               "sites": hazard.parse_sites(args.sites) if args.sites is not None else None}
    mfds.check_parameters(options["b_value"], options["bin_width"], min_magnitude=options["min_magnitude"])
    if options["moment_constant"] not in (9.1, 9.05):
        raise InputError(f"--moment-constant must be 9.1 (faultslip's Mw) or 9.05 (Hanks & Kanamori, the engine's "
                         f"MFD code), got {args.moment_constant}")
    # the branch files and the engine job's logic trees, checked and held like -o
    system = spec.rupture_rules is not None
    extra = [path for path in hazard.branch_paths(outputs["nrml"], relations, system).values()
             if path != outputs["nrml"]]
    if system:
        extra += list(hazard.system_paths(outputs["nrml"], relations).values())
    if outputs["engine_job"] is not None:
        job = outputs["engine_job"]
        if len(relations) == 1 and not system:
            extra.append(job.with_name(f"{job.stem}_source_model_logic_tree.xml"))
        extra.append(job.with_name(f"{job.stem}_gmpe_logic_tree.xml"))
    for path in extra:
        checked = check_output(path, label="--nrml", suffixes=(".xml",), inputs=spec.inputs, overwrite=args.overwrite)
        claim(checked, "faultslip map", args.overwrite, "--nrml")
    options["extra"] = extra
    return options


def _renewal_options(args, spec, outputs) -> dict | None:
    """Check the time-dependent options and claim the branch files, before any work (None: not asked)."""
    given = [flag for flag, value in (("--last-ruptures", args.last_ruptures), ("--forecast-year", args.forecast_year))
             if value is not None]
    if outputs["time_dependent"] is None:
        if given:
            raise InputError(f"{given[0]} describes time-dependent sources: give --time-dependent FILE.xml too")
        return None
    if spec.segments is None:
        raise InputError("--time-dependent writes fault sources: it needs a segment map ([segments]), not a raster")
    if args.last_ruptures is None:
        raise InputError("--time-dependent needs each segment's last rupture: --last-ruptures 'SEGMENT=YEAR; ...'")
    model, aperiodicity = hazard.parse_renewal(args.renewal)
    last = hazard.parse_last_ruptures(args.last_ruptures)
    now = datetime.now(timezone.utc)
    forecast = (_number(args.forecast_year, "--forecast-year") if args.forecast_year is not None else
                now.year + (now.timetuple().tm_yday - 1) / 365.25)
    late = sorted(key for key, year in last.items() if year > forecast)
    if late:
        raise InputError(f"--last-ruptures: segment {late[0]} ruptured in {last[late[0]]:g}, after the forecast year "
                         f"{forecast:g}")
    window = to_si(args.investigation_time, "time", "--investigation-time")
    path = outputs["time_dependent"]
    extra = [path.with_name(f"{path.stem}_{name}{path.suffix}") for name in ("poisson", model)]
    job = outputs["engine_job"] if outputs["nrml"] is None else None  # with --nrml, the job runs those sources
    if outputs["nrml"] is None and (outputs["engine_job"] is None) != (args.sites is None):
        raise InputError("--engine-job and --sites go together: the job computes hazard at the sites")
    if job is not None:
        extra.append(job.with_name(f"{job.stem}_gmpe_logic_tree.xml"))
    for item in extra:
        claim(check_output(item, label="--time-dependent", suffixes=(".xml",), inputs=spec.inputs,
                           overwrite=args.overwrite), "faultslip map", args.overwrite, "--time-dependent")
    return {"model": model, "aperiodicity": aperiodicity, "last": last, "forecast_year": forecast,
            "investigation_time": window, "extra": extra, "job": job,
            "sites": hazard.parse_sites(args.sites) if job is not None else None}


def _displacement_options(args, spec, outputs) -> dict | None:
    """Check the displacement-hazard options and claim its figure, before any work (None: not asked)."""
    if args.displacement_hazard is None:
        for flag, value, default in (("--displacement-model", args.displacement_model, "faultslip"),
                                     ("--displacements", args.displacements, None)):
            if value != default:
                raise InputError(f"{flag} describes a displacement hazard: give --displacement-hazard 'LON LAT' too")
        return None
    if spec.segments is None:
        raise InputError("--displacement-hazard needs fault segments ([segments]), not a raster map")
    sites = hazard.parse_sites(args.displacement_hazard)
    if len(sites) != 1:
        raise InputError(f"--displacement-hazard takes one site, 'lon lat' in degrees, got {len(sites)}")
    if args.displacement_model not in displacement_hazard.MODELS:
        raise InputError(f"--displacement-model must be one of {', '.join(displacement_hazard.MODELS)}, "
                         f"got {args.displacement_model!r}")
    if args.displacement_model in displacement_hazard.FDHPY_MODELS and importlib.util.find_spec("fdhpy") is None:
        raise InputError(f"--displacement-model {args.displacement_model} comes from fdhpy, which is not installed: "
                         "pip install 'faultslip[fdh]'")
    displacements = None
    if args.displacements is not None:
        parts = [part for part in args.displacements.replace(";", ",").split(",") if part.strip()]
        displacements = sorted(to_si(part.strip(), "length", "--displacements") for part in parts)
        if not displacements or displacements[0] <= 0:
            raise InputError("--displacements must be positive lengths with units, e.g. '0.1 m, 1 m, 3 m'")
    figure = None
    if outputs["plot"] is not None:
        target = Path(outputs["plot"])
        figure = check_output(target.with_name(target.stem + "_displacement" + target.suffix),
                              label="--plot (displacement hazard)", inputs=spec.inputs + _written(outputs),
                              overwrite=args.overwrite)
    return {"site": sites[0], "model": args.displacement_model, "displacements": displacements, "figure": figure}


def _written(outputs) -> list:
    """The map's netCDF, where one is written (-o), for the checks that no other output overwrites it."""
    return [outputs["output"]] if outputs.get("output") is not None else []


def _system_relations(args, spec) -> tuple:
    """The branches whose rupture sets the command solves: each --scaling-relations one with --nrml; faultslip's
    for a displacement hazard or the traces figure alone; none without [rupture_set] rules."""
    if spec.rupture_rules is None or spec.segments is None:
        return ()
    if args.nrml is not None:
        return tuple(name for name, _ in hazard.parse_relations(args.scaling_relations))
    return ("faultslip",) if args.displacement_hazard is not None or args.plot is not None else ()


def cmd_map(args) -> int:
    if args.estimate:  # before any output is checked: what the map would need, its predictions' cycles included
        spec = read_map(args.map)
        return _emit_estimate(map_size_estimate(spec, args.output, _tolerance(args) or 1e-6,
                                                _system_relations(args, spec)), args.json)
    if not any(getattr(args, name, None) for name in ("output", "nrml", "plot", "time_dependent")):
        raise InputError("faultslip map writes its results: give -o OUT.nc, --nrml FILE.xml, --time-dependent "
                         "FILE.xml or --plot FILE.png (or several)")
    spec = read_map(args.map)
    outputs = _outputs(args, {"output": ("-o", (".nc",)), "plot": ("--plot", FIGURE_SUFFIXES),
                              "nrml": ("--nrml", (".xml",)), "engine_job": ("--engine-job", (".ini",)),
                              "time_dependent": ("--time-dependent", (".xml",))}, spec.inputs)
    options = _hazard_options(args, spec, outputs)
    renewal = _renewal_options(args, spec, outputs)
    displacement = _displacement_options(args, spec, outputs)
    observed = traces_figure = None
    if outputs["plot"] is not None and spec.segments is not None:
        target = Path(outputs["plot"])
        observed = check_output(target.with_name(target.stem + "_observed" + target.suffix), label="--plot (observed)",
                                inputs=spec.inputs + _written(outputs), overwrite=args.overwrite)
        traces_figure = check_output(target.with_name(target.stem + "_faults" + target.suffix),
                                     label="--plot (fault traces)", inputs=spec.inputs + _written(outputs),
                                     overwrite=args.overwrite)
    tolerance = _tolerance(args) or 1e-6
    check_map_size(spec, outputs["output"], args.allow_large, tolerance, _system_relations(args, spec))
    dataset = run_map(spec, method=args.method or "auto", tolerance=tolerance, allow_large=True)
    plots, sources, written, systems = [], [], None, {}
    if options is not None:  # built before anything is written: a refusal leaves nothing behind
        sources = hazard.hazard_sources(spec, dataset, args.stable_continental)
        models = hazard.source_models(sources, options["relations"], options["kind"], options["min_magnitude"],
                                      options["b_value"], options["bin_width"], options["moment_constant"],
                                      args.stable_continental)
        systems = hazard.system_models(spec, dataset, options["relations"], args.stable_continental,
                                       options["bin_width"], args.allow_large)
    site_hazard = None
    system = systems.get("faultslip") or next(iter(systems.values()), None)
    if system is None and spec.rupture_rules is not None and (displacement is not None or traces_figure is not None):
        system = rupture_sets.rupture_set(spec, dataset, spec.rupture_rules, "faultslip",
                                          allow_large=args.allow_large)
    if displacement is not None:  # also before anything is written: a site off every trace leaves nothing behind
        site_hazard = displacement_hazard.displacement_hazard(spec, dataset, displacement["site"],
                                                              displacement["model"], displacement["displacements"],
                                                              system)
        for name, variable in site_hazard.to_dataset().data_vars.items():
            dataset[f"displacement_hazard_{name}" if not name.startswith("annual") else f"displacement_{name}"] = variable
        spec.notes.extend(f"displacement hazard: {note}" for note in site_hazard.notes)
    renewal_sources = None
    if renewal is not None:  # also before anything is written
        sources = sources or hazard.hazard_sources(spec, dataset, args.stable_continental)
        renewal_sources = hazard.time_dependent_sources(
            sources, {key: (renewal["forecast_year"] - year) * JULIAN_YEAR for key, year in renewal["last"].items()},
            renewal["model"], renewal["aperiodicity"], renewal["investigation_time"])
    with _locked(outputs["output"], outputs["plot"], observed, traces_figure, outputs["nrml"], outputs["engine_job"],
                 outputs["time_dependent"], *(options["extra"] if options else []),
                 *([displacement["figure"]] if displacement and displacement["figure"] else []),
                 *(renewal["extra"] if renewal else [])):
        if outputs["output"] is not None:
            write_dataset(dataset, outputs["output"])
        if options is not None:
            written = hazard.write_hazard_model(outputs["nrml"], models, options["relations"], spec.name, systems,
                                                options["bin_width"], options["moment_constant"])
            branches = ", ".join(f"{name} {weight:g}" for name, weight in options["relations"])
            for result in systems.values():
                spec.notes.append(f"fault system, {result.notes[0]}; weight {result.rules.weight:g} against the "
                                  "per-segment sources in the logic tree")
            segment_counts = [count for key, count in written["sources"].items() if not key.endswith("_system")]
            spec.notes.append(f"{max(segment_counts, default=0)} simple-fault source(s), {args.mfd} MFD "
                              f"(b = {options['b_value']:g} from Mw {options['min_magnitude']:g}, bins of "
                              f"{options['bin_width']:g}), moment-balanced, per scaling relation ({branches}), "
                              f"written as NRML to {', '.join(written['files'])}")
            if outputs["engine_job"] is not None:
                job_files = hazard.write_engine_job(outputs["engine_job"], str(outputs["nrml"]),
                                                    len(options["relations"]) > 1 or bool(systems), options["sites"],
                                                    bin_width=options["bin_width"], description=spec.name,
                                                    infer_occur_rates=bool(systems),
                                                    # a multiFaultSource's rates are read from one-year
                                                    # probabilities, and the engine wants the job's time to match
                                                    investigation_time=1.0 if systems else 50.0)
                written["files"] += job_files
                spec.notes.append(f"OpenQuake classical job at {len(options['sites'])} site(s)"
                                  + (", over 1 yr (annual probabilities: the fault system's multiFaultSource gives "
                                     "its rates as one-year probabilities)" if systems else "")
                                  + f": oq engine --run {outputs['engine_job']}")
        if renewal_sources is not None:
            td = hazard.write_time_dependent_model(outputs["time_dependent"], renewal_sources, spec.name)
            if renewal["job"] is not None:  # the engine runs the time-dependent logic tree over its own window
                td["files"] += hazard.write_engine_job(renewal["job"], str(outputs["time_dependent"]), True,
                                                       renewal["sites"], description=f"{spec.name} (time-dependent)",
                                                       investigation_time=renewal["investigation_time"] / JULIAN_YEAR)
                spec.notes.append(f"OpenQuake classical job over the time-dependent sources at "
                                  f"{len(renewal['sites'])} site(s): oq engine --run {renewal['job']}")
            spec.notes.append(f"{len(renewal_sources)} time-dependent source(s), {renewal['model']} with aperiodicity "
                              f"{renewal['aperiodicity']:g} from {renewal['forecast_year']:g} over "
                              f"{renewal['investigation_time'] / JULIAN_YEAR:g} yr, beside their Poissonian twins, "
                              f"written as NRML to {', '.join(td['files'])}")
        if outputs["plot"]:
            save_figure(map_figure(dataset), outputs["plot"], dpi=150)
            plots.append(args.plot)
            if observed is not None and has_observations(dataset):
                save_figure(observed_figure(dataset), observed, dpi=150)
                plots.append(str(observed))
            elif observed is not None:
                spec.notes.append("no segment has an observed slip or recurrence: the observed figure is not drawn")
            if traces_figure is not None:
                participation = None if system is None else (
                    system.sections.traces, system.participation, f"the fault system's ruptures ({system.relation})")
                save_figure(fault_system_figure(dataset, participation), traces_figure, dpi=150)
                plots.append(str(traces_figure))
            if site_hazard is not None:
                save_figure(displacement_hazard_figure(site_hazard), displacement["figure"], dpi=150)
                plots.append(str(displacement["figure"]))
    if args.json:
        year = JULIAN_YEAR
        def value(number):
            return number if math.isfinite(number) else None

        rows = [{"segment": row["segment"], "slip_per_event": {"value": value(row["slip_per_event"]), "units": "m"},
                 "recurrence_period": {"value": value(row["recurrence_period"]), "units": "s"},
                 "moment_magnitude": value(row["moment_magnitude"]),
                 "observed_recurrence": {"value": value(row["observed_recurrence"]), "units": "s"},
                 "recurrence_ratio": value(row["recurrence_ratio"]), "slip_ratio": value(row["slip_ratio"])}
                for row in (segment_rows(dataset) if "segment" in dataset.dims else [])]
        hazard_json = None if written is None else {
            "files": written["files"], "mfd": args.mfd,
            "relations": [{"relation": name, "weight": weight} for name, weight in options["relations"]],
            "sources": hazard.sources_json(sources, models),
            "rupture_sets": {name: result.summary() | {"rules": result.rules.as_dict()}
                             for name, result in systems.items()} or None}
        if renewal_sources is not None:
            hazard_json = (hazard_json or {}) | {"time_dependent": [s.as_dict() for s in renewal_sources]}
        print(json.dumps({"output": args.output, "plots": plots, "segments": rows, "year": {"value": year, "units": "s"},
                          "hazard": hazard_json, "displacement_hazard": site_hazard.as_dict() if site_hazard else None,
                          "notes": spec.notes}, indent=2))
    else:
        print(f"faultslip map: {spec.name}")
        for note in spec.notes:
            print(f"  {note}")
        if "segment" in dataset.dims:
            print(observed_table(dataset, most=MOST_ROWS))
        if sources:
            print("\n" + hazard.magnitude_table(sources[:MOST_ROWS]))
        if site_hazard is not None:
            lon, lat = site_hazard.site
            print(f"\nfault-displacement hazard at {lon:g}, {lat:g} (on {site_hazard.fault}, {site_hazard.model}):")
            for wanted in (0.1, 1.0, 3.0, 10.0):
                if site_hazard.displacements[0] <= wanted <= site_hazard.displacements[-1]:
                    rate = float(np.exp(np.interp(math.log(wanted), np.log(site_hazard.displacements),
                                                  np.log(np.maximum(site_hazard.rate, 1e-300)))))
                    print(f"  D > {wanted:g} m: {rate:.3g} /yr" + (f" (return period {1 / rate:.3g} yr)"
                                                                     if rate > 1e-300 else ""))
        print("\nwrote " + ", ".join(([args.output] if args.output else []) + plots
                                     + (written["files"] if written else [])))
    return 0
