"""
The phase plane and the critical rate
=====================================

Below the critical loading rate the slider sticks and slips (a limit cycle that touches
x' = V); above it, damping wins and the slider slides steadily.
"""
import faultslip
from faultslip.plots import phase_plane_figure

system = faultslip.models.SliderSystem.from_preset("glass_dry", loading_rate="1 1/s", damping_ratio=0.05)
result = faultslip.models.critical(system)
print(f"critical loading rate: {result.critical_loading_rate:.4g} 1/s")
phase_plane_figure(system, rate_factors=(0.3, 0.999, 1.5))
