"""2-D fault scenes: ``family = "fault_2d"``, friction that may vary with depth, and a run.

::

    family = "fault_2d"
    name = "SEAS BP1-QD"
    [fault]
    density = "2670 kg/m^3"
    shear_wave_speed = "3.464 km/s"
    width = "40 km"              # W_f, the frictional fault; below it, steady slip at the plate rate
    element_size = "25 m"
    plate_rate = "1e-9 m/s"
    evolution = "aging"          # or "slip"
    [friction]                   # each: a number, or a profile in depth
    reference_speed = "1e-6 m/s"
    reference_friction = 0.6
    b = 0.015
    critical_slip = "8 mm"
    normal_stress = "50 MPa"
    a = { shallow = 0.010, deep = 0.025, depth = "15 km", transition = "3 km" }   # BP1's ramp
    # or a = { depth = ["0 km", "15 km", "18 km", "40 km"], value = [0.010, 0.010, 0.025, 0.025] }
    [initial]
    initial_speed = "1e-9 m/s"   # BP1: V = V_init everywhere, steady state where a = a_max
    [run]
    duration = "3000 yr"
    rtol = 1e-8
    stations = ["0 km", "2.5 km", ...]   # default: BP1's twelve
    profile_interval = "5 yr"
    coseismic_interval = "1 s"
    fault_length = "100 km"     # optional: the along-strike length that turns moment per length into Mw

A dipping fault slips in plane strain (SEAS BP3): ``[fault]`` adds ``plane = "strain"``, ``dip = "60 deg"``,
``sense = "thrust"`` (or ``"normal"``) and ``poisson_ratio = 0.25``; every length along the fault (the width,
the profiles' depths, the stations) is then a distance down dip, as BP3 gives them, and ``[run]
surface_stations`` (default BP3's, -32 to +32 km, + over the hanging wall) are where the surface's displacement
and velocity are recorded.

A profile in depth is either a table (``depth`` and ``value``, linear in between, constant beyond)
or BP1's ramp: ``shallow`` above ``depth``, rising linearly over ``transition`` to ``deep``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from faultslip.models.fault_2d.integrate import BP1_STATIONS, YEAR, OverBudget, first_run_cost, run_cycles, step_path
from faultslip.models.fault_2d.kernel import dense_limit, relative_step_cost
from faultslip.models.fault_2d.analysis import MIN_RESOLUTION
from faultslip.models.fault_2d.model import Fault2D, steady_initial_conditions
from faultslip.models.fault_2d.plane_strain import BP3_SURFACE_STATIONS
from faultslip import ranges
from faultslip.io import gate
from faultslip.errors import FaultslipError, InputError
from faultslip.fault.ladder import expected_recurrence
from faultslip.io.seas import station_file_name
from faultslip.io.processes import threads_are_automatic, threads_for
from faultslip.io.resources import read_text_file, resolve_path
from faultslip.io.resources import check_toml_layout, parse_toml
from faultslip.units import to_si_scalar
from faultslip.models.fault_2d import cost

_FAULT = {"density", "shear_wave_speed", "shear_modulus", "width", "element_size", "plate_rate", "evolution", "plane",
          "dip", "sense", "poisson_ratio"}
_FRICTION = {"reference_speed", "reference_friction", "a", "b", "critical_slip", "normal_stress"}
_INITIAL = {"initial_speed"}
_RUN = {"duration", "rtol", "stations", "profile_interval", "coseismic_interval", "fault_length", "kernel", "threads",
        "surface_stations"}
_PROFILE_KINDS = {"a": "dimensionless", "b": "dimensionless", "critical_slip": "length", "normal_stress": "pressure"}
#: Largest element count a scene may ask for (memory and time grow with it; --allow-large lifts it).
MAX_ELEMENTS = 20_000
#: Elements no run could hold even with --allow-large (a dipping fault's two dense N x N kernels would take
#: 2 x 8 x 1e14 bytes): a resolution that needs more is refused without a suggested size, whose search and estimate
#: would build that fault
RESOLVABLE_ELEMENTS = 1e7
#: From this many elements a run's kernels use every core by default (benchmarks/fault_2d_threads.py: two threads
#: gain 1.25-1.5x from 1,024 elements up; below, the threads' start-up eats the gain)
THREADS_PAY_FROM = 1024


@dataclass
class Fault2DScene:
    """A 2-D fault scene: the fault (built at its element size), its run settings and where it came from."""

    name: str
    fault: Fault2D
    duration: float
    rtol: float = 1e-8
    stations: tuple = BP1_STATIONS
    profile_interval: float = 5 * YEAR
    coseismic_interval: float = 1.0
    fault_length: float | None = None
    kernel: str = "auto"
    threads: int | None = None  # the kernels' threads (None: every core from THREADS_PAY_FROM elements, else 1)
    surface_stations: tuple = BP3_SURFACE_STATIONS  # plane strain only: surface positions (m, + over the hanging wall)
    settings: dict = field(default_factory=dict)  # the parsed friction and geometry, to rebuild at another size
    origin: str = ""
    path: object = None  # the scene file (a Path), if read from one
    text: str = ""  # the scene file as read (studies embed it to reproduce themselves)

    @property
    def resolution(self) -> float:
        """Elements per L_b = G D_c / (sigma_n b) (the smallest over depth)."""
        return self.fault.process_zone() / self.fault.element_size

    def require_resolution(self, allow_underresolved: bool = False) -> None:
        """Refuse, before any work, elements too coarse for the sequence to keep its character
        (:data:`faultslip.models.fault_2d.analysis.MIN_RESOLUTION` per L_b), naming the element size needed and
        its cost; ``allow_underresolved`` runs it anyway, as a qualitative answer."""
        if allow_underresolved or self.resolution >= MIN_RESOLUTION:
            return
        width = self.fault.element_size * self.fault.count
        process_zone = self.fault.process_zone()
        said = (f"{self.name}: elements of {self.fault.element_size:g} m resolve L_b = {process_zone:.4g} m with "
                f"{self.resolution:.2g} each; below {MIN_RESOLUTION:g} per L_b a sequence changes character "
                "(benchmarks/fault_2d_resolution.py). ")
        fewest = width * MIN_RESOLUTION / process_zone
        if fewest > RESOLVABLE_ELEMENTS:  # no run could hold it: likely a mis-stated G, D_c, sigma_n or b
            raise InputError(said + f"It would need {fewest:.3g} elements, beyond any run: check the shear modulus "
                                    "(density and shear-wave speed), D_c, sigma_n and b, since L_b = G D_c / (sigma_n b)")
        count, size = dividing_size(width, math.ceil(fewest))
        try:
            cost = self.at_element_size(float(size)).estimate().describe()
        except InputError as refused:  # past the element limit: say so rather than estimate it
            cost = f"which the element limit refuses: {refused}"
        raise InputError(said + f"Use element_size = \"{size} m\" ({count} elements, {cost}), or "
                         "--allow-underresolved for a qualitative answer")

    def antiplane(self) -> "Fault2DScene":
        """The rung below a dipping fault: the same description (friction down dip, the same width) read as a
        vertical fault in antiplane strain (:mod:`faultslip.fault.dip_error` declares its error)."""
        settings = {**self.settings, "plane": "antiplane", "dip": 90.0}
        name = f"{self.name} (antiplane)"
        return replace(self, name=name, fault=build_fault(settings, self.fault.element_size, name), settings=settings)

    def at_element_size(self, element_size: float) -> "Fault2DScene":
        """The same scene on elements of another size (for convergence studies)."""
        return replace(self, fault=build_fault(self.settings, element_size, self.name))

    def from_start(self, initial_speed: float) -> "Fault2DScene":
        """The same scene started otherwise: every element in steady state at ``initial_speed`` (m/s; BP1 eqs.
        8-9), as ``[initial] initial_speed`` states it."""
        settings = {**self.settings, "initial_speed": float(initial_speed)}
        return replace(self, fault=build_fault(settings, self.fault.element_size, self.name), settings=settings)

    def run(self, rtol: float | None = None, folder=None, resume: bool = False, progress=None,
            time_limit: float | None = None):
        """Integrate this scene with its own settings (:func:`faultslip.models.fault_2d.integrate.run_cycles`);
        past ``time_limit`` wall seconds it stops (checkpointed where it has a folder) in one sentence saying how to
        continue."""
        threads = self.threads or threads_for(self.fault.count, THREADS_PAY_FROM)
        try:
            return run_cycles(self.fault, self.duration, rtol=self.rtol if rtol is None else rtol,
                              stations=self.stations, kernel=self.kernel, profile_interval=self.profile_interval,
                              coseismic_interval=self.coseismic_interval, folder=folder, resume=resume,
                              progress=progress, threads=threads,
                              adapt_threads=self.threads is None and threads_are_automatic(), time_limit=time_limit,
                              surface_stations=self.surface_stations)
        except OverBudget as stopped:
            how = (f"its checkpoint in {folder} lets 'faultslip simulate SCENE --output-dir {folder} --resume "
                   "--allow-large' finish it" if folder is not None else
                   "run it with --output-dir to keep a checkpoint, or with --allow-large")
            raise InputError(f"{self.name}: the run reached twice its time budget ({stopped.seconds:.0f} s of wall "
                             f"time) at {stopped.t / YEAR:.4g} yr of {self.duration / YEAR:.4g}, its estimate "
                             f"({self.estimate(rtol).describe()}) far short; {how}") from None

    def expected_events(self) -> float | None:
        """The system-size events this run will see: its duration over the recurrence the one-slider rung expects
        (:func:`faultslip.fault.ladder.expected_recurrence`); None where the block has none (a creeping fault)."""
        try:
            return self.duration / expected_recurrence(self.fault.description())
        except FaultslipError:
            return None

    def estimated_steps(self, rtol: float | None = None) -> float:
        """The steps this scene's run takes: from the events it will see (:meth:`expected_events`), its width over
        the nucleation size and the process zone, its element size and tolerance
        (:func:`faultslip.models.fault_2d.cost.fault_2d_steps`)."""
        fault = self.fault
        return cost.fault_2d_steps(years=self.duration / YEAR, plate_rate=fault.plate_rate,
                                     element_size=fault.element_size, process_zone=fault.process_zone(),
                                     nucleation_size=fault.nucleation_size(),
                                     seismogenic_width=fault.seismogenic_width(),
                                     rtol=self.rtol if rtol is None else rtol, events=self.expected_events())

    def estimate(self, rtol: float | None = None, output=None, in_this_process: bool = False,
                 steps: float | None = None):
        """What a run of this scene needs (:class:`faultslip.io.budget.Estimate`), before it starts;
        ``in_this_process``: a run about to start here, its first-run cost included (:meth:`first_run_cost`);
        ``steps``: its steps where they are known better than :meth:`estimated_steps` (a rerun's, from the run before)."""
        return cost.fault_2d_estimate(self.fault.count, self.duration / YEAR, len(self.stations), output,
                                        steps=self.estimated_steps(rtol) if steps is None else steps,
                                        outside_fit=self.outside_fit(),
                                        step_cost=relative_step_cost(step_path()),
                                        plane_strain=self.fault.plane == "strain",
                                        first_run=self.first_run_cost() if in_this_process else (0.0, ""))

    def first_run_cost(self, fresh_process: bool = False) -> tuple[float, str]:
        """CPU seconds this process's run of the scene (``fresh_process``: a new process's, a study's worker, on
        one thread) spends before its first step, and on what
        (:func:`~faultslip.models.fault_2d.integrate.first_run_cost`): the whole step's where its kernel is the FFT
        and rocket-fft is here, else the compiled force balance's; a dipping fault's step runs in Python over it,
        on one thread (:func:`run_cycles`)."""
        path = step_path()
        method = self.kernel if self.kernel != "auto" else "dense" if self.fault.count <= dense_limit(path) else "fft"
        strain = self.fault.plane == "strain"
        threads = 1 if strain or fresh_process else self.threads or threads_for(self.fault.count, THREADS_PAY_FROM)
        return first_run_cost(path == "fused" and not strain and method == "fft", threads, fresh_process)

    def outside_fit(self) -> tuple:
        """Where this scene lies outside the scenes its cost estimate was fitted on
        (:func:`faultslip.io.cost.fault_2d_outside_fit`): W/h* and the weakening part's normal stress."""
        fault = self.fault
        weakening = fault.b > fault.a
        if not np.any(weakening):
            return ()  # a creeping fault: no events, the fallback model's few steps
        stress = fault.normal_stress[weakening]
        return cost.fault_2d_outside_fit(width_over_nucleation=fault.seismogenic_width() / fault.nucleation_size(),
                                           normal_stress_low=float(stress.min()),
                                           normal_stress_high=float(stress.max()))

    def with_values(self, **values) -> "Fault2DScene":
        """The scene with parameters replaced, in SI (what a study sweeps; :data:`SWEEPABLE`)."""
        settings = dict(self.settings, profiles=dict(self.settings["profiles"]))
        ramp = dict(settings.get("a_ramp") or {})
        element_size = self.fault.element_size
        for name, value in values.items():
            if name not in SWEEPABLE:
                raise InputError(f"a 2-D fault study sweeps {', '.join(SWEEPABLE)}, not {name!r}")
            if name == "sense":
                settings["sense"] = _sense(value, "the swept sense")
                continue
            value = float(value)
            if name == "dip" and settings.get("plane", "antiplane") != "strain":
                raise InputError("sweeping dip needs the base scene's fault in plane strain: [fault] plane = \"strain\"")
            if name in ("critical_slip", "normal_stress", "b"):
                settings["profiles"][name] = _constant(value)
            elif name in ("seismogenic_depth", "a_deep"):
                if not ramp:
                    raise InputError(f"sweeping {name} needs a as BP1's ramp, a = {{ shallow, deep, depth, transition }}")
                ramp["depth" if name == "seismogenic_depth" else "deep"] = value
            elif name == "element_size":
                element_size = value
            else:
                settings[name] = value
        if ramp:
            settings["a_ramp"] = ramp
            settings["profiles"]["a"] = _ramp(ramp["shallow"], ramp["deep"], ramp["depth"], ramp["transition"])
        return replace(self, fault=build_fault(settings, element_size, self.name), settings=settings)


#: What a study may sweep on a 2-D fault: name -> (unit kind, SI unit, meaning).
SWEEPABLE = {
    "critical_slip": ("length", "m", "critical slip distance D_c (uniform in depth)"),
    "normal_stress": ("pressure", "Pa", "effective normal stress sigma_n (uniform in depth)"),
    "b": ("dimensionless", "1", "evolution effect b (uniform in depth)"),
    "seismogenic_depth": ("length", "m", "depth H where a starts to rise (BP1's ramp)"),
    "a_deep": ("dimensionless", "1", "a below the ramp, a_max (BP1's ramp)"),
    "plate_rate": ("speed", "m/s", "plate rate V_pl"),
    "element_size": ("length", "m", "boundary element size"),
    "dip": ("angle", "degree", "fault dip (plane strain)"),
    "sense": ("category", None, "thrust or normal (plane strain)"),
}


def _sense(value, where: str) -> str:
    if value not in ("thrust", "normal"):
        raise InputError(f"{where} must be thrust or normal, got {value!r}")
    return value


def dividing_size(width: float, fewest: int) -> tuple[int, str]:
    """(elements, element size as written) for the fewest elements from ``fewest`` up whose size, written with at most
    six significant digits, divides ``width`` into them as :func:`build_fault` checks (a suggested size that did not
    divide the fault was refused when used: "170.213 m" of a 40 km fault); at most 1,000 counts are tried."""
    for count in range(fewest, fewest + min(fewest, 1000) + 1):
        text = f"{width / count:.6g}"
        if math.isclose(count * float(text), width, rel_tol=1e-10):
            return count, text
    return fewest, repr(width / fewest)


def _profile(spec, kind: str, where: str):
    """A function of depth (m) for one friction parameter."""
    if not isinstance(spec, dict):
        value = to_si_scalar(spec, kind, where) if kind != "dimensionless" else _number(spec, where)
        return _Constant(value)
    if set(spec) == {"depth", "value"}:
        depths, values = spec["depth"], spec["value"]
        if not (isinstance(depths, list) and isinstance(values, list) and len(depths) == len(values) >= 1):
            raise InputError(f"{where}: depth and value must be lists of the same length")
        z = np.array([to_si_scalar(d, "length", f"{where} depth") for d in depths])
        v = np.array([to_si_scalar(x, kind, f"{where} value") if kind != "dimensionless" else _number(x, where)
                      for x in values])
        if np.any(np.diff(z) <= 0):
            raise InputError(f"{where}: depths must increase")
        return _Table(z, v)
    if set(spec) == {"shallow", "deep", "depth", "transition"}:
        convert = (lambda x, w: _number(x, w)) if kind == "dimensionless" else (lambda x, w: to_si_scalar(x, kind, w))
        shallow, deep = convert(spec["shallow"], f"{where} shallow"), convert(spec["deep"], f"{where} deep")
        top = to_si_scalar(spec["depth"], "length", f"{where} depth")
        transition = to_si_scalar(spec["transition"], "length", f"{where} transition")
        if top < 0 or transition <= 0:
            raise InputError(f"{where}: depth must not be negative and transition must be positive")
        return _ramp(shallow, deep, top, transition)
    raise InputError(f"{where} must be a number, {{ depth = [...], value = [...] }} or "
                     "{ shallow, deep, depth, transition }")


@dataclass(frozen=True)
class _Constant:
    """A profile of one SI value at every depth (a class, not a closure: studies send scenes to workers)."""

    value: float

    def __call__(self, depth):
        return np.full(np.shape(depth), float(self.value))


@dataclass(frozen=True)
class _Table:
    """Linear between tabulated depths, constant beyond."""

    depths: np.ndarray
    values: np.ndarray

    def __call__(self, depth):
        return np.interp(depth, self.depths, self.values)


@dataclass(frozen=True)
class _Ramp:
    """BP1's profile: ``shallow`` above ``top``, rising linearly over ``transition`` to ``deep``."""

    shallow: float
    deep: float
    top: float
    transition: float

    def __call__(self, depth):
        return self.shallow + (self.deep - self.shallow) * np.clip((np.asarray(depth) - self.top) / self.transition,
                                                                    0.0, 1.0)


def _ramp(shallow: float, deep: float, top: float, transition: float) -> _Ramp:
    return _Ramp(shallow, deep, top, transition)


def _constant(value: float) -> _Constant:
    return _Constant(float(value))


def _number(value, where) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InputError(f"{where} must be a number, got {value!r}")
    return float(value)


def build_fault(settings: dict, element_size: float, name: str) -> Fault2D:
    """The fault on elements of ``element_size`` from parsed settings (see :func:`parse_fault_2d_scene`)."""
    width = settings["width"]
    ranges.check("element_size", element_size, f"the element size of {name}")
    count = int(round(width / element_size))
    if count < 2 or not math.isclose(count * element_size, width, rel_tol=1e-9):
        raise InputError(f"the element size {element_size:g} m must divide the fault width {width:g} m into 2 "
                         "elements or more")
    if count > settings.get("max_elements", MAX_ELEMENTS):
        raise InputError(f"{count} elements exceed the limit of {MAX_ELEMENTS} (memory and time grow with them); "
                         "choose a larger element_size, or pass --allow-large")
    depth = (np.arange(count) + 0.5) * element_size
    values = {key: settings["profiles"][key](depth) for key in _PROFILE_KINDS}
    for key in ("a", "critical_slip", "normal_stress"):
        if np.any(values[key] <= 0):
            raise InputError(f"[friction] {key} must be positive at every depth")
    for key in ("a", "b"):  # the rate-and-state coefficients of rock lie well inside (0, 1)
        if not np.all((values[key] > 0) & (values[key] < 1)):
            raise InputError(f"[friction] {key} of {name} must lie in (0, 1) at every depth (rock: about 0.005-0.03)")
    ranges.check("critical_slip", values["critical_slip"], f"[friction] critical_slip of {name}")
    damping = settings["shear_modulus"] / (2 * settings["shear_wave_speed"])
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):  # refused below if not finite
        tau0, psi0 = steady_initial_conditions(values["a"], values["b"], values["normal_stress"], damping,
                                               settings["initial_speed"], settings["reference_speed"],
                                               settings["reference_friction"], stress_a=float(values["a"].max()))
    if not (np.all(np.isfinite(tau0)) and np.all(np.isfinite(psi0))):
        raise InputError(f"{name}: the initial steady state (BP1 eqs. 8-9) overflows with these f0, a and b; "
                         "f0 + b ln(V0 / V_init) must stay within a few hundred times a")
    return Fault2D(element_size, values["a"], values["b"], values["critical_slip"], values["normal_stress"],
                   settings["shear_modulus"], settings["shear_wave_speed"], settings["plate_rate"],
                   settings["reference_speed"], settings["reference_friction"], tau0, psi0,
                   evolution=settings["evolution"], name=name, plane=settings.get("plane", "antiplane"),
                   dip=settings.get("dip", 90.0), sense=settings.get("sense", "thrust"),
                   poisson_ratio=settings.get("poisson_ratio", 0.25))


def require_keys(data: dict, required, source: str) -> None:
    """One sentence for the first of ``required`` ((table, keys) pairs) that a fault scene lacks."""
    for table, keys in required:
        for key in keys:
            if key not in data.get(table, {}):
                raise InputError(f"[{table}] {key} is missing in {source}")


def elasticity(fault: dict, source: str) -> tuple[float, float]:
    """A fault scene's (shear-wave speed, shear modulus) in SI from its [fault] table: the modulus given, or
    G = rho c_s^2 from the density."""
    speed = to_si_scalar(fault["shear_wave_speed"], "speed", f"[fault] shear_wave_speed in {source}")
    if "shear_modulus" in fault:
        return speed, to_si_scalar(fault["shear_modulus"], "pressure", f"[fault] shear_modulus in {source}")
    if "density" in fault:
        return speed, to_si_scalar(fault["density"], "density", f"[fault] density in {source}") * speed ** 2
    raise InputError(f"[fault] in {source} needs shear_modulus or density (G = rho c_s^2)")


def parse_fault_2d_scene(text: str, source: str = "<scene>", allow_large: bool = False) -> Fault2DScene:
    data = parse_toml(text, source)
    check_toml_layout(data, {"fault": _FAULT, "friction": _FRICTION, "initial": _INITIAL, "run": _RUN,
                             "sources": None}, source, "a 2-D fault scene")
    if data.get("family", "fault_2d") != "fault_2d":
        raise InputError(f"{source} declares family {data.get('family')!r}; a 2-D fault scene is family = \"fault_2d\"")
    fault, friction = data.get("fault", {}), data.get("friction", {})
    initial, run = data.get("initial", {}), data.get("run", {})
    require_keys(data, (("fault", ("width", "element_size", "plate_rate", "shear_wave_speed")),
                        ("friction", ("a", "b", "critical_slip", "normal_stress", "reference_speed",
                                      "reference_friction")), ("run", ("duration",))), source)
    speed, modulus = elasticity(fault, source)
    settings = {
        "width": to_si_scalar(fault["width"], "length", f"[fault] width in {source}"),
        "shear_modulus": modulus, "shear_wave_speed": speed,
        "plate_rate": to_si_scalar(fault["plate_rate"], "speed", f"[fault] plate_rate in {source}"),
        "evolution": fault.get("evolution", "aging"),
        "reference_speed": to_si_scalar(friction["reference_speed"], "speed", f"[friction] reference_speed in {source}"),
        "reference_friction": _number(friction["reference_friction"], f"[friction] reference_friction in {source}"),
        "initial_speed": to_si_scalar(initial.get("initial_speed", fault["plate_rate"]), "speed",
                                      f"[initial] initial_speed in {source}"),
        "profiles": {key: _profile(friction[key], kind, f"[friction] {key} in {source}")
                     for key, kind in _PROFILE_KINDS.items()},
        "a_ramp": ({"shallow": _number(friction["a"]["shallow"], "a shallow"),
                    "deep": _number(friction["a"]["deep"], "a deep"),
                    "depth": to_si_scalar(friction["a"]["depth"], "length", "a depth"),
                    "transition": to_si_scalar(friction["a"]["transition"], "length", "a transition")}
                   if isinstance(friction["a"], dict) and set(friction["a"]) == {"shallow", "deep", "depth",
                                                                                 "transition"} else None),
        "max_elements": math.inf if allow_large else MAX_ELEMENTS,
        "plane": fault.get("plane", "antiplane"),
        "dip": to_si_scalar(fault.get("dip", 90.0), "angle", f"[fault] dip in {source}", default_unit="degree"),
        "sense": _sense(fault.get("sense", "thrust"), f"[fault] sense in {source}"),
        "poisson_ratio": _number(fault.get("poisson_ratio", 0.25), f"[fault] poisson_ratio in {source}"),
    }
    if settings["plane"] not in ("antiplane", "strain"):
        raise InputError(f"[fault] plane in {source} must be antiplane or strain, got {settings['plane']!r}")
    for key in ("width", "shear_modulus", "shear_wave_speed", "plate_rate", "reference_speed", "initial_speed"):
        if not settings[key] > 0:
            raise InputError(f"{key} in {source} must be positive")
    if settings["evolution"] not in ("aging", "slip"):
        raise InputError(f"[fault] evolution in {source} must be aging or slip, got {settings['evolution']!r}")
    element_size = to_si_scalar(fault["element_size"], "length", f"[fault] element_size in {source}")
    ranges.check("element_size", element_size, f"[fault] element_size in {source}")
    for key in ("reference_friction", "plate_rate"):
        ranges.check(key, settings[key], f"{key} in {source}")
    name = data.get("name", "2-D fault")
    built = build_fault(settings, element_size, name)
    duration = to_si_scalar(run["duration"], "time", f"[run] duration in {source}")
    if not duration > 0:
        raise InputError(f"[run] duration in {source} must be positive")
    rtol = run.get("rtol", 1e-8)
    if isinstance(rtol, bool) or not isinstance(rtol, (int, float)) or not 1e-14 <= rtol <= 1e-2:
        raise InputError(f"[run] rtol in {source} must be a number from 1e-14 to 1e-2, got {rtol!r}")
    stations = _lengths(run, "stations", BP1_STATIONS, "depths", source)
    if any(s < 0 or s > settings["width"] for s in stations):
        raise InputError(f"[run] stations in {source} must lie on the fault, from 0 to {settings['width']:g} m")
    names = [station_file_name(s) for s in stations]
    repeated = gate.repeated_names(names)
    if repeated:
        depths = ", ".join(f"{s / 1e3:g} km" for s, name in zip(stations, names) if name == repeated[0])
        raise InputError(f"[run] stations in {source}: {depths} would share the SEAS file {repeated[0]} (stations "
                         "are named to 100 m); give each station its own depth, 100 m or more apart")
    length = run.get("fault_length")
    if length is not None:
        length = ranges.check("fault_length", to_si_scalar(length, "length", f"[run] fault_length in {source}"),
                              f"[run] fault_length in {source}")
    surface = _lengths(run, "surface_stations", BP3_SURFACE_STATIONS, "distances from the trace", source)
    kernel = run.get("kernel", "auto")
    if kernel not in ("auto", "dense", "fft"):
        raise InputError(f"[run] kernel in {source} must be auto, dense or fft, got {kernel!r}")
    threads = run.get("threads", "auto")
    if threads != "auto" and (isinstance(threads, bool) or not isinstance(threads, int) or not 1 <= threads <= 1024):
        raise InputError(f"[run] threads in {source} must be auto or a whole number from 1 to 1024, got {threads!r}")
    return Fault2DScene(
        name=name, fault=built, duration=duration, rtol=float(rtol), stations=tuple(stations),
        profile_interval=to_si_scalar(run.get("profile_interval", "5 yr"), "time", f"[run] profile_interval in {source}"),
        coseismic_interval=to_si_scalar(run.get("coseismic_interval", "1 s"), "time",
                                        f"[run] coseismic_interval in {source}"),
        fault_length=length,
        kernel=kernel, threads=None if threads == "auto" else threads, settings=settings, text=text,
        surface_stations=surface)


def _lengths(run: dict, key: str, default: tuple, what: str, source: str) -> tuple:
    """``[run] key``: a list of lengths with units (SI), or ``default`` where the scene gives none."""
    given = run.get(key)
    if given is None:
        return tuple(default)
    if not isinstance(given, list) or not given:
        raise InputError(f"[run] {key} in {source} must be a list of {what}")
    return tuple(to_si_scalar(value, "length", f"[run] {key} in {source}") for value in given)


def is_fault_2d_document(document) -> bool:
    """Whether a parsed TOML document declares the 2-D fault family."""
    return isinstance(document, dict) and document.get("family") == "fault_2d"


def read_fault_2d_scene(path, allow_large: bool = False) -> Fault2DScene:
    """A 2-D fault scene (``family = "fault_2d"``) from a file or a bundled scene's name.

    Parameters
    ----------
    path : str or path
        The scene.
    allow_large : bool
        Allow more elements than the budget.

    Returns
    -------
    Fault2DScene
    """
    if isinstance(path, Fault2DScene):
        return path
    resolved, origin = resolve_path(path, "scene")
    scene = parse_fault_2d_scene(read_text_file(resolved, "scene file"), resolved.name, allow_large)
    scene.origin, scene.path = origin, resolved
    return scene


def from_one_slider(rate_state_scene, element_size: float | None = None, duration: float | None = None,
                    rtol: float = 1e-8, elements_per_process_zone: float = 8.0) -> Fault2DScene:
    """The 2-D fault a one-slider rate-and-state fault scene stands for: its friction uniform from the
    surface to the width it states (W, or the seed's D), loaded by steady slip at the plate rate below. Elements resolve L_b = G D_c / (sigma_n b) with
    ``elements_per_process_zone`` each (8) unless ``element_size`` is given."""
    law, fault = rate_state_scene.law, rate_state_scene.fault
    # the width the scene states: its seismogenic width W, or the seed's zone width D
    modulus, width = fault["shear_modulus"], getattr(rate_state_scene, "width", None) or fault["zone_width"]
    # the block's own wave speed (its radiation damper G / (2 c_s)): c_s = sqrt(G / rho) where the scene gives none
    speed = fault.get("shear_wave_speed") or math.sqrt(modulus / fault.get("density", 2700.0))
    sigma = fault["normal_stress"]
    process = modulus * law.critical_slip / (sigma * law.b) if law.b > 0 else width / 64
    if element_size is None:
        count = max(16, int(math.ceil(width / (process / elements_per_process_zone))))
        element_size = width / count
    settings = {"width": width, "shear_modulus": modulus, "shear_wave_speed": speed,
                "plate_rate": rate_state_scene.plate_rate, "evolution": law.evolution,
                "reference_speed": law.reference_speed, "reference_friction": law.mu0,
                "initial_speed": rate_state_scene.plate_rate, "max_elements": MAX_ELEMENTS,
                "profiles": {"a": _constant(law.a), "b": _constant(law.b), "critical_slip": _constant(law.critical_slip),
                             "normal_stress": _constant(sigma)}}
    name = f"{rate_state_scene.name} (2-D)"
    built = build_fault(settings, element_size, name)
    return Fault2DScene(name=name, fault=built, duration=duration or 0.0, rtol=rtol,
                        stations=tuple(s for s in (0.0, width / 4, width / 2, 3 * width / 4)), settings=settings)
