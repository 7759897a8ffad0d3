"""Spring-block chain scenes: ``family = "spring_chain"`` and a ``[chain]`` table.
::

    name = "a fault of 100 blocks"
    family = "spring_chain"

    [chain]
    blocks = 100
    mass = "1 kg"                    # each block's (default: W / g, as seed 003's sliders)
    leaf_stiffness = "1 kN/m"        # k_p, to the plate
    coupling_stiffness = "10 kN/m"   # k_c, between neighbours
    normal_load = "100 N"            # W on each block
    platform_speed = "1 mm/s"        # V
    damping_ratio = 0.1              # c = 2 zeta sqrt(k_p m)
    threshold_spread = 0.5           # mu_s,i = mu_k + (mu_s - mu_k)(1 + spread u_i), u_i uniform on [-1, 1]
    initial_offset = "1 mm"          # each block starts displaced uniformly in [0, this]
    seed = 1                         # of the thresholds and the start

    [friction]                       # the seed's rate law at each block's loading rate k_p V / W ...
    preset = "glass_dry"
    # ... or constant coefficients: static = 0.6, kinetic = 0.4

    [moment]                         # each block stands for a patch of a fault: M0 = G A sum(slip)
    shear_modulus = "30 GPa"
    patch_area = "1 km^2"

    [run]
    events = 2000
    system_size = 0.5                # an event slipping this share of the blocks is system-size

``faultslip run``, ``simulate`` and ``sweep`` take such a scene.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from faultslip.contract.scenes import scene_source
from faultslip import ranges
from faultslip.errors import InputError
from faultslip.friction.materials import STANDARD_GRAVITY, get_preset
from faultslip.io.resources import check_toml_layout, parse_toml
from faultslip.models.spring_chain.dynamics import Chain
from faultslip.units import to_si

_CHAIN = {"blocks", "mass", "leaf_stiffness", "coupling_stiffness", "normal_load", "platform_speed", "damping_ratio",
          "threshold_spread", "initial_offset", "seed"}
_FRICTION = {"preset", "static", "kinetic"}
_MOMENT = {"shear_modulus", "patch_area"}
_RUN = {"events", "system_size"}
#: the most blocks and events a scene may ask for (a sweep's cell runs each)
MAX_BLOCKS, MAX_EVENTS = 2000, 1_000_000


@dataclass(frozen=True)
class ChainScene:
    """A chain scene read.

    Attributes
    ----------
    chain : Chain
        The blocks, springs and friction.
    initial_position : array
        Each block's position at t = 0 (m).
    shear_modulus, patch_area : float
        G (Pa) and A (m^2): an event's moment is G A sum(slip).
    events : int
        How many events a run records.
    system_size : float
        The share of the blocks that makes an event system-size.
    """

    name: str
    chain: Chain
    initial_position: np.ndarray
    shear_modulus: float
    patch_area: float
    events: int
    system_size: float
    friction: str  # where mu_s and mu_k came from, for the report
    loading_rate: float


def _number(table: dict, key: str, default, source: str, low=None, high=None, whole=False):
    value = table.get(key, default)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InputError(f"[{'chain' if key in _CHAIN else 'run'}] {key} in {source} must be a number, got {value!r}")
    if whole and value != int(value):
        raise InputError(f"{key} in {source} must be a whole number, got {value!r}")
    if (low is not None and value < low) or (high is not None and value > high):
        raise InputError(f"{key} in {source} must lie from {low:g} to {high:g}, got {value!r}")
    return int(value) if whole else float(value)


def parse_chain_scene(text_or_document, source: str = "<scene>") -> ChainScene:
    """A chain scene from its TOML text (see the module); one sentence for anything wrong.

    Parameters
    ----------
    text_or_document : str or dict
        The scene's TOML, or its parsed document.
    source : str
        The scene's name in messages.

    Returns
    -------
    ChainScene
        The chain, its start, the moment of a block's slip and the run's length.
    """
    data = parse_toml(text_or_document, source) if isinstance(text_or_document, str) else text_or_document
    check_toml_layout(data, {"chain": _CHAIN, "friction": _FRICTION, "moment": _MOMENT, "run": _RUN,
                             "sources": None}, source, "a spring-block chain scene")
    if data.get("family") != "spring_chain":
        raise InputError(f"{source} is not a spring-block chain scene: it needs family = \"spring_chain\"")
    chain = data.get("chain")
    if not isinstance(chain, dict):
        raise InputError(f"{source} needs a [chain] table (blocks, leaf_stiffness, normal_load, platform_speed, ...)")
    blocks = _number(chain, "blocks", None, source, 1, MAX_BLOCKS, whole=True)
    for key in ("leaf_stiffness", "normal_load", "platform_speed"):
        if key not in chain:
            raise InputError(f"[chain] in {source} needs {key}")
    leaf = to_si(chain["leaf_stiffness"], "stiffness", f"[chain] leaf_stiffness in {source}")
    load = to_si(chain["normal_load"], "force", f"[chain] normal_load in {source}")
    speed = to_si(chain["platform_speed"], "speed", f"[chain] platform_speed in {source}")
    coupling = to_si(chain.get("coupling_stiffness", "0 N/m"), "stiffness", f"[chain] coupling_stiffness in {source}")
    # the physical ranges every input passes (faultslip.ranges), so that no value overflows the event loop
    for label, rule, value in (("leaf_stiffness", "stiffness", leaf), ("normal_load", "normal_load", load),
                               ("platform_speed", "platform_speed", speed)):
        ranges.check(rule, value, f"[chain] {label} in {source}")
    if coupling < 0:
        raise InputError(f"[chain] coupling_stiffness in {source} must be zero or positive, got {coupling:g}")
    if coupling > 0:
        ranges.check("stiffness", coupling, f"[chain] coupling_stiffness in {source}")
    mass = (to_si(chain["mass"], "mass", f"[chain] mass in {source}") if "mass" in chain else load / STANDARD_GRAVITY)
    ranges.check("mass", mass, f"[chain] mass in {source}")
    zeta = _number(chain, "damping_ratio", 0.0, source, 0.0, 0.99)
    spread = _number(chain, "threshold_spread", 0.0, source, 0.0, 0.99)
    offset = to_si(chain.get("initial_offset", "0 m"), "length", f"[chain] initial_offset in {source}")
    ranges.check("initial_offset", offset, f"[chain] initial_offset in {source}")
    seed = _number(chain, "seed", 0, source, 0, 2 ** 32 - 1, whole=True)
    loading_rate = leaf * speed / load
    static, kinetic, friction = _friction(data.get("friction", {}), loading_rate, source)
    rng = np.random.default_rng(seed)
    thresholds = kinetic + (static - kinetic) * (1 + spread * rng.uniform(-1.0, 1.0, blocks))
    start = rng.uniform(0.0, offset, blocks) if offset > 0 else np.zeros(blocks)
    moment = data.get("moment", {})
    shear = to_si(moment.get("shear_modulus", "30 GPa"), "pressure", f"[moment] shear_modulus in {source}")
    area = to_si(moment.get("patch_area", "1 km^2"), "area", f"[moment] patch_area in {source}")
    if not (shear > 0 and area > 0):
        raise InputError(f"[moment] shear_modulus and patch_area in {source} must be positive")
    run = data.get("run", {})
    events = _number(run, "events", 1000, source, 1, MAX_EVENTS, whole=True)
    system_size = _number(run, "system_size", 0.5, source, 1e-9, 1.0)
    name = data.get("name", Path(source).stem)
    built = Chain(mass, leaf, coupling, load, speed, thresholds, kinetic, 2 * zeta * math.sqrt(leaf * mass),
                  name=str(name))
    return ChainScene(str(name), built, start, shear, area, events, system_size, friction, loading_rate)


def _friction(table: dict, loading_rate: float, source: str) -> tuple[float, float, str]:
    """(mu_s, mu_k, where they came from): a seed-law preset at the block's loading rate, or constants."""
    if "preset" in table:
        if set(table) - {"preset"}:
            raise InputError(f"[friction] in {source}: give a preset or static and kinetic, not both")
        preset = get_preset(str(table["preset"]))
        law = preset.require_stick_slip()
        static = float(law.static(loading_rate))
        return static, float(law.mu_m), (f"seed 003's rate law for {preset.name}: mu_s = {static:.6g} at the "
                                         f"block's loading rate {loading_rate:.4g} 1/s, mu_k = mu_m = {law.mu_m:g}")
    static, kinetic = table.get("static", 0.6), table.get("kinetic", 0.4)
    for label, value in (("static", static), ("kinetic", kinetic)):
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not (math.isfinite(value) and value >= 0):
            raise InputError(f"[friction] {label} in {source} must be a friction coefficient, got {value!r}")
    if not static > kinetic:
        raise InputError(f"[friction] static ({static:g}) must exceed kinetic ({kinetic:g}) in {source}: without a "
                         "drop there is no stick-slip")
    return float(static), float(kinetic), f"constant: mu_s = {static:g}, mu_k = {kinetic:g}"


def read_chain_scene(scene) -> ChainScene:
    """A chain scene from a file, a bundled scene's name or a study's cell.

    Parameters
    ----------
    scene : str, path, TomlScene or ChainScene
        The scene.

    Returns
    -------
    ChainScene
        The scene read (:func:`parse_chain_scene`).
    """
    if isinstance(scene, ChainScene):
        return scene
    text, source, _, _ = scene_source(scene, "spring-block chain scene")
    return parse_chain_scene(text, source)
