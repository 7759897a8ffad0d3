"""Where seed 004's integrators work: platform speed against slope spread, per method.

Each cell runs the asperity slider (Table I case 3, C = 200 kg/s unless another model is given) for a
short time with each method and records the outcome: ``stick_slip`` or ``sliding`` when it finishes,
``contact_lost`` when the six-state integration finds F_n(t) reaching zero (the paper's "computations
become unstable"), ``declined`` when the quasi-static method refuses a speed above its contact-loss
estimate, ``solver_failure`` or ``budget_exceeded`` otherwise. Failed cells carry no numbers.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from faultslip.models.asperity.dynamics import AsperityModel, analyse, simulate
from faultslip.errors import InputError

OUTCOMES = ("stick_slip", "sliding", "contact_lost", "declined", "solver_failure", "budget_exceeded")
METHODS = ("asperity_quasistatic", "asperity_LSODA")


def asperity_map(speeds, slope_stds, model: AsperityModel | None = None, methods=METHODS, duration: float = 0.3,
                 max_seconds: float = 30.0):
    """An xarray Dataset of outcome codes (index into :data:`OUTCOMES`), stick fraction and computing time,
    over (method, slope_std, platform_speed)."""
    import xarray as xr  # heavy: imported where used

    speeds, slope_stds = np.asarray(speeds, float), np.asarray(slope_stds, float)
    unknown = [m for m in methods if m not in METHODS]
    if unknown:
        raise InputError(f"asperity map methods must be among {', '.join(METHODS)}, got {unknown[0]!r}")
    base = model or AsperityModel.table_case(3, dashpot=200.0)
    shape = (len(methods), slope_stds.size, speeds.size)
    outcome, stick, elapsed = np.zeros(shape, "i1"), np.full(shape, np.nan), np.zeros(shape)
    for i, method in enumerate(methods):
        for j, spread in enumerate(slope_stds):
            for k, speed in enumerate(speeds):
                run = simulate(replace(base, slope_std=float(spread), platform_speed=float(speed)), duration, method,
                               rtol=1e-7, max_seconds=max_seconds)
                elapsed[i, j, k] = run.elapsed
                if run.status == "ok":
                    response = analyse(run)
                    stick[i, j, k] = response.stick_fraction
                    outcome[i, j, k] = OUTCOMES.index("stick_slip" if response.stick_slip else "sliding")
                else:
                    outcome[i, j, k] = OUTCOMES.index(run.status)
    dims = ("method", "slope_std", "platform_speed")
    return xr.Dataset(
        {"outcome": (dims, outcome, {"flag_values": list(range(len(OUTCOMES))), "flag_meanings": " ".join(OUTCOMES)}),
         "stick_fraction": (dims, stick, {"units": "1"}), "elapsed": (dims, elapsed, {"units": "s"})},
        coords={"method": list(methods), "slope_std": ("slope_std", slope_stds, {"units": "rad"}),
                "platform_speed": ("platform_speed", speeds, {"units": "m/s"})},
        attrs={"title": f"seed 004 integrators: where they work ({base.name})", "Conventions": "CF-1.8",
               "duration_s": duration})
