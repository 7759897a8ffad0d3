"""Seed 002, quasi-harmonic vibration without sticking: one model family, one folder.

* ``family``: the declaration (run, simulate, methods, sweep outputs), the amplitude study;
* ``scene``: the ``[vibration]`` scene reader.

The averaging numerics (eq. 10 and its averaged envelope) are in :mod:`faultslip.dynamics.vibration`,
because the spring-slider's method hierarchy shares them; seed 002's own figures are in
:mod:`faultslip.plots.vibration`.
"""
