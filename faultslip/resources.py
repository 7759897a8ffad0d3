"""Locate the bundled ``data/`` and ``configs/`` directories.

In a wheel they are installed as ``faultslip/_bundled/{data,configs}``; in a
source checkout (editable install or running from the tree) they are the
top-level directories of the repository.
"""

from __future__ import annotations

import csv
from pathlib import Path

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    import tomli as tomllib

from .errors import InputError

_PACKAGE = Path(__file__).resolve().parent


def bundled_dir(kind: str) -> Path:
    """Directory of bundled ``"data"`` or ``"configs"``."""
    for candidate in (_PACKAGE / "_bundled" / kind, _PACKAGE.parent / kind):
        if candidate.is_dir():
            return candidate
    raise FileNotFoundError(f"bundled {kind}/ directory not found next to {_PACKAGE}")


def data_path(name: str) -> Path:
    return bundled_dir("data") / name


def config_path(name: str) -> Path:
    return bundled_dir("configs") / name


def split_header(column: str) -> tuple[str, str | None]:
    """``"normal_load (lbf)"`` -> ``("normal_load", "lbf")``; no unit -> None."""
    column = column.strip()
    if column.endswith(")") and " (" in column:
        name, unit = column[:-1].split(" (", 1)
        return name.strip(), unit.strip()
    return column, None


def read_unit_csv(path, label: str):
    """A user CSV with ``name (unit)`` headers: ``(header, rows)``, rows as ``(line number, cells)``.

    Every problem becomes one :class:`InputError` sentence naming ``label`` (e.g. "segment table
    x.csv") and the row: unreadable file, empty file, invalid CSV, wrong number of fields.
    """
    from .errors import InputError

    try:
        handle = open(path, newline="", encoding="utf-8")
    except OSError as exc:
        raise InputError(f"cannot read {label}: {exc}") from None
    with handle:
        try:
            reader = csv.reader(handle)
            try:
                header = [split_header(column) for column in next(reader)]
            except StopIteration:
                raise InputError(f"{label} is empty") from None
            rows = []
            for line, row in enumerate(reader, start=2):
                if not any(cell.strip() for cell in row):
                    continue
                if len(row) != len(header):
                    raise InputError(f"{label}, row {line}: {len(row)} fields, expected {len(header)}")
                rows.append((line, [cell.strip() for cell in row]))
        except (csv.Error, UnicodeDecodeError) as exc:
            raise InputError(f"{label} is not valid CSV: {exc}") from None
    return header, rows


def read_numeric_csv(path, label: str) -> dict:
    """:func:`read_unit_csv` with every cell a number: ``{name: (values, unit)}``."""
    import numpy as np

    from .errors import InputError

    header, rows = read_unit_csv(path, label)
    columns = {name: [] for name, _ in header}
    for line, cells in rows:
        for (name, _), cell in zip(header, cells):
            try:
                columns[name].append(float(cell))
            except ValueError:
                raise InputError(f"{label}, row {line}: {name} {cell!r} is not a number") from None
    return {name: (np.array(columns[name]), unit) for name, unit in header}


def read_table(path: Path) -> list[dict[str, tuple[str, str | None]]]:
    """Rows of a bundled CSV as ``{name: (text, unit)}``, text kept as printed."""
    with open(path, newline="", encoding="utf-8") as handle:
        reader = csv.reader(handle)
        header = [split_header(column) for column in next(reader)]
        rows = []
        for row in reader:
            if not row:
                continue
            rows.append({name: (text.strip(), unit) for (name, unit), text in zip(header, row)})
    return rows


def parse_toml(text: str, source: str) -> dict:
    """Parse TOML text; a syntax error becomes one :class:`InputError` naming ``source``."""
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{source} is not valid TOML: {exc}") from None
