"""The spring-slider system (seed 003 Fig. 2-1; SPEC §1).

A slider of mass M under normal load W rests on a platform driven at speed
V. A spring K and a dashpot C (to the ground) hold it back; an optional
radiation damper eta resists the sliding speed u = V - x' (quasi-dynamic
faults). With x the displacement from the unloaded spring:

* stick: x' = V while the holding force K x + C V stays below W mu_s;
* slip:  M x'' + C x' + K x = W mu(u) + eta u, until u returns to 0 with the
  holding force inside the static limit.

At fault scale every quantity is per unit fault area: K in Pa/m, W the
normal stress in Pa, M = rho D in kg/m^2, C and eta in Pa s/m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from faultslip.dynamics.spring_slider import closed_form
from faultslip.errors import InputError
from faultslip.friction.laws import ConstantKinetic, ConstantStatic, LinearKinetic, RateLaw, TimeOfStickLaw
from faultslip.friction.materials import Preset, get_preset
from faultslip.units import STANDARD_GRAVITY, takes_units, to_si
from dataclasses import replace

#: SI unit of each dimensional attribute, lab scale / fault scale.
SI_UNITS = {
    "lab": {"mass": "kg", "stiffness": "N/m", "dashpot": "N*s/m", "normal_load": "N", "force": "N"},
    "fault": {"mass": "kg/m^2", "stiffness": "Pa/m", "dashpot": "Pa*s/m", "normal_load": "Pa", "force": "Pa"},
}


@takes_units(alternative_from=("scale", ("lab", "fault")), mass="mass|mass_per_area",
             stiffness="stiffness|stress_per_length", normal_load="force|pressure", platform_speed="speed",
             dashpot="damping|stress_damping", radiation_damper="damping|stress_damping")
@dataclass(frozen=True)
class SliderSystem:
    """A spring-slider with its friction laws; all attributes in SI.

    Build one with :meth:`from_preset` (a Table I laboratory scene) or
    :meth:`from_fault` (one slider per unit fault area), or directly from SI
    floats (``scale`` says whether W is a force in N or a stress in Pa).

    Parameters
    ----------
    mass : float
        M (kg; kg/m^2 per unit fault area).
    stiffness : float
        K (N/m; Pa/m per unit area).
    normal_load : float
        W (N; the effective normal stress in Pa per unit area).
    platform_speed : float
        V (m/s; the tectonic slip rate on a fault).
    static_law, kinetic_law : friction laws
        The static law (:class:`RateLaw`, :class:`ConstantStatic`, :class:`TimeOfStickLaw`) and the kinetic law
        (:class:`ConstantKinetic`, :class:`LinearKinetic`, :class:`PolynomialKinetic`, :class:`CallableKinetic`).
    dashpot, radiation_damper : float
        Damping coefficients (N s/m; Pa s/m per unit area).
    scale : str
        ``lab`` or ``fault``: whether W is a force or a stress.
    name : str
        A name for reports.
    info : dict
        Where the values came from (reports quote it).
    """

    mass: float
    stiffness: float
    normal_load: float
    platform_speed: float
    static_law: object
    kinetic_law: object
    dashpot: float = 0.0
    radiation_damper: float = 0.0
    scale: str = "lab"
    name: str = "slider"
    info: dict = field(default_factory=dict, compare=False)

    def __post_init__(self):
        for key in ("mass", "stiffness", "normal_load", "platform_speed"):
            value = getattr(self, key)
            if not (np.isfinite(value) and value > 0):
                raise InputError(f"{key.replace('_', ' ')} must be positive, got {value!r} in {self.name}")
        for key in ("dashpot", "radiation_damper"):
            if not np.isfinite(getattr(self, key)):
                raise InputError(f"{key.replace('_', ' ')} must be finite in {self.name}")
        if self.radiation_damper < 0:
            raise InputError(f"radiation damper must be non-negative, got {self.radiation_damper} in {self.name}")
        if self.scale not in SI_UNITS:
            raise InputError(f"scale must be 'lab' or 'fault', got {self.scale!r}")

    # --- constructors ---
    @classmethod
    def from_preset(
        cls,
        preset: str | Preset,
        *,
        platform_speed=None,
        loading_rate=None,
        damping_ratio: float = 0.0,
        kinetic_slope=None,
        normal_load=None,
        stiffness=None,
    ) -> "SliderSystem":
        """A laboratory scene from a seed 003 Table I preset.

        W and K come from the table (or the overrides), M = W/g with
        g = 9.80665 m/s^2, the dashpot from ``damping_ratio`` as
        C = 2 zeta sqrt(K M), and the kinetic law is mu_m + beta (V - x')
        with beta = ``kinetic_slope`` (default 0). Give the drive as
        ``platform_speed`` or as ``loading_rate`` (theta_dot = K V / W).
        """
        preset = get_preset(preset) if isinstance(preset, str) else preset
        law = preset.require_stick_slip()
        load = preset.normal_load if normal_load is None else to_si(normal_load, "force", "normal load")
        spring = preset.stiffness if stiffness is None else to_si(stiffness, "stiffness", "stiffness")
        if load is None or spring is None:
            raise InputError(f"preset {preset.name} has no apparatus; give normal_load and stiffness")
        mass = load / STANDARD_GRAVITY
        speed = _drive(platform_speed, loading_rate, spring, load, preset.name)
        _check_damping_ratio(damping_ratio, preset.name)
        beta = 0.0 if kinetic_slope is None else to_si(kinetic_slope, "slowness", "kinetic slope beta")
        kinetic = LinearKinetic(law.mu_m, beta) if beta else ConstantKinetic(law.mu_m)
        return cls(
            mass=mass,
            stiffness=spring,
            normal_load=load,
            platform_speed=speed,
            static_law=law,
            kinetic_law=kinetic,
            dashpot=float(closed_form.dashpot_for_damping_ratio(damping_ratio, spring, mass)),
            scale="lab",
            name=preset.name,
            info={"preset": preset.name, "damping_ratio_input": damping_ratio},
        )

    @classmethod
    def from_fault(cls, fault, *, radiation_damping: bool | None = None, slip_rate=None) -> "SliderSystem":
        """One slider per unit fault area from a :class:`faultslip.fault.scaling.Fault`.

        K = G/D, W = sigma_n, M = rho D, a dashpot giving the fault's damping
        ratio, and (if enabled) the radiation damper eta = G / (2 c_s).
        """
        law = fault.rate_law
        stiffness = fault.stiffness
        mass = fault.mass_per_area
        use_radiation = fault.radiation_damping if radiation_damping is None else radiation_damping
        eta = fault.radiation_damper if use_radiation else 0.0
        if use_radiation and eta == 0.0:  # enabled here though not on the fault: eta = G / (2 c_s)
            eta = fault.shear_modulus / (2.0 * fault.shear_wave_speed)
        speed = fault.slip_rate if slip_rate is None else to_si(slip_rate, "speed", "slip rate")
        return cls(
            mass=mass,
            stiffness=stiffness,
            normal_load=fault.effective_normal_stress,
            platform_speed=speed,
            static_law=law,
            kinetic_law=ConstantKinetic(law.mu_m),
            dashpot=float(closed_form.dashpot_for_damping_ratio(fault.damping_ratio, stiffness, mass)),
            radiation_damper=eta,
            scale="fault",
            name=fault.name,
            info={"lithology": fault.lithology},
        )

    def with_(self, **changes) -> "SliderSystem":
        """A copy with SI attributes changed (e.g. another platform speed)."""

        return replace(self, **changes)

    def at_loading_rate(self, loading_rate: float) -> "SliderSystem":
        """The same system driven at another loading rate theta_dot (1/s)."""
        return self.with_(platform_speed=float(closed_form.platform_speed(self.stiffness, loading_rate, self.normal_load)))

    # --- derived quantities ---
    @property
    def units(self) -> dict:
        return SI_UNITS[self.scale]

    @cached_property  # frozen: derived values never go stale (with_() makes a new system)
    def loading_rate(self) -> float:
        return float(closed_form.loading_rate(self.stiffness, self.platform_speed, self.normal_load))

    @cached_property
    def natural_frequency(self) -> float:
        return math.sqrt(self.stiffness / self.mass)

    @cached_property
    def kinetic_slope(self) -> float:
        """beta of the kinetic law at rest (s/m)."""
        return float(self.kinetic_law.slope)

    @cached_property
    def viscous_coefficient(self) -> float:
        """C + beta W + eta: the slip phase's damping coefficient (linear laws)."""
        return self.dashpot + self.kinetic_slope * self.normal_load + self.radiation_damper

    @cached_property
    def damping_ratio(self) -> float:
        """zeta = (C + beta W + eta) / (2 sqrt(K M)) (seed 003 under eq. 2-8, plus radiation damping)."""
        return self.viscous_coefficient / (2.0 * math.sqrt(self.stiffness * self.mass))

    @cached_property
    def mu_m(self) -> float:
        """Kinetic friction at vanishing sliding speed."""
        return float(self.kinetic_law.mu_m)

    @cached_property
    def is_linear(self) -> bool:
        """Linear slip phase: constant or linear kinetic law (exact cycle applies)."""
        return bool(self.kinetic_law.is_linear)

    @cached_property
    def error_calibrated(self) -> bool:
        """Whether the event-driven integrators' declared error was fitted on this kind of kinetic law (a law
        the calibration never drew is checked run by run: faultslip.dynamics.methods.refinement_check)."""
        return bool(getattr(self.kinetic_law, "error_calibrated", False))

    @cached_property
    def rate_static_friction(self) -> float | None:
        """mu_s at this loading rate, for static laws that do not depend on stick time."""
        if self.static_law.depends_on_stick_time:
            return None
        return float(self.static_law.limit(self.loading_rate))

    @cached_property
    def static_excess(self) -> float | None:
        """mu_s - mu_m at this loading rate (None for a time-of-stick law)."""
        mu_s = self.rate_static_friction
        return None if mu_s is None else mu_s - self.mu_m

    @cached_property
    def dimensionless_rate(self) -> float | None:
        """epsilon = theta_dot / (omega_n (mu_s - mu_m)); see :func:`closed_form.dimensionless_rate`."""
        excess = self.static_excess
        if excess is None or excess <= 0:
            return None
        return float(closed_form.dimensionless_rate(self.loading_rate, self.natural_frequency, excess))

    def holding_force(self, displacement):
        """Force the static friction must supply to keep the slider stuck: K x + C V."""
        return self.stiffness * displacement + self.dashpot * self.platform_speed

    def describe(self) -> dict:
        """SI attributes with units, for reports and dataset attributes."""
        u = self.units
        return {
            "mass": (self.mass, u["mass"]),
            "stiffness": (self.stiffness, u["stiffness"]),
            "dashpot": (self.dashpot, u["dashpot"]),
            "radiation_damper": (self.radiation_damper, u["dashpot"]),
            "normal_load": (self.normal_load, u["normal_load"]),
            "platform_speed": (self.platform_speed, "m/s"),
            "loading_rate": (self.loading_rate, "1/s"),
            "damping_ratio": (self.damping_ratio, "1"),
        }


def _check_damping_ratio(zeta, name):
    if not (np.isfinite(zeta) and -1.0 < zeta < 1.0):
        raise InputError(f"damping ratio must lie in (-1, 1) for an oscillating slip phase, got {zeta} in {name}")


def _drive(platform_speed, loading_rate, stiffness, normal_load, name):
    if (platform_speed is None) == (loading_rate is None):
        raise InputError(f"give exactly one of platform speed or loading rate for {name}")
    if platform_speed is not None:
        speed = to_si(platform_speed, "speed", "platform speed")
    else:
        rate = to_si(loading_rate, "rate", "loading rate")
        speed = float(closed_form.platform_speed(stiffness, rate, normal_load))
    if not speed > 0:
        raise InputError(f"platform speed must be positive, got {speed:g} m/s in {name}")
    return speed


def static_law_from_spec(spec: dict):
    """Build a static law from a scene's ``[friction]`` table entries (SI)."""
    kind = spec.get("kind", "rate")
    if kind == "rate":
        return RateLaw(spec["mu_so"], spec["mu_m"], spec.get("b", 0.0), spec.get("d", 1.0))
    if kind == "constant":
        return ConstantStatic(spec["mu_s"])
    if kind == "time_of_stick":
        return TimeOfStickLaw(spec["mu_lower"], spec["mu_upper"], spec["growth_rate"])
    raise InputError(f"unknown static friction law {kind!r}; allowed: rate, constant, time_of_stick")
