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

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    import tomli as tomllib

from .errors import InputError
from .resources import bundled_dir, config_path

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
        "damping_ratio": "dimensionless",
        "radiation_damping": None,
        "density": "density",
        "shear_wave_speed": "speed",
        "observed_slip": "length",
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
    "sources": {},  # free text: any key, string values
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

    @property
    def fault_inputs(self) -> dict:
        inputs = {k: v for k, v in self.tables.get("fault", {}).items() if k != "observed_slip"}
        inputs.setdefault("name", self.name)
        return inputs

    @property
    def observed_slip(self):
        return self.tables.get("fault", {}).get("observed_slip")

    def fault(self):
        from .fault import Fault

        return Fault(**self.fault_inputs)

    def slider(self):
        """The scene's :class:`~faultslip.slider.SliderSystem`."""
        from .slider import SliderSystem

        if self.kind == "fault":
            return SliderSystem.from_fault(self.fault())
        lab = dict(self.tables["lab"])
        preset = lab.pop("preset")
        return SliderSystem.from_preset(preset, **lab)


def _suggest(key: str, allowed) -> str:
    close = difflib.get_close_matches(key, list(allowed), n=3, cutoff=0.6)
    return f"did you mean {', '.join(close)}? " if close else ""


def parse_scene(text: str, source: str = "<scene>", path: Path | None = None) -> Scene:
    """Parse and validate scene TOML text. Raises :class:`InputError` naming the offending key."""
    try:
        document = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{source} is not valid TOML: {exc}") from None
    for table, content in document.items():
        if table not in SCHEMA:
            raise InputError(
                f"unknown table [{table}] in {source}; {_suggest(table, SCHEMA)}allowed tables: {', '.join(SCHEMA)}"
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
    from .units import to_si

    where = f"[{table}] {key} in {source}"
    if kind is None:
        if key == "radiation_damping":
            if not isinstance(value, bool):
                raise InputError(f"{where} must be true or false, got {value!r}")
        elif not isinstance(value, str):
            raise InputError(f"{where} must be a string, got {value!r}")
        return
    if kind != "dimensionless" and not isinstance(value, str):
        raise InputError(f"{where} must state its units as a string, e.g. {key} = \"{value} <unit>\"; got {value!r}")
    to_si(value, kind, where)  # raises with the key and file named


def load_scene(path_or_name=None) -> Scene:
    """Load a scene from a path, or a bundled scene by file name (default: the 1906 scene)."""
    if path_or_name is None:
        path = config_path(DEFAULT_SCENE)
    else:
        path = Path(path_or_name)
        if not path.exists():
            bundled = config_path(path.name if path.suffix else f"{path.name}.toml")
            if bundled.exists():
                path = bundled
            else:
                raise InputError(f"scene file {str(path_or_name)!r} does not exist (bundled scenes: {', '.join(bundled_scenes())})")
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read scene file {str(path)!r}: {exc}") from None
    return parse_scene(text, source=path.name, path=path)


def bundled_scenes() -> list[str]:
    return sorted(p.name for p in bundled_dir("configs").glob("*.toml"))


def run_scene(scene: Scene):
    """Evaluate a scene and return its :class:`~faultslip.report.Report`.

    A fault scene gives the slip and recurrence estimate, or, with
    ``observed_slip``, the implied kinetic friction (seed 003 §5-2). A lab
    scene gives the stick-slip cycle at its drive speed.
    """
    if scene.kind == "fault":
        fault = scene.fault()
        if scene.observed_slip is not None:
            report = fault.infer_kinetic_friction(scene.observed_slip).report()
        else:
            report = fault.estimate().report()
    else:
        from .closed_form import closed_form_cycle

        report = closed_form_cycle(scene.slider()).report(f"faultslip lab cycle: {scene.name}")
    if scene.description:
        report.notes.insert(0, scene.description)
    for key, citation in scene.sources.items():
        report.note(f"source of {key}: {citation}")
    return report
