"""One way in: every file faultslip reads passes this gate.

The gate checks a path before a byte is read, and turns whatever a decoder raises into one
sentence that names the file:

* :func:`check_input` accepts a regular file (or, where asked, a directory store) and refuses a
  device, FIFO or socket (``/dev/zero`` would never end) and anything larger than the limit of
  its kind, naming the limit;
* :func:`read_bytes` and :func:`read_text` read at most that limit, so a file that grows, or a
  ``/proc`` file whose size says 0, cannot exhaust memory;
* :func:`parse_toml` bounds the nesting depth before the recursive TOML parser sees the text;
* :func:`decoding` wraps a third-party decoder (netCDF/HDF5, zlib, zarr, obspy, lxml, json,
  csv, UTF-8): any exception it raises becomes an :class:`~faultslip.errors.InputError`, and
  :func:`quiet` keeps the libraries' own stderr chatter (``Exception ignored ...``, multi-line
  warnings) from reaching the user.

A new reader uses these and never guards itself.
"""

from __future__ import annotations

import contextlib
import gc
import hashlib
import io
import json
import os
import stat
import sys
import warnings
import zipfile
from collections import Counter
from pathlib import Path

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    import tomli as tomllib

from faultslip.errors import FaultslipError, InputError

MiB = 2**20
#: Largest file of each kind read whole; :func:`check_input` refuses larger ones before reading.
LIMITS = {
    "config": 16 * MiB,  # TOML scenes, studies, maps; the fit registry
    "table": 512 * MiB,  # CSV and whitespace tables: lab data, records, segments, catalogs
    "geojson": 64 * MiB,
    "netcdf": 2048 * MiB,
    "waveform": 512 * MiB,  # miniSEED, SAC
    "catalog": 256 * MiB,  # QuakeML
    "bundle": 1024 * MiB,  # fit bundles (a record, its report and draws, zipped)
}
#: Deepest nesting of arrays and inline tables accepted in TOML (real files use 2 or 3).
MAX_TOML_DEPTH = 32


def json_checksum(record: dict, skip: str = "checksum") -> str:
    """SHA-256 of a JSON record's content, its own ``skip`` key left out, keys sorted: what a progress ledger or a
    fit bundle's manifest carries of itself, so that one edited after writing no longer matches."""
    body = {key: value for key, value in record.items() if key != skip}
    return hashlib.sha256(json.dumps(body, sort_keys=True, default=str).encode("utf-8")).hexdigest()


def repeated_names(names) -> list:
    """The names given more than once, sorted: in linear time (a 20,000-column header took a minute when each name
    was counted across the list)."""
    return sorted(name for name, count in Counter(names).items() if count > 1)


def size_text(n: float) -> str:
    """A byte count as people read it: "1.5 GiB", "12 MiB", "3 kiB"."""
    return f"{n / 2**30:.1f} GiB" if n >= 2**30 else f"{n / MiB:.0f} MiB" if n >= MiB else f"{n / 1024:.0f} kiB"


def check_input(path, label: str, kind: str = "table", *, store: bool = False, limit: int | None = None) -> Path:
    """``path`` as a Path if it is a readable regular file (or, with ``store``, a folder) within the limit.

    Refused in one sentence: a missing path, a folder (unless ``store``), a device, FIFO or socket,
    and a file larger than ``LIMITS[kind]`` (or ``limit``).
    """
    path = Path(path)
    limit = LIMITS[kind] if limit is None else limit
    try:
        info = path.stat()
    except FileNotFoundError:
        raise InputError(f"{label} {str(path)!r} does not exist") from None
    except OSError as exc:
        raise InputError(f"cannot read {label} {str(path)!r}: {exc.strerror or exc}") from None
    if stat.S_ISDIR(info.st_mode):
        if store:
            return path
        raise InputError(f"{label} {str(path)!r} is a folder, not a file")
    if not stat.S_ISREG(info.st_mode):
        what = ("a device" if stat.S_ISCHR(info.st_mode) or stat.S_ISBLK(info.st_mode) else
                "a pipe" if stat.S_ISFIFO(info.st_mode) else "a socket" if stat.S_ISSOCK(info.st_mode) else
                "not a regular file")
        raise InputError(f"{label} {str(path)!r} is {what}; faultslip reads regular files only")
    if info.st_size > limit:
        raise InputError(f"{label} {str(path)!r} is {size_text(info.st_size)}; the limit for such a file is "
                         f"{size_text(limit)}")
    if not os.access(path, os.R_OK):
        raise InputError(f"cannot read {label} {str(path)!r}: permission denied")
    return path


def read_bytes(path, label: str, kind: str = "table", limit: int | None = None) -> bytes:
    """The checked file's bytes, reading no more than its limit whatever the file claims."""
    path = check_input(path, label, kind, limit=limit)
    limit = LIMITS[kind] if limit is None else limit
    try:
        with open(path, "rb") as handle:
            data = handle.read(limit + 1)
    except OSError as exc:
        raise InputError(f"cannot read {label} {str(path)!r}: {exc.strerror or exc}") from None
    if len(data) > limit:
        raise InputError(f"{label} {str(path)!r} is larger than the limit for such a file, {size_text(limit)}")
    return data


def read_head(path, label: str, kind: str = "table", size: int = 65536) -> bytes:
    """At most the first ``size`` bytes of a checked file (a header to sniff), whatever its length."""
    path = check_input(path, label, kind)
    try:
        with open(path, "rb") as handle:
            return handle.read(size)
    except OSError as exc:
        raise InputError(f"cannot read {label} {str(path)!r}: {exc.strerror or exc}") from None


def read_json(path, label: str, kind: str = "config"):
    """A JSON file through the gate; anything unreadable is one sentence naming it."""
    text = read_text(path, label, kind)
    with decoding(path, label, "JSON"):
        return json.loads(text)


def read_text(path, label: str, kind: str = "config", limit: int | None = None) -> str:
    """The checked file as UTF-8 text (a byte-order mark is dropped)."""
    data = read_bytes(path, label, kind, limit)
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise InputError(f"{label} {str(path)!r} is not UTF-8 text (byte {exc.start}); save it as UTF-8") from None


def toml_depth(text: str) -> int:
    """The deepest nesting of ``[`` and ``{`` in TOML ``text`` outside strings and comments."""
    depth = deepest = 0
    i, n = 0, len(text)
    while i < n:
        char = text[i]
        if char == "#":
            end = text.find("\n", i)
            i = n if end < 0 else end
            continue
        if char in "\"'":
            triple = text.startswith(char * 3, i)
            quote = char * 3 if triple else char
            j = i + len(quote)
            while j < n:
                if char == '"' and text[j] == "\\":
                    j += 2
                    continue
                if text.startswith(quote, j):
                    break
                if not triple and text[j] == "\n":
                    break
                j += 1
            i = j + len(quote)
            continue
        if char in "[{":
            depth += 1
            deepest = max(deepest, depth)
        elif char in "]}":
            depth = max(depth - 1, 0)
        i += 1
    return deepest


def parse_toml(text: str | dict, source: str) -> dict:
    """Parse TOML text; a syntax error or nesting beyond :data:`MAX_TOML_DEPTH` is one sentence naming ``source``.

    A document parsed already (a sweep cell's scene, :class:`faultslip.contract.scenes.TomlScene`) is
    returned as it is, so a family's reader takes either."""
    if isinstance(text, dict):
        return text
    if toml_depth(text) > MAX_TOML_DEPTH:
        raise InputError(f"{source} nests arrays or tables more than {MAX_TOML_DEPTH} deep; faultslip reads "
                         "TOML nested at most that deep")
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{source} is not valid TOML: {exc}") from None
    except RecursionError:  # defence in depth: the depth scan should have refused it
        raise InputError(f"{source} nests arrays or tables too deep to read") from None


#: faultslip's TOML files by kind: the tables that make one (any of them), and the command that takes it
TOML_KINDS = {"study": (("study", "sweep"), "faultslip sweep {source} -o OUTPUT"),
              "map": (("map",), "faultslip map {source} -o OUTPUT")}


def toml_kind(document: dict) -> str:
    """What a parsed faultslip TOML file is: a study, a map, or (any other) a scene."""
    for kind, (tables, _) in TOML_KINDS.items():
        if any(table in document for table in tables):
            return kind
    return "scene"


def check_toml_kind(document: dict, source: str, wanted: str) -> None:
    """Refuse, in one sentence saying what takes it, a study, map or scene file given where another kind is
    read (a study to 'faultslip run' had been refused as a scene with an unknown table [study])."""
    kind = toml_kind(document)
    if kind == wanted:
        return
    if kind == "scene":
        raise InputError(f"{source} is a scene, not a {wanted} (a {wanted} has a "
                         f"{' or '.join(f'[{t}]' for t in TOML_KINDS[wanted][0])} table): "
                         f"'faultslip run {source}' runs it, and a {wanted} names a scene as its base")
    command = TOML_KINDS[kind][1].format(source=source)
    base = document.get(kind, {}).get("base") if isinstance(document.get(kind), dict) else None
    based = f" (its base scene, {base}, is one)" if isinstance(base, str) and wanted == "scene" else ""
    raise InputError(f"{source} is a {kind}, not a {wanted}: '{command}' runs it; this command takes a "
                     f"{wanted}{based}")


def read_toml(path, label: str) -> dict:
    """A TOML file through the gate."""
    path = Path(path)
    return parse_toml(read_text(path, label, "config"), path.name)


def _first_line(exc: BaseException) -> str:
    text = " ".join(str(exc).split())
    return (text[:160] or type(exc).__name__)


@contextlib.contextmanager
def quiet():
    """Silence what decoding libraries print behind our back: warnings, unraisable-exception reports
    (``Exception ignored in ...``, from finalisers run by the garbage collector) and the C-level stderr."""
    hook = sys.unraisablehook
    sys.unraisablehook = lambda unraisable: None
    saved = None
    try:
        sys.stderr.flush()
        saved = os.dup(2)
        with open(os.devnull, "w") as null:
            os.dup2(null.fileno(), 2)
    except (OSError, ValueError, AttributeError):  # no real stderr (a notebook): the Python hooks suffice
        saved = None
    # what exists now is not the decoder's: frozen, the collection below scans only what the decoder made (a full
    # collection of a long session's heap took 0.5 s a file), every generation of it
    gc.freeze()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                yield
            finally:
                gc.collect()  # finalisers of half-built objects run now, while reports are swallowed
    finally:
        gc.unfreeze()
        if saved is not None:
            with contextlib.suppress(OSError, ValueError):
                sys.stderr.flush()
            os.dup2(saved, 2)
            os.close(saved)
        sys.unraisablehook = hook


@contextlib.contextmanager
def decoding(path, label: str, what: str, silence: bool = False):
    """Run a decoder of ``path``: any exception it raises becomes one sentence,
    "cannot read LABEL NAME as WHAT (reason)". ``silence`` also applies :func:`quiet`."""
    name = Path(path).name
    try:
        with (quiet() if silence else contextlib.nullcontext()):
            yield
    except FaultslipError:
        raise
    except (KeyboardInterrupt, SystemExit):
        raise
    except MemoryError:
        raise InputError(f"cannot read {label} {name} as {what}: it needs more memory than is available") from None
    except Exception as exc:  # noqa: BLE001  every decoder raises its own types; all mean "not readable"
        raise InputError(f"cannot read {label} {name} as {what} ({_first_line(exc)})") from None


#: Largest ratio of a zip member's size to its compressed size accepted above :data:`RATIO_FLOOR`: deflate
#: reaches about 1,000:1 on one repeated byte, where records, reports, workbooks and checkpoints compress
#: 2-30:1 (the shipped examples, and every file the test suite writes).
MAX_COMPRESSION_RATIO = 200
#: Members smaller than this are not held to the ratio (a small JSON of zeros compresses far).
RATIO_FLOOR = MiB


def open_zip(data: bytes, path, label: str, *, total_limit: int, member_limits: dict | None = None,
             member_limit: int | None = None):
    """A zip archive held in ``data``, checked before any member is inflated.

    Refused in one sentence naming the file: not a zip; a member name given twice (a later entry would shadow
    the first); a member whose declared size passes its limit (``member_limits[name]``, else ``member_limit``,
    else ``total_limit``); members that together pass ``total_limit``; a member larger than :data:`RATIO_FLOOR`
    compressed more than :data:`MAX_COMPRESSION_RATIO` to one (a zip bomb); an encrypted member. Python's
    zipfile stops inflating a member at its declared size (and fails its CRC beyond), so the declared sizes
    bound what any later read allocates.

    Returns
    -------
    zipfile.ZipFile
    """
    with decoding(path, label, "a zip archive"):
        archive = zipfile.ZipFile(io.BytesIO(data))
        members = archive.infolist()
    name = Path(path).name
    seen, total = set(), 0
    for info in members:
        if info.filename in seen:
            raise InputError(f"{label} {name} holds {info.filename!r} twice; one entry would shadow the other")
        seen.add(info.filename)
        if info.flag_bits & 0x1:
            raise InputError(f"{label} {name}: member {info.filename!r} is encrypted")
        limit = (member_limits or {}).get(info.filename, member_limit if member_limit is not None else total_limit)
        if info.file_size > limit:
            raise InputError(f"{label} {name}: member {info.filename!r} inflates to {size_text(info.file_size)}, past the "
                             f"limit of {size_text(limit)} for it")
        if info.file_size > RATIO_FLOOR and info.file_size > MAX_COMPRESSION_RATIO * max(info.compress_size, 1):
            raise InputError(f"{label} {name}: member {info.filename!r} is compressed "
                             f"{info.file_size / max(info.compress_size, 1):.0f} to 1, past the "
                             f"{MAX_COMPRESSION_RATIO} to 1 real files reach (a zip bomb?)")
        total += info.file_size
        if total > total_limit:
            raise InputError(f"{label} {name}: its members inflate to more than {size_text(total_limit)}, the limit "
                             "for such a file")
    return archive


def read_member(archive, member: str, path, label: str) -> bytes:
    """One member of an archive from :func:`open_zip`, its bytes (bounded by its checked declared size)."""
    with decoding(path, label, f"its member {member}"):
        return archive.read(member)

