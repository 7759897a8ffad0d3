"""Input and output: bundled resources, atomic writes, netCDF, reports and JSON, output checks and locks,
worker processes, and the budget a run is checked against. Imports only the core (units, errors).

Its public names (``faultslip.io.NAME``) are listed in :mod:`faultslip.api`; the modules hold the rest.
"""

from faultslip.api import TOPICS as _TOPICS
from faultslip.api import exports as _exports

__getattr__, __dir__, __all__ = _exports(__name__, _TOPICS["io"])
