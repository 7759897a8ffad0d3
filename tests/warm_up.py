"""Compile what a fresh environment compiles on first use, once, beside the suite's first tests.

A new virtual environment (CI's, a fresh clone's) has no numba cache: the OpenQuake engine compiles its numba
functions when it is first imported (about a minute here, then cached in its package), and the 2-D fault's whole
step is built on one thread and on two (about 40 s, cached in faultslip's). The suite's workers (pytest-xdist,
one a core) would each compile them where a test of theirs first needs them; conftest.py starts this script once,
from the controller, at the session's start, so that they are compiled once, early. It changes no result: a test
that gets there first compiles the same functions itself, and numba writes each cache entry whole. It dies with
the suite (its parent, given as the argument).

    python tests/warm_up.py PARENT_PID
"""

from __future__ import annotations

import contextlib
import ctypes
import os
import signal
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def die_with(parent: int) -> None:
    if sys.platform.startswith("linux"):
        with contextlib.suppress(OSError, AttributeError):
            ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    if os.getppid() != parent:  # the parent died before prctl took effect
        os._exit(0)


def main() -> None:
    die_with(int(sys.argv[1]))
    with contextlib.suppress(Exception):  # the engine compiles its numba functions on import
        import openquake.hazardlib.nrml  # noqa: F401
        import openquake.hazardlib.sourceconverter  # noqa: F401
        import openquake.calculators.classical  # noqa: F401
    with contextlib.suppress(Exception):  # the 2-D fault's step, one thread and two, on a fault with the FFT kernel
        from faultslip.constants import JULIAN_YEAR
        from faultslip.models.fault_2d.integrate import run_cycles
        from faultslip.models.fault_2d.scene import read_fault_2d_scene

        fault = read_fault_2d_scene(ROOT / "configs" / "seas_bp1.toml").at_element_size(40e3 / 600).fault
        for threads in (1, 2):
            run_cycles(fault, 1e-3 * JULIAN_YEAR, rtol=1e-4, threads=threads)


if __name__ == "__main__":
    main()
