"""Laboratory record analysis: friction from measured motion, stick/slip events, free-decay identification.

Seed 003 §3-2 (its eq. 3-2) and seed 000 ch. 3 recover the friction coefficient from the motion:

.. math:: \\mu(t) = \\frac{M\\ddot x + C\\dot x + K x}{W}

(C = 0 in the seed's lightly damped apparatus), or directly mu = F/W from a measured friction
force. The sliding speed is u = V - x', with x' from differentiating x or from integrating the
acceleration with a drift correction (x' = V during stick). Stick and slip phases are separated
by the sliding speed; each event gives static friction at break-away, kinetic friction (median
over the slip), peak-to-peak amplitude, period and stick time.

Free decay (seed 002 Appendix C): the log decrement of amplitudes N cycles apart and the damped
frequency give the decay constant Delta = ln(X_n / X_{n+N}) f_d / N, the damping ratio, and,
with the known stiffness, the mass M = K / omega_n^2 and the damping coefficient r = 2 M Delta.

Readers are pluggable: :func:`register_reader` adds a file format. CSV and netCDF are built in, and
miniSEED and SAC come through obspy (channels mapped by component code, :mod:`faultslip.io.waveforms`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

from faultslip.constants import STANDARD_GRAVITY
import numpy as np

from faultslip.errors import InputError
from faultslip.io.resources import check_input_file, open_netcdf, read_numeric_csv
from faultslip.io.waveforms import STREAM_SUFFIXES, channels_by_quantity, read_stream
from faultslip.units import takes_units, unit_factor
from faultslip.dynamics.spring_slider.exact_cycle import _Oscillator, exact_cycle
from faultslip.dynamics.spring_slider.simulate import _equilibrium, _stick_duration
from faultslip.io.report import Report
from faultslip.datasets import ToXarray

RECORD_COLUMNS = {"time": "time", "displacement": "length", "acceleration": "acceleration", "force": "force",
                  "velocity": "speed"}
_READERS = {}


@dataclass
class Record(ToXarray):
    """A time series of slider motion in SI (acceleration or friction force, or neither)."""
    #: the units and dimensions of to_xarray() (faultslip.datasets.ToXarray)
    UNITS = {'time': 's', 'displacement': 'm', 'acceleration': 'm/s2', 'force': 'N', 'velocity': 'm/s'}
    DIMENSIONS = {'time': 'time', 'displacement': 'time', 'acceleration': 'time', 'force': 'time', 'velocity': 'time'}

    time: np.ndarray
    displacement: np.ndarray
    acceleration: np.ndarray | None = None
    force: np.ndarray | None = None
    velocity: np.ndarray | None = None
    source: str = ""

    def __post_init__(self):
        for name in ("time", "displacement", "acceleration", "force", "velocity"):
            values = getattr(self, name)
            if values is not None and np.shape(values) != np.shape(self.time):
                raise InputError(f"record {self.source}: {name} has {np.size(values)} samples and time "
                                 f"{np.size(self.time)}; every column needs one value per time")
        if self.time.ndim != 1:
            raise InputError(f"record {self.source}: time must be one column of values")
        if self.time.size < 5:
            raise InputError(f"record {self.source or ''} has {self.time.size} samples; at least 5 are needed".replace("  ", " "))
        if np.any(np.diff(self.time) <= 0):
            raise InputError(f"record {self.source}: time must increase strictly")
        for name in ("time", "displacement", "acceleration", "force", "velocity"):
            values = getattr(self, name)
            if values is not None and not np.all(np.isfinite(values)):
                raise InputError(f"record {self.source}: {name} contains NaN or infinity "
                                 f"(sample {int(np.argmax(~np.isfinite(values)))})")


def register_reader(suffix: str, reader) -> None:
    """Make ``read_record`` accept files ending in ``suffix`` (``reader(path) -> Record``)."""
    _READERS[suffix.lower()] = reader


def read_record(path) -> Record:
    """A motion record from CSV (``name (unit)`` headers) or netCDF.

    Parameters
    ----------
    path : str or path
        The record.

    Returns
    -------
    Record
        Time (s) and displacement (m), with velocity (m/s) where recorded.
    """
    path = check_input_file(path, "record file")
    reader = _READERS.get(path.suffix.lower())
    if reader is None:
        raise InputError(f"record {path.name}: no reader for '{path.suffix}' files (known: {', '.join(sorted(_READERS))})")
    return reader(path)


def _si(values, unit, name, source):
    kind = RECORD_COLUMNS[name]
    if unit in (None, "") or not isinstance(unit, str):
        raise InputError(f"record {source}: column {name!r} needs a unit in its header, e.g. '{name} (s)'")
    factor = unit_factor(unit, kind, f"record {source}, column {name}")
    try:
        values = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"record {source}: column {name!r} is not numeric") from None
    with np.errstate(over="ignore", invalid="ignore"):
        return values * factor


def _read_csv(path: Path) -> Record:
    return _record_from_columns(read_numeric_csv(path, f"record {path.name}"), path.name)


def _read_netcdf(path: Path) -> Record:
    data = open_netcdf(path, "record")
    columns = {name: (data[name].values, data[name].attrs.get("units")) for name in list(data.data_vars) + list(data.coords)
               if name in RECORD_COLUMNS}
    return _record_from_columns(columns, path.name)


def _record_from_columns(columns, source):
    for name in columns:
        if name not in RECORD_COLUMNS:
            raise InputError(f"record {source}: unknown column {name!r} (allowed: {', '.join(RECORD_COLUMNS)})")
    for required in ("time", "displacement"):
        if required not in columns:
            raise InputError(f"record {source} needs a {required} column")
    si = {name: _si(values, unit, name, source) for name, (values, unit) in columns.items()}
    return Record(si["time"], si["displacement"], si.get("acceleration"), si.get("force"), si.get("velocity"), source)


def _read_stream(path: Path) -> Record:
    """miniSEED or SAC through obspy (faultslip.io.waveforms): channels by component code, D displacement
    (m), A acceleration (m/s^2), N force (N), V velocity (m/s); other components are ignored. A SAC file
    ``STEM.X.sac`` brings its siblings ``STEM.*.sac``, one channel each."""
    if path.suffix.lower() == ".sac":
        stem = path.name[: -len(".sac")].rsplit(".", 1)[0] if path.name.count(".") >= 2 else path.stem
        files = sorted(path.parent.glob(f"{stem}.*.sac")) or [path]
        stream = read_stream(files[0])
        for extra in files[1:]:
            stream += read_stream(extra)
    else:
        stream = read_stream(path)
    time, found = channels_by_quantity(stream, f"record {path.name}")
    if "displacement" not in found:
        raise InputError(f"record {path.name} has no displacement channel (component code D, in m)")
    return Record(time, found["displacement"], found.get("acceleration"), found.get("force"), found.get("velocity"),
                  path.name)


register_reader(".csv", _read_csv)
register_reader(".nc", _read_netcdf)
for _suffix in STREAM_SUFFIXES:
    register_reader(_suffix, _read_stream)


def sliding_velocity(record: Record, platform_speed: float, method: str = "auto"):
    """Slider velocity x'(t): differentiate x, or integrate x'' with a drift correction to x' = V in stick."""
    if record.velocity is not None and method in ("auto", "measured"):
        return record.velocity
    if method == "integrate" or (method == "auto" and record.acceleration is not None):
        if record.acceleration is None:
            raise InputError(f"record {record.source}: integrating needs an acceleration column")
        from scipy.integrate import cumulative_trapezoid  # heavy: imported where used

        raw = cumulative_trapezoid(record.acceleration, record.time, initial=0.0)
        quiet = np.abs(record.acceleration) <= 1e-3 * np.max(np.abs(record.acceleration))  # stick: x'' = 0
        if quiet.sum() >= 2:  # constant and drift chosen so that stick velocities equal V
            coefficients = np.polyfit(record.time[quiet], raw[quiet] - platform_speed, 1)
            return raw - np.polyval(coefficients, record.time)
        return raw + platform_speed - np.median(raw)
    if method not in ("auto", "differentiate"):
        raise InputError(f"velocity method must be auto, differentiate or integrate, got {method!r}")
    return np.gradient(record.displacement, record.time)


def friction_coefficient(record: Record, mass: float, stiffness: float, normal_load: float, dashpot: float = 0.0,
                         velocity=None):
    """mu(t) = (M x'' + C x' + K x) / W (seed 003 eq. 3-2 with C), or F / W from a force record."""
    if record.force is not None:
        return record.force / normal_load
    if record.acceleration is None:
        acceleration = np.gradient(np.gradient(record.displacement, record.time), record.time)
    else:
        acceleration = record.acceleration
    velocity = np.gradient(record.displacement, record.time) if velocity is None else velocity
    return (mass * acceleration + dashpot * velocity + stiffness * record.displacement) / normal_load


@dataclass
class RecordAnalysis(ToXarray):
    #: the units and dimensions of to_xarray() (faultslip.datasets.ToXarray)
    UNITS = {'time': 's', 'friction': '1', 'sliding_speed': 'm/s', 'slipping': '1', 'platform_speed': 'm/s'}
    DIMENSIONS = {'time': 'time', 'friction': 'time', 'sliding_speed': 'time', 'slipping': 'time'}
    time: np.ndarray
    friction: np.ndarray
    sliding_speed: np.ndarray
    slipping: np.ndarray
    platform_speed: float
    events: dict = field(default_factory=dict)  # name -> array, one value per complete cycle

    def summary(self) -> dict:
        return {name: float(np.median(values)) for name, values in self.events.items() if len(values)}

    def report(self, title="faultslip record analysis"):

        r = Report(title)
        r.add("platform_speed", self.platform_speed, "m/s", "platform speed V")
        r.add("events", int(len(self.events.get("break_time", []))), label="complete stick-slip cycles")
        units = {"static_friction": None, "kinetic_friction": None, "amplitude": "m", "period": "s", "stick_time": "s",
                 "slip_time": "s", "peak_sliding_speed": "m/s"}
        for name, value in self.summary().items():
            if name in units:
                r.add(name, value, units[name], f"{name.replace('_', ' ')} (median over cycles)")
        return r


@takes_units(mass="mass", stiffness="stiffness", normal_load="force", platform_speed="speed", dashpot="damping")
def analyze_record(record: Record, mass, stiffness, normal_load, platform_speed=None, dashpot=0.0,
                   velocity_method="auto", threshold=0.05) -> RecordAnalysis:
    """Friction, sliding speed, stick/slip phases and per-event quantities of a stick-slip record.

    ``platform_speed`` defaults to the median slider velocity (the slider moves with the platform
    most of the time). A sample slips when its sliding speed exceeds ``threshold`` times the
    largest sliding speed; only cycles between two break-aways count as complete events.

    Parameters
    ----------
    record : Record
        :func:`read_record`'s record (time in s, displacement in m).
    mass : float
        M (kg).
    stiffness : float
        K (N/m).
    normal_load : float
        W (N).
    platform_speed : float, optional
        V (m/s).
    dashpot : float
        Dashpot (N s/m).
    velocity_method : str
        auto, differentiate or integrate.
    threshold : float
        The fraction of the largest sliding speed above which a sample slips.

    Returns
    -------
    RecordAnalysis
        Friction (dimensionless), sliding speed (m/s), phases and per-event quantities, with ``report()``.
    """
    for value, name in ((mass, "mass"), (stiffness, "stiffness"), (normal_load, "normal load")):
        if not (np.isfinite(value) and value > 0):
            raise InputError(f"record analysis: {name} must be positive, got {value!r}")
    if platform_speed is None:
        platform_speed = float(np.median(np.gradient(record.displacement, record.time)))
        if platform_speed <= 0:
            raise InputError(f"record {record.source}: cannot infer the platform speed; give it")
    velocity = sliding_velocity(record, platform_speed, velocity_method)
    friction = friction_coefficient(record, mass, stiffness, normal_load, dashpot, velocity)
    sliding = platform_speed - velocity
    slipping = sliding > threshold * max(float(np.max(sliding)), platform_speed)
    starts = np.flatnonzero(slipping[1:] & ~slipping[:-1]) + 1
    ends = np.flatnonzero(~slipping[1:] & slipping[:-1]) + 1
    events = {key: [] for key in ("break_time", "static_friction", "kinetic_friction", "amplitude", "period",
                                  "stick_time", "slip_time", "peak_sliding_speed")}
    for k in range(len(starts) - 1):
        start, following = starts[k], starts[k + 1]
        end = ends[(ends > start) & (ends <= following)]
        if end.size == 0:
            continue
        end = int(end[0])
        previous_end = ends[ends < start]
        stick = slice(int(previous_end[-1]) if previous_end.size else 0, start + 1)
        peak = stick.start + int(np.argmax(friction[stick]))  # friction peaks at break-away, then drops
        events["break_time"].append(float(record.time[peak]))
        events["static_friction"].append(float(friction[peak]))
        interior = slice(start + 1, max(end - 1, start + 2))
        events["kinetic_friction"].append(float(np.median(friction[interior])))
        cycle = slice(start - 1 if start > 0 else 0, following)
        events["amplitude"].append(float(np.ptp(record.displacement[cycle])))
        events["period"].append(float(record.time[following] - record.time[start]))
        events["stick_time"].append(float(record.time[following] - record.time[end]))
        events["slip_time"].append(float(record.time[end] - record.time[start]))
        events["peak_sliding_speed"].append(float(np.max(sliding[start:end])))
    return RecordAnalysis(record.time, friction, sliding, slipping, platform_speed,
                          {key: np.array(values) for key, values in events.items()})


def hysteresis_figure(analysis: RecordAnalysis, title="Friction against sliding speed"):
    """mu against sliding speed: the loop a stick-slip cycle traces (seed 003 §3-2, seed 000 ch. 3)."""
    import matplotlib.pyplot as plt  # heavy: imported where used

    figure, (left, right) = plt.subplots(1, 2, figsize=(11, 4.4), constrained_layout=True)
    left.plot(analysis.sliding_speed * 1e3, analysis.friction, lw=0.8)
    left.set_xlabel("sliding speed V - x' (mm/s)")
    left.set_ylabel("friction coefficient μ")
    left.set_title(title, fontsize=10)
    left.grid(True, alpha=0.3)
    right.plot(analysis.time, analysis.friction, lw=0.8, color="C1")
    right.set_xlabel("time (s)")
    right.set_ylabel("friction coefficient μ")
    right.grid(True, alpha=0.3)
    return figure


@dataclass
class FreeDecay(ToXarray):
    """System identification from a free-decay record (seed 002 Appendix C)."""
    #: the units and dimensions of to_xarray() (faultslip.datasets.ToXarray)
    UNITS = {'decay_constant': '1/s', 'damped_frequency': 'rad/s', 'natural_frequency': 'rad/s', 'damping_ratio': '1', 'mass': 'kg', 'damping_coefficient': 'N s/m', 'stiffness': 'N/m'}

    decay_constant: float  # Delta = r / (2M), 1/s
    damped_frequency: float  # f_d, Hz
    natural_frequency: float  # omega_n, rad/s
    damping_ratio: float
    mass: float  # kg
    damping_coefficient: float  # r = 2 M Delta, N s/m
    stiffness: float  # N/m
    #: standard errors from a record's least-squares fit (None for the seed's hand numbers)
    standard_errors: dict | None = None

    def report(self, title="faultslip free-decay identification"):

        r = Report(title)
        r.add("decay_constant", self.decay_constant, "1/s", "decay constant Delta = r/(2M)")
        r.add("damped_frequency", self.damped_frequency, "Hz", "damped frequency f_d")
        if self.standard_errors:
            units = {"decay_constant": "1/s", "damped_frequency": "Hz", "mass": "kg", "damping_ratio": "1"}
            values = {"decay_constant": self.decay_constant, "damped_frequency": self.damped_frequency,
                      "mass": self.mass, "damping_ratio": self.damping_ratio}
            for name, error in self.standard_errors.items():
                label = f"standard error of {name.replace('_', ' ')} (least-squares fit of the record)"
                if error < FIT_RESOLUTION * abs(values[name]):  # the fit's own convergence, not the data's scatter
                    r.add(f"{name}_standard_error", BELOW_ROUND_OFF, label=label)
                else:
                    r.add(f"{name}_standard_error", error, units[name], label)
        r.add("natural_frequency", self.natural_frequency, "rad/s", "natural frequency omega_n")
        r.add("damping_ratio", self.damping_ratio, label="damping ratio zeta")
        r.add("stiffness", self.stiffness, "N/m", "stiffness k", also=("lbf/in",))
        r.add("mass", self.mass, "kg", "mass M = k / omega_n^2", also=("lb",))
        r.add("mass_weight", self.mass * STANDARD_GRAVITY, "N", "its weight M g", also=("lbf",))
        r.add("damping_coefficient", self.damping_coefficient, "N*s/m", "damping coefficient r = 2 M Delta",
              also=("lbf*s/in",))
        return r


#: curve_fit's (MINPACK lmdif's) default step tolerance: the fit stops once a step changes the parameters by
#: less than this relative amount, so a standard error below it times the value says nothing about the record
#: (a noiseless record's errors are round-off, and differ between machines and BLAS kernels by 2-3x).
FIT_RESOLUTION = 1.49012e-8
BELOW_ROUND_OFF = "below round-off"


@takes_units(damped_frequency="frequency", stiffness="stiffness")
def free_decay(amplitude_ratio: float, cycles: float, damped_frequency: float, stiffness: float) -> FreeDecay:
    """Identify decay constant, damping ratio, mass and damping coefficient (seed 002 Appendix C).

    X_n / X_{n+N} = exp(Delta N T_d) with T_d = 1/f_d, so Delta = ln(ratio) f_d / N;
    omega_n = sqrt(omega_d^2 + Delta^2), M = k / omega_n^2, r = 2 M Delta, zeta = Delta / omega_n.

    Parameters
    ----------
    amplitude_ratio : float
        X_n / X_{n+N}.
    cycles : float
        N.
    damped_frequency : float
        f_d (Hz).
    stiffness : float
        k (N/m).

    Returns
    -------
    FreeDecay
        Decay constant Delta (1/s), damping ratio, mass M (kg) and damping coefficient r (N s/m), with ``report()``.
    """
    if not amplitude_ratio > 1:
        raise InputError(f"free decay: the amplitude ratio must exceed 1 (amplitudes fall), got {amplitude_ratio}")
    for value, name in ((cycles, "cycles"), (damped_frequency, "frequency"), (stiffness, "stiffness")):
        if not value > 0:
            raise InputError(f"free decay: {name} must be positive, got {value}")
    delta = math.log(amplitude_ratio) * damped_frequency / cycles
    omega_d = 2 * math.pi * damped_frequency
    omega_n = math.hypot(omega_d, delta)
    mass = stiffness / omega_n**2
    return FreeDecay(delta, damped_frequency, omega_n, delta / omega_n, mass, 2 * mass * delta, stiffness)


@takes_units(stiffness="stiffness")
def free_decay_from_record(record: Record, stiffness: float) -> FreeDecay:
    """Free decay from a displacement record, by least squares: x(t) = c + A exp(-Delta t) cos(omega_d t + phi)
    fitted to the samples from the first peak on, started from the peaks' log-amplitude slope and spacing.

    The peaks alone put the frequency on the sample grid (issue 27: 0.3 % off in M and 0.16 % in zeta on the
    bundled record); the fit reads it between samples, and its covariance gives the standard errors of
    Delta, f_d and, to first order, of M = k / (omega_d^2 + Delta^2) and zeta = Delta / omega_n.

    Parameters
    ----------
    record : Record
        A free-decay displacement record (s, m).
    stiffness : float
        k (N/m).

    Returns
    -------
    FreeDecay
        Delta (1/s), f_d (Hz), M (kg), zeta and r (N s/m) with standard errors, and ``report()``.
    """
    from scipy.optimize import curve_fit  # heavy: imported where used
    from scipy.signal import find_peaks  # heavy: imported where used

    x = record.displacement
    prominence = 0.02 * float(np.ptp(x))  # noise makes spurious peaks; a swing stands out
    peaks, _ = find_peaks(x, prominence=prominence)
    troughs, _ = find_peaks(-x, prominence=prominence)
    pairs = [(p, troughs[troughs > p][0]) for p in peaks if np.any(troughs > p)]
    if len(pairs) < 3:
        raise InputError(f"record {record.source}: fewer than 3 decaying swings; not a free-decay record")
    # half the peak-to-trough swing does not depend on where the oscillation is centred
    times = np.array([0.5 * (record.time[p] + record.time[q]) for p, q in pairs])
    halves = np.array([0.5 * (x[p] - x[q]) for p, q in pairs])
    slope, _ = np.polyfit(times, np.log(halves), 1)
    period = float(np.median(np.diff(record.time[[p for p, _ in pairs]])))
    cycles = (times[-1] - times[0]) / period
    start = free_decay(float(np.exp(-slope * (times[-1] - times[0]))), cycles, 1.0 / period, stiffness)
    first = pairs[0][0]
    t, y = record.time[first:] - record.time[first], x[first:]

    def model(t, offset, amplitude, delta, omega, phase):
        return offset + amplitude * np.exp(-delta * t) * np.cos(omega * t + phase)

    guess = (float(np.mean(x[pairs[-1][0]:])), float(halves[0]), start.decay_constant,
             2 * math.pi * start.damped_frequency, 0.0)
    try:
        with np.errstate(over="ignore", invalid="ignore"):  # trial decays far off the data overflow harmlessly
            values, covariance = curve_fit(model, t, y, p0=guess, maxfev=20000)
    except (RuntimeError, ValueError) as exc:
        raise InputError(f"record {record.source}: the damped oscillation does not fit ({exc}); is it a free decay?") \
            from None
    _, _, delta, omega_d, _ = values
    if not (delta > 0 and omega_d > 0) or not np.all(np.isfinite(covariance)):
        raise InputError(f"record {record.source}: the fitted decay (Delta = {delta:.3g} 1/s) does not describe a "
                         "free decay; is the record a decaying oscillation?")
    result = free_decay(math.exp(delta * 2 * math.pi / omega_d), 1.0, omega_d / (2 * math.pi), stiffness)
    sd_delta, sd_omega = math.sqrt(covariance[2, 2]), math.sqrt(covariance[3, 3])
    correlation = covariance[2, 3]
    omega_n2 = omega_d ** 2 + delta ** 2
    # first-order propagation: M = k / omega_n^2, zeta = Delta / sqrt(omega_n^2)
    grad_mass = np.array([-2 * delta, -2 * omega_d]) * stiffness / omega_n2 ** 2
    grad_zeta = np.array([omega_d ** 2, -delta * omega_d]) / omega_n2 ** 1.5
    block = np.array([[sd_delta ** 2, correlation], [correlation, sd_omega ** 2]])
    result.standard_errors = {"decay_constant": sd_delta, "damped_frequency": sd_omega / (2 * math.pi),
                              "mass": float(math.sqrt(grad_mass @ block @ grad_mass)),
                              "damping_ratio": float(math.sqrt(grad_zeta @ block @ grad_zeta))}
    return result


def synthetic_record(system, cycles: int, sample_rate: float, noise: float = 0.0, seed: int = 0):
    """A uniformly sampled record of a linear-law slider from the exact solution (x, x', x'').

    Starts at rest with the spring unloaded; ``noise`` is the standard deviation added to the
    displacement (m) and, scaled by omega_n^2, to the acceleration.
    """

    if not system.is_linear or system.static_law.depends_on_stick_time:
        raise InputError("synthetic_record needs a linear kinetic law and a rate or constant static law")
    cycle = exact_cycle(system)
    V, K, W = system.platform_speed, system.stiffness, system.normal_load
    omega_n = system.natural_frequency
    first = _stick_duration(system, 0.0)
    x_break = V * first
    length = W / K
    x_eq = _equilibrium(system)
    osc = _Oscillator(np.float64(system.damping_ratio), np.float64((x_break - x_eq) / length), np.float64(V / (omega_n * length)))
    x_end = x_break - cycle.stick_duration * V
    duration = first + cycles * cycle.period
    t = np.arange(0.0, duration, 1.0 / sample_rate)
    x = np.empty_like(t)
    v = np.empty_like(t)
    a = np.zeros_like(t)
    loading = t < first
    x[loading], v[loading] = V * t[loading], V
    phase = np.mod(t[~loading] - first, cycle.period)
    in_slip = phase < cycle.slip_duration
    s = omega_n * phase[in_slip]
    xs, vs, acc = np.empty_like(phase), np.full_like(phase, V), np.zeros_like(phase)
    xs[in_slip] = x_eq + length * osc("u", s)
    vs[in_slip] = omega_n * length * osc("v", s)
    acc[in_slip] = omega_n**2 * length * osc("a", s)
    xs[~in_slip] = x_end + V * (phase[~in_slip] - cycle.slip_duration)
    x[~loading], v[~loading], a[~loading] = xs, vs, acc
    if noise:
        rng = np.random.default_rng(seed)
        x = x + noise * rng.standard_normal(x.size)
        a = a + noise * omega_n**2 * rng.standard_normal(a.size)
    return Record(t, x, a, None, None, f"synthetic {system.name}")
