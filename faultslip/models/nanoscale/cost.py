"""The nanoscale family's cost model: what an LSODA run over a nanoscale time needs, before it runs."""

from __future__ import annotations


from faultslip.io.budget import Estimate


#: Seconds of LSODA per unit of nanoscale time (1/omega), measured on seed 001's scene (2 cores, 2026-11-24:
#: 30,000 units in 9 s); taken 2x for a slower machine.
NANOSCALE_SECONDS_PER_UNIT = 6e-4


def nanoscale_estimate(duration: float, samples: int) -> Estimate:
    """Time and memory of a nanoscale run over ``duration`` (in 1/omega) kept at ``samples`` points."""
    return Estimate(what=f"a nanoscale run over {duration:.3g}/omega", seconds=duration * NANOSCALE_SECONDS_PER_UNIT,
                    memory=float(samples) * 6 * 8.0 * 3)
