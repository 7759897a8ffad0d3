"""Seismology commands: catalog."""

from __future__ import annotations

import numpy as np

from faultslip import ranges
from faultslip.cli.common import _locked, _number, _outputs
from faultslip.cli.printing import _emit
from faultslip.errors import InputError
from faultslip.evaluation.catalogs import compare
from faultslip.fault.scene import read_slider_scene
from faultslip.io.atomic import save_figure
from faultslip.io.catalogs import parse_time, read_catalog
from faultslip.io.geo import parse_trace
from faultslip.io.outputs import FIGURE_SUFFIXES
from faultslip.plots.catalogs import catalog_figure
from faultslip.units import to_si


def cmd_catalog(args) -> int:
    plot = _outputs(args, {"plot": ("--plot", FIGURE_SUFFIXES)}, [args.catalog, args.fault])["plot"]
    ranges.check_count(args.bootstrap, "--bootstrap", 0, ranges.MOST_RESAMPLES)
    ranges.check_count(args.seed, "--seed")
    scene = read_slider_scene(args.fault)
    trace = parse_trace(args.trace, "--trace") if args.trace else scene.trace
    window = {key: parse_time(getattr(args, key), f"--{key.replace('_', '-')}") if getattr(args, key) else None
              for key in ("since", "until", "as_of")}
    magnitudes = {key: _number(getattr(args, key), f"--{key.replace('_', '-')}") if getattr(args, key) else None
                  for key in ("min_magnitude", "max_magnitude")}
    if args.cluster_fraction == "refuse":
        cluster_fraction = None
    else:
        cluster_fraction = _number(args.cluster_fraction, "--cluster-fraction")
        if not 0 < cluster_fraction < 1:
            raise InputError(f"--cluster-fraction must lie between 0 and 1 (or be 'refuse'), got {args.cluster_fraction}")
    catalog = read_catalog(args.catalog)
    comparison = compare(catalog, scene, trace=trace, max_distance=to_si(args.max_distance, "length", "--max-distance"),
                         cluster_fraction=cluster_fraction,
                         horizon=to_si(args.horizon, "time", "--horizon"), bootstrap=args.bootstrap, seed=args.seed,
                         as_of=window["as_of"] if window["as_of"] is not None else np.datetime64("now", "ms"),
                         since=window["since"], until=window["until"], **magnitudes)
    title = f"faultslip catalog: {catalog.path.split('/')[-1]} on {scene.name}"
    report = comparison.report(title)
    if trace is None:
        report.note("no trace (neither --trace nor [fault] trace): events were selected by magnitude and time only")
    if plot:
        with _locked(plot):
            save_figure(catalog_figure(comparison, title), plot, dpi=150)
        report.note(f"figure drawn to {args.plot}")
    return _emit(report, args.json)
