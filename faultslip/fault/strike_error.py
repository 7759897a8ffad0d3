"""The 2-D rung's declared model error on a fault finite along strike, against the 3-D fault.

The 2-D fault reads the middle column of a 3-D scene (friction down dip) as a fault infinitely long along strike.
A finite velocity-weakening patch is stiffer (its stress drop is spread over a shorter rupture) and its ends creep
into it, so its recurrence and slip per event differ from the 2-D fault's, the more so the shorter the patch.
``benchmarks/fault_3d_model_error.py`` measures the difference on SEAS BP5-QD's fault (at 1/20 scale) for patches
of aspect L / W = 1 to 8 and three burials, and ships ``data/strike_model_error.json``: each measured cell's error
times :data:`MARGIN`. A fault's declared error is the largest at the measured aspects bracketing its own (any
measured burial), where its burial lies within the measured ones; outside them nothing is known (infinite).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from faultslip.errors import InputError
from faultslip.io.resources import read_bundled_table

TABLE_FILE = "strike_model_error.json"
#: The declared error's factor over the largest measured (as the dip's and the one slider's).
MARGIN = 1.25


def groups_of(fault) -> dict:
    """A 3-D fault's velocity-weakening patch as the declaration reads it: ``aspect_measured`` (its longest extent
    along strike over its widest down dip) and ``burial`` (its top's distance down dip, in the middle column, over
    that width)."""
    weakening = fault.grid(fault.b > fault.a)
    width = fault.seismogenic_width()
    column = weakening[fault.column(0.0)]
    top = float(np.argmax(column) * fault.element_size) if np.any(column) else math.nan
    return {"aspect_measured": fault.seismogenic_length() / width if width > 0 else math.nan,
            "burial": top / width if width > 0 else math.nan}


@functools.lru_cache(maxsize=1)
def load_table() -> dict:
    """``data/strike_model_error.json``, checked: rows of ``aspect``, ``burial`` and ``model_error``."""
    table = read_bundled_table(TABLE_FILE, "the 2-D rung's model error against the 3-D fault",
                               "benchmarks/fault_3d_model_error.py")
    rows = table.get("rows") if isinstance(table, dict) else None
    if not (isinstance(rows, list) and rows and all(
            isinstance(row, dict) and isinstance(row.get("aspect"), (int, float))
            and isinstance(row.get("burial"), (int, float))
            and (row.get("model_error") is None or row["model_error"] >= 0) for row in rows)):
        raise InputError(f"{TABLE_FILE} lacks rows of aspect, burial and a non-negative model_error; rerun "
                         "benchmarks/fault_3d_model_error.py")
    return table


def declared(aspect: float, rows: list | None = None, burial: float | None = None) -> float:
    """The 2-D rung's declared model error (relative, the larger of recurrence and slip per event) on a fault whose
    weakening patch has aspect ``aspect`` (L / W) and ``burial`` (top / W).

    Parameters
    ----------
    aspect : float
        The patch's length along strike over its width down dip.
    rows : list of dict, optional
        ``aspect``, ``burial`` and ``model_error`` (already the bound) rows; the shipped table's otherwise.
    burial : float, optional
        The patch's top over its width; without it, any.

    Returns
    -------
    float
        The declared model error (dimensionless); ``inf`` outside the measured aspects or burials, or where a
        bracketing cell had no answer (the 3-D patch crept, or the 2-D fault did).
    """
    rows = rows if rows is not None else load_table()["rows"]
    aspects = sorted({float(row["aspect"]) for row in rows})
    burials = [float(row["burial"]) for row in rows]
    if not (math.isfinite(aspect) and aspects[0] <= aspect <= aspects[-1]):
        return math.inf
    if burial is not None and not (min(burials) - 1e-9 <= burial <= max(burials) + 1e-9):
        return math.inf
    lower = max(a for a in aspects if a <= aspect)
    upper = min(a for a in aspects if a >= aspect)
    errors = [row["model_error"] for row in rows if float(row["aspect"]) in (lower, upper)]
    if any(error is None for error in errors):
        return math.inf
    return float(max(errors))
