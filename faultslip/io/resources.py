"""Locate the bundled ``data/`` and ``configs/`` directories.

In a wheel they are installed as ``faultslip/_bundled/{data,configs}``; in a
source checkout (editable install or running from the tree) they are the
top-level directories of the repository.
"""

from __future__ import annotations

import contextlib
from array import array

import csv
import json
import re
import tomllib
from io import BytesIO
from pathlib import Path

from faultslip.errors import InputError
from faultslip.io import gate
from faultslip.io.atomic import write_text_atomic
from faultslip.io.chunks import block_digest
import numpy as np
import subprocess
import sys
import warnings

_PACKAGE = Path(__file__).resolve().parent.parent  # faultslip/, this file being faultslip/io/resources.py


def bundled_dir(kind: str) -> Path:
    """Directory of bundled ``"data"`` or ``"configs"``."""
    for candidate in (_PACKAGE / "_bundled" / kind, _PACKAGE.parent / kind):
        if candidate.is_dir():
            return candidate
    raise FileNotFoundError(f"bundled {kind}/ directory not found next to {_PACKAGE}")


def data_path(name: str) -> Path:
    return bundled_dir("data") / name


#: The key under which a bundled table carries the SHA-256 of the rest of it (:func:`faultslip.io.gate.json_checksum`).
TABLE_CHECKSUM = "checksum"


def bundled_table_text(table: dict) -> str:
    """A table as ``data/`` ships it: its content as JSON (indent 1) and, last, the checksum of that content."""
    if not isinstance(table, dict) or TABLE_CHECKSUM in table:
        raise ValueError(f"a bundled table is a dict without a {TABLE_CHECKSUM!r} key of its own")
    return json.dumps({**table, TABLE_CHECKSUM: gate.json_checksum(table, TABLE_CHECKSUM)}, indent=1) + "\n"


def write_bundled_table(path, table: dict) -> None:
    """Write a table the package reads back (a calibration, a cost model, a declared error) into ``data/``, sealed
    with its checksum and written atomically: :func:`read_bundled_table` trusts only a table that matches it."""
    write_text_atomic(path, bundled_table_text(table))


def read_bundled_table(name: str, label: str, producer: str):
    """A JSON table shipped in ``data/`` (checked through the gate and against the checksum
    :func:`write_bundled_table` sealed it with), without that checksum; or one sentence naming the benchmark
    ``producer`` that writes it. A table edited or damaged after it was written would change what faultslip
    declares (a calibration's coefficient, a cost, a model error) with no other sign, so it is refused."""
    path = bundled_dir("data") / name
    try:
        table = gate.read_json(path, label)
    except InputError as exc:
        raise InputError(f"{exc}; reinstall faultslip or run {producer}") from None
    if not isinstance(table, dict) or TABLE_CHECKSUM not in table:
        raise InputError(f"{label} ({path}) carries no checksum, so it was not written by {producer} as shipped; "
                         f"reinstall faultslip or run {producer}")
    if table[TABLE_CHECKSUM] != gate.json_checksum(table, TABLE_CHECKSUM):
        raise InputError(f"{label} ({path}) does not match the checksum written with it: it was edited or damaged "
                         f"after {producer} wrote it; reinstall faultslip or run {producer}")
    return {key: value for key, value in table.items() if key != TABLE_CHECKSUM}


def config_path(name: str) -> Path:
    """A bundled file of ``configs/`` by name.

    Parameters
    ----------
    name : str
        The file's name ("san_andreas_1906.toml").

    Returns
    -------
    pathlib.Path
        Where the installed package holds it.
    """
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

    gate.check_input(path, label, "table")
    try:
        handle = open(path, newline="", encoding="utf-8-sig")
    except OSError as exc:
        raise InputError(f"cannot read {label}: {exc.strerror or exc}") from None
    with handle:
        try:
            reader = csv.reader(handle)
            try:
                header = [split_header(column) for column in next(reader)]
            except StopIteration:
                raise InputError(f"{label} is empty") from None
            names = [name for name, _ in header]
            if any(not name for name in names):
                raise InputError(f"{label}: a column has no name in the header")
            repeated = gate.repeated_names(names)
            if repeated:
                raise InputError(f"{label}: the column {repeated[0]!r} appears twice in the header")
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


def check_input_file(path, label: str, kind: str = "table") -> Path:
    """An input file through the gate (:func:`faultslip.io.gate.check_input`)."""
    return gate.check_input(path, label, kind)


#: Run in a child process by :func:`probe_netcdf`: everything xarray reads when it opens a file, then the file's
#: checksum (:func:`faultslip.io.netcdf.checksum_problem`), whose finding is the one line it prints.
_PROBE = """
import sys, netCDF4
sys.path.insert(0, sys.argv[3])  # the faultslip that runs this, wherever it was imported from
from faultslip.io.netcdf import checksum_problem
with netCDF4.Dataset(sys.argv[1]) as nc:
    def walk(group):
        [group.getncattr(k) for k in group.ncattrs()]
        for variable in group.variables.values():
            [variable.getncattr(k) for k in variable.ncattrs()]
            if variable.size <= int(sys.argv[2]):
                variable[...]
        for child in group.groups.values():
            walk(child)
    walk(nc)
    print(checksum_problem(nc, sys.argv[1]) or "")
"""

#: What :func:`probe_netcdf` says of a file by the probe's finding.
_CHECKSUM_FINDINGS = {
    "mismatch": "does not match the checksum faultslip wrote with it: it was changed or damaged after writing",
    "damaged": "has lost its checksum, or its checksum attribute is damaged: it was changed after faultslip wrote it",
}


def probe_netcdf(path, label: str, data_limit: int = 2**26, *, refuse_changed: bool = True) -> str | None:
    """Read a netCDF file's structure (and data up to ``data_limit`` values per variable) in a child process.

    A damaged file can make the netCDF-C/HDF5 libraries crash the process that reads it (a
    segmentation fault while closing a file with a corrupt attribute): found by the fuzzer. The
    child takes that crash, and the damaged file becomes one sentence here. The child also checks
    the checksum of a file faultslip wrote (:mod:`faultslip.io.netcdf`): a file that does not match
    it is refused; a file of an older faultslip without one is read with a warning. With
    ``refuse_changed=False`` the finding is returned instead (``"mismatch"``, ``"damaged"`` or
    ``"unsealed"``; None for a file that matches its checksum or carries none): for ``reproduce``,
    whose answer a changed file is.
    """

    path = check_input_file(path, label, "netcdf")  # a regular file within the netCDF size limit, before the child
    # a damaged file can also make the library loop for ever (found by the fuzzer): allow 20 s plus
    # the time to read the file at 20 MB/s, then call it unreadable
    allowed = 20.0 + Path(path).stat().st_size / 20e6
    try:
        result = subprocess.run([sys.executable, "-c", _PROBE, str(path), str(data_limit), str(_PACKAGE.parent)],
                                capture_output=True, text=True, timeout=allowed)
    except subprocess.TimeoutExpired:
        raise InputError(f"cannot read {label} {Path(path).name} as netCDF: reading it did not finish in "
                         f"{allowed:.0f} s, so it is probably damaged") from None
    if result.returncode != 0:
        lines = [line for line in result.stderr.strip().splitlines() if line.strip()]
        reason = (lines[-1][:160] if lines and result.returncode > 0 else
                  f"the netCDF library crashed reading it (signal {-result.returncode})")
        raise InputError(f"cannot read {label} {Path(path).name} as netCDF ({reason})")
    finding = result.stdout.strip().splitlines()[-1] if result.stdout.strip() else ""
    if not refuse_changed:
        return finding or None
    if finding in _CHECKSUM_FINDINGS:
        raise InputError(f"{label} {Path(path).name} {_CHECKSUM_FINDINGS[finding]}")
    if finding == "unsealed":
        warnings.warn(f"{label} {Path(path).name} was written by a faultslip that did not yet seal its netCDF files "
                      "with a checksum: it is read unchecked", stacklevel=3)
    return None


def open_netcdf(path, label: str):
    """A netCDF file loaded into memory as an xarray Dataset; any failure to read it is one sentence."""
    import xarray as xr  # heavy: imported where used

    path = Path(path)
    probe_netcdf(path, label)  # through the gate first
    with gate.decoding(path, label, "netCDF", silence=True):
        with xr.open_dataset(path) as opened:
            return opened.load()


@contextlib.contextmanager
def open_dataset_lazily(path, label: str, *, zarr: bool = False, checked: bool = False):
    """A netCDF file (or a Zarr store) opened lazily with dask chunks, through the gate: what a finished study
    is read back with, chunk by chunk. ``checked``: the file was probed already (one this run wrote).

    Inside the block, dask computes on this process's threads: a file on this machine is read where it lies, and
    dask, asked by name for any scheduler, first imports distributed to look for a client (0.2 s, and up to a
    second of CPU on a busy host, in every sweep that counts its cells)."""
    import dask.threaded  # heavy: imported where used
    import xarray as xr  # heavy: imported where used

    path = Path(path)
    if not checked:
        if zarr:
            gate.check_input(path, label, store=True)
        else:
            probe_netcdf(path, label)  # through the gate first
    with gate.decoding(path, label, "a Zarr store" if zarr else "netCDF", silence=True):
        opened = xr.open_zarr(path) if zarr else xr.open_dataset(path, chunks={})
    with opened, dask.config.set(scheduler=dask.threaded.get):  # a callable: no scheduler looked up by name
        yield opened


def stored_block_digests(path, blocks: list, dims: list, *, zarr: bool = False) -> list:
    """The digest (:func:`faultslip.io.chunks.block_digest`) of each block ({dimension: slice}) of a study's output
    as stored: raw values, fill values as they are, outputs on the study's ``dims``. What a resume checks the
    partial file's blocks by."""
    import xarray as xr  # heavy: imported where used

    with gate.decoding(path, "the partial output", "a Zarr store" if zarr else "netCDF", silence=True):
        opened = (xr.open_zarr(path, mask_and_scale=False, decode_times=False, chunks=None) if zarr else
                  xr.open_dataset(path, engine="netcdf4", mask_and_scale=False, decode_times=False))
        with opened as dataset:
            outputs = [name for name in dataset.data_vars if set(dataset[name].dims) == set(dims)]
            found = []
            for block in blocks:
                region = dataset.isel(block) if dims else dataset
                found.append(block_digest({name: region[name].transpose(*dims).values for name in outputs}))
    return found


def read_numeric_csv(path, label: str) -> dict:
    """:func:`read_unit_csv` with every cell a number: ``{name: (values, unit)}``."""


    header, rows = read_unit_csv(path, label)
    columns = {name: [] for name, _ in header}
    for line, cells in rows:
        for (name, _), cell in zip(header, cells):
            try:
                columns[name].append(float(cell))
            except ValueError:
                raise InputError(f"{label}, row {line}: {name} {cell!r} is not a number") from None
    return {name: (np.array(columns[name]), unit) for name, unit in header}


#: Most columns, and most cells (rows x columns), a workbook's sheet may declare: a record of a million rows of
#: twenty columns fits; a sheet that declares more (one stray cell at XFD1048576 declares 1.7e10) is refused from
#: its dimension, before a row is read.
MAX_WORKBOOK_COLUMNS, MAX_WORKBOOK_CELLS = 1024, 20_000_000
_DIMENSION = re.compile(rb'<(?:\w+:)?dimension\s+ref="\$?([A-Z]{1,3})\$?(\d+)(?::\$?([A-Z]{1,3})\$?(\d+))?"')


def _column_number(letters: bytes) -> int:
    number = 0
    for letter in letters:
        number = number * 26 + letter - 64
    return number


def _open_workbook(path, label: str):
    """An Excel workbook through the gate, bounded before openpyxl reads it: its zip members by their declared
    sizes and ratios (:func:`faultslip.io.gate.open_zip`), each sheet by the dimension it declares."""
    try:
        from openpyxl import load_workbook  # heavy and optional (the xlsx extra): imported where used
    except ImportError:
        raise InputError(f"{label} is an Excel workbook: reading it needs openpyxl (pip install 'faultslip[xlsx]'), "
                         "or save it as CSV") from None
    data = gate.read_bytes(path, label, "table")
    archive = gate.open_zip(data, path, label, total_limit=gate.LIMITS["table"])
    for info in archive.infolist():
        if not (info.filename.startswith("xl/worksheets/") and info.filename.endswith(".xml")):
            continue
        with gate.decoding(path, label, "an Excel workbook"):
            with archive.open(info) as stream:
                head = stream.read(65536)
        found = _DIMENSION.search(head)
        if found is None:
            continue
        last_column, last_row = found.group(3) or found.group(1), found.group(4) or found.group(2)
        columns = _column_number(last_column) - _column_number(found.group(1)) + 1
        rows = int(last_row) - int(found.group(2)) + 1
        if columns > MAX_WORKBOOK_COLUMNS or rows * columns > MAX_WORKBOOK_CELLS:
            span = f"{found.group(1).decode()}{found.group(2).decode()}:{last_column.decode()}{last_row.decode()}"
            raise InputError(f"{label}: a sheet spans {span} ({rows:,} rows of {columns:,} columns), past the "
                             f"{MAX_WORKBOOK_CELLS:,} cells and {MAX_WORKBOOK_COLUMNS:,} columns a record may have; "
                             "clear the cells outside the table, or save it as CSV")
    with gate.decoding(path, label, "an Excel workbook"):
        return load_workbook(BytesIO(data), read_only=True, data_only=True)


def read_numeric_xlsx(path, label: str) -> dict:
    """The first sheet of an Excel workbook (``.xlsx``) as a table: its first row names the columns, each
    ``name (unit)`` as in a CSV header, and every row below holds numbers (empty rows at the end are dropped):
    ``{name: (values, unit)}``. Read through openpyxl (the ``xlsx`` extra), cached values, no formulas run,
    bounded before it is read (:func:`_open_workbook`) and streamed a row at a time into arrays; every problem is
    one sentence naming ``label`` and the cell."""
    workbook = _open_workbook(path, label)
    try:
        with gate.decoding(path, label, "an Excel workbook"):
            sheet = workbook.worksheets[0]
            first = next(sheet.iter_rows(max_row=1, max_col=MAX_WORKBOOK_COLUMNS, values_only=True), ())
        width = max((index + 1 for index, cell in enumerate(first) if cell is not None), default=0)
        if not width:
            raise InputError(f"{label}: the first row of its first sheet names no column")
        header = []
        for column, cell in enumerate(first[:width], start=1):
            if not isinstance(cell, str) or not cell.strip():
                raise InputError(f"{label}: column {column} of the header row has no name ({cell!r})")
            header.append(split_header(cell))
        if len({name for name, _ in header}) != len(header):
            raise InputError(f"{label}: two columns of the header row have one name")
        columns = [array("d") for _ in header]
        blank_since = None  # the first of a run of empty rows: allowed only at the end
        with gate.decoding(path, label, "an Excel workbook"):
            rows = sheet.iter_rows(min_row=2, max_col=width, values_only=True)
            for number, row in enumerate(rows, start=2):
                cells = list(row) + [None] * (width - len(row))
                if all(cell is None for cell in cells):
                    blank_since = blank_since or number
                    continue
                if blank_since is not None:
                    raise InputError(f"{label}, row {blank_since}: an empty row inside the table")
                if (number - 1) * width > MAX_WORKBOOK_CELLS:
                    raise InputError(f"{label}: more than {MAX_WORKBOOK_CELLS:,} cells of numbers; save it as CSV")
                for values, (name, _), cell in zip(columns, header, cells):
                    if isinstance(cell, bool) or not isinstance(cell, (int, float)):
                        raise InputError(f"{label}, row {number}: {name} {cell!r} is not a number")
                    values.append(float(cell))
    finally:
        workbook.close()
    if not columns[0]:
        raise InputError(f"{label}: its first sheet needs a header row and at least one row of numbers")
    return {name: (np.frombuffer(values, dtype=float).copy(), unit) for (name, unit), values in zip(header, columns)}


#: a workbook sheet of this name (any case) holds a record's metadata: one key and value a row
METADATA_SHEET = "metadata"
#: Rows of a metadata sheet read (a record's metadata is tens of keys).
MAX_METADATA_ROWS = 10_000


def read_table_metadata(path, label: str) -> dict:
    """A record's own metadata: an Excel workbook's ``metadata`` sheet (a key and a value a row, e.g.
    ``normal_stress | 10 MPa``, ``experiment | p655``), or a netCDF file's global attributes; {} for other kinds.
    Values stay as written (text with units is read where it is used); every problem is one sentence."""
    suffix = Path(path).suffix.lower()
    if suffix == ".nc":
        with gate.decoding(path, label, "netCDF attributes"):
            import netCDF4  # heavy: imported where used

            with netCDF4.Dataset(str(path)) as dataset:
                return {key: _plain_attribute(dataset.getncattr(key)) for key in dataset.ncattrs()}
    if suffix != ".xlsx":
        return {}
    try:
        import openpyxl  # noqa: F401  heavy and optional (the xlsx extra): imported where used
    except ImportError:
        return {}
    workbook = _open_workbook(path, label)
    with gate.decoding(path, label, "an Excel workbook"):
        sheets = [sheet for sheet in workbook.worksheets if sheet.title.strip().lower() == METADATA_SHEET]
        # a key and a value a row: two columns, and no more rows than a sheet of metadata has
        rows = [list(row) for row in sheets[0].iter_rows(max_col=2, max_row=MAX_METADATA_ROWS + 1, values_only=True)] \
            if sheets else []
        workbook.close()
    if len(rows) > MAX_METADATA_ROWS:
        raise InputError(f"{label}: its metadata sheet has more than {MAX_METADATA_ROWS:,} rows; a record's metadata "
                         "is a key and a value a row")
    metadata = {}
    for number, row in enumerate(rows, start=1):
        if not row or all(cell is None for cell in row):
            continue
        key, value = (row + [None, None])[:2]
        if not isinstance(key, str) or not key.strip() or value is None:
            raise InputError(f"{label}: row {number} of its metadata sheet must hold a key and a value, got {row[:2]}")
        if key.strip() in metadata:
            raise InputError(f"{label}: its metadata sheet gives {key.strip()!r} twice")
        metadata[key.strip()] = value if isinstance(value, (int, float, str)) and not isinstance(value, bool) \
            else str(value)
    return metadata


def _plain_attribute(value):
    """A netCDF attribute as JSON has it."""
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    return value


def read_numeric_table(path, label: str) -> dict:
    """A table by its suffix: whitespace text (``.txt``, ``.dat``, ``.tsv``), an Excel workbook (``.xlsx``) or
    CSV: ``{name: (values, unit)}``."""
    suffix = Path(path).suffix.lower()
    if suffix in (".txt", ".dat", ".tsv"):
        return read_numeric_text(path, label)
    if suffix == ".xlsx":
        return read_numeric_xlsx(path, label)
    return read_numeric_csv(path, label)


def read_numeric_text(path, label: str) -> dict:
    """A whitespace-delimited table as rigs write it: ``{name: (values, unit)}``.

    Lines starting with ``#`` are comments. The first other line names the columns, each name
    optionally with its unit as ``name(unit)`` or ``name[unit]``; a second line that is not numbers
    gives the units instead (``s mm kN kN``, or ``-`` for none). Every problem is one
    :class:`InputError` sentence naming ``label`` and the line."""
    gate.check_input(path, label, "table")
    try:
        with open(path, encoding="utf-8-sig") as handle:
            lines = [(number, line.split()) for number, line in enumerate(handle, start=1)
                     if line.strip() and not line.lstrip().startswith("#")]
    except UnicodeDecodeError:
        raise InputError(f"{label} is not text (UTF-8)") from None
    except OSError as exc:
        raise InputError(f"cannot read {label}: {exc.strerror or exc}") from None
    if not lines:
        raise InputError(f"{label} is empty")

    def numeric(cells):
        try:
            [float(cell) for cell in cells]
        except ValueError:
            return False
        return True

    header = []
    for token in lines[0][1]:
        for opening, closing in (("(", ")"), ("[", "]")):
            if token.endswith(closing) and opening in token:
                name, unit = token[:-1].split(opening, 1)
                header.append((name, unit or None))
                break
        else:
            header.append((token, None))
    rest = lines[1:]
    if rest and not numeric(rest[0][1]):
        number, units = rest[0]
        if len(units) != len(header):
            raise InputError(f"{label}, line {number}: {len(units)} units for {len(header)} columns")
        header = [(name, None if unit in ("-", "1") else unit.strip("()[]")) for (name, _), unit in zip(header, units)]
        rest = rest[1:]
    names = [name for name, _ in header]
    repeated = gate.repeated_names(names)
    if repeated:
        raise InputError(f"{label}: the column {repeated[0]!r} appears twice in the header")
    if not rest:
        raise InputError(f"{label} holds no rows of numbers under its header")
    columns = {name: [] for name in names}
    for number, cells in rest:
        if len(cells) != len(header):
            raise InputError(f"{label}, line {number}: {len(cells)} fields, expected {len(header)}")
        for name, cell in zip(names, cells):
            try:
                columns[name].append(float(cell))
            except ValueError:
                raise InputError(f"{label}, line {number}: {name} {cell!r} is not a number") from None
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


parse_toml = gate.parse_toml
check_toml_kind, toml_kind = gate.check_toml_kind, gate.toml_kind


def check_toml_layout(data: dict, tables: dict, source: str, what: str,
                      top_level=("name", "description", "family")) -> None:
    """One sentence for a TOML document's first unknown table or key.

    ``tables`` maps each allowed table to its allowed keys (None: any key); ``top_level`` are the
    plain values allowed outside tables; ``what`` names the document ("a vibration scene")."""
    unknown = sorted(set(data) - set(tables) - set(top_level))
    if unknown:
        listed = ", ".join(f"[{name}]" for name in tables)
        raise InputError(f"unknown table {unknown[0]!r} in {source} ({what} has {listed})")
    for table, allowed in tables.items():
        if table not in data:
            continue
        check_table_keys(data[table], allowed, table, source)


def check_table_keys(content, allowed, table: str, source: str) -> None:
    """``[table]`` must be a table whose keys are all in ``allowed`` (None: any key)."""
    if not isinstance(content, dict):
        raise InputError(f"[{table}] in {source} must be a table")
    if allowed is None:
        return
    extra = sorted(set(content) - set(allowed))
    if extra:
        raise InputError(f"unknown key {extra[0]!r} in [{table}] of {source} (allowed: {', '.join(sorted(allowed))})")


# --- scene files: one way to find and read them, for every family ------------------------------------


#: The kinds of bundled config, as a refusal lists them.
PLURALS = {"scene": "scenes", "study": "studies", "map": "maps", "example": "examples"}
#: Bundled files that are not examples of a data command's input.
_NOT_EXAMPLES = (".toml", ".py", ".md", ".json")


def bundled_examples() -> dict[str, Path]:
    """The bundled example inputs of the data commands (``fit``, ``record``, ``decay``, ``surface``, ``catalog``,
    ``reduce``, ``convert``), by file name: the records, catalogs and surfaces of ``configs/``, its Zarr store, and
    the rig files of ``data/p655``.

    Returns
    -------
    dict of str to pathlib.Path
        File name -> where the installed package holds it, sorted by name.
    """
    found = {}
    for folder in (bundled_dir("configs"), bundled_dir("data") / "p655"):
        for path in sorted(folder.iterdir()) if folder.is_dir() else ():
            if path.suffix in _NOT_EXAMPLES or path.name == "LICENSE":
                continue
            if path.is_file() or (path.is_dir() and path.suffix == ".zarr"):
                found[path.name] = path
    return dict(sorted(found.items()))


def resolve_path(argument, what: str, base_dir: Path | None = None, kind: str = "scene") -> tuple[Path, str]:
    """A file argument as ``(path, origin)``: paths are paths, and only a bare name may mean a bundled file.

    A path with a folder in it (``configs/x.toml``, ``./x.toml``) must exist. A bare name
    (``x.toml`` or ``x``) is looked up in ``base_dir`` (or the current folder) first and then
    among the bundled configs; ``origin`` then says that the bundled file was used. A name found in neither
    is refused, listing the bundled configs of ``kind`` ("scene", "study" or "map": :func:`bundled_configs`).
    ``kind="example"`` looks a bare name up among :func:`bundled_examples` instead (by file name, or by its stem
    where one example has it), and leaves a folder to the command's reader (a Zarr store is one).
    """
    text = str(argument)
    if not text.strip():
        raise InputError(f"{what}: the file name is empty")
    path = Path(text)
    bare = path.name == text and not path.is_absolute()
    local = (base_dir / path) if (base_dir is not None and not path.is_absolute()) else path
    try:  # a name the system cannot look up (too long, a folder unreadable) is the input's fault: one sentence
        exists, folder, link = local.exists(), local.is_dir(), local.is_symlink()
        bundled = None if not bare or kind == "example" else \
            config_path(path.name if path.suffix else f"{path.name}.toml")
        bundled = bundled if bundled is not None and bundled.is_file() else None
    except (OSError, ValueError) as exc:
        raise InputError(f"cannot look up {what} {text[:80]!r}: {getattr(exc, 'strerror', None) or exc}") from None
    if exists:
        if folder and kind != "example":  # a data command's reader says whether it takes a folder
            raise InputError(f"{what} {text!r} is a folder, not a file")
        return local, ""
    if link:  # a broken link here is the user's file gone missing, not a call for the bundled one
        raise InputError(f"{what} {text!r} is a link to a file that does not exist")
    if bare and kind == "example":
        examples = bundled_examples()
        by_stem = [name for name in examples if Path(name).stem == text]
        name = text if text in examples else by_stem[0] if len(by_stem) == 1 else None
        if name is not None:
            return examples[name], f"bundled example {name} (no file {text!r} here)"
        raise InputError(f"{what} {text!r} does not exist here or among the bundled examples "
                         f"({', '.join(examples)})")
    if bare:
        if bundled is not None:
            return bundled, f"bundled {what} {bundled.name} (no file {text!r} here)"
        raise InputError(f"{what} {text!r} does not exist here or among the bundled configs "
                         f"(the {PLURALS.get(kind, kind)}: {', '.join(bundled_configs(kind))})")
    raise InputError(f"{what} {text!r} does not exist")


def read_text_file(path: Path, what: str) -> str:
    """A UTF-8 config file through the gate (:func:`faultslip.io.gate.read_text`)."""
    return gate.read_text(path, what, "config")


def scene_document(argument) -> dict | None:
    """A scene argument's parsed TOML, to tell scene kinds apart (nanoscale, vibration, seed law); None for
    anything unreadable, which the reader of the kind then reports in its own words."""
    try:
        path, _ = resolve_path(argument, "scene")
        return parse_toml(read_text_file(path, "scene file"), path.name)
    except InputError:
        return None


def bundled_configs(kind: str = "scene") -> list[str]:
    """The bundled TOML configs of one kind: ``"scene"`` (of any family), ``"study"`` or ``"map"``
    (:func:`faultslip.io.gate.toml_kind`).

    Parameters
    ----------
    kind : str
        "scene", "study" or "map".

    Returns
    -------
    list of str
        Their file names, sorted.
    """
    names = []
    for path in sorted(bundled_dir("configs").glob("*.toml")):
        try:
            document = tomllib.loads(path.read_text(encoding="utf-8"))
        except (tomllib.TOMLDecodeError, UnicodeDecodeError):  # not one of ours: listed as no kind
            continue
        if gate.toml_kind(document) == kind:
            names.append(path.name)
    return names


def bundled_scenes() -> list[str]:
    """Bundled scene files (configs/ also holds studies and maps, which are not scenes)."""
    return sorted(p.name for p in bundled_dir("configs").glob("*.toml")
                  if "[scene]" in p.read_text(encoding="utf-8").splitlines())
