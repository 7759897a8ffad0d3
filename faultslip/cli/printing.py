"""Printing a command's report, and its progress on stderr: all that the lightest commands need from the CLI."""

from __future__ import annotations

import time

from faultslip.io.progress import Progress


def _emit(report, as_json: bool) -> int:
    print(report.to_json() if as_json else report.to_text())
    return 0


def _emit_estimate(estimate, as_json: bool) -> int:
    """An ``--estimate``: the family's cost model, and the CPU this command has used to start (the interpreter and
    its imports, which no cost model counts), so its total is what the command without --estimate would use."""
    return _emit(estimate.report(started=time.process_time()), as_json)


def _progress(label, enabled=True, unit="it"):
    """Progress on stderr (faultslip.io.progress): a bar on a terminal, log lines when redirected; none
    with --json or for work shorter than two seconds."""
    return Progress(label, unit) if enabled else None
