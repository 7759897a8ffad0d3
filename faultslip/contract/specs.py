"""What a family declares of its inputs and outputs: units, CF names and ranges, once.

A sweep's coordinates, a study file's variables, the command line's help and the conformance
check (:func:`faultslip.testing.check_family`) all read these; nothing restates them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Parameter:
    """One input of a family's scene.

    ``kind`` is a unit kind of :mod:`faultslip.units` (``"length"``, ``"pressure"``, ``"dimensionless"``,
    ...) or ``"category"`` (a name: a lithology, a preset, an evolution law); ``unit`` is its SI unit
    (``"1"`` for a number, None for a category). ``location`` is where a scene file keeps it, as
    ``(table, key)``; ``number`` says the file writes it as a bare number (a dimensionless model's inputs)
    rather than a quantity with units.
    """

    name: str
    kind: str
    unit: str | None
    long_name: str
    location: tuple | None = None
    sweepable: bool = True
    number: bool = False

    @property
    def is_category(self) -> bool:
        return self.kind == "category"

    def attrs(self) -> dict:
        """CF attributes of this parameter as a coordinate."""
        return {"long_name": self.long_name} if self.is_category else {"units": self.unit, "long_name": self.long_name}

    def toml_value(self, value):
        """``value`` (SI) as its scene file writes it: a category's name, a bare number, or a quantity string."""
        if self.is_category:
            return str(value)
        if self.number or self.unit in (None, "1"):
            return float(value)
        return f"{float(value)!r} {self.unit}"


def parameters(table: dict, location: str | None = None, number: bool = False) -> dict:
    """:class:`Parameter` objects from ``name -> (kind, unit, long_name)``; ``location`` names the TOML table
    that holds them all (the key is the name)."""
    return {name: Parameter(name, kind, unit, long_name, None if location is None else (location, name),
                            number=number)
            for name, (kind, unit, long_name) in table.items()}


def flags_attrs(meanings, extra: dict | None = None) -> dict:
    """CF flag attributes: ``meanings`` maps each meaning to its code (int8)."""
    return {"flag_values": np.array(list(meanings.values()), dtype=np.int8), "flag_meanings": " ".join(meanings),
            "units": "1", **(extra or {})}


@dataclass(frozen=True)
class Output:
    """One output of a family's cell: what a sweep writes for it.

    ``units`` is a UDUNITS string (``"1"`` for a number); ``flags`` lists the meanings of a flag
    variable (coded 0, 1, ... in int8; the cell's value is the text its result reports, whose first
    word is the meaning); ``key`` is the name in the family's :class:`~faultslip.models.Result` where
    it differs.
    """

    name: str
    units: str
    long_name: str
    standard_name: str | None = None
    flags: tuple = ()
    key: str | None = None

    @property
    def dtype(self):
        return np.dtype(np.int8) if self.flags else np.dtype(float)

    @property
    def fill(self):
        """What a cell without a value holds."""
        return -1 if self.flags else np.nan

    def code(self, text) -> int:
        """The flag code of a reported text, by its first word (``"stick_slip (A < A_c ...)"``)."""
        word = str(text).split(" ", 1)[0]
        if word not in self.flags:
            raise ValueError(f"{self.name} {text!r} is none of the declared meanings {', '.join(self.flags)}")
        return self.flags.index(word)

    def attrs(self) -> dict:
        if self.flags:
            return flags_attrs({meaning: code for code, meaning in enumerate(self.flags)},
                               {"long_name": self.long_name})
        attrs = {"units": self.units, "long_name": self.long_name}
        if self.standard_name:
            attrs["standard_name"] = self.standard_name
        return attrs
