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
interrupted write, leaves the registry as it was.
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

VERSION = 1


def registry_path() -> Path:
    """Where the registry lives (``FAULTSLIP_REGISTRY`` overrides the XDG default)."""
    override = os.environ.get("FAULTSLIP_REGISTRY")
    if override:
        return Path(override).expanduser()
    base = os.environ.get("XDG_DATA_HOME") or os.path.join(os.path.expanduser("~"), ".local", "share")
    return Path(base) / "faultslip" / "fits.json"


def load() -> dict:
    """All entries by name (an empty registry if the file does not exist)."""
    path = registry_path()
    if not path.exists():
        return {}
    text = gate.read_text(path, "fit registry", "config")
    try:
        document = json.loads(text)
    except (ValueError, RecursionError) as exc:
        raise InputError(f"the fit registry {str(path)!r} is unreadable ({exc}); move it aside or set FAULTSLIP_REGISTRY") from None
    if not isinstance(document, dict) or not isinstance(document.get("fits"), dict):
        raise InputError(f"the fit registry {str(path)!r} is not a faultslip registry; move it aside or set FAULTSLIP_REGISTRY")
    return document["fits"]


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
        entries[key] = entry
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
    """The entries by key, or an empty dict with a warning if the file is unreadable.

    Reading bundled materials must not fail on a broken user file; writing still refuses it
    (:func:`load` raises), so nothing is overwritten.
    """
    try:
        return load()
    except InputError as exc:
        warnings.warn(f"{exc}; user fits are not available", stacklevel=3)
        return {}
