"""Locate the bundled ``data/`` and ``configs/`` directories.

In a wheel they are installed as ``faultslip/_bundled/{data,configs}``; in a
source checkout (editable install or running from the tree) they are the
top-level directories of the repository.
"""

from __future__ import annotations

import csv
from pathlib import Path

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
