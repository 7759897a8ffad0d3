"""Scaling the spring-slider to a strike-slip fault (seed 003 §5-2).

An elastic zone of half-width D on each side of the fault is treated as a
pure-shear block and reduced to one slider per unit fault area:

* stiffness :math:`K = G/D` (seed eq. 5-3), in Pa/m;
* normal load :math:`W = \\sigma_n`, the effective normal stress, in Pa; the
  seed derives it from an upper bound on shear stress, :math:`\\sigma_n = \\tau/\\mu_{so}`;
* platform speed :math:`V` = the tectonic slip rate, so :math:`\\dot\\theta = K V/\\sigma_n`.

Then the amplitude of seed eq. 2-19 approximates the slip per earthquake and
:math:`T = \\alpha / V` (seed eq. 5-5) its recurrence period. faultslip reports the slip of the
event itself, the relative sliding :math:`\\int u\\,dt = V T` (``slip_per_event``), beside the
seeds' :math:`\\alpha = x_1 - x_2` (``stress_drop_slip``); at fault scale they agree to
:math:`V t_{slip}/\\alpha \\sim 10^{-8}` (24 s of slip at 2 in/yr for 1906).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields

import numpy as np

from faultslip.dynamics.spring_slider import closed_form

from faultslip import ranges
from faultslip.dynamics.spring_slider.critical import critical_dimensionless_rate, solve_rate_law_critical
from faultslip.dynamics.kernel import cell_kernel
from faultslip.dynamics.methods import DEFAULT_TOLERANCE, solve
from faultslip.dynamics.spring_slider.slider import SliderSystem
from faultslip.intervals import percentile_interval
from faultslip.errors import InputError
from faultslip.fault import empirical
from faultslip.friction.laws import RateLaw
from faultslip.friction.materials import MaterialChoice, resolve_material
from faultslip.io.report import Report
from faultslip.units import quantity, si_unit, takes_units, to_si

#: Constant of the moment magnitude, Mw = (2/3)(log10 M0[N m] - 9.1): the
#: IASPEI (2013) standard. Hanks & Kanamori (1979) is equivalent to 9.05; pass
#: ``constant=9.05`` to :func:`moment_magnitude` to reproduce codes that use it.
MW_CONSTANT = 9.1
#: Default rock density for the slider mass per unit area, M = rho D.
DEFAULT_DENSITY = 2700.0  # kg/m^3


def fault_stiffness(shear_modulus, zone_width):
    r"""Stiffness per unit fault area :math:`K = G/D` in Pa/m (seed 003 eq. 5-3)."""
    return shear_modulus / zone_width


def normal_stress_from_shear_stress(shear_stress, mu_so):
    r"""Effective normal stress :math:`\sigma_n = \tau/\mu_{so}` in Pa (seed 003 §5-2).

    The seed takes :math:`\tau` as the upper bound of shear stress the fault
    can hold, i.e. the static strength :math:`\mu_{so}\sigma_n`.
    """
    return shear_stress / mu_so


@takes_units(shear_modulus="pressure", rupture_length="length", seismogenic_depth="length", slip="length")
def seismic_moment(shear_modulus, rupture_length, seismogenic_depth, slip):
    r"""Seismic moment :math:`M_0 = G L H \bar u` in N m (Aki 1966).

    Parameters
    ----------
    shear_modulus : float or array_like
        G (Pa).
    rupture_length, seismogenic_depth : float or array_like
        L and H (m).
    slip : float or array_like
        Average slip (m).

    Returns
    -------
    float or ndarray
        M0 (N m).
    """
    return shear_modulus * rupture_length * seismogenic_depth * slip


@takes_units(seismic_moment="moment")
def moment_magnitude(seismic_moment, constant=MW_CONSTANT):
    r"""Moment magnitude :math:`M_w = \tfrac{2}{3}(\log_{10} M_0 - 9.1)`, :math:`M_0` in N m.

    The constant 9.1 is the IASPEI (2013) standard; see :data:`MW_CONSTANT`.

    Parameters
    ----------
    seismic_moment : float or array_like
        M0 (N m).
    constant : float
        The constant of the definition.

    Returns
    -------
    float or ndarray
        Mw.
    """
    return (2.0 / 3.0) * (np.log10(seismic_moment) - constant)


def shear_wave_speed(shear_modulus, density):
    r"""Shear-wave speed :math:`c_s = \sqrt{G/\rho}` in m/s of the same elastic medium.

    faultslip's default: with the slider mass :math:`M = \rho D` and :math:`K = G/D` the
    radiation damper then gives the damping ratio :math:`\eta/(2\sqrt{KM}) = 1/4` exactly,
    whatever G, rho and D. A c_s taken from elsewhere (3.3 km/s beside G = 0.25e6 bar and
    rho = 2700 kg/m^3, whose own c_s is 3.04 km/s) would mix two media.
    """
    return np.sqrt(shear_modulus / density)


def radiation_damper(shear_modulus, shear_wave_speed):
    r"""Radiation damper per unit area :math:`\eta = G / (2 c_s)` in Pa s/m (quasi-dynamic approximation).

    Rice (1993), Spatio-temporal complexity of slip on a fault, JGR 98(B6).
    """
    return shear_modulus / (2.0 * shear_wave_speed)


def friction_drop_for_slip(observed_slip, normal_stress, stiffness, loading_rate, b, d, damping_ratio=0.0):
    r"""Invert eq. 2-19 for :math:`\mu_{so} - \mu_m` from an observed slip per event.

    With :math:`q = \alpha K / (\sigma_n (1 + e^{-\lambda\pi}))` the required
    :math:`\mu_s - \mu_m`, eq. 2-18 gives
    :math:`\mu_{so} - \mu_m = q / (1 - q\,b\,\dot\theta^d)`. In the seed's
    low-rate, light-damping form (b = 0, :math:`\zeta = 0`) this is
    :math:`\alpha K/(2\sigma_n)` (seed 003 §5-2, granite). Returns NaN where
    no friction drop can produce the slip (:math:`q\,b\,\dot\theta^d \ge 1`).
    """
    required_excess = observed_slip * stiffness / (normal_stress * closed_form.overshoot_factor(damping_ratio))
    rate_term = b * loading_rate**d
    denominator = 1.0 - required_excess * rate_term
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(denominator > 0, required_excess / np.where(denominator > 0, denominator, 1.0), np.nan)


_QUANTITY_FIELDS = {
    "shear_modulus": ("pressure", "shear modulus"),
    "zone_width": ("length", "elastic-zone width"),
    "normal_stress": ("pressure", "normal stress"),
    "shear_stress": ("pressure", "shear stress"),
    "slip_rate": ("speed", "slip rate"),
    "rupture_length": ("length", "rupture length"),
    "seismogenic_depth": ("length", "seismogenic depth"),
    "density": ("density", "density"),
    "shear_wave_speed": ("speed", "shear-wave speed"),
}
_NUMBER_FIELDS = {"mu_so", "mu_m", "b", "d", "damping_ratio", "dip", "rake"}


@dataclass(frozen=True)
class Fault:
    """A strike-slip fault reduced to one slider per unit area (seed 003 §5-2).

    Quantities accept strings with units ("13 mi"), pint Quantities, and are
    stored in SI. Give either ``normal_stress`` or ``shear_stress`` (the
    seed's route, :math:`\\sigma_n = \\tau/\\mu_{so}`).

    ``lithology`` (a lithology such as ``"granodiorite"`` or a preset such as
    ``"granodiorite_water"``) supplies G and the friction law (mu_so, mu_m, b,
    d) unless they are given. Without a friction preset (e.g. granite) give
    mu_so and mu_m; b then defaults to 0, a rate-independent static friction.

    Parameters
    ----------
    slip_rate : str, Quantity or float
        Tectonic slip rate V ("2 in/yr"; m/s as a float).
    zone_width : str, Quantity or float
        Elastic-zone half-width D ("13 mi"; m); K = G / D.
    shear_modulus : str, Quantity or float, optional
        G ("0.25e6 bar"; Pa); the lithology's otherwise.
    normal_stress, shear_stress : str, Quantity or float, optional
        Effective normal stress, or shear stress tau with sigma_n = tau / mu_so (Pa); give one.
    lithology : str, optional
        A lithology, a Table I preset or a saved fit (``faultslip materials``).
    mu_so, mu_m, b, d : float, optional
        The rate law of eq. 2-18 (dimensionless; b in s^d), replacing the lithology's.
    rupture_length, seismogenic_depth : str, Quantity or float, optional
        L and H (m): the seismic moment M0 = G L W u and Mw, with W = H / sin(dip) the down-dip width.
    dip, rake : float
        Degrees (90 and 180 by default: vertical, dextral). The dip sets the rupture's width down dip, W = H / sin(dip);
        the rake its slip type for the empirical relations. The block's stiffness G / D keeps the elastic-zone
        width D whatever the dip: the same geometric choice as for a vertical fault.
    damping_ratio : float
        Damping ratio of the slider's dashpot.
    radiation_damping : bool
        Add the radiation damper G / (2 c_s).
    density : str, Quantity or float
        Rock density rho (kg/m^3): the mass per unit area M = rho D.
    shear_wave_speed : str, Quantity or float, optional
        c_s (m/s; sqrt(G / rho) otherwise).
    name : str
        A name for reports.
    material : MaterialChoice, optional
        A resolved material (internal; ``lithology`` resolves one).
    """

    slip_rate: object
    zone_width: object
    shear_modulus: object = None
    normal_stress: object = None
    shear_stress: object = None
    lithology: str | None = None
    mu_so: float | None = None
    mu_m: float | None = None
    b: float | None = None
    d: float | None = None
    rupture_length: object = None
    seismogenic_depth: object = None
    dip: float = 90.0
    rake: float = 180.0
    damping_ratio: float = 0.0
    radiation_damping: bool = False
    density: object = f"{DEFAULT_DENSITY} kg/m^3"
    shear_wave_speed: object = None  # default sqrt(G / rho): the medium's own (see shear_wave_speed())
    name: str = "fault"
    material: MaterialChoice | None = field(default=None, compare=False, repr=False)

    def __post_init__(self):
        set_ = lambda key, value: object.__setattr__(self, key, value)  # noqa: E731 (frozen dataclass)
        for key, (kind, label) in _QUANTITY_FIELDS.items():
            value = getattr(self, key)
            if value is not None:
                set_(key, to_si(value, kind, label))
        for key in _NUMBER_FIELDS:
            value = getattr(self, key)
            if value is not None:
                set_(key, to_si(value, "dimensionless", key))

        material = resolve_material(self.lithology) if self.lithology else None
        set_("material", material)
        if self.shear_modulus is None:
            if material is None or material.shear_modulus is None:
                where = f"lithology {self.lithology!r} has no shear modulus" if self.lithology else "no lithology given"
                raise InputError(f"shear modulus is required ({where}); give it, e.g. --shear-modulus '0.25e6 bar'")
            set_("shear_modulus", material.shear_modulus)
        law = material.rate_law if material is not None else None
        for key in ("mu_so", "mu_m", "b", "d"):
            if getattr(self, key) is None:
                if law is not None:
                    set_(key, getattr(law, key))
                elif key == "mu_so":
                    raise InputError(f"mu_so is required ({self._no_preset()}); give it, e.g. --mu-so 0.65")
                elif key == "mu_m":
                    continue  # only the inverse (which computes mu_m) may go without it
                else:
                    set_(key, 0.0 if key == "b" else 1.0)

        if self.shear_wave_speed is None:
            ranges.check("shear_modulus", self.shear_modulus)
            ranges.check("density", self.density)
            set_("shear_wave_speed", float(shear_wave_speed(self.shear_modulus, self.density)))
        for key in ("shear_modulus", "zone_width", "slip_rate", "density", "shear_wave_speed", "rupture_length",
                    "seismogenic_depth", "normal_stress", "shear_stress", "mu_so", "mu_m", "b", "d", "damping_ratio"):
            if getattr(self, key) is not None:
                ranges.check(key, getattr(self, key))
        if not 0.0 < self.dip <= 90.0:
            raise InputError(f"the dip must lie above 0 and at most 90 degrees, got {self.dip:g}")
        if not -180.0 <= self.rake <= 180.0:
            raise InputError(f"the rake must lie from -180 to 180 degrees, got {self.rake:g}")
        if (self.normal_stress is None) == (self.shear_stress is None):
            raise InputError("give exactly one of normal stress or shear stress (sigma_n = tau / mu_so)")
        RateLaw(self.mu_so, self.mu_so if self.mu_m is None else self.mu_m, self.b, self.d)  # validates

    def _no_preset(self) -> str:
        return f"lithology {self.lithology!r} has no friction preset" if self.lithology else "no lithology given"

    # --- derived quantities (SI) ---
    @property
    def rate_law(self) -> RateLaw:
        if self.mu_m is None:
            raise InputError(f"mu_m is required ({self._no_preset()}); give it, e.g. --mu-m 0.55")
        return RateLaw(self.mu_so, self.mu_m, self.b, self.d)

    @property
    def effective_normal_stress(self) -> float:
        if self.normal_stress is not None:
            return self.normal_stress
        return normal_stress_from_shear_stress(self.shear_stress, self.mu_so)

    @property
    def stiffness(self) -> float:
        return fault_stiffness(self.shear_modulus, self.zone_width)

    @property
    def rupture_width(self) -> float | None:
        """W = H / sin(dip), the rupture's width down dip (m): what its moment and area take."""
        if self.seismogenic_depth is None:
            return None
        return self.seismogenic_depth / math.sin(math.radians(self.dip))

    @property
    def loading_rate(self) -> float:
        return closed_form.loading_rate(self.stiffness, self.slip_rate, self.effective_normal_stress)

    @property
    def mass_per_area(self) -> float:
        """M = rho D, needed only by the dynamics (the closed form at low rate needs no mass)."""
        return self.density * self.zone_width

    @property
    def natural_frequency(self) -> float:
        return float(closed_form.natural_frequency(self.stiffness, self.mass_per_area))

    @property
    def radiation_damper(self) -> float:
        return radiation_damper(self.shear_modulus, self.shear_wave_speed) if self.radiation_damping else 0.0

    @property
    def total_damping_ratio(self) -> float:
        """The given damping ratio plus that of the radiation damper, eta / (2 sqrt(K M))."""
        extra = self.radiation_damper / (2.0 * math.sqrt(self.stiffness * self.mass_per_area))
        return self.damping_ratio + extra

    def with_(self, **changes) -> "Fault":
        """A copy with some inputs changed; changed quantities need units like any input."""
        keep = {}
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name == "material":
                continue
            if f.name in _QUANTITY_FIELDS and value is not None:
                unit = si_unit(_QUANTITY_FIELDS[f.name][0])
                # a scalar as text in its SI unit: read back exactly, without building pint's registry
                value = f"{float(value)!r} {unit}" if np.ndim(value) == 0 else quantity(value, unit)
            keep[f.name] = value
        if changes.get("shear_stress") is not None:
            keep["normal_stress"] = None
        if changes.get("normal_stress") is not None:
            keep["shear_stress"] = None
        keep.update(changes)
        return Fault(**keep)

    # --- predictions ---
    def estimate(self, method: str = "auto", tolerance: float | None = None) -> "FaultEstimate":
        """Slip and recurrence (seed 003 eqs. 2-19, 5-4, 5-5) by the cheapest sufficient method.

        ``method="auto"`` picks the closed form where its error model meets ``tolerance``
        (default 1e-6 relative) and the exact cycle otherwise; the estimate records which.
        """
        if self.material is not None and self.material.preset is not None and not self.material.preset.stick_slip:
            if self.mu_so == self.mu_m:
                self.material.preset.require_stick_slip()
        self.rate_law.require_stick_slip(f"a stick-slip prediction of {self.name}")
        return FaultEstimate.from_fault(self, method, tolerance)

    def infer_kinetic_friction(self, observed_slip) -> "FaultInverse":
        """The mu_m that makes eq. 2-19 reproduce an observed slip (seed 003 §5-2, granite)."""
        slip = ranges.check("observed_slip", to_si(observed_slip, "length", "observed slip"))
        return FaultInverse.from_fault(self, slip)


def _inputs_section(r: Report, f: Fault) -> Report:
    """The inputs every fault report starts with."""
    r.section("Inputs")
    if f.lithology:
        r.add("lithology", f.lithology, label="lithology / preset")
    r.add("shear_modulus", f.shear_modulus, "Pa", "shear modulus G", also=("bar",))
    r.add("zone_width", f.zone_width, "m", "elastic-zone width D", also=("km", "mi"))
    if f.shear_stress is not None:
        r.add("shear_stress", f.shear_stress, "Pa", "shear stress tau", also=("bar",))
    r.add("slip_rate", f.slip_rate, "m/s", "slip rate V", also=("mm/yr", "in/yr"))
    return r


def fitted_draws(fault, method="auto", tolerance=None):
    """(slip per event (m), recurrence (s)) for each of the bootstrap samples stored with a user fit that is
    ``fault``'s material (vectorised), or None: a bundled preset has none, and a fault whose fitted constants
    were overridden no longer has the fit's uncertainty."""
    material = fault.material
    stored = None
    if material is not None and material.preset is not None and isinstance(material.preset.printed, dict):
        stored = material.preset.printed.get("registry")
    if not stored or not stored.get("bootstrap"):
        return None
    law = material.preset.rate_law
    if (fault.mu_so, fault.mu_m, fault.b, fault.d) != (law.mu_so, law.mu_m, law.b, law.d):
        return None
    samples = np.asarray(stored["bootstrap"], dtype=float)
    mu_so, mu_m, b, d = samples.T
    stiffness, load, speed = fault.stiffness, fault.effective_normal_stress, fault.slip_rate
    if fault.shear_stress is not None:  # sigma_n = tau / mu_so moves with each sample's mu_so
        load = fault.shear_stress / mu_so
    omega_n = math.sqrt(stiffness / fault.mass_per_area)
    zeta = fault.total_damping_ratio
    eps_c = float(critical_dimensionless_rate(zeta))
    critical = solve_rate_law_critical(omega_n * eps_c, mu_so, mu_m, b, d)
    outputs = cell_kernel(stiffness, load, speed, omega_n, zeta, eps_c, critical, mu_so, mu_m, b, d, np.nan,
                          method=method if method in ("closed_form", "exact_cycle") else "auto",
                          tolerance=DEFAULT_TOLERANCE if tolerance is None else tolerance)
    return np.asarray(outputs[0], float), np.asarray(outputs[1], float)


def _propagated_uncertainty(fault, method, tolerance, slip_estimate=math.nan, period_estimate=math.nan) -> dict:
    """95 % ranges of slip and recurrence from a user fit's bootstrap samples (:func:`fitted_draws`), each
    containing its estimate (:func:`faultslip.intervals.percentile_interval`)."""
    draws = fitted_draws(fault, method, tolerance)
    if draws is None:
        return {}
    slip, period = draws
    return {"slip_per_event_95": tuple(percentile_interval(slip, slip_estimate)[:2]),
            "recurrence_period_95": tuple(percentile_interval(period, period_estimate)[:2]),
            "uncertainty_samples": int(slip.size)}


@dataclass(frozen=True)
class FaultEstimate:
    """Closed-form predictions for a :class:`Fault` (all SI)."""

    fault: Fault
    stiffness: float
    normal_stress: float
    loading_rate: float
    static_friction: float
    damping_ratio: float
    slip_per_event: float
    stress_drop_slip: float
    low_rate_amplitude: float
    recurrence_period: float
    stress_drop: float
    seismic_moment: float | None
    moment_magnitude: float | None
    method: str = "closed_form"
    method_reason: str = ""
    estimated_relative_error: float = float("nan")
    regime: str = "stick_slip"
    #: 95 % ranges carried from a fitted material's bootstrap samples (None for bundled presets)
    slip_per_event_95: tuple | None = None
    recurrence_period_95: tuple | None = None
    uncertainty_samples: int = 0

    #: The SI unit of each quantity ("": dimensionless), for :meth:`quantities`.
    UNITS = {"stiffness": "Pa/m", "normal_stress": "Pa", "loading_rate": "1/s", "static_friction": "",
             "damping_ratio": "", "slip_per_event": "m", "stress_drop_slip": "m", "low_rate_amplitude": "m",
             "recurrence_period": "s", "stress_drop": "Pa", "seismic_moment": "N*m", "moment_magnitude": ""}

    def quantities(self) -> dict:
        """Every predicted value as a pint Quantity: ``estimate.quantities()["recurrence_period"].to("yr")``."""
        return {name: quantity(getattr(self, name), unit or "dimensionless") for name, unit in self.UNITS.items()
                if getattr(self, name) is not None}

    def __getitem__(self, name: str):
        """One predicted value with its units, e.g. ``estimate["slip_per_event"].to("ft")``."""
        if name not in self.UNITS:
            raise KeyError(f"{name!r} is not a quantity of the estimate ({', '.join(self.UNITS)})")
        return self.quantities()[name]

    @classmethod
    def from_fault(cls, fault: Fault, method: str = "auto", tolerance: float | None = None) -> "FaultEstimate":
        law = fault.rate_law
        sigma = fault.effective_normal_stress
        stiffness = fault.stiffness
        rate = fault.loading_rate
        zeta = fault.total_damping_ratio
        solution = solve(SliderSystem.from_fault(fault), method=method,
                         tolerance=DEFAULT_TOLERANCE if tolerance is None else tolerance)
        cycle = solution.cycle
        slip = cycle.slip_per_event  # the relative sliding of the event: the slip of an earthquake
        moment = magnitude = None
        if fault.rupture_length is not None and fault.seismogenic_depth is not None:
            moment = float(seismic_moment(fault.shear_modulus, fault.rupture_length, fault.rupture_width, slip))
            magnitude = float(moment_magnitude(moment))
        return cls(
            fault=fault,
            stiffness=stiffness,
            normal_stress=sigma,
            loading_rate=rate,
            static_friction=float(law.static(rate)),
            damping_ratio=zeta,
            slip_per_event=slip,
            stress_drop_slip=cycle.stress_drop_slip,
            low_rate_amplitude=float(closed_form.low_rate_amplitude(sigma, stiffness, law.mu_so, law.mu_m)),
            recurrence_period=cycle.period,
            stress_drop=cycle.stress_drop,
            seismic_moment=moment,
            moment_magnitude=magnitude,
            method=solution.method,
            method_reason=solution.method_reason,
            estimated_relative_error=solution.estimated_relative_error,
            regime=cycle.regime,
            **_propagated_uncertainty(fault, method, tolerance, slip, cycle.period),
        )

    def empirical(self) -> list:
        """The slip per event and Mw beside W&C (1994) and Leonard (2010), strike-slip (needs L and H)."""
        if self.moment_magnitude is None:
            return []
        f = self.fault
        return empirical.compare(self.slip_per_event, self.moment_magnitude, f.rupture_length, f.rupture_width,
                                 empirical.slip_type_from_rake(f.rake))

    def report(self) -> Report:
        f = self.fault
        r = _inputs_section(Report(f"faultslip fault estimate: {f.name}"), f)
        r.add("mu_so", f.mu_so, label="mu_so")
        r.add("mu_m", f.mu_m, label="mu_m")
        r.add("b", f.b, f"s^{f.d:g}" if f.b else None, "rate coefficient b")
        r.add("d", f.d, label="rate exponent d")
        r.add("damping_ratio", self.damping_ratio, label="damping ratio zeta")
        if f.rupture_length is not None:
            r.add("rupture_length", f.rupture_length, "m", "rupture length L", also=("km", "mi"))
        if f.seismogenic_depth is not None:
            r.add("seismogenic_depth", f.seismogenic_depth, "m", "seismogenic depth H", also=("km",))
            if f.dip != 90.0:
                r.add("dip", f.dip, "degree", "dip").add("rake", f.rake, "degree", "rake")
                r.add("rupture_width", f.rupture_width, "m", "rupture width down dip W = H / sin(dip)", also=("km",))
                r.note(f"dipping at {f.dip:g} degrees: the moment and the empirical relations take W = H / sin(dip) = "
                       f"{f.rupture_width / 1e3:.4g} km; the block's stiffness G / D keeps the elastic-zone width D, "
                       "the same geometric choice as for a vertical fault")
        r.section("Method")
        r.add("method", self.method)
        r.add("method_reason", self.method_reason, label="why this method")
        r.add("estimated_relative_error", self.estimated_relative_error, label="estimated relative error")
        r.section("Predictions (seed 003 eqs. 2-18, 2-19, 5-3 to 5-5)")
        r.add("regime", self.regime)
        r.add("stiffness", self.stiffness, "Pa/m", "stiffness K = G/D", also=("psi/in",))
        r.add("normal_stress", self.normal_stress, "Pa", "normal stress sigma_n", also=("bar",))
        r.add("loading_rate", self.loading_rate, "1/s", "loading rate K V / sigma_n")
        r.add("static_friction", self.static_friction, label="static friction mu_s")
        r.add("slip_per_event", self.slip_per_event, "m", "slip per event, integral of u dt = V T", also=("ft",))
        if self.slip_per_event_95 is not None:
            r.add("slip_per_event_95", list(self.slip_per_event_95), "m", "slip per event, 95 % range")
        r.add("stress_drop_slip", self.stress_drop_slip, "m", "stress-drop slip alpha = x1 - x2 (eq. 2-19)",
              also=("ft",))
        r.add("low_rate_amplitude", self.low_rate_amplitude, "m", "eq. 5-4: 2 sigma_n D dmu / G", also=("ft",))
        r.add("recurrence_period", self.recurrence_period, "s", "recurrence period T", also=("yr",))
        if self.recurrence_period_95 is not None:
            r.add("recurrence_period_95", list(self.recurrence_period_95), "s", "recurrence period, 95 % range",
                  also=("yr",))
            r.note(f"95 % ranges carry the fitted friction law's uncertainty: {self.uncertainty_samples} bootstrap "
                   "fits of the laboratory data, each evaluated like the central estimate.")
        r.add("stress_drop", self.stress_drop, "Pa", "stress drop K alpha", also=("bar", "MPa"))
        if self.seismic_moment is not None:
            r.add("seismic_moment", self.seismic_moment, "N*m", "seismic moment M0 = G L H (slip per event)")
            r.add("moment_magnitude", self.moment_magnitude, label="moment magnitude Mw")
            r.note(f"Mw = (2/3)(log10 M0 - {MW_CONSTANT}) with M0 in N m (IASPEI 2013 standard).")
            empirical.add_to_report(r, self.empirical())
        r.note("A year is the Julian year, 365.25 d.")
        r.note("Model error against a 2-D fault: not declared for the seed's static-friction law, because the "
               "2-D fault (docs/fault_2d.md) carries rate-and-state friction; a rate-and-state scene of the same "
               "fault declares its one-slider model error against it (faultslip model-error).")
        if f.b == 0:
            r.note("No rate law (b = 0): static friction is taken as rate-independent, mu_s = mu_so.")
        return r


@dataclass(frozen=True)
class FaultInverse:
    """The kinetic friction implied by an observed slip per event."""

    fault: Fault
    observed_slip: float
    stiffness: float
    normal_stress: float
    loading_rate: float
    friction_drop: float
    kinetic_friction: float
    recurrence_period: float

    @classmethod
    def from_fault(cls, fault: Fault, slip: float) -> "FaultInverse":
        sigma = fault.effective_normal_stress
        stiffness = fault.stiffness
        rate = fault.loading_rate
        zeta = fault.total_damping_ratio
        # an observed slip is the event's sliding, alpha + V t_slip; eq. 2-19 inverts alpha alone
        slip_time = float(closed_form.slip_duration(stiffness, fault.mass_per_area, zeta))
        alpha = slip - fault.slip_rate * slip_time
        drop = float(friction_drop_for_slip(alpha, sigma, stiffness, rate, fault.b, fault.d, zeta))
        if not np.isfinite(drop):
            raise InputError(
                f"observed slip {slip:g} m is larger than the rate law allows at this loading rate; "
                "no friction drop reproduces it"
            )
        if drop > fault.mu_so:
            raise InputError(
                f"observed slip {slip:g} m needs a friction drop {drop:.3g} larger than mu_so = {fault.mu_so}; "
                "it cannot be reproduced"
            )
        return cls(fault, slip, stiffness, sigma, rate, drop, fault.mu_so - drop, slip / fault.slip_rate)

    def report(self) -> Report:
        f = self.fault
        r = _inputs_section(Report(f"faultslip inverse estimate: {f.name}"), f)
        r.add("observed_slip", self.observed_slip, "m", "observed slip per event", also=("ft",))
        r.add("mu_so", f.mu_so, label="mu_so")
        r.section("Inverse of eq. 2-19 (seed 003 §5-2)")
        r.add("stiffness", self.stiffness, "Pa/m", "stiffness K = G/D", also=("psi/in",))
        r.add("normal_stress", self.normal_stress, "Pa", "normal stress sigma_n", also=("bar",))
        r.add("loading_rate", self.loading_rate, "1/s", "loading rate K V / sigma_n")
        r.add("friction_drop", self.friction_drop, label="friction drop mu_so - mu_m")
        r.add("kinetic_friction", self.kinetic_friction, label="implied kinetic friction mu_m")
        r.add("recurrence_period", self.recurrence_period, "s", "recurrence period T = alpha/V", also=("yr",))
        r.note("A year is the Julian year, 365.25 d.")
        return r
