"""The model families and how a scene names its family.

A scene names its family in one key, ``family = "vibration"`` at the top of its TOML. A scene
written before that key existed is read by the one declaration each family makes here: the
table that is its own (``[vibration]``, ``[law]``) or the ``[friction] law`` it uses. The
command line and :func:`faultslip.run` ask :func:`family_of` and nothing else; a new family is
one module with a :class:`Family` and one line in :data:`DECLARATIONS`. A family's module is
imported when a scene of it runs, so a command that needs one family loads no other (seed 004's
dynamics bring scipy's integrators, which a closed-form fault estimate never needs).
"""

from __future__ import annotations

import importlib
import os
from dataclasses import dataclass
from typing import Callable

from faultslip.errors import InputError, did_you_mean
from faultslip.io.resources import resolve_path, scene_document


@dataclass(frozen=True)
class Family:
    """One model family's contract: how its scenes declare it, and its run and simulation.

    ``run(path, method, tolerance)`` and ``simulate(path, **options)`` return a
    :class:`~faultslip.models.result.Result`. How a scene declares the family is in
    :data:`DECLARATIONS`.
    """

    name: str
    description: str
    run: Callable
    simulate: Callable
    simulate_options: tuple = ()  # the options of simulate beyond the scene (cycles, slip_solver, rtol, ...)
    run_options: tuple = ()  # the options of run beyond method and tolerance (allow_large)
    why: str = ""  # why the other options do not apply, said when one is given


#: Every family: its module, and the table or [friction] law that declares it in a scene without a
#: ``family`` key. The first is the default.
DECLARATIONS = {
    "spring_slider": ("faultslip.models.spring_slider", None, None),
    "rate_state_slider": ("faultslip.models.rate_state_slider", "law", None),
    "vibration": ("faultslip.models.vibration", "vibration", None),
    "nanoscale": ("faultslip.models.nanoscale", None, "nanoscale"),
    "asperity": ("faultslip.models.asperity", None, "asperity"),
    "rough_surface": ("faultslip.models.rough_surface", None, "rough_surface"),
    "fault_2d": ("faultslip.models.fault_2d", None, None),  # declared by family = "fault_2d" alone
}

#: Scene objects a family's run and simulate take as they are, by qualified class name (told apart without
#: importing a family): what :func:`faultslip.load_scene` and the families' loaders return, and a Fault.
SCENE_TYPES = {
    "faultslip.fault.scene.Scene": "spring_slider",
    "faultslip.fault.scaling.Fault": "spring_slider",
    "faultslip.fault.rate_state_scene.RateStateScene": "rate_state_slider",
    "faultslip.fault.fault_2d_scene.Fault2DScene": "fault_2d",
}

#: The families loaded so far, by name (:func:`load` fills it).
FAMILIES: dict[str, Family] = {}


def register(family: Family) -> Family:
    """Called by a family's module: its :class:`Family` joins :data:`FAMILIES`."""
    FAMILIES[family.name] = family
    return family


def load(name: str) -> Family:
    """The family ``name``, its module imported on first use."""
    if name not in FAMILIES:
        importlib.import_module(DECLARATIONS[name][0])
    return FAMILIES[name]


def families() -> dict[str, Family]:
    """Every family, loaded."""
    return {name: load(name) for name in DECLARATIONS}


def _declared(document: dict) -> str | None:
    declared = document.get("family")
    if declared is not None:
        if not isinstance(declared, str) or declared not in DECLARATIONS:
            raise InputError(f"family {declared!r} is not one of faultslip's model families "
                             f"({', '.join(DECLARATIONS)}){did_you_mean(str(declared), DECLARATIONS)}")
        return declared
    friction = document.get("friction")
    law = friction.get("law") if isinstance(friction, dict) else None
    for name, (_, _, friction_law) in DECLARATIONS.items():
        if friction_law is not None and law == friction_law:
            return name
    for name, (_, table, _) in DECLARATIONS.items():
        if table is not None and table in document:
            return name
    return None


def family_of(scene=None) -> Family:
    """The family of a scene file, a bundled scene's name or a scene object (None: the default 1906 scene, a
    spring-slider)."""
    default = next(iter(DECLARATIONS))
    if scene is None:
        return load(default)
    if not isinstance(scene, (str, os.PathLike)):
        kind = f"{type(scene).__module__}.{type(scene).__qualname__}"
        if kind not in SCENE_TYPES:
            raise InputError(f"a scene is a path, a bundled scene's name or a scene object "
                             f"({', '.join(name.rsplit('.', 1)[1] for name in SCENE_TYPES)}), not a "
                             f"{type(scene).__name__}")
        return load(SCENE_TYPES[kind])
    path, _ = resolve_path(scene, "scene")
    document = scene_document(str(path))
    if document is None:  # unreadable: the spring-slider's reader says why in its own words
        return load(default)
    return load(_declared(document) or default)
