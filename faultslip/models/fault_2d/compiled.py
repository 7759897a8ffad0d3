"""The 2-D fault's force balance and state rate, element by element, compiled by numba where it is here.

The same equations as :class:`faultslip.models.fault_2d.model.ForceBalance` (see there), in one
pass over the elements (one thread: numba's parallel loop measured no faster at 1,600 elements, and
oversubscribed the cores when runs go side by side in processes): Newton's method
on u = asinh[V / (2 V_0) exp(psi / a)] from the last solution, safeguarded by the bracket
from 0 to the nearer of tau / (sigma_n a) and asinh(tau / c) that holds the root (a step leaving it bisects), each element to its own convergence
(a step |du| <= 1e-10 (1 + |u|) leaves an error of the order of its square), then V and d psi / dt.
"""

from __future__ import annotations

import math

from faultslip.dynamics.shared.compiler import available  # noqa: F401 (re-exported for the model)

_COMPILED = []


def _balance(stress, psi, u, sigma_a, inverse_a, two_v0_eta, inverse_damping, aging, aging_rate, f0, inverse_b,
             v0, critical_slip, b, speed, psi_rate, iterations):
    """Fill ``speed`` and ``psi_rate``; ``u`` is updated in place. An element whose state has no finite
    slip rate, or whose iteration fails, gets NaN: the integrator rejects that trial step."""
    for i in range(stress.shape[0]):
        coefficient = two_v0_eta * math.exp(-psi[i] * inverse_a[i])
        tau = stress[i]
        # the root lies between 0 and tau / (sigma_n a): g is monotone, and the bracket keeps each
        # Newton step honest (a step that leaves it is a bisection instead)
        outer = tau / sigma_a[i]  # beyond the root: g(outer) = c sinh(outer) has the sign of tau
        if abs(outer) >= 700.0 or coefficient == 0.0:  # V would overflow: an absurd trial state, which the step rejects
            speed[i] = math.nan
            psi_rate[i] = math.nan
            continue
        low = min(0.0, outer)
        high = max(0.0, outer)
        x = u[i]
        if not low <= x <= high:
            x = outer
        converged = False
        sinh_x = 0.0
        for iteration in range(iterations):
            e = math.exp(x)
            inverse = 1.0 / e
            sinh_x = 0.5 * (e - inverse)
            cosh_x = 0.5 * (e + inverse)
            if iteration == 0 and abs(coefficient * sinh_x) > abs(tau):
                # asinh(tau / c), where the friction term vanishes, is beyond the root too: a start past it
                # (a far warm start, or tau / (sigma_n a)) moves there, else Newton walks back a unit a step
                x = math.asinh(tau / coefficient)
                if tau >= 0:
                    high = x
                else:
                    low = x
                continue
            residual = sigma_a[i] * x + coefficient * sinh_x - tau
            if not math.isfinite(residual):  # no finite slip rate here: an absurd trial state
                break
            if residual > 0:
                high = x
            else:
                low = x
            step = residual / (sigma_a[i] + coefficient * cosh_x)
            proposal = x - step
            newton = low <= proposal <= high  # inclusive: at the root the step may land on the bound just set
            if not newton:
                proposal = 0.5 * (low + high)
                step = x - proposal
            x = proposal
            sinh_x -= step * cosh_x  # sinh at the new x to first order: the error is of the order of step^2
            # the error left after a Newton step is of the order of the step squared: 1e-10 leaves round-off
            if (newton and abs(step) <= 1e-10 * (1.0 + abs(x))) or high - low <= 4e-16 * (1.0 + abs(x)):
                converged = newton or high - low <= 4e-16 * (1.0 + abs(x))
                if not newton:
                    sinh_x = math.sinh(x)
                break
        if not converged or not math.isfinite(x):
            speed[i] = math.nan
            continue
        u[i] = x
        v = coefficient * sinh_x * inverse_damping
        speed[i] = v
        if aging:
            psi_rate[i] = aging_rate[i] * (math.exp((f0 - psi[i]) * inverse_b[i]) - v / v0)
        else:
            psi_rate[i] = -(v / critical_slip[i]) * (psi[i] - f0 + b[i] * math.log(v / v0))


def balance(compiled: bool = True):
    """The force balance, compiled by numba on first use (cached on disk), or as plain Python."""
    if not compiled:
        return _balance
    if not _COMPILED:
        import numba  # heavy: optional dependency (faultslip[fast]), imported only when the kernel is wanted

        _COMPILED.append(numba.njit(cache=True)(_balance))
    return _COMPILED[0]
