"""The SCEC SEAS benchmarks' ASCII files: on-fault station time series and slip profiles.

Layout (SEAS BP1 description, Erickson et al. 2020, and the community upload checker): ``#``
header lines naming the problem, code, element size, time steps and columns; one line of column
names; then one row per time. Station files are named ``fltst_dpXXX`` with XXX the depth in
hundreds of metres (``fltst_dp025`` at 2.5 km) and hold time (s), slip (m), log10 slip rate
(log10 m/s), shear stress (MPa) and log10 state (log10 s). The slip-profile file
``devol.dat`` holds a first row of depths (m) after two zeros, then time (s), the peak slip rate
(m/s) and the slip (m) at every depth. Numbers are written with 15 significant digits, as the
checker asks.
"""

from __future__ import annotations

import math
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

from faultslip.errors import InputError
from faultslip.io import gate
from faultslip.io.atomic import write_chunks_atomic

STATION_COLUMNS = ("t", "slip", "slip_rate", "shear_stress", "state")
#: BP3's on-fault columns (a dipping fault's normal stress changes with slip) and its surface stations' columns.
BP3_STATION_COLUMNS = ("t", "slip", "slip_rate", "shear_stress", "normal_stress", "state")
SURFACE_COLUMNS = ("t", "disp_1", "disp_2", "vel_1", "vel_2")


def station_file_name(depth: float) -> str:
    """``fltst_dp025`` for 2.5 km: the depth in hundreds of metres, three digits."""
    return f"fltst_dp{int(round(depth / 100.0)):03d}"


def surface_file_name(position: float) -> str:
    """``srfst_fn-16`` for 16 km on the footwall's side, ``srfst_fn+08`` for 8 km over the hanging wall, and
    ``srfst_fn-00`` / ``srfst_fn+00`` for the trace's two sides (-0.0 and 0.0): BP3's names, in km."""
    sign = "-" if math.copysign(1.0, position) < 0 else "+"
    return f"srfst_fn{sign}{int(round(abs(position) / 1e3)):02d}"


def _header(problem: str, code: str, version: str, element_size: float, extra: list) -> list:
    now = datetime.now(timezone.utc).strftime("%Y/%m/%d")
    return [f"# problem={problem}", "# author=faultslip", f"# date={now}", f"# code={code}",
            f"# code_version={version}", f"# element_size={element_size:g} m", *extra]


def _time_steps(time) -> list:
    steps = np.diff(time)
    return [f"# minimum_time_step={steps.min() if steps.size else 0.0:.15g}",
            f"# maximum_time_step={steps.max() if steps.size else 0.0:.15g}", f"# num_time_steps={time.size}"]


def write_station(path, time, slip, log10_slip_rate, shear_stress_mpa, log10_state, *, depth: float,
                  element_size: float, problem: str = "SEAS Benchmark BP1-QD", code: str = "faultslip",
                  version: str = "", normal_stress_mpa=None) -> None:
    """One station's time series in the SEAS layout, written atomically. With ``normal_stress_mpa`` (a dipping
    fault: SEAS BP3) the normal stress is the fifth column and ``depth`` a distance down dip."""
    time = np.asarray(time, float)
    bp3 = normal_stress_mpa is not None
    names = ["Slip (m)", "Slip rate (log10 m/s)", "Shear stress (MPa)"] + (["Normal stress (MPa)"] if bp3 else []) + [
        "State (log10 s)"]
    extra = [f"# location= on fault, {depth / 1e3:g} km {'down-dip distance' if bp3 else 'depth'}",
             *_time_steps(time), "# Column #1 = Time (s)",
             *[f"# Column #{i} = {name}" for i, name in enumerate(names, start=2)],
             "# The line below lists the names of the data fields:"]
    text = "\n".join(_header(problem, code, version, element_size, extra)
                     + [" ".join(BP3_STATION_COLUMNS if bp3 else STATION_COLUMNS)]) + "\n"
    columns = ((time, slip, log10_slip_rate, shear_stress_mpa, normal_stress_mpa, log10_state) if bp3
               else (time, slip, log10_slip_rate, shear_stress_mpa, log10_state))
    write_chunks_atomic(path, chunked_rows(text, lambda a, b: np.column_stack([np.asarray(c[a:b], float) for c in columns]),
                                      time.size))


def write_surface_station(path, time, displacement, velocity, *, position: float, element_size: float,
                          problem: str = "SEAS Benchmark BP3-QD", code: str = "faultslip", version: str = "") -> None:
    """One surface station's series in BP3's layout, written atomically: horizontal and vertical displacement (m)
    and velocity (m/s), ``displacement`` and ``velocity`` as (times, 2) with the vertical positive down."""
    time = np.asarray(time, float)
    side = "-" if math.copysign(1.0, position) < 0 else "+"
    extra = [f"# location= on surface, {side}{abs(position) / 1e3:g}km distance off-fault", *_time_steps(time),
             "# Column #1 = Time (s)", "# Column #2 = Displacement_1 (m)", "# Column #3 = Displacement_2 (m)",
             "# Column #4 = Velocity_1 (m/s)", "# Column #5 = Velocity_2 (m/s)",
             "# The line below lists the names of the data fields:"]
    text = "\n".join(_header(problem, code, version, element_size, extra) + [" ".join(SURFACE_COLUMNS)]) + "\n"
    write_chunks_atomic(path, chunked_rows(text, lambda a, b: np.column_stack(
        [time[a:b], np.asarray(displacement[a:b], float), np.asarray(velocity[a:b], float)]), time.size))


def chunked_rows(head: str, rows, count: int, block: int = 8192):
    """``head``, then ``rows(a, b)`` formatted with 15 significant digits, ``block`` rows at a time (a run's
    records are written without ever being held whole, as text or as numbers)."""
    yield head
    for start in range(0, count, block):
        values = np.asarray(rows(start, min(start + block, count)), float)
        # one %-format over the block: the same text as f"{v:.15g}" a value, three times faster
        line = " ".join(["%.15g"] * values.shape[1]) + "\n"
        yield (line * values.shape[0]) % tuple(values.ravel().tolist())


def write_profiles(path, time, max_slip_rate, slip, depths, *, element_size: float,
                   problem: str = "SEAS Benchmark BP1-QD", code: str = "faultslip", version: str = "",
                   quantity: str = "slip", down_dip: bool = False) -> None:
    """Slip profiles (rows: times; columns: depths) in the SEAS ``devol`` layout, written atomically; the maximum
    slip rate (given in m/s) is written as log10, as the SEAS writers do. ``quantity``: "slip" (m), or
    "shear_stress" or "normal_stress" (MPa, BP3's stress profiles); ``down_dip``: the first row holds distances
    down dip (BP3's x_d)."""
    depths = np.asarray(depths, float)
    label = {"slip": "Slip (m)", "shear_stress": "Shear stress (MPa)", "normal_stress": "Normal stress (MPa)"}
    if quantity not in label:
        raise InputError(f"a SEAS profile holds slip, shear_stress or normal_stress, not {quantity!r}")
    where = "Distance down dip (m)" if down_dip else "Depth (m)"
    extra = [f"# Row #1 = {where} with two zeros first", "# Column #1 = Time (s)",
             "# Column #2 = Max slip rate (log10 m/s)", f"# Columns #3-{depths.size + 2} = {label[quantity]}",
             "# The line below lists the names of the data fields:"]
    lines = _header(problem, code, version, element_size, extra) + (
        ["x_d", f"t max_slip_rate {quantity}"] if down_dip else [f"t max_slip_rate {quantity}"])
    lines.append(" ".join(f"{v:.15g}" for v in np.concatenate([[0.0, 0.0], depths])))
    with np.errstate(divide="ignore"):  # log10, as the SEAS writers give it (a rate of 0 is -inf)
        log10_rate = np.log10(np.asarray(max_slip_rate, float))
    time = np.asarray(time, float)
    # slip may be a run's RecordColumns on disk: read a block of rows at a time
    block = max(1, (1 << 20) // (8 * max(1, depths.size)))
    write_chunks_atomic(path, chunked_rows("\n".join(lines) + "\n", lambda a, b: np.column_stack(
        [time[a:b], log10_rate[a:b], np.asarray(slip[a:b], float)]), time.size, block))


def read_seas(path) -> tuple[dict, list, np.ndarray]:
    """(header fields, column names, rows) of a SEAS ASCII file; one sentence for anything malformed.

    Parameters
    ----------
    path : str or path
        A SEAS station or profile file.

    Returns
    -------
    tuple
        (header fields, column names, rows in the file's SI units).
    """
    label = f"SEAS file {Path(path).name}"
    text = gate.read_text(path, "SEAS file", "table")
    header, names, rows = {}, None, []
    for number, line in enumerate(text.splitlines(), start=1):
        stripped = line.strip()
        if not stripped:
            continue
        if stripped.startswith("#"):
            key, _, value = stripped[1:].partition("=")
            if value:
                header[key.strip()] = value.strip()
            continue
        if names is None:
            names = stripped.split()
            continue
        try:
            values = [float(v) for v in stripped.split()]
        except ValueError:
            if not rows and names == ["x_d"]:  # BP3's profiles name their fields on two lines: x_d, then t ...
                names.extend(stripped.split())
                continue
            raise InputError(f"{label}, line {number}: not a row of numbers") from None
        if rows and len(values) != len(rows[0]):
            raise InputError(f"{label}, line {number}: {len(values)} values where the rows above have {len(rows[0])}")
        if not all(math.isfinite(v) or math.isinf(v) for v in values):
            raise InputError(f"{label}, line {number}: a value is not a number")
        rows.append(values)
    if names is None or not rows:
        raise InputError(f"{label} has no data rows")
    return header, names, np.asarray(rows, float)
