"""Write the synthetic example inputs in configs/ (run from the repository root).

Every number comes from the model, never from a measurement: the friction data follow the wet
granodiorite preset (seed 003 Table I row 11) with 1 % noise; the motion records are exact
solutions of the glass (dry) slider (seed 003 Table I row 4). They exist so that every command
that takes a file has a working example (`faultslip fit`, also `fit --law rate-state` with the
velocity-step record, `record`, `decay`, and `convert`, whose
example is the Zarr store of study_lab_glass.toml); they are labelled synthetic in
configs/README.md.
"""

from pathlib import Path

import numpy as np

from faultslip.friction.materials import get_preset
from faultslip.lab.records import synthetic_record
from faultslip.dynamics.spring_slider.slider import SliderSystem

HERE = Path(__file__).resolve().parent


def friction_data(path: Path) -> None:
    law = get_preset("granodiorite_water").rate_law
    rng = np.random.default_rng(2026)
    rates = np.geomspace(1e-4, 1e2, 24)
    friction = law.static(rates) * (1 + 0.01 * rng.standard_normal(rates.size))
    lines = ["loading_rate (1/s),static_friction"] + [f"{r:.6g},{m:.6f}" for r, m in zip(rates, friction)]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def motion_record(path: Path) -> None:
    system = SliderSystem.from_preset("glass_dry", loading_rate="0.5 1/s")
    record = synthetic_record(system, 4, 4000.0)
    lines = ["time (s),displacement (m),acceleration (m/s^2)"]
    lines += [f"{t:.9g},{x:.9g},{a:.9g}" for t, x, a in zip(record.time, record.displacement, record.acceleration)]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def decay_record(path: Path) -> None:
    mass, stiffness, zeta = 0.8, 12346.0, 0.01  # seed 002 Appendix C's apparatus, about 19.9 Hz
    omega_n = np.sqrt(stiffness / mass)
    t = np.arange(0.0, 1.0, 2.5e-4)
    x = 1e-3 * np.exp(-zeta * omega_n * t) * np.cos(omega_n * np.sqrt(1 - zeta**2) * t)
    lines = ["time (s),displacement (m)"] + [f"{a:.9g},{b:.9g}" for a, b in zip(t, x)]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def velocity_steps(path: Path) -> None:
    """A synthetic velocity-step record (1 -> 10 -> 1 µm/s) of a known law, with 2e-4 noise in friction."""
    from faultslip.dynamics.rate_state.slider import LoadHistory
    from faultslip.friction.rate_state import RateStateLaw
    from faultslip.lab.rate_state_fit import synthetic_step_record

    law = RateStateLaw(a=0.006, b=0.009, critical_slip=15e-6, mu0=0.6, reference_speed=1e-6)
    history = LoadHistory.velocity_steps([(0.0, 1e-6), (10.0, 10e-6), (20.0, 1e-6)], 40.0)
    record = synthetic_step_record(law, 1e4, history, 801, noise=2e-4, seed=2026)
    speed = [history.speeds[0] if t < 10 else history.speeds[1] if t < 20 else history.speeds[2] for t in record.time]
    lines = ["time (s),friction,load_point_speed (um/s)"]
    lines += [f"{t:.6g},{m:.7f},{v * 1e6:g}" for t, m, v in zip(record.time, record.friction, speed)]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def raw_velocity_steps(path: Path) -> None:
    """A synthetic raw rig record: five velocity steps and a 60 s hold of a known law (aging, a 0.008,
    b 0.012, D_c 20 µm, mu0 0.62), written as a rig would: time (s), load-point displacement (µm), shear
    and normal load (kN) on a 5 x 5 cm sample at 10 MPa, machine stiffness 2e8 N/m (200 kN/mm), 10 Hz,
    noise on the loads and the LVDT, and a slip-weakening drift of -0.003 per mm."""
    from faultslip.dynamics.rate_state.slider import LoadHistory
    from faultslip.friction.rate_state import RateStateLaw
    from faultslip.lab.raw_records import synthetic_raw_record

    law = RateStateLaw(a=0.008, b=0.012, critical_slip=20e-6, mu0=0.62, reference_speed=1e-6)
    history = LoadHistory((0.0, 100.0, 130.0, 230.0, 245.0, 300.0, 360.0, 420.0),
                          (1e-6, 10e-6, 1e-6, 30e-6, 3e-6, 0.0, 3e-6))
    raw = synthetic_raw_record(law, 2e8, 0.0025, 25e3, history, rate=10.0, drift=-3.0, seed=2026)
    lines = ["# synthetic raw record written by configs/make_examples.py (faultslip): not a measurement",
             "# law: aging, a 0.008, b 0.012, D_c 20 um, mu0 0.62 at 1 um/s; machine 2e8 N/m; area 25 cm^2",
             "time(s) load_point_displacement(um) shear_load(kN) normal_load(kN)"]
    lines += [f"{t:.2f} {d * 1e6:.4f} {s * 0.0025 / 1e3:.5f} {n * 0.0025 / 1e3:.4f}"
              for t, d, s, n in zip(raw.time, raw.load_point_displacement, raw.shear_stress, raw.normal_stress)]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def study_store(path: Path) -> None:
    """study_lab_glass.toml swept into a Zarr store (needs zarr: pip install 'faultslip[zarr]')."""
    from faultslip.studies.grid import load_study
    from faultslip.studies.streaming import run_study

    run_study(load_study(HERE / "study_lab_glass.toml"), path, workers=1, overwrite=True)


if __name__ == "__main__":
    friction_data(HERE / "example_friction_data.csv")
    motion_record(HERE / "example_record.csv")
    decay_record(HERE / "example_decay_record.csv")
    velocity_steps(HERE / "example_velocity_steps.csv")
    raw_velocity_steps(HERE / "example_raw_velocity_steps.txt")
    study_store(HERE / "example_lab_glass.zarr")
