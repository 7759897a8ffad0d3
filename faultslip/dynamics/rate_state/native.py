"""The compiled fault-cycle stepper (``_cycles``, C, built at install where a compiler is; hatch_build.py).

:func:`faultslip.dynamics.rate_state.slider.fault_cycles` runs it as ``dopri5_compiled``: the same
Dormand-Prince 5(4) scheme, states and event location as its ``dopri5``, stepped in C from one event
edge to the next (about 50 times faster a step). Without the build, ``auto`` never chooses it.
"""

from __future__ import annotations

try:
    from faultslip.dynamics.rate_state import _cycles
except ImportError:  # built only where a C compiler was found at install
    _cycles = None

#: status codes of ``_cycles.run``
CROSSED, HORIZON, TOO_MANY_STEPS, STEP_COLLAPSE = 0, 1, 2, 3


def available() -> bool:
    """Whether the C stepper was built with this install."""
    return _cycles is not None


def run(*args):
    """``_cycles.run``: see its docstring (``faultslip.dynamics.rate_state._cycles``)."""
    return _cycles.run(*args)
