"""The Dormand & Prince (1980) 5(4) Runge-Kutta pair and its order-4 continuous extension (Shampine 1986).

Shared by the pure-Python integrator (:func:`faultslip.dynamics.rate_state.slider.dopri5`) and the compiled
kernel (:mod:`faultslip.dynamics.rate_state.compiled`). Hairer, Norsett & Wanner, Solving ODEs I,
Table 5.2; tests compare every coefficient with scipy's RK45.
"""

# Dormand & Prince (1980) 5(4) tableau: nodes, stages, 5th-order weights and the error weights
# (5th minus embedded 4th order); Hairer, Norsett & Wanner, Solving ODEs I, Table 5.2.
_C = (0.0, 1 / 5, 3 / 10, 4 / 5, 8 / 9, 1.0)
_A = ((),
      (1 / 5,),
      (3 / 40, 9 / 40),
      (44 / 45, -56 / 15, 32 / 9),
      (19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729),
      (9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656))
_B = (35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84)
_E = (71 / 57600, 0.0, -71 / 16695, 71 / 1920, -17253 / 339200, 22 / 525, -1 / 40)
# continuous extension of order 4 (Shampine 1986), as a polynomial in the step fraction s:
# y(t0 + s h) = y0 + h sum_i k_i sum_j _P[i][j] s^(j+1)
_P = ((1.0, -8048581381 / 2820520608, 8663915743 / 2820520608, -12715105075 / 11282082432),
      (0.0, 0.0, 0.0, 0.0),
      (0.0, 131558114200 / 32700410799, -68118460800 / 10900136933, 87487479700 / 32700410799),
      (0.0, -1754552775 / 470086768, 14199869525 / 1410260304, -10690763975 / 1880347072),
      (0.0, 127303824393 / 49829197408, -318862633887 / 49829197408, 701980252875 / 199316789632),
      (0.0, -282668133 / 205662961, 2019193451 / 616988883, -1453857185 / 822651844),
      (0.0, 40617522 / 29380423, -110615467 / 29380423, 69997945 / 29380423))

(A21,), (A31, A32), (A41, A42, A43), (A51, A52, A53, A54), (A61, A62, A63, A64, A65) = _A[1:]
B1, _, B3, B4, B5, B6 = _B
E1, _, E3, E4, E5, E6, E7 = _E


def continuous_state(y0, h, stages, fraction):
    """The order-4 continuous extension at ``fraction`` s of a step (Shampine 1986):
    y(t0 + s h) = y0 + h sum_i k_i sum_j P_ij s^(j+1), with ``stages`` (k1, k3, k4, k5, k6, k7) of the step
    (k2's row of P is zero). Its error is of the step's own order, so a crossing located on it is as accurate
    as the integration; a cubic Hermite interpolant of the step's ends errs by O(h^4), and that error led the
    slip per event (rate-and-state cycles near a / b = 1: c rtol^0.8, not c rtol)."""
    s2 = fraction * fraction
    powers = (fraction, s2, s2 * fraction, s2 * s2)
    weights = [sum(p * w for p, w in zip(row, powers)) for row in (_P[0],) + _P[2:]]
    return [y + h * sum(w * k[i] for w, k in zip(weights, stages)) for i, y in enumerate(y0)]
