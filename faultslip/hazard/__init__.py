"""The hazard analyst's functions in one place: regional maps and their fault systems, rupture sets, OpenQuake
source models and jobs, displacement hazard, empirical scaling, magnitude-frequency distributions, renewal
probabilities and catalogue predictability.

A facade only: each name lives in ``faultslip.studies``, ``faultslip.fault`` or ``faultslip.evaluation`` (the
table is :data:`faultslip.api.TOPICS`), and is loaded on first use.
"""

from faultslip.api import TOPICS as _TOPICS
from faultslip.api import exports as _exports

__getattr__, __dir__, __all__ = _exports(__name__, _TOPICS["hazard"])
