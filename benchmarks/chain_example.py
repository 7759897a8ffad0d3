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
from fault_2d_profile import write_results  # noqa: E402


def identical_blocks() -> dict:
    """configs/spring_chain.toml with every block alike and starting alike: its magnitudes, b-value (or why there
    is none) and system-size events."""
    text = (ROOT / "configs" / "spring_chain.toml").read_text(encoding="utf-8")
    alike = text.replace("threshold_spread = 0.5 ", "threshold_spread = 0.0 ").replace(
        'initial_offset = "0.05 mm"', 'initial_offset = "0 mm"')
    assert alike != text and alike.count("= 0.0 ") >= 1, "configs/spring_chain.toml changed its spread or offset lines"
    with tempfile.TemporaryDirectory() as folder:
        scene = Path(folder) / "identical.toml"
        scene.write_text(alike, encoding="utf-8")
        result = faultslip.run(str(scene))
    values = result.values
    b_label = next(item.label for item in result.report().items if item.key == "b_value")
    return {"events": values["events"], "magnitude_range": [values["magnitude_min"], values["magnitude_max"]],
            "b_value": values["b_value"], "b_value_label": b_label, "system_events": values["system_size_events"]}


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
    document["identical_blocks"] = identical_blocks()
    write_results("chain_example.json", document)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
