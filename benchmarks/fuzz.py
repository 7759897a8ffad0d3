"""Fuzz every reader and option of the faultslip CLI with mutated inputs, and count the outcomes.

    python benchmarks/fuzz.py [--cases 10000] [--workers 2] [--seed 0] [--out benchmarks/results/fuzz.json]

Each case mutates one bundled or example input (scene, study, map with its segment table, lab
friction CSV, motion record, free-decay record, a sweep's netCDF, or unit strings for ``fault``)
and runs the matching command in-process through ``faultslip.cli.main``. Issue 41 added the 2-D
fault: mutated scenes, surgery on a stopped run's checkpoint (bytes flipped or cut, arrays re-saved,
dropped or edited, a link in its place) and on its record streams (flipped, cut, grown, deleted, or
replaced by a link to a victim file that must stay untouched), then ``--resume``; the hazard options
(b-value, magnitudes, bin width, moment constant, scaling relations, method); and classroom uploads
with hostile names and headers, analysed as the app does, where whatever reaches the page must hold
no markup. Issue 26 added the
readers' and writers' hard cases: Zarr stores with damaged, missing or re-attributed chunks;
TOML nested hundreds deep; device files, FIFOs and folders given as inputs; symlinks, hard
links and FIFOs planted at an output's lock; writes into a full disk (a tmpfs of a few hundred
kB, where the fuzzer may mount one); and a second writer of another kind holding the output
(a forked process with the lock). Path names the file system may not take (too long, broken links, not UTF-8,
control characters) and bundled examples' bare names are given as inputs and outputs. The machine kind damages the
machine speed record (an edit, a reseal past its bounds, a link, FIFO or folder in its place, a link at its lock)
before an estimate: exit 0 is right, but one that took a changed record's readings is ``silent``, and one that
rewrote a damaged record ``unclean``. Outcomes:

* ``ok``: exit 0;
* ``mismatch``: ``reproduce`` found that a (mutated) file differs from its reproduction: exit 1;
* ``clean``: exit 2 with exactly one line on stderr, no traceback (the contract for bad input);
* ``environment``: exit 1 (a machine error such as a full disk), one line;
* ``unclean``: exit 2 but more than one line on stderr;
* ``traceback``: an exception escaped ``main`` (a bug: its type and place are recorded);
* ``timeout``: the case took longer than ``--timeout`` seconds;
* ``silent``: exit 0 from an input changed so that it must be refused (a tampered fit bundle, a Zarr store with
  two chunks swapped): a wrong or unverified answer given as right.

The acceptance criterion of issue 9 is zero ``traceback``, ``unclean``, ``timeout`` and
``environment`` over at least 10,000 cases (a mutated input must never reach the machine's limits). The tally, every
distinct failure and the slowest case are written to the JSON file. ``FAULTSLIP_FUZZ_KEEP=DIR`` keeps the inputs of
each case that timed out or raised (and, with ``FAULTSLIP_FUZZ_SLOW=SECONDS``, of each slower case) in DIR.
"""

from __future__ import annotations

import argparse
import collections
import contextlib
import io
import re
import json
import os
import random
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import traceback
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benchmarks"))  # provenance, when a test loads this file by its path
from provenance import stamp  # noqa: E402  (one stamp for every results file)

CONFIGS, DATA = ROOT / "configs", ROOT / "data"

NASTY_VALUES = [
    '""', '"-1 km"', '"0 m"', '"1e400 m"', '"nan m"', '"\u22125 km"', '"1,5 km"', '"5 m)"', '"1/0 m"',
    '"10**400 m"', '"1 m*"', "true", "0", "-1", "1e308", "nan", "inf", "-inf", "[]", "{}", '[1, "a"]',
    '"granite"', '"unknown_thing"', '"2 bar"', '"1e9 1/s"', "1e9", '"1e-30 m/s"', '"1 rad"', '"125 rad/s"',
    '{ logspace = ["1 mm/yr", "100 mm/yr", 10000000000] }', '{ linspace = ["-5 km", "5 km", 3] }',
    '{ logspace = ["0 mm/yr", "1 mm/yr", 3] }', "[0.0, 0.5, 0.99]", "[-0.999]", '"1 1/s"', '"1e-12 in/s"',
    '"100 m/s"', '"1e6 bar"', "0.999999", "1.0", "-0.5", '["granodiorite", "granodiorite"]', '"green_schist_water"',
    "1000000", "2000000000", '"3 ms"', '"1e-300 m"', '"1e300 km"', '"µm"', '"1 µm"', '"1 furlong/fortnight"',
    '{ linspace = [0, 1, 0] }', '{ linspace = [-200, 200, 5] }', '"../../etc/passwd"', '"/"', '"."',
    '"lab_glass_dry.toml"', '"no_such_scene.toml"', '"configs/no.toml"', '"DOP853"', '"Radau"', '"bogus"',
    "[[1, 2], [3]]", '"\\u0000"', "1970-01-01", "0.0", "-0.0", "1e-320", "123456789012345678901234567890",
]
NASTY_CELLS = ["", "nan", "inf", "-inf", "-1", "0", "1e400", "1e-400", "abc", "1,5", "\u22121", "1e308", " ",
               "0x10", "1_000", "true", "None", '"', "1;2", "-0", "1e-320", "9" * 400]
NASTY_UNITS = ["", "m", "km)", "(s", "1/0", "**2", "furlongz", "g_0", "Hz", "rad/s", "%", "degC", "m^-1", "s**0.5",
               "lbf/in", "in/s", "mm/yr", "m/s^2", "bar", "N", "kg"]
UNIT_STRINGS = ["13 mi", "2 in/yr", "0.25e6 bar", "250 bar", "\u22125 km", "1,5 km", "5 m)", "1/0 m", "10**400 m",
                "1 m*", "1e400 m", "nan m", "inf km", "-1 km", "0 km", "1e-300 m", "5", "5 bar", "3 s", "",
                " ", "1 km km", "1 km/s", "2 in/yr)", "2 (in/yr", "24 mm/yr", "1e6 mm/yr", "1e-30 mm/yr",
                "\u00a013\u00a0mi", "13mi", "13 MI", "13 Mi", "0x13 mi", "13e mi", "e13 mi", "1.3.3 mi"]
FAULT_FLAGS = {"--zone-width": "13 mi", "--shear-stress": "250 bar", "--slip-rate": "2 in/yr",
               "--shear-modulus": "0.25e6 bar", "--rupture-length": "270 mi", "--depth": "12 km",
               "--density": "2700 kg/m^3", "--shear-wave-speed": "3 km/s", "--mu-so": "0.65", "--mu-m": "0.55",
               "--damping-ratio": "0.1", "--rate-coefficient": "38", "--rate-exponent": "0.665",
               "--observed-slip": "21 ft", "--tolerance": "1e-6"}


# --- mutations ---------------------------------------------------------------------------------

def mutate_toml(text: str, rng: random.Random) -> str | bytes:
    lines = text.splitlines()
    choice = rng.random()
    value_lines = [i for i, line in enumerate(lines) if "=" in line and not line.lstrip().startswith("#")]
    if choice < 0.45 and value_lines:
        i = rng.choice(value_lines)
        key = lines[i].split("=", 1)[0]
        lines[i] = f"{key}= {rng.choice(NASTY_VALUES)}"
    elif choice < 0.55 and lines:
        del lines[rng.randrange(len(lines))]
    elif choice < 0.62 and lines:
        i = rng.randrange(len(lines))
        lines.insert(i, lines[i])
    elif choice < 0.7 and value_lines:
        i = rng.choice(value_lines)
        key, value = lines[i].split("=", 1)
        key = key.strip()
        typo = key[:-1] if len(key) > 2 and rng.random() < 0.5 else key + rng.choice(["_x", "s", "2"])
        lines[i] = f"{typo} ={value}"
    elif choice < 0.75:
        lines.insert(rng.randrange(len(lines) + 1), rng.choice(["[bogus]", "[scene]", "[sweep]", "[friction]",
                                                                 "[simulation]", "x = 1", "[[study]]", "= 3"]))
    elif choice < 0.8:
        raw = "\n".join(lines).encode("utf-8")
        cut = rng.randrange(len(raw) + 1)
        return raw[:cut] + bytes(rng.randrange(256) for _ in range(rng.randint(1, 4))) + raw[cut:]
    elif choice < 0.85:
        raw = "\n".join(lines)
        return raw[: rng.randrange(len(raw) + 1)]
    else:
        raw = "\n".join(lines)
        if raw:
            i = rng.randrange(len(raw))
            raw = raw[:i] + rng.choice(["", "x", '"', "[", "]", "=", "\n", "{", "-", "0", "\u2212"]) + raw[i + 1:]
        return raw
    return "\n".join(lines) + "\n"


def mutate_csv(text: str, rng: random.Random) -> str | bytes:
    lines = text.splitlines()
    if not lines:
        return text
    choice = rng.random()
    header = lines[0].split(",")
    if choice < 0.35 and len(lines) > 1:
        i = rng.randrange(1, len(lines))
        cells = lines[i].split(",")
        cells[rng.randrange(len(cells))] = rng.choice(NASTY_CELLS)
        lines[i] = ",".join(cells)
    elif choice < 0.5:
        j = rng.randrange(len(header))
        name = header[j].split(" (")[0]
        header[j] = f"{name} ({rng.choice(NASTY_UNITS)})" if rng.random() < 0.7 else rng.choice(
            [name + "x", "", header[(j + 1) % len(header)], name])
        lines[0] = ",".join(header)
    elif choice < 0.6:
        j = rng.randrange(len(header))
        lines = [",".join(c for k, c in enumerate(line.split(",")) if k != j) for line in lines]
    elif choice < 0.67 and len(lines) > 1:
        i = rng.randrange(1, len(lines))
        lines[i] = lines[i] + "," + rng.choice(NASTY_CELLS)
    elif choice < 0.74:
        keep = rng.randint(0, min(len(lines), 4))
        lines = lines[:keep]
    elif choice < 0.8:
        raw = "\n".join(lines).encode("utf-8")
        cut = rng.randrange(len(raw) + 1)
        return raw[:cut] + bytes(rng.randrange(128, 256) for _ in range(rng.randint(1, 3))) + raw[cut:]
    elif choice < 0.86 and len(lines) > 2:
        lines = [lines[0]] + sorted(lines[1:], key=lambda _: rng.random())[: rng.randint(1, len(lines) - 1)]
    elif choice < 0.92 and len(lines) > 2:
        i = rng.randrange(1, len(lines))
        lines.insert(i, lines[i])
    else:
        lines[0] = lines[0] + "," + header[rng.randrange(len(header))]
        lines[1:] = [line + ",1" for line in lines[1:]]
    return "\n".join(lines) + "\n"


def mutate_bytes(raw: bytes, rng: random.Random) -> bytes:
    data = bytearray(raw)
    choice = rng.random()
    if choice < 0.4 and data:
        for _ in range(rng.randint(1, 16)):
            data[rng.randrange(len(data))] = rng.randrange(256)
    elif choice < 0.7:
        data = data[: rng.randrange(len(data) + 1)]
    else:
        start = rng.randrange(len(data) + 1)
        data[start:start] = bytes(rng.randrange(256) for _ in range(rng.randint(1, 64)))
    return bytes(data)


#: The name the registry kind's seed fit is saved under.
REGISTRY_FIT = "fuzz_gouge"


def _registry_fit(text) -> dict | None:
    """The seed fit's entry in a registry's text, its checksum left out (None where the text does not parse)."""
    try:
        entry = json.loads(text)["fits"][REGISTRY_FIT]
        return {key: value for key, value in entry.items() if key != "checksum"}
    except (ValueError, KeyError, TypeError, UnicodeDecodeError):
        return None


def _kept_or_mutated(text: str, rng: random.Random) -> str | bytes | None:
    """A JSON file's text left as written (15 %), its bytes mutated (30 %), or None: to be edited as JSON."""
    choice = rng.random()
    if choice < 0.15:
        return text
    if choice < 0.45:
        return mutate_bytes(text.encode("utf-8"), rng)
    return None


def mutate_registry(text: str, rng: random.Random) -> str | bytes:
    """A fit registry's JSON edited (a parameter of the fit changed, its checksum or the version removed), its
    bytes mutated, or left as saved (which must be used)."""
    kept = _kept_or_mutated(text, rng)
    if kept is not None:
        return kept
    document = json.loads(text)
    entry = document["fits"][REGISTRY_FIT]
    edit = rng.choice(["value", "value", "checksum", "version", "both"])
    if edit in ("value", "both"):
        key = rng.choice(["mu_so", "mu_m", "b", "d", "shear_modulus"])
        entry[key] = rng.choice([entry[key] * 1.01, entry[key] * 2, -entry[key], 0, "0.5", None])
    if edit in ("checksum", "both"):
        entry.pop("checksum", None)
    if edit == "version":
        document.pop("faultslip_registry")
    return json.dumps(document, indent=1) + "\n"


def record_content(text) -> dict | None:
    """A machine speed record's parsed content (None where it does not parse): what an estimate would take."""
    try:
        return json.loads(text)
    except (ValueError, TypeError, UnicodeDecodeError, RecursionError):
        return None


def mutate_machine_record(text: str, rng: random.Random) -> str | bytes:
    """A machine speed record edited as a hand or a tool would (a reading changed, the checksum or version removed,
    more readings or kinds of machine than faultslip keeps, a reading out of range), its bytes mutated, grown past
    its bound, or left as written (which must be used)."""
    from faultslip.io import machine
    from faultslip.io.gate import json_checksum

    kept = _kept_or_mutated(text, rng)
    if kept is not None:
        return kept
    document = json.loads(text)
    readings = next(iter(document["machines"].values()))
    edit = rng.choice(["reading", "reading", "checksum", "version", "many", "kinds", "range", "grown"])
    if edit == "reading":
        readings[rng.randrange(len(readings))][1] = rng.choice([readings[0][1] * 10, -1e-3, 0, "1e-3", None, 1e300])
    elif edit == "checksum":
        document.pop("checksum")
    elif edit == "version":
        document["faultslip_machine_record"] = rng.choice([2, "1", None])
    elif edit == "many":
        readings.extend([[1.0, 1e-3]] * machine.RECORD_READINGS)
    elif edit == "kinds":
        document["machines"].update({f"cpu {i}": [[1.0, 1e-3]] for i in range(machine.RECORD_MACHINES)})
    elif edit == "range":
        readings[0] = rng.choice([[1.0, 5.0], [-1.0, 1e-3], [1.0], [1.0, 1e-3, 2.0], "x"])
    else:
        document["padding"] = " " * machine.RECORD_BYTES
    if edit not in ("checksum", "reading") and rng.random() < 0.7:  # resealed: only the record's bounds can tell
        document.pop("checksum", None)
        document["checksum"] = json_checksum(document)
    return json.dumps(document)


def quakeml_events(data: bytes):
    """What a QuakeML file says of its events, read by obspy alone (None where obspy cannot read it): each
    event's preferred origin's time, place and depth, its preferred magnitude and type, and its descriptions."""
    import warnings

    from obspy import read_events

    try:
        with warnings.catch_warnings(), contextlib.redirect_stderr(io.StringIO()):
            warnings.simplefilter("ignore")
            events = read_events(io.BytesIO(data), format="QUAKEML")
    except Exception:  # noqa: BLE001 (obspy raises many kinds for a damaged file)
        return None
    rows = []
    for event in events:
        origin = event.preferred_origin() or (event.origins[0] if event.origins else None)
        magnitude = event.preferred_magnitude() or (event.magnitudes[0] if event.magnitudes else None)
        rows.append((str(origin.time) if origin else None, origin.latitude if origin else None,
                     origin.longitude if origin else None, origin.depth if origin else None,
                     magnitude.mag if magnitude else None, magnitude.magnitude_type if magnitude else None,
                     [d.text for d in event.event_descriptions], event.creation_info.agency_id
                     if event.creation_info else None))
    return rows


def stream_samples(data: bytes):
    """What a miniSEED file holds beside faultslip's checksum record, read by obspy alone (None where it cannot):
    each trace's id, start, rate and samples."""
    import warnings

    from obspy import read

    try:
        with warnings.catch_warnings(), contextlib.redirect_stderr(io.StringIO()):
            warnings.simplefilter("ignore")
            stream = read(io.BytesIO(data), format="MSEED")
    except Exception:  # noqa: BLE001 (obspy raises many kinds for a damaged file)
        return None
    return [(t.id, t.stats.starttime.ns, t.stats.sampling_rate, t.data.tobytes()) for t in stream
            if t.stats.channel != "LOG" and t.data.dtype.kind != "S"]


def mutate_quakeml(data: bytes, rng: random.Random) -> bytes:
    """A QuakeML file with one value's digit changed, its faultslip checksum element removed, both, or its bytes
    mutated."""
    text = data.decode("utf-8")
    choice = rng.random()
    if choice < 0.4:
        return mutate_bytes(data, rng)
    if choice < 0.85:
        values = list(re.finditer(r"<value>([^<]*\d[^<]*)</value>", text))
        found = rng.choice(values)
        digits = [m.start() for m in re.finditer(r"\d", found.group(1))]
        at = found.start(1) + rng.choice(digits)
        text = text[:at] + str((int(text[at]) + rng.randint(1, 9)) % 10) + text[at + 1:]
    if choice >= 0.7:
        text = re.sub(r"\s*<faultslip:checksum>[^<]*</faultslip:checksum>", "", text)
    return text.encode("utf-8")


def mutate_stream(data: bytes, rng: random.Random) -> bytes:
    """A miniSEED file left as written (10 %), with one bit flipped in its data records (after faultslip's checksum
    record), or its bytes mutated."""
    choice = rng.random()
    if choice < 0.1:
        return data
    if choice < 0.55 or len(data) <= 4096:
        return mutate_bytes(data, rng)
    raw = bytearray(data)
    raw[rng.randrange(4096, len(raw))] ^= 1 << rng.randrange(8)
    return bytes(raw)


#: Each table faultslip ships in data/ and reads back, with a command that reads it (the table kind).
TABLE_COMMANDS = {
    "ladder_calibration.json": ["run", "seas_bp1.toml", "--model", "one_slider", "--json"],
    "fault_2d_model_error.json": ["run", "rsf_block_bp1.toml", "--json"],
    "family_costs.json": ["run", "lab_glass_dry.toml", "--estimate", "--json"],
    "kernel_crossover.json": ["run", "fault_2d_small.toml", "--estimate", "--json"],
    "strike_model_error.json": ["run", "fault_3d_small.toml", "--model", "one_slider", "--json"],
    "dip_model_error.json": ["model-error", "rsf_block_bp1.toml", "--plot", "PLOT", "--overwrite", "--json"],
    "dip_slider_calibration.json": ["run", "seas_bp3_thrust60.toml", "--model", "one_slider", "--json"],
    "fault_2d_hierarchy.json": ["model-error", "rsf_block_bp1.toml", "--plot", "PLOT", "--overwrite", "--json"],
}


def _table_content(text) -> dict | None:
    """A bundled table's content, its checksum left out (None where the text does not parse as a table)."""
    try:
        table = json.loads(text)
    except (ValueError, TypeError, UnicodeDecodeError):
        return None
    return {key: value for key, value in table.items() if key != "checksum"} if isinstance(table, dict) else None


def _numbers_and_texts(value, where=()):
    """(path, leaf) for every number and string in a JSON value."""
    if isinstance(value, dict):
        for key, item in value.items():
            yield from _numbers_and_texts(item, where + (key,))
    elif isinstance(value, list):
        for index, item in enumerate(value):
            yield from _numbers_and_texts(item, where + (index,))
    elif isinstance(value, (int, float, str)) and not isinstance(value, bool):
        yield where, value


def mutate_table(text: str, rng: random.Random) -> str | bytes:
    """A table of data/ edited as a hand would (one number or text changed, its checksum removed, or both), its
    bytes mutated, or left as shipped (which must be used)."""
    kept = _kept_or_mutated(text, rng)
    if kept is not None:
        return kept
    table = json.loads(text)
    edit = rng.choice(["value", "value", "value", "checksum", "both"])
    if edit in ("value", "both"):
        where, leaf = rng.choice(list(_numbers_and_texts(table)))
        parent = table
        for key in where[:-1]:
            parent = parent[key]
        parent[where[-1]] = (rng.choice([leaf + " (edited)", "", 0]) if isinstance(leaf, str) else
                             rng.choice([leaf * 1.01, leaf * 2, -leaf, leaf + 1, 0, "0.5", None]))
    if edit in ("checksum", "both"):
        table.pop("checksum", None)
    return json.dumps(table, indent=1) + "\n"


def table_caches() -> list:
    """The loaders that keep a bundled table once read: cleared around each table case."""
    from faultslip.fault import dip_error, dip_slider, ladder, strike_error
    from faultslip.io import budget
    from faultslip.models.fault_2d import kernel
    from faultslip.models.rate_state_slider import one_slider

    return [ladder.load_calibration, dip_error.load_table, dip_slider.load_table, strike_error.load_table,
            budget.family_costs, kernel.measured_crossover, one_slider.load_calibration]


def mutate_ledger(text: str, rng: random.Random) -> str | bytes:
    """A failure ledger's JSON edited as a hand or a tool would (a cell dropped, an index or the count changed, a
    key removed), its bytes mutated, or left as written (which must be retried)."""
    kept = _kept_or_mutated(text, rng)
    if kept is not None:
        return kept
    record = json.loads(text)
    edit = rng.choice(["drop", "index", "count", "key", "reason"])
    if edit == "drop":
        record["cells"].pop(rng.randrange(len(record["cells"])))
    elif edit == "index":
        cell = rng.choice(record["cells"])
        name = rng.choice(list(cell["index"]))
        cell["index"][name] = rng.choice([0, 1, 2, -1, 10**6, "0", None])
    elif edit == "count":
        record["failed_cells"] = rng.choice([0, 1, 3, -1])
    elif edit == "key":
        record.pop(rng.choice(list(record)))
    else:
        rng.choice(record["cells"])["reason"] = ""
    return json.dumps(record, indent=1) + "\n"


def ledger_content(text) -> dict | None:
    """A failure ledger's parsed content (None where it does not parse): what --retry-failed trusts. A mutation
    that gives the same bytes back, or changes only whitespace, leaves it as written, and a retry must then run
    (comparing text flagged those as silent: seed 19191's one silent case was the ledger's own bytes)."""
    try:
        record = json.loads(text.decode("utf-8") if isinstance(text, bytes) else text)
    except (ValueError, UnicodeDecodeError):
        return None
    return record if isinstance(record, dict) else None


def mutate_progress(text: str, rng: random.Random) -> str | bytes:
    """An interrupted sweep's progress record edited (a block added to or dropped from the done list, a digest or
    the layout checksum changed or removed, its own checksum removed), its bytes mutated, or left as written."""
    kept = _kept_or_mutated(text, rng)
    if kept is not None:
        return kept
    record = json.loads(text)
    edit = rng.choice(["done", "drop", "digest", "layout", "no layout", "checksum"])
    if edit == "done":
        record["done"] = list(range(record["blocks"]))
    elif edit == "drop" and record["done"]:
        record["done"].pop()
    elif edit == "digest" and record["digests"]:
        record["digests"][rng.choice(sorted(record["digests"]))] = "0" * 64
    elif edit == "layout":
        record["layout"] = "0" * 64
    elif edit == "no layout":
        record.pop("layout", None)
    record.pop("checksum", None) if edit == "checksum" or rng.random() < 0.3 else None
    return json.dumps(record)


def mutate_netcdf(path: Path, rng: random.Random) -> None:
    """A netCDF file's bytes mutated (:func:`mutate_bytes`), one bit flipped (in a small file, often in its
    attributes or layout), or an attribute or a coordinate edited through the library, as a later tool would."""
    choice = rng.random()
    if choice < 0.4:
        path.write_bytes(mutate_bytes(path.read_bytes(), rng))
        return
    if choice < 0.7:
        data = bytearray(path.read_bytes())
        data[rng.randrange(len(data))] ^= 1 << rng.randrange(8)
        path.write_bytes(bytes(data))
        return
    import netCDF4
    import numpy as np

    with netCDF4.Dataset(path, "a") as nc:
        variables = [name for name in nc.variables if nc[name].ncattrs()]
        edit = rng.choice(["global", "global", "variable", "coordinate", "delete"])
        if edit == "global":
            key = rng.choice(nc.ncattrs())
            value = nc.getncattr(key)
            nc.setncattr(key, value + " " if isinstance(value, str) else np.asarray(value) * 2 + 1)
        elif edit == "variable":
            variable = nc[rng.choice(variables)]
            key = rng.choice(variable.ncattrs())
            if key != "_FillValue":
                value = variable.getncattr(key)
                variable.setncattr(key, value + "x" if isinstance(value, str) else np.asarray(value) * 2 + 1)
        elif edit == "coordinate":
            coordinate = nc[rng.choice([name for name in nc.dimensions if name in nc.variables])]
            coordinate[0] = coordinate[0] * 1.001 if coordinate.dtype != str else coordinate[0] + "x"
        else:
            nc.delncattr(rng.choice(nc.ncattrs()))


def stop_sweep(study, output: Path, blocks: int = 2) -> None:
    """Run ``study`` into ``output`` in one-cell blocks, uncompressed, and stop it as Ctrl-C would after ``blocks``
    blocks: its partial output and progress record stay, to be resumed (the fuzzer's partial kind, and a test's)."""
    import faultslip.studies.streaming as streaming

    real = {name: getattr(streaming, name) for name in ("compute_block", "block_arrays")}
    calls = {"n": 0}

    def stopping(function):
        def call(*args, **kwargs):
            calls["n"] += 1
            if calls["n"] > blocks:
                raise KeyboardInterrupt
            return function(*args, **kwargs)
        return call

    for name, function in real.items():  # a netCDF run's blocks come from one, a Zarr run's from the other
        setattr(streaming, name, stopping(function))
    try:
        streaming.run_study(study, output, chunk_cells=1, workers=1, compression="none")
    except KeyboardInterrupt:
        pass
    finally:
        for name, function in real.items():
            setattr(streaming, name, function)
    if not output.with_name(output.name + ".progress.json").exists():
        raise AssertionError(f"the sweep into {output.name} was not stopped")


# --- cases ---------------------------------------------------------------------------------------

def unmount_full(folder: Path) -> None:
    """Unmount a workspace's full-disk tmpfs, ``folder``/full (lazily: a case's process may still hold it); nothing
    where none is mounted."""
    subprocess.run(["umount", "-l", str(folder / "full")], capture_output=True)


class Workspace:
    """Seed inputs, copied once per worker into a scratch folder."""

    def __init__(self, folder: Path):
        self.folder = folder
        self.scenes = sorted(p for p in CONFIGS.glob("*.toml") if "[scene]" in p.read_text(encoding="utf-8")
                             or 'family = "spring_chain"' in p.read_text(encoding="utf-8"))
        self.studies = [CONFIGS / "study_spring_slider.toml", CONFIGS / "study_lab_glass.toml",
                        CONFIGS / "study_rate_state.toml"]
        self.segments = (DATA / "san_andreas_segments.csv").read_text(encoding="utf-8")
        self.map_text = ('[map]\nname = "fuzz map"\nbase = "san_andreas_1906.toml"\n[segments]\nfile = "segments.csv"\n'
                         '[grid]\nlon = { linspace = [-124.0, -115.0, 10] }\nlat = { linspace = [33.0, 40.0, 8] }\n'
                         'max_distance = "60 km"\n')
        self.friction = (CONFIGS / "example_friction_data.csv").read_text(encoding="utf-8")
        record_lines = (CONFIGS / "example_record.csv").read_text(encoding="utf-8").splitlines()
        self.record = "\n".join(record_lines[:1500]) + "\n"
        decay_lines = (CONFIGS / "example_decay_record.csv").read_text(encoding="utf-8").splitlines()
        self.decay = "\n".join(decay_lines[:1200]) + "\n"
        self.netcdf = self._small_sweep()
        self.ledger = self._failure_ledger()
        self.interrupted, self.uninterrupted = self._interrupted_sweeps()
        self.registry = self._registry()
        self.machine_record = self._machine_record()
        self.table_dir = folder / "data"  # data/ as shipped, the table kind's edits made in this copy
        shutil.copytree(DATA, self.table_dir)
        self.tables = {name: (DATA / name).read_text(encoding="utf-8") for name in TABLE_COMMANDS}
        self.table_case = None  # the table a case edited, put back after it
        self.catalog = (CONFIGS / "catalog_san_andreas.csv").read_text(encoding="utf-8")
        self.geojson = (DATA / "gem_faults_example.geojson").read_text(encoding="utf-8")
        self.sherifs = {name: (CONFIGS / "sherifs_example" / name).read_text(encoding="utf-8")
                        for name in ("Faults_geometry.txt", "Faults_properties.txt", "ruptures.txt")}
        self.sherifs_map = (CONFIGS / "sherifs_example.toml").read_text(encoding="utf-8")
        phyphox_lines = (CONFIGS / "example_phyphox.csv").read_text(encoding="utf-8").splitlines()
        self.phyphox = "\n".join(phyphox_lines[:800]) + "\n"
        raw_lines = (CONFIGS / "example_raw_velocity_steps.txt").read_text(encoding="utf-8").splitlines()
        self.raw = "\n".join(raw_lines[:1400]) + "\n"  # the first two steps
        surface_lines = (CONFIGS / "example_surface.csv").read_text(encoding="utf-8").splitlines()
        self.surface = "\n".join(surface_lines[:1025]) + "\n"
        self.quakeml, self.mseed = self._seismology_files()
        self.bundle, self.workbook = self._bundle(), self._workbook()
        self.rfile = (DATA / "p655" / "p655_r").read_text(encoding="utf-8", errors="replace")
        shutil.copy(DATA / "p655" / "p655intact100l", folder / "p655intact100l")
        self.silent_if_ok = False  # a case whose input was changed so that exit 0 would be a silent result
        self.machine_case = None  # (record, its bytes, changed): a damaged record is neither used nor overwritten
        self.changed_netcdf = None  # a mutated sealed netCDF file: exit 0 with its content changed would be silent
        self.resumed_output = None  # (output, the uninterrupted run's content): a resume that exits 0 must give it
        self.netcdf_content = netcdf_content(self.folder / "seed.nc")
        self.fault_2d, self.stopped = self._stopped_2d_run()
        self.fifo = folder / "pipe.toml"
        os.mkfifo(self.fifo)
        self.full = self._tmpfs()
        self.victims: list[Path] = []
        self.holders: list[int] = []

    def _tmpfs(self) -> Path | None:
        """A 300 kB tmpfs for the full-disk cases (root only); None where it cannot be mounted."""
        mount = self.folder / "full"
        mount.mkdir()
        made = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=300k", "tmpfs", str(mount)], capture_output=True)
        return mount if made.returncode == 0 else None

    def close(self) -> None:
        """Unmount the full-disk tmpfs (:func:`unmount_full`)."""
        unmount_full(self.folder)

    def release(self) -> None:
        """Kill the lock holders of the last case and check that no planted victim was written through; put back a
        table the case edited, and where the library finds its tables."""
        if self.table_case is not None:
            from faultslip.io import resources

            name, shipped = self.table_case
            (self.table_dir / name).write_text(self.tables[name], encoding="utf-8")
            resources.bundled_dir = shipped
            for cache in table_caches():
                cache.cache_clear()
            self.table_case = None
        for pid in self.holders:
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, signal.SIGKILL)
            with contextlib.suppress(ChildProcessError):
                os.waitpid(pid, 0)
        self.holders.clear()
        for victim in self.victims:
            if victim.read_text(encoding="utf-8") != "precious":
                raise AssertionError(f"{victim} was written through a planted lock")
        self.victims.clear()

    def _small_sweep(self) -> bytes:
        study = self.folder / "seed_study.toml"
        study.write_text('[study]\nbase = "san_andreas_1906.toml"\n[sweep]\nslip_rate = ["10 mm/yr", "30 mm/yr"]\n'
                         'lithology = ["granodiorite", "pyrite"]\n', encoding="utf-8")
        out = self.folder / "seed.nc"
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            from faultslip.cli.main import main

            assert main(["sweep", str(study), "-o", str(out), "--overwrite", "--workers", "1"]) == 0
        return out.read_bytes()

    def _machine_record(self) -> str:
        """A machine speed record as the library writes it (the seed of the machine kind): five probes' readings."""
        from faultslip.io import machine

        path = self.folder / "machine_speed.json"
        saved = os.environ.get(machine.RECORD_ENVIRONMENT)
        os.environ[machine.RECORD_ENVIRONMENT] = str(path)
        try:
            for reading in (1.0e-3, 1.2e-3, 0.9e-3, 1.1e-3, 1.4e-3):
                machine.recorded_median(reading)
        finally:
            if saved is None:
                os.environ.pop(machine.RECORD_ENVIRONMENT)
            else:
                os.environ[machine.RECORD_ENVIRONMENT] = saved
        return path.read_text(encoding="utf-8")

    def _failure_ledger(self) -> str:
        """The failure ledger a run of the seed sweep leaves where two of its cells failed (the seed of the ledger
        kind): written by the library's own writer, for the study the command line reads."""
        from faultslip.studies.grid import load_study
        from faultslip.studies.streaming import _write_failure_ledger, failure_ledger

        study = load_study(self.folder / "seed_study.toml")
        cells = [{"index": {"slip_rate": 0, "lithology": 1}, "values": {"slip_rate": "10 mm/yr", "lithology": "pyrite"},
                  "reason": "the solver failed"},
                 {"index": {"slip_rate": 1, "lithology": 0}, "values": {"slip_rate": "30 mm/yr",
                                                                        "lithology": "granodiorite"},
                  "reason": "the solver failed"}]
        _write_failure_ledger(self.folder / "seed.nc", study, study.fingerprint(), cells)
        path = failure_ledger(self.folder / "seed.nc")
        text = path.read_text(encoding="utf-8")
        path.unlink()
        return text

    def _interrupted_sweeps(self) -> tuple[Path, dict]:
        """The seed sweep stopped after two of its four one-cell blocks (:func:`stop_sweep`), into netCDF and into
        Zarr: the partial outputs and progress records the partial kind damages before ``--resume``; and the
        content of the same sweep run without a stop, which a resume that exits 0 must give."""
        from faultslip.studies.grid import load_study
        from faultslip.studies.streaming import run_study

        study = load_study(self.folder / "seed_study.toml")
        folder = self.folder / "interrupted"
        folder.mkdir()
        uninterrupted = {}
        for name in ("sweep.nc", "sweep.zarr"):
            stop_sweep(study, folder / name)
            reference = self.folder / f"reference_{name}"
            run_study(study, reference, chunk_cells=1, workers=1, compression="none")
            uninterrupted[name] = output_content(reference)
        return folder, uninterrupted

    def _registry(self) -> str:
        """A fit registry holding one saved fit (the seed of the registry kind), written by the library's writer."""
        from faultslip.friction import registry

        keep = os.environ.get("FAULTSLIP_REGISTRY")
        os.environ["FAULTSLIP_REGISTRY"] = str(self.folder / "seed_fits.json")
        try:
            registry.save_entry(REGISTRY_FIT, {"mu_so": 0.68, "mu_m": 0.57, "b": 40.0, "d": 0.66,
                                               "shear_modulus": 2.5e10, "note": "fuzz seed", "source": "fuzz"})
            return (self.folder / "seed_fits.json").read_text(encoding="utf-8")
        finally:
            os.environ.pop("FAULTSLIP_REGISTRY") if keep is None else os.environ.update(FAULTSLIP_REGISTRY=keep)

    def _stopped_2d_run(self) -> tuple[str, Path]:
        """A small 2-D fault scene (2 km elements, 150 yr: about a second) and a run of it stopped right after
        a checkpoint, as a kill would leave it: the seed of the checkpoint-surgery and record-stream cases."""
        from faultslip.models.fault_2d.integrate import _Stopped, run_cycles
        from faultslip.models.fault_2d.scene import read_fault_2d_scene

        text = (CONFIGS / "fault_2d_small.toml").read_text(encoding="utf-8")
        text = text.replace('element_size = "500 m"', 'element_size = "2 km"').replace('duration = "600 yr"',
                                                                                     'duration = "150 yr"')
        scene = self.write("fault_2d.toml", text)
        loaded = read_fault_2d_scene(scene)
        stopped = self.folder / "stopped_2d"
        try:
            run_cycles(loaded.fault, loaded.duration, rtol=loaded.rtol, stations=loaded.stations, folder=stopped,
                       stop_after_steps=300)
        except _Stopped:
            pass
        return text, stopped

    def _bundle(self) -> bytes:
        """A fit bundle of the example friction data (the seed of the bundle kind)."""
        out = self.folder / "seed_bundle.zip"
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            from faultslip.cli.main import main

            assert main(["fit", str(CONFIGS / "example_friction_data.csv"), "--bootstrap", "5", "--bundle",
                         str(out), "--json"]) == 0
        return out.read_bytes()

    def _workbook(self) -> bytes:
        """The raw velocity-step record as an Excel workbook (the seed of the xlsx kind: one the fit accepts)."""
        import openpyxl

        book = openpyxl.Workbook()
        sheet = book.active
        lines = [line.split() for line in self.raw.splitlines() if line.strip() and not line.startswith("#")]
        header = [re.sub(r"^(\w+)\((.+)\)$", r"\1 (\2)", cell) for cell in lines[0]]  # "time (s)": a sheet's form
        sheet.append(header)
        for row in lines[1:]:  # the whole record: its first rows hold no velocity step
            try:
                sheet.append([float(v) for v in row])
            except ValueError:
                continue
        buffer = io.BytesIO()
        book.save(buffer)
        return buffer.getvalue()

    def _seismology_files(self) -> tuple[bytes, bytes]:
        """A QuakeML catalog and a miniSEED record to corrupt (written by faultslip itself)."""
        import numpy as np

        from faultslip.io.catalogs import read_catalog, write_quakeml
        from faultslip.io.waveforms import build_stream, write_stream

        catalog = read_catalog(CONFIGS / "catalog_san_andreas.csv")
        write_quakeml(catalog.time, catalog.latitude, catalog.longitude, [1e4] * len(catalog), catalog.magnitude,
                      self.folder / "seed.xml", names=catalog.name)
        stream = build_stream(200.0, {"D": 1e-5 * np.sin(np.linspace(0, 60, 2000)), "N": np.ones(2000)}, 0.0)
        write_stream(stream, self.folder / "seed.mseed")
        return (self.folder / "seed.xml").read_bytes(), (self.folder / "seed.mseed").read_bytes()

    def write(self, name: str, content) -> Path:
        path = self.folder / name
        path.parent.mkdir(parents=True, exist_ok=True)
        if isinstance(content, bytes):
            path.write_bytes(content)
        else:
            path.write_text(content, encoding="utf-8", errors="surrogatepass")
        return path


#: Run in a child (a damaged file may crash the netCDF library): a digest of everything a netCDF file holds.
_CONTENT = """
import hashlib, sys, netCDF4, numpy as np
digest = hashlib.sha256()
def feed(value):
    value = np.asarray(value)
    digest.update(repr((value.dtype.str, value.shape)).encode())
    digest.update(repr(value.tolist()).encode() if value.dtype.kind in "OUS" else value.tobytes())
with netCDF4.Dataset(sys.argv[1]) as nc:
    def walk(group):
        for key in sorted(group.ncattrs()):
            digest.update(key.encode()); feed(group.getncattr(key))
        for name, variable in sorted(group.variables.items()):
            variable.set_auto_maskandscale(False)
            digest.update(repr((name, variable.dimensions, str(variable.dtype))).encode())
            for key in sorted(variable.ncattrs()):
                digest.update(key.encode()); feed(variable.getncattr(key))
            feed(variable[...])
        for child in sorted(group.groups):
            walk(group.groups[child])
    walk(nc)
print(digest.hexdigest())
"""


def netcdf_content(path) -> str | None:
    """The digest of everything ``path`` holds (attributes, types, values), or None where it does not read."""
    try:
        result = subprocess.run([sys.executable, "-c", _CONTENT, str(path)], capture_output=True, text=True,
                                timeout=60)
    except subprocess.TimeoutExpired:
        return None
    return result.stdout.strip() if result.returncode == 0 else None


#: Run in a child: a digest of a study output's content (netCDF or Zarr) as xarray reads it undecoded, without the
#: attributes that differ between two runs of one study (the time in history) or seal a finished file.
_OUTPUT_CONTENT = """
import hashlib, sys, numpy as np, xarray as xr
path = sys.argv[1]
skip = {"history", "faultslip_checksum", "faultslip_checksum_covers", "faultslip_block_digests"}
opened = xr.open_zarr(path, decode_cf=False) if path.endswith(".zarr") else xr.open_dataset(path, decode_cf=False)
digest = hashlib.sha256()
with opened as ds:
    digest.update(repr(sorted((k, repr(v)) for k, v in ds.attrs.items() if k not in skip)).encode())
    for name in sorted(ds.variables):
        variable = ds[name]
        digest.update(repr((name, variable.dims, str(variable.dtype), sorted((k, repr(v)) for k, v in
                                                                              variable.attrs.items()))).encode())
        values = variable.values
        digest.update(repr(values.tolist()).encode() if values.dtype.kind in "OUS" else values.tobytes())
print(digest.hexdigest())
"""


def output_content(path) -> str | None:
    """The digest of a study output's content (:data:`_OUTPUT_CONTENT`), or None where it does not read."""
    try:
        result = subprocess.run([sys.executable, "-c", _OUTPUT_CONTENT, str(path)], capture_output=True, text=True,
                                timeout=60)
    except subprocess.TimeoutExpired:
        return None
    return result.stdout.strip() if result.returncode == 0 else None


def make_case(kind: str, space: Workspace, rng: random.Random) -> list[str]:
    out = str(space.folder / "out.nc")
    if kind == "scene":
        seed = rng.choice(space.scenes)
        path = space.write("scene.toml", mutate_toml(seed.read_text(encoding="utf-8"), rng))
        command = rng.choice([["run", str(path), "--json"], ["simulate", str(path), "--cycles", "3", "--json"],
                              ["cycle", str(path), "--loading-rate", rng.choice(["0.1 1/s", "1e3 1/s", "-1 1/s"]),
                               "--json"], ["critical", str(path), "--json"]])
        return command
    if kind == "study":
        seed = rng.choice(space.studies)
        text = seed.read_text(encoding="utf-8").replace("41]", "5]").replace("26]", "4]").replace("61]", "7]")
        text = text.replace("13] }", "3] }").replace("cycles = 5", "cycles = 1")  # rate-state: few, short
        text = text.replace('base = "', f'base = "{CONFIGS}/')
        path = space.write("study.toml", mutate_toml(text, rng))
        return ["sweep", str(path), "-o", out, "--overwrite", "--workers", "1", "--json"]
    if kind == "map":
        map_text = space.map_text
        if rng.random() < 0.3:  # a rate-and-state base, one cycle per segment
            map_text = map_text.replace('base = "san_andreas_1906.toml"',
                                        'base = "san_andreas_1906_rate_state.toml"\ncycles = 1')
        if rng.random() < 0.5:
            space.write("segments.csv", mutate_csv(space.segments, rng))
            path = space.write("map.toml", map_text)
        else:
            space.write("segments.csv", space.segments)
            path = space.write("map.toml", mutate_toml(map_text, rng))
        return ["map", str(path), "-o", out, "--overwrite", "--json"]
    if kind == "nanoscale":
        text = (CONFIGS / "nanoscale_seed001.toml").read_text(encoding="utf-8").replace("3000.0", "300.0")
        path = space.write("nanoscale.toml", mutate_toml(text, rng))
        return ["nanoscale", str(path), "--json"] + rng.choice([[], ["--no-run"], ["--damping", rng.choice(
            ["13", "-1", "nan", "1e300", "x"])]])
    if kind == "vibration":
        text = (CONFIGS / "vibration_seed002.toml").read_text(encoding="utf-8")
        path = space.write("vibration.toml", mutate_toml(text, rng))
        return ["quasi-harmonic", str(path), "--json"] + rng.choice(
            [[], ["--speeds", "1 in/s", rng.choice(["16 in/s", "0 in/s", "1e9 in/s"]), rng.choice(["5", "1", "x"])],
             ["--speed", rng.choice(["13 in/s", "-1 in/s", "1e30 m/s"])], ["--tolerance", rng.choice(["1e-2", "0", "2"])]])
    if kind == "fit":
        path = space.write("friction.csv", mutate_csv(space.friction, rng))
        return ["fit", str(path), "--bootstrap", "5", "--json"]
    if kind == "raw":
        path = space.write(rng.choice(["rig.txt", "rig.dat"]), mutate_csv(space.raw, rng))
        return ["fit", str(path), "--law", "rate-state", "--stiffness",
                rng.choice(["200 kN/mm", "80 MPa/mm", "8e-3 1/um", "-1 kN/mm", "3 kg", "nan 1/um"]),
                "--area", rng.choice(["25 cm^2", "0 m^2", "1 m", "abc"]), "--json"] + rng.choice(
            [[], ["--detrend", rng.choice(["linear", "quadratic"])], ["--steps", rng.choice(["100 s", "500 s", "x"])],
             ["--each-step"], ["--windows", rng.choice(["50 s - 130 s", "9 s - 1 s", "a - b", "50 s to 60 s"])],
             ["--posterior", "--samples", "200", "--max-steps", "200", "--prior",
              rng.choice(["a=uniform:0:0.05", "a=uniform:1:0", "zz=normal:0:1", "b=lognormal:0:1"])],
             ["--units", rng.choice(["time=ms", "shear_load=kg", "speed=m/s", "time"])]])
    if kind == "record":
        path = space.write("record.csv", mutate_csv(space.record, rng))
        return ["record", str(path), "--stiffness", "1.94e4 lbf/in", "--normal-load", "137.8 lbf", "--json"]
    if kind == "decay":
        path = space.write("decay.csv", mutate_csv(space.decay, rng))
        return ["decay", str(path), "--stiffness", "12346 N/m", "--json"]
    if kind == "netcdf":
        path = space.write("mutated.nc", space.netcdf)
        mutate_netcdf(path, rng)
        space.changed_netcdf = path  # the seed is a sealed sweep output
        return rng.choice([["reproduce", str(path), "--workers", "1", "--json"],
                           ["reproduce", str(path), "--cells", rng.choice(["1", "2", "0", "-3", "1e9", "x", "99999"]),
                            "--seed", rng.choice(["0", "7", "-1", "2.5"]), "--workers", "1", "--json"],
                           ["record", str(path), "--stiffness", "1 N/m", "--normal-load", "1 N", "--json"],
                           ["fit", str(path), "--bootstrap", "5", "--json"]])
    if kind == "units":
        flags = dict(FAULT_FLAGS)
        del flags["--shear-stress" if rng.random() < 0.5 else "--observed-slip"]
        if rng.random() < 0.3:
            del flags["--shear-wave-speed"]
        for flag in rng.sample(sorted(flags), rng.randint(1, 3)):
            flags[flag] = rng.choice(UNIT_STRINGS)
        argv = ["fault", "--lithology", rng.choice(["granodiorite", "granite", "pyrite", "nope", "green_schist"])]
        for flag, value in flags.items():
            argv += [flag, value]
        return argv + ["--json"]
    if kind == "options":
        scene = str(rng.choice(space.scenes))
        return rng.choice([
            ["simulate", scene, "--cycles", rng.choice(["0", "-5", "1000000000", "2", "x"]), "--json"],
            ["simulate", scene, "--rtol", rng.choice(["0", "1", "1e-20", "nan", "1e-6"]), "--cycles", "2", "--json"],
            ["simulate", scene, "--slip-solver", rng.choice(["Radau", "bogus", "analytic", "LSODA"]), "--cycles", "2",
             "-o", rng.choice([out, str(space.folder), str(space.folder / "no" / "x.nc"), str(space.folder / "x.txt")]),
             "--overwrite", "--json"],
            ["run", rng.choice([scene, "nope", "configs/nope.toml", str(space.folder), "", "lab_glass_dry"]),
             "--tolerance", rng.choice(["1e-6", "0", "2", "-1", "abc", "1e-300"]), "--json"],
            ["cycle", scene, "--platform-speed", rng.choice(UNIT_STRINGS), "--json"],
            ["critical", "--preset", rng.choice(["glass_dry", "nope", "green_schist_water"]), "--damping-ratio",
             rng.choice(["0.1", "0", "-0.5", "1", "1.5", "nan", "\u22120.1"]), "--json"],
            ["decay", "--stiffness", rng.choice(UNIT_STRINGS + ["70.5 lbf/in"]), "--ratio",
             rng.choice(["1.225", "0.9", "1", "nan", "1e400", "-2"]), "--cycles", rng.choice(["10", "0", "-1", "1e9"]),
             "--frequency", rng.choice(["19.9 Hz", "125 rad/s", "0 Hz", "-1 Hz", "1 m"]), "--json"],
            ["plot", "rate-law", "-o", rng.choice([str(space.folder / "p.png"), str(space.folder / "p.xyz"),
                                                   str(space.folder)]), "--overwrite"],
            # the asperity speed sweep's options; all valid is rare, since each converged speed costs seconds
            ["asperity", str(CONFIGS / "asperity_seed004.toml"), "--from",
             rng.choice(["3 mm/s", "0 mm/s", "5 kg", "nan mm/s", "1e30 m/s"]), "--to", "3.2 mm/s", "--points",
             rng.choice(["3", "1", "x", "2001"]), "--tolerance", rng.choice(["0", "2", "abc", "-1", "nan", "1e400",
                                                                              "1 m", "0.5"]), "--json"],
        ])
    if kind == "catalog":
        if rng.random() < 0.5:
            path = space.write("catalog.csv", mutate_csv(space.catalog, rng))
        else:
            mutated = mutate_quakeml(space.quakeml, rng)
            path = space.write("catalog.xml", mutated)
            # exit 0 on events other than those written would be silent
            space.silent_if_ok = quakeml_events(mutated) not in (None, quakeml_events(space.quakeml))
        return ["catalog", str(path), "--fault", str(CONFIGS / "parkfield.toml"), "--bootstrap", "20", "--as-of",
                rng.choice(["2026-01-01"] * 4 + ["1800-01-01", "nope"]), "--json"]
    if kind == "sherifs":  # SHERIFS's three input files, one of them mutated, through a map that reads them
        victim = rng.choice(sorted(space.sherifs))
        for name, text in space.sherifs.items():
            space.write(f"sherifs_example/{name}", mutate_csv(text, rng) if name == victim else text)
        space.write("sherifs_example/base.toml", (CONFIGS / "sherifs_example" / "base.toml").read_text(encoding="utf-8"))
        path = space.write("sherifs.toml", space.sherifs_map)
        return ["map", str(path), "-o", out, "--overwrite", "--json"]
    if kind == "geojson":
        space.write("faults.geojson", mutate_csv(space.geojson, rng))
        path = space.write("gaf_map.toml", space.map_text.replace('file = "segments.csv"', 'file = "faults.geojson"'))
        return ["map", str(path), "-o", out, "--overwrite", "--json"] + rng.choice(
            [[], ["--nrml", str(space.folder / "s.xml"), "--mfd",
                  rng.choice(["characteristic", "truncated_gr", "single_bin", "x"]),
                  "--scaling-relations", rng.choice(["faultslip", "faultslip,WC1994,Leonard2010", "WC1994:0.7,x",
                                                     "Leonard2010:0.2,faultslip:0.2", ""]),
                  "--min-magnitude", rng.choice(["5.0", "7.9", "-40", "nan", "5 m"]),
                  "--b-value", rng.choice(["1.0", "0", "0.8", "inf"])]
             + rng.choice([[], ["--engine-job", str(space.folder / "j.ini"),
                                "--sites", rng.choice(["-120 36", "-120", "500 0; 1 1", ""])]])])
    if kind == "mseed":
        mutated = mutate_stream(space.mseed, rng)
        path = space.write("record.mseed", mutated)
        space.silent_if_ok = stream_samples(mutated) not in (None, stream_samples(space.mseed))  # other samples used
        # the platform speed given (the seed record's sine cannot show it), so that the record as written is answered
        return ["record", str(path), "--stiffness", "1e4 N/m", "--normal-load", "10 N", "--json"] + rng.choice(
            [["--platform-speed", "1e-5 m/s"]] * 3 + [[]])
    if kind == "phyphox":
        path = space.write("phone.csv", mutate_csv(space.phyphox, rng))
        return ["record", str(path), "--json"] + rng.choice([[], ["--axis", rng.choice(["x", "y", "w"])]])
    if kind == "ledger":  # a sweep's failure ledger edited, then --retry-failed
        out = space.write("retry.nc", space.netcdf)
        text = mutate_ledger(space.ledger, rng)
        space.write("retry.nc.failed.json", text)
        # exit 0 with other content would retry cells the run did not list
        space.silent_if_ok = ledger_content(text) != ledger_content(space.ledger)
        return ["sweep", str(space.folder / "seed_study.toml"), "-o", str(out), "--retry-failed", "--workers", "1",
                "--json"]
    if kind == "partial":  # an interrupted sweep's partial output or progress record damaged, then --resume
        name = rng.choice(["sweep.nc", "sweep.zarr"])
        folder = space.folder / "resume_sweep"
        shutil.rmtree(folder, ignore_errors=True)
        shutil.copytree(space.interrupted, folder)
        partial, progress = folder / f"{name}.partial", folder / f"{name}.progress.json"
        target = rng.random()
        if target < 0.35:
            text = mutate_progress(progress.read_text(encoding="utf-8"), rng)
            progress.write_bytes(text.encode("utf-8") if isinstance(text, str) else text)
        elif name == "sweep.nc":
            mutate_netcdf(partial, rng)
        else:
            damage_store(partial, rng)
        space.resumed_output = (folder / name, space.uninterrupted[name])  # exit 0 must give the uninterrupted run's
        return ["sweep", str(space.folder / "seed_study.toml"), "-o", str(folder / name), "--resume", "--workers",
                "1", "--chunks", "1", "--compression", "none", "--json"]
    if kind == "registry":  # the user's fit registry edited, then its fit used for a fault
        text = mutate_registry(space.registry, rng)
        Path(os.environ["FAULTSLIP_REGISTRY"]).write_bytes(text.encode("utf-8") if isinstance(text, str) else text)
        space.silent_if_ok = _registry_fit(text) != _registry_fit(space.registry)  # exit 0 would use another fit
        return ["fault", "--lithology", REGISTRY_FIT, "--zone-width", "13 mi", "--shear-stress", "250 bar",
                "--slip-rate", "2 in/yr", "--json"]
    if kind == "machine":  # the machine speed record damaged or replaced, then an estimate that reads it
        from faultslip.io import machine

        path = space.folder / "machine_speed.json"
        os.environ[machine.RECORD_ENVIRONMENT] = str(path)
        machine._probe.clear()  # this process probes again, and reads the record
        for stale in (path, path.with_name(f".{path.name}.lock")):
            if stale.is_dir() and not stale.is_symlink():
                shutil.rmtree(stale)
            elif stale.exists() or stale.is_symlink():
                stale.unlink()
        plant = rng.choice(["text"] * 7 + ["link", "dangling", "fifo", "folder", "lock"])
        if plant == "text":
            text = mutate_machine_record(space.machine_record, rng)
            path.write_bytes(text.encode("utf-8") if isinstance(text, str) else text)
            changed = record_content(text) != record_content(space.machine_record)
        else:
            victim = space.folder / "victim.txt"
            victim.write_text("precious", encoding="utf-8")
            space.victims.append(victim)
            target = path.with_name(f".{path.name}.lock") if plant == "lock" else path
            if plant in ("link", "lock"):
                target.symlink_to(victim)
            elif plant == "dangling":
                target.symlink_to(space.folder / "nowhere" / "x")
            elif plant == "fifo":
                os.mkfifo(target)
            else:
                target.mkdir()
            changed = plant != "lock"
        # exit 0 is right, but never from a changed record's readings, and the record keeps every byte
        space.machine_case = (path, path.read_bytes() if path.is_file() and not path.is_symlink() else None, changed)
        os.environ.pop("FAULTSLIP_MACHINE_FACTOR", None)
        return rng.choice([["run", str(CONFIGS / "fault_2d_small.toml"), "--estimate", "--json"],
                           ["run", str(CONFIGS / "lab_glass_dry.toml"), "--estimate", "--json"],
                           ["sweep", str(space.folder / "seed_study.toml"), "-o", str(space.folder / "estimated.nc"),
                            "--estimate", "--json"]])
    if kind == "table":  # a table faultslip ships and reads back (a calibration, a cost model) edited, then read
        from faultslip.io import resources

        name = rng.choice(sorted(TABLE_COMMANDS))
        text = mutate_table(space.tables[name], rng)
        (space.table_dir / name).write_bytes(text.encode("utf-8") if isinstance(text, str) else text)
        space.silent_if_ok = _table_content(text) != _table_content(space.tables[name])  # exit 0 used another table
        shipped = resources.bundled_dir
        resources.bundled_dir = lambda kind: space.table_dir if kind == "data" else shipped(kind)
        space.table_case = (name, shipped)
        for cache in table_caches():
            cache.cache_clear()
        return [str(CONFIGS / a) if a.endswith(".toml") else str(space.folder / "tables.png") if a == "PLOT" else a
                for a in TABLE_COMMANDS[name]]
    if kind == "bundle":
        path = space.write("fit.zip", mutate_bundle(space.bundle, rng, space))
        return ["fit", "--replay", str(path), "--json"]
    if kind == "xlsx":
        path = space.write("rig.xlsx", mutate_workbook(space.workbook, rng))
        return ["fit", str(path), "--law", "rate-state", "--stiffness", "200 kN/mm", "--area", "25 cm^2", "--json"]
    if kind == "rfile":
        path = space.write("p655_r", mutate_csv(space.rfile, rng) if rng.random() < 0.8 else
                           mutate_bytes(space.rfile.encode(), rng))
        return ["reduce", str(path), "--json"]
    if kind == "memo":
        import faultslip.units as units

        cache = space.folder / "cache"
        os.environ["XDG_CACHE_HOME"] = str(cache)
        units._MEMO = None  # this process read its memo: it reads the mutated one afresh
        units._unit_factor.cache_clear()
        units._conversion.cache_clear()
        memo = units._memo_path()
        if memo.exists():
            text = memo.read_bytes()
            memo.write_bytes(mutate_bytes(text, rng) if rng.random() < 0.5 else
                             text.replace(b"1000.0", rng.choice([b"10000.0", b"1e400", b"-1.0", b"\"nan\""])))
            space.silent_if_ok = False  # a rejected memo is recomputed from pint: exit 0 with the right answer
        return ["fault", "--lithology", "granodiorite", "--zone-width", rng.choice(["13 mi", "20 km", "1e4 m"]),
                "--slip-rate", "2 in/yr", "--shear-stress", "250 bar", "--json"]
    if kind == "zarr":
        store = space.folder / "store.zarr"
        shutil.rmtree(store, ignore_errors=True)
        shutil.copytree(CONFIGS / "example_lab_glass.zarr", store)
        space.silent_if_ok = damage_store(store, rng) is True  # chunks swapped, an attribute edited: exit 0 is silent
        return rng.choice([["convert", str(store), "-o", out, "--overwrite", "--workers", "1", "--json"],
                           ["reproduce", str(store), "--workers", "1", "--json"],
                           ["reproduce", str(store), "--cells", rng.choice(["1", "3", "0"]), "--seed", "2",
                            "--workers", "1", "--json"]])
    if kind == "deep":
        depth = rng.choice([33, 100, 500, 3000])
        opener, closer = rng.choice([("[", "]"), ("{ a = ", " }")])
        nested = opener * depth + closer * depth
        target = rng.choice(["scene", "study", "map", "reproduce"])
        if target == "reproduce":  # the study that reproduce parses from a netCDF's attribute
            import netCDF4

            path = space.write("deep.nc", space.netcdf)
            with netCDF4.Dataset(path, "a") as nc:
                nc.setncattr("faultslip_study", f"[study]\nname = {nested}\n")
            return ["reproduce", str(path), "--workers", "1", "--json"]
        path = space.write(f"deep_{target}.toml", f"[{target}]\nname = \"deep\"\nx = {nested}\n")
        return {"scene": ["run", str(path), "--json"], "study": ["sweep", str(path), "-o", out, "--overwrite"],
                "map": ["map", str(path), "-o", out, "--overwrite"]}[target]
    if kind == "device":
        special = rng.choice(["/dev/zero", "/dev/null", "/dev/urandom", str(space.fifo), str(space.folder)])
        return rng.choice([["run", special], ["fit", special], ["record", special],
                           ["record", special, "--stiffness", "1 N/m", "--normal-load", "1 N"],
                           ["catalog", special, "--fault", str(CONFIGS / "parkfield.toml")],
                           ["convert", special, "-o", out], ["reproduce", special], ["surface", special],
                           ["decay", special, "--stiffness", "1 N/m"], ["sweep", special, "-o", out]])
    if kind == "names":  # hostile names as an input or an output: one sentence or the answer, never the system's
        name = hostile_name(space, rng)
        if rng.random() < 0.5:
            argv, _ = writer_case(space, rng, space.folder)
            outputs = [i for i, a in enumerate(argv) if a.startswith(str(space.folder / "TARGET"))]
            argv[rng.choice(outputs)] = name if os.path.isabs(name) else str(space.folder / name)  # never in cwd
            return argv
        return rng.choice([["run", name], ["fit", name], ["record", name], ["surface", name], ["predictability", name],
                           ["decay", name, "--stiffness", "1 N/m"], ["reduce", name, "-o", out, "--overwrite"],
                           ["catalog", name, "--fault", str(CONFIGS / "parkfield.toml")],
                           ["convert", name, "-o", out, "--overwrite"], ["sweep", name, "-o", out, "--overwrite"],
                           ["map", name, "-o", out, "--overwrite"],
                           ["simulate", "fault_2d_small.toml", "--output-dir", name, "--estimate"]])
    if kind in ("lock", "full", "race"):
        folder = space.full if kind == "full" and space.full is not None else space.folder
        argv, target = writer_case(space, rng, folder)
        if kind == "lock":
            plant_lock(target, rng, space)
        elif kind == "full":
            pad = folder / "pad"
            pad.unlink(missing_ok=True)
            free = shutil.disk_usage(folder).free
            pad.write_bytes(b"\0" * max(0, free - rng.choice([0, 4096, 40_000, 120_000])))
        else:
            space.holders.append(hold_lock(target, rng.choice(["faultslip sweep", "faultslip map", "faultslip fit"])))
        return argv
    if kind == "gaf":
        document = json.loads(space.geojson)
        mutate_gaf(document, rng)
        space.write("faults.geojson", json.dumps(document))
        path = space.write("gaf_map.toml", space.map_text.replace('file = "segments.csv"', 'file = "faults.geojson"'))
        return ["map", str(path), "-o", out, "--overwrite", "--json", "--nrml", str(space.folder / "s.xml")]
    if kind == "surface":
        path = space.write("surface.csv", mutate_csv(space.surface, rng))
        return ["surface", str(path), "--json"] + rng.choice(
            [[], ["--modulus", rng.choice(["210 GPa", "-1 GPa", "1e400 Pa"]), "--hardness", "2 GPa"],
             ["--flow-pressure", "280 N/mm^2", "--load", rng.choice(["0.01 N", "1e9 N", "-1 N"])]])
    if kind == "fault_2d":
        path = space.write("fault_2d_case.toml", mutate_toml(space.fault_2d, rng))
        return rng.choice([["run", str(path), "--json"],
                           ["simulate", str(path), "--output-dir", str(space.folder / "run_2d"), "--overwrite",
                            "--json"]])
    if kind in ("checkpoint", "stream"):
        folder = space.folder / "resume_2d"
        shutil.rmtree(folder, ignore_errors=True)
        shutil.copytree(space.stopped, folder, symlinks=True)
        if kind == "checkpoint":
            damage_checkpoint(folder / "checkpoint.npz", rng)
        else:
            damage_stream(folder / rng.choice(["stations.f8", "profiles.f8", "events.f8"]), rng, space)
        return ["simulate", str(space.folder / "fault_2d.toml"), "--output-dir", str(folder), "--resume", "--json"]
    if kind == "hazard":
        space.write("segments.csv", space.segments)
        path = space.write("map.toml", space.map_text)
        argv = ["map", str(path), "-o", out, "--overwrite", "--json", "--nrml", str(space.folder / "h.xml"),
                "--mfd", rng.choice(["characteristic", "truncated_gr", "single_bin", "gr", ""])]
        for flag, values in (("--b-value", ["1.0", "1e-300", "0", "-1", "3.01", "nan", "1e300", "x"]),
                             ("--min-magnitude", ["5.0", "-3", "11", "nan", "inf", "7.9"]),
                             ("--mfd-bin-width", ["0.1", "1e-300", "0", "0.7", "-0.1", "nan"]),
                             ("--moment-constant", ["9.1", "9.05", "9", "nan"]),
                             ("--scaling-relations", ["faultslip", "WC1994:0.5,Leonard2010:0.5", "WC1994:2", ":",
                                                      "faultslip,faultslip"]),
                             ("--renewal", ["bpt:0.5", "lognormal:0.3", "bpt:0", "weibull:1", "bpt:x", "lognormal:6"]),
                             ("--forecast-year", ["2026", "1800", "nan", "x", "1e300"]),
                             ("--investigation-time", ["50 yr", "0 yr", "-1 yr", "50 m", "x"])):
            if rng.random() < 0.6:
                argv += [flag, rng.choice(values)]
        if rng.random() < 0.5:  # time-dependent sources: each segment's last rupture, or a broken list of them
            ids = [line.split(",")[0] for line in space.segments.splitlines()[1:] if line.strip()]
            whole = "; ".join(f"{segment}={rng.choice(['1857', '1906.3', '2004.74', '1690'])}" for segment in ids)
            argv += ["--time-dependent", str(space.folder / "td.xml"), "--last-ruptures",
                     rng.choice([whole, whole + "; nowhere=1900", "=", "a=b", "", ids[0] + "=2999" if ids else "x=1"])]
        if rng.random() < 0.2:
            argv += ["--method", rng.choice(["auto", "closed_form", "bogus", "exact_cycle", ""])]
        return argv
    if kind == "upload":
        name = rng.choice(["phone.csv", "<img src=x onerror=alert(1)>.csv", "../../etc/passwd", "a.txt", "x.exe",
                           "\u0000.csv", "<script>alert(1)</script>", "", "é.csv", "a" * 300 + ".csv"])
        content = mutate_csv(space.phyphox, rng)
        if rng.random() < 0.3:
            content = (content if isinstance(content, bytes) else content.encode("utf-8", "surrogatepass"))
            content = content.replace(b"Time", b"<img src=x onerror=alert(1)>", 1)
        path = space.write("upload.bin", content)
        return ["__upload__", str(path), name]
    raise ValueError(kind)


def damage_checkpoint(path: Path, rng) -> None:
    """Surgery on a 2-D run's checkpoint: bytes flipped, cut or emptied, arrays re-saved, dropped or edited."""
    import numpy as np

    how = rng.choice(["bytes", "truncate", "empty", "resave", "drop", "edit", "link", "delete", "text"])
    data = path.read_bytes()
    if how == "bytes":
        path.write_bytes(mutate_bytes(data, rng))
    elif how == "truncate":
        path.write_bytes(data[: rng.randrange(len(data))])
    elif how == "empty":
        path.write_bytes(b"")
    elif how == "text":
        path.write_text("checkpoint", encoding="utf-8")
    elif how == "delete":
        path.unlink()
    elif how == "link":
        path.unlink()
        path.symlink_to(path.parent / "stations.f8")
    else:
        with np.load(io.BytesIO(data)) as archive:
            arrays = {key: archive[key] for key in archive.files}
        if how == "resave":
            arrays.pop("checksum", None)
        elif how == "drop":
            arrays.pop(rng.choice(sorted(arrays)))
        else:
            key = rng.choice(sorted(k for k in arrays if arrays[k].dtype.kind == "f"))
            arrays[key] = arrays[key] * rng.choice([2.0, -1.0, float("nan")])
        buffer = io.BytesIO()
        np.savez(buffer, **arrays)
        path.write_bytes(buffer.getvalue())


def damage_stream(path: Path, rng, space) -> None:
    """A record stream flipped, cut, grown, deleted, or replaced by a link to a victim (never to be written)."""
    how = rng.choice(["bytes", "truncate", "grow", "delete", "symlink", "hardlink"])
    data = path.read_bytes()
    if how == "bytes":
        path.write_bytes(mutate_bytes(data, rng))
    elif how == "truncate":
        path.write_bytes(data[: rng.randrange(max(1, len(data)))])
    elif how == "grow":  # a write after the checkpoint, which resume cuts back: the run goes on
        path.write_bytes(data + bytes(rng.randrange(1, 100)))
    elif how == "delete":
        path.unlink()
    else:
        victim = space.folder / f"victim_{len(space.victims)}.txt"
        victim.write_text("precious", encoding="utf-8")
        space.victims.append(victim)
        path.unlink()
        (path.symlink_to if how == "symlink" else lambda target: os.link(target, path))(victim)


KINDS = {"scene": 22, "study": 12, "map": 4, "fit": 12, "record": 6, "decay": 6, "netcdf": 8, "units": 20,
         "options": 10, "vibration": 4, "nanoscale": 3, "catalog": 4, "geojson": 3, "mseed": 3, "phyphox": 3,
         "surface": 3, "zarr": 5, "deep": 3, "device": 3, "lock": 3, "full": 3, "race": 3, "gaf": 3, "raw": 6,
         "fault_2d": 5, "checkpoint": 5, "stream": 4, "hazard": 4, "upload": 4,
         "bundle": 6, "xlsx": 4, "rfile": 4, "memo": 3, "sherifs": 3, "ledger": 4, "registry": 4, "table": 4,
         "partial": 4, "names": 4, "machine": 4}

#: Writer commands of every output kind, each writing TARGET (netCDF, Zarr, PNG, GIF, NRML, QuakeML, miniSEED, SAC).
WRITERS = [
    (["sweep", "STUDY", "-o", "TARGET.nc", "--workers", "1"], "TARGET.nc"),
    (["sweep", "STUDY", "-o", "TARGET.zarr", "--workers", "1"], "TARGET.zarr"),
    (["map", "MAP", "-o", "TARGET.nc", "--plot", "TARGET.png", "--nrml", "TARGET.xml"], "TARGET.nc"),
    (["map", "MAP", "-o", "other.nc", "--plot", "TARGET.png"], "TARGET.png"),
    (["map", "MAP", "-o", "other.nc", "--nrml", "TARGET.xml"], "TARGET.xml"),
    (["fit", str(CONFIGS / "example_friction_data.csv"), "--bootstrap", "5", "--plot", "TARGET.png"], "TARGET.png"),
    (["simulate", "lab_glass_dry.toml", "--cycles", "3", "-o", "TARGET.nc", "--plot", "TARGET.png"], "TARGET.nc"),
    (["simulate", "lab_glass_dry.toml", "--cycles", "3", "--stream", "TARGET.mseed"], "TARGET.mseed"),
    (["simulate", "lab_glass_dry.toml", "--cycles", "3", "--stream", "TARGET.sac"], "TARGET.D.sac"),
    (["simulate", "san_andreas_1906.toml", "--cycles", "3", "--events", "TARGET.xml"], "TARGET.xml"),
    (["animate", "lab_glass_dry.toml", "-o", "TARGET.gif", "--frames", "4"], "TARGET.gif"),
    (["convert", str(CONFIGS / "example_lab_glass.zarr"), "-o", "TARGET.nc", "--workers", "1"], "TARGET.nc"),
]


def hostile_name(space, rng) -> str:
    """A path argument the file system may not take: too long (a name or a folder past NAME_MAX, a name that fits
    alone but not with the temporary file beside it, a path past PATH_MAX), a broken link, not UTF-8, a control
    character, a bundled example's bare name, or an empty, dot or dash name."""
    name_max = os.pathconf(space.folder, "PC_NAME_MAX")
    suffix = rng.choice([".nc", ".csv", ".toml", ".zarr", ".png", ".xml", ""])
    broken = space.folder / f"broken{rng.randrange(10**6)}{suffix}"
    if rng.random() < 0.1:
        broken.symlink_to(space.folder / "gone")
    return rng.choice([
        "a" * rng.choice([name_max - 64 + 1, name_max, name_max + 1, 3 * name_max]) + suffix,
        str(space.folder / ("d" * (name_max + 1)) / f"x{suffix}"),
        str(space.folder / "/".join(["e" * 200] * 25)) + suffix,
        str(broken), os.fsdecode(b"bad\xff" + suffix.encode()), f"line\nbreak{suffix}", f"tab\tname{suffix}",
        rng.choice(["example_record.csv", "example_friction_data", "p655_r", "catalog_san_andreas.csv",
                    "example_lab_glass.zarr", "san_andreas_1906", "study_spring_slider.toml"]),
        "", " ", ".", "..", "-", "--", "/", "//", "~"])


def writer_case(space, rng, folder: Path) -> tuple[list[str], Path]:
    """A writer command into ``folder`` and the output its lock guards."""
    argv, target = rng.choice(WRITERS)
    study = space.write("writer_study.toml", '[study]\nbase = "' + str(CONFIGS / "san_andreas_1906.toml")
                        + '"\n[sweep]\nslip_rate = ["10 mm/yr", "30 mm/yr"]\n')
    space.write("segments.csv", space.segments)
    map_path = space.write("writer_map.toml", space.map_text)
    for stale in [*folder.glob("TARGET*"), *folder.glob(".TARGET*"), *folder.glob(".other.nc*")]:
        shutil.rmtree(stale, ignore_errors=True) if stale.is_dir() and not stale.is_symlink() else stale.unlink()
    (folder / "other.nc").unlink(missing_ok=True)
    replaced = [str(folder / a) if a.startswith(("TARGET", "other.")) else a for a in argv]
    replaced = [str(study) if a == "STUDY" else str(map_path) if a == "MAP" else a for a in replaced]
    return replaced + ["--overwrite"], folder / target


def plant_lock(target: Path, rng, space) -> None:
    """A symlink, a hard link or a FIFO at the output's lock path (none may be followed or truncated)."""
    lock = target.with_name(f".{target.name}.lock")
    if lock.exists() or lock.is_symlink():
        lock.unlink()
    victim = space.folder / "victim.txt"
    victim.write_text("precious", encoding="utf-8")
    choice = rng.choice(["symlink", "hardlink", "fifo", "dangling"])
    if choice == "symlink":
        lock.symlink_to(victim)
    elif choice == "hardlink":
        os.link(victim, lock)
    elif choice == "fifo":
        os.mkfifo(lock)
    else:
        lock.symlink_to(space.folder / "nowhere" / "x")
    space.victims.append(victim)


def hold_lock(target: Path, command: str) -> int:
    """A forked process holding the output's lock as another faultslip run would; returns its pid."""
    import fcntl

    import select

    lock = target.with_name(f".{target.name}.lock")
    if lock.is_symlink() or lock.exists():  # what an earlier case planted there
        lock.unlink()
    ready_read, ready_write = os.pipe()
    pid = os.fork()
    if pid == 0:  # the child: lock, say so, wait to be killed
        try:
            descriptor = os.open(lock, os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW, 0o644)
            fcntl.flock(descriptor, fcntl.LOCK_EX | fcntl.LOCK_NB)
            os.write(descriptor, json.dumps({"pid": os.getpid(), "command": command, "started": time.time()}).encode())
            os.write(ready_write, b"1")
            time.sleep(120)
        except BaseException:  # noqa: BLE001  the parent must never wait for a child that failed
            os.write(ready_write, b"0")
        finally:
            os._exit(0)
    ready, _, _ = select.select([ready_read], [], [], 10.0)
    answer = os.read(ready_read, 1) if ready else b"0"
    os.close(ready_read)
    os.close(ready_write)
    if answer != b"1":
        raise RuntimeError(f"the lock holder for {target.name} could not take its lock")
    return pid


def damage_store(store: Path, rng) -> bool | None:
    """Leave the store as written (8 %: it must convert), swap, delete or corrupt chunks, give an attribute another
    valid value (True: exit 0 would be silent) or one netCDF cannot hold, or damage an array's metadata."""
    if rng.random() < 0.08:
        return None
    chunks = sorted(p for p in store.rglob("*") if p.is_file() and not p.name.startswith("."))
    choice = rng.random()
    pairs = [(a, b) for a in chunks for b in chunks if a.parent == b.parent and a < b
             and a.read_bytes() != b.read_bytes()]
    if choice < 0.15 and pairs:  # two chunks of one array swapped: each valid by its own CRC, the digests tell
        first, second = rng.choice(pairs)
        content = first.read_bytes()
        first.write_bytes(second.read_bytes())
        second.write_bytes(content)
        return True
    if choice < 0.3:
        rng.choice(chunks).unlink()
    elif choice < 0.55:
        chunk = rng.choice(chunks)
        chunk.write_bytes(mutate_bytes(chunk.read_bytes(), rng))
    elif choice < 0.8:  # an attribute given another valid value (units, a name, the study), as zarr would write it
        def texts(document):
            return sorted(k for k, v in document.items() if isinstance(v, str) and v and not k.startswith("_"))

        attrs = rng.choice([p for p in sorted(store.rglob(".zattrs")) if texts(json.loads(p.read_text("utf-8")))])
        key = attrs.parent.relative_to(store).as_posix()
        document = json.loads(attrs.read_text(encoding="utf-8"))
        name = rng.choice(texts(document))
        document[name] = rng.choice([value for value in ("m", "mm", "yr", document[name] + " (edited)",
                                                         document[name][::-1]) if value != document[name]])
        if rng.random() < 0.5 or not (store / ".zmetadata").exists():  # in the array's own file and the
            attrs.write_text(json.dumps(document), encoding="utf-8")  # consolidated copy, as zarr would write it
        if (store / ".zmetadata").exists():  # a finished store (a partial one has none yet)
            consolidated = json.loads((store / ".zmetadata").read_text(encoding="utf-8"))
            consolidated["metadata"][f"{key}/.zattrs" if key != "." else ".zattrs"] = document
            (store / ".zmetadata").write_text(json.dumps(consolidated), encoding="utf-8")
        return True  # exit 0 would carry another attribute into the answer
    elif choice < 0.9:
        attrs = rng.choice(sorted(store.rglob(".zattrs")))
        document = json.loads(attrs.read_text(encoding="utf-8"))
        document[rng.choice(["bad", "units", "long_name", "_FillValue"])] = rng.choice(
            [None, {}, {"a": 1}, [], [1, "a"], True, 1e308, "x" * 10_000])
        attrs.write_text(json.dumps(document), encoding="utf-8")
        (store / ".zmetadata").unlink(missing_ok=True)
    else:
        meta = rng.choice(sorted(store.rglob(".zarray")))
        meta.write_bytes(mutate_bytes(meta.read_bytes(), rng))
        (store / ".zmetadata").unlink(missing_ok=True)


def mutate_bundle(raw: bytes, rng, space) -> bytes:
    """A fit bundle changed after writing: its bytes, a member edited (report numbers, types, emptied), removed,
    shadowed by a second entry, or inflated; options of the wrong kind. Exit 0 from any of these is silent."""
    import zipfile

    space.silent_if_ok = True
    if rng.random() < 0.2:
        flipped = mutate_bytes(raw, rng)
        space.silent_if_ok = _members(flipped) != _members(raw)  # bytes of the zip's own dates or padding change nothing
        return flipped
    with zipfile.ZipFile(io.BytesIO(raw)) as archive:
        members = {name: archive.read(name) for name in archive.namelist()}
    choice = rng.random()
    extra = []
    report = json.loads(members["report.json"])
    manifest = json.loads(members["manifest.json"])
    if choice < 0.25:
        numbers = [k for k, v in report.items() if isinstance(v, (int, float)) and not isinstance(v, bool)]
        if numbers:
            key = rng.choice(numbers)
            report[key] = rng.choice([report[key] * 3, str(report[key] * 3), None, -report[key] - 1])
        members["report.json"] = json.dumps(report).encode()
    elif choice < 0.35:
        members["report.json"] = rng.choice([b"{}", b"[]", b"null", b"{not json"])
    elif choice < 0.5:
        del members[rng.choice(sorted(members))]
    elif choice < 0.6:
        extra.append(("report.json", b"{}"))
    elif choice < 0.75:
        key = rng.choice(["bootstrap", "seed", "posterior", "joint", "detrend", "law"])
        manifest["options"][key] = rng.choice(["many", 1.5, [1], {}, True, "cubic", None, -1])
        members["manifest.json"] = json.dumps(manifest).encode()
    elif choice < 0.85:
        manifest[rng.choice(["versions", "members", "record", "format"])] = rng.choice([[], "x", None, {"a": 1}, 5])
        members["manifest.json"] = json.dumps(manifest).encode()
    else:  # a member that inflates far past its size on disk
        members[rng.choice(["manifest.json", "report.json"])] += b" " * rng.choice([2 ** 20, 40 * 2 ** 20])
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", compression=zipfile.ZIP_DEFLATED) as archive:
        for name, content in list(members.items()) + extra:
            with warnings_off():
                archive.writestr(name, content)
    # an edit that left every value as it was (an option set to its own value) is no change: exit 0 is right
    space.silent_if_ok = bool(extra) or _members(buffer.getvalue()) != _members(raw)
    return buffer.getvalue()


def _members(raw: bytes):
    """A zip's members by name and content, or None where it does not open (for the bundle kind's oracle)."""
    import zipfile

    try:
        with zipfile.ZipFile(io.BytesIO(raw)) as archive:
            members = {name: archive.read(name) for name in archive.namelist()}
        # JSON by its values: a manifest written again with an option set to what it was is no change
        return {name: (json.loads(content) if name.endswith(".json") else content) for name, content in members.items()}
    except Exception:  # noqa: BLE001  a damaged zip: a changed input, whatever broke
        return None


@contextlib.contextmanager
def warnings_off():
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        yield


def mutate_workbook(raw: bytes, rng) -> bytes:
    """An Excel workbook's bytes flipped, a stray cell far out, text among the numbers, or a sheet that inflates."""
    import openpyxl

    choice = rng.random()
    if choice < 0.3:
        return mutate_bytes(raw, rng)
    book = openpyxl.load_workbook(io.BytesIO(raw))
    sheet = book.active
    if choice < 0.55:
        sheet[rng.choice(["XFD1048576", "ZZ100000", "B1000000", "AA1"])] = rng.choice([1.0, "x"])
    elif choice < 0.8:
        sheet.cell(row=rng.randint(1, 50), column=rng.randint(1, 4), value=rng.choice(["", "nan", "1,5", None, "x"]))
    else:
        for _ in range(rng.choice([1, 3])):
            sheet.insert_rows(rng.randint(2, 40))
    buffer = io.BytesIO()
    book.save(buffer)
    return buffer.getvalue()


GAF_TERMS = ["Dextral_Transform", "Sinistral_Transform", "Subduction_Thrust", "Normal-Strike-Slip",
             "Reverse-Strike-Slip", "Blind Thrust", "Dextral-Oblique", "Wobbly", "", None, {}, [], 5, "dextral"]


def mutate_gaf(document: dict, rng) -> None:
    """GeoJSON-level mutations: GAF slip types, MultiLineStrings, repeated ids, odd values."""
    features = document["features"]
    for _ in range(rng.randint(1, 4)):
        feature = rng.choice(features)
        choice = rng.random()
        if choice < 0.35:
            feature["properties"]["slip_type"] = rng.choice(GAF_TERMS)
        elif choice < 0.55 and feature["geometry"].get("type") == "LineString":
            line = feature["geometry"]["coordinates"]
            cut = rng.randint(1, max(1, len(line) - 1))
            feature["geometry"] = {"type": "MultiLineString", "coordinates": rng.choice(
                [[line[:cut + 1], line[cut:]], [line, [[c[0] + 1.0, c[1]] for c in line]], [], [[]]])}
        elif choice < 0.62:  # a trace that crosses or retraces itself, or one fault given twice
            line = feature["geometry"].get("coordinates")
            if feature["geometry"].get("type") == "LineString" and isinstance(line, list) and len(line) >= 2:
                how = rng.choice(["retrace", "cross", "repeat", "twice"])
                if how == "retrace":
                    feature["geometry"]["coordinates"] = line + line[-2::-1]
                elif how == "cross":
                    feature["geometry"]["coordinates"] = line + [[line[0][0] + 0.01, line[0][1] + 0.2],
                                                                 [line[0][0] + 0.01, line[0][1] - 0.2]]
                elif how == "repeat":
                    feature["geometry"]["coordinates"] = line[:1] + line
                else:
                    features.append(json.loads(json.dumps({**feature, "properties": {
                        **feature["properties"], "catalog_id": f"{feature['properties'].get('catalog_id')}-again"}})))
        elif choice < 0.7:
            other = rng.choice(features)
            feature["properties"]["catalog_id"] = other["properties"].get("catalog_id")
        else:
            key = rng.choice(["net_slip_rate", "average_dip", "average_rake", "upper_seis_depth", "lower_seis_depth",
                              "name", "catalog_id"])
            feature["properties"][key] = rng.choice([None, {}, [], "(,,)", "(1e400,,)", -5, "(-5,,)", "x", True])


class _Timeout(Exception):
    pass


def _alarm(signum, frame):
    raise _Timeout


def upload_case(path: str, name: str):
    """A classroom upload as the app handles it: analysed, or refused in one sentence; whatever the page shows of
    it must hold no markup (faultslip.apps.classroom escapes it)."""
    from faultslip.apps.classroom import _text, experiment
    from faultslip.errors import FaultslipError

    content = Path(path).read_bytes()
    try:
        result = experiment(content, name or "upload.csv")
        shown = _text(result["filename"])
    except FaultslipError as exc:
        if "\n" in str(exc):
            return 2, "two lines"
        shown = _text(exc)
        if "<" in shown or ">" in shown:
            return 2, f"markup reached the page: {shown[:120]}"
        return 2, None
    if "<" in shown or ">" in shown:
        return 2, f"markup reached the page: {shown[:120]}"
    return 0, None


def machine_record_outcome(case, outcome: str, detail):
    """A machine case's outcome: an estimate that took a changed record's readings (more than this process's
    probe) is silent, and one that changed a damaged record's bytes is unclean."""
    from faultslip.io import machine

    path, before, changed = case
    if outcome != "ok" or not changed:
        return outcome, detail
    if machine.speed_reading()["readings"] > 1:
        return "silent", "machine: an estimate took the readings of a changed machine speed record"
    after = path.read_bytes() if before is not None and path.is_file() and not path.is_symlink() else None
    if before is not None and after != before:
        return "unclean", "machine: a damaged machine speed record was overwritten"
    return outcome, detail


def run_case(argv: list[str], timeout: float):
    from faultslip.cli.main import main

    out, err = io.StringIO(), io.StringIO()
    signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_REAL, timeout)
    started = time.perf_counter()
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                if argv[0] == "__upload__":
                    code, problem = upload_case(argv[1], argv[2])
                    if problem:
                        return "unclean", problem, time.perf_counter() - started
                    if code == 2:
                        print("faultslip: error: refused", file=sys.stderr)
                else:
                    code = main(argv)
            except SystemExit as exit_:  # argparse
                code = exit_.code if isinstance(exit_.code, int) else 2
    except _Timeout:
        return "timeout", None, time.perf_counter() - started
    except BaseException as exc:  # noqa: BLE001 (a fuzzer records whatever escapes)
        frame = traceback.extract_tb(exc.__traceback__)[-1]
        where = f"{type(exc).__name__}: {str(exc)[:120]} at {Path(frame.filename).name}:{frame.lineno} ({frame.name})"
        return "traceback", where, time.perf_counter() - started
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
    lines = [line for line in err.getvalue().splitlines() if line.strip() and "warning:" not in line
             and "note:" not in line]
    if code == 0:
        return "ok", None, time.perf_counter() - started
    if code == 2:
        if len(lines) == 1 and "Traceback" not in err.getvalue():
            return "clean", None, time.perf_counter() - started
        return "unclean", err.getvalue()[:300], time.perf_counter() - started
    if code == 1 and (argv[0] == "reproduce" or "--replay" in argv):  # a difference found and said, as designed
        return "mismatch", None, time.perf_counter() - started
    if code == 1:
        return "environment", err.getvalue()[:200] or "exit 1", time.perf_counter() - started
    return "unclean", f"exit {code}: {err.getvalue()[:200]}", time.perf_counter() - started


def worker(job):
    start, count, seed, timeout, only = job
    os.environ.setdefault("MPLBACKEND", "Agg")
    folder = Path(tempfile.mkdtemp(prefix="faultslip-fuzz-"))
    # matplotlib's own cache, built once in this worker: the user's may list the fonts of a venv since deleted,
    # whose every mathtext plot then warns on stderr, which the fuzzer would count against the case
    os.environ["MPLCONFIGDIR"] = str(folder / "matplotlib")
    import warnings

    import matplotlib

    matplotlib.use("Agg")
    warnings.simplefilter("ignore")
    os.environ["FAULTSLIP_REGISTRY"] = str(folder / "fits.json")
    os.environ["FAULTSLIP_MACHINE_RECORD"] = str(folder / "machine_speed.json")  # never the user's own
    # a mutated input may legitimately ask for an hour of work; the fuzzer's budget is its time-out
    os.environ["FAULTSLIP_TIME_BUDGET"] = str(timeout / 4)
    try:
        space = Workspace(folder)
        rng = random.Random(seed * 1_000_003 + start)
        kinds = only.split(",") if only else list(KINDS)
        weights = [KINDS[k] for k in kinds]
        tally = collections.Counter()
        by_kind = collections.defaultdict(collections.Counter)
        failures = {}
        slowest = (0.0, None, None)  # seconds, kind, argv: the case nearest the time-out, to look into
        for _ in range(count):
            kind = rng.choices(kinds, weights)[0]
            argv = make_case(kind, space, rng)
            if os.environ.get("FAULTSLIP_FUZZ_LOG"):  # to find a case that kills the process (a crash in C)
                with open(f"{os.environ['FAULTSLIP_FUZZ_LOG']}.{os.getpid()}", "a", encoding="utf-8") as log:
                    log.write(json.dumps(argv) + "\n")
                for name in ("scene.toml", "study.toml", "mutated.nc", "segments.csv", "map.toml"):
                    if (space.folder / name).exists():
                        shutil.copy(space.folder / name, Path(os.environ["FAULTSLIP_FUZZ_LOG"]).parent / name)
            outcome, detail, seconds = run_case(argv, timeout)
            if outcome == "ok" and space.silent_if_ok:  # a changed input reported as if nothing had changed
                outcome, detail = "silent", f"{kind}: a changed input went through with exit 0"
            if outcome == "ok" and space.changed_netcdf is not None \
                    and netcdf_content(space.changed_netcdf) != space.netcdf_content:
                outcome, detail = "silent", f"{kind}: a sealed file read with exit 0 though its content changed"
            if outcome == "ok" and space.resumed_output is not None \
                    and output_content(space.resumed_output[0]) != space.resumed_output[1]:
                outcome, detail = "silent", f"{kind}: a resumed sweep gave another output than the run without a stop"
            if space.machine_case is not None:
                outcome, detail = machine_record_outcome(space.machine_case, outcome, detail)
            space.silent_if_ok, space.changed_netcdf, space.resumed_output = False, None, None
            space.machine_case = None
            try:
                space.release()
            except AssertionError as exc:
                outcome, detail = "traceback", str(exc)
            if outcome in ("ok", "clean") and kind in ("full", "race", "lock"):
                left = [p.name for p in (space.full if kind == "full" and space.full else space.folder).glob("*")
                        if ".partial" in p.name or ".tmp" in p.name]
                if left:  # nothing half-written may stay behind
                    outcome, detail = "unclean", f"left behind: {left[:3]}"
            if seconds > slowest[0]:
                slowest = (seconds, kind, list(argv))
            tally[outcome] += 1
            by_kind[kind][outcome] += 1
            if detail and outcome in ("traceback", "unclean", "timeout", "environment", "silent") \
                    and detail not in failures:
                failures[detail] = {"outcome": outcome, "kind": kind, "argv": [a for a in argv]}
            elif outcome == "timeout":
                failures.setdefault(f"timeout {kind}", {"outcome": outcome, "kind": kind, "argv": argv})
            slow = seconds > float(os.environ.get("FAULTSLIP_FUZZ_SLOW", "inf"))  # a case near the time-out
            if (outcome in ("timeout", "traceback") or slow) and os.environ.get("FAULTSLIP_FUZZ_KEEP"):
                label = outcome if outcome in ("timeout", "traceback") else f"slow-{seconds:.0f}s"
                keep = Path(os.environ["FAULTSLIP_FUZZ_KEEP"]) / f"{label}-{start}-{tally[outcome]}"
                # the inputs, to replay the case: files and folders (not the FIFO, nor a lock gone meanwhile)
                with contextlib.suppress(shutil.Error):
                    shutil.copytree(space.folder, keep, dirs_exist_ok=True, ignore=lambda folder, names: [
                        name for name in names if not (Path(folder, name).is_file() or Path(folder, name).is_dir())])
                (keep / "argv.json").write_text(json.dumps(argv), encoding="utf-8")
        return tally, {k: dict(v) for k, v in by_kind.items()}, failures, slowest
    finally:
        unmount_full(folder)  # by its path: a workspace that failed while it was made may have mounted it
        shutil.rmtree(folder, ignore_errors=True)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", type=int, default=10_000)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--timeout", type=float, default=60.0)
    parser.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "fuzz.json"))
    parser.add_argument("--kinds", help="comma-separated input kinds to draw from (default: all, by their weights)")
    args = parser.parse_args(argv)
    if args.kinds:
        unknown = set(args.kinds.split(",")) - set(KINDS)
        if unknown:
            parser.error(f"unknown kinds {sorted(unknown)}; choose from {sorted(KINDS)}")
    started = time.perf_counter()
    per = -(-args.cases // args.workers)
    jobs = [(i * per, min(per, args.cases - i * per), args.seed, args.timeout, args.kinds)
            for i in range(args.workers)]
    tally, by_kind, failures, slowest = collections.Counter(), collections.defaultdict(collections.Counter), {}, (0.0,)
    with ProcessPoolExecutor(args.workers) as pool:
        for part_tally, part_kinds, part_failures, part_slowest in pool.map(worker, jobs):
            tally.update(part_tally)
            for kind, counts in part_kinds.items():
                by_kind[kind].update(counts)
            failures.update(part_failures)
            slowest = max(slowest, part_slowest, key=lambda case: case[0])
    result = {
        "cases": sum(tally.values()), "outcomes": dict(tally), "by_input": {k: dict(v) for k, v in by_kind.items()},
        "distinct_failures": failures, "slowest_case_s": slowest[0],
        "slowest_case": {"kind": slowest[1], "argv": slowest[2]} if len(slowest) > 1 else None,
        "wall_time_s": time.perf_counter() - started,
        "seed": args.seed, **({"kinds": args.kinds} if args.kinds else {}), **stamp(),
    }
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")
    print(json.dumps({k: v for k, v in result.items() if k != "distinct_failures"}, indent=1))
    for detail, info in list(failures.items())[:40]:
        print(f"{info['outcome']:10s} {info['kind']:8s} {detail}", file=sys.stderr)
    bad = tally["traceback"] + tally["unclean"] + tally["timeout"] + tally["environment"] + tally["silent"]
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
