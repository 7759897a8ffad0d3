"""
The San Andreas map
===================

Segment by segment, with each segment's slip rate and lithology (configs/san_andreas_map.toml),
predicted slip and recurrence mapped onto a longitude-latitude grid.
"""
from faultslip import config_path, load_map, map_figure, observed_table, run_map

spec = load_map(config_path("san_andreas_map.toml"))
dataset = run_map(spec)
print(observed_table(dataset))
map_figure(dataset)
