"""Laboratory records: motion records, stick-slip event analysis and free-decay identification.

Its public names (``faultslip.lab.NAME``) are listed in :mod:`faultslip.api`; the modules hold the rest.
"""

from faultslip.api import TOPICS as _TOPICS
from faultslip.api import exports as _exports

__getattr__, __dir__, __all__ = _exports(__name__, _TOPICS["lab"])
