"""The nanoscale family's cost model: LSODA's CPU time per unit of nanoscale time (1/omega), fitted on seed 001's
scene by ``benchmarks/family_costs.py`` (``data/family_costs.json``), and the closed form's overhead."""

from __future__ import annotations

from faultslip.io import budget
from faultslip.io.budget import Estimate

#: The model time (1/omega) :meth:`~faultslip.models.nanoscale.dynamics.NanoscaleModel.settled_cycle` integrates
#: at a time, and at most: a cycle that settles is found within the chunk it settles in, so the run's cost counts
#: whole chunks (:func:`settle_work`).
SETTLE_CHUNK, SETTLE_MAX_TIME = 400.0, 2e5


def nanoscale_estimate(duration: float, samples: int) -> Estimate:
    """Time and memory of a nanoscale run over ``duration`` (in 1/omega) kept at ``samples`` points."""
    return budget.fitted_estimate("nanoscale", "lsoda", duration, f"a nanoscale run over {duration:.3g}/omega",
                                  memory=float(samples) * 6 * 8.0 * 3,
                                  imports=(*budget.DATASET_IMPORTS, *budget.INTEGRATION_IMPORTS))


def settle_work(model, approach: float) -> float:
    """The drive's displacement over the model time a settled cycle integrates: the unit of the ``run:settle``
    cost entry, v_a T with T = SETTLE_CHUNK (1 + k / (1 - A / A_c)), at most SETTLE_MAX_TIME.

    LSODA's steps follow the stick-slip cycles it integrates, and a cycle loads the spring by about one force
    swing, so the cycles in a chunk grow with the drive's displacement over it. Away from A_c the cycle settles
    within the first chunk; near it the approach slows as 1 / (A_c - A) (seed 001's Hopf point) and
    Steffensen's restarts take more chunks: ``approach`` is k, fitted on near-critical scenes with the cost
    (``benchmarks/family_costs.py``)."""
    # above a subcritical A_c a run from rest settles on the large cycle, or decays, as far from A_c
    distance = max(abs(1.0 - model.damping / model.critical_damping), 1e-12)
    return model.drive_speed * min(SETTLE_CHUNK * (1.0 + approach / distance), SETTLE_MAX_TIME)


def settle_estimate(model) -> Estimate:
    """Time and memory of a run's settled cycle (:meth:`NanoscaleModel.settled_cycle`): the fitted ``run:settle``
    entry over :func:`settle_work`. The run itself checks its worst case (SETTLE_MAX_TIME) against the budget
    before it starts."""
    entry = budget.family_costs()["families"]["nanoscale"]["run:settle"]
    return budget.fitted_estimate("nanoscale", "run:settle", settle_work(model, entry["approach"]),
                                  "a nanoscale run settling its cycle (LSODA, chunks of 400/omega)",
                                  memory=2 * 6 * 8.0 * 3, imports=budget.INTEGRATION_IMPORTS)
