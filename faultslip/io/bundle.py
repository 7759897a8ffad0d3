"""A fit bundle: everything that made a fit, in one zip that opens without faultslip.

``faultslip fit ... --bundle FIT.zip`` writes, and ``faultslip fit --replay FIT.zip`` reads:

- ``manifest.json``: the format, when and with what it was made (``versions``: Python, faultslip, numpy,
  scipy, emcee, numba, ...), the command's options and seed, the record's name, size and SHA-256, and the
  SHA-256 of every other member (``members``), and its own (``checksum``): a member or the manifest changed
  after writing is refused on reading;
- ``record/<name>``: the input record's bytes, as read;
- ``report.json``: every number the fit reported, as ``faultslip fit --json`` prints it;
- ``draws.nc``: the bootstrap resamples and posterior draws as netCDF (classic format, which any netCDF
  reader opens), one variable per kind of draw on dimensions ``draw`` and ``parameter``.

:func:`compare_numbers` walks two reports and lists every number that moved; a replay on the same versions
moves none.
"""

from __future__ import annotations

import hashlib
import io
import json
import math
import platform
import zipfile
from dataclasses import dataclass, field
from datetime import datetime, timezone
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

import numpy as np

from faultslip.errors import InputError
from faultslip.io.atomic import atomic_path
from faultslip.io.gate import LIMITS, MiB, check_input, decoding, json_checksum, open_zip, read_bytes, read_member

FORMAT = "faultslip-fit-bundle/2"  # /2: the manifest holds every member's SHA-256, not only the record's
MANIFEST, REPORT, DRAWS, RECORD_FOLDER = "manifest.json", "report.json", "draws.nc", "record/"
#: the packages whose versions a bundle records (those a fit's numbers depend on)
PACKAGES = ("faultslip", "numpy", "scipy", "emcee", "numba", "xarray", "netCDF4", "pint")
#: report keys whose numbers measure the machine, not the fit: never compared
UNTIMED = ("seconds", "wall", "elapsed")


def package_versions() -> dict:
    """{package: version} of :data:`PACKAGES` (None where not installed) and Python's."""
    versions = {"python": platform.python_version()}
    for name in PACKAGES:
        try:
            versions[name] = version(name)
        except PackageNotFoundError:
            versions[name] = None
    return versions


@dataclass
class Bundle:
    """A bundle's contents: the manifest, the record's name and bytes, the report and the draws."""

    manifest: dict
    record_name: str
    record: bytes
    report: dict
    draws: dict = field(default_factory=dict)  # kind -> (names, array (draws, parameters))


def _draws_netcdf(draws: dict) -> bytes:
    import xarray as xr  # heavy: imported where used

    data, coords = {}, {}
    for kind, (names, values) in draws.items():
        values = np.asarray(values, dtype=float)
        if values.size == 0:
            continue
        dims = (f"{kind}_draw", f"{kind}_parameter")
        data[kind] = (dims, values, {"long_name": f"{kind.replace('_', ' ')} draws, natural scale (SI)"})
        coords[f"{kind}_parameter"] = (f"{kind}_parameter", np.array(list(names), dtype=str))
    dataset = xr.Dataset(data, coords=coords, attrs={"Conventions": "CF-1.10", "source": FORMAT})
    return bytes(dataset.to_netcdf(format="NETCDF3_64BIT"))


def manifest_checksum(manifest: dict) -> str:
    """SHA-256 of a manifest's content, its own ``checksum`` left out, keys sorted: a manifest edited after writing
    (its options, versions or members' checksums) no longer matches it."""
    return json_checksum(manifest)


def write_bundle(path, *, record_path, options: dict, report: dict, draws: dict | None = None,
                 command: str = "faultslip fit") -> dict:
    """Write a fit bundle to ``path`` (atomically); returns its manifest.

    Parameters
    ----------
    path : str or path
        The zip to write.
    record_path : str or path
        The record the fit read (its bytes go in whole).
    options : dict
        Every option of the command, JSON-ready.
    report : dict
        The fit's report (``Report.to_dict()``).
    draws : dict, optional
        kind -> (parameter names, array of draws (draws, parameters)).
    command : str
        What made it.

    Returns
    -------
    dict
        The manifest.
    """
    record = read_bytes(record_path, "the fit's record", "table")
    manifest = {"format": FORMAT, "command": command, "created": datetime.now(timezone.utc).isoformat(),
                "versions": package_versions(), "options": options,
                "record": {"name": Path(record_path).name, "original_path": str(record_path), "bytes": len(record),
                           "sha256": hashlib.sha256(record).hexdigest()}}
    members = {REPORT: json.dumps(report, indent=2, allow_nan=False).encode("utf-8")}
    if draws:
        members[DRAWS] = _draws_netcdf(draws)
    manifest["members"] = {name: hashlib.sha256(content).hexdigest() for name, content in members.items()}
    manifest["checksum"] = manifest_checksum(manifest)
    with atomic_path(path) as temporary:
        with zipfile.ZipFile(temporary, "w", compression=zipfile.ZIP_DEFLATED) as archive:
            archive.writestr(MANIFEST, json.dumps(manifest, indent=2))
            archive.writestr(RECORD_FOLDER + manifest["record"]["name"], record)
            for name, content in members.items():
                archive.writestr(name, content)
    return manifest


def read_bundle(path) -> Bundle:
    """Read and check a fit bundle; every fault in it is one sentence naming the file.

    Parameters
    ----------
    path : str or path
        The zip (``fit --bundle``'s).

    Returns
    -------
    Bundle
        Its manifest (options, versions, seeds, the record's checksum), the record's name and bytes, the report and
        the draws by kind.
    """
    import xarray as xr  # heavy: imported where used

    path = check_input(path, "fit bundle", "bundle")
    data = read_bytes(path, "fit bundle", "bundle")
    # bounded before anything is inflated: each member's declared size against its kind's limit, and the ratios
    archive = open_zip(data, path, "fit bundle", total_limit=LIMITS["bundle"], member_limit=LIMITS["table"],
                       member_limits={MANIFEST: MiB, REPORT: 16 * MiB, DRAWS: LIMITS["bundle"] // 2})
    names = archive.namelist()
    if MANIFEST not in names or REPORT not in names:
        raise InputError(f"fit bundle {path.name} has no {MANIFEST} and {REPORT}: it is not a faultslip fit bundle")
    with decoding(path, "fit bundle", "JSON"):
        manifest = json.loads(read_member(archive, MANIFEST, path, "fit bundle").decode("utf-8"))
    if not isinstance(manifest, dict) or manifest.get("format") != FORMAT:
        older = isinstance(manifest, dict) and manifest.get("format") == "faultslip-fit-bundle/1"
        raise InputError(f"fit bundle {path.name} is not in the format {FORMAT}" + (
            ": it was written before bundles carried a checksum for every member, so its report cannot be "
            "trusted; make it again with 'faultslip fit ... --bundle'" if older else ""))
    if manifest.get("checksum") != manifest_checksum(manifest):
        raise InputError(f"fit bundle {path.name}: its manifest does not match its SHA-256; the bundle was changed "
                         "after it was written")
    entry, checksums = manifest.get("record"), manifest.get("members")
    if not (isinstance(entry, dict) and isinstance(entry.get("name"), str) and isinstance(entry.get("sha256"), str)
            and isinstance(manifest.get("options"), dict) and isinstance(checksums, dict)
            and all(isinstance(value, str) for value in checksums.values())):
        raise InputError(f"fit bundle {path.name}: its manifest lacks the record's name and checksum, the members' "
                         "checksums or the options")
    name = entry["name"]
    if "/" in name or "\\" in name or name in ("", ".", ".."):
        raise InputError(f"fit bundle {path.name}: the record's name {name!r} is not a plain file name")
    expected = {RECORD_FOLDER + name, MANIFEST, *checksums}
    stray = sorted(set(names) - expected)
    if stray or RECORD_FOLDER + name not in names or REPORT not in checksums:
        what = (f"holds {stray[0]!r}, which its manifest does not list" if stray else
                f"does not hold its record {name!r}" if RECORD_FOLDER + name not in names else
                f"has no checksum for {REPORT}")
        raise InputError(f"fit bundle {path.name} {what}")
    contents = {}
    for member, digest in checksums.items():
        if member not in names:
            raise InputError(f"fit bundle {path.name} lacks {member}, which its manifest lists")
        contents[member] = read_member(archive, member, path, "fit bundle")
        if hashlib.sha256(contents[member]).hexdigest() != digest:
            raise InputError(f"fit bundle {path.name}: {member} does not match its SHA-256; the bundle was changed "
                             "after it was written")
    record = read_member(archive, RECORD_FOLDER + name, path, "fit bundle")
    if hashlib.sha256(record).hexdigest() != entry["sha256"]:
        raise InputError(f"fit bundle {path.name}: its record {name!r} does not match its SHA-256; the bundle was "
                         "changed after it was written")
    with decoding(path, "fit bundle", "JSON"):
        report = json.loads(contents[REPORT].decode("utf-8"))
    if not isinstance(report, dict):
        raise InputError(f"fit bundle {path.name}: its {REPORT} is not a report")
    draws = {}
    if DRAWS in names:
        with decoding(path, "fit bundle", "netCDF draws"):
            with xr.open_dataset(io.BytesIO(contents[DRAWS]), engine="scipy") as dataset:
                for kind in dataset.data_vars:
                    draws[kind] = ([str(v) for v in dataset[f"{kind}_parameter"].values],
                                   np.asarray(dataset[kind].values, dtype=float))
    return Bundle(manifest, name, record, report, draws)


def extract_record(bundle: Bundle, folder) -> Path:
    """Write a bundle's record into ``folder`` under its own name (a reader picks its format by the name)."""
    target = Path(folder) / bundle.record_name
    with atomic_path(target, immediate=True) as temporary:  # read back at once, inside the command's transaction
        Path(temporary).write_bytes(bundle.record)
    return target


def _numbers(value, prefix=""):
    """(dotted key, number) for every number in a report, skipping what measures the machine."""
    if isinstance(value, dict):
        for key, item in value.items():
            if any(word in str(key) for word in UNTIMED):
                continue
            yield from _numbers(item, f"{prefix}.{key}" if prefix else str(key))
    elif isinstance(value, list):
        for index, item in enumerate(value):
            yield from _numbers(item, f"{prefix}[{index}]")
    elif isinstance(value, (int, float)) and not isinstance(value, bool):
        yield prefix, float(value)


def compare_numbers(old: dict, new: dict) -> dict:
    """Every number of ``old`` against ``new``: {"compared", "moved": [(key, old, new, relative change)],
    "missing": [keys in old only], "extra": [keys in new only]}."""
    first, second = dict(_numbers(old)), dict(_numbers(new))
    moved = []
    for key, value in first.items():
        if key in second and not (value == second[key] or (math.isnan(value) and math.isnan(second[key]))):
            other = second[key]
            scale = max(abs(value), abs(other), 1e-300)
            moved.append((key, value, other, abs(other - value) / scale))
    return {"compared": sum(1 for key in first if key in second), "moved": moved,
            "missing": sorted(set(first) - set(second)), "extra": sorted(set(second) - set(first))}
