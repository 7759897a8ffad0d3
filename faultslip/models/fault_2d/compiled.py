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
import importlib.util
import math
import struct
import types

from faultslip.dynamics.shared.compiler import available  # noqa: F401 (re-exported for the model)

#: the kernels' loops over parts of the elements: range in plain Python; numba's prange once compiled (a parallel
#: build splits the parts over threads, a serial one runs them as range)
prange = range
#: parts of the elements a kernel's loop runs: one in a serial build; PARALLEL_PARTS in a parallel one, some per
#: thread, so that a thread whose part holds an event's slow-converging elements holds up the others less
PARTS = 1
PARALLEL_PARTS = 16
#: K x's time (the FFT pair and the spectrum's product) against the exponentials of the N elements' balance
#: (:func:`_exponentials`, in SIMD): about 2.1 at 1,024 to 3,200 elements on the 2-core benchmark machine (12.2 us
#: against 5.8 at 1,600; both grow about as N). The FFTs' task takes that much less of the exponentials, so that
#: the tasks end together: none of them at 2.1, where the other task ends first.
FFT_COST = 2.1


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


def _exponentials(first, end, psi, u, inverse_a, two_v0_eta, aging, f0, inverse_b, coefficients, healing, warm):
    """What the force balance of elements ``first`` to ``end`` - 1 needs before their stress is known: from the
    state, c = 2 V_0 eta exp(-psi / a) and, for the aging law, exp((f_0 - psi) / b); and exp(u) at the Newton
    iteration's warm start, the last solution. Three of a solve's three or four exponentials (most solves take
    one Newton step), by :func:`_exp`, a loop each over views of the part (a loop over range(first, end) or over
    several outputs at once is not vectorised)."""
    state, speed_term, inverse_b_part = psi[first:end], inverse_a[first:end], inverse_b[first:end]
    coefficients_part, healing_part, warm_part, u_part = (coefficients[first:end], healing[first:end],
                                                          warm[first:end], u[first:end])
    for i in range(state.shape[0]):
        coefficients_part[i] = two_v0_eta * _exp(-state[i] * speed_term[i])
    if aging:
        for i in range(state.shape[0]):
            healing_part[i] = _exp((f0 - state[i]) * inverse_b_part[i])
    for i in range(state.shape[0]):
        warm_part[i] = _exp(u_part[i])


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
            e = warm[i] if iteration == 0 and started_warm else math.exp(x)
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
                        inverse_b, v0, critical_slip, b, speed, psi_rate, iterations, tolerance, psi, psi, psi, False)


# --- a Dormand-Prince step's element-wise work, fused (issue 43, items 2 and 3) -------------------------------
#
# numpy spent a fifth of a step on the stages' temporaries (y + h (a_1 k_1 + ...)) and the error norm: one pass
# each here, in numpy's order of operations (left to right; numba contracts nothing into fused multiply-adds
# without fastmath), so the bits are numpy's. The kernel's spectrum product stays numpy's: its complex product
# runs in SIMD with fused multiply-adds where the CPU has them, which no scalar loop reproduces bit for bit.
# Each element's arithmetic is the same on any number of threads.

def _stage_entries(first, end, out, padded, y, h, weights, rows, stages, count, plate_rate, time):
    """Entries ``first`` to ``end`` - 1 of :func:`_stage`."""
    for i in range(first, end):
        total = weights[0] * stages[rows[0], i]
        for m in range(1, rows.shape[0]):
            total = total + weights[m] * stages[rows[m], i]
        value = y[i] + h * total
        out[i] = value
        if i < count:
            padded[i] = value - plate_rate * time


def _stage(out, padded, y, h, weights, rows, stages, count, plate_rate, time):
    """out = y + h (w_0 k[rows_0] + w_1 k[rows_1] + ...); padded[:count] = out[:count] - V_pl t, the slip deficit
    the stress kernel takes."""
    size = y.shape[0]
    for part in prange(PARTS):
        _stage_entries(part * size // PARTS, (part + 1) * size // PARTS, out, padded, y, h, weights, rows, stages,
                       count, plate_rate, time)


def _error_entries(first, end, ratios, y, y_new, h, weights, rows, stages, rtol, scale):
    """Entries ``first`` to ``end`` - 1 of :func:`_error_ratios`."""
    for i in range(first, end):
        total = weights[0] * stages[rows[0], i]
        for m in range(1, rows.shape[0]):
            total = total + weights[m] * stages[rows[m], i]
        ratios[i] = abs(h * total) / (rtol * max(max(abs(y[i]), abs(y_new[i])), scale[i]))


def _error_ratios(ratios, y, y_new, h, weights, rows, stages, rtol, scale):
    """ratios = |h (e_1 k_1 + ...)| / (rtol max(|y|, |y_new|, scale)): Hairer's norm is their largest."""
    size = y.shape[0]
    for part in prange(PARTS):
        _error_entries(part * size // PARTS, (part + 1) * size // PARTS, ratios, y, y_new, h, weights, rows, stages,
                       rtol, scale)


# --- the whole step in one call (issue 43, items 2 and 3) ------------------------------------------------------
#
# Each stage's force balance and the next stage's state are one pass over the elements: element i's rates are
# all that its next state needs, so one parallel region a stage does both (its state may be overwritten in
# place: element i's balance has read it). The FFTs between them stay serial.

def _spectrum_product(both, spectrum, toeplitz_hat, hankel_hat):
    """both = T^ X + H^ conj(X): the Toeplitz and the Hankel parts of K x in one spectrum
    (:class:`faultslip.models.fault_2d.kernel.StressKernel`). Serial: a few microseconds, less than a parallel
    region costs."""
    for i in range(spectrum.shape[0]):
        both[i] = toeplitz_hat[i] * spectrum[i] + hankel_hat[i] * spectrum[i].conjugate()


def _balance_then_stage(product, initial_stress, stress, psi, u, sigma_a, inverse_a, two_v0_eta, inverse_damping,
                        aging, aging_rate, f0, inverse_b, v0, critical_slip, b, speed, psi_rate, iterations, tolerance,
                        coefficients, healing, warm, out, padded, y, h, weights, rows, stages, plate_rate, time):
    """The force balance (the stress set from ``product``; in a parallel build its exponentials done beside the
    FFTs), then :func:`_stage` for the next state, a part of the elements at a time."""
    count = stress.shape[0]
    for part in prange(PARTS):
        first, end = part * count // PARTS, (part + 1) * count // PARTS
        _solve_elements(first, end, product, initial_stress, True, stress, psi, u, sigma_a, inverse_a, two_v0_eta,
                        inverse_damping, aging, aging_rate, f0, inverse_b, v0, critical_slip, b, speed, psi_rate,
                        iterations, tolerance, coefficients, healing, warm, True)
        _stage_entries(first, end, out, padded, y, h, weights, rows, stages, count, plate_rate, time)
        _stage_entries(count + first, count + end, out, padded, y, h, weights, rows, stages, count, plate_rate, time)


def _balance_then_error(product, initial_stress, stress, psi, u, sigma_a, inverse_a, two_v0_eta, inverse_damping,
                        aging, aging_rate, f0, inverse_b, v0, critical_slip, b, speed, psi_rate, iterations, tolerance,
                        coefficients, healing, warm, ratios, y, y_new, h, weights, rows, stages, rtol, scale):
    """The force balance at y_new (its k7), then :func:`_error_ratios`, a part of the elements at a time."""
    count = stress.shape[0]
    for part in prange(PARTS):
        first, end = part * count // PARTS, (part + 1) * count // PARTS
        _solve_elements(first, end, product, initial_stress, True, stress, psi, u, sigma_a, inverse_a, two_v0_eta,
                        inverse_damping, aging, aging_rate, f0, inverse_b, v0, critical_slip, b, speed, psi_rate,
                        iterations, tolerance, coefficients, healing, warm, True)
        _error_entries(first, end, ratios, y, y_new, h, weights, rows, stages, rtol, scale)
        _error_entries(count + first, count + end, ratios, y, y_new, h, weights, rows, stages, rtol, scale)


def _product_and_exponentials(product, both, padded, toeplitz_hat, hankel_hat, length, psi, u, inverse_a,
                              two_v0_eta, aging, f0, inverse_b, coefficients, healing, warm, tasks):
    """K x (one real FFT, the spectrum product, the inverse) into ``product``, and the exponentials the balance
    needs before it (:func:`_exponentials`), side by side, a task a thread (``tasks``, at least 2): task 0 is the
    FFTs and the first share of the elements, the others the rest in equal parts. Neither needs the other, so
    the FFTs, which run on one thread, take no time of their own."""
    count = psi.shape[0]
    others = tasks - 1
    start = int(count * max(0.0, (1.0 / others - FFT_COST) / (1.0 + 1.0 / others)))
    for task in prange(tasks):
        if task == 0:
            _spectrum_product(both, fft.rfft(padded), toeplitz_hat, hankel_hat)
            product[:] = fft.irfft(both, length)
            _exponentials(0, start, psi, u, inverse_a, two_v0_eta, aging, f0, inverse_b, coefficients, healing, warm)
        else:
            first = start + (task - 1) * (count - start) // others
            end = start + task * (count - start) // others
            _exponentials(first, end, psi, u, inverse_a, two_v0_eta, aging, f0, inverse_b, coefficients, healing,
                          warm)


#: scipy.fft, set where the step kernel is built: numba compiles its calls through rocket-fft
fft = None


def _fused_step(y, h, t, stages, work, y_new, padded, both, product, coefficients, healing, warm, toeplitz_hat,
                hankel_hat, length, initial_stress, stress, u, sigma_a, inverse_a, two_v0_eta, inverse_damping, aging,
                aging_rate, f0, inverse_b, v0, critical_slip, b, iterations, tolerance, plan_rows, plan_weights,
                plan_terms, plan_fractions, error_rows, error_weights, rtol, scale, ratios, plate_rate, tasks):
    """A whole Dormand-Prince trial step (stages[0] holds k1). On one thread, for each stage its state and slip
    deficit (:func:`_stage`), K x by one real FFT and its inverse, and its force balance (:func:`_balance_rates`);
    then the error ratios. On several, the first stage's state; then for each stage K x beside the state's
    exponentials (:func:`_product_and_exponentials`), and the force balance with the next state
    (:func:`_balance_then_stage`), the last with the error ratios (:func:`_balance_then_error`): the same
    arithmetic element by element, so the same bits. Returns Hairer's norm, the largest ratio (NaN where a stage
    had no finite slip rate); ``tasks``: the threads, at least 2. ``stress`` is left at y_new's; y_new's rates are
    stages[6]."""
    count = stress.shape[0]
    last = plan_rows.shape[0] - 1
    if PARTS == 1:  # one thread: each stage's state, K x, its balance, in turn (fusing them was slower here)
        for s in range(last + 1):
            terms = plan_terms[s]
            state = work if s < last else y_new
            _stage(state, padded, y, h, plan_weights[s, :terms], plan_rows[s, :terms], stages, count, plate_rate,
                   t + plan_fractions[s] * h)
            _spectrum_product(both, fft.rfft(padded), toeplitz_hat, hankel_hat)
            row = s + 1
            # the exponentials first, in SIMD, as the parallel branch takes them: the same bits on any threads
            _exponentials(0, count, state[count:], u, inverse_a, two_v0_eta, aging, f0, inverse_b, coefficients,
                          healing, warm)
            _solve_elements(0, count, fft.irfft(both, length), initial_stress, True, stress, state[count:], u,
                            sigma_a, inverse_a, two_v0_eta, inverse_damping, aging, aging_rate, f0, inverse_b, v0,
                            critical_slip, b, stages[row, :count], stages[row, count:], iterations, tolerance,
                            coefficients, healing, warm, True)
        _error_ratios(ratios, y, y_new, h, error_weights, error_rows, stages, rtol, scale)
    else:  # threads: the FFTs beside the exponentials, then each balance with the next state in one region
        terms = plan_terms[0]
        _stage(work, padded, y, h, plan_weights[0, :terms], plan_rows[0, :terms], stages, count, plate_rate,
               t + plan_fractions[0] * h)
        for s in range(last + 1):
            state = work if s < last else y_new
            _product_and_exponentials(product, both, padded, toeplitz_hat, hankel_hat, length, state[count:], u,
                                      inverse_a, two_v0_eta, aging, f0, inverse_b, coefficients, healing, warm,
                                      tasks)
            row = s + 1
            if s < last:
                following = s + 1
                terms = plan_terms[following]
                out = work if following < last else y_new
                _balance_then_stage(product, initial_stress, stress, state[count:], u, sigma_a, inverse_a,
                                    two_v0_eta, inverse_damping, aging, aging_rate, f0, inverse_b, v0, critical_slip,
                                    b, stages[row, :count], stages[row, count:], iterations, tolerance, coefficients,
                                    healing, warm, out, padded, y, h, plan_weights[following, :terms],
                                    plan_rows[following, :terms], stages, plate_rate, t + plan_fractions[following] * h)
            else:
                _balance_then_error(product, initial_stress, stress, state[count:], u, sigma_a, inverse_a,
                                    two_v0_eta, inverse_damping, aging, aging_rate, f0, inverse_b, v0, critical_slip,
                                    b, stages[row, :count], stages[row, count:], iterations, tolerance, coefficients,
                                    healing, warm, ratios, y, y_new, h, error_weights, error_rows, stages, rtol, scale)
    largest = 0.0
    for i in range(ratios.shape[0]):
        value = ratios[i]
        if not value <= largest:  # NaN wins: a stage without a finite slip rate rejects the step
            largest = value
            if math.isnan(value):
                break
    return largest


_KERNELS = {}
#: the functions over a part of the elements, compiled first; then the loops over the parts
ELEMENTS = ("_exponentials", "_solve_elements", "_stage_entries", "_error_entries", "_spectrum_product")
#: the force balance's two pieces as the step calls them: its exponentials (SIMD), then Newton's method and the rates
PIECES = ("_exponentials", "_solve_elements")
KERNELS = ("_balance_rates", "_stage", "_error_ratios", "_balance_then_stage", "_balance_then_error")


def fused_available() -> bool:
    """Whether the whole step can be compiled: numba, and rocket-fft (which lets numba call scipy.fft)."""
    return available() and importlib.util.find_spec("rocket_fft") is not None


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
        elements = {name: inline(_named(module[name], key, {"_exp": exp}) if name == "_exponentials" else module[name])
                    for name in ELEMENTS}
        names = {**elements, "PARTS": PARALLEL_PARTS if key == "parallel" else 1}
        built = {name: numba.njit(cache=True, parallel=key == "parallel")(_named(module[name], key, names))
                 for name in KERNELS}
        _KERNELS[key] = {name.lstrip("_"): kernel for name, kernel in built.items()}
        for name in PIECES:  # callable alone too (their tests, the profile benchmark)
            _KERNELS[key][name.lstrip("_")] = elements[name]
        if fused_available():
            from scipy import fft as scipy_fft  # heavy: imported where the step is built

            with_fft = {**names, "fft": scipy_fft}
            side_by_side = numba.njit(cache=True, parallel=key == "parallel")(
                _named(_product_and_exponentials, key, with_fft))
            _KERNELS[key]["fused_step"] = numba.njit(cache=True)(_named(
                _fused_step, key, {**built, **with_fft, "_product_and_exponentials": side_by_side}))
    return _KERNELS[key]


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
        from scipy import fft as scipy_fft  # heavy: imported where the step runs

        build = "python_parallel" if threads > 1 else "python"
        names = {"PARTS": PARALLEL_PARTS if threads > 1 else 1, "fft": scipy_fft}
        loops = {name: _named(globals()[name], build, names) for name in KERNELS}
        side_by_side = _named(_product_and_exponentials, build, names)
        plain = {name.lstrip("_"): function for name, function in loops.items()}
        plain.update({name.lstrip("_"): globals()[name] for name in PIECES})
        plain["fused_step"] = _named(_fused_step, build, {**names, **loops,
                                                          "_product_and_exponentials": side_by_side})
        return plain
    return _compiled(threads)


def balance(compiled: bool = True):
    """The force balance (:func:`_balance_rates`), compiled by numba on first use (cached on disk), or as plain
    Python."""
    return kernels(compiled)["balance_rates"]
