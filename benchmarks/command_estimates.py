"""Each family's command estimate against the CPU the command uses: ``faultslip run SCENE --estimate --json``'s
``command_seconds`` beside the CPU of ``faultslip run SCENE --json`` in its own process.

    python benchmarks/command_estimates.py [--rounds 3]

The cases are every family's short runs and simulations, example studies swept to a file, and the San Andreas
maps (the 2-D and 3-D faults' runs are measured by ``benchmarks/ladder_escalations.py``). Each command runs as a
whole process (``python -m faultslip.cli``), its CPU taken from its rusage (user and system); per round the estimate
and the run alternate which goes first, and the figure is the median over rounds. Beside it, in the same run, the
estimate without the imports its run needs (``import_seconds``, which faultslip.io.budget.with_imports measures),
as every estimate was before it counted them. Writes ``benchmarks/results/command_estimates.json``;
docs/benchmarks.md's table is written from it by ``benchmarks/readme.py``.
"""

from __future__ import annotations

import argparse
import json
import resource
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benchmarks"))

from provenance import write_results  # noqa: E402  (one stamp for every results file)

#: (command, scene, options): the short runs of every family but the discretised faults
CASES = [
    ("run", "san_andreas_1906.toml", []),
    ("run", "lab_glass_dry.toml", []),
    ("run", "lab_glass_dry.toml", ["--method", "event_driven_DOP853"]),
    ("run", "lab_steel_dry_time_of_stick.toml", []),
    ("run", "lab_steel_dry_polynomial.toml", []),
    ("simulate", "lab_glass_dry.toml", ["--cycles", "20"]),
    ("run", "rsf_velocity_step.toml", []),
    ("run", "rsf_block_bp1.toml", ["--model", "one_slider"]),
    ("simulate", "rsf_block_bp1.toml", []),
    ("run", "rough_surface_seed000.toml", []),
    ("run", "nanoscale_seed001.toml", []),
    ("run", "asperity_seed004.toml", []),
    ("run", "asperity_seed004.toml", ["--method", "asperity_measured_wavelength"]),
    ("run", "vibration_seed002.toml", []),
    ("run", "vibration_seed002.toml", ["--method", "quasi_harmonic_integration"]),
    ("simulate", "vibration_seed002.toml", []),
    ("run", "spring_chain_small.toml", []),
    # sweeps and maps, to a file (OUT: a fresh file each time)
    ("sweep", "study_spring_slider.toml", ["-o", "OUT"]),
    ("sweep", "study_rate_state.toml", ["-o", "OUT"]),
    ("sweep", "study_rate_state_slider.toml", ["-o", "OUT"]),
    ("sweep", "study_vibration.toml", ["-o", "OUT"]),
    ("sweep", "study_nanoscale.toml", ["-o", "OUT"]),
    ("sweep", "study_rough_surface.toml", ["-o", "OUT"]),
    ("sweep", "study_spring_chain.toml", ["-o", "OUT"]),
    ("map", "san_andreas_map.toml", ["-o", "OUT"]),
    ("map", "san_andreas_map_rate_state.toml", ["-o", "OUT"]),
]


def _child_cpu(command: list) -> tuple[float, str]:
    with tempfile.TemporaryDirectory() as folder:  # a sweep's or map's file, new each time
        command = [str(Path(folder) / "out.nc") if part == "OUT" else part for part in command]
        return _timed(command)


def _timed(command: list) -> tuple[float, str]:
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    done = subprocess.run([sys.executable, "-m", "faultslip.cli", *command], capture_output=True, text=True,
                          cwd=ROOT)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        raise SystemExit(f"{' '.join(command)} failed: {done.stderr.strip()[-400:]}")
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), done.stdout


def _value(entry) -> float:
    return float(entry["value"] if isinstance(entry, dict) else entry)


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args(argv)
    for action, scene, options in CASES:  # warm the file cache and numba's
        _child_cpu([action, scene, *options, "--json"])
    found = {i: {"estimate": [], "imports": [], "used": []} for i in range(len(CASES))}
    for round_ in range(args.rounds):
        for i, (action, scene, options) in enumerate(CASES):
            order = ("estimate", "run") if (round_ + i) % 2 == 0 else ("run", "estimate")
            for which in order:
                if which == "estimate":
                    _, text = _child_cpu([action, scene, *options, "--estimate", "--json"])
                    report = json.loads(text)
                    found[i]["estimate"].append(_value(report["command_seconds"]))
                    found[i]["imports"].append(_value(report["import_seconds"]) if "import_seconds" in report
                                               else 0.0)
                else:
                    found[i]["used"].append(_child_cpu([action, scene, *options, "--json"])[0])
    rows = []
    for i, (action, scene, options) in enumerate(CASES):
        estimate, imports, used = (statistics.median(found[i][key]) for key in ("estimate", "imports", "used"))
        rows.append({"command": f"faultslip {action} {scene}" + (f" {' '.join(options)}" if options else ""),
                     "estimate_seconds": estimate, "import_seconds": imports, "used_seconds": used,
                     "used_over_estimate": used / estimate,
                     "used_over_estimate_without_imports": used / max(estimate - imports, 1e-9)})
        print(f"{rows[-1]['command']:<80} {estimate:6.2f} s (imports {imports:4.2f}) used {used:6.2f} s: "
              f"{rows[-1]['used_over_estimate']:.2f}x, {rows[-1]['used_over_estimate_without_imports']:.2f}x without")
    ratios = [row["used_over_estimate"] for row in rows]
    before = [row["used_over_estimate_without_imports"] for row in rows]
    result = {"rounds": args.rounds, "cases": rows,
              "within_2x": sum(0.5 <= r <= 2.0 for r in ratios),
              "within_2x_without_imports": sum(0.5 <= r <= 2.0 for r in before)}
    write_results("command_estimates.json", result)
    return result


if __name__ == "__main__":
    main()
