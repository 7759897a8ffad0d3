"""
Nanoscale stick-slip with contact charging
==========================================

Seed 001's toy model: a tip pulled over a polymer, velocity weakening above v_m, and contact charge
that adds adhesion. Below the damping threshold A_c = 12 it sticks and slips, and the charge it
deposits tracks the displacement.
"""
from faultslip.models import NanoscaleModel, nanoscale_figure

model = NanoscaleModel(damping=3.0)
print(f"A_c = {model.critical_damping:.6g}; stick-slip: {model.stick_slip}")
nanoscale_figure(model.simulate(duration=1500.0, samples=3001))
