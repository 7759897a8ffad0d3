"""Units at the boundary: parse quantities with pint, return SI floats.

Every quantity entering faultslip (CLI flag, TOML scene, public API) goes
through :func:`to_si`. It accepts a string such as ``"13 mi"`` or
``"0.25e6 bar"``, a :class:`pint.Quantity`, or a bare number when the caller
documents a default unit. Inside the package everything is SI.

The year is the Julian year, 365.25 d (pint's ``year``; pinned here and in the
tests). Seed 003 used 365 d, a 0.07 % difference.

pint loads on first need, not at import. Every factor pint gives for a unit text is kept in a
small file in the user's cache folder (:func:`_memo`), keyed to the installed pint, so that a
command whose units were seen before starts without pint (0.13 s of a closed-form answer's
0.5 s). A unit that is new, wrong or unknown always asks pint itself.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import importlib.util
import inspect
import json
import math
import numbers
import os
import re
import stat
import sys
import tempfile
from pathlib import Path

try:
    import fcntl
except ImportError:  # not POSIX: the unit memo is written unlocked
    fcntl = None

from faultslip.constants import JULIAN_YEAR, STANDARD_GRAVITY  # noqa: F401 (re-exported)
import numpy as np

from faultslip import ranges
from faultslip.errors import InputError



#: Seconds in one Julian year (365.25 d): the only year faultslip uses.
#: Standard gravity, used for a load given as a mass (W = M g).

_REGISTRY = None
#: Set by the command line: load pint with its probe for dask answered "absent". pint.compat
#: imports dask.base (0.1 s) only so that a Quantity can wrap a dask array; the command line never
#: makes one (its quantities are SI floats, its dask arrays stay bare inside xarray), and a later
#: ``import dask`` works as usual. The Python API leaves it False: a notebook may wrap dask arrays.
PINT_WITHOUT_DASK = False


def _import_pint():
    if not PINT_WITHOUT_DASK or "dask" in sys.modules or "pint" in sys.modules:
        import pint  # heavy: imported where used

        return pint
    sys.modules["dask"] = None  # find_spec("dask") is None while pint loads; removed at once below
    try:
        import pint  # heavy: imported where used
    finally:
        del sys.modules["dask"]
    return pint


def registry():
    """pint's registry, loaded on first use and built from its definitions cached on disk.

    Parsing pint's definition files takes about 0.2 s; with ``cache_folder`` pint keeps the
    parsed result in the user cache folder and a later start reads it in ~0.02 s. A cache folder
    that cannot be written only costs the parse.
    """
    global _REGISTRY
    if _REGISTRY is None:
        pint = _import_pint()  # 0.13 s: a command whose units are memoised never needs it
        try:
            built = pint.UnitRegistry(cache_folder=":auto:")
        except Exception:  # noqa: BLE001 (an unwritable or damaged cache must never stop faultslip)
            built = pint.UnitRegistry()
        if not math.isclose(built.Quantity(1, "year").to("s").magnitude, JULIAN_YEAR):
            raise ImportError("pint's year is not the Julian year; faultslip requires 365.25 d")
        _REGISTRY = built
    return _REGISTRY


def __getattr__(name):  # PEP 562: ``units`` and ``Quantity`` load pint when first asked for
    if name == "units":
        return registry()
    if name == "Quantity":
        return registry().Quantity
    raise AttributeError(f"module 'faultslip.units' has no attribute {name!r}")


def quantity(value, unit: str):
    """A pint Quantity of ``value`` in ``unit`` (pint loads on first use)."""
    return registry().Quantity(value, unit)


def is_quantity(value) -> bool:
    """Whether ``value`` is a pint Quantity; without pint loaded, nothing can be one."""
    pint = sys.modules.get("pint")
    return pint is not None and isinstance(value, pint.Quantity)


# --- pint's answers, memoised on disk ---------------------------------------------------------

_MEMO: dict | None = None
#: Entries kept at most: the file stays small however many units a user tries.
MEMO_ENTRIES = 4096


def _memo_path() -> Path:
    """The memo of this environment: its name carries a digest of the interpreter, its prefix (the virtual
    environment) and the pint install, so environments sharing a home folder never invalidate each other's."""
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "faultslip" / f"unit_factors-{_environment_key()}.json"


@functools.lru_cache(maxsize=1)
def _environment_key() -> str:
    text = "\x1f".join((sys.version, sys.prefix, sys.executable, _pint_fingerprint()))
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _pint_fingerprint() -> str:
    """Which pint answers: its installed file (path and modification time), found without importing it."""
    spec = importlib.util.find_spec("pint")
    origin = (spec.origin or "") if spec is not None else ""
    try:
        return f"{origin}:{os.stat(origin).st_mtime_ns}"
    except OSError:
        return origin


#: Bytes of the memo read at most (MEMO_ENTRIES entries of a unit text and its factor fit in well under this).
MEMO_BYTES = 4 * 2**20


def _memo_checksum(pint: str, factors: dict) -> str:
    """SHA-256 of a memo's pint fingerprint and factors (keys sorted, floats by repr)."""
    body = json.dumps({"pint": pint, "factors": factors}, sort_keys=True)
    return hashlib.sha256(body.encode("utf-8")).hexdigest()


def _read_memo_file(path: Path) -> bytes:
    """The memo's bytes, at most :data:`MEMO_BYTES`: opened without following a link and without waiting on a
    FIFO, and read only if it is a regular file (raises OSError otherwise). The core layer's own small version
    of the io gate's rule, which it cannot import."""
    flags = os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0)
    handle = os.open(path, flags)
    with os.fdopen(handle, "rb") as stream:
        if not stat.S_ISREG(os.fstat(stream.fileno()).st_mode):
            raise OSError(f"{path} is not a regular file")
        return stream.read(MEMO_BYTES)


def _stored_memo(path: Path) -> dict:
    """The factors a memo file holds, or {} where it is missing, damaged or stale."""
    try:
        stored = json.loads(_read_memo_file(path).decode("utf-8"))
        # checked before trusted: a memo whose factors do not match the digest written with them (one changed
        # digit shifted every chain magnitude by 0.67) is dropped, and pint answers afresh
        if (stored.get("pint") == _pint_fingerprint() and isinstance(stored.get("factors"), dict)
                and stored.get("checksum") == _memo_checksum(stored["pint"], stored["factors"])):
            return {key: (value[0], value[1]) for key, value in stored["factors"].items()
                    if isinstance(value, list) and len(value) == 2 and isinstance(value[0], float)
                    and math.isfinite(value[0]) and isinstance(value[1], str)}
    except (OSError, ValueError, AttributeError, TypeError):
        pass
    return {}


def _memo() -> dict:
    """The memo of pint's factors, read from disk once; a missing, damaged or stale memo is empty."""
    global _MEMO
    if _MEMO is None:
        _MEMO = _stored_memo(_memo_path())
    return _MEMO


@contextlib.contextmanager
def _memo_lock(path: Path):
    """An exclusive lock on ``path``'s lock file while its memo is read, merged and replaced: processes that
    learn units at once (a pool, a test run's workers) would otherwise each write their own reading and drop the
    others' entries. Where locks are not available the write goes on unlocked."""
    if fcntl is None:
        yield
        return
    flags = os.O_RDWR | os.O_CREAT | getattr(os, "O_NOFOLLOW", 0)
    try:
        handle = os.open(path.with_name(path.name + ".lock"), flags, 0o600)
    except OSError:
        yield
        return
    try:
        fcntl.flock(handle, fcntl.LOCK_EX)
        yield
    finally:
        os.close(handle)  # closing releases the lock


def _remember(key: str, answer: tuple) -> None:
    """Keep one of pint's answers: merged, under a lock, with what other processes wrote since this one read the
    memo; the file is replaced atomically, and a failed write costs nothing."""
    memo = _memo()
    memo[key] = answer
    path = _memo_path()
    temporary = None
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with _memo_lock(path):
            merged = {**_stored_memo(path), **memo}
            for old in list(merged)[: max(0, len(merged) - MEMO_ENTRIES)]:
                merged.pop(old)
            handle, temporary = tempfile.mkstemp(dir=path.parent, prefix=".unit_factors.", suffix=".tmp")
            factors = {k: list(v) for k, v in merged.items()}
            with os.fdopen(handle, "w", encoding="utf-8") as stream:
                json.dump({"pint": _pint_fingerprint(), "factors": factors,
                           "checksum": _memo_checksum(_pint_fingerprint(), factors)}, stream)
            os.replace(temporary, path)
            temporary = None
        memo.update(merged)
    except OSError:
        if temporary is not None:
            try:
                os.unlink(temporary)
            except OSError:
                pass


#: kind -> (pint dimensionality, SI unit string, phrase used in messages)
KINDS: dict[str, tuple[str, str, str]] = {
    "length": ("[length]", "m", "a length"),
    "area": ("[area]", "m^2", "an area"),
    "speed": ("[length]/[time]", "m/s", "a speed"),
    "time": ("[time]", "s", "a time"),
    "rate": ("1/[time]", "1/s", "a rate (1/time)"),
    "pressure": ("[pressure]", "Pa", "a stress"),
    "stress_per_length": ("[pressure]/[length]", "Pa/m", "a stiffness per area (stress/length)"),
    "force": ("[force]", "N", "a force"),
    "stiffness": ("[force]/[length]", "N/m", "a stiffness (force/length)"),
    "damping": ("[force]*[time]/[length]", "N*s/m", "a damping coefficient (force*time/length)"),
    "stress_damping": ("[pressure]*[time]/[length]", "Pa*s/m", "a damper per area (stress*time/length)"),
    "slowness": ("[time]/[length]", "s/m", "a friction-speed slope (time/length)"),
    "inverse_length": ("1/[length]", "1/m", "a stiffness per normal load (1/length, e.g. 1e-3 1/um)"),
    "mass": ("[mass]", "kg", "a mass"),
    "mass_per_area": ("[mass]/[area]", "kg/m^2", "a mass per area"),
    "density": ("[density]", "kg/m^3", "a density"),
    "moment": ("[energy]", "N*m", "a seismic moment (force*length)"),
    "moment_rate": ("[energy]/[time]", "N*m/s", "a moment rate (force*length/time)"),
    "frequency": ("1/[time]", "Hz", "a frequency (Hz, 1/s or rad/s)"),
    "acceleration": ("[acceleration]", "m/s^2", "an acceleration"),
    "dimensionless": ("[]", "", "dimensionless"),
    # a fault's dip, in degrees as geology writes it (inside, where trigonometry needs it, code takes radians)
    "angle": ("[]", "degree", "an angle"),
}

# Engineering usage writes loads in lb meaning pound-force. For these kinds a
# mass-based unit is accepted as a weight: multiplied by standard gravity.
_GRAVITATIONAL = {"force", "stiffness", "damping"}


def _dimensionality(kind: str):
    return registry().get_dimensionality(KINDS[kind][0])


def _describe(value) -> str:
    if is_quantity(value):
        return f"{value:~P}"
    return str(value)


# --- the one door for quantity text ----------------------------------------------------------
# pint's own parser evaluates arithmetic ("1/0 m", "10**400 m") and drops characters it does not
# know (U+2212 "−5 km" became +5 km), so text is first read by a small grammar of our own:
#   text     := [sign] number [unit] | unit-free number
#   unit     := term (("*" | "/" | " ") term)*
#   term     := factor [("^" | "**") exponent]
#   factor   := name | "(" unit ")" | "1" (only as the "1" of "1/s")
# and only then are the unit names looked up in pint.

#: Characters read as a minus sign: hyphen-minus, minus sign, figure dash, en dash, small and full-width hyphen-minus.
_MINUS_SIGNS = "\u2212\u2012\u2013\ufe63\uff0d"
_SPACE_LIKE = "\u00a0\u2009\u202f\u2007"
_NUMBER = re.compile(r"[+-]?\s*(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")
_TOKEN = re.compile(r"\s*(?:(?P<name>[^\W\d][\w°µμΩ]*|[°%][\w]*)|(?P<power>\*\*|\^)|(?P<op>[*/·⋅])"
                    r"|(?P<open>\()|(?P<close>\))|(?P<num>\d+(?:\.\d+)?)|(?P<sign>[+-]))")


def _normalise(text: str) -> str:
    for minus in _MINUS_SIGNS:
        text = text.replace(minus, "-")
    for space in _SPACE_LIKE:
        text = text.replace(space, " ")
    return text.strip()


def _tokens(unit_text: str, original: str, name: str):
    tokens, position = [], 0
    while position < len(unit_text):
        match = _TOKEN.match(unit_text, position)
        if match is None or match.end() == position:
            bad = unit_text[position:].strip()[:1]
            raise InputError(f"{name}: cannot read {original!r}: unexpected {bad!r} in the unit")
        position = match.end()
        kind = match.lastgroup
        tokens.append((kind, match.group(kind)))
    return tokens


def _check_unit_grammar(tokens, original: str, name: str) -> str:
    """Validate the token sequence; returns pint-ready unit text (``·`` as ``*``, ``^`` as ``**``)."""
    where = f"{name}: cannot read {original!r}"
    out, depth, index = [], 0, 0

    def fail(reason):
        raise InputError(f"{where}: {reason}")

    def exponent(i):
        # [sign] digits | "(" [sign] digits ["/" digits] ")"
        parts = []
        if i < len(tokens) and tokens[i][0] == "open":
            parts.append("(")
            i += 1
            if i < len(tokens) and tokens[i][0] == "sign":
                parts.append(tokens[i][1])
                i += 1
            if i >= len(tokens) or tokens[i][0] != "num":
                fail("an exponent must be a number")
            parts.append(tokens[i][1])
            i += 1
            if i < len(tokens) and tokens[i] == ("op", "/"):
                if i + 1 >= len(tokens) or tokens[i + 1][0] != "num":
                    fail("an exponent must be a number")
                parts += ["/", tokens[i + 1][1]]
                i += 2
            if i >= len(tokens) or tokens[i][0] != "close":
                fail("unbalanced brackets in an exponent")
            return "".join(parts) + ")", i + 1
        if i < len(tokens) and tokens[i][0] == "sign":
            parts.append(tokens[i][1])
            i += 1
        if i >= len(tokens) or tokens[i][0] != "num":
            fail("an exponent must be a number")
        return "".join(parts) + tokens[i][1], i + 1

    expect_factor = True
    while index < len(tokens):
        kind, text = tokens[index]
        if expect_factor:
            if kind == "name":
                out.append(text)
                index += 1
            elif kind == "open":
                out.append("(")
                depth += 1
                index += 1
                continue
            elif kind == "num" and text == "1" and index + 1 < len(tokens) and tokens[index + 1] == ("op", "/"):
                out.append("1")
                index += 1
            else:
                fail("a unit name is missing" if kind in ("op", "power", "close") or index == len(tokens)
                     else f"unexpected {text!r} in the unit")
            expect_factor = False
            continue
        if kind == "power":
            value, index = exponent(index + 1)
            out.append("**" + value)
        elif kind == "close":
            depth -= 1
            if depth < 0:
                fail("unbalanced brackets")
            out.append(")")
            index += 1
        elif kind == "op":
            out.append("*" if text in "·⋅" else text)
            expect_factor = True
            index += 1
        elif kind in ("name", "open"):
            out.append(" ")  # implicit product: "N m"
            expect_factor = True
        else:
            fail(f"unexpected {text!r} in the unit")
    if expect_factor and tokens:
        fail("the unit ends with an operator")
    if depth != 0:
        fail("unbalanced brackets")
    return "".join(out)


@functools.lru_cache(maxsize=4096)
def _unit_factor(unit_text: str, kind: str):
    """(multiplier to the SI unit of ``kind``, note) for a pint-ready unit; raises pint errors or ValueError.

    pint's answer is memoised on disk (:func:`_memo`); a unit pint refuses is never memoised."""
    si = KINDS[kind][1]
    if si and kind != "angle" and unit_text in (si, si.replace("^", "**")):  # the kind's SI unit: 1 by definition
        return 1.0, ""
    key = f"{kind}\x1f{unit_text}"
    known = _memo().get(key)
    if known is not None:
        return known
    answer = _pint_unit_factor(unit_text, kind)
    _remember(key, (float(answer[0]), answer[1]))
    return answer


def _pint_unit_factor(unit_text: str, kind: str):
    units = registry()
    pint = _import_pint()
    dims = _dimensionality(kind)
    quantity = units.Quantity(1.0, unit_text)
    root = quantity.to_root_units()
    angular = "radian" in root._units
    if kind == "angle":
        if quantity.dimensionality != dims:
            raise pint.DimensionalityError(quantity.units, "degree")
        return quantity.to("degree").magnitude, "angle"
    if angular and kind == "frequency":  # an angular frequency: omega / (2 pi) in Hz
        quantity = quantity.to("radian/s")
        return quantity.magnitude / (2.0 * math.pi), "angular"
    if angular:
        raise ValueError("angle")
    if quantity.dimensionality != dims:
        if kind in _GRAVITATIONAL and quantity.dimensionality * units.get_dimensionality("[acceleration]") == dims:
            return (quantity * units.Quantity(STANDARD_GRAVITY, "m/s^2")).to(KINDS[kind][1]).magnitude, "weight"
        raise pint.DimensionalityError(quantity.units, KINDS[kind][1] or "dimensionless")
    si = KINDS[kind][1]
    return (quantity.to(si).magnitude if si else quantity.to("dimensionless").magnitude), ""


def unit_factor(unit_text: str, kind: str, name: str) -> float:
    """Multiplier from ``unit_text`` to the SI unit of ``kind`` (e.g. a CSV header's unit)."""
    if not isinstance(unit_text, str):
        raise InputError(f"{name}: the unit must be text such as \"m/s\", got {unit_text!r}")
    text = _normalise(unit_text)
    if not text:
        raise InputError(f"{name}: the unit is empty")
    if len(text) > 200:
        raise InputError(f"{name}: the unit is too long ({len(text)} characters)")
    clean = _check_unit_grammar(_tokens(text, unit_text, name), unit_text, name)
    return _lookup(clean, kind, name, unit_text)[0]


def _lookup(clean: str, kind: str, name: str, original: str):
    try:
        return _unit_factor(clean, kind)
    except Exception as error:  # pint raises many types on odd text; every one is the user's input
        raise _unit_error(error, clean, kind, name, original) from None


class _WrongKind(InputError):
    """A unit of another dimension than the kind asked for (:func:`takes_units` then tries the other kind)."""


def _unit_error(error, clean, kind, name, original) -> InputError:
    """One sentence for a unit pint refused (pint is loaded: it was asked)."""
    pint = _import_pint()

    try:
        raise error
    except pint.UndefinedUnitError as exc:
        unknown = ", ".join(repr(u) for u in getattr(exc, "unit_names", ()) or ()) or repr(clean)
        return InputError(f"{name}: unknown unit {unknown} in {original!r}; give a number with units such as "
                         f"{_example(kind)}")
    except pint.DimensionalityError:
        if kind == "dimensionless":
            return _WrongKind(f"{name} must be a dimensionless number, got {original}")
        return _WrongKind(f"{name} must be {KINDS[kind][2]} such as {_example(kind)}, got {original}")
    except ValueError as exc:
        if str(exc) == "angle":
            return InputError(f"{name} must be {KINDS[kind][2]}; an angle unit has no meaning here, got {original!r}")
        return InputError(f"{name}: cannot read {original!r}; give a number with units such as {_example(kind)}")
    except Exception:  # pint raises many types on odd text; every one is the user's input
        return InputError(f"{name}: cannot read {original!r}; give a number with units such as {_example(kind)}")


def parse_quantity_text(value: str, kind: str, name: str, default_unit: str | None = None) -> float:
    """The SI float of quantity text such as ``"13 mi"``, ``"−5 km"`` or ``"5e-11 1/s"``.

    Refuses (one :class:`InputError` sentence): a decimal comma (with the corrected text), an
    expression (``"1/0 m"``, ``"10**400 m"``), unbalanced brackets, a trailing operator, an
    unknown unit, the wrong dimension, and a value that overflows or is not finite.
    """
    text = _normalise(value)
    if not text:
        raise InputError(f"{name} must be {KINDS[kind][2]}, got an empty string")
    if len(text) > 200:
        raise InputError(f"{name}: the text is too long ({len(text)} characters); give a number with units")
    comma = re.search(r"\d,\d", text)
    if comma:
        fixed = re.sub(r"(\d),(\d)", r"\1.\2", text)
        raise InputError(f"{name}: {value!r} has a comma; write numbers with a decimal point and no thousands "
                         f"separator, e.g. {fixed!r}")
    if re.match(r"[+-]?\s*(nan|inf(inity)?)\b", text, re.IGNORECASE):
        raise InputError(f"{name} must be finite, got {value!r}")
    match = _NUMBER.match(text)
    if match is None:
        raise InputError(f"{name}: cannot read {value!r}; it must start with a number, e.g. {_example(kind)}")
    number_text = "".join(match.group(0).split())  # "- 5" or "-\r0": the sign may be spaced by any whitespace
    magnitude = float(number_text)
    if not math.isfinite(magnitude):
        raise InputError(f"{name}: {value!r} is out of range (a double holds about 1.8e308 at most)")
    rest = text[match.end():].strip()
    if not rest:
        if kind == "dimensionless":
            return magnitude
        return _bare(magnitude, kind, name, default_unit, KINDS[kind][2])
    if rest[0] == "/":  # "5 /s": the number is the numerator
        rest = "1" + rest
    if (rest[0].isdigit() and not re.match(r"1\s*/", rest)) or rest[0] == ".":
        raise InputError(f"{name}: cannot read {value!r}; put one number before the unit, e.g. {_example(kind)}")
    clean = _check_unit_grammar(_tokens(rest, value, name), value, name)
    factor, _ = _lookup(clean, kind, name, value)
    with np.errstate(over="ignore", invalid="ignore"):
        result = magnitude * factor
    if not math.isfinite(result):
        raise InputError(f"{name}: {value!r} is out of range in SI units")
    return result


def to_si(value, kind: str, name: str, default_unit: str | None = None):
    """Convert ``value`` to a float (or array) in the SI unit of ``kind``.

    Parameters
    ----------
    value : str, pint.Quantity, number or array
        ``"2 in/yr"``, ``Quantity(2, "in/yr")``, or a bare number when
        ``default_unit`` is given.
    kind : str
        One of :data:`KINDS`, e.g. ``"speed"``.
    name : str
        The physical name used in error messages, e.g. ``"slip rate"``.
    default_unit : str, optional
        Unit of a bare number. Without it a bare number is an error for a
        dimensional kind.

    Raises
    ------
    InputError
        With one sentence naming the input and what is allowed.
    """
    if kind not in KINDS:
        raise KeyError(kind)
    if isinstance(value, (bool, np.bool_)):
        raise InputError(f"{name} must be {KINDS[kind][2]}, got {value!r}")
    if isinstance(value, str):
        return parse_quantity_text(value, kind, name, default_unit)
    if is_quantity(value):
        try:
            magnitude = np.asarray(value.magnitude, dtype=float)
            unit_text = str(value.units)
        except (TypeError, ValueError):
            raise InputError(f"{name} must be a number with units, got {value!r}") from None
        factor, _ = _lookup(unit_text, kind, name, _describe(value))
        with np.errstate(over="ignore", invalid="ignore"):
            return _finite(magnitude * factor, name)
    return _bare(value, kind, name, default_unit, KINDS[kind][2])


def to_si_scalar(value, kind: str, name: str, default_unit: str | None = None) -> float:
    """:func:`to_si` for one value from a file: a list, table, date or boolean is refused."""
    if isinstance(value, bool) or not (isinstance(value, (str, int, float)) or is_quantity(value)):
        raise InputError(f"{name} must be a single value such as {_example(kind)}, got {_short(value)}")
    result = to_si(value, kind, name, default_unit)
    if np.ndim(result):
        raise InputError(f"{name} must be a single value such as {_example(kind)}, got {_short(value)}")
    return float(result)


def _bare(value, kind, name, default_unit, phrase):
    if kind == "dimensionless":
        return _finite(_as_float(value, name), name)
    if default_unit is None:
        what = "the bare number" if isinstance(value, numbers.Real) else "a value without units,"
        raise InputError(f"{name} must be {phrase} with units, such as {_example(kind)}; got {what} {_short(value)}")
    factor = unit_factor(default_unit, kind, name)
    with np.errstate(over="ignore", invalid="ignore"):
        return _finite(_as_float(value, name) * factor, name)


def _as_float(value, name):
    try:
        if isinstance(value, numbers.Real):
            return float(value)
        array = np.asarray(value, dtype=float)
    except OverflowError:
        raise InputError(f"{name}: {value!r} is out of range (a double holds about 1.8e308 at most)") from None
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number, got {_short(value)}") from None
    return array


def _short(value) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _finite(magnitude, name):
    array = np.asarray(magnitude, dtype=float)
    if not np.all(np.isfinite(array)):
        raise InputError(f"{name} must be finite, got {_short(magnitude)} (NaN, infinity or out of range)")
    return float(array) if array.ndim == 0 else array


_EXAMPLES = {
    "length": '"13 mi" or "20 km"',
    "area": '"1 mm^2"',
    "speed": '"2 in/yr" or "24 mm/yr"',
    "time": '"100 yr" or "3 ms"',
    "rate": '"5e-11 1/s"',
    "pressure": '"250 bar" or "25 MPa"',
    "stress_per_length": '"4.4 psi/in" or "1.2 MPa/km"',
    "force": '"225.8 lbf" or "1 kN"',
    "stiffness": '"1.94e4 lbf/in"',
    "damping": '"3.7e-3 lbf*s/in"',
    "stress_damping": '"3.8 MPa*s/m"',
    "slowness": '"0.01 s/m"',
    "inverse_length": '"1e-3 1/um" (friction per slip)',
    "mass": '"102 kg"',
    "mass_per_area": '"5.6e7 kg/m^2"',
    "density": '"2700 kg/m^3"',
    "moment": '"8e20 N*m"',
    "frequency": '"19.9 Hz" or "125 rad/s"',
    "moment_rate": '"1e17 N*m/yr"',
    "acceleration": '"9.81 m/s^2" or "1 g_0"',
    "dimensionless": "0.65",
    "angle": '"60 deg" or "1.047 rad"',
}


def _example(kind: str) -> str:
    return _EXAMPLES[kind]


def si_unit(kind: str) -> str:
    """The SI unit string faultslip uses for ``kind`` (pint- and udunits-parsable)."""
    return KINDS[kind][1]


def quantity_json(value, unit: str) -> dict:
    """``{"value": number, "units": unit}``: the JSON form of every quantity (a range: a list)."""
    if isinstance(value, (list, tuple)):
        return {"value": [_json_number(v) for v in value], "units": unit}
    return {"value": _json_number(value), "units": unit}


def _json_number(value):
    if value is None:  # a bound that does not exist (an unbounded range)
        return None
    value = float(value)
    # JSON has no NaN or infinity; null means "does not exist" (e.g. no recurrence).
    return None if not math.isfinite(value) else value


def convert(value_si, si: str, target: str) -> float:
    """Convert an SI magnitude to ``target`` units (for human-readable reports)."""
    return value_si * _conversion(si, target)


@functools.lru_cache(maxsize=256)
def _conversion(si: str, target: str) -> float:
    """The factor from ``si`` to ``target`` (multiplicative units only), memoised like unit factors."""
    key = f"convert\x1f{si}\x1f{target}"
    known = _memo().get(key)
    if known is not None:
        return known[0]
    units = registry()
    if units.Quantity(0.0, si).to(target).magnitude != 0.0:
        raise ValueError(f"{si} to {target} is not a multiplicative conversion")
    factor = float(units.Quantity(1.0, si).to(target).magnitude)
    _remember(key, (factor, ""))
    return factor


#: CF attributes of a run's model time. It is an elapsed time in seconds, not a date: CF's time
#: axis (``axis = "T"``) needs an epoch ("seconds since ..."), which a run has only when a user
#: dates it (``simulate --start-time`` dates the miniSEED stream and the QuakeML events).
ELAPSED_TIME_ATTRS = {"units": "s", "long_name": "time since the start of the run",
                      "comment": "elapsed model time, not a date; simulate --start-time dates the stream and events"}


# --- units at the Python API's boundary -----------------------------------------------------------
def _convertible(value) -> bool:
    """Whether :func:`takes_units` converts ``value``: text or a pint Quantity."""
    return isinstance(value, str) or is_quantity(value)


def takes_units(alternative_from: tuple | None = None, domains: dict | None = None, **declared):
    """Let a public function's named arguments be text or pint Quantities as well as numbers (MetPy's ``calc``).

    ``declared`` maps an argument to its kind (:data:`KINDS`), to ``"kind_a|kind_b"`` where it may be either of
    two (a lab's N/m or a fault's Pa/m), or to ``(kind, unit)`` where a bare number is in ``unit`` rather than
    SI (a moment rate in N m/yr). Text and Quantities are converted (:func:`to_si`, one sentence on a wrong
    unit) before the function runs; numbers, arrays and None pass unchanged, so the vectorised callers inside
    faultslip pay one type test per declared argument. Arguments with two kinds must agree on which: a stiffness
    in Pa/m with a load in N is refused; ``alternative_from`` = (argument, (value_a, value_b)) names the argument
    that says which (a slider's ``scale``, "lab" or "fault"). Decorating a class converts its constructor's
    arguments. The function still returns SI numbers.

    A converted value is also checked against its argument's physical range, where :data:`faultslip.ranges.RULES`
    has one by its name (or :data:`faultslip.ranges.ALIASES`'): "-10 km" for a rupture length is refused in one
    sentence. Its bounds apply where the value is in the rule's unit; otherwise (a fault's stiffness in Pa/m, a
    number in another unit) only its sign. A plain finite number (an int or float, numpy's scalars among them) is
    checked for its sign the same way: ``seismic_moment(3e10, -1e4, 1.2e4, 2.0)`` is refused as "-10 km" is; the
    bounds, which are a scene's, are not applied to it; arrays (the vectorised callers') and NaN or inf (a
    documented "no value", a limit) pass unchecked. ``domains`` maps an argument to the function's own rule
    (:data:`faultslip.ranges.NON_NEGATIVE`, say) where the function is defined beyond the scene's: the static
    friction at a loading rate of 0 is the rate law's limit mu_so; it then replaces the rule and its bounds.
    """
    specs = {}
    for name, spec in declared.items():
        kind, unit = spec if isinstance(spec, tuple) else (spec, None)
        kinds = tuple(kind.split("|"))
        if any(k not in KINDS for k in kinds) or len(kinds) > 2 or (unit is not None and len(kinds) > 1):
            raise KeyError(spec)
        specs[name] = (kinds, unit)
    domains = dict(domains or {})
    if set(domains) - set(specs) or set(domains.values()) - set(ranges.RULE_KINDS):
        raise KeyError(domains)

    def decorate(target):
        function = target.__init__ if inspect.isclass(target) else target
        signature = inspect.signature(function)
        missing = (set(specs) | ({alternative_from[0]} if alternative_from else set())) - set(signature.parameters)
        if missing:
            raise TypeError(f"{target.__qualname__} has no argument {sorted(missing)}")
        label = target.__name__
        positions = [(index, name) for index, name in enumerate(signature.parameters) if name in specs]

        @functools.wraps(function)
        def wrapper(*args, **kwargs):
            # only text or a Quantity in a declared place is converted: everything else goes straight through
            if not any(index < len(args) and _convertible(args[index]) for index, _ in positions) and \
                    not any(name in kwargs and _convertible(kwargs[name]) for _, name in positions):
                for index, name in positions:  # plain numbers: their sign only
                    value = args[index] if index < len(args) else kwargs.get(name)
                    if _plain_number(value):
                        _in_range(name, value, *specs[name], None, label, domains.get(name))
                return function(*args, **kwargs)
            try:
                bound = signature.bind(*args, **kwargs)
            except TypeError as error:
                raise InputError(f"{label}(): {error}") from None
            chosen = {}
            for name, value in bound.arguments.items():
                if name in specs and _convertible(value):
                    bound.arguments[name], chosen[name] = _declared_to_si(value, name, *specs[name])
                    _in_range(name, bound.arguments[name], *specs[name], chosen[name], label, domains.get(name))
                elif name in specs and _plain_number(value):
                    _in_range(name, value, *specs[name], None, label, domains.get(name))
            _same_alternative(chosen, specs, _named_alternative(bound, signature, alternative_from))
            return function(*bound.args, **bound.kwargs)

        wrapper.__units__ = dict(declared)
        if inspect.isclass(target):
            target.__init__ = wrapper
            target.__units__ = wrapper.__units__
            return target
        return wrapper

    return decorate


def _plain_number(value) -> bool:
    """A finite real scalar, not a bool: what :func:`takes_units` checks the sign of without converting it."""
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def _in_range(name: str, value, kinds: tuple, unit: str | None, chosen: int | None, label: str,
              domain: str | None = None) -> None:
    """Refuse an argument outside its physical range (:func:`faultslip.ranges.check`, by its name): a converted
    value (``chosen``, which of its kinds it was) within its bounds where it is in the rule's unit, a plain number
    (``chosen`` None) by its sign; where the function has its own ``domain``, by that rule alone."""
    rule = ranges.ALIASES.get(name, name)
    if rule not in ranges.RULES:
        return
    if chosen is None and (value > 0 if (domain or ranges.RULES[rule][0]) == ranges.POSITIVE else
                           value >= 0 if (domain or ranges.RULES[rule][0]) == ranges.NON_NEGATIVE else False):
        return  # a plain number in its domain: no array made (internal scalar callers pay a comparison)
    where = f"{label}() argument {name}"
    if domain is not None:
        ranges.check_rule(rule, domain, value, where)
        return
    in_rule_unit = chosen is not None and unit is None and \
        KINDS[kinds[chosen]][1].replace("*", " ") == ranges.RULES[rule][2]
    ranges.check(rule, value, where, bounded=in_rule_unit)


def _named_alternative(bound, signature, alternative_from):
    """(the argument that names the alternative, its value, which alternative that is), or None."""
    if alternative_from is None:
        return None
    name, values = alternative_from
    value = bound.arguments.get(name, signature.parameters[name].default)
    return (name, value, values.index(value)) if value in values else None


def _declared_to_si(value, name: str, kinds: tuple, unit: str | None):
    """(``value`` in the argument's unit, which of its kinds it was)."""
    label = name.replace("_", " ")
    if unit is not None:
        return to_si(value, kinds[0], label) / unit_factor(unit, kinds[0], label), 0
    refusals = []
    for index, kind in enumerate(kinds):
        try:
            return to_si(value, kind, label), index
        except InputError as error:
            refusals.append(error)
    wrong_dimension = [isinstance(error, _WrongKind) for error in refusals]
    if len(kinds) == 1 or not all(wrong_dimension):
        raise refusals[wrong_dimension.index(False) if False in wrong_dimension else 0]
    raise InputError(f"{label} must be {KINDS[kinds[0]][2]} or {KINDS[kinds[1]][2]}, such as {_example(kinds[0])} "
                     f"or {_example(kinds[1])}; got {_describe(value)}")


def _same_alternative(chosen: dict, specs: dict, named=None) -> None:
    """Refuse arguments of two kinds that took different ones (a stiffness per area with a force), or another than
    the one an argument names (``named``: its name, value and the alternative it means)."""
    paired = {name: index for name, index in chosen.items() if len(specs[name][0]) == 2}
    if named is not None:
        argument, value, index = named
        for name, taken in paired.items():
            if taken != index:
                raise InputError(f"{name.replace('_', ' ')} is {KINDS[specs[name][0][taken]][2]}, which "
                                 f"{argument} = {value!r} does not take: give it in {si_unit(specs[name][0][index])} "
                                 f"or set {argument} to match")
    if len(set(paired.values())) > 1:
        first, second = sorted(paired, key=paired.get)[0], sorted(paired, key=paired.get)[-1]
        kinds_first, kinds_second = specs[first][0], specs[second][0]
        raise InputError(
            f"{first.replace('_', ' ')} is {KINDS[kinds_first[0]][2]} but {second.replace('_', ' ')} is "
            f"{KINDS[kinds_second[1]][2]}: give both whole "
            f"({si_unit(kinds_first[0])}, {si_unit(kinds_second[0])}) or both per unit area "
            f"({si_unit(kinds_first[1])}, {si_unit(kinds_second[1])})")
