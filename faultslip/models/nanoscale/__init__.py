"""Seed 001, nanoscale stick-slip with contact charging: one model family, one folder.

* ``family``: the declaration, run, simulate and the damping swing;
* ``scene``: the scene reader (``[friction] law = "nanoscale"``);
* ``dynamics``: the model, its damping threshold A_c in closed form and its LSODA run;
* ``figures``: its figure.
"""
