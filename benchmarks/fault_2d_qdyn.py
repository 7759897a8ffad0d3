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

**Equal accuracy.** For each code (and each QDYN solver) a tolerance study over
``--tolerance-years``: the recurrence interval at each tolerance against that code's tightest. The
loosest tolerance within 0.1 % of it is the code's fair setting (issue 33). Then BP1 for ``--years``
at that setting, each code timed as a whole process (start-up, input, output), one after the other
in this run. A run that fails (QDYN's Bulirsch-Stoer can return NaN slip rates with exit status 0)
is reported as failed, with why, and is never timed as a result.

Recurrence, for both codes by one rule (faultslip's ``summarise``): events start where the peak
slip rate rises through 1e-3 m/s; system-size events slip at the surface at least half the largest;
the recurrence is the last interval between them, and the sequence has settled when the last three
agree to 1e-3.

Writes benchmarks/results/fault_2d_qdyn.json and the README's table ``fault_2d_qdyn``.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import os
import platform
import re
import shutil
import subprocess
import sys
import tempfile
import time
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from faultslip.models.fault_2d.integrate import YEAR  # noqa: E402
from faultslip.models.fault_2d.scene import load_fault_2d_scene  # noqa: E402

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


def _timed(command: list[str], folder: Path, log: Path) -> tuple[int, float]:
    start = time.perf_counter()
    with open(log, "w", encoding="utf-8") as out:
        status = subprocess.call(command, cwd=folder, stdout=out, stderr=subprocess.STDOUT)
    return status, time.perf_counter() - start


# --- faultslip ---------------------------------------------------------------------------------


def faultslip_run(elements: int, years: float, rtol: float, work: Path) -> dict:
    folder = work / f"faultslip_{elements}_{years:g}_{rtol:g}"
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    text = SCENE.read_text(encoding="utf-8")
    text = re.sub(r'element_size = "[^"]*"', f'element_size = "{WIDTH / elements!r} m"', text)
    text = re.sub(r'duration = "[^"]*"', f'duration = "{years:g} yr"', text)
    text = re.sub(r"rtol = [0-9.e-]+", f"rtol = {rtol:g}", text)
    (folder / "scene.toml").write_text(text, encoding="utf-8")
    command = [sys.executable, "-m", "faultslip.cli", "simulate", "scene.toml", "--output-dir", "out", "--json"]
    status, wall = _timed(command, folder, folder / "log.txt")
    row = {"code": "faultslip", "solver": "Dormand-Prince 5(4)", "tolerance": rtol, "elements": elements,
           "years": years, "wall_s": wall, "status": status}
    if status != 0:
        row["failed"] = (folder / "log.txt").read_text(encoding="utf-8")[-400:].strip()
        return row
    with open(folder / "out" / "events.csv", encoding="utf-8", newline="") as handle:
        events = list(csv.DictReader(handle))
    starts = np.array([float(event["start (s)"]) for event in events])
    surface = np.array([float(event["surface_slip (m)"]) for event in events])
    row.update(sequence(starts, surface))
    log = (folder / "log.txt").read_text(encoding="utf-8")
    report = json.loads(log[log.index("{"):])
    row["steps"] = report.get("steps")
    row["reported_recurrence_yr"] = report["recurrence_interval"]["value"] / YEAR if report.get(
        "recurrence_interval") and report["recurrence_interval"]["value"] is not None else None
    return row


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
    """QDYN's own writer puts qdyn.in in the working folder: run it in ``folder``."""
    here = os.getcwd()
    try:
        os.chdir(folder)
        model.write_input()
    finally:
        os.chdir(here)


def qdyn_run(qdyn: Path, elements: int, years: float, accuracy: float, solver: int, work: Path) -> dict:
    folder = work / f"qdyn_{elements}_{years:g}_{accuracy:g}_{solver}"
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    scene = load_fault_2d_scene(SCENE).at_element_size(WIDTH / elements)
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
    status, wall = _timed([str(qdyn / "src" / "qdyn")], folder, folder / "log.txt")
    row = {"code": "QDYN", "solver": SOLVERS[solver], "tolerance": accuracy, "elements": elements, "years": years,
           "wall_s": wall, "status": status}
    vmax = np.loadtxt(folder / "output_vmax", comments="#", usecols=(0, 2))
    surface = np.loadtxt(folder / f"output_ot_{stations[0]}", comments="#", usecols=(0, 7))
    row["steps"] = int(vmax.shape[0] - 1)
    reached = float(vmax[-1, 0]) / YEAR
    if status != 0 or not np.all(np.isfinite(vmax[:, 1])) or reached < years * (1 - 1e-6):
        bad = np.flatnonzero(~np.isfinite(vmax[:, 1]))
        row["failed"] = (f"exit status {status}; " if status else "exit status 0, but ") + (
            f"NaN slip rates from t = {vmax[bad[0], 0] / YEAR:.2f} yr" if bad.size else
            f"stopped at {reached:.2f} yr")
        return row
    fast = vmax[:, 1] >= EVENT_SPEED
    rises = np.flatnonzero(fast[1:] & ~fast[:-1]) + 1
    falls = np.flatnonzero(~fast[1:] & fast[:-1]) + 1
    falls = np.array([falls[falls > r][0] if np.any(falls > r) else fast.size - 1 for r in rises], int)
    starts = vmax[rises, 0]
    slip_at = np.interp(np.concatenate([vmax[rises, 0], vmax[falls, 0]]), surface[:, 0], surface[:, 1])
    surface_slip = slip_at[rises.size:] - slip_at[:rises.size]
    row.update(sequence(starts, surface_slip))
    return row


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
    if "failed" in row:
        print(f"  {row['code']} {row['solver']} {row['tolerance']:g}, {row['years']:g} yr: FAILED ({row['failed']}), "
              f"{row['wall_s']:.1f} s", flush=True)
    else:
        print(f"  {row['code']} {row['solver']} {row['tolerance']:g}, {row['years']:g} yr: T {row['recurrence_yr']:.6g} yr "
              f"(settled {row['settled']}), surface slip {row['surface_slip_m']:.5g} m, {row.get('steps')} steps, "
              f"{row['wall_s']:.1f} s", flush=True)


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--qdyn", type=Path, default=os.environ.get("QDYN_DIR"))
    parser.add_argument("--elements", type=int, default=1024, help="a power of two (QDYN's FFT): 1024 is 39 m")
    parser.add_argument("--years", type=float, default=3000.0)
    parser.add_argument("--tolerance-years", type=float, default=1000.0)
    parser.add_argument("--rtols", type=float, nargs="+", default=[1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9])
    parser.add_argument("--accuracies", type=float, nargs="+", default=[1e-6, 1e-7, 1e-8, 1e-9, 1e-10])
    parser.add_argument("--solvers", type=int, nargs="+", default=[2, 1], help="QDYN solvers: 1 BS, 2 RKF45")
    parser.add_argument("--from-study", action="store_true",
                        help="reuse the tolerance studies saved by the last run (results/fault_2d_qdyn_study.json) "
                             "and time the 3000-yr runs again")
    args = parser.parse_args(argv)
    if args.elements < 2 or args.elements & (args.elements - 1):
        parser.error(f"--elements must be a power of two (QDYN's FFT), got {args.elements}")
    qdyn = Path(args.qdyn).expanduser().resolve() if args.qdyn else None
    missing = qdyn_available(qdyn)
    work = Path(tempfile.mkdtemp(prefix="faultslip-qdyn-"))
    codes = {"faultslip": {"study": [], "setting": None, "timed": None}}
    saved = ROOT / "benchmarks" / "results" / "fault_2d_qdyn_study.json"
    try:
        if args.from_study:
            codes = json.loads(saved.read_text(encoding="utf-8"))
            print(f"tolerance studies from {saved}")
        else:
            _studies(args, codes, qdyn, missing, work)
            saved.write_text(json.dumps(codes, indent=1) + "\n", encoding="utf-8")
        print(f"BP1 for {args.years:g} yr at each code's loosest tolerance within 0.1 %, one after the other:")
        for name, code in codes.items():
            code["setting"], code["study"] = loosest(code["study"])
            if code["setting"] is None:
                print(f"  {name}: no tolerance gave a settled sequence; not timed")
                continue
            if name == "faultslip":
                code["timed"] = faultslip_run(args.elements, args.years, code["setting"], work)
            else:
                solver = next(k for k, v in SOLVERS.items() if name.endswith(v))
                code["timed"] = qdyn_run(qdyn, args.elements, args.years, code["setting"], solver, work)
            _say(code["timed"])
    finally:
        shutil.rmtree(work, ignore_errors=True)
    ours = codes["faultslip"]["timed"]
    peers = {name: code["timed"] for name, code in codes.items() if name != "faultslip" and code["timed"]
             and "failed" not in code["timed"]}
    best = min(peers.items(), key=lambda item: item[1]["wall_s"]) if peers else None
    ratio = ours["wall_s"] / best[1]["wall_s"] if best and ours and "failed" not in ours else None
    result = {"elements": args.elements, "element_size_m": WIDTH / args.elements, "years": args.years,
              "tolerance_years": args.tolerance_years, "codes": codes, "qdyn_missing": missing,
              "qdyn_commit": _commit(qdyn) if missing is None else None,
              "best_peer": best[0] if best else None, "ratio_faultslip_over_best_peer": ratio,
              "machine": f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}",
              "date": datetime.now(timezone.utc).strftime("%Y-%m-%d")}
    out = ROOT / "benchmarks" / "results" / "fault_2d_qdyn.json"
    out.write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")
    print(f"written to {out}" + (f"; faultslip / {best[0]} = {ratio:.2f}" if ratio else ""))
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    import readme

    readme.update()
    return result


def _studies(args, codes, qdyn, missing, work) -> None:
    """Each code's tolerance study over --tolerance-years, into ``codes``."""
    print(f"faultslip tolerance study, {args.elements} elements, {args.tolerance_years:g} yr:")
    for rtol in sorted(args.rtols, reverse=True):
        codes["faultslip"]["study"].append(faultslip_run(args.elements, args.tolerance_years, rtol, work))
        _say(codes["faultslip"]["study"][-1])
    if missing is not None:
        print(f"QDYN not run: {missing}")
        return
    for solver in args.solvers:
        name = f"QDYN {SOLVERS[solver]}"
        codes[name] = {"study": [], "setting": None, "timed": None}
        print(f"{name} tolerance study:")
        for accuracy in sorted(args.accuracies, reverse=True):
            codes[name]["study"].append(qdyn_run(qdyn, args.elements, args.tolerance_years, accuracy, solver, work))
            _say(codes[name]["study"][-1])


def _commit(qdyn: Path) -> str | None:
    """The QDYN commit: its checkout's HEAD, or QDYN_COMMIT for a tree exported without git."""
    try:
        return subprocess.run(["git", "-C", str(qdyn), "rev-parse", "HEAD"], capture_output=True, text=True,
                              check=True).stdout.strip() or None
    except (OSError, subprocess.CalledProcessError):
        return os.environ.get("QDYN_COMMIT")


if __name__ == "__main__":
    main()
