"""The user registry of fitted materials (``faultslip fit --name NAME``).

A JSON file, by default ``$XDG_DATA_HOME/faultslip/fits.json`` (``~/.local/share/faultslip/fits.json``),
or the path in the environment variable ``FAULTSLIP_REGISTRY``. Each entry holds a fit of seed 003
eq. 2-18 with its uncertainty (covariance, standard errors, 95 % intervals and the bootstrap
samples used to carry the uncertainty into fault predictions), its source, and optionally the
shear modulus of the rock, so that ``faultslip fault --lithology NAME`` can use it.

Edits are read-modify-write under a lock (two concurrent ``fit --name`` runs both land), atomic
(temporary file, then rename), and happen only after a fit has succeeded: a failed fit, or an
interrupted write, leaves the registry as it was. A damaged entry is skipped with a warning that
names it, and an entry that would shadow a bundled preset or lithology is ignored, also with a
warning.
"""

from __future__ import annotations

import json
import os
import warnings
from datetime import datetime, timezone
from pathlib import Path

from .atomic import write_text_atomic
from .errors import InputError
from .outputs import file_lock

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
    try:
        document = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise InputError(f"the fit registry {str(path)!r} is unreadable ({exc}); move it aside or set FAULTSLIP_REGISTRY") from None
    if not isinstance(document, dict) or not isinstance(document.get("fits"), dict):
        raise InputError(f"the fit registry {str(path)!r} is not a faultslip registry; move it aside or set FAULTSLIP_REGISTRY")
    return document["fits"]


def save_fit(name: str, fit, shear_modulus: float | None = None, note: str = "") -> Path:
    """Store a fit under ``name`` (snake_case; bundled names are refused) atomically."""
    from .materials import _bundled_lithologies, _bundled_presets, _normalise

    key = _normalise(name)
    if not key or not key.replace("_", "").isalnum():
        raise InputError(f"fit name {name!r} must be letters, digits and underscores")
    if key in _bundled_presets() or key in _bundled_lithologies():
        raise InputError(f"{key!r} is a bundled preset or lithology; choose another name for the fit")
    entry = fit.to_record()
    entry.update(name=key, created=datetime.now(timezone.utc).isoformat(timespec="seconds"), note=note,
                 shear_modulus=shear_modulus)
    path = registry_path()
    path.parent.mkdir(parents=True, exist_ok=True)
    with file_lock(path):  # read-modify-write: a concurrent fit must not be lost
        entries = load()
        entries[key] = entry
        write_text_atomic(path, json.dumps({"faultslip_registry": VERSION, "fits": entries}, indent=1) + "\n")
    return path


def remove_fit(name: str) -> None:
    from .materials import _normalise

    key = _normalise(name)
    with file_lock(registry_path()):
        entries = load()
        if key not in entries:
            raise InputError(f"no fit named {name!r} in {registry_path()}")
        del entries[key]
        write_text_atomic(registry_path(), json.dumps({"faultslip_registry": VERSION, "fits": entries}, indent=1) + "\n")


def user_presets() -> dict:
    """User fits as :class:`~faultslip.materials.Preset` objects (friction law; no apparatus)."""
    from .friction import RateLaw
    from .materials import Preset, _bundled_lithologies, _bundled_presets

    presets = {}
    bundled = set(_bundled_presets()) | set(_bundled_lithologies())
    try:
        stored = load()
    except InputError as exc:  # reading bundled materials must not fail on a broken user file
        warnings.warn(f"{exc}; user fits are not available", stacklevel=2)
        return presets
    for key, entry in stored.items():
        if key in bundled:
            warnings.warn(f"the fit registry entry {key!r} would shadow a bundled preset or lithology; it is ignored "
                          f"(rename it in {registry_path()})", stacklevel=2)
            continue
        try:
            if not isinstance(entry, dict):
                raise TypeError("not a table")
            law = RateLaw(*(float(entry[k]) for k in ("mu_so", "mu_m", "b", "d")))
        except (KeyError, TypeError, ValueError, InputError) as exc:
            detail = f"missing {exc}" if isinstance(exc, KeyError) else str(exc)
            warnings.warn(f"the fit registry entry {key!r} is damaged ({detail}); it is skipped", stacklevel=2)
            continue
        presets[key] = Preset(name=key, material="user fit", condition=entry.get("note") or "fitted", lithology=None,
                              source=f"user fit of {Path(entry.get('source', '?')).name} ({entry.get('created', '')})",
                              rate_law=law, printed={"registry": entry})
    return presets


def entry(name: str) -> dict | None:
    from .materials import _normalise

    return load().get(_normalise(name))
