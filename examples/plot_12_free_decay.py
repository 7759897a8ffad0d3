"""
Identifying the apparatus from a free decay
===========================================

Seed 002 Appendix C: the log decrement of a free vibration gives the decay constant, the damping
ratio and, with the known stiffness, the mass and damping coefficient.
"""
import matplotlib.pyplot as plt

from faultslip.io import config_path
from faultslip.lab import free_decay_from_record, read_record

record = read_record(config_path("example_decay_record.csv"))
decay = free_decay_from_record(record, stiffness=70.5 * 4.4482216152605 / 0.0254)
print(decay.report().to_text())
figure, axis = plt.subplots(figsize=(7, 3.5))
axis.plot(record.time, record.displacement * 1e3)
axis.set(xlabel="time (s)", ylabel="displacement (mm)", title="free decay of seed 002's beam")
