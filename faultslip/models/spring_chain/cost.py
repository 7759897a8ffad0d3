"""The spring-block chain's cost model, fitted by ``benchmarks/family_costs.py``.

The closed form's unit of work is the block-event (events x blocks: each event's sub-phases touch the blocks that
slip, and the loading between events every block). A scipy integrator's is the slip sub-phase: each is one
``solve_ivp`` call, and how many an event takes depends on how many blocks it sweeps, a mix no count of events
and blocks foretells (a 50-block chain's events take half the sub-phases per block-event a 12-block chain's do).
Each integrator is its own entry (``simulate:RK45``, ...): a sub-phase costs twenty times more by RK23 than by
DOP853.
The exact compiled closed form follows the same sub-phases at a hundredth of the cost, so the estimate counts
them on it, over at most :data:`COUNTED_EVENTS` events, and scales to the run's. The closed form in Python (asked
for, or what ``auto`` runs where the compiled loop was not built) is its own entry (``run:closed_form``,
``simulate:closed_form``): a block-event costs it about 160 times the compiled loop's.
"""

from __future__ import annotations

from faultslip.errors import InputError, SolverError
from faultslip.io import budget
from faultslip.models.spring_chain.dynamics import chosen_solver, compiled_available, simulate_chain
from faultslip.models.spring_chain.scene import read_chain_scene

#: At most this many events are counted by the closed form for an integrated run's estimate (about 0.1 s at 50
#: blocks); a longer run's sub-phases are scaled from them.
COUNTED_EVENTS = 500


def subphases(loaded, events: int) -> tuple[float, str]:
    """(sub-phases, how counted): an integrated run's slip sub-phases over ``events`` events, counted by the exact
    compiled closed form over its first min(events, :data:`COUNTED_EVENTS`) and scaled; without the compiled
    closed form (or where it stops), one a block-event, said."""
    counted = min(int(events), COUNTED_EVENTS)
    uncounted = float(events * loaded.chain.blocks)
    if not compiled_available():
        return uncounted, "uncounted: one a block-event (the compiled closed form is not built)"
    try:
        run = simulate_chain(loaded.chain, counted, initial_position=loaded.initial_position,
                             slip_solver="closed_form_compiled")
    except (InputError, SolverError) as error:  # the run itself will stop there too, and say so
        return uncounted, f"uncounted: one a block-event (the closed form stopped: {error})"
    return run.subphases * events / counted, f"counted by the closed form over {counted} events"


#: What a chain's run imports beside its Dataset: the statistics of its catalogue (scipy.stats brings the
#: integrators and root finders with it).
IMPORTS = ("scipy.stats", "scipy.interpolate", "scipy.ndimage")


def _work(loaded, action: str, cycles, slip_solver) -> tuple[str, float, str, float]:
    events = float(loaded.events if cycles is None or action == "run" else cycles)
    integrated = slip_solver not in (None, "auto", "analytic", "closed_form", "closed_form_compiled")
    blocks = loaded.chain.blocks
    if integrated:
        count, how = subphases(loaded, int(events))
        return (f"{action}:{slip_solver}", count,
                f"{count:.0f} slip sub-phases in {events:g} events of {blocks} blocks ({how})", events * blocks)
    if chosen_solver("auto" if slip_solver in (None, "analytic") else slip_solver) == "closed_form":
        why = "" if slip_solver == "closed_form" else ": the compiled loop is not built"
        return (f"{action}:closed_form", events * blocks,
                f"{events:g} events of {blocks} blocks (the closed form in Python{why})", events * blocks)
    return action, events * blocks, f"{events:g} events of {blocks} blocks", events * blocks


def work(scene, action: str = "run", cycles=None, slip_solver=None, **_) -> tuple[str, float, str]:
    """(cost entry, units, what): the closed form's block-events (``cycles`` events for a simulation, times the
    blocks); each scipy integrator as the slip solver is its own entry, in slip sub-phases (:func:`subphases`)."""
    entry, units, what, _ = _work(read_chain_scene(scene), action, cycles, slip_solver)
    return entry, units, what


def estimate(scene, action: str = "run", cycles=None, slip_solver=None, **options) -> budget.Estimate:
    """What a run or simulation of a chain scene needs, before it starts: its time by :func:`work`, and its
    catalogue's slip (events x blocks) and the arrays beside it in memory."""
    entry, units, what, block_events = _work(read_chain_scene(scene), action, cycles, slip_solver)
    # its catalogue's Dataset, and the statistics of its events (their sizes' distribution, fitted)
    return budget.fitted_estimate("spring_chain", entry, units, what, memory=block_events * 8.0 * 4,
                                  output=options.get("output"), imports=(*budget.DATASET_IMPORTS, *IMPORTS))
