"""The 2-D fault's force balance and state rate, element by element, compiled by numba where it is here.

The same equations as :class:`faultslip.dynamics.fault_2d.model.ForceBalance` (see there), in one
pass over the elements, shared between the cores (the elements are independent): Newton's method
on u = asinh[V / (2 V_0) exp(psi / a)] from the last solution, each element to its own convergence
(a step |du| <= 1e-10 (1 + |u|) leaves an error of the order of its square), then V and d psi / dt.
"""

from __future__ import annotations

import math

from faultslip.dynamics.shared.compiler import available  # noqa: F401 (re-exported for the model)

_COMPILED = []


def _balance(stress, psi, u, sigma_a, inverse_a, two_v0_eta, inverse_damping, aging, aging_rate, f0, inverse_b,
             v0, critical_slip, b, speed, psi_rate, iterations):
    """Fill ``speed`` and ``psi_rate``; ``u`` is updated in place. An element whose Newton iteration
    fails gets a NaN speed (the caller names it)."""
    for i in _elements(stress.shape[0]):
        coefficient = two_v0_eta * math.exp(-psi[i] * inverse_a[i])
        x = u[i]
        converged = False
        for _ in range(iterations):
            e = math.exp(x)
            inverse = 1.0 / e
            step = ((sigma_a[i] * x + coefficient * 0.5 * (e - inverse) - stress[i])
                    / (sigma_a[i] + coefficient * 0.5 * (e + inverse)))
            x -= step
            # the error left after a Newton step is of the order of the step squared: 1e-10 leaves round-off
            if abs(step) <= 1e-10 * (1.0 + abs(x)):
                converged = True
                break
        if not converged or not math.isfinite(x):
            speed[i] = math.nan
            continue
        u[i] = x
        v = coefficient * math.sinh(x) * inverse_damping
        speed[i] = v
        if aging:
            psi_rate[i] = aging_rate[i] * (math.exp((f0 - psi[i]) * inverse_b[i]) - v / v0)
        else:
            psi_rate[i] = -(v / critical_slip[i]) * (psi[i] - f0 + b[i] * math.log(v / v0))


_elements = range  # numba.prange when compiled: the elements are independent, so the answer is the same


def balance(compiled: bool = True):
    """The force balance, compiled by numba on first use (cached on disk), or as plain Python."""
    if not compiled:
        return _balance
    if not _COMPILED:
        import numba  # heavy: optional dependency (faultslip[fast]), imported only when the kernel is wanted

        namespace = dict(_balance.__globals__, _elements=numba.prange)
        source = type(_balance)(_balance.__code__, namespace, _balance.__name__)
        _COMPILED.append(numba.njit(cache=True, parallel=True)(source))
    return _COMPILED[0]
