"""
From a laboratory CSV to a fault prediction with uncertainty
============================================================

Fit the rate law to static-friction measurements (configs/example_friction_data.csv), with
bootstrap intervals, then carry the fit's uncertainty into a fault's slip and recurrence.
"""
import numpy as np

from faultslip.models import Fault
from faultslip.io import config_path
from faultslip.plots import fit_figure
from faultslip.friction import fit_rate_law, read_friction_data

data = read_friction_data(config_path("example_friction_data.csv"))
fit = fit_rate_law(data, bootstrap=100, seed=1)
print(fit.report("fit").to_text())
inputs = dict(shear_modulus="0.25e6 bar", zone_width="13 mi", shear_stress="250 bar", slip_rate="2 in/yr")
central = Fault(**inputs, **{key: fit.values[key] for key in ("mu_so", "mu_m", "b", "d")}).estimate()
slips = [Fault(**inputs, mu_so=s[0], mu_m=s[1], b=s[2], d=s[3]).estimate().slip_per_event for s in fit.bootstrap]
low, high = np.percentile(slips, [2.5, 97.5])
print(f"slip per event {central.slip_per_event:.2f} m (95 %: {low:.2f}-{high:.2f} m) "
      f"every {central.recurrence_period / 3.15576e7:.0f} yr")
fit_figure(data, fit)
