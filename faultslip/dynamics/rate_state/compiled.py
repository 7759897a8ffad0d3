"""A compiled Dormand-Prince 5(4) kernel for the common rate-and-state slider: one state variable,
quasi-static or quasi-dynamic, in the log states x = ln(V/V0), psi = ln(V0 theta / D_c).

Why compiled: on this two-state system every integrator that calls back into Python spends most of
its time in the call (odeint's floor is ~2 µs per evaluation; a velocity step needs ~500), so no
choice of method or formulation in Python reaches the issue's 3x over odeint. The same kernel,
compiled by numba, takes ~0.1 µs per evaluation. numba is optional (``pip install faultslip[fast]``);
without it the kernel is never chosen by ``auto`` and can still run as plain Python (slowly), which
the tests use to check it without numba.

The right-hand side (quasi-static when eta = 0):

    V = V0 e^x,  psi' = (V0 e^-psi - V) / D_c (aging)  or  -(V / D_c)(x + psi) (slip),
    x' = (k (V_lp(t) - V) - sigma_n b psi') / (sigma_n a + eta V),

with V_lp linear on each segment of the load history. Step control and dense output follow
:func:`faultslip.dynamics.rate_state.slider.dopri5` (PI controller, order-4 continuous extension).
"""

from __future__ import annotations

import math

import numpy as np

from faultslip.dynamics.shared.compiler import available  # noqa: F401 (the family's probe, re-exported)
from faultslip.dynamics.shared.dormand_prince import (A21, A31, A32, A41, A42, A43, A51, A52, A53, A54, A61, A62, A63, A64,
                                               A65, B1, B3, B4, B5, B6, E1, E3, E4, E5, E6, E7, _C, _P)

#: kernel status codes
OK, TOO_MANY_STEPS, DIVERGED, STEP_COLLAPSE = 0, 1, 2, 3

(P11, P12, P13, P14), _, (P31, P32, P33, P34), (P41, P42, P43, P44), (P51, P52, P53, P54), \
    (P61, P62, P63, P64), (P71, P72, P73, P74) = _P
C2, C3, C4, C5 = _C[1:5]


def _rates(t, x, psi, aging, v0, dc, k, sigma_a, sigma_b, damping, t_start, v_start, v_slope):
    speed = v0 * math.exp(x)
    if aging:
        dpsi = (v0 * math.exp(-psi) - speed) / dc
    else:
        dpsi = -(speed / dc) * (x + psi)
    load = v_start + v_slope * (t - t_start)
    return (k * (load - speed) - sigma_b * dpsi) / (sigma_a + damping * speed), dpsi


def _kernel(x, psi, t0, t1, v_start, v_slope, aging, v0, dc, k, sigma_a, sigma_b, damping, t_eval, out, rtol,
            atol_x, atol_psi, limit, max_steps, h):
    """Integrate (x, psi) from t0 to t1, writing the states at ``t_eval`` (sorted, in [t0, t1]) into ``out``.

    Returns (status, t, x, psi, steps, evaluations, next step size). ``h`` <= 0 asks for a first step
    from the size of y, f and f' (Hairer, Norsett & Wanner I, II.4).
    """
    n_out = t_eval.shape[0]
    next_out = 0
    while next_out < n_out and t_eval[next_out] <= t0:
        out[next_out, 0] = x
        out[next_out, 1] = psi
        next_out += 1
    t = t0
    k1x, k1p = _rates(t, x, psi, aging, v0, dc, k, sigma_a, sigma_b, damping, t0, v_start, v_slope)
    nfev = 1
    span = t1 - t0
    if span <= 0.0:
        return OK, t, x, psi, 0, nfev, h
    if h <= 0.0:
        sx, sp = atol_x + rtol * abs(x), atol_psi + rtol * abs(psi)
        d0 = math.sqrt(((x / sx) ** 2 + (psi / sp) ** 2) / 2)
        d1 = math.sqrt(((k1x / sx) ** 2 + (k1p / sp) ** 2) / 2)
        h = 1e-6 if d0 < 1e-5 or d1 < 1e-5 else 0.01 * d0 / d1
        h = min(h, span)
        fx, fp = _rates(t + h, x + h * k1x, psi + h * k1p, aging, v0, dc, k, sigma_a, sigma_b, damping, t0,
                        v_start, v_slope)
        nfev += 1
        d2 = math.sqrt((((fx - k1x) / sx) ** 2 + ((fp - k1p) / sp) ** 2) / 2) / h
        if not math.isfinite(d2):
            d2 = 1e300
        big = max(d1, d2)
        h1 = (0.01 / big) ** 0.2 if big > 1e-15 else max(1e-6, h * 1e-3)
        h = min(100 * h, h1, span)
    previous_error = 1e-4
    steps = 0
    while t < t1:
        if steps >= max_steps:
            return TOO_MANY_STEPS, t, x, psi, steps, nfev, h
        t_next = t + h
        if t_next >= t1:  # the last step lands on t1 exactly (t + (t1 - t) may miss it by an ulp)
            h, t_next = t1 - t, t1
        k2x, k2p = _rates(t + C2 * h, x + h * A21 * k1x, psi + h * A21 * k1p, aging, v0, dc, k, sigma_a, sigma_b,
                          damping, t0, v_start, v_slope)
        k3x, k3p = _rates(t + C3 * h, x + h * (A31 * k1x + A32 * k2x), psi + h * (A31 * k1p + A32 * k2p), aging, v0,
                          dc, k, sigma_a, sigma_b, damping, t0, v_start, v_slope)
        k4x, k4p = _rates(t + C4 * h, x + h * (A41 * k1x + A42 * k2x + A43 * k3x),
                          psi + h * (A41 * k1p + A42 * k2p + A43 * k3p), aging, v0, dc, k, sigma_a, sigma_b, damping,
                          t0, v_start, v_slope)
        k5x, k5p = _rates(t + C5 * h, x + h * (A51 * k1x + A52 * k2x + A53 * k3x + A54 * k4x),
                          psi + h * (A51 * k1p + A52 * k2p + A53 * k3p + A54 * k4p), aging, v0, dc, k, sigma_a,
                          sigma_b, damping, t0, v_start, v_slope)
        k6x, k6p = _rates(t + h, x + h * (A61 * k1x + A62 * k2x + A63 * k3x + A64 * k4x + A65 * k5x),
                          psi + h * (A61 * k1p + A62 * k2p + A63 * k3p + A64 * k4p + A65 * k5p), aging, v0, dc, k,
                          sigma_a, sigma_b, damping, t0, v_start, v_slope)
        x_new = x + h * (B1 * k1x + B3 * k3x + B4 * k4x + B5 * k5x + B6 * k6x)
        psi_new = psi + h * (B1 * k1p + B3 * k3p + B4 * k4p + B5 * k5p + B6 * k6p)
        k7x, k7p = _rates(t + h, x_new, psi_new, aging, v0, dc, k, sigma_a, sigma_b, damping, t0, v_start, v_slope)
        nfev += 6
        ex = h * (E1 * k1x + E3 * k3x + E4 * k4x + E5 * k5x + E6 * k6x + E7 * k7x)
        ep = h * (E1 * k1p + E3 * k3p + E4 * k4p + E5 * k5p + E6 * k6p + E7 * k7p)
        error = math.sqrt(((ex / (atol_x + rtol * max(abs(x), abs(x_new)))) ** 2
                           + (ep / (atol_psi + rtol * max(abs(psi), abs(psi_new)))) ** 2) / 2)
        if not math.isfinite(error):  # a trial stage left the domain (exp overflow): a smaller step
            h *= 0.1
        elif error <= 1.0:
            while next_out < n_out and t_eval[next_out] <= t_next:  # the order-4 continuous extension
                s = (t_eval[next_out] - t) / h
                s2 = s * s
                s3 = s2 * s
                s4 = s3 * s
                w1 = P11 * s + P12 * s2 + P13 * s3 + P14 * s4
                w3 = P31 * s + P32 * s2 + P33 * s3 + P34 * s4
                w4 = P41 * s + P42 * s2 + P43 * s3 + P44 * s4
                w5 = P51 * s + P52 * s2 + P53 * s3 + P54 * s4
                w6 = P61 * s + P62 * s2 + P63 * s3 + P64 * s4
                w7 = P71 * s + P72 * s2 + P73 * s3 + P74 * s4
                out[next_out, 0] = x + h * (w1 * k1x + w3 * k3x + w4 * k4x + w5 * k5x + w6 * k6x + w7 * k7x)
                out[next_out, 1] = psi + h * (w1 * k1p + w3 * k3p + w4 * k4p + w5 * k5p + w6 * k6p + w7 * k7p)
                next_out += 1
            t = t_next
            x, psi = x_new, psi_new
            k1x, k1p = k7x, k7p
            steps += 1
            if x > limit:  # the quasi-static speed runs away: no solution past here
                return DIVERGED, t, x, psi, steps, nfev, h
            factor = 0.9 * error ** -0.14 * previous_error ** 0.08 if error > 0 else 5.0
            h *= min(5.0, max(0.2, factor))
            previous_error = max(error, 1e-4)
        else:
            h *= max(0.2, 0.9 * error ** -0.2)
        if h < 6.4e-15 * max(abs(t), abs(t0), 1e-300):  # a few float spacings of t
            return STEP_COLLAPSE, t, x, psi, steps, nfev, h
    return OK, t, x, psi, steps, nfev, h


_COMPILED = []


def kernel(compiled: bool = True):
    """The kernel, compiled by numba on first use (cached on disk), or as plain Python."""
    if not compiled:
        return _kernel
    if not _COMPILED:
        import numba  # heavy: optional dependency (faultslip[fast]), imported only when the kernel is wanted

        rates = numba.njit(cache=True)(_rates)
        namespace = dict(_kernel.__globals__, _rates=rates)
        source = type(_kernel)(_kernel.__code__, namespace, _kernel.__name__)
        _COMPILED.append(numba.njit(cache=True)(source))
    return _COMPILED[0]


def integrate(law, stiffness, normal_stress, damping, segments, duration, y0, t_eval, rtol, atol, max_speed,
              compiled=True, max_steps=5_000_000):
    """(states at t_eval, steps, evaluations, status, time reached) over the load history's segments.

    ``segments`` yields (t0, t1, V_lp at t0, V_lp at t1); the kernel restarts at each breakpoint (the
    load-point speed may jump there). ``status`` is :data:`OK` or the first failure's code.
    """
    run = kernel(compiled)
    aging = law.evolution == "aging"
    v0, dc = law.reference_speed, law.critical_slip
    sigma_a, sigma_b = normal_stress * law.a, normal_stress * law.b
    limit = math.log(max_speed / v0) if math.isfinite(max_speed) else math.inf
    t_eval = np.ascontiguousarray(t_eval, dtype=float)
    out = np.empty((t_eval.size, 2))
    x, psi = float(y0[0]), float(y0[1])
    steps = nfev = 0
    h = -1.0
    filled = 0
    for t0, t1, v_start, v_end in segments:
        first = int(np.searchsorted(t_eval, t0, side="left"))  # the samples in [t0, t1), or [t0, t1] at the end
        stop = int(np.searchsorted(t_eval, t1, side="right" if t1 == duration else "left"))
        slope = (v_end - v_start) / (t1 - t0)
        status, t, x, psi, segment_steps, segment_nfev, h = run(
            x, psi, float(t0), float(t1), float(v_start), float(slope), aging, v0, dc, float(stiffness), sigma_a,
            sigma_b, float(damping), t_eval[first:stop], out[first:stop], float(rtol), float(atol[0]),
            float(atol[1]), limit, int(max_steps), -1.0)
        steps, nfev = steps + segment_steps, nfev + segment_nfev
        if status != OK:
            return out[:filled], steps, nfev, status, t
        filled = max(filled, stop)
    return out, steps, nfev, OK, float(t_eval[-1]) if t_eval.size else 0.0
