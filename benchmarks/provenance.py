"""Where and with what a benchmark ran: one stamp for every file in benchmarks/results/.

A figure re-measured elsewhere (another host, the newest packages) is only comparable when the file says what it
was measured with, so every benchmark writes :func:`stamp` beside its numbers and ``benchmarks/readme.py`` prints it
under each table. tests/project/test_architecture.py refuses a benchmark that writes its own.
"""

from __future__ import annotations

import json
import os
import platform
from datetime import datetime, timezone
from importlib import metadata
from pathlib import Path

#: the distributions whose versions move the figures: the array stack, the compiler and FFT of the compiled paths,
#: and the plotting, labelled-array, unit and seismology layers the benchmarks time, and the 3-D kernel's dislocations
PACKAGES = ("numpy", "scipy", "numba", "llvmlite", "rocket-fft", "matplotlib", "xarray", "dask", "pint", "obspy", "cutde")


def machine() -> str:
    """The machine as the docs' tables name it: architecture, cores and Python, e.g.
    "x86_64, 2 cores, Python 3.11.7"."""
    return f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}"


def packages() -> dict[str, str]:
    """The installed version of each of :data:`PACKAGES` (those not installed left out)."""
    versions = {}
    for name in PACKAGES:
        try:
            versions[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            continue
    return versions


def stamp() -> dict:
    """The machine, the packages and the UTC date, as a results file's keys ``machine``, ``packages``, ``date``; and
    ``reference_work_seconds``, the machine's speed as the file was written (:func:`faultslip.io.machine.probe_seconds`),
    so that CPU times measured on another day can be set beside these."""
    from faultslip.io.machine import probe_seconds

    return {"machine": machine(), "packages": packages(),
            "date": datetime.now(timezone.utc).strftime("%Y-%m-%d"), "reference_work_seconds": probe_seconds()}


def described(stamped: dict | None = None) -> str:
    """A stamp (:func:`stamp`, a fresh one by default) as one line for a generated page: "x86_64, 2 cores, Python
    3.11.7, 2026-11-28 (numpy 2.3.5, scipy 1.17.1, ...)"."""
    stamped = stamp() if stamped is None else stamped
    versions = listed(stamped)
    return f"{stamped['machine']}, {stamped['date']}" + (f" ({versions})" if versions else "")


def listed(stamped: dict) -> str:
    """A stamp's packages as "numpy 2.3.5, scipy 1.17.1, ..." (empty for a result written before stamps held
    them)."""
    return ", ".join(f"{name} {version}" for name, version in stamped.get("packages", {}).items())


def write_results(name: str, document: dict) -> None:
    """benchmarks/results/NAME: ``document`` with its :func:`stamp` (machine, packages, date)."""
    out = Path(__file__).resolve().parent / "results" / name
    document = {**document, **stamp()}
    out.write_text(json.dumps(document, indent=1) + "\n", encoding="utf-8")
    print(f"written to {out}")
