"""Seed 003, the spring-slider in the lab and scaled to a fault: one model family, one folder.

* ``family``: the declaration, run, simulate and the cycle of a scene.

It is the base every application shares: its numerics (:mod:`faultslip.dynamics.spring_slider`), its
method hierarchy (:mod:`faultslip.dynamics.methods`), its scene (:mod:`faultslip.fault.scene`), its fault
scaling (:mod:`faultslip.fault.scaling`) and its vectorised sweep (:mod:`faultslip.fault.spring_slider_cells`)
are used by the maps, the hazard chain, the classroom and the catalogs, so they stay below the families.
"""
