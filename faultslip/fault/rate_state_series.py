"""A one-block rate-and-state fault's recorded cycles as a CF dataset: what ``simulate`` writes to netCDF."""

from __future__ import annotations

from faultslip.errors import InputError


def cycles_series(cycles, law, title: str):
    """Cycles recorded by :func:`~faultslip.dynamics.rate_state.slider.fault_cycles` (``record=True``) as a CF
    dataset: the time series on ``time`` (the solver's steps, dense in the events) and the events on ``event``.
    ``law`` is the friction law (its description goes into the attributes)."""
    import xarray as xr  # heavy: imported where used

    if cycles is None or cycles.series is None:
        raise InputError("no cycles to write: the fault slides stably (K >= K_c) or was run without recording")
    series = cycles.series
    time = {"units": "s", "long_name": "time since the start of the run (spin-up included)"}
    return xr.Dataset(
        {"slip_rate": ("time", series["slip_rate"], {"units": "m/s", "long_name": "slip rate V"}),
         "log_state": ("time", series["psi"], {"units": "1", "long_name": "psi = ln(V0 theta / D_c)"}),
         "slip": ("time", series["slip"], {"units": "m", "long_name": "slip since the start of the run"}),
         "shear_stress": ("time", series["shear_stress"],
                          {"units": "Pa", "long_name": "elastic shear stress sigma_n mu + eta V"}),
         "event_time": ("event", cycles.event_times, {**time, "long_name": "event start (slip rate above 1 mm/s)"}),
         "slip_per_event": ("event", cycles.slip_per_event, {"units": "m", "long_name": "slip while V > 1 mm/s"}),
         "stress_drop": ("event", cycles.stress_drop, {"units": "Pa", "long_name": "stress drop of the event"}),
         "peak_slip_rate": ("event", cycles.peak_slip_rate, {"units": "m/s", "long_name": "peak slip rate"})},
        coords={"time": ("time", series["time"], time)},
        attrs={"title": title, "Conventions": "CF-1.8", "model": cycles.model, "method": cycles.method,
               "law": law.describe(), "stiffness_ratio": cycles.stiffness_ratio,
               "plate_rate_m_per_s": cycles.plate_rate, "scale": "fault",
               "comment": "quasi-dynamic spring-slider fault (seed 003 §5-2 scaling) with rate-and-state friction; "
                          "samples are the integrator's accepted steps"})
