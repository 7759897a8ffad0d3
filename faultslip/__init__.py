"""faultslip: laboratory rock-friction stick-slip scaled to earthquake slip and recurrence.

The physics follows seed 003 (Friction-induced oscillations in rock systems):
a spring-slider whose static friction rises as the loading rate falls
(eq. 2-18), whose stick-slip amplitude follows eq. 2-19, and which, scaled to
a strike-slip fault (§5-2), predicts slip per earthquake and recurrence.

Internally every quantity is SI; the year is the Julian year (365.25 d).
"""

__version__ = "0.1.0"

# The public API (faultslip/api.py): the five verbs, Result, the errors and the units here, the rest by topic
# below (faultslip.io, friction, lab, models, hazard, plots), each loaded on first use (PEP 562) so that
# "import faultslip" and the command line start fast, and a Ctrl-C during start-up reaches the CLI's handler.
from faultslip import api as _api

TOPICS = tuple(_api.TOPICS)
__all__ = sorted(set(_api.TOP) | set(TOPICS))


def __getattr__(name):
    if name in _api.TOP:
        value = _api.resolve(_api.TOP[name])
    elif name in TOPICS:
        import importlib

        value = importlib.import_module(f".{name}", __name__)
    else:
        value = _api.moved(name)  # a flat name of an earlier release, with a FutureWarning
        if value is None:
            raise AttributeError(f"module 'faultslip' has no attribute {name!r}")
        return value  # not cached: every use of an old name is told
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))
