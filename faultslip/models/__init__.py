"""Every model family behind one contract: a scene in, a :class:`Result` out.

>>> import faultslip
>>> result = faultslip.run("san_andreas_1906.toml")
>>> result["slip_per_event"]            # a pint Quantity  # doctest: +SKIP
>>> result.method, result.estimated_relative_error  # doctest: +SKIP
>>> result.to_xarray()                  # CF attributes, as the CLI writes  # doctest: +SKIP

A scene names its family with ``family = "..."`` (:data:`DECLARATIONS`); :func:`family_of` reads it,
and imports that family's module alone.
The families: the seed 003 spring-slider (the default), the rate-and-state slider, seed 002's
quasi-harmonic vibration, seed 001's nanoscale model, seed 004's asperities and seed 000's rough
surfaces.
"""

from __future__ import annotations

from faultslip.errors import InputError
from faultslip.models.registry import DECLARATIONS, FAMILIES, Family, families, family_of, load, register
from faultslip.models.result import Result

__all__ = ["DECLARATIONS", "FAMILIES", "Family", "Result", "families", "family_of", "load", "register", "run",
           "simulate"]


#: Options every family may be given: where the run's output goes (for a disk estimate) and the budget's
#: override; a family that has no use for them ignores them.
UNIVERSAL = ("output", "allow_large", "overwrite")


def run(scene=None, method: str | None = None, tolerance: float | None = None, allow_large: bool = False) -> Result:
    """Evaluate a scene (a path, or a bundled scene's name; None: the 1906 San Francisco scene).

    ``method`` is one of the family's methods or ``"auto"`` (the cheapest whose declared error
    meets ``tolerance``, a relative error; each family has its default). ``allow_large`` runs
    beyond the time and memory budget, for a family whose run has one (a family without one
    needs no permission).
    """
    family = family_of(scene)
    options = {"allow_large": allow_large} if allow_large and "allow_large" in family.run_options else {}
    return family.run(scene, method=method, tolerance=tolerance, **options)


def simulate(scene=None, **options) -> Result:
    """Simulate a scene's time series with the family's options (``cycles``, ``slip_solver``, ``rtol``,
    ``allow_large``, ...); an option the family does not take is refused in one sentence."""
    family = family_of(scene)
    given = {name: value for name, value in options.items() if value is not None and value is not False}
    extra = [name for name in given if name not in family.simulate_options and name not in UNIVERSAL]
    if extra:
        raise InputError(f"--{extra[0].replace('_', '-')} applies to seed-law scenes; {family.why}")
    return family.simulate(scene, **{name: value for name, value in given.items() if name in family.simulate_options})
