"""
The Parkfield sequence against the seed law
===========================================

The Parkfield M~6 earthquakes (configs/catalog_san_andreas.csv) fitted with lognormal and
Brownian-passage-time renewal models, beside the seed law's predicted recurrence for the
Parkfield segment (configs/parkfield.toml).
"""
import numpy as np

from faultslip.evaluation.catalogs import compare
from faultslip.fault.scene import load_scene
from faultslip.io.catalogs import read_catalog
from faultslip.io.resources import config_path
from faultslip.plots.catalogs import catalog_figure

scene = load_scene(config_path("parkfield.toml"))
comparison = compare(read_catalog(config_path("catalog_san_andreas.csv")), scene, trace=scene.trace,
                     max_magnitude=6.5, as_of=np.datetime64("2026-01-01"), bootstrap=300)
print(comparison.report("Parkfield").to_text())
catalog_figure(comparison, "Parkfield M~6 sequence against the seed law")
