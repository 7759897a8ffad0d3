"""Regenerate seed 000's sliding-model trends (docs/surfaces.md): chapter 5's runs, in which the surfaces
stay apart through the deceleration, as the seed ran them and with the addendum's corrections.

    python benchmarks/surface_trends.py          # ~1 min on 2 cores

Writes benchmarks/results/surface_trends.json (benchmarks/readme.py renders its tables into docs/surfaces.md)
and docs/figures/surface_chapter5.png.
"""

from __future__ import annotations

import math
import os
import warnings
from pathlib import Path

import numpy as np

os.environ.setdefault("MPLBACKEND", "Agg")
from faultslip.dynamics.spring_slider.simulate import simulate  # noqa: E402
from faultslip.friction.laws import STANDARD_GRAVITY  # noqa: E402
from faultslip.io.atomic import save_figure  # noqa: E402
from faultslip.models.rough_surface.scene import rough_surface_slider, separation_history, separation_sweep  # noqa: E402
from faultslip.lab.surfaces import gaussian_surface  # noqa: E402
from faultslip.plots.surfaces import separation_figure  # noqa: E402
from provenance import write_results  # noqa: E402  (one stamp for every results file)

ROOT = Path(__file__).resolve().parents[1]
#: The scenes' stand-in surface (configs/rough_surface_*.toml): RMS and correlation length (m), grid, seed.
SURFACE_SPEC = {"rms": 3.26e-6, "correlation_length": 60e-6, "size": 128, "seed": 2026}
SURFACE = gaussian_surface(SURFACE_SPEC["rms"], SURFACE_SPEC["correlation_length"], size=SURFACE_SPEC["size"],
                           seed=SURFACE_SPEC["seed"])
CHAPTER5_C = [0.001, 0.005, 0.01, 0.02, 0.04]  # s/mm, figs. 5.10-5.14 (fig. 5.9 is c = 0)
# Table 5.1 as the seed ran it: p_c 280 N/mm^2 (should be 208 kgf/mm^2, AD1.1 item 1) and forces in N read as
# accelerations in mm/s^2 (AD1.1 item 2), which is a slider 1000 times heavier.
AS_RUN = dict(mass=600.0, stiffness=12.66e3, normal_load=30.0, platform_speed=0.2e-3, hardness=2.8e8,
              shear_strength=8.25e7)
# The same with the addendum's corrections; p_s keeps p_s / p_c (82.5 / 280 x 2040 N/mm^2 = 601 N/mm^2,
# the addendum's own 6.0e8 Pa).
CORRECTED = dict(AS_RUN, mass=0.6, hardness=2.04e9, shear_strength=6.0e8)
# Seed 000 §4.5: the surfaces need >= 20 ms to squeeze out the air film over ~0.5 um: a = 2 h / t^2.
SQUEEZE_FALL = 2 * 0.5e-6 / 0.020 ** 2


def _system(setting, c, memory="held", reference="static_compression", fall=STANDARD_GRAVITY, **changes):
    values = dict(setting, **changes)
    return rough_surface_slider(SURFACE, values["mass"], values["stiffness"], values["normal_load"],
                                values["platform_speed"], values["hardness"], values["shear_strength"], c,
                                memory=memory, fall_acceleration=fall, separation_reference=reference)


def _run(system, cycles=6):
    record = simulate(system, cycles=cycles, slip_solver="DOP853", rtol=1e-8)
    last = record.isel(event=-1)
    breakaway = system.normal_load * system.static_law.mu_s / system.stiffness
    return record, {"amplitude_mm": float(last["amplitude"]) * 1e3,
                    "relative": float(last["amplitude"]) / breakaway,
                    "lowest_mm": float(record["displacement"].where(record["time"] >= float(last["event_time"])).min()) * 1e3,
                    "slip_s": float(last["slip_duration"]), "stick_s": float(last["stick_duration"]),
                    "peak_mm_s": float(last["peak_slip_speed"]) * 1e3}


def _sweep_rows(sweep) -> dict:
    """A chapter 5 sweep as lists: per separation coefficient (s/mm), per memory, the amplitude over the
    break-away stretch and the lowest displacement (m)."""
    return {"separation_coefficient": [float(c) * 1e-3 for c in sweep["separation_coefficient"].values],
            "memory": [str(m) for m in sweep["memory"].values],
            "relative_amplitude": [[float(sweep.sel(memory=m).isel(separation_coefficient=j)["relative_amplitude"])
                                    for m in sweep["memory"].values] for j in range(sweep.sizes["separation_coefficient"])],
            "lowest_displacement": [[float(sweep.sel(memory=m).isel(separation_coefficient=j)["lowest_displacement"])
                                     for m in sweep["memory"].values]
                                    for j in range(sweep.sizes["separation_coefficient"])]}


def main() -> None:
    warnings.simplefilter("ignore")
    memories = ("none", "held", "falling")
    sweeps = {}
    for label, setting in (("as run", AS_RUN), ("corrected", CORRECTED)):
        sweeps[label] = separation_sweep(SURFACE, **setting, coefficients=np.array(CHAPTER5_C) * 1e3,
                                         memories=memories, separation_reference="static_compression")
    rows = [("fig. 5.13: c 0.02, V0 0.2 mm/s, k 12.66 N/mm, L 30 N", {}, 0.02),
            ("fig. 5.15: V0 0.05 mm/s, c 0.01", {"platform_speed": 0.05e-3}, 0.01),
            ("fig. 5.16: V0 0.1 mm/s, c 0.01", {"platform_speed": 0.1e-3}, 0.01),
            ("fig. 5.12: V0 0.2 mm/s, c 0.01", {}, 0.01),
            ("fig. 5.17: V0 0.5 mm/s, c 0.01", {"platform_speed": 0.5e-3}, 0.01),
            ("fig. 5.21: k 6.3 N/mm, c 0.02", {"stiffness": 6.3e3}, 0.02),
            ("fig. 5.22: k 6.3 N/mm, c 0.03", {"stiffness": 6.3e3}, 0.03),
            ("fig. 5.24: L 60 N, c 0.02", {"normal_load": 60.0}, 0.02)]
    chapter5_runs = []
    for label, changes, c in rows:
        system, _ = _system(AS_RUN, c * 1e3, **changes)
        chapter5_runs.append({"run": label, **_run(system)[1]})
    records = {}
    for c in (0.005, 0.01, 0.02, 0.04):
        system, _ = _system(AS_RUN, c * 1e3)
        record, _ = _run(system, cycles=3)
        records[f"c = {c:g} s/mm"] = (record, separation_history(record, system.kinetic_law))
    ad3 = dict(CORRECTED, platform_speed=0.01)
    ad3_runs = []
    for label, memory, fall in (("none (AD1.3)", "none", STANDARD_GRAVITY), ("held (chapter 5)", "held", STANDARD_GRAVITY),
                                ("falling, gravity", "falling", STANDARD_GRAVITY),
                                (f"falling, squeeze film ({SQUEEZE_FALL:.3g} m/s²)", "falling", SQUEEZE_FALL),
                                ("falling, 3e-4 m/s²", "falling", 3e-4)):
        system, _ = _system(ad3, 0.8, memory=memory, reference="rms", fall=fall)
        record, row = _run(system)
        records[label] = (record.where(record["time"] <= 0.25, drop=True),
                          separation_history(record, system.kinetic_law)[record["time"].values <= 0.25])
        ad3_runs.append({"memory": label, **row})
    system, details = _system(ad3, 0.8, reference="rms")
    _, row = _run(system)
    write_results("surface_trends.json", {
        "surface": SURFACE_SPEC,
        "gravity_fall_time": math.sqrt(2 * 0.5e-6 / STANDARD_GRAVITY),
        "sweeps": {label: _sweep_rows(sweep) for label, sweep in sweeps.items()},
        "chapter5_runs": chapter5_runs, "ad3_runs": ad3_runs,
        "peak_separation": details["separation_per_speed"] * row["peak_mm_s"] * 1e-3,
        "slip_angular_frequency": math.pi / row["slip_s"]})
    save_figure(separation_figure(records, sweeps), ROOT / "docs" / "figures" / "surface_chapter5.png", dpi=110)


if __name__ == "__main__":
    main()
