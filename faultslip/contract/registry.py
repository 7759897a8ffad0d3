"""The model families, how a scene names its family, and each family's contract.

A scene names its family in one key, ``family = "vibration"`` at the top of its TOML. A scene
written before that key existed is read by the one declaration each family makes here: the
table that is its own (``[vibration]``, ``[law]``) or the ``[friction] law`` it uses. The
command line, :func:`faultslip.run` and the sweep engine ask :func:`family_of` and nothing
else; a new family is one module with a :class:`Family` and one :func:`declare` (or one line in
:data:`DECLARATIONS`). A family's module is imported when a scene of it runs, so a command that
needs one family loads no other (seed 004's dynamics bring scipy's integrators, which a
closed-form fault estimate never needs).
"""

from __future__ import annotations

import importlib
import importlib.metadata
import os
from dataclasses import dataclass
from typing import Callable

from faultslip.errors import InputError, did_you_mean
from faultslip.io.resources import check_toml_kind, parse_toml, read_text_file, resolve_path, scene_document


@dataclass(frozen=True)
class Family:
    """One model family's contract.

    ``run(scene, method, tolerance)`` and ``simulate(scene, **options)`` return a
    :class:`~faultslip.contract.result.Result`; ``scene`` is a path, a bundled name or a scene object.
    ``read_scene(text, source, path)`` reads a scene file into the object a sweep varies (it has
    ``name``, ``text``, ``path`` and ``with_values(**si)``); ``cells`` is the family's sweep
    (:class:`faultslip.contract.cells.Cells`): its parameters, outputs, methods and ``evaluate``
    over a block of cells.
    """

    name: str
    description: str
    run: Callable
    simulate: Callable
    simulate_options: tuple = ()  # the options of simulate beyond the scene (cycles, slip_solver, rtol, ...)
    run_options: tuple = ()  # the options of run beyond method and tolerance (allow_large)
    why: str = ""  # why the other options do not apply, said when one is given
    read_scene: Callable | None = None
    cells: object = None  # a Cells, or scene -> Cells for a family whose scenes come in more than one shape
    #: () -> the family's methods, each {name, friction_laws, domain, cost_model} ('faultslip methods')
    methods: Callable | None = None
    #: (a coarser family's scene, reason, allow_large=, progress=) -> Result: the scene run on this richer model,
    #: for a family that escalates to it (the rate-and-state slider's fault to the 2-D fault)
    refine: Callable | None = None
    #: (estimate, report, name, method=, tolerance=, allow_large=, progress=) -> Result: a one-block answer of this
    #: family reached by another door (``faultslip fault`` with a saved rate-and-state fit) put on the family's
    #: ladder: its model error declared, a tolerance it misses escalated (None: the family takes none)
    adopt: Callable | None = None
    #: (scene, cycles=, frames=, slip_share=) -> (movie, figure, details): the family's animation for
    #: ``faultslip animate`` (:func:`faultslip.plots.animation.save_gif` writes it); None: it has none
    animate: Callable | None = None
    #: (scene, tolerance=) -> Result: every rung of the ladder on the scene, its answer, declared range and cost,
    #: with the chart (``faultslip model-error SCENE``); None: the family has no ladder
    ladder: Callable | None = None
    #: ``(scene, action, **options) -> Estimate``: the family's cost model, what ``run`` (action
    #: "run") or ``simulate`` ("simulate") of the scene with those options needs before it starts; the budget is
    #: checked against it (``faultslip run SCENE --estimate`` prints it)
    estimate: Callable | None = None
    #: the family's worked example, which the conformance suite runs (check_family over the registry): a scene
    #: (a bundled name), a study of it (a bundled name), a small sweep of the scene (parameter -> two values with
    #: units) and its simulation's options (None: the check does not simulate it)
    example: "Example | None" = None


@dataclass(frozen=True)
class Example:
    """A family's worked example (:attr:`Family.example`)."""

    scene: str
    study: str
    sweep: dict
    simulate: dict | None = None


@dataclass(frozen=True)
class Declaration:
    """Where a family lives, and what declares it in a scene without a ``family`` key."""

    module: str
    table: str | None = None  # a table of its own ([vibration], [law])
    friction_law: str | None = None  # or the [friction] law it uses


#: Every family. The first is the default.
DECLARATIONS = {
    "spring_slider": Declaration("faultslip.models.spring_slider.family"),
    # its own form ([law]), and the older one: a seed-law fault scene with [friction] law = "rate_state"
    "rate_state_slider": Declaration("faultslip.models.rate_state_slider.family", table="law", friction_law="rate_state"),
    "vibration": Declaration("faultslip.models.vibration.family", table="vibration"),
    "nanoscale": Declaration("faultslip.models.nanoscale.family", friction_law="nanoscale"),
    "asperity": Declaration("faultslip.models.asperity.family", friction_law="asperity"),
    "rough_surface": Declaration("faultslip.models.rough_surface.family", friction_law="rough_surface"),
    "fault_2d": Declaration("faultslip.models.fault_2d.family"),  # declared by family = "fault_2d" alone
    "fault_3d": Declaration("faultslip.models.fault_3d.family"),  # declared by family = "fault_3d" alone
    "spring_chain": Declaration("faultslip.models.spring_chain.family"),  # declared by family = "spring_chain" alone
}

#: Scene objects a family's run and simulate take as they are, by qualified class name (told apart without
#: importing a family): what :func:`faultslip.models.read_slider_scene` and the families' loaders return, and a Fault. A
#: scene object with a ``family`` attribute (:class:`faultslip.contract.scenes.TomlScene`) names its own.
SCENE_TYPES = {
    "faultslip.fault.scene.Scene": "spring_slider",
    "faultslip.fault.scaling.Fault": "spring_slider",
    "faultslip.models.rate_state_slider.scene.RateStateScene": "rate_state_slider",
    "faultslip.models.fault_2d.scene.Fault2DScene": "fault_2d",
    "faultslip.models.fault_3d.scene.Fault3DScene": "fault_3d",
}

#: The families loaded so far, by name (:func:`load` fills it).
FAMILIES: dict[str, Family] = {}


def declare(name: str, module: str, table: str | None = None, friction_law: str | None = None) -> None:
    """Add a family: the one line a new family needs (its module then registers its :class:`Family`)."""
    if not name.isidentifier():
        raise InputError(f"a family's name is an identifier, got {name!r}")
    DECLARATIONS[name] = Declaration(module, table, friction_law)


def register(family: Family) -> Family:
    """Called by a family's module: its :class:`Family` joins :data:`FAMILIES`."""
    FAMILIES[family.name] = family
    return family


#: Families declared outside faultslip for processes it starts or that start it (batch jobs, workers, a CLI run
#: from a script): ``FAULTSLIP_FAMILIES="name=package.module, other=package.other"``, each as :func:`declare`.
FAMILIES_VARIABLE = "FAULTSLIP_FAMILIES"


#: The entry-point group a package registers its families in (``pyproject.toml``:
#: ``[project.entry-points."faultslip.families"]``, ``name = "package.module"``): a family outside faultslip is
#: found as xarray finds its backends, with nothing to edit here.
ENTRY_POINTS = "faultslip.families"


def _declared_in_environment() -> None:
    """Declare the families :data:`FAMILIES_VARIABLE` names and those installed packages register under
    :data:`ENTRY_POINTS` (a malformed entry is one sentence)."""
    for entry in filter(None, (part.strip() for part in os.environ.get(FAMILIES_VARIABLE, "").split(","))):
        name, separator, module = (piece.strip() for piece in entry.partition("="))
        if not separator or not module:
            raise InputError(f"{FAMILIES_VARIABLE} lists families as name=package.module, separated by commas; "
                             f"got {entry!r}")
        if name not in DECLARATIONS:
            declare(name, module)
    for point in _entry_points():
        if point.name not in DECLARATIONS:
            declare(point.name, point.value.partition(":")[0].strip())


def _entry_points() -> tuple:
    """The installed packages' family entry points (read once a process: installing one needs a new process)."""
    if not _ENTRY_POINTS_SEEN:
        _ENTRY_POINTS_SEEN.append(tuple(importlib.metadata.entry_points(group=ENTRY_POINTS)))
    return _ENTRY_POINTS_SEEN[0]


_ENTRY_POINTS_SEEN: list = []


def load(name: str) -> Family:
    """The family ``name``, its module imported on first use."""
    if name not in FAMILIES:
        if name not in DECLARATIONS:
            _declared_in_environment()
        if name not in DECLARATIONS:
            raise InputError(f"{name!r} is not one of faultslip's model families ({', '.join(DECLARATIONS)})"
                             f"{did_you_mean(name, DECLARATIONS)}")
        module = importlib.import_module(DECLARATIONS[name].module)
        declared = getattr(module, "FAMILY", None)  # imported before, and forgotten since: register it again
        if name not in FAMILIES and getattr(declared, "name", None) == name:
            register(declared)
        if name not in FAMILIES:
            raise InputError(f"{DECLARATIONS[name].module} registers no family named {name!r}")
    return FAMILIES[name]


def families() -> dict[str, Family]:
    """Every family, loaded.

    Returns
    -------
    dict
        Family name -> :class:`Family`, each family's module imported.
    """
    _declared_in_environment()
    return {name: load(name) for name in DECLARATIONS}


def cells_of(family: Family, scene):
    """The :class:`~faultslip.contract.cells.Cells` that sweep ``scene`` (a family may have one per scene shape)."""
    cells = family.cells
    return cells(scene) if callable(cells) and not hasattr(cells, "evaluate") else cells


#: The rungs of the ladder a fault scene runs on, cheapest first (``faultslip run SCENE --model NAME``): each reads
#: the same scene, the one description of the fault (:mod:`faultslip.fault.ladder`). A family whose methods hold none
#: of them is not on the ladder, and asked for one says so (:func:`check_rung`).
RUNGS = ("one_slider", "fault_2d", "fault_3d")


def check_rung(family, method) -> None:
    """Refuse a rung of the ladder (:data:`RUNGS`) asked of a family whose methods hold none, in one sentence
    that says what runs the rungs (a fault scene) and where the family's own methods are listed."""
    if method not in RUNGS or family.methods is None or set(RUNGS) & {row["name"] for row in family.methods()}:
        return  # on the ladder: the family's run says which rungs its scene reaches
    article = "an" if family.name[0] in "aeiou" else "a"
    raise InputError(f"{method!r} is a rung of a fault's ladder ({', '.join(RUNGS)}), which a fault scene runs "
                     f"(a rate-and-state fault, a 2-D or a 3-D fault: configs/seas_bp1.toml); {article} {family.name} "
                     f"scene is not one: its methods are listed by 'faultslip methods'")


#: What every method declares: its name, the friction laws it takes, where it holds, what it costs, and the error
#: it declares there (what ``faultslip methods`` prints and ``auto`` chooses by).
METHOD_FIELDS = ("name", "friction_laws", "domain", "cost_model", "declared_error")


def run_method(row: dict) -> str | None:
    """The ``--method`` value ``faultslip run`` takes for a method row: its name, unless the row says it is reached
    another way (``"run_method": None`` and a ``selected_by`` sentence: a baseline, an integrator a study or
    ``simulate`` chooses). check_family asks the family's run for every one it lists."""
    return row.get("run_method", row["name"])


def selected_by(row: dict) -> str:
    """How a user reaches the method: the run's option, or the row's own sentence where run does not take it."""
    name = run_method(row)
    return f"faultslip run SCENE --method {name}" if name is not None else row["selected_by"]


def declared_rows(family: str, *names: str) -> list[dict]:
    """The method rows ``names`` of another family's declaration (a rung one family's run reaches through another:
    the rate-and-state block's ``fault_2d``), so a row is written once."""
    return [row for row in (load(family).methods() or []) if row["name"] in names]


def method_rows(family: str | None = None) -> list[dict]:
    """Every family's methods (or one family's), each once, with the families that use it, the ``--method`` value
    ``faultslip run`` takes for it (``run_method``, None where run does not) and how it is reached (``selected_by``):
    what ``faultslip methods`` prints."""
    rows: dict[str, dict] = {}
    for name, declared in families().items():
        for row in (declared.methods() if declared.methods else []):
            entry = rows.setdefault(row["name"], {key: row[key] for key in METHOD_FIELDS} | {
                "run_method": run_method(row), "selected_by": selected_by(row), "families": []})
            entry["families"].append(name)
    return [row for row in rows.values() if family is None or family in row["families"]]


def _declared(document: dict) -> str | None:
    declared = document.get("family")
    if isinstance(declared, str) and declared not in DECLARATIONS:
        _declared_in_environment()
    if declared is not None:
        if not isinstance(declared, str) or declared not in DECLARATIONS:
            raise InputError(f"family {declared!r} is not one of faultslip's model families "
                             f"({', '.join(DECLARATIONS)}){did_you_mean(str(declared), DECLARATIONS)}")
        return declared
    friction = document.get("friction")
    law = friction.get("law") if isinstance(friction, dict) else None
    for name, declaration in DECLARATIONS.items():
        if declaration.friction_law is not None and law == declaration.friction_law:
            return name
    for name, declaration in DECLARATIONS.items():
        if declaration.table is not None and declaration.table in document:
            return name
    return None


def family_of_document(document: dict) -> Family:
    """The family of a parsed scene file."""
    return load(_declared(document) or next(iter(DECLARATIONS)))


def family_of(scene=None) -> Family:
    """The family of a scene file, a bundled scene's name or a scene object (None: the default 1906 scene, a
    spring-slider).

    Parameters
    ----------
    scene : str, path or scene object, optional
        A scene file, a bundled scene's name, or a scene object.

    Returns
    -------
    Family
        The family the scene names, by its ``family`` key or its declaring table.
    """
    default = next(iter(DECLARATIONS))
    if scene is None:
        return load(default)
    if not isinstance(scene, (str, os.PathLike)):
        own = getattr(scene, "family", None)
        if isinstance(own, str) and own in DECLARATIONS:
            return load(own)
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
    check_toml_kind(document, path.name, "scene")
    return load(_declared(document) or default)


def read_scene(scene, base_dir=None):
    """A scene file (or a bundled scene's name) read by its family into the object a sweep varies; a scene
    object is returned as it is. (scene object, family)."""
    if not isinstance(scene, (str, os.PathLike)):
        return scene, family_of(scene)
    path, origin = resolve_path(scene, "scene", base_dir=base_dir)
    text = read_text_file(path, "scene file")
    return read_scene_text(text, path.name, path, origin)


def read_scene_text(text: str, source: str, path=None, origin: str = ""):
    """A scene's text read by its family: (scene object, family)."""
    document = parse_toml(text, source)
    check_toml_kind(document, source, "scene")
    family = family_of_document(document)
    if family.read_scene is None:
        raise InputError(f"a {family.name} scene cannot be read for a study")
    scene = family.read_scene(text, source, path)
    if origin:
        scene.origin = origin
    return scene, family
