"""The rate-and-state slider: one model family, one folder.

* ``family``: the declaration, run, simulate, velocity steps, stability, the older scene form;
* ``cycles``: a fault's earthquake cycles on one quasi-dynamic spring-block;
* ``figures``: its cycles figure;
* ``scene``: its scene files (a laboratory slider, or a fault as one slider);
* ``one_slider``: the one slider's stiffness and its calibration against the 2-D fault;
* ``model_error``: that calibration's declared model error; ``cost``: its cost model.

The numerics (:mod:`faultslip.dynamics.rate_state`) and the one-block fault (:mod:`faultslip.fault.rate_state_fault`,
:mod:`faultslip.fault.rate_state_cells`) are shared: the laboratory fits, the maps and the 2-D fault's ladder
use them too.
"""
