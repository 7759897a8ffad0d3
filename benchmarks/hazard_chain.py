"""Lab friction to hazard curves, end to end: faultslip's map -> moment-balanced NRML -> OpenQuake.

For each magnitude-frequency distribution (characteristic, truncated_gr, single_bin) this runs

    faultslip map configs/california_faults_map.toml --nrml ... --scaling-relations faultslip,WC1994,Leonard2010
        --mfd KIND --engine-job job.ini --sites "..."
    oq engine --run job.ini --exports csv

and draws the mean hazard curves (probability of exceeding PGA in 50 years, BooreEtAl2014, Vs30 760 m/s)
at four Californian sites, with the MFDs of one segment beside them: docs/figures/hazard_curves.png, and
the curves and the PGA at 10 % in 50 years in benchmarks/results/hazard_chain.json.

Needs the engine: pip install '.[hazard]' (docs/hazard.md). About 3 minutes on 2 cores.

    python benchmarks/hazard_chain.py [--sites "lon lat; ..."]
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from provenance import stamp  # noqa: E402  (one stamp for every results file)

ROOT = Path(__file__).resolve().parent.parent
SITES = {"San Francisco": (-122.42, 37.77), "Parkfield": (-120.43, 35.87), "Los Angeles": (-118.24, 34.05),
         "San Bernardino": (-117.29, 34.11)}
KINDS = ("characteristic", "truncated_gr", "single_bin")
SEGMENT = "SA-CAR"


def _read_curves(folder: Path):
    (path,) = folder.glob("hazard_curve-mean-PGA*.csv")
    lines = path.read_text().splitlines()
    header = lines[1].split(",")
    levels = np.array([float(name.removeprefix("poe-")) for name in header[3:]])
    rows = [[float(v) for v in line.split(",")] for line in lines[2:] if line.strip()]
    return levels, {(row[0], row[1]): np.array(row[3:]) for row in rows}


def _level_at(levels, poes, target=0.1):
    """PGA (g) exceeded with probability ``target``, log-log interpolated; NaN off the curve."""
    inside = poes > 0
    if not inside.any() or poes[0] < target or poes[inside][-1] > target:
        return float("nan")
    return float(np.exp(np.interp(np.log(target), np.log(poes[inside][::-1]), np.log(levels[inside][::-1]))))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--figure", default=str(ROOT / "docs" / "figures" / "hazard_curves.png"))
    parser.add_argument("--results", default=str(ROOT / "benchmarks" / "results" / "hazard_chain.json"))
    parser.add_argument("--replot", action="store_true", help="redraw the figure from the saved results only")
    args = parser.parse_args(argv)
    if args.replot:
        _figure(json.loads(Path(args.results).read_text()), args.figure)
        return 0
    oq = shutil.which("oq", path=os.path.dirname(sys.executable)) or shutil.which("oq")
    if oq is None:
        print("the OpenQuake engine is not installed: pip install '.[hazard]'", file=sys.stderr)
        return 2
    sites = "; ".join(f"{lon} {lat}" for lon, lat in SITES.values())
    results = {"sites": SITES, "kinds": {}}
    with tempfile.TemporaryDirectory() as scratch:
        scratch = Path(scratch)
        for kind in KINDS:
            folder = scratch / kind
            folder.mkdir()
            started = time.perf_counter()
            mapped = subprocess.run([sys.executable, "-m", "faultslip.cli", "map",
                                     str(ROOT / "configs" / "california_faults_map.toml"), "-o", str(folder / "m.nc"),
                                     "--nrml", str(folder / "sources.xml"), "--mfd", kind, "--scaling-relations",
                                     "faultslip,WC1994,Leonard2010", "--engine-job", str(folder / "job.ini"),
                                     "--sites", sites, "--json"], capture_output=True, text=True, check=True)
            summary = json.loads(mapped.stdout)
            environment = dict(os.environ, OQ_DATADIR=str(folder / "oqdata"))
            subprocess.run([oq, "engine", "--run", str(folder / "job.ini"), "--exports", "csv"], capture_output=True,
                           text=True, check=True, env=environment)
            levels, curves = _read_curves(folder)
            source = next(s for s in summary["hazard"]["sources"] if s["id"] == SEGMENT)
            results["kinds"][kind] = {
                "seconds": time.perf_counter() - started, "levels_g": levels.tolist(),
                "curves": {name: curves[min(curves, key=lambda key: abs(key[0] - lon) + abs(key[1] - lat))].tolist()
                           for name, (lon, lat) in SITES.items()},
                "mfd": {relation: source["mfd"][relation] for relation in source["mfd"]},
                "moment_rate": source["moment_rate"]}
            results["kinds"][kind]["pga_10pct_50yr_g"] = {
                name: _level_at(levels, np.array(curve)) for name, curve in results["kinds"][kind]["curves"].items()}
            print(f"{kind}: {results['kinds'][kind]['seconds']:.0f} s; PGA at 10 % in 50 yr "
                  + ", ".join(f"{n} {v:.2f} g" for n, v in results["kinds"][kind]["pga_10pct_50yr_g"].items()))
    results.update(stamp())
    Path(args.results).write_text(json.dumps(results, indent=2) + "\n")
    _figure(results, args.figure)
    print(f"wrote {args.results} and {args.figure}")
    return 0


def _figure(results, path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, (left, right) = plt.subplots(1, 2, figsize=(12, 4.8))
    styles = {"characteristic": "-", "truncated_gr": "--", "single_bin": ":"}
    for kind, style in styles.items():
        for relation, colour in (("faultslip", "C0"), ("WC1994", "C1"), ("Leonard2010", "C2")):
            distribution = results["kinds"][kind]["mfd"][relation]
            rates = np.array(distribution["rates"]["value"])
            magnitudes = distribution["min_magnitude"] + distribution["bin_width"] * np.arange(len(rates))
            cumulative = np.cumsum(rates[::-1])[::-1]
            if len(rates) == 1:  # one bin: a point, not a step
                left.semilogy(magnitudes, cumulative, "o", color=colour, mfc="none", label=f"{kind}, {relation}")
                continue
            left.semilogy(magnitudes - distribution["bin_width"] / 2, cumulative, style, color=colour,
                          drawstyle="steps-post", label=f"{kind}, {relation}")
    left.set_xlabel("moment magnitude Mw")
    left.set_ylabel("annual rate of events ≥ Mw (1/yr)")
    left.set_title(f"{SEGMENT}: the same moment rate, three MFDs × three relations")
    left.legend(fontsize=6, ncol=1)
    left.grid(True, which="both", alpha=0.3)
    for index, name in enumerate(SITES):
        for kind, style in styles.items():
            data = results["kinds"][kind]
            right.loglog(data["levels_g"], np.maximum(data["curves"][name], 1e-8), style, color=f"C{index}",
                         label=f"{name}" if kind == "characteristic" else None)
    right.axhline(0.1, color="k", lw=0.6)
    right.text(0.006, 0.11, "10 % in 50 yr", fontsize=7)
    right.set_ylim(1e-5, 1.2)
    right.set_xlabel("PGA (g)")
    right.set_ylabel("probability of exceedance in 50 years")
    right.set_title("OpenQuake on faultslip's sources (solid: characteristic,\ndashed: truncated GR, dotted: single bin)",
                    fontsize=9)
    right.legend(fontsize=7)
    right.grid(True, which="both", alpha=0.3)
    figure.suptitle(f"Lab friction to hazard: California faults map, BooreEtAl2014, Vs30 760 m/s "
                    f"({results['machine']}, {results['date']})", fontsize=9)
    figure.tight_layout()
    figure.savefig(path, dpi=130)


if __name__ == "__main__":
    sys.exit(main())
