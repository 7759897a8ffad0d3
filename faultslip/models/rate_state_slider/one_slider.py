"""One spring-block for a rate-and-state fault: its stiffness from the fault's geometry, and the calibration that
says how far the block stands from the 2-D fault (issue 42).

A one-slider scene states the seismogenic (velocity-weakening) width W, or, for the seed's section 5-2 reduction,
the elastic-zone width D. The block's stiffness is then

* ``K = c G / W`` with ``c`` the factor calibrated against a designed set of 2-D faults
  (``benchmarks/fault_2d_calibration.py``: the c whose worst model error over the set is smallest; 2 / pi would be
  the stiffness of a surface-breaking crack of width W under a uniform stress drop), or
* ``K = G / D``, the seed's reduction, named as such.

The calibration, ``data/fault_2d_model_error.json``, holds both: for each reduction, the largest model error
(times a safety factor) at each W / h* of the designed set, and its coverage on faults held out of it.
"""

from __future__ import annotations

from faultslip.fault.one_slider_error import CALIBRATION_FILE, DESCRIPTIONS, REDUCTIONS, load_calibration
from faultslip.io.resources import bundled_dir, read_bundled_table

HIERARCHY_FILE = "fault_2d_hierarchy.json"
__all__ = ["CALIBRATION_FILE", "DESCRIPTIONS", "HIERARCHY_FILE", "REDUCTIONS", "load_calibration", "load_hierarchy",
           "stiffness_factor"]


def stiffness_factor() -> float:
    """c of the geometric stiffness K = c G / W, from the shipped calibration (dimensionless).

    Returns
    -------
    float
        The factor whose worst model error over the designed 2-D faults is smallest.
    """
    return float(load_calibration()["geometric"]["stiffness_factor"])


def load_hierarchy() -> dict | None:
    """Speed against accuracy on SEAS BP1 (``data/fault_2d_hierarchy.json``, benchmarks/hierarchy_chart.py).

    Returns
    -------
    dict or None
        ``points`` (each method's cost in s, error against the converged 2-D answer and declared error), or None
        where the file is not installed.
    """
    if not (bundled_dir("data") / HIERARCHY_FILE).is_file():
        return None
    return read_bundled_table(HIERARCHY_FILE, "the speed-accuracy chart's data", "benchmarks/hierarchy_chart.py")
