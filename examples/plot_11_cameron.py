"""
Cameron's time-of-stick law
===========================

Seed 002: static friction grows with the time the surfaces have been stuck,
mu_s = mu_U - (mu_U - mu_L) exp(-gamma t^n). The longer each stick, the larger the next slip:
the cycle settles only after the sticks do.
"""
import matplotlib.pyplot as plt

from faultslip.models import read_slider_scene, simulate_slider

record = simulate_slider(read_slider_scene("lab_steel_dry_time_of_stick.toml").slider(), cycles=12)
figure, (left, right) = plt.subplots(1, 2, figsize=(10, 3.8))
left.plot(record["stick_duration"] * 1e3, record["static_friction"], "o-")
left.set(xlabel="stick duration (ms)", ylabel="static friction at break-away", title="time-of-stick law")
right.plot(record["event"], record["slip"] * 1e6, "o-")
right.set(xlabel="event", ylabel="slip (um)", title="slip settling onto the limit cycle")
