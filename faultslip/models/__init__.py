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

import dataclasses
import importlib
import numbers

from faultslip import ranges
from faultslip.errors import InputError, refusal
from faultslip.io import budget
from faultslip.contract.options import OPTIONS, UNIVERSAL
# re-exported (the names' __all__ is built below, which linters cannot read)
from faultslip.contract.registry import DECLARATIONS as DECLARATIONS, FAMILIES as FAMILIES, Family as Family
from faultslip.contract.registry import check_rung, families, family_of, method_rows
from faultslip.contract.registry import load as load, register as register
from faultslip.contract.result import Result, judge_tolerance

from faultslip.api import TOPICS as _TOPICS
from faultslip.api import exports as _exports

# the family-level names of faultslip.api's "models" topic (read_slider_scene, simulate_fault, ...), loaded on first use
__getattr__, __dir__, __all__ = _exports(__name__, {name: where for name, where in _TOPICS["models"].items()
                                                    if not where.startswith("models:")},
                                         defined=("DECLARATIONS", "FAMILIES", "Family", "Result", "animate", "estimate",
                                                  "families", "family_of", "load", "methods", "register", "run",
                                                  "simulate"))


def _not_an_option(name: str, family) -> str:
    """One sentence: the option is not the family's, and what the family takes instead."""
    article = "an" if family.name[0] in "aeiou" else "a"
    flag = OPTIONS[name].flag if name in OPTIONS else f"--{name.replace('_', '-')}"
    return (f"{name} ({flag}) is not an option of {article} {family.name} scene; "
            f"{family.why or 'see faultslip simulate --help'}")


def _checked_option(name: str, value):
    """``value`` as its option's kind (:data:`OPTIONS`) takes it, or refused in one sentence: a count is a whole
    number (3.0 is 3), a number is real, a switch is True or False (the command line's parser reads its flags so; a
    notebook's ``simulate(cycles="ten")`` had met a TypeError from deep in the family)."""
    kind = OPTIONS[name].kind if name in OPTIONS else "text"
    label = f"{name} ({OPTIONS[name].flag})" if name in OPTIONS else name  # the keyword, and the command's flag
    if kind == "count":
        return ranges.check_count(value, label, 1)
    real = isinstance(value, numbers.Real) and not isinstance(value, bool)  # numpy's scalars register as Real
    if (kind == "number" and not real) or (kind == "switch" and not isinstance(value, (bool, numbers.Integral))):
        raise InputError(f"{label} is {'a number (such as 1e-8)' if kind == 'number' else 'True or False'}, "
                         f"got {value!r}")
    return value


def run(scene=None, method: str | None = None, tolerance: float | None = None, allow_large: bool = False,
        progress=None, allow_underresolved: bool = False, richardson: bool = False, check_starts: bool = False,
        model: str | None = None, **quantities) -> Result:
    """Evaluate a scene, as ``faultslip run`` does.

    Parameters
    ----------
    scene : str, path, scene object or None
        A scene file, a bundled scene's name, or a scene object (:func:`faultslip.models.read_slider_scene`'s Scene, a
        :class:`faultslip.models.Fault`, a rate-and-state or 2-D fault scene). None: the 1906 San Francisco scene,
        unless ``quantities`` describe a fault.
    method : str, optional
        One of the family's methods, or ``"auto"``: the cheapest whose declared error meets ``tolerance``.
    tolerance : float, optional
        The relative error allowed (each family has its default).
    allow_large : bool
        Run beyond the time and memory budget, for a family whose run has one.
    progress : callable, optional
        ``(done, total)``: progress of a long run (an escalation to the 2-D fault), for a family that reports it.
    allow_underresolved : bool
        Run a discretised fault coarser than its sequences keep their character at, as a qualitative answer.
    richardson : bool
        Run a discretised fault again on elements half the size, and declare the discretisation error the two
        show (Richardson) instead of the a-priori bound.
    check_starts : bool
        Run a discretised fault again from other starts (0.1 and 10 times its start's slip rate), and say whether
        it settles to the same cycle from each.
    model : str, optional
        A fault scene's rung (``one_slider``, ``fault_2d``, ``fault_3d``): another name for ``method``, as
        ``--model`` is for ``--method``.
    **quantities
        A fault's inputs as keywords with units, as ``faultslip fault`` takes them: ``lithology="granodiorite"``,
        ``zone_width="13 mi"``, ``shear_stress="250 bar"``, ``slip_rate="2 in/yr"``, ...

    Returns
    -------
    Result
        Values as pint Quantities (``result["slip_per_event"]``), the method and its declared error, the
        report, ``to_xarray()`` and the figure.
    """
    method = _method_or_model(method, model)
    tolerance = ranges.check_tolerance(tolerance)  # "10 %" as the command takes it; refused here in one sentence
    if quantities:
        if scene is not None:
            raise InputError(f"run() with a scene takes method (or model), tolerance and its options, not "
                             f"{', '.join(quantities)}; a fault's quantities as keywords (lithology, zone_width, "
                             "...) are given without a scene")
        # the model the lithology calls for: the seed law, or a saved rate-and-state fit (faultslip fault)
        return importlib.import_module("faultslip.models.fault_estimate").fault_estimate(
            method=method, tolerance=tolerance, **quantities)  # it judges its tolerance itself, as run does
    family = family_of(scene)
    check_rung(family, method)
    options = {}
    if progress is not None and "progress" in family.run_options:  # a family whose run may be long reports it
        options["progress"] = progress
    for name, asked in (("allow_large", allow_large), ("allow_underresolved", allow_underresolved),
                        ("richardson", richardson), ("check_starts", check_starts)):
        if not _checked_option(name, asked):
            continue
        if name in family.run_options:
            options[name] = asked
        elif name not in UNIVERSAL:
            raise InputError(_not_an_option(name, family))
    if family.estimate is not None and "allow_large" not in family.run_options:  # its cost model, checked here
        budget.check(family.estimate(scene, "run", method=method, tolerance=tolerance), allow_large)
    return judge_tolerance(family.run(scene, method=method, tolerance=tolerance, **options), tolerance)


def _method_or_model(method: str | None, model: str | None) -> str | None:
    """``method``, or ``model`` (its other name, as on the command line); both, only where they agree."""
    if model is not None and method is not None and model != method:
        raise InputError(f"give method or model (the same option), not both: got method {method!r} and model "
                         f"{model!r}")
    return method if method is not None else model


def estimate(scene=None, action: str = "run", **options) -> budget.Estimate:
    """What :func:`run` or :func:`simulate` of a scene would need, from its family's cost model, before it starts.

    Parameters
    ----------
    scene : str, path or scene object
        As for :func:`run`.
    action : str
        ``"run"``, ``"simulate"``, or ``"ladder"``: every rung of ``faultslip model-error SCENE`` (a fault scene's;
        ``include_3d=True`` adds a 2-D scene's 3-D rung).
    **options
        The options the run or simulation would take (``method`` or ``model``, ``tolerance``; ``cycles``, ``rtol``,
        ...).

    Returns
    -------
    faultslip.io.budget.Estimate
        CPU seconds, memory and disk (``report()``, ``to_xarray()``), and where the scene lies outside the scenes
        the cost model was fitted on. Its seconds include the CPU of the modules the run imports that this process
        has not yet (xarray, scipy's integrators, ...), measured by importing them (``import_seconds``).
    """
    if action not in ("run", "simulate", "ladder"):
        raise InputError(f"an estimate is of a run, a simulation or a ladder, not {action!r}")
    if "model" in options:
        options["method"] = _method_or_model(options.get("method"), options.pop("model"))
    if "tolerance" in options:
        options["tolerance"] = ranges.check_tolerance(options["tolerance"])
    family = family_of(scene)
    check_rung(family, options.get("method"))
    if action == "ladder" and family.ladder is None:
        raise InputError(f"a {family.name} scene has no ladder of rungs to run ('faultslip model-error' reads its "
                         "model error from a table), so there is nothing to estimate")
    for name in ("richardson", "check_starts"):  # what run would refuse, an estimate refuses too
        if options.get(name) and action == "run" and name not in family.run_options:
            raise InputError(_not_an_option(name, family))
    if family.estimate is None:
        raise InputError(f"the {family.name} family declares no cost model (Family.estimate), so nothing can be "
                         "estimated before it runs")
    estimated = family.estimate(scene, action, **{name: value for name, value in options.items() if value is not None})
    if str(options.get("output") or "").endswith(".nc"):  # a run's Dataset written through xarray
        estimated = dataclasses.replace(estimated, imports=(*estimated.imports, *budget.DATASET_WRITER_IMPORTS))
    # and the CPU this process would spend importing what the run needs, measured (a short run's largest part)
    return budget.with_imports(estimated)


def methods(scene=None) -> list[dict]:
    """The solution methods, as ``faultslip methods [SCENE]`` lists them: every family's, or the scene's family's.

    Parameters
    ----------
    scene : str, path or scene object, optional
        A scene: only the methods of its family that its run takes (asked through the family's estimate, before
        any work), and those it reaches another way (None: every family's).

    Returns
    -------
    list of dict
        One per method: ``name``, ``friction_laws``, ``domain``, ``cost_model``, ``declared_error``, the families
        that use it, ``run_method`` (what ``run(scene, method=...)`` and ``faultslip run --method`` take for it, or
        None where run does not) and ``selected_by`` (how it is reached).
    """
    if scene is None:
        return method_rows()
    family = family_of(scene)
    family.estimate(scene, "run")  # a scene its run would refuse is refused here, not listed with no method
    return [row for row in method_rows(family.name) if row["run_method"] is None
            or refusal(lambda: family.estimate(scene, "run", method=row["run_method"])) is None]


def simulate(scene=None, **options) -> Result:
    """Simulate a scene's time series, as ``faultslip simulate`` does.

    Parameters
    ----------
    scene : str, path, scene object or None
        As for :func:`run`. A :class:`faultslip.models.SliderSystem` is simulated as it is
        (:func:`faultslip.models.simulate_slider`, which returns the time series Dataset).
    **options
        The family's options (``cycles``, ``slip_solver``, ``rtol``, ``allow_large``, ...; the table
        :data:`faultslip.contract.options.OPTIONS`); one the family does not take is refused in one sentence
        naming the family. Any other keyword is a fault's quantity with units, as :func:`run` takes them
        (``lithology="granodiorite"``, ``zone_width="13 mi"``, ...): the fault is simulated as a scene.

    Returns
    -------
    Result
        With the time series (``result.time_series()``, ``to_xarray()``) and the family's figure (``plot()``).
    """
    if hasattr(scene, "is_linear") and hasattr(scene, "kinetic_law"):  # a SliderSystem: the integrator itself
        return importlib.import_module("faultslip.dynamics.spring_slider.simulate").simulate(scene, **options)
    quantities = {name: value for name, value in options.items() if name not in OPTIONS}
    if quantities:  # a fault as keywords with units, as run takes it
        if scene is not None:
            raise InputError(f"give a scene or a fault's quantities as keywords, not both ({', '.join(quantities)})")
        scene = importlib.import_module("faultslip.fault.scene").fault_scene(**quantities)
        options = {name: value for name, value in options.items() if name in OPTIONS}
    family = family_of(scene)
    given = {name: value for name, value in options.items() if value is not None and value is not False}
    extra = [name for name in given if name not in family.simulate_options and name not in UNIVERSAL]
    if extra:
        raise InputError(_not_an_option(extra[0], family))
    taken = {name: _checked_option(name, value) for name, value in given.items() if name in family.simulate_options}
    if family.estimate is not None and "allow_large" not in family.simulate_options:  # as in run
        budget.check(family.estimate(scene, "simulate", **taken), bool(given.get("allow_large")))
    return family.simulate(scene, **taken)


def animate(scene, cycles: int = 2, frames: int = 120, slip_share: float = 0.5):
    """A scene's animation, as ``faultslip animate`` draws it: the scene's family's own (a slider's block, spring
    and platform; a chain's blocks and catalogue).

    Parameters
    ----------
    scene : str, path or scene object
        A scene whose family animates.
    cycles : int
        Cycles (a slider) or events (a chain) to show.
    frames : int
        Frames of the animation.
    slip_share : float
        The share of the frames given to slips (a slider).

    Returns
    -------
    tuple
        (movie, figure, details): :func:`faultslip.plots.animation.save_gif` writes the movie; ``details`` are
        what the command reports (with units where they have them).
    """
    family = family_of(scene)
    if family.animate is None:
        able = sorted(name for name, declared in families().items() if declared.animate is not None)
        raise InputError(f"faultslip animate draws {', '.join(able)} scenes; {scene} is a {family.name} scene, "
                         "which has no animation (its figure: faultslip simulate SCENE --plot FILE.png)")
    return family.animate(scene, cycles=cycles, frames=frames, slip_share=slip_share)
