"""
The closed form against the exact cycle: error and cost
=======================================================

The closed form (seed 003 eq. 2-19) is a first-order expansion in eps = theta_dot / (omega_n dmu).
Its error grows with eps, while it costs microseconds; the exact cycle is exact and costs
milliseconds. ``auto`` takes the closed form only where its error model meets the tolerance.
"""
import time

import matplotlib.pyplot as plt
import numpy as np

from faultslip.models import SliderSystem, closed_form_cycle, critical, exact_cycle

base = SliderSystem.from_preset("granodiorite_water", loading_rate="1 1/s", damping_ratio=0.01)
theta_c = critical(base).critical_loading_rate
rates = theta_c * np.logspace(-5, np.log10(0.9), 20)
errors, costs = [], []
for rate in rates:
    system = base.at_loading_rate(rate)
    started = time.perf_counter()
    closed = closed_form_cycle(system)
    costs.append(time.perf_counter() - started)
    errors.append(abs(closed.amplitude / exact_cycle(system).amplitude - 1))
figure, axis = plt.subplots(figsize=(6.5, 4))
axis.loglog(rates / theta_c, np.maximum(errors, 1e-16), "o-")
axis.set(xlabel="theta_dot / theta_c", ylabel="relative amplitude error",
         title=f"closed form against the exact cycle (closed form: {np.median(costs) * 1e6:.0f} us a cycle)")
axis.grid(True, which="both", alpha=0.3)
