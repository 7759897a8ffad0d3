"""Laboratory friction presets (seed 003 Table I) and lithologies.

A *preset* is a (material, condition) pair with a stable snake_case name such
as ``granodiorite_water``. Stick-slip presets carry the rate law of seed 003
eq. 2-18 and the apparatus they were measured on (normal load W, strain-ring
stiffness K, moving mass M = W/g). Steady-sliding presets (green schist, dry
granodiorite) carry only their friction coefficient.

A *lithology* carries the shear modulus quoted in seed 003 and the preset that
supplies its friction law on a fault.
"""

from __future__ import annotations

import difflib
import warnings
from dataclasses import dataclass, field
from datetime import datetime, timezone
from functools import lru_cache
from pathlib import Path

from faultslip.friction import registry
from faultslip.errors import InputError
from faultslip.friction.laws import RateLaw
from faultslip.friction.rate_state import RateStateLaw
from faultslip.io.resources import data_path, read_table
from faultslip.units import STANDARD_GRAVITY, to_si


@dataclass(frozen=True)
class Preset:
    """One laboratory friction measurement set."""

    name: str
    material: str
    condition: str
    lithology: str | None
    source: str
    rate_law: RateLaw | None = None
    #: Apparatus normal load W in N (None where the seed does not give it).
    normal_load: float | None = None
    #: Apparatus stiffness K in N/m.
    stiffness: float | None = None
    figures: str = ""
    #: Friction of a steady-sliding material (no stick-slip).
    friction: float | None = None
    #: Table I row as printed: name -> (text, unit).
    printed: dict = field(default_factory=dict, compare=False, repr=False)

    @property
    def stick_slip(self) -> bool:
        return self.rate_law is not None and self.rate_law.stick_slip

    @property
    def mass(self) -> float | None:
        """Moving mass M = W/g in kg (seed 003 §2: W = M g in its apparatus)."""
        return None if self.normal_load is None else self.normal_load / STANDARD_GRAVITY

    def require_stick_slip(self) -> RateLaw:
        if not self.stick_slip:
            raise InputError(
                f"preset {self.name} shows no stick-slip (steady sliding, friction about {self.friction}); "
                "choose a stick-slip preset, see 'faultslip materials'"
            )
        return self.rate_law


@dataclass(frozen=True)
class Lithology:
    """A rock type with the shear modulus quoted in seed 003."""

    name: str
    shear_modulus: float | None  # Pa (None: a saved fit stored without one)
    default_preset: str | None
    source: str


def _normalise(name: str) -> str:
    return "_".join(str(name).strip().lower().replace("-", " ").replace(",", " ").split())


def _parse(text_unit, kind, name):
    text, unit = text_unit
    if text == "":
        return None
    if unit in (None, "1"):
        return float(text)
    return to_si(f"{text} {unit}", kind, name)


def _described(row) -> dict:
    """The columns that Table I and the steady-sliding table share."""
    return dict(
        name=row["preset"][0],
        material=row["material"][0],
        condition=row["condition"][0],
        lithology=row["lithology"][0] or None,
        source=row["source"][0],
        printed=row,
    )


@lru_cache(maxsize=None)
def _bundled_presets() -> dict[str, Preset]:
    presets: dict[str, Preset] = {}
    for row in read_table(data_path("table_I.csv")):
        law = RateLaw(
            mu_so=_parse(row["mu_so"], None, "mu_so"),
            mu_m=_parse(row["mu_m"], None, "mu_m"),
            b=float(row["b"][0]),
            d=_parse(row["d"], None, "d"),
        )
        presets[row["preset"][0]] = Preset(
            **_described(row),
            rate_law=law,
            normal_load=_parse(row["normal_load"], "force", "normal load"),
            stiffness=_parse(row["stiffness"], "stiffness", "stiffness"),
            figures=row["figures"][0],
        )
    for row in read_table(data_path("steady_sliding.csv")):
        mu = _parse(row["friction"], None, "friction")
        presets[row["preset"][0]] = Preset(
            **_described(row),
            rate_law=RateLaw(mu_so=mu, mu_m=mu),
            friction=mu,
        )
    return presets


@lru_cache(maxsize=None)
def _bundled_lithologies() -> dict[str, Lithology]:
    return {
        row["lithology"][0]: Lithology(
            name=row["lithology"][0],
            shear_modulus=_parse(row["shear_modulus"], "pressure", "shear modulus"),
            default_preset=row["default_preset"][0] or None,
            source=row["source"][0],
        )
        for row in read_table(data_path("lithologies.csv"))
    }


def presets() -> dict[str, Preset]:
    """All presets by name: Table I, the steady-sliding materials and the user's fits.

    Returns
    -------
    dict
        Name -> :class:`Preset` (rate law, apparatus in N and N/m, sources).
    """
    merged = dict(_bundled_presets())
    merged.update(user_presets())
    return merged


def user_presets() -> dict[str, Preset]:
    """User fits from the registry as presets (friction law; no apparatus).

    A damaged entry is skipped with a warning that names it; an entry that would shadow a
    bundled preset or lithology is ignored, also with a warning.
    """
    out = {}
    bundled = set(_bundled_presets()) | set(_bundled_lithologies())
    for key, entry in registry.stored_entries().items():
        if isinstance(entry, dict) and entry.get("kind") == "rate_state":
            continue  # a rate-and-state fit: see user_rate_state_fits
        if key in bundled:
            warnings.warn(f"the fit registry entry {key!r} would shadow a bundled preset or lithology; it is ignored "
                          f"(rename it in {registry.registry_path()})", stacklevel=2)
            continue
        try:
            if not isinstance(entry, dict):
                raise TypeError("not a table")
            law = RateLaw(*(float(entry[k]) for k in ("mu_so", "mu_m", "b", "d")))
        except (KeyError, TypeError, ValueError, InputError) as exc:
            detail = f"missing {exc}" if isinstance(exc, KeyError) else str(exc)
            warnings.warn(f"the fit registry entry {key!r} is damaged ({detail}); it is skipped", stacklevel=2)
            continue
        out[key] = Preset(name=key, material="user fit", condition=entry.get("note") or "fitted", lithology=None,
                          source=f"user fit of {Path(str(entry.get('source', '?'))).name} ({entry.get('created', '')})",
                          rate_law=law, printed={"registry": entry})
    return out


def user_rate_state_fits() -> dict[str, tuple[RateStateLaw, dict]]:
    """Rate-and-state fits from the registry: name -> (law, entry). A damaged entry is skipped with a warning."""
    out = {}
    for key, entry in registry.stored_entries().items():
        if not (isinstance(entry, dict) and entry.get("kind") == "rate_state"):
            continue
        try:
            law = RateStateLaw(a=float(entry["a"]), b=float(entry["b"]), critical_slip=float(entry["critical_slip"]),
                               mu0=float(entry["mu0"]), reference_speed=float(entry["reference_speed"]),
                               evolution=str(entry["evolution"]), b2=float(entry.get("b2") or 0.0),
                               critical_slip2=(float(entry["critical_slip2"]) if entry.get("critical_slip2") else None),
                               source=f"user fit of {Path(str(entry.get('source', '?'))).name} "
                                      f"({entry.get('created', '')})")
        except (KeyError, TypeError, ValueError, InputError) as exc:
            detail = f"missing {exc}" if isinstance(exc, KeyError) else str(exc)
            warnings.warn(f"the fit registry entry {key!r} is damaged ({detail}); it is skipped", stacklevel=2)
            continue
        out[key] = (law, entry)
    return out


def check_fit_name(name, overwrite: bool = False) -> str:
    """The registry key of a fit to be saved as ``name``, checked before any fitting starts.

    Refused in one sentence: an empty name, one that is not letters, digits and underscores, a
    bundled preset's or lithology's name, and, unless ``overwrite``, the name of a saved fit.
    """
    key = _normalise(str(name))
    if not key:
        raise InputError("the fit's name (--name) is empty; give the name to save it under")
    if not key.replace("_", "").isalnum():
        raise InputError(f"fit name {name!r} must be letters, digits and underscores")
    if key in _bundled_presets() or key in _bundled_lithologies():
        raise InputError(f"{key!r} is a bundled preset or lithology; choose another name for the fit")
    if not overwrite and key in registry.load():
        raise InputError(f"a fit named {key!r} is saved already in {registry.registry_path()}; pass --overwrite to "
                         "replace it, or choose another name")
    return key


def save_user_fit(name: str, fit, shear_modulus: float | None = None, note: str = "", source: str = "",
                  overwrite: bool = False) -> Path:
    """Store a fit (eq. 2-18, or rate-and-state) under ``name`` (snake_case) in the user registry.

    Bundled names are refused, and a saved fit is replaced only with ``overwrite``. A
    rate-and-state fit is stored with ``kind = "rate_state"``.
    """
    key = check_fit_name(name, overwrite)
    entry = fit.to_record()
    entry.update(name=key, created=datetime.now(timezone.utc).isoformat(timespec="seconds"), note=note,
                 shear_modulus=shear_modulus)
    if source:
        entry["source"] = source
    return registry.save_entry(key, entry, overwrite)


def remove_user_fit(name: str) -> None:
    registry.remove_entry(_normalise(name))


def user_fit_entry(name: str) -> dict | None:
    return registry.stored_entries().get(_normalise(name))


def lithologies() -> dict[str, Lithology]:
    """All lithologies by name: the bundled ones and the user's saved fits (what ``fault --lithology`` takes and
    ``faultslip materials`` lists). A saved fit's shear modulus is the one it was saved with (None: none).

    Returns
    -------
    dict
        Name -> :class:`Lithology` (shear modulus in Pa, density in kg/m^3, friction preset, sources).
    """
    merged = dict(_bundled_lithologies())
    entries = registry.stored_entries()
    rate_law_fits = user_presets()  # read once: each call reads the registry file again
    for name in list(rate_law_fits) + list(user_rate_state_fits()):
        entry = entries.get(name, {})
        modulus = entry.get("shear_modulus")
        merged[name] = Lithology(name=name, shear_modulus=float(modulus) if modulus is not None else None,
                                 default_preset=name if name in rate_law_fits else None,
                                 source=f"user fit ({entry.get('kind', 'rate_law')}, saved {entry.get('created', '')})")
    return merged


def bundled_lithologies() -> dict[str, Lithology]:
    """The lithologies shipped with faultslip (data/lithologies.csv), without the user's fits."""
    return dict(_bundled_lithologies())


def fits() -> dict[str, dict]:
    """The user's saved fits by name, as the registry stores them (law, parameters, intervals, note, source).

    Returns
    -------
    dict
        Fit name -> the registry's entry: its law, parameters (SI), intervals, note and source.
    """
    return {name: dict(entry) for name, entry in registry.stored_entries().items() if isinstance(entry, dict)}


def save_fit(name: str, fit, shear_modulus=None, note: str = "", overwrite: bool = False) -> Path:
    """Save a fit (:func:`~faultslip.friction.fitting.fit_rate_law`, or a rate-and-state fit or posterior) under
    ``name`` in the user registry, for ``fault --lithology NAME`` and :func:`lithologies`.

    Parameters
    ----------
    name : str
        Letters, digits and underscores; not a bundled preset's or lithology's name.
    fit : RateLawFit or RateStateFit or Posterior
        What to save (its ``to_record()``).
    shear_modulus : float or str, optional
        The rock's shear modulus, Pa or text with units ("30 GPa"), kept for fault predictions.
    note : str
        A note kept with the fit (rock, condition).
    overwrite : bool
        Replace a fit already saved under ``name`` (refused otherwise).

    Returns
    -------
    pathlib.Path
        The registry file.
    """
    modulus = None
    if shear_modulus is not None:
        modulus = shear_modulus if isinstance(shear_modulus, (int, float)) else to_si(shear_modulus, "pressure",
                                                                                         "shear modulus")
    return save_user_fit(name, fit, shear_modulus=modulus, note=note, overwrite=overwrite)


def table_i_presets() -> list[Preset]:
    """The eleven stick-slip rows of seed 003 Table I, in table order."""
    return [p for p in _bundled_presets().values() if p.normal_load is not None]


def _unknown(kind: str, name: str, known) -> InputError:
    known = sorted(known)
    close = difflib.get_close_matches(_normalise(name), known, n=3, cutoff=0.5)
    if not close:  # also match on a shared word, e.g. "granite" -> granodiorite_*
        close = [k for k in known if any(part and part in k for part in _normalise(name).split("_"))][:3]
    hint = f"; did you mean {', '.join(close)}?" if close else ""
    return InputError(f"unknown {kind} {name!r}{hint} (see 'faultslip materials' for the list)")


def _lookup(kind: str, name: str, table: dict):
    key = _normalise(name)
    if key in table:
        return table[key]
    raise _unknown(kind, name, table)


def get_preset(name: str) -> Preset:
    """A preset by name (case and separators are forgiven).

    Parameters
    ----------
    name : str
        A preset's name (Table I, steady-sliding materials, saved fits).

    Returns
    -------
    Preset
        Its rate law and apparatus (N, N/m), with sources.
    """
    return _lookup("preset", name, presets())


def get_lithology(name: str) -> Lithology:
    """A lithology by name (case and separators are forgiven).

    Parameters
    ----------
    name : str
        A lithology's name.

    Returns
    -------
    Lithology
        Its shear modulus (Pa), density and friction preset, with sources.
    """
    return _lookup("lithology", name, lithologies())


@dataclass(frozen=True)
class MaterialChoice:
    """What a ``--lithology NAME`` resolves to: a shear modulus and a friction preset."""

    name: str
    lithology: Lithology | None
    preset: Preset | None
    #: a rate-and-state fit from the registry, and its entry (intervals, bootstrap resamples)
    rate_state: RateStateLaw | None = None
    rate_state_entry: dict | None = None

    @property
    def shear_modulus(self) -> float | None:
        return None if self.lithology is None else self.lithology.shear_modulus

    @property
    def rate_law(self) -> RateLaw | None:
        return None if self.preset is None else self.preset.rate_law


def resolve_material(name: str) -> MaterialChoice:
    """Resolve a preset or lithology name to (lithology, preset).

    A preset brings its friction law and, if it is a rock, its lithology's
    shear modulus. A lithology brings its shear modulus and its default preset
    (the wet fit for granodiorite, black marble and pyrite: fault zones are
    fluid-saturated and seed 003 used the wet fit for its fault example).
    """
    key = _normalise(name)
    table = presets()
    liths = bundled_lithologies()  # a saved fit resolves below, as a preset or a rate-and-state law
    if key in table:
        preset = table[key]
        stored = preset.printed.get("registry") if isinstance(preset.printed, dict) else None
        if stored is not None and stored.get("shear_modulus"):  # a user fit saved with its rock's modulus
            return MaterialChoice(key, Lithology(key, float(stored["shear_modulus"]), key, preset.source), preset)
        return MaterialChoice(key, liths.get(preset.lithology) if preset.lithology else None, preset)
    if key in liths:
        lith = liths[key]
        return MaterialChoice(key, lith, table.get(lith.default_preset) if lith.default_preset else None)
    fits = user_rate_state_fits()
    if key in fits:
        law, entry = fits[key]
        modulus = entry.get("shear_modulus")
        lith = Lithology(key, float(modulus), key, law.source) if modulus else None
        return MaterialChoice(key, lith, None, rate_state=law, rate_state_entry=entry)
    raise _unknown("lithology or preset", name, list(table) + list(liths) + list(fits))
