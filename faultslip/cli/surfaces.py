"""Surface command: faultslip surface (seed 000's rough-surface statistics and contact)."""

from __future__ import annotations

from faultslip.cli.common import _number, _outputs, _save_run
from faultslip.cli.printing import _emit
from faultslip.io.outputs import FIGURE_SUFFIXES
from faultslip.lab.surfaces import analyze_surface
from faultslip.plots.surfaces import surface_figure


def cmd_surface(args) -> int:
    plot = _outputs(args, {"plot": ("--plot", FIGURE_SUFFIXES)}, [args.surface] if args.surface else [])["plot"]
    analysis = analyze_surface(args.surface, synthetic=args.synthetic, size=args.size, profile=args.profile,
                               seed=args.seed, modulus=args.modulus, poisson=_number(args.poisson, "--poisson"),
                               hardness=args.hardness, against=args.against, flow_pressure=args.flow_pressure,
                               load=args.load)
    report = analysis.report
    _save_run(report, {"plot": plot}, args, None,
              lambda: surface_figure(analysis.surface, analysis.stats, analysis.contact),
              drawing="surface, autocorrelation, height density and contact")
    return _emit(report, args.json)
