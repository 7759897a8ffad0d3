"""The conformance check of a model family: what every family owes the rest of faultslip.

Like scikit-learn's ``check_estimator``, :func:`check_family` runs a registered family through the whole
contract on one of its scenes: the run and the simulation return a :class:`Result` whose Dataset has units on
every variable; its declared outputs are read from its run in their declared units and flags; its parameters
vary its scene; and a small sweep writes a CF file whose every variable has units. The suite runs it over every
registered family (``tests/capabilities/contract/test_families.py``); a new family passes it before it lands.
"""

from __future__ import annotations

import math
import re
import tempfile
from pathlib import Path

import numpy as np

from faultslip.contract.cells import cell_value
from faultslip.contract.registry import METHOD_FIELDS, cells_of, load, read_scene, run_method
from faultslip.errors import FaultslipError, refusal
from faultslip.contract.result import Result
from faultslip.io.budget import Estimate
from faultslip.io.netcdf import write_dataset
from faultslip.io.resources import open_dataset_lazily
from faultslip.studies.grid import Study, sweep


class ConformanceError(AssertionError):
    """A family breaks its contract; the message says where."""


def _require(condition, message: str) -> None:
    if not condition:
        raise ConformanceError(message)


def check_units(dataset, where: str) -> None:
    """Every data variable and numeric coordinate of ``dataset`` has a ``units`` attribute (CF: "1" for a
    number), and a flag variable its values and meanings."""
    for name, variable in {**dataset.data_vars, **dataset.coords}.items():
        if variable.dtype.kind in "OUS":  # a categorical coordinate: names, no units
            continue
        _require("units" in variable.attrs, f"{where}: {name} has no units attribute")
        if "flag_meanings" in variable.attrs:
            meanings = str(variable.attrs["flag_meanings"]).split()
            _require(len(meanings) == np.size(variable.attrs.get("flag_values")),
                     f"{where}: {name}'s flag_values and flag_meanings differ in number")


def _refuses(call) -> bool:
    """Whether ``call()`` refuses its input (raises :class:`~faultslip.errors.InputError`)."""
    return refusal(call) is not None


def _check_listed_methods(name: str, family, scene, rows: list[dict], unknown: str) -> None:
    """'faultslip methods' and the run agree: every method the family lists by a run name (``run_method``), its run
    takes (asked through its estimate, before any work), and the sentence refusing an unknown method names exactly
    those (its other names with an underscore are listed ones: a name the run takes but the listing hides fails)."""
    listed = [run_method(row) for row in rows if run_method(row) is not None]
    for method in listed:
        refused = refusal(lambda: family.estimate(scene, "run", method=method))
        _require(refused is None, f"{name}: lists method {method!r} for 'faultslip run --method' and its run "
                                  f"refuses it: {refused}")
    sentence = refusal(lambda: family.estimate(scene, "run", method=unknown)) or ""
    named = set(re.findall(r"\b[a-z][a-z0-9]*(?:_[A-Za-z0-9]+)+\b", sentence)) - {unknown}
    _require(all(method in named for method in listed) and named <= set(listed),
             f"{name}: refusing an unknown method, its run names {sorted(named)}, and 'faultslip methods' lists "
             f"{sorted(listed)} for it: the two say the same names")


def check_family(name: str, scene, sweep_values: dict, simulate: bool = True, simulate_options: dict | None = None):
    """Run family ``name`` through the contract on ``scene``; raise :class:`ConformanceError` where it breaks it.

    Parameters
    ----------
    name : str
        A registered family.
    scene : str or path
        A scene of the family (a file or a bundled scene's name).
    sweep_values : dict
        A small sweep of the scene: parameter -> values with units (two values make the check's sweep).
    simulate : bool
        Check the simulation too (its time series and figure).
    simulate_options : dict, optional
        Options of the family's simulate for the check (a short run).

    Returns
    -------
    dict
        What was checked: ``result`` (the run), ``dataset`` (the sweep) and ``outputs`` (the declared outputs).
    """
    family = load(name)
    _require(family.read_scene is not None and family.cells is not None,
             f"{name}: a family declares read_scene and cells (faultslip.contract)")
    rows = family.methods() if family.methods else []
    _require(rows and all(row.get(key) for row in rows for key in METHOD_FIELDS),
             f"{name}: declares its methods, each with {', '.join(METHOD_FIELDS)} ('faultslip methods')")
    # its cost model: what the run (and the simulation) needs, before it starts, in seconds, bytes and words
    _require(family.estimate is not None, f"{name}: declares its cost model (Family.estimate: scene, action -> "
                                          "faultslip.io.budget.Estimate)")
    for action in ("run",) + (("simulate",) if simulate else ()):
        estimate = family.estimate(scene, action, **((simulate_options or {}) if action == "simulate" else {}))
        _require(isinstance(estimate, Estimate) and estimate.what and all(
            math.isfinite(value) and value >= 0 for value in (estimate.seconds, estimate.memory, estimate.disk)),
            f"{name}: its cost model's {action} estimate is an Estimate with finite seconds, memory and disk")
    # an estimate is of the run it names: a method the run refuses before any work, the estimate refuses too
    unknown = "no_such_method"
    refused = {what: _refuses(call) for what, call in (
        ("run", lambda: family.run(scene, method=unknown)),
        ("estimate", lambda: family.estimate(scene, "run", method=unknown)))}
    _require(refused["run"] == refused["estimate"],
             f"{name}: its run {'refuses' if refused['run'] else 'takes'} method {unknown!r} and its estimate "
             f"{'refuses' if refused['estimate'] else 'takes'} it: an estimate is of the run it names")
    _check_listed_methods(name, family, scene, rows, unknown)
    # the run: a Result of this family, its Dataset with units, its report
    result = family.run(scene)
    _require(isinstance(result, Result) and result.family == name, f"{name}: run returns a Result of the family")
    check_units(result.to_xarray(), f"{name} run's to_xarray()")
    # a method a tolerance chose (the scene's or the family's default) is judged against it: the run carries it
    chose = re.search(r"\btolerance (\d[\d.e+-]*)", result.method_reason or "")
    _require(chose is None or (result.tolerance is not None and
                               math.isclose(result.tolerance, float(chose.group(1).rstrip(".")), rel_tol=1e-3)),
             f"{name}: its run's method was chosen for a tolerance ({chose.group(0) if chose else ''}) that the "
             "Result does not carry (Result.tolerance), so faultslip.run cannot judge it")
    _require(result.report().to_text().strip(), f"{name}: the run's report is empty")
    # the method it reports is one the listing names (the vibration run had said 'averaging', which no
    # --method took): a user who reads it can ask for it again
    names = {row["name"] for row in rows} | {run_method(row) for row in rows} - {None}
    _require(result.method is None or result.method in names,
             f"{name}: its run reports method {result.method!r}, which 'faultslip methods' does not list for it "
             f"({', '.join(sorted(names))})")
    # a scene read for a study varies by its declared parameters, and reads back
    loaded, found = read_scene(scene)
    _require(found.name == name, f"{name}: its scene reads as a {found.name} scene")
    cells = cells_of(family, loaded)
    for attribute in ("label", "checkpoints", "default_tolerance"):
        _require(hasattr(cells, attribute), f"{name}: its cells have no {attribute}")
    parameters = cells.parameters(loaded)
    _require(parameters and all(p.name == key for key, p in parameters.items()),
             f"{name}: declares its sweepable parameters by name")
    for key in sweep_values:
        _require(key in parameters, f"{name}: {key} is not among its sweepable parameters")
    # the declared outputs are the run's, in their units and flags
    study = Study(name="check", scene=loaded, dims={}, method="auto", tolerance=cells.default_tolerance,
                  family=family)
    outputs = cells.outputs(study)
    if outputs is not None:
        for output in outputs.values():
            try:
                value = cell_value(result, output)
            except (ValueError, TypeError) as exc:
                raise ConformanceError(f"{name}: declared output {output.name}: {exc}") from None
            if output.flags:
                _require(value == -1 or 0 <= value < len(output.flags), f"{name}: {output.name} flag {value}")
            else:
                _require(isinstance(value, float), f"{name}: {output.name} is not a number")
    # a small sweep in memory: every variable with units, every swept dimension labelled
    dataset = sweep(scene, **sweep_values)
    check_units(dataset, f"{name} sweep")
    for key, values in sweep_values.items():
        _require(dataset.sizes.get(key) == len(values), f"{name}: the sweep's {key} dimension")
    _require(dataset.attrs.get("faultslip_family") == name, f"{name}: the sweep names its family")
    numeric = [v for v in dataset.data_vars.values() if v.dtype.kind == "f"]
    _require(any(np.isfinite(v.values).any() for v in numeric), f"{name}: the sweep computed nothing")
    with tempfile.TemporaryDirectory() as folder:  # through netCDF and back, as the CLI writes it
        path = Path(folder) / "check.nc"
        write_dataset(dataset, path)
        with open_dataset_lazily(path, "check output") as back:
            check_units(back, f"{name} sweep written")
    if simulate:
        simulated = family.simulate(scene, **(simulate_options or {}))
        _require(isinstance(simulated, Result), f"{name}: simulate returns a Result")
        series = simulated.time_series()
        check_units(series, f"{name} simulation")
        figure = simulated.plot()
        _require(hasattr(figure, "savefig"), f"{name}: plot() returns a matplotlib Figure")
        import matplotlib.pyplot as plt  # heavy: imported where used

        plt.close(figure)
    return {"result": result, "dataset": dataset, "outputs": outputs}


def read_or_refuse(name: str, text: str) -> str | None:
    """Read ``text`` as a scene of family ``name`` for a study: None if it reads, else the one sentence that
    refuses it (an error of faultslip's own); anything else, a traceback's exception, propagates. The fuzzing
    half of the conformance check (``tests/capabilities/contract/test_families.py`` feeds it hypothesis's texts)."""
    family = load(name)
    try:
        scene = family.read_scene(text, "fuzzed.toml", None)
        cells = cells_of(family, scene)
        study = Study(name="fuzz", scene=scene, dims={}, method="auto", tolerance=cells.default_tolerance,
                      family=family)
        cells.parameters(scene)
        cells.check(study, "[study] in fuzz:", "fuzz")
    except FaultslipError as exc:
        return str(exc)
    return None
