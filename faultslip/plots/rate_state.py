"""Rate-and-state stability charts: the slip law's critical step, and k_c with a damper or inertia."""

from __future__ import annotations

import numpy as np

from faultslip.dynamics.rate_state.slider import critical_step_ratio
from faultslip.friction.rate_state import RateStateLaw, critical_stiffness, get_law
from faultslip.plots.figures import _pyplot


def stability_figure(law: RateStateLaw | None = None, stiffness_ratios=None):
    """Left: the smallest velocity step V2/V1 that destabilises a quasi-static slider at k / k_c
    (slip law, by simulation; the aging law stays stable above k_c). Right: k_c with a radiation
    damper and with inertia, relative to the quasi-static sigma_n (b - a) / D_c, against the
    sliding speed, for SCEC SEAS BP1's friction on a 20 km spring-slider fault."""
    plt = _pyplot()
    law = law or get_law("step_example")
    ratios = np.asarray(stiffness_ratios if stiffness_ratios is not None else [1.1, 1.25, 1.5, 2, 2.5, 3, 4, 6],
                        dtype=float)
    figure, (left, right) = plt.subplots(1, 2, figsize=(11, 4.4), constrained_layout=True)
    slip = [critical_step_ratio(law.with_evolution("slip"), r) for r in ratios]
    aging = [critical_step_ratio(law.with_evolution("aging"), r, largest=1e3) for r in ratios[::3]]
    finite = np.isfinite(slip)
    left.semilogy(ratios[finite], np.asarray(slip)[finite], "o-", label="slip law: unstable above the line")
    for r, value in zip(ratios[::3], aging):
        if not np.isfinite(value):
            left.annotate("aging law:\nstable to 1000x", (r, 1e3), ha="center", va="top", fontsize=8, color="C1")
    left.axvline(1.0, color="0.5", lw=1, ls="--")
    left.set_ylim(1.0, 2e3)
    left.set(xlabel="k / k_c", ylabel="critical velocity step V2 / V1",
             title=f"nonlinear instability (a {law.a:g}, b {law.b:g}, D_c {law.critical_slip * 1e6:g} µm)")
    left.legend(fontsize=8)
    left.grid(True, which="both", alpha=0.3)
    sigma, a, b, dc = 50e6, 0.010, 0.015, 0.008
    shear, width, density, wave = 3.2e10, 20e3, 2670.0, 3464.0
    speeds = np.geomspace(1e-12, 10.0, 400)
    quasi = critical_stiffness(sigma, a, b, dc)
    damped = critical_stiffness(sigma, a, b, dc, speeds, damping=shear / (2 * wave))
    inertial = critical_stiffness(sigma, a, b, dc, speeds, mass=density * width, damping=shear / (2 * wave))
    right.semilogx(speeds, damped / quasi, label="quasi-dynamic (radiation damper)")
    right.semilogx(speeds, inertial / quasi, "--", label="inertial with damper")
    right.axhline(1.0, color="0.5", lw=1, ls=":", label="quasi-static")
    right.set(xlabel="steady sliding speed V (m/s)", ylabel="k_c / [sigma_n (b - a) / D_c]",
              title="k_c from the characteristic equation\n(SEAS BP1 friction, 20 km spring-slider fault)")
    right.set_ylim(-0.5, 2.5)
    right.legend(fontsize=8)
    right.grid(True, which="both", alpha=0.3)
    return figure
