"""
The San Andreas map
===================

Segment by segment, with each segment's slip rate and lithology (configs/san_andreas_map.toml),
predicted slip and recurrence mapped onto a longitude-latitude grid.
"""
from faultslip.io import config_path
from faultslip.hazard import read_map, observed_table, run_map
from faultslip.plots import map_figure

spec = read_map(config_path("san_andreas_map.toml"))
dataset = run_map(spec)
print(observed_table(dataset))
map_figure(dataset)
