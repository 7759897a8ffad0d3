"""
Rough surfaces and their real contact
=====================================

Seed 000: a few asperity tips carry the load. A Gaussian surface's statistics, and the real area
of contact against its own inverted copy as the two are pressed together (contact by truncation,
all contacts plastic at p_c = 280 N/mm^2, the seed's steel).
"""
from faultslip.lab import gaussian_surface, surface_statistics, truncation_contact
from faultslip.plots import surface_figure

surface = gaussian_surface(2.3e-6, 20e-6, size=128, seed=1)
stats = surface_statistics(surface)
print(f"CLA {stats['cla'] * 1e6:.2f} um, RMS {stats['rms'] * 1e6:.2f} um, beta* {stats['correlation_length'] * 1e6:.1f} um")
contact = truncation_contact(surface, [i * 0.5e-6 for i in range(9)], flow_pressure=280e6)
surface_figure(surface, stats, contact)
