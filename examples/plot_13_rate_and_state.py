"""
Rate-and-state friction: a velocity step
========================================

Dieterich's aging law on a slider 2 k_c stiff: a tenfold step of the load-point speed gives the
direct effect a ln 10, then the evolution to the new steady state (a - b) ln 10, with the
oscillation of a stiffness near critical.
"""
import matplotlib.pyplot as plt

from faultslip.io import config_path
from faultslip.models import read_rate_state_scene, simulate_rate_state

scene = read_rate_state_scene(config_path("rsf_velocity_step.toml"))
run = simulate_rate_state(scene.slider, scene.history, model=scene.model, samples=scene.samples)
figure, axis = plt.subplots(figsize=(7, 3.8))
axis.plot(run.time, run.friction)
axis.set(xlabel="time (s)", ylabel="friction", title="1 -> 10 um/s at 10 s (aging law)")
