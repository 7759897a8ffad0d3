"""One entry point for the benchmarks, and the command that regenerates every generated docs table.

    python -m benchmarks --list                 # every benchmark, and the results file(s) it writes
    python -m benchmarks NAME [ARGS ...]        # one benchmark, as python benchmarks/NAME.py ARGS
    python -m benchmarks --all [--quick] [--qdyn PATH] [--pylook-python PATH] [--peer DIR]

``--all`` runs every benchmark that writes a results file a docs table is generated from (:data:`PRODUCERS`),
each as its own process, in turn, and then ``readme.py``, which rewrites every generated table. ``--quick`` gives
each its short form (:data:`QUICK`: fewer rounds, sizes and cases; the tables then say what they measured). A
benchmark against a peer code runs only when the peer is given (``--qdyn``, ``--pylook-python``, ``--peer``); otherwise it is
skipped and its table keeps its last measured results, and the run says so. A benchmark that fails is reported
and the others still run; the exit status is 1 if any failed.
"""

from __future__ import annotations

import argparse
import importlib.util
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent

#: The runs whose results files benchmarks/readme.py renders into docs tables, in the order --all runs them:
#: (script, its arguments, its short form's arguments for --quick, the results file it writes).
PRODUCERS = (
    ("run", [], ["--quick"], "latest.json"),
    ("sweep_scale", [], ["--quick"], "sweep.json"),
    ("startup", [], ["--repeats", "3"], "startup.json"),
    ("first_run", [], ["--rounds", "1"], "first_run.json"),
    ("command_estimates", [], ["--rounds", "1"], "command_estimates.json"),
    ("fault_2d", [], ["--quick"], "fault_2d.json"),
    ("fault_2d_threads", [], ["--elements", "1600", "--rounds", "1", "--placement", "5", "--batches", "5",
                              "--pairs", "2"], "fault_2d_threads.json"),
    ("fault_2d_placement", [], ["--seconds", "5"], "fault_2d_placement.json"),
    ("fault_2d_qdyn", [], ["--rounds", "1"], "fault_2d_qdyn.json"),
    ("fault_2d_profile", [], ["--elements", "1024"], "fault_2d_profile.json"),
    ("fault_2d_resolution", [], ["--quick"], "fault_2d_resolution.json"),
    ("fault_2d_resolution_designs", ["--refine"], ["--quick"], "fault_2d_resolution_designs.json"),
    ("fault_2d_resolution_designs", ["--refine", "--source", "ladder_fresh_second.json", "--first", "24"],
     ["--quick", "--source", "ladder_fresh_second.json"], "fault_2d_resolution_ladder_fresh_second.json"),
    ("fault_2d_period3", [], [], "fault_2d_period3.json"),
    ("spring_block_qdyn", [], ["--repeats", "1"], "spring_block_qdyn.json"),
    ("spring_chain_speed", [], ["--rounds", "1"], "spring_chain_speed.json"),
    ("posterior_speed", [], [], "posterior_speed.json"),
    ("fit_coverage", [], ["--cases", "40"], "fit_coverage.json"),
    ("stiffness_free", [], ["--cases", "20", "--rounds", "1"], "stiffness_free.json"),
    ("p655_analysis", [], ["--quick"], "p655_analysis.json"),
    ("classroom_redraw", [], [], "classroom_redraw.json"),
    ("animation_speed", [], ["--pairs", "1"], "animation.json"),
    ("chain_example", [], [], "chain_example.json"),
    ("san_andreas_map", [], [], "san_andreas_map.json"),
    ("docs_numbers", [], [], "docs_numbers.json"),
    ("asperity_trends", [], [], "asperity_trends.json"),
    ("asperity_wavelength_check", [], ["--quick"], "asperity_wavelength_check.json"),
    ("asperity_measured_wavelength_check", [], [], "asperity_measured_wavelength_check.json"),  # after the locks
    ("averaging_check", [], ["--quick"], "averaging_check.json"),
    ("nanoscale_hopf_check", [], ["--quick"], "nanoscale_hopf_check.json"),
    ("asperity_quasistatic_check", [], ["--quick"], "asperity_quasistatic_check.json"),
    ("asperity_lsoda_steps", [], ["--quick"], "asperity_lsoda_steps.json"),
    ("surface_trends", [], [], "surface_trends.json"),
    ("event_driven_calibration", [], ["--quick"], "event_driven_calibration.json"),
    ("refinement_check", [], ["--count", "4"], "refinement_check.json"),
    # the cost table auto reads (INTEGRATOR_EVALUATIONS), before the run that checks the cost it gives; its short
    # form writes its own file, since a test holds the table to the full one
    ("integrator_evaluations", [], ["--quick"], "integrator_evaluations.json"),
    ("lab_cycle_cost", [], ["--quick"], "lab_cycle_cost.json"),
    ("slider_simulation_cost", [], ["--quick"], "slider_simulation_cost.json"),
    ("rate_state_calibration", [], ["--quick"], "rate_state_calibration.json"),
    ("rate_state_settling", [], [], "rate_state_settling.json"),
    ("chain_coverage", [], ["--quick"], "chain_coverage.json"),
    ("hazard_chain", [], [], "hazard_chain.json"),
    ("renewal_coverage", [], ["--catalogs", "200", "--draws", "200"], "renewal_coverage.json"),
    ("ladder_regimes", [], [], "ladder_regimes.json"),
    ("ladder_designs", ["--fresh", "40"], ["--fresh", "40"], "ladder_fresh.json"),  # rows already there are kept
    ("ladder_designs", ["--fresh", "40", "--seed", "68012"], ["--fresh", "40", "--seed", "68012"],
     "ladder_fresh_second.json"),
    ("ladder_designs", ["--fresh", "40", "--seed", "68014"], ["--fresh", "40", "--seed", "68014"],
     "ladder_fresh_third.json"),
    ("ladder_designs", ["--fresh", "40", "--seed", "68031"], ["--fresh", "40", "--seed", "68031"],
     "ladder_fresh_fourth.json"),
    ("ladder_designs", ["--fresh", "40", "--seed", "68041"], ["--fresh", "40", "--seed", "68041"],
     "ladder_fresh_fifth.json"),
    ("ladder_designs", ["--fresh", "40", "--seed", "68061"], ["--fresh", "40", "--seed", "68061"],
     "ladder_fresh_sixth.json"),
    ("ladder_designs", ["--fresh", "40", "--seed", "68071"], ["--fresh", "40", "--seed", "68071"],
     "ladder_fresh_seventh.json"),
    ("ladder_designs", ["--fresh", "40", "--seed", "68081"], ["--fresh", "40", "--seed", "68081"],
     "ladder_fresh_eighth.json"),
    ("ladder_calibration", [], [], "ladder_held_out.json"),
    ("ladder_outside_box", [], ["--count", "6"], "ladder_outside_box.json"),  # after the calibration it clamps to
    # the step count's model from the saved runs (after the calibration whose recurrences count the events)
    ("fault_2d_event_steps", [], [], "fault_2d_event_steps.json"),
    ("fuzz", ["--seed", "69"], ["--seed", "69", "--cases", "500"], "fuzz.json"),
    ("fuzz", ["--seed", "690", "--out", "benchmarks/results/fuzz_second_seed.json"],
     ["--seed", "690", "--cases", "500", "--out", "benchmarks/results/fuzz_second_seed.json"], "fuzz_second_seed.json"),
    ("kills", [], ["--kills", "5", "--races", "5"], "kills.json"),
    ("plane_strain_step", [], ["--elements", "200", "400", "--years", "20"], "plane_strain_step.json"),
    ("dip_model_error", [], ["--element-size", "200", "--years", "600"], "dip_model_error.json"),
    # the one slider against plane strain: each measured fault's surface slip, then the fit (before the fresh draws)
    ("dip_slider_runs", [], [], "dip_slider_runs.json"),
    ("dip_slider_calibration", [], [], "dip_slider_calibration.json"),
    # fresh draws against the shipped declaration (after the run above, which may rewrite it)
    ("dip_model_error", ["--fresh", "32", "--seed", "4311"], ["--fresh", "32", "--seed", "4311"],
     "dip_model_error_fresh_4311.json"),
    # and against the one slider's calibration against plane strain, as shipped
    ("dip_model_error", ["--fresh", "32", "--seed", "4313"], ["--fresh", "32", "--seed", "4313"],
     "dip_model_error_fresh_4313.json"),
    ("dip_model_error", ["--fresh", "32", "--seed", "4315"], ["--fresh", "32", "--seed", "4315"],
     "dip_model_error_fresh_4315.json"),
    ("dip_model_error", ["--fresh", "32", "--seed", "4317"], ["--fresh", "32", "--seed", "4317"],
     "dip_model_error_fresh_4317.json"),
    ("seas_bp3", [], ["--sizes", "200", "100", "--years", "600"], "seas_bp3.json"),
    ("engine_branches", [], [], "engine_branches.json"),
    ("fault_3d_operator", [], ["--quick"], "fault_3d_operator.json"),
    ("family_costs", [], ["--rounds", "1"], "family_costs.json"),
    ("rough_auto_choice", [], ["--count", "3"], "rough_auto_choice.json"),  # at the prices just fitted
    ("sherifs_example", [], [], "sherifs_example.json"),
    ("rupture_rate_stability", [], ["--quick"], "rupture_rate_stability.json"),
    ("rupture_rate_cost", [], ["--quick"], "rupture_rate_cost.json"),
    ("rupture_rate_exact_point", [], ["--quick"], "rupture_rate_exact_point.json"),
    ("fault_3d_model_error", [], ["--quick"], "fault_3d_model_error.json"),
    ("fault_3d_model_error", ["--starts"], ["--starts"], "fault_3d_starts.json"),  # the cells just written
    # the draws run after the table (their 3-D cells kept by inputs: run again, only the 2-D sides are)
    ("fault_3d_model_error", ["--fresh", "7301", "8"], ["--fresh", "7301", "8"], "fault_3d_model_error_fresh.json"),
    ("fault_3d_model_error", ["--fresh", "7305", "8"], ["--fresh", "7305", "8"], "fault_3d_model_error_fresh.json"),
    ("fault_3d_model_error", ["--fresh", "7307", "16"], ["--fresh", "7307", "16"], "fault_3d_model_error_fresh.json"),
    ("fault_3d_model_error", ["--fresh", "7309", "8", "--box", "wide"], ["--fresh", "7309", "8", "--box", "wide"],
     "fault_3d_model_error_fresh.json"),
    ("fault_3d_model_error", ["--fresh", "7311", "8", "--box", "wide"], ["--fresh", "7311", "8", "--box", "wide"],
     "fault_3d_model_error_fresh.json"),
    ("fault_3d_model_error", ["--fresh", "7313", "8"], ["--fresh", "7313", "8"], "fault_3d_model_error_fresh.json"),
    ("fault_3d_model_error", ["--fresh", "7315", "8"], ["--fresh", "7315", "8"], "fault_3d_model_error_fresh.json"),
    ("fault_3d_model_error", ["--fresh", "7317", "8"], ["--fresh", "7317", "8"], "fault_3d_model_error_fresh.json"),
    ("seas_bp5", ["--sizes", "2000", "1000", "500", "--finest-years", "1800"],
     ["--sizes", "2000", "1000", "--years", "600", "--finest-years", "600"], "seas_bp5.json"),
    # drawn faults at three square sizes (quick: the saved runs judged again), then the slip bound fitted on them
    ("fault_3d_resolution", ["--sizes", "100", "50", "25"], ["--reuse", "--sizes", "100"], "fault_3d_resolution.json"),
    ("fault_3d_slip_error", [], [], "fault_3d_slip_error.json"),
    # faults drawn after the recurrence bound's margin was set from those above: its held-out check
    ("fault_3d_resolution", ["--seed", "7403", "--count", "5", "--sizes", "100", "50", "25", "--out",
                             "benchmarks/results/fault_3d_resolution_fresh.json"],
     ["--seed", "7403", "--count", "5", "--reuse", "--sizes", "100", "--out",
      "benchmarks/results/fault_3d_resolution_fresh.json"], "fault_3d_resolution_fresh.json"),
    ("fault_3d_resolution", ["--seed", "7405", "--count", "5", "--sizes", "100", "50", "25", "--out",
                             "benchmarks/results/fault_3d_resolution_fresh_second.json"],
     ["--seed", "7405", "--count", "5", "--reuse", "--sizes", "100", "--out",
      "benchmarks/results/fault_3d_resolution_fresh_second.json"], "fault_3d_resolution_fresh_second.json"),
    # the 3-D cost model's fit runs (quick: refitted from the saved runs), then its held-out draw
    ("fault_3d_cost", ["--part", "fit"], ["--part", "refit"], "fault_3d_cost.json"),
    # every cost group's reference work, after the fits it anchors and before the estimates checked against it
    ("machine_speed", [], ["--quick"], "machine_speed.json"),
    # the machine speed record's median against one probe, on the same runs
    ("machine_record", [], ["--pairs", "8"], "machine_record.json"),
    ("machine_record", ["--out", "benchmarks/results/machine_record_held_out.json"],
     ["--pairs", "8", "--out", "benchmarks/results/machine_record_held_out.json"], "machine_record_held_out.json"),
    ("fault_3d_cost", ["--part", "held-out"], ["--part", "held-out"], "fault_3d_cost.json"),
    ("fault_3d_cost", ["--part", "rtol"], ["--part", "rtol"], "fault_3d_cost.json"),
    # escalations estimated on this machine (after machine_speed)
    ("ladder_escalations", ["--seed", "68001"], ["--seed", "68001", "--count", "4"], "ladder_escalations_held_out.json"),
    # the later unseen draws, each into its own file
    *(("ladder_escalations", ["--seed", seed, "--out", f"benchmarks/results/{name}"],
       ["--seed", seed, "--count", "4", "--out", f"benchmarks/results/{name}"], name)
      for seed, name in (("68003", "ladder_escalations_second_draw.json"),
                         ("68004", "ladder_escalations_third_draw.json"),
                         ("68005", "ladder_escalations_fourth_draw.json"),
                         ("68008", "ladder_escalations_fifth_draw.json"),
                         ("68009", "ladder_escalations_sixth_draw.json"),
                         ("68013", "ladder_escalations_seventh_draw.json"),
                         ("68021", "ladder_escalations_eighth_draw.json"),
                         ("68050", "ladder_escalations_ninth_draw.json"),
                         ("68060", "ladder_escalations_tenth_draw.json"),
                         ("68070", "ladder_escalations_eleventh_draw.json"),
                         ("68080", "ladder_escalations_twelfth_draw.json"))),
)
#: Packages a benchmark needs beyond the test install, by the module that shows they are there: without it the
#: benchmark is skipped and its table keeps its last results, as a peer's does.
REQUIRES = {"hazard_chain": "openquake"}
#: Peer codes a benchmark needs, by the flag that gives it.
PEERS = {"fault_2d_qdyn": "--qdyn", "spring_block_qdyn": "--qdyn", "look_against_pylook": "--pylook-python",
         "seas_bp3": "--peer"}
#: Every script that is a benchmark (not a helper module).
HELPERS = {"__init__", "__main__", "provenance", "readme", "peer_runs"}


def benchmarks() -> list[str]:
    """Every benchmark script's name."""
    return sorted(path.stem for path in HERE.glob("*.py") if path.stem not in HELPERS)


def run_one(name: str, arguments: list[str]) -> int:
    """``python benchmarks/NAME.py ARGUMENTS`` as its own process; its exit status."""
    if name not in benchmarks() and name != "readme":
        raise SystemExit(f"python -m benchmarks: no benchmark named {name!r}; 'python -m benchmarks --list' lists them")
    return subprocess.call([sys.executable, str(HERE / f"{name}.py"), *arguments], cwd=ROOT)


def run_all(quick: bool, peers: dict) -> int:
    failed, skipped = [], []
    for name, full, short, _ in PRODUCERS:
        arguments = list(short if quick else full)
        if name in PEERS:
            peer = peers.get(PEERS[name])
            if peer is None:
                skipped.append(f"{name} (needs {PEERS[name]} PATH)")
                continue
            arguments += [PEERS[name], peer]
        if name in REQUIRES and importlib.util.find_spec(REQUIRES[name]) is None:
            skipped.append(f"{name} (needs the {REQUIRES[name]} package)")
            continue
        began = time.perf_counter()
        print(f"python -m benchmarks: {name} {' '.join(arguments)}", flush=True)
        status = run_one(name, arguments)
        print(f"python -m benchmarks: {name} {'done' if status == 0 else f'FAILED (exit {status})'} in "
              f"{time.perf_counter() - began:.0f} s", flush=True)
        if status != 0:
            failed.append(name)
    status = run_one("readme", [])
    if skipped:
        print("skipped, their tables keep their last results: " + ", ".join(skipped))
    if failed:
        print("failed: " + ", ".join(failed))
    return 1 if failed or status != 0 else 0


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    if argv and not argv[0].startswith("-"):
        return run_one(argv[0], argv[1:])
    parser = argparse.ArgumentParser(prog="python -m benchmarks", description=__doc__.splitlines()[0])
    parser.add_argument("--list", action="store_true", help="list the benchmarks and the results they write")
    parser.add_argument("--all", action="store_true", help="run every producer of a docs table, then readme.py")
    parser.add_argument("--quick", action="store_true", help="each benchmark's short form")
    parser.add_argument("--qdyn", help="a built QDYN (its qdyn.py folder) for the peer benchmarks")
    parser.add_argument("--pylook-python", help="a Python with pylook installed, for the pylook comparisons")
    parser.add_argument("--peer", help="a folder with FDRA's published SEAS BP3-QD files, for benchmarks/seas_bp3.py")
    args = parser.parse_args(argv)
    if args.list or not args.all:
        for name in benchmarks():
            writes = ", ".join(out for script, _, _, out in PRODUCERS if script == name) or \
                "(a figure, a study or data; no docs table)"
            print(f"{name:24s} {writes}")
        return 0
    return run_all(args.quick, {"--qdyn": args.qdyn, "--pylook-python": args.pylook_python, "--peer": args.peer})


if __name__ == "__main__":
    raise SystemExit(main())
