"""Seed 000, a slider on rough surfaces: one model family, one folder.

* ``family``: the declaration, run and simulate;
* ``scene``: the scene reader (``[friction] law = "rough_surface"``), friction from real contact.

It runs on the spring-slider's engine (:mod:`faultslip.dynamics.spring_slider`) and analyses surfaces
with :mod:`faultslip.lab.surfaces`, both shared.
"""
