"""Figure commands: plot rate-law, plot phase-plane, plot rate-state-stability, plot seed002, animate."""

from __future__ import annotations


from faultslip.cli.common import _locked, _number, _outputs, _system_from_args
from faultslip.cli.printing import _emit, _progress
from faultslip.errors import FaultslipError
from faultslip.friction.materials import get_preset, table_i_presets
from faultslip.io.atomic import save_figure
from faultslip.io.outputs import FIGURE_SUFFIXES
from faultslip.plots.figures import phase_plane_figure, rate_law_figure
from faultslip.io.report import Report
from faultslip.lab.seed002_curves import figures_9_to_11
from faultslip.plots.rate_state import stability_figure
from faultslip.plots.vibration import seed002_figures
from faultslip.plots.animation import MAX_FRAMES, save_gif
from faultslip import models


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


def cmd_plot_seed002(args) -> int:
    output = _outputs(args, {"output": ("-o", FIGURE_SUFFIXES)})["output"]
    table = figures_9_to_11()
    with _locked(output):
        save_figure(seed002_figures(table), output, dpi=150)
    report = Report("seed 002 Figs. 9-11 in kind: where each averaged branch ends")
    for name, speed in table["termination"].items():
        curve = table["curves"][name]
        report.add(f"curve_{name}_ends", speed, "m/s", also=("in/s",),
                   label=f"({name}) ends; flattens at {curve.flattening_speed / 0.0254:g} in/s")
    for factor, speed in table["damped_termination"].items():
        report.add(f"curve_A_damping_x{factor:g}_ends", speed, "m/s", also=("in/s",), label=f"(A), damping x {factor:g}, ends")
    report.add("figure", str(output))
    report.note("every amplitude on the rising branches has A omega > v: the slider would stick there "
                "(docs/seed_discrepancies.md)")
    return _emit(report, args.json)


def cmd_animate(args) -> int:
    output = _outputs(args, {"output": ("-o", (".gif",))}, [args.scene])["output"]
    if not 1 <= args.cycles <= 50:
        raise FaultslipError(f"--cycles must be from 1 to 50, got {args.cycles}")
    if not 1 <= args.fps <= 60:  # checked before any work, as are the frames and the share below
        raise FaultslipError(f"--fps must be from 1 to 60, got {args.fps}")
    if not 2 <= args.frames <= MAX_FRAMES:
        raise FaultslipError(f"--frames must be from 2 to {MAX_FRAMES}, got {args.frames}")
    if not 0 < args.slip_share < 1:
        raise FaultslipError(f"--slip-share must lie strictly between 0 and 1, got {args.slip_share}")
    movie, figure, details = models.animate(args.scene, cycles=args.cycles, frames=args.frames,
                                            slip_share=args.slip_share)
    with _locked(output):
        save_gif(movie, figure, output, fps=args.fps, progress=_progress("animate", not getattr(args, "json", False), "frame"))
    report = Report(f"faultslip animate: {details.pop('title')}")
    report.add("frames", args.frames).add("fps", args.fps)
    for key, value in details.items():
        value, label = value if isinstance(value, tuple) else (value, None)
        report.add(key, value, label=label)
    report.add("output", str(output))
    return _emit(report, args.json)
