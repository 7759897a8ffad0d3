"""The OpenQuake engine on faultslip's three source models at one site: per segment, time-dependent, rupture set.

    python benchmarks/engine_branches.py [--site "-120.43 35.87"]

Each branch is written by ``faultslip map`` and computed by the engine's classical calculator (``oq engine --run``,
PGA, the job faultslip writes), here in turn:

- **per segment** (configs/san_andreas_map.toml): each segment's characteristic events, Poisson;
- **time-dependent** (the same map, ``--time-dependent`` with the segments' last ruptures, forecast from 2026
  over 30 yr): each segment's BPT probability in the window, given the time since its last rupture;
- **fault system** (configs/california_fault_system.toml, ``--engine-job`` with its logic tree's two branches
  computed apart): the map's own per-segment branch, and the rupture set's multi-section ruptures.

The engine's probabilities of exceedance in each job's investigation time T are turned into equivalent annual
rates, -ln(1 - PoE) / T, so that the branches compare. Writes benchmarks/results/engine_branches.json; needs the
``hazard`` extra (``oq`` beside this Python).
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
from xml.etree import ElementTree
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
from provenance import stamp  # noqa: E402  (one stamp for every results file)

LAST = ("north_coast=1906.3; peninsula=1906.3; santa_cruz_mountains=1989.8; parkfield=2004.74; carrizo=1857.02; "
        "mojave=1857.02; san_bernardino=1812.9; coachella=1690; hayward=1868.8")


def faultslip(*arguments, folder: Path) -> None:
    done = subprocess.run([sys.executable, "-m", "faultslip.cli", *map(str, arguments)], cwd=folder, capture_output=True,
                          text=True)
    if done.returncode != 0:
        raise SystemExit(f"faultslip {' '.join(map(str, arguments))} failed: {done.stderr[-1000:]}")


def engine(job: Path) -> dict:
    """Run ``job``; per realization (or the mean), the PGA levels and their probabilities of exceedance."""
    oq = shutil.which("oq", path=os.path.dirname(sys.executable)) or shutil.which("oq")
    if oq is None:
        raise SystemExit("the OpenQuake engine's 'oq' is not installed: pip install 'faultslip[hazard]'")
    environment = dict(os.environ, OQ_DATADIR=str(job.parent / "oqdata"), OQ_DISTRIBUTE="no")
    done = subprocess.run([oq, "engine", "--run", str(job), "--exports", "csv"], capture_output=True, text=True,
                          env=environment)
    if done.returncode != 0:
        raise SystemExit(f"the engine failed on {job.name}: {done.stdout[-1500:]}{done.stderr[-1500:]}")
    curves = {}
    for path in sorted(job.parent.glob("hazard_curve-*-PGA*.csv")):
        with path.open(encoding="utf-8") as stream:
            rows = [row for row in csv.reader(stream) if row and not row[0].startswith("#")]
        header, values = rows[0], rows[1]
        levels = [float(name.split("-")[1]) for name in header if name.startswith("poe-")]
        poes = [float(value) for name, value in zip(header, values) if name.startswith("poe-")]
        curves[path.name.split("-")[2].split("_")[0] if "rlz" in path.name else "mean"] = {"levels": levels,
                                                                                           "poes": poes}
    return curves


def investigation_time(job: Path) -> float:
    for line in job.read_text(encoding="utf-8").splitlines():
        if line.startswith("investigation_time"):
            return float(line.split("=")[1])
    raise SystemExit(f"{job} states no investigation time")


def annual(poes: list, years: float) -> list:
    return [-math.log1p(-min(p, 1 - 1e-16)) / years for p in poes]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--site", default="-120.43 35.87", help="'lon lat' in degrees")
    parser.add_argument("--out", type=Path, default=HERE / "results" / "engine_branches.json")
    args = parser.parse_args(argv)
    branches = {}
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch)
        faultslip("map", ROOT / "configs" / "san_andreas_map.toml", "-o", "seg.nc", "--engine-job", "seg.ini",
                  "--nrml", "seg.xml", "--sites", args.site, folder=folder)
        (folder / "td").mkdir()
        faultslip("map", ROOT / "configs" / "san_andreas_map.toml", "-o", "td/td.nc", "--time-dependent", "td/td.xml",
                  "--last-ruptures", LAST, "--forecast-year", "2026", "--investigation-time", "30 yr",
                  "--engine-job", "td/td.ini", "--sites", args.site, folder=folder)
        (folder / "system").mkdir()
        faultslip("map", ROOT / "configs" / "california_fault_system.toml", "-o", "system/s.nc", "--nrml",
                  "system/s.xml", "--engine-job", "system/s.ini", "--sites", args.site, folder=folder)
        job = folder / "system" / "s.ini"  # both branches' curves, not only their weighted mean
        job.write_text(job.read_text(encoding="utf-8").replace("[calculation]", "[calculation]\nindividual_curves = true"),
                       encoding="utf-8")
        for name, job in (("per_segment", folder / "seg.ini"), ("time_dependent", folder / "td" / "td.ini"),
                          ("system", folder / "system" / "s.ini")):
            years = investigation_time(job)
            curves = engine(job)
            for key, curve in curves.items():
                label = name if key == "mean" and name != "system" else (f"{name}_{key}" if name == "system" else name)
                branches[label] = {"investigation_time_yr": years, "levels_g": curve["levels"], "poe": curve["poes"],
                                   "annual_rate": annual(curve["poes"], years)}
                print(f"{label}: annual rate of PGA > {curve['levels'][4]:g} g = "
                      f"{branches[label]['annual_rate'][4]:.3g} /yr", flush=True)
        # the engine names a realization by its branches' letters in the source-model logic tree's order
        tree = ElementTree.parse(folder / "system" / "s.xml")  # --nrml FILE is the logic tree itself here
        ids = [branch.get("branchID") for branch in tree.iter() if branch.tag.endswith("logicTreeBranch")]
        paths = {}
        for path in (folder / "system").glob("realizations_*.csv"):
            with path.open(encoding="utf-8") as stream:
                for row in csv.DictReader(row for row in stream if not row.startswith("#")):
                    letter = row["branch_path"].split("~")[0]
                    paths[f"{int(row['rlz_id']):03d}"] = ids[ord(letter) - ord("A")]
        for key, branch in paths.items():
            branches[f"system: {branch}"] = branches.pop(f"system_{key}")
        branches["system: weighted mean"] = branches.pop("system_mean")
    args.out.write_text(json.dumps({"site": args.site, "branches": branches, **stamp()}, indent=1) + "\n",
                        encoding="utf-8")
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
