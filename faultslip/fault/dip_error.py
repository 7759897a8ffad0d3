"""The antiplane rung's declared model error on a dip-slip fault, against the 2-D fault in plane strain.

The antiplane fault reads a dipping fault's description (friction down dip, its width) as a vertical fault in
antiplane strain: it misses the in-plane stiffness (1 / (1 - nu) of the antiplane's at depth), the free surface's
in-plane image, and the normal stress that slip changes (BP3 eq. 15). ``benchmarks/dip_model_error.py`` measures
the difference, in recurrence and mean slip per event, on SEAS BP3's fault at dips 30-90 degrees for thrust and
normal faults, and ships ``data/dip_model_error.json``: at each measured dip, the largest error of both senses
times :data:`MARGIN`. Between measured dips the larger of the two brackets holds; outside them nothing is known.
"""

from __future__ import annotations

import functools
import math

from faultslip.errors import InputError
from faultslip.io import gate
from faultslip.io.resources import bundled_dir

TABLE_FILE = "dip_model_error.json"
#: The declared error's factor over the largest measured (the one-slider calibration's, issue 42).
MARGIN = 1.25


@functools.lru_cache(maxsize=1)
def load_table() -> dict:
    """``data/dip_model_error.json``, checked: rows of ``dip`` (degrees) and ``model_error`` (relative)."""
    path = bundled_dir("data") / TABLE_FILE
    try:
        table = gate.read_json(path, "the antiplane rung's model error on dip-slip faults")
    except InputError as exc:
        raise InputError(f"{exc}; reinstall faultslip or run benchmarks/dip_model_error.py") from None
    rows = table.get("rows") if isinstance(table, dict) else None
    if not (isinstance(rows, list) and rows and all(
            isinstance(row, dict) and isinstance(row.get("dip"), (int, float))
            and isinstance(row.get("model_error"), (int, float)) and row["model_error"] >= 0 for row in rows)):
        raise InputError(f"{path.name} lacks rows of dip and a non-negative model_error; rerun "
                         "benchmarks/dip_model_error.py")
    return table


def declared(dip: float, rows: list | None = None) -> float:
    """The antiplane rung's declared model error (relative, the larger of recurrence and slip) on a fault dipping
    ``dip`` degrees: the larger of the measured dips that bracket it; infinite outside them.

    Parameters
    ----------
    dip : float
        The fault's dip (degrees).
    rows : list of dict, optional
        ``dip`` and ``model_error`` rows (the shipped table's otherwise).

    Returns
    -------
    float
        The declared model error (dimensionless); ``inf`` outside the measured dips.
    """
    rows = sorted(rows if rows is not None else load_table()["rows"], key=lambda row: row["dip"])
    dips = [float(row["dip"]) for row in rows]
    if not (dips[0] <= dip <= dips[-1]):
        return math.inf
    if dip in dips:
        return float(rows[dips.index(dip)]["model_error"])
    for lower, upper in zip(rows, rows[1:] + rows[-1:]):
        if lower["dip"] <= dip <= upper["dip"]:
            return float(max(lower["model_error"], upper["model_error"]))
    return float(rows[-1]["model_error"])
