"""Is a fault's cycle its own, whatever its start? Runs of one scene from several starts, compared.

A fault model's answer is the cycle its start settles to. Most faults settle to one cycle from any start; some
are multistable and settle elsewhere (``benchmarks/ladder_regimes.py --part start``: 2 of 31 settled held-out 2-D
faults; the 3-D cells: ``benchmarks/fault_3d_model_error.py --starts``), which no declared error covers. ``faultslip run SCENE --check-starts`` runs a cycle model's scene again
from :data:`START_FACTORS` times its start's slip rate; :func:`compare_starts` says what the runs show, on the
scene's own run's :class:`~faultslip.contract.result.Result`.
"""

from __future__ import annotations

from faultslip.constants import JULIAN_YEAR as YEAR
from faultslip.contract.result import Result
from faultslip.io import budget

#: The other starts: the scene's start's slip rate times these
START_FACTORS = (0.1, 10.0)
#: Two runs of one scene from different starts reach the same cycle where their recurrences differ by no more than
#: this (the settling tolerance the held-out runs were classified at), or than their sequences' own errors together
SAME_CYCLE = 0.01


def same_cycle(recurrence: float, sequence_error, settled: bool, other: float, other_error,
               other_settled: bool) -> bool | None:
    """Whether two runs of a scene from different starts reached the same cycle: yes where their recurrences lie
    within :data:`SAME_CYCLE`, or, both settled, within their two sequence errors together; no where they differ by
    more and both settled to a period; None where they differ and either did not settle (its mean may still be
    moving, and an unsettled run's error is its intervals' spread, wide enough to hold two cycles: run longer)."""
    change = abs(other / recurrence - 1)
    if change <= SAME_CYCLE:
        return True
    if not (settled and other_settled):
        return None
    if sequence_error is not None and other_error is not None and change <= sequence_error + other_error:
        return True
    return False


def other_starts(scene) -> tuple[float, list]:
    """(the scene's start's slip rate in m/s, the scene from each of :data:`START_FACTORS` times it): a 2-D or 3-D
    fault scene, through its ``from_start``."""
    speed = float(scene.settings["initial_speed"])
    return speed, [scene.from_start(factor * speed) for factor in START_FACTORS]


def starts_estimate(scene, others: list, rtol=None, output=None) -> budget.Estimate:
    """What the scene's run and its runs from ``others`` (:func:`other_starts`) need, one after another, in this
    process (the first owes what the process has not loaded or compiled yet)."""
    return budget.one_after_another(f"{len(others) + 1} runs of {scene.name} (its start and {len(others)} others)",
                                    [scene.estimate(rtol, output, in_this_process=True),
                                     *(each.estimate(rtol, output) for each in others)])


def start_note(speed: float, patch: bool = False) -> str:
    """What every cycle model's answer is: its start's cycle (the sentence its report carries); ``patch``: a
    nucleation patch starts faster than the rest (SEAS BP5)."""
    where = "every element off the nucleation patch" if patch else "every element"
    return (f"the answer is the cycle this scene's start settles to ({where} in steady state at {speed:.3g} m/s, "
            "[initial] initial_speed); a fault can settle to another cycle from another start, which the declared "
            "error does not cover (docs/ladder.md; --check-starts runs it from others)")


def _recurrence(result: Result) -> float:
    return float(result.values["recurrence_interval"].to("s").magnitude)


def _error(result: Result):
    value = result.values["sequence_error"] if "sequence_error" in result else None
    return None if value is None else float(value)


def compare_starts(result: Result, others: list[Result], speed: float) -> Result:
    """Add to ``result`` (the run from the scene's start, at ``speed`` m/s) what ``others`` (the runs from
    :data:`START_FACTORS` times it, in that order) show: each start's speed, recurrence and sequence, the largest
    relative change of the recurrence (``start_change``) and ``multistable`` (True: another start settles to
    another period; None: they differ but a run has not settled), with a note. Each result needs
    ``recurrence_interval``, ``sequence``, ``settled`` and ``sequence_error``."""
    own = _recurrence(result)
    verdicts = [same_cycle(own, _error(result), bool(result.values["settled"]), _recurrence(run), _error(run),
                           bool(run.values["settled"])) for run in others]
    changes = [_recurrence(run) / own - 1 for run in others]
    result.add("start_speeds", [factor * speed for factor in (1.0, *START_FACTORS)], "m/s",
               label="each run's start: every element (off a nucleation patch) in steady state at this slip rate")
    result.add("start_recurrences", [own] + [_recurrence(run) for run in others], "s", also=("yr",),
               label="the recurrence each start settles to")
    result.add("start_sequences", [result.values["sequence"]] + [run.values["sequence"] for run in others],
               label="the sequence each start settles to")
    result.add("start_change", max(changes, key=abs),
               label="the largest relative change of the recurrence from another start")
    multistable = True if False in verdicts else (None if None in verdicts else False)
    result.add("multistable", multistable,
               label=f"another start settles to another period (recurrences apart by more than {SAME_CYCLE:g} and "
                     "their sequences' errors, both settled; null: they differ but a run has not settled)")
    if multistable:
        moved = max(range(len(others)), key=lambda k: abs(changes[k]))
        result.note(f"multistable: from {START_FACTORS[moved] * speed:.3g} m/s the fault settles to another cycle "
                    f"({others[moved].values['sequence']}, recurrence {_recurrence(others[moved]) / YEAR:.4g} yr, "
                    f"{100 * changes[moved]:+.0f} %); the answer above is its own start's, and the declared error "
                    "does not cover the other")
    elif multistable is None:
        result.note("the starts' recurrences differ, but not every run settled to a period, so its mean may still "
                    "be moving: run longer ([run] duration) to tell whether the fault is multistable")
    else:
        result.note(f"from {' and '.join(f'{f * speed:.3g}' for f in START_FACTORS)} m/s the fault reaches the same "
                    f"recurrence (within {SAME_CYCLE:g} or its sequences' errors): one cycle, whatever the start")
    return result
