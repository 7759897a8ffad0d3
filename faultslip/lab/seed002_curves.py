"""Seed 002's theoretical curves (its Figs. 9-11), rebuilt in kind.

The seed draws four friction-velocity curves without printing them (Fig. 9): (B) is (A) shifted down
by 0.18; (C) has (A)'s static value but flattens at a lower speed; (D) has a lower static value and
flattens earliest. Its Fig. 10 gives the averaged amplitude against the driving speed for each, and
Fig. 11 the effect of damping. What the text states, and what is checked here:

1. (A) and (B) give the same amplitude and end at the same speed (the vertical-shift invariance);
2. the amplitude rises with the driving speed at about the same rate for (A), (C) and (D);
3. each branch ends close to where its curve flattens;
4. more damping ends the oscillation at a lower speed.

The curves here have Bristow's form (seed 002 Fig. 8), f(u) = f_k + (f_s - f_k)(1 - u/u_f)^2 below
the flattening speed u_f and f_k above it; their numbers are illustrative (the seed prints none).
The apparatus is seed 002's (Appendices B and C) with W = 2 lbf, as in configs/vibration_seed002.toml.

The rising branch of Fig. 10 has A omega > v: the oscillation's sliding speed v - A omega cos b
becomes negative, where the slider would stick. The seed's polynomials (10th and 12th degree)
supply friction there by extrapolation; which branch appears then depends on the fit (measured: (C)
has the branch with a 10th-degree fit and none with a 12th). Here the curve is extended to negative
sliding speeds as f(|u|), which is definite, and :func:`seed_branch` flags every such amplitude as
stick-slip, the regime :class:`~faultslip.dynamics.vibration.QuasiHarmonic` reports for it
(docs/seed_discrepancies.md).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from faultslip.dynamics.vibration import SEED002_APPARATUS, QuasiHarmonic

APPARATUS = SEED002_APPARATUS
INCH_PER_S = 0.0254
#: amplitudes are searched up to A omega = this speed (well past any curve's flattening)
SEARCH_SPEED = 80 * INCH_PER_S


@dataclass(frozen=True)
class TheoreticalCurve:
    """f(u) = kinetic + (static - kinetic)(1 - |u|/flattening)^2 for |u| < flattening, kinetic beyond, minus shift."""

    name: str
    static: float
    kinetic: float
    flattening_speed: float  # m/s
    shift: float = 0.0
    description: str = ""

    def __call__(self, sliding_speed):
        fraction = np.clip(np.abs(np.asarray(sliding_speed, dtype=float)) / self.flattening_speed, 0.0, 1.0)
        return self.kinetic + (self.static - self.kinetic) * (1.0 - fraction) ** 2 - self.shift


#: the four curves of seed 002 Fig. 9, in kind (illustrative numbers; the relations are the seed's)
CURVES = {
    "A": TheoreticalCurve("A", 0.5, 0.3, 15 * INCH_PER_S, 0.0, "flattens at 15 in/s"),
    "B": TheoreticalCurve("B", 0.5, 0.3, 15 * INCH_PER_S, 0.18, "(A) shifted down by 0.18 (seed 002)"),
    "C": TheoreticalCurve("C", 0.5, 0.3, 10 * INCH_PER_S, 0.0, "(A)'s static value, flattens at 10 in/s"),
    "D": TheoreticalCurve("D", 0.42, 0.3, 8 * INCH_PER_S, 0.0, "lower static value, flattens at 8 in/s"),
}


def slider(curve: TheoreticalCurve, speed: float, damping_factor: float = 1.0) -> QuasiHarmonic:
    """Seed 002's apparatus on ``curve`` at driving speed ``speed`` (m/s), damping scaled by ``damping_factor``."""
    return QuasiHarmonic(APPARATUS["mass"], APPARATUS["damping"] * damping_factor, APPARATUS["stiffness"],
                         APPARATUS["normal_load"], float(speed), friction=curve, name=f"seed 002 curve {curve.name}")


def seed_branch(curve: TheoreticalCurve, speeds, damping_factor: float = 1.0) -> dict:
    """The seed's amplitude against driving speed: where steady sliding is unstable, the smallest stable
    root of eq. (20) up to A omega = SEARCH_SPEED, whether or not the slider would stick there; 0 where
    the oscillation dies out. Returns ``amplitude`` (m), ``peak_speed`` A omega (m/s) and ``sticks``
    (A omega >= v: stick-slip in fact)."""
    speeds = np.asarray(speeds, dtype=float)
    amplitude = np.zeros(speeds.size)
    for index, speed in enumerate(speeds):
        system = slider(curve, speed, damping_factor)
        if system.steady_sliding_growth <= 0:
            continue
        stable = [c for c in system.limit_cycles(largest=SEARCH_SPEED / system.angular_frequency) if c.stable]
        amplitude[index] = stable[0].amplitude if stable else 0.0
    omega = slider(curve, 1.0).angular_frequency
    peak = amplitude * omega
    return {"speed": speeds, "amplitude": amplitude, "peak_speed": peak, "sticks": (amplitude > 0) & (peak >= speeds)}


def termination_speed(branch: dict) -> float:
    """The first driving speed past the branch's last nonzero amplitude (m/s; NaN if it never ends)."""
    alive = np.nonzero(branch["amplitude"] > 0)[0]
    if alive.size == 0 or alive[-1] + 1 >= branch["speed"].size:
        return float("nan")
    return float(branch["speed"][alive[-1] + 1])


def figures_9_to_11(speeds=None, damping_factors=(1.0, 2.0, 4.0), curves=("A", "B", "C", "D")) -> dict:
    """Everything Figs. 9-11 show: each curve's branch (Fig. 10) and curve (A) at several dampings
    (Fig. 11), with the termination speeds. ``speeds`` default: 0.5 to 20 in/s every 0.5 in/s, the
    seed's increments."""
    speeds = np.arange(1, 41) * 0.5 * INCH_PER_S if speeds is None else np.asarray(speeds, dtype=float)
    branches = {name: seed_branch(CURVES[name], speeds) for name in curves}
    damped = {factor: seed_branch(CURVES["A"], speeds, factor) for factor in damping_factors}
    return {"speeds": speeds, "curves": {name: CURVES[name] for name in curves}, "branches": branches,
            "damped": damped, "termination": {name: termination_speed(b) for name, b in branches.items()},
            "damped_termination": {factor: termination_speed(b) for factor, b in damped.items()}}
