"""The classroom stick-slip experiment: a phone pulled across a table through a rubber band, recorded with
phyphox (or any accelerometer), analysed from its acceleration alone.

**Reading.** A phyphox CSV export ("Acceleration without g" or "Acceleration with g", any of its CSV
flavours: comma with decimal point, semicolon with decimal comma, or tab) has the columns
``"Time (s)"``, ``"Linear Acceleration x (m/s^2)"`` (or ``"Acceleration x (m/s^2)"``), y, z and
``"Absolute acceleration (m/s^2)"``. A generic accelerometer CSV has ``time (unit)`` and one or more
acceleration columns with units (``a (m/s^2)``, or ``ax (g_0)`` in standard gravities). The pulling
axis is the one named, or the one with the largest spread; its median (gravity's share of a tilted
phone, sensor offset) is removed.

**Stick and slip.** While the phone sticks, its acceleration is sensor noise; a slip is a burst. A
sample belongs to a slip where ``|a|`` exceeds ``threshold`` times the robust noise level (1.4826 times
the median absolute deviation). A slip accelerates and then decelerates, quiet for a moment at its zero
crossing, so a burst joins the one before it when the gap is shorter than that burst (or ``merge_time``).

**The friction estimate.** During a slip the spring-slider (seed 003 eqs. 2-5 to 2-10, undamped,
constant kinetic friction) has a(t) = (mu_s - mu_k) g cos(omega t): the acceleration at break-away is
(mu_s - mu_k) g, and the slip lasts about pi / omega. So each slip gives the friction drop
mu_s - mu_k = a_peak / g, the band's omega = pi / t_slip (stiffness per mass, k/m = omega^2), and the
slip distance (the integral of the velocity, itself integrated from rest with its drift removed).
The same model predicts the slip distance 2 (mu_s - mu_k) g / omega^2, a check on the record. The
levels mu_s and mu_k themselves need the band's force (a spring scale); acceleration alone gives
their difference, and the report says so.
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from faultslip.dynamics.spring_slider.simulate import simulate
from faultslip.dynamics.spring_slider.slider import SliderSystem
from faultslip.errors import InputError
from faultslip.friction.laws import ConstantKinetic, ConstantStatic
from faultslip.io import gate
from faultslip.io.atomic import write_text_atomic
from faultslip.io.report import Report
from faultslip.io.resources import split_header
from faultslip.units import STANDARD_GRAVITY, takes_units, unit_factor
from faultslip.datasets import ToXarray

AXES = ("x", "y", "z")


@dataclass
class AccelerometerRecord(ToXarray):
    #: the units and dimensions of to_xarray() (faultslip.datasets.ToXarray)
    UNITS = {'time': 's', 'acceleration': 'm/s2'}
    DIMENSIONS = {'time': 'time'}
    time: np.ndarray  # s, from the first sample
    acceleration: dict  # axis name -> m/s^2
    source: str
    kind: str  # "phyphox" or "generic"


def _dialect(text: str) -> tuple[str, bool]:
    """(delimiter, decimal comma) of a phyphox export: ',' with '.', ';' with ',', or tab."""
    first = text.splitlines()[0] if text else ""
    if "\t" in first:
        return "\t", "," in text.splitlines()[1] if len(text.splitlines()) > 1 else False
    if ";" in first:
        return ";", True
    return ",", False


#: Fastest sampling of a phone's accelerometer that a record may claim (phones give 100-500 Hz).
MAX_PHONE_RATE = 5000.0


def is_accelerometer_csv(path) -> bool:
    """Whether a CSV's header is an accelerometer's (a time column and acceleration columns, no displacement)."""
    try:
        first = gate.read_head(path, "record", "table").decode("utf-8-sig", errors="replace").splitlines()[0]
    except (InputError, IndexError):
        return False
    names = [split_header(cell.strip().strip('"'))[0].lower() for cell in first.replace(";", ",").replace("\t", ",")
             .split(",")]
    return bool(names) and names[0] in ("time", "t") and "displacement" not in names and any(
        "acceleration" in name or name in ("a", "ax", "ay", "az") for name in names[1:])


def read_accelerometer(path) -> AccelerometerRecord:
    """A phyphox export or a generic accelerometer CSV, in SI; one sentence for anything malformed.

    Parameters
    ----------
    path : str or path
        A CSV file.

    Returns
    -------
    AccelerometerRecord
        Time (s) and acceleration (m/s^2) by axis.
    """
    label = f"accelerometer record {Path(path).name}"
    text = gate.read_text(path, "accelerometer record", "table")
    path = Path(path)
    if not text.strip():
        raise InputError(f"{label} is empty")
    delimiter, decimal_comma = _dialect(text)
    try:
        rows = list(csv.reader(io.StringIO(text), delimiter=delimiter))
    except csv.Error as exc:
        raise InputError(f"{label} is not valid CSV ({exc})") from None
    header = [split_header(cell) for cell in rows[0]]
    names = [name for name, _ in header]
    repeated = gate.repeated_names(names)
    if repeated:
        raise InputError(f"{label}: the column {repeated[0]!r} appears twice in the header")
    phyphox = names[0] == "Time" and any(name.endswith(" x") and "cceleration" in name for name in names)
    body = [row for row in rows[1:] if any(cell.strip() for cell in row)]
    if len(body) < 20:
        raise InputError(f"{label} has {len(body)} samples; a stick-slip record needs at least 20")
    columns = {}
    for index, (name, unit) in enumerate(header):
        values = []
        for line, row in enumerate(body, start=2):
            if len(row) != len(header):
                raise InputError(f"{label}, row {line}: {len(row)} fields, expected {len(header)}")
            cell = row[index].strip().replace(",", ".") if decimal_comma else row[index].strip()
            try:
                values.append(float(cell))
            except ValueError:
                raise InputError(f"{label}, row {line}: {name} {row[index]!r} is not a number") from None
        columns[name] = (np.array(values), unit)
    time_name = names[0]
    if time_name.lower() not in ("time", "t"):
        raise InputError(f"{label}: the first column must be the time, e.g. 'Time (s)', got {rows[0][0]!r}")
    time_values, time_unit = columns.pop(time_name)
    if time_unit is None:
        raise InputError(f"{label}: the time column needs a unit, e.g. 'Time (s)'")
    time_values = time_values * unit_factor(time_unit, "time", f"{label}, time")
    if not np.all(np.isfinite(time_values)) or np.any(np.diff(time_values) <= 0):
        raise InputError(f"{label}: time must be finite and increase strictly")
    rate = 1.0 / float(np.median(np.diff(time_values)))
    if rate > MAX_PHONE_RATE:
        raise InputError(f"{label}: read with its time in {time_unit!r}, it samples at {rate:.3g} Hz, beyond any "
                         f"phone's accelerometer ({MAX_PHONE_RATE:g} Hz at most); check the time column's unit")
    acceleration = {}
    for name, (values, unit) in columns.items():
        lowered = name.lower()
        if lowered.startswith("absolute"):
            continue  # |a| mixes the axes: not a direction
        if "accel" not in lowered and lowered not in ("a", "ax", "ay", "az"):
            continue
        if unit is None:
            raise InputError(f"{label}: column {name!r} needs a unit, e.g. '{name} (m/s^2)'")
        si = values * unit_factor(unit, "acceleration", f"{label}, {name}")
        if not np.all(np.isfinite(si)) or np.max(np.abs(si)) > 1e6:  # a phone's sensor reads ~160 m/s^2 at most
            raise InputError(f"{label}: column {name!r} has values that are not finite or beyond 1e6 m/s^2")
        axis = lowered[-1] if lowered[-1] in AXES and (lowered.endswith(" " + lowered[-1]) or lowered in
                                                       ("ax", "ay", "az")) else lowered
        acceleration[axis] = si
    if not acceleration:
        raise InputError(f"{label} has no acceleration column (phyphox 'Linear Acceleration x (m/s^2)', or "
                         "'a (m/s^2)')")
    return AccelerometerRecord(time_values - time_values[0], acceleration, path.name,
                               "phyphox" if phyphox else "generic")


@dataclass
class ClassroomAnalysis(ToXarray):
    #: the units and dimensions of to_xarray() (faultslip.datasets.ToXarray)
    UNITS = {'noise': 'm/s2', 'starts': 's', 'durations': 's', 'peak_acceleration': 'm/s2', 'slip_distance': 'm', 'peak_speed': 'm/s', 'omega': 'rad/s', 'pull_speed': 'm/s'}
    DIMENSIONS = {'starts': 'slip', 'durations': 'slip', 'peak_acceleration': 'slip', 'slip_distance': 'slip', 'peak_speed': 'slip', 'omega': 'slip', 'pull_speed': 'slip'}
    record: AccelerometerRecord
    axis: str
    noise: float  # m/s^2
    starts: np.ndarray  # s
    durations: np.ndarray  # s
    peak_acceleration: np.ndarray  # m/s^2, at break-away (along the pull)
    slip_distance: np.ndarray  # m
    peak_speed: np.ndarray  # m/s
    omega: np.ndarray  # 1/s, fitted
    pull_speed: np.ndarray  # m/s, fitted
    notes: list = field(default_factory=list)

    @property
    def friction_drop(self) -> np.ndarray:
        return self.peak_acceleration / STANDARD_GRAVITY

    @property
    def angular_frequency(self) -> np.ndarray:
        return self.omega

    @property
    def model_distance(self) -> np.ndarray:
        """The fitted slider's slip: the integral of u(t) = V (1 - cos w t) + (D/w) sin w t up to its stop,
        w t* = 2 pi - 2 atan(D / (w V)), with D = (mu_s - mu_k) g."""
        drop, omega, pull = self.peak_acceleration, self.omega, np.maximum(self.pull_speed, 1e-12)
        stop = (2 * np.pi - 2 * np.arctan(drop / (omega * pull))) / omega
        return pull * (stop - np.sin(omega * stop) / omega) + drop / omega ** 2 * (1 - np.cos(omega * stop))

    def report(self, title: str = "faultslip classroom: stick-slip analysis") -> Report:
        r = Report(title)
        r.add("format", self.record.kind).add("axis", self.axis, label="pulling axis")
        r.add("samples", int(self.record.time.size)).add("duration", float(self.record.time[-1]), "s")
        r.add("noise", self.noise, "m/s^2", label="sensor noise (robust)")
        r.add("events", int(self.starts.size), label="slip events")
        if self.starts.size:
            median = lambda values: float(np.median(values))  # noqa: E731
            r.add("friction_drop", median(self.friction_drop), label="mu_s - mu_k = a at break-away / g (median)")
            r.add("friction_drop_range", [float(self.friction_drop.min()), float(self.friction_drop.max())],
                  label="mu_s - mu_k, smallest and largest")
            r.add("slip_duration", median(self.durations), "s", label="slip duration (median)")
            r.add("angular_frequency", median(self.angular_frequency), "1/s", label="omega of the band (fitted)")
            r.add("pull_speed", median(self.pull_speed), "m/s", also=("mm/s",), label="pulling speed V (fitted)")
            r.add("stiffness_per_mass", median(self.angular_frequency) ** 2, "1/s^2", label="band k / m = omega^2")
            r.add("slip_distance", median(self.slip_distance), "m", also=("mm",), label="slip distance (median)")
            r.add("slip_distance_model", median(self.model_distance), "m", also=("mm",),
                  label="slip distance of the fitted slider (model)")
            r.add("peak_speed", median(self.peak_speed), "m/s", label="peak speed (median)")
        if self.starts.size > 2:
            intervals = np.diff(self.starts)
            r.add("recurrence", float(intervals.mean()), "s", label="mean interval between slips")
            r.add("recurrence_cv", float(intervals.std(ddof=1) / intervals.mean()), label="coefficient of variation")
        for note in self.notes:
            r.note(note)
        r.note("mu_s and mu_k themselves need the band's force (a spring scale); the acceleration gives their "
               "difference")
        return r


@takes_units(merge_time="time")
def analyse(record: AccelerometerRecord, axis: str | None = None, threshold: float = 6.0,
            merge_time: float = 0.05) -> ClassroomAnalysis:
    """Stick and slip phases, the friction drop and the event statistics of a record (see the module).

    Parameters
    ----------
    record : AccelerometerRecord
        :func:`read_accelerometer`'s record (m/s^2 against s).
    axis : str, optional
        x, y or z: the axis along the pull (the one with the largest swing otherwise).
    threshold : float
        A slip is where ``|a|`` exceeds this many times the record's noise level (dimensionless).
    merge_time : float
        Slips closer than this (s) are one.

    Returns
    -------
    ClassroomAnalysis
        The stick and slip phases, the friction drops (dimensionless) and the event statistics, with ``report()``.
    """
    if axis is not None and axis not in record.acceleration:
        raise InputError(f"axis {axis!r} is not in the record (it has {', '.join(record.acceleration)})")
    if not threshold > 1 or not merge_time >= 0:
        raise InputError("the threshold must exceed 1 (times the noise) and the merge time must not be negative")
    notes = []
    if axis is None:
        axis = max(record.acceleration, key=lambda name: float(np.std(record.acceleration[name])))
        notes.append(f"pulling axis {axis}: the largest spread of acceleration")
    signal = record.acceleration[axis] - float(np.median(record.acceleration[axis]))
    time = record.time
    noise = 1.4826 * float(np.median(np.abs(signal - np.median(signal))))
    if noise <= 0:
        noise = float(np.std(signal)) or 1e-12
    loud = np.abs(signal) > threshold * noise
    events = []
    index = 0
    while index < loud.size:
        if not loud[index]:
            index += 1
            continue
        start = index
        end = index
        while True:
            # a slip accelerates, then decelerates: the quiet gap at its zero crossing is shorter than
            # the burst so far, while a stick is longer (rule: merge while the gap is within both)
            reach = max(merge_time, time[end] - time[start])
            nxt = end + 1
            while nxt < loud.size and not loud[nxt] and time[nxt] - time[end] <= reach:
                nxt += 1
            if nxt < loud.size and loud[nxt]:
                end = nxt
                continue
            break
        events.append((start, end))
        index = end + 1
    # the pull's direction: the sign of the acceleration at break-away, the same for most events
    signs = [np.sign(signal[s]) for s, _ in events]
    direction = float(np.sign(np.sum(signs))) if signs else 1.0
    starts, durations, peaks, distances, speeds, omegas, pulls = [], [], [], [], [], [], []
    for start, end in events:
        if start == 0 or end >= signal.size - 1:
            notes.append("an event touching the record's start or end was left out")
            continue
        window = slice(start - 1, end + 2)
        t, a = time[window], direction * signal[window]
        velocity = np.concatenate([[0.0], np.cumsum(0.5 * (a[1:] + a[:-1]) * np.diff(t))])
        velocity -= velocity[-1] * (t - t[0]) / (t[-1] - t[0])  # at rest before and after: remove the drift
        starts.append(float(time[start]))
        durations.append(float(time[end] - time[start]))
        drop, omega, pull = fit_slip(time[start:end + 1] - 0.5 * (time[start - 1] + time[start]),
                                     direction * signal[start:end + 1])
        if not (drop > 0 and pull > 0):  # the slider's law gives both positive: this burst is not a slip
            notes.append(f"the burst at {time[start]:.3g} s does not follow the slider's law (fitted drop "
                         f"{drop:.3g} m/s^2, pull speed {pull:.3g} m/s); left out")
            starts.pop()
            durations.pop()
            continue
        peaks.append(drop)
        omegas.append(omega)
        pulls.append(pull)
        distances.append(float(np.sum(0.5 * (velocity[1:] + velocity[:-1]) * np.diff(t))))
        speeds.append(float(np.max(velocity)))
    if not starts:
        notes.append("no slip stood out of the noise: a steady pull (no stick-slip), or a threshold too high")
    return ClassroomAnalysis(record, axis, noise, np.array(starts), np.array(durations), np.array(peaks),
                             np.array(distances), np.array(speeds), np.array(omegas), np.array(pulls), notes)


def fit_slip(t, acceleration) -> tuple[float, float, float]:
    """(a at break-away, omega, pull speed) of one slip by least squares on the slider's own law: with the
    band pulled at V, the phone's acceleration from break-away (t = 0) is
    a(t) = (mu_s - mu_k) g cos(omega t) + V omega sin(omega t) (seed 003 eqs. 2-5 to 2-10, undamped).
    omega is searched on a grid (from the slip's length: between pi/2 and 2 pi over its duration), the two
    amplitudes solved linearly at each."""
    span = float(t[-1] - t[0]) + 1e-12
    step = float(np.median(np.diff(t))) if t.size > 1 else span
    best = None
    # break-away lies between the last quiet sample and the first loud one: its time is searched too
    for shift in np.linspace(-0.5 * step, 0.5 * step, 11):
        since = t - shift
        for omega in np.linspace(0.5 * math.pi / span, 2.0 * math.pi / span, 200):
            basis = np.column_stack([np.cos(omega * since), np.sin(omega * since)])
            coefficients, *_ = np.linalg.lstsq(basis, acceleration, rcond=None)
            error = float(np.sum((basis @ coefficients - acceleration) ** 2))
            if best is None or error < best[0]:
                best = (error, float(coefficients[0]), float(omega), float(coefficients[1]) / float(omega))
    return best[1], best[2], best[3]


def synthetic_record(mass: float = 0.2, stiffness: float = 8.0, static: float = 0.45, kinetic: float = 0.35,
                     pull_speed: float = 0.02, rate: float = 100.0, duration: float = 20.0, noise: float = 0.03,
                     seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """A phone on a table pulled through a band (seed 003's slider, undamped, constant friction levels),
    sampled like phyphox at ``rate`` Hz with Gaussian sensor noise: (time s, acceleration along the pull
    m/s^2). Synthetic: for the worked lesson and the tests."""
    system = SliderSystem(mass=mass, stiffness=stiffness, normal_load=mass * STANDARD_GRAVITY,
                          platform_speed=pull_speed, static_law=ConstantStatic(static),
                          kinetic_law=ConstantKinetic(kinetic), name="phone on a table")
    period = simulate(system, cycles=2)["period"].values[-1]
    data = simulate(system, cycles=int(duration / period) + 3, samples_per_slip=256)
    # the phone's acceleration over the table is -x'' = (K x - F_friction) / M (zero while it sticks)
    phone = (data["spring_force"].values - data["friction_force"].values) / mass
    sim_time = data["time"].values
    start = data["event_time"].values[0] - 0.5 * period  # begin in a stick, past the first loading
    times = np.arange(0.0, duration, 1.0 / rate)
    acceleration = np.interp(start + times, sim_time, phone)
    return times, acceleration + np.random.default_rng(seed).normal(0.0, noise, times.size)


def write_phyphox_csv(path, time, acceleration, axis: str = "y", decimal_comma: bool = False) -> None:
    """A record in phyphox's "Acceleration without g" CSV export: "Time (s)", "Linear Acceleration x/y/z
    (m/s^2)", "Absolute acceleration (m/s^2)"; the pull along ``axis``, the other axes zero."""
    columns = {name: np.zeros_like(acceleration) for name in AXES}
    columns[axis] = acceleration
    delimiter = ";" if decimal_comma else ","
    header = ['"Time (s)"'] + [f'"Linear Acceleration {name} (m/s^2)"' for name in AXES] + \
        ['"Absolute acceleration (m/s^2)"']
    lines = [delimiter.join(header)]
    absolute = np.sqrt(sum(values ** 2 for values in columns.values()))
    for i in range(time.size):
        cells = [f"{time[i]:.9E}"] + [f"{columns[name][i]:.9E}" for name in AXES] + [f"{absolute[i]:.9E}"]
        if decimal_comma:
            cells = [cell.replace(".", ",") for cell in cells]
        lines.append(delimiter.join(cells))
    write_text_atomic(path, "\n".join(lines) + "\n")
