"""3-D fault scenes: ``family = "fault_3d"``, a velocity-weakening patch on a planar fault, and a run.

::

    family = "fault_3d"
    name = "SEAS BP5-QD"
    [fault]
    density = "2670 kg/m^3"
    shear_wave_speed = "3.464 km/s"
    poisson_ratio = 0.25
    width = "40 km"              # W_f, down dip; below it and beyond the ends, steady slip at the plate rate
    length = "100 km"            # l_f, along strike, centred on 0
    element_size = "1000 m"      # squares
    plate_rate = "1e-9 m/s"
    dip = "90 deg"               # optional; a dipping fault slips along its rake, with its normal stress changing
    rake = "strike"              # or "thrust", "normal"
    evolution = "aging"
    [friction]
    reference_speed = "1e-6 m/s"
    reference_friction = 0.6
    b = 0.03
    critical_slip = "0.14 m"
    normal_stress = "25 MPa"
    # BP5's patch (eq. 6): a = inside within [top, bottom] x [-length/2, length/2], outside beyond transition
    a = { inside = 0.004, outside = 0.04, top = "4 km", bottom = "16 km", length = "60 km", transition = "2 km" }
    [nucleation]                 # optional: a patch that starts faster, with its own D_c
    strike_from = "-30 km"
    strike_to = "-18 km"
    top = "4 km"
    bottom = "16 km"
    critical_slip = "0.13 m"
    initial_speed = "0.01 m/s"
    [initial]
    initial_speed = "1e-9 m/s"   # V_init: every square's state theta_0 = D_c / V_init, its stress steady at it
    [run]
    duration = "1800 yr"
    rtol = 1e-6
    stations = [["0 km", "10 km"], ...]   # (along strike, down dip); default: BP5's ten
    profile_interval = "5 yr"
    coseismic_interval = "0.5 s"

Lengths along the fault (width, the patch's depths, the stations' second coordinate) are distances down dip, as on
the 2-D fault.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from faultslip import ranges
from faultslip.errors import InputError
from faultslip.io import budget
from faultslip.io.resources import check_toml_layout, parse_toml, read_text_file, resolve_path
from faultslip.models.fault_2d.integrate import YEAR, OverBudget, first_run_cost, run_cycles
from faultslip.fault.ladder import groups
from faultslip.fault.strike_error import groups_of
from faultslip.models.fault_2d.model import Fault2D, steady_initial_conditions
from faultslip.models.fault_2d.scene import Fault2DScene, elasticity, require_keys
from faultslip.models.fault_3d import cost
from faultslip.models.fault_3d.kernel import RAKES, StrikeConvolution
from faultslip.models.fault_3d.model import Fault3D, StationGrid, bp5_initial_conditions
from faultslip.units import to_si_scalar

_FAULT = {"density", "shear_wave_speed", "shear_modulus", "poisson_ratio", "width", "length", "element_size",
          "plate_rate", "dip", "rake", "evolution"}
_FRICTION = {"reference_speed", "reference_friction", "a", "b", "critical_slip", "normal_stress"}
_PATCH = {"inside", "outside", "top", "bottom", "length", "transition"}
_NUCLEATION = {"strike_from", "strike_to", "top", "bottom", "critical_slip", "initial_speed"}
_RUN = {"duration", "rtol", "stations", "profile_interval", "coseismic_interval"}
#: SEAS BP5's on-fault stations (along strike, down dip; m).
BP5_STATIONS = ((-36e3, 0.0), (-16e3, 0.0), (0.0, 0.0), (16e3, 0.0), (36e3, 0.0), (-24e3, 10e3), (-16e3, 10e3),
                (0.0, 10e3), (16e3, 10e3), (0.0, 22e3))
#: Largest square count a scene may ask for (--allow-large lifts it): the operator is N_x N_z^2 numbers.
MAX_ELEMENTS = 40_000
#: The parameters a 3-D fault study sweeps: name -> (unit kind, SI unit, long name).
SWEEPABLE = {
    "critical_slip": ("length", "m", "critical slip distance D_c (the nucleation patch's keeps its proportion)"),
    "normal_stress": ("pressure", "Pa", "effective normal stress sigma_n (uniform)"),
    "patch_length": ("length", "m", "along-strike length of the velocity-weakening patch (BP5's l)"),
    "element_size": ("length", "m", "side of the square elements"),
}


@dataclass(frozen=True)
class Patch:
    """BP5's a(x, z) (Jiang et al. 2022, eq. 6): ``inside`` within [top, bottom] down dip and |x| <= length / 2,
    ``outside`` beyond ``transition`` of that rectangle, linear in the larger of the two distances in between."""

    inside: float
    outside: float
    top: float
    bottom: float
    length: float
    transition: float

    def __call__(self, along: np.ndarray, down: np.ndarray) -> np.ndarray:
        middle, half = (self.top + self.bottom) / 2, (self.bottom - self.top) / 2
        distance = np.maximum(np.abs(down - middle) - half, np.abs(along) - self.length / 2)
        return self.inside + (self.outside - self.inside) * np.clip(distance / self.transition, 0.0, 1.0)


@dataclass
class Fault3DScene:
    """A 3-D fault scene: the fault (built at its element size), its run settings and where it came from."""

    name: str
    fault: Fault3D
    duration: float
    rtol: float = 1e-6
    stations: tuple = BP5_STATIONS
    profile_interval: float = 5 * YEAR
    coseismic_interval: float = 0.5
    settings: dict = field(default_factory=dict)
    origin: str = ""
    path: object = None
    text: str = ""

    def operator(self) -> StrikeConvolution:
        """The traction operator of this fault (FFT along strike), built once."""
        built = self.settings.get("_operator")
        fault = self.fault
        key = (fault.strike_count, fault.dip_count, fault.element_size, fault.dip, fault.rake, fault.shear_modulus,
               fault.poisson_ratio)
        if built is None or built[0] != key:
            operator = StrikeConvolution(*key)
            operator.settings = {"grid": list(key[:3]), "dip": fault.dip, "rake": fault.rake,
                                 "poisson_ratio": fault.poisson_ratio}
            self.settings["_operator"] = built = (key, operator)
        return built[1]

    def recorder(self) -> StationGrid:
        return StationGrid(self.stations, self.fault)

    def run(self, rtol: float | None = None, folder=None, resume: bool = False, progress=None,
            time_limit: float | None = None):
        """Integrate this scene (the 2-D fault's stepping, records and checkpoints, this fault's operator)."""
        recorder = self.recorder()
        try:
            run = run_cycles(self.fault, self.duration, rtol=self.rtol if rtol is None else rtol,
                             stations=recorder, profile_interval=self.profile_interval,
                             coseismic_interval=self.coseismic_interval, folder=folder, resume=resume,
                             progress=progress, time_limit=time_limit, operator=self.operator())
        except OverBudget as stopped:
            how = (f"its checkpoint in {folder} lets 'faultslip simulate SCENE --output-dir {folder} --resume "
                   "--allow-large' finish it" if folder is not None else
                   "run it with --output-dir to keep a checkpoint, or with --allow-large")
            raise InputError(f"{self.name}: the run reached twice its time budget ({stopped.seconds:.0f} s of wall "
                             f"time) at {stopped.t / YEAR:.4g} yr of {self.duration / YEAR:.4g}, its estimate "
                             f"({self.estimate(rtol).describe()}) far short; {how}") from None
        run.station_positions = recorder.positions  # (along strike, down dip) of each station
        return run

    @property
    def resolution(self) -> float:
        """Squares per L_b = G D_c / (sigma_n b) (the smallest)."""
        return self.fault.process_zone() / self.fault.element_size

    def estimate(self, rtol: float | None = None, output=None, in_this_process: bool = False) -> budget.Estimate:
        """What a run of this scene needs, before it starts (:mod:`faultslip.models.fault_3d.cost`);
        ``in_this_process``: a run about to start here, with what its process owes before the first step (its step
        runs in Python over the 2-D fault's compiled force balance, on one thread:
        :func:`~faultslip.models.fault_2d.integrate.first_run_cost`)."""
        fault = self.fault
        return cost.estimate(fault.strike_count, fault.dip_count, self.duration / YEAR, len(self.stations), output,
                             **self._step_inputs(rtol), products=cost.products(fault),
                             first_run=first_run_cost(False, 1) if in_this_process else (0.0, ""))

    def expected_steps(self, rtol: float | None = None) -> float:
        """The Dormand-Prince steps :meth:`estimate` counts a run at (:func:`faultslip.models.fault_3d.cost.steps`)."""
        return cost.steps(self.fault.strike_count, **self._step_inputs(rtol))

    def _step_inputs(self, rtol: float | None) -> dict:
        """What the steps model reads of this scene (:func:`faultslip.models.fault_3d.cost.steps`), one place for
        :meth:`estimate` and :meth:`expected_steps`."""
        groups = groups_of(self.fault)
        return {"events": self.expected_events(), "width_over_nucleation": groups["width_over_nucleation"],
                "rtol": self.rtol if rtol is None else rtol, "burial": groups["burial"],
                "resolution": self.resolution}

    def expected_events(self) -> float:
        """System-size events over the run: its duration over the recurrence of the 2-D fault's crude estimate
        (the plate's loading of the patch's stress drop, :func:`faultslip.models.fault_3d.cost.expected_recurrence`)."""
        return self.duration / cost.expected_recurrence(self.fault)

    def at_element_size(self, element_size: float) -> "Fault3DScene":
        """The same scene on squares of another size (for convergence studies)."""
        if "two_d" in self.settings:  # a 2-D scene's 3-D fault: that scene's, at the size
            return from_two_d(self.settings["two_d"].at_element_size(element_size), allow_large=True)
        return replace(self, fault=build_fault(self.settings, element_size, self.name),
                       settings={k: v for k, v in self.settings.items() if k != "_operator"})

    def from_start(self, initial_speed: float) -> "Fault3DScene":
        """The same scene started otherwise: every square off the nucleation patch in steady state at
        ``initial_speed`` (m/s; BP5's start), as ``[initial] initial_speed`` states it."""
        if "two_d" in self.settings:
            return from_two_d(self.settings["two_d"].from_start(initial_speed), allow_large=True)
        settings = {k: v for k, v in self.settings.items() if k != "_operator"}
        settings["initial_speed"] = float(initial_speed)
        return replace(self, fault=build_fault(settings, self.fault.element_size, self.name), settings=settings)

    def with_values(self, **values) -> "Fault3DScene":
        """The scene with parameters replaced, in SI (what a study sweeps; :data:`SWEEPABLE`)."""
        if "two_d" in self.settings:
            raise InputError(f"{self.name} is a 2-D scene's 3-D fault: sweep the 2-D scene, or state the fault as a "
                             "3-D scene (family fault_3d)")
        settings = {k: v for k, v in self.settings.items() if k != "_operator"}
        element_size = self.fault.element_size
        for name, value in values.items():
            if name not in SWEEPABLE:
                raise InputError(f"a 3-D fault study sweeps {', '.join(SWEEPABLE)}, not {name!r}")
            if name == "element_size":
                element_size = float(value)
            elif name == "patch_length":
                settings["patch"] = replace(settings["patch"], length=float(value))
            elif name == "critical_slip":
                ratio = float(value) / settings["critical_slip"]  # the nucleation patch's D_c keeps its proportion
                settings["critical_slip"] = float(value)
                if settings.get("nucleation"):
                    nucleation = dict(settings["nucleation"])
                    nucleation["critical_slip"] *= ratio
                    settings["nucleation"] = nucleation
            else:
                settings[name] = float(value)
        return replace(self, fault=build_fault(settings, element_size, self.name), settings=settings)

    def two_d(self, element_size: float | None = None) -> Fault2D:
        """The rung below: the middle column's friction down dip as a 2-D fault (antiplane for a vertical fault
        slipping along strike, plane strain otherwise), with BP5's initial state at V_init and no nucleation patch;
        a 2-D scene's 3-D fault (:func:`from_two_d`) gives that scene's fault back."""
        if "two_d" in self.settings:
            source = self.settings["two_d"]
            return source.fault if element_size in (None, source.fault.element_size) else \
                source.at_element_size(element_size).fault
        settings = self.settings
        size = self.fault.element_size if element_size is None else element_size
        count = int(round(settings["width"] / size))
        down = (np.arange(count) + 0.5) * size
        along = np.zeros(count)
        a = settings["patch"](along, down)
        b = np.full(count, settings["b"])
        critical_slip = np.full(count, settings["critical_slip"])
        normal_stress = np.full(count, settings["normal_stress"])
        damping = settings["shear_modulus"] / (2 * settings["shear_wave_speed"])
        tau0, psi0 = bp5_initial_conditions(a, b, normal_stress, damping, settings["initial_speed"],
                                            settings["initial_speed"], settings["reference_speed"],
                                            settings["reference_friction"])
        vertical = settings["dip"] == 90.0 and settings["rake"] == "strike"
        return Fault2D(size, a, b, critical_slip, normal_stress, settings["shear_modulus"],
                       settings["shear_wave_speed"], settings["plate_rate"], settings["reference_speed"],
                       settings["reference_friction"], tau0, psi0, evolution=settings["evolution"],
                       name=f"{self.name} (2-D, the middle column)", plane="antiplane" if vertical else "strain",
                       dip=settings["dip"], sense=settings["rake"] if settings["rake"] != "strike" else "thrust",
                       poisson_ratio=settings["poisson_ratio"])


def from_two_d(loaded: Fault2DScene, allow_large: bool = False) -> Fault3DScene:
    """The 3-D fault a 2-D scene states with its ``[run] fault_length`` L: its friction profile down dip (a, b, D_c,
    sigma_n) on every column within L / 2 of the middle, and beyond each end a rising to the profile's largest (its
    strengthening below the rupture zone) over the profile's own ramp below the zone, then strengthening for as far
    again as the zone is wide; beyond the squares, and below them, steady slip at the plate rate (as on the 2-D
    fault below its width). The squares are the 2-D elements; every square starts as the 2-D fault's column does
    (BP1 eqs. 8-9: sliding at V_init, steady where a is largest), so the middle column is the 2-D fault's start.

    Parameters
    ----------
    loaded : Fault2DScene
        A 2-D fault scene with a ``fault_length``.
    allow_large : bool
        Build more squares than :data:`MAX_ELEMENTS`.

    Returns
    -------
    Fault3DScene
        Its stations the 2-D stations on the middle column; its duration, rtol and intervals the scene's.
    """
    flat = loaded.fault
    if not loaded.fault_length:
        raise InputError(f"{loaded.name} states no [run] fault_length: a 2-D scene is a fault infinitely long along "
                         "strike, and its 3-D fault needs that length")
    zone = groups(flat.description())
    size = flat.element_size
    ramp = max(zone["ramp"] * zone["width"], 2 * size)
    ends = ramp + zone["width"]
    strike_count = int(math.ceil((loaded.fault_length + 2 * ends) / size - 1e-9))
    strike_count += strike_count % 2  # an even count puts a column edge, not a centre, on the middle line
    count = strike_count * flat.count
    if count > MAX_ELEMENTS and not allow_large:
        raise InputError(f"{loaded.name}: its 3-D fault, {loaded.fault_length / 1e3:g} km long and "
                         f"{flat.width / 1e3:g} km wide on the scene's {size:g} m elements, needs {count} squares, "
                         f"beyond the limit of {MAX_ELEMENTS} (the operator's memory and each step's time grow with "
                         "them); pass --allow-large, or state the fault as a 3-D scene on larger squares")
    origin = -strike_count * size / 2
    along = np.repeat(origin + (np.arange(strike_count) + 0.5) * size, flat.count)
    column = np.tile(np.arange(flat.count), strike_count)
    strongest = float(flat.a.max())
    beyond = np.clip((np.abs(along) - loaded.fault_length / 2) / ramp, 0.0, 1.0)
    a = flat.a[column] + (strongest - flat.a[column]) * beyond
    b, critical_slip, normal_stress = flat.b[column], flat.critical_slip[column], flat.normal_stress[column]
    damping = flat.shear_modulus / (2 * flat.shear_wave_speed)
    initial_speed = loaded.settings.get("initial_speed", flat.plate_rate)
    tau0, psi0 = steady_initial_conditions(a, b, normal_stress, damping, initial_speed, flat.reference_speed,
                                           flat.reference_friction, stress_a=strongest)
    vertical = flat.plane == "antiplane"
    fault = Fault3D(size, a, b, critical_slip, normal_stress, flat.shear_modulus, flat.shear_wave_speed,
                    flat.plate_rate, flat.reference_speed, flat.reference_friction, tau0, psi0,
                    evolution=flat.evolution, name=f"{loaded.name} (3-D, {loaded.fault_length / 1e3:g} km long)",
                    plane="3d", dip=90.0 if vertical else flat.dip, poisson_ratio=flat.poisson_ratio,
                    strike_count=strike_count, strike_origin=origin, rake="strike" if vertical else flat.sense)
    return Fault3DScene(name=fault.name, fault=fault, duration=loaded.duration, rtol=loaded.rtol,
                        stations=tuple((0.0, float(depth)) for depth in loaded.stations),
                        profile_interval=loaded.profile_interval, coseismic_interval=loaded.coseismic_interval,
                        settings={"initial_speed": initial_speed, "two_d": loaded}, origin=loaded.origin)


def build_fault(settings: dict, element_size: float, name: str) -> Fault3D:
    """The fault on squares of ``element_size`` from parsed settings (see :func:`parse_fault_3d_scene`)."""
    ranges.check("element_size", element_size, f"the element size of {name}")
    strike_count = int(round(settings["length"] / element_size))
    dip_count = int(round(settings["width"] / element_size))
    if (strike_count < 2 or dip_count < 2 or not math.isclose(strike_count * element_size, settings["length"],
                                                               rel_tol=1e-9)
            or not math.isclose(dip_count * element_size, settings["width"], rel_tol=1e-9)):
        raise InputError(f"{name}: the element size {element_size:g} m must divide the length "
                         f"{settings['length']:g} m and the width {settings['width']:g} m into 2 squares or more")
    count = strike_count * dip_count
    if count > settings.get("max_elements", MAX_ELEMENTS):
        raise InputError(f"{name}: {count} squares exceed the limit of {MAX_ELEMENTS} (the operator's memory and "
                         "each step's time grow with them); choose a larger element_size, or pass --allow-large")
    origin = -settings["length"] / 2
    along = np.repeat(origin + (np.arange(strike_count) + 0.5) * element_size, dip_count)
    down = np.tile((np.arange(dip_count) + 0.5) * element_size, strike_count)
    a = settings["patch"](along, down)
    b = np.full(count, settings["b"])
    critical_slip = np.full(count, settings["critical_slip"])
    normal_stress = np.full(count, settings["normal_stress"])
    initial_speed = np.full(count, settings["initial_speed"])
    nucleation = settings.get("nucleation")
    if nucleation:
        inside = ((down >= nucleation["top"]) & (down <= nucleation["bottom"]) & (along >= nucleation["strike_from"])
                  & (along <= nucleation["strike_to"]))
        if not np.any(inside):
            raise InputError(f"{name}: [nucleation] holds no square's centre at {element_size:g} m squares")
        critical_slip[inside] = nucleation["critical_slip"]
        initial_speed[inside] = nucleation["initial_speed"]
    for key, values in (("a", a), ("b", b)):
        if not np.all((values > 0) & (values < 1)):
            raise InputError(f"[friction] {key} of {name} must lie in (0, 1) everywhere (rock: about 0.005-0.04)")
    ranges.check("critical_slip", critical_slip, f"[friction] critical_slip of {name}")
    damping = settings["shear_modulus"] / (2 * settings["shear_wave_speed"])
    with np.errstate(over="ignore", invalid="ignore"):
        tau0, psi0 = bp5_initial_conditions(a, b, normal_stress, damping, initial_speed, settings["initial_speed"],
                                            settings["reference_speed"], settings["reference_friction"])
    if not (np.all(np.isfinite(tau0)) and np.all(np.isfinite(psi0))):
        raise InputError(f"{name}: the initial stress overflows with these f0, a and b; f0 + b ln(V0 / V_init) "
                         "must stay within a few hundred times a")
    return Fault3D(element_size, a, b, critical_slip, normal_stress, settings["shear_modulus"],
                   settings["shear_wave_speed"], settings["plate_rate"], settings["reference_speed"],
                   settings["reference_friction"], tau0, psi0, evolution=settings["evolution"], name=name,
                   plane="3d", dip=settings["dip"], poisson_ratio=settings["poisson_ratio"],
                   strike_count=strike_count, strike_origin=origin, rake=settings["rake"])


def _number(value, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InputError(f"{where} must be a number, got {value!r}")
    return float(value)


def _table(data: dict, key: str, allowed: set, source: str) -> dict:
    table = data.get(key, {})
    if not isinstance(table, dict):
        raise InputError(f"[{key}] in {source} must be a table")
    return table


def _patch(spec, source: str) -> Patch:
    where = f"[friction] a in {source}"
    if not isinstance(spec, dict) or set(spec) != _PATCH:
        raise InputError(f"{where} must be BP5's patch {{ {', '.join(sorted(_PATCH))} }}")
    patch = Patch(_number(spec["inside"], f"{where}: inside"), _number(spec["outside"], f"{where}: outside"),
                  *(to_si_scalar(spec[k], "length", f"{where}: {k}") for k in ("top", "bottom", "length",
                                                                              "transition")))
    if not (0 <= patch.top < patch.bottom and patch.length > 0 and patch.transition > 0):
        raise InputError(f"{where}: top must lie above bottom, and length and transition must be positive")
    return patch


def parse_fault_3d_scene(text: str, source: str = "<scene>", allow_large: bool = False) -> Fault3DScene:
    """A 3-D fault scene from its TOML text (the module's docstring shows one)."""
    data = parse_toml(text, source)
    check_toml_layout(data, {"fault": _FAULT, "friction": _FRICTION, "nucleation": _NUCLEATION, "initial": {
        "initial_speed"}, "run": _RUN, "sources": None}, source, "a 3-D fault scene")
    if data.get("family") != "fault_3d":
        raise InputError(f"{source} declares family {data.get('family')!r}; a 3-D fault scene is family = \"fault_3d\"")
    fault, friction = _table(data, "fault", _FAULT, source), _table(data, "friction", _FRICTION, source)
    initial, run = _table(data, "initial", set(), source), _table(data, "run", _RUN, source)
    require_keys(data, (("fault", ("width", "length", "element_size", "plate_rate", "shear_wave_speed")),
                        ("friction", ("a", "b", "critical_slip", "normal_stress", "reference_speed",
                                      "reference_friction")), ("run", ("duration",))), source)
    speed, modulus = elasticity(fault, source)
    rake = fault.get("rake", "strike")
    if rake not in RAKES:
        raise InputError(f"[fault] rake in {source} must be one of {', '.join(RAKES)}, got {rake!r}")
    settings = {
        "width": to_si_scalar(fault["width"], "length", f"[fault] width in {source}"),
        "length": to_si_scalar(fault["length"], "length", f"[fault] length in {source}"),
        "shear_modulus": modulus, "shear_wave_speed": speed,
        "poisson_ratio": _number(fault.get("poisson_ratio", 0.25), f"[fault] poisson_ratio in {source}"),
        "plate_rate": to_si_scalar(fault["plate_rate"], "speed", f"[fault] plate_rate in {source}"),
        "dip": to_si_scalar(fault.get("dip", 90.0), "angle", f"[fault] dip in {source}", default_unit="degree"),
        "rake": rake, "evolution": fault.get("evolution", "aging"),
        "reference_speed": to_si_scalar(friction["reference_speed"], "speed", f"[friction] reference_speed in {source}"),
        "reference_friction": _number(friction["reference_friction"], f"[friction] reference_friction in {source}"),
        "b": _number(friction["b"], f"[friction] b in {source}"),
        "critical_slip": to_si_scalar(friction["critical_slip"], "length", f"[friction] critical_slip in {source}"),
        "normal_stress": to_si_scalar(friction["normal_stress"], "pressure", f"[friction] normal_stress in {source}"),
        "patch": _patch(friction["a"], source),
        "initial_speed": to_si_scalar(initial.get("initial_speed", fault["plate_rate"]), "speed",
                                      f"[initial] initial_speed in {source}"),
        "max_elements": math.inf if allow_large else MAX_ELEMENTS,
    }
    if not 0.0 <= settings["poisson_ratio"] < 0.5:
        raise InputError(f"[fault] poisson_ratio in {source} must lie in [0, 0.5), got {settings['poisson_ratio']!r}")
    if not 0.0 < settings["dip"] <= 90.0:
        raise InputError(f"[fault] dip in {source} must lie in (0, 90] degrees")
    if settings["evolution"] not in ("aging", "slip"):
        raise InputError(f"[fault] evolution in {source} must be aging or slip, got {settings['evolution']!r}")
    for key in ("width", "length", "shear_modulus", "shear_wave_speed", "plate_rate", "reference_speed",
                "initial_speed", "normal_stress"):
        if not settings[key] > 0:
            raise InputError(f"{key} in {source} must be positive")
    for key in ("reference_friction", "plate_rate"):
        ranges.check(key, settings[key], f"{key} in {source}")
    nucleation = data.get("nucleation")
    if nucleation is not None:
        missing = _NUCLEATION - set(nucleation)
        if missing:
            raise InputError(f"[nucleation] in {source} lacks {', '.join(sorted(missing))}")
        settings["nucleation"] = {
            **{k: to_si_scalar(nucleation[k], "length", f"[nucleation] {k} in {source}")
               for k in ("strike_from", "strike_to", "top", "bottom", "critical_slip")},
            "initial_speed": to_si_scalar(nucleation["initial_speed"], "speed",
                                          f"[nucleation] initial_speed in {source}")}
        if not (settings["nucleation"]["strike_from"] < settings["nucleation"]["strike_to"]
                and settings["nucleation"]["top"] < settings["nucleation"]["bottom"]):
            raise InputError(f"[nucleation] in {source}: strike_from must lie before strike_to, top above bottom")
    element_size = to_si_scalar(fault["element_size"], "length", f"[fault] element_size in {source}")
    name = data.get("name", "3-D fault")
    built = build_fault(settings, element_size, name)
    duration = to_si_scalar(run["duration"], "time", f"[run] duration in {source}")
    if not duration > 0:
        raise InputError(f"[run] duration in {source} must be positive")
    rtol = run.get("rtol", 1e-6)
    if isinstance(rtol, bool) or not isinstance(rtol, (int, float)) or not 1e-14 <= rtol <= 1e-2:
        raise InputError(f"[run] rtol in {source} must be a number from 1e-14 to 1e-2, got {rtol!r}")
    stations = BP5_STATIONS
    if "stations" in run:
        given = run["stations"]
        if not (isinstance(given, list) and given and all(isinstance(p, list) and len(p) == 2 for p in given)):
            raise InputError(f"[run] stations in {source} must be a list of [along strike, down dip] pairs")
        stations = tuple((to_si_scalar(p[0], "length", f"[run] stations in {source}"),
                          to_si_scalar(p[1], "length", f"[run] stations in {source}")) for p in given)
    StationGrid(stations, built)  # on the fault, or refused now
    return Fault3DScene(name=name, fault=built, duration=duration, rtol=float(rtol), stations=tuple(stations),
                        profile_interval=to_si_scalar(run.get("profile_interval", "5 yr"), "time",
                                                      f"[run] profile_interval in {source}"),
                        coseismic_interval=to_si_scalar(run.get("coseismic_interval", "0.5 s"), "time",
                                                        f"[run] coseismic_interval in {source}"),
                        settings=settings, text=text)


def load_fault_3d_scene(path, allow_large: bool = False) -> Fault3DScene:
    """A 3-D fault scene from a file, a bundled name or a scene object."""
    if isinstance(path, Fault3DScene):
        return path
    resolved, origin = resolve_path(path, "3-D fault scene")
    scene = parse_fault_3d_scene(read_text_file(resolved, "3-D fault scene"), resolved.name, allow_large)
    scene.path, scene.origin = resolved, origin
    return scene
