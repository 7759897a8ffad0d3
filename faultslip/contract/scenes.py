"""A scene file varied cell by cell: the scene object of families whose readers take TOML."""

from __future__ import annotations

import copy
from dataclasses import dataclass, field, replace
from pathlib import Path

from faultslip.errors import InputError
from faultslip.io.resources import parse_toml, read_text_file, resolve_path


@dataclass
class TomlScene:
    """A family's scene file with some of its values replaced (``with_values``), read by the family's own reader.

    ``parameters`` (name -> :class:`~faultslip.contract.specs.Parameter`) say where each value lives in
    the file; ``overrides`` are the replaced values as the file would write them. The family's reader
    takes :meth:`document` in place of the file's text, so a cell is checked exactly as a file is.
    """

    family: str
    text: str
    source: str
    parameters: dict
    path: Path | None = None
    overrides: tuple = ()
    origin: str = field(default="", compare=False)  # where a bundled scene came from

    @property
    def name(self) -> str:
        name = parse_toml(self.text, self.source).get("name")
        return name if isinstance(name, str) else Path(self.source).stem

    @property
    def base_dir(self):
        return None if self.path is None else Path(self.path).parent

    def document(self) -> dict:
        """The scene's TOML document with the replaced values."""
        document = copy.deepcopy(parse_toml(self.text, self.source))
        for (table, key), value in self.overrides:
            holder = document.setdefault(table, {}) if table else document
            if not isinstance(holder, dict):
                raise InputError(f"{self.source}: {table} must be a table to vary {key}")
            holder[key] = value
        return document

    def with_values(self, **values) -> "TomlScene":
        """The scene with parameters replaced, in SI (what a study sweeps)."""
        overrides = dict(self.overrides)
        for name, value in values.items():
            spec = self.parameters.get(name)
            if spec is None or spec.location is None:
                raise InputError(f"a {self.family.replace('_', '-')} scene varies "
                                 f"{', '.join(n for n, p in self.parameters.items() if p.location)}, not {name!r}")
            overrides[tuple(spec.location)] = spec.toml_value(value)
        return replace(self, overrides=tuple(overrides.items()))


def toml_reader(family: str, parameters: dict):
    """A family's ``read_scene``: its scene file as a :class:`TomlScene` (parsed once here, so a file that is
    not TOML is refused before any work)."""

    def read_scene(text: str, source: str, path=None) -> TomlScene:
        parse_toml(text, source)
        return TomlScene(family, text, source, parameters, path)

    return read_scene


def scene_source(argument, what: str):
    """``(text or document, source name, folder, origin)`` of a scene argument, for a family's reader: a file
    or a bundled scene's name is resolved and read through the gate; a :class:`TomlScene` gives its document
    with the replaced values."""
    if isinstance(argument, TomlScene):
        return argument.document(), argument.source, argument.base_dir, argument.origin
    path, origin = resolve_path(argument, what)
    return read_text_file(path, what), path.name, path.parent, origin
