"""
The spring-slider and its sawtooth
==================================

Seed 003's apparatus: a block on a moving platform, held by a spring. Dry glass sticks while the
spring force builds, then slips: the spring force traces a sawtooth.
"""
import faultslip
from faultslip.plots import sawtooth_figure

scene = faultslip.models.read_slider_scene("lab_glass_dry.toml")
record = faultslip.models.simulate_slider(scene.slider(), cycles=8, scene=scene.name)
print(f"slip per event {float(record['slip'][-1]) * 1e6:.2f} um, period {float(record['period'][-1]):.3f} s")
sawtooth_figure(record)
