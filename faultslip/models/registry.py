"""The model families and how a scene names its family.

A scene names its family in one key, ``family = "vibration"`` at the top of its TOML. A scene
written before that key existed is read by the one declaration each family makes here: the
table that is its own (``[vibration]``, ``[law]``) or the ``[friction] law`` it uses. The
command line and :func:`faultslip.run` ask :func:`family_of` and nothing else; a new family is
one module with a :class:`Family` and one line in :data:`FAMILIES`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from faultslip.errors import InputError, did_you_mean
from faultslip.fault.scene import resolve_path, scene_document


@dataclass(frozen=True)
class Family:
    """One model family's contract: how its scenes declare it, and its run and simulation.

    ``run(path, method, tolerance)`` and ``simulate(path, **options)`` return a
    :class:`~faultslip.models.result.Result`. ``table`` and ``friction_law`` are the declaration
    a scene without a ``family`` key is read by.
    """

    name: str
    description: str
    run: Callable
    simulate: Callable
    table: str | None = None
    friction_law: str | None = None
    simulate_options: tuple = ()  # the options of simulate beyond the scene (cycles, slip_solver, rtol, ...)
    why: str = ""  # why the other options do not apply, said when one is given


FAMILIES: dict[str, Family] = {}


def register(family: Family) -> Family:
    FAMILIES[family.name] = family
    return family


def _declared(document: dict) -> str | None:
    declared = document.get("family")
    if declared is not None:
        if not isinstance(declared, str) or declared not in FAMILIES:
            raise InputError(f"family {declared!r} is not one of faultslip's model families "
                             f"({', '.join(FAMILIES)}){did_you_mean(str(declared), FAMILIES)}")
        return declared
    friction = document.get("friction")
    law = friction.get("law") if isinstance(friction, dict) else None
    for family in FAMILIES.values():
        if family.friction_law is not None and law == family.friction_law:
            return family.name
    for family in FAMILIES.values():
        if family.table is not None and family.table in document:
            return family.name
    return None


def family_of(scene=None) -> Family:
    """The family of a scene file or bundled scene name (None: the default 1906 scene, a spring-slider)."""
    if scene is None:
        return FAMILIES["spring_slider"]
    path, _ = resolve_path(scene, "scene")
    document = scene_document(str(path))
    if document is None:  # unreadable: the spring-slider's reader says why in its own words
        return FAMILIES["spring_slider"]
    return FAMILIES[_declared(document) or "spring_slider"]
