"""
Quasi-harmonic vibration by averaging
=====================================

Seed 002: where friction falls with speed, steady sliding can give way to an oscillation that never
sticks. Kryloff-Bogoliuboff averaging gives its amplitude in closed form for a polynomial curve;
where the cycle would reach the driving speed the slider sticks, and averaging hands over.
"""
import numpy as np

from faultslip.models import amplitude_against_speed, amplitude_speed_figure, read_vibration_scene
from faultslip.io import config_path

system, _ = read_vibration_scene(config_path("vibration_seed002.toml"))
sweep = amplitude_against_speed(system, np.linspace(0.0254, 16 * 0.0254, 61))
amplitude_speed_figure(system, sweep)
