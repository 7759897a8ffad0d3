"""The spring-block chain's cost model: CPU time in block-events (events x blocks: each event's sub-phases touch
the blocks that slip, and the loading between events every block), fitted by ``benchmarks/family_costs.py``."""

from __future__ import annotations

from faultslip.io import budget
from faultslip.models.spring_chain.scene import read_chain_scene


def work(scene, action: str = "run", cycles=None, slip_solver=None, **_) -> tuple[str, float, str]:
    """(cost entry, units, what): the scene's events (``cycles`` of them for a simulation) times its blocks; a
    scipy integrator as the slip solver is its own entry."""
    loaded = read_chain_scene(scene)
    events = float(loaded.events if cycles is None or action == "run" else cycles)
    integrated = slip_solver not in (None, "auto", "analytic", "closed_form", "closed_form_compiled")
    entry = f"{action}:integrated" if integrated else action
    return entry, events * loaded.chain.blocks, f"{events:g} events of {loaded.chain.blocks} blocks"


def estimate(scene, action: str = "run", **options) -> budget.Estimate:
    """What a run or simulation of a chain scene needs, before it starts."""
    entry, units, what = work(scene, action, **options)
    return budget.fitted_estimate("spring_chain", entry, units, what, memory=units * 8.0 * 4,
                                  output=options.get("output"))
