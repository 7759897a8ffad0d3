"""
The static-friction rate law and Table I
========================================

Seed 003 eq. 2-18: static friction falls as the loading rate rises,
mu_s = mu_m + (mu_so - mu_m) / (1 + b theta_dot^d), with each rock's constants from Table I. The
amplitude of stick-slip follows it (eq. 2-19).
"""
from faultslip.friction import get_preset
from faultslip.plots import rate_law_figure

chosen = [get_preset(name) for name in ("glass_dry", "pyrite_dry", "granodiorite_water", "black_marble_water")]
for preset in chosen:
    law = preset.rate_law
    print(f"{preset.name:20s} mu_so {law.mu_so:.2f}  mu_m {law.mu_m:.2f}  b {law.b:.3g}  d {law.d:.3g}")
rate_law_figure(chosen)
