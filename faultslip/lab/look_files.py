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
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from faultslip.errors import InputError
from faultslip.io import gate

HEADER_BYTES = 36
COLUMN_HEADER_BYTES = 84
#: (header columns, bytes per value, numpy dtype) of each generation of the format
LAYOUTS = ((16, 4, ">f4"), (32, 4, ">f4"), (32, 8, "<f8"))


@dataclass
class LookFile:
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


def read_look(path) -> LookFile:
    """Read an xlook binary data file through the reader gate.

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
    return parse_look(data, Path(path).name)
