"""Seed 004's block on a moving platform with asperity friction (Bengisu & Akay 1999, eqs. 9-29).

A rigid block of mass M, held by a spring K and dashpot C, rests under gravity on a platform moving at
v. Its state is (x, x', y, y', A_r, A_a): tangential and normal displacement and speed, and the
normal projections of the resisting and assisting contact areas (eq. 22, with s' = x' - v, h' = y'):

    M x'' + C x' + K x = -F_t,   M y'' = -M g + F_n                                        (21)
    alpha (<Z'>^2 + 1) A_r' = -(alpha <Z'> d<Z'>/dt + y' - <Z'> s') A_r                     (22)
    alpha (<Z'>^2 + 1) A_a' = -(alpha <Z'> d<Z'>/dt + y' + <Z'> s') A_a,   alpha = 1/(gamma pi r)

with F_t and F_n from eqs. (17) and (20), <Z'> from eqs. (25) and (27) at the approach dh = -y
(y = 0 at first contact). Adhesion is set-valued at s' = 0: the block sticks while the adhesive force
needed, |C v + K x + F_t,def|, stays below tau A_n + beta F_n (the paper: adhesion "maintains, even for
a short moment, zero relative velocity"). Integration is event-driven (slip -> stick -> slip).

Choices the paper leaves open (docs/asperity.md shows how the results depend on each):

* **summits.** Eq. (22) alone lets the growing family win for ever: the block climbs to the slope
  cut-off and friction loses its deformation part (tested). At the cut-off the contacts are at the
  summits; sliding on carries them onto the opposite faces, so the families exchange (A_r <-> A_a)
  when the climbing family dominates. The block then descends and climbs again, sliding the eq. (29)
  wavelength per cycle: the paper's "combined normal and tangential oscillation".
* **initial state.** Sliding at the adhesive equilibrium x = (tau A* + beta M g)/K, at rest, at
  approach dh0 (0.3 um, "the maximum relative approach considered") with equal families carrying
  A* = M g sqrt(gamma) / K_H. dh0 sets dh_max and so lambda.
* **contact density gamma**: the mean contact area 1/gamma (default 1/(pi r alpha) with alpha = 0.1 um).

Two methods solve it (:data:`METHODS`): ``asperity_LSODA`` integrates all six states; the cheaper
``asperity_quasistatic`` drops the normal inertia (F_n(t) = M g), leaving (x, x', dh, ln(A_r/A_a)),
and declines speeds where following the surface needs a downward acceleration above g.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace

import numpy as np

from faultslip.units import ELAPSED_TIME_ATTRS, takes_units
from faultslip.dynamics.shared.settling import assess_settling
from faultslip import ranges
from faultslip.errors import InputError, SolverError
from faultslip.models.asperity import friction as contact
from faultslip.io.progress import reporter
from faultslip.io.report import Report
from faultslip.units import STANDARD_GRAVITY
from faultslip.datasets import ToXarray

SLIP_BACKWARD, STICK, SLIP_FORWARD = -1, 0, 1
_ROOT_2_PI = math.sqrt(2.0 / math.pi)
_ROOT_2 = math.sqrt(2.0)


@takes_units(platform_speed="speed", mass="mass", natural_frequency="frequency", dashpot="damping",
             shear_strength="pressure", composite_modulus="pressure", asperity_radius="length",
             slope_radius="length", loss_factor="damping", contact_length="length", slope_cutoff="length",
             initial_approach="length", gravity="acceleration")
@dataclass(frozen=True)
class AsperityModel:
    """Seed 004's dynamic system in SI; the defaults are Table I case 6 at 3.6 mm/s.

    Parameters
    ----------
    platform_speed : float
        Platform speed v (m/s).
    mass : float
        Block mass M (kg).
    natural_frequency : float
        Natural frequency f0 = sqrt(K / M) / 2 pi (Hz).
    dashpot : float
        Tangential damping C (N s/m).
    slope_std : float
        Standard deviation s of the asperity slopes (rad).
    shear_strength : float
        Shear strength tau of the adhesion law (Pa; eq. 18).
    pressure_coefficient : float
        Pressure coefficient beta of the adhesion law (dimensionless).
    composite_modulus : float
        Composite elastic modulus (Pa).
    asperity_radius, slope_radius : float
        Asperity radius r and slope radius rho (m; eq. 27).
    loss_factor : float
        Normal loss factor eta (N s/m).
    contact_length : float
        alpha = 1 / (gamma pi r), the contact-density choice (m).
    slope_cutoff, initial_approach : float
        Slope cutoff and initial approach (m).
    summit_exchange : bool
        Exchange the asperity families at the summits (docs/asperity.md).
    gravity : float
        Acceleration of gravity (m/s^2).
    name : str
        A name for reports.
    """

    platform_speed: float = 3.6e-3  # v, m/s
    mass: float = contact.TABLE_I_COMMON["mass"]  # M, kg
    natural_frequency: float = 10.0  # f0 = sqrt(K/M) / (2 pi), Hz
    dashpot: float = 2.0  # C, kg/s
    slope_std: float = 0.1  # s, rad
    shear_strength: float = 9.8e6  # tau, Pa
    pressure_coefficient: float = 0.075  # beta
    composite_modulus: float = contact.TABLE_I_COMMON["composite_modulus"]  # E, Pa
    asperity_radius: float = contact.TABLE_I_COMMON["asperity_radius"]  # r, m (Hertz and alpha)
    slope_radius: float = contact.SLOPE_RADIUS  # rho of eq. (27), m
    loss_factor: float = contact.TABLE_I_COMMON["loss_factor"]  # eta, N s/m
    contact_length: float = 1e-7  # alpha = 1/(gamma pi r), m
    slope_cutoff: float = contact.SLOPE_CUTOFF  # m
    initial_approach: float = 0.3e-6  # dh0, m
    summit_exchange: bool = True
    gravity: float = STANDARD_GRAVITY
    name: str = "seed 004 asperity slider"

    def __post_init__(self):
        limits = {"platform_speed": (1e-7, 10.0, "m/s"), "mass": (1e-4, 1e4, "kg"),
                  "natural_frequency": (0.01, 1e4, "Hz"), "dashpot": (0.0, 1e6, "kg/s"),
                  "slope_std": (1e-3, 1.0, "rad"), "shear_strength": (0.0, 1e10, "Pa"),
                  "pressure_coefficient": (0.0, 1.0, ""), "composite_modulus": (1e6, 1e13, "Pa"),
                  "asperity_radius": (1e-8, 1e-2, "m"), "slope_radius": (1e-8, 1e-2, "m"),
                  "loss_factor": (0.0, 1e8, "N s/m"), "contact_length": (1e-11, 1e-3, "m"),
                  "slope_cutoff": (1e-13, 1e-6, "m"), "initial_approach": (1e-10, 1e-4, "m"),
                  "gravity": (0.01, 100.0, "m/s^2")}
        for key, (low, high, unit) in limits.items():
            value = getattr(self, key)
            if not (isinstance(value, (int, float)) and not isinstance(value, bool) and low <= value <= high):
                raise InputError(f"the asperity model's {key.replace('_', ' ')} must be a number from {low:g} to "
                                 f"{high:g} {unit}, got {value!r}")
        if self.initial_approach <= self.slope_cutoff:
            raise InputError(f"the initial approach ({self.initial_approach:g} m) must exceed the slope cut-off "
                             f"({self.slope_cutoff:g} m): below it the contacts carry no slope")

    @classmethod
    def table_case(cls, case: int, **changes) -> "AsperityModel":
        """Seed 004 Table I case 1-8 (C = 2 kg/s, the dynamic runs' value, unless changed)."""
        if case not in contact.TABLE_I:
            raise InputError(f"seed 004 Table I has cases 1-8, got {case!r}")
        values = {**contact.TABLE_I[case], "name": f"seed 004 Table I case {case}", **changes}
        return replace(cls(), **values)

    # --- derived constants ---
    @property
    def stiffness(self) -> float:
        return self.mass * (2.0 * math.pi * self.natural_frequency) ** 2

    @property
    def contact_density(self) -> float:
        """gamma = 1/(pi r alpha), contacts per m^2 of real contact area."""
        return 1.0 / (math.pi * self.asperity_radius * self.contact_length)

    @property
    def hertz(self) -> float:
        return float(contact.hertz_constant(self.composite_modulus, self.asperity_radius))

    @property
    def weight(self) -> float:
        return self.mass * self.gravity

    @property
    def resting_area(self) -> float:
        """A* = M g sqrt(gamma) / K_H: the real contact area carrying the weight (eq. 17, no slope)."""
        return self.weight * math.sqrt(self.contact_density) / self.hertz

    @property
    def wavelength(self) -> float:
        return float(contact.friction_wavelength(self.initial_approach, self.slope_std, self.slope_radius,
                                                 self.slope_cutoff))

    def critical_speeds(self, orders=(1, 2, 3, 4, 5, 6)) -> np.ndarray:
        return contact.critical_speeds(self.natural_frequency, self.wavelength, orders)

    @property
    def contact_loss_speed(self) -> float:
        return float(contact.contact_loss_speed(self.initial_approach, self.slope_std, self.slope_radius,
                                                self.gravity))

    @property
    def adhesive_friction(self) -> float:
        """tau A* + beta M g: the adhesion a sliding block must overcome, N."""
        return self.shear_strength * self.resting_area + self.pressure_coefficient * self.weight

    def slope(self, approach: float):
        """(<Z'>, d<Z'>/d dh, <Z'^2>) at one approach, with the paper's cut-off (zero below it, or held at its
        value with the summit exchange, which sends the block back down): the scalar form of
        :func:`faultslip.models.asperity.friction.mean_contact_slope` and its companions (tested equal), called
        ~1e5 times per simulated second."""
        if approach < self.slope_cutoff:
            if not self.summit_exchange:
                return 0.0, 0.0, 0.0
            approach = self.slope_cutoff  # at the summits: the block leaves them on the exchanged family's slope
        s = self.slope_std
        ratio2 = approach / self.slope_radius / (s * s)  # (Z'_max / s)^2
        capped = ratio2 >= 9.0
        if capped:
            ratio2 = 9.0
        decay = math.exp(-0.5 * ratio2)
        mean = s * _ROOT_2_PI * -math.expm1(-0.5 * ratio2)
        derivative = 0.0 if capped else _ROOT_2_PI / (2.0 * s * self.slope_radius) * decay
        ratio = math.sqrt(ratio2)
        square = s * s * (math.erf(ratio / _ROOT_2) - _ROOT_2_PI * ratio * decay)
        return mean, derivative, square

    def describe(self) -> dict:
        return {"platform_speed": (self.platform_speed, "m/s"), "mass": (self.mass, "kg"),
                "natural_frequency": (self.natural_frequency, "Hz"), "stiffness": (self.stiffness, "N/m"),
                "dashpot": (self.dashpot, "kg/s"), "slope_std": (self.slope_std, "rad"),
                "shear_strength": (self.shear_strength, "Pa"), "pressure_coefficient": (self.pressure_coefficient, "1"),
                "composite_modulus": (self.composite_modulus, "Pa"), "asperity_radius": (self.asperity_radius, "m"),
                "slope_radius": (self.slope_radius, "m"), "loss_factor": (self.loss_factor, "N*s/m"),
                "contact_length": (self.contact_length, "m"), "contact_density": (self.contact_density, "1/m^2"),
                "slope_cutoff": (self.slope_cutoff, "m"), "initial_approach": (self.initial_approach, "m"),
                "resting_area": (self.resting_area, "m^2")}


# --------------------------------------------------------------------------- the two right-hand sides
class _FullSystem:
    """The six states (x, x', y, y', ln A_r, ln A_a); logarithms keep the areas positive."""

    names = ("x", "x_dot", "y", "y_dot", "log_resisting", "log_assisting")

    def __init__(self, model: AsperityModel):
        self.m = model
        self.alpha = model.contact_length
        self.k_area = model.hertz / math.sqrt(model.contact_density)
        self.k_rate = model.loss_factor / (math.pi * model.asperity_radius)

    def initial(self):
        m = self.m
        half = math.log(0.5 * m.resting_area)
        return np.array([m.adhesive_friction / m.stiffness, 0.0, -m.initial_approach, 0.0, half, half])

    def approach(self, state):
        return -state[2]

    def log_ratio(self, state):
        return state[4] - state[5]

    def exchange(self, state):
        state[4], state[5] = state[5], state[4]

    def parts(self, state, sliding_speed):
        """Contact quantities at a state: areas, slope, deformation force and adhesion capacity."""
        m = self.m
        resisting, assisting = math.exp(state[4]), math.exp(state[5])
        area = resisting + assisting
        z, dz, z2 = m.slope(-state[2])
        scale = self.alpha * (1.0 + z * z)
        climb = state[3] * (1.0 - self.alpha * z * dz)  # y' + alpha <Z'> d<Z'>/dt, with d dh/dt = -y'
        rate_r = -(climb - z * sliding_speed) / scale
        rate_a = -(climb + z * sliding_speed) / scale
        area_rate = resisting * rate_r + assisting * rate_a
        force = self.k_area * area * (1.0 + 0.25 * z2) + self.k_rate * area_rate * (1.0 + 0.5 * z2)
        tangential = z * (resisting - assisting)
        deformation_friction = tangential / area * force
        capacity = m.shear_strength * area + m.pressure_coefficient * force
        normal_adhesion = m.shear_strength * tangential + m.pressure_coefficient * deformation_friction
        return force, deformation_friction, capacity, normal_adhesion, rate_r, rate_a, area

    def rhs(self, t, state, mode):
        m = self.m
        if mode == STICK:
            force, friction_d, capacity, normal_adhesion, rate_r, rate_a, _ = self.parts(state, 0.0)
            share = self.needed(state, friction_d) / capacity if capacity > 0 else 0.0
            normal = force - share * normal_adhesion
            return [m.platform_speed, 0.0, state[3], normal / m.mass - m.gravity, rate_r, rate_a]
        force, friction_d, capacity, normal_adhesion, rate_r, rate_a, _ = self.parts(state, state[1] - m.platform_speed)
        friction = friction_d + mode * capacity
        normal = force - mode * normal_adhesion
        return [state[1], (-m.dashpot * state[1] - m.stiffness * state[0] - friction) / m.mass,
                state[3], normal / m.mass - m.gravity, rate_r, rate_a]

    def needed(self, state, friction_d=None):
        """The adhesive force that keeps the block stuck: -(C v + K x) - F_t,def."""
        m = self.m
        if friction_d is None:
            friction_d = self.parts(state, 0.0)[1]
        return -(m.dashpot * m.platform_speed + m.stiffness * state[0]) - friction_d

    def capacity(self, state):
        return self.parts(state, 0.0)[2]

    def forces(self, state, mode):
        """(F_t, F_n, F_t,def, A_n) along a stored state."""
        m = self.m
        sliding = 0.0 if mode == STICK else state[1] - m.platform_speed
        force, friction_d, capacity, normal_adhesion, _, _, area = self.parts(state, sliding)
        share = (self.needed(state, friction_d) / capacity if capacity > 0 else 0.0) if mode == STICK else mode
        return friction_d + share * capacity, force - share * normal_adhesion, friction_d, area


class _QuasiStaticSystem(_FullSystem):
    """Normal inertia dropped: F_n = M g holds at every instant, so A_n follows the slope (eq. 17) and
    y' = <Z'> s' tanh(L/2) / (1 - alpha <Z'> d<Z'>/d dh) keeps the area constant; states (x, x', dh, L)."""

    names = ("x", "x_dot", "approach", "log_ratio")

    def initial(self):
        m = self.m
        return np.array([m.adhesive_friction / m.stiffness, 0.0, m.initial_approach, 0.0])

    def approach(self, state):
        return state[2]

    def log_ratio(self, state):
        return state[3]

    def exchange(self, state):
        state[3] = -state[3]

    def parts(self, state, sliding_speed):
        m = self.m
        z, dz, z2 = m.slope(state[2])
        area = m.weight / (self.k_area * (1.0 + 0.25 * z2))
        share = math.tanh(0.5 * state[3])
        force = m.weight
        deformation_friction = z * share * force
        capacity = m.shear_strength * area + m.pressure_coefficient * force
        log_rate = 2.0 * z * sliding_speed / (self.alpha * (1.0 + z * z))
        approach_rate = -z * sliding_speed * share / (1.0 - self.alpha * z * dz)
        return force, deformation_friction, capacity, 0.0, log_rate, approach_rate, area

    def rhs(self, t, state, mode):
        m = self.m
        if mode == STICK:
            return [m.platform_speed, 0.0, 0.0, 0.0]
        _, friction_d, capacity, _, log_rate, approach_rate, _ = self.parts(state, state[1] - m.platform_speed)
        friction = friction_d + mode * capacity
        return [state[1], (-m.dashpot * state[1] - m.stiffness * state[0] - friction) / m.mass,
                approach_rate, log_rate]


# --------------------------------------------------------------------------- methods and their declarations
#: the quasi-static method's model error against asperity_LSODA, in the stick fraction and the mean friction
#: (benchmarks/asperity_quasistatic_check.py measures it on random systems; a test reads the results)
QUASISTATIC_ERROR = 0.05
#: The loosest and tightest tolerances of :func:`converged_run`, and the step between them.
CONVERGENCE_RTOLS = (1e-8, 1e-10, 1e-12)
#: 1.5 times the largest error of the closed form's v_cn against the simulated n-loop lock over Table I and random
#: systems, rounded up (benchmarks/asperity_wavelength_check.py; a test checks that the fit gives this value)
WAVELENGTH_ERROR = 0.3
#: the same for f0 lambda_run / n, lambda_run the slip per approach cycle of one run (:func:`measured_wavelength`),
#: fitted on the same sweeps' locks (benchmarks/asperity_measured_wavelength_check.py; a test checks the fit)
MEASURED_WAVELENGTH_ERROR = 0.08
#: the measuring run: natural periods at the closed form's v_c1, of which the first are dropped as its transient
MEASURE_PERIODS, MEASURE_TRANSIENT_PERIODS = 16, 4
#: fewest approach cycles a measured wavelength is the median of
MEASURE_MIN_CYCLES = 4
#: the quasi-static integrator's longest step, in natural periods: an event (a stick, a summit exchange) whose
#: function changes sign twice inside one step is never seen, and at rtol 1e-8 DOP853's steps on random systems grew
#: long enough to skip both kinds (benchmarks/asperity_quasistatic_check.py); 1/20 still skipped one
STEPS_PER_PERIOD = 50
METHODS = {
    "asperity_wavelength": {
        "name": "asperity_wavelength", "friction_laws": "asperity (seed 004)",
        "domain": "critical speeds v_cn = f0 lambda / n and the contact-loss speed only (eqs. 28-29)",
        "cost_model": "closed form, microseconds",
        "declared_error": f"{WAVELENGTH_ERROR:g} of the simulated critical speed, the strongest response locked n "
                          "loops a forcing period in a sweep about f0 lambda / n; the closed form lies below the "
                          "lock (benchmarks/asperity_wavelength_check.py: Table I and random systems, "
                          "docs/asperity.md)"},
    "asperity_measured_wavelength": {
        "name": "asperity_measured_wavelength", "friction_laws": "asperity (seed 004)",
        "domain": "critical speeds v_cn = f0 lambda_run / n only, lambda_run the median slip per approach cycle "
                  f"of one run of {MEASURE_PERIODS} natural periods at the closed form's v_c1",
        "cost_model": f"two asperity_quasistatic runs (rtol 1e-8 and 1e-10, the second its convergence check) of "
                      f"{MEASURE_PERIODS} natural periods (asperity_LSODA where v_c1 is within a factor 2 of contact "
                      "loss): ~0.1-2 s",
        "declared_error": f"{MEASURED_WAVELENGTH_ERROR:g} of the simulated critical speed, on the sweeps that set "
                          "asperity_wavelength's. Eq. (29) is the limit alpha -> 0 of eq. (22); a run slides further "
                          "per approach cycle where the contact length alpha is longer, and the lock follows the run "
                          "(benchmarks/asperity_measured_wavelength_check.py, docs/asperity.md)"},
    "asperity_quasistatic": {
        "name": "asperity_quasistatic", "friction_laws": "asperity (seed 004)",
        "domain": "contact kept: platform speed below the contact-loss speed; normal inertia neglected",
        "cost_model": f"4-state DOP853 with stick events, steps at most 1/{STEPS_PER_PERIOD} of the natural "
                      "period: ~0.15 s per simulated second at 3.6 mm/s",
        "declared_error": "0.05 in the stick fraction and the mean friction against asperity_LSODA "
                          "(benchmarks/asperity_quasistatic_check.py: random systems near their critical speeds, "
                          "docs/asperity.md), plus its own change against a tighter rtol"},
    "asperity_LSODA": {
        "name": "asperity_LSODA", "friction_laws": "asperity (seed 004)",
        "domain": "all speeds with contact; stops and reports contact loss (F_n(t) reaching 0) as a failure",
        "cost_model": "6-state LSODA with stick events, resolving the kHz normal mode: ~0.3 s per simulated second "
                      "at 3.6 mm/s, ~10 s at 0.3 m/s",
        "declared_error": "its statistics' change against a run at a tighter rtol, tightened until it meets the "
                          "tolerance (or said not to)"},
}


@dataclass
class AsperityRun(ToXarray):
    """A simulated time series and how it went."""
    #: the units and dimensions of to_xarray() (faultslip.datasets.ToXarray)
    UNITS = {'time': '1', 'friction': '1', 'normal_force': '1', 'deformation_friction': '1', 'normal_area': '1', 'approach': '1', 'summits': '1', 'sticks': '1', 'elapsed': 's', 'mode': '1'}
    DIMENSIONS = {'time': 'time', 'mode': 'time', 'friction': 'time', 'normal_force': 'time', 'deformation_friction': 'time', 'normal_area': 'time', 'approach': 'time'}

    model: AsperityModel
    method: str
    time: np.ndarray
    states: np.ndarray
    mode: np.ndarray
    friction: np.ndarray
    normal_force: np.ndarray
    deformation_friction: np.ndarray
    normal_area: np.ndarray
    approach: np.ndarray
    status: str = "ok"  # ok | contact_lost | solver_failure | declined
    reason: str = ""
    summits: int = 0
    sticks: int = 0
    elapsed: float = 0.0
    notes: list = field(default_factory=list)

    @property
    def speed(self):
        return self.states[1]

    @property
    def displacement(self):
        return self.states[0]


@takes_units(duration="time", samples_per_second="frequency", max_seconds="time", max_step="time")
def simulate(model: AsperityModel, duration: float = 6.0, method: str = "asperity_LSODA", rtol: float = 1e-8,
             samples_per_second: float = 2000.0, max_seconds: float | None = None,
             max_step: float | None = None) -> AsperityRun:
    """Integrate the block for ``duration`` s with ``method``; a contact loss or solver failure ends the run early
    and is reported in ``status`` and ``reason``, never as numbers past it.

    Parameters
    ----------
    model : AsperityModel
        The slider.
    duration : float
        Simulated time (s).
    method : str
        asperity_quasistatic or asperity_LSODA.
    rtol : float
        Relative tolerance.
    samples_per_second : float
        Output rate (Hz).
    max_seconds : float, optional
        A wall-time limit (s).
    max_step : float, optional
        The integrator's longest step (s): by default none for asperity_LSODA and 1 / (STEPS_PER_PERIOD f0) for
        asperity_quasistatic, whose long steps can pass over an event; ``math.inf`` lifts the bound.

    Returns
    -------
    AsperityRun
        The states against time (s, m, m/s, N), ``status`` and ``reason``.
    """
    from scipy.integrate import solve_ivp  # heavy: imported where used (a closed-form run never integrates)

    if method not in ("asperity_LSODA", "asperity_quasistatic"):
        raise InputError(f"asperity simulation method must be asperity_LSODA or asperity_quasistatic, got {method!r}")
    if not (isinstance(duration, (int, float)) and 0 < duration <= 1e4):
        raise InputError(f"the asperity run's duration must be from 0 to 1e4 s, got {duration!r}")
    if not 1e-12 <= rtol <= 1e-2:
        raise InputError(f"rtol must be from 1e-12 to 1e-2, got {rtol!r}")
    system = _FullSystem(model) if method == "asperity_LSODA" else _QuasiStaticSystem(model)
    if method == "asperity_quasistatic" and model.platform_speed >= model.contact_loss_speed:
        return _declined(model, method, f"v = {model.platform_speed:.4g} m/s is above the contact-loss speed "
                         f"{model.contact_loss_speed:.4g} m/s, where the surface falls away faster than g and the "
                         "quasi-static normal balance fails; use asperity_LSODA, which reports the loss")
    solver = "LSODA" if method == "asperity_LSODA" else "DOP853"
    if max_step is None:  # the six-state run resolves the kHz normal mode, so only the quasi-static one needs it
        max_step = np.inf if method == "asperity_LSODA" else 1.0 / (STEPS_PER_PERIOD * model.natural_frequency)
    if not (isinstance(max_step, (int, float)) and max_step > 0):
        raise InputError(f"max_step must be a positive number of seconds, got {max_step!r}")
    state = system.initial()
    size = state.size
    atol = (np.array([1e-12, 1e-10, 1e-15, 1e-12, 1e-9, 1e-9]) if size == 6 else np.array([1e-12, 1e-10, 1e-15, 1e-9]))
    v = model.platform_speed
    t, mode = 0.0, SLIP_BACKWARD
    grid = np.linspace(0.0, duration, max(int(duration * samples_per_second), 2) + 1)
    pieces, summits, sticks, status, reason = [], 0, 0, "ok", ""
    started = time.perf_counter()
    def never(t_, s, *_):  # without the exchange the summits are not events (eq. 22 alone)
        return 1.0

    while t < duration:
        def summit(t_, s, *_):
            return system.approach(s) - model.slope_cutoff
        summit.terminal, summit.direction = True, -1

        def lost(t_, s, *_, mode=mode):  # contact forces push: F_n(t) < 0 would need the surfaces to pull
            return system.forces(s, mode)[1] / model.weight if size == 6 else 1.0
        lost.terminal, lost.direction = True, -1
        if mode == STICK:
            def change(t_, s, *_):
                return abs(system.needed(s)) - system.capacity(s)
            change.direction = 1
        else:
            def change(t_, s, *_):
                return s[1] - v
            change.direction = -mode
        change.terminal = True
        inside = grid[(grid > t) & (grid < duration)]
        if max_seconds is not None and time.perf_counter() - started > max_seconds:
            status, reason = "budget_exceeded", f"stopped at t = {t:.4g} s after {max_seconds:g} s of computing"
            break
        events = [summit if model.summit_exchange else never, change, lost]
        steps = None
        if mode != STICK and size == 4:
            events.append(_slowest(system, mode))  # see _graze
        elif mode != STICK:  # LSODA's interpolant cannot place that event: its step ends are kept instead
            steps = _StepEnds(system, mode, v)
            events.append(steps)
        sol = solve_ivp(system.rhs, (t, duration), state, method=solver, args=(mode,), rtol=rtol, atol=atol,
                        max_step=max_step, events=events,
                        t_eval=np.concatenate([[t], inside]) if inside.size else None)
        if sol.status < 0 or not np.all(np.isfinite(sol.y)):
            status, reason = "solver_failure", f"{solver} failed at t = {t:.4g} s: {sol.message}"
            break
        which = next((i for i, times in enumerate(sol.t_events[:3]) if times.size), None)
        before = float(sol.t_events[which][0]) if which is not None else math.inf
        grazed = (_graze(sol, mode, v, before) if steps is None else
                  _graze_between_steps(system, steps, mode, v, before, rtol, atol))
        if grazed is not None:  # the sign test at step ends missed a touch of the platform's speed
            which, (t, state) = 1, grazed
            keep = sol.t < t
            pieces.append((np.append(sol.t[keep], t), np.column_stack([sol.y[:, keep], state]), mode))
        elif which is None:  # reached the end of the run
            pieces.append((sol.t, sol.y, mode))
            t = float(sol.t[-1])
            break
        else:
            state, t = sol.y_events[which][0].copy(), float(sol.t_events[which][0])
            pieces.append((np.append(sol.t, t), np.column_stack([sol.y, state]), mode))
        if which == 2:
            status = "contact_lost"
            reason = (f"contact lost at t = {t:.4g} s: the normal contact force F_n(t) reaches zero, so the block "
                      f"leaves the surface and the model no longer applies (seed 004 Sec. IV.D); lower the platform "
                      f"speed (closed-form estimate of the limit {model.contact_loss_speed:.3g} m/s)")
            break
        if which == 0:
            climbing_dominant = (system.log_ratio(state) > 0) == (state[1] - v > 0)
            if mode != STICK and model.summit_exchange and climbing_dominant:
                system.exchange(state)
                summits += 1
            if size == 6:  # carried by its momentum just past the cut-off: no immediate second crossing
                state[2] = -model.slope_cutoff * (1.0 - 1e-9)
            else:  # quasi-static: the exchanged family now carries the block down from the summit
                state[2] = model.slope_cutoff * (1.0 + 1e-9)
            continue
        needed = system.needed(state)
        if mode != STICK:
            state[1] = v
            if abs(needed) <= system.capacity(state):
                mode, sticks = STICK, sticks + 1
                continue
        mode = SLIP_FORWARD if needed > 0 else SLIP_BACKWARD
        state[1] = v + mode * 1e-15
        if len(pieces) > 2_000_000:
            status, reason = "solver_failure", "more than 2e6 stick and slip phases: chattering"
            break
    elapsed = time.perf_counter() - started
    return _assemble(model, method, system, pieces, status, reason, summits, sticks, elapsed)


def _slowest(system, mode):
    """The event where a slipping block's speed relative to the platform is least (its acceleration falls through
    zero the way ``mode`` slips): a non-terminal event, read by :func:`_graze`."""
    def slowest(t_, s, *_):
        return system.rhs(t_, s, mode)[1]
    slowest.direction = mode
    return slowest


def _graze(sol, mode, platform_speed, before):
    """(time, state) of the first least relative speed before ``before`` (s) at which the block has passed the
    platform's speed, or None. Such a dip lasts less than one step, and the sign test at step ends misses it:
    seed 004's scene at 3.727 mm/s dipped 2.8e-6 m/s past it unseen, and slipped on where it could stick. The
    quasi-static system's; the six-state one's is :func:`_graze_between_steps`."""
    if mode == STICK or len(sol.t_events) < 4 or not sol.t_events[3].size:
        return None
    for time_, state in zip(sol.t_events[3], sol.y_events[3]):
        if time_ >= before:
            return None
        if (state[1] - platform_speed) * mode < 0:
            return float(time_), state.copy()
    return None


class _StepEnds:
    """A non-terminal event that never fires: scipy evaluates it at every step's end, where it keeps the steps that
    may hide a dip of the speed along the slip past zero (:func:`_graze_between_steps`). Only those are kept, so a
    long slip's memory does not grow with its steps."""

    def __init__(self, system, mode, platform_speed):
        self.system, self.mode, self.platform_speed = system, mode, platform_speed
        self.fastest, self.last, self.steps = 0.0, None, []

    def __call__(self, t_, s, *_):
        along = (s[1] - self.platform_speed) * self.mode
        self.fastest = max(self.fastest, along)
        now = [t_, s.copy(), along, None]
        last, self.last = self.last, now
        if last is None or not (0 < along < GRAZE_NEAR * self.fastest and 0 < last[2] < GRAZE_NEAR * self.fastest):
            return 1.0
        if last[3] is None:
            last[3] = self.system.rhs(last[0], last[1], self.mode)[1] * self.mode
        if last[3] >= 0:  # rising at the step's start: no turn from falling to rising (its end's slope waits)
            return 1.0
        now[3] = self.system.rhs(t_, s, self.mode)[1] * self.mode
        width = t_ - last[0]
        if now[3] > 0 and width > 0 and _least_of_cubic(last[2], last[3], along, now[3], width) < \
                0.5 * min(last[2], along):
            self.steps.append((last[0], last[1], t_))
        return 1.0


#: the cubic Hermite basis (h00, h10, h01, h11) at 33 points of a step, for _least_of_cubic
_POINTS = np.linspace(0.0, 1.0, 33)
_HERMITE = np.array([2 * _POINTS ** 3 - 3 * _POINTS ** 2 + 1, _POINTS ** 3 - 2 * _POINTS ** 2 + _POINTS,
                     -2 * _POINTS ** 3 + 3 * _POINTS ** 2, _POINTS ** 3 - _POINTS ** 2])


def _least_of_cubic(start, start_slope, end, end_slope, width):
    """The least value over [0, width] of the cubic Hermite interpolant of two ends' values and slopes."""
    return float(np.min(np.array([start, width * start_slope, end, width * end_slope]) @ _HERMITE))


#: a step of the six-state run is searched for a dip where the speed along the slip at both its ends is below this
#: fraction of the phase's fastest so far (a step is about 1/650 of a natural period, over which that speed moves
#: about 1 %), it turns from falling to rising within the step, and the ends' cubic dips at least halfway to zero
GRAZE_NEAR = 0.05
#: the searched step is integrated again by DOP853 with steps this many times shorter
GRAZE_REFINE = 64


def _graze_between_steps(system, steps, mode, platform_speed, before, rtol, atol):
    """The six-state run's :func:`_graze`: (time, state) where the block's speed first reached the platform's
    inside one LSODA step, before ``before`` (s), or None.

    Its tangential acceleration carries the kHz normal mode, so its zero crossings are not the slip's least speed,
    and LSODA's interpolant need not pass through its step ends (scipy's event search fails on it). Instead each
    step that may hide a dip is kept (:class:`_StepEnds`) and integrated again by DOP853, GRAZE_REFINE times finer,
    with the slip's end as its event. At 3.7395 mm/s on seed 004's scene LSODA passed over a stick so (13 sticks in
    3 s where steps of 1/3000 of a natural period find 14; benchmarks/asperity_lsoda_steps.py)."""
    from scipy.integrate import solve_ivp  # heavy: imported where used

    def ended(t_, s, *_):
        return (s[1] - platform_speed) * mode
    ended.terminal, ended.direction = True, -1
    for start, state, end in steps.steps:
        if end > before:
            return None
        again = solve_ivp(system.rhs, (start, end), state, method="DOP853", args=(mode,), rtol=rtol, atol=atol,
                          max_step=(end - start) / GRAZE_REFINE, events=[ended])
        if again.t_events[0].size:
            return float(again.t_events[0][0]), again.y_events[0][0].copy()
    return None


def _declined(model, method, reason):
    empty = np.zeros(0)
    return AsperityRun(model, method, empty, np.zeros((6, 0)), empty, empty, empty, empty, empty, empty,
                       status="declined", reason=reason)


def _assemble(model, method, system, pieces, status, reason, summits, sticks, elapsed):
    times = np.concatenate([p[0] for p in pieces]) if pieces else np.zeros(0)
    states = np.concatenate([p[1] for p in pieces], axis=1) if pieces else np.zeros((len(system.names), 0))
    modes = np.concatenate([np.full(p[0].size, p[2]) for p in pieces]) if pieces else np.zeros(0)
    keep = np.concatenate([[True], np.diff(times) > 0]) if times.size else np.zeros(0, bool)
    times, states, modes = times[keep], states[:, keep], modes[keep]
    values = np.array([system.forces(states[:, i], int(modes[i])) for i in range(times.size)]).reshape(-1, 4)
    approach = -states[2] if states.shape[0] == 6 else states[2]
    if states.shape[0] == 4:  # normal speed of the quasi-static block, for a uniform output
        states = np.vstack([states[:2], -states[2:3], np.gradient(-states[2], times) if times.size > 1 else
                            np.zeros_like(times), states[3:4]])
    return AsperityRun(model, method, times, states, modes, values[:, 0], values[:, 1], values[:, 2], values[:, 3],
                       approach, status, reason, summits, sticks, elapsed)


# --------------------------------------------------------------------------- analysis
@dataclass
class Response(ToXarray):
    """The settled response: the paper's averages, stick, the loops per period and the dominant frequency."""
    #: the units and dimensions of to_xarray() (faultslip.datasets.ToXarray)
    UNITS = {'mean_friction': '1', 'mean_deformation_friction': '1', 'stick_fraction': '1', 'velocity_range': '1', 'loops': '1', 'dominant_frequency': '1', 'friction_frequency': '1'}

    mean_friction: float  # m-bar: time average of F_t / F_n (friction on the block along the platform's motion)
    mean_deformation_friction: float  # m-bar_D
    stick_fraction: float
    velocity_range: tuple
    loops: int  # response period over the natural period (1, 2, 3 at v_c1, v_c2, v_c3); 0 if not periodic
    dominant_frequency: float
    friction_frequency: float  # summits per second: f_f of eq. (28)
    stick_slip: bool
    #: the analysed half in SETTLING_WINDOWS equal windows: has m-bar settled across them? (issue 27)
    settling: object = None

    @property
    def settling_error(self) -> float:
        """m-bar's declared settling error: the shared verdict's remaining distance, or the windows' spread."""
        verdict = self.settling
        if verdict is None:
            return math.nan
        return float(verdict.remaining) if math.isfinite(verdict.remaining) else float(
            np.ptp(self._windows) / max(abs(np.mean(self._windows)), 1e-300))

    _windows: tuple = ()


#: Windows of the analysed half whose mean frictions the shared settling test compares.
SETTLING_WINDOWS = 6


def analyse(run: AsperityRun, settle: float = 0.5) -> Response:
    """The response after discarding the first ``settle`` fraction (the paper excludes transients).

    Parameters
    ----------
    run : AsperityRun
        :func:`simulate_asperity`'s run.
    settle : float
        The fraction of the run discarded as transient.

    Returns
    -------
    Response
        Mean friction and deformation friction (dimensionless), stick fraction, loops and the dominant
        frequencies (Hz).
    """
    if run.status not in ("ok",) or run.time.size < 10:
        raise InputError(f"the {run.method} run has no settled response to analyse: {run.reason or run.status}")
    t = run.time
    start = t[0] + settle * (t[-1] - t[0])
    sel = t >= start
    span = t[-1] - start
    ts, speed = t[sel], run.speed[sel]
    ratio = -run.friction[sel] / run.normal_force[sel]
    ratio_d = -run.deformation_friction[sel] / run.normal_force[sel]
    mean = float(np.trapezoid(ratio, ts) / span)
    mean_d = float(np.trapezoid(ratio_d, ts) / span)
    stick = float(np.trapezoid((run.mode[sel] == STICK).astype(float), ts) / span)
    uniform = np.linspace(start, t[-1], 4096)
    u = np.interp(uniform, t, run.speed) - np.interp(uniform, t, run.speed).mean()
    spectrum = np.abs(np.fft.rfft(u * np.hanning(u.size)))
    freqs = np.fft.rfftfreq(u.size, uniform[1] - uniform[0])
    dominant = float(freqs[1:][np.argmax(spectrum[1:])]) if u.any() else 0.0
    loops = _loops(uniform, u, run.model.natural_frequency)
    summit_rate = run.model.platform_speed / run.model.wavelength
    edges = np.linspace(start, t[-1], SETTLING_WINDOWS + 1)
    windows = []
    for low, high in zip(edges[:-1], edges[1:]):
        inside = (t >= low) & (t <= high)
        if np.count_nonzero(inside) >= 2:
            windows.append(float(np.trapezoid(-run.friction[inside] / run.normal_force[inside], t[inside])
                                 / (t[inside][-1] - t[inside][0])))
    verdict = assess_settling(windows, 1e-3, names=("m-bar",)) if len(windows) >= 2 else None
    return Response(mean, mean_d, stick, (float(speed.min()), float(speed.max())), loops, dominant, summit_rate,
                    stick > 1e-3, verdict, tuple(windows))


def _loops(times, speed, natural_frequency) -> int:
    """The smallest n <= 6 with the speed repeating after n natural periods (correlation > 0.98), else 0."""
    if not np.any(speed):
        return 0
    dt = times[1] - times[0]
    for n in range(1, 7):
        lag = int(round(n / natural_frequency / dt))
        if lag >= speed.size // 2:
            break
        a, b = speed[:-lag], speed[lag:]
        if np.std(a) > 0 and np.std(b) > 0 and np.corrcoef(a, b)[0, 1] > 0.98:
            return n
    return 0


#: what a sweep does not check, said in its dataset and report: each speed runs once, at one rtol
SWEEP_CONVERGENCE = ("not tested: each speed runs once at rtol. The quasi-static step bound keeps events from being "
                     "passed over, which changed random systems' stick fractions at one rtol before it "
                     "(docs/asperity.md); give a tolerance to converge each speed, or `faultslip run` at one speed")


def speed_sweep(model: AsperityModel, speeds, duration: float = 3.0, method: str = "asperity_quasistatic",
                rtol: float = 1e-7, progress=None, tolerance: float | None = None):
    """m-bar, m-bar_D, stick fraction and loops against platform speed (seed 004 Figs. 5-7), as an xarray Dataset.

    Without ``tolerance`` each speed runs once at ``rtol``, and the sweep says its convergence is not tested.
    With one, each speed goes through :func:`converged_run` (rtol ``CONVERGENCE_RTOLS`` until two successive runs'
    statistics agree to ``tolerance``), about 3-5 times the cost: ``numerical_error`` holds each speed's measured
    change and ``converged`` whether it met the tolerance; a speed that did not keeps its tightest run, declared.
    Cells that fail (contact loss, declined, solver failure) carry NaN and their status, never numbers.
    ``progress``: True for a bar, or a callable (done, total) (:mod:`faultslip.io.progress`)."""
    import xarray as xr  # heavy: imported where used

    tolerance = ranges.check_tolerance(tolerance, label="a sweep's convergence tolerance")
    speeds = np.asarray(speeds, float)
    progress = reporter(progress, "speed sweep", "speed")
    names = ["mean_friction", "mean_deformation_friction", "stick_fraction", "loops", "elapsed"]
    if tolerance is not None:
        names.append("numerical_error")
    rows = {k: np.full(speeds.size, np.nan) for k in names}
    status, converged = [], []
    for i, speed in enumerate(speeds):
        at_speed = replace(model, platform_speed=float(speed))
        if tolerance is None:
            run = simulate(at_speed, duration, method, rtol)
            rows["elapsed"][i] = run.elapsed
        else:  # the elapsed time covers every rtol the convergence took
            started = time.perf_counter()
            run, error, met = converged_run(at_speed, duration, method, float(tolerance))
            rows["elapsed"][i] = time.perf_counter() - started
            rows["numerical_error"][i] = error if math.isfinite(error) else np.nan
            converged.append(bool(met))
        status.append(run.status)
        if run.status == "ok":
            response = analyse(run)
            rows["mean_friction"][i] = response.mean_friction
            rows["mean_deformation_friction"][i] = response.mean_deformation_friction
            rows["stick_fraction"][i] = response.stick_fraction
            rows["loops"][i] = response.loops
        if progress:
            progress(i + 1, speeds.size)
    attrs = {"mean_friction": ("1", "time-averaged F_t/F_n (m-bar)"),
             "mean_deformation_friction": ("1", "time-averaged deformation part (m-bar_D)"),
             "stick_fraction": ("1", "fraction of time stuck"), "loops": ("1", "response period / natural period"),
             "elapsed": ("s", "computing time"),
             "numerical_error": ("1", "the statistics' largest relative change between the last two rtols")}
    data = {k: ("platform_speed", v, {"units": attrs[k][0], "long_name": attrs[k][1]}) for k, v in rows.items()}
    data["status"] = ("platform_speed", np.array(status, dtype=str))
    if tolerance is None:
        convergence, rtol_note = SWEEP_CONVERGENCE, rtol
    else:
        data["converged"] = ("platform_speed", np.array(converged, dtype="i1"),
                             {"units": "1", "long_name": f"1 where two successive rtols agreed to {tolerance:g}"})
        missed = len(converged) - sum(converged)
        convergence = (f"each speed converged to {tolerance:g} over rtol {', '.join(f'{r:g}' for r in CONVERGENCE_RTOLS)}"
                       + (f"; {missed} of {len(converged)} speeds did not and declare their measured change "
                          "(numerical_error)" if missed else ""))
        rtol_note = np.array(CONVERGENCE_RTOLS)
    return xr.Dataset(data, coords={"platform_speed": ("platform_speed", speeds, {"units": "m/s"})},
                      attrs={"title": f"seed 004 speed sweep: {model.name}", "method": method,
                             "Conventions": "CF-1.8", "wavelength_m": model.wavelength,
                             "critical_speeds_m_per_s": model.critical_speeds(), "rtol": rtol_note,
                             "convergence": convergence})


def peak_speeds(sweep, variable: str = "mean_deformation_friction", prominence: float = 0.05) -> np.ndarray:
    """Speeds of the resonance-like peaks of a sweep variable (the paper's Tables II-III), highest speed first:
    local maxima standing out by at least ``prominence`` of the largest value, so numerical ripple is not a peak."""
    from scipy.signal import find_peaks  # heavy: scipy.signal is needed only here

    values = np.nan_to_num(sweep[variable].values, nan=0.0)
    speeds = sweep["platform_speed"].values
    padded = np.concatenate([[0.0], values, [0.0]])  # a peak at either end of the sweep counts
    found, _ = find_peaks(padded, prominence=prominence * max(float(values.max()), 1e-300))
    return np.sort(speeds[found - 1])[::-1]


@dataclass
class MeasuredWavelength:
    """The wavelength a run slides: ``wavelength`` (m) the median slip per approach cycle over ``cycles`` cycles,
    ``spread`` their (largest - smallest) / median, ``numerical_error`` its relative change from the run at the
    looser rtol, and the (tighter) ``run``; ``elapsed`` covers both runs (s)."""
    wavelength: float
    cycles: int
    spread: float
    run: AsperityRun
    numerical_error: float = 0.0
    elapsed: float = 0.0


def measured_wavelength(model: AsperityModel, rtols=CONVERGENCE_RTOLS[:2]) -> MeasuredWavelength:
    """lambda_run at each of ``rtols`` (:func:`wavelength_of_run`): the tightest's, with its change from the one
    before declared as ``numerical_error``, the convergence test every asperity integration gets."""
    found = [wavelength_of_run(model, rtol) for rtol in rtols]
    change = abs(found[-2].wavelength / found[-1].wavelength - 1.0) if len(found) > 1 else 0.0
    return replace(found[-1], numerical_error=change, elapsed=sum(line.run.elapsed for line in found))


def wavelength_of_run(model: AsperityModel, rtol: float = 1e-8) -> MeasuredWavelength:
    """lambda_run: the slip per approach cycle of one run at the closed form's v_c1, m.

    Eq. (29) integrates d(dh) / <Z'> over a climb: eq. (22) with the contact length alpha -> 0, contacts that follow
    the slope at once. With alpha > 0 the areas lag the slope, and a run slides further per cycle (Table I case 3:
    about 0.5 %, 5 % and 21 % at alpha = 0.01, 0.1 and 0.3 um). The run lasts :data:`MEASURE_PERIODS` natural
    periods (asperity_quasistatic, or asperity_LSODA within a factor 2 of contact loss); after the first
    :data:`MEASURE_TRANSIENT_PERIODS`, each approach maximum standing out by half the approach's range ends a
    cycle, and lambda_run is the median slip s = x - v t between successive ones. Then v_cn = f0 lambda_run / n.

    Raises SolverError naming what to use where the run fails or shows fewer than :data:`MEASURE_MIN_CYCLES` cycles.
    """
    from scipy.signal import find_peaks  # heavy: scipy.signal is needed only here

    speed = float(model.critical_speeds((1,))[0])
    method = "asperity_quasistatic" if speed < 0.5 * model.contact_loss_speed else "asperity_LSODA"
    duration = MEASURE_PERIODS / model.natural_frequency
    run = simulate(replace(model, platform_speed=speed), duration, method, rtol)
    advice = (f"use asperity_wavelength (closed form, declared {WAVELENGTH_ERROR:g}) or sweep the platform speed "
              "(faultslip asperity SCENE --from ... --to ...)")
    if run.status != "ok":
        raise SolverError(f"asperity_measured_wavelength: the {method} run at v_c1 = {speed:.4g} m/s did not finish "
                          f"({run.status}: {run.reason}); {advice}")
    late = run.time >= MEASURE_TRANSIENT_PERIODS / model.natural_frequency
    approach, slip = run.approach[late], run.displacement[late] - speed * run.time[late]
    span = float(np.ptp(approach)) if approach.size else 0.0
    ends = find_peaks(approach, prominence=0.5 * span)[0] if span > 0 else np.array([], int)
    if ends.size < MEASURE_MIN_CYCLES + 1:
        raise SolverError(f"asperity_measured_wavelength: the run at v_c1 = {speed:.4g} m/s shows "
                          f"{max(ends.size - 1, 0)} approach cycles in {MEASURE_PERIODS - MEASURE_TRANSIENT_PERIODS} "
                          f"natural periods, fewer than {MEASURE_MIN_CYCLES}: no wavelength to measure; {advice}")
    per_cycle = np.abs(np.diff(slip[ends]))
    middle = float(np.median(per_cycle))
    return MeasuredWavelength(middle, int(per_cycle.size), float(np.ptp(per_cycle) / middle), run,
                              elapsed=run.elapsed)


# --------------------------------------------------------------------------- method choice and report
@dataclass
class AsperityChoice:
    method: str
    reason: str
    estimated_error: float


def choose_method(model: AsperityModel, outputs=("response",), tolerance: float = 0.05,
                  method: str = "auto") -> AsperityChoice:
    """The cheapest method accurate enough: the closed form for critical speeds alone, the quasi-static
    integration where contact holds and its declared error meets the tolerance, the full one otherwise."""
    names = ("auto", *METHODS)
    if method not in names:
        raise InputError(f"asperity method must be one of {', '.join(names)}, got {method!r}")
    if method != "auto":
        error = {"asperity_wavelength": WAVELENGTH_ERROR, "asperity_measured_wavelength": MEASURED_WAVELENGTH_ERROR,
                 "asperity_quasistatic": QUASISTATIC_ERROR, "asperity_LSODA": 0.0}[method]
        return AsperityChoice(method, "requested", error)
    if set(outputs) <= {"critical_speeds"}:
        if tolerance >= WAVELENGTH_ERROR:
            return AsperityChoice("asperity_wavelength", "only critical speeds are asked: eqs. (28)-(29) in closed "
                                  "form", WAVELENGTH_ERROR)
        if tolerance >= MEASURED_WAVELENGTH_ERROR:
            return AsperityChoice("asperity_measured_wavelength", f"only critical speeds are asked, to {tolerance:g}: "
                                  f"below the closed form's declared {WAVELENGTH_ERROR:g}, so f0 lambda / n with the "
                                  "wavelength one run slides", MEASURED_WAVELENGTH_ERROR)
        # an integration at one speed gives no critical speed: say what does
        raise InputError(f"critical speeds come from a wavelength, declared to {MEASURED_WAVELENGTH_ERROR:g} of the "
                         f"simulated lock at best (a run's; the closed form's {WAVELENGTH_ERROR:g}), above the "
                         f"tolerance {tolerance:g}: sweep the platform speed about them (faultslip asperity SCENE "
                         "--from ... --to ...) and read the n-loop lock's speed")
    loss = model.contact_loss_speed
    if model.platform_speed < 0.5 * loss and tolerance >= QUASISTATIC_ERROR:
        return AsperityChoice("asperity_quasistatic", f"v = {model.platform_speed:.3g} m/s is below half the "
                              f"contact-loss speed {loss:.3g} m/s, and the declared error {QUASISTATIC_ERROR:g} meets "
                              f"tolerance {tolerance:g}", QUASISTATIC_ERROR)
    why = (f"tolerance {tolerance:g} is below the quasi-static method's declared error {QUASISTATIC_ERROR:g}"
           if tolerance < QUASISTATIC_ERROR else
           f"v = {model.platform_speed:.3g} m/s is within a factor 2 of the contact-loss speed {loss:.3g} m/s")
    return AsperityChoice("asperity_LSODA", f"{why}: the full six-state integration", 1e-6)


def report(model: AsperityModel, run: AsperityRun | None = None, choice: AsperityChoice | None = None,
           title: str = "faultslip asperity friction (seed 004, Bengisu & Akay 1999)",
           measured: MeasuredWavelength | None = None) -> Report:
    """The model, its critical speeds (from ``measured``'s wavelength where given, else eq. 29's) and the run's
    statistics."""
    r = Report(title)
    for key, (value, unit) in model.describe().items():
        r.add(key, value, unit)
    r.add("wavelength", model.wavelength, "m", label="lambda, eq. (29) at dh_max = initial approach")
    if measured is None:
        for n, speed in enumerate(model.critical_speeds((1, 2, 3)), start=1):
            r.add(f"critical_speed_{n}", float(speed), "m/s", label=f"v_c{n} = f0 lambda / {n} (eq. 28)")
        r.add("critical_speed_error", WAVELENGTH_ERROR, label="declared error of v_cn against the simulated lock of "
                                                              "n loops a forcing period, which lies above it")
    else:
        r.add("run_wavelength", measured.wavelength, "m",
              label=f"lambda_run: median slip per approach cycle over {measured.cycles} cycles of a run at v_c1")
        r.add("run_wavelength_spread", measured.spread, label="(largest - smallest) / median slip per cycle")
        speeds = contact.critical_speeds(model.natural_frequency, measured.wavelength, (1, 2, 3))
        for n, speed in enumerate(speeds, start=1):
            r.add(f"critical_speed_{n}", float(speed), "m/s", label=f"v_c{n} = f0 lambda_run / {n} (eq. 28)")
        r.add("critical_speed_error", MEASURED_WAVELENGTH_ERROR,
              label="declared error of v_cn against the simulated lock of n loops a forcing period")
        r.add("numerical_error", measured.numerical_error,
              label=f"lambda_run's change from rtol {CONVERGENCE_RTOLS[0]:g} to {CONVERGENCE_RTOLS[1]:g} (measured)")
        r.add("computing_time", measured.elapsed, "s")
    r.add("contact_loss_speed", model.contact_loss_speed, "m/s",
          label="speed where following the surface needs more than g")
    if choice is not None:
        r.add("method", choice.method).add("method_reason", choice.reason, label="why this method")
        r.add("estimated_error", choice.estimated_error, label="declared error of the method")
    if run is not None:
        r.add("status", run.status)
        if run.reason:
            r.add("status_reason", run.reason)
        r.add("duration", float(run.time[-1]) if run.time.size else 0.0, "s")
        r.add("summits", run.summits, label="summit crossings (families exchanged)")
        r.add("computing_time", run.elapsed, "s")
        if run.status == "ok" and run.time.size > 10:
            response = analyse(run)
            r.add("mean_friction", response.mean_friction, label="m-bar, last half")
            r.add("mean_friction_settling_error", response.settling_error,
                  label="m-bar's settling error (its windows' approach, or their spread)")
            if response.settling is not None and not response.settling.settled:
                r.note(f"m-bar over {SETTLING_WINDOWS} windows of the last half: {response.settling.reason}")
            r.add("mean_deformation_friction", response.mean_deformation_friction, label="m-bar_D, last half")
            r.add("stick_fraction", response.stick_fraction, label="fraction of time stuck, last half")
            r.add("regime", "stick_slip" if response.stick_slip else "sliding (sustained oscillation)")
            r.add("loops", response.loops, label="response period / natural period (0: not periodic)")
            r.add("dominant_frequency", response.dominant_frequency, "Hz", label="dominant frequency of x'")
            r.add("friction_frequency", response.friction_frequency, "Hz", label="f_f = v / lambda (eq. 28)")
    r.note("choices the paper leaves open (docs/asperity.md): summit exchange, initial state at the adhesive "
           "equilibrium with equal families at the initial approach, contact density from alpha, rho = 120 um")
    return r


def run_dataset(run: AsperityRun):
    """The time series as a CF dataset."""
    import xarray as xr  # heavy: imported where used

    dims = ("time",)
    variables = {
        "displacement": (run.states[0], "m", "tangential displacement x"),
        "speed": (run.states[1], "m/s", "tangential speed x'"),
        "normal_displacement": (run.states[2], "m", "normal displacement y (0 at first contact)"),
        "approach": (run.approach, "m", "relative approach dh"),
        "friction": (run.friction, "N", "friction force F_t(t) (eq. 20)"),
        "normal_force": (run.normal_force, "N", "normal force F_n(t) (eq. 20)"),
        "deformation_friction": (run.deformation_friction, "N", "deformation part (A_t/A_n) F_n"),
        "normal_area": (run.normal_area, "m^2", "real contact area A_n"),
        "stuck": (run.mode == STICK, "1", "1 while stuck"),
    }
    data = {k: (dims, np.asarray(v), {"units": u, "long_name": n}) for k, (v, u, n) in variables.items()}
    data["stuck"] = (dims, (run.mode == STICK).astype("i1"), {"units": "1", "long_name": "1 while stuck"})
    return xr.Dataset(data, coords={"time": (dims, run.time, ELAPSED_TIME_ATTRS)},
                      attrs={"title": f"faultslip asperity run: {run.model.name}", "Conventions": "CF-1.8",
                             "method": run.method, "status": run.status, "status_reason": run.reason,
                             **{k: v for k, (v, _) in run.model.describe().items()}})




def statistics_difference(first: "Response", second: "Response") -> float:
    """The largest relative difference of the response's statistics (stick fraction, mean friction, mean
    deformation friction) between two runs, each against the second's value (at least 0.01: a stick fraction
    of 0 against 0.001 is a difference of 0.1, not of infinity)."""
    pairs = ((first.stick_fraction, second.stick_fraction), (first.mean_friction, second.mean_friction),
             (first.mean_deformation_friction, second.mean_deformation_friction))
    return max(abs(a - b) / max(abs(b), 0.01) for a, b in pairs if math.isfinite(a) and math.isfinite(b))


def converged_run(model: AsperityModel, duration: float, method: str, tolerance: float):
    """Converge or declare: the run at the loosest of :data:`CONVERGENCE_RTOLS` whose statistics agree with the
    next tighter run's to ``tolerance``, and that difference as the numerical error; where even the tightest
    pair differs by more, the tightest run with the difference declared (never 0: issue 42).

    Parameters
    ----------
    model : AsperityModel
        The slider.
    duration : float
        Simulated time (s).
    method : str
        asperity_quasistatic or asperity_LSODA.
    tolerance : float
        The relative error asked of the statistics.

    Returns
    -------
    tuple
        (the run, its numerical error (relative), whether it met ``tolerance``).
    """
    run = simulate(model, duration, method, rtol=CONVERGENCE_RTOLS[0])
    for tighter in CONVERGENCE_RTOLS[1:]:
        finer = simulate(model, duration, method, rtol=tighter)
        if run.status != "ok" or finer.status != "ok":
            return finer if finer.status != "ok" else run, math.inf, False
        error = statistics_difference(analyse(run), analyse(finer))
        if error <= tolerance:
            return finer, error, True
        run = finer
    return run, error, False
