"""The user registry of fitted materials (``faultslip fit --name NAME``).

A JSON file, by default ``$XDG_DATA_HOME/faultslip/fits.json`` (``~/.local/share/faultslip/fits.json``),
or the path in the environment variable ``FAULTSLIP_REGISTRY``. Each entry holds a fit of seed 003
eq. 2-18 with its uncertainty (covariance, standard errors, 95 % intervals and the bootstrap
samples used to carry the uncertainty into fault predictions), its source, and optionally the
shear modulus of the rock, so that ``faultslip fault --lithology NAME`` can use it.

This module only stores entries: names, the bundled-name check and the presets built from the
entries belong to :mod:`faultslip.friction.materials` (which imports this module, never the reverse).
Edits are read-modify-write under a lock (two concurrent ``fit --name`` runs both land), atomic
(temporary file, then rename), and happen only after a fit has succeeded: a failed fit, or an
interrupted write, leaves the registry as it was. Each entry carries the checksum of its own content
(:func:`faultslip.io.gate.json_checksum`), written with it: an entry changed afterwards is skipped with
a warning that names it, as a damaged one is, and is never used as if it were the fit that was saved.
"""

from __future__ import annotations

import json
import os
import warnings
from pathlib import Path

from faultslip.io import gate
from faultslip.io.atomic import write_text_atomic
from faultslip.errors import InputError
from faultslip.io.outputs import file_lock

#: 2: every entry carries its checksum (version 1 registries, of an older faultslip, carry none).
VERSION = 2


def registry_path() -> Path:
    """Where the registry lives (``FAULTSLIP_REGISTRY`` overrides the XDG default)."""
    override = os.environ.get("FAULTSLIP_REGISTRY")
    if override:
        return Path(override).expanduser()
    base = os.environ.get("XDG_DATA_HOME") or os.path.join(os.path.expanduser("~"), ".local", "share")
    return Path(base) / "faultslip" / "fits.json"


def load() -> dict:
    """All entries by name as the file holds them, checksums included (an empty registry if the file does not
    exist). :func:`stored_entries` gives the entries that match their checksums."""
    return _document()[1]


def _document() -> tuple[int, dict]:
    """The registry's version and its entries as stored."""
    path = registry_path()
    if not path.exists():
        return VERSION, {}
    text = gate.read_text(path, "fit registry", "config")
    try:
        document = json.loads(text)
    except (ValueError, RecursionError) as exc:
        raise InputError(f"the fit registry {str(path)!r} is unreadable ({exc}); move it aside or set FAULTSLIP_REGISTRY") from None
    if not isinstance(document, dict) or not isinstance(document.get("fits"), dict):
        raise InputError(f"the fit registry {str(path)!r} is not a faultslip registry; move it aside or set FAULTSLIP_REGISTRY")
    version = document.get("faultslip_registry")
    return (version if isinstance(version, int) and not isinstance(version, bool) else VERSION), document["fits"]


def _sealed(entry: dict) -> dict:
    """``entry`` with the checksum of its content."""
    entry = {key: value for key, value in entry.items() if key != "checksum"}
    return entry | {"checksum": gate.json_checksum(entry)}


def save_entry(key: str, entry: dict, overwrite: bool = False) -> Path:
    """Store one entry under ``key`` (already checked by :func:`faultslip.friction.materials.save_user_fit`).

    Read-modify-write under a lock, written atomically: a concurrent save is never lost, and an
    entry saved meanwhile under the same key is replaced only with ``overwrite``.
    """
    path = registry_path()
    path.parent.mkdir(parents=True, exist_ok=True)
    with file_lock(path):
        entries = load()
        if key in entries and not overwrite:
            raise InputError(f"a fit named {key!r} is saved already in {path}; pass --overwrite to replace it, or "
                             "choose another name")
        entries[key] = _sealed(entry)  # the others stay as they were read: a damaged one is not sealed anew
        write_text_atomic(path, json.dumps({"faultslip_registry": VERSION, "fits": entries}, indent=1) + "\n",
                          immediate=True)  # written under the lock, or a concurrent fit is lost
    return path


def remove_entry(key: str) -> None:
    """Remove the entry ``key``; an unknown key is an :class:`InputError`."""
    path = registry_path()
    with file_lock(path):
        entries = load()
        if key not in entries:
            raise InputError(f"no fit named {key!r} in {path}")
        del entries[key]
        write_text_atomic(path, json.dumps({"faultslip_registry": VERSION, "fits": entries}, indent=1) + "\n",
                          immediate=True)  # written under the lock, or a concurrent fit is lost


def stored_entries() -> dict:
    """The entries by key that match the checksums written with them (without the checksum), or an empty dict
    with a warning if the file is unreadable.

    An entry that does not match its checksum, or has none in a registry that writes them, is skipped with a
    warning that names it; the entries of an older faultslip's registry (version 1, no checksums) are read with
    one warning that says they are unchecked. Reading bundled materials must not fail on a broken user file;
    writing still refuses it (:func:`load` raises), so nothing is overwritten.
    """
    try:
        version, entries = _document()
    except InputError as exc:
        warnings.warn(f"{exc}; user fits are not available", stacklevel=3)
        return {}
    found, unchecked = {}, []
    for key, entry in entries.items():
        if not isinstance(entry, dict):
            found[key] = entry  # the readers of entries skip it, naming it damaged
        elif "checksum" in entry or version >= 2:
            if entry.get("checksum") != gate.json_checksum(entry):
                warnings.warn(f"the fit registry entry {key!r} does not match the checksum written with it (it was "
                              f"edited or damaged after it was saved); it is skipped (save the fit again, or remove it "
                              f"from {registry_path()})", stacklevel=3)
                continue
            found[key] = {name: value for name, value in entry.items() if name != "checksum"}
        else:
            found[key] = entry
            unchecked.append(key)
    if unchecked:
        warnings.warn(f"the fit registry {registry_path()} was written by an older faultslip, without checksums: its "
                      f"{len(unchecked)} entries are read unchecked (saving a fit seals that fit)", stacklevel=3)
    return found
