"""The shipped chain's numbers, as docs/spring_chain.md and docs/classroom.md quote them (generated, never typed).

    python benchmarks/chain_example.py

Runs configs/spring_chain.toml as ``faultslip run`` does, and the predictability of its events
(:func:`faultslip.hazard.predictability` on every event's start and total slip, as the classroom's chain tab does).
Writes benchmarks/results/chain_example.json; benchmarks/readme.py renders it.
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

import numpy as np  # noqa: E402

import faultslip  # noqa: E402
from fault_2d_profile import write_results  # noqa: E402


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
    write_results("chain_example.json", document)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
