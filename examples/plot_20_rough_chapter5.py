"""
Surfaces held apart through the deceleration
============================================

Seed 000's chapter 5 model: sliding parts the surfaces, and they stay apart until they come to rest
(``separation_memory = "held"``), so friction falls as the slider speeds up and stays low as it
slows down: the looped friction-velocity curve of the seed's fig. 5.18. Beside it, the addendum's
memoryless model, where friction retraces its path.
"""
import matplotlib.pyplot as plt

from faultslip.io import config_path
from faultslip.lab import gaussian_surface
from faultslip.models import read_rough_scene, rough_surface_slider, separation_history, simulate_slider

system, details, _ = read_rough_scene(config_path("rough_surface_chapter5.toml"))
print(f"h0 = {details['compression_at_rest'] * 1e6:.2f} um, separation per speed {details['separation_per_speed']:.3g} s")
surface = gaussian_surface(3.26e-6, 60e-6, size=128, seed=2026)  # the scene's stand-in surface
fig, (loop, gap) = plt.subplots(1, 2, figsize=(10, 3.6), constrained_layout=True)
for memory in ("none", "held"):
    slider, _ = rough_surface_slider(surface, 600.0, 12.66e3, 30.0, 0.2e-3, 2.8e8, 8.25e7, 20.0, memory=memory,
                                     separation_reference="static_compression")
    record = simulate_slider(slider, cycles=3, slip_solver="DOP853", rtol=1e-8)
    slipping = record["phase"].values == 1
    loop.plot(record["sliding_speed"].values[slipping] * 1e3, record["friction_coefficient"].values[slipping], ".",
              ms=3, label=memory)
    gap.plot(record["time"], separation_history(record, slider.kinetic_law) * 1e9, label=memory)
    print(f"{memory}: amplitude {float(record['amplitude'][-1]) * 1e3:.4f} mm, slip {float(record['slip_duration'][-1]):.3f} s")
loop.set(xlabel="sliding speed (mm/s)", ylabel="mu", title="friction in slip (seed 000 fig. 5.18)")
gap.set(xlabel="t (s)", ylabel="separation (nm)", title="separation (fig. 5.20)")
loop.legend()
gap.legend()
