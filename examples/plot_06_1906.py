"""
The 1906 San Francisco earthquake, step by step
===============================================

Seed 003 §5-2: wet granodiorite, G = 0.25e6 bar, an elastic zone D = 13 mi, tau = 250 bar and a
plate rate of 2 in/yr. faultslip computes every intermediate number (the seed's arithmetic has
slips: docs/seed_discrepancies.md).
"""
import faultslip
from faultslip.plots import sawtooth_figure

scene = faultslip.models.read_slider_scene("san_andreas_1906.toml")
estimate = scene.fault().estimate()
print(f"stiffness K = G/D      {estimate.stiffness:.4g} Pa/m")
print(f"normal stress          {estimate.normal_stress / 1e5:.1f} bar")
print(f"loading rate           {estimate.loading_rate:.4g} 1/s")
print(f"slip per event         {estimate.slip_per_event:.2f} m")
print(f"recurrence             {estimate.recurrence_period / faultslip.JULIAN_YEAR:.0f} yr")
print(f"moment magnitude       {estimate.moment_magnitude:.2f}")
sawtooth_figure(faultslip.models.simulate_slider(scene.slider(), cycles=4, scene=scene.name))
