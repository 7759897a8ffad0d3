"""The 2-D fault's step count from the events a run will see (FAULT_2D_EVENT_STEPS), fitted and tested.

    python benchmarks/fault_2d_event_steps.py

Step counts do not depend on the machine, so this reads the runs already saved. The model is

    steps = A events (W / h*)^q (W / L_b)^r (L_b / h / 3)^s (rtol / 1e-8)^-0.18 + 100:

a settled sequence takes the same steps each cycle, so they grow as its events (a run's duration over the
recurrence the one-slider rung expects, :meth:`Fault2DScene.expected_events`). A, q and r are least squares over
the 36 calibration runs of ``benchmarks/ladder_designs.py`` (all at 3 elements per L_b, rtol 1e-8); s, how the
steps grow with the elements per L_b, over the first escalation draw's runs (seed 68000, 3-5 per L_b, the draw
the per-step CPU is fitted on), through the calibration's level at 3. It is tested on the runs it never saw: the
34 held-out designs, the 40 fresh ones of each later draw (``ladder_fresh.json``, ``ladder_fresh_second.json``,
``ladder_fresh_third.json``, ``ladder_fresh_fourth.json``, ``ladder_fresh_fifth.json``, ``ladder_fresh_sixth.json``),
and the first runs of the later escalation draws (``ladder_escalations*.json``, from the scene's own start; a rerun
twice as long took twice the steps, so the first took the last's over 2^(runs - 1)). For comparison it refits the
earlier model, events^p (W / h*)^q N^r with FAULT_2D_STEPS' resolution factor: fitted across faults, its p
(0.56-0.78) stood in for the events and the groups together, and it counted a rerun's twice the events as 1.5 times
the steps. Writes benchmarks/results/fault_2d_event_steps.json.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from faultslip.fault.ladder import expected_recurrence, groups, load_calibration, outside_box  # noqa: E402
from faultslip.models.fault_2d import cost  # noqa: E402
from faultslip.models.fault_2d.calibration import Design  # noqa: E402
from ladder_designs import FRESH_DRAWS  # noqa: E402
from provenance import stamp  # noqa: E402

RESULTS = ROOT / "benchmarks" / "results"
OUT = RESULTS / "fault_2d_event_steps.json"
GROUPS = ("width_over_nucleation", "width_over_process_zone")
#: the earlier model's groups, with FAULT_2D_STEPS' resolution factor: the events' power fitted, the element count N
EARLIER = ("events", "width_over_nucleation", "elements")
#: the draw the resolution's exponent is fitted on (and the per-step CPU, FAULT_2D_STEP_SECONDS)
RESOLUTION_DRAW = "escalations 68000"
#: draws run before a fault outside the one slider's box had its recurrence clamped to the box's edge: a row of
#: theirs outside the box ran over a duration that rule no longer gives, and is left out (2 of the 68000 draw's 12)
RUN_BEFORE_CLAMPING = {"ladder_escalations.json"}
ESCALATION_DRAWS = {"ladder_escalations.json": 68000, "ladder_escalations_held_out.json": 68001,
                    "ladder_escalations_second_draw.json": 68003, "ladder_escalations_third_draw.json": 68004,
                    "ladder_escalations_fourth_draw.json": 68005, "ladder_escalations_fifth_draw.json": 68008,
                    "ladder_escalations_sixth_draw.json": 68009, "ladder_escalations_seventh_draw.json": 68013,
                    "ladder_escalations_eighth_draw.json": 68021,
                    "ladder_escalations_ninth_draw.json": 68050}


def point(row: dict, elements_per_process_zone: float, duration: float, steps: float, group: str) -> dict:
    """One run's groups, its elements per L_b, the earlier model's resolution and tolerance factor, and its
    measured steps."""
    scene = Design(**row["design"]).two_d(elements_per_process_zone, duration=duration)
    fault = scene.fault
    groups = cost.event_step_groups(events=scene.expected_events(), seismogenic_width=fault.seismogenic_width(),
                                    element_size=fault.element_size, nucleation_size=fault.nucleation_size(),
                                    process_zone=fault.process_zone())
    factor = cost._resolution_factor(fault.element_size / fault.process_zone()) / cost._resolution_factor(1.0 / 3.0)
    return {"name": row["design"]["name"], "set": group, **groups, "elements": fault.count,
            "elements_per_process_zone": fault.process_zone() / fault.element_size, "earlier_factor": factor,
            "rtol_factor": (scene.rtol / 1e-8) ** cost.FAULT_2D_STEPS["rtol"], "steps": steps}


def points() -> list[dict]:
    """Every saved run with its groups: designs (calibration, held out, fresh) and escalations' first runs."""
    out = []
    for name in ("ladder_designs.json", *(path.name for _, path in FRESH_DRAWS.values())):
        for row in json.loads((RESULTS / name).read_text(encoding="utf-8"))["rows"]:
            group = row["design"]["name"].rsplit(" ", 1)[0]
            out.append(point(row, 3.0, row["duration"], row["steps"], group))
    box = load_calibration()
    for name, seed in ESCALATION_DRAWS.items():
        path = RESULTS / name
        if not path.exists():
            continue
        for row in json.loads(path.read_text(encoding="utf-8"))["rows"]:
            if "steps" not in row:
                continue  # refused before it ran
            scene = Design(**row["design"]).two_d(row["elements_per_process_zone"])
            description = scene.fault.description()
            if "duration" not in row and name in RUN_BEFORE_CLAMPING and outside_box(groups(description), box):
                continue  # its duration came from the rule before; the row does not say what it was
            duration = row.get("duration") or 8 * expected_recurrence(description)  # as ladder_escalations.py ran it
            out.append(point(row, row["elements_per_process_zone"], duration,
                             row["steps"] / 2 ** (row["runs"] - 1), f"escalations {seed}"))
    return out


def _ln_rest(p: dict) -> float:
    """ln of a run's steps less the 100 every run takes, over its events and tolerance factor."""
    return math.log((p["steps"] - 100.0) / p["events"] / p["rtol_factor"])


def fit(every: list[dict]) -> dict:
    """The model (module docstring): A, q, r over the calibration runs, s over :data:`RESOLUTION_DRAW`'s."""
    calibration = [p for p in every if p["set"] == "calibration"]
    design = np.array([[1.0] + [math.log(p[g]) for g in GROUPS] for p in calibration])
    coefficients = np.linalg.lstsq(design, np.array([_ln_rest(p) for p in calibration]), rcond=None)[0]
    model = {"scale": float(math.exp(coefficients[0])), **{g: float(c) for g, c in zip(GROUPS, coefficients[1:])},
             "resolution": 3.0}
    level = [p for p in every if p["set"] == RESOLUTION_DRAW]
    x = np.array([math.log(p["elements_per_process_zone"] / 3.0) for p in level])
    y = np.array([_ln_rest(p) - math.log(model["scale"]) - sum(model[g] * math.log(p[g]) for g in GROUPS)
                  for p in level])
    model["elements_per_process_zone"] = float(x @ y / (x @ x))
    return model


def predicted(model: dict, p: dict) -> float:
    """The model's steps for run ``p`` (the library's :func:`faultslip.models.fault_2d.cost.fault_2d_steps`)."""
    return (model["scale"] * p["events"] * math.prod(p[g] ** model[g] for g in GROUPS)
            * (p["elements_per_process_zone"] / model["resolution"]) ** model["elements_per_process_zone"]
            * p["rtol_factor"] + 100.0)


def fit_earlier(every: list[dict]) -> dict:
    """The earlier model refitted on the calibration runs: ln(steps - 100) on ln events, W / h* and N."""
    calibration = [p for p in every if p["set"] == "calibration"]
    design = np.array([[1.0] + [math.log(p[g]) for g in EARLIER] for p in calibration])
    target = np.array([math.log((p["steps"] - 100.0) / p["earlier_factor"] / p["rtol_factor"]) for p in calibration])
    coefficients = np.linalg.lstsq(design, target, rcond=None)[0]
    return {"scale": float(math.exp(coefficients[0])), **{g: float(c) for g, c in zip(EARLIER, coefficients[1:])}}


def predicted_earlier(model: dict, p: dict) -> float:
    return (model["scale"] * math.prod(p[g] ** model[g] for g in EARLIER) * p["earlier_factor"] * p["rtol_factor"]
            + 100.0)


def spread(model: dict, chosen: list[dict], how=predicted) -> dict:
    """Estimated over measured steps on ``chosen``."""
    ratios = [how(model, p) / p["steps"] for p in chosen]
    return {"runs": len(ratios), "within_2x": int(sum(0.5 <= r <= 2 for r in ratios)), "ratio_min": min(ratios),
            "ratio_median": float(np.median(ratios)), "ratio_max": max(ratios),
            "log_sd": float(np.std(np.log(ratios)))}


def main():
    every = points()
    model, earlier = fit(every), fit_earlier(every)
    sets = sorted({p["set"] for p in every}, key=lambda s: (s != "calibration", s))
    table = {s: {"declared": spread(model, [p for p in every if p["set"] == s]),
                 "earlier": spread(earlier, [p for p in every if p["set"] == s], predicted_earlier)} for s in sets}
    left_out = {}
    for name in RUN_BEFORE_CLAMPING:
        ran = sum("steps" in row for row in json.loads((RESULTS / name).read_text(encoding="utf-8"))["rows"])
        draw = f"escalations {ESCALATION_DRAWS[name]}"
        left_out[draw] = ran - sum(p["set"] == draw for p in every)
    OUT.write_text(json.dumps({**stamp(), "groups": list(GROUPS), "model": model, "earlier_groups": list(EARLIER),
                               "earlier_model": earlier, "sets": table, "left_out": left_out, "points": every},
                              indent=1) + "\n", encoding="utf-8")
    print("fitted:", ", ".join(f"{k} {v:.4g}" for k, v in model.items()))
    for s, line in table.items():
        d, e = line["declared"], line["earlier"]
        print(f"{s}: {d['runs']} runs, estimated / measured steps {d['ratio_min']:.2f}-{d['ratio_max']:.2f} (median "
              f"{d['ratio_median']:.2f}, {d['within_2x']} within 2x); earlier model {e['ratio_min']:.2f}-"
              f"{e['ratio_max']:.2f} (median {e['ratio_median']:.2f}, {e['within_2x']} within 2x)")


if __name__ == "__main__":
    main()
