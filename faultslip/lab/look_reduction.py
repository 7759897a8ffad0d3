"""xlook's reduction files ("r-files"): the commands that turn a biax run's columns into stresses, displacements
and friction (issue 46, item 1).

An r-file is a list of commands, one a line, ``#`` starting a comment, commas read as spaces, ``end`` ending it.
The columns are xlook's 32 slots: slot 0 holds the record number, and a data file's columns follow from slot 1 in
file order (``read FILE``, a file beside the r-file). The commands, as Penn State's r-files use them:

* ``math A OP B TYPE OUT NAME UNIT``: column A combined with column B (``TYPE`` ``:``) or the number B (``=``) by
  ``OP`` (``* / + -``) into slot OUT, named and with a unit;
* ``math_int A OP B TYPE OUT FIRST LAST NAME UNIT``: the same on records FIRST to LAST only; the other records keep
  column A's values;
* ``summation IN OUT NAME UNIT``: the running sum; ``power P IN OUT NAME UNIT``: the power;
* ``zero COL REC``: column COL less its value at record REC;
* ``offset_int COL FIRST LAST Y|N``: removes the step between records FIRST and LAST from LAST on, and with ``y``
  holds the records between at FIRST's value (a spike or a reset of a transducer);
* ``ec DISP LOAD OUT FIRST LAST SLOPE NAME UNIT``: the elastic correction of a displacement for the machine's
  stretch, DISP - LOAD / SLOPE on records FIRST to LAST (SLOPE the stiffness, load per displacement);
* ``strain DISP THICK OUT FIRST LAST NAME UNIT``: the shear strain accumulated over records FIRST to LAST, the sum of
  displacement increments over the layer's thickness, sum(d DISP / THICK), 0 at FIRST;
* ``r_col COL`` clears a slot; ``r_row FIRST LAST`` removes records FIRST to LAST from every column;
* ``begin``, ``com_file`` and ``end`` frame the file.

Record ranges include both ends, and a LAST of -1 is the last record. The r-files say so themselves: p655's
``r_row 86283 86283`` removes the one record its comment names ("normal stress has a zero at 86283, ax it").
pylook's interpreter reads ranges as Python slices, stopping before LAST; benchmarks/look_against_pylook.py shows
where that, and its elastic correction, differ from this reading.

A command faultslip does not know, a wrong number of arguments, a slot outside 0 to 31, a record outside the data or
a column used before it holds data is one sentence naming the line (xlook printed a warning and went on; a
reduction that silently skips a step is not one a lab can trust).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from faultslip.errors import InputError
from faultslip.io import gate
from faultslip.lab.look_files import cf_unit as _cf_unit, read_look

SLOTS = 32
_ARGUMENTS = {"math": 8, "math_int": 10, "summation": 5, "power": 6, "zero": 3, "offset_int": 5, "ec": 9,
              "strain": 8, "r_col": 2, "r_row": 3, "read": 2, "begin": 1, "com_file": 1}


@dataclass
class Reduction:
    """A reduced experiment: xlook's slots (name, unit, values), the data file read, and the commands run."""

    names: list = field(default_factory=lambda: [None] * SLOTS)
    units: list = field(default_factory=lambda: [None] * SLOTS)
    data: list = field(default_factory=lambda: [None] * SLOTS)
    source: str = ""
    commands: int = 0
    experiment: str = ""  # the data file's own name for its run (xlook's header)

    def column(self, slot: int) -> np.ndarray:
        """Slot ``slot``'s values."""
        return self.data[slot]

    def to_dataset(self):
        """The slots as CF netCDF: one variable a slot on dimension ``record``, its xlook name as ``long_name``, its
        unit as ``units`` where udunits reads it (xlook's ``.`` for a ratio is ``1``; ``mic`` is ``micron``), the
        r-file's own unit kept as ``xlook_units``."""
        import xarray as xr  # heavy: imported where used

        data = {}
        for slot, (name, unit, values) in enumerate(zip(self.names, self.units, self.data)):
            if values is None or name is None:
                continue
            key = "".join(c if c.isalnum() or c == "_" else "_" for c in name).strip("_") or f"slot_{slot}"
            if key in data:
                key = f"{key}_{slot}"
            data[key] = ("record", values, {"long_name": name, "units": _cf_unit(unit), "xlook_units": str(unit),
                                            "xlook_slot": slot})
        return xr.Dataset(data, coords={"record": ("record", np.arange(_records(self)), {"units": "1"})},
                          attrs={"title": f"xlook reduction {self.source}", "Conventions": "CF-1.8",
                                 "commands": self.commands, **({"experiment": self.experiment} if self.experiment
                                                               else {})})

    def as_dict(self) -> dict:
        """Every slot that holds data: name -> (values, unit), in slot order (a name used twice keeps its slot)."""
        out = {}
        for slot, (name, unit, values) in enumerate(zip(self.names, self.units, self.data)):
            if values is not None and name is not None:
                out[name if name not in out else f"{name}_{slot}"] = (values, unit)
        return out


def run_r_file(path) -> Reduction:
    """Run an xlook r-file (see the module) on the data file it reads.

    Parameters
    ----------
    path : str or path
        The r-file; its ``read`` command names a data file beside it.

    Returns
    -------
    Reduction
        The slots after the last command.
    """
    path = Path(path)
    text = gate.read_text(path, "xlook r-file", "config")
    return run_commands(text, path.name, base_dir=path.parent)


def run_commands(text: str, source: str = "<r-file>", base_dir=None, look=None) -> Reduction:
    """Run r-file commands from ``text``; ``look`` (a :class:`~faultslip.lab.look_files.LookFile`) stands for the
    data a ``read`` command would load.

    Parameters
    ----------
    text : str
        The r-file's text.
    source : str
        Its name in messages.
    base_dir : path, optional
        Where ``read`` finds its file.
    look : LookFile, optional
        Data already read.

    Returns
    -------
    Reduction
        The slots after the last command.
    """
    state = Reduction(source=source)
    # every line's command and its number of arguments first: a file is refused before any data is read
    lines = []
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.split("#", 1)[0].replace(",", " ").strip()
        if not line:
            continue
        words = line.split()
        command = words[0]
        where = f"{source}, line {number} ({line!r})"
        if command == "end":
            break
        if command not in _ARGUMENTS:
            raise InputError(f"{where}: faultslip does not know the command {command!r} (it runs "
                             f"{', '.join(sorted(_ARGUMENTS))} and end)")
        if len(words) != _ARGUMENTS[command]:
            raise InputError(f"{where}: {command} takes {_ARGUMENTS[command] - 1} arguments, got {len(words) - 1}")
        lines.append((command, words, where))
    if look is not None:
        _load(state, look)
    for command, words, where in lines:
        if command == "read":
            if look is None:
                folder = Path(base_dir) if base_dir is not None else Path(".")
                _load(state, read_look(folder / Path(words[1]).name))
        elif command not in ("begin", "com_file"):
            _COMMANDS[command](state, words[1:], where)
        state.commands += 1
    return state


def _load(state: Reduction, look) -> None:
    names = list(look.columns)
    if len(names) >= SLOTS:
        raise InputError(f"{look.name}: {len(names)} columns do not fit xlook's {SLOTS - 1} data slots")
    # a read replaces the data set whole (xlook's read): no slot of an earlier file, of another length, survives
    state.names[:], state.units[:], state.data[:] = [None] * SLOTS, [None] * SLOTS, [None] * SLOTS
    state.names[0], state.units[0], state.data[0] = "rec_num", "1", np.arange(look.records, dtype=float)
    state.experiment = look.name  # it travels into the netCDF, and from there into a fit's metadata
    for slot, name in enumerate(names, start=1):
        state.names[slot], state.units[slot] = name, look.units.get(name)
        state.data[slot] = np.array(look.columns[name], dtype=float)


def _slot(text: str, where: str) -> int:
    try:
        slot = int(text)
    except ValueError:
        raise InputError(f"{where}: a column is a slot number from 0 to {SLOTS - 1}, got {text!r}") from None
    if not 0 <= slot < SLOTS:
        raise InputError(f"{where}: a column is a slot number from 0 to {SLOTS - 1}, got {slot}")
    return slot


def _values(state: Reduction, text: str, where: str) -> np.ndarray:
    slot = _slot(text, where)
    if state.data[slot] is None:
        raise InputError(f"{where}: column {slot} holds no data (read the data file first, or fill the column)")
    if len(state.data[slot]) != _records(state):
        raise InputError(f"{where}: column {slot} holds {len(state.data[slot])} records where the data set has "
                         f"{_records(state)}")
    return state.data[slot]


def _number(text: str, where: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise InputError(f"{where}: {text!r} is not a number") from None


def _range(state: Reduction, first: str, last: str, where: str) -> slice:
    """Records FIRST to LAST, both included (LAST -1: the last record)."""
    records = _records(state)
    try:
        start, stop = int(first), int(last)
    except ValueError:
        raise InputError(f"{where}: a record range is two whole numbers, got {first!r} and {last!r}") from None
    stop = records - 1 if stop == -1 else stop
    if not 0 <= start <= stop < records:
        raise InputError(f"{where}: records {first} to {last} are not within the data's 0 to {records - 1}")
    return slice(start, stop + 1)


def _records(state: Reduction) -> int:
    lengths = {len(values) for values in state.data if values is not None}
    if not lengths:
        raise InputError(f"{state.source}: no data has been read")
    return max(lengths)


def _combine(state, words, where):
    first, operation, second, kind = words[:4]
    a = _values(state, first, where)
    if kind == ":":
        b = _values(state, second, where)
    elif kind == "=":
        b = _number(second, where)
    else:
        raise InputError(f"{where}: the fourth word is ':' (column with column) or '=' (column with number), got {kind!r}")
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):  # xlook divides as the machine does
        if operation == "*":
            return a, a * b
        if operation == "/":
            return a, a / b
        if operation == "+":
            return a, a + b
        if operation == "-":
            return a, a - b
    raise InputError(f"{where}: the operation is one of * / + -, got {operation!r}")


def _store(state, slot_text, name, unit, values, where):
    slot = _slot(slot_text, where)
    state.data[slot], state.names[slot], state.units[slot] = values, name, unit


def _math(state, words, where):
    _, result = _combine(state, words, where)
    _store(state, words[4], words[5], words[6], result, where)


def _math_int(state, words, where):
    column, result = _combine(state, words, where)
    span = _range(state, words[5], words[6], where)
    out = column.copy()
    out[span] = result[span]
    _store(state, words[4], words[7], words[8], out, where)


def _summation(state, words, where):
    _store(state, words[1], words[2], words[3], np.cumsum(_values(state, words[0], where)), where)


def _power(state, words, where):
    exponent = _number(words[0], where)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        _store(state, words[2], words[3], words[4], _values(state, words[1], where) ** exponent, where)


def _zero(state, words, where):
    values = _values(state, words[0], where)
    record = _range(state, words[1], words[1], where).start
    state.data[_slot(words[0], where)] = values - values[record]


def _offset_int(state, words, where):
    values = _values(state, words[0], where).copy()
    span = _range(state, words[1], words[2], where)
    first, last = span.start, span.stop - 1
    hold = words[3].lower()
    if hold not in ("y", "n"):
        raise InputError(f"{where}: the last word is y (hold the records between) or n, got {words[3]!r}")
    step = values[last] - values[first]
    if hold == "y":
        values[first:last] = values[first]
    values[last:] -= step
    state.data[_slot(words[0], where)] = values


def _ec(state, words, where):
    displacement, load = _values(state, words[0], where), _values(state, words[1], where)
    span = _range(state, words[3], words[4], where)
    stiffness = _number(words[5], where)
    if stiffness == 0:
        raise InputError(f"{where}: the elastic correction's stiffness (load per displacement) must not be 0")
    out = displacement.copy()
    out[span] = displacement[span] - load[span] / stiffness
    _store(state, words[2], words[6], words[7], out, where)


def _strain(state, words, where):
    displacement, thickness = _values(state, words[0], where), _values(state, words[1], where)
    span = _range(state, words[3], words[4], where)
    out = np.zeros_like(displacement)
    with np.errstate(divide="ignore", invalid="ignore"):
        increments = np.diff(displacement[span]) / thickness[span][1:]
    out[span.start + 1:span.stop] = np.cumsum(increments)
    out[span.stop:] = out[span.stop - 1]
    _store(state, words[2], words[5], words[6], out, where)


def _r_col(state, words, where):
    slot = _slot(words[0], where)
    state.data[slot] = state.names[slot] = state.units[slot] = None


def _r_row(state, words, where):
    span = _range(state, words[0], words[1], where)
    state.data = [None if values is None else np.delete(values, span) for values in state.data]


#: xlook's shorthand units and what udunits calls them
_COMMANDS = {"math": _math, "math_int": _math_int, "summation": _summation, "power": _power, "zero": _zero,
             "offset_int": _offset_int, "ec": _ec, "strain": _strain, "r_col": _r_col, "r_row": _r_row}
