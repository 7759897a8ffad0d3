"""Shared helpers of the docs tables: results files, their stamps, the peer sentence."""

from __future__ import annotations

import json
from pathlib import Path

from provenance import listed  # one stamp for every results file

ROOT = Path(__file__).resolve().parents[2]
RESULTS = ROOT / "benchmarks" / "results"


def _load(name):
    path = RESULTS / name
    return json.loads(path.read_text(encoding="utf-8")) if path.exists() else None


def _load_with(name, key):
    """The results file ``name`` if it holds ``key`` (an older file without it renders nothing), else None."""
    result = _load(name)
    return result if result is not None and key in result else None


def _packages(result) -> str:
    """The packages a result was measured with (provenance.stamp), as a sentence; empty for an older result."""
    versions = listed(result)
    return f" Packages: {versions}." if versions else ""


def _machine(result) -> str:
    machine = result.get("machine", "")
    if isinstance(machine, dict):
        machine = f"{machine.get('platform', '')}, Python {machine.get('python', '')}"
    return f"Measured on {machine}, {result.get('date', 'date not recorded')}.{_packages(result)}"


def _peer_closing(rows: list, result: dict) -> str:
    """A peer table's end: why QDYN did not run, if it did not, and the machine and date."""
    if not result.get("ratio_faultslip_over_best_peer") and result.get("qdyn_missing"):
        rows.append(f"QDYN was not run on this machine: {result['qdyn_missing']}.")
    return "\n".join(rows) + "\n\n" + _machine(result)


#: The one slider's quantities, as the ladder's tables name them.
ONE_SLIDER_QUANTITIES = {"recurrence": "recurrence", "mean_slip": "slip per event, mean over the rupture zone",
                         "surface_slip": "surface slip per event (surface-breaking faults)"}
