"""Seed 002's averaging re-measured on random friction curves it was never set on (docs/quasi_harmonic.md).

    python benchmarks/averaging_check.py            # ~15 min on 2 cores
    python benchmarks/averaging_check.py --quick    # 3 curves and 6 sliders a draw

Averaging declares ERROR_CONSTANT eps^2 in the amplitude, set on Rayleigh's curve (with and without an even term)
and seed 002's scene. Three things are measured here, on two random draws neither of which set anything:

1. The amplitude's error over eps^2, against eq. (10) integrated from the averaged amplitude until the approach has
   decayed by e^-16, at three speeds of each curve's vibrating band: its lowest and highest speed on a grid of 300
   (the Hopf ends, where the cycle is small, or the sticking end; the nearest speed that settles within 20000
   periods) and its middle. Curves: cubics with an even term,
   quintics (f = 0.5 - c1 d + c2 d^2 + c3 d^3 + c5 d^5, d = u - v_s) and Stribeck curves
   (mu_c + (mu_s - mu_c) exp(-|u / v_s|^p) + sigma u, by quadrature), apparatus drawn over decades.
2. The call at the sticking end: at 7 speeds across the grid step where the cycle's peak speed A omega reaches v,
   whether averaging says it sticks and whether eq. (10), integrated from that cycle, does; the distance
   A omega / v - 1 in units of eps where they disagree, against HAND_OVER_MARGIN (within which averaging declines).
3. The call after break-away on seed 003's slider (M = K = W = 1, a quintic curve about the driving speed, sub- or
   supercritical, static friction above it): averaging's regime against the event-driven simulation's (DOP853,
   rtol 1e-9, 3 cycles) where it sticks, and else eq. (10) integrated from the amplitude after one period for
   twice the time eq. (20)'s envelope takes to settle (at most 20000 periods; steady sliding below 5 % of it).
   Beside it, the call averaging made before it followed the envelope from break-away (the cycle reached from
   small disturbances), which a subcritical slider (steady sliding stable, a stable cycle
   above an unstable one) gets wrong.

Writes benchmarks/results/averaging_check.json (benchmarks/readme.py renders docs/quasi_harmonic.md's table).
"""

from __future__ import annotations

import argparse
import math
import sys
import warnings
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from faultslip.dynamics import vibration  # noqa: E402
from faultslip.dynamics.methods import AVERAGING  # noqa: E402
from faultslip.dynamics.spring_slider.simulate import simulate  # noqa: E402
from faultslip.dynamics.spring_slider.slider import SliderSystem  # noqa: E402
from faultslip.errors import SolverError  # noqa: E402
from faultslip.friction.laws import ConstantStatic, PolynomialKinetic  # noqa: E402
from provenance import write_results  # noqa: E402  (one stamp for every results file)

SEEDS = (2002, 2003)
CURVES, SLIDERS = 12, 30
KINDS = ("cubic", "quintic", "stribeck")
GRID = 300
#: the periods an amplitude measurement may take to settle (e^-16 of the approach); nearer a Hopf end, the next
#: speed inward is measured
MAX_PERIODS = 20000


def draw_curve(rng, index: int) -> tuple[str, vibration.QuasiHarmonic]:
    """One random averaged slider: the curve's kind by ``index``, its speed scale 1 mm/s - 1 m/s, M 0.1-10 kg,
    k 1e2-1e5 N/m, W set so that eps at the weakening slope is 0.01-0.5, r 0-0.6 W times that slope."""
    kind = KINDS[index % len(KINDS)]
    mass, stiffness = 10 ** rng.uniform(-1, 1), 10 ** rng.uniform(2, 5)
    omega = math.sqrt(stiffness / mass)
    scale = 10 ** rng.uniform(-3, 0)
    eps = 10 ** rng.uniform(-2, -0.3)
    if kind == "stribeck":
        peak = rng.uniform(0.3, 0.8)
        floor = peak * rng.uniform(0.4, 0.9)
        strengthening = rng.uniform(0.02, 0.3) * (peak - floor) / scale
        power = rng.uniform(1, 2)

        def friction(u, peak=peak, floor=floor, scale=scale, strengthening=strengthening, power=power):
            return floor + (peak - floor) * np.exp(-np.abs(u / scale) ** power) + strengthening * u

        curve, weakening = {"friction": friction}, (peak - floor) / scale
    else:
        weakening = rng.uniform(0.05, 0.5) / scale
        cubic = weakening / scale ** 2 * rng.uniform(0.2, 2)
        even = rng.uniform(-1, 1) * math.sqrt(weakening * cubic)
        quintic = cubic / scale ** 2 * rng.uniform(0, 1) if kind == "quintic" else 0.0
        offset = np.polynomial.Polynomial([-scale, 1.0])
        polynomial = 0.5 - weakening * offset + even * offset ** 2 + cubic * offset ** 3 + quintic * offset ** 5
        curve = {"coefficients": tuple(polynomial.coef)}
    load = eps * mass * omega / weakening
    damping = rng.uniform(0, 0.6) * load * weakening
    return kind, vibration.QuasiHarmonic(mass, damping, stiffness, load, scale, **curve,
                                         name=f"{kind} curve {index}")


def _settling_end(system, speeds) -> float:
    """The first of ``speeds`` (a band from one end) whose integration settles within MAX_PERIODS: at a Hopf end
    the cycle's decay rate vanishes, and e^-16 of the approach can take 10^5 periods or more."""
    for speed in speeds[:40]:
        at = replace(system, speed=float(speed))
        if vibration.settle_periods(at, at.analyse()) <= MAX_PERIODS:
            return float(speed)
    return float(speeds[min(40, speeds.size - 1)])


def _integrated_sticks(system: vibration.QuasiHarmonic, amplitude: float, decay_rate: float) -> bool:
    period = 2 * math.pi / system.angular_frequency
    periods = max(60.0, min(400.0, 16.0 / max(abs(decay_rate) * period, 1e-12)))
    try:
        vibration.integrate(system, amplitude, periods=periods, extensions=1)
    except SolverError:
        return True
    return False


def measure_curve(job) -> dict:
    """Parts 1 and 2 on one random curve."""
    seed, index = job
    kind, system = draw_curve(np.random.default_rng([seed, index]), index)
    grid = np.linspace(0, 3 * system.speed, GRID + 1)[1:]
    sweep = vibration.amplitude_against_speed(system, grid)
    vibrating = (sweep["amplitude"] > 0) & ~sweep["sticks"]
    row = {"seed": seed, "index": index, "kind": kind, "amplitude_errors": [], "boundary": []}
    band = grid[vibrating]
    for where, speed in (("low end", _settling_end(system, band)), ("middle", band[band.size // 2]),
                         ("high end", _settling_end(system, band[::-1]))) if band.size >= 3 else ():
        at = replace(system, speed=float(speed))
        try:
            measured = vibration.averaging_error(at)
        except SolverError as error:  # the integration sticks where averaging saw a cycle: part 2's business
            row["amplitude_errors"].append({"where": where, "speed": float(speed), "sticks": str(error)[:120]})
            continue
        row["amplitude_errors"].append({"where": where, "speed": float(speed), "eps": measured["small_parameter"],
                                        "error": measured["error"],
                                        "ratio": measured["error"] / measured["small_parameter"] ** 2})
    changes = np.flatnonzero(vibrating[:-1] != vibrating[1:])
    edges = [(grid[i], grid[i + 1]) for i in changes if sweep["sticks"][i] or sweep["sticks"][i + 1]]
    for speed in (np.linspace(*edges[0], 7) if edges else ()):
        at = replace(system, speed=float(speed))
        result = at.analyse()
        stable = [cycle for cycle in result.limit_cycles if cycle.stable]
        if not stable or result.growth_rate <= 0:
            continue
        cycle = stable[0]
        omega = at.angular_frequency
        eps = at.small_parameter(min(cycle.amplitude, at.speed / omega))
        row["boundary"].append({"speed": float(speed), "eps": float(eps),
                                "distance": float((1 - cycle.amplitude * omega / at.speed) / eps),
                                "averaging_sticks": bool(cycle.sticks), "marginal": bool(result.marginal),
                                "integrated_sticks": _integrated_sticks(at, cycle.amplitude, cycle.decay_rate)})
    return row


def draw_slider(rng, index: int) -> SliderSystem:
    """Seed 003's slider, M = K = W = 1: f = 2 + a1 d - a3 d^3 + a5 d^5 (d = u - V), static friction f(V) + 0-1,
    damping 0-0.3 |a1|, V 1.5-3.5. Half are subcritical: a1 > 0 (steady sliding stable) with the averaged slope
    a1 - 3/4 a3 x^2 + 5/8 a5 x^4 vanishing at two peak speeds x = A omega drawn in 0.2-1 V (an unstable cycle
    below a stable one); the other half supercritical (a1 < 0)."""
    speed = rng.uniform(1.5, 3.5)
    offset = np.polynomial.Polynomial([-speed, 1.0])
    size = 10 ** rng.uniform(-2, -0.5)  # a5 V^4
    quintic = size / speed ** 4
    if rng.random() < 0.5:
        low, high = np.sort(rng.uniform(0.2, 1.0, 2)) * speed
        linear, cubic = 0.625 * quintic * low ** 2 * high ** 2, 5 / 6 * quintic * (low ** 2 + high ** 2)
    else:
        linear, cubic = -rng.uniform(0.05, 1.0) * size, rng.uniform(0.0, 1.0) * size / speed ** 2
    curve = 2.0 + linear * offset - cubic * offset ** 3 + quintic * offset ** 5
    excess = rng.uniform(0.0, 1.0)
    return SliderSystem(mass=1.0, stiffness=1.0, normal_load=1.0, platform_speed=speed,
                        static_law=ConstantStatic(float(curve(speed)) + excess),
                        kinetic_law=PolynomialKinetic(tuple(curve.coef)), dashpot=rng.uniform(0, 0.3) * abs(linear),
                        name=f"random slider {index}")


def _settled_regime(averaged, start: float) -> str:
    """Steady sliding or an oscillation, by eq. (10) integrated from ``start`` for twice the time eq. (20)'s
    envelope takes to come within 1 % of ``start`` of where it ends (at least 60, at most MAX_PERIODS): the
    simulation's 3 cycles call a slow decay (1 / e in 200 periods) sustained."""
    period = 2 * math.pi / averaged.angular_frequency
    times, envelope = averaged.envelope(start, MAX_PERIODS * period, samples=4001)
    near = np.flatnonzero(np.abs(envelope - envelope[-1]) < 0.01 * start)
    periods = min(MAX_PERIODS, max(60.0, 2.0 * times[near[0]] / period if near.size else MAX_PERIODS))
    try:
        run = vibration.integrate(averaged, start, periods=periods, extensions=0)
    except SolverError:
        return "stick_slip"
    return "steady_sliding" if run["amplitude"] < 0.05 * start else "sustained_oscillation"


def measure_slider(job) -> dict:
    """Part 3 on one random slider."""
    seed, index = job
    system = draw_slider(np.random.default_rng([seed, 1000 + index]), index)
    averaged = vibration.from_slider(system)
    assessment = AVERAGING.assess(system, ("amplitude", "period"), 0.5, 10)
    call = AVERAGING.run(system, 10, {})[0].regime if assessment.applicable else "declined"
    small = averaged.analyse()  # the call before: from small disturbances
    before = ("declined" if not assessment.applicable else
              "sustained_oscillation" if small.valid and small.amplitude > 0 else
              "steady_sliding" if small.valid else "stick_slip")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        regime = simulate(system, cycles=3, slip_solver="DOP853", rtol=1e-9).attrs["regime"]
    if regime != "stick_slip":
        regime = _settled_regime(averaged, vibration.after_break_away(system, averaged)["after_one_period"])
    subcritical = averaged.steady_sliding_growth < 0 and any(c.stable for c in small.limit_cycles)
    return {"seed": seed, "index": index, "subcritical": bool(subcritical), "averaging": call, "before": before,
            "simulated": regime, "reason": assessment.reason[:200]}


def run_draw(seed: int, curves: int, sliders: int) -> dict:
    with ProcessPoolExecutor(2) as pool:
        curve_rows = list(pool.map(measure_curve, [(seed, i) for i in range(curves)]))
        slider_rows = list(pool.map(measure_slider, [(seed, i) for i in range(sliders)]))
    ratios = [e["ratio"] for row in curve_rows for e in row["amplitude_errors"] if "ratio" in e]
    boundary = [b for row in curve_rows for b in row["boundary"]]
    wrong = [b for b in boundary if b["averaging_sticks"] != b["integrated_sticks"]]
    answered = [r for r in slider_rows if r["averaging"] != "declined"]
    return {"seed": seed, "curves": curve_rows, "sliders": slider_rows,
            "largest_ratio": max(ratios) if ratios else None, "amplitudes_measured": len(ratios),
            "boundary_calls": len(boundary), "boundary_wrong": len(wrong),
            "boundary_wrong_largest_distance": max((abs(b["distance"]) for b in wrong), default=0.0),
            "boundary_wrong_outside_margin": int(sum(abs(b["distance"]) >= vibration.HAND_OVER_MARGIN for b in wrong)),
            "sliders_answered": len(answered),
            "sliders_wrong": sum(r["averaging"] != r["simulated"] for r in answered),
            "sliders_wrong_before": sum(r["before"] != r["simulated"] for r in answered),
            "subcritical_sliders": sum(r["subcritical"] for r in slider_rows)}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="3 curves and 6 sliders a draw")
    args = parser.parse_args(argv)
    curves, sliders = (3, 6) if args.quick else (CURVES, SLIDERS)
    draws = [run_draw(seed, curves, sliders) for seed in SEEDS]
    document = {"error_constant": vibration.ERROR_CONSTANT, "hand_over_margin": vibration.HAND_OVER_MARGIN,
                "seeds": list(SEEDS), "grid": GRID, "draws": draws, "quick": bool(args.quick),
                "largest_ratio": max(d["largest_ratio"] for d in draws if d["largest_ratio"] is not None)}
    write_results("averaging_check.json", document)
    for d in draws:
        print(f"draw {d['seed']}: error / eps^2 at most {d['largest_ratio']:.3g} over {d['amplitudes_measured']} "
              f"cycles (declared {vibration.ERROR_CONSTANT:g}); sticking calls {d['boundary_wrong']} wrong of "
              f"{d['boundary_calls']} (largest {d['boundary_wrong_largest_distance']:.2g} eps, "
              f"{d['boundary_wrong_outside_margin']} beyond the margin); break-away {d['sliders_wrong']} wrong of "
              f"{d['sliders_answered']} answered ({d['sliders_wrong_before']} before; "
              f"{d['subcritical_sliders']} subcritical)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
