"""The 2-D fault's force balance and state rate, element by element, compiled by numba where it is here.

The same equations as :class:`faultslip.models.fault_2d.model.ForceBalance` (see there), in one
pass over the elements (one thread, or several in the parallel build: a run's ``threads``): Newton's method
on u = asinh[V / (2 V_0) exp(psi / a)] from the last solution, safeguarded by the bracket
from 0 to the nearer of tau / (sigma_n a) and asinh(tau / c) that holds the root (a step leaving it bisects), each
element to its own convergence (a step leaves an error of at most half its square: a step |du| <= 1e-10 (1 + |u|)
leaves round-off, and one with du^2 <= ``tolerance`` (1 + |u|) leaves the integrator's share, see
:func:`faultslip.models.fault_2d.model.newton_tolerance`), then V and d psi / dt.
"""

from __future__ import annotations

import decimal
import importlib.metadata
import importlib.util
import math
import platform
import struct
import time
import types
from pathlib import Path

import numpy as np

from faultslip.dynamics.shared.compiler import available  # noqa: F401 (re-exported for the model)
from faultslip.models.fault_2d.kernel import (  # the rows of the kernel's halves table (SpectrumHalves)
    HALF_TWIDDLE, HANKEL_EVEN, HANKEL_ODD, TOEPLITZ_EVEN, TOEPLITZ_ODD, TWIDDLE)

#: the kernels' loops over parts of the elements: range in plain Python; numba's prange once compiled (a parallel
#: build splits the parts over threads, a serial one runs them as range)
prange = range
#: parts of the elements a kernel's loop runs: one in a serial build; PARALLEL_PARTS in a parallel one, some per
#: thread, so that a thread whose part holds an event's slow-converging elements holds up the others less
PARTS = 1
PARALLEL_PARTS = 16
#: the parts the threaded step's task 0 owns at first beyond an equal share, as a fraction of it: task 0 takes the
#: even half of K x's spectrum, which costs less than task 1's odd half (:func:`_first_split`). The step then moves
#: the split to where the two tasks' work takes equal times (:func:`_adapted_split`). With a fixed split, at 1,600
#: elements 10 of 16 parts left task 1 waiting 15 us of a trial step's 200, at 3,200 elements 37 of 381, at 6,400
#: 91 of 780
EVEN_EXTRA = 0.25


# --- exp in SIMD ---------------------------------------------------------------------------------------------
#
# A scalar loop calls libm's exp, 3 ns an element here; the same function written out in arithmetic, which LLVM
# vectorises, takes about 1.2 ns, and three of a solve's three or four exponentials can be taken that way, in
# loops of their own (:func:`_exponentials`). exp(x) = 2^k exp(r), k = round(x / ln 2), r = x - k ln 2 in two
# parts (Cody & Waite 1980, "Software Manual for the Elementary Functions"; Muller 2016, "Elementary Functions",
# ch. 11), exp(r) by its Taylor series.

_LN2 = decimal.Context(prec=60).ln(decimal.Decimal(2))
#: ln 2's leading 32 bits, so that k ln2_hi is exact for |k| < 2^21, and the rest of ln 2 (to 60 digits)
LN2_HI = math.floor(float(_LN2) * 2.0 ** 32) / 2.0 ** 32
LN2_LO = float(_LN2 - decimal.Decimal(LN2_HI))
LOG2_E = float(1 / _LN2)
#: 1.5 2^52: adding it and taking it away rounds a float below 2^51 to a whole number (no floor: numba's returns an
#: int, which a NaN has none of)
ROUNDING_SHIFT = 1.5 * 2.0 ** 52
#: exp(r)'s Taylor coefficients 1/j!, j = 0 .. 13: for |r| <= ln 2 / 2 the remainder r^14 / 14! is below 4e-18
EXP_TAYLOR = tuple(1.0 / math.factorial(j) for j in range(14))


def _float_from_bits(bits):
    """The float64 whose IEEE bits are the int64 ``bits`` (in the compiled build an LLVM bitcast, which vectorises)."""
    return struct.unpack("<d", struct.pack("<q", bits))[0]


def _exp(x):
    """exp(x) within 1 ulp of libm's (tested), NaN for NaN, inf above 709.78, 0 below -745.14. 2^k is made from
    its bits in two halves, so that a subnormal result or an overflow to inf comes out as libm's does."""
    x = float(x)  # plain Python: a float overflows to inf without numpy's warning
    if x > 1400.0:  # beyond, the result is inf or 0 anyway; a NaN passes both tests
        x = 1400.0
    if x < -1400.0:
        x = -1400.0
    k = (x * LOG2_E + ROUNDING_SHIFT) - ROUNDING_SHIFT  # x / ln 2 to the nearest whole number; NaN stays NaN
    r = (x - k * LN2_HI) - k * LN2_LO
    p = EXP_TAYLOR[13]
    for j in range(12, -1, -1):
        p = EXP_TAYLOR[j] + r * p
    n = int(k) if abs(k) <= 2100.0 else 0  # NaN: any k does, p is NaN
    half = n >> 1
    return p * _float_from_bits((half + 1023) << 52) * _float_from_bits((n - half + 1023) << 52)


#: the rows of the Newton iteration's warm start (``warm``), each a function of the last solution u alone:
#: exp(u), sinh(u), cosh(u), g(u) + tau = sigma_n a u + c sinh(u), and the slope g'(u) = sigma_n a + c cosh(u)
WARM_ROWS = 5


def _exponentials(first, end, psi, u, sigma_a, inverse_a, two_v0_eta, aging, f0, inverse_b, coefficients, healing,
                  warm):
    """What the force balance of elements ``first`` to ``end`` - 1 needs before their stress is known: from the
    state, c = 2 V_0 eta exp(-psi / a) and, for the aging law, exp((f_0 - psi) / b); and at the Newton
    iteration's warm start, the last solution u, the rows of ``warm`` (:data:`WARM_ROWS`): all of its first
    iteration but the stress's part. Three of a solve's three or four exponentials (most solves take one Newton
    step), by :func:`_exp`, and a division, in loops over views of the part, which vectorise (a loop over
    range(first, end) does not)."""
    state, speed_term, inverse_b_part = psi[first:end], inverse_a[first:end], inverse_b[first:end]
    coefficients_part, healing_part, u_part, sigma_a_part = (coefficients[first:end], healing[first:end],
                                                             u[first:end], sigma_a[first:end])
    exp_u, sinh_u, cosh_u, residual_u, slope_u = (warm[0, first:end], warm[1, first:end], warm[2, first:end],
                                                  warm[3, first:end], warm[4, first:end])
    for i in range(state.shape[0]):
        coefficients_part[i] = two_v0_eta * _exp(-state[i] * speed_term[i])
    if aging:
        for i in range(state.shape[0]):
            healing_part[i] = _exp((f0 - state[i]) * inverse_b_part[i])
    for i in range(state.shape[0]):
        exp_u[i] = _exp(u_part[i])
    for i in range(state.shape[0]):  # :func:`_solve_elements`'s first iteration's expressions, so its bits
        e = exp_u[i]
        inverse = 1.0 / e if e != 0.0 else math.inf  # u below -745: never a solution (|u| < 700), but no error
        sinh_u[i] = 0.5 * (e - inverse)
        cosh_u[i] = 0.5 * (e + inverse)
        residual_u[i] = sigma_a_part[i] * u_part[i] + coefficients_part[i] * sinh_u[i]
        slope_u[i] = sigma_a_part[i] + coefficients_part[i] * cosh_u[i]


def _solve_elements(first, end, product, initial_stress, add_initial, stress, psi, u, sigma_a, inverse_a, two_v0_eta,
                    inverse_damping, aging, aging_rate, f0, inverse_b, v0, critical_slip, b, speed, psi_rate,
                    iterations, tolerance, coefficients, healing, warm, precomputed):
    """Elements ``first`` to ``end`` - 1 of :func:`_balance_rates` (a function a part, not an element: a call
    passes twenty arrays, whose reference counts cost more than an element's solve)."""
    for i in range(first, end):
        if add_initial:
            stress[i] = initial_stress[i] + product[i]
        # with ``precomputed``, :func:`_exponentials` has filled ``coefficients`` and ``healing`` (the same
        # expressions, so the same bits)
        coefficient = coefficients[i] if precomputed else two_v0_eta * math.exp(-psi[i] * inverse_a[i])
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
        started_warm = precomputed
        if not low <= x <= high:
            x = outer
            started_warm = False
        converged = False
        sinh_x = 0.0
        for iteration in range(iterations):
            from_warm = iteration == 0 and started_warm
            if from_warm:  # :func:`_exponentials` took this iteration's every term but tau's
                sinh_x = warm[1, i]
                cosh_x = warm[2, i]
            else:
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
            residual = warm[3, i] - tau if from_warm else sigma_a[i] * x + coefficient * sinh_x - tau
            if not math.isfinite(residual):  # no finite slip rate here: an absurd trial state
                break
            if residual > 0:
                high = x
            else:
                low = x
            step = residual / (warm[4, i] if from_warm else sigma_a[i] + coefficient * cosh_x)
            proposal = x - step
            newton = low <= proposal <= high  # inclusive: at the root the step may land on the bound just set
            if not newton:
                proposal = 0.5 * (low + high)
                step = x - proposal
            x = proposal
            sinh_x -= step * cosh_x  # sinh at the new x to first order: the error is of the order of step^2
            # the error left after a Newton step is at most half the step squared (|g''| <= g' here): a step of
            # 1e-10 leaves round-off, and one whose square is within the tolerance leaves the tolerance
            if (newton and (abs(step) <= 1e-10 * (1.0 + abs(x)) or step * step <= tolerance * (1.0 + abs(x)))) \
                    or high - low <= 4e-16 * (1.0 + abs(x)):
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
            psi_rate[i] = aging_rate[i] * ((healing[i] if precomputed else math.exp((f0 - psi[i]) * inverse_b[i]))
                                           - v / v0)
        else:
            psi_rate[i] = -(v / critical_slip[i]) * (psi[i] - f0 + b[i] * math.log(v / v0))


def _balance_rates(product, initial_stress, add_initial, stress, psi, u, sigma_a, inverse_a, two_v0_eta,
                   inverse_damping, aging, aging_rate, f0, inverse_b, v0, critical_slip, b, speed, psi_rate,
                   iterations, tolerance):
    """Fill ``speed`` and ``psi_rate``; ``u`` is updated in place, to within ``tolerance`` (1 + |u|) (0: to
    round-off). With ``add_initial`` the stress is first set,
    stress = tau_0 + (K x) (``initial_stress`` + ``product``); without, ``stress`` is taken as it is. An element
    whose state has no finite slip rate, or whose iteration fails, gets NaN: the integrator rejects that trial
    step."""
    count = stress.shape[0]
    for part in prange(PARTS):
        _solve_elements(part * count // PARTS, (part + 1) * count // PARTS, product, initial_stress, add_initial,
                        stress, psi, u, sigma_a, inverse_a, two_v0_eta, inverse_damping, aging, aging_rate, f0,
                        inverse_b, v0, critical_slip, b, speed, psi_rate, iterations, tolerance, psi, psi,
                        psi.reshape((1, psi.shape[0])), False)


# --- a Dormand-Prince step's element-wise work, fused (issue 43, items 2 and 3) -------------------------------
#
# numpy spent a fifth of a step on the stages' temporaries (y + h (a_1 k_1 + ...)) and the error norm: one pass
# each here, in numpy's order of operations (left to right; numba contracts nothing into fused multiply-adds
# without fastmath), so the bits are numpy's. The kernel's spectrum product stays numpy's: its complex product
# runs in SIMD with fused multiply-adds where the CPU has them, which no scalar loop reproduces bit for bit.
# Each element's arithmetic is the same on any number of threads.

def _weighted_sum(first, end, total, weights, rows, terms, stages):
    """total[first:end] = w_0 k[rows_0] + w_1 k[rows_1] + ... over ``terms`` terms, each element's sum left to
    right (numpy's order: the same bits), a loop a term over views of the part, which vectorises (a loop over the
    elements with the terms inside does not: 11 us of a 60 us stage at 1,600 elements)."""
    part = total[first:end]
    leading, weight = stages[rows[0], first:end], weights[0]
    for i in range(part.shape[0]):
        part[i] = weight * leading[i]
    for m in range(1, terms):
        term, weight = stages[rows[m], first:end], weights[m]
        for i in range(part.shape[0]):
            part[i] = part[i] + weight * term[i]


def _deficit(first, end, out, padded, count, plate_rate, time):
    """padded[i] = out[i] - V_pl t for the slip entries among ``first`` to ``end`` - 1: the slip deficit."""
    end = min(end, count)
    if end > first:
        slip, deficit = out[first:end], padded[first:end]
        for i in range(slip.shape[0]):
            deficit[i] = slip[i] - plate_rate * time


def _stage_entries(first, end, out, padded, y, h, weights, rows, stages, count, plate_rate, time):
    """Entries ``first`` to ``end`` - 1 of :func:`_stage`."""
    _weighted_sum(first, end, out, weights, rows, rows.shape[0], stages)
    state, start = out[first:end], y[first:end]
    for i in range(state.shape[0]):
        state[i] = start[i] + h * state[i]
    _deficit(first, end, out, padded, count, plate_rate, time)


def _stage(out, padded, y, h, weights, rows, stages, count, plate_rate, time):
    """out = y + h (w_0 k[rows_0] + w_1 k[rows_1] + ...); padded[:count] = out[:count] - V_pl t, the slip deficit
    the stress kernel takes."""
    size = y.shape[0]
    for part in prange(PARTS):
        _stage_entries(part * size // PARTS, (part + 1) * size // PARTS, out, padded, y, h, weights, rows, stages,
                       count, plate_rate, time)


def _error_entries(first, end, ratios, y, y_new, h, weights, rows, stages, rtol, scale):
    """Entries ``first`` to ``end`` - 1 of :func:`_error_ratios`."""
    _weighted_sum(first, end, ratios, weights, rows, rows.shape[0], stages)
    _ratios(first, end, ratios, y, y_new, h, rtol, scale)


def _ratios(first, end, ratios, y, y_new, h, rtol, scale):
    """ratios = |h ratios| / (rtol max(|y|, |y_new|, scale)) for entries ``first`` to ``end`` - 1, over views."""
    error, start, new, floor = ratios[first:end], y[first:end], y_new[first:end], scale[first:end]
    for i in range(error.shape[0]):
        error[i] = abs(h * error[i]) / (rtol * max(max(abs(start[i]), abs(new[i])), floor[i]))


def _error_ratios(ratios, y, y_new, h, weights, rows, stages, rtol, scale):
    """ratios = |h (e_1 k_1 + ...)| / (rtol max(|y|, |y_new|, scale)): Hairer's norm is their largest."""
    size = y.shape[0]
    for part in prange(PARTS):
        _error_entries(part * size // PARTS, (part + 1) * size // PARTS, ratios, y, y_new, h, weights, rows, stages,
                       rtol, scale)


# --- the whole step in one call (issue 43, items 2 and 3) ------------------------------------------------------
#
# Each stage's force balance and the next stage's state are one pass over the elements: element i's rates are
# all that its next state needs, so one pass does both (its state may be overwritten in place: element i's
# balance has read it). K x between them is taken in two halves of its spectrum, the even bins and the odd ones,
# which never meet (:mod:`faultslip.models.fault_2d.kernel`, "K x in two halves"): two tasks take one each.

#: rows of the step's ``transforms`` buffer (complex, M / 2 + 1 columns): the even half's spectrum, the odd half's
#: packed input (then its spectrum's pairs, the inverse's input), the odd half's spectrum and its inverse
EVEN_SPECTRUM, PACKED, ODD_SPECTRUM, ODD_INVERSE = range(4)


def _even_half(padded, transforms, halves, even_product):
    """a, K x's even bins' share: the slip deficit's first M values' real FFT, times the Toeplitz and Hankel
    spectra at the even bins 2 j (T_2j X + H_2j conj X), and its inverse, scaled by 1 / (2 M)."""
    half = even_product.shape[0]
    spectrum = transforms[EVEN_SPECTRUM]
    _real_fft(padded, spectrum)
    toeplitz, hankel = halves[TOEPLITZ_EVEN], halves[HANKEL_EVEN]
    for j in range(spectrum.shape[0]):
        value = spectrum[j]
        spectrum[j] = toeplitz[j] * value + hankel[j] * value.conjugate()
    _inverse_real_fft(spectrum, even_product, 0.5 / half)


def _odd_half(padded, transforms, halves):
    """K x's odd bins' share, as a complex vector r of length M / 2 (:func:`_sum_halves` unpacks it). The odd bins
    O_j = sum_n x_n w^(n (j + 1/2)), w = exp(-2 pi i / M), from one complex FFT Z of z_m = (x_2m + i x_2m+1) w^m:
    O_j = U_j + w^(j + 1/2) V_j, U_j = (Z_j + conj Z_j') / 2, V_j = (Z_j - conj Z_j') / 2i, j' = M / 2 - 1 - j.
    Their product B_j = T_2j+1 O_j + H_2j+1 conj O_j, and back: R_j = P_j + i Q_j, P_j = B_j + conj B_j',
    Q_j = (B_j - conj B_j') w^-(j + 1/2), and r = the inverse FFT of R over 2 M, so that w^-m r_m holds the odd
    share of K x at 2 m (its real part) and 2 m + 1 (its imaginary part)."""
    quarter = padded.shape[0] // 2
    packed = transforms[PACKED, :quarter]
    spectrum = transforms[ODD_SPECTRUM, :quarter]
    twiddle, half_twiddle = halves[TWIDDLE], halves[HALF_TWIDDLE]
    for m in range(quarter):
        packed[m] = complex(padded[2 * m], padded[2 * m + 1]) * twiddle[m]
    _complex_fft(packed, spectrum)
    toeplitz, hankel = halves[TOEPLITZ_ODD], halves[HANKEL_ODD]
    for j in range((quarter + 1) // 2):  # each pair (j, j') once; j = j' at the middle of an odd M / 2
        mirror = quarter - 1 - j
        first, second = spectrum[j], spectrum[mirror]
        odd_first = 0.5 * (first + second.conjugate()) - 0.5j * (first - second.conjugate()) * half_twiddle[j]
        odd_second = 0.5 * (second + first.conjugate()) - 0.5j * (second - first.conjugate()) * half_twiddle[mirror]
        product_first = toeplitz[j] * odd_first + hankel[j] * odd_first.conjugate()
        product_second = toeplitz[mirror] * odd_second + hankel[mirror] * odd_second.conjugate()
        packed[j] = (product_first + product_second.conjugate()) + 1j * (
            (product_first - product_second.conjugate()) * half_twiddle[j].conjugate())
        packed[mirror] = (product_second + product_first.conjugate()) + 1j * (
            (product_second - product_first.conjugate()) * half_twiddle[mirror].conjugate())
    _inverse_complex_fft(packed, transforms[ODD_INVERSE, :quarter], 0.5 / padded.shape[0])


def _sum_halves(first, end, product, even_product, transforms, halves):
    """K x = a + s for elements ``first`` to ``end`` - 1: the even half's a and the odd half's s, unpacked from
    :func:`_odd_half`'s r (s_2m + i s_2m+1 = w^-m r_m)."""
    odd, twiddle = transforms[ODD_INVERSE], halves[TWIDDLE]
    for i in range(first, end):
        m = i // 2
        share = odd[m] * twiddle[m].conjugate()
        product[i] = even_product[i] + (share.imag if i % 2 else share.real)


def _stress_product(padded, transforms, halves, even_product, product):
    """product = K x for the slip deficit x in ``padded`` (zero beyond the elements), on one thread: its two halves
    and their sum."""
    _even_half(padded, transforms, halves, even_product)
    _odd_half(padded, transforms, halves)
    _sum_halves(0, product.shape[0], product, even_product, transforms, halves)


# --- the threaded step: one parallel region a step (issue 43, item 3) -------------------------------------------
#
# numba's parallel region costs about 2.5 us to start here (its OpenMP layer), and a step of regions started 13:
# a sixth of a step on two threads at 1,600 elements. So on several threads a step is one region whose tasks, one a
# thread, meet at spin barriers between its phases (0.06 us here). Each task owns a run of the parts of the
# elements (:func:`_owned`), and each stage has two phases:
# - the halves and the preparation: task 0 takes K x's even half and task 1 its odd half (:func:`_even_half`,
#   :func:`_odd_half`), then each task prepares its own parts' balances (:func:`_prepare`: the exponentials,
#   Newton's warm start and the next sum's leading terms, none of which needs the stress);
# - the balance, as soon as both halves are done (:func:`_wait_for`, not a barrier: a task does not wait for the
#   other's preparation): each task sums K x's halves for its own parts (:func:`_sum_halves`), solves them in
#   order and finishes their next state (or error ratios), then takes any the others have left, from their ends
#   (:func:`_claimed`), once their owner has prepared them.
# A barrier opens each stage: its halves read the whole slip deficit the stage before wrote; and no balance, which
# writes the next deficit, starts before both halves are done. A barrier between the phases, as before, made the
# task with the cheaper half wait for the other's preparation too, and the split that evened the first phases left
# the balances uneven: task 1 took about 7 of a trial's 96 part-balances from task 0, each moving the part's data
# between the cores. Now the split evens each task's whole work (:func:`_adapted_split`; a part taken by another
# task counts as its owner's), 1-3 % faster a trial at 1,600 elements (docs/fault_2d.md).
# An element's arrays stay in the cache of the core that owns it, each part on cache lines of its own
# (:func:`_part_start`, :func:`on_lines`): only the slip deficit (to the halves) and the
# halves' results cross between cores each stage. Where the cores are far apart this decides the speed: on the
# earlier host the two vCPUs' round trip was 0.07 us at some times and 0.4 us at others, and a step in which one
# task prepared every element moved about 1,300 cache lines a stage between them and ran 280 us against 180.
# Every element's arithmetic, and the order of every sum, is the one-thread step's: the same bits on any threads.

#: int64s a cache line: each counter of the step's ``sync`` array on a line of its own
LINE = 8
#: a cache line's bytes
LINE_BYTES = 8 * LINE
#: ``sync``'s slots: the barrier's word (the barriers passed times :data:`BARRIER_UNIT`, plus the tasks arrived at
#: the next), the step given up, the spins a task waits at a barrier before it gives the step up (set once, by the
#: caller), and the trials a run's parallel region took (:func:`_run_tasks`)
BARRIER, ABANDONED, SPIN_LIMIT, TRIALS_TAKEN = 0, 2 * LINE, 3 * LINE, 3 * LINE + 1
#: a barrier word's unit of barriers passed: the tasks arrived are its remainder
BARRIER_UNIT = 1 << 16
#: slots kept from step to step: the parts task 0 owns (0 before the first step), and the smoothed difference of
#: the two tasks' work and a part's (cycles a trial step, :func:`_adapted_split`)
SPLIT, IMBALANCE, PART_COST = 4 * LINE, 5 * LINE, 6 * LINE
#: a step's cycles, tasks 0 and 1 a line each: each task's work (its half of K x, and its own parts' preparation
#: and balance, whichever task balanced them), and its parts' work alone
WORK, PART_WORK = 7 * LINE, 9 * LINE
#: the barriers passed when each half of K x was last finished (tasks 0 and 1, a line each; :func:`_publish`)
HALF_DONE = 11 * LINE
#: phases with parts: the first state's, and a balance a stage (at most 16 stages)
CLAIMED_PHASES = 17
#: each phase's part flags
CLAIMS = 13 * LINE
#: the barriers passed when each task last finished preparing its own parts, a line a task (at most PARALLEL_PARTS
#: tasks: each owns a part), after the claims
PREPARED = CLAIMS + (CLAIMED_PHASES * PARALLEL_PARTS + LINE - 1) // LINE * LINE
#: steps over which the split's measurements are averaged (an exponential average, 1 / SMOOTHING a step)
SMOOTHING = 8
#: the spins (seconds) after which a task waiting at a barrier gives the step up, which is then taken on one
#: thread: a thread that never comes (a threading layer that ran two tasks on one thread) must not hang a run
SPINS = 1 << 32
#: whether :func:`_step_tasks` runs its tasks side by side (a parallel build) or each phase's in turn (plain Python)
PARALLEL_REGION = False
#: :func:`_step_task`'s ``in_turn`` in a parallel region: every phase, or all but the first state's
ALL_PHASES, AFTER_FIRST_STATE = 0, -1
#: the rows of a threaded step's ``part_extremes``: each part's largest error ratio and its largest slip rate
LARGEST_RATIO, PEAK_SPEED = 0, 1


def on_lines(shape, dtype=float) -> np.ndarray:
    """A zeroed array whose data starts on a cache line (:data:`LINE` int64s, 64 bytes; numpy's often start 16 or
    48 bytes in): the threaded step's arrays, so that its parts (:func:`_part_start`) and its ``sync`` slots each
    keep lines of their own. Batches of trial steps at 1,600 elements, near: 2.5-3.3 % faster on two threads
    (docs/fault_2d.md)."""
    dtype = np.dtype(dtype)
    size = int(np.prod(shape)) * dtype.itemsize
    raw = np.zeros(size + LINE_BYTES, dtype=np.uint8)
    start = -raw.ctypes.data % LINE_BYTES
    return raw[start:start + size].view(dtype).reshape(shape)


def lined(array: np.ndarray) -> np.ndarray:
    """``array`` itself where its data is contiguous and starts on a cache line, else such a copy (:func:`on_lines`)."""
    if array.flags.c_contiguous and array.ctypes.data % LINE_BYTES == 0:
        return array
    copy = on_lines(array.shape, array.dtype)
    copy[...] = array
    return copy


def new_sync(spins: int = SPINS):
    """A threaded step's ``sync`` array, its spin limit set, on cache lines (each slot at a line's start)."""
    sync = on_lines(PREPARED + PARALLEL_PARTS * LINE, np.int64)
    sync[SPIN_LIMIT] = spins
    return sync


def _cycles():
    """A cycle counter (plain Python: nanoseconds; compiled: the time-stamp counter, :func:`_cycle_counter_intrinsic`):
    only differences taken on one thread are used."""
    return time.perf_counter_ns()


def _atomic_add(array, index, value):
    """array[index] += value, returning the old value (atomic in the compiled build)."""
    old = array[index]
    array[index] = old + value
    return old


def _atomic_load(array, index):
    """array[index] (an atomic load with acquire order in the compiled build: a spin loop sees other threads'
    stores)."""
    return array[index]


def _atomic_compare_swap(array, index, expected, value):
    """Set array[index] to ``value`` if it holds ``expected``; whether it did (atomic in the compiled build)."""
    if array[index] != expected:
        return False
    array[index] = value
    return True


def _barrier(sync, tasks):
    """Wait until all ``tasks`` have arrived. False when the step was given up (a wait beyond sync[SPIN_LIMIT]
    spins, here or at another task's barrier). All or none: every change of the barrier's word is one atomic
    compare-and-swap, so a task giving up takes its arrival back only while the barrier is still shut, and a
    barrier that opens opens for every task (a run's parallel region commits a trial after its last barrier:
    :func:`_run_task`)."""
    while True:
        if _atomic_load(sync, ABANDONED) != 0:
            return False
        word = _atomic_load(sync, BARRIER)
        if word % BARRIER_UNIT == tasks - 1:  # the last to arrive opens it: the next barrier, none arrived
            if _atomic_compare_swap(sync, BARRIER, word, word - word % BARRIER_UNIT + BARRIER_UNIT):
                return True
        elif _atomic_compare_swap(sync, BARRIER, word, word + 1):
            return _wait_while(sync, word // BARRIER_UNIT)


def _wait_while(sync, passed):
    """Spin while the barrier's word shows ``passed`` barriers. False if the step was given up meanwhile, or is
    given up here after sync[SPIN_LIMIT] spins: this task's arrival is taken back in the same swap that finds the
    barrier still shut."""
    spins, limit = 0, sync[SPIN_LIMIT]
    while True:
        word = _atomic_load(sync, BARRIER)
        if word // BARRIER_UNIT != passed:
            return True
        if _atomic_load(sync, ABANDONED) != 0:
            return False
        spins += 1
        if spins > limit:
            if _atomic_compare_swap(sync, BARRIER, word, word - 1):
                _atomic_add(sync, ABANDONED, 1)
                return False
            spins = 0  # the word moved (another arrival, or the barrier opened): look again


def _barriers_passed(sync):
    """The barriers this task has passed, read after it passed the last: the barrier's word cannot move past it
    until this task arrives at the next."""
    return _atomic_load(sync, BARRIER) // BARRIER_UNIT


def _publish(sync, slot, value):
    """sync[slot] = ``value``, after every store before it (a compare-and-swap: sequentially consistent); the
    slot has no other writer."""
    _atomic_compare_swap(sync, slot, sync[slot], value)


def _wait_for(sync, slot, value):
    """Spin until sync[slot] reaches ``value`` (:func:`_publish`). False if the step was given up meanwhile, or
    is given up here after sync[SPIN_LIMIT] spins: this task then never arrives at the trial's last barrier, so
    no task commits the trial (:func:`_barrier`)."""
    spins, limit = 0, sync[SPIN_LIMIT]
    while True:
        if _atomic_load(sync, ABANDONED) != 0:
            return False
        if _atomic_load(sync, slot) >= value:
            return True
        spins += 1
        if spins > limit:
            _atomic_add(sync, ABANDONED, 1)
            return False


def _halves_done(sync, task, tasks, passed):
    """Wait until both halves of K x of the stage that opened at ``passed`` barriers are done: task 0 for task
    1's, task 1 for task 0's, any other task for both (:func:`_wait_for`)."""
    for half in range(min(2, tasks)):
        if half != task and not _wait_for(sync, HALF_DONE + half * LINE, passed):
            return False
    return True


def _first_split(tasks):
    """The parts task 0 owns before a step has been timed: :data:`EVEN_EXTRA` more than an equal share (its half of
    K x costs less than task 1's), leaving each other task at least one."""
    return min(PARTS - tasks + 1, max(1, int(PARTS * (1.0 + EVEN_EXTRA) / tasks + 0.5)))


def _part_start(part, count):
    """The first of ``count`` elements in ``part`` of :data:`PARTS`: an equal share, rounded down to a cache line's
    worth (:data:`LINE` elements), so that with the step's arrays on cache lines (:func:`on_lines`) no line holds
    two parts' elements, which the two tasks would pass between their cores; part :data:`PARTS` starts at
    ``count``."""
    start = part * count // PARTS
    return start if part >= PARTS else start - start % LINE


def _part_elements(first_part, end_part, count):
    """The elements of parts ``first_part`` to ``end_part`` - 1, (first, end) (:func:`_part_start`)."""
    return _part_start(first_part, count), _part_start(end_part, count)


def _owned(task, tasks, split):
    """The run of parts ``task`` owns, (first, end): task 0 the first ``split``, the others an equal share of the
    rest."""
    if task == 0:
        return 0, split
    rest = PARTS - split
    return split + (task - 1) * rest // (tasks - 1), split + task * rest // (tasks - 1)


def _adapted_split(split, imbalance, part_cost, tasks, parts):
    """The next step's split of ``parts`` between two tasks, from the smoothed ``imbalance`` (task 0's work less
    task 1's) and ``part_cost`` (a part's preparation and balance), both a trial step's: a part moved from the slower
    task to the other changes the imbalance by twice its cost, so it is moved where the imbalance exceeds that cost
    (a smaller one would swing the other way), and each task keeps a part. Nothing moves without a cost (no cycle
    counter)."""
    if part_cost <= 0:
        return split
    if imbalance > part_cost and split > 1:
        return split - 1
    if -imbalance > part_cost and split < parts - tasks + 1:
        return split + 1
    return split


def _claimed(sync, phase, part):
    """Whether this call claimed ``part`` in ``phase`` (an atomic test and set: each part is claimed once)."""
    return _atomic_add(sync, CLAIMS + phase * PARTS + part, 1) == 0


def _next_part(sync, phase, task, tasks, split, position, passed):
    """The next part ``task`` takes in ``phase``, claimed (:func:`_claimed`), and the position to go on from
    (start at 0): its own parts in order, then each other task's left over, from their ends, if that task has
    prepared them in the stage that opened at ``passed`` barriers (sync[PREPARED], :func:`_publish`; 0 where the
    phase needs no preparation); (-1, position) when none is left. Position = offset PARTS + step: the
    ``step``-th part of task ``task`` + ``offset``."""
    while True:
        offset, step = position // PARTS, position % PARTS
        if offset >= tasks:
            return -1, position
        owner = (task + offset) % tasks
        first_part, end_part = _owned(owner, tasks, split)
        if step >= end_part - first_part or (
                offset > 0 and step == 0 and _atomic_load(sync, PREPARED + owner * LINE) < passed):
            position = (offset + 1) * PARTS
            continue
        part = first_part + step if offset == 0 else end_part - 1 - step
        position += 1
        if _claimed(sync, phase, part):
            return part, position
        if offset > 0:  # an owner takes its parts in order: those before are taken too
            position = (offset + 1) * PARTS


def _partial_entries(first, end, partial, weights, rows, terms, stages):
    """partial = w_0 k[rows_0] + ... for all but the last of ``terms`` (left to right, as :func:`_stage_entries`)."""
    _weighted_sum(first, end, partial, weights, rows, terms - 1, stages)


def _finish_stage_entries(first, end, out, padded, y, h, partial, weight, row, stages, count, plate_rate, time):
    """:func:`_stage_entries` from the sum of its leading terms: out = y + h (partial + w k[row])."""
    state, start, leading, newest = out[first:end], y[first:end], partial[first:end], stages[row, first:end]
    for i in range(state.shape[0]):
        state[i] = start[i] + h * (leading[i] + weight * newest[i])
    _deficit(first, end, out, padded, count, plate_rate, time)


def _finish_error_entries(first, end, ratios, y, y_new, h, partial, weight, row, stages, rtol, scale):
    """:func:`_error_entries` from the sum of its leading terms; returns their largest (NaN where one is NaN)."""
    error, leading, newest = ratios[first:end], partial[first:end], stages[row, first:end]
    for i in range(error.shape[0]):
        error[i] = leading[i] + weight * newest[i]
    _ratios(first, end, ratios, y, y_new, h, rtol, scale)
    largest = 0.0
    for i in range(error.shape[0]):
        value = error[i]
        if not value <= largest and not math.isnan(largest):  # NaN wins: a stage without a finite slip rate
            largest = value  # rejects the step
    return largest


def _first_state_parts(task, tasks, sync, split, out, padded, y, h, weights, rows, stages, plate_rate, time):
    """The step's first trial state (:func:`_stage`): the task's own parts, then any of the others' left over
    (:func:`_claimed`)."""
    count, position = out.shape[0] // 2, 0
    while True:
        part, position = _next_part(sync, 0, task, tasks, split, position, 0)
        if part < 0:
            return
        first, end = _part_elements(part, part + 1, count)
        _stage_entries(first, end, out, padded, y, h, weights, rows, stages, count, plate_rate, time)
        _stage_entries(count + first, count + end, out, padded, y, h, weights, rows, stages, count, plate_rate,
                       time)


def _prepare(first_part, end_part, state, u, sigma_a, inverse_a, two_v0_eta, aging, f0, inverse_b, coefficients,
             healing, warm, partial, weights, rows, terms, stages):
    """What the balance of parts ``first_part`` to ``end_part`` - 1 needs before its stress is known: the
    exponentials and Newton's warm start at ``state`` (:func:`_exponentials`), and the next sum's leading terms
    (``weights``, ``rows``, ``terms``) into ``partial``; in one loop each over the parts' elements, which
    vectorises better than a loop a part."""
    count = u.shape[0]
    first, end = _part_elements(first_part, end_part, count)
    _exponentials(first, end, state[count:], u, sigma_a, inverse_a, two_v0_eta, aging, f0, inverse_b, coefficients,
                  healing, warm)
    _partial_entries(first, end, partial, weights, rows, terms, stages)
    _partial_entries(count + first, count + end, partial, weights, rows, terms, stages)


def _halves_and_preparation(task, tasks, sync, split, passed, state, padded, transforms, halves, even_product, u,
                             sigma_a, inverse_a, two_v0_eta, aging, f0, inverse_b, coefficients, healing, warm,
                             partial, weights, rows, terms, stages):
    """Task 0 takes K x's even half (:func:`_even_half`), task 1 its odd half (:func:`_odd_half`), and each says
    so (sync[HALF_DONE]); then each task prepares its own parts (:func:`_prepare`), in its own cache, and says so
    (sync[PREPARED]: the others may take them), both as the stage's ``passed`` barriers. Tasks 0 and 1 add the
    cycles this took to their :data:`WORK` slots, and those of the preparation to their :data:`PART_WORK`."""
    began = _cycles()
    if task == 0:
        _even_half(padded, transforms, halves, even_product)
    elif task == 1:
        _odd_half(padded, transforms, halves)
    if task < 2:
        _publish(sync, HALF_DONE + task * LINE, passed)
    first_part, end_part = _owned(task, tasks, split)
    prepared = _cycles()
    _prepare(first_part, end_part, state, u, sigma_a, inverse_a, two_v0_eta, aging, f0, inverse_b, coefficients,
             healing, warm, partial, weights, rows, terms, stages)
    _publish(sync, PREPARED + task * LINE, passed)
    if task < 2:
        ended = _cycles()
        _atomic_add(sync, WORK + task * LINE, ended - began)
        _atomic_add(sync, PART_WORK + task * LINE, ended - prepared)


def _first_largest(values):
    """The largest of ``values`` as a loop from the first finds it (values[0], then each larger one): the peak slip
    rate of an accepted state, which has no NaN. Over the parts' peaks in order it gives the whole's, the same
    element and so the same bits, -0.0 or 0.0 included."""
    largest = values[0]
    for i in range(1, values.shape[0]):
        if values[i] > largest:
            largest = values[i]
    return largest


def _owner(part, tasks, split):
    """The task that owns ``part`` (:func:`_owned`)."""
    for task in range(tasks):
        if part < _owned(task, tasks, split)[1]:
            return task
    return tasks - 1


def _balance_parts(task, tasks, sync, split, passed, phase, row, product, even_product, transforms, halves,
                   initial_stress, stress, state, u, sigma_a, inverse_a, two_v0_eta, inverse_damping, aging,
                   aging_rate, f0, inverse_b, v0, critical_slip, b, iterations, tolerance, coefficients, healing,
                   warm, stages, partial, weights, rows, terms, following, out, padded, y, h, plate_rate, time, y_new,
                   ratios, rtol, scale, part_extremes):
    """The balance at ``state`` into k[row], the task's own parts in order and then the others' left over, from
    their ends, once prepared (:func:`_next_part`); each part's K x first summed from its halves
    (:func:`_sum_halves`), and the part then finished: its next state (``following``) or, after the last stage,
    its error ratios and their largest (part_extremes[LARGEST_RATIO]) and its largest slip rate
    (part_extremes[PEAK_SPEED]). Each part's cycles count as its owner's work (sync[WORK], sync[PART_WORK]), so
    that the split sees what each task owns, not what it happened to take."""
    count, position = u.shape[0], 0
    weight, newest = weights[terms - 1], rows[terms - 1]
    while True:
        part, position = _next_part(sync, phase, task, tasks, split, position, passed)
        if part < 0:
            return
        began = _cycles()
        first, end = _part_elements(part, part + 1, count)
        _sum_halves(first, end, product, even_product, transforms, halves)
        _solve_elements(first, end, product, initial_stress, True, stress, state[count:], u, sigma_a, inverse_a,
                        two_v0_eta, inverse_damping, aging, aging_rate, f0, inverse_b, v0, critical_slip, b,
                        stages[row, :count], stages[row, count:], iterations, tolerance, coefficients, healing,
                        warm, True)
        if following:
            for at in (0, count):
                _finish_stage_entries(at + first, at + end, out, padded, y, h, partial, weight, newest, stages,
                                      count, plate_rate, time)
        else:
            lower = _finish_error_entries(first, end, ratios, y, y_new, h, partial, weight, newest, stages, rtol,
                                          scale)
            upper = _finish_error_entries(count + first, count + end, ratios, y, y_new, h, partial, weight,
                                          newest, stages, rtol, scale)
            part_extremes[LARGEST_RATIO, part] = lower if math.isnan(lower) or lower >= upper else upper  # NaN wins
            part_extremes[PEAK_SPEED, part] = _first_largest(stages[row, first:end]) if end > first else -math.inf
        owner = _owner(part, tasks, split)
        if owner < 2:
            spent = _cycles() - began
            _atomic_add(sync, WORK + owner * LINE, spent)
            _atomic_add(sync, PART_WORK + owner * LINE, spent)


def _step_task(task, tasks, sync, split, part_extremes, y, h, t, stages, work, partial, y_new, padded, transforms, even_product, product,
               coefficients, healing, warm, halves, initial_stress, stress, u, sigma_a,
               inverse_a, two_v0_eta, inverse_damping, aging, aging_rate, f0, inverse_b, v0, critical_slip, b,
               iterations, tolerance, plan_rows, plan_weights, plan_terms, plan_fractions, error_rows, error_weights,
               rtol, scale, ratios, plate_rate, in_turn):
    """One task's share of a threaded trial step, phase by phase (``in_turn`` :data:`ALL_PHASES`, or
    :data:`AFTER_FIRST_STATE`: a run's region has taken its own parts' first state): a barrier opens each stage,
    and its balance waits for both halves of K x (:func:`_halves_done`); with ``in_turn`` > 0 only that phase
    (1: the first state; 2 s + 2 and 2 s + 3: stage s's two), without waiting."""
    last = plan_rows.shape[0] - 1
    if in_turn == ALL_PHASES or in_turn == 1:
        _first_state_parts(task, tasks, sync, split, work, padded, y, h, plan_weights[0, :plan_terms[0]],
                           plan_rows[0, :plan_terms[0]], stages, plate_rate, t + plan_fractions[0] * h)
    for s in range(last + 1):
        state = work if s < last else y_new
        following = s < last
        if following:
            weights, rows, terms = plan_weights[s + 1], plan_rows[s + 1], plan_terms[s + 1]
            out, time = (work if s + 1 < last else y_new), t + plan_fractions[s + 1] * h
        else:
            weights, rows, terms = error_weights, error_rows, error_rows.shape[0]
            out, time = y_new, t + h
        passed = 0  # in turn, every task's preparation comes before any balance
        if in_turn <= 0:
            if not _barrier(sync, tasks):
                return
            passed = _barriers_passed(sync)
        if in_turn <= 0 or in_turn == 2 * s + 2:
            _halves_and_preparation(task, tasks, sync, split, passed, state, padded, transforms, halves, even_product,
                                    u, sigma_a, inverse_a, two_v0_eta, aging, f0, inverse_b, coefficients, healing,
                                    warm, partial, weights, rows, terms, stages)
        if in_turn <= 0 and not _halves_done(sync, task, tasks, passed):
            return
        if in_turn <= 0 or in_turn == 2 * s + 3:
            _balance_parts(task, tasks, sync, split, passed, s + 1, s + 1, product, even_product, transforms, halves,
                           initial_stress, stress, state, u, sigma_a,
                           inverse_a, two_v0_eta, inverse_damping, aging, aging_rate, f0, inverse_b, v0, critical_slip,
                           b, iterations, tolerance, coefficients, healing, warm, stages, partial, weights, rows, terms,
                           following, out, padded, y, h, plate_rate, time, y_new, ratios, rtol, scale, part_extremes)


def _step_tasks(tasks, sync, part_extremes, y, h, t, stages, work, partial, y_new, padded, transforms, even_product, product, coefficients,
                healing, warm, halves, initial_stress, stress, u, sigma_a, inverse_a,
                two_v0_eta, inverse_damping, aging, aging_rate, f0, inverse_b, v0, critical_slip, b, iterations,
                tolerance, plan_rows, plan_weights, plan_terms, plan_fractions, error_rows, error_weights, rtol, scale,
                ratios, plate_rate):
    """The threaded trial step: one task a thread, in one parallel region (a parallel build), or each phase's tasks
    in turn (plain Python, where ``prange`` is ``range``: tasks one after another would wait at a barrier
    forever)."""
    split = sync[SPLIT]
    if PARALLEL_REGION:
        for task in prange(tasks):
            _step_task(task, tasks, sync, split, part_extremes, y, h, t, stages, work, partial, y_new, padded, transforms, even_product, product,
                       coefficients, healing, warm, halves, initial_stress, stress, u,
                       sigma_a, inverse_a, two_v0_eta, inverse_damping, aging, aging_rate, f0, inverse_b, v0,
                       critical_slip, b, iterations, tolerance, plan_rows, plan_weights, plan_terms, plan_fractions,
                       error_rows, error_weights, rtol, scale, ratios, plate_rate, ALL_PHASES)
    else:
        for in_turn in range(1, 2 * plan_rows.shape[0] + 2):
            for task in range(tasks):
                _step_task(task, tasks, sync, split, part_extremes, y, h, t, stages, work, partial, y_new, padded,
                           transforms, even_product, product, coefficients, healing, warm, halves, initial_stress,
                           stress, u, sigma_a, inverse_a, two_v0_eta, inverse_damping, aging, aging_rate, f0,
                           inverse_b, v0, critical_slip, b, iterations, tolerance, plan_rows, plan_weights,
                           plan_terms, plan_fractions, error_rows, error_weights, rtol, scale, ratios, plate_rate,
                           in_turn)


def _real_fft(values, spectrum):
    """spectrum = rfft(values), into the caller's buffer (plain Python: scipy's; compiled: rocket-fft's low-level
    transform, :func:`_fft_kernels`, which allocates nothing)."""
    from scipy import fft  # heavy: the plain-Python build's only

    spectrum[:] = fft.rfft(values)


def _inverse_real_fft(spectrum, values, scale):
    """values = the real inverse of the Hermitian ``spectrum``, unnormalised, times ``scale`` (as
    :func:`_real_fft`)."""
    from scipy import fft  # heavy: the plain-Python build's only

    values[:] = fft.irfft(spectrum, values.shape[0], norm="forward") * scale


def _complex_fft(values, spectrum):
    """spectrum = fft(values), into the caller's buffer (as :func:`_real_fft`)."""
    from scipy import fft  # heavy: the plain-Python build's only

    spectrum[:] = fft.fft(values)


def _inverse_complex_fft(spectrum, values, scale):
    """values = the inverse of ``spectrum``, unnormalised, times ``scale`` (as :func:`_real_fft`)."""
    from scipy import fft  # heavy: the plain-Python build's only

    values[:] = fft.ifft(spectrum, norm="forward") * scale


def _largest(ratios):
    """The largest of ``ratios``, NaN where one is NaN: Hairer's norm (a stage without a finite slip rate rejects
    the step)."""
    largest = 0.0
    for i in range(ratios.shape[0]):
        value = ratios[i]
        if not value <= largest:
            largest = value
            if math.isnan(value):
                break
    return largest


def _one_thread_step(y, h, t, stages, work, y_new, padded, transforms, even_product, product, coefficients, healing, warm, halves, initial_stress, stress, u, sigma_a, inverse_a, two_v0_eta, inverse_damping,
                     aging, aging_rate, f0, inverse_b, v0, critical_slip, b, iterations, tolerance, plan_rows,
                     plan_weights, plan_terms, plan_fractions, error_rows, error_weights, rtol, scale, ratios,
                     plate_rate):
    """:func:`_fused_step` on one thread: each stage's state and slip deficit (:func:`_stage_entries`), K x by its
    two halves (:func:`_stress_product`), its exponentials and force balance, in
    turn (fusing them was slower here); then the error ratios."""
    count = stress.shape[0]
    size = y.shape[0]
    last = plan_rows.shape[0] - 1
    for s in range(last + 1):
        terms = plan_terms[s]
        state = work if s < last else y_new
        _stage_entries(0, size, state, padded, y, h, plan_weights[s, :terms], plan_rows[s, :terms], stages, count,
                       plate_rate, t + plan_fractions[s] * h)
        _stress_product(padded, transforms, halves, even_product, product)
        row = s + 1
        _exponentials(0, count, state[count:], u, sigma_a, inverse_a, two_v0_eta, aging, f0, inverse_b, coefficients,
                      healing, warm)
        _solve_elements(0, count, product, initial_stress, True, stress, state[count:], u,
                        sigma_a, inverse_a, two_v0_eta, inverse_damping, aging, aging_rate, f0, inverse_b, v0,
                        critical_slip, b, stages[row, :count], stages[row, count:], iterations, tolerance,
                        coefficients, healing, warm, True)
    _error_entries(0, size, ratios, y, y_new, h, error_weights, error_rows, stages, rtol, scale)
    return _largest(ratios)


def _fused_step(y, h, t, stages, work, partial, y_new, padded, transforms, even_product, product, coefficients, healing, warm,
                halves, initial_stress, stress, u, u_start, sigma_a, inverse_a, two_v0_eta,
                inverse_damping, aging, aging_rate, f0, inverse_b, v0, critical_slip, b, iterations, tolerance,
                plan_rows, plan_weights, plan_terms, plan_fractions, error_rows, error_weights, rtol, scale, ratios,
                plate_rate, sync, part_extremes, tasks):
    """A whole Dormand-Prince trial step (stages[0] holds k1): :func:`_one_thread_step` on one thread, or
    :func:`_step_tasks` on ``tasks`` threads (the same arithmetic element by element, so the same bits). Returns
    Hairer's norm, the largest error ratio (NaN where a stage had no finite slip rate). ``stress`` is left at
    y_new's; y_new's rates are stages[6]. A threaded step whose threads did not all come is
    taken again on one thread from its start (``sync[SPIN_LIMIT]``)."""
    if PARTS == 1 or tasks < 2:
        return _one_thread_step(y, h, t, stages, work, y_new, padded, transforms, even_product, product, coefficients, healing, warm,
                                halves, initial_stress, stress, u, sigma_a, inverse_a,
                                two_v0_eta, inverse_damping, aging, aging_rate, f0, inverse_b, v0, critical_slip, b,
                                iterations, tolerance, plan_rows, plan_weights, plan_terms, plan_fractions, error_rows,
                                error_weights, rtol, scale, ratios, plate_rate)
    sync[:SPIN_LIMIT] = 0
    sync[WORK:] = 0
    if sync[SPLIT] == 0:
        sync[SPLIT] = _first_split(tasks)
    u_start[:] = u  # the Newton solves' warm start, which a step given up must not have moved
    _step_tasks(tasks, sync, part_extremes, y, h, t, stages, work, partial, y_new, padded, transforms, even_product, product,
                coefficients, healing, warm, halves, initial_stress, stress, u, sigma_a,
                inverse_a, two_v0_eta, inverse_damping, aging, aging_rate, f0, inverse_b, v0, critical_slip, b,
                iterations, tolerance, plan_rows, plan_weights, plan_terms, plan_fractions, error_rows, error_weights,
                rtol, scale, ratios, plate_rate)
    if sync[ABANDONED] != 0:
        sync[SPLIT] = 0  # a later step starts again from the first split: this one's times are a lost thread's
        u[:] = u_start
        return _one_thread_step(y, h, t, stages, work, y_new, padded, transforms, even_product, product, coefficients, healing, warm,
                                halves, initial_stress, stress, u, sigma_a, inverse_a,
                                two_v0_eta, inverse_damping, aging, aging_rate, f0, inverse_b, v0, critical_slip, b,
                                iterations, tolerance, plan_rows, plan_weights, plan_terms, plan_fractions, error_rows,
                                error_weights, rtol, scale, ratios, plate_rate)
    if tasks == 2:
        _move_split(sync, tasks)
    return _largest(part_extremes[LARGEST_RATIO])


def _moved_split(split, imbalance, part_cost, step_imbalance, step_part_cost, tasks):
    """A threaded step's times (its tasks' difference in work and a part's work, cycles) into the
    smoothed ``imbalance`` and ``part_cost`` (:data:`SMOOTHING`), and the split moved by a part where that pays
    (:func:`_adapted_split`): (split, imbalance, part_cost), the imbalance then the one expected after the move."""
    imbalance += (step_imbalance - imbalance) // SMOOTHING
    part_cost += (step_part_cost - part_cost) // SMOOTHING
    moved = _adapted_split(split, imbalance, part_cost, tasks, PARTS)
    return moved, imbalance + 2 * (moved - split) * part_cost, part_cost


def _move_split(sync, tasks):
    """After a threaded step: :func:`_moved_split` from the times in ``sync``, kept there."""
    sync[SPLIT], sync[IMBALANCE], sync[PART_COST] = _moved_split(
        sync[SPLIT], sync[IMBALANCE], sync[PART_COST], sync[WORK] - sync[WORK + LINE],
        (sync[PART_WORK] + sync[PART_WORK + LINE]) // PARTS, tasks)


# --- many steps in one call ------------------------------------------------------------------------------------
#
# Between two trial steps the integrator's Python (the step's controller, a station record, the event test and a
# call with 47 arguments) took about 30 us a step on one core, a tenth of a step at 1,600 elements, and the part
# a second thread cannot share. :func:`_run_steps` takes whole steps, accepted and rejected, in compiled code and
# returns to Python only where Python has something to do: an event starts or ends, the station records' buffer
# is full (or the profiles' with a profile due), the step budget is spent, the run ends or fails. Profiles, 129 of
# a 200-year run's 130 returns at 1,600 elements before, go into a buffer as the station records do.
#
# On several threads a call's trials are one parallel region (:func:`_run_tasks`), not one a trial: a region's
# start and end, the copies of k1 and the warm start and the peak, 9 us a trial on one thread at 1,600 elements,
# held up both threads, and the copies pulled the other core's lines to the first each step. A barrier ends each
# trial; both tasks then take the controller's decisions from the same numbers, and each copies its own parts.

#: ``clock``'s slots (float64, read and written): the time, the next step, the controller's memory (the last
#: accepted step's error) and whether the last trial was rejected (1.0), the smallest and largest accepted steps,
#: the peak slip rate of the last accepted state and of the one before, the largest peak in the event under way,
#: the time before the last accepted step, and the times of the last profile of each kind (between events and
#: within one; a task's own, so that every task takes the same decisions)
(TIME, STEP_SIZE, PREVIOUS_NORM, AFTER_REJECTION, MIN_STEP, MAX_STEP, PEAK, PREVIOUS_PEAK, EVENT_PEAK,
 PREVIOUS_TIME, LAST_PROFILE, LAST_COSEISMIC) = range(12)
CLOCK_SLOTS = 12
#: ``settings``' slots (float64, read): the run's end, rtol, the controller's memory weight (beta), the event speed,
#: the profile intervals between and within events, whether an event is under way (1.0)
(DURATION, RTOL, MEMORY_WEIGHT, EVENT_LIMIT, PROFILE_INTERVAL, COSEISMIC_INTERVAL, INSIDE) = range(7)
SETTINGS_SLOTS = 7
#: ``counters``' slots (int64): accepted steps, rejected trials, stage evaluations, station rows written this call,
#: which of ``states``' rows holds the state, the trials this call may take, the step at which to stop (-1: none),
#: the run's budget of accepted steps (max_steps), why the call returned (one of the RETURNED_ values below), and
#: the profile rows written this call (set to 0 by the caller)
STEPS, REJECTED, EVALUATIONS, ROWS, CURRENT, BUDGET, STOP_AT, MAX_STEPS, RETURNED, PROFILE_ROWS = range(10)
COUNTER_SLOTS = 10
#: why :func:`_run_steps` returned: the run reached its end; its step budget (max_steps); a rejected step left
#: t + h equal to t; an accepted step Python must look at (an event began or ended, the stop step, or a profile
#: due with the buffer of profile rows full); the buffer of station rows is full; the call's trials were spent
(RETURNED_END, RETURNED_MAX_STEPS, RETURNED_COLLAPSE, RETURNED_NOTICE, RETURNED_ROWS_FULL,
 RETURNED_BUDGET) = range(6)


def _ulp(x):
    """The spacing of floats at ``x`` >= 1 (numpy's spacing): 2^(e - 53) for x = m 2^e, 0.5 <= m < 1."""
    exponent = math.frexp(x)[1]
    return math.ldexp(1.0, exponent - 53)


def step_factor(norm, previous_norm, after_rejection, memory_weight):
    """The factor on the step after an accepted step of error ``norm`` (<= 1), the last accepted one's being
    ``previous_norm``: h_new / h = 0.9 err^-(1/5 - 3 beta / 4) err_old^beta (Hairer, Norsett & Wanner, Solving ODEs
    I, II.4, eq. 4.13), beta the ``memory_weight``, between 0.1 and 5, and at most 1 right after a rejection
    (Hairer's DOPRI5). One function for the Python loop and the compiled one, so the same bits."""
    growth = 0.9 * max(norm, 1e-10) ** (0.75 * memory_weight - 0.2) * previous_norm ** memory_weight
    factor = min(5.0, max(0.1, growth))
    return min(factor, 1.0) if after_rejection else factor


def rejection_factor(norm):
    """The factor on the step after a rejected one of error ``norm`` (> 1, inf where a stage had no finite slip
    rate): 0.9 err^(-1/5), at least 0.2; 0.1 for inf. The Python loop's and the compiled one's."""
    return max(0.2, 0.9 * norm ** -0.2) if math.isfinite(norm) else 0.1


#: a trial step's verdict (:func:`judged_step`)
ACCEPTED, REJECTED, COLLAPSED = 0, 1, 2


def judged_step(norm, h, t):
    """A trial step from t over h of error ``norm`` (NaN where a stage had no finite slip rate): (its norm, inf
    for NaN; the next step after a rejection (norm > 1, :func:`rejection_factor`), else h, which the controller
    then sets; ACCEPTED, REJECTED, or COLLAPSED where the next step would leave t + h equal to t). The Python
    loop's and the compiled one's."""
    if not math.isfinite(norm):
        norm = math.inf
    if norm <= 1.0:
        return norm, h, ACCEPTED
    h *= rejection_factor(norm)
    return norm, h, COLLAPSED if h <= 8 * _ulp(max(abs(t), 1.0)) else REJECTED


def _record_near(row, t, state, stress, speed, near):
    """A station record's raw values: t, and at the stations' neighbouring elements ``near`` the slip, the slip
    rate, the shear stress and the state (:func:`faultslip.models.fault_2d.integrate.station_rows` makes the
    record of them)."""
    count, width = stress.shape[0], near.shape[0]
    row[0] = t
    for j in range(width):
        element = near[j]
        row[1 + j] = state[element]
        row[1 + width + j] = speed[element]
        row[1 + 2 * width + j] = stress[element]
        row[1 + 3 * width + j] = state[count + element]


#: a run's loop goes on (no RETURNED_ value yet); a task of its parallel region found the run given up; an
#: accepted step whose only notice is a profile due (:func:`_profile_taken`)
GO_ON, GAVE_UP, PROFILE_DUE = -1, -2, -3
#: a task's row of the clock and the counters in a run's parallel region (two cache lines: one task's row is
#: never on another's line)
TASK_ROW = 2 * LINE


def _record_profile(row, t, peak, state, speed):
    """A profile's raw values: t, the peak slip rate, every element's slip and slip rate (the run makes the profile
    of them: the rate's log10 over a block of rows)."""
    count = speed.shape[0]
    row[0], row[1] = t, peak
    row[2:2 + count] = state[:count]
    row[2 + count:2 + 2 * count] = speed


def _profile_taken(returned, peak, clock, counters, settings, profiles):
    """After :func:`_accept`: where its only notice is a profile due and the buffer has a row free, the profile is
    taken here (the time of the last profile of its kind moved on, a row counted): (:data:`GO_ON`, its row);
    with the buffer full, (RETURNED_NOTICE, -1), for Python to take it; else (``returned``, -1)."""
    if returned != PROFILE_DUE:
        return returned, -1
    row = counters[PROFILE_ROWS]
    if row >= profiles.shape[0]:
        return RETURNED_NOTICE, -1
    if peak > settings[EVENT_LIMIT]:
        clock[LAST_COSEISMIC] = clock[TIME]
    else:
        clock[LAST_PROFILE] = clock[TIME]
    counters[PROFILE_ROWS] = row + 1
    return GO_ON, row


def _next_trial(states, clock, counters, settings, trials):
    """Before a run's next trial: why its loop stops (a RETURNED_ value: the run's end, its step budget, the call's
    trials spent) or :data:`GO_ON`; the trial's step, no further than the run's end (kept in ``clock``); its start
    state and the row for its end."""
    returned = GO_ON
    if not clock[TIME] < settings[DURATION]:
        returned = RETURNED_END
    elif counters[STEPS] >= counters[MAX_STEPS]:
        returned = RETURNED_MAX_STEPS
    elif trials >= counters[BUDGET]:
        returned = RETURNED_BUDGET
    else:
        clock[STEP_SIZE] = min(clock[STEP_SIZE], settings[DURATION] - clock[TIME])
    current = counters[CURRENT]
    return returned, clock[STEP_SIZE], states[current], states[1 - current]


def _verdict(norm, clock, counters):
    """A trial of error ``norm`` counted (:func:`judged_step`): after a rejected one, the next step. Its verdict and
    its norm."""
    counters[EVALUATIONS] += 6
    norm, h, verdict = judged_step(norm, clock[STEP_SIZE], clock[TIME])
    clock[STEP_SIZE] = h
    if verdict != ACCEPTED:
        counters[REJECTED] += 1
        clock[AFTER_REJECTION] = 1.0
    return verdict, norm


def _accept(norm, peak, clock, counters, settings):
    """The controller after an accepted trial of error ``norm``, its state's largest slip rate ``peak``: the time,
    the next step (:func:`step_factor`), the counters and the peaks. RETURNED_NOTICE where Python must look at the
    state (an event begins or ends, the stop step), :data:`PROFILE_DUE` where only a profile is due, else
    :data:`GO_ON`."""
    t, h = clock[TIME], clock[STEP_SIZE]
    clock[PREVIOUS_TIME] = t
    t = t + h
    clock[TIME] = t
    counters[CURRENT] = 1 - counters[CURRENT]
    counters[STEPS] += 1
    clock[MIN_STEP], clock[MAX_STEP] = min(clock[MIN_STEP], h), max(clock[MAX_STEP], h)
    clock[STEP_SIZE] = h * step_factor(norm, clock[PREVIOUS_NORM], clock[AFTER_REJECTION] != 0.0,
                                       settings[MEMORY_WEIGHT])
    clock[PREVIOUS_NORM], clock[AFTER_REJECTION] = max(norm, 1e-4), 0.0
    clock[PREVIOUS_PEAK], clock[PEAK] = clock[PEAK], peak
    inside = settings[INSIDE] != 0.0
    if inside:
        clock[EVENT_PEAK] = max(clock[EVENT_PEAK], peak)
    if (peak > settings[EVENT_LIMIT]) != inside or counters[STEPS] == counters[STOP_AT]:
        return RETURNED_NOTICE
    if (t - clock[LAST_COSEISMIC] >= settings[COSEISMIC_INTERVAL] if peak > settings[EVENT_LIMIT]
            else t - clock[LAST_PROFILE] >= settings[PROFILE_INTERVAL]):
        return PROFILE_DUE
    return GO_ON


def _steps_in_turn(states, clock, counters, settings, records, near, profiles, stages, work, partial, padded,
                   transforms, even_product, product, coefficients, healing, warm, halves, initial_stress, stress, u,
                   u_start, sigma_a, inverse_a, two_v0_eta, inverse_damping, aging, aging_rate, f0, inverse_b, v0,
                   critical_slip, b, iterations, tolerance, plan_rows, plan_weights, plan_terms, plan_fractions,
                   error_rows, error_weights, scale, ratios, plate_rate, sync, part_extremes, tasks, rows, trials):
    """:func:`_run_steps`' loop a trial at a time, each a :func:`_fused_step` (on one thread, or on ``tasks``
    threads in a region of its own), from ``rows`` station rows and ``trials`` trials taken."""
    count = stress.shape[0]
    while True:
        returned, h, y, y_new = _next_trial(states, clock, counters, settings, trials)
        if returned != GO_ON:
            break
        norm = _fused_step(y, h, clock[TIME], stages, work, partial, y_new, padded, transforms, even_product,
                           product, coefficients, healing, warm, halves, initial_stress, stress, u, u_start, sigma_a,
                           inverse_a, two_v0_eta, inverse_damping, aging, aging_rate, f0, inverse_b, v0,
                           critical_slip, b, iterations, tolerance, plan_rows, plan_weights, plan_terms,
                           plan_fractions, error_rows, error_weights, settings[RTOL], scale, ratios, plate_rate, sync,
                           part_extremes, tasks)
        trials += 1
        verdict, norm = _verdict(norm, clock, counters)
        if verdict == COLLAPSED:
            returned = RETURNED_COLLAPSE
            break
        if verdict != ACCEPTED:
            continue
        stages[0, :] = stages[6, :]  # k7 is the next step's k1 (first same as last)
        peak = _first_largest(stages[6, :count])
        returned, profile = _profile_taken(_accept(norm, peak, clock, counters, settings), peak, clock, counters,
                                           settings, profiles)
        if profile >= 0:
            _record_profile(profiles[profile], clock[TIME], peak, y_new, stages[6, :count])
        _record_near(records[rows], clock[TIME], y_new, stress, stages[6], near)
        rows += 1
        if returned == GO_ON and rows == records.shape[0]:
            returned = RETURNED_ROWS_FULL
        if returned != GO_ON:
            break
    counters[ROWS], counters[RETURNED] = rows, returned


def _run_task(task, tasks, task_clock, task_counters, states, settings, records, near, profiles, stages, work, partial,
              padded, transforms, even_product, product, coefficients, healing, warm, halves, initial_stress, stress, u,
              u_start, sigma_a, inverse_a, two_v0_eta, inverse_damping, aging, aging_rate, f0, inverse_b, v0,
              critical_slip, b, iterations, tolerance, plan_rows, plan_weights, plan_terms, plan_fractions, error_rows,
              error_weights, scale, ratios, plate_rate, sync, part_extremes):
    """One task's share of :func:`_steps_in_turn`'s loop in one parallel region over many trials: a barrier
    ends each trial (:func:`_barrier`: all tasks pass it or none), after which every task takes the same
    decisions from the same numbers (the controller on its own row of ``task_clock`` and ``task_counters``, the
    split of the parts from both tasks' times). What a task does between two trials it does for its own parts, in
    its own cache: the next k1 (k7), the Newton solves' warm start (``u_start``, kept for a run given up), the
    claims' reset and the first trial state; the peak slip rate comes from the parts' peaks. Task 0 writes the
    station rows, and at the end the clock and counters, the trials taken and the split. A barrier given up ends
    the region at the trial under way (uncommitted)."""
    clock, counters = task_clock[task], task_counters[task]
    count = stress.shape[0]
    split, imbalance, part_cost = sync[SPLIT], sync[IMBALANCE], sync[PART_COST]
    seen_work, seen_other_work = sync[WORK], sync[WORK + LINE]
    seen_part_work = sync[PART_WORK] + sync[PART_WORK + LINE]
    first_terms = plan_terms[0]
    first_weights, first_rows = plan_weights[0, :first_terms], plan_rows[0, :first_terms]
    rows, trials = 0, 0
    while True:
        returned, h, y, y_new = _next_trial(states, clock, counters, settings, trials)
        if returned != GO_ON:
            break
        t = clock[TIME]
        first_part, end_part = _owned(task, tasks, split)
        first, end = _part_elements(first_part, end_part, count)
        u_start[first:end] = u[first:end]
        for phase in range(1, plan_rows.shape[0] + 1):
            for part in range(first_part, end_part):
                sync[CLAIMS + phase * PARTS + part] = 0
        for part in range(first_part, end_part):
            part_first, part_end = _part_elements(part, part + 1, count)
            for at in (0, count):
                _stage_entries(at + part_first, at + part_end, work, padded, y, h, first_weights, first_rows, stages,
                               count, plate_rate, t + plan_fractions[0] * h)
        _step_task(task, tasks, sync, split, part_extremes, y, h, t, stages, work, partial, y_new, padded,
                   transforms, even_product, product, coefficients, healing, warm, halves, initial_stress, stress, u,
                   sigma_a, inverse_a, two_v0_eta, inverse_damping, aging, aging_rate, f0, inverse_b, v0,
                   critical_slip, b, iterations, tolerance, plan_rows, plan_weights, plan_terms, plan_fractions,
                   error_rows, error_weights, settings[RTOL], scale, ratios, plate_rate, AFTER_FIRST_STATE)
        if not _barrier(sync, tasks):
            returned = GAVE_UP
            break
        trials += 1
        if tasks == 2:  # both tasks' times, read by each: the same split on both
            task_work, other_work = sync[WORK], sync[WORK + LINE]
            part_work = sync[PART_WORK] + sync[PART_WORK + LINE]
            split, imbalance, part_cost = _moved_split(
                split, imbalance, part_cost, (task_work - seen_work) - (other_work - seen_other_work),
                (part_work - seen_part_work) // PARTS, tasks)
            seen_work, seen_other_work, seen_part_work = task_work, other_work, part_work
        verdict, norm = _verdict(_largest(part_extremes[LARGEST_RATIO]), clock, counters)
        if verdict == COLLAPSED:
            returned = RETURNED_COLLAPSE
            break
        if verdict != ACCEPTED:
            continue
        first_part, end_part = _owned(task, tasks, split)  # the next trial's own parts: its first state reads them
        first, end = _part_elements(first_part, end_part, count)
        for at in (0, count):  # k7 is the next step's k1 (first same as last): the task's own parts
            stages[0, at + first:at + end] = stages[6, at + first:at + end]
        peak = _first_largest(part_extremes[PEAK_SPEED])
        returned, profile = _profile_taken(_accept(norm, peak, clock, counters, settings), peak, clock, counters,
                                           settings, profiles)
        if task == 0:  # before its next barrier: no task writes y_new or k7 until then
            if profile >= 0:
                _record_profile(profiles[profile], clock[TIME], peak, y_new, stages[6, :count])
            _record_near(records[rows], clock[TIME], y_new, stress, stages[6], near)
        rows += 1
        if returned == GO_ON and rows == records.shape[0]:
            returned = RETURNED_ROWS_FULL
        if returned != GO_ON:
            break
    if task == 0:
        counters[ROWS], counters[RETURNED], sync[TRIALS_TAKEN] = rows, returned, trials
        sync[SPLIT], sync[IMBALANCE], sync[PART_COST] = split, imbalance, part_cost


def _run_tasks(tasks, task_clock, task_counters, states, settings, records, near, profiles, stages, work, partial,
               padded, transforms, even_product, product, coefficients, healing, warm, halves, initial_stress, stress,
               u, u_start, sigma_a, inverse_a, two_v0_eta, inverse_damping, aging, aging_rate, f0, inverse_b, v0,
               critical_slip, b, iterations, tolerance, plan_rows, plan_weights, plan_terms, plan_fractions, error_rows,
               error_weights, scale, ratios, plate_rate, sync, part_extremes):
    """A run's trials in one parallel region, one :func:`_run_task` a thread."""
    for task in prange(tasks):
        _run_task(task, tasks, task_clock, task_counters, states, settings, records, near, profiles, stages, work,
                  partial, padded, transforms, even_product, product, coefficients, healing, warm, halves,
                  initial_stress, stress, u, u_start, sigma_a, inverse_a, two_v0_eta, inverse_damping, aging,
                  aging_rate, f0, inverse_b, v0, critical_slip, b, iterations, tolerance, plan_rows, plan_weights,
                  plan_terms, plan_fractions, error_rows, error_weights, scale, ratios, plate_rate, sync, part_extremes)


def _run_steps(states, clock, counters, settings, records, near, profiles, stages, work, partial, padded, transforms,
               even_product, product, coefficients, healing, warm, halves, initial_stress, stress, u, u_start, sigma_a,
               inverse_a, two_v0_eta, inverse_damping, aging, aging_rate, f0, inverse_b, v0, critical_slip, b,
               iterations, tolerance, plan_rows, plan_weights, plan_terms, plan_fractions, error_rows, error_weights,
               scale, ratios, plate_rate, sync, part_extremes, tasks):
    """Dormand-Prince steps with the integrator's controller, from the state states[counters[CURRENT]] whose k1 is
    stages[0], as :func:`faultslip.models.fault_2d.integrate.run_cycles` takes them one by one in Python (the same
    operations, so its bits): until the run's end, or an accepted step Python must look at, or a full ``records``
    buffer (a row an accepted step: :func:`_record_near`), or counters[BUDGET] trials. A profile due is written to
    ``profiles`` (:func:`_profile_taken`, :func:`_record_profile`), counters[PROFILE_ROWS] rows a call. ``clock``
    and ``counters`` carry the integrator's state in and out, and why the call returned (counters[RETURNED]).

    On one thread each trial is a :func:`_fused_step`; on ``tasks`` threads of a parallel build the trials run in
    one parallel region (:func:`_run_tasks`), which a step's region start and end, about 9 us a trial at 1,600
    elements on one thread, and the copies between trials no longer hold up. Where a task waited beyond the spin
    limit the trial under way is taken again on one thread from its start (the Newton solves' warm start
    restored), and the call's other trials too."""
    rows, trials = 0, 0
    if PARALLEL_REGION and PARTS > 1 and tasks >= 2:
        sync[:SPIN_LIMIT] = 0
        sync[WORK:] = 0
        if sync[SPLIT] == 0:
            sync[SPLIT] = _first_split(tasks)
        task_clock, task_counters = np.empty((tasks, TASK_ROW)), np.empty((tasks, TASK_ROW), dtype=np.int64)
        for task in range(tasks):
            task_clock[task, :CLOCK_SLOTS] = clock
            task_counters[task, :COUNTER_SLOTS] = counters
        _run_tasks(tasks, task_clock, task_counters, states, settings, records, near, profiles, stages, work, partial,
                   padded, transforms, even_product, product, coefficients, healing, warm, halves, initial_stress,
                   stress, u, u_start, sigma_a, inverse_a, two_v0_eta, inverse_damping, aging, aging_rate, f0,
                   inverse_b, v0, critical_slip, b, iterations, tolerance, plan_rows, plan_weights, plan_terms,
                   plan_fractions, error_rows, error_weights, scale, ratios, plate_rate, sync, part_extremes)
        clock[:] = task_clock[0, :CLOCK_SLOTS]
        counters[:] = task_counters[0, :COUNTER_SLOTS]
        if sync[ABANDONED] == 0:
            return
        sync[SPLIT] = 0  # a later region starts again from the first split: these times are a lost thread's
        u[:] = u_start
        rows, trials, tasks = counters[ROWS], sync[TRIALS_TAKEN], 1
    _steps_in_turn(states, clock, counters, settings, records, near, profiles, stages, work, partial, padded,
                   transforms, even_product, product, coefficients, healing, warm, halves, initial_stress, stress, u,
                   u_start, sigma_a, inverse_a, two_v0_eta, inverse_damping, aging, aging_rate, f0, inverse_b, v0,
                   critical_slip, b, iterations, tolerance, plan_rows, plan_weights, plan_terms, plan_fractions,
                   error_rows, error_weights, scale, ratios, plate_rate, sync, part_extremes, tasks, rows, trials)


_KERNELS = {}
#: the functions over a part of the elements, compiled first; then the loops over the parts
ELEMENTS = ("_exponentials", "_solve_elements", "_weighted_sum", "_deficit", "_ratios", "_stage_entries",
            "_error_entries", "_partial_entries", "_finish_stage_entries", "_finish_error_entries")
#: the force balance's two pieces as the step calls them: its exponentials (SIMD), then Newton's method and the rates
PIECES = ("_exponentials", "_solve_elements")
KERNELS = ("_balance_rates", "_stage", "_error_ratios")
#: the whole step's functions, each built on those before it; ``_step_tasks`` holds the parallel region
STEP = ("_part_start", "_part_elements", "_wait_while", "_barrier", "_barriers_passed", "_publish", "_wait_for",
        "_halves_done", "_first_split", "_owned", "_adapted_split", "_moved_split", "_move_split", "_claimed",
        "_next_part", "_first_state_parts",
        "_prepare", "_even_half", "_odd_half", "_sum_halves", "_stress_product", "_halves_and_preparation",
        "_first_largest", "_owner", "_balance_parts", "_step_task", "_step_tasks", "_largest", "_one_thread_step",
        "_fused_step", "_ulp", "step_factor", "rejection_factor", "judged_step", "_record_near", "_record_profile",
        "_profile_taken", "_next_trial",
        "_verdict", "_accept", "_steps_in_turn", "_run_task", "_run_tasks", "_run_steps")
#: the functions that hold a parallel region in a parallel build
REGIONS = ("_step_tasks", "_run_tasks")
#: the first rocket-fft whose low-level transforms (``rocket_fft.lowlevel``: DUCC0's, into the caller's arrays) the
#: step calls
ROCKET_FFT = (0, 4)


def fused_available() -> bool:
    """Whether the whole step can be compiled: numba, and rocket-fft from :data:`ROCKET_FFT` (its transforms are
    callable from compiled code)."""
    if not available() or importlib.util.find_spec("rocket_fft") is None:
        return False
    try:
        release = importlib.metadata.version("rocket-fft")
    except importlib.metadata.PackageNotFoundError:
        return False
    parts = [int(part) if part.isdigit() else 0 for part in release.split(".")[:2]]
    return tuple(parts) >= ROCKET_FFT


#: the axis the step's transforms run along, as rocket-fft's low-level calls take it
FFT_AXES = np.zeros(1, dtype=np.int64)
#: rocket_fft.lowlevel, set where the step is built
lowlevel = None


def _low_level_real_fft(values, spectrum):
    """:func:`_real_fft` in the compiled build: rocket-fft's low-level r2c (DUCC0's), into ``spectrum``."""
    lowlevel.r2c(values, spectrum, FFT_AXES, True, 1.0, 1)


def _low_level_inverse_real_fft(spectrum, values, scale):
    """:func:`_inverse_real_fft` in the compiled build: rocket-fft's low-level c2r, times ``scale``."""
    lowlevel.c2r(spectrum, values, FFT_AXES, False, scale, 1)


def _low_level_complex_fft(values, spectrum):
    """:func:`_complex_fft` in the compiled build: rocket-fft's low-level c2c, forward."""
    lowlevel.c2c(values, spectrum, FFT_AXES, True, 1.0, 1)


def _low_level_inverse_complex_fft(spectrum, values, scale):
    """:func:`_inverse_complex_fft` in the compiled build: rocket-fft's low-level c2c, backward, times ``scale``."""
    lowlevel.c2c(spectrum, values, FFT_AXES, False, scale, 1)


#: the step's transforms: the plain-Python build's name -> the compiled build's
LOW_LEVEL = {"_real_fft": _low_level_real_fft, "_inverse_real_fft": _low_level_inverse_real_fft,
             "_complex_fft": _low_level_complex_fft, "_inverse_complex_fft": _low_level_inverse_complex_fft}


def _fft_kernels(build: str) -> dict:
    """The step's transforms compiled (:data:`LOW_LEVEL`): rocket-fft's low-level r2c, c2r and c2c, which write
    into the caller's arrays (scipy.fft's calls through rocket-fft allocate their results)."""
    import numba  # heavy: optional dependency (faultslip[fast]), as the kernels
    from rocket_fft import lowlevel as rocket_lowlevel  # heavy: as above

    inline = numba.njit(cache=True, inline="always")
    names = {"lowlevel": rocket_lowlevel}
    return {name: inline(_named(function, build, names)) for name, function in LOW_LEVEL.items()}


def _compiled(threads: int) -> dict:
    """name -> kernel, compiled by numba on first use (cached on disk): a serial build for one thread, a parallel
    one (numba's OpenMP or TBB layer) for more; with rocket-fft, the whole step (``fused_step``) on that build's
    kernels too."""
    key = "parallel" if threads > 1 else "serial"
    if key not in _KERNELS:
        import numba  # heavy: optional dependency (faultslip[fast]), imported only when the kernel is wanted

        module = globals()
        module["prange"] = numba.prange  # the loops become numba's (a serial build runs it as range)
        inline = numba.njit(cache=True, inline="always")
        exp = inline(_named(_exp, key, {"_float_from_bits": _float_from_bits_intrinsic()}))
        elements = {}
        for name in ELEMENTS:  # each built on those before it
            elements[name] = inline(_named(module[name], key, {**elements, "_exp": exp}))
        names = {**elements, "PARTS": PARALLEL_PARTS if key == "parallel" else 1}
        built = {name: numba.njit(cache=True, parallel=key == "parallel")(_named(module[name], key, names))
                 for name in KERNELS}
        _KERNELS[key] = {name.lstrip("_"): kernel for name, kernel in built.items()}
        for name in PIECES:  # callable alone too (their tests, the profile benchmark)
            _KERNELS[key][name.lstrip("_")] = elements[name]
        if fused_available():
            atomic_add, atomic_load, atomic_compare_swap = _atomic_intrinsics()
            step = {**names, **_fft_kernels(key), "_atomic_add": atomic_add, "_atomic_load": atomic_load,
                    "_atomic_compare_swap": atomic_compare_swap,
                    "_cycles": _cycle_counter_intrinsic(), "PARALLEL_REGION": key == "parallel"}
            for name in STEP:
                step[name] = numba.njit(cache=True, parallel=key == "parallel" and name in REGIONS)(
                    _named(module[name], key, step))
            _KERNELS[key]["fused_step"] = step["_fused_step"]
            _KERNELS[key]["run_steps"] = step["_run_steps"]
            _KERNELS[key]["stress_product"] = step["_stress_product"]  # alone too (its test, the profile)
    return _KERNELS[key]


def _outermost(built: dict, fused: bool | None):
    """The kernel a run calls first: the whole step where it is fused (``None``: wherever it can be built), else
    the force balance."""
    return built.get("run_steps") if fused is not False and "run_steps" in built else built["balance_rates"]


def compilation_pending(threads: int = 1, fused: bool | None = None) -> bool:
    """Whether the first compiled run on ``threads`` threads will compile the step here: numba's disk cache has
    no index yet for the build's outermost kernel (a fresh environment, or a new faultslip); ``fused``: the whole
    step's (True), the force balance's (False, a dense kernel's path), or the whole step's where it is built. Its
    cost, cold against warm, is measured by ``benchmarks/first_run.py``."""
    kernel = _outermost(_compiled(threads), fused)
    try:
        index = kernel._cache._cache_file._index_path  # numba's own cache locator, where it will look
    except AttributeError:  # a numba without that layout: say nothing rather than guess
        return False
    return not Path(index).exists()


def step_loaded(threads: int = 1, fused: bool | None = None) -> bool:
    """Whether this process holds the compiled step for ``threads`` threads already (a run here compiled it or
    loaded it from numba's cache): a later run pays no first-run cost. Builds nothing (no numba import)."""
    built = _KERNELS.get("parallel" if threads > 1 else "serial")
    return bool(built) and bool(_outermost(built, fused).overloads)


def _float_from_bits_intrinsic():
    """:func:`_float_from_bits` for numba: an LLVM bitcast (no instruction; a loop of them vectorises)."""
    from numba.core import types as numba_types  # heavy: optional dependency (faultslip[fast]), as the kernels
    from numba.extending import intrinsic  # heavy: as above

    @intrinsic
    def float_from_bits(typing_context, bits):
        def codegen(context, builder, signature, arguments):
            return builder.bitcast(arguments[0], context.get_value_type(numba_types.float64))
        return numba_types.float64(numba_types.int64), codegen
    return float_from_bits


def _no_cycles():
    """:func:`_cycles` where the compiled step reads no counter: 0, which leaves the split where it started."""
    return 0


def _cycle_counter_intrinsic():
    """:func:`_cycles` for numba: LLVM's readcyclecounter on x86 (the time-stamp counter, a few ns); elsewhere
    :func:`_no_cycles` (on ARM it reads a register user code may not, and the process would die)."""
    import numba  # heavy: optional dependency (faultslip[fast]), as the kernels

    if platform.machine().lower() not in ("x86_64", "amd64"):
        return numba.njit(cache=True, inline="always")(_no_cycles)
    from llvmlite import ir  # heavy: optional dependency (faultslip[fast]), as the kernels
    from numba.core import cgutils, types as numba_types  # heavy: as above
    from numba.extending import intrinsic  # heavy: as above

    @intrinsic
    def cycles(typing_context):
        def codegen(context, builder, signature, arguments):
            counter = cgutils.get_or_insert_function(builder.module, ir.FunctionType(ir.IntType(64), []),
                                                     "llvm.readcyclecounter")
            return builder.call(counter, [])
        return numba_types.int64(), codegen
    return cycles


def _atomic_intrinsics():
    """:func:`_atomic_add`, :func:`_atomic_load` and :func:`_atomic_compare_swap` for numba on an int64 array: LLVM's
    atomicrmw add and cmpxchg (sequentially consistent) and an atomic load with acquire order."""
    from numba.core import cgutils, types as numba_types  # heavy: optional dependency (faultslip[fast])
    from numba.extending import intrinsic  # heavy: as above

    def pointer(context, builder, array_type, array, index):
        made = context.make_array(array_type)(context, builder, array)
        return cgutils.get_item_pointer(context, builder, array_type, made, [index])

    @intrinsic
    def atomic_add(typing_context, array, index, value):
        def codegen(context, builder, signature, arguments):
            where = pointer(context, builder, signature.args[0], arguments[0], arguments[1])
            return builder.atomic_rmw("add", where, arguments[2], "seq_cst")
        return numba_types.int64(array, index, numba_types.int64), codegen

    @intrinsic
    def atomic_load(typing_context, array, index):
        def codegen(context, builder, signature, arguments):
            return builder.load_atomic(pointer(context, builder, signature.args[0], arguments[0], arguments[1]),
                                       "acquire", 8)
        return numba_types.int64(array, index), codegen

    @intrinsic
    def atomic_compare_swap(typing_context, array, index, expected, value):
        def codegen(context, builder, signature, arguments):
            where = pointer(context, builder, signature.args[0], arguments[0], arguments[1])
            swapped = builder.cmpxchg(where, arguments[2], arguments[3], "seq_cst", "seq_cst")
            return builder.extract_value(swapped, 1)
        return numba_types.boolean(array, index, numba_types.int64, numba_types.int64), codegen
    return atomic_add, atomic_load, atomic_compare_swap


def _named(function, build: str, names: dict | None = None):
    """``function`` itself for the serial build; for the parallel one a copy under its own qualified name, because
    numba's disk cache keeps one build per name (the parallel one would otherwise load the serial one). ``names``
    replace the copy's globals (the build's own kernels, for the fused step)."""
    if build == "serial" and not names:
        return function
    copy = types.FunctionType(function.__code__, {**function.__globals__, **(names or {})}, function.__name__,
                              function.__defaults__, function.__closure__)
    copy.__qualname__ = f"{function.__qualname__}_{build}"
    return copy


def kernels(compiled: bool = True, threads: int = 1) -> dict:
    """The force balance and the fused step kernels: numba's (serial, or over ``threads`` threads), or plain
    Python (``compiled=False``, the same loops, slow: for tests without numba; with ``threads`` > 1 the parallel
    build's loops, its parts run in turn)."""
    if not compiled:
        build = "python_parallel" if threads > 1 else "python"
        names = {"PARTS": PARALLEL_PARTS if threads > 1 else 1}
        loops = {name: _named(globals()[name], build, names) for name in KERNELS}
        plain = {name.lstrip("_"): function for name, function in loops.items()}
        plain.update({name.lstrip("_"): globals()[name] for name in PIECES})
        step = {**names, **loops}
        for name in STEP:
            step[name] = _named(globals()[name], build, step)
        plain["fused_step"] = step["_fused_step"]
        plain["run_steps"] = step["_run_steps"]
        plain["stress_product"] = step["_stress_product"]
        return plain
    return _compiled(threads)


def balance(compiled: bool = True):
    """The force balance (:func:`_balance_rates`), compiled by numba on first use (cached on disk), or as plain
    Python."""
    return kernels(compiled)["balance_rates"]
