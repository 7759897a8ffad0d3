"""The shipped chain's numbers, as docs/spring_chain.md and docs/classroom.md quote them (generated, never typed).

    python benchmarks/chain_example.py

Runs configs/spring_chain.toml as ``faultslip run`` does, and the predictability of its events
(:func:`faultslip.hazard.predictability` on every event's start and total slip, as the classroom's chain tab does);
and the same chain with identical blocks from identical starts (no threshold spread, no initial offset), which
breaks into events of many sizes on its own (docs/spring_chain.md).
Writes benchmarks/results/chain_example.json; benchmarks/readme.py renders it.
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

import numpy as np  # noqa: E402

import faultslip  # noqa: E402
from provenance import write_results  # noqa: E402  (one stamp for every results file)


#: The classroom's knobs, each a change to configs/spring_chain.toml's text (docs/classroom.md, docs/spring_chain.md).
VARIANTS = {
    "weaker coupling, k_c = 2 kN/m": (('coupling_stiffness = "10 kN/m"', 'coupling_stiffness = "2 kN/m"'),),
    "less spread, threshold_spread = 0.2": (("threshold_spread = 0.5 ", "threshold_spread = 0.2 "),),
    "identical blocks from identical starts": (("threshold_spread = 0.5 ", "threshold_spread = 0.0 "),
                                               ('initial_offset = "0.05 mm"', 'initial_offset = "0 mm"')),
}


def chain_numbers(scene) -> dict:
    """A chain scene's catalogue as the lessons read it: blocks per event, magnitudes, b-value (or why there is
    none), system-size events and their intervals' CV."""
    result = faultslip.run(str(scene))
    catalogue = faultslip.simulate(str(scene)).to_xarray()
    values = result.values
    b_label = next(item.label for item in result.report().items if item.key == "b_value")
    return {"events": values["events"], "blocks_per_event": float(catalogue["blocks_slipped"].mean()),
            "magnitude_range": [values["magnitude_min"], values["magnitude_max"]], "b_value": values["b_value"],
            "b_value_label": b_label, "gutenberg_richter": values.get("gutenberg_richter"),
            "system_events": values["system_size_events"], "system_cv": values["recurrence_cv"]}


def variants() -> dict:
    """:data:`VARIANTS`, each run on its changed copy of the shipped scene."""
    text = (ROOT / "configs" / "spring_chain.toml").read_text(encoding="utf-8")
    found = {}
    with tempfile.TemporaryDirectory() as folder:
        for label, changes in VARIANTS.items():
            changed = text
            for old, new in changes:
                if old not in changed:
                    raise SystemExit(f"configs/spring_chain.toml no longer has {old!r}: update VARIANTS")
                changed = changed.replace(old, new)
            scene = Path(folder) / "variant.toml"
            scene.write_text(changed, encoding="utf-8")
            found[label] = chain_numbers(scene)
    return found


def main() -> int:
    result = faultslip.run("spring_chain.toml")
    values = result.values
    catalogue = faultslip.simulate("spring_chain.toml").to_xarray()
    starts = np.asarray(catalogue["event_start"].values, float)
    predict = faultslip.hazard.predictability(starts, np.asarray(catalogue["total_slip"].values, float))
    document = {
        "scene": "configs/spring_chain.toml", "blocks": values["blocks"], "events": values["events"],
        "magnitude_range": [values["magnitude_min"], values["magnitude_max"]],
        "gutenberg_richter": values["gutenberg_richter"], "gr_p_value": values["gutenberg_richter_p_value"],
        "b_value": values["b_value"], "b_over_cutoffs": list(values["b_value_over_cutoffs"]),
        "system_events": values["system_size_events"], "system_cv": values["recurrence_cv"],
        "all_events_cv": predict.aperiodicity,
        "time_predictable": {"r": predict.time_correlation, "range": list(predict.time_range),
                             "holds": predict.verdicts["time_predictable"]},
        "slip_predictable": {"r": predict.slip_correlation, "range": list(predict.slip_range),
                             "holds": predict.verdicts["slip_predictable"]},
        "all_events_cv_range": list(predict.aperiodicity_range),
    }
    document["shipped"] = chain_numbers(ROOT / "configs" / "spring_chain.toml")
    document["variants"] = variants()
    write_results("chain_example.json", document)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
