"""Rate-and-state scenes: a law, a slider (lab) or a fault, and a load history, from TOML with units.

::

    [law]                         # or: preset = "granite_illustrative"
    a = 0.005
    b = 0.01
    critical_slip = "10 um"
    mu0 = 0.6
    reference_speed = "1 um/s"
    evolution = "aging"           # or "slip"; b2 and critical_slip2 add a second state variable

    [slider]                      # a laboratory slider ...
    stiffness = "1e-3 1/um"       # friction per slip (k / sigma_n), or a stiffness with normal_load
    model = "quasi_static"        # quasi_static, quasi_dynamic (needs damping) or inertial (needs mass)

    [fault]                       # ... or a fault (per unit area): eta = G / (2 c_s), m = rho G / K
    shear_modulus = "32 GPa"
    seismogenic_width = "15 km"   # W: K = c G / W, c calibrated against the 2-D fault (faultslip.models.rate_state_slider.one_slider)
                                  # or zone_width = "20 km": the seed's section 5-2 reduction, K = G / D
    normal_stress = "50 MPa"
    plate_rate = "1e-9 m/s"

    [load]                        # the load point (a slider): steps, or slide_hold_slide
    steps = [["0 s", "1 um/s"], ["10 s", "10 um/s"]]
    duration = "40 s"
    samples = 4001
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

from faultslip.fault.one_slider_error import declared_model_error
from faultslip.dynamics.rate_state.slider import MODELS, LoadHistory, RateStateSlider
from faultslip.contract.scenes import scene_source
from faultslip.errors import InputError
from faultslip.models.rate_state_slider.one_slider import REDUCTIONS, stiffness_factor
from faultslip.friction.rate_state import RateStateLaw, get_law
from faultslip.io.resources import check_table_keys, parse_toml
from faultslip.units import to_si_scalar

_LAW_KEYS = {"preset", "a", "b", "critical_slip", "mu0", "reference_speed", "evolution", "b2", "critical_slip2",
             "regularized", "source"}
_SLIDER_KEYS = {"stiffness", "normal_load", "mass", "damping", "model"}
_FAULT_KEYS = {"shear_modulus", "zone_width", "seismogenic_width", "normal_stress", "plate_rate", "density", "shear_wave_speed", "model",
               "radiation_damping"}
_LOAD_KEYS = {"steps", "slide_hold_slide", "speed", "duration", "samples"}


@dataclass
class RateStateScene:
    """A parsed scene: ``kind`` is "lab" (with a load history) or "fault" (with a plate rate)."""

    name: str
    kind: str
    law: RateStateLaw
    slider: RateStateSlider
    model: str
    history: LoadHistory | None = None
    samples: int = 1001
    plate_rate: float | None = None
    origin: str = ""
    #: a fault scene's inputs in SI (shear_modulus, zone_width, normal_stress, density, shear_wave_speed);
    #: ``zone_width`` is the block's G / K (D itself for the seed's reduction)
    fault: dict = field(default_factory=dict)
    #: how the block's stiffness comes from the fault (faultslip.models.rate_state_slider.one_slider.REDUCTIONS): "geometric", from
    #: the seismogenic width, or "zone_width", the seed's section 5-2 reduction
    reduction: str = "zone_width"
    #: m: the width the scene states (W, or D for the seed's reduction)
    width: float | None = None


def _check_keys(table, allowed, section, source):
    check_table_keys(table, allowed, section, source)


def _law(table, source) -> RateStateLaw:
    _check_keys(table, _LAW_KEYS, "law", source)
    if "preset" in table:
        if len(table) > 1:
            raise InputError(f"[law] in {source}: give either preset or the parameters, not both")
        return get_law(str(table["preset"]))
    for key in ("a", "b", "critical_slip"):
        if key not in table:
            raise InputError(f"[law] in {source} needs {key}")
    evolution = table.get("evolution", "aging")
    if not isinstance(evolution, str):
        raise InputError(f"[law] in {source}: evolution must be \"aging\" or \"slip\"")
    regularized = table.get("regularized", False)
    if not isinstance(regularized, bool):
        raise InputError(f"[law] in {source}: regularized must be true or false")
    return RateStateLaw.from_text(table["a"], table["b"], table["critical_slip"], table.get("mu0", 0.6),
                                  table.get("reference_speed", "1 um/s"), evolution, table.get("b2", 0.0),
                                  table.get("critical_slip2"), regularized, str(table.get("source", source)))


def _history(table, source) -> tuple[LoadHistory, int]:
    _check_keys(table, _LOAD_KEYS, "load", source)
    samples = table.get("samples", 1001)
    if not isinstance(samples, int) or isinstance(samples, bool) or not 2 <= samples <= 10_000_000:
        raise InputError(f"[load] samples in {source} must be a whole number from 2 to 1e7, got {samples!r}")
    if "duration" not in table:
        raise InputError(f"[load] in {source} needs duration")
    duration = to_si_scalar(table["duration"], "time", "duration")
    if not duration > 0:
        raise InputError(f"[load] duration in {source} must be positive")
    if "steps" in table:
        steps = table["steps"]
        if not isinstance(steps, list) or not steps or not all(isinstance(s, list) and len(s) == 2 for s in steps):
            raise InputError(f"[load] steps in {source} must be a list of [time, speed] pairs")
        parsed = [(to_si_scalar(t, "time", "step time"), to_si_scalar(v, "speed", "step speed")) for t, v in steps]
        if parsed[0][0] != 0.0:
            raise InputError(f"[load] the first step in {source} must start at 0 s")
        if parsed[-1][0] >= duration:
            raise InputError(f"[load] every step in {source} must start before the duration ends")
        return LoadHistory.velocity_steps(parsed, duration), samples
    if "slide_hold_slide" in table:
        spec = table["slide_hold_slide"]
        if not isinstance(spec, dict) or not {"speed", "slide", "holds"} <= set(spec):
            raise InputError(f"[load] slide_hold_slide in {source} needs speed, slide and holds")
        history = LoadHistory.slide_hold_slide(to_si_scalar(spec["speed"], "speed", "speed"),
                                               to_si_scalar(spec["slide"], "time", "slide"),
                                               [to_si_scalar(h, "time", "hold") for h in spec["holds"]])
        return history, samples
    if "speed" in table:
        return LoadHistory.constant(to_si_scalar(table["speed"], "speed", "speed"), duration), samples
    raise InputError(f"[load] in {source} needs steps, slide_hold_slide or speed")


def parse_rate_state_scene(text: str, source: str = "<scene>") -> RateStateScene:
    data = parse_toml(text, source)
    unknown = sorted(set(data) - {"name", "family", "law", "slider", "fault", "load"})
    if unknown:
        raise InputError(f"unknown section {unknown[0]!r} in {source} (a rate-and-state scene has [law], [slider] "
                         "or [fault], and [load])")
    if "law" not in data:
        raise InputError(f"{source} needs a [law] table")
    law = _law(data["law"], source)
    name = str(data.get("name", Path(source).stem))
    if ("slider" in data) == ("fault" in data):
        raise InputError(f"{source} needs exactly one of [slider] (a laboratory slider) and [fault]")
    if "slider" in data:
        table = data["slider"]
        _check_keys(table, _SLIDER_KEYS, "slider", source)
        if "stiffness" not in table:
            raise InputError(f"[slider] in {source} needs stiffness")
        if "normal_load" in table:
            stiffness = to_si_scalar(table["stiffness"], "stiffness", "stiffness")
            normal = to_si_scalar(table["normal_load"], "force", "normal load")
        else:  # friction per slip: the normal load is the unit
            stiffness, normal = to_si_scalar(table["stiffness"], "inverse_length", "stiffness"), 1.0
        mass = to_si_scalar(table.get("mass", "0 kg"), "mass", "mass")
        damping = to_si_scalar(table.get("damping", "0 N*s/m"), "damping", "damping")
        slider = RateStateSlider(law, stiffness, normal, mass, damping)
        model = table.get("model", "quasi_static")
        if "load" not in data:
            raise InputError(f"{source} needs a [load] table for a laboratory slider")
        history, samples = _history(data["load"], source)
        kind, plate_rate, fault_inputs, reduction, width = "lab", None, {}, "zone_width", None
    else:
        table = data["fault"]
        _check_keys(table, _FAULT_KEYS, "fault", source)
        for key in ("shear_modulus", "normal_stress", "plate_rate"):
            if key not in table:
                raise InputError(f"[fault] in {source} needs {key}")
        stated = [key for key in REDUCTIONS if key in table]
        if len(stated) != 1:
            raise InputError(f"[fault] in {source} needs one of seismogenic_width (W: K = c G / W, the stiffness "
                             "calibrated against the 2-D fault) and zone_width (D: the seed's reduction K = G / D)")
        reduction = REDUCTIONS[stated[0]]
        width = to_si_scalar(table[stated[0]], "length", stated[0].replace("_", " "))
        radiation = table.get("radiation_damping", True)
        if not isinstance(radiation, bool):
            raise InputError(f"[fault] radiation_damping in {source} must be true or false")
        wave = to_si_scalar(table["shear_wave_speed"], "speed", "shear wave speed") if "shear_wave_speed" in table else None
        fault = {"shear_modulus": to_si_scalar(table["shear_modulus"], "pressure", "shear modulus"),
                 "zone_width": width if reduction == "zone_width" else width / stiffness_factor(),
                 "normal_stress": to_si_scalar(table["normal_stress"], "pressure", "normal stress"),
                 "density": to_si_scalar(table.get("density", "2700 kg/m^3"), "density", "density"),
                 "shear_wave_speed": wave}
        slider = RateStateSlider.at_fault(law, fault["shear_modulus"], fault["zone_width"], fault["normal_stress"],
                                          fault["density"], wave, radiation)
        plate_rate = to_si_scalar(table["plate_rate"], "speed", "plate rate")
        if not (plate_rate > 0 and math.isfinite(plate_rate)):
            raise InputError(f"[fault] plate_rate in {source} must be a positive speed")
        model = table.get("model", "quasi_dynamic")
        history, samples, kind = None, 0, "fault"
        fault_inputs = fault
        if "load" in data:
            history, samples = _history(data["load"], source)
    if model not in MODELS:
        raise InputError(f"model in {source} must be one of {', '.join(MODELS)}, got {model!r}")
    return RateStateScene(name, kind, law, slider, model, history, samples, plate_rate, fault=fault_inputs,
                          reduction=reduction, width=width)


def read_rate_state_scene(path) -> RateStateScene:
    """A rate-and-state scene ([law], and [slider] with [load] or [fault]) from a file, a bundled scene's name or a
    scene varied for a sweep.

    Parameters
    ----------
    path : str, path, TomlScene or RateStateScene
        The scene.

    Returns
    -------
    RateStateScene
        The law, the slider (SI) and the load history or plate rate (m/s).
    """
    if isinstance(path, RateStateScene):  # loaded already
        return path
    text, source, _, origin = scene_source(path, "rate-and-state scene")
    scene = parse_rate_state_scene(text, source)
    scene.origin = origin
    return scene


def model_error_of(loaded) -> tuple[float, float, str]:
    """(model error, W / h*, how it was found) of a one-block fault scene against the 2-D fault it stands for
    (:func:`faultslip.fault.one_slider_error.declared_model_error` at the scene's width and reduction)."""
    fault = loaded.fault
    return declared_model_error(loaded.law, fault["shear_modulus"], fault["normal_stress"], loaded.width,
                                reduction=loaded.reduction)


def stands_for(loaded) -> str:
    """Which fault a one-slider scene stands for: it states one width, so the 2-D fault its declared error and its
    escalation refer to has the scene's friction uniform from the surface to that width, with steady slip at the
    plate rate imposed right below, not a depth profile."""
    width = loaded.width or loaded.fault.get("zone_width")
    return (f"this one-slider scene stands for the fault with its friction uniform from the surface to "
            f"{width / 1e3:.4g} km and steady slip at the plate rate right below (no ramp, no strengthening depth); a "
            "fault scene that states the depth profile (family = \"fault_2d\", configs/rsf_fault_bp1.toml) runs every "
            "rung of the ladder on that profile, the one slider with 95 % ranges in years and metres")
