"""A 3-D fault run's SEAS BP5-QD files (Jiang et al. 2022, sec. 2.4): on-fault station series, the maximum slip
rate and moment rate, rupture times of the first event, and slip and shear-stress profiles along two lines.

The rake is held fixed (slip along strike on BP5's fault): the second slip component is written as 0 and its rate
as 10^-20 m/s, as BP5's participants write a vanishing component; the headers say so. Shear stress is the
traction's component along the rake, tau_0 + K (delta - V_p t) - eta V, as the stations record it.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from faultslip.io.atomic import write_chunks_atomic, write_text_atomic
from faultslip.io.seas import chunked_rows, write_profiles

PROBLEM = "SEAS Benchmark BP5-QD"
#: log10 of the slip rate written for the component the fixed rake leaves still.
STILL = -20.0
STATION_COLUMNS = ("t", "slip_2", "slip_3", "slip_rate_2", "slip_rate_3", "shear_stress_2", "shear_stress_3", "state")
#: Each column as BP5's files name it, with its unit.
COLUMN_LABELS = ("Time (s)", "Slip_2 (m)", "Slip_3 (m)", "Slip_rate_2 (log10 m/s)", "Slip_rate_3 (log10 m/s)",
                 "Shear_stress_2 (MPa)", "Shear_stress_3 (MPa)", "State (log10 s)")


def station_name(along: float, down: float) -> str:
    """BP5's file name of the station ``along`` strike and ``down`` dip (m): fltst_strk-36dp+00."""
    return f"fltst_strk{round(along / 1e3):+03d}dp{round(down / 1e3):+03d}.dat"


def _header(code_version: str, element_size: float, lines: list) -> str:
    head = ["# This is the file header:", f"# problem={PROBLEM}", "# code=faultslip", f"# version={code_version}",
            f"# element_size={element_size:g} m",
            "# the rake is held fixed along strike: slip_3 is 0 and slip_rate_3 is written as -20 (log10 m/s)"]
    return "\n".join(head + lines) + "\n"


def write_stations(run, folder: Path, version: str) -> list:
    """One file per station (BP5's eight columns), a block of rows at a time."""
    written = []
    fault = run.fault
    recorder_positions = run.station_positions
    time = np.asarray(run.station_time, float)
    for k, (along, down) in enumerate(recorder_positions):
        columns = [f"# Column #{i} = {label}" for i, label in enumerate(COLUMN_LABELS, start=1)]
        text = _header(version, fault.element_size, [f"# location= on fault, {along / 1e3:g} km along strike, "
                                                     f"{down / 1e3:g} km down dip", *columns,
                                                     "# The line below lists the names of the data fields:",
                                                     " ".join(STATION_COLUMNS)])

        def rows(a, b, k=k):
            count = b - a
            return np.column_stack([time[a:b], np.asarray(run.stations["slip"][a:b, k], float), np.zeros(count),
                                    np.asarray(run.stations["log10_slip_rate"][a:b, k], float),
                                    np.full(count, STILL),
                                    np.asarray(run.stations["shear_stress"][a:b, k], float) / 1e6, np.zeros(count),
                                    np.asarray(run.stations["log10_state"][a:b, k], float)])

        path = folder / station_name(along, down)
        write_chunks_atomic(path, chunked_rows(text, rows, time.size))
        written.append(path)
    return written


def global_series(run) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(time, log10 of the peak slip rate, moment rate G sum(V) h^2) at the recorded profiles."""
    fault = run.fault
    time = np.asarray(run.profile_time, float)
    moment_rate = np.empty(time.size)
    for start in range(0, time.size, 256):
        rates = 10.0 ** np.asarray(run.profile_log10_slip_rate[start:start + 256], float)
        moment_rate[start:start + 256] = fault.shear_modulus * rates.sum(axis=1) * fault.element_size ** 2
    return time, np.log10(np.asarray(run.profile_max_speed, float)), moment_rate


def rupture_times(run, event: int = 0, threshold: float = -3.0) -> np.ndarray:
    """Each square's rupture time in event ``event`` (s): when its slip rate first reaches 10^threshold m/s between
    the event's start and end, interpolated in log10 slip rate between the recorded profiles; NaN where it never
    does."""
    start, end = float(run.events["start"][event]), float(run.events["end"][event])
    time = np.asarray(run.profile_time, float)
    rows = np.flatnonzero((time >= start - 1e-9) & (time <= end + 1e-9))
    found = np.full(run.fault.count, np.nan)
    if rows.size == 0:
        return found
    previous_rate = np.asarray(run.profile_log10_slip_rate[rows[0]], float)
    previous_time = time[rows[0]]
    found[previous_rate >= threshold] = previous_time
    for row in rows[1:]:
        rate = np.asarray(run.profile_log10_slip_rate[row], float)
        crossing = np.isnan(found) & (rate >= threshold)
        fraction = (threshold - previous_rate[crossing]) / (rate[crossing] - previous_rate[crossing])
        found[crossing] = previous_time + np.clip(fraction, 0.0, 1.0) * (time[row] - previous_time)
        previous_rate, previous_time = rate, time[row]
    return found


def write_bp5(run, folder: Path, version: str) -> list:
    """Every BP5 file of ``run`` in ``folder``; the paths written."""
    fault = run.fault
    written = write_stations(run, folder, version)
    time, log_peak, moment_rate = global_series(run)
    text = _header(version, fault.element_size, ["# Column #1 = Time (s)", "# Column #2 = Max slip rate (log10 m/s)",
                                                 "# Column #3 = Moment rate (N-m/s)",
                                                 "# The line below lists the names of the data fields:",
                                                 "t max_slip_rate moment_rate"])
    rows = np.column_stack([time, log_peak, moment_rate])
    path = folder / "global.dat"
    write_text_atomic(path, text + "".join(f"{t:.16e} {v:.8e} {m:.8e}\n" for t, v, m in rows))
    written.append(path)
    if run.event_count:
        times = rupture_times(run, 0) - float(run.events["start"][0])
        keep = np.isfinite(times)
        text = _header(version, fault.element_size, ["# rupture time of the first event: when the slip rate first "
                                                     "reaches 1 mm/s, from the event's start",
                                                     "# Column #1 = x2 (m)", "# Column #2 = x3 (m)",
                                                     "# Column #3 = t (s)", "x2 x3 t"])
        path = folder / "rupture.dat"
        write_text_atomic(path, text + "".join(f"{x:.6e} {z:.6e} {t:.8e}\n" for x, z, t in zip(
            fault.strike_position[keep], fault.depth[keep], times[keep])))
        written.append(path)
    middle_column = fault.column(0.0)
    dip_line = np.arange(fault.dip_count) + middle_column * fault.dip_count
    row = int(np.clip(np.round(10e3 / fault.element_size - 0.5), 0, fault.dip_count - 1))
    strike_line = np.arange(fault.strike_count) * fault.dip_count + row
    for name, elements, positions, what in (
            ("slip_2_depth.dat", dip_line, fault.depth[dip_line], "down dip at x2 = 0"),
            ("slip_2_strike.dat", strike_line, fault.strike_position[strike_line],
             f"along strike at x3 = {fault.depth[row] / 1e3:g} km")):
        path = folder / name
        write_profiles(path, run.profile_time, run.profile_max_speed, _Columns(run.profiles, elements), positions,
                       element_size=fault.element_size, problem=f"{PROBLEM}: slip_2 {what}", code="faultslip",
                       version=version)
        written.append(path)
    return written


class _Columns:
    """Rows of a profile record restricted to some elements, read a block at a time."""

    def __init__(self, values, elements):
        self.values, self.elements = values, elements
        self.shape = (values.shape[0], elements.size)

    def __getitem__(self, rows):
        return np.asarray(self.values[rows], float)[..., self.elements]

    def __len__(self):
        return self.shape[0]
