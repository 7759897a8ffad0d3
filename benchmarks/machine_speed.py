"""Each cost group carried to the reference work, so that estimates follow the machine (faultslip.io.machine).

    python benchmarks/machine_speed.py            # every group (about 8 min on two cores)
    python benchmarks/machine_speed.py --quick    # fewer runs a group (about 4 min)
    python benchmarks/machine_speed.py --group families

A cost group's constants were fitted on this machine in one state, and say nothing of it. This repeats runs of
each group's own fit now, the same scenes and the same work timed as the fit timed them, and probes the reference
work (:func:`faultslip.io.machine.probe_seconds`) before and after each. The fit's CPU over now's, median over the
runs, carries the probe to the state the group was fitted in:

    t_ref(group) = t_ref(now) x median(CPU then / CPU now)

per step where the runs count steps (the steps can move with the code; the work of a step does not):

- ``fault_2d_step`` (FAULT_2D_STEP_SECONDS, and the first-run load measured with it): the twelve escalations of
  ``benchmarks/results/ladder_escalations.json`` (seed 68000, the fit's draw), two at a time in fresh worker
  processes, as there;
- ``plane_strain_step`` (PLANE_STRAIN_STEP_SECONDS): ``plane_strain_step.json``'s sizes up to 400 elements, the
  faster of two runs, as there;
- ``fault_3d`` (FAULT_3D_STEP_SECONDS and FAULT_3D_PAIR_SECONDS): ``fault_3d_cost.json``'s fit runs that took
  under 10 s, each step's CPU and the assembly's apart;
- ``families`` (``data/family_costs.json``, and the typed rates carried with it): ``family_costs.json``'s fitted
  cases of 0.05 s or more, the median of three timings after a warm-up, as there.

Writes ``data/machine_reference.json`` (what faultslip reads) and ``benchmarks/results/machine_speed.json`` (every
run, then and now). A group's refit must rerun its group here: ``tests/capabilities/contract/test_machine_speed.py``
checks each run's "then" against the fit's file as it stands (:func:`recorded`).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(HERE))

from faultslip import __version__  # noqa: E402
from faultslip.io import budget, machine  # noqa: E402
from faultslip.io.resources import read_bundled_table, write_bundled_table  # noqa: E402
from ladder_escalations import total_steps  # noqa: E402
from provenance import stamp  # noqa: E402

RESULTS = HERE / "results"
OUT = ROOT / "data" / machine.REFERENCE_FILE
RECORD = RESULTS / "machine_speed.json"
#: the fit files each group's runs repeat
SOURCES = {"fault_2d_step": "ladder_escalations.json", "plane_strain_step": "plane_strain_step.json",
           "fault_3d": "fault_3d_cost.json", "families": "family_costs.json"}


def _source(group: str) -> dict:
    return json.loads((RESULTS / SOURCES[group]).read_text(encoding="utf-8"))


def _per_step(row: dict) -> float:
    """An escalation's CPU a step, over all its runs."""
    return row["cpu_time"] / total_steps(row)


def recorded(group: str) -> dict[str, float]:
    """What the group's fit recorded of each run it may repeat ("then"), by the run's name: CPU seconds a step, an
    assembly's, or a case's. The test that checks the reference recomputes these from the fit's file as it stands."""
    source = _source(group)
    if group == "fault_2d_step":
        return {row["design"]["name"]: _per_step(row) for row in source["rows"] if "cpu_time" in row}
    if group == "plane_strain_step":
        return {f"BP3-QD thrust on {row['elements']} elements": row["seconds_per_step"] for row in source["rows"]}
    if group == "fault_3d":
        steps = {row["what"]: row["steps_cpu_s"] / row["steps"] for row in source["fit_runs"]}
        return {**steps, **{f"{row['what']}: assembly": row["assembly_s"] for row in source["fit_runs"]}}
    return {f"{row['family']} {row['case']}": row["cpu_seconds"] for row in source["rows"] if not row["held_out"]}


def fault_2d_step(quick: bool = False) -> list[dict]:
    import ladder_escalations

    source = {row["design"]["name"]: row for row in _source("fault_2d_step")["rows"] if "cpu_time" in row}
    then = recorded("fault_2d_step")
    # the draw's first designs are the same at any count (ladder_designs.draw draws them in turn)
    now = ladder_escalations.escalations(4 if quick else len(source), 68000)
    same = [row for row in now if "cpu_time" in row and row["design"]["name"] in source
            and source[row["design"]["name"]]["elements"] == row["elements"]]
    return [{"run": row["design"]["name"], "then": then[row["design"]["name"]], "now": _per_step(row),
             "per": "step"} for row in same]


def plane_strain_step(quick: bool = False) -> list[dict]:
    import plane_strain_step as plane

    then = recorded("plane_strain_step")
    largest = 200 if quick else 400
    sizes = [row["elements"] for row in _source("plane_strain_step")["rows"] if row["elements"] <= largest]
    return [{"run": f"BP3-QD thrust on {count} elements", "then": then[f"BP3-QD thrust on {count} elements"],
             "now": plane.timed(count)["seconds_per_step"], "per": "step"} for count in sizes]


def fault_3d(quick: bool = False) -> list[dict]:
    import fault_3d_cost

    short = {row["what"] for row in _source("fault_3d")["fit_runs"] if row["cpu_s"] < (5.0 if quick else 10.0)}
    then = recorded("fault_3d")
    fault_3d_cost.cell(4.0, 600.0, 200.0, years=5.0).run()  # the compiled force balance loaded, as the fit did
    out = []
    for what, make in fault_3d_cost.FIT:
        if what not in short:
            continue
        row = fault_3d_cost.measured(what, make())
        out.append({"run": what, "then": then[what], "now": row["steps_cpu_s"] / row["steps"], "per": "step"})
        out.append({"run": f"{what}: assembly", "then": then[f"{what}: assembly"], "now": row["assembly_s"],
                    "per": "assembly"})
    return out


def families(quick: bool = False) -> list[dict]:
    import family_costs

    then = {name: seconds for name, seconds in recorded("families").items() if seconds >= 0.05}
    lifted = budget.check
    budget.check = lambda *a, **k: None  # the fit's runs, as family_costs.py times them (a budget would gate a few)
    try:
        out = []
        for family, _entry, _units, label, call in family_costs.cases():
            if f"{family} {label}" in then:
                out.append({"run": f"{family} {label}", "then": then[f"{family} {label}"],
                            "now": family_costs.cpu_seconds(call, 1 if quick else 3), "per": "run"})
    finally:
        budget.check = lifted
    return out


GROUPS = {"fault_2d_step": fault_2d_step, "plane_strain_step": plane_strain_step, "fault_3d": fault_3d,
          "families": families}


def anchored(group: str, quick: bool = False) -> dict:
    """One group's runs repeated between two probes, and its reference work's time then."""
    before = machine.probe_seconds()
    runs = GROUPS[group](quick)
    after = machine.probe_seconds()
    probe = statistics.median([before, after])
    ratio = statistics.median(run["then"] / run["now"] for run in runs)
    print(f"{group}: {len(runs)} runs, CPU then / now median {ratio:.3f}; reference work {probe * 1e3:.3f} ms now",
          flush=True)
    return {"reference_work_seconds": probe * ratio, "probe_now_seconds": [before, after], "then_over_now": ratio,
            "source": f"benchmarks/results/{SOURCES[group]}", "source_date": _source(group).get("date"),
            "runs": runs}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--group", choices=tuple(GROUPS), action="append",
                        help="anchor only this group (repeatable); the others keep their reference")
    parser.add_argument("--quick", action="store_true", help="fewer runs a group")
    args = parser.parse_args(argv)
    # the runs' estimates are not what is measured here, and must not need the reference this writes
    os.environ[machine.ENVIRONMENT] = "1"
    chosen = args.group or list(GROUPS)
    try:
        kept = read_bundled_table(machine.REFERENCE_FILE, "the machine reference", "benchmarks/machine_speed.py")
    except Exception:  # noqa: BLE001 - a first run has none to keep
        kept = {"groups": {}}
    groups = dict(kept.get("groups", {}))
    try:  # the groups not rerun keep their runs in the record too (the data file holds none)
        recorded = json.loads(RECORD.read_text(encoding="utf-8")).get("groups", {})
    except (OSError, ValueError):
        recorded = {}
    groups.update({name: entry for name, entry in recorded.items() if name in groups and "runs" in entry
                   and entry.get("reference_work_seconds") == groups[name].get("reference_work_seconds")})
    for group in chosen:
        groups[group] = anchored(group, args.quick)
    write_bundled_table(OUT, {"provenance": {"computed_by": "benchmarks/machine_speed.py", "faultslip": __version__,
                                             **stamp(), "definition": "the reference work's thread CPU seconds "
                                             "(faultslip.io.machine.reference_work) in the machine state each cost "
                                             "group was fitted in"},
                              "groups": {name: {key: value for key, value in entry.items() if key != "runs"}
                                         for name, entry in groups.items()}})
    RECORD.write_text(json.dumps({**stamp(), "groups": groups}, indent=1) + "\n", encoding="utf-8")
    for name, entry in groups.items():
        print(f"{name}: reference work {entry['reference_work_seconds'] * 1e3:.3f} ms "
              f"(then / now {entry['then_over_now']:.3f})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
