"""SEAS BP1-QD on faultslip and on QDYN, side by side at equal accuracy, as whole processes.

    python benchmarks/fault_2d_qdyn.py --qdyn PATH/TO/qdyn [--elements 512] [--years 3000]

QDYN (github.com/ydluo/qdyn, GPL-3) is the Fortran code this field uses; it is not part of
faultslip and nothing of it is copied here. Build it from its public source (``cd src && make``
with gfortran and OpenMPI from the system packages) and pass the checkout as ``--qdyn`` (or set
QDYN_DIR). Its own Python wrapper, ``src/pyqdyn.py``, imported from that checkout, writes its input.
Without a built QDYN the result says so and the faultslip rows are still measured.

**The same discretised problem.** N elements of W_f / N over BP1's 40 km frictional width (QDYN's
FFT needs N a power of two: 512 gives 78.125 m, 2048 gives 19.53 m). QDYN's FINITE = 3 is a free
surface at the top edge of the first element and steady slip at V_p below W_f, as in faultslip's
model; the regularised aging law, radiation damping eta = G / (2 c_s), and BP1's initial stress and
state, both codes taking a(z) and theta_0(z) at the element centres from faultslip's scene reader.

**Equal work.** Each code writes the twelve BP1 station series at every step. faultslip also writes
its slip profiles (every 5 yr, every 1 s in events) and event catalogue; QDYN writes its peak-slip-
rate series at every step (from which its events are found) and a snapshot of every 16th element
every 1000 steps.

**Equal accuracy, on one grid.** For each code (and each QDYN solver) a tolerance study over
``--tolerance-years`` on the same grid, 1e-2 to 1e-10 (``peer_runs.COMMON_GRID``), so that each code's
loosest passing tolerance is found rather than assumed: the recurrence interval at each tolerance
against that code's tightest settled run. The loosest tolerance within 0.1 % of it is the code's fair
setting. A run that fails (QDYN's Bulirsch-Stoer can return NaN slip rates with exit status 0) is
reported as failed, with why, and never counts. The study's runs may go two at a time
(``--study-workers 2``), each pinned to its own core: they measure accuracy, not speed.

**Equal conditions.** Then BP1 for ``--years`` at each code's setting, every run a whole process
(start-up, input, output) pinned to the same core, interleaved in ``--rounds`` rounds (at least 3) with
the order reversed every other round; the median wall time, CPU time and peak memory of each code
(``peer_runs``).

Recurrence, for both codes by one rule (faultslip's ``summarise``): events start where the peak
slip rate rises through 1e-3 m/s; system-size events slip at the surface at least half the largest;
the recurrence is the last interval between them, and the sequence has settled when the last three
agree to 1e-3.

Writes benchmarks/results/fault_2d_qdyn.json; ``python benchmarks/readme.py`` writes the docs' table
``fault_2d_qdyn`` from it.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import os
import re
import shutil
import subprocess
import sys
import queue
import tempfile
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Callable
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

sys.path.insert(0, str(ROOT / "benchmarks"))

from faultslip.models.fault_2d.integrate import YEAR  # noqa: E402
from faultslip.models.fault_2d.scene import read_fault_2d_scene  # noqa: E402
from peer_runs import COMMON_GRID, interleaved, measured, medians  # noqa: E402
from provenance import stamp  # noqa: E402  (one stamp for every results file)

SCENE = ROOT / "configs" / "seas_bp1.toml"
WIDTH = 40e3
EVENT_SPEED = 1e-3  # m/s: BP1's event threshold on the peak slip rate
SETTLED_INTERVALS = 3
WITHIN = 1e-3  # the equal-accuracy criterion: recurrence within 0.1 % of the code's tightest


def sequence(starts: np.ndarray, surface_slip: np.ndarray) -> dict:
    """Recurrence by faultslip's summarise rule, from event starts (s) and surface slip per event (m)."""
    if starts.size == 0:
        return {"events": 0, "recurrence_yr": math.nan, "spread": math.inf, "settled": False,
                "surface_slip_m": math.nan}
    system = np.flatnonzero(surface_slip >= 0.5 * surface_slip.max())
    intervals = np.diff(starts[system]) / YEAR
    if intervals.size == 0:
        return {"events": int(starts.size), "recurrence_yr": math.nan, "spread": math.inf, "settled": False,
                "surface_slip_m": float(surface_slip[system[-1]])}
    last = intervals[-SETTLED_INTERVALS:]
    spread = float((last.max() - last.min()) / last.mean()) if last.size > 1 else math.inf
    return {"events": int(starts.size), "recurrence_yr": float(intervals[-1]), "spread": spread,
            "settled": bool(intervals.size >= SETTLED_INTERVALS and spread <= 1e-3),
            "surface_slip_m": float(surface_slip[system[-1]])}


@dataclass
class Run:
    """One code's run of BP1, ready to start as a whole process (its input written in ``folder``)."""

    code: str
    solver: str
    tolerance: float
    elements: int
    years: float
    folder: Path
    command: list[str]
    outputs: tuple[str, ...]  # what a run writes, removed before the next run starts afresh
    parse: Callable[[Path, dict], None]

    def label(self) -> dict:
        return {"code": self.code, "solver": self.solver, "tolerance": self.tolerance, "elements": self.elements,
                "years": self.years}

    def __call__(self, core: int | None = 0) -> dict:
        self.clear()
        row = self.label() | measured(self.command, self.folder, self.folder / "log.txt", core)
        if row["status"] != 0:
            row["failed"] = f"exit status {row['status']}: " + (self.folder / "log.txt").read_text(
                encoding="utf-8", errors="replace")[-300:].strip()
        else:
            try:
                self.parse(self.folder, row)
            except (OSError, ValueError, KeyError, IndexError) as error:
                row["failed"] = f"its output could not be read: {error}"
        return row

    def clear(self) -> None:
        for name in self.outputs:
            for path in self.folder.glob(name):
                shutil.rmtree(path) if path.is_dir() else path.unlink()


# --- faultslip ---------------------------------------------------------------------------------


def faultslip_prepare(elements: int, years: float, rtol: float, work: Path) -> Run:
    folder = work / f"faultslip_{elements}_{years:g}_{rtol:g}"
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    text = SCENE.read_text(encoding="utf-8")
    text = re.sub(r'element_size = "[^"]*"', f'element_size = "{WIDTH / elements!r} m"', text)
    text = re.sub(r'duration = "[^"]*"', f'duration = "{years:g} yr"', text)
    text = re.sub(r"rtol = [0-9.e-]+", f"rtol = {rtol:g}", text)
    (folder / "scene.toml").write_text(text, encoding="utf-8")
    command = [sys.executable, "-m", "faultslip.cli", "simulate", "scene.toml", "--output-dir", "out", "--json"]
    return Run("faultslip", "Dormand-Prince 5(4)", rtol, elements, years, folder, command, ("out",),
               _faultslip_parse)


def _faultslip_parse(folder: Path, row: dict) -> None:
    with open(folder / "out" / "events.csv", encoding="utf-8", newline="") as handle:
        events = list(csv.DictReader(handle))
    starts = np.array([float(event["start (s)"]) for event in events])
    surface = np.array([float(event["surface_slip (m)"]) for event in events])
    row.update(sequence(starts, surface))
    log = (folder / "log.txt").read_text(encoding="utf-8")
    report = json.loads(log[log.index("{"):])
    row["steps"] = report.get("steps")
    reported = report.get("recurrence_interval") or {}
    row["reported_recurrence_yr"] = reported["value"] / YEAR if reported.get("value") is not None else None


# --- QDYN --------------------------------------------------------------------------------------

SOLVERS = {1: "Bulirsch-Stoer", 2: "Runge-Kutta-Fehlberg 4(5)"}


def qdyn_available(qdyn: Path | None) -> str | None:
    """None if a built QDYN is at ``qdyn``, else the reason it is not."""
    if qdyn is None:
        return "no QDYN checkout given (--qdyn or QDYN_DIR)"
    if not (qdyn / "src" / "pyqdyn.py").is_file():
        return f"{qdyn} is not a QDYN checkout (no src/pyqdyn.py)"
    if not os.access(qdyn / "src" / "qdyn", os.X_OK):
        return f"QDYN is not built in {qdyn} (no src/qdyn: run make in src/ with gfortran and OpenMPI)"
    return None


def write_input(model, folder: Path) -> None:
    """QDYN's own writer puts qdyn.in in the working folder: run it in ``folder`` (main thread only)."""
    here = os.getcwd()
    try:
        os.chdir(folder)
        model.write_input()
    finally:
        os.chdir(here)


def qdyn_prepare(qdyn: Path, elements: int, years: float, accuracy: float, solver: int, work: Path) -> Run:
    folder = work / f"qdyn_{elements}_{years:g}_{accuracy:g}_{solver}"
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    scene = read_fault_2d_scene(SCENE).at_element_size(WIDTH / elements)
    fault = scene.fault
    sys.path.insert(0, str(qdyn / "src"))
    from pyqdyn import qdyn as QDYN  # QDYN's own input writer, from its checkout (GPL-3, not copied)

    model = QDYN()
    model.settings({
        "MESHDIM": 1, "FINITE": 3, "N": elements, "L": WIDTH, "VS": float(fault.shear_wave_speed),
        "MU": float(fault.shear_modulus), "SIGMA": float(fault.normal_stress[0]), "V_PL": float(fault.plate_rate),
        "TMAX": years * YEAR, "ACC": accuracy, "SOLVER": solver, "NTOUT_OT": 1, "NTOUT": 1000, "NXOUT": 16,
        "IC": 0, "V_TH": EVENT_SPEED, "DTTRY": 0.1,
        "SET_DICT_RSF": {"RNS_LAW": 2, "THETA_LAW": 1, "B": float(fault.b[0]), "DC": float(fault.critical_slip[0]),
                         "MU_SS": float(fault.reference_friction), "V_SS": float(fault.reference_speed),
                         "V_0": float(scene.settings["initial_speed"]) if "initial_speed" in scene.settings
                         else float(fault.plate_rate)}})
    model.render_mesh()
    model.mesh_dict["A"] = np.asarray(fault.a, float).copy()
    model.mesh_dict["TH_0"] = np.asarray(fault.state_to_theta(fault.initial_state), float).copy()
    iot = np.zeros(elements)
    stations = np.unique(np.clip(np.floor(np.asarray(scene.stations, float) / (WIDTH / elements)).astype(int),
                                 0, elements - 1))
    iot[stations] = 1
    model.mesh_dict["IOT"] = iot
    write_input(model, folder)

    def parse(folder: Path, row: dict) -> None:
        _qdyn_parse(folder, row, int(stations[0]))

    return Run("QDYN", SOLVERS[solver], accuracy, elements, years, folder, [str(qdyn / "src" / "qdyn")],
               ("output_*", "fort.*"), parse)


def _qdyn_parse(folder: Path, row: dict, surface_station: int) -> None:
    vmax = np.loadtxt(folder / "output_vmax", comments="#", usecols=(0, 2), ndmin=2)
    surface = np.loadtxt(folder / f"output_ot_{surface_station}", comments="#", usecols=(0, 7), ndmin=2)
    row["steps"] = int(vmax.shape[0] - 1)
    reached = float(vmax[-1, 0]) / YEAR
    if not np.all(np.isfinite(vmax[:, 1])) or reached < row["years"] * (1 - 1e-6):
        bad = np.flatnonzero(~np.isfinite(vmax[:, 1]))
        row["failed"] = "exit status 0, but " + (f"NaN slip rates from t = {vmax[bad[0], 0] / YEAR:.2f} yr"
                                                 if bad.size else f"stopped at {reached:.2f} yr")
        return
    fast = vmax[:, 1] >= EVENT_SPEED
    rises = np.flatnonzero(fast[1:] & ~fast[:-1]) + 1
    falls = np.flatnonzero(~fast[1:] & fast[:-1]) + 1
    falls = np.array([falls[falls > r][0] if np.any(falls > r) else fast.size - 1 for r in rises], int)
    starts = vmax[rises, 0]
    slip_at = np.interp(np.concatenate([vmax[rises, 0], vmax[falls, 0]]), surface[:, 0], surface[:, 1])
    row.update(sequence(starts, slip_at[rises.size:] - slip_at[:rises.size]))


# --- the study ---------------------------------------------------------------------------------


def loosest(rows: list[dict]) -> tuple[float | None, list[dict]]:
    """The loosest tolerance whose recurrence is within 0.1 % of the tightest successful, settled run's."""
    good = [row for row in rows if "failed" not in row and row.get("settled")]
    if not good:
        return None, rows
    reference = min(good, key=lambda row: row["tolerance"])
    for row in good:
        row["recurrence_error"] = abs(row["recurrence_yr"] / reference["recurrence_yr"] - 1)
    within = [row["tolerance"] for row in good if row["recurrence_error"] <= WITHIN and row is not reference]
    return (max(within) if within else reference["tolerance"]), rows


def _say(row: dict) -> None:
    cost = f"{row['wall_s']:.1f} s wall, {row['cpu_s']:.1f} s CPU, {row['peak_mib']:.0f} MiB"
    if "failed" in row:
        print(f"  {row['code']} {row['solver']} {row['tolerance']:g}, {row['years']:g} yr: FAILED ({row['failed']}), "
              f"{cost}", flush=True)
    else:
        print(f"  {row['code']} {row['solver']} {row['tolerance']:g}, {row['years']:g} yr: T {row['recurrence_yr']:.6g} "
              f"yr (settled {row['settled']}), surface slip {row['surface_slip_m']:.5g} m, {row.get('steps')} steps, "
              f"{cost}", flush=True)


def run_study(runs: list[Run], workers: int) -> list[dict]:
    """Every run once, ``workers`` at a time, each pinned to a core of its own; rows in the runs' order."""
    cores: queue.Queue = queue.Queue()
    for core in sorted(os.sched_getaffinity(0))[:max(1, workers)]:
        cores.put(core)

    def one(run: Run) -> dict:
        core = cores.get()
        try:
            row = run(core)
        finally:
            cores.put(core)
        run.clear()  # QDYN's series at every step run to gigabytes at 1e-10
        _say(row)
        return row

    with ThreadPoolExecutor(max_workers=max(1, workers)) as pool:
        return list(pool.map(one, runs))


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--qdyn", type=Path, default=os.environ.get("QDYN_DIR"))
    parser.add_argument("--elements", type=int, default=1024, help="a power of two (QDYN's FFT): 1024 is 39 m")
    parser.add_argument("--years", type=float, default=3000.0)
    parser.add_argument("--tolerance-years", type=float, default=1000.0)
    parser.add_argument("--tolerances", type=float, nargs="+", default=list(COMMON_GRID),
                        help="the grid every code is studied on (default 1e-2 to 1e-10)")
    parser.add_argument("--solvers", type=int, nargs="+", default=[2, 1], help="QDYN solvers: 1 BS, 2 RKF45")
    parser.add_argument("--study-workers", type=int, default=1,
                        help="tolerance-study runs at a time, each pinned to its own core")
    parser.add_argument("--rounds", type=int, default=3, help="interleaved timing rounds (at least 3)")
    parser.add_argument("--core", type=int, default=0, help="the core every timed run is pinned to")
    parser.add_argument("--from-study", action="store_true",
                        help="reuse the tolerance studies saved by the last run (results/fault_2d_qdyn_study.json) "
                             "and time the runs again")
    parser.add_argument("--study-only", action="store_true", help="run and save the tolerance studies, time nothing")
    parser.add_argument("--restudy", nargs="+", default=[], metavar="CODE",
                        help="run these codes' tolerance studies again (faultslip, or a QDYN solver's name as saved) "
                             "and keep the others' saved ones")
    parser.add_argument("--memory-years", type=float, default=300.0,
                        help="each code once over this span too: its peak memory beside the long run's")
    args = parser.parse_args(argv)
    if args.elements < 2 or args.elements & (args.elements - 1):
        parser.error(f"--elements must be a power of two (QDYN's FFT), got {args.elements}")
    if args.rounds < 3:
        parser.error(f"--rounds must be at least 3 (a median of fewer says little), got {args.rounds}")
    qdyn = Path(args.qdyn).expanduser().resolve() if args.qdyn else None
    missing = qdyn_available(qdyn)
    work = Path(tempfile.mkdtemp(prefix="faultslip-qdyn-"))
    saved = ROOT / "benchmarks" / "results" / "fault_2d_qdyn_study.json"
    try:
        if args.from_study or args.restudy:
            codes = json.loads(saved.read_text(encoding="utf-8"))
            print(f"tolerance studies from {saved}")
            if args.restudy:
                unknown = sorted(set(args.restudy) - set(codes))
                if unknown:
                    parser.error(f"--restudy: no saved study of {', '.join(unknown)} (saved: {', '.join(codes)})")
                codes.update(_studies(args, qdyn, missing, work, only=set(args.restudy)))
                saved.write_text(json.dumps(codes, indent=1) + "\n", encoding="utf-8")
        else:
            codes = _studies(args, qdyn, missing, work)
            saved.write_text(json.dumps(codes, indent=1) + "\n", encoding="utf-8")
        if args.study_only:
            return codes
        timed = {}
        for name, code in codes.items():
            code["setting"], code["study"] = loosest(code["study"])
            if code["setting"] is None:
                print(f"  {name}: no tolerance gave a settled sequence; not timed")
            elif name == "faultslip":
                timed[name] = faultslip_prepare(args.elements, args.years, code["setting"], work)
            elif missing is None:
                solver = next(k for k, v in SOLVERS.items() if name.endswith(v))
                timed[name] = qdyn_prepare(qdyn, args.elements, args.years, code["setting"], solver, work)
        print(f"BP1 for {args.years:g} yr at each code's loosest tolerance within 0.1 %, pinned to core {args.core}, "
              f"{args.rounds} interleaved rounds:")

        def measure(run):
            def go():
                row = run(args.core)
                run.clear()
                _say(row)
                return row
            return go

        rounds = interleaved({name: measure(run) for name, run in timed.items()}, args.rounds)
        # memory flat in duration (issue 43, item 4): each code once over a tenth of the span, on the same core
        print(f"each code once over {args.memory_years:g} yr, for its peak memory:")
        short = {}
        for name, run in timed.items():
            again = (faultslip_prepare(args.elements, args.memory_years, run.tolerance, work) if name == "faultslip"
                     else qdyn_prepare(qdyn, args.elements, args.memory_years, run.tolerance,
                                       next(k for k, v in SOLVERS.items() if name.endswith(v)), work))
            short[name] = measure(again)()
    finally:
        shutil.rmtree(work, ignore_errors=True)
    for name, rows in rounds.items():
        failed = [row for row in rows if "failed" in row]
        codes[name]["timed"] = rows[-1] | ({"failed": failed[0]["failed"]} if failed else medians(rows))
        if not failed and "failed" not in short[name]:
            codes[name]["memory"] = {"short_years": args.memory_years, "short_peak_mib": short[name]["peak_mib"],
                                     "long_years": args.years, "long_peak_mib": codes[name]["timed"]["peak_mib"],
                                     "growth": codes[name]["timed"]["peak_mib"] / short[name]["peak_mib"] - 1}
    ours = codes["faultslip"].get("timed")
    peers = {name: code["timed"] for name, code in codes.items() if name != "faultslip" and code.get("timed")
             and "failed" not in code["timed"]}
    best = min(peers.items(), key=lambda item: item[1]["wall_s"]) if peers else None
    good = best and ours and "failed" not in ours
    result = {"elements": args.elements, "element_size_m": WIDTH / args.elements, "years": args.years,
              "tolerance_years": args.tolerance_years, "tolerance_grid": sorted(args.tolerances, reverse=True),
              "rounds": args.rounds, "pinned_core": args.core, "codes": codes, "qdyn_missing": missing,
              "qdyn_commit": _commit(qdyn) if missing is None else None,
              "best_peer": best[0] if best else None,
              "ratio_faultslip_over_best_peer": ours["wall_s"] / best[1]["wall_s"] if good else None,
              "cpu_ratio_faultslip_over_best_peer": ours["cpu_s"] / best[1]["cpu_s"] if good else None,
              **stamp()}
    out = ROOT / "benchmarks" / "results" / "fault_2d_qdyn.json"
    out.write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")
    print(f"written to {out}" + (f"; faultslip / {best[0]} = {result['ratio_faultslip_over_best_peer']:.2f} "
                                 f"(CPU {result['cpu_ratio_faultslip_over_best_peer']:.2f})" if good else "")
          + "; python benchmarks/readme.py writes the docs' table")
    return result


def _studies(args, qdyn, missing, work, only: set | None = None) -> dict:
    """Each code's tolerance study over --tolerance-years on the common grid (only those in ``only``, if given)."""
    grid = sorted(args.tolerances, reverse=True)
    names = {}
    if only is None or "faultslip" in only:
        names["faultslip"] = [faultslip_prepare(args.elements, args.tolerance_years, rtol, work) for rtol in grid]
    if missing is None:
        for solver in args.solvers:
            name = f"QDYN {SOLVERS[solver]}"
            if only is None or name in only:
                names[name] = [qdyn_prepare(qdyn, args.elements, args.tolerance_years, accuracy, solver, work)
                               for accuracy in grid]
    else:
        print(f"QDYN not run: {missing}")
    print(f"tolerance studies, {args.elements} elements, {args.tolerance_years:g} yr, grid {grid[0]:g} to {grid[-1]:g}:")
    # the slowest (tightest) runs first, so that two workers finish together
    order = sorted(((name, run) for name, runs in names.items() for run in runs), key=lambda item: item[1].tolerance)
    rows = run_study([run for _, run in order], args.study_workers)
    codes = {name: {"study": [], "setting": None, "timed": None} for name in names}
    for (name, _), row in zip(order, rows):
        codes[name]["study"].append(row)
    for code in codes.values():
        code["study"].sort(key=lambda row: -row["tolerance"])
    return codes


def _commit(qdyn: Path) -> str | None:
    """The QDYN commit: its checkout's HEAD, or QDYN_COMMIT for a tree exported without git."""
    try:
        return subprocess.run(["git", "-C", str(qdyn), "rev-parse", "HEAD"], capture_output=True, text=True,
                              check=True).stdout.strip() or None
    except (OSError, subprocess.CalledProcessError):
        return os.environ.get("QDYN_COMMIT")


if __name__ == "__main__":
    main()
