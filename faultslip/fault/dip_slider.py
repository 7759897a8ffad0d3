"""The one slider on a dipping fault, calibrated against the 2-D fault in plane strain directly.

Read through the antiplane fault, the one slider's range on a dipping fault composes two errors: its own 95 %
range against the antiplane fault (:mod:`faultslip.fault.ladder`), then the antiplane rung's error against plane
strain (:mod:`faultslip.fault.dip_error`). Both hold, but together they are wide (a median factor of 7 from the
low end to the high on BP3's faults), and from a dip error of 1 no upper end is left.

Where a fault lies among the dipping faults ``benchmarks/dip_model_error.py`` measured in plane strain (SEAS
BP3's friction profile at dips 30-90 degrees, thrust and normal, D_c 6-24 mm, seismogenic depth 12-16 km), the
block derived from its profile (:func:`faultslip.fault.ladder.derived_block`) is corrected against plane strain
itself: ln(plane strain / block) is linear in ln W/h*, its square, cos(dip) and s cos(dip) (s = +1 thrust, -1
normal: the normal stress a dip-slip event changes, BP3 eq. 15, has the sign of s cos(dip) and vanishes on a
vertical fault), fitted by least squares over the measured faults (``benchmarks/dip_slider_calibration.py``).
The residual's spread is not one number over the box (its root mean square is 0.05 near W / h* 1.4 and 0.15 near
4, for the recurrence), so the 95 % range is the prediction interval (:mod:`faultslip.fault.regression`) with the
spread and t quantile of the measured faults within a factor exp(window) of the fault's W / h*, where at least
``min_neighbours`` were measured. Outside those faults' box the composed range stands.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from faultslip.errors import InputError
from faultslip.fault import regression
from faultslip.io.resources import read_bundled_table

TABLE_FILE = "dip_slider_calibration.json"
#: The groups the correction is linear in, after the constant (see :func:`features`).
FEATURES = ("log_width_over_nucleation", "log_width_over_nucleation_squared", "cos_dip", "sense_cos_dip")
#: What a fault's description must lie within, each over the measured faults' range: the dip, the groups that set
#: the block (W / h*, W / L_b, a / b) and the profile's shape about the zone (burial, the strengthening zone's depth
#: and its a - b over the zone's b - a). The ramp below the zone is not one of them: BP3's ramp is one length, so
#: its share of W moves with H as the strengthening depth's does, and its element count moves it at another
#: element size.
BOX = ("dip", "width_over_nucleation", "width_over_process_zone", "a_over_b", "burial", "strengthening_depth",
       "strengthening_ratio")
#: The quantities calibrated, and the block's answer each corrects. Not the surface slip: its correction missed 3
#: of 28 held-out faults (benchmarks/dip_slider_calibration.py), so a dipping fault's surface slip keeps the
#: antiplane calibration's range widened by the dip error.
QUANTITIES = {"recurrence": "recurrence", "mean_slip": "slip"}


@functools.lru_cache(maxsize=1)
def load_table() -> dict:
    """``data/dip_slider_calibration.json``, checked: per quantity of :data:`QUANTITIES` the regression
    (:func:`faultslip.fault.regression.least_squares`), the ``box`` of :data:`BOX` and ``senses``."""
    table = read_bundled_table(TABLE_FILE, "the one slider's calibration against plane strain",
                               "benchmarks/dip_slider_calibration.py")
    box = table.get("box")
    if not (all(_model(table.get(name)) for name in QUANTITIES)
            and isinstance(box, dict)
            and all(_numbers(box.get(name), 2) and box[name][0] <= box[name][1] for name in BOX)
            and isinstance(table.get("senses"), list) and set(table["senses"]) <= {"thrust", "normal"}
            and _number(table.get("window")) and table["window"] > 0
            and _number(table.get("min_neighbours")) and table["min_neighbours"] >= 3):
        raise InputError(f"{TABLE_FILE} lacks the regressions of {', '.join(QUANTITIES)} with their residuals, or "
                         f"the box of {', '.join(BOX)}, its senses, window and min_neighbours; rerun "
                         "benchmarks/dip_slider_calibration.py")
    return table


def _number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def _numbers(values, count: int) -> bool:
    return isinstance(values, list) and len(values) == count and all(_number(value) for value in values)


def _model(model) -> bool:
    """A regression as :func:`faultslip.fault.regression.least_squares` writes it, over :data:`FEATURES`."""
    size = len(FEATURES) + 1
    return (isinstance(model, dict) and _numbers(model.get("coefficients"), size)
            and isinstance(model.get("inverse_gram"), list) and len(model["inverse_gram"]) == size
            and all(_numbers(row, size) for row in model["inverse_gram"])
            and all(_number(model.get(key)) and model[key] >= 0 for key in ("residual_sd", "t_quantile", "faults"))
            and _number(model.get("median_bias_corrected"))
            and isinstance(model.get("residual_points"), list)
            and all(_numbers(point, 2) for point in model["residual_points"]))


def sense_sign(sense: str) -> float:
    """s: +1 on a thrust, -1 on a normal fault (the sign of the normal stress change per unit slip times cos(dip))."""
    return 1.0 if sense == "thrust" else -1.0


def features(group: dict, dip: float, sense: str) -> np.ndarray:
    """The regression's row: 1, ln W/h*, (ln W/h*)^2, cos(dip), s cos(dip) (:func:`sense_sign`); dip in degrees."""
    ratio = math.log(group["width_over_nucleation"])
    cos_dip = math.cos(math.radians(dip))
    return np.array([1.0, ratio, ratio ** 2, cos_dip, sense_sign(sense) * cos_dip])


def box_values(group: dict, dip: float) -> dict:
    """The fault's values of :data:`BOX`, from its groups (:func:`faultslip.fault.ladder.groups`) and dip."""
    return {"dip": dip, "a_over_b": group["a"] / group["b"],
            **{name: group[name] for name in BOX if name not in ("dip", "a_over_b")}}


def box_of(groups_and_dips: list[tuple[dict, float]]) -> dict:
    """Each of :data:`BOX`'s range over the calibration faults (their groups and dips)."""
    values = [box_values(group, dip) for group, dip in groups_and_dips]
    return {name: [min(v[name] for v in values), max(v[name] for v in values)] for name in BOX}


def outside(group: dict, dip: float, sense: str, table: dict | None = None) -> list[str]:
    """Where a fault lies outside the calibration's box, as sentences (empty: inside)."""
    table = table or load_table()
    out = [f"{name} = {value:.4g} (calibrated {table['box'][name][0]:.4g} to {table['box'][name][1]:.4g})"
           for name, value in box_values(group, dip).items()
           if not table["box"][name][0] <= value <= table["box"][name][1]]
    if sense not in table["senses"] and dip != 90.0:
        out.append(f"a {sense} fault (calibrated: {', '.join(table['senses'])})")
    near = len(neighbourhood("recurrence", group["width_over_nucleation"], table))
    if not out and near < table["min_neighbours"]:
        out.append(f"{near} measured faults within a factor {math.exp(table['window']):.3g} of its W / h* "
                   f"{group['width_over_nucleation']:.3g} (a spread needs {table['min_neighbours']:g})")
    return out


def neighbourhood(quantity: str, width_over_nucleation: float, table: dict | None = None) -> list[float]:
    """The standardized residuals of ``quantity``'s calibration faults within a factor exp(window) of
    ``width_over_nucleation``: what the fault's range is as wide as."""
    table = table or load_table()
    centre = math.log(width_over_nucleation)
    return [residual for log_ratio, residual in table[quantity]["residual_points"]
            if abs(log_ratio - centre) <= table["window"]]


def predict(quantity: str, raw: float, group: dict, dip: float, sense: str, table: dict | None = None) -> dict | None:
    """The block's ``raw`` answer (s or m) for ``quantity`` corrected against plane strain, with its 95 % range
    (:func:`faultslip.fault.regression.corrected` with the spread of the calibration faults near the fault's
    W / h*: ``value``, ``low``, ``high``, ``half_width``); None where fewer than ``min_neighbours`` are near."""
    table = table or load_table()
    near = neighbourhood(quantity, group["width_over_nucleation"], table)
    if len(near) < table["min_neighbours"]:
        return None
    return regression.corrected(raw, features(group, dip, sense), table[quantity], regression.local_scale(near))


def fit(faults: list[dict], window: float, min_neighbours: int, level: float = 0.95) -> dict:
    """The calibration from measured faults, each with its ``group``, ``dip``, ``sense``, the block's ``raw``
    answer (``recurrence`` s, ``slip`` m) and the plane-strain answer ``plane_strain`` (``recurrence``,
    ``mean_slip``; a quantity None where it was not kept): per quantity ln(plane strain /
    block) regressed on :func:`features` over the faults that have it, each fault's ln W / h* and standardized
    residual (``residual_points``), and the box of them all; a range's spread is read within a factor
    exp(``window``) of a fault's W / h*, from at least ``min_neighbours`` faults."""
    table = {"window": window, "min_neighbours": min_neighbours}
    for quantity, block in QUANTITIES.items():
        having = [fault for fault in faults if fault["plane_strain"].get(quantity) is not None]
        model = regression.least_squares(
            np.array([features(fault["group"], fault["dip"], fault["sense"]) for fault in having]),
            [math.log(fault["plane_strain"][quantity] / fault["raw"][block]) for fault in having], level)
        model["residual_points"] = [[math.log(fault["group"]["width_over_nucleation"]), residual]
                                    for fault, residual in zip(having, model.pop("standardized_residuals"))]
        table[quantity] = model
    table["box"] = box_of([(fault["group"], fault["dip"]) for fault in faults])
    table["senses"] = sorted({fault["sense"] for fault in faults})
    return table
