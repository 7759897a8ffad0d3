"""The spring slider's cost model: what a simulation of N cycles needs, before it runs (the family declares it)."""

from __future__ import annotations


from faultslip.io.budget import Estimate


def simulation_estimate(cycles: int, samples_per_slip: int, integrated: bool, output=None) -> Estimate:
    """Memory and time of ``simulate``: the time series holds about (samples + 2) rows per cycle."""
    rows = float(cycles) * (samples_per_slip + 2)
    memory = rows * 6 * 8.0 * 3  # six columns, about three copies while the dataset is built
    seconds = float(cycles) * (2.5e-3 if integrated else 2e-6) + rows * 1e-8
    return Estimate(what=f"a simulation of {cycles:.3g} cycles", memory=memory, disk=rows * 6 * 8.0 if output else 0.0,
                    seconds=seconds, output=output)
