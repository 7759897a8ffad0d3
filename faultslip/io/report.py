"""Results as ordered, labelled quantities: one source for JSON and text reports.

Every computing command returns a :class:`Report`. Its JSON form is one
object whose physical quantities are ``{"value": number, "units": str}`` with
SI units that pint and udunits both parse; plain fields (method names,
regimes, notes) are strings or numbers.
"""

from __future__ import annotations

import json
import math
import textwrap
from dataclasses import dataclass, field

from faultslip.constants import JULIAN_YEAR
from faultslip.units import convert, quantity_json


#: Widest label column in a text report; a longer label is printed on its own line.
LABEL_WIDTH = 46
#: Width a sentence-row (a label without a value) is folded to.
LINE_WIDTH = 110


@dataclass
class Item:
    key: str
    value: object
    units: str | None = None  # None: a plain (non-physical) field
    label: str = ""
    also: tuple[str, ...] = ()  # extra display units for the text report
    error: float | None = None  # absolute uncertainty (SI): the text shows the digits it supports
    in_text: bool = True  # False: a table for the JSON, which the text report shows as a table of its own

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

    def add(self, key, value, units=None, label="", also=(), error=None, in_text: bool = True) -> "Report":
        self.items.append(Item(key, value, units, label or key.replace("_", " "), tuple(also), error, in_text))
        return self

    def set(self, key, value) -> "Report":
        """Replace the value of an item already reported (its units and label stay)."""
        for item in self.items:
            if item.key == key:
                item.value = value
                return self
        raise KeyError(key)

    def note(self, text: str) -> "Report":
        """Add a note; a note already made is not made twice."""
        if text not in self.notes:
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
        # a long title is folded like a note, its rule as long as its longest line (not the whole title)
        title = textwrap.wrap(self.title, width=LINE_WIDTH, break_on_hyphens=False) or [""]
        lines = [*title, "=" * max(len(line) for line in title)]
        starts = {index: heading for heading, index in self.sections.items()}
        width = min(max((len(item.label) for item in self.items), default=10), LABEL_WIDTH) + 2
        for index, item in enumerate(self.items):
            if index in starts:
                lines.append("")
                lines.append(starts[index])
            if not item.in_text:
                continue
            shown = _format_item(item)
            if not shown:  # a sentence of its own, folded to a readable width
                lines.extend(textwrap.wrap(item.label, width=LINE_WIDTH, initial_indent="  ",
                                           subsequent_indent="      ", break_on_hyphens=False))
            else:  # a long label takes its own line rather than widening every row; a long value is folded
                indent = " " * (width + 2)
                first = indent if len(item.label) > LABEL_WIDTH else f"  {item.label:<{width}}"
                if len(item.label) > LABEL_WIDTH:
                    lines.append(f"  {item.label}")
                lines.extend(textwrap.wrap(shown, width=max(LINE_WIDTH, width + 40), initial_indent=first,
                                           subsequent_indent=indent, break_on_hyphens=False,
                                           break_long_words=False) or [first.rstrip()])
        if self.notes:
            lines.append("")
            lines.append("Notes")
            for text in self.notes:  # folded, so that no line of a report runs past a terminal's width
                lines.extend(textwrap.wrap(text, width=LINE_WIDTH, initial_indent="  - ", subsequent_indent="    ",
                                           break_on_hyphens=False, break_long_words=False) or ["  -"])
        return "\n".join(lines)


#: Display units for text reports, chosen by magnitude (JSON and files stay SI): (SI unit) -> [(threshold on
#: |value| in SI, unit, SI per unit)], the first whose threshold the value reaches. The Julian year is the
#: astronomers' (and pint's) 365.25 days.
DISPLAY_UNITS = {
    "m": [(1e4, "km", 1e3), (1.0, "m", 1.0), (1e-3, "mm", 1e-3), (1e-6, "µm", 1e-6), (0.0, "nm", 1e-9)],
    "s": [(0.5 * JULIAN_YEAR, "yr", JULIAN_YEAR), (86400.0, "days", 86400.0), (3600.0, "h", 3600.0),
          (60.0, "min", 60.0), (1.0, "s", 1.0), (1e-3, "ms", 1e-3), (0.0, "µs", 1e-6)],
    "Pa": [(1e9, "GPa", 1e9), (1e6, "MPa", 1e6), (1e3, "kPa", 1e3), (0.0, "Pa", 1.0)],
    "m/s": [(1e-3, "m/s", 1.0), (1e-6, "µm/s", 1e-6), (0.0, "mm/yr", 1e-3 / JULIAN_YEAR)],
}


def display_unit(values, units: str | None) -> tuple[str, float]:
    """The unit a person reads ``values`` (SI, in ``units``) in, and its size in SI: µm for D_c, years for a
    recurrence, MPa for a stress; no unit for a dimensionless value."""
    if units in (None, "1", ""):
        return "", 1.0
    table = DISPLAY_UNITS.get(units)
    finite = [abs(float(v)) for v in values if v is not None and math.isfinite(float(v)) and v != 0]
    if table is None or not finite:
        return units, 1.0
    size = max(finite)
    for threshold, unit, factor in table:
        if size >= threshold:
            return unit, factor
    return units, 1.0


def significant(value: float, uncertainty: float | None = None) -> str:
    """``value`` to the digits its ``uncertainty`` (absolute, same units) supports: the uncertainty's first two
    significant figures fix the last digit shown. Without one, five significant figures."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "n/a"
    if math.isinf(value):
        return "inf" if value > 0 else "-inf"
    if uncertainty is None or not math.isfinite(uncertainty) or uncertainty <= 0:
        return _number(value)
    last = math.floor(math.log10(uncertainty)) - 1  # the decade of the uncertainty's second figure
    magnitude = abs(value)
    if magnitude >= 1e6 or (magnitude and magnitude < 1e-4):
        digits = max(1, math.floor(math.log10(magnitude)) - last + 1) if magnitude else 2
        return f"{value:.{min(digits, 17)}g}"
    return f"{value:.{min(max(-last, 0), 17)}f}"


def _plain(value):
    """A plain field for JSON: non-finite numbers are null, inside lists and tables too (JSON has no infinity)."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if hasattr(value, "item") and getattr(value, "ndim", 0) == 0:  # numpy scalar
        return _plain(value.item())
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, dict):
        return {key: _plain(v) for key, v in value.items()}
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
    if value is None:  # a value that does not exist here (no range outside a calibration; no coupling)
        return "none"
    if isinstance(value, bool):
        return str(value)
    if isinstance(value, float):
        return _number(value)
    if hasattr(value, "item") and getattr(value, "ndim", 1) == 0:  # a numpy scalar
        return _plain_text(value.item())
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_distinct(value)) + "]"
    if isinstance(value, dict) and set(value) == {"value", "units"}:  # a quantity inside a structured field
        return f"{_plain_text(value['value'])} {value['units']}".rstrip()
    if isinstance(value, dict):
        return ", ".join(f"{key}: {_plain_text(v)}" for key, v in value.items())
    return str(value)


def _distinct(values) -> list[str]:
    """A list's fields as text; numbers that differ are shown with the digits that tell them apart (an interval is
    never printed as [0.6201, 0.6201])."""
    shown = [_plain_text(v) for v in values]
    numbers = [float(v) for v in values if isinstance(v, (int, float)) and not isinstance(v, bool)]
    if len(numbers) == len(values) and len(set(numbers)) > 1 and len(set(shown)) < len(set(numbers)):
        for digits in range(6, 18):
            shown = [f"{v:.{digits}g}" for v in numbers]
            if len(set(shown)) == len(set(numbers)):
                break
    return shown


def _readable(value: float) -> bool:
    """Whether ``value`` reads without an exponent in a second unit (a lab speed is not 31557 mm/yr)."""
    return value == 0 or 1e-3 <= abs(value) < 1e4


def _format_item(item: Item) -> str:
    if not item.is_quantity:
        if isinstance(item.value, dict) and "summary" in item.value:  # a structured row: its one-line summary
            return str(item.value["summary"])
        if isinstance(item.value, dict):  # a structured row says itself in its label; JSON carries the fields
            return ""
        if item.error is not None and isinstance(item.value, float) and item.error > 0:
            return f"{significant(item.value, item.error)} ± {significant(item.error, item.error)}"
        return _plain_text(item.value)
    if isinstance(item.value, (list, tuple)) and len(item.value) == 2 and item.value[1] is None \
            and item.value[0] is not None:  # a range with no upper end
        unit, factor = display_unit([float(item.value[0])], item.units)
        return f"{significant(float(item.value[0]) / factor, None)} {unit} or more (no upper end)".replace("  ", " ")
    if isinstance(item.value, (list, tuple)):  # a range, in one display unit
        values = [float(v) if v is not None else math.nan for v in item.value]
        unit, factor = display_unit(values, item.units)
        width = max(values) - min(values) if all(math.isfinite(v) for v in values) and len(values) > 1 else None
        shown = [significant(v / factor, width / factor / 10 if width else None) for v in values]
        return " to ".join(shown) + (f" {unit}" if unit else "") if len(values) == 2 else \
            "[" + ", ".join(shown) + "]" + (f" {unit}" if unit else "")
    if item.value is None:
        return "none"
    value = float(item.value)
    if math.isnan(value):  # no value here (a period of steady sliding): no unit to read it in
        return "n/a"
    unit, factor = display_unit([value], item.units)
    error = item.error / factor if item.error is not None else None
    text = f"{significant(value / factor, error)} {unit}".rstrip()
    if error is not None and math.isfinite(error) and error > 0:
        text += f" ± {significant(error, error)}"
    extras = [u for u in item.also if u != unit and _readable(convert(value, item.units or "", u))] \
        if math.isfinite(value) else []
    if extras:
        extra = ", ".join(f"{_number(convert(value, item.units or '', u))} {u}" for u in extras)
        text += f"  ({extra})"
    return text
