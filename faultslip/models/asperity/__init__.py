"""Seed 004, a block on asperities: one model family, one folder.

* ``family``: the declaration, run, simulate and the speed study;
* ``scene``: the scene reader (``[friction] law = "asperity"``);
* ``friction``: the contact law of the asperities (seed 004 §2);
* ``dynamics``: the six-state model, its quasi-static reduction, critical speeds and methods;
* ``speed_map``: stick fraction and outcome over speed and slope roughness;
* ``figures``: its figures.
"""
