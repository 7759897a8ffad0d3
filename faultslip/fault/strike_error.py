"""The 2-D rung's declared model error on a fault finite along strike, against the 3-D fault.

The 2-D fault reads the middle column of a 3-D scene (friction down dip) as a fault infinitely long along strike.
A finite velocity-weakening patch is stiffer (its stress drop is spread over a shorter rupture) and its ends creep
into it, so its recurrence and slip per event differ from the 2-D fault's, the more so the shorter the patch.
``benchmarks/fault_3d_model_error.py`` measures the difference on SEAS BP5-QD's fault (at 1/20 scale) for patches
of aspect L / W = 1 to 32, of widths W / h* near 1 to 2 and of three burials, and ships
``data/strike_model_error.json``: each measured cell's error times :data:`MARGIN`. Among the measured cells the
error falls as the patch lengthens, widens (W / h*) and deepens, so a measured cell shorter, narrower and shallower
than a fault bounds it, but only inside the measured region: a fault must also have a measured cell at least as long
and as wide (W / h*) whose 3-D run settled. Beyond it the order fails (wide, long patches, whose 3-D events break
only part of the patch, erred up to 117 % where a shorter, narrower cell bounded them at 86 %; the second wide draw
of the benchmark). A fault's declared error is the largest among the measured cells that bound it and lie nearest
below it in aspect; where none does (a patch shorter or narrower than every measured one, longer or wider than every
settled one, or a bounding cell whose 3-D run did not settle, even run four times as long: a crept patch, or a
sequence that never repeats) nothing is declared (infinite).
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
    along strike over its widest down dip), ``burial`` (its top's distance down dip, in the middle column, over
    that width) and ``width_over_nucleation`` (that width over h*)."""
    weakening = fault.grid(fault.b > fault.a)
    width = fault.seismogenic_width()
    column = weakening[fault.column(0.0)]
    top = float(np.argmax(column) * fault.element_size) if np.any(column) else math.nan
    return {"aspect_measured": fault.seismogenic_length() / width if width > 0 else math.nan,
            "burial": top / width if width > 0 else math.nan,
            "width_over_nucleation": width / fault.nucleation_size() if width > 0 else math.nan}


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
    surface = table.get("surface_rows", [])
    if not (isinstance(surface, list) and all(
            isinstance(row, dict) and all(isinstance(row.get(key), (int, float)) and not isinstance(row.get(key), bool)
                                          for key in ("aspect", "width_over_nucleation"))
            and (row.get("measured_error") is None or (isinstance(row["measured_error"], (int, float))
                                                       and row["measured_error"] >= 0)) for row in surface)):
        raise InputError(f"{TABLE_FILE}'s surface_rows lack aspect, W / h* and a non-negative measured_error; rerun "
                         "benchmarks/fault_3d_model_error.py")
    return table


def declared(aspect: float, rows: list | None = None, burial: float | None = None,
             width_over_nucleation: float | None = None) -> float:
    """The 2-D rung's declared model error (relative, the larger of recurrence and slip per event) on a fault whose
    weakening patch has aspect ``aspect`` (L / W), ``burial`` (top / W) and ``width_over_nucleation`` (W / h*).

    Parameters
    ----------
    aspect : float
        The patch's length along strike over its width down dip.
    rows : list of dict, optional
        ``aspect``, ``burial``, ``width_over_nucleation`` and ``model_error`` (already the bound) rows; the shipped
        table's otherwise.
    burial : float, optional
        The patch's top over its width; without it, the measured cells' burials are not required to bound it.
    width_over_nucleation : float, optional
        The patch's width over h*; likewise.

    Returns
    -------
    float
        The declared model error (dimensionless); ``inf`` where no measured cell bounds the fault, or where no
        settled cell is at least as long and as wide (the fault lies outside the measured region).
    """
    rows = rows if rows is not None else load_table()["rows"]
    if not math.isfinite(aspect):
        return math.inf
    slack = 1e-9
    # inside the measured region: a settled cell at least as long and as wide (no extrapolation past it)
    if not any(row["model_error"] is not None and float(row["aspect"]) >= aspect - slack
               and (width_over_nucleation is None or "width_over_nucleation" not in row
                    or float(row["width_over_nucleation"]) >= width_over_nucleation - slack) for row in rows):
        return math.inf

    def bounds(row) -> bool:
        return (float(row["aspect"]) <= aspect + slack
                and (burial is None or float(row["burial"]) <= burial + slack)
                and (width_over_nucleation is None or "width_over_nucleation" not in row
                     or float(row["width_over_nucleation"]) <= width_over_nucleation + slack))

    candidates = [row for row in rows if bounds(row)]
    if not candidates:
        return math.inf
    nearest = max(float(row["aspect"]) for row in candidates)
    errors = [row["model_error"] for row in candidates if abs(float(row["aspect"]) - nearest) <= slack]
    if any(error is None for error in errors):
        return math.inf
    return float(max(errors))


def declared_for(fault, rows: list | None = None) -> float:
    """:func:`declared` at a 3-D fault's own patch (:func:`groups_of`)."""
    groups = groups_of(fault)
    return declared(groups["aspect_measured"], rows, groups["burial"], groups["width_over_nucleation"])


def length_note(fault_length: float, width: float, burial: float, width_over_nucleation: float,
                rows: list | None = None, surface_rows: list | None = None) -> str:
    """What a 2-D scene's ``fault_length`` says of the rung above it: the 2-D answer is that of a fault infinitely
    long along strike, and a 3-D fault ``fault_length`` long differs from it by up to :func:`declared` at its patch
    (L / W, ``burial`` and ``width_over_nucleation``), where the measured cells bound it.

    Parameters
    ----------
    fault_length : float
        The scene's length along strike (m).
    width : float
        The velocity-weakening width down dip (m).
    burial, width_over_nucleation : float
        The patch's top over its width, and its width over h*.
    rows : list of dict, optional
        The measured cells; the shipped table's otherwise.
    surface_rows : list of dict, optional
        The surface-breaking patches measured (``aspect``, ``width_over_nucleation``, ``measured_error``), which
        bound nothing; the shipped table's otherwise. A surface-breaking fault's note quotes them.

    Returns
    -------
    str
        One sentence for the report.
    """
    if rows is None:
        rows, surface_rows = load_table()["rows"], load_table().get("surface_rows", [])
    aspect = fault_length / width if width > 0 else math.nan
    error = declared(aspect, rows, burial, width_over_nucleation)
    head = (f"the scene's fault_length ({fault_length / 1e3:g} km, L / W {aspect:.3g}) sets Mw only: the 2-D answer is "
            "that of a fault infinitely long along strike, ")
    if math.isfinite(error):
        return head + (f"and a 3-D fault that long would differ from it by up to {error:.0%} (the 2-D fault's "
                       "declared model error against 3-D at its L / W, W / h* and burial, "
                       "benchmarks/fault_3d_model_error.py); to include it, state the fault as a 3-D scene "
                       "(family fault_3d)")
    measured = [row for row in rows if row.get("model_error") is not None]

    def span(key: str) -> str:
        values = [float(row[key]) for row in measured if key in row]
        return f"{min(values):.2g}-{max(values):.2g}" if values else "none"

    text = head + (f"and its model error against a 3-D fault that long is not declared: the 3-D comparison "
                   f"(benchmarks/fault_3d_model_error.py) measured buried patches of L / W {span('aspect')}, burial "
                   f"{span('burial')} and W / h* {span('width_over_nucleation')}, and none bounds this one (burial "
                   f"{burial:.2g}, W / h* {width_over_nucleation:.2g}): a bound is no longer, no deeper and no wider "
                   "in W / h*, its 3-D run settled, and a settled cell at least as long and as wide must be measured")
    near = [row for row in (surface_rows or []) if row.get("measured_error") is not None
            and float(row["aspect"]) <= aspect * 1.5 and float(row["aspect"]) >= aspect / 1.5]
    if burial == 0 and near:
        errors = [float(row["measured_error"]) for row in near]
        ratios = [float(row["width_over_nucleation"]) for row in near]
        text += (f"; surface-breaking patches of L / W {min(float(r['aspect']) for r in near):.3g}-"
                 f"{max(float(r['aspect']) for r in near):.3g} and W / h* {min(ratios):.2g}-{max(ratios):.2g} were "
                 f"{min(errors):.0%}-{max(errors):.0%} off their 2-D fault, but a wider one can err more than a "
                 "narrower one, so each bounds no other fault (docs/fault_3d.md)")
    return text
