"""What every command shares: output checks and locks, worker caps, progress lines, small parsers."""

from __future__ import annotations

import contextlib
import sys
from pathlib import Path

from faultslip import ranges
from faultslip.dynamics.spring_slider.closed_form import dashpot_for_damping_ratio
from faultslip.dynamics.spring_slider.slider import SliderSystem
from faultslip.errors import FaultslipError, InputError
from faultslip.fault.scene import read_slider_scene
from faultslip.io.atomic import claim, save_figure
from faultslip.io.netcdf import write_dataset
from faultslip.io.outputs import check_output, output_lock, same_file
from faultslip.io.processes import usable_cores, usable_workers
from faultslip.io.resources import resolve_path
from faultslip.units import to_si


def resolve_examples(args) -> list[str]:
    """A data command's input files (``args.example_inputs``: attribute -> what it is), each a path as given, or,
    as a bare name with no such file here, the bundled example of that name: the README's examples run outside a
    clone too (:func:`faultslip.io.resources.bundled_examples`). Returns what was found where, for the command to
    say once it has succeeded (a refusal stays one sentence)."""
    origins = []

    def resolved(value, what):
        path, origin = resolve_path(value, what, kind="example")
        origins.append(origin)
        return str(path)

    for attribute, what in getattr(args, "example_inputs", {}).items():
        value = getattr(args, attribute, None)
        if isinstance(value, list):  # a repeated option (fit --joint)
            setattr(args, attribute, [resolved(item, what) for item in value])
        elif value is not None:
            setattr(args, attribute, resolved(value, what))
    return [origin for origin in origins if origin]


def _outputs(args, specs, inputs=()):
    """Check every output option before any work; returns {attribute: Path or None}.

    ``specs`` maps an attribute of ``args`` to (label, allowed suffixes). Two options naming one
    file are refused too.
    """

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
    for attribute, path in paths:  # held to the command's end: a second writer is refused before any work
        claim(path, _command_name(), getattr(args, "overwrite", False), specs[attribute][0])
    return checked


def _command_name() -> str:
    return " ".join(["faultslip"] + [word for word in sys.argv[1:3] if not word.startswith("-")][:2])


def _locked(*paths):
    """Hold the output lock of every given path (None skipped) while the outputs are written."""


    stack = contextlib.ExitStack()
    for path in paths:
        if path is not None:
            stack.enter_context(output_lock(path, _command_name()))
    return stack


def _output_dir(args, default, names):
    """Check an output folder and the files it will receive, before any work; create the folder."""


    folder = check_output(args.output or default, label="--output-dir", directory=True)
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


    if args.workers is None:  # not given: as many as help, silently
        return usable_workers(usable_cores(), tasks)[0]
    workers, note = usable_workers(args.workers, tasks)
    if note:
        args.notes = getattr(args, "notes", []) + [note]
        if not args.json:
            print(f"faultslip: note: {note}", file=sys.stderr)
    return workers


def _tolerance(args):
    if getattr(args, "tolerance", None) is None:
        return None
    return ranges.check_tolerance(args.tolerance, "--tolerance")


def _number(text, name):
    return to_si(text, "dimensionless", name)


def _system_from_args(args):
    if args.preset and getattr(args, "scene", None):
        raise InputError("give a preset or a scene, not both")
    if args.preset:
        zeta = 0.0 if args.damping_ratio is None else _number(args.damping_ratio, "damping ratio")
        return SliderSystem.from_preset(args.preset, loading_rate="1 1/s", damping_ratio=zeta)
    if getattr(args, "scene", None):
        system = read_slider_scene(args.scene).slider()
        if args.damping_ratio is not None:

            zeta = _number(args.damping_ratio, "damping ratio")
            system = system.with_(dashpot=float(dashpot_for_damping_ratio(zeta, system.stiffness, system.mass)))
        return system
    raise InputError("give --preset NAME (with --damping-ratio) or a scene file")


def _save_run(report, outputs: dict, args, dataset, figure, series: str = "time series", drawing: str = "figure"):
    """Write a run's dataset to ``-o`` and draw ``figure()`` (called only if asked) to ``--plot``, locked
    against a second writer, each noted in the report."""
    with _locked(outputs.get("output"), outputs.get("plot")):
        if outputs.get("output"):
            write_dataset(dataset, outputs["output"])
            report.note(f"{series} written to {args.output}")
        if outputs.get("plot"):
            save_figure(figure(), outputs["plot"], dpi=150)
            report.note(f"{drawing} drawn to {args.plot}")
