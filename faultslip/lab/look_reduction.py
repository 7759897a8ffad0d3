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
* ``begin``, ``com_file`` and ``end`` frame the file;
* xlook's further data commands, each as its source (src/array.c, func.c, special.c, cmds.c) defines it: column
  functions (exp, ln, log, recip, positive, trig, col_power, and func.c's Power1 .. Poly4), deriv, smooth,
  median_smooth, slope, z_min, z_max, r_mean, r_spike, offset, name, cgt, rgt, vc, r_trend, sort, curv, compress,
  r_row_col, decimat, interpolate, peak, pdf and polyfit, and append and doit (docs/lab_fits.md tables each
  with its check). Display and interactive commands (plots, type, stat, windows; the rate-and-state tools qi,
  simplex, ...) are skipped, each noted, the tools' note naming faultslip's own fit.

Record ranges include both ends, and a LAST of -1 is the last record. The r-files say so themselves: p655's
``r_row 86283 86283`` removes the one record its comment names ("normal stress has a zero at 86283, ax it").
pylook's interpreter reads ranges as Python slices, stopping before LAST; benchmarks/look_against_pylook.py shows
where that, and its elastic correction, differ from this reading.

A command faultslip does not know, a wrong number of arguments, a slot outside 0 to 31, a record outside the data or
a column used before it holds data is one sentence naming the line (xlook printed a warning and went on; a
reduction that silently skips a step is not one a lab can trust).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from faultslip.errors import InputError
from faultslip.io import gate
from faultslip.lab.look_files import cf_unit as _cf_unit, read_look
from faultslip.datasets import ToXarray

SLOTS = 32
_ARGUMENTS = {"math": 8, "math_int": 10, "summation": 5, "power": 6, "zero": 3, "offset_int": 5, "ec": 9,
              "strain": 8, "r_col": 2, "r_row": 3, "read": 2, "begin": 1, "com_file": 1, "append": 2, "doit": 2}


@dataclass
class Reduction(ToXarray):
    """A reduced experiment: xlook's slots (name, unit, values), the data file read, and the commands run."""

    names: list = field(default_factory=lambda: [None] * SLOTS)
    units: list = field(default_factory=lambda: [None] * SLOTS)
    data: list = field(default_factory=lambda: [None] * SLOTS)
    source: str = ""
    commands: int = 0
    experiment: str = ""  # the data file's own name for its run (xlook's header)
    ran: list = field(default_factory=list)  # the commands run, in order
    current: str = ""  # the command running (a variant such as r_trend_o reads it)
    skipped: list = field(default_factory=list)  # the display commands skipped, each with its line

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
            records = _records(self)
            padded = values if len(values) == records else np.concatenate([values, np.full(records - len(values),
                                                                                          np.nan)])
            data[key] = ("record", padded, {"long_name": name, "units": _cf_unit(unit), "xlook_units": str(unit),
                                            "xlook_slot": slot, "xlook_records": len(values)})
        return xr.Dataset(data, coords={"record": ("record", np.arange(_records(self)), {"units": "1"})},
                          attrs={"title": f"xlook reduction {self.source}", "Conventions": "CF-1.8",
                                 "commands": self.commands, "commands_run": " ".join(self.ran),
                                 "commands_skipped": "; ".join(self.skipped),
                                 **({"experiment": self.experiment} if self.experiment else {})})

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
        Where ``read``, ``append`` and ``doit`` find their files.
    look : LookFile, optional
        Data already read.

    Returns
    -------
    Reduction
        The slots after the last command.
    """
    state = Reduction(source=source)
    lines = _parse(text, source, state)  # every line checked first: a file is refused before any data is read
    if look is not None:
        _load(state, look)
    _execute(state, lines, base_dir, look, depth=0)
    return state


#: How deep ``doit`` files may call one another (xlook's own limit on open command files is a handful).
MAX_DOIT_DEPTH = 8


def _parse(text: str, source: str, state: Reduction) -> list:
    """Every line's command and its number of arguments, checked: (command, words, where) of the data commands;
    display commands noted in ``state.skipped``."""
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
        if command in DISPLAY_COMMANDS or (command.startswith("plot") and command.endswith("h")):
            state.skipped.append(f"{source} line {number}: {command} (draws, prints or prompts: no data changes)")
            continue
        if command in FITTING_TOOLS or command.startswith(("rsm", "cm_h", "scm", "qi_")):
            state.skipped.append(f"{source} line {number}: {command} (xlook's interactive rate-and-state tool: fit the "
                                 "reduced record with 'faultslip fit --law rate-state', or model it with a "
                                 "rate_state_slider scene)")
            continue
        if command not in _ARGUMENTS:
            raise InputError(f"{where}: faultslip does not know the command {command!r} (it runs "
                             f"{', '.join(sorted(_ARGUMENTS))} and end, and skips xlook's display commands)")
        allowed = _ARGUMENTS[command] if isinstance(_ARGUMENTS[command], tuple) else (_ARGUMENTS[command],)
        if len(words) not in allowed:
            raise InputError(f"{where}: {command} takes {' or '.join(str(n - 1) for n in allowed)} arguments, got "
                             f"{len(words) - 1}")
        lines.append((command, words, where))
    return lines


def _execute(state: Reduction, lines: list, base_dir, look, depth: int) -> None:
    folder = Path(base_dir) if base_dir is not None else Path(".")
    for command, words, where in lines:
        if command == "read":
            if look is None:
                _load(state, read_look(folder / Path(words[1]).name))
        elif command == "append":
            _append(state, read_look(folder / Path(words[1]).name), where)
        elif command == "doit":  # a command file beside this one, run on the same data (cmds1.c's doit_proc)
            if depth >= MAX_DOIT_DEPTH:
                raise InputError(f"{where}: doit files call one another more than {MAX_DOIT_DEPTH} deep (a loop?)")
            path = folder / Path(words[1]).name
            nested = gate.read_text(path, "xlook command file", "config")
            _execute(state, _parse(nested, path.name, state), folder, look, depth + 1)
        elif command not in ("begin", "com_file"):
            state.current = command
            _COMMANDS[command](state, words[1:], where)
        state.commands += 1
        state.ran.append(command)


def _append(state: Reduction, look, where: str) -> None:
    """``append FILE``: FILE's records after the data set's (filtersm.c's reed in append mode): its columns, in
    file order, extend slots 1 onwards, and slot 0 counts on; a file with other columns is refused."""
    if state.data[1] is None:
        raise InputError(f"{where}: append adds records to a data set: read a file first")
    names = list(look.columns)
    held = [slot for slot in range(1, SLOTS) if state.data[slot] is not None]
    if len(names) != len(held):
        raise InputError(f"{where}: {look.name} has {len(names)} columns where the data set holds {len(held)}")
    records = _records(state)
    for slot, name in zip(held, names):
        state.data[slot] = np.concatenate([state.data[slot], np.asarray(look.columns[name], dtype=float)])
    state.data[0] = np.arange(records + look.records, dtype=float)


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
    state.data = [None if values is None else _without(values, span) for values in state.data]


def _without(values: np.ndarray, span: slice) -> np.ndarray:
    """``values`` without the records of ``span`` it holds (a shorter column loses those it has)."""
    return np.delete(values, np.arange(span.start, min(span.stop, len(values))))


def _single(state: Reduction, text: str, where: str) -> np.ndarray:
    """A column's values at its own length (xlook's commands on one column run over its own records)."""
    slot = _slot(text, where)
    if state.data[slot] is None:
        raise InputError(f"{where}: column {slot} holds no data (read the data file first, or fill the column)")
    return state.data[slot]


def _r_row_col(state, words, where):
    """``r_row_col COL FIRST LAST`` (or rrc): records FIRST to LAST removed from column COL alone (do_r_row_col):
    it then holds fewer records than the others, as xlook allows."""
    slot = _slot(words[0], where)
    values = _single(state, words[0], where)
    span = _range(state, words[1], words[2], where)
    state.data[slot] = _without(values, span)


def _compress(state, words, where):
    """``compress IN OUT NAME UNIT``: IN's non-zero values, in order, into OUT, a shorter column (do_compress)."""
    if _slot(words[0], where) == _slot(words[1], where):
        raise InputError(f"{where}: compress writes into another column than it reads")
    values = _single(state, words[0], where)
    _store(state, words[1], words[2], words[3], values[values != 0.0].copy(), where)


def _decimat(state, words, where):
    """``decimat IN OUT STEP FIRST LAST NAME UNIT``: every STEP-th record of IN from FIRST to LAST written into OUT
    from FIRST on (do_decimat); OUT's other records keep their values. ``decimat_r`` (or decimatr) then ends OUT
    after the last one written, a shorter column."""
    values = _values(state, words[0], where)
    try:
        step = int(words[2])
    except ValueError:
        raise InputError(f"{where}: the step is a whole number of records, got {words[2]!r}") from None
    if step < 1:
        raise InputError(f"{where}: the step must be 1 or more records, got {step}")
    span = _range(state, words[3], words[4], where)
    out = _output(state, words[1], where)
    picked = values[span.start:span.stop:step]
    out[span.start:span.start + picked.size] = picked
    if state.current.endswith("r"):
        out = out[:span.start + picked.size]
    _store(state, words[1], words[5], words[6], out, where)


def _interpolate(state, words, where):
    """``interpolate X Y NEW_X NEW_Y FIRST LAST DX|d NAME_X UNIT_X NAME_Y UNIT_Y``: do_interpolate, Y resampled at
    equal steps of X from FIRST: NEW_X steps by DX (or, with ``d``, the range of X over the records over their
    count), NEW_Y linear between the bracketing records; the first record as it is. ``interpolate_r`` (or
    interpolater) then removes the records after the last one written from every column, as its generated r_row
    does."""
    x, y = _values(state, words[0], where), _values(state, words[1], where)
    span = _range(state, words[4], words[5], where)
    first, last = span.start, span.stop - 1
    if words[6][:1] == "d":
        step = (x[span].max() - x[span].min()) / (last - first + 1)
    else:
        step = _number(words[6], where)
    if not step > 0:
        raise InputError(f"{where}: the increment must be positive, got {step!r}")
    new_x, new_y = _output(state, words[2], where), _output(state, words[3], where)
    new_x[first], new_y[first] = x[first], y[first]
    i, k = first, first + 1
    while k <= last:
        if new_x[i] + step > x[k]:
            k += 1
            continue
        if i + 1 > last:
            raise InputError(f"{where}: an increment of {step:g} gives more points than records {first} to {last} "
                             "hold; use a larger increment")
        new_y[i + 1] = y[k - 1] + (y[k] - y[k - 1]) * (new_x[i] + step - x[k - 1]) / (x[k] - x[k - 1])
        new_x[i + 1] = new_x[i] + step
        i += 1
    _store(state, words[2], words[7], words[8], new_x, where)
    _store(state, words[3], words[9], words[10], new_y, where)
    if state.current.endswith("r") and i + 1 <= last:
        removed = slice(i + 1, last + 1)
        state.data = [None if values is None else _without(values, removed) for values in state.data]


def _peak(state, words, where):
    """``peak IN OUT NAME UNIT``: do_peak, OUT holds IN where IN is above its two neighbours on each side (records
    2 to N - 3), and 0 elsewhere."""
    values = _single(state, words[0], where)
    out = np.zeros_like(values)
    middle = values[2:-2]
    local = ((middle > values[3:-1]) & (middle > values[1:-3]) & (middle > values[4:]) & (middle > values[:-4]))
    out[2:-2] = np.where(local, middle, 0.0)
    _store(state, words[1], words[2], words[3], out, where)


# --- column functions (xlook's src/array.c and src/func.c; the command's words as src/cmds.c reads them) ---------

def _output(state, slot_text, where) -> np.ndarray:
    """The values a command writes into: a new slot starts at zero (xlook's name() gives it the input's length); a
    slot that holds data keeps it where the command does not write."""
    slot = _slot(slot_text, where)
    if slot == 0:
        raise InputError(f"{where}: slot 0 holds the record numbers; write into slots 1 to {SLOTS - 1}")
    existing = state.data[slot]
    return existing.copy() if existing is not None and len(existing) == _records(state) else np.zeros(_records(state))


def _elementwise(function):
    """``CMD IN OUT NAME UNIT``: OUT = function(IN) on every record (exp: exp; ln: ln; log: log10; recip: 1 / x;
    positive: 1 where IN > 0, else 0; array.c's expvec, lnvec, logvec, recipvec; cmds.c's do_positive)."""
    def command(state, words, where):
        values = _values(state, words[0], where)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):  # xlook computes as the machine does
            _store(state, words[1], words[2], words[3], function(values), where)
    return command


def _trig(state, words, where):
    """``trig IN OUT FUNC NAME UNIT`` (also reached as sin, cos, tan, asin, acos, atan): FUNC read by its first
    letters as do_trig reads them (s, c, t; as, ac, at)."""
    function = words[2]
    table = {"s": np.sin, "c": np.cos, "t": np.tan}
    if function[:1] == "a":
        chosen = {"s": np.arcsin, "c": np.arccos, "t": np.arctan}.get(function[1:2])
    else:
        chosen = table.get(function[:1])
    if chosen is None:
        raise InputError(f"{where}: the function is one of sin, cos, tan, asin, acos, atan, got {function!r}")
    with np.errstate(invalid="ignore", divide="ignore"):
        _store(state, words[1], words[3], words[4], chosen(_values(state, words[0], where)), where)


def _col_power(state, words, where):
    """``col_power POWER_COL IN OUT NAME UNIT``: OUT = IN ** POWER_COL, record by record (powcvec)."""
    exponent, base = _values(state, words[0], where), _values(state, words[1], where)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        _store(state, words[2], words[3], words[4], base ** exponent, where)


def _chi_square_gamma(ndf: float) -> float:
    """Gamma(ndf / 2). xlook's func.c now takes exp(tgamma(ndf / 2)), a port of the older C library's gamma(),
    which returned ln Gamma: exp of that is Gamma, the chi-square density's own (Press et al., Numerical Recipes,
    eq. 6.14.8), which faultslip takes (tests/capabilities/lab/test_look_reduction.py checks it integrates to 1)."""
    return math.gamma(ndf / 2.0)


def _generator(parameters: int, formula):
    """``CMD IN OUT P1 .. Pn NAME UNIT``: OUT = formula(IN, P1 .. Pn) on every record (func.c's generators)."""
    def command(state, words, where):
        values = _values(state, words[0], where)
        numbers = [_number(text, where) for text in words[2:2 + parameters]]
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            _store(state, words[1], words[2 + parameters], words[3 + parameters], formula(values, *numbers), where)
    return command


def _scchisqr(x, sigma, ndf, offset):
    sigx = math.sqrt(sigma / (math.sqrt(ndf) * math.sqrt(2.0)))
    temp = sigx ** ndf * 2.0 ** (ndf / 2.0) * _chi_square_gamma(ndf)
    return np.where(offset >= x, 0.0, np.abs(x - offset) ** ((ndf - 2.0) / 2.0)
                    * np.exp((offset - x) / (2.0 * sigx * sigx)) / temp)


_GENERATORS = {
    "Power1": (2, lambda x, a, b: x ** a + b),  # y = x^A + B
    "Power2": (3, lambda x, a, b, c: a * x ** b + c),  # y = A x^B + C
    "normal": (2, lambda x, mean, sigma: np.exp(-((x - mean) / sigma) ** 2 / 2.0) / math.sqrt(2 * math.pi) / sigma),
    "chisqr": (1, lambda x, ndf: x ** ((ndf - 2.0) / 2.0) * np.exp(-x / 2.0)
               / (2.0 ** (ndf / 2.0) * _chi_square_gamma(ndf))),
    "scchisqr": (3, _scchisqr),
    "rclow": (2, lambda x, a, b: (1.0 / (x * b)) * np.sqrt(1.0 + (x * b * a) ** 2)),  # y = sqrt(1 + (x B A)^2) / (x B)
    "rcph": (2, lambda x, a, b: -np.arctan(1.0 / (x * a * b))),  # y = -atan(1 / (x A B))
    "genexp": (4, lambda x, a, b, c, d: a * np.exp(b * x + c) + d),  # y = A exp(B x + C) + D
    "gensin": (4, lambda x, a, b, c, d: a * np.sin(b * x + c) + d),  # y = A sin(B x + C) + D
    "ExpLin": (3, lambda x, a, b, c: a * (1.0 - np.exp(b * x)) + c * x),  # y = A (1 - exp(B x)) + C x
    "Poly4": (5, lambda x, a, b, c, d, e: a + b * x + c * x ** 2 + d * x ** 3 + e * x ** 4),
}


def _deriv(state, words, where):
    """``deriv X Y OUT FIRST LAST NAME UNIT``: dY/dX on records FIRST to LAST by array.c's deriv: the three-point
    difference for unequal spacing about each record (e1 = x[i+1] - x[i], e2 = x[i] - x[i-1]),

        dy/dx = [e2^2 y[i+1] - e1^2 y[i-1] - (e2^2 - e1^2) y[i]] / (|e1| e2^2 + |e2| e1^2),

    its first value also at FIRST and its last also at LAST; the records outside keep OUT's values (zero in a new
    slot)."""
    x, y = _values(state, words[0], where), _values(state, words[1], where)
    span = _range(state, words[3], words[4], where)
    first, last = span.start, span.stop - 1
    if last - first < 2:
        raise InputError(f"{where}: a derivative needs three records or more, got {last - first + 1}")
    out = _output(state, words[2], where)
    a, b, c = x[first:last - 1], x[first + 1:last], x[first + 2:last + 1]
    ya, yb, yc = y[first:last - 1], y[first + 1:last], y[first + 2:last + 1]
    e1, e2 = c - b, b - a
    with np.errstate(divide="ignore", invalid="ignore"):
        slope = (e2 * e2 * yc - e1 * e1 * ya - (e2 * e2 - e1 * e1) * yb) / (np.abs(e1) * e2 * e2 + np.abs(e2) * e1 * e1)
    out[first + 1:last] = slope
    out[first], out[last] = slope[0], slope[-1]
    _store(state, words[2], words[5], words[6], out, where)


def _shifted_by(statistic):
    """``CMD IN OUT NAME UNIT``: OUT = IN less its mean, minimum or maximum over every record (z_min, z_max and
    r_mean: stats() then sub() over the whole column)."""
    def command(state, words, where):
        values = _values(state, words[0], where)
        _store(state, words[1], words[2], words[3], values - statistic(values), where)
    return command


def _r_spike(state, words, where):
    """``r_spike COL REC``: record REC takes record REC - 1's value (do_r_spike; REC 0 has none before it)."""
    values = _values(state, words[0], where).copy()
    record = _range(state, words[1], words[1], where).start
    if record == 0:
        raise InputError(f"{where}: record 0 has no record before it to take the place of a spike")
    values[record] = values[record - 1]
    state.data[_slot(words[0], where)] = values


def _name(state, words, where):
    """``name COL NAME UNIT``: the slot's name and unit (do_name)."""
    slot = _slot(words[0], where)
    if state.data[slot] is None:
        raise InputError(f"{where}: column {slot} holds no data to name")
    state.names[slot], state.units[slot] = words[1], words[2]


def _offset(state, words, where):
    """``offset COL1 REC1 COL2 REC2``: COL1 shifted, every record, by COL2[REC2] - COL1[REC1] (array.c's offset)."""
    values = _values(state, words[0], where)
    other = _values(state, words[2], where)
    first = _range(state, words[1], words[1], where).start
    second = _range(state, words[3], words[3], where).start
    state.data[_slot(words[0], where)] = values + (other[second] - values[first])


def _window(state, words, where, at: int) -> tuple[int, int, int]:
    """(first, last, odd window) of a smoothing command: records FIRST to LAST, the window forced odd as
    special.c does (2 (W / 2) + 1) and no wider than the records."""
    span = _range(state, words[at], words[at + 1], where)
    try:
        window = int(words[at + 2])
    except ValueError:
        raise InputError(f"{where}: the window is a whole number of records, got {words[at + 2]!r}") from None
    window = 2 * (window // 2) + 1
    if window < 1 or window > span.stop - span.start:
        raise InputError(f"{where}: a window of {window} records does not fit records {span.start} to {span.stop - 1}")
    return span.start, span.stop - 1, window


def _smooth(state, words, where):
    """``smooth IN OUT FIRST LAST WINDOW NAME UNIT``: special.c's smooth(), a running mean over an odd window,
    value for value: the first half-window padded with IN[FIRST], the last with IN[LAST], and its tail as xlook
    computes it (each tail step takes away IN[LAST - WINDOW], not the window's oldest value: kept, so that old
    reductions reproduce). xlook copies IN into slot 0 as its scratch; faultslip keeps the record numbers."""
    x = _values(state, words[0], where)
    start, end, window = _window(state, words, where, 2)
    half = window // 2
    out = _output(state, words[1], where)
    total = half * x[start]
    k = 0
    for i in range(window):
        total += x[start + i]
        if i >= half:
            out[start + k] = total / window
            total -= x[start]
            k += 1
    for i in range(start + window, end + 1):
        total += x[i]
        out[i - half] = total / window
        total -= x[i - (window - 1)]
    for i in range(1, half + 1):
        total += x[end]
        out[end - half + i] = total / window
        total -= x[end - window]
    _store(state, words[1], words[5], words[6], out, where)


def _median_smooth(state, words, where):
    """``median_smooth IN OUT FIRST LAST WINDOW NAME UNIT`` (or ms): special.c's median_smooth(), the median of each
    odd window written at its middle record; the first half-window and the records from LAST - WINDOW / 2 on keep
    IN's values (special.c copies them over the last median it wrote)."""
    x = _values(state, words[0], where)
    start, end, window = _window(state, words, where, 2)
    half = window // 2
    out = _output(state, words[1], where)
    out[start:start + half] = x[start:start + half]
    windows = np.lib.stride_tricks.sliding_window_view(x[start:end + 1], window)
    out[start + half:start + half + windows.shape[0]] = np.median(windows, axis=1)
    out[end - half:end + 1] = x[end - half:end + 1]
    _store(state, words[1], words[5], words[6], out, where)


def _slope(state, words, where):
    """``slope X Y OUT FIRST LAST WINDOW NAME UNIT`` (or ras): special.c's o_slope(), the least-squares slope of Y on
    X over each odd window, written at its middle; the first half-window takes the first slope, and the last
    half-window the slope one record before the last computed (as o_slope pads them)."""
    x, y = _values(state, words[0], where), _values(state, words[1], where)
    start, end, window = _window(state, words, where, 3)
    half = window // 2
    out = _output(state, words[2], where)
    xs = np.lib.stride_tricks.sliding_window_view(x[start:end + 1], window)
    ys = np.lib.stride_tricks.sliding_window_view(y[start:end + 1], window)
    dx = xs - xs.mean(axis=1, keepdims=True)
    with np.errstate(divide="ignore", invalid="ignore"):
        slopes = (dx * (ys - ys.mean(axis=1, keepdims=True))).sum(axis=1) / (dx * dx).sum(axis=1)
    out[start + half:start + half + slopes.size] = slopes
    out[start:start + half] = out[start + half]
    if half:
        out[end - half + 1:end + 1] = out[end - half - 1]
    _store(state, words[2], words[6], words[7], out, where)


def _c_float(text: str, where: str) -> float:
    """A number as xlook's sscanf reads it with %f: a C float, rounded to single precision (cgt, rgt, vc)."""
    return float(np.float32(_number(text, where)))


def _cgt(state, words, where):
    """``cgt L H DISP OUT NAME UNIT``: array.c's calc_geom_thin(), the layer's geometric thinning in direct shear
    from an initial thickness H over a block of length L, h_i = h_(i-1) (1 - (d_i - d_(i-1)) / (2 L)), h_0 = H;
    L and H read as C floats."""
    length, thickness = _c_float(words[0], where), _c_float(words[1], where)
    d = _values(state, words[2], where)
    out = np.empty_like(d)
    h = thickness
    out[0] = h
    for i in range(1, d.size):  # a recurrence, as array.c writes it (its rounding too)
        h -= (d[i] - d[i - 1]) * h / (2.0 * length)
        out[i] = h
    _store(state, words[3], words[4], words[5], out, where)


def _rgt(state, words, where):
    """``rgt L DISP THICK OUT NAME UNIT``: array.c's geom_thin(), the thickness corrected for geometric thinning:
    out_i = thick_(i-1) + sum_(k<=i) (d_k - d_(k-1)) thick_(k-1) / (2 L), out_0 = thick_0; L read as a C float."""
    length = _c_float(words[0], where)
    d, thick = _values(state, words[1], where), _values(state, words[2], where)
    if _slot(words[1], where) == _slot(words[3], where):
        raise InputError(f"{where}: rgt's output must not be its displacement column")
    out = np.empty_like(d)
    out[0] = thick[0]
    change = 0.0
    for i in range(1, d.size):
        change += (d[i] - d[i - 1]) * thick[i - 1] / (2.0 * length)
        out[i] = thick[i - 1] + change
    _store(state, words[3], words[4], words[5], out, where)


def _vc(state, words, where):
    """``vc VS TAU OUT FIRST LAST S NAME UNIT``: array.c's vol_corr(), the volume strain corrected for the pressure
    on the layer's edges, out_r = out_(r-1) + (vs_r - vs_(r-1)) - (tau_r - tau_(r-1)) S from out_FIRST = vs_FIRST
    to LAST; S (S Va / V) read as a C float; the records outside keep OUT's values."""
    vs, tau = _values(state, words[0], where), _values(state, words[1], where)
    span = _range(state, words[3], words[4], where)
    factor = _c_float(words[5], where)
    out = _output(state, words[2], where)
    first, last = span.start, span.stop - 1
    out[first] = vs[first]
    for row in range(first + 1, last + 1):
        out[row] = out[row - 1] + vs[row] - vs[row - 1] - (tau[row] - tau[row - 1]) * factor
    _store(state, words[2], words[6], words[7], out, where)


def _line(x, y) -> tuple[float, float]:
    """special.c's line(): the least-squares slope and intercept of y on x, from the means (its loop order)."""
    x_mean, y_mean = x.sum() / x.size, y.sum() / y.size
    slope = float(((y - y_mean) * (x - x_mean)).sum() / ((x - x_mean) ** 2).sum())
    return slope, float(y_mean - slope * x_mean)


def _r_trend(state, words, where):
    """``r_trend X|Y i X Y OUT SLOPE INTERCEPT NAME UNIT`` (a trend given) or ``r_trend X|Y c X Y OUT FIRST LAST NAME
    UNIT`` (fitted to records FIRST to LAST by special.c's line()), as cmds.c's do_r_trend_final removes it over
    every record: with Y, OUT = Y - (SLOPE X + INTERCEPT); with X, OUT = X - (Y - INTERCEPT) / SLOPE.
    ``r_trend_o`` (or ``r_trendo``) then offsets OUT to Y at the first record of the fit, as its generated
    ``offset`` does (records from 0 where the trend is given). xlook uses slot 0 as scratch; faultslip keeps the
    record numbers."""
    axis, given = words[0][:1].lower(), words[1][:1].lower() == "i"
    if axis not in ("x", "y"):
        raise InputError(f"{where}: r_trend removes a trend from X or from Y, got {words[0]!r}")
    x, y = _values(state, words[2], where), _values(state, words[3], where)
    if given:
        slope, intercept, first = _number(words[5], where), _number(words[6], where), 0
    else:
        span = _range(state, words[5], words[6], where)
        slope, intercept = _line(x[span], y[span])
        first = span.start
    with np.errstate(divide="ignore", invalid="ignore"):
        out = x - (y - intercept) / slope if axis == "x" else y - (x * slope + intercept)
    if state.current.endswith("o"):
        out = out + (y[first] - out[first])
    _store(state, words[4], words[7], words[8], out, where)


def _sort(state, words, where):
    """``sort COL FIRST LAST`` (or order; a negative COL for descending): cmds.c's do_sort, which keeps from FIRST
    the records that continue COL's order (each next kept record the first beyond the last kept that is greater,
    or smaller descending) and removes the others from every column up to LAST; records after LAST stay. Slot 0
    then holds the kept records' numbers, as xlook's scratch of them does."""
    try:
        column = int(words[0])
    except ValueError:
        raise InputError(f"{where}: a column is a slot number, got {words[0]!r}") from None
    ascend = -1.0 if column < 0 else 1.0
    values = _values(state, str(abs(column)), where)
    span = _range(state, words[1], words[2], where)
    first, last = span.start, span.stop - 1
    kept, i = [first], first
    while i < last:
        k = 1
        while i + k <= last and ascend * values[i + k] <= ascend * values[i]:
            k += 1
        i += k
        if i <= last:
            kept.append(i)
    keep = np.concatenate([np.arange(first), kept, np.arange(last + 1, _records(state))]).astype(int)
    state.data = [None if column_values is None else column_values[keep] for column_values in state.data]


def _curv(state, words, where):
    """``curv IN OUT DX NAME UNIT``: cmds.c's do_curv, the second difference of IN at spacing DX (a C float) to
    fourth order, (-30 y_i + 16 (y_(i+1) + y_(i-1)) - (y_(i+2) + y_(i-2))) / (12 DX^2), on records 2 to N - 3;
    the others keep OUT's values."""
    y = _values(state, words[0], where)
    dx = _c_float(words[2], where)
    if y.size < 5:
        raise InputError(f"{where}: curv needs five records or more, got {y.size}")
    out = _output(state, words[1], where)
    out[2:-2] = (-30.0 * y[2:-2] + 16.0 * (y[3:-1] + y[1:-3]) - (y[4:] + y[:-4])) / (12.0 * dx ** 2)
    _store(state, words[1], words[3], words[4], out, where)


def _pdf(state, words, where):
    """``pdf IN OUT BIN K MAX MIN`` and ``pdfauto IN OUT BIN K``: do_pdf's probability density of IN in K bins from
    MIN to MAX (whole numbers, as xlook reads them; pdfauto: IN's own range), into OUT ("prob_dens") and BIN ("bin",
    IN's unit), columns of K records: bin centres MIN + (j + 1/2) / (K - 1) (MAX - MIN), each value's bin
    (K - 1) (x - MIN) / (MAX - MIN) rounded to a C float and truncated, the counts over N (MAX - MIN) / (K - 1)."""
    values = _single(state, words[0], where)
    try:
        bins = int(words[3])
        low, high = (float(int(words[5])), float(int(words[4]))) if len(words) > 4 else (values.min(), values.max())
    except ValueError:
        raise InputError(f"{where}: the bins, MAX and MIN are whole numbers") from None
    if bins < 2 or not high > low:
        raise InputError(f"{where}: a density needs 2 bins or more and MAX above MIN")
    if np.any(values < low) or np.any(values > high):
        raise InputError(f"{where}: values of column {words[0]} lie outside {low:g} to {high:g}: widen MIN and MAX "
                         "(xlook would write past its bins)")
    centres = low + (np.arange(bins) + 0.5) / (bins - 1) * (high - low)
    index = np.trunc(((bins - 1) * (values - low) / (high - low)).astype(np.float32)).astype(int)
    density = np.bincount(index, minlength=bins)[:bins].astype(float) / (values.size * ((high - low) / (bins - 1.0)))
    _store(state, words[1], "prob_dens", "prob_dens", density, where)
    _store(state, words[2], "bin", state.units[_slot(words[0], where)], centres, where)


def _polyfit(state, words, where):
    """``polyfit X Y OUT ORDER FIRST LAST a|n|y [ROW] NAME UNIT`` and ``polyfit_i X Y OUT ORDER FIRST LAST DX|d
    [ROW] NAME UNIT``: do_polyfit, the least-squares polynomial of ORDER of Y on X over records FIRST to LAST
    (xlook fits orthogonal polynomials, polyfit.c's ortpol: the same polynomial, to round-off), evaluated into OUT
    at X on FIRST to LAST (n), on every record (a), or on FIRST to ROW (y, with ROW); polyfit_i evaluates it at
    X[FIRST] + k DX instead (d: the range of X over the records over their count), to LAST or to ROW."""
    x, y = _values(state, words[0], where), _values(state, words[1], where)
    try:
        order = int(words[3])
    except ValueError:
        raise InputError(f"{where}: the order is a whole number, got {words[3]!r}") from None
    span = _range(state, words[4], words[5], where)
    first, last = span.start, span.stop - 1
    if not 0 <= order < last - first + 1:
        raise InputError(f"{where}: a polynomial of order {order} needs more than {order} records, got "
                         f"{last - first + 1}")
    extended = len(words) == 10
    row = _range(state, words[7], words[7], where).start if extended else None
    name, unit = words[-2], words[-1]
    fit = np.polynomial.Polynomial.fit(x[span], y[span], order)
    out = _output(state, words[2], where)
    mode = words[6]
    if state.current.startswith("polyfit_i"):
        step = (x[span].max() - x[span].min()) / (last - first + 1) if mode[:1] == "d" else _number(mode, where)
        end = row if extended else last
        if end < first:
            raise InputError(f"{where}: the row to extend to lies before FIRST")
        out[first:end + 1] = fit(x[first] + np.arange(end - first + 1) * step)
    elif mode[:1] in ("a", "A"):
        out = fit(x)
    elif mode[:1] in ("y", "Y"):
        if row is None:
            raise InputError(f"{where}: extending the fit (y) needs the row to extend to before NAME")
        if row < first:
            raise InputError(f"{where}: the row to extend to lies before FIRST")
        out[first:row + 1] = fit(x[first:row + 1])
    else:
        out[first:last + 1] = fit(x[first:last + 1])
    _store(state, words[2], name, unit, out, where)


_COMMANDS = {"math": _math, "math_int": _math_int, "summation": _summation, "power": _power, "zero": _zero,
             "offset_int": _offset_int, "ec": _ec, "strain": _strain, "r_col": _r_col, "r_row": _r_row,
             "exp": _elementwise(np.exp), "ln": _elementwise(np.log), "log": _elementwise(np.log10),
             "recip": _elementwise(lambda x: 1.0 / x), "positive": _elementwise(lambda x: np.where(x > 0.0, 1.0, 0.0)),
             "col_power": _col_power, "deriv": _deriv, "z_min": _shifted_by(np.min), "z_max": _shifted_by(np.max),
             "r_mean": _shifted_by(np.mean), "r_spike": _r_spike, "name": _name, "offset": _offset,
             "smooth": _smooth, "median_smooth": _median_smooth, "ms": _median_smooth, "slope": _slope, "ras": _slope,
             "cs": _strain, "cgt": _cgt, "calc_geometric_thinning": _cgt, "rgt": _rgt, "geometric_thinning": _rgt,
             "vc": _vc, "vol_cor": _vc, "r_trend": _r_trend, "r_trend_o": _r_trend, "r_trendo": _r_trend,
             "sort": _sort, "order": _sort, "curv": _curv, "r_row_col": _r_row_col, "rrc": _r_row_col,
             "compress": _compress, "decimat": _decimat, "decimat_r": _decimat, "decimatr": _decimat,
             "interpolate": _interpolate, "interpolate_r": _interpolate, "interpolater": _interpolate,
             "peak": _peak, "pdf": _pdf, "pdfauto": _pdf, "polyfit": _polyfit, "polyfit_i": _polyfit,
             **{name: _trig for name in ("trig", "sin", "cos", "tan", "asin", "acos", "atan")},
             **{name: _generator(count, formula) for name, (count, formula) in _GENERATORS.items()}}
_ARGUMENTS.update({"exp": 5, "ln": 5, "log": 5, "recip": 5, "positive": 5, "col_power": 6, "deriv": 8, "z_min": 5,
                   "z_max": 5, "r_mean": 5, "r_spike": 3, "name": 4, "offset": 5, "smooth": 8, "median_smooth": 8,
                   "ms": 8, "slope": 9, "ras": 9, "cs": 8, "cgt": 7, "calc_geometric_thinning": 7, "rgt": 7,
                   "geometric_thinning": 7, "vc": 9, "vol_cor": 9, "r_trend": 10, "r_trend_o": 10, "r_trendo": 10,
                   "sort": 4, "order": 4, "curv": 6, "r_row_col": 4, "rrc": 4, "compress": 5, "decimat": 8,
                   "decimat_r": 8, "decimatr": 8, "interpolate": 12, "interpolate_r": 12, "interpolater": 12,
                   "peak": 5, "pdf": 7, "pdfauto": 5, "polyfit": (10, 11), "polyfit_i": (10, 11),
                   **{name: 6 for name in ("trig", "sin", "cos", "tan", "asin", "acos", "atan")},
                   **{name: 5 + count for name, (count, _) in _GENERATORS.items()}})
#: xlook's rate-and-state forward models and inversions (its "r/s fric tool"; rsm and cm now only point to it):
#: interactive, so skipped with a note that names faultslip's own fit and slider, which do this work.
FITTING_TOOLS = {"qi", "qi_mvs", "simplex", "rsm", "cm", "cm2", "mem", "scm"}
#: xlook's commands that draw, print, prompt or manage windows and files: an r-file that holds them runs, each
#: skipped with a note (the report lists them), as they change no data.
DISPLAY_COMMANDS = {"kp", "kill_plot", "kw", "kill_window", "nw", "new_window", "aw", "activate_window", "ap",
                    "activate_plot", "q", "quit", "set_path", "plotover", "plotall", "plotsr", "plotauto", "pa",
                    "plotlog", "plotsame", "plotscale", "examin", "getaschead", "head", "type", "typeall",
                    "type_all", "stat", "stat_a", "trend", "trend_a", "comment", "qi_tool",
                    "fric_tool", "write", "findint", "all"}
