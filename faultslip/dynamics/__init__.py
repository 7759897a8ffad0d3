"""The model families' numerics, apart from the machinery they share.

* ``shared/``: the cycle result, the assessment a method declares, the Dormand-Prince tableau;
* ``spring_slider/``: seed 003's slider, closed form (eq. 2-19), exact cycle, critical rate,
  event-driven simulation and the regularised baseline;
* ``rate_state/``: the rate-and-state slider, its compiled kernel and method declarations;
* ``vibration``, ``nanoscale``, ``asperity``: seeds 002, 001 and 004, one module each;
* ``methods``: the method hierarchy over every family, with ``auto``, and ``kernel``, the
  vectorised cell kernel that studies run on it.
"""
