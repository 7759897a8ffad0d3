"""The ``faultslip`` command line: the parser, and dispatch to one module per command group.

Thin: it parses, calls the library, prints. Each command's handler lives in its group's module
(:mod:`faultslip.cli.scenes`, ``studies``, ``lab``, ``evaluation``, ``plots``) and is named
here as ``"module:function"``. The module is imported when its command runs, so ``--help`` and
a parse error never load numpy, pint or the physics. Every command that computes has ``--json``.
Bad input exits with status 2 and one sentence on stderr, never a traceback.
"""

from __future__ import annotations

import argparse
import difflib
import re
import importlib
import os
import signal
import sys
import warnings

from faultslip import __version__
from faultslip.contract.options import COMMON, DEPRECATED, options_of
from faultslip.errors import FaultslipError
from faultslip.io.atomic import transaction


class _Parser(argparse.ArgumentParser):
    """argparse with a one-line error and exit status 2."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {did_you_mean(message, _option_strings(self))} (see '{self.prog} --help')\n")


def _option_strings(parser: argparse.ArgumentParser) -> list[str]:
    """Every option string of ``parser`` and of its subcommands, at any depth."""
    found = []
    for action in parser._actions:
        found.extend(action.option_strings)
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                found.extend(_option_strings(sub))
    return sorted(set(found))


def did_you_mean(message: str, options=()) -> str:
    """argparse's message for a mistyped command or option, with the nearest valid spelling where one is close
    ("invalid choice: 'swep' (choose from ...)" becomes "... did you mean 'sweep'?"); other messages unchanged."""
    choice = re.match(r"argument (.+?): invalid choice: '([^']*)' \(choose from (.*)\)$", message)
    if choice:
        name, given, listed = choice.groups()
        valid = re.findall(r"'([^']*)'", listed)
        near = difflib.get_close_matches(given, valid, n=1, cutoff=0.6)
        hint = f"; did you mean '{near[0]}'?" if near else f"; choose from {', '.join(valid)}"
        return f"argument {name}: invalid choice '{given}'{hint}"
    unknown = re.match(r"unrecognized arguments: (.*)$", message)
    if unknown:
        hints = []
        for word in unknown.group(1).split():
            near = difflib.get_close_matches(word.split("=")[0], options, n=1, cutoff=0.7) if word.startswith("--") else []
            if near:
                hints.append(f"did you mean '{near[0]}' for '{word}'?")
        return message + ("; " + " ".join(hints) if hints else "")
    return message


class _RoutedTo(argparse.Action):
    """An option that, given, routes the command to another handler: one that needs more of the library
    (``rate-state cycles --seed-law`` needs the seed law's fault scaling, which the lean cycle run does not load)."""

    def __init__(self, *args, handler: str, **kwargs):
        super().__init__(*args, **kwargs)
        self.handler = handler

    def __call__(self, parser, namespace, values, option_string=None):
        setattr(namespace, self.dest, values)
        namespace.handler = self.handler


class _Deprecated(argparse.Action):
    """An old spelling kept for one release: it stores its value where the new one does, and says to use the new."""

    def __init__(self, *args, now: str, **kwargs):
        super().__init__(*args, **kwargs)
        self.now = now

    def __call__(self, parser, namespace, values, option_string=None):
        setattr(namespace, self.dest, values)
        print(f"{parser.prog}: note: {option_string} is deprecated here and goes in the next release; use {self.now}",
              file=sys.stderr)


def _output_dir_option(parser, command: str, default: str, help_text: str) -> None:
    """``--output-dir`` (a folder), and its old spelling ``-o`` for one release (:data:`DEPRECATED`)."""
    parser.add_argument("--output-dir", dest="output", default=default, help=help_text)
    parser.add_argument("-o", "--output", dest="output", action=_Deprecated, now=DEPRECATED[(command, "-o")],
                        help=argparse.SUPPRESS)


def _overwrite_and_json(parser) -> None:
    """The two flags of every command that writes files and prints a report."""
    parser.add_argument("--overwrite", action="store_true", help=COMMON["--overwrite"])
    parser.add_argument("--json", action="store_true", help=COMMON["--json"])


def _family_options(parser, command: str) -> None:
    """run's and simulate's flags, from the options the families declare (faultslip.contract.options)."""
    for option in options_of(command):
        names = (option.short, option.flag) if option.short else (option.flag,)
        if option.kind == "switch":
            parser.add_argument(*names, action="store_true", help=option.help)
        else:
            parser.add_argument(*names, type=int if option.kind == "count" else None, help=option.help)


def _method_flags(parser):
    parser.add_argument("--method", "--model", dest="method", help="solution method, or a fault scene's rung (one_slider, fault_2d, and "
                        "fault_3d on a 3-D scene): see 'faultslip methods' (default: auto, the cheapest method whose "
                        "error model meets the tolerance)")
    parser.add_argument("--tolerance", help="relative error the answer must meet (0.1, 1e-3 or 10 %%; default "
                        "1e-6); on a rate-and-state "
                        "fault scene the model error too: where one slider cannot meet it, the run moves up to the "
                        "2-D fault of the same scene (estimated and budgeted first) and reports both rungs; on a 3-D "
                        "scene up to the 3-D fault")


class _Unbuilt:
    """A command that is not being run: its help line is in the parser, its options are never built."""

    def __getattr__(self, name):
        return lambda *args, **kwargs: self


class _Commands:
    """The subcommands, building in full only the one being run (``only``; all when None).

    Building every command's options took 38 ms of a 100-cycle run's 260 ms whole process."""

    def __init__(self, commands, only):
        self.commands, self.only = commands, only

    def add_parser(self, name, **kwargs):
        parser = self.commands.add_parser(name, **kwargs)
        return parser if self.only is None or name == self.only else _Unbuilt()


def build_parser(argv=None) -> argparse.ArgumentParser:
    """The command line's parser, every command built; given ``argv``, only the command it names is."""
    parser = _Parser(prog="faultslip", description="Laboratory rock friction to earthquake slip and recurrence.")
    parser.add_argument("--version", action="version", version=f"faultslip {__version__}")
    words = [word for word in (argv or [])[:1] if not word.startswith("-")]
    commands = _Commands(parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser),
                         None if argv is None else words[0] if words else "")
    _scenes_commands(commands)
    _studies_commands(commands)
    _lab_commands(commands)
    _rate_state_commands(commands)
    _vibration_commands(commands)
    _evaluation_commands(commands)
    _seismology_commands(commands)
    _surface_commands(commands)
    _plots_commands(commands)
    classroom = commands.add_parser("classroom", help="an interactive stick-slip lab in the browser (served locally)")
    classroom.add_argument("--port", type=int, default=5006, help="the local port (default 5006)")
    classroom.add_argument("--address", default="127.0.0.1", help="the address to serve on (default 127.0.0.1: "
                                                                  "this machine only)")
    classroom.add_argument("--open", action="store_true", help="open the app in the default browser")
    classroom.add_argument("--export", help="write the lesson as one self-contained HTML file (FILE.html) that opens "
                           "offline without Python, and serve nothing")
    classroom.add_argument("--overwrite", action="store_true", help=COMMON["--overwrite"])
    classroom.set_defaults(handler="apps:cmd_classroom")
    return parser


def _surface_commands(commands) -> None:
    """Rough surfaces (handlers in faultslip.cli.surfaces)."""
    surface = commands.add_parser("surface", help="rough-surface statistics and contact by truncation (seed 000)")
    surface.add_argument("surface", nargs="?", help="profile or map: CSV (x, z or x, y, z with units) or netCDF (height)")
    surface.add_argument("--synthetic", nargs=2, metavar=("RMS", "LENGTH"),
                         help="a Gaussian surface instead: RMS and correlation length, e.g. '2 um' '20 um'")
    surface.add_argument("--size", type=int, default=256, help="synthetic points a side (default 256)")
    surface.add_argument("--profile", action="store_true", help="a synthetic profile rather than a map")
    surface.add_argument("--seed", type=int, default=0, help="random seed of the synthetic surface")
    surface.add_argument("--modulus", help="Young's modulus E, e.g. '210 GPa' (for the plasticity index)")
    surface.add_argument("--poisson", default="0.3", help="Poisson's ratio (default 0.3)")
    surface.add_argument("--hardness", help="hardness H, e.g. '208 kgf/mm^2'")
    surface.add_argument("--flow-pressure", help="plastic flow pressure p_c for the contact, e.g. '280 N/mm^2'")
    surface.add_argument("--load", help="load L: the approach where p_c A = L (needs --flow-pressure)")
    surface.add_argument("--against", default="inverted", help="counter-surface: inverted (its own inverted copy, "
                                                               "as seed 000) or flat")
    surface.add_argument("--plot", help="draw the surface, autocorrelation, height density and contact to FILE.png")
    _overwrite_and_json(surface)
    surface.set_defaults(handler="surfaces:cmd_surface", example_inputs={"surface": "surface file"})


def _seismology_commands(commands) -> None:
    """Catalogs and seismology's formats (handlers in faultslip.cli.seismology)."""
    catalog = commands.add_parser("catalog", help="observed recurrence and magnitude of a fault's events beside the "
                                                  "prediction (QuakeML or CSV catalog)")
    catalog.add_argument("catalog", help="catalog: QuakeML (.xml, .quakeml, .qml) or CSV")
    catalog.add_argument("--fault", required=True, help="fault scene (its [fault] trace selects the events)")
    catalog.add_argument("--trace", help="fault trace 'lon lat; lon lat; ...' in degrees (default: the scene's)")
    catalog.add_argument("--max-distance", default="25 km", help="events within this distance of the trace (25 km)")
    catalog.add_argument("--min-magnitude", help="smallest magnitude kept")
    catalog.add_argument("--max-magnitude", help="largest magnitude kept (e.g. to leave out a great earthquake)")
    catalog.add_argument("--since", help="first time kept, ISO 8601 (e.g. 1850-01-01)")
    catalog.add_argument("--until", help="last time kept, ISO 8601")
    catalog.add_argument("--as-of", help="date of the conditional probability (default: now)")
    catalog.add_argument("--horizon", default="30 yr", help="probability horizon (30 yr)")
    catalog.add_argument("--bootstrap", type=int, default=1000, help="draws of the generalized pivotal quantities behind the 95 %% ranges (1000)")
    catalog.add_argument("--seed", type=int, default=0, help="random seed of the bootstrap")
    catalog.add_argument("--cluster-fraction", default="0.01",
                         help="intervals under this fraction of the mean are fore/aftershocks and are declustered "
                              "(0.01); 'refuse' stops instead")
    catalog.add_argument("--plot", help="draw the events and the recurrence to FILE.png")
    _overwrite_and_json(catalog)
    catalog.set_defaults(handler="seismology:cmd_catalog", example_inputs={"catalog": "catalog"})


def _scenes_commands(commands) -> None:
    """Scene and fault commands (handlers in faultslip.cli.scenes)."""
    run = commands.add_parser("run", help="run a scene (default: the 1906 San Francisco scene)")
    run.add_argument("scene", nargs="?", help="scene TOML file or bundled scene name")
    _method_flags(run)
    _family_options(run, "run")
    run.add_argument("--json", action="store_true", help=COMMON["--json"])
    run.set_defaults(handler="scenes:cmd_run")

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
    fault.add_argument("--dip", help="dip in degrees (default 90): the moment takes the down-dip width H / sin(dip)")
    fault.add_argument("--rake", help="rake in degrees (default 180, dextral): the slip type of the empirical relations")
    fault.add_argument("--damping-ratio", help="damping ratio zeta of the slip phase (default 0)")
    fault.add_argument("--radiation-damping", action="store_true", help="add the radiation damper G/(2 c_s)")
    fault.add_argument("--density", help="rock density for M = rho D (default 2700 kg/m^3)")
    fault.add_argument("--shear-wave-speed", help="c_s for radiation damping (default 3.3 km/s)")
    fault.add_argument("--observed-slip", help="inverse: report the mu_m that reproduces this slip, e.g. '21 ft'")
    fault.add_argument("--seed-law", help="with a rate-and-state fit as --lithology: the seed-law lithology or preset "
                                          "estimated beside it on the same fault (default granodiorite)")
    fault.add_argument("--name", default="fault", help="a name for the report")
    _method_flags(fault)
    fault.add_argument("--json", action="store_true", help=COMMON["--json"])
    fault.set_defaults(handler="scenes:cmd_fault")

    materials = commands.add_parser("materials", help="list presets and lithologies with their sources")
    materials.add_argument("--json", action="store_true", help=COMMON["--json"])
    materials.set_defaults(handler="scenes:cmd_materials")

    methods = commands.add_parser("methods", help="the solution methods: friction laws, domain and cost of each, "
                                                  "and how each is run")
    methods.add_argument("scene", nargs="?", help="a scene: only the methods its family runs (default: every family's)")
    methods.add_argument("--json", action="store_true", help=COMMON["--json"])
    methods.set_defaults(handler="scenes:cmd_methods")

    simulate = commands.add_parser("simulate", help="event-driven simulation of stick-slip cycles of a scene")
    simulate.add_argument("scene", help="scene TOML file or bundled scene name")
    _family_options(simulate, "simulate")
    simulate.add_argument("--json", action="store_true", help=COMMON["--json"])
    simulate.set_defaults(handler="scenes:cmd_simulate")

    critical = commands.add_parser("critical", help="critical loading rate: exact and seed Appendix I")
    critical.add_argument("scene", nargs="?", help="scene file (alternative to --preset)")
    critical.add_argument("--preset", help="Table I preset on its apparatus")
    critical.add_argument("--damping-ratio", help="damping ratio zeta of the dashpot")
    critical.add_argument("--table", action="store_true", help="write the exact-vs-seed comparison (nc, md, png)")
    _output_dir_option(critical, "critical", ".", "the folder for --table's files (default: the current one)")
    _overwrite_and_json(critical)
    critical.set_defaults(handler="scenes:cmd_critical")

    cycle = commands.add_parser("cycle", help="exact stick-slip cycle of a scene at a loading rate")
    cycle.add_argument("scene", help="scene TOML file or bundled scene name")
    cycle.add_argument("--loading-rate", help="theta_dot, e.g. '0.1 1/s'")
    cycle.add_argument("--platform-speed", help="V, e.g. '1e-4 in/s'")
    _method_flags(cycle)
    cycle.add_argument("--json", action="store_true", help=COMMON["--json"])
    cycle.set_defaults(handler="scenes:cmd_cycle")


def _studies_commands(commands) -> None:
    """Study and map commands (handlers in faultslip.cli.sweeps and faultslip.cli.studies)."""
    sweep = commands.add_parser("sweep", help="gridded parameter study to CF netCDF (or a Zarr store)")
    sweep.add_argument("study", help="study TOML file")
    sweep.add_argument("-o", "--output", required=True,
                       help="output netCDF file, or Zarr store (OUT.zarr); written atomically")
    sweep.add_argument("--format", choices=("netcdf", "zarr"),
                       help="output format (default: from the suffix, .nc or .zarr); with --scheduler ADDRESS, "
                            "zarr lets every worker write its own chunks")
    sweep.add_argument("--allow-large", action="store_true", help=COMMON["--allow-large"])
    sweep.add_argument("--overwrite", action="store_true", help=COMMON["--overwrite"])
    sweep.add_argument("--scheduler", help="'local' for a dask LocalCluster, 'slurm' for --workers SLURM jobs through "
                                           "dask-jobqueue (resources from dask's jobqueue.slurm configuration), or "
                                           "the address of a dask scheduler")
    sweep.add_argument("--chunks", type=int, help="cells per chunk (default 524288)")
    sweep.add_argument("--workers", type=int, help="parallel workers (default: the cores, at most one per chunk)")
    sweep.add_argument("--resume", action="store_true", help="reuse the chunks of an interrupted run of the same study")
    sweep.add_argument("--retry-failed", action="store_true",
                       help="compute again only the cells the output's failure ledger (OUT.failed.json) lists, and "
                            "write them into the output")
    sweep.add_argument("--compression", choices=("zlib", "zstd", "none"), default="zlib",
                       help="netCDF4 filter (default zlib, readable everywhere; zstd writes ~2.5x faster)")
    sweep.add_argument("--estimate", action="store_true",
                       help="print what the sweep would need (time on its workers, memory, disk), each cell's cost "
                            "from its family's cost model, and stop")
    sweep.add_argument("--json", action="store_true", help=COMMON["--json"])
    sweep.set_defaults(handler="sweeps:cmd_sweep")

    convert = commands.add_parser("convert", help="convert a Zarr store written by sweep into one netCDF file")
    convert.add_argument("store", help="a Zarr store (folder), e.g. written by faultslip sweep -o OUT.zarr")
    convert.add_argument("-o", "--output", required=True, help="output netCDF file (written atomically)")
    convert.add_argument("--workers", type=int, help="processes that compress chunks (default: the cores)")
    convert.add_argument("--overwrite", action="store_true", help=COMMON["--overwrite"])
    convert.add_argument("--allow-large", action="store_true", help=COMMON["--allow-large"])
    convert.add_argument("--json", action="store_true", help=COMMON["--json"])
    convert.set_defaults(handler="sweeps:cmd_convert", example_inputs={"store": "Zarr store"})

    reproduce = commands.add_parser("reproduce", help="re-run the study embedded in a sweep's netCDF and compare")
    reproduce.add_argument("file", help="a netCDF written by faultslip sweep")
    reproduce.add_argument("-o", "--output", help="keep the reproduced file here")
    reproduce.add_argument("--overwrite", action="store_true", help=COMMON["--overwrite"])
    reproduce.add_argument("--allow-large", action="store_true", help=COMMON["--allow-large"])
    reproduce.add_argument("--workers", type=int, help="parallel workers (default: the cores, at most one per chunk)")
    reproduce.add_argument("--cells", type=int, help="a spot check: run again only this many cells, drawn at random, "
                                                     "and compare them (the rest by the file's checksum)")
    reproduce.add_argument("--seed", type=int, help="the draw of --cells (default: a new one, named in the output)")
    reproduce.add_argument("--scheduler", help="'local' for a dask LocalCluster, 'slurm' for --workers SLURM jobs "
                                               "through dask-jobqueue, or the address of a dask scheduler: where the "
                                               "cells run again")
    reproduce.add_argument("--json", action="store_true", help=COMMON["--json"])
    reproduce.set_defaults(handler="sweeps:cmd_reproduce")

    regional = commands.add_parser("map", help="regional map from a fault-segment table or a raster")
    regional.add_argument("map", help="map TOML file")
    regional.add_argument("-o", "--output", help="output netCDF file (a map may write --nrml, --time-dependent or "
                          "--plot alone)")
    regional.add_argument("--plot", help="draw the maps to FILE.png (and predicted vs observed to FILE_observed.png)")
    regional.add_argument("--nrml", help="write each segment as an OpenQuake simple-fault source (NRML 0.5) to FILE.xml; "
                          "a map with a [rupture_set] table adds its fault system's multi-fault ruptures as "
                          "logic-tree branches (docs/hazard.md)")
    regional.add_argument("--mfd", default="characteristic", help="NRML magnitude-frequency distribution, balanced "
                          "on the segment's moment rate: characteristic (Youngs & Coppersmith 1985), truncated_gr or "
                          "single_bin (default characteristic)")
    regional.add_argument("--b-value", default="1.0", help="Gutenberg-Richter b-value of the MFD (default 1.0)")
    regional.add_argument("--min-magnitude", default="5.0", help="lowest magnitude of the MFD (default 5.0)")
    regional.add_argument("--mfd-bin-width", default="0.1", help="magnitude bin width of the MFD (default 0.1)")
    regional.add_argument("--moment-constant", default="9.1", help="c of M0 = 10^(1.5 Mw + c) in the moment balance: "
                          "9.1, faultslip's Mw (default), or 9.05, the engine's MFD code")
    regional.add_argument("--scaling-relations", help="a logic-tree branch per relation, e.g. "
                          "'faultslip,WC1994,Leonard2010' or 'faultslip:0.5,WC1994:0.25,Leonard2010:0.25': each "
                          "branch's characteristic Mw from that relation, the same moment rate (default faultslip)")
    regional.add_argument("--stable-continental", action="store_true",
                          help="Leonard (2010) branch and comparison for a stable continental region")
    regional.add_argument("--time-dependent", help="write each segment's rupture as a time-dependent source: a "
                          "logic tree FILE.xml over a renewal branch and a Poissonian one (non-parametric NRML)")
    regional.add_argument("--renewal", default="bpt:0.5", help="the renewal model and its aperiodicity for "
                          "--time-dependent: bpt:A or lognormal:A (default bpt:0.5)")
    regional.add_argument("--last-ruptures", help="each segment's last rupture for --time-dependent, as decimal "
                          "years: 'SA-PKF=2004.74; SA-CAR=1857.02'")
    regional.add_argument("--forecast-year", help="the decimal year the investigation time starts (default: now)")
    regional.add_argument("--investigation-time", default="50 yr", help="the window of --time-dependent (default "
                          "50 yr; an engine job uses it too)")
    regional.add_argument("--engine-job", help="also write an OpenQuake classical job (FILE.ini) over the sources")
    regional.add_argument("--sites", help="the job's sites: 'lon lat; lon lat' in degrees")
    regional.add_argument("--displacement-hazard", metavar="SITE", help="the annual rate of exceeding each "
                          "displacement at a site on a fault trace, 'lon lat' in degrees (principal displacement: "
                          "Petersen et al. 2011's profile; with --plot also FILE_displacement.png)")
    regional.add_argument("--displacement-model", default="faultslip", help="faultslip (its slip per event as the "
                          "rupture's average displacement, default), petersen_2011 (the level from Mw), one of "
                          "fdhpy's for the fault's style of faulting (youngs_2003, moss_ross_2011, "
                          "lavrentiadis_abrahamson_2023, moss_2024, kuehn_2024, chiou_2025; pip install "
                          "'faultslip[fdh]'), or logic_tree (every model that applies, equally weighted)")
    regional.add_argument("--displacements", help="the displacements of the curve, e.g. '0.1 m, 1 m, 3 m, 10 ft' "
                          "(default 41 from 1 cm to 30 m)")
    regional.add_argument("--overwrite", action="store_true", help=COMMON["--overwrite"])
    regional.add_argument("--allow-large", action="store_true", help=COMMON["--allow-large"])
    _method_flags(regional)
    regional.add_argument("--estimate", action="store_true",
                          help="print what the map would need (CPU time, memory, disk), a rate-and-state map's cycles "
                               "in every segment or cell included, and stop")
    regional.add_argument("--json", action="store_true", help=COMMON["--json"])
    regional.set_defaults(handler="studies:cmd_map")


def _lab_commands(commands) -> None:
    """Laboratory commands (handlers in faultslip.cli.lab)."""
    reduce = commands.add_parser("reduce", help="run an xlook r-file on its biax data file: the reduced columns "
                                                "(stresses, displacements, friction) to CF netCDF")
    reduce.add_argument("r_file", help="the r-file (its 'read' command names a data file beside it), e.g. "
                                       "data/p655/p655_r")
    reduce.add_argument("-o", "--output", help="write the reduced columns to OUT.nc")
    reduce.add_argument("--overwrite", action="store_true", help=COMMON["--overwrite"])
    reduce.add_argument("--json", action="store_true", help=COMMON["--json"])
    reduce.set_defaults(handler="lab:cmd_reduce", example_inputs={"r_file": "r-file"})
    fit = commands.add_parser("fit", help="fit the rate law (eq. 2-18) to laboratory data, with uncertainty")
    fit.add_argument("data", nargs="?", help="CSV or netCDF: loading_rate (or platform_speed, stiffness, normal_load), "
                     "static_friction[, amplitude]")
    fit.add_argument("--bundle", help="also write FIT.zip: the record, every option, the versions, the draws and the "
                     "report, readable without faultslip (JSON and netCDF inside)")
    fit.add_argument("--replay", help="run a bundle's fit again (FIT.zip) and say which numbers moved, and by how "
                     "much: none on the same versions")
    fit.add_argument("--name", help="save the fit under this name in the user registry")
    fit.add_argument("--shear-modulus", help="shear modulus of the rock, stored with the fit for fault predictions")
    fit.add_argument("--note", help="a note stored with the fit (e.g. rock and condition)")
    fit.add_argument("--plot", help="draw data, fit and 95 %% band (rate-state: the posterior's bands) to FILE.png")
    fit.add_argument("--overwrite", action="store_true", help=COMMON["--overwrite"])
    fit.add_argument("--loss", default="linear", help="least-squares loss: linear, soft_l1, huber or cauchy (robust)")
    fit.add_argument("--bootstrap", type=int, help="bootstrap samples (default 200; 50 for --law rate-state, where "
                                                    "each is a refit)")
    fit.add_argument("--seed", type=int, default=0, help="bootstrap seed (default 0): results are reproducible")
    fit.add_argument("--mu-m", help="fix the kinetic friction instead of fitting it")
    fit.add_argument("--law", choices=("rate-law", "rate-state"), default="rate-law",
                     help="rate-law: the seed's eq. 2-18 (default); rate-state: a, b and D_c from a velocity-step "
                          "record (time, friction, load_point_speed or load_point_displacement)")
    fit.add_argument("--stiffness", help="rate-state: the machine stiffness as friction per slip ('1e-2 1/um'), "
                                          "stress per slip ('50 MPa/mm') or force per slip ('200 kN/mm', with --area)")
    fit.add_argument("--joint", action="append", help="rate-state: a further record of the same rock (repeat): one "
                     "law fitted to all, a, b and D_c shared, each record's mu0 (and k) its own")
    fit.add_argument("--select-law", action="store_true", help="rate-state: also fit the aging, slip and two-state "
                     "aging laws and say which the record supports (BIC, Kass & Raftery's scale)")
    fit.add_argument("--stiffness-free", action="store_true", help="rate-state: fit the machine stiffness too, "
                     "started at --stiffness (a posterior's prior: log-normal about it, a factor of 2 as one sd; "
                     "--prior stiffness=... replaces it)")
    fit.add_argument("--area", help="rate-state, raw record: the sample's contact area, turning loads into stresses")
    fit.add_argument("--units", help="rate-state, raw record: units the file does not give, 'time=ms,shear_load=kN'")
    fit.add_argument("--detrend", default="none", choices=("none", "linear", "quadratic", "fitted"),
                     help="rate-state: remove a trend in slip from a raw record's friction (linear, quadratic; stated "
                          "in the report), or fit a linear trend in the load point's displacement with the law "
                          "(fitted: each fit its own, its uncertainty carried)")
    fit.add_argument("--columns", help="rate-state: the record's columns by faultslip's names, 'time=Time, "
                                       "load_point_displacement=LP_disp, shear_stress=Shear_stress, "
                                       "normal_stress=Nor_stress' (an xlook reduction's netCDF)")
    fit.add_argument("--span", help="rate-state: fit only the rows in this span of the file's time, "
                                    "'2400 s - 3150 s'")
    fit.add_argument("--steps", help="rate-state, raw record: the step times instead of detecting them, '100 s, 130 s'")
    fit.add_argument("--min-change", default="0.3", help="rate-state, raw record: the smallest relative change of the "
                                                          "load point's speed detected as a step (default 0.3)")
    fit.add_argument("--each-step", action="store_true", help="rate-state, raw record: also fit each step on its own")
    fit.add_argument("--windows", help="rate-state, raw record: each step's fit window instead of the automatic "
                                       "ones, '50 s - 130 s, 115 s - 230 s' (implies --each-step)")
    fit.add_argument("--posterior", action="store_true", help="rate-state: sample the Bayesian posterior (emcee) "
                                                               "until it has converged")
    fit.add_argument("--samples", type=int, default=10_000, help="posterior draws after burn-in (default 10000)")
    fit.add_argument("--walkers", type=int, help="posterior: emcee walkers (default 4 per parameter, at least 16)")
    fit.add_argument("--max-steps", type=int, default=20_000, help="posterior: refuse if not converged within these "
                                                                   "steps (default 20000)")
    fit.add_argument("--prior", action="append", help="posterior prior, SI: 'a=uniform:0:0.05', "
                                                      "'critical_slip=loguniform:1e-7:1e-3', 'b=normal:0.012:0.002' "
                                                      "(repeat)")
    fit.add_argument("--corner", help="posterior: draw the corner plot to FILE.png")
    fit.add_argument("--workers", type=int, help="posterior: likelihood worker processes (default 1)")
    fit.add_argument("--evolution", choices=("aging", "slip"), default="aging", help="rate-state: the state evolution law")
    fit.add_argument("--two-state", action="store_true", help="rate-state: fit b2 and D_c2 as well")
    fit.add_argument("--json", action="store_true", help=COMMON["--json"])
    fit.set_defaults(handler="lab:cmd_fit", example_inputs={"data": "data file", "joint": "record"})

    record = commands.add_parser("record", help="friction and stick-slip events from a measured motion record, or a "
                                                "phone's accelerometer (phyphox) in the classroom experiment")
    record.add_argument("record", help="CSV or netCDF (time, displacement, and acceleration or force), or miniSEED "
                                         "or SAC (channels by component code: D, A, N, V; docs/catalogs.md)")
    record.add_argument("--stiffness", help="spring stiffness K, e.g. '1.94e4 lbf/in' (motion records)")
    record.add_argument("--normal-load", help="normal load W, e.g. '225.8 lbf' (motion records)")
    record.add_argument("--axis", help="pulling axis of an accelerometer record (x, y or z; default: the largest "
                                       "spread)")
    record.add_argument("--mass", help="moving mass M (default W/g)")
    record.add_argument("--dashpot", help="dashpot C, e.g. '0 N*s/m' (default 0, as seed 003 eq. 3-2)")
    record.add_argument("--platform-speed", help="platform speed V (default: the median slider speed)")
    record.add_argument("--velocity", default="auto", help="auto, differentiate (x) or integrate (x'')")
    record.add_argument("--plot", help="draw mu against sliding speed to FILE.png")
    _overwrite_and_json(record)
    record.set_defaults(handler="lab:cmd_record", example_inputs={"record": "record"})

    decay = commands.add_parser("decay", help="system identification from free decay (seed 002 Appendix C)")
    decay.add_argument("record", nargs="?", help="a free-decay displacement record (alternative to --ratio ...)")
    decay.add_argument("--stiffness", required=True, help="known stiffness, e.g. '70.5 lbf/in'")
    decay.add_argument("--ratio", help="amplitude ratio X_n / X_{n+N}, e.g. 1.225")
    decay.add_argument("--cycles-between", dest="cycles", help="N, the cycles between the two amplitudes, e.g. 10")
    decay.add_argument("--cycles", dest="cycles", action=_Deprecated, now="--cycles-between", help=argparse.SUPPRESS)
    decay.add_argument("--frequency", help="damped frequency, e.g. '19.9 Hz'")
    decay.add_argument("--json", action="store_true", help=COMMON["--json"])
    decay.set_defaults(handler="lab:cmd_decay", example_inputs={"record": "record"})


def _vibration_commands(commands) -> None:
    """Quasi-harmonic vibration (handler in faultslip.cli.lab)."""
    vibration = commands.add_parser("quasi-harmonic", help="friction-induced vibration without sticking "
                                                           "(seed 002, averaging)")
    vibration.add_argument("scene", help="vibration scene TOML (e.g. configs/vibration_seed002.toml)")
    vibration.add_argument("--speed", help="driving speed, overriding the scene's, e.g. '12.5 in/s'")
    vibration.add_argument("--speeds", nargs=3, metavar=("START", "STOP", "COUNT"),
                           help="amplitude against driving speed, e.g. '1 in/s' '16 in/s' 61")
    vibration.add_argument("--plot", help="draw the friction curve and the amplitude against speed (needs --speeds)")
    vibration.add_argument("--dampings", nargs=3, metavar=("START", "STOP", "COUNT"),
                           help="damping coefficients for --regions, e.g. '0 lbf*s/in' '0.02 lbf*s/in' 41")
    vibration.add_argument("--regions", help="draw the (v, r) plane of regimes (needs --speeds and --dampings)")
    vibration.add_argument("--method", default="auto", help="auto (averaging where its error meets the tolerance), "
                                                              "quasi_harmonic_averaging or quasi_harmonic_integration "
                                                              "(averaging or integration for short)")
    vibration.add_argument("--tolerance", help="relative error asked of the amplitude (default 1e-3)")
    vibration.add_argument("--error-chart", help="draw averaging's error against integration over eps, measured "
                                                 "on Rayleigh's curve and on the scene itself (~5 s)")
    vibration.add_argument("--hand-over-chart", help="draw where averaging hands over to stick-slip, against "
                                                     "event-driven simulation (~70 s)")
    _overwrite_and_json(vibration)
    vibration.set_defaults(handler="lab:cmd_quasi_harmonic")
    nano = commands.add_parser("nanoscale", help="nanoscale stick-slip with contact charging (seed 001's toy model)")
    nano.add_argument("scene", help="nanoscale scene TOML (e.g. configs/nanoscale_seed001.toml)")
    nano.add_argument("--damping", help="the damping A, overriding the scene's (stick-slip below A_c)")
    nano.add_argument("--no-run", action="store_true", help="the threshold analysis only, no simulation")
    nano.add_argument("--allow-large", action="store_true", help=COMMON["--allow-large"])
    nano.add_argument("-o", "--output", help="write the time series to this netCDF file")
    nano.add_argument("--plot", help="draw force against displacement and the charge (seed 001 Fig. 3)")
    _overwrite_and_json(nano)
    nano.set_defaults(handler="lab:cmd_nanoscale")
    asperity = commands.add_parser("asperity", help="asperity friction (seed 004): m_D and stick against platform speed")
    asperity.add_argument("scene", help="asperity scene TOML (e.g. configs/asperity_seed004.toml)")
    asperity.add_argument("--from", dest="low", default="0.8 mm/s", help="lowest platform speed (default 0.8 mm/s)")
    asperity.add_argument("--to", dest="high", default="5 mm/s", help="highest platform speed (default 5 mm/s)")
    asperity.add_argument("--points", type=int, default=43, help="speeds in the sweep (default 43)")
    asperity.add_argument("--dashpot", help="the tangential damping C, overriding the scene's (200 kg/s: the paper's "
                                            "averages)")
    asperity.add_argument("--method", default="asperity_quasistatic",
                          help="asperity_quasistatic (default) or asperity_LSODA (the six states, ~20x slower)")
    asperity.add_argument("--tolerance", help="converge each speed: rerun at tighter rtols until its statistics change by "
                          "less than this (e.g. 0.01; about 3-5x the cost). Default: each speed runs once, untested")
    asperity.add_argument("-o", "--output", help="write the sweep to this netCDF file")
    asperity.add_argument("--plot", help="draw m_D and the stick fraction against speed (Figs. 6-7)")
    asperity.add_argument("--map", help="also draw where each integrator works, over speed (1 mm/s-0.7 m/s) and "
                                        "slope spread (0.1-0.3), contact loss marked (~30 s)")
    _overwrite_and_json(asperity)
    asperity.set_defaults(handler="lab:cmd_asperity")


def _rate_state_commands(commands) -> None:
    """Rate-and-state commands (handlers in faultslip.cli.rate_state)."""
    group = commands.add_parser("rate-state", help="rate-and-state friction: simulate, stability, fault cycles")
    actions = group.add_subparsers(dest="action", metavar="ACTION", parser_class=_Parser)
    simulate = actions.add_parser("simulate", help="a slider under a load history (velocity steps, slide-hold-slide)")
    simulate.add_argument("scene", help="rate-and-state scene TOML (e.g. configs/rsf_velocity_step.toml)")
    simulate.add_argument("--method", default="auto", help="auto, lsoda, dopri5, dopri5_compiled (needs numba), radau or bdf (default auto)")
    simulate.add_argument("--rtol", type=float, default=1e-8, help="relative tolerance (default 1e-8)")
    simulate.add_argument("-o", "--output", help="write the time series to this netCDF file")
    _overwrite_and_json(simulate)
    simulate.set_defaults(handler="rate_state:cmd_simulate")
    stability = actions.add_parser("stability", help="critical stiffness k_c (quasi-static, with damper, with inertia)")
    stability.add_argument("scene", help="rate-and-state scene TOML")
    stability.add_argument("--json", action="store_true", help=COMMON["--json"])
    stability.set_defaults(handler="rate_state:cmd_stability")
    cycles = actions.add_parser("cycles", help="quasi-dynamic earthquake cycles of a fault: recurrence, slip, stress drop")
    cycles.add_argument("scene", help="rate-and-state scene TOML with a [fault] table (e.g. configs/rsf_block_bp1.toml)")
    cycles.add_argument("--cycles", type=int, default=20, help="cycles to measure after two of spin-up (default 20)")
    cycles.add_argument("--seed-law", action=_RoutedTo, handler="rate_state:cmd_cycles_beside_seed_law", help="a seed-law lithology or preset (e.g. granodiorite) to estimate beside, on "
                                           "the same fault with radiation damping")
    cycles.add_argument("--json", action="store_true", help=COMMON["--json"])
    cycles.set_defaults(handler="rate_state_cycles:cmd_cycles")
    bench = actions.add_parser("bench", help="work-precision of the cycle integrators and where each method fails")
    bench.add_argument("--quick", action="store_true", help="3 ratios, 3 tolerances, a coarse failure map (~30 s)")
    _output_dir_option(bench, "rate-state bench", "bench", "the folder for its files (default: bench/)")
    bench.add_argument("--overwrite", action="store_true", help=COMMON["--overwrite"])
    bench.add_argument("--workers", type=int, help="parallel processes (default: the cores)")
    bench.add_argument("--held-out-seed", type=int, help="check the declared errors on this seed's draw of random "
                       "faults, one they were not fitted on (default: the shipped held-out draw; runs with --quick "
                       "too)")
    bench.add_argument("--json", action="store_true", help=COMMON["--json"])
    bench.set_defaults(handler="evaluation:cmd_rate_state_bench")
    group.set_defaults(handler="rate_state:cmd_missing_action")


def _evaluation_commands(commands) -> None:
    """Method evaluation commands (handlers in faultslip.cli.evaluation)."""
    bench = commands.add_parser("bench", help="work-precision study of every method on standard scenes")
    bench.add_argument("--quick", action="store_true", help="fewer tolerances and cycles (under 2 minutes on 2 cores)")
    _output_dir_option(bench, "bench", "bench", "the folder for its files (default: bench/)")
    bench.add_argument("--overwrite", action="store_true", help=COMMON["--overwrite"])
    bench.add_argument("--scene", action="append", help="only this standard scene (repeatable)")
    bench.add_argument("--method", action="append", help="only this method (repeatable)")
    bench.add_argument("--workers", type=int, help="parallel processes (default: the cores)")
    bench.add_argument("--held-out-seed", type=int, help="check the event-driven integrators' declared errors on this "
                       "seed's draw of random scenes, one they were not set on (default: the shipped held-out draw; "
                       "runs with --quick, --scene or --method too)")
    bench.add_argument("--json", action="store_true", help=COMMON["--json"])
    bench.set_defaults(handler="evaluation:cmd_bench")

    stability = commands.add_parser("stability", help="map where each method fails (rate, damping, separation)")
    _output_dir_option(stability, "stability", "stability", "the folder for its files (default: stability/)")
    stability.add_argument("--overwrite", action="store_true", help=COMMON["--overwrite"])
    stability.add_argument("--ratio", action="append", help="only these theta/theta_c values (repeatable)")
    stability.add_argument("--damping-ratio", action="append", help="only these damping ratios (repeatable)")
    stability.add_argument("--separation", action="append", help="only these stick/slip ratios (repeatable)")
    stability.add_argument("--method", action="append", help="only this method (repeatable)")
    stability.add_argument("--workers", type=int, help="parallel processes (default: the cores)")
    stability.add_argument("--json", action="store_true", help=COMMON["--json"])
    stability.set_defaults(handler="evaluation:cmd_stability")

    error = commands.add_parser("model-error", help="one slider's error against the 2-D fault over W / h*, and a scene's")
    error.add_argument("scene", nargs="?", help="a rate-and-state fault scene: its declared model error")
    error.add_argument("--tolerance", help="the model error allowed: where one slider suffices")
    error.add_argument("--plot", help="draw the model-error map to FILE.png")
    error.add_argument("--include-3d", action="store_true",
                       help="on a 2-D fault scene, add the 3-D fault its fault_length states (budgeted first)")
    error.add_argument("--estimate", action="store_true",
                       help="print what the scene's ladder would need (CPU time, memory, disk), its rungs one after "
                            "another, each from its cost model, and stop")
    _overwrite_and_json(error)
    error.set_defaults(handler="evaluation:cmd_model_error")

    predict = commands.add_parser("predictability", help="test a catalogue's recurrence: time-predictable, "
                                                         "slip-predictable, periodic or Poisson (QuakeCaster's exercise)")
    predict.add_argument("catalog", help="catalog: QuakeML (.xml, .quakeml, .qml) or CSV")
    predict.add_argument("--name", help="keep the events whose name holds this text (e.g. Parkfield)")
    predict.add_argument("--seed", type=int, default=0, help="the bootstrap's seed (default 0)")
    predict.add_argument("--plot", help="draw the staircase and the correlations to FILE.png")
    _overwrite_and_json(predict)
    predict.set_defaults(handler="evaluation:cmd_predictability", example_inputs={"catalog": "catalog"})


def _plots_commands(commands) -> None:
    """Figure commands (handlers in faultslip.cli.plots)."""
    plot = commands.add_parser("plot", help="draw a figure")
    figures = plot.add_subparsers(dest="figure", metavar="FIGURE", parser_class=_Parser)
    rate_law = figures.add_parser("rate-law", help="mu_s and amplitude against log10 loading rate (seed Figs. 4-1 to 4-22)")
    rate_law.add_argument("--preset", action="append", help="preset name (repeatable; default: all of Table I)")
    rate_law.add_argument("-o", "--output", required=True, help="output image, e.g. rate_law.png")
    rate_law.add_argument("--overwrite", action="store_true", help=COMMON["--overwrite"])
    rate_law.set_defaults(handler="plots:cmd_plot_rate_law")
    phase = figures.add_parser("phase-plane", help="phase-plane limit cycles below, at and above the critical rate")
    phase.add_argument("--preset", help="Table I preset on its apparatus")
    phase.add_argument("--scene", help="or a scene file")
    phase.add_argument("--damping-ratio", help="damping ratio zeta (needed for a critical rate)")
    phase.add_argument("--rate-factor", action="append", help="loading rate as a multiple of theta_c (repeatable)")
    phase.add_argument("-o", "--output", required=True, help="output image")
    phase.add_argument("--overwrite", action="store_true", help=COMMON["--overwrite"])
    phase.set_defaults(handler="plots:cmd_plot_phase_plane")
    stability = figures.add_parser("rate-state-stability", help="the slip law's critical step and k_c with a damper "
                                                                "or inertia (docs/rate_state.md)")
    stability.add_argument("-o", "--output", required=True, help="output image")
    stability.add_argument("--overwrite", action="store_true", help=COMMON["--overwrite"])
    stability.set_defaults(handler="plots:cmd_plot_rate_state_stability")
    animate = commands.add_parser("animate", help="animate a scene's stick-slip: block, spring and platform beside "
                                                  "the phase plane and the friction trace (GIF)")
    animate.add_argument("scene", help="scene TOML file or bundled scene name")
    animate.add_argument("-o", "--output", required=True, help="output GIF, e.g. slider.gif")
    animate.add_argument("--frames", type=int, default=120, help="frames (default 120, at most 2000)")
    animate.add_argument("--fps", type=int, default=20, help="frames per second (default 20)")
    animate.add_argument("--cycles", type=int, default=2, help="stick-slip cycles shown (default 2)")
    animate.add_argument("--slip-share", type=float, default=0.5, help="share of the frames given to slip phases "
                                                                      "(default 0.5: the time axis is compressed)")
    _overwrite_and_json(animate)
    animate.set_defaults(handler="plots:cmd_animate")
    seed002 = figures.add_parser("seed002", help="seed 002 Figs. 9-11 in kind: four friction curves, amplitude against "
                                                 "speed, damping (docs/quasi_harmonic.md)")
    seed002.add_argument("-o", "--output", required=True, help="output image")
    seed002.add_argument("--overwrite", action="store_true", help=COMMON["--overwrite"])
    seed002.add_argument("--json", action="store_true", help=COMMON["--json"])
    seed002.set_defaults(handler="plots:cmd_plot_seed002")


def _show_warning(message, category, filename, lineno, file=None, line=None):
    """One line per warning: a library's multi-line advice is cut to its first line."""
    text = " ".join(str(message).strip().splitlines()[0].split()) if str(message).strip() else category.__name__
    print(f"faultslip: warning: {text}", file=sys.stderr)


def main(argv=None) -> int:
    """Run one command; returns the exit status (0, 1 machine error, 2 bad input, 130 interrupted)."""

    try:
        warnings.showwarning = _show_warning
        parser = build_parser(argv if argv is not None else sys.argv[1:])
        args = parser.parse_args(argv)
        handler = getattr(args, "handler", None)
        if handler is None:
            parser.print_help(sys.stderr)
            return 2
        module, function = handler.split(":")
        # pint, when a command needs it, loads without its dask probe (faultslip.units.PINT_WITHOUT_DASK)
        importlib.import_module("faultslip.units").PINT_WITHOUT_DASK = True
        command = getattr(importlib.import_module(f"faultslip.cli.{module}"), function)
        found = []
        if getattr(args, "example_inputs", None):  # a data command's inputs: a path, or a bundled example's name
            found = importlib.import_module("faultslip.cli.common").resolve_examples(args)
        with transaction():  # a command's outputs appear together when it succeeds, or none do
            code = command(args)
        for origin in found if code in (0, None) else ():  # said after the answer: a refusal stays one sentence
            print(f"faultslip: {origin}", file=sys.stderr)
        return code
    except FaultslipError as exc:
        print(f"faultslip: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        if _AS_PROGRAM:  # answered once: a further Ctrl-C while cleaning up must not end in a traceback

            signal.signal(signal.SIGINT, signal.SIG_IGN)
        print("faultslip: interrupted; no output file was left half-written", file=sys.stderr)
        return 130
    except MemoryError:
        print("faultslip: error: out of memory; make the run smaller (see --allow-large and the budget)", file=sys.stderr)
        return 1
    except BrokenPipeError:  # the reader (e.g. head) closed the pipe: stop quietly

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

    global _AS_PROGRAM
    _AS_PROGRAM = True
    code = main()
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if code == 130:
        # A Ctrl-C that landed inside an import leaves CPython's "unhandled KeyboardInterrupt" flag
        # set, and the interpreter would then end itself with SIGINT (status -2) although the
        # interrupt was handled. Outputs are closed and pools stopped by now: leave at once.

        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(130)
    sys.exit(code)


_AS_PROGRAM = False  # True when running as the faultslip program, not called from Python