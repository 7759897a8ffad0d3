"""The antiplane rung's declared model error on a dip-slip fault, against the 2-D fault in plane strain.

The antiplane fault reads a dipping fault's description (friction down dip, its width) as a vertical fault in
antiplane strain: it misses the in-plane stiffness (1 / (1 - nu) of the antiplane's at depth), the free surface's
in-plane image, and the normal stress that slip changes (BP3 eq. 15). ``benchmarks/dip_model_error.py`` measures
the difference, in recurrence and mean slip per event, on SEAS BP3's fault: a grid of dips 30-90 degrees, thrust and
normal, at three D_c, and faults drawn at random over dip, sense, D_c and seismogenic depth. The error moves with
W / h* far more than with the dip, and not smoothly: where the two rungs' sequences part (partial ruptures in one,
system-size events in the other) it jumps, and a jump seen at one W / h* comes back at larger ones, where no
measured fault beside it foretells it. So ``data/dip_model_error.json`` ships the measured faults, and the
declared error at a fault's W / h* is the largest measured at any W / h* up to a window above it (any dip and
sense: the measured errors' running maximum), times :data:`MARGIN`, where at least ``min_neighbours`` were
measured within the window either side; outside the measured dips or W / h*, or where the window holds too few,
nothing is declared.
"""

from __future__ import annotations

import functools
import math

from faultslip.errors import InputError
from faultslip.io.gate import json_checksum
from faultslip.io.resources import TABLE_CHECKSUM, read_bundled_table

TABLE_FILE = "dip_model_error.json"
#: The declared error's factor over the largest measured (the one-slider calibration's, issue 42).
MARGIN = 1.25


@functools.lru_cache(maxsize=1)
def load_table() -> dict:
    """``data/dip_model_error.json``, checked: ``faults`` of ``dip`` (degrees), ``width_over_nucleation`` and
    ``model_error`` (relative, measured), and the declaration's ``margin``, ``window`` and ``min_neighbours``."""
    table = read_bundled_table(TABLE_FILE, "the antiplane rung's model error on dip-slip faults", "benchmarks/dip_model_error.py")
    faults = table.get("faults") if isinstance(table, dict) else None
    if not (isinstance(faults, list) and faults and all(
            isinstance(row, dict) and all(_number(row.get(key)) for key in ("dip", "width_over_nucleation", "model_error"))
            and row["model_error"] >= 0 and row["width_over_nucleation"] > 0 for row in faults)
            and all(_number(table.get(key)) and table[key] > 0 for key in ("margin", "window", "min_neighbours"))):
        raise InputError(f"{TABLE_FILE} lacks faults of dip, W / h* and a non-negative model_error, or the "
                         "declaration's margin, window and min_neighbours; rerun benchmarks/dip_model_error.py")
    return table


def declaration_checksum(table: dict | None = None) -> str:
    """The checksum ``data/dip_model_error.json`` was written with, from its content (the shipped table's
    otherwise): it names the declaration a fresh draw was read against (benchmarks/dip_model_error.py --fresh)."""
    return json_checksum(table if table is not None else load_table(), TABLE_CHECKSUM)


def _number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def neighbours(width_over_nucleation: float, faults: list, window: float) -> list:
    """The measured faults whose W / h* lies within a factor exp(``window``) of ``width_over_nucleation``."""
    return [row for row in faults
            if abs(math.log(row["width_over_nucleation"] / width_over_nucleation)) <= window]


def declared(dip: float, width_over_nucleation: float, table: dict | None = None) -> float:
    """The antiplane rung's declared model error (relative, the larger of recurrence and slip) on a fault dipping
    ``dip`` degrees with ``width_over_nucleation`` (W / h*):

        e(dip, W / h*) = margin max { e_i : ln(W_i / h*_i) - ln(W / h*) <= window },

    over the measured faults i of any dip and sense (the running maximum of their errors, up to a factor
    exp(window) above W / h*), where at least ``min_neighbours`` lie within a factor exp(window) either side;
    infinite outside the measured dips or W / h*, or where fewer lie near it.

    Parameters
    ----------
    dip : float
        The fault's dip (degrees).
    width_over_nucleation : float
        The fault's W / h* (:meth:`faultslip.models.fault_2d.model.Fault2D.nucleation_size`).
    table : dict, optional
        ``faults`` (``dip``, ``width_over_nucleation``, ``model_error``), ``margin``, ``window`` and
        ``min_neighbours``, as :func:`load_table` returns; the shipped table's otherwise.

    Returns
    -------
    float
        The declared model error (dimensionless); ``inf`` where none is declared.
    """
    table = table if table is not None else load_table()
    if _reach(dip, width_over_nucleation, table)[0]:
        return math.inf
    reach = width_over_nucleation * math.exp(table["window"])
    return table["margin"] * max(row["model_error"] for row in table["faults"] if row["width_over_nucleation"] <= reach)


def why_undeclared(dip: float, width_over_nucleation: float, table: dict | None = None) -> str:
    """Why :func:`declared` declares nothing for this fault, as a clause ("" where it declares an error): its dip
    or W / h* outside the measured faults', or too few measured near its W / h*."""
    return _reach(dip, width_over_nucleation, table if table is not None else load_table())[0]


def _reach(dip: float, width_over_nucleation: float, table: dict) -> tuple[str, list]:
    """(why nothing is declared, "" where it is; the measured faults the declaration reads)."""
    faults = table["faults"]
    dips = [row["dip"] for row in faults]
    widths = [row["width_over_nucleation"] for row in faults]
    if not min(dips) <= dip <= max(dips):
        return f"its dip, {dip:g} degrees, lies outside the measured faults' {min(dips):g}-{max(dips):g} degrees", []
    if not min(widths) <= width_over_nucleation <= max(widths):
        return (f"its W / h*, {width_over_nucleation:.3g}, lies outside the measured faults' {min(widths):.3g}-"
                f"{max(widths):.3g}"), []
    near = neighbours(width_over_nucleation, faults, table["window"])
    if len(near) < table["min_neighbours"]:
        return (f"{len(near)} measured faults lie within a factor {math.exp(table['window']):.3g} of its W / h* "
                f"({width_over_nucleation:.3g}), and {table['min_neighbours']:g} are needed"), near
    return "", near
