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
from faultslip.io.resources import read_bundled_table

TABLE_FILE = "dip_model_error.json"
#: The declared error's factor over the largest measured (the one-slider calibration's, issue 42).
MARGIN = 1.25


@functools.lru_cache(maxsize=1)
def load_table() -> dict:
    """``data/dip_model_error.json``, checked: rows of ``dip`` (degrees) and ``model_error`` (relative)."""
    table = read_bundled_table(TABLE_FILE, "the antiplane rung's model error on dip-slip faults", "benchmarks/dip_model_error.py")
    rows = table.get("rows") if isinstance(table, dict) else None
    if not (isinstance(rows, list) and rows and all(
            isinstance(row, dict) and isinstance(row.get("dip"), (int, float))
            and isinstance(row.get("model_error"), (int, float)) and row["model_error"] >= 0 for row in rows)):
        raise InputError(f"{TABLE_FILE} lacks rows of dip and a non-negative model_error; rerun "
                         "benchmarks/dip_model_error.py")
    return table


def declared(dip: float, rows: list | None = None, width_over_nucleation: float | None = None) -> float:
    """The antiplane rung's declared model error (relative, the larger of recurrence and slip) on a fault dipping
    ``dip`` degrees with ``width_over_nucleation`` (W / h*): the largest at the measured cells that bracket it, in
    W / h* (the two measured levels either side) and in dip (at each level, the two measured dips either side);
    infinite outside them.

    Parameters
    ----------
    dip : float
        The fault's dip (degrees).
    rows : list of dict, optional
        ``dip``, ``width_over_nucleation`` and ``model_error`` (already the bound) rows; the shipped table's
        otherwise.
    width_over_nucleation : float, optional
        The fault's W / h* (:meth:`faultslip.models.fault_2d.model.Fault2D.nucleation_size`); without it, the
        largest over every measured level at the bracketing dips.

    Returns
    -------
    float
        The declared model error (dimensionless); ``inf`` outside the measured dips or W / h*.
    """
    rows = rows if rows is not None else load_table()["rows"]
    levels = sorted({round(float(row.get("width_over_nucleation", 0.0)), 9) for row in rows})
    if width_over_nucleation is None:
        chosen = levels
    else:
        if not levels[0] <= width_over_nucleation <= levels[-1]:
            return math.inf
        below = max(level for level in levels if level <= width_over_nucleation)
        above = min(level for level in levels if level >= width_over_nucleation)
        chosen = sorted({below, above})
    worst = 0.0
    for level in chosen:
        cells = sorted((row for row in rows if round(float(row.get("width_over_nucleation", 0.0)), 9) == level),
                       key=lambda row: row["dip"])
        dips = [float(row["dip"]) for row in cells]
        if not dips[0] <= dip <= dips[-1]:
            return math.inf
        lower = max(d for d in dips if d <= dip)
        upper = min(d for d in dips if d >= dip)
        worst = max([worst] + [float(row["model_error"]) for row in cells if float(row["dip"]) in (lower, upper)])
    return worst
