"""Friction laws and the materials that carry them: static and kinetic laws (seed 003 eq. 2-18,
Cameron's time-of-stick law), Table I and the lithologies, the user registry of fits, and fitting eq. 2-18
to laboratory data.

Its public names (``faultslip.friction.NAME``) are listed in :mod:`faultslip.api`; the modules hold the rest.
"""

from faultslip.api import TOPICS as _TOPICS
from faultslip.api import exports as _exports

__getattr__, __dir__, __all__ = _exports(__name__, _TOPICS["friction"])
