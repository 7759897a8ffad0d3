"""
Amplitude against loading rate
==============================

The stick-slip amplitude of dry pyrite over the apparatus' range of loading rates (seed 003's
even-numbered figures): the closed form (eq. 2-19) beside the exact cycle, which also finds where
stick-slip ends at the critical rate with damping.
"""
import matplotlib.pyplot as plt
import numpy as np

from faultslip.models import SliderSystem, closed_form_cycle, critical, exact_cycle

base = SliderSystem.from_preset("pyrite_dry", loading_rate="1 1/s", damping_ratio=0.02)
theta_c = critical(base).critical_loading_rate
rates = np.logspace(-4, np.log10(0.95 * theta_c), 25)
closed = [closed_form_cycle(base.at_loading_rate(r)).amplitude for r in rates]
exact = [exact_cycle(base.at_loading_rate(r)).amplitude for r in rates]
figure, axis = plt.subplots(figsize=(6.5, 4))
axis.semilogx(rates, np.array(closed) * 1e6, label="closed form (eq. 2-19)")
axis.semilogx(rates, np.array(exact) * 1e6, "o", ms=4, label="exact cycle")
axis.axvline(theta_c, color="0.5", ls=":", label=f"critical rate {theta_c:.3g} 1/s")
axis.set(xlabel="loading rate theta_dot (1/s)", ylabel="amplitude (um)", title="dry pyrite, zeta 0.02")
axis.legend()
