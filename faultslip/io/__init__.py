"""Input and output: bundled resources, atomic writes, netCDF, reports and JSON, output checks and locks,
worker processes, and the budget a run is checked against. Imports only the core (units, errors).
"""
