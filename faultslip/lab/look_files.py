"""xlook's binary data files: what Penn State's biax and many friction machines write (issue 46, item 1).

The layout, as xlook writes it (documented by pylook, Leeman Geophysical, BSD-3; nothing of its code is used):

* a 36-byte header: the experiment's name (20 bytes, NUL-terminated), then big-endian 32-bit integers: the number
  of records, the number of columns, and two fields no longer used (sweep, date);
* 16 or 32 column headers of 84 bytes each: the name (13 bytes), the unit (13), an unused integer, an unused
  50-byte comment, and the column's number of records (big-endian); a column named ``no_val...`` is empty;
* the data, column after column: 4-byte big-endian floats (16- and 32-column files of older machines) or 8-byte
  little-endian doubles (32-column files of newer ones).

Which of the three layouts a file has follows from its size, the only thing that tells them apart; a file that
matches none is refused in one sentence, as are a header that claims more than the file holds, and a column whose
length differs from the records'. The bytes come through the reader gate (:func:`faultslip.io.gate.read_bytes`).

xlook also exports a run as text (its ``type`` command, read by Leeman's biaxread; :func:`parse_look_ascii`):

* ``number of records = N``;
* a line of column labels (``col 1  col 2 ...``), one a column;
* the columns' names and then their units, each in 12-character fields after a 5-character margin (``.`` for
  none);
* each column's number of records (``N recs``);
* the rows: the record's number, then one value a column.

:func:`read_look` reads either kind, by the first bytes.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from faultslip.errors import InputError
from faultslip.io import gate
from faultslip.units import registry
from faultslip.datasets import ToXarray

HEADER_BYTES = 36
COLUMN_HEADER_BYTES = 84
#: (header columns, bytes per value, numpy dtype) of each generation of the format
LAYOUTS = ((16, 4, ">f4"), (32, 4, ">f4"), (32, 8, "<f8"))


@dataclass
class LookFile(ToXarray):
    """An xlook data file: its name, its columns (name -> float64 array) in file order, and their units."""

    name: str
    columns: dict
    units: dict
    path: str = ""
    layout: tuple = ()
    notes: list = field(default_factory=list)

    @property
    def records(self) -> int:
        """The number of records (rows) of every column."""
        return len(next(iter(self.columns.values()))) if self.columns else 0

    def to_dataset(self):
        """The file as CF netCDF: one variable a column on dimension ``record``, its name as ``long_name``, its unit as
        ``units`` where udunits reads it, the file's own unit kept as ``xlook_units``."""
        import xarray as xr  # heavy: imported where used

        data = {}
        for index, (name, values) in enumerate(self.columns.items()):
            key = "".join(c if c.isalnum() or c == "_" else "_" for c in name).strip("_") or f"column_{index}"
            key = key if key not in data else f"{key}_{index}"
            unit = self.units.get(name, "")
            data[key] = ("record", values, {"long_name": name, "units": cf_unit(unit), "xlook_units": str(unit)})
        return xr.Dataset(data, coords={"record": ("record", np.arange(self.records), {"units": "1"})},
                          attrs={"title": f"xlook data file {self.path or self.name}", "experiment": self.name,
                                 "Conventions": "CF-1.8"})


_UNITS = {".": "1", "mic": "micron", "microns": "micron", "sec": "s", "msec": "ms", "bit": "1", "bits": "1", "d": "1",
          "": "1", "None": "1"}


def cf_unit(unit) -> str:
    """An xlook unit as udunits reads it (``.`` a ratio is ``1``, ``mic`` is ``micron``); ``1`` where pint reads
    none."""
    text = _UNITS.get(str(unit), str(unit))
    try:  # the one unit parser (pint): is the unit one it reads?
        registry().Unit(text)
        return text
    except Exception:  # pint's errors are many kinds; an unread unit is kept as xlook_units, "1" here
        return "1"



def _text(raw: bytes) -> str:
    """A fixed-width field: up to its first NUL, decoded as Latin-1 (old machines wrote 8-bit ASCII), stripped."""
    return raw.split(b"\x00", 1)[0].decode("latin-1").strip()


def parse_look(data: bytes, source: str = "<look file>") -> LookFile:
    """An xlook binary data file from its bytes.

    Parameters
    ----------
    data : bytes
        The whole file.
    source : str
        Its name, for messages.

    Returns
    -------
    LookFile
        Every column with data, in file order, as float64, with its unit as the file states it.
    """
    if len(data) < HEADER_BYTES:
        raise InputError(f"{source} is {len(data)} bytes, too short for an xlook data file's 36-byte header")
    name = _text(data[:20])
    records, count = (int(v) for v in np.frombuffer(data[20:28], ">i4"))
    if not (0 < count <= 32 and 0 < records < 2**31):
        raise InputError(f"{source} is not an xlook data file: its header claims {records} records in {count} "
                         "columns (1 to 32 columns)")
    layout = next((candidate for candidate in LAYOUTS
                   if len(data) == HEADER_BYTES + COLUMN_HEADER_BYTES * candidate[0] + candidate[1] * records * count),
                  None)
    if layout is None:
        raise InputError(f"{source} is {len(data)} bytes, which fits no xlook layout for {records} records in {count} "
                         "columns (16 or 32 column headers, 4- or 8-byte values): truncated, or not an xlook file")
    slots, width, dtype = layout
    headers = []
    for slot in range(slots):
        start = HEADER_BYTES + COLUMN_HEADER_BYTES * slot
        column, unit = _text(data[start:start + 13]), _text(data[start + 13:start + 26])
        length = int(np.frombuffer(data[start + 80:start + 84], ">i4")[0])
        if column and not column.startswith("no_val"):
            headers.append((column, unit, length))
    if len(headers) != count:
        raise InputError(f"{source} names {len(headers)} columns in its headers but says it has {count}")
    columns, units, offset = {}, {}, HEADER_BYTES + COLUMN_HEADER_BYTES * slots
    for column, unit, length in headers:
        if length != records:
            raise InputError(f"{source}: column {column!r} has {length} records, the file {records}")
        if column in columns:
            raise InputError(f"{source}: two columns are named {column!r}")
        values = np.frombuffer(data, dtype, records, offset).astype(np.float64)
        offset += width * records
        columns[column], units[column] = values, unit
    return LookFile(name, columns, units, source, layout)


ASCII_MARK = b"number of records"
#: the width of a name or unit field in an ASCII export, after its margin
ASCII_FIELD, ASCII_MARGIN = 12, 5


def _fields(line: str, count: int) -> list:
    """``count`` fixed-width fields of an ASCII export's header line (names or units), stripped."""
    body = line[ASCII_MARGIN:]
    return [body[ASCII_FIELD * i:ASCII_FIELD * (i + 1)].strip() for i in range(count)]


def parse_look_ascii(text: str, source: str = "<look export>") -> LookFile:
    """An xlook ASCII export (see the module) from its text.

    Parameters
    ----------
    text : str
        The whole file.
    source : str
        Its name, for messages.

    Returns
    -------
    LookFile
        Every column, in file order, as float64, with its unit (an empty string for xlook's ``.``).
    """
    lines = text.splitlines()
    if len(lines) < 5 or not lines[0].strip().startswith("number of records"):
        raise InputError(f"{source} is not an xlook ASCII export: it must open with 'number of records = N' and four "
                         "header lines")
    try:
        records = int(lines[0].split("=", 1)[1])
    except (IndexError, ValueError):
        raise InputError(f"{source}: its first line must read 'number of records = N', got {lines[0].strip()!r}") \
            from None
    count = lines[1].split().count("col")
    if not (0 < count <= 32 and 0 < records < 2**31):
        raise InputError(f"{source} is not an xlook ASCII export: {records} records in {count} columns (1 to 32)")
    names, units = _fields(lines[2], count), _fields(lines[3], count)
    lengths = lines[4].split("recs")
    if any(not name for name in names) or len(set(names)) != count:
        raise InputError(f"{source}: its third line must name {count} different columns, 12 characters each after "
                         f"a margin of 5; got {names}")
    try:
        lengths = [int(part) for part in lengths if part.strip()]
    except ValueError:
        raise InputError(f"{source}: its fifth line must give each column's records as 'N recs'") from None
    if len(lengths) != count or any(length != records for length in lengths):
        raise InputError(f"{source}: every one of its {count} columns must have the file's {records} records, "
                         f"got {lengths}")
    rows = [line for line in lines[5:] if line.strip()]
    if len(rows) != records:
        raise InputError(f"{source} says it holds {records} records but has {len(rows)} rows of data")
    try:
        table = np.array([row.split() for row in rows], dtype=np.float64)
    except ValueError:
        bad = next(i for i, row in enumerate(rows) if len(row.split()) != count + 1 or not _numeric(row))
        raise InputError(f"{source}: data row {bad + 1} must hold the record's number and {count} numbers, got "
                         f"{rows[bad].strip()[:60]!r}") from None
    if table.ndim != 2 or table.shape[1] != count + 1:
        raise InputError(f"{source}: every data row must hold the record's number and {count} numbers")
    columns = {name: np.ascontiguousarray(table[:, i + 1]) for i, name in enumerate(names)}
    return LookFile("", columns, {name: "" if unit == "." else unit for name, unit in zip(names, units)}, source,
                    ("ascii",))


def _numeric(row: str) -> bool:
    try:
        [float(value) for value in row.split()]
    except ValueError:
        return False
    return True


def read_look(path) -> LookFile:
    """Read an xlook data file, binary or an ASCII export, through the reader gate.

    Parameters
    ----------
    path : str or path
        The file (``configs/p655intact100l``, a Penn State biax run).

    Returns
    -------
    LookFile
        Its columns and units.
    """
    data = gate.read_bytes(path, "xlook data file")
    if data.lstrip()[:len(ASCII_MARK)] == ASCII_MARK:
        with gate.decoding(path, "xlook ASCII export", "UTF-8 text"):
            text = data.decode("utf-8")
        return parse_look_ascii(text, Path(path).name)
    return parse_look(data, Path(path).name)
