"""The bundled San Andreas maps predicted against observed, as docs/studies.md shows them (generated, never typed).

    python benchmarks/san_andreas_map.py

Runs configs/san_andreas_map.toml (the seed law) and configs/san_andreas_map_rate_state.toml (one rate-and-state
block a segment, with its model error against the 2-D fault) as ``faultslip map`` does, and keeps each segment's
predicted and observed slip and recurrence. Writes benchmarks/results/san_andreas_map.json; benchmarks/readme.py
renders it.
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from provenance import write_results  # noqa: E402  (one stamp for every results file)
from faultslip.studies.maps import read_map, run_map, segment_rows  # noqa: E402

MAPS = {"seed_law": "san_andreas_map.toml", "rate_state": "san_andreas_map_rate_state.toml"}


def measure(config: str) -> dict:
    """One map's segments: slip rate, predicted and observed slip and recurrence, and the events observed."""
    dataset = run_map(read_map(config))
    rows = segment_rows(dataset)
    events = ([str(value) for value in dataset["observed_slip_event"].values] if "observed_slip_event" in dataset
              else [""] * len(rows))
    finite = lambda value: value if value == value and abs(value) != float("inf") else None  # noqa: E731 (JSON)
    return {"config": f"configs/{config}", "segments": [
        {"segment": row["segment"], "observed_slip_event": event,
         **{key: finite(value) for key, value in row.items() if key != "segment"}}
        for row, event in zip(rows, events)]}


def main() -> int:
    document = {name: measure(config) for name, config in MAPS.items()}
    write_results("san_andreas_map.json", document)
    for name, result in document.items():
        print(name, len(result["segments"]), "segments")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
