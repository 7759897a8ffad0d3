"""The 2-D fault (quasi-dynamic cycles in an elastic half-space, SEAS BP1): one model family, one folder.

* ``family``: the declaration, run, simulate, Richardson runs;
* ``scene``: the scene reader, budgets, and the 2-D fault built from a one-slider scene;
* ``kernel``, ``model``, ``compiled``, ``integrate``: the antiplane stress kernel (dense and FFT), the
  force balance, adaptive stepping with events, records, checkpoints and restart;
* ``analysis``: settled cycles, periodic, aperiodic and unsettled sequences, declared errors;
* ``cells``: its sweep (checkpointed cells);
* ``model_error``: the one slider's model error measured against this fault (the calibration);
* ``figures``: its figures.

Its files go through the door (:mod:`faultslip.io.records`, :mod:`faultslip.io.seas`).
"""
