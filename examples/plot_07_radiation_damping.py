"""
Radiation damping
=================

A fault radiates energy as seismic waves: the radiation damper eta = G / (2 c_s) acts on the slip
rate. It lowers the peak slip rate and, slightly, the slip per event of the 1906 scene.
"""
import matplotlib.pyplot as plt

from faultslip.models import read_slider_scene, simulate_slider

records = {label: simulate_slider(read_slider_scene(name).slider(), cycles=3)
           for label, name in (("no radiation damping", "san_andreas_1906.toml"),
                               ("radiation damping", "san_andreas_1906_radiation.toml"))}
figure, axis = plt.subplots(figsize=(6.5, 4))
for label, record in records.items():
    slipping = record["phase"].values == 1
    time = record["time"].values[slipping]
    event = time >= float(record["event_time"][-1])
    axis.plot(time[event] - time[event][0], record["sliding_speed"].values[slipping][event], label=label)
    print(f"{label}: slip {float(record['slip'][-1]):.3f} m, peak slip rate {float(record['peak_slip_speed'][-1]):.3f} m/s")
axis.set(xlabel="time into the event (s)", ylabel="slip rate (m/s)", title="the 1906 rupture's slip rate")
axis.legend()
