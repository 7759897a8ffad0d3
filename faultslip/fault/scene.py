"""Scenes: TOML files that describe a fault or a laboratory slider.

A scene states its units: every dimensional value is a string such as
``"13 mi"``; a bare number where a dimension is needed is rejected, and so is
any key the schema does not know (with the nearest allowed names).

.. code-block:: toml

    [scene]
    kind = "fault"                 # or "lab"
    name = "San Andreas fault, 1906"

    [fault]
    lithology = "granodiorite_water"
    shear_modulus = "0.25e6 bar"
    zone_width = "13 mi"
    shear_stress = "250 bar"
    slip_rate = "2 in/yr"

    [sources]
    zone_width = "seed 003 §5-2, its reference 40"
"""

from __future__ import annotations

import difflib
from dataclasses import dataclass, field
from pathlib import Path

from faultslip import ranges
from faultslip.contract.scenes import scene_source
from faultslip.errors import InputError
from faultslip.io.resources import config_path, parse_toml, read_text_file, resolve_path, scene_document
from faultslip.dynamics.methods import DEFAULT_TOLERANCE, solve
from faultslip.dynamics.spring_slider.slider import SliderSystem
from faultslip.fault.rate_state_fault import FAULT_QUANTITIES, estimate_rate_state_fault
from faultslip.fault.scaling import Fault
from faultslip.friction.materials import resolve_material
from faultslip.friction.rate_state import RateStateLaw
from faultslip.friction.laws import ConstantKinetic, ConstantStatic, LinearKinetic, PolynomialKinetic, TimeOfStickLaw
from faultslip.io.geo import parse_trace
from faultslip.units import registry, to_si, to_si_scalar

#: Allowed keys of each table; value is the unit kind (None: a plain value).
SCHEMA: dict[str, dict[str, str | None]] = {
    "scene": {"kind": None, "name": None, "description": None},
    "fault": {
        "lithology": None,
        "shear_modulus": "pressure",
        "zone_width": "length",
        "normal_stress": "pressure",
        "shear_stress": "pressure",
        "slip_rate": "speed",
        "mu_so": "dimensionless",
        "mu_m": "dimensionless",
        "b": "dimensionless",
        "d": "dimensionless",
        "rupture_length": "length",
        "seismogenic_depth": "length",
        "dip": "dimensionless",  # degrees (default 90)
        "rake": "dimensionless",  # degrees (default 180)
        "damping_ratio": "dimensionless",
        "radiation_damping": None,
        "density": "density",
        "shear_wave_speed": "speed",
        "observed_slip": "length",
        # the fault's surface trace, "lon lat; lon lat; ..." (degrees): where its catalog events are
        "trace": "trace",
    },
    "lab": {
        "preset": None,
        "platform_speed": "speed",
        "loading_rate": "rate",
        "damping_ratio": "dimensionless",
        "kinetic_slope": "slowness",
        "normal_load": "force",
        "stiffness": "stiffness",
    },
    "friction": {
        "static": "choice",
        "mu_s": "dimensionless",
        "mu_lower": "dimensionless",
        "mu_upper": "dimensionless",
        "growth_rate": "rate",
        "kinetic": "choice",
        "kinetic_slope": "slowness",
        "polynomial": "list",
        "polynomial_speed_unit": "unit",
        # law = "rate_state": a fault's friction is rate-and-state (docs/rate_state.md)
        "law": "choice",
        "a": "dimensionless",
        "b": "dimensionless",
        "critical_slip": "length",
        "mu0": "dimensionless",
        "reference_speed": "speed",
        "evolution": "choice",
        "fit": None,
    },
    "simulation": {
        "cycles": "integer",
        "slip_solver": "choice",
        "rtol": "dimensionless",
        "samples_per_slip": "integer",
        "horizon_periods": "integer",
    },
    "method": {"name": "choice", "tolerance": "dimensionless"},
    "sources": {},  # free text: any key, string values
}
METHOD_NAMES = ("auto", "closed_form", "exact_cycle", "simulate", "quasi_harmonic_averaging", "event_driven_DOP853",
                "event_driven_RK45",
                "event_driven_LSODA", "event_driven_Radau")
CHOICES = {
    ("method", "name"): METHOD_NAMES,
    ("friction", "static"): ("rate", "constant", "time_of_stick"),
    ("friction", "kinetic"): ("constant", "linear", "polynomial"),
    ("friction", "law"): ("seed", "rate_state"),
    ("friction", "evolution"): ("aging", "slip"),
    ("simulation", "slip_solver"): ("auto", "analytic", "RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA"),
}
SCENE_KINDS = ("fault", "lab")

DEFAULT_SCENE = "san_andreas_1906.toml"


@dataclass
class Scene:
    """A parsed, validated scene. ``text`` is the file as read (for provenance)."""

    kind: str
    name: str
    description: str
    tables: dict
    sources: dict = field(default_factory=dict)
    path: Path | None = None
    text: str = ""
    #: how the argument was resolved, e.g. "bundled scene san_andreas_1906.toml (no file of that name here)"
    origin: str = ""

    @property
    def fault_inputs(self) -> dict:
        inputs = {k: v for k, v in self.tables.get("fault", {}).items() if k not in ("observed_slip", "trace")}
        inputs.setdefault("name", self.name)
        return inputs

    @property
    def rate_state(self) -> bool:
        """Whether the scene's friction is rate-and-state (``[friction] law = "rate_state"``)."""
        return self.tables.get("friction", {}).get("law", "seed") == "rate_state"

    @property
    def family(self) -> str:
        """The model family of this scene (:func:`faultslip.contract.family_of`): a fault with rate-and-state
        friction is one rate-and-state block, whatever the shape of its file."""
        return "rate_state_slider" if self.rate_state else "spring_slider"

    def rate_state_law(self):
        """The ``[friction]`` table's rate-and-state law: a registry ``fit`` or a, b, critical_slip (SI)."""
        spec = self.tables.get("friction", {})
        seed_keys = sorted(set(spec) & {"static", "mu_s", "mu_lower", "mu_upper", "growth_rate", "kinetic",
                                        "kinetic_slope", "polynomial", "polynomial_speed_unit"})
        if seed_keys:
            raise InputError(f"[friction] in {self.name} has law = \"rate_state\" and the seed-law key "
                             f"{seed_keys[0]!r}; a scene's friction is one or the other")
        if "fit" in spec:
            if set(spec) - {"law", "fit"}:
                raise InputError(f"[friction] in {self.name} names a fit; give its parameters there, not here")
            choice = resolve_material(spec["fit"])
            if choice.rate_state is None:
                raise InputError(f"[friction] fit {spec['fit']!r} in {self.name} is not a rate-and-state fit "
                                 "(faultslip fit --law rate-state ... --name NAME)")
            return choice.rate_state, choice.rate_state_entry
        missing = [key for key in ("a", "b", "critical_slip") if key not in spec]
        if missing:
            raise InputError(f"[friction] in {self.name} with law = \"rate_state\" needs {', '.join(missing)} "
                             "(or fit = NAME)")
        law = RateStateLaw(a=float(spec["a"]), b=float(spec["b"]),
                           critical_slip=to_si_scalar(spec["critical_slip"], "length", "critical_slip"),
                           mu0=float(spec.get("mu0", 0.6)),
                           reference_speed=to_si_scalar(spec.get("reference_speed", "1 um/s"), "speed",
                                                        "reference_speed"),
                           evolution=spec.get("evolution", "aging"), source=self.sources.get("friction", "scene"))
        return law, None

    def rate_state_fault_values(self, law=None, require_modulus: bool = True) -> tuple[dict, object]:
        """A rate-and-state fault scene's ``[fault]`` quantities in SI by Fault field name, and the seed-law
        :class:`Fault` to put beside it (its lithology or mu_so and mu_m, radiation-damped), or None.

        ``shear_modulus`` comes from the lithology where the scene gives none (unless
        ``require_modulus`` is false: a study may sweep it, or take it from a fit).
        """
        inputs = {k: v for k, v in self.fault_inputs.items() if k not in ("name", "radiation_damping", "damping_ratio")}
        seed_law = None
        if "lithology" in inputs or {"mu_so", "mu_m"} <= set(inputs):
            seed_law = self.fault().with_(radiation_damping=True)
        values = {key: to_si_scalar(value, FAULT_QUANTITIES[key][0], key.replace("_", " "))
                  for key, value in inputs.items() if key in FAULT_QUANTITIES}
        if "shear_modulus" not in values and seed_law is not None:
            values["shear_modulus"] = seed_law.shear_modulus
        if require_modulus and "shear_modulus" not in values:
            raise InputError(f"[fault] in {self.name} needs shear_modulus (or a lithology that has one)")
        return values, seed_law

    @property
    def trace(self):
        """The ``[fault] trace`` as an (n, 2) array of (lon, lat) degrees, or None."""
        text = self.tables.get("fault", {}).get("trace")
        return None if text is None else parse_trace(text, f"[fault] trace in {self.name}")

    @property
    def observed_slip(self):
        return self.tables.get("fault", {}).get("observed_slip")

    def fault(self):

        missing = [key for key in ("zone_width", "slip_rate") if key not in self.tables.get("fault", {})]
        if missing:
            raise InputError(f"[fault] in {self.name} needs {' and '.join(missing)}")
        return Fault(**self.fault_inputs)

    @property
    def method(self) -> str:
        return self.tables.get("method", {}).get("name", "auto")

    @property
    def tolerance(self) -> float:

        return ranges.check_tolerance(self.tables.get("method", {}).get("tolerance", DEFAULT_TOLERANCE),
                                      f"[method] in {self.name}")

    @property
    def simulation(self) -> dict:
        """Settings of the ``[simulation]`` table (keyword arguments of :func:`faultslip.dynamics.spring_slider.simulate.simulate`)."""
        settings = dict(self.tables.get("simulation", {}))
        if "rtol" in settings:
            settings["rtol"] = float(settings["rtol"])
        return settings

    def slider(self):
        """The scene's :class:`~faultslip.dynamics.spring_slider.slider.SliderSystem`, with any ``[friction]`` laws applied."""
        if self.rate_state:
            raise InputError(f"{self.name} has rate-and-state friction: 'faultslip run' gives its cycles, and "
                             "'faultslip rate-state cycles' or 'simulate' take a rate-state scene "
                             "(configs/rsf_block_bp1.toml)")

        if self.kind == "fault":
            system = SliderSystem.from_fault(self.fault())
        else:
            lab = dict(self.tables["lab"])
            preset = lab.pop("preset")
            system = SliderSystem.from_preset(preset, **lab)
        return apply_friction(system, self.tables.get("friction", {}), self.name)


#: the families whose scenes this reader takes (a scene names its family, or is one of these by its tables)
SLIDER_FAMILIES = ("spring_slider", "rate_state_slider")


def _suggest(key: str, allowed) -> str:
    close = difflib.get_close_matches(key, list(allowed), n=3, cutoff=0.6)
    return f"did you mean {', '.join(close)}? " if close else ""


def parse_scene(text: str, source: str = "<scene>", path: Path | None = None) -> Scene:
    """Parse and validate scene TOML text. Raises :class:`InputError` naming the offending key."""
    document = parse_toml(text, source)
    friction = document.get("friction")
    if isinstance(friction, dict) and friction.get("law") == "nanoscale":
        raise InputError(f"{source} is a nanoscale scene (seed 001): 'faultslip run', 'simulate' and 'nanoscale' take "
                         "it; studies and maps take seed-law or rate-and-state scenes")
    family = document.get("family")
    if isinstance(family, str) and family not in SLIDER_FAMILIES:
        raise InputError(f"{source} is a {family} scene; this reads a one-block scene (seed law or rate and state), "
                         "and 'faultslip run' takes every family's")
    for table, content in document.items():
        if table == "family" and isinstance(content, str):  # the model family's name (faultslip.models)
            continue
        if table not in SCHEMA:
            what = f"table [{table}]" if isinstance(content, dict) else f"key {table} outside any table"
            raise InputError(
                f"unknown {what} in {source}; {_suggest(table, SCHEMA)}allowed tables: {', '.join(SCHEMA)}"
            )
        if not isinstance(content, dict):
            raise InputError(f"{table} in {source} must be a table [{table}], got a value")
        allowed = SCHEMA[table]
        for key, value in content.items():
            if table == "sources":
                if not isinstance(value, str):
                    raise InputError(f"[sources] {key} in {source} must be a string citation")
                continue
            if key not in allowed:
                raise InputError(
                    f"unknown key {key!r} in [{table}] of {source}; {_suggest(key, allowed)}"
                    f"allowed: {', '.join(allowed)}"
                )
            _check_value(table, key, value, allowed[key], source)

    scene_table = document.get("scene", {})
    kind = scene_table.get("kind")
    if kind not in SCENE_KINDS:
        raise InputError(f"[scene] kind in {source} must be one of {', '.join(SCENE_KINDS)}, got {kind!r}")
    if kind not in document:
        raise InputError(f"{source} has kind = {kind!r} but no [{kind}] table")
    other = "lab" if kind == "fault" else "fault"
    if other in document:
        raise InputError(f"{source} has kind = {kind!r} but also a [{other}] table; a scene is one or the other")
    if kind == "lab" and "preset" not in document["lab"]:
        raise InputError(f"[lab] in {source} needs a preset (see 'faultslip materials')")
    return Scene(
        kind=kind,
        name=scene_table.get("name", Path(source).stem),
        description=scene_table.get("description", ""),
        tables={k: v for k, v in document.items() if k not in ("scene", "sources")},
        sources=document.get("sources", {}),
        path=path,
        text=text,
    )


def _check_value(table, key, value, kind, source):

    where = f"[{table}] {key} in {source}"
    if kind == "choice":
        allowed = CHOICES[(table, key)]
        if value not in allowed:
            raise InputError(f"{where} must be one of {', '.join(allowed)}; got {value!r}")
        return
    if kind == "integer":
        if not isinstance(value, int) or isinstance(value, bool) or not 1 <= value <= 10**12:
            raise InputError(f"{where} must be a whole number from 1 to 1e12, got {value!r}")
        return
    if kind == "list":
        if not isinstance(value, list) or not value or not all(isinstance(c, (int, float)) and not isinstance(c, bool) for c in value):
            raise InputError(f"{where} must be a list of numbers (coefficients in increasing powers), got {value!r}")
        return
    if kind == "trace":
        if not isinstance(value, str):
            raise InputError(f"{where} must be a string of vertices \"lon lat; lon lat; ...\" in degrees, got {value!r}")
        parse_trace(value, where)
        return
    if kind == "unit":
        try:
            ok = registry().Quantity(1, value).dimensionality == registry().get_dimensionality("[length]/[time]")
        except Exception:
            ok = False
        if not ok:
            raise InputError(f"{where} must be a speed unit such as \"m/s\" or \"in/s\", got {value!r}")
        return
    if kind is None:
        if key == "radiation_damping":
            if not isinstance(value, bool):
                raise InputError(f"{where} must be true or false, got {value!r}")
        elif not isinstance(value, str):
            raise InputError(f"{where} must be a string, got {value!r}")
        return
    if kind != "dimensionless" and not isinstance(value, str):
        raise InputError(f"{where} must state its units as a string, e.g. {key} = \"{value} <unit>\"; got {value!r}")
    ranges.check(key, to_si_scalar(value, kind, where), where)  # raises with the key and file named


def apply_friction(system, spec: dict, name: str = "scene"):
    """Replace a slider's friction laws as a scene's ``[friction]`` table says (SI after parsing)."""

    if not spec:
        return system
    changes = {}
    static = spec.get("static", "rate")
    if static == "constant":
        _need(spec, ("mu_s",), "static = \"constant\"", name)
        changes["static_law"] = ConstantStatic(to_si(spec["mu_s"], "dimensionless", "mu_s"))
    elif static == "time_of_stick":
        _need(spec, ("mu_lower", "mu_upper", "growth_rate"), "static = \"time_of_stick\"", name)
        changes["static_law"] = TimeOfStickLaw(
            to_si(spec["mu_lower"], "dimensionless", "mu_lower"), to_si(spec["mu_upper"], "dimensionless", "mu_upper"),
            to_si(spec["growth_rate"], "rate", "growth_rate"))
    mu_m = system.mu_m if static != "time_of_stick" else changes["static_law"].mu_lower
    kinetic = spec.get("kinetic", "constant" if "kinetic_slope" not in spec else "linear")
    if kinetic == "constant":
        changes["kinetic_law"] = ConstantKinetic(mu_m)
    elif kinetic == "linear":
        _need(spec, ("kinetic_slope",), "kinetic = \"linear\"", name)
        changes["kinetic_law"] = LinearKinetic(mu_m, to_si(spec["kinetic_slope"], "slowness", "kinetic_slope"))
    elif kinetic == "polynomial":
        _need(spec, ("polynomial",), "kinetic = \"polynomial\"", name)
        unit = registry().Quantity(1, spec.get("polynomial_speed_unit", "m/s")).to("m/s").magnitude
        changes["kinetic_law"] = PolynomialKinetic([c / unit**k for k, c in enumerate(spec["polynomial"])])
    updated = system.with_(**changes)
    law = updated.static_law
    highest = float(law.mu_upper if hasattr(law, "mu_upper") else law.limit(0.0))
    if not updated.mu_m < highest:
        raise InputError(f"[friction] in {name}: kinetic friction at rest, {updated.mu_m:.4g}, is not below the "
                         f"highest static friction, {highest:.4g}; static friction is at least kinetic, so such a "
                         "slider never sticks and slips")
    return updated


def _need(spec, keys, what, name):
    missing = [key for key in keys if key not in spec]
    if missing:
        raise InputError(f"[friction] with {what} in {name} needs {', '.join(missing)}")


def read_slider_scene(path_or_name=None) -> Scene:
    """Load a scene from a path, or a bundled scene by bare file name (default: the 1906 scene).

    A bundled scene is used only for a bare name with no such file here; ``Scene.origin`` says so.

    Parameters
    ----------
    path_or_name : str or path, optional
        A scene file or a bundled scene's name.

    Returns
    -------
    Scene
    """
    if isinstance(path_or_name, Scene):  # loaded already
        return path_or_name
    if path_or_name is None:
        path, origin = config_path(DEFAULT_SCENE), f"bundled scene {DEFAULT_SCENE} (the default)"
    else:
        path, origin = resolve_path(path_or_name, "scene")
    text = read_text_file(path, "scene file")
    scene = parse_scene(text, source=path.name, path=path)
    scene.origin = origin
    return scene


def fault_scene(name: str = "fault", **quantities) -> Scene:
    """A fault scene from its quantities as keywords with units, read as a scene file's ``[fault]`` table is.

    Parameters
    ----------
    name : str
        The scene's name.
    **quantities
        The ``[fault]`` table's keys: ``lithology``, ``zone_width="13 mi"``, ``shear_stress="250 bar"`` or
        ``normal_stress``, ``slip_rate="2 in/yr"``, ``shear_modulus``, ``rupture_length``, ``seismogenic_depth``,
        the seed law's ``mu_so``, ``mu_m``, ... Values are strings with units or pint Quantities.

    Returns
    -------
    Scene
        A fault scene (``kind = "fault"``), checked as a file's would be.
    """
    def plain(value):
        return f"{value.magnitude!r} {value.units}" if hasattr(value, "magnitude") and hasattr(value, "units") \
            else value

    fault = {key: plain(value) for key, value in quantities.items() if value is not None}
    scene = parse_scene({"scene": {"kind": "fault", "name": name}, "fault": fault}, "the keywords")
    scene.origin = "a fault given as keywords"
    return scene


def has_friction_law(argument, law: str) -> bool:
    """Whether a scene argument's ``[friction]`` names ``law``; False for anything unreadable."""
    friction = (scene_document(argument) or {}).get("friction")
    return isinstance(friction, dict) and friction.get("law") == law


def load_law_scene(path, what: str, parser):
    """Resolve, read and parse a scene of one friction law with ``parser(text, source)``; the bundled origin,
    if any, goes into the notes (the parser's third result)."""
    text, source, _, origin = scene_source(path, what)
    model, settings, notes = parser(text, source)
    if origin:
        notes["origin"] = origin
    return model, settings, notes


def _run_rate_state(scene: Scene):
    """A fault scene with rate-and-state friction: cycles, K / K_c, and the scene's seed law beside."""
    return estimate_scene_rate_state(scene).report(f"faultslip rate-and-state fault: {scene.name}")


def estimate_scene_rate_state(scene: Scene, cycles: int = 5, record: bool = False):
    """The :class:`RateStateFaultEstimate` of a fault scene with ``[friction] law = "rate_state"``."""
    if scene.kind != "fault":
        raise InputError(f"{scene.name}: [friction] law = \"rate_state\" applies to fault scenes; a laboratory "
                         "slider under rate-and-state friction is a rate-state scene (configs/rsf_velocity_step.toml, "
                         "faultslip rate-state simulate)")
    if scene.observed_slip is not None:
        raise InputError(f"{scene.name}: observed_slip (the inverse for mu_m) belongs to the seed law, not to "
                         "rate-and-state friction")
    law, entry = scene.rate_state_law()
    values, seed_law = scene.rate_state_fault_values(law)
    modulus = values["shear_modulus"]
    normal = values.get("normal_stress") or values["shear_stress"] / law.mu0
    estimate = estimate_rate_state_fault(law, shear_modulus=modulus, zone_width=values["zone_width"],
                                         normal_stress=normal, plate_rate=values["slip_rate"],
                                         density=values.get("density", 2700.0),
                                         shear_wave_speed=values.get("shear_wave_speed"), entry=entry,
                                         rupture_length=values.get("rupture_length"),
                                         seismogenic_depth=values.get("seismogenic_depth"), seed_law=seed_law,
                                         cycles=cycles, record=record)
    if "shear_stress" in values and "normal_stress" not in values:
        estimate.notes.append(f"sigma_n = tau / mu0 = {normal:.4g} Pa (mu0 = {law.mu0:.4g}); the seed law beside "
                              "uses tau / mu_so")
    return estimate


def check_method(method: str) -> None:
    """Refuse a method that is not one of the seed law's (:data:`METHOD_NAMES`), in one sentence: a run and its
    estimate alike."""
    if method not in METHOD_NAMES:
        raise InputError(f"method must be one of {', '.join(METHOD_NAMES)}, got {method!r}")


def run_scene(scene: Scene, method: str | None = None, tolerance: float | None = None):
    """Evaluate a scene and return its :class:`~faultslip.io.report.Report`.

    A fault scene gives the slip and recurrence estimate, or, with ``observed_slip``, the
    implied kinetic friction (seed 003 §5-2). A lab scene gives its stick-slip limit cycle. The
    method is the scene's ``[method]`` (default ``auto``: the cheapest one that meets the
    tolerance, 1e-6 relative unless the scene or caller says otherwise).

    Parameters
    ----------
    scene : Scene
        The scene.
    method : str, optional
        The seed law's method.
    tolerance : float, optional
        Relative error allowed.

    Returns
    -------
    Report
    """
    method = method or scene.method
    tolerance = scene.tolerance if tolerance is None else tolerance
    check_method(method)
    if scene.rate_state:
        if method != "auto":  # the seed law's methods: not to be accepted and then ignored
            raise InputError(f"method {method!r} is one of the seed law's; a rate-and-state fault's cycles choose "
                             "their integrator themselves (LSODA below K / K_c 0.01, dopri5 above)")
        report = _run_rate_state(scene)
    elif scene.kind == "fault":
        fault = scene.fault()
        if scene.observed_slip is not None:
            report = fault.infer_kinetic_friction(scene.observed_slip).report()
        else:
            report = fault.estimate(method=method, tolerance=tolerance).report()
    else:

        # the report shows one limit cycle: the event times of more than 1000 cycles add nothing
        solution = solve(scene.slider(), method=method, tolerance=tolerance,
                         cycles=min(int(scene.simulation.get("cycles", 200)), 1000))
        report = solution.report(f"faultslip lab cycle: {scene.name}")
    return with_scene_notes(report, scene)


def with_scene_notes(report, scene: Scene):
    """``report`` with what the scene says of itself: its description and origin first, each source last."""
    if scene.description:
        report.notes.insert(0, scene.description)
    if scene.origin:
        report.notes.insert(0, f"scene: {scene.origin}")
    for key, citation in scene.sources.items():
        report.note(f"source of {key}: {citation}")
    return report
