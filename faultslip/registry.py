"""The user registry of fitted materials (``faultslip fit --name NAME``).

A JSON file, by default ``$XDG_DATA_HOME/faultslip/fits.json`` (``~/.local/share/faultslip/fits.json``),
or the path in the environment variable ``FAULTSLIP_REGISTRY``. Each entry holds a fit of seed 003
eq. 2-18 with its uncertainty (covariance, standard errors, 95 % intervals and the bootstrap
samples used to carry the uncertainty into fault predictions), its source, and optionally the
shear modulus of the rock, so that ``faultslip fault --lithology NAME`` can use it.

Edits are atomic (temporary file, then rename) and happen only after a fit has succeeded: a
failed fit, or an interrupted write, leaves the registry as it was.
"""

from __future__ import annotations

import json
import os
from datetime import datetime, timezone
from pathlib import Path

from .atomic import write_text_atomic
from .errors import InputError

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
    entries = load()
    entry = fit.to_record()
    entry.update(name=key, created=datetime.now(timezone.utc).isoformat(timespec="seconds"), note=note,
                 shear_modulus=shear_modulus)
    entries[key] = entry
    path = registry_path()
    path.parent.mkdir(parents=True, exist_ok=True)
    write_text_atomic(path, json.dumps({"faultslip_registry": VERSION, "fits": entries}, indent=1) + "\n")
    return path


def remove_fit(name: str) -> None:
    from .materials import _normalise

    entries = load()
    key = _normalise(name)
    if key not in entries:
        raise InputError(f"no fit named {name!r} in {registry_path()}")
    del entries[key]
    write_text_atomic(registry_path(), json.dumps({"faultslip_registry": VERSION, "fits": entries}, indent=1) + "\n")


def user_presets() -> dict:
    """User fits as :class:`~faultslip.materials.Preset` objects (friction law; no apparatus)."""
    from .friction import RateLaw
    from .materials import Preset

    presets = {}
    for key, entry in load().items():
        try:
            law = RateLaw(entry["mu_so"], entry["mu_m"], entry["b"], entry["d"])
        except (KeyError, TypeError, InputError):
            continue  # a damaged entry is skipped, not fatal
        presets[key] = Preset(name=key, material="user fit", condition=entry.get("note") or "fitted", lithology=None,
                              source=f"user fit of {Path(entry.get('source', '?')).name} ({entry.get('created', '')})",
                              rate_law=law, printed={"registry": entry})
    return presets


def entry(name: str) -> dict | None:
    from .materials import _normalise

    return load().get(_normalise(name))
