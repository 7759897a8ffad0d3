"""The vectorised cell kernel: every output of a block of stick-slip cells in plain numpy.

One call computes slip per event, recurrence, loading rate, static friction, stress drop, regime,
method and estimated error, eps, and the moment and magnitude for arrays of cells (seed 003 eqs.
2-18 and 2-19, and the exact cycle where the closed form is not accurate enough). Studies, maps
and the uncertainty of fitted materials all use it. It lives below them, with the dynamics it
evaluates, so that ``fault`` can use it without importing ``study``.
"""

from __future__ import annotations

import numpy as np

from faultslip.dynamics.spring_slider.closed_form import overshoot_factor
from faultslip.dynamics.spring_slider.exact_cycle import exact_cycle_error, slip_cycle
from faultslip.dynamics.methods import ClosedForm

METHOD_CODES = {"closed_form": 0, "exact_cycle": 1, "event_driven": 2, "quasi_harmonic_averaging": 3}
REGIME_CODES = {"stick_slip": 0, "steady_sliding": 1, "growing_oscillation": 2, "sustained_oscillation": 3}


def _exact_where(mask, zeta, eps):
    """Exact-cycle dimensionless quantities where ``mask`` (only there: elsewhere NaN)."""
    zeta, eps, mask = (np.array(a) for a in np.broadcast_arrays(np.asarray(zeta, float), np.asarray(eps, float),
                                                                 np.asarray(mask, bool)))
    out = np.full((4,) + zeta.shape, np.nan)
    if mask.any():
        cycle = slip_cycle(zeta[mask], eps[mask])
        # out[k, ...] is a view even for 0-d cells (out[k] would be a scalar copy)
        out[0, ...][mask] = cycle["u_max"] - cycle["u_min"]  # amplitude / L
        out[1, ...][mask] = cycle["u_drop"]  # stick advance / L
        out[2, ...][mask] = cycle["slip_time"]  # omega_n t_slip
        out[3, ...][mask] = cycle["v_min"]
    return out


def _fits(buffer, *operands) -> bool:
    """Whether ``buffer op= operand`` can run in place: a writeable array already of the result's shape."""
    return (isinstance(buffer, np.ndarray) and buffer.flags.writeable and buffer.ndim > 0
            and np.broadcast_shapes(buffer.shape, *(np.shape(o) for o in operands)) == buffer.shape)


def cell_kernel(stiffness, load, drive, omega_n, zeta, eps_c, critical_rate, mu_so, mu_m, b, d, moment_factor,
                drive_is_rate=False, method="auto", tolerance=1e-6):
    """Every output of one block of cells, in plain numpy (the only full-grid work of a study).

    ``drive`` is the platform speed (fault: the slip rate) or, with ``drive_is_rate``, the loading
    rate. Parameter-level inputs (omega_n, zeta, eps_c, critical rate) arrive broadcastable.
    Cells where the closed form meets the tolerance use it; the others use the exact cycle; cells
    above the critical rate slide steadily (slip 0, period NaN).
    """
    shape = np.broadcast_shapes(*(np.shape(a) for a in (stiffness, load, drive, omega_n, zeta, eps_c, critical_rate,
                                                        mu_so, mu_m, b, d, moment_factor)))
    if drive_is_rate:
        rate = drive
        speed = rate * (load / stiffness)
    else:
        speed = drive
        rate = (stiffness / load) * speed  # the parameter factor first: one grid-sized operation
    drop = mu_so - mu_m
    # seed 003 eq. 2-18 as drop / (1 + drop b rate^d), in place on one grid-sized buffer
    # a fresh array spanning every input of eq. 2-18, so the in-place steps below never broadcast
    # into a smaller buffer (a swept mu_m or b adds dimensions that rate does not have)
    excess = np.array(np.power(rate, d), dtype=float, copy=None, ndmin=1)
    if _fits(excess, drop, b):
        excess *= drop * b
    else:
        excess = excess * (drop * b)
    excess = excess.reshape(np.broadcast_shapes(np.shape(rate), np.shape(d), np.shape(drop), np.shape(b)))
    excess += 1.0
    np.divide(drop, excess, out=excess)
    has_excess = bool(np.all(np.asarray(drop) > 0))
    with np.errstate(divide="ignore", invalid="ignore"):  # no excess (mu_so = mu_m): eps = inf, steady sliding
        eps = np.asarray(omega_n * excess, dtype=float)
        if np.broadcast_shapes(np.shape(rate), eps.shape) == eps.shape and eps.ndim:
            np.divide(rate, eps, out=eps)
        else:
            eps = np.asarray(rate / eps, dtype=float)
        sticks = eps < eps_c if has_excess else (excess > 0) & (eps < eps_c)
        error = 2.0 * np.abs(zeta) + eps  # 1.5 (2|zeta| eps + eps^2) = 1.5 eps (2|zeta| + eps)
        error *= eps
        error *= ClosedForm.SAFETY
    if method == "closed_form":
        use_closed = np.ones((), dtype=bool)
    elif method == "exact_cycle":
        use_closed = np.zeros((), dtype=bool)
    elif np.all(np.isinf(eps_c)):  # no damping: no critical rate to stay below
        use_closed = error <= tolerance
    else:
        use_closed = (eps <= 0.1 * eps_c) & (error <= tolerance)
    # eq. 2-19: the stress-drop slip x1 - x2 = (W / K) excess * overshoot, parameter factor first
    stick_advance = (load / stiffness * overshoot_factor(zeta)) * excess
    slip_time = np.pi / (omega_n * np.sqrt(1.0 - zeta * zeta))
    all_closed, all_stick = bool(np.all(use_closed)), bool(np.all(sticks))
    if not all_closed:
        error = np.where(use_closed, error, exact_cycle_error(eps, eps_c))
        need_exact = sticks & ~use_closed
        if need_exact.any():
            exact = _exact_where(need_exact, zeta, eps)
            stick_advance = np.where(need_exact, (load / stiffness) * excess * exact[1], stick_advance)
            slip_time = np.where(need_exact, exact[2] / omega_n, slip_time)
    period = stick_advance / speed
    period += slip_time
    slip = speed * period  # slip per event: the sliding during the event, integral of u dt = V T
    if _fits(stick_advance, stiffness):  # the last use of stick_advance: reuse its buffer
        stress_drop = stick_advance
        stress_drop *= stiffness
    else:
        stress_drop = stiffness * stick_advance
    if all_stick:  # the common case: no masking needed
        regime = np.where(np.asarray(zeta) < 0, REGIME_CODES["growing_oscillation"], REGIME_CODES["stick_slip"]).astype(np.int8)
    else:
        with np.errstate(invalid="ignore"):
            slip = np.where(sticks, slip, 0.0)
            period = np.where(sticks, period, np.nan)
            stress_drop = np.where(sticks, stress_drop, 0.0)
        regime = np.where(sticks, np.where(zeta < 0, REGIME_CODES["growing_oscillation"], REGIME_CODES["stick_slip"]),
                          REGIME_CODES["steady_sliding"]).astype(np.int8)
    method_code = (np.zeros((), np.int8) if all_closed else
                   np.where(use_closed, METHOD_CODES["closed_form"], METHOD_CODES["exact_cycle"]).astype(np.int8))
    if np.all(np.isnan(moment_factor)):
        moment = magnitude = np.full((), np.nan)
    else:
        moment = moment_factor * slip
        with np.errstate(divide="ignore", invalid="ignore"):
            magnitude = np.log10(moment)
            magnitude -= 9.1
            magnitude *= 2.0 / 3.0
            if not all_stick:
                magnitude = np.where(moment > 0, magnitude, np.nan)
    static = excess  # reuse the buffer: mu_s = mu_m + excess is the last use of excess
    static += mu_m
    return tuple(np.broadcast_to(value, shape) for value in (
        slip, period, rate, static, stress_drop, regime, critical_rate, method_code, error, eps, moment, magnitude))


KERNEL_OUTPUTS = ("slip_per_event", "recurrence_period", "loading_rate", "static_friction", "stress_drop", "regime",
                  "critical_loading_rate", "method", "estimated_relative_error", "dimensionless_rate",
                  "seismic_moment", "moment_magnitude")
