"""One spring-block with SEAS BP1 friction for 100 earthquake cycles: faultslip and QDYN side by side,
as whole processes, at equal accuracy.

    python benchmarks/spring_block_qdyn.py --qdyn PATH/TO/qdyn [--repeats 15]

QDYN (github.com/ydluo/qdyn, GPL-3) is built from its public source (``cd src && make`` with gfortran and
OpenMPI); its own ``src/pyqdyn.py`` writes its input. Nothing of it is copied here. Without a built QDYN
the rows say so and faultslip is still measured.

**The same input.** ``configs/rsf_block_bp1.toml``: the unregularised aging law (a 0.010, b 0.015,
D_c 8 mm, mu0 0.6, V0 1 um/s), sigma_n 50 MPa, K = G / D = 32 GPa / 20 km, radiation damping
G / (2 c_s), loaded at 1e-9 m/s from steady sliding at 1.01 V_pl. QDYN runs it as its spring-block
(MESHDIM = 0, stiffness MU / L) with RNS_LAW = 0 and THETA_LAW = 1, over the simulated time faultslip
needs for its spin-up, 100 measured cycles and the start of the next.

**Equal accuracy, on one grid.** Each code's recurrence against the converged value (QDYN's
Bulirsch-Stoer at ACC 1e-10; faultslip at rtol 1e-11 agrees with it to 1e-9), each code studied on the same
grid, 1e-2 to 1e-10 (``peer_runs.COMMON_GRID``): QDYN at the loosest ACC whose recurrence is within 1e-6 of
it; faultslip's command at its default (rtol 1e-7, auto's choice; the command takes no tolerance), with the
loosest rtol of its own study shown beside, so that any advantage a looser setting would give it is
stated, not taken.

**Equal work.** faultslip's command prints 100 events' recurrence, slip, stress drop and peak speed;
QDYN's events are found from its time series, so the fair QDYN row writes every step. It is also timed
writing every 1000th step and writing none (its floor), and the ratio is taken against the fastest of
all, the strictest comparison. Every run is a whole process (start-up, input, output) pinned to one
core, timed ``--repeats`` times, interleaved with the order reversed every other round, the medians of
wall time, CPU time and peak memory kept (``peer_runs``).

Writes benchmarks/results/spring_block_qdyn.json; ``python benchmarks/readme.py`` writes the docs' table
``spring_block_qdyn`` from it.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shutil
import statistics
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from fault_2d_qdyn import SOLVERS, _commit, qdyn_available, write_input  # noqa: E402
from peer_runs import COMMON_GRID, interleaved, measured  # noqa: E402
from faultslip.dynamics.rate_state.slider import fault_cycles  # noqa: E402
from faultslip.models.rate_state_slider.scene import read_rate_state_scene  # noqa: E402
from provenance import stamp  # noqa: E402  (one stamp for every results file)

SCENE = ROOT / "configs" / "rsf_block_bp1.toml"
YEAR = 365.25 * 86400.0
EVENT_SPEED = 1e-3  # m/s, faultslip's and SEAS's event threshold
WITHIN = 1e-6  # equal accuracy: recurrence within this of the converged value
CYCLES = 100


def faultslip_command() -> list[str]:
    """The installed program, as a user runs it (the console script beside this Python)."""
    program = Path(sys.executable).with_name("faultslip")
    head = [str(program)] if program.is_file() else [sys.executable, "-m", "faultslip.cli"]
    return head + ["rate-state", "cycles", str(SCENE), "--cycles", str(CYCLES), "--json"]


def _timed(command: list[str], folder: Path | None = None, core: int | None = 0) -> tuple[int, float, str, dict]:
    """Exit status, wall time, standard output and the measurement (wall, CPU, peak memory) of a whole process
    pinned to ``core``; its output goes to a file, as a user's run to a terminal or log would."""
    with tempfile.TemporaryDirectory() as scratch:
        log = Path(scratch) / "log.txt"
        row = measured(command, folder, log, core)
        return row["status"], row["wall_s"], log.read_text(encoding="utf-8", errors="replace"), row


def qdyn_input(qdyn: Path, folder: Path, scene, accuracy: float, solver: int, every: int, span: float) -> None:
    """QDYN's qdyn.in for the scene's spring-block, by QDYN's own writer."""
    sys.path.insert(0, str(qdyn / "src"))
    from pyqdyn import qdyn as QDYN  # QDYN's own input writer, from its checkout (GPL-3, not copied)

    law, fault = scene.law, scene.fault
    folder.mkdir(parents=True, exist_ok=True)
    model = QDYN()
    model.settings({
        "MESHDIM": 0, "N": 1, "L": float(fault["zone_width"]), "MU": float(fault["shear_modulus"]),
        "VS": float(fault["shear_wave_speed"]), "SIGMA": float(fault["normal_stress"]),
        "V_PL": float(scene.plate_rate), "TMAX": span, "ACC": accuracy, "SOLVER": solver,
        "NTOUT_OT": every, "NTOUT": max(every * 1000, 10 ** 8) if every < 10 ** 5 else every, "V_TH": EVENT_SPEED, "DTTRY": 0.1,
        "SET_DICT_RSF": {"RNS_LAW": 0, "THETA_LAW": 1, "A": law.a, "B": law.b, "DC": law.critical_slip,
                         "MU_SS": law.mu0, "V_SS": law.reference_speed, "V_0": 1.01 * scene.plate_rate,
                         "TH_0": law.critical_slip / scene.plate_rate}})
    model.render_mesh()
    write_input(model, folder)


def qdyn_recurrence(folder: Path) -> tuple[float, int]:
    """The last recurrence interval (yr) from QDYN's peak-slip-rate series (every step), and its steps.

    Event starts where ln V rises through ln(1e-3 m/s), linearly interpolated in ln V between steps."""
    series = np.loadtxt(folder / "output_vmax", comments="#", usecols=(0, 2))
    if not np.all(np.isfinite(series[:, 1])):
        return math.nan, series.shape[0] - 1
    log_speed, threshold = np.log(series[:, 1]), math.log(EVENT_SPEED)
    up = np.flatnonzero((log_speed[1:] > threshold) & (log_speed[:-1] <= threshold))
    starts = series[up, 0] + (threshold - log_speed[up]) / (log_speed[up + 1] - log_speed[up]) * (
        series[up + 1, 0] - series[up, 0])
    return (float(np.diff(starts)[-1]) / YEAR if up.size > 1 else math.nan), series.shape[0] - 1


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--qdyn", type=Path, default=os.environ.get("QDYN_DIR"))
    parser.add_argument("--repeats", type=int, default=15)
    parser.add_argument("--accuracies", type=float, nargs="+", default=list(COMMON_GRID),
                        help="the grid every code is studied on (default 1e-2 to 1e-10)")
    args = parser.parse_args(argv)
    qdyn = Path(args.qdyn).expanduser().resolve() if args.qdyn else None
    missing = qdyn_available(qdyn)
    scene = read_rate_state_scene(SCENE)

    # faultslip's answer, at its default and converged, through the library (the timed runs are whole processes)
    ours = fault_cycles(scene.slider, scene.plate_rate, cycles=CYCLES)
    tight = fault_cycles(scene.slider, scene.plate_rate, cycles=5, rtol=1e-11)
    # faultslip's own study on the common grid (through the library: the command takes no tolerance)
    own = []
    for rtol in sorted(args.accuracies, reverse=True):
        try:
            cycle = fault_cycles(scene.slider, scene.plate_rate, cycles=5, rtol=rtol)
            own.append({"rtol": rtol, "recurrence_yr": cycle.recurrence / YEAR,
                        "recurrence_error": abs(cycle.recurrence / tight.recurrence - 1), "steps": cycle.steps})
        except Exception as exc:  # a tolerance the integrator refuses is a row of the study, not a crash
            own.append({"rtol": rtol, "failed": str(exc)[:200]})
    span = (ours.spin_up + CYCLES + 1) * ours.recurrence
    result = {"cycles": CYCLES, "simulated_years": span / YEAR, "qdyn_missing": missing,
              "faultslip": {"integrator": ours.method, "rtol": ours.rtol, "steps": ours.steps,
                            "recurrence_yr": ours.recurrence / YEAR, "converged_recurrence_yr": tight.recurrence / YEAR,
                            "cycles_wall_s": ours.wall_time, "study": own,
                            "loosest_within": max((row["rtol"] for row in own if row.get("recurrence_error", 1) <= WITHIN),
                                                  default=None)},
              "qdyn": {}, **stamp()}
    print(f"faultslip: {ours.method} at rtol {ours.rtol:g}, T = {ours.recurrence / YEAR:.9g} yr "
          f"(rtol 1e-11: {tight.recurrence / YEAR:.9g} yr), {ours.steps} steps, {ours.wall_time * 1e3:.1f} ms in the library")
    work = Path(tempfile.mkdtemp(prefix="faultslip-spring-block-"))
    runs = {"faultslip": (faultslip_command(), None)}
    try:
        if missing is None:
            result["qdyn_commit"] = _commit(qdyn)
            studies = {}
            for solver in (1, 2):
                name = SOLVERS[solver]
                studies[name] = []
                for accuracy in sorted(args.accuracies, reverse=True):
                    folder = work / f"study_{solver}_{accuracy:g}"
                    qdyn_input(qdyn, folder, scene, accuracy, solver, 1, span)
                    status, wall, _, _ = _timed([str(qdyn / "src" / "qdyn")], folder, None)
                    recurrence, steps = qdyn_recurrence(folder)
                    studies[name].append({"accuracy": accuracy, "status": status, "recurrence_yr": recurrence,
                                          "steps": steps})
                    print(f"QDYN {name} ACC {accuracy:g}: T = {recurrence:.9g} yr, {steps} steps")
                    shutil.rmtree(folder)
            converged = studies[SOLVERS[1]][-1]["recurrence_yr"]
            result["converged_recurrence_yr"] = converged
            result["faultslip"]["recurrence_error"] = abs(ours.recurrence / YEAR / converged - 1)
            for name, study in studies.items():
                for row in study:
                    row["recurrence_error"] = abs(row["recurrence_yr"] / converged - 1)
                good = [row["accuracy"] for row in study if row["status"] == 0 and row["recurrence_error"] <= WITHIN]
                setting = max(good) if good else min(row["accuracy"] for row in study)
                result["qdyn"][name] = {"study": study, "accuracy": setting, "timed": {}}
                for every, label in ((1, "every step"), (1000, "every 1000 steps"), (10 ** 8, "none")):
                    folder = work / f"{solver_of(name)}_{every}"
                    qdyn_input(qdyn, folder, scene, setting, solver_of(name), every, span)
                    runs[f"QDYN {name}, time series written: {label}"] = ([str(qdyn / "src" / "qdyn")], folder)
        else:
            print(f"QDYN not run: {missing}")

        def one(name, command, folder):
            def go():
                status, wall, out, row = _timed(command, folder)
                if status != 0:
                    raise SystemExit(f"{name} failed (exit status {status})")
                if name == "faultslip":  # the integrator the command chose, as it reports it
                    result["faultslip"]["command_integrator"] = json.loads(out)["integrator"]
                return row
            return go

        measures = interleaved({name: one(name, *run) for name, run in runs.items()}, args.repeats)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    walls = {name: [row["wall_s"] for row in rows] for name, rows in measures.items()}
    medians = {name: statistics.median(values) for name, values in walls.items()}
    result["wall_s"] = medians
    result["cpu_s"] = {name: statistics.median(row["cpu_s"] for row in rows) for name, rows in measures.items()}
    result["peak_mib"] = {name: statistics.median(row["peak_mib"] for row in rows) for name, rows in measures.items()}
    result["pinned_core"] = 0
    result["wall_s_quartiles"] = {name: [float(q) for q in np.percentile(values, [25, 75])]
                                  for name, values in walls.items()}
    peers = {name: wall for name, wall in medians.items() if name != "faultslip"}
    if peers:
        best = min(peers, key=peers.get)
        result["best_peer"], result["ratio_faultslip_over_best_peer"] = best, medians["faultslip"] / peers[best]
        fair = [name for name in peers if name.endswith("every step")]
        result["fair_peer"] = min(fair, key=peers.get)
        result["ratio_faultslip_over_fair_peer"] = medians["faultslip"] / peers[result["fair_peer"]]
    # where faultslip's whole process goes: the interpreter, numpy, and the rest (imports, scene, report)
    for label, command in (("python", [sys.executable, "-c", "pass"]),
                           ("python + numpy", [sys.executable, "-c", "import numpy"])):
        result.setdefault("startup_s", {})[label] = statistics.median(_timed(command)[1] for _ in range(args.repeats))
    if missing is None:  # QDYN's start-up alone: its RKF45 run over one simulated second
        folder = Path(tempfile.mkdtemp(prefix="faultslip-qdyn-startup-"))
        qdyn_input(qdyn, folder, scene, 1e-5, 2, 10 ** 8, 1.0)
        result["startup_s"]["QDYN, 1 s simulated"] = statistics.median(
            _timed([str(qdyn / "src" / "qdyn")], folder)[1] for _ in range(args.repeats))
        shutil.rmtree(folder, ignore_errors=True)
    for name, wall in medians.items():
        print(f"{name}: {wall * 1e3:.0f} ms")
    if peers:
        print(f"faultslip / {result['best_peer']} = {result['ratio_faultslip_over_best_peer']:.2f}")
    out = ROOT / "benchmarks" / "results" / "spring_block_qdyn.json"
    out.write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")
    print(f"written to {out}; python benchmarks/readme.py writes the docs' table")
    return result


def solver_of(name: str) -> int:
    return next(number for number, label in SOLVERS.items() if label == name)


if __name__ == "__main__":
    main()
