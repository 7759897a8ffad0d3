"""The posterior's cost against emcee driving a plain scipy-odeint forward model, on the same work (issue 29).

The record is the shipped raw example (configs/example_raw_velocity_steps.txt: five velocity steps and a
hold, 4,201 samples), prepared as ``faultslip fit`` prepares it. faultslip samples its posterior until
converged with 10,000 draws (its default); that fixes the number of chain steps. The baseline is what a
competent user writes with emcee and scipy: the same priors, the same likelihood (sigma integrated
out), the same walkers, moves and seed, run for the same number of steps, with a forward model of
rsfmodel's kind: friction and state as the ODE's variables, a right-hand side on ``math`` (not numpy on
single floats), ``scipy.integrate.odeint`` restarted at each step of the load point, at faultslip's
tolerance (rtol 1e-7, atol 1e-10). Its friction at the law is checked against faultslip's before timing.
Both run as whole sampling runs in this process on one core; the row is the ratio of the two times.

    python benchmarks/posterior_speed.py     # about 3 minutes
"""

from __future__ import annotations

import json
import math
import sys
import time
from pathlib import Path

import numpy as np
from provenance import stamp  # noqa: E402  (one stamp for every results file)

ROOT = Path(__file__).resolve().parent.parent


def baseline_friction(params, stiffness, history, t_eval, rtol=1e-7):
    """A user's forward model: d mu/dt = k (V_lp - V), d theta/dt = 1 - V theta / D_c (aging), V from mu and
    theta, integrated by odeint segment by segment."""
    from scipy.integrate import odeint

    mu0, a, b, dc = params
    v0 = history.speeds[0]
    log, exp = math.log, math.exp

    def rates(y, t, lp):
        mu, theta = y
        v = v0 * exp((mu - mu0 - b * log(v0 * theta / dc)) / a)
        return [stiffness * (lp - v), 1.0 - v * theta / dc]

    state = [mu0, dc / v0]
    out = np.empty(t_eval.size)
    for start, end, speed in zip(history.times[:-1], history.times[1:], history.speeds):
        last = end == history.times[-1]
        inside = (t_eval >= start) & ((t_eval <= end) if last else (t_eval < end))
        times = np.concatenate(([start], t_eval[inside], [end]))
        solution = odeint(rates, state, times, args=(speed,), rtol=rtol, atol=1e-10, mxstep=50_000)
        out[inside] = solution[1:-1, 0]
        state = solution[-1]
    return out


def main() -> int:
    import emcee

    from faultslip.lab.posterior import DEFAULT_PRIORS, sample_posterior
    from faultslip.lab.raw_records import prepare_record, read_raw_record
    from faultslip.dynamics.rate_state.slider import quasi_static_friction

    raw = read_raw_record(ROOT / "configs" / "example_raw_velocity_steps.txt", area="25 cm^2")
    prepared = prepare_record(raw, "200 kN/mm", area="25 cm^2", detrend="linear")
    record, stiffness = prepared.record, prepared.stiffness
    started = time.perf_counter()
    posterior = sample_posterior(record, stiffness, samples=10_000, seed=7)
    ours = time.perf_counter() - started
    law = posterior.law()
    check = np.max(np.abs(baseline_friction((law.mu0, law.a, law.b, law.critical_slip), stiffness, record.history,
                                            record.time)
                          - quasi_static_friction(law, stiffness, record.history, record.time, 1e-7)))
    names = posterior.names
    n = record.time.size

    def log_posterior(theta):
        mu0, a, b, log_dc = theta
        values = (mu0, a, b, math.exp(log_dc))
        total = sum(DEFAULT_PRIORS[name].log_density(v) for name, v in zip(names, values)) + log_dc
        if not math.isfinite(total):
            return -math.inf
        try:
            misfit = baseline_friction(values, stiffness, record.history, record.time) - record.friction
        except Exception:
            return -math.inf
        ssr = float(misfit @ misfit)
        return total - 0.5 * n * math.log(ssr) if math.isfinite(ssr) and ssr > 0 else -math.inf

    fit = posterior.fit
    centre = np.array([fit.parameters["mu0"], fit.parameters["a"], fit.parameters["b"],
                       math.log(fit.parameters["critical_slip"])])
    rng = np.random.default_rng(7)
    start = centre + 1e-4 * np.abs(centre) * rng.standard_normal((posterior.walkers, 4))
    sampler = emcee.EnsembleSampler(posterior.walkers, 4, log_posterior,
                                    moves=[(emcee.moves.DEMove(), 0.8), (emcee.moves.DESnookerMove(), 0.2)])
    sampler.random_state = np.random.RandomState(7).get_state()
    started = time.perf_counter()
    sampler.run_mcmc(start, posterior.steps, progress=False)
    baseline = time.perf_counter() - started
    result = {"record": "configs/example_raw_velocity_steps.txt (5 steps and a hold, 4201 samples)",
              "walkers": posterior.walkers, "steps": posterior.steps, "draws": int(posterior.samples.shape[0]),
              "faultslip_seconds": ours, "baseline_seconds": baseline, "ratio": ours / baseline,
              "baseline_minus_faultslip_friction_at_the_law": float(check),
              "baseline": "emcee + scipy.integrate.odeint on (mu, theta), math.* right-hand side, restarted at each "
                          "step, rtol 1e-7 atol 1e-10; same priors, likelihood, walkers, moves, seed and steps",
              "faultslip": "sample_posterior(samples=10000): least-squares start, run until converged "
                           "(the fit's time included)",
              **stamp()}
    path = ROOT / "benchmarks" / "results" / "posterior_speed.json"
    path.write_text(json.dumps(result, indent=1) + "\n")
    print(json.dumps(result, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
