"""Figure commands: plot rate-law, plot phase-plane, plot rate-state-stability."""

from __future__ import annotations


from faultslip.cli.common import _locked, _number, _outputs, _system_from_args
from faultslip.errors import FaultslipError
from faultslip.friction.materials import get_preset, table_i_presets
from faultslip.io.atomic import save_figure
from faultslip.io.outputs import FIGURE_SUFFIXES
from faultslip.plots.figures import phase_plane_figure, rate_law_figure
from faultslip.plots.rate_state import stability_figure


def cmd_plot_rate_law(args) -> int:
    output = _outputs(args, {"output": ("-o", FIGURE_SUFFIXES)})["output"]
    chosen = [get_preset(name) for name in args.preset] if args.preset else table_i_presets()
    for preset in chosen:
        preset.require_stick_slip()
    figure = rate_law_figure(chosen)
    with _locked(output):
        save_figure(figure, output, dpi=150)
    print(f"wrote {args.output}")
    return 0


def cmd_plot_phase_plane(args) -> int:
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


def cmd_plot_rate_state_stability(args) -> int:
    output = _outputs(args, {"output": ("-o", FIGURE_SUFFIXES)})["output"]
    with _locked(output):
        save_figure(stability_figure(), output, dpi=150)
    print(f"wrote {args.output}")
    return 0
