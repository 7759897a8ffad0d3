"""A fault simulation's events as an earthquake catalog: origin times, locations and Mw from M0."""

from __future__ import annotations

import numpy as np

from faultslip.errors import InputError
from faultslip.fault.scaling import moment_magnitude, seismic_moment
from faultslip.io.waveforms import DEFAULT_START


def simulated_events(dataset, fault, trace=None, start_seconds: float = DEFAULT_START) -> dict:
    """Event origin times (s since 1970: ``start_seconds`` plus the model time of each event), the trace's
    middle vertex as epicentre (0 N 0 E without a trace, said in ``note``), half the seismogenic depth, and
    Mw = (2/3)(log10 M0 - 9.1) with M0 = G L H slip (Aki 1966)."""
    if fault.rupture_length is None or fault.seismogenic_depth is None:
        raise InputError("events need a moment: the scene's [fault] must give rupture_length and seismogenic_depth")
    slips = dataset["slip"].values
    times = start_seconds + dataset["event_time"].values
    moments = seismic_moment(fault.shear_modulus, fault.rupture_length, fault.seismogenic_depth, slips)
    note = ""
    if trace is not None:
        lon, lat = (float(v) for v in trace[len(trace) // 2])
    else:
        lon, lat, note = 0.0, 0.0, "no [fault] trace: the events are placed at 0 N 0 E"
    count = slips.size
    return {"times": times, "latitude": np.full(count, lat), "longitude": np.full(count, lon),
            "depth": np.full(count, 0.5 * fault.seismogenic_depth), "magnitude": np.asarray(moment_magnitude(moments)),
            "names": [f"{fault.name}: simulated event {i + 1}" for i in range(count)], "note": note}
