"""The rate-and-state slider: one model family, one folder.

* ``family``: the declaration, run, simulate, velocity steps, stability, the older scene form;
* ``cycles``: a fault's earthquake cycles on one quasi-dynamic spring-block;
* ``figures``: its cycles figure.

The numerics (:mod:`faultslip.dynamics.rate_state`), the scene (:mod:`faultslip.fault.rate_state_scene`)
and the one-block fault (:mod:`faultslip.fault.rate_state_fault`, :mod:`faultslip.fault.rate_state_cells`)
are shared: the laboratory fits, the maps and the 2-D fault's calibration use them too.
"""
