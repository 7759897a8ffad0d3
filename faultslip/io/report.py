"""Results as ordered, labelled quantities: one source for JSON and text reports.

Every computing command returns a :class:`Report`. Its JSON form is one
object whose physical quantities are ``{"value": number, "units": str}`` with
SI units that pint and udunits both parse; plain fields (method names,
regimes, notes) are strings or numbers.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field

from faultslip.units import convert, quantity_json


@dataclass
class Item:
    key: str
    value: object
    units: str | None = None  # None: a plain (non-physical) field
    label: str = ""
    also: tuple[str, ...] = ()  # extra display units for the text report

    @property
    def is_quantity(self) -> bool:
        return self.units is not None


@dataclass
class Report:
    title: str
    items: list[Item] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    sections: dict[str, int] = field(default_factory=dict)  # heading -> index of its first item

    def section(self, heading: str) -> "Report":
        self.sections[heading] = len(self.items)
        return self

    def add(self, key, value, units=None, label="", also=()) -> "Report":
        self.items.append(Item(key, value, units, label or key.replace("_", " "), tuple(also)))
        return self

    def set(self, key, value) -> "Report":
        """Replace the value of an item already reported (its units and label stay)."""
        for item in self.items:
            if item.key == key:
                item.value = value
                return self
        raise KeyError(key)

    def note(self, text: str) -> "Report":
        self.notes.append(text)
        return self

    def __getitem__(self, key):
        for item in self.items:
            if item.key == key:
                return item.value
        raise KeyError(key)

    def __contains__(self, key) -> bool:
        return any(item.key == key for item in self.items)

    def to_dict(self) -> dict:
        out: dict = {"title": self.title}
        for item in self.items:
            if item.is_quantity:
                out[item.key] = quantity_json(item.value, item.units)
            else:
                out[item.key] = _plain(item.value)
        if self.notes:
            out["notes"] = list(self.notes)
        return out

    def to_json(self) -> str:
        return json.dumps(self.to_dict(), indent=2, allow_nan=False)

    def to_text(self) -> str:
        lines = [self.title, "=" * len(self.title)]
        starts = {index: heading for heading, index in self.sections.items()}
        width = max((len(item.label) for item in self.items), default=10) + 2
        for index, item in enumerate(self.items):
            if index in starts:
                lines.append("")
                lines.append(starts[index])
            lines.append(f"  {item.label:<{width}}{_format_item(item)}")
        if self.notes:
            lines.append("")
            lines.append("Notes")
            lines.extend(f"  - {text}" for text in self.notes)
        return "\n".join(lines)


def _plain(value):
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if hasattr(value, "item"):  # numpy scalar
        return _plain(value.item())
    return value


def _number(value: float) -> str:
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "n/a"
    if isinstance(value, float) and math.isinf(value):
        return "inf"
    magnitude = abs(value)
    if magnitude != 0 and (magnitude >= 1e5 or magnitude < 1e-3):
        return f"{value:.4g}"
    return f"{value:.5g}"


def _plain_text(value) -> str:
    """A plain field as a reader wants it: numbers rounded to their meaning, lists and tables one line."""
    if isinstance(value, bool) or value is None:
        return str(value)
    if isinstance(value, float):
        return _number(value)
    if hasattr(value, "item") and getattr(value, "ndim", 1) == 0:  # a numpy scalar
        return _plain_text(value.item())
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_plain_text(v) for v in value) + "]"
    if isinstance(value, dict) and set(value) == {"value", "units"}:  # a quantity inside a structured field
        return f"{_plain_text(value['value'])} {value['units']}".rstrip()
    if isinstance(value, dict):
        return ", ".join(f"{key}: {_plain_text(v)}" for key, v in value.items())
    return str(value)


def _format_item(item: Item) -> str:
    if not item.is_quantity:
        if isinstance(item.value, dict) and "summary" in item.value:  # a structured row: its one-line summary
            return str(item.value["summary"])
        return _plain_text(item.value)
    if isinstance(item.value, (list, tuple)):  # a range
        text = ("[" + ", ".join(_number(float(v)) for v in item.value) + "]"
                + (f" {item.units}" if item.units not in ("1", "") else ""))
        if item.also:
            text += "  (" + ", ".join("[" + ", ".join(_number(convert(float(v), item.units, u)) for v in item.value)
                                      + f"] {u}" for u in item.also) + ")"
        return text
    value = float(item.value)
    text = f"{_number(value)} {item.units}".rstrip()
    if item.also and math.isfinite(value):
        extra = ", ".join(f"{_number(convert(value, item.units or '', unit))} {unit}" for unit in item.also)
        text += f"  ({extra})"
    return text
