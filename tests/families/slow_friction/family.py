"""The slow-friction family's declaration: constant friction's physics, with a cost, a log and a failure."""

from __future__ import annotations

import os
import time

from faultslip.contract.cells import PerCell
from faultslip.contract.registry import Family, register
from faultslip.contract.result import Result
from faultslip.contract.scenes import toml_reader
from faultslip.errors import InputError, SolverError
from faultslip.io.report import Report

from families.constant_friction.family import cycle
from families.constant_friction.scene import OUTPUTS, PARAMETERS, read


def _log(event: str, values: dict) -> None:
    path = os.environ.get("FAULTSLIP_TEST_CELL_LOG")
    if path:  # one short line, appended in one write: lines of several workers never interleave
        line = f"{event} {values['static']:.6g} {values['platform_speed']:.6g} {os.environ.get('SLURM_JOB_ID', '-')}\n"
        with open(path, "a", encoding="utf-8") as log:
            log.write(line)


def run(scene, method=None, tolerance=None) -> Result:
    if method not in (None, "auto", "closed_form"):
        raise InputError(f"a slow-friction scene runs closed_form, got {method!r}")
    values = read(scene)
    _log("start", values)
    time.sleep(float(os.environ.get("FAULTSLIP_TEST_CELL_SECONDS", "0")))
    limit = os.environ.get("FAULTSLIP_TEST_FAIL_ABOVE")
    if limit is not None and values["static"] > float(limit):
        _log("failed", values)
        raise SolverError(f"the test solver fails above static friction {limit} (asked {values['static']:.6g})")
    slip, period, _ = cycle(values)
    report = Report("slow friction")
    report.add("slip_per_event", slip, "m").add("recurrence_period", period, "s").add("regime", "stick_slip")
    _log("end", values)
    return Result("slow_friction", report)


CELLS = PerCell("a slow-friction study", PARAMETERS, OUTPUTS, run, read, methods=("auto", "closed_form"), seconds=1.0)
FAMILY = register(Family("slow_friction", "constant friction that takes its time (a test family)", run, None,
                         read_scene=toml_reader("slow_friction", PARAMETERS), cells=CELLS, methods=lambda: []))
