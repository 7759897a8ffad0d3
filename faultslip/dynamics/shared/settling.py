"""Has a steady cycle settled? The one test every family that reports a steady cycle uses.

A steady-cycle quantity (slip per event, period, force swing) is the limit of a sequence q_1, q_2,
... that a cycle map produces. Successive cycles agreeing is not enough: near a bifurcation the map
contracts by a rate rho -> 1 per cycle, successive cycles differ by |d_n| while the limit is still

    |q_inf - q_n| ~ |d_n| rho / (1 - rho)                                   (geometric tail)

away, which can be many times |d_n| (issue 27: 400 cycles of Cameron's law 5.7 % from the steady
cycle with successive cycles agreeing to 1e-6). :func:`assess_settling` estimates rho from the
last differences and declares that tail as the remaining error; a sequence is settled only when
the tail is within the tolerance. :func:`aitken` extrapolates the limit (Aitken's delta-squared,
exact for a geometric approach), which a family with a one-dimensional cycle map can restart from
(Steffensen's method) to reach the steady cycle in a few cycles however slow the natural approach.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: Relative change treated as round-off: a sequence this still is periodic to machine precision.
ROUND_OFF = 1e-13
#: Ratios of successive differences whose largest is the contraction rate.
WINDOW = 4
#: Cycles over which a spiralling approach's average contraction is measured.
TREND_WINDOW = 16
#: Changes that stall below this many times the method's nominal per-cycle error are its scatter, not a
#: sequence that fails to settle (aging-law cycles at K / K_c = 0.997 stalled at 25 rtol, issue 42).
STALL_FACTOR = 100.0
#: The geometric tail is declared twice over: the contraction is measured on a few cycles and drifts
#: where the approach is not yet linear (0.02 % short for Cameron's law 1 % below V_c without it).
TAIL_SAFETY = 2.0


@dataclass(frozen=True)
class Settling:
    """The verdict on a sequence of cycles."""

    settled: bool
    cycles: int
    contraction: float  # rho, the per-cycle contraction of successive differences (nan: unknown)
    remaining: float  # estimated relative distance from the last cycle to the steady one
    limit: np.ndarray  # the steady quantities extrapolated (the last cycle's once settled)
    reason: str  # one sentence: settled, or why not and how far

    def cycles_to_settle(self, tolerance: float) -> float:
        """More cycles the natural approach needs to bring the remaining distance within ``tolerance``."""
        if self.settled:
            return 0.0
        if not 0 < self.contraction < 1 or not math.isfinite(self.remaining):
            return math.inf
        if self.remaining <= tolerance:
            return 0.0
        return max(math.log(tolerance / self.remaining) / math.log(self.contraction), 0.0)


def settled_error(numerical: float, remaining: float) -> float:
    """A steady-cycle quantity's declared error: the method's own error and what settling left, added.

    The run's last cycle is ``remaining`` from the steady cycle of the equations as integrated, which is
    ``numerical`` from the true one: the two add (the triangle inequality), and the larger alone understates
    their sum by up to 2x (a fresh draw of random rate-and-state faults, K / K_c 0.998 at rtol 1e-10: 1.38e-6 off
    against 1.05e-6 declared, with 7.5e-7 of settling left). An unknown remaining distance (nan) is unbounded.
    """
    remaining = float(remaining)
    return math.inf if math.isnan(remaining) else float(numerical) + remaining


def aitken(x0, x1, x2):
    """Aitken's delta-squared limit of x0, x1, x2 (elementwise): x2 - (x2 - x1)^2 / (x2 - 2 x1 + x0).

    Where the second difference vanishes (already constant, or not geometric), x2 itself.
    """
    x0, x1, x2 = (np.asarray(v, float) for v in (x0, x1, x2))
    second = x2 - 2 * x1 + x0
    safe = np.abs(second) > 1e-300
    return np.where(safe, x2 - (x2 - x1) ** 2 / np.where(safe, second, 1.0), x2)


def assess_settling(history, tolerance: float, floor=None, names=None, noise: float = ROUND_OFF,
                    contraction_hint: float = math.nan) -> Settling:
    """Whether the cycles in ``history`` (one row per cycle, one column per quantity) have settled.

    Differences are relative to ``max(|q_last|, floor)`` per quantity (``floor`` keeps a quantity
    that tends to zero, such as the stress drop above a critical speed, from dividing by zero).
    The remaining distance is the geometric tail |d_n| rho / (1 - rho), with rho the geometric
    largest of the last ratios |d_k| / |d_(k-1)|; it is infinite while the sequence does not contract.
    ``noise`` is the method's own error per cycle (an integrator's tolerance): changes that small
    are indistinguishable from it, so a sequence whose last two changes are within it has settled
    to it. What remains is then noise / (1 - rho): an error of ``noise`` per cycle moves the fixed
    point of a map contracting by rho that much, which near a bifurcation (rho -> 1) is many times
    the noise. rho is ``contraction_hint`` (measured earlier, before the noise took over) when the
    history itself cannot show it.
    """
    q = np.asarray(history, float)
    if q.ndim == 1:
        q = q[:, None]
    count = q.shape[0]
    names = list(names) if names is not None else [f"quantity {i}" for i in range(q.shape[1])]
    if count < 2:
        return Settling(False, count, math.nan, math.inf, q[-1] if count else q,
                        "fewer than two cycles: nothing to compare")
    scale = np.abs(q[-1])
    if floor is not None:
        scale = np.maximum(scale, np.asarray(floor, float))
    scale = np.where(scale > 0, scale, 1.0)
    steps = np.abs(np.diff(q, axis=0)) / scale
    change = steps.max(axis=1)
    worst = names[int(np.argmax(steps[-1]))]
    last = float(change[-1])
    if last <= ROUND_OFF:
        return Settling(True, count, 0.0, last, q[-1].copy(), f"periodic to round-off after {count} cycles")
    if noise > ROUND_OFF and change.size >= 2 and change[-2:].max() <= noise:
        gain = 1.0 / (1.0 - contraction_hint) if 0 < contraction_hint < 1 else 1.0
        return Settling(True, count, contraction_hint, noise * gain, q[-1].copy(),
                        f"settled after {count} cycles to the method's own error: successive cycles differ by "
                        f"{last:.2g}, within {noise:.2g}" + (f", which the map's contraction {contraction_hint:.3g} "
                                                             f"amplifies to {noise * gain:.2g}" if gain > 1 else ""))
    if count < 4:
        return Settling(False, count, math.nan, math.inf, q[-1].copy(),
                        f"{count} cycles, successive change {last:.2g} ({worst}): too few to estimate the approach")
    window = min(WINDOW, change.size - 1)
    previous = change[-window - 1:-1]
    current = change[-window:]
    usable = previous > ROUND_OFF
    ratios = current[usable] / previous[usable]
    # the largest recent ratio, not their mean: a contraction underestimated from a few cycles would
    # declare too short a tail (measured: 25 % short for Cameron's law 0.4 % below V_c)
    rho = float(ratios.max()) if ratios.size else math.nan
    if 0 < contraction_hint < 1 and not rho >= 1:  # measured earlier on larger, cleaner differences
        rho = max(rho, contraction_hint) if math.isfinite(rho) else contraction_hint
    if not rho < 1:
        # an approach that spirals in (near a Hopf bifurcation the cycle map's contraction is complex) makes
        # single ratios exceed 1 while the changes still shrink on the whole: the trend over a longer window
        # (the envelope: the largest change in each half of the window, robust to the spiral's phase)
        span = min(TREND_WINDOW, change.size)
        half = span // 2
        early, late = change[-span:-span + half].max(), change[-half:].max()
        trend = (late / early) ** (1.0 / (span - half)) if span >= 8 and early > 0 else math.inf
        level = float(change[-span:].max())
        # scatter changes sign at random; a slow drift (a growing transient near a bifurcation) keeps its sign
        signed = np.diff(q, axis=0)[-span:] / scale
        flips = np.count_nonzero(np.diff(np.sign(signed), axis=0), axis=0)
        scattered = bool(np.all(flips >= span // 4))
        if not trend < 1 and span >= 8 and scattered and noise > ROUND_OFF and level <= STALL_FACTOR * noise:
            # the changes neither shrink nor grow, at the method's own scale: the sequence has settled to the
            # integrator's scatter, which is larger here than its nominal error (near a bifurcation the map
            # amplifies it); that scatter, amplified as the contraction measured earlier says, is what remains
            gain = 1.0 / (1.0 - contraction_hint) if 0 < contraction_hint < 1 else 1.0
            return Settling(True, count, contraction_hint, TAIL_SAFETY * level * gain, q[-1].copy(),
                            f"settled after {count} cycles to the integrator's scatter: successive cycles differ by "
                            f"up to {level:.2g} over the last {span + 1} without shrinking or growing, "
                            f"{level / noise:.2g} times the nominal {noise:.2g}; declared {TAIL_SAFETY * level * gain:.2g}"
                            " (a tighter rtol shrinks it)")
        if not trend < 1:
            return Settling(False, count, rho, math.inf, q[-1].copy(),
                            f"successive cycles still change by {last:.2g} ({worst}) and the changes do not shrink "
                            f"over the last {span + 1} cycles (ratio {rho:.3g} per cycle): no steady cycle is approached")
        remaining = TAIL_SAFETY * late * trend / (1 - trend)
        return Settling(False, count, trend, remaining, q[-1].copy(),
                        f"not settled after {count} cycles: the cycles spiral in (single ratios up to {rho:.3g}, "
                        f"{trend:.4g} per cycle over the last {span + 1}), so the steady cycle is still "
                        f"~{remaining:.2g} away; {_more_cycles(tolerance, remaining, trend)}")
    # the tail (doubled: rho drifts as the approach leaves the linear regime), plus the round-off of
    # differences of O(1) numbers summed over it
    remaining = TAIL_SAFETY * last * rho / (1 - rho) + 8 * np.finfo(float).eps / (1 - rho)
    limit = aitken(q[-3], q[-2], q[-1]) if count >= 3 else q[-1].copy()
    if remaining <= tolerance:
        return Settling(True, count, rho, remaining, q[-1].copy(),
                        f"settled after {count} cycles: contraction {rho:.3g} per cycle, {remaining:.2g} left")
    return Settling(False, count, rho, remaining, limit,
                    f"not settled after {count} cycles: successive cycles change by {last:.2g} ({worst}) but contract "
                    f"only by {rho:.4g} per cycle, so the steady cycle is still ~{remaining:.2g} away; "
                    f"{_more_cycles(tolerance, remaining, rho)}")


def _more_cycles(tolerance: float, remaining: float, rate: float) -> str:
    """'~N more cycles to reach the tolerance' at a contraction ``rate`` per cycle; words where no count follows
    (a zero, infinite or undefined distance or rate: a spiral's envelope can vanish between two cycles)."""
    if not (0 < rate < 1 and 0 < remaining < math.inf):
        return f"how many more cycles reach {tolerance:g} is unknown"
    return f"~{max(math.log(tolerance / remaining) / math.log(rate), 1):.3g} more cycles to reach {tolerance:g}"


def settle(advance, tolerance: float, min_cycles: int = 4, max_cycles: int = 1000, floor=None, names=None):
    """Run ``advance()`` (one cycle, returning its quantities) until :func:`assess_settling` says settled.

    Returns ``(history, settling)``: the quantities of every cycle run and the verdict on them.
    """
    history = []
    verdict = Settling(False, 0, math.nan, math.inf, np.empty(0), "no cycle run")
    while len(history) < max_cycles:
        history.append(np.atleast_1d(np.asarray(advance(), float)))
        if len(history) >= min_cycles:
            verdict = assess_settling(np.vstack(history), tolerance, floor, names)
            if verdict.settled:
                break
    if history and len(history) < min_cycles:
        verdict = assess_settling(np.vstack(history), tolerance, floor, names)
    return np.vstack(history) if history else np.empty((0, 0)), verdict


def bifurcation_note(name: str, parameter: str, value: float, critical: float, unit: str = "") -> str | None:
    """A sentence naming a bifurcation when ``value`` is within 10 % of ``critical`` (None otherwise)."""
    if not (math.isfinite(value) and math.isfinite(critical)) or critical == 0:
        return None
    distance = value / critical - 1
    if abs(distance) > 0.1:
        return None
    side = "below" if distance < 0 else "above"
    unit = f" {unit}" if unit else ""
    return (f"{abs(distance) * 100:.3g} % {side} {name} (at {parameter} = {critical:.6g}{unit}): cycles settle slowly "
            "near it, so the steady cycle is checked for settling and its remaining distance declared")
