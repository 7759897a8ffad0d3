"""Friction laws: the static-friction rate law of seed 003 and its relatives.

All functions are pure and vectorised: numpy arrays and xarray objects pass
through unchanged in type (xarray by its arithmetic, so labels and dask
chunks survive).
"""

from __future__ import annotations

from dataclasses import dataclass

from faultslip.constants import STANDARD_GRAVITY
import numpy as np

from faultslip.errors import InputError
from faultslip.ranges import NON_NEGATIVE
from faultslip.units import takes_units


def static_friction_excess(loading_rate, mu_so, mu_m, b, d):
    r"""Excess of static over kinetic friction, :math:`\mu_s - \mu_m`.

    .. math::

        \mu_s - \mu_m = \frac{1}{1/(\mu_{so} - \mu_m) + b\,\dot\theta^{d}}
                      = \frac{\mu_{so} - \mu_m}{1 + (\mu_{so} - \mu_m)\, b\,\dot\theta^{d}}

    The second form is used: it is exact and gives 0 (not 0/0) when
    :math:`\mu_{so} = \mu_m`.

    Parameters
    ----------
    loading_rate : array_like
        :math:`\dot\theta = K V / W` in 1/s (seed 003 eq. 2-3).
    mu_so, mu_m : array_like
        Static friction as the loading rate tends to 0, and kinetic friction.
    b : array_like
        Rate coefficient in s^d.
    d : array_like
        Rate exponent (dimensionless).

    References
    ----------
    Seed 003 (Friction-induced oscillations in rock systems), eq. 2-18 and the
    note under its Table I, where ``a = 1/(mu_so - mu_m)``.
    """
    drop = mu_so - mu_m
    return drop / (1.0 + drop * b * loading_rate**d)


@takes_units(domains={"loading_rate": NON_NEGATIVE}, loading_rate="rate")  # 0: the limit mu_so
def static_friction(loading_rate, mu_so, mu_m, b, d):
    r"""Static friction coefficient at a loading rate (seed 003 eq. 2-18).

    .. math::

        \mu_s(\dot\theta) = \mu_m + \frac{1}{1/(\mu_{so} - \mu_m) + b\,\dot\theta^{d}}

    :math:`\mu_s \to \mu_{so}` as :math:`\dot\theta \to 0` and
    :math:`\mu_s \to \mu_m` as :math:`\dot\theta \to \infty`. See
    :func:`static_friction_excess` for units and references.

    Parameters
    ----------
    loading_rate : array_like
        theta_dot (1/s).
    mu_so, mu_m, b, d : array_like
        The rate law.

    Returns
    -------
    ndarray or float
        mu_s (dimensionless).
    """
    return mu_m + static_friction_excess(loading_rate, mu_so, mu_m, b, d)


def log_rate_coefficient(d):
    r"""Table I's ``c = d ln 10``: the exponent of the law written in log10 of the rate.

    :math:`b\dot\theta^d = b\,e^{c \log_{10}\dot\theta}` (seed 003, note under Table I).
    """
    return d * np.log(10.0)


@dataclass(frozen=True)
class RateLaw:
    """The static-friction rate law of seed 003 eq. 2-18 with its four constants.

    Attributes
    ----------
    mu_so : float
        Static friction as the loading rate tends to zero.
    mu_m : float
        Kinetic friction.
    b : float
        Rate coefficient, s^d. Zero makes static friction rate-independent.
    d : float
        Rate exponent.
    """

    mu_so: float
    mu_m: float
    b: float = 0.0
    d: float = 1.0

    def __post_init__(self):
        for name in ("mu_so", "mu_m", "b", "d"):
            value = getattr(self, name)
            if not np.isfinite(value):
                raise InputError(f"{name} must be a finite number, got {value!r}")
        if self.mu_m < 0:
            raise InputError(f"mu_m must be non-negative, got {self.mu_m}")
        if self.mu_so < self.mu_m:
            raise InputError(
                f"mu_so ({self.mu_so}) must not be below mu_m ({self.mu_m}): static friction is at least kinetic"
            )
        if self.b < 0:
            raise InputError(f"rate coefficient b must be non-negative, got {self.b}")
        if self.d <= 0:
            raise InputError(f"rate exponent d must be positive, got {self.d}")

    @property
    def friction_drop(self) -> float:
        """``mu_so - mu_m``; Table I's ``a`` is its reciprocal."""
        return self.mu_so - self.mu_m

    @property
    def stick_slip(self) -> bool:
        """Whether the law admits stick-slip at all (mu_so > mu_m)."""
        return self.mu_so > self.mu_m

    def static(self, loading_rate):
        """:math:`\\mu_s(\\dot\\theta)`, eq. 2-18."""
        return static_friction(loading_rate, self.mu_so, self.mu_m, self.b, self.d)

    def excess(self, loading_rate):
        """:math:`\\mu_s(\\dot\\theta) - \\mu_m`."""
        return static_friction_excess(loading_rate, self.mu_so, self.mu_m, self.b, self.d)

    #: A static law's limit depends on the loading rate, the stick time, or both.
    depends_on_stick_time = False

    def limit(self, loading_rate, stick_time=0.0):
        """Static limit mu_s that ends a stick phase (rate law: loading rate only)."""
        return self.static(loading_rate)

    def require_stick_slip(self, what: str = "this calculation") -> None:
        """Raise a clear error if mu_m >= mu_so, where stick-slip is required."""
        if not self.stick_slip:
            raise InputError(
                f"mu_m ({self.mu_m}) must be below mu_so ({self.mu_so}) for {what}: "
                "with no excess of static over kinetic friction there is no stick-slip"
            )


# --- static-friction laws: the limit W mu_s that ends a stick phase ---------


@dataclass(frozen=True)
class ConstantStatic:
    """A rate- and time-independent static friction coefficient.

    Parameters
    ----------
    mu_s : float
        The static friction coefficient (dimensionless).
    """

    mu_s: float

    def __post_init__(self):
        if not (np.isfinite(self.mu_s) and self.mu_s >= 0):
            raise InputError(f"static friction mu_s must be a non-negative number, got {self.mu_s!r}")

    depends_on_stick_time = False

    def limit(self, loading_rate, stick_time=0.0):
        return self.mu_s + 0.0 * np.asarray(loading_rate, dtype=float)


def time_of_stick_static_friction(stick_time, mu_lower, mu_upper, growth_rate):
    r"""Cameron's time-of-stick law (seed 002 eq. 2; SPEC §6).

    .. math:: \mu_s(t) = \mu_L + (\mu_u - \mu_L)(1 - e^{-c t})

    ``stick_time`` in s, ``growth_rate`` c in 1/s.
    """
    return mu_lower + (mu_upper - mu_lower) * -np.expm1(-growth_rate * stick_time)


@takes_units(growth_rate="rate")
@dataclass(frozen=True)
class TimeOfStickLaw:
    """Static friction that grows with time of stick (Cameron; seed 002 eq. 2).

    With a stick time of :math:`\\alpha/V` it gives a critical velocity
    :math:`V_c = c\\,\\alpha_m` (seed 002 eq. 9 and the limit below it).

    Parameters
    ----------
    mu_lower, mu_upper : float
        Static friction after no stick and after a long one (dimensionless).
    growth_rate : float
        c, the rate at which static friction grows with the time of stick (1/s).
    """

    mu_lower: float
    mu_upper: float
    growth_rate: float  # c, 1/s

    def __post_init__(self):
        if not (0 <= self.mu_lower <= self.mu_upper):
            raise InputError(
                f"time-of-stick law needs 0 <= mu_lower <= mu_upper, got {self.mu_lower} and {self.mu_upper}"
            )
        if not self.growth_rate > 0:
            raise InputError(f"time-of-stick growth rate c must be positive, got {self.growth_rate}")

    depends_on_stick_time = True

    def limit(self, loading_rate, stick_time=0.0):
        return time_of_stick_static_friction(stick_time, self.mu_lower, self.mu_upper, self.growth_rate)


# --- kinetic-friction laws: mu as a function of sliding speed u = V - x' -----


@dataclass(frozen=True)
class ConstantKinetic:
    """Kinetic friction independent of sliding speed.

    Parameters
    ----------
    mu_m : float
        The kinetic friction coefficient (dimensionless).
    """

    mu_m: float

    is_linear = True
    #: drawn by the event-driven integrators' calibration (faultslip.dynamics.methods.EventDriven)
    error_calibrated = True

    def __post_init__(self):
        if not (np.isfinite(self.mu_m) and self.mu_m >= 0):
            raise InputError(f"kinetic friction mu_m must be a non-negative number, got {self.mu_m!r}")

    @property
    def slope(self) -> float:
        return 0.0

    def __call__(self, sliding_speed):
        return self.mu_m + 0.0 * sliding_speed

    def derivative(self, sliding_speed):
        return 0.0 * sliding_speed


@takes_units(slope="slowness")
@dataclass(frozen=True)
class LinearKinetic:
    r"""Linear kinetic law :math:`\mu = \mu_m + \beta (V - \dot x)` (seed 003 eq. 2-7).

    ``slope`` is :math:`\beta` in s/m. :math:`\beta > 0` adds damping
    :math:`\beta W` to the slip phase; :math:`\beta < 0` (friction weakening
    with speed) removes it and can make the slip oscillation grow.

    Parameters
    ----------
    mu_m : float
        Kinetic friction at rest relative to the platform (dimensionless).
    slope : float
        beta (s/m): the change of friction per unit of the speed difference V - x'.
    """

    mu_m: float
    slope: float

    is_linear = True
    error_calibrated = True

    def __post_init__(self):
        if not (np.isfinite(self.mu_m) and self.mu_m >= 0 and np.isfinite(self.slope)):
            raise InputError(f"linear kinetic law needs finite mu_m >= 0 and slope, got {self.mu_m}, {self.slope}")

    def __call__(self, sliding_speed):
        return self.mu_m + self.slope * sliding_speed

    def derivative(self, sliding_speed):
        return self.slope + 0.0 * sliding_speed


@dataclass(frozen=True)
class PolynomialKinetic:
    r"""Polynomial kinetic law :math:`\mu(u) = \sum_k c_k u^k` (seed 002 eq. 22).

    ``coefficients`` are in increasing powers of the sliding speed u (m/s):
    ``c_k`` has units (s/m)^k. Seed 002 writes the same sextic in decreasing
    powers (its c_1 ... c_7).

    Parameters
    ----------
    coefficients : tuple of float
        c_0, c_1, ... in increasing powers of the sliding speed (c_k in (s/m)^k); mu is dimensionless.
    """

    coefficients: tuple

    is_linear = False
    error_calibrated = True

    def __post_init__(self):
        coefficients = tuple(float(c) for c in self.coefficients)
        if not coefficients or not all(np.isfinite(coefficients)):
            raise InputError("polynomial kinetic law needs at least one finite coefficient")
        object.__setattr__(self, "coefficients", coefficients)
        if coefficients[0] < 0:
            raise InputError(f"polynomial kinetic law: friction at rest c_0 must be non-negative, got {coefficients[0]}")

    @property
    def mu_m(self) -> float:
        return self.coefficients[0]

    @property
    def slope(self) -> float:
        return self.coefficients[1] if len(self.coefficients) > 1 else 0.0

    def __call__(self, sliding_speed):
        return np.polynomial.polynomial.polyval(sliding_speed, self.coefficients)

    def derivative(self, sliding_speed):
        deriv = np.polynomial.polynomial.polyder(self.coefficients) if len(self.coefficients) > 1 else [0.0]
        return np.polynomial.polynomial.polyval(sliding_speed, deriv)


class _CurveKinetic:
    """What every nonlinear kinetic law derives from its own values: mu_m = mu(0), the slope at rest and
    a one-sided-at-zero central difference (sliding speed u >= 0)."""

    is_linear = False
    #: never drawn by the event-driven integrators' calibration: a table's kinks, a switch at the peak speed
    error_calibrated = False

    def _check_at_rest(self):
        value = float(np.asarray(self(0.0)))
        if not (np.isfinite(value) and value >= 0):
            raise InputError(f"kinetic law {self.name!r} must give a finite friction >= 0 at rest, got {value}")

    @property
    def mu_m(self) -> float:
        return float(np.asarray(self(0.0)))

    @property
    def slope(self) -> float:
        return float(self.derivative(0.0))

    def derivative(self, sliding_speed, step=1e-7):
        u = np.asarray(sliding_speed, dtype=float)
        h = step * np.maximum(1.0, np.abs(u))
        low = np.maximum(u - h, 0.0)
        return (self(u + h) - self(low)) / (u + h - low)


@dataclass(frozen=True)
class CallableKinetic(_CurveKinetic):
    """Any kinetic law given as a callable ``mu(sliding_speed)`` (vectorised, SI).

    Parameters
    ----------
    function : callable
        ``mu(sliding_speed)``: the kinetic friction coefficient (dimensionless) at sliding speeds in m/s,
        vectorised over numpy arrays.
    name : str
        A name for reports.
    """

    function: object
    name: str = "callable"

    def __post_init__(self):
        if not callable(self.function):
            raise InputError(f"kinetic law {self.name!r} is not callable")
        self._check_at_rest()

    def __call__(self, sliding_speed):
        return self.function(sliding_speed)


#: How the surfaces' separation follows the sliding speed (see :class:`SeparatingSurfacesKinetic`).
SEPARATION_MEMORIES = ("none", "held", "falling")


@dataclass(frozen=True)
class SeparatingSurfacesKinetic(_CurveKinetic):
    """Friction of rough surfaces that part as they slide, with the separation's memory of the slip.

    Sliding at speed u parts the surfaces by h = k_h |u| (seed 000 eq. 27; k_h = c RMS in its addendum
    AD1.3, c h0 in chapter 5), and friction is a function of the separation, mu = f(h). How h follows
    the slip is the ``memory``:

    - ``"none"``: h = k_h |u| at every instant (AD1.3: "simple interpolation on a fixed curve").
    - ``"held"``: after the slip's fastest moment the surfaces stay apart at h_peak = k_h u_peak
      until they come to rest relative to each other (seed 000 §5.4, the dotted line of its fig. 5.8;
      the runs of its figs. 5.9-5.24).
    - ``"falling"``: after the peak the surfaces fall back together from rest at ``fall_acceleration``
      a, h = max(h_peak - a tau^2 / 2, k_h |u|) a time tau after the peak (seed 000 §4.5: "one possible
      reason for the surfaces' taking a finite time to fall together is simple inertia").

    At rest the surfaces close to h = 0 again, so each slip phase starts afresh. The engine
    (:func:`faultslip.dynamics.spring_slider.simulate.simulate`) switches to :meth:`after_peak` at the first maximum
    of the sliding speed in a slip phase, and back if the speed later exceeds that peak.

    Parameters
    ----------
    friction_at_separation : callable
        mu(h), vectorised, h in m (>= 0); finite and non-negative.
    separation_per_speed : float
        k_h in m per m/s (that is, s).
    memory : {"none", "held", "falling"}
    fall_acceleration : float
        a in m/s^2 for ``"falling"``; default standard gravity.
    """

    friction_at_separation: object
    separation_per_speed: float
    memory: str = "none"
    fall_acceleration: float = STANDARD_GRAVITY
    name: str = "separating surfaces"

    def __post_init__(self):
        if not callable(self.friction_at_separation):
            raise InputError(f"kinetic law {self.name!r}: friction_at_separation must be callable")
        if not (np.isfinite(self.separation_per_speed) and self.separation_per_speed >= 0):
            raise InputError(f"the separation per sliding speed must be >= 0 s, got {self.separation_per_speed!r}")
        if self.memory not in SEPARATION_MEMORIES:
            raise InputError(f"unknown separation memory {self.memory!r}; allowed: {', '.join(SEPARATION_MEMORIES)}")
        if not (np.isfinite(self.fall_acceleration) and self.fall_acceleration > 0):
            raise InputError(f"the fall acceleration must be positive (m/s^2), got {self.fall_acceleration!r}")
        self._check_at_rest()

    @property
    def holds_peak(self) -> bool:
        """Whether friction after the slip's fastest moment depends on that peak (the engine asks)."""
        return self.memory != "none"

    def separation(self, sliding_speed):
        """h = k_h |u| (m), the separation the speed alone sets."""
        return self.separation_per_speed * np.abs(np.asarray(sliding_speed, dtype=float))

    def __call__(self, sliding_speed):
        return self.friction_at_separation(self.separation(sliding_speed))

    def separation_after_peak(self, peak_speed, elapsed, sliding_speed):
        """h (m) a time ``elapsed`` (s) after the sliding speed peaked at ``peak_speed`` (m/s)."""
        now = self.separation(sliding_speed)
        peak = self.separation_per_speed * abs(float(peak_speed))
        if self.memory == "none":
            return now
        if self.memory == "held":
            return np.maximum(peak, now)
        fallen = peak - 0.5 * self.fall_acceleration * np.asarray(elapsed, dtype=float) ** 2
        return np.maximum(fallen, now)

    def after_peak(self, peak_speed, elapsed, sliding_speed):
        """mu after the peak: f at :meth:`separation_after_peak`."""
        return self.friction_at_separation(self.separation_after_peak(peak_speed, elapsed, sliding_speed))
